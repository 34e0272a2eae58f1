"""The numbers the seed reports publish, as printed (the lab reports armkit grew from, not shipped
with it; README's "Notes on the seed reports" says where their numbers and armkit's differ).

Report 000 (PROBOT Anno, Gazebo), report 003 (ZJU-I, CoppeliaSim), report 004 (GRB400
SCARA, real arm). Poses of report 000 are ``[x, y, z, roll, pitch, yaw]`` in metres and
radians, angles X-Y-Z *fixed* (``"xyz-fixed"``); report 003 uses X-Y'-Z' *Euler* angles in
degrees (``"xyz-euler"``); report 004 millimetres and degrees. The reports print 1.57
where they computed with pi/2; the targets below use pi/2 (README, "Notes on the seed reports").
"""

from __future__ import annotations

import math

HALF_PI = math.pi / 2

# ---------------------------------------------------------------- report 000, PROBOT Anno
PROBOT_HOME_POSE = (0.2289, 0.0, 0.454, HALF_PI, 0.0, 0.0)

#: (q, pose computed by the report, pose in Gazebo) for the FK experiment.
PROBOT_FK = (
    ((0.927, -0.687, -0.396, 0.0, 1.083, 0.927),
     (0.150047, 0.199940, 0.200756, 1.5708, 0.0, 0.0),
     (0.150035, 0.199922, 0.200783, 1.570801, 0.0, 0.0)),
    ((0.322, -0.855, -0.021, 0.0, 0.877, 0.322),
     (0.300121, 0.100124, 0.200812, 1.571110, -0.000950, 0.0),
     (0.300094, 0.100114, 0.200833, 1.571116, -0.000948, 0.0)),
    ((-0.322, -0.636, -0.011, 0.0, 0.647, -0.322),
     (0.300029, -0.100093, 0.272028, 1.5708, 0.0, 0.0),
     (0.299995, -0.100083, 0.272040, 1.57081, 0.0, 0.0)),
)

#: (target pose, the in-limit solutions the report lists, its Gazebo error of the pose).
PROBOT_IK = (
    ((0.2, 0.2, 0.2007, HALF_PI, -HALF_PI, 0.0),
     ((0.943488, -0.924743, -0.347274, -2.17673, 0.173647, 2.89722),
      (0.943488, -0.924743, -0.347274, 0.964865, 2.96795, -0.244375),
      (-2.1981, 0.924743, 3.48887, 0.964865, 0.173647, 2.89722),
      (-2.1981, 0.924743, 3.48887, -2.17673, 2.96795, -0.244375)),
     (-0.0054, -0.000011, 0.00003, 0.0, 0.0, 0.0)),
    ((0.15, 0.2, 0.2007, 0.0, 0.0, 0.0),
     ((1.03907, -1.00894, -0.0831629, -0.585271, -0.408274, 1.31351),
      (1.03907, -1.00894, -0.0831629, 2.55632, 3.54987, -1.82808),
      (-2.10252, 1.00894, 3.22476, 2.55632, -0.408274, 1.31351),
      (-2.10252, 1.00894, 3.22476, -0.585271, 3.54987, -1.82808)),
     (-0.000011, -0.000018, 0.000026, 0.000004, 0.0, 0.0)),
    ((0.3, 0.0, 0.122, HALF_PI, 0.0, 0.0),
     ((0.0, -1.11165, -0.0152543, 0.0, 1.1269, 0.0),
      (0.0, -1.11165, -0.0152543, 3.14159, 2.01469, 3.14159),
      (3.14159, 1.11165, 3.15685, -3.14159, 1.1269, 0.0),
      (3.14159, 1.11165, 3.15685, 0.0, 2.01469, 3.14159)),
     (-0.000019, 0.0, 0.000026, 0.000801, 0.0, 0.0)),
)

#: How many in-limit solutions the report's text says each target has ("在范围内共有N组解"). For
#: target 3 it says 3 but prints 4 (Check 0-3) and its video caption says 4 ("4个解").
PROBOT_IK_STATED_COUNTS = (4, 4, 3)

#: Straight line by velocity control: start, displacement, the end the report measured.
PROBOT_LINE_START = (0.229, 0.0, 0.454)
PROBOT_LINE_DISPLACEMENT = (0.15, 0.0, -0.15)
PROBOT_LINE_END = (0.379, 0.0, 0.304)
PROBOT_LINE_END_GAZEBO = (0.378651, -0.000001, 0.303826)

#: Trajectory: Cartesian waypoints, their IK solutions in the report, 10 s per segment.
PROBOT_WAYPOINT_POSES = (
    (0.2289, 0.0, 0.454, HALF_PI, 0.0, 0.0),
    (0.3, 0.25, 0.322, HALF_PI, -HALF_PI, 0.0),
    (0.3, 0.1, 0.172, HALF_PI, -HALF_PI, 0.0),
    (0.3, -0.1, 0.122, HALF_PI, -HALF_PI, 0.0),
)
PROBOT_WAYPOINT_JOINTS = (
    (0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
    (0.795586, -0.772686, 0.205056, 1.08734, 2.51046, -0.842853),
    (0.387677, -1.07517, -0.199884, 0.404374, 2.86768, -0.114923),
    (-0.387371, -1.29256, -0.0658126, -0.394643, 2.94426, 0.0811483),
)
PROBOT_SEGMENT_SECONDS = 10.0
#: Report: sum of absolute pose errors in Gazebo when passing waypoints 2 and 3.
PROBOT_WAYPOINT_RESIDUALS = (0.00094727, 0.000834903)
#: Report: final pose error in Gazebo.
PROBOT_TRAJECTORY_FINAL_ERROR = (-0.000004, -0.000008, 0.000141, -0.005, 0.0001, -0.005)

#: Fixed-point rotation: twist [v; w] at the home pose, at least 40 deg (the report: > 180 deg).
PROBOT_ROTATION_TWIST = (0.0, 0.0, 0.0, -0.2, 0.0, 0.0)
PROBOT_ROTATION_REPORTED = "more than 180 deg, millimetre-level position drift"

# ---------------------------------------------------------------- report 003, ZJU-I
#: q = [pi/12] * 6: pose computed by the report and in CoppeliaSim, xyz-euler, m and deg.
ZJU_FK = (
    (tuple([math.pi / 12] * 6),
     (0.226, 0.107, 0.552, -148.00, 36.35, -107.00),
     (0.226, 0.107, 0.552, -148.05, 36.31, -107.00)),
)

# ---------------------------------------------------------------- report 004, GRB400 SCARA
#: (q in deg/mm: t1, t2, d3, t4), published coordinate name, published value [mm].
SCARA_FK = (
    ((45.0, 45.0, 0.0, 0.0), "x", 141.4214),
    ((45.0, 45.0, 0.0, 0.0), "y", 341.4214),
    ((90.0, 40.0, 0.0, 0.0), "y", 353.2089),
    ((90.0, 60.0, 0.0, 0.0), "y", 300.0000),
    ((30.0, 30.0, 0.0, 0.0), "y", 273.2051),
    ((60.0, 20.0, 0.0, 0.0), "y", 370.1666),
    ((45.0, 45.0, 10.0, 0.0), "z", 10.0),
)

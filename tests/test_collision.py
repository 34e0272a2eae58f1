"""armkit.collision: geometric truths of Scene's queries, clearance against hand-computed distances,
contact names, self-collision pairs and the path check's resolution bound."""

from __future__ import annotations

import importlib.util
import itertools
import sys
from pathlib import Path

import numpy as np
import pytest

import armkit
from armkit.chain import DHRow
from armkit.errors import InputError
from armkit.export.physical import capsule_bodies
from armkit.spatial.transforms import transform_from

pytest.importorskip("mujoco")

UR5 = armkit.load("ur5")
#: A UR5 configuration clear of the floor and of itself (elbow up, the tool pointing down above the floor).
Q_FREE = np.array([0.0, -1.2, 1.0, 0.0, 1.5, 0.0])
#: Relative precision of MuJoCo's mesh vertices (single precision) [1].
FLOAT32 = 6e-8


def one_link(radius: float = 0.05) -> tuple[armkit.Robot, float]:
    """A single revolute joint about the base z axis with a 1 m link along its x axis."""
    return armkit.Robot.from_dh([DHRow(0.0, 1.0, 0.0, 0.0)], "standard", name="one link"), radius


@pytest.fixture(scope="module")
def ur5_scene() -> armkit.Scene:
    return armkit.Scene(UR5, floor=0.0)


def test_clearance_of_a_capsule_above_the_floor_and_beside_a_sphere_is_the_hand_computed_distance():
    robot, r = one_link()
    scene = armkit.Scene(robot, [armkit.Sphere(0.1, [0.5, 0.0, 0.3])], floor=-0.5, link_radius=r)
    # q = 0: the link's axis runs from (0,0,0) to (1,0,0); the sphere's centre is 0.3 m above its middle
    assert scene.clearance([0.0]) == pytest.approx(0.3 - 0.1 - r, abs=1e-9)
    # q = pi/2: the link lies along y, so the joint's housing sphere (radius 1.5 r, at the origin) is the
    # nearest part: sqrt(0.5^2 + 0.3^2) from the sphere's centre, 0.5 m above the floor
    expected = min(np.hypot(0.5, 0.3) - 0.1 - 1.5 * r, 0.5 - 1.5 * r)
    assert scene.clearance([np.pi / 2]) == pytest.approx(expected, abs=1e-9)
    assert scene.collides([0.0]) is False and scene.collides([np.pi / 2]) is False


def test_clearance_is_negative_by_the_penetration_depth_and_then_collides():
    robot, r = one_link()
    scene = armkit.Scene(robot, [armkit.Sphere(0.1, [0.5, 0.0, 0.12])], floor=None, link_radius=r)
    assert scene.clearance([0.0]) == pytest.approx(0.12 - 0.1 - r, abs=1e-9)  # -0.03 m: overlapping
    assert scene.collides([0.0]) is True
    assert scene.contacts([0.0]) == [("link1", "sphere1")]


def test_clearance_against_boxes_and_cylinders_is_the_distance_to_their_faces():
    robot, r = one_link()
    box = armkit.Box([0.2, 0.2, 0.2], transform_from(np.eye(3), [0.5, 0.0, 0.5]), name="crate")
    scene = armkit.Scene(robot, [box], floor=None, link_radius=r)
    # a box is a convex mesh whose corners (here +-0.1 m) MuJoCo keeps in single precision
    assert scene.clearance([0.0]) == pytest.approx(0.5 - 0.1 - r, abs=0.1 * FLOAT32)  # the bottom face, 0.4
    upright = armkit.Cylinder(0.1, 0.4, transform_from(np.eye(3), [0.0, 0.6, 0.0]))
    scene = armkit.Scene(robot, [upright], floor=None, link_radius=r)
    assert scene.clearance([np.pi / 2]) == pytest.approx(-(0.1 + r), abs=1e-6)  # the link runs through it
    assert scene.clearance([np.pi]) == pytest.approx(0.6 - 0.1 - 1.5 * r, abs=1e-6)  # housing to its side


def _capsule_distance(robot: armkit.Robot, q: np.ndarray, centre: np.ndarray, radius: float) -> float:
    """Distance from a sphere to the arm's capsules and housings, in NumPy (independent of MuJoCo)."""
    link_radius, base, bodies = capsule_bodies(robot)
    frames, _ = armkit.kinematics.joint_frames(robot, q)
    best = np.inf
    for T, shape in zip(frames, bodies, strict=True):
        best = min(best, np.linalg.norm(T[:3, 3] - centre) - 1.5 * link_radius)
        for start, end in shape.segments:
            a, b = T[:3, :3] @ start + T[:3, 3], T[:3, :3] @ end + T[:3, 3]
            t = np.clip(np.dot(centre - a, b - a) / np.dot(b - a, b - a), 0.0, 1.0)
            best = min(best, np.linalg.norm(a + t * (b - a) - centre) - link_radius)
    return best - radius


def test_clearance_to_a_sphere_equals_a_numpy_capsule_distance_over_random_configurations():
    rng = np.random.default_rng(3)
    arm = ("base", *(f"link{i + 1}" for i in range(UR5.n)))
    no_self = list(itertools.combinations(arm, 2))
    for _ in range(5):
        centre = rng.uniform([-0.6, -0.6, 0.0], [0.6, 0.6, 0.8])
        scene = armkit.Scene(UR5, [armkit.Sphere(0.08, centre)], floor=None, disabled_pairs=no_self,
                             samples=0)
        q = UR5.random_q(20, rng=rng)
        expected = [_capsule_distance(UR5, qi, centre, 0.08) for qi in q]
        np.testing.assert_allclose(scene.clearance(q), expected, atol=1e-9)
        np.testing.assert_array_equal(scene.collides(q), np.array(expected) < 0)


def test_a_joint_origin_under_the_floor_is_always_reported(ur5_scene):
    q = UR5.random_q(4000, rng=7)
    frames, _ = armkit.kinematics.joint_frames(UR5, q)
    under = (frames[:, 1:, 2, 3] < -1e-9).any(axis=1)  # joint 1's origin stands on the floor itself
    assert under.sum() > 100
    assert ur5_scene.collides(q[under]).all()


def test_a_joint_origin_inside_an_obstacle_is_always_reported():
    rng = np.random.default_rng(11)
    q = UR5.random_q(30, rng=rng)
    frames, _ = armkit.kinematics.joint_frames(UR5, q)
    for qi, T in zip(q, frames, strict=True):
        joint = rng.integers(1, UR5.n)
        box = armkit.Box([0.02, 0.03, 0.04], transform_from(np.eye(3), T[joint, :3, 3] + [0.005, 0, 0]))
        scene = armkit.Scene(UR5, [box], floor=None, samples=0)
        assert scene.collides(qi)
        assert (f"link{joint + 1}", "box1") in scene.contacts(qi)


def test_a_configuration_far_from_everything_is_never_reported():
    rng = np.random.default_rng(5)
    reach = np.linalg.norm(UR5.chain.T_between[:, :3, 3], axis=-1).sum() + 0.2
    for _ in range(10):
        direction = rng.normal(size=3)
        centre = direction / np.linalg.norm(direction) * rng.uniform(reach + 0.5, reach + 3)
        scene = armkit.Scene(UR5, [armkit.Sphere(0.5, centre), armkit.Box([1, 1, 1], transform_from(
            np.eye(3), -centre))], floor=-reach, samples=0)
        assert not scene.collides(Q_FREE)
        assert scene.clearance(Q_FREE) > 0


def test_a_negative_clearance_is_exactly_a_collision_for_every_kind_of_shape():
    boxes = armkit.Box([0.3, 0.3, 0.4], transform_from(np.eye(3), [0.5, 0.3, 0.2]))
    post = armkit.Cylinder(0.06, 1.2, transform_from(np.eye(3), [0.2, -0.55, 0.6]))
    scene = armkit.Scene(UR5, [boxes, post, armkit.Sphere(0.12, [-0.4, 0.4, 0.5])], floor=0.0)
    q = UR5.random_q(1500, rng=5)
    hit = scene.collides(q)
    assert 0.1 < hit.mean() < 0.9
    np.testing.assert_array_equal(scene.clearance(q) < 0, hit)


def test_batches_keep_their_shape_and_agree_with_single_queries(ur5_scene):
    q = UR5.random_q((3, 50), rng=2)
    batch = ur5_scene.collides(q)
    assert batch.shape == (3, 50) and batch.dtype == bool
    assert [ur5_scene.collides(qi) for qi in q[1, :10]] == batch[1, :10].tolist()
    assert ur5_scene.clearance(q).shape == (3, 50)
    one = armkit.Scene(UR5, floor=0.0, threads=1)
    np.testing.assert_array_equal(one.collides(q), batch)  # the thread count does not change answers
    assert ur5_scene.collides(np.empty((0, 6))).shape == (0,)


def test_contacts_name_the_links_and_the_floor(ur5_scene):
    assert ur5_scene.contacts(Q_FREE) == []
    assert ur5_scene.contacts(UR5.home) == [("link5", "floor"), ("link6", "floor")]


def test_self_collision_pairs_found_by_sampling_include_adjacent_always_and_never(ur5_scene):
    pairs = ur5_scene.disabled_pairs
    assert pairs[("base", "link1")] == "adjacent" and pairs[("link5", "link6")] == "adjacent"
    assert pairs[("link1", "floor")] == "always"  # the first link stands on the floor
    assert set(pairs.values()) <= {"adjacent", "always", "never", "home"}
    folded = np.array([0.0, -1.2, 3.1, 0.0, 0.0, 0.0])  # the forearm folded back onto the upper arm
    assert ur5_scene.contacts(folded)  # self-collision is checked where pairs are not disabled
    enabled = armkit.Scene(UR5, floor=0.0, enabled_pairs=[("link1", "floor")])
    assert ("link1", "floor") not in enabled.disabled_pairs and enabled.collides(Q_FREE)


def test_an_enabled_adjacent_pair_collides_exactly_where_its_clearance_is_negative():
    """MuJoCo skips parent and child bodies by default: the scene turns that off and excludes the
    adjacent pairs by name, so a user who enables one gets it checked by collides as by clearance."""
    scene = armkit.Scene(UR5, floor=None, samples=0, enabled_pairs=[("link2", "link3")], threads=1)
    q = UR5.random_q(300, rng=1)
    np.testing.assert_array_equal(scene.collides(q), scene.clearance(q) < 0)
    assert ("link2", "link3") in scene.contacts(q[0])


def test_user_disabled_pairs_are_not_checked():
    robot, r = one_link()
    scene = armkit.Scene(robot, [armkit.Sphere(0.1, [0.5, 0.0, 0.12])], floor=None, link_radius=r,
                         disabled_pairs=[("sphere1", "link1")])
    assert scene.disabled_pairs[("link1", "sphere1")] == "user"
    assert not scene.collides([0.0]) and scene.clearance([0.0]) == np.inf


def test_path_collides_checks_the_segment_at_the_resolution_bound():
    robot, r = one_link()
    # a thin post the link sweeps through between q = 0 and q = 1 rad, far from both ends
    post = armkit.Cylinder(0.004, 1.0, transform_from(np.eye(3), [np.cos(0.5), np.sin(0.5), 0.0]))
    scene = armkit.Scene(robot, [post], floor=None, link_radius=0.001)
    assert not scene.collides([[0.0], [1.0]]).any()
    assert scene.path_collides([0.0], [1.0], resolution=0.005)
    # the bound: the link's far end (1 m plus its radius) is the farthest point from the joint
    assert scene.displacement_bound([0.0], [1.0]) == pytest.approx(1.0 + 0.001, abs=1e-12)
    assert not scene.path_collides([0.0], [0.3])


def test_path_collides_bound_covers_the_true_motion_of_every_geometry_point(ur5_scene):
    rng = np.random.default_rng(4)
    _, _, bodies = capsule_bodies(UR5)
    for _ in range(5):
        q_a, q_b = UR5.random_q(2, rng=rng)
        t = np.linspace(0, 1, 2001)[:, None]
        frames, _ = armkit.kinematics.joint_frames(UR5, q_a + t * (q_b - q_a))
        ends = np.concatenate([frames[:, i, :3, :3] @ shape.segments.reshape(-1, 3).T + frames[:, i, :3, 3:]
                               for i, shape in enumerate(bodies)], axis=-1)
        travelled = np.linalg.norm(np.diff(ends, axis=0), axis=1).sum(axis=0).max()
        assert travelled <= ur5_scene.displacement_bound(q_a, q_b)


def test_a_urdf_robots_collision_elements_become_its_geometry(tmp_path):
    urdf = tmp_path / "arm.urdf"
    urdf.write_text("""<robot name="arm">
  <link name="base"/>
  <link name="upper"><collision><origin xyz="0.25 0 0"/><geometry><box size="0.5 0.1 0.1"/></geometry>
    </collision></link>
  <link name="fore"><collision><geometry><sphere radius="0.05"/></geometry></collision></link>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" velocity="1" effort="1"/></joint>
  <joint name="elbow" type="revolute"><parent link="upper"/><child link="fore"/><origin xyz="0.5 0 0"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" velocity="1" effort="1"/></joint>
</robot>""")
    robot = armkit.load(urdf)
    scene = armkit.Scene(robot, [armkit.Sphere(0.1, [0.25, 0.0, 0.3])], floor=-0.2, samples=0)
    assert scene.parts[:3] == ("base", "upper", "fore")
    assert scene.clearance([0.0, 0.0]) == pytest.approx(min(0.3 - 0.05 - 0.1, 0.2 - 0.05), abs=1e-9)
    moved = armkit.Scene(robot, [armkit.Sphere(0.1, [0.25, 0.0, 0.12])], floor=None, samples=0)
    assert moved.contacts([0.0, 0.0]) == [("upper", "sphere1")]


def test_urdf_meshes_resolve_relative_to_the_file_and_through_package_paths(tmp_path):
    from armkit.collision.model import resolve_mesh

    (tmp_path / "pkg" / "meshes").mkdir(parents=True)
    mesh = tmp_path / "pkg" / "meshes" / "link.stl"
    mesh.write_bytes(b"solid x\nendsolid x\n")
    assert resolve_mesh("pkg/meshes/link.stl", tmp_path, ()) == mesh.resolve()
    assert resolve_mesh("package://pkg/meshes/link.stl", None, [tmp_path]) == mesh.resolve()
    assert resolve_mesh("package://pkg/meshes/link.stl", None, [tmp_path / "pkg"]) == mesh.resolve()
    with pytest.raises(InputError, match="package-path"):
        resolve_mesh("package://pkg/meshes/link.stl", None, [])
    (tmp_path / "visual.dae").write_text("")
    with pytest.raises(InputError, match="STL, OBJ"):
        resolve_mesh("visual.dae", tmp_path, ())


def test_a_mesh_obstacle_collides_as_its_convex_hull(tmp_path):
    # an L-shaped (non-convex) slab, legs along x = 0.9..1 and y = 0.9..1 of the unit square, 0.1 m thick
    outline = np.array([[0, 0.9], [0.9, 0.9], [0.9, 0], [1, 0], [1, 1], [0, 1]])
    vertices = [(x, y, z) for z in (-0.05, 0.05) for x, y in outline]
    faces = [(5, 6, 1), (5, 1, 2), (5, 2, 3), (5, 3, 4), (11, 7, 12), (11, 8, 7), (11, 9, 8), (11, 10, 9)]
    lines = [f"v {x} {y} {z}" for x, y, z in vertices] + [f"f {a} {b} {c}" for a, b, c in faces]
    (tmp_path / "ell.obj").write_text("\n".join(lines) + "\n")
    robot, r = one_link()
    scene = armkit.Scene(robot, [armkit.Mesh(tmp_path / "ell.obj")], floor=None, link_radius=r)
    # along the diagonal the link's tip (0.707, 0.707) stays 0.19 - r from both legs, but lies inside the
    # hull (x + y >= 1): MuJoCo collides the hull
    assert scene.collides([np.pi / 4])
    assert not scene.collides([-np.pi / 4])


@pytest.mark.parametrize("make, message", [
    (lambda: armkit.Box([1, 0, 1]), "Box size"),
    (lambda: armkit.Sphere(-1, [0, 0, 0]), "Sphere radius"),
    (lambda: armkit.Sphere(0.1, [0, 0]), "Sphere center"),
    (lambda: armkit.Cylinder(0.1, 0.0), "Cylinder length"),
    (lambda: armkit.Box([1, 1, 1], np.ones((4, 4))), "Box pose"),
    (lambda: armkit.Scene(UR5, ["table"]), "obstacles"),
    (lambda: armkit.Scene(UR5, floor="low"), "floor"),
    (lambda: armkit.Scene(UR5, disabled_pairs=[("link1", "table")], samples=0), "'table' is not a part"),
    (lambda: armkit.Scene(UR5, [armkit.Sphere(0.1, name="link2")], samples=0), "two parts are named"),
    (lambda: armkit.Scene(UR5, link_radius=[0.1, 0.2], samples=0), "link_radius"),
    (lambda: armkit.Scene(UR5, [armkit.Mesh("/no/such/file.stl")], samples=0), "file not found"),
])
def test_bad_scene_input_raises_one_input_error_naming_it(make, message):
    with pytest.raises(InputError, match=message):
        make()


def test_bad_queries_raise_input_errors(ur5_scene):
    with pytest.raises(InputError, match="6 joint values"):
        ur5_scene.collides([0.0, 1.0])
    with pytest.raises(InputError, match="one configuration"):
        ur5_scene.contacts(np.zeros((2, 6)))
    with pytest.raises(InputError, match="resolution"):
        ur5_scene.path_collides(Q_FREE, Q_FREE, resolution=0)


def test_collisions_agree_with_pinocchio_and_coal_on_the_same_shapes():
    """The benchmark's scene checked by coal (through pinocchio) with the same shapes and pairs."""
    pytest.importorskip("coal")
    path = Path(__file__).parent.parent / "benchmarks" / "bench_collision.py"
    spec = importlib.util.spec_from_file_location("bench_collision", path)
    bench = importlib.util.module_from_spec(spec)
    sys.path.insert(0, str(path.parent))
    try:
        spec.loader.exec_module(bench)
    finally:
        sys.path.remove(str(path.parent))
    scene = bench.ur5_scene()
    pin, model, geometry = bench.pinocchio_peer(scene)
    data, geometry_data = model.createData(), geometry.createData()
    q = UR5.random_q(3000, rng=8)
    theirs = [pin.computeCollisions(model, data, geometry, geometry_data, qi, True) for qi in q]
    ours = scene.collides(q)
    assert 0.2 < ours.mean() < 0.9  # both answers occur
    np.testing.assert_array_equal(ours, theirs)


def test_the_lab_floor_check_reports_a_motion_through_the_floor(tmp_path):
    from armkit.lab.context import LabContext
    from armkit.lab.floor import floor_check

    ctx = LabContext(robot=UR5, folder=tmp_path, quick=True, seeds=False)
    ctx.stage = "down"
    ctx.record(Q_FREE + np.linspace(0, 1.2, 50)[:, None] * [0, 1, 0, 0, 0, 0])  # the upper arm swings down
    ctx.stage = "around"
    ctx.record(Q_FREE + np.linspace(0, 3, 50)[:, None] * [1, 0, 0, 0, 0, 0])  # turns about the base
    section = floor_check(ctx)
    assert section.status == "failed" and section.headline.startswith("1 of 2 motions")
    down, around = section.tables[0].rows
    assert down[0] == "down" and int(down[2]) > 0 and "floor" in down[4] and float(down[3]) < 0
    assert around[0] == "around" and around[2] == "0" and around[4] == "-" and float(around[3]) > 0


def test_a_radius_per_joint_in_a_robot_file_sizes_that_links_capsules(tmp_path):
    path = tmp_path / "arm.toml"
    path.write_text('convention = "standard"\nlength_unit = "mm"\nangle_unit = "deg"\n'
                    '[[joints]]\nalpha = 0\na = 1000\nd = 0\ntheta = 0\nradius = 80\n')
    robot = armkit.load(path)
    assert robot.chain.joints[0].radius == pytest.approx(0.08)
    assert armkit.robot_to_toml(robot).count("radius = 0.08") == 1  # written back (in metres)
    scene = armkit.Scene(robot, [armkit.Sphere(0.1, [0.5, 0.0, 0.3])], floor=None)
    assert scene.clearance([0.0]) == pytest.approx(0.3 - 0.1 - 0.08, abs=1e-9)
    path.write_text(path.read_text().replace("radius = 80", "radius = -1"))
    with pytest.raises(armkit.RobotDefinitionError, match="radius"):
        armkit.load(path)


def test_without_mujoco_a_scene_is_one_error_naming_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "mujoco", None)  # import mujoco then raises ImportError
    with pytest.raises(armkit.ArmkitError, match=r"pip install 'armkit\[collision\]'"):
        armkit.Scene(UR5, samples=0)


def test_example_robot_datas_ur5_collision_meshes_load_through_package_paths():
    from importlib.metadata import PackageNotFoundError, distribution

    try:
        share = Path(distribution("example-robot-data").locate_file("cmeel.prefix/share"))
    except PackageNotFoundError:
        pytest.skip("example-robot-data is not installed")
    robots = share / "example-robot-data" / "robots"
    robot = armkit.load(robots / "ur_description/urdf/ur5_robot.urdf", tip="tool0")
    assert "mesh" in {c.kind for c in robot.urdf.collisions}
    scene = armkit.Scene(robot, floor=0.0, package_paths=[robots.parent], samples=500)
    assert scene.parts[1:7] == ("shoulder_link", "upper_arm_link", "forearm_link", "wrist_1_link",
                                "wrist_2_link", "wrist_3_link")
    q = robot.random_q(300, rng=2)
    frames, _ = armkit.kinematics.joint_frames(robot, q)
    under = frames[:, 2:, 2, 3].min(axis=1) < -0.1  # the elbow or a wrist joint 10 cm under the floor
    assert under.any() and scene.collides(q[under]).all()
    assert all(any("floor" in pair for pair in scene.contacts(qi)) for qi in q[under][:5])


def test_a_link_through_a_thin_wall_with_both_ends_outside_collides():
    """MuJoCo's capsule-box test misses a capsule crossing a thin box with both ends outside (no
    contact, distance +0.146 m here); boxes go to MuJoCo as convex meshes, which it does not miss.
    The tester's UR5 solution: the forearm from (-0.29, 0.05, 0.40) to (-0.67, 0.13, 0.38) through
    a 4 cm wall at x = -0.45 m."""
    wall = armkit.Box([0.04, 1.0, 0.8], [[1, 0, 0, -0.45], [0, 1, 0, 0], [0, 0, 1, 0.4], [0, 0, 0, 1]],
                      name="wall")
    scene = armkit.Scene(UR5, [wall], floor=None, samples=0)
    q = np.array([-0.1829, -0.8111, 0.8502, 1.5317, 1.5708, -1.7537])
    frames = UR5.link_frames(q)
    assert frames[2][0, 3] > -0.45 > frames[3][0, 3]  # the forearm's two ends on either side of the wall
    assert scene.collides(q) and ("link3", "wall") in scene.contacts(q) and scene.clearance(q) < 0
    (shape,) = [s for s in scene.world_shapes() if s.part == "wall"]
    assert shape.kind == "box"
    np.testing.assert_allclose(sorted(shape.size), [0.02, 0.4, 0.5], rtol=1e-6)  # float32 vertices


def test_arm_pairs_in_contact_at_home_are_disabled_as_moveit_s_default_rule():
    scara = armkit.load("grb400-scara")
    plain = armkit.Scene(scara, floor=None, samples=0)
    touching = [pair for pair in plain.contacts(scara.home) if "floor" not in pair]
    assert touching  # the quill's capsule passes through the forearm's
    scene = armkit.Scene(scara, floor=None)
    assert all(scene.disabled_pairs.get(pair) in ("home", "adjacent", "always") for pair in touching)
    assert not scene.collides(scara.home)
    with pytest.raises(InputError, match="samples: expected a whole number from 0 to 1000000"):
        armkit.Scene(scara, floor=None, samples=10**9)

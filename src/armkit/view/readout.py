"""The viewer's text: pose read-out, IK solution list, waypoint list, the lines a user copies.

Plain functions from numbers to HTML or text, so they can be tested without a browser. The HTML
carries ``data-armkit`` attributes that the browser tests read.
"""

from __future__ import annotations

import html
import shlex

import numpy as np
from numpy.typing import NDArray

from armkit.ik.solve import IKSolutions
from armkit.robot import Robot
from armkit.spatial.rotations import euler_from_matrix, parse_convention, quaternion_wxyz_from_matrix

__all__ = ["BOX_CHARS", "LABEL_CHARS", "QUATERNION", "angle_conventions", "box_decimals", "box_range",
           "copy_pose_text", "copy_q_text", "joint_name_html", "joint_text", "pose_html", "solutions_html",
           "waypoints_html"]

#: The read-out's name for the unit quaternion ``w x y z``.
QUATERNION = "wxyz"
#: Characters of a slider label that fit the panel's label column on one line or two.
LABEL_CHARS = 16
#: Characters a slider's number box shows in full.
BOX_CHARS = 6


def box_decimals(low: float, high: float, most: int) -> int:
    """Decimals (at most ``most``) that keep every value of ``[low, high]`` within :data:`BOX_CHARS`.

    >>> box_decimals(-360.0, 360.0, 1), box_decimals(-6.2832, 6.2832, 3), box_decimals(-0.1, 0.25, 4)
    (1, 3, 3)
    """
    widest = max(len(f"{value:.0f}") for value in (low, high))
    return int(np.clip(BOX_CHARS - widest - 1, 0, most))


def box_range(low: float, high: float, decimals: int) -> tuple[float, float]:
    """A slider's ends rounded inwards to ``decimals`` (``-360.0``, not ``-360.000842``); an end
    within a millionth of a step of a step is that step (``169.99999999999997`` is ``170.0``). A range
    narrower than a step stays as it is.

    >>> box_range(-360.000842, 360.000842, 1), box_range(-2.9671, 2.9671, 3)
    ((-360.0, 360.0), (-2.967, 2.967))
    >>> box_range(0.0, 169.99999999999997, 1), box_range(0.00012, 0.00018, 4)
    ((0.0, 170.0), (0.00012, 0.00018))
    """
    scale = 10.0**decimals
    inner = np.ceil(np.round(low * scale, 6)) / scale, np.floor(np.round(high * scale, 6)) / scale
    return (float(inner[0]), float(inner[1])) if inner[0] <= inner[1] else (float(low), float(high))


def joint_name_html(j: int, label: str) -> str:
    """A joint's full name and unit on a row of its own above its slider (``q{j+1}``), wrapping."""
    return (f"<div style='font-size:0.8em;overflow-wrap:anywhere;margin-top:4px' data-armkit='joint-name'>"
            f"q{j + 1}: {html.escape(label)}</div>")


def angle_conventions() -> tuple[str, ...]:
    """The read-out's choices: the three of the seed reports, the other Euler orders, ``wxyz``."""
    common = ("xyz-fixed", "xyz-euler", "zyz-euler", "zyx-euler", "zxz-euler")
    return (*common, QUATERNION)


def joint_text(robot: Robot, q: NDArray[np.float64], degrees: bool, digits: int = 2) -> list[str]:
    """Each joint value as text with its unit: degrees or radians for revolute joints, m for prismatic."""
    out = []
    for value, prismatic in zip(q, robot.chain.prismatic, strict=True):
        if prismatic:
            out.append(f"{value:.4f} m")
        elif degrees:
            out.append(f"{np.degrees(value):.{digits}f}°")
        else:
            out.append(f"{value:.{digits + 2}f}")
    return out


def _matrix_text(T: NDArray[np.float64]) -> str:
    return "\n".join(" ".join(f"{v:10.6f}" for v in row) for row in np.round(T, 6) + 0.0)


def _orientation(T: NDArray[np.float64], convention: str, degrees: bool) -> tuple[str, NDArray[np.float64]]:
    if convention == QUATERNION:
        return "quaternion w x y z", quaternion_wxyz_from_matrix(T[:3, :3])
    parsed = parse_convention(convention)
    angles = euler_from_matrix(T[:3, :3], parsed, degrees=degrees)
    return f"{parsed.name} angles [{'deg' if degrees else 'rad'}]", angles


def pose_html(robot: Robot, q: NDArray[np.float64], T: NDArray[np.float64], convention: str,
              degrees: bool) -> str:
    """The live read-out: tool pose matrix, position, orientation in ``convention``, how singular."""
    label, values = _orientation(T, convention, degrees)
    sigma = robot.singular_values(q)
    digits = 3 if degrees and convention != QUATERNION else 6
    return (
        "<div style='font-size:0.8em'>"
        f"<b>T_base_tool</b> [m]<pre data-armkit='pose-matrix' style='margin:2px 0'>"
        f"{_matrix_text(T)}</pre>"
        f"<div>position [m]: <span data-armkit='position'>"
        f"{' '.join(f'{v:.6f}' for v in np.round(T[:3, 3], 6) + 0.0)}</span></div>"
        f"<div>{html.escape(label)}: <span data-armkit='orientation'>"
        f"{' '.join(f'{v:.{digits}f}' for v in np.round(values, digits) + 0.0)}</span></div>"
        f"<div>manipulability: <span data-armkit='manipulability'>{robot.manipulability(q):.4g}</span>, "
        f"smallest singular value: <span data-armkit='sigma-min'>{sigma[-1]:.4g}</span></div></div>")


def solutions_html(robot: Robot, found: IKSolutions, current: int | None, degrees: bool,
                   method: str) -> str:
    """The IK list: one row per solution, in or out of the limits, singular family flagged."""
    inside = int(found.within_limits.sum())
    head = (f"<div data-armkit='ik-summary'>{method}: {len(found.q)} solution{'s' * (len(found.q) != 1)}, "
            f"<span style='color:#2e9e44'>{inside} in limits</span>, "
            f"<span style='color:#d33'>{len(found.q) - inside} out of limits</span></div>")
    rows = []
    for k, (q, ok, family) in enumerate(zip(found.q, found.within_limits, found.family, strict=True)):
        colour = "#2e9e44" if ok else "#d33"
        flags = ("in" if ok else "OUT") + (", singular family" if family else "")
        mark = " ◀ arm" if k == current else ""
        rows.append(f"<tr data-armkit='solution' data-within='{str(bool(ok)).lower()}' "
                    f"data-family='{str(bool(family)).lower()}' style='color:{colour}'>"
                    f"<td>{k + 1}</td><td>{flags}{mark}</td>"
                    f"<td>{' '.join(joint_text(robot, q, degrees, 1))}</td></tr>")
    note = ("<div>singular family: only a combination of joints is fixed (e.g. q4 + q6 at a "
            "wrist singularity); the row shows the member nearest the arm.</div>"
            if found.family.any() else "")
    return (f"<div style='font-size:0.8em'>{head}<table>{''.join(rows)}</table>{note}</div>")


def waypoints_html(robot: Robot, waypoints: list[NDArray[np.float64]], degrees: bool) -> str:
    """The taught waypoints, numbered as the markers in the scene."""
    if not waypoints:
        return "<div style='font-size:0.8em' data-armkit='waypoints'>no waypoints taught yet</div>"
    rows = "".join(f"<tr data-armkit='waypoint'><td>W{k + 1}</td>"
                   f"<td>{' '.join(joint_text(robot, q, degrees, 1))}</td></tr>"
                   for k, q in enumerate(waypoints))
    return f"<div style='font-size:0.8em' data-armkit='waypoints'><table>{rows}</table></div>"


def copy_q_text(robot_source: str, q: NDArray[np.float64]) -> str:
    """``armkit fk`` with the joint values ``q`` (SI units), ready to paste.

    ``robot_source`` is the built-in name or file the robot was loaded from.

    >>> copy_q_text("probot-anno", np.array([0.5, -0.25, 0, 0, 1, 0]))
    'armkit fk probot-anno 0.500000 -0.250000 0.000000 0.000000 1.000000 0.000000'
    """
    return f"armkit fk {shlex.quote(robot_source)} " + " ".join(f"{v:.6f}" for v in q + 0.0)


def copy_pose_text(robot_source: str, T: NDArray[np.float64], convention: str, closed_form: bool) -> str:
    """``armkit ik`` with the tool pose ``T`` (m, rad; the 16 matrix entries for ``wxyz``),
    asking for every solution when the arm has a closed form."""
    command = f"armkit ik {shlex.quote(robot_source)}" + (" --all --outside" if closed_form else "")
    if convention == QUATERNION:
        return f"{command} --matrix " + " ".join(f"{v:.6f}" for v in T.ravel() + 0.0)
    angles = euler_from_matrix(T[:3, :3], parse_convention(convention))
    numbers = " ".join(f"{v:.6f}" for v in np.concatenate([T[:3, 3], angles]) + 0.0)
    return f"{command} --pose {numbers} --euler {convention}"

"""``armkit ik``: every inverse-kinematics solution of a pose, or the one nearest a seed."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import numpy as np
import typer
from rich import box
from rich.console import Console
from rich.markup import escape
from rich.measure import Measurement
from rich.table import Table

from armkit.cli.app import (
    ALLOW_NEGATIVE,
    JOINT_UNITS,
    QUATERNION_NAMES,
    BaseOpt,
    LockOpt,
    RobotArg,
    TipOpt,
    app,
    console,
    fmt_number,
    joint_option,
    load_robot,
    option_values,
    print_json,
    to_si,
)
from armkit.cli.scene_option import PackagePathOpt, SceneOpt, load_scene_option
from armkit.errors import InputError, JointLimitError, NoClosedFormError, pair_text
from armkit.ik.messages import outside_limits
from armkit.ik.pipeline import count_turn_copies
from armkit.ik.position import ik_position_solutions, position_case
from armkit.ik.solve import ik_solutions
from armkit.ik.structure import analyze_structure
from armkit.robot import Robot
from armkit.spatial.rotations import matrix_from_euler, parse_convention, rotation_angle_between
from armkit.spatial.transforms import check_transform, transform_from

#: ``--matrix`` takes the 16 entries of a 4x4 transform.
Matrix16 = tuple[(float,) * 16]


#: Task mask of ``--position``: the tool position only, any orientation.
POSITION_ONLY = (1.0, 1.0, 1.0, 0.0, 0.0, 0.0)


def target_from_options(pose: tuple[float, ...] | None, matrix: tuple[float, ...] | None,
                        position: tuple[float, ...] | None, convention: str, degrees: bool) -> np.ndarray:
    """The 4x4 target of ``--pose`` / ``--matrix`` / ``--position`` (exactly one given; a position
    alone has the identity rotation), checked, angles in degrees if ``degrees``."""
    if sum(x is not None for x in (pose, matrix, position)) != 1:
        raise InputError("give the target as one of --pose X Y Z A B C, --matrix with 16 numbers "
                         "(row by row) or --position X Y Z (position only)")
    if matrix is not None:
        return check_transform(np.reshape(matrix, (4, 4)), "--matrix")
    if position is not None:
        return transform_from(np.eye(3), position)
    angles = np.asarray(pose[3:])
    if not np.all(np.isfinite(pose)):
        raise InputError(f"--pose {list(pose)}: expected six finite numbers (X Y Z A B C)")
    if not degrees and np.any(np.abs(angles) > 2 * np.pi):
        raise InputError(f"pose angles {angles.tolist()} rad: larger than 2 pi in magnitude; add --deg "
                         f"if they are degrees")
    R = matrix_from_euler(angles, convention, degrees=degrees)
    return transform_from(R, pose[:3])


#: Joint distance [rad or m] below which a returned solution is the same as a listed one.
SAME_SOLUTION = 1e-9


def _contact_text(contacts: list[tuple[str, str]]) -> str:
    """A table cell: ``free``, or the pairs in contact (``link3-floor``)."""
    return pair_text(contacts, "free")


def _numbered(robot: Robot, T: np.ndarray, q: np.ndarray, near: np.ndarray,
              closed_form: bool, turn_copies: bool) -> tuple[np.ndarray, np.ndarray]:
    """Each row of ``q``: its number among all solutions, and whether it stands for a family.

    The numbers are positions in :func:`ik_solutions`'s list for the same ``near``, in-limit
    solutions first (nearest first), then the others: ``--outside`` adds rows after the
    in-limit ones and never renumbers them. The family flag is that list's own (asking
    ``ik_solutions`` with another reference would move a family's member elsewhere).
    """
    if not closed_form:
        return np.arange(1, len(q) + 1), np.zeros(len(q), dtype=bool)
    found = ik_solutions(robot, T, near=near, turn_copies=turn_copies)
    order = np.argsort(~found.within_limits, kind="stable")
    listed, family = found.q[order], found.family[order]
    distance = np.abs(q[:, None, :] - listed[None, :, :]).max(axis=-1)
    index = np.argmin(distance, axis=1)
    matched = distance[np.arange(len(q)), index] < SAME_SOLUTION
    return np.where(matched, index + 1, 0), matched & family[index]


def _position_ik(arm: Robot, p: np.ndarray, all_solutions: bool, near: np.ndarray, outside: bool,
                 turn_copies: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray, bool, str]:
    """``--position``: closed form where joints 1-3 have one (every solution with ``--all``),
    else numeric IK for the position alone; (q, numbers, family, closed, method)."""
    try:
        case = position_case(arm)
        if arm.n > 3 and not all_solutions:  # one solution: every joint may move (numeric)
            raise NoClosedFormError("joints 4.. would be held")
    except NoClosedFormError as exc:
        if all_solutions:
            raise NoClosedFormError(f"--position --all lists closed-form solutions, but {exc}; drop --all "
                                    f"for one numeric solution nearest --near") from exc
        q = np.atleast_2d(arm.ik(transform_from(np.eye(3), p), near=near, within_limits=not outside,
                                 mask=POSITION_ONLY))
        return q, np.ones(1, dtype=int), np.zeros(1, dtype=bool), False, "numeric (Levenberg-Marquardt)"
    q = np.atleast_2d(arm.ik_position(p, all_solutions=all_solutions, near=near, within_limits=not outside,
                                      turn_copies=turn_copies))
    found = ik_position_solutions(arm, p, near=near, turn_copies=turn_copies)
    order = np.argsort(~found.within_limits, kind="stable")
    distance = np.abs(q[:, None, :] - found.q[order][None]).max(axis=-1)
    index = np.argmin(distance, axis=1)
    held = f", joints 4-{arm.n} held at --near" if arm.n > 3 else ""
    return q, index + 1, found.family[order][index], True, f"closed form, position only ({case}{held})"


@app.command("ik", context_settings=ALLOW_NEGATIVE)
def ik_command(
    robot: RobotArg,
    near_values: Annotated[list[str] | None, typer.Argument(
        metavar="[Q...]", help="The rest of the --near joint values.", show_default=False)] = None,
    pose: Annotated[tuple[float, float, float, float, float, float] | None, typer.Option(
        help="Target: position X Y Z in m and three angles A B C in the --euler convention.",
        show_default=False)] = None,
    matrix: Annotated[Matrix16 | None, typer.Option(
        help="Target as 16 numbers: the 4x4 matrix row by row, lengths in m.", show_default=False)] = None,
    position: Annotated[tuple[float, float, float] | None, typer.Option(
        help="Target position X Y Z in m, any orientation: numeric IK, or closed form where joints 1-3 "
             "have one (a 3-joint arm, or with --all: joints 4.. held at --near).",
        show_default=False)] = None,
    euler: Annotated[str, typer.Option(help="Convention of the pose angles, e.g. xyz-fixed "
                                            "(roll pitch yaw), xyz-euler, zyz-euler.")] = "xyz-fixed",
    deg: Annotated[bool, typer.Option("--deg", help="Angles (pose, --near, printed joints) "
                                                    "in degrees.")] = False,
    all_solutions: Annotated[bool, typer.Option("--all", help="List every solution inside the "
                                                              "limits (closed form).")] = False,
    outside: Annotated[bool, typer.Option("--outside", help="Also list solutions outside the "
                                                            "joint limits.")] = False,
    turn_copies: Annotated[bool, typer.Option(
        "--turn-copies/--no-turn-copies", help="With --all, also list the whole-turn copies q + 360 deg "
                                               "of joints whose limits span more than a turn (e.g. a "
                                               "UR5's +-360 deg); default each solution once, with the "
                                               "number of copies inside the limits.")] = False,
    near: Annotated[str | None, typer.Option(
        "--near", metavar="Q...", help="Return the solution closest to these joint values, e.g. "
                                       "--near 0 -0.5 0.5 0 1 0 or --near 0,-0.5,0.5,0,1,0 (rad and m; "
                                       "deg with --deg; default zeros).", show_default=False)] = None,
    json_output: Annotated[bool, typer.Option("--json", help="Print JSON (SI units) instead of "
                                                             "a table.")] = False,
    free_joint: Annotated[str | None, typer.Option(
        "--free-joint", metavar="JOINT", help="Hold this joint (name or number 1..n) and solve the others "
                                              "exactly: every solution of a 7-joint arm at --free-value.",
        show_default=False)] = None,
    free_value: Annotated[float | None, typer.Option(
        "--free-value", help="The held joint's value (rad or m; deg with --deg); default its --near value.",
        show_default=False)] = None,
    self_motion_plot: Annotated[Path | None, typer.Option(
        "--self-motion", metavar="FILE", help="With --free-joint: every branch of the self-motion along it "
                                              "(64 values over its limits), each joint plotted against it "
                                              "(.png, .svg, .pdf).", show_default=False)] = None,
    force: Annotated[bool, typer.Option("--force", help="Replace an existing --self-motion file.")] = False,
    base: BaseOpt = None,
    tip: TipOpt = None,
    lock: LockOpt = None,
    scene: SceneOpt = None,
    package_path: PackagePathOpt = None,
) -> None:
    """Inverse kinematics: the solutions of a tool pose, with limits flag and FK residual.

    Example: armkit ik probot-anno --pose 0.2 0.2 0.2007 1.5707963 -1.5707963 0 --all
    """
    arm = load_robot(robot, base, tip, lock)
    world = load_scene_option(arm, scene, package_path)
    words = option_values(near, near_values, "--near", "joint values")
    q_near = to_si(arm, words, deg, "--near") if words is not None else np.zeros(arm.n)
    if euler.strip().lower() in QUATERNION_NAMES:
        raise InputError("--euler quat is an output format (armkit fk); give the target as --pose with "
                         "angles in a convention such as xyz-fixed, or as --matrix")
    convention = parse_convention(euler)
    T = target_from_options(pose, matrix, position, convention, deg)
    structure = analyze_structure(arm.chain)
    closed = structure.closed_form
    if self_motion_plot is not None and free_joint is None:
        raise InputError("--self-motion: name the joint it sweeps with --free-joint")
    try:
        if free_joint is not None:
            if position is not None:
                raise InputError("--free-joint takes a full pose (--pose or --matrix), not --position")
            held = joint_option(arm, free_joint, f"--free-joint {free_joint!r}")
            value = None
            if free_value is not None:
                value = np.radians(free_value) if deg and not arm.chain.prismatic[held] else float(free_value)
            options = {"turn_copies": turn_copies} if all_solutions else {}
            q = np.atleast_2d(arm.ik(T, all_solutions=all_solutions, near=q_near, within_limits=not outside,
                                     free_joint=held, free_value=value, **options))
            number, family = np.arange(1, len(q) + 1), np.zeros(len(q), dtype=bool)
            shown_value = q_near[held] if value is None else value
            unit = "m" if arm.chain.prismatic[held] else ("deg" if deg else "rad")
            shown_value = np.degrees(shown_value) if unit == "deg" else shown_value
            method = f"closed form with {arm.joint_names[held]} held at {fmt_number(shown_value, 4)} {unit}"
        elif position is not None:
            q, number, family, closed, method = _position_ik(arm, T[:3, 3], all_solutions, q_near, outside,
                                                              turn_copies)
        else:
            options = {"turn_copies": turn_copies} if all_solutions else {"scene": world}
            q = np.atleast_2d(arm.ik(T, all_solutions=all_solutions, near=q_near, within_limits=not outside,
                                     **options))
            number, family = _numbered(arm, T, q, q_near, closed, turn_copies)
            method = "closed form" if closed else "numeric (Levenberg-Marquardt)"
    except JointLimitError as exc:  # said again in the units the user typed
        if not deg or exc.q is None:
            raise
        raise outside_limits(arm.chain, exc.q, "", degrees=True) from None
    order = np.argsort(number, kind="stable")
    q, number, family = q[order], number[order], family[order]
    inside = arm.within_limits(q)
    copies = (count_turn_copies(arm.chain, q[inside], None if position is None else np.arange(arm.n) < 3)
              if all_solutions and not turn_copies else None)
    contacts = [world.contacts(qi) for qi in q] if world is not None else None
    T_found = arm.fk(q)
    position_error = np.linalg.norm(T_found[:, :3, 3] - T[:3, 3], axis=-1)
    orientation_error = (rotation_angle_between(T_found, T) if position is None
                         else np.full(len(q), np.nan))
    if json_output:
        print_json({"robot": arm.name, "target": T, "method": method,
                    "structure": structure.description, "solutions": q, "numbers": number,
                    "within_limits": inside, "family": family,
                    "position_error": position_error, "orientation_error": orientation_error,
                    "configurations_inside_limits": copies,
                    **({} if contacts is None else {"collides": [bool(c) for c in contacts],
                                                    "contacts": contacts}),
                    "joint_names": arm.joint_names},
                   {"target": "m (translation column)", "solutions": JOINT_UNITS, "position_error": "m",
                    "orientation_error": "rad"})
        return
    unit = "deg" if deg else "rad"
    shown = np.where(arm.chain.prismatic, q, np.degrees(q) if deg else q)
    digits = np.where(arm.chain.prismatic, 4, 2 if deg else 4)
    table = Table(title=escape(f"{arm.name}: {len(q)} IK solution{'s' * (len(q) != 1)}, {method}"),
                  caption="# = the solution's number (in-limit ones first, nearest --near first); FK "
                          "residual of each solution", box=box.SIMPLE_HEAD)
    table.add_column("#", justify="right")
    for name, prismatic in zip(arm.joint_names, arm.chain.prismatic, strict=True):
        table.add_column(escape(f"{name} [{'m' if prismatic else unit}]"), justify="right")
    extra = ["limits", *(["family"] if family.any() else []),
             *(["collision"] if contacts is not None else []), "pos.err [m]", "ang.err [rad]"]
    for column in extra:
        table.add_column(escape(column), justify="right")
    for k in range(len(q)):
        flags = ["in" if inside[k] else "OUT", *(["yes" if family[k] else ""] if family.any() else []),
                 *([_contact_text(contacts[k])] if contacts is not None else [])]
        table.add_row(str(number[k]) if number[k] else "-",
                      *(fmt_number(v, d) for v, d in zip(shown[k], digits, strict=True)),
                      *flags, f"{position_error[k]:.0e}",
                      "-" if np.isnan(orientation_error[k]) else f"{orientation_error[k]:.0e}")
    natural = Measurement.get(console, console.options.update_width(1000), table).maximum
    # wider than the terminal rather than truncate a joint value
    Console(width=max(console.width, natural)).print(table)
    if all_solutions and arm.chain.spans_turns:
        joints = ", ".join(arm.joint_names[j] for j in arm.chain.spans_turns)
        if turn_copies:
            console.print(escape(f"Whole-turn copies are listed: the limits of {joints} span more than a "
                                 f"turn (without --turn-copies each solution is listed once)."))
        else:
            console.print(escape(f"With their whole-turn copies the {int(inside.sum())} solutions inside the "
                                 f"limits make {copies} configurations there (the limits of {joints} span "
                                 f"more than a turn); --turn-copies lists them."))
    if contacts is not None:
        console.print(escape(f"collision: checked against {scene} (free, or the parts in contact)"
                             + ("; without --all the nearest free solution is shown" if not all_solutions
                                else "")))
    if family.any():
        console.print("family = yes: a singular pose; the row represents a one-parameter family "
                      "of solutions (e.g. only q4 + q6 is defined at a wrist singularity).")
    if self_motion_plot is not None:
        from armkit.ik.self_motion import self_motion

        motion = self_motion(arm, T, free_joint=joint_option(arm, free_joint, f"--free-joint {free_joint!r}"),
                             samples=64)
        motion.plot(self_motion_plot, joint_names=arm.joint_names, overwrite=force)
        console.print(escape(f"Self-motion: {len(motion.q)} branches along "
                             f"{arm.joint_names[motion.free_joint]}, written to {self_motion_plot}"))

"""``armkit lab``: run the seed experiments end to end and write the HTML report.

With no robot the lab reproduces report 000 on the PROBOT Anno (FK check, IK with every
in-limit solution, straight line by velocity control, minimum-jerk trajectory, fixed-point
rotation), compares the trajectory's joint torques with MuJoCo's inverse dynamics, plans a
motion around a box (armkit's own experiment 7), adds the FK tables of the ZJU-I (report 003)
and the GRB400 SCARA (report 004), and checks every simulated motion against a floor and the
arm itself. With a robot file it runs experiments 1-7 and the check on that arm, choosing
reachable targets itself.
"""

from __future__ import annotations

import shutil
import time
from collections.abc import Callable
from dataclasses import dataclass
from datetime import UTC, datetime
from pathlib import Path

import numpy as np
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

import armkit
from armkit.errors import ArmkitError
from armkit.lab import dynamics, fk_ik, floor, motion, planning
from armkit.lab.context import LabContext
from armkit.lab.report import (
    Section,
    Table,
    check_folder,
    install_report,
    staging_folder,
    status_label,
    write_report,
)
from armkit.poe import poe_from_chain
from armkit.robot import Robot
from armkit.robot_file import load

__all__ = ["LabResult", "run_lab"]

Experiment = Callable[[LabContext], Section]


@dataclass(frozen=True)
class LabResult:
    """Where the report went, its sections, and how long the run took [s]."""

    index: Path
    sections: list[Section]
    seconds: float


def _dh_section(robots: list[Robot]) -> Section:
    section = Section("dh", "DH tables and joint axes", "The robots as armkit read them; DH lengths and "
                      "angles in the units of the robot file, q = the joint variable.", badge=False)
    for robot in robots:
        if robot.dh is None:
            section.tables.append(_joint_axes_table(robot))
            continue
        dh = robot.dh
        length = 1e-3 if dh.length_unit == "mm" else 1.0
        angle = np.pi / 180 if dh.angle_unit == "deg" else 1.0
        keys = ["alpha", "a", "d", "theta"] if dh.convention == "modified" else ["theta", "d", "a", "alpha"]
        names = {"alpha": "alpha_{i-1}" if dh.convention == "modified" else "alpha_i",
                 "a": "a_{i-1}" if dh.convention == "modified" else "a_i", "d": "d_i", "theta": "theta_i"}
        rows = []
        labelled = ([(f"base {k + 1}", None, r) for k, r in enumerate(dh.base_rows)]
                    + [(j.name, j, r) for j, r in zip(robot.chain.joints, dh.rows, strict=True)]
                    + [(f"tool {k + 1}", None, r) for k, r in enumerate(dh.tool_rows)])
        for label, joint, row in labelled:
            cells = []
            for key in keys:
                value = getattr(row, key) / (angle if key in ("alpha", "theta") else length)
                moving = joint is not None and key == ("theta" if joint.kind == "revolute" else "d")
                cells.append((f"q {'-' if value < 0 else '+'} {abs(value):g}" if value else "q") if moving
                             else f"{value:g}")
            if joint is None:
                rows.append([label, "fixed", *cells, ""])
                continue
            unit = angle if joint.kind == "revolute" else length
            rows.append([label, joint.kind, *cells, f"[{joint.lower / unit:g}, {joint.upper / unit:g}]"])
        section.tables.append(Table(f"{robot.name}: {dh.convention} DH ({dh.length_unit}, {dh.angle_unit})",
                                    ["joint", "type", *[names[k] for k in keys], "limits"], rows))
    return section


def _joint_axes_table(robot: Robot) -> Table:
    """A robot without a DH table (URDF, joint lines, locked joints): its joint axes at q = 0."""
    poe = poe_from_chain(robot.chain)
    rows = [[joint.name, joint.kind, " ".join(f"{v:.6g}" for v in np.round(axis, 9) + 0.0),
             " ".join(f"{v:.6g}" for v in np.round(point, 9) + 0.0), f"[{joint.lower:g}, {joint.upper:g}]"]
            for joint, axis, point in zip(robot.chain.joints, poe.axes, poe.points, strict=True)]
    return Table(f"{robot.name}: joint axes at q = 0, base frame (m, rad)",
                 ["joint", "type", "axis", "point", "limits"], rows)


def _run_one(experiment: Experiment, ctx: LabContext) -> Section:
    """Run one experiment; an error marks its section failed (with the message) instead of ending the lab."""
    try:
        return experiment(ctx)
    except (ArmkitError, ValueError, RuntimeError) as exc:
        doc = (experiment.__doc__ or experiment.__name__).splitlines()[0]
        section = Section(experiment.__name__, doc, "")
        section.status = "failed"
        section.notes.append(f"{type(exc).__name__}: {exc}")
        return section


def _summary(sections: list[Section], seeds: bool) -> Table:
    """One row per experiment; the seed reports' column only when the seed experiments ran."""
    rows = [[s.title, status_label(s.status, seeds and not s.own), s.headline,
             *([s.published] if seeds else [])] for s in sections if s.key != "dh"]
    columns = ["experiment", "status", "armkit + MuJoCo", *(["the seed report"] if seeds else [])]
    return Table("Summary", columns, rows, wrap=True)


def run_lab(robot: str | Path | Robot | None = None, out: str | Path = "armkit-report", *,
            quick: bool = False, force: bool = False, progress: bool = True) -> LabResult:
    """Run the lab and write ``out/index.html``.

    Parameters
    ----------
    robot : str, Path or Robot, optional
        A robot, robot file, URDF file or built-in name; default: the seed experiments
        (PROBOT Anno, ZJU-I, GRB400 SCARA).
    out : str or Path
        Report folder. An earlier armkit report there is replaced, once the new one is
        complete (it is written to a staging folder beside ``out`` first, which an error or
        Ctrl-C removes); any other non-empty folder is refused unless ``force``.
    quick : bool
        Fewer, smaller animation frames and shorter moves (for tests).
    progress : bool
        Show a progress bar (rich) on the terminal.

    Raises
    ------
    InputError
        If ``out`` is not an armkit report folder and ``force`` is false.
    RobotDefinitionError
        If the robot cannot be loaded or simulated.
    """
    started = time.perf_counter()
    folder = Path(out)
    seeds = robot is None
    arm = robot if isinstance(robot, Robot) else load("probot-anno" if seeds else robot)
    check_folder(folder, force)
    staging = None
    try:
        ctx = LabContext(robot=arm, folder=folder, quick=quick, seeds=seeds)
        ctx.sim  # noqa: B018  (build the model first: a robot that cannot be simulated fails before any file)
        staging = ctx.folder = staging_folder(folder)
        sections = _run_stages(ctx, started, progress)
        install_report(staging, folder, force)
    finally:
        if staging is not None and staging.exists():
            shutil.rmtree(staging, ignore_errors=True)
    return LabResult(index=folder / "index.html", sections=sections, seconds=time.perf_counter() - started)


def _run_stages(ctx: LabContext, started: float, progress: bool) -> list[Section]:
    """Run every experiment and write the report into ``ctx.folder``; return the sections."""
    arm, seeds, quick = ctx.robot, ctx.seeds, ctx.quick
    stages: list[tuple[str, Experiment]] = [
        ("FK check", fk_ik.fk_check), ("IK, every solution", fk_ik.ik_check),
        ("straight line", motion.linear_motion), ("minimum-jerk trajectory", motion.trajectory_experiment),
        ("fixed-point rotation", motion.fixed_point_rotation),
        ("joint torques", dynamics.dynamics_experiment), ("planned around a box", planning.planned_motion)]
    if seeds:
        stages += [("ZJU-I table", fk_ik.fk_table_zju), ("SCARA table", fk_ik.fk_table_scara)]
    sections = []
    columns = (TextColumn("[bold]{task.description:<28}"), BarColumn(),
               TextColumn("{task.completed}/{task.total}"), TimeElapsedColumn())
    with Progress(*columns, disable=not progress, transient=False) as bar:
        task = bar.add_task("armkit lab", total=len(stages) + 2)
        for label, experiment in stages:
            bar.update(task, description=label)
            ctx.stage = label
            sections.append(_run_one(experiment, ctx))
            bar.advance(task)
        bar.update(task, description="collision check")
        sections.append(_run_one(floor.floor_check, ctx))
        bar.advance(task)
        bar.update(task, description="writing the report")
        robots = [arm, load("zju-i"), load("grb400-scara")] if seeds else [arm]
        sections.append(_dh_section(robots))
        seconds = time.perf_counter() - started
        title = "armkit lab: " + ("the seed experiments in MuJoCo" if seeds else f"{arm.name} in MuJoCo")
        subtitle = (f"armkit {armkit.__version__}, MuJoCo simulation at 1 kHz with gravity, "
                    f"{datetime.now(UTC):%Y-%m-%d %H:%M} UTC, {seconds:.0f} s"
                    f"{' (quick mode)' if quick else ''}.")
        write_report(ctx.folder, title, subtitle, _summary(sections, seeds), sections, ctx.files, seeds)
        bar.advance(task)
    return sections

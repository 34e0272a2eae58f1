"""The lab's collision check: every simulated motion of the experiments against a floor at the base.

Each experiment that runs a motion in MuJoCo records its commanded configurations
(:meth:`LabContext.record`); this section checks all of them with an :class:`armkit.Scene` of the
robot and a floor plane at ``z = 0`` of its base frame (self-collision included, the sampled pairs
left out as in :mod:`armkit.collision.scene`), and lists per experiment the configurations checked,
those in collision, the smallest clearance and the first contact.
"""

from __future__ import annotations

import numpy as np

from armkit.errors import pair_text
from armkit.lab.context import FLOOR_HEIGHT, LabContext, fmt, fmt_q
from armkit.lab.report import Section, Table

__all__ = ["FLOOR_HEIGHT", "floor_check"]



def floor_check(ctx: LabContext) -> Section:
    """Collisions with a floor and with the arm itself along every simulated motion."""
    section = Section("floor", "Collision check: floor and self-collision",
                      f"Every configuration the experiments command in MuJoCo, checked with armkit.Scene: "
                      f"the arm's capsules against a floor at z = {FLOOR_HEIGHT:g} m of the base frame and "
                      f"against themselves (docs/collision.md).", own=True)
    scene = ctx.scene
    rows, colliding = [], 0
    for name, q in ctx.motions:
        hit = scene.collides(q)
        clearance = scene.clearance(q[:: max(1, len(q) // 200)])  # about 200 samples per motion
        first = int(np.argmax(hit)) if hit.any() else None
        contact = ("-" if first is None else
                   pair_text(scene.contacts(q[first])) + f" at {fmt_q(q[first], 3)}")
        rows.append([name, f"{len(q):,}", f"{int(hit.sum()):,}", fmt(float(clearance.min()), 4), contact])
        colliding += int(hit.any())
    section.tables.append(Table("Configurations in collision per experiment",
                                ["experiment", "configurations", "in collision",
                                 "min clearance [m] (sampled)", "first contact"], rows, wrap=True))
    if not ctx.motions:
        section.status = "n/a"
        section.notes.append("Not applicable, because no experiment ran a motion.")
        section.headline = "no motion to check"
    elif colliding:
        section.status = "failed"
        section.headline = f"{colliding} of {len(ctx.motions)} motions touch the floor or the arm itself"
    else:
        section.headline = f"{len(ctx.motions)} motions free of the floor and of self-collision"
    return section

"""Collision-free IK: :meth:`armkit.Robot.ik` with ``scene=``.

Every solution the IK lists is checked with :meth:`Scene.collides`; ``all_solutions=True`` keeps
the free ones (in the same order, nearest to ``near`` first), one solution is the nearest free one:
the first free one of that listing (whole-turn copies of a joint move no link, so the copy nearest to
``near`` stands for all of them). A chain without a closed form has one numeric solution per seed:
it is returned when free, else :class:`~armkit.errors.CollisionError`.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit.collision.scene import Scene
from armkit.errors import CollisionError, InputError, pair_text
from armkit.ik.structure import analyze_structure
from armkit.robot import Robot

__all__ = ["ik_free"]


def _label(i: int, batch: bool) -> str:
    return f"target pose {i}" if batch else "the target pose"


def ik_free(robot: Robot, scene: Scene, T_base_tool: ArrayLike, *, all_solutions: bool,
            near: ArrayLike | None, within_limits: bool,
            **options) -> NDArray[np.float64] | list[NDArray[np.float64]]:
    """:meth:`Robot.ik` restricted to the configurations where ``scene`` finds no collision.

    Raises
    ------
    CollisionError
        If one solution is asked and every solution of a pose collides (the error's ``contacts``
        name the pairs in contact at the nearest one).
    InputError
        If ``scene`` is not an :class:`armkit.Scene` built for this robot.
    """
    if not isinstance(scene, Scene):
        raise InputError(f"scene: expected an armkit.Scene, got {type(scene).__name__}")
    scene.check_robot(robot)
    if all_solutions:
        listed = robot.ik(T_base_tool, all_solutions=True, near=near, within_limits=within_limits, **options)
        if isinstance(listed, list):
            return [q[~scene.collides(q)] for q in listed]
        return listed[~scene.collides(listed)]
    if not analyze_structure(robot.chain).closed_form or "mask" in options:
        q = robot.ik(T_base_tool, near=near, within_limits=within_limits, **options)
        hit = np.atleast_1d(scene.collides(q))
        if hit.any():
            i = int(np.argmax(hit))
            one = np.reshape(q, (-1, robot.n))[i]
            raise CollisionError(f"{_label(i, q.ndim > 1)}: the numeric IK solution from near collides "
                                 f"({pair_text(scene.contacts(one))}); try another near", q=one,
                                 contacts=scene.contacts(one))
        return q
    listed = robot.ik(T_base_tool, all_solutions=True, near=near, within_limits=within_limits, **options)
    batch = isinstance(listed, list)
    chosen = []
    for i, q in enumerate(listed if batch else [listed]):
        free = ~scene.collides(q)
        if not free.any():
            contacts = scene.contacts(q[0])
            raise CollisionError(f"{_label(i, batch)}: all {len(q)} IK solution{'s' * (len(q) != 1)} "
                                 f"collide (the nearest to near: {pair_text(contacts)})", q=q,
                                 contacts=contacts)
        chosen.append(q[int(np.argmax(free))])
    if not batch:
        return chosen[0]
    shape = np.shape(T_base_tool)[:-2]
    return np.reshape(np.array(chosen), (*shape, robot.n))




"""Collision-free IK: Robot.ik(..., scene=) lists the free subset and picks the nearest free solution."""

from __future__ import annotations

import numpy as np
import pytest

import armkit
from armkit.errors import CollisionError, InputError
from armkit.spatial.transforms import transform_from

pytest.importorskip("mujoco")

UR5 = armkit.load("ur5")


@pytest.fixture(scope="module")
def scene() -> armkit.Scene:
    wall = armkit.Box([0.05, 2.0, 2.0], transform_from(np.eye(3), [-0.45, 0.0, 1.0]))
    return armkit.Scene(UR5, [wall], floor=0.0)


def _targets(count: int, seed: int) -> np.ndarray:
    return UR5.fk(UR5.random_q(count, rng=seed))


def test_the_free_solutions_are_the_listing_filtered_by_collides(scene):
    found_colliding = found_free = 0
    for T in _targets(40, 1):
        listed = UR5.ik(T, all_solutions=True)
        free = UR5.ik(T, all_solutions=True, scene=scene)
        np.testing.assert_array_equal(free, listed[~scene.collides(listed)])
        found_colliding += len(listed) - len(free)
        found_free += len(free)
    assert found_colliding > 20 and found_free > 20  # both kinds occur among these poses


def test_a_batch_of_poses_lists_the_free_subset_of_each(scene):
    T = _targets(6, 2)
    listed = UR5.ik(T, all_solutions=True)
    free = UR5.ik(T, all_solutions=True, scene=scene)
    for a, b in zip(listed, free, strict=True):
        np.testing.assert_array_equal(b, a[~scene.collides(a)])


def test_near_gives_the_nearest_free_solution(scene):
    rng = np.random.default_rng(3)
    checked = 0
    for T in _targets(60, 4):
        near = UR5.random_q(rng=rng)
        listed = UR5.ik(T, all_solutions=True, near=near)
        free = listed[~scene.collides(listed)]
        if len(free) == 0:
            with pytest.raises(CollisionError, match="collide") as info:
                UR5.ik(T, near=near, scene=scene)
            assert info.value.contacts == scene.contacts(listed[0])
            continue
        q = UR5.ik(T, near=near, scene=scene)
        assert not scene.collides(q)
        distance = np.linalg.norm(free - near, axis=1)
        assert np.linalg.norm(q - near) == pytest.approx(distance.min(), abs=1e-12)
        checked += 1
    assert checked > 20  # and the rest raised


def test_near_for_a_batch_of_poses_gives_one_free_solution_each(scene):
    T = _targets(5, 6)
    T = T[[not np.all(scene.collides(UR5.ik(Ti, all_solutions=True))) for Ti in T]]
    q = UR5.ik(T, near=np.zeros(6), scene=scene)
    assert q.shape == (len(T), 6) and not scene.collides(q).any()
    for Ti, qi in zip(T, q, strict=True):
        np.testing.assert_allclose(UR5.fk(qi), Ti, atol=1e-9)


def test_a_scene_of_another_robot_is_refused(scene):
    puma = armkit.load("puma560")
    with pytest.raises(InputError, match="built for"):
        puma.ik(puma.fk(np.zeros(6)), scene=scene)


def test_the_same_arm_loaded_again_takes_the_scene_and_a_locked_copy_does_not(scene):
    again = armkit.load("ur5")
    T = again.fk([0.3, -1.2, 1.0, -0.5, 1.2, 0.4])
    np.testing.assert_array_equal(again.ik(T, all_solutions=True, scene=scene),
                                  scene.robot.ik(T, all_solutions=True, scene=scene))
    locked = again.lock({"q6": 0.0})
    with pytest.raises(InputError, match="joints, links or limits differ"):
        locked.ik(locked.fk(np.zeros(5)), scene=scene)

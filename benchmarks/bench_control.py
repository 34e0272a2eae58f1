"""One resolved-rate control step: armkit against roboticstoolbox-python, in one process.

The step, for a 6-joint arm at one configuration and a desired base-frame twist: forward
kinematics and Jacobian, the smallest singular value, damped least squares with the
damping of :func:`armkit.control.damping`, and scaling to the joint velocity limits.
roboticstoolbox-python has no resolved-rate function of its own (its docs' resolved-rate
example is ``pinv(jacob0(q)) @ v``), so its side is its fastest Jacobian (the compiled ETS
``jacob0``) followed by the same damped solve in NumPy; its DH-class ``jacob0`` and the
plain ``pinv`` example are shown too. The script first checks that both sides return the
same joint velocities. A closed-loop step adds the pose error from FK: armkit's
:func:`armkit.control.track_poses` step against rtb ``ETS.eval`` + ``p_servo``.

Run: python benchmarks/bench_control.py [--quick]
Prints the median time per step [us] and the ratio peer / armkit (> 1: armkit is faster).
"""

from __future__ import annotations

import argparse

import numpy as np
import roboticstoolbox as rtb
from _timing import median_seconds
from scipy.linalg import lapack
from spatialmath import SE3

import armkit
from armkit.control import ResolvedRate
from armkit.control.resolved_rate import DEFAULT_MAX_DAMPING, DEFAULT_THRESHOLD
from armkit.kinematics import pose_error


def probot_rtb() -> rtb.DHRobot:
    """PROBOT Anno in roboticstoolbox-python, from the same modified DH table."""
    d = np.pi / 180
    links = [rtb.RevoluteMDH(alpha=0, a=0, d=0.284),
             rtb.RevoluteMDH(alpha=90 * d, a=0, d=0, offset=90 * d),
             rtb.RevoluteMDH(alpha=0, a=0.225, d=0),
             rtb.RevoluteMDH(alpha=90 * d, a=0, d=0.2289),
             rtb.RevoluteMDH(alpha=-90 * d, a=0, d=0, offset=-90 * d),
             rtb.RevoluteMDH(alpha=90 * d, a=0, d=0)]
    return rtb.DHRobot(links, tool=SE3.Tz(0.055) * SE3.Rx(-90 * d), name="PROBOT Anno")


def dls_numpy(J: np.ndarray, twist: np.ndarray, inverse_max_velocity: np.ndarray) -> np.ndarray:
    """The same damped least squares and velocity scaling, written with NumPy for the peer."""
    sigma_min = np.linalg.svd(J, compute_uv=False)[-1]
    ratio = min(sigma_min / DEFAULT_THRESHOLD, 1.0)  # armkit's damping law, in plain floats
    lam2 = (1.0 - ratio * ratio) * DEFAULT_MAX_DAMPING**2
    qd = J.T @ np.linalg.solve(J @ J.T + lam2 * np.eye(6), twist)
    ratio = np.max(np.abs(qd) * inverse_max_velocity)
    return qd / ratio if ratio > 1 else qd


def median_us(function, repeat: int, number: int) -> float:
    return median_seconds(function, repeat, number) * 1e6


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--quick", action="store_true", help="fewer repetitions")
    args = parser.parse_args()
    repeat, number = (7, 200) if args.quick else (15, 2000)
    ours = armkit.load("probot-anno")
    theirs = probot_rtb()
    ets = theirs.ets()
    control = ResolvedRate(ours)
    inverse_max_velocity = 1.0 / ours.max_velocity
    q = np.array([0.3, -0.5, 0.4, 0.2, 1.2, -0.3])
    twist = np.array([0.05, -0.02, 0.03, 0.1, -0.2, 0.15])

    # Same work, same answer: check before timing.
    expected = dls_numpy(ets.jacob0(q), twist, inverse_max_velocity)
    assert np.allclose(control.step(q, twist).qd, expected, atol=1e-12), "the two steps disagree"
    q_near = np.array([0.3, -0.5, 0.4, 0.2, np.pi / 2 - 1e-3, -0.3])  # near the wrist singularity
    assert np.allclose(control.step(q_near, twist).qd,
                       dls_numpy(ets.jacob0(q_near), twist, inverse_max_velocity), atol=1e-9)

    T_target = ours.fk(q + 0.01)
    T_target_se3 = SE3(T_target, check=False)

    def armkit_closed_loop():
        T, J = control.kernel.fk_jacobian(q)
        return control.solve(J, twist + 20.0 * pose_error(T_target, T)).qd

    def rtb_closed_loop():
        T = ets.eval(q)
        v = rtb.p_servo(SE3(T, check=False), T_target_se3, gain=20.0)[0]
        return dls_numpy(ets.jacob0(q), twist + v, inverse_max_velocity)

    cases = [
        ("step: J, DLS, scaling", lambda: control.step(q, twist),
         [("rtb ETS jacob0 + NumPy DLS", lambda: dls_numpy(ets.jacob0(q), twist, inverse_max_velocity)),
          ("rtb DH jacob0 + NumPy DLS",
           lambda: dls_numpy(theirs.jacob0(q), twist, inverse_max_velocity)),
          ("rtb ETS jacob0 + pinv (no damping)", lambda: np.linalg.pinv(ets.jacob0(q)) @ twist)]),
        ("closed-loop step (+ pose error)", armkit_closed_loop,
         [("rtb ETS eval + p_servo + jacob0 + DLS", rtb_closed_loop)]),
    ]
    J = ours.jacobian(q)
    assert np.isclose(control.solve(J, twist).sigma_min, np.linalg.svd(J, compute_uv=False)[-1])
    print("ingredient: DLS step through a given 6x6 Jacobian (sigma_min, damping, solve) [us]: "
          f"np.linalg.svd alone {median_us(lambda: np.linalg.svd(J, compute_uv=False), repeat, number):.2f}, "
          "J J^T + LAPACK dsyev alone "
          f"{median_us(lambda: lapack.dsyev(J @ J.T, compute_v=0), repeat, number):.2f}, "
          f"armkit's whole step (core) {median_us(lambda: control.solve(J, twist), repeat, number):.2f}")
    print(f"PROBOT Anno (6R), one configuration; median of {repeat} x {number} calls")
    print(f"{'case':34} {'armkit [us]':>11}  {'peer':38} {'peer [us]':>9} {'peer/armkit':>11}")
    for label, mine, peers in cases:
        t_ours = median_us(mine, repeat, number)
        for peer_label, peer in peers:
            peer_runs = max(3, number // 20) if "DH" in peer_label else number
            t_peer = median_us(peer, repeat, peer_runs)
            print(f"{label:34} {t_ours:11.2f}  {peer_label:38} {t_peer:9.2f} {t_peer / t_ours:11.2f}")


if __name__ == "__main__":
    main()

"""IK speed and success: armkit against EAIK, ik-geo, roboticstoolbox-python and ikpy.

Run: python benchmarks/bench_ik.py [--quick]

(a) All-solutions closed-form IK for the PROBOT Anno and the UR5: median time per pose,
    one pose at a time and batched (N = 20,000, every core; armkit's ik_solutions also on
    one thread; a batch: the median of 3 calls after a warm-up one, see batch_seconds), and
    the mean number of solutions per pose that reproduce the pose to 1e-6 by armkit's FK.
    armkit's user-facing paths too: every solution with flags (ik_solutions), every
    solution as arrays (robot.ik(all_solutions=True)), and the nearest solution only
    (robot.ik(near=), one verified solution per pose).
(a2) The listing with whole-turn copies (turn_copies=True; a UR5's +-360 degree limits give
    2^6 copies of each solution) against the distinct listing: time per pose and per listed
    solution, one pose at a time and batched.
(b) Numeric IK on the Panda with joint limits from the same random seed per pose: success
    rate and median / mean time over random reachable poses (a batch: time per pose of one
    call), success judged by armkit's
    FK for every solver: position within 1e-6 m, orientation within 1e-6 rad, inside
    the limits.
Every peer is given exactly armkit's kinematics (same joint zeros, base and tool), so the
joint values are comparable. Ratios are peer time / armkit time (> 1: armkit is faster).
"""

from __future__ import annotations

import argparse
import time
import warnings

import eaik.pybindings.EAIK as eaik
import ik_geo
import numpy as np
import roboticstoolbox as rtb
from _timing import median_seconds

import armkit
from armkit import kinematics
from armkit.ik import closed_form_ik, ik_solutions, numeric_ik
from armkit.ik.numeric import NumericIK
from armkit.spatial import euler_from_matrix, rotation_angle_between

TOLERANCE = 1e-6  # m and rad: a solution counts if armkit's FK reproduces the pose this well


# ------------------------------------------------------------------ helpers
def timed(function, *args) -> tuple[float, object]:
    start = time.perf_counter()
    out = function(*args)
    return time.perf_counter() - start, out


def batch_seconds(function, T_batch: np.ndarray) -> float:
    """Median time of 3 calls on the batch after one warm-up call: the first call of a size pays
    for the first touch of fresh memory (on this development machine's VM about 17 ms per MB,
    some 100x a bare Linux machine's), which later calls reuse."""
    function(T_batch)
    return median_seconds(lambda: function(T_batch), 3)


def reproduces(robot: armkit.Robot, q: np.ndarray, T: np.ndarray) -> np.ndarray:
    """Per row of ``q`` ``(k, n)``: finite and FK within TOLERANCE of ``T``."""
    q = np.atleast_2d(np.asarray(q, dtype=float))
    finite = np.all(np.isfinite(q), axis=-1)
    F = robot.fk(np.where(finite[:, None], q, 0.0))
    return (finite & (np.linalg.norm(F[:, :3, 3] - T[:3, 3], axis=-1) <= TOLERANCE)
            & (rotation_angle_between(F, T) <= TOLERANCE))


def valid_rows(solutions) -> np.ndarray:
    return solutions.q[solutions.valid]


def axes_at_zero(chain: armkit.Chain) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Joint axes ``h`` (n, 3), offsets ``p`` (n + 1, 3) and tool rotation, in the base frame.

    The points of consecutive axes that meet are moved to where they meet (later pairs
    win), as IK-Geo's solvers require for a spherical wrist (EAIK finds them itself).
    """
    frames, T_tool = kinematics.joint_frames(chain, np.zeros(chain.n))
    h, points = frames[:, :3, 2], frames[:, :3, 3].copy()
    for i in range(chain.n - 1):
        normal = np.cross(h[i], h[i + 1])
        if np.linalg.norm(normal) < 1e-9:
            continue
        # closest points of the two lines; they meet if those coincide
        A = np.stack([h[i], -h[i + 1]], axis=1)
        s, t = np.linalg.lstsq(A, points[i + 1] - points[i], rcond=None)[0]
        a, b = points[i] + s * h[i], points[i + 1] + t * h[i + 1]
        if np.linalg.norm(a - b) < 1e-9:  # any point of an axis will do: take the meeting point
            points[i] = points[i + 1] = a
    offsets = np.vstack([points[0], np.diff(points, axis=0), T_tool[:3, 3] - points[-1]])
    return h, offsets, T_tool[:3, :3]


def table(title: str, header: list[str], rows: list[list[str]]) -> None:
    widths = [max(len(str(r[i])) for r in [header, *rows]) for i in range(len(header))]
    print(f"\n{title}")
    for row in [header, *rows]:
        cells = [f"{c:>{w}}" if i else f"{c:<{w}}" for i, (c, w) in enumerate(zip(row, widths, strict=True))]
        print("  ".join(cells))


def us(seconds: float) -> str:
    return f"{seconds * 1e6:.1f}"


def ratio(peer: float, ours: float) -> str:
    return f"{peer / ours:.2f}" if np.isfinite(peer) else "n/a"


# ------------------------------------------------------------------ (a) closed form
def closed_form_peers(robot: armkit.Robot, name: str) -> dict:
    """``label -> (solve one pose -> (k, n) array, solve a batch or None)`` for each peer."""
    h, p, R_tool = axes_at_zero(robot.chain)
    eaik_robot = eaik.Robot(h.T, p.T, R_tool, [], True)
    peers = {"EAIK (C++)": (lambda T: np.asarray(eaik_robot.calculate_IK(T).Q),
                            lambda Ts: eaik_robot.calculate_IK_batched(list(Ts), 1))}
    factory = {"probot-anno": ik_geo.Robot.spherical_two_parallel,
               "ur5": ik_geo.Robot.three_parallel_two_intersecting}[name]
    geo = factory(h.tolist(), p.tolist())
    # ik-geo reads the rotation row by row, so it gets the transpose
    peers["ik-geo (Rust)"] = (lambda T: np.array([s[0] for s in geo.get_ik((T[:3, :3] @ R_tool.T).T,
                                                                             T[:3, 3])]), None)
    if name == "ur5":  # rtb's analytic IK needs standard DH: the UR5, not the PROBOT Anno
        model = rtb.models.DH.UR5()
        start = time.perf_counter()
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                solver = model.analytic_ik()
        except (ImportError, ValueError) as exc:  # needs sympy; some sympy versions derive nothing
            print(f"  (rtb analytic_ik left out: {exc})")
            return peers
        print(f"  (rtb analytic_ik: symbolic derivation for the UR5 took "
              f"{time.perf_counter() - start:.1f} s, once)")
        peers["rtb analytic_ik"] = (lambda T: np.atleast_2d(solver.solve(T, joint_limits=False).q),
                                    None)
    return peers


def bench_closed_form(name: str, one: int, batch: int) -> None:
    robot = armkit.load(name)
    rng = np.random.default_rng(0)
    T_one = robot.fk(robot.random_q(one, rng=rng))
    T_batch = robot.fk(robot.random_q(batch, rng=rng))
    near = np.zeros((batch, robot.n))
    # each solution once (turn_copies=False), as the peers list them: a UR5's +-360 degree
    # limits would otherwise add 2^6 whole-turn copies of each
    mine = {"armkit ik_solutions": (lambda T: ik_solutions(robot, T, turn_copies=False).q,
                                    lambda Ts: ik_solutions(robot, Ts, turn_copies=False)),
            "armkit robot.ik(all_solutions=True)": (
                lambda T: robot.ik(T, all_solutions=True, within_limits=False, turn_copies=False),
                lambda Ts: robot.ik(Ts, all_solutions=True, within_limits=False, turn_copies=False)),
            "armkit robot.ik(near=) (nearest only)": (
                lambda T: robot.ik(T, within_limits=False),
                lambda Ts: robot.ik(Ts, near=near, within_limits=False)),
            "armkit closed_form_ik (raw)": (lambda T: valid_rows(closed_form_ik(robot, T)),
                                            lambda Ts: closed_form_ik(robot, Ts))}
    solvers = {**mine, **closed_form_peers(robot, name)}
    results = {}
    for label, (solve_one, solve_batch) in solvers.items():
        for T in T_one[:20]:  # warm-up (armkit: loads its compiled kernels from numba's cache)
            solve_one(T)
        times, counts = [], []
        for T in T_one:
            dt, q = timed(solve_one, T)
            times.append(dt)
            counts.append(int(reproduces(robot, q, T).sum()) if len(q) else 0)
        batched = batch_seconds(solve_batch, T_batch) / batch if solve_batch else np.nan
        results[label] = (float(np.median(times)), batched, float(np.mean(counts)))
        if label == "armkit ik_solutions":  # the same batch on one thread: what the second core adds
            one_thread = batch_seconds(lambda Ts: ik_solutions(robot, Ts, threads=1), T_batch) / batch
            results["armkit ik_solutions (batch on 1 thread)"] = (np.nan, one_thread, float(np.mean(counts)))
    ours_one, ours_batch, _ = results["armkit ik_solutions"]
    rows = [[label, "n/a" if np.isnan(t1) else us(t1), ratio(t1, ours_one), "n/a" if np.isnan(tb) else us(tb),
             ratio(tb, ours_batch), f"{n:.3f}"] for label, (t1, tb, n) in results.items()]
    table(f"(a) all-solutions IK, {robot.name}: {one} poses one at a time, batch of {batch}",
          ["solver", "one [us]", "/armkit", "batched [us/pose]", "/armkit", "verified sol./pose"], rows)


# ------------------------------------------------------------------ (a2) whole-turn copies
def bench_turn_copies(one: int, batch: int) -> None:
    robot = armkit.load("ur5")
    rng = np.random.default_rng(1)
    T_one, T_batch = robot.fk(robot.random_q(one, rng=rng)), robot.fk(robot.random_q(batch, rng=rng))
    rows, per_solution = [], {}
    for copies in (False, True):
        def listing(T, copies=copies):
            return robot.ik(T, all_solutions=True, turn_copies=copies)
        for T in T_one[:20]:  # warm-up
            listing(T)
        one_time = median_seconds(lambda: [listing(T) for T in T_one], 3) / one
        listed = np.mean([len(listing(T)) for T in T_one])
        def listings(Ts, copies=copies):
            return ik_solutions(robot, Ts, turn_copies=copies)
        batch_time = batch_seconds(listings, T_batch)
        batch_listed = float(listings(T_batch).counts.mean())
        per_solution[copies] = (one_time / listed, batch_time / batch / batch_listed)
        label = "with whole-turn copies" if copies else "each solution once"
        rows.append([f"{label}: robot.ik(T, all_solutions=True{', turn_copies=True' if copies else ''})",
                     us(one_time), f"{listed:.1f}", f"{one_time / listed * 1e9:.0f}",
                     us(batch_time / batch), f"{batch_time / batch / batch_listed * 1e9:.0f}"])
    rows.append(["per listed solution: copies / once", "", "",
                 f"{per_solution[True][0] / per_solution[False][0]:.2f}x", "",
                 f"{per_solution[True][1] / per_solution[False][1]:.2f}x"])
    table(f"(a2) whole-turn copies, UR5 at +-360 deg: {one} poses one at a time; ik_solutions on a batch of "
          f"{batch}", ["listing", "one [us]", "solutions/pose", "one [ns/solution]", "batched [us/pose]",
                       "batched [ns/solution]"], rows)


# ------------------------------------------------------------------ (b) numeric
def ets_from_chain(chain: armkit.Chain) -> rtb.ETS:
    """rtb's elementary transform sequence with exactly armkit's kinematics and limits."""
    ets = rtb.ET.SE3(np.array(chain.T_between[0]))
    for i, joint in enumerate(chain.joints):
        motion = rtb.ET.tz if joint.kind == "prismatic" else rtb.ET.Rz
        ets = ets * motion(qlim=[joint.lower, joint.upper]) * rtb.ET.SE3(np.array(chain.T_between[i + 1]))
    return ets


def ikpy_chain(chain: armkit.Chain):
    """An ikpy chain with exactly armkit's kinematics and limits."""
    from ikpy.chain import Chain as IkpyChain
    from ikpy.link import OriginLink, URDFLink

    def link(name: str, T: np.ndarray, joint=None) -> URDFLink:
        rpy = euler_from_matrix(T, "xyz-fixed")
        if joint is None:
            return URDFLink(name, T[:3, 3], rpy, joint_type="fixed")
        return URDFLink(name, T[:3, 3], rpy, rotation=[0, 0, 1], bounds=(joint.lower, joint.upper))

    links = [OriginLink()]
    links += [link(j.name, np.array(chain.T_between[i]), j) for i, j in enumerate(chain.joints)]
    links.append(link("tool", np.array(chain.T_between[-1])))
    mask = [False] + [True] * chain.n + [False]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return IkpyChain(links, active_links_mask=mask)


def bench_numeric(poses: int, slow_poses: int) -> None:
    robot = armkit.load("panda")
    chain = robot.chain
    q_true = robot.random_q(poses, rng=10)
    targets = robot.fk(q_true)
    seeds = robot.random_q(poses, rng=11)
    ets = ets_from_chain(chain)
    assert np.allclose(ets.eval(q_true[0]), targets[0], atol=1e-12)
    ik_py = ikpy_chain(chain)
    full = np.concatenate([[0.0], q_true[0], [0.0]])
    assert np.allclose(ik_py.forward_kinematics(full), targets[0], atol=1e-9)

    def ikpy_solve(T, q0):
        start = np.concatenate([[0.0], q0, [0.0]])
        return ik_py.inverse_kinematics_frame(T, initial_position=start, orientation_mode="all")[1:-1]

    # built once per chain, as rtb's ETS is
    solver = NumericIK(chain)
    coarse = NumericIK(chain, position_tolerance=1e-6, orientation_tolerance=1e-6)
    solvers = [
        ("armkit NumericIK.solve (tol 1e-9)", lambda T, q0, i: solver.solve(T, q0, rng=i).q, poses),
        ("armkit NumericIK.solve (tol 1e-6)", lambda T, q0, i: coarse.solve(T, q0, rng=i).q, poses),
        ("armkit numeric_ik (builds the solver)", lambda T, q0, i: numeric_ik(chain, T, q0=q0, rng=i).q,
         poses),
        ("rtb ik_LM C++ (tol 1e-6, default)",
         lambda T, q0, i: ets.ik_LM(T, q0=q0, joint_limits=True).q, poses),
        ("rtb ik_LM C++ (tol 1e-14)",
         lambda T, q0, i: ets.ik_LM(T, q0=q0, tol=1e-14, joint_limits=True).q, poses),
        ("rtb ikine_LM Python (tol 1e-14)",
         lambda T, q0, i: ets.ikine_LM(T, q0=q0, tol=1e-14, joint_limits=True).q, slow_poses),
        ("ikpy (scipy)", lambda T, q0, i: ikpy_solve(T, q0), slow_poses),
    ]
    rows, ours = [], None
    for label, solve, count in solvers:
        times, ok = [], 0
        for i in range(count):
            dt, q = timed(solve, targets[i], seeds[i], i)
            times.append(dt)
            ok += bool(reproduces(robot, q, targets[i])[0] and robot.within_limits(q))
        median, mean = float(np.median(times)), float(np.mean(times))
        ours = ours or median
        rows.append([label, str(count), f"{100 * ok / count:.1f}", f"{median * 1e3:.3f}",
                     f"{mean * 1e3:.3f}", ratio(median, ours)])
    for threads in (1, None):  # the whole batch in one call: its time per pose as the mean
        dt, result = timed(solver.solve_batch, targets[:poses], seeds[:poses], 0, threads)
        ok = sum(bool(reproduces(robot, q, T)[0] and robot.within_limits(q))
                 for q, T in zip(result.q, targets[:poses], strict=True))
        rows.append([f"armkit NumericIK.solve_batch (tol 1e-9, threads={threads or 'all'})", str(poses),
                     f"{100 * ok / poses:.1f}", "-", f"{dt / poses * 1e3:.3f}", "-"])
    table("(b) numeric IK, Panda with joint limits, random reachable poses, one random seed each",
          ["solver", "poses", "success %", "median [ms]", "mean [ms]", "median /armkit"], rows)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="a small run (seconds)")
    args = parser.parse_args()
    one, batch, poses, slow = (100, 20_000, 100, 20) if args.quick else (1000, 20_000, 1000, 200)
    for name in ("probot-anno", "ur5"):
        bench_closed_form(name, one, batch)
    bench_turn_copies(one, 2000)
    bench_numeric(poses, slow)


if __name__ == "__main__":
    main()

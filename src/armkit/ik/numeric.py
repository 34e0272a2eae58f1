"""Numeric inverse kinematics for any chain: Levenberg-Marquardt with random restarts.

The solver minimises ``E = 1/2 e^T W e`` where ``e = [p_target - p; log(R_target R^T)]``
is the pose error in the base frame (metres over radians, the rotation part a rotation
vector, :func:`armkit.kinematics.pose_error`) and ``W`` a diagonal 0/1 task mask. Each
step solves the damped normal equations of Sugihara's Levenberg-Marquardt method
(T. Sugihara, "Solvability-unconcerned inverse kinematics by the Levenberg-Marquardt
method", IEEE T-RO 27(5), 2011)::

    (J^T W J + (g E + damping) I) dq = J^T W e

whose damping grows with the error far from the target and nearly vanishes near it, so
the last steps converge quadratically (Sugihara uses ``g = 1``; ``g = 0.1`` needed the
fewest iterations on random Panda poses here). The floor ``damping = 1e-9`` is small on
purpose: with ``1e-6``, configurations whose Jacobian has a singular value near ``1e-3``
converged only linearly below ``1e-8`` and 0.3-1.7 % of random poses of the 6-joint built-ins
failed the ``1e-9`` tolerance; with ``1e-9`` none did. For ``m`` task rows and ``n >= m``
joints the same step is ``dq = J^T y`` with the ``m x m`` system ``(J J^T + lambda I) y = e``,
else the ``n x n`` one; either is solved by a Cholesky factorisation written out in the
compiled core.

Joint limits are kept during the iterations, as bounds: after each step a revolute angle
outside its range is moved into it by whole turns if that fits, else to the bound nearer
in angle (a prismatic value to the nearer bound), and a joint held at a bound by the
gradient (``J^T e`` pointing outwards) is left out of the next step (its Jacobian column
is zeroed), so the other joints take over instead of the step stalling against the
bound: an active set, so every answer is inside the limits. One seed iterates at a time, first
the caller's ``q0``: an attempt that has not halved its error in ``3`` steps, or has
used ``max_iterations`` steps, is abandoned for a new uniform random seed inside the
limits, until ``max_restarts`` runs out (or a ``time_budget``, only when one is given: a solve
cut short by the clock depends on the machine's load).

The whole solve, restarts included, is one call of the compiled core (``armkit._core``,
cpp/src/ik_numeric.cpp): the tool pose and Jacobian, the pose error, the projection, the
active set, the Cholesky solve, the restart seeds and the time budget, about 1 us per step on
a 7-joint arm. The restart seeds come from a small deterministic generator (xoshiro256**)
seeded once per solve from ``rng`` (default :data:`DEFAULT_SEED`), so the same call gives the
same answer on every run and platform. :meth:`NumericIK.solve_batch` solves many targets over
threads with the GIL released; pose ``i`` draws from stream ``i`` of one seed, so its answer does
not depend on the thread count (unless a time budget, which each pose has for itself, cuts its
solve short).
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit import _core
from armkit._deprecation import deprecated_property, renamed_argument
from armkit._params import (
    float_array,
    non_negative_float,
    positive_float,
    thread_count,
    whole_number,
)
from armkit.chain import Chain, as_chain
from armkit.errors import InputError

if TYPE_CHECKING:
    from armkit.robot import Robot

__all__ = ["DEFAULT_SEED", "IKResult", "IKResultBatch", "NumericIK", "numeric_ik", "wrap_into_limits"]

#: Seed of the random restarts unless ``rng`` says otherwise: two identical calls give the same
#: answer (``rng=None`` draws fresh entropy instead).
DEFAULT_SEED = 0


@dataclass(frozen=True)
class IKResult:
    """The outcome of a numeric IK solve.

    Attributes
    ----------
    q : ndarray, shape (n,)
        The best configuration found [rad or m]; inside the joint limits unless the solver
        was called with ``within_limits=False``.
    success : bool
        Whether the masked position and orientation errors are within the tolerances.
    iterations : int
        Levenberg-Marquardt iterations over all attempts.
    restarts : int
        Attempts started from a random configuration after the first one.
    position_error : float
        Distance [m] between the target and the tool position at ``q`` (masked axes only).
    orientation_error : float
        Angle [rad] of the orientation error at ``q`` (masked axes only).
    """

    q: NDArray[np.float64]
    success: bool
    iterations: int
    restarts: int
    position_error: float
    orientation_error: float


@dataclass(frozen=True)
class IKResultBatch:
    """The outcomes of :meth:`NumericIK.solve_batch` for ``N`` targets: the fields of
    :class:`IKResult` as arrays, one entry per target; ``result[i]`` is target ``i``'s
    :class:`IKResult`.

    Attributes
    ----------
    q : ndarray, shape (N, n)
        Best configuration per target [rad or m].
    success : ndarray of bool, shape (N,)
    iterations, restarts : ndarray of int64, shape (N,)
    position_error, orientation_error : ndarray, shape (N,)
        [m] and [rad], masked axes only.
    """

    q: NDArray[np.float64]
    success: NDArray[np.bool_]
    iterations: NDArray[np.int64]
    restarts: NDArray[np.int64]
    position_error: NDArray[np.float64]
    orientation_error: NDArray[np.float64]

    def __len__(self) -> int:
        return len(self.success)

    def __getitem__(self, i: int) -> IKResult:
        return IKResult(self.q[i], bool(self.success[i]), int(self.iterations[i]), int(self.restarts[i]),
                        float(self.position_error[i]), float(self.orientation_error[i]))


def _task_rows(mask: ArrayLike | None) -> list[int]:
    """The rows of the pose error ``x y z rx ry rz`` that the 0/1 ``mask`` keeps."""
    if mask is None:
        return [0, 1, 2, 3, 4, 5]
    m = np.asarray(mask, dtype=float)
    if m.shape != (6,) or not np.all((m == 0) | (m == 1)) or not m.any():
        raise InputError(f"mask: expected 6 values of 0 or 1 (x y z rx ry rz, at least one 1), "
                         f"got {np.asarray(mask).tolist()}")
    return np.flatnonzero(m).tolist()


def _check_target(T_base_tool: ArrayLike) -> NDArray[np.float64]:
    T = float_array(T_base_tool, "T_base_tool", "a 4x4 transform")
    if T.shape != (4, 4) or not math.isfinite(T.sum()):
        raise InputError(f"T_base_tool: expected a finite 4x4 transform, got {T.tolist()}")
    return T


def _check_seed(q0: ArrayLike, n: int) -> NDArray[np.float64]:
    q = float_array(q0, "q0", f"{n} finite joint values")
    if q.shape != (n,) or not math.isfinite(q.sum()):
        raise InputError(f"q0: expected {n} finite joint values, got {q.tolist()}")
    return q


def _shape_or_values(values: NDArray[np.float64], shaped: bool) -> str:
    """What is wrong with an array of the expected shape (its values) or of another one."""
    return "non-finite values" if shaped else f"an array of shape {values.shape}"


def _seed(rng: np.random.Generator | int | None) -> int:
    """The 64-bit seed of one solve's restart seeds: an int ``rng`` itself, one draw from a
    Generator (or whatever ``np.random.default_rng`` takes), fresh entropy for ``None``."""
    if type(rng) is int and 0 <= rng < 2**64:
        return rng
    if rng is None:
        return int.from_bytes(os.urandom(8), "little")
    if isinstance(rng, (int, np.integer)) and not isinstance(rng, bool):
        if 0 <= rng < 2**64:
            return int(rng)
        raise InputError(f"rng: expected a seed in [0, 2**64), a numpy Generator or None, got {rng}")
    try:
        return int(np.random.default_rng(rng).integers(2**63))
    except (TypeError, ValueError) as exc:
        raise InputError(f"rng: expected a seed in [0, 2**64), a numpy Generator or None, "
                         f"got {rng!r}") from exc


def wrap_into_limits(robot: Robot | Chain, q: ArrayLike, reference: ArrayLike) -> NDArray[np.float64]:
    """Shift revolute angles ``(..., n)`` by multiples of ``2 pi`` into the joint limits.

    Among several shifts that fit (limits wider than ``2 pi``) the one closest to
    ``reference`` (broadcast against ``q``) is taken; an angle that fits no shift is moved
    as close to ``reference`` as whole turns allow. Prismatic values are left alone.

    Examples
    --------
    >>> import armkit
    >>> panda = armkit.load("panda")   # joint 6 in [-0.0175, 3.7525]
    >>> float(wrap_into_limits(panda, [0, 0, 0, -1, 0, -3.0, 0], 0.0)[5].round(4))
    3.2832
    """
    chain = as_chain(robot)
    q = np.asarray(q, dtype=np.float64)
    reference = np.asarray(reference, dtype=np.float64)
    try:
        shape = np.broadcast_shapes(q.shape, reference.shape)
    except ValueError:
        shape = ()
    if shape[-1:] != (chain.n,):
        raise InputError(f"wrap_into_limits: expected q (..., {chain.n}) and a reference broadcasting "
                         f"to it, got shapes {q.shape} and {reference.shape}")
    flat = (-1, chain.n)
    q = np.ascontiguousarray(np.broadcast_to(q, shape)).reshape(flat)
    reference = np.ascontiguousarray(np.broadcast_to(reference, shape)).reshape(flat)
    out = np.empty(q.shape)
    _core.wrap_into_limits(chain._core, q, reference, out)
    return out.reshape(shape)


class NumericIK:
    """Numeric IK of one chain, reusable for many targets (see :func:`numeric_ik`).

    Holds the chain and settings in the compiled core (an ``_core.NumericSolver``), so that a
    loop over targets pays for them once; :meth:`solve_batch` solves many targets at once.
    Parameters are those of :func:`numeric_ik`; ``within_limits`` is kept as an attribute
    (``respect_limits``, its old name, still reads it, with a warning).

    Examples
    --------
    >>> import armkit
    >>> panda = armkit.load("panda")
    >>> solver = NumericIK(panda, position_tolerance=1e-10)
    >>> T = panda.fk([0.1, -0.3, 0.2, -2.0, 0.1, 1.8, 0.5])
    >>> result = solver.solve(T, rng=0)
    >>> result.success, bool(result.position_error < 1e-10), bool(panda.within_limits(result.q))
    (True, True, True)
    """

    def __init__(self, robot: Robot | Chain, *, position_tolerance: float = 1e-9,
                 orientation_tolerance: float = 1e-9, mask: ArrayLike | None = None,
                 damping_gain: float = 0.1, damping: float = 1e-9, max_iterations: int = 30,
                 max_restarts: int = 100, time_budget: float | None = None, within_limits: bool = True,
                 respect_limits: bool | None = None) -> None:
        within_limits = renamed_argument("NumericIK", "respect_limits", "within_limits", respect_limits,
                                         within_limits, True)
        tolerances = (positive_float(position_tolerance, "position_tolerance"),
                      positive_float(orientation_tolerance, "orientation_tolerance"))
        damping_terms = (non_negative_float(damping_gain, "damping_gain"),
                         non_negative_float(damping, "damping"))
        self.max_iterations = whole_number(max_iterations, "max_iterations", minimum=1)
        self.max_restarts = whole_number(max_restarts, "max_restarts", minimum=0)
        self.time_budget = (None if time_budget is None
                            else non_negative_float(time_budget, "time_budget", infinite=True))
        self.chain = chain = as_chain(robot)
        self.rows = _task_rows(mask)
        self.within_limits = bool(within_limits)
        self._solver = _core.NumericSolver(chain._core, self.rows, *tolerances, *damping_terms,
                                           self.max_iterations, self.max_restarts,
                                           math.inf if self.time_budget is None else self.time_budget,
                                           self.within_limits)

    respect_limits = deprecated_property("respect_limits", "within_limits")

    def solve(self, T_base_tool: NDArray[np.float64], q0: ArrayLike | None = None,
              rng: np.random.Generator | int | None = DEFAULT_SEED) -> IKResult:
        """Solve ``fk(q) = T_base_tool`` ``(4, 4)`` from ``q0`` ``(n,)``; see :func:`numeric_ik`.

        Raises
        ------
        InputError
            If ``T_base_tool`` is not a finite 4x4 array, ``q0`` not ``n`` finite values or
            ``rng`` not a seed, Generator or None.
        """
        n = self.chain.n
        T = float_array(T_base_tool, "T_base_tool", "a 4x4 transform")
        seed_q = None if q0 is None else float_array(q0, "q0", f"{n} finite joint values")
        if T.shape != (4, 4):
            _check_target(T)
        if seed_q is not None and seed_q.shape != (n,):
            _check_seed(seed_q, n)
        q = np.empty(n)
        status, *found = self._solver.solve(T, seed_q, _seed(rng), q)
        if status == _core.NUMERIC_TARGET_NOT_FINITE:
            _check_target(T)  # raises, naming the values
        elif status == _core.NUMERIC_SEED_NOT_FINITE:
            _check_seed(seed_q, n)
        return IKResult(q, *found)

    def solve_batch(self, T_base_tool: ArrayLike, q0: ArrayLike | None = None,
                    rng: np.random.Generator | int | None = DEFAULT_SEED,
                    threads: int | None = None) -> IKResultBatch:
        """Solve ``N`` targets ``T_base_tool`` ``(N, 4, 4)`` at once, over threads.

        Parameters
        ----------
        T_base_tool : array_like, shape (N, 4, 4)
            Target tool poses [m], assumed rigid.
        q0 : array_like, shape (N, n) or (n,), optional
            First seed per target [rad or m]; default the middle of the limits.
        rng : numpy Generator or int, optional
            One seed for the whole batch: target ``i`` draws its restart seeds from stream
            ``i`` of it (target 0 from the stream :meth:`solve` uses with the same ``rng``);
            default :data:`DEFAULT_SEED`, ``None`` for fresh entropy.
        threads : int, optional
            Threads to spread the targets over: ``None`` (default) all cores, else 1 to
            :data:`armkit._params.MAX_THREADS`.

        Returns
        -------
        IKResultBatch
            One entry per target. Identical whatever ``threads`` is, except for targets whose
            solve ran out of a ``time_budget``, if one was given (each target has the full budget
            for itself; a solve that stops on time rather than on ``max_restarts`` depends on the
            machine's load).

        Raises
        ------
        InputError
            If ``T_base_tool`` is not finite ``(N, 4, 4)``, ``q0`` not finite ``(N, n)`` or
            ``(n,)``, or ``threads`` not a thread count.

        Examples
        --------
        >>> import armkit
        >>> panda = armkit.load("panda")
        >>> T = panda.fk(panda.random_q(20, rng=1))
        >>> result = NumericIK(panda).solve_batch(T, rng=0)
        >>> bool(result.success.all()), result.q.shape
        (True, (20, 7))
        """
        n = self.chain.n
        T = float_array(T_base_tool, "T_base_tool", "transforms (N, 4, 4)")
        if T.ndim != 3 or T.shape[1:] != (4, 4) or not math.isfinite(T.sum()):
            raise InputError("T_base_tool: expected finite transforms (N, 4, 4), got "
                             + _shape_or_values(T, T.ndim == 3 and T.shape[1:] == (4, 4)))
        N = T.shape[0]
        seeds = None
        if q0 is not None:
            seeds = float_array(q0, "q0", f"joint values (N, {n})")
            if seeds.shape == (n,):
                seeds = np.ascontiguousarray(np.broadcast_to(seeds, (N, n)))
            if seeds.shape != (N, n) or not math.isfinite(seeds.sum()):
                raise InputError(f"q0: expected finite joint values ({N}, {n}) or ({n},), got "
                                 + _shape_or_values(seeds, seeds.shape == (N, n)))
        threads = thread_count(threads)
        q, success = np.empty((N, n)), np.empty(N, dtype=bool)
        iterations, restarts = np.empty(N, dtype=np.int64), np.empty(N, dtype=np.int64)
        position, orientation = np.empty(N), np.empty(N)
        self._solver.solve_batch(T, seeds, _seed(rng), threads, q, success, iterations, restarts,
                                 position, orientation)
        return IKResultBatch(q, success, iterations, restarts, position, orientation)


def numeric_ik(robot: Robot | Chain, T_base_tool: NDArray[np.float64], *, q0: ArrayLike | None = None,
               position_tolerance: float = 1e-9, orientation_tolerance: float = 1e-9,
               mask: ArrayLike | None = None, damping_gain: float = 0.1, damping: float = 1e-9,
               max_iterations: int = 30, max_restarts: int = 100, time_budget: float | None = None,
               within_limits: bool = True, rng: np.random.Generator | int | None = DEFAULT_SEED,
               respect_limits: bool | None = None) -> IKResult:
    """Solve ``fk(q) = T_base_tool`` numerically inside the joint limits.

    Levenberg-Marquardt from ``q0`` (moved into the limits); an attempt that stops
    improving (error not halved in 3 steps) or reaches ``max_iterations`` steps is
    restarted from a uniform random configuration inside the limits. The joint limits
    are bounds of every step (see the module notes), so every answer is inside them.
    For many targets of one chain, build a :class:`NumericIK` once and call its
    ``solve``.

    Parameters
    ----------
    robot : Robot or Chain
        The arm (a :class:`~armkit.chain.Chain` is accepted too, see :func:`armkit.chain.as_chain`).
    T_base_tool : ndarray, shape (4, 4)
        Target tool pose [m], assumed rigid (see :func:`armkit.spatial.check_transform`).
    q0 : array_like, shape (n,), optional
        First seed [rad or m]; default the middle of the limits.
    position_tolerance, orientation_tolerance : float
        Success when the masked position error [m] and orientation error [rad] are below.
    mask : array_like, shape (6,), optional
        0/1 weights of the error components ``x y z rx ry rz`` (base frame), e.g.
        ``[1, 1, 1, 0, 0, 0]`` for a position-only target. Default all ones.
    damping_gain, damping : float
        The Levenberg-Marquardt damping is ``damping_gain * E + damping``.
    max_iterations : int
        Steps per attempt at most.
    max_restarts : int
        Random seeds drawn after the first attempt at most.
    time_budget : float, optional
        Wall-clock budget [s], checked between attempts; default none (``max_restarts`` bounds
        the work, and the answer does not depend on the machine's speed).
    within_limits : bool
        Keep every step inside the joint limits (default). ``False`` accepts any solution,
        e.g. to refine a known one. The same word as :meth:`armkit.Robot.ik`'s.
    rng : numpy Generator or int, optional
        Source of the random restart seeds: an int in ``[0, 2**64)`` is the seed itself, a
        Generator gives one draw per solve, ``None`` fresh entropy; the same ``rng`` gives the
        same answer (except a solve cut short by a ``time_budget``). Default
        :data:`DEFAULT_SEED`: the same call, the same answer.
    respect_limits : bool, optional
        Deprecated name of ``within_limits``; warns.

    Returns
    -------
    IKResult
        The solution, or (``success=False``) the configuration with the smallest error
        seen (inside the limits when ``within_limits``).

    Examples
    --------
    >>> import armkit
    >>> panda = armkit.load("panda")
    >>> T = panda.fk([0.1, -0.3, 0.2, -2.0, 0.1, 1.8, 0.5])
    >>> result = numeric_ik(panda, T, rng=0)
    >>> result.success, bool(result.position_error < 1e-9)
    (True, True)
    """
    within_limits = renamed_argument("numeric_ik", "respect_limits", "within_limits", respect_limits,
                                     within_limits, True)
    solver = NumericIK(robot, position_tolerance=position_tolerance,
                       orientation_tolerance=orientation_tolerance, mask=mask,
                       damping_gain=damping_gain, damping=damping, max_iterations=max_iterations,
                       max_restarts=max_restarts, time_budget=time_budget, within_limits=within_limits)
    return solver.solve(T_base_tool, q0, rng)

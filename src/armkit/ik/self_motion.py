"""Every IK solution of a redundant arm along one free joint: the self-motion of a 7R arm.

With one joint held at a value, a 7-joint arm is a 6-joint arm (:meth:`armkit.Robot.lock`)
whose every solution the closed form lists (a Pieper class, or the general 6R or 5R1P solver). Doing
that at many values of the free joint samples each branch of the self-motion manifold; the
samples are joined into branches by continuity (each solution continues the branch whose
last sample is nearest, within a bound that grows with the step of the free joint).

Example
-------
>>> import numpy as np, armkit
>>> panda = armkit.load("panda")
>>> q = np.array([0.3, -0.4, 0.2, -2.0, 0.1, 1.8, 0.6])
>>> motion = armkit.self_motion(panda, panda.fk(q), free_joint=2, samples=9)
>>> motion.q.shape[1:], bool(np.isfinite(motion.q).any())
((9, 7), True)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from numbers import Real
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit.errors import InputError, UnreachableError

if TYPE_CHECKING:
    from armkit.robot import Robot

__all__ = ["SelfMotion", "free_joint_index", "ik_at_free_joint", "largest_joint_gap", "self_motion"]

#: A solution continues a branch when it lies within this many times the free joint's step
#: of the branch's last sample (every joint, modulo 2 pi): along a smooth branch the other
#: joints move in proportion to the free one, faster only near a singularity of the branch.
_BRANCH_REACH = 20.0


@dataclass(frozen=True)
class SelfMotion:
    """The self-motion of a redundant arm at one pose, sampled along its free joint.

    Attributes
    ----------
    free_joint : int
        Index of the free joint (0-based).
    values : ndarray (N,)
        The free joint's values [rad or m].
    q : ndarray (branches, N, n)
        Every branch's configuration at each value [rad or m]; NaN where the branch has no
        solution (the pose is out of reach there, or the branch has not begun or has ended).
    within_limits : ndarray of bool (branches, N)
        The configuration is inside every joint limit (False where NaN).
    """

    free_joint: int
    values: NDArray[np.float64]
    q: NDArray[np.float64]
    within_limits: NDArray[np.bool_]

    def __repr__(self) -> str:
        found = np.isfinite(self.q).all(axis=-1)
        return (f"SelfMotion({len(self.q)} branches x {len(self.values)} values of joint {self.free_joint} "
                f"from {self.values[0]:.4g} to {self.values[-1]:.4g}; {int(found.sum())} solutions, "
                f"{int(self.within_limits.sum())} inside the limits)")

    def plot(self, path: str | None = None, *, joint_names: list[str] | None = None, overwrite: bool = False):
        """Each joint against the free joint, one line per branch [deg]; saved to ``path``
        (PNG, SVG or PDF; never over an existing file unless ``overwrite``) if given.

        Returns the matplotlib figure.
        """
        from armkit.plots import Figure, save_figure  # first: without matplotlib, armkit's one-line error

        n = self.q.shape[-1]
        names = joint_names or [f"q{j + 1}" for j in range(n)]
        shown = [j for j in range(n) if j != self.free_joint]
        figure = Figure(figsize=(7, 1.4 * len(shown) + 0.8), layout="constrained")
        axes = figure.subplots(len(shown), 1, sharex=True, squeeze=False)[:, 0]
        from matplotlib import colormaps  # there: armkit.plots imported it

        colours = colormaps["tab20"].colors
        for b, branch in enumerate(self.q):
            colour = colours[b % len(colours)]
            for j, ax in zip(shown, axes, strict=True):
                y = np.degrees(branch[:, j])
                y[1:][np.abs(np.diff(y)) > 180.0] = np.nan  # no line across the +-180 deg seam
                inside = np.where(self.within_limits[b], y, np.nan)
                ax.plot(np.degrees(self.values), y, lw=0.8, ls=":", color=colour)  # outside the limits
                ax.plot(np.degrees(self.values), inside, lw=1.6, color=colour, label=f"branch {b + 1}")
        for j, ax in zip(shown, axes, strict=True):
            ax.set_ylabel(f"{names[j]} [deg]")
            ax.grid(alpha=0.3)
        axes[-1].set_xlabel(f"free joint {names[self.free_joint]} [deg]")
        axes[0].set_title(f"Self-motion: {len(self.q)} branches (solid: inside every limit, dotted: outside)")
        if 0 < len(self.q) <= 20:
            figure.legend(*axes[0].get_legend_handles_labels(), fontsize=7, loc="outside right center")
        if path is not None:
            save_figure(figure, path, overwrite)
        return figure


def free_joint_index(robot: Robot, free_joint: int | str) -> int:
    """The 0-based index of ``free_joint`` (an index or a joint name), checked."""
    if isinstance(free_joint, str) and free_joint in robot.joint_names:
        return robot.joint_names.index(free_joint)
    whole = isinstance(free_joint, int | np.integer) and not isinstance(free_joint, bool)
    if whole and 0 <= free_joint < robot.n:
        return int(free_joint)
    raise InputError(f"free_joint {free_joint!r}: expected a joint name ({', '.join(robot.joint_names)}) "
                     f"or an index 0 to {robot.n - 1}")


def ik_at_free_joint(robot: Robot, T_base_tool: ArrayLike, free_joint: int | str, free_value: float | None, *,
                     all_solutions: bool = False, near: ArrayLike | None = None, within_limits: bool = True,
                     **options) -> NDArray[np.float64] | list[NDArray[np.float64]]:
    """IK of ``robot`` with joint ``free_joint`` held at ``free_value`` (default: ``near``'s
    value of it, or 0), the other joints solved exactly by the closed form of
    :meth:`armkit.Robot.lock` (what ``robot.ik(..., free_joint=J, free_value=v)`` calls).

    Returns the whole robot's configurations, shaped as :meth:`armkit.Robot.ik` returns them.
    """
    index = free_joint_index(robot, free_joint)
    if robot.n < 7:
        raise InputError(f"free_joint: holds a joint of a redundant arm (7 or more joints); this arm has "
                         f"{robot.n}, so solve it whole (robot.ik without free_joint)")
    near_q = None if near is None else robot.check_q(near, "near")
    if free_value is None and near_q is not None and near_q.ndim > 1:
        # one near per pose: each pose holds the free joint at its own near's value
        T = np.asarray(T_base_tool, dtype=float)
        if T.shape[:-2] != near_q.shape[:-1]:
            raise InputError(f"near: shape {near_q.shape} for target poses of shape {T.shape}; expected "
                             f"{(*T.shape[:-2], robot.n)}, one per pose")
        each = [ik_at_free_joint(robot, Ti, index, None, all_solutions=all_solutions, near=qi,
                                 within_limits=within_limits, **options)
                for Ti, qi in zip(T.reshape(-1, 4, 4), near_q.reshape(-1, robot.n), strict=True)]
        return each if all_solutions else np.stack(each).reshape(near_q.shape)
    if free_value is None:
        free_value = 0.0 if near_q is None else float(np.reshape(near_q, (-1, robot.n))[0, index])
    unit = "m" if robot.chain.prismatic[index] else "rad"
    if isinstance(free_value, bool) or not isinstance(free_value, Real) or not math.isfinite(free_value):
        raise InputError(f"free_value {free_value!r}: expected a finite value of "
                         f"{robot.joint_names[index]} [{unit}]", parameter="free_value", value=free_value)
    arm = robot.lock({index: free_value})
    near_arm = None if near_q is None else arm.reduced_q(near_q)
    q = arm.ik(T_base_tool, all_solutions=all_solutions, near=near_arm, within_limits=within_limits,
               **options)
    if isinstance(q, list):
        return [arm.full_q(x) if len(x) else np.empty((0, robot.n)) for x in q]
    return arm.full_q(q) if q.size else np.empty((*q.shape[:-1], robot.n))


def self_motion(robot: Robot, T_base_tool: ArrayLike, *, free_joint: int | str, samples: int = 64,
                values: ArrayLike | None = None) -> SelfMotion:
    """Every branch of ``robot``'s solutions at one pose, sampled along ``free_joint``.

    Parameters
    ----------
    robot : Robot
        A 7-joint arm (any arm with one joint more than the closed form needs).
    T_base_tool : array_like (4, 4)
        Target tool pose [m].
    free_joint : int or str
        The joint swept (0-based index or name).
    samples : int
        Number of values, spread evenly over the free joint's limits (``[-pi, pi]`` for an
        unbounded revolute joint); ignored when ``values`` is given.
    values : array_like (N,), optional
        The free joint's values [rad or m], in order.

    Returns
    -------
    SelfMotion
        ``q`` of shape ``(branches, N, n)``, NaN where a branch does not exist.

    Raises
    ------
    InputError
        For an unknown joint, fewer than two samples, or values outside the joint's limits.
    """
    index = free_joint_index(robot, free_joint)
    if values is None:
        whole = isinstance(samples, int | np.integer) and not isinstance(samples, bool)
        if not whole or not 2 <= samples <= 100_000:
            raise InputError(f"samples: expected a whole number from 2 to 100000, got {samples!r}")
        low, high = robot.limits[index]
        unbounded = np.pi if not robot.chain.prismatic[index] else 1.0
        low, high = (low if np.isfinite(low) else -unbounded), (high if np.isfinite(high) else unbounded)
        values = np.linspace(low, high, int(samples))
    values = np.asarray(values, dtype=float)
    if values.ndim != 1 or len(values) < 2 or not np.isfinite(values).all():
        raise InputError(f"values: expected at least two finite values of the free joint, got {values!r}")
    step = float(np.abs(np.diff(values)).max())
    revolute = ~robot.chain.prismatic
    branches: list[list[NDArray[np.float64] | None]] = []
    for k, value in enumerate(values):
        try:
            found = list(ik_at_free_joint(robot, T_base_tool, index, float(value), all_solutions=True,
                                          within_limits=False, turn_copies=False))
        except UnreachableError:  # out of reach at this value: no branch has a sample here
            found = []
        for branch in branches:  # each open branch takes its nearest solution, if near enough
            last = branch[k - 1] if k else None
            if last is None or not found:
                branch.append(None)
                continue
            gap = largest_joint_gap(np.array(found), last, revolute)
            best = int(np.argmin(gap))
            branch.append(found.pop(best) if gap[best] <= _BRANCH_REACH * step + 1e-9 else None)
        for q in found:  # the others start branches of their own
            branches.append([None] * k + [q])
    q = np.full((len(branches), len(values), robot.n), np.nan)
    for b, branch in enumerate(branches):
        for k, sample in enumerate(branch):
            if sample is not None:
                q[b, k] = sample
    inside = np.zeros(q.shape[:2], dtype=bool)
    finite = np.isfinite(q).all(axis=-1)
    inside[finite] = robot.chain.within_limits(q[finite])
    return SelfMotion(index, values, q, inside)


def largest_joint_gap(q: ArrayLike, reference: ArrayLike, revolute: ArrayLike) -> NDArray[np.float64]:
    """The largest joint difference of each configuration ``q`` ``(..., n)`` from ``reference``
    (broadcast against it) [rad or m], the joints flagged ``revolute`` ``(n,)`` modulo a turn;
    shape ``(...)``.

    Example
    -------
    >>> float(largest_joint_gap([3.1, 0.5], [-3.1, 0.2], [True, False]))   # 2 pi - 6.2 and 0.3
    0.3
    """
    d = np.asarray(q, dtype=float) - np.asarray(reference, dtype=float)
    revolute = np.asarray(revolute, dtype=bool)
    d = np.where(revolute, np.angle(np.exp(1j * d)), d)
    return np.abs(d).max(axis=-1)

"""The :class:`Robot`: a named chain with its DH description and the user-facing methods."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit import kinematics
from armkit.chain import LIMIT_TOLERANCE, Chain, DHConvention, DHRow, chain_from_dh
from armkit.errors import InputError, JointLimitError
from armkit.spatial.transforms import check_transform, pose_from_transform

__all__ = ["DHDescription", "Robot"]


@dataclass(frozen=True)
class DHDescription:
    """The DH table a robot was written in, kept for display and export.

    ``length_unit`` and ``angle_unit`` are the units the user wrote; ``rows`` are in SI.
    """

    convention: DHConvention
    rows: tuple[DHRow, ...]
    base_rows: tuple[DHRow, ...] = ()
    tool_rows: tuple[DHRow, ...] = ()
    length_unit: str = "m"
    angle_unit: str = "rad"


class Robot:
    """A serial arm: FK, Jacobians, limits (and IK, motion, simulation in later modules).

    Parameters
    ----------
    chain : Chain
        The kinematic chain (see :mod:`armkit.chain`).
    name : str
    dh : DHDescription, optional
        The DH table the chain was built from, if any.

    Examples
    --------
    >>> robot = Robot.from_dh([DHRow(0, 0, 0, 0), DHRow(0, 1.0, 0, 0)], "modified", name="2R")
    >>> robot.fk([0.0, 0.0])[:3, 3]
    array([1., 0., 0.])
    """

    def __init__(self, chain: Chain, name: str = "robot", dh: DHDescription | None = None,
                 source: str | None = None, description: str = "") -> None:
        self.chain = chain
        self.name = name
        self.description = description
        self.dh = dh
        self.source = source

    @classmethod
    def from_dh(cls, rows: Sequence[DHRow], convention: DHConvention, *, name: str = "robot",
                limits: Sequence[tuple[float, float]] | None = None,
                max_velocity: Sequence[float | None] | None = None,
                max_acceleration: Sequence[float | None] | None = None,
                base_rows: Sequence[DHRow] = (), tool_rows: Sequence[DHRow] = (),
                length_unit: str = "m", angle_unit: str = "rad",
                names: Sequence[str] | None = None) -> Robot:
        """Build a robot from DH rows in SI units (see :func:`armkit.chain.chain_from_dh`)."""
        chain = chain_from_dh(rows, convention, limits=limits, max_velocity=max_velocity,
                              max_acceleration=max_acceleration, base_rows=base_rows,
                              tool_rows=tool_rows, names=names)
        dh = DHDescription(convention, tuple(rows), tuple(base_rows), tuple(tool_rows),
                           length_unit, angle_unit)
        return cls(chain, name=name, dh=dh)

    def __repr__(self) -> str:
        kinds = "".join("P" if p else "R" for p in self.chain.prismatic)
        return f"Robot({self.name!r}, {self.n} joint{'s' * (self.n != 1)} {kinds})"

    # ----------------------------------------------------------------- properties
    @property
    def n(self) -> int:
        """Number of joints."""
        return self.chain.n

    @property
    def joint_names(self) -> list[str]:
        return [j.name for j in self.chain.joints]

    @property
    def joint_types(self) -> list[str]:
        """``"revolute"`` or ``"prismatic"`` per joint."""
        return [j.kind for j in self.chain.joints]

    @property
    def limits(self) -> NDArray[np.float64]:
        """``(n, 2)`` lower/upper position limits [rad or m]."""
        return np.stack([self.chain.lower, self.chain.upper], axis=1)

    @property
    def home(self) -> NDArray[np.float64]:
        """``(n,)`` the zero configuration clipped into the position limits [rad or m].

        >>> import armkit
        >>> armkit.load("stanford").home.tolist()   # prismatic d3 starts at 0.3048 m
        [0.0, 0.0, 0.3048, 0.0, 0.0, 0.0]
        """
        return np.clip(np.zeros(self.n), self.chain.lower, self.chain.upper)

    @property
    def max_velocity(self) -> NDArray[np.float64]:
        """``(n,)`` velocity limits [rad/s or m/s]; ``inf`` where none was given."""
        return np.array([np.inf if j.max_velocity is None else j.max_velocity
                         for j in self.chain.joints])

    @property
    def max_acceleration(self) -> NDArray[np.float64]:
        """``(n,)`` acceleration limits [rad/s^2 or m/s^2]; ``inf`` where none was given."""
        return np.array([np.inf if j.max_acceleration is None else j.max_acceleration
                         for j in self.chain.joints])

    # ----------------------------------------------------------------- checks
    def check_q(self, q: ArrayLike, name: str = "q") -> NDArray[np.float64]:
        """Return ``q`` as float64 ``(..., n)``, or raise :class:`InputError` saying why not."""
        try:
            q = np.asarray(q, dtype=float)
        except (TypeError, ValueError) as exc:
            raise InputError(f"{name}: expected {self.n} numbers, got {q!r}") from exc
        if q.ndim == 0 or q.shape[-1] != self.n:
            got = {0: "a scalar", 1: f"{q.size}"}.get(q.ndim, f"an array of shape {q.shape}")
            raise InputError(f"{name}: expected {self.n} joint values, got {got} "
                             f"({self.name} has {self.n} joints)")
        if not np.all(np.isfinite(q)):
            raise InputError(f"{name}: contains NaN or infinite values: {q.tolist()}")
        return q

    def within_limits(self, q: ArrayLike) -> NDArray[np.bool_]:
        """Whether each configuration ``(..., n)`` lies inside all position limits, ``(...)``."""
        return self.chain.within_limits(self.check_q(q))

    def limit_violations(self, q: ArrayLike, degrees: bool = False) -> list[str]:
        """One message per joint value of a single configuration outside its limits.

        With ``degrees`` the messages show revolute values and limits in degrees.
        """
        q = self.check_q(q)
        if q.ndim != 1:
            raise InputError(f"q: expected one configuration of {self.n} values, got {q.shape}")
        messages = []
        for joint, value in zip(self.chain.joints, q, strict=True):
            if not joint.lower - LIMIT_TOLERANCE <= value <= joint.upper + LIMIT_TOLERANCE:
                scale, unit = ((180 / np.pi, " deg") if degrees and joint.kind == "revolute"
                               else (1.0, " rad" if joint.kind == "revolute" else " m"))
                messages.append(f"joint {joint.name} = {value * scale:.6g}{unit} is outside its limits "
                                f"[{joint.lower * scale:.6g}, {joint.upper * scale:.6g}]{unit}")
        return messages

    def check_limits(self, q: ArrayLike, degrees: bool = False) -> NDArray[np.float64]:
        """Return ``q`` if every value is inside its limits, else raise :class:`JointLimitError`."""
        violations = self.limit_violations(q, degrees)
        if violations:
            raise JointLimitError("; ".join(violations))
        return self.check_q(q)

    # ----------------------------------------------------------------- kinematics
    def fk(self, q: ArrayLike) -> NDArray[np.float64]:
        """Tool pose ``T_base_tool`` [m], ``(4, 4)`` for ``q`` ``(n,)``, ``(N, 4, 4)`` for ``(N, n)``.

        Examples
        --------
        >>> import armkit
        >>> armkit.load("probot-anno").fk([0, 0, 0, 0, 0, 0])[:3, 3].round(4) + 0.0
        array([0.2289, 0.    , 0.454 ])
        """
        return kinematics._fk(self.chain, self.check_q(q))  # checked once, here

    def pose(self, q: ArrayLike, convention: str = "xyz-fixed",
             degrees: bool = False) -> NDArray[np.float64]:
        """Tool pose as ``(..., 6)``: position [m] then three angles in ``convention``."""
        return pose_from_transform(self.fk(q), convention, degrees)

    def link_frames(self, q: ArrayLike) -> NDArray[np.float64]:
        """Base, every DH link frame and tool: ``(..., n + 2, 4, 4)``."""
        return kinematics._link_frames(self.chain, self.check_q(q))

    def jacobian(self, q: ArrayLike, frame: str = "base") -> NDArray[np.float64]:
        """Geometric Jacobian ``(..., 6, n)``, rows ``[v; w]``, in the ``"base"`` or ``"tool"`` frame."""
        return kinematics._geometric_jacobian(self.chain, self.check_q(q), frame)

    def analytic_jacobian(self, q: ArrayLike, convention: str = "xyz-fixed") -> NDArray[np.float64]:
        """Analytic Jacobian ``(..., 6, n)``: position rates over angle rates in ``convention``."""
        return kinematics.analytic_jacobian(self.chain, self.check_q(q), convention)

    def manipulability(self, q: ArrayLike) -> NDArray[np.float64]:
        """Yoshikawa manipulability ``(...)``; zero at singularities."""
        return kinematics.manipulability(self.chain, self.check_q(q))

    def singular_values(self, q: ArrayLike) -> NDArray[np.float64]:
        """Jacobian singular values ``(..., min(6, n))``; the last is the singularity measure."""
        return kinematics.singular_values(self.chain, self.check_q(q))

    def ik(self, T_base_tool: ArrayLike, all: bool = False, near: ArrayLike | None = None,
           within_limits: bool = True, **options) -> NDArray[np.float64] | list[NDArray[np.float64]]:
        """Inverse kinematics: every closed-form solution, or the one closest to ``near``.

        Closed form where the chain's geometry has one, numeric (seeded from ``near``)
        otherwise; every answer reproduces the target to 1e-9 m and 1e-9 rad. See
        :func:`armkit.ik.solve.ik` for the options, and :func:`armkit.ik.ik_solutions`
        for every solution with per-solution flags (limits, singular family, residual).

        Parameters
        ----------
        T_base_tool : array_like, shape (4, 4) or (N, 4, 4)
            Target tool pose(s) [m].
        all : bool
            ``(k, n)``: every solution, nearest to ``near`` first (closed form only).
        near : array_like, shape (n,) or (N, n), optional
            Reference configuration [rad or m]; default zeros.
        within_limits : bool
            Only solutions inside the joint limits (default).

        Returns
        -------
        ndarray
            ``(n,)`` or ``(N, n)``; with ``all=True`` ``(k, n)`` (a list for ``N`` poses).
            An empty batch ``(0, 4, 4)`` gives ``(0, n)`` (``[]`` with ``all=True``).

        Raises
        ------
        InputError
            If a target is not a rigid transform, or ``near`` is not ``n`` finite joint values
            (per pose, or one set for all).

        Examples
        --------
        >>> import armkit
        >>> robot = armkit.load("probot-anno")
        >>> T = robot.fk([0.927, -0.687, -0.396, 0, 1.083, 0.927])
        >>> robot.ik(T, all=True).shape
        (4, 6)
        >>> robot.ik(T, near=[1, -1, 0, 0, 1, 1]).round(3)
        array([ 0.927, -0.687, -0.396,  0.   ,  1.083,  0.927])
        """
        from armkit.ik.solve import ik  # here, not at the top: armkit.ik imports this module

        T = check_transform(T_base_tool, "target pose")
        if near is not None:
            near = self.check_q(near, "near")
            if near.ndim > 1 and near.shape[:-1] != T.shape[:-2]:
                poses = "one target pose" if T.ndim == 2 else f"target poses of shape {T.shape}"
                raise InputError(f"near: shape {near.shape} for {poses}; expected ({self.n},), one set of "
                                 f"joint values for every pose, or {(*T.shape[:-2], self.n)}, one per pose")
        if T.ndim > 2 and T.shape[0] == 0:
            return [] if all else np.empty((0, self.n))
        return ik(self.chain, T, all=all, near=near, within_limits=within_limits, **options)

    def random_q(self, size: int | tuple[int, ...] | None = None,
                 rng: np.random.Generator | int | None = None) -> NDArray[np.float64]:
        """Uniform random configurations inside the limits (unbounded joints: ±1 m).

        ``rng``: a generator, a non-negative integer seed, or ``None`` (fresh entropy).
        """
        try:
            rng = np.random.default_rng(rng)
        except (TypeError, ValueError) as exc:
            raise InputError(f"rng: expected a numpy Generator, a non-negative integer seed or None, "
                             f"got {rng!r}") from exc
        lim = np.where(np.isfinite(self.limits), self.limits, [[-1.0, 1.0]])
        shape = (() if size is None else (size,) if isinstance(size, int) else tuple(size))
        return rng.uniform(lim[:, 0], lim[:, 1], size=(*shape, self.n))

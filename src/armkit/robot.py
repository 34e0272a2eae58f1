"""The :class:`Robot`: a named chain with the description it came from and the user-facing methods.

A robot keeps how it was written (a DH table, joint lines of a product of exponentials, a
URDF file: ``robot.dh``, ``robot.poe``, ``robot.urdf``, at most one of them set) for
display and for writing it back; everything it computes reads only ``robot.chain``.
:meth:`Robot.lock` fixes some joints and returns a :class:`LockedRobot`, a robot of its own
that knows how to give the full configuration back.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from functools import cache
from types import ModuleType
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit import _core, dynamics, kinematics
from armkit._deprecation import renamed_argument
from armkit._params import core_ready, real_array, thread_count, whole_number
from armkit.chain import MAX_VALUE, Chain, DHConvention, DHRow, JointKind, chain_from_dh
from armkit.errors import InputError, JointLimitError
from armkit.inertial import Inertial
from armkit.spatial.transforms import invert_transform, pose_from_transform, rot_z, trans_z

if TYPE_CHECKING:  # the descriptions' modules import this one; matplotlib only when drawing
    from matplotlib.figure import Figure
    from mpl_toolkits.mplot3d import Axes3D

    from armkit.collision.scene import Scene
    from armkit.poe import PoeDescription
    from armkit.urdf import UrdfDescription

__all__ = ["DHDescription", "LockedRobot", "Robot"]


@cache
def _closed_form() -> ModuleType:
    """:mod:`armkit.ik.closed_form` (its ``one_pose``), imported on first use (armkit.ik imports
    this module)."""
    from armkit.ik import closed_form

    return closed_form


@cache
def _solve_ik() -> Callable[..., NDArray[np.float64] | list[NDArray[np.float64]]]:
    """:func:`armkit.ik.solve.ik`, imported on first use (armkit.ik imports this module)."""
    from armkit.ik.solve import ik

    return ik


#: The keywords :meth:`Robot.ik` handles itself (the deprecated ``all=`` and a held joint); the others go
#: to :func:`armkit.ik.solve.ik`.
_ROBOT_IK_OPTIONS = frozenset({"all", "free_joint", "free_value"})


@dataclass(frozen=True)
class DHDescription:
    """The DH table a robot was written in, kept for display and export.

    ``length_unit`` and ``angle_unit`` are the units the user wrote; ``rows`` are in SI.
    ``T_base`` / ``T_tool``: base and tool given as plain transforms (``[base]`` / ``[tool]``
    with ``xyz`` and ``rpy`` in a robot file) instead of DH rows, else None.
    """

    convention: DHConvention
    rows: tuple[DHRow, ...]
    base_rows: tuple[DHRow, ...] = ()
    tool_rows: tuple[DHRow, ...] = ()
    length_unit: str = "m"
    angle_unit: str = "rad"
    T_base: NDArray[np.float64] | None = None
    T_tool: NDArray[np.float64] | None = None


def _with_base_inertials(chain: Chain, inertials: Sequence[Inertial | None] | None,
                         max_torque: Sequence[float | None] | None) -> Chain:
    """``chain`` with per-joint ``max_torque`` and ``inertials`` given in the base frame at
    ``q = 0`` (moved into each joint's link frame)."""
    n = chain.n
    inertials = [None] * n if inertials is None else list(inertials)
    max_torque = [None] * n if max_torque is None else list(max_torque)
    if len(inertials) != n or len(max_torque) != n:
        raise InputError(f"inertials and max_torque: expected {n} entries each, one per joint, got "
                         f"{len(inertials)} and {len(max_torque)}")
    joints, T_base_link = [], np.eye(4)
    for joint, inertial, limit in zip(chain.joints, inertials, max_torque, strict=True):
        T_base_link = T_base_link @ joint.T_before @ joint.T_after
        moved = None if inertial is None else inertial.moved(invert_transform(T_base_link))
        joints.append(replace(joint, inertial=moved, max_torque=limit))
    return Chain(tuple(joints), chain.T_base, chain.T_tool)


class Robot:
    """A serial arm: FK, Jacobians, limits (and IK, motion, simulation in later modules).

    Parameters
    ----------
    chain : Chain
        The kinematic chain (see :mod:`armkit.chain`).
    name : str
    dh : DHDescription, optional
        The DH table the chain was built from, if any.
    source : str, optional
        The file (or built-in) it was loaded from.
    description : str
    poe : PoeDescription, optional
        The joint lines it was written with (a ``convention = "poe"`` file, :meth:`from_poe`).
    urdf : UrdfDescription, optional
        The URDF file, links and meshes it was loaded from (:func:`armkit.urdf.load_urdf`).

    Examples
    --------
    >>> robot = Robot.from_dh([DHRow(0, 0, 0, 0), DHRow(0, 1.0, 0, 0)], "modified", name="2R")
    >>> robot.fk([0.0, 0.0])[:3, 3]
    array([1., 0., 0.])
    """

    def __init__(self, chain: Chain, name: str = "robot", dh: DHDescription | None = None,
                 source: str | None = None, description: str = "", *, poe: PoeDescription | None = None,
                 urdf: UrdfDescription | None = None) -> None:
        self.chain = chain
        self.name = name
        self.description = description
        self.dh = dh
        self.source = source
        self.poe = poe
        self.urdf = urdf

    @classmethod
    def from_dh(cls, rows: Sequence[DHRow], convention: DHConvention, *, name: str = "robot",
                limits: Sequence[tuple[float, float]] | None = None,
                max_velocity: Sequence[float | None] | None = None,
                max_acceleration: Sequence[float | None] | None = None,
                base_rows: Sequence[DHRow] = (), tool_rows: Sequence[DHRow] = (),
                length_unit: str = "m", angle_unit: str = "rad",
                names: Sequence[str] | None = None, T_base: ArrayLike | None = None,
                T_tool: ArrayLike | None = None, inertials: Sequence[Inertial | None] | None = None,
                max_torque: Sequence[float | None] | None = None) -> Robot:
        """Build a robot from DH rows in SI units (see :func:`armkit.chain.chain_from_dh`).

        ``T_base`` ``(4, 4)`` places the DH base frame in the world (before any base rows),
        ``T_tool`` ``(4, 4)`` follows the tool rows (or the last joint's link frame) [m].
        ``inertials`` per joint in its DH link frame, ``max_torque`` [N m or N] per joint.
        """
        T_base = None if T_base is None else np.array(T_base, dtype=float)
        T_tool = None if T_tool is None else np.array(T_tool, dtype=float)
        chain = chain_from_dh(rows, convention, limits=limits, max_velocity=max_velocity,
                              max_acceleration=max_acceleration, base_rows=base_rows,
                              tool_rows=tool_rows, names=names, T_base=T_base, T_tool=T_tool,
                              inertials=inertials, max_torque=max_torque)
        dh = DHDescription(convention, tuple(rows), tuple(base_rows), tuple(tool_rows),
                           length_unit, angle_unit, T_base, T_tool)
        return cls(chain, name=name, dh=dh)

    @classmethod
    def from_poe(cls, axes: ArrayLike, points: ArrayLike, M: ArrayLike, *, name: str = "robot",
                 kinds: Sequence[JointKind] | None = None, T_base: ArrayLike | None = None,
                 limits: Sequence[tuple[float, float] | None] | None = None,
                 max_velocity: Sequence[float | None] | None = None,
                 max_acceleration: Sequence[float | None] | None = None,
                 names: Sequence[str] | None = None, length_unit: str = "m",
                 angle_unit: str = "rad", inertials: Sequence[Inertial | None] | None = None,
                 max_torque: Sequence[float | None] | None = None) -> Robot:
        """Build a robot from joint lines at ``q = 0`` (product of exponentials, SI units).

        ``axes[i]`` ``(n, 3)`` is joint ``i``'s direction and ``points[i]`` a point on its
        line [m], both in the base frame; ``M`` ``(4, 4)`` the tool pose at ``q = 0``. See
        :func:`armkit.poe.chain_from_poe` for the other parameters. ``inertials`` per joint
        are given like the lines, in the base frame at ``q = 0``; ``max_torque`` [N m or N].

        Examples
        --------
        >>> M = np.eye(4); M[0, 3] = 1.0
        >>> robot = Robot.from_poe([[0, 0, 1]], [[0, 0, 0]], M, name="1R")
        >>> robot.fk([np.pi / 2])[:3, 3].round(12) + 0.0
        array([0., 1., 0.])
        """
        from armkit.poe import PoeDescription, chain_from_poe

        chain = chain_from_poe(axes, points, M, kinds=kinds, T_base=T_base, limits=limits,
                               max_velocity=max_velocity, max_acceleration=max_acceleration, names=names)
        if inertials is not None or max_torque is not None:
            chain = _with_base_inertials(chain, inertials, max_torque)
        axes = np.asarray(axes, dtype=float)
        poe = PoeDescription(axes / np.linalg.norm(axes, axis=1, keepdims=True),
                             np.asarray(points, dtype=float), np.asarray(M, dtype=float),
                             np.array(chain.T_base), length_unit, angle_unit)
        return cls(chain, name=name, poe=poe)

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

    @property
    def max_torque(self) -> NDArray[np.float64]:
        """``(n,)`` torque [N m] or force [N] limits (URDF ``effort``); ``inf`` where none was given."""
        return np.array([np.inf if j.max_torque is None else j.max_torque for j in self.chain.joints])

    # ----------------------------------------------------------------- checks
    def check_q(self, q: ArrayLike, name: str = "q") -> NDArray[np.float64]:
        """Return ``q`` as float64 ``(..., n)``, or raise :class:`InputError` saying why not."""
        q = real_array(q, name, f"{self.n} numbers")  # text, bools, None refused
        if q.ndim == 0 or q.shape[-1] != self.n:
            got = {0: "a scalar", 1: f"{q.size}"}.get(q.ndim, f"an array of shape {q.shape}")
            raise InputError(f"{name}: expected {self.n} joint values, got {got} "
                             f"({self.name} has {self.n} joints)")
        if not np.all(np.isfinite(q)):
            raise kinematics.non_finite_error(q, name)
        return q

    def _checked(self, q: ArrayLike) -> NDArray[np.float64]:
        """``q`` for the kinematic kernels: as it is when it is already a C-ordered float64
        array ``(..., n)`` (the core checks finiteness in its loop), else :meth:`check_q`."""
        return q if core_ready(q, (self.n,)) else np.ascontiguousarray(self.check_q(q))

    def _refused(self, q: ArrayLike, refused: Exception) -> InputError:
        """The error for joint values the core refused in :meth:`fk` or :meth:`jacobian`
        (``_core.RefusedJointValues``: the flat index of the first non-finite value, or -1 for
        values that are not ``n`` numbers per configuration, which :meth:`check_q` raises for)."""
        try:
            values, bad = self.check_q(q), int(str(refused))
        except InputError as error:  # raised by the caller, without the core's refusal as its context
            return error
        if bad < 0:
            return InputError(f"q: expected {self.n} joint values, got {q!r}")
        return kinematics.non_finite_error(values, bad=bad)

    def within_limits(self, q: ArrayLike) -> NDArray[np.bool_]:
        """Whether each configuration ``(..., n)`` lies inside all position limits, ``(...)``."""
        return self.chain.within_limits(self.check_q(q))

    def limit_violations(self, q: ArrayLike, degrees: bool = False) -> list[str]:
        """One message per joint value of a single configuration outside its limits.

        With ``degrees`` the messages show revolute values and limits in degrees; see
        :meth:`armkit.chain.Chain.limit_violations` (the test and the message, once).
        """
        q = self.check_q(q)
        if q.ndim != 1:
            raise InputError(f"q: expected one configuration of {self.n} values, got {q.shape}")
        return self.chain.limit_violations(q, degrees)

    def check_limits(self, q: ArrayLike, degrees: bool = False) -> NDArray[np.float64]:
        """Return ``q`` if every value is inside its limits, else raise :class:`JointLimitError`."""
        violations = self.limit_violations(q, degrees)
        if violations:
            q = self.check_q(q)
            raise JointLimitError("; ".join(violations), q, **self.chain.limit_fields(q))
        return self.check_q(q)

    # ----------------------------------------------------------------- kinematics
    def fk(self, q: ArrayLike, *, threads: int | None = None) -> NDArray[np.float64]:
        """Tool pose ``T_base_tool`` [m], ``(4, 4)`` for ``q`` ``(n,)``, ``(N, 4, 4)`` for ``(N, n)``.

        One core call for any batch shape (see :func:`armkit.kinematics.fk`). A batch is split
        over ``threads`` (default: every core); the result does not depend on it.

        Examples
        --------
        >>> import armkit
        >>> armkit.load("probot-anno").fk([0, 0, 0, 0, 0, 0])[:3, 3].round(4) + 0.0
        array([0.2289, 0.    , 0.454 ])
        """
        threads = 0 if threads is None else thread_count(threads)
        try:
            return _core.fk(self.chain._core, q, threads)  # one core call, for any batch shape
        except _core.RefusedJointValues as refused:
            raise self._refused(q, refused) from None

    def pose(self, q: ArrayLike, convention: str = "xyz-fixed",
             degrees: bool = False) -> NDArray[np.float64]:
        """Tool pose as ``(..., 6)``: position [m] then three angles in ``convention``."""
        return pose_from_transform(self.fk(q), convention, degrees)

    def link_frames(self, q: ArrayLike) -> NDArray[np.float64]:
        """Base, every DH link frame and tool: ``(..., n + 2, 4, 4)``."""
        return kinematics.link_frames_at(self.chain, self._checked(q))

    def plot(self, q: ArrayLike, *, ax: Axes3D | None = None, frames: bool = False,
             joint_axes: bool = True, title: str | None = None) -> Figure:
        """Draw the arm at ``q`` in matplotlib 3-D (like the Robotics Toolbox's ``robot.plot``).

        Links, joint origins and axes, the base and tool frames (and every link frame with
        ``frames``), equal scale in x, y and z. A batch ``q`` ``(N, n)`` draws the last
        configuration as the arm and the others as translucent ghosts. ``ax``: draw into these
        3-D axes instead of a new figure. Returns the figure; see :func:`armkit.animation.plot_arm`.

        Examples
        --------
        >>> import armkit
        >>> figure = armkit.load("probot-anno").plot([0, -0.5, 0.5, 0, 1, 0])
        >>> figure.savefig("arm.png")  # doctest: +SKIP
        """
        from armkit.animation import plot_arm

        return plot_arm(self, q, ax=ax, frames=frames, joint_axes=joint_axes, title=title)

    def jacobian(self, q: ArrayLike, frame: str = "base", *,
                 threads: int | None = None) -> NDArray[np.float64]:
        """Geometric Jacobian ``(..., 6, n)``, rows ``[v; w]``, in the ``"base"`` or ``"tool"`` frame."""
        tool = kinematics.is_tool_frame(frame)
        threads = 0 if threads is None else thread_count(threads)
        try:
            return _core.jacobian(self.chain._core, q, tool, threads)  # as fk
        except _core.RefusedJointValues as refused:
            raise self._refused(q, refused) from None

    def analytic_jacobian(self, q: ArrayLike, convention: str = "xyz-fixed") -> NDArray[np.float64]:
        """Analytic Jacobian ``(..., 6, n)``: position rates over angle rates in ``convention``."""
        return kinematics.analytic_jacobian(self.chain, self.check_q(q), convention)

    def manipulability(self, q: ArrayLike) -> NDArray[np.float64]:
        """Yoshikawa manipulability ``(...)``; zero at singularities."""
        return kinematics.manipulability(self.chain, self.check_q(q))

    def singular_values(self, q: ArrayLike) -> NDArray[np.float64]:
        """Jacobian singular values ``(..., min(6, n))``; the last is the singularity measure."""
        return kinematics.singular_values(self.chain, self.check_q(q))

    def ik(self, T_base_tool: ArrayLike, all_solutions: bool = False, near: ArrayLike | None = None,
           within_limits: bool = True, *, scene: Scene | None = None,
           **options) -> NDArray[np.float64] | list[NDArray[np.float64]]:
        """Inverse kinematics: every closed-form solution, or the one closest to ``near``.

        Closed form where the chain's geometry has one, numeric (seeded from ``near``)
        otherwise; every answer reproduces the target to 1e-9 m and 1e-9 rad. See
        :func:`armkit.ik.solve.ik` for the options, and :func:`armkit.ik.ik_solutions`
        for every solution with per-solution flags (limits, singular family, residual).

        Parameters
        ----------
        T_base_tool : array_like, shape (4, 4) or (N, 4, 4)
            Target tool pose(s) [m].
        all_solutions : bool
            ``(k, n)``: every solution, nearest to ``near`` first (closed form only), each
            once; ``turn_copies=True`` adds the whole-turn copies inside the limits of joints
            whose limits span more than a whole turn (see :func:`armkit.ik.ik_solutions`).
            ``all=`` is its deprecated old name (it shadowed the builtin); it warns.
        near : array_like, shape (n,) or (N, n), optional
            Reference configuration [rad or m]; default zeros.
        within_limits : bool
            Only solutions inside the joint limits (default).
        free_joint : int or str, optional (keyword)
            A redundant arm's joint held fixed (index or name), the others solved exactly by
            the closed form of :meth:`lock` (a 7R arm: every solution at that joint value;
            see :func:`armkit.self_motion` for the whole self-motion).
        free_value : float, optional (keyword)
            The value it is held at [rad or m]; default ``near``'s value of it, or 0.
        scene : armkit.Scene, optional (keyword)
            Only solutions free of collisions in this scene (built for this robot): the free subset
            of the listing, or the nearest free solution (see :mod:`armkit.collision.ik`).

        Returns
        -------
        ndarray
            ``(n,)`` or ``(N, n)``; with ``all_solutions=True`` ``(k, n)`` (a list for ``N``
            poses). An empty batch ``(0, 4, 4)`` gives ``(0, n)`` (``[]`` with ``all_solutions``).

        Raises
        ------
        InputError
            If a target is not a rigid transform, or ``near`` is not ``n`` finite joint values
            (per pose, or one set for all).
        CollisionError
            With ``scene``, one solution asked and every solution of a pose in collision.

        Examples
        --------
        >>> import armkit
        >>> robot = armkit.load("probot-anno")
        >>> T = robot.fk([0.927, -0.687, -0.396, 0, 1.083, 0.927])
        >>> robot.ik(T, all_solutions=True).shape
        (4, 6)
        >>> robot.ik(T, near=[1, -1, 0, 0, 1, 1]).round(3)
        array([ 0.927, -0.687, -0.396,  0.   ,  1.083,  0.927])
        """
        copies = options.get("turn_copies", False)
        if scene is None and options.keys() <= {"turn_copies"} and not (copies and self.chain.spans_turns):
            # one pose as the core takes it, each solution once (as ik lists it): one core call, else None
            q = _closed_form().one_pose(self.chain, T_base_tool, near, within_limits, not all_solutions)
            if q is not None:
                return q
        if scene is not None:
            from armkit.collision.ik import ik_free

            return ik_free(self, scene, T_base_tool, all_solutions=all_solutions, near=near,
                           within_limits=within_limits, **options)
        if not _ROBOT_IK_OPTIONS.isdisjoint(options):
            if "all" in options:
                all_solutions = renamed_argument("Robot.ik", "all", "all_solutions", options.pop("all"),
                                                 all_solutions, False)
            if options.get("free_joint") is None and options.get("free_value") is None:
                options.pop("free_joint", None)
                options.pop("free_value", None)
            if "free_joint" in options or "free_value" in options:
                from armkit.ik.self_motion import ik_at_free_joint

                if options.get("free_joint") is None:
                    raise InputError("free_value: given without free_joint; name the joint it holds")
                joint, value = options.pop("free_joint"), options.pop("free_value", None)
                return ik_at_free_joint(self, T_base_tool, joint, value, all_solutions=all_solutions,
                                        near=near, within_limits=within_limits, **options)
        if near is not None:  # in this robot's words (its shape against the targets': ik)
            near = self.check_q(near, "near")
        return _solve_ik()(self.chain, T_base_tool, all_solutions=all_solutions, near=near,
                           within_limits=within_limits, **options)

    def ik_position(self, position: ArrayLike, *, all_solutions: bool = False, near: ArrayLike | None = None,
                    within_limits: bool = True, turn_copies: bool = False) -> NDArray[np.float64]:
        """Position IK in closed form: joints 1-3 put the tool point at ``position`` [m]
        (orientation free; joints 4..n keep ``near``'s values). See :func:`armkit.ik.ik_position`.

        Examples
        --------
        >>> import armkit
        >>> robot = armkit.load("examples/data/my_arm.toml")
        >>> q = robot.ik_position([0.3, 0.1, 0.3], near=[0.3, -0.3, -1.6])
        >>> robot.fk(q)[:3, 3].round(9).tolist()
        [0.3, 0.1, 0.3]
        """
        from armkit.ik.position import ik_position

        return ik_position(self.chain, position, all_solutions=all_solutions, near=near,
                           within_limits=within_limits, turn_copies=turn_copies)

    def random_q(self, size: int | tuple[int, ...] | None = None,
                 rng: np.random.Generator | int | None = None) -> NDArray[np.float64]:
        """Uniform random configurations inside the limits.

        An unbounded revolute joint (URDF ``continuous``) is drawn from ``[-pi, pi]`` (one
        whole turn), an unbounded prismatic one from ``[-1, 1]`` m. ``rng``: a generator, a
        non-negative integer seed, or ``None`` (fresh entropy). ``size``: whole numbers from 0
        to 2**31 - 1 (:func:`armkit._params.whole_number`).
        """
        try:
            rng = np.random.default_rng(rng)
        except (TypeError, ValueError) as exc:
            raise InputError(f"rng: expected a numpy Generator, a non-negative integer seed or None, "
                             f"got {rng!r}") from exc
        unbounded = np.where(self.chain.prismatic, 1.0, np.pi)[:, None] * [[-1.0, 1.0]]
        lim = np.where(np.isfinite(self.limits), self.limits, unbounded)
        shape = () if size is None else tuple(size) if isinstance(size, tuple | list) else (size,)
        shape = tuple(whole_number(k, "size", minimum=0) for k in shape)
        return rng.uniform(lim[:, 0], lim[:, 1], size=(*shape, self.n))

    # ----------------------------------------------------------------- dynamics
    # One state (arrays (n,) the core takes as they are, default gravity: the model's, no threads) goes
    # straight to the core's one-state call, which answers None for anything it does not take as it is
    # (a batch, a value not finite, a singular mass matrix): the checked path then answers or says why.
    def inverse_dynamics(self, q: ArrayLike, qd: ArrayLike | None = None, qdd: ArrayLike | None = None, *,
                         gravity: ArrayLike | None = None, threads: int | None = None) -> NDArray[np.float64]:
        """Joint torques ``(..., n)`` [N m or N] for positions, velocities and accelerations
        ``(..., n)`` (recursive Newton-Euler); see :func:`armkit.dynamics.inverse_dynamics`.

        Examples
        --------
        >>> import armkit
        >>> armkit.load("puma560").inverse_dynamics(np.zeros(6), np.zeros(6), np.zeros(6)).round(3)
        array([ 0.   , 37.484,  0.249,  0.   ,  0.   ,  0.   ])
        """
        if gravity is None and threads is None:
            tau = _core.inverse_dynamics_one(dynamics.dynamics_model(self.chain), q, qd, qdd)
            if tau is not None:
                return tau
        return dynamics.inverse_dynamics(self.chain, q, qd, qdd, threads=threads,
                                         gravity=dynamics.GRAVITY if gravity is None else gravity)

    def mass_matrix(self, q: ArrayLike, *, threads: int | None = None) -> NDArray[np.float64]:
        """Joint-space mass matrices ``(..., n, n)`` at ``q`` ``(..., n)``; see
        :func:`armkit.dynamics.mass_matrix`."""
        if threads is None:
            M = _core.mass_matrix_one(dynamics.dynamics_model(self.chain), q)
            if M is not None:
                return M
        return dynamics.mass_matrix(self.chain, q, threads=threads)

    def gravity_torques(self, q: ArrayLike, *, gravity: ArrayLike | None = None,
                        threads: int | None = None) -> NDArray[np.float64]:
        """Torques ``(..., n)`` [N m or N] holding the arm still at ``q`` ``(..., n)``."""
        return self.inverse_dynamics(q, gravity=gravity, threads=threads)

    def coriolis_torques(self, q: ArrayLike, qd: ArrayLike, *,
                         threads: int | None = None) -> NDArray[np.float64]:
        """Coriolis and centrifugal torques ``C(q, qd) qd`` ``(..., n)`` [N m or N]."""
        return dynamics.coriolis_torques(self.chain, q, qd, threads=threads)

    def forward_dynamics(self, q: ArrayLike, qd: ArrayLike, tau: ArrayLike, *,
                         gravity: ArrayLike | None = None, threads: int | None = None) -> NDArray[np.float64]:
        """Joint accelerations ``(..., n)`` under torques ``tau`` ``(..., n)``; see
        :func:`armkit.dynamics.forward_dynamics`."""
        if gravity is None and threads is None:
            qdd = _core.forward_dynamics_one(dynamics.dynamics_model(self.chain), q, qd, tau)
            if qdd is not None:
                return qdd
        return dynamics.forward_dynamics(self.chain, q, qd, tau, threads=threads,
                                         gravity=dynamics.GRAVITY if gravity is None else gravity)

    def with_payload(self, mass: float, com: ArrayLike = (0.0, 0.0, 0.0),
                     inertia: ArrayLike = ((0.0,) * 3,) * 3) -> Robot:
        """This robot carrying a payload [kg] fixed to the tool frame (``com`` [m] in it,
        ``inertia`` [kg m^2] about it), added to the last link's own; see
        :func:`armkit.dynamics.with_payload`."""
        return dynamics.with_payload(self, mass, com, inertia)

    def with_estimated_inertia(self, density: float = 1000.0) -> Robot:
        """This robot with every link's inertia estimated from MJCF export's capsules of
        ``density`` [kg/m^3]; see :func:`armkit.dynamics.with_estimated_inertia`."""
        return dynamics.with_estimated_inertia(self, density)

    # ----------------------------------------------------------------- locked joints
    def lock(self, values: Mapping[int | str, float]) -> LockedRobot:
        """The robot with some joints fixed at given values: a robot of the other joints.

        The locked joints' motions are folded into the fixed transforms around them, so the
        reduced robot has its own closed-form analysis (a 7-joint arm with one joint locked
        can be a 6R arm with a spherical wrist) and every method works on it.

        Parameters
        ----------
        values : mapping of joint name or index to value
            Joint names as in :attr:`joint_names`, or 0-based indices; values in rad or m,
            inside the joint's limits.

        Returns
        -------
        LockedRobot
            With :meth:`LockedRobot.full_q` to map its configurations back to this robot's.

        Raises
        ------
        InputError
            If a joint is unknown or named twice, a value is not a finite number, or every
            joint would be locked.
        JointLimitError
            If a value is outside its joint's limits.

        Examples
        --------
        >>> import armkit
        >>> arm = armkit.load("puma560").lock({"q6": 0.5})
        >>> arm.n, arm.full_q(np.zeros(5)).tolist()
        (5, [0.0, 0.0, 0.0, 0.0, 0.0, 0.5])
        >>> bool(np.allclose(arm.fk(np.zeros(5)), armkit.load("puma560").fk([0, 0, 0, 0, 0, 0.5])))
        True
        """
        return LockedRobot(self, self._lock_values(values))

    def _lock_values(self, values: Mapping[int | str, float]) -> dict[int, float]:
        """``{index: value}`` from names or indices, checked (see :meth:`lock`)."""
        if not isinstance(values, Mapping) or not values:
            raise InputError(f"joints to lock: expected a mapping such as {{'{self.joint_names[0]}': 0.3}}, "
                             f"got {values!r}")
        out: dict[int, float] = {}
        for key, value in values.items():
            if isinstance(key, str) and key in self.joint_names:
                index = self.joint_names.index(key)
            elif isinstance(key, int | np.integer) and not isinstance(key, bool) and 0 <= key < self.n:
                index = int(key)
            else:
                raise InputError(f"joint {key!r} to lock: expected a joint name "
                                 f"({', '.join(self.joint_names)}) or an index 0 to {self.n - 1}")
            if index in out:
                raise InputError(f"joint {self.joint_names[index]} is locked twice")
            try:
                number = float(value)
            except (TypeError, ValueError) as exc:
                raise InputError(f"joint {self.joint_names[index]}: lock value {value!r} is not a "
                                 f"number") from exc
            if not abs(number) <= MAX_VALUE:
                raise InputError(f"joint {self.joint_names[index]}: lock value {value!r} is not a finite "
                                 f"number from {-MAX_VALUE:g} to {MAX_VALUE:g} (rad or m)")
            out[index] = number
        if len(out) == self.n:
            raise InputError(f"locking all {self.n} joints leaves no robot; keep at least one free")
        q = self.home.copy()  # inside the limits: only the locked values can be outside
        q[list(out)] = list(out.values())
        violations = self.limit_violations(self.check_q(q, "locked joint values"))
        if violations:
            raise JointLimitError("cannot lock: " + "; ".join(violations), q, **self.chain.limit_fields(q))
        return out


class LockedRobot(Robot):
    """A robot with some joints of another robot fixed (see :meth:`Robot.lock`).

    Attributes
    ----------
    full_robot : Robot
        The robot with every joint.
    locked : dict of int to float
        Locked joints of ``full_robot`` (0-based indices) and their values [rad or m].
    free : ndarray of int
        Indices in ``full_robot`` of this robot's joints, in order.
    """

    def __init__(self, full_robot: Robot, locked: Mapping[int, float]) -> None:
        if isinstance(full_robot, LockedRobot):  # locking more: one level, indices of the full robot
            locked = {int(full_robot.free[i]): v for i, v in locked.items()} | full_robot.locked
            full_robot = full_robot.full_robot
        self.full_robot = full_robot
        self.locked = dict(sorted(locked.items()))
        self.free = np.array([i for i in range(full_robot.n) if i not in self.locked])
        chain = full_robot.chain
        joints, pending = [], None
        for i, joint in enumerate(chain.joints):
            if i in self.locked:
                motion = (trans_z if joint.kind == "prismatic" else rot_z)(self.locked[i])
                fixed = joint.T_before @ motion @ joint.T_after
                pending = fixed if pending is None else pending @ fixed
            else:
                joints.append(joint if pending is None else replace(joint, T_before=pending @ joint.T_before))
                pending = None
        tool = chain.T_tool if pending is None else pending @ chain.T_tool
        if any(joint.inertial is not None for joint in chain.joints):  # locked links ride on the one before
            joints = [replace(joint, inertial=inertial) for joint, inertial in
                      zip(joints, dynamics.locked_inertials(chain, self.locked), strict=True)]
        names = ", ".join(f"{full_robot.joint_names[i]} = {v:.6g}" for i, v in self.locked.items())
        super().__init__(Chain(tuple(joints), chain.T_base, tool), name=f"{full_robot.name} ({names} locked)",
                         source=full_robot.source, description=full_robot.description)

    def full_q(self, q: ArrayLike) -> NDArray[np.float64]:
        """This robot's configurations ``(..., n)`` as the full robot's ``(..., n_full)``.

        >>> import armkit
        >>> armkit.load("ur5").lock({1: -0.5}).full_q([[1, 2, 3, 4, 5]]).tolist()
        [[1.0, -0.5, 2.0, 3.0, 4.0, 5.0]]
        """
        q = self.check_q(q)
        full = np.empty((*q.shape[:-1], self.full_robot.n))
        full[..., self.free] = q
        for i, value in self.locked.items():
            full[..., i] = value
        return full

    def reduced_q(self, q_full: ArrayLike) -> NDArray[np.float64]:
        """The free joints' values ``(..., n)`` of full configurations ``(..., n_full)``."""
        return self.full_robot.check_q(q_full)[..., self.free]

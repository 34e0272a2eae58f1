"""A robot among obstacles: collision, clearance and contact queries, one configuration or a batch.

The checks run in MuJoCo (``mj_kinematics`` then ``mj_collision`` on the model of
:mod:`armkit.collision.model`); clearance is ``mj_geomDistance`` over the pairs that are checked.
Batches are split into contiguous chunks, one per thread, each with its own ``MjData`` (MuJoCo releases
the GIL inside its functions), so the answer does not depend on the thread count.

Which pairs are checked
    Every arm part against the floor and every obstacle, and every pair of arm parts, except the
    *disabled* pairs: adjacent parts (the base and link 1, link ``i`` and link ``i + 1``: they meet at
    their joint), and pairs found once by sampling ``samples`` random configurations inside the limits
    (as MoveIt's setup assistant does): arm pairs in contact in *every* sample or in *none*, and arm
    parts in contact with the floor in every sample (a first link standing on it). The fixed base is
    never checked against the floor or the obstacles (neither moves). ``disabled_pairs`` adds pairs,
    ``enabled_pairs`` removes any (the sampled ones included), by name.
"""

from __future__ import annotations

import math
import os
import queue
import threading
from collections.abc import Callable, Iterable, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit._params import positive_float, thread_count, whole_number
from armkit.collision.model import (
    BOX_MESH,
    FLOOR,
    body_names,
    build_xml,
    compile_model,
    part_names,
    require_mujoco,
)
from armkit.collision.shapes import Box, Cylinder, Mesh, Obstacle, Sphere
from armkit.errors import InputError
from armkit.robot import Robot

__all__ = ["DEFAULT_SAMPLES", "MAX_SAMPLES", "Scene", "WorldShape"]

#: Random configurations sampled to find the pairs that always or never touch (default), and the most
#: accepted (about 10-30 s of checks; more only holds a user up, and a billion took 45 GB).
DEFAULT_SAMPLES = 5000
MAX_SAMPLES = 1_000_000
#: Largest distance [m] :meth:`Scene.clearance` measures; farther pairs count as this far.
MAX_DISTANCE = 1e3
_CHUNK_MIN = 64  # configurations below which a batch runs on the calling thread

Pair = tuple[str, str]


@dataclass(frozen=True)
class WorldShape:
    """A floor or obstacle geom for drawing.

    Attributes
    ----------
    part : str
        ``floor`` or the obstacle's name.
    kind : str
        ``"plane"``, ``"box"``, ``"sphere"``, ``"cylinder"`` or ``"mesh"``.
    size : ndarray (3,)
        MuJoCo's geom size: half extents of a box, ``(radius, half length)`` of a cylinder, the radius
        of a sphere first [m].
    T_base_geom : ndarray (4, 4)
        The geom's pose [m].
    vertices, faces : ndarray or None
        A mesh's vertices ``(V, 3)`` [m] in the geom frame and triangles ``(F, 3)``.
    """

    part: str
    kind: str
    size: NDArray[np.float64]
    T_base_geom: NDArray[np.float64]
    vertices: NDArray[np.float64] | None
    faces: NDArray[np.int32] | None


class Scene:
    """A robot, a floor and obstacles, with batch collision queries.

    Parameters
    ----------
    robot : Robot
    obstacles : sequence of Box, Sphere, Cylinder or Mesh
        Fixed in the frame :meth:`Robot.fk` reports poses in (the base frame) [m].
    floor : float or None
        Height [m] of a floor plane (normal +z) in that frame; ``None`` for none.
    link_radius : float or sequence, optional
        Capsule radius [m], one for all or one per body (the base first); default the MJCF export's
        (2.5 % of the total link length). Only for capsule geometry.
    geometry : {"auto", "capsules", "urdf"}
        The arm's shapes: the URDF's ``<collision>`` elements (``"auto"`` when it has any) or capsules.
    package_paths : sequence of path
        Folders to look for ``package://NAME/...`` meshes in (``DIR/NAME/...``).
    disabled_pairs, enabled_pairs : sequence of (str, str)
        Part pairs never to check, or always to check (overriding adjacency and sampling).
    samples : int
        Random configurations that find the always/never-touching pairs (0: no sampling; at most
        :data:`MAX_SAMPLES`).
    threads : int, optional
        Threads for batches (``None``: every core; see :func:`armkit._params.thread_count`).
    relative_to : path, optional
        Folder that relative obstacle mesh paths start from (a scene file's folder).

    Attributes
    ----------
    robot : Robot
    obstacles : tuple of obstacles
    floor : float or None
    parts : tuple of str
        The part names queries report: the base and the links (URDF link names, or ``base``,
        ``link1``, ...), then ``floor`` and the obstacles (their ``name``, or ``box1``, ``sphere1``, ...).
    disabled_pairs : dict
        ``(part, part) -> reason`` (``"adjacent"``, ``"always"``, ``"never"``, ``"home"``, ``"user"``) of
        the pairs not checked.

    Examples
    --------
    >>> import armkit
    >>> robot = armkit.load("ur5")
    >>> scene = armkit.Scene(robot, [armkit.Sphere(0.1, [0.5, 0.0, 0.3])], floor=0.0)
    >>> q = [0, -1.2, 1.0, 0, 1.5, 0]  # elbow up, the tool above the floor
    >>> scene.collides(q), scene.collides([q, robot.home]).tolist()  # at home the wrist points down
    (False, [False, True])
    >>> scene.contacts(robot.home)
    [('link5', 'floor'), ('link6', 'floor')]
    """

    def __init__(self, robot: Robot, obstacles: Iterable[Obstacle] = (), floor: float | None = 0.0, *,
                 link_radius: float | Sequence[float] | None = None, geometry: str = "auto",
                 package_paths: Sequence[str | Path] = (), disabled_pairs: Iterable[Pair] = (),
                 enabled_pairs: Iterable[Pair] = (), samples: int = DEFAULT_SAMPLES,
                 threads: int | None = None, relative_to: str | Path | None = None) -> None:
        if not isinstance(robot, Robot):
            raise InputError(f"Scene: expected an armkit.Robot, got {type(robot).__name__}")
        self.robot = robot
        self.obstacles = tuple(obstacles)
        for obstacle in self.obstacles:
            if not isinstance(obstacle, Box | Sphere | Cylinder | Mesh):
                raise InputError(f"Scene obstacles: expected armkit.Box, Sphere, Cylinder or Mesh, got "
                                 f"{obstacle!r}")
        if floor is not None:
            floor = float(floor) if isinstance(floor, int | float) and not isinstance(floor, bool) else floor
            if not isinstance(floor, float) or not math.isfinite(floor):
                raise InputError(f"Scene floor: expected a height in metres or None, got {floor!r}")
        self.floor = floor
        self.threads = thread_count(threads) or os.cpu_count() or 1
        self._options = {"link_radius": link_radius, "geometry": geometry,
                         "package_paths": tuple(package_paths), "relative_to": relative_to}
        samples = whole_number(samples, "samples", minimum=0, maximum=MAX_SAMPLES)
        names = part_names(robot, self.obstacles, floor is not None)
        self.parts = names.names
        self._robot_parts = names.robot
        self._index = {name: i for i, name in enumerate(self.parts)}
        self._bodies = body_names(robot, floor is not None, len(self.obstacles))
        disabled = {pair: "adjacent" for pair in self._adjacent()}
        disabled |= {self._pair(pair, "disabled_pairs"): "user" for pair in disabled_pairs}
        enabled = {self._pair(pair, "enabled_pairs") for pair in enabled_pairs}
        self._xml = build_xml(robot, names, self.obstacles, floor, link_radius=link_radius,
                              package_paths=package_paths, geometry=geometry,
                              relative_to=None if relative_to is None else Path(relative_to))
        self._use_model({pair: why for pair, why in disabled.items() if pair not in enabled})
        if samples:
            sampled = self._sampled_pairs(robot.random_q(samples, rng=0))
            disabled |= {pair: why for pair, why in sampled.items() if pair not in disabled}
            self._use_model({pair: why for pair, why in disabled.items() if pair not in enabled})

    @classmethod
    def from_file(cls, path: str | Path, robot: Robot, **options) -> Scene:
        """The scene a TOML scene file describes for ``robot``: :func:`armkit.load_scene`."""
        from armkit.collision.scene_file import load_scene

        return load_scene(path, robot, **options)

    def __reduce__(self) -> tuple:
        """Pickled as its description (the robot as a robot file, or its URDF file and links, the
        obstacles, the pairs decided), rebuilt without sampling on one thread: a Dask worker gets the
        scene a task checks against."""
        from armkit.robot_file import robot_to_toml

        urdf = self.robot.urdf
        if urdf is not None and not Path(urdf.path).is_file():
            raise InputError(f"scene of {self.robot.name}: a robot read from URDF text cannot be sent to "
                             f"another process (its collision geometry is in the text); load it from a file")
        robot = (("toml", robot_to_toml(self.robot)) if urdf is None
                 else ("urdf", urdf.path, urdf.base, urdf.tip))
        pairs = tuple(self.disabled_pairs.items())
        return _rebuilt, (robot, self.obstacles, self.floor, self._options, pairs)

    # ------------------------------------------------------------------ construction
    def _pair(self, pair: object, what: str) -> Pair:
        """``pair`` as two known part names, the arm part (or the earlier part) first."""
        if isinstance(pair, str) or not isinstance(pair, Sequence) or len(pair) != 2:
            raise InputError(f"{what}: expected pairs of part names such as ('link1', 'link3'), got {pair!r}")
        for name in pair:
            if name not in self._index:
                raise InputError(f"{what}: {name!r} is not a part of the scene; its parts: "
                                 f"{', '.join(self.parts)}")
        a, b = sorted(pair, key=self._index.__getitem__)
        if a == b:
            raise InputError(f"{what}: ({a!r}, {b!r}) pairs a part with itself")
        return a, b

    def _adjacent(self) -> list[Pair]:
        arm = self.parts[:self._robot_parts]
        return list(zip(arm, arm[1:], strict=False))

    def _use_model(self, disabled: dict[Pair, str]) -> None:
        """Compile the model with ``disabled`` excluded; set the pairs clearance measures."""
        self.disabled_pairs = dict(sorted(disabled.items(), key=lambda item: tuple(map(self._index.get,
                                                                                       item[0]))))
        body = dict(zip(self.parts, self._bodies, strict=True))
        self._model = compile_model(self._xml, [(body[a], body[b]) for a, b in self.disabled_pairs])
        self._mujoco = require_mujoco()
        self._pool: queue.SimpleQueue = queue.SimpleQueue()
        old = getattr(self, "_executor", None)
        if old is not None:  # the sampling's threads: done with
            old.shutdown(wait=False)
        self._executor: ThreadPoolExecutor | None = None
        self._executor_lock = threading.Lock()
        model = self._model
        part_of_body = np.full(model.nbody, -1)
        for i, name in enumerate(self._bodies):
            part_of_body[self._mujoco.mj_name2id(model, self._mujoco.mjtObj.mjOBJ_BODY, name)] = i
        self._part_of_geom = part_of_body[model.geom_bodyid]
        static = np.ones(len(self.parts), dtype=bool)
        static[1:self._robot_parts] = False  # the links move; the base, floor and obstacles do not
        skipped = {(self._index[a], self._index[b]) for a, b in self.disabled_pairs}
        pairs = []
        for g1 in range(model.ngeom):
            for g2 in range(g1 + 1, model.ngeom):
                p1, p2 = sorted((self._part_of_geom[g1], self._part_of_geom[g2]))
                if p1 < 0 or p1 == p2 or (static[p1] and static[p2]) or (p1, p2) in skipped:
                    continue
                pairs.append((g1, g2))
        self._geom_pairs = tuple(pairs)

    def _sampled_pairs(self, q: NDArray[np.float64]) -> dict[Pair, str]:
        """Arm pairs in contact in every or no configuration of ``q``, arm-floor pairs in every one, and
        (MoveIt's "default" rule) the arm pairs in contact at the robot's home configuration: a shape
        model that overlaps there (a SCARA's quill through its forearm capsule) is no fault of a motion."""
        counts = np.zeros((len(self.parts), len(self.parts)), dtype=np.int64)
        for part in self._map(self._contact_counts, q, len(self.parts)):
            counts += part
        arm = self._robot_parts
        has_geometry = np.zeros(len(self.parts), dtype=bool)
        has_geometry[self._part_of_geom[self._part_of_geom >= 0]] = True
        found = {}
        for i in range(arm):
            for j in range(i + 1, arm):
                pair = (self.parts[i], self.parts[j])
                if pair in self.disabled_pairs or not (has_geometry[i] and has_geometry[j]):
                    continue
                if counts[i, j] in (0, len(q)):
                    found[pair] = "never" if counts[i, j] == 0 else "always"
            if FLOOR in self._index and has_geometry[i] and counts[i, self._index[FLOOR]] == len(q):
                found[(self.parts[i], FLOOR)] = "always"
        arm_parts = set(self.parts[:arm])
        for pair in self.contacts(self.robot.home):
            if set(pair) <= arm_parts and pair not in found:
                found[pair] = "home"
        return found

    # ------------------------------------------------------------------ batches
    def _data(self):  # -> mujoco.MjData
        try:
            return self._pool.get_nowait()
        except queue.Empty:
            return self._mujoco.MjData(self._model)

    def _map(self, kernel: Callable, q: NDArray[np.float64], *args) -> list:
        """``kernel(data, chunk, *args)`` over contiguous chunks of ``q`` ``(N, n)``, one per thread."""
        chunks = max(1, min(self.threads, len(q) // _CHUNK_MIN))
        bounds = [len(q) * k // chunks for k in range(chunks + 1)]

        def run(k: int):
            data = self._data()
            try:
                return kernel(data, q[bounds[k]:bounds[k + 1]], *args)
            finally:
                self._pool.put(data)

        if chunks == 1:
            return [run(0)]
        with self._executor_lock:  # one pool, whichever thread asks first
            if self._executor is None:
                self._executor = ThreadPoolExecutor(self.threads, thread_name_prefix="armkit-collision")
        return list(self._executor.map(run, range(chunks)))

    def _batch(self, kernel: Callable, q: ArrayLike, dtype: type) -> NDArray:
        q = self.robot.check_q(q)
        flat = np.ascontiguousarray(q.reshape(-1, self.robot.n))
        parts = self._map(kernel, flat) if len(flat) else [np.zeros(0, dtype=dtype)]
        out = parts[0] if len(parts) == 1 else np.concatenate(parts)
        return out.reshape(q.shape[:-1])

    def _collides_kernel(self, data, q: NDArray[np.float64]) -> NDArray[np.bool_]:
        mujoco, model = self._mujoco, self._model
        kinematics, collision = mujoco.mj_kinematics, mujoco.mj_collision
        out = np.empty(len(q), dtype=bool)
        qpos = data.qpos
        for i, row in enumerate(q):
            qpos[:] = row
            kinematics(model, data)
            collision(model, data)
            out[i] = data.ncon > 0
        return out

    def _clearance_kernel(self, data, q: NDArray[np.float64]) -> NDArray[np.float64]:
        mujoco, model, pairs = self._mujoco, self._model, self._geom_pairs
        distance, kinematics = mujoco.mj_geomDistance, mujoco.mj_kinematics
        out = np.full(len(q), np.inf)
        qpos = data.qpos
        for i in range(len(q)):
            qpos[:] = q[i]
            kinematics(model, data)
            out[i] = min((distance(model, data, g1, g2, MAX_DISTANCE, None) for g1, g2 in pairs),
                         default=np.inf)
        return out

    def _contact_counts(self, data, q: NDArray[np.float64], parts: int) -> NDArray[np.int64]:
        mujoco, model = self._mujoco, self._model
        counts = np.zeros((parts, parts), dtype=np.int64)
        qpos = data.qpos
        for i in range(len(q)):
            qpos[:] = q[i]
            mujoco.mj_kinematics(model, data)
            mujoco.mj_collision(model, data)
            if data.ncon:
                touching = np.sort(self._part_of_geom[data.contact.geom[:data.ncon]], axis=1)
                for a, b in set(map(tuple, touching)):
                    counts[a, b] += 1
        return counts

    # ------------------------------------------------------------------ queries
    def collides(self, q: ArrayLike) -> bool | NDArray[np.bool_]:
        """Whether the arm at ``q`` touches an obstacle, the floor or itself (checked pairs only).

        Parameters
        ----------
        q : array_like, shape (..., n)
            Configurations [rad or m].

        Returns
        -------
        bool or ndarray of bool, shape (...)
        """
        out = self._batch(self._collides_kernel, q, bool)
        return bool(out) if out.ndim == 0 else out

    def clearance(self, q: ArrayLike) -> float | NDArray[np.float64]:
        """The smallest signed distance [m] between checked pairs: negative when they overlap (the
        penetration depth), ``inf`` when no pair is checked, at most :data:`MAX_DISTANCE`.

        Parameters
        ----------
        q : array_like, shape (..., n)

        Returns
        -------
        float or ndarray, shape (...)
        """
        out = self._batch(self._clearance_kernel, q, float)
        return float(out) if out.ndim == 0 else out

    def contacts(self, q: ArrayLike) -> list[Pair]:
        """The part pairs in contact at one configuration ``q`` ``(n,)``, e.g. ``[("link3", "floor")]``,
        the arm part first, sorted."""
        q = self.robot.check_q(q)
        if q.ndim != 1:
            raise InputError(f"contacts: expected one configuration of {self.robot.n} values, got shape "
                             f"{q.shape}")
        counts = self._map(self._contact_counts, q[None], len(self.parts))[0]
        return [(self.parts[a], self.parts[b]) for a, b in zip(*np.nonzero(counts), strict=True)]

    def self_collision_toml(self) -> str:
        """The ``[self_collision]`` table of a scene file that fixes this scene's disabled pairs (no
        sampling when it is read), with each pair's reason as a comment.

        Examples
        --------
        >>> import armkit
        >>> print(armkit.Scene(armkit.load("ur5"), floor=0.0).self_collision_toml().splitlines()[2])
        disabled = [
        """
        lines = ["[self_collision]", "samples = 0", "disabled = ["]
        lines += [f'    ["{a}", "{b}"],  # {why}' for (a, b), why in self.disabled_pairs.items()]
        return "\n".join([*lines, "]"]) + "\n"

    def check_robot(self, robot: Robot, label: str = "scene") -> None:
        """Raise :class:`InputError` unless ``robot`` has this scene's kinematics (the same joints,
        link transforms and limits: the same arm loaded twice counts, a locked copy does not)."""
        mine, theirs = self.robot.chain, robot.chain
        if mine is theirs:
            return
        if not (mine.n == theirs.n and np.array_equal(mine.T_between, theirs.T_between)
                and np.array_equal(mine.prismatic, theirs.prismatic)
                and np.array_equal(mine.lower, theirs.lower) and np.array_equal(mine.upper, theirs.upper)):
            raise InputError(f"{label}: built for {self.robot.name} ({self.robot.n} joints), whose joints, "
                             f"links or limits differ from {robot.name}'s ({robot.n} joints); build one with "
                             f"armkit.Scene(robot, ...) for this robot")

    def world_shapes(self) -> list[WorldShape]:
        """The floor's and the obstacles' geoms as MuJoCo holds them (meshes as their vertices and faces),
        for drawing: one :class:`WorldShape` per geom."""
        mujoco, model = self._mujoco, self._model
        data = self._data()
        try:
            mujoco.mj_kinematics(model, data)
            shapes = []
            for g in range(model.ngeom):
                part = self._part_of_geom[g]
                if part < self._robot_parts:
                    continue
                T = np.eye(4)
                T[:3, :3], T[:3, 3] = data.geom_xmat[g].reshape(3, 3), data.geom_xpos[g]
                kind = mujoco.mjtGeom(model.geom_type[g]).name.removeprefix("mjGEOM_").lower()
                vertices = faces = None
                size = model.geom_size[g].copy()
                if kind == "mesh" and model.geom(g).name.startswith(BOX_MESH):  # a box (model._add_box)
                    mesh = model.geom_dataid[g]
                    start, count = model.mesh_vertadr[mesh], model.mesh_vertnum[mesh]
                    kind, size = "box", np.abs(model.mesh_vert[start:start + count]).max(axis=0).astype(float)
                elif kind == "mesh":
                    mesh = model.geom_dataid[g]
                    start, count = model.mesh_vertadr[mesh], model.mesh_vertnum[mesh]
                    vertices = model.mesh_vert[start:start + count].copy()
                    first, faces_count = model.mesh_faceadr[mesh], model.mesh_facenum[mesh]
                    faces = model.mesh_face[first:first + faces_count].copy()
                shapes.append(WorldShape(self.parts[part], kind, size, T, vertices, faces))
            return shapes
        finally:
            self._pool.put(data)

    def displacement_bound(self, q_a: ArrayLike, q_b: ArrayLike) -> float:
        """An upper bound [m] on how far any point of the arm's geometry moves along the straight
        joint-space segment from ``q_a`` to ``q_b``.

        ``sum_j |dq_j| R_j`` over revolute joints plus ``|dq_j|`` over prismatic ones, where ``R_j`` is
        the farthest any geometry beyond joint ``j`` can be from joint ``j``'s origin: the sum of the
        distances between the following joint origins (plus the largest prismatic travel on the
        segment) and the extent of the body's geometry (its geoms' distance from the body origin plus
        their bounding radius). A point at distance ``r`` from a joint's axis moves at most ``r |dq|``
        when that joint turns by ``dq``; the contributions add (triangle inequality).
        """
        q_a, q_b = self.robot.check_q(q_a, "q_a"), self.robot.check_q(q_b, "q_b")
        if q_a.shape != (self.robot.n,) or q_b.shape != (self.robot.n,):
            raise InputError(f"q_a, q_b: expected one configuration of {self.robot.n} values each, got "
                             f"shapes {q_a.shape} and {q_b.shape}")
        model, prismatic = self._model, self.robot.chain.prismatic
        extent = np.zeros(self.robot.n)
        for g in range(model.ngeom):
            part = self._part_of_geom[g]
            if 1 <= part < self._robot_parts:
                reach = np.linalg.norm(model.geom_pos[g]) + model.geom_rbound[g]
                extent[part - 1] = max(extent[part - 1], reach)
        travel = np.where(prismatic, np.maximum(np.abs(q_a), np.abs(q_b)), 0.0)
        link = np.linalg.norm(self.robot.chain.T_between[1:-1, :3, 3], axis=-1) + travel[1:]
        reach = np.zeros(self.robot.n)
        for j in range(self.robot.n - 1, -1, -1):  # R_j = max(extent_j, link_j + R_{j+1})
            reach[j] = max(extent[j], link[j] + reach[j + 1] if j + 1 < self.robot.n else 0.0)
        dq = np.abs(q_b - q_a)
        return float(np.sum(np.where(prismatic, dq, dq * reach)))

    def path_collides(self, q_a: ArrayLike, q_b: ArrayLike, resolution: float = 0.005) -> bool:
        """Whether the straight joint-space motion from ``q_a`` to ``q_b`` collides, checked at
        configurations close enough that no point of the arm moves more than ``resolution`` [m]
        between two of them (:meth:`displacement_bound`), both ends included.

        Examples
        --------
        >>> import armkit
        >>> robot = armkit.load("ur5")
        >>> scene = armkit.Scene(robot, floor=0.0)
        >>> q = np.array([0, -1.2, 1.0, 0, 1.5, 0])
        >>> scene.path_collides(q, q + [3.0, 0, 0, 0, 0, 0]), scene.path_collides(q, q + [0, 1.2, 0, 0, 0, 0])
        (False, True)
        """
        resolution = positive_float(resolution, "resolution (m)")
        bound = self.displacement_bound(q_a, q_b)
        q_a, q_b = self.robot.check_q(q_a), self.robot.check_q(q_b)
        steps = max(1, math.ceil(bound / resolution))
        for start in range(0, steps + 1, 1024):  # early exit on a collision, batches stay threaded
            t = np.arange(start, min(start + 1024, steps + 1)) / steps
            if np.any(self.collides(q_a + t[:, None] * (q_b - q_a))):
                return True
        return False


def _rebuilt(robot: tuple, obstacles: tuple[Obstacle, ...], floor: float | None, options: dict,
             disabled: tuple[tuple[Pair, str], ...]) -> Scene:
    """A pickled :class:`Scene` again (see ``Scene.__reduce__``)."""
    from armkit.urdf import load_urdf
    from armkit.workspace.sampling import robot_from_toml

    arm = robot_from_toml(robot[1]) if robot[0] == "toml" else load_urdf(robot[1], robot[2], robot[3])
    scene = Scene(arm, obstacles, floor, samples=0, threads=1, **options)
    scene._use_model(dict(disabled))
    return scene

"""MJCF import: the serial chain between two bodies of a MuJoCo model, read through MuJoCo's own parser.

The file is compiled by MuJoCo (``pip install 'armkit[sim]'``), so everything its compiler
accepts is read as MuJoCo reads it: ``<include>``, ``<default>`` classes, degrees or
radians, ``euler``/``axisangle``/``xyaxes`` orientations, inertias from geoms. armkit then
reads the compiled :class:`mujoco.MjModel`:

Bodies and joints
    A body sits at ``body_pos``/``body_quat`` in its parent. A hinge (slide) joint of a body
    turns about (moves along) ``jnt_axis`` through ``jnt_pos``, both in the body frame, by
    ``q - ref`` (MuJoCo's ``qpos0``): the body frame is where the bodies were written at
    ``q = ref``. With ``R`` a rotation taking z onto the axis (:func:`armkit.poe.rotation_z_to`)
    and ``P`` the translation to ``jnt_pos``, the joint fills the chain (:mod:`armkit.chain`) as
    ``T_before = F · P · R · M_z(-ref)`` and ``T_after = R^T · P^-1``, ``F`` being the body poses
    met since the previous joint; a body's joints act in the order written. armkit's ``q`` is
    MuJoCo's ``qpos`` of the joint, so ranges and values need no conversion, and link frame
    ``i`` is the frame of the body joint ``i`` moves.
What is read
    Hinge and slide joints of the bodies from ``base`` (default the world body) down to
    ``tip`` (a body or a site; default the only leaf body below ``base``); ``range`` of a
    limited joint (an unlimited one, ``limited="false"`` or no ``range``, has no limits),
    ``actuatorfrcrange`` as the joint's ``max_torque``; mass, centre of mass and inertia of
    every body moving with a chain link (bodies fixed to it, side branches and bodies beyond
    the tip held at ``q = ref``), merged into that link as :mod:`armkit.urdf` does. Bodies
    fixed to the base carry no load and are left out. A joint's velocity, acceleration and
    torque limits from the custom numerics ``armkit:<joint>:max_velocity``
    (``max_acceleration``, ``max_torque``) that :mod:`armkit.export.mjcf` writes (MJCF
    itself has no velocity or acceleration limits; ``actuatorfrcrange`` wins over the
    numeric torque). Armature, damping, friction, actuators, geoms and contacts are ignored.
Refused, with one :class:`~armkit.errors.RobotDefinitionError`
    A file MuJoCo cannot compile (its message is passed on), unknown base or tip names,
    a tip not below the base, ball and free joints on the chosen path, no joint on it, a
    limited joint whose ``range`` is not two finite numbers of magnitude at most
    :data:`armkit.chain.MAX_VALUE` (a ``range="-1e300 1e300"`` in degrees would be limits of
    1.7e298 rad: a typo, or a way of writing "unlimited" that MJCF spells ``limited="false"``).
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from armkit.chain import MAX_VALUE, chain_from_frames
from armkit.errors import ArmkitError, RobotDefinitionError, warn_at_caller
from armkit.inertial import Inertial
from armkit.poe import rotation_z_to
from armkit.robot import Robot
from armkit.spatial.rotations import matrix_from_quaternion_wxyz
from armkit.spatial.transforms import invert_transform, rot_z, trans_z, transform_from

__all__ = ["load_mjcf", "robot_from_mjcf"]

_HINGE, _SLIDE = 3, 2  # mujoco.mjtJoint values
_KIND_NAMES = {0: "free", 1: "ball", 2: "slide", 3: "hinge"}


def _import_mujoco() -> Any:
    try:
        import mujoco
    except ImportError as exc:
        raise ArmkitError("reading an MJCF file needs MuJoCo: pip install 'armkit[sim]' "
                          "(or pip install mujoco)") from exc
    return mujoco


def load_mjcf(path: str | Path, base: str | None = None, tip: str | None = None) -> Robot:
    """Load the serial chain from body ``base`` to body or site ``tip`` of an MJCF file.

    Meshes, ``<include>`` files and other assets are found relative to the file, as MuJoCo
    finds them. See the module notes for what is read.

    Parameters
    ----------
    path : str or Path
    base : str, optional
        Body whose frame is the robot's base frame; default the world body.
    tip : str, optional
        Body or site whose frame is the tool frame; default the only leaf body below ``base``.

    Raises
    ------
    RobotDefinitionError
        If MuJoCo cannot compile the file or it has no usable chain (the message names the
        file, the body or the joint).
    ArmkitError
        If MuJoCo is not installed.
    """
    mujoco = _import_mujoco()
    path = Path(path)
    if not path.is_file():
        raise RobotDefinitionError(f"{path}: no such file")
    model, said = _compiled(mujoco, mujoco.MjModel.from_xml_path, str(path), str(path))
    return _robot(mujoco, model, str(path), base, tip, said,
                  lambda: _in_degrees(mujoco, "from_file", str(path)))


def robot_from_mjcf(model: Any, source: str = "MJCF text", *, base: str | None = None,
                    tip: str | None = None) -> Robot:
    """A :class:`~armkit.Robot` from MJCF text or a compiled :class:`mujoco.MjModel` (see :func:`load_mjcf`).

    Text is compiled with :meth:`mujoco.MjModel.from_xml_string` (files it names are looked
    up from the working folder; :func:`load_mjcf` looks beside the file).

    Examples
    --------
    >>> text = '''<mujoco model="r"><worldbody>
    ...   <body name="link1"><joint name="j1" axis="0 1 0"/><geom size="0.05"/>
    ...     <body name="flange" pos="0 0 0.5"/></body>
    ... </worldbody></mujoco>'''
    >>> robot = robot_from_mjcf(text)
    >>> robot.joint_names, robot.limits.tolist()
    (['j1'], [[-inf, inf]])
    >>> robot.fk([np.pi / 2])[:3, 3].round(12) + 0.0
    array([0.5, 0. , 0. ])
    """
    mujoco = _import_mujoco()
    if isinstance(model, str | bytes):
        try:
            text = model if isinstance(model, str) else model.decode()
        except UnicodeDecodeError as exc:
            raise RobotDefinitionError(f"{source}: MuJoCo cannot compile it: {_one_line(exc)}") from exc
        model, said = _compiled(mujoco, mujoco.MjModel.from_xml_string, text, source)
        return _robot(mujoco, model, source, base, tip, said,
                      lambda: _in_degrees(mujoco, "from_string", text))
    return _robot(mujoco, model, source, base, tip, [], lambda: None)


def _robot(mujoco: Any, model: Any, source: str, base: str | None, tip: str | None, said: list[str],
           in_degrees: Callable[[], bool | None]) -> Robot:
    """:func:`robot_from_mjcf` of a compiled model; ``said``: MuJoCo's warnings while compiling it;
    ``in_degrees``: whether the file writes angles in degrees (``None``: unknown, a compiled model),
    asked only for an error message."""
    bodies = [mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_BODY, b) or f"body {b}"
              for b in range(model.nbody)]
    base_id = 0 if base is None else _body_id(bodies, base, "base", source)
    tip_body, T_body_tip, tip_name = _tip(mujoco, model, bodies, base_id, tip, source)
    path = _path(model, bodies, base_id, tip_body, source)
    kinds, before, after, limits, names, ids, frame_of = [], [], [], [], [], [], {}
    pending = np.eye(4)
    for body in path:
        _check_finite(source, f"body {bodies[body]!r}", pos=model.body_pos[body], quat=model.body_quat[body])
        pending = pending @ _body_pose(model, body)
        for j in range(model.body_jntadr[body], model.body_jntadr[body] + model.body_jntnum[body]):
            name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_JOINT, j) or f"joint {j}"
            kind = int(model.jnt_type[j])
            if kind not in (_HINGE, _SLIDE):
                raise RobotDefinitionError(
                    f"{source}, joint {name!r} of body {bodies[body]!r}: a {_KIND_NAMES[kind]} joint on the "
                    f"path from {bodies[base_id]!r} to {tip_name!r}; armkit reads hinge and slide joints "
                    f"(a floating arm: choose its first body as base=...)")
            _check_finite(source, f"joint {name!r}", axis=model.jnt_axis[j], pos=model.jnt_pos[j])
            R = transform_from(rotation_z_to(model.jnt_axis[j]), np.zeros(3))
            P = transform_from(np.eye(3), model.jnt_pos[j])
            ref = float(model.qpos0[model.jnt_qposadr[j]])
            kinds.append("revolute" if kind == _HINGE else "prismatic")
            before.append(pending @ P @ R @ (rot_z(-ref) if kind == _HINGE else trans_z(-ref)))
            after.append(R.T @ invert_transform(P))
            if model.jnt_limited[j] and not (np.abs(model.jnt_range[j]) <= MAX_VALUE).all():
                written = _as_written(model.jnt_range[j], kind == _HINGE, in_degrees())
                raise RobotDefinitionError(
                    f"{source}, joint {name!r}: range {written}; expected two finite numbers of magnitude at "
                    f"most {MAX_VALUE:g} rad ({np.degrees(MAX_VALUE):.4g} degrees) or m (for no limits: "
                    f"limited=\"false\", or no range)")
            limits.append(tuple(model.jnt_range[j]) if model.jnt_limited[j] else (-np.inf, np.inf))
            names.append(name)
            ids.append(j)
            pending = np.eye(4)
        frame_of[body] = (len(kinds), pending.copy())
    if not kinds:
        raise RobotDefinitionError(f"{source}: no joint between bodies {bodies[base_id]!r} and {tip_name!r}")
    torque = [float(np.abs(model.jnt_actfrcrange[j]).max()) if model.jnt_actfrclimited[j]
              else _limit_numeric(mujoco, model, name, "max_torque", source)
              for j, name in zip(ids, names, strict=True)]
    chain = chain_from_frames(kinds, before, after, limits=limits, T_tool=pending @ T_body_tip, names=names,
                              max_velocity=[_limit_numeric(mujoco, model, n, "max_velocity", source)
                                            for n in names],
                              max_acceleration=[_limit_numeric(mujoco, model, n, "max_acceleration", source)
                                                for n in names],
                              max_torque=torque, inertials=_inertials(model, path, frame_of, len(kinds)))
    if any("NaN" in text for text in said):  # e.g. a geom's mass, which MuJoCo then computes itself
        raise RobotDefinitionError(f"{source}: MuJoCo warns that the XML contains a 'NaN' (in an attribute "
                                   f"armkit does not name here, e.g. a geom's mass or size); write finite "
                                   f"numbers")
    name = _model_name(model) or Path(source).stem
    return Robot(chain, name=name, source=source,
                 description=f"MJCF {Path(source).name}, {bodies[base_id]} to {tip_name}")


def _in_degrees(mujoco: Any, parse: str, xml: str) -> bool | None:
    """Whether ``mujoco.MjSpec.<parse>(xml)`` (MuJoCo's own parser: ``<include>`` files and MuJoCo's
    default, degrees, as it reads them) says the file writes angles in degrees; ``None`` if it cannot
    tell (MuJoCo before 3.2 has no ``MjSpec``)."""
    spec = getattr(mujoco, "MjSpec", None)
    if spec is None:
        return None
    with _WARNING_HANDLER:  # its warnings were already given once, by the compile
        previous = mujoco.get_mju_user_warning()
        mujoco.set_mju_user_warning(lambda text: None)
        try:
            return bool(getattr(spec, parse)(xml).compiler.degree)
        except ValueError:
            return None
        finally:
            mujoco.set_mju_user_warning(previous)


def _as_written(values: NDArray[np.float64], angle: bool, degrees: bool | None) -> str:
    """A joint's compiled ``range`` (radians or metres) as the file wrote it, with its unit.

    >>> print(_as_written(np.array([np.nan, np.pi / 2]), True, True))
    [nan, 90] degrees (<compiler angle="degree">, MuJoCo's default)
    """
    if angle and degrees:
        written, unit = np.degrees(values), 'degrees (<compiler angle="degree">, MuJoCo\'s default)'
    else:
        written = values
        unit = "m" if not angle else 'rad (the file\'s <compiler angle="radian">)' if degrees is False else \
            "rad, as MuJoCo compiled it"
    return f"[{', '.join(f'{v:g}' for v in written)}] {unit}"


def _check_finite(source: str, where: str, **attributes: NDArray[np.float64]) -> None:
    """A :class:`RobotDefinitionError` naming the first of ``attributes`` of ``where`` that is not
    finite (as MuJoCo compiled it)."""
    for key, value in attributes.items():
        if not np.isfinite(value).all():
            raise RobotDefinitionError(f"{source}, {where}: {key} {np.asarray(value).tolist()}; expected "
                                       f"finite numbers")


def _limit_numeric(mujoco: Any, model: Any, joint: str, limit: str, source: str) -> float | None:
    """Joint ``joint``'s ``limit`` from its custom numeric (see :data:`armkit.export.mjcf.LIMIT_NUMERIC`)."""
    from armkit.export.mjcf import LIMIT_NUMERIC

    name = LIMIT_NUMERIC.format(joint=joint, limit=limit)
    i = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_NUMERIC, name)
    if i < 0:
        return None
    data = model.numeric_data[model.numeric_adr[i]:model.numeric_adr[i] + model.numeric_size[i]]
    if data.shape != (1,) or not (np.isfinite(data[0]) and data[0] > 0):
        shown = " ".join(f"{v:g}" for v in data)
        raise RobotDefinitionError(f"{source}, custom numeric {name!r}: expected one finite number > 0 (the "
                                   f"{limit} of joint {joint!r}), got data {shown}")
    return float(data[0])


#: MuJoCo's warning handler is one for the process: a compile swaps it under this lock.
_WARNING_HANDLER = threading.Lock()


def _compiled(mujoco: Any, compile_xml: Any, xml: str, source: str) -> tuple[Any, list[str]]:
    """``compile_xml(xml)`` and MuJoCo's warnings, with MuJoCo's compiler errors as
    :class:`RobotDefinitionError` and its warnings as Python warnings naming ``source`` (MuJoCo
    would otherwise print them and append them to a ``MUJOCO_LOG.TXT`` in the user's folder)."""
    said: list[str] = []
    with _WARNING_HANDLER:
        previous = mujoco.get_mju_user_warning()
        mujoco.set_mju_user_warning(said.append)
        try:
            model = compile_xml(xml)
        except ValueError as exc:
            warned = "".join(f"; MuJoCo warned: {text.strip()}" for text in dict.fromkeys(said))
            raise RobotDefinitionError(f"{source}: MuJoCo cannot compile it: {_one_line(exc)}"
                                       f"{warned}") from exc
        finally:
            mujoco.set_mju_user_warning(previous)
    for text in dict.fromkeys(said):
        warn_at_caller(UserWarning(f"{source}: MuJoCo warns: {text.strip()}"))
    return model, said


def _one_line(exc: Exception) -> str:
    return " ".join(str(exc).split())


def _model_name(model: Any) -> str:
    """The ``<mujoco model>`` name: the first entry of MuJoCo's name buffer."""
    return bytes(model.names).split(b"\0", 1)[0].decode(errors="replace")


def _body_pose(model: Any, body: int) -> NDArray[np.float64]:
    """The body's frame in its parent's at ``q = ref`` ``(4, 4)`` [m]."""
    return transform_from(matrix_from_quaternion_wxyz(model.body_quat[body]), model.body_pos[body])


def _body_id(bodies: list[str], name: str, what: str, source: str) -> int:
    if name not in bodies:
        shown = ", ".join(bodies[:20]) + (", ..." if len(bodies) > 20 else "")
        raise RobotDefinitionError(f"{source}: {what} body {name!r} is not in the model; its bodies: {shown}")
    return bodies.index(name)


def _below(model: Any, body: int, base: int) -> bool:
    while body != base and body != 0:
        body = int(model.body_parentid[body])
    return body == base


def _tip(mujoco: Any, model: Any, bodies: list[str], base: int, tip: str | None,
         source: str) -> tuple[int, NDArray[np.float64], str]:
    """The tip's body, the tip frame in that body ``(4, 4)`` and its name: a body, else a site."""
    if tip is None:
        has_child = set(int(p) for p in model.body_parentid[1:])
        leaves = [b for b in range(1, model.nbody)
                  if b not in has_child and b != base and _below(model, b, base)]
        if len(leaves) != 1:
            listed = ", ".join(bodies[b] for b in leaves[:8]) + (f" and {len(leaves) - 8} more"
                                                                 if len(leaves) > 8 else "")
            raise RobotDefinitionError(f"{source}: {len(leaves)} leaf bodies below {bodies[base]!r}"
                                       f"{': ' + listed if listed else ''}; choose the tip body or site "
                                       f"(tip=... in Python, --tip NAME on the command line)")
        return leaves[0], np.eye(4), bodies[leaves[0]]
    if tip in bodies:
        return bodies.index(tip), np.eye(4), tip
    site = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, tip)
    if site < 0:
        sites = [mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_SITE, s) for s in range(model.nsite)]
        shown = ", ".join([*bodies[1:13], *(s for s in sites[:8] if s)])
        raise RobotDefinitionError(f"{source}: tip {tip!r} is neither a body nor a site of the model; "
                                   f"its bodies and sites include: {shown}")
    T = transform_from(matrix_from_quaternion_wxyz(model.site_quat[site]), model.site_pos[site])
    return int(model.site_bodyid[site]), T, tip


def _path(model: Any, bodies: list[str], base: int, tip: int, source: str) -> list[int]:
    """The bodies below ``base`` down to ``tip``, in order (``base`` itself left out)."""
    if not _below(model, tip, base):
        raise RobotDefinitionError(f"{source}: tip body {bodies[tip]!r} is not below base body "
                                   f"{bodies[base]!r}")
    path = []
    while tip != base:
        path.append(tip)
        tip = int(model.body_parentid[tip])
    return path[::-1]


def _inertials(model: Any, path: list[int], frame_of: dict[int, tuple[int, NDArray[np.float64]]],
               n: int) -> list[Inertial] | None:
    """Per joint, the bodies moving with its link in its link frame (see the module notes); None
    if none of them has mass."""
    children: dict[int, list[int]] = {}
    for body in range(1, model.nbody):
        children.setdefault(int(model.body_parentid[body]), []).append(body)
    on_path = set(path)
    stack = [(body, *frame_of[body]) for body in path]
    links = [Inertial.zero() for _ in range(n)]
    while stack:
        body, frame, T_link_body = stack.pop()
        if frame > 0 and model.body_mass[body] > 0:
            T_body_com = transform_from(matrix_from_quaternion_wxyz(model.body_iquat[body]),
                                        model.body_ipos[body])
            inertial = Inertial(float(model.body_mass[body]), np.zeros(3), np.diag(model.body_inertia[body]))
            links[frame - 1] = links[frame - 1] + inertial.moved(T_link_body @ T_body_com)
        for child in children.get(body, []):
            if child not in on_path:  # side branches and bodies beyond the tip, held at q = ref
                stack.append((child, frame, T_link_body @ _body_pose(model, child)))
    return links if any(link.mass > 0 for link in links) else None

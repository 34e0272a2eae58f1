"""Obstacles of a collision scene: boxes, spheres, cylinders and meshes fixed in the robot's base frame.

Sizes are in metres and are the *full* extents (a box's edge lengths, a cylinder's whole length),
not MuJoCo's half sizes; a pose is a ``(4, 4)`` transform of the shape's centre in the base frame
(omitted: the identity). A mesh is used through its convex hull (MuJoCo collides meshes as convex
hulls), so a U-shaped part blocks its opening as well.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit._params import positive_float
from armkit.errors import InputError
from armkit.spatial.transforms import check_transform

__all__ = ["Box", "Cylinder", "Mesh", "Obstacle", "Sphere"]


def _pose(pose: ArrayLike | None, name: str) -> NDArray[np.float64]:
    if pose is None:
        return np.eye(4)
    T = check_transform(pose, name)
    if T.shape != (4, 4):
        raise InputError(f"{name}: expected one (4, 4) transform, got shape {T.shape}")
    T = T.copy()
    T.setflags(write=False)
    return T


def _name(name: str | None) -> str | None:
    if name is not None and (not isinstance(name, str) or not name.strip()):
        raise InputError(f"obstacle name: expected a non-empty string, got {name!r}")
    return name


@dataclass(frozen=True, init=False)
class Box:
    """A box of full edge lengths ``size = (x, y, z)`` [m], centred at ``pose`` (base frame).

    Examples
    --------
    >>> Box([1.0, 0.6, 0.05], name="table").size
    (1.0, 0.6, 0.05)
    """

    size: tuple[float, float, float]
    pose: NDArray[np.float64] = field(repr=False)
    name: str | None = None

    def __init__(self, size: ArrayLike, pose: ArrayLike | None = None, *, name: str | None = None) -> None:
        values = np.asarray(size, dtype=object).ravel()
        if values.shape != (3,):
            raise InputError(f"Box size: expected 3 edge lengths [m], got {size!r}")
        edges = tuple(positive_float(v, f"Box size[{i}] (full edge length, m)") for i, v in enumerate(values))
        object.__setattr__(self, "size", edges)
        object.__setattr__(self, "pose", _pose(pose, "Box pose"))
        object.__setattr__(self, "name", _name(name))


@dataclass(frozen=True, init=False)
class Sphere:
    """A sphere of ``radius`` [m] at ``center`` ``(3,)`` [m] in the base frame.

    Examples
    --------
    >>> Sphere(0.1, [0.5, 0, 0.3]).pose[:3, 3]
    array([0.5, 0. , 0.3])
    """

    radius: float
    pose: NDArray[np.float64] = field(repr=False)
    name: str | None = None

    def __init__(self, radius: float, center: ArrayLike = (0.0, 0.0, 0.0), *,
                 name: str | None = None) -> None:
        object.__setattr__(self, "radius", positive_float(radius, "Sphere radius (m)"))
        try:
            c = np.asarray(center, dtype=float)
        except (TypeError, ValueError) as exc:
            raise InputError(f"Sphere center: expected 3 numbers [m], got {center!r}") from exc
        if c.shape != (3,) or not np.isfinite(c).all():
            raise InputError(f"Sphere center: expected 3 finite numbers [m], got {center!r}")
        T = np.eye(4)
        T[:3, 3] = c
        T.setflags(write=False)
        object.__setattr__(self, "pose", T)
        object.__setattr__(self, "name", _name(name))


@dataclass(frozen=True, init=False)
class Cylinder:
    """A solid cylinder of ``radius`` and full ``length`` [m] along the z axis of ``pose``, centred there.

    Examples
    --------
    >>> Cylinder(0.05, 0.8).length
    0.8
    """

    radius: float
    length: float
    pose: NDArray[np.float64] = field(repr=False)
    name: str | None = None

    def __init__(self, radius: float, length: float, pose: ArrayLike | None = None, *,
                 name: str | None = None) -> None:
        object.__setattr__(self, "radius", positive_float(radius, "Cylinder radius (m)"))
        object.__setattr__(self, "length", positive_float(length, "Cylinder length (full length, m)"))
        object.__setattr__(self, "pose", _pose(pose, "Cylinder pose"))
        object.__setattr__(self, "name", _name(name))


@dataclass(frozen=True, init=False)
class Mesh:
    """A mesh file (STL or OBJ, vertices in metres times ``scale``) placed at ``pose``; collided as
    its convex hull.

    Examples
    --------
    >>> Mesh("fixture.stl", scale=0.001).scale  # a file drawn in millimetres
    (0.001, 0.001, 0.001)
    """

    path: Path
    pose: NDArray[np.float64] = field(repr=False)
    scale: tuple[float, float, float] = (1.0, 1.0, 1.0)
    name: str | None = None

    def __init__(self, path: str | Path, pose: ArrayLike | None = None, *,
                 scale: float | ArrayLike = 1.0, name: str | None = None) -> None:
        if not isinstance(path, (str, Path)) or not str(path).strip():
            raise InputError(f"Mesh path: expected a file name, got {path!r}")
        values = np.broadcast_to(np.asarray(scale, dtype=object), (3,)) if np.ndim(scale) == 0 \
            else np.asarray(scale, dtype=object).ravel()
        if values.shape != (3,):
            raise InputError(f"Mesh scale: expected one number or 3, got {scale!r}")
        factors = tuple(positive_float(v, f"Mesh scale[{i}]") for i, v in enumerate(values))
        object.__setattr__(self, "path", Path(path))
        object.__setattr__(self, "pose", _pose(pose, "Mesh pose"))
        object.__setattr__(self, "scale", factors)
        object.__setattr__(self, "name", _name(name))


Obstacle = Box | Sphere | Cylinder | Mesh

"""A rigid body's inertial parameters: mass, centre of mass, inertia tensor, and how they combine.

Every joint of a chain (:mod:`armkit.chain`) may carry the :class:`Inertial` of the link it
moves, expressed in that joint's *link frame* (the frame after ``T_after``: the DH link
frame of a DH robot, the URDF frame of the joint's child link, the joint's frame of a
product of exponentials). Bodies rigidly fixed to a link are added to it with
:meth:`Inertial.moved` and ``+`` (the parallel-axis theorem), which is how URDF fixed
links, locked joints (:meth:`armkit.Robot.lock`) and payloads
(:meth:`armkit.Robot.with_payload`) are folded in.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from armkit.errors import RobotDefinitionError

__all__ = ["Inertial"]


def _skew_squared(r: NDArray[np.float64]) -> NDArray[np.float64]:
    """``|r|^2 I - r r^T``: the inertia [per kg] of a unit point mass at ``r`` about the origin."""
    return float(r @ r) * np.eye(3) - np.outer(r, r)


@dataclass(frozen=True)
class Inertial:
    """Mass, centre of mass and inertia of a rigid body, in one frame.

    Attributes
    ----------
    mass : float
        [kg], at least 0.
    com : ndarray (3,)
        Centre of mass in the frame [m].
    inertia : ndarray (3, 3)
        Inertia tensor about the centre of mass, frame axes [kg m^2], symmetric.

    Examples
    --------
    A 2 kg point 0.5 m along x of a frame, plus a 1 kg point at its origin:

    >>> body = Inertial(2.0, [0.5, 0, 0], np.zeros((3, 3))) + Inertial(1.0, [0, 0, 0], np.zeros((3, 3)))
    >>> body.mass, body.com.round(6).tolist(), body.inertia[2, 2].round(6)
    (3.0, [0.333333, 0.0, 0.0], np.float64(0.166667))
    """

    mass: float
    com: NDArray[np.float64]
    inertia: NDArray[np.float64]

    def __post_init__(self) -> None:
        com = np.array(self.com, dtype=float)
        inertia = np.array(self.inertia, dtype=float)
        mass = float(self.mass)
        if not (np.isfinite(mass) and mass >= 0):
            raise RobotDefinitionError(f"mass = {self.mass!r} kg; expected a finite number >= 0")
        if com.shape != (3,) or not np.isfinite(com).all():
            raise RobotDefinitionError(f"com = {com.tolist()}; expected 3 finite numbers [m]")
        if inertia.shape != (3, 3) or not np.isfinite(inertia).all():
            raise RobotDefinitionError(f"inertia = {inertia.tolist()}; expected a finite 3x3 matrix [kg m^2]")
        scale = max(float(np.abs(inertia).max()), 1e-300)
        if not np.allclose(inertia, inertia.T, rtol=0, atol=1e-9 * scale):
            raise RobotDefinitionError(f"inertia = {inertia.tolist()} is not symmetric; expected "
                                       f"[[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]]")
        inertia = (inertia + inertia.T) / 2
        com.setflags(write=False)
        inertia.setflags(write=False)
        object.__setattr__(self, "mass", mass)
        object.__setattr__(self, "com", com)
        object.__setattr__(self, "inertia", inertia)

    @classmethod
    def zero(cls) -> Inertial:
        """No body: mass 0 (the neutral element of ``+``)."""
        return cls(0.0, np.zeros(3), np.zeros((3, 3)))

    @classmethod
    def from_values(cls, mass: float, com: ArrayLike, inertia: ArrayLike) -> Inertial:
        """An inertial from a mass [kg], a centre of mass ``(3,)`` [m] and an inertia about it
        [kg m^2]: ``(3, 3)``, or ``(3,)`` for the diagonal (axes along the frame's).

        >>> Inertial.from_values(1.0, [0, 0, 0.1], [0.01, 0.01, 0.002]).inertia.diagonal().tolist()
        [0.01, 0.01, 0.002]
        """
        values = np.asarray(inertia, dtype=float)
        return cls(mass, com, np.diag(values) if values.shape == (3,) else values)

    def moved(self, T_parent_frame: ArrayLike) -> Inertial:
        """The same body expressed in a parent frame, where this frame sits at
        ``T_parent_frame`` ``(4, 4)`` [m]."""
        T = np.asarray(T_parent_frame, dtype=float)
        R = T[:3, :3]
        return Inertial(self.mass, R @ self.com + T[:3, 3], R @ self.inertia @ R.T)

    def about_origin(self) -> NDArray[np.float64]:
        """Inertia about the frame's origin [kg m^2], ``(3, 3)``."""
        return self.inertia + self.mass * _skew_squared(self.com)

    def __add__(self, other: Inertial) -> Inertial:
        """Two bodies in the same frame as one rigid body."""
        mass = self.mass + other.mass
        if mass == 0.0:
            return Inertial.zero()
        com = (self.mass * self.com + other.mass * other.com) / mass
        about_origin = self.about_origin() + other.about_origin()
        return Inertial(mass, com, about_origin - mass * _skew_squared(com))

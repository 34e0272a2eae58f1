"""Export an armkit robot as a simulation model: MJCF (MuJoCo) and URDF."""

from armkit.export.mjcf import mjcf_from_robot, write_mjcf
from armkit.export.physical import PhysicalModel, physical_model
from armkit.export.urdf import urdf_from_robot, write_urdf

__all__ = ["PhysicalModel", "mjcf_from_robot", "physical_model", "urdf_from_robot", "write_mjcf",
           "write_urdf"]

"""Collision checking: the arm's geometry, a floor and obstacles, checked in MuJoCo.

See ``docs/collision.md``: :class:`Scene` (queries), the obstacle shapes, and scene files
(:func:`load_scene`). MuJoCo is imported when a scene is built, not with this package.
"""

from armkit._lazy import lazy_exports

_MODULES = {
    "armkit.collision.scene": ["Scene"],
    "armkit.collision.scene_file": ["load_scene", "scene_from_dict"],
    "armkit.collision.shapes": ["Box", "Cylinder", "Mesh", "Sphere"],
}
__getattr__, __dir__, __all__ = lazy_exports(__name__, _MODULES)

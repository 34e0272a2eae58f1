"""``armkit view``: the arm in a browser, built on viser (``pip install 'armkit[view]'``).

:class:`Viewer` serves a page with the arm, a slider per joint, the tool pose read out live,
a handle on the tool whose every IK solution is drawn as a ghost arm, taught waypoints and a
timeline. ``import armkit`` does not import this package; viser is imported when a viewer starts.
"""

from armkit.view.viewer import Viewer

__all__ = ["Viewer"]

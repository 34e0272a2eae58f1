"""``save waypoints`` in the viewer: the file name box, and a dialog before an existing file is replaced."""

from __future__ import annotations

import html
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from armkit.view.viewer import Viewer

__all__ = ["WaypointSaving"]


class WaypointSaving:
    """The waypoints file box and its ``save waypoints`` button (:meth:`Viewer.save_waypoints`)."""

    def __init__(self, viewer: Viewer) -> None:
        self._viewer = viewer
        gui = viewer._server.gui
        self.file = gui.add_text("waypoints file", "waypoints.csv")
        self.button = gui.add_button("save waypoints")
        self.button.on_click(lambda event: viewer._guarded(lambda: self._clicked(event)))

    def _clicked(self, event: Any) -> None:
        viewer, path = self._viewer, Path(self.file.value)
        if not path.exists():
            self._saved(viewer.save_waypoints(path))
            return
        client = event.client
        with client.gui.add_modal("Replace the file?") as modal:
            client.gui.add_markdown(f"`{path}` exists. Replace it with {len(viewer.waypoints)} waypoints?")
            replace = client.gui.add_button("replace", color="red")
            cancel = client.gui.add_button("cancel")

        def do_replace(_: Any) -> None:
            viewer._guarded(lambda: self._saved(viewer.save_waypoints(path, overwrite=True)))
            modal.close()

        replace.on_click(do_replace)
        cancel.on_click(lambda _: modal.close())

    def _saved(self, path: Path) -> None:
        self._viewer._show_status(f"<div style='font-size:0.8em' data-armkit='saved'>saved "
                                  f"{len(self._viewer.waypoints)} waypoints to "
                                  f"{html.escape(str(path))}</div>")

"""One line instead of a traceback when a browser (or anything else) sends the viewer's web
server a message it cannot read or use.

viser reads each websocket message in the ``websockets`` library's connection handler and
hands it to its handlers on its own event loop. A malformed message (not MessagePack, a text
frame, a cut-off message, an unknown type) ends that connection, and ``websockets`` logs
``connection handler failed`` with the whole traceback; a well-formed message with values of
the wrong type fails in viser's handler task, and ``asyncio`` logs ``Task exception was never
retrieved`` with its traceback. Either way the server stays up and serves every other
connection. :class:`OneLineMessageErrors`, attached to those two loggers while a
:class:`~armkit.view.Viewer` runs, keeps such a record (so logging configured by the user
still sees it) but makes it one line naming the error; records whose traceback does not pass
through viser or websockets are left alone.

A connection that never sends an HTTP request (a browser's speculative pre-connection closed
unused, a tool checking that the port is open, a TLS hello sent to the plain-HTTP port) fails
the opening handshake with ``InvalidMessage`` before it is a websocket or a page at all; the
filter drops that record: nothing was asked, nothing failed.
"""

from __future__ import annotations

import logging
import os
from types import TracebackType

__all__ = ["SERVER_LOGGERS", "OneLineMessageErrors"]

#: The loggers a failed connection handler or message handler is reported on.
SERVER_LOGGERS = ("websockets.server", "asyncio")
_SERVER_PACKAGES = (f"{os.sep}viser{os.sep}", f"{os.sep}websockets{os.sep}")


def _from_the_server(tb: TracebackType | None) -> bool:
    while tb is not None:
        if any(package in tb.tb_frame.f_code.co_filename for package in _SERVER_PACKAGES):
            return True
        tb = tb.tb_next
    return False


class OneLineMessageErrors(logging.Filter):
    """Turn a server record with a traceback into ``armkit view: ignored a message it cannot read (...)``;
    drop a probe's (a connection without an HTTP request)."""

    def filter(self, record: logging.LogRecord) -> bool:
        if record.exc_info and record.exc_info[1] is not None and _from_the_server(record.exc_info[2]):
            from websockets.exceptions import InvalidMessage

            exc = record.exc_info[1]
            if isinstance(exc, InvalidMessage):  # no HTTP request came: a probe of the port
                return False
            reason = f"{type(exc).__name__}: {exc}" if str(exc) else type(exc).__name__
            record.msg = f"armkit view: ignored a message it cannot read ({reason}); the server keeps running"
            record.args, record.exc_info, record.exc_text = (), None, None
        return True

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

A connection that sends no valid HTTP request fails the opening handshake with
``InvalidMessage`` before it is a websocket or a page at all. One closed before sending a byte
(a browser's speculative pre-connection closed unused, a tool checking that the port is open)
asked nothing: the filter drops its record. A TLS hello (``https://`` typed for the page's
``http://``: its first line holds binary data ended by a bare line feed, or starts with the TLS
record bytes ``16 03``) becomes :data:`TLS_LINE`; any other request that is not the HTTP/1.1
``GET`` the server reads becomes one line naming what was wrong.
"""

from __future__ import annotations

import logging
import os
from types import TracebackType

__all__ = ["SERVER_LOGGERS", "TLS_LINE", "OneLineMessageErrors"]

#: The loggers a failed connection handler or message handler is reported on.
SERVER_LOGGERS = ("websockets.server", "asyncio")
#: Logged for a TLS hello (a browser asked for ``https://``).
TLS_LINE = ("armkit view: refused an https:// (TLS) connection: the viewer serves http://, not https:// "
            "(open the address it printed)")
_SERVER_PACKAGES = (f"{os.sep}viser{os.sep}", f"{os.sep}websockets{os.sep}")


def _causes(exc: BaseException) -> list[BaseException]:
    """``exc`` and the exceptions it was raised from, outermost first."""
    chain = [exc]
    while chain[-1].__cause__ is not None and len(chain) < 10:
        chain.append(chain[-1].__cause__)
    return chain


def _handshake_line(exc: BaseException) -> str | None:
    """The line for a connection that sent no valid HTTP request; ``None`` for one that sent nothing."""
    causes = _causes(exc)[1:]
    text = " ".join(str(cause) for cause in causes)
    binary_first_line = "request line" in text and "line without CRLF" in text  # HTTP ends it with CRLF
    if "\x16\x03" in text or "\\x16\\x03" in text or binary_first_line:
        return TLS_LINE
    if causes and isinstance(causes[-1], EOFError) and "after 0 bytes" in str(causes[-1]):
        return None  # closed before a byte came: a probe of the port
    reason = "; ".join(f"{type(cause).__name__}: {cause}" for cause in causes) or str(exc)
    return f"armkit view: refused a connection that sent no valid HTTP request ({reason})"


def _from_the_server(tb: TracebackType | None) -> bool:
    while tb is not None:
        if any(package in tb.tb_frame.f_code.co_filename for package in _SERVER_PACKAGES):
            return True
        tb = tb.tb_next
    return False


class OneLineMessageErrors(logging.Filter):
    """Turn a server record with a traceback into ``armkit view: ignored a message it cannot read (...)``
    (or, for a connection without a valid HTTP request, a line saying so); drop a probe's (a
    connection closed before it sent a byte)."""

    def filter(self, record: logging.LogRecord) -> bool:
        if record.exc_info and record.exc_info[1] is not None and _from_the_server(record.exc_info[2]):
            from websockets.exceptions import InvalidMessage

            exc = record.exc_info[1]
            if isinstance(exc, InvalidMessage):  # no valid HTTP request came
                line = _handshake_line(exc)
                if line is None:
                    return False
                record.msg = line
            else:
                reason = f"{type(exc).__name__}: {exc}" if str(exc) else type(exc).__name__
                record.msg = (f"armkit view: ignored a message it cannot read ({reason}); "
                              f"the server keeps running")
            record.args, record.exc_info, record.exc_text = (), None, None
        return True

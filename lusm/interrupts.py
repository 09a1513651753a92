"""Ctrl-C and SIGTERM end a command with one line and exit code 130, nothing half-written.

While a command runs, SIGINT raises ``KeyboardInterrupt`` and SIGTERM :class:`Terminated`, so
that every ``finally`` runs (staging folders are removed) and the CLI prints its one line. A
handler inside a ``__del__`` or a weakref callback cannot propagate its exception (Python
reports it and goes on), so each signal is recorded too, and :func:`checkpoint` raises it
again before an output is moved in and at the end of the command.
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager


class Terminated(BaseException):
    """SIGTERM, raised in the main thread so that cleanup (``finally``) runs."""


_received: list[type[BaseException]] = []
"""The exception of each signal received since :func:`handlers` was entered."""


def _on_signal(signum, frame) -> None:  # pragma: no cover - exercised by signals
    stop = KeyboardInterrupt if signum == signal.SIGINT else Terminated
    _received.append(stop)
    raise stop


def checkpoint() -> None:
    """Raise the first recorded signal's exception, if one arrived, so that no output is
    moved in after the user asked to stop."""
    if _received:
        raise _received[0]


@contextmanager
def handlers() -> Iterator[None]:
    """Install the recording SIGTERM and SIGINT handlers for a command (in the main thread
    only; SIGINT only in place of Python's own handler); an error that ends the command after
    a signal (a ``SystemError`` out of a compiled call) ends it as the signal's exception."""
    _received.clear()
    previous = {}
    if threading.current_thread() is threading.main_thread():
        previous[signal.SIGTERM] = signal.signal(signal.SIGTERM, _on_signal)
        if signal.getsignal(signal.SIGINT) is signal.default_int_handler:
            previous[signal.SIGINT] = signal.signal(signal.SIGINT, _on_signal)
    try:
        yield
        checkpoint()
    except Exception as exc:
        if _received:
            raise _received[0] from exc
        raise
    finally:
        _received.clear()
        for signum, handler in previous.items():
            signal.signal(signum, handler)

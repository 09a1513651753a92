"""SIGINT and SIGTERM held while a compiled kernel runs, delivered when it returns.

numba hands a kernel's results back by boxing them, which runs a little Python: a signal's
exception raised there ends the call as a ``SystemError`` or crashes the process (a
segmentation fault, 5 times in 6 for ``lusm simulate --duration 2`` interrupted while its
kernel ran). While held, the signals are only recorded; the outermost hold restores the
handlers and then delivers the first one. A kernel never looks at signals, so nothing becomes
slower to interrupt. Only the main thread sets handlers; elsewhere this is a no-op.
"""

from __future__ import annotations

import signal
import threading

HELD = (signal.SIGINT, signal.SIGTERM)
"""The signals held back."""

_caught: list[int] = []
"""Signals received while held (delivered by the outermost hold)."""
_depth = [0]
"""Holds in force: an inner one (the steady engine holds once per point around its ~20
kernel calls) costs a counter, not two handler swaps."""


def _record(signum, frame) -> None:  # pragma: no cover - exercised by signals
    _caught.append(signum)


class deferred_signals:  # noqa: N801 - used as a function: ``with deferred_signals():``
    """Hold SIGINT and SIGTERM for the block; deliver the first one received afterwards."""

    def __enter__(self) -> None:
        self.main = threading.current_thread() is threading.main_thread()
        _depth[0] += self.main
        first = self.main and _depth[0] == 1  # an inner hold: the outermost delivers
        self.previous = [signal.signal(s, _record) for s in HELD] if first else None

    def __exit__(self, *exc) -> None:
        _depth[0] -= self.main
        if self.previous is None:
            return
        for s, handler in zip(HELD, self.previous, strict=True):
            signal.signal(s, handler)
        if _caught:
            signum = _caught[0]
            _caught.clear()
            handler = self.previous[HELD.index(signum)]
            if callable(handler):
                handler(signum, None)  # Python's default_int_handler, or the caller's own
            elif handler == signal.SIG_DFL:
                signal.raise_signal(signum)  # the default action: the process ends


def call_held(kernel, *args):
    """``kernel(*args)`` with SIGINT and SIGTERM held (:class:`deferred_signals`)."""
    with deferred_signals():
        return kernel(*args)

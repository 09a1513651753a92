"""Ctrl-C and SIGTERM held back while a compiled kernel runs, and delivered when it returns.

numba hands a kernel's results back by boxing them, and boxing runs a little Python (numba's
``_numba_unpickle``). A signal that arrived while the kernel ran is handled right there, at the
first Python bytecode: its ``KeyboardInterrupt`` is raised inside numba's boxing, which does not
expect one. The call then ends as a ``SystemError`` ("returned a result with an exception
set") or, with ``lusm simulate --duration 2`` interrupted after 1.2 s, in a segmentation fault
(8 times out of 8). While a kernel runs, :func:`deferred_signals` replaces the SIGINT and
SIGTERM handlers by one that only records the signal, then restores them and hands the
recorded signal to the restored handler once the results are back in Python.

A kernel never looks at signals, so nothing becomes slower to interrupt. Only the main
thread can set handlers (Python runs them there); elsewhere this is a no-op.
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager

HELD = (signal.SIGINT, signal.SIGTERM)
"""The signals held back."""

_MAIN = threading.main_thread()
_caught: list[int] = []
"""Signals received while held (shared by nested holds; delivered by the outermost)."""


def _record(signum, frame) -> None:  # pragma: no cover - exercised by signals
    _caught.append(signum)


@contextmanager
def deferred_signals() -> Iterator[None]:
    """Hold SIGINT and SIGTERM for the block; deliver the first one received afterwards."""
    if threading.current_thread() is not _MAIN:
        yield
        return
    previous = _hold()
    try:
        yield
    finally:
        _release(previous)


def call_held(kernel, *args):
    """``kernel(*args)`` with SIGINT and SIGTERM held (:func:`deferred_signals` without the
    generator). Inside an outer hold (the steady engine holds once per point around its ~20
    kernel calls, 12 us each alone) it costs a counter."""
    if threading.current_thread() is not _MAIN:
        return kernel(*args)
    previous = _hold()
    try:
        return kernel(*args)
    finally:
        _release(previous)


_depth = [0]
"""Holds in force on the main thread: an inner one costs a counter, not two handler swaps."""


def _hold() -> tuple | None:
    _depth[0] += 1
    if _depth[0] > 1:
        return None
    return signal.signal(signal.SIGINT, _record), signal.signal(signal.SIGTERM, _record)


def _release(previous: tuple | None) -> None:
    _depth[0] -= 1
    if previous is None:  # an inner hold: the outermost restores and delivers
        return
    signal.signal(signal.SIGINT, previous[0])
    signal.signal(signal.SIGTERM, previous[1])
    if _caught:  # only the outermost hold gets here
        signum = _caught[0]
        _caught.clear()
        _deliver(signum, previous[0] if signum == signal.SIGINT else previous[1])


def _deliver(signum: int, handler) -> None:
    """What ``signum`` would have done under ``handler``, now that Python is in control."""
    if callable(handler):
        handler(signum, None)  # Python's default_int_handler, or the caller's own
    elif handler == signal.SIG_DFL:
        if signum == signal.SIGINT:
            raise KeyboardInterrupt
        signal.raise_signal(signum)  # the default action (SIGTERM ends the process)
    # SIG_IGN, or a handler not set from Python (None): nothing to do

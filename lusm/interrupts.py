"""Ctrl-C and SIGTERM that always stop a command, even when Python swallows the exception.

A Python signal handler runs between bytecodes of the main thread, wherever it happens to
be. When that is inside a weakref callback or a ``__del__`` (importlib's module locks use
one; so do many libraries), the exception the handler raises cannot propagate: Python
prints "Exception ignored in ..." with a traceback and carries on, and the command would
then finish and move its output in as if nothing had happened.

So the handlers here also *record* the signal. :func:`checkpoint` re-raises a recorded
signal; the commit step of every output set calls it before moving files in, and the CLI
calls it when a command returns, so a swallowed signal still ends in exit code 130 with
nothing moved in; any other exception that ends a command after a signal (a signal inside a
numba call surfaces as a ``SystemError``) is replaced by the signal's. The swallowed
exception's traceback is not printed (:data:`sys.unraisablehook` filters it; every other
unraisable exception is reported as before).
"""

from __future__ import annotations

import logging
import signal
import sys
import threading
from collections.abc import Iterator
from contextlib import contextmanager


class Terminated(BaseException):
    """SIGTERM, raised in the main thread so that cleanup (``finally``) runs."""


_pending: type[BaseException] | None = None
"""The exception of a signal received since :func:`handlers` was entered, if any."""

_outer_hook = sys.__unraisablehook__
"""The ``sys.unraisablehook`` that :func:`handlers` replaced; it reports everything else."""


def _on_sigterm(signum, frame) -> None:  # pragma: no cover - exercised by signals
    global _pending
    _pending = Terminated
    raise Terminated


def _on_sigint(signum, frame) -> None:  # pragma: no cover - exercised by signals
    global _pending
    _pending = KeyboardInterrupt
    raise KeyboardInterrupt


def _hide_swallowed_signal(unraisable) -> None:
    """``sys.unraisablehook``: drop the report of a signal's exception that Python had to
    ignore (it is recorded and re-raised at the next :func:`checkpoint`)."""
    if _pending is not None and isinstance(unraisable.exc_value, _pending):
        return
    _outer_hook(unraisable)


def import_held(name: str) -> None:
    """Import module ``name`` with SIGINT and SIGTERM held, delivered once it is done.

    A SIGTERM landing inside VTK's import (``pyvista``, about a second) crashed the
    interpreter (exit 139, found by exploratory testing of ``lusm render``) and left the
    staging folder; the handler's exception must not unwind through a half-loaded
    extension module.
    """
    import importlib

    from contact.deferred_signals import deferred_signals

    with deferred_signals():
        importlib.import_module(name)


def checkpoint() -> None:
    """Raise the recorded signal's exception (:class:`Terminated` or ``KeyboardInterrupt``),
    if one arrived, so that no output is moved in after the user asked to stop."""
    if _pending is not None:
        raise _pending


class QuietAfterSignal(logging.Filter):
    """A logging filter that drops every record once a signal is pending.

    Libraries that run an event loop in another thread (dask.distributed) log the teardown
    of their interrupted work (cancelled gathers, callbacks that lost their future) as
    errors; after the user asked to stop, those are noise, not news.
    """

    def filter(self, record: logging.LogRecord) -> bool:  # noqa: A003 - logging's name
        return _pending is None


@contextmanager
def quiet_logs_after_signal(*names: str) -> Iterator[None]:
    """Attach :class:`QuietAfterSignal` to the handlers of the loggers ``names`` (and their
    own records), for the duration of the block."""
    quiet = QuietAfterSignal()
    attached = []
    for name in names:
        logger = logging.getLogger(name)
        for target in [logger, *logger.handlers]:
            target.addFilter(quiet)
            attached.append(target)
    try:
        yield
    finally:
        for target in attached:
            target.removeFilter(quiet)


@contextmanager
def handlers() -> Iterator[None]:
    """Install the recording SIGTERM / SIGINT handlers for the duration of a command; the
    record is cleared on the way out.

    Outside the main thread (a command called from a worker) nothing is installed. SIGINT is
    only taken over from Python's own ``default_int_handler``, never from a handler someone
    else installed.
    """
    global _pending, _outer_hook
    _pending = None
    if threading.current_thread() is not threading.main_thread():
        try:
            yield
        finally:
            _pending = None
        return
    previous_term = signal.signal(signal.SIGTERM, _on_sigterm)
    previous_int = None
    if signal.getsignal(signal.SIGINT) is signal.default_int_handler:
        previous_int = signal.signal(signal.SIGINT, _on_sigint)
    previous_hook = _outer_hook = sys.unraisablehook
    sys.unraisablehook = _hide_swallowed_signal
    try:
        yield
    except BaseException as exc:
        # whatever the interruption turned into is the interruption: a signal landing in a
        # compiled (numba) call comes back as "SystemError: ... returned a result with an
        # exception set"
        if _pending is not None and not isinstance(exc, _pending):
            raise _pending from exc
        raise
    finally:
        _pending = None  # a later command (or library call) in this process starts clean
        signal.signal(signal.SIGTERM, previous_term)
        if previous_int is not None:
            signal.signal(signal.SIGINT, previous_int)
        sys.unraisablehook = previous_hook

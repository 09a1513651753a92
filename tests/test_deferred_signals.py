"""A Ctrl-C or SIGTERM that arrives while a compiled kernel runs is delivered after it returns.

numba boxes a kernel's results with a little Python; a signal handled there crashed
``lusm simulate`` (segmentation fault) or ended it as a SystemError.
"""

from __future__ import annotations

import signal
import subprocess
import sys

import pytest

from contact.deferred_signals import deferred_signals
from tests.conftest import ROOT


def test_a_signal_in_the_block_is_raised_after_it():
    ran = []
    with pytest.raises(KeyboardInterrupt):
        with deferred_signals():
            signal.raise_signal(signal.SIGINT)
            ran.append("after the signal")  # the block is not cut short
    assert ran == ["after the signal"]
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_the_callers_handler_gets_the_signal():
    seen = []
    previous = signal.signal(signal.SIGTERM, lambda s, f: seen.append(s))
    try:
        with deferred_signals():
            signal.raise_signal(signal.SIGTERM)
            assert seen == []
        assert seen == [signal.SIGTERM]
    finally:
        signal.signal(signal.SIGTERM, previous)


SCRIPT = """
import os, signal, threading
from contact.simulate import simulate
from rom.table2 import table2
simulate(table2(), 200, 14, 40e3, duration_s=1e-3, dt_s=1e-7)  # compiled (or loaded) first
threading.Timer(0.3, os.kill, (os.getpid(), signal.SIGINT)).start()
try:
    simulate(table2(), 200, 14, 40e3, duration_s=1.5, dt_s=1e-7)  # ~1.5 s in the kernel
    print("finished")
except KeyboardInterrupt:
    print("interrupted")
"""


def test_ctrl_c_during_the_event_kernel_is_a_keyboard_interrupt():
    # before: exit -11 (segmentation fault) or a SystemError out of numba's boxing
    proc = subprocess.run([sys.executable, "-c", SCRIPT], cwd=ROOT, capture_output=True,
                          text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert proc.stdout.strip() == "interrupted" and "SystemError" not in proc.stderr


def test_nested_holds_deliver_once_at_the_outermost():
    from contact.deferred_signals import call_held

    order = []

    def inner():
        signal.raise_signal(signal.SIGINT)
        order.append("inner kernel returned")

    with pytest.raises(KeyboardInterrupt):
        with deferred_signals():
            call_held(inner)
            order.append("outer block goes on")
    assert order == ["inner kernel returned", "outer block goes on"]
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler

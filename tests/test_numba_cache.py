"""The compiled kernels' disk caches go stale with the modules whose code they inline."""

from __future__ import annotations

import os
import pickle
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from tests.conftest import ROOT


@pytest.mark.slow
@pytest.mark.benchmark
def test_an_edit_of_the_state_layout_recompiles_the_event_kernel(tmp_path):
    """Swapping two scalar indices in contact/state.py (a copy of the package) kept serving
    the event kernel's old machine code from the disk cache: the velocity of the old layout
    until the cache was removed (found by exploratory testing). The probe: the velocity
    before the edit is the original source's (computed in this process), after it not."""
    pkg = tmp_path / "pkg"
    shutil.copytree(ROOT / "contact", pkg / "contact",
                    ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copytree(ROOT / "rom", pkg / "rom", ignore=shutil.ignore_patterns("__pycache__"))
    probe = textwrap.dedent("""
        from contact.simulate import simulate
        from rom import table2
        r = simulate(table2(), 200, 14, duration_s=2e-3)
        print(repr(r.steady.velocity_m_s))
    """)

    def run(cache: Path) -> str:
        env = {**os.environ, "PYTHONPATH": str(pkg), "NUMBA_CACHE_DIR": str(cache)}
        out = subprocess.run([sys.executable, "-c", probe], env=env, capture_output=True,
                             text=True, check=True, cwd=tmp_path)
        return out.stdout.strip()

    from contact.simulate import simulate
    from rom import table2

    # the original source's answer, in this process (its cache is this test run's)
    original = repr(simulate(table2(), 200, 14, duration_s=2e-3).steady.velocity_m_s)
    assert run(tmp_path / "cache") == original  # the copy's cache, from the original
    state = pkg / "contact" / "state.py"
    text = state.read_text()
    assert "(SC_MU_S, SC_MU_D, " in text
    state.write_text(text.replace("(SC_MU_S, SC_MU_D, ", "(SC_MU_D, SC_MU_S, ", 1))
    st = state.stat()
    os.utime(state, ns=(st.st_atime_ns, st.st_mtime_ns + 10**9))  # a later edit
    # the swapped indices change the answer (mu_s and mu_d trade places); a stale cache
    # kept answering the original's
    assert run(tmp_path / "cache") != original


def _index_signatures(dispatcher) -> list:
    """Signatures in the on-disk cache index of a jitted function (numba's internal layout:
    the numba version pickled, then the pickled ``(stamp, overloads)``)."""
    cache_file = getattr(getattr(dispatcher, "_cache", None), "_cache_file", None)
    path = getattr(cache_file, "_index_path", None)
    if path is None:
        pytest.skip("numba's cache index layout differs from the one this test reads")
    with open(path, "rb") as f:
        pickle.load(f)
        _, overloads = pickle.loads(f.read())
    return [key[0] for key in overloads]


@pytest.mark.slow
def test_every_contact_kernel_is_compiled_for_one_signature():
    """numba types a constant argument of a call between kernels as a literal and compiles
    the callee once more for it (integrate_switch_model from the orbit kernels costs seconds
    of every cold start). After the transient schemes and both steady levels, each kernel's
    cache index (all runs since its source last changed) holds one signature."""
    from numba.core.registry import CPUDispatcher

    from contact.simulate import simulate
    from contact.steady import orbit_kernel
    from contact.steady.engine import steady_state
    from contact.transient import event_kernel, literal_kernel
    from rom import table2

    p = table2()
    simulate(p, 200, 14, duration_s=2e-3, energy=True)
    simulate(p, 200, 14, duration_s=2e-3, method="literal")
    steady_state(p, 200, 14, coupling="paper", accuracy="fast", load_N=1.0)
    steady_state(p, 200, 14, coupling="paper", load_N=1.0)
    kernels = [obj for mod in (event_kernel, literal_kernel, orbit_kernel)
               for obj in vars(mod).values()
               if isinstance(obj, CPUDispatcher) and obj.__module__ == mod.__name__
               and obj.targetoptions.get("inline") != "always"]  # inlined: no index
    assert len(kernels) >= 25
    found = {k.__qualname__: _index_signatures(k) for k in kernels}
    several = {name: sigs for name, sigs in found.items() if len(sigs) > 1}
    assert not several


@pytest.mark.slow
def test_a_kernel_has_one_cache_stamp_whatever_is_imported_after_it():
    """The event kernel's cache is keyed the same in a process that runs only transients
    and in one that imports the orbit kernel too (which calls it): one stamp, one cache,
    not two that processes overwrite in turn."""
    probe = (
        "import contact.transient.event_kernel as ek\n"
        "before = ek.integrate_switch_model._cache._cache_file._source_stamp\n"
        "import contact.steady.orbit_kernel as ok\n"
        "after = ek.integrate_switch_model._cache._cache_file._source_stamp\n"
        "own = ok.find_orbit_compiled._cache._cache_file._source_stamp\n"
        "print(before == after, own != after)\n")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                         timeout=120, check=True)
    assert out.stdout.split() == ["True", "True"]

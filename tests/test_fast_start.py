"""The console script's start-up trims (lusm.fast_start) change no result.

Each check runs in a fresh interpreter, the only place the trims apply.
"""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

PROBE = textwrap.dedent("""
    import importlib, json, sys
    import numpy as np
    from lusm import fast_start
    loaded = fast_start.load_blas_probe()
    parent_before = "scipy.linalg" in sys.modules
    from numba.core.registry import cpu_target
    cpu_target.target_context.refresh()   # runs numba's BLAS probe
    import numba
    from numba.np import arraymath
    parent_after_probe = "scipy.linalg" in sys.modules

    @numba.njit
    def dot(a, b):
        return np.dot(a, b)

    rng = np.random.default_rng(0)
    a, b = rng.standard_normal((7, 5)), rng.standard_normal((5, 3))
    err = float(np.max(np.abs(dot(a, b) - a @ b)))
    import scipy.linalg
    lu = scipy.linalg.lu_factor(a[:5])
    same = importlib.import_module(fast_start.BLAS_PROBE) is sys.modules[fast_start.BLAS_PROBE]
    print(json.dumps(dict(loaded=loaded, parent_before=parent_before,
                          parent_after_probe=parent_after_probe, blas=arraymath._HAVE_BLAS,
                          err=err, lu_ok=bool(np.all(np.isfinite(lu[0]))), same=same)))
""")


def _run(code: str, *args: str) -> str:
    out = subprocess.run([sys.executable, "-c", code, *args], capture_output=True, text=True,
                         check=True, timeout=300)
    return out.stdout


def test_blas_probe_module_loaded_alone_serves_numba_and_scipy():
    r = json.loads(_run(PROBE))
    assert r["loaded"]
    assert not r["parent_before"] and not r["parent_after_probe"]  # the saving itself
    assert r["blas"]  # numba still found BLAS: np.dot compiles to the BLAS call
    assert r["err"] < 1e-12
    assert r["lu_ok"] and r["same"]  # SciPy imports and works afterwards


CLI = textwrap.dedent("""
    import sys
    from lusm.cli import main
    how = sys.argv.pop(1)
    sys.exit(main() if how == "script" else main(sys.argv[1:]))
""")


def test_console_script_start_gives_the_library_call_result():
    args = ["simulate", "--voltage", "150", "--preload", "14", "--duration", "0.005", "--json"]
    script = json.loads(_run(CLI, "script", *args))
    library = json.loads(_run(CLI, "library", *args))
    for key in ("steady_velocity_m_s", "motion", "events", "y_tip_min_m"):
        assert script[key] == library[key]

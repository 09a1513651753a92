"""Start-up of a fresh ``lusm`` process: what the profile of a one-shot command asked for.

A one-shot ``lusm simulate`` computes for ~0.03 s and used to spend ~0.5 s starting
(``python benchmarks/startup.py``, ``docs/contact.md`` section 5.1). Two costs are not the
project's imports and are trimmed here, only for the console script (``cli.main`` with
``argv=None``), never for library callers:

* **numba's BLAS probe.** Setting up numba's CPU target imports ``numba.np.arraymath``, which
  runs ``import scipy.linalg.cython_blas`` to learn whether ``np.dot`` may call BLAS. Python
  imports the parent package first, and ``scipy.linalg``'s ``__init__`` pulls in its whole
  namespace and SciPy's array-API layer, whose clone of NumPy's namespace touches NumPy's
  lazy submodules (``numpy.f2py``, ``numpy.testing``, ``numpy.ma``): ~0.1 s for one
  extension module. :func:`load_blas_probe` loads that one module from its file under its own
  name, so the probe finds it in ``sys.modules`` and the parent is imported only if a command
  uses it. The module object is the one SciPy would load; numba takes its function pointers
  by module name, so compiled code is unchanged.
* **The cyclic garbage collector** ran ~250 times through the ~2e5 container objects that
  importing numba and SciPy allocates (and none of which is garbage), and walked numba's
  object graph once more at exit. :func:`prepare_process` raises the young-generation
  threshold; :func:`finish_process` freezes the heap before the interpreter exits.
"""

from __future__ import annotations

import gc
import importlib.machinery
import importlib.util
import os
import sys

BLAS_PROBE = "scipy.linalg.cython_blas"
"""The module numba's target set-up imports to probe for BLAS."""

YOUNG_THRESHOLD = 100_000
"""Allocations between young-generation collections in a fresh ``lusm`` process (Python's
default is 700)."""


def load_blas_probe() -> bool:
    """Load :data:`BLAS_PROBE` without importing ``scipy.linalg``'s package namespace.

    Returns
    -------
    bool
        Whether the module was loaded here; False when it (or ``scipy.linalg``) is already
        imported, or SciPy's file layout is not the expected one (then the ordinary import
        happens later, as without this function).

    Notes
    -----
    Until ``scipy.linalg`` itself is imported and the module imported by name again, the
    attribute ``scipy.linalg.cython_blas`` does not exist; ``importlib.import_module`` (what
    numba uses) returns the module.
    """
    if BLAS_PROBE in sys.modules or "scipy.linalg" in sys.modules:
        return False
    try:
        import scipy
    except ImportError:  # numba then finds no BLAS either way
        return False
    folder = os.path.join(scipy.__path__[0], "linalg")
    for suffix in importlib.machinery.EXTENSION_SUFFIXES:
        path = os.path.join(folder, "cython_blas" + suffix)
        if not os.path.isfile(path):
            continue
        spec = importlib.util.spec_from_file_location(BLAS_PROBE, path)
        if spec is None or spec.loader is None:
            return False
        module = importlib.util.module_from_spec(spec)
        sys.modules[BLAS_PROBE] = module
        try:
            spec.loader.exec_module(module)
        except Exception:  # leave SciPy's own import to do (and report) it
            del sys.modules[BLAS_PROBE]
            return False
        return True
    return False


def prepare_process() -> None:
    """Set up a fresh console-script process (collector threshold only; no imports)."""
    gc.set_threshold(YOUNG_THRESHOLD, 50, 100)


def finish_process() -> None:
    """The process ends next: freeze the heap so its final collection does not walk it."""
    gc.freeze()

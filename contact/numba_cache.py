"""Stale numba disk caches: a compiled module's cache is keyed on its own source only."""

from __future__ import annotations

import os
from types import ModuleType


def depend_on(namespace: dict, *modules: ModuleType) -> None:
    """Make the on-disk numba cache of the functions in ``namespace`` (a module's
    ``globals()``) stale when ``modules`` change.

    numba keys a cached function on its own source file only, while the code it caches
    contains the functions it calls from other modules and the constants it imports (the
    state layout of :mod:`contact.state`): an edit of those would otherwise keep serving
    stale machine code (numba documents this limitation; swapping two ``SC_*`` indices in
    ``contact.state`` would leave ``lusm simulate`` printing the old layout's velocity until
    the cache is removed). The source stamp each cache index is checked against is extended by the
    stamps (mtime, size) of ``modules``. Relies on numba's cache internals; where they
    differ the cache behaves as numba's own.
    """
    extra = tuple((os.stat(m.__file__).st_mtime, os.stat(m.__file__).st_size)
                  for m in modules)
    own = namespace.get("__name__")
    for obj in list(namespace.values()):
        # only the module's own functions: one it imports (the orbit kernel imports the
        # event kernel's) keeps its own module's stamp, so that every process reads and
        # writes one cache of it whatever it imported first (two stamps for one cache make
        # processes that imported different modules recompile and overwrite it in turn)
        if getattr(getattr(obj, "py_func", None), "__module__", None) != own:
            continue
        cache_file = getattr(getattr(obj, "_cache", None), "_cache_file", None)
        stamp = getattr(cache_file, "_source_stamp", None)
        if stamp is not None:
            cache_file._source_stamp = (stamp, extra)

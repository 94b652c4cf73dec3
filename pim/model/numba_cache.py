"""numba's on-disk cache keyed on more source files than the compiled function's own.

numba keys a cached function on its own source file only: a kernel that compiles functions
of another file (the PIM formula, the tyre force law) would silently keep a stale compiled
version after that file is edited. :func:`stamped_cache` adds the SHA-256 of the given files
to the source stamp, so numba recompiles when any of them changes. Where no cache location is
writable, the kernel is compiled in every process instead, as ``cache=True`` would.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

from numba.core import caching

__all__ = ["stamped_cache", "cache_stamp", "files_stamp"]


def files_stamp(*files) -> str:
    """SHA-256 over the bytes of ``files`` (paths or modules)."""
    digest = hashlib.sha256()
    for f in files:
        path = Path(getattr(f, "__file__", f))
        digest.update(path.read_bytes())
    return digest.hexdigest()


def stamped_cache(*files):
    """Decorator: cache a numba dispatcher on disk under a key that covers its own file and
    ``files`` (modules or paths)."""
    stamp = files_stamp(*files)

    class Stamp:
        def get_source_stamp(self):
            return super().get_source_stamp(), stamp

    class Impl(caching.CompileResultCacheImpl):
        _locator_classes = [type(f"{cls.__name__}Stamped", (Stamp, cls), {})
                            for cls in getattr(caching.CompileResultCacheImpl,
                                               "_locator_classes", ())]

    class Cache(caching.FunctionCache):
        _impl_class = Impl

    def decorate(dispatcher):
        try:
            dispatcher._cache = Cache(dispatcher.py_func)
        except (RuntimeError, AttributeError):  # no locator for this file, or numba's
            pass                                # caching internals changed: compile always
        return dispatcher

    return decorate


def cache_stamp(dispatcher) -> object:
    """The source stamp numba stores with a dispatcher's cache (for tests and diagnostics)."""
    return dispatcher._cache._impl.locator.get_source_stamp()

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
from types import FunctionType, SimpleNamespace

from numba import njit
from numba.core import caching

__all__ = ["stamped_cache", "cache_stamp", "files_stamp", "compile_module"]


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


def compile_module(module, compiled=None, *, separate=()) -> SimpleNamespace:
    """numba versions of the functions defined in ``module``, calling each other.

    Each function of ``module`` is copied with a namespace in which the module's functions
    are their compiled versions and the names in ``compiled`` (name -> numba dispatcher: the
    plain functions the module imports, compiled by the caller) are those: the Python source
    is the one Python and numpy evaluate. They are inlined where they are called (numba's
    ``inline="always"``), except those named in ``separate``, compiled as functions of their
    own.

    Parameters
    ----------
    module : module
        Its functions hold plain arithmetic on numbers and arrays (a "formula" module).
    compiled : dict, optional
        Name -> dispatcher for the functions it imports from elsewhere.
    separate : iterable of str
        The module's functions not to inline.
    """
    namespace = dict(vars(module))
    namespace.update(compiled or {})
    out = {}
    for name, obj in vars(module).items():
        if isinstance(obj, FunctionType) and obj.__module__ == module.__name__:
            copy = FunctionType(obj.__code__, namespace, name, obj.__defaults__,
                                obj.__closure__)
            inline = "never" if name in separate else "always"
            out[name] = njit(inline=inline, error_model="numpy")(copy)
    namespace.update(out)
    return SimpleNamespace(**out)

"""A guard that keeps numba's on-disk cache honest when kernels span several modules.

numba's ``cache=True`` keys a cached function on the timestamp and size of the one file that
defines it. A kernel that calls (and inlines) functions or reads structures from *another* module
is therefore served from the cache after that other module changed: stale machine code, silently
(numba issue #6845, "cache does not detect changes in called functions"). Splitting a kernel file
into several modules makes this likely for a maintainer.

:func:`guard_cache` closes the gap. A kernel module calls it at its end with the modules its
kernels depend on::

    guard_cache(globals(), deps=("murus.rocking.dopri",))

It hashes the source of the module and of its dependencies (and the numba version); when the hash
differs from the one stored beside the module's cache, it flushes the cache of every numba
dispatcher of the module (numba's own ``flush``: the next call recompiles and re-caches) and stores
the new hash. It touches only the caches of murus's own kernels.
"""

from __future__ import annotations

import hashlib
import importlib.util
from pathlib import Path

from murus.outputs import atomic_write

__all__ = ["guard_cache", "sources_digest"]

#: Name of the file, beside a module's numba cache, holding the hash of its sources.
_STAMP_SUFFIX = ".murus-sources"


def _module_file(name: str) -> Path:
    spec = importlib.util.find_spec(name)
    if spec is None or spec.origin is None:
        raise ImportError(f"guard_cache: no source file for module {name!r}")
    return Path(spec.origin)


def sources_digest(files) -> str:
    """SHA-256 of the contents of ``files`` (in the given order) and of the numba version.

    Parameters
    ----------
    files : iterable of path-like
        Source files whose change must invalidate the cache.

    Returns
    -------
    str
        Hexadecimal digest.
    """
    import numba

    h = hashlib.sha256(f"numba {numba.__version__}\n".encode())
    for f in files:
        data = Path(f).read_bytes()
        h.update(f"{Path(f).name} {len(data)}\n".encode())
        h.update(data)
    return h.hexdigest()


def _dispatchers(namespace: dict):
    for value in list(namespace.values()):
        cache = getattr(value, "_cache", None)
        if cache is not None and hasattr(value, "py_func") and getattr(cache, "cache_path", None):
            yield value


def guard_cache(namespace: dict, deps: tuple[str, ...] = ()) -> bool:
    """Flush the numba cache of a module's kernels when it or a dependency changed.

    Parameters
    ----------
    namespace : dict
        The ``globals()`` of the kernel module; call this at the end of the module, after every
        ``@njit(cache=True)`` function is defined.
    deps : tuple of str
        Dotted names of the modules whose source the kernels compile in (called functions,
        structure layouts, constants).

    Returns
    -------
    bool
        True when the cache was flushed (the sources changed or no hash was stored yet).
    """
    here = Path(namespace["__file__"])
    files = [here] + [_module_file(d) for d in deps]
    try:
        digest = sources_digest(files)
    except OSError:
        return False
    disps = list(_dispatchers(namespace))
    paths = sorted({d._cache.cache_path for d in disps})
    flushed = False
    for path in paths:
        stamp = Path(path) / (here.stem + _STAMP_SUFFIX)
        try:
            if stamp.read_text() == digest:
                continue
        except OSError:
            pass
        for d in disps:
            if d._cache.cache_path == path:
                try:
                    d._cache.flush()
                except OSError:
                    pass
        try:
            Path(path).mkdir(parents=True, exist_ok=True)
            atomic_write(stamp, lambda tmp: tmp.write_text(digest), fsync=False)
        except OSError:
            pass
        flushed = True
    return flushed

"""Lazy package exports (PEP 562), shared by the subpackages: ``import murus.rocking`` must not
load numba, xarray or Dask until a name that needs them is used (``murus --help`` stays fast).
"""

from __future__ import annotations

from importlib import import_module


def lazy_exports(package: str, exports: dict[str, str], namespace: dict,
                 submodules: tuple[str, ...] = ()):
    """``__getattr__`` and ``__dir__`` for a package whose public names live in submodules.

    Parameters
    ----------
    package : str
        The package's ``__name__``.
    exports : dict
        Maps a public name to the submodule (relative to ``package``) defining it; a name is
        imported on first access and cached in the package ``namespace``.
    namespace : dict
        The package's ``globals()``.
    submodules : tuple of str
        Submodules reachable as attributes (``murus.motion.spectra``) without an explicit
        import: imported on first access.

    Returns
    -------
    tuple
        ``(__getattr__, __dir__)``, to assign at the end of the package's ``__init__``.

    References
    ----------
    PEP 562, "Module __getattr__ and __dir__".
    """

    def __getattr__(name: str):
        if name in exports:
            value = getattr(import_module(f"{package}.{exports[name]}"), name)
            namespace[name] = value
            return value
        if name in submodules:
            return import_module(f"{package}.{name}")
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    def __dir__():
        return sorted(set(namespace) | set(exports) | set(submodules))

    return __getattr__, __dir__

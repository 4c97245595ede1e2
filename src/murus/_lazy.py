"""Lazy package exports (PEP 562), shared by the subpackages: ``import murus.rocking`` must not
load numba, xarray or Dask until a name that needs them is used (``murus --help`` stays fast).
"""

from __future__ import annotations

from importlib import import_module


def lazy_exports(package: str, exports: dict[str, str], namespace: dict):
    """``__getattr__`` and ``__dir__`` for a package whose public names live in submodules.

    ``exports`` maps a public name to the submodule (relative to ``package``) defining it; a
    name is imported on first access and cached in the package ``namespace``."""

    def __getattr__(name: str):
        if name in exports:
            value = getattr(import_module(f"{package}.{exports[name]}"), name)
            namespace[name] = value
            return value
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    def __dir__():
        return sorted(set(namespace) | set(exports))

    return __getattr__, __dir__

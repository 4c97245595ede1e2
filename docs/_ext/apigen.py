"""Generate the API reference pages at build time (Sphinx extension).

Walks the ``murus`` package with :func:`pkgutil.walk_packages` and writes one page per public
module (no name component starting with ``_``) under ``docs/api/``: a new subpackage or module
appears in the reference without being listed anywhere. A package page shows its docstring, a
table of the names in its ``__all__`` (linked to the module that defines each) and its
submodules; a module page documents the module's own members (autodoc, numpydoc docstrings).
The pages are rewritten only when their text changes, so incremental builds stay incremental.
"""

from __future__ import annotations

import importlib
import pkgutil
from pathlib import Path

PACKAGE = "murus"


def _public(name: str) -> bool:
    return not any(part.startswith("_") for part in name.split("."))


def discover(package: str = PACKAGE) -> tuple[list[str], set[str]]:
    """All public modules of ``package`` (sorted) and the set of those that are packages."""
    root = importlib.import_module(package)
    names = [package]
    packages = {package}
    for info in pkgutil.walk_packages(root.__path__, prefix=package + "."):
        if not _public(info.name):
            continue
        names.append(info.name)
        if info.ispkg:
            packages.add(info.name)
    return sorted(names), packages


def _title(name: str) -> str:
    text = f"``{name}``"
    return f"{text}\n{'=' * len(text)}\n"


def _canonical(package: str, name: str) -> str | None:
    """``module.name`` where ``package.name`` is defined, or None when it cannot be resolved."""
    try:
        obj = getattr(importlib.import_module(package), name)
    except Exception:  # noqa: BLE001 - an optional extra missing: list it without a link
        return None
    module = getattr(obj, "__module__", None)
    if not isinstance(module, str) or not module.startswith(PACKAGE):
        return None
    if not _public(module):
        return None
    return f"{module}.{name}"


def package_page(name: str, modules: list[str]) -> str:
    mod = importlib.import_module(name)
    children = [m for m in modules if m.rpartition(".")[0] == name]
    exported = list(getattr(mod, "__all__", []) or [])
    # the package's own objects: those of __all__ defined in its __init__, or, without __all__,
    # every public object defined there (e.g. ``murus.G``)
    own = [item for item in exported if _canonical(name, item) == f"{name}.{item}"]
    if own:
        members = f"   :members: {', '.join(own)}\n"
    elif not exported:
        members = "   :members:\n"
    else:
        members = "   :no-members:\n"
    lines = [_title(name), f".. automodule:: {name}\n{members}"]
    if exported:
        lines.append("Public names\n------------\n")
        lines.append(".. list-table::\n   :widths: 40 60\n   :header-rows: 1\n")
        lines.append("   * - name\n     - defined in\n")
        for item in exported:
            target = _canonical(name, item)
            if target is None:
                lines.append(f"   * - ``{name}.{item}``\n     - \n")
            else:
                module = target.rpartition(".")[0]
                lines.append(f"   * - :py:obj:`~{target}`\n     - :py:mod:`{module}`\n")
        lines.append("")
    if children:
        lines.append("Modules\n-------\n")
        lines.append(".. toctree::\n   :maxdepth: 1\n")
        for child in children:
            lines.append(f"   {child}")
        lines.append("")
    return "\n".join(lines) + "\n"


def module_page(name: str) -> str:
    return (_title(name)
            + f"\n.. automodule:: {name}\n   :members:\n   :show-inheritance:\n")


def generate(outdir: Path, package: str = PACKAGE) -> list[str]:
    """Write the pages into ``outdir``; remove pages of modules that no longer exist."""
    outdir.mkdir(parents=True, exist_ok=True)
    modules, packages = discover(package)
    wanted = {}
    for name in modules:
        wanted[name] = package_page(name, modules) if name in packages else module_page(name)
    for path in outdir.glob("*.rst"):
        if path.stem not in wanted:
            path.unlink()
    for name, text in wanted.items():
        path = outdir / f"{name}.rst"
        if not path.exists() or path.read_text() != text:
            path.write_text(text)
    return modules


def _on_builder_inited(app):
    generate(Path(app.srcdir) / "api")


def setup(app):
    app.connect("builder-inited", _on_builder_inited)
    return {"parallel_read_safe": True, "parallel_write_safe": True}

"""Write the intersphinx inventories of python, numpy, scipy, xarray and matplotlib offline.

The documentation build never touches the network: ``docs/conf.py`` reads only the ``*.inv``
files of this folder. Where the projects' own ``objects.inv`` can be downloaded, prefer them::

    python docs/_intersphinx/make_inventories.py --download   # needs network access

Without network access (the build machines of murus), this script builds small inventories
from the installed packages instead (``python docs/_intersphinx/make_inventories.py``): it lists
the public modules, classes, functions and methods by introspection and maps each to the page
where the project's documentation puts it (the URL layouts of numpy, scipy, xarray, matplotlib
and the Python library as of 2025). A link to a page the real inventory would place elsewhere
is the price of working offline; the names and modules are exactly those of the installed
versions. Run it again after upgrading a package, and commit the ``*.inv`` files.
"""

from __future__ import annotations

import argparse
import builtins
import importlib
import inspect
import sys
import urllib.request
import zlib
from pathlib import Path

HERE = Path(__file__).resolve().parent

URLS = {
    "python": "https://docs.python.org/3/",
    "numpy": "https://numpy.org/doc/stable/",
    "scipy": "https://docs.scipy.org/doc/scipy/",
    "xarray": "https://docs.xarray.dev/en/stable/",
    "matplotlib": "https://matplotlib.org/stable/",
}


def _public(obj) -> list[tuple[str, object]]:
    names = getattr(obj, "__all__", None) or [n for n in dir(obj) if not n.startswith("_")]
    out = []
    for name in names:
        try:
            out.append((name, getattr(obj, name)))
        except Exception:  # noqa: BLE001 - lazy attributes that fail to import
            continue
    return out


def _role(obj) -> str | None:
    if inspect.ismodule(obj):
        return None
    if inspect.isclass(obj):
        return "py:exception" if issubclass(obj, BaseException) else "py:class"
    if callable(obj):
        return "py:function"
    return None


def _members(qual: str, cls, page) -> list[tuple[str, str, str]]:
    rows = []
    for name, value in vars(cls).items():
        if name.startswith("_"):
            continue
        if callable(value) or isinstance(value, (staticmethod, classmethod)):
            rows.append((f"{qual}.{name}", "py:method", page(f"{qual}.{name}")))
        elif isinstance(value, property):
            rows.append((f"{qual}.{name}", "py:attribute", page(f"{qual}.{name}")))
    return rows


def _module_rows(modname: str, page, modpage, classes_members=()) -> list[tuple[str, str, str]]:
    mod = importlib.import_module(modname)
    rows = [(modname, "py:module", modpage(modname))]
    for name, value in _public(mod):
        role = _role(value)
        if role is None:
            continue
        qual = f"{modname}.{name}"
        rows.append((qual, role, page(qual)))
        if role == "py:class" and name in classes_members:
            rows += _members(qual, value, page)
    return rows


def numpy_rows():
    page = lambda q: f"reference/generated/{q}.html#{q}"  # noqa: E731
    modpage = lambda m: f"reference/routines.{m.partition('.')[2] or 'html'}.html#module-{m}"  # noqa: E731
    rows = _module_rows("numpy", page, lambda m: "reference/index.html#module-numpy",
                        classes_members=("ndarray", "dtype"))
    for sub in ("numpy.random", "numpy.fft", "numpy.linalg", "numpy.polynomial"):
        rows += _module_rows(sub, page, modpage, classes_members=("Generator",))
    # the glossary term and label that numpydoc's default type aliases point to
    rows.append(("array_like", "std:term", "glossary.html#term-array_like"))
    rows.append(("arrays.scalars", "std:label", "reference/arrays.scalars.html#$", "Scalars"))
    for const in ("inf", "nan", "pi", "e", "newaxis"):
        rows.append((f"numpy.{const}", "py:data", f"reference/constants.html#numpy.{const}"))
    return rows


def scipy_rows():
    page = lambda q: f"reference/generated/{q}.html#{q}"  # noqa: E731
    modpage = lambda m: f"reference/{m.partition('.')[2]}.html#module-{m}"  # noqa: E731
    rows = [("scipy", "py:module", "reference/index.html#module-scipy")]
    for sub in ("integrate", "interpolate", "optimize", "signal", "stats", "fft", "linalg",
                "sparse", "spatial", "special", "ndimage"):
        rows += _module_rows(f"scipy.{sub}", page, modpage)
    return rows


def xarray_rows():
    page = lambda q: f"generated/{q}.html#{q}"  # noqa: E731
    return _module_rows("xarray", page, lambda m: "api.html#module-xarray",
                        classes_members=("Dataset", "DataArray"))


def matplotlib_rows():
    page = lambda q: f"api/_as_gen/{q}.html#{q}"  # noqa: E731
    modpage = lambda m: f"api/{m.partition('.')[2]}_api.html#module-{m}"  # noqa: E731
    rows = [("matplotlib", "py:module", "api/matplotlib_configuration_api.html#module-matplotlib")]
    rows += _module_rows("matplotlib.pyplot", page,
                         lambda m: "api/pyplot_summary.html#module-matplotlib.pyplot")
    import matplotlib.axes
    import matplotlib.figure
    rows.append(("matplotlib.axes", "py:module", "api/axes_api.html#module-matplotlib.axes"))
    rows.append(("matplotlib.axes.Axes", "py:class", "api/axes_api.html#matplotlib.axes.Axes"))
    rows += _members("matplotlib.axes.Axes", matplotlib.axes.Axes, page)
    rows.append(("matplotlib.figure", "py:module", modpage("matplotlib.figure")))
    rows.append(("matplotlib.figure.Figure", "py:class",
                 "api/_as_gen/matplotlib.figure.Figure.html#matplotlib.figure.Figure"))
    rows += _members("matplotlib.figure.Figure", matplotlib.figure.Figure, page)
    return rows


def python_rows():
    rows = []
    stdtypes = {"dict", "list", "tuple", "str", "bytes", "set", "frozenset", "range",
                "memoryview", "bytearray"}
    for name, value in vars(builtins).items():
        if name.startswith("_"):
            continue
        if inspect.isclass(value) and issubclass(value, BaseException):
            rows.append((name, "py:exception", f"library/exceptions.html#{name}"))
        elif inspect.isclass(value):
            where = "stdtypes" if name in stdtypes else "functions"
            rows.append((name, "py:class", f"library/{where}.html#{name}"))
        elif callable(value):
            rows.append((name, "py:function", f"library/functions.html#{name}"))
    rows.append(("None", "py:data", "library/constants.html#None"))
    for const in ("True", "False", "Ellipsis", "NotImplemented"):
        rows.append((const, "py:data", f"library/constants.html#{const}"))
    # the labels and glossary terms that numpydoc's default type aliases point to
    rows.append(("bltin-boolean-values", "std:label", "library/stdtypes.html#$",
                 "Boolean Values"))
    for term in ("function", "iterable", "sequence", "generator", "mapping", "callable",
                 "path-like object", "file object"):
        rows.append((term, "std:term", f"glossary.html#term-{term.replace(' ', '-')}"))
    page_of = {}
    for modname in ("os", "os.path", "pathlib", "json", "functools", "dataclasses", "typing",
                    "concurrent.futures", "multiprocessing", "signal", "tempfile", "shutil",
                    "hashlib", "warnings", "collections", "collections.abc", "itertools", "math",
                    "enum", "io", "logging", "subprocess", "threading", "time", "datetime",
                    "contextlib"):
        page_of[modname] = f"library/{modname}.html"
        rows += _module_rows(
            modname, lambda q, m=modname: f"library/{m}.html#{q}",
            lambda m: f"library/{m}.html#module-{m}",
            classes_members=("Path", "Executor", "Future", "ProcessPoolExecutor"))
    return rows


def write(project: str, version: str, rows) -> Path:
    seen = set()
    lines = []
    for name, role, uri, *disp in rows:
        if (name, role) in seen:
            continue
        seen.add((name, role))
        if uri.endswith("#" + name):
            uri = uri[: -len(name)] + "$"
        prio = -1 if role.startswith("std:") else 1
        lines.append(f"{name} {role} {prio} {uri} {disp[0] if disp else '-'}")
    header = (f"# Sphinx inventory version 2\n# Project: {project}\n# Version: {version}\n"
              "# The remainder of this file is compressed using zlib.\n").encode()
    path = HERE / f"{project}.inv"
    path.write_bytes(header + zlib.compress("\n".join(sorted(lines)).encode() + b"\n", 9))
    return path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--download", action="store_true",
                        help="download the projects' own objects.inv (network access)")
    args = parser.parse_args()
    if args.download:
        for project, url in URLS.items():
            with urllib.request.urlopen(url + "objects.inv", timeout=30) as resp:
                (HERE / f"{project}.inv").write_bytes(resp.read())
            print(f"{project}: downloaded")
        return
    builders = {"python": python_rows, "numpy": numpy_rows, "scipy": scipy_rows,
                "xarray": xarray_rows, "matplotlib": matplotlib_rows}
    for project, build in builders.items():
        version = (sys.version.split()[0] if project == "python"
                   else importlib.import_module(project).__version__)
        rows = build()
        path = write(project, version, rows)
        print(f"{project} {version}: {len(rows)} objects -> {path.name} "
              f"({path.stat().st_size} bytes)")


if __name__ == "__main__":
    main()

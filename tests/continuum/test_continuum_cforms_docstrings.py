"""The public API of the continuum closed forms, VTK writer and plots has numpydoc docstrings
with Parameters (when it takes any), Returns (functions) and References sections (issue 16
item 5 style; tests/test_docstrings.py does not list murus.continuum yet)."""

from __future__ import annotations

import importlib
import inspect
import re

import pytest

MODULES = ["murus.continuum.closed_forms", "murus.continuum.vtk", "murus.continuum.plots"]


def _section(doc: str, name: str) -> bool:
    return re.search(rf"^\s*{name}\s*\n\s*-{{3,}}\s*$", doc, re.M) is not None


def _public():
    for mod_name in MODULES:
        mod = importlib.import_module(mod_name)
        for name in mod.__all__:
            obj = getattr(mod, name)
            if inspect.isfunction(obj) or (inspect.isclass(obj)
                                           and not issubclass(obj, BaseException)):
                yield f"{mod_name}.{name}", obj


@pytest.mark.parametrize("name,obj", list(_public()))
def test_numpydoc_sections(name, obj):
    doc = inspect.getdoc(obj) or ""
    params = [p for p in inspect.signature(obj).parameters if p not in ("self", "cls")]
    if inspect.isclass(obj):
        assert _section(doc, "Attributes") or _section(doc, "Parameters"), name
        return
    if params:
        assert _section(doc, "Parameters"), name
        for p in params:
            assert re.search(rf"^\s*(\*\*)?{p}\b", doc, re.M) or f", {p}" in doc, (name, p)
    assert _section(doc, "Returns"), name
    assert _section(doc, "References"), name


def test_the_walk_sees_the_api():
    names = {n for n, _ in _public()}
    assert len(names) >= 20
    assert "murus.continuum.closed_forms.hole_displacement" in names

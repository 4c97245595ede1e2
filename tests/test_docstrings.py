"""The public API has numpydoc docstrings (issue 16 item 5), so that the documentation site can
be generated from them: every public function and class that the murus packages export (their
``__all__``) has a docstring, and one with a ``Parameters`` section when it takes parameters
(for a class, the parameters of its constructor; a dataclass may document its fields in an
``Attributes`` section instead, as numpydoc allows). numpydoc's own validator is not a
dependency: the sections are found by their underlined headers.
"""

from __future__ import annotations

import importlib
import inspect
import re

PACKAGES = ["murus", "murus.motion", "murus.eurocode", "murus.rocking", "murus.dem",
            "murus.retaining", "murus.identify", "murus.studies",
            # murus.eurocode exports nothing itself and murus.motion little: the public API of
            # these two is the ``__all__`` of their modules
            "murus.eurocode.ec6", "murus.eurocode.ec8", "murus.eurocode.ec8_5", "murus.motion.core",
            "murus.motion.io", "murus.motion.spectra", "murus.motion.measures",
            "murus.motion.processing", "murus.motion.synthetic", "murus.motion.artificial",
            "murus.continuum", "murus.continuum.mesh", "murus.continuum.closed_forms",
            "murus.continuum.vtk", "murus.continuum.plots", "murus.continuum.freefield",
            "murus.continuum.interface", "murus.continuum.coupled", "murus.limit"]

#: Names whose docstrings are not converted yet, by module (empty: all converted, issue 16 item 5).
PENDING = {}


def _section(doc: str, name: str) -> bool:
    return re.search(rf"^\s*{name}\s*\n\s*-{{3,}}\s*$", doc, re.M) is not None


def _public():
    seen = {}
    for pkg in PACKAGES:
        mod = importlib.import_module(pkg)
        for name in getattr(mod, "__all__", []):
            obj = getattr(mod, name)
            if not (inspect.isfunction(obj) or inspect.isclass(obj)):
                continue
            if inspect.isclass(obj) and issubclass(obj, BaseException):
                continue  # errors: their message is their documentation
            seen.setdefault((obj.__module__, obj.__qualname__), obj)
    return seen


def _parameters(obj) -> list[str]:
    try:
        sig = inspect.signature(obj)
    except (TypeError, ValueError):
        return []
    return [p.name for p in sig.parameters.values() if p.name not in ("self", "cls")]


def _problem(obj) -> str | None:
    doc = inspect.getdoc(obj) or ""
    if not doc.strip():
        return "no docstring"
    if not _parameters(obj):
        return None
    if _section(doc, "Parameters"):
        return None
    if inspect.isclass(obj) and _section(doc, "Attributes"):
        return None
    return "no Parameters section"


def test_public_api_has_numpydoc_parameters():
    bad = []
    for (module, qualname), obj in sorted(_public().items()):
        if qualname in PENDING.get(module, ()):
            continue
        why = _problem(obj)
        if why:
            bad.append(f"{module}.{qualname}: {why}")
    assert not bad, "\n".join(bad)


def test_the_walk_sees_the_api():
    """The check is not vacuous: it walks the exported functions and classes (more than a
    hundred) and tells a docstring without the section from one with it."""
    names = {f"{m}.{q}" for m, q in _public()}
    assert len(names) > 100
    assert {"murus.rocking.body.RigidBlock", "murus.eurocode.ec8.elastic_spectrum"} <= names

    def f(x):
        """Summary only."""

    def g(x):
        """Summary.

        Parameters
        ----------
        x : float
            A length [m].
        """

    assert _problem(f) == "no Parameters section" and _problem(g) is None


def test_pending_names_exist():
    """A pending name that no longer exists is removed from the list (it would hide nothing)."""
    missing = [f"{m}.{n}" for m, names in PENDING.items() for n in names
               if not hasattr(importlib.import_module(m), n)]
    assert not missing, missing

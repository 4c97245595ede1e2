"""A short hash of murus's own source code, blind to its documentation: what keys the cached
validation runs (``validation/runcache.py``) and the checkpoints of long runs
(:func:`murus.retaining.collapse.collapse_run`), so that a change of code invalidates them and a
change of a docstring or a comment does not."""

from __future__ import annotations

from pathlib import Path

#: Modules that do not compute (command lines, figures, case files, verification tables, the
#: calibration of the DEM's contact damping), left out of :func:`source_key` unless named.
NOT_ENGINE = ("cli.py", "plots.py", "vtk.py", "case.py", "coupled_case.py", "verify.py",
              "study.py", "closed_forms.py", "rocking_damping.py")


def source_key(*packages: str, root: Path | None = None,
               exclude: tuple[str, ...] = NOT_ENGINE) -> str:
    """A short hash of the source of ``packages`` (sub-packages of murus, e.g. ``"dem"``,
    ``"continuum"``, or modules, ``"motion/synthetic.py"``): the syntax tree of every module
    with its docstrings removed, so that a change of code changes the key and a change of
    documentation or comments does not. Modules of a package named in ``exclude`` are left
    out.

    Parameters
    ----------
    *packages : str
        Sub-packages or modules, relative to ``root``.
    root : path-like, optional
        The folder holding them (default: the installed ``murus`` package).
    exclude : tuple of str
        File names left out of the packages (not of modules named explicitly).

    Returns
    -------
    str
        16 hexadecimal digits.
    """
    import ast
    import hashlib

    src = Path(__file__).resolve().parent if root is None else Path(root)
    h = hashlib.sha256()
    for pkg in sorted(packages):
        base = src / pkg
        if base.is_dir():
            files = [f for f in sorted(base.rglob("*.py")) if f.name not in exclude]
        else:
            files = [base if pkg.endswith(".py") else src / f"{pkg}.py"]
        for f in files:
            tree = ast.parse(f.read_text())
            for node in ast.walk(tree):
                body = getattr(node, "body", None)
                if (isinstance(body, list) and body and isinstance(body[0], ast.Expr)
                        and isinstance(body[0].value, ast.Constant)
                        and isinstance(body[0].value.value, str)):
                    body[0] = ast.Pass()
            h.update(str(f.relative_to(src)).encode())
            h.update(ast.dump(tree).encode())
    return h.hexdigest()[:16]

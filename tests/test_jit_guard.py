"""The numba cache guard: a kernel whose callee lives in another module is recompiled when the
callee changes (numba alone serves the stale cached code, numba issue #6845)."""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

A = """
from numba import njit
from pkgx.b import g
from murus._jit import guard_cache

@njit(cache=True)
def f(x):
    return g(x) + 1.0

FLUSHED = {guard}
"""

B = """
from numba import njit

@njit(cache=True)
def g(x):
    return {k} * x
"""


def _write(root: Path, guard: bool, k: float):
    pkg = root / "pkgx"
    pkg.mkdir(exist_ok=True)
    (pkg / "__init__.py").write_text("")
    g = 'guard_cache(globals(), deps=("pkgx.b",))' if guard else "False"
    (pkg / "a.py").write_text(A.format(guard=g))
    (pkg / "b.py").write_text(B.format(k=k))
    # numba compares the timestamp and size of the defining file; keep b.py's size equal and
    # move its mtime forward so that only the guard can tell the difference in a.py's cache
    t = time.time() + 2.0
    os.utime(pkg / "b.py", (t, t))


def _run(root: Path) -> tuple[float, bool]:
    src = str(Path(__file__).resolve().parents[1] / "src")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(root), src]))
    out = subprocess.run(
        [sys.executable, "-c", "import pkgx.a as a; print(a.f(2.0), a.FLUSHED)"],
        env=env, capture_output=True, text=True, check=True, cwd=root,
    ).stdout.split()
    return float(out[0]), out[1] == "True"


def test_guard_recompiles_after_a_callee_changed(tmp_path):
    _write(tmp_path, guard=True, k=3.0)
    assert _run(tmp_path) == (7.0, True)        # first import: no stamp yet, compiled
    assert _run(tmp_path) == (7.0, False)       # unchanged: served from the cache
    (tmp_path / "pkgx" / "b.py").write_text(B.format(k=5.0))
    assert _run(tmp_path) == (11.0, True)       # callee changed: flushed and recompiled


def test_without_the_guard_numba_serves_stale_code(tmp_path):
    """Why the guard exists. If a numba release fixes this, this test fails and the guard can go."""
    _write(tmp_path, guard=False, k=3.0)
    assert _run(tmp_path)[0] == 7.0
    (tmp_path / "pkgx" / "b.py").write_text(B.format(k=5.0))
    assert _run(tmp_path)[0] == 7.0             # stale: still 3 x + 1

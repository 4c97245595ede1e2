"""Small structured meshes for the continuum tests (no dependence on murus.continuum.mesh)."""

from __future__ import annotations

import numpy as np


def rect_mesh(nx: int, ny: int, width: float, height: float, x0: float = 0.0,
              y0: float = 0.0):
    """A rectangle of nx by ny zones: gridpoints (ng, 2) [m], zones (nz, 4) counter-clockwise,
    gridpoint (i, j) at index j (nx + 1) + i, zone (i, j) at index j nx + i."""
    xs = x0 + np.linspace(0.0, width, nx + 1)
    ys = y0 + np.linspace(0.0, height, ny + 1)
    X, Y = np.meshgrid(xs, ys)
    xy = np.column_stack([X.ravel(), Y.ravel()])
    i, j = np.meshgrid(np.arange(nx), np.arange(ny))
    a = (j * (nx + 1) + i).ravel()
    zones = np.column_stack([a, a + 1, a + nx + 2, a + nx + 1]).astype(np.int64)
    return xy, zones


def sides(xy, tol=1e-9):
    """Masks of the gridpoints on the left, right, bottom and top sides."""
    x, y = xy[:, 0], xy[:, 1]
    return (np.abs(x - x.min()) < tol, np.abs(x - x.max()) < tol,
            np.abs(y - y.min()) < tol, np.abs(y - y.max()) < tol)

"""The disc lattices of murus.dem.packing (closed forms) and the old import paths."""

import math

import numpy as np
import pytest

from murus.dem.packing import PackingError, check_overlap, disc_grid, solid_fraction


def test_square_lattice():
    c, r, pitch = disc_grid((0.02, 0.03), seed=5, lattice="square", n=23, columns=4)
    assert pitch == pytest.approx(2 * 0.03 * 1.02, rel=1e-15)
    assert c.shape == (23, 2) and np.all((r >= 0.02) & (r <= 0.03))
    # rows of 4 from half a pitch off the origin
    assert np.allclose(c[5], (1.5 * pitch, 1.5 * pitch), rtol=1e-14)
    check_overlap(c, r)
    c2, r2, _ = disc_grid((0.02, 0.03), seed=5, lattice="square", n=23, columns=4)
    assert np.array_equal(c, c2) and np.array_equal(r, r2)  # a pure function of the seed


def test_hex_lattice_in_a_rectangle():
    rmax, gap = 0.05, 0.02
    c, r, pitch = disc_grid((0.04, rmax), seed=1, gap=gap, lattice="hex", floor=0.0, top=1.0,
                            left=lambda z: 0.0, right=1.0, ceiling=lambda x: 1.0)
    clear = rmax * (1 + gap)
    dz = pitch * math.sqrt(3) / 2
    rows = math.floor((1.0 - 2 * clear) / dz) + 1
    even = math.floor((1.0 - 2 * clear) / pitch) + 1
    odd = math.floor((1.0 - 2 * clear - 0.5 * pitch) / pitch) + 1
    assert len(c) == (rows + 1) // 2 * even + rows // 2 * odd
    from scipy.spatial import cKDTree

    d, _ = cKDTree(c).query(c, k=2)
    assert d[:, 1] == pytest.approx(pitch, rel=1e-12)  # every neighbour one pitch away
    check_overlap(c, r)


def test_overlap_and_fraction():
    with pytest.raises(PackingError, match="overlap"):
        check_overlap([[0.0, 0.0], [0.03, 0.0]], [0.02, 0.02])
    # one disc in a window, sampled at the cell midpoints of a grid of a tenth of the radius:
    # exactly the share of midpoints inside the circle, and within the area of the cells the
    # circle crosses (at most 8 r / h + 4 of them) of the exact pi r^2 / area
    r, h = 0.2, 0.02
    phi = solid_fraction([[0.5, 0.5]], [r], (0.0, 1.0, 0.0, 1.0))
    mid = np.arange(0.5 * h, 1.0, h)
    X, Z = np.meshgrid(mid, mid)
    assert phi == np.mean((X - 0.5) ** 2 + (Z - 0.5) ** 2 < r**2)
    assert abs(phi - math.pi * r**2) <= (8 * r / h + 4) * h**2


def test_old_import_paths():
    from murus.dem import boundary, packing
    from murus.retaining import backfill

    assert backfill.AbsorbingBoundary is boundary.AbsorbingBoundary
    assert backfill.wall_thrust is boundary.wall_thrust
    assert backfill.check_overlap is packing.check_overlap
    assert backfill.solid_fraction is packing.solid_fraction
    assert backfill.BackfillError is packing.PackingError

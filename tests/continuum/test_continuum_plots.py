"""Figures of the zones: built with Agg, checked by their collections (no pixel comparison)."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.collections import LineCollection, PolyCollection  # noqa: E402
from matplotlib.colors import to_rgba  # noqa: E402

from murus.continuum.plots import plot_plastic_state, plot_zones, state_label  # noqa: E402


def _mesh(nx=3, ny=2):
    x, y = np.meshgrid(np.linspace(0, 3, nx + 1), np.linspace(0, 2, ny + 1))
    xy = np.column_stack([x.ravel(), y.ravel()])
    zones = []
    for j in range(ny):
        for i in range(nx):
            a = j * (nx + 1) + i
            zones.append([a, a + 1, a + nx + 2, a + nx + 1])
    return xy, np.array(zones)


def _polys(ax):
    return [c for c in ax.collections if isinstance(c, PolyCollection)]


def test_zones_coloured_by_a_field_on_the_deformed_mesh():
    xy, zones = _mesh()
    nz = len(zones)
    syy = -np.arange(nz, dtype=float) * 1e4
    disp = np.column_stack([0.001 * xy[:, 1], -0.002 * xy[:, 0]])
    blocks = [np.array([[3.2, 0], [3.7, 0], [3.7, 1.0], [3.2, 1.0]]),
              np.array([[3.2, 1.0], [3.7, 1.0], [3.7, 2.0], [3.2, 2.0]])]
    ax = plot_zones(xy, zones, syy, displacement=disp, magnification=100.0, blocks=blocks,
                    label="syy [Pa]", show_original=True)
    zc, bc = _polys(ax)
    assert len(zc.get_paths()) == nz and len(bc.get_paths()) == 2
    np.testing.assert_array_equal(zc.get_array(), syy)
    assert zc.norm.vmin == syy.min() and zc.norm.vmax == syy.max()
    assert zc.colorbar is not None and zc.colorbar.ax.get_ylabel() == "syy [Pa]"
    # the deformed positions, magnified
    moved = xy + 100.0 * disp
    np.testing.assert_allclose(zc.get_paths()[4].vertices[:4], moved[zones[4]], rtol=1e-15)
    # the undeformed mesh: one closed ring of 5 vertices per zone
    (lines,) = [c for c in ax.collections if isinstance(c, LineCollection)]
    segs = lines.get_segments()
    assert len(segs) == nz
    np.testing.assert_array_equal(segs[4], xy[np.r_[zones[4], zones[4][0]]])
    # rendering works (Agg), the colours are those of the values
    ax.figure.canvas.draw()
    fc = zc.get_facecolors()
    assert len(fc) == nz and len({tuple(c) for c in fc}) == nz
    plt.close(ax.figure)


def test_plain_mesh_has_no_colour_bar():
    xy, zones = _mesh(2, 2)
    ax = plot_zones(xy, zones)
    (zc,) = _polys(ax)
    assert zc.get_array() is None and zc.colorbar is None
    np.testing.assert_array_equal(zc.get_facecolors(), [to_rgba("white")])
    plt.close(ax.figure)


def test_plastic_state_categories_and_legend():
    xy, zones = _mesh()
    state = np.array([0, 1, 5, 4, 0, 8], dtype=np.int8)
    ax = plot_plastic_state(xy, zones, state, blocks=[np.array([[4, 0], [5, 0], [5, 1.0]])])
    zc, bc = _polys(ax)
    fc = [tuple(c) for c in zc.get_facecolors()]
    assert len(fc) == 6
    # one colour per distinct state, the same colour for the same state
    assert len(set(fc)) == 5 and fc[0] == fc[4] == to_rgba("white")
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels == ["elastic", "shear-n", "shear-p", "shear-n shear-p", "tension-p", "blocks"]
    plt.close(ax.figure)


def test_state_labels():
    assert state_label(0) == "elastic"
    assert state_label(2) == "tension-n"
    assert state_label(15) == "shear-n tension-n shear-p tension-p"
    with pytest.raises(ValueError):
        state_label(16)


@pytest.mark.parametrize("kwargs,message", [
    (dict(values=np.zeros(5)), r"expected \(6,\)"),
    (dict(displacement=np.zeros((3, 2))), "one \\(ux, uy\\) per gridpoint"),
    (dict(blocks=[np.zeros((2, 2))]), "block 0"),
])
def test_bad_input(kwargs, message):
    xy, zones = _mesh()
    with pytest.raises(ValueError, match=message):
        plot_zones(xy, zones, **kwargs)
    with pytest.raises(ValueError, match="0..15"):
        plot_plastic_state(xy, zones, np.full(6, 16))

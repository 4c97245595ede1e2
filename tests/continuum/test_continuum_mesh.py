"""Mesh generation of the continuum zones (issue 17 items 1 and 6): areas against the polygon
(shoelace) and the polygonal annulus (closed forms), geometric grading, target size, conforming
merges, the automatic corners of a backfill, selections and the one-line errors with their keys."""

from __future__ import annotations

import math

import numpy as np
import pytest

from murus.continuum.mesh import (
    Mesh,
    MeshError,
    annulus,
    graded_fractions,
    merge,
    mesh_regions,
    polygon_corners,
    polygon_region,
    quad_region,
    rectangle,
    strip_footing,
)


def shoelace(p) -> float:
    p = np.asarray(p, dtype=float)
    x, y = p[:, 0], p[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def assert_valid(m: Mesh) -> None:
    """Every zone counter-clockwise with a positive area and convex (all angles below 180)."""
    assert m.zones.dtype == np.int64 and m.zones.shape[1] == 4
    assert m.xy.dtype == np.float64 and m.xy.shape[1] == 2
    assert (m.areas() > 0).all()
    ang = m.angles_deg()
    assert (ang > 0).all() and (ang < 180).all()
    # the four triangles of the two overlays (Marti & Cundall) all positive
    p = m.xy[m.zones]
    for a, b, c in ((0, 1, 2), (0, 2, 3), (0, 1, 3), (1, 2, 3)):
        u, v = p[:, b] - p[:, a], p[:, c] - p[:, a]
        assert (u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0] > 0).all()
    # no duplicated gridpoint
    d = np.hypot(*(m.xy[:, None] - m.xy[None]).transpose(2, 0, 1))
    np.fill_diagonal(d, np.inf)
    assert d.min() > 1e-9 * m.size


# the backfill of a retaining wall: wall back inclined 10 deg from the vertical (heel at the
# origin), the ground level for 1 m behind the wall top, then sloped up at 20 deg to the far side
H, L, BETA = 3.0, 8.0, math.radians(20.0)
A = (0.0, 0.0)                                              # heel of the wall back
E = (H * math.tan(math.radians(10.0)), H)                   # top of the wall back
K = (E[0] + 1.0, H)                                         # end of the level part
D = (L, H + (L - K[0]) * math.tan(BETA))                    # far top corner
Bf = (L, 0.0)
BACKFILL = [A, Bf, D, K, E]


def test_straight_sided_regions_tile_the_polygon_exactly():
    # a quadrilateral with an inclined left side (a wall back) and a broken top (level, sloped)
    bottom = [(0.0, 0.0), (6.0, 0.0)]
    right = [(6.0, 0.0), (6.0, 4.0)]
    top = [(6.0, 4.0), (2.0, 3.0), (0.5, 3.0)]              # sloped, then level
    left = [(0.5, 3.0), (0.0, 0.0)]                         # inclined
    m = quad_region(bottom, right, top, left, nx=9, ny=5, grading=(1.15, 0.9))
    assert_valid(m)
    ring = bottom[:-1] + right[:-1] + top[:-1] + left[:-1]
    assert m.areas().sum() == pytest.approx(shoelace(ring), rel=1e-12)
    # the kink of the top is a gridpoint
    assert np.hypot(*(m.xy[m.side("top")] - (2.0, 3.0)).T).min() < 1e-12
    assert m.n_zones == 45 and m.n_gridpoints == 60
    # polygons: the backfill (automatic corners), a clockwise hexagon, a triangle
    for verts, kw in ((BACKFILL, {"size": 0.4}), ([(0, 0), (1, 2), (3, 2.5), (5, 1), (4, -1),
                                                   (2, -1.5)], {"nx": 6, "ny": 5}),
                      ([(0, 0), (3, 0), (1, 2)], {"nx": 4})):
        m = polygon_region(verts, **kw)
        assert_valid(m)
        assert m.areas().sum() == pytest.approx(abs(shoelace(verts)), rel=1e-12)
    assert m.n_zones == 3 * 4 * 4                             # triangle: three quadrilaterals


def test_clockwise_polygon_is_normalised():
    ccw = [(0, 0), (4, 0), (4, 2), (0, 2)]
    m1 = polygon_region(ccw, nx=4, ny=2)
    m2 = polygon_region(ccw[::-1], corners=(3, 2, 1, 0), nx=4, ny=2)
    assert_valid(m2)
    np.testing.assert_allclose(m1.xy, m2.xy, atol=1e-14)
    np.testing.assert_array_equal(m1.zones, m2.zones)


@pytest.mark.parametrize("ratio", [1.0, 1.25, 0.7])
def test_graded_side_reproduces_the_geometric_progression(ratio):
    n, width = 7, 3.0
    m = rectangle(1.0, -2.0, width, 1.0, nx=n, ny=2, grading=(ratio, 1.0))
    x = m.xy[m.side("bottom"), 0]
    h = np.diff(x)
    # h_i = W (r - 1) r^i / (r^n - 1), uniform W / n for r = 1
    h0 = width / n if ratio == 1.0 else width * (ratio - 1) / (ratio ** n - 1)
    np.testing.assert_allclose(h, h0 * ratio ** np.arange(n), rtol=1e-12)
    # the top follows the same progression, the vertical lines stay vertical
    np.testing.assert_allclose(m.xy[m.side("top"), 0][::-1], x, rtol=0, atol=1e-14)
    s = graded_fractions(n, ratio)
    np.testing.assert_allclose(np.diff(s)[1:] / np.diff(s)[:-1], ratio, rtol=1e-12)


def test_grading_on_a_broken_side_keeps_the_progression_within_each_segment():
    top = [(6.0, 2.0), (3.0, 2.0), (0.0, 2.0 + 3.0 * math.tan(math.radians(25)))]
    m = quad_region([(0, 0), (6, 0)], [(6, 0), (6, 2)], top, [top[-1], (0, 0)], nx=10, ny=3,
                    grading=(1.2, 1.0))
    p = m.xy[m.side("top")][::-1]                            # from c3 (left) towards c2
    h = np.hypot(*np.diff(p, axis=0).T)
    k = int(np.argmin(np.hypot(*(p - (3.0, 2.0)).T)))        # the kink is gridpoint k
    assert np.hypot(*(p[k] - (3.0, 2.0))) < 1e-12
    for seg in (h[:k], h[k:]):
        np.testing.assert_allclose(seg[1:] / seg[:-1], 1.2, rtol=1e-12)


def test_target_size_bounds_every_zone_edge():
    for size in (0.5, 0.23):
        m = polygon_region(BACKFILL, size=size, grading=(1.02, 1.0), name="backfill")
        assert_valid(m)
        assert m.quality().max_edge <= size * (1 + 1e-9)
    # straight uniform sides: the smallest count, ceil(L / h)
    m = rectangle(0, 0, 2.0, 1.0, size=0.3)
    assert m.n_zones == math.ceil(2.0 / 0.3) * math.ceil(1.0 / 0.3)
    # graded: the largest zone L (r-1) r^(n-1) / (r^n - 1) <= h with n the smallest such count
    m = rectangle(0, 0, 4.0, 1.0, size=(0.5, 1.0), grading=(1.1, 1.0))
    n = m.n_zones
    big = [4.0 * 0.1 * 1.1 ** (k - 1) / (1.1 ** k - 1) for k in (n - 1, n)]
    assert big[1] <= 0.5 < big[0]
    # per-direction sizes
    m = rectangle(0, 0, 2.0, 1.0, size=(0.5, 0.1))
    assert m.n_zones == 4 * 10


def test_merging_two_rectangles_sharing_a_side():
    a = rectangle(0, 0, 1.0, 2.0, nx=3, ny=4, grading=(1.0, 1.3), name="a")
    b = rectangle(1.0, 0, 2.5, 2.0, nx=5, ny=4, grading=(1.4, 1.3), name="b")
    m = merge([a, b])
    assert_valid(m)
    assert m.n_zones == (3 + 5) * 4
    assert m.n_gridpoints == (3 + 5 + 1) * (4 + 1)
    assert m.areas().sum() == pytest.approx(3.5 * 2.0, rel=1e-12)
    np.testing.assert_array_equal(m.side("a.right"), m.side("b.left")[::-1])
    np.testing.assert_array_equal(np.bincount(m.region), [12, 20])
    assert m.region_names == ("a", "b")
    # the shared side is interior: the boundary has 2 (8 + 4) edges
    assert len(m.boundary_edges()) == 2 * (8 + 4)
    assert set(m.side("bottom")) == set(m.side("a.bottom")) | set(m.side("b.bottom"))


def test_merge_rejects_non_conforming_sides_and_overlaps():
    a = rectangle(0, 0, 1.0, 1.0, nx=3, ny=4, name="a")
    with pytest.raises(MeshError, match="without conforming") as e:
        merge([a, rectangle(1.0, 0, 1.0, 1.0, nx=3, ny=3, name="b")])
    assert e.value.key == ("meshes", 0)
    with pytest.raises(MeshError, match="overlaps") as e:
        merge([a, rectangle(0, 0, 1.0, 1.0, nx=3, ny=4, name="b")])
    with pytest.raises(MeshError, match="appears twice") as e:
        merge([a, rectangle(1.0, 0, 1.0, 1.0, nx=3, ny=4, name="a")])
    assert e.value.key == ("meshes", 1)


def test_quarter_annulus_area_is_the_polygonal_closed_form():
    a, b, nr, nt = 1.0, 5.0, 12, 16
    q = (b / a) ** (1 / nr)
    m = annulus(a, b, nr, nt, grading=q)
    assert_valid(m)
    dth = math.pi / 2 / nt
    polygonal = nt * math.sin(dth) * (b * b - a * a) / 2
    assert m.areas().sum() == pytest.approx(polygonal, rel=1e-12)
    exact = math.pi / 4 * (b * b - a * a)
    chord = nt * (dth - math.sin(dth)) * (b * b - a * a) / 2    # the segments cut by the chords
    assert exact - m.areas().sum() == pytest.approx(chord, rel=1e-9)
    assert chord / exact < dth ** 2 / 6
    # gridpoints on the circles, radii in geometric progression
    r = np.hypot(*m.xy.T)
    np.testing.assert_allclose(r[m.side("inner")], a, rtol=1e-14)
    np.testing.assert_allclose(r[m.side("outer")], b, rtol=1e-14)
    radii = r[m.side("start")]
    np.testing.assert_allclose(radii[1:] / radii[:-1], q, rtol=1e-12)
    # full annulus: periodic, no seam
    full = annulus(a, b, 3, 24, theta1_deg=360.0)
    assert_valid(full)
    assert full.n_zones == 3 * 24 and full.n_gridpoints == 4 * 24
    assert full.areas().sum() == pytest.approx(24 * math.sin(math.pi / 12) * (b * b - a * a) / 2,
                                               rel=1e-12)
    assert len(full.boundary_edges()) == 48


def test_strip_footing_mesh():
    B, D, W, nf, q = 1.0, 5.0, 6.0, 4, 1.15
    m = strip_footing(B, D, W, n_footing=nf, grading=q)
    assert_valid(m)
    assert m.areas().sum() == pytest.approx(W * D, rel=1e-12)
    foot = m.xy[m.side("footing")]
    np.testing.assert_allclose(foot[:, 1], 0.0, atol=1e-14)
    np.testing.assert_allclose(foot[:, 0], np.linspace(0, B, nf + 1), atol=1e-14)
    x = m.xy[m.side("surface"), 0]
    h = np.diff(x)
    np.testing.assert_allclose(h[1:] / h[:-1], q, rtol=1e-12)
    assert x[0] == pytest.approx(B) and x[-1] == pytest.approx(W)
    y = m.xy[m.side("axis"), 1]
    hy = -np.diff(y)[::-1]                                   # from the surface down
    np.testing.assert_allclose(hy[1:] / hy[:-1], q, rtol=1e-12)
    full = strip_footing(B, D, W, n_footing=nf, grading=q, full=True)
    assert_valid(full)
    assert full.areas().sum() == pytest.approx(2 * W * D, rel=1e-12)
    assert len(full.side("footing")) == 2 * nf + 1
    assert len(full.side("base")) == len(np.unique(full.side("base")))


def test_automatic_corners_of_a_sloped_backfill():
    # interior angles: 80 (heel), 90, 90, 160 (break of slope), 110 (wall top): the break is
    # not a corner; c0 is the heel
    assert polygon_corners(BACKFILL) == (0, 1, 2, 4)
    # clockwise and rotated input: the same vertices (as indices into the input)
    rev = BACKFILL[::-1]                                     # index i -> 4 - i
    assert sorted(polygon_corners(rev)) == [0, 2, 3, 4]
    assert polygon_corners(rev)[0] == 4
    m = polygon_region(BACKFILL, nx=16, ny=6, grading=(1.1, 1.0), name="backfill")
    top = m.xy[m.side("backfill.top")]
    assert np.hypot(*(top - K).T).min() < 1e-12             # the break is a gridpoint
    np.testing.assert_allclose(top[[0, -1]], [D, E], atol=1e-14)
    left = m.xy[m.side("backfill.left")]                     # the wall back, E down to A
    np.testing.assert_allclose(left[:, 0], left[:, 1] * math.tan(math.radians(10.0)), atol=1e-14)
    # finer near the wall: bottom zones grow by 1.1 from the heel
    h = np.diff(m.xy[m.side("backfill.bottom"), 0])
    np.testing.assert_allclose(h[1:] / h[:-1], 1.1, rtol=1e-12)


def test_thin_but_valid_regions_are_accepted():
    m = rectangle(0, 0, 100.0, 0.01, nx=1000, ny=1)
    assert m.quality().max_aspect == pytest.approx(10.0)
    m = polygon_region([(0, 0), (100, 0), (100, 0.02), (0, 0.001)], nx=50, ny=1)
    assert m.areas().sum() == pytest.approx(shoelace([(0, 0), (100, 0), (100, 0.02),
                                                      (0, 0.001)]), rel=1e-12)
    # a long sliver with a 0.1 deg corner
    t = math.tan(math.radians(0.1))
    assert_valid(polygon_region([(0, 0), (50, 0), (50, 50 * t)], nx=3))


def test_selections():
    m = merge([rectangle(0, 0, 2, 1, nx=4, ny=2, name="a"),
               rectangle(2, 0, 2, 1, nx=4, ny=2, name="b")])
    line = m.on_line((4.0, 0.0), (0.0, 0.0))
    np.testing.assert_allclose(m.xy[line, 0], np.arange(4.0, -0.1, -0.5))
    box = m.in_box(1.9, -1, 2.1, 5)
    np.testing.assert_allclose(m.xy[box, 0], 2.0)
    assert len(box) == 3
    assert len(m.side("bottom")) == 9 and len(m.side("a.left")) == 3
    e = m.edges_of(m.side("top"))
    assert len(e) == 8
    # counter-clockwise around the mesh: the top edges run right to left
    assert (m.xy[e[:, 1], 0] < m.xy[e[:, 0], 0]).all()
    be = m.boundary_edges()
    p, q = m.xy[be[:, 0]], m.xy[be[:, 1]]
    assert 0.5 * np.sum(p[:, 0] * q[:, 1] - q[:, 0] * p[:, 1]) == pytest.approx(4.0, rel=1e-12)
    extra = m.with_side("crest", line)
    np.testing.assert_array_equal(extra.side("crest"), line)
    q = m.quality()
    assert (q.min_area, q.max_area, q.min_angle_deg, q.max_angle_deg, q.max_aspect) == \
        pytest.approx((0.25, 0.25, 90.0, 90.0, 1.0))


BAD = [
    ("bow tie", lambda: polygon_region([(0, 0), (1, 1), (1, 0), (0, 1)], nx=2, ny=2),
     ("vertices",), "intersects itself"),
    ("two vertices", lambda: polygon_region([(0, 0), (1, 0)], nx=2), ("vertices",), "at least 3"),
    ("duplicated vertex", lambda: polygon_region([(0, 0), (1, 0), (1, 1), (1, 0.0), (0, 1)],
                                                 nx=2), ("vertices", 3), "coincide"),
    ("zero size", lambda: rectangle(0, 0, 1, 1, size=0.0), ("size",), "> 0"),
    ("negative size", lambda: polygon_region(BACKFILL, size=-0.5), ("size",), "> 0"),
    ("one negative size", lambda: rectangle(0, 0, 1, 1, size=(0.1, -1)), ("size", 1), "> 0"),
    ("nx zero", lambda: rectangle(0, 0, 1, 1, nx=0, ny=2), ("nx",), ">= 1"),
    ("ny zero", lambda: rectangle(0, 0, 1, 1, nx=2, ny=0), ("ny",), ">= 1"),
    ("nx float", lambda: rectangle(0, 0, 1, 1, nx=2.5, ny=2), ("nx",), "integer"),
    ("grading zero", lambda: rectangle(0, 0, 1, 1, nx=2, ny=2, grading=0.0), ("grading",),
     "> 0"),
    ("grading negative", lambda: rectangle(0, 0, 1, 1, nx=2, ny=2, grading=(1.0, -1.2)),
     ("grading", 1), "> 0"),
    ("no count", lambda: rectangle(0, 0, 1, 1), ("size",), "give nx and ny"),
    ("unreachable size", lambda: rectangle(0, 0, 8, 1, size=0.25, grading=1.05), ("size",),
     "grading between"),
    ("inverted (L shape)", lambda: polygon_region([(0, 0), (2, 0), (2, 2), (1, 2), (1, 1),
                                                   (0, 1)], nx=4, ny=4), ("corners",),
     "inverted"),
    ("reflex corner", lambda: polygon_region([(0, 0), (2, 0), (2, 2), (1, 2), (1, 1), (0, 1)],
                                             corners=(0, 1, 4, 5), nx=4, ny=4), ("corners",),
     "below 180"),
    ("few segments", lambda: polygon_region(BACKFILL, nx=1, ny=3), ("nx",), "segments"),
    ("sides do not join", lambda: quad_region([(0, 0), (1, 0)], [(1, 0), (1, 1)],
                                              [(1, 1), (0, 1)], [(0, 1.1), (0, 0)], nx=1, ny=1),
     ("left", 0), "starts at"),
    ("clockwise sides", lambda: quad_region([(0, 0), (0, 1)], [(0, 1), (1, 1)],
                                            [(1, 1), (1, 0)], [(1, 0), (0, 0)], nx=1, ny=1),
     ("sides",), "counter-clockwise"),
    ("annulus radii", lambda: annulus(2.0, 1.0, 3, 3), ("outer_radius",), "exceed"),
    ("graded triangle", lambda: polygon_region([(0, 0), (3, 0), (1, 2)], nx=3, grading=1.2),
     ("grading",), "no grading"),
    ("bad corners", lambda: polygon_region(BACKFILL, corners=(0, 1, 1, 4), nx=4, ny=4),
     ("corners",), "distinct"),
]


@pytest.mark.parametrize("case", BAD, ids=[c[0] for c in BAD])
def test_bad_input_is_a_one_line_error_with_its_key(case):
    _, build, key, text = case
    with pytest.raises(MeshError, match=text) as e:
        build()
    assert e.value.key == key
    assert "\n" not in str(e.value)
    assert isinstance(e.value, ValueError)


def test_a_selection_that_names_no_gridpoint_is_an_error():
    m = rectangle(0, 0, 2, 1, nx=4, ny=2, name="soil")
    key = ("boundaries", 2, "line")
    with pytest.raises(MeshError, match="names no gridpoint") as e:
        m.on_line((0, 2), (2, 2), key=key)
    assert e.value.key == key
    with pytest.raises(MeshError, match="names no gridpoint") as e:
        m.in_box(3, 3, 4, 4, key=("boundaries", 0, "box"))
    assert e.value.key == ("boundaries", 0, "box")
    with pytest.raises(MeshError, match="no side named 'wall'") as e:
        m.side("wall", key=("boundaries", 1, "side"))
    assert e.value.key == ("boundaries", 1, "side")


def test_mesh_rejects_a_clockwise_or_non_convex_zone():
    xy = [(0, 0), (1, 0), (1, 1), (0, 1), (0.9, 0.2)]
    Mesh(xy, [[0, 1, 2, 3]], [0], ("r",))
    with pytest.raises(MeshError, match="not convex and counter-clockwise") as e:
        Mesh(xy, [[0, 1, 2, 3], [0, 3, 2, 1]], [0, 0], ("r",))
    assert e.value.key == ("zones", 1)
    with pytest.raises(MeshError) as e:
        Mesh(xy, [[0, 1, 2, 4]], [0], ("r",))                 # a dart: corner 4 is reflex
    assert e.value.key == ("zones", 0)
    with pytest.raises(MeshError) as e:
        Mesh(xy, [[0, 1, 2, 7]], [0], ("r",))
    assert e.value.key == ("zones", 0)


def test_mesh_regions_prefixes_the_keys_of_the_case_file():
    regions = [{"name": "foundation", "vertices": [(0, -1), (4, -1), (4, 0), (0, 0)], "nx": 4,
                "ny": 2, "material": "clay"},
               {"name": "fill", "vertices": [(0, 0), (4, 0), (4, 2), (0, 2)], "nx": 4, "ny": 3}]
    m = mesh_regions(regions)
    assert m.region_names == ("foundation", "fill")
    np.testing.assert_array_equal(np.bincount(m.region), [8, 12])
    assert m.n_gridpoints == 5 * 6
    bad = [dict(regions[0]), dict(regions[1], vertices=[(0, 0), (4, 0), (4, 2), (4, 2), (0, 2)])]
    with pytest.raises(MeshError, match="coincide") as e:
        mesh_regions(bad)
    assert e.value.key == ("zones", 1, "vertices", 3)
    with pytest.raises(MeshError, match="without conforming") as e:
        mesh_regions([regions[0], dict(regions[1], nx=5)])
    assert e.value.key[:1] == ("zones",) and e.value.key[1] in (0, 1)
    with pytest.raises(MeshError, match="> 0") as e:
        mesh_regions([dict(regions[0], nx=None, size=0)])
    assert e.value.key == ("zones", 0, "size")


def test_three_given_corners_mesh_a_triangle_with_a_collinear_vertex():
    verts = [(0, 0), (2, 0), (4, 0), (0, 3)]                   # vertex 1 on the bottom side
    m = polygon_region(verts, nx=3)                            # automatic: three corners
    m3 = polygon_region(verts, corners=(0, 2, 3), nx=3)
    for mesh in (m, m3):
        assert_valid(mesh)
        assert mesh.n_zones == 27
        assert mesh.areas().sum() == pytest.approx(6.0, rel=1e-12)
        assert np.hypot(*(mesh.xy[mesh.side("bottom")] - (2.0, 0.0)).T).min() < 1e-12


def test_backfill_example_builds_a_conforming_mesh(tmp_path):
    import importlib.util
    from pathlib import Path

    path = Path(__file__).resolve().parents[2] / "examples" / "continuum" / "mesh_backfill.py"
    spec = importlib.util.spec_from_file_location("mesh_backfill", path)
    ex = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ex)
    ex.main(tmp_path)
    assert (tmp_path / "mesh_backfill.png").stat().st_size > 0
    m = ex.build()
    assert_valid(m)
    assert m.region_names == ("under_wall", "foundation", "backfill")
    assert m.n_zones == 4 * 4 + ex.NX * 4 + ex.NX * ex.NY
    # conforming: the gridpoints of the foundation top are those of the backfill bottom
    np.testing.assert_array_equal(m.side("foundation.top")[::-1], m.side("backfill.bottom"))
    area = abs(shoelace(ex.backfill_vertices())) + (ex.LENGTH + ex.WALL_BASE) * ex.FOUNDATION
    assert m.areas().sum() == pytest.approx(area, rel=1e-12)


def test_mesh_pickles_and_is_read_only():
    import pickle

    m = strip_footing(1.0, 3.0, 4.0, n_footing=3)
    m2 = pickle.loads(pickle.dumps(m))
    np.testing.assert_array_equal(m2.xy, m.xy)
    np.testing.assert_array_equal(m2.zones, m.zones)
    assert m2.region_names == m.region_names and set(m2.sides) == set(m.sides)
    np.testing.assert_array_equal(m2.side("footing"), m.side("footing"))
    with pytest.raises(ValueError):
        m.xy[0, 0] = 1.0
    with pytest.raises(TypeError):
        m.sides["new"] = np.array([0])

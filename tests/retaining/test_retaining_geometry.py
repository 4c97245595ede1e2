"""Dry-stone retaining wall sections: Savalle et al. (2022), Table 5 presets, polygon, joints, bad
input."""

import csv
import math

import pytest

from murus.retaining.geometry import (
    MOCKUP_SLENDERNESS,
    PRESETS,
    GeometryError,
    RetainingWall,
    clip_above,
    mockup,
    polygon_area_centroid,
    preset,
)


def table5(data_dir):
    with open(data_dir / "retaining" / "savalle2022_table5.csv") as fh:
        return {r["wall"]: r for r in csv.DictReader(ln for ln in fh if not ln.startswith("#"))}


def test_presets_are_table5_and_table6(data_dir):
    rows = table5(data_dir)
    with open(data_dir / "retaining" / "savalle2022_table6.csv") as fh:
        t6 = {r["parameter"]: r for r in csv.DictReader(ln for ln in fh
                                                        if not ln.startswith("#"))}
    assert set(rows) == set(PRESETS)
    for name, r in rows.items():
        w = preset(name)
        assert w.height == float(r["H_m"]) and w.base_width == float(r["B_m"])
        assert w.top_width == pytest.approx(float(r["b_m"]), abs=1e-12)
        assert w.internal_batter == pytest.approx(float(r["internal_batter_pct"]) / 100)
        assert w.external_batter == pytest.approx(float(r["external_batter_pct"]) / 100)
        assert w.bed_inclination_deg == float(r["bed_inclination_deg"])
        assert w.backfill_slope_deg == float(r["backfill_slope_deg"])
        # b = B - H (lambda_v + lambda_m): Table 5 is consistent with itself
        assert w.base_width - w.height * (w.external_batter + w.internal_batter) == \
            pytest.approx(float(r["b_m"]), abs=1e-12)
        # Table 6 and section 4.1
        assert w.wall_unit_weight == 1e3 * float(t6["unit_weight_kN_m3"]["units"])
        assert w.backfill_unit_weight == 1e3 * float(t6["unit_weight_kN_m3"]["backfill"])
        assert w.backfill_friction_deg == float(t6["friction_angle_deg"]["backfill"])
        assert w.joint_friction_deg == float(t6["interface_friction_angle_deg"]["units"])
        assert w.interface_friction_deg == float(t6["interface_friction_angle_deg"]["interface"])
        assert (w.stone_height, w.stone_length) == (0.1, 0.35)
    assert preset("C3s") == preset("DSRW2")  # Figure 9 caption (names do not compare)


def test_dsrw1_polygon_area_centroid_weight():
    w = preset("DSRW1")
    t = math.tan(math.radians(9.1))
    expected = [(0, 0), (0.7, -0.7 * t), (0.7, 2.5), (0.15, 2.5)]
    for p, q in zip(w.polygon, expected, strict=True):
        assert p == pytest.approx(q, abs=1e-15)
    trap = 0.5 * (0.7 + 0.55) * 2.5
    tri = 0.5 * 0.7 * 0.7 * t
    assert w.area == pytest.approx(trap + tri, rel=1e-14)
    # centroid: trapezoid (x from the composition of a rectangle and a triangle) + triangle
    xs_trap = (0.55 * 2.5 * (0.15 + 0.275) + 0.5 * 0.15 * 2.5 * 0.1) / trap
    zs_trap = (0.55 * 2.5 * 1.25 + 0.5 * 0.15 * 2.5 * 2.5 / 3) / trap
    x_tri, z_tri = (0 + 0.7 + 0.7) / 3, -0.7 * t / 3
    assert w.centroid[0] == pytest.approx((trap * xs_trap + tri * x_tri) / w.area, rel=1e-12)
    assert w.centroid[1] == pytest.approx((trap * zs_trap + tri * z_tri) / w.area, rel=1e-12)
    assert w.weight == pytest.approx(20e3 * w.area, rel=1e-15)
    assert w.psi == pytest.approx(math.pi / 2)


def test_bed_joints_one_stone_apart_perpendicular():
    w = preset("DSRW1")
    a = math.radians(9.1)
    js = w.joints
    assert js[0].front == (0.0, 0.0) and js[0].back == pytest.approx(w.heel)
    assert len(js) == 25  # 2.5 m of wall at 0.1 m / cos(alpha) per course along the front
    for j0, j1 in zip(js, js[1:], strict=False):
        assert j1.angle == pytest.approx(a)
        # the front edge is on the front face, the back end on the back face
        assert j1.front[0] == pytest.approx(0.06 * j1.front[1], abs=1e-12)
        assert j1.back[0] == pytest.approx(0.7, abs=1e-12)
        assert j1.back[1] == pytest.approx(j1.front[1] - (0.7 - j1.front[0]) * math.tan(a))
        # perpendicular distance between successive joint lines = the stone height
        n = j1.normal
        dist = (j1.front[0] - j0.front[0]) * n[0] + (j1.front[1] - j0.front[1]) * n[1]
        assert dist == pytest.approx(0.1, rel=1e-12)
    assert js[-1].front[1] < 2.5


def test_parts_above_joints():
    w = preset("DSRW1")
    prev = math.inf
    for j in w.joints:
        p = w.part_above(j)
        assert p.area < prev
        prev = p.area
        assert p.back_top == (0.7, 2.5)
        assert p.back_bottom == pytest.approx(j.back)
        assert p.weight == pytest.approx(20e3 * p.area)
    base = w.part_above(w.joints[0])
    assert base.area == pytest.approx(w.area, rel=1e-14)
    assert base.back_height == pytest.approx(2.5 + 0.7 * math.tan(math.radians(9.1)))
    # a horizontal joint through a rectangle: the part above is a rectangle
    r = RetainingWall(height=2.0, base_width=0.5, bed_inclination_deg=0.0, stone_height=0.25)
    p = r.part_above(r.joints[3])
    assert p.area == pytest.approx(0.5 * 1.25) and p.centroid == pytest.approx((0.25, 1.375))
    assert p.back_height == pytest.approx(1.25)


def test_horizontal_base_and_internal_batter():
    w = preset("DSRW1", base="horizontal")
    assert w.heel == (0.7, 0.0) and w.joints[0].angle == 0.0
    assert w.area == pytest.approx(0.5 * (0.7 + 0.55) * 2.5)
    # joints that dip below the base leave the wall through the base: their part's back face
    # is then the whole back face
    j1 = w.joints[1]
    assert j1.back[1] == pytest.approx(0.0, abs=1e-12) and j1.back[0] < 0.7
    assert w.part_above(j1).back_height == pytest.approx(2.5)
    v = RetainingWall(height=2.0, base_width=1.0, internal_batter=0.1, external_batter=0.1,
                      bed_inclination_deg=5.0)
    assert v.top_width == pytest.approx(0.6)
    assert v.psi == pytest.approx(math.pi / 2 - math.atan(0.1))  # soil rests on the back
    t = math.tan(math.radians(5.0))
    xh = 1.0 / (1 - 0.1 * t)
    assert v.heel == pytest.approx((xh, -t * xh))
    assert v.heel[0] == pytest.approx(1.0 - 0.1 * v.heel[1])  # on the back face


def test_polygon_helpers():
    sq = [(0, 0), (1, 0), (1, 1), (0, 1)]
    assert polygon_area_centroid(sq) == pytest.approx((1.0, 0.5, 0.5))
    assert polygon_area_centroid(sq[::-1]) == pytest.approx((1.0, 0.5, 0.5))
    half = clip_above(sq, (0, 0.25), (0, 1))
    assert polygon_area_centroid(half) == pytest.approx((0.75, 0.5, 0.625))
    tri = clip_above(sq, (0, 0), (-1 / math.sqrt(2), 1 / math.sqrt(2)))
    assert polygon_area_centroid(tri)[0] == pytest.approx(0.5)


def test_mockups():
    assert MOCKUP_SLENDERNESS == (1.3, 1.7, 2.3, 2.7, 3.0, 3.3)
    for r in MOCKUP_SLENDERNESS:
        m = mockup(r)
        assert m.slenderness == pytest.approx(r)
        assert m.base_width == 0.034 and m.external_batter == 0 and m.bed_inclination_deg == 0
        assert len(m.joints) == 1  # courses not given by the paper: base joint only
        assert (m.wall_unit_weight, m.backfill_unit_weight) == (14.4e3, 15.4e3)
        assert (m.backfill_friction_deg, m.joint_friction_deg) == (45.0, 32.0)
    assert preset("mockup-2.7") == mockup(2.7)
    assert mockup(2.7, width=0.04).height == pytest.approx(0.108)


@pytest.mark.parametrize("kwargs, word", [
    (dict(height=-1, base_width=0.7), "height must be > 0"),
    (dict(height=2.5, base_width=0.7, top_width=0.5, external_batter=0.06), "inconsistent"),
    (dict(height=2.5, base_width=0.7, external_batter=0.3), "close the section"),
    (dict(height=2.5, base_width=0.7, bed_inclination_deg=50), "bed_inclination_deg"),
    (dict(height=2.5, base_width=0.7, backfill_slope_deg=40), "backfill_slope_deg"),
    (dict(height=2.5, base_width=0.7, interface_friction_deg=40), "interface_friction_deg"),
    (dict(height=2.5, base_width=0.7, base="flat"), "base must be"),
    (dict(height=2.5, base_width=0.7, wall_unit_weight=0), "wall_unit_weight"),
    (dict(height="x", base_width=0.7), "must be a number"),
    (dict(height=2.5, base_width=0.7, backfill_profile=((1, 1), (0.5, 1))), "backfill_profile"),
])
def test_bad_geometry_one_line(kwargs, word):
    with pytest.raises(GeometryError) as exc:
        RetainingWall(**kwargs)
    assert word in str(exc.value) and "\n" not in str(exc.value)


def test_unknown_presets():
    with pytest.raises(GeometryError, match="unknown preset 'DSRW9'"):
        preset("DSRW9")
    with pytest.raises(GeometryError, match="unknown mock-up"):
        preset("mockup-x")
    assert preset("dsrw3").name == "DSRW3"

"""DEM model of a dry-stone retaining wall and its equivalent thrust (murus.retaining.dem_wall)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from murus import G
from murus.dem import kernels as K
from murus.eurocode import ec8_5
from murus.retaining.dem_wall import (
    DemWallError,
    EquivalentThrust,
    build_wall,
    pressure_weights,
    stones_of_wall,
)
from murus.retaining.geometry import polygon_area_centroid, preset


def test_dsrw1_stones_tile_the_section_in_running_bond():
    w = preset("DSRW1")
    dw = build_wall(w)
    assert abs(dw.stone_weight / w.weight - 1.0) < 1e-6
    area = sum(polygon_area_centroid([tuple(p) for p in poly])[0] for poly in dw.polygons)
    assert area == pytest.approx(w.area, rel=1e-9)
    # Savalle et al. (2022), §4.1: stones 0.1 m high, 0.35 m long; courses follow the bed joints
    assert len(dw.courses) == len(w.joints)
    assert max(len(c) for c in dw.courses) <= 3
    # running bond: the first head joint of adjacent courses is offset along the beds
    firsts = []
    for course in stones_of_wall(w):
        p = np.asarray(course[0])
        firsts.append(np.ptp(p[:, 0]))
    assert all(abs(a - b) > 0.1 for a, b in zip(firsts[:8], firsts[1:9], strict=False))
    # no initial overlap: every sub-contact starts at (numerically) zero force
    m = dw.model
    on = m.sid >= 0
    assert on.any()
    assert np.abs(m.sf[on][:, K.F_FN]).max() < 1e-6 * w.weight
    assert np.min(m.sf[on][:, K.F_GAP]) > -1e-9
    # the back face is carried by one stone per course
    assert len(dw.back) == len(dw.courses)
    assert dw.model.nbody == len(dw.stones) + 2  # foundation and backstop (kinematic)
    assert dw.back_height == pytest.approx(w.height + w.base_width * math.tan(w.alpha), rel=1e-9)


def test_static_thrust_equals_annex_e_and_acts_at_a_third():
    w = preset("DSRW1")
    dw = build_wall(w)
    th = EquivalentThrust(dw)
    th(dw.model)
    Fx, Fy, M = th.resultant(dw.model)
    phi = math.radians(w.backfill_friction_deg)
    delta = 2.0 / 3.0 * phi
    Es, _ = ec8_5.thrust_components(w.backfill_unit_weight, dw.back_height, phi, 0.0, 0.0,
                                    w.beta, delta, w.psi)
    assert math.hypot(Fx, Fy) == pytest.approx(Es, rel=1e-2)
    assert math.degrees(math.atan2(-Fy, -Fx)) == pytest.approx(math.degrees(delta), abs=1e-6)
    # moment about the heel: resultant at h/3 above it on the (vertical) back face
    hx, hz = w.heel
    Mh = M - (hx * Fy - hz * Fx)
    # every force acts on the back face x = x_heel: Mh = -(z - z_heel) Fx
    z_app = -Mh / Fx
    assert z_app == pytest.approx(dw.back_height / 3.0, rel=1e-2)
    # seismic: Es + dE of EN 1998-5 (E.1) at kh = 0.2, kv = -0.1
    th.acc = lambda t: (0.2 * G, 0.1 * G)
    th(dw.model)
    Fx, Fy, _ = th.resultant(dw.model)
    Es, dE = ec8_5.thrust_components(w.backfill_unit_weight, dw.back_height, phi, 0.2, -0.1,
                                     w.beta, delta, w.psi)
    assert math.hypot(Fx, Fy) == pytest.approx(Es + dE, rel=1e-9)
    assert th.last[1:3] == pytest.approx((0.2, -0.1))
    # kh < 0: the static active thrust (times 1 - kv)
    th.acc = lambda t: (-0.3 * G, 0.0)
    th(dw.model)
    assert math.hypot(*th.resultant(dw.model)[:2]) == pytest.approx(Es, rel=1e-9)


def test_pressure_weights():
    s = np.linspace(0.0, 1.0, 11)
    for f in (1.0 / 3.0, 0.5, 0.45):
        w, sp = pressure_weights(s[:-1], s[1:], f)
        assert w.sum() == pytest.approx(1.0)
        assert (w * sp).sum() == pytest.approx(f)


def test_short_wall_settles_under_gravity_and_static_thrust():
    w = preset("DSRW1", height=0.8, top_width=None)
    dw = build_wall(w, stiffness_scale=1e-3)
    m = dw.model
    x0 = m.bpos.copy()
    a0 = m.bang.copy()
    res = m.settle(external=EquivalentThrust(dw))
    assert res.converged
    assert np.abs(m.bpos - x0).max() < 2e-4  # joint closure under 2.8e9 Pa/m
    assert np.abs(m.bang - a0).max() < 1e-3
    assert abs(dw.d_top()) < 1e-9  # the reference is the settled state


def test_errors():
    with pytest.raises(DemWallError, match="courses are unknown"):
        build_wall(preset("mockup-2.7"))
    with pytest.raises(DemWallError, match="stiffness_scale"):
        build_wall(preset("DSRW1"), stiffness_scale=0.0)


def test_headers_and_bond_phase():
    """Header courses are one stone from face to face; bond_phase 1 swaps the courses that start
    with a half stone; the stones still tile the section; bad indices are refused by name."""
    w = preset("DSRW1")
    plain = stones_of_wall(w)
    laid = stones_of_wall(w, headers=[3, 10])
    for k, (a, b) in enumerate(zip(plain, laid, strict=True)):
        if k in (3, 10):
            assert len(a) >= 2 and len(b) == 1
            assert polygon_area_centroid([tuple(p) for p in b[0]])[0] == pytest.approx(
                sum(polygon_area_centroid([tuple(p) for p in q])[0] for q in a), rel=1e-12)
        else:
            assert len(a) == len(b)
    swapped = stones_of_wall(w, bond_phase=1)

    def front_width(course):
        return float(np.ptp(np.asarray(course[0])[:, 0]))

    # phase 0: the odd courses start with a half stone at the front (0.175 m along the bed plus
    # the batter), phase 1 the even ones; the front stones of the other courses are whole
    for k in range(len(plain)):
        half, whole = (plain[k], swapped[k]) if k % 2 else (swapped[k], plain[k])
        assert front_width(half) < 0.2 < 0.35 < front_width(whole)
    dw = build_wall(w, headers=[0], bond_phase=1)
    assert abs(dw.stone_weight / w.weight - 1.0) < 1e-6 and len(dw.courses[0]) == 1
    with pytest.raises(DemWallError, match=r"headers: course 99 is not a course index"):
        stones_of_wall(w, headers=[99])
    with pytest.raises(DemWallError, match="bond_phase must be 0 or 1"):
        stones_of_wall(w, bond_phase=2)

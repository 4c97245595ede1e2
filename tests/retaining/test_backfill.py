"""Discrete granular backfill (murus.retaining.backfill): generation without overlap, bulk unit
weight, at-rest thrust, the absorbing boundary's dashpots, bad input.

A small wall keeps the tests fast: DSRW1's section scaled to H = 0.6 m (B = 0.4 m, six
0.1 m courses), discs of mean radius 0.02 m, W = 1 m (about 400 discs; packing, settling and
relaxation take about 10 s on one core).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from murus import G
from murus.retaining.backfill import (
    CALIBRATION,
    AbsorbingBoundary,
    BackfillError,
    DiscreteBackfill,
    check_overlap,
    generate_packing,
    rolling_for,
    wall_thrust,
    wave_speeds,
)
from murus.retaining.backfill import _grid as grid
from murus.retaining.geometry import preset

#: Critical-state friction angle [deg] of the disc assembly with mu_r = 0.167 (biaxial test,
#: 200 discs, sigma3 = 20 kPa, seed 0: phi_cs = 26.1 deg, phi_peak 32.3 deg for this one
#: assembly; :func:`murus.dem.biaxial.biaxial_test`).
PHI_CS_DEG = 26.1


def small_wall():
    return preset("DSRW1", height=0.6, base_width=0.4, top_width=None)


@pytest.fixture(scope="module")
def settled(small_wall_packing):
    from murus.retaining.dem_wall import build_wall

    w = small_wall()
    p = small_wall_packing  # generate_packing(w, 1.0, radius=0.02, seed=0), tests/conftest.py
    bf = DiscreteBackfill(w, 1.0, "container", packing=p)
    dw = build_wall(w, stiffness_scale=1e-3, backstop=False, add_bodies=bf.add_to)
    bf.settle(dw)
    return w, p, bf, dw


def test_grid_has_no_overlap_and_overlap_is_an_error():
    w = small_wall()
    c, r, _ = grid(w, 1.0, 0.02, 0.2, 0.02, 1.45, 0)
    check_overlap(c, r)  # the generator's grid: no overlap
    assert r.min() >= 0.016 - 1e-12 and r.max() <= 0.024 + 1e-12
    c2 = np.array([[0.0, 0.0], [0.03, 0.0]])
    with pytest.raises(BackfillError, match="overlap"):
        check_overlap(c2, np.array([0.02, 0.02]))


def test_packing_relieved_and_in_region(settled):
    w, p, bf, dw = settled
    check_overlap(p.centres, p.radii)  # the radii are relieved of the elastic overlaps
    xh, zh = w.heel
    assert np.all(p.centres[:, 0] > xh) and np.all(p.centres[:, 0] < xh + 1.0)
    assert np.all(p.centres[:, 1] > zh) and np.all(p.centres[:, 1] <= w.height + 1e-9)
    assert 300 < p.n < 600
    assert 0.75 < p.phi < 0.86  # dense random disc packing (2D)


def test_bulk_unit_weight(settled):
    """The disc density is gamma / (g phi) with phi measured in the interior window of the
    packing; putting it behind the wall and settling again changes phi by the re-compaction
    only. Tolerance 2 %: the grid sampling of phi is exact to ~0.1 % (h = r_min / 10) and the
    re-settling compacts the assembly by 0.3-0.6 % (measured on DSRW1 and this wall)."""
    w, p, bf, dw = settled
    assert bf.unit_weight == pytest.approx(w.backfill_unit_weight, rel=0.02)
    # over the whole region (wall, floor and surface layers included) it is slightly less
    assert 0.9 * w.backfill_unit_weight < bf.unit_weight_region < bf.unit_weight
    m = dw.model
    mass = float(np.sum(m.bmass[bf.discs]))
    assert mass == pytest.approx(bf.density * np.sum(np.pi * p.radii**2), rel=1e-12)


def test_at_rest_thrust(settled):
    """Horizontal thrust of the settled backfill on the wall, ``K = 2 E_h / (gamma h²)``,
    against the closed forms: above the Coulomb active value (EN 1998-5 (E.2) with kh = kv = 0,
    delta = the interface friction, vertical back face) and below the Jaky at-rest value
    ``1 - sin(phi_cs)`` with the critical-state angle of the disc assembly (the stress ratio
    of a gravity deposit is set by the friction mobilised along the loading, near phi_cs), with
    a 15 % margin for the ~30 disc contacts on the back face. Also: the vertical component
    pulls the wall down (wall friction mobilised upwards on the soil) or is small."""
    w, p, bf, dw = settled
    fx, fy = wall_thrust(dw.model, dw.stones, bf.discs)
    h = dw.back_height
    K = -2.0 * fx / (w.backfill_unit_weight * h * h)
    phi = math.radians(w.backfill_friction_deg)
    d = math.radians(w.interface_friction_deg)
    ka = math.cos(phi) ** 2 / (math.cos(d) * (1 + math.sqrt(math.sin(phi + d) * math.sin(phi)
                                                           / math.cos(d))) ** 2)
    k0_cs = 1.0 - math.sin(math.radians(PHI_CS_DEG))
    assert 0.85 * ka < K < 1.15 * k0_cs
    assert abs(fy) < abs(fx) * math.tan(d) + 1e-9


def test_absorbing_dashpot_force():
    """F = static - rho Vp L t (vx - vbx), static - rho Vs L t (vy - vby)."""
    rho, vp, vs = 1519.0, 264.0, 158.0
    L = np.array([0.08, 0.05])
    static = np.array([[-100.0, 0.0, 0.0], [-50.0, 1.0, 0.0]])
    ab = AbsorbingBoundary([3, 7], L, static, rho, vp, vs, thickness=1.0)
    v = np.array([[0.2, -0.1], [0.0, 0.3]])
    f = ab.forces(v, (0.05, 0.1))
    assert f[:, 0] == pytest.approx(static[:, 0] - rho * vp * L * (v[:, 0] - 0.05), rel=1e-14)
    assert f[:, 1] == pytest.approx(static[:, 1] - rho * vs * L * (v[:, 1] - 0.1), rel=1e-14)
    ab.dashpots = False
    assert np.array_equal(ab.forces(v, (0.05, 0.1)), static)


def test_absorbing_hook_on_a_model():
    """Through the engine's external-force hook: a disc moving at a prescribed velocity
    relative to a moving base receives -rho Vp L (v - v_base)."""
    from murus.dem import Model

    m = Model(gravity=0.0)
    m.add_rectangle(1.0, 0.1, center=(0.0, -1.0), kinematic="base")
    d = m.add_disc((0.0, 0.0), 0.05, density=2000.0)
    m.set_base_motion(velocity=lambda t: 0.3 + 0.0 * np.asarray(t))
    m.build()
    m.dt = 1e-4
    ab = AbsorbingBoundary([d], [0.1], np.zeros((1, 3)), 1500.0, 200.0, 100.0)
    m.bvel[d] = (1.0, -0.5)
    ab(m)
    assert m.bext[d, 0] == pytest.approx(-1500.0 * 200.0 * 0.1 * (1.0 - 0.3))
    assert m.bext[d, 1] == pytest.approx(-1500.0 * 100.0 * 0.1 * (-0.5))
    # stable explicit interval: c dt_hook / m <= 0.5
    n = ab.interval(m)
    assert n * m.dt * ab.cn[0] / m.bmass[d] <= 0.5 + 1e-12


def test_wave_speeds_from_seed_tables():
    vp, vs = wave_speeds(preset("DSRW1"))
    rho = 14.9e3 / G
    E, nu = 92.7e6, 0.22
    assert vs == pytest.approx(math.sqrt(E / (2 * (1 + nu) * rho)))
    assert vp == pytest.approx(264.0, abs=1.0) and vs == pytest.approx(158.2, abs=0.5)


def test_rolling_calibration():
    for phi, mu in CALIBRATION:
        assert rolling_for(phi) == pytest.approx(mu)
    assert CALIBRATION[0][1] < rolling_for(40.0) < CALIBRATION[1][1]
    with pytest.raises(BackfillError, match="calibrate"):
        rolling_for(30.0)


def test_bad_input():
    w = small_wall()
    with pytest.raises(BackfillError, match="boundary"):
        DiscreteBackfill(w, 1.0, "free-field")
    with pytest.raises(BackfillError, match="W must be positive"):
        generate_packing(w, -1.0)
    with pytest.raises(BackfillError, match="radius"):
        generate_packing(w, 1.0, radius=0.0)
    with pytest.raises(BackfillError, match="narrower"):
        generate_packing(w, 0.1, radius=0.02)
    with pytest.raises(BackfillError, match="no backfill"):
        DiscreteBackfill(w.with_(backfill_unit_weight=0.0), 1.0)
    with pytest.raises(BackfillError, match="positive"):
        AbsorbingBoundary([0], [0.1], np.zeros((1, 3)), 1500.0, -1.0, 100.0)


def test_collapse_run_rejects_unknown_backfill():
    from murus.retaining.collapse import CollapseError, collapse_run

    with pytest.raises(CollapseError, match="backfill"):
        collapse_run(small_wall(), 5.0, backfill="soil", A_pseudo=1.0)


def test_collapse_run_with_discrete_backfill(small_wall_packing):
    """The integration: a short S2 segment on the small wall, the backfill summary in the
    options, the d_top history sampled as in the thrust case. The packing is the one the run
    would generate from ``W`` and ``radius`` (the session's, tests/conftest.py: the generation
    is tested by the fixture ``settled``)."""
    from murus.retaining.collapse import collapse_run

    r = collapse_run(small_wall(), 5.0, backfill="discrete", t_max=0.1, A_pseudo=1.0,
                     backfill_options=dict(W=1.0, boundary="absorbing", radius=0.02,
                                           packing=small_wall_packing))
    assert not r.collapsed and r.status == "completed"
    o = r.options["backfill_options"]
    assert r.options["backfill"] == "discrete" and o["boundary"] == "absorbing"
    assert o["n_boundary"] > 5 and o["unit_weight"] == pytest.approx(14.9e3, rel=0.02)
    assert r.t.size == r.d_top.size and r.t[-1] == pytest.approx(0.1, abs=0.011)
    assert np.all(np.abs(r.d_top) < 0.01)
    # the snapshot: the discs with their displacement; the container plate of the absorbing
    # boundary, moved out of reach, is not among the polygons
    assert r.disc_radii.size == r.disc_displacement.size == o["n_discs"]
    assert r.disc_centres.shape == (o["n_discs"], 2)
    assert len(r.polygons) == len(r.displacement) == len(r.rotation)
    x_end = small_wall().heel[0] + 1.0 + 0.5  # W = 1 m behind the heel, and the plate width
    assert max(float(np.max(q[:, 0])) for q in r.polygons) < x_end
    import matplotlib

    matplotlib.use("Agg", force=True)
    from murus.retaining.collapse import plot_collapse

    ax = plot_collapse(r.polygons, r.displacement, (r.disc_centres, r.disc_radii),
                       r.disc_displacement, "test")
    assert len(ax.collections) == 2  # the polygons and the discs
    import matplotlib.pyplot as plt

    plt.close(ax.figure)

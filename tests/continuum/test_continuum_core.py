"""Core of the continuum (zones) engine: patch test, Mohr-Coulomb return, gravity column,
oedometer, shear-column frequency and amplification, biaxial strength, bad inputs.

Tolerances come from closed forms (REFERENCE: "Continuum zones"): elasticity of a uniform strain
(exact for constant-strain triangles), the yield surface of the return, the 1D column under
gravity, the oedometric settlement ``s t / M``, the first frequency ``Vs / 4H`` of a layer on a
rigid base and its transfer function, and the Mohr-Coulomb strength
``sigma_1 = N_phi sigma_3 + 2 c sqrt(N_phi)``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from continuum_inputs import rect_mesh, sides

from murus.continuum import (
    ContinuumModel,
    Elastic,
    MaterialError,
    ModelError,
    MohrCoulomb,
    RunError,
)
from murus.continuum import kernels as K

RHO = 2000.0
G_ACC = 9.81


def _distorted(nx=3, ny=3):
    """A 3 x 3 mesh of a 3 m square with the interior gridpoints moved (convex zones)."""
    xy, zones = rect_mesh(nx, ny, 3.0, 3.0)
    rng = np.random.default_rng(4)
    inner = (xy[:, 0] > 0) & (xy[:, 0] < 3) & (xy[:, 1] > 0) & (xy[:, 1] < 3)
    xy[inner] += rng.uniform(-0.2, 0.2, (inner.sum(), 2))
    return xy, zones


# ---------------------------------------------------------------------- patch test
def test_patch_uniform_velocity_gradient_gives_the_elastic_stress():
    xy, zones = _distorted()
    mat = Elastic(density=RHO, E=3e7, nu=0.25)
    m = ContinuumModel(xy, zones, mat, large_strain=False)
    L = np.array([[2e-3, 5e-4], [-1e-3, -3e-3]])  # velocity gradient dv_i/dx_j [1/s]
    m.gvel[:] = m.gxy @ L.T
    dt = m.dt
    K._zones_ser(K._ALL, m.zg, m.zmat, m.zsig, m.zstate, m.zwork, m.zf, m.gxy, m.gvel, m.mprops,
                 m.P)
    exx, eyy = L[0, 0] * dt, L[1, 1] * dt
    exy = 0.5 * (L[0, 1] + L[1, 0]) * dt
    k, g = mat.bulk, mat.shear
    lam = k - 2 * g / 3
    want = np.array([2 * g * exx + lam * (exx + eyy), 2 * g * eyy + lam * (exx + eyy),
                     2 * g * exy, lam * (exx + eyy)])
    scale = np.abs(want).max()
    assert np.abs(m.zsig - want).max() < 1e-10 * scale
    # a uniform stress is in equilibrium: no net force on an interior gridpoint
    f = np.zeros((m.ng, 2))
    np.add.at(f, m.zg.ravel(), m.zf)
    inner = (xy[:, 0] > 0) & (xy[:, 0] < 3) & (xy[:, 1] > 0) & (xy[:, 1] < 3)
    assert np.abs(f[inner]).max() < 1e-10 * scale * 3.0
    # the zones pull the gridpoints of the right side with minus the traction sigma . n
    right = np.abs(xy[:, 0] - 3.0) < 1e-12
    assert f[right, 0].sum() == pytest.approx(-want[0] * 3.0, rel=1e-10)
    assert f[right, 1].sum() == pytest.approx(-want[2] * 3.0, rel=1e-10)


def test_lumped_mass_is_the_zone_mass_and_dt_is_area_over_cp_diagonal():
    xy, zones = rect_mesh(4, 2, 2.0, 1.0)
    mat = Elastic(density=RHO, E=3e7, nu=0.25)
    m = ContinuumModel(xy, zones, mat)
    assert m.gmass.sum() == pytest.approx(RHO * 2.0, rel=1e-13)
    h = 0.5
    assert m.critical_dt() == pytest.approx(h * h / (mat.vp * h * math.sqrt(2)), rel=1e-13)
    assert m.dt == pytest.approx(0.5 * m.critical_dt(), rel=1e-13)


# ---------------------------------------------------------------------- return mapping
def _principal(s):
    """In-plane principal values (a <= b), the angle of b, and szz."""
    c = 0.5 * (s[0] + s[1])
    r = math.hypot(0.5 * (s[0] - s[1]), s[2])
    th = 0.5 * math.atan2(s[2], 0.5 * (s[0] - s[1]))
    return c - r, c + r, th, s[3]


def _in_axes(s, th):
    """Components of s along the axes of angle th (b direction) and th + 90 deg (a)."""
    c, sn = math.cos(th), math.sin(th)
    sb = s[0] * c * c + s[1] * sn * sn + 2 * s[2] * c * sn
    sa = s[0] * sn * sn + s[1] * c * c - 2 * s[2] * c * sn
    off = (s[1] - s[0]) * c * sn + s[2] * (c * c - sn * sn)
    return sa, sb, off


@pytest.mark.parametrize("psi", [0.0, 10.0, 30.0])
def test_return_ends_on_the_yield_surface_with_the_flow_rule(psi):
    mat = MohrCoulomb(density=RHO, E=5e7, nu=0.3, friction_deg=30.0, cohesion=2e4,
                      dilation_deg=psi, tension=5e3)
    row = mat.row()
    mp = row[None, :]
    rng = np.random.default_rng(11)
    n = 3000
    # trial stresses as in a run: an admissible stress (a random stress returned once) plus
    # the elastic increment of one step, a few per cent of the stress level
    base = rng.uniform(-3e5, 1e5, (n, 4))
    base[:, 2] *= 0.5
    K.return_stresses(base, mp, 0)
    trial = base + rng.normal(0.0, 4e3, (n, 4))
    sig = trial.copy()
    flags, dwp = K.return_stresses(sig, mp, 0)
    nphi, npsi, csn, st = row[K.M_NPHI], row[K.M_NPSI], row[K.M_CSN], row[K.M_TENS]
    assert npsi == pytest.approx((1 + math.sin(math.radians(psi)))
                                 / (1 - math.sin(math.radians(psi))))
    k, g = mat.bulk, mat.shear
    counts = np.bincount(flags, minlength=3)[:3]
    assert counts.min() > 20  # elastic, shear and tension cases all exercised
    single = 0
    for i in range(n):
        t = trial[i]
        a, b, th, z = _principal(t)
        scale = max(abs(a), abs(b), abs(z), 1e4)
        sa, sb, off = _in_axes(sig[i], th)
        assert abs(off) < 1e-9 * scale  # principal directions unchanged
        s_sorted = sorted([sa, sb, sig[i, 3]])
        fs = s_sorted[0] - s_sorted[2] * nphi + csn
        if flags[i] == K.R_ELASTIC:
            assert np.array_equal(sig[i], t)
            assert fs >= 0 and s_sorted[2] <= st
            continue
        if flags[i] & K.R_SHEAR:
            assert abs(fs) < 1e-9 * scale * nphi
        if flags[i] & K.R_TENSION:
            assert abs(s_sorted[2] - st) < 1e-9 * scale
        assert fs > -1e-9 * scale * nphi and s_sorted[2] < st + 1e-9 * scale  # admissible
        # plastic strain increment C^-1 (trial - final) in the principal axes of the trial
        d = np.array([a - sa, b - sb, z - sig[i, 3]])
        e = d / (2 * g) + d.sum() / 3 * (1 / (3 * k) - 1 / (2 * g))
        order = np.argsort([a, b, z], kind="stable")
        e1, e2, e3 = e[order]
        n1, n2, n3 = s_sorted
        if flags[i] == K.R_SHEAR and min(n2 - n1, n3 - n2) > 1e-6 * scale:
            # one surface: flow (1, 0, -N_psi) in (s1, s2, s3), intermediate strain zero
            assert abs(e2) < 1e-7 * abs(e1)
            assert e3 / e1 == pytest.approx(-npsi, rel=1e-7)
            single += 1
        elif flags[i] == K.R_SHEAR:
            # on an edge: the flow is a non-negative mix of the two surfaces' flows, so the
            # plastic volume change is the dilatancy of each, (1 - N_psi) / (1 + N_psi) of
            # the plastic shear strain
            gam = e.max() - e.min()
            if psi == 0.0:
                assert abs(e.sum()) < 1e-7 * gam
        elif flags[i] == K.R_TENSION and n2 < st - 1e-6 * scale:
            assert abs(e1) < 1e-7 * abs(e3) and abs(e2) < 1e-7 * abs(e3)
        assert dwp[i] >= -1e-9 * scale * abs(e).max()  # dissipation is not negative
    assert single > 20


# ---------------------------------------------------------------------- gravity column
def test_gravity_column_stresses_and_settlement():
    H = 10.0
    E, nu = 1e8, 0.3
    mat = Elastic(density=RHO, E=E, nu=nu)
    xy, zones = rect_mesh(2, 10, 1.0, H)
    m = ContinuumModel(xy, zones, mat)
    left, right, bottom, top = sides(xy)
    m.fix(left | right, x=True, y=False)
    m.fix(bottom)
    yc = m.centroids()[:, 1]
    res = m.settle(tol=1e-6, reset=False)
    assert res.converged, res.message
    s = m.zone_stress()
    sv = -RHO * G_ACC * (H - yc)
    inner = (yc > 1.0) & (yc < H - 1.0)
    assert np.abs(s[inner, 1] / sv[inner] - 1).max() < 0.01
    assert np.abs(s[inner, 0] / s[inner, 1] - nu / (1 - nu)).max() < 0.01
    M = mat.constrained
    want = -RHO * G_ACC * H * H / (2 * M)
    assert np.abs(m.gdisp[top, 1] / want - 1).max() < 0.02


def test_k0_initial_stresses_are_in_equilibrium():
    H = 10.0
    mat = Elastic(density=RHO, E=1e8, nu=0.25)
    xy, zones = rect_mesh(2, 10, 1.0, H)
    m = ContinuumModel(xy, zones, mat)
    left, right, bottom, top = sides(xy)
    m.fix(left | right, x=True, y=False)
    m.fix(bottom)
    m.initial_stress_k0(k0=0.5)
    s0 = m.zone_stress()
    res = m.settle(tol=1e-5, reset=False)
    assert res.converged
    # K0 stresses at the centroids need only the half-zone correction at the top: settlement
    # far below the gravity settlement of a stress-free column
    M = mat.constrained
    assert np.abs(m.gdisp[top, 1]).max() < 0.05 * RHO * G_ACC * H * H / (2 * M)
    yc = m.centroids()[:, 1]
    inner = (yc > 1.0) & (yc < H - 1.0)
    assert np.allclose(s0[inner, 0], 0.5 * s0[inner, 1], rtol=1e-12)


def test_oedometric_layer_under_pressure():
    t, s = 2.0, 1e5
    mat = Elastic(density=RHO, E=2e7, nu=0.35)
    xy, zones = rect_mesh(2, 4, 1.0, t)
    m = ContinuumModel(xy, zones, mat, gravity=0.0)
    left, right, bottom, top = sides(xy)
    m.fix(left | right, x=True, y=False)
    m.fix(bottom)
    topg = np.flatnonzero(top)
    m.apply_pressure(np.column_stack([topg[:-1], topg[1:]]), s)
    assert m.gext[top, 1].sum() == pytest.approx(-s * 1.0, rel=1e-12)
    res = m.settle(tol=1e-7, reset=False)
    assert res.converged
    want = -s * t / mat.constrained
    assert np.abs(m.gdisp[top, 1] / want - 1).max() < 0.02


# ---------------------------------------------------------------------- shear column
def _shear_column(H=10.0, n=20, vs=100.0, nu=0.3):
    """A column one zone wide: every gridpoint fixed vertically, free horizontally. The exact
    1D shear-beam field (u = u(y), v = 0, only sxy) satisfies it (the vertical fixity carries
    the complementary shear on the sides, sxx = 0 on them), so the column is the 1D layer."""
    G = RHO * vs * vs
    mat = Elastic(density=RHO, E=2 * G * (1 + nu), nu=nu)
    xy, zones = rect_mesh(1, n, 1.0, H)
    m = ContinuumModel(xy, zones, mat, gravity=0.0, large_strain=False)
    left, right, bottom, top = sides(xy)
    m.fix(np.ones(m.ng, bool), x=False, y=True)
    return m, bottom, top


def test_shear_column_first_frequency_and_energy():
    H, vs = 10.0, 100.0
    m, bottom, top = _shear_column(H=H, vs=vs)
    m.fix(bottom)
    f1 = vs / (4 * H)
    # first mode shape as initial velocity
    m.gvel[:, 0] = 0.1 * np.sin(0.5 * np.pi * m.gxy[:, 1] / H)
    m.gvel[bottom, 0] = 0.0
    m.reset_reference()
    g = int(np.flatnonzero(top)[0])
    res = m.run(5.0 / f1, monitors={"u": ("gp", g, "ux")}, every=1)
    assert res.success, res.message
    t, u = res.t, res["u"]
    # zero crossings, linearly interpolated
    k = np.flatnonzero((u[:-1] < 0) != (u[1:] < 0))[1:]
    tz = t[k] - u[k] * (t[k + 1] - t[k]) / (u[k + 1] - u[k])
    f = 0.5 / np.mean(np.diff(tz))
    assert f == pytest.approx(f1, rel=0.01)
    # no damping: kinetic (leapfrog form) + strain energy conserved to round-off (a linear
    # system under central differences conserves m v- . v+ / 2 + the strain energy exactly)
    e = res["energy.kinetic"] + res["energy.strain"]
    assert np.abs(e - e[0]).max() < 1e-9 * e[0]
    assert np.abs(res["energy.error"]).max() < 1e-9 * e[0]


def test_shear_column_on_a_shaking_base_follows_the_damped_transfer_function():
    H, vs, xi = 10.0, 100.0, 0.05
    m, bottom, top = _shear_column(H=H, vs=vs)
    m.set_base(bottom, x=True, y=False)
    f1 = vs / (4 * H)
    w = 2 * np.pi * f1
    ub = 1e-3
    g = int(np.flatnonzero(top)[0])
    res = m.run(12.0, velocity=lambda tt: ub * w * np.cos(w * tt), xi=xi, freq=f1,
                monitors={"u": ("gp", g, "ux"), "ub": ("gp", 0, "ux")}, every=2)
    assert res.success, res.message
    assert np.abs(res["ub"] - ub * np.sin(w * res.t)).max() < 1e-3 * ub
    # closed form with mass-proportional damping on the relative velocity:
    # G u'' + rho (w² - i w aM) u = -rho i w aM u_b, u(base) = u_b, u'(top) = 0
    aM = 4 * np.pi * xi * f1
    kst = np.sqrt(w * w - 1j * w * aM) / vs
    C = -1j * w * aM * ub / (w * w - 1j * w * aM)
    amp = abs(C + (ub - C) / np.cos(kst * H)) / ub
    tail = res.t > 12.0 - 2.0 / f1
    got = np.abs(res["u"][tail]).max() / ub
    assert got == pytest.approx(amp, rel=0.05)
    # energy balance of the driven, damped run: central differences balance the energy of a
    # linear system exactly in the form of ContinuumModel.energy (round-off only)
    e = res.values
    scale = np.abs(e["energy.base_work"]).max()
    assert np.abs(e["energy.error"]).max() < 1e-9 * scale


# ---------------------------------------------------------------------- Mohr-Coulomb
@pytest.mark.parametrize("psi", [0.0, 30.0])
def test_biaxial_compression_yields_at_the_mohr_coulomb_strength(psi):
    """With and without dilation (psi = 30 deg diverged to 3.5e23 Pa on this 2 x 2 sample
    before the triangles of an overlay took their mean isotropic stress after the plastic
    correction)."""
    p, c, phi = 1e5, 1e4, 30.0
    mat = MohrCoulomb(density=RHO, E=1e8, nu=0.3, friction_deg=phi, cohesion=c,
                      dilation_deg=psi)
    xy, zones = rect_mesh(2, 2, 1.0, 1.0)
    m = ContinuumModel(xy, zones, mat, gravity=0.0, large_strain=False)
    left, right, bottom, top = sides(xy)
    m.fix(left, x=True, y=False)
    m.fix(bottom, x=False, y=True)
    m.set_base(top, x=False, y=True)
    rg = np.flatnonzero(right)
    m.apply_pressure(np.column_stack([rg[:-1], rg[1:]]), p)
    m.set_stress(-p, -p, 0.0, -p)
    # the same platen travel (1 cm); slower with dilation, whose lateral flow against the
    # pressure boundary is resisted by the damped inertia of the loaded side (quasi-static
    # within 1 % at this rate)
    v = 0.005 if psi == 0.0 else 0.001
    res = m.run(0.01 / v, velocity=lambda tt: (0.0 * tt, -v + 0.0 * tt), local_damping=0.8,
                monitors={"syy": ("zone", 0, "syy"), "sxx": ("zone", 0, "sxx"),
                          "state": ("zone", 0, "state")}, every=10)
    assert res.success
    nphi = (1 + math.sin(math.radians(phi))) / (1 - math.sin(math.radians(phi)))
    s1 = nphi * p + 2 * c * math.sqrt(nphi)
    assert -res["syy"][-1] == pytest.approx(s1, rel=0.01)
    assert -res["sxx"][-1] == pytest.approx(p, rel=0.01)
    assert int(res["state"][-1]) & K.ST_SHEAR_NOW
    assert (m.plastic_state() & K.ST_SHEAR_PAST).all()
    e = m.energy()
    assert e["plastic"] > 0
    # energy balance with plastic flow, local damping, a driven platen and a pressure: the
    # stress is uniform, so the corner forces are conjugate to the mixed strain increments
    # and the balance is exact (round-off)
    assert abs(e["error"]) < 1e-9 * e["base_work"]


@pytest.mark.parametrize("large", [False, True])
def test_energy_balance_of_a_shaken_mohr_coulomb_layer(large):
    """Gravity, plastic flow, mass-proportional damping and a shaking base: the balance closes
    within 1 % of the base work (issue 17, item 7's criterion); what remains comes from the
    plastic corrections, which differ between the two triangles of an overlay (their forces
    are then not exactly conjugate to the mixed strain increments)."""
    mat = MohrCoulomb(density=RHO, E=1e7, nu=0.3, friction_deg=25.0, cohesion=5e3,
                      dilation_deg=5.0)
    xy, zones = rect_mesh(20, 15, 40.0, 30.0)
    m = ContinuumModel(xy, zones, mat, large_strain=large)
    left, right, bottom, top = sides(xy)
    m.fix(left | right, x=True, y=False)
    m.set_base(bottom)
    assert m.settle(tol=1e-5).converged
    res = m.run(1.0, velocity=lambda t: 0.3 * np.sin(10.0 * t), xi=0.05, freq=2.0, every=20)
    assert res.success
    e = m.energy()
    assert e["plastic"] > 0.3 * e["base_work"]  # a strongly plastic case
    assert np.abs(res["energy.error"]).max() < 0.01 * e["base_work"]


# ---------------------------------------------------------------------- bad inputs
@pytest.mark.parametrize("kw, key", [
    (dict(density=RHO, E=1e7, nu=0.5), ("nu",)),
    (dict(density=RHO, E=-1e7, nu=0.3), ("E",)),
    (dict(density=-1.0, E=1e7, nu=0.3), ("density",)),
    (dict(density=RHO, E=1e7, nu=0.3, K=1e7, G=1e7), ("E",)),
    (dict(density=RHO, E=1e7, nu=0.3, friction_deg=30, dilation_deg=35), ("dilation_deg",)),
    (dict(density=RHO, E=1e7, nu=0.3, friction_deg=30, cohesion=-5.0), ("cohesion",)),
    (dict(density=RHO, E=1e7, nu=0.3, friction_deg=95), ("friction_deg",)),
    (dict(density=RHO, E=1e7, nu=0.3, friction_deg=30, tension=-1.0), ("tension",)),
])
def test_bad_materials_raise_with_the_key(kw, key):
    with pytest.raises(MaterialError) as e:
        MohrCoulomb(**kw)
    assert e.value.key == key


def test_tension_is_capped_at_the_apex():
    mat = MohrCoulomb(density=RHO, E=1e7, nu=0.3, friction_deg=30, cohesion=1e4, tension=1e6)
    assert mat.tensile_strength == pytest.approx(1e4 / math.tan(math.radians(30)))


def test_bad_models_raise_with_the_key():
    xy, zones = rect_mesh(2, 1, 2.0, 1.0)
    mat = Elastic(density=RHO, E=1e7, nu=0.3)
    with pytest.raises(ModelError) as e:
        ContinuumModel(xy, zones[:, ::-1], mat)
    assert e.value.key == ("zones", 0)
    bad = zones.copy()
    bad[1, 2] = 99
    with pytest.raises(ModelError) as e:
        ContinuumModel(xy, bad, mat)
    assert e.value.key == ("zones", 1)
    with pytest.raises(ModelError) as e:
        ContinuumModel(xy, zones, [mat, "clay"], zone_material=[0, 1])
    assert e.value.key == ("materials", 1)
    m = ContinuumModel(xy, zones, mat)
    with pytest.raises(ModelError) as e:
        m.fix([0, 40])
    assert e.value.key == ("fix",)
    with pytest.raises(ModelError) as e:
        m.fix(np.zeros(m.ng, bool))
    assert e.value.key == ("fix",)
    with pytest.raises(ModelError) as e:
        m.apply_pressure([[1, 4]], 1e3)  # the interior edge between the two zones
    assert e.value.key == ("edges", 0)
    with pytest.raises(RunError) as e:
        m.run(-1.0)
    assert e.value.key == ("duration",)
    with pytest.raises(RunError) as e:
        m.run(1.0, monitors={"u": ("gp", 99, "ux")})
    assert e.value.key == ("monitors", "u")
    with pytest.raises(RunError) as e:
        m.settle(alpha=1.0)
    assert e.value.key == ("alpha",)
    with pytest.raises(ModelError) as e:
        m.set_dt(1.01 * m.critical_dt())
    assert e.value.key == ("dt",)
    assert m.set_dt(m.critical_dt()) == m.critical_dt()


# ---------------------------------------------------------------------- quiet base
@pytest.mark.parametrize("wave", ["S", "P"])
def test_a_pulse_leaves_through_the_quiet_base(wave):
    """A downgoing plane pulse (u = f(y + c t): velocity c f', stress rho c times the velocity
    in the matching component) in a 1D column leaves through the quiet base: the energy left in
    the column afterwards is the reflected energy."""
    H, n = 20.0, 40
    mat = Elastic(density=RHO, E=5e7, nu=0.3)
    xy, zones = rect_mesh(1, n, 1.0, H)
    m = ContinuumModel(xy, zones, mat, gravity=0.0, large_strain=False)
    left, right, bottom, top = sides(xy)
    d = 0 if wave == "S" else 1  # the moving direction
    m.fix(np.ones(m.ng, bool), x=(d == 1), y=(d == 0))
    bg = np.flatnonzero(bottom)
    m.add_quiet([[bg[0], bg[1]]])
    c = mat.vs if wave == "S" else mat.vp
    y0, w = 13.0, 1.5

    def vel(y):
        return 0.1 * np.exp(-0.5 * ((y - y0) / w) ** 2)

    m.gvel[:, d] = vel(m.gxy[:, 1])
    yc = m.centroids()[:, 1]
    v = vel(yc)
    k, g = mat.bulk, mat.shear
    if wave == "S":
        m.set_stress(0.0, 0.0, RHO * c * v, 0.0)
    else:
        lam = k - 2 * g / 3
        m.set_stress(lam / (k + 4 * g / 3) * RHO * c * v, RHO * c * v, 0.0,
                     lam / (k + 4 * g / 3) * RHO * c * v)
    m.reset_reference()
    e0 = m.K0 + m.stored_strain_energy()
    res = m.run((y0 + 8 * w) / c, every=10)
    assert res.success
    e = m.energy()
    left_in = e["kinetic"] + m.stored_strain_energy()
    # the strain-energy change from the stress work is the change of the stored energy
    assert e["strain"] == pytest.approx(m.stored_strain_energy() - (e0 - m.K0), rel=1e-9)
    assert left_in < 0.03 * e0
    # the energy that left is the dashpots' work, exactly (linear system, energy() form)
    assert -e["dashpot_work"] == pytest.approx(e0 - left_in, rel=1e-9)


def test_large_strain_rotates_the_stress_with_the_body():
    """A rigid rotation of a prestressed zone (Jaumann rate): no strain, the stress turns with
    the body, R sigma_0 R^T, to first order in the step's rotation (error ~ theta w dt)."""
    xy, zones = rect_mesh(1, 1, 1.0, 1.0)
    mat = Elastic(density=RHO, E=1e8, nu=0.3)
    m = ContinuumModel(xy, zones, mat, gravity=0.0)
    m.set_stress(-1e5, -3e4, 2e4, -4e4)
    s0 = m.zsig[0, 0].copy()
    omega, nsteps = 1.0, 2000
    dt = 0.5 / (omega * nsteps)  # 0.5 rad in all
    m.P[K.P_DT] = dt
    c = np.array([0.5, 0.5])
    for _ in range(nsteps):
        r = m.gxy - c
        m.gvel[:] = omega * np.column_stack([-r[:, 1], r[:, 0]])
        K._zones_ser(K._ALL, m.zg, m.zmat, m.zsig, m.zstate, m.zwork, m.zf, m.gxy, m.gvel,
                     m.mprops, m.P)
        ang = omega * dt  # exact rigid rotation of the coordinates over the step
        R = np.array([[math.cos(ang), -math.sin(ang)], [math.sin(ang), math.cos(ang)]])
        m.gxy[:] = c + (m.gxy - c) @ R.T
    th = omega * dt * nsteps
    R = np.array([[math.cos(th), -math.sin(th)], [math.sin(th), math.cos(th)]])
    S = R @ np.array([[s0[0], s0[2]], [s0[2], s0[1]]]) @ R.T
    want = np.array([S[0, 0], S[1, 1], S[0, 1], s0[3]])
    # the explicit rotation (forward Euler on the spin) lengthens the deviator by
    # sqrt(1 + (2 w dt)²) per step: after N steps, 2 N (w dt)² of its radius
    rad = math.hypot(0.5 * (s0[0] - s0[1]), s0[2])
    bound = 2 * (2 * nsteps * (omega * dt) ** 2) * rad
    for t in range(4):
        assert np.abs(m.zsig[0, t] - want).max() < bound
    # the invariants are kept to round-off order of the step: mean and radius of Mohr's circle
    got = m.zsig[0, 0]
    assert got[0] + got[1] == pytest.approx(s0[0] + s0[1], rel=1e-12)


# ---------------------------------------------------------------------- quiet sides on the base
def _box(frame, static=False):
    """A 4 x 2 m elastic box on a base-driven bottom, its two sides quiet in ``frame``."""
    xy, zones = rect_mesh(8, 4, 4.0, 2.0)
    mat = Elastic(density=RHO, E=5e7, nu=0.3)
    m = ContinuumModel(xy, zones, mat, gravity=0.0, large_strain=False)
    left, right, bottom, top = sides(xy)
    m.set_base(bottom)
    for side in (left, right):
        g = np.flatnonzero(side)
        g = g[np.argsort(xy[g, 1])]
        m.add_quiet(np.stack([g[:-1], g[1:]], axis=1), frame=frame, static=static)
    return m


def test_quiet_sides_on_the_base_do_not_resist_a_rigid_motion_with_it():
    """The box moving with its base at a constant velocity is a rigid translation: dashpots on
    the velocity relative to the base exert nothing (the velocity stays uniform to round-off);
    on the absolute velocity they brake the sides (the closed form of the dashpot force, rho Cp
    v per unit length, decelerates them)."""
    v0 = 0.05
    out = {}
    for frame in ("base", "rest"):
        m = _box(frame)
        m.set_base_motion(velocity=lambda t: np.full(np.shape(t), v0))
        m.gvel[:, 0] = v0
        m.run(0.05)
        out[frame] = m.gvel[:, 0].copy()
    assert np.abs(out["base"] - v0).max() < 1e-12 * v0
    assert np.abs(out["rest"] - v0).max() > 1e-2 * v0


def test_quiet_frame_is_one_per_model():
    m = _box("base")
    with pytest.raises(ModelError) as err:
        m.add_quiet([[0, 1]], frame="rest")
    assert err.value.key == ("quiet", "frame")
    with pytest.raises(ModelError) as err:
        _box("sideways")
    assert err.value.key == ("quiet", "frame")
    # a free-field side's dashpots are not quiet edges: any frame may follow them
    xy, zones = rect_mesh(4, 2, 4.0, 2.0)
    m = ContinuumModel(xy, zones, Elastic(density=RHO, E=5e7, nu=0.3), gravity=0.0)
    left, right, bottom, top = sides(xy)
    m.set_base(bottom)
    m.add_free_field([np.flatnonzero(right)[np.argsort(xy[right, 1])]])
    g = np.flatnonzero(left)[np.argsort(xy[left, 1])]
    m.add_quiet(np.stack([g[:-1], g[1:]], axis=1), frame="base")
    assert m.P[K.P_QFRAME] == 1.0


def test_quiet_side_with_its_static_reaction_keeps_a_settled_layer_at_rest():
    """A layer settled under gravity on rollers: a side made quiet with ``static=True`` keeps
    the roller's reaction as a constant force, so the layer stays at rest (displacement after
    0.2 s below 1e-6 of the oedometric settlement of its top, rho g H^2 / 2M); released
    without it, the side bulges out."""
    res = {}
    for static in (True, False):
        xy, zones = rect_mesh(8, 4, 4.0, 2.0)
        mat = Elastic(density=RHO, E=5e7, nu=0.3)
        m = ContinuumModel(xy, zones, mat, gravity=G_ACC, large_strain=False)
        left, right, bottom, top = sides(xy)
        m.fix(bottom)
        m.fix(left | right, x=True, y=False)
        m.settle(tol=1e-9, max_steps=400_000)
        # the settlement of the layer's top under its own weight, rho g H^2 / (2 M)
        M = mat.E * (1 - mat.nu) / ((1 + mat.nu) * (1 - 2 * mat.nu))
        settle = RHO * G_ACC * 2.0**2 / (2 * M)
        g = np.flatnonzero(right)
        g = g[np.argsort(xy[g, 1])]
        if static:
            m.add_quiet(np.stack([g[:-1], g[1:]], axis=1), frame="base", static=True)
        else:
            m.free(g[1:], x=True, y=False)
        u0 = m.gdisp.copy()
        m.run(0.2)
        res[static] = float(np.abs(m.gdisp - u0).max()) / settle
    assert res[True] < 1e-6  # measured 3e-15 (the settling tolerance is 1e-9)
    assert res[False] > 1e-2

"""Verification cases of the continuum (zones) engine against closed forms and the energy
balance (issue 17 item 7), shared by ``tests/continuum/test_continuum_verification.py`` and
``murus verify continuum``.

Each case function ``case(quick)`` returns a list of rows ``dict(case, expected, obtained,
error, tolerance, passed)``; ``error`` is relative unless the row's case name says otherwise.
``quick=True`` runs a coarser mesh or a shorter run with the same tolerance. Rows of problems
that need parts not built yet (zone-block interfaces, free-field boundaries) carry
``available=False``, ``passed=None`` and NaN numbers: they are listed, neither passed nor failed.

Closed forms (:mod:`murus.continuum.closed_forms`):

- elastic shear column on a shaking rigid base: ``f1 = Vs / 4H`` and the transfer function of the
  layer with mass-proportional damping on the velocity relative to the base (the run's
  ``damping_frame="base"``), :func:`~murus.continuum.closed_forms.layer_transfer_rayleigh`
  (Kramer 1996, ch. 7, for the undamped and hysteretic forms);
- quiet base: a plane P or S pulse at normal incidence on Lysmer & Kuhlemeyer (1969) dashpots,
  reflected energy 0 (:func:`~murus.continuum.closed_forms.quiet_boundary_reflection`);
- cylindrical hole in a Mohr-Coulomb medium (Salençon 1969; Itasca's verification problem,
  G = 2.8 GPa, K = 3.9 GPa, c = 3.45 MPa, phi = 30 deg, psi = 0, P0 = 30 MPa, Pi = 0);
- Prandtl (1920) strip footing on a weightless cohesive soil, ``(2 + pi) c``, and with friction
  the Prandtl-Reissner factor ``N_c`` (Reissner 1924);
- smooth rigid wall moving away from a dry sand backfill: Rankine's ``1/2 K_A gamma H²``;
- oedometric settlement ``s t / M`` of an elastic layer under a uniform pressure;
- energy balance of a dynamic run with plasticity (:meth:`ContinuumModel.energy`).
"""

from __future__ import annotations

import math

import numpy as np

from murus.continuum import closed_forms as cf
from murus.continuum import mesh as cmesh
from murus.continuum.materials import Elastic, MohrCoulomb
from murus.continuum.model import ContinuumModel

__all__ = ["CASES", "run_verification", "footing_limit_pressure", "case_shear_column",
           "case_quiet_base", "case_free_field", "case_hole", "case_prandtl", "case_rankine",
           "case_oedometer", "case_energy"]

RHO = 2000.0
G_ACC = 9.81


def _row(case, expected, obtained, tolerance, relative=True):
    err = abs(obtained - expected) / abs(expected) if relative else abs(obtained - expected)
    return {"case": case, "expected": float(expected), "obtained": float(obtained),
            "error": float(err), "tolerance": float(tolerance),
            "passed": bool(np.isfinite(err) and err <= tolerance)}


def _bound_row(case, obtained, tolerance):
    """A row ``|obtained| <= tolerance`` (expected 0, absolute error): the quantities are
    magnitudes or energy fractions, so a negative value beyond the tolerance is a failure too."""
    return {"case": case, "expected": 0.0, "obtained": float(obtained),
            "error": float(abs(obtained)), "tolerance": float(tolerance),
            "passed": bool(np.isfinite(obtained) and abs(obtained) <= tolerance)}


def _not_available(case, tolerance, why):
    return {"case": f"{case} [not yet available: {why}]", "expected": math.nan,
            "obtained": math.nan, "error": math.nan, "tolerance": float(tolerance),
            "passed": None, "available": False}


def _nodal_forces(m):
    """Forces of the zones on the gridpoints (ng, 2) [N/m] of the last step."""
    f = np.zeros((m.ng, 2))
    np.add.at(f, m.zg.ravel(), m.zf)
    return f


def _column(H, n, mat, x_free=True):
    """A column one zone (1 m) wide and n zones high; every gridpoint fixed in the direction
    that is not the wave's (x_free: shear waves, fixed in y; else P waves, fixed in x), so that
    the column is the 1D medium."""
    msh = cmesh.rectangle(0.0, 0.0, 1.0, H, nx=1, ny=n, name="col")
    m = ContinuumModel(msh.xy, msh.zones, mat, gravity=0.0, large_strain=False)
    m.fix(np.ones(m.ng, bool), x=not x_free, y=x_free)
    return m, msh


# ---------------------------------------------------------------------- 1. shear column
def case_shear_column(quick=False):
    """Elastic layer (H = 10 m, Vs = 100 m/s) on a rigid base, a column one zone wide (the 1D
    shear beam): the first frequency from a free vibration of the first mode, within 1 % of
    ``Vs / 4H``; the steady amplification ``|u_top / u_base|`` when the base shakes at ``f1``
    with 5 % mass-proportional damping (on the velocity relative to the base), within 5 % of
    :func:`~murus.continuum.closed_forms.layer_transfer_rayleigh` (``relative=True``).

    Parameters
    ----------
    quick : bool
        Coarser mesh or shorter run (same tolerance).

    Returns
    -------
    list of dict
        Rows ``dict(case, expected, obtained, error, tolerance, passed)`` (module doc).

    References
    ----------
    Kramer, S. L. (1996). Geotechnical Earthquake Engineering, ch. 7 (layer on a rigid base).
    """
    H, vs, nu, xi = 10.0, 100.0, 0.3, 0.05
    n = 10 if quick else 40
    G = RHO * vs * vs
    mat = Elastic(density=RHO, E=2 * G * (1 + nu), nu=nu)
    f1 = float(cf.layer_frequency(vs, H))
    rows = []
    # free vibration of the first mode shape
    m, msh = _column(H, n, mat)
    bottom, top = msh.side("col.bottom"), msh.side("col.top")
    m.fix(bottom)
    m.gvel[:, 0] = 0.1 * np.sin(0.5 * np.pi * m.gxy[:, 1] / H)
    m.gvel[bottom, 0] = 0.0
    m.reset_reference()
    g = int(top[0])
    res = m.run(5.0 / f1, monitors={"u": ("gp", g, "ux")}, every=1)
    t, u = res.t, res["u"]
    k = np.flatnonzero((u[:-1] < 0) != (u[1:] < 0))[1:]
    tz = t[k] - u[k] * (t[k + 1] - t[k]) / (u[k + 1] - u[k])
    f = 0.5 / float(np.mean(np.diff(tz))) if tz.size > 1 else math.nan
    rows.append(_row(f"shear column H = {H:g} m, Vs = {vs:g} m/s, {n} zones: first frequency "
                     "Vs/4H [Hz]", f1, f, 0.01))
    # harmonic base motion at f1, steady state
    m, msh = _column(H, n, mat)
    bottom, top = msh.side("col.bottom"), msh.side("col.top")
    m.set_base(bottom, x=True, y=False)
    w = 2 * np.pi * f1
    ub = 1e-3
    duration = 12.0
    res = m.run(duration, velocity=lambda tt: ub * w * np.cos(w * tt), xi=xi, freq=f1,
                monitors={"u": ("gp", int(top[0]), "ux")}, every=2)
    alpha = 4 * np.pi * xi * f1
    amp = float(abs(cf.layer_transfer_rayleigh(f1, vs, H, alpha, relative=True)))
    tail = res.t > duration - 2.0 / f1
    got = float(np.abs(res["u"][tail]).max() / ub)
    rows.append(_row(f"shear column on a base shaking at f1, xi = {xi:g} (mass-proportional, "
                     "relative): amplification |u_top/u_base|", amp, got, 0.05))
    return rows


# ---------------------------------------------------------------------- 2. quiet base
def _pulse_energy_reflected(wave, quick):
    """Reflected energy fraction of a plane pulse (P or S) that crosses a quiet base at normal
    incidence, in a 1D column (module doc of :func:`case_quiet_base`)."""
    H = 60.0
    n = 60 if quick else 240
    mat = Elastic(density=RHO, E=5e7, nu=0.3)
    m, msh = _column(H, n, mat, x_free=(wave == "S"))
    bottom = msh.side("col.bottom")
    m.add_quiet(np.column_stack([bottom[:-1], bottom[1:]]))
    m.reset_reference()
    # a down-going wave u = f(y + c t): v = c f'(y), strain du/dy = f'(y); f' a cosine bell
    # of length L centred at y0 (a smooth pulse of 15 zones over a quarter of the column)
    c = mat.vs if wave == "S" else mat.vp
    L, y0, a = H / 4.0, 0.5 * H, 1e-4  # a: peak strain [-]

    def fp(y):
        s = (y - y0) / L
        return np.where(np.abs(s) < 0.5, a * 0.5 * (1 + np.cos(2 * np.pi * s)), 0.0)

    d = 0 if wave == "S" else 1
    m.gvel[:, d] = c * fp(m.gxy[:, 1])
    e = fp(m.centroids()[:, 1])
    lam = mat.bulk - 2 * mat.shear / 3
    if wave == "S":
        m.set_stress(0.0, 0.0, mat.shear * e, 0.0)
    else:
        m.set_stress(lam * e, (lam + 2 * mat.shear) * e, 0.0, lam * e)
    # the energy of the pulse: kinetic and the energy of its stresses (energy()["strain"] is
    # measured from the stresses just set, so it cannot serve here)
    w0 = m.energy()["kinetic"] + m.stored_strain_energy()
    # until the whole pulse has crossed the base and its reflection (if any) is back inside
    res = m.run((y0 + L) / c * 1.3, every=50)
    if not res.success:
        return math.nan
    return (m.energy()["kinetic"] + m.stored_strain_energy()) / w0


def case_quiet_base(quick=False):
    """Quiet (Lysmer-Kuhlemeyer) base under a 1D column (60 m, elastic, one zone wide; the
    gridpoints fixed across the wave so that the column is the 1D medium): a plane P pulse and a
    plane S pulse (cosine bells 15 m long, 15 zones quick and 60 full, set as down-going waves:
    velocity ``c f'`` and the matching stresses) leave through the base. The energy left in the
    column once the pulse has crossed the base is the reflected energy, 0 for the exact plane
    wave at normal incidence (:func:`~murus.continuum.closed_forms.quiet_boundary_reflection`);
    below 3 % of the pulse's energy.

    Parameters
    ----------
    quick : bool
        Coarser mesh or shorter run (same tolerance).

    Returns
    -------
    list of dict
        Rows ``dict(case, expected, obtained, error, tolerance, passed)`` (module doc).

    References
    ----------
    Lysmer, J. and Kuhlemeyer, R. L. (1969). Finite dynamic model for infinite media. J. Eng.
    Mech. Div. ASCE 95(EM4), 859-877.
    """
    rows = []
    for wave in ("P", "S"):
        want = cf.quiet_boundary_reflection(0.0, 1.0, 0.5, wave=wave)
        r = _pulse_energy_reflected(wave, quick)
        rows.append(_bound_row(f"quiet base, {wave} pulse at normal incidence: reflected energy "
                               f"fraction (closed form {want.energy_reflected:.2g}) (abs)",
                               r, 0.03))
    return rows


# ---------------------------------------------------------------------- 3. hole
def _polar(m):
    """Radius [m] and radial, tangential stresses [Pa, compression positive] at the zone
    centroids of a model centred on the origin."""
    c = m.centroids()
    r = np.hypot(c[:, 0], c[:, 1])
    ct, st = c[:, 0] / r, c[:, 1] / r
    s = m.zone_stress()
    srr = s[:, 0] * ct * ct + s[:, 1] * st * st + 2 * s[:, 2] * ct * st
    stt = s[:, 0] * st * st + s[:, 1] * ct * ct - 2 * s[:, 2] * ct * st
    return r, -srr, -stt


def case_hole(quick=False):
    """Cylindrical hole (a = 1 m) in a Mohr-Coulomb medium, plane strain, small strain
    (Salençon 1969; Itasca's verification problem: G = 2.8 GPa, K = 3.9 GPa, c = 3.45 MPa,
    phi = 30 deg, psi = 0, P0 = 30 MPa, Pi = 0): a quarter annulus out to 20 a (radii in
    geometric progression), rollers on the two symmetry rays, the far-field pressure P0 on the
    outer boundary and the initial stress P0 everywhere; the hole is unloaded at once and the
    model settles with local damping (plastic from the start).

    Rows: the plastic radius, from the elastic zones (``sigma_t - sigma_r = 2 C / r²`` and
    ``sigma_t + sigma_r = 2 A`` fitted there, then the radius where the elastic stresses reach
    the yield line ``sigma_t = Kp sigma_r + q``; this also absorbs the finite outer radius),
    within 3 %; the radial and tangential stresses at the zone centroids out to 5 a, the
    largest difference from :func:`~murus.continuum.closed_forms.hole_stresses` (averaged over
    each zone's radial span) as a fraction of P0, within 3 %.

    Parameters
    ----------
    quick : bool
        Coarser mesh or shorter run (same tolerance).

    Returns
    -------
    list of dict
        Rows ``dict(case, expected, obtained, error, tolerance, passed)`` (module doc).

    References
    ----------
    Salençon, J. (1969); Itasca, FLAC Verification Problems: "Cylindrical hole in an infinite
    Mohr-Coulomb medium".
    """
    return hole_solution(quick)[0]


def hole_solution(quick=False):
    """The model of :func:`case_hole`, settled, with its rows.

    Parameters
    ----------
    quick : bool
        Coarser mesh.

    Returns
    -------
    tuple
        ``(rows, model, r, sigma_r, sigma_t)``: the rows of :func:`case_hole`, the settled
        :class:`ContinuumModel`, and the radius [m], radial and tangential stresses [Pa,
        compression positive] at the zone centroids.
    """
    a, b = 1.0, 20.0
    G, K = 2.8e9, 3.9e9
    c, phi, p0 = 3.45e6, 30.0, 30e6
    nr, nt = (40, 16) if quick else (60, 24)
    mat = MohrCoulomb(density=2500.0, K=K, G=G, friction_deg=phi, cohesion=c, dilation_deg=0.0)
    msh = cmesh.annulus(a, b, nr, nt, grading=(b / a) ** (1.0 / nr), name="rock")
    m = ContinuumModel(msh.xy, msh.zones, mat, gravity=0.0, large_strain=False)
    m.fix(msh.side("rock.start"), x=False, y=True)
    m.fix(msh.side("rock.end"), x=True, y=False)
    out = msh.side("rock.outer")
    m.apply_pressure(np.column_stack([out[:-1], out[1:]]), p0)
    m.set_stress(-p0, -p0, 0.0, -p0)
    res = m.settle(tol=1e-6 if quick else 1e-7, elastic_first=False, max_steps=400_000)
    r, sr, st = _polar(m)
    ph = math.radians(phi)
    kp = (1 + math.sin(ph)) / (1 - math.sin(ph))
    q = 2 * c * math.tan(0.25 * math.pi + 0.5 * ph)
    r0 = cf.hole_plastic_radius(a, p0, 0.0, c, ph)
    el = (m.plastic_state() == 0) & (r < 0.5 * b)
    C = float(np.median(0.5 * (st[el] - sr[el]) * r[el] ** 2))
    A = float(np.median(0.5 * (st[el] + sr[el])))
    r0_got = math.sqrt(C * (1 + kp) / ((kp - 1) * A + q)) if res.converged else math.nan
    name = f"hole in Mohr-Coulomb (Salencon), {nr} x {nt} zones:"
    rows = [_row(f"{name} plastic radius R0/a", r0 / a, r0_got / a, 0.03)]
    near = r <= 5 * a
    rc = np.hypot(m.gxy[m.zg[near], 0], m.gxy[m.zg[near], 1])  # corner radii
    # the closed form averaged over each zone's radial span (area weights r dr): a zone's
    # stress is a mean, and the exact tangential stress has a kink at R0
    u = (np.arange(16) + 0.5) / 16
    rr = rc.min(axis=1)[:, None] + (rc.max(axis=1) - rc.min(axis=1))[:, None] * u[None, :]
    srx, stx = cf.hole_stresses(rr.ravel(), a, p0, 0.0, c, ph)
    srx = (srx.reshape(rr.shape) * rr).sum(axis=1) / rr.sum(axis=1)
    stx = (stx.reshape(rr.shape) * rr).sum(axis=1) / rr.sum(axis=1)
    for lab, got, want in (("radial", sr[near], srx), ("tangential", st[near], stx)):
        err = float(np.abs(got - want).max() / p0) if res.converged else math.nan
        rows.append(_bound_row(f"{name} {lab} stress to 5a, max |error| / P0 (abs)", err, 0.03))
    return rows, m, r, sr, st


# ---------------------------------------------------------------------- 6. oedometer, energy
def case_oedometer(quick=False):
    """An elastic layer (t = 2 m, E = 20 MPa, nu = 0.35, 4 m wide, rollers on the sides, fixed
    base, weightless) under a uniform pressure s = 100 kPa on its top, settled with local
    damping: the settlement of the top within 2 % of ``s t / M``
    (:func:`~murus.continuum.closed_forms.oedometric_settlement`). The rigid block pressed on
    the layer needs the zone-block interfaces (listed as not yet available).

    Parameters
    ----------
    quick : bool
        Coarser mesh or shorter run (same tolerance).

    Returns
    -------
    list of dict
        Rows ``dict(case, expected, obtained, error, tolerance, passed)`` (module doc).

    References
    ----------
    The oedometric modulus ``M = E (1 - nu) / ((1 + nu)(1 - 2 nu))``
    (:func:`~murus.continuum.closed_forms.oedometric_modulus`).
    """
    t, s, E, nu = 2.0, 1e5, 2e7, 0.35
    nx, ny = (4, 4) if quick else (8, 16)
    mat = Elastic(density=RHO, E=E, nu=nu)
    msh = cmesh.rectangle(0.0, 0.0, 4.0, t, nx=nx, ny=ny, name="layer")
    m = ContinuumModel(msh.xy, msh.zones, mat, gravity=0.0)
    m.fix(np.concatenate([msh.side("layer.left"), msh.side("layer.right")]), x=True, y=False)
    m.fix(msh.side("layer.bottom"))
    top = msh.side("layer.top")
    m.apply_pressure(np.column_stack([top[:-1], top[1:]]), s)
    res = m.settle(tol=1e-7, reset=False)
    got = float(-m.gdisp[top, 1].mean()) if res.converged else math.nan
    want = cf.oedometric_settlement(s, t, E, nu)
    return [_row(f"oedometric settlement of an elastic layer under a uniform pressure, {nx} x {ny} "
                 "zones: s t / M [m]", want, got, 0.02),
            _not_available("oedometric settlement under a rigid block", 0.02,
                           "zone-block interfaces")]


def case_energy(quick=False):
    """Energy balance of a dynamic run with plasticity: a Mohr-Coulomb soil (10 m x 5 m,
    phi = 30 deg, c = 5 kPa, psi = 0) under gravity (K0 stresses, then settled), on a rigid
    base shaking horizontally (0.5 g sine at 2 Hz, 2 s, 1 s quick), quiet dashpots on both sides,
    5 % mass-proportional damping at 2 Hz, large strain. :meth:`ContinuumModel.energy` gives the
    kinetic, strain and gravity energies, the plastic work, the work of the damping, of the
    dashpots and of the base; their balance closes within 1 % of the largest term over the run
    (the row names the plastic work's share of that scale, so that plasticity is exercised).

    With a dilation it closes too (quick mesh: 0.17 % with psi = 10 deg, 0.79 % with psi = 30
    deg), since the two triangles of an overlay take their mean isotropic stress after the
    plastic correction (:func:`murus.continuum.kernels._iso_mean`); before that it missed by
    16 % and 112 %.

    Parameters
    ----------
    quick : bool
        Coarser mesh or shorter run (same tolerance).

    Returns
    -------
    list of dict
        Rows ``dict(case, expected, obtained, error, tolerance, passed)`` (module doc).

    References
    ----------
    Itasca FLAC, Theory and Background (explicit scheme); the balance of
    :meth:`ContinuumModel.energy`.
    """
    Lx, H = 10.0, 5.0
    nx, ny = (10, 5) if quick else (20, 10)
    mat = MohrCoulomb(density=1900.0, E=3e7, nu=0.3, friction_deg=30.0, cohesion=5e3,
                      dilation_deg=0.0)
    msh = cmesh.rectangle(0.0, 0.0, Lx, H, nx=nx, ny=ny, name="soil")
    m = ContinuumModel(msh.xy, msh.zones, mat)
    left, right = msh.side("soil.left"), msh.side("soil.right")
    bottom = msh.side("soil.bottom")
    m.fix(np.concatenate([left, right]), x=True, y=False)
    m.fix(bottom)
    m.initial_stress_k0()
    m.settle(tol=1e-6)
    # dynamic: the sides free, with dashpots; the base shakes
    m.free(np.concatenate([left, right]), x=True, y=False)
    m.set_base(bottom)
    m.add_quiet(np.column_stack([left[:-1], left[1:]]))
    m.add_quiet(np.column_stack([right[:-1], right[1:]]))
    m.reset_reference()
    f, amax = 2.0, 0.5 * G_ACC
    w = 2 * np.pi * f
    res = m.run(1.0 if quick else 2.0, velocity=lambda tt: amax / w * np.sin(w * tt), xi=0.05,
                freq=f, every=20)
    e = res.values
    terms = ("kinetic", "strain", "gravity", "plastic", "damping_work", "dashpot_work",
             "base_work")
    scale = max(float(np.abs(e["energy." + k]).max()) for k in terms)
    err = float(np.abs(e["energy.error"]).max() / scale) if res.success else math.nan
    share = float(e["energy.plastic"][-1] / scale)
    return [_bound_row(f"energy balance of a shaken Mohr-Coulomb soil, {nx} x {ny} zones "
                       f"(plastic work {share:.0%} of the largest term): max |error| / largest "
                       "term (abs)", err, 0.01),
            _not_available("energy balance with zone-block contacts", 0.01,
                           "zone-block interfaces")]


# ---------------------------------------------------------------------- 5. Rankine wall
def case_rankine(quick=False):
    """A smooth rigid wall (x = 0, H = 4 m) moving away from a dry sand backfill (8 m long,
    Mohr-Coulomb phi = 30 deg, c = 0, psi = 0, unit weight 18 kN/m³ from rho = 1835 kg/m³,
    E = 50 MPa, nu = 0.3) on a smooth base (rollers), rollers at the far end: K0 stresses,
    settled; then the wall gridpoints move outward (-x) slowly, free in y (smooth), with local
    damping, to 1 % of H, and the model settles with the wall held. The thrust, the sum of the
    zones' forces on the wall gridpoints, within 5 % of Rankine's ``1/2 K_A gamma H²``
    (:func:`~murus.continuum.closed_forms.rankine_thrust`). The rough wall (Coulomb) and the
    pseudo-static Mononobe-Okabe thrust need the zone-block interfaces (listed as not yet
    available).

    Parameters
    ----------
    quick : bool
        Coarser mesh or shorter run (same tolerance).

    Returns
    -------
    list of dict
        Rows ``dict(case, expected, obtained, error, tolerance, passed)`` (module doc).

    References
    ----------
    Rankine, W. J. M. (1857) (:func:`~murus.continuum.closed_forms.rankine_thrust`).
    """
    H, Lx, phi = 4.0, 8.0, 30.0
    nx, ny = (16, 8) if quick else (32, 16)
    rho = 18e3 / G_ACC
    mat = MohrCoulomb(density=rho, E=5e7, nu=0.3, friction_deg=phi, cohesion=0.0)
    msh = cmesh.rectangle(0.0, 0.0, Lx, H, nx=nx, ny=ny, name="fill")
    m = ContinuumModel(msh.xy, msh.zones, mat, large_strain=False)
    wall, far = msh.side("fill.left"), msh.side("fill.right")
    m.fix(msh.side("fill.bottom"), x=False, y=True)
    m.fix(np.concatenate([wall, far]), x=True, y=False)
    m.initial_stress_k0()
    s0 = m.settle(tol=1e-6)
    f0 = -float(_nodal_forces(m)[wall, 0].sum())
    # the wall moves away: base-driven in x, at a speed of ~2e-7 H per step
    m.free(wall, x=True, y=False)
    m.set_base(wall, x=True, y=False)
    v = 2e-7 * H / m.dt
    dmax = 0.01 * H
    m.run(dmax / v, velocity=lambda tt: -v * np.ones_like(tt), local_damping=0.8, every=500)
    m.free(wall, x=True, y=False)
    m.fix(wall, x=True, y=False)
    s1 = m.settle(tol=1e-6, elastic_first=False, reset=False)
    thrust = -float(_nodal_forces(m)[wall, 0].sum())
    if not (s0.converged and s1.converged):
        thrust = math.nan
    want = cf.rankine_thrust(mat.density * G_ACC, H, math.radians(phi))
    return [_row(f"smooth wall moving away from a sand backfill (phi = {phi:g} deg), {nx} x {ny} "
                 f"zones (at rest {f0 / want:.2f} x): Rankine thrust [N/m]", want, thrust, 0.05),
            _not_available("rough wall (delta = 2/3 phi): Coulomb thrust", 0.10,
                           "zone-block interfaces"),
            _not_available("pseudo-static kh: Mononobe-Okabe thrust", 0.10,
                           "zone-block interfaces")]


# ---------------------------------------------------------------------- 4. Prandtl
def _footing_load(m, foot):
    """Vertical force of the zones on the footing gridpoints [N/m] (the footing load)."""
    return float(_nodal_forces(m)[foot, 1].sum())


def footing_limit_pressure(phi_deg, n_footing, *, psi_deg=0.0, rough=False, G_over_c=1000.0,
                           settlement=0.025, rate=1e-6, grading=1.1):
    """Limit pressure of a rigid strip footing on a weightless Mohr-Coulomb soil, in units of
    the cohesion (the half model of :func:`murus.continuum.mesh.strip_footing`: B = 1 m,
    5 B deep and wide, rollers on the axis and the far side, fixed base).

    The footing gridpoints move down at a constant velocity (``rate`` B per step; rough: also
    fixed in x, smooth: free in x) with local damping 0.8; the footing load is the sum of the
    zones' vertical forces on them. The limit pressure is the mean load over the last 40 % of
    the settlement (the plateau), divided by B c.

    Parameters
    ----------
    phi_deg, psi_deg : float
        Friction and dilation angles [deg].
    n_footing : int
        Zones across the half-width of the footing.
    rough : bool
        Rough (no horizontal slip) or smooth footing.
    G_over_c : float
        Shear modulus over cohesion [-] (c = 100 kPa, nu = 0.3).
    settlement : float
        Final settlement over B [-].
    rate : float
        Settlement per step over B [-].
    grading : float
        Growth ratio of the zones away from the footing.

    Returns
    -------
    tuple
        (limit pressure / c [-], the load history / (B c) [-], the model).

    References
    ----------
    Prandtl, L. (1920); Itasca FLAC, Theory and Background (local damping, velocities
    prescribed at gridpoints).
    """
    B, c, nu = 1.0, 1e5, 0.3
    G = G_over_c * c
    mat = MohrCoulomb(density=2000.0, E=2 * G * (1 + nu), nu=nu, friction_deg=phi_deg,
                      cohesion=c, dilation_deg=psi_deg)
    msh = cmesh.strip_footing(B, 5 * B, 5 * B, n_footing=n_footing, grading=grading)
    m = ContinuumModel(msh.xy, msh.zones, mat, gravity=0.0, large_strain=False)
    foot = msh.side("footing")
    m.fix(msh.side("axis"), x=True, y=False)
    m.fix(msh.side("far"), x=True, y=False)
    m.fix(msh.side("base"))
    if rough:
        m.fix(foot, x=True, y=False)
    m.set_base(foot, x=False, y=True)
    v = rate * B / m.dt
    res = m.run(settlement * B / v, velocity=lambda tt: (np.zeros_like(tt), -v * np.ones_like(tt)),
                local_damping=0.8, monitors={"F": lambda mm: _footing_load(mm, foot)}, every=200)
    q = res["F"] / (B * c)
    if not res.success or not np.all(np.isfinite(q)):
        return math.nan, q, m
    tail = res.t >= 0.6 * res.t[-1]
    return float(q[tail].mean()), q, m


def case_prandtl(quick=False):
    """Prandtl's strip footing on a weightless cohesive soil (phi = 0, c): ``(2 + pi) c``
    within 5 %; with friction (phi = 30 deg), the Prandtl-Reissner factor ``N_c = 30.14``
    within 10 % (:func:`~murus.continuum.closed_forms.strip_footing_capacity`); smooth rigid
    footing, :func:`footing_limit_pressure`. The frictional case uses associated flow (psi =
    phi), the assumption of the Prandtl-Reissner solution (8 zones under the half-width: 30.73
    c, 16: 28.90 c; with psi = 0: 28.65 c and 28.00 c).

    Parameters
    ----------
    quick : bool
        Coarser mesh or shorter run (same tolerance).

    Returns
    -------
    list of dict
        Rows ``dict(case, expected, obtained, error, tolerance, passed)`` (module doc).

    References
    ----------
    Prandtl, L. (1920); Reissner, H. (1924)
    (:func:`~murus.continuum.closed_forms.bearing_capacity_factors`).
    """
    rows = []
    for phi, nf, G_c, s, tol in ((0.0, 12 if quick else 24, 1000.0, 0.025, 0.05),
                                 (30.0, 8 if quick else 16, 5000.0, 0.05, 0.10)):
        want = cf.strip_footing_capacity(1.0, math.radians(phi))
        got, _, m = footing_limit_pressure(phi, nf, psi_deg=phi, G_over_c=G_c, settlement=s)
        lab = "(2 + pi)" if phi == 0.0 else "Prandtl-Reissner N_c"
        rows.append(_row(f"strip footing (Prandtl), smooth, phi = psi = {phi:g} deg, "
                         f"{nf} zones under the half-width ({m.nz} zones): q_u / c = {lab}",
                         want, got, tol))
    return rows


def case_free_field(quick=False):
    """Free-field lateral boundaries: an elastic layer (H = 10 m, Vs = 100 m/s, 40 m wide, 20 m
    quick) with free-field sides (:mod:`murus.continuum.freefield`) on a rigid base shaken
    harmonically at its first frequency (a vertically propagating S wave), 5 % mass-proportional
    damping, 12 s: the top gridpoints at a side and at the centre move as the top of the 1D
    free-field column within 2 % of its amplitude, and that amplitude is the damped layer's
    closed form (:func:`~murus.continuum.closed_forms.layer_transfer_rayleigh`) within 5 %.
    Without the free field the sides deviate by 49 % (free) or 88 % (quiet dashpots) from the
    centre (tests/continuum/test_continuum_freefield.py).

    Parameters
    ----------
    quick : bool
        Coarser mesh or shorter run (same tolerance).

    Returns
    -------
    list of dict
        Rows ``dict(case, expected, obtained, error, tolerance, passed)`` (module doc).

    References
    ----------
    Itasca FLAC, Dynamic Analysis (free-field boundaries); Kramer (1996), ch. 7 (the layer).
    """
    from murus.continuum.materials import Elastic

    H, vs, rho, nu = 10.0, 100.0, 2000.0, 0.3
    width, nx = (20.0, 4) if quick else (40.0, 8)
    G = rho * vs * vs
    mat = Elastic(density=rho, E=2 * G * (1 + nu), nu=nu)
    msh = cmesh.rectangle(0.0, 0.0, width, H, nx=nx, ny=10, name="layer")
    m = ContinuumModel(msh.xy, msh.zones, mat, gravity=0.0, large_strain=False)
    bottom = msh.side("layer.bottom")
    m.set_base(bottom, x=True, y=False)
    m.fix(bottom, x=False, y=True)
    m.add_free_field([msh.side("layer.left"), msh.side("layer.right")])
    top = msh.side("layer.top")
    side = int(top[np.argmin(msh.xy[top, 0])])
    centre = int(top[np.argmin(np.abs(msh.xy[top, 0] - 0.5 * width))])
    col_top = int(m.ff.fstart[1] - 1)
    f1, xi, ub = vs / (4 * H), 0.05, 1e-3
    w = 2 * math.pi * f1
    res = m.run(12.0, velocity=lambda tt: ub * w * np.cos(w * tt), xi=xi, freq=f1,
                monitors={"side": ("gp", side, "ux"), "centre": ("gp", centre, "ux"),
                          "ff": lambda mm: float(mm.ff.fdisp[col_top, 0])}, every=4)
    tail = res.t > 12.0 - 2.0 / f1
    amp = float(np.abs(res["ff"][tail]).max())
    d_side = float(np.abs(res["side"][tail] - res["ff"][tail]).max() / amp)
    d_centre = float(np.abs(res["centre"][tail] - res["ff"][tail]).max() / amp)
    want = cf.layer_transfer_rayleigh(f1, vs, H, 4 * math.pi * xi * f1, relative=True)
    if not res.success:
        d_side = d_centre = amp = math.nan
    return [_bound_row(f"free-field sides, {msh.n_zones} zones, S wave at f1: max |u_side - "
                       "u_column| / column amplitude (abs)", d_side, 0.02),
            _bound_row("free field: max |u_centre - u_column| / column amplitude (abs)",
                       d_centre, 0.02),
            _row("free field: column amplitude / base amplitude = damped layer", want,
                 amp / ub, 0.05)]


CASES = {
    "shear_column": case_shear_column,
    "quiet_base": case_quiet_base,
    "free_field": case_free_field,
    "hole": case_hole,
    "prandtl": case_prandtl,
    "rankine": case_rankine,
    "oedometer": case_oedometer,
    "energy": case_energy,
}


def run_verification(quick: bool = False) -> list[dict]:
    """All verification cases: rows dict(case, expected, obtained, error, tolerance, passed).

    Parameters
    ----------
    quick : bool
        Run the short variants of the cases.

    Returns
    -------
    list of dict
        One row per check; rows of problems not yet available have ``passed=None``.

    References
    ----------
    The closed forms of :mod:`murus.continuum.closed_forms` (module doc).
    """
    rows = []
    for fn in CASES.values():
        rows.extend(fn(quick))
    return rows

"""Verification cases of the continuum (zones) engine against closed forms and the energy
balance (issue 17 item 7), shared by ``tests/continuum/test_continuum_verification.py`` and
``murus verify continuum``.

Each case function ``case(quick)`` returns a list of rows ``dict(case, expected, obtained,
error, tolerance, passed)``; ``error`` is relative unless the row's case name says otherwise.
``quick=True`` runs a coarser mesh or a shorter run with the same tolerance. Rows of problems
that need parts not built yet would carry ``available=False``, ``passed=None`` and NaN numbers
(:func:`_not_available`): listed, neither passed nor failed (none today).

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
- rough rigid wall (a distinct-element block, through the zone-block interface): Coulomb's
  thrust and, with tilted gravity, Mononobe-Okabe's
  (:func:`~murus.continuum.closed_forms.active_thrust`);
- oedometric settlement ``s t / M`` of an elastic layer under a uniform pressure, and of the
  layer under a rigid block resting on it through the interface;
- energy balance of a dynamic run with plasticity (:meth:`ContinuumModel.energy`), and of
  blocks, zones and interface together with plasticity and slip
  (:meth:`murus.continuum.coupled.CoupledModel.energy`).

The coupled rows use :class:`murus.continuum.coupled.CoupledModel`.
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
           "case_oedometer", "case_energy", "wall_thrust", "wall_friction_rows",
           "block_on_layer", "block_settlement", "coupled_energy"]

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
    (:func:`~murus.continuum.closed_forms.oedometric_settlement`); and a rigid block (a
    distinct-element body) resting on an elastic layer through the zone-block interface, its
    settlement within 2 % of the oedometric closed form (:func:`block_settlement`).

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
            block_settlement(quick)[0]]


#: The block on a layer of :func:`block_on_layer`: layer width W, thickness H, block height HB,
#: overhang [m]; E [Pa], nu; interface kn [Pa/m].
BLOCK_LAYER = {"W": 2.0, "H": 1.0, "HB": 0.5, "over": 0.1, "E": 1e7, "nu": 0.25, "kn": 1e9}


def block_on_layer(nx: int = 4, ny: int = 4):
    """A rigid block resting on an elastic layer through the zone-block interface (the coupled
    model of :func:`case_oedometer`'s block row and of tests/continuum/test_continuum_coupled.py).

    The layer: 2 m wide, 1 m thick, rho = 2000 kg/m³, E = 10 MPa, nu = 0.25, rollers on its
    sides (smooth rigid walls), fixed base, under its own weight (g = 9.81 m/s²); the block:
    2.2 m x 0.5 m, rho = 2000 kg/m³, centred on the layer, its underside on the top surface (it
    overhangs by 0.1 m on each side, so that its flat face, not its rounded corners, covers every
    top gridpoint); interface kn = ks = 1e9 Pa/m, friction 30 deg.

    Parameters
    ----------
    nx, ny : int
        Zones across and through the layer.

    Returns
    -------
    tuple
        ``(coupled, dem, zones, interface)``: the :class:`~murus.continuum.coupled.CoupledModel`,
        the blocks' :class:`murus.dem.Model`, the :class:`ContinuumModel` and the
        :class:`~murus.continuum.interface.Interface`, not settled.

    References
    ----------
    Itasca UDEC, Theory and Background (blocks and zones in one calculation cycle).
    """
    from murus.continuum.coupled import CoupledModel
    from murus.continuum.interface import Interface
    from murus.dem import Joint, Model

    W, H, HB, over = BLOCK_LAYER["W"], BLOCK_LAYER["H"], BLOCK_LAYER["HB"], BLOCK_LAYER["over"]
    msh = cmesh.rectangle(0.0, 0.0, W, H, nx=nx, ny=ny, name="layer")
    zm = ContinuumModel(msh.xy, msh.zones, Elastic(density=RHO, E=BLOCK_LAYER["E"],
                                                   nu=BLOCK_LAYER["nu"]), gravity=G_ACC)
    zm.fix(msh.side("layer.left"), x=True, y=False)
    zm.fix(msh.side("layer.right"), x=True, y=False)
    zm.fix(msh.side("layer.bottom"))
    joint = Joint(kn=BLOCK_LAYER["kn"], ks=BLOCK_LAYER["kn"], friction_deg=30.0)
    dm = Model(thickness=1.0, gravity=G_ACC, joint=joint, rounding=1e-3)
    dm.add_rectangle(W + 2 * over, HB, center=(0.5 * W, H + 0.5 * HB), density=RHO)
    iface = Interface.from_side(zm, msh, "layer.top", dm, joint)
    return CoupledModel(dm, zm, iface), dm, zm, iface


def block_settlement(quick: bool = False):
    """The block of :func:`block_on_layer` settled under gravity: its settlement against the
    oedometric closed form ``rho g H² / (2 M) + p H / M + p / kn`` (the layer's self-weight,
    the block's pressure ``p`` = its weight over the layer's width, the interface spring).

    Parameters
    ----------
    quick : bool
        4 x 4 zones (else 8 x 8).

    Returns
    -------
    tuple
        ``(row, coupled)``: the row (2 %) and the settled
        :class:`~murus.continuum.coupled.CoupledModel`.

    References
    ----------
    :func:`~murus.continuum.closed_forms.oedometric_settlement`.
    """
    n = 4 if quick else 8
    cm, dm, zm, iface = block_on_layer(n, n)
    b = BLOCK_LAYER
    y0 = float(dm.bpos[0, 1])
    res = cm.settle(tol=1e-7, max_steps=400_000)
    got = y0 - float(dm.bpos[0, 1]) if res.converged else math.nan
    weight = RHO * (b["W"] + 2 * b["over"]) * b["HB"] * G_ACC
    p = weight / b["W"]
    want = (cf.oedometric_settlement(0.5 * RHO * G_ACC * b["H"], b["H"], b["E"], b["nu"])
            + cf.oedometric_settlement(p, b["H"], b["E"], b["nu"]) + p / b["kn"])
    row = _row(f"rigid block (a distinct-element body) on an elastic layer through the "
               f"interface, {zm.nz} zones: settlement rho g H^2/2M + p H/M + p/kn [m]",
               want, got, 0.02)
    return row, cm


def case_energy(quick=False):
    """Energy balance of a dynamic run with plasticity: a Mohr-Coulomb soil (10 m x 5 m,
    phi = 30 deg, c = 5 kPa, psi = 0) under gravity (K0 stresses, then settled), on a rigid
    base shaking horizontally (0.5 g sine at 2 Hz, 2 s, 1 s quick), quiet dashpots on both sides,
    5 % mass-proportional damping at 2 Hz, large strain. :meth:`ContinuumModel.energy` gives the
    kinetic, strain and gravity energies, the plastic work, the work of the damping, of the
    dashpots and of the base; their balance closes within 1 % of the largest term over the run
    (the row names the plastic work's share of that scale, so that plasticity is exercised).
    Then blocks, zones and interface together: a block on a Mohr-Coulomb layer shaken by its
    base, where zones yield and the block slides (:func:`coupled_energy`), within 1 % of the
    input work.

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
            _coupled_energy_row(quick)]


def _coupled_energy_row(quick):
    r, info, _ = coupled_energy(quick)
    return _bound_row(f"energy balance of a block on a Mohr-Coulomb layer shaken by its base, "
                      f"{info['nz']} zones ({info['plastic_zones']} yielded, plastic work "
                      f"{info['plastic']:.0f} J; interface slip {info['slip']:.0f} J; input "
                      f"work {info['input_work']:.0f} J): max |error| / max |input work| (abs)",
                      r, 0.01)


def coupled_energy(quick: bool = False):
    """Energy balance of blocks, zones and interface in a dynamic run with plasticity and
    contact slip (:meth:`murus.continuum.coupled.CoupledModel.energy`).

    A Mohr-Coulomb layer (2 m x 1 m; rho = 2000 kg/m³, E = 20 MPa, nu = 0.3, phi = 30 deg,
    c = 2 kPa, psi = 0; large strain) whose sides (in x) and bottom move with the base carries
    a block (0.8 m x 0.5 m, rho = 2000 kg/m³) through the interface (kn = ks = 1e9 Pa/m,
    friction 25 deg); settled under gravity, then the base shakes horizontally (velocity
    0.3 sin(2 pi 4 t) m/s, 1 s, 2 s full) with 5 % mass-proportional damping at 4 Hz: zones
    yield under the block and the block slides on the layer.

    The error of the balance is measured against the work put in from outside (the work of the
    base on the blocks and on the zones, of the applied forces on both, and of the tilt; here
    the zones' base work alone is non-zero): ``max |error(t)| / max |W_in(t)|``. Not the
    largest term of the balance: the blocks' gravity term is their potential energy from the
    datum (m g y, the reference subtracted in the error), which would dilute the error by the
    height of the block above y = 0; every change of the energy comes from the input work.

    Parameters
    ----------
    quick : bool
        8 x 4 zones and 1 s (else 16 x 8 zones and 2 s).

    Returns
    -------
    tuple
        ``(ratio, info, coupled)``: the error ratio [-] (NaN when the run did not complete),
        a dict of the run's ``input_work``, ``plastic`` work, interface ``slip`` [J],
        ``plastic_zones`` (zones that yielded) and ``nz``, and the
        :class:`~murus.continuum.coupled.CoupledModel`.

    References
    ----------
    Itasca UDEC, Theory and Background (energy of blocks and zones); the balance of
    :func:`murus.dem.engine.energy`.
    """
    from murus.continuum.coupled import CoupledModel
    from murus.continuum.interface import Interface
    from murus.dem import Joint, Model

    W, H, HB = 2.0, 1.0, 0.5
    nx, ny, T = (8, 4, 1.0) if quick else (16, 8, 2.0)
    mat = MohrCoulomb(density=RHO, E=2e7, nu=0.3, friction_deg=30.0, cohesion=2e3,
                      dilation_deg=0.0)
    msh = cmesh.rectangle(0.0, 0.0, W, H, nx=nx, ny=ny, name="layer")
    zm = ContinuumModel(msh.xy, msh.zones, mat, gravity=G_ACC)
    zm.set_base(msh.side("layer.left"), x=True, y=False)
    zm.set_base(msh.side("layer.right"), x=True, y=False)
    zm.set_base(msh.side("layer.bottom"))
    joint = Joint(kn=1e9, ks=1e9, friction_deg=25.0)
    dm = Model(thickness=1.0, gravity=G_ACC, joint=joint, rounding=1e-3)
    dm.add_rectangle(0.8, HB, center=(0.5 * W, H + 0.5 * HB), density=RHO)
    iface = Interface.from_side(zm, msh, "layer.top", dm, joint)
    cm = CoupledModel(dm, zm, iface)
    ok = cm.settle(tol=1e-6, max_steps=200_000).converged
    f = 4.0
    dm.set_base_motion(velocity=lambda t: 0.3 * np.sin(2 * np.pi * f * t))
    res = cm.run(T, xi=0.05, freq=f, every=50)
    e = res.values
    win = sum(e["energy." + k] for k in ("base_work", "zones_base_work", "external_work",
                                         "zones_external_work", "tilt_work"))
    ratio = float(np.abs(e["energy.error"]).max() / np.abs(win).max())
    if not (ok and res.status == "completed"):
        ratio = math.nan
    info = {"input_work": float(win[-1]), "plastic": float(e["energy.zones_plastic"][-1]),
            "slip": float(e["energy.interface_slip"][-1]),
            "plastic_zones": int((zm.plastic_state() > 0).sum()), "nz": zm.nz}
    return ratio, info, cm


# ---------------------------------------------------------------------- 5. Rankine wall
def case_rankine(quick=False):
    """A smooth rigid wall (x = 0, H = 4 m) moving away from a dry sand backfill (8 m long,
    Mohr-Coulomb phi = 30 deg, c = 0, psi = 0, unit weight 18 kN/m³ from rho = 1835 kg/m³,
    E = 50 MPa, nu = 0.3) on a smooth base (rollers), rollers at the far end: K0 stresses,
    settled; then the wall gridpoints move outward (-x) slowly, free in y (smooth), with local
    damping, to 1 % of H, and the model settles with the wall held. The thrust, the sum of the
    zones' forces on the wall gridpoints, within 5 % of Rankine's ``1/2 K_A gamma H²``
    (:func:`~murus.continuum.closed_forms.rankine_thrust`). Then the rough wall, a
    distinct-element block against the backfill through the zone-block interface: Coulomb's
    thrust and, with tilted gravity, Mononobe-Okabe's, within 10 % (:func:`wall_friction_rows`).

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
            *wall_friction_rows(quick)]


# ---------------------------------------------------------------------- 5b. rigid block wall
def wall_thrust(delta_deg: float = 20.0, tilt_deg: float = 0.0, quick: bool = False, *,
                increments: int = 8, step: float = 0.0005, kn: float = 2e8):
    """Horizontal thrust of a dry sand backfill on a rigid wall (a distinct-element block) that
    rotates away from it about its heel, through the zone-block interface
    (:class:`~murus.continuum.coupled.CoupledModel`).

    The backfill (H = 4 m high, 8 m long; Mohr-Coulomb phi = 30 deg, c = 0, psi = 0, unit
    weight 18 kN/m³, E = 50 MPa, nu = 0.3; large strain) rests on a rough fixed base, rollers
    at the far end; the gridpoint at the heel is free in x (it belongs to the wall's face, not
    to the base: fixed there, it would carry the thrust of the bottom zones itself). The wall is
    a ``"prescribed"`` block 0.5 m thick whose face is the backfill's side x = 0, from 0.5 m
    below the base to 0.5 m above the surface; the interface has kn = ks = ``kn`` [Pa/m], the
    wall friction ``delta``, no cohesion nor tension. Gravity (the blocks' model's, which the
    zones follow) may be tilted by ``tilt_deg`` towards the wall: a pseudo-static
    ``kh = tan(tilt)`` on ``g cos(tilt)``. K0 stresses (``nu / (1 - nu)``), settled with the
    wall held; then ``increments`` rotations of the wall about its heel, each moving the top of
    its face by ``step H`` away from the backfill at 2e-7 H per time step with local damping
    0.7, followed by a settling with the wall held. The thrust is the horizontal force of the
    interface on the wall at each settled state; the active thrust is the smallest.

    Why a rough base and a rotation: on a smooth base the backfill's horizontal equilibrium
    makes the wall's thrust equal the far end's, which cannot drop below Rankine's whatever the
    wall friction (a rough wall then gave Rankine's thrust, +21 % on Coulomb's, in a trial with
    16 x 8 zones); a wall that translates on a rough base tears the bottom zones off the fixed
    base at the heel (-17 % on Coulomb's and on Rankine's in the same trials).
    The rotation about the heel is the classical active test (Terzaghi's); the soil settles
    along the wall and mobilises the wall friction over its height.

    Parameters
    ----------
    delta_deg : float
        Wall friction angle of the interface [deg] (0: smooth).
    tilt_deg : float
        Tilt of gravity towards the wall [deg] (0: static).
    quick : bool
        16 x 8 zones (else 32 x 16).
    increments : int
        Rotation increments.
    step : float
        Movement of the top of the wall per increment over H [-].
    kn : float
        Normal and shear stiffness of the interface [Pa/m].

    Returns
    -------
    tuple
        ``(thrust, history, model)``: the smallest settled thrust [N/m], the thrusts of the
        settled states (the first at rest) [N/m], and the :class:`CoupledModel`; the thrust is
        NaN when a settling did not converge.

    References
    ----------
    Terzaghi, K. (1943). Theoretical Soil Mechanics, ch. 5 (active earth pressure, the wall
    yielding by rotation about its base); Itasca UDEC, Theory and Background (blocks and zones).
    """
    from murus.continuum.coupled import CoupledModel
    from murus.continuum.interface import Interface
    from murus.dem import Joint, Model

    H, Lx, phi = 4.0, 8.0, 30.0
    nx, ny = (16, 8) if quick else (32, 16)
    rho = 18e3 / G_ACC
    mat = MohrCoulomb(density=rho, E=5e7, nu=0.3, friction_deg=phi, cohesion=0.0)
    msh = cmesh.rectangle(0.0, 0.0, Lx, H, nx=nx, ny=ny, name="fill")
    zm = ContinuumModel(msh.xy, msh.zones, mat, gravity=G_ACC)
    base = msh.side("fill.bottom")
    zm.fix(base)
    zm.free([int(base[np.argmin(msh.xy[base, 0])])], x=True, y=False)
    zm.fix(msh.side("fill.right"), x=True, y=False)
    zm.initial_stress_k0()
    dm = Model(thickness=1.0, gravity=G_ACC, joint=Joint(kn=kn, ks=kn, friction_deg=delta_deg))
    wall = dm.add_rectangle(0.5, H + 1.0, center=(-0.25, 0.5 * H), kinematic="prescribed")
    iface = Interface.from_side(zm, msh, "fill.left", dm,
                                Joint(kn=kn, ks=kn, friction_deg=delta_deg))
    cm = CoupledModel(dm, zm, iface)
    if tilt_deg:
        dm.set_tilt(0.0, start_deg=-tilt_deg)

    def thrust():
        return -float(iface.work.fb[wall, 0]) / dm.thickness

    ok = cm.settle(tol=1e-6, max_steps=200_000).converged
    hist = [thrust()]
    v = 2e-7 * H / cm.dt  # speed of the top of the face [m/s]
    for _ in range(increments):
        if not ok:
            break
        om = v / H  # counter-clockwise: the top moves to -x
        c = dm.bpos[wall, :2]  # centroid relative to the heel (0, 0)
        dm.set_velocity(wall, -om * c[1], om * c[0], om)
        cm.run(step * H / v, local_damping=0.7, every=10_000)
        dm.set_velocity(wall, 0.0, 0.0, 0.0)
        ok = cm.settle(tol=1e-6, max_steps=200_000, reset=False).converged
        hist.append(thrust())
    hist = np.array(hist)
    return (float(hist[1:].min()) if ok else math.nan), hist, cm


def wall_friction_rows(quick=False):
    """A rough rigid wall (a distinct-element block, delta = 2/3 phi = 20 deg, no cohesion)
    rotating away from a dry sand backfill (phi = 30 deg, c = 0, psi = 0), through the
    zone-block interface (:func:`wall_thrust`): the smallest horizontal thrust within 10 % of
    Coulomb's active thrust times ``cos delta``; with gravity tilted by 11.31 deg towards the
    wall (``kh = tan(tilt) = 0.2`` on ``g cos(tilt)``) within 10 % of Mononobe-Okabe's
    (:func:`~murus.continuum.closed_forms.active_thrust` with ``kh = sin(tilt)``,
    ``kv = 1 - cos(tilt)``, i.e. ``theta = tilt``, EN 1998-5 (E.6)).

    The Mononobe-Okabe wall is rough too, the same model as Coulomb's with only the tilt added:
    the two rows then differ by the pseudo-static load alone, and Mononobe-Okabe is used with
    the wall friction in practice (EN 1998-5 Annex E, delta up to 2/3 phi). A smooth wall gives
    1.039 (16 x 8 zones) and 1.027 (32 x 16) of the smooth Mononobe-Okabe thrust, the rough
    1.050 and 1.027; the smooth wall without tilt 1.002 and 0.998 of Rankine's (the coupled
    model against the zones-only row above).

    Parameters
    ----------
    quick : bool
        Coarser mesh (same tolerance).

    Returns
    -------
    list of dict
        Rows ``dict(case, expected, obtained, error, tolerance, passed)`` (module doc).

    References
    ----------
    Coulomb (1776); Mononobe, N. and Matsuo, H. (1929); Okabe, S. (1926); Kramer (1996),
    ch. 11 (:func:`~murus.continuum.closed_forms.active_thrust`).
    """
    phi, delta, tilt = 30.0, 20.0, math.degrees(math.atan(0.2))
    gamma = 18e3
    rows = []
    for t in (0.0, tilt):
        got, hist, cm = wall_thrust(delta, t, quick)
        th = math.radians(t)
        d = math.radians(delta)
        want = cf.active_thrust(gamma, 4.0, math.radians(phi), d, kh=math.sin(th),
                                kv=1.0 - math.cos(th)) * math.cos(d)
        nz = cm.zones.nz
        if t == 0.0:
            name = (f"rough wall (block, delta = {delta:g} deg) rotating away from a sand "
                    f"backfill, {nz} zones (at rest {hist[0] / want:.2f} x): Coulomb thrust "
                    "P_A cos(delta) [N/m]")
        else:
            name = (f"rough wall, gravity tilted {t:.2f} deg (kh = {math.tan(th):.2g}), {nz} "
                    f"zones: Mononobe-Okabe thrust P_AE cos(delta) [N/m]")
        rows.append(_row(name, want, got, 0.10))
    return rows


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

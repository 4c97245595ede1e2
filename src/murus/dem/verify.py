"""Verification cases of the distinct-element engine (closed forms, murus.rocking, conservation
laws, a published collapse limit), shared by ``tests/dem/test_verification.py`` and
``murus verify dem``.

Each case function returns a list of rows ``dict(case, expected, obtained, error, tolerance,
passed)``; ``error`` is relative unless the row says ``abs`` in its case name. g = 9.81 m/s².

Sources: block on an inclined plane and Newmark's (1965) rigid sliding block (closed forms);
Housner (1963) rocking block, reference numbers from :mod:`murus.rocking`; tilting-table limits
atan(b/h) (toppling) and phi (sliding); minimum thickness of a semicircular arch under
self-weight t/R = 0.1075 (Milankovitch 1907, reported by Ochsendorf 2002 and Makris & Alexakis
2013; Heyman's approximation 0.106).
"""

from __future__ import annotations

import math

import numpy as np

from murus import G
from murus.dem import engine as E
from murus.dem import kernels as K
from murus.dem.materials import Joint
from murus.dem.model import Model

RHO = 2000.0


def _row(case, expected, obtained, tolerance, relative=True):
    err = abs(obtained - expected) / abs(expected) if relative else abs(obtained - expected)
    return {"case": case, "expected": float(expected), "obtained": float(obtained),
            "error": float(err), "tolerance": float(tolerance),
            "passed": bool(np.isfinite(err) and err <= tolerance)}


def _pair_fn(m, a, b):
    """Normal forces of the active sub-contacts between bodies a and b."""
    on = m.sid >= 0
    ba = m.sbody[m.pairs[:, 0]]
    bb = m.sbody[m.pairs[:, 1]]
    sel = ((ba == a) & (bb == b)) | ((ba == b) & (bb == a))
    f = m.sf[sel][on[sel]]
    return f[:, K.F_FN]


def _min_fn(a, b, n=2):
    """Probe: smallest normal force of the a-b interface (0 if fewer than n sub-contacts)."""
    def p(m):
        fn = _pair_fn(m, a, b)
        if fn.size < n:
            return 0.0
        return float(fn.min())
    return p


# ---------------------------------------------------------------------- builders
def block_on_base(width, height, joint, *, base="fixed", rounding=None, angle=0.0,
                  pivot=None):
    """A block (width x height [m]) resting on a wide base whose top is y = 0; with ``pivot``
    (+1 right, -1 left corner) and ``angle`` [rad] > 0 the block is tilted onto that corner
    (uplifted on the other side), touching the base."""
    m = Model(joint=joint, rounding=rounding)
    b0 = m.add_rectangle(max(6 * width, 2.0), 0.2, center=(0.0, -0.1), kinematic=base)
    if pivot is None:
        b1 = m.add_rectangle(width, height, center=(0.0, height / 2))
    else:
        v = np.array([[-width / 2, 0.0], [width / 2, 0.0], [width / 2, height],
                      [-width / 2, height]])
        corner = v[0 if pivot < 0 else 1]
        th = -angle if pivot > 0 else angle  # lift the opposite corner
        c, s = math.cos(th), math.sin(th)
        v = (v - corner) @ np.array([[c, s], [-s, c]]) + corner
        r = m.rounding if m.rounding is not None else 0.005 * min(width, height)
        # rounded corner: the lowest point of the rounding touches y = 0
        v[:, 1] -= r * (math.cos(angle) + math.sin(angle) - 1.0)
        b1 = m.add_polygon(v)
    return m, b0, b1


def stack(n, width=0.4, height=0.2, joint=None):
    m = Model(joint=joint or Joint(kn=1e9, ks=1e9, friction_deg=35))
    base = m.add_rectangle(2.0, 0.2, center=(0.0, -0.1), kinematic="fixed")
    blocks = [m.add_rectangle(width, height, center=(0.0, height / 2 + height * i))
              for i in range(n)]
    return m, base, blocks


def semicircular_arch(t_over_R, n=24, R=1.0, joint=None):
    """Semicircular arch of n voussoirs (centreline radius R, thickness t) on a fixed
    foundation; returns (model, foundation, voussoirs)."""
    t = t_over_R * R
    m = Model(joint=joint or Joint(kn=1e9, ks=1e9, friction_deg=45))
    f = m.add_rectangle(2 * R + 2 * t + 1.0, 0.2, center=(0.0, -0.1), kinematic="fixed")
    ri, ro = R - t / 2, R + t / 2
    vs = []
    for i in range(n):
        a0, a1 = math.pi * i / n, math.pi * (i + 1) / n
        v = [(ro * math.cos(a0), ro * math.sin(a0)), (ro * math.cos(a1), ro * math.sin(a1)),
             (ri * math.cos(a1), ri * math.sin(a1)), (ri * math.cos(a0), ri * math.sin(a0))]
        vs.append(m.add_polygon(v))
    return m, f, vs


# ---------------------------------------------------------------------- cases
def case_inclined_plane(quick=False):
    """Block on a 30 deg plane, friction 25 deg: a = g (sin 30 - cos 30 tan 25); at 20 deg it
    does not move. The plane is the level base under gravity tilted by beta (equivalent)."""
    rows = []
    for beta, phi in ((30.0, 25.0), (20.0, 25.0)):
        m, base, blk = block_on_base(0.5, 0.25, Joint(kn=1e9, ks=1e9, friction_deg=45.0))
        m.set_tilt(0.0, start_deg=beta)
        m.settle(tol=1e-7)
        m.update_joint(Joint(kn=1e9, ks=1e9, friction_deg=phi))
        res = m.run(0.6 if quick else 1.0, probes={"u": E.relative_probe(blk, base, "ux")},
                    sample_dt=0.005)
        t, u = res.t, res["u"]
        if beta == 30.0:
            sel = t > 0.1
            a = 2.0 * np.polyfit(t[sel], u[sel], 2)[0]
            b = math.radians(beta)
            exp = G * (math.sin(b) - math.cos(b) * math.tan(math.radians(phi)))
            rows.append(_row("inclined plane 30/25 deg: acceleration [m/s2]", exp, a, 0.01))
        else:
            rows.append(_row("inclined plane 20/25 deg: displacement over 1 s [m] (abs)", 0.0,
                             float(np.abs(u).max()), 1e-6, relative=False))
    return rows


def case_newmark(quick=False):
    """Newmark sliding block: friction 0.3, rectangular base pulse 0.5 g x 0.2 s: permanent
    slip 0.0654 m, stop at t = 0.3333 s (closed form)."""
    from murus.motion.synthetic import rectangular_pulse
    joint = Joint(kn=1e9, ks=1e9, friction_deg=math.degrees(math.atan(0.3)))
    m, base, blk = block_on_base(0.5, 0.25, joint, base="base")
    m.settle(tol=1e-7)
    m.set_base_motion(rectangular_pulse(0.5 * G, 0.2, dt=0.001, total=0.6))
    res = m.run(0.5, probes={"u": E.relative_probe(blk, base, "ux"),
                             "v": E.relative_probe(blk, base, "vx")}, every=5)
    t, u, v = res.t, res["u"], res["v"]
    # stop: first zero crossing of the relative velocity after the pulse
    k = np.nonzero((t > 0.21)[:-1] & (v[:-1] < 0) & (v[1:] >= 0))[0]
    ts = np.nan
    if k.size:
        i = k[0]
        ts = t[i] - v[i] * (t[i + 1] - t[i]) / (v[i + 1] - v[i])
    a1, a2, tp = 0.2 * G, 0.3 * G, 0.2
    vp = a1 * tp
    slip_exp = 0.5 * a1 * tp**2 + vp**2 / (2 * a2)
    return [_row("Newmark block: permanent slip [m]", slip_exp, abs(u[-1]), 0.02),
            _row("Newmark block: stop time [s]", tp + vp / a2, ts, 0.02)]


def case_rocking(quick=False):
    """0.25 x 1.0 block: onset of rocking at g tan(alpha) under a slow base ramp; released from
    alpha/2 it first hits its base at 0.349 s (murus.rocking); one-sine pulse vs murus.rocking."""
    from murus.rocking import RigidBlock, simulate
    from murus.rocking import sine_pulse as rsine
    b, h = 0.25, 1.0
    alpha = math.atan(b / h)
    rows = []
    joint = Joint(kn=1e10, ks=1e10, friction_deg=40.0)
    r = 2e-4
    # onset under a ramp a = A t
    A = 2.0
    m, base, blk = block_on_base(b, h, joint, base="base", rounding=r)
    m.settle(tol=1e-7)
    m.set_base_motion(velocity=lambda t: 0.5 * A * np.maximum(t, 0.0) ** 2)
    res = m.run(1.6, probes={"fmin": _min_fn(base, blk)}, every=10,
                stop=lambda mm: _min_fn(base, blk)(mm) <= 0.0)
    i = np.nonzero(res["fmin"] <= 0.0)[0]
    a_on = A * res.t[i[0]] if i.size else np.nan
    rows.append(_row("rocking onset: base acceleration [m/s2]", G * math.tan(alpha), a_on, 0.02))
    # free rocking from alpha/2
    ref = simulate(RigidBlock(b, h, density=RHO), theta0_over_alpha=0.5, duration=1).impacts[0, 0]
    m, base, blk = block_on_base(b, h, joint, rounding=r, angle=alpha / 2, pivot=+1)
    res = m.run(0.45, probes={"th": E.body_probe(blk, "angle")}, every=2)
    th = res["th"] - alpha / 2  # the body was built tilted by -alpha/2 (clockwise)
    k = np.nonzero((th[:-1] < 0) & (th[1:] >= 0))[0]
    t_imp = np.nan
    if k.size:
        j = k[0]
        t_imp = res.t[j] - th[j] * (res.t[j + 1] - res.t[j]) / (th[j + 1] - th[j])
    rows.append(_row("free rocking from alpha/2: first impact [s]", ref, t_imp, 0.02))
    # one-sine pulse: largest rotation before the first impact
    ap, fp = 2.0 * G * math.tan(alpha), 2.0
    rr = simulate(RigidBlock(b, h, density=RHO), rsine(ap, fp), duration=1.5)
    t_ref_imp = rr.impacts[0, 0] if rr.n_impacts else rr.t[-1]
    sel = rr.t <= t_ref_imp
    th_ref = float(np.abs(rr.theta[sel]).max())
    from murus.motion.synthetic import sine_pulse
    m, base, blk = block_on_base(b, h, joint, base="base", rounding=r)
    m.settle(tol=1e-7)
    m.set_base_motion(sine_pulse(ap, fp, dt=0.0005, duration=1.5))
    res = m.run(min(1.5, t_ref_imp + 0.05), probes={"th": E.relative_probe(blk, base, "rot")},
                every=5)
    sel = res.t <= t_ref_imp
    th_dem = float(np.abs(res["th"][sel]).max())
    rows.append(_row("one-sine pulse 2 g tan(alpha), 2 Hz: max rotation before the first "
                     "impact [rad]", th_ref, th_dem, 0.05))
    return rows


def case_tilting(quick=False):
    """Tilting table (gravity rotated slowly): a 0.25 x 1.0 block with 30 deg friction topples
    at atan(0.25) = 14.04 deg; a 1.0 x 0.5 block slides at 30 deg."""
    rows = []
    joint = Joint(kn=1e10, ks=1e10, friction_deg=30.0)
    rate = 2.0  # [deg/s]
    m, base, blk = block_on_base(0.25, 1.0, joint, rounding=2e-4)
    m.set_tilt(0.0, start_deg=12.0)
    m.settle(tol=1e-7)
    m.set_tilt(rate, start_deg=12.0)
    res = m.run(2.0, probes={"fmin": _min_fn(base, blk), "tilt": E.tilt_probe()}, every=10,
                stop=lambda mm: _min_fn(base, blk)(mm) <= 0.0)
    i = np.nonzero(res["fmin"] <= 0.0)[0]
    tilt = res["tilt"][i[0]] if i.size else np.nan
    rows.append(_row("tilting table 0.25 x 1.0: toppling tilt [deg] (abs)",
                     math.degrees(math.atan(0.25)), tilt, 0.1, relative=False))
    m, base, blk = block_on_base(1.0, 0.5, joint)
    m.set_tilt(0.0, start_deg=28.0)
    m.settle(tol=1e-7)
    m.set_tilt(rate, start_deg=28.0)
    res = m.run(2.0, probes={"u": E.relative_probe(blk, base, "ux"), "tilt": E.tilt_probe()},
                every=10, stop=E.stop_when(E.relative_probe(blk, base, "ux"), ">", 1e-3))
    i = np.nonzero(res["u"] > 1e-4)[0]
    tilt = res["tilt"][i[0]] if i.size else np.nan
    rows.append(_row("tilting table 1.0 x 0.5: sliding tilt [deg] (abs)", 30.0, tilt, 1.0,
                     relative=False))
    return rows


def case_stack(quick=False):
    """A stack of 5 blocks at rest: the normal forces of each joint sum to the weight above
    (1e-6 relative) and nothing drifts over 1e5 undamped steps."""
    n = 5
    m, base, blocks = stack(n)
    m.settle(tol=1e-12, max_steps=400_000)
    W = m.bmass[blocks[0]] * G
    worst = 0.0
    below = [base] + blocks[:-1]
    for k in range(n):
        fn = _pair_fn(m, below[k], blocks[k]).sum()
        worst = max(worst, abs(fn - (n - k) * W) / ((n - k) * W))
    rows = [_row("stack of 5: joint normal force / weight above - 1 (abs)", 0.0, worst, 1e-6,
                 relative=False)]
    x0 = m.bpos.copy()
    a0 = m.bang.copy()
    steps = 20_000 if quick else 100_000
    m.run(steps * m.dt * (1 - 1e-9) + 0.5 * m.dt, sample_dt=1.0)
    drift = max(np.abs(m.bpos - x0).max(), (np.abs(m.bang - a0) * m.brad).max())
    rows.append(_row(f"stack of 5: drift over {steps} undamped steps [m] (abs)", 0.0, drift,
                     1e-9, relative=False))
    return rows


def case_energy(quick=False):
    """Energy: (1) free rocking from alpha/2 on a frictionless base, no damping (elastic
    impacts, nothing dissipates): total energy constant to 0.1 % of the potential energy of the
    release (safety 0.1); (2) the same on a 45 deg joint (the elastic impacts bounce and the
    landing slips): balance including the slip dissipation closes to 0.1 %; (3) a sliding
    block under a one-sine pulse with 5 % mass-proportional damping: balance within 1 % of the
    work of the base."""
    from murus.motion.synthetic import sine_pulse
    b, h = 0.25, 1.0
    alpha = math.atan(b / h)
    R = 0.5 * math.hypot(b, h)
    rows = []
    dur = 0.8 if quick else 1.5
    for phi, safety in ((0.0, 0.1), (45.0, 0.2)):
        joint = Joint(kn=1e10, ks=1e10, friction_deg=phi)
        m, base, blk = block_on_base(b, h, joint, rounding=2e-4, angle=alpha / 2, pivot=+1)
        m.safety = safety
        res = m.run(dur, sample_dt=0.002)
        dE = m.bmass[blk] * G * R * (math.cos(alpha / 2) - math.cos(alpha))
        err = float(np.abs(res["energy.error"]).max() / dE)
        if phi == 0.0:
            rows.append(_row(f"free rocking, frictionless, no damping, {dur:g} s: max |energy "
                             "change| / release energy (abs)", 0.0, err, 1e-3, relative=False))
        else:
            rows.append(_row(f"free rocking, 45 deg joint, no damping, {dur:g} s: max |balance "
                             "error| / release energy (abs)", 0.0, err, 1e-3, relative=False))
    joint = Joint(kn=1e9, ks=1e9, friction_deg=math.degrees(math.atan(0.3)))
    m, base, blk = block_on_base(0.5, 0.25, joint, base="base")
    m.settle(tol=1e-7)
    m.set_base_motion(sine_pulse(0.6 * G, 2.0, dt=0.001, duration=1.0))
    res = m.run(1.0, xi=0.05, freq=5.0, sample_dt=0.002)
    win = np.abs(res["energy.base_work"]).max()
    rows.append(_row("sliding block, pulse + 5 % mass damping: max |balance error| / base work "
                     "(abs)", 0.0, float(np.abs(res["energy.error"]).max() / win), 0.01,
                     relative=False))
    return rows


def case_arch(quick=False):
    """Semicircular arch of 24 voussoirs under self-weight (friction 45 deg, kn = 1e10 Pa/m):
    stands at t/R = 1.05 x 0.1075 and collapses at 0.95 x 0.1075 (Milankovitch's minimum
    thickness of a continuous arch, Ochsendorf 2002). The 5 % bracket covers the discretisation:
    24 trapezoidal voussoirs (chords lose a little of the extrados) and hinges at the rounded
    corners; the engine's own limit lies between 1.00 and 1.02 x 0.1075."""
    rows = []
    tmin = 0.1075
    for f, stands in ((1.05, True), (0.95, False)):
        m, fnd, vs = semicircular_arch(f * tmin, joint=Joint(kn=1e10, ks=1e10,
                                                             friction_deg=45.0))
        crown = vs[len(vs) // 2]
        m.settle(tol=1e-6, max_steps=30_000, reset=False)
        m.run(0.5 if quick else 1.0, sample_dt=0.05,
              stop=E.stop_when(E.body_probe(crown, "uy"), "<", -0.05))
        d = -m.body_displacement()[crown, 1]
        rows.append({"case": f"semicircular arch t/R = {f:.2f} x 0.1075: "
                             f"{'stands' if stands else 'collapses'} (crown drop [m])",
                     "expected": 0.0 if stands else 0.05, "obtained": float(d),
                     "error": float(d if stands else max(0.0, 0.05 - d)),
                     "tolerance": 1e-3 if stands else 0.0,
                     "passed": bool(d < 1e-3) if stands else bool(d >= 0.05)})
    return rows


def case_rolling(quick=False):
    """Rolling resistance: a disc on a tilting table (friction 45 deg, mu_r = 0.2) starts to roll
    when tan(beta) = mu_r, i.e. at 11.31 deg (elastic-plastic rolling moment mu_r r Fn)."""
    m = Model(joint=Joint(kn=1e9, ks=1e9, friction_deg=45.0, rolling=0.2))
    base = m.add_rectangle(2.0, 0.2, center=(0.0, -0.1), kinematic="fixed")
    d = m.add_disc((0.0, 0.1), 0.1)
    m.set_tilt(0.0, start_deg=10.0)
    m.settle(tol=1e-7)
    m.set_tilt(1.0, start_deg=10.0)
    pr = E.relative_probe(d, base, "rot")
    res = m.run(2.5, probes={"rot": pr, "tilt": E.tilt_probe()}, every=10,
                stop=E.stop_when(pr, "abs>", 1e-3))
    i = np.nonzero(np.abs(res["rot"]) > 1e-4)[0]
    tilt = res["tilt"][i[0]] if i.size else np.nan
    return [_row("disc with rolling resistance 0.2: rolling tilt [deg] (abs)",
                 math.degrees(math.atan(0.2)), tilt, 0.2, relative=False)]


CASES = {
    "inclined_plane": case_inclined_plane,
    "newmark": case_newmark,
    "rocking": case_rocking,
    "tilting": case_tilting,
    "stack": case_stack,
    "energy": case_energy,
    "arch": case_arch,
    "rolling": case_rolling,
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
    """
    rows = []
    for fn in CASES.values():
        rows.extend(fn(quick))
    return rows

"""The interface's corner rule (``corner_share``) against references: two checks.

1. A block rocking freely on the interface's springs against the Winkler rocking model.

The wall-backfill interface of the continuum backfill (:mod:`murus.continuum.interface`) lumps
the joint's normal stiffness ``kn`` [Pa/m] at the gridpoints of the zones' surface (each over its
tributary length) and at the block corners (the part of the face the touching gridpoints leave:
the coverage rule). With the zones held still it is a Winkler bed of modulus ``kn`` sampled at
the gridpoints, so a rigid block rocking freely on it should rock as the same block on the
exact Winkler integral, :func:`murus.rocking.winkler.simulate_winkler` (``k_w = kn``, no
damping, the ``"corner"`` kinematics). The check compares the mean half-period over five
half-cycles and the amplitude kept, for the two corner rules (``corner_share``: ``"follow"``,
the corner's share follows the coverage rule up and down under load; ``"shrink"``, down
only), at gridpoint spacings b / 4, b / 8 and b / 16.

The block: 0.25 m x 1.0 m (slenderness 4), 0.8 m thick, 2000 kg/m³, corners rounded by 0.1 mm
(the Winkler body's width is the flat face, 0.2498 m, at the same mass); ``kn = 1e8`` Pa/m,
``ks = kn``, friction 85° (the Winkler model does not slide), no cohesion or tension; released
at rest from ``theta0`` (a fraction of its slenderness angle alpha) at the Winkler model's
equilibrium penetration. The gridpoints are offset from the block's corners (0.013 m). The
block is integrated here (leapfrog, ``dt = 0.1 / omega_v``, ``omega_v`` the vertical frequency
on full contact; half of it changes the half-periods by under 0.01 %) with the interface's
forces (:meth:`murus.continuum.interface.Interface.forces`) and gravity.

2. The rocking stack of ``tests/continuum/test_continuum_coupled.py`` (two 0.4 m x 0.25 m
blocks, their joint 100 times stiffer than the interface's kn = 1e9 Pa/m, on a 2 m x 1 m
elastic layer, E = 20 MPa, settled, then set rocking at 0.5 rad/s, no damping, 0.2 s) on
layers of 8 x 4, 16 x 8 and 32 x 16 zones with either rule: the upper block's largest rise
and the energy the interface's contacts booked as breaking (positive: released; negative:
created by a change of a pressed contact's stiffness). As the mesh is refined a corner's share
of the face matters less and the two rules must agree; the coarse meshes show which of them
is right there.

Run: ``python validation/corner_rule.py`` (about 3 minutes); the results are cached in
``validation/results/corner_rule.json`` with the key of the source they came from.
"""

from __future__ import annotations

import json
import math
import statistics
from pathlib import Path
from types import SimpleNamespace

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
OUT = HERE / "results" / "corner_rule.json"
#: the sources the numbers come from (runcache.source_key)
ENGINE = ("continuum", "dem", "rocking")

KN, T, RHO, G = 1.0e8, 0.8, 2000.0, 9.81
B, H, R = 0.25, 1.0, 1.0e-4
BF = B - 2 * R  # the flat face: the Winkler body's width
OFFSET = 0.013  # of the gridpoints from the block's corner [m]
FRACS = (0.02, 0.04)  # theta0 / alpha
SPACINGS = (4, 8, 16)  # gridpoints to the face
RULES = ("follow", "shrink")
DURATION = 3.0
HALF_CYCLES = 5


def _body():
    from murus.rocking.body import RigidBlock

    return RigidBlock(width=BF, height=H, thickness=T, density=RHO * B / BF)


def _base():
    from murus.rocking.winkler import WinklerBase

    return WinklerBase(stiffness=KN, width_out_of_plane=T)


def winkler(theta0: float, duration: float = DURATION, out_dt: float = 1e-4):
    """The Winkler model's rotation history (t, theta) [s, rad], clockwise positive."""
    from murus.rocking.winkler import simulate_winkler

    r = simulate_winkler(_body(), _base(), None, duration=duration, theta0=theta0,
                         out_dt=out_dt, rtol=1e-9)
    return np.asarray(r.t), np.asarray(r.theta)


def interface(rule: str, per_face: int, theta0: float, duration: float = DURATION,
              dt_factor: float = 0.1):
    """The block on the interface's springs: (t, theta, energies) with theta clockwise
    positive as the Winkler model's; ``energies`` the interface's (slip, break, stored) [J]
    and the block's total energy change (kinetic, gravity and the springs' stored energy)."""
    from murus.continuum import interface as ifc_mod
    from murus.dem import Joint, Model
    from murus.rocking.winkler import initial_settlement

    h = BF / per_face
    x0 = -B / 2 - 2 * h - OFFSET
    n = int(math.ceil((B + 4 * h + 2 * OFFSET) / h)) + 1
    grid = SimpleNamespace(gxy=np.column_stack([x0 + h * np.arange(n), np.zeros(n)]),
                           gvel=np.zeros((n, 2)))
    edges = np.array([[i + 1, i] for i in range(n - 1)], np.int64)
    m = Model(thickness=T, rounding=R, margin=0.01,
              joint=Joint(kn=KN, ks=KN, friction_deg=85.0))
    m.add_rectangle(B, H, center=(0.0, H / 2), density=RHO)
    ifc = ifc_mod.Interface(grid, edges, m, corner_share=rule, bond_initial=False)
    mass, inert = float(m.bmass[0]), float(m.binert[0])
    # the Winkler model's start: corner O (xi = +b/2) fixed, v from equilibrium at theta0;
    # theta clockwise positive lowers the right corner, the blocks' angle is anticlockwise
    v0 = initial_settlement(_body(), _base(), theta0)
    x_c = BF / 2 * (1 - math.cos(theta0))
    m.bpos[0] = (x_c + math.sin(theta0) * H / 2, v0 + math.cos(theta0) * H / 2)
    m.bang[0] = -theta0
    dt = dt_factor / math.sqrt(KN * T * BF / mass)
    nsteps = int(duration / dt)
    theta = np.empty(nsteps + 1)
    theta[0] = theta0
    vel, om = np.zeros(2), 0.0

    def energy():
        return (0.5 * mass * float(vel @ vel) + 0.5 * inert * om * om
                + mass * G * float(m.bpos[0][1]) + ifc_mod.stored_energy(ifc.nodes, ifc.corners))

    f = ifc.forces(0.0)[1][0].copy()
    e0 = energy()
    for k in range(1, nsteps + 1):
        h_dt = dt if k > 1 else 0.5 * dt  # leapfrog: velocities at the half steps
        vel += h_dt * np.array([f[0] / mass, f[1] / mass - G])
        om += h_dt * f[2] / inert
        m.bvel[0] = vel
        m.bomg[0] = om
        m.bpos[0] += dt * vel
        m.bang[0] += dt * om
        f = ifc.forces(dt)[1][0].copy()
        theta[k] = -m.bang[0]
    en = dict(ifc.energy)
    en["block_change"] = energy() - e0
    return np.arange(nsteps + 1) * dt, theta, en


STACK_MESHES = ((8, 4), (16, 8), (32, 16))


def stack(nx: int, ny: int, rule: str, omega: float = 0.5, duration: float = 0.2) -> dict:
    """The rocking stack on a layer of ``nx`` x ``ny`` zones with the corner rule ``rule``:
    its settling's steps, the upper block's largest rise [m], the interface's breaking
    energy [J] and the energy given [J]."""
    from murus.continuum import ContinuumModel, Elastic
    from murus.continuum.coupled import CoupledModel
    from murus.continuum.interface import Interface
    from murus.dem import Joint, Model
    from murus.dem.engine import body_probe

    # the layer as tests/continuum/continuum_inputs.rect_mesh makes it (the same numbering)
    X, Y = np.meshgrid(np.linspace(0.0, 2.0, nx + 1), np.linspace(0.0, 1.0, ny + 1))
    xy = np.column_stack([X.ravel(), Y.ravel()])
    i, j = np.meshgrid(np.arange(nx), np.arange(ny))
    a = (j * (nx + 1) + i).ravel()
    zones = np.column_stack([a, a + 1, a + nx + 2, a + nx + 1]).astype(np.int64)
    zm = ContinuumModel(xy, zones, Elastic(density=RHO, E=2e7, nu=0.3), gravity=G)
    left = np.flatnonzero(np.isclose(xy[:, 0], 0.0))
    right = np.flatnonzero(np.isclose(xy[:, 0], 2.0))
    bottom = np.flatnonzero(np.isclose(xy[:, 1], 0.0))
    top = np.flatnonzero(np.isclose(xy[:, 1], 1.0))
    zm.set_base(left, x=True, y=False)
    zm.set_base(right, x=True, y=False)
    zm.set_base(bottom)
    kn = 1e9
    dm = Model(thickness=1.0, gravity=G, rounding=1e-3,
               joint=Joint(kn=100 * kn, ks=100 * kn, friction_deg=35.0))
    for k in range(2):
        dm.add_rectangle(0.4, 0.25, center=(1.0, 1.0 + 0.125 + 0.25 * k), density=RHO)
    edges = [e for e in zm.boundary_edges() if np.isin(e, top).all()]
    iface = Interface(zm, np.array(edges), dm, Joint(kn=kn, ks=kn, friction_deg=35.0),
                      corner_share=rule)
    cm = CoupledModel(dm, zm, iface)
    st = cm.settle(tol=1e-7, max_steps=1_000_000)
    dm.bomg[:] = omega
    given = 0.5 * float((dm.binert * dm.bomg ** 2).sum())
    dm.reset_reference()
    y0 = float(dm.bpos[1, 1])
    brk0 = cm.energy()["interface_breaking"]
    res = cm.run(duration, xi=0.0, freq=5.0, every=10, probes={"y": body_probe(1, "y")})
    return {"nx": nx, "ny": ny, "rule": rule, "settle_steps": int(st.steps),
            "settled": bool(st.converged), "rise_m": float(np.nanmax(res["y"])) - y0,
            "breaking_J": cm.energy()["interface_breaking"] - brk0, "given_J": given}


def zero_crossings(t, x) -> np.ndarray:
    s = np.sign(x)
    i = np.nonzero(s[1:] * s[:-1] < 0)[0]
    return t[i] - x[i] * (t[i + 1] - t[i]) / (x[i + 1] - x[i])


def half_period(t, x, n: int = HALF_CYCLES) -> float:
    """Mean time between the first n + 1 zero crossings [s]."""
    z = zero_crossings(t, x)
    if len(z) < n + 1:
        return math.nan
    return float((z[n] - z[0]) / n)


def amplitude_kept(t, x, n: int = HALF_CYCLES) -> float:
    """The largest |theta| in the n-th half-cycle over that in the first (the extrema between
    zero crossings)."""
    z = zero_crossings(t, x)
    if len(z) < n + 1:
        return math.nan

    def peak(a, b):
        sel = (t > a) & (t < b)
        return float(np.max(np.abs(x[sel])))

    return peak(z[n - 1], z[n]) / peak(z[0], z[1])


#: the case drawn in the figure: (gridpoints to the face, theta0 / alpha), its first 1.5 s
FIGURE_CASE, FIGURE_SPAN, FIGURE_STEP = (16, 0.04), 1.5, 2e-3


def compute() -> dict:
    import runcache

    out = {"_engine_source": runcache.source_key(*ENGINE), "cases": []}
    alpha = _body().alpha
    grid = np.arange(0.0, FIGURE_SPAN + 0.5 * FIGURE_STEP, FIGURE_STEP)
    fig = {"per_face": FIGURE_CASE[0], "theta0_over_alpha": FIGURE_CASE[1],
           "t": np.round(grid, 4).tolist()}

    def trace(t, x, th0):  # theta / theta0 on the figure's grid
        return np.round(np.interp(grid, t, x) / th0, 5).tolist()

    for frac in FRACS:
        th0 = frac * alpha
        tw, xw = winkler(th0)
        ref = {"theta0_over_alpha": frac, "winkler_half_period": half_period(tw, xw),
               "winkler_amplitude_kept": amplitude_kept(tw, xw), "runs": []}
        if frac == FIGURE_CASE[1]:
            fig["winkler"] = trace(tw, xw, th0)
        for per in SPACINGS:
            for rule in RULES:
                t, x, en = interface(rule, per, th0)
                ref["runs"].append({"per_face": per, "rule": rule,
                                    "half_period": half_period(t, x),
                                    "amplitude_kept": amplitude_kept(t, x),
                                    "slip_J": en["slip"], "break_J": en["break"],
                                    "block_change_J": en["block_change"]})
                if (per, frac) == FIGURE_CASE:
                    fig[rule] = trace(t, x, th0)
        out["cases"].append(ref)
    out["figure"] = fig
    out["stack"] = [stack(nx, ny, rule) for nx, ny in STACK_MESHES for rule in RULES]
    OUT.parent.mkdir(parents=True, exist_ok=True)
    tmp = OUT.with_suffix(".json.tmp")
    tmp.write_text(json.dumps(out, indent=1))
    tmp.replace(OUT)
    return out


def cached() -> dict | None:
    """The cached results when made by this source, else None."""
    import runcache

    try:
        rec = json.loads(OUT.read_text())
    except (OSError, ValueError):
        return None
    return rec if rec.get("_engine_source") == runcache.source_key(*ENGINE) else None


def figure(rec: dict, path: Path) -> None:
    """theta / theta0 against time: the Winkler model and the interface with either rule
    (``rec``: :func:`compute`'s)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    h = rec["figure"]
    fig, ax = plt.subplots(figsize=(7.5, 3.2))
    ax.plot(h["t"], h["winkler"], "k-", lw=2.0, label="Winkler model (exact integral)")
    for rule, st in (("follow", "C3--"), ("shrink", "C0-")):
        ax.plot(h["t"], h[rule], st, lw=1.0, label=f"interface, '{rule}', b / {h['per_face']}")
    ax.set_xlabel("t [s]")
    ax.set_ylabel(r"$\theta / \theta_0$")
    ax.set_title(r"Free rocking on the interface's springs, $\theta_0$ = "
                 f"{h['theta0_over_alpha']:g} " + r"$\alpha$")
    ax.legend(fontsize=8, loc="lower left")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def text(rec: dict | None, fig_rel: str | None = None) -> list[str]:
    """The Markdown paragraph and table of the check (``rec``: :func:`compute`'s)."""
    if rec is None:
        return ["- The free-rocking check against the Winkler model "
                "(`python validation/corner_rule.py`) is not computed for this source.",
                ""]
    out = ["Free rocking of a block on the interface's springs (zones held: a Winkler bed "
           "sampled at the gridpoints) against murus's Winkler rocking model, which integrates "
           "the bed exactly (`validation/corner_rule.py`, module doc: a 0.25 x 1.0 m "
           "block, kn = 1e8 Pa/m, no damping). Mean half-period over five half-cycles, against "
           "the Winkler model's, and the amplitude of the fifth half-cycle over the first's "
           "(the Winkler model: 1, it conserves energy); b the face, gridpoints every b / n:", "",
           "| theta0 / alpha | gridpoints to the face | half-period 'follow' | 'shrink' "
           "| amplitude kept 'follow' | 'shrink' | interface's breaking 'follow' / 'shrink' "
           "[J] |", "|---|---|---|---|---|---|---|"]
    errs = {r: [] for r in RULES}
    for case in rec["cases"]:
        hw = case["winkler_half_period"]
        by = {(r["per_face"], r["rule"]): r for r in case["runs"]}
        for per in sorted({r["per_face"] for r in case["runs"]}):
            f, s = by[(per, "follow")], by[(per, "shrink")]
            for r in (f, s):
                errs[r["rule"]].append(100 * (r["half_period"] / hw - 1))
            out.append(f"| {case['theta0_over_alpha']:g} | {per} | "
                       f"{100 * (f['half_period'] / hw - 1):+.1f} % | "
                       f"{100 * (s['half_period'] / hw - 1):+.1f} % | "
                       f"{f['amplitude_kept']:.3f} | {s['amplitude_kept']:.3f} | "
                       f"{f['break_J']:+.3f} / {s['break_J']:+.3f} |")
    span = {r: (min(v), max(v)) for r, v in errs.items()}
    out += ["", f"- Half-period against the Winkler model: 'follow' {span['follow'][0]:+.1f} "
            f"to {span['follow'][1]:+.1f} % (mean {statistics.mean(errs['follow']):+.1f} %), "
            f"'shrink' {span['shrink'][0]:+.1f} to {span['shrink'][1]:+.1f} % (mean "
            f"{statistics.mean(errs['shrink']):+.1f} %). The likely mechanism: with 'follow' a "
            "pivot corner whose "
            "neighbouring gridpoints lift off takes the face they leave at its own, largest, "
            "penetration, where the Winkler pressure falls to zero over the contact length: a "
            "stiffer rocking, a shorter period; 'shrink' keeps the share it had. The "
            "breaking term is positive (energy released, never gained) for both rules in free "
            "rocking on a flat bed: the pump of the mock-up (a corner pressed sideways into "
            "the backfill by a stone that rocks) needs the corner's depth and its neighbour's "
            "contact to cycle out of phase, which a free block on its base does not do.", ""]
    if fig_rel:
        out += [f"![Free rocking on the interface against the Winkler model]({fig_rel})", ""]
    out += _stack_text(rec.get("stack"))
    return out


def _stack_text(rows) -> list[str]:
    if not rows:
        return []
    by = {(r["nx"], r["rule"]): r for r in rows}
    fine = max(r["nx"] for r in rows)
    out = ["A rocking stack on layers of three meshes (the stack of "
           "`test_a_subcycled_impact_on_a_stiff_interface_gains_no_energy`: two 0.4 x 0.25 m "
           "blocks on a 2 x 1 m elastic layer, set rocking at 0.5 rad/s, no damping, 0.2 s; "
           "`validation/corner_rule.py`, module doc): the upper block's largest rise and the "
           "energy the interface's contacts booked as breaking (positive: released; negative: "
           "created when a pressed contact's stiffness changed), against the energy given:", "",
           "| zones | rise 'follow' [m] | rise 'shrink' [m] | breaking 'follow' [J] "
           "| breaking 'shrink' [J] | energy given [J] |", "|---|---|---|---|---|---|"]
    for nx, ny in sorted({(r["nx"], r["ny"]) for r in rows}):
        f, s = by[(nx, "follow")], by[(nx, "shrink")]
        out.append(f"| {nx} x {ny} | {f['rise_m']:.3g} | {s['rise_m']:.3g} | "
                   f"{f['breaking_J']:+.3g} | {s['breaking_J']:+.3g} | {f['given_J']:.3g} |")
    ff, sf = by[(fine, "follow")], by[(fine, "shrink")]
    ratio = {r: [by[(nx, r)]["rise_m"] / by[(fine, r)]["rise_m"]
                 for nx in sorted({x["nx"] for x in rows}) if nx != fine] for r in RULES}
    out += ["", f"- On the finest mesh the rules agree (rise {ff['rise_m']:.3g} and "
            f"{sf['rise_m']:.3g} m, {100 * (ff['rise_m'] / sf['rise_m'] - 1):+.0f} %). On "
            "the coarser ones 'shrink' rises "
            + " and ".join(f"{x:.2g}" for x in ratio["shrink"])
            + " times the fine mesh's, 'follow' "
            + " and ".join(f"{x:.2g}" for x in ratio["follow"])
            + " times, driven by the energy its contacts create (the negative breaking, of the "
            "order of the energy given or more): the larger rocking of the coarse stack with "
            "'follow' was this pump, not a price of 'shrink'.", ""]
    return out


def main() -> None:
    rec = compute()
    print("\n".join(text(rec)))
    print(f"(cached in {OUT.relative_to(ROOT)})")


if __name__ == "__main__":
    main()

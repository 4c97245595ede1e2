"""Blocks and zones in one time loop (issue 17, item 5): a rigid block resting on an elastic
layer through the zone-block interface. Closed forms: the interface carries the block's weight;
the layer between smooth rigid walls is oedometric, so the block settles by
``rho g H^2 / (2 M) + p H / M + p / kn`` (self-weight, the block's pressure p = weight / width
of the layer, the interface spring), ``M = E (1 - nu) / ((1 + nu)(1 - 2 nu))``. The block
overhangs the layer by 0.1 m on each side, so that its flat face (not its rounded corners)
covers every top gridpoint. The model and the settlement row are those of ``murus verify
continuum`` (:func:`murus.continuum.verify.block_on_layer`)."""

from __future__ import annotations

import numpy as np
import pytest
from continuum_inputs import rect_mesh, sides

from murus.continuum import ContinuumModel, Elastic
from murus.continuum import kernels as ZK
from murus.continuum import verify as V
from murus.continuum.coupled import CoupledError, CoupledModel
from murus.continuum.interface import Interface
from murus.dem import Joint, Model
from murus.dem.engine import body_probe

G_ACC, RHO, E, NU = 9.81, 2000.0, 1e7, 0.25
W, H, HB, KN, OVER = 2.0, 1.0, 0.5, 1e9, 0.1


def _block_on_layer():
    return V.block_on_layer(4, 4)


def test_block_on_an_elastic_layer_settles_to_the_closed_form():
    row, cm = V.block_settlement(quick=True)
    assert row["passed"], row
    weight = RHO * (W + 2 * OVER) * HB * G_ACC
    assert cm.iface.normal_force() == pytest.approx(weight, rel=0.005)
    M = E * (1 - NU) / ((1 + NU) * (1 - 2 * NU))
    p = weight / W
    want = RHO * G_ACC * H * H / (2 * M) + p * H / M + p / KN
    assert row["expected"] == pytest.approx(want, rel=1e-12)
    assert row["obtained"] == pytest.approx(want, rel=0.02)


def test_one_time_step_for_all():
    cm, dm, zm, iface = _block_on_layer()
    assert cm.dt <= zm.stable_dt() and cm.dt <= iface.critical_dt() * dm.safety
    with pytest.raises(CoupledError):
        cm.set_dt(2 * cm.stable_dt())


def test_a_settled_block_stays_at_rest_in_a_run():
    """The dynamic loop from a settled state with no base motion: nothing moves (the static
    solution is an equilibrium of the dynamic equations), and the time advances."""
    cm, dm, zm, iface = _block_on_layer()
    assert cm.settle(tol=1e-7, max_steps=400_000).converged
    y1 = float(dm.bpos[0, 1])
    res = cm.run(0.05, xi=0.05, freq=5.0, every=50,
                 probes={"y": body_probe(0, "y"), "N": lambda m: iface.normal_force()})
    weight = RHO * (W + 2 * OVER) * HB * G_ACC
    assert res.status == "completed"
    assert res.t[-1] == pytest.approx(0.05, abs=cm.dt)
    # the layer's settlement is ~1.7 mm: rest within a thousandth of it
    assert np.abs(res["y"] - y1).max() < 2e-6
    assert np.allclose(res["N"], weight, rtol=0.005)


def _block_on(nx, width, material, block, *, driven=False, friction=25.0, settle=True):
    """A ``block = (w, h)`` [m] centred at x = 1 m on a layer of ``nx`` x 4 zones, ``width`` x
    H, of ``material``: sides on rollers and base fixed, or (``driven``) sides and base moved
    by the base motion; settled under gravity (``settle``)."""
    xy, zones = rect_mesh(nx, 4, width, H)
    zm = ContinuumModel(xy, zones, material, gravity=G_ACC)
    left, right, bottom, top = (np.flatnonzero(s) for s in sides(xy))
    hold = zm.set_base if driven else zm.fix
    hold(left, x=True, y=False)
    hold(right, x=True, y=False)
    hold(bottom)
    joint = Joint(kn=KN, ks=KN, friction_deg=friction)
    dm = Model(thickness=1.0, gravity=G_ACC, joint=joint, rounding=1e-3)
    dm.add_rectangle(block[0], block[1], center=(1.0, H + 0.5 * block[1]), density=RHO)
    edges = [e for e in zm.boundary_edges() if np.isin(e, top).all()]
    iface = Interface(zm, np.array(edges), dm, joint)
    cm = CoupledModel(dm, zm, iface)
    if settle:
        assert cm.settle(tol=1e-6).converged
    return cm, dm, zm, iface, top


def _block_pushed_over_a_layer():
    """A 1.2 m x 0.2 m block on a 4 m wide elastic layer of 16 x 4 zones, pushed by a
    horizontal force of 0.6 times its weight (interface friction 25 deg): it slides over
    several gridpoints of the layer's surface."""
    out = _block_on(16, 4.0, Elastic(density=RHO, E=2e7, nu=0.3), (1.2, 0.2))
    out[1].bext[0, 0] = 0.6 * out[1].bmass[0] * G_ACC
    return out


def test_energy_balance_of_a_block_sliding_over_gridpoints():
    """Conservation of energy over blocks, zones and interface (CoupledModel.energy): the
    work of the push goes into the block's and the layer's kinetic and elastic energy and the
    interface's slip. The block slides 0.2 m, over the layer's gridpoints at x = 1.75 m:
    before the interface carried a contact's shear stress over a change of its tributary
    length, a kept force on a shrinking stiffness counted 6 kJ of slip here (9 times the
    push's work); now the balance closes within 1 % of the push's work."""
    cm, dm, zm, iface, top = _block_pushed_over_a_layer()
    res = cm.run(0.6, every=200, probes={"ux": body_probe(0, "ux")})
    assert res.status == "completed"
    e = cm.energy()
    assert res["ux"][-1] > 0.15  # it passed the gridpoint at 1.75 m with its front edge
    assert e["interface_slip"] > 0.5 * e["external_work"]
    assert abs(e["error"]) < 0.01 * e["external_work"]


def test_probes_of_gridpoints_and_zones_and_a_stop_condition():
    """The blocks' engine samples the zones' gridpoints and zones and stops on a block's
    displacement; a gridpoint probe reads the zones' own displacement."""
    from murus.dem.engine import Probe, stop_when

    cm, dm, zm, iface, top = _block_pushed_over_a_layer()
    g = int(top[len(top) // 2])
    res = cm.run(1.0, every=20, probes={"ux": body_probe(0, "ux"),
                                        "gp_uy": Probe(("gp", g, "uy")),
                                        "z_syy": Probe(("zone", 0, "syy"))},
                 stop=stop_when(body_probe(0, "ux"), ">", 0.02))
    assert res.status == "stopped"
    assert 0.02 < res["ux"][-1] < 0.03
    assert res["gp_uy"][-1] == zm.gdisp[g, 1]
    # the bottom-left zone carries the layer's and the block's weight: syy < 0
    assert res["z_syy"][-1] < 0.0
    assert zm.time == pytest.approx(dm.time)


def _block_on_a_shaken_mohr_coulomb_layer():
    from murus.continuum import MohrCoulomb

    mat = MohrCoulomb(density=RHO, E=2e7, nu=0.3, friction_deg=30.0, cohesion=2e3,
                      dilation_deg=0.0)
    cm, dm, zm, _, _ = _block_on(8, W, mat, (0.8, 0.5), driven=True)
    dm.set_base_motion(velocity=lambda t: 0.3 * np.sin(2 * np.pi * 4.0 * t))
    dm.bext[0, 0] = 0.3 * dm.bmass[0] * G_ACC
    return cm, dm, zm


def test_energy_balance_of_a_block_pushed_and_shaken_on_a_mohr_coulomb_layer():
    """Conservation of energy with plasticity and contacts: a 0.8 m x 0.5 m block on a
    Mohr-Coulomb layer (8 x 4 zones, c = 2 kPa, phi = 30 deg), pushed by 0.3 times its weight
    while the base shakes the layer at 4 Hz (0.3 m/s, its sides and bottom driven) with 5 %
    mass-proportional damping: the zones yield, the block slides 0.15 m over the layer's
    gridpoints, contacts open and form. The balance (kinetic, gravity, strain, plastic work,
    the interface's springs, slip and contact changes, damping, base and push) closes within
    1 % of the work put in (base + push). Before the interface's coverage rule the corners'
    stiffness switched on and off and this case gained about 600 J (error 4 %)."""
    cm, dm, zm = _block_on_a_shaken_mohr_coulomb_layer()
    res = cm.run(1.0, xi=0.05, freq=4.0, every=500, probes={"ux": body_probe(0, "ux")})
    assert res.status == "completed"
    e = cm.energy()
    put_in = e["zones_base_work"] + e["external_work"]
    assert e["zones_plastic"] > 0.05 * put_in and e["interface_slip"] > 0.5 * put_in
    assert res["ux"][-1] > 0.1
    assert abs(e["error"]) < 0.01 * put_in


def test_a_checkpoint_resumes_bit_for_bit(tmp_path):
    """Save in the middle of a run with plasticity, slip and contacts, restore on the model
    built again, and the rest of the run is the uninterrupted one, bit for bit (blocks,
    gridpoints, stresses, interface forces, energy)."""
    cm, dm, zm = _block_on_a_shaken_mohr_coulomb_layer()
    cm.run(0.2, xi=0.05, freq=4.0, every=100)
    ck = tmp_path / "ck.npz"
    cm.save(ck)
    cm.run(0.2, xi=0.05, freq=4.0, every=100)
    cm2, dm2, zm2 = _block_on_a_shaken_mohr_coulomb_layer()
    cm2.restore(ck)
    assert dm2.time == pytest.approx(0.2, abs=dm.dt)
    cm2.run(0.2, xi=0.05, freq=4.0, every=100)
    assert np.array_equal(dm2.bpos, dm.bpos) and np.array_equal(dm2.bvel, dm.bvel)
    assert np.array_equal(zm2.gxy, zm.gxy) and np.array_equal(zm2.zsig, zm.zsig)
    assert np.array_equal(cm2.iface.nodes.sf, cm.iface.nodes.sf)
    assert cm2.energy()["error"] == cm.energy()["error"]
    with pytest.raises(CoupledError):
        dm.save(tmp_path / "dem_only.npz")  # the blocks alone would lose the zones


def test_a_checkpoint_of_another_model_is_refused(tmp_path):
    cm, dm, zm, iface = _block_on_layer()
    ck = tmp_path / "ck.npz"
    cm.save(ck)
    cm2, dm2, zm2 = _block_on_a_shaken_mohr_coulomb_layer()
    with pytest.raises(CoupledError, match="another model"):
        cm2.restore(ck)


def test_elastic_first_settling_runs_an_elastic_then_a_plastic_stage():
    """Gravity initialisation in two stages (``settle(elastic_first=True)``): the zones are
    elastic in the first stage and plastic in the second (read at every check of the
    settling through its hook), plasticity stays on for what follows, and the settled
    interface carries the block's weight (within 0.5 %)."""
    from murus.continuum import MohrCoulomb

    mat = MohrCoulomb(density=RHO, E=2e7, nu=0.3, friction_deg=30.0, cohesion=5e3)
    cm, dm, zm, iface, _ = _block_on(8, W, mat, (0.8, 0.2), settle=False)
    seen = []
    res = cm.settle(elastic_first=True, tol=1e-6,
                    external=lambda m: seen.append(float(zm.P[ZK.P_PLASTIC])))
    assert res.converged
    assert seen[0] == 0.0 and seen[-1] == 1.0 and seen == sorted(seen)
    assert zm.P[ZK.P_PLASTIC] == 1.0
    weight = float(dm.bmass[0]) * G_ACC
    assert iface.normal_force() == pytest.approx(weight, rel=0.005)


# ---------------------------------------------------------------------- subcycling
def _stack_on(mat, width, friction_deg, tol, share="follow"):
    """Two ``width`` x 0.25 m blocks stacked on a 2 m x 1 m layer of ``mat`` (8 x 4 zones,
    rollers on its sides, fixed base), their joint 100 times stiffer than the interface
    (``friction_deg``), settled to ``tol``."""
    xy, zones = rect_mesh(8, 4, W, H)
    zm = ContinuumModel(xy, zones, mat, gravity=G_ACC)
    left, right, bottom, top = (np.flatnonzero(s) for s in sides(xy))
    zm.set_base(left, x=True, y=False)
    zm.set_base(right, x=True, y=False)
    zm.set_base(bottom)
    stiff = Joint(kn=100 * KN, ks=100 * KN, friction_deg=35.0)
    dm = Model(thickness=1.0, gravity=G_ACC, joint=stiff, rounding=1e-3)
    for k in range(2):
        dm.add_rectangle(width, 0.25, center=(1.0, H + 0.125 + 0.25 * k), density=RHO)
    edges = [e for e in zm.boundary_edges() if np.isin(e, top).all()]
    iface = Interface(zm, np.array(edges), dm, Joint(kn=KN, ks=KN, friction_deg=friction_deg),
                      corner_share=share)
    cm = CoupledModel(dm, zm, iface)
    assert cm.settle(tol=tol, max_steps=400_000).converged
    return cm, dm, zm


def _stack_on_a_shaken_mohr_coulomb_layer():
    """Two 0.8 m x 0.25 m blocks stacked on the shaken Mohr-Coulomb layer of
    :func:`_block_on_a_shaken_mohr_coulomb_layer`, their joint 100 times stiffer than the
    interface's (kn = ks = 1e11 Pa/m): the blocks' contact sets the time step, about a sixth
    of the interface's and the zones' stable steps, as the stones' joints do in the mock-ups
    of Savalle et al. (2022)."""
    from murus.continuum import MohrCoulomb

    mat = MohrCoulomb(density=RHO, E=2e7, nu=0.3, friction_deg=30.0, cohesion=2e3,
                      dilation_deg=0.0)
    cm, dm, zm = _stack_on(mat, 0.8, 25.0, 1e-6)
    dm.set_base_motion(velocity=lambda t: 0.3 * np.sin(2 * np.pi * 4.0 * t))
    dm.bext[:, 0] = 0.3 * dm.bmass * G_ACC
    return cm, dm, zm


def test_subcycling_closes_the_energy_balance_within_the_time_step_error():
    """Subcycling (the zones step once every n steps of the blocks, but the interface's
    gridpoints and the zones touching them with the blocks): the energy balance of the
    shaken and pushed stack still closes within 1 % of the work put in, with n at its limit
    (the zones' and the interface's stable steps, 10 here) and at half of it; and
    subcycling changes the stack's slide by less than halving the time step of one step for
    all does (its change is within the time discretisation's own error)."""
    def slide(n, dt_factor=1.0):
        cm, dm, zm = _stack_on_a_shaken_mohr_coulomb_layer()
        if dt_factor != 1.0:
            cm.set_dt(dt_factor * dm.dt)
        lim = cm.subcycle_limit()
        got = cm.set_subcycle(max(2, lim // 2) if n == "half" else n)
        assert zm.P[ZK.P_DT] == pytest.approx(got * dm.dt, rel=1e-15)
        res = cm.run(0.6, xi=0.05, freq=4.0, every=100, probes={"ux": body_probe(0, "ux")})
        assert res.status == "completed"
        e = cm.energy()
        put_in = e["zones_base_work"] + e["external_work"]
        assert e["interface_slip"] > 0.3 * put_in and e["zones_plastic"] > 0.02 * put_in
        assert abs(e["error"]) < 0.01 * put_in, (n, e["error"] / put_in)
        return res["ux"][-1], lim

    ref, _ = slide(1, 0.5)
    one, lim = slide(1)
    assert lim >= 4 and ref > 0.05
    for n in ("half", "auto"):
        ux, _ = slide(n)
        assert abs(ux - one) <= abs(one - ref), (n, ux, one, ref)


def test_a_rocking_stack_gets_no_energy_from_the_interface_with_shrink():
    """The rocking stack on its coarse layer (8 x 4 zones: a 0.4 m face on about two zone
    edges, so its corners carry much of it): with ``corner_share="follow"`` the interface's
    contacts create energy as the stack rocks (breaking negative: 1.4 J in 0.2 s, more than
    the 0.93 J given; the stack rises 10 times what it does on a 32 x 16 layer, where both
    rules agree: validation/corner_rule.py); with "shrink" they only release it (breaking
    >= 0: a passive interface, the energy balance of a contact law). The same stack with
    "follow" is run by :func:`test_a_subcycled_impact_on_a_stiff_interface_gains_no_energy`,
    which checks that its breaking is below -0.5 times the energy given (this test's
    contrast: it can fail)."""
    *_, breaking = _rocking_stack(1, share="shrink")
    assert breaking >= 0.0


def test_a_subcycled_run_resumes_bit_for_bit_within_a_zones_step(tmp_path):
    """A checkpoint taken between two steps of the zones (the blocks' step count not a
    multiple of n) holds the subcycle and its phase: the resumed run is the uninterrupted
    one, bit for bit."""
    cm, dm, zm = _stack_on_a_shaken_mohr_coulomb_layer()
    n = cm.set_subcycle("auto")
    k = 0.1 + 1.5 * dm.dt  # not a whole number of the zones' steps
    cm.run(k, xi=0.05, freq=4.0, every=100)
    phase = int(cm._phase[0])
    assert phase != 0
    ck = tmp_path / "ck.npz"
    cm.save(ck)
    cm.run(0.1, xi=0.05, freq=4.0, every=100)
    cm2, dm2, zm2 = _stack_on_a_shaken_mohr_coulomb_layer()
    cm2.restore(ck)
    assert cm2.nsub == n and int(cm2._phase[0]) == phase
    cm2.run(0.1, xi=0.05, freq=4.0, every=100)
    assert cm2.nsub == n
    assert np.array_equal(dm2.bpos, dm.bpos) and np.array_equal(dm2.bvel, dm.bvel)
    assert np.array_equal(zm2.gxy, zm.gxy) and np.array_equal(zm2.zsig, zm.zsig)
    assert cm2.energy()["error"] == cm.energy()["error"]


def test_subcycle_is_checked():
    cm, dm, zm, iface = _block_on_layer()
    lim = cm.subcycle_limit()
    for bad in (0, lim + 1, 2.5, True, "fast"):
        with pytest.raises(CoupledError, match="subcycle"):
            cm.set_subcycle(bad)
    assert cm.set_subcycle("auto") == lim and cm.set_subcycle(1) == 1
    # a model whose every gridpoint were on the interface would have no slow partition
    cm, dm, zm = _stack_on_a_shaken_mohr_coulomb_layer()
    fz, sz, sg, sc = cm._partition()
    cm._part = (fz, sz, sg[:0], sc)
    assert cm.subcycle_limit() >= 2
    with pytest.raises(CoupledError, match="every gridpoint is on the interface"):
        cm.set_subcycle(2)
    assert cm.nsub == 1 and cm.set_subcycle(1) == 1


def _rocking_stack(n=1, dt_factor=1.0, share="follow"):
    """A stack of two 0.4 m x 0.25 m blocks (joint 100 times stiffer than the interface) settled
    on an elastic layer, then set rocking (0.5 rad/s about its centre, no damping): its
    corners lift off the interface and land again, an impact at every half cycle. Returns the
    model after 0.2 s, its energy balance's error gained since the first step over the energy
    given, the upper block's largest uplift, and the energy the interface booked as breaking
    over the energy given (negative: created by its contacts)."""
    cm, dm, zm = _stack_on(Elastic(density=RHO, E=2e7, nu=0.3), 0.4, 35.0, 1e-7, share)
    if dt_factor != 1.0:
        cm.set_dt(dt_factor * dm.dt)
    cm.set_subcycle(n)
    dm.bomg[:] = 0.5
    given = 0.5 * float((dm.binert * dm.bomg ** 2).sum())
    dm.reset_reference()
    y0 = float(dm.bpos[1, 1])
    cm.run(0.001, xi=0.0, freq=5.0)  # the balance from its first steps (the velocity set)
    e0, b0 = cm.energy()["error"], cm.energy()["interface_breaking"]
    res = cm.run(0.2, xi=0.0, freq=5.0, every=10, probes={"y": body_probe(1, "y")})
    assert res.status == "completed"
    e1 = cm.energy()
    return (cm, (e1["error"] - e0) / given, float(np.nanmax(res["y"])) - y0,
            (e1["interface_breaking"] - b0) / given)


def test_a_subcycled_impact_on_a_stiff_interface_gains_no_energy():
    """The rocking stack lands on the interface at every half cycle (in the first subcycled
    scheme the interface's force on the gridpoints was taken once per zones' step, on the
    stones at every step, so the impact gained energy: +2.8 % of the energy given, in 0.2 s,
    the stack lifting 32 % higher; measured on session 14's code, b6870b2). With the
    interface's gridpoints stepped with the blocks, subcycled at the limit (n = 9) the energy
    balance's error stays within the time discretisation's (one step for all: -0.3 %, -0.4 %
    at half the step; bound: twice the larger; subcycled: -0.1 %), and the uplift changes by
    less than halving the time step of one step for all changes it (1.4e-7 m against 4.3e-6 m
    of 1.45e-4 m)."""
    _, err1, up1, breaking = _rocking_stack(1)
    # the stack rocks on 'follow', whose corners create energy (1.4 J of 0.93 J given):
    # the contrast of test_a_rocking_stack_gets_no_energy_from_the_interface_with_shrink
    assert breaking < -0.5
    _, err_half, up_half, _ = _rocking_stack(1, dt_factor=0.5)
    cm, err_n, up_n, _ = _rocking_stack("auto")
    assert cm.nsub >= 8
    # energy conserved as well as central differences conserve it with one step for all
    # (at dt and dt / 2: their impacts' own balance error), within a factor 2
    assert abs(err_n) <= 2 * max(abs(err1), abs(err_half)), (err_n, err1, err_half)
    assert up1 > 1e-4  # it rocks: the corner lifts by a tenth of a millimetre
    assert abs(up_n - up1) <= abs(up1 - up_half), (up_n, up1, up_half)

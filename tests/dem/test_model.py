"""Geometry, contacts, statics, time step and checkpoints of murus.dem."""

import math
import os
import signal

import numpy as np
import pytest

from murus.dem import Joint, Model, ModelError, body_probe, relative_probe
from murus.dem import kernels as K
from murus.motion.synthetic import sine_pulse

G = 9.81


def test_polygon_mass_properties_and_clump():
    m = Model(thickness=0.5)
    b = m.add_rectangle(0.4, 0.2, center=(1.0, 2.0), density=2000.0)
    # an L-shaped clump made of two rectangles (0..1 x 0..0.2) and (0..0.2 x 0.2..1)
    c = m.add_clump([[(0, 0), (1, 0), (1, 0.2), (0, 0.2)],
                     [(0, 0.2), (0.2, 0.2), (0.2, 1.0), (0, 1.0)]], density=1000.0)
    d = m.add_disc((3.0, 0.0), 0.1, density=1000.0)
    m.build()
    assert m.bmass[b] == pytest.approx(2000 * 0.5 * 0.08)
    assert m.binert[b] == pytest.approx(m.bmass[b] * (0.4**2 + 0.2**2) / 12)
    assert np.allclose(m.bpos[b], [1.0, 2.0])
    A1, A2 = 0.2, 0.16
    cx = (A1 * 0.5 + A2 * 0.1) / (A1 + A2)
    cy = (A1 * 0.1 + A2 * 0.6) / (A1 + A2)
    assert m.bmass[c] == pytest.approx(1000 * 0.5 * (A1 + A2))
    assert np.allclose(m.bpos[c], [cx, cy])
    J = (A1 * ((1 + 0.04) / 12 + (0.5 - cx) ** 2 + (0.1 - cy) ** 2)
         + A2 * ((0.04 + 0.64) / 12 + (0.1 - cx) ** 2 + (0.6 - cy) ** 2))
    assert m.binert[c] == pytest.approx(1000 * 0.5 * J)
    assert m.binert[d] == pytest.approx(0.5 * m.bmass[d] * 0.01)
    assert len(m.world_polygons()) == 3
    assert np.array_equal(m.body_of_polygon(), [b, c, c])
    centres, radii = m.discs()
    assert np.allclose(centres, [[3.0, 0.0]]) and np.allclose(radii, [0.1])
    assert np.array_equal(m.body_of_disc(), [d])


def test_polygon_input_checks():
    m = Model()
    with pytest.raises(ModelError, match="body 0: the polygon is not convex: split it into a"):
        m.add_polygon([(0, 0), (2, 0), (2, 2), (1, 0.5), (0, 2)])
    b = m.add_polygon([(0, 0), (0, 1), (1, 1), (1, 0)])  # clockwise: reversed
    m.add_disc((5.0, 0.0), 0.1)
    with pytest.raises(ModelError, match="body 2 part 1: the polygon is not convex"):
        m.add_clump([[(3, 3), (4, 3), (4, 4)], [(0, 0), (2, 0), (2, 2), (1, 0.5), (0, 2)]])
    m.build()
    w = m.world_polygons()[0]
    x, y = w[:, 0], w[:, 1]
    assert 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y) > 0
    assert m.bmass[b] == pytest.approx(2000.0)
    with pytest.raises(ModelError, match="rounding"):
        mm = Model(rounding=0.2)
        mm.add_rectangle(1.0, 0.3)
        mm.build()


def test_block_on_block_two_subcontacts_carry_the_weight():
    """An offset block on a wider block: two sub-contacts at the ends of the interface; forces
    sum to m g and their centroid is the resultant position (the block's centroid)."""
    m = Model(joint=Joint(kn=1e9, ks=1e9, friction_deg=35), rounding=1e-3)
    lo = m.add_rectangle(0.8, 0.2, center=(0.0, 0.1), kinematic="fixed")
    top = m.add_rectangle(0.4, 0.2, center=(0.17, 0.3))
    assert m.settle(tol=1e-10).converged
    c = m.contacts_array()
    assert c.shape[0] == 2
    fn = c[:, 2]
    W = m.bmass[top] * G
    assert fn.sum() == pytest.approx(W, rel=1e-9)
    assert np.sum(fn * c[:, 0]) / fn.sum() == pytest.approx(m.bpos[top, 0], abs=1e-9)
    # the two points sit at the corners of the interface (less the rounding)
    assert np.allclose(np.sort(c[:, 0]), [0.17 - 0.2 + 1e-3, 0.17 + 0.2 - 1e-3], atol=1e-6)
    assert np.allclose(c[:, 5], 1.0)
    assert np.array_equal(m.contact_pairs(), [[lo, top], [lo, top]])


def test_overhanging_block_contacts_at_the_overlap_ends():
    m = Model(joint=Joint(kn=1e9, ks=1e9, friction_deg=35), rounding=1e-3)
    m.add_rectangle(0.4, 0.2, center=(0.0, 0.1), kinematic="fixed")
    top = m.add_rectangle(0.4, 0.2, center=(0.1, 0.3))  # interface from x = -0.1 to 0.2
    assert m.settle(tol=1e-10).converged
    c = m.contacts_array()
    assert np.allclose(np.sort(c[:, 0]), [-0.1 + 1e-3, 0.2 - 1e-3], atol=1e-6)
    assert c[:, 2].sum() == pytest.approx(m.bmass[top] * G, rel=1e-9)


def test_disc_resting_on_two_discs():
    """Statics of disc contacts: a disc on two fixed discs at 60 deg; the normals lie along
    the lines of centres, the two contacts are symmetric and carry m g together (the shear
    springs take part of it: the problem is statically indeterminate)."""
    m = Model(joint=Joint(kn=1e9, ks=1e9, friction_deg=30))
    r = 0.1
    m.add_disc((-r, 0.0), r, kinematic="fixed")
    m.add_disc((r, 0.0), r, kinematic="fixed")
    top = m.add_disc((0.0, 2 * r * math.sin(math.pi / 3)), r)
    assert m.settle(tol=1e-10).converged
    c = m.contacts_array()
    assert c.shape[0] == 2
    W = m.bmass[top] * G
    assert c[0, 2] == pytest.approx(c[1, 2], rel=1e-9)
    assert np.allclose(np.abs(c[:, 5]), math.sin(math.pi / 3), atol=1e-6)
    fy = c[:, 2] * c[:, 5] + c[:, 3] * c[:, 4]  # (fn n + fs t)_y with t = (-ny, nx)
    assert np.abs(fy).sum() == pytest.approx(W, rel=1e-8)
    assert np.abs(c[:, 2] - W / (2 * math.cos(math.pi / 6))).max() < 0.4 * W


def test_user_dt_above_the_stable_step_is_an_error():
    m = Model(joint=Joint(kn=1e9, ks=1e9))
    m.add_rectangle(1.0, 0.2, center=(0, -0.1), kinematic="fixed")
    m.add_rectangle(0.2, 0.2, center=(0, 0.1))
    dts = m.stable_dt()
    assert 0 < dts < 1e-3
    with pytest.raises(ValueError, match="exceeds the stable time step"):
        m.run(0.01, dt=2 * dts)
    res = m.run(0.01, dt=0.5 * dts)
    assert res.dt == 0.5 * dts and res.status == "completed"


def _shaken_stack():
    m = Model(joint=Joint(kn=1e9, ks=1e9, friction_deg=25))
    base = m.add_rectangle(3.0, 0.2, center=(0.0, -0.1), kinematic="base")
    blocks = [m.add_rectangle(0.3, 0.6, center=(0.0, 0.3 + 0.6 * i)) for i in range(3)]
    m.settle(tol=1e-8)
    m.set_base_motion(sine_pulse(0.6 * G, 3.0, cycles=2, dt=0.001, duration=0.5))
    return m, base, blocks


def _probes(base, blocks):
    return {"d_top": relative_probe(blocks[-1], base, "ux"), "rot": body_probe(blocks[-1],
                                                                              "angle")}


def _state(m):
    return [m.bpos, m.bang, m.bvel, m.bomg, m.sf, m.sid, m.E, m.C, m.pairs]


def test_checkpoint_resume_is_bit_identical(tmp_path):
    t_end = 0.4
    m1, base, blocks = _shaken_stack()
    r1 = m1.run(t_end=t_end, probes=_probes(base, blocks), every=20, xi=0.02, freq=5.0)
    assert r1.status == "completed"
    assert np.abs(r1["d_top"]).max() > 1e-3  # the stack moves

    m2, base, blocks = _shaken_stack()
    r2 = m2.run(t_end=t_end, probes=_probes(base, blocks), every=20, xi=0.02, freq=5.0,
                max_steps=1234)
    assert r2.status == "max_steps" and r2.steps == 1234
    m2.save(tmp_path / "ck.npz")
    m3 = Model.load(tmp_path / "ck.npz")
    r3 = m3.run(t_end=t_end, every=20, xi=0.02, freq=5.0)
    assert r3.status == "completed"
    for a, b in zip(_state(m1), _state(m3), strict=True):
        assert np.array_equal(a, b)
    assert np.array_equal(r1.t, r3.t)
    for k in r1.values:
        assert np.array_equal(r1[k], r3[k], equal_nan=True), k


def test_ctrl_c_interrupts_between_chunks_and_resumes(tmp_path):
    t_end = 0.3
    m1, base, blocks = _shaken_stack()
    m1.run(t_end=t_end, probes=_probes(base, blocks), every=25)

    m2, base, blocks = _shaken_stack()
    fired = []

    def interrupt(m):
        if m.time > 0.1 and not fired:
            fired.append(m.time)
            os.kill(os.getpid(), signal.SIGINT)
        return False

    r2 = m2.run(t_end=t_end, probes=_probes(base, blocks), every=25, stop=interrupt)
    assert r2.status == "interrupted"
    assert m2.time < t_end
    m2.save(tmp_path / "ck.npz")
    m3 = Model.load(tmp_path / "ck.npz")
    m3.run(t_end=t_end, every=25)
    for a, b in zip(_state(m1), _state(m3), strict=True):
        assert np.array_equal(a, b)


def test_stop_condition_and_output_arrays():
    m, base, blocks = _shaken_stack()
    res = m.run(0.5, probes=_probes(base, blocks), every=10,
                stop=lambda mm: abs(mm.body_displacement()[blocks[-1], 0]) > 2e-3)
    assert res.status == "stopped"
    assert abs(m.body_displacement()[blocks[-1], 0]) > 2e-3
    ca = m.contacts_array()
    assert ca.shape[1] == 6 and ca.shape[0] >= 4
    assert np.allclose(np.hypot(ca[:, 4], ca[:, 5]), 1.0)
    assert m.body_displacement().shape == (4, 2)
    e = m.energy()
    assert abs(e["error"]) < 1e-2 * max(abs(e["base_work"]), 1e-9)


def test_contact_updates_counted_and_rebuilds():
    m, base, blocks = _shaken_stack()
    res = m.run(0.2)
    assert res.contact_updates >= 4 * res.steps
    assert m.C[K.C_REBUILD] >= 1


def _free_disc(frame, U=0.3, v0=1.0, xi=0.05, f=2.0):
    """A disc in the air (no gravity, no contact) with velocity v0 beside a base moving at U."""
    m = Model(gravity=0.0)
    m.add_rectangle(1.0, 0.2, center=(0.0, -5.0), kinematic="base")
    d = m.add_disc((0.0, 0.0), 0.1)
    m.set_base_motion(velocity=lambda t: U + 0.0 * t)
    m.build()
    m.bvel[d, 0] = v0
    m.snapshot()
    m.reset_reference()
    alpha = 4 * math.pi * xi * f  # mass-proportional coefficient [1/s]
    res = m.run(1.0, xi=xi, freq=f, damping_frame=frame,
                probes={"vx": body_probe(d, "vx")}, sample_dt=0.05)
    return res, alpha, m


@pytest.mark.parametrize("frame", ["base", "absolute"])
def test_mass_damping_frame_closed_form(frame):
    """Mass-proportional damping relaxes a free body towards the damping frame:
    v(t) = Uf + (v0 - Uf) exp(-alpha t) with Uf = U (frame "base") or 0 ("absolute"). The
    central-difference average is second order: error ~ (alpha dt)^2 alpha t / 12 << 1e-6."""
    U, v0 = 0.3, 1.0
    res, alpha, m = _free_disc(frame, U, v0)
    uf = U if frame == "base" else 0.0
    t = res.t
    exact = uf + (v0 - uf) * np.exp(-alpha * t)
    got = res["vx"]
    assert np.max(np.abs(got - exact)) < 1e-6
    # energy balance: the damping work closes it up to the start-up offset of the leapfrog
    # (first half step, of order alpha dt times the initial kinetic energy)
    e = m.energy()
    ke0 = 0.5 * m.bmass[1] * v0**2
    assert abs(e["damping_work"]) > 0.3 * ke0
    assert abs(e["error"]) < alpha * m.dt * ke0


def test_damping_frame_is_checked():
    m = Model()
    m.add_rectangle(1.0, 0.2, center=(0.0, -0.1), kinematic="fixed")
    m.add_rectangle(0.2, 0.2, center=(0.0, 0.1))
    with pytest.raises(ValueError, match="damping_frame"):
        m.run(0.01, damping_frame="relative")


def test_tilting_gravity_work_closes_the_energy_balance():
    """Rotating gravity (tilting table) does work -sum m x . dg/dt on the bodies; with it, and
    with the jump of a new start tilt booked at set_tilt, the balance closes (1e-3 of the
    work) before and after sliding starts (a 1.0 x 0.5 block, friction 30 deg)."""
    from murus.dem.verify import block_on_base
    m, base, blk = block_on_base(1.0, 0.5, Joint(kn=1e10, ks=1e10, friction_deg=30.0))
    m.set_tilt(0.0, start_deg=10.0)
    m.settle(tol=1e-7)
    m.set_tilt(0.0, start_deg=26.0)  # a jump of the tilt: a change of potential energy
    e = m.energy()
    assert abs(e["tilt_work"]) > 1.0
    assert abs(e["error"]) < 1e-6 * abs(e["tilt_work"])
    m.set_tilt(20.0, start_deg=26.0)  # from the current time: 26 deg now
    assert math.isclose(math.degrees(float(m.tilt_angle(m.time))), 26.0, abs_tol=1e-12)
    m.run(0.15)  # to 29 deg: the block sits, gravity turns
    e = m.energy()
    assert abs(e["slip"]) < 1e-3 * abs(e["tilt_work"])
    assert abs(e["error"]) < 1e-3 * abs(e["tilt_work"])
    m.run(0.3)  # to 35 deg: it slides
    e = m.energy()
    assert e["slip"] > 1e-2 * abs(e["tilt_work"])
    assert abs(e["error"]) < 1e-3 * (abs(e["tilt_work"]) + e["slip"])


def test_prescribed_body_pushes_a_block_and_its_work_is_counted():
    """A kinematic "prescribed" platen pushed at constant speed moves a block that slides on a
    fixed base (friction 30 deg): the push is mu W on average, and the platen's work (counted
    as base work) equals the slip dissipation plus the kinetic energy, the balance within
    1 % of the work (issue 5 item 5; the sudden start of the platen is an impact)."""
    m = Model(joint=Joint(kn=1e9, ks=1e9, friction_deg=30.0))
    m.add_rectangle(4.0, 0.2, center=(0.0, -0.1), kinematic="fixed")
    blk = m.add_rectangle(0.4, 0.4, center=(0.0, 0.2))
    plate = m.add_rectangle(0.1, 0.3, center=(-0.25 - 1e-4, 0.2), kinematic="prescribed")
    with pytest.raises(ModelError, match="not a kinematic='prescribed' body"):
        m.set_velocity(blk, 0.1)
    m.settle(tol=1e-7)
    m.set_velocity(plate, vx=0.05)
    m.run(1.0)
    e = m.energy()
    W = m.bmass[blk] * G
    assert m.body_displacement()[blk, 0] == pytest.approx(0.05 * 1.0 - 1e-4, abs=2e-3)
    assert e["base_work"] == pytest.approx(math.tan(math.radians(30)) * W * 0.0499, rel=2e-2)
    assert abs(e["error"]) < 1e-2 * e["base_work"]
    assert e["slip"] == pytest.approx(e["base_work"], rel=2e-2)
    assert m.bpos[plate, 0] == pytest.approx(-0.25 - 1e-4 + 0.05 * m.time, abs=1e-12)

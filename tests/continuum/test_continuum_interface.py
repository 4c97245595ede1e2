"""Interfaces between continuum zones and blocks (murus.continuum.interface).

Closed forms of the joint law (Savalle et al. (2022), eqs. 3-4): a gridpoint pressed by delta
carries ``kn L t delta`` over its tributary length L; the shear force is capped at
``c A + Fn tan(phi)`` and the slip dissipation is the trapezoid-rule work beyond the elastic
energy; a bond breaks at its tensile strength and then carries its residual tension; a face on a
row of gridpoints carries ``kn t delta`` times the covered length, its corners nothing (the
coverage rule); a corner between two gridpoints of a coarse mesh is split ``(1 - s, s)``.
Conservation: the forces on the gridpoints and the blocks are equal and opposite, in force and
in moment. A static check couples a block and an elastic layer in a short explicit loop written
here (the public continuum kernel :func:`murus.continuum.kernels.run_chunk`, one step at a time,
with the interface forces as applied gridpoint forces): the interface carries the block's weight
within 0.5 %; the same loop without damping conserves the total energy, the interface's slip
dissipation included, within 1 % of the initial kinetic energy. A step allocates nothing.
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
from continuum_inputs import rect_mesh, sides

from murus.continuum import interface as I
from murus.dem import Joint, Model
from murus.dem.kernels import F_GAP

KN = 1.0e9
KS = 5.0e8
T = 0.8  # thickness [m]
H = 0.5  # gridpoint spacing [m]
BW = 0.25  # width of the narrow blocks [m], half the tributary length of a gridpoint
R_ROUND = 0.01  # the rounding of _model [m]
BF = BW - 2 * R_ROUND  # the flat bottom face of a narrow block [m]


def _surface(n, h=H, x0=0.0):
    """n gridpoints on y = 0 at x0 + i h, the zones below: the grid side and the interface
    edges (zone on the left: walking right to left)."""
    xy = np.column_stack([x0 + h * np.arange(n), np.zeros(n)])
    grid = SimpleNamespace(gxy=xy, gvel=np.zeros((n, 2)))
    edges = np.array([[i + 1, i] for i in range(n - 1)], np.int64)
    return grid, edges


def _model(joint=None, rounding=0.01):
    return Model(thickness=T, rounding=rounding, margin=0.05,
                 joint=joint or Joint(kn=KN, ks=KS, friction_deg=30.0))


def _moment_of(fg, xy, c):
    """Moment about c of the forces fg at the points xy."""
    return float(np.sum((xy[:, 0] - c[0]) * fg[:, 1] - (xy[:, 1] - c[1]) * fg[:, 0]))


def test_gridpoint_pressed_into_a_face():
    """A gridpoint of tributary length h (half of each of its two edges) under a block
    narrower than h, of flat bottom face b (its width less the two roundings), pressed by
    delta: ``kn b t delta`` (the part of the tributary length that faces the face) up on the
    block, down on the gridpoint, nothing at the other
    gridpoints and no corner contact (the face is carried by the gridpoint)."""
    delta = 1e-4
    grid, edges = _surface(3, x0=-H)
    m = _model()
    m.add_rectangle(BW, 0.4, center=(0.0, 0.2 - delta))
    ifc = I.Interface(grid, edges, m)
    fg, fb = ifc.forces(0.0)
    f = KN * BF * T * delta
    assert fb[0, 1] == pytest.approx(f, rel=1e-9)
    assert fg[1, 1] == pytest.approx(-f, rel=1e-9)
    assert np.abs(fg[[0, 2]]).max() == 0.0
    assert abs(fb[0, 0]) < 1e-9 * f and abs(fb[0, 2]) < 1e-9 * f
    assert ifc.C[I.IC_NODES] == 1 and ifc.C[I.IC_CORNERS] == 0


def test_gridpoint_inside_the_core():
    """A gridpoint of a vertical interface (zones on the left) inside the core polygon of a
    block pressed into it by 0.03 m (more than the rounding): the gap is minus the distance to
    the nearest core edge minus the rounding, -0.03 m, the normal that edge's inward normal;
    the block's face (0.4 m less the two roundings) is shorter than the gridpoint's tributary
    length h = 0.5 m, so the contact takes the length of the face."""
    xy = np.array([[0.0, -H], [0.0, 0.0], [0.0, H]])
    grid = SimpleNamespace(gxy=xy, gvel=np.zeros((3, 2)))
    edges = np.array([[0, 1], [1, 2]])  # upward: zones at x < 0
    m = _model()
    pen = 0.03
    m.add_rectangle(0.4, 0.4, center=(0.2 - pen, 0.0))
    ifc = I.Interface(grid, edges, m)
    fg, fb = ifc.forces(0.0)
    f = KN * (0.4 - 2 * R_ROUND) * T * pen
    assert fb[0, 0] == pytest.approx(f, rel=1e-9)
    assert fg[1, 0] == pytest.approx(-f, rel=1e-9)
    assert abs(fb[0, 1]) < 1e-9 * f and abs(fb[0, 2]) < 1e-9 * f
    assert ifc.nodes.sf[..., F_GAP][ifc.nodes.sid >= 0] == pytest.approx(-pen, rel=1e-9)
    assert ifc.C[I.IC_CORNERS] == 0


def test_forces_are_equal_and_opposite():
    """A tilted block pressing a corner and a face onto a surface, moving and spinning over
    moving gridpoints (shear increments): total force zero, and the moment on the block about
    its centroid equals minus the moment of the gridpoint forces about it."""
    grid, edges = _surface(6, h=0.2)
    m = _model()
    ang = 0.3
    w, h = 0.5, 0.3
    # lowest corner (-w/2, -h/2) rotated by ang, placed at (0.19, -0.01)
    c, s = math.cos(ang), math.sin(ang)
    lx, ly = -w / 2, -h / 2
    cx = 0.19 - (c * lx - s * ly)
    cy = -0.01 - (s * lx + c * ly)
    m.add_rectangle(w, h, center=(cx, cy), angle=ang)
    ifc = I.Interface(grid, edges, m)
    rng = np.random.default_rng(3)
    grid.gvel[:] = rng.normal(0.0, 0.01, grid.gvel.shape)
    m.bvel[0] = (0.02, -0.01)
    m.bomg[0] = 0.05
    for _ in range(3):
        fg, fb = ifc.forces(1e-3)
        scale = np.abs(fb).max()
        assert ifc.C[I.IC_NODES] >= 1 and ifc.C[I.IC_CORNERS] >= 1
        assert np.abs(fg.sum(axis=0) + fb[0, :2]).max() < 1e-12 * scale
        assert abs(fb[0, 2] + _moment_of(fg, grid.gxy, m.bpos[0])) < 1e-12 * scale
        assert abs(ifc.shear_force()) > 0.0


def test_coulomb_cap_and_slip_dissipation():
    """A block sliding at constant velocity over a pressed gridpoint: the shear force grows by
    ``ks A du`` per step up to ``c A + Fn tan(phi)`` and stays there; the slip dissipation is the
    trapezoid-rule work of the shear force minus the elastic energy, ``Fmax du`` per sliding
    step (du chosen so that the cap is reached exactly after 10 steps)."""
    delta = 2e-5
    coh = 1.0e4
    phi = 25.0
    joint = Joint(kn=KN, ks=KS, friction_deg=phi, cohesion=coh, cohesion_res=coh)
    grid, edges = _surface(3, x0=-H)
    m = _model(joint)
    m.add_rectangle(BW, 0.4, center=(0.0, 0.2 - delta))
    ifc = I.Interface(grid, edges, m)
    A = BF * T  # the block's flat face, within the gridpoint's tributary length
    fn = KN * A * delta
    fmax = coh * A + fn * math.tan(math.radians(phi))
    nel = 10
    du = fmax / (KS * A * nel)
    m.bvel[0] = (1.0, 0.0)  # +x: the shear force on the block points to -x
    work = 0.0
    fs_old = 0.0
    nsteps = 25
    for k in range(1, nsteps + 1):
        fg, fb = ifc.forces(du)
        fs = -fb[0, 0]
        assert fb[0, 1] == pytest.approx(fn, rel=1e-9)
        assert fs <= fmax * (1 + 1e-12)
        assert fs == pytest.approx(min(k, nel) * KS * A * du, rel=1e-9)
        work += 0.5 * (fs_old + fs) * du
        fs_old = fs
    d_slip = ifc.energy["slip"]
    assert d_slip == pytest.approx(fmax * (nsteps - nel) * du, rel=1e-9)
    assert d_slip == pytest.approx(work - 0.5 * fmax ** 2 / (KS * A), rel=1e-9)
    assert ifc.energy["stored"] == pytest.approx(0.5 * fmax ** 2 / (KS * A)
                                                 + 0.5 * fn ** 2 / (KN * A), rel=1e-9)


def test_tensile_bond_breaks_then_carries_its_residual():
    """A bonded gridpoint contact pulled apart: elastic tension ``kn A g`` up to the strength
    ``T A``; past it the bond breaks (energy ``(T A)² / (2 kn A)`` released) and the contact
    carries at most the residual tension, while compression is unchanged."""
    ten, tres = 1.0e5, 2.0e4
    joint = Joint(kn=KN, ks=KS, friction_deg=30.0, tension=ten, tension_res=tres)
    grid, edges = _surface(3, x0=-H)
    m = _model(joint)
    m.add_rectangle(BW, 0.4, center=(0.0, 0.2))  # touching: gap 0, bonded
    ifc = I.Interface(grid, edges, m)
    A = BF * T  # the block's flat face, within the gridpoint's tributary length
    y0 = float(m.bpos[0, 1])

    def fn_at(gap):
        m.bpos[0, 1] = y0 + gap
        fg, fb = ifc.forces(0.0)
        assert fb[0, 1] == pytest.approx(-fg[1, 1], rel=1e-12, abs=1e-9)
        return fb[0, 1]

    g_t = ten / KN
    assert fn_at(0.5 * g_t) == pytest.approx(-0.5 * ten * A, rel=1e-9)
    assert ifc.energy["break"] == 0.0
    assert fn_at(1.5 * g_t) == pytest.approx(-tres * A, rel=1e-9)
    assert ifc.energy["break"] == pytest.approx(0.5 * (ten * A) ** 2 / (KN * A), rel=1e-9)
    assert fn_at(0.5 * g_t) == pytest.approx(-tres * A, rel=1e-9)  # residual only
    assert fn_at(0.1 * g_t) == pytest.approx(-0.1 * ten * A, rel=1e-9)  # below the residual
    assert fn_at(-1e-5) == pytest.approx(KN * A * 1e-5, rel=1e-9)


def test_flat_face_on_a_row_of_gridpoints():
    """A block of width 4h (a flat face of 4h less the two roundings) resting on a row of
    gridpoints (spacing h) pressed by delta carries ``kn t delta (4h - 2r)``: the two inner
    gridpoints their tributary h each, the two outer ones the h - r of theirs under the face;
    its corners, above zone edges, add nothing: the face is carried by the gridpoints (without
    the rule each corner would add half the face)."""
    delta = 1e-4
    h = 0.25
    grid, edges = _surface(9, h=h)
    m = _model()
    m.add_rectangle(4 * h, 0.3, center=(3.5 * h, 0.15 - delta))
    ifc = I.Interface(grid, edges, m)
    fg, fb = ifc.forces(0.0)
    assert fb[0, 1] == pytest.approx(KN * T * delta * (4 * h - 2 * R_ROUND), rel=1e-9)
    want = KN * T * delta * np.array([h - R_ROUND, h, h, h - R_ROUND])
    assert fg[2:6, 1] == pytest.approx(-want, rel=1e-9)
    assert ifc.C[I.IC_NODES] == 4 and ifc.C[I.IC_CORNERS] == 0


def _slide_a_face(corner_share="follow"):
    """A block's flat face (length 1.1 m less the two roundings) pressed by delta on a row of
    gridpoints (spacing h = 0.25 m) and moved across a whole spacing in steps of 1 cm: yields
    the step, the forces on the block, ``kn t delta`` and the face's carried length if whole."""
    delta, h, w = 1e-4, 0.25, 1.1
    grid, edges = _surface(12, h=h)
    m = _model()
    m.add_rectangle(w, 0.3, center=(1.0, 0.15 - delta))
    ifc = I.Interface(grid, edges, m, corner_share=corner_share)
    for k in range(26):
        m.bpos[0, 0] = 1.0 + 0.01 * k
        yield k, ifc.forces(0.0)[1][0], KN * T * delta, w - 2 * R_ROUND


def test_a_face_sliding_over_gridpoints_is_carried_once_everywhere():
    """The coverage rule (:func:`_slide_a_face`): wherever the face's ends are (over a
    gridpoint's tributary or between gridpoints, where the corners take what the gridpoints
    leave), the face carries ``kn t delta`` times its length; the moment about the centroid
    is only that of lumping each end's segment at a gridpoint or a corner, at most ``kn t
    delta h`` times ``h / 2`` at either end."""
    h = 0.25
    for k, fb, unit, length in _slide_a_face():
        assert fb[1] == pytest.approx(unit * length, rel=1e-9), k
        assert abs(fb[2]) <= unit * h * h, k


def test_a_face_sliding_over_gridpoints_with_shrinking_corners_is_never_carried_twice():
    """The coverage rule with ``corner_share="shrink"`` (:func:`_slide_a_face`): where the
    corners' contacts form (the start, and wherever a corner's share is what the gridpoints
    leave) the face carries ``kn t delta`` times its length, and it never carries more. A
    loaded corner's share follows the rule down, not up (the interface gives no energy to a
    loaded corner): as the gridpoint next to the trailing corner falls behind, the corner
    keeps its share and the face carries less, by at most ``kn t delta h / 2`` (a flat face on
    a row of gridpoints leaves at most half a spacing next to a corner), until the corner's
    contact is renewed (here when the gridpoint behind it has left the face: 10 % less at
    most, 20 cm into the move). The moment about the centroid is that of lumping each end's
    segment at a gridpoint or a corner, at most ``kn t delta h`` times ``h / 2`` at either
    end, and of the missing segment at the face's end (lever half the face)."""
    h, w = 0.25, 1.1
    short = []
    for k, fb, unit, length in _slide_a_face("shrink"):
        assert fb[1] <= unit * length * (1 + 1e-9), k
        assert fb[1] >= unit * (length - h / 2), k
        short.append(1 - fb[1] / (unit * length))
        assert abs(fb[2]) <= unit * h * (h + w / 2), k
    assert short[0] <= 1e-9 and short[-1] <= 1e-9
    assert max(short) > 0.05  # the trailing corner's share was held


def test_a_corner_rocking_next_to_a_gridpoint_gains_no_energy():
    """A closed loop of a block's motion does no net work through the interface: the block
    (0.25 m wide) has its bottom-left corner pressed into a zone edge and a gridpoint under its
    bottom face 0.15 m from the corner, and is moved (no time step: elastic forces only) round
    a loop in its depth and tilt that makes the face touch the gridpoint and lift off it again
    at two different depths of the corner. The coverage rule gives the corner half the face
    while the gridpoint is off and only what the gridpoint leaves while it touches; with the
    corner's stiffness following that up and down under load (``corner_share="follow"``,
    the earlier default), every loop gives the block 0.62 J (0.54 of the largest stored
    energy: the pump behind the creep of VALIDATION.md, *Subcycling*). With
    ``corner_share="shrink"`` a loaded corner's stiffness follows the rule down, not up:
    the first loop may release energy (booked as breaking), and from the second on the
    springs are elastic. What work
    is left is that of the gridpoint's tributary length projected on the tilted face (``cos
    theta``), at most the stored energy times ``theta_max²``, and of contacts formed a step
    late (it vanishes as the steps shrink)."""
    grid, edges = _surface(3, h=0.25)
    w, hgt, xa, lever = 0.25, 0.3, 0.1, 0.15
    c0 = np.array([xa + w / 2, hgt / 2])
    corner = np.array([xa, 0.0])
    d0, a = 1e-4, 5e-5  # mean depth of the corner and its amplitude [m]
    th0, b = d0 / lever, 2 * a / lever  # tilt: the face reaches the gridpoint at mid-loop

    def loops(n):
        m = _model()
        m.add_rectangle(w, hgt, center=(xa + w / 2, hgt / 2))
        ifc = I.Interface(grid, edges, m, corner_share="shrink")

        def place(ph):
            th = th0 + b * math.sin(ph)
            rot = np.array([[math.cos(th), -math.sin(th)], [math.sin(th), math.cos(th)]])
            c = np.array([xa, -(d0 + a * math.cos(ph))]) + rot @ (c0 - corner)
            m.bpos[0] = c
            m.bang[0] = th
            return np.array([c[0], c[1], th])

        q = place(0.0)
        f = ifc.forces(0.0)[1][0].copy()
        u0 = I.stored_energy(ifc.nodes, ifc.corners)
        out, umax, touched = [], 0.0, set()
        for _ in range(2):
            work, brk = 0.0, ifc.energy["break"]
            for k in range(1, n + 1):
                q1 = place(2 * math.pi * k / n)
                f1 = ifc.forces(0.0)[1][0].copy()
                work += 0.5 * float(np.dot(f + f1, q1 - q))
                umax = max(umax, I.stored_energy(ifc.nodes, ifc.corners))
                touched.add(int(ifc.C[I.IC_NODES]))
                assert ifc.C[I.IC_CORNERS] == 1
                q, f = q1, f1
            u1 = I.stored_energy(ifc.nodes, ifc.corners)
            out.append((work, u1 - u0, ifc.energy["break"] - brk))
            u0 = u1
        return out, umax, touched

    (first, second), umax, touched = loops(500)
    assert touched == {0, 1}  # the face touches the gridpoint and lifts off it
    bound = umax * (th0 + b) ** 2
    work, du, brk = first
    assert brk >= 0.0  # released, not gained
    assert work + du <= bound  # the block got no more than the springs gave up
    assert abs(second[0]) <= bound
    (_, second2), _, _ = loops(1000)
    assert abs(second2[0]) <= bound
    assert abs(second2[0] - second[0]) <= 0.1 * bound  # converged: not the trapezoid sum's


@pytest.mark.parametrize("share", ["follow", "shrink"])
@pytest.mark.parametrize("h", [0.0625, 0.25 / 6])
def test_a_tilted_face_carries_the_winkler_force(share, h):
    """A block's face (0.25 m, flat length L = 0.23 m) pressed by delta = 1e-4 m at its middle
    into a row of gridpoints of spacing h (4 or 6 to the face; the zones held, so the
    interface's springs alone: a Winkler foundation of modulus kn) and tilted about its
    middle, step by step, to just below uplift (theta < 2 delta / L): the normal force is the
    Winkler integral ``kn t L delta`` (a linear penetration over the whole face). Each
    gridpoint carries its tributary length at its own penetration, exact for a linear one when
    the tributary is centred on it; at either end of the face a corner's share (at most h / 2)
    or a gridpoint's tributary cut by the face's end is lumped at the vertex or the gridpoint
    instead of its middle, off by at most ``kn t theta h² / 8``: within ``kn t theta h² / 4``
    in all, with either corner rule (a monotonic tilt lifts no gridpoint next to a loaded
    corner, so the rules agree)."""
    delta, B, x0 = 1e-4, 0.25, 0.0137
    n = int(math.ceil((x0 + B) / h)) + 3
    grid, edges = _surface(n, h=h, x0=-h)
    m = _model()
    xc = x0 + B / 2
    m.add_rectangle(B, 0.3, center=(xc, 0.15 - delta))
    ifc = I.Interface(grid, edges, m, corner_share=share)
    L = B - 2 * R_ROUND
    for th in np.linspace(0.0, 0.95 * 2 * delta / L, 20):
        m.bang[0] = -th
        m.bpos[0] = (xc - 0.15 * math.sin(-th), -delta + 0.15 * math.cos(th))
        fb = ifc.forces(0.0)[1][0]
        assert abs(fb[1] - KN * T * L * delta) <= KN * T * th * h * h / 4 + 1e-9 * fb[1], th


@pytest.mark.parametrize("s", [0.3, 0.75])
def test_corner_between_two_gridpoints_of_a_coarse_mesh(s):
    """A square block standing on a corner (rotated 45°) poking into a zone edge of length L
    between its two gridpoints: one corner contact, tributary length half of each adjacent core
    edge projected on the zone edge, force ``-kn t w g`` split ``(1 - s, s)`` between the
    gridpoints; the gridpoints touch nothing."""
    L = 1.0
    grid, edges = _surface(2, h=L)
    m = _model()
    a = 0.3
    pen = 1e-2
    half = a / math.sqrt(2.0)
    m.add_polygon([[s * L, -pen], [s * L + half, half - pen], [s * L, 2 * half - pen],
                   [s * L - half, half - pen]])
    ifc = I.Interface(grid, edges, m)
    fg, fb = ifc.forces(0.0)
    wv = m.wv
    low = int(np.argmin(wv[:, 1]))
    gap = wv[low, 1] - m.srad[0]
    core = np.hypot(*(wv[1] - wv[0]))
    trib = 2 * 0.5 * core * math.cos(math.pi / 4)
    f = -KN * T * trib * gap
    sc = wv[low, 0] / L
    assert ifc.C[I.IC_NODES] == 0 and ifc.C[I.IC_CORNERS] == 1
    assert fb[0, 1] == pytest.approx(f, rel=1e-9)
    assert fg[0, 1] == pytest.approx(-(1 - sc) * f, rel=1e-9)
    assert fg[1, 1] == pytest.approx(-sc * f, rel=1e-9)
    assert abs(fb[0, 2] + _moment_of(fg, grid.gxy, m.bpos[0])) < 1e-12 * f


def test_disc_on_a_gridpoint_and_between_two():
    """A disc of radius R pressed by delta: on a gridpoint, ``kn 2R t delta`` from the gridpoint
    alone (the part of its tributary length h that faces the disc; the disc is carried by it:
    no edge contact); between the two gridpoints of a coarse edge, an edge contact of the same
    tributary 2 R (the blocks' disc-polygon tributary) split ``(1 - s, s)``."""
    R = 0.1
    delta = 1e-4
    grid, edges = _surface(3, x0=-H)
    m = _model()
    m.add_disc((0.0, R - delta), R)
    ifc = I.Interface(grid, edges, m)
    fg, fb = ifc.forces(0.0)
    assert fb[0, 1] == pytest.approx(KN * 2 * R * T * delta, rel=1e-9)
    assert fg[1, 1] == pytest.approx(-KN * 2 * R * T * delta, rel=1e-9)
    assert ifc.C[I.IC_NODES] == 1 and ifc.C[I.IC_CORNERS] == 0
    sc = 0.3
    grid, edges = _surface(2, h=1.0)
    m = _model()
    m.add_disc((sc, R - delta), R)
    ifc = I.Interface(grid, edges, m)
    fg, fb = ifc.forces(0.0)
    f = KN * 2 * R * T * delta
    assert ifc.C[I.IC_NODES] == 0 and ifc.C[I.IC_CORNERS] == 1
    assert fb[0, 1] == pytest.approx(f, rel=1e-9)
    assert fg[:, 1] == pytest.approx([-(1 - sc) * f, -sc * f], rel=1e-9)
    assert abs(fb[0, 2]) < 1e-9 * f


def test_critical_time_step():
    """The interface's critical step ``min sqrt(m / k)``: a light gridpoint against the
    stiffness ``max(kn, ks) L t`` of its tributary length (its mass per metre times t); with
    heavy gridpoints, the block against its interface contacts (at least the blocks' floor
    ``max(kn, ks) t`` times its longest edge)."""
    grid, edges = _surface(3, x0=-H)
    m = _model()
    m.add_rectangle(0.25, 0.4, center=(0.0, 0.2 - 1e-4))
    ifc = I.Interface(grid, edges, m)
    ifc.forces(0.0)
    assert ifc.critical_dt(np.full(3, 1.0)) == pytest.approx(math.sqrt(1.0 / (KN * H)),
                                                             rel=1e-12)
    kt = max(KN * H * T, KN * T * 0.4)
    kr = max(KN * H * T * float(m.bpos[0, 1]) ** 2, KN * T * 0.4 * float(m.brad[0]) ** 2)
    want = min(math.sqrt(float(m.bmass[0]) / kt), math.sqrt(float(m.binert[0]) / kr))
    assert ifc.critical_dt(np.full(3, 1e9)) == pytest.approx(want, rel=1e-12)


def test_wall_against_a_backfill_corner():
    """Two wall blocks pressed 0.02 m (more than the rounding) into the vertical side of a
    backfill whose top surface is part of the interface too, the bed joint 0.05 m below that
    surface. The upper block's lower corner, behind the top edge, is no contact with it (the
    depth limit), so the interface pushes the wall horizontally only. Every point of the side
    is carried once (the coverage rule): the gridpoint at the top of the side by the upper
    block over the 0.05 m between the joint and the top (its top edge, normal to the wall's
    face, projects to nothing), the lower block's upper corner over the rest of that half
    edge, the bottom gridpoint's length (in the notch of the lower block's rounded corner) by
    that corner; the side carries ``kn t pen`` over its length less the three roundings of the
    blocks' corners against it (the faces are the blocks' core edges)."""
    h = 0.25
    r = 0.01  # the rounding of _model
    side = [(0.0, -h * k) for k in range(4, -1, -1)]  # x = 0, y = -1 .. 0
    top = [(h * k, 0.0) for k in range(1, 5)]  # y = 0, x = 0.25 .. 1
    xy = np.array(side + top)
    grid = SimpleNamespace(gxy=xy, gvel=np.zeros((len(xy), 2)))
    # zones at x > 0, y < 0 on the left of each edge: down the side, right to left on top
    edges = [(k + 1, k) for k in range(4)] + [(5, 4)] + [(k + 1, k) for k in range(5, 8)]
    m = _model()
    pen = 0.02
    m.add_polygon([[-0.5, -1.0], [pen, -1.0], [pen, -0.05], [-0.5, -0.05]])
    m.add_polygon([[-0.5, -0.05], [pen, -0.05], [pen, 0.5], [-0.5, 0.5]])
    ifc = I.Interface(grid, np.array(edges), m)
    fg, fb = ifc.forces(0.0)
    assert ifc.C[I.IC_NODES] == 4 and ifc.C[I.IC_CORNERS] == 2
    on = ifc.corners.sid >= 0
    assert np.all(ifc.corners.sf[..., I.F_NX][on] == pytest.approx(-1.0, abs=1e-12))
    assert np.abs(fb[:, 1]).max() < 1e-12 * np.abs(fb[:, 0]).max()
    assert fb[:, 0].sum() == pytest.approx(-KN * T * pen * (4 * h - 3 * r), rel=1e-9)
    # the top gridpoint's contact with the upper block: from its face's lower end to the top
    top_node = (ifc.nodes.sid >= 0)[:, 0] & (ifc.geo.ig[ifc.nodes.pairs[:, 0]] == 4)
    assert ifc.nodes.sf[top_node, 0, I.F_FN] == pytest.approx(KN * T * pen * (0.05 - r),
                                                              rel=1e-9)


def test_contact_opens_and_closes_again():
    """A sheared gridpoint contact that opens releases its shear spring energy; moved away
    beyond the margin the pair leaves the candidate list (rebuild), and coming back the contact
    forms again with the full normal force and no shear memory."""
    delta = 1e-4
    grid, edges = _surface(3, x0=-H)
    m = _model()
    m.add_rectangle(BW, 0.4, center=(0.0, 0.2 - delta))
    ifc = I.Interface(grid, edges, m)
    A = BF * T  # the block's flat face, within the gridpoint's tributary length
    y0 = float(m.bpos[0, 1])
    m.bvel[0] = (0.01, 0.0)
    for _ in range(3):
        ifc.forces(1e-3)
    fs = ifc.shear_force()
    assert fs == pytest.approx(3 * KS * A * 1e-5, rel=1e-9)
    m.bvel[0] = (0.0, 0.0)
    m.bpos[0, 1] = y0 + 2 * delta  # open
    fg, fb = ifc.forces(1e-3)
    assert np.abs(fb).max() == 0.0 and np.abs(fg).max() == 0.0
    assert ifc.energy["break"] == pytest.approx(0.5 * fs ** 2 / (KS * A), rel=1e-9)
    assert ifc.C[I.IC_NODES] == 0
    m.bpos[0, 1] = y0 + 1.0  # far away: the candidate pairs are rebuilt without it
    ifc.forces(1e-3)
    assert ifc.C[I.IC_REBUILD] == 1 and ifc.nodes.pairs.shape[0] == 0
    m.bpos[0, 1] = y0  # back: rebuilt, and the contact forms again
    fg, fb = ifc.forces(1e-3)
    assert ifc.C[I.IC_REBUILD] == 2 and ifc.C[I.IC_NODES] == 1
    assert fb[0, 1] == pytest.approx(KN * A * delta, rel=1e-9)
    assert fb[0, 0] == 0.0


def test_bad_edges_are_refused():
    """An interface edge that is not a zone boundary edge is an error naming it; so is an
    unknown corner share."""
    from murus.continuum import ContinuumModel, Elastic

    xy, zones = rect_mesh(2, 1, 2.0, 1.0)
    cm = ContinuumModel(xy, zones, Elastic(density=2000.0, E=1e7, nu=0.3))
    m = _model()
    m.add_rectangle(0.5, 0.5, center=(1.0, 1.25))
    with pytest.raises(I.InterfaceError) as e:
        I.Interface(cm, [[1, 4]], m)  # the inner vertical edge
    assert e.value.key == ("edges", 0)
    ifc = I.Interface(cm, [[4, 3], [5, 4]], m)  # the top edges, either orientation
    assert ifc.geo.ie.tolist() == [[4, 3], [5, 4]]
    with pytest.raises(I.InterfaceError) as e:
        I.Interface(cm, [[4, 3]], m, corner_share="grow")
    assert e.value.key == ("corner_share",) and "follow, shrink" in str(e.value)


def _layer_and_block(friction_deg=30.0):
    """A weightless elastic layer 2 m x 1 m (8 x 4 zones, fixed base, rollers on the sides,
    top at y = 0) and a 1 m x 0.5 m block (1000 kg per metre) resting on it, with the interface
    along the top; returns the pieces of the explicit loop of :func:`_run`."""
    from murus.continuum import ContinuumModel, Elastic
    from murus.continuum import _kdata as ckd
    from murus.continuum import kernels as CK
    from murus.dem._kdata import Drive

    xy, zones = rect_mesh(8, 4, 2.0, 1.0, x0=-1.0, y0=-1.0)
    cm = ContinuumModel(xy, zones, Elastic(density=2000.0, E=5.0e7, nu=0.3))
    left, right, bottom, top = sides(xy)
    cm.fix(bottom)
    cm.fix(left | right, y=False)
    be = cm.boundary_edges()
    edges = be[top[be[:, 0]] & top[be[:, 1]]]
    kn = 2.0e8
    m = Model(thickness=1.0, rounding=0.005, margin=0.05,
              joint=Joint(kn=kn, ks=kn, friction_deg=friction_deg))
    m.add_rectangle(1.0, 0.5, center=(0.1, 0.25), density=2000.0)
    ifc = I.Interface(cm, edges, m)
    dt = min(cm.stable_dt(), 0.2 * ifc.critical_dt())
    cm.P[CK.P_DT] = dt
    z = np.zeros((1, 2))
    drive = Drive(z, z, z, z)  # no base motion, no gravity on the (weightless) layer
    return SimpleNamespace(cm=cm, m=m, ifc=ifc, dt=dt, drive=drive, CK=CK,
                           grid=ckd.pack(ckd.Grid, cm), zones=ckd.pack(ckd.Zones, cm))


def _run(s, nsteps, alpha, record=None):
    """``nsteps`` central-difference steps of the layer and the block with local damping
    ``alpha``: interface forces at the positions of the step, the zones by the public kernel
    (the gridpoint reactions as applied forces, per metre: thickness 1), the block by
    ``v += dt F / m``, ``x += v dt``. ``record``: a list receiving, at each step, the energies
    at the time of the force evaluation (kinetic energies with the mean of the two half-step
    velocities)."""
    cm, m, ifc, dt, CK = s.cm, s.m, s.ifc, s.dt, s.CK
    cm.P[CK.P_ALOCAL] = alpha
    g = 9.81
    mass = float(m.bmass[0])
    m3 = np.array([mass, mass, float(m.binert[0])])
    free = cm.gfix == 0
    fg = fb = None
    for _ in range(nsteps):
        fg, fb = ifc.forces(dt)
        cm.gext[:] = fg
        CK.run_chunk(1, cm.P, cm.E, cm.C, cm.S, s.drive, s.grid, s.zones, cm.mprops, cm.part,
                     cm.ff)
        f = fb[0] + np.array([0.0, -mass * g, 0.0])
        v0 = np.array([m.bvel[0, 0], m.bvel[0, 1], m.bomg[0]])
        v1 = v0 + dt * (f - alpha * np.abs(f) * np.sign(v0)) / m3
        if record is not None:
            vm = 0.5 * (v0 + v1)
            gvm = cm.gvel - 0.5 * dt * cm.gacc
            e = ifc.energy
            record.append(0.5 * float(m3 @ vm ** 2) + mass * g * m.bpos[0, 1]
                          + 0.5 * float((cm.gmass[:, None] * gvm ** 2 * free).sum())
                          + cm.energy()["strain"] + e["stored"] + e["slip"] + e["break"])
        m.bvel[0] = v1[:2]
        m.bomg[0] = v1[2]
        m.bpos[0] += v1[:2] * dt
        m.bang[0] += v1[2] * dt
    return fg, fb


def test_block_resting_on_an_elastic_layer():
    """A rigid block on a weightless elastic layer, both integrated with central differences
    and local damping in a loop written here (:func:`_run`): at equilibrium the interface
    normal forces sum to the block's weight within 0.5 %, the gridpoints receive the opposite,
    and the block has sunk into the layer."""
    s = _layer_and_block()
    fg, fb = _run(s, 2500, 0.8)
    weight = float(s.m.bmass[0]) * 9.81
    assert s.ifc.normal_force() == pytest.approx(weight, rel=5e-3)
    assert -fg[:, 1].sum() == pytest.approx(weight, rel=5e-3)
    assert s.m.bpos[0, 1] < 0.25
    assert s.ifc.C[I.IC_NODES] == 4


def test_layer_follows_a_retreating_block_then_contact_returns():
    """The settled block is lifted slowly (a prescribed velocity) and brought back: the layer
    follows it while it rebounds (the interface force falls steadily), separates once the
    block has risen past the layer's rebound (no contact, no force: a dry joint has no
    tension), and when the block is back at its settled position the contacts have formed
    again and carry its weight (within 1 %, the same elastic equilibrium) -- the backfill
    following the wall of Savalle et al. (2022), Figure 11."""
    s = _layer_and_block()
    _run(s, 1500, 0.8)
    cm, m, ifc, dt, CK = s.cm, s.m, s.ifc, s.dt, s.CK
    weight = float(m.bmass[0]) * 9.81
    y_set = float(m.bpos[0, 1])
    sink = 0.25 - y_set  # the settlement [m]
    m.bvel[0] = 0.0
    m.bomg[0] = 0.0

    def move(n, v):
        force = []
        for _ in range(n):
            m.bvel[0, 1] = v
            fg, fb = ifc.forces(dt)
            cm.gext[:] = fg
            CK.run_chunk(1, cm.P, cm.E, cm.C, cm.S, s.drive, s.grid, s.zones, cm.mprops,
                         cm.part, cm.ff)
            m.bpos[0, 1] += v * dt
            force.append(ifc.normal_force())
        return np.array(force)

    n = 2000
    v = 2.0 * sink / (n * dt)
    up = move(n, v)
    assert up[0] == pytest.approx(weight, rel=0.01)
    assert np.all(up >= 0.0)
    assert np.all(np.diff(up[::100]) <= 0.0)  # falls steadily (quasi-static, sampled)
    assert ifc.C[I.IC_NODES] == 0 and up[-1] == 0.0
    half = up[: n // 2]
    assert half[-1] < 0.2 * weight  # mostly unloaded at half the rise (the rebound)
    move(n, -v)
    m.bpos[0, 1] = y_set
    back = move(1000, 0.0)
    assert ifc.C[I.IC_NODES] == 4
    assert back[-1] == pytest.approx(weight, rel=0.01)


def test_energy_of_a_block_sliding_on_an_elastic_layer():
    """The settled block is launched at 0.05 m/s along the layer, no damping: it slides with
    friction (20°) and stops. The total energy (block kinetic and potential, zones kinetic and
    strain, interface springs) plus the interface's slip and break dissipation stays constant
    within 1 % of the initial kinetic energy, while the slip dissipation takes most of it."""
    s = _layer_and_block(friction_deg=20.0)
    _run(s, 1500, 0.8)
    s.cm.reset_reference()
    s.ifc.E[:] = 0.0
    s.m.bvel[0, 0] = 0.05
    ke0 = 0.5 * float(s.m.bmass[0]) * 0.05 ** 2
    rec = []
    _run(s, 3000, 0.0, rec)
    tot = np.array(rec)
    assert np.abs(tot - tot[0]).max() < 0.01 * ke0
    assert s.ifc.energy["slip"] > 0.5 * ke0
    assert abs(s.m.bvel[0, 0]) < 0.5 * 0.05


def test_public_api_has_numpydoc_sections():
    """Every exported function and class of the module has its numpydoc sections (Parameters
    naming each parameter, Returns and References for functions; Attributes or Parameters for
    classes), the numba kernels included."""
    import inspect
    import re

    def section(doc, name):
        return re.search(rf"^\s*{name}\s*\n\s*-{{3,}}\s*$", doc, re.M) is not None

    seen = 0
    for name in I.__all__:
        obj = getattr(I, name)
        func = getattr(obj, "py_func", obj)
        if inspect.isclass(obj):
            if issubclass(obj, BaseException):
                continue
            doc = obj.__doc__ or ""
            assert section(doc, "Attributes") or section(doc, "Parameters"), name
            seen += 1
        elif inspect.isfunction(func):
            doc = inspect.getdoc(func) or ""
            params = [p for p in inspect.signature(func).parameters if p not in ("self", "cls")]
            assert section(doc, "Returns") and section(doc, "References"), name
            if params:
                assert section(doc, "Parameters"), name
                for p in params:
                    assert re.search(rf"^\s*(\*\*)?{p}\b", doc, re.M) or f", {p}" in doc, \
                        (name, p)
            seen += 1
    assert seen >= 9


def test_a_step_allocates_nothing():
    """Without a rebuild, a step (:func:`murus.continuum.interface.step`, run by a numba loop)
    makes no allocation of numba's runtime: the count of allocations of 1 step and of 21 steps
    is the same."""
    from numba import njit
    from numba.core.runtime import _nrt_python, rtsys

    @njit
    def loop(n, P, E, C, geo, side, bodies, shapes, jprops, c, state, work):
        for _ in range(n):
            I.step(P, E, C, geo, side, bodies, shapes, jprops, c[0], c[1], state, work)
        return 0

    grid, edges = _surface(5, h=0.1)
    m = _model()
    m.add_rectangle(0.25, 0.2, center=(0.2, 0.1 - 1e-4), angle=0.01)
    ifc = I.Interface(grid, edges, m)
    ifc.P[I.IP_DT] = 1e-4
    m.bvel[0] = (0.01, 0.0)
    args = (ifc.P, ifc.E, ifc.C, ifc.geo, I.GridSide(grid.gxy, grid.gvel), ifc.bodies,
            ifc.shapes, ifc.jprops, (ifc.nodes, ifc.corners), ifc.state, ifc.work)
    loop(1, *args)
    _nrt_python.memsys_enable_stats()
    s0 = rtsys.get_allocation_stats().alloc
    loop(1, *args)
    s1 = rtsys.get_allocation_stats().alloc
    loop(21, *args)
    s2 = rtsys.get_allocation_stats().alloc
    assert ifc.C[I.IC_NODES] + ifc.C[I.IC_CORNERS] >= 2 and ifc.C[I.IC_REBUILD] == 0
    assert s2 - s1 == s1 - s0


def test_kernels_take_at_most_twelve_arguments():
    """The interface kernels take named structures: none has more than 12 arguments, and the
    module guards its numba cache against changes of the joint law it compiles in."""
    import inspect

    from numba.core.registry import CPUDispatcher

    found = {name: obj for name, obj in vars(I).items()
             if isinstance(obj, CPUDispatcher) and obj.py_func.__module__ == I.__name__}
    assert {"step", "rebuild", "node_contacts", "corner_contacts"} <= set(found)
    assert max(len(inspect.signature(d.py_func).parameters) for d in found.values()) <= 12
    assert "_guard_cache(globals(), deps=(\"murus.dem.kernels\"" in inspect.getsource(I)

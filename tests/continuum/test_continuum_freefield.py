"""Free-field columns (issue 17, item 4): the 1D column beside a side reproduces the 1D layer
(first frequency Vs / 4H, amplification of the damped layer: closed forms of
murus.continuum.closed_forms), starts in the equilibrium of the zones it is taken from, and
acts on the main grid with ``L sigma . n`` and dashpots ``L rho Cp`` (normal), ``L rho Cs``
(tangential)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from continuum_inputs import rect_mesh, sides

from murus.continuum import ContinuumModel, Elastic
from murus.continuum import kernels as K
from murus.continuum.closed_forms import layer_transfer_rayleigh
from murus.continuum.freefield import FreeFieldError, build_free_field, freefield_step
from murus.dem._kdata import Frame

RHO, VS, NU, H = 2000.0, 100.0, 0.3, 10.0


def _model(n=20, gravity=0.0):
    G = RHO * VS * VS
    mat = Elastic(density=RHO, E=2 * G * (1 + NU), nu=NU)
    xy, zones = rect_mesh(2, n, 2.0, H)
    m = ContinuumModel(xy, zones, mat, gravity=gravity, large_strain=False)
    left, right, bottom, top = sides(xy)
    return m, np.flatnonzero(left), np.flatnonzero(right), np.flatnonzero(bottom)


def _steps(m, ff, n, vel=None, xi=0.0, f=1.0, gy=0.0):
    """n steps of the columns alone; vel(t) the base velocity (x)."""
    gff = np.zeros((m.ng, 4))
    P = m.P.copy()
    P[K.P_AMASS] = 4 * math.pi * xi * f
    P[K.P_DREL] = 1.0
    dt = P[K.P_DT]
    t = 0.0
    out = []
    top = ff.fstart[1] - 1
    for _ in range(n):
        vb = 0.0 if vel is None else vel(t)
        vh = 0.0 if vel is None else vel(t + 0.5 * dt)
        freefield_step(P, Frame(vb, 0.0, vh, 0.0, 0.0, gy, 0.0, 0.0), ff, m.mprops, gff)
        t += dt
        out.append((t, ff.fdisp[top, 0] - ff.fdisp[0, 0]))
    return np.array(out), gff


def test_column_first_frequency_is_vs_over_4h():
    m, left, right, bottom = _model()
    m.set_base(bottom)
    ff = build_free_field(m, [left])
    # first mode shape as initial velocity, base fixed
    y = ff.fy[: ff.fstart[1]]
    ff.fvel[: ff.fstart[1], 0] = 0.1 * np.sin(0.5 * np.pi * y / H)
    ff.fvel[0] = 0.0
    f1 = VS / (4 * H)
    n = int(5.0 / f1 / m.dt)
    out, _ = _steps(m, ff, n)
    t, u = out[:, 0], out[:, 1]
    k = np.flatnonzero((u[:-1] < 0) != (u[1:] < 0))[1:]
    tz = t[k] - u[k] * (t[k + 1] - t[k]) / (u[k + 1] - u[k])
    assert 0.5 / np.mean(np.diff(tz)) == pytest.approx(f1, rel=0.01)


def test_column_on_a_shaking_base_follows_the_damped_layer():
    m, left, right, bottom = _model()
    m.set_base(bottom)
    ff = build_free_field(m, [left])
    f1, xi, ub = VS / (4 * H), 0.05, 1e-3
    w = 2 * math.pi * f1
    n = int(12.0 / m.dt)
    out, _ = _steps(m, ff, n, vel=lambda tt: ub * w * math.cos(w * tt), xi=xi, f=f1)
    tail = out[:, 0] > 12.0 - 2.0 / f1
    # relative displacement top - base; the closed form gives |u_top / u_base| (absolute)
    top_abs = out[tail, 1] + ub * np.sin(w * out[tail, 0])
    got = np.abs(top_abs).max() / ub
    want = layer_transfer_rayleigh(f1, VS, H, 4 * math.pi * xi * f1, relative=True)
    assert got == pytest.approx(want, rel=0.05)


def test_column_starts_in_the_equilibrium_of_the_zones_and_loads_the_side():
    m, left, right, bottom = _model(gravity=9.81)
    m.fix(left, x=True, y=False)
    m.fix(right, x=True, y=False)
    m.fix(bottom)
    m.initial_stress_k0()
    res = m.settle(tol=1e-7)
    assert res.converged
    ff = build_free_field(m, [left, right])
    out, gff = _steps(m, ff, 2000, gy=-9.81)
    assert np.abs(ff.fvel).max() < 1e-6  # at rest: the zones' stresses hold the column
    # L sigma_xx n_x on a mid-height left gridpoint: the at-rest thrust pushes into the grid
    i = ff.fstart[0] + 10
    g = ff.fgp[i]
    sxx = 0.5 * (ff.fsig[i, 0] + ff.fsig[i - 1, 0])
    assert ff.fnrm[i, 0] == pytest.approx(-1.0)
    assert gff[g, 0] == pytest.approx(-ff.flen[i] * sxx, rel=1e-12)
    assert gff[g, 0] > 0
    # the dashpots of the main grid: L rho Cp normal, L rho Cs tangential; sides released in x
    mat = m.materials[0]
    assert m.gdash[g, 0] == pytest.approx(ff.flen[i] * RHO * mat.vp, rel=1e-12)
    assert m.gdash[g, 2] == pytest.approx(ff.flen[i] * RHO * mat.vs, rel=1e-12)
    assert m.gfix[g, 0] == 0


def test_a_side_that_is_not_vertical_is_refused():
    m, left, right, bottom = _model()
    with pytest.raises(FreeFieldError, match="vertical") as e:
        build_free_field(m, [left, bottom])
    assert e.value.key[0] == 1


def test_a_wide_layer_with_free_field_sides_moves_as_the_column():
    """Issue 17, item 7 ("free field"): a layer with free-field sides under a vertically
    propagating S wave (harmonic base motion at the first frequency, 5 % mass-proportional
    damping) moves at its sides as the 1D column, within 2 %, and as the damped layer's closed
    form within 5 %."""
    G = RHO * VS * VS
    mat = Elastic(density=RHO, E=2 * G * (1 + NU), nu=NU)
    xy, zones = rect_mesh(8, 10, 40.0, H)
    m = ContinuumModel(xy, zones, mat, gravity=0.0, large_strain=False)
    left, right, bottom, top = (np.flatnonzero(s) for s in sides(xy))
    m.set_base(bottom, x=True, y=False)
    m.fix(bottom, x=False, y=True)
    m.add_free_field([left, right])
    f1, xi, ub = VS / (4 * H), 0.05, 1e-3
    w = 2 * math.pi * f1
    tl = int(top[np.argmin(xy[top, 0])])
    tc = int(top[np.argmin(np.abs(xy[top, 0] - 20.0))])
    col_top = int(m.ff.fstart[1] - 1)

    def ff_top(model):
        return float(model.ff.fdisp[col_top, 0])

    res = m.run(12.0, velocity=lambda tt: ub * w * np.cos(w * tt), xi=xi, freq=f1,
                monitors={"side": ("gp", tl, "ux"), "centre": ("gp", tc, "ux"), "ff": ff_top},
                every=4)
    assert res.success, res.message
    tail = res.t > 12.0 - 2.0 / f1
    amp = np.abs(res["ff"][tail]).max()
    assert np.abs(res["side"][tail] - res["ff"][tail]).max() < 0.02 * amp
    assert np.abs(res["centre"][tail] - res["ff"][tail]).max() < 0.02 * amp
    want = layer_transfer_rayleigh(f1, VS, H, 4 * math.pi * xi * f1, relative=True)
    assert amp / ub == pytest.approx(want, rel=0.05)
    # the energy balance closes with the free field's work counted as external work
    e = res.values
    assert np.abs(e["energy.error"]).max() < 0.01 * np.abs(e["energy.base_work"]).max()


def test_a_side_without_its_base_gridpoint_is_refused():
    """A free-field side given without its lowest, fixed gridpoint would hang a column free
    vertically, which falls under gravity: refused with a one-line error naming the side."""
    from murus.continuum.freefield import FreeFieldError

    xy, zones = rect_mesh(4, 4, 4.0, 2.0)
    m = ContinuumModel(xy, zones, Elastic(density=2000.0, E=1e7, nu=0.3))
    left, right, bottom, top = (np.flatnonzero(s) for s in sides(xy))
    m.fix(bottom)
    m.fix(right, x=True, y=False)
    m.settle()
    side = right[np.argsort(xy[right, 1])][1:]  # the base gridpoint left out
    with pytest.raises(FreeFieldError, match="free vertically"):
        m.add_free_field([side])
    m.add_free_field([right])  # the whole side is accepted

"""Free-field lateral boundaries of the continuum: a 1D soil column beside each vertical side,
driven by the same base, coupled to the main grid through dashpots and its own stresses (as FLAC
and UDEC do).

Why: a model whose input comes from its base (a vertically propagating wave) needs lateral
boundaries that neither reflect the waves radiated by the structure nor change the motion of
the soil far from it. Rollers reflect everything; quiet dashpots alone let the sides sag and
slide, because they resist the free-field motion itself. The free field removes that defect:
each side gridpoint ``g`` (outward normal ``n``, tributary length ``L``) receives

    F = -C (v_g - v_ff) + L sigma_ff . n,    C = L rho (Cp n n^T + Cs t t^T),

with ``v_ff`` and ``sigma_ff`` the velocity and stress of a 1D column at the same height,
integrated alongside the main grid with the same base motion, gravity, damping and materials.
A wave that leaves the model meets the dashpots as at a quiet boundary; the soil far from the
structure moves as the column and feels no boundary.

The column (per unit width): nodes at the heights of the side gridpoints (bottom first),
elements between them with the material of the adjacent zone of the main grid. Kinematics of a
1D column: ``exx = 0``, ``eyy = dv/dy``, ``exy = du/dy / 2``; the stresses follow the same
law as the zones (:func:`murus.continuum.kernels._tri_stress`: elastic or Mohr-Coulomb, plane
strain with ``szz``); node forces ``(sxy, syy)`` of the element above minus that of the element
below, plus gravity; central differences with the zones' mass-proportional and local damping
(:func:`murus.continuum.kernels._grid_block`). Initial stresses are those of the adjacent zones
when the free field is attached (after the static stage, as in FLAC), so that the column starts
in the equilibrium of the main grid's side.

The main grid takes the columns through one array of its own, ``gff (ng, 4)``: the force
``L sigma_ff . n`` (x, y) [N] and the reference velocity ``v_ff`` (x, y) [m/s] of its dashpots,
written by :func:`freefield_step` before the gridpoint update; the dashpot coefficients go to
the main grid's quiet-boundary matrix ``gdash`` (so a quiet side is a free-field side whose
column stays at rest).

References
----------
Itasca FLAC, Dynamic Analysis, section "Free-field boundaries" (the 1D free-field column, its
coupling by viscous dashpots and the unbalanced forces of the free field, initial stresses
from the adjacent zones). Lysmer & Kuhlemeyer (1969) (the dashpots).
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit

from murus._jit import guard_cache as _guard_cache
from murus.continuum import kernels as K
from murus.continuum.kernels import _tri_stress
from murus.errors import MurusError

__all__ = ["FreeField", "FreeFieldError", "build_free_field", "freefield_step", "empty", "merge"]


class FreeFieldError(MurusError, ValueError):
    """A side that cannot take a free field (not vertical, no zone beside it)."""


FreeField = namedtuple("FreeField", ["fstart", "fy", "fvel", "fdisp", "fmass", "ffix", "fgp",
                                     "flen", "fnrm", "fsig", "fmat", "fstate"])
FreeField.__doc__ = """The free-field columns (``nf`` nodes over ``nc`` columns).

Attributes
----------
fstart, fy, fvel, fdisp, fmass, ffix, fgp, flen, fnrm, fsig, fmat, fstate : ndarray
    As follows.

- ``fstart (nc + 1,)`` int64: nodes of column c are ``fstart[c] .. fstart[c + 1] - 1``, bottom
  first;
- ``fy (nf,)``: height of each node [m];
- ``fvel (nf, 2)``: velocity at the half step [m/s]; ``fdisp (nf, 2)``: displacement [m];
- ``fmass (nf,)``: lumped mass per unit width [kg/m];
- ``ffix (nf, 2)`` int64: 0 free, 1 fixed, 2 moved by the base (those of the side gridpoint);
- ``fgp (nf,)`` int64: the main-grid gridpoint of each node;
- ``flen (nf,)``: its tributary length on the side [m]; ``fnrm (nf, 2)``: the side's outward
  normal;
- ``fsig (nf, 4)``: stress (sxx, syy, sxy, szz) [Pa, tension positive] of the element above
  node i (the top node's row is unused); ``fmat (nf,)`` int64: its material row;
- ``fstate (nf,)`` int64: its plastic-state bits (``ST_*`` of :mod:`murus.continuum.kernels`).
"""


def empty() -> FreeField:
    """A free field with no column (the kernels skip it)."""
    z = np.zeros
    return FreeField(np.zeros(1, np.int64), z(0), z((0, 2)), z((0, 2)), z(0),
                     np.zeros((0, 2), np.int64), np.zeros(0, np.int64), z(0), z((0, 2)),
                     z((0, 4)), np.zeros(0, np.int64), np.zeros(0, np.int64))


def merge(a: FreeField, b: FreeField) -> FreeField:
    """The columns of two free fields in one (``b``'s after ``a``'s).

    Parameters
    ----------
    a, b : FreeField
        The free fields.

    Returns
    -------
    FreeField
    """
    if a.fy.size == 0:
        return b
    if b.fy.size == 0:
        return a
    start = np.concatenate([a.fstart, b.fstart[1:] + a.fstart[-1]])
    return FreeField(start, *[np.concatenate([x, y]) for x, y in zip(a[1:], b[1:], strict=True)])


@njit(cache=True, error_model="numpy")
def freefield_step(P, fr, ff, mprops, gff):
    """Advance the free-field columns one step and write their action on the main grid.

    Parameters
    ----------
    P : ndarray
        The zones' parameters (``P_DT``, ``P_ALOCAL``, ``P_AMASS``, ``P_DREL``,
        ``P_PLASTIC`` of :mod:`murus.continuum.kernels`).
    fr : murus.dem._kdata.Frame
        The step's base velocities and gravity.
    ff : FreeField
        The columns, updated in place.
    mprops : ndarray (nmat, NM)
        Material rows.
    gff : ndarray (ng, 4)
        The main grid's free-field record, written for the gridpoints of the columns: force
        ``L sigma_ff . n`` [N] and the velocity ``v_ff`` [m/s] its dashpots act against.

    Returns
    -------
    float
        Work of the free-field columns' damping in the step [J/m] (negative).

    References
    ----------
    Itasca FLAC, Dynamic Analysis, "Free-field boundaries".
    """
    dt = P[K.P_DT]
    alocal = P[K.P_ALOCAL]
    amass = P[K.P_AMASS]
    drel = P[K.P_DREL]
    plastic = P[K.P_PLASTIC] > 0.0
    cm = 0.5 * amass * dt
    fy = ff.fy
    fvel = ff.fvel
    fsig = ff.fsig
    fmat = ff.fmat
    fstate = ff.fstate
    wd = 0.0
    for c in range(ff.fstart.size - 1):
        lo = ff.fstart[c]
        hi = ff.fstart[c + 1]
        # element stresses from the velocities of the half step
        for i in range(lo, hi - 1):
            h = fy[i + 1] - fy[i]
            eyy = (fvel[i + 1, 1] - fvel[i, 1]) / h * dt
            exy = 0.5 * (fvel[i + 1, 0] - fvel[i, 0]) / h * dt
            p = mprops[fmat[i]]
            flag = _tri_stress(fsig[i], 0.0, eyy, exy, 0.0, p[K.M_K], p[K.M_G], p, False,
                               plastic)[0]
            st = fstate[i] & ~(K.ST_SHEAR_NOW | K.ST_TENSION_NOW)
            if flag & K.R_SHEAR:
                st |= K.ST_SHEAR_NOW | K.ST_SHEAR_PAST
            if flag & K.R_TENSION:
                st |= K.ST_TENSION_NOW | K.ST_TENSION_PAST
            fstate[i] = st
        # nodes
        for i in range(lo, hi):
            m = ff.fmass[i]
            for d in range(2):
                # (sxy, syy) of the element above minus the element below
                k = 2 if d == 0 else 1
                f = 0.0
                if i < hi - 1:
                    f += fsig[i, k]
                if i > lo:
                    f -= fsig[i - 1, k]
                fix = ff.ffix[i, d]
                v0 = fvel[i, d]
                if fix == 0:
                    gg = fr.gx if d == 0 else fr.gy
                    vb = fr.vx if d == 0 else fr.vy
                    db = drel * vb
                    f += m * gg
                    fd = 0.0
                    wv = v0 - db
                    if alocal > 0.0 and wv != 0.0:
                        fd = -alocal * abs(f) * (1.0 if wv > 0.0 else -1.0)
                    v1 = (v0 * (1.0 - cm) + dt * (f + fd) / m + 2.0 * cm * db) / (1.0 + cm)
                    vm = 0.5 * (v0 + v1)
                    wd += dt * (fd - amass * m * (vm - db)) * vm
                elif fix == 1:
                    v1 = 0.0
                else:
                    v1 = fr.vhx if d == 0 else fr.vhy
                fvel[i, d] = v1
                ff.fdisp[i, d] += v1 * dt
        # the columns' action on the main grid: L sigma . n at the node (mean of the elements
        # beside it, by their lengths) and the velocity the dashpots act against
        for i in range(lo, hi):
            sxx = 0.0
            sxy = 0.0
            syy = 0.0
            wsum = 0.0
            if i < hi - 1:
                w = fy[i + 1] - fy[i]
                sxx += w * fsig[i, 0]
                sxy += w * fsig[i, 2]
                syy += w * fsig[i, 1]
                wsum += w
            if i > lo:
                w = fy[i] - fy[i - 1]
                sxx += w * fsig[i - 1, 0]
                sxy += w * fsig[i - 1, 2]
                syy += w * fsig[i - 1, 1]
                wsum += w
            sxx /= wsum
            sxy /= wsum
            syy /= wsum
            nx = ff.fnrm[i, 0]
            ny = ff.fnrm[i, 1]
            L = ff.flen[i]
            g = ff.fgp[i]
            gff[g, 0] = L * (sxx * nx + sxy * ny)
            gff[g, 1] = L * (sxy * nx + syy * ny)
            gff[g, 2] = fvel[i, 0]
            gff[g, 3] = fvel[i, 1]
    return wd


def _side_chain(xy, gridpoints, tol):
    g = np.asarray(gridpoints, np.int64)
    if g.size < 2:
        raise FreeFieldError("a free-field side needs at least two gridpoints", key=("side",))
    x = xy[g, 0]
    if np.ptp(x) > tol:
        raise FreeFieldError(f"a free-field side must be vertical: its gridpoints span "
                             f"x = {x.min():.6g} .. {x.max():.6g} m", key=("side",))
    order = np.argsort(xy[g, 1], kind="stable")
    g = g[order]
    if np.any(np.diff(xy[g, 1]) <= tol):
        raise FreeFieldError("two gridpoints of a free-field side at the same height",
                             key=("side",))
    return g


def build_free_field(model, sides, *, tol: float | None = None) -> FreeField:
    """Free-field columns beside vertical sides of a model, in the model's current state.

    Call it after the static stage (gravity settled): each column takes the stresses of the
    zones beside it and the fixities of the side gridpoints (a base gridpoint stays driven by
    the base); the side gridpoints are released horizontally (the column now carries the side),
    and the dashpots ``L rho (Cp n n^T + Cs t t^T)`` are added to the model's quiet-boundary
    matrix.

    Parameters
    ----------
    model : murus.continuum.model.ContinuumModel
        The model (its ``gdash`` and ``gfix`` are updated).
    sides : sequence of array_like of int
        The gridpoints of each vertical side (e.g. ``mesh.side("soil.left")``), any order.
    tol : float, optional
        Tolerance on "vertical" [m] (default 1e-9 times the model size).

    Returns
    -------
    FreeField

    Raises
    ------
    FreeFieldError
        A side that is not vertical, two of its gridpoints at one height, a side edge that is
        not a boundary edge of one zone, a lowest gridpoint free vertically (the column would
        fall) (key ``("side",)`` with the side's index first).
    """
    xy = model.gxy
    size = float(np.ptp(xy, axis=0).max())
    tol = 1e-9 * size if tol is None else float(tol)
    # the zone of each directed zone edge (counter-clockwise: the zone on its left)
    zg = model.zg
    edge_zone = {}
    for z in range(zg.shape[0]):
        for c in range(4):
            a, b = int(zg[z, c]), int(zg[z, (c + 1) % 4])
            edge_zone[(a, b)] = z
    zstress = model.zone_stress()
    chains = []
    for s, side in enumerate(sides):  # the geometry of every side first
        try:
            chains.append(_side_chain(xy, side, tol))
        except FreeFieldError as exc:
            raise FreeFieldError(f"side {s}: {exc}", key=(s,) + exc.key) from None
    cols = []
    for s, g in enumerate(chains):
        n = g.size
        mats = np.zeros(n, np.int64)
        sig = np.zeros((n, 4))
        nrm = np.zeros((n, 2))
        lens = np.zeros(n)
        mass = np.zeros(n)
        for i in range(n - 1):
            a, b = int(g[i]), int(g[i + 1])
            z = edge_zone.get((a, b), edge_zone.get((b, a)))
            if z is None or ((a, b) not in edge_zone) == ((b, a) not in edge_zone):
                raise FreeFieldError(f"side {s}: the edge {a}-{b} is not a boundary edge of "
                                     "one zone", key=(s, "side"))
            # outward normal: the zone is on the left of a->b when (a, b) is its edge
            d = xy[b] - xy[a]
            L = float(np.hypot(*d))
            out = np.array([d[1], -d[0]]) / L if (a, b) in edge_zone else \
                -np.array([d[1], -d[0]]) / L
            mats[i] = model.zmat[z]
            sig[i] = zstress[z]
            h = L
            rho = model.mprops[mats[i], K.M_RHO]
            mass[i] += 0.5 * rho * h
            mass[i + 1] += 0.5 * rho * h
            lens[i] += 0.5 * L
            lens[i + 1] += 0.5 * L
            nrm[i] += out
            nrm[i + 1] += out
        nrm /= np.hypot(nrm[:, 0], nrm[:, 1])[:, None]
        # the column: driven where the side is driven by the base; the bottom node keeps a
        # fixity of the side; every other node is free (the column carries itself)
        gf = model.gfix[g]
        if gf[0, 1] == 0:
            raise FreeFieldError(f"side {s}: its lowest gridpoint {int(g[0])} is free "
                                 "vertically: the column would fall under gravity (give the "
                                 "whole side, its base gridpoint included, fixed or moved by "
                                 "the base)", key=(s, "side"))
        fix = np.where(gf == 2, 2, 0).astype(np.int64)
        fix[0] = gf[0]
        cols.append((g, xy[g, 1].copy(), mass, fix, lens, nrm, sig, mats))
        # the main grid: dashpots, and the side released horizontally (not its base)
        for i in range(n):
            gi = int(g[i])
            p = model.mprops[mats[min(i, n - 2)]]
            rho = p[K.M_RHO]
            cp = math.sqrt((p[K.M_K] + 4.0 * p[K.M_G] / 3.0) / rho)
            cs = math.sqrt(p[K.M_G] / rho)
            nn = nrm[i]
            t = np.array([-nn[1], nn[0]])
            C = lens[i] * rho * (cp * np.outer(nn, nn) + cs * np.outer(t, t))
            model.gdash[gi] += (C[0, 0], C[0, 1], C[1, 1])
            for d in range(2):
                if model.gfix[gi, d] == 1:
                    model.gfix[gi, d] = 0
    fstart = np.zeros(len(cols) + 1, np.int64)
    np.cumsum([c[0].size for c in cols], out=fstart[1:])

    def cat(k, dt=float):
        return np.concatenate([c[k] for c in cols]).astype(dt)

    nf = int(fstart[-1])
    return FreeField(fstart, cat(1), np.zeros((nf, 2)), np.zeros((nf, 2)), cat(2),
                     cat(3, np.int64), cat(0, np.int64), cat(4), cat(5), cat(6),
                     cat(7, np.int64), np.zeros(nf, np.int64))


_guard_cache(globals(), deps=("murus.continuum.kernels", "murus.continuum._kdata"))

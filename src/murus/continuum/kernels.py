"""Numerical kernels of the continuum (zones) engine (numba, no I/O, no Python objects).

Discretisation (Marti & Cundall (1982); Itasca FLAC, Theory and Background, "Mixed
discretization")
---------------------------------------------------------------------------------------------
A quadrilateral zone (gridpoints 0, 1, 2, 3 counter-clockwise) is two overlays of two
constant-strain triangles: overlay A cut by the diagonal 0-2, triangles (0, 1, 2) and
(0, 2, 3); overlay B cut by 1-3, triangles (0, 1, 3) and (1, 2, 3). Each triangle has its own
stress (``zsig[z, t]``); the volumetric strain rate of the two triangles of an overlay is
replaced by their area-weighted mean (so that incompressible plastic flow does not lock), the
deviatoric part is the triangle's own. The nodal forces of a triangle are
``f_i = -(sxx b_i + sxy c_i, sxy b_i + syy c_i) / 2`` with ``b_i = y_j - y_k``,
``c_i = x_k - x_j`` (i, j, k cyclic), and each overlay's forces are halved. Masses are lumped:
each triangle gives ``rho A / 3`` to its nodes, halved per overlay. Plane strain: ``e_zz = 0``
and ``szz`` is tracked.

Large strain (default): the gridpoint coordinates move with the gridpoints each step and the
stresses are rotated with the Jaumann rate, ``sxx -= 2 w sxy dt``, ``syy += 2 w sxy dt``,
``sxy += w (sxx - syy) dt`` with the spin ``w = (dvy/dx - dvx/dy) / 2``, before the
constitutive increment (FLAC's "large-strain" mode). Small strain: coordinates fixed, no
rotation.

Constitutive update (Itasca FLAC, Constitutive Models, "Mohr-Coulomb model"; the open
implementation compared with: DynEarthSol, Choi et al. (2013), ``rheology.cxx``,
``elasto_plastic2d``, MIT licence): elastic trial ``ds = 2 G de + (K - 2 G / 3) tr(de) I`` (with
``de_zz = 0``), then :func:`mc_return`.

Time integration (central differences, as the blocks: :mod:`murus.dem.kernels`): gridpoint
velocities at the half steps; a step is the zone loop (strain increment from the velocities at
``t - dt/2``, stresses at t, the force of each zone on each of its corners ``zf[4 z + c]``) and
the gridpoint loop (gather of the corner forces through the CSR incidence ``gsp``/``gzc``,
gravity ``m g`` and applied forces, damping, fixities, velocity at ``t + dt/2``, move). Both
loops write only their own rows, so they run in parallel (numba ``prange``) with results that do
not depend on the number of threads; the gridpoint loop combines its partial sums in a fixed
order of ``NBLK`` blocks. Damping: Cundall's local non-viscous damping ``-alpha |F| sign(v)``
per direction (Cundall (1987)) and mass-proportional damping ``-alpha_M m (v - v_base)`` treated
by the central-difference average (the blocks' form, stable for any ``alpha_M dt``).
Quiet (viscous) boundaries, Lysmer & Kuhlemeyer (1969): dashpots ``rho Cp`` normal and
``rho Cs`` tangential per unit length of a boundary edge, lumped to its gridpoints as the matrix
``gdash`` (absolute velocities), their diagonal treated as the mass damping.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from murus._jit import guard_cache as _guard_cache
from murus.continuum._kdata import IG_GACC, IG_GDISP, IG_GVEL, IG_GXY
from murus.dem._kdata import Frame

# ---- material columns (rows of mprops) -------------------------------------------------------
M_K = 0  # bulk modulus [Pa]
M_G = 1  # shear modulus [Pa]
M_RHO = 2  # density [kg/m³]
M_NPHI = 3  # N_phi = (1 + sin phi) / (1 - sin phi) [-]
M_NPSI = 4  # N_psi = (1 + sin psi) / (1 - sin psi) [-]
M_CSN = 5  # 2 c sqrt(N_phi) [Pa]
M_TENS = 6  # tensile strength sigma_t (capped at c / tan phi) [Pa]
M_PLAS = 7  # 1.0: Mohr-Coulomb, 0.0: linear elastic
NM = 8

# ---- parameter vector ------------------------------------------------------------------------
P_DT = 0  # time step [s]
P_ALOCAL = 1  # local damping coefficient [-]
P_AMASS = 2  # mass-proportional damping alpha_M [1/s]
P_DREL = 3  # damping frame: 1 relative to the base motion, 0 absolute
P_LARGE = 4  # 1: large strain (coordinates updated, stresses rotated), 0: small strain
P_PLASTIC = 5  # 1: plasticity on, 0: every material elastic (elastic settling)
P_PARMIN = 6  # smallest number of zones for the parallel loops
P_QFRAME = 7  # reference of the quiet dashpots: 1 the base motion, 0 rest
NP = 8

# ---- energy accumulators ---------------------------------------------------------------------
E_WDAMP = 0  # work of the damping forces (negative) [J]
E_WBASE = 1  # work of the fixed and base-driven gridpoints on the zones [J]
E_WEXT = 2  # work of the applied forces gext [J]
E_WDASH = 3  # work of the quiet-boundary dashpots (negative) [J]
# the share of the last step's work done after the time of its stresses (``dt F . v+ / 2``):
# the energy at that time (:meth:`murus.continuum.model.ContinuumModel.energy`) subtracts it
E_TDAMP = 4
E_TBASE = 5
E_TEXT = 6
E_TDASH = 7
NE = 8

# ---- counters and statistics -----------------------------------------------------------------
C_STEP = 0
NC = 1
S_UNBAL = 0  # largest unbalanced force of a gridpoint (free directions) at the last step [N]
S_MEANF = 1  # mean over gridpoints of the sum of the magnitudes of their corner forces [N]
#              (computed with local damping on, i.e. when settling; 0 otherwise)
NS = 2

# ---- partial sums of the gridpoint blocks ----------------------------------------------------
Q_UNBAL = 0
Q_FSUM = 1
Q_NFREE = 2
Q_WDAMP = 3
Q_WBASE = 4
Q_WEXT = 5
Q_WDASH = 6
Q_TDAMP = 7
Q_TBASE = 8
Q_TEXT = 9
Q_TDASH = 10
NQ = 11

#: Blocks of the gridpoint loop (fixed, so the partial sums are combined in the same order on
#: any number of threads).
NBLK = 64

# ---- zone state bits -------------------------------------------------------------------------
ST_SHEAR_NOW = 1
ST_TENSION_NOW = 2
ST_SHEAR_PAST = 4
ST_TENSION_PAST = 8
ST_INVERTED = 16  # a triangle of the zone has a non-positive area (zone too distorted)

# ---- return flags of mc_return ---------------------------------------------------------------
R_ELASTIC = 0
R_SHEAR = 1  # bit: returned to the shear surface
R_TENSION = 2  # bit: returned to the tension cut-off (3: to the corner of both)

#: Triangles of a zone: corners (i, j, k) of overlay A (0, 1) and overlay B (2, 3).
TRI = ((0, 1, 2), (0, 2, 3), (0, 1, 3), (1, 2, 3))


@njit(cache=True, error_model="numpy", inline="always")
def _corner(s1, s2, s3, a1, a2, npsi, sp, tens):
    """Return of the principal trial stresses ``s1 <= s2 <= s3`` [Pa] to the corner of the
    shear and tension surfaces (``s1 = s_P``, ``s3 = sigma_t``) with the shear flow
    ``(1, 0, -N_psi)`` and the tension flow ``(0, 0, 1)`` (two plastic multipliers); ``s2``
    follows the flows, kept within ``[s_P, sigma_t]`` (the apex edges)."""
    A1 = a1 - a2 * npsi
    A2 = a2 * (1.0 - npsi)
    A3 = a2 - a1 * npsi
    det = A1 * a1 - a2 * A3
    r1 = s1 - sp
    r3 = s3 - tens
    ls = (r1 * a1 - a2 * r3) / det
    lt = (A1 * r3 - A3 * r1) / det
    return sp, min(max(s2 - ls * A2 - lt * a2, sp), tens), tens


@njit(cache=True, error_model="numpy", inline="always")
def mc_return(sxx, syy, sxy, szz, K, G, nphi, npsi, csn, tens):
    """Mohr-Coulomb return of a trial stress (FLAC's algorithm; plane strain with ``szz``).

    Parameters
    ----------
    sxx, syy, sxy, szz : float
        Trial stress [Pa], tension positive.
    K, G : float
        Bulk and shear moduli [Pa].
    nphi, npsi : float
        ``N_phi``, ``N_psi`` [-] (``(1 + sin a) / (1 - sin a)`` of friction and dilation).
    csn : float
        ``2 c sqrt(N_phi)`` [Pa].
    tens : float
        Tensile strength ``sigma_t`` [Pa].

    Returns
    -------
    tuple
        ``(sxx, syy, sxy, szz, flag, dwp)``: the stress on or inside the yield surface [Pa],
        the flag (``R_ELASTIC``, or the bits ``R_SHEAR``, ``R_TENSION``: 3 at their corner)
        and the plastic work density ``sigma : de_p`` of the correction [J/m³].

    Notes
    -----
    Principal stresses ``s1 <= s2 <= s3`` (tension positive) of the in-plane pair and ``szz``;
    shear yield ``f_s = s1 - s3 N_phi + 2 c sqrt(N_phi) < 0``, tension yield ``s3 > sigma_t``;
    the surface is chosen by ``h = s3 - sigma_t + a_P (s1 - s_P)`` (``h <= 0``: shear), with
    ``a_P = sqrt(1 + N_phi²) + N_phi``, ``s_P = sigma_t N_phi - 2 c sqrt(N_phi)``; shear:
    ``l = f_s / (a1 - a2 N_psi + a1 N_phi N_psi - a2 N_phi)``, ``s1 -= l (a1 - a2 N_psi)``,
    ``s2 -= l a2 (1 - N_psi)``, ``s3 -= l (a2 - a1 N_psi)``; tension: ``l = (s3 - sigma_t) /
    a1``, ``s1 -= l a2``, ``s2 -= l a2``, ``s3 -= l a1`` (``a1 = K + 4 G / 3``,
    ``a2 = K - 2 G / 3``); the principal directions are unchanged. Two additions to FLAC's
    one-surface corrections, for trial stresses far outside the surface: when the shear
    correction would reverse the order of ``s2`` and ``s3`` (or ``s1`` and ``s2``), the stress
    returns to the edge of the Mohr-Coulomb pyramid with both surfaces active (two plastic
    multipliers, Koiter's rule; de Souza Neto, Perić & Owen (2008), §8.2); when ``s2`` also
    exceeds the tensile strength after the tension correction, ``s2`` and ``s3`` both return to
    it (and ``s1`` too if it still exceeds it); when the tension correction leaves the shear
    surface violated, the stress returns to the corner of the two surfaces (``s3 = sigma_t``,
    ``s1 = s_P``).

    References
    ----------
    Itasca FLAC, Constitutive Models, section "Mohr-Coulomb model" (incremental elastic law,
    yield and potential functions, plastic corrections). DynEarthSol, Choi et al. (2013),
    ``rheology.cxx``, functions ``elasto_plastic`` and ``elasto_plastic2d`` (MIT licence).
    de Souza Neto, Perić & Owen (2008), Computational Methods for Plasticity, §8.2 (return to
    an edge of the Mohr-Coulomb surface).
    """
    c = 0.5 * (sxx + syy)
    d = 0.5 * (sxx - syy)
    r = math.sqrt(d * d + sxy * sxy)
    sa = c - r
    sb = c + r
    # order s1 <= s2 <= s3 with the position iz of szz
    if szz <= sa:
        s1 = szz
        s2 = sa
        s3 = sb
        iz = 0
    elif szz <= sb:
        s1 = sa
        s2 = szz
        s3 = sb
        iz = 1
    else:
        s1 = sa
        s2 = sb
        s3 = szz
        iz = 2
    fs = s1 - s3 * nphi + csn
    ft = s3 - tens
    if fs >= 0.0 and ft <= 0.0:
        return sxx, syy, sxy, szz, R_ELASTIC, 0.0
    return _mc_correct(s1, s2, s3, iz, fs, ft, d, r, sxy, K, G, (nphi, npsi, csn, tens))


@njit(cache=True, error_model="numpy")
def _mc_correct(s1, s2, s3, iz, fs, ft, d, r, sxy, K, G, mp):
    """The plastic correction of :func:`mc_return` (kept out of line: the zone loop inlines
    only the elastic check): principal stresses ``s1 <= s2 <= s3`` [Pa] with the position
    ``iz`` of szz, the yield functions ``fs``, ``ft`` [Pa], the in-plane half difference ``d``,
    radius ``r`` and ``sxy`` of the trial [Pa], the moduli [Pa] and ``mp = (N_phi, N_psi,
    2 c sqrt(N_phi), sigma_t)``."""
    nphi, npsi, csn, tens = mp
    a1 = K + 4.0 * G / 3.0
    a2 = K - 2.0 * G / 3.0
    ap = math.sqrt(1.0 + nphi * nphi) + nphi
    sp = tens * nphi - csn
    h = s3 - tens + ap * (s1 - sp)
    if h <= 0.0:
        # shear (FLAC): one surface, s1 - s3 N_phi + 2 c sqrt(N_phi) = 0
        A1 = a1 - a2 * npsi
        A2 = a2 * (1.0 - npsi)
        A3 = a2 - a1 * npsi
        lam = fs / (A1 - nphi * A3)
        n1 = s1 - lam * A1
        n2 = s2 - lam * A2
        n3 = s3 - lam * A3
        if n2 > n3:
            # the return crossed the edge s2 = s3: return to the edge, both surfaces
            # (s1, s3) and (s1, s2) active, flows (1, 0, -N_psi) and (1, -N_psi, 0)
            B1 = A1
            B2 = A3
            B3 = A2
            fb = s1 - s2 * nphi + csn
            m11 = A1 - nphi * A3
            m12 = B1 - nphi * B3
            m21 = A1 - nphi * A2
            m22 = B1 - nphi * B2
            det = m11 * m22 - m12 * m21
            la = (fs * m22 - m12 * fb) / det
            lb = (m11 * fb - m21 * fs) / det
            n1 = s1 - la * A1 - lb * B1
            n2 = s2 - la * A2 - lb * B2
            n3 = s3 - la * A3 - lb * B3
        elif n2 < n1:
            # the return crossed the edge s1 = s2: surfaces (s1, s3) and (s2, s3), flows
            # (1, 0, -N_psi) and (0, 1, -N_psi)
            B1 = A2
            B2 = A1
            B3 = A3
            fb = s2 - s3 * nphi + csn
            m11 = A1 - nphi * A3
            m12 = B1 - nphi * B3
            m21 = A2 - nphi * A3
            m22 = B2 - nphi * B3
            det = m11 * m22 - m12 * m21
            la = (fs * m22 - m12 * fb) / det
            lb = (m11 * fb - m21 * fs) / det
            n1 = s1 - la * A1 - lb * B1
            n2 = s2 - la * A2 - lb * B2
            n3 = s3 - la * A3 - lb * B3
        flag = R_SHEAR
        if max(n2, n3) > tens:
            # the shear correction crossed the tension cut-off: the corner
            n1, n2, n3 = _corner(s1, s2, s3, a1, a2, npsi, sp, tens)
            flag = R_SHEAR | R_TENSION
    else:
        # tension (FLAC): s3 to sigma_t; and s2 (then s1) when it also exceeds it
        lam = ft / a1
        n1 = s1 - lam * a2
        n2 = s2 - lam * a2
        n3 = tens
        if n2 > tens:
            det = a1 * a1 - a2 * a2
            l2 = (a1 * (s2 - tens) - a2 * (s3 - tens)) / det
            l3 = (a1 * (s3 - tens) - a2 * (s2 - tens)) / det
            n1 = s1 - a2 * (l2 + l3)
            n2 = tens
            if n1 > tens:
                n1 = tens
        if n1 - n3 * nphi + csn < 0.0:
            # the tension correction left the shear surface violated: the corner
            n1, n2, n3 = _corner(s1, s2, s3, a1, a2, npsi, sp, tens)
            flag = R_SHEAR | R_TENSION
        else:
            flag = R_TENSION
    d1 = s1 - n1
    d2 = s2 - n2
    d3 = s3 - n3
    s1 = n1
    s2 = n2
    s3 = n3
    # plastic work density: sigma_new : C^-1 (sigma_trial - sigma_new)
    tr = (d1 + d2 + d3) / 3.0
    k1 = 1.0 / (3.0 * K) - 1.0 / (2.0 * G)
    dwp = 0.0
    dwp += s1 * (d1 / (2.0 * G) + tr * k1)
    dwp += s2 * (d2 / (2.0 * G) + tr * k1)
    dwp += s3 * (d3 / (2.0 * G) + tr * k1)
    if iz == 0:
        sz = s1
        na = s2
        nb = s3
    elif iz == 1:
        na = s1
        sz = s2
        nb = s3
    else:
        na = s1
        nb = s2
        sz = s3
    if r > 0.0:
        cs = d / r
        sn = sxy / r
    else:
        cs = 1.0
        sn = 0.0
    c2 = 0.5 * (na + nb)
    r2 = 0.5 * (nb - na)
    return c2 + r2 * cs, c2 - r2 * cs, r2 * sn, sz, flag, dwp


@njit(cache=True, error_model="numpy")
def return_stresses(sig, mprops, mat):
    """:func:`mc_return` of each row of ``sig (n, 4)`` (sxx, syy, sxy, szz) [Pa] in place,
    with the material row ``mprops[mat]`` (``M_*`` columns).

    Parameters
    ----------
    sig : ndarray (n, 4)
        Trial stresses [Pa], replaced by the returned stresses.
    mprops : ndarray (nmat, NM)
        Material rows.
    mat : int
        The row to use.

    Returns
    -------
    tuple of ndarray
        ``(flags, dwp)``: the return flags (n,) and plastic work densities [J/m³] (n,).

    References
    ----------
    As :func:`mc_return`.
    """
    n = sig.shape[0]
    flags = np.zeros(n, np.int64)
    dwp = np.zeros(n)
    p = mprops[mat]
    for i in range(n):
        a, b, c, d, f, w = mc_return(sig[i, 0], sig[i, 1], sig[i, 2], sig[i, 3], p[M_K], p[M_G],
                                     p[M_NPHI], p[M_NPSI], p[M_CSN], p[M_TENS])
        sig[i, 0] = a
        sig[i, 1] = b
        sig[i, 2] = c
        sig[i, 3] = d
        flags[i] = f
        dwp[i] = w
    return flags, dwp


@njit(cache=True, error_model="numpy", inline="always")
def _grad(xi, yi, xj, yj, xk, yk, ui, uj, uk, vi, vj, vk):
    """Twice the area [m²] and the velocity gradient (du/dx, du/dy, dv/dx, dv/dy) [1/s] of the
    constant-strain triangle (i, j, k) with nodal velocities (u, v)."""
    bi = yj - yk
    bj = yk - yi
    bk = yi - yj
    ci = xk - xj
    cj = xi - xk
    ck = xj - xi
    a2 = (xj - xi) * (yk - yi) - (xk - xi) * (yj - yi)
    inv = 1.0 / a2
    return (a2, (ui * bi + uj * bj + uk * bk) * inv, (ui * ci + uj * cj + uk * ck) * inv,
            (vi * bi + vj * bj + vk * bk) * inv, (vi * ci + vj * cj + vk * ck) * inv)


@njit(cache=True, error_model="numpy", inline="always")
def _tri_stress(s, exx, eyy, exy, w, K, G, p, large, plastic):
    """Stress update of one triangle (row ``s`` of 4: sxx, syy, sxy, szz [Pa]) by the strain
    increments ``exx, eyy, exy`` (tensor shear) and the rotation ``w`` [rad] of the step;
    material row ``p``. Returns (flag of :func:`mc_return`, plastic work density [J/m³],
    stress work density ``(sigma_old + sigma_new) / 2 : de`` [J/m³])."""
    sxx = s[0]
    syy = s[1]
    sxy = s[2]
    szz = s[3]
    if large:
        rr = 2.0 * w * sxy
        dd = w * (sxx - syy)
        sxx -= rr
        syy += rr
        sxy += dd
    ox = sxx
    oy = syy
    oxy = sxy
    lam = K - 2.0 * G / 3.0
    ev = lam * (exx + eyy)
    sxx += 2.0 * G * exx + ev
    syy += 2.0 * G * eyy + ev
    sxy += 2.0 * G * exy
    szz += ev
    flag = R_ELASTIC
    dwp = 0.0
    if plastic and p[M_PLAS] > 0.0:
        sxx, syy, sxy, szz, flag, dwp = mc_return(sxx, syy, sxy, szz, K, G, p[M_NPHI],
                                                  p[M_NPSI], p[M_CSN], p[M_TENS])
    s[0] = sxx
    s[1] = syy
    s[2] = sxy
    s[3] = szz
    dws = 0.5 * ((ox + sxx) * exx + (oy + syy) * eyy + 2.0 * (oxy + sxy) * exy)
    return flag, dwp, dws


@njit(cache=True, error_model="numpy", inline="always")
def _iso_mean(s, t, a, b):
    """Give the stresses ``s`` and ``t`` (sxx, syy, sxy, szz [Pa]) of two triangles of areas
    ``a`` and ``b`` their area-weighted mean isotropic stress, keeping their deviators."""
    ps = (s[0] + s[1] + s[3]) / 3.0
    pt = (t[0] + t[1] + t[3]) / 3.0
    pm = (a * ps + b * pt) / (a + b)
    ds = pm - ps
    dt = pm - pt
    s[0] += ds
    s[1] += ds
    s[3] += ds
    t[0] += dt
    t[1] += dt
    t[3] += dt


@njit(cache=True, error_model="numpy", inline="always")
def _zone(z, zg, zmat, zsig, zstate, zwork, zf, gxy, gvel, mprops, P):
    """Zone ``z``: strain increments of its four triangles (mixed discretisation), stress
    update, plastic state and work, forces on its four corners (module doc)."""
    dt = P[P_DT]
    large = P[P_LARGE] > 0.0
    plastic = P[P_PLASTIC] > 0.0
    p = mprops[zmat[z]]
    K = p[M_K]
    G = p[M_G]
    n0 = zg[z, 0]
    n1 = zg[z, 1]
    n2 = zg[z, 2]
    n3 = zg[z, 3]
    x0 = gxy[n0, 0]
    y0 = gxy[n0, 1]
    x1 = gxy[n1, 0]
    y1 = gxy[n1, 1]
    x2 = gxy[n2, 0]
    y2 = gxy[n2, 1]
    x3 = gxy[n3, 0]
    y3 = gxy[n3, 1]
    u0 = gvel[n0, 0] * dt
    v0 = gvel[n0, 1] * dt
    u1 = gvel[n1, 0] * dt
    v1 = gvel[n1, 1] * dt
    u2 = gvel[n2, 0] * dt
    v2 = gvel[n2, 1] * dt
    u3 = gvel[n3, 0] * dt
    v3 = gvel[n3, 1] * dt
    # overlay A: (0, 1, 2), (0, 2, 3); overlay B: (0, 1, 3), (1, 2, 3) (displacement
    # increments of the step, so the gradients are strain increments)
    aA1, a11, a12, a21, a22 = _grad(x0, y0, x1, y1, x2, y2, u0, u1, u2, v0, v1, v2)
    aA2, b11, b12, b21, b22 = _grad(x0, y0, x2, y2, x3, y3, u0, u2, u3, v0, v2, v3)
    aB1, c11, c12, c21, c22 = _grad(x0, y0, x1, y1, x3, y3, u0, u1, u3, v0, v1, v3)
    aB2, d11, d12, d21, d22 = _grad(x1, y1, x2, y2, x3, y3, u1, u2, u3, v1, v2, v3)
    st = zstate[z] & ~(ST_SHEAR_NOW | ST_TENSION_NOW)
    if aA1 <= 0.0 or aA2 <= 0.0 or aB1 <= 0.0 or aB2 <= 0.0:
        st |= ST_INVERTED
    # mixed discretisation: area-weighted mean volumetric increment of each overlay
    evA = (aA1 * (a11 + a22) + aA2 * (b11 + b22)) / (aA1 + aA2)
    evB = (aB1 * (c11 + c22) + aB2 * (d11 + d22)) / (aB1 + aB2)
    s = zsig[z]
    # triangle 0 of A
    h = 0.5 * (evA - a11 - a22)
    f0, w0, q0 = _tri_stress(s[0], a11 + h, a22 + h, 0.5 * (a12 + a21), 0.5 * (a21 - a12), K, G, p,
                         large, plastic)
    h = 0.5 * (evA - b11 - b22)
    f1, w1, q1 = _tri_stress(s[1], b11 + h, b22 + h, 0.5 * (b12 + b21), 0.5 * (b21 - b12), K, G, p,
                         large, plastic)
    h = 0.5 * (evB - c11 - c22)
    f2, w2, q2 = _tri_stress(s[2], c11 + h, c22 + h, 0.5 * (c12 + c21), 0.5 * (c21 - c12), K, G, p,
                         large, plastic)
    h = 0.5 * (evB - d11 - d22)
    f3, w3, q3 = _tri_stress(s[3], d11 + h, d22 + h, 0.5 * (d12 + d21), 0.5 * (d21 - d12), K, G, p,
                         large, plastic)
    fl = f0 | f1 | f2 | f3
    if fl != 0:
        # mixed discretisation of a nonlinear law: the isotropic stress is constant over each
        # overlay (Marti & Cundall (1982); FLAC: "isotropic stress and strain components are
        # taken to be constant over the whole quadrilateral element"), so the two triangles
        # of an overlay, whose plastic corrections differ, take their area-weighted mean
        # pressure again (the work of this exchange is zero: both have the same volumetric
        # increment and the weighted corrections sum to zero)
        _iso_mean(s[0], s[1], aA1, aA2)
        _iso_mean(s[2], s[3], aB1, aB2)
    if fl & R_SHEAR:
        st |= ST_SHEAR_NOW | ST_SHEAR_PAST
    if fl & R_TENSION:
        st |= ST_TENSION_NOW | ST_TENSION_PAST
    zstate[z] = st
    # each triangle's volume is a2 / 2 and each overlay counts one half
    if fl != 0:
        zwork[z, 0] += 0.25 * (aA1 * w0 + aA2 * w1 + aB1 * w2 + aB2 * w3)
    zwork[z, 1] += 0.25 * (aA1 * q0 + aA2 * q1 + aB1 * q2 + aB2 * q3)
    # corner forces, -(sxx b + sxy c, sxy b + syy c) / 2 per triangle, halved per overlay
    fx0 = 0.0
    fy0 = 0.0
    fx1 = 0.0
    fy1 = 0.0
    fx2 = 0.0
    fy2 = 0.0
    fx3 = 0.0
    fy3 = 0.0
    # triangle (0, 1, 2)
    t = s[0]
    bi = y1 - y2
    bj = y2 - y0
    bk = y0 - y1
    ci = x2 - x1
    cj = x0 - x2
    ck = x1 - x0
    fx0 -= t[0] * bi + t[2] * ci
    fy0 -= t[2] * bi + t[1] * ci
    fx1 -= t[0] * bj + t[2] * cj
    fy1 -= t[2] * bj + t[1] * cj
    fx2 -= t[0] * bk + t[2] * ck
    fy2 -= t[2] * bk + t[1] * ck
    # triangle (0, 2, 3)
    t = s[1]
    bi = y2 - y3
    bj = y3 - y0
    bk = y0 - y2
    ci = x3 - x2
    cj = x0 - x3
    ck = x2 - x0
    fx0 -= t[0] * bi + t[2] * ci
    fy0 -= t[2] * bi + t[1] * ci
    fx2 -= t[0] * bj + t[2] * cj
    fy2 -= t[2] * bj + t[1] * cj
    fx3 -= t[0] * bk + t[2] * ck
    fy3 -= t[2] * bk + t[1] * ck
    # triangle (0, 1, 3)
    t = s[2]
    bi = y1 - y3
    bj = y3 - y0
    bk = y0 - y1
    ci = x3 - x1
    cj = x0 - x3
    ck = x1 - x0
    fx0 -= t[0] * bi + t[2] * ci
    fy0 -= t[2] * bi + t[1] * ci
    fx1 -= t[0] * bj + t[2] * cj
    fy1 -= t[2] * bj + t[1] * cj
    fx3 -= t[0] * bk + t[2] * ck
    fy3 -= t[2] * bk + t[1] * ck
    # triangle (1, 2, 3)
    t = s[3]
    bi = y2 - y3
    bj = y3 - y1
    bk = y1 - y2
    ci = x3 - x2
    cj = x1 - x3
    ck = x2 - x1
    fx1 -= t[0] * bi + t[2] * ci
    fy1 -= t[2] * bi + t[1] * ci
    fx2 -= t[0] * bj + t[2] * cj
    fy2 -= t[2] * bj + t[1] * cj
    fx3 -= t[0] * bk + t[2] * ck
    fy3 -= t[2] * bk + t[1] * ck
    r = 4 * z
    zf[r, 0] = 0.25 * fx0
    zf[r, 1] = 0.25 * fy0
    zf[r + 1, 0] = 0.25 * fx1
    zf[r + 1, 1] = 0.25 * fy1
    zf[r + 2, 0] = 0.25 * fx2
    zf[r + 2, 1] = 0.25 * fy2
    zf[r + 3, 0] = 0.25 * fx3
    zf[r + 3, 1] = 0.25 * fy3


#: No selection: every zone (:func:`_zones_par`, called from Python; :func:`zone_forces`
#: makes its own).
_ALL = np.zeros(0, np.int64)


@njit(cache=True, error_model="numpy", parallel=True)
def _zones_par(sel, zg, zmat, zsig, zstate, zwork, zf, gxy, gvel, mprops, P):
    """:func:`_zone` of the zones ``sel`` (empty: every zone), parallel (each zone writes only
    its own rows)."""
    n = sel.size if sel.size > 0 else zg.shape[0]
    for k in prange(n):
        z = np.int64(k)
        if sel.size > 0:
            z = sel[k]
        _zone(z, zg, zmat, zsig, zstate, zwork, zf, gxy, gvel, mprops, P)


@njit(cache=True, error_model="numpy")
def _zones_ser(sel, zg, zmat, zsig, zstate, zwork, zf, gxy, gvel, mprops, P):
    """:func:`_zones_par` on one thread."""
    n = sel.size if sel.size > 0 else zg.shape[0]
    for k in range(n):
        z = np.int64(k)
        if sel.size > 0:
            z = sel[k]
        _zone(z, zg, zmat, zsig, zstate, zwork, zf, gxy, gvel, mprops, P)


@njit(cache=True, error_model="numpy", inline="always")
def _grid_block(blk, P, fr, grid, zf, part, gsel):
    """Central-difference update of the gridpoints of block ``blk`` (of ``NBLK``): gather of
    the corner forces, gravity and applied forces, damping, fixities, move (module doc);
    ``fr`` the step's base velocities and gravity (:class:`murus.dem._kdata.Frame`);
    ``part[blk, Q_*]`` the block's partial sums; ``gsel`` the gridpoints updated (empty:
    all)."""
    gxy = grid[IG_GXY]
    gvel = grid[IG_GVEL]
    gacc = grid[IG_GACC]
    gdisp = grid[IG_GDISP]
    gmass = grid.gmass
    gfix = grid.gfix
    gext = grid.gext
    gdash = grid.gdash
    gff = grid.gff
    gsp = grid.gsp
    gzc = grid.gzc
    full = gsel.size == 0
    ng = gmass.size if full else gsel.size
    dt = P[P_DT]
    alocal = P[P_ALOCAL]
    amass = P[P_AMASS]
    drel = P[P_DREL]
    large = P[P_LARGE] > 0.0
    # the mean force of the unbalanced-force ratio: needed when settling (local damping on)
    ratio = alocal > 0.0
    cm = 0.5 * amass * dt
    lo = blk * ng // NBLK
    hi = (blk + 1) * ng // NBLK
    unbal = 0.0
    fsum = 0.0
    nfree = 0.0
    wdamp = 0.0
    wbase = 0.0
    wext = 0.0
    wdash = 0.0
    tdamp = 0.0
    tbase = 0.0
    text = 0.0
    tdash = 0.0
    for kg in range(lo, hi):
        g = kg if full else gsel[kg]
        fix_x = gfix[g, 0]
        fix_y = gfix[g, 1]
        fx = 0.0
        fy = 0.0
        fa = 0.0
        for j in range(gsp[g], gsp[g + 1]):
            r = gzc[j]
            ax = zf[r, 0]
            ay = zf[r, 1]
            fx += ax
            fy += ay
            if ratio:
                fa += math.sqrt(ax * ax + ay * ay)
        m = gmass[g]
        vx0 = gvel[g, 0]
        vy0 = gvel[g, 1]
        cxy = gdash[g, 1]
        un2 = 0.0
        for d in range(2):
            fint = fx if d == 0 else fy
            fix = fix_x if d == 0 else fix_y
            v0 = vx0 if d == 0 else vy0
            if fix == 0:
                gg = fr.gx if d == 0 else fr.gy
                vb = fr.vx if d == 0 else fr.vy
                db = drel * vb
                fe = gext[g, d] + gff[g, d]  # applied forces and the free field's stresses
                f = fint + fe + m * gg
                un2 += f * f
                fd = 0.0
                wv = v0 - db
                if alocal > 0.0 and wv != 0.0:
                    fd = -alocal * abs(f) * (1.0 if wv > 0.0 else -1.0)
                # quiet dashpots: the diagonal term on the mean velocity of the step (as the
                # mass damping), the coupling term on the other direction's half-step velocity
                # (relative to the free field's velocity on a free-field side, else to rest)
                cdd = gdash[g, 0] if d == 0 else gdash[g, 2]
                vref = gff[g, 2 + d]
                fc = -cxy * ((vy0 - gff[g, 3]) if d == 0 else (vx0 - gff[g, 2]))
                cd = 0.5 * cdd * dt / m
                v1 = ((v0 * (1.0 - cm - cd) + dt * (f + fd + fc) / m + 2.0 * cm * db
                       + 2.0 * cd * vref) / (1.0 + cm + cd))
                vm = 0.5 * (v0 + v1)
                f_damp = fd - amass * m * (vm - db)
                f_dash = fc - cdd * (vm - vref)
                wdamp += dt * f_damp * vm
                wdash += dt * f_dash * vm
                wext += dt * fe * vm
                tdamp += 0.5 * dt * f_damp * v1
                tdash += 0.5 * dt * f_dash * v1
                text += 0.5 * dt * fe * v1
            elif fix == 1:
                v1 = 0.0
            else:
                # moved by the base: its work on the zones, with the force at t and the mean
                # of the half-step velocities around t (the form in which the leapfrog's
                # kinetic energy m v- . v+ / 2 and the strain energy balance exactly)
                v1 = fr.vhx if d == 0 else fr.vhy
                wbase -= dt * fint * 0.5 * (v0 + v1)
                tbase -= 0.5 * dt * fint * v1
            gacc[g, d] = (v1 - v0) / dt
            gvel[g, d] = v1
            gdisp[g, d] += v1 * dt
            if large:
                gxy[g, d] += v1 * dt
        if fix_x == 0 or fix_y == 0:
            un = math.sqrt(un2)
            if un > unbal:
                unbal = un
            fsum += fa
            nfree += 1.0
    part[blk, Q_UNBAL] = unbal
    part[blk, Q_FSUM] = fsum
    part[blk, Q_NFREE] = nfree
    part[blk, Q_WDAMP] = wdamp
    part[blk, Q_WBASE] = wbase
    part[blk, Q_WEXT] = wext
    part[blk, Q_WDASH] = wdash
    part[blk, Q_TDAMP] = tdamp
    part[blk, Q_TBASE] = tbase
    part[blk, Q_TEXT] = text
    part[blk, Q_TDASH] = tdash


@njit(cache=True, error_model="numpy", parallel=True)
def _grid_par(P, fr, grid, zf, part, gsel):
    """:func:`_grid_block` of every block, parallel over the blocks."""
    for blk in prange(NBLK):
        _grid_block(blk, P, fr, grid, zf, part, gsel)


@njit(cache=True, error_model="numpy")
def _grid_ser(P, fr, grid, zf, part, gsel):
    """:func:`_grid_par` on one thread."""
    for blk in range(NBLK):
        _grid_block(blk, P, fr, grid, zf, part, gsel)


@njit(cache=True, error_model="numpy", inline="always")
def zone_forces(P, grid, zones, mprops, par):
    """The first half of a step: every zone's strain increments, stress update and corner
    forces ``zones.zf`` (:func:`_zone`), parallel over the zones when ``par``.

    Parameters
    ----------
    P : ndarray
        Parameters (``P_*``).
    grid : Grid
        Gridpoints (read: coordinates and half-step velocities).
    zones : Zones
        Zones, updated in place.
    mprops : ndarray (nmat, NM)
        Material rows.
    par : bool
        Run the zone loop in parallel.

    Returns
    -------
    None
    """
    # an empty selection of this function's own, not the global _ALL: a global array is a
    # read-only constant to numba, another type than the selections of zone_forces_sel, and
    # each of _zones_par and _zones_ser was compiled twice (about 35 s of CPU, cold)
    allz = np.empty(0, np.int64)
    if par:
        _zones_par(allz, zones.zg, zones.zmat, zones.zsig, zones.zstate, zones.zwork, zones.zf,
                   grid.gxy, grid.gvel, mprops, P)
    else:
        _zones_ser(allz, zones.zg, zones.zmat, zones.zsig, zones.zstate, zones.zwork, zones.zf,
                   grid.gxy, grid.gvel, mprops, P)


@njit(cache=True, error_model="numpy")
def quiet_reference(fr, gdash, gff, gsel):
    """The velocity that quiet dashpots act against, when it is the base's (``P_QFRAME`` = 1):
    ``gff[g, 2:4]`` of every gridpoint with dashpots set to the base velocity at t, ``fr.vx``,
    ``fr.vy`` (the free-field columns, stepped after, overwrite their own sides').

    Parameters
    ----------
    fr : murus.dem._kdata.Frame
        The step's base velocities and gravity.
    gdash : ndarray (ng, 3)
        Dashpot matrices of the gridpoints.
    gff : ndarray (ng, 4)
        The free field's action; columns 2 and 3 written here.
    gsel : ndarray int64
        The gridpoints concerned (empty: all).

    Returns
    -------
    None
    """
    n = gsel.size if gsel.size > 0 else gdash.shape[0]
    for k in range(n):
        g = gsel[k] if gsel.size > 0 else k
        if gdash[g, 0] != 0.0 or gdash[g, 2] != 0.0:
            gff[g, 2] = fr.vx
            gff[g, 3] = fr.vy


@njit(cache=True, error_model="numpy", inline="always")
def _combine(E, S, part):
    """The gridpoint blocks' partial sums ``part`` combined in block order into the energy
    accumulators ``E`` (the last step's shares ``E_T*`` replaced) and the statistics ``S``."""
    unbal = 0.0
    fsum = 0.0
    nfree = 0.0
    E[E_TDAMP] = 0.0
    E[E_TBASE] = 0.0
    E[E_TEXT] = 0.0
    E[E_TDASH] = 0.0
    for blk in range(NBLK):
        unbal = max(unbal, part[blk, Q_UNBAL])
        fsum += part[blk, Q_FSUM]
        nfree += part[blk, Q_NFREE]
        E[E_WDAMP] += part[blk, Q_WDAMP]
        E[E_WBASE] += part[blk, Q_WBASE]
        E[E_WEXT] += part[blk, Q_WEXT]
        E[E_WDASH] += part[blk, Q_WDASH]
        E[E_TDAMP] += part[blk, Q_TDAMP]
        E[E_TBASE] += part[blk, Q_TBASE]
        E[E_TEXT] += part[blk, Q_TEXT]
        E[E_TDASH] += part[blk, Q_TDASH]
    S[S_UNBAL] = unbal
    S[S_MEANF] = fsum / nfree if nfree > 0.0 else 0.0


@njit(cache=True, error_model="numpy", inline="always")
def grid_update(P, E, C, S, fr, grid, zf, work, par):
    """The second half of a step: the free-field columns (their action written to
    ``grid.gff``), then the gridpoints under the corner forces ``zf`` and every other force
    (:func:`_grid_block`), their partial sums combined in block order into the energies and
    statistics.

    Parameters
    ----------
    P, E, C, S : ndarray
        Parameters, energy accumulators, counters, statistics.
    fr : murus.dem._kdata.Frame
        The step's base velocities and gravity.
    grid : Grid
        Gridpoints, updated in place.
    zf : ndarray (4 nz, 2)
        Corner forces of the zones [N].
    work : tuple
        ``(part, ff, mprops, gsel)``: the partial sums ``(NBLK, NQ)``, the free-field columns
        (:mod:`murus.continuum.freefield`), the material rows and the gridpoints updated
        (int64; empty: all).
    par : bool
        Run the gridpoint loop in parallel.

    Returns
    -------
    None
    """
    part, ff, mprops, gsel = work
    if P[P_QFRAME] > 0.0:
        quiet_reference(fr, grid.gdash, grid.gff, gsel)
    if ff.fy.size > 0:
        freefield_step(P, fr, ff, mprops, grid.gff)
    if par:
        _grid_par(P, fr, grid, zf, part, gsel)
    else:
        _grid_ser(P, fr, grid, zf, part, gsel)
    _combine(E, S, part)
    C[C_STEP] += 1


@njit(cache=True, error_model="numpy", inline="always")
def grid_update_sel(P, E, S, fr, grid, zf, part, gsel):
    """The gridpoints ``gsel`` alone (none of them on a free-field side), on one thread: the
    fast partition of a subcycled step (:func:`murus.continuum.coupled.run_chunk_sub`), with
    its own energy accumulators ``E`` and statistics ``S``; the zones' step counter is not
    advanced.

    Parameters
    ----------
    P, E, S : ndarray
        Parameters (``P_DT`` the step of these gridpoints), energy accumulators, statistics.
    fr : murus.dem._kdata.Frame
        The step's base velocities and gravity.
    grid : Grid
        Gridpoints, the rows ``gsel`` updated in place.
    zf : ndarray (4 nz, 2)
        Corner forces of the zones [N] (those of every zone touching ``gsel`` current).
    part : ndarray (NBLK, NQ)
        Work array of the partial sums.
    gsel : ndarray int64
        The gridpoints (not empty).

    Returns
    -------
    None
    """
    if P[P_QFRAME] > 0.0:
        quiet_reference(fr, grid.gdash, grid.gff, gsel)
    _grid_ser(P, fr, grid, zf, part, gsel)
    _combine(E, S, part)


@njit(cache=True, error_model="numpy", inline="always")
def zone_forces_sel(P, gxy, grid, zones, mprops, sel, par):
    """:func:`zone_forces` of the zones ``sel`` only, reading the gridpoints' coordinates from
    ``gxy`` (those of the subcycled step's fast zones: their slow corners on their straight
    path, :func:`murus.continuum.coupled.run_chunk_sub`) and their velocities from ``grid``.

    Parameters
    ----------
    P : ndarray
        Parameters (``P_DT`` the step of these zones).
    gxy : ndarray (ng, 2)
        Coordinates of the gridpoints [m] (rows of the zones' corners read).
    grid : Grid
        Gridpoints (read: half-step velocities).
    zones : Zones
        Zones, the rows ``sel`` updated in place.
    mprops : ndarray (nmat, NM)
        Material rows.
    sel : ndarray int64
        The zones (not empty).
    par : bool
        Run the loop in parallel.

    Returns
    -------
    None
    """
    if par:
        _zones_par(sel, zones.zg, zones.zmat, zones.zsig, zones.zstate, zones.zwork,
                   zones.zf, gxy, grid.gvel, mprops, P)
    else:
        _zones_ser(sel, zones.zg, zones.zmat, zones.zsig, zones.zstate, zones.zwork,
                   zones.zf, gxy, grid.gvel, mprops, P)


@njit(cache=True, error_model="numpy")
def run_chunk(nsteps, P, E, C, S, drive, grid, zones, mprops, part, ff):
    """Advance ``nsteps`` central-difference steps of the zones (module doc).

    Parameters
    ----------
    nsteps : int
        Steps.
    P, E, C, S : ndarray
        Parameters, energy accumulators, counters, statistics (``P_*``, ``E_*``, ``C_*``,
        ``S_*`` fields).
    drive : murus.dem._kdata.Drive
        Step inputs, row i: base velocity at t_i (``vfull``) and t_i + dt/2 (``vhalf``) [m/s],
        gravity at t_i (``grav``) [m/s²].
    grid : murus.continuum._kdata.Grid
        Gridpoints, updated in place.
    zones : murus.continuum._kdata.Zones
        Zones, updated in place.
    mprops : ndarray (nmat, NM)
        Material rows.
    part : ndarray (NBLK, NQ)
        Work array of the partial sums of the gridpoint blocks.
    ff : murus.continuum.freefield.FreeField
        The free-field columns (none: :func:`murus.continuum.freefield.empty`), advanced
        before the gridpoints in each step.

    Returns
    -------
    int
        0 (the state is in the arrays).

    References
    ----------
    Marti & Cundall (1982); Itasca FLAC, Theory and Background (explicit finite-difference
    scheme, mixed discretisation).
    """
    par = zones.zg.shape[0] >= P[P_PARMIN]
    allg = np.zeros(0, np.int64)
    for i in range(nsteps):
        zone_forces(P, grid, zones, mprops, par)
        grid_update(P, E, C, S, _frame(i, drive), grid, zones.zf, (part, ff, mprops, allg), par)
    return 0


@njit(cache=True, error_model="numpy", inline="always")
def _frame(i, drive):
    """Row i of the step inputs (:class:`murus.dem._kdata.Drive`) as a
    :class:`murus.dem._kdata.Frame`."""
    return Frame(drive.vfull[i, 0], drive.vfull[i, 1], drive.vhalf[i, 0], drive.vhalf[i, 1],
                 drive.grav[i, 0], drive.grav[i, 1], drive.gdot[i, 0], drive.gdot[i, 1])


@njit(cache=True, error_model="numpy")
def zone_dt(gxy, zg, zmat, mprops):
    """Critical time step of each zone, ``A / (Cp L)`` [s], with A the zone's area, L the
    longest of its edges and diagonals and ``Cp = sqrt((K + 4 G / 3) / rho)`` the P-wave
    speed (Itasca FLAC, Theory and Background, "Stability of the explicit scheme": the step of
    FLAC's automatic time step before its safety factor).

    Parameters
    ----------
    gxy : ndarray (ng, 2)
        Gridpoint coordinates [m].
    zg : ndarray (nz, 4) int64
        Zones (counter-clockwise gridpoints).
    zmat : ndarray (nz,) int64
        Material row of each zone.
    mprops : ndarray (nmat, NM)
        Material rows.

    Returns
    -------
    ndarray (nz,)
        The critical step of each zone [s] (0 for an inverted zone).

    References
    ----------
    Itasca FLAC, Theory and Background; Itasca UDEC, Theory and Background (zone time step).
    """
    nz = zg.shape[0]
    out = np.empty(nz)
    for z in range(nz):
        p = mprops[zmat[z]]
        cp = math.sqrt((p[M_K] + 4.0 * p[M_G] / 3.0) / p[M_RHO])
        x0 = gxy[zg[z, 0], 0]
        y0 = gxy[zg[z, 0], 1]
        x1 = gxy[zg[z, 1], 0]
        y1 = gxy[zg[z, 1], 1]
        x2 = gxy[zg[z, 2], 0]
        y2 = gxy[zg[z, 2], 1]
        x3 = gxy[zg[z, 3], 0]
        y3 = gxy[zg[z, 3], 1]
        a = 0.5 * ((x0 * y1 - x1 * y0) + (x1 * y2 - x2 * y1) + (x2 * y3 - x3 * y2)
                   + (x3 * y0 - x0 * y3))
        l2 = max((x1 - x0) ** 2 + (y1 - y0) ** 2, (x2 - x1) ** 2 + (y2 - y1) ** 2,
                 (x3 - x2) ** 2 + (y3 - y2) ** 2, (x0 - x3) ** 2 + (y0 - y3) ** 2,
                 (x2 - x0) ** 2 + (y2 - y0) ** 2, (x3 - x1) ** 2 + (y3 - y1) ** 2)
        out[z] = a / (cp * math.sqrt(l2)) if a > 0.0 else 0.0
    return out


# numba's cache checks only this file: flush it when the structure layouts and field positions
# it compiles in change
# the free-field step, compiled into run_chunk (imported last: it reads this module's law)
from murus.continuum.freefield import freefield_step  # noqa: E402

_guard_cache(globals(), deps=("murus.continuum._kdata", "murus.dem._kdata",
                              "murus.continuum.freefield"))

"""Numba kernels for linear single-degree-of-freedom (SDOF) response. No I/O, arrays only.

Equation of motion of the oscillator relative to the ground, per unit mass:

    u'' + 2 xi omega u' + omega² u = -a_g(t)

with u the relative displacement [m], omega = 2 pi / T [rad/s], xi the damping ratio (0 <= xi < 1)
and a_g the ground acceleration [m/s²], taken as linear between samples. For such an input the
state (u, u') at the end of a step follows exactly from the state at its start and the two end
values of a_g (Nigam, N. C. and Jennings, P. C., 1969, "Calculation of response spectra from
strong-motion earthquake records", Bull. Seismol. Soc. Am. 59(2), 909-922):

    [u, u']_{i+1} = A [u, u']_i + B [a_i, a_{i+1}]

The recurrence is exact at the step ends, but a peak between two steps is missed; the kernels
therefore (1) split each record step into ``m`` sub-steps (the input stays the same linear
interpolant, so the sub-stepped recurrence is still exact) and (2) refine each interior extremum
with the cubic Hermite interpolant built from the value and its exact time derivative at both
ends of the sub-step (error O(h^4)).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["nj_coefficients", "sdof_peaks", "sdof_history"]


@njit(cache=True)
def nj_coefficients(omega, xi, h):
    """Nigam-Jennings (1969) matrices A, B for one step h [s]; returns 8 floats
    (a11, a12, a21, a22, b11, b12, b21, b22) for u'' + 2 xi omega u' + omega² u = -a_g."""
    sq = math.sqrt(1.0 - xi * xi)
    wd = omega * sq
    e = math.exp(-xi * omega * h)
    s = math.sin(wd * h)
    c = math.cos(wd * h)
    r = xi / sq
    a11 = e * (r * s + c)
    a12 = e * s / wd
    a21 = -omega / sq * e * s
    a22 = e * (c - r * s)
    w2 = omega * omega
    w3 = w2 * omega
    k1 = (2.0 * xi * xi - 1.0) / (w2 * h)
    k2 = 2.0 * xi / (w3 * h)
    b11 = e * ((k1 + xi / omega) * s / wd + (k2 + 1.0 / w2) * c) - k2
    b12 = -e * (k1 * s / wd + k2 * c) - 1.0 / w2 + k2
    b21 = e * ((k1 + xi / omega) * (c - r * s) - (k2 + 1.0 / w2) * (wd * s + xi * omega * c)) + (
        1.0 / (w2 * h)
    )
    b22 = -e * (k1 * (c - r * s) - k2 * (wd * s + xi * omega * c)) - 1.0 / (w2 * h)
    return a11, a12, a21, a22, b11, b12, b21, b22


@njit(cache=True)
def _hermite_peak(y0, y1, d0, d1, h):
    """max |y| on [0, h] of the cubic Hermite interpolant of (y0, d0), (y1, d1); only called when
    the derivative changes sign, i.e. when an interior extremum exists."""
    c1 = h * d0
    c2 = 3.0 * (y1 - y0) - 2.0 * h * d0 - h * d1
    c3 = 2.0 * (y0 - y1) + h * d0 + h * d1
    best = max(abs(y0), abs(y1))
    # p'(tau) = c1 + 2 c2 tau + 3 c3 tau^2
    qa = 3.0 * c3
    qb = 2.0 * c2
    qc = c1
    if abs(qa) < 1e-300:
        if qb != 0.0:
            tau = -qc / qb
            if 0.0 < tau < 1.0:
                p = y0 + tau * (c1 + tau * (c2 + tau * c3))
                best = max(best, abs(p))
        return best
    disc = qb * qb - 4.0 * qa * qc
    if disc < 0.0:
        return best
    sd = math.sqrt(disc)
    for sign in (-1.0, 1.0):
        tau = (-qb + sign * sd) / (2.0 * qa)
        if 0.0 < tau < 1.0:
            p = y0 + tau * (c1 + tau * (c2 + tau * c3))
            best = max(best, abs(p))
    return best


@njit(cache=True)
def sdof_peaks(acc, dt, omegas, xi, substeps, refine=True):
    """Peak responses of linear SDOF oscillators to a piecewise-linear ground acceleration.

    acc [m/s²] sampled at dt [s]; omegas [rad/s] (> 0); xi damping ratio in [0, 1);
    substeps[j] >= 1 sub-steps per record step for oscillator j. Starts from rest; the record is
    followed by nothing (append zeros beforehand for free vibration).
    Returns (sd [m], sv [m/s], sa [m/s²]): max |u|, max |u'|, max |u'' + a_g| (absolute
    acceleration), each refined between sub-steps by cubic Hermite interpolation when
    ``refine`` (else sampled at the sub-steps only, the classical step-sampled spectrum).
    """
    nper = omegas.size
    n = acc.size
    sd = np.zeros(nper)
    sv = np.zeros(nper)
    sa = np.zeros(nper)
    for j in range(nper):
        w = omegas[j]
        m = substeps[j]
        h = dt / m
        a11, a12, a21, a22, b11, b12, b21, b22 = nj_coefficients(w, xi, h)
        tw = 2.0 * xi * w
        w2 = w * w
        u = 0.0
        v = 0.0
        ag = acc[0]
        # state derivatives at the current node
        rel = -ag - tw * v - w2 * u  # u''
        absa = -(tw * v + w2 * u)  # u'' + a_g
        pd = 0.0
        pv = 0.0
        pa = abs(absa)
        inv_m = 1.0 / m
        for i in range(n - 1):
            a0 = acc[i]
            da = (acc[i + 1] - a0) * inv_m
            for k in range(m):
                ag1 = a0 + da * (k + 1)
                un = a11 * u + a12 * v + b11 * ag + b12 * ag1
                vn = a21 * u + a22 * v + b21 * ag + b22 * ag1
                reln = -ag1 - tw * vn - w2 * un
                absn = -(tw * vn + w2 * un)
                # displacement: derivative v
                x = abs(un)
                if refine and v * vn < 0.0:
                    x = _hermite_peak(u, un, v, vn, h)
                if x > pd:
                    pd = x
                # relative velocity: derivative u''
                x = abs(vn)
                if refine and rel * reln < 0.0:
                    x = _hermite_peak(v, vn, rel, reln, h)
                if x > pv:
                    pv = x
                # absolute acceleration: derivative -(2 xi w u'' + w² u')
                d0 = -(tw * rel + w2 * v)
                d1 = -(tw * reln + w2 * vn)
                x = abs(absn)
                if refine and d0 * d1 < 0.0:
                    x = _hermite_peak(absa, absn, d0, d1, h)
                if x > pa:
                    pa = x
                u = un
                v = vn
                ag = ag1
                rel = reln
                absa = absn
        sd[j] = pd
        sv[j] = pv
        sa[j] = pa
    return sd, sv, sa


@njit(cache=True)
def sdof_history(acc, dt, omega, xi):
    """Relative displacement u [m] and velocity u' [m/s] at the record samples (from rest)."""
    n = acc.size
    u = np.zeros(n)
    v = np.zeros(n)
    a11, a12, a21, a22, b11, b12, b21, b22 = nj_coefficients(omega, xi, dt)
    for i in range(n - 1):
        u[i + 1] = a11 * u[i] + a12 * v[i] + b11 * acc[i] + b12 * acc[i + 1]
        v[i + 1] = a21 * u[i] + a22 * v[i] + b21 * acc[i] + b22 * acc[i + 1]
    return u, v


@njit(cache=True)
def _substep_peak(u, v, a0, a1, m, c, h, refine):
    """max |u| over one record step split into m sub-steps of length h (coefficients c for h),
    from the state (u, v) at its start and the end values a0, a1 of the ground acceleration."""
    a11, a12, a21, a22, b11, b12, b21, b22 = c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]
    best = 0.0
    da = (a1 - a0) / m
    ag = a0
    for k in range(m):
        ag1 = a0 + da * (k + 1)
        un = a11 * u + a12 * v + b11 * ag + b12 * ag1
        vn = a21 * u + a22 * v + b21 * ag + b22 * ag1
        x = abs(un)
        if refine and v * vn < 0.0:
            x = _hermite_peak(u, un, v, vn, h)
        if x > best:
            best = x
        u = un
        v = vn
        ag = ag1
    return best


@njit(cache=True)
def nj_columns(omegas, xi, dt):
    """The eight Nigam-Jennings coefficients of every oscillator, one array per coefficient."""
    nper = omegas.size
    C = np.empty((8, nper))
    for j in range(nper):
        cs = nj_coefficients(omegas[j], xi, dt)
        for r in range(8):
            C[r, j] = cs[r]
    return C[0], C[1], C[2], C[3], C[4], C[5], C[6], C[7]


@njit(cache=True)
def _sd_single_step(acc, dt, omegas, xi, refine):
    """max |u| [m] for oscillators advanced by the record step only (no sub-steps)."""
    nper = omegas.size
    n = acc.size
    c0, c1, c2, c3, c4, c5, c6, c7 = nj_columns(omegas, xi, dt)
    herm = 1.0 if refine else 0.0
    u = np.zeros(nper)
    v = np.zeros(nper)
    un = np.zeros(nper)
    vn = np.zeros(nper)
    pd = np.zeros(nper)
    flag = np.zeros(nper)
    for i in range(n - 1):
        a0 = acc[i]
        a1 = acc[i + 1]
        for j in range(nper):
            uj = u[j]
            vj = v[j]
            x = c0[j] * uj + c1[j] * vj + c4[j] * a0 + c5[j] * a1
            y = c2[j] * uj + c3[j] * vj + c6[j] * a0 + c7[j] * a1
            un[j] = x
            vn[j] = y
            pd[j] = max(pd[j], abs(x))
            # an interior extremum when the velocity changes sign: Hermite refinement
            flag[j] = herm if vj * y < 0.0 else 0.0
        for j in range(nper):
            if flag[j] != 0.0:
                z = _hermite_peak(u[j], un[j], v[j], vn[j], dt)
                if z > pd[j]:
                    pd[j] = z
        u, un = un, u
        v, vn = vn, v
    return pd


@njit(cache=True)
def _sd_substepped(acc, dt, omegas, xi, substeps, refine):
    """max |u| [m] for oscillators with substeps[j] > 1: advanced by the record step, a step
    being sub-stepped only when the bound of :func:`sdof_sd_peaks` allows a new peak in it."""
    nper = omegas.size
    n = acc.size
    S = np.empty((nper, 8))
    c0, c1, c2, c3, c4, c5, c6, c7 = nj_columns(omegas, xi, dt)
    iw2 = np.empty(nper)
    q = np.empty(nper)
    xw = np.empty(nper)
    iwd = np.empty(nper)
    for j in range(nper):
        w = omegas[j]
        cs = nj_coefficients(w, xi, dt / substeps[j])
        for r in range(8):
            S[j, r] = cs[r]
        iw2[j] = 1.0 / (w * w)
        q[j] = 2.0 * xi / (w * w * w)
        xw[j] = xi * w
        iwd[j] = 1.0 / (w * math.sqrt(1.0 - xi * xi))
    u = np.zeros(nper)
    v = np.zeros(nper)
    un = np.zeros(nper)
    vn = np.zeros(nper)
    pd = np.zeros(nper)
    flag = np.zeros(nper)
    inv_dt = 1.0 / dt
    for i in range(n - 1):
        a0 = acc[i]
        a1 = acc[i + 1]
        dd = a1 - a0
        g = dd * inv_dt
        for j in range(nper):
            uj = u[j]
            vj = v[j]
            x = c0[j] * uj + c1[j] * vj + c4[j] * a0 + c5[j] * a1
            y = c2[j] * uj + c3[j] * vj + c6[j] * a0 + c7[j] * a1
            un[j] = x
            vn[j] = y
            p = max(pd[j], abs(x))
            pd[j] = p
            up0 = g * q[j] - a0 * iw2[j]  # particular solution at both ends of the step
            up1 = up0 - dd * iw2[j]
            uh = uj - up0  # free oscillation: amplitude² r2
            ww = (vj + g * iw2[j] + xw[j] * uh) * iwd[j]
            r2 = uh * uh + ww * ww
            d = p - max(abs(up0), abs(up1))
            flag[j] = 1.0 if (d <= 0.0 or r2 > d * d) else 0.0
        for j in range(nper):
            if flag[j] != 0.0:
                m = substeps[j]
                z = _substep_peak(u[j], v[j], a0, a1, m, S[j], dt / m, refine)
                if z > pd[j]:
                    pd[j] = z
        u, un = un, u
        v, vn = vn, v
    return pd


def sdof_sd_peaks(acc, dt, omegas, xi, substeps, refine=True):
    """Peak relative displacement max |u| [m] only (for PSA = omega² SD), same result as the SD
    of :func:`sdof_peaks` (same recurrence, sub-steps and Hermite refinement) but faster:

    - all oscillators advance together, one record step at a time (independent dependency
      chains that the processor overlaps; the inner loops make no calls);
    - the state is advanced by the record step, and a step of an oscillator with
      ``substeps[j]`` > 1 is sub-stepped only if a new peak may lie inside it. Within a step
      the exact response is u(s) = u_p(s) + u_h(s), with u_p the particular solution for the
      linear input (u_p = -a(s)/omega² + 2 xi a'/omega³, linear in s) and u_h a damped free
      oscillation of amplitude at most R = sqrt(u_h0² + ((v_h0 + xi omega u_h0)/omega_d)²);
      when max|u_p| + R <= the peak so far, the step cannot hold a new peak and is skipped.

    Arguments as :func:`sdof_peaks` (numpy arrays; ``substeps`` int64). Returns sd [m].
    """
    acc = np.ascontiguousarray(acc, dtype=np.float64)
    omegas = np.ascontiguousarray(omegas, dtype=np.float64)
    substeps = np.ascontiguousarray(substeps, dtype=np.int64)
    out = np.empty(omegas.size)
    short = substeps > 1
    if short.any():
        out[short] = _sd_substepped(acc, float(dt), omegas[short], float(xi), substeps[short],
                                    bool(refine))
    if (~short).any():
        out[~short] = _sd_single_step(acc, float(dt), omegas[~short], float(xi), bool(refine))
    return out

"""Numerical kernels of the rigid body on a no-tension elastic (Winkler) layer (numba, no I/O).

The model, its sign convention and the derivation of the equations of motion are written once in
the docstring of :mod:`murus.rocking.winkler`; this module only evaluates them.

State ``y = (v, theta, v', theta', D, W)``: vertical displacement of the base centre [m], rotation
[rad] (clockwise positive), their rates, the energy dissipated by the layer's damping ``D`` [J]
and the work ``W`` [J] of the inertial forces of the ground motion (both carried as quadratures so
that the energy balance ``T + V + U + D - W = const`` can be checked).

The contact force per unit length of base is ``t_w q(xi)``, with ``q = max(0, k delta + c
delta')`` where the layer is compressed (``delta > 0``) and 0 elsewhere; ``delta`` and ``q`` are
linear in the body coordinate ``xi``, so the pressure is a linear function on one interval and all
resultants are integrated in closed form (:func:`contact`).

Integrator: adaptive explicit Dormand-Prince 5(4) (Dormand and Prince 1980; the tableau of
``kernels.dp_step``), stepping on the breakpoints of the input (``kernels.segment_end``); output on
a uniform grid by quintic Hermite interpolation (``kernels.hermite5``); crossings of
``theta = 0``, half-cycle peaks and overturning (``|theta| = pi/2``) located inside the step.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from murus._jit import guard_cache as _guard_cache
from murus.rocking import kernels as K
from murus.rocking.summary import WINKLER_SUMMARY, slots

# ---- the model parameters: one record of a structured dtype --------------------------------
#: The parameters read by the kernels, declared once: (field, units, description); the kernels
#: read them by name (``P.m``), :data:`PARAM_DTYPE` is built from this table.
PARAMS = (
    ("m", "kg", "mass"),
    ("ig", "kg m2", "moment of inertia about G"),
    ("zg", "m", "height of G above the base"),
    ("hb", "m", "half width b/2"),
    ("tw", "m", "out-of-plane width of the contact"),
    ("k", "N/m3", "layer stiffness per unit area"),
    ("c", "N s/m3", "layer damping per unit area"),
    ("g", "m/s2", "gravity"),
    ("kin", "-", "horizontal kinematics code (KIN_* below)"),
    ("dsc", "m", "penetration scale for the error control (static settlement m g / (k t_w b))"),
    ("wsc", "rad/s", "circular frequency scale for the velocity error"),
    ("spare_11", "-", "unused"),
)
PARAM_DTYPE = np.dtype([(name, np.float64) for name, _, _ in PARAMS])

# horizontal kinematics codes
KIN_CENTRE = 0  # base centre fixed
KIN_CORNER = 1  # corner on the rotation side fixed


def new_params() -> np.void:
    """A zeroed parameter record (:data:`PARAMS`); fields are set by name."""
    return np.zeros(1, PARAM_DTYPE)[0]


# ---- state -----------------------------------------------------------------------------------
Y_V = 0
Y_TH = 1
Y_VD = 2
Y_OM = 3
Y_D = 4
Y_W = 5
NY = 6

# ---- columns of the output history -------------------------------------------------------------
O_V = 0  # [m]
O_TH = 1  # [rad]
O_VD = 2  # [m/s]
O_OM = 3  # [rad/s]
O_D = 4  # dissipated by the layer's damping [J]
O_W = 5  # work of the ground's inertial forces [J]
O_F = 6  # contact resultant [N]
O_LC = 7  # contact length [m]
O_XP = 8  # centre of pressure, body coordinate [m] (nan without contact)
O_QMAX = 9  # largest contact pressure [Pa]
O_U = 10  # elastic energy of the layer [J]
O_THDD = 11  # angular acceleration [rad/s2]
O_SIZE = 12

# ---- slots of the summary vector: declared once in murus.rocking.summary.WINKLER_SUMMARY ---
_SLOT = slots(WINKLER_SUMMARY)
S_THETA_MAX = _SLOT["theta_max"]  # max |theta| [rad]
S_THETA_AT_MAX = _SLOT["theta_signed_max"]  # signed theta at the max
S_T_THETA_MAX = _SLOT["t_theta_max"]
S_OVERTURNED = _SLOT["overturned"]
S_T_OVERTURN = _SLOT["t_overturn"]
S_N_CROSS = _SLOT["n_crossings"]  # crossings of theta = 0
S_N_PEAKS = _SLOT["n_peaks"]  # half-cycle peaks
S_F_MAX = _SLOT["peak_contact_force"]  # largest contact resultant [N] (at step ends)
S_T_F_MAX = _SLOT["t_peak_contact_force"]
S_Q_MAX = _SLOT["peak_pressure"]  # largest contact pressure [Pa] (at step ends)
S_THDD_MAX = _SLOT["peak_angular_acceleration"]  # largest |theta''| [rad/s2] (at step ends)
S_LC_MIN = _SLOT["min_contact_length"]  # smallest contact length [m]
S_STATUS = _SLOT["status"]  # 0 ok, 1 step size underflow, 2 step budget exhausted
S_N_STEPS = _SLOT["n_steps"]
S_T_FINAL = _SLOT["t_final"]
S_N_REJECT = _SLOT["n_rejected"]
S_SIZE = len(WINKLER_SUMMARY)

HALF_PI = 0.5 * math.pi

# The Dormand-Prince 5(4) tableau of both rocking engines (:mod:`murus.rocking.kernels`)
_C = K.DP_C
_A = K.DP_A
_E = K.DP_E


# ========================================================================= contact ======
@njit(cache=True, inline="always")
def positive_part(c0, c1, lo, hi):
    """The interval of ``xi`` in ``[lo, hi]`` where ``c0 + c1 xi > 0`` (empty: ``(lo, lo)``)."""
    a = lo
    b = hi
    if c1 > 0.0:
        a = max(lo, -c0 / c1)
    elif c1 < 0.0:
        b = min(hi, -c0 / c1)
    elif c0 <= 0.0:
        return lo, lo
    if b <= a:
        return lo, lo
    return a, b


@njit(cache=True, inline="always")
def moments(a, b):
    """``int_a^b xi^n dxi`` for n = 0, 1, 2 (factored against cancellation)."""
    L = b - a
    return L, 0.5 * L * (a + b), L * (a * a + a * b + b * b) / 3.0


@njit(cache=True, inline="always")
def contact(v, th, vd, om, P):
    """Closed-form resultants of the contact pressure on the base.

    With ``delta = -v + xi sin(theta)`` (penetration) and ``delta' = -v' + xi cos(theta) theta'``,
    ``q = k delta + c delta'`` on the interval where both ``delta > 0`` and ``q > 0``.

    Returns ``(F, Mx, Lc, qmax, U, Dp)``: resultant ``F = t_w int q dxi`` [N], first moment
    ``Mx = t_w int q xi dxi`` [N m], contact length [m], largest pressure [Pa], elastic energy
    ``U = k t_w / 2 int_{delta>0} delta^2 dxi`` [J], and dissipation rate ``Dp`` [W]: ``c t_w
    int delta'^2`` on the active interval plus ``-k t_w int delta delta'`` where the layer is
    compressed but the body leaves it faster than the damper lets it recover (``q`` clipped at
    0; there ``delta' < -k delta / c < 0``, so both parts are >= 0)."""
    hb = P.hb
    k = P.k
    c = P.c
    tw = P.tw
    s = math.sin(th)
    co = math.cos(th)
    d0 = -v
    d1 = s
    e0 = -vd
    e1 = co * om
    q0 = k * d0 + c * e0
    q1 = k * d1 + c * e1
    a1, b1 = positive_part(d0, d1, -hb, hb)  # compressed zone
    if b1 <= a1:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    m0, m1, m2 = moments(a1, b1)
    U = 0.5 * k * tw * (d0 * d0 * m0 + 2.0 * d0 * d1 * m1 + d1 * d1 * m2)
    if c == 0.0:
        a = a1
        b = b1
        n0 = m0
        n1 = m1
        n2 = m2
        Dp = 0.0
    else:
        a, b = positive_part(q0, q1, a1, b1)  # active zone
        n0, n1, n2 = moments(a, b)
        Dp = c * tw * (e0 * e0 * n0 + 2.0 * e0 * e1 * n1 + e1 * e1 * n2)
        ca, cb = positive_part(-q0, -q1, a1, b1)  # compressed but released
        if cb > ca:
            r0, r1, r2 = moments(ca, cb)
            Dp -= k * tw * (d0 * e0 * r0 + (d0 * e1 + d1 * e0) * r1 + d1 * e1 * r2)
    if b <= a:
        return 0.0, 0.0, 0.0, 0.0, U, Dp
    F = tw * (q0 * n0 + q1 * n1)
    Mx = tw * (q0 * n1 + q1 * n2)
    qmax = max(q0 + q1 * a, q0 + q1 * b, 0.0)
    return F, Mx, b - a, qmax, U, Dp


@njit(cache=True, inline="always")
def lever(th, side, P):
    """Horizontal kinematics of the base: ``x_G = X(theta) + z_G sin(theta)``; returns
    ``A = dx_G/dtheta`` and ``A' = d2x_G/dtheta2``. ``X = 0`` (base centre fixed) or
    ``X = (b/2) side (1 - cos theta)`` (the corner on the side of the rotation fixed), where
    ``side = sgn(theta)`` is carried by the integrator so that each step sees one smooth branch
    (``A'`` jumps at ``theta = 0``)."""
    zg = P.zg
    s = math.sin(th)
    co = math.cos(th)
    A = zg * co
    Ap = -zg * s
    if P.kin == KIN_CORNER:
        A += P.hb * side * s
        Ap += P.hb * side * co
    return A, Ap


@njit(cache=True, inline="always")
def side_of(th):
    return 1.0 if th >= 0.0 else -1.0


@njit(cache=True)
def rates(t, tm, y, drv, P, side, out):
    """Time derivative of the state (the 2x2 Lagrange equations of :mod:`murus.rocking.winkler`,
    solved in closed form) written into ``out``."""
    gh, gv = K.ground(t, tm, drv)
    m = P.m
    zg = P.zg
    ge = P.g + gv
    v = y[Y_V]
    th = y[Y_TH]
    vd = y[Y_VD]
    om = y[Y_OM]
    s = math.sin(th)
    co = math.cos(th)
    F, Mx, _, _, _, Dp = contact(v, th, vd, om, P)
    A, Ap = lever(th, side, P)
    Mtt = P.ig + m * (A * A + zg * zg * s * s)
    dMtt = 2.0 * m * (A * Ap + zg * zg * s * co)
    Mvt = -m * zg * s
    rv = -m * ge + F + m * zg * co * om * om
    rt = m * ge * zg * s + m * gh * A - co * Mx - 0.5 * dMtt * om * om
    det = m * Mtt - Mvt * Mvt
    out[Y_V] = vd
    out[Y_TH] = om
    out[Y_VD] = (Mtt * rv - Mvt * rt) / det
    out[Y_OM] = (m * rt - Mvt * rv) / det
    out[Y_D] = Dp
    out[Y_W] = m * gh * A * om - m * gv * (vd - zg * s * om)


@njit(cache=True)
def evaluate(P, drv, t, y):
    """Rates of the state ``y`` at time ``t`` (a convenience for tests and static checks)."""
    out = np.empty(NY)
    rates(t, t, y, drv, P, side_of(y[Y_TH]), out)
    return out


# ======================================================================= integrator ======
@njit(cache=True)
def dp_step(t, y, h, tm, drv, P, side, ks, ytmp):
    """One Dormand-Prince 5(4) step from ``y`` with ``ks[0] = f(t, y)``; leaves the stages in
    ``ks`` (``ks[6] = f(t + h, y_new)``), the new state in ``ytmp`` and returns nothing."""
    for st in range(1, 7):
        for i in range(NY):
            acc = 0.0
            for j in range(st):
                acc += _A[st, j] * ks[j, i]
            ytmp[i] = y[i] + h * acc
        rates(t + _C[st] * h, tm, ytmp, drv, P, side, ks[st])


@njit(cache=True, inline="always")
def penetration(y, P):
    """Largest penetration of the base [m] (negative when lifted)."""
    e = P.hb * abs(math.sin(y[Y_TH]))
    return -y[Y_V] + e


@njit(cache=True)
def error_norm(h, y, yn, ks, rtol, P):
    """Scaled error of the step: the error of the penetration anywhere on the base
    (``|e_v| + b/2 |e_theta|``) against ``rtol`` times the larger of the static settlement and
    the current penetration, and of its rate against the same times the vertical frequency."""
    ev = 0.0
    et = 0.0
    evd = 0.0
    eom = 0.0
    for j in range(7):
        w = _E[j]
        ev += w * ks[j, Y_V]
        et += w * ks[j, Y_TH]
        evd += w * ks[j, Y_VD]
        eom += w * ks[j, Y_OM]
    hb = P.hb
    sc = rtol * max(P.dsc, penetration(y, P), penetration(yn, P))
    e_pos = h * (abs(ev) + hb * abs(et)) / sc
    e_vel = h * (abs(evd) + hb * abs(eom)) / (sc * P.wsc)
    return max(e_pos, e_vel)


@njit(cache=True, inline="always")
def cubic(u, h, y0, d0, y1, d1):
    """Cubic Hermite interpolation (value) at fraction ``u`` of a step ``h``."""
    u2 = u * u
    u3 = u2 * u
    return ((2.0 * u3 - 3.0 * u2 + 1.0) * y0 + (u3 - 2.0 * u2 + u) * h * d0
            + (3.0 * u2 - 2.0 * u3) * y1 + (u3 - u2) * h * d1)


@njit(cache=True)
def interp_state(u, h, y, yn, k0, k6, out):
    """State at fraction ``u`` of the step: quintic Hermite for ``v, theta`` (and their rates),
    cubic Hermite for the energy quadratures."""
    out[Y_V], out[Y_VD] = K.hermite5(u, h, y[Y_V], y[Y_VD], k0[Y_VD], yn[Y_V], yn[Y_VD],
                                     k6[Y_VD])
    out[Y_TH], out[Y_OM] = K.hermite5(u, h, y[Y_TH], y[Y_OM], k0[Y_OM], yn[Y_TH], yn[Y_OM],
                                      k6[Y_OM])
    out[Y_D] = cubic(u, h, y[Y_D], k0[Y_D], yn[Y_D], k6[Y_D])
    out[Y_W] = cubic(u, h, y[Y_W], k0[Y_W], yn[Y_W], k6[Y_W])


@njit(cache=True)
def theta_root(level, h, y, yn, k0, k6):
    """Fraction ``u`` where ``theta - level`` of the interpolant changes sign (the shared
    bisection :func:`murus.rocking.kernels.hermite_bisect`; the sign differs at the two
    ends)."""
    f0 = y[Y_TH] - level
    sense = 1.0 if f0 > 0.0 else (-1.0 if f0 < 0.0 else 0.0)
    _, hi = K.hermite_bisect(sense, level, 1e-14, h, y[Y_TH], y[Y_OM], k0[Y_OM], yn[Y_TH],
                             yn[Y_OM], k6[Y_OM])
    return hi


@njit(cache=True)
def write_output(j, tj, yj, drv, P, side, out, kbuf):
    """One row of the output history at time ``tj``."""
    for i in range(NY):
        out[j, i] = yj[i]
    F, Mx, Lc, qm, U, _ = contact(yj[Y_V], yj[Y_TH], yj[Y_VD], yj[Y_OM], P)
    out[j, O_F] = F
    out[j, O_LC] = Lc
    out[j, O_XP] = Mx / F if F > 0.0 else np.nan
    out[j, O_QMAX] = qm
    out[j, O_U] = U
    rates(tj, tj, yj, drv, P, side, kbuf)
    out[j, O_THDD] = kbuf[Y_OM]


@njit(cache=True)
def new_summary():
    S = np.zeros(S_SIZE)
    S[S_T_OVERTURN] = np.nan
    S[S_LC_MIN] = np.inf
    return S


@njit(cache=True)
def locate_crossing(t, y, h, tm, drv, P, side, ks, yn):
    """Step size ``tau`` in (0, h] at which ``theta`` reaches 0: first guess from the Hermite
    interpolant of the accepted step, then Newton iterations on fresh steps of size ``tau``
    (whose derivative is ``theta'`` itself) inside the kept bracket. Leaves the step of size
    ``tau`` in ``ks`` and ``yn``."""
    lo = 0.0
    hi = h
    tau = theta_root(0.0, h, y, yn, ks[0], ks[6]) * h
    for _ in range(40):
        dp_step(t, y, tau, tm, drv, P, side, ks, yn)
        f = side * yn[Y_TH]
        if f > 0.0:
            lo = tau
        else:
            hi = tau
        if f == 0.0:
            break
        d = side * yn[Y_OM]
        nt = tau - f / d if d != 0.0 else 0.5 * (lo + hi)
        if not (nt > lo and nt < hi):
            nt = 0.5 * (lo + hi)
        if abs(nt - tau) <= 1e-15 * (1.0 + t) or hi - lo <= 1e-15 * (1.0 + t):
            tau = nt
            break
        tau = nt
    dp_step(t, y, tau, tm, drv, P, side, ks, yn)
    return tau


@njit(cache=True)
def winkler_core(P, drv, t_end, y0, rtol, out_dt, out, zc, pk, max_steps):
    """Integrate one history from the state ``y0`` to ``t_end``.

    The history is written on the grid ``j * out_dt`` into ``out`` (rows: time, columns ``O_*``;
    zero rows: no history). Crossings of ``theta = 0`` are located (each step ends on them, where
    the kinematic branch switches) and logged into ``zc`` (rows ``t, theta', v``); the extreme
    rotation of each half cycle between crossings goes into ``pk`` (rows ``t, theta``; the first
    row is the initial half cycle), up to their capacity; the summary counts them all. Returns
    the summary vector."""
    S = new_summary()
    nzc = zc.shape[0]
    npk = pk.shape[0]
    nout = out.shape[0]
    ks = np.zeros((7, NY))
    y = y0.copy()
    yn = np.zeros(NY)
    yi = np.zeros(NY)
    kbuf = np.zeros(NY)
    t = 0.0
    h = 0.05 / P.wsc
    steps = 0
    rejects = 0
    j = 0
    side = side_of(y[Y_TH])
    if y[Y_TH] == 0.0 and y[Y_OM] != 0.0:
        side = side_of(y[Y_OM])
    ext_v = y[Y_TH]  # extreme of the current half cycle
    ext_t = 0.0
    S[S_THETA_MAX] = abs(y[Y_TH])
    S[S_THETA_AT_MAX] = y[Y_TH]
    over = False
    flipped = False
    while t < t_end:
        if steps + rejects >= max_steps:
            S[S_STATUS] = 2.0
            break
        tb = K.segment_end(t, drv, t_end)
        tm = 0.5 * (t + tb)
        if y[Y_TH] != 0.0:
            side = side_of(y[Y_TH])
        rates(t, tm, y, drv, P, side, ks[0])
        if y[Y_TH] == 0.0 and not flipped:
            # leaving theta = 0: the branch of the motion (theta'' does not depend on it when
            # theta' = 0)
            if y[Y_OM] != 0.0:
                side = side_of(y[Y_OM])
            elif ks[0, Y_OM] != 0.0:
                side = side_of(ks[0, Y_OM])
        hmax = tb - t
        hh = min(h, hmax)
        if hh >= hmax * (1.0 - 1e-12):
            hh = hmax
        if hh <= 1e-14 * (1.0 + t):
            S[S_STATUS] = 1.0
            break
        dp_step(t, y, hh, tm, drv, P, side, ks, yn)
        err = error_norm(hh, y, yn, ks, rtol, P)
        if not (err <= 1.0):
            rejects += 1
            fac = 0.9 * err ** (-0.2) if err == err else 0.1
            h = hh * max(0.1, fac)
            continue
        fac = 0.9 * err ** (-0.2) if err > 0.0 else 5.0
        h_next = hh * min(5.0, max(0.2, fac))
        crossing = False
        if side * yn[Y_TH] < 0.0:
            if y[Y_TH] == 0.0:
                if not flipped:  # left theta = 0 on the other side: retry on that branch
                    side = -side
                    flipped = True
                    continue
            else:
                hh = locate_crossing(t, y, hh, tm, drv, P, side, ks, yn)
                yn[Y_TH] = 0.0
                crossing = True
        flipped = False
        steps += 1
        # overturning: |theta| reaches pi/2 inside the step
        if abs(yn[Y_TH]) >= HALF_PI:
            lev = HALF_PI if yn[Y_TH] > 0.0 else -HALF_PI
            u = theta_root(lev, hh, y, yn, ks[0], ks[6])
            while j < nout and j * out_dt <= t + u * hh:
                uj = max(0.0, (j * out_dt - t) / hh)
                interp_state(uj, hh, y, yn, ks[0], ks[6], yi)
                write_output(j, j * out_dt, yi, drv, P, side, out, kbuf)
                j += 1
            t = t + u * hh
            S[S_OVERTURNED] = 1.0
            S[S_T_OVERTURN] = t
            S[S_THETA_MAX] = HALF_PI
            S[S_THETA_AT_MAX] = lev
            S[S_T_THETA_MAX] = t
            over = True
            while j < nout:
                for i in range(O_SIZE):
                    out[j, i] = np.nan
                out[j, O_TH] = lev
                j += 1
            break
        # interior extremum of theta (theta' changes sign)
        if y[Y_OM] * yn[Y_OM] < 0.0:
            sg = 1.0 if y[Y_OM] > 0.0 else -1.0
            up = K.hermite_root_omega(sg, hh, y[Y_TH], y[Y_OM], ks[0, Y_OM], yn[Y_TH], yn[Y_OM],
                                      ks[6, Y_OM])
            yp, _ = K.hermite5(up, hh, y[Y_TH], y[Y_OM], ks[0, Y_OM], yn[Y_TH], yn[Y_OM],
                               ks[6, Y_OM])
            if abs(yp) > abs(ext_v):
                ext_v = yp
                ext_t = t + up * hh
            if abs(yp) > S[S_THETA_MAX]:
                S[S_THETA_MAX] = abs(yp)
                S[S_THETA_AT_MAX] = yp
                S[S_T_THETA_MAX] = t + up * hh
        if abs(yn[Y_TH]) > abs(ext_v):
            ext_v = yn[Y_TH]
            ext_t = t + hh
        if abs(yn[Y_TH]) > S[S_THETA_MAX]:
            S[S_THETA_MAX] = abs(yn[Y_TH])
            S[S_THETA_AT_MAX] = yn[Y_TH]
            S[S_T_THETA_MAX] = t + hh
        if crossing:
            ic = int(S[S_N_CROSS])
            if ic < nzc:
                zc[ic, 0] = t + hh
                zc[ic, 1] = yn[Y_OM]
                zc[ic, 2] = yn[Y_V]
            S[S_N_CROSS] = ic + 1
            ip = int(S[S_N_PEAKS])
            if ip < npk:
                pk[ip, 0] = ext_t
                pk[ip, 1] = ext_v
            S[S_N_PEAKS] = ip + 1
            ext_v = 0.0
            ext_t = t + hh
        # contact extremes at the end of the step
        F, _, Lc, qm, _, _ = contact(yn[Y_V], yn[Y_TH], yn[Y_VD], yn[Y_OM], P)
        if F > S[S_F_MAX]:
            S[S_F_MAX] = F
            S[S_T_F_MAX] = t + hh
        S[S_Q_MAX] = max(S[S_Q_MAX], qm)
        S[S_THDD_MAX] = max(S[S_THDD_MAX], abs(ks[6, Y_OM]))
        S[S_LC_MIN] = min(S[S_LC_MIN], Lc)
        # history on the output grid
        while j < nout and j * out_dt <= t + hh:
            uj = max(0.0, (j * out_dt - t) / hh)
            interp_state(uj, hh, y, yn, ks[0], ks[6], yi)
            write_output(j, j * out_dt, yi, drv, P, side, out, kbuf)
            j += 1
        at_break = hh >= hmax
        t = t + hh if not at_break else tb
        for i in range(NY):
            y[i] = yn[i]
        h = h_next
        if crossing:
            side = -side
    if not over:
        # the last half cycle
        ip = int(S[S_N_PEAKS])
        if ip < npk:
            pk[ip, 0] = ext_t
            pk[ip, 1] = ext_v
        S[S_N_PEAKS] = ip + 1
        while j < nout:  # grid points beyond the last step by round-off only
            write_output(j, t, y, drv, P, side, out, kbuf)
            j += 1
    S[S_N_STEPS] = steps
    S[S_N_REJECT] = rejects
    S[S_T_FINAL] = t
    return S


# numba's cache checks only this file: flush it when the kernels it inlines or the summary
# layout change
_guard_cache(globals(), deps=("murus.rocking.kernels", "murus.rocking.summary"))

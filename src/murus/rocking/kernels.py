"""Numerical kernels of the rigid-block rocking engine (numba, no I/O, no Python objects).

State machine shared by both integrators
----------------------------------------
The active pivot ``s`` is part of the state: ``0`` at rest, ``+1`` rocking about the right corner O
(``theta >= 0``), ``-1`` about the left corner O' (``theta <= 0``); overturning ends the run. The
pivot is never ``sign(theta)``, which is undefined at ``theta = 0``.

- rest -> rocking: when the moment about a corner at ``theta = 0``, ``theta' = 0`` turns the body
  away from the base (Mordant et al. (SERIES) eq. 9: ``m a_g H > m g B/2`` for the top-mass wall),
  in the direction of that moment; the instant is located inside the step by root finding;
- rocking -> impact: ``theta`` crosses zero; the instant is located inside the step, the angular
  velocity is multiplied by the coefficient of restitution and the pivot switches to ``-s``;
- impact -> rest: at the accumulation point of the cascade of ever smaller impacts (a Zeno
  point), never before. Once the velocity after an impact is below ``rest_tol * p * alpha`` (free
  rocking and bounces against rigid transverse walls alike), the rest of the cascade is summed
  instead of integrated (:func:`cascade_end`): the bounce times form a geometric series whose
  limit is the instant the body comes to rest; the body is put at rest there, and only if the
  ground cannot lift it over the cascade and as long again after it (lift margins at every input
  breakpoint of that window); otherwise the integration goes on;
- rocking -> overturned: ``|theta|`` reaches ``pi/2``.

Equation of motion (Mordant et al. (SERIES) eq. 5, EURODYN (2020) eq. 1), a sum of moment terms
about the active
pivot, ``I_O theta'' = M_gravity + M_ground (+ further terms)``::

    M_gravity = -m (g + a_v) R sin(s alpha - theta)
    M_ground  = +m a_g R cos(s alpha - theta)

Sign convention: ``theta > 0`` clockwise; a positive ``a_g`` drives a positive rotation (EURODYN
(2020) eq. 1, where the ground term stands on the right-hand side with a plus sign); ``a_v`` is
positive upward, so that it adds to gravity. The linearised option replaces ``sin x`` by ``x`` and
``cos x`` by 1 (the equation of the closed-form overturning solutions).

Named data: the model parameters are one record ``P`` of :data:`PARAM_DTYPE` (fields declared
once in :data:`PARAMS`, read by name, codes compared by name: ``PIVOT_*``, ``E_*``, ``TIE_*``,
``X_*``); the excitation is a :class:`Drive` and what a run writes a :class:`Log` (named tuples
numba compiles); the summary slots ``S_*`` come from the declared table
:data:`murus.rocking.summary.SUMMARY`.

A new moment term touches two places and the integrators never change: this module (its
parameters as rows of :data:`PARAMS`, its moment in :func:`restraint_terms`) and its class in
:mod:`murus.rocking.restraints` (validation and ``fill``, which writes those parameters; the model
that carries it calls ``fill`` like the tie's). Both rocking engines (this one and
:mod:`murus.rocking.winkler_kernels`) share one Dormand-Prince tableau (:data:`DP_A`, ...) and
one Hermite bisection (:func:`hermite_bisect`); :func:`lever` serves the Python side too
(:func:`levers`).

References
----------
Mordant, Dietz & Degée (SERIES shaking-table tests), "Mordant et al. (SERIES)" below.
EURODYN (2020), "Mitigation of amplified response of restrained rocking walls through horizontal
dampers", doi:10.47964/1120.9351.20156.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit, prange

from murus._jit import guard_cache as _guard_cache
from murus.rocking.summary import SUMMARY, slots

# ---- the model parameters: one record of a structured dtype ------------------------------
#: The parameters read by the kernels, declared once: (field, units, description). The kernels
#: read them by name (``P.m``); :data:`PARAM_DTYPE` is built from this table, in this order (the
#: byte layout of the flat 40-slot vector of earlier versions, so that a study's cache key, the
#: bytes of the record, is unchanged). A new moment term declares its parameters here.
PARAMS = (
    ("i_o", "kg m2", "moment of inertia about the corner pivot"),
    ("m", "kg", "mass"),
    ("r", "m", "corner to centre of gravity"),
    ("alpha", "rad", "slenderness angle"),
    ("g", "m/s2", "gravity"),
    ("linear", "-", "1: linearised equation"),
    ("e_kind", "-", "restitution law code (E_* below)"),
    ("e", "-", "restitution value of the constant law"),
    ("rest_tol", "-", "rest threshold, relative to p * alpha"),
    ("ig", "kg m2", "moment of inertia about the centre of gravity"),
    ("zg", "m", "height of the centre of gravity"),
    ("hb", "m", "half base width b/2"),
    ("pivot", "-", "pivot law code (PIVOT_* below)"),
    ("pivot_min", "m", "smallest pivot lever"),
    ("pivot_factor", "-", "factor on the ground acceleration of the equivalent static load"),
    ("terms", "-", "1: restraint terms present (tie, spring bed, damper)"),
    ("tie_mode", "-", "tie code (TIE_* below)"),
    ("tie_k", "N/m", "tie stiffness"),
    ("tie_y", "m", "tie height above the base"),
    ("tie_x", "m", "tie anchor, horizontal body coordinate from the base centre"),
    ("tie_p0", "N", "pretension"),
    ("tie_fy", "N", "yield force (inf: elastic)"),
    ("tie_dp", "m", "plastic elongation (state of the run: kernels work on a copy)"),
    ("bed_k", "N/m/m", "spring bed stiffness per unit height (0: none)"),
    ("bed_z1", "m", "spring bed from height z1 ..."),
    ("bed_z2", "m", "... to z2"),
    ("bed_x", "m", "spring bed face, horizontal body coordinate (side of pivot -1)"),
    ("dmp_c", "N s/m", "damper coefficient (0: none)"),
    ("dmp_y", "m", "damper height"),
    ("dmp_x", "m", "damper anchor, horizontal body coordinate"),
    ("e_k0", "-", "coefficient law e = 1 - (k0 + k1 r) sin^2(alpha_n) during the input ..."),
    ("e_k1", "-", "..."),
    ("e_k0f", "-", "... and with (k0f, k1f) in free vibration "
     "(Mordant et al. (SERIES), eq. 17)"),
    ("e_k1f", "-", "..."),
    ("e_free", "-", "1: a distinct free-vibration law"),
    ("e_aspect", "-", "factor on the energy lost at an impact (Mordant et al. (SERIES), "
     "eq. 18; 1: off)"),
    ("e_absmax", "rad", "iterated variant of eq. 16: largest rotation of the whole run "
     "(0: causal)"),
    ("stop", "-", "1: rigid transverse walls, the wall bounces at theta = 0"),
    ("spare_38", "-", "unused"),
    ("spare_39", "-", "unused"),
)
PARAM_DTYPE = np.dtype([(name, np.float64) for name, _, _ in PARAMS])
_PARAM_NAMES = frozenset(PARAM_DTYPE.names)
_PARAM_ZEROS = (0.0,) * len(PARAM_DTYPE.names)


def params_record(values: dict) -> np.void:
    """The parameter record of the fields ``values`` (name -> number; the others 0), built at
    once. A name that is not a field of :data:`PARAMS` raises ``KeyError``."""
    unknown = values.keys() - _PARAM_NAMES
    if unknown:
        raise KeyError(f"not a rocking kernel parameter: {', '.join(sorted(unknown))}")
    return np.array([tuple(map(values.get, PARAM_DTYPE.names, _PARAM_ZEROS))], PARAM_DTYPE)[0]


def new_params() -> np.void:
    """A zeroed parameter record (:data:`PARAMS`); fields are set by name, ``P["m"] = ...``."""
    return np.zeros(1, PARAM_DTYPE)[0]


# restitution law codes
E_CONSTANT = 0  # P.e at every impact (constant and Housner on the corner)
E_MOMENTUM = 1  # angular momentum about the new pivot with the current levers (eq. 13)
E_COEFFICIENT = 2  # 1 - (k0 + k1 r) sin^2(alpha_n) (eqs. 14-17)

# pivot law codes (lever of the weight about the pivot, Mordant et al. (SERIES) §3.3.1)
PIVOT_CORNER = 0  # b/2 (Housner)
PIVOT_KERN = 1  # b/6
PIVOT_EFFECTIVE = 2  # Lc / 2, Lc the compressed length of the linear distribution
PIVOT_NEUTRAL = 3  # b - 3e, the zero-stress point of the linear distribution

# tie codes
TIE_NONE = 0
TIE_TENSION = 1  # tension only
TIE_BOTH = 2  # tension and compression

# ---- layout of the excitation vector X ---------------------------------------------------
X_KIND = 0  # 0: sampled record (piecewise linear), 1: harmonic pulse
X_DT = 1  # record time step [s]
X_T0 = 2  # pulse start [s]
X_AMP = 3  # pulse amplitude [m/s2]
X_OMEGA = 4  # pulse circular frequency [rad/s]
X_PHASE = 5  # pulse phase [rad]: a = A sin(omega (t - t0) + phase)
X_DUR = 6  # pulse duration [s]
X_PIECE = 7  # pulse subdivision for the scan of uplift at rest [s]
X_INV_DT = 8  # 1 / record time step [1/s]
X_SIZE = 10

# excitation kinds
X_RECORD = 0
X_PULSE = 1


class Drive(NamedTuple):
    """The excitation of one run, read by every kernel (a named tuple numba compiles): ``X``
    the excitation vector (``X_*`` slots), ``ag`` and ``av`` the horizontal and vertical records
    [m/s2] (``av`` empty: none; both empty for a pulse or free vibration)."""

    X: np.ndarray
    ag: np.ndarray
    av: np.ndarray


class Log(NamedTuple):
    """What a run writes (a named tuple numba compiles): the summary ``S`` (``S_*`` slots), the
    law memory ``mem`` (``MEM_*``), the histories on the output grid ``th``, ``om``, ``pv``
    (length 0: none), impacts ``imp`` (rows t, omega before, omega after), uplift intervals
    ``up`` (rows start, end) and peaks ``pk`` (rows t, theta), each up to its capacity."""

    S: np.ndarray
    mem: np.ndarray
    th: np.ndarray
    om: np.ndarray
    pv: np.ndarray
    imp: np.ndarray
    up: np.ndarray
    pk: np.ndarray

# ---- slots of the summary vector: declared once in :data:`murus.rocking.summary.SUMMARY` ---
_SLOT = slots(SUMMARY)
S_THETA_MAX = _SLOT["theta_max"]  # max |theta| [rad]
S_THETA_AT_MAX = _SLOT["theta_signed_max"]  # signed theta at the max [rad]
S_T_THETA_MAX = _SLOT["t_theta_max"]  # time of the max [s]
S_N_IMPACTS = _SLOT["n_impacts"]
S_T_UPLIFT = _SLOT["t_uplift"]  # first uplift [s] (nan: never)
S_OVERTURNED = _SLOT["overturned"]  # 1.0 if overturned
S_T_OVERTURN = _SLOT["t_overturn"]  # [s] (nan)
S_T_EXCEED_ALPHA = _SLOT["t_exceed_alpha"]  # first |theta| > alpha [s] (nan)
S_E_DISSIPATED = _SLOT["energy_dissipated"]  # energy lost at impacts [J]
S_N_UPLIFTS = _SLOT["n_uplifts"]
S_STATUS = _SLOT["status"]  # 0 ok, 1 step size underflow, 2 step budget exhausted
S_N_STEPS = _SLOT["n_steps"]
S_T_FINAL = _SLOT["t_final"]
S_THETA_POS = _SLOT["theta_pos"]  # max theta [rad]
S_THETA_NEG = _SLOT["theta_neg"]  # min theta [rad]
S_N_PEAKS = _SLOT["n_peaks"]
S_SIZE = len(SUMMARY)

# ---- law memory (state carried by history-dependent laws of later issues) ----------------
MEM_HALF_MAX = 0  # max |theta| since the last impact
MEM_ABS_MAX = 1  # max |theta| so far
MEM_T_FREE = 2  # end of the input: free vibration after it [s]
MEM_SIZE = 4

HALF_PI = 0.5 * math.pi
CASCADE_BOUNCES = 16  # bounces of a cascade summed one by one before the closed-form tail


# ======================================================================== excitation ======
@njit(cache=True, inline="always")
def continuous_at(tb, drv):
    """Whether the input is continuous at the breakpoint ``tb`` (records: everywhere but at
    their last sample; pulses: everywhere but at their start and end)."""
    X = drv.X
    if X[X_KIND] == X_RECORD:
        return tb < (drv.ag.shape[0] - 1) * X[X_DT] * (1.0 - 1e-12)
    eps = 1e-12 * (1.0 + tb)
    return X[X_T0] + eps < tb < X[X_T0] + X[X_DUR] - eps


@njit(cache=True, inline="always")
def ground(t, tm, drv):
    """Ground acceleration (horizontal, vertical) [m/s2] at time ``t`` in the segment that
    contains ``tm`` (so that a discontinuous input takes the value of that segment)."""
    X = drv.X
    if X[X_KIND] == X_RECORD:
        ag = drv.ag
        av = drv.av
        idt = X[X_INV_DT]
        n = ag.shape[0]
        k = int(tm * idt)  # tm >= 0: truncation is the floor
        if k < 0 or k >= n - 1:
            return 0.0, 0.0
        u = t * idt - k
        h = ag[k] + u * (ag[k + 1] - ag[k])
        v = 0.0
        if av.shape[0] == n:
            v = av[k] + u * (av[k + 1] - av[k])
        return h, v
    t0 = X[X_T0]
    if tm < t0 or tm > t0 + X[X_DUR]:
        return 0.0, 0.0
    return X[X_AMP] * math.sin(X[X_OMEGA] * (t - t0) + X[X_PHASE]), 0.0


@njit(cache=True, inline="always")
def segment_end(t, drv, t_end):
    """The next breakpoint of the input strictly after ``t`` (or ``t_end``)."""
    X = drv.X
    eps = 1e-12 * (1.0 + abs(t))
    if X[X_KIND] == X_RECORD:
        n = drv.ag.shape[0]
        dt = X[X_DT]
        k = int(math.floor(t * X[X_INV_DT]))
        cand = (k + 1) * dt
        if cand <= t + eps:
            cand = (k + 2) * dt
        if cand > (n - 1) * dt + eps:
            cand = t_end
        return min(cand, t_end)
    t0 = X[X_T0]
    t1 = t0 + X[X_DUR]
    if t < t0 - eps:
        return min(t0, t_end)
    if t < t1 - eps:
        piece = X[X_PIECE]
        k = int(math.floor((t - t0) / piece))
        cand = t0 + (k + 1) * piece
        if cand <= t + eps:
            cand = t0 + (k + 2) * piece
        return min(cand, t1, t_end)
    return t_end


# ======================================================================= moment terms =====
@njit(cache=True, inline="always")
def lever(ag, av, P):
    """Lever arm of the weight about the active pivot [m] (Mordant et al. (SERIES) §3.3.1, eqs.
    11-12).

    The corner law gives ``b/2``. The compressive-length laws place the pivot where the linear
    no-tension stress block of the equivalent static load puts it: eccentricity
    ``e = f |a_g| z_G / (g + a_v)`` (``f``: ``P.pivot_factor``), compressed length
    ``Lc = B`` for ``e <= B/6``, else ``3 (B/2 - e)`` (EN 1996-1-1, :mod:`murus.eurocode.ec6`),
    and the lever is ``B/6`` (kern), ``Lc/2`` (effective width) or ``B - 3e`` (zero-stress point,
    neutral axis), bounded to ``[P.pivot_min, B/2]``."""
    hb = P.hb
    code = P.pivot
    if code == PIVOT_CORNER:
        return hb
    B = 2.0 * hb
    if code == PIVOT_KERN:
        bl = B / 6.0
    else:
        e = P.pivot_factor * abs(ag) * P.zg / (P.g + av)
        lc = B if e <= B / 6.0 else 3.0 * (hb - e)
        bl = 0.5 * lc if code == PIVOT_EFFECTIVE else lc - hb
    return min(hb, max(P.pivot_min, bl))


@njit(cache=True)
def levers(ag, av, P):
    """:func:`lever` at every sample of the ground accelerations ``ag``, ``av`` [m/s2] (arrays
    of one length): the formula of the kernel, for the Python side (:meth:`Pivot.lever
    <murus.rocking.restraints.Pivot.lever>`, the rocking criterion of a result)."""
    out = np.empty(ag.shape[0])
    for i in range(ag.shape[0]):
        out[i] = lever(ag[i], av[i], P)
    return out


@njit(cache=True, inline="always")
def inertia(bl, P):
    """Moment of inertia about a pivot of lever ``bl`` [kg m2] (parallel axes)."""
    if P.pivot == PIVOT_CORNER:
        return P.i_o
    return P.ig + P.m * (bl * bl + P.zg * P.zg)


@njit(cache=True, inline="always")
def _bed_moment(ct, st, s, bl, P):
    """Moment of a no-tension spring bed of stiffness ``k'`` per unit height on the face at body
    coordinate ``x_b`` over heights ``[z1, z2]`` (the transverse walls of EURODYN (2020), eqs. 3-6).

    A face point at height ``z`` (pivot frame ``x0 = x_b - s b``) moves horizontally by
    ``x0 (cos th - 1) + z sin th``; the bed is compressed by ``c(z) = x0 (1 - cos th) - z sin th``
    where positive and pushes back with ``k' c``, at the lever ``y(z) = z cos th - x0 sin th``.
    The moment ``int k' c y dz`` over the compressed part is integrated in closed form. For the
    bed on the pivot's face (``x0 = 0``) it is ``k' (z2^3 - z1^3)/3 sin(-th) cos th``, the term of
    REFERENCE.md; EURODYN (2020) eq. 6 is ``-cos th`` times this integral for a bed at the distance
    ``s`` from the pivot over ``[0, h']`` (its ``B`` term needs a factor ``s``), a difference of
    order ``th^2`` at the tiny rotations a stiff bed allows (tests/rocking/test_restraints.py)."""
    x0 = P.bed_x - s * bl
    a0 = x0 * (1.0 - ct)
    a1 = -st
    z1 = P.bed_z1
    z2 = P.bed_z2
    if a1 == 0.0:
        if a0 <= 0.0:
            return 0.0
    else:
        zc = -a0 / a1  # c(z) = 0
        if a1 > 0.0:
            z1 = max(z1, zc)
        else:
            z2 = min(z2, zc)
    if z2 <= z1:
        return 0.0
    y0 = -x0 * st
    y1 = ct
    c1 = y0 * a1 + y1 * a0
    c2 = y1 * a1
    F2 = y0 * a0 * z2 + 0.5 * c1 * z2 * z2 + c2 * z2 * z2 * z2 / 3.0
    F1 = y0 * a0 * z1 + 0.5 * c1 * z1 * z1 + c2 * z1 * z1 * z1 / 3.0
    return P.bed_k * (F2 - F1)


@njit(cache=True, inline="always")
def tie_force(d, P):
    """Tie force [N] (tension positive) at the outward displacement ``d`` [m] of its anchor:
    pretension plus ``K (d - d_p)``, none in compression for a tension-only tie, bounded by the
    yield force (``d_p``: plastic elongation so far)."""
    f = P.tie_p0 + P.tie_k * (d - P.tie_dp)
    fy = P.tie_fy
    if P.tie_mode == TIE_TENSION:
        f = max(0.0, f)
    elif f < -fy:
        f = -fy
    return min(f, fy)


@njit(cache=True, inline="always")
def restraint_moment(th, om, s, bl, P):
    """Moments of the restraints about pivot ``s`` [N m] (see :func:`restraint_terms`)."""
    return restraint_terms(math.cos(th), math.sin(th), om, s, bl, P)


@njit(cache=True, inline="always")
def restraint_terms(ct, st, om, s, bl, P):
    """Moments of the restraints about pivot ``s`` [N m] (EURODYN (2020) eqs. 2, 6, 7).

    A body point at body coordinates ``(u, y)`` (``u`` from the base centre, positive towards
    pivot +1, the outer face) sits at ``x0 = u - s b`` from the pivot; after the rotation it is at
    ``X = x0 cos th + y sin th``, ``Y = y cos th - x0 sin th``. A horizontal force ``F_x`` there
    has the moment ``Y F_x`` (positive clockwise, as theta).

    - tie (eq. 2): outward anchor displacement ``d = X - x0``, force :func:`tie_force`, moment
      ``-Y F``; for a tie at ``(R_t, alpha_t)`` from the pivot this is
      ``-K R_t^2 cos(A_t) (sin alpha_t - sin A_t)``, EURODYN (2020) eq. 2;
    - damper (eq. 7): the anchor moves at ``Y theta'``, force ``-c Y theta'``, moment
      ``-c Y^2 theta'``, i.e. ``-c R_d^2 cos^2(A_d) theta'``;
    - spring bed (eqs. 3-6): :func:`_bed_moment`.

    ``ct, st``: cosine and sine of theta, computed once per evaluation."""
    M = 0.0
    if P.tie_mode != TIE_NONE:
        x0 = P.tie_x - s * bl
        y = P.tie_y
        d = x0 * (ct - 1.0) + y * st
        M -= (y * ct - x0 * st) * tie_force(d, P)
    if P.dmp_c != 0.0:
        x0 = P.dmp_x - s * bl
        Y = P.dmp_y * ct - x0 * st
        M -= P.dmp_c * Y * Y * om
    if P.bed_k != 0.0:
        M += _bed_moment(ct, st, s, bl, P)
    return M


@njit(cache=True, inline="always")
def moment_at(th, om, s, bl, ag, av, P):
    """Total moment about the active pivot ``s`` of lever ``bl`` [N m] (Mordant et al. (SERIES) eq.
    5, EURODYN (2020) eq. 1): gravity, ground inertia and the restraints.

    With ``R sin(alpha) = bl`` and ``R cos(alpha) = z_G``, the terms
    ``-m (g + a_v) R sin(s alpha - th) + m a_g R cos(s alpha - th)`` are evaluated as
    ``-m (g + a_v) (s bl cos th - z_G sin th) + m a_g (z_G cos th + s bl sin th)``: one sine
    and one cosine per evaluation, shared with the restraints."""
    m = P.m
    geff = P.g + av
    zg = P.zg
    if P.linear != 0.0:
        if P.pivot == PIVOT_CORNER:
            R = P.r
            a = P.alpha
        else:
            R = math.sqrt(bl * bl + zg * zg)
            a = math.atan2(bl, zg)
        M = -m * geff * R * (s * a - th) + m * ag * R
        if P.terms != 0.0:
            M += restraint_moment(th, om, s, bl, P)
        return M
    ct = math.cos(th)
    st = math.sin(th)
    sb = s * bl
    M = -m * geff * (sb * ct - zg * st) + m * ag * (zg * ct + sb * st)
    if P.terms != 0.0:
        M += restraint_terms(ct, st, om, s, bl, P)
    return M


@njit(cache=True, inline="always")
def moment(th, om, s, ag, av, P):
    """Total moment about the active pivot ``s`` [N m]."""
    return moment_at(th, om, s, lever(ag, av, P), ag, av, P)


@njit(cache=True, inline="always")
def accel(th, om, s, t, tm, drv, P):
    """Angular acceleration [rad/s2]."""
    gh, gv = ground(t, tm, drv)
    bl = lever(gh, gv, P)
    return moment_at(th, om, s, bl, gh, gv, P) / inertia(bl, P)


@njit(cache=True)
def update_tie(th, s, bl, P):
    """Plastic elongation of a yielding tie after an accepted step (return mapping; the step
    itself used the bounded force, so the error is local to the step that yields)."""
    if P.tie_mode == TIE_NONE or not math.isfinite(P.tie_fy):
        return
    x0 = P.tie_x - s * bl
    d = x0 * (math.cos(th) - 1.0) + P.tie_y * math.sin(th)
    f = P.tie_p0 + P.tie_k * (d - P.tie_dp)
    fy = P.tie_fy
    if f > fy:
        P.tie_dp = d - (fy - P.tie_p0) / P.tie_k
    elif P.tie_mode == TIE_BOTH and f < -fy:
        P.tie_dp = d - (-fy - P.tie_p0) / P.tie_k


@njit(cache=True)
def lift_direction(t, tm, drv, P):
    """Pivot about which the ground lifts the body at rest at time ``t`` (0: none)."""
    if lift_margin_call(t, tm, 1.0, drv, P) > 0.0:
        return 1.0
    if lift_margin_call(t, tm, -1.0, drv, P) > 0.0:
        return -1.0
    return 0.0


@njit(cache=True, inline="always")
def lift_margin(t, tm, s, drv, P):
    """``s * M(theta=0)`` about pivot ``s``: positive when the ground lifts the body."""
    if s < 0.0 and P.stop != 0.0:
        return -1.0
    gh, gv = ground(t, tm, drv)
    return s * moment(0.0, 0.0, s, gh, gv, P)


# The called (not inlined) copies of accel and lift_margin, for the paths taken once per event
# (uplift, impact, cascade, the start of a Newmark run): an inlined copy of the whole moment in
# each of them made the event engine take 67 s of CPU to compile, against 30 s now; the
# stepping paths (dp_step, the body at rest in rest_phase, newmark_solve) keep theirs inlined,
# which is worth 30-40 % of the speed of a batch (benchmarks/ab_rocking.py; the results are
# bit for bit those of the all-inlined kernel).
@njit(cache=True)
def accel_call(th, om, s, t, tm, drv, P):
    """:func:`accel`, called rather than inlined."""
    return accel(th, om, s, t, tm, drv, P)


@njit(cache=True)
def lift_margin_call(t, tm, s, drv, P):
    """:func:`lift_margin`, called rather than inlined."""
    return lift_margin(t, tm, s, drv, P)


@njit(cache=True)
def locate_uplift(ta, tb, tm, drv, P):
    """First instant in ``(ta, tb]`` where the ground lifts the body, by the Illinois method on
    the lift margin (exact in two iterations for a piecewise-linear record). Returns
    ``(time, pivot)`` or ``(tb, 0)`` when there is none."""
    best_t = tb
    best_s = 0.0
    for si in range(2):
        s = 1.0 if si == 0 else -1.0
        fb = lift_margin_call(tb, tm, s, drv, P)
        if fb <= 0.0:
            continue
        a = ta
        fa = lift_margin_call(ta, tm, s, drv, P)
        b = tb
        side = 0
        for _ in range(200):
            if b - a <= 1e-14 * (1.0 + abs(b)):
                break
            c = (a * fb - b * fa) / (fb - fa)
            if not (c > a and c < b):
                c = 0.5 * (a + b)
            fc = lift_margin_call(c, tm, s, drv, P)
            if fc > 0.0:
                b = c
                fb = fc
                if side == 1:
                    fa *= 0.5
                side = 1
            else:
                a = c
                fa = fc
                if side == -1:
                    fb *= 0.5
                side = -1
        if b < best_t or best_s == 0.0:
            best_t = b
            best_s = s
    return best_t, best_s


# ======================================================================== restitution =====
@njit(cache=True)
def restitution(P, mem, om_before, t, bl):
    """Coefficient of restitution applied at an impact at time ``t`` with the pivot lever ``bl``
    (law code ``P.e_kind``; Mordant et al. (SERIES) §3.3.2).

    - constant (Housner on the corner included): ``P.e``;
    - momentum: angular momentum about the new pivot, levers ``b1`` before and ``b2`` after,
      ``e = (I_G + m z_G^2 - m b1 b2) / (I_G + m z_G^2 + m b2^2)`` (Housner's derivation with the
      pivot at the compressive-length point, eq. 13; ``cos 2 alpha`` for a mass at the top);
      here ``b1 = b2 = bl``, the lever at the instant of the impact;
    - coefficient: ``e = 1 - (k0 + k1 r) sin^2(alpha_n)``, ``alpha_n = atan(bl / z_G)``, with
      ``r`` the largest rotation of the half-cycle before the impact over the largest rotation
      so far (causal) or of the whole run (iterated, ``P.e_absmax > 0``) (eqs. 14-16), and
      ``(k0f, k1f)`` once the input has ended when a free-vibration law is set (eq. 17).

    The aspect-ratio factor ``f`` of eq. 18 scales the energy lost at the impact:
    ``e' = sqrt(1 - f (1 - e^2))``."""
    kind = P.e_kind
    if kind == E_CONSTANT:
        e = P.e
    elif kind == E_MOMENTUM:
        j = P.ig + P.m * P.zg * P.zg
        mb = P.m * bl
        e = (j - mb * bl) / (j + mb * bl)
    else:
        zg = P.zg
        s2 = bl * bl / (bl * bl + zg * zg)
        amax = P.e_absmax if P.e_absmax > 0.0 else mem[MEM_ABS_MAX]
        r = min(1.0, mem[MEM_HALF_MAX] / amax) if amax > 0.0 else 1.0
        if P.e_free != 0.0 and t > mem[MEM_T_FREE]:
            e = 1.0 - (P.e_k0f + P.e_k1f * r) * s2
        else:
            e = 1.0 - (P.e_k0 + P.e_k1 * r) * s2
    f = P.e_aspect
    if f != 1.0:
        e = math.sqrt(max(0.0, 1.0 - f * (1.0 - e * e)))
    return min(1.0, max(0.0, e))


# ========================================================================== helpers ======
@njit(cache=True)
def potential(th, P):
    """Potential energy above the rest position [J] (rigid base)."""
    a = P.alpha
    return P.m * P.g * P.r * (math.cos(a - abs(th)) - math.cos(a))


@njit(cache=True)
def hermite5(u, h, y0, v0, a0, y1, v1, a1):
    """Quintic Hermite interpolation on a step of length ``h`` at fraction ``u``: value and
    derivative, from value, first and second derivative at both ends (order h^6)."""
    u2 = u * u
    u3 = u2 * u
    u4 = u3 * u
    u5 = u4 * u
    H0 = 1.0 - 10.0 * u3 + 15.0 * u4 - 6.0 * u5
    H1 = u - 6.0 * u3 + 8.0 * u4 - 3.0 * u5
    H2 = 0.5 * u2 - 1.5 * u3 + 1.5 * u4 - 0.5 * u5
    H3 = 10.0 * u3 - 15.0 * u4 + 6.0 * u5
    H4 = -4.0 * u3 + 7.0 * u4 - 3.0 * u5
    H5 = 0.5 * u3 - u4 + 0.5 * u5
    y = H0 * y0 + h * H1 * v0 + h * h * H2 * a0 + H3 * y1 + h * H4 * v1 + h * h * H5 * a1
    D0 = -30.0 * u2 + 60.0 * u3 - 30.0 * u4
    D1 = 1.0 - 18.0 * u2 + 32.0 * u3 - 15.0 * u4
    D2 = u - 4.5 * u2 + 6.0 * u3 - 2.5 * u4
    D3 = -D0
    D4 = -12.0 * u2 + 28.0 * u3 - 15.0 * u4
    D5 = 1.5 * u2 - 4.0 * u3 + 2.5 * u4
    dy = (D0 * y0 + D3 * y1) / h + D1 * v0 + D4 * v1 + h * (D2 * a0 + D5 * a1)
    return y, dy


@njit(cache=True)
def hermite_root_omega(s, h, y0, v0, a0, y1, v1, a1):
    """Fraction ``u`` in (0, 1] where ``s * theta'`` of the interpolant changes sign (bisection
    and regula falsi; ``s * v0 > 0 >= s * v1``)."""
    lo = 0.0
    hi = 1.0
    flo = s * v0
    fhi = s * v1
    for _ in range(60):
        u = lo + (hi - lo) * flo / (flo - fhi) if flo != fhi else 0.5 * (lo + hi)
        if not (u > lo and u < hi):
            u = 0.5 * (lo + hi)
        _, d = hermite5(u, h, y0, v0, a0, y1, v1, a1)
        f = s * d
        if f > 0.0:
            lo = u
            flo = f
        else:
            hi = u
            fhi = f
        if hi - lo < 1e-13:
            break
    return 0.5 * (lo + hi)


@njit(cache=True)
def hermite_bisect(sense, level, tol, h, y0, v0, a0, y1, v1, a1):
    """Bracket ``(lo, hi)`` of the fraction ``u`` of a step at which the quintic Hermite
    interpolant :func:`hermite5` crosses ``level`` (bisection until ``hi - lo < tol``, at most 60
    halvings): ``lo`` moves while ``sense * (theta(u) - level) > 0``, i.e. ``sense`` is the sign
    of ``theta - level`` at the start of the step. The one bisection of both rocking engines
    (rigid base: overturning, exceedance of alpha and the first guess of an impact; Winkler
    base: crossings and overturning)."""
    lo = 0.0
    hi = 1.0
    for _ in range(60):
        u = 0.5 * (lo + hi)
        y, _ = hermite5(u, h, y0, v0, a0, y1, v1, a1)
        if sense * (y - level) > 0.0:
            lo = u
        else:
            hi = u
        if hi - lo < tol:
            break
    return lo, hi


@njit(cache=True)
def hermite_root_level(s, level, h, y0, v0, a0, y1, v1, a1):
    """Fraction ``u`` where ``s * theta`` of the interpolant first reaches ``level`` (bisection;
    ``s * y0 < level <= s * y1``)."""
    _, hi = hermite_bisect(-s, s * level, 1e-13, h, y0, v0, a0, y1, v1, a1)
    return hi


# ================================================================ Dormand-Prince 5(4) ======
# The Dormand-Prince 5(4) tableau (Dormand and Prince 1980), declared once for both rocking
# engines: nodes C*, stages A*, error weights E* (5th minus 4th order weights; the 5th-order
# weights are the last row of A). :func:`dp_step` unrolls it for the rigid base; the Winkler
# base (:mod:`murus.rocking.winkler_kernels`) loops over :data:`DP_A`, :data:`DP_C`, :data:`DP_E`.
C2, C3, C4, C5 = 0.2, 0.3, 0.8, 8.0 / 9.0
A21 = 0.2
A31, A32 = 3.0 / 40.0, 9.0 / 40.0
A41, A42, A43 = 44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0
A51, A52, A53, A54 = 19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0
A61, A62, A63, A64, A65 = (9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0,
                           -5103.0 / 18656.0)
A71, A73, A74, A75, A76 = (35.0 / 384.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0,
                           11.0 / 84.0)
E1, E3, E4, E5, E6, E7 = (71.0 / 57600.0, -71.0 / 16695.0, 71.0 / 1920.0, -17253.0 / 339200.0,
                          22.0 / 525.0, -1.0 / 40.0)
DP_C = np.array([0.0, C2, C3, C4, C5, 1.0, 1.0])
DP_A = np.array([
    [0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [A21, 0.0, 0.0, 0.0, 0.0, 0.0],
    [A31, A32, 0.0, 0.0, 0.0, 0.0],
    [A41, A42, A43, 0.0, 0.0, 0.0],
    [A51, A52, A53, A54, 0.0, 0.0],
    [A61, A62, A63, A64, A65, 0.0],
    [A71, 0.0, A73, A74, A75, A76],
])
DP_E = np.array([E1, 0.0, E3, E4, E5, E6, E7])


@njit(cache=True)
def dp_step(t, th, om, a0, h, s, tm, drv, P):
    """One Dormand-Prince 5(4) step for ``y = (theta, theta')``; ``a0`` is ``theta''`` at ``t``.
    Returns the 5th-order state, the embedded error estimate and ``theta''`` at the end."""
    k1t = om
    k1o = a0
    y2t = th + h * (A21 * k1t)
    y2o = om + h * (A21 * k1o)
    k2t = y2o
    k2o = accel(y2t, y2o, s, t + C2 * h, tm, drv, P)
    y3t = th + h * (A31 * k1t + A32 * k2t)
    y3o = om + h * (A31 * k1o + A32 * k2o)
    k3t = y3o
    k3o = accel(y3t, y3o, s, t + C3 * h, tm, drv, P)
    y4t = th + h * (A41 * k1t + A42 * k2t + A43 * k3t)
    y4o = om + h * (A41 * k1o + A42 * k2o + A43 * k3o)
    k4t = y4o
    k4o = accel(y4t, y4o, s, t + C4 * h, tm, drv, P)
    y5t = th + h * (A51 * k1t + A52 * k2t + A53 * k3t + A54 * k4t)
    y5o = om + h * (A51 * k1o + A52 * k2o + A53 * k3o + A54 * k4o)
    k5t = y5o
    k5o = accel(y5t, y5o, s, t + C5 * h, tm, drv, P)
    y6t = th + h * (A61 * k1t + A62 * k2t + A63 * k3t + A64 * k4t + A65 * k5t)
    y6o = om + h * (A61 * k1o + A62 * k2o + A63 * k3o + A64 * k4o + A65 * k5o)
    k6t = y6o
    k6o = accel(y6t, y6o, s, t + h, tm, drv, P)
    nt = th + h * (A71 * k1t + A73 * k3t + A74 * k4t + A75 * k5t + A76 * k6t)
    no = om + h * (A71 * k1o + A73 * k3o + A74 * k4o + A75 * k5o + A76 * k6o)
    k7t = no
    k7o = accel(nt, no, s, t + h, tm, drv, P)
    et = h * (E1 * k1t + E3 * k3t + E4 * k4t + E5 * k5t + E6 * k6t + E7 * k7t)
    eo = h * (E1 * k1o + E3 * k3o + E4 * k4o + E5 * k5o + E6 * k6o + E7 * k7o)
    return nt, no, et, eo, k7o


@njit(cache=True)
def locate_in_step(kind, level, t, h, s, tm, drv, P, y0, y1):
    """Step size ``tau`` in (0, h] at which a terminal event happens.

    ``kind`` 0: ``s * theta`` reaches ``level`` from below (overturning);
    ``kind`` 1: ``s * theta`` falls to 0 (impact).
    ``y0 = (theta, theta', theta'')`` at the start of the accepted step, ``y1`` at its end.
    The first guess is the root of the quintic Hermite interpolant of the accepted step; Newton
    iterations on fresh RK steps of size ``tau`` (whose derivative is the angular velocity
    itself) then make the event as accurate as the integration; the bracket is kept and
    bisection takes over if Newton leaves it."""
    th, om, a0 = y0
    nt, no, a1 = y1
    lo = 0.0
    hi = h
    sg = 1.0 if kind == 1 else -1.0
    lev = 0.0 if kind == 1 else level
    # root of the interpolant: sg * (s * y - lev) goes from > 0 to <= 0
    a, b = hermite_bisect(sg * s, s * lev, 1e-7, h, th, om, a0, nt, no, a1)
    tau = 0.5 * (a + b) * h
    for _ in range(30):
        y, w, _, _, _ = dp_step(t, th, om, a0, tau, s, tm, drv, P)
        f = sg * (s * y - lev)
        if f > 0.0:
            lo = tau
        else:
            hi = tau
        if f == 0.0:
            return tau
        df = sg * s * w
        nxt = tau - f / df if df != 0.0 else 0.5 * (lo + hi)
        if not (nxt > lo and nxt < hi):
            nxt = 0.5 * (lo + hi)
        if abs(nxt - tau) <= 1e-14 * (1.0 + t):
            tau = nxt
            break
        tau = nxt
        if hi - lo <= 1e-14 * (1.0 + t):
            break
    return tau


@njit(cache=True)
def reset_summary(S):
    """Initial values of the summary vector (times of events not reached: nan)."""
    S[:] = 0.0
    S[S_T_UPLIFT] = np.nan
    S[S_T_OVERTURN] = np.nan
    S[S_T_EXCEED_ALPHA] = np.nan


def new_log(n_out: int = 0, n_impacts: int = 0, n_events: int = 0) -> Log:
    """A :class:`Log` for one run: histories of ``n_out`` points, room for ``n_impacts`` impacts
    and ``n_events`` uplift intervals and peaks (all nan until written)."""
    # three blocks, not eight arrays: a single history is short and its Python side counts
    z = np.zeros(S_SIZE + MEM_SIZE)
    h = np.full((3, n_out), np.nan)
    ni = 3 * n_impacts
    ev = np.full(ni + 4 * n_events, np.nan)
    return Log(z[:S_SIZE], z[S_SIZE:], h[0], h[1], h[2], ev[:ni].reshape(n_impacts, 3),
               ev[ni:ni + 2 * n_events].reshape(n_events, 2),
               ev[ni + 2 * n_events:].reshape(n_events, 2))


@njit(cache=True)
def record_theta(S, mem, th, t):
    """Update the extreme values with a rotation reached at time ``t``."""
    a = abs(th)
    if a > S[S_THETA_MAX]:
        S[S_THETA_MAX] = a
        S[S_THETA_AT_MAX] = th
        S[S_T_THETA_MAX] = t
    if th > S[S_THETA_POS]:
        S[S_THETA_POS] = th
    if th < S[S_THETA_NEG]:
        S[S_THETA_NEG] = th
    if a > mem[MEM_HALF_MAX]:
        mem[MEM_HALF_MAX] = a
    if a > mem[MEM_ABS_MAX]:
        mem[MEM_ABS_MAX] = a


@njit(cache=True)
def record_peak(S, pk, t, th):
    """Log a peak of the rotation (``theta' = 0`` while rocking)."""
    n = int(S[S_N_PEAKS])
    if n < pk.shape[0]:
        pk[n, 0] = t
        pk[n, 1] = th
    S[S_N_PEAKS] = n + 1


@njit(cache=True)
def cascade_end(t, om, s, drv, P, mem):
    """Accumulation time [s] of the cascade of impacts that starts at ``t`` with the angular
    velocity ``om`` [rad/s] about pivot ``s`` just after an impact, or ``-1.0`` when the cascade
    cannot be summed (the ground lifts the body during it or just after it). With ``e = 1``
    (only a damper dissipates) the cascade has no accumulation point and the body is put at
    rest at ``t`` (the rule of ``rest_tol``), with the same check of the ground.

    At small amplitude a bounce about pivot ``s`` is a flight under the constant restoring
    acceleration ``d = -s theta''(theta = 0)`` (gravity, ground, restraints at ``theta = 0``):
    it lasts ``2 w / d`` and returns with the launch speed ``w``, which the next impact multiplies
    by ``e`` (by ``e^2`` against rigid transverse walls: an impact into the walls and one out of
    them). With constant ``e`` and ``d`` the bounce times form the geometric series
    ``T_n = T_0 e^n`` and the cascade ends at ``t + T_0 / (1 - e)`` (free rocking: ``d = p^2
    alpha``, ``t_inf = t + 2 w / (p^2 alpha (1 - e))``; Housner 1963, where the half-period of
    the linearised equation, ``tanh(p T / 2) = w / (p alpha)``, tends to ``2 w / (p^2 alpha)``
    at small ``w``). Here ``d`` and ``e`` are evaluated bounce by bounce for the first
    ``CASCADE_BOUNCES`` bounces (``d`` at mid-bounce, so a slowly varying ground acceleration is
    followed), and the tail is summed in closed form with the last values: bounces about
    alternating pivots ``s, -s, ...`` with restoring accelerations ``d_1, d_2`` sum to
    ``(2 w / (1 - e^2)) (1/d_1 + e/d_2)``; against rigid walls, where the pivot stays and the
    ratio is ``e^2``, to ``2 w / (d (1 - e^2))``.

    The sum is accepted only when the lift margins about both pivots stay negative at ``t``, at
    every breakpoint of the input in ``[t, t + 2 (t_inf - t)]`` and at its end: then the body
    truly comes to rest (the factor 2 covers the error of the sum), and it stays at rest from
    ``t_inf`` until the ground lifts it, a case for the rest phase."""
    w = abs(om)
    if w == 0.0:
        return t
    tc = t
    e = 1.0
    dp = 0.0  # restoring acceleration of the last bounce about pivot +1 ...
    dm = 0.0  # ... and about pivot -1 [rad/s2]
    elastic = False
    for _ in range(CASCADE_BOUNCES):
        a = accel_call(0.0, 0.0, s, tc, tc, drv, P)
        d = -s * a
        if not (d > 0.0):
            return -1.0
        tn = 2.0 * w / d
        a = accel_call(0.0, 0.0, s, tc + 0.5 * tn, tc + 0.5 * tn, drv, P)
        d = -s * a
        if not (d > 0.0):
            return -1.0
        tn = 2.0 * w / d
        if s > 0.0:
            dp = d
        else:
            dm = d
        tc += tn
        gh, gv = ground(tc, tc, drv)
        bl = lever(gh, gv, P)
        e = restitution(P, mem, 0.0, tc, bl)
        if P.stop != 0.0 and s > 0.0:
            e = e * restitution(P, mem, 0.0, tc, bl)  # into the walls and out of them
        else:
            s = -s
        if not (e < 1.0):
            # e = 1: the impacts dissipate nothing. With a damper alone the bounces shrink by
            # a factor that tends to 1 (the flight, hence the damper's work, shrinks with
            # them), so the bounce times form a divergent series and the cascade has no
            # accumulation point: an unbounded number of ever smaller bounces. The body is put
            # at rest now (below rest_tol p alpha), if the ground does not lift it over twice
            # the first bounce.
            elastic = True
            break
        w *= e
    if elastic:
        t_inf = t
        t_win = t + 2.0 * (tc - t)
    # the tail in closed form with the last restoring accelerations
    elif P.stop != 0.0 and s > 0.0:
        t_inf = tc + 2.0 * w / (dp * (1.0 - e))
    else:
        d1 = dp if s > 0.0 else dm
        d2 = dm if s > 0.0 else dp
        if d1 == 0.0 or d2 == 0.0:  # pragma: no cover (CASCADE_BOUNCES >= 2)
            d1 = d2 = max(d1, d2)
        t_inf = tc + 2.0 * w / (1.0 - e * e) * (1.0 / d1 + e / d2)
    # the ground must not lift the body over the cascade and as long again after it
    if not elastic:
        t_win = t + 2.0 * (t_inf - t)
    tb = t
    for _ in range(100_000):
        if lift_margin_call(tb, tb, 1.0, drv, P) > 0.0:
            return -1.0
        if lift_margin_call(tb, tb, -1.0, drv, P) > 0.0:
            return -1.0
        if tb >= t_win:
            break
        tb = min(segment_end(tb, drv, t_win), t_win)
    return t_inf


@njit(cache=True)
def do_impact(t, tm, om_b, s, drv, P, log):
    """Apply an impact at ``t``: restitution, pivot switch, log; returns ``(omega, pivot)``.
    A velocity after the impact below ``rest_tol * p * alpha`` puts the body at rest right away
    (the rule of the fixed-step Newmark method; the event-driven method sums the cascade
    instead: :func:`do_impact_cascade`)."""
    om_a, s_next, t_rest = impact_core(t, tm, om_b, s, drv, P, log, False)
    return om_a, s_next


@njit(cache=True)
def do_impact_cascade(t, tm, om_b, s, drv, P, log):
    """Apply an impact at ``t`` (event-driven method); returns ``(omega, pivot, t_rest)``: when
    the cascade that follows is summed (:func:`cascade_end`), pivot 0 and the accumulation time
    ``t_rest`` at which the body comes to rest; else ``t_rest = t``."""
    return impact_core(t, tm, om_b, s, drv, P, log, True)


@njit(cache=True)
def impact_core(t, tm, om_b, s, drv, P, log, cascade):
    """Impact at ``t``: restitution, pivot switch, log, and the end of a cascade (see
    :func:`do_impact` and :func:`do_impact_cascade`)."""
    S = log.S
    mem = log.mem
    imp = log.imp
    up = log.up
    ni_cap = imp.shape[0]
    nu_cap = up.shape[0]
    gh, gv = ground(t, tm, drv)
    bl = lever(gh, gv, P)
    e = restitution(P, mem, om_b, t, bl)
    om_a = e * om_b
    s_next = -s
    if P.stop != 0.0 and s > 0.0:
        # rigid transverse walls: the limit of a stiff spring bed, an impact on the base into
        # the walls, an elastic bounce of no duration and an impact on the base out of them
        mem[MEM_HALF_MAX] = 0.0
        om_a = -restitution(P, mem, om_a, t, bl) * om_a
        s_next = s
    n = int(S[S_N_IMPACTS])
    if n < ni_cap:
        imp[n, 0] = t
        imp[n, 1] = om_b
        imp[n, 2] = om_a
    S[S_N_IMPACTS] = n + 1
    i_o = inertia(bl, P)
    S[S_E_DISSIPATED] += 0.5 * i_o * (om_b * om_b - om_a * om_a)
    mem[MEM_HALF_MAX] = 0.0
    p = math.sqrt(P.m * P.g * P.r / P.i_o)
    rest = abs(om_a) < P.rest_tol * p * P.alpha
    if not rest and s_next == s and not cascade:
        # (Newmark) a bounce on rigid walls: end the cascade once the excursion it starts,
        # om^2 / (2 |theta''|) under the restoring acceleration at theta = 0, is below
        # rest_tol * alpha (the bounces form a geometric series of vanishing excursions)
        a0 = accel_call(0.0, om_a, s, t, tm, drv, P)
        rest = s * a0 < 0.0 and om_a * om_a < 2.0 * P.rest_tol * P.alpha * abs(a0)
    t_rest = t
    if rest and cascade:
        # sum the rest of the cascade; at rest only at its accumulation point, and only if the
        # ground cannot lift the body over it (else integrate on)
        t_rest = cascade_end(t, om_a, s_next, drv, P, mem)
        rest = t_rest >= t
    if rest:
        # the cascade ends: back to rest (the rest phase lifts the body when the ground can)
        S[S_E_DISSIPATED] += 0.5 * i_o * om_a * om_a
        k = int(S[S_N_UPLIFTS]) - 1
        if 0 <= k < nu_cap:
            up[k, 1] = t_rest
        return 0.0, 0.0, t_rest
    return om_a, s_next, t


@njit(cache=True)
def start_uplift(t, log):
    """Open an uplift interval at ``t``."""
    S = log.S
    up = log.up
    nu_cap = up.shape[0]
    if math.isnan(S[S_T_UPLIFT]):
        S[S_T_UPLIFT] = t
    k = int(S[S_N_UPLIFTS])
    if k < nu_cap:
        up[k, 0] = t
        up[k, 1] = np.nan
    S[S_N_UPLIFTS] = k + 1


@njit(cache=True, inline="always")
def fill_rest(j, t_to, out_dt, log, inclusive):
    """Write rest values on the output grid up to ``t_to``; returns the next output index."""
    th_out = log.th
    om_out = log.om
    pv_out = log.pv
    n = th_out.shape[0]
    while j < n:
        tj = j * out_dt
        if tj > t_to or (not inclusive and tj >= t_to):
            break
        th_out[j] = 0.0
        om_out[j] = 0.0
        pv_out[j] = 0.0
        j += 1
    return j


@njit(cache=True)
def start_run(P, drv, log):
    """Working copy of the parameters (a yielding tie keeps its plastic elongation there), law
    memory with the end of the input (the switch to free vibration of Mordant et al. (SERIES) eq.
    17)."""
    w = np.empty(1, PARAM_DTYPE)
    w[0] = P
    Pw = w[0]
    Pw.tie_dp = 0.0
    reset_summary(log.S)
    mem = log.mem
    mem[:] = 0.0
    X = drv.X
    n_rec = drv.ag.shape[0]
    if X[X_KIND] == X_RECORD:
        mem[MEM_T_FREE] = (n_rec - 1) * X[X_DT]
    else:
        mem[MEM_T_FREE] = X[X_T0] + X[X_DUR]
    return Pw


@njit(cache=True)
def initial_pivot(th0, om0, log):
    """Pivot of the initial state (the side of theta0, else of omega0, else rest: 0); a body
    that starts rocking opens an uplift interval at t = 0."""
    s = 0.0
    if th0 != 0.0:
        s = 1.0 if th0 > 0.0 else -1.0
    elif om0 != 0.0:
        s = 1.0 if om0 > 0.0 else -1.0
    if s != 0.0:
        start_uplift(0.0, log)
        record_theta(log.S, log.mem, th0, 0.0)
    return s


@njit(cache=True, inline="always")
def rest_phase(t, tb, tm, drv, P, have_m, mp_a, mm_a, j, out_dt, log):
    """One segment ``[t, tb]`` at rest: lift margins at both ends (those at ``t`` carried over
    from the previous segment when the input is continuous there), uplift located inside.

    Returns ``(t, pivot, j, have_m, mp_a, mm_a)``: pivot 0 and ``t = tb`` when the body stays
    at rest, else the uplift time and pivot."""
    if not have_m:
        mp_a = lift_margin_call(t, tm, 1.0, drv, P)
        mm_a = lift_margin_call(t, tm, -1.0, drv, P)
    if mp_a > 0.0 or mm_a > 0.0:
        tu = t
        sd = 1.0 if mp_a >= mm_a else -1.0
    else:
        # the hot path (a body at rest, segment after segment): one inlined copy of the
        # margin for both pivots
        mp_b = 0.0
        mm_b = 0.0
        for k in range(2):
            m = lift_margin(tb, tm, 1.0 - 2.0 * k, drv, P)
            if k == 0:
                mp_b = m
            else:
                mm_b = m
        if mp_b <= 0.0 and mm_b <= 0.0:
            j = fill_rest(j, tb, out_dt, log, True)
            return tb, 0.0, j, continuous_at(tb, drv), mp_b, mm_b
        tu, sd = locate_uplift(t, tb, tm, drv, P)
    j = fill_rest(j, tu, out_dt, log, False)
    start_uplift(tu, log)
    return tu, sd, j, False, mp_a, mm_a


@njit(cache=True)
def overturned_at(t, th, s, j, log):
    """Record overturning at ``t`` and fill the rest of the history."""
    S = log.S
    up = log.up
    nu_cap = up.shape[0]
    th_out = log.th
    om_out = log.om
    pv_out = log.pv
    S[S_OVERTURNED] = 1.0
    S[S_T_OVERTURN] = t
    k = int(S[S_N_UPLIFTS]) - 1
    if 0 <= k < nu_cap:
        up[k, 1] = t
    while j < th_out.shape[0]:
        th_out[j] = th
        om_out[j] = np.nan
        pv_out[j] = s
        j += 1
    return j


@njit(cache=True)
def finish(t, th, om, s, steps, j, log):
    """Grid points beyond the last step by round-off only get the final state; counters."""
    S = log.S
    th_out = log.th
    om_out = log.om
    pv_out = log.pv
    while j < th_out.shape[0] and S[S_OVERTURNED] == 0.0:
        th_out[j] = th
        om_out[j] = om
        pv_out[j] = s
        j += 1
    S[S_N_STEPS] = steps
    S[S_T_FINAL] = t


# ============================================================ event-driven integrator ======
@njit(cache=True)
def event_core(P, drv, t_end, th0, om0, rtol, out_dt, log, max_steps):
    """Event-driven integration of one history (adaptive Dormand-Prince 5(4), stepping exactly on
    the input breakpoints; uplift, impacts and overturning located inside the step).

    ``P``: the parameter record (:data:`PARAMS`); ``drv``: the :class:`Drive`. Histories are
    written into ``log`` (a :class:`Log`) on the grid ``k * out_dt`` (length 0: no history),
    with the impacts, uplift intervals and peaks up to their capacity. Returns the summary
    vector ``log.S``."""
    P = start_run(P, drv, log)
    S = log.S
    mem = log.mem
    th_out = log.th
    om_out = log.om
    pv_out = log.pv
    pk = log.pk
    alpha = P.alpha
    p = math.sqrt(P.m * P.g * P.r / P.i_o)
    atol_t = rtol * alpha
    atol_o = rtol * p * alpha
    t = 0.0
    th = th0
    om = om0
    s = initial_pivot(th0, om0, log)
    j = 0  # next output index
    h = 0.0
    steps = 0
    a0 = 0.0
    have_a0 = False  # theta'' at t is known (first same as last, across continuous breakpoints)
    mp_a = 0.0
    mm_a = 0.0
    have_m = False  # lift margins at t are known (at rest)
    while t < t_end:
        if steps >= max_steps:
            S[S_STATUS] = 2.0
            break
        tb = segment_end(t, drv, t_end)
        tm = 0.5 * (t + tb)
        if s == 0.0:
            t, s, j, have_m, mp_a, mm_a = rest_phase(t, tb, tm, drv, P, have_m, mp_a, mm_a,
                                                     j, out_dt, log)
            if s == 0.0:
                continue
            th = 0.0
            om = 0.0
            h = 0.0
            have_a0 = False
            if t >= tb:
                continue
        # ---- rocking about pivot s inside the segment [t, tb]
        if not have_a0:
            a0 = accel(th, om, s, t, tm, drv, P)
            have_a0 = True
        if h <= 0.0:
            # initial step: a fraction of the rocking time scale 1/p
            h = 0.01 / p
        hmax = tb - t
        if th == 0.0 and s * a0 < 0.0 and s * om > 0.0:
            # leaving the base with a decelerating motion: do not step past the apex
            h = min(h, 0.9 * abs(om / a0))
        hh = min(h, hmax)
        if hh >= hmax * (1.0 - 1e-12):
            hh = hmax
        if hh <= 1e-14 * (1.0 + t):
            S[S_STATUS] = 1.0
            break
        nt, no, et, eo, a1 = dp_step(t, th, om, a0, hh, s, tm, drv, P)
        steps += 1
        sc_t = atol_t + rtol * max(abs(th), abs(nt))
        sc_o = atol_o + rtol * max(abs(om), abs(no))
        err = max(abs(et) / sc_t, abs(eo) / sc_o)
        if not (err <= 1.0):
            fac = 0.9 * err ** (-0.2) if err == err else 0.1
            h = hh * max(0.1, fac)
            continue
        # accepted step [t, t + hh]
        fac = 0.9 * err ** (-0.2) if err > 0.0 else 5.0
        h_next = hh * min(5.0, max(0.2, fac))
        event = 0  # 0 none, 1 impact, 2 overturn
        if s * nt >= HALF_PI:
            event = 2
        elif s * nt < 0.0:
            event = 1
        if event != 0:
            level = HALF_PI if event == 2 else 0.0
            tau = locate_in_step(2 - event, level, t, hh, s, tm, drv, P, (th, om, a0),
                                 (nt, no, a1))
            nt, no, _, _, a1 = dp_step(t, th, om, a0, tau, s, tm, drv, P)
            if event == 1:
                nt = 0.0
            else:
                nt = s * HALF_PI
            hh = tau
        if P.tie_mode != TIE_NONE and event == 0:
            gh, gv = ground(t + hh, tm, drv)
            update_tie(nt, s, lever(gh, gv, P), P)
        # non-terminal events on the interpolant: peak and first exceedance of alpha
        if s * om > 0.0 and s * no <= 0.0:
            u = hermite_root_omega(s, hh, th, om, a0, nt, no, a1)
            yp, _ = hermite5(u, hh, th, om, a0, nt, no, a1)
            record_theta(S, mem, yp, t + u * hh)
            record_peak(S, pk, t + u * hh, yp)
        record_theta(S, mem, nt, t + hh)
        if math.isnan(S[S_T_EXCEED_ALPHA]) and s * nt > alpha and s * th <= alpha:
            u = hermite_root_level(s, alpha, hh, th, om, a0, nt, no, a1)
            S[S_T_EXCEED_ALPHA] = t + u * hh
        # history on the output grid
        while j < th_out.shape[0] and j * out_dt <= t + hh:
            u = (j * out_dt - t) / hh
            if u < 0.0:
                u = 0.0
            yj, dj = hermite5(u, hh, th, om, a0, nt, no, a1)
            th_out[j] = yj
            om_out[j] = dj
            pv_out[j] = s
            j += 1
        at_break = hh >= hmax
        t = t + hh if not at_break else tb
        th = nt
        om = no
        h = h_next
        a0 = a1
        have_a0 = event == 0 and (not at_break or continuous_at(tb, drv))
        if event == 2:
            j = overturned_at(t, th, s, j, log)
            break
        if event == 1:
            om, s, t_rest = do_impact_cascade(t, tm, om, s, drv, P, log)
            th = 0.0
            h = h_next
            if s == 0.0:
                # at rest from the accumulation point of the cascade
                t = min(t_rest, t_end)
                have_m = False
    finish(t, th, om, s, steps, j, log)
    return S


# ==================================================== Newmark (average acceleration) ======
@njit(cache=True)
def newmark_solve(t, th, om, a0, h, s, drv, P):
    """One Newmark step (beta = 1/4, gamma = 1/2) of size ``h`` with Newton iterations on the
    nonlinear equation of motion (Mordant et al. (SERIES) §3.1.2, eqs. 6-8 reconstructed: the
    standard constant-average-acceleration update). Returns ``(theta, theta', theta'')`` at ``t +
    h``."""
    t1 = t + h
    x = th + h * om + 0.5 * h * h * a0
    d = 1e-7 * P.alpha
    for _ in range(50):
        a1 = 4.0 / (h * h) * (x - th - h * om) - a0
        w1 = 2.0 / h * (x - th) - om
        r = a1 - accel(x, w1, s, t1, t1, drv, P)
        fp = accel(x + d, w1 + 2.0 * d / h, s, t1, t1, drv, P)
        fm = accel(x - d, w1 - 2.0 * d / h, s, t1, t1, drv, P)
        dr = 4.0 / (h * h) - (fp - fm) / (2.0 * d)
        dx = r / dr
        x -= dx
        if abs(dx) <= 1e-14 * (P.alpha + abs(x)):
            break
    a1 = 4.0 / (h * h) * (x - th - h * om) - a0
    w1 = 2.0 / h * (x - th) - om
    return x, w1, a1


@njit(cache=True)
def newmark_locate(kind, level, t, th, om, a0, h, s, drv, P):
    """Sub-step ``tau`` in (0, h] at which the Newmark solution reaches the event (see
    :func:`locate_in_step`): locating the impact inside the step keeps the scheme second
    order."""
    lo = 0.0
    hi = h
    x, _, _ = newmark_solve(t, th, om, a0, h, s, drv, P)
    if kind == 0:
        flo = level - s * th
        fhi = level - s * x
    else:
        flo = s * th
        fhi = s * x
    side = 0
    for _ in range(100):
        if hi - lo <= 1e-13 * (1.0 + t):
            break
        c = (lo * fhi - hi * flo) / (fhi - flo)
        if not (c > lo and c < hi):
            c = 0.5 * (lo + hi)
        x, _, _ = newmark_solve(t, th, om, a0, c, s, drv, P)
        fc = (level - s * x) if kind == 0 else s * x
        if fc > 0.0:
            lo = c
            flo = fc
            if side == -1:
                fhi *= 0.5
            side = -1
        else:
            hi = c
            fhi = fc
            if side == 1:
                flo *= 0.5
            side = 1
        if fc == 0.0:
            break
    return hi


@njit(cache=True)
def newmark_core(P, drv, t_end, th0, om0, dt, log):
    """Newmark constant-average-acceleration integration with the step ``dt`` given by the user,
    uplift and impacts located inside the step. Output on the grid ``k * dt`` into ``log`` (see
    :func:`event_core`)."""
    P = start_run(P, drv, log)
    S = log.S
    mem = log.mem
    th_out = log.th
    om_out = log.om
    pv_out = log.pv
    pk = log.pk
    nu_cap = log.up.shape[0]
    up = log.up
    nsteps = int(math.ceil(t_end / dt - 1e-9))
    th = th0
    om = om0
    s = initial_pivot(th0, om0, log)
    nout = th_out.shape[0]
    if nout > 0:
        th_out[0] = th
        om_out[0] = om
        pv_out[0] = s
    a = accel_call(th, om, s, 0.0, 0.0, drv, P) if s != 0.0 else 0.0
    done = False
    for n in range(nsteps):
        t = n * dt
        t_next = (n + 1) * dt
        while t < t_next * (1.0 - 1e-15) and not done:
            if s == 0.0:
                sd = lift_direction(t, t, drv, P)
                tu = t
                if sd == 0.0:
                    tu, sd = locate_uplift(t, t_next, t, drv, P)
                if sd == 0.0:
                    t = t_next
                    break
                t = tu
                s = sd
                th = 0.0
                om = 0.0
                start_uplift(t, log)
                a = accel_call(0.0, 0.0, s, t, t, drv, P)
                if t >= t_next:
                    break
            h = t_next - t
            x, w, a1 = newmark_solve(t, th, om, a, h, s, drv, P)
            if s * x >= HALF_PI:
                tau = newmark_locate(0, HALF_PI, t, th, om, a, h, s, drv, P)
                x, w, a1 = newmark_solve(t, th, om, a, tau, s, drv, P)
                t = t + tau
                th = s * HALF_PI
                om = w
                record_theta(S, mem, th, t)
                S[S_OVERTURNED] = 1.0
                S[S_T_OVERTURN] = t
                k = int(S[S_N_UPLIFTS]) - 1
                if 0 <= k < nu_cap:
                    up[k, 1] = t
                done = True
                break
            if s * x < 0.0:
                tau = newmark_locate(1, 0.0, t, th, om, a, h, s, drv, P)
                x, w, a1 = newmark_solve(t, th, om, a, tau, s, drv, P)
                t = t + tau
                om, s = do_impact(t, t, w, s, drv, P, log)
                th = 0.0
                a = accel_call(0.0, om, s, t, t, drv, P) if s != 0.0 else 0.0
                continue
            if s * om > 0.0 and s * w <= 0.0:
                u = hermite_root_omega(s, h, th, om, a, x, w, a1)
                yp, _ = hermite5(u, h, th, om, a, x, w, a1)
                record_theta(S, mem, yp, t + u * h)
                record_peak(S, pk, t + u * h, yp)
            th = x
            om = w
            a = a1
            t = t_next
            record_theta(S, mem, th, t)
            if P.tie_mode != TIE_NONE:
                gh, gv = ground(t, t, drv)
                update_tie(th, s, lever(gh, gv, P), P)
        if nout > n + 1:
            th_out[n + 1] = th
            om_out[n + 1] = om
            pv_out[n + 1] = s
        if done:
            for k in range(n + 2, nout):
                th_out[k] = th
                om_out[k] = np.nan
                pv_out[k] = s
            break
    S[S_N_STEPS] = nsteps
    S[S_T_FINAL] = S[S_T_OVERTURN] if done else nsteps * dt
    return S


# ================================================================= batch entry point ======
@njit(cache=True, parallel=True)
def batch_event(Ps, Xs, ag_flat, av_flat, offsets, lengths, t_ends, th0s, om0s, rtol, max_steps):
    """Run many cases in parallel (``numba.prange``): case ``i`` uses the model ``Ps[i]``, the
    excitation ``Xs[i]`` with the record ``ag_flat[offsets[i]:offsets[i] + lengths[i]]``.
    Returns the summary matrix (one row per case), identical to one-by-one runs."""
    nc = Ps.shape[0]
    out = np.empty((nc, S_SIZE))
    for i in prange(nc):
        o = offsets[i]
        n = lengths[i]
        ag = ag_flat[o:o + n]
        av = av_flat[o:o + n] if av_flat.shape[0] == ag_flat.shape[0] else av_flat[0:0]
        e0 = np.empty(0)
        log = Log(np.empty(S_SIZE), np.empty(MEM_SIZE), e0, e0, e0, np.empty((0, 3)),
                  np.empty((0, 2)), np.empty((0, 2)))
        out[i, :] = event_core(Ps[i], Drive(Xs[i], ag, av), t_ends[i], th0s[i], om0s[i], rtol,
                               1.0, log, max_steps)
    return out


# numba's cache checks only this file: flush it when the summary layout it compiles in changes
_guard_cache(globals(), deps=("murus.rocking.summary",))

"""Contact damping of the distinct-element joints calibrated to a rocking restitution
(issue 19, item 5): how a DEM block gets Housner's (1963) energy loss per impact.

A rigid block rocking on a rigid base (:mod:`murus.rocking`) loses a fraction ``1 - e²`` of its
kinetic energy at each impact, ``e = omega_after / omega_before`` (Housner 1963: ``e = 1 -
1.5 sin²(alpha)`` for a uniform rectangle). A DEM block on elastic contacts loses energy at an
impact only by slip (0.25 x 1.0 m block, kn = 1e10 Pa/m, phi = 40 deg: ``e`` = 0.97-0.98 per
impact against Housner's 0.91). The joint's contact damping
(:attr:`murus.dem.materials.Joint.contact_damping`, a normal dashpot of critical-damping ratio
zeta acting only while a contact closes) supplies the missing loss. Its zeta for a target
``e`` depends on the block (slenderness, contact stiffness, rounding) and is found here by
running the free-rocking block (:func:`calibrate`): the equivalent-viscous-damping approach of
Vlachakis, Vlachaki, Lourenço, Giouvanidis & Dimitrakopoulos (2021), "Numerical block-based
simulation of rocking structures using a novel universal viscous damping model", J. Eng. Mech.
147(11), 04021089, DOI 10.1061/(ASCE)EM.1943-7889.0001985, who calibrate a damping active only
at impact to the classical restitution (their predictive equations are fitted to their own
software's damping form and are not reused here).

:func:`point_restitution` is the closed form of one point impact on the dashpot (the normal
restitution of a linear spring with a dashpot acting during the approach only), the first
guess of the calibration; a rocking impact spreads over the two corners and the friction, so
that the rocking ``e`` of a given zeta is measured, not predicted. Measured (0.25 x 1.0 m block,
kn = 1e10 Pa/m, phi = 40 deg, rounding 0.2 mm): e = 0.974 (zeta 0), 0.956 (0.05), 0.939
(0.15), 0.927 (0.3), 0.920 (0.6), 0.9166 (1.0) against Housner's 0.912: the dashpot on the
closing corner makes the impact at most plastic there, which is Housner's assumption, so that
the reachable range is [e(zeta = 1), e(0)] and Housner's behaviour is ``contact_damping = 1``
(docs/guide/dem_rocking.md). A restitution below Housner's (0.85 for this block) is out of
reach of this damping.

Measured restitution (:func:`restitutions`): the block's angular velocity at theta = 0 of the
rigid rocking before and after each impact, from the invariant of the rigid rotation about
the corner in each half-cycle (the DEM block bounces for a few degrees after an impact on its
stiff contacts, so that the velocity right after the crossing is not the rocking one): the
ratio of Housner's rigid model.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from murus import G
from murus.errors import MurusError

__all__ = ["point_restitution", "point_zeta", "FreeRocking", "free_rocking", "restitutions",
           "record_rocking", "calibrate", "CalibrationError", "KN", "FRICTION_DEG", "ROUNDING",
           "DENSITY"]

#: defaults of the calibration block: contact stiffness [Pa/m], friction [deg], rounding [m],
#: density [kg/m³] (those of murus.dem.verify.case_rocking)
KN = 1e10
FRICTION_DEG = 40.0
ROUNDING = 2e-4
DENSITY = 2000.0


class CalibrationError(MurusError, ValueError):
    """A restitution that the contact damping cannot reach, or bad calibration input."""


def point_restitution(zeta: float) -> float:
    """Normal restitution of a point mass hitting a linear spring with a dashpot of
    critical-damping ratio ``zeta`` that acts during the approach only.

    Approach: damped free vibration from ``x = 0``, ``v = v0``; the velocity vanishes at
    ``omega_d t = arccos(zeta)``, at ``x_max = (v0 / omega) exp(-zeta arccos(zeta) /
    sqrt(1 - zeta²))``; rebound undamped: ``v_out = omega x_max``. Hence ``e_n = exp(-zeta
    arccos(zeta) / sqrt(1 - zeta²))`` (``exp(-1)`` at zeta = 1, ``exp(-pi zeta / 2)`` for small
    zeta).

    Parameters
    ----------
    zeta : float
        Critical-damping ratio, 0 <= zeta <= 1.

    Returns
    -------
    float
        ``v_out / v_in``.
    """
    z = float(zeta)
    if not (0.0 <= z <= 1.0):
        raise CalibrationError(f"zeta must be in [0, 1], got {zeta!r}")
    if z == 1.0:
        return math.exp(-1.0)
    return math.exp(-z * math.acos(z) / math.sqrt(1.0 - z * z))


def point_zeta(e: float) -> float:
    """Inverse of :func:`point_restitution` (bisection, 1e-12): the zeta of a normal
    restitution ``e`` in [exp(-1), 1].

    Parameters
    ----------
    e : float
        Target normal restitution.

    Returns
    -------
    float
    """
    if not (math.exp(-1.0) <= e <= 1.0):
        raise CalibrationError(f"a point restitution must be in [exp(-1), 1], got {e!r}")
    lo, hi = 0.0, 1.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if point_restitution(mid) > e:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


@dataclass
class FreeRocking:
    """A free-rocking DEM history: time [s], rotation theta [rad] (negative: on the right
    corner), angular velocity [rad/s], slenderness alpha [rad], the rigid-rotation constant
    ``p2 = m g R / I_O`` [1/s²] and the measured restitutions and peak angles."""

    t: np.ndarray
    theta: np.ndarray
    omega: np.ndarray
    alpha: float
    p2: float
    e: np.ndarray
    peaks: np.ndarray


def _block(width, height, zeta, theta0, kn, friction_deg, rounding, density):
    from murus.dem.materials import Joint
    from murus.dem.verify import block_on_base

    joint = Joint(kn=kn, ks=kn, friction_deg=friction_deg, contact_damping=zeta)
    m, base, blk = block_on_base(width, height, joint, rounding=rounding, angle=theta0, pivot=+1)
    for b in m._bodies:
        b["density"] = density
    return m, base, blk


def free_rocking(width: float, height: float, zeta: float, *, theta0_over_alpha: float = 0.5,
                 n_impacts: int = 5, kn: float = KN, friction_deg: float = FRICTION_DEG,
                 rounding: float = ROUNDING, density: float = DENSITY,
                 duration: float | None = None, sample_dt: float = 5e-4) -> FreeRocking:
    """Release a ``width`` x ``height`` block tilted onto its right corner by
    ``theta0_over_alpha`` alpha on a fixed base, with joint contact damping ``zeta``, and
    record its rocking until ``n_impacts`` impacts (or ``duration`` [s]).

    Parameters
    ----------
    width, height : float
        Block [m].
    zeta : float
        Contact damping of the joint (:attr:`murus.dem.materials.Joint.contact_damping`).
    theta0_over_alpha : float
        Initial tilt as a fraction of alpha.
    n_impacts : int
        Impacts to record.
    kn, friction_deg, rounding, density : float
        Joint stiffness (kn = ks) [Pa/m], friction [deg], rounding [m], density [kg/m³].
    duration : float, optional
        Length of the run [s]; default: the time of ``n_impacts`` impacts of the rigid block
        with e = 0.99 (above the undamped DEM block's 0.97-0.98), plus one and a half swings:
        the elastic contacts lengthen the DEM block's swings a little (with kn = 1e9 Pa/m the
        third impact of the undamped block comes after the rigid block's with e = 0.97).
    sample_dt : float
        Interval of the recorded history [s] (whole time steps, at least one): the
        restitutions are medians over the swings and the peaks sit where the rotation is
        stationary, so the default 5e-4 s changes the mean restitution of the first three
        impacts by at most 3.5e-6 against 1e-4 s (measured on the 0.25 x 1.0 m block, kn = 1e9
        and 1e10 Pa/m, zeta = 0, 0.15 and 1; 1e-4 s itself is within 2e-6 of a history of
        every step), 600 times below the calibration's tolerance, in a fifth of the time: each
        sample pauses the engine (about 0.2 ms of Python, several times the steps between
        two samples at 1e-4 s).

    Returns
    -------
    FreeRocking
    """
    from murus.dem import engine as E
    from murus.rocking import RigidBlock, simulate

    alpha = math.atan(width / height)
    th0 = theta0_over_alpha * alpha
    if duration is None:
        # the impacts of the rigid model with an e above the undamped DEM block's, plus one
        # and a half swings
        rr = simulate(RigidBlock(width, height, density=density),
                      theta0_over_alpha=theta0_over_alpha, restitution=0.99, duration=30.0,
                      max_impacts=n_impacts + 2)
        ti = rr.impacts[:, 0]
        duration = float(ti[n_impacts] + 0.5 * (ti[n_impacts + 1] - ti[n_impacts])
                         if ti.size > n_impacts + 1 else 30.0)
    m, base, blk = _block(width, height, zeta, th0, kn, friction_deg, rounding, density)
    res = m.run(duration, probes={"a": E.body_probe(blk, "angle"),
                                  "w": E.body_probe(blk, "omega")}, sample_dt=sample_dt)
    theta = np.asarray(res["a"]) - th0
    omega = np.asarray(res["w"])
    R = 0.5 * math.hypot(width, height)
    p2 = G * R / (4.0 / 3.0 * R * R)  # m g R / I_O of a uniform rectangle, I_O = 4/3 m R²
    e, peaks = restitutions(np.asarray(res.t), theta, omega, alpha, p2)
    return FreeRocking(np.asarray(res.t), theta, omega, alpha, p2, e, peaks)


def record_rocking(width: float, height: float, zeta: float, motion, *,
                   duration: float | None = None, kn: float = KN,
                   friction_deg: float = FRICTION_DEG, rounding: float = ROUNDING,
                   density: float = DENSITY):
    """A ``width`` x ``height`` DEM block standing on a base shaken by ``motion`` (a
    :class:`~murus.motion.core.GroundMotion`, horizontal), with joint contact damping ``zeta``:
    its rotation history.

    Parameters
    ----------
    width, height : float
        Block [m].
    zeta : float
        Contact damping of the joint.
    motion : murus.motion.core.GroundMotion
        Base acceleration.
    duration : float, optional
        Length of the run [s] (default: the record's, plus 2 s).
    kn, friction_deg, rounding, density : float
        As in :func:`free_rocking`.

    Returns
    -------
    tuple of ndarray
        ``(t, theta)`` [s, rad] (theta counter-clockwise, sampled every step).
    """
    from murus.dem import engine as E
    from murus.dem.materials import Joint
    from murus.dem.verify import block_on_base

    joint = Joint(kn=kn, ks=kn, friction_deg=friction_deg, contact_damping=zeta)
    m, base, blk = block_on_base(width, height, joint, base="base", rounding=rounding)
    for b in m._bodies:
        b["density"] = density
    m.set_base_motion(motion)
    if duration is None:
        duration = motion.dt * motion.acc.size + 2.0
    res = m.run(duration, probes={"a": E.body_probe(blk, "angle")}, every=4)
    return np.asarray(res.t), np.asarray(res["a"])


def restitutions(t, theta, omega, alpha, p2, window=0.1, band=0.5):
    """Restitution of each impact and the peak angles of a free-rocking history.

    The history is cut into half-cycles (runs of one sign of theta among the samples with
    ``|theta| >= window alpha``). In each, the rigid rocking about the corner keeps ``H =
    omega² + 2 p2 cos(alpha - |theta|)`` constant; ``H_k`` is its median over the samples with
    ``|theta|`` at least ``band`` times the half-cycle's peak (away from the impact, whose
    bounce on the stiff contacts spans the first degrees after it). The impact between
    half-cycles k and k + 1 has ``e = omega_after / omega_before`` at theta = 0 of the rigid
    motions: ``e² = (H_{k+1} - C) / (H_k - C)``, ``C = 2 p2 cos(alpha)`` (Housner's ratio).

    Parameters
    ----------
    t, theta, omega : ndarray
        History [s, rad, rad/s].
    alpha : float
        Slenderness [rad].
    p2 : float
        ``m g R / I_O`` [1/s²].
    window, band : float
        Fractions of alpha and of the peak (above).

    Returns
    -------
    tuple of ndarray
        ``(e, peaks)``: the restitution of each impact, the peak ``|theta|`` [rad] of each
        complete half-cycle (the first: the release angle).
    """
    idx = np.nonzero(np.abs(theta) >= window * alpha)[0]
    if idx.size == 0:
        return np.zeros(0), np.zeros(0)
    sg = np.sign(theta[idx])
    breaks = np.nonzero(sg[1:] != sg[:-1])[0] + 1
    C = 2.0 * p2 * math.cos(alpha)
    H = []
    peaks = []
    for seg in np.split(idx, breaks):
        a = np.abs(theta[seg])
        w = omega[seg]
        # complete: its peak inside (omega changes sign, or the release at rest)
        if not (np.any(w[1:] * w[:-1] <= 0.0) or w[0] == 0.0):
            break
        pk = float(a.max())
        sel = seg[a >= band * pk]
        H.append(float(np.median(omega[sel] ** 2 + 2.0 * p2 * np.cos(alpha - np.abs(theta[sel])))))
        peaks.append(pk)
    H = np.array(H)
    e = np.sqrt(np.maximum(H[1:] - C, 0.0) / (H[:-1] - C)) if H.size > 1 else np.zeros(0)
    return e, np.array(peaks)


@lru_cache(maxsize=256)
def _mean_e(width, height, z, n_impacts, kn, friction_deg, rounding, density) -> float:
    """Mean restitution of the first ``n_impacts`` impacts of :func:`free_rocking` (cached:
    the calibrations of one block share their runs at zeta = 0 and 1)."""
    r = free_rocking(width, height, z, n_impacts=n_impacts, kn=kn, friction_deg=friction_deg,
                     rounding=rounding, density=density)
    if r.e.size < n_impacts:
        raise CalibrationError(f"zeta {z:.4g}: the block stopped rocking after {r.e.size} "
                               "impacts")
    return float(np.mean(r.e[:n_impacts]))


@lru_cache(maxsize=64)
def calibrate(width: float, height: float, e_target: float, *, kn: float = KN,
              friction_deg: float = FRICTION_DEG, rounding: float = ROUNDING,
              density: float = DENSITY, n_impacts: int = 3, tol: float = 0.002,
              max_runs: int = 8) -> float:
    """The contact damping zeta whose DEM block rocks with the restitution ``e_target`` (the
    mean over its first ``n_impacts`` impacts, released from alpha/2), by the secant method on
    free-rocking runs (:func:`free_rocking`); cached per argument set.

    Parameters
    ----------
    width, height : float
        Block [m].
    e_target : float
        Target restitution per impact (e.g. Housner's, ``1 - 1.5 sin²(alpha)``).
    kn, friction_deg, rounding, density : float
        As in the model to calibrate.
    n_impacts : int
        Impacts averaged per run.
    tol : float
        Absolute tolerance on e.
    max_runs : int
        Largest number of DEM runs.

    Returns
    -------
    float
        zeta.

    Raises
    ------
    CalibrationError
        When ``e_target`` is outside the reachable range: above the undamped block's
        restitution, or below the one at zeta = 1 (close to Housner's value: the dashpot
        acting on the closing corner can at most make that impact plastic, which is Housner's
        assumption), or not reached in ``max_runs`` runs.
    """
    if not (0.0 < e_target < 1.0):
        raise CalibrationError(f"target restitution must be in (0, 1), got {e_target!r}")

    def e_of(z):
        return _mean_e(width, height, float(z), n_impacts, kn, friction_deg, rounding, density)

    z0, e0 = 0.0, e_of(0.0)
    if e_target > e0 + tol:
        raise CalibrationError(f"target restitution {e_target:.4g} is above the undamped "
                               f"block's {e0:.4g}: contact damping only lowers it")
    if abs(e0 - e_target) <= tol:
        return 0.0
    e_max = e_of(1.0)
    if e_target < e_max - tol:
        raise CalibrationError(f"target restitution {e_target:.4g} is below the block's "
                               f"{e_max:.4g} at contact_damping = 1 (a plastic impact on the "
                               "new corner, Housner's limit): not reachable by contact damping")
    if abs(e_max - e_target) <= tol:
        return 1.0
    z1 = min(1.0, point_zeta(max(math.exp(-1.0), 1.0 - (e0 - e_target))))
    e1 = e_of(z1)
    for _ in range(max_runs - 2):
        if abs(e1 - e_target) <= tol:
            return z1
        if e1 == e0:
            break
        z2 = z1 + (e_target - e1) * (z1 - z0) / (e1 - e0)
        z2 = min(1.0, max(0.0, z2))
        z0, e0 = z1, e1
        z1, e1 = z2, e_of(z2)
    if abs(e1 - e_target) <= tol:
        return z1
    raise CalibrationError(f"restitution {e_target:.4g} not reached: zeta {z1:.4g} gives "
                           f"{e1:.4g}")

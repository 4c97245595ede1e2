"""Pseudo-static active thrust by a trial-wedge (Coulomb) search, planar or broken backfill.

The soil wedge between the back face of the wall and a planar failure surface through the heel
is in limit equilibrium under its weight and pseudo-static inertia ``gamma A (-kh, -(1 - kv))``
(``kh`` towards the wall, ``kv`` positive upwards, as in :mod:`murus.eurocode.ec8_5`), the
reaction of the wall (inclined by ``delta`` to the normal of the back face, upwards on the
wedge) and the reaction of the soil below the failure plane (inclined by ``phi`` to its
normal). The active thrust is the maximum over the inclination ``rho`` of the failure plane.
For a planar backfill it equals the Mononobe-Okabe value of EN 1998-5 (E.1)-(E.2) (Coulomb's
for ``kh = kv = 0``); a broken backfill (a polyline) needs the search. This is the "Coulomb's
wedge of soil" of Savalle et al. (2022), §4.4.

Local frame: the heel at the origin, ``x`` into the backfill, ``z`` upwards; the back face goes
up from the heel to the crest, where the backfill surface starts; ``psi`` is its inclination to
the horizontal measured on the wall side, as in EN 1998-5 Annex E (``pi/2`` vertical, less when
the soil rests on the back face). The thrust on the wall is
``-thrust (sin(psi - delta), cos(psi - delta))``. Units: m, N/m³, N per metre, radians.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from murus.errors import MurusError

__all__ = ["WedgeError", "WedgeResult", "trial_wedge"]


class WedgeError(MurusError, ValueError):
    """No finite trial-wedge thrust for these inputs (one-line message)."""


@dataclass(frozen=True)
class WedgeResult:
    """Active thrust ``thrust`` [N/m] on a back face of vertical height ``height`` [m], the
    critical failure-plane inclination ``rho`` [rad] to the horizontal, and the equivalent
    coefficient ``K = 2 thrust / (gamma (1 - kv) height²)`` of EN 1998-5 (E.1).

    Attributes
    ----------
    thrust : float
        [N/m].
    rho : float
        Inclination of the failure plane [rad].
    K : float
        Equivalent coefficient [-].
    height : float
        Vertical height of the back face [m].
    """

    thrust: float
    rho: float
    K: float
    height: float


def _surface(top, profile, beta):
    """Surface vertices from the crest, and the direction of the last (infinite) segment."""
    pts = [top]
    if profile:
        pts += [(top[0] + dx, top[1] + dz) for dx, dz in profile]
        (x0, z0), (x1, z1) = pts[-2], pts[-1]
        n = math.hypot(x1 - x0, z1 - z0)
        last = ((x1 - x0) / n, (z1 - z0) / n)
    else:
        last = (math.cos(beta), math.sin(beta))
    return pts, last


def _wedge_areas(rho, pts, last) -> np.ndarray:
    """Areas of the wedges for failure planes at ``rho`` (array) through the heel (origin);
    NaN where the plane does not meet the surface beyond the crest."""
    rho = np.atleast_1d(np.asarray(rho, dtype=float))
    ux, uz = np.cos(rho), np.sin(rho)
    area2 = np.full(rho.shape, np.nan)
    chain = 0.0  # signed shoelace sum of p_i -> p_(i-1) -> ... -> p_0
    for i in range(len(pts)):
        p = pts[i]
        if i > 0:
            q = pts[i - 1]
            chain += p[0] * q[1] - q[0] * p[1]
        if i < len(pts) - 1:
            d = (pts[i + 1][0] - p[0], pts[i + 1][1] - p[1])
            infinite = False
        else:
            d = last
            infinite = True
        den = ux * d[1] - uz * d[0]
        with np.errstate(divide="ignore", invalid="ignore"):
            s = (p[0] * d[1] - p[1] * d[0]) / den
            t = (p[0] * uz - p[1] * ux) / den
        ok = (np.abs(den) > 1e-15) & (s > 0) & (t >= 0) & (infinite | (t <= 1.0))
        ok &= np.isnan(area2)
        if np.any(ok):
            # polygon origin -> D -> p_i -> ... -> p_0 -> origin
            Dx, Dz = s[ok] * ux[ok], s[ok] * uz[ok]
            area2[ok] = Dx * p[1] - p[0] * Dz + chain
    return 0.5 * np.abs(area2)


def trial_wedge(height: float, phi: float, delta: float = 0.0, gamma: float = 1.0,
                kh: float = 0.0, kv: float = 0.0, psi: float = 0.5 * math.pi,
                beta: float = 0.0, profile=None, n_grid: int = 241) -> WedgeResult:
    """Maximum pseudo-static thrust over planar failure surfaces through the heel.

    Parameters
    ----------
    height : vertical height of the back face [m].
    phi, delta : friction of the backfill and of the wall-backfill interface [rad].
    gamma : unit weight of the backfill [N/m³].
    kh, kv : seismic coefficients (``kh`` towards the wall, ``kv`` positive upwards).
    psi : back face to the horizontal, wall side (EN 1998-5) [rad].
    beta : slope of a planar backfill [rad] (ignored when ``profile`` is given).
    profile : broken backfill, points ``(dx, dz)`` [m] from the crest with ``dx`` increasing;
        the last segment extends to infinity.
    n_grid : points of the coarse search before the local refinement (bounded Brent).
    """
    from scipy.optimize import minimize_scalar

    if not height > 0:
        raise WedgeError(f"the back face height must be positive, got {height!r} m")
    if not 0 < phi < 0.5 * math.pi or not 0 <= delta <= phi + 1e-12:
        raise WedgeError("need 0 < phi < pi/2 and 0 <= delta <= phi (rad)")
    if kv >= 1 or kh < 0:
        raise WedgeError("need kh >= 0 and kv < 1")
    if not 0 < psi < math.pi:
        raise WedgeError(f"psi must be in (0, pi) rad, got {psi!r}")
    top = (-height * math.cos(psi) / math.sin(psi), height)
    pts, last = _surface(top, profile, beta)
    slope_last = math.atan2(last[1], last[0])
    theta = math.atan2(kh, 1.0 - kv)
    if slope_last > phi - theta + 1e-12:
        raise WedgeError(
            f"the (last) backfill slope {math.degrees(slope_last):.2f} deg exceeds phi - theta "
            f"= {math.degrees(phi - theta):.2f} deg: the slope itself is unstable, no finite "
            "trial-wedge maximum (EN 1998-5 (E.3) is a convention for this case)")
    if gamma == 0.0:
        return WedgeResult(0.0, float("nan"), 0.0, height)
    # reaction of the wall on the wedge: normal into the soil turned by delta, upwards
    dP = (math.sin(psi - delta), math.cos(psi - delta))
    body = (-kh, -(1.0 - kv))

    def thrust(rho):
        r = np.atleast_1d(np.asarray(rho, dtype=float))
        area = _wedge_areas(r, pts, last)
        # reaction of the soil below, inclined by phi to the normal, friction up the plane
        dRx = -np.sin(r) * math.cos(phi) + np.cos(r) * math.sin(phi)
        dRz = np.cos(r) * math.cos(phi) + np.sin(r) * math.sin(phi)
        fx, fz = -gamma * area * body[0], -gamma * area * body[1]
        det = dP[0] * dRz - dP[1] * dRx
        with np.errstate(divide="ignore", invalid="ignore"):
            P = (fx * dRz - fz * dRx) / det
        return np.where(np.isfinite(P) & (np.abs(det) > 1e-15), P, -np.inf)

    lo = max(slope_last, -0.5 * math.pi + 1e-6) + 1e-9
    hi = math.pi - psi - 1e-9
    grid = np.linspace(lo, hi, int(n_grid))
    vals = thrust(grid)
    if not np.any(np.isfinite(vals)):
        raise WedgeError("no trial wedge meets the backfill surface")
    i = int(np.nanargmax(np.where(np.isfinite(vals), vals, -np.inf)))
    if i == 0 and profile is None:
        raise WedgeError("the thrust grows without bound towards the backfill slope")
    a, b = grid[max(i - 1, 0)], grid[min(i + 1, len(grid) - 1)]
    res = minimize_scalar(lambda r: -float(thrust(r)[0]), bounds=(a, b), method="bounded",
                          options={"xatol": 1e-12})
    rho, P = (float(res.x), -float(res.fun)) if -res.fun >= vals[i] else (float(grid[i]),
                                                                         float(vals[i]))
    K = 2.0 * P / (gamma * (1.0 - kv) * height * height)
    return WedgeResult(P, rho, K, height)

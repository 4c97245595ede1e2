"""EN 1998-5:2004 (Eurocode 8, part 5) Annex E: pseudo-static earth thrust on retaining walls.

Clauses implemented (dry backfill only: water table below the wall, so ``gamma* = gamma`` and
``E_ws = E_wd = 0``, Annex E eqs (E.5) and (E.7)):

- §7.3.2.2 seismic coefficients: ``kh = alpha S / r`` (7.1), ``kv = +-0.5 kh`` when
  ``avg / ag > 0.6`` and ``+-0.33 kh`` otherwise (7.2, 7.3), Table 7.1 for ``r``;
- Annex E eq (E.1): total design thrust ``E_d = 1/2 gamma* (1 -+ kv) K H²``;
- Annex E eqs (E.2) and (E.3): active earth pressure coefficient (Mononobe-Okabe), both
  branches, ``beta <= phi - theta`` and ``beta > phi - theta``;
- Annex E eq (E.6): the seismic angle ``tan theta = kh / (1 -+ kv)`` (water table below the
  wall);
- §7.3.2.3(4)-(5): points of application (see :func:`application_heights`).

Angles are in radians, unit weights in N/m³, heights in m, thrusts in N per metre of wall.

Sign conventions (written once, here):

- ``psi`` is the inclination of the back of the wall to the horizontal as in Annex E, measured
  on the wall side (under the back face): ``psi = pi/2`` for a vertical back, ``psi < pi/2``
  when the wall widens downwards on its back so that the soil rests on the back face (larger
  thrust), ``psi > pi/2`` when the back overhangs the wall's base (the formula (E.2) read with
  this angle is what a trial wedge gives, tests/eurocode/test_ec8_5.py);
- ``beta`` is the backfill slope, positive rising away from the wall;
- ``delta`` is the wall friction angle (soil-wall), the thrust being inclined by ``delta`` to
  the normal of the back face, downwards on the wall (active state);
- ``kh >= 0`` is the horizontal seismic coefficient with the inertia pushing the soil against
  the wall; ``kv`` is signed, **positive when the vertical inertia force acts upwards** (it
  reduces gravity): the standard's pair of signs ``(1 +- kv)`` in (E.1) and ``kh / (1 -+ kv)``
  in (E.6) both become ``(1 - kv)`` here, which is what a trial-wedge equilibrium with the
  body force ``(-kh, -(1 - kv)) gamma`` gives (tests/eurocode/test_ec8_5.py). Both signs of
  ``kv`` must be checked (``kv = +-0.5 kh`` in (7.2)); :func:`total_thrust` takes one.

Validity limits (the ``PARAMS`` of each function): ``0 < phi < pi/2``, ``0 <= delta <= phi``,
``0 < psi < pi``, ``|beta| < pi/2``, ``kh >= 0``, ``kv < 1``, ``sin(psi - theta - delta) > 0``
and ``sin(psi + beta) > 0``. The branch (E.3) is the standard's convention for slopes steeper
than the seismic angle allows (an infinite planar slope is then unstable and a trial wedge has
no finite maximum).
"""

from __future__ import annotations

import math

from murus.errors import MurusError

__all__ = [
    "EC85Error", "R_FACTORS", "seismic_angle", "active_coefficient", "coulomb_coefficient",
    "rankine_coefficient", "total_thrust", "thrust_components", "application_heights",
    "horizontal_coefficient", "vertical_coefficient",
]


class EC85Error(MurusError, ValueError):
    """Input outside the validity limits of EN 1998-5 Annex E (one-line message)."""


#: EN 1998-5 Table 7.1: factor r by type of retaining structure (recommended values). The
#: displacements are the admissible ones, in mm, times ``alpha S``.
R_FACTORS = {
    "free gravity wall, displacement up to 300 alpha S mm": 2.0,
    "free gravity wall, displacement up to 200 alpha S mm": 1.5,
    "flexural RC, anchored or braced wall, wall on vertical piles, restrained basement wall, "
    "bridge abutment": 1.0,
}


def _finite(name: str, value) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise EC85Error(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(v):
        raise EC85Error(f"{name} must be finite, got {value!r}")
    return v


def seismic_angle(kh: float, kv: float = 0.0) -> float:
    """Seismic angle ``theta = atan(kh / (1 - kv))`` [rad], EN 1998-5 Annex E eq (E.6).

    ``kh >= 0``; ``kv < 1`` positive upwards (module docstring): the standard's
    ``kh / (1 -+ kv)`` with one signed ``kv``. For a tilting table at angle ``t``
    (``kh = sin t``, ``kv = 1 - cos t``) this gives ``theta = t``.

    Parameters
    ----------
    kh : float
        Horizontal seismic coefficient [-] (>= 0).
    kv : float
        Vertical seismic coefficient [-], positive upward (< 1).

    Returns
    -------
    float
        theta [rad].
    """
    kh, kv = _finite("kh", kh), _finite("kv", kv)
    if kh < 0:
        raise EC85Error(f"kh must be >= 0 (inertia towards the wall), got {kh!r}")
    if kv >= 1:
        raise EC85Error(f"kv must be < 1 (the effective gravity 1 - kv must stay positive), "
                        f"got {kv!r}")
    return math.atan2(kh, 1.0 - kv)


def _check_angles(phi, beta, delta, psi, theta) -> tuple[float, ...]:
    phi, beta = _finite("phi", phi), _finite("beta", beta)
    delta, psi, theta = _finite("delta", delta), _finite("psi", psi), _finite("theta", theta)
    if not 0.0 < phi < 0.5 * math.pi:
        raise EC85Error(f"phi must be in (0, pi/2) rad, got {phi!r}")
    if not 0.0 <= delta <= phi + 1e-12:
        raise EC85Error(f"the wall friction delta must be in [0, phi] rad, got {delta!r} "
                        f"(phi = {phi!r})")
    if not 0.0 < psi < math.pi:
        raise EC85Error(f"psi (back of the wall to the horizontal) must be in (0, pi) rad, "
                        f"got {psi!r}")
    if not abs(beta) < 0.5 * math.pi:
        raise EC85Error(f"beta must be in (-pi/2, pi/2) rad, got {beta!r}")
    if not 0.0 <= theta < 0.5 * math.pi:
        raise EC85Error(f"theta must be in [0, pi/2) rad, got {theta!r}")
    if math.sin(psi - theta - delta) <= 0.0:
        raise EC85Error("psi - theta - delta must be in (0, pi): the seismic angle is too large "
                        "for this wall (EN 1998-5 (E.2))")
    if math.sin(psi + beta) <= 0.0:
        raise EC85Error("psi + beta must be in (0, pi): the backfill overhangs the wall")
    return phi, beta, delta, psi, theta


def active_coefficient(phi: float, beta: float = 0.0, delta: float = 0.0,
                       psi: float = 0.5 * math.pi, theta: float = 0.0) -> float:
    """Active earth pressure coefficient K, EN 1998-5 Annex E eqs (E.2) and (E.3).

    If ``beta <= phi - theta`` (E.2)::

        K = sin²(psi + phi - theta) / { cos(theta) sin²(psi) sin(psi - theta - delta)
            [1 + sqrt( sin(phi + delta) sin(phi - beta - theta)
                       / (sin(psi - theta - delta) sin(psi + beta)) )]² }

    otherwise (E.3)::

        K = sin²(psi + phi - theta) / { cos(theta) sin²(psi) sin(psi - theta - delta) }

    The two branches meet at ``beta = phi - theta``. All angles in radians (module docstring
    for the conventions). With ``theta = 0`` this is Coulomb's coefficient
    (:func:`coulomb_coefficient`). The thrust ``1/2 gamma (1 - kv) K H²`` uses the vertical
    height H of the back face and is inclined by ``delta`` to its normal.

    Parameters
    ----------
    phi : float
        Friction angle of the backfill [rad].
    beta : float
        Inclination of the backfill surface [rad].
    delta : float
        Wall friction angle [rad].
    psi : float
        Inclination of the back face to the horizontal [rad] (pi/2: vertical).
    theta : float
        Seismic angle [rad] (:func:`seismic_angle`).

    Returns
    -------
    float
        K [-].
    """
    phi, beta, delta, psi, theta = _check_angles(phi, beta, delta, psi, theta)
    num = math.sin(psi + phi - theta) ** 2
    den = math.cos(theta) * math.sin(psi) ** 2 * math.sin(psi - theta - delta)
    if beta <= phi - theta:
        ratio = (math.sin(phi + delta) * math.sin(phi - beta - theta)
                 / (math.sin(psi - theta - delta) * math.sin(psi + beta)))
        den *= (1.0 + math.sqrt(max(ratio, 0.0))) ** 2
    return num / den


def coulomb_coefficient(phi: float, beta: float = 0.0, delta: float = 0.0,
                        psi: float = 0.5 * math.pi) -> float:
    """Static (Coulomb) active coefficient: EN 1998-5 (E.2) with ``theta = 0``.

    ``beta > phi`` has no static active state (the slope itself is unstable): an error.

    Parameters
    ----------
    phi : float
        Friction angle of the backfill [rad].
    beta : float
        Inclination of the backfill surface [rad].
    delta : float
        Wall friction angle [rad].
    psi : float
        Inclination of the back face to the horizontal [rad] (pi/2: vertical).

    Returns
    -------
    float
        K_A [-].
    """
    if _finite("beta", beta) > _finite("phi", phi):
        raise EC85Error(f"the backfill slope beta = {beta!r} rad exceeds phi = {phi!r} rad: "
                        "no static active state")
    return active_coefficient(phi, beta, delta, psi, 0.0)


def rankine_coefficient(phi: float) -> float:
    """Rankine's ``tan²(pi/4 - phi/2)``: vertical smooth back, level backfill [-].

    Parameters
    ----------
    phi : float
        Friction angle [rad].

    Returns
    -------
    float
        K_A [-].
    """
    phi = _finite("phi", phi)
    if not 0.0 < phi < 0.5 * math.pi:
        raise EC85Error(f"phi must be in (0, pi/2) rad, got {phi!r}")
    return math.tan(0.25 * math.pi - 0.5 * phi) ** 2


def total_thrust(gamma: float, H: float, K: float, kv: float = 0.0) -> float:
    """Total design thrust ``E_d = 1/2 gamma* (1 - kv) K H²`` [N/m], EN 1998-5 eq (E.1).

    Dry backfill (water table below the wall): ``gamma* = gamma`` (E.5), no water terms
    (``E_ws = 0``, ``E_wd = 0`` (E.7)). ``gamma`` [N/m³] the unit weight of the backfill, ``H``
    [m] the vertical height of the back face, ``K`` from :func:`active_coefficient` with the
    same ``kv`` (positive upwards) in its ``theta``.

    Parameters
    ----------
    gamma : float
        Unit weight of the backfill [N/m³].
    H : float
        Vertical height of the back face [m].
    K : float
        Earth pressure coefficient [-].
    kv : float
        Vertical seismic coefficient [-], positive upward.

    Returns
    -------
    float
        E_d [N/m].
    """
    gamma, H, K, kv = (_finite("gamma", gamma), _finite("H", H), _finite("K", K),
                       _finite("kv", kv))
    if gamma < 0:
        raise EC85Error(f"the unit weight gamma must be >= 0 N/m3, got {gamma!r}")
    if H < 0:
        raise EC85Error(f"the height H must be >= 0 m, got {H!r}")
    if K < 0:
        raise EC85Error(f"the coefficient K must be >= 0, got {K!r}")
    if kv >= 1:
        raise EC85Error(f"kv must be < 1, got {kv!r}")
    return 0.5 * gamma * (1.0 - kv) * K * H * H


def thrust_components(gamma: float, H: float, phi: float, kh: float, kv: float = 0.0,
                      beta: float = 0.0, delta: float = 0.0,
                      psi: float = 0.5 * math.pi) -> tuple[float, float]:
    """Static thrust and dynamic increment ``(E_static, dE)`` [N/m] for a dry backfill.

    ``E_static = 1/2 gamma K_A H²`` (Coulomb, ``theta = 0``, ``kv = 0``) and
    ``dE = E_d - E_static`` with ``E_d`` of eq (E.1) for ``theta`` of eq (E.6) (§7.3.2.3(3):
    the design force is the resultant of the static and dynamic pressures). ``dE`` may be
    negative for a large upward ``kv``.

    Parameters
    ----------
    gamma : float
        Unit weight of the backfill [N/m³].
    H : float
        Vertical height of the back face [m].
    phi : float
        Friction angle of the backfill [rad].
    kh, kv : float
        Seismic coefficients [-] (``kv`` positive upward).
    beta, delta, psi : float
        Backfill slope, wall friction and back-face inclination [rad].

    Returns
    -------
    tuple of float
        ``(E_static, dE)`` [N/m].
    """
    K_s = coulomb_coefficient(phi, beta, delta, psi)
    K_d = active_coefficient(phi, beta, delta, psi, seismic_angle(kh, kv))
    E_s = total_thrust(gamma, H, K_s, 0.0)
    return E_s, total_thrust(gamma, H, K_d, kv) - E_s


def application_heights(H: float, dynamic: str = "mid-height") -> tuple[float, float]:
    """Heights above the heel of the static thrust and of the dynamic increment [m].

    The static thrust acts at ``H/3`` (triangular pressure). EN 1998-5 §7.3.2.3(4): the force
    due to the dynamic earth pressure acts at mid-height in the absence of a more detailed
    study (``dynamic="mid-height"``); §7.3.2.3(5): for walls free to rotate about their toe it
    may act at the same point as the static force (``dynamic="static"``, ``H/3``).

    Parameters
    ----------
    H : float
        Vertical height of the back face [m].
    dynamic : str
        ``"mid-height"`` or ``"static"``.

    Returns
    -------
    tuple of float
        Heights of the static thrust and of the dynamic increment [m].
    """
    H = _finite("H", H)
    if H < 0:
        raise EC85Error(f"the height H must be >= 0 m, got {H!r}")
    if dynamic == "mid-height":
        return H / 3.0, 0.5 * H
    if dynamic == "static":
        return H / 3.0, H / 3.0
    raise EC85Error(f"dynamic must be 'mid-height' (§7.3.2.3(4)) or 'static' (§7.3.2.3(5)), "
                    f"got {dynamic!r}")


def horizontal_coefficient(alpha: float, S: float = 1.0, r: float = 1.0) -> float:
    """``kh = alpha S / r``, EN 1998-5 eq (7.1); ``alpha = ag / g``, ``r`` of Table 7.1.

    Parameters
    ----------
    alpha : float
        ``ag / g`` [-].
    S : float
        Soil factor [-].
    r : float
        Factor of EN 1998-5 Table 7.1 [-].

    Returns
    -------
    float
        kh [-].
    """
    alpha, S, r = _finite("alpha", alpha), _finite("S", S), _finite("r", r)
    if alpha < 0 or S <= 0 or r <= 0:
        raise EC85Error("alpha must be >= 0, S and r positive (EN 1998-5 (7.1))")
    return alpha * S / r


def vertical_coefficient(kh: float, avg_over_ag: float = 0.9) -> float:
    """``|kv| = 0.5 kh`` if ``avg / ag > 0.6`` (7.2), else ``0.33 kh`` (7.3), EN 1998-5 §7.3.2.2.

    The standard writes ``kv = +-0.5 kh``: the sign is the user's, check both.

    Parameters
    ----------
    kh : float
        Horizontal seismic coefficient [-].
    avg_over_ag : float
        Ratio of the vertical to the horizontal design ground acceleration [-].

    Returns
    -------
    float
        ``|kv|`` [-].
    """
    kh, ratio = _finite("kh", kh), _finite("avg_over_ag", avg_over_ag)
    if kh < 0 or ratio < 0:
        raise EC85Error("kh and avg/ag must be >= 0")
    return (0.5 if ratio > 0.6 else 0.33) * kh

"""Design of a restrained rocking wall: tie, spring bed, resonance, damper (EURODYN (2020), §2-3).

EURODYN (2020) studies a wall rocking in one-sided motion: a horizontal
tie (stiffness ``K``, optionally with a viscous damper ``c``) restrains the clockwise rotation about
the outer corner O, and the transverse walls, modelled as a bed of horizontal springs of stiffness
``K'`` per unit height, restrain the anticlockwise rotation about O'. This module collects the
design equations of that paper:

- eq. 8 and 9: resonance frequencies of the two one-sided systems, next to the linearised
  frequencies they approximate (:func:`resonance_frequencies`);
- eq. 10 and 11: spring bed stiffness from the transverse walls or by equating the two systems
  (:func:`bed_stiffness_from_walls`, :func:`bed_stiffness_equal`);
- eq. 12: steel tie rod by static equilibrium (:func:`tie_design`);
- eq. 13: reference damping coefficient (:func:`reference_damping`).

Geometry and sign convention (as :mod:`murus.rocking.body`): ``theta > 0`` is clockwise about the
right corner O at ``x = +b/2``; O' is the left corner at ``x = -b/2``. A point of the wall is given
by its height ``y`` above the base and its horizontal position ``x`` in the body frame (0 at
mid-thickness). SI units throughout: m, kg, s, N, N/m (tie), N/m/m = N/m² (spring bed per unit
height), N s/m (damper), rad, rad/s.

>>> from murus.rocking import restrained_wall_block
>>> blk = restrained_wall_block("block1")
>>> round(bed_stiffness_from_walls(1.5e9, 0.3, 1.0))     # EURODYN (2020), §4.2: K' = 4.5e8 N/m/m
450000000
>>> td = tie_design(blk)
>>> round(td.T_d, 1), round(td.phi_d * 1000, 2)           # N, mm
(945.0, 2.05)
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

from murus import G
from murus.errors import MurusError
from murus.rocking.body import RigidBlock


class DesignError(MurusError, ValueError):
    """An invalid design input (one-line message naming the parameter)."""


#: Commercial diameters of steel tie rods [mm] used by ``tie_design(round_to_commercial=True)``.
COMMERCIAL_DIAMETERS_MM = (8, 10, 12, 14, 16, 20, 24, 27, 30, 36)

#: Ultimate tensile strength of S275 steel [Pa]: EN 1993-1-1:2005 Table 3.1 (steel to
#: EN 10025-2, nominal thickness t <= 40 mm), f_u = 430 MPa.
S275_FU = 430e6

#: Young's modulus of structural steel [Pa] (EN 1993-1-1 §3.2.6).
STEEL_E = 210e9


# -- validation ------------------------------------------------------------------------------
def _number(name: str, value) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise DesignError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(v):
        raise DesignError(f"{name} must be a finite number, got {value!r}")
    return v


def _positive(name: str, value, unit: str = "") -> float:
    v = _number(name, value)
    if v <= 0.0:
        u = f" {unit}" if unit else ""
        raise DesignError(f"{name} must be a positive finite number, got {v!r}{u}")
    return v


def _non_negative(name: str, value, unit: str = "") -> float:
    v = _number(name, value)
    if v < 0.0:
        u = f" {unit}" if unit else ""
        raise DesignError(f"{name} must be a non-negative finite number, got {v!r}{u}")
    return v


def _body(body) -> RigidBlock:
    if not isinstance(body, RigidBlock):
        raise DesignError(f"body must be a RigidBlock, got {type(body).__name__}")
    return body


def _height_on_wall(body: RigidBlock, value, what: str = "tie height") -> float:
    """A height in (0, h] [m]; ``None`` gives the top of the wall."""
    if value is None:
        return body.height
    y = _number(what, value)
    if y <= 0.0:
        raise DesignError(f"{what} must be positive, got {y!r} m")
    if y > body.height * (1.0 + 1e-12):
        raise DesignError(f"{what} {y!r} m is above the wall (h = {body.height!r} m)")
    return min(y, body.height)


def _x_on_wall(body: RigidBlock, value, what: str = "tie x") -> float:
    x = _number(what, value)
    half = 0.5 * body.width
    if abs(x) > half * (1.0 + 1e-12):
        raise DesignError(
            f"{what} {x!r} m is outside the wall thickness [{-half!r}, {half!r}] m"
        )
    return max(-half, min(half, x))


def _nan_to_none(v):
    if isinstance(v, float) and math.isnan(v):
        return None
    return v


# -- geometry --------------------------------------------------------------------------------
@dataclass(frozen=True)
class TieGeometry:
    """Lever quantities of a point of the wall (a tie or damper anchorage), EURODYN (2020), eq. 2
    and 7.

    Attributes (SI): ``height`` [m] above the base and ``x`` [m] in the body frame; ``R_t`` [m]
    the distance from the pivot O (x = +b/2) to the point and ``alpha_t`` [rad] the angle between
    that segment and the vertical (``R_t``, ``alpha_t`` of eq. 2; ``R_d``, ``alpha_d`` of eq. 7);
    ``R_t_neg``, ``alpha_t_neg`` the same about the pivot O' (x = -b/2).
    """

    height: float
    x: float
    R_t: float
    alpha_t: float
    R_t_neg: float
    alpha_t_neg: float

    @property
    def lever(self) -> float:
        """Lever arm [m] of a horizontal force about either pivot at ``theta = 0``:
        ``R_t cos(alpha_t) = height``."""
        return self.height

    def as_dict(self) -> dict:
        return {**asdict(self), "lever": self.lever}


def tie_geometry(body: RigidBlock, height: float | None = None, x: float = 0.0) -> TieGeometry:
    """Lever quantities of the point at ``height`` [m] above the base and ``x`` [m] across the
    wall (0 = mid-thickness, ``+b/2`` = the face on the side of the pivot O).

    About O at ``(+b/2, 0)``: ``R_t = sqrt((b/2 - x)² + height²)`` and
    ``alpha_t = atan2(b/2 - x, height)`` (EURODYN (2020), eq. 2 notation: in eq. 2 the horizontal
    displacement of the point is ``R_t (sin alpha_t - sin A_t)`` and its lever ``R_t cos A_t``).
    About O' at ``(-b/2, 0)``: ``R_t_neg = sqrt((b/2 + x)² + height²)``,
    ``alpha_t_neg = atan2(b/2 + x, height)``. ``height`` defaults to the top of the wall;
    it must lie in (0, h] and ``x`` in [-b/2, b/2], otherwise :class:`DesignError`.
    """
    body = _body(body)
    y = _height_on_wall(body, height)
    x = _x_on_wall(body, x)
    half = 0.5 * body.width
    return TieGeometry(
        height=y,
        x=x,
        R_t=math.hypot(half - x, y),
        alpha_t=math.atan2(half - x, y),
        R_t_neg=math.hypot(half + x, y),
        alpha_t_neg=math.atan2(half + x, y),
    )


# -- spring bed (eq. 10, 11) -----------------------------------------------------------------
def bed_stiffness_from_walls(E_x: float, t: float, L_eff: float) -> float:
    """Stiffness of the spring bed of the transverse walls, ``K' = E_x t / L_eff`` (EURODYN (2020)
    eq. 10) [N/m per m of height = N/m²].

    ``E_x`` [Pa] equivalent lateral elastic modulus of the transverse walls, ``t`` [m] their
    thickness, ``L_eff`` [m] their effective length. EURODYN (2020), §4.3: ``E_x = 1.5e9`` (printed
    "N/m/m", a modulus in Pa), ``t = 0.3 m``, ``L_eff = 1.0 m`` give ``K' = 4.5e8 N/m/m``, the
    value used in §4.2.
    """
    E_x = _positive("E_x", E_x, "Pa")
    t = _positive("t", t, "m")
    L_eff = _positive("L_eff", L_eff, "m")
    return E_x * t / L_eff


def bed_stiffness_equal(
    body: RigidBlock, K: float, tie_height: float | None = None, tie_x: float = 0.0
) -> float:
    """Spring bed stiffness [N/m/m] that makes the two one-sided systems equally stiff,
    EURODYN (2020) eq. 11 as printed: ``K' = K (3/8) R_t² / (R³ cos(alpha))``.

    ``K`` [N/m] is the tie stiffness, ``R_t`` the distance from the pivot O to the tie (at
    ``tie_height``, ``tie_x``; default top, mid-thickness), ``R`` and ``alpha`` those of the body.
    Dimensions: N/m x m² / m³ = N/m², a stiffness per unit height, as ``K'``.

    Equating the radicands of eq. 8 and eq. 9, ``K R_t² / (m g R) = 8 K' R² / (3 m g)``, gives
    ``K' = 3 K R_t² / (8 R³)``, without the ``cos(alpha)`` of the printed eq. 11 (a factor
    ``1/cos(alpha)``, 0.5 % for ``lambda = 10``). The printed form is kept here; the value without
    ``cos(alpha)`` is ``bed_stiffness_equal(...) * cos(body.alpha)``.
    """
    body = _body(body)
    K = _non_negative("K", K, "N/m")
    geo = tie_geometry(body, tie_height, tie_x)
    return K * 3.0 / 8.0 * geo.R_t**2 / (body.R**3 * math.cos(body.alpha))


# -- resonance (eq. 8, 9) --------------------------------------------------------------------
@dataclass(frozen=True)
class Resonance:
    """Resonance frequencies of the restrained wall [rad/s] (EURODYN (2020), eq. 8, 9) and the
    linearised values they approximate.

    ``omega_plus`` (eq. 8, tie in tension, rotation about O) and ``omega_minus`` (eq. 9, spring
    bed in compression, rotation about O') are NaN when their radicand is negative: the restraint
    is weaker than gravity, the linearised system has no restoring stiffness and does not
    oscillate (the block rocks away from equilibrium until the restraint, growing nonlinearly,
    or an impact stops it). Same for ``omega_plus_lin``, ``omega_minus_lin`` when
    ``K_theta_plus``, ``K_theta_minus`` [N m/rad] are not positive.
    """

    p: float
    K: float
    K_bed: float
    bed_height: float
    tie: TieGeometry
    omega_plus: float
    omega_minus: float
    K_theta_plus: float
    K_theta_minus: float
    omega_plus_lin: float
    omega_minus_lin: float

    @property
    def oscillates_plus(self) -> bool:
        """Whether eq. 8 has a real value (tie stiffer than gravity)."""
        return not math.isnan(self.omega_plus)

    @property
    def oscillates_minus(self) -> bool:
        """Whether eq. 9 has a real value (spring bed stiffer than gravity)."""
        return not math.isnan(self.omega_minus)

    def as_dict(self) -> dict:
        d = {k: _nan_to_none(v) for k, v in asdict(self).items() if k != "tie"}
        d["tie"] = self.tie.as_dict()
        return d


def _sqrt_or_nan(x: float) -> float:
    return math.sqrt(x) if x >= 0.0 else math.nan


def resonance_frequencies(
    body: RigidBlock,
    K: float = 0.0,
    tie_height: float | None = None,
    tie_x: float = 0.0,
    K_bed: float = 0.0,
    g: float = G,
    bed_height: float | None = None,
) -> Resonance:
    """Resonance frequencies [rad/s] of the one-sided restrained wall (EURODYN (2020), §2).

    Parameters
    ----------
    body:
        The wall (:class:`~murus.rocking.body.RigidBlock`), mass ``m`` [kg], ``R`` [m],
        ``alpha`` [rad], ``I_O`` [kg m²].
    K:
        Tie stiffness [N/m] (>= 0), acting on clockwise rotation about O (tension).
    tie_height, tie_x:
        Tie position [m] (default top of the wall, mid-thickness), see :func:`tie_geometry`.
    K_bed:
        Spring bed stiffness ``K'`` [N/m per m of height] (>= 0), acting on anticlockwise
        rotation about O' (compression against the transverse walls).
    g:
        Gravity [m/s²].
    bed_height:
        Effective height ``h'`` [m] of the spring bed, from the base, for the linearised value
        (default: the wall height ``h``; must lie in (0, h]).

    EURODYN (2020) formulas, with ``p = sqrt(m g R / I_O)`` (EURODYN (2020), §2):

    - eq. 8: ``omega_r+ = p sqrt(K R_t² / (m g R) - 1) = sqrt((K R_t² - m g R) / I_O)``;
    - eq. 9: ``omega_r- = p sqrt(8 K' R² / (3 m g) - 1) = sqrt((8 K' R³ / 3 - m g R) / I_O)``.

    Linearised values ``omega = sqrt(K_theta / I_O)`` about ``theta = 0``: the tie term of eq. 2
    linearises to ``K (R_t cos alpha_t)² theta = K y_t² theta`` (``y_t`` = tie height, the
    vertical lever about the pivot), the spring bed term of eq. 6 to ``K' h'³ / 3 theta``
    (``A = O(theta³)``, ``B = O(theta²)``, ``C ~ theta``), and gravity to
    ``-m g R cos(alpha) theta = -m g z_G theta``:

    - ``K_theta+ = K y_t² - m g z_G``;  ``K_theta- = K' h'³ / 3 - m g z_G``.

    Eq. 8 and 9 differ from these in two ways: they use ``m g R`` for ``m g z_G`` (the ``cos
    alpha`` of the gravity term is dropped) and eq. 8 uses ``R_t²`` for ``y_t²`` (equal only for a
    tie on the face at ``x = +b/2``); eq. 9 is the linearised value for a spring bed of height
    ``h' = 2R`` (its hidden assumption: ``(2R)³ / 3 = 8 R³ / 3``), i.e. the diagonal of a uniform
    rectangle, slightly taller than the wall. Values are NaN when a radicand is negative.
    """
    body = _body(body)
    K = _non_negative("K", K, "N/m")
    K_bed = _non_negative("K' (bed stiffness)", K_bed, "N/m/m")
    g = _positive("g", g, "m/s2")
    geo = tie_geometry(body, tie_height, tie_x)
    hb = _height_on_wall(body, bed_height, "bed height")
    m, R, I_O = body.mass, body.R, body.I_O
    mgR = m * g * R
    p = math.sqrt(mgR / I_O)
    omega_plus = p * _sqrt_or_nan(K * geo.R_t**2 / mgR - 1.0)  # eq. 8
    omega_minus = p * _sqrt_or_nan(8.0 * K_bed * R**2 / (3.0 * m * g) - 1.0)  # eq. 9
    grav = m * g * body.z_G  # = m g R cos(alpha)
    k_plus = K * geo.height**2 - grav
    k_minus = K_bed * hb**3 / 3.0 - grav
    return Resonance(
        p=p,
        K=K,
        K_bed=K_bed,
        bed_height=hb,
        tie=geo,
        omega_plus=omega_plus,
        omega_minus=omega_minus,
        K_theta_plus=k_plus,
        K_theta_minus=k_minus,
        omega_plus_lin=_sqrt_or_nan(k_plus / I_O),
        omega_minus_lin=_sqrt_or_nan(k_minus / I_O),
    )


# -- tie rod (eq. 12) ------------------------------------------------------------------------
@dataclass(frozen=True)
class TieDesign:
    """A steel tie rod designed by EURODYN (2020), eq. 12 (SI units).

    ``W`` [N] weight, ``T_d`` [N] design tie force (<= 0: no tie needed), ``sigma_d`` [Pa] design
    stress, ``phi_required`` [m] diameter from ``T_d`` and ``sigma_d``, ``phi_d`` [m] adopted
    diameter (``phi_required`` or the commercial size above it), ``area`` [m²] of ``phi_d``,
    ``K_d`` [N/m] axial stiffness ``E A / L``; ``needed`` is False (and ``phi_d``, ``area``,
    ``K_d`` are 0) when the wall is stable without a tie.
    """

    W: float
    tie_height: float
    mu: float
    f_uk: float
    gamma: float
    length: float
    E: float
    T_d: float
    sigma_d: float
    phi_required: float
    phi_d: float
    area: float
    K_d: float
    needed: bool
    commercial: bool

    @property
    def message(self) -> str:
        if self.needed:
            return f"tie needed: T_d = {self.T_d:.6g} N"
        return (f"T_d = {self.T_d:.6g} N <= 0: the wall is stable without a tie "
                f"for mu = {self.mu:g}")

    def as_dict(self) -> dict:
        return {**asdict(self), "message": self.message}


def tie_design(
    body: RigidBlock,
    tie_height: float | None = None,
    mu: float = 0.2,
    f_uk: float = S275_FU,
    gamma: float = 1.05,
    length: float = 10.0,
    E: float = STEEL_E,
    round_to_commercial: bool = False,
    g: float = G,
) -> TieDesign:
    """Design a steel tie rod by equilibrium about the pivot (EURODYN (2020), eq. 12).

    Eq. 12, ``T_d h_t + W s/2 = mu W h/2``: the seismic action is a horizontal static force
    ``mu W`` at the centre of gravity (EURODYN (2020), §3), ``W = m g`` [N] the weight, ``s`` =
    ``b`` [m] the wall thickness, ``h_t`` [m] the tie height (default the top, ``h``). The lever of
    ``mu W`` is the height of the centre of gravity ``z_G``, which is ``h/2`` for the uniform
    walls of EURODYN (2020); ``z_G`` is used so that a top mass is handled. Then

    - ``T_d = W (mu z_G - b/2) / h_t`` [N]; ``T_d <= 0`` means the wall is stable without a tie
      (``mu <= tan(alpha)``): reported with ``needed = False``;
    - ``sigma_d = 0.7 f_uk / gamma`` [Pa] (EURODYN (2020), §3, ``gamma = 1.05``), with ``f_uk = 430
      MPa`` for S275 (EN 1993-1-1 Table 3.1, steel to EN 10025-2, t <= 40 mm);
    - ``phi = sqrt(4 T_d / (pi sigma_d))`` [m] from ``T_d = sigma_d pi phi² / 4``; with
      ``round_to_commercial`` the next size of :data:`COMMERCIAL_DIAMETERS_MM` is adopted;
    - ``K_d = E A / L`` [N/m] with ``A = pi phi_d² / 4``, ``E = 210 GPa`` and ``L = 10 m`` (seed
      002 §3: "The length of the tie rod is assumed 10 m").
    """
    body = _body(body)
    h_t = _height_on_wall(body, tie_height)
    mu = _positive("mu", mu)
    f_uk = _positive("f_uk", f_uk, "Pa")
    gamma = _positive("gamma", gamma)
    length = _positive("tie length", length, "m")
    E = _positive("E", E, "Pa")
    g = _positive("g", g, "m/s2")
    W = body.mass * g
    T_d = W * (mu * body.z_G - 0.5 * body.width) / h_t
    sigma_d = 0.7 * f_uk / gamma
    needed = T_d > 0.0
    if needed:
        phi_req = math.sqrt(4.0 * T_d / (math.pi * sigma_d))
        phi = phi_req
        if round_to_commercial:
            sizes = [d / 1000.0 for d in COMMERCIAL_DIAMETERS_MM if d / 1000.0 >= phi_req]
            if not sizes:
                raise DesignError(
                    f"required tie diameter {phi_req * 1000:.4g} mm exceeds the largest "
                    f"commercial size {COMMERCIAL_DIAMETERS_MM[-1]} mm"
                )
            phi = sizes[0]
        area = math.pi * phi**2 / 4.0
        K_d = E * area / length
    else:
        phi_req = phi = area = K_d = 0.0
    return TieDesign(
        W=W, tie_height=h_t, mu=mu, f_uk=f_uk, gamma=gamma, length=length, E=E, T_d=T_d,
        sigma_d=sigma_d, phi_required=phi_req, phi_d=phi, area=area, K_d=K_d, needed=needed,
        commercial=bool(round_to_commercial and needed),
    )


# -- damping (eq. 13) ------------------------------------------------------------------------
def reference_damping(body: RigidBlock, delta_t: float, g: float = G) -> float:
    """Reference damping coefficient ``c_d`` [N s/m] of a horizontal damper (EURODYN (2020), eq.
    13).

    ``c_d = F_0 / v = mu W / (delta_u / delta_t) = 2 m g delta_t / h``: from the capacity curve of
    the free-standing wall, ``F_0 = mu W`` is the horizontal force at uplift (``mu = tan(alpha) =
    (b/2) / z_G``, the static collapse multiplier, ``s/h`` for a uniform wall), ``delta_u = b/2``
    the ultimate displacement of the centre of gravity (EURODYN (2020), §4.2, ``u_G = s/2``) and
    ``delta_t`` [s] a characteristic time of the event, so that ``v = delta_u / delta_t``.
    Written with ``z_G``: ``c_d = m g delta_t / z_G``, i.e. ``2 m g delta_t / h`` for the uniform
    walls of EURODYN (2020) (``z_G = h/2``). EURODYN (2020) uses ``c`` = 0.1 %, 1 %, 5 %, > 10 % of
    ``c_d``.
    """
    body = _body(body)
    delta_t = _positive("delta_t", delta_t, "s")
    g = _positive("g", g, "m/s2")
    return body.mass * g * delta_t / body.z_G


# -- report ----------------------------------------------------------------------------------
def design_report(
    body: RigidBlock,
    *,
    K: float | None = None,
    K_over_Kd: float | None = None,
    tie_height: float | None = None,
    tie_x: float = 0.0,
    K_bed: float | None = None,
    walls: tuple[float, float, float] | None = None,
    bed_height: float | None = None,
    mu: float = 0.2,
    f_uk: float = S275_FU,
    gamma: float = 1.05,
    length: float = 10.0,
    E: float = STEEL_E,
    round_to_commercial: bool = False,
    delta_t: float | None = None,
    fractions: tuple[float, ...] = (),
    g: float = G,
) -> dict:
    """All the design quantities of EURODYN (2020) for ``body`` as a JSON-ready dictionary (SI
    units).

    The tie stiffness is ``K`` [N/m] if given, else ``K_over_Kd * K_d``, else ``K_d`` (eq. 12,
    the reference value of EURODYN (2020)). The spring bed stiffness is ``K_bed`` [N/m/m] if given,
    else eq. 10 from ``walls = (E_x, t, L_eff)``, else eq. 11 from ``K``. The damping section
    (eq. 13, with ``c = f c_d`` for each of ``fractions``) is present when ``delta_t`` [s] is
    given. NaN values (no oscillation) are written as ``None``.
    """
    body = _body(body)
    if K is not None and K_over_Kd is not None:
        raise DesignError("give either K or K_over_Kd, not both")
    if K_bed is not None and walls is not None:
        raise DesignError("give either the bed stiffness K' or the transverse walls, not both")
    td = tie_design(body, tie_height, mu=mu, f_uk=f_uk, gamma=gamma, length=length, E=E,
                    round_to_commercial=round_to_commercial, g=g)
    if K is not None:
        K_val, K_src = _non_negative("K", K, "N/m"), "given"
    elif K_over_Kd is not None:
        r = _non_negative("K/K_d", K_over_Kd)
        K_val, K_src = r * td.K_d, f"K = {r:g} K_d (eq. 12)"
    else:
        K_val, K_src = td.K_d, "K = K_d (eq. 12)"
    if K_bed is not None:
        Kb, Kb_src = _non_negative("K' (bed stiffness)", K_bed, "N/m/m"), "given"
    elif walls is not None:
        try:
            E_x, t, L_eff = walls
        except (TypeError, ValueError):
            raise DesignError("walls must be three numbers E_x, t, L_eff") from None
        Kb, Kb_src = bed_stiffness_from_walls(E_x, t, L_eff), "eq. 10"
    else:
        Kb, Kb_src = bed_stiffness_equal(body, K_val, tie_height, tie_x), "eq. 11"
    res = resonance_frequencies(body, K_val, tie_height, tie_x, Kb, g=g, bed_height=bed_height)
    out = {
        "body": body.describe(),
        "tie": td.as_dict(),
        "stiffness": {"K": K_val, "K_source": K_src, "K_bed": Kb, "K_bed_source": Kb_src,
                      "K_bed_eq11": bed_stiffness_equal(body, K_val, tie_height, tie_x)},
        "resonance": res.as_dict(),
        "damping": None,
    }
    if delta_t is not None:
        c_d = reference_damping(body, delta_t, g=g)
        fr = [_non_negative("damping fraction", f) for f in fractions]
        out["damping"] = {"delta_t": float(delta_t), "c_d": c_d,
                          "c": [{"fraction": f, "c": f * c_d} for f in fr]}
    return out

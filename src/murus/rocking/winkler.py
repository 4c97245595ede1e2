"""A rigid wall on a no-tension elastic (Winkler) layer: walls on acoustic rubber strips.

Mordant et al. (SERIES), §1.1 and §2.1, test walls with and without 1 cm acoustic rubber layers
under them and conclude that with rubber "the assumption of rigid support is no more valid and the
wall has to be considered as resting on an elastic foundation": natural frequencies 30-40 % lower
and a softer passage through the vertical position. Here the base contact is a bed of independent
springs and dashpots (Winkler 1867) that act only in compression, so that the contact length, the
pivot (centre of pressure) and the energy lost at each "impact" follow from the deformation of the
layer instead of a restitution law (the same idea as Psycharis and Jennings 1983, "Rocking of
slender rigid bodies allowed to uplift", EESD 11, whose equations are not reproduced here: the
derivation below is ours).

Model
-----
Planar rigid body of mass ``m``, moment of inertia ``I_G`` about its centre of gravity G (``I_G =
I_O - m R^2`` from :class:`~murus.rocking.body.RigidBlock`), base of width ``b``, G at height
``z_G`` above the base centre C. Coordinates in the frame of the ground (``x`` horizontal, ``y``
up), with two degrees of freedom:

- ``v``: vertical displacement of C (the undeformed layer surface is ``y = 0``; ``v < 0`` when
  the layer is compressed);
- ``theta``: rotation, **clockwise positive** as in the rigid engine (:mod:`murus.rocking.kernels`:
  ``theta > 0`` lowers the right corner O at ``xi = +b/2``); a positive ground acceleration
  ``a_g`` drives a positive rotation and ``a_v`` (upward) adds to gravity.

No sliding: the horizontal position of C is prescribed, ``x_C = X(theta)``, with two options
(``WinklerBase(kinematics=...)``):

- ``"centre"``: ``X = 0``, the base centre does not move horizontally;
- ``"corner"`` (default): ``X = (b/2) sgn(theta) (1 - cos theta)``, the corner on the side of the
  rotation does not move horizontally (the kinematics of the rigid model, where the body turns
  about a fixed corner). Both give the same linearised equations; they differ by the horizontal
  velocity ``(b/2) |sin theta| theta'`` of G: on a corner (``v = (b/2) |sin theta|``) the kinetic
  energy is ``1/2 I_O theta'^2`` with ``"corner"`` but lacks
  ``1/2 m (b z_G |sin theta| cos theta + b^2/4 sin^2 theta) theta'^2`` with ``"centre"``. Only
  ``"corner"`` tends to Housner's rigid model as ``k -> inf``: with ``"centre"``
  the first-impact time of the short wall of Mordant et al. (SERIES) released from ``alpha/2`` tends
  to a value 1.3 % shorter (8.5 % for the long wall), which a convergence study cannot remove.

Position of G and of a base point at body coordinate ``xi`` in ``[-b/2, b/2]`` (positive towards
O)::

    x_G = X(theta) + z_G sin(theta)          y_G = v + z_G cos(theta)
    y(xi) = v - xi sin(theta)                penetration delta(xi) = -y(xi) = -v + xi sin(theta)

Contact law (no tension, no adhesion): pressure ``q = max(0, k delta + c delta')`` where
``delta > 0``, else 0; force per unit length of base ``t_w q`` (``t_w``: out-of-plane width of
the contact). ``k`` [N/m³] is ``E_layer / t_layer``; ``c`` [N s/m³].

Lagrange equations
------------------
Kinetic energy, with ``A(theta) = dx_G/dtheta = X'(theta) + z_G cos(theta)``,
``s = sin(theta)``, ``co = cos(theta)``::

    T = 1/2 m (x_G'^2 + y_G'^2) + 1/2 I_G theta'^2 = 1/2 q'^T M(theta) q',   q = (v, theta)
    M = [[m,            -m z_G s],
         [-m z_G s,     M_tt    ]],       M_tt = I_G + m (A^2 + z_G^2 s^2)

(``"centre"``: ``A^2 + z_G^2 s^2 = z_G^2`` and ``M_tt = I_G + m z_G^2``). With ``d/dt(dT/dq') -
dT/dq = Q`` and ``dM/dtheta = [[0, -m z_G co], [-m z_G co, M_tt']]``,
``M_tt' = 2 m (A A' + z_G^2 s co)``::

    m v'' - m z_G s theta''             = Q_v + m z_G co theta'^2
    -m z_G s v'' + M_tt theta''         = Q_theta - 1/2 M_tt' theta'^2

(the ``v' theta'`` terms cancel; ``M_tt' = 0`` for ``"centre"``, where ``A' = -z_G s``; for
``"corner"`` ``A' = (b/2) sgn(theta) co - z_G s``, which jumps at ``theta = 0``: the acceleration
is discontinuous there, the energy is still conserved). The 2x2 system is solved in closed form
(``det = m M_tt - m^2 z_G^2 s^2 = m (I_G + m A^2) > 0``).

Generalised forces, from the virtual work of each force (``delta y_G = delta v - z_G s
delta theta``, ``delta x_G = A delta theta``, ``delta y(xi) = delta v - xi co delta theta``)::

    gravity + vertical ground motion:   Q_v = -m (g + a_v),     Q_theta = +m (g + a_v) z_G s
    horizontal ground motion:                                   Q_theta = +m a_g A
    contact:  Q_v = F = t_w int q dxi,  Q_theta = -co Mx,       Mx = t_w int q xi dxi

The horizontal friction that enforces ``x_C = X(theta)`` is a workless constraint reaction. On
its support the pressure is linear in ``xi``, ``q = q0 + q1 xi`` with ``q0 = -k v - c v'``,
``q1 = k s + c co theta'``, and the support is the intersection of two half-lines with the base,
so ``F`` and ``Mx`` are integrated in closed form (:func:`murus.rocking.winkler_kernels.contact`).

Energy: ``E = T + V + U`` with ``V = m g (v + z_G (cos theta - 1))`` and
``U = k t_w / 2 int_{delta > 0} delta^2 dxi``; ``E + D - W`` is constant, ``D`` being the energy
dissipated by the damping of the layer (including the elastic energy of the compressed zone that
the body leaves faster than the dashpots let the layer recover, where ``q`` is clipped at 0) and
``W`` the work of the inertial forces ``m a_g`` and ``-m a_v`` of the ground motion.

Linearised on full contact about the static settlement ``v0 = -m g / (k t_w b)``: vertical and
rocking modes are uncoupled, ``omega_v^2 = k t_w b / m`` and
``omega_theta^2 = (k t_w b^3 / 12 - m g z_G) / (I_G + m z_G^2)`` (the rotational stiffness of the
layer minus the destabilising moment of gravity, over the inertia about C).

Statics (:func:`static_pushover`): under a constant ``a_g`` the layer starts to lift at the heel
when the resultant leaves the kern, ``Mx / F = b/6``, i.e. at ``a_up -> g b / (6 z_G)`` for a stiff
layer; with a triangular pressure on ``Lc = sqrt(2 m g / (k t_w sin theta))`` the equilibrium curve
is ``a(theta) = g (co (b/2 - Lc/3) - z_G s) / A``, whose maximum tends to the rigid-body value
``g tan(alpha) = g b / (2 z_G)`` (Mordant et al. (SERIES) eq. 9) as ``k`` grows.

Units: SI throughout (m, kg, s, N, Pa, rad).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from murus import G
from murus.errors import MurusError
from murus.results import Result, deprecated_alias
from murus.rocking import kernels as K
from murus.rocking import winkler_kernels as WK
from murus.rocking.body import RigidBlock
from murus.rocking.defaults import WINKLER_RTOL
from murus.rocking.excitation import as_excitation, default_duration
from murus.rocking.summary import WINKLER_SUMMARY, table_summary, values

__all__ = [
    "WinklerBase",
    "WinklerError",
    "WinklerResult",
    "initial_settlement",
    "overturning_acceleration",
    "params",
    "simulate_winkler",
    "small_amplitude_frequency",
    "static_pushover",
    "uplift_acceleration",
    "vertical_frequency",
]


_STATUS = {
    0: "ok",
    1: "step size underflow: the integration stopped early",
    2: "step budget exhausted: the integration stopped early",
}

_KINEMATICS = {"centre": WK.KIN_CENTRE, "corner": WK.KIN_CORNER}


class WinklerError(MurusError, ValueError):
    """An invalid elastic-layer model or simulation option (one-line message)."""


def _number(name: str, value, *, positive: bool = False, allow_none: bool = False):
    if value is None and allow_none:
        return None
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise WinklerError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(v) or v < 0.0 or (positive and v == 0.0):
        kind = "positive" if positive else "non-negative"
        raise WinklerError(f"{name} must be a {kind} finite number, got {value!r}")
    return v


@dataclass(frozen=True)
class WinklerBase:
    """A no-tension elastic (Winkler) layer under the body.

    Parameters
    ----------
    stiffness:
        ``k_w`` [N/m³], contact pressure per unit penetration (``E_layer / t_layer``).
    thickness:
        Layer thickness [m]; informative only (the layer is a bed of independent springs).
    damping:
        ``c_w`` [N s/m³], viscous pressure per unit penetration rate.
    damping_ratio:
        Alternative to ``damping``: the ratio of critical damping of the **vertical** mode of the
        body on full contact, ``c_w = 2 zeta sqrt(k_w m / (t_w b))`` (it depends on the body, so
        it is resolved by :meth:`damping_coefficient`).
    width_out_of_plane:
        ``t_w`` [m], out-of-plane width of the contact; default: the body's thickness.
    kinematics:
        ``"corner"`` (default) or ``"centre"``: the point of the base that does not slide (see the
        module docstring; only ``"corner"`` tends to the rigid rocking model).
    """

    stiffness: float
    thickness: float | None = None
    damping: float = 0.0
    damping_ratio: float = 0.0
    width_out_of_plane: float | None = None
    kinematics: str = "corner"
    name: str = field(default="winkler", compare=False)

    #: Declared parameters and their validity limits (GUIDE §3).
    PARAMS = {
        "stiffness": ("N/m3", "> 0"),
        "thickness": ("m", "> 0 or None"),
        "damping": ("N s/m3", ">= 0"),
        "damping_ratio": ("-", ">= 0 (not with damping)"),
        "width_out_of_plane": ("m", "> 0 or None"),
        "kinematics": ("-", "'corner' or 'centre'"),
    }

    def __post_init__(self) -> None:
        object.__setattr__(self, "stiffness", _number("stiffness", self.stiffness, positive=True))
        object.__setattr__(self, "thickness",
                           _number("thickness", self.thickness, positive=True, allow_none=True))
        object.__setattr__(self, "damping", _number("damping", self.damping))
        object.__setattr__(self, "damping_ratio", _number("damping_ratio", self.damping_ratio))
        object.__setattr__(self, "width_out_of_plane",
                           _number("width_out_of_plane", self.width_out_of_plane, positive=True,
                                   allow_none=True))
        if self.damping > 0.0 and self.damping_ratio > 0.0:
            raise WinklerError("give either damping or damping_ratio, not both")
        if self.kinematics not in _KINEMATICS:
            raise WinklerError(f"kinematics must be 'corner' or 'centre', got {self.kinematics!r}")

    @classmethod
    def from_layer(cls, E: float, t_layer: float, **kw) -> WinklerBase:
        """A layer of compression modulus ``E`` [Pa] and thickness ``t_layer`` [m]:
        ``k_w = E / t_layer`` (the modulus of the confined strip, shape factor included, is the
        user's assumption)."""
        E = _number("E", E, positive=True)
        t_layer = _number("t_layer", t_layer, positive=True)
        return cls(stiffness=E / t_layer, thickness=t_layer, **kw)

    def contact_width(self, body: RigidBlock) -> float:
        """``t_w`` [m]."""
        return self.width_out_of_plane if self.width_out_of_plane is not None else body.thickness

    def damping_coefficient(self, body: RigidBlock) -> float:
        """``c_w`` [N s/m³] for this body."""
        if self.damping_ratio > 0.0:
            tw = self.contact_width(body)
            return 2.0 * self.damping_ratio * math.sqrt(self.stiffness * body.mass
                                                        / (tw * body.width))
        return self.damping

    def describe(self, body: RigidBlock | None = None) -> dict:
        d = {"name": self.name, "stiffness": self.stiffness, "thickness": self.thickness,
             "damping": self.damping, "damping_ratio": self.damping_ratio,
             "width_out_of_plane": self.width_out_of_plane, "kinematics": self.kinematics}
        if body is not None:
            d["damping_coefficient"] = self.damping_coefficient(body)
            d["contact_width"] = self.contact_width(body)
        return d


def _body(body) -> RigidBlock:
    b = getattr(body, "body", body)  # a RockingModel carries its body
    if not isinstance(b, RigidBlock):
        raise WinklerError(f"body must be a RigidBlock, got {type(body).__name__}")
    return b


def _base(base) -> WinklerBase:
    if not isinstance(base, WinklerBase):
        raise WinklerError(f"base must be a WinklerBase, got {type(base).__name__}")
    return base


def _gravity(gravity) -> float:
    return _number("gravity", gravity, positive=True)


def _I_G(body: RigidBlock) -> float:
    return max(body.I_O - body.mass * body.R**2, 0.0)


def params(body: RigidBlock, base: WinklerBase, gravity: float = G) -> np.void:
    """The parameter record read by :mod:`murus.rocking.winkler_kernels` (its ``PARAMS``)."""
    body = _body(body)
    base = _base(base)
    g = _gravity(gravity)
    tw = base.contact_width(body)
    P = WK.new_params()
    P["m"] = body.mass
    P["ig"] = _I_G(body)
    P["zg"] = body.z_G
    P["hb"] = 0.5 * body.width
    P["tw"] = tw
    P["k"] = base.stiffness
    P["c"] = base.damping_coefficient(body)
    P["g"] = g
    P["kin"] = _KINEMATICS[base.kinematics]
    P["dsc"] = body.mass * g / (base.stiffness * tw * body.width)
    P["wsc"] = vertical_frequency(body, base)
    return P


# ================================================================= closed forms ========
def vertical_frequency(body, base) -> float:
    """Circular frequency of the vertical mode on full contact, ``sqrt(k t_w b / m)`` [rad/s]."""
    body = _body(body)
    base = _base(base)
    return math.sqrt(base.stiffness * base.contact_width(body) * body.width / body.mass)


def small_amplitude_frequency(body, base, gravity: float = G) -> float:
    """Circular frequency of small rocking oscillations on full contact [rad/s]:
    ``omega^2 = (k t_w b^3 / 12 - m g z_G) / (I_G + m z_G^2)`` (linearisation of the Lagrange
    equations of the module docstring about the static settlement; the vertical mode is
    uncoupled). A layer too soft to hold the body upright is an error."""
    body = _body(body)
    base = _base(base)
    g = _gravity(gravity)
    k_theta = base.stiffness * base.contact_width(body) * body.width**3 / 12.0
    net = k_theta - body.mass * g * body.z_G
    if net <= 0.0:
        raise WinklerError(f"layer stiffness {base.stiffness:g} N/m3 cannot hold the body "
                           "upright (k t_w b^3/12 <= m g z_G)")
    return math.sqrt(net / (_I_G(body) + body.mass * body.z_G**2))


def initial_settlement(body, base, theta: float = 0.0, gravity: float = G) -> float:
    """Vertical position ``v`` [m] of the base centre in vertical equilibrium at the rotation
    ``theta`` (zero velocity): ``-m g / (k t_w b)`` while the whole base is compressed, else the
    triangular pressure on ``Lc = sqrt(2 m g / (k t_w |sin theta|))`` at the lowered corner,
    ``v = (b/2 - Lc) |sin theta|``."""
    body = _body(body)
    base = _base(base)
    g = _gravity(gravity)
    kt = base.stiffness * base.contact_width(body)
    N = body.mass * g
    s = abs(math.sin(theta))
    hb = 0.5 * body.width
    v_full = -N / (kt * body.width)
    if -v_full - hb * s >= 0.0:
        return v_full
    Lc = math.sqrt(2.0 * N / (kt * s))
    return (hb - Lc) * s


def static_pushover(body, base, theta, gravity: float = G) -> dict:
    """Static equilibrium under a constant horizontal acceleration, for rotations ``theta >= 0``
    [rad]: returns arrays ``a`` (the acceleration [m/s²] that holds the body at ``theta``),
    ``v`` [m], ``contact_length`` [m] and ``pivot`` (centre of pressure, body coordinate [m])."""
    body = _body(body)
    base = _base(base)
    g = _gravity(gravity)
    th = np.atleast_1d(np.asarray(theta, dtype=float))
    if np.any(~np.isfinite(th)) or np.any(th < 0.0) or np.any(th >= 0.5 * math.pi):
        raise WinklerError("static_pushover needs rotations in [0, pi/2)")
    kt = base.stiffness * base.contact_width(body)
    m, b, zg = body.mass, body.width, body.z_G
    hb = 0.5 * b
    N = m * g
    s, co = np.sin(th), np.cos(th)
    full = hb * s <= N / (kt * b)
    with np.errstate(divide="ignore", invalid="ignore"):
        Lc = np.where(full, b, np.sqrt(2.0 * N / (kt * np.where(s > 0, s, 1.0))))
        xp = np.where(full, kt * s * b**3 / 12.0 / N, hb - Lc / 3.0)
    v = np.where(full, -N / (kt * b), (hb - Lc) * s)
    A = zg * co + (hb * s if base.kinematics == "corner" else 0.0)
    a = (co * N * xp - N * zg * s) / (m * A)
    return {"theta": th, "a": a, "v": v, "contact_length": Lc, "pivot": xp}


def uplift_acceleration(body, base, gravity: float = G) -> float:
    """Constant horizontal acceleration [m/s²] at which the heel starts to lift (the resultant
    reaches the edge of the kern, ``b/6`` from the centre), P-delta effect included; tends to
    ``g b / (6 z_G)`` as the layer stiffens."""
    body = _body(body)
    base = _base(base)
    g = _gravity(gravity)
    kt = base.stiffness * base.contact_width(body)
    s_up = 2.0 * body.mass * g / (kt * body.width**2)
    if s_up >= 1.0:
        raise WinklerError("layer too soft: the heel never lifts before pi/2")
    return float(static_pushover(body, base, math.asin(s_up), g)["a"][0])


def overturning_acceleration(body, base, gravity: float = G) -> float:
    """Largest constant horizontal acceleration [m/s²] for which a static equilibrium exists
    (the peak of :func:`static_pushover`); tends to ``g tan(alpha) = g b / (2 z_G)``."""
    from scipy.optimize import minimize_scalar

    body = _body(body)
    base = _base(base)
    g = _gravity(gravity)
    th_hi = min(body.alpha, 0.5 * math.pi - 1e-9)
    grid = np.geomspace(1e-12, th_hi, 2001)
    a = static_pushover(body, base, grid, g)["a"]
    i = int(np.argmax(a))
    lo = grid[max(i - 1, 0)]
    hi = grid[min(i + 1, grid.size - 1)]
    res = minimize_scalar(lambda x: -static_pushover(body, base, x, g)["a"][0],
                          bounds=(lo, hi), method="bounded", options={"xatol": 1e-14 + 1e-10 * hi})
    return float(max(-res.fun, a[i]))


# ================================================================== simulation =========
@dataclass
class WinklerResult(Result):
    """One time history of a rigid body on the elastic layer (SI units: s, m, rad, N, Pa, J).

    Arrays are on the output grid ``t``. The scalar quantities are declared in
    :data:`murus.rocking.summary.WINKLER_SUMMARY`; ``first_crossing`` is the deprecated name
    of ``t_first_crossing``.

    Attributes
    ----------
    t : ndarray
        Output times [s].
    theta : ndarray
        Rotation [rad], clockwise positive (``theta > 0`` lowers the corner O).
    omega : ndarray
        Angular velocity [rad/s].
    v : ndarray
        Vertical displacement of the base centre [m] (negative: layer compressed).
    v_dot : ndarray
        Its velocity [m/s].
    angular_acceleration : ndarray
        ``theta''`` [rad/s²].
    ag, av : ndarray
        Horizontal and vertical (upward) ground accelerations on the grid [m/s²].
    contact_force : ndarray
        Contact resultant ``F = t_w int q dxi`` [N].
    contact_length : ndarray
        Length of the base in contact ``Lc`` [m].
    pivot : ndarray
        Centre of pressure in body coordinates [m]: ``xi`` from the base centre, positive
        towards the corner O (nan without contact).
    max_pressure : ndarray
        Largest contact pressure [Pa].
    kinetic_energy, potential_energy, elastic_energy : ndarray
        ``T``, ``V`` (relative to the undeformed upright position) and the elastic energy ``U``
        of the layer [J].
    dissipated_energy : ndarray
        Energy ``D`` dissipated by the damping of the layer since the start [J].
    input_energy : ndarray
        Work ``W`` of the inertial forces of the ground motion since the start [J].
    crossings : ndarray
        Rows ``(t, theta', v)`` [s, rad/s, m] at each ``theta = 0``.
    peaks : ndarray
        Rows ``(t, theta)`` [s, rad]: the extreme rotation of each half cycle between
        crossings (the first row is the initial half cycle, the last one the half cycle
        running at the end).
    width : float
        Base width ``b`` [m].
    alpha : float
        Slenderness angle [rad].
    theta_max : float
        Largest absolute rotation [rad].
    theta_signed_max : float
        Signed rotation at the largest absolute rotation [rad].
    t_theta_max : float
        Time of the largest absolute rotation [s].
    overturned : bool
        Whether the body overturned.
    t_overturn : float or None
        Time of overturning [s] (None: no overturning).
    peak_contact_force : float
        Largest contact resultant (at step ends) [N].
    t_peak_contact_force : float
        Time of the largest contact resultant [s].
    peak_pressure : float
        Largest contact pressure (at step ends) [Pa].
    peak_angular_acceleration : float
        Largest ``|theta''|`` (at step ends) [rad/s²].
    min_contact_length : float
        Smallest contact length [m].
    status : int
        0 ok, 1 step size underflow, 2 step budget exhausted.
    message : str
        ``"ok"`` or why the integration stopped early.
    n_steps, n_rejected : int
        Accepted and rejected Runge-Kutta steps [-].
    meta : dict
        Input of the run: body, base, motion and solver options.

    References
    ----------
    Mordant et al. (SERIES), eq. 10 (:meth:`apparent_restitution`, the energy lost per
    impact by the rigid model); Housner (1963) (the rigid rocking model that the layer tends
    to as its stiffness grows).
    """

    t: np.ndarray
    theta: np.ndarray
    omega: np.ndarray
    v: np.ndarray
    v_dot: np.ndarray
    angular_acceleration: np.ndarray
    ag: np.ndarray
    av: np.ndarray
    contact_force: np.ndarray
    contact_length: np.ndarray
    pivot: np.ndarray
    max_pressure: np.ndarray
    kinetic_energy: np.ndarray
    potential_energy: np.ndarray
    elastic_energy: np.ndarray
    dissipated_energy: np.ndarray
    input_energy: np.ndarray
    crossings: np.ndarray
    peaks: np.ndarray
    width: float
    alpha: float
    theta_max: float
    theta_signed_max: float
    t_theta_max: float
    overturned: bool
    t_overturn: float | None
    peak_contact_force: float
    t_peak_contact_force: float
    peak_pressure: float
    peak_angular_acceleration: float
    min_contact_length: float
    status: int
    message: str
    n_steps: int
    n_rejected: int
    meta: dict = field(default_factory=dict)

    first_crossing = deprecated_alias("t_first_crossing", "first_crossing")

    def headline(self) -> str:
        """``theta_max/alpha = ..., zero crossings = ..., overturned = ...`` (the CLI's line)."""
        return (f"theta_max/alpha = {self.theta_max_over_alpha:.4f}, zero crossings = "
                f"{self.crossings.shape[0]}, overturned = {self.overturned}")

    @property
    def lifted_length(self) -> np.ndarray:
        """Length of the base out of contact, ``b - Lc`` [m]."""
        return self.width - self.contact_length

    @property
    def total_energy(self) -> np.ndarray:
        """``T + V + U`` [J] (``V`` relative to the undeformed upright position)."""
        return self.kinetic_energy + self.potential_energy + self.elastic_energy

    @property
    def energy_balance(self) -> np.ndarray:
        """``T + V + U + D - W`` minus its initial value [J]: zero up to the integration error."""
        e = self.total_energy + self.dissipated_energy - self.input_energy
        return e - e[0]

    @property
    def theta_max_over_alpha(self) -> float:
        return self.theta_max / self.alpha

    @property
    def t_first_crossing(self) -> float | None:
        """Time of the first return to ``theta = 0`` [s] (the 'impact' of the rigid model)."""
        return float(self.crossings[0, 0]) if self.crossings.shape[0] else None

    def apparent_restitution(self, n: int = 1) -> float:
        """The constant coefficient of restitution with which the rigid model would lose the
        same energy in the first ``n`` impacts, per impact: from the peaks ``theta_0`` and
        ``theta_n`` of half cycles 0 and ``n``, ``e = [(cos(alpha - theta_n) - cos alpha) /
        (cos(alpha - theta_0) - cos alpha)]^(1 / 2n)`` (energy ``x e^2`` per impact, Mordant et al.
        (SERIES) eq. 10 context)."""
        if self.peaks.shape[0] <= n:
            raise WinklerError(f"only {self.peaks.shape[0]} half cycles: no peak number {n}")
        a = self.alpha
        e0 = math.cos(a - abs(self.peaks[0, 1])) - math.cos(a)
        en = math.cos(a - abs(self.peaks[n, 1])) - math.cos(a)
        return (max(en, 0.0) / e0) ** (0.5 / n)

    def summary(self) -> dict:
        """Plain-number summary (what ``summary.json`` holds): the quantities of the declared
        table :data:`murus.rocking.summary.WINKLER_SUMMARY` that a result keeps, then the
        derived ones; ``status`` is the message."""
        out = table_summary(self, WINKLER_SUMMARY, _RESULT_FIELDS)
        out.update({
            "theta_max_over_alpha": self.theta_max_over_alpha,
            "t_first_crossing": self.t_first_crossing,
            "first_crossing": self.t_first_crossing,  # earlier name (kept for readers)
            "n_crossings": int(self.crossings.shape[0]),
            "crossings": int(self.crossings.shape[0]),  # earlier name (kept for readers)
            "energy_dissipated": float(self.dissipated_energy[-1]),
            "status": self.message,
            "input": self.meta,
        })
        return out


@dataclass(frozen=True)
class WinklerModel:
    """A rigid body on a no-tension elastic (Winkler) layer: the model that
    :func:`murus.rocking.simulate` runs with :func:`simulate_winkler`.

    Parameters
    ----------
    body : RigidBlock
        The body.
    base : WinklerBase
        The elastic layer.
    gravity : float
        ``g`` [m/s²].
    """

    body: RigidBlock
    base: WinklerBase
    gravity: float = G

    def __post_init__(self) -> None:
        object.__setattr__(self, "body", _body(self.body))
        object.__setattr__(self, "base", _base(self.base))
        object.__setattr__(self, "gravity", _gravity(self.gravity))


#: Quantities of the summary table kept as attributes of a :class:`WinklerResult`.
_RESULT_FIELDS = ("theta_max", "theta_signed_max", "t_theta_max", "overturned", "t_overturn",
                  "peak_contact_force", "t_peak_contact_force", "peak_pressure",
                  "peak_angular_acceleration", "min_contact_length", "status", "n_steps",
                  "n_rejected")


def simulate_winkler(
    body,
    base: WinklerBase,
    motion=None,
    *,
    duration: float | None = None,
    theta0: float = 0.0,
    omega0: float = 0.0,
    theta0_over_alpha: float | None = None,
    gravity: float = G,
    rtol: float = WINKLER_RTOL,
    out_dt: float | None = None,
    max_steps: int = 50_000_000,
    max_events: int = 1_000_000,
) -> WinklerResult:
    """Time history of a rigid body on a no-tension elastic layer.

    Parameters
    ----------
    body:
        A :class:`RigidBlock` (or a model carrying one as ``.body``).
    base:
        The :class:`WinklerBase`.
    motion:
        As for :func:`murus.rocking.simulate`: a GroundMotion, an excitation of
        :mod:`murus.rocking.excitation` or ``None`` (free vibration).
    duration:
        End of the analysis [s]; default: end of the input plus 5 s.
    theta0, omega0, theta0_over_alpha:
        Initial rotation [rad] (or as a fraction of alpha) and angular velocity [rad/s]. The run
        starts at rest vertically: ``v`` from vertical equilibrium at ``theta0``
        (:func:`initial_settlement`: the full static settlement while the whole base is
        compressed, else the body rests on the compressed zone at the lowered corner) and
        ``v' = 0``; with ``theta0 = 0`` it is the exact static state ``v0 = -m g / (k t_w b)``
        (gravity only: a vertical ground acceleration at ``t = 0`` is not in it).
    rtol:
        Relative tolerance of the Dormand-Prince 5(4) integrator, applied to the penetration of
        the base (absolute scale: the static settlement).
    out_dt:
        Output grid step [s] (default: the record's step).
    """
    body = _body(body)
    base = _base(base)
    g = _gravity(gravity)
    exc = as_excitation(motion)
    if duration is None:
        duration = default_duration(exc)
    t_end = _number("duration", duration, positive=True)
    if theta0_over_alpha is not None:
        theta0 = float(theta0_over_alpha) * body.alpha
    th0 = float(theta0)
    om0 = float(omega0)
    if not (math.isfinite(th0) and math.isfinite(om0)):
        raise WinklerError("initial conditions must be finite")
    if abs(th0) >= 0.5 * math.pi:
        raise WinklerError(f"initial rotation {th0!r} rad is beyond overturning (pi/2)")
    try:
        rtol = float(rtol)
    except (TypeError, ValueError):
        raise WinklerError(f"rtol must be a number, got {rtol!r}") from None
    if not (1e-14 <= rtol < 1e-2):
        raise WinklerError(f"rtol must be in [1e-14, 1e-2), got {rtol!r}")
    step = float(out_dt) if out_dt is not None else exc.default_output_step()
    if not (math.isfinite(step) and step > 0.0):
        raise WinklerError(f"out_dt must be positive, got {out_dt!r}")
    P = params(body, base, g)
    drv = K.Drive(exc.vector(), *exc.arrays())
    y0 = np.zeros(WK.NY)
    y0[WK.Y_V] = initial_settlement(body, base, th0, g)
    y0[WK.Y_TH] = th0
    y0[WK.Y_OM] = om0
    n_out = int(math.floor(t_end / step + 1e-9)) + 1
    t = np.arange(n_out) * step
    cap = 256
    while True:
        out = np.full((n_out, WK.O_SIZE), np.nan)
        zc = np.full((cap, 3), np.nan)
        pk = np.full((cap, 2), np.nan)
        S = WK.winkler_core(P, drv, t_end, y0, rtol, step, out, zc, pk, int(max_steps))
        need = max(S[WK.S_N_CROSS], S[WK.S_N_PEAKS])
        if need <= cap or cap >= max_events:
            break
        cap = int(min(max(need, 2 * cap), max_events))
    gh, gv = exc.sample(t)
    n_zc = min(int(S[WK.S_N_CROSS]), cap)
    n_pk = min(int(S[WK.S_N_PEAKS]), cap)
    m, zg = body.mass, body.z_G
    v, th, vd, om = out[:, WK.O_V], out[:, WK.O_TH], out[:, WK.O_VD], out[:, WK.O_OM]
    s = np.sin(th)
    A = zg * np.cos(th)
    if base.kinematics == "corner":
        A = A + 0.5 * body.width * np.abs(s)
    Mtt = _I_G(body) + m * (A**2 + zg**2 * s**2)
    T = 0.5 * (m * vd**2 - 2.0 * m * zg * s * vd * om + Mtt * om**2)
    V = m * g * (v + zg * (np.cos(th) - 1.0))
    vals = values(WINKLER_SUMMARY, S)
    status = vals["status"]
    meta = {
        "body": body.describe(),
        "base": base.describe(body),
        "motion": exc.describe(),
        "solver": {"method": "dopri5", "duration": t_end, "rtol": rtol, "out_dt": step,
                   "theta0": th0, "omega0": om0, "v0": float(y0[WK.Y_V]), "gravity": g},
    }
    return WinklerResult(
        t=t, theta=th, omega=om, v=v, v_dot=vd, angular_acceleration=out[:, WK.O_THDD],
        ag=gh, av=gv,
        contact_force=out[:, WK.O_F], contact_length=out[:, WK.O_LC], pivot=out[:, WK.O_XP],
        max_pressure=out[:, WK.O_QMAX],
        kinetic_energy=T, potential_energy=V, elastic_energy=out[:, WK.O_U],
        dissipated_energy=out[:, WK.O_D], input_energy=out[:, WK.O_W],
        crossings=zc[:n_zc].copy(), peaks=pk[:n_pk].copy(),
        width=body.width, alpha=body.alpha,
        **{k: v for k, v in vals.items() if k in _RESULT_FIELDS},
        message=_STATUS.get(status, "unknown"), meta=meta,
    )

"""Rigid-block mechanisms of masonry walls and the virtual-work engine of the kinematic checks.

Sign convention: x horizontal, positive outward (the direction in which the façade overturns),
y vertical upward, origin at the outer face of the wall at ground level. A mechanism is a chain of
rigid blocks with one degree of freedom, the rotation ``theta`` [rad] of its first block
(``theta > 0`` moves the wall outward). Every weight is lumped at its point of application
(a block's weight at its centroid), as in the sums over the weights P_k of the Circolare 2019,
eq. [C8.7.1.1].

For a configuration ``theta`` the engine takes the virtual displacements of all points as the
derivatives of their positions with respect to ``theta`` (central differences) and writes the
virtual work equation of Circolare 2019 eq. [C8.7.1.1]::

    alpha (sum_k W_k dx_k) = sum_k P_k dy_k + sum_j T_j dt_j - sum_h F_h dx_h

with P_k the weights (gravity, their virtual upward displacement dy_k), W_k the weights whose
masses produce horizontal inertial forces alpha W_k (P_k + Q_k in the Circolare: a floor load
carried by the wall has both, the wall above a restrained top only gravity), T_j the strength of
the ties (virtual elongation dt_j = outward displacement of the anchor), F_h horizontal outward
thrusts. At ``theta = 0`` this is the activation multiplier alpha0; at finite ``theta`` the
large-displacement equilibrium that gives the capacity curve alpha(d) (§C8.7.1.2.1.3).

References
----------
Circolare 21 gennaio 2019 n. 7 C.S.LL.PP., §C8.7.1.2.1 (eqs. C8.7.1.1, C8.7.1.3-C8.7.1.5).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from murus.errors import MurusError

__all__ = [
    "MechanismError", "Storey", "Floor", "Mechanism", "SimpleOverturning", "VerticalFlexure",
    "CornerOverturning",
    "alpha", "virtual", "participation", "GRAVITY",
]

#: gravity [m/s²] (murus.G)
GRAVITY = 9.81

#: step of the central differences of the virtual displacements [rad]
_H = 1e-7


class MechanismError(MurusError, ValueError):
    """A mechanism cannot be built or analysed (geometry, loads, no collapse displacement)."""


def _positive(value, key, name, allow_zero=False):
    v = float(value)
    ok = math.isfinite(v) and (v >= 0 if allow_zero else v > 0)
    if not ok:
        raise MechanismError(f"{name} must be {'>= 0' if allow_zero else '> 0'}, got {value!r}",
                             key=key)
    return v


@dataclass(frozen=True)
class Storey:
    """One storey of a façade wall (a rectangular panel).

    Parameters
    ----------
    height : float
        Storey height [m] (> 0).
    thickness : float
        Wall thickness [m] (> 0); storeys are aligned on the outer face.
    density : float, optional
        Masonry density [kg/m³]; the weight is density g thickness (height width - openings).
    weight : float, optional
        The weight of the panel [N] instead of ``density`` (openings already removed).
    width : float
        Width of the façade strip analysed [m] (1.0: results per metre).
    openings : float
        Area of the openings within the strip [m²], removed from the weight.
    """

    height: float
    thickness: float
    density: float | None = None
    weight: float | None = None
    width: float = 1.0
    openings: float = 0.0

    def __post_init__(self):
        _positive(self.height, ("height",), "height")
        _positive(self.thickness, ("thickness",), "thickness")
        _positive(self.width, ("width",), "width")
        _positive(self.openings, ("openings",), "openings", allow_zero=True)
        if (self.density is None) == (self.weight is None):
            raise MechanismError("give either density or weight", key=("density",))
        if self.density is not None:
            _positive(self.density, ("density",), "density")
            if self.openings >= self.height * self.width:
                raise MechanismError("the openings take the whole panel", key=("openings",))
        else:
            _positive(self.weight, ("weight",), "weight")

    @property
    def W(self) -> float:
        """Weight of the panel [N]."""
        if self.weight is not None:
            return float(self.weight)
        return self.density * GRAVITY * self.thickness * (self.height * self.width
                                                          - self.openings)


@dataclass(frozen=True)
class Floor:
    """A floor (or the roof) resting on the top of a storey, with its tie.

    Parameters
    ----------
    level : int
        The floor at the top of storey ``level`` (1 = first floor).
    load : float
        Vertical load carried by the wall strip [N] (>= 0).
    x : float, optional
        Distance of the point of application of ``load`` from the outer face [m] (default: the
        middle of the wall below).
    tie : float
        Strength of the tie anchored at this floor [N] (0: no tie); it acts horizontally at the
        floor level, at mid-thickness of the wall.
    thrust : float
        Horizontal outward thrust of the floor or roof on the wall [N] (>= 0).
    inertial : bool
        The mass of the load moves with the wall (True, a floor resting on it): its weight also
        produces the horizontal force alpha x load.
    """

    level: int
    load: float = 0.0
    x: float | None = None
    tie: float = 0.0
    thrust: float = 0.0
    inertial: bool = True

    def __post_init__(self):
        if int(self.level) != self.level or self.level < 1:
            raise MechanismError(f"level must be an integer >= 1, got {self.level!r}",
                                 key=("level",))
        _positive(self.load, ("load",), "load", allow_zero=True)
        _positive(self.tie, ("tie",), "tie", allow_zero=True)
        _positive(self.thrust, ("thrust",), "thrust", allow_zero=True)
        if self.x is not None:
            _positive(self.x, ("x",), "x", allow_zero=True)


@dataclass(frozen=True)
class State:
    """Positions of the points of a mechanism in one configuration (arrays, SI units)."""

    points: np.ndarray      # (n, 2) application points of the weights
    P: np.ndarray           # (n,) gravity weights [N]
    W: np.ndarray           # (n,) weights producing horizontal inertial forces [N]
    ties: np.ndarray        # (m, 2) tie anchors
    T: np.ndarray           # (m,) tie strengths [N]
    thrusts: np.ndarray     # (k, 2) points of the thrusts
    F: np.ndarray           # (k,) thrusts [N]


@dataclass(frozen=True)
class Mechanism:
    """Base of the mechanisms: a one-degree-of-freedom chain of rigid blocks.

    Subclasses define :meth:`state` (positions at the rotation ``theta``), ``name``, ``z``
    (height of the base of the mechanism above the foundation [m], for the floor spectra of
    §C7.2.3) and ``theta_max`` (largest rotation of the kinematics [rad]).
    """

    def state(self, theta: float) -> State:  # pragma: no cover - abstract
        raise NotImplementedError

    name: str = field(default="mechanism", init=False)

    @property
    def z(self) -> float:  # pragma: no cover - abstract
        raise NotImplementedError

    theta_max: float = field(default=0.5 * math.pi, init=False)


def virtual(mech: Mechanism, theta: float) -> tuple[State, State]:
    """The configuration at ``theta`` and its virtual displacements (d position / d theta).

    Parameters
    ----------
    mech : Mechanism
    theta : float
        Rotation of the first block [rad].

    Returns
    -------
    tuple
        ``(state, rates)``: ``rates.points``, ``rates.ties``, ``rates.thrusts`` hold the
        virtual displacements per unit virtual rotation [m/rad].
    """
    s = mech.state(theta)
    a, b = mech.state(theta + _H), mech.state(theta - _H)
    d = State((a.points - b.points) / (2 * _H), s.P, s.W, (a.ties - b.ties) / (2 * _H), s.T,
              (a.thrusts - b.thrusts) / (2 * _H), s.F)
    return s, d


def alpha(mech: Mechanism, theta: float = 0.0) -> float:
    """Load multiplier alpha of the horizontal forces in equilibrium at the rotation ``theta``,
    by the virtual work equation, Circolare 2019 eq. [C8.7.1.1] (``theta = 0``: alpha0).

    Parameters
    ----------
    mech : Mechanism
    theta : float
        Rotation [rad].

    Returns
    -------
    float
        alpha [-] (negative beyond the collapse rotation).
    """
    _, d = virtual(mech, theta)
    den = float(np.sum(d.W * d.points[:, 0]))
    if den <= 0:
        raise MechanismError(f"{mech.name}: the horizontal forces do no work at theta = "
                             f"{theta:g} rad")
    num = float(np.sum(d.P * d.points[:, 1]))
    if d.T.size:
        num += float(np.sum(d.T * d.ties[:, 0]))
    if d.F.size:
        num -= float(np.sum(d.F * d.thrusts[:, 0]))
    return num / den


def participation(mech: Mechanism) -> dict:
    """Participating mass and the virtual displacements of the equivalent oscillator.

    ``e* = (sum W dx)^2 / (sum W sum W dx^2)`` (Circolare 2019 eq. [C8.7.1.5]),
    ``M* = e* sum W / g`` (Circolare 2009 eq. C8A.4.2), with the virtual displacements dx of the
    initial configuration; the control point is the centroid of the weights W.

    Parameters
    ----------
    mech : Mechanism

    Returns
    -------
    dict
        ``e_star`` [-], ``M_star`` [kg], ``W_total`` [N], ``dx`` [m/rad] of the weights,
        ``dx_control`` [m/rad], ``factor`` = sum W dx^2 / (dx_control sum W dx) [-] of
        eq. [C8.7.1.4].
    """
    s, d = virtual(mech, 0.0)
    W, dx = s.W, d.points[:, 0]
    Wt = float(W.sum())
    s1, s2 = float(np.sum(W * dx)), float(np.sum(W * dx ** 2))
    if Wt <= 0 or s1 <= 0:
        raise MechanismError(f"{mech.name}: no mass moves horizontally")
    e = s1 ** 2 / (Wt * s2)
    dxc = s1 / Wt  # the control point: centroid of the weights W
    return {"e_star": e, "M_star": e * Wt / GRAVITY, "W_total": Wt, "dx": dx,
            "dx_control": dxc, "factor": s2 / (dxc * s1)}


def control_x(mech: Mechanism, theta: float) -> float:
    """Horizontal position of the control point (centroid of the weights W) [m]."""
    s = mech.state(theta)
    return float(np.sum(s.W * s.points[:, 0]) / np.sum(s.W))


def _rot(v: np.ndarray, phi: float) -> np.ndarray:
    """Rotate the vectors ``v`` (n, 2) by ``phi`` clockwise (outward for a point above)."""
    c, s = math.cos(phi), math.sin(phi)
    return np.column_stack([v[:, 0] * c + v[:, 1] * s, -v[:, 0] * s + v[:, 1] * c])


def _arr(rows) -> np.ndarray:
    return np.asarray(rows, dtype=float).reshape(-1, 2)


@dataclass(frozen=True)
class SimpleOverturning(Mechanism):
    """Simple overturning of a façade about a hinge at the base of storey ``hinge`` (0-based):
    the storeys ``hinge`` ... top rotate as one rigid block about the outer edge of the base.

    Parameters
    ----------
    storeys : sequence of Storey
        Bottom to top.
    floors : sequence of Floor
        Floors and roof; a floor at the level of the hinge or below stays still.
    hinge : int
        Index of the lowest moving storey (0: the hinge at the foundation).
    slices : int
        Horizontal slices per storey, each with its weight at its centroid (1: one weight per
        storey, the sums over the block weights of eq. [C8.7.1.1]). More slices approach the
        continuous distribution of the mass: e* = 3 n^2 / (4 n^2 - 1) for one storey of n
        slices, 1 for n = 1, 3/4 in the limit; d0* = t/2 (4/3 - 1/(3 n^2)), t/2 to 2t/3.

    Notes
    -----
    The floors above the hinge act through their loads (at ``x`` from the outer face), ties
    (at mid-thickness) and thrusts; the tie of the floor at the hinge level does not restrain
    the mechanism. Circolare 2019 §C8.7.1.2.1; the overturning of the whole façade or of its upper
    storeys is the first mechanism of the Circolare 2009 §C8A.4 list.
    """

    storeys: tuple = ()
    floors: tuple = ()
    hinge: int = 0
    slices: int = 1

    def __post_init__(self):
        if int(self.slices) != self.slices or not 1 <= self.slices <= 1000:
            raise MechanismError(f"slices must be an integer in 1..1000, got {self.slices!r}",
                                 key=("slices",))
        object.__setattr__(self, "storeys", tuple(self.storeys))
        object.__setattr__(self, "floors", tuple(self.floors))
        n = len(self.storeys)
        if n == 0:
            raise MechanismError("no storeys", key=("storeys",))
        if not 0 <= self.hinge < n:
            raise MechanismError(f"hinge must be a storey index in 0..{n - 1}", key=("hinge",))
        for i, f in enumerate(self.floors):
            if f.level > n:
                raise MechanismError(f"level {f.level} is above the top storey ({n})",
                                     key=("floors", i, "level"))
            if f.x is not None and f.x > self.storeys[f.level - 1].thickness:
                raise MechanismError(f"x = {f.x:g} m is beyond the inner face of the wall "
                                     f"({self.storeys[f.level - 1].thickness:g} m thick)",
                                     key=("floors", i, "x"))
        object.__setattr__(self, "name", f"overturning from storey {self.hinge + 1}")
        levels = np.cumsum([0.0] + [s.height for s in self.storeys])
        pts, P, W = [], [], []
        m = int(self.slices)
        for i in range(self.hinge, n):
            s = self.storeys[i]
            for j in range(m):  # m horizontal slices of equal weight (openings spread evenly)
                pts.append((-0.5 * s.thickness, levels[i] + (j + 0.5) * s.height / m))
                P.append(s.W / m)
                W.append(s.W / m)
        ties, T, thr, F = [], [], [], []
        for f in self.floors:
            if f.level <= self.hinge:
                continue
            t = self.storeys[f.level - 1].thickness
            y = levels[f.level]
            if f.load > 0:
                x = 0.5 * t if f.x is None else f.x
                pts.append((-x, y))
                P.append(f.load)
                W.append(f.load if f.inertial else 0.0)
            if f.tie > 0:
                ties.append((-0.5 * t, y))
                T.append(f.tie)
            if f.thrust > 0:
                thr.append((0.0, y))
                F.append(f.thrust)
        y0 = levels[self.hinge]
        object.__setattr__(self, "_base", (y0, _arr(pts) - (0, y0), np.array(P), np.array(W),
                                           _arr(ties) - (0, y0), np.array(T, dtype=float),
                                           _arr(thr) - (0, y0), np.array(F, dtype=float)))
        object.__setattr__(self, "theta_max", 0.5 * math.pi)

    @property
    def z(self) -> float:
        """Height of the hinge above the foundation [m]."""
        return float(self._base[0])

    @property
    def height(self) -> float:
        """Height of the moving part [m]."""
        return float(sum(s.height for s in self.storeys[self.hinge:]))

    def state(self, theta: float) -> State:
        y0, pts, P, W, ties, T, thr, F = self._base
        o = np.array([0.0, y0])
        return State(_rot(pts, theta) + o, P, W, _rot(ties, theta) + o, T,
                     _rot(thr, theta) + o, F)


@dataclass(frozen=True)
class VerticalFlexure(Mechanism):
    """Vertical flexure of a wall restrained at its top and bottom: two blocks with the
    intermediate hinge at the height ``h1`` above the base.

    Hinges: A at the outer face of the base, B at the inner face at ``h1``, C at the outer face
    of the top; C is restrained horizontally and free to rise (the wall lifts the load above).
    Blocks: lower (A-B) rotates outward by theta about A, upper (B-C) by theta2 (h1 theta =
    (h - h1) theta2 at small rotations, exactly from x_C = 0 at finite rotations).

    Parameters
    ----------
    height, thickness : float
        Wall height and thickness [m].
    weight : float
        Weight of the wall [N] (openings removed).
    h1 : float
        Height of the intermediate hinge above the base [m], in (0, height).
    top_load : float
        Load on the top of the wall [N] (the wall and floors above).
    top_load_x : float, optional
        Its distance from the outer face [m] (default: half the thickness).
    top_inertial : bool
        The top load's mass pushes on the wall (default False: its horizontal force goes to the
        restraint at the top).
    z0 : float
        Height of the base of the wall above the foundation [m].

    References
    ----------
    Circolare 2019 §C8.7.1.2.1 (kinematic chain); the vertical flexure mechanism of the
    Circolare 2009 §C8A.4 (two blocks, hinge height chosen to minimise alpha0).
    """

    height: float = 3.0
    thickness: float = 0.5
    weight: float = 1.0
    h1: float = 1.5
    top_load: float = 0.0
    top_load_x: float | None = None
    top_inertial: bool = False
    z0: float = 0.0

    def __post_init__(self):
        _positive(self.height, ("height",), "height")
        _positive(self.thickness, ("thickness",), "thickness")
        _positive(self.weight, ("weight",), "weight")
        _positive(self.top_load, ("top_load",), "top_load", allow_zero=True)
        _positive(self.z0, ("z0",), "z0", allow_zero=True)
        if not 0 < self.h1 < self.height:
            raise MechanismError(f"h1 must be in (0, height), got {self.h1!r}", key=("h1",))
        object.__setattr__(self, "name", "vertical flexure")
        object.__setattr__(self, "theta_max", 0.5 * math.pi)

    @property
    def z(self) -> float:
        """Height of the base of the wall above the foundation [m]."""
        return float(self.z0)

    def _theta2(self, theta: float) -> float:
        t, h1, h2 = self.thickness, self.h1, self.height - self.h1
        c = t * math.cos(theta) - h1 * math.sin(theta)
        R = math.hypot(t, h2)
        if abs(c) > R:
            return float("nan")
        return math.acos(c / R) - math.atan2(h2, t)

    def state(self, theta: float) -> State:
        t, h, h1 = self.thickness, self.height, self.h1
        h2 = h - h1
        w1, w2 = self.weight * h1 / h, self.weight * h2 / h
        th2 = self._theta2(theta)
        B = _rot(_arr([(-t, h1)]), theta)[0]
        p1 = _rot(_arr([(-0.5 * t, 0.5 * h1)]), theta)[0]
        xn = 0.5 * t if self.top_load_x is None else self.top_load_x
        rel = _rot(_arr([(0.5 * t, 0.5 * h2), (t - xn, h2)]), -th2) + B
        pts = np.vstack([p1, rel[0], rel[1]]) + (0.0, self.z0)
        P = np.array([w1, w2, self.top_load])
        W = np.array([w1, w2, self.top_load if self.top_inertial else 0.0])
        e = np.zeros((0, 2))
        return State(pts, P, W, e, np.zeros(0), e, np.zeros(0))


@dataclass(frozen=True)
class CornerOverturning(Mechanism):
    """Overturning of a building corner: a rigid wedge of the two walls meeting at the corner,
    detached by straight cracks, rotating about the horizontal axis through the external corner
    of its base, orthogonal to the bisector of the corner; the horizontal forces act along the
    bisector, outward.

    The formulation (the simplest one murus could state completely): in each wall the wedge is
    a triangle with its apex at the corner at the hinge level and its top side along the top of
    the walls, of width ``height * tan(crack_angle)`` (wall 1 measured from the corner, wall 2
    from the inner face of wall 1, so that the corner pier is counted once). A rigid rotation
    about a horizontal axis moves each point in the vertical plane orthogonal to the axis: the
    points are described by their height and their distance s from the axis along the outward
    bisector (s = -(X + Y) / sqrt(2) for a point at X, Y in plan from the external corner), and
    the virtual work of Circolare 2019 eq. [C8.7.1.1] is written in that plane. Ties along wall 1
    and wall 2 at the top level restrain the wedge with their component along the bisector
    (strength / sqrt(2) each); a thrust along the bisector (hip rafter) pushes it outward.

    Parameters
    ----------
    height : float
        Height of the wedge above the hinge [m].
    t1, t2 : float
        Thickness of wall 1 and wall 2 [m].
    density : float
        Masonry density [kg/m³].
    crack_angle_deg : float
        Angle of the cracks from the vertical [deg] (0 < angle < 75).
    roof_load : float
        Vertical load on the top of the wedge [N] (moves with it; its mass pushes too).
    roof_load_s : float, optional
        Its distance from the corner along the inward bisector [m] (default: the centroid of the
        wedge's top in plan).
    thrust : float
        Outward thrust along the bisector at the top [N].
    tie1, tie2 : float
        Strengths of the ties along wall 1 and wall 2 at the top [N].
    z0 : float
        Height of the hinge above the foundation [m].

    References
    ----------
    Circolare 2019 §C8.7.1.2.1 (kinematic chain and virtual work, eq. C8.7.1.1); the corner
    overturning ("ribaltamento del cantonale") is one of the recurrent mechanisms of the Italian
    practice listed with the Circolare 2009 §C8A.4.
    """

    height: float = 3.0
    t1: float = 0.5
    t2: float = 0.5
    density: float = 1800.0
    crack_angle_deg: float = 30.0
    roof_load: float = 0.0
    roof_load_s: float | None = None
    thrust: float = 0.0
    tie1: float = 0.0
    tie2: float = 0.0
    z0: float = 0.0

    def __post_init__(self):
        for k in ("height", "t1", "t2", "density"):
            _positive(getattr(self, k), (k,), k)
        for k in ("roof_load", "thrust", "tie1", "tie2", "z0"):
            _positive(getattr(self, k), (k,), k, allow_zero=True)
        if not 0 < self.crack_angle_deg < 75:
            raise MechanismError("crack_angle_deg must be in (0, 75)", key=("crack_angle_deg",))
        h, t1, t2 = self.height, self.t1, self.t2
        L = h * math.tan(math.radians(self.crack_angle_deg))
        g = GRAVITY * self.density
        r2 = math.sqrt(2.0)
        # wall 1: triangle (X from 0 to L at the top), Y = t1 / 2; wall 2: Y from t1, X = t2 / 2
        W1 = g * t1 * 0.5 * L * h
        W2 = g * t2 * 0.5 * L * h
        X1, Y1 = L / 3.0, 0.5 * t1
        X2, Y2 = 0.5 * t2, t1 + L / 3.0
        pts = [(-(X1 + Y1) / r2, 2.0 * h / 3.0), (-(X2 + Y2) / r2, 2.0 * h / 3.0)]
        P, W = [W1, W2], [W1, W2]
        if self.roof_load > 0:
            s = (self.roof_load_s if self.roof_load_s is not None
                 else (W1 * (X1 + Y1) + W2 * (X2 + Y2)) / (r2 * (W1 + W2)))
            pts.append((-s, h))
            P.append(self.roof_load)
            W.append(self.roof_load)
        ties, T = [], []
        for tie in (self.tie1, self.tie2):
            if tie > 0:
                ties.append((-(L / 2 + 0.5 * t1) / r2, h))
                T.append(tie / r2)
        thr, F = ([(0.0, h)], [self.thrust]) if self.thrust > 0 else ([], [])
        object.__setattr__(self, "name", "corner overturning")
        object.__setattr__(self, "theta_max", 0.5 * math.pi)
        object.__setattr__(self, "_base", (self.z0, _arr(pts), np.array(P), np.array(W),
                                           _arr(ties), np.array(T, dtype=float), _arr(thr),
                                           np.array(F, dtype=float)))

    @property
    def z(self) -> float:
        """Height of the hinge above the foundation [m]."""
        return float(self.z0)

    state = SimpleOverturning.state

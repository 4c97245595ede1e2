"""Rigid bodies that rock on their base.

Geometry and sign convention
----------------------------
The body is a rectangle of width ``b`` (in the plane of rocking) and height ``h``, standing on a
rigid base with its two bottom corners O (right, pivot ``+1``) and O' (left, pivot ``-1``).  Its
mass is the sum of a uniform rectangle of density ``rho`` and thickness ``t`` (out of plane) and of
an optional lumped mass ``m_top`` at mid-top (Mordant et al. (SERIES), §3.1: 5 t on the tested
walls), and of optional lumped masses ``m_i`` at heights ``y_i`` on the centreline (the floors
carried by a façade).

- ``theta > 0`` is a clockwise rotation about O (Mordant et al. (SERIES), §3.1.1, EURODYN (2020),
  Figure 1).
- ``R`` is the distance from a corner to the centre of gravity G and ``alpha`` the angle between
  ``R`` and the vertical: ``tan(alpha) = (b/2) / z_G`` (Mordant et al. (SERIES), eq. 2; its
  "tan(B/2H)" is a typo for ``alpha = arctan(B / 2H)``, see REFERENCE.md).
- ``I_O`` is the moment of inertia about a corner (Mordant et al. (SERIES), eq. 4 for the top mass,
  ``m R^2``; ``4/3 m R^2`` for a uniform rectangle, EURODYN (2020), Table 1).
- ``p = sqrt(m g R / I_O)`` is the frequency parameter (EURODYN (2020), §2).

All quantities in SI units: m, kg, kg m², rad, rad/s.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from functools import cached_property

from murus import G
from murus.errors import MurusError


class BodyError(MurusError, ValueError):
    """A body definition that is not physical (one-line message naming the parameter)."""


def _positive(name: str, value: float) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise BodyError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(v) or v <= 0.0:
        raise BodyError(f"{name} must be a positive finite number, got {value!r}")
    return v


def _non_negative(name: str, value: float) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise BodyError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(v) or v < 0.0:
        raise BodyError(f"{name} must be a non-negative finite number, got {value!r}")
    return v


@dataclass(frozen=True)
class RigidBlock:
    """A rectangular rigid wall or block, with self-weight and/or a lumped mass at mid-top.

    Parameters
    ----------
    width:
        ``b`` [m], dimension in the plane of rocking (the wall thickness ``s`` of EURODYN (2020),
        the wall length ``B`` of Mordant et al. (SERIES)).
    height:
        ``h`` [m].
    thickness:
        Out-of-plane dimension [m] (1.0 for the unit-length walls of EURODYN (2020)).
    density:
        Mass density of the uniform rectangle [kg/m³]; 0 for a massless wall carrying only
        ``top_mass`` (Mordant et al. (SERIES): self-weight neglected).  EURODYN (2020) uses 21
        kN/m³, i.e. ``21000 / 9.81 = 2140.7`` kg/m³.
    top_mass:
        Lumped mass at mid-top [kg] (Mordant et al. (SERIES): 5000 kg).
    name:
        Label used in reports.
    masses:
        Further lumped masses on the centreline, ``((m_i [kg], y_i [m]), ...)`` with
        ``0 <= y_i <= h``: the floors a façade carries (their loads on the wall at mid-thickness,
        moving with it). ``top_mass = m`` is ``masses = ((m, h),)``.

    Examples
    --------
    >>> blk = RigidBlock(width=0.3, height=3.0, density=21000 / 9.81)   # EURODYN (2020) block1
    >>> round(blk.mass), round(blk.R, 3), round(blk.I_O)
    (1927, 1.507, 5838)
    """

    width: float
    height: float
    thickness: float = 1.0
    density: float = 0.0
    top_mass: float = 0.0
    name: str = field(default="block", compare=False)
    masses: tuple = ()

    #: Declared parameters and their validity limits (GUIDE §3).
    PARAMS = {
        "width": ("m", "> 0"),
        "height": ("m", "> 0"),
        "thickness": ("m", "> 0"),
        "density": ("kg/m3", ">= 0"),
        "top_mass": ("kg", ">= 0"),
        "masses": ("(kg, m)", "m_i >= 0, 0 <= y_i <= height"),
    }

    def __post_init__(self) -> None:
        object.__setattr__(self, "width", _positive("width", self.width))
        object.__setattr__(self, "height", _positive("height", self.height))
        object.__setattr__(self, "thickness", _positive("thickness", self.thickness))
        object.__setattr__(self, "density", _non_negative("density", self.density))
        object.__setattr__(self, "top_mass", _non_negative("top_mass", self.top_mass))
        lumped = []
        try:
            pairs = [tuple(p) for p in self.masses]
        except TypeError:
            raise BodyError("masses must be pairs (mass [kg], height [m])") from None
        for i, p in enumerate(pairs):
            if len(p) != 2:
                raise BodyError(f"masses[{i}] must be a pair (mass [kg], height [m])")
            m = _non_negative(f"masses[{i}] mass", p[0])
            y = _non_negative(f"masses[{i}] height", p[1])
            if y > self.height * (1 + 1e-12):
                raise BodyError(f"masses[{i}] height {y:g} m is above the top of the body "
                                f"({self.height:g} m)")
            lumped.append((m, y))
        object.__setattr__(self, "masses", tuple(lumped))
        if self.mass <= 0.0:
            raise BodyError("the body has no mass: give a positive density or top_mass")

    # -- masses -----------------------------------------------------------------------------
    @cached_property
    def body_mass(self) -> float:
        """Mass of the uniform rectangle [kg]."""
        return self.density * self.width * self.height * self.thickness

    @cached_property
    def mass(self) -> float:
        """Total mass ``m`` [kg]."""
        return self.body_mass + self.top_mass + sum(m for m, _ in self.masses)

    @property
    def weight(self) -> float:
        """Weight ``m g`` [N] with ``g = murus.G``."""
        return self.mass * G

    # -- geometry about a corner -------------------------------------------------------------
    @cached_property
    def z_G(self) -> float:
        """Height of the centre of gravity above the base [m]."""
        return (self.body_mass * 0.5 * self.height + self.top_mass * self.height
                + sum(m * y for m, y in self.masses)) / self.mass

    @cached_property
    def R(self) -> float:
        """Distance from a base corner to the centre of gravity [m] (Mordant et al. (SERIES), eq.
        2)."""
        return math.hypot(self.z_G, 0.5 * self.width)

    @cached_property
    def alpha(self) -> float:
        """Slenderness angle [rad]: ``arctan((b/2) / z_G)``."""
        return math.atan2(0.5 * self.width, self.z_G)

    @cached_property
    def I_O(self) -> float:
        """Moment of inertia about a base corner [kg m²] (Mordant et al. (SERIES), eq. 4,
        EURODYN (2020), Table 1).

        Uniform rectangle: ``m_b (b² + h²) / 3``; top mass: ``m_top (h² + b²/4)``; a lumped
        mass on the centreline: ``m_i (y_i² + b²/4)``.
        """
        rect = self.body_mass * (self.width**2 + self.height**2) / 3.0
        top = self.top_mass * (self.height**2 + 0.25 * self.width**2)
        lumped = sum(m * (y * y + 0.25 * self.width**2) for m, y in self.masses)
        return rect + top + lumped

    @cached_property
    def p(self) -> float:
        """Frequency parameter ``p = sqrt(m g R / I_O)`` [rad/s] (EURODYN (2020), §2)."""
        return math.sqrt(self.mass * G * self.R / self.I_O)

    @property
    def slenderness(self) -> float:
        """``lambda = h / b`` [-] (EURODYN (2020), §3)."""
        return self.height / self.width

    @property
    def uplift_acceleration(self) -> float:
        """Static uplift threshold ``g tan(alpha)`` [m/s²] (Mordant et al. (SERIES), eq. 9)."""
        return G * math.tan(self.alpha)

    def housner_restitution(self) -> float:
        """Housner's coefficient of restitution for this body [-].

        Conservation of angular momentum about the new pivot at impact gives
        ``e = 1 - 2 m R² sin²(alpha) / I_O`` (Mordant et al. (SERIES), eq. 10), which is ``cos 2
        alpha`` for the top mass alone and ``1 - 3/2 sin²(alpha)`` for a uniform rectangle
        (EURODYN (2020), §4.3).
        """
        return 1.0 - 2.0 * self.mass * self.R**2 * math.sin(self.alpha) ** 2 / self.I_O

    def describe(self) -> dict:
        """The derived quantities as a plain dictionary (SI units)."""
        return {
            "name": self.name,
            "width": self.width,
            "height": self.height,
            "thickness": self.thickness,
            "density": self.density,
            "top_mass": self.top_mass,
            "masses": [list(p) for p in self.masses],
            "mass": self.mass,
            "z_G": self.z_G,
            "R": self.R,
            "alpha": self.alpha,
            "I_O": self.I_O,
            "p": self.p,
            "housner_e": self.housner_restitution(),
        }


#: Unit weight used by EURODYN (2020) for all blocks [N/m³].
RESTRAINED_WALL_UNIT_WEIGHT = 21000.0


def restrained_wall_block(label: str) -> RigidBlock:
    """One of the six unit-length blocks of EURODYN (2020), Table 1 (``block1`` ... ``block6``).

    Thickness ``s`` and slenderness ``lambda`` from the table, unit weight 21 kN/m³.

    Parameters
    ----------
    label : str
        ``"block1"`` ... ``"block6"``.

    Returns
    -------
    RigidBlock
        Width ``s`` [m], height ``lambda s`` [m], 1 m thick, density 21000 / g [kg/m³].

    References
    ----------
    EURODYN (2020), Table 1 (docs/references.md, key ``eurodyn2020``).
    """
    table = {
        "block1": (10, 0.3),
        "block2": (10, 0.6),
        "block3": (10, 0.9),
        "block4": (13, 0.3),
        "block5": (13, 0.6),
        "block6": (13, 0.9),
    }
    if label not in table:
        raise BodyError(f"unknown EURODYN (2020) block {label!r}; expected one of {sorted(table)}")
    lam, s = table[label]
    return RigidBlock(
        width=s, height=lam * s, thickness=1.0, density=RESTRAINED_WALL_UNIT_WEIGHT / G, name=label
    )


def series_clay_wall(kind: str, self_weight: bool = False, density: float = 0.0) -> RigidBlock:
    """A wall of Mordant et al. (SERIES), §1.2: ``"short"`` (0.72 m) or ``"long"`` (2.10 m), 1.80 m
    high,
    0.138 m thick, with 5 t at mid-top; its self-weight is neglected unless ``self_weight``.

    Parameters
    ----------
    kind : str
        ``"short"`` (B = 0.72 m) or ``"long"`` (B = 2.10 m).
    self_weight : bool
        Include the self-weight of the masonry (neglected by default).
    density : float
        Masonry density [kg/m³], needed with ``self_weight``.

    Returns
    -------
    RigidBlock

    References
    ----------
    Mordant et al. (SERIES), §1.2 (docs/references.md, key ``mordant_series``).
    """
    widths = {"short": 0.72, "long": 2.10}
    if kind not in widths:
        raise BodyError(f"unknown Mordant et al. (SERIES) wall {kind!r}; "
                        "expected 'short' or 'long'")
    if self_weight and density <= 0.0:
        raise BodyError("self_weight=True needs the masonry density")
    return RigidBlock(
        width=widths[kind],
        height=1.80,
        thickness=0.138,
        density=density if self_weight else 0.0,
        top_mass=5000.0,
        name=f"series-{kind}",
    )


# ------------------------------------------------------------ deprecated names (one release) --
def seed002_block(label: str) -> RigidBlock:
    """Deprecated alias of :func:`restrained_wall_block` (removed in the next release).

    Parameters
    ----------
    label : str
        ``"block1"`` ... ``"block6"``.

    Returns
    -------
    RigidBlock
        The block of EURODYN (2020), Table 1.
    """
    warnings.warn("seed002_block is deprecated: use restrained_wall_block", DeprecationWarning,
                  stacklevel=2)
    return restrained_wall_block(label)


def seed000_wall(kind: str, self_weight: bool = False, density: float = 0.0) -> RigidBlock:
    """Deprecated alias of :func:`series_clay_wall` (removed in the next release).

    Parameters
    ----------
    kind : str
        ``"short"`` or ``"long"``.
    self_weight : bool
        Include the self-weight of the masonry.
    density : float
        Masonry density [kg/m³] (needed with ``self_weight``).

    Returns
    -------
    RigidBlock
        The wall of Mordant et al. (SERIES), §1.2.
    """
    warnings.warn("seed000_wall is deprecated: use series_clay_wall", DeprecationWarning,
                  stacklevel=2)
    return series_clay_wall(kind, self_weight=self_weight, density=density)


def __getattr__(name: str):
    if name == "SEED002_UNIT_WEIGHT":
        warnings.warn("SEED002_UNIT_WEIGHT is deprecated: use RESTRAINED_WALL_UNIT_WEIGHT",
                      DeprecationWarning, stacklevel=2)
        return RESTRAINED_WALL_UNIT_WEIGHT
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

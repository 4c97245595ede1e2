"""Restraints of a rocking wall: a horizontal tie, a spring bed (transverse walls) and a viscous
damper (EURODYN (2020), §2, eqs. 1-7), and the pivot laws of Mordant et al. (SERIES), §3.3.1.

Geometry: a point of the wall is given by its height ``y`` above the base and its horizontal body
coordinate ``x`` from the middle of the base, positive towards the pivot O of positive rotations
(the outer face, ``x = +b/2``). The wall rotates outward (``theta > 0``) against the tie and
inward (``theta < 0``, about the pivot O' at ``x = -b/2``) against the transverse walls,
represented by a no-tension bed of horizontal springs over the heights ``[z1, z2]`` (EURODYN (2020)
Figure 1: "one-sided" motion). By default the bed acts on the face at ``x = +b/2``, at the
distance ``s = b`` from O', which is the geometry of EURODYN (2020), eq. 6 (reproduced exactly up to
the factor ``cos theta`` of its springs normal to the rotated face, and with the factor ``s`` that
its printed ``B`` term lacks for dimensional consistency); ``x = -b/2`` puts it on the pivot's face.
The moments are written out in :func:`murus.rocking.kernels.restraint_moment`. SI units: N/m,
N/m per m of height, N s/m, m.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

from murus import G
from murus.errors import MurusError


class RestraintError(MurusError, ValueError):
    """An invalid restraint (one-line message naming the parameter)."""


def _num(owner: str, name: str, value, *, positive=False, allow_inf=False) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise RestraintError(f"{owner} {name} must be a number, got {value!r}") from None
    if math.isnan(v) or (math.isinf(v) and not allow_inf):
        raise RestraintError(f"{owner} {name} must be finite, got {value!r}")
    if positive and not v > 0.0:
        raise RestraintError(f"{owner} {name} must be positive, got {value!r}")
    if not positive and v < 0.0:
        raise RestraintError(f"{owner} {name} must not be negative, got {value!r}")
    return v


@dataclass(frozen=True)
class Tie:
    """A horizontal tie (steel tie rod, or the elastic part of a device) of axial stiffness
    ``stiffness`` [N/m] anchored at ``height`` [m] and body coordinate ``x`` [m] (EURODYN (2020),
    eq. 2, term T_K).

    ``tension_only`` (default): the tie works only when the wall moves outward (a rod anchored
    by a plate); ``False``: the bidirectional elastic tie of EURODYN (2020), Figure 2.
    ``pretension`` [N] and ``yield_force`` [N] (elastic-perfectly plastic, with the plastic
    elongation carried along the run) are the options EURODYN (2020) leaves out.

    Parameters
    ----------
    stiffness : float
        Axial stiffness [N/m] (>= 0).
    height : float
        Height of the anchorage above the base [m].
    x : float
        Body coordinate of the anchorage [m] (0: mid-thickness).
    tension_only : bool
        The tie works only when the wall moves outward.
    pretension : float
        Initial tension [N].
    yield_force : float, optional
        Yield force [N] of an elastic-perfectly plastic tie; ``None``: elastic.

    References
    ----------
    EURODYN (2020), eqs. 2 and 12.
    """

    stiffness: float
    height: float
    x: float = 0.0
    tension_only: bool = True
    pretension: float = 0.0
    yield_force: float = math.inf
    KIND: ClassVar[str] = "tie"

    def __post_init__(self) -> None:
        object.__setattr__(self, "stiffness", _num("tie", "stiffness", self.stiffness,
                                                   positive=True))
        object.__setattr__(self, "height", _num("tie", "height", self.height, positive=True))
        object.__setattr__(self, "pretension", _num("tie", "pretension", self.pretension))
        object.__setattr__(self, "yield_force", _num("tie", "yield_force", self.yield_force,
                                                     positive=True, allow_inf=True))
        try:
            object.__setattr__(self, "x", float(self.x))
        except (TypeError, ValueError):
            raise RestraintError(f"tie x must be a number, got {self.x!r}") from None
        if self.pretension > self.yield_force:
            raise RestraintError("tie pretension exceeds its yield force")

    def fill(self, P, body) -> None:
        """Write the tie into the kernels' parameter record ``P`` (:data:`murus.rocking.kernels.
        PARAMS`; the moment is in :func:`murus.rocking.kernels.restraint_terms`)."""
        from murus.rocking import kernels as K

        P["tie_mode"] = float(K.TIE_TENSION if self.tension_only else K.TIE_BOTH)
        P["tie_k"] = self.stiffness
        P["tie_y"] = self.height
        P["tie_x"] = self.x
        P["tie_p0"] = self.pretension
        P["tie_fy"] = self.yield_force

    def describe(self) -> dict:
        return {"stiffness": self.stiffness, "height": self.height, "x": self.x,
                "tension_only": self.tension_only, "pretension": self.pretension,
                "yield_force": None if math.isinf(self.yield_force) else self.yield_force}


@dataclass(frozen=True)
class SpringBed:
    """Transverse walls as a no-tension bed of horizontal springs of stiffness ``stiffness``
    per unit height [N/m/m], from ``z1`` to ``z1 + effective_height`` [m], resisting inward
    motion (EURODYN (2020), eqs. 3-6, term T_K'; eq. 10: ``K' = E_x t / L_eff``, 4.5e8 N/m/m in
    §4.2).
    ``x``: body coordinate of the face it acts on (default ``+b/2``, EURODYN (2020), eq. 6; see the
    module docstring).

    ``stiffness = inf``: rigid transverse walls, the limit of a stiff bed. The wall then never
    rotates inward: at ``theta = 0`` it bounces with ``theta'+ = -e_1 e_2 theta'-``, the two
    base impacts of the elastic bed's bounce (into and out of the walls; the second with the
    half-cycle rotation of the bounce, zero) with an elastic bounce of no duration. The run then
    needs none of the many small steps a stiff bed contact takes
    (tests/rocking/test_restraints.py checks the convergence as the stiffness grows). The
    geometric cascade of ever smaller bounces ends, with the wall at rest against the walls,
    once the excursion a bounce starts (``theta'^2 / (2 |theta''|)`` under the restoring
    acceleration at ``theta = 0``) is below ``rest_tol * alpha``.

    Parameters
    ----------
    stiffness : float
        Stiffness per unit height [N/m/m]; ``inf`` for rigid transverse walls.
    effective_height : float
        Height of the bed [m].
    z1 : float
        Height of its lower end [m].
    x : float, optional
        Body coordinate of the face it acts on [m] (default ``+b/2``).

    References
    ----------
    EURODYN (2020), eqs. 3-6 and 10.
    """

    stiffness: float
    effective_height: float
    z1: float = 0.0
    x: float | None = None
    KIND: ClassVar[str] = "transverse_walls"

    def __post_init__(self) -> None:
        object.__setattr__(self, "stiffness", _num("transverse_walls", "stiffness",
                                                   self.stiffness, positive=True,
                                                   allow_inf=True))
        object.__setattr__(self, "effective_height", _num(
            "transverse_walls", "effective_height", self.effective_height, positive=True))
        object.__setattr__(self, "z1", _num("transverse_walls", "z1", self.z1))

    def fill(self, P, body) -> None:
        """Write the spring bed (or the rigid walls) into the kernels' parameter record ``P``."""
        if math.isinf(self.stiffness):
            P["stop"] = 1.0
        else:
            P["bed_k"] = self.stiffness
        P["bed_z1"] = self.z1
        P["bed_z2"] = self.z1 + self.effective_height
        P["bed_x"] = 0.5 * body.width if self.x is None else self.x

    def describe(self) -> dict:
        k = "rigid" if math.isinf(self.stiffness) else self.stiffness
        return {"stiffness": k, "effective_height": self.effective_height,
                "z1": self.z1, "x": self.x}


@dataclass(frozen=True)
class Damper:
    """A horizontal linear viscous damper of coefficient ``coefficient`` [N s/m] at ``height``
    [m] and body coordinate ``x`` [m] (EURODYN (2020), eq. 7, term T_D; eq. 13 gives the reference
    ``c_d``, :func:`murus.rocking.design.reference_damping`).

    Parameters
    ----------
    coefficient : float
        Damping coefficient [N s/m] (>= 0).
    height : float
        Height of the anchorage above the base [m].
    x : float
        Body coordinate of the anchorage [m].

    References
    ----------
    EURODYN (2020), eqs. 7 and 13.
    """

    coefficient: float
    height: float
    x: float = 0.0
    KIND: ClassVar[str] = "damper"

    def __post_init__(self) -> None:
        object.__setattr__(self, "coefficient", _num("damper", "coefficient",
                                                     self.coefficient))
        object.__setattr__(self, "height", _num("damper", "height", self.height,
                                                positive=True))
        try:
            object.__setattr__(self, "x", float(self.x))
        except (TypeError, ValueError):
            raise RestraintError(f"damper x must be a number, got {self.x!r}") from None

    def fill(self, P, body) -> None:
        """Write the damper into the kernels' parameter record ``P``."""
        P["dmp_c"] = self.coefficient
        P["dmp_y"] = self.height
        P["dmp_x"] = self.x

    def describe(self) -> dict:
        return {"coefficient": self.coefficient, "height": self.height, "x": self.x}


# ------------------------------------------------------------------------------ pivot laws ---
#: Readings of the zero-stress pivot of Mordant et al. (SERIES), §3.3.1 (lever arm of the weight
#: about it).
PIVOT_READINGS = {
    "corner": 0,  # b/2, Housner's corner
    "kern": 1,  # b/6
    "effective-width": 2,  # Lc/2
    "neutral-axis": 3,  # b - 3e
}


@dataclass(frozen=True)
class Pivot:
    """Where the wall pivots (Mordant et al. (SERIES), §3.3.1, eqs. 11-13, reconstructed: their text
    was lost).

    ``law = "corner"`` is Housner's corner. ``law = "compressive-length"`` puts the pivot at the
    point given by the EN 1996-1-1 linear stress block of the equivalent static load at every
    instant: eccentricity ``e = factor |a_g| z_G / (g + a_v)``, compressed length ``Lc``, and the
    lever of the weight about the pivot is read as ``reading``:

    - ``"kern"``: ``b/6``; rocking starts at 3 times the corner's criterion;
    - ``"effective-width"`` (default): ``Lc/2``, the middle of the compressed length; rocking
      starts when ``e = 0.3 b``, at 5/3 of the corner's criterion;
    - ``"neutral-axis"``: ``b - 3e = Lc - b/2``, the lever about the zero-stress point; starts at
      ``e = b/4``, twice the corner's criterion;
    - ``"corner"``: ``b/2``.

    All are bounded to ``[min_lever, b/2]`` (``min_lever`` default 5 % of ``b/2``: a lever of
    zero would leave no restoring moment at all). The default reading is the one that predicts
    rocking for tests S07-S09 of both walls of Mordant et al. (SERIES) and not for the long wall at
    S06 (VALIDATION.md). ``alpha_n``, ``R_n``, the inertia about the pivot and Housner's ``e_n``
    follow the lever (eqs. 12-13).

    Parameters
    ----------
    law : str
        ``"corner"`` or ``"compressive-length"``.
    reading : str
        ``"effective-width"``, ``"kern"``, ``"neutral-axis"`` or ``"corner"``.
    factor : float
        Factor on the eccentricity of the equivalent static load [-].
    min_lever_fraction : float
        Smallest lever as a fraction of ``b/2`` [-].

    References
    ----------
    Mordant et al. (SERIES), §3.3.1, eqs. 11-13 (reconstructed); EN 1996-1-1, as in
    :mod:`murus.eurocode.ec6`.
    """

    law: str = "corner"
    reading: str = "effective-width"
    factor: float = 1.0
    min_lever_fraction: float = 0.05

    def __post_init__(self) -> None:
        if self.law not in ("corner", "compressive-length"):
            raise RestraintError(
                f"unknown pivot law {self.law!r}; expected 'corner' or 'compressive-length'")
        if self.reading not in PIVOT_READINGS:
            raise RestraintError(f"unknown pivot reading {self.reading!r}; expected one of "
                                 f"{', '.join(PIVOT_READINGS)}")
        f = _num("pivot", "factor", self.factor, positive=True)
        object.__setattr__(self, "factor", f)
        mf = _num("pivot", "min_lever_fraction", self.min_lever_fraction, positive=True)
        if mf > 1.0:
            raise RestraintError(f"pivot min_lever_fraction must be at most 1, got {mf!r}")
        object.__setattr__(self, "min_lever_fraction", mf)

    @property
    def code(self) -> int:
        return 0 if self.law == "corner" else PIVOT_READINGS[self.reading]

    def lever(self, body, a_g, a_v=0.0, g: float = G):
        """Lever of the weight about the pivot [m] for ground accelerations ``a_g``, ``a_v``
        [m/s²] (scalars or arrays), evaluated by the kernel's own formula
        (:func:`murus.rocking.kernels.lever`).

        Parameters
        ----------
        body : RigidBlock
            The body (its width [m] and height of the centre of gravity [m]).
        a_g, a_v : float or array_like
            Horizontal and vertical ground accelerations [m/s²].
        g : float
            Gravity [m/s²].

        Returns
        -------
        float or numpy.ndarray
            The lever [m], of the shape of ``a_g``.
        """
        import numpy as np

        from murus.rocking import kernels as K

        P = K.new_params()
        P["hb"] = 0.5 * body.width
        P["zg"] = body.z_G
        P["g"] = g
        self.fill(P, body)
        ag = np.asarray(a_g, dtype=float)
        av = np.broadcast_to(np.asarray(a_v, dtype=float), ag.shape)
        out = K.levers(np.ascontiguousarray(ag.ravel()), np.ascontiguousarray(av.ravel()), P)
        return float(out[0]) if ag.ndim == 0 else out.reshape(ag.shape)

    def fill(self, P, body) -> None:
        """Write the pivot law into the kernels' parameter record ``P``."""
        P["pivot"] = float(self.code)
        P["pivot_min"] = self.min_lever_fraction * 0.5 * body.width
        P["pivot_factor"] = self.factor

    def describe(self) -> dict:
        return {"law": self.law, "reading": self.reading if self.law != "corner" else None,
                "factor": self.factor, "min_lever_fraction": self.min_lever_fraction}

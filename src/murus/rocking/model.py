"""The rocking model: a body, its restitution law and the options of the equation of motion.

The model compiles into the flat parameter vector that the numba kernels read
(:mod:`murus.rocking.kernels`); moment terms added later (ties, spring beds, dampers, variable
pivot) extend that vector, not the integrators.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from murus import G
from murus.errors import MurusError
from murus.rocking import kernels as K
from murus.rocking.body import RigidBlock
from murus.rocking.restitution import Housner, RestitutionLaw, make_restitution
from murus.rocking.restraints import Damper, Pivot, SpringBed, Tie


class ModelError(MurusError, ValueError):
    """An invalid model option."""


@dataclass(frozen=True)
class RockingModel:
    """A rigid body rocking on a rigid base (Housner 1963; Mordant et al. (SERIES), §3.1,
    EURODYN (2020), eq. 1).

    Parameters
    ----------
    body:
        The :class:`RigidBlock`.
    restitution:
        A law object, ``"housner"`` or a number in [0, 1] (constant law).
    linearised:
        Use the linearised equation ``sin x -> x, cos x -> 1`` (slender blocks; the equation of
        the closed-form pulse solutions).
    gravity:
        ``g`` [m/s²].
    rest_tol:
        End of a cascade of ever smaller impacts [-] (event-driven method). Once the velocity
        after an impact is below ``rest_tol * p * alpha``, the rest of the cascade is summed
        instead of integrated: its bounce times form a geometric series (ratio ``e``; ``e^2``
        against rigid transverse walls) whose limit, the accumulation point, is where the body
        truly comes to rest (Housner 1963). The body is put at rest there, and only if the
        ground cannot lift it over the cascade and as long again after it; otherwise the
        integration goes on. The default 1e-3 agrees with ``rest_tol = 1e-9`` at ``rtol =
        1e-12`` within 0.1 % on theta_max on real records wherever the response is not chaotic
        (VALIDATION.md); ``0`` never ends a cascade, and the run stops with a step size
        underflow (``success`` False). With ``method = "newmark"`` the body is put at rest at
        once (velocity below ``rest_tol * p * alpha``, or a bounce on rigid walls below
        ``rest_tol * alpha``).
    tie, transverse_walls, damper:
        Restraints (:mod:`murus.rocking.restraints`; EURODYN (2020), eqs. 2-7).
    motion_sides:
        ``"two"``: the wall rocks freely both ways; ``"one"``: inward rotations push against the
        transverse walls (EURODYN (2020) "one-sided motion"), which must then be given.
    pivot:
        A :class:`Pivot` law (Mordant et al. (SERIES), §3.3.1); default Housner's corner.
    restraints:
        Further restraints, the extension point of the rocking moment: objects with
        ``fill(P, body)`` (write their parameters by name into the kernel record ``P``),
        ``describe()`` (a dict) and optionally ``check(body)`` (raise on an invalid
        placement). A new term of the moment touches two places: its parameter rows in
        :data:`murus.rocking.kernels.PARAMS` with its moment in
        :func:`murus.rocking.kernels.restraint_terms`, and its class (here, or in
        :mod:`murus.rocking.restraints` beside :class:`Tie`); the model takes it as it is.
    """

    body: RigidBlock
    restitution: RestitutionLaw = field(default_factory=Housner)
    linearised: bool = False
    gravity: float = G
    rest_tol: float = 1e-3
    tie: Tie | None = None
    transverse_walls: SpringBed | None = None
    damper: Damper | None = None
    motion_sides: str = "two"
    pivot: Pivot = field(default_factory=Pivot)
    restraints: tuple = ()

    def __post_init__(self) -> None:
        if not isinstance(self.body, RigidBlock):
            raise ModelError("body must be a RigidBlock")
        object.__setattr__(self, "restitution", make_restitution(self.restitution))
        if not (math.isfinite(self.gravity) and self.gravity > 0.0):
            raise ModelError(f"gravity must be positive, got {self.gravity!r}")
        if not (math.isfinite(self.rest_tol) and 0.0 <= self.rest_tol < 1.0):
            raise ModelError(f"rest_tol must be in [0, 1), got {self.rest_tol!r}")
        self._check_restraints()

    def _check_restraints(self) -> None:
        b = self.body
        hb = 0.5 * b.width
        for item, kind in ((self.tie, Tie), (self.damper, Damper)):
            if item is None:
                continue
            if not isinstance(item, kind):
                raise ModelError(f"{kind.KIND} must be a {kind.__name__}")
            if item.height > b.height * (1 + 1e-12):
                raise ModelError(f"{kind.KIND} height {item.height:g} m is above the wall "
                                 f"(height {b.height:g} m)", key=(kind.KIND,))
            if abs(item.x) > hb * (1 + 1e-12):
                raise ModelError(f"{kind.KIND} x = {item.x:g} m is outside the wall "
                                 f"(|x| <= {hb:g} m)", key=(kind.KIND,))
        bed = self.transverse_walls
        if bed is not None:
            if not isinstance(bed, SpringBed):
                raise ModelError("transverse_walls must be a SpringBed")
            if bed.z1 + bed.effective_height > b.height * (1 + 1e-12):
                raise ModelError(
                    f"transverse walls reach {bed.z1 + bed.effective_height:g} m, above the "
                    f"wall (height {b.height:g} m)", key=("transverse_walls",))
            if bed.x is not None and abs(bed.x) > hb * (1 + 1e-12):
                raise ModelError(f"transverse_walls x = {bed.x:g} m is outside the wall",
                                 key=("transverse_walls",))
        if self.motion_sides not in ("one", "two"):
            raise ModelError(f"motion_sides must be 'one' or 'two', got {self.motion_sides!r}")
        if self.motion_sides == "one" and bed is None:
            raise ModelError("a one-sided wall needs transverse walls (the spring bed that stops "
                             "inward rotations)", key=("motion_sides",))
        if self.motion_sides == "two" and bed is not None:
            raise ModelError("transverse walls make the motion one-sided: set "
                             "motion_sides = 'one'", key=("transverse_walls",))
        if not isinstance(self.pivot, Pivot):
            raise ModelError("pivot must be a Pivot")
        object.__setattr__(self, "restraints", tuple(self.restraints))
        for i, r in enumerate(self.restraints):
            if not (callable(getattr(r, "fill", None)) and callable(getattr(r, "describe", None))):
                raise ModelError(f"restraints[{i}]: a restraint needs fill(P, body) and "
                                 f"describe(), got {type(r).__name__}", key=("restraints", i))
            if callable(getattr(r, "check", None)):
                r.check(b)

    @property
    def restrained(self) -> bool:
        return bool(self.restraints) or any(
            x is not None for x in (self.tie, self.transverse_walls, self.damper))

    @property
    def rigid_walls(self) -> bool:
        """Transverse walls of infinite stiffness: the wall bounces at theta = 0."""
        return self.transverse_walls is not None and math.isinf(self.transverse_walls.stiffness)

    @property
    def e(self) -> float:
        """The coefficient of restitution of the constant-valued laws [-]."""
        return self.restitution.value(self.body)

    @property
    def p(self) -> float:
        b = self.body
        return math.sqrt(b.mass * self.gravity * b.R / b.I_O)

    def params(self) -> np.void:
        """The parameter record ``P`` read by the kernels (:data:`murus.rocking.kernels.PARAMS`,
        fields set by name). A fresh copy on every call (the engine may change it during a
        run); the model is frozen, so the record is built once."""
        flat = self.__dict__.get("_params")
        if flat is None:
            rec = self._build_params()
            flat = np.frombuffer(rec.tobytes(), np.float64)  # the record's 40 slots
            object.__setattr__(self, "_params", flat)
        # a copy of the slots viewed as a record (copying a record itself costs 16 us)
        return flat.copy().view(K.PARAM_DTYPE)[0]

    def _build_params(self) -> np.void:
        b = self.body
        P = {}  # filled by name, then one record (a record set field by field costs 10 us more)
        P["i_o"] = b.I_O
        P["m"] = b.mass
        P["r"] = b.R
        P["alpha"] = b.alpha
        P["g"] = self.gravity
        P["linear"] = 1.0 if self.linearised else 0.0
        P["rest_tol"] = self.rest_tol
        P["ig"] = b.I_O - b.mass * b.R**2
        P["zg"] = b.z_G
        P["hb"] = 0.5 * b.width
        self.pivot.fill(P, b)
        P["e_aspect"] = 1.0
        self.restitution.fill(P, b, self.pivot.code != 0)
        P["terms"] = 1.0 if self.restrained else 0.0
        for r in (self.tie, self.transverse_walls, self.damper, *self.restraints):
            if r is not None:
                r.fill(P, b)
        return K.params_record(P)

    def replace(self, **changes) -> RockingModel:
        """A copy with some fields changed (validated again)."""
        from dataclasses import replace

        return replace(self, **changes)

    def describe(self) -> dict:
        law = {"law": self.restitution.name, "e": self.e}
        if hasattr(self.restitution, "describe"):
            law.update(self.restitution.describe())
        return {
            "body": self.body.describe(),
            "restitution": law,
            "linearised": self.linearised,
            "gravity": self.gravity,
            "rest_tol": self.rest_tol,
            "pivot": self.pivot.describe(),
            "motion_sides": self.motion_sides,
            "tie": None if self.tie is None else self.tie.describe(),
            "transverse_walls": (None if self.transverse_walls is None
                                 else self.transverse_walls.describe()),
            "damper": None if self.damper is None else self.damper.describe(),
            # only when given: the description keys the study caches
            **({"restraints": [r.describe() for r in self.restraints]} if self.restraints
               else {}),
        }


def as_model(model_or_body, restitution=None, linearised: bool | None = None) -> RockingModel:
    """A :class:`RockingModel` from a model or a body (with optional overrides)."""
    if isinstance(model_or_body, RockingModel):
        m = model_or_body
        if restitution is not None:
            m = m.replace(restitution=restitution)
        if linearised is not None:
            m = m.replace(linearised=linearised)
        return m
    if isinstance(model_or_body, RigidBlock):
        return RockingModel(
            model_or_body,
            restitution if restitution is not None else Housner(),
            bool(linearised),
        )
    raise ModelError(f"expected a RockingModel or a RigidBlock, got {type(model_or_body).__name__}")

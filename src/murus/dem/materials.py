"""Joint materials of the distinct-element engine (UDEC "Coulomb slip" joint, Savalle et al. (2022),
eqs. 3-4).

Stiffnesses are per unit area of the joint [Pa/m]; a sub-contact of tributary length L in a model
of thickness t has the spring ``kn L t`` [N/m]. Strengths are stresses [Pa]; a sub-contact that
fails in tension or shear keeps the residual values (default 0: a dry joint) from then on.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from murus.dem import kernels as K
from murus.errors import MurusError

__all__ = ["Joint", "JointError"]


class JointError(MurusError, ValueError):
    """Invalid joint parameters."""


@dataclass(frozen=True)
class Joint:
    """Mohr-Coulomb joint (elastic-perfectly plastic in shear, brittle in tension).

    Parameters
    ----------
    kn, ks : normal and shear stiffness per unit area [Pa/m];
    friction_deg : friction angle [deg], 0 <= phi < 90;
    cohesion, tension : initial cohesion c and tensile strength T [Pa];
    cohesion_res, tension_res : residual values after failure [Pa] (default 0);
    rolling : rolling-friction coefficient mu_r [-] of disc contacts (limit mu_r r_eff Fn).
    contact_damping : critical-damping ratio zeta [-] of a normal dashpot per sub-contact,
        0 <= zeta <= 1 (default 0: none). The dashpot ``c = 2 zeta sqrt(kn A m_eff)``
        (``m_eff`` the reduced mass of the two bodies, a kinematic body counting as infinitely
        heavy) acts only while the surfaces overlap and approach (an impact), never in
        separation, and never pulls; its dissipation is the energy term ``contact_damping``.
        :func:`murus.dem.rocking_damping.calibrate` gives the zeta of a target rocking
        restitution (docs/guide/dem_rocking.md).
    """

    kn: float = 1.0e10
    ks: float = 4.0e9
    friction_deg: float = 30.0
    cohesion: float = 0.0
    tension: float = 0.0
    cohesion_res: float = 0.0
    tension_res: float = 0.0
    rolling: float = 0.0
    contact_damping: float = 0.0

    def __post_init__(self) -> None:
        for name in ("kn", "ks"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v > 0):
                raise JointError(f"Joint: {name} must be a positive finite stiffness [Pa/m], "
                                 f"got {v!r}")
        if not (0.0 <= self.friction_deg < 90.0):
            raise JointError(f"Joint: friction_deg must be in [0, 90), got {self.friction_deg!r}")
        for name in ("cohesion", "tension", "cohesion_res", "tension_res", "rolling"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v >= 0):
                raise JointError(f"Joint: {name} must be >= 0, got {v!r}")
        z = self.contact_damping
        if not (math.isfinite(z) and 0.0 <= z <= 1.0):
            raise JointError("Joint: contact_damping (critical-damping ratio of the normal "
                             f"dashpot) must be in [0, 1], got {z!r}")

    def row(self) -> np.ndarray:
        """The property row of the kernels (``J_*`` columns)."""
        r = np.zeros(K.NJ)
        r[K.J_KN] = self.kn
        r[K.J_KS] = self.ks
        r[K.J_TANPHI] = math.tan(math.radians(self.friction_deg))
        r[K.J_C] = self.cohesion
        r[K.J_T] = self.tension
        r[K.J_CRES] = self.cohesion_res
        r[K.J_TRES] = self.tension_res
        r[K.J_MUROLL] = self.rolling
        r[K.J_CDAMP] = self.contact_damping
        return r

    @classmethod
    def from_row(cls, r) -> Joint:
        return cls(kn=float(r[K.J_KN]), ks=float(r[K.J_KS]),
                   friction_deg=math.degrees(math.atan(float(r[K.J_TANPHI]))),
                   cohesion=float(r[K.J_C]), tension=float(r[K.J_T]),
                   cohesion_res=float(r[K.J_CRES]), tension_res=float(r[K.J_TRES]),
                   rolling=float(r[K.J_MUROLL]),
                   contact_damping=float(r[K.J_CDAMP]) if len(r) > K.J_CDAMP else 0.0)

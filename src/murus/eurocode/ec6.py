"""EN 1996-1-1 (Eurocode 6): the compressed (contact) length of a wall section under an axial
force and an in-plane moment, as used by Mordant et al. (SERIES), §2.2.1 to assess the walls of its
shaking-table tests. Lengths in m, forces in N, moments in N m.

Two stress distributions over a no-tension section of length ``L`` with eccentricity
``e = |M| / N`` (Mordant et al. (SERIES), §2.2.1, formulas (2,a) and (2,b), lost in the text
extraction and reconstructed here from the standard):

- constant stress block (the effective width behind the capacity reduction factor
  ``Phi = 1 - 2 e / t`` of EN 1996-1-1 §6.1.2.2): ``Lc = L - 2 e`` for ``e < L/2``, else 0;
- linear distribution, no tension (the compressed length ``l_c`` of the shear check of
  EN 1996-1-1 §6.2, "ignoring any part of the wall that is in tension"): the whole section is
  compressed while ``e <= L/6`` (the kern), else the triangle of resultant at ``e`` gives
  ``Lc = 3 (L/2 - e)``, and 0 for ``e >= L/2``.

The resultant leaves the section at ``e = L/2`` (overturning in static terms, rocking in dynamic
terms, Mordant et al. (SERIES), §2.2.2).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from murus import G
from murus.errors import MurusError

DISTRIBUTIONS = ("linear", "constant")


class EC6Error(MurusError, ValueError):
    """Invalid input to a Eurocode 6 check."""


def eccentricity(N, M):
    """Eccentricity ``e = |M| / N`` [m] of the resultant; ``N > 0`` is compression [N]."""
    N = np.asarray(N, dtype=float)
    if np.any(~np.isfinite(N)) or np.any(N <= 0.0):
        raise EC6Error("the axial force N must be a positive compression (N)")
    M = np.asarray(M, dtype=float)
    if np.any(~np.isfinite(M)):
        raise EC6Error("the moment M must be finite (N m)")
    e = np.abs(M) / N
    return float(e) if e.ndim == 0 else e


def compressive_length(N, M, L, distribution: str = "linear"):
    """Compressed length ``Lc`` [m] of a section of length ``L`` [m] under ``N`` [N] and ``M``
    [N m] (see the module docstring for the two distributions). Vectorised over N and M."""
    if not (isinstance(L, int | float) and math.isfinite(L) and L > 0.0):
        raise EC6Error(f"the section length L must be positive, got {L!r}")
    if distribution not in DISTRIBUTIONS:
        raise EC6Error(f"unknown distribution {distribution!r}; expected one of {DISTRIBUTIONS}")
    e = np.asarray(eccentricity(N, M), dtype=float)
    if distribution == "constant":
        lc = np.clip(L - 2.0 * e, 0.0, L)
    else:
        lc = np.where(e <= L / 6.0, L, np.clip(3.0 * (0.5 * L - e), 0.0, L))
    return float(lc) if lc.ndim == 0 else lc


def kern_limit(L: float) -> float:
    """Largest eccentricity with the whole section compressed (linear distribution): L/6 [m]."""
    return L / 6.0


@dataclass(frozen=True)
class EquivalentStatic:
    """The equivalent static load case of Mordant et al. (SERIES), Table 2: a mass ``m`` [kg] on top
    of a wall at height ``H`` [m], loaded horizontally by ``factor * a * m g`` (factor 2.5, the
    plateau of the EN 1998-1 spectrum) for an acceleration level ``a`` [g]."""

    mass: float = 5000.0
    height: float = 1.80
    factor: float = 2.5

    def forces(self, level_g):
        a = np.asarray(level_g, dtype=float)
        N = self.mass * G * np.ones_like(a)
        M = self.factor * a * self.mass * G * self.height
        return N, M

    def compressive_length(self, L: float, level_g, distribution: str = "linear"):
        N, M = self.forces(level_g)
        return compressive_length(N, M, L, distribution)

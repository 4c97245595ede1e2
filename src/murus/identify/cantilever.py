"""A cantilever model of a wall for the low-amplitude regime (issue 8, item 5).

Before it rocks, a wall of Mordant et al. (SERIES) vibrates as a cantilever clamped at the table
with the 5 t mass on top (its white-noise tests, Mordant et al. (SERIES), §2.1 and Figure 3). This
module models it as a Timoshenko beam (bending and shear deformation, rotary inertia of the section)
with a tip mass and a tip rotary inertia, discretised by finite elements, and gives

- its natural frequencies and modes (:meth:`Cantilever.modes`), to compare with the
  frequencies identified from white-noise tests (:mod:`murus.identify`);
- its response to a base acceleration by modal superposition with a damping ratio per mode
  (:meth:`Cantilever.response`), each modal equation integrated exactly for a piecewise-linear
  input (Nigam & Jennings 1969, the kernel of the response spectra of :mod:`murus.motion`);
- the Young's modulus that makes the first frequency equal to a measured one
  (:meth:`Cantilever.fit_modulus`), the usual way of reading a frequency drop along a test
  sequence as a loss of stiffness.

Element: two nodes, deflection and section rotation at each, with the interdependent
interpolation of Friedman & Kosmatka (1993) (the static solution of the element, so no shear
locking): its stiffness is the exact one of a Timoshenko beam element, with Phi = 12 E I /
(kappa G A l^2), and its mass matrix the consistent one of the same functions (translation and
rotary inertia rho I of the section), built by exact quadrature. The stiffness being exact,
the static tip flexibility H^3/(3 E I) + H/(kappa G A) is reproduced with any number of
elements; the frequencies converge from above as the mesh is refined, as h^2 for the
Timoshenko beam and h^4 in the Euler-Bernoulli limit (measured against the exact solution of
the Timoshenko equations with tip mass and inertia in ``tests/identify/test_cantilever.py``:
with the default 40 elements the first two frequencies of the Mordant et al. (SERIES) walls are
within 0.05 %).

Conventions and units: in-plane bending of a wall of length ``length`` (the bending depth) and
thickness ``thickness``, height ``height`` [m]; A = length x thickness, I = thickness length^3/12;
E, G [Pa], density [kg/m3]; tip mass [kg] at the top node, tip rotary inertia [kg m2] about the
out-of-plane axis through the top node. Displacements relative to the base [m], accelerations
[m/s2], frequencies [Hz]. Default G = 0.4 E (EN 1996-1-1 §3.7.3) and kappa = 5/6 (rectangle).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from murus.errors import MurusError

__all__ = ["Cantilever", "CantileverError", "CantileverModes", "CantileverResponse",
           "equivalent_moduli"]


class CantileverError(MurusError, ValueError):
    """A parameter of the cantilever model is out of range."""


@dataclass(frozen=True)
class CantileverModes:
    """Natural modes: ``frequency`` [Hz], ``shape`` (n_nodes x n_modes deflections along the
    height, normalised to 1 at the top), ``participation`` (Gamma_n = L_n / m_n for a unit
    base acceleration, with the normalised shapes), ``effective_mass`` L_n^2 / m_n [kg] (over
    all modes they sum to the total mass less the small part of the first element that the
    consistent mass attaches to the support, which vanishes as the mesh is refined), node
    heights ``z`` [m]."""

    frequency: np.ndarray
    shape: np.ndarray
    participation: np.ndarray
    effective_mass: np.ndarray
    z: np.ndarray
    vectors: np.ndarray = field(repr=False)  # all DOFs (w1, th1, ...), unit top deflection

    @property
    def period(self) -> np.ndarray:
        return 1.0 / self.frequency


@dataclass(frozen=True)
class CantileverResponse:
    """Response to a base acceleration: times ``t`` [s]; ``top_displacement`` relative to the
    base [m]; ``top_acceleration`` absolute [m/s2]; ``base_shear`` [N] and ``base_moment``
    [N m] about the base: the force and moment the base applies to the wall, i.e. the sum of
    mass x absolute acceleration (and of its moment), positive with the acceleration; the
    modes used."""

    t: np.ndarray
    top_displacement: np.ndarray
    top_acceleration: np.ndarray
    base_shear: np.ndarray
    base_moment: np.ndarray
    modes: CantileverModes = field(repr=False)


def _element(h: float, EI: float, g: float, rhoA: float, rhoI: float):
    """Stiffness and consistent mass of a Timoshenko element of length h (DOFs w1, psi1, w2,
    psi2; psi the rotation of the section) with the interdependent interpolation of Friedman &
    Kosmatka (1993): the shape functions are the static solution of the element without
    distributed load, w = a0 + a1 x + a2 x^2 + a3 x^3 and psi = a1 + 6 g a3 + 2 a2 x + 3 a3 x^2
    with g = E I / (kappa G A) (from V' = 0 and kappa G A (w' - psi) = -E I psi''). Hence the
    stiffness is exact (Phi = 12 g / h^2) and no shear locking; the mass integrates rho A w^2 +
    rho I psi^2 exactly (4-point Gauss, degree 6). g = 0 gives the Euler-Bernoulli element with
    the cubic Hermite functions."""
    # nodal values (w(0), psi(0), w(h), psi(h)) in terms of (a0, a1, a2, a3)
    C = np.array([[1.0, 0.0, 0.0, 0.0],
                  [0.0, 1.0, 0.0, 6.0 * g],
                  [1.0, h, h * h, h**3],
                  [0.0, 1.0, 2.0 * h, 3.0 * h * h + 6.0 * g]])
    Ci = np.linalg.inv(C)  # a = Ci d
    xg, wg = np.polynomial.legendre.leggauss(4)
    x = 0.5 * h * (xg + 1.0)
    wq = 0.5 * h * wg
    one, zero = np.ones_like(x), np.zeros_like(x)
    Nw = np.stack([one, x, x * x, x**3]) .T @ Ci          # (nq, 4)
    Npsi = np.stack([zero, one, 2 * x, 3 * x * x + 6 * g]).T @ Ci
    dNw = np.stack([zero, one, 2 * x, 3 * x * x]).T @ Ci
    dNpsi = np.stack([zero, zero, 2 * one, 6 * x]).T @ Ci
    gam = dNw - Npsi  # shear strain per DOF
    k = EI * np.einsum("q,qi,qj->ij", wq, dNpsi, dNpsi)
    if g > 0:
        k += EI / g * np.einsum("q,qi,qj->ij", wq, gam, gam)
    m = rhoA * np.einsum("q,qi,qj->ij", wq, Nw, Nw) + rhoI * np.einsum("q,qi,qj->ij", wq, Npsi,
                                                                       Npsi)
    return k, m


def _positive(name: str, value: float, allow_zero: bool = False) -> float:
    v = float(value)
    if not math.isfinite(v) or v < 0 or (v == 0 and not allow_zero):
        need = ">= 0" if allow_zero else "> 0"
        raise CantileverError(f"{name} must be a finite number {need}, got {value!r}")
    return v


@dataclass(frozen=True)
class Cantilever:
    """Timoshenko cantilever with a tip mass (see the module docstring for the conventions).

    Parameters
    ----------
    height : float
        Height of the wall, the length of the cantilever [m].
    length : float
        In-plane length of the wall, the bending depth [m].
    thickness : float
        Thickness of the wall [m].
    modulus : float
        Young's modulus E [Pa].
    density : float
        Density of the wall [kg/m³] (>= 0; 0 needs a ``tip_mass``).
    shear_modulus : float, optional
        Shear modulus G [Pa]; default 0.4 E (EN 1996-1-1, §3.7.3).
    tip_mass : float
        Mass on the top node [kg].
    tip_inertia : float
        Rotary inertia of the tip mass about the out-of-plane axis through the top node
        [kg m²].
    kappa : float
        Shear coefficient [-]; 5/6 for a rectangle.
    elements : int
        Number of finite elements along the height.
    shear : bool
        ``False`` gives the Euler-Bernoulli beam (no shear deformation).
    rotary_inertia : bool
        ``False`` drops the rotary inertia rho I of the section.

    Raises
    ------
    CantileverError
        If a dimension, the modulus or ``kappa`` is not a finite positive number, the density
        or a tip quantity is negative, ``elements`` is not a whole number >= 1, or the
        cantilever has no mass.

    References
    ----------
    Friedman & Kosmatka (1993) (the element); EN 1996-1-1 (2005), §3.7.3 (G = 0.4 E);
    Nigam & Jennings (1969) (the modal response).
    """

    height: float
    length: float
    thickness: float
    modulus: float
    density: float
    shear_modulus: float | None = None
    tip_mass: float = 0.0
    tip_inertia: float = 0.0
    kappa: float = 5.0 / 6.0
    elements: int = 40
    shear: bool = True
    rotary_inertia: bool = True

    def __post_init__(self) -> None:
        for name in ("height", "length", "thickness", "modulus", "kappa"):
            _positive(name, getattr(self, name))
        _positive("density", self.density, allow_zero=True)
        _positive("tip_mass", self.tip_mass, allow_zero=True)
        _positive("tip_inertia", self.tip_inertia, allow_zero=True)
        if self.shear_modulus is not None:
            _positive("shear_modulus", self.shear_modulus)
        if int(self.elements) != self.elements or self.elements < 1:
            raise CantileverError(f"elements must be a whole number >= 1, got {self.elements!r}")
        if self.density == 0 and self.tip_mass == 0:
            raise CantileverError("a cantilever needs mass: density > 0 or tip_mass > 0")

    # ------------------------------------------------------------------ section properties
    @property
    def area(self) -> float:
        return self.length * self.thickness

    @property
    def inertia(self) -> float:
        """Second moment of area I = t L^3 / 12 [m4] (in-plane bending)."""
        return self.thickness * self.length**3 / 12.0

    @property
    def G(self) -> float:
        return 0.4 * self.modulus if self.shear_modulus is None else self.shear_modulus

    @property
    def total_mass(self) -> float:
        return self.density * self.area * self.height + self.tip_mass

    def tip_flexibility(self) -> float:
        """Static top deflection under a unit top force [m/N]: H^3/(3 E I) + H/(kappa G A)."""
        f = self.height**3 / (3.0 * self.modulus * self.inertia)
        if self.shear:
            f += self.height / (self.kappa * self.G * self.area)
        return f

    # ------------------------------------------------------------------ matrices
    def full_matrices(self) -> tuple[np.ndarray, np.ndarray]:
        """Stiffness and mass matrices over all DOFs (w0, th0, w1, th1, ..., wn, thn) [N/m,
        kg, ...]; node 0 is the base; the tip mass and inertia are on the last node."""
        n = int(self.elements)
        h = self.height / n
        EI = self.modulus * self.inertia
        g = EI / (self.kappa * self.G * self.area) if self.shear else 0.0
        ke, me = _element(h, EI, g, self.density * self.area,
                          self.density * self.inertia if self.rotary_inertia else 0.0)
        ndof = 2 * (n + 1)
        K = np.zeros((ndof, ndof))
        M = np.zeros((ndof, ndof))
        for e in range(n):
            s = slice(2 * e, 2 * e + 4)
            K[s, s] += ke
            M[s, s] += me
        M[-2, -2] += self.tip_mass
        M[-1, -1] += self.tip_inertia
        return K, M

    def matrices(self) -> tuple[np.ndarray, np.ndarray]:
        """Stiffness and mass matrices of the free DOFs (w1, th1, ..., wn, thn): the base node
        is clamped."""
        K, M = self.full_matrices()
        return K[2:, 2:], M[2:, 2:]

    def _loads(self, M: np.ndarray) -> tuple[np.ndarray, np.ndarray, float, float]:
        """Effective earthquake loads on the free DOFs for a unit base acceleration: the
        inertia of the rigid translation, p = M_ff r + M_f0 e_w0 (the consistent mass couples
        the first free node to the base), and the same rows weighted for the moment about the
        base, p_M = (h^T M)_f with h = z on deflections and 1 on rotations (couples); plus the
        total mass and the total moment of the rigid translation, h^T M r."""
        nd = M.shape[0]
        r = np.zeros(nd)
        r[0::2] = 1.0
        z = np.linspace(0.0, self.height, int(self.elements) + 1)
        hv = np.ones(nd)
        hv[0::2] = z
        return (M @ r)[2:], (hv @ M)[2:], float(r @ M @ r), float(hv @ M @ r)

    # ------------------------------------------------------------------ modes
    def modes(self, n_modes: int | None = None) -> CantileverModes:
        """The natural modes, lowest first (all of them by default)."""
        from scipy.linalg import eigh

        K, M = self.matrices()
        nd = K.shape[0]
        # a DOF without mass (rotations when density = 0 and no tip inertia) is condensed out
        keep = np.diag(M) > 0
        if not keep.all():
            a, b = np.nonzero(keep)[0], np.nonzero(~keep)[0]
            T = np.zeros((nd, a.size))
            T[a, np.arange(a.size)] = 1.0
            T[b] = -np.linalg.solve(K[np.ix_(b, b)], K[np.ix_(b, a)])
        else:
            T = np.eye(nd)
        Kr, Mr = T.T @ K @ T, T.T @ M @ T
        n_max = Kr.shape[0]
        n_modes = n_max if n_modes is None else n_modes
        if not 1 <= n_modes <= n_max:
            raise CantileverError(f"n_modes must be between 1 and {n_max}, got {n_modes}")
        lam, vec = eigh(Kr, Mr, subset_by_index=[0, n_modes - 1])
        phi = T @ vec
        phi = phi / phi[-2]  # unit deflection at the top
        p, _, _, _ = self._loads(self.full_matrices()[1])
        mn = np.einsum("in,ij,jn->n", phi, M, phi)
        ln = phi.T @ p
        z = np.linspace(0.0, self.height, int(self.elements) + 1)
        shape = np.vstack([np.zeros(n_modes), phi[0::2]])
        return CantileverModes(frequency=np.sqrt(np.maximum(lam, 0.0)) / (2 * math.pi),
                               shape=shape, participation=ln / mn, effective_mass=ln**2 / mn,
                               z=z, vectors=phi)

    def frequencies(self, n_modes: int = 3) -> np.ndarray:
        """The lowest ``n_modes`` natural frequencies [Hz]."""
        return self.modes(n_modes).frequency

    # ------------------------------------------------------------------ response
    def response(self, motion, damping: float | list[float] = 0.02,
                 n_modes: int | None = None) -> CantileverResponse:
        """Response to the base acceleration of ``motion`` (a :class:`murus.motion.GroundMotion`
        or a pair ``(acc [m/s2], dt [s])``) by modal superposition: each mode's equation
        q'' + 2 xi w q' + w^2 q = -Gamma a_g integrated exactly for a piecewise-linear input.
        ``damping``: one ratio for every mode or one per mode; ``n_modes``: modes kept (all by
        default, so that the base shear sums the whole mass).

        The absolute acceleration of mode n is A_n = -(2 xi w q' + w^2 q) (its equation); the
        base shear is sum_n L_n A_n plus the mass the kept modes do not carry times a_g, and
        the base moment likewise with the moment loads (rotations add their inertia couples).
        """
        from murus.motion._kernels import sdof_history

        if isinstance(motion, tuple):
            acc, dt = np.asarray(motion[0], dtype=float), float(motion[1])
        else:
            acc, dt = np.asarray(motion.acc, dtype=float), float(motion.dt)
        if acc.ndim != 1 or acc.size < 2 or not np.isfinite(acc).all():
            raise CantileverError("the base acceleration must be a finite 1-D series")
        _positive("dt", dt)
        md = self.modes(n_modes)
        nm = md.frequency.size
        xi = np.full(nm, float(damping)) if np.ndim(damping) == 0 \
            else np.asarray(damping, dtype=float)
        if xi.shape != (nm,):
            raise CantileverError(f"damping: one ratio or {nm} (one per mode), got {xi.size}")
        if ((xi < 0) | (xi >= 1)).any():
            raise CantileverError("damping ratios must lie in [0, 1)")
        w = 2 * math.pi * md.frequency
        q = np.empty((nm, acc.size))
        qd = np.empty_like(q)
        for k in range(nm):
            u, v = sdof_history(acc, dt, float(w[k]), float(xi[k]))
            q[k] = md.participation[k] * u
            qd[k] = md.participation[k] * v
        A = -(2 * xi[:, None] * w[:, None] * qd + w[:, None] ** 2 * q)
        p, pm, mass, moment = self._loads(self.full_matrices()[1])
        ln, lm = md.vectors.T @ p, md.vectors.T @ pm
        # the mass the kept modes do not carry moves with the base (residual-mass correction;
        # with all modes it is the part of the first element attached to the support)
        shear = ln @ A + (mass - ln @ md.participation) * acc
        moment_ = lm @ A + (moment - lm @ md.participation) * acc
        return CantileverResponse(t=np.arange(acc.size) * dt,
                                  top_displacement=md.shape[-1] @ q,
                                  top_acceleration=md.shape[-1] @ A,
                                  base_shear=shear, base_moment=moment_, modes=md)

    # ------------------------------------------------------------------ calibration
    def fit_modulus(self, frequency_hz: float, mode: int = 1) -> float:
        """Young's modulus E [Pa] that gives the measured natural frequency of ``mode`` (1 =
        first), with G = 0.4 E kept proportional (or the given G scaled with E). Frequencies
        scale as sqrt(E) when G/E is fixed, so the answer is exact in one step."""
        f_meas = _positive("frequency_hz", frequency_hz)
        f0 = self.frequencies(mode)[mode - 1]
        return self.modulus * (f_meas / f0) ** 2


def equivalent_moduli(cantilever: Cantilever, frequencies_hz) -> np.ndarray:
    """Young's modulus [Pa] that makes the first frequency of ``cantilever`` equal to each
    identified frequency (NaN where the frequency is not finite): the reading of a frequency
    drop along a test sequence as a loss of stiffness, E_eff / E_0 = (f / f_0)^2 (G/E fixed).
    """
    f = np.asarray(frequencies_hz, dtype=float)
    f0 = cantilever.frequencies(1)[0]
    return np.where(np.isfinite(f) & (f > 0), cantilever.modulus * (f / f0) ** 2, np.nan)

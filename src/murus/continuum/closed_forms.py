"""Closed forms for the verification of the continuum zones (issue 17 item 7).

Each function is the exact (or classical) solution of one verification problem; ``murus verify
continuum`` compares the zones with them. Units are SI (m, s, Pa, N/m, N/m³); angles are in
radians (the case files take ``*_deg``); stresses of the hole problem are **compression
positive**, as in Salençon (1969) and Itasca's verification problem; displacements are positive
outwards (along +r) or upwards.

Problems and sources:

- elastic layer on a rigid base (1D shear column): natural frequencies, and the transfer function
  ``|u_top / u_base|`` for hysteretic damping (Kramer 1996, ch. 7) and for mass-proportional
  (Rayleigh) damping, both exact solutions of the damped 1D wave equation derived here, with the
  modal superposition they must equal (:func:`layer_transfer_modal`);
- Lysmer-Kuhlemeyer quiet boundary: reflection of a plane P or SV wave on a viscous boundary at
  any incidence (Lysmer & Kuhlemeyer 1969), exact plane-wave solution derived here; with no
  dashpot it is the free-surface reflection of Aki & Richards (2002), §5.2;
- cylindrical hole in a Mohr-Coulomb medium, plane strain, hydrostatic far field (Salençon 1969;
  the Itasca verification problem "Cylindrical hole in an infinite Mohr-Coulomb medium"):
  plastic radius, stresses, radial displacement with a non-associated dilation;
- Prandtl's strip footing on a weightless soil (Prandtl 1920; Reissner 1924): bearing capacity
  factors;
- oedometric modulus and settlement of a layer;
- active thrusts on a vertical wall with a level backfill: Rankine, Coulomb, Mononobe-Okabe, as
  thin wrappers of :mod:`murus.eurocode.ec8_5` (no second copy of those formulas).

Every function checks its input and raises :class:`ClosedFormError` (a ``ValueError``) with a
one-line message on a value outside its validity limits.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from murus.errors import MurusError
from murus.eurocode import ec8_5

__all__ = [
    "ClosedFormError",
    "layer_frequency", "layer_transfer_hysteretic", "layer_transfer_rayleigh",
    "layer_transfer_modal", "mass_damping_alpha", "mass_damping_ratio",
    "QuietReflection", "quiet_boundary_reflection",
    "hole_plastic_radius", "hole_stresses", "hole_displacement",
    "bearing_capacity_factors", "strip_footing_capacity",
    "oedometric_modulus", "oedometric_settlement",
    "rankine_thrust", "active_thrust",
]


class ClosedFormError(MurusError, ValueError):
    """An input outside the validity limits of a closed form (one-line message)."""


def _pos(name: str, value, allow_zero: bool = False) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ClosedFormError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(v) or v < 0 or (v == 0 and not allow_zero):
        limit = ">= 0" if allow_zero else "> 0"
        raise ClosedFormError(f"{name} must be finite and {limit}, got {value!r}")
    return v


def _freqs(f) -> np.ndarray:
    a = np.asarray(f, dtype=np.float64)
    if not np.all(np.isfinite(a)) or np.any(a < 0):
        raise ClosedFormError("frequencies must be finite and >= 0 Hz")
    return a


# ----------------------------------------------------------------------------- 1D layer


def layer_frequency(vs: float, H: float, n=1):
    """Natural frequencies of an elastic layer on a rigid base, ``f_n = (2n - 1) Vs / (4 H)``.

    Parameters
    ----------
    vs : float
        Shear-wave velocity of the layer [m/s].
    H : float
        Thickness of the layer [m].
    n : int or array of int
        Mode number(s), 1 for the fundamental.

    Returns
    -------
    float or numpy.ndarray
        f_n [Hz].

    References
    ----------
    Kramer, S. L. (1996). Geotechnical Earthquake Engineering, Prentice Hall, §7.2.1 (uniform
    undamped soil on rigid rock).
    """
    vs, H = _pos("vs", vs), _pos("H", H)
    k = np.asarray(n)
    if k.dtype.kind not in "iu" or np.any(k < 1):
        raise ClosedFormError(f"mode numbers must be integers >= 1, got {n!r}")
    f = (2.0 * k - 1.0) * vs / (4.0 * H)
    return float(f) if f.ndim == 0 else f


def layer_transfer_hysteretic(f, vs: float, H: float, xi: float, complex_output: bool = False):
    """Transfer function ``u_top / u_base`` of a layer with hysteretic damping on a rigid base.

    ``F(w) = 1 / cos(k* H)`` with the complex wavenumber ``k* = w / Vs*`` and the complex
    shear-wave velocity ``Vs* = Vs sqrt(1 + 2 i xi)`` (complex modulus ``G* = G (1 + 2 i xi)``).
    Kramer's text approximates ``Vs* ~ Vs (1 + i xi)`` for small ``xi``; the exact square root is
    used here (the two differ by O(xi²)). Its peaks are at ``f_n`` (:func:`layer_frequency`)
    within O(xi²), with ``|F(f_n)| ~ 2 / ((2n - 1) pi xi)``.

    Parameters
    ----------
    f : float or array
        Frequencies [Hz], >= 0.
    vs : float
        Shear-wave velocity [m/s].
    H : float
        Layer thickness [m].
    xi : float
        Hysteretic damping ratio [-], >= 0.
    complex_output : bool
        Return the complex ratio (time factor ``exp(i w t)``) instead of its modulus.

    Returns
    -------
    numpy.ndarray or float
        ``|u_top / u_base|`` [-] (or the complex ratio).

    References
    ----------
    Kramer, S. L. (1996). Geotechnical Earthquake Engineering, Prentice Hall, §7.2.1 (uniform
    damped soil on rigid rock).
    """
    fa = _freqs(f)
    vs, H, xi = _pos("vs", vs), _pos("H", H), _pos("xi", xi, allow_zero=True)
    k = 2.0 * np.pi * fa / (vs * np.sqrt(1.0 + 2.0j * xi))
    out = 1.0 / np.cos(k * H)
    out = out if complex_output else np.abs(out)
    return out[()] if out.ndim == 0 else out


def mass_damping_alpha(xi: float, f: float) -> float:
    """Mass-proportional Rayleigh coefficient ``alpha = 4 pi f xi`` [1/s] giving ``xi`` at ``f``.

    With a damping force per unit mass ``-alpha v`` the damping ratio of a mode of circular
    frequency ``w`` is ``xi(w) = alpha / (2 w)`` (it falls as ``1/f``).

    Parameters
    ----------
    xi : float
        Damping ratio wanted [-] at ``f``.
    f : float
        Frequency [Hz] (e.g. the fundamental frequency of the layer).

    Returns
    -------
    float
        alpha [1/s].

    References
    ----------
    Chopra, A. K. (2012). Dynamics of Structures, 4th ed., Prentice Hall, ch. 11 (Rayleigh
    damping).
    """
    return 4.0 * math.pi * _pos("f", f) * _pos("xi", xi, allow_zero=True)


def mass_damping_ratio(alpha: float, f):
    """Damping ratio ``xi = alpha / (4 pi f)`` [-] of mass-proportional damping at ``f`` [Hz].

    Parameters
    ----------
    alpha : float
        Mass-proportional coefficient [1/s].
    f : float or array
        Frequency [Hz], > 0.

    Returns
    -------
    float or numpy.ndarray
        xi [-].

    References
    ----------
    Chopra, A. K. (2012). Dynamics of Structures, 4th ed., Prentice Hall, ch. 11.
    """
    fa = _freqs(f)
    if np.any(fa == 0):
        raise ClosedFormError("the frequency must be > 0 Hz")
    out = _pos("alpha", alpha, allow_zero=True) / (4.0 * np.pi * fa)
    return out[()] if out.ndim == 0 else out


def layer_transfer_rayleigh(f, vs: float, H: float, alpha: float, relative: bool = True,
                            complex_output: bool = False):
    """Transfer function ``u_top / u_base`` of a layer with mass-proportional damping.

    Exact steady-state solution of the 1D shear wave equation (z down from the free surface,
    ``u(H) = u_base``, ``du/dz(0) = 0``, time factor ``exp(i w t)``) with a damping force per
    unit volume proportional to the velocity, ``-rho alpha v``:

    - ``relative=True``: ``v`` is the velocity relative to the base,
      ``rho d²u/dt² + rho alpha d(u - u_b)/dt = G d²u/dz²``. With ``u = u_b + r`` and the
      circular frequency ``w``: ``G d²r/dz² + rho (w² - i alpha w) r = -rho w² u_b``, whose
      solution with ``r(H) = 0``, ``dr/dz(0) = 0`` gives::

          F = 1 - w / (w - i alpha) (1 - 1 / cos(kappa H)),   kappa = sqrt(w² - i alpha w) / Vs

      This is the form of the blocks' mass-proportional damping in murus with its default
      ``damping_frame="base"`` (:func:`murus.dem.engine.run`: damping on the velocities
      relative to the base).
    - ``relative=False``: ``v`` is the absolute velocity (the damping also resists the
      rigid-body motion with the base, as when every gridpoint velocity of a grid on a moving
      base is damped; ``damping_frame="absolute"`` for the blocks):
      ``G d²u/dz² + rho (w² - i alpha w) u = 0``, so ``F = 1 / cos(kappa H)``.

    Both have the modal damping ``xi_n = alpha / (2 w_n)``; they differ in the load on the
    modes (the base acceleration alone, or also the damping force ``-rho alpha du_b/dt`` of the
    base velocity). Both equal the modal superposition of :func:`layer_transfer_modal` with
    all modes (checked in tests/continuum/test_continuum_closed_forms.py), and at the first
    resonance both are ``~ Gamma_1 / (2 xi_1) = 2 / (pi xi_1)`` with ``xi_1 = alpha / (2 w_1)``
    (single-mode modal damping), the same peak as :func:`layer_transfer_hysteretic` with
    ``xi = xi_1``. The two forms differ by the factor ``w / (w - i alpha)`` on the relative
    part, i.e. by O(alpha / w): little for a few per cent of damping (0.3 % at the first
    resonance with ``xi_1 = 5 %``), and they meet as ``w >> alpha``.

    Parameters
    ----------
    f : float or array
        Frequencies [Hz], >= 0.
    vs : float
        Shear-wave velocity [m/s].
    H : float
        Layer thickness [m].
    alpha : float
        Mass-proportional coefficient [1/s] (:func:`mass_damping_alpha`).
    relative : bool
        Damping on the velocity relative to the base (True) or on the absolute velocity.
    complex_output : bool
        Return the complex ratio instead of its modulus.

    Returns
    -------
    numpy.ndarray or float
        ``|u_top / u_base|`` [-] (or the complex ratio).

    References
    ----------
    Kramer, S. L. (1996). Geotechnical Earthquake Engineering, Prentice Hall, §7.2.1 (the same
    boundary-value problem with a complex modulus); the damping term is derived here.
    Chopra, A. K. (2012). Dynamics of Structures, 4th ed., ch. 11 (Rayleigh damping).
    """
    fa = _freqs(f)
    vs, H, alpha = _pos("vs", vs), _pos("H", H), _pos("alpha", alpha, allow_zero=True)
    w = 2.0 * np.pi * fa.astype(np.complex128)
    kappa = np.sqrt(w * w - 1j * alpha * w) / vs
    sec = 1.0 / np.cos(kappa * H)
    if relative:
        with np.errstate(invalid="ignore", divide="ignore"):
            ratio = np.where(w == 0, 1.0, w / np.where(w == 0, 1.0, w - 1j * alpha))
        out = 1.0 - ratio * (1.0 - sec)
    else:
        out = sec
    out = out if complex_output else np.abs(out)
    return out[()] if out.ndim == 0 else out


def layer_transfer_modal(f, vs: float, H: float, alpha: float, n_modes: int = 1,
                         relative: bool = True, complex_output: bool = False):
    """Modal superposition of the transfer function of a layer with mass-proportional damping.

    Modes of the shear column fixed at the base: ``phi_n(z) = cos((2n - 1) pi z / (2H))`` (z down
    from the surface), ``w_n = 2 pi f_n``, participation ``Gamma_n = 4 (-1)^(n+1) / ((2n-1) pi)``
    (``phi_n(0) = 1``), modal damping ``2 xi_n w_n = alpha``::

        relative: F = 1 + sum_n Gamma_n w² / (w_n² - w² + i alpha w)
        absolute: F = 1 + sum_n Gamma_n (w² - i alpha w) / (w_n² - w² + i alpha w)

    With ``n_modes = 1`` this is the single-mode (modal damping) approximation; as
    ``n_modes`` grows it converges to :func:`layer_transfer_rayleigh` (error O(1/n_modes²)).

    Parameters
    ----------
    f : float or array
        Frequencies [Hz], >= 0.
    vs : float
        Shear-wave velocity [m/s].
    H : float
        Layer thickness [m].
    alpha : float
        Mass-proportional coefficient [1/s].
    n_modes : int
        Number of modes summed, >= 1.
    relative : bool
        Damping on the relative (True) or absolute velocity, as in
        :func:`layer_transfer_rayleigh`.
    complex_output : bool
        Return the complex ratio instead of its modulus.

    Returns
    -------
    numpy.ndarray or float
        ``|u_top / u_base|`` [-] (or the complex ratio).

    References
    ----------
    Chopra, A. K. (2012). Dynamics of Structures, 4th ed., Prentice Hall, ch. 17 (systems with
    distributed mass and elasticity: modal analysis under base excitation).
    """
    fa = _freqs(f)
    vs, H, alpha = _pos("vs", vs), _pos("H", H), _pos("alpha", alpha, allow_zero=True)
    if isinstance(n_modes, bool) or not isinstance(n_modes, int | np.integer) or n_modes < 1:
        raise ClosedFormError(f"n_modes must be an integer >= 1, got {n_modes!r}")
    w = 2.0 * np.pi * fa[..., None]
    n = np.arange(1, int(n_modes) + 1)
    wn = (2 * n - 1) * np.pi * vs / (2.0 * H)
    gamma = 4.0 * (-1.0) ** (n + 1) / ((2 * n - 1) * np.pi)
    load = w * w if relative else w * w - 1j * alpha * w
    out = 1.0 + np.sum(gamma * load / (wn * wn - w * w + 1j * alpha * w), axis=-1)
    out = out if complex_output else np.abs(out)
    return out[()] if out.ndim == 0 else out


# ----------------------------------------------------------------------------- quiet boundary


@dataclass(frozen=True)
class QuietReflection:
    """Plane-wave reflection at a viscous (Lysmer-Kuhlemeyer) boundary.

    Attributes
    ----------
    same : complex
        Amplitude (displacement) ratio of the reflected wave of the incident type (P for P,
        SV for SV) to the incident wave [-].
    converted : complex
        Amplitude ratio of the converted reflected wave (SV for P, P for SV) [-]; the sign
        depends on the polarisation convention of the module (only its modulus is compared).
    energy_same : float
        Energy flux of the reflected wave of the incident type through the boundary, as a
        fraction of the incident flux [-].
    energy_converted : float
        The same for the converted wave [-]; 0 beyond the critical angle of an incident SV
        wave (the converted P wave is then evanescent).
    energy_absorbed : float
        Power dissipated in the dashpots, fraction of the incident flux [-]; the three
        energies add up to 1.
    angle_converted : float
        Angle of the converted wave to the normal [rad], ``nan`` when it is evanescent.
    """

    same: complex
    converted: complex
    energy_same: float
    energy_converted: float
    energy_absorbed: float
    angle_converted: float

    @property
    def energy_reflected(self) -> float:
        """Reflected energy fraction ``energy_same + energy_converted`` [-]."""
        return self.energy_same + self.energy_converted


def quiet_boundary_reflection(theta: float, vp: float, vs: float, wave: str = "P",
                              a: float = 1.0, b: float = 1.0) -> QuietReflection:
    """Reflection of a plane P or SV wave on a Lysmer-Kuhlemeyer viscous boundary.

    The medium (density ``rho``, velocities ``Vp``, ``Vs``) fills ``y > 0``; its boundary
    ``y = 0`` carries the tractions ``t_n = -a rho Vp v_n`` and ``t_s = -b rho Vs v_s`` per unit
    area (``a = b = 1``: the standard quiet boundary). A plane wave of unit displacement
    amplitude arrives at ``theta`` from the normal; the reflected P and SV waves share its
    horizontal slowness ``p = sin(theta) / c`` (Snell). The two boundary conditions give a 2 x 2
    linear system for the two reflected amplitudes, solved here exactly (``rho`` cancels). At
    normal incidence with ``a = b = 1`` nothing is reflected; at oblique incidence a part is
    (Lysmer & Kuhlemeyer 1969, their energy-ratio figure); with ``a = b = 0`` the boundary is a
    free surface and the coefficients are the free-surface ones of Aki & Richards (2002),
    §5.2, all the energy reflected.

    Parameters
    ----------
    theta : float
        Angle of incidence to the boundary normal [rad], in [0, pi/2).
    vp, vs : float
        P- and S-wave velocities [m/s], ``vp > vs > 0``.
    wave : {"P", "S"}
        Type of the incident wave (S: in-plane SV).
    a, b : float
        Dimensionless coefficients of the normal and shear dashpots (>= 0).

    Returns
    -------
    QuietReflection
        Amplitude and energy ratios.

    References
    ----------
    Lysmer, J. and Kuhlemeyer, R. L. (1969). Finite dynamic model for infinite media. J. Eng.
    Mech. Div. ASCE 95(EM4), 859-877.
    Aki, K. and Richards, P. G. (2002). Quantitative Seismology, 2nd ed., University Science
    Books, §5.2 (reflection of P-SV waves at a free surface).
    """
    try:
        theta = float(theta)
    except (TypeError, ValueError):
        raise ClosedFormError(f"theta must be a number, got {theta!r}") from None
    if not 0.0 <= theta < 0.5 * math.pi:
        raise ClosedFormError(f"theta must be in [0, pi/2) rad, got {theta!r}")
    vp, vs = _pos("vp", vp), _pos("vs", vs)
    if vp <= vs:
        raise ClosedFormError(f"vp = {vp!r} m/s must exceed vs = {vs!r} m/s")
    a, b = _pos("a", a, allow_zero=True), _pos("b", b, allow_zero=True)
    if wave not in ("P", "S"):
        raise ClosedFormError(f"wave must be 'P' or 'S', got {wave!r}")
    mu, lam = vs * vs, vp * vp - 2.0 * vs * vs  # rho = 1
    c_in = vp if wave == "P" else vs
    p = math.sin(theta) / c_in

    def eta(c):  # vertical slowness of an up-going wave; decaying (Im > 0) when evanescent
        return np.sqrt(complex(1.0 / (c * c) - p * p))

    eta_p, eta_s = eta(vp), eta(vs)
    if eta_p.real == 0.0:
        eta_p = 1j * abs(eta_p.imag)
    # (slowness, polarisation) of each wave; reflected waves go up (+y)
    up_p = (np.array([p, eta_p]), vp * np.array([p, eta_p]))
    up_s = (np.array([p, eta_s]), vs * np.array([eta_s, -p]))
    if wave == "P":
        inc = (np.array([p, -eta_p]), vp * np.array([p, -eta_p]))
    else:
        inc = (np.array([p, -eta_s]), vs * np.array([-eta_s, -p]))

    def row(w):
        s, d = w
        sxy = mu * (s[0] * d[1] + s[1] * d[0])
        syy = lam * (s[0] * d[0] + s[1] * d[1]) + 2.0 * mu * s[1] * d[1]
        # boundary: sigma_xy = b rho Vs v_x, sigma_yy = a rho Vp v_y, v = -i w d A (/ i w)
        return np.array([sxy + b * vs * d[0], syy + a * vp * d[1]])

    m = np.column_stack([row(up_p), row(up_s)])
    rp, rs = np.linalg.solve(m, -row(inc))
    flux_in = c_in * c_in * (eta_p if wave == "P" else eta_s).real
    e_p = abs(rp) ** 2 * vp * vp * eta_p.real / flux_in
    e_s = abs(rs) ** 2 * vs * vs * eta_s.real / flux_in
    v = inc[1] + rp * up_p[1] + rs * up_s[1]  # velocity / (-i w) at y = 0
    e_abs = (a * vp * abs(v[1]) ** 2 + b * vs * abs(v[0]) ** 2) / flux_in
    if wave == "P":
        same, conv, e_same, e_conv, c_conv = rp, rs, e_p, e_s, vs
    else:
        same, conv, e_same, e_conv, c_conv = rs, rp, e_s, e_p, vp
    s_conv = p * c_conv
    ang = math.asin(s_conv) if s_conv <= 1.0 else float("nan")
    return QuietReflection(complex(same), complex(conv), float(e_same), float(e_conv),
                           float(e_abs), ang)


# ----------------------------------------------------------------------------- hole


def _hole_input(a, p0, pi, c, phi):
    a, p0 = _pos("a", a), _pos("p0", p0)
    pi, c = _pos("pi", pi, allow_zero=True), _pos("c", c, allow_zero=True)
    phi = _pos("phi", phi)
    if phi >= 0.5 * math.pi:
        raise ClosedFormError(f"phi must be in (0, pi/2) rad, got {phi!r}")
    if pi > p0:
        raise ClosedFormError(f"the internal pressure pi = {pi!r} Pa exceeds p0 = {p0!r} Pa "
                              "(the solution is for unloading)")
    kp = (1.0 + math.sin(phi)) / (1.0 - math.sin(phi))
    q = 2.0 * c * math.tan(0.25 * math.pi + 0.5 * phi)
    if pi + q / (kp - 1.0) <= 0.0:
        raise ClosedFormError("c = 0 with pi = 0: the hole collapses (no plastic radius)")
    return a, p0, pi, c, phi, kp, q


def hole_plastic_radius(a: float, p0: float, pi: float, c: float, phi: float) -> float:
    """Radius of the plastic zone around a cylindrical hole in a Mohr-Coulomb medium.

    ``R0 = a [2 / (Kp + 1) (P0 + q / (Kp - 1)) / (Pi + q / (Kp - 1))]^(1 / (Kp - 1))`` with
    ``Kp = (1 + sin phi) / (1 - sin phi)`` and ``q = 2 c tan(pi/4 + phi/2)`` (the uniaxial
    compressive strength); plane strain, hydrostatic far-field stress ``P0``, internal
    pressure ``Pi``, elastic-perfectly plastic. When the hole wall does not yield
    (``Pi >= (2 P0 - q) / (Kp + 1)``) the result is ``a`` (no plastic zone).

    Parameters
    ----------
    a : float
        Radius of the hole [m].
    p0 : float
        Far-field (in-situ) stress, compression positive [Pa].
    pi : float
        Internal pressure [Pa], ``0 <= pi <= p0``.
    c : float
        Cohesion [Pa].
    phi : float
        Friction angle [rad], in (0, pi/2).

    Returns
    -------
    float
        R0 [m].

    References
    ----------
    Salençon, J. (1969). Contraction quasi-statique d'une cavité à symétrie sphérique ou
    cylindrique dans un milieu élastoplastique. Annales des Ponts et Chaussées 4, 231-236.
    Itasca, FLAC Verification Problems: "Cylindrical hole in an infinite Mohr-Coulomb medium".
    """
    a, p0, pi, c, phi, kp, q = _hole_input(a, p0, pi, c, phi)
    A = q / (kp - 1.0)
    r0 = a * (2.0 / (kp + 1.0) * (p0 + A) / (pi + A)) ** (1.0 / (kp - 1.0))
    return max(r0, a)


def hole_stresses(r, a: float, p0: float, pi: float, c: float, phi: float):
    """Radial and tangential stresses around a cylindrical hole in a Mohr-Coulomb medium.

    Compression positive. Plastic zone ``a <= r <= R0`` (:func:`hole_plastic_radius`), with
    ``A = q / (Kp - 1)``::

        sigma_r = -A + (Pi + A) (r / a)^(Kp - 1)
        sigma_t = -A + Kp (Pi + A) (r / a)^(Kp - 1)

    elastic zone ``r >= R0``, with ``sigma_re = (2 P0 - q) / (Kp + 1)`` the radial stress at
    ``R0``::

        sigma_r = P0 - (P0 - sigma_re) (R0 / r)²
        sigma_t = P0 + (P0 - sigma_re) (R0 / r)²

    (with no plastic zone, ``sigma_re = Pi`` and ``R0 = a``: Kirsch's hydrostatic solution).
    Both satisfy equilibrium ``d sigma_r / dr = (sigma_t - sigma_r) / r`` and are continuous at
    ``R0``; the plastic stresses lie on the yield line ``sigma_t = Kp sigma_r + q``. The
    out-of-plane stress is not part of the solution (it is the intermediate principal stress).

    Parameters
    ----------
    r : float or array
        Distances from the centre of the hole [m], ``r >= a``.
    a : float
        Radius of the hole [m].
    p0 : float
        Far-field stress, compression positive [Pa].
    pi : float
        Internal pressure [Pa].
    c : float
        Cohesion [Pa].
    phi : float
        Friction angle [rad].

    Returns
    -------
    tuple of numpy.ndarray
        ``(sigma_r, sigma_t)`` [Pa], compression positive.

    References
    ----------
    Salençon, J. (1969), Annales des Ponts et Chaussées 4, 231-236.
    Itasca, FLAC Verification Problems: "Cylindrical hole in an infinite Mohr-Coulomb medium".
    """
    a, p0, pi, c, phi, kp, q = _hole_input(a, p0, pi, c, phi)
    ra = np.asarray(r, dtype=np.float64)
    if not np.all(np.isfinite(ra)) or np.any(ra < a * (1.0 - 1e-12)):
        raise ClosedFormError(f"r must be finite and >= a = {a!r} m")
    r0 = hole_plastic_radius(a, p0, pi, c, phi)
    A = q / (kp - 1.0)
    sre = (2.0 * p0 - q) / (kp + 1.0) if r0 > a else pi
    rho = ra / a
    plastic = ra < r0
    sr = np.where(plastic, -A + (pi + A) * rho ** (kp - 1.0), p0 - (p0 - sre) * (r0 / ra) ** 2)
    st = np.where(plastic, -A + kp * (pi + A) * rho ** (kp - 1.0),
                  p0 + (p0 - sre) * (r0 / ra) ** 2)
    return (sr[()], st[()]) if sr.ndim == 0 else (sr, st)


def hole_displacement(r, a: float, p0: float, pi: float, c: float, phi: float, G: float,
                      K: float, psi: float = 0.0):
    """Radial displacement around a cylindrical hole in a Mohr-Coulomb medium [m], outwards.

    Small strains, plane strain, the stresses of :func:`hole_stresses`, Hooke's law on the
    stress changes from ``P0`` (``nu = (3K - 2G) / (2 (3K + G))``) and the non-associated flow
    rule of dilation ``psi``: the plastic strains satisfy ``e_r^p + Kpsi e_t^p = 0`` with
    ``Kpsi = (1 + sin psi) / (1 - sin psi)``. Elastic zone ``r >= R0``::

        u = -(P0 - sigma_re) R0² / (2 G r)

    plastic zone ``a <= r <= R0``, integrating ``du/dr + Kpsi u / r = e_r^e + Kpsi e_t^e`` from
    the continuity of ``u`` at ``R0`` (with ``A = q / (Kp - 1)``, ``B = Pi + A``)::

        u = -r / (2G) [ (2 nu - 1) (P0 + A)
                        + (1 - nu) (Kp² - 1) / (Kp + Kpsi) B (R0 / a)^(Kp - 1) (R0 / r)^(Kpsi + 1)
                        + ((1 - nu) (Kp Kpsi + 1) / (Kp + Kpsi) - nu) B (r / a)^(Kp - 1) ]

    the expression of the Itasca verification problem (derived again here; the tests check the
    continuity at ``R0`` and the flow rule numerically). Negative values: the wall converges.

    Parameters
    ----------
    r : float or array
        Distances from the centre [m], ``r >= a``.
    a : float
        Radius of the hole [m].
    p0 : float
        Far-field stress, compression positive [Pa].
    pi : float
        Internal pressure [Pa].
    c : float
        Cohesion [Pa].
    phi : float
        Friction angle [rad].
    G, K : float
        Shear and bulk moduli [Pa].
    psi : float
        Dilation angle [rad], ``0 <= psi <= phi``.

    Returns
    -------
    numpy.ndarray or float
        u_r [m], positive outwards (the displacement caused by the excavation from ``P0``).

    References
    ----------
    Salençon, J. (1969), Annales des Ponts et Chaussées 4, 231-236.
    Itasca, FLAC Verification Problems: "Cylindrical hole in an infinite Mohr-Coulomb medium".
    """
    a, p0, pi, c, phi, kp, q = _hole_input(a, p0, pi, c, phi)
    G, K = _pos("G", G), _pos("K", K)
    psi = _pos("psi", psi, allow_zero=True)
    if psi > phi + 1e-12:
        raise ClosedFormError(f"the dilation psi = {psi!r} rad exceeds phi = {phi!r} rad")
    nu = (3.0 * K - 2.0 * G) / (2.0 * (3.0 * K + G))
    if not -1.0 < nu < 0.5:
        raise ClosedFormError(f"K = {K!r} Pa and G = {G!r} Pa give nu = {nu!r} outside (-1, 0.5)")
    ra = np.asarray(r, dtype=np.float64)
    if not np.all(np.isfinite(ra)) or np.any(ra < a * (1.0 - 1e-12)):
        raise ClosedFormError(f"r must be finite and >= a = {a!r} m")
    r0 = hole_plastic_radius(a, p0, pi, c, phi)
    sre = (2.0 * p0 - q) / (kp + 1.0) if r0 > a else pi
    kpsi = (1.0 + math.sin(psi)) / (1.0 - math.sin(psi))
    A = q / (kp - 1.0)
    B = pi + A
    elastic = -(p0 - sre) * r0 * r0 / (2.0 * G * ra)
    plastic = -ra / (2.0 * G) * (
        (2.0 * nu - 1.0) * (p0 + A)
        + (1.0 - nu) * (kp * kp - 1.0) / (kp + kpsi) * B * (r0 / a) ** (kp - 1.0)
        * (r0 / ra) ** (kpsi + 1.0)
        + ((1.0 - nu) * (kp * kpsi + 1.0) / (kp + kpsi) - nu) * B * (ra / a) ** (kp - 1.0))
    u = np.where(ra < r0, plastic, elastic)
    return u[()] if u.ndim == 0 else u


# ----------------------------------------------------------------------------- footing


def bearing_capacity_factors(phi: float) -> tuple[float, float]:
    """Prandtl-Reissner bearing capacity factors ``(N_c, N_q)`` [-].

    ``N_q = exp(pi tan phi) tan²(pi/4 + phi/2)`` (Reissner 1924) and
    ``N_c = (N_q - 1) cot phi`` (Prandtl 1920); ``phi = 0`` gives ``N_c = 2 + pi`` (the limit),
    ``N_q = 1``. A strip footing on a weightless soil of cohesion ``c`` under a surcharge
    ``q`` beside it carries ``c N_c + q N_q`` (:func:`strip_footing_capacity`).

    Parameters
    ----------
    phi : float
        Friction angle [rad], in [0, pi/2).

    Returns
    -------
    tuple of float
        ``(N_c, N_q)`` [-].

    References
    ----------
    Prandtl, L. (1920). Über die Härte plastischer Körper. Nachr. Ges. Wiss. Göttingen,
    Math.-Phys. Kl., 74-85.
    Reissner, H. (1924). Zum Erddruckproblem. Proc. 1st Int. Congress of Applied Mechanics,
    Delft, 295-311.
    Das, B. M. (2011). Principles of Foundation Engineering, 7th ed., Cengage, Table 3.3.
    """
    phi = _pos("phi", phi, allow_zero=True)
    if phi >= 0.5 * math.pi:
        raise ClosedFormError(f"phi must be in [0, pi/2) rad, got {phi!r}")
    if phi == 0.0:
        return 2.0 + math.pi, 1.0
    # N_q - 1 = expm1(pi t) T² + (T² - 1) with T² = tan²(pi/4 + phi/2) = (1 + s) / (1 - s): no
    # cancellation as phi -> 0, so N_c -> 2 + pi continuously
    s = math.sin(phi)
    t2 = (1.0 + s) / (1.0 - s)
    nq_1 = math.expm1(math.pi * math.tan(phi)) * t2 + 2.0 * s / (1.0 - s)
    return nq_1 / math.tan(phi), 1.0 + nq_1


def strip_footing_capacity(c: float, phi: float = 0.0, q: float = 0.0) -> float:
    """Ultimate pressure under a rough strip footing on a weightless soil, ``c N_c + q N_q``.

    With ``phi = 0``: Prandtl's ``(2 + pi) c + q``.

    Parameters
    ----------
    c : float
        Cohesion [Pa].
    phi : float
        Friction angle [rad].
    q : float
        Surcharge beside the footing [Pa].

    Returns
    -------
    float
        q_u [Pa] (force per unit area of the footing).

    References
    ----------
    Prandtl (1920); Reissner (1924) (see :func:`bearing_capacity_factors`).
    """
    nc, nq = bearing_capacity_factors(phi)
    return _pos("c", c, allow_zero=True) * nc + _pos("q", q, allow_zero=True) * nq


# ----------------------------------------------------------------------------- oedometer


def oedometric_modulus(E: float, nu: float) -> float:
    """Constrained (oedometric) modulus ``M = E (1 - nu) / ((1 + nu) (1 - 2 nu))`` [Pa].

    Equal to ``K + 4 G / 3`` (the P-wave modulus).

    Parameters
    ----------
    E : float
        Young's modulus [Pa].
    nu : float
        Poisson's ratio [-], in (-1, 0.5).

    Returns
    -------
    float
        M [Pa].

    References
    ----------
    Timoshenko, S. P. and Goodier, J. N. (1970). Theory of Elasticity, 3rd ed., McGraw-Hill
    (Hooke's law with the lateral strains prevented).
    """
    E = _pos("E", E)
    try:
        nu = float(nu)
    except (TypeError, ValueError):
        raise ClosedFormError(f"nu must be a number, got {nu!r}") from None
    if not -1.0 < nu < 0.5:
        raise ClosedFormError(f"nu must be in (-1, 0.5), got {nu!r}")
    return E * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu))


def oedometric_settlement(pressure: float, thickness: float, E: float, nu: float) -> float:
    """Settlement ``s = p t / M`` [m] of a laterally confined layer under a uniform pressure.

    Parameters
    ----------
    pressure : float
        Uniform vertical pressure added on the layer [Pa].
    thickness : float
        Layer thickness [m].
    E : float
        Young's modulus [Pa].
    nu : float
        Poisson's ratio [-].

    Returns
    -------
    float
        Settlement [m] (downwards positive).

    References
    ----------
    Timoshenko & Goodier (1970) (see :func:`oedometric_modulus`).
    """
    return (_pos("pressure", pressure, allow_zero=True) * _pos("thickness", thickness)
            / oedometric_modulus(E, nu))


# ----------------------------------------------------------------------------- thrusts


def rankine_thrust(gamma: float, H: float, phi: float) -> float:
    """Rankine's active thrust ``1/2 K_A gamma H²`` [N/m] on a smooth vertical wall.

    ``K_A = (1 - sin phi) / (1 + sin phi)``
    (:func:`murus.eurocode.ec8_5.rankine_coefficient`), level dry backfill, no cohesion; the
    thrust is horizontal and acts at ``H/3`` above the heel.

    Parameters
    ----------
    gamma : float
        Unit weight of the backfill [N/m³].
    H : float
        Height of the wall [m].
    phi : float
        Friction angle of the backfill [rad].

    Returns
    -------
    float
        P_A [N per metre of wall].

    References
    ----------
    Rankine, W. J. M. (1857). On the stability of loose earth. Phil. Trans. R. Soc. London 147,
    9-27.
    """
    return ec8_5.total_thrust(gamma, H, ec8_5.rankine_coefficient(phi))


def active_thrust(gamma: float, H: float, phi: float, delta: float = 0.0, kh: float = 0.0,
                  kv: float = 0.0) -> float:
    """Active thrust on a vertical wall with a level dry backfill [N/m]: Coulomb or M-O.

    ``P = 1/2 gamma (1 - kv) K H²`` with ``K`` from :func:`murus.eurocode.ec8_5.active_coefficient`
    at the seismic angle ``theta = atan(kh / (1 - kv))`` (EN 1998-5 (E.1), (E.2), (E.6)):
    ``kh = kv = 0`` is Coulomb's thrust (``delta = 0``: Rankine's), ``kh > 0`` is the
    Mononobe-Okabe thrust (static part included). The thrust is inclined by ``delta`` to the
    normal of the wall; its horizontal component is ``P cos(delta)``.

    Parameters
    ----------
    gamma : float
        Unit weight of the backfill [N/m³].
    H : float
        Height of the wall [m].
    phi : float
        Friction angle of the backfill [rad].
    delta : float
        Wall friction angle [rad], ``0 <= delta <= phi`` (smooth wall: 0; rough: e.g. 2/3 phi).
    kh : float
        Horizontal pseudo-static coefficient [-], towards the wall.
    kv : float
        Vertical pseudo-static coefficient [-], positive upwards
        (:mod:`murus.eurocode.ec8_5` conventions).

    Returns
    -------
    float
        P_A (or P_AE) [N per metre of wall].

    References
    ----------
    Coulomb, C. A. (1776). Essai sur une application des règles de maximis et minimis à
    quelques problèmes de statique relatifs à l'architecture. Mém. Acad. R. Sci. 7, 343-382.
    Mononobe, N. and Matsuo, H. (1929); Okabe, S. (1926) (as in :mod:`murus.eurocode.ec8_5`).
    CEN (2004). EN 1998-5:2004, Annex E, eqs. (E.1), (E.2), (E.6).
    """
    theta = ec8_5.seismic_angle(kh, kv)
    K = ec8_5.active_coefficient(phi, 0.0, delta, 0.5 * math.pi, theta)
    return ec8_5.total_thrust(gamma, H, K, kv)

"""Pseudo-static limit equilibrium of a dry-stone retaining wall, joint by joint
(Savalle et al. (2022), §4.4).

Savalle et al. (2022) §4.4 computes the pseudo-static resistance ``A_pseudo`` of each
wall "using an analytical approach based on the limit-equilibrium of a Coulomb's wedge of soil
[18, 27]" with the properties of Tables 5 and 6 and perfect stones ("no internal rotation of
the stones"); Table 8 gives 1.58 m/s² for DSRW1 under horizontal action and 1.50 m/s² with a
vertical component of half the horizontal one. The paper gives no equations; this module is a
reconstruction from EN 1998-5 and the usual DSRW limit analysis, every open choice being an
explicit :class:`Assumptions` field (documented, with their effect, in VALIDATION.md).

Model. The wall above each bed joint (:meth:`RetainingWall.part_above`) is a rigid block
loaded by

- its weight ``W`` at its centroid and the inertia forces ``kh W`` horizontal, out of the slope,
  and ``kv W`` vertical (``kv`` positive upwards: the effective weight is ``(1 - kv) W``);
- the earth thrust on its back face of vertical height ``h``: the static part
  ``E_s = 1/2 gamma K_A h²`` at ``static_point h`` above the bottom of the back face and the
  dynamic increment ``dE = 1/2 gamma (1 - kv) K h² - E_s`` at ``dynamic_point h`` (EN 1998-5
  (E.1)-(E.3), (E.6) and §7.3.2.3(4)-(5); or the trial-wedge thrust for a broken backfill),
  both inclined by the wall friction ``delta`` to the normal of the back face;
- the reaction of the bed joint, inclined by ``alpha`` towards the backfill.

Two mechanisms per joint: sliding out of the slope along the joint (up its inclination),
``FS = N tan(phi_j) / T`` with ``N`` and ``T`` the normal and tangential components of the
applied forces on the joint; overturning about the front (downhill) edge of the joint,
``FS = sum of stabilising moments / sum of overturning moments``, each force component
(horizontal and vertical) counted on the side of its moment; the vertical inertia is netted
with the weight (``(1 - kv) W``) and the static and dynamic thrusts are one force when they act
at the same point, so that the safety factors depend on the direction of the effective gravity
only (a tilt ``t`` gives those of ``kh = tan t``, ``kv = 0``). The limit ``FS = 1`` does not
depend on these conventions. ``A_pseudo = kh g`` at the smallest ``kh`` where the smallest
safety factor over joints and mechanisms reaches 1 (:func:`critical_acceleration`, a scan then
``brentq``), for ``kv = +-kv_ratio kh`` (the worse sign reported).

Defaults. ``delta = 2/3 phi`` and the whole thrust at ``h/3`` (EN 1998-5 §7.3.2.3(5)), the
base parallel to the beds, the worse sign of ``kv``: DSRW1 gives 1.588 m/s² (Table 8: 1.58)
and 1.469 m/s² with ``kv = 0.5 kh`` (1.50), and the walls whose values the paper does not
print give behaviour factors consistent with the mean and minimum it states. The literal
reading of Table 6 (``delta = phi = 37.7 deg``) with the EN mid-height increment is 13 % high.
VALIDATION.md has the sensitivity to each choice.

Tilting table (Savalle et al. (2022), refs [18, 33]): tilting the wall and its backfill by ``t``
turns gravity into ``g (sin t, -cos t)`` in the wall's frame, i.e. ``kh = sin t``, ``kv = 1 - cos
t`` (:func:`tilt_coefficients`, :func:`critical_tilt`).

Frame and units: those of :mod:`murus.retaining.geometry` (x into the backfill, z up, toe at
the origin); forces in N and moments in N m per metre of wall, accelerations in m/s².
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field
from functools import lru_cache

import numpy as np

from murus import G
from murus.errors import MurusError
from murus.eurocode import ec8_5
from murus.retaining.geometry import BedJoint, RetainingWall, WallPart

__all__ = [
    "PseudoStaticError", "Assumptions", "JointCheck", "PseudoStaticResult", "check_joint",
    "check_joints", "min_safety", "critical_acceleration", "safety_curves",
    "tilt_coefficients", "tilt_from_coefficients", "critical_tilt", "earth_thrust",
]

MODES = ("sliding", "overturning")


class PseudoStaticError(MurusError, ValueError):
    """Invalid pseudo-static input or no limit state in the searched range (one line)."""


@dataclass(frozen=True)
class Assumptions:
    """The choices Savalle et al. (2022) leaves open, with their defaults (VALIDATION.md shows their
    effect).

    Parameters
    ----------
    delta_ratio : wall friction ``delta = delta_ratio phi`` (default 2/3, the customary value
        for a gravity wall); ``None`` takes the wall-backfill interface friction of the wall
        (37.7 deg = phi in Savalle et al. (2022), Table 6).
    delta_deg : wall friction [deg], overrides ``delta_ratio`` when given.
    static_point : height of the static thrust above the bottom of the back face, as a
        fraction of its height (1/3: triangular pressure).
    dynamic_point : same for the dynamic increment: 1/3 (default; EN 1998-5 §7.3.2.3(5),
        walls free to rotate about their toe, the governing mechanism of a DSRW; also what
        the pseudo-static Coulomb wedge with a triangular pressure gives, and the only
        reading consistent with the tilting-table equivalence) or 0.5 (§7.3.2.3(4), mid-
        height "in the absence of a more detailed study").
    thrust : ``"mononobe-okabe"`` (EN 1998-5 Annex E, planar backfill) or ``"wedge"``
        (trial-wedge search, any backfill profile; equal for a planar one).
    seismic_angle : ``"E.6"`` (default, ``tan theta = kh / (1 - kv)``, EN 1998-5 (E.6)) or
        ``"kh-only"`` (``tan theta = kh``, ``kv`` scaling the thrust by ``1 - kv`` only):
        not the standard, kept to show how much the ``kv`` case depends on it.
    back_height : ``"back"``: the thrust acts on the back face of the part above the joint,
        down to where the joint meets it (lower than the joint's front edge when the beds are
        inclined); ``"front"``: down to the level of the joint's front edge only (the thrust
        height ``H - z_front``, as if the joint were horizontal).
    modes : mechanisms checked, among ``"sliding"`` and ``"overturning"``.
    joints : ``"all"``, ``"base"`` (only the base joint) or ``"above-base"`` (all but the
        base: the bottom course fixed to the foundation, as the DEM models of Savalle et al. (2022)
        fix the bottom wall units).
    """

    delta_ratio: float | None = 2.0 / 3.0
    delta_deg: float | None = None
    static_point: float = 1.0 / 3.0
    dynamic_point: float = 1.0 / 3.0
    thrust: str = "mononobe-okabe"
    seismic_angle: str = "E.6"
    back_height: str = "back"
    modes: tuple[str, ...] = MODES
    joints: str = "all"

    def __post_init__(self) -> None:
        for name in ("static_point", "dynamic_point"):
            v = getattr(self, name)
            if not (isinstance(v, int | float) and 0.0 <= v <= 1.0):
                raise PseudoStaticError(f"{name} must be a fraction of the height in [0, 1], "
                                        f"got {v!r}")
        if self.delta_deg is not None and not (isinstance(self.delta_deg, int | float)
                                               and 0.0 <= self.delta_deg < 90.0):
            raise PseudoStaticError(f"delta_deg must be in [0, 90) deg, got {self.delta_deg!r}")
        if self.delta_ratio is not None and not (isinstance(self.delta_ratio, int | float)
                                                 and 0.0 <= self.delta_ratio <= 1.0):
            raise PseudoStaticError(f"delta_ratio must be in [0, 1], got {self.delta_ratio!r}")
        if self.seismic_angle not in ("E.6", "kh-only"):
            raise PseudoStaticError(f"seismic_angle must be 'E.6' or 'kh-only', got "
                                    f"{self.seismic_angle!r}")
        if self.seismic_angle == "kh-only" and self.thrust != "mononobe-okabe":
            raise PseudoStaticError("seismic_angle='kh-only' needs thrust='mononobe-okabe'")
        if self.thrust not in ("mononobe-okabe", "wedge"):
            raise PseudoStaticError(f"thrust must be 'mononobe-okabe' or 'wedge', got "
                                    f"{self.thrust!r}")
        if self.back_height not in ("back", "front"):
            raise PseudoStaticError(f"back_height must be 'back' or 'front', got "
                                    f"{self.back_height!r}")
        modes = tuple(self.modes)
        if not modes or any(m not in MODES for m in modes):
            raise PseudoStaticError(f"modes must be a non-empty subset of {MODES}, got "
                                    f"{self.modes!r}")
        object.__setattr__(self, "modes", modes)
        if self.joints not in ("all", "base", "above-base"):
            raise PseudoStaticError(f"joints must be 'all', 'base' or 'above-base', got "
                                    f"{self.joints!r}")

    def delta(self, wall: RetainingWall) -> float:
        """Wall friction [rad] for ``wall``."""
        if self.delta_deg is not None:
            d = self.delta_deg
        elif self.delta_ratio is not None:
            d = self.delta_ratio * wall.backfill_friction_deg
        else:
            d = wall.interface_friction_deg
        if d > wall.backfill_friction_deg + 1e-12:
            raise PseudoStaticError(f"delta = {d:g} deg exceeds the backfill friction "
                                    f"{wall.backfill_friction_deg:g} deg")
        return math.radians(d)


@dataclass(frozen=True)
class JointCheck:
    """Limit-equilibrium check of the wall above one joint, for given ``kh`` and ``kv``.

    Forces per metre [N/m]: ``weight``, thrust ``E_static`` and ``dE``; on the joint the
    normal ``N`` (compression positive) and the tangential ``T`` (out of the slope positive);
    moments about the front edge [N m/m]: ``M_stab``, ``M_over``. ``back_height`` [m] is the
    height the thrust acts on.

    Attributes
    ----------
    joint : int
        Index (0 the base).
    height, back_height : float
        [m].
    kh, kv : float
        [-].
    weight, E_static, dE, N, T : float
        [N/m].
    fs_sliding, fs_overturning : float
        Safety factors [-].
    M_stab, M_over : float
        [N m/m].
    """

    joint: int
    height: float
    back_height: float
    kh: float
    kv: float
    weight: float
    E_static: float
    dE: float
    N: float
    T: float
    fs_sliding: float
    M_stab: float
    M_over: float
    fs_overturning: float

    def fs(self, mode: str) -> float:
        return self.fs_sliding if mode == "sliding" else self.fs_overturning


@lru_cache(maxsize=4096)
def _wedge_thrust(h, phi, delta, gamma, psi, beta, profile, kh, kv) -> float:
    from murus.retaining.wedge import trial_wedge

    return trial_wedge(h, phi, delta, gamma, kh, kv, psi, beta, profile).thrust


def earth_thrust(wall: RetainingWall, h: float, kh: float, kv: float, delta: float,
                 method: str = "mononobe-okabe", angle: str = "E.6") -> tuple[float, float]:
    """Static thrust and dynamic increment ``(E_s, dE)`` [N/m] on a back face of height ``h``.

    ``"mononobe-okabe"``: EN 1998-5 (E.1)-(E.3) with theta of (E.6) (planar backfill at
    ``wall.beta``); ``"wedge"``: :func:`murus.retaining.wedge.trial_wedge` with the wall's
    backfill profile. Both are dry backfills. ``angle="kh-only"`` (not the standard, see
    :class:`Assumptions`) takes ``tan theta = kh``.
    """
    gamma = wall.backfill_unit_weight
    if gamma == 0.0 or h <= 0.0:
        return 0.0, 0.0
    phi = math.radians(wall.backfill_friction_deg)
    if method == "wedge":
        from murus.retaining.wedge import WedgeError

        args = (h, phi, delta, gamma, wall.psi, wall.beta, wall.backfill_profile)
        try:
            Es = _wedge_thrust(*args, 0.0, 0.0)
            Ed = _wedge_thrust(*args, kh, kv)
        except WedgeError as exc:
            raise PseudoStaticError(str(exc)) from None
        return Es, Ed - Es
    if wall.backfill_profile is not None:
        raise PseudoStaticError("a broken backfill profile needs thrust='wedge'")
    try:
        if angle == "kh-only":
            Es = ec8_5.total_thrust(gamma, h, ec8_5.coulomb_coefficient(
                phi, wall.beta, delta, wall.psi))
            K = ec8_5.active_coefficient(phi, wall.beta, delta, wall.psi, math.atan(kh))
            return Es, ec8_5.total_thrust(gamma, h, K, kv) - Es
        return ec8_5.thrust_components(gamma, h, phi, kh, kv, wall.beta, delta, wall.psi)
    except ec8_5.EC85Error as exc:
        raise PseudoStaticError(str(exc)) from None


def _forces(wall: RetainingWall, part: WallPart, kh: float, kv: float, asm: Assumptions,
            delta: float):
    """Applied forces on the part: list of (point, Fx, Fz), and (E_s, dE, h)."""
    W = part.weight
    g = part.centroid
    # the vertical inertia is netted with the weight: (1 - kv) W, one stabilising force
    forces = [(g, 0.0, -(1.0 - kv) * W), (g, -kh * W, 0.0)]
    bottom, top = part.back_bottom, part.back_top
    if asm.back_height == "front":
        zb = min(max(part.joint.front[1], bottom[1]), top[1])
        f = (zb - bottom[1]) / (top[1] - bottom[1]) if top[1] > bottom[1] else 0.0
        bottom = (bottom[0] + f * (top[0] - bottom[0]), zb)
    h = top[1] - bottom[1]
    Es, dE = earth_thrust(wall, h, kh, kv, delta, asm.thrust, asm.seismic_angle)
    psi = wall.psi
    ux, uz = -math.sin(psi - delta), -math.cos(psi - delta)  # thrust direction on the wall

    def at(frac):
        return (bottom[0] + frac * (top[0] - bottom[0]), bottom[1] + frac * (top[1] - bottom[1]))

    ps, pd = at(asm.static_point), at(asm.dynamic_point)
    if abs(ps[0] - pd[0]) + abs(ps[1] - pd[1]) < 1e-12:
        # one resultant when both act at the same point (its components keep their sides)
        forces += [(ps, (Es + dE) * ux, 0.0), (ps, 0.0, (Es + dE) * uz)]
    else:
        forces += [(ps, Es * ux, 0.0), (ps, 0.0, Es * uz), (pd, dE * ux, 0.0),
                   (pd, 0.0, dE * uz)]
    return forces, (Es, dE, h)


def check_joint(wall: RetainingWall, joint: BedJoint | int, kh: float, kv: float = 0.0,
                assumptions: Assumptions | None = None) -> JointCheck:
    """Sliding and overturning of the wall above ``joint`` under ``kh``, ``kv``.

    Parameters
    ----------
    wall : RetainingWall
        The wall.
    joint : BedJoint or int
        The joint (or its index, 0 the base).
    kh, kv : float
        Seismic coefficients [-] (``kv`` positive upward).
    assumptions : Assumptions, optional
        The open choices (default :class:`Assumptions`).

    Returns
    -------
    JointCheck
    """
    asm = assumptions or Assumptions()
    if isinstance(joint, int):
        try:
            joint = wall.joints[joint]
        except IndexError:
            raise PseudoStaticError(f"joint {joint} does not exist (the wall has "
                                    f"{len(wall.joints)} joints)") from None
    kh, kv = float(kh), float(kv)
    if not (math.isfinite(kh) and math.isfinite(kv)) or kh < 0 or kv >= 1:
        raise PseudoStaticError(f"need finite kh >= 0 and kv < 1, got kh = {kh!r}, kv = {kv!r}")
    delta = asm.delta(wall)
    part = wall.part_above(joint)
    forces, (Es, dE, h) = _forces(wall, part, kh, kv, asm, delta)
    Fx = sum(f[1] for f in forces)
    Fz = sum(f[2] for f in forces)
    n, t = joint.normal, joint.tangent_out
    N = -(Fx * n[0] + Fz * n[1])
    T = Fx * t[0] + Fz * t[1]
    phij = math.radians(wall.joint_friction_deg)
    fs_s = N * math.tan(phij) / T if T > 0 else math.inf
    ox, oz = joint.front
    M_stab = M_over = 0.0
    for (px, pz), fx, fz in forces:
        m = (px - ox) * fz - (pz - oz) * fx  # > 0: outward (counter-clockwise) rotation
        if m > 0:
            M_over += m
        else:
            M_stab -= m
    fs_o = M_stab / M_over if M_over > 0 else math.inf
    return JointCheck(joint.index, joint.height, h, kh, kv, part.weight, Es, dE, N, T, fs_s,
                      M_stab, M_over, fs_o)


def _joints(wall: RetainingWall, asm: Assumptions) -> tuple[BedJoint, ...]:
    if asm.joints == "base":
        return wall.joints[:1]
    if asm.joints == "above-base":
        if len(wall.joints) < 2:
            raise PseudoStaticError(f"{wall.name}: no joint above the base (courses unknown)")
        return wall.joints[1:]
    return wall.joints


def check_joints(wall: RetainingWall, kh: float, kv: float = 0.0,
                 assumptions: Assumptions | None = None) -> list[JointCheck]:
    """:func:`check_joint` for every joint (base first).

    Parameters
    ----------
    wall : RetainingWall
        The wall.
    kh, kv : float
        Seismic coefficients [-] (``kv`` positive upward).
    assumptions : Assumptions, optional
        The open choices (default :class:`Assumptions`).

    Returns
    -------
    list of JointCheck
    """
    asm = assumptions or Assumptions()
    return [check_joint(wall, j, kh, kv, asm) for j in _joints(wall, asm)]


def min_safety(checks: list[JointCheck], modes=MODES) -> tuple[float, int, str]:
    """Smallest safety factor, its joint index and mechanism."""
    best = (math.inf, -1, "")
    for c in checks:
        for m in modes:
            if c.fs(m) < best[0]:
                best = (c.fs(m), c.joint, m)
    return best


@dataclass(frozen=True)
class PseudoStaticResult:
    """Pseudo-static resistance of a wall.

    ``A_pseudo = kh g`` [m/s²] (horizontal component), ``kh``, ``kv`` (signed, positive
    upwards) at the limit; ``joint`` (index, 0 = base) and ``joint_height`` [m] (its front
    edge above the toe) and ``mode`` of the governing mechanism; ``fs_static`` the smallest
    static safety factor; ``by_sign`` the limits for each sign of ``kv`` ({+1: upwards,
    -1: downwards}: (kh, joint, mode)).

    Attributes
    ----------
    wall : str
    A_pseudo : float
        [m/s²].
    kh, kv, kv_ratio : float
        [-].
    joint : int
    joint_height : float
        [m].
    mode : str
    fs_static : float
        [-].
    by_sign : dict
    assumptions : Assumptions
    """

    wall: str
    A_pseudo: float
    kh: float
    kv: float
    kv_ratio: float
    joint: int
    joint_height: float
    mode: str
    fs_static: float
    by_sign: dict = field(default_factory=dict)
    assumptions: Assumptions = field(default_factory=Assumptions)

    def summary(self) -> dict:
        d = {k: v for k, v in asdict(self).items() if k not in ("by_sign", "assumptions")}
        d["kv_sign"] = "upwards" if self.kv > 0 else ("downwards" if self.kv < 0 else "none")
        d["by_sign"] = {("upwards" if s > 0 else "downwards"): {
            "kh": v[0], "A_pseudo": v[0] * G, "joint": v[1], "mode": v[2]}
            for s, v in self.by_sign.items()}
        d["assumptions"] = asdict(self.assumptions)
        d["assumptions"]["modes"] = list(self.assumptions.modes)
        return d


def _limit(f, kh_max: float, n: int = 60) -> float | None:
    """Smallest root of f(kh) = min FS - 1 in (0, kh_max] by a scan and brentq."""
    from scipy.optimize import brentq

    grid = np.linspace(0.0, kh_max, n + 1)
    prev = f(grid[0])
    for a, b in zip(grid[:-1], grid[1:], strict=True):
        cur = f(b)
        if cur <= 0.0:
            if prev <= 0.0:
                return float(a)
            return float(brentq(f, a, b, xtol=1e-12, rtol=1e-12))
        prev = cur
    return None


def _kh_max(wall: RetainingWall, asm: Assumptions, kv_ratio: float) -> float:
    """Upper end of the search: below the seismic angle that closes EN 1998-5 (E.2)."""
    delta = asm.delta(wall)
    th = min(wall.psi - delta, 0.5 * math.pi) - 1e-3
    if asm.thrust == "wedge" or wall.backfill_profile is not None:
        # the trial wedge needs the last backfill slope below phi - theta
        phi = math.radians(wall.backfill_friction_deg)
        last = wall.beta
        if wall.backfill_profile:
            pts = [(0.0, 0.0), *wall.backfill_profile]
            (x0, z0), (x1, z1) = pts[-2], pts[-1]
            last = math.atan2(z1 - z0, x1 - x0)
        th = min(th, phi - last - 1e-6)
    if th <= 0:
        return 0.0
    # theta = atan(kh / (1 - r kh)) < th  <=>  kh < tan(th) / (1 + r tan(th))
    r = abs(kv_ratio)
    return min(math.tan(th) / (1.0 + r * math.tan(th)), 0.999 / r if r > 0 else math.inf, 3.0)


def critical_acceleration(wall: RetainingWall, kv_ratio: float = 0.0,
                          assumptions: Assumptions | None = None,
                          signs: tuple[int, ...] | None = None) -> PseudoStaticResult:
    """Pseudo-static resistance ``A_pseudo = kh g`` of ``wall`` (Savalle et al. (2022), §4.4, Table
    8).

    ``kv = s kv_ratio kh`` for ``s`` in ``signs`` (default both, +1 upwards first); the
    smallest ``kh`` at which the smallest safety factor over joints and mechanisms is 1.
    Raises :class:`PseudoStaticError` if the wall is not statically stable or no limit is
    found below the largest seismic angle EN 1998-5 (E.2) admits.

    Parameters
    ----------
    wall : RetainingWall
        The wall.
    kv_ratio : float
        ``|kv| / kh`` [-].
    assumptions : Assumptions, optional
        The open choices (default :class:`Assumptions`).
    signs : tuple of int, optional
        Signs of ``kv`` tried (+1 upward).

    Returns
    -------
    PseudoStaticResult

    References
    ----------
    Savalle et al. (2022), §4.4, Table 8; EN 1998-5 Annex E.
    """
    asm = assumptions or Assumptions()
    r = float(kv_ratio)
    if not math.isfinite(r) or r < 0:
        raise PseudoStaticError(f"kv_ratio must be >= 0, got {kv_ratio!r}")
    if signs is None:
        signs = (1, -1) if r > 0 else (1,)
    static = check_joints(wall, 0.0, 0.0, asm)
    fs0 = min_safety(static, asm.modes)[0]
    if fs0 <= 1.0:
        raise PseudoStaticError(f"{wall.name}: statically unstable (smallest static safety "
                                f"factor {fs0:.3f})")
    kh_max = _kh_max(wall, asm, r)
    by_sign = {}
    for s in signs:
        def f(kh, s=s):
            return min_safety(check_joints(wall, kh, s * r * kh, asm), asm.modes)[0] - 1.0

        kh = _limit(f, kh_max)
        if kh is None:
            continue
        _, j, mode = min_safety(check_joints(wall, kh, s * r * kh, asm), asm.modes)
        by_sign[s] = (kh, j, mode)
    if not by_sign:
        raise PseudoStaticError(f"{wall.name}: no limit state for kh up to {kh_max:.4f} (the "
                                "largest seismic angle EN 1998-5 (E.2) admits)")
    s = min(by_sign, key=lambda k: by_sign[k][0])
    kh, j, mode = by_sign[s]
    return PseudoStaticResult(wall.name, kh * G, kh, s * r * kh, r, j, wall.joints[j].height,
                              mode, fs0, by_sign, asm)


def safety_curves(wall: RetainingWall, kh, kv_ratio: float = 0.0, sign: int = 1,
                  assumptions: Assumptions | None = None) -> dict[str, np.ndarray]:
    """Safety factors on a grid of ``kh``: arrays ``[joint, kh]`` for each mechanism, and the
    joint heights. For plots (VALIDATION.md).

    Parameters
    ----------
    wall : RetainingWall
        The wall.
    kh : array_like
        Horizontal coefficients [-].
    kv_ratio : float
        ``|kv| / kh`` [-].
    sign : int
        Sign of ``kv`` (+1 upward).
    assumptions : Assumptions, optional
        The open choices (default :class:`Assumptions`).

    Returns
    -------
    dict of numpy.ndarray
    """
    asm = assumptions or Assumptions()
    kh = np.asarray(kh, dtype=float)
    joints = _joints(wall, asm)
    out = {m: np.empty((len(joints), kh.size)) for m in MODES}
    for i, k in enumerate(kh):
        for jj, c in enumerate(check_joints(wall, k, sign * kv_ratio * k, asm)):
            out["sliding"][jj, i] = c.fs_sliding
            out["overturning"][jj, i] = c.fs_overturning
    out["joint_height"] = np.array([j.height for j in joints])
    out["kh"] = kh
    return out


# -- tilting table -------------------------------------------------------------------------------
def tilt_coefficients(tilt: float) -> tuple[float, float]:
    """``(kh, kv) = (sin t, 1 - cos t)`` for a tilt ``t`` [rad] of the wall and its backfill.

    In the tilted frame gravity is ``g (sin t, -cos t)``: a horizontal coefficient ``sin t``
    out of the slope and a vertical one ``1 - cos t`` upwards (Savalle et al. (2022), refs [18,
    33]).

    Parameters
    ----------
    tilt : float
        Tilt of the table [rad].

    Returns
    -------
    tuple of float
        ``(kh, kv)`` [-].
    """
    t = float(tilt)
    if not (math.isfinite(t) and 0.0 <= t < 0.5 * math.pi):
        raise PseudoStaticError(f"the tilt must be in [0, pi/2) rad, got {tilt!r}")
    return math.sin(t), 1.0 - math.cos(t)


def tilt_from_coefficients(kh: float, kv: float) -> float:
    """The tilt [rad] equivalent to ``(kh, kv)`` when ``kh² + (1 - kv)² = 1`` (else an error).

    Parameters
    ----------
    kh, kv : float
        Seismic coefficients [-] (``kv`` positive upward).

    Returns
    -------
    float
        Tilt [rad].
    """
    if abs(kh * kh + (1.0 - kv) ** 2 - 1.0) > 1e-9:
        raise PseudoStaticError(f"(kh, kv) = ({kh!r}, {kv!r}) is not a tilt: kh² + (1 - kv)² "
                                "must be 1")
    return math.atan2(kh, 1.0 - kv)


def critical_tilt(wall: RetainingWall, assumptions: Assumptions | None = None) -> tuple[
        float, int, str]:
    """Tilt [rad] of a tilting table at which the smallest safety factor is 1, its joint and
    mechanism (``kh = sin t``, ``kv = 1 - cos t``).

    Parameters
    ----------
    wall : RetainingWall
        The wall.
    assumptions : Assumptions, optional
        The open choices (default :class:`Assumptions`).

    Returns
    -------
    tuple
        Tilt [rad], joint index, mechanism (``"sliding"`` or ``"overturning"``).
    """
    from scipy.optimize import brentq

    asm = assumptions or Assumptions()

    def f(t):
        kh, kv = tilt_coefficients(t)
        return min_safety(check_joints(wall, kh, kv, asm), asm.modes)[0] - 1.0

    if f(0.0) <= 0:
        raise PseudoStaticError(f"{wall.name}: statically unstable")
    t_max = min(wall.psi - asm.delta(wall), 0.5 * math.pi) - 1e-3
    if wall.backfill_unit_weight > 0:
        t_max = min(t_max, math.radians(wall.backfill_friction_deg) - wall.beta - 1e-6)
    grid = np.linspace(0.0, t_max, 401)
    for a, b in zip(grid[:-1], grid[1:], strict=True):
        if f(b) <= 0:
            t = float(brentq(f, a, b, xtol=1e-12))
            kh, kv = tilt_coefficients(t)
            _, j, m = min_safety(check_joints(wall, kh, kv, asm), asm.modes)
            return t, j, m
    raise PseudoStaticError(f"{wall.name}: no limit state below a tilt of "
                            f"{math.degrees(t_max):.2f} deg")

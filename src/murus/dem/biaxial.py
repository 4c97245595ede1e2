"""2D biaxial test of a disc assembly and calibration of the rolling resistance (issue 6, 2a).

The backfill of a dry-stone retaining wall is modelled with discs (Savalle et al. (2022), §2:
granular backfill of friction angle 37.7 deg at full scale, 45 deg for the mock-ups). Round
particles roll too easily: a disc assembly with a realistic interparticle friction alone gives a
macroscopic friction angle well below the one of angular gravel, and the usual remedy is a rolling
resistance at the contacts (:class:`~murus.dem.materials.Joint` ``rolling`` = mu_r, rolling
moment limited by ``mu_r r_eff Fn``). :func:`calibrate_rolling` finds the mu_r that gives a
target peak friction angle in a numerical biaxial test (:func:`biaxial_test`).

Procedure (plane strain, per metre out of plane, no gravity):

1. ``n`` discs of radii uniform in ``radius`` [m] on a square grid of pitch ``2 r_max (1 +
   gap)`` (no initial overlap), in a box of four rigid frictionless walls (kinematic bodies);
2. isotropic compaction to ``sigma3`` [Pa]: the walls close in at a constant speed until the
   mean wall stress reaches sigma3 / 4, then the four walls are servo-controlled (PFC's servo:
   each wall moves by ``du = alpha (sigma - sigma3) A / k_w`` per chunk of steps, ``k_w`` the sum
   of the normal stiffnesses of its contacts, capped at a maximum speed) until the four stresses
   are within ``tol`` of ``sigma3`` and the assembly is in equilibrium (unbalanced-force ratio);
3. vertical compression at the constant strain rate ``strain_rate`` [1/s] (top and bottom walls
   move towards each other at ``H rate / 2`` each), the lateral walls servo-controlled at
   ``sigma3``, up to the axial strain ``max_strain``.

The walls are kinematic ``"fixed"`` bodies moved by this module between chunks of a few steps
(position and velocity set directly: the engine does not integrate kinematic ``"fixed"`` bodies
and detects contacts at their current position); the wall stresses are the sums of the
sub-contact forces on each wall divided by the current length of the sample side (thickness
``Model.thickness`` = 1 m).

Recorded: axial strain ``eps1 = 1 - H / H0``, lateral stress sigma3, axial stress sigma1 (mean of
the top and bottom walls), volumetric strain ``eps_v = 1 - H W / (H0 W0)`` (2D, positive in
contraction), all averaged over each sampling interval. Mobilised friction angle ``phi =
asin((sigma1 - sigma3) / (sigma1 + sigma3))``; ``phi_peak_deg`` at the peak of the stress ratio,
``phi_cs_deg`` the mean over the last ``cs_fraction`` of the test (critical state).

Quasi-static loading: the inertial number ``I = rate d sqrt(rho / sigma3)`` (GDR MiDi 2004) is
kept at ``inertial`` (default 1e-3: quasi-static regime, I < 1e-3) when ``strain_rate`` is None.
"""

from __future__ import annotations

import math
import time as _time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from murus.dem import kernels as K
from murus.dem.materials import Joint
from murus.dem.model import Model
from murus.dem.packing import GRID_GAP, disc_grid

__all__ = ["BiaxialResult", "CalibrationResult", "disc_assembly", "biaxial_test",
           "calibrate_rolling", "plot_biaxial"]

_LEFT, _RIGHT, _BOTTOM, _TOP = 0, 1, 2, 3

# Settings of the procedure (module docstring), named once:
#: Local damping during the compaction (Cundall's 0.7, PFC's default for static problems).
COMPACTION_DAMPING = 0.7
#: Closing speed of the walls before the servo, as a multiple of the shear strain rate.
CLOSE_RATE = 10.0
#: The servo takes over when the mean wall stress reaches this fraction of sigma3.
CLOSE_STRESS = 0.25
#: Unbalanced-force ratio below which the compacted sample is in equilibrium.
COMPACTION_UNBALANCE = 2e-2
#: Consecutive chunks within ``tol`` and :data:`COMPACTION_UNBALANCE` that end the compaction.
COMPACTION_STREAK = 5
#: Largest number of steps of the compaction (a RuntimeError beyond).
MAX_COMPACTION_STEPS = 400_000
#: Time constant of the integral term of the lateral servo during the shear [chunks].
SERVO_INTEGRAL_CHUNKS = 50.0
#: Largest speed of the lateral walls during the shear, as a multiple of ``strain_rate W0``.
LATERAL_RATE = 20.0


@dataclass
class BiaxialResult:
    """History of a biaxial test (SI units: strains [-], stresses [Pa], angles [deg]).

    ``volumetric_strain`` > 0 is contraction; ``stress_ratio = (s1 - s3) / (s1 + s3)`` the sine
    of the mobilised friction angle."""

    axial_strain: np.ndarray
    sigma1: np.ndarray
    sigma3: np.ndarray
    volumetric_strain: np.ndarray
    sigma3_target: float
    phi_peak_deg: float
    phi_cs_deg: float
    strain_at_peak: float
    porosity0: float  # porosity after compaction [-]
    n: int
    rolling: float
    friction_deg: float
    strain_rate: float  # [1/s]
    dt: float  # [s]
    steps: int
    wall: float  # wall-clock time [s]
    meta: dict = field(default_factory=dict)

    @property
    def deviatoric(self) -> np.ndarray:
        """sigma1 - sigma3 [Pa]."""
        return self.sigma1 - self.sigma3

    @property
    def stress_ratio(self) -> np.ndarray:
        """(sigma1 - sigma3) / (sigma1 + sigma3) = sin(phi_mobilised) [-]."""
        return (self.sigma1 - self.sigma3) / (self.sigma1 + self.sigma3)

    @property
    def phi_deg(self) -> np.ndarray:
        """Mobilised friction angle [deg] along the test."""
        return np.degrees(np.arcsin(np.clip(self.stress_ratio, -1.0, 1.0)))


@dataclass
class CalibrationResult:
    """Rolling coefficient ``rolling`` giving ``phi_peak_deg`` near ``target_deg`` [deg];
    ``history`` the (rolling, mean phi_peak_deg) pairs tried, in order; ``status`` and
    ``message`` say how the search ended (:func:`calibrate_rolling`); ``result`` the test of
    the first assembly at ``rolling``."""

    rolling: float
    phi_peak_deg: float
    target_deg: float
    converged: bool
    history: list
    result: BiaxialResult | None = None
    status: str = ""
    message: str = ""
    std_deg: float = math.nan  # standard deviation over the assemblies at ``rolling`` [deg]
    phi_seeds: tuple = ()  # peak angle of each assembly at ``rolling`` [deg]
    se_deg: float = math.nan  # standard error of the calibrated angle [deg]


def disc_assembly(n: int, radius=(0.02, 0.03), seed: int = 0, aspect: float = 2.0,
                  gap: float = GRID_GAP) -> tuple[np.ndarray, np.ndarray, float, float]:
    """``n`` discs without overlap on a square grid of pitch ``2 r_max (1 + gap)``, about
    ``aspect`` = height / width; radii uniform in ``radius`` [m] (generator ``seed``).
    Returns centres (n, 2) [m] (box corner at the origin), radii (n,) [m], box width and
    height [m] (half a pitch of clearance to the walls). The square lattice of
    :func:`murus.dem.packing.disc_grid`."""
    rmin, rmax = float(radius[0]), float(radius[1])
    if not (0 < rmin <= rmax):
        raise ValueError(f"radius range must satisfy 0 < rmin <= rmax [m], got {radius!r}")
    if n < 4:
        raise ValueError(f"n must be at least 4 discs, got {n!r}")
    if not aspect > 0:
        raise ValueError(f"aspect must be positive, got {aspect!r}")
    nx = max(2, int(round(math.sqrt(n / aspect))))
    ny = int(math.ceil(n / nx))
    centres, r, pitch = disc_grid((rmin, rmax), seed=seed, gap=gap, lattice="square", n=n,
                                  columns=nx)
    return centres, r, nx * pitch, ny * pitch


class _Box:
    """Four kinematic walls around a disc assembly, moved between chunks of steps."""

    def __init__(self, m: Model, walls: list[int], width: float, height: float, thick: float):
        self.m = m
        self.walls = walls
        self.half = 0.5 * thick
        self.thick_out = m.thickness

    def faces(self) -> tuple[float, float, float, float]:
        p = self.m.bpos
        w = self.walls
        return (p[w[_LEFT], 0] + self.half, p[w[_RIGHT], 0] - self.half,
                p[w[_BOTTOM], 1] + self.half, p[w[_TOP], 1] - self.half)

    def size(self) -> tuple[float, float]:
        xl, xr, yb, yt = self.faces()
        return xr - xl, yt - yb

    def wall_loads(self) -> tuple[np.ndarray, np.ndarray]:
        """Normal force pushing on each wall [N] (> 0 compression) and the sum of the normal
        stiffnesses ``kn A`` of its contacts [N/m]."""
        m = self.m
        on = m.sid >= 0
        f = m.sf
        ba = m.sbody[m.pairs[:, 0]]
        bb = m.sbody[m.pairs[:, 1]]
        force = np.zeros(4)
        kw = np.zeros(4)
        # outward normal of each wall (direction in which the discs push it)
        out = np.array([[-1.0, 0.0], [1.0, 0.0], [0.0, -1.0], [0.0, 1.0]])
        for j, w in enumerate(self.walls):
            for col, sgn in ((ba, -1.0), (bb, 1.0)):
                sel = (col == w)[:, None] & on
                if not sel.any():
                    continue
                fn = f[..., K.F_FN][sel]
                fs = f[..., K.F_FS][sel]
                nx = f[..., K.F_NX][sel]
                ny = f[..., K.F_NY][sel]
                fx = sgn * (fn * nx - fs * ny)  # force on the wall
                fy = sgn * (fn * ny + fs * nx)
                force[j] += float(np.sum(fx * out[j, 0] + fy * out[j, 1]))
                kw[j] += float(np.sum(f[..., K.F_KNA][sel]))
        return force, kw

    def stresses(self) -> tuple[np.ndarray, np.ndarray]:
        """Stress on each wall [Pa] (left, right, bottom, top) and the wall stiffnesses."""
        width, height = self.size()
        force, kw = self.wall_loads()
        t = self.thick_out
        length = np.array([height, height, width, width]) * t
        return force / length, kw

    def move(self, du: np.ndarray, dt_chunk: float) -> None:
        """Move each wall inwards by ``du`` [m] (negative: outwards) over ``dt_chunk`` [s]."""
        inward = np.array([[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]])
        for j, w in enumerate(self.walls):
            d = du[j] * inward[j]
            self.m.bpos[w] += d
            self.m.bvel[w] = d / dt_chunk if dt_chunk > 0 else 0.0


def _build(joint: Joint, n, radius, seed, aspect, density, wall_joint):
    centres, radii, width, height = disc_assembly(n, radius, seed, aspect)
    m = Model(gravity=0.0, joint=joint)
    m.set_joint(wall_joint if wall_joint is not None
                else Joint(kn=0.1 * joint.kn, ks=0.1 * joint.ks, friction_deg=0.0), "wall",
                "default")
    thick = 0.5 * max(width, height)
    long_ = 3.0 * max(width, height)
    walls = [
        m.add_rectangle(thick, long_, center=(-0.5 * thick, 0.5 * height), kinematic="fixed",
                        group="wall"),
        m.add_rectangle(thick, long_, center=(width + 0.5 * thick, 0.5 * height),
                        kinematic="fixed", group="wall"),
        m.add_rectangle(long_, thick, center=(0.5 * width, -0.5 * thick), kinematic="fixed",
                        group="wall"),
        m.add_rectangle(long_, thick, center=(0.5 * width, height + 0.5 * thick),
                        kinematic="fixed", group="wall"),
    ]
    for c, r in zip(centres, radii, strict=True):
        m.add_disc(c, r, density=density)
    m.build()
    return m, _Box(m, walls, width, height, thick), radii


def _advance(m: Model, nsteps: int, alpha: float) -> None:
    """``nsteps`` steps with local damping ``alpha`` (the history of the run is dropped; the
    interpenetration check of the engine, 5 % of the cost of such short calls, is made by
    :func:`_check_overlap` at each recorded sample instead)."""
    m.run(duration=nsteps * m.dt, every=nsteps, local_damping=alpha, max_overlap=None)
    if len(m.history.get("t", ())) > 1000:  # (an empty history costs one more sample)
        m.history.clear()


def _check_overlap(m: Model, where: str, walls) -> None:
    """RuntimeError when two discs interpenetrate by more than the engine's limit
    (:data:`murus.dem.engine.OVERLAP_LIMIT` of the smaller one's diameter). The contacts with
    the ``walls`` are left out: their compliance (a tenth of the discs' stiffness, for the
    servo) is a device of the test, and a disc presses into a wall by up to about 10 % of its
    diameter at the peak."""
    from murus.dem.engine import OVERLAP_LIMIT, overlap_fraction

    frac, a, b, depth = overlap_fraction(m, exclude=walls)
    if frac > OVERLAP_LIMIT:
        raise RuntimeError(f"{where}: discs {a} and {b} interpenetrate by {depth:.3g} m, "
                           f"{100 * frac:.3g} % of the diameter of the smaller one (limit "
                           f"{100 * OVERLAP_LIMIT:g} %): kn is too low for sigma3")


def biaxial_test(joint: Joint, n: int = 200, sigma3: float = 50e3, radius=(0.02, 0.03),
                 seed: int = 0, aspect: float = 2.0, density: float = 2650.0,
                 max_strain: float = 0.12, strain_rate: float | None = None,
                 inertial: float = 1e-3, cs_fraction: float = 0.3, damping: float = 0.3,
                 compaction_friction_deg: float | None = None, wall_joint: Joint | None = None,
                 chunk: int = 10, servo_alpha: float = 0.5, tol: float = 0.02,
                 sample_strain: float = 0.002,
                 max_compaction_steps: int = MAX_COMPACTION_STEPS,
                 progress: Callable | None = None) -> BiaxialResult:
    """Biaxial test of ``n`` discs (module doc) with the disc-disc ``joint`` (kn, ks [Pa/m],
    friction, rolling coefficient).

    sigma3 : confining stress [Pa]; radius : (r_min, r_max) [m]; density [kg/m³];
    max_strain : final axial strain [-]; strain_rate : axial strain rate [1/s] (None: from the
    inertial number ``inertial``); cs_fraction : last fraction of the test averaged for the
    critical-state angle; damping : Cundall local damping during the shear phase (0.7 during
    compaction); compaction_friction_deg : interparticle friction during compaction (None: the
    joint's; lower gives a denser sample); wall_joint : disc-wall joint (default frictionless,
    stiffnesses a tenth of the joint's: a compliant wall contact makes the servo faster, and
    the wall penetration, sigma3 / kn_wall ~ 5e-4 m at 50 kPa, is negligible against the
    sample size); chunk : steps between wall updates; servo_alpha : servo gain (fraction of
    the stress error corrected per chunk if the sample were rigid; the lateral servo of the
    shear phase adds an integral term of time constant 50 chunks that carries the dilatancy
    velocity); tol : relative tolerance on the four wall stresses at the end of compaction
    (reached with an unbalanced-force ratio below 2e-2 for 5 chunks in a row);
    sample_strain : axial-strain interval of the recorded (averaged) samples;
    progress : ``progress(strain, max_strain)`` called at each recorded sample of the shear
    phase (axial strain reached [-], final axial strain [-]).
    """
    if not sigma3 > 0:
        raise ValueError(f"sigma3 must be positive [Pa], got {sigma3!r}")
    if not (0 < max_strain < 0.5):
        raise ValueError(f"max_strain must be in (0, 0.5), got {max_strain!r}")
    if not (0 < cs_fraction < 1):
        raise ValueError(f"cs_fraction must be in (0, 1), got {cs_fraction!r}")
    t_start = _time.perf_counter()
    comp_joint = joint
    if compaction_friction_deg is not None:
        comp_joint = Joint(kn=joint.kn, ks=joint.ks, friction_deg=compaction_friction_deg,
                           rolling=joint.rolling)
    m, box, radii = _build(comp_joint, n, radius, seed, aspect, density, wall_joint)
    m.run(duration=0.0)  # time step from the model (no contact yet: one full face per disc)
    m.history.clear()
    dt = m.dt
    dmean = 2.0 * float(np.mean(radii))
    if strain_rate is None:
        strain_rate = inertial / (dmean * math.sqrt(density / sigma3))
    if not strain_rate > 0:
        raise ValueError(f"strain_rate must be positive [1/s], got {strain_rate!r}")
    tc = chunk * dt

    def servo(sig, kw, du_max, which, integ=None):
        width, height = box.size()
        length = np.array([height, height, width, width]) * m.thickness
        du = np.zeros(4)
        for j in which:
            err = sigma3 - sig[j]  # > 0: push inwards
            d = servo_alpha * err * length[j] / kw[j] if kw[j] > 0 else du_max
            if integ is not None:  # PI: the integral term carries the steady wall speed
                integ[j] += d / SERVO_INTEGRAL_CHUNKS
                d += integ[j]
            du[j] = max(-du_max, min(du_max, d))
        return du

    # ---- 1. isotropic compaction: the walls close in at a constant speed (strain rate
    # 10 x the shear rate) until the mean wall stress reaches sigma3 / 4, then the servo
    w0, h0 = box.size()
    v_close = CLOSE_RATE * strain_rate * np.array([w0, w0, h0, h0])
    steps = 0
    sig, kw = box.stresses()
    while np.mean(sig) < CLOSE_STRESS * sigma3 and steps < max_compaction_steps:
        box.move(v_close * tc, tc)
        _advance(m, chunk, COMPACTION_DAMPING)
        steps += chunk
        sig, kw = box.stresses()
    vmax_c = CLOSE_RATE * strain_rate * max(w0, h0)
    ok = 0
    while steps < max_compaction_steps:
        box.move(servo(sig, kw, vmax_c * tc, range(4)), tc)
        _advance(m, chunk, COMPACTION_DAMPING)
        steps += chunk
        sig, kw = box.stresses()
        ratio = m.S[K.S_UNBAL] / m.S[K.S_MEANF] if m.S[K.S_MEANF] > 0 else math.inf
        if np.all(np.abs(sig / sigma3 - 1.0) < tol) and ratio < COMPACTION_UNBALANCE:
            ok += 1
            if ok >= COMPACTION_STREAK:
                break
        else:
            ok = 0
    else:
        raise RuntimeError(f"compaction to sigma3={sigma3:g} Pa did not converge in "
                           f"{max_compaction_steps} steps (stresses {sig})")
    _check_overlap(m, "compaction", box.walls)
    if compaction_friction_deg is not None:
        m.update_joint(joint)
    box.move(np.zeros(4), tc)
    W0, H0 = box.size()
    porosity0 = 1.0 - float(np.sum(np.pi * radii**2)) / (W0 * H0)
    comp_steps = steps

    # ---- 2. shearing at constant axial strain rate, lateral stress held
    v_axial = 0.5 * strain_rate * H0  # each of top and bottom [m/s]
    vmax_l = LATERAL_RATE * strain_rate * W0
    every = max(1, int(round(sample_strain / (strain_rate * tc))))
    e1, s1, s3, ev = [], [], [], []
    acc = np.zeros(3)
    nacc = 0
    eps = 0.0
    integ = np.zeros(4)
    while eps < max_strain:
        du = servo(sig, kw, vmax_l * tc, (_LEFT, _RIGHT), integ)
        du[_BOTTOM] = du[_TOP] = v_axial * tc
        box.move(du, tc)
        _advance(m, chunk, damping)
        steps += chunk
        sig, kw = box.stresses()
        width, height = box.size()
        eps = 1.0 - height / H0
        acc += (0.5 * (sig[_BOTTOM] + sig[_TOP]), 0.5 * (sig[_LEFT] + sig[_RIGHT]),
                1.0 - width * height / (W0 * H0))
        nacc += 1
        if nacc == every:
            e1.append(eps)
            s1.append(acc[0] / nacc)
            s3.append(acc[1] / nacc)
            ev.append(acc[2] / nacc)
            acc[:] = 0.0
            nacc = 0
            _check_overlap(m, f"shear at {100 * eps:.2f} % axial strain", box.walls)
            if progress is not None:
                progress(eps, max_strain)
    e1a = np.array(e1)
    s1a = np.array(s1)
    s3a = np.array(s3)
    q = (s1a - s3a) / (s1a + s3a)
    ipk = int(np.argmax(q))
    cs = e1a >= (1.0 - cs_fraction) * e1a[-1]
    return BiaxialResult(
        axial_strain=e1a, sigma1=s1a, sigma3=s3a, volumetric_strain=np.array(ev),
        sigma3_target=float(sigma3), phi_peak_deg=math.degrees(math.asin(q[ipk])),
        phi_cs_deg=math.degrees(math.asin(float(np.mean(q[cs])))),
        strain_at_peak=float(e1a[ipk]), porosity0=porosity0, n=int(n),
        rolling=float(joint.rolling), friction_deg=float(joint.friction_deg),
        strain_rate=float(strain_rate), dt=float(dt), steps=int(steps),
        wall=_time.perf_counter() - t_start,
        meta={"compaction_steps": comp_steps, "W0": W0, "H0": H0, "seed": seed,
              "radius": tuple(radius), "density": density, "damping": damping})


def calibrate_rolling(target_phi_deg: float, joint: Joint | None = None,
                      bracket=(0.0, 1.0), tol_deg: float = 0.5, max_runs: int = 8,
                      seeds=(0,), progress: Callable | None = None,
                      **kw) -> CalibrationResult:
    """Rolling coefficient mu_r of ``joint`` (default kn = ks = 1e9 Pa/m, friction 30 deg) for
    which the mean peak friction angle of :func:`biaxial_test` (keywords ``kw``) over the
    assemblies ``seeds`` is ``target_phi_deg`` [deg]; at most ``max_runs`` values of mu_r.

    The peak angle of one 200-disc sample scatters by about 3.5 deg from one assembly to the
    next and from one mu_r to a close one (strain localisation: the sample is chaotic), so that
    phi(mu_r) of one assembly is not monotone at the scale of a few hundredths of mu_r. Each
    value of mu_r is therefore evaluated on every assembly of ``seeds``, and the search
    accounts for the noise of the means, estimated from the scatter over the assemblies
    (``s``, pooled over the values tried; ``se = s sqrt(2 / len(seeds))`` for the difference
    of two means):

    1. the two ends of ``bracket`` are run; their means must increase by more than 2 se
       (status ``"non_monotone"`` otherwise) and enclose the target within ``tol_deg``
       (``"outside_bracket"``);
    2. bisection, the point placed by linear interpolation while the bracket shrinks from
       both sides and at the middle otherwise, while the angles of the bracket's ends differ by
       more than 6 se (below, a new point would not be resolved from the ends); a mean outside
       the angles of the ends by more than 3 se stops the search (``"non_monotone"``: more
       assemblies or discs are needed); a mean within ``tol_deg`` of the target ends it;
    3. if the bisection stopped at the noise level: the straight line fitted (least squares)
       to every test inside the last bracket resolved above the noise (the final bracket and
       the point that split it) gives mu_r at the target, within the final bracket; its slope
       must exceed 2 standard errors (``"non_monotone"`` otherwise); the assemblies are then
       run at that mu_r (if ``max_runs`` allows) and the line fitted again with them.

    Without scatter (one seed, or identical results) the noise is taken as zero and the
    search is the plain bisection with the stop at ``tol_deg``.

    Returns a :class:`CalibrationResult`: ``status`` ``"converged"``, ``"outside_bracket"``,
    ``"non_monotone"`` or ``"max_runs"`` (``converged`` only for the first); ``rolling`` [-];
    ``phi_peak_deg`` the mean angle over the assemblies at ``rolling`` (when they were run
    there; else the fitted line's value); ``std_deg`` their standard deviation (the scatter of
    one sample) and ``phi_seeds`` each of them; ``se_deg`` the standard error of the
    calibrated angle (of the fitted line at ``rolling``, or of the mean). ``progress(done,
    total)``, if given, is called after each biaxial test (tests done, most tests)."""
    from dataclasses import replace

    joint = joint or Joint(kn=1e9, ks=1e9, friction_deg=30.0)
    seeds = tuple(seeds)
    if not seeds:
        raise ValueError("seeds must name at least one assembly")
    if not tol_deg > 0:
        raise ValueError(f"tol_deg must be positive, got {tol_deg!r}")
    if int(max_runs) < 2:
        raise ValueError(f"max_runs must be at least 2, got {max_runs!r}")
    target = float(target_phi_deg)
    hist = []  # (mu, mean phi) in order
    runs = {}  # mu -> results over the seeds
    total = int(max_runs) * len(seeds)
    S = len(seeds)

    def f(mu):
        rs = []
        for s_ in seeds:
            rs.append(biaxial_test(replace(joint, rolling=float(mu)), seed=s_, **kw))
            if progress is not None:
                progress(sum(len(v) for v in runs.values()) + len(rs), total)
        phi = float(np.mean([r.phi_peak_deg for r in rs]))
        hist.append((float(mu), phi))
        runs[float(mu)] = rs
        return phi

    def scatter():  # pooled standard deviation over the assemblies [deg]
        if S < 2:
            return 0.0
        v = [np.var([r.phi_peak_deg for r in rs], ddof=1) for rs in runs.values()]
        return float(math.sqrt(np.mean(v)))

    def done(status, message, mu=None, phi=None, se=math.nan):
        if mu is None:
            mu, phi = min(hist, key=lambda h: abs(h[1] - target))
            se = scatter() / math.sqrt(S) if S > 1 else math.nan
        rs = runs.get(mu)
        phis = tuple(float(r.phi_peak_deg) for r in rs) if rs else ()
        if rs:
            phi = float(np.mean(phis))
        std = float(np.std(phis, ddof=1)) if len(phis) > 1 else math.nan
        first = rs[0] if rs else runs[min(runs, key=lambda m_: abs(m_ - mu))][0]
        return CalibrationResult(mu, phi, target, status == "converged", hist, first,
                                 status=status, message=message, std_deg=std,
                                 phi_seeds=phis, se_deg=se)

    a, b = float(bracket[0]), float(bracket[1])
    if not b > a:
        raise ValueError(f"bracket must be (low, high) with low < high, got {bracket!r}")
    fa, fb = f(a), f(b)
    se = scatter() * math.sqrt(2.0 / S)
    if not fb - fa > 2.0 * se:
        return done("non_monotone", f"the bracket's ends do not increase beyond the noise: "
                    f"mu_r = {a:g} gives {fa:.2f} deg, {b:g} gives {fb:.2f} deg (2 standard "
                    f"errors: {2 * se:.2f} deg)")
    if not fa - tol_deg <= target <= fb + tol_deg:
        return done("outside_bracket", f"the target {target:g} deg is outside the angles "
                    f"{fa:.2f}-{fb:.2f} deg of mu_r = {a:g}-{b:g}")
    side = 0
    wide = (a, b)  # the last bracket resolved above the noise (the window of the final fit)
    while True:
        best = min(hist, key=lambda h: abs(h[1] - target))
        if abs(best[1] - target) <= tol_deg:
            return done("converged", f"mu_r = {best[0]:.4g} gives {best[1]:.2f} deg "
                        f"(target {target:g} +- {tol_deg:g} deg)")
        se = scatter() * math.sqrt(2.0 / S)
        if se > 0 and fb - fa <= 6.0 * se:
            break  # the noise level: fit a line over the bracket
        if len(hist) >= max_runs:
            return done("max_runs", f"{max_runs} values of mu_r tried, the closest gives "
                        f"{best[1]:.2f} deg (target {target:g} +- {tol_deg:g} deg)")
        wide = (a, b)
        c = a + (target - fa) / (fb - fa) * (b - a)
        if side in (-2, 2) or not a < c < b:  # the same end kept twice: bisect
            c = 0.5 * (a + b)
        fc = f(c)
        if fc < fa - 3.0 * se or fc > fb + 3.0 * se or (se == 0 and not fa <= fc <= fb):
            return done("non_monotone", "the mean peak angle is not monotone in mu_r beyond "
                        f"the noise ({3 * se:.2f} deg): {fa:.2f}, {fc:.2f}, {fb:.2f} deg at "
                        f"mu_r = {a:.4g}, {c:.4g}, {b:.4g} (average more assemblies, "
                        "--seeds)")
        if fc > target:
            b, fb = c, fc
            side = side - 1 if side < 0 else -1
        else:
            a, fa = c, fc
            side = side + 1 if side > 0 else 1
        if side in (-3, 3):
            side = 0

    lo, hi = wide

    def fit():
        x = np.array([mu for mu, rs in runs.items() if lo <= mu <= hi for _ in rs])
        y = np.array([r.phi_peak_deg for mu, rs in runs.items() if lo <= mu <= hi for r in rs])
        A = np.column_stack([np.ones_like(x), x - x.mean()])
        coef, *_ = np.linalg.lstsq(A, y, rcond=None)
        dof = max(len(y) - 2, 1)
        s2 = float(np.sum((y - A @ coef) ** 2)) / dof
        cov = s2 * np.linalg.inv(A.T @ A)
        return coef, cov, float(x.mean())

    coef, cov, xm = fit()
    if not coef[1] > 2.0 * math.sqrt(cov[1, 1]):
        return done("non_monotone", f"over mu_r = {lo:.4g}-{hi:.4g} the peak angle does not "
                    f"increase beyond 2 standard errors (slope {coef[1]:.3g} +- "
                    f"{math.sqrt(cov[1, 1]):.2g} deg per unit of mu_r; average more "
                    "assemblies, --seeds)")
    mu = float(np.clip(xm + (target - coef[0]) / coef[1], a, b))
    if len(hist) < max_runs and mu not in runs:
        f(mu)
        coef, cov, xm = fit()
        if not coef[1] > 2.0 * math.sqrt(cov[1, 1]):
            return done("non_monotone", f"over mu_r = {lo:.4g}-{hi:.4g} the peak angle does "
                        f"not increase beyond 2 standard errors (slope {coef[1]:.3g} +- "
                        f"{math.sqrt(cov[1, 1]):.2g} deg per unit of mu_r)")
    mu_fit = float(np.clip(xm + (target - coef[0]) / coef[1], a, b))
    g = np.array([1.0, mu - xm])
    phi_fit = float(coef[0] + coef[1] * (mu - xm))
    se_fit = float(math.sqrt(g @ cov @ g))
    n_fit = sum(len(rs) for m_, rs in runs.items() if lo <= m_ <= hi)
    msg = (f"mu_r = {mu:.4g}: the line fitted to the {n_fit} tests over mu_r = {lo:.4g}-{hi:.4g} "
           f"gives {phi_fit:.2f} +- {se_fit:.2f} deg there (target {target:g} deg; with the "
           f"tests at {mu:.4g}, its root is {mu_fit:.4g})")
    return done("converged", msg, mu, phi_fit, se_fit)


def plot_biaxial(result: BiaxialResult, ax=None):
    """Stress ratio (sigma1 - sigma3) / (sigma1 + sigma3) and volumetric strain (right axis,
    contraction positive) against the axial strain [%]; returns the Axes."""
    if ax is None:
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(figsize=(6, 4))
    e = 100 * result.axial_strain
    ax.plot(e, result.stress_ratio, color="C0", label="stress ratio")
    ax.axhline(math.sin(math.radians(result.phi_peak_deg)), color="C0", ls=":", lw=0.8)
    ax.axhline(math.sin(math.radians(result.phi_cs_deg)), color="C0", ls="--", lw=0.8)
    ax.set_xlabel("axial strain [%]")
    ax.set_ylabel("(σ1 - σ3) / (σ1 + σ3) [-]", color="C0")
    ax2 = ax.twinx()
    ax2.plot(e, 100 * result.volumetric_strain, color="C1", label="volumetric strain")
    ax2.set_ylabel("volumetric strain [%] (contraction > 0)", color="C1")
    ax.set_title(f"biaxial test: μr = {result.rolling:g}, φ_peak = {result.phi_peak_deg:.1f}°, "
                 f"φ_cs = {result.phi_cs_deg:.1f}°", fontsize=9)
    return ax

"""Collapse protocol and seismic behaviour factor of a dry-stone retaining wall
(Savalle et al. (2022), §4.2-4.4, Tables 7 and 8; issues 6 and 18), on the DEM wall
(:mod:`murus.retaining.dem_wall`) with a backfill: by default the paper's Mohr-Coulomb continuum
(:mod:`murus.retaining.continuum_backfill`, the reference), or the equivalent EN 1998-5 thrust,
or a disc assembly (:mod:`murus.retaining.backfill`); docs/retaining_backfills.md says which
to use for what.

Protocol (Savalle et al. (2022), §4.2-4.3):

- input S2: the harmonic ramp ``S(t) = A t sin(2 pi f t)`` (Savalle et al. (2022), eq. 5) whose
  envelope reaches the pseudo-static resistance ``A_pseudo`` at ``t_pseudo = 2.5 s``: ``A = A_pseudo
  /
  2.5`` [m/s³] ("the slope is defined so that its pseudo-static resistance is always reached at
  2.5 s"); ``A_pseudo`` from :func:`murus.retaining.pseudostatic.critical_acceleration` (with
  ``kv_ratio = 0.5`` when a vertical component is applied: "the slope of S2 is recomputed,
  accounting for the vertical acceleration");
- collapse when ``d_top``, the horizontal displacement of the top stone relative to the base
  (positive out of the slope), exceeds 20 % of the wall height (5 % for the mock-ups, §3.1);
  ``t_col`` is that instant (linear interpolation between samples) and ``A_col = A t_col`` the
  amplitude of the input (its envelope) at that instant;
- ``A_peak = 0.6 A_col`` (§4.2): the ratio is checked with two S1 signals (same slope, peak
  ``0.6 A_col`` and ``0.7 A_col``, decreasing part twice as long as the increasing one; seed
  Figure 14: stable at 0.6, collapsed at 0.7): :func:`peak_ratio_check`; an S1 run is "stable"
  when d_top stays below the threshold during the signal and a free tail after it (default
  1 s, gravity and the static thrust only);
- ``r = A_peak / A_pseudo`` (§4.4, Table 8);
- vertical component (§4.3): the same shape with half the amplitude, in phase (its positive
  peaks, upwards, with the positive horizontal peaks, i.e. with the horizontal inertia out of
  the slope: the effective gravity is largest then) or in opposition (the critical case of the
  seed).

Sign of the horizontal input: ``a_x > 0`` is a base acceleration into the backfill, whose
inertia on the wall acts out of the slope (``kh = a_x / g``); S(t) starts with that sign.

Numerics (documented choices): mass-proportional damping of ``xi = 5 %`` of critical at the input
frequency (:data:`XI_SAVALLE`), the effective damping of Savalle et al. (2022): "a damping value
zeta of 5 % is considered ... Since only the mass-proportional part of the Rayleigh damping is
used, a multiplicative factor of 2 is applied to the chosen value to ensure appropriate effective
damping (5 %) at the critical frequency" (§3.1; §4.1 the same). Tables 1 and 6 print the 10 % given
to UDEC, whose Rayleigh input (xi_min, f_min) sets ``alpha = xi_min omega_min``: its mass term
alone damps ``alpha / (2 omega) = xi_min / 2`` at ``f_min``. murus's ``xi`` is the fraction of
critical itself (``alpha = 2 xi omega``), so the paper's damping is ``xi = 0.05`` (before issue 18
murus used 0.10, twice the paper's damping: DSRW1 at 5 Hz on the continuum backfill collapsed at
6.91 instead of 5.92 m/s²). The damping acts on the
velocity relative to the base (``damping_frame="base"``; ``"absolute"`` damps the velocity in
the fixed frame, as UDEC does, so that it also resists the motion of the wall with the
ground); joint stiffness of Table 6 times ``stiffness_scale`` (:data:`STIFFNESS_SCALE`: 1e-2
on the continuum, whose A_col of DSRW1 is then that of the printed stiffness within 0.3 %; not
so for the scaled-down mock-ups: H/B = 1.7 fails at 3.06 m/s² (median of four runs, range
3.02-3.08) at 1e-2 and at 3.35 m/s² at 1e-1, H/B = 2.7 at 2.93 and 2.59 m/s², VALIDATION.md;
1e-3 for the equivalent thrust and the discs, so that a full-scale run takes about half a
minute). With
``backfill="thrust"`` a kinematic backstop runs along the back face (the backfill cannot be
entered, :func:`~murus.retaining.dem_wall.build_wall`); with ``"discrete"`` or
``"continuum"`` the backstop and the thrust are replaced by the backfill behind the wall.
Units: SI (m, s, m/s², m/s³, Hz).

Check of the thrust model: DSRW1 under a monotonic base acceleration ``a = 0.75 t`` (no
carrier, 1e-3 stiffness) starts a mechanism near 1.5-1.65 m/s² (d_top 1 cm at 1.5, 2.2 cm at
1.65, 22 cm at 2.25 m/s²), i.e. at the pseudo-static ``A_pseudo = 1.59 m/s²``: the DEM wall
and the limit analysis agree when the load is quasi-static.
"""

from __future__ import annotations

import math
import time as _time
from collections.abc import Callable, Sequence
from concurrent.futures import Executor
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from murus.continuum import DEFAULT_CORNER_SHARE
from murus.errors import MurusError
from murus.retaining.geometry import RetainingWall

__all__ = ["CollapseError", "CollapseResult", "BehaviourTable", "VERTICAL_MODES",
           "pseudo_static_resistance", "ramp_rate", "collapse_run", "peak_ratio_check",
           "failure_mode", "plot_collapse", "behaviour_factor", "SEED_TABLE7", "XI_SAVALLE",
           "DT_FACTORS", "CollapseEnsemble", "collapse_ensemble", "STIFFNESS_SCALE",
           "SUBCYCLE_MAX_SCALE", "subcycle_refused"]

#: Default factor on the joint stiffness of Savalle et al. (2022), Tables 1 and 6, per backfill
#: model. Continuum: 1e-2, whose A_col is that of the stiffness as printed within 0.3 % (DSRW1 at
#: 5 Hz: 6.15 against 6.14 m/s², where 1e-3 gives 5.92, -3.5 %; VALIDATION.md) at a third of its
#: cost; the equivalent thrust and the disc backfill, validated at 1e-3, keep it.
STIFFNESS_SCALE = {"thrust": 1e-3, "discrete": 1e-3, "continuum": 1e-2}

#: The largest joint stiffness scale at which subcycling is allowed with the interface's corner
#: rule ``corner_share="follow"``: at the printed stiffness (x 1) the subcycled mock-ups crept
#: from a quarter of their resistance while the interface chattered (sessions 14 and 15;
#: ``validation/subcycle_chatter.py``), and so did one step for all under any small
#: perturbation (session 16), fed by energy a rocking stone's corner gained from the interface
#: when its stiffness followed the coverage rule up under load. The default rule, "shrink"
#: (session 17: ``interface._kept_trib``; VALIDATION.md, *The corner rule*), mends it, and
#: with it subcycling is allowed at any stiffness: at x 1 the subcycled runs agree with one
#: step for all (VALIDATION.md, *Subcycling*: the mock-ups H/B = 1.7 and 2.7 and DSRW1 at
#: 5 Hz), as at x 1e-1 and below.
SUBCYCLE_MAX_SCALE = 0.1


def subcycle_refused(subcycle, stiffness_scale: float | None,
                     corner_share: str = DEFAULT_CORNER_SHARE) -> str | None:
    """Why ``subcycle`` is refused at ``stiffness_scale`` with the interface's corner rule
    ``corner_share`` (above :data:`SUBCYCLE_MAX_SCALE` with the rule "follow"), or None
    (allowed; also when the scale is not given yet).

    Parameters
    ----------
    subcycle : int, "auto" or None
        As :func:`collapse_run`'s.
    stiffness_scale : float or None
        The joints' stiffness scale.
    corner_share : {"shrink", "follow"}
        The interface's corner rule (:class:`murus.retaining.continuum_backfill.ContinuumBackfill`).

    Returns
    -------
    str or None
    """
    if subcycle in (None, 1) or stiffness_scale is None or corner_share != "follow":
        return None
    if stiffness_scale > SUBCYCLE_MAX_SCALE * (1 + 1e-12):
        return (f"subcycle = {subcycle!r} at stiffness_scale = {stiffness_scale:g} with "
                f"corner_share = 'follow': not validated above x {SUBCYCLE_MAX_SCALE:g} (the "
                f"rocking corners feed the interface's chatter: VALIDATION.md, Subcycling); use "
                f"the default corner rule 'shrink' or one step for all")
    return None


#: Mass-proportional damping of Savalle et al. (2022), fraction of critical at the input frequency
#: (§3.1 and §4.1: 5 %, given to UDEC as 10 % because the mass term alone gives half of it).
XI_SAVALLE = 0.05

#: Vertical components: none, in phase, in opposition (Savalle et al. (2022), §4.3, ratio 0.5).
VERTICAL_MODES = ("none", "in_phase", "opposition")

#: Savalle et al. (2022), Table 7 / Table 8 for DSRW1: (frequency [Hz], vertical) -> (t_col [s],
#: A_col [m/s²], A_pseudo [m/s²], r).
SEED_TABLE7 = {
    (3.0, "none"): (7.6, 4.83, 1.58, 1.83),
    (5.0, "none"): (8.5, 5.38, 1.58, 2.04),
    (10.0, "none"): (9.5, 6.03, 1.58, 2.29),
    (5.0, "in_phase"): (8.9, 5.34, 1.50, 2.14),
    (5.0, "opposition"): (8.6, 5.19, 1.50, 2.07),
}


class CollapseError(MurusError, ValueError):
    """Invalid collapse-protocol input (one-line message)."""


def _vertical(kv_mode: str) -> str:
    k = str(kv_mode).strip().lower().replace("-", "_")
    aliases = {"none": "none", "": "none", "-": "none", "in_phase": "in_phase",
               "phase": "in_phase", "opposition": "opposition", "opposite": "opposition"}
    if k not in aliases:
        raise CollapseError(f"vertical mode must be one of {', '.join(VERTICAL_MODES)}, got "
                            f"{kv_mode!r}")
    return aliases[k]


def pseudo_static_resistance(wall: RetainingWall, kv_mode: str = "none",
                             assumptions=None, vertical_ratio: float = 0.5) -> float:
    """``A_pseudo`` [m/s²] of ``wall`` (horizontal component), with ``kv = +-0.5 kh`` when a
    vertical component is applied (both signs, the worse: the paper prints one value)."""
    from murus.retaining.pseudostatic import critical_acceleration

    r = 0.0 if _vertical(kv_mode) == "none" else vertical_ratio
    return critical_acceleration(wall, r, assumptions).A_pseudo


def ramp_rate(A_pseudo: float, t_pseudo: float = 2.5) -> float:
    """Slope ``A`` [m/s³] of the envelope reaching ``A_pseudo`` at ``t_pseudo`` (§4.3)."""
    if not (A_pseudo > 0 and t_pseudo > 0):
        raise CollapseError("A_pseudo and t_pseudo must be positive")
    return A_pseudo / t_pseudo


@dataclass
class CollapseResult:
    """One DEM run of the collapse protocol, made by :func:`collapse_run`.

    :meth:`summary` adds ``d_top_max`` [m], ``A_peak = 0.6 A_col`` [m/s²] and the behaviour
    factor ``r = A_peak / A_pseudo`` [-] (NaN without collapse; Savalle et al. (2022), §4.2
    and §4.4, Table 8).

    Attributes
    ----------
    wall : str
        Name of the wall.
    frequency : float
        Frequency f of the input [Hz].
    vertical : str
        Vertical component: ``"none"``, ``"in_phase"`` or ``"opposition"``.
    signal : str
        ``"S2"`` (harmonic ramp to collapse) or ``"S1"`` (ramp up to ``a_peak`` and down).
    A_rate : float
        Slope A of the envelope of the input [m/s³].
    A_pseudo : float
        Pseudo-static resistance of the wall [m/s²].
    a_peak : float
        Peak of the envelope of an S1 signal [m/s²]; NaN for S2.
    threshold : float
        Collapse threshold on ``d_top`` [m] (a fraction of ``height``).
    height : float
        Height H of the wall [m].
    collapsed : bool
        Whether ``d_top`` exceeded ``threshold``.
    t_col : float
        Instant of collapse [s], linear interpolation between samples; NaN if none.
    A_col : float
        Amplitude of the envelope of the input at ``t_col`` [m/s²] (``A_rate t_col`` for S2);
        NaN if no collapse.
    t_end : float
        Model time at the end of the run [s] (``t_col``'s step when stopped by the collapse).
    t : numpy.ndarray
        Sample times [s].
    d_top : numpy.ndarray
        Horizontal displacement of the top stone relative to the base [m], positive out of
        the slope, at ``t``.
    acc : numpy.ndarray
        Horizontal input acceleration [m/s²] at ``t``, positive into the backfill.
    acc_v : numpy.ndarray
        Vertical input acceleration [m/s²] at ``t`` (zeros without one).
    kh : numpy.ndarray
        Horizontal seismic coefficient of the thrust at ``t`` [-].
    kv : numpy.ndarray
        Vertical seismic coefficient of the thrust at ``t`` [-].
    polygons : list of numpy.ndarray
        The stones and foundation at the end of the run (the collapse instant when stopped
        there), each a (k, 2) array of vertices [m].
    displacement : numpy.ndarray
        Displacement magnitude of each polygon's body relative to the base [m].
    wall_time : float
        Computing time of the run, set-up included [s].
    steps : int
        Time steps of the dynamic run.
    dt : float
        Time step of the DEM [s].
    status : str
        Status of the DEM run: ``"stopped"`` (collapse) or ``"completed"``.
    options : dict
        The numerical settings of the run (damping, intervals, threshold fraction, backfill,
        those of the DEM wall).
    rotation : numpy.ndarray
        Rotation of each polygon's body [rad], counter-clockwise positive.
    mode : str
        Mechanism at the end of the run, ``"S"`` (sliding) or ``"T"`` (toppling), ``""``
        when ``d_top <= 0`` (:func:`failure_mode`; Savalle et al. (2022), Table 3).
    setup_time : float
        Part of ``wall_time`` before the dynamic run [s] (building, settling, the backfill's
        generation); not in :meth:`summary`, which stays the same on a re-run.
    disc_centres : numpy.ndarray
        Centres of the discs of a discrete backfill at the end [m], shape (n, 2).
    disc_radii : numpy.ndarray
        Their radii [m], shape (n,).
    disc_displacement : numpy.ndarray
        Their displacement magnitude relative to the base [m], shape (n,).
    zone_xy, zone_cells, zone_state : numpy.ndarray
        Zones of a continuum backfill at the end: gridpoint coordinates [m] (ng, 2), the
        gridpoints of each zone (nz, 4) and its plastic state (nz,) (bits: 1 shear now,
        2 tension now, 4 shear past, 8 tension past).

    References
    ----------
    Savalle et al. (2022), §4.2-4.4, Tables 3, 7 and 8.
    """

    wall: str
    frequency: float
    vertical: str
    signal: str
    A_rate: float
    A_pseudo: float
    a_peak: float
    threshold: float
    height: float
    collapsed: bool
    t_col: float
    A_col: float
    t_end: float
    t: np.ndarray
    d_top: np.ndarray
    acc: np.ndarray
    acc_v: np.ndarray
    kh: np.ndarray
    kv: np.ndarray
    polygons: list = field(default_factory=list, repr=False)
    displacement: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)
    wall_time: float = 0.0
    steps: int = 0
    dt: float = 0.0
    status: str = ""
    options: dict = field(default_factory=dict)
    rotation: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)
    mode: str = ""
    setup_time: float = 0.0
    disc_centres: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)), repr=False)
    disc_radii: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)
    disc_displacement: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)
    zone_xy: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)), repr=False)
    zone_cells: np.ndarray = field(default_factory=lambda: np.zeros((0, 4), np.int64),
                                   repr=False)
    zone_state: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64), repr=False)

    @property
    def stable(self) -> bool:
        return not self.collapsed

    def summary(self) -> dict:
        """JSON-ready scalars (nan as None is left to the writer)."""
        d = {k: v for k, v in asdict(self).items()
             if k not in ("t", "d_top", "acc", "acc_v", "kh", "kv", "polygons", "displacement",
                          "rotation", "setup_time", "disc_centres", "disc_radii",
                          "disc_displacement", "zone_xy", "zone_cells", "zone_state")}
        d["d_top_max"] = float(np.nanmax(self.d_top)) if self.d_top.size else math.nan
        d["A_peak"] = 0.6 * self.A_col if self.collapsed else math.nan
        d["r"] = d["A_peak"] / self.A_pseudo if self.collapsed else math.nan
        return d

    def history_csv(self, path) -> None:
        """``t, d_top, acc, acc_v, kh, kv`` to a CSV file (SI units)."""
        arr = np.column_stack([self.t, self.d_top, self.acc, self.acc_v, self.kh, self.kv])
        np.savetxt(path, arr, delimiter=",", fmt="%.9g",
                   header="t_s,d_top_m,acc_m_s2,acc_v_m_s2,kh,kv", comments="")


def _threshold(wall: RetainingWall, fraction: float | None) -> float:
    if fraction is None:
        fraction = 0.05 if wall.name.lower().startswith("mockup") else 0.20
    if not 0 < fraction < 10:
        raise CollapseError(f"threshold fraction must be positive, got {fraction!r}")
    return fraction * wall.height


def collapse_run(wall: RetainingWall, frequency: float, vertical: str = "none", *,
                 signal: str = "S2", A_rate: float | None = None, a_peak: float | None = None,
                 t_pseudo: float = 2.5, t_max: float | None = None, tail: float = 1.0,
                 threshold: float | None = None, xi: float | None = None,
                 stiffness_scale: float | None = None, safety: float = 0.2,
                 update_dt: float = 1e-3,
                 sample_dt: float = 0.01, motion_dt: float = 1e-3, thrust_scale: float = 1.0,
                 vertical_ratio: float = 0.5, assumptions=None, build: dict | None = None,
                 A_pseudo: float | None = None,
                 damping_frame: str = "base", backfill: str = "continuum",
                 backfill_options: dict | None = None,
                 progress: Callable | None = None, checkpoint=None,
                 checkpoint_every: float = 300.0,
                 subcycle: int | str | None = None) -> CollapseResult:
    """Run the DEM wall under S2 (or S1 with ``a_peak``) until collapse (module docstring).

    Parameters
    ----------
    wall : RetainingWall
        The wall (geometry, stones, backfill soil).
    frequency : float
        Frequency f of the harmonic input [Hz], > 0.
    vertical : str
        Vertical component: ``"none"``, ``"in_phase"`` or ``"opposition"`` (§4.3).
    signal : str
        ``"S2"`` (harmonic ramp ``A t sin(2 pi f t)``, Savalle et al. (2022), eq. 5) or
        ``"S1"`` (ramp up to ``a_peak``, down over twice as long).
    A_rate : float, optional
        Slope A of the envelope [m/s³]; default ``A_pseudo / t_pseudo``.
    a_peak : float, optional
        Peak of an S1 envelope [m/s²]; required for S1.
    t_pseudo : float
        Instant at which the S2 envelope reaches ``A_pseudo`` [s].
    t_max : float, optional
        End of an S2 run without collapse [s]; default ``6 t_pseudo`` (the envelope at six
        times ``A_pseudo``).
    tail : float
        Free time after an S1 signal [s].
    threshold : float, optional
        Collapse threshold on ``d_top`` as a fraction of the height H [-]; default 0.2
        (0.05 for the mock-ups, whose name starts with "mockup").
    xi : float, optional
        Mass-proportional damping, fraction of critical at ``frequency`` [-]; default
        :data:`XI_SAVALLE` (5 %, the effective damping of Savalle et al. (2022), §3.1, §4.1).
    stiffness_scale : float, optional
        Factor on the joint stiffness of Table 6 [-]; passed to
        :func:`~murus.retaining.dem_wall.build_wall`; default :data:`STIFFNESS_SCALE` of the
        backfill model (1e-2 on the continuum, 1e-3 otherwise).
    safety : float
        Time-step safety factor on ``min sqrt(m / k)`` [-], in (0, 1]; passed to
        ``build_wall``.
    update_dt : float
        Interval between updates of the thrust [s].
    sample_dt : float
        Interval between the samples of the histories [s].
    motion_dt : float
        Time step of the input record [s].
    thrust_scale : float
        Factor on the equivalent thrust [-]: 0 removes the backfill, 1 the EN 1998-5 Annex E
        thrust.
    vertical_ratio : float
        Amplitude of the vertical component over the horizontal one [-].
    assumptions : optional
        Assumptions of the thrust and of the pseudo-static resistance
        (:mod:`murus.retaining.pseudostatic`); default theirs.
    build : dict, optional
        Other keywords of :func:`~murus.retaining.dem_wall.build_wall`.
    A_pseudo : float, optional
        Pseudo-static resistance [m/s²]; given, its computation is skipped.
    damping_frame : str
        The velocities the mass-proportional damping acts on: ``"base"`` (relative to the
        base) or ``"absolute"`` (fixed frame, as UDEC/3DEC: "a force which is proportional to
        absolute velocity and mass", 3DEC 5.0 manual, Optional Features §2.2).
    backfill : str
        ``"continuum"`` (default, the reference: Mohr-Coulomb zones behind the wall, the model
        of Savalle et al. (2022), §2:
        :class:`~murus.retaining.continuum_backfill.ContinuumBackfill`; VALIDATION.md against
        its Tables 3, 7 and 8), ``"thrust"`` (the equivalent thrust on a wall with a
        backstop: fast, up to 57 % above the paper's A_col) or ``"discrete"`` (a disc
        backfill behind the wall, no backstop, no thrust:
        :class:`~murus.retaining.backfill.DiscreteBackfill`); with a backfill, ``wall_time``
        includes its generation and settling, ``options["backfill_options"]`` its summary.
    backfill_options : dict, optional
        Keywords of :class:`~murus.retaining.backfill.DiscreteBackfill` (``W``,
        ``boundary``, ``radius``, ...) or of
        :class:`~murus.retaining.continuum_backfill.ContinuumBackfill` (``W``, ``size``,
        ``boundary``, ...).
    progress : callable, optional
        ``progress(t, t_end, info)``, called before the settling (t = 0, info
        ``"settling"``) and after each chunk of the run (model time t [s], info ``"run"``),
        e.g. the ``update`` of a :func:`murus.progress.progress` block.
    checkpoint : path-like, optional
        A checkpoint file (``.npz``; the suffix is added when missing) that makes a long run
        survive its interruption (Ctrl-C, a killed process): the state of the run is written
        to it, atomically, every ``checkpoint_every`` seconds of wall time; a run started
        again with the same arguments and the same file resumes from it (the wall is built
        and settled again, then the state of the checkpoint replaces the settled one) and
        gives the uninterrupted run's result **bit for bit** (the run is cut only at steps
        where the uninterrupted run updates its loads and ends a chunk of steps, also after
        a change of the time step). Ctrl-C (main thread) is taken at the next such step,
        within a few seconds: the checkpoint is written there, then KeyboardInterrupt. The
        file is removed when the run ends (collapse, ``t_max`` or an error status). The
        file's folder must exist; a file that is not a checkpoint of this run is refused
        before any computation and left as it is. Continuum and thrust backfills; not the
        disc backfill (its relaxation has a state of its own).
    checkpoint_every : float
        Interval between two writes of the checkpoint [s of wall time], > 0.
    subcycle : int or "auto", optional
        Continuum backfill: step the zones once every ``subcycle`` steps of the blocks
        during the shaking (:meth:`murus.continuum.coupled.CoupledModel.set_subcycle`;
        ``"auto"``: as many as the zones' and the interface's stable steps allow); the
        blocks' contacts set the time step, and the zones, most of a step's cost, then
        take a step of their own size. Default: off (one step for all). Refused above
        ``stiffness_scale`` :data:`SUBCYCLE_MAX_SCALE` (0.1) with the corner rule
        ``corner_share="follow"``, where it is not validated (VALIDATION.md, *Subcycling*).

    Returns
    -------
    CollapseResult
        The run: collapse or not, ``t_col`` and ``A_col``, histories and final state.

    Raises
    ------
    CollapseError
        If an argument is out of range, the wall does not settle under gravity and the
        static thrust, the DEM run ends with an error status, or ``checkpoint`` is a file of
        another run (other arguments or another version of murus's code).
    KeyboardInterrupt
        If the run was interrupted (Ctrl-C caught by the DEM engine).

    References
    ----------
    Savalle et al. (2022), §4.2-4.4, eq. 5, Tables 6-8; EN 1998-5 (2004), Annex E (the
    thrust).
    """
    from murus.dem.engine import stop_when
    from murus.motion.synthetic import harmonic_ramp, two_ramp

    xi = XI_SAVALLE if xi is None else float(xi)
    if not (math.isfinite(xi) and 0 <= xi < 1):
        raise CollapseError(f"xi must be in [0, 1), got {xi!r}")
    from murus.retaining.dem_wall import EquivalentThrust, build_wall

    f = float(frequency)
    if not (f > 0 and math.isfinite(f)):
        raise CollapseError(f"frequency must be positive [Hz], got {frequency!r}")
    vmode = _vertical(vertical)
    sig = str(signal).upper()
    if sig not in ("S1", "S2"):
        raise CollapseError(f"signal must be 'S1' or 'S2', got {signal!r}")
    if A_pseudo is None:
        A_pseudo = pseudo_static_resistance(wall, vmode, assumptions, vertical_ratio)
    A = ramp_rate(A_pseudo, t_pseudo) if A_rate is None else float(A_rate)
    if not (A > 0 and math.isfinite(A)):
        raise CollapseError(f"A_rate must be positive [m/s3], got {A_rate!r}")
    thr = _threshold(wall, threshold)
    if damping_frame not in ("base", "absolute"):
        raise CollapseError(f"damping_frame must be 'base' or 'absolute', got "
                            f"{damping_frame!r}")
    vert = None if vmode == "none" else vmode
    if sig == "S2":
        t_end = 6.0 * t_pseudo if t_max is None else float(t_max)
        gm = harmonic_ramp(A, f, t_end, motion_dt, vert, vertical_ratio)
        ap = math.nan
    else:
        if a_peak is None or not a_peak > 0:
            raise CollapseError("an S1 run needs a_peak > 0 [m/s2]")
        ap = float(a_peak)
        gm = two_ramp(A, f, ap, motion_dt, vert, vertical_ratio)
        t_end = (gm.acc.size - 1) * gm.dt + float(tail)
    tt = np.arange(gm.acc.size) * gm.dt
    accv = gm.acc_v if gm.acc_v is not None else np.zeros_like(gm.acc)

    def acc_at(t):
        return (float(np.interp(t, tt, gm.acc, right=0.0)),
                float(np.interp(t, tt, accv, right=0.0)))

    bmode = str(backfill).strip().lower()
    if bmode not in ("thrust", "discrete", "continuum"):
        raise CollapseError(f"backfill must be 'thrust', 'discrete' or 'continuum', got "
                            f"{backfill!r}")
    if subcycle is not None:
        if bmode != "continuum":
            raise CollapseError(f"subcycle: only with the continuum backfill, not {bmode!r}")
        from murus.continuum.coupled import CoupledError, check_subcycle

        try:
            check_subcycle(subcycle)
        except CoupledError as e:
            raise CollapseError(str(e)) from None
    if checkpoint is not None:
        if bmode == "discrete":
            raise CollapseError("checkpoint: not available with the disc backfill (its "
                                "relaxation has a state of its own); use 'continuum' or "
                                "'thrust'")
        if not (checkpoint_every > 0 and math.isfinite(checkpoint_every)):
            raise CollapseError(f"checkpoint_every must be positive [s], got "
                                f"{checkpoint_every!r}")
    if stiffness_scale is None:
        stiffness_scale = STIFFNESS_SCALE[bmode]
    refused = subcycle_refused(subcycle, stiffness_scale,
                               (backfill_options or {}).get("corner_share",
                                                               DEFAULT_CORNER_SHARE))
    if refused:
        raise CollapseError(refused)
    ck_path = ck_run = digest = None
    if checkpoint is not None:  # checked before any computation
        ck_path = _checkpoint_path(checkpoint)
        digest = _run_digest(wall, dict(
            f=f, vertical=vmode, signal=sig, A=A, a_peak=ap if sig == "S1" else None,
            A_pseudo=float(A_pseudo), t_end=t_end, threshold=thr, xi=xi,
            stiffness_scale=stiffness_scale, safety=safety, update_dt=update_dt,
            sample_dt=sample_dt, motion_dt=motion_dt, thrust_scale=thrust_scale,
            vertical_ratio=vertical_ratio, assumptions=repr(assumptions), build=build,
            damping_frame=damping_frame, backfill=bmode, backfill_options=backfill_options,
            tail=tail, t_pseudo=t_pseudo, **({} if subcycle is None else
                                             {"subcycle": subcycle})))
        ck_run = _check_checkpoint(ck_path, digest)
    bf = None
    if bmode == "thrust":
        dw = build_wall(wall, stiffness_scale=stiffness_scale, safety=safety, **(build or {}))
        m = dw.model
        thrust = EquivalentThrust(dw, acc=acc_at, assumptions=assumptions, scale=thrust_scale)
        t0 = _time.perf_counter()
        if progress is not None:
            progress(0.0, t_end, "settling")
        st = m.settle(external=thrust)
        if st.interrupted:
            raise KeyboardInterrupt(f"{wall.name}: {st.message}")
        if not st.converged:
            raise CollapseError(f"{wall.name}: the DEM wall does not settle under gravity and "
                                f"the static thrust ({st.message})")
    else:
        if bmode == "continuum":
            from murus.retaining.continuum_backfill import ContinuumBackfill as Backfill
        else:
            from murus.retaining.backfill import DiscreteBackfill as Backfill

        t0 = _time.perf_counter()
        bf = Backfill(wall, **dict({"stiffness_scale": stiffness_scale},
                                   **(backfill_options or {})))
        discs = {"add_bodies": bf.add_to} if bmode == "discrete" else {}
        dw = build_wall(wall, stiffness_scale=stiffness_scale, safety=safety,
                        **dict(build or {}, backstop=False, **discs))
        m = dw.model
        thrust = EquivalentThrust(dw, acc=acc_at, assumptions=assumptions, scale=0.0)
        if progress is not None:
            progress(0.0, t_end, "settling")
        st = bf.settle(dw, external=thrust, **({} if subcycle is None else
                                               {"built": _subcycle_check(subcycle)}))
        if getattr(st, "interrupted", False):
            raise KeyboardInterrupt(f"{wall.name}: {st.message}")
        # (the disc backfill goes on with its dynamic relaxation when its settling stops short)
        if bmode == "continuum" and not st.converged:
            raise CollapseError(f"{wall.name}: the wall and its continuum backfill do not "
                                f"settle ({st.message})")
    if subcycle is not None:
        try:
            bf.coupled.set_subcycle(subcycle)
        except ValueError as e:
            raise CollapseError(str(e)) from None
    m.set_base_motion(gm)
    every = max(1, int(round(update_dt / m.dt)))
    external, ext_every = thrust, every
    if bf is not None and bmode == "discrete":
        external, ext_every = bf.external(thrust), min(every, bf.interval(m))

    def d_top(model):
        return dw.d_top()

    probes = {"d_top": d_top,
              "kh": lambda model: thrust.last[1], "kv": lambda model: thrust.last[2]}
    setup_time = _time.perf_counter() - t0
    report = None if progress is None else (lambda done, total: progress(m.time, t_end, "run"))
    run_kw = dict(t_end=t_end, xi=xi, freq=f, probes=probes,
                  every=max(1, int(round(sample_dt / m.dt))), stop=stop_when(d_top, ">", thr),
                  external=external, external_every=ext_every, damping_frame=damping_frame,
                  progress=report or False)
    before = 0.0
    if checkpoint is None:
        res = m.run(**run_kw)
    else:
        res, before = _run_checkpointed(m, run_kw, ck_path, float(checkpoint_every), digest,
                                        ck_run)
    wall_time = _time.perf_counter() - t0 + before
    t = res.t
    d = res["d_top"]
    collapsed = res.status == "stopped"
    t_col = A_col = math.nan
    if collapsed:
        i = int(np.argmax(d > thr))
        if i > 0 and d[i] > d[i - 1]:
            t_col = float(t[i - 1] + (thr - d[i - 1]) * (t[i] - t[i - 1]) / (d[i] - d[i - 1]))
        else:
            t_col = float(t[i])
        if sig == "S2":
            A_col = A * t_col
        else:
            tp = ap / A
            A_col = A * t_col if t_col <= tp else max(ap * (1 - (t_col - tp) / (2 * tp)), 0.0)
    elif res.status == "interrupted":  # Ctrl-C caught by the DEM engine: pass it on
        raise KeyboardInterrupt(f"{wall.name}: {res.message}")
    elif res.status not in ("completed",):
        raise CollapseError(f"{wall.name}: DEM run ended with status {res.status}: "
                            f"{res.message}")
    acc = np.interp(t, tt, gm.acc, right=0.0)
    acc_v = np.interp(t, tt, accv, right=0.0)
    disp = m.body_displacement() - m.body_displacement()[dw.foundation]
    bodies = m.body_of_polygon()
    # the polygons of the section (the container plate of an absorbing boundary, moved out of
    # reach, is left out) and the discs of a discrete backfill
    shown = np.ones(bodies.size, bool) if bmode != "discrete" or bf.absorbing is None else \
        bodies != bf.container
    polys = [q for q, k in zip(m.world_polygons(), shown, strict=True) if k]
    bodies = bodies[shown]
    dmag = np.hypot(disp[bodies, 0], disp[bodies, 1])
    centres, radii = m.discs()
    db = m.body_of_disc()
    ddisc = np.hypot(disp[db, 0], disp[db, 1])
    rot = m.body_rotation()
    mode = failure_mode(float(d[-1]) if d.size else 0.0, float(rot[dw.top]),
                        float(m.bref[dw.top, 1]))
    opts = dict(dw.options, xi=xi, update_dt=update_dt, sample_dt=sample_dt,
                motion_dt=motion_dt, thrust_scale=thrust_scale, t_pseudo=t_pseudo,
                threshold_fraction=thr / wall.height, vertical_ratio=vertical_ratio,
                settle_steps=st.steps, damping_frame=damping_frame)
    opts["backfill"] = bmode
    if bf is not None:
        opts["backfill_options"] = bf.summary()
    zones = {}
    if bmode == "continuum":
        zm = bf.zones
        zones = dict(zone_xy=zm.gxy.copy(), zone_cells=zm.zg.copy(),
                     zone_state=zm.plastic_state().copy())
    return CollapseResult(wall.name, f, vmode, sig, A, float(A_pseudo), ap, thr, wall.height,
                          collapsed, t_col, A_col, float(m.time), t, d, acc, acc_v,
                          res["kh"], res["kv"], polys, dmag, wall_time, res.steps, res.dt,
                          res.status, opts, rot[bodies], mode, setup_time, centres, radii,
                          ddisc, **zones)


def plot_collapse(polygons, displacement, discs=None, disc_displacement=None, title="",
                  ax=None, zones=None):
    """The stones (and the discs of a discrete backfill) at the end of a collapse run, coloured
    by their displacement relative to the base [m], to scale: ``polygons`` (k, 2) vertex
    arrays [m], ``discs`` ``(centres (n, 2), radii (n,))`` [m]; ``zones`` ``(xy, cells,
    state)`` of a continuum backfill, drawn deformed and coloured by their plastic state
    (:func:`murus.continuum.plots.plot_plastic_state`). Returns the Axes."""
    from murus.dem.plots import plot_blocks

    if zones is not None and len(zones[1]):
        from murus.continuum.plots import plot_plastic_state

        if ax is None:
            import matplotlib.pyplot as plt

            _, ax = plt.subplots(figsize=(10.0, 3.8), layout="constrained")
        ax = plot_plastic_state(zones[0], zones[1], zones[2], ax=ax)
        ax.get_legend().set_title("backfill zones\n(plastic during the run)")

    values = np.asarray(displacement, float)
    if discs is not None and len(discs[1]):
        values = np.concatenate([values, np.asarray(disc_displacement, float)])
    else:
        discs = None
    ax = plot_blocks(polygons, discs=discs, values=values,
                     label="displacement relative to the base [m]", ax=ax)
    if title:
        ax.set_title(title, fontsize=9)
    return ax


#: Steps of a segment of a checkpointed run, at least: the run pauses at the first step after
#: them where it updates its loads, checks the clock and Ctrl-C, and goes on.
_SEGMENT = 20000

#: The code a collapse run executes (sub-packages and modules of murus, without the command
#: lines, figures and case files: murus._source.NOT_ENGINE): a checkpoint written by another
#: version of it is refused.
_CODE = ("__init__.py", "_jit.py", "threads.py", "results.py", "dem", "continuum", "retaining",
         "motion", "eurocode")

_CODE_KEY: str | None = None


def _code_key() -> str:
    """:func:`murus._source.source_key` of :data:`_CODE` (blind to docstrings and comments)."""
    global _CODE_KEY
    if _CODE_KEY is None:
        from murus._source import source_key

        _CODE_KEY = source_key(*_CODE)
    return _CODE_KEY


def _subcycle_check(subcycle):
    """A check of ``subcycle`` against the built model's limit, before its settling."""
    from murus.continuum.coupled import CoupledError, check_subcycle

    def check(bf):
        try:
            check_subcycle(subcycle, bf.coupled.subcycle_limit())
        except CoupledError as e:
            raise CollapseError(str(e)) from None
    return check


def wall_dict(wall: RetainingWall) -> dict:
    """The wall's fields and name, for a digest."""
    return dict(asdict(wall), name=wall.name)


def digest(obj) -> str:
    """20 hex digits of the SHA-256 of ``obj`` as sorted JSON (the identity of a run or a
    study's case)."""
    import hashlib
    import json

    return hashlib.sha256(json.dumps(obj, sort_keys=True, default=str).encode()).hexdigest()[:20]


def _run_digest(wall: RetainingWall, args: dict) -> str:
    """The identity of a collapse run: the wall, the arguments, murus's code and the versions
    of numpy and numba (their arithmetic)."""
    import numba

    import murus

    return digest({"wall": wall_dict(wall), "args": args, "code": _code_key(),
                   "version": murus.__version__, "numpy": np.__version__,
                   "numba": numba.__version__, "format": 1})


def _checkpoint_path(checkpoint) -> Path:
    p = Path(checkpoint)
    return p if p.name.endswith(".npz") else p.with_name(p.name + ".npz")


def _check_checkpoint(path: Path, digest: str) -> dict | None:
    """Before any computation: the folder of ``path`` exists and is writable; a file there is
    a checkpoint of this run (its bookkeeping returned) or a CollapseError (the file is left
    as it is)."""
    import json
    import os

    folder = path.parent
    if not folder.is_dir():
        raise CollapseError(f"checkpoint {path}: the folder {folder} does not exist")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise CollapseError(f"checkpoint {path}: the folder {folder} is not writable")
    if not path.exists():
        return None
    try:
        with np.load(path, allow_pickle=False) as z:
            run = json.loads(str(z["run"]))
        if not isinstance(run, dict):
            raise ValueError("no bookkeeping")
        for k in ("left", "steps", "updates", "wall"):
            float(run[k])
    except Exception as e:  # noqa: BLE001 - any unreadable file is "not a checkpoint"
        msg = " ".join(str(e).split()) or type(e).__name__
        raise CollapseError(f"{path}: not a checkpoint of a collapse run ({msg}); remove it "
                            f"or choose another file") from None
    if run.get("digest") != digest:
        raise CollapseError(f"{path}: a checkpoint of another run (other arguments or another "
                            f"version of murus, numpy or numba): remove it or choose another "
                            f"file")
    return run


def _save_checkpoint(m, path, digest: str, run: dict) -> None:
    """The model's state (:meth:`murus.continuum.CoupledModel.save` or
    :meth:`murus.dem.Model.save`) and the run's bookkeeping, in one file written atomically."""
    import io
    import json

    from murus.outputs import atomic_write

    buf = io.BytesIO()
    (m.__dict__.get("coupled") or m).save(buf)
    body = np.frombuffer(buf.getvalue(), np.uint8)
    info = np.array(json.dumps(dict(run, digest=digest)))
    atomic_write(path, lambda tmp: np.savez(tmp, model=body, run=info))


def _restore_checkpoint(m, path) -> None:
    """Replace the model's state by the checkpoint's (checked by :func:`_check_checkpoint`)."""
    import io
    import json

    with np.load(path, allow_pickle=False) as z:
        body = z["model"].tobytes()
    cp = m.__dict__.get("coupled")
    if cp is not None:
        cp.restore(io.BytesIO(body))
    else:
        with np.load(io.BytesIO(body), allow_pickle=False) as z:
            m.restore_arrays(z, json.loads(str(z["meta"])))


def _run_checkpointed(m, kw: dict, path: Path, interval: float, digest: str,
                      run: dict | None):
    """:func:`murus.dem.engine.run` with the arguments ``kw``, paused every
    :data:`_SEGMENT` steps or more at a step where it updates its loads (``pause_every``): the
    uninterrupted run's chunks of steps, so the same result bit for bit. At a pause, a
    checkpoint is written when ``interval`` seconds passed since the last one, and when Ctrl-C
    was pressed (then KeyboardInterrupt). ``run``: the bookkeeping of the checkpoint to resume
    from (its state restored into ``m`` here), or None. Returns the run's result (its steps,
    wall time and contact updates those of the whole run) and the wall time spent before the
    checkpoint it resumed from [s]."""
    from murus.dem.engine import RunResult, _SigInt

    left = int(round((kw["t_end"] - m.time) / m.dt))
    steps = updates = 0
    before = 0.0
    if run is not None:
        _restore_checkpoint(m, path)
        left, steps, updates, before = (int(run["left"]), int(run["steps"]),
                                        int(run["updates"]), float(run["wall"]))
    t0 = last = _time.perf_counter()
    # Ctrl-C as a flag (main thread; unless a caller set a handler of its own), taken at the
    # next pause: the engine's own catch, which would stop the run between two pauses, stays
    # out of the way (it defers to a handler set by a caller)
    with _SigInt() as ctrl:
        while True:
            r = m.run(**dict(kw, t_end=m.time + left * m.dt, pause_every=_SEGMENT))
            steps += r.steps
            updates += r.contact_updates
            left -= r.steps
            if r.status != "paused":
                break
            now = _time.perf_counter()
            if ctrl.hit or now - last >= interval:
                _save_checkpoint(m, path, digest, {"left": left, "steps": steps,
                                                   "updates": updates,
                                                   "wall": before + now - t0})
                last = now
            if ctrl.hit:
                raise KeyboardInterrupt(f"interrupted at t = {m.time:.6g} s (checkpoint "
                                        f"{path})")
    if r.status != "interrupted":  # the run ended: its checkpoint is of no more use
        path.unlink(missing_ok=True)
    res = RunResult(t=r.t, values=r.values, status=r.status, message=r.message, steps=steps,
                    wall=before + _time.perf_counter() - t0, contact_updates=updates, dt=r.dt)
    return res, before


def failure_mode(d_top: float, rotation: float, z_top: float, share: float = 0.5) -> str:
    """``"T"`` (toppling) or ``"S"`` (sliding), the mechanism labels of Savalle et al. (2022), Table
    3, from the top stone's displacement ``d_top`` [m] (out of the slope positive), its rotation
    [rad] (counter-clockwise positive, i.e. tipping out of the slope) and the height of its
    centroid above the toe ``z_top`` [m]: toppling when the rotation accounts for at least
    ``share`` of d_top (``rotation z_top >= share d_top``; a rigid toppling about a joint at
    height ``z_j`` gives ``rotation z_top = d_top z_top / (z_top - z_j) >= d_top``, a pure
    sliding gives 0). ``""`` when ``d_top <= 0``."""
    if not d_top > 0:
        return ""
    return "T" if rotation * z_top >= share * d_top else "S"


def peak_ratio_check(wall: RetainingWall, frequency: float, A_col: float,
                     ratios: Sequence[float] = (0.6, 0.7), vertical: str = "none",
                     executor: Executor | None = None, **kw) -> dict[float, CollapseResult]:
    """S1 runs with ``A_peak = ratio A_col`` and the S2 slope (Savalle et al. (2022), §4.2, Figure
    14: stable at 0.6, collapsed at 0.7). Returns ``{ratio: CollapseResult}`` (``.stable``).

    Parameters
    ----------
    wall : RetainingWall
        The wall.
    frequency : float
        [Hz].
    A_col : float
        [m/s²].
    ratios : sequence of float
        ``A_peak / A_col`` [-].
    vertical : str
        Vertical component.
    executor : concurrent.futures.Executor, optional
        Where the runs go.
    **kw
        Keywords of :func:`collapse_run`.

    Returns
    -------
    dict
        ``{ratio: CollapseResult}``.
    """
    if not (A_col > 0 and math.isfinite(A_col)):
        raise CollapseError(f"A_col must be positive, got {A_col!r}")
    jobs = [(wall, frequency, vertical, dict(kw, signal="S1", a_peak=r * A_col))
            for r in ratios]
    results = _map(executor, jobs)
    return dict(zip(ratios, results, strict=True))


def _case(job):
    wall, f, v, kw = job
    return collapse_run(wall, f, v, **kw)


def _map(executor: Executor | None, jobs):
    if executor is None:
        return [_case(j) for j in jobs]
    futs = [executor.submit(_case, j) for j in jobs]
    return [fu.result() for fu in futs]


#: Factors on the time-step safety of the runs of a collapse ensemble (the first is the nominal
#: run, the one a single :func:`collapse_run` makes): time steps 100, 95, 90, 85 and 80 % of it.
DT_FACTORS = (1.0, 0.95, 0.90, 0.85, 0.80)


@dataclass
class CollapseEnsemble:
    """The same collapse run with perturbed numerics (issue 18, item 6): a single run of a
    chaotic collapse is sensitive to the time step (DSRW1 at 3 Hz on the equivalent thrust
    moved by 6 % with a 10 % smaller step), so a value worth quoting is the median of several
    runs with its range.

    Attributes
    ----------
    results : list of CollapseResult
        The runs, in the order of ``factors``; ``results[0]`` is the nominal run.
    factors : tuple of float
        Factor on the time-step safety of each run [-].
    """

    results: list[CollapseResult]
    factors: tuple

    @property
    def A_col(self) -> np.ndarray:
        """A_col of each run [m/s²]; ``inf`` for a run that did not collapse."""
        return np.array([r.A_col if r.collapsed else math.inf for r in self.results])

    @property
    def median(self) -> float:
        """Median A_col [m/s²] (``inf`` when half of the runs or more did not collapse)."""
        return float(np.median(self.A_col))

    @property
    def range(self) -> tuple[float, float]:
        """Smallest and largest A_col [m/s²]."""
        a = self.A_col
        return float(a.min()), float(a.max())

    @property
    def nominal(self) -> CollapseResult:
        return self.results[0]

    def summary(self) -> dict:
        """JSON-ready: the nominal run's summary, with ``A_col_median``, ``A_col_min``,
        ``A_col_max``, the A_col, t_col, mode, time step and wall time of each run."""
        d = self.nominal.summary()
        lo, hi = self.range
        med = self.median
        d.update(A_col_median=med, A_col_min=lo, A_col_max=hi,
                 r_median=0.6 * med / self.nominal.A_pseudo,
                 runs=[{"dt_factor": f, "A_col": r.A_col if r.collapsed else None,
                        "t_col": r.t_col if r.collapsed else None, "mode": r.mode,
                        "dt": r.dt, "steps": r.steps, "wall_time": r.wall_time}
                       for f, r in zip(self.factors, self.results, strict=True)])
        return d


def collapse_ensemble(wall: RetainingWall, frequency: float, vertical: str = "none", *,
                      runs: int = 5, executor: Executor | str | None = None,
                      workers: int | None = None, **kw) -> CollapseEnsemble:
    """:func:`collapse_run` ``runs`` times with the time step perturbed (its safety factor
    times :data:`DT_FACTORS`): the median A_col and its range (issue 18, item 6).

    Parameters
    ----------
    wall : RetainingWall
        The wall.
    frequency : float
        [Hz].
    vertical : str
        Vertical component.
    runs : int
        Number of runs, 1 to ``len(DT_FACTORS)``; the first is the nominal run.
    executor : concurrent.futures.Executor or str, optional
        Where the runs go: default one after the other here; an Executor; or ``"serial"``,
        ``"process"`` or ``"dask"`` (:func:`murus.studies.sweep.run_tasks`, which stops
        within seconds on Ctrl-C).
    workers : int, optional
        Workers of a ``"process"`` or ``"dask"`` executor.
    **kw
        Keywords of :func:`collapse_run` (``safety`` is the nominal one; ``progress`` reports
        each run here, or the runs done on an executor given by name).

    Returns
    -------
    CollapseEnsemble

    Raises
    ------
    CollapseError
        If ``runs`` is out of range, or as :func:`collapse_run`.
    """
    n = int(runs)
    if not 1 <= n <= len(DT_FACTORS) or n != runs:
        raise CollapseError(f"runs must be an integer from 1 to {len(DT_FACTORS)}, got "
                            f"{runs!r}")
    safety = float(kw.pop("safety", 0.2))
    prog = kw.pop("progress", None)
    factors = DT_FACTORS[:n]
    jobs = [(wall, frequency, vertical, dict(kw, safety=safety * f)) for f in factors]
    if isinstance(executor, str):
        from murus.studies.sweep import run_tasks

        got: dict[int, CollapseResult] = {}
        fails = run_tasks(_case, list(enumerate(jobs)), executor, workers=workers,
                          retries=0, on_result=lambda i, r: got.__setitem__(i, r),
                          progress=None if prog is None else
                          (lambda done, total, _f: prog(done, total, "runs")))
        if fails:
            i, f = min(fails.items())
            raise CollapseError(f"{wall.name}: run {i + 1} of the ensemble failed: "
                                f"{f['error']}")
        results = [got[i] for i in range(n)]
    elif executor is None and prog is not None:
        results = []
        for i, j in enumerate(jobs):
            j[3]["progress"] = (lambda t, te, info, i=i: prog(t, te, f"run {i + 1}/{n} {info}"))
            results.append(_case(j))
    else:
        results = _map(executor, jobs)
    return CollapseEnsemble(results, factors)


@dataclass
class BehaviourTable:
    """Savalle et al. (2022), Tables 7 and 8 layout: one row per case (wall, frequency, vertical)
    with ``t_col`` [s], ``A_col``, ``A_peak = ratio A_col``, ``A_pseudo`` [m/s²], ``r`` and the run
    time; ``results`` the runs; ``peak_checks`` optional S1 checks per case.

    Attributes
    ----------
    rows : list of dict
    results : list of CollapseResult
    peak_ratio : float
        [-].
    """

    rows: list[dict]
    results: list[CollapseResult] = field(default_factory=list, repr=False)
    peak_ratio: float = 0.6

    COLUMNS = ("wall", "frequency_Hz", "vertical", "t_col_s", "A_col_m_s2", "A_peak_m_s2",
               "A_pseudo_m_s2", "r", "collapsed", "wall_time_s", "seed_A_col_m_s2", "seed_r")

    def to_csv(self, path) -> None:
        import csv

        with open(path, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(self.COLUMNS)
            for row in self.rows:
                w.writerow(["" if (isinstance(row[c], float) and not math.isfinite(row[c]))
                            else (f"{row[c]:.6g}" if isinstance(row[c], float) else row[c])
                            for c in self.COLUMNS])

    def to_markdown(self) -> str:
        """Tables 7 and 8 in one: a column per case."""
        def fmt(v, nd=2):
            if isinstance(v, float):
                return "-" if not math.isfinite(v) else f"{v:.{nd}f}"
            return str(v)

        heads = [f"{r['wall']} {r['frequency_Hz']:g} Hz" for r in self.rows]
        lines = ["| | " + " | ".join(heads) + " |", "|---" * (len(heads) + 1) + "|"]
        spec = [("Vertical acceleration", "vertical", None),
                ("t_col (s)", "t_col_s", 2), ("A_col (m/s²)", "A_col_m_s2", 2),
                (f"A_peak = {self.peak_ratio:g} A_col (m/s²)", "A_peak_m_s2", 2),
                ("A_pseudo (m/s²)", "A_pseudo_m_s2", 2), ("r = A_peak/A_pseudo", "r", 2),
                ("seed A_col (m/s²)", "seed_A_col_m_s2", 2), ("seed r", "seed_r", 2),
                ("run time (s)", "wall_time_s", 1)]
        for label, key, nd in spec:
            vals = [(r[key] if r[key] != "none" else "-") if nd is None else fmt(r[key], nd)
                    for r in self.rows]
            lines.append(f"| {label} | " + " | ".join(vals) + " |")
        return "\n".join(lines) + "\n"


def behaviour_factor(wall: RetainingWall, freqs: Sequence[float] = (3.0, 5.0, 10.0),
                     kv_modes: Sequence[str] = ("none",), executor: Executor | None = None,
                     peak_ratio: float = 0.6, **kw) -> BehaviourTable:
    """S2 collapse runs of ``wall`` for every frequency and vertical mode (through
    ``executor``, default serial) and the behaviour factor ``r = peak_ratio A_col / A_pseudo``
    (Savalle et al. (2022), Tables 7-8). ``kw`` go to :func:`collapse_run`.

    Parameters
    ----------
    wall : RetainingWall
        The wall.
    freqs : sequence of float
        Frequencies [Hz].
    kv_modes : sequence of str
        ``"none"``, ``"in_phase"``, ``"opposition"``.
    executor : concurrent.futures.Executor, optional
        Where the runs go (default serial).
    peak_ratio : float
        ``A_peak / A_col`` [-].
    **kw
        Keywords of :func:`collapse_run`.

    Returns
    -------
    BehaviourTable

    References
    ----------
    Savalle et al. (2022), §4.2-4.4, Tables 7 and 8.
    """
    freqs = [float(f) for f in freqs]
    modes = [_vertical(v) for v in kv_modes]
    if not freqs or not modes:
        raise CollapseError("give at least one frequency and one vertical mode")
    cases = [(f, v) for v in modes for f in freqs]
    # A_pseudo once per vertical mode
    aps = {v: pseudo_static_resistance(wall, v, kw.get("assumptions"),
                                       kw.get("vertical_ratio", 0.5)) for v in modes}
    jobs = [(wall, f, v, dict(kw, A_pseudo=aps[v])) for f, v in cases]
    results = _map(executor, jobs)
    rows = []
    for (f, v), r in zip(cases, results, strict=True):
        A_peak = peak_ratio * r.A_col if r.collapsed else math.nan
        seed = SEED_TABLE7.get((f, v)) if wall.name == "DSRW1" else None
        rows.append({"wall": wall.name, "frequency_Hz": f, "vertical": v,
                     "t_col_s": r.t_col, "A_col_m_s2": r.A_col, "A_peak_m_s2": A_peak,
                     "A_pseudo_m_s2": r.A_pseudo, "r": A_peak / r.A_pseudo,
                     "collapsed": r.collapsed, "wall_time_s": r.wall_time,
                     "seed_A_col_m_s2": seed[1] if seed else math.nan,
                     "seed_r": seed[3] if seed else math.nan})
    return BehaviourTable(rows, results, peak_ratio)

"""``murus retaining`` commands: pseudo-static resistance and geometry of dry-stone retaining walls.

Thin layer over :mod:`murus.retaining` (Savalle et al. (2022), §4.4). The wall is a preset
(``DSRW1`` ... ``DSRW4``, ``C3s`` of Savalle et al. (2022), Table 5, or ``mockup-<H/B>`` for the
scaled-down walls of its §3). Every open assumption of the analytical tool of the paper is an option
with the default of
:class:`murus.retaining.pseudostatic.Assumptions`. Bad input exits with code 2 and a one-line
``error:`` message on stderr. The library is imported inside the commands (no numba, no
matplotlib), so that ``murus --help`` stays fast.
"""

from __future__ import annotations

import math
from pathlib import Path

import typer

from murus.cliutil import dumps, guard
from murus.cliutil import fail as _fail
from murus.outputs import OutputError
from murus.studies.cli import (
    DASK_OPTION,
    EXECUTOR_OPTION,
    SCHEDULER_OPTION,
    SERIAL_OPTION,
    WORKERS_OPTION,
)

app = typer.Typer(
    rich_markup_mode=None,
    name="retaining",
    help="Dry-stone retaining walls (Savalle et al. (2022)): geometry, pseudo-static resistance "
         "A_pseudo, "
         "dynamic collapse A_col, behaviour factor r, backfill calibration, several sections.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)

_PRESET = typer.Option(..., "--preset", help="DSRW1..DSRW4, C3s (Savalle et al. (2022), Table 5) "
                                             "or "
                       "mockup-<H/B> (Savalle et al. (2022), §3), e.g. mockup-2.7.")
_BASE = typer.Option(None, "--base", help="Base joint: 'inclined' (parallel to the beds, "
                     "default) or 'horizontal'.")
_JSON = typer.Option(False, "--json", help="Print JSON instead of text.")


def _errors():
    from murus.eurocode.ec8_5 import EC85Error
    from murus.retaining.geometry import GeometryError
    from murus.retaining.pseudostatic import PseudoStaticError

    return (GeometryError, PseudoStaticError, EC85Error, ValueError)


def _json(obj) -> None:
    typer.echo(dumps(obj))


def _wall(name: str, base: str | None):
    from murus.retaining.geometry import preset

    return preset(name, **({"base": base} if base is not None else {}))


@app.command("pseudo-static")
def pseudo_static(
    preset_name: str = _PRESET,
    kv_ratio: float = typer.Option(0.0, "--kv-ratio", help="kv = +-ratio kh (0.5: EN 1998-5 "
                                   "(7.2)); both signs are checked, the worse is reported."),
    delta: float | None = typer.Option(None, "--delta", help="Wall friction delta [deg] "
                                       "(overrides --delta-ratio)."),
    delta_ratio: float | None = typer.Option(None, "--delta-ratio", help="delta = ratio x "
                                             "phi (default 2/3)."),
    interface_delta: bool = typer.Option(False, "--interface-delta", help="delta = the "
                                         "wall-backfill interface friction of the preset "
                                         "(37.7 deg in Savalle et al. (2022), Table 6)."),
    dynamic_point: float = typer.Option(1.0 / 3.0, "--dynamic-point", help="Height of the "
                                        "dynamic increment / back face height: 1/3 (EN 1998-5 "
                                        "§7.3.2.3(5), default) or 0.5 (§7.3.2.3(4))."),
    static_point: float = typer.Option(1.0 / 3.0, "--static-point",
                                       help="Height of the static thrust / back face height."),
    thrust: str = typer.Option("mononobe-okabe", "--thrust", help="'mononobe-okabe' "
                               "(EN 1998-5 Annex E) or 'wedge' (trial-wedge search)."),
    back_height: str = typer.Option("back", "--back-height", help="'back': the thrust acts "
                                    "down to where the joint meets the back face; 'front': "
                                    "down to the level of its front edge."),
    base: str | None = _BASE,
    as_json: bool = _JSON,
) -> None:
    """Pseudo-static resistance A_pseudo = kh g (Savalle et al. (2022), §4.4, Table 8): the smallest
    kh at which the wall above some bed joint slides or overturns."""
    from murus import G
    from murus.retaining.pseudostatic import Assumptions, critical_acceleration

    try:
        from murus.config import check_physical

        check_physical("kv_ratio", kv_ratio, "--kv-ratio")
        if interface_delta and (delta is not None or delta_ratio is not None):
            raise ValueError("give --interface-delta, --delta or --delta-ratio, not several")
        kw = {}
        if interface_delta:
            kw["delta_ratio"] = None
        elif delta_ratio is not None:
            kw["delta_ratio"] = delta_ratio
        asm = Assumptions(delta_deg=delta, static_point=static_point,
                          dynamic_point=dynamic_point, thrust=thrust, back_height=back_height,
                          **kw)
        wall = _wall(preset_name, base)
        res = critical_acceleration(wall, kv_ratio, asm)
        delta_used = math.degrees(asm.delta(wall))
    except _errors() as exc:
        _fail(exc)
    if as_json:
        d = res.summary()
        d["delta_deg_used"] = delta_used
        d["g"] = G
        _json(d)
        return
    sign = {1: "upwards", -1: "downwards"}
    typer.echo(f"{wall.name}: A_pseudo = {res.A_pseudo:.4f} m/s2 (kh = {res.kh:.5f}, "
               f"kv = {res.kv:+.5f})")
    typer.echo(f"  governing: joint {res.joint} (front edge at {res.joint_height:.3f} m), "
               f"{res.mode}")
    for s, (kh, j, mode) in res.by_sign.items():
        if kv_ratio > 0:
            typer.echo(f"  kv {sign[s]:<9}: A_pseudo = {kh * G:.4f} m/s2, joint {j}, {mode}")
    typer.echo(f"  delta = {delta_used:.3f} deg, static at {static_point:.3g} h, dynamic "
               f"increment at {dynamic_point:.3g} h, thrust: {thrust}, base: {wall.base}, "
               f"static FS = {res.fs_static:.3f}")


@app.command()
def geometry(
    preset_name: str = _PRESET,
    base: str | None = _BASE,
    as_json: bool = _JSON,
) -> None:
    """Cross-section of a preset: polygon, area, weight, bed joints."""
    try:
        wall = _wall(preset_name, base)
    except _errors() as exc:
        _fail(exc)
    joints = [{"index": j.index, "front": list(j.front), "back": list(j.back),
               "angle_deg": math.degrees(j.angle)} for j in wall.joints]
    if as_json:
        d = wall.summary()
        d["polygon"] = [list(p) for p in wall.polygon]
        d["centroid"] = list(wall.centroid)
        d["joints"] = joints
        _json(d)
        return
    s = wall.summary()
    typer.echo(f"{wall.name}: H = {s['H_m']:g} m, B = {s['B_m']:g} m, b = {s['b_m']:.4g} m, "
               f"batter {100 * s['external_batter']:g} % (external) / "
               f"{100 * s['internal_batter']:g} % (internal), beds {s['bed_inclination_deg']:g} "
               f"deg, backfill slope {s['backfill_slope_deg']:g} deg, base {wall.base}")
    typer.echo("  polygon [m]: " + ", ".join(f"({x:.4f}, {z:.4f})" for x, z in wall.polygon))
    typer.echo(f"  area = {wall.area:.5f} m2, centroid = ({wall.centroid[0]:.4f}, "
               f"{wall.centroid[1]:.4f}) m, weight = {wall.weight:.1f} N/m")
    typer.echo(f"  {len(joints)} bed joints; front edges at z = "
               + ", ".join(f"{j.height:.3f}" for j in wall.joints) + " m")


def _dem_wall(name: str, base: str | None, stone_height: float | None):
    kw = {}
    if base is not None:
        kw["base"] = base
    if stone_height is not None:
        kw["stone_height"] = stone_height
    from murus.retaining.geometry import preset

    return preset(name, **kw)


def _collapse_errors():
    from murus.dem.materials import JointError
    from murus.dem.model import ModelError
    from murus.retaining.collapse import CollapseError
    from murus.retaining.dem_wall import DemWallError

    return (*_errors(), CollapseError, DemWallError, ModelError, JointError)


def _prepare_out(out, names=None) -> None:
    """Refuse a bad ``--out`` folder before any computation (:func:`murus.outputs.check_dir`;
    an OutputError is a ValueError)."""
    from murus.outputs import check_dir

    check_dir(out, names)


def _staged(out, names=None):
    from murus.outputs import command_line, staged_dir

    return staged_dir(out, command_line(), names)


_COLLAPSE_FILES = ["d_top.csv", "summary.json", "collapse.png"]
_BIAXIAL_FILES = ["biaxial.png", "biaxial.svg", "biaxial.csv", "biaxial.json"]


_STONE_H = typer.Option(None, "--stone-height", help="Course height [m] (needed for the "
                        "mock-ups, whose courses Savalle et al. (2022) does not give).")
_STIFF = typer.Option(None, "--stiffness-scale", help="Multiplies the joint stiffness of "
                      "Savalle et al. (2022), Table 6 (2.8e12 Pa/m); the time step grows as its "
                      "inverse square root. Default 1e-2 with --backfill continuum (within 0.3 "
                      "% of the printed stiffness's A_col), 1e-3 otherwise.")
_XI = typer.Option(None, "--xi", help="Mass-proportional damping, fraction of critical at "
                   "the input frequency (default 0.05: Savalle et al. (2022), §3.1 and §4.1, "
                   "5 %, which its Tables 1 and 6 print as the 10 % given to UDEC).")
_THR = typer.Option(None, "--threshold", help="Collapse when d_top exceeds this fraction of H "
                    "(default 0.2; 0.05 for mock-ups).")
_TMAX = typer.Option(None, "--t-max", help="End of an S2 run without collapse [s] (default "
                     "15 s: the envelope at 6 A_pseudo).")


@app.command()
def collapse(
    preset_name: str = _PRESET,
    frequency: float = typer.Option(5.0, "--frequency", help="Input frequency [Hz]."),
    vertical: str = typer.Option("none", "--vertical", help="Vertical component: none, "
                                 "in_phase or opposition (half the horizontal amplitude)."),
    out: str = typer.Option(..., "--out", help="Output directory."),
    check_peak: bool = typer.Option(False, "--check-peak", help="Also run S1 at 0.6 and 0.7 "
                                    "A_col (Savalle et al. (2022), Figure 14)."),
    stone_height: float | None = _STONE_H,
    stiffness_scale: float | None = _STIFF,
    xi: float | None = _XI,
    threshold: float | None = _THR,
    t_max: float | None = _TMAX,
    base: str | None = _BASE,
    backfill: str = typer.Option("continuum", "--backfill", help="'continuum': Mohr-Coulomb "
                                 "zones behind the wall, the paper's model and the reference "
                                 "(minutes); 'thrust': the equivalent EN 1998-5 thrust "
                                 "on the back face (half a minute; A_col up to 57 % above the "
                                 "paper's); 'discrete': a disc backfill (minutes; research). "
                                 "docs/retaining_backfills.md says when to use which."),
    width: float | None = typer.Option(None, "--width", help="With --backfill discrete or "
                                       "continuum: backfill width W [m] (default 2 H: 5 m "
                                       "for the Savalle et al. (2022) walls)."),
    boundary: str | None = typer.Option(None, "--boundary", help="With --backfill discrete: "
                                        "lateral boundary, 'absorbing' (viscous; default "
                                        "at full scale, the paper's free field) or 'container' "
                                        "(a rigid plate moving with the base; default for the "
                                        "mock-ups, tested in a box). With --backfill "
                                        "continuum: 'free-field' (default), 'fixed' or "
                                        "'quiet' (dashpots relative to the base)."),
    zone_size: float | None = typer.Option(None, "--zone-size", help="With --backfill "
                                           "continuum: target zone size [m] (default H / 12)."),
    radius: float | None = typer.Option(None, "--radius", help="With --backfill discrete: "
                                        "mean disc radius [m] (default 0.016 H)."),
    damping_frame: str = typer.Option("base", "--damping-frame", help="Velocities the "
                                      "mass-proportional damping acts on: 'base' (relative to "
                                      "the base) or 'absolute' (as UDEC)."),
    runs: int = typer.Option(1, "--runs", help="Number of runs with the time step perturbed "
                             "(100, 95, 90, 85, 80 % of the nominal one; at most 5): "
                             "summary.json adds the median A_col and its range; the files "
                             "of the nominal run are written."),
    workers: int = typer.Option(1, "--workers", help="With --runs: processes running them "
                                "(one numba thread each)."),
    checkpoint: str | None = typer.Option(None, "--checkpoint", help="A file (.npz) where the "
                                          "run's state is saved every --checkpoint-every "
                                          "seconds: the same command run again after an "
                                          "interruption resumes from it and gives the "
                                          "uninterrupted result bit for bit; removed when the "
                                          "run ends. Continuum or thrust backfill, one run."),
    checkpoint_every: float = typer.Option(300.0, "--checkpoint-every", help="With "
                                           "--checkpoint: seconds of wall time between two "
                                           "saves."),
    subcycle: str | None = typer.Option(None, "--subcycle", help="With --backfill "
                                        "continuum: step the zones once every N steps of the "
                                        "stones ('auto': as many as their stable step allows; "
                                        "about 3 times faster for the mock-ups; "
                                        "VALIDATION.md gives its effect on A_col; refused "
                                        "above --stiffness-scale 0.1, where it is not "
                                        "validated yet)."),
    corner_share: str | None = typer.Option(None, "--corner-share", help="With --backfill "
                                            "continuum: how a loaded stone corner's share "
                                            "of the backfill's face follows the "
                                            "interface's coverage rule, 'shrink' (default: "
                                            "down only, no energy given to a rocking "
                                            "corner) or 'follow' (up and down, the rule "
                                            "of earlier versions; VALIDATION.md, The "
                                            "corner rule)."),
) -> None:
    """S2 collapse run of the DEM wall on the continuum backfill of the paper (the default),
    the equivalent thrust or a disc backfill (Savalle et al. (2022), §4.2): writes d_top.csv
    (history), summary.json (A_col, t_col, A_pseudo, r) and collapse.png (the blocks at the
    end of the run, coloured by their displacement relative to the base)."""
    from pathlib import Path

    from murus.progress import LazyProgress
    from murus.retaining.backfill import BackfillError
    from murus.retaining.collapse import (
        DT_FACTORS,
        collapse_ensemble,
        collapse_run,
        peak_ratio_check,
    )
    from murus.retaining.continuum_backfill import ContinuumBackfillError

    error = None
    phase = "run"
    try:
        _prepare_out(out, _COLLAPSE_FILES)
        wall = _dem_wall(preset_name, base, stone_height)
        kw = dict(stiffness_scale=stiffness_scale, xi=xi, threshold=threshold, t_max=t_max,
                  damping_frame=damping_frame, backfill=backfill)
        opts = {k: v for k, v in (("W", width), ("boundary", boundary), ("radius", radius),
                                  ("size", zone_size)) if v is not None}
        bmode = backfill.strip().lower()
        if opts and bmode not in ("discrete", "continuum"):
            raise ValueError("--width, --boundary, --radius and --zone-size need --backfill "
                             "discrete or continuum")
        if bmode == "discrete":
            if "size" in opts:
                raise ValueError("--zone-size needs --backfill continuum")
            mock = wall.name.lower().startswith("mockup")
            kw["backfill_options"] = dict(
                {"boundary": "container" if mock else "absorbing"}, **opts)
        elif bmode == "continuum":
            if "radius" in opts:
                raise ValueError("--radius needs --backfill discrete")
            if corner_share is not None:
                from murus.continuum.interface import CORNER_SHARES

                cs = corner_share.strip().lower()
                if cs not in CORNER_SHARES:
                    raise ValueError(f"--corner-share must be "
                                     f"{' or '.join(repr(c) for c in CORNER_SHARES)}, got "
                                     f"{corner_share!r}")
                opts["corner_share"] = cs
            kw["backfill_options"] = opts
        if corner_share is not None and bmode != "continuum":
            raise ValueError("--corner-share needs --backfill continuum")
        if subcycle is not None:
            if bmode != "continuum":
                raise ValueError("--subcycle needs --backfill continuum")
            sc = subcycle.strip().lower()
            if sc != "auto" and not (sc.isdigit() and int(sc) >= 1):
                raise ValueError(f"--subcycle must be 'auto' or a positive integer, got "
                                 f"{subcycle!r}")
            kw["subcycle"] = sc if sc == "auto" else int(sc)
        if not 1 <= runs <= len(DT_FACTORS):
            raise ValueError(f"--runs must be from 1 to {len(DT_FACTORS)}, got {runs}")
        if workers < 1:
            raise ValueError(f"--workers must be >= 1, got {workers}")
        if checkpoint is not None and runs != 1:
            raise ValueError("--checkpoint needs --runs 1 (one run, one checkpoint file)")
        ens = None
        if runs == 1:
            ck = {} if checkpoint is None else dict(checkpoint=checkpoint,
                                                    checkpoint_every=checkpoint_every)
            with LazyProgress(f"collapse {wall.name} {frequency:g} Hz", unit="s") as bar:
                res = collapse_run(wall, frequency, vertical, progress=bar.update, **kw, **ck)
        else:
            # (one numba thread in each worker process: the pool's initializer sets it)
            with LazyProgress(f"collapse {wall.name} {frequency:g} Hz, {runs} runs",
                              unit="runs" if workers > 1 else "s") as bar:
                ens = collapse_ensemble(wall, frequency, vertical, runs=runs,
                                        executor="process" if workers > 1 else None,
                                        workers=workers, progress=bar.update, **kw)
            res = ens.nominal
        checks = {}
        phase = "checks"
        if check_peak and res.collapsed:
            # at the median A_col of an ensemble (that of the single run otherwise)
            a_col = res.A_col if ens is None else ens.median
            with LazyProgress("S1 checks at 0.6 and 0.7 A_col", unit="s") as bar:
                checks = peak_ratio_check(wall, frequency, a_col, vertical=vertical,
                                          A_rate=res.A_rate, A_pseudo=res.A_pseudo,
                                          progress=bar.update, **kw)
    except (*_collapse_errors(), BackfillError, ContinuumBackfillError) as exc:
        error = exc
    except KeyboardInterrupt:
        from murus.cliutil import failed

        if checkpoint is not None and phase == "checks":
            failed("interrupted during the S1 checks: nothing was written; the collapse run "
                   "had ended and its checkpoint was removed: the same command runs "
                   "everything again", code=130)
        if checkpoint is not None:
            from murus.retaining.collapse import _checkpoint_path

            path = _checkpoint_path(checkpoint)
            if path.exists():
                failed(f"interrupted: nothing was written; the checkpoint {path} is kept: run "
                       "the same command again to resume from it", code=130)
            # Ctrl-C during the run writes the checkpoint: this one came before the run
            failed("interrupted before the run started (while the wall was built or settled): "
                   "nothing was written; the same command starts again", code=130)
        failed("interrupted: nothing was written (a collapse run restarts from the beginning: "
               "run the same command again, or give --checkpoint to resume)", code=130)
    if error is not None:
        _fail(error)
    summary = res.summary() if ens is None else ens.summary()
    if check_peak:
        summary["peak_checks"] = {f"{r:g}": {"a_peak": c.a_peak, "stable": c.stable,
                                             "d_top_max": float(max(c.d_top)),
                                             "wall_time": c.wall_time}
                                  for r, c in checks.items()}
    # everything computed: write
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    from murus.retaining.collapse import plot_collapse

    d = Path(out)
    state = f"collapse at t = {res.t_col:.2f} s" if res.collapsed else "no collapse"
    with guard(OutputError), _staged(out, _COLLAPSE_FILES) as tmp:
        res.history_csv(tmp / "d_top.csv")
        (tmp / "summary.json").write_text(dumps(summary))
        ax = plot_collapse(res.polygons, res.displacement, (res.disc_centres, res.disc_radii),
                           res.disc_displacement,
                           f"{wall.name}, {frequency:g} Hz, vertical {res.vertical}: {state}",
                           zones=(res.zone_xy, res.zone_cells, res.zone_state))
        ax.figure.savefig(tmp / "collapse.png", dpi=120)
        plt.close(ax.figure)
    if res.collapsed:
        typer.echo(f"{wall.name} {frequency:g} Hz ({res.vertical}): A_col = {res.A_col:.3f} "
                   f"m/s2 at t_col = {res.t_col:.2f} s; A_pseudo = {res.A_pseudo:.3f} m/s2, "
                   f"r = {summary['r']:.2f}; {res.wall_time:.1f} s")
    else:
        typer.echo(f"{wall.name} {frequency:g} Hz ({res.vertical}): no collapse up to "
                   f"t = {res.t_end:.2f} s; {res.wall_time:.1f} s")
    if ens is not None:
        lo, hi = ens.range
        typer.echo(f"  {runs} runs (time step x {', '.join(f'{f:g}' for f in ens.factors)}): "
                   f"median A_col = {ens.median:.3f} m/s2, range {lo:.3f} to {hi:.3f} m/s2 "
                   "(inf: no collapse)")
    for r, c in checks.items():
        typer.echo(f"  S1 at {r:g} A_col: {'stable' if c.stable else 'collapsed'}")
    typer.echo(f"wrote {d / 'd_top.csv'}, {d / 'summary.json'}, {d / 'collapse.png'}")


# options of the command line form of behaviour-factor -> keys of the case file
_BF_KEYS = {"wall.preset": "--preset", "wall.stone_height": "--stone-height",
            "wall.base": "--base", "cases.frequencies": "--frequencies",
            "cases.vertical": "--vertical", "cases.check_ratios": "--check-ratios",
            "numerics.stiffness_scale": "--stiffness-scale", "numerics.xi": "--xi",
            "numerics.A_rate": "--a-rate", "numerics.threshold": "--threshold",
            "numerics.t_max": "--t-max"}


def _numbers(text: str, option: str) -> list[float]:
    try:
        vals = [float(x) for x in text.split(",") if x.strip()]
    except ValueError:
        raise ValueError(f"{option} must be numbers separated by commas, got {text!r}") from None
    if any(not math.isfinite(v) for v in vals):
        raise ValueError(f"{option} must be finite numbers, got {text!r}")
    return vals


def _options_case(preset_name, frequencies, vertical, check_ratios, stone_height,
                  stiffness_scale, xi, threshold, t_max, base, a_rate=None) -> dict:
    """The case-file tables of the command-line form (defaults: 3, 5, 10 Hz, no vertical
    component, checks at 0.6 and 0.7 A_col, the numerics of collapse_run)."""
    freqs = _numbers(frequencies if frequencies is not None else "3,5,10", "--frequencies")
    if not freqs or any(f <= 0 for f in freqs):
        raise ValueError(f"--frequencies must be positive numbers, got {frequencies!r}")
    wall = {"preset": preset_name}
    if stone_height is not None:
        wall["stone_height"] = stone_height
    if base is not None:
        wall["base"] = base
    cases = {"frequencies": freqs}
    if vertical is not None:
        cases["vertical"] = [x.strip() for x in vertical.split(",") if x.strip()]
    if check_ratios is not None:
        cases["check_ratios"] = _numbers(check_ratios, "--check-ratios")
    num = {k: v for k, v in (("stiffness_scale", stiffness_scale), ("xi", xi),
                             ("A_rate", a_rate), ("threshold", threshold), ("t_max", t_max))
           if v is not None}
    return {"wall": wall, "cases": cases, "numerics": num}


@app.command("behaviour-factor")
def behaviour_factor_cmd(
    case: Path | None = typer.Argument(None, help="Case file (TOML, examples/retaining/); or "
                                       "give the wall with --preset and the options below.",
                                       show_default=False),
    out: Path | None = typer.Option(None, "--out", "-o", help="Study folder (default: the "
                                    "case file's [output] folder, or its name next to it)."),
    executor: str | None = EXECUTOR_OPTION,
    workers: int | None = WORKERS_OPTION,
    scheduler: str | None = SCHEDULER_OPTION,
    dask: str | None = DASK_OPTION,
    serial: bool = SERIAL_OPTION,
    retries: int | None = typer.Option(None, "--retries", min=0, help="Retries of a failing "
                                       "case (default: [study] retries, 2)."),
    quiet: bool = typer.Option(False, "--quiet", "-q", help="No progress bar."),
    no_snapshots: bool = typer.Option(False, "--no-snapshots", help="Do not draw the "
                                      "cases/*.png figures."),
    preset_name: str | None = typer.Option(None, "--preset", help="Without a case file: "
                                           "DSRW1..DSRW4, C3s or mockup-<H/B>."),
    frequencies: str | None = typer.Option(None, "--frequencies", help="Without a case "
                                           "file: input frequencies [Hz], comma-separated "
                                           "(default 3,5,10)."),
    vertical: str | None = typer.Option(None, "--vertical", help="Without a case file: "
                                        "vertical modes, comma-separated: none, in_phase, "
                                        "opposition (default none)."),
    check_ratios: str | None = typer.Option(None, "--check-ratios", help="Without a case "
                                            "file: S1 checks at these fractions of A_col, "
                                            "comma-separated (default 0.6,0.7; '' none)."),
    stone_height: float | None = typer.Option(None, "--stone-height", help="Without a case "
                                              "file: course height [m] (mock-ups)."),
    stiffness_scale: float | None = typer.Option(None, "--stiffness-scale", help="Without a "
                                                 "case file: joint stiffness factor (default "
                                                 "1e-2 on the continuum backfill, 1e-3 on the "
                                                 "thrust and discs)."),
    xi: float | None = typer.Option(None, "--xi", help="Without a case file: damping ratio "
                                    "(default 0.05, the paper's effective 5 %)."),
    a_rate: float | None = typer.Option(None, "--a-rate", help="Without a case file: slope A "
                                        "of the S2 envelope [m/s³] (default A_pseudo / 2.5 "
                                        "s; the mock-ups of Table 3: 0.1307)."),
    threshold: float | None = typer.Option(None, "--threshold", help="Without a case file: "
                                           "collapse threshold, fraction of H."),
    t_max: float | None = typer.Option(None, "--t-max", help="Without a case file: end of an "
                                       "S2 run without collapse [s]."),
    base: str | None = _BASE,
) -> None:
    """Behaviour factor r = 0.6 A_col / A_pseudo (Savalle et al. (2022), Tables 7 and 8): S2
    collapse runs for each frequency and vertical mode, then S1 checks at 0.6 and 0.7 A_col, as
    stored, resumable tasks on a process pool or a Dask cluster (as `murus study run`: running the
    same command again computes only the missing cases; a folder of another study is refused).
    Writes OUT/behaviour_factor.csv and .md, OUT/cases/*.json (summaries), *.csv (d_top
    histories) and *.png (the blocks at collapse); `murus study status OUT` shows progress."""
    from murus.cliutil import guard
    from murus.config import CaseError
    from murus.studies.cli import executor_choice, progress_bar
    from murus.studies.sweep import StudyError, check_folder

    legacy = {"--preset": preset_name, "--frequencies": frequencies, "--vertical": vertical,
              "--check-ratios": check_ratios, "--stone-height": stone_height,
              "--stiffness-scale": stiffness_scale, "--xi": xi, "--a-rate": a_rate,
              "--threshold": threshold, "--t-max": t_max, "--base": base}
    given = [k for k, v in legacy.items() if v is not None]
    errors = (CaseError, StudyError, ImportError, OSError, *_collapse_errors())
    with guard(*errors, first_line=True):
        from murus.retaining.study import behaviour_study, load_behaviour_study

        if case is not None and given:
            raise ValueError(f"give a case file or {given[0]} and the other wall options, "
                             "not both")
        if case is None:
            if preset_name is None:
                raise ValueError("give a case file (CASE.toml) or --preset")
            if out is None:
                raise ValueError("--out is required without a case file")
            data = _options_case(preset_name, frequencies, vertical, check_ratios,
                                 stone_height, stiffness_scale, xi, threshold, t_max, base,
                                 a_rate)
            try:
                st = behaviour_study(data)
            except CaseError as exc:  # name the option, not the table key
                opt = _BF_KEYS.get(".".join(str(x) for x in exc.key
                                            if not isinstance(x, int)))
                if opt is None:
                    raise
                reason = exc.reason
                name = str(exc.key[-1]) if exc.key else ""
                if name and reason.startswith(name + " "):  # "stone_height must be > 0"
                    reason = reason[len(name) + 1:]
                raise CaseError(f"{opt} {reason}", key=exc.key, reason=exc.reason) from None
            folder = out
        else:
            st = load_behaviour_study(case)
            folder = out if out is not None else Path(st.output) if st.output else \
                case.parent / case.stem
        if retries is not None:
            st.retries = retries
        kind, sched = executor_choice(executor, serial, dask, scheduler, default=(
            st.executor["kind"], st.executor.get("scheduler")))
        n_workers = workers if workers is not None else (
            st.executor.get("workers") if kind == st.executor["kind"] else None)
        check_folder(folder, st.digest())  # another study: refused before anything is written
    with guard(OutputError):
        _prepare_out(folder)  # not a file, under a file, the current folder, unwritable
    n = len(st.tasks())
    typer.echo(f"{st.name}: {st.wall.name}, {len(st.cases)} S2 runs and "
               f"{n - len(st.cases)} S1 checks -> {folder}")
    from murus.retaining.study import run_behaviour_study, running_cases, write_snapshots
    from murus.studies.cli import interrupted, resume_command

    run = dict(workers=n_workers, scheduler=sched, out=folder)
    resume = resume_command("retaining", "behaviour-factor", *(
        [case] if case is not None else [w for k in given for w in (k, legacy[k])]),
        "--out", folder)
    try:
        # the executor is opened (and closed) by the run: on Ctrl-C the finished cases are
        # kept, the runs in progress abandoned
        with guard(*errors, first_line=True):
            prog, cb = progress_bar("cases", st.name, quiet=quiet,
                                    poll=lambda: running_cases(folder))
            with prog:
                res = run_behaviour_study(st, kind, progress=cb, **run)
    except KeyboardInterrupt:
        interrupted(folder, resume)
    if not no_snapshots:
        with guard(*errors, first_line=True):
            write_snapshots(folder)
    typer.echo(res.to_markdown(), nl=False)
    typer.echo(f"wrote {folder / 'behaviour_factor.csv'}, {folder / 'behaviour_factor.md'}, "
               f"{folder / 'cases'}/")
    if res.n_failed:
        typer.echo(f"warning: {res.n_failed} cases failed (errors in "
                   f"{folder / 'failures.json'}); run the same command again to retry them",
                   err=True)
        raise typer.Exit(1)


@app.command("calibrate-backfill")
def calibrate_backfill(
    target: float | None = typer.Option(None, "--target", help="Target peak friction angle "
                                        "[deg] (Savalle et al. (2022): 37.7 full scale, 45 "
                                        "mock-ups): finds "
                                        "the rolling resistance; without it, one test at "
                                        "--rolling."),
    rolling: float = typer.Option(0.167, "--rolling", help="Rolling resistance coefficient "
                                  "mu_r of a single test [-]."),
    friction: float = typer.Option(30.0, "--friction", help="Interparticle friction [deg]."),
    n: int = typer.Option(200, "--discs", min=4, help="Discs in the sample."),
    sigma3: float = typer.Option(50e3, "--sigma3", help="Confining stress [Pa]."),
    seeds: int | None = typer.Option(None, "--seeds", min=1, help="Assemblies averaged per "
                                     "value of mu_r (default 8 with --target: one 200-disc "
                                     "sample scatters by ~3 deg; 1 for a single test)."),
    kn: float = typer.Option(1e9, "--kn", help="Normal and shear contact stiffness [Pa/m]."),
    out: str | None = typer.Option(None, "--out", help="Folder for biaxial.png/.svg, "
                                   "biaxial.csv and biaxial.json."),
) -> None:
    """Biaxial test of the disc backfill (murus.dem.biaxial): peak and critical-state friction
    angles, with a stress-strain figure; with --target, the rolling resistance that gives it
    (Savalle et al. (2022), §2: 37.7 deg), averaged over --seeds assemblies, with the scatter over
    them. A calibration that does not converge writes its outputs with status not ok and exits 1."""
    from dataclasses import replace
    from pathlib import Path

    from murus.dem.biaxial import biaxial_test, calibrate_rolling
    from murus.dem.materials import Joint, JointError
    from murus.progress import LazyProgress

    error = None
    try:
        if out is not None:
            _prepare_out(out, _BIAXIAL_FILES)
        if target is not None and not (0.0 < target < 90.0):
            raise ValueError(f"--target must be an angle in (0, 90) deg, got {target!r}")
        joint = Joint(kn=kn, ks=kn, friction_deg=friction, rolling=rolling)
        nseeds = seeds if seeds is not None else (8 if target is not None else 1)
        if target is None:
            runs = []
            with LazyProgress("biaxial test", nseeds, unit="tests") as bar:
                for s_ in range(nseeds):
                    runs.append(biaxial_test(joint, n=n, sigma3=sigma3, seed=s_,
                                             progress=lambda e, em, k=s_: bar.update(k + e / em)))
            res = runs[0]
            cal = None
        else:
            with LazyProgress("calibrate-backfill", 8 * nseeds, unit="tests") as bar:
                cal = calibrate_rolling(target, joint=replace(joint, rolling=0.0), n=n,
                                        sigma3=sigma3, seeds=tuple(range(nseeds)),
                                        progress=bar.update)
            res = cal.result
    except (*_errors(), JointError) as exc:
        error = exc
    except RuntimeError as exc:  # the compaction did not converge: a job that failed
        typer.echo(f"error: {' '.join(str(exc).split())}", err=True)
        raise typer.Exit(code=1) from None
    if error is not None:
        _fail(error)
    which = " of assembly 0 (the figure and table)" if nseeds > 1 else ""
    typer.echo(f"biaxial test{which}: {res.n} discs, friction {res.friction_deg:g} deg, mu_r = "
               f"{res.rolling:.4g}, sigma3 = {res.sigma3_target / 1e3:g} kPa: phi_peak = "
               f"{res.phi_peak_deg:.2f} deg at {100 * res.strain_at_peak:.2f} % strain, "
               f"phi_cs = {res.phi_cs_deg:.2f} deg, porosity {res.porosity0:.3f}")
    if cal is None and nseeds > 1:
        import numpy as np

        phis = np.array([r.phi_peak_deg for r in runs])
        typer.echo(f"over {nseeds} assemblies: phi_peak = {phis.mean():.2f} deg, standard "
                   f"deviation {phis.std(ddof=1):.2f} deg")
    if cal is not None:
        hist = ", ".join(f"{m:.3f} -> {p:.1f}" for m, p in cal.history)
        state = "converged" if cal.converged else f"NOT converged: {cal.status}"
        nse = len(cal.phi_seeds)
        scatter = (f"; over the {nse} assemblies at mu_r = {cal.rolling:.4f}: standard "
                   f"deviation {cal.std_deg:.2f} deg" if nse > 1 else "")
        se = f" (standard error {cal.se_deg:.2f} deg)" if cal.se_deg == cal.se_deg else ""
        typer.echo(f"calibration to {target:g} deg: mu_r = {cal.rolling:.4f}{se}, {state}: "
                   f"{cal.message}; mean phi_peak at each mu_r tried: {hist}{scatter}")
    failed = cal is not None and not cal.converged
    if out is None:
        if failed:
            _not_converged(cal)
        return
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from murus.dem.biaxial import plot_biaxial

    dest = Path(out)
    with guard(OutputError), _staged(out, _BIAXIAL_FILES) as tmp:
        ax = plot_biaxial(res)
        ax.figure.tight_layout()
        ax.figure.savefig(tmp / "biaxial.png", dpi=120)
        ax.figure.savefig(tmp / "biaxial.svg")
        plt.close(ax.figure)
        rows = ["axial_strain,sigma1_pa,sigma3_pa,volumetric_strain,phi_deg"]
        rows += [f"{a:.6g},{s1:.6g},{s3:.6g},{v:.6g},{p:.4f}" for a, s1, s3, v, p in
                 zip(res.axial_strain, res.sigma1, res.sigma3, res.volumetric_strain,
                     res.phi_deg, strict=True)]
        (tmp / "biaxial.csv").write_text("\n".join(rows) + "\n", encoding="utf-8")
        summary = {"status": cal.status if cal is not None else "completed",
                   "ok": not failed, "assembly": res.meta.get("seed", 0),
                   "discs": res.n, "friction_deg": res.friction_deg, "rolling": res.rolling,
                   "sigma3_pa": res.sigma3_target, "phi_peak_deg": res.phi_peak_deg,
                   "phi_cs_deg": res.phi_cs_deg, "strain_at_peak": res.strain_at_peak,
                   "porosity0": res.porosity0}
        if cal is None and nseeds > 1:
            summary["phi_peak_deg_assemblies"] = [r.phi_peak_deg for r in runs]
        if cal is not None:
            summary["calibration"] = {"target_deg": target, "rolling": cal.rolling,
                                      "phi_peak_deg": cal.phi_peak_deg,
                                      "converged": cal.converged, "status": cal.status,
                                      "message": cal.message, "seeds": len(cal.phi_seeds),
                                      "phi_peak_deg_assemblies": list(cal.phi_seeds),
                                      "std_deg": cal.std_deg, "se_deg": cal.se_deg,
                                      "runs": cal.history}
        (tmp / "biaxial.json").write_text(dumps(summary), encoding="utf-8")
    typer.echo(f"wrote {dest}/biaxial.png, .svg, .csv, .json")
    if failed:
        _not_converged(cal)


def _not_converged(cal) -> None:
    """A calibration that did not converge: its reason on one line, exit code 1."""
    typer.echo(f"error: calibration not converged ({cal.status}): {cal.message}", err=True)
    raise typer.Exit(code=1)


@app.command("weighted-response")
def weighted_response_cmd(
    histories: list[str] = typer.Argument(..., help="d_top histories of the cross-sections: "
                                          "CSV files with columns t_s and d_top_m (as written "
                                          "by 'murus retaining collapse')."),
    weights: str = typer.Option(..., "--weights", help="Proportion of each section along the "
                                "wall, comma-separated (Savalle et al. (2022), Table 2: 7,7,7,2)."),
    levels: int = typer.Option(200, "--levels", min=2, help="Displacement levels."),
    out: str | None = typer.Option(None, "--out", help="CSV file of the global response "
                                   "(t_s, d_top_m and the time of each section)."),
) -> None:
    """Global response of a wall from several cross-sections (Savalle et al. (2022), §3.2, Table 2):
    for each d_top level, the times at which the sections reach it, weighted by their proportions
    along the wall."""
    from pathlib import Path

    import numpy as np

    from murus.outputs import check_file, write_file
    from murus.retaining.sections import SectionsError, weighted_response

    if out is not None:
        if any(Path(out).resolve() == Path(f).resolve() for f in histories):
            _fail(f"--out {out}: is one of the input histories; name another file")
        with guard(OutputError):
            check_file(out, (".csv",))
    try:
        w = [float(x) for x in weights.split(",") if x.strip()]
    except ValueError:
        _fail(f"--weights must be comma-separated numbers, got {weights!r}")
    try:
        hs = []
        for f in histories:
            p = Path(f)
            if not p.is_file():
                raise ValueError(f"{f}: no such file")
            head = p.read_text(encoding="utf-8").splitlines()[0].split(",")
            if "t_s" not in head or "d_top_m" not in head:
                raise ValueError(f"{f}: needs columns t_s and d_top_m (got {','.join(head)})")
            try:
                arr = np.loadtxt(p, delimiter=",", skiprows=1, ndmin=2)
            except ValueError as exc:
                raise ValueError(f"{f}: not a numeric CSV ({exc})") from None
            hs.append((arr[:, head.index("t_s")], arr[:, head.index("d_top_m")]))
        res = weighted_response(hs, w, n_levels=levels)
    except (SectionsError, ValueError) as exc:
        _fail(exc)
    if res.levels.size == 0:
        _fail("no displacement level is reached by every section")
    i = np.searchsorted(res.levels, res.levels[-1] / 2)
    typer.echo(f"{len(hs)} sections, weights {', '.join(f'{x:.3f}' for x in res.weights)}: "
               f"d_top = {1e3 * res.levels[i]:.2f} mm at {res.time[i]:.3f} s (sections "
               f"{', '.join(f'{t:.3f}' for t in res.section_times[:, i])} s); up to "
               f"{1e3 * res.levels[-1]:.2f} mm at {res.time[-1]:.3f} s")
    if out is not None:
        cols = np.column_stack([res.time, res.levels, res.section_times.T])
        header = "t_s,d_top_m," + ",".join(f"t_section{k + 1}_s" for k in range(len(hs)))
        with guard(OutputError):
            write_file(out, lambda p: np.savetxt(p, cols, delimiter=",", fmt="%.9g",
                                                 header=header, comments=""),
                       record=True)
        typer.echo(f"wrote {out}")

"""``murus motion`` commands: info, spectrum, process, plot, generate ec8, ramp.

Thin layer over the library. Bad input exits with code 2 and a one-line message on stderr;
outputs are written with :mod:`murus.outputs` (a temporary folder or file published at the
end; in an existing folder only files murus wrote there before are replaced), so a failed
command leaves nothing half-written and nothing of the user's is touched. Heavy imports stay
inside the commands.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import typer

from murus import G
from murus.cliutil import guard
from murus.outputs import check_dir

app = typer.Typer(
    rich_markup_mode=None,
    name="motion",
    help="Ground motions: record info, response spectra, EC8 artificial records, ramps.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)
generate_app = typer.Typer(rich_markup_mode=None, help="Generate ground motions.",
                           no_args_is_help=True)
app.add_typer(generate_app, name="generate")


def _guard():
    """Turn user errors (bad files, bad values) into exit code 2 with a one-line message."""
    from murus.motion.io import MotionFormatError

    return guard(MotionFormatError, ValueError, ImportError, OSError)


def _staged_dir(out: Path, names=None):
    """:func:`murus.outputs.staged_dir`: a temporary folder published into ``out`` on
    success (only files murus wrote there before are replaced)."""
    from murus.outputs import command_line, staged_dir

    return staged_dir(out, command_line(), names)


def _load(file: Path, units: str | None, dt: float | None, channel: str | None = None):
    from murus.motion.io import read

    return read(file, units=units, dt=dt, channel=channel)


UNITS_HELP = "Units of a CSV/text file without a '# units:' line: g, m/s2 or cm/s2."
FORMATS_HELP = ("Record file: PEER AT2, ESM ASCII, COSMOS V0/V1/V2, CSMIP/DMG V1/V2, K-NET/KiK-net "
                "ASCII, CSV/text (detected from the content).")
CHANNEL_HELP = ("Channel of a multi-channel file: its number (2), orientation as written "
                "('360 Deg', 'Up', 'E-W'), azimuth (90) or N, E, Z. Default: the first "
                "horizontal channel.")


@app.command()
def info(
    file: Path = typer.Argument(..., help=FORMATS_HELP),
    as_json: bool = typer.Option(False, "--json", help="Print a JSON object (SI units)."),
    units: str = typer.Option(None, help=UNITS_HELP),
    dt: float = typer.Option(None, help="Time step [s] of a one-column file."),
    channel: str = typer.Option(None, help=CHANNEL_HELP),
) -> None:
    """Format, dt, npts, PGA, PGV, PGD, Arias intensity, D5-75, D5-95 and CAV of a record.

    PGV and PGD are given after a stated baseline correction (a linear acceleration making the
    final velocity and displacement zero; murus.motion.measures.BASELINE), with the
    uncorrected values beside them."""
    with _guard():
        from murus.motion.io import read_all, select_channel
        from murus.motion.measures import corrected_peaks, summary

        chans = read_all(file, units=units, dt=dt)
        gm = select_channel(chans, channel, file.name)
        s = summary(gm)
        s.update(corrected_peaks(gm))
    s = {k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in s.items()}
    s = {"file": str(file), "format": gm.meta.get("format"), "name": gm.name,
         **{k: gm.meta.get(k) for k in ("station", "channel", "component")}, **s}
    s["channels"] = [f"{c.meta.get('channel')} ({c.meta.get('component', '')})".replace(" ()", "")
                     for c in chans]
    if as_json:
        typer.echo(json.dumps(s))
        return
    typer.echo(f"{file}  [{s['format']}]")
    if len(chans) > 1:
        typer.echo(f"  channel {s['channels'][chans.index(gm)]} of {len(chans)}: "
                   f"{', '.join(s['channels'])} (choose with --channel)")
    typer.echo(f"  npts {s['npts']}   dt {s['dt']:g} s   duration {s['duration']:.3f} s")
    typer.echo(f"  PGA {s['pga']:.4g} m/s² ({s['pga'] / G:.4g} g)   PGV {s['pgv']:.4g} m/s"
               f"   PGD {s['pgd']:.4g} m (after baseline correction)")
    typer.echo(f"  uncorrected: PGV {s['pgv_raw']:.4g} m/s   PGD {s['pgd_raw']:.4g} m")
    typer.echo(f"  baseline: {s['baseline']}")
    typer.echo(f"  Arias {s['arias']:.4g} m/s   D5-75 {s['d5_75']:.3f} s   "
               f"D5-95 {s['d5_95']:.3f} s   CAV {s['cav']:.4g} m/s")


@app.command()
def spectrum(
    file: Path = typer.Argument(..., help=FORMATS_HELP),
    damping: float = typer.Option(0.05, help="Damping ratio (fraction of critical)."),
    out: Path = typer.Option(Path("spectrum"), help="Output directory."),
    units: str = typer.Option(None, help=UNITS_HELP),
    dt: float = typer.Option(None, help="Time step [s] of a one-column file."),
    n_periods: int = typer.Option(100, help="Number of log-spaced periods 0.01-10 s."),
    channel: str = typer.Option(None, help=CHANNEL_HELP),
) -> None:
    """Response spectrum: DIR/spectrum.csv (columns period [s], sd [m], sv [m/s], sa [m/s²],
    psv [m/s], psa [m/s²]) and DIR/spectrum.png."""
    with _guard():
        if not 0 <= damping < 1:
            raise ValueError(f"--damping {damping} must be in [0, 1)")
        if n_periods < 2:
            raise ValueError("--n-periods must be >= 2")
        check_dir(out, ["spectrum.csv", "spectrum.png"])
        from murus.motion.spectra import default_periods, response_spectrum

        gm = _load(file, units, dt, channel)
        sp = response_spectrum(gm, default_periods(n_periods), damping)
        with _staged_dir(out, ["spectrum.csv", "spectrum.png"]) as tmp:
            lines = ["period,sd,sv,sa,psv,psa"]
            for row in zip(sp.period, sp.sd, sp.sv, sp.sa, sp.psv, sp.psa, strict=True):
                lines.append(",".join(f"{x:.10g}" for x in row))
            # units: period s, sd m, sv m/s, sa m/s² (absolute), psv m/s, psa m/s²
            (tmp / "spectrum.csv").write_text("\n".join(lines) + "\n")
            import matplotlib

            matplotlib.use("Agg")
            import matplotlib.pyplot as plt

            from murus.motion.plots import plot_spectrum

            ax = plot_spectrum(sp, label=gm.name)
            ax.figure.savefig(tmp / "spectrum.png", dpi=120)
            plt.close(ax.figure)
    typer.echo(f"wrote {out}/spectrum.csv and {out}/spectrum.png")


_EC8_NAMES = ["report.txt", "report.json", "spectra.png"]


@generate_app.command("ec8")
def generate_ec8_cmd(
    ag: float = typer.Option(..., help="Reference peak ground acceleration on rock, in g."),
    ground: str = typer.Option("B", help="Ground type A-E."),
    spectrum_type: int = typer.Option(1, "--type", help="Spectrum type 1 or 2."),
    n: int = typer.Option(7, help="Number of records (EN 1998-1 requires at least 3)."),
    seed: int = typer.Option(1, help="Random seed (reproducible)."),
    out: Path = typer.Option(Path("ec8_records"), help="Output directory."),
    t1: float = typer.Option(None, help="Fundamental period T1 [s]: check range [0.2 T1, 2 T1]."),
    t_lo: float = typer.Option(0.05, help="Lower period of the check range [s] (without --t1)."),
    t_hi: float = typer.Option(2.0, help="Upper period of the check range [s] (without --t1)."),
    dt: float = typer.Option(0.01, help="Time step [s]."),
    stationary: float = typer.Option(10.0, help="Stationary part of the envelope [s]."),
    fmt: str = typer.Option("csv", "--format",
                            help="Format of the records: csv (m/s², commented header) or at2 "
                                 "(PEER AT2 in g, read by other tools)."),
) -> None:
    """Artificial records compatible with the EN 1998-1 elastic spectrum, with the
    §3.2.3.1.2 report (report.txt, report.json) and a figure of the spectra (spectra.png)."""
    with _guard():
        from murus import G
        from murus.eurocode.ec8 import parameters
        from murus.motion.artificial import check_ec8, generate_ec8
        from murus.motion.io import write

        if not (ag > 0 and math.isfinite(ag)):
            raise ValueError(f"--ag {ag} must be positive (in g)")
        if ag > 3:
            raise ValueError(f"--ag {ag} is in g and looks too large (m/s² given?)")
        parameters(ground, spectrum_type)
        if n < 1 or n > 1000:
            raise ValueError("--n must be between 1 and 1000")
        if not (dt > 0 and dt <= 0.05):
            raise ValueError("--dt must be in (0, 0.05] s")
        rng = (0.2 * t1, 2.0 * t1) if t1 else (t_lo, t_hi)
        if not 0 < rng[0] < rng[1]:
            raise ValueError("period range must satisfy 0 < T_lo < T_hi")
        fmt = fmt.lower()
        if fmt not in ("csv", "at2"):
            raise ValueError(f"--format {fmt!r}: use csv or at2")
        check_dir(out, _EC8_NAMES)
        agm = ag * G
        recs = generate_ec8(agm, ground, spectrum_type, n=n, seed=seed, dt=dt,
                            stationary=stationary)
        rep = check_ec8(recs, agm, ground, spectrum_type, period_range=rng)
        with _staged_dir(out, _EC8_NAMES) as tmp:
            for r in recs:
                write(r, tmp / f"{r.name}.{fmt}", format=fmt)
            (tmp / "report.txt").write_text(rep.to_text() + "\n")
            (tmp / "report.json").write_text(json.dumps(rep.to_dict(), indent=2) + "\n")
            import matplotlib

            matplotlib.use("Agg")
            import matplotlib.pyplot as plt

            from murus.motion.plots import plot_compatibility

            ax = plot_compatibility(rep)
            ax.figure.savefig(tmp / "spectra.png", dpi=120)
            plt.close(ax.figure)
    typer.echo(rep.to_text())
    typer.echo(f"wrote {n} records, report.txt, report.json and spectra.png to {out}")


@app.command()
def ramp(
    amplitude_rate: float = typer.Option(..., help="Amplitude rate A of S(t) = A t sin(2 pi f t)"
                                                   " [m/s³]."),
    frequency: float = typer.Option(..., help="Frequency f [Hz]."),
    duration: float = typer.Option(..., help="Duration [s]."),
    out: Path = typer.Option(..., help="Output file (.csv or .at2)."),
    dt: float = typer.Option(0.005, help="Time step [s]."),
    vertical: str = typer.Option(None, help="Vertical component: in_phase or opposition."),
) -> None:
    """Harmonic ramp S(t) = A t sin(2 pi f t) of Savalle et al. (2022) (eq. 5), written as CSV or
    AT2."""
    with _guard():
        from murus.motion.io import write
        from murus.motion.synthetic import harmonic_ramp
        from murus.outputs import check_file

        check_file(out, (".csv", ".at2"))

        for key, val in (("--amplitude-rate", amplitude_rate), ("--frequency", frequency),
                         ("--duration", duration), ("--dt", dt)):
            if not (math.isfinite(val) and val > 0):
                raise ValueError(f"{key} {val} must be positive")
        if frequency >= 0.5 / dt:
            raise ValueError(f"--frequency {frequency} Hz is above the Nyquist frequency "
                             f"{0.5 / dt:g} Hz of --dt {dt}")
        if duration / dt > 5e7:
            raise ValueError("too many samples: increase --dt or reduce --duration")
        if vertical is not None and out.suffix.lower() == ".at2":
            raise ValueError("an AT2 file holds one component: use a .csv --out for --vertical")
        gm = harmonic_ramp(amplitude_rate, frequency, duration, dt, vertical=vertical)
        write(gm, out)
    typer.echo(f"wrote {out} ({gm.npts} samples, peak {gm.pga:.4g} m/s²)")


@app.command()
def process(
    file: Path = typer.Argument(..., help="Record file."),
    out: Path = typer.Option(..., help="Output file (.csv or .at2); the operations are listed "
                             "in its header."),
    baseline: int = typer.Option(None, help="Remove a polynomial baseline of this degree "
                                 "(0: the mean, the usual first step)."),
    baseline_fit: str = typer.Option("acceleration", help="Quantity the baseline is fitted "
                                     "to: acceleration, velocity or displacement."),
    taper: float = typer.Option(None, help="Cosine taper over this fraction of the duration "
                                "at both ends (0.05 is usual)."),
    highpass: float = typer.Option(None, help="High-pass corner [Hz] (acausal Butterworth "
                                   "with zero pads)."),
    lowpass: float = typer.Option(None, help="Low-pass corner [Hz] (with --highpass: a "
                                  "band-pass)."),
    order: int = typer.Option(4, help="Order of the Butterworth filters."),
    resample: float = typer.Option(None, help="New time step [s] (anti-alias low-pass at 0.4 "
                                   "/ dt when down-sampling)."),
    trim: str = typer.Option(None, help="Keep T0,T1 [s], e.g. 2,30."),
    trim_arias: str = typer.Option(None, help="Keep between these fractions of the Arias "
                                   "intensity, e.g. 0.001,0.999."),
    pga: float = typer.Option(None, help="Scale to this PGA [m/s²]."),
    pga_g: float = typer.Option(None, "--pga-g", help="Scale to this PGA [g]."),
    sa: str = typer.Option(None, help="Scale to PSA(T) = VALUE, given as T,VALUE: T [s], "
                           "VALUE [m/s²]."),
    sa_damping: float = typer.Option(0.05, help="Damping of --sa [-]."),
    units: str = typer.Option(None, help=UNITS_HELP),
    dt: float = typer.Option(None, help="Time step [s] of a one-column file."),
    out_units: str = typer.Option("m/s2", help="Units of a CSV output: m/s2, g or cm/s2 (AT2 "
                                  "is in g)."),
) -> None:
    """Process a record and write it: baseline, taper, filter, resample, trim, scale, applied
    in this order (the usual sequence, Boore and Bommer 2005; murus.motion.processing.process),
    each operation recorded in the output's header."""
    with _guard():
        from murus.motion.io import normalize_units, write
        from murus.motion.processing import process as run_process
        from murus.outputs import check_file

        check_file(out, (".csv", ".at2"))
        if Path(out).resolve() == Path(file).resolve():
            raise ValueError(f"--out {out}: is the input file; name another file")
        normalize_units(out_units, "--out-units")
        if baseline_fit not in ("acceleration", "velocity", "displacement"):
            raise ValueError(f"--baseline-fit {baseline_fit}: choose acceleration, velocity or "
                             "displacement")
        if pga is not None and pga_g is not None:
            raise ValueError("give --pga or --pga-g, not both")
        for key, val in (("--taper", taper), ("--highpass", highpass), ("--lowpass", lowpass),
                         ("--resample", resample), ("--pga", pga), ("--pga-g", pga_g),
                         ("--sa-damping", sa_damping)):
            if val is not None and not math.isfinite(val):
                raise ValueError(f"{key} {val} is not a number")
        if not 0 <= sa_damping < 1:
            raise ValueError(f"--sa-damping {sa_damping} must be in [0, 1)")
        target = pga if pga is not None else (pga_g * G if pga_g is not None else None)

        def pair(key, v):
            if v is None:
                return None
            parts = [x.strip() for x in v.split(",")]
            try:
                a, b = (float(x) for x in parts)
            except ValueError:
                raise ValueError(f"{key} {v}: expected two numbers separated by a comma"
                                 ) from None
            if not (math.isfinite(a) and math.isfinite(b)):
                raise ValueError(f"{key} {v}: not finite numbers")
            return a, b

        trim_p, arias_p, sa_p = pair("--trim", trim), pair("--trim-arias", trim_arias), \
            pair("--sa", sa)

        gm = _load(file, units, dt)
        done = run_process(gm, baseline=baseline, baseline_fit=baseline_fit,
                           taper_fraction=taper, highpass_hz=highpass, lowpass_hz=lowpass,
                           filter_order=order, resample_dt=resample, trim_s=trim_p,
                           trim_arias_fractions=arias_p, pga=target, sa=sa_p,
                           sa_damping=sa_damping)
        if Path(out).suffix.lower() == ".at2" and done.acc_v is not None:
            typer.echo("note: AT2 holds one component; the vertical one is not written",
                       err=True)
        write(done, out, units=out_units)
    steps = done.meta.get("processing", [])
    for i, s in enumerate(steps, 1):
        typer.echo(f"  {i}. {s}")
    typer.echo(f"wrote {out} ({done.npts} samples, dt {done.dt:g} s, PGA {done.pga:.4g} m/s², "
               f"{len(steps)} operation(s))")


_PLOT_NAMES = ["record.png", "measures.json", "measures.csv", "spectra.csv", "fourier.csv"]


@app.command()
def plot(
    file: Path = typer.Argument(..., help="Record file."),
    out: Path = typer.Option(Path("record"), help="Output directory."),
    damping: list[float] = typer.Option([0.02, 0.05, 0.10, 0.20], "--damping",
                                        help="Damping ratios of the response spectra "
                                        "(repeatable)."),
    n_periods: int = typer.Option(100, help="Number of log-spaced periods 0.01-10 s."),
    as_json: bool = typer.Option(False, "--json", help="Print the intensity measures as JSON."),
    units: str = typer.Option(None, help=UNITS_HELP),
    dt: float = typer.Option(None, help="Time step [s] of a one-column file."),
) -> None:
    """A record at a glance: DIR/record.png (acceleration, velocity and displacement, Husid
    plot with D5-95, Fourier amplitude spectrum, response spectra at several dampings), the
    intensity measures (PGA, PGV, PGD, Arias, CAV, D5-75, D5-95, Housner intensity,
    predominant and mean periods) printed and in DIR/measures.json and measures.csv, and the
    spectra in spectra.csv and fourier.csv."""
    with _guard():
        if not damping or any(not (0 <= x < 1) for x in damping):
            raise ValueError("--damping values must be in [0, 1)")
        if len(set(damping)) != len(damping):
            raise ValueError("--damping: repeated value")
        if n_periods < 2:
            raise ValueError("--n-periods must be >= 2")
        check_dir(out, _PLOT_NAMES)
        from murus.motion.measures import MEASURES, fourier_amplitude, intensity_measures
        from murus.motion.spectra import default_periods, response_spectrum

        gm = _load(file, units, dt)
        im = intensity_measures(gm)
        T = default_periods(n_periods)
        spectra = [response_spectrum(gm, T, x) for x in damping]
        f, c = fourier_amplitude(gm)
        with _staged_dir(out, _PLOT_NAMES) as tmp:
            (tmp / "measures.json").write_text(json.dumps(
                {"file": str(file), "name": gm.name, "units": {k: u for k, (_, u) in
                                                              MEASURES.items()}, **im},
                indent=2) + "\n")
            rows = ["measure,label,value,units"] + [
                f"{k},{MEASURES[k][0].replace(',', ';')},{v:.10g},{MEASURES[k][1]}"
                for k, v in im.items()]
            (tmp / "measures.csv").write_text("\n".join(rows) + "\n")
            head = "period_s," + ",".join(f"psa_{x:g}_m_s2" for x in damping)
            lines = [head] + [",".join([f"{t:.10g}"] + [f"{sp.psa[i]:.10g}" for sp in spectra])
                              for i, t in enumerate(T)]
            (tmp / "spectra.csv").write_text("\n".join(lines) + "\n")
            lines = ["frequency_hz,fourier_amplitude_m_s"] + [
                f"{a:.10g},{b:.10g}" for a, b in zip(f, c, strict=True)]
            (tmp / "fourier.csv").write_text("\n".join(lines) + "\n")
            import matplotlib.pyplot as plt

            from murus.motion.plots import plot_record

            fig = plot_record(gm, spectra, im)
            fig.savefig(tmp / "record.png", dpi=110)
            plt.close(fig)
    if as_json:
        typer.echo(json.dumps(im))
        return
    from rich.console import Console
    from rich.table import Table

    table = Table(title=f"{gm.name or file}: intensity measures")
    for col in ("measure", "value", "units"):
        table.add_column(col, justify="left" if col != "value" else "right")
    for k, v in im.items():
        table.add_row(MEASURES[k][0], f"{v:.4g}", MEASURES[k][1])
    Console().print(table)
    typer.echo(f"wrote {', '.join(_PLOT_NAMES)} to {out}/")


_ROTD_NAMES = ["rotd.csv", "rotd.png"]


@app.command()
def rotd(
    file: Path = typer.Argument(..., help="A three-component file (its two horizontal "
                                "channels), or the first horizontal component."),
    file_b: Path = typer.Argument(None, help="The second horizontal component (perpendicular "
                                  "to the first), when the first file holds one."),
    out: Path = typer.Option(Path("rotd"), help="Output directory."),
    damping: float = typer.Option(0.05, help="Damping ratio (fraction of critical)."),
    n_periods: int = typer.Option(100, help="Number of log-spaced periods 0.01-10 s."),
    units: str = typer.Option(None, help=UNITS_HELP),
    dt: float = typer.Option(None, help="Time step [s] of one-column files."),
) -> None:
    """RotD50 and RotD100 spectra of a horizontal pair (Boore 2010): DIR/rotd.csv (period,
    RotD50, RotD100, the angle of RotD100 from the first component, and the PSA of each
    component) and DIR/rotd.png."""
    with _guard():
        if not 0 <= damping < 1:
            raise ValueError(f"--damping {damping} must be in [0, 1)")
        if n_periods < 2:
            raise ValueError("--n-periods must be >= 2")
        check_dir(out, _ROTD_NAMES)
        from murus.motion.components import horizontal_pair, rotd_spectrum
        from murus.motion.io import read_all
        from murus.motion.spectra import default_periods, pseudo_spectrum

        if file_b is None:
            a, b = horizontal_pair(read_all(file, units=units, dt=dt))
        else:
            ca, cb = read_all(file, units=units, dt=dt), read_all(file_b, units=units, dt=dt)
            if len(ca) != 1 or len(cb) != 1:
                raise ValueError("with two files, each must hold one channel (give a "
                                 "three-component file alone)")
            a, b = horizontal_pair([ca[0].with_meta(vertical=False),
                                    cb[0].with_meta(vertical=False)])
        T = default_periods(n_periods)
        sp = rotd_spectrum(a, b, T, damping)
        sa, sb = pseudo_spectrum(a, T, damping), pseudo_spectrum(b, T, damping)
        with _staged_dir(out, _ROTD_NAMES) as tmp:
            lines = ["period_s,rotd50_m_s2,rotd100_m_s2,angle_rotd100_deg,psa_a_m_s2,psa_b_m_s2"]
            for i, t in enumerate(T):
                lines.append(",".join(f"{x:.10g}" for x in (
                    t, sp[50][i], sp[100][i], sp.angle_max_deg[i], sa[i], sb[i])))
            (tmp / "rotd.csv").write_text("\n".join(lines) + "\n")
            import matplotlib.pyplot as plt

            from murus.motion.plots import plot_rotd

            ax = plot_rotd(sp, sa, sb, names=(a.name, b.name))
            ax.figure.savefig(tmp / "rotd.png", dpi=120)
            plt.close(ax.figure)
    typer.echo(f"wrote {out}/rotd.csv and {out}/rotd.png (at T = {T[0]:g} s: RotD50 "
               f"{sp[50][0]:.4g} m/s², RotD100 {sp[100][0]:.4g} m/s²)")

"""``murus retaining`` commands: pseudo-static resistance and geometry of dry-stone retaining walls.

Thin layer over :mod:`murus.retaining` (seed 001 §4.4). The wall is a preset (``DSRW1`` ...
``DSRW4``, ``C3s`` of seed 001 Table 5, or ``mockup-<H/B>`` for the scaled-down walls of its
§3). Every open assumption of the seed's analytical tool is an option with the default of
:class:`murus.retaining.pseudostatic.Assumptions`. Bad input exits with code 2 and a one-line
``error:`` message on stderr. The library is imported inside the commands (no numba, no
matplotlib), so that ``murus --help`` stays fast.
"""

from __future__ import annotations

import json
import math

import typer

app = typer.Typer(
    rich_markup_mode=None,
    name="retaining",
    help="Dry-stone retaining walls (seed 001): pseudo-static resistance A_pseudo, geometry.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)

_PRESET = typer.Option(..., "--preset", help="DSRW1..DSRW4, C3s (seed 001 Table 5) or "
                       "mockup-<H/B> (seed 001 §3), e.g. mockup-2.7.")
_BASE = typer.Option(None, "--base", help="Base joint: 'inclined' (parallel to the beds, "
                     "default) or 'horizontal'.")
_JSON = typer.Option(False, "--json", help="Print JSON instead of text.")


def _fail(msg) -> None:
    typer.echo(f"error: {' '.join(str(msg).split())}", err=True)
    raise typer.Exit(code=2)


def _errors():
    from murus.eurocode.ec8_5 import EC85Error
    from murus.retaining.geometry import GeometryError
    from murus.retaining.pseudostatic import PseudoStaticError

    return (GeometryError, PseudoStaticError, EC85Error, ValueError)


def _json(obj) -> None:
    def clean(v):
        if isinstance(v, float) and not math.isfinite(v):
            return None
        if isinstance(v, dict):
            return {str(k): clean(x) for k, x in v.items()}
        if isinstance(v, list | tuple):
            return [clean(x) for x in v]
        return v

    typer.echo(json.dumps(clean(obj), indent=2))


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
                                         "(37.7 deg in seed 001 Table 6)."),
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
    """Pseudo-static resistance A_pseudo = kh g (seed 001 §4.4, Table 8): the smallest kh at
    which the wall above some bed joint slides or overturns."""
    from murus import G
    from murus.retaining.pseudostatic import Assumptions, critical_acceleration

    try:
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

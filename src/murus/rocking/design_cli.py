"""``murus design`` commands: tie, damper, resonance (EURODYN (2020), eq. 8-13).

Thin layer over :mod:`murus.rocking.design`. The wall is ``--block block1..block6`` (EURODYN (2020)
Table 1) or ``--width --height [--thickness --density --top-mass]``. Each command prints a small
table (name, value, unit, equation) or, with ``--json``, a JSON object. Bad input exits with code
2 and a one-line ``error:`` message on stderr. The library (and numba, through
:mod:`murus.rocking`) is imported inside the commands, so that ``murus --help`` stays fast.
"""

from __future__ import annotations

import math

import typer

from murus import G
from murus.cliutil import dumps
from murus.cliutil import fail as _fail

app = typer.Typer(
    rich_markup_mode=None,
    name="design",
    help="Design of restrained rocking walls (EURODYN (2020)): tie rod, damper, resonance "
         "frequencies.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)

#: EURODYN (2020) unit weight 21 kN/m³ over g = 9.81 m/s² (same as ``restrained_wall_block``)
#: [kg/m³].
_RESTRAINED_WALL_DENSITY = 21000.0 / G

_BLOCK = typer.Option(None, "--block", help="EURODYN (2020) block: block1 ... block6 (Table 1).")
_WIDTH = typer.Option(None, "--width", help="Wall thickness b (s of EURODYN (2020)) [m].")
_HEIGHT = typer.Option(None, "--height", help="Wall height h [m].")
_THICK = typer.Option(1.0, "--thickness", help="Out-of-plane length of the wall [m].")
_DENSITY = typer.Option(_RESTRAINED_WALL_DENSITY, "--density",
                        help="Density [kg/m3] (default 21 kN/m3 / g, EURODYN (2020)).")
_TOP = typer.Option(0.0, "--top-mass", help="Lumped mass at mid-top [kg].")
_JSON = typer.Option(False, "--json", help="Print JSON instead of a table.")
_TIE_H = typer.Option(None, "--tie-height", help="Tie height above the base [m] (default: top).")
_MU = typer.Option(0.2, "--mu", help="Seismic multiplier mu of eq. 12 [-].")
_FU = typer.Option(430e6, "--fu", help="Ultimate strength f_uk of the tie steel [Pa] (S275).")
_LENGTH = typer.Option(10.0, "--length", help="Tie rod length L [m].")


def _errors():
    from murus.rocking.body import BodyError
    from murus.rocking.design import DesignError

    return (DesignError, BodyError, ValueError)


def _make_body(block, width, height, thickness, density, top_mass):
    from murus.rocking.body import RigidBlock, restrained_wall_block

    if block is not None:
        if width is not None or height is not None:
            raise ValueError("give either --block or --width/--height, not both")
        return restrained_wall_block(block)
    if width is None or height is None:
        raise ValueError("give the wall as --block block1..block6 or as --width and --height")
    from murus.config import check_physical

    for key, v in (("width", width), ("height", height), ("thickness", thickness),
                   ("density", density), ("top_mass", top_mass)):
        check_physical(key, v, "--" + key.replace("_", "-"))
    return RigidBlock(width=width, height=height, thickness=thickness, density=density,
                      top_mass=top_mass, name="wall")


def _fmt(v) -> str:
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return "none"
    if isinstance(v, float):
        return f"{v:.6g}"
    return str(v)


def _table(title: str, rows: list[tuple], notes: list[str] = ()) -> None:
    typer.echo(title)
    w = max(len(r[0]) for r in rows)
    wv = max(len(_fmt(r[1])) for r in rows)
    wu = max(len(r[2]) for r in rows)
    for name, value, unit, eq in rows:
        typer.echo(f"  {name:<{w}}  {_fmt(value):>{wv}}  {unit:<{wu}}  {eq}".rstrip())
    for n in notes:
        typer.echo(f"note: {n}")


def _json(obj) -> None:
    typer.echo(dumps(obj))


def _title(body) -> str:
    return (f"{body.name}: b = {body.width:g} m, h = {body.height:g} m, m = {body.mass:.6g} kg, "
            f"R = {body.R:.6g} m, alpha = {body.alpha:.6g} rad, I_O = {body.I_O:.6g} kg m2")


def _tie_rows(td) -> list[tuple]:
    return [
        ("W", td.W, "N", "m g"),
        ("h_t", td.tie_height, "m", "tie height"),
        ("T_d", td.T_d, "N", "EURODYN (2020), eq. 12"),
        ("sigma_d", td.sigma_d, "Pa", "0.7 f_uk / 1.05 (EURODYN (2020), §3)"),
        ("phi_required", td.phi_required * 1000.0, "mm", "T_d = sigma_d pi phi^2 / 4"),
        ("phi_d", td.phi_d * 1000.0, "mm", "commercial size" if td.commercial else "= required"),
        ("A", td.area, "m2", "pi phi_d^2 / 4"),
        ("K_d", td.K_d, "N/m", "E A / L"),
    ]


@app.command()
def tie(
    block: str | None = _BLOCK,
    width: float | None = _WIDTH,
    height: float | None = _HEIGHT,
    thickness: float = _THICK,
    density: float = _DENSITY,
    top_mass: float = _TOP,
    tie_height: float | None = _TIE_H,
    mu: float = _MU,
    fu: float = _FU,
    length: float = _LENGTH,
    commercial: bool = typer.Option(False, "--commercial",
                                    help="Round the diameter up to a commercial size."),
    as_json: bool = _JSON,
) -> None:
    """Steel tie rod by equilibrium (EURODYN (2020), eq. 12): T_d, diameter, stiffness K_d."""
    from murus.rocking.design import tie_design

    try:
        body = _make_body(block, width, height, thickness, density, top_mass)
        td = tie_design(body, tie_height, mu=mu, f_uk=fu, length=length,
                        round_to_commercial=commercial)
    except _errors() as exc:
        _fail(exc)
    if as_json:
        _json({"body": body.describe(), "tie": td.as_dict()})
        return
    _table(_title(body), _tie_rows(td), [] if td.needed else [td.message])


def _fractions(values: list[str] | None) -> list[float]:
    out = []
    for v in values or []:
        for part in v.split(","):
            if part.strip():
                try:
                    out.append(float(part))
                except ValueError:
                    raise ValueError(f"--fraction: {part.strip()!r} is not a number") from None
    return out


@app.command()
def damper(
    block: str | None = _BLOCK,
    width: float | None = _WIDTH,
    height: float | None = _HEIGHT,
    thickness: float = _THICK,
    density: float = _DENSITY,
    top_mass: float = _TOP,
    delta_t: float = typer.Option(..., "--delta-t", help="Characteristic time of the event [s]."),
    fraction: list[str] | None = typer.Option(
        None, "--fraction", help="Print c = fraction * c_d (repeat, or comma-separated)."),
    as_json: bool = _JSON,
) -> None:
    """Reference damping coefficient c_d = 2 m g delta_t / h (EURODYN (2020), eq. 13)."""
    from murus.rocking.design import reference_damping

    try:
        body = _make_body(block, width, height, thickness, density, top_mass)
        c_d = reference_damping(body, delta_t)
        fr = _fractions(fraction)
        for f in fr:
            if not (math.isfinite(f) and f >= 0.0):
                raise ValueError(f"--fraction must be a non-negative number, got {f!r}")
    except _errors() as exc:
        _fail(exc)
    if as_json:
        _json({"body": body.describe(), "delta_t": delta_t, "c_d": c_d,
               "c": [{"fraction": f, "c": f * c_d} for f in fr]})
        return
    rows = [("delta_t", delta_t, "s", "characteristic time"),
            ("c_d", c_d, "N s/m", "EURODYN (2020), eq. 13")]
    rows += [(f"c ({f:g} c_d)", f * c_d, "N s/m", "fraction of c_d") for f in fr]
    _table(_title(body), rows)


def _walls(text: str) -> tuple[float, float, float]:
    parts = [p.strip() for p in text.split(",")]
    try:
        vals = tuple(float(p) for p in parts)
    except ValueError:
        vals = ()
    if len(vals) != 3:
        raise ValueError(f"--walls must be three numbers E_x,t,L_eff, got {text!r}")
    return vals


@app.command()
def resonance(
    block: str | None = _BLOCK,
    width: float | None = _WIDTH,
    height: float | None = _HEIGHT,
    thickness: float = _THICK,
    density: float = _DENSITY,
    top_mass: float = _TOP,
    K: float | None = typer.Option(None, "--K", help="Tie stiffness K [N/m] (default K_d)."),
    K_over_Kd: float | None = typer.Option(None, "--K-over-Kd", help="Tie stiffness as K/K_d."),
    bed_stiffness: float | None = typer.Option(
        None, "--bed-stiffness", help="Spring bed stiffness K' [N/m/m] (default eq. 11)."),
    walls: str | None = typer.Option(
        None, "--walls", help="Transverse walls E_x,t,L_eff [Pa,m,m] for K' by eq. 10."),
    tie_height: float | None = _TIE_H,
    tie_x: float = typer.Option(0.0, "--tie-x",
                                help="Tie position across the wall [m] (0 = mid-thickness)."),
    bed_height: float | None = typer.Option(
        None, "--bed-height", help="Spring bed height h' for the linearised value [m] (h)."),
    mu: float = _MU,
    fu: float = _FU,
    length: float = _LENGTH,
    as_json: bool = _JSON,
) -> None:
    """Resonance frequencies of the restrained wall (EURODYN (2020), eq. 8, 9) and linearised
    values."""
    from murus.rocking.design import design_report

    try:
        body = _make_body(block, width, height, thickness, density, top_mass)
        if K is not None and K_over_Kd is not None:
            raise ValueError("give either --K or --K-over-Kd, not both")
        if bed_stiffness is not None and walls is not None:
            raise ValueError("give either --bed-stiffness or --walls, not both")
        rep = design_report(
            body, K=K, K_over_Kd=K_over_Kd, tie_height=tie_height, tie_x=tie_x,
            K_bed=bed_stiffness, walls=_walls(walls) if walls is not None else None,
            bed_height=bed_height, mu=mu, f_uk=fu, length=length,
        )
    except _errors() as exc:
        _fail(exc)
    st, res = rep["stiffness"], rep["resonance"]
    if as_json:
        _json({"body": rep["body"], "K_d": rep["tie"]["K_d"], "stiffness": st, "resonance": res})
        return
    tie = res["tie"]
    rows = [
        ("p", res["p"], "rad/s", "sqrt(m g R / I_O)"),
        ("R_t", tie["R_t"], "m", "pivot O to tie (eq. 2)"),
        ("alpha_t", tie["alpha_t"], "rad", "eq. 2"),
        ("K_d", rep["tie"]["K_d"], "N/m", "eq. 12"),
        ("K", st["K"], "N/m", st["K_source"]),
        ("K'", st["K_bed"], "N/m/m", st["K_bed_source"]),
        ("omega_r+", res["omega_plus"], "rad/s", "EURODYN (2020), eq. 8"),
        ("omega_r+ lin", res["omega_plus_lin"], "rad/s", "sqrt((K h_t^2 - m g z_G) / I_O)"),
        ("omega_r-", res["omega_minus"], "rad/s", "EURODYN (2020), eq. 9"),
        ("omega_r- lin", res["omega_minus_lin"], "rad/s",
         f"sqrt((K' h'^3/3 - m g z_G) / I_O), h' = {res['bed_height']:g} m"),
    ]
    notes = []
    if res["omega_plus"] is None or res["omega_minus"] is None:
        notes.append("none = the restraint is weaker than gravity (negative radicand): "
                     "no oscillation about theta = 0")
    _table(_title(body), rows, notes)

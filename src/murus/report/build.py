"""Builder of the one-page HTML report of an output folder (see :mod:`murus.report`)."""

from __future__ import annotations

import base64
import csv
import html
import json
import math
import re
import shlex
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

REPORT = "report.html"
"""Name of the report written into the folder."""

_MAX_ROWS = 60  # rows of a list-of-records table or a CSV head shown
_MAX_CSV_ROWS = 8
_MAX_FIGURES = 40
_MAX_TEXT = 20000  # characters of an echoed case file

# ----------------------------------------------------------------------------- references
#: References of the methods, keyed as in docs/references.md (references.bib).
REFERENCES = {
    "housner1963": "Housner, G. W. (1963). The behavior of inverted pendulum structures "
    "during earthquakes. Bulletin of the Seismological Society of America 53(2), 403-417. "
    "doi:10.1785/BSSA0530020403",
    "eurodyn2020": "(2020). Mitigation of amplified response of restrained rocking walls "
    "through horizontal dampers. EURODYN 2020, XI International Conference on Structural "
    "Dynamics (Athens), 4292-4303. doi:10.47964/1120.9351.20156",
    "mordant_series": "Mordant, C., Dietz, M. and Degée, H. Shaking-table tests of "
    "unreinforced clay masonry walls with and without acoustic rubber layers, and rigid-body "
    "rocking models. SERIES project, EQUALS laboratory, University of Bristol.",
    "savalle2022": "Savalle, N., Vincens, É., Hans, S. and Lourenço, P. B. (2022). Dynamic "
    "numerical simulations of dry-stone retaining walls: identification of the seismic "
    "behaviour factor. Geosciences 12(6), 252. doi:10.3390/geosciences12060252",
    "en1998_5": "CEN (2004). EN 1998-5:2004 Eurocode 8: Design of structures for earthquake "
    "resistance - Part 5: Foundations, retaining structures and geotechnical aspects.",
    "ntc2018": "Ministero delle Infrastrutture e dei Trasporti (2018). Aggiornamento delle "
    "«Norme tecniche per le costruzioni», D.M. 17 gennaio 2018 (NTC 2018).",
    "circolare2019": "Consiglio Superiore dei Lavori Pubblici (2019). Circolare 21 gennaio "
    "2019 n. 7 C.S.LL.PP., §C8.7.1.2.1 (local mechanisms) and §C7.2.3 (floor spectra).",
    "livesley1978": "Livesley, R. K. (1978). Limit analysis of structures formed from rigid "
    "blocks. International Journal for Numerical Methods in Engineering 12(12), 1853-1871. "
    "doi:10.1002/nme.1620121207",
    "gilbert2006": "Gilbert, M., Casapulla, C. and Ahmed, H. M. (2006). Limit analysis of "
    "masonry block structures with non-associative frictional joints using linear "
    "programming. Computers & Structures 84(13-14), 873-887. "
    "doi:10.1016/j.compstruc.2006.02.005",
    "cundall_strack1979": "Cundall, P. A. and Strack, O. D. L. (1979). A discrete numerical "
    "model for granular assemblies. Géotechnique 29(1), 47-65. doi:10.1680/geot.1979.29.1.47",
    "cundall1987": "Cundall, P. A. (1987). Distinct element models of rock and soil "
    "structure. Analytical and Computational Methods in Engineering Rock Mechanics, 129-163.",
    "marti_cundall1982": "Marti, J. and Cundall, P. A. (1982). Mixed discretization procedure "
    "for accurate modelling of plastic collapse. International Journal for Numerical and "
    "Analytical Methods in Geomechanics 6(1), 129-139. doi:10.1002/nag.1610060109",
    "itasca_flac": "Itasca Consulting Group. FLAC, Fast Lagrangian Analysis of Continua: "
    "Theory and Background; Constitutive Models (Mohr-Coulomb model); Dynamic Analysis. "
    "Itasca, Minneapolis.",
    "lysmer_kuhlemeyer1969": "Lysmer, J. and Kuhlemeyer, R. L. (1969). Finite dynamic model "
    "for infinite media. Journal of the Engineering Mechanics Division (ASCE) 95(EM4), "
    "859-877.",
    "fema_p695": "Federal Emergency Management Agency (2009). Quantification of Building "
    "Seismic Performance Factors. FEMA P695, Washington, DC.",
    "nigam_jennings1969": "Nigam, N. C. and Jennings, P. C. (1969). Calculation of response "
    "spectra from strong-motion earthquake records. Bulletin of the Seismological Society of "
    "America 59(2), 909-922. doi:10.1785/BSSA0590020909",
    "arias1970": "Arias, A. (1970). A measure of earthquake intensity. Seismic Design for "
    "Nuclear Power Plants, 438-483.",
    "trifunac_brady1975": "Trifunac, M. D. and Brady, A. G. (1975). A study on the duration "
    "of strong earthquake ground motion. Bulletin of the Seismological Society of America "
    "65(3), 581-626. doi:10.1785/BSSA0650030581",
    "rathje1998": "Rathje, E. M., Abrahamson, N. A. and Bray, J. D. (1998). Simplified "
    "frequency content estimates of earthquake ground motions. Journal of Geotechnical and "
    "Geoenvironmental Engineering 124(2), 150-159.",
    "baker2015": "Baker, J. W. (2015). Efficient analytical fragility function fitting using "
    "dynamic structural analysis. Earthquake Spectra 31(1), 579-599. "
    "doi:10.1193/021113EQS025M",
}


# ----------------------------------------------------------------------------- folder
@dataclass
class Folder:
    """What the report reads from an output folder (read once)."""

    path: Path
    manifest: dict = field(default_factory=dict)
    summary: dict | None = None
    study: dict | None = None

    @property
    def command(self) -> str:
        return str(self.manifest.get("command", ""))

    def files(self, suffix: str) -> list[Path]:
        out = []
        for p in sorted(self.path.rglob(f"*{suffix}")):
            rel = p.relative_to(self.path)
            if any(part.startswith(".") for part in rel.parts) or not p.is_file():
                continue
            out.append(p)
        return out


def _read_json(p: Path):
    try:
        return json.loads(p.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None


def _folder(path) -> Folder:
    from murus.outputs import MANIFEST

    path = Path(path)
    if not path.is_dir():
        from murus.outputs import OutputError

        raise OutputError(f"{path}: not a folder (murus report takes an output folder)")
    manifest = _read_json(path / MANIFEST)
    summary = _read_json(path / "summary.json")
    study = _read_json(path / "study.json")
    return Folder(path, manifest if isinstance(manifest, dict) else {},
                  summary if isinstance(summary, dict) else None,
                  study if isinstance(study, dict) else None)


# ----------------------------------------------------------------------------- kinds
@dataclass(frozen=True)
class Kind:
    """One kind of output folder: how to recognise it, its title, the units of its summary,
    its verdicts and the references of its methods."""

    name: str
    title: str
    match: Callable[[Folder], bool]
    references: tuple[str, ...] | Callable[[Folder], tuple] = ()
    units: Callable[[Folder], dict] = lambda f: {}
    verdicts: Callable[[Folder], list] = lambda f: []


def _s(f: Folder) -> dict:
    return f.summary or {}


def _cmd_has(f: Folder, *words: str) -> bool:
    return all(w in f.command.split() for w in words)


def _rocking_units(f: Folder) -> dict:
    from murus.rocking.summary import SUMMARY, WINKLER_SUMMARY

    units = {"alpha": "rad", "p": "rad/s", "restitution": "1", "theta_max_over_alpha": "1",
             "uplift_intervals": "s"}
    for q in (*WINKLER_SUMMARY, *SUMMARY):
        for name in (q.name, *q.aliases):
            units[name] = q.units
    return units


def _rocking_verdicts(f: Folder) -> list:
    s = _s(f)
    out = []
    if "overturned" in s:
        t = s.get("t_overturn")
        out.append(("overturned" if s["overturned"] else "not overturned",
                    not s["overturned"],
                    f"at t = {_num(t)} s" if s["overturned"] and t is not None else
                    f"theta_max/alpha = {_num(s.get('theta_max_over_alpha'))}"))
    for name, reached in (s.get("limit_states") or {}).items():
        out.append((f"limit state {name}", "warn" if reached else True,
                    "reached" if reached else "not reached"))
    if s.get("status") not in (None, "ok", 0):
        out.append(("integration", False, f"status {s.get('status')}"))
    return out


def _mechanism_units(f: Folder) -> dict:
    return {"alpha0": "1", "e_star": "1", "ratio": "1", "FC": "1", "q": "1",
            "a0_star": "m/s2", "d0_star": "m", "activation_ratio_SLV": "1",
            **(_s(f).get("units") or {})}


def _mechanism_verdicts(f: Folder) -> list:
    s = _s(f)
    out = []
    if "passed" in s:
        g = s.get("governing") or {}
        out.append(("façade check", bool(s["passed"]),
                    f"governing: {g.get('name', '-')}, ratio {_num(g.get('ratio'))}"))
    for m in s.get("mechanisms") or []:
        if isinstance(m, dict) and "passed" in m:
            out.append((str(m.get("name", "mechanism")), bool(m["passed"]),
                        f"capacity/demand = {_num(m.get('ratio'))}"))
    return out


def _limit_verdicts(f: Folder) -> list:
    s = _s(f)
    out = [("load factor", "info", f"{_num(s.get('load_factor'))} "
            f"({s.get('load', '')} load, {s.get('friction', '')} friction)")]
    if "converged" in s:
        out.append(("solver", bool(s["converged"]),
                    "converged" if s["converged"] else "not converged"))
    return out


_DEM_UNITS = {"t_end": "s", "dt": "s", "wall_time_s": "s", "height": "m", "steps": "1",
              "bodies": "1", "energy_error": "1", "ratio": "1", "zones": "1",
              "gridpoints": "1", "plastic_zones": "1", "ever_plastic_zones": "1"}


def _dem_verdicts(f: Folder) -> list:
    s = _s(f)
    ok = s.get("ok", s.get("status") in ("completed", "stopped"))
    return [("run", bool(ok), f"{s.get('status', '')} {s.get('message', '')}".strip())]


_RETAINING_UNITS = {"A_col": "m/s2", "A_pseudo": "m/s2", "A_peak": "m/s2", "a_peak": "m/s2",
                    "A_rate": "m/s3", "t_col": "s", "r": "1", "frequency": "Hz", "H": "m",
                    "B": "m", "height": "m", "d_top": "m", "threshold": "m", "t_max": "s",
                    "t_end": "s", "t_pseudo": "s", "run_time_s": "s", "wall_time": "s",
                    "wall_time_s": "s", "dt": "s", "steps": "1", "stiffness_scale": "1",
                    "xi": "1", "width": "m", "stone_height": "m", "stone_length": "m",
                    "kn": "Pa/m", "ks": "Pa/m", "foundation_depth": "m",
                    "foundation_front": "m", "update_dt": "s", "sample_dt": "s",
                    "motion_dt": "s", "threshold_fraction": "1", "vertical_ratio": "1",
                    "thrust_scale": "1", "settle_steps": "1",
                    "d_top_max": "m"}


def _retaining_verdicts(f: Folder) -> list:
    s = _s(f)
    out = []
    for key in ("collapsed", "collapse"):
        if key in s:
            out.append(("collapse", not s[key],
                        f"collapsed at t_col = {_num(s.get('t_col'))} s, A_col = "
                        f"{_num(s.get('A_col'))} m/s2" if s[key] else "no collapse"))
            break
    else:
        if s.get("t_col") is not None:
            out.append(("collapse", False, f"collapsed at t_col = {_num(s.get('t_col'))} s, "
                        f"A_col = {_num(s.get('A_col'))} m/s2"))
    return out


def _study_kind(f: Folder) -> str:
    spec = (f.study or {}).get("spec") or {}
    sweep = spec.get("sweep") if isinstance(spec.get("sweep"), dict) else {}
    return "fragility" if spec.get("im") or "im" in sweep else "spectrum"


def _bf_verdicts(f: Folder) -> list:
    try:
        with open(f.path / "behaviour_factor.csv", newline="", encoding="utf-8") as fh:
            rows = list(csv.DictReader(ln for ln in fh if not ln.startswith("#")))
    except OSError:
        return []
    out = []
    for r in rows:
        label = f"{r.get('wall', '')} {r.get('frequency_Hz', '')} Hz".strip()
        if r.get("r"):
            out.append((f"{label}: behaviour factor", "info",
                        f"r = A_peak/A_pseudo = {r['r']}, A_col = {r.get('A_col_m_s2', '-')} "
                        "m/s2"))
        for k, v in r.items():
            if k and k.startswith("S1_") and v:
                out.append((f"{label}: {k}", v.strip().lower() == "stable", v))
    return out


def _study_refs(f: Folder) -> tuple:
    base = ("housner1963", "eurodyn2020", "fema_p695")
    return (*base, "baker2015") if _study_kind(f) == "fragility" else base


def _study_verdicts(f: Folder) -> list:
    try:
        import xarray as xr

        with xr.open_dataset(f.path / "result.nc") as ds:
            out = []
            if "overturned" in ds:
                v = ds["overturned"].values
                n = int((v == 1).sum())
                out.append(("overturned", "info", f"{n} of {v.size} histories"))
            nf = int(ds.attrs.get("n_failed_chunks", 0) or 0)
            out.append(("study", nf == 0, "complete" if nf == 0 else f"{nf} failed chunks"))
            return out
    except Exception:  # noqa: BLE001 - a report never fails on an unreadable result
        return []


def _motion_verdicts(f: Folder) -> list:
    m = _read_json(f.path / "measures.json")
    if not isinstance(m, dict):
        return []
    units = m.get("units") if isinstance(m.get("units"), dict) else {}
    return [(key.upper().replace("_", "-"), "info", f"{_num(m[key])} {units.get(key, '')}")
            for key in ("pga", "pgv", "d5_95") if isinstance(m.get(key), (int, float))]


def _lab_verdicts(f: Folder) -> list:
    s = _s(f)
    out = []
    evo = [e for e in s.get("evolution") or [] if isinstance(e, dict) and "f1_hz" in e]
    if len(evo) >= 2:
        f0, f1 = evo[0]["f1_hz"], evo[-1]["f1_hz"]
        drop = f" ({100 * (1 - f1 / f0):.0f} % drop)" if f0 else ""
        out.append(("first frequency", "info", f"{_num(f0)} Hz ({evo[0].get('test', '')}) "
                    f"-> {_num(f1)} Hz ({evo[-1].get('test', '')}){drop}"))
    classes = [c for c in s.get("classification") or [] if isinstance(c, dict)]
    if classes:
        last = classes[-1]
        out.append(("response", "info", f"{last.get('class', '-')} at the last test "
                    f"({last.get('test', '')})"))
    return out


KINDS: tuple[Kind, ...] = (
    Kind("rocking", "Rocking run of a rigid wall",
         lambda f: "theta_max" in _s(f),
         ("housner1963", "eurodyn2020", "mordant_series"), _rocking_units, _rocking_verdicts),
    Kind("mechanism", "Local mechanisms of a façade",
         lambda f: "mechanisms" in _s(f) and "governing" in _s(f),
         ("circolare2019", "ntc2018"), _mechanism_units, _mechanism_verdicts),
    Kind("limit", "Limit analysis of a block structure",
         lambda f: "load_factor" in _s(f),
         ("livesley1978", "gilbert2006"), lambda f: dict(_s(f).get("units") or {}),
         _limit_verdicts),
    Kind("retaining-collapse", "Collapse run of a dry-stone retaining wall",
         lambda f: "A_col" in _s(f) or _cmd_has(f, "retaining", "collapse"),
         ("savalle2022", "en1998_5", "cundall1987"), lambda f: dict(_RETAINING_UNITS),
         _retaining_verdicts),
    Kind("retaining-behaviour-factor", "Behaviour factor of dry-stone retaining walls",
         lambda f: (f.study or {}).get("kind") == "retaining.behaviour_factor",
         ("savalle2022", "en1998_5", "cundall1987"), lambda f: dict(_RETAINING_UNITS),
         _bf_verdicts),
    Kind("rocking-study", "Rocking study (spectrum or fragility)",
         lambda f: f.study is not None and (f.path / "result.nc").is_file(),
         _study_refs, _rocking_units,
         _study_verdicts),
    Kind("lab-sequence", "Shaking-table test sequence",
         lambda f: (f.path / "report.md").is_file() and _cmd_has(f, "lab")
         or (f.path / "report.md").is_file() and "frequency.png" in
         {p.name for p in f.path.iterdir()},
         ("mordant_series",), lambda f: {}, _lab_verdicts),
    Kind("motion-record", "Ground motion record",
         lambda f: (f.path / "measures.json").is_file() and (f.path / "record.png").is_file(),
         ("nigam_jennings1969", "arias1970", "trifunac_brady1975", "rathje1998"),
         lambda f: {}, _motion_verdicts),
    Kind("continuum", "Continuum (zones) run",
         lambda f: "zones" in _s(f) and "gridpoints" in _s(f),
         ("marti_cundall1982", "itasca_flac", "lysmer_kuhlemeyer1969"),
         lambda f: dict(_DEM_UNITS), _dem_verdicts),
    Kind("dem", "Distinct-element run",
         lambda f: "steps" in _s(f) and "bodies" in _s(f),
         ("cundall_strack1979", "cundall1987"), lambda f: dict(_DEM_UNITS), _dem_verdicts),
    Kind("folder", "murus output folder", lambda f: True),
)


def detect(folder) -> str:
    """Name of the kind of the output folder ``folder`` (one of :data:`KINDS`).

    Parameters
    ----------
    folder : path-like
        An output folder of murus.

    Returns
    -------
    str
        ``"rocking"``, ``"mechanism"``, ``"limit"``, ``"retaining-collapse"``,
        ``"retaining-behaviour-factor"``, ``"rocking-study"``, ``"lab-sequence"``,
        ``"motion-record"``, ``"continuum"``, ``"dem"``, or ``"folder"`` (no known kind: the
        generic report).
    """
    f = _folder(folder)
    return _kind(f).name


def _kind(f: Folder) -> Kind:
    return next(k for k in KINDS if k.match(f))


# ----------------------------------------------------------------------------- HTML pieces
def _e(x) -> str:
    return html.escape(str(x), quote=True)


def _num(x) -> str:
    if isinstance(x, bool) or x is None:
        return "-" if x is None else str(x).lower()
    if isinstance(x, int):
        return str(x)
    if isinstance(x, float):
        if not math.isfinite(x):
            return str(x)
        if x != 0 and (abs(x) < 1e-3 or abs(x) >= 1e6):
            return f"{x:.4g}"
        return f"{x:.4g}" if abs(x) < 10 else f"{x:.6g}"
    return str(x)


#: Units named by the suffix of a key (``f1_hz``, ``t_min_s``, ``pga_nominal_g``): the
#: convention of the CSV columns and JSON keys of murus (README "Conventions").
_SUFFIX_UNITS = {"hz": "Hz", "g": "g", "rad": "rad", "mm": "mm", "m": "m", "s": "s",
                 "pa": "Pa", "kg": "kg", "percent": "%", "deg": "deg", "kn": "kN", "n": "N",
                 "m_s2": "m/s2", "m_s": "m/s", "rad_s": "rad/s", "j": "J"}


def _unit(units: dict, key: str) -> str:
    last = key.split(".")[-1]
    for k in (key, last, re.sub(r"\[\d+\]", "", key)):
        if k in units:
            u = units[k]
            return "-" if u in ("1", "") else u
    for suffix in sorted(_SUFFIX_UNITS, key=len, reverse=True):
        if last.endswith("_" + suffix) and len(last) > len(suffix) + 1:
            return _SUFFIX_UNITS[suffix]
    return ""


def _flatten(d: dict, prefix: str = "") -> tuple[list, list]:
    """Scalars of a nested mapping as (key, value) rows; lists of mappings apart."""
    rows, tables = [], []
    for k, v in d.items():
        key = f"{prefix}{k}"
        if isinstance(v, dict):
            r, t = _flatten(v, key + ".")
            rows += r
            tables += t
        elif isinstance(v, list) and v and all(isinstance(x, dict) for x in v):
            tables.append((key, v))
        elif isinstance(v, list):
            rows.append((key, _list_text(v)))
        else:
            rows.append((key, v))
    return rows, tables


def _list_text(v: list) -> str:
    nums = [x for x in v if isinstance(x, (int, float)) and not isinstance(x, bool)]
    if len(v) > 6 and len(nums) == len(v):
        return f"{len(v)} values, {_num(min(nums))} .. {_num(max(nums))}"
    text = json.dumps(v)
    return text if len(text) < 160 else text[:160] + " ..."


def _kv_table(rows: list, units: dict) -> str:
    if not rows:
        return ""
    body = "".join(f"<tr><th>{_e(k)}</th><td class=num>{_e(_num(v))}</td>"
                   f"<td>{_e(_unit(units, k))}</td></tr>" for k, v in rows)
    return ("<table class=kv><thead><tr><th>quantity</th><th>value</th><th>units</th></tr>"
            f"</thead><tbody>{body}</tbody></table>")


def _records_table(name: str, recs: list, units: dict) -> str:
    cols: list[str] = []
    flat, nested = [], []
    for i, r in enumerate(recs[:_MAX_ROWS]):
        rows, tables = _flatten(r)
        flat.append(dict(rows))
        label = r.get("name", r.get("label", i)) if isinstance(r, dict) else i
        nested += [(f"{name}: {label}: {k}", v) for k, v in tables]
        for k, _v in rows:
            if k not in cols:
                cols.append(k)
    head = "".join(f"<th>{_e(c)}" + (f" [{_e(_unit(units, c))}]" if _unit(units, c) else "")
                   + "</th>" for c in cols)
    body = "".join("<tr>" + "".join(f"<td class=num>{_e(_num(r.get(c, '')))}</td>"
                                    for c in cols) + "</tr>" for r in flat)
    more = (f"<p class=note>{len(recs) - _MAX_ROWS} more rows in the JSON file.</p>"
            if len(recs) > _MAX_ROWS else "")
    return (f"<h3>{_e(name)}</h3><div class=wide><table><thead><tr>{head}</tr></thead>"
            f"<tbody>{body}</tbody></table></div>{more}"
            + "".join(_records_table(k, v, units) for k, v in nested[:_MAX_ROWS]))


def _json_section(title: str, data, units: dict) -> str:
    if isinstance(data, list) and data and all(isinstance(x, dict) for x in data):
        return _records_table(title, data, units)
    if not isinstance(data, dict):
        return f"<h3>{_e(title)}</h3><pre>{_e(json.dumps(data, indent=1)[:_MAX_TEXT])}</pre>"
    rows, tables = _flatten(data)
    out = f"<h3>{_e(title)}</h3>" + _kv_table(rows, units)
    out += "".join(_records_table(f"{title}: {k}", v, units) for k, v in tables)
    return out


def _csv_head(p: Path, rel: str) -> str:
    try:
        with open(p, newline="", encoding="utf-8", errors="replace") as fh:
            lines = [ln for ln in fh if not ln.startswith("#")]
        rows = list(csv.reader(lines[:_MAX_CSV_ROWS + 1]))
    except OSError:
        return ""
    if not rows:
        return ""
    head = "".join(f"<th>{_e(c)}</th>" for c in rows[0])
    body = "".join("<tr>" + "".join(f"<td class=num>{_e(c)}</td>" for c in r) + "</tr>"
                   for r in rows[1:])
    n = len(lines) - 1
    return (f"<h3>{_e(rel)}</h3><div class=wide><table><thead><tr>{head}</tr></thead>"
            f"<tbody>{body}</tbody></table></div>"
            f"<p class=note>first {len(rows) - 1} of {n} rows.</p>")


def _figure(p: Path, rel: str) -> str:
    data = base64.b64encode(p.read_bytes()).decode("ascii")
    return (f"<figure><img alt=\"{_e(rel)}\" src=\"data:image/png;base64,{data}\">"
            f"<figcaption>{_e(rel)}</figcaption></figure>")


def _markdown(text: str) -> str:
    """A small Markdown subset (headings, pipe tables, lists, paragraphs) as HTML: enough
    for the Markdown reports murus writes (``murus lab sequence``, behaviour factors)."""
    out, table, para, items = [], [], [], []

    def flush():
        if table:
            rows = [[c.strip() for c in r.strip().strip("|").split("|")] for r in table
                    if not re.fullmatch(r"\s*\|?[\s:|-]+\|?\s*", r)]
            if rows:
                head = "".join(f"<th>{_e(c)}</th>" for c in rows[0])
                body = "".join("<tr>" + "".join(f"<td>{_e(c)}</td>" for c in r) + "</tr>"
                               for r in rows[1:])
                out.append(f"<div class=wide><table><thead><tr>{head}</tr></thead>"
                           f"<tbody>{body}</tbody></table></div>")
            table.clear()
        if para:
            out.append(f"<p>{_e(' '.join(para))}</p>")
            para.clear()
        if items:
            out.append("<ul>" + "".join(f"<li>{_e(i)}</li>" for i in items) + "</ul>")
            items.clear()

    for line in text.splitlines():
        s = line.strip()
        m = re.match(r"(#{1,6})\s+(.*)", s)
        if s.startswith("|"):
            if para or items:
                flush()
            table.append(s)
            continue
        if table:
            flush()
        if m:
            flush()
            level = min(len(m.group(1)) + 2, 6)
            out.append(f"<h{level}>{_e(m.group(2))}</h{level}>")
        elif re.match(r"[-*]\s+", s):
            if para:
                flush()
            items.append(s[2:].strip())
        elif s.startswith("![") or not s:
            flush()
        else:
            if items:
                flush()
            para.append(s)
    flush()
    return "".join(out)


_CSS = """
body{font-family:"DejaVu Sans",Helvetica,Arial,sans-serif;font-size:13px;color:#222;
 margin:24px auto;max-width:1100px;padding:0 16px;background:#fff}
h1{font-size:22px;margin:0 0 4px}h2{font-size:17px;border-bottom:1px solid #bbb;
 margin-top:26px}h3{font-size:14px;margin:16px 0 6px}
.meta{color:#555}table{border-collapse:collapse;margin:6px 0;font-size:12px}
th,td{border:1px solid #ccc;padding:2px 6px;text-align:left;vertical-align:top}
thead th{background:#eef1f5}td.num{font-variant-numeric:tabular-nums}
table.kv th{font-weight:normal;background:#f7f7f7}
pre{background:#f6f6f6;border:1px solid #ddd;padding:8px;font-size:11px;
 white-space:pre-wrap;word-break:break-word}
.verdicts{display:flex;flex-wrap:wrap;gap:8px}
.v{border-radius:4px;padding:6px 10px;border:1px solid}
.v b{margin-right:6px}.pass{background:#e6f4ea;border-color:#2e7d32;color:#1b5e20}
.fail{background:#fdecea;border-color:#c62828;color:#8e0000}
.warn{background:#fff4e0;border-color:#e65100;color:#8a3b00}
.info{background:#eef3fb;border-color:#1f5fa8;color:#123c6b}
figure{margin:10px 0;text-align:center}figure img{max-width:100%;height:auto}
figcaption{color:#555;font-size:11px}.note{color:#666;font-size:11px}
.wide{overflow-x:auto}.warnline{color:#8a3b00}ol.refs li{margin-bottom:4px}
@media print{@page{size:A4;margin:15mm}body{margin:0;max-width:none;font-size:10.5px}
 figure,table,pre,.v,tr{break-inside:avoid;page-break-inside:avoid}
 h2,h3{break-after:avoid;page-break-after:avoid}.wide{overflow:visible}
 table{font-size:9px;max-width:100%}td,th{word-break:break-word}
 figure img{max-height:230mm}}
"""


def _case_files(f: Folder) -> list[Path]:
    """Case files named on the recorded command line that still exist (TOML, JSON)."""
    try:
        args = shlex.split(f.command)
    except ValueError:
        return []
    out = []
    for a in args[1:]:
        p = Path(a)
        if p.suffix.lower() in (".toml", ".json") and p.is_file():
            out.append(p)
    return out


def _changed_after_run(p: Path, when) -> bool:
    """True when ``p`` was modified after the manifest's time (UTC, to the second)."""
    import calendar
    import time

    try:
        t = calendar.timegm(time.strptime(str(when), "%Y-%m-%dT%H:%M:%SZ"))
        return p.stat().st_mtime > t + 1
    except (ValueError, OSError):
        return False


def _input_section(f: Folder) -> str:
    parts = []
    if f.command:
        parts.append(f"<p>Command: <code>{_e(f.command)}</code>"
                     + (f" ({_e(f.manifest.get('time', ''))})" if f.manifest.get("time")
                        else "") + "</p>")
    for p in _case_files(f):
        try:
            text = p.read_text(encoding="utf-8", errors="replace")
        except OSError:
            continue
        note = ""
        if _changed_after_run(p, f.manifest.get("time")):
            note = ("<p class=\"note warnline\">This file was modified after the run: it may "
                    "not be the input of these results.</p>")
        parts.append(f"<h3>{_e(p.name)}</h3>{note}<pre>{_e(text[:_MAX_TEXT])}</pre>")
    s = f.summary or {}
    if not _case_files(f) and isinstance(s.get("input"), dict):
        parts.append("<h3>input (recorded in summary.json)</h3>"
                     f"<pre>{_e(json.dumps(s['input'], indent=1)[:_MAX_TEXT])}</pre>")
    if f.study and "spec" in f.study:
        parts.append("<h3>study specification (study.json)</h3>"
                     f"<pre>{_e(json.dumps(f.study['spec'], indent=1)[:_MAX_TEXT])}</pre>")
    if not parts:
        parts.append("<p class=note>This folder records no command line or case file.</p>")
    return "<h2>Input</h2>" + "".join(parts)


def _netcdf_section(p: Path, rel: str, units: dict) -> str:
    try:
        import numpy as np
        import xarray as xr

        with xr.open_dataset(p) as ds:
            dims = ", ".join(f"{k}: {v}" for k, v in ds.sizes.items())
            rows = []
            for name, var in ds.variables.items():
                u = var.attrs.get("units", "") or _unit(units, str(name))
                vals = var.values
                stat = ""
                if vals.dtype.kind in "fiu" and vals.size:
                    fin = vals[np.isfinite(vals)] if vals.dtype.kind == "f" else vals
                    stat = (f"{_num(float(fin.min()))} .. {_num(float(fin.max()))}"
                            if fin.size else "all NaN")
                elif vals.size:
                    stat = ", ".join(str(x) for x in vals.ravel()[:6])
                rows.append(f"<tr><th>{_e(name)}</th><td>{_e(', '.join(var.dims))}</td>"
                            f"<td>{_e('-' if u == '1' else u)}</td>"
                            f"<td>{_e(var.attrs.get('long_name', ''))}</td>"
                            f"<td class=num>{_e(stat)}</td></tr>")
            attrs = "".join(f"<tr><th>{_e(k)}</th><td>{_e(str(v)[:300])}</td></tr>"
                            for k, v in ds.attrs.items() if k != "study")
        return (f"<h3>{_e(rel)}</h3><p>dimensions: {_e(dims)}</p><div class=wide><table>"
                "<thead><tr><th>variable</th><th>dims</th><th>units</th><th>description</th>"
                f"<th>range</th></tr></thead><tbody>{''.join(rows)}</tbody></table></div>"
                f"<table class=kv><tbody>{attrs}</tbody></table>")
    except Exception as exc:  # noqa: BLE001 - a report never fails on an unreadable file
        return f"<h3>{_e(rel)}</h3><p class=note>not readable here: {_e(exc)}</p>"


#: CSS class and label of a verdict: passed, failed, a limit state reached, information.
_STATUS = {"pass": ("pass", "PASS"), "fail": ("fail", "FAIL"), "warn": ("warn", "REACHED"),
           "info": ("info", "RESULT")}


def _status(ok) -> str:
    return ok if isinstance(ok, str) else ("pass" if ok else "fail")


def _fragility_section(p: Path) -> str:
    """The lognormal fragilities of a study with an intensity dimension ``im`` (maximum
    likelihood over the stripes, :func:`murus.studies.fragility.fit_fragility`, no confidence
    intervals: they take seconds; ``murus study plot`` draws them)."""
    try:
        import xarray as xr

        from murus.studies.fragility import fit_fragility

        with xr.open_dataset(p) as ds:
            if "im" not in ds.dims or "overturned" not in ds:
                return ""
            fit = fit_fragility(ds.load(), ci="none")
        unit = fit["fragility_median"].attrs.get("units", "")
        df = fit[["fragility_median", "fragility_beta", "fragility_status"]].to_dataframe()
    except Exception as exc:  # noqa: BLE001 - a report never fails on a fit
        return f"<p class=note>fragility fit not available here: {_e(exc)}</p>"
    names = list(df.index.names)
    head = "".join(f"<th>{_e(n)}</th>" for n in names)
    body = "".join(
        "<tr>" + "".join(f"<td>{_e(v)}</td>" for v in (i if isinstance(i, tuple) else (i,)))
        + f"<td class=num>{_e(_num(float(r.fragility_median)))}</td>"
        f"<td class=num>{_e(_num(float(r.fragility_beta)))}</td>"
        f"<td>{_e(r.fragility_status)}</td></tr>" for i, r in df.iterrows())
    return ("<h3>fragility (lognormal, maximum likelihood over the stripes; Baker 2015)</h3>"
            f"<table><thead><tr>{head}<th>median [{_e(unit)}]</th><th>beta [-]</th>"
            f"<th>status</th></tr></thead><tbody>{body}</tbody></table>")


def build_report(folder) -> str:
    """The one-page HTML report of the murus output folder ``folder``.

    Parameters
    ----------
    folder : path-like
        An output folder of a murus command.

    Returns
    -------
    str
        Self-contained HTML (inline CSS with a print style sheet, PNG figures as base64
        ``data:`` URIs, no external resources).

    Raises
    ------
    murus.outputs.OutputError
        ``folder`` is not a folder.
    """
    f = _folder(folder)
    kind = _kind(f)
    units = kind.units(f)
    title = (f.summary or {}).get("title") or (f.study or {}).get("name") or f.path.name
    parts = [f"<h1>{_e(kind.title)}: {_e(title)}</h1>",
             f"<p class=meta>folder <code>{_e(f.path.resolve())}</code>; kind "
             f"<code>{_e(kind.name)}</code>; units SI unless stated (\"-\": dimensionless)"
             "</p>"]
    verdicts = kind.verdicts(f)
    # runs in sub-folders (``murus demo``: one folder per case): their kinds' units,
    # verdicts and references
    subs = {}
    if kind.name == "folder":
        for p in sorted(f.path.glob("*/summary.json")):
            sub = _folder(p.parent)
            k = _kind(sub)
            if k.name != "folder":
                subs[p.parent.name] = (sub, k)
                verdicts += [(f"{p.parent.name}: {label}", ok, text)
                             for label, ok, text in k.verdicts(sub)]
    if verdicts:
        items = "".join(
            f"<div class=\"v {_STATUS[_status(ok)][0]}\"><b>{_STATUS[_status(ok)][1]}</b>"
            f"{_e(label)}: {_e(text)}</div>" for label, ok, text in verdicts)
        parts.append(f"<h2>Verdicts</h2><div class=verdicts>{items}</div>")
    parts.append(_input_section(f))

    parts.append("<h2>Results</h2>")
    skip = {REPORT}
    for p in f.files(".json"):
        rel = p.relative_to(f.path).as_posix()
        if rel in skip or rel == "study.json" or (f.study is not None and "/" in rel):
            continue
        data = f.summary if rel == "summary.json" else _read_json(p)
        if data is None:
            continue
        own = units
        if rel.count("/") == 1 and rel.split("/")[0] in subs:
            sub, k = subs[rel.split("/")[0]]
            own = k.units(sub)
        if isinstance(data, dict):  # units a file declares itself (a "units" mapping)
            if isinstance(data.get("units"), dict):
                own = {**units, **{str(k): str(v) for k, v in data["units"].items()}}
            data = {k: v for k, v in data.items()
                    if k != "units" and not (p.name == "summary.json" and k == "input")}
        parts.append(_json_section(rel, data, own))
    for p in f.files(".nc"):
        parts.append(_netcdf_section(p, p.relative_to(f.path).as_posix(), units))
        if kind.name == "rocking-study" and _study_kind(f) == "fragility":
            parts.append(_fragility_section(p))
    for p in f.files(".md"):
        rel = p.relative_to(f.path).as_posix()
        if "/" in rel:
            continue
        try:
            parts.append(f"<h3>{_e(rel)}</h3>" + _markdown(p.read_text(encoding="utf-8")))
        except OSError:
            pass
    csvs = [p for p in f.files(".csv") if f.study is None
            or "/" not in p.relative_to(f.path).as_posix()]
    if csvs:
        parts.append("<h2>Tables</h2>")
        parts += [_csv_head(p, p.relative_to(f.path).as_posix()) for p in csvs[:_MAX_ROWS]]

    pngs = f.files(".png")
    if pngs:
        parts.append("<h2>Figures</h2>")
        parts += [_figure(p, p.relative_to(f.path).as_posix()) for p in pngs[:_MAX_FIGURES]]
        if len(pngs) > _MAX_FIGURES:
            parts.append(f"<p class=note>{len(pngs) - _MAX_FIGURES} more figures in the "
                         "folder.</p>")

    keys = []
    for k, fo in [(kind, f), *((k, sub) for sub, k in subs.values())]:
        for key in k.references(fo) if callable(k.references) else k.references:
            if key not in keys:
                keys.append(key)
    refs = [REFERENCES[k] for k in keys]
    parts.append("<h2>References</h2>")
    if refs:
        parts.append("<ol class=refs>" + "".join(f"<li>{_e(r)}</li>" for r in refs)
                     + "</ol>")
    else:
        parts.append("<p class=note>No method recognised; see docs/references.md.</p>")
    from murus import __version__

    parts.append(f"<p class=note>Written by murus {_e(__version__)} "
                 "(<code>murus report</code>).</p>")
    return ("<!DOCTYPE html>\n<html lang=en><head><meta charset=utf-8>"
            f"<title>{_e(kind.title)}: {_e(title)}</title>"
            "<meta name=viewport content=\"width=device-width, initial-scale=1\">"
            f"<style>{_CSS}</style></head><body>\n" + "\n".join(parts)
            + "\n</body></html>\n")


def write_report(folder) -> Path:
    """Write :func:`build_report` as ``folder/report.html`` (atomically, recorded as murus's
    own: in the folder's manifest, or in its list of murus files when it has none).

    A ``report.html`` that murus did not write is never overwritten.

    Parameters
    ----------
    folder : path-like
        An output folder of murus.

    Returns
    -------
    Path
        The report file.

    Raises
    ------
    murus.outputs.OutputError
        ``folder`` is not a folder, or holds a ``report.html`` murus did not write.
    """
    from murus.outputs import add_to_folder

    text = build_report(folder)
    return add_to_folder(folder, REPORT, text)

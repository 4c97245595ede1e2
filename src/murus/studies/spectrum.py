"""Rocking spectra (EURODYN (2020), §4.1, Figures 3-4) and overturning maps.

A rocking spectrum is the largest normalised rotation ``theta_max / alpha`` of one geometry under
one record as a function of the restraint: EURODYN (2020) sweeps the tie stiffness ``K`` over
``0 <= K <= K_d`` (50 values; ``K_d`` from eq. 12), with a tension-only tie at the top and the
transverse walls as a spring bed whose stiffness follows the tie by eq. 11 (one-sided motion),
Housner's restitution, and reads the curves against the limit states of limited (0.1) and
moderate (0.4) rocking and against the free-standing response. At ``K = 0`` eq. 11 gives
``K' = 0``: the wall is free-standing and rocks two-sided.

The same machinery sweeps any other parameter of the restraint or of the input: damper
coefficient as a fraction of ``c_d`` (eq. 13; EURODYN (2020), Figure 10), record scale factor, or
the frequency ratio ``omega_p / p`` of a pulse.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from murus.rocking.defaults import RTOL
from murus.rocking.summary import LIMIT_STATES as _ROCKING_LIMIT_STATES
from murus.studies.records import RecordSet

__all__ = ["rocking_spectrum", "spectrum_case", "plot_rocking_spectrum", "plot_overturning_map",
           "LIMIT_STATES"]

#: Limit states on theta_max / alpha (declared once: :data:`murus.rocking.summary.LIMIT_STATES`,
#: EURODYN (2020), §4).
LIMIT_STATES = _ROCKING_LIMIT_STATES

#: The 50 stiffness ratios of EURODYN (2020), §4.1 (0 <= K <= K_d).
TIE_STIFFNESS_RATIOS = np.linspace(0.0, 1.0, 50)


def spectrum_case(body, *, walls="eq11", restitution="housner", tie_height=None,
                  tension_only: bool = True, c_over_cd=None, delta_t=None, damper_height=None,
                  duration=None, rtol: float = RTOL) -> dict:
    """The rocking case (tables as a dict) of EURODYN (2020), §4.1 for ``body`` (a RigidBlock).

    walls:
        ``"eq11"`` (spring bed from the tie, EURODYN (2020), eq. 11), ``"rigid"``, or a stiffness
        [N/m/m] (e.g. 4.5e8, eq. 10 in §4.2).
    restitution:
        ``"housner"`` or a number (constant coefficient).
    c_over_cd, delta_t:
        A damper at ``damper_height`` (default the top) with ``c = c_over_cd * c_d`` (eq. 13,
        characteristic time ``delta_t`` [s]).

    Parameters
    ----------
    body : RigidBlock
        The wall.
    walls : str or float
        See above.
    restitution : str or float
        See above.
    tie_height : float, optional
        Height of the tie [m] (default the top).
    tension_only : bool
        The tie works in tension only.
    c_over_cd, delta_t : float, optional
        See above.
    damper_height : float, optional
        Height of the damper [m] (default the top).
    duration : float, optional
        Duration of each run [s] (default the record's).
    rtol : float
        Relative tolerance of the integrator.

    Returns
    -------
    dict
        The case tables.
    """
    b = body
    case = {
        "body": {"width": b.width, "height": b.height, "thickness": b.thickness,
                 "density": b.density, "top_mass": b.top_mass, "name": b.name},
        "restitution": ({"law": "housner"} if restitution in (None, "housner")
                        else {"law": "constant", "value": float(restitution)}),
        "restraint": {
            "motion_sides": "one",
            "tie": {"height": b.height if tie_height is None else float(tie_height),
                    "tension_only": bool(tension_only), "stiffness": 1.0},
            "transverse_walls": {"stiffness": walls if isinstance(walls, str) else float(walls),
                                 "effective_height": b.height},
        },
        "solver": {"rtol": rtol},
    }
    if isinstance(walls, str) and walls not in ("eq11", "rigid"):
        raise ValueError(f"walls must be 'eq11', 'rigid' or a stiffness in N/m/m, got {walls!r}")
    if duration is not None:
        case["solver"]["duration"] = float(duration)
    if c_over_cd is not None:
        if delta_t is None:
            raise ValueError("a damper as a fraction of c_d needs delta_t [s] (EURODYN (2020), "
                             "eq. 13)")
        case["restraint"]["damper"] = {
            "fraction": 0.0, "delta_t": float(delta_t),
            "height": b.height if damper_height is None else float(damper_height)}
    return case


def rocking_spectrum(
    body,
    records="farfield",
    K_over_Kd=TIE_STIFFNESS_RATIOS,
    *,
    walls="eq11",
    restitution="housner",
    tie_height=None,
    tension_only: bool = True,
    c_over_cd=None,
    delta_t=None,
    scale=None,
    omega_p_over_p=None,
    duration=None,
    free_standing: bool = True,
    executor="process",
    workers=None,
    scheduler=None,
    out=None,
    chunk_size: int = 256,
    retries: int = 2,
    progress=None,
):
    """Rocking spectra of ``body`` under ``records`` (EURODYN (2020), §4.1) as an xarray Dataset.

    Parameters
    ----------
    body:
        A :class:`~murus.rocking.RigidBlock` (e.g. ``restrained_wall_block("block2")``).
    records:
        A FEMA P695 suite name (default ``"farfield"``: 44 components), a folder, a list of
        files or GroundMotions, a :class:`~murus.studies.records.RecordSet`, or a pulse as a
        case ``[motion]`` table, e.g. ``{"type": "sine-pulse", "amplitude_g": 0.3}`` (then
        ``omega_p_over_p`` sweeps its frequency ratio).
    K_over_Kd, c_over_cd, scale, omega_p_over_p:
        Tie stiffness over ``K_d`` (eq. 12), damper coefficient over ``c_d`` (eq. 13, needs
        ``delta_t``), factor on the records, pulse frequency over ``p``: an array makes a
        dimension of the Dataset (in this order), a number a fixed value (a scalar
        coordinate).
    walls, restitution, tie_height, tension_only:
        See :func:`spectrum_case`; EURODYN (2020): ``"eq11"``, Housner, top, tension-only.
    free_standing:
        Also run the wall without tie and damper (the reference line of Figures 3-4):
        variable ``free_standing`` (``theta_max / alpha``) and ``free_standing_overturned``.
    executor, workers, scheduler, out, chunk_size, retries, progress:
        See :func:`murus.studies.sweep.run_plan`; with ``out`` the free-standing runs go to
        ``out/free_standing``.

    Returns the Dataset of :func:`~murus.studies.sweep.run_plan` (dims: the swept parameters
    and ``record``) with ``K_over_Kd`` in ``[0, 1]`` and variables ``theta_max_over_alpha``,
    ``overturned``, ``n_impacts`` ..., ``tie_stiffness`` [N/m] and ``bed_stiffness`` [N/m/m].
    """
    from pathlib import Path

    from murus.studies.executors import ExecutorHandle, open_executor
    from murus.studies.study import make_study
    from murus.studies.sweep import run_plan

    case = spectrum_case(body, walls=walls, restitution=restitution, tie_height=tie_height,
                         tension_only=tension_only, c_over_cd=c_over_cd, delta_t=delta_t,
                         duration=duration)
    pulse = isinstance(records, dict)
    if pulse:
        case["motion"] = {**records}
        case["motion"].setdefault("frequency", 1.0)
        rec = None
    else:
        rec = RecordSet.coerce(records)
        if omega_p_over_p is not None:
            raise ValueError("omega_p_over_p needs a pulse as records (a [motion] table)")
    sweep = {}
    scalars = []
    for name, val in (("K_over_Kd", K_over_Kd), ("restraint.damper.fraction", c_over_cd),
                      ("motion.scale", scale), ("omega_p_over_p", omega_p_over_p)):
        if val is None:
            continue
        arr = np.atleast_1d(np.asarray(val, dtype=float))
        if arr.ndim != 1 or arr.size == 0 or not np.all(np.isfinite(arr)):
            raise ValueError(f"{name} must be a number or a 1-D array of finite numbers")
        sweep[name] = arr
        if np.ndim(val) == 0:
            scalars.append(name)
    if np.any(sweep["K_over_Kd"] < 0):
        raise ValueError("K_over_Kd must be >= 0")
    study = make_study(case, sweep, rec, name=f"rocking_spectrum_{body.name}",
                       chunk_size=chunk_size, retries=retries)
    plan = study.plan()
    plan.spec["function"] = "rocking_spectrum"
    handle = executor if isinstance(executor, ExecutorHandle) else open_executor(
        executor, workers, scheduler)
    try:
        ds = run_plan(plan, handle, out=out, retries=retries, progress=progress)
        if free_standing:
            free_sweep = {k: v for k, v in sweep.items()
                          if k not in ("K_over_Kd", "restraint.damper.fraction")}
            free_case = {**case, "restraint": {**case["restraint"]}}
            free_case["restraint"].pop("damper", None)
            free_sweep = {"K_over_Kd": np.array([0.0]), **free_sweep}
            fplan = make_study(free_case, free_sweep, rec, name=study.name + "_free",
                               chunk_size=chunk_size, retries=retries).plan()
            fds = run_plan(fplan, handle, out=None if out is None else Path(out) /
                           "free_standing", retries=retries)
            fds = fds.isel(K_over_Kd=0, drop=True)
            ds["free_standing"] = fds["theta_max_over_alpha"].assign_attrs(
                long_name="theta_max / alpha of the free-standing wall (no tie, no damper)")
            ds["free_standing_overturned"] = fds["overturned"]
    finally:
        if handle is not executor:
            handle.close()
    for name in scalars:
        ds = ds.squeeze(name)
    ds.attrs["walls"] = str(walls)
    ds.attrs["body"] = body.name
    if out is not None:
        from murus.studies.sweep import write_netcdf

        write_netcdf(ds, Path(out) / "result.nc")
    return ds


# ----------------------------------------------------------------------------- plots -----
def _plt():
    import matplotlib.pyplot as plt

    return plt


def plot_rocking_spectrum(ds, ax=None, *, record=None, x=None, limit_states=LIMIT_STATES,
                          ymax: float | None = None):
    """Plot ``theta_max / alpha`` against the swept parameter ``x`` (default the first
    dimension, ``K_over_Kd``), in the style of EURODYN (2020), Figures 3-4: one curve per record (or
    the chosen ``record``, a name or index), the limit states (dashed), the free-standing value
    (dotted, when the Dataset has it) and overturned cases as crosses at the top. With many
    records the median and the 16-84 % band are drawn over thin lines. Returns the Axes.

    Parameters
    ----------
    ds : xarray.Dataset
        A rocking-spectrum result.
    ax : matplotlib.axes.Axes, optional
        Where to draw.
    record : str or int, optional
        One record (name or index).
    x : str, optional
        The swept dimension.
    limit_states : dict
        ``{name: theta_max / alpha}`` lines.
    ymax : float, optional
        Upper limit of the axis.

    Returns
    -------
    matplotlib.axes.Axes
    """
    plt = _plt()
    if ax is None:
        _, ax = plt.subplots(figsize=(7.0, 3.6), layout="constrained")
    da = ds["theta_max_over_alpha"]
    if x is None:
        x = next(d for d in da.dims if d != "record")
    other = [d for d in da.dims if d not in (x, "record")]
    sel = {d: 0 for d in other}
    da = da.isel(sel)
    over = ds["overturned"].isel(sel)
    free = ds["free_standing"].isel({d: 0 for d in other if d in ds["free_standing"].dims}) \
        if "free_standing" in ds else None
    if record is not None and "record" in da.dims:
        idx = record if isinstance(record, int) else list(ds["record"].values).index(record)
        da, over = da.isel(record=idx), over.isel(record=idx)
        if free is not None and "record" in free.dims:
            free = free.isel(record=idx)
    xs = np.asarray(ds[x].values, dtype=float)
    y = np.atleast_2d(np.asarray(da.transpose(x, ...).values, dtype=float).reshape(xs.size, -1).T)
    ov = np.atleast_2d(np.asarray(over.transpose(x, ...).values, dtype=float)
                       .reshape(xs.size, -1).T) > 0.5
    yplot = np.where(ov, np.nan, y)
    top = ymax if ymax is not None else max(1.0, float(np.nanmax(yplot, initial=0.0)))
    if free is None and x == "K_over_Kd" and "tie_stiffness" in ds:
        ts = ds["tie_stiffness"].isel({d: 0 for d in other if d in ds["tie_stiffness"].dims})
        zero = np.flatnonzero(np.asarray(ts.values) == 0.0)
        if zero.size:  # K = 0 with eq. 11 walls: the free-standing wall
            free = da.isel({x: int(zero[0])})
    if y.shape[0] == 1:
        ax.plot(xs, yplot[0], "-o", ms=3, lw=1.2, color="C0", label=r"$\theta_{max}/\alpha$")
    else:
        for row in yplot:
            ax.plot(xs, row, lw=0.4, color="0.7")
        med = np.nanmedian(np.where(ov, top, y), axis=0)
        lo, hi = np.nanpercentile(np.where(ov, top, y), [16, 84], axis=0)
        ax.fill_between(xs, lo, np.minimum(hi, top), color="C0", alpha=0.2, label="16-84 %")
        ax.plot(xs, np.minimum(med, top), lw=1.6, color="C0", label=f"median of {y.shape[0]}")
    if ov.any():
        xi, yi = np.nonzero(ov.T)
        ax.plot(xs[xi], np.full(xi.size, top), "x", color="C3", ms=5,
                label="overturned (drawn at the top; π/(2α) in the data)")
    for i, (name, v) in enumerate(limit_states.items()):
        ax.axhline(v, ls="--", lw=0.9, color=("C2", "C1", "C4")[i % 3],
                   label=f"{name} rocking ({v:g})")
    if free is not None:
        fv = np.asarray(free.values, dtype=float)
        f0 = float(fv) if fv.ndim == 0 else float(np.nanmedian(fv))
        if math.isfinite(f0) and f0 <= top:
            ax.axhline(f0, ls=":", lw=1.2, color="k",
                       label="free-standing" + ("" if fv.ndim == 0 else " (median)"))
        elif math.isfinite(f0):  # the free-standing wall overturns: no reference line
            ax.plot([], [], ls=":", color="k", label="free-standing: overturns")
    ax.set_xlabel(_label(ds, x))
    ax.set_ylabel(r"$\theta_{max}/\alpha$ [-] (peak rotation / slenderness)")
    ax.set_xlim(xs.min(), xs.max())
    ax.set_ylim(0.0, top * 1.08 if ymax is None else ymax)
    name = ds.attrs.get("body") or ds.attrs.get("title", "").removeprefix("murus study ")
    rec = "" if record is None else f", {record}"
    ax.set_title(f"Rocking spectrum: {name}{rec}", fontsize=9)
    ax.legend(fontsize=8, ncol=2, loc="upper right", framealpha=0.9)
    return ax


def _label(ds, name: str) -> str:
    units = ds[name].attrs.get("units", "")
    nice = {"K_over_Kd": r"$K/K_d$", "restraint.damper.fraction": r"$c/c_d$",
            "motion.scale": "scale factor", "omega_p_over_p": r"$\omega_p/p$"}.get(name, name)
    return nice + (f" [{units}]" if units not in ("", "1") else "")


def plot_overturning_map(ds, x=None, y=None, ax=None, *, what: str = "overturned"):
    """A map over two dimensions (default: the first swept parameter and ``record``, or the
    first two parameters, averaged over the records) of the fraction of overturned cases
    (``what="overturned"``) or of the median ``theta_max / alpha`` (``what="theta"``).
    Returns the Axes.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep result.
    x, y : str, optional
        The two dimensions.
    ax : matplotlib.axes.Axes, optional
        Where to draw.
    what : str
        ``"overturned"`` or ``"theta"``.

    Returns
    -------
    matplotlib.axes.Axes
    """
    plt = _plt()
    if ax is None:
        _, ax = plt.subplots(figsize=(7.0, 4.0), layout="constrained")
    dims = [d for d in ds["theta_max_over_alpha"].dims if d != "record"]
    x = x or dims[0]
    if y is None:
        y = dims[1] if len(dims) > 1 else "record"
    if what == "overturned":
        da = ds["overturned"]
        reduce = [d for d in da.dims if d not in (x, y)]
        z = da.mean(reduce) if reduce else da
        label = "fraction overturned"
        vmax = 1.0
    else:
        da = ds["theta_max_over_alpha"].where(ds["overturned"] < 0.5, 1.0)
        reduce = [d for d in da.dims if d not in (x, y)]
        z = da.median(reduce) if reduce else da
        label = r"median $\theta_{max}/\alpha$ (overturned = 1)"
        vmax = 1.0
    z = z.transpose(y, x)
    xs = np.asarray(ds[x].values, dtype=float)
    if y == "record":
        ys = np.arange(ds.sizes["record"])
    else:
        ys = np.asarray(ds[y].values, dtype=float)
    m = ax.pcolormesh(xs, ys, np.asarray(z.values, dtype=float), shading="nearest",
                      vmin=0.0, vmax=vmax, cmap="magma_r")
    plt.colorbar(m, ax=ax, label=label)
    ax.set_xlabel(_label(ds, x))
    if y == "record":
        ax.set_yticks(ys)
        ax.set_yticklabels([str(v) for v in ds["record"].values], fontsize=5)
        ax.set_ylabel("record")
    else:
        ax.set_ylabel(_label(ds, y))
    return ax


def __getattr__(name: str):
    if name == "SEED002_RATIOS":
        warnings.warn("SEED002_RATIOS is deprecated: use TIE_STIFFNESS_RATIOS", DeprecationWarning,
                      stacklevel=2)
        return TIE_STIFFNESS_RATIOS
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

"""Writers of rocking results: ``summary.json``, ``timeseries.csv`` and ``response.png``,
published with :mod:`murus.outputs` (temporary folder, manifest, nothing of the user's
deleted), so that nothing is left half-written."""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from pathlib import Path

import numpy as np


def _clean(obj):
    if isinstance(obj, dict):
        return {str(k): _clean(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_clean(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _clean(obj.tolist())
    if isinstance(obj, np.generic):
        return _clean(obj.item())
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def summary_json(result) -> str:
    return json.dumps(_clean(result.summary()), indent=2) + "\n"


def timeseries_csv(result) -> str:
    """Columns: t [s], ag [m/s2], av [m/s2], rc [-], theta [rad], theta_over_alpha [-],
    omega [rad/s], pivot [-1, 0, 1]; on a Winkler base: t, ag, av, theta, theta_over_alpha,
    omega, v [m], contact_length [m], centre_of_pressure [m], contact_force [N]."""
    from murus.rocking.winkler import WinklerResult

    if isinstance(result, WinklerResult):  # dispatch on the result class
        return _winkler_csv(result)
    cols = np.column_stack([
        result.t, result.ag, result.av, result.rocking_criterion, result.theta,
        result.theta / result.alpha, result.omega, result.pivot,
    ])
    header = "t_s,ag_m_s2,av_m_s2,rc,theta_rad,theta_over_alpha,omega_rad_s,pivot"
    lines = [header]
    fmt = "{:.6f},{:.9g},{:.9g},{:.9g},{:.12g},{:.9g},{:.9g},{:.0f}"
    for row in cols:
        lines.append(fmt.format(*row))
    return "\n".join(lines) + "\n"


def _winkler_csv(result) -> str:
    cols = np.column_stack([
        result.t, result.ag, result.av, result.theta, result.theta / result.alpha, result.omega,
        result.v, result.contact_length, result.pivot, result.contact_force,
    ])
    header = ("t_s,ag_m_s2,av_m_s2,theta_rad,theta_over_alpha,omega_rad_s,v_m,"
              "contact_length_m,centre_of_pressure_m,contact_force_n")
    fmt = ",".join(["{:.6f}"] + ["{:.9g}"] * 9)
    return "\n".join([header] + [fmt.format(*row) for row in cols]) + "\n"


def atomic_dir(out: Path, write: Callable[[Path], None], names=None) -> Path:
    """Run ``write(tmp)`` in a temporary folder and publish its files into ``out`` with
    :func:`murus.outputs.write_dir`: an existing ``out`` keeps every file murus did not write
    there (only the files of its manifest are replaced); on any error ``out`` is as it was."""
    from murus.outputs import command_line, write_dir

    return write_dir(out, write, command=command_line(), names=names)


def output_names(figure: bool = True) -> list[str]:
    """Relative paths written by :func:`write_result_files`."""
    return ["summary.json", "timeseries.csv"] + (["response.png"] if figure else [])


def write_result_files(result, folder: Path, figure: bool = True) -> None:
    """Write ``summary.json``, ``timeseries.csv`` and ``response.png`` into ``folder``."""
    folder = Path(folder)
    (folder / "summary.json").write_text(summary_json(result))
    (folder / "timeseries.csv").write_text(timeseries_csv(result))
    if figure:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        from murus.rocking.plots import plot_response, plot_winkler
        from murus.rocking.winkler import WinklerResult

        ax = plot_winkler(result) if isinstance(result, WinklerResult) else plot_response(result)
        fig = ax[0].figure
        fig.savefig(folder / "response.png", dpi=120)
        plt.close(fig)


def write_outputs(result, out: Path, figure: bool = True) -> Path:
    """Write the outputs of one run into ``out`` (:func:`murus.outputs.write_dir`)."""
    return atomic_dir(out, lambda tmp: write_result_files(result, tmp, figure),
                      names=output_names(figure))

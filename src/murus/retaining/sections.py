"""Global response of a wall from several cross-sections (Savalle et al. (2022), §3.2, Figure 4,
Table 2).

A 2D model has one cross-section, but a real dry-stone wall is an assemblage whose sections
differ along its length (headers at different heights, Savalle et al. (2022), Figure 3).
Savalle et al. (2022) runs each section and combines their crest displacements into a global
response "weighting the individual responses according to the proportions [of each section along the
wall]. For each d_top, one finds the corresponding times in each response and then weights them to
obtain the global response time" (Table 2: for d_top = 5 mm, times 18.4, 21.5, 19.9 and 21.5 s with
proportions 7/23, 7/23, 7/23 and 2/23 give 20.1 s).

:func:`weighted_response` does this for a whole range of displacement levels: the time at which
each section first reaches a level (linear interpolation between samples, on the running
maximum of |d_top| so that the curve is monotone) and their weighted mean. A level that some
section never reaches is left out of the global curve (its time would be undefined), and the
result says so.

Units: s, m.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from murus.errors import MurusError

__all__ = ["SectionsError", "WeightedResponse", "first_passage_times", "weighted_response"]


class SectionsError(MurusError, ValueError):
    """Bad section histories or weights."""


@dataclass(frozen=True)
class WeightedResponse:
    """``levels`` [m] of d_top; ``time`` [s] of the global response at each level;
    ``section_times`` (n_sections x n_levels) [s]; ``weights`` normalised to 1; ``levels_left_out``
    the requested levels that some section never reached."""

    levels: np.ndarray
    time: np.ndarray
    section_times: np.ndarray
    weights: np.ndarray
    levels_left_out: np.ndarray

    def as_history(self) -> tuple[np.ndarray, np.ndarray]:
        """The global curve as (t, d_top): times increasing, displacements the levels."""
        return self.time.copy(), self.levels.copy()


def first_passage_times(t, d, levels) -> np.ndarray:
    """First time [s] at which |d| reaches each level (linear interpolation between samples;
    ``nan`` where it never does). ``t`` increasing [s], ``d`` [m]."""
    t = np.asarray(t, dtype=float)
    env = np.maximum.accumulate(np.abs(np.asarray(d, dtype=float)))
    levels = np.asarray(levels, dtype=float)
    out = np.full(levels.shape, np.nan)
    for j, lv in enumerate(levels):
        i = int(np.searchsorted(env, lv, side="left"))
        if i >= env.size:
            continue
        if i == 0 or env[i] == env[i - 1]:
            out[j] = t[i]
        else:
            out[j] = t[i - 1] + (lv - env[i - 1]) / (env[i] - env[i - 1]) * (t[i] - t[i - 1])
    return out


def weighted_response(histories, weights, levels=None, n_levels: int = 200) -> WeightedResponse:
    """Weighted global response of several cross-sections (Savalle et al. (2022), Table 2).

    ``histories``: a list of (t [s], d_top [m]) per section; ``weights``: the proportion of each
    section along the wall (normalised here; Savalle et al. (2022): 7/23, 7/23, 7/23, 2/23);
    ``levels``: the displacement levels [m] (default ``n_levels`` levels from 0 to the smallest of
    the sections' largest |d_top|, so that every section reaches them)."""
    if len(histories) == 0:
        raise SectionsError("no section history given")
    w = np.asarray(weights, dtype=float)
    if w.shape != (len(histories),):
        raise SectionsError(f"{len(histories)} sections need {len(histories)} weights, "
                            f"got {w.size}")
    if not (np.isfinite(w).all() and (w >= 0).all() and w.sum() > 0):
        raise SectionsError("weights must be non-negative numbers, not all zero")
    w = w / w.sum()
    hs = []
    for k, (t, d) in enumerate(histories):
        t = np.asarray(t, dtype=float)
        d = np.asarray(d, dtype=float)
        if t.ndim != 1 or t.shape != d.shape or t.size < 2:
            raise SectionsError(f"section {k + 1}: t and d_top must be 1-D of the same length")
        if not (np.isfinite(t).all() and np.isfinite(d).all()) or (np.diff(t) <= 0).any():
            raise SectionsError(f"section {k + 1}: t must increase and values be finite")
        hs.append((t, d))
    if levels is None:
        top = min(float(np.abs(d).max()) for _, d in hs)
        levels = np.linspace(0.0, top, n_levels + 1)[1:]
    levels = np.asarray(levels, dtype=float)
    times = np.array([first_passage_times(t, d, levels) for t, d in hs])
    ok = np.isfinite(times).all(axis=0)
    return WeightedResponse(levels=levels[ok], time=w @ times[:, ok],
                            section_times=times[:, ok], weights=w,
                            levels_left_out=levels[~ok])

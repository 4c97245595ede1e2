"""Classification of seismic tests as cantilever, hybrid or rocking responses (issue 8, item 4;
Mordant et al. (SERIES), §2.3, Figures 6, 7, 19 and 20).

Mordant et al. (SERIES), §2.3 sorts its tests by comparing the rotations measured at the bottom and
at the top of the wall: a "significant difference" (low levels, S01-S03: the wall bends as a
cantilever), "quasi-equal rotations" (high levels, S07-S09: the wall rocks as a rigid body on its
base joint), and a hybrid in between (S04-S06). Mordant et al. (SERIES) give no number; the
criterion here is

    ratio = max |rot_bottom| / max |rot_top|

(the share of the top rotation that comes from rotation at the base joint; the rotations are
relative to the table, :mod:`murus.identify.testdata`) with

- ``cantilever`` if ``ratio < cantilever_below`` (default 0.3) or if the top rotation stays
  below ``min_rotation`` (default 1e-5 rad: under it the ratio is a ratio of sensor noises;
  ten times the resolution of a typical inclinometer of a shaking-table set-up);
- ``rocking`` if ``ratio >= rocking_above`` (default 0.8: "quasi-equal" read as the base joint
  giving at least 80 % of the top rotation, the deformation of the wall at most 20 %);
- ``hybrid`` otherwise.

The defaults are a reading of the text of Mordant et al. (SERIES), not values from it; they are
parameters of :class:`Criterion`. Both peaks are taken after a centred moving average of ``smooth``
samples (default 1: none) so that isolated noise spikes can be filtered out.

The lifted-length history ``L - Lc(t)`` (Mordant et al. (SERIES), Figures 19-20) comes from the base
transducers by :mod:`murus.identify.compressive`.

Units: rad, s, m.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from murus.errors import MurusError

__all__ = ["ClassifyError", "Criterion", "Classification", "classify", "classify_test",
           "classify_sequence", "lifted_length", "plot_rotations", "plot_lifted_length",
           "CLASSES"]

CLASSES = ("cantilever", "hybrid", "rocking")


class ClassifyError(MurusError, ValueError):
    """Invalid input to the classification."""


@dataclass(frozen=True)
class Criterion:
    """Thresholds of the classification (module docstring).

    Parameters
    ----------
    cantilever_below : float
        Ratio below which the wall bends as a cantilever [-].
    rocking_above : float
        Ratio above which it rocks [-].
    min_rotation : float
        Smallest top rotation classified [rad].
    smooth : int
        Samples of the centred moving average.
    """

    cantilever_below: float = 0.3
    rocking_above: float = 0.8
    min_rotation: float = 1e-5
    smooth: int = 1

    def __post_init__(self) -> None:
        if not (0.0 <= self.cantilever_below <= self.rocking_above):
            raise ClassifyError("thresholds must satisfy 0 <= cantilever_below <= rocking_above,"
                                f" got {self.cantilever_below!r} and {self.rocking_above!r}")
        if not (math.isfinite(self.min_rotation) and self.min_rotation >= 0):
            raise ClassifyError(f"min_rotation must be >= 0 rad, got {self.min_rotation!r}")
        if int(self.smooth) < 1:
            raise ClassifyError(f"smooth must be >= 1 sample, got {self.smooth!r}")


@dataclass
class Classification:
    """Result: ``label`` (one of ``CLASSES``), ``ratio`` of the peaks, ``peak_bottom`` and
    ``peak_top`` [rad].

    Attributes
    ----------
    name : str
        The test.
    label : str
        One of ``CLASSES``.
    ratio : float
        ``max |rot_bottom| / max |rot_top|`` [-].
    peak_bottom, peak_top : float
        [rad].
    """

    name: str
    label: str
    ratio: float
    peak_bottom: float
    peak_top: float

    def to_dict(self) -> dict:
        return {"test": self.name, "class": self.label,
                "ratio": self.ratio if math.isfinite(self.ratio) else None,
                "peak_rot_bottom_rad": self.peak_bottom, "peak_rot_top_rad": self.peak_top}


def _peak(x: np.ndarray, n: int) -> float:
    if n > 1:
        x = np.convolve(x, np.ones(n) / n, mode="same")
    return float(np.max(np.abs(x)))


def classify(rot_bottom, rot_top, criterion: Criterion | None = None,
             name: str = "") -> Classification:
    """Classify one test from its bottom and top rotation histories [rad]."""
    c = criterion or Criterion()
    rb = np.asarray(rot_bottom, dtype=float)
    rt = np.asarray(rot_top, dtype=float)
    if rb.shape != rt.shape or rb.ndim != 1 or rb.size == 0:
        raise ClassifyError("rot_bottom and rot_top must be 1-D histories of the same length")
    if not (np.all(np.isfinite(rb)) and np.all(np.isfinite(rt))):
        raise ClassifyError("rotations must be finite")
    pb, pt = _peak(rb, int(c.smooth)), _peak(rt, int(c.smooth))
    ratio = pb / pt if pt > 0 else float("nan")
    if pt < c.min_rotation or not math.isfinite(ratio) or ratio < c.cantilever_below:
        label = "cantilever"
    elif ratio >= c.rocking_above:
        label = "rocking"
    else:
        label = "hybrid"
    return Classification(name=name, label=label, ratio=ratio, peak_bottom=pb, peak_top=pt)


def classify_test(test, criterion: Criterion | None = None) -> Classification:
    """Classify a :class:`~murus.identify.testdata.ShakingTableTest` (needs ``rot_bottom`` and
    ``rot_top``).

    Parameters
    ----------
    test : ShakingTableTest
        The test.
    criterion : Criterion, optional
        The thresholds (default :class:`Criterion`).

    Returns
    -------
    Classification
    """
    if not test.has_rotations:
        raise ClassifyError(f"{test.source or test.name}: needs the rot_bottom and rot_top "
                            "channels")
    return classify(test.rot_bottom, test.rot_top, criterion, name=test.name)


def classify_sequence(sequence, criterion: Criterion | None = None) -> list[Classification]:
    """Classify every seismic test of a sequence that has both rotations.

    Parameters
    ----------
    sequence : TestSequence
        The tests of a specimen.
    criterion : Criterion, optional
        The thresholds (default :class:`Criterion`).

    Returns
    -------
    list of Classification
    """
    return [classify(e.test.rot_bottom, e.test.rot_top, criterion, name=e.label)
            for e in sequence.seismic if e.test.has_rotations]


def lifted_length(test, closure: float = 0.0):
    """``(t [s], L - Lc(t) [m])`` of a test with base transducers (Mordant et al. (SERIES), Figures
    19-20).

    Parameters
    ----------
    test : ShakingTableTest
        A test with base transducers.
    closure : float
        Elastic closure of the base joint [m].

    Returns
    -------
    tuple of numpy.ndarray
        Times [s] and lifted length [m].
    """
    from murus.identify.compressive import test_contact

    tc = test_contact(test, closure)
    return tc.t, tc.lifted


def plot_rotations(test, ax=None, classification: Classification | None = None):
    """Bottom and top rotations against time (Mordant et al. (SERIES), Figures 6 and 7), in mrad."""
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(7, 3.5))
    ax.plot(test.t, 1e3 * test.rot_top, lw=0.8, label="top")
    ax.plot(test.t, 1e3 * test.rot_bottom, lw=0.8, label="bottom")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("rotation [mrad]")
    title = test.name
    if classification is not None:
        title += f": {classification.label} (ratio {classification.ratio:.2f})"
    ax.set_title(title)
    ax.legend(fontsize=8)
    ax.grid(True, alpha=0.3)
    return ax


def plot_lifted_length(test, ax=None, closure: float = 0.0, model=None):
    """Lifted length ``L - Lc`` [mm] against time (Mordant et al. (SERIES), Figures 19-20);
    ``model`` an optional ``(t, lifted [m])`` to compare with."""
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(7, 3.5))
    t, lift = lifted_length(test, closure)
    ax.plot(t, 1e3 * lift, lw=0.8, label="measured (plane section)")
    if model is not None:
        ax.plot(model[0], 1e3 * np.asarray(model[1]), lw=0.8, ls="--", label="model")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("lifted length [mm]")
    ax.set_title(test.name)
    ax.legend(fontsize=8)
    ax.grid(True, alpha=0.3)
    return ax

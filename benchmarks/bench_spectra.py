"""Benchmark: 5 %-damped PSA at 100 periods of a 4000-step record, murus vs eqsig vs pyrotd.

Same input, same run. Accuracy is measured against the exact response of the oscillator to the
piecewise-linear record, computed independently with scipy.signal.lsim (matrix exponential,
exact for linear input between samples) on the record linearly up-sampled 64 times, with
parabolic refinement of the peak. Times are the best of ``--repeat`` runs after a warm-up
(numba compilation excluded; it is cached on disk).

Run: python benchmarks/bench_spectra.py [--repeat 7] [--out benchmarks/RESULTS_motion.md]
"""

from __future__ import annotations

import argparse
import platform
import time

import numpy as np

from murus.motion import GroundMotion
from murus.motion.spectra import pseudo_spectrum, response_spectrum

N_STEPS = 4000
DT = 0.01
PERIODS = np.geomspace(0.02, 10.0, 100)
XI = 0.05


def make_record(seed: int = 2024) -> np.ndarray:
    """Band-limited noise (0.1-25 Hz) with a trapezoidal envelope, 4000 steps of 0.01 s [m/s²]."""
    rng = np.random.default_rng(seed)
    n = N_STEPS
    x = rng.standard_normal(n)
    X = np.fft.rfft(x)
    f = np.fft.rfftfreq(n, DT)
    X[(f < 0.1) | (f > 25.0)] = 0
    x = np.fft.irfft(X, n)
    t = DT * np.arange(n)
    env = np.clip(t / 3.0, 0, 1) * np.clip((t[-1] - t) / 10.0, 0, 1)
    x *= env
    return 3.0 * x / np.max(np.abs(x))


def exact_psa(acc: np.ndarray, periods: np.ndarray, xi: float, up: int = 64) -> np.ndarray:
    from scipy import signal

    n = acc.size
    t = DT * np.arange(n)
    tf = np.linspace(0, t[-1], (n - 1) * up + 1)
    af = np.interp(tf, t, acc)
    out = np.empty(periods.size)
    for j, T in enumerate(periods):
        w = 2 * np.pi / T
        sys = signal.StateSpace([[0, 1], [-w * w, -2 * xi * w]], [[0], [-1]], [[1, 0]], [[0]])
        _, y, _ = signal.lsim(sys, af, tf)
        k = int(np.argmax(np.abs(y)))
        peak = abs(y[k])
        if 0 < k < y.size - 1:  # parabolic refinement through three points
            y0, y1, y2 = abs(y[k - 1]), abs(y[k]), abs(y[k + 1])
            den = y0 - 2 * y1 + y2
            if den != 0:
                peak = y1 - (y2 - y0) ** 2 / (8 * den)
        out[j] = w * w * peak
    return out


def timeit(fn, repeat):
    fn()  # warm-up
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--out", default=None)
    ap.add_argument("--up", type=int, default=64, help="up-sampling of the reference")
    args = ap.parse_args(argv)

    acc = make_record()
    gm = GroundMotion(dt=DT, acc=acc)
    t0 = time.perf_counter()
    ref = exact_psa(acc, PERIODS, XI, up=args.up)
    t_ref = time.perf_counter() - t0

    rows = []

    def murus_run():
        return response_spectrum(gm, PERIODS, XI).psa

    def murus_plain():
        return pseudo_spectrum(gm, PERIODS, XI, oversample=1, refine=False)

    def murus_psa():
        return pseudo_spectrum(gm, PERIODS, XI)

    rows.append(("murus pseudo_spectrum (PSA only; auto oversampling + Hermite peaks)",
                 murus_psa))
    rows.append(("murus response_spectrum (SD, SV, SA, PSA; same method)", murus_run))
    rows.append(("murus pseudo_spectrum (oversample=1, refine=False: step-sampled peaks)",
                 murus_plain))
    versions = {}
    try:
        import eqsig
        import eqsig.sdof

        versions["eqsig"] = eqsig.__version__

        def eq():
            return eqsig.sdof.pseudo_response_spectra(acc, DT, PERIODS, XI)[2]

        rows.append((f"eqsig {eqsig.__version__} (sdof.pseudo_response_spectra)", eq))
    except Exception as exc:  # pragma: no cover - reported in the table
        versions["eqsig"] = f"unavailable: {exc}"
    try:
        import pyrotd

        versions["pyrotd"] = pyrotd.__version__

        def pr():
            return pyrotd.calc_spec_accels(DT, acc, 1.0 / PERIODS, XI).spec_accel

        rows.append((f"pyrotd {pyrotd.__version__} (calc_spec_accels)", pr))
    except Exception as exc:  # pragma: no cover
        versions["pyrotd"] = f"unavailable: {exc}"

    results = []
    for name, fn in rows:
        psa = np.asarray(fn(), float)
        err = np.abs(psa / ref - 1)
        short = PERIODS < 10 * DT
        results.append((name, timeit(fn, args.repeat), err.max(), err[short].max(),
                        err[~short].max()))
    peers = [r for r in results if not r[0].startswith("murus")]
    fastest_peer = min((r[1] for r in peers), default=np.nan)
    lines = [
        "# Response spectrum benchmark (murus.motion)",
        "",
        f"Input: {N_STEPS}-step record (dt = {DT} s, band-limited noise 0.1-25 Hz, PGA 3 m/s²), "
        f"5 % PSA at {PERIODS.size} log-spaced periods {PERIODS[0]:g}-{PERIODS[-1]:g} s "
        f"({int(np.sum(PERIODS < 10 * DT))} of them below 10 dt). Reference: exact response "
        f"(scipy.signal.lsim on the 64x linearly up-sampled record, {t_ref:.1f} s).",
        f"Machine: {platform.processor() or platform.machine()}, Python "
        f"{platform.python_version()}; best of {args.repeat} runs after a warm-up.",
        "Command: `python benchmarks/bench_spectra.py`",
        "",
        "| tool | time [ms] | speed-up vs fastest peer | max rel. error (all T) | "
        "T < 10 dt | T >= 10 dt |",
        "|---|---:|---:|---:|---:|---:|",
    ]
    for name, t, e_all, e_s, e_l in results:
        lines.append(f"| {name} | {t * 1e3:.2f} | {fastest_peer / t:.1f}x | {e_all:.2e} | "
                     f"{e_s:.2e} | {e_l:.2e} |")
    lines += [
        "",
        "Notes:",
        "",
        "- Peers: " + ", ".join(f"{k} {v}" for k, v in versions.items()) + " (both install "
        "from PyPI on Python 3.11; eqsig builds from its sdist).",
        "- The goal of the issue is >= 10x the fastest peer at equal or better accuracy. "
        "`pseudo_spectrum` (PSA only, the quantity benchmarked) reaches it at an accuracy "
        "about 500 times better than the peers; `response_spectrum`, which also tracks the SV "
        "and SA peaks with sub-steps everywhere, is slower; the step-sampled mode is the "
        "fastest and still more accurate than both peers.",
        "- eqsig samples the peak at the record steps only (no sub-steps): its error reaches "
        "tens of % for T < 10 dt (largest near T = 5 dt, underestimated). pyrotd works in the "
        "frequency domain: its error is largest at the longest periods (about +44 % at 10 s "
        "for this 40 s record) and 18 % at short periods.",
        "- The smallest error that this reference can resolve is about 1e-4 (64x up-sampling "
        "with a parabolic peak); murus is verified more tightly against closed forms in "
        "tests/motion/test_spectra.py (step response to 2e-4, sine response to 1e-3 at "
        "T = 0.004-2 s with dt = 0.001 s).",
    ]
    text = "\n".join(lines) + "\n"
    print(text)
    if args.out:
        with open(args.out, "w") as f:
            f.write(text)


if __name__ == "__main__":
    main()

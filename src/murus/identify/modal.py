"""Modal identification from white-noise shaking-table tests (issue 8, item 2;
Mordant et al. (SERIES), §2.1, Figures 3 and 4).

Frequency response function
    H1 estimator ``H(f) = G_xy(f) / G_xx(f)`` with ``x`` the table acceleration and ``y`` the
    top acceleration (both absolute, m/s2), the one- and cross-sided spectral densities by
    Welch averaging (:func:`scipy.signal.welch`, :func:`scipy.signal.csd`; Hann window, 50 %
    overlap, linear detrending); coherence ``gamma^2 = |G_xy|^2 / (G_xx G_yy)``. H1 is unbiased
    for noise on the output; noise on the input scales it by a constant for a white input, which
    moves neither the peaks nor their width (Bendat & Piersol, *Random Data*, 4th ed., §9.2).

Model of the FRF (base excitation)
    For a linear structure with classical damping excited at its base, the absolute
    acceleration of a point over the table acceleration (the transmissibility) is
    ``T(w) = 1 + sum_k r_k w^2 / (w_k^2 - w^2 + 2 i zeta_k w_k w)`` with ``r_k`` the product of
    the mode shape at that point and the participation factor (``sum_k r_k = 1`` at the top of
    a cantilever); for one mode ``T = (w_n^2 + 2 i zeta w_n w) / (w_n^2 - w^2 + 2 i zeta w_n w)``.
    Near a peak ``k`` the fit model is ``H(w) = R w^2 / (w_k^2 - w^2 + 2 i zeta_k w_k w) + C``
    with complex ``R`` and ``C`` (``C`` collects the other modes and the rigid term 1): for
    given ``(f_k, zeta_k)`` the model is linear in ``R, C``, which are eliminated by linear least
    squares (variable projection); ``f_k, zeta_k`` minimise the coherence-weighted residual by
    :func:`scipy.optimize.least_squares` with bounds.

Peak picking
    Local maxima of ``log10 |H|``, smoothed by a running mean over ``smooth_bins`` bins (single
    bins of a noisy estimate are not modes), with a prominence of at least ``prominence``
    decades, inside the band ``(f_min, f_max)``, where the coherence reaches ``min_coherence``
    (0.7 by default: on the synthetic records of the tests, spurious peaks of the noisy
    high-frequency tail have coherences of 0.5-0.65, the modes above 0.95); the peak
    frequency is refined by a parabola through the three bins around the maximum of
    ``log |H|`` (exact for a Gaussian peak, a good approximation of a resonance sampled by a Hann
    window). Half-power damping ``zeta = (f_2 - f_1) / (2 f_peak)`` from the frequencies where
    ``|H|`` crosses ``|H|_peak / sqrt(2)`` (linear interpolation between bins), searched no
    further than the neighbouring minimum; the transmissibility's extra numerator makes this
    estimate slightly biased (its peak is at ``f_n (sqrt(1 + 8 zeta^2) - 1)^(1/2) / (2 zeta)``,
    0.25 % below ``f_n`` for 5 %); the fitted values are the reported ones.

Reliability (Mordant et al. (SERIES), §2.1: damping ratios "as high as 100 %": "questionable")
    Each mode carries the list ``warnings``; it is ``reliable`` when the list is empty:
    coherence at the peak below ``min_coherence_reliable`` (0.8); a half-power point not found
    before the neighbouring minimum; damping above ``max_damping`` (20 %); the half-power and the
    fitted damping differing by more than 30 %; the half-power bandwidth narrower than four
    frequency bins (resolution bias of the spectral estimate: the normalised bias of the peak is
    about ``-(B_e / B_r)^2 / 3`` with ``B_e = 1.5 df`` for Hann, Bendat & Piersol §8.5); the fit
    at a bound or failed.

Units: Hz, s, m/s2; damping ratios as fractions (0.05 = 5 %).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from murus.errors import MurusError

__all__ = ["ModalError", "FRF", "Mode", "ModalResult", "Evolution", "frf", "identify",
           "evolution", "transmissibility", "plot_frf", "plot_frequency_evolution",
           "plot_damping_evolution"]


class ModalError(MurusError, ValueError):
    """Invalid input to the modal identification."""


@dataclass
class FRF:
    """H1 estimate: frequency ``f`` [Hz], complex ``H`` [-], ``coherence`` [-], auto spectral
    densities ``Gxx``, ``Gyy`` [(m/s2)^2/Hz], segment length ``nperseg`` and sampling rate
    ``fs`` [Hz]; ``n_averages`` Welch segments.

    Attributes
    ----------
    f : numpy.ndarray
        [Hz].
    H : numpy.ndarray
        Complex FRF [-].
    coherence : numpy.ndarray
        [-].
    Gxx, Gyy : numpy.ndarray
        [(m/s²)²/Hz].
    nperseg : int
    fs : float
        [Hz].
    n_averages : int
    """

    f: np.ndarray
    H: np.ndarray
    coherence: np.ndarray
    Gxx: np.ndarray
    Gyy: np.ndarray
    nperseg: int
    fs: float
    n_averages: int

    @property
    def df(self) -> float:
        return self.fs / self.nperseg


@dataclass
class Mode:
    """One mode identified by :func:`identify` (see the module docstring for the methods).

    Attributes
    ----------
    frequency : float
        Natural frequency from the modal fit [Hz].
    damping : float
        Damping ratio from the modal fit [-] (0.05 = 5 %).
    frequency_peak : float
        Frequency of the peak of |H| by peak picking with parabolic interpolation [Hz].
    damping_half_power : float
        Damping ratio by the half-power bandwidth [-]; NaN if a half-power point is missing.
    amplitude : float
        |H| at the peak [-] (ratio of two accelerations).
    coherence : float
        Coherence gamma^2 at the peak [-].
    residue : float
        |R| of the fitted model ``R w^2 / (w_k^2 - w^2 + 2 i zeta_k w_k w) + C`` [-].
    warnings : list of str
        Reasons to doubt the mode; empty when it is :attr:`reliable`.
    fit_band : tuple of float
        Lowest and highest frequency of the bins of the fit [Hz].
    fit_coefficients : tuple of complex
        ``(R, C)`` of the fitted model [-].

    References
    ----------
    Bendat & Piersol, *Random Data*, 4th ed., §8.5 and §9.2 (H1 estimator, resolution bias);
    Mordant et al. (SERIES), §2.1.
    """

    frequency: float
    damping: float
    frequency_peak: float
    damping_half_power: float
    amplitude: float
    coherence: float
    residue: float = float("nan")
    warnings: list[str] = field(default_factory=list)
    fit_band: tuple[float, float] = (float("nan"), float("nan"))
    fit_coefficients: tuple[complex, complex] = (complex("nan"), complex("nan"))

    def fitted(self, f) -> np.ndarray:
        """The fitted model ``R w^2 / (w_k^2 - w^2 + 2 i zeta_k w_k w) + C`` at ``f`` [Hz]."""
        w = 2 * np.pi * np.asarray(f, dtype=float)
        wk = 2 * np.pi * self.frequency
        R, C = self.fit_coefficients
        return R * w**2 / (wk**2 - w**2 + 2j * self.damping * wk * w) + C

    @property
    def reliable(self) -> bool:
        return not self.warnings

    def to_dict(self) -> dict:
        d = {k: _clean(getattr(self, k)) for k in
             ("frequency", "damping", "frequency_peak", "damping_half_power", "amplitude",
              "coherence", "residue")}
        d["fit_band_hz"] = [_clean(v) for v in self.fit_band]
        d["reliable"] = self.reliable
        d["warnings"] = list(self.warnings)
        return d


def _clean(v):
    v = float(v)
    return v if math.isfinite(v) else None


@dataclass
class ModalResult:
    """Identified modes (by increasing frequency) and the FRF they come from.

    Attributes
    ----------
    frf : FRF
    modes : list of Mode
    name : str
    """

    frf: FRF
    modes: list[Mode]
    name: str = ""

    def to_dict(self) -> dict:
        return {"name": self.name, "nperseg": self.frf.nperseg, "df_hz": self.frf.df,
                "n_averages": self.frf.n_averages,
                "modes": [m.to_dict() for m in self.modes]}

    def table(self) -> str:
        """Markdown table of the modes."""
        rows = ["| mode | f [Hz] | f peak [Hz] | damping fit [%] | damping half-power [%] | "
                "coherence | reliable |", "|---|---|---|---|---|---|---|"]
        for k, m in enumerate(self.modes):
            hp = "/" if not math.isfinite(m.damping_half_power) else \
                f"{100 * m.damping_half_power:.2f}"
            rel = "yes" if m.reliable else "no: " + "; ".join(m.warnings)
            rows.append(f"| {k + 1} | {m.frequency:.3f} | {m.frequency_peak:.3f} | "
                        f"{100 * m.damping:.2f} | {hp} | {m.coherence:.3f} | {rel} |")
        return "\n".join(rows)


def transmissibility(f, modes) -> np.ndarray:
    """Transmissibility ``1 + sum r_k w^2 / (w_k^2 - w^2 + 2 i zeta_k w_k w)`` at frequencies
    ``f`` [Hz] for ``modes = [(f_k [Hz], zeta_k, r_k), ...]`` (module docstring).

    Parameters
    ----------
    f : array_like
        [Hz].
    modes : sequence of tuple
        ``(f_k [Hz], zeta_k [-], r_k [-])``.

    Returns
    -------
    numpy.ndarray
        Complex [-].
    """
    w = 2 * np.pi * np.asarray(f, dtype=float)
    H = np.ones_like(w, dtype=complex)
    for fk, zk, rk in modes:
        wk = 2 * np.pi * fk
        H += rk * w**2 / (wk**2 - w**2 + 2j * zk * wk * w)
    return H


def _xy(data, fs):
    if fs is None:
        if not hasattr(data, "table_acc"):
            raise ModalError("give a ShakingTableTest or (x, y) arrays with fs")
        return np.asarray(data.table_acc, float), np.asarray(data.top_acc, float), \
            float(data.sampling_rate)
    x, y = data
    return np.asarray(x, float), np.asarray(y, float), float(fs)


def frf(data, fs: float | None = None, nperseg: int | None = None,
        df: float | None = None) -> FRF:
    """H1 FRF and coherence of a test (``ShakingTableTest``) or of ``(x, y)`` sampled at ``fs``
    [Hz]. Segment length: ``nperseg`` samples, or the power of two giving a resolution at most
    ``df`` [Hz], or by default the power of two nearest to an eighth of the record (about 15
    averages with 50 % overlap).

    Parameters
    ----------
    data : ShakingTableTest or tuple
        A test, or ``(x, y)`` [m/s²].
    fs : float, optional
        Sampling rate of ``(x, y)`` [Hz].
    nperseg : int, optional
        Segment length [samples].
    df : float, optional
        Largest frequency resolution [Hz].

    Returns
    -------
    FRF
    """
    from scipy import signal

    x, y, fs = _xy(data, fs)
    if x.shape != y.shape or x.ndim != 1:
        raise ModalError("input and output must be 1-D arrays of the same length")
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
        raise ModalError("input or output has NaN or infinite values")
    n = x.size
    if nperseg is None:
        if df is not None:
            nperseg = 2 ** int(math.ceil(math.log2(fs / df)))
        else:
            nperseg = 2 ** int(round(math.log2(max(n / 8, 16))))
    nperseg = int(nperseg)
    if nperseg < 16 or nperseg > n:
        raise ModalError(f"nperseg {nperseg} must be in [16, {n}] (record length)")
    if np.std(x) == 0.0:
        raise ModalError("the table acceleration is constant: no excitation")
    kw = dict(fs=fs, window="hann", nperseg=nperseg, noverlap=nperseg // 2, detrend="linear")
    f, Gxx = signal.welch(x, **kw)
    _, Gyy = signal.welch(y, **kw)
    _, Gxy = signal.csd(x, y, **kw)
    with np.errstate(divide="ignore", invalid="ignore"):
        H = Gxy / Gxx
        coh = np.abs(Gxy) ** 2 / (Gxx * Gyy)
    H = np.where(np.isfinite(H), H, 0.0)
    coh = np.clip(np.where(np.isfinite(coh), coh, 0.0), 0.0, 1.0)
    n_avg = 1 + (n - nperseg) // (nperseg - nperseg // 2)
    return FRF(f=f, H=H, coherence=coh, Gxx=Gxx, Gyy=Gyy, nperseg=nperseg, fs=fs,
               n_averages=n_avg)


def _parabolic(y, i):
    """Vertex offset (bins) and value of the parabola through y[i-1], y[i], y[i+1]."""
    a, b, c = y[i - 1], y[i], y[i + 1]
    den = a - 2 * b + c
    if den >= 0:
        return 0.0, b
    p = 0.5 * (a - c) / den
    return p, b - 0.25 * (a - c) * p


def _half_power(f, mag, i, lo, hi, level):
    """Frequencies where ``mag`` crosses ``level`` left and right of bin ``i``, not beyond
    bins ``lo``/``hi``; NaN when not found."""
    f1 = f2 = float("nan")
    j = i
    while j > lo and mag[j - 1] > level:
        j -= 1
    if j > lo or (j == lo and mag[lo] <= level):
        if j > lo:
            j0 = j - 1
            f1 = f[j0] + (level - mag[j0]) * (f[j] - f[j0]) / (mag[j] - mag[j0])
    j = i
    while j < hi and mag[j + 1] > level:
        j += 1
    if j < hi:
        j1 = j + 1
        f2 = f[j] + (mag[j] - level) * (f[j1] - f[j]) / (mag[j] - mag[j1])
    return f1, f2


def _fit_mode(fr: FRF, sl: slice, f0: float, z0: float):
    """Variable-projection least-squares fit of ``R w^2/(wk^2 - w^2 + 2 i z wk w) + C``."""
    from scipy.optimize import least_squares

    f = fr.f[sl]
    H = fr.H[sl]
    wgt = np.sqrt(np.clip(fr.coherence[sl], 1e-3, 1.0))
    w = 2 * np.pi * f

    def basis(p):
        wk = 2 * np.pi * p[0]
        g = w**2 / (wk**2 - w**2 + 2j * p[1] * wk * w)
        return np.column_stack([g, np.ones_like(g)])

    def coeffs(p):
        A = basis(p) * wgt[:, None]
        c, *_ = np.linalg.lstsq(A, H * wgt, rcond=None)
        return c

    def resid(p):
        r = (basis(p) @ coeffs(p) - H) * wgt
        return np.concatenate([r.real, r.imag])

    lo = np.array([f[0], 1e-4])
    hi = np.array([f[-1], 1.0])
    p0 = np.clip([f0, z0], lo * (1 + 1e-9), hi * (1 - 1e-9))
    sol = least_squares(resid, p0, bounds=(lo, hi), x_scale=[max(f0 * z0, fr.df), z0],
                        xtol=1e-12, ftol=1e-12)
    c = coeffs(sol.x)
    at_bound = bool(np.any(np.isclose(sol.x, lo, rtol=1e-6)) or
                    np.any(np.isclose(sol.x, hi, rtol=1e-6)))
    return (float(sol.x[0]), float(sol.x[1]), (complex(c[0]), complex(c[1])),
            bool(sol.success), at_bound)


def identify(data, fs: float | None = None, *, nperseg: int | None = None,
             df: float | None = None, f_min: float = 0.0, f_max: float | None = None,
             n_modes: int | None = None, prominence: float = 0.3, smooth_bins: int = 5,
             min_coherence: float = 0.7, min_coherence_reliable: float = 0.8,
             max_damping: float = 0.20, name: str | None = None) -> ModalResult:
    """Natural frequencies and damping ratios of a white-noise test (module docstring).

    Parameters
    ----------
    data : ShakingTableTest or tuple of array_like
        A :class:`~murus.identify.testdata.ShakingTableTest` (its ``table_acc`` and
        ``top_acc``), or ``(x, y)``: table and top absolute accelerations [m/s²].
    fs : float, optional
        Sampling rate of ``(x, y)`` [Hz]; not needed with a test.
    nperseg : int, optional
        Length of the Welch segments [samples]; see :func:`frf`.
    df : float, optional
        Largest frequency resolution [Hz], used when ``nperseg`` is not given.
    f_min : float
        Lower end of the band where peaks are searched [Hz].
    f_max : float, optional
        Upper end of that band [Hz]; default 0.8 of the Nyquist frequency.
    n_modes : int, optional
        At most this many modes, the lowest in frequency, are returned; default all.
    prominence : float
        Smallest prominence of a peak of ``log10 |H|`` [decades].
    smooth_bins : int
        Width of the running mean over ``log10 |H|`` before peak picking [bins].
    min_coherence : float
        Smallest coherence at a peak for it to be a mode [-].
    min_coherence_reliable : float
        Below this coherence at the peak [-], the mode carries a warning.
    max_damping : float
        Above this fitted damping ratio [-], the mode carries a warning.
    name : str, optional
        Label of the result; default the name of the test, or ``""``.

    Returns
    -------
    ModalResult
        The FRF and the modes found, by increasing frequency.

    Raises
    ------
    ModalError
        If the input is not a test nor ``(x, y)`` with ``fs``, has non-finite values or a
        constant input, ``nperseg`` is out of range, or the band holds no frequency bins.

    References
    ----------
    Bendat & Piersol, *Random Data*, 4th ed., §8.5 and §9.2; Mordant et al. (SERIES), §2.1,
    Figures 3 and 4.
    """
    fr = frf(data, fs, nperseg=nperseg, df=df)
    f, H, coh = fr.f, fr.H, fr.coherence
    if f_max is None:
        f_max = 0.8 * fr.fs / 2
    mag = np.abs(H)
    logm = np.log10(np.maximum(mag, 1e-300))
    from scipy.signal import find_peaks

    band = (f > f_min) & (f < f_max)
    nb = max(int(smooth_bins), 1)
    smooth = np.convolve(logm, np.ones(nb) / nb, mode="same") if nb > 1 else logm
    inband = np.flatnonzero(band)
    if inband.size < 3:
        raise ModalError(f"no frequency bins in the band ({f_min}, {f_max}) Hz")
    idx, _ = find_peaks(smooth[inband], prominence=prominence)
    idx = inband[idx]
    keep = []
    for k in idx:
        a, b = max(k - nb, 1), min(k + nb + 1, f.size - 1)
        i = a + int(np.argmax(mag[a:b]))
        if band[i] and coh[i] >= min_coherence and 0 < i < f.size - 1 and i not in keep:
            keep.append(i)
    keep.sort()
    if n_modes is not None:
        keep = keep[:n_modes]
    modes = []
    for q, i in enumerate(keep):
        prev = keep[q - 1] if q > 0 else 1
        nxt = keep[q + 1] if q + 1 < len(keep) else f.size - 2
        lo = prev + int(np.argmin(mag[prev:i + 1])) if q > 0 else 1
        hi = i + int(np.argmin(mag[i:nxt + 1])) if q + 1 < len(keep) else f.size - 2
        p, lv = _parabolic(logm, i)
        fpk = f[i] + p * fr.df
        amp = 10 ** lv
        f1, f2 = _half_power(f, mag, i, lo, hi, amp / math.sqrt(2))
        warn = []
        if coh[i] < min_coherence_reliable:
            warn.append(f"low coherence {coh[i]:.2f} at the peak")
        if math.isfinite(f1) and math.isfinite(f2):
            z_hp = (f2 - f1) / (2 * fpk)
            if (f2 - f1) < 4 * fr.df:
                warn.append(f"half-power bandwidth {f2 - f1:.3g} Hz under 4 frequency bins "
                            f"(df {fr.df:.3g} Hz): resolution bias")
        else:
            z_hp = float("nan")
            warn.append("half-power point not found")
        z0 = z_hp if math.isfinite(z_hp) and z_hp > 0 else 0.05
        half = max(2.5 * z0 * fpk, 5 * fr.df)
        j0 = max(int(np.searchsorted(f, fpk - half)), lo, 1)
        j1 = min(int(np.searchsorted(f, fpk + half)) + 1, hi + 1, f.size)
        if j1 - j0 < 6:
            j0, j1 = max(i - 3, 1), min(i + 4, f.size)
        try:
            fk, zk, coef, ok, at_bound = _fit_mode(fr, slice(j0, j1), fpk, min(z0, 0.9))
        except (ValueError, np.linalg.LinAlgError):
            fk, zk, coef, ok, at_bound = fpk, z_hp, (complex("nan"),) * 2, False, False
        if not ok:
            warn.append("modal fit failed")
        elif at_bound:
            warn.append("modal fit at a bound of the fitting band")
        if math.isfinite(zk) and zk > max_damping:
            warn.append(f"damping {100 * zk:.0f} % above {100 * max_damping:.0f} %")
        if math.isfinite(z_hp) and math.isfinite(zk) and abs(z_hp - zk) > 0.3 * zk:
            warn.append(f"half-power ({100 * z_hp:.1f} %) and fitted ({100 * zk:.1f} %) "
                        "damping differ by more than 30 %")
        modes.append(Mode(frequency=fk, damping=zk, frequency_peak=float(fpk),
                          damping_half_power=float(z_hp), amplitude=float(amp),
                          coherence=float(coh[i]), residue=abs(coef[0]), warnings=warn,
                          fit_band=(float(f[j0]), float(f[j1 - 1])), fit_coefficients=coef))
    nm = name if name is not None else getattr(data, "name", "")
    return ModalResult(frf=fr, modes=modes, name=nm)


# --- evolution along a sequence ------------------------------------------------------------

@dataclass
class Evolution:
    """Frequencies and damping ratios of the white-noise tests of a sequence, made by
    :func:`evolution`.

    Attributes
    ----------
    name : str
        Name of the sequence (the specimen).
    labels : list of str
        Label of each white-noise test, in the order of the sequence.
    number : numpy.ndarray
        Position of each test in the sequence, shape (n_tests,).
    after_pga_g : numpy.ndarray
        Nominal PGA of the last seismic test before each one [g] (0 before the first; the
        measured PGA where no nominal one is given), shape (n_tests,).
    frequency : numpy.ndarray
        Fitted natural frequencies [Hz], shape (n_tests, n_modes); NaN where a mode was not
        found.
    damping : numpy.ndarray
        Fitted damping ratios [-], shape (n_tests, n_modes); NaN where not found.
    damping_half_power : numpy.ndarray
        Half-power damping ratios [-], shape (n_tests, n_modes); NaN where not found.
    reliable : numpy.ndarray
        Whether each mode is :attr:`Mode.reliable`, bool, shape (n_tests, n_modes); False where
        not found.
    results : list of ModalResult
        The full identification of each test.

    References
    ----------
    Mordant et al. (SERIES), §2.1, Figures 3 and 4.
    """

    name: str
    labels: list[str]
    number: np.ndarray
    after_pga_g: np.ndarray
    frequency: np.ndarray
    damping: np.ndarray
    damping_half_power: np.ndarray
    reliable: np.ndarray
    results: list[ModalResult] = field(default_factory=list, repr=False)

    def rows(self) -> list[dict]:
        out = []
        for k, lab in enumerate(self.labels):
            row = {"test": lab, "number": int(self.number[k]),
                   "after_pga_g": float(self.after_pga_g[k])}
            for m in range(self.frequency.shape[1]):
                row[f"f{m + 1}_hz"] = _clean(self.frequency[k, m])
                row[f"zeta{m + 1}"] = _clean(self.damping[k, m])
                row[f"zeta{m + 1}_half_power"] = _clean(self.damping_half_power[k, m])
                row[f"reliable{m + 1}"] = bool(self.reliable[k, m])
            out.append(row)
        return out

    def table(self) -> str:
        nm = self.frequency.shape[1]
        head = "| test | no. | after PGA [g] | " + " | ".join(
            f"f{m + 1} [Hz] | zeta{m + 1} [%]" for m in range(nm)) + " |"
        rows = [head, "|" + "---|" * (3 + 2 * nm)]
        for k, lab in enumerate(self.labels):
            cells = [lab, str(int(self.number[k])), f"{self.after_pga_g[k]:.3f}"]
            for m in range(nm):
                fk, zk = self.frequency[k, m], self.damping[k, m]
                mark = "" if self.reliable[k, m] else " (?)"
                cells += ["/" if not math.isfinite(fk) else f"{fk:.3f}",
                          "/" if not math.isfinite(zk) else f"{100 * zk:.2f}{mark}"]
            rows.append("| " + " | ".join(cells) + " |")
        return "\n".join(rows)


def evolution(sequence, n_modes: int = 1, **kwargs) -> Evolution:
    """Identify every white-noise test of ``sequence`` (a
    :class:`~murus.identify.testdata.TestSequence`) with :func:`identify` (``kwargs`` passed
    on) and tabulate the first ``n_modes`` modes along the sequence.

    Parameters
    ----------
    sequence : TestSequence
        The tests of a specimen.
    n_modes : int
        Modes tabulated.
    **kwargs
        Keywords of :func:`identify`.

    Returns
    -------
    Evolution
    """
    labels, number, after, results = [], [], [], []
    last_pga = 0.0
    for e in sequence.entries:
        if e.kind == "seismic":
            last_pga = e.pga_g if e.pga_g is not None else e.test.measured_pga_g
            continue
        res = identify(e.test, n_modes=n_modes, name=e.label, **kwargs)
        labels.append(e.label)
        number.append(e.number)
        after.append(last_pga)
        results.append(res)
    if not results:
        raise ModalError(f"sequence {sequence.name!r} has no white-noise test")
    nt = len(results)
    F = np.full((nt, n_modes), np.nan)
    Z = np.full((nt, n_modes), np.nan)
    Zh = np.full((nt, n_modes), np.nan)
    R = np.zeros((nt, n_modes), bool)
    for k, res in enumerate(results):
        for m, mode in enumerate(res.modes[:n_modes]):
            F[k, m], Z[k, m], Zh[k, m] = mode.frequency, mode.damping, mode.damping_half_power
            R[k, m] = mode.reliable
    return Evolution(name=sequence.name, labels=labels, number=np.array(number),
                     after_pga_g=np.array(after, float), frequency=F, damping=Z,
                     damping_half_power=Zh, reliable=R, results=results)


# --- figures -------------------------------------------------------------------------------

def plot_frf(result: ModalResult, axes=None):
    """|H1|, phase and coherence against frequency, identified modes marked; returns the
    three axes."""
    import matplotlib.pyplot as plt

    fr = result.frf
    if axes is None:
        fig, axes = plt.subplots(3, 1, sharex=True, figsize=(7, 7),
                                 gridspec_kw={"height_ratios": [3, 1.5, 1.5]})
    a0, a1, a2 = axes
    a0.semilogy(fr.f, np.abs(fr.H), lw=0.9, label="|H1| (top / table)")
    for k, m in enumerate(result.modes):
        if all(math.isfinite(v) for v in m.fit_band) and math.isfinite(m.damping):
            ff = np.linspace(*m.fit_band, 200)
            a0.semilogy(ff, np.abs(m.fitted(ff)), color="C1", lw=1.5,
                        label="modal fit" if k == 0 else None)
        a0.axvline(m.frequency, color="C3", lw=0.7, ls="--")
        a0.annotate(f"{m.frequency:.2f} Hz\n{100 * m.damping:.1f} %"
                    + ("" if m.reliable else " (?)"), (m.frequency, m.amplitude),
                    textcoords="offset points", xytext=(5, -5), fontsize=8, va="top")
    ok = fr.coherence >= 0.5
    if ok.any():
        a0.set_xlim(0, min(fr.f[ok].max() * 1.1, fr.f[-1]))
    a0.set_ylabel("|H| [-]")
    a0.legend(fontsize=8)
    a1.plot(fr.f, np.degrees(np.angle(fr.H)), lw=0.8)
    a1.set_ylabel("phase [deg]")
    a2.plot(fr.f, fr.coherence, lw=0.8)
    a2.set_ylim(0, 1.05)
    a2.set_ylabel("coherence [-]")
    a2.set_xlabel("frequency [Hz]")
    a0.set_title(result.name or "FRF")
    return axes


def _x(evo: Evolution, x: str):
    if x == "test":
        return evo.number, "test number in the sequence"
    if x == "pga":
        return evo.after_pga_g, "PGA of the preceding seismic test [g]"
    raise ModalError(f"x must be 'test' or 'pga', got {x!r}")


def plot_frequency_evolution(evo: Evolution, ax=None, x: str = "test", label: str | None = None):
    """Natural frequencies along the sequence (Mordant et al. (SERIES), Figure 3)."""
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(6, 4))
    xs, xl = _x(evo, x)
    for m in range(evo.frequency.shape[1]):
        ax.plot(xs, evo.frequency[:, m], "o-", label=f"{label or evo.name} mode {m + 1}")
    ax.set_xlabel(xl)
    ax.set_ylabel("natural frequency [Hz]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    return ax


def plot_damping_evolution(evo: Evolution, ax=None, x: str = "test", label: str | None = None):
    """Damping ratios along the sequence (Mordant et al. (SERIES), Figure 4); unreliable estimates
    drawn as open markers."""
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(6, 4))
    xs, xl = _x(evo, x)
    for m in range(evo.damping.shape[1]):
        z = 100 * evo.damping[:, m]
        (line,) = ax.plot(xs, z, "-", label=f"{label or evo.name} mode {m + 1}")
        ok = evo.reliable[:, m]
        ax.plot(xs[ok], z[ok], "o", color=line.get_color())
        ax.plot(xs[~ok], z[~ok], "o", mfc="none", color=line.get_color(),
                label="questionable" if (~ok).any() else None)
    ax.set_xlabel(xl)
    ax.set_ylabel("damping ratio [%]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    return ax

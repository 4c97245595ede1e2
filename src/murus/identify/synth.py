"""A virtual shaking-table test sequence in the documented format (issue 8, item 8).

No shaking-table data ships with murus, so :func:`synthesize_sequence` writes a complete
sequence like that of Mordant et al. (SERIES) (§2: white-noise tests alternating with seismic tests
of increasing level, Table 1) for a wall with a mass on top. The files follow
:mod:`murus.identify.testdata`, so everything that reads them works unchanged on laboratory
files. The wall model is deliberately simple and stated here, not calibrated on any test:

- **Cantilever (all tests).** The wall is one linear mode (frequency ``f``, damping ``zeta``)
  excited at its base: top absolute acceleration and top displacement relative to the base from
  the exact discrete-time solution for a piecewise-linear input (first-order hold,
  :func:`modal_response`). The bending rotation of the top is ``1.5 u / H`` (a cantilever under
  a tip load).
- **Elastic base joint.** A no-tension Winkler bed of stiffness ``k_b = m g / (closure L)``
  (``closure``: its static closure under the top mass, default 10 um) carries ``N = m g`` and
  the moment ``M = -m a_top H`` (inertia of the top mass). The compressed length is ``L`` while
  ``|e| = |M| / N <= L/6`` and ``3 (L/2 - |e|)`` beyond (the EN 1996-1-1 linear stress block),
  down to ``min_contact`` (default 10 % of ``L``: ``|e|`` is capped there, since the rotation
  of a no-tension Winkler bed grows without bound as the contact shrinks; larger uplifts are
  the rigid rocking below); the base rotation is the slope of the compression line. The
  transducers are zeroed before the mass is placed (header ``lvdt_zero: unloaded``), so they
  read ``-closure`` at rest and the plane-section contact length with ``closure = 0``
  (:mod:`murus.identify.compressive`) is exactly the one of the model.
- **Rigid rocking (seismic tests above the onset).** :func:`murus.rocking.simulate` of the
  wall as a rigid block with the top mass (``series_clay_wall``-like geometry, Housner restitution)
  under the table motion gives ``theta(t)``; it is zero below the uplift acceleration
  ``g L / (2 H)`` and is added to both rotations, to the transducers (a rigid rotation about
  the corner: ``(L - x) sin theta`` for ``theta > 0``) and to the top acceleration
  (``H d2theta/dt2``). The rocking module's sign convention makes a positive table
  acceleration drive a positive rotation; it is fed ``-table_acc`` so that ``theta > 0`` moves
  the top towards ``+x`` like a positive cantilever displacement.
- **Damage.** After each seismic test of PGA ``a`` [g] the frequency is multiplied by
  ``1 - frequency_drop_per_g * a`` and ``damping_increase_per_g * a`` is added to the damping
  ratio, so the white-noise tests see a frequency dropping along the sequence
  (Mordant et al. (SERIES) Figures 3-4).
- **Inputs.** White-noise tests: Gaussian noise band-limited to ``wn_band`` [Hz], RMS
  ``wn_rms_g``. Seismic tests: one band-limited noise record (1-15 Hz) with a trapezoidal
  envelope (rise 15 %, strong part 55 %, decay 30 % of the duration), scaled to each PGA level,
  as Mordant et al. (SERIES) scales one artificial record step by step.
- **Sensors.** Independent Gaussian noise on every channel: ``noise_acc`` [m/s2],
  ``noise_lvdt`` [m], ``noise_rot`` [rad].

Everything is deterministic for a given ``seed``. ``truth.json`` in the folder records the
true frequency and damping of every test and whether the rigid body rocked.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from murus import G
from murus.identify.testdata import ShakingTableTest, write_sequence

__all__ = ["modal_response", "SynthWall", "synthesize_tests", "synthesize_sequence",
           "DEFAULT_LEVELS"]

#: Nominal PGA levels [g] of the seismic tests (close to Mordant et al. (SERIES), Table 1, long
#: wall).
DEFAULT_LEVELS = (0.04, 0.08, 0.08, 0.16, 0.24, 0.32, 0.45)


def modal_response(acc, dt: float, modes):
    """Absolute acceleration and relative displacement of a base-excited linear structure.

    ``acc``: table acceleration [m/s2] sampled at ``dt`` [s], linear between samples;
    ``modes``: ``[(f_k [Hz], zeta_k, r_k), ...]`` with ``r_k`` the mode shape at the output
    point times the participation factor. Each modal equation
    ``q'' + 2 zeta w q' + w^2 q = -a_g`` is discretised exactly for a piecewise-linear input
    (the matrix-exponential step of :func:`scipy.signal.lsim`, written as a recursive
    filter) and filtered. Returns
    ``(absolute acceleration [m/s2], relative displacement [m])`` at the output point:
    ``a_g + sum r_k q_k''`` and ``sum r_k q_k``; the transfer function of the first is
    :func:`murus.identify.modal.transmissibility`.

    Parameters
    ----------
    acc : array_like
        Table acceleration [m/s²].
    dt : float
        [s].
    modes : sequence of tuple
        ``(f_k [Hz], zeta_k [-], r_k [-])``.

    Returns
    -------
    tuple of numpy.ndarray
        Absolute acceleration [m/s²] and relative displacement [m].
    """
    from scipy import signal
    from scipy.linalg import expm

    acc = np.asarray(acc, dtype=float)
    a_abs = acc.copy()
    u = np.zeros_like(acc)
    for fk, zk, rk in modes:
        w = 2 * math.pi * fk
        A = np.array([[0.0, 1.0], [-w * w, -2 * zk * w]])
        B = np.array([[0.0], [-1.0]])
        C = np.array([[-w * w, -2 * zk * w], [1.0, 0.0]])  # q'' + a_g, and q
        # exact step for an input linear between samples (as scipy.signal.lsim):
        # x[k+1] = Ad x[k] + B0 u[k] + B1 u[k+1]
        Mx = np.zeros((4, 4))
        Mx[:2, :2] = A * dt
        Mx[:2, 2:3] = B * dt
        Mx[2, 3] = 1.0
        E = expm(Mx)
        Ad, B1 = E[:2, :2], E[:2, 3:4]
        B0 = E[:2, 2:3] - B1
        # with w[k] = x[k] - B1 u[k]: w[k+1] = Ad w[k] + (Ad B1 + B0) u[k], y = C w + C B1 u
        Bw = Ad @ B1 + B0
        x0 = B1[:, 0] * acc[0]  # the filter below starts from x[0] = B1 u[0], lsim from 0
        for row in (0, 1):
            c = C[row]
            y = signal.lfilter(*_tf2(Ad, Bw[:, 0], c, float(c @ B1[:, 0])), acc)
            imp = np.zeros_like(acc)
            imp[0] = 1.0
            y -= signal.lfilter(*_tf2(Ad, Ad @ x0, c, float(c @ x0)), imp)
            if row == 0:
                a_abs += rk * (y - acc)
            else:
                u += rk * y
    return a_abs, u


def _tf2(Ad, b, c, d):
    """Transfer function (numerator, denominator in powers of 1/z) of the 2-state discrete
    system ``(Ad, b, c, d)``: ``c adj(zI - Ad) b + d det(zI - Ad)`` over ``det(zI - Ad)``."""
    (a11, a12), (a21, a22) = Ad
    den = np.array([1.0, -(a11 + a22), a11 * a22 - a12 * a21])
    num = d * den + np.array([0.0, c[0] * b[0] + c[1] * b[1],
                              c[0] * (a12 * b[1] - a22 * b[0]) + c[1] * (a21 * b[0] - a11 * b[1])])
    return num, den


@dataclass(frozen=True)
class SynthWall:
    """The virtual specimen (module docstring): length ``L``, height ``H`` [m], top mass
    [kg], initial frequency [Hz] and damping ratio, base closure [m], number of transducers
    (evenly from 2 % to 98 % of ``L``), smallest contact length of the elastic base as a
    fraction of ``L``.

    Parameters
    ----------
    length, height, thickness : float
        [m].
    top_mass : float
        [kg].
    frequency : float
        Initial frequency [Hz].
    damping : float
        Initial damping ratio [-].
    closure : float
        Base closure [m].
    n_lvdt : int
        Number of base transducers.
    min_contact : float
        Smallest contact length over ``length`` [-].
    """

    length: float = 0.72
    height: float = 1.80
    thickness: float = 0.138
    top_mass: float = 5000.0
    frequency: float = 8.0
    damping: float = 0.05
    closure: float = 1e-5
    n_lvdt: int = 5
    min_contact: float = 0.1

    @property
    def lvdt_positions(self) -> np.ndarray:
        return np.linspace(0.02, 0.98, self.n_lvdt) * self.length

    def base_joint(self, a_top: np.ndarray):
        """Readings (n_lvdt, n) [m] and base rotation [rad] of the elastic no-tension bed
        under the inertia of the top mass ``a_top`` [m/s2] (module docstring)."""
        L, x = self.length, self.lvdt_positions
        M = -self.top_mass * a_top * self.height  # clockwise-positive moment [N m]
        N = self.top_mass * G
        e_max = 0.5 * L - self.min_contact * L / 3.0
        e = np.clip(M / N, -e_max, e_max)
        kb = N / (self.closure * L)  # [N/m2]
        lin = np.abs(e) <= L / 6
        # compression c(x) = c_mid + slope (x - L/2), positive slope when e > 0
        slope_lin = 12 * N * e / (kb * L**3)
        lc = 3 * (L / 2 - np.abs(e))
        cmax = 2 * N / (kb * np.where(lin, L, lc))
        slope_tri = np.sign(e) * cmax / np.where(lin, L, lc)
        slope = np.where(lin, slope_lin, slope_tri)
        # triangle: zero at x = L - lc (e > 0) or x = lc (e < 0)
        x_zero = np.where(e > 0, L - lc, lc)
        c_mid = np.where(lin, N / (kb * L), slope * (L / 2 - x_zero))
        c = c_mid[None, :] + slope[None, :] * (x[:, None] - L / 2)
        return -c, slope


def _envelope(n: int) -> np.ndarray:
    s = np.linspace(0, 1, n)
    env = np.ones(n)
    env[s < 0.15] = s[s < 0.15] / 0.15
    late = s > 0.70
    env[late] = np.clip((1 - s[late]) / 0.30, 0, 1)
    return env


def _band_noise(n: int, dt: float, band, rng) -> np.ndarray:
    x = rng.standard_normal(n)
    X = np.fft.rfft(x)
    f = np.fft.rfftfreq(n, dt)
    X[(f < band[0]) | (f > band[1])] = 0.0
    x = np.fft.irfft(X, n=n)
    return x / np.sqrt(np.mean(x * x))


def _rocking(wall: SynthWall, acc: np.ndarray, dt: float):
    from murus.motion import GroundMotion
    from murus.rocking import RigidBlock, simulate

    body = RigidBlock(width=wall.length, height=wall.height, thickness=wall.thickness,
                      density=0.0, top_mass=wall.top_mass, name="synth")
    if np.max(np.abs(acc)) < body.uplift_acceleration:
        return np.zeros_like(acc)
    res = simulate(body, GroundMotion(dt=dt, acc=-acc), duration=(acc.size - 1) * dt, out_dt=dt)
    th = np.zeros_like(acc)
    m = min(th.size, res.theta.size)
    th[:m] = res.theta[:m]
    if res.overturned:
        raise ValueError("the synthetic wall overturned: lower the PGA levels")
    return th


def _one_test(wall: SynthWall, name: str, kind: str, acc: np.ndarray, fs: float, f: float,
              z: float, pga: float | None, rng, noise) -> tuple[ShakingTableTest, dict]:
    dt = 1.0 / fs
    a_top, u = modal_response(acc, dt, [(f, z, 1.0)])
    theta = _rocking(wall, acc, dt) if kind == "seismic" else np.zeros_like(acc)
    rocked = bool(np.any(theta != 0.0))
    d_el, phi_b = wall.base_joint(a_top)
    x = wall.lvdt_positions
    L = wall.length
    st = np.sin(theta)
    d_rock = np.where(st > 0, (L - x)[:, None] * st[None, :], -x[:, None] * st[None, :])
    a_top = a_top + wall.height * np.gradient(np.gradient(theta, dt), dt)
    rot_bottom = phi_b + theta
    rot_top = phi_b + 1.5 * u / wall.height + theta
    n_acc, n_lvdt, n_rot = noise
    chans = {"table_acc": acc + n_acc * rng.standard_normal(acc.size),
             "top_acc": a_top + n_acc * rng.standard_normal(acc.size)}
    d = d_el + d_rock + n_lvdt * rng.standard_normal(d_el.shape)
    for k in range(x.size):
        chans[f"lvdt_{k + 1}"] = d[k]
    chans["rot_bottom"] = rot_bottom + n_rot * rng.standard_normal(acc.size)
    chans["rot_top"] = rot_top + n_rot * rng.standard_normal(acc.size)
    test = ShakingTableTest(
        name=name, sampling_rate=fs, wall_length=L, wall_height=wall.height, channels=chans,
        kind=kind, pga_g=pga, lvdt_positions=x, top_mass=wall.top_mass,
        meta={"lvdt_zero": "unloaded", "source": "murus.identify.synth (virtual test)"})
    truth = {"test": name, "kind": kind, "frequency_hz": f, "damping": z, "pga_g": pga,
             "rocked": rocked, "theta_max_rad": float(np.max(np.abs(theta)))}
    return test, truth


def synthesize_tests(*, seed: int = 0, wall: SynthWall | None = None,
                     levels=DEFAULT_LEVELS, fs: float = 100.0, wn_duration: float = 120.0,
                     wn_rms_g: float = 0.02, wn_band=(0.5, 40.0), seismic_duration: float = 20.0,
                     frequency_drop_per_g: float = 0.35, damping_increase_per_g: float = 0.04,
                     noise_acc: float = 0.005, noise_lvdt: float = 1e-6,
                     noise_rot: float = 2e-6):
    """The tests of a virtual sequence and their truth (module docstring), in memory.

    White-noise tests ``WN01, WN02, ...`` alternate with seismic tests ``S01, S02, ...``, one
    per level, starting and ending with a white-noise test.

    Parameters
    ----------
    seed : int
        Seed of the random generator (inputs and sensor noise); the output is deterministic
        for a given seed.
    wall : SynthWall, optional
        The virtual wall; default ``SynthWall()``.
    levels : sequence of float
        Nominal PGA of the seismic tests, in order [g], each in (0, 2).
    fs : float
        Sampling rate [Hz]; more than four times the wall's frequency.
    wn_duration : float
        Duration of a white-noise test [s] (at least 2048 samples).
    wn_rms_g : float
        RMS of the white-noise table acceleration [g].
    wn_band : tuple of float
        Frequency band of the white noise [Hz].
    seismic_duration : float
        Duration of a seismic test [s] (at least 64 samples).
    frequency_drop_per_g : float
        Relative drop of the frequency after a seismic test, per g of its PGA [1/g].
    damping_increase_per_g : float
        Increase of the damping ratio after a seismic test, per g of its PGA [1/g].
    noise_acc : float
        Standard deviation of the noise on the accelerations [m/s²].
    noise_lvdt : float
        Standard deviation of the noise on the transducers [m].
    noise_rot : float
        Standard deviation of the noise on the rotations [rad].

    Returns
    -------
    tests : list of ShakingTableTest
        The tests, in the order of the sequence.
    truth : list of dict
        Per test: ``test`` (name), ``kind``, ``frequency_hz`` [Hz] and ``damping`` [-] of the
        wall during the test, ``pga_g`` [g] (``None`` for white noise), ``rocked`` (bool) and
        ``theta_max_rad``, the largest rigid rocking rotation [rad].

    Raises
    ------
    ValueError
        If a level is outside (0, 2) g, ``fs`` is too low for the wall, or a duration is too
        short for ``fs``.

    References
    ----------
    Mordant et al. (SERIES), §2 and Table 1 (the sequence), Figures 3-4 (the frequency drop).
    """
    wall = wall or SynthWall()
    levels = [float(a) for a in levels]
    if not levels or any(not (math.isfinite(a) and 0 < a < 2) for a in levels):
        raise ValueError(f"levels must be PGAs in (0, 2) g, got {levels!r}")
    if not (math.isfinite(fs) and fs > 4 * wall.frequency):
        raise ValueError(f"fs must exceed four times the wall frequency, got {fs!r}")
    if wn_duration * fs < 2048 or seismic_duration * fs < 64:
        raise ValueError("wn_duration and seismic_duration are too short for fs")
    rng = np.random.default_rng(seed)
    dt = 1.0 / fs
    n_s = int(round(seismic_duration * fs)) + 1
    base = _band_noise(n_s, dt, (1.0, 15.0), rng) * _envelope(n_s)
    base /= np.max(np.abs(base))
    noise = (noise_acc, noise_lvdt, noise_rot)
    f, z = wall.frequency, wall.damping
    tests, truth = [], []
    n_w = int(round(wn_duration * fs)) + 1
    for k in range(len(levels) + 1):
        wn = _band_noise(n_w, dt, wn_band, rng) * wn_rms_g * G
        t, tr = _one_test(wall, f"WN{k + 1:02d}", "white_noise", wn, fs, f, z, None, rng,
                          noise)
        tests.append(t)
        truth.append(tr)
        if k == len(levels):
            break
        a = levels[k]
        t, tr = _one_test(wall, f"S{k + 1:02d}", "seismic", base * a * G, fs, f, z, a, rng,
                          noise)
        tests.append(t)
        truth.append(tr)
        f *= max(1.0 - frequency_drop_per_g * a, 0.2)
        z += damping_increase_per_g * a
    return tests, truth


def synthesize_sequence(folder, *, seed: int = 0, name: str = "virtual wall", **kwargs) -> Path:
    """Write a virtual test sequence into ``folder`` (created; files ``NN_<test>.csv``,
    ``sequence.toml`` and ``truth.json``); ``kwargs`` as :func:`synthesize_tests`. Returns
    the folder. Deterministic for a given ``seed``.

    Parameters
    ----------
    folder : str or pathlib.Path
        Created.
    seed : int
        Seed of the noise.
    name : str
        Name of the specimen.
    **kwargs
        Keywords of :func:`synthesize_tests`.

    Returns
    -------
    pathlib.Path
    """
    tests, truth = synthesize_tests(seed=seed, **kwargs)
    folder = Path(folder)
    write_sequence(folder, tests, name=name)
    meta = {"seed": seed, "name": name, "model": "murus.identify.synth", "tests": truth}
    (folder / "truth.json").write_text(json.dumps(meta, indent=2), encoding="utf-8")
    return folder

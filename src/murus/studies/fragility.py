"""Fragility functions of rocking walls from a record suite: multiple-stripe analysis (MSA) or
incremental dynamic analysis (IDA), lognormal fits by maximum likelihood, confidence bands.

The fragility of a limit state is ``P(LS | IM = x) = Phi(ln(x / theta) / beta)`` with median
``theta`` (units of the IM) and dispersion ``beta``.

- MSA (Baker 2015, Earthquake Spectra 31(1), eq. 11): at each level ``x_j`` the ``n_j`` records
  scaled to ``x_j`` give ``z_j`` exceedances; the likelihood is binomial,
  ``L = prod_j C(n_j, z_j) p_j^z_j (1 - p_j)^(n_j - z_j)`` with ``p_j = Phi(ln(x_j / theta) /
  beta)``. Written as a probit regression ``p_j = Phi(a + b ln x_j)`` (``b = 1 / beta``,
  ``a = -ln(theta) / beta``) the negative log-likelihood is convex in ``(a, b)``, so the
  maximum found is the global one.
- IDA (Baker 2015 eq. 3-4 as maximum likelihood): each record's capacity is the lowest level at
  which it exceeds the limit state (rocking response is not monotonic in the scale: "first
  exceedance"; the resolution is the spacing of the levels); records that never exceed are
  right-censored at the highest level. Without censoring ``ln theta`` is the mean of the log
  capacities and ``beta`` their standard deviation (MLE, divisor n).

Limit states (EURODYN (2020), §4): ``theta_max / alpha >= 0.1`` (limited rocking), ``>= 0.4``
(moderate rocking), overturning. Confidence bands: bootstrap over the records (the same records
are scaled to every level, so resampling records keeps the correlation between stripes), or the
Fisher information (expected information of the binomial likelihood for MSA, observed information
for IDA) with the delta method for the curve.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from murus.rocking.summary import LIMIT_STATES as _ROCKING_LIMIT_STATES

__all__ = ["FragilityFit", "fit_msa", "fit_ida", "fisher_covariance", "fragility_curve",
           "LIMIT_STATES", "exceedance", "fit_fragility", "fragility", "restraint_configs",
           "plot_fragility"]

#: name -> threshold on theta_max / alpha (None: overturning); the rocking limit states are
#: declared once in :data:`murus.rocking.summary.LIMIT_STATES`.
LIMIT_STATES = {**_ROCKING_LIMIT_STATES, "overturning": None}

_B_MIN, _B_MAX = 1.0 / 5.0, 1.0 / 0.01  # beta in [0.01, 5]


@dataclass(frozen=True)
class FragilityFit:
    """A lognormal fragility: ``median`` (IM units), ``beta`` [-], ``cov`` the 2 x 2 covariance
    of ``(ln median, beta)`` (NaN if not available), ``loglik``, ``status`` ("ok", "none
    exceeded", "all exceeded", "boundary": beta hit its bound of [0.01, 5]).

    Attributes
    ----------
    median : float
        Median capacity (IM units).
    beta : float
        Logarithmic standard deviation [-].
    cov : numpy.ndarray
        Covariance of ``(ln median, beta)``.
    loglik : float
        Log-likelihood at the optimum.
    status : str
        ``"ok"``, ``"none exceeded"``, ``"all exceeded"`` or ``"boundary"``.
    """

    median: float
    beta: float
    cov: np.ndarray
    loglik: float
    status: str = "ok"

    def __call__(self, x):
        return fragility_curve(x, self.median, self.beta)


def fragility_curve(x, median: float, beta: float):
    """``Phi(ln(x / median) / beta)``.

    Parameters
    ----------
    x : array_like
        IM values (IM units).
    median : float
        Median capacity (IM units).
    beta : float
        Logarithmic standard deviation [-].

    Returns
    -------
    numpy.ndarray
        Probability of exceedance [-].
    """
    from scipy.special import ndtr

    x = np.asarray(x, dtype=float)
    with np.errstate(divide="ignore"):
        return ndtr(np.log(x / median) / beta)


def _check_stripes(levels, n, z):
    x = np.asarray(levels, dtype=float)
    n = np.asarray(n, dtype=float)
    z = np.asarray(z, dtype=float)
    if not (x.shape == n.shape == z.shape and x.ndim == 1 and x.size >= 1):
        raise ValueError("levels, n and z must be 1-D arrays of the same length")
    if np.any(x <= 0) or not np.all(np.isfinite(x)):
        raise ValueError("IM levels must be positive and finite")
    if np.any(z < 0) or np.any(z > n):
        raise ValueError("exceedances must satisfy 0 <= z <= n")
    keep = n > 0
    return x[keep], n[keep], z[keep]


_LOG_SQRT_2PI = 0.5 * math.log(2.0 * math.pi)


def _probit_nll(a: float, b: float, v, z, m):
    """Negative log-likelihood of the stripes at ``u = a + b v`` (binomial coefficients
    omitted), or ``inf`` where it is not finite."""
    from scipy.special import log_ndtr

    u = a + b * v
    with np.errstate(over="ignore", invalid="ignore"):
        f = -float(z @ log_ndtr(u) + m @ log_ndtr(-u))
    return f if math.isfinite(f) else math.inf


def _probit_derivatives(a: float, b: float, v, z, m):
    """Negative log-likelihood ``f`` of the stripes at ``u = a + b v``, its gradient and Hessian
    in ``(a, b)``.

    With ``r1 = phi(u) / Phi(u)`` and ``r2 = phi(u) / Phi(-u)`` (from :func:`log_ndtr`, stable
    for large ``|u|``), ``df/du = -z r1 + m r2`` and ``d2f/du2 = z r1 (u + r1) + m r2 (r2 - u)``,
    each curvature term being in ``(0, 1)`` (the normal CDF is strongly log-concave: it is
    clipped there against the cancellation in ``u + r1`` for ``u << 0``).

    Parameters
    ----------
    a, b : float
        Probit intercept and slope.
    v : numpy.ndarray
        Centred log IM levels.
    z, m : numpy.ndarray
        Records exceeding and not exceeding at each level.

    Returns
    -------
    f : float
    grad : numpy.ndarray
        ``(df/da, df/db)``.
    hess : numpy.ndarray
        2 x 2.
    """
    from scipy.special import log_ndtr

    u = a + b * v
    lp, lq = log_ndtr(u), log_ndtr(-u)
    f = -float(z @ lp + m @ lq)
    lphi = -0.5 * u * u - _LOG_SQRT_2PI
    r1 = np.exp(lphi - lp)  # phi / Phi(u)
    r2 = np.exp(lphi - lq)  # phi / Phi(-u)
    d = m * r2 - z * r1
    w = z * np.clip(r1 * (u + r1), 0.0, 1.0) + m * np.clip(r2 * (r2 - u), 0.0, 1.0)
    wv = w * v
    grad = np.array([d.sum(), d @ v])
    hess = np.array([[w.sum(), wv.sum()], [wv.sum(), wv @ v]])
    return f, grad, hess


def _newton_direction(grad, hess):
    """``-hess^-1 grad``, with a ridge if ``hess`` is (numerically) singular."""
    h00, h01, h11 = hess[0, 0], hess[0, 1], hess[1, 1]
    scale = max(h00, h11, 1e-300)
    ridge = 0.0
    for _ in range(60):
        p, s = h00 + ridge, h11 + ridge
        det = p * s - h01 * h01
        if det > 1e-12 * p * s and p > 0:
            return np.array([-(s * grad[0] - h01 * grad[1]) / det,
                             -(p * grad[1] - h01 * grad[0]) / det])
        ridge = max(4.0 * ridge, 1e-10 * scale)
    return -grad / scale


def _fit_probit(v, z, m, a0: float, b0: float, b_min: float, b_max: float,
                max_iter: int = 100):
    """Minimise the negative log-likelihood of the probit model ``P = Phi(a + b v)`` over
    ``b_min <= b <= b_max`` by a projected, damped Newton method (the function is convex):
    analytic gradient and Hessian, Armijo backtracking along the projected path; when ``b`` is
    at a bound and the Newton step points out of the box, ``b`` is held there and the step is
    taken in ``a`` alone. Stops on a Newton decrement ``-g^T d < 1e-28 (1 + |f|)`` (about 1000
    times the decrement left by rounding: the gradient is then zero to rounding), on a step
    below rounding, or when no decrease is found along the Newton direction.

    Parameters
    ----------
    v : numpy.ndarray
        Centred log IM levels.
    z, m : numpy.ndarray
        Records exceeding and not exceeding at each level.
    a0, b0 : float
        Start.
    b_min, b_max : float
        Bounds of ``b`` (equal: ``b`` is held there and only ``a`` is fitted).
    max_iter : int
        Most Newton steps.

    Returns
    -------
    a, b, f : float
        The optimum and the negative log-likelihood there.
    """
    a, b = a0, min(max(b0, b_min), b_max)
    f, g, H = _probit_derivatives(a, b, v, z, m)
    tol = 1e-28
    for _ in range(max_iter):
        d = _newton_direction(g, H)
        at_lo = b <= b_min * (1.0 + 1e-12) and d[1] < 0.0
        at_hi = b >= b_max * (1.0 - 1e-12) and d[1] > 0.0
        if at_lo or at_hi or b_min >= b_max:  # a bound is active: Newton in a alone
            b = b_min if at_lo else b_max
            d = np.array([-g[0] / H[0, 0] if H[0, 0] > 0 else -g[0], 0.0])
        dec = -float(g @ d)  # Newton decrement squared
        if not dec > tol * (1.0 + abs(f)):
            break
        slack = 4e-16 * (1.0 + abs(f))  # rounding of f
        t = 1.0
        while t > 1e-12:
            at = a + t * d[0]
            bt = min(max(b + t * d[1], b_min), b_max)
            ft = _probit_nll(at, bt, v, z, m)
            if ft <= f + 1e-4 * min(g[0] * (at - a) + g[1] * (bt - b), 0.0) + slack:
                break
            t *= 0.5
        else:
            break  # no decrease along the Newton direction: at the optimum to rounding
        small = abs(at - a) <= 4e-16 * (1.0 + abs(a)) and abs(bt - b) <= 4e-16 * b
        a, b = at, bt
        f, g, H = _probit_derivatives(a, b, v, z, m)
        if small:
            break
    return a, b, f


def fit_msa(levels, n, z) -> FragilityFit:
    """Maximum-likelihood lognormal fragility from stripes: ``z[j]`` of ``n[j]`` records exceed
    the limit state at the level ``levels[j]`` (Baker 2015 eq. 11).

    Parameters
    ----------
    levels : array_like
        IM levels of the stripes (IM units, > 0).
    n : array_like
        Number of records at each level.
    z : array_like
        Number of records exceeding the limit state at each level.

    Returns
    -------
    FragilityFit

    Notes
    -----
    The likelihood is maximised as a probit regression ``p_j = Phi(a + b ln x_j)``, convex in
    ``(a, b)``, by a projected Newton method with the analytic gradient and Hessian
    (:func:`_fit_probit`), ``b = 1 / beta`` bounded to ``beta`` in [0.01, 5]. Without a finite
    maximum, the fit is at a bound of ``beta`` (status ``"boundary"``): separated stripes (all 0
    below a level, all ``n`` above it, at most the stripes of that one level mixed: beta = 0.01)
    or fractions flat or decreasing with the IM (the best ``beta`` above 5: beta = 5).

    References
    ----------
    Baker (2015), eq. 11.
    """
    from scipy.special import ndtri

    x, n, z = _check_stripes(levels, n, z)
    nan2 = np.full((2, 2), np.nan)
    if x.size == 0:
        return FragilityFit(math.nan, math.nan, nan2, math.nan, "no data")
    if z.sum() == 0:
        return FragilityFit(math.nan, math.nan, nan2, 0.0, "none exceeded")
    if (n - z).sum() == 0:
        return FragilityFit(math.nan, math.nan, nan2, 0.0, "all exceeded")
    lx = np.log(x)
    part = (z > 0) & (z < n)
    if not part.any():
        below = lx[z == 0]
        above = lx[z == n]
        if below.size and above.size and below.max() < above.min():
            # perfectly separated stripes: the likelihood grows as beta -> 0 (no MLE)
            med = math.exp(0.5 * (below.max() + above.min()))
            return FragilityFit(med, 1.0 / _B_MAX, nan2, 0.0, "boundary")

    # the levels are centred (u = a + b (ln x - c)) for the conditioning of the Newton steps
    c = float(n @ lx / n.sum())
    v = lx - c
    top = lx[z < n].max()
    if top <= lx[z > 0].min():
        # quasi-separated: the stripes below the level top are all 0, those above all n; the
        # likelihood grows (ever more slowly) as beta -> 0, its profile in b = 1/beta being
        # convex and decreasing: b is at its upper bound, the fraction at top is matched
        at = lx == top
        a0 = float(ndtri(z[at].sum() / n[at].sum())) - _B_MAX * (top - c)
        a, b, f = _fit_probit(v, z, n - z, a0, _B_MAX, _B_MAX, _B_MAX)
    else:
        # start: beta = 0.5 and the median where the observed fraction crosses one half
        frac = z / n
        lm0 = float(np.interp(0.5, np.maximum.accumulate(frac), lx)) if frac.max() > 0.5 \
            else float(lx.max() + 0.5)
        b0 = 2.0  # the problem is convex in (a, b): one start is enough
        a, b, f = _fit_probit(v, z, n - z, b0 * (c - lm0), b0, _B_MIN, _B_MAX)
    beta = 1.0 / b
    median = math.exp(c - a / b)
    status = "boundary" if (b <= _B_MIN * (1 + 1e-6) or b >= _B_MAX * (1 - 1e-6)) else "ok"
    cov = fisher_covariance(median, beta, x, n) if status == "ok" else nan2
    return FragilityFit(median, beta, cov, -f, status)


def fisher_covariance(median: float, beta: float, levels, n) -> np.ndarray:
    """Inverse of the expected Fisher information of the MSA likelihood in ``(ln median,
    beta)``: ``I = sum_j n_j g_j g_j^T / (p_j (1 - p_j))`` with ``g_j`` the gradient of
    ``p_j`` (``dp/d ln theta = -phi(u)/beta``, ``dp/d beta = -phi(u) u / beta``)."""
    from scipy.special import ndtr

    x = np.asarray(levels, dtype=float)
    n = np.asarray(n, dtype=float)
    u = (np.log(x) - math.log(median)) / beta
    p = np.clip(ndtr(u), 1e-300, 1 - 1e-16)
    phi = np.exp(-0.5 * u * u) / math.sqrt(2 * math.pi)
    g = np.stack([-phi / beta, -phi * u / beta])
    w = n / (p * (1 - p))
    info = (g * w) @ g.T
    try:
        return np.linalg.inv(info)
    except np.linalg.LinAlgError:
        return np.full((2, 2), np.nan)


def fit_ida(capacities, censored_at: float | None = None) -> FragilityFit:
    """Maximum-likelihood lognormal fragility from record capacities (IM at which each record
    first exceeds the limit state); NaN capacities are right-censored at ``censored_at`` (the
    highest level run). Covariance from the observed information (numerical Hessian).

    Parameters
    ----------
    capacities : array_like
        Capacity of each record, in IM units; NaN: not exceeded up to ``censored_at``.
    censored_at : float, optional
        Highest level run (IM units).

    Returns
    -------
    FragilityFit

    References
    ----------
    Baker (2015), eqs. 3-4.
    """
    from scipy.optimize import minimize
    from scipy.special import log_ndtr

    c = np.asarray(capacities, dtype=float)
    obs = np.log(c[np.isfinite(c)])
    n_cens = int(np.sum(~np.isfinite(c)))
    nan2 = np.full((2, 2), np.nan)
    if obs.size == 0:
        return FragilityFit(math.nan, math.nan, nan2, math.nan, "none exceeded")
    if n_cens and censored_at is None:
        raise ValueError("censored capacities need censored_at (the highest IM level)")
    lc = math.log(censored_at) if n_cens else 0.0

    def nll(q):
        mu, beta = q[0], math.exp(q[1])
        r = (obs - mu) / beta
        f = np.sum(0.5 * r * r + math.log(beta) + 0.5 * math.log(2 * math.pi))
        if n_cens:
            f -= n_cens * log_ndtr(-(lc - mu) / beta)
        return f

    mu0 = obs.mean()
    s0 = obs.std() if obs.size > 1 and obs.std() > 0 else 0.3
    if n_cens == 0 and obs.size > 1 and obs.std() > 0:
        mu, beta = mu0, obs.std()
    else:
        res = minimize(nll, [mu0, math.log(s0)], method="Nelder-Mead",
                       options={"xatol": 1e-10, "fatol": 1e-12, "maxiter": 4000})
        mu, beta = res.x[0], math.exp(res.x[1])
    if not (0.01 <= beta <= 5.0):
        beta = min(max(beta, 0.01), 5.0)
        return FragilityFit(math.exp(mu), beta, nan2, -nll([mu, math.log(beta)]), "boundary")
    # observed information in (mu, beta) by central differences
    h = np.array([1e-4, 1e-4]) * max(1.0, beta)

    def f2(m, b):
        return nll([m, math.log(b)])

    H = np.empty((2, 2))
    p0 = np.array([mu, beta])
    for i in range(2):
        for j in range(2):
            ei = np.eye(2)[i] * h[i]
            ej = np.eye(2)[j] * h[j]
            H[i, j] = (f2(*(p0 + ei + ej)) - f2(*(p0 + ei - ej)) - f2(*(p0 - ei + ej))
                       + f2(*(p0 - ei - ej))) / (4 * h[i] * h[j])
    try:
        cov = np.linalg.inv(H)
    except np.linalg.LinAlgError:
        cov = nan2
    return FragilityFit(math.exp(mu), beta, cov, -nll([mu, math.log(beta)]), "ok")


def _ida_capacities(E: np.ndarray, levels: np.ndarray) -> np.ndarray:
    """First level at which each record (rows of E: records x levels, ascending) exceeds."""
    first = np.where(E.any(axis=1), E.argmax(axis=1), -1)
    return np.where(first >= 0, levels[np.maximum(first, 0)], np.nan)


# ----------------------------------------------------------------------------- datasets --
def exceedance(ds, limit_states=None):
    """Boolean DataArray (``limit_state`` first) of the cases exceeding each limit state;
    failed cases are NaN."""
    import xarray as xr

    ls = LIMIT_STATES if limit_states is None else limit_states
    theta = ds["theta_max_over_alpha"]
    over = ds["overturned"]
    valid = ~(np.isnan(theta) | np.isnan(over))
    out = []
    for _name, thr in ls.items():
        e = (over > 0.5) if thr is None else ((theta >= thr) | (over > 0.5))
        out.append(e.astype(float).where(valid))
    return xr.concat(out, dim=xr.Variable("limit_state", list(ls)))


def fit_fragility(ds, *, x: str = "im", method: str = "msa", ci: str = "bootstrap",
                  n_boot: int = 200, level: float = 0.90, seed: int = 0, limit_states=None,
                  n_curve: int = 200, progress=None):
    """Fit lognormal fragilities on a sweep Dataset with an intensity dimension ``x`` (levels
    in IM units) and ``record``, for every combination of the other dimensions (e.g.
    ``config``) and every limit state. Returns a copy of ``ds`` with ``fragility_median``,
    ``fragility_beta`` and their ``_lo``/``_hi`` bounds (two-sided ``level``),
    ``fragility_status``, ``p_exceed`` (observed fractions), ``fragility_curve`` with
    ``_lo``/``_hi`` on ``im_curve``, and ``n_valid``. ``progress(done, total)``, if given, is
    called after each fit (a fit with its bootstrap can take seconds).

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep result with dimensions ``x`` and ``record``.
    x : str
        Name of the intensity dimension.
    method : str
        ``"msa"`` or ``"ida"``.
    ci : str
        Confidence intervals: ``"bootstrap"``, ``"fisher"`` or ``"none"``.
    n_boot : int
        Bootstrap samples.
    level : float
        Two-sided confidence level [-].
    seed : int
        Seed of the bootstrap.
    limit_states : dict, optional
        ``{name: theta_max / alpha threshold}``; default the limit states of EURODYN (2020), §4.
    n_curve : int
        Points of the fitted curves.
    progress : callable, optional
        ``progress(done, total)``.

    Returns
    -------
    xarray.Dataset

    References
    ----------
    Baker (2015).
    """
    import xarray as xr
    from scipy.special import ndtr, ndtri

    if method not in ("msa", "ida"):
        raise ValueError(f"method must be 'msa' or 'ida', got {method!r}")
    if ci not in ("bootstrap", "fisher", "none"):
        raise ValueError(f"ci must be 'bootstrap', 'fisher' or 'none', got {ci!r}")
    if x not in ds.dims or "record" not in ds.dims:
        raise ValueError(f"the Dataset needs the dimensions {x!r} and 'record'")
    E = exceedance(ds, limit_states)
    other = [d for d in E.dims if d not in ("limit_state", x, "record")]
    E = E.transpose(*other, "limit_state", x, "record")
    levels = np.asarray(ds[x].values, dtype=float)
    order = np.argsort(levels)
    levels = levels[order]
    Ev = np.asarray(E.values)[..., order, :]
    curve_x = np.geomspace(levels.min() / 3.0, levels.max() * 1.5, n_curve)
    shp = Ev.shape[:-2]
    med = np.full(shp, np.nan)
    bet = np.full(shp, np.nan)
    mlo, mhi, blo, bhi = (np.full(shp, np.nan) for _ in range(4))
    status = np.full(shp, "", dtype=object)
    curve = np.full(shp + (n_curve,), np.nan)
    clo = np.full(shp + (n_curve,), np.nan)
    chi = np.full(shp + (n_curve,), np.nan)
    k = float(ndtri(0.5 + level / 2.0))
    rng = np.random.default_rng(seed)
    n_fits = int(np.prod(shp))
    for k_fit, idx in enumerate(np.ndindex(shp)):
        if progress is not None:
            progress(k_fit, n_fits)
        e = Ev[idx]  # levels x records (NaN = failed)
        fit = _fit(e, levels, method)
        status[idx] = fit.status
        if fit.status != "ok" and not math.isfinite(fit.median):
            continue
        med[idx], bet[idx] = fit.median, fit.beta
        curve[idx] = fit(curve_x)
        if ci == "fisher" and np.all(np.isfinite(fit.cov)):
            s_mu, s_b = math.sqrt(fit.cov[0, 0]), math.sqrt(fit.cov[1, 1])
            mlo[idx], mhi[idx] = fit.median * math.exp(-k * s_mu), fit.median * math.exp(k * s_mu)
            blo[idx], bhi[idx] = fit.beta - k * s_b, fit.beta + k * s_b
            u = (np.log(curve_x) - math.log(fit.median)) / fit.beta
            g = np.stack([-np.ones_like(u) / fit.beta, -u / fit.beta])
            su = np.sqrt(np.einsum("in,ij,jn->n", g, fit.cov, g))
            clo[idx], chi[idx] = ndtr(u - k * su), ndtr(u + k * su)
        elif ci == "bootstrap":
            n_rec = e.shape[1]
            ms, bs, cs = [], [], []
            for _ in range(n_boot):
                pick = rng.integers(0, n_rec, n_rec)
                f = _fit(e[:, pick], levels, method)
                if math.isfinite(f.median) and f.status in ("ok", "boundary"):
                    ms.append(f.median)
                    bs.append(f.beta)
                    cs.append(f(curve_x))
            if len(ms) >= max(10, n_boot // 4):
                q = [50 * (1 - level), 50 * (1 + level)]
                mlo[idx], mhi[idx] = np.percentile(ms, q)
                blo[idx], bhi[idx] = np.percentile(bs, q)
                clo[idx], chi[idx] = np.percentile(np.array(cs), q, axis=0)
    if progress is not None:
        progress(n_fits, n_fits)
    odims = other + ["limit_state"]
    im_attrs = dict(ds[x].attrs)
    out = ds.copy()
    units = im_attrs.get("units", "")
    out = out.assign_coords(im_curve=xr.Variable(("im_curve",), curve_x, im_attrs))
    out["fragility_median"] = xr.Variable(odims, med, {"units": units,
                                                       "long_name": "median theta of the IM"})
    out["fragility_beta"] = xr.Variable(odims, bet, {"units": "1", "long_name": "dispersion"})
    for nm, arr, u in (("fragility_median_lo", mlo, units), ("fragility_median_hi", mhi, units),
                       ("fragility_beta_lo", blo, "1"), ("fragility_beta_hi", bhi, "1")):
        out[nm] = xr.Variable(odims, arr, {"units": u, "confidence": level})
    out["fragility_status"] = xr.Variable(odims, status.astype(str))
    cdims = odims + ["im_curve"]
    out["fragility_curve"] = xr.Variable(cdims, curve, {"units": "1"})
    out["fragility_curve_lo"] = xr.Variable(cdims, clo, {"units": "1", "confidence": level})
    out["fragility_curve_hi"] = xr.Variable(cdims, chi, {"units": "1", "confidence": level})
    frac = E.mean("record", skipna=True)
    out["p_exceed"] = frac.assign_attrs(units="1", long_name="observed fraction exceeding")
    out["n_valid"] = E.notnull().sum("record").assign_attrs(units="1")
    out.attrs.update({"fragility_method": method, "fragility_ci": ci,
                      "fragility_confidence": level, "fragility_n_boot": n_boot,
                      "fragility_x": x,
                      "fragility_limit_states": str(dict(LIMIT_STATES if limit_states is None
                                                         else limit_states))})
    return out


def _fit(e: np.ndarray, levels: np.ndarray, method: str) -> FragilityFit:
    """Fit one limit state from ``e`` (levels x records, 1/0/NaN)."""
    valid = ~np.isnan(e)
    if method == "msa":
        n = valid.sum(axis=1)
        z = np.nansum(e, axis=1)
        return fit_msa(levels, n, z)
    ok = valid.all(axis=0)
    E = e[:, ok].T > 0.5
    cap = _ida_capacities(E, levels)
    return fit_ida(cap, censored_at=levels.max())


# ----------------------------------------------------------------------------- analysis --
def restraint_configs(body, *, delta_t: float = 10.186, c_over_cd: float = 0.10, walls="eq11",
                    K_over_Kd: float = 1.0) -> dict:
    """Free-standing, tied and damped versions of an EURODYN (2020) wall (dict name ->
    RockingModel): free-standing (two-sided); tied: a tension-only tie ``K = K_over_Kd K_d`` (eq.
    12) at the top and one-sided transverse walls (eq. 11 by default); damped: the tied wall with a
    damper ``c = c_over_cd c_d`` at the top (eq. 13, characteristic time ``delta_t`` [s]; the
    default 10.186 s is the value calibrated in validation/restrained.py on EURODYN (2020), Figure
    9, and 10 % c_d is the design value of EURODYN (2020) for limited rocking).

    Parameters
    ----------
    body : RigidBlock
        The wall.
    delta_t : float
        Characteristic time of eq. 13 [s].
    c_over_cd : float
        Damper coefficient over ``c_d`` [-].
    walls : str or float
        ``"eq11"``, ``"rigid"`` or a spring-bed stiffness [N/m/m].
    K_over_Kd : float
        Tie stiffness over ``K_d`` [-].

    Returns
    -------
    dict
        ``{name: RockingModel}``.

    References
    ----------
    EURODYN (2020), eqs. 11-13 and Figure 9.
    """
    from murus.rocking import Damper, RockingModel, SpringBed, Tie
    from murus.rocking.design import bed_stiffness_equal, reference_damping, tie_design

    K = K_over_Kd * tie_design(body).K_d
    kb = (bed_stiffness_equal(body, K) if walls == "eq11" else
          math.inf if walls == "rigid" else float(walls))
    tied = RockingModel(body, tie=Tie(K, body.height), transverse_walls=SpringBed(kb, body.height),
                        motion_sides="one")
    damped = tied.replace(damper=Damper(c_over_cd * reference_damping(body, delta_t),
                                        body.height))
    return {"free-standing": RockingModel(body), "tied": tied,
            f"tied + damper {100 * c_over_cd:g} % c_d": damped}



def seed002_configs(body, **kw) -> dict:
    """Deprecated alias of :func:`restraint_configs` (removed in the next release).

    Parameters
    ----------
    body : RigidBlock
        The wall.
    **kw
        The keywords of :func:`restraint_configs`.

    Returns
    -------
    dict
        ``{name: RockingModel}``.
    """
    warnings.warn("seed002_configs is deprecated: use restraint_configs", DeprecationWarning,
                  stacklevel=2)
    return restraint_configs(body, **kw)

def fragility(models, records="farfield", im="PGA", levels=None, *, method: str = "msa",
              ci: str = "bootstrap", n_boot: int = 200, level: float = 0.90, seed: int = 0,
              duration=None, executor="process", workers=None, scheduler=None, out=None,
              chunk_size: int = 256, retries: int = 2, progress=None):
    """Fragility analysis of one or more rocking models over a record suite.

    models:
        A RockingModel or a dict ``{name: RockingModel}`` (e.g. :func:`restraint_configs`), run
        side by side (dimension ``config``).
    records:
        Default the FEMA P695 far-field set (44 components); see
        :meth:`~murus.studies.records.RecordSet.coerce`.
    im, levels:
        ``"PGA"`` or ``"Sa(T=...)"`` (levels in g) or ``"PGV"`` (m/s); every record is scaled
        to every level (the stripes of MSA, the scale ladder of IDA). Default levels: 20 from
        0.05 to 1.0 (g or m/s).
    method, ci, n_boot, level, seed:
        See :func:`fit_fragility`.
    executor, workers, scheduler, out, chunk_size, retries, progress:
        See :func:`murus.studies.sweep.run_plan`.

    Returns the sweep Dataset (dims ``config``, ``im``, ``record``) with the fits.
    """
    from murus.rocking.model import RockingModel
    from murus.studies.records import IntensityMeasure, RecordSet
    from murus.studies.sweep import Dim, Plan, Point, run_plan, write_netcdf

    if isinstance(models, RockingModel):
        models = {"model": models}
    if not models:
        raise ValueError("no models")
    measure = IntensityMeasure.parse(im)
    lv = np.linspace(0.05, 1.0, 20) if levels is None else np.asarray(levels, dtype=float)
    if lv.ndim != 1 or lv.size < 2 or np.any(lv <= 0) or not np.all(np.isfinite(lv)):
        raise ValueError("levels must be at least two positive finite numbers")
    rec = RecordSet.coerce(records)
    ims = measure.of(rec.load())
    if np.any(ims <= 0):
        raise ValueError("a record has a zero intensity measure")
    dims = [Dim("config", tuple(models), {"long_name": "configuration"}),
            Dim("im", tuple(float(v) for v in lv),
                {"units": measure.units, "long_name": f"intensity measure {measure.label}"})]
    points = [Point(m, tuple(float(s) for s in v / ims)) for m in models.values() for v in lv]
    spec = {"function": "fragility", "im": measure.label, "levels": lv.tolist(),
            "records": rec.describe(), "configs": {k: m.describe() for k, m in models.items()}}
    plan = Plan("fragility", dims, points, records=rec, spec=spec, duration=duration,
                chunk_size=chunk_size)
    ds = run_plan(plan, executor, workers=workers, scheduler=scheduler, out=out,
                  retries=retries, progress=progress)
    ds = ds.assign_coords(record_im=("record", ims, {"units": measure.units,
                                                     "long_name": f"{measure.label} of the "
                                                     "unscaled record"}))
    ds = fit_fragility(ds, method=method, ci=ci, n_boot=n_boot, level=level, seed=seed)
    if out is not None:
        from pathlib import Path

        write_netcdf(ds, Path(out) / "result.nc")
    return ds


def plot_fragility(ds, ax=None, *, limit_state=None, config=None, progress=None):
    """Fragility curves with their confidence bands and the observed fractions (markers), one
    colour per configuration, one line style per limit state (fitted first by
    :func:`fit_fragility`, with its ``progress``, unless ``ds`` has them). Returns the Axes.

    Parameters
    ----------
    ds : xarray.Dataset
        A fragility result (or a sweep to fit first).
    ax : matplotlib.axes.Axes, optional
        Where to draw.
    limit_state, config : str, optional
        Restrict to one limit state or configuration.
    progress : callable, optional
        ``progress(done, total)`` of the fit.

    Returns
    -------
    matplotlib.axes.Axes
    """
    import matplotlib.pyplot as plt

    if "fragility_curve" not in ds:
        ds = fit_fragility(ds, progress=progress)
    if ax is None:
        _, ax = plt.subplots(figsize=(7.0, 4.0), layout="constrained")
    x = ds.attrs.get("fragility_x", "im")
    curve = ds["fragility_curve"]
    other = [d for d in curve.dims if d not in ("limit_state", "im_curve")]
    lss = list(ds["limit_state"].values) if limit_state is None else (
        [limit_state] if isinstance(limit_state, str) else list(limit_state))
    styles = ["-", "--", ":", "-."]
    combos = list(np.ndindex(*[ds.sizes[d] for d in other])) if other else [()]
    for ci_, idx in enumerate(combos):
        sel = dict(zip(other, idx, strict=True))
        label0 = ", ".join(str(ds[d].values[i]) for d, i in sel.items())
        if config is not None and "config" in sel and ds["config"].values[sel["config"]] \
                not in np.atleast_1d(config):
            continue
        color = f"C{ci_ % 10}"
        for li, ls in enumerate(lss):
            s = {**sel, "limit_state": list(ds["limit_state"].values).index(ls)}
            xs = ds["im_curve"].values
            ax.plot(xs, ds["fragility_curve"].isel(s).values, styles[li % 4], color=color,
                    lw=1.4, label=f"{label0}: {ls}" if label0 else ls)
            lo = ds["fragility_curve_lo"].isel(s).values
            hi = ds["fragility_curve_hi"].isel(s).values
            if np.any(np.isfinite(lo)):
                ax.fill_between(xs, lo, hi, color=color, alpha=0.12, lw=0)
            ax.plot(ds[x].values, ds["p_exceed"].isel(s).values, "o", color=color, ms=3,
                    mfc="none" if li else color)
    units = ds[x].attrs.get("units", "")
    ax.set_xlabel(ds[x].attrs.get("long_name", x) + (f" [{units}]" if units else ""))
    ax.set_ylabel("probability of exceedance")
    ax.set_ylim(-0.02, 1.02)
    ax.set_xlim(0, float(ds["im_curve"].max()))
    conf = ds.attrs.get("fragility_confidence", 0.9)
    ax.set_title(f"Fragility ({ds.attrs.get('fragility_method', 'msa').upper()}, "
                 f"{100 * float(conf):g} % bands: {ds.attrs.get('fragility_ci', '')})",
                 fontsize=9)
    # the bands are not in the legend: say what they are once
    ax.fill_between([], [], [], color="0.5", alpha=0.25,
                    label=f"{100 * float(conf):g} % confidence band")
    ax.plot([], [], "o", color="0.3", ms=3, label="observed fraction")
    n = len(ax.get_legend_handles_labels()[0])
    ax.legend(fontsize=8, ncol=2 if n > 6 else 1, loc="lower right", framealpha=0.9)
    return ax

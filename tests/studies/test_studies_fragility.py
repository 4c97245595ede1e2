"""Lognormal fragility fits by maximum likelihood (Baker 2015) on synthetic data drawn from a
known lognormal, with bounds from the sampling theory (Fisher information), and the fragility
analysis end to end (issue 7, item 4)."""

import math

import numpy as np
import pytest
import xarray as xr
from scipy.special import log_ndtr, ndtr, ndtri

from murus.studies.fragility import (
    fisher_covariance,
    fit_fragility,
    fit_ida,
    fit_msa,
    fragility,
    plot_fragility,
)

THETA, BETA = 0.5, 0.4
LEVELS = np.geomspace(0.1, 2.0, 12)
N = 40


def draw(rng, n=N):
    p = ndtr(np.log(LEVELS / THETA) / BETA)
    return rng.binomial(n, p)


def test_msa_mle_recovers_known_lognormal():
    """One fixed-seed sample: the estimates lie within 3 standard errors of the truth, the
    standard errors being those of the expected Fisher information at the true parameters."""
    z = draw(np.random.default_rng(2024))
    fit = fit_msa(LEVELS, np.full(LEVELS.size, N), z)
    assert fit.status == "ok"
    cov = fisher_covariance(THETA, BETA, LEVELS, np.full(LEVELS.size, N))
    s_mu, s_b = math.sqrt(cov[0, 0]), math.sqrt(cov[1, 1])
    assert 0.02 < s_mu < 0.1 and 0.02 < s_b < 0.1  # the test is not vacuous
    assert abs(math.log(fit.median) - math.log(THETA)) < 3 * s_mu
    assert abs(fit.beta - BETA) < 3 * s_b


def test_msa_mle_is_the_maximum():
    z = draw(np.random.default_rng(5))
    fit = fit_msa(LEVELS, np.full(LEVELS.size, N), z)

    def ll(m, b):
        p = np.clip(ndtr(np.log(LEVELS / m) / b), 1e-300, 1 - 1e-16)
        return np.sum(z * np.log(p) + (N - z) * np.log1p(-p))

    assert fit.loglik == pytest.approx(ll(fit.median, fit.beta), abs=1e-8)
    for dm, db in ((1.01, 1), (0.99, 1), (1, 1.02), (1, 0.98)):
        assert ll(fit.median * dm, fit.beta * db) < fit.loglik


def _msa_score(x, n, z, median, beta):
    """Log-likelihood of the stripes, its gradient in ``(ln median, beta)`` and, per component,
    the sum of the absolute values of the terms of that gradient (the scale of its rounding)."""
    u = np.log(x / median) / beta
    lphi = -0.5 * u * u - 0.5 * math.log(2 * math.pi)
    lp, lq = log_ndtr(u), log_ndtr(-u)
    r1, r2 = np.exp(lphi - lp), np.exp(lphi - lq)  # phi / Phi(u), phi / Phi(-u)
    s = z * r1 - (n - z) * r2  # d ll / du
    t = z * r1 + (n - z) * r2
    grad = np.array([np.sum(-s / beta), np.sum(-s * u / beta)])
    scale = np.array([np.sum(t / beta), np.sum(t * np.abs(u) / beta)])
    return float(np.sum(z * lp + (n - z) * lq)), grad, scale


@pytest.mark.parametrize("seed", [5, 11, 2024])
def test_msa_newton_fit_is_a_stationary_maximum(seed):
    """At the fit the score vanishes to rounding: each component is below 1000 ulp of the sum
    of the absolute values of its 12 terms (each term is good to a few ulp, and the rounding of
    the returned median and beta adds as much); no point of a grid around the fit, out to 0.1
    and down to 1e-4 standard errors, has a higher log-likelihood (beyond the rounding of the
    log-likelihood)."""
    n = np.full(LEVELS.size, N)
    z = draw(np.random.default_rng(seed))
    fit = fit_msa(LEVELS, n, z)
    assert fit.status == "ok"
    ll, grad, scale = _msa_score(LEVELS, n, z, fit.median, fit.beta)
    assert fit.loglik == pytest.approx(ll, abs=1e-12 * abs(ll))
    eps = np.finfo(float).eps
    assert np.all(np.abs(grad) <= 1e3 * eps * scale)
    s_mu, s_b = np.sqrt(np.diag(fit.cov))
    for h in (1e-1, 1e-2, 1e-4):
        for i in range(-4, 5):
            for j in range(-4, 5):
                if i or j:
                    m = fit.median * math.exp(0.25 * i * h * s_mu)
                    b = fit.beta + 0.25 * j * h * s_b
                    assert _msa_score(LEVELS, n, z, m, b)[0] <= fit.loglik + 8 * eps * abs(ll)


@pytest.mark.parametrize("x, n, z", [([0.2, 0.5], [10, 10], [3, 8]),
                                     ([0.1, 1.5], [7, 40], [1, 39]),
                                     ([0.3, 0.31], [25, 25], [5, 20])])
def test_msa_two_stripes_reproduce_the_fractions(x, n, z):
    """Two stripes, two parameters: the model is exactly identified and the MLE reproduces the
    observed fractions, ``Phi(ln(x_j / median) / beta) = z_j / n_j``, i.e. the closed form
    ``beta = ln(x2 / x1) / (u2 - u1)``, ``ln median = ln x1 - beta u1`` with
    ``u_j = Phi^-1(z_j / n_j)``."""
    x, n, z = (np.asarray(a, dtype=float) for a in (x, n, z))
    fit = fit_msa(x, n, z)
    assert fit.status == "ok"
    assert np.all(np.abs(ndtr(np.log(x / fit.median) / fit.beta) - z / n) < 1e-9)
    u = ndtri(z / n)
    beta = math.log(x[1] / x[0]) / (u[1] - u[0])
    assert fit.beta == pytest.approx(beta, rel=1e-9)
    assert fit.median == pytest.approx(x[0] * math.exp(-beta * u[0]), rel=1e-9)
    p = z / n
    assert fit.loglik == pytest.approx(np.sum(z * np.log(p) + (n - z) * np.log1p(-p)),
                                       abs=1e-9)


def test_msa_quasi_separated_stripes_are_at_the_bound():
    """Stripes all 0 below one level and all n above it, with the mixed stripe in between: the
    likelihood grows as beta -> 0 (no finite MLE), so beta is at its lower bound, 0.01, and the
    fraction at the mixed level is matched exactly (the other stripes, 69 standard deviations
    away at beta = 0.01, add nothing): the log-likelihood is that of that stripe alone."""
    lv = np.array([0.1, 0.2, 0.4, 0.8])
    n = np.full(4, 10)
    fit = fit_msa(lv, n, np.array([0, 4, 10, 10]))
    assert fit.status == "boundary" and fit.beta == 0.01
    assert ndtr(math.log(0.2 / fit.median) / fit.beta) == pytest.approx(0.4, abs=1e-12)
    assert fit.loglik == pytest.approx(4 * math.log(0.4) + 6 * math.log(0.6), abs=1e-12)
    # decreasing fractions: the slope 1 / beta would be negative, beta is at its upper bound 5
    dec = fit_msa(lv, n, np.array([9, 6, 3, 1]))
    assert dec.status == "boundary" and dec.beta == 5.0


def test_msa_sampling_distribution_matches_fisher():
    """300 replicates: the spread of ln(median) and beta matches the Fisher standard errors
    (within 20 %), the bias is small, and the 90 % Wald intervals cover the truth ~90 %."""
    rng = np.random.default_rng(7)
    n = np.full(LEVELS.size, N)
    cov = fisher_covariance(THETA, BETA, LEVELS, n)
    s_mu, s_b = math.sqrt(cov[0, 0]), math.sqrt(cov[1, 1])
    mus, bs, cover = [], [], 0
    for _ in range(300):
        f = fit_msa(LEVELS, n, draw(rng))
        mus.append(math.log(f.median))
        bs.append(f.beta)
        se = math.sqrt(f.cov[0, 0])
        cover += abs(math.log(f.median) - math.log(THETA)) < 1.645 * se
    mus, bs = np.array(mus), np.array(bs)
    assert np.std(mus) == pytest.approx(s_mu, rel=0.2)
    assert np.std(bs) == pytest.approx(s_b, rel=0.2)
    assert abs(mus.mean() - math.log(THETA)) < 0.5 * s_mu
    assert abs(bs.mean() - BETA) < 0.5 * s_b
    assert 0.84 <= cover / 300 <= 0.96


def test_ida_mle_with_and_without_censoring():
    rng = np.random.default_rng(3)
    n = 200
    cap = THETA * np.exp(BETA * rng.standard_normal(n))
    fit = fit_ida(cap)
    s_mu, s_b = BETA / math.sqrt(n), BETA / math.sqrt(2 * n)
    assert abs(math.log(fit.median) - math.log(THETA)) < 3 * s_mu
    assert abs(fit.beta - BETA) < 3 * s_b
    assert math.sqrt(fit.cov[0, 0]) == pytest.approx(fit.beta / math.sqrt(n), rel=0.05)
    # right-censored at 0.7: about 20 % of the records never exceed
    c = np.where(cap > 0.7, np.nan, cap)
    cf = fit_ida(c, censored_at=0.7)
    assert np.isnan(c).mean() > 0.1
    assert abs(math.log(cf.median) - math.log(THETA)) < 3 * math.sqrt(cf.cov[0, 0])
    assert abs(cf.beta - BETA) < 3 * math.sqrt(cf.cov[1, 1])


def test_degenerate_stripes():
    n = np.full(4, 10)
    lv = np.array([0.1, 0.2, 0.3, 0.4])
    assert fit_msa(lv, n, np.zeros(4)).status == "none exceeded"
    assert fit_msa(lv, n, n).status == "all exceeded"
    sep = fit_msa(lv, n, np.array([0, 0, 10, 10]))  # perfectly separated: beta -> 0
    assert sep.status == "boundary" and 0.2 <= sep.median <= 0.3
    with pytest.raises(ValueError):
        fit_msa(lv, n, n + 1)


def synthetic_sweep(n_rec=60, seed=1):
    """A sweep Dataset whose records have lognormal capacities: theta/alpha = 0.4 x / c."""
    rng = np.random.default_rng(seed)
    c = THETA * np.exp(BETA * rng.standard_normal(n_rec))
    th = 0.4 * LEVELS[:, None] / c[None, :]
    over = (th > 1.5).astype(float)
    th = th[None]
    return xr.Dataset(
        {"theta_max_over_alpha": (("config", "im", "record"), th),
         "overturned": (("config", "im", "record"), over[None])},
        coords={"config": ["a"], "im": ("im", LEVELS, {"units": "g"}),
                "record": [f"r{i}" for i in range(n_rec)]}), c


@pytest.mark.parametrize("ci", ["bootstrap", "fisher"])
def test_fit_fragility_on_dataset(ci):
    ds, c = synthetic_sweep()
    out = fit_fragility(ds, ci=ci, n_boot=100)
    m = out["fragility_median"].sel(config="a", limit_state="moderate").item()
    b = out["fragility_beta"].sel(config="a", limit_state="moderate").item()
    # the moderate state is reached at x = c: the fit is that of the sample capacities
    assert abs(math.log(m) - np.log(c).mean()) < 0.1
    assert abs(b - np.log(c).std()) < 0.1
    lo = out["fragility_median_lo"].sel(config="a", limit_state="moderate").item()
    hi = out["fragility_median_hi"].sel(config="a", limit_state="moderate").item()
    assert lo < m < hi
    cl = out["fragility_curve_lo"].sel(config="a", limit_state="moderate").values
    ch = out["fragility_curve_hi"].sel(config="a", limit_state="moderate").values
    cv = out["fragility_curve"].sel(config="a", limit_state="moderate").values
    assert np.all(cl <= cv + 1e-12) and np.all(cv <= ch + 1e-12)
    # limited (0.1) comes first, overturning (1.5 x / c > ... ) last
    med = out["fragility_median"].sel(config="a").values
    assert med[0] < med[1] < med[2]
    ida = fit_fragility(ds, method="ida", ci="none")
    assert ida["fragility_median"].sel(config="a", limit_state="moderate").item() == \
        pytest.approx(m, rel=0.15)


def test_fragility_end_to_end(records):
    import matplotlib

    matplotlib.use("Agg")
    from murus.rocking import RockingModel, restrained_wall_block
    from murus.studies.fragility import restraint_configs

    b = restrained_wall_block("block1")
    models = restraint_configs(b)
    assert list(models)[0] == "free-standing" and isinstance(models["tied"], RockingModel)
    ds = fragility(models, records, im="PGA", levels=[0.1, 0.2, 0.35, 0.5], executor="serial",
                   n_boot=30)
    assert ds["theta_max_over_alpha"].dims == ("config", "im", "record")
    # every record is scaled to each level of PGA
    pga = ds["record_pga"].values * ds["record_scale"].isel(config=0)
    assert np.allclose(pga / 9.81, ds["im"].values[:, None])
    assert set(ds["fragility_status"].values.ravel()) <= {"ok", "boundary", "none exceeded",
                                                          "all exceeded"}
    ax = plot_fragility(ds)
    assert len(ax.lines) >= 9

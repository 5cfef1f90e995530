"""Fragility fitting against an independent maximum-likelihood fit: scipy's
optimiser on the binomial log-likelihood of the same counts (issue 30's
check), and the risk integral against the closed form of a lognormal
fragility on a power-law hazard curve."""
import math

import numpy as np
import pytest

import quakejoint as qj

scipy = pytest.importorskip("scipy")
from scipy import optimize, stats  # noqa: E402

LEVELS = np.array([0.2, 0.35, 0.5, 0.7, 1.0, 1.4, 2.0, 2.8])


def scipy_fit(im, n, z):
    """Maximum likelihood by scipy: Nelder-Mead then BFGS on -log L(ln theta, ln beta)."""

    def nll(p):
        ln_theta, ln_beta = p
        prob = stats.norm.cdf((np.log(im) - ln_theta) / math.exp(ln_beta))
        prob = np.clip(prob, 1e-300, 1 - 1e-16)
        return -np.sum(stats.binom.logpmf(z, n, prob))

    x0 = [np.log(np.median(im)), np.log(0.5)]
    r = optimize.minimize(nll, x0, method="Nelder-Mead", options={"xatol": 1e-12, "fatol": 1e-14, "maxiter": 20000})
    r = optimize.minimize(nll, r.x, method="BFGS", options={"gtol": 1e-12})
    return math.exp(r.x[0]), math.exp(r.x[1])


@pytest.mark.parametrize("median, beta, records, seed", [(0.8, 0.3, 20, 1), (1.0, 0.5, 10, 2), (0.6, 0.7, 40, 3)])
def test_fit_equals_scipys_maximum_likelihood(median, beta, records, seed):
    rng = np.random.default_rng(seed)
    n = np.full(len(LEVELS), records)
    z = rng.binomial(n, stats.norm.cdf(np.log(LEVELS / median) / beta))
    f = qj.fit_fragility(LEVELS, n, z)
    m, b = scipy_fit(LEVELS, n, z)
    assert abs(f["median"] / m - 1) < 1e-6 and abs(f["beta"] / b - 1) < 1e-6, (f, m, b)
    # and the truth within three standard errors
    assert abs(math.log(f["median"] / median)) < 3 * f["se_ln_median"]
    assert abs(f["beta"] - beta) < 3 * f["se_beta"]


def test_risk_is_the_power_law_closed_form():
    k0, k = 1e-4, 2.5
    im = np.array([0.05, 0.1, 0.3, 1.0, 3.0, 10.0])
    rate = k0 * im ** -k
    for median, beta in [(0.8, 0.3), (1.2, 0.6)]:
        lam = qj.limit_state_frequency(median, beta, im, rate)
        exact = k0 * median ** -k * math.exp(k * k * beta * beta / 2)
        assert abs(lam / exact - 1) < 1e-6


def test_bootstrap_is_seeded_and_bad_input_is_refused():
    rng = np.random.default_rng(5)
    outcomes = (rng.random((30, len(LEVELS))) < stats.norm.cdf(np.log(LEVELS / 1.0) / 0.5)).astype(int).tolist()
    a = qj.bootstrap_fragility(outcomes, LEVELS, samples=300, seed=9)
    assert a == qj.bootstrap_fragility(outcomes, LEVELS, samples=300, seed=9)
    assert a["median"][0] < a["median"][1]
    with pytest.raises(qj.InputError, match="0 of 20 runs exceeded"):
        qj.fit_fragility([0.5, 1.0], [10, 10], [0, 0])
    with pytest.raises(qj.InputError, match="whole numbers"):
        qj.fit_fragility([0.5, 1.0], [10, 10.5], [1, 2])

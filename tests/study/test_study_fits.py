"""study.fits and .coursework: growth-law fits, model comparison, the coursework's table.

* ``analytic``: synthetic data from a known law (noise-free: recovered to rounding; with a
  seeded random noise: within the reported standard errors).
* ``reference``: the coursework's table 4.1 (``data/coursework_table_4_1.csv``: the coursework's
  quartic fits it with R² > 0.99, as its figure 4.1 shows).
* ``api``: the loaders and argument errors.  (The modules' docstring examples run as doctests:
  ``bubbleoptics/`` is in pytest's ``testpaths``.)
"""

from pathlib import Path

import numpy as np
import pytest

from study import (
    COURSEWORK_COLUMNS,
    compare_fits,
    fit_affine_exponential,
    fit_exponential,
    fit_polynomial,
    holdout_errors,
    load_coursework_table,
    load_timing,
    timing_series,
)
from study.fits import branching_interval

DATA = Path(__file__).resolve().parents[2] / "data"
DEPTH = np.arange(1.0, 11.0)
COURSEWORK = load_coursework_table(DATA / "coursework_table_4_1.csv")


# ------------------------------------------------------------------ synthetic laws (analytic)


@pytest.mark.analytic
@pytest.mark.parametrize("relative", [True, False])
@pytest.mark.parametrize("a,b", [(3.7, 1.62), (17.48, 1.7), (0.25, 1.05), (100.0, 0.8)])
def test_exponential_recovers_noise_free(a, b, relative):
    """a·b^d without noise: a and b to 1e-9 relative, zero residuals, R² = 1, zero errors."""
    fit = fit_exponential(DEPTH, a * b**DEPTH, relative=relative)
    assert fit.params["a"] == pytest.approx(a, rel=1e-9)
    assert fit.params["b"] == pytest.approx(b, rel=1e-9)
    assert np.abs(fit.relative_residuals).max() < 1e-9
    assert fit.r2 == pytest.approx(1.0, abs=1e-12)
    assert fit.stderr["a"] < 1e-6 * a and fit.stderr["b"] < 1e-6 * b
    assert fit.predict(12.0) == pytest.approx(a * b**12, rel=1e-8)


@pytest.mark.analytic
@pytest.mark.parametrize("seed", range(5))
def test_exponential_with_noise(seed):
    """a·b^d times (1 + 2 % Gaussian noise): b within 0.02 and within 4 standard errors."""
    a, b = 9.0, 1.65
    rng = np.random.default_rng(seed)
    t = a * b**DEPTH * (1 + 0.02 * rng.standard_normal(DEPTH.size))
    fit = fit_exponential(DEPTH, t)
    assert abs(fit.params["b"] - b) < 0.02
    assert abs(fit.params["b"] - b) < 4 * fit.stderr["b"]
    assert abs(fit.params["a"] - a) < 4 * fit.stderr["a"]
    assert 0 < fit.stderr["b"] < 0.02
    assert 0.02 * 0.3 < fit.rms_relative < 0.02 * 2.0  # the noise level, within sampling scatter of 10 points


@pytest.mark.analytic
@pytest.mark.parametrize("relative", [False, True])
def test_polynomial_reproduces_a_quartic(relative):
    """A quartic (the coursework's one-bubble coefficients) is reproduced exactly, in the unscaled basis."""
    coef = np.array([84.1, -104.46688228, 49.83787587, -8.45955128, 0.5620542])
    t = np.polynomial.polynomial.polyval(DEPTH, coef)
    fit = fit_polynomial(DEPTH, t, 4, relative=relative)
    np.testing.assert_allclose(fit.coef, coef, rtol=1e-9, atol=1e-9)
    assert [fit.params[f"c{j}"] for j in range(5)] == pytest.approx(coef.tolist(), rel=1e-9, abs=1e-9)
    assert np.abs(fit.residuals).max() < 1e-9
    assert fit.r2 == pytest.approx(1.0, abs=1e-12)
    assert fit.n_params == 5
    np.testing.assert_allclose(fit.predict([0.0, 11.5]), np.polynomial.polynomial.polyval([0.0, 11.5], coef),
                               rtol=1e-9)


@pytest.mark.analytic
def test_polynomial_lower_degree():
    """Degree 1 on a line: slope and intercept, two parameters."""
    fit = fit_polynomial(DEPTH, 2.0 + 3.0 * DEPTH, 1)
    np.testing.assert_allclose(fit.coef, [2.0, 3.0], rtol=1e-12)
    assert fit.n_params == 2


@pytest.mark.analytic
@pytest.mark.parametrize("a,c,b", [(10.0, 2.0, 1.6), (20.0, 8.0, 1.72), (0.3, 0.01, 1.9)])
def test_affine_exponential_recovers_noise_free(a, c, b):
    fit = fit_affine_exponential(DEPTH, a + c * b**DEPTH)
    for name, value in zip("acb", (a, c, b)):
        assert fit.params[name] == pytest.approx(value, rel=1e-7)
    assert np.abs(fit.relative_residuals).max() < 1e-9


@pytest.mark.analytic
@pytest.mark.parametrize("seed", range(3))
def test_affine_exponential_with_noise(seed):
    a, c, b = 20.0, 8.0, 1.72
    rng = np.random.default_rng(seed)
    t = (a + c * b**DEPTH) * (1 + 0.01 * rng.standard_normal(DEPTH.size))
    fit = fit_affine_exponential(DEPTH, t)
    assert abs(fit.params["b"] - b) < 0.02
    assert abs(fit.params["b"] - b) < 4 * fit.stderr["b"]


@pytest.mark.analytic
@pytest.mark.parametrize("seed", range(3))
@pytest.mark.parametrize(
    "law,truth",
    [
        ("exponential", 9.0 * 1.65**DEPTH),
        ("affine exponential", 20.0 + 8.0 * 1.72**DEPTH),
        ("polynomial, degree 4", np.polynomial.polynomial.polyval(DEPTH, [84.1, -104.47, 49.84, -8.46, 0.562])),
    ],
    ids=["exponential", "affine", "quartic"],
)
def test_compare_fits_finds_the_true_law(law, truth, seed):
    """With 1 % noise on ten points, AICc picks the law that made the data (and not a bigger one)."""
    rng = np.random.default_rng(seed)
    t = truth * (1 + 0.01 * rng.standard_normal(DEPTH.size))
    comparison = compare_fits(DEPTH, t)
    assert comparison.best == law
    assert comparison.rows[0]["delta"] == 0.0 and comparison.rows[1]["delta"] > 2.0
    assert sum(r["weight"] for r in comparison.rows) == pytest.approx(1.0)


@pytest.mark.analytic
def test_information_criteria_formulas():
    """AIC, AICc and BIC of a fit equal the textbook expressions with K = k + 1."""
    rng = np.random.default_rng(7)
    t = 9.0 * 1.65**DEPTH * (1 + 0.02 * rng.standard_normal(DEPTH.size))
    fit = fit_exponential(DEPTH, t)
    row = compare_fits(DEPTH, t, [fit]).rows[0]
    n, big_k = DEPTH.size, 3
    rss = np.sum(fit.relative_residuals**2)
    assert row["rss"] == pytest.approx(rss)
    assert row["aic"] == pytest.approx(n * np.log(rss / n) + 2 * big_k)
    assert row["aicc"] == pytest.approx(row["aic"] + 2 * big_k * (big_k + 1) / (n - big_k - 1))
    assert row["bic"] == pytest.approx(n * np.log(rss / n) + big_k * np.log(n))


@pytest.mark.analytic
def test_holdout_of_the_true_law_is_exact():
    held, err = holdout_errors(fit_affine_exponential, DEPTH, 5.0 + 2.0 * 1.7**DEPTH, 6)
    assert held.tolist() == [7.0, 8.0, 9.0, 10.0]
    assert np.abs(err).max() < 1e-7


# ------------------------------------------------------------------ the interval of b (analytic)


@pytest.mark.analytic
def test_branching_interval_noise_free_collapses_to_the_truth():
    """Without noise every interval is the true b (width below 1e-6; the bootstrap's grid search to 1e-6)."""
    ci = branching_interval(DEPTH, 20.0 + 8.0 * 1.72**DEPTH, n_boot=200)
    assert ci.b == pytest.approx(1.72, rel=1e-9)
    for lo, hi in ci.intervals.values():
        assert lo <= 1.72 + 1e-6 and hi >= 1.72 - 1e-6 and hi - lo < 1e-6


@pytest.mark.analytic
def test_branching_interval_coverage_on_synthetic_data():
    """Coverage, the independent check of an interval: on 100 synthetic tables t = (20 + 8·1.72^d)(1 + 1 % noise)
    the 95 % Wald and profile intervals contain the true b in 88-100 % of the cases (binomial
    spread of 100 trials at 95 %: ±4.4 % at two sigma); measured 94 and 95 % on 200 tables."""
    hits = {"wald": 0, "profile": 0}
    n = 100
    for seed in range(n):
        t = (20.0 + 8.0 * 1.72**DEPTH) * (1 + 0.01 * np.random.default_rng(1000 + seed).standard_normal(DEPTH.size))
        ci = branching_interval(DEPTH, t, n_boot=0)
        for method in hits:
            lo, hi = ci.intervals[method]
            hits[method] += lo < 1.72 < hi
            assert lo < ci.b < hi
    assert all(0.88 <= v / n <= 1.0 for v in hits.values()), hits


@pytest.mark.analytic
@pytest.mark.parametrize("seed", range(3))
def test_branching_bootstrap_contains_the_truth_and_refits_b(seed):
    """The bootstrap's refits centre on the fitted b, and its interval contains the true b
    (percentile intervals of ten points run a little narrow: measured coverage 89 % on 200 tables)."""
    t = (20.0 + 8.0 * 1.72**DEPTH) * (1 + 0.01 * np.random.default_rng(seed).standard_normal(DEPTH.size))
    ci = branching_interval(DEPTH, t, n_boot=400, seed=seed)
    lo, hi = ci.bootstrap
    assert lo < 1.72 < hi
    assert np.median(ci.bootstrap_b) == pytest.approx(ci.b, abs=0.25 * (hi - lo))
    # the bootstrap's vectorised refit and fit_affine_exponential agree on the data itself
    resampled_fit = fit_affine_exponential(DEPTH, t)
    assert resampled_fit.params["b"] == pytest.approx(ci.b, rel=1e-12)


@pytest.mark.api
def test_branching_interval_arguments():
    with pytest.raises(ValueError, match="level"):
        branching_interval(DEPTH, 2.0**DEPTH, level=1.5)
    with pytest.raises(ValueError, match="n_boot"):
        branching_interval(DEPTH, 2.0**DEPTH, n_boot=-1)
    with pytest.raises(ValueError, match="more than 3 points"):
        branching_interval(DEPTH[:3], 2.0 ** DEPTH[:3])


# ------------------------------------------------------------------ the coursework's table (reference)


def _high_depth_ratio(t):
    """Geometric mean of t(d+1)/t(d) over depths 7..10: (t(10)/t(7))^(1/3)."""
    return (t[-1] / t[-4]) ** (1 / 3)


@pytest.mark.reference
@pytest.mark.parametrize("bubbles", [1, 2, 3])
def test_coursework_quartic_fits_its_table(bubbles):
    """The coursework's fourth-degree polynomials (its figure 4.1) fit its table: R² > 0.99 (measured
    0.9994, 0.9998, 0.9999); the fit is least squares on the times, as numpy's polyfit does."""
    fit = fit_polynomial(COURSEWORK["depth"], COURSEWORK["seconds"][bubbles], 4)
    assert fit.r2 > 0.999
    # ...yet ten points do not determine its five coefficients: the standard error of the
    # linear one is 25-45 % of its value
    assert fit.stderr["c1"] > 0.2 * abs(fit.params["c1"])


@pytest.mark.reference
@pytest.mark.parametrize("bubbles", [1, 2, 3])
def test_coursework_growth_factor(bubbles):
    """b of the coursework's table against the ratio of successive times at high depth.

    At depths 7-10 the coursework's times grow by a factor (t(10)/t(7))^(1/3) = 1.68, 1.71, 1.70 per
    level (one, two, three bubbles).  The pure exponential a·b^d must also absorb the fixed
    cost that dominates at depth 1, which drags its b down to 1.59-1.62: it lies between 1.5
    and that ratio.  The affine law a + c·b^d separates the fixed cost and its b (1.67, 1.74,
    1.72) matches the high-depth ratio within 0.05.
    """
    t = COURSEWORK["seconds"][bubbles]
    ratio = _high_depth_ratio(t)
    assert 1.65 < ratio < 1.75
    b = fit_exponential(COURSEWORK["depth"], t).params["b"]
    assert 1.5 < b < ratio
    affine = fit_affine_exponential(COURSEWORK["depth"], t)
    assert 1.6 < affine.params["b"] < 1.8
    assert abs(affine.params["b"] - ratio) < 0.05
    assert affine.params["a"] > 0 and affine.params["c"] > 0  # a fixed cost, a growing tree


@pytest.mark.reference
@pytest.mark.parametrize("relative", [True, False])
@pytest.mark.parametrize("bubbles", [1, 2, 3])
def test_coursework_table_follows_fixed_cost_plus_branching(bubbles, relative):
    """a + c·b^d wins by AIC, AICc and BIC, with relative or absolute residuals; with relative
    ones (timing noise is proportional to the time) decisively (ΔAICc > 10 to the next law)."""
    for criterion in ("aic", "aicc", "bic"):
        comparison = compare_fits(COURSEWORK["depth"], COURSEWORK["seconds"][bubbles], relative=relative,
                                  criterion=criterion)
        assert comparison.best == "affine exponential"
    if relative:
        assert comparison.rows[1]["delta"] > 10.0


@pytest.mark.reference
@pytest.mark.parametrize("bubbles", [1, 2, 3])
def test_quartic_interpolates_affine_exponential_extrapolates(bubbles):
    """Fitted to depths 1-7, a + c·b^d predicts depths 8-10 within 5 %; the quartic misses
    depth 10 by more than 10 % (measured: 15-23 % low)."""
    t = COURSEWORK["seconds"][bubbles]
    _, err_affine = holdout_errors(fit_affine_exponential, COURSEWORK["depth"], t, 7)
    _, err_quartic = holdout_errors(fit_polynomial, COURSEWORK["depth"], t, 7, relative=True)
    assert np.abs(err_affine).max() < 0.05
    assert abs(err_quartic[-1]) > 0.10


@pytest.mark.reference
@pytest.mark.parametrize("bubbles", [1, 2, 3])
def test_coursework_branching_interval(bubbles):
    """The three intervals of the coursework's b agree: the profile's and the covariance's ends
    within 0.002 (measured 2e-4), the bootstrap's inside them within 0.01 (it runs narrower);
    each about ±0.02 wide (measured 1.656-1.691, 1.725-1.754, 1.703-1.747), and none contains
    the golden ratio 1.618, the branching factor of the two-sphere bubble's ray tree."""
    ci = branching_interval(COURSEWORK["depth"], COURSEWORK["seconds"][bubbles], n_boot=500)
    (wl, wh), (pl, ph), (bl, bh) = ci.wald, ci.profile, ci.bootstrap
    assert abs(wl - pl) < 0.002 and abs(wh - ph) < 0.002
    assert abs(bl - pl) < 0.01 and abs(bh - ph) < 0.01
    for lo, hi in ci.intervals.values():
        assert lo < ci.b < hi and 0.01 < hi - lo < 0.1
        assert lo > (1 + 5**0.5) / 2


# ------------------------------------------------------------------ loaders and arguments (api)


@pytest.mark.api
def test_load_coursework_table():
    assert COURSEWORK["depth"].tolist() == list(range(1, 11))
    assert COURSEWORK["seconds"][1][0] == 17.48 and COURSEWORK["seconds"][3][-1] == 1889.56
    assert sorted(COURSEWORK["seconds"]) == sorted(COURSEWORK_COLUMNS)
    assert any("Apple M3 Pro" in note for note in COURSEWORK["notes"])


@pytest.mark.api
def test_load_coursework_table_sorts_by_depth(tmp_path):
    """Rows in any order come back sorted by depth, each column with its own depth."""
    path = tmp_path / "table.csv"
    path.write_text("# a note\ndepth,one_bubble,two_bubbles,three_bubbles\n2,2.5,3.5,4.5\n1,1.5,2.5,3.5\n")
    table = load_coursework_table(path)
    assert table["depth"].tolist() == [1, 2]
    assert table["seconds"][1].tolist() == [1.5, 2.5] and table["seconds"][3].tolist() == [3.5, 4.5]
    assert table["notes"] == ["a note"]


@pytest.mark.api
def test_load_timing_matches_the_coursework_and_is_complete():
    timing = load_timing(DATA / "derived" / "coursework_table.csv")
    assert timing["depth"].size == 60  # 3 scenes x 2 modes x 10 depths
    assert timing["seconds_runs"].shape[0] == 60
    for nb in (1, 2, 3):
        for mode in ("pruned", "exhaustive"):
            depth, coursework_seconds = timing_series(timing, nb, mode, "seed_seconds")  # the file's column name
            assert depth.tolist() == list(range(1, 11))
            np.testing.assert_array_equal(coursework_seconds, COURSEWORK["seconds"][nb])
            _, rays = timing_series(timing, nb, mode, "rays_total")
            assert rays.dtype.kind == "i" and np.all(np.diff(rays) >= 0)
    extra = [row["mode"] for row in timing["extra"]]
    assert extra[-1] == "fresh process, start to saved image"
    assert sorted(set(extra[:-1])) == ["threads 1", "threads 2"] and len(extra[:-1]) == 12  # 3 scenes, depth 1 and 10
    # the spread columns: quartiles inside the runs' range, the median between them
    for column in ("seconds_q1", "seconds_q3", "seconds_min", "seconds_max"):
        assert np.all(np.isfinite(timing[column]))
    assert np.all((timing["seconds_min"] <= timing["seconds_q1"]) & (timing["seconds_q1"] <= timing["seconds_median"])
                  & (timing["seconds_median"] <= timing["seconds_q3"]) & (timing["seconds_q3"] <= timing["seconds_max"]))
    assert timing["seconds_runs"].shape[1] >= 9
    with pytest.raises(ValueError, match="mode"):
        timing_series(timing, 1, "fast")


@pytest.mark.api
def test_fit_argument_errors():
    with pytest.raises(ValueError, match="more than 5 points"):
        fit_polynomial(DEPTH[:5], DEPTH[:5], 4)
    with pytest.raises(ValueError, match="equal length"):
        fit_exponential(DEPTH, DEPTH[:-1])
    with pytest.raises(ValueError, match="seconds > 0"):
        fit_exponential(DEPTH, DEPTH - 3)
    with pytest.raises(ValueError, match="finite"):
        fit_affine_exponential(DEPTH, np.where(DEPTH == 3, np.nan, DEPTH))
    with pytest.raises(ValueError, match="criterion"):
        compare_fits(DEPTH, 2.0**DEPTH, criterion="r2")
    with pytest.raises(ValueError, match="other data"):
        compare_fits(DEPTH, 2.0**DEPTH, [fit_exponential(DEPTH, 3.0**DEPTH)])

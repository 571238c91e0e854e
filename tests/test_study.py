"""tracer.study: growth-law fits, model comparison, Pareto fronts and ΔE00.

* ``analytic``: synthetic data from a known law (noise-free: recovered to rounding; with a
  seeded noise: within the reported standard errors), hand-made Pareto sets.
* ``reference``: the seed's table 4.1 (``data/seed_table_4_1.csv``: the seed's quartic fits it
  with R² > 0.99, as its figure 4.1 shows) and CIEDE2000 against published values (Sharma, Wu &
  Dalal 2005, the pairs colour-science's own tests use) and against colour-science's pipeline.
* ``api``: the loaders, argument errors, and the module's docstring examples.
"""

import doctest

import colour
import numpy as np
import pytest

import tracer.study as study
from tracer.study import (
    compare_fits,
    delta_e00,
    fit_affine_exponential,
    fit_exponential,
    fit_polynomial,
    holdout_errors,
    load_seed_table,
    load_timing,
    pareto_front,
    timing_series,
)

DEPTH = np.arange(1.0, 11.0)
SEED = load_seed_table()


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
    """A quartic (the seed's one-bubble coefficients) is reproduced exactly, in the unscaled basis."""
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


# ------------------------------------------------------------------ the seed's table (reference)


def _high_depth_ratio(t):
    """Geometric mean of t(d+1)/t(d) over depths 7..10: (t(10)/t(7))^(1/3)."""
    return (t[-1] / t[-4]) ** (1 / 3)


@pytest.mark.reference
@pytest.mark.parametrize("bubbles", [1, 2, 3])
def test_seed_quartic_fits_its_table(bubbles):
    """The seed's fourth-degree polynomials (its figure 4.1) fit its table: R² > 0.99 (measured
    0.9994, 0.9998, 0.9999); the fit is least squares on the times, as numpy's polyfit does."""
    fit = fit_polynomial(SEED["depth"], SEED["seconds"][bubbles], 4)
    assert fit.r2 > 0.999
    # ...yet ten points do not determine its five coefficients: the standard error of the
    # linear one is 25-45 % of its value
    assert fit.stderr["c1"] > 0.2 * abs(fit.params["c1"])


@pytest.mark.reference
@pytest.mark.parametrize("bubbles", [1, 2, 3])
def test_seed_growth_factor(bubbles):
    """b of the seed's table against the ratio of successive times at high depth.

    At depths 7-10 the seed's times grow by a factor (t(10)/t(7))^(1/3) = 1.68, 1.71, 1.70 per
    level (one, two, three bubbles).  The pure exponential a·b^d must also absorb the fixed
    cost that dominates at depth 1, which drags its b down to 1.59-1.62: it lies between 1.5
    and that ratio.  The affine law a + c·b^d separates the fixed cost and its b (1.67, 1.74,
    1.72) matches the high-depth ratio within 0.05.
    """
    t = SEED["seconds"][bubbles]
    ratio = _high_depth_ratio(t)
    assert 1.65 < ratio < 1.75
    b = fit_exponential(SEED["depth"], t).params["b"]
    assert 1.5 < b < ratio
    affine = fit_affine_exponential(SEED["depth"], t)
    assert 1.6 < affine.params["b"] < 1.8
    assert abs(affine.params["b"] - ratio) < 0.05
    assert affine.params["a"] > 0 and affine.params["c"] > 0  # a fixed cost, a growing tree


@pytest.mark.reference
@pytest.mark.parametrize("relative", [True, False])
@pytest.mark.parametrize("bubbles", [1, 2, 3])
def test_seed_table_follows_fixed_cost_plus_branching(bubbles, relative):
    """a + c·b^d wins by AIC, AICc and BIC, with relative or absolute residuals; with relative
    ones (timing noise is proportional to the time) decisively (ΔAICc > 10 to the next law)."""
    for criterion in ("aic", "aicc", "bic"):
        comparison = compare_fits(SEED["depth"], SEED["seconds"][bubbles], relative=relative, criterion=criterion)
        assert comparison.best == "affine exponential"
    if relative:
        assert comparison.rows[1]["delta"] > 10.0


@pytest.mark.reference
@pytest.mark.parametrize("bubbles", [1, 2, 3])
def test_quartic_interpolates_affine_exponential_extrapolates(bubbles):
    """Fitted to depths 1-7, a + c·b^d predicts depths 8-10 within 5 %; the quartic misses
    depth 10 by more than 10 % (measured: 15-23 % low)."""
    t = SEED["seconds"][bubbles]
    _, err_affine = holdout_errors(fit_affine_exponential, SEED["depth"], t, 7)
    _, err_quartic = holdout_errors(fit_polynomial, SEED["depth"], t, 7, relative=True)
    assert np.abs(err_affine).max() < 0.05
    assert abs(err_quartic[-1]) > 0.10


# ------------------------------------------------------------------ Pareto front (analytic)


@pytest.mark.analytic
def test_pareto_front_hand_made():
    #            0    1    2    3    4    5    6    7       8
    times = [1.0, 2.0, 3.0, 2.5, 2.0, 4.0, 3.0, np.nan, 0.5]
    errors = [5.0, 3.0, 1.0, 4.0, 3.5, 0.5, 1.0, 0.0, 9.0]
    # 3 is dominated by 1; 4 by 1 (same time, larger error); 6 duplicates 2 (both kept);
    # 7 has a NaN; 8 is the fastest and so on the front; 5 is the most accurate
    assert pareto_front(times, errors).tolist() == [8, 0, 1, 2, 6, 5]


@pytest.mark.analytic
def test_pareto_front_edge_cases():
    assert pareto_front([], []).tolist() == []
    assert pareto_front([1.0], [1.0]).tolist() == [0]
    assert pareto_front([1.0, 2.0, 3.0], [1.0, 1.0, 1.0]).tolist() == [0]  # equal error: the fastest
    assert pareto_front([1.0, 2.0, 3.0], [3.0, 2.0, 1.0]).tolist() == [0, 1, 2]  # all trade-offs
    with pytest.raises(ValueError, match="same length"):
        pareto_front([1.0, 2.0], [1.0])


@pytest.mark.reference
@pytest.mark.parametrize("seed", range(5))
def test_pareto_front_against_literal_definition(seed):
    """Against the definition applied pair by pair (O(n²)), on integer grids full of ties."""
    rng = np.random.default_rng(seed)
    t = rng.integers(0, 8, 60).astype(float)
    e = rng.integers(0, 8, 60).astype(float)
    literal = [
        i for i in range(t.size)
        if not any(t[j] <= t[i] and e[j] <= e[i] and (t[j] < t[i] or e[j] < e[i]) for j in range(t.size))
    ]
    assert sorted(pareto_front(t, e).tolist()) == literal


# ------------------------------------------------------------------ ΔE00


def _lab_to_linear_srgb(lab):
    """Inverse of delta_e00's Lab conversion.  Solves with colour's RGB -> XYZ matrix rather than
    using its XYZ -> RGB one: IEC 61966-2-1 rounds both matrices to four decimals, so they are
    not exact inverses and the round trip would be off by ~1e-4 in ΔE00."""
    space = colour.RGB_COLOURSPACES["sRGB"]
    XYZ = colour.Lab_to_XYZ(np.asarray(lab, dtype=float), space.whitepoint)
    return np.linalg.solve(space.matrix_RGB_to_XYZ, XYZ[..., None])[..., 0]


@pytest.mark.analytic
def test_delta_e00_of_identical_images_is_zero():
    rng = np.random.default_rng(0)
    image = rng.uniform(0.0, 1.5, (7, 5, 3))  # HDR values above 1 too
    d = delta_e00(image, image)
    assert d.shape == (7, 5)
    assert np.all(d == 0.0)


# Sharma, Wu & Dalal (2005), Color Res. Appl. 30, 21, table 1: pairs 1, 2, 3, 7, 17, 25, 31, 34
# (also in colour-science's own tests, colour/difference/tests/test_delta_e.py).
SHARMA = [
    ([50.0, 2.6772, -79.7751], [50.0, 0.0, -82.7485], 2.0425),
    ([50.0, 3.1571, -77.2803], [50.0, 0.0, -82.7485], 2.8615),
    ([50.0, 2.8361, -74.0200], [50.0, 0.0, -82.7485], 3.4412),
    ([50.0, 0.0, 0.0], [50.0, -1.0, 2.0], 2.3669),
    ([50.0, 2.5, 0.0], [73.0, 25.0, -18.0], 27.1492),
    ([60.2574, -34.0099, 36.2677], [60.4626, -34.1751, 39.4387], 1.2644),
    ([90.8027, -2.0831, 1.4410], [91.1528, -1.6435, 0.0447], 1.4441),
    ([2.0776, 0.0795, -1.1350], [0.9033, -0.0636, -0.5514], 0.9082),
]


@pytest.mark.reference
def test_delta_e00_published_pairs():
    """Lab pairs with published ΔE00, carried to linear sRGB (exact, unclipped) and back."""
    lab_1 = np.array([p[0] for p in SHARMA])
    lab_2 = np.array([p[1] for p in SHARMA])
    expected = np.array([p[2] for p in SHARMA])
    d = delta_e00(_lab_to_linear_srgb(lab_1), _lab_to_linear_srgb(lab_2))
    np.testing.assert_allclose(d, expected, atol=1e-4)
    np.testing.assert_allclose(d, colour.delta_E(lab_1, lab_2, method="CIE 2000"), rtol=1e-9)


@pytest.mark.reference
def test_delta_e00_equals_colour_science_on_images():
    """Two random linear-sRGB images: equal to colour-science's own RGB -> XYZ -> Lab -> ΔE00."""
    rng = np.random.default_rng(1)
    a = rng.uniform(0.0, 1.0, (6, 4, 3))
    b = np.clip(a + rng.normal(0.0, 0.05, a.shape), 0.0, None)
    space = colour.RGB_COLOURSPACES["sRGB"]
    lab = [colour.XYZ_to_Lab(colour.RGB_to_XYZ(x, space), space.whitepoint) for x in (a, b)]
    np.testing.assert_allclose(delta_e00(a, b), colour.delta_E(*lab, method="CIE 2000"), rtol=1e-12, atol=1e-12)
    # one known pair in full: sRGB red against green, both at full intensity
    assert delta_e00([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]) == pytest.approx(
        float(colour.delta_E(*[colour.XYZ_to_Lab(colour.RGB_to_XYZ(x, space), space.whitepoint)
                               for x in ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0])], method="CIE 2000")), rel=1e-12)


@pytest.mark.api
def test_delta_e00_shapes_and_errors():
    assert delta_e00(np.zeros((4, 3)), np.ones(3)).shape == (4,)  # broadcasting
    with pytest.raises(ValueError, match="3 channels"):
        delta_e00(np.zeros((4, 4)), np.zeros((4, 4)))


# ------------------------------------------------------------------ loaders and arguments (api)


@pytest.mark.api
def test_load_seed_table():
    assert SEED["depth"].tolist() == list(range(1, 11))
    assert SEED["seconds"][1][0] == 17.48 and SEED["seconds"][3][-1] == 1889.56
    assert any("Apple M3 Pro" in note for note in SEED["notes"])


@pytest.mark.api
def test_load_timing_matches_the_seed_and_is_complete():
    timing = load_timing()
    assert timing["depth"].size == 60  # 3 scenes x 2 modes x 10 depths
    assert timing["seconds_runs"].shape[0] == 60
    for nb in (1, 2, 3):
        for mode in ("pruned", "exhaustive"):
            depth, seed_seconds = timing_series(timing, nb, mode, "seed_seconds")
            assert depth.tolist() == list(range(1, 11))
            np.testing.assert_array_equal(seed_seconds, SEED["seconds"][nb])
            _, rays = timing_series(timing, nb, mode, "rays_total")
            assert rays.dtype.kind == "i" and np.all(np.diff(rays) >= 0)
    assert [row["mode"] for row in timing["extra"]] == ["fresh process, start to saved image"]
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


@pytest.mark.api
def test_docstring_examples():
    """tracer/ is not in pytest's doctest paths; run the module's examples here."""
    result = doctest.testmod(study, optionflags=doctest.ELLIPSIS)
    assert result.attempted >= 10 and result.failed == 0

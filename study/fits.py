"""Growth laws of run time against trace depth, fitted and compared.

*t(d)*, the run time *t* (s) of a render against its trace depth *d* (an integer ≥ 1, the number
of ray levels): :func:`fit_polynomial` (the coursework's fourth-degree polynomial, its figure
4.1), :func:`fit_exponential` (*t = a·bᵈ*), :func:`fit_affine_exponential` (*t = a + c·bᵈ*),
ranked by :func:`compare_fits` (AIC, AICc, BIC), :func:`holdout_errors` (fitted on the
shallow depths, tested on the deep ones) and :func:`branching_interval` (confidence intervals of
the growth base *b* of *a + c·bᵈ*: from the covariance, the profile likelihood and a residual
bootstrap).

Why an exponential: a Whitted tracer spawns a reflected and a refracted ray at every hit (the
coursework's listings 3.3-3.4), so the rays alive at recursion level *d* multiply by an
effective branching factor *b* per level and the work up to depth *d* is a geometric sum,
*t(d) = a + c·bᵈ* (*a*: the per-pixel cost independent of depth, camera rays and the image;
*c·bᵈ*: the tree).  A quartic has five free coefficients and no such structure: on ten points it
interpolates, but it does not extrapolate (see :func:`holdout_errors`).

scipy is imported inside the exponential fits only (``import study`` stays light).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

__all__ = [
    "Fit",
    "fit_polynomial",
    "fit_exponential",
    "fit_affine_exponential",
    "Comparison",
    "compare_fits",
    "holdout_errors",
    "BranchingInterval",
    "branching_interval",
]


@dataclass(frozen=True)
class Fit:
    """A fitted growth law *t(d)* and its quality.

    Attributes
    ----------
    model : ``"polynomial, degree k"``, ``"exponential"`` or ``"affine exponential"``.
    formula : the model as text, e.g. ``"a·b^d"``.
    params, stderr : dicts of parameter name -> value and its standard error (from the
        residual-scaled covariance: ``s² (JᵀWJ)⁻¹``, ``s² = Σ(w r)²/(n − k)``).
    coef : the parameter values in order (for a polynomial: ascending powers of *d*, unscaled
        basis, i.e. ``t = coef[0] + coef[1] d + …``).
    n_params : *k*, the number of fitted parameters (the noise scale not counted).
    depth, seconds, fitted, residuals : the data, the model at the data, ``seconds − fitted``.
    r2 : 1 − Σ(t − t̂)² / Σ(t − t̄)², unweighted, as usually quoted for such plots.
    rms_relative : √(mean(((t − t̂)/t)²)), the typical relative miss.
    relative : True if the fit minimised relative residuals Σ((t − t̂)/t)² (weights 1/t),
        False if absolute ones Σ(t − t̂)².
    """

    model: str
    formula: str
    params: dict
    stderr: dict
    coef: np.ndarray
    n_params: int
    depth: np.ndarray
    seconds: np.ndarray
    fitted: np.ndarray
    residuals: np.ndarray
    r2: float
    rms_relative: float
    relative: bool
    _function: Callable = field(repr=False, compare=False)

    def predict(self, depth):
        """The fitted law at *depth* (array_like), in seconds."""
        return self._function(np.asarray(depth, dtype=float))

    @property
    def relative_residuals(self):
        """``(t − t̂) / t`` at the data."""
        return self.residuals / self.seconds


def _data(depth, seconds, n_params, relative):
    x = np.asarray(depth, dtype=float)
    y = np.asarray(seconds, dtype=float)
    if x.ndim != 1 or x.shape != y.shape:
        raise ValueError(f"depth and seconds must be 1-D of equal length (got {x.shape} and {y.shape})")
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
        raise ValueError("depth and seconds must be finite")
    if x.size <= n_params:
        raise ValueError(f"{n_params} parameters need more than {n_params} points (got {x.size})")
    if relative and not np.all(y > 0):
        raise ValueError("this fit needs seconds > 0 (weights 1/seconds or a logarithmic start)")
    return x, y


def _finish(model, formula, names, values, cov, x, y, function, relative):
    fitted = function(x)
    residuals = y - fitted
    ss_tot = float(np.sum((y - y.mean()) ** 2))
    r2 = 1.0 - float(np.sum(residuals**2)) / ss_tot if ss_tot > 0 else math.nan
    se = np.sqrt(np.clip(np.diag(cov), 0.0, None)) if cov is not None else np.full(len(values), math.nan)
    values = np.asarray(values, dtype=float)
    return Fit(
        model=model, formula=formula,
        params={k: float(v) for k, v in zip(names, values)},
        stderr={k: float(s) for k, s in zip(names, se)},
        coef=values, n_params=len(values), depth=x, seconds=y, fitted=fitted, residuals=residuals,
        r2=r2, rms_relative=float(np.sqrt(np.mean((residuals / y) ** 2))), relative=relative,
        _function=function,
    )


def _scaled_covariance(jacobian, weighted_residuals):
    """s² (AᵀA)⁻¹ for a weighted Jacobian A (rows scaled by the weights), s² = Σ(w r)²/(n − k)."""
    n, k = jacobian.shape
    s2 = float(np.sum(weighted_residuals**2)) / (n - k)
    return s2 * np.linalg.pinv(jacobian.T @ jacobian)


def fit_polynomial(depth, seconds, degree=4, *, relative=False):
    """Least-squares polynomial *t = Σⱼ cⱼ dʲ*, j = 0..degree: the coursework's figure 4.1 (degree 4).

    Fitted with ``numpy.polynomial.Polynomial.fit`` (a scaled, well-conditioned basis), then
    converted to the unscaled basis for ``coef`` (ascending powers).  By default the residuals
    are absolute, as in the coursework (ordinary least squares on the times); ``relative=True``
    weights each point by 1/t, i.e. minimises Σ((t − t̂)/t)².

    Parameters
    ----------
    depth : 1-D array_like, trace depths.
    seconds : 1-D array_like, times (s).
    degree : polynomial degree (4: five parameters).

    Returns
    -------
    :class:`Fit` with params ``c0 … c{degree}``.

    Example
    -------
    >>> d = np.arange(1.0, 11.0)
    >>> fit = fit_polynomial(d, 2 + 0.5 * d**4)
    >>> (np.round(fit.coef, 8) + 0.0).tolist(), round(fit.r2, 12)   # + 0.0 turns -0.0 into 0.0
    ([2.0, 0.0, 0.0, 0.0, 0.5], 1.0)
    """
    k = int(degree) + 1
    x, y = _data(depth, seconds, k, relative)
    w = 1.0 / y if relative else np.ones_like(y)
    poly = np.polynomial.Polynomial.fit(x, y, int(degree), w=w)
    coef = np.zeros(k)
    converted = poly.convert().coef
    coef[: converted.size] = converted
    design = x[:, None] ** np.arange(k)
    cov = _scaled_covariance(design * w[:, None], w * (y - poly(x)))
    return _finish(f"polynomial, degree {degree}", " + ".join(f"c{j}·d^{j}" for j in range(k)),
                   [f"c{j}" for j in range(k)], coef, cov, x, y, poly, relative)


def _log_linear_start(x, y):
    """(ln a, ln b) of least squares on ln t = ln a + d ln b: exact for noise-free a·bᵈ."""
    design = np.column_stack([np.ones_like(x), x])
    (ln_a, ln_b), *_ = np.linalg.lstsq(design, np.log(y), rcond=None)
    return ln_a, ln_b


def fit_exponential(depth, seconds, *, relative=True):
    """Fit *t = a·bᵈ*: a ray tree with effective branching factor *b* per level.

    Method: nonlinear least squares on the model itself (``scipy.optimize.curve_fit``,
    Levenberg-Marquardt, parametrised as *a·exp(βd)* with *b = e^β* so *b* stays positive),
    started from the closed-form least-squares line through ln t (which is exact for
    noise-free data).  Why not stop at the log-linear fit: fitting the model in the same
    residuals as the other laws makes the residuals, R² and information criteria of
    :func:`compare_fits` comparable (the affine law *a + c·bᵈ* cannot be linearised).  By
    default (``relative=True``) each point is weighted by 1/t, i.e. Σ((t − t̂)/t)² is minimised:
    timing noise is multiplicative (a few per cent of the time), and the times span two orders
    of magnitude, so unweighted residuals would let the deepest point decide the fit.
    ``relative=False`` minimises absolute residuals.

    Standard errors: from the residual-scaled covariance of (a, β); *se(b) = b·se(β)* (delta
    method).

    Returns
    -------
    :class:`Fit` with params ``a`` (s) and ``b`` (dimensionless, per depth level).

    Example
    -------
    >>> d = np.arange(1.0, 11.0)
    >>> fit = fit_exponential(d, 3.0 * 1.7**d)
    >>> round(fit.params["a"], 10), round(fit.params["b"], 10)
    (3.0, 1.7)
    """
    from scipy.optimize import curve_fit

    x, y = _data(depth, seconds, 2, True)  # ln t needs t > 0 for the start
    ln_a, beta = _log_linear_start(x, y)

    def model(d, a, beta):
        return a * np.exp(beta * d)

    popt, _ = curve_fit(model, x, y, p0=(math.exp(ln_a), beta), sigma=y if relative else None, maxfev=20000)
    a, beta = popt
    w = 1.0 / y if relative else np.ones_like(y)
    jac = np.column_stack([np.exp(beta * x), a * x * np.exp(beta * x)]) * w[:, None]
    cov_ab = _scaled_covariance(jac, w * (y - model(x, a, beta)))
    b = math.exp(beta)
    scale = np.diag([1.0, b])  # d(a, b)/d(a, β)
    cov = scale @ cov_ab @ scale
    return _finish("exponential", "a·b^d", ["a", "b"], [a, b], cov, x, y,
                   lambda d: a * np.exp(beta * d), relative)


def fit_affine_exponential(depth, seconds, *, relative=True):
    """Fit *t = a + c·bᵈ*: a depth-independent cost *a* plus a ray tree branching *b* per level.

    The physics: the work that does not depend on depth (camera rays of every pixel, the
    background, writing the image) is a constant, the ray tree is a geometric sum
    Σₖ c′bᵏ = c·bᵈ + const.  So *a* is the fixed cost and *b* the effective branching factor;
    a pure exponential (:func:`fit_exponential`) must bend its *b* down to absorb *a*.

    Method: for fixed *b* the model is linear in (a, c), so a grid over *b* ∈ [1.001, 4] solved
    by weighted linear least squares (variable projection) gives a start free of guesses; then
    ``scipy.optimize.curve_fit`` refines (a, c, β = ln b) on the model.  Weights as in
    :func:`fit_exponential` (relative by default).  On data that do not grow (c ≈ 0) or grow
    linearly (b → 1, c → ∞) the law is degenerate and *b* is not identified: look at the
    standard errors before reading *b*.

    Returns
    -------
    :class:`Fit` with params ``a`` (s), ``c`` (s) and ``b`` (per level).

    Example
    -------
    >>> d = np.arange(1.0, 11.0)
    >>> fit = fit_affine_exponential(d, 10.0 + 2.0 * 1.6**d)
    >>> [round(fit.params[k], 6) for k in "acb"]
    [10.0, 2.0, 1.6]
    """
    from scipy.optimize import curve_fit

    x, y = _data(depth, seconds, 3, relative)
    w = 1.0 / y if relative else np.ones_like(y)

    def model(d, a, c, beta):
        return a + c * np.exp(beta * d)

    grid = np.linspace(1.001, 4.0, 600)
    b0 = float(grid[np.argmin(_rowwise_profile(x, y[None, :], w[None, :], grid[None, :])[0])])
    design = np.column_stack([np.ones_like(x), b0**x]) * w[:, None]
    (a0, c0), *_ = np.linalg.lstsq(design, w * y, rcond=None)
    p0 = (a0, c0, math.log(b0))
    try:
        popt, _ = curve_fit(model, x, y, p0=p0, sigma=1.0 / w, maxfev=20000)
    except RuntimeError:  # no convergence (e.g. flat data, where b is not identifiable)
        popt = np.asarray(p0)
    a, c, beta = popt
    e = np.exp(beta * x)
    jac = np.column_stack([np.ones_like(x), e, c * x * e]) * w[:, None]
    cov_acb = _scaled_covariance(jac, w * (y - model(x, a, c, beta)))
    b = math.exp(beta)
    scale = np.diag([1.0, 1.0, b])
    cov = scale @ cov_acb @ scale
    return _finish("affine exponential", "a + c·b^d", ["a", "c", "b"], [a, c, b], cov, x, y,
                   lambda d: a + c * np.exp(beta * d), relative)


@dataclass(frozen=True)
class Comparison:
    """Information criteria of several fits to the same data (see :func:`compare_fits`).

    ``rows``: one dict per fit, sorted best first by *criterion*, with ``model``, ``formula``,
    ``n_params`` (k), ``rss`` (in the residual space used), ``aic``, ``aicc``, ``bic``,
    ``delta`` (criterion minus the best), ``weight`` (Akaike-type weight exp(−Δ/2)/Σ),
    ``r2``, ``rms_relative`` and ``fit`` (the :class:`Fit`).  ``best``: the winning model's name.
    """

    rows: list
    best: str
    criterion: str
    relative: bool
    n: int

    def __str__(self):
        space = "relative" if self.relative else "absolute"
        lines = [f"n = {self.n} points, {space} residuals, ranked by {self.criterion.upper()}",
                 f"{'model':24s} {'k':>2s} {'AIC':>8s} {'AICc':>8s} {'BIC':>8s} {'delta':>7s} "
                 f"{'weight':>7s} {'R2':>8s} {'rms rel':>8s}"]
        for r in self.rows:
            lines.append(f"{r['model']:24s} {r['n_params']:2d} {r['aic']:8.2f} {r['aicc']:8.2f} {r['bic']:8.2f} "
                         f"{r['delta']:7.2f} {r['weight']:7.3f} {r['r2']:8.5f} {r['rms_relative']:8.4f}")
        return "\n".join(lines)


def compare_fits(depth, seconds, fits=None, *, relative=True, criterion="aicc"):
    """Which growth law explains *t(d)* best, for its number of parameters.

    Each fit is scored with the Gaussian maximum-likelihood information criteria (Burnham &
    Anderson 2002, *Model Selection and Multimodel Inference*, §2.2 and §6.4), with K = k + 1
    parameters (the *k* of the law plus the noise scale) and RSS the residual sum of squares
    in the chosen space (relative: Σ((t − t̂)/t)², i.e. noise proportional to t; absolute:
    Σ(t − t̂)²):

    * AIC  = n ln(RSS/n) + 2K
    * AICc = AIC + 2K(K + 1)/(n − K − 1)   (small samples: n = 10 here)
    * BIC  = n ln(RSS/n) + K ln n

    Terms common to all models (the Jacobian of the relative scale, Σ ln t) cancel in the
    differences.  Lower is better; a difference above ~10 is decisive.

    Parameters
    ----------
    fits : list of :class:`Fit` to score (default: the quartic, the exponential and the
        affine exponential, each fitted with the same *relative* weighting, so each sits at
        its own optimum of the likelihood compared).  Fits made with another weighting are
        scored as given (disadvantaged: they did not minimise this RSS).
    relative : residual space of the likelihood.
    criterion : ``"aic"``, ``"aicc"`` or ``"bic"``, for ``best`` and the ranking.

    Returns
    -------
    :class:`Comparison`.

    Example
    -------
    >>> d = np.arange(1.0, 11.0)
    >>> noise = 1 + 0.01 * np.random.default_rng(0).standard_normal(d.size)
    >>> compare_fits(d, (10.0 + 2.0 * 1.7**d) * noise).best
    'affine exponential'
    """
    if criterion not in ("aic", "aicc", "bic"):
        raise ValueError(f"criterion must be 'aic', 'aicc' or 'bic' (got {criterion!r})")
    x, y = _data(depth, seconds, 0, relative)
    if fits is None:
        fits = [fit_polynomial(x, y, 4, relative=relative), fit_exponential(x, y, relative=relative),
                fit_affine_exponential(x, y, relative=relative)]
    n = x.size
    rows = []
    for fit in fits:
        if fit.depth.shape != x.shape or not (np.array_equal(fit.depth, x) and np.array_equal(fit.seconds, y)):
            raise ValueError(f"the {fit.model} fit was made on other data")
        r = fit.residuals / y if relative else fit.residuals
        rss = float(np.sum(r**2))
        big_k = fit.n_params + 1
        core = n * math.log(rss / n) if rss > 0 else -math.inf
        aic = core + 2 * big_k
        aicc = aic + 2 * big_k * (big_k + 1) / (n - big_k - 1) if n - big_k - 1 > 0 else math.inf
        bic = core + big_k * math.log(n)
        rows.append(dict(model=fit.model, formula=fit.formula, n_params=fit.n_params, rss=rss, aic=aic,
                         aicc=aicc, bic=bic, r2=fit.r2, rms_relative=fit.rms_relative, fit=fit))
    rows.sort(key=lambda r: r[criterion])
    best = rows[0][criterion]
    for r in rows:
        r["delta"] = r[criterion] - best if math.isfinite(best) else (0.0 if r[criterion] == best else math.inf)
    total = sum(math.exp(-0.5 * r["delta"]) for r in rows)
    for r in rows:
        r["weight"] = math.exp(-0.5 * r["delta"]) / total
    return Comparison(rows=rows, best=rows[0]["model"], criterion=criterion, relative=relative, n=n)


def holdout_errors(fitter, depth, seconds, max_train_depth, **kwargs):
    """Relative error of a law fitted on depths ≤ *max_train_depth* at the deeper points.

    Tells an interpolating law from an explaining one: ``fitter(depth, seconds, **kwargs)`` (one
    of the ``fit_*`` functions) sees only the shallow depths; returns ``(depth_held_out,
    (t̂ − t)/t)`` at the others.

    Example
    -------
    >>> d = np.arange(1.0, 11.0)
    >>> _, err = holdout_errors(fit_exponential, d, 3.0 * 1.7**d, 7)
    >>> bool(np.abs(err).max() < 1e-9)
    True
    """
    x = np.asarray(depth, dtype=float)
    y = np.asarray(seconds, dtype=float)
    train = x <= max_train_depth
    if train.all():
        raise ValueError(f"no depths above {max_train_depth} to hold out")
    fit = fitter(x[train], y[train], **kwargs)
    return x[~train], fit.predict(x[~train]) / y[~train] - 1.0


# ------------------------------------------------------------------ the uncertainty of b


def _argmin_b(x, y, w, lo=1.001, hi=4.0):
    """The least-squares b of a + c·bᵈ for each row of ``y`` (m, n): a grid over [lo, hi] in
    ln b, then four finer grids around the best point (resolution ~1e-8 in ln b)."""
    grid = np.exp(np.linspace(math.log(lo), math.log(hi), 301))
    rss = _rowwise_profile(x, y, w, np.broadcast_to(grid, (y.shape[0], grid.size)))
    best = grid[np.argmin(rss, axis=1)]
    step = math.log(hi / lo) / 300
    for _ in range(4):
        fine = np.exp(np.log(best)[:, None] + np.linspace(-2 * step, 2 * step, 41)[None, :])  # (m, 41)
        rss = _rowwise_profile(x, y, w, fine)
        best = fine[np.arange(y.shape[0]), np.argmin(rss, axis=1)]
        step = step / 10
    return best


def _rowwise_profile(x, y, w, b):
    """Weighted RSS of a + c·bᵈ minimised over (a, c) at each *b*: ``y``, ``w`` (m, n), ``b``
    (m, g), a grid of b per row -> (m, g).  For fixed b the model is linear in (a, c): the 2×2
    normal equations, vectorised."""
    e = b[:, :, None] ** x[None, None, :]
    w2 = (w**2)[:, None, :]
    yy = y[:, None, :]
    s11 = w2.sum(axis=2)
    s12 = (w2 * e).sum(axis=2)
    s22 = (w2 * e * e).sum(axis=2)
    t1 = (w2 * yy).sum(axis=2)
    t2 = (w2 * e * yy).sum(axis=2)
    det = s11 * s22 - s12**2
    with np.errstate(divide="ignore", invalid="ignore"):
        a = (s22 * t1 - s12 * t2) / det
        c = (s11 * t2 - s12 * t1) / det
        rss = (w2 * (yy - a[..., None] - c[..., None] * e) ** 2).sum(axis=2)
    return np.where(np.isfinite(rss), rss, np.inf)  # b -> 1: a and c not separable


@dataclass(frozen=True)
class BranchingInterval:
    """Confidence intervals of *b* in *t(d) = a + c·bᵈ* (see :func:`branching_interval`).

    Attributes
    ----------
    b : the least-squares estimate (relative weights, as :func:`fit_affine_exponential`).
    level : the confidence level (e.g. 0.95).
    wald : (low, high) from the residual-scaled covariance: b ± t₍ₙ₋₃₎ · se(b).
    profile : (low, high) of the profile likelihood: the b whose best (a, c) raise the RSS by
        at most the F-test's factor (an end not reached within the search range (1, b_max] is
        given as that edge).
    bootstrap : (low, high), percentile interval of *b* refitted to ``n_boot`` residual-bootstrap
        data sets.
    bootstrap_b : the refitted values (array, ``n_boot``).
    fit : the :class:`Fit` of :func:`fit_affine_exponential`.
    """

    b: float
    level: float
    wald: tuple
    profile: tuple
    bootstrap: tuple
    bootstrap_b: np.ndarray = field(repr=False)
    fit: Fit = field(repr=False)

    @property
    def intervals(self):
        """{method: (low, high)} for ``"wald"``, ``"profile"`` and ``"bootstrap"``."""
        return {"wald": self.wald, "profile": self.profile, "bootstrap": self.bootstrap}


def branching_interval(depth, seconds, *, level=0.95, n_boot=2000, seed=0, b_max=4.0):
    """Confidence intervals of the growth base *b* of *t(d) = a + c·bᵈ*, three ways.

    The fit is :func:`fit_affine_exponential` with relative weights (noise proportional to *t*:
    the model for timings, and for a transcribed table whose entries carry a fixed number of
    significant digits).  With *n* points and *k* = 3 parameters:

    * **Wald** (the fit's covariance): b ± t_{n−k}((1 + level)/2) · se(b), se(b) from the
      residual-scaled covariance s²(JᵀWJ)⁻¹ (delta method through β = ln b).  Symmetric by
      construction; trusts the linearisation of the model around the estimate.
    * **Profile likelihood**: for each *b*, (a, c) are solved by weighted linear least squares
      (the model is linear in them) giving RSS(b); the interval is the set of *b* with
      RSS(b)/RSS(b̂) ≤ 1 + F_{1,n−k}(level)/(n − k) (the F-test of one restriction, exact for
      linear models and the usual small-sample form of the likelihood-ratio interval for
      nonlinear least squares: Bates & Watts 1988, *Nonlinear Regression Analysis and Its
      Applications*, §6.1).  Follows the curvature of the model; may be asymmetric.  Ends are
      found by root bracketing on (1, *b_max*]; an end not reached is reported as that edge.
    * **Residual bootstrap** (percentile): the relative residuals rᵢ = (tᵢ − t̂ᵢ)/t̂ᵢ, centred
      and scaled by √(n/(n−k)) (their variance is biased low by the fit's k parameters), are
      resampled with replacement, t*ᵢ = t̂ᵢ(1 + r*ᵢ), and *b* is refitted (by a vectorised
      profile search of b ∈ [1.001, *b_max*]) *n_boot* times; the interval is the
      ((1 − level)/2, (1 + level)/2) quantiles of the refitted b (Efron & Tibshirani 1993, *An
      Introduction to the Bootstrap*, §9.5 and ch. 13).  With ten points it tends to be a little
      narrow.

    Parameters
    ----------
    depth, seconds : 1-D array_like (more than 3 points, seconds > 0).
    level : confidence level in (0, 1).
    n_boot : bootstrap resamples (0: skip, the interval is (nan, nan)).
    seed : of the bootstrap's random numbers (numpy's default generator).
    b_max : upper end of the search for b (the profile's and the bootstrap's).

    Returns
    -------
    :class:`BranchingInterval`.

    Example
    -------
    >>> d = np.arange(1.0, 11.0)
    >>> noise = 1 + 0.01 * np.random.default_rng(1).standard_normal(d.size)
    >>> ci = branching_interval(d, (20.0 + 8.0 * 1.72**d) * noise, n_boot=500)
    >>> all(lo < 1.72 < hi for lo, hi in ci.intervals.values())
    True
    """
    from scipy.optimize import brentq
    from scipy.stats import f as f_dist
    from scipy.stats import t as t_dist

    if not 0.0 < level < 1.0:
        raise ValueError(f"level must be in (0, 1) (got {level})")
    if n_boot < 0:
        raise ValueError(f"n_boot must be >= 0 (got {n_boot})")
    x, y = _data(depth, seconds, 3, True)
    fit = fit_affine_exponential(x, y)
    b = fit.params["b"]
    n, k = x.size, 3
    dof = n - k
    w = 1.0 / y

    half = float(t_dist.ppf(0.5 + level / 2, dof)) * fit.stderr["b"]
    wald = (b - half, b + half)

    def rss(bb):
        return float(_rowwise_profile(x, y[None, :], w[None, :], np.array([[bb]]))[0, 0])

    rss_min = rss(b)
    limit = rss_min * (1.0 + float(f_dist.ppf(level, 1, dof)) / dof)

    def excess(bb):
        return rss(bb) - limit

    def end(edge):
        grid = np.linspace(b, edge, 400)
        above = np.flatnonzero(_rowwise_profile(x, y[None, :], w[None, :], grid[None, :])[0] > limit)
        if above.size == 0:
            return float(edge)  # not reached within the search range
        i = int(above[0])
        return float(brentq(excess, grid[i - 1], grid[i], xtol=1e-10)) if i > 0 else float(b)

    profile = (end(1.0 + 1e-9), end(b_max))

    if n_boot > 0:
        rng = np.random.default_rng(seed)
        fitted = fit.fitted
        r = (y - fitted) / fitted
        r = (r - r.mean()) * math.sqrt(n / dof)
        ystar = fitted[None, :] * (1.0 + rng.choice(r, size=(n_boot, n), replace=True))
        ystar = np.clip(ystar, 1e-300, None)
        bstar = _argmin_b(x, ystar, 1.0 / ystar, hi=b_max)
        q = np.quantile(bstar, [0.5 - level / 2, 0.5 + level / 2])
        bootstrap = (float(q[0]), float(q[1]))
    else:
        bstar = np.empty(0)
        bootstrap = (math.nan, math.nan)
    return BranchingInterval(b=b, level=level, wald=(float(wald[0]), float(wald[1])),
                             profile=(float(profile[0]), float(profile[1])), bootstrap=bootstrap,
                             bootstrap_b=bstar, fit=fit)

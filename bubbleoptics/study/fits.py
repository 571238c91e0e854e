"""Growth laws of run time against trace depth, fitted and compared.

*t(d)*, the run time *t* (s) of a render against its trace depth *d* (an integer ≥ 1, the number
of ray levels): :func:`fit_polynomial` (the coursework's fourth-degree polynomial, its figure
4.1), :func:`fit_exponential` (*t = a·bᵈ*), :func:`fit_affine_exponential` (*t = a + c·bᵈ*),
ranked by :func:`compare_fits` (AIC, AICc, BIC), and :func:`holdout_errors` (fitted on the
shallow depths, tested on the deep ones).

Why an exponential: a Whitted tracer spawns a reflected and a refracted ray at every hit (the
coursework's listings 3.3-3.4), so the rays alive at recursion level *d* multiply by an
effective branching factor *b* per level and the work up to depth *d* is a geometric sum,
*t(d) = a + c·bᵈ* (*a*: the per-pixel cost independent of depth, camera rays and the image;
*c·bᵈ*: the tree).  A quartic has five free coefficients and no such structure: on ten points it
interpolates, but it does not extrapolate (see :func:`holdout_errors`).

scipy is imported inside the exponential fits only (``import bubbleoptics.study`` stays light).
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

    best = None
    for beta in np.log(np.linspace(1.001, 4.0, 600)):
        design = np.column_stack([np.ones_like(x), np.exp(beta * x)]) * w[:, None]
        (a, c), *_ = np.linalg.lstsq(design, w * y, rcond=None)
        rss = float(np.sum((w * (y - model(x, a, c, beta))) ** 2))
        if best is None or rss < best[0]:
            best = (rss, a, c, beta)
    p0 = best[1:]
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

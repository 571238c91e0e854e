"""Analysis helpers for the studies: the seed's timing table, growth-law fits, Pareto fronts, ΔE00.

Shared by the notebooks (``notebooks/03_depth_timing.ipynb``, ``04_...``) and the paper's figure
scripts (``paper/scripts/``), so that a number in the paper and the same number in a notebook are
computed by one piece of code.  Nothing here renders; the inputs are files in ``data/`` and arrays.

Contents
--------
* :func:`load_seed_table` — the seed coursework's table 4.1 (``data/seed_table_4_1.csv``);
  :func:`load_timing` and :func:`timing_series` — our re-run of it
  (``data/derived/seed_table.csv``, written by ``benchmarks/seed_table.py``).
* Growth laws of run time *t* against trace depth *d*: :func:`fit_polynomial` (the seed's
  fourth-degree polynomial, its figure 4.1), :func:`fit_exponential` (*t = a·bᵈ*),
  :func:`fit_affine_exponential` (*t = a + c·bᵈ*), and :func:`compare_fits` (AIC, AICc, BIC).
* :func:`pareto_front` — the non-dominated (time, error) points of a trade-off study.
* :func:`delta_e00` — per-pixel CIEDE2000 between two linear-sRGB images (colour-science).

Why an exponential: a Whitted tracer spawns a reflected and a refracted ray at every hit (the
seed's listings 3.3-3.4), so the rays alive at recursion level *d* multiply by an effective
branching factor *b* per level and the work up to depth *d* is a geometric sum,
*t(d) = a + c·bᵈ* (*a*: the per-pixel cost independent of depth, camera rays and the image;
*c·bᵈ*: the tree).  A quartic has five free coefficients and no such structure: on ten points it
interpolates, but it does not extrapolate (see :func:`holdout_errors`).

Units: depth is the trace depth (an integer ≥ 1, the number of ray levels), times in seconds.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

__all__ = [
    "SEED_COLUMNS",
    "read_commented_csv",
    "load_seed_table",
    "load_timing",
    "timing_series",
    "Fit",
    "fit_polynomial",
    "fit_exponential",
    "fit_affine_exponential",
    "Comparison",
    "compare_fits",
    "holdout_errors",
    "pareto_front",
    "delta_e00",
]

_ROOT = Path(__file__).resolve().parents[1]
_SEED_TABLE = _ROOT / "data" / "seed_table_4_1.csv"
_TIMING = _ROOT / "data" / "derived" / "seed_table.csv"

#: Column of ``data/seed_table_4_1.csv`` for each number of bubbles.
SEED_COLUMNS = {1: "one_bubble", 2: "two_bubbles", 3: "three_bubbles"}

_INT_COLUMNS = ("bubbles", "depth", "width", "height", "rays_camera", "rays_reflected", "rays_transmitted",
                "rays_shadow", "rays_total")
_MODES = ("pruned", "exhaustive")


# --------------------------------------------------------------------------------------------
# data


def read_commented_csv(path):
    """(comment lines without '# ', rows as dicts of strings) of a CSV whose leading lines start
    with '#': the provenance comment every benchmark writes (``benchmarks/_results.py``)."""
    lines = Path(path).read_text(encoding="utf-8").splitlines()
    notes = [ln.lstrip("#").strip() for ln in lines if ln.startswith("#")]
    rows = list(csv.DictReader(ln for ln in lines if ln.strip() and not ln.startswith("#")))
    return notes, rows


def load_seed_table(path=None):
    """The seed coursework's table 4.1: run time (s) against trace depth for 1, 2 and 3 bubbles.

    Source: the seed's table 4.1 (960×960 PNG, Apple M3 Pro), transcribed in
    ``data/seed_table_4_1.csv`` (provenance in ``data/README.md``).  The seed fitted a
    fourth-degree polynomial to each column (its figure 4.1).

    Parameters
    ----------
    path : path of the CSV (default: ``data/seed_table_4_1.csv`` of this checkout).

    Returns
    -------
    dict with ``"depth"`` (int array, 1..10), ``"seconds"`` (dict: number of bubbles -> float
    array of times in s, one per depth) and ``"notes"`` (the file's header comments, a list of
    str: machine, units argument).

    Example
    -------
    >>> seed = load_seed_table()
    >>> seed["depth"].tolist()[:3], float(seed["seconds"][3][-1])
    ([1, 2, 3], 1889.56)
    """
    notes, rows = read_commented_csv(_SEED_TABLE if path is None else path)
    depth = np.array([int(r["depth"]) for r in rows])
    order = np.argsort(depth)
    seconds = {nb: np.array([float(r[col]) for r in rows])[order] for nb, col in SEED_COLUMNS.items()}
    return {"depth": depth[order], "seconds": seconds, "notes": notes}


def _number(text, integer):
    text = (text or "").strip()
    if text == "":
        return None if integer else math.nan
    return int(float(text)) if integer else float(text)


def load_timing(path=None):
    """Our re-run of the seed's table 4.1, as written by ``benchmarks/seed_table.py``.

    The file (``data/derived/seed_table.csv``; regenerate with ``python benchmarks/seed_table.py``
    or ``make bench``) has one row per (bubbles, depth, mode) with mode ``"pruned"`` (the default
    threshold) or ``"exhaustive"`` (threshold 0: the seed's full ray tree), and extra rows of
    other kinds (a fresh process timed from start to a saved image).

    Parameters
    ----------
    path : path of the CSV (default: ``data/derived/seed_table.csv`` of this checkout).

    Returns
    -------
    dict of column name -> numpy array over the pruned and exhaustive rows (``bubbles``,
    ``depth``, ``width``, ``height`` and the ``rays_*`` counts as int; ``mode`` as str;
    ``threshold``, ``seconds_median``, ``seed_seconds``, ``speedup_vs_seed`` as float), plus
    ``"seconds_runs"`` (float array, rows × repeats, NaN-padded), ``"extra"`` (list of dicts: the
    other rows, numbers parsed, empty cells None/NaN) and ``"notes"`` (header comments).

    Example
    -------
    >>> timing = load_timing()
    >>> sorted(set(timing["mode"].tolist()))
    ['exhaustive', 'pruned']
    """
    notes, rows = read_commented_csv(_TIMING if path is None else path)
    main = [r for r in rows if r["mode"] in _MODES]
    extra = [r for r in rows if r["mode"] not in _MODES]
    if not main:
        raise ValueError(f"{path or _TIMING}: no pruned or exhaustive rows")
    out = {}
    for name in main[0]:
        if name in ("mode", "seconds_runs"):
            continue
        integer = name in _INT_COLUMNS
        out[name] = np.array([_number(r[name], integer) for r in main], dtype=int if integer else float)
    out["mode"] = np.array([r["mode"] for r in main])
    runs = [[float(v) for v in r["seconds_runs"].split()] for r in main]
    width = max(len(v) for v in runs)
    out["seconds_runs"] = np.array([v + [math.nan] * (width - len(v)) for v in runs])
    out["extra"] = [
        {k: (v if k in ("mode", "seconds_runs") else _number(v, k in _INT_COLUMNS)) for k, v in r.items()}
        for r in extra
    ]
    out["notes"] = notes
    return out


def timing_series(timing, bubbles, mode, column="seconds_median"):
    """``(depth, values)`` of one column of :func:`load_timing`'s result, sorted by depth.

    Example
    -------
    >>> d, t = timing_series(load_timing(), 3, "exhaustive")
    >>> d.tolist() == list(range(1, 11)), bool(np.all(t > 0))
    (True, True)
    """
    if mode not in _MODES:
        raise ValueError(f"mode must be one of {_MODES} (got {mode!r})")
    pick = (timing["bubbles"] == bubbles) & (timing["mode"] == mode)
    if not pick.any():
        raise ValueError(f"no rows for {bubbles} bubble(s), mode {mode!r}")
    depth = timing["depth"][pick]
    order = np.argsort(depth)
    return depth[order], np.asarray(timing[column])[pick][order]


# --------------------------------------------------------------------------------------------
# fits


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
    """Least-squares polynomial *t = Σⱼ cⱼ dʲ*, j = 0..degree: the seed's figure 4.1 (degree 4).

    Fitted with ``numpy.polynomial.Polynomial.fit`` (a scaled, well-conditioned basis), then
    converted to the unscaled basis for ``coef`` (ascending powers).  By default the residuals
    are absolute, as in the seed (ordinary least squares on the times); ``relative=True``
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
    >>> seed = load_seed_table()
    >>> compare_fits(seed["depth"], seed["seconds"][1]).best
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


# --------------------------------------------------------------------------------------------
# trade-offs and colour


def pareto_front(times, errors):
    """Indices of the non-dominated points of a (time, error) trade-off, both to be minimised.

    Point *i* is dominated if some *j* has ``times[j] <= times[i]`` and ``errors[j] <=
    errors[i]`` with at least one strict inequality.  Exact duplicates do not dominate each
    other (both are kept); points with a NaN are ignored.  O(n log n): sort by time, then
    error, and keep each point whose error is below every faster point's.

    Returns
    -------
    int array of indices into the inputs, ordered by increasing time (decreasing error).

    Example
    -------
    >>> pareto_front([1.0, 2.0, 3.0, 2.5], [5.0, 3.0, 1.0, 4.0]).tolist()
    [0, 1, 2]
    """
    t = np.asarray(times, dtype=float).ravel()
    e = np.asarray(errors, dtype=float).ravel()
    if t.shape != e.shape:
        raise ValueError(f"times and errors must have the same length (got {t.size} and {e.size})")
    valid = np.flatnonzero(~(np.isnan(t) | np.isnan(e)))
    order = valid[np.lexsort((e[valid], t[valid]))]
    front = []
    best_before = math.inf  # lowest error among points strictly faster than the current time
    i = 0
    while i < order.size:
        j = i
        while j < order.size and t[order[j]] == t[order[i]]:
            j += 1
        group = order[i:j]  # equal times, sorted by error
        lowest = e[group[0]]
        if lowest < best_before:
            front.extend(int(k) for k in group if e[k] == lowest)
        best_before = min(best_before, lowest)
        i = j
    return np.array(front, dtype=int)


def delta_e00(rgb_a, rgb_b):
    """Per-pixel CIEDE2000 colour difference ΔE00 between two linear-sRGB images.

    Each image (array ``(..., 3)``, linear sRGB, *not* gamma-encoded; the tracer's output) is
    converted to CIE XYZ with the sRGB primaries and D65 white (``colour.RGB_to_XYZ``, no
    decoding), then to CIE L*a*b* relative to D65 (``colour.XYZ_to_Lab``), and compared with
    ``colour.delta_E(..., method="CIE 2000")`` (CIE 142-2001; Sharma, Wu & Dalal 2005, Color
    Res. Appl. 30, 21).  Values are absolute: linear RGB (1, 1, 1) is white with Y = 1 and
    L* = 100, so scale HDR images by the same exposure before comparing.  About 1-2 is a
    just-noticeable difference side by side.

    Returns
    -------
    ndarray of shape ``broadcast(rgb_a, rgb_b).shape[:-1]``.

    Example
    -------
    >>> a = np.full((2, 2, 3), 0.5)
    >>> delta_e00(a, a).tolist()
    [[0.0, 0.0], [0.0, 0.0]]
    """
    import colour

    a = np.asarray(rgb_a, dtype=float)
    b = np.asarray(rgb_b, dtype=float)
    if a.shape[-1:] != (3,) or b.shape[-1:] != (3,):
        raise ValueError(f"images must have 3 channels in the last axis (got {a.shape} and {b.shape})")
    a, b = np.broadcast_arrays(a, b)
    space = colour.RGB_COLOURSPACES["sRGB"]
    white = space.whitepoint

    def lab(rgb):
        XYZ = colour.RGB_to_XYZ(rgb, space, illuminant=white, chromatic_adaptation_transform=None,
                                apply_cctf_decoding=False)
        return colour.XYZ_to_Lab(XYZ, white)

    return np.asarray(colour.delta_E(lab(a), lab(b), method="CIE 2000"), dtype=float)

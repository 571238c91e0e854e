"""Trade-offs between two costs: Pareto fronts, and the time a curve needs to reach an error.

Used for run time against error (``benchmarks/time_vs_error.py``, notebook 04, the paper's
figure of it): :func:`pareto_front` is the one definition of "on the front".
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["pareto_front", "time_at_error", "time_ratio_curve"]


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


def time_at_error(seconds, errors, target):
    """Seconds at which a curve of (seconds, errors) reaches *target*: log(time) interpolated
    linearly in log(error) between the measured points, NaN outside the measured errors.

    For "time to equal error" comparisons (``benchmarks/peer_mitsuba.py``, the paper's numbers).

    Example
    -------
    >>> time_at_error([1.0, 4.0], [0.4, 0.1], 0.2)   # error halves as time doubles
    2.0
    >>> time_at_error([1.0, 4.0], [0.4, 0.1], 0.01)
    nan
    """
    order = np.argsort(seconds)
    t = np.log(np.asarray(seconds, float)[order])
    e = np.log(np.asarray(errors, float)[order])
    lt = math.log(target)
    for k in range(len(t) - 1):
        lo, hi = sorted((e[k], e[k + 1]))
        if lo <= lt <= hi and e[k] != e[k + 1]:
            return float(math.exp(t[k] + (lt - e[k]) * (t[k + 1] - t[k]) / (e[k + 1] - e[k])))
    return float("nan")


def time_ratio_curve(slow, fast, n=25):
    """Time ratio of two curves at equal error, over the errors both reach.

    *slow* and *fast* are (seconds, errors) pairs of sequences.  Returns (targets, ratios): *n*
    error targets spaced evenly in log(error) over the range both curves measured (the overlap
    of [min, max] of their errors), and at each the ratio ``time_at_error(slow) /
    time_at_error(fast)`` (:func:`time_at_error`; NaN where a curve is not monotonic enough to
    reach the target).  Empty arrays when the ranges do not overlap.

    For the peer comparison's "time to equal error" at every target, not at one
    (``paper/scripts/fig_peer.py``, ``numbers_peer.py``).

    Example
    -------
    >>> targets, ratios = time_ratio_curve(([2.0, 8.0], [0.4, 0.1]), ([1.0, 4.0], [0.4, 0.1]), n=3)
    >>> [round(float(x), 3) for x in targets], [round(float(r), 3) for r in ratios]
    ([0.1, 0.2, 0.4], [2.0, 2.0, 2.0])
    """
    (ts, es), (tf, ef) = slow, fast
    low = max(min(es), min(ef))
    high = min(max(es), max(ef))
    if not (low > 0 and high >= low):
        return np.array([]), np.array([])
    # a hair inside the overlap, so that rounding in exp(log(x)) never puts an end outside a curve
    targets = np.exp(np.linspace(math.log(low) + 1e-12, math.log(high) - 1e-12, n))
    ratios = np.array([time_at_error(ts, es, x) / time_at_error(tf, ef, x) for x in targets])
    return targets, ratios

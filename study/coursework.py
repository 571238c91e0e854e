"""The coursework's timing table 4.1, and our re-run of it.

The original C++/Qt ray tracer this project grew out of (called *the coursework* throughout)
timed its renderer at trace depths 1-10 on scenes with one, two and three bubbles (its table 4.1,
960×960, Apple M3 Pro), transcribed in the repository's ``data/coursework_table_4_1.csv``
(provenance in ``data/README.md``).  ``benchmarks/coursework_table.py`` re-runs that table with
our tracer and writes ``data/derived/coursework_table.csv``.

The loaders take the file's path: this installed module does not know where a checkout keeps
its data (the repository's scripts and notebooks name the files).  Units: depth is the trace
depth (an integer ≥ 1), times in seconds.
"""

from __future__ import annotations

import math

import numpy as np

from .results import read_commented_csv

__all__ = ["COURSEWORK_COLUMNS", "load_coursework_table", "load_timing", "timing_series", "timing_spread",
           "identical_work_check", "rays_per_level", "load_rays", "rays_series"]

#: Column of the coursework's table for each number of bubbles.
COURSEWORK_COLUMNS = {1: "one_bubble", 2: "two_bubbles", 3: "three_bubbles"}

_INT_COLUMNS = ("bubbles", "depth", "width", "height", "rays_camera", "rays_reflected", "rays_transmitted",
                "rays_shadow", "rays_total", "rays_level")
_MODES = ("pruned", "exhaustive")


def load_coursework_table(path):
    """The coursework's table 4.1: run time (s) against trace depth for 1, 2 and 3 bubbles.

    Source: the coursework's table 4.1 (960×960 PNG, Apple M3 Pro), transcribed in
    ``data/coursework_table_4_1.csv`` of the repository (provenance in ``data/README.md``).  The
    coursework fitted a fourth-degree polynomial to each column (its figure 4.1).

    Parameters
    ----------
    path : path of the CSV (columns ``depth`` and those of :data:`COURSEWORK_COLUMNS`).

    Returns
    -------
    dict with ``"depth"`` (int array, sorted), ``"seconds"`` (dict: number of bubbles -> float
    array of times in s, one per depth) and ``"notes"`` (the file's header comments, a list of
    str: machine, units argument).

    Example (run from the repository's root)
    -------------------------------------------
    >>> table = load_coursework_table("data/coursework_table_4_1.csv")
    >>> table["depth"].tolist()[:3], float(table["seconds"][3][-1])
    ([1, 2, 3], 1889.56)
    """
    notes, rows = read_commented_csv(path)
    depth = np.array([int(r["depth"]) for r in rows])
    order = np.argsort(depth)
    seconds = {nb: np.array([float(r[col]) for r in rows])[order] for nb, col in COURSEWORK_COLUMNS.items()}
    return {"depth": depth[order], "seconds": seconds, "notes": notes}


def _number(text, integer):
    text = (text or "").strip()
    if text == "":
        return None if integer else math.nan
    return int(float(text)) if integer else float(text)


def load_timing(path):
    """Our re-run of the coursework's table 4.1, as written by ``benchmarks/coursework_table.py``.

    The file (``data/derived/coursework_table.csv`` in the repository; regenerate with ``python
    benchmarks/coursework_table.py`` or ``make bench``) has one row per (bubbles, depth, mode)
    with mode ``"pruned"`` (the default threshold) or ``"exhaustive"`` (threshold 0: the
    coursework's full ray tree), and extra rows of other kinds (a fresh process timed from start
    to a saved image).  Its columns ``seed_seconds`` and ``speedup_vs_seed`` hold the
    coursework's times and our speed-up over them (names kept from the file's first version).

    Parameters
    ----------
    path : path of the CSV.

    Returns
    -------
    dict of column name -> numpy array over the pruned and exhaustive rows (``bubbles``,
    ``depth``, ``width``, ``height`` and the ``rays_*`` counts as int; ``mode`` as str; the
    other columns as float), plus ``"seconds_runs"`` (float array, rows × repeats, NaN-padded),
    ``"extra"`` (list of dicts: the other rows, numbers parsed, empty cells None/NaN) and
    ``"notes"`` (header comments).

    Example (run from the repository's root)
    -------------------------------------------
    >>> timing = load_timing("data/derived/coursework_table.csv")
    >>> sorted(set(timing["mode"].tolist()))
    ['exhaustive', 'pruned']
    """
    notes, rows = read_commented_csv(path)
    main = [r for r in rows if r["mode"] in _MODES]
    extra = [r for r in rows if r["mode"] not in _MODES]
    if not main:
        raise ValueError(f"{path}: no pruned or exhaustive rows")
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

    Example (run from the repository's root)
    -------------------------------------------
    >>> d, t = timing_series(load_timing("data/derived/coursework_table.csv"), 3, "exhaustive")
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


def timing_spread(timing, bubbles, mode):
    """``(depth, median, low, high)`` of one series of :func:`load_timing`: the median of the
    runs and their interquartile range (numpy's linear interpolation), sorted by depth.

    Why quartiles, not the fastest and slowest run: on a shared machine one run in nine can be
    disturbed by other work (a late, isolated slow run), and the extremes report that run; the
    quartiles need three of nine runs to move.  Computed from ``seconds_runs``, so files without
    quartile columns give them too.

    Example (run from the repository's root)
    -------------------------------------------
    >>> d, med, lo, hi = timing_spread(load_timing("data/derived/coursework_table.csv"), 1, "pruned")
    >>> bool(np.all((lo <= med) & (med <= hi)))
    True
    """
    depth, runs = timing_series(timing, bubbles, mode, "seconds_runs")
    low, median, high = np.nanpercentile(runs, [25, 50, 75], axis=1)
    return depth, median, low, high


def identical_work_check(timing, depth=1):
    """Cells doing identical work must agree: at depth 1 the pruned and the exhaustive tree are
    the same tree (camera rays only; they differ at most in shadow rays the threshold drops), so
    their times measure one workload twice.

    Returns a list of dicts, one per number of bubbles: ``bubbles``, ``pruned`` and
    ``exhaustive`` (medians, s), ``ratio`` (pruned / exhaustive median), ``overlap`` (True if
    the interquartile ranges of the two cells overlap) and ``rays_pruned`` /
    ``rays_exhaustive`` (the total ray counts, which show how identical the work is).  A cell
    whose quartile range misses its twin's was disturbed (or the work differs): the paper quotes
    no range from it without saying so.

    Example (run from the repository's root)
    -------------------------------------------
    >>> rows = identical_work_check(load_timing("data/derived/coursework_table.csv"))
    >>> [r["bubbles"] for r in rows]
    [1, 2, 3]
    """
    out = []
    for nb in sorted(set(timing["bubbles"].tolist())):
        cells = {}
        for mode in _MODES:
            d, med, lo, hi = timing_spread(timing, nb, mode)
            _, rays = timing_series(timing, nb, mode, "rays_total")
            i = int(np.flatnonzero(d == depth)[0])
            cells[mode] = (med[i], lo[i], hi[i], int(rays[i]))
        (pm, plo, phi, pr), (em, elo, ehi, er) = cells["pruned"], cells["exhaustive"]
        out.append(dict(bubbles=nb, pruned=float(pm), exhaustive=float(em), ratio=float(pm / em),
                        overlap=bool(plo <= ehi and elo <= phi), rays_pruned=pr, rays_exhaustive=er))
    return out


def rays_per_level(depth, secondary, camera):
    """Rays of each level of an exhaustive ray tree, from the tracer's cumulative counts.

    With threshold 0 the tree traced to depth *d* is the tree traced to depth *d* − 1 plus one
    more generation of rays, so the rays of level *d* (*d* ≥ 2) are the secondary rays
    (reflected + transmitted) counted at depth *d* minus those counted at depth *d* − 1; level 1
    is the camera rays.  (Shadow rays are not part of the tree's levels.)

    Parameters
    ----------
    depth : 1-D sequence of consecutive trace depths starting at 1.
    secondary : the reflected + transmitted rays of the render at each depth (cumulative).
    camera : the camera rays (the same at every depth).

    Returns
    -------
    int array of rays per level, one per depth.

    Example
    -------
    >>> rays_per_level([1, 2, 3, 4], [0, 2, 4, 8], 10).tolist()
    [10, 2, 2, 4]
    """
    depth = np.asarray(depth)
    secondary = np.asarray(secondary, dtype=np.int64)
    if depth.ndim != 1 or depth.shape != secondary.shape or depth.size == 0:
        raise ValueError("depth and secondary must be 1-D of equal, non-zero length")
    if depth[0] != 1 or np.any(np.diff(depth) != 1):
        raise ValueError(f"depth must be consecutive from 1 (got {depth.tolist()})")
    if secondary[0] != 0:
        raise ValueError(f"a depth-1 tree has no secondary rays (got {int(secondary[0])})")
    level = np.diff(secondary, prepend=0)
    if np.any(level < 0):
        raise ValueError("the secondary-ray counts must not decrease with depth (an exhaustive tree, threshold 0)")
    level[0] = int(camera)
    return level


def load_rays(path):
    """Rays per level and run times of ``benchmarks/coursework_rays.py`` (``data/derived/coursework_rays.csv``).

    Returns a dict of column name -> numpy array (``model`` as str, counts as int, the others
    float; an empty ``branching`` cell is NaN), plus ``seconds_runs`` (rows × repeats) and
    ``notes``.

    Example (run from the repository's root)
    -------------------------------------------
    >>> rays = load_rays("data/derived/coursework_rays.csv")
    >>> sorted(set(rays["model"].tolist()))
    ['thin film', 'two spheres']
    """
    notes, rows = read_commented_csv(path)
    if not rows:
        raise ValueError(f"{path}: no rows")
    out = {}
    for name in rows[0]:
        if name in ("model", "seconds_runs"):
            continue
        integer = name in _INT_COLUMNS
        out[name] = np.array([_number(r[name], integer) for r in rows], dtype=int if integer else float)
    out["model"] = np.array([r["model"] for r in rows])
    runs = [[float(v) for v in r["seconds_runs"].split()] for r in rows]
    width = max(len(v) for v in runs)
    out["seconds_runs"] = np.array([v + [math.nan] * (width - len(v)) for v in runs])
    out["notes"] = notes
    return out


def rays_series(rays, model, bubbles, column="rays_level"):
    """``(depth, values)`` of one column of :func:`load_rays`' result, sorted by depth."""
    pick = (rays["model"] == model) & (rays["bubbles"] == bubbles)
    if not pick.any():
        raise ValueError(f"no rows for model {model!r}, {bubbles} bubble(s)")
    depth = rays["depth"][pick]
    order = np.argsort(depth)
    return depth[order], np.asarray(rays[column])[pick][order]

"""What the benchmark scripts share: the one writer of their result CSVs (``data/derived/*.csv``)
and the one timing loop (:func:`wall_times`).

Every benchmark script writes its table through :func:`write_csv`: atomically (a temporary file
in the same directory, then :func:`os.replace`, so a reader never sees half a file and an
interrupted run leaves the previous file intact), with the provenance comment line(s) first
(``# written by benchmarks/x.py on <date> ...``), then a ``csv.DictWriter`` header and the rows.

Readers (``paper/scripts/make_numbers.py``, ``paper/scripts/fig_*.py``, the notebooks) go through
:func:`tracer.study.read_commented_csv`, which drops the lines starting with ``#`` and hands the
rest to ``csv.DictReader``; the
exceptions, ``paper/scripts/fig_stability.py`` and ``benchmarks/stability.py``'s ``read_csv``,
take the first line as the header, so the stability files are written without a comment.

Byte layout, kept from the scripts' earlier private writers so that regenerated files differ
from the committed ones only in their numbers and date: comment lines end in ``\\n``, the header
and rows in *lineterminator* (``\\r\\n``, the :mod:`csv` default, unless a script asks for
``\\n``).

Scripts run as ``python benchmarks/x.py`` have ``benchmarks/`` on ``sys.path``; scripts loaded
by file path (the notebooks' ``load_by_path``) do not, so each script appends it before importing
this module.
"""

import csv
import math
import os
import time
from pathlib import Path

__all__ = ["write_csv", "wall_times"]


def wall_times(func, repeats, warmup=1):
    """Wall times (s, :func:`time.perf_counter`) of *repeats* calls of *func*, after *warmup*
    untimed calls (compilation, thread pools, page faults)."""
    for _ in range(warmup):
        func()
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        func()
        times.append(time.perf_counter() - t0)
    return times


def _formatter(float_format, na_rep):
    """A function turning one cell value into what the csv writer gets."""
    if float_format is None:
        fmt = float.__repr__  # shortest round-trip, as csv writes a float itself (also for np.float64)
    elif callable(float_format):
        fmt = float_format
    else:
        fmt = float_format.format

    def cell(value):
        if isinstance(value, float):  # includes np.float64; ints, strings, None pass through
            if na_rep is not None and math.isnan(value):
                return na_rep
            return fmt(value)
        return value

    return cell


def write_csv(path, rows, comment, fieldnames=None, float_format="{:.4g}", *, na_rep=None,
              lineterminator="\r\n", restval="", extrasaction="raise"):
    """Write *rows* (dicts) to *path* atomically, provenance comment first; return the path.

    Parameters
    ----------
    path : where to write (its folder is created if needed).
    rows : iterable of dicts, one per row.
    comment : the provenance line written as ``# <comment>``; a list or tuple of strings gives
        one ``#`` line each (a string with line breaks is split, each part its own ``#`` line);
        ``None`` writes none (only for files whose readers cannot skip one).
    fieldnames : column order (default: the keys of the first row).
    float_format : how to write values that are ``float`` instances (including ``np.float64``): a
        ``str.format`` pattern with one field (default ``"{:.4g}"``), a callable, or ``None`` for
        the shortest round-trip representation (what :mod:`csv` writes by itself).  Other values
        are left to :mod:`csv` (``str``; ``None`` becomes empty).
    na_rep : if given, what a NaN float is written as (e.g. ``""``); default: formatted like any
        float (``nan``).
    lineterminator : ending of the header and data lines (comment lines end in ``\\n``).
    restval, extrasaction : as in :class:`csv.DictWriter` (missing keys are written as
        *restval*; ``"ignore"`` drops keys that are not in *fieldnames*).
    """
    path = Path(path)
    rows = list(rows)
    if fieldnames is None:
        if not rows:
            raise ValueError(f"{path}: no rows and no fieldnames")
        fieldnames = list(rows[0])
    if comment is None:
        comments = []
    elif isinstance(comment, str):
        comments = [comment]
    else:
        comments = list(comment)
    comments = [part for line in comments for part in str(line).splitlines() or [""]]  # '#' on every line
    cell = _formatter(float_format, na_rep)

    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")  # same folder: os.replace is atomic
    try:
        with open(tmp, "w", newline="", encoding="utf-8") as fh:
            for line in comments:
                fh.write(f"# {line}\n")
            writer = csv.DictWriter(fh, fieldnames=fieldnames, restval=restval, extrasaction=extrasaction,
                                    lineterminator=lineterminator)
            writer.writeheader()
            for row in rows:
                writer.writerow({k: cell(v) for k, v in row.items()})
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return path

"""The benchmarks' result files: the one writer, the one reader, and the one timing loop.

Every benchmark (``benchmarks/*.py``) writes its table into ``data/derived/`` through
:func:`write_csv`: atomically (a temporary file in the same folder, then :func:`os.replace`, so a
reader never sees half a file and an interrupted run leaves the previous file intact), with
provenance comment lines first (``# written by benchmarks/x.py on DATE (machine, N cores, Python
X.Y.Z)...``, from :func:`provenance`), then a :class:`csv.DictWriter` header and the rows.

Every reader (the paper's scripts, the notebooks, the benchmarks themselves) goes through
:func:`read_commented_csv`, which drops the lines starting with ``#`` and hands the rest to
:class:`csv.DictReader`; :func:`read_columns` gives the same file as NumPy columns (and
:func:`rows_to_columns` rows computed in memory).  A file
without comment lines reads the same way.

Byte layout, fixed so that regenerated files differ from the committed ones only in their
numbers and date: comment lines end in ``\\n``, the header and
rows in *lineterminator* (``\\r\\n``, the :mod:`csv` default, unless a script asks for ``\\n``).

Nothing here knows where the repository's files are: every function takes its path.
"""

from __future__ import annotations

import csv
import datetime
import math
import os
import platform
import time
from pathlib import Path

import numpy as np

__all__ = ["read_commented_csv", "read_columns", "rows_to_columns", "write_csv", "provenance", "cpu_model", "wall_times",
           "image_benchmark_arguments"]


def read_commented_csv(path):
    """``(notes, rows)`` of a CSV whose leading lines may be ``#`` comments.

    *notes*: the comment lines without their ``#`` and surrounding blanks (a list of str, empty
    when the file has none); *rows*: the other lines as dicts of str (:class:`csv.DictReader`).
    Blank lines are skipped.

    Example
    -------
    >>> import tempfile
    >>> path = Path(tempfile.mkdtemp()) / "t.csv"
    >>> _ = path.write_text("# written by me\\na,b\\n1,x\\n")
    >>> read_commented_csv(path)
    (['written by me'], [{'a': '1', 'b': 'x'}])
    """
    lines = Path(path).read_text(encoding="utf-8").splitlines()
    notes = [ln.lstrip("#").strip() for ln in lines if ln.startswith("#")]
    rows = list(csv.DictReader(ln for ln in lines if ln.strip() and not ln.startswith("#")))
    return notes, rows


def rows_to_columns(rows):
    """Rows (dicts, as read from a file or as computed) as a dict of NumPy columns: float where
    every value of the column is a number or parses as one (``nan`` included), str otherwise.

    Example
    -------
    >>> columns = rows_to_columns([{"a": 1, "b": "x"}, {"a": "nan", "b": "y"}])
    >>> columns["a"].tolist()[0], columns["b"].tolist()
    (1.0, ['x', 'y'])
    """
    rows = list(rows)
    if not rows:
        raise ValueError("no rows")
    out = {}
    for name in rows[0]:
        values = [r[name] for r in rows]
        try:
            out[name] = np.array([float(v) for v in values])
        except (TypeError, ValueError):
            out[name] = np.array(values)
    return out


def read_columns(path):
    """The rows of :func:`read_commented_csv` as NumPy columns (:func:`rows_to_columns`).

    Example
    -------
    >>> import tempfile
    >>> path = Path(tempfile.mkdtemp()) / "t.csv"
    >>> _ = path.write_text("a,b\\n1,x\\nnan,y\\n")
    >>> read_columns(path)["b"].tolist()
    ['x', 'y']
    """
    _, rows = read_commented_csv(path)
    if not rows:
        raise ValueError(f"{path}: no rows")
    return rows_to_columns(rows)


def cpu_model(cpuinfo="/proc/cpuinfo"):
    """The CPU's model as the machine names it: the first ``model name`` of *cpuinfo* (Linux), with
    its ``cpu family`` and ``model`` numbers, which identify a CPU whose name a virtual machine
    shortens ("AMD EPYC"); where there is no such file, :func:`platform.processor`; ``""`` when
    neither says.  Semicolons become commas (the header separates its parts with ``; ``).

    Example
    -------
    >>> import tempfile
    >>> with tempfile.NamedTemporaryFile("w", suffix=".txt", delete=False) as f:
    ...     _ = f.write(chr(10).join(["processor: 0", "cpu family: 25", "model: 17", "model name: AMD EPYC"]))
    >>> cpu_model(f.name)
    'AMD EPYC (family 25, model 17)'
    >>> os.remove(f.name)
    """
    fields = {}
    try:
        with open(cpuinfo, encoding="utf-8", errors="replace") as lines:
            for line in lines:
                key, sep, value = line.partition(":")
                if not sep:
                    if fields:  # the end of the first processor's block
                        break
                    continue
                fields.setdefault(key.strip(), " ".join(value.split()))
    except OSError:
        fields = {}
    name = fields.get("model name", "")
    if name and fields.get("cpu family") and fields.get("model"):
        name = f"{name} (family {fields['cpu family']}, model {fields['model']})"
    return (name or platform.processor() or "").replace(";", ",")


def provenance(script, *details):
    """The first comment line of a result file: ``written by SCRIPT on DATE (MACHINE, N cores,
    Python X.Y.Z); CPU MODEL``, then each of *details* after ``; ``.

    *script*: how to name the writer (``"benchmarks/optics_speed.py"``).  The machine is
    :func:`platform.processor` or, where that is empty, :func:`platform.machine`; the CPU model
    :func:`cpu_model` (the ``; CPU`` part is left out where the machine does not say).  The paper's
    numbers read the date, the ``(machine, N cores`` part and the CPU model back from this line.

    Example
    -------
    >>> provenance("benchmarks/x.py", "regenerate with: python benchmarks/x.py")  # doctest: +ELLIPSIS
    'written by benchmarks/x.py on ... cores, Python ...); regenerate with: python benchmarks/x.py'
    """
    machine = platform.processor() or platform.machine()
    head = (f"written by {script} on {datetime.date.today()} ({machine}, {os.cpu_count()} cores, "
            f"Python {platform.python_version()})")
    cpu = cpu_model()
    return "; ".join([head, *([f"CPU {cpu}"] if cpu else []), *details])


def image_benchmark_arguments(description, out, repeats, quick_repeats, argv=None, size=960, quick_size=240):
    """The command line the image benchmarks share: ``[--repeats N] [--quick] [--out PATH]``.

    Returns ``(args, size, repeats)``: the image size and number of repeats to use (*quick_size*
    and *quick_repeats* with ``--quick``, a smoke test).

    Example
    -------
    >>> args, size, repeats = image_benchmark_arguments("x", Path("o.csv"), 7, 2, argv=["--quick"])
    >>> size, repeats, args.out.name
    (240, 2, 'o.csv')
    """
    import argparse

    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--repeats", type=int, default=repeats)
    parser.add_argument("--quick", action="store_true",
                        help=f"{quick_size}x{quick_size}, {quick_repeats} repeat(s) (smoke test)")
    parser.add_argument("--out", type=Path, default=out)
    args = parser.parse_args(argv)
    if args.quick:
        return args, quick_size, quick_repeats
    return args, size, args.repeats


def wall_times(func, repeats, warmup=1):
    """Wall times (s, :func:`time.perf_counter`) of *repeats* calls of *func*, after *warmup*
    untimed calls (compilation, thread pools, page faults).

    Example
    -------
    >>> times = wall_times(lambda: sum(range(1000)), 3)
    >>> len(times), all(t > 0 for t in times)
    (3, True)
    """
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
    comment : the provenance line written as ``# <comment>`` (:func:`provenance` makes the
        first one); a list or tuple of strings gives one ``#`` line each (a string with line
        breaks is split, each part its own ``#`` line); ``None`` writes none.
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

    Example
    -------
    >>> import tempfile
    >>> path = write_csv(Path(tempfile.mkdtemp()) / "t.csv", [{"a": 1, "b": 0.123456}], "by me")
    >>> path.read_bytes()
    b'# by me\\na,b\\r\\n1,0.1235\\r\\n'
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

"""The helpers the ``numbers_*.py`` plug-ins of ``make_numbers.py`` share: number formats and the
benchmarks' CSV headers.

Number formats: :func:`significant` (plain decimals, thousands separated by a thin space),
:func:`scientific` (``a\\times10^{k}``, wrapped in ``\\ensuremath`` so a macro works in text and
in mathematics), :func:`plain` (a constant as the code writes it) and :data:`NA`, the text of a
number that could not be computed.  Inputs: :func:`read_commented_csv` and the machine, date and
load average that a benchmark writes in its header comments.
"""

from __future__ import annotations

import math
import re

from study import read_commented_csv as _read_commented_csv

NA = r"\NumberNA{}"

#: the coursework's bubble counts, as words of macro names
WORDS = {1: "One", 2: "Two", 3: "Three"}


# ------------------------------------------------------------------------------------------
# formatting
# ------------------------------------------------------------------------------------------
def group_digits(digits: str) -> str:
    """'1458000' -> '1\\,458\\,000' (thin spaces between groups of three, from 10 000 on)."""
    if len(digits) <= 4:
        return digits
    head = len(digits) % 3 or 3
    parts = [digits[:head]] + [digits[i : i + 3] for i in range(head, len(digits), 3)]
    return r"\,".join(parts)


def significant(x: float, n: int = 2, min_decimals: int = 0) -> str:
    """*x* rounded to *n* significant digits, as plain decimals (no exponent).

    >>> significant(195.28, 3), significant(31.97), significant(54771.9), significant(0.0019988 * 1000)
    ('195', '32', '55\\\\,000', '2.0')
    """
    x = float(x)
    if not math.isfinite(x):
        return NA
    if x == 0:
        return "0"
    exponent = math.floor(math.log10(abs(x)))
    rounded = round(x, n - 1 - exponent)
    if rounded and abs(rounded) >= 10.0 ** (exponent + 1):  # 0.0999 -> 0.10, not 0.100
        exponent += 1
    decimals = max(n - 1 - exponent, min_decimals, 0)
    text = f"{abs(rounded):.{decimals}f}"
    whole, _, frac = text.partition(".")
    out = group_digits(whole) + ("." + frac if frac else "")
    return ("-" if rounded < 0 else "") + out


def scientific(x: float, n: int = 2) -> str:
    """*x* as ``a\\times10^{k}`` with *n* significant digits (``10^{k}`` when a = 1).

    >>> scientific(8.48e-14), scientific(1e-12), scientific(0.0084722)
    ('\\\\ensuremath{8.5\\\\times10^{-14}}', '\\\\ensuremath{10^{-12}}', '\\\\ensuremath{8.5\\\\times10^{-3}}')
    """
    x = float(x)
    if not math.isfinite(x):
        return NA
    if x == 0:
        return "0"
    mantissa, _, exponent = f"{x:.{n - 1}e}".partition("e")
    k = int(exponent)
    if float(mantissa) == 1.0:
        return rf"\ensuremath{{10^{{{k}}}}}"
    if float(mantissa) == -1.0:
        return rf"\ensuremath{{-10^{{{k}}}}}"
    return rf"\ensuremath{{{mantissa}\times10^{{{k}}}}}"


def plain(x: float) -> str:
    """A constant as the code writes it, shortest form ('5', '0.42', '1400'; ``format(x, 'g')``)."""
    return format(float(x), "g")


def sci_or_plain(x: float, n: int = 2) -> str:
    """Plain decimals between 0.01 and 10 000, scientific otherwise."""
    return significant(x, n) if 0.01 <= abs(float(x)) < 1e4 else scientific(x, n)


# ------------------------------------------------------------------------------------------
# inputs
# ------------------------------------------------------------------------------------------
def read_commented_csv(path):
    """(header comments, rows as dicts) of a benchmark's CSV (:func:`study.read_commented_csv`);
    a file without rows is an error."""
    notes, rows = _read_commented_csv(path)
    if not rows:
        raise ValueError(f"{path}: no rows")
    return notes, rows


def machine_of(notes):
    """'x86_64, 2 cores' from a benchmark's header comment '... (x86_64, 2 cores, Python ...)'."""
    for note in notes:
        m = re.search(r"\(([^,()]+), (\d+) cores?", note)
        if m:
            return f"{m.group(1)}, {m.group(2)} cores".replace("_", r"\_")
    raise ValueError("no machine description in the header comments")


def date_of(notes):
    """'2026-12-02': the date in a benchmark's header comments."""
    for note in notes:
        m = re.search(r"\b(\d{4}-\d{2}-\d{2})\b", note)
        if m:
            return m.group(1)
    raise ValueError("no date in the header comments")


def load_average_of(notes):
    """(before, after) from the benchmark's 'machine load average X before, Y after' note."""
    for note in notes:
        m = re.search(r"load average ([\d.]+) before, ([\d.]+) after", note)
        if m:
            return m.group(1), m.group(2)
    raise ValueError("no machine load in the header comments")


def to_float(text):
    """A CSV cell as a float, NaN when it is empty or not a number."""
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def thick_film_range_um(path):
    """(thinnest, thickest) film in µm of a TOML scene's bubbles (uniform and draining films)."""
    import tomllib

    values = []
    for b in tomllib.loads(path.read_text(encoding="utf-8")).get("bubbles", []):
        film = b.get("film", {})
        values += [float(film[k]) for k in ("thickness_nm", "top_nm", "bottom_nm") if k in film]
    return min(values) / 1e3, max(values) / 1e3


"""The helpers the ``numbers_*.py`` plug-ins of ``make_numbers.py`` share: number formats and the
benchmarks' CSV headers.

Number formats: :func:`significant` (plain decimals, thousands separated by a thin space),
:func:`scientific` (``a\\times10^{k}``, wrapped in ``\\ensuremath`` so a macro works in text and
in mathematics), :func:`plain` (a constant as the code writes it) and :data:`NA`, the text of a
number that could not be computed.

Bounds: a number the text quotes after "at least", "more than", ... is rounded *down*
(:func:`at_least`), one after "up to", "at most", "below", "within", ... *up* (:func:`up_to`, also
called :func:`at_most`), so that rounding never makes a bound false ("at least 310" for 305.29).
Their text is a :class:`Bound`, a ``str`` that remembers the unrounded value and the direction;
:func:`plain` returns one too, with direction ``"exact"`` (a setting, not a measurement).
``tests/paper/test_paper_bounds.py`` finds every macro that follows a bound phrase in the paper
and checks it against the value it was computed from.

Inputs: :func:`read_commented_csv` and the machine, date, load average and CPU model that a
benchmark writes in its header comments.
"""

from __future__ import annotations

import math
import re
from fractions import Fraction

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
    """A constant as the code writes it, shortest form ('5', '0.42', '1400'; ``format(x, 'g')``),
    as a :class:`Bound` with direction ``"exact"``: a setting may follow "up to" unrounded.

    >>> plain(0.42), plain(1400.0).direction
    ('0.42', 'exact')
    """
    return Bound(format(float(x), "g"), x, "exact")


def sci_or_plain(x: float, n: int = 2) -> str:
    """Plain decimals between 0.01 and 10 000, scientific otherwise."""
    return significant(x, n) if 0.01 <= abs(float(x)) < 1e4 else scientific(x, n)


# ------------------------------------------------------------------------------------------
# bounds: rounded in the direction that keeps them true
# ------------------------------------------------------------------------------------------
class Bound(str):
    """The LaTeX text of a number that states a bound, with ``raw``, the value it was computed
    from (unrounded), and ``direction``: ``"lower"`` (the text's number is at most ``raw``: "at
    least"), ``"upper"`` (at least ``raw``: "up to", "below") or ``"exact"`` (a setting, written as
    the code has it).  It is a ``str`` everywhere else (``numbers.tex`` gets its text).

    >>> b = at_least(305.29, 2)
    >>> b, b.raw, b.direction, b + "x"
    ('300', 305.29, 'lower', '300x')
    """

    def __new__(cls, text, raw, direction):
        if direction not in ("lower", "upper", "exact"):
            raise ValueError(f"direction {direction!r}: 'lower', 'upper' or 'exact'")
        self = super().__new__(cls, text)
        self.raw, self.direction = float(raw), direction
        return self

    def __reduce__(self):  # pickles (and copies) as a Bound, not as a plain str
        return (Bound, (str(self), self.raw, self.direction))


def _directed_digits(x: float, n: int, direction: str):
    """(sign, integer m, exponent k): *x* rounded to *n* significant digits towards minus
    infinity ("lower") or plus infinity ("upper"), as sign * m * 10**k with 10**(n-1) <= m < 10**n.
    Exact (fractions), so the result is the tightest such number on the right side of *x*.

    *x* is taken as the shortest decimal that reads back as the same float (``repr(x)``), the
    number a CSV cell ``0.147`` means: 0.147 stays 0.147 at three digits either way, where the
    float's binary value (0.14699999...) would round down to 0.146.  The float of the text is
    still on the right side of *x* (rounding a decimal to the nearest float is monotonic)."""
    if n < 1:
        raise ValueError(f"n = {n}: at least one significant digit")
    value = Fraction(repr(x))  # the shortest decimal of the float
    size = abs(value)
    exponent = math.floor(math.log10(abs(x)))  # may be off by one near a power of ten: fixed below
    while Fraction(10) ** exponent > size:
        exponent -= 1
    while Fraction(10) ** (exponent + 1) <= size:
        exponent += 1
    k = exponent - n + 1
    scaled = value / Fraction(10) ** k
    m = math.floor(scaled) if direction == "lower" else math.ceil(scaled)
    if m == 0:  # cannot happen (|scaled| >= 10**(n-1)); kept as a guard
        raise AssertionError((x, n, direction))
    sign, m = (-1 if m < 0 else 1), abs(m)
    if m == 10 ** n:  # 0.0999 up to two digits -> 0.10, not 0.100 (one digit carried)
        m, k = m // 10, k + 1
    return sign, m, k


def _decimal_text(m: int, k: int, min_decimals: int = 0) -> str:
    """m * 10**k in plain decimals (m >= 0), thousands grouped as :func:`significant` does."""
    digits = str(m)
    if k >= 0:
        whole, frac = digits + "0" * k, ""
    else:
        digits = digits.rjust(-k + 1, "0")
        whole, frac = digits[:k], digits[k:]
    frac = frac.ljust(min_decimals, "0")
    return group_digits(whole) + ("." + frac if frac else "")


def directed(x: float, n: int = 2, direction: str = "lower", min_decimals: int = 0, form: str = "plain",
             decimals: int | None = None) -> str:
    """*x* rounded to *n* significant digits towards minus infinity (*direction* ``"lower"``) or
    plus infinity (``"upper"``), as a :class:`Bound`: :func:`at_least` and :func:`up_to`.
    With *decimals*, to that many decimals instead (plain form; *n* is then ignored).

    *form*: ``"plain"`` decimals as :func:`significant` writes them (thousands grouped, *min_decimals*
    padded with zeros), ``"scientific"`` as :func:`scientific`, ``"auto"`` as :func:`sci_or_plain`
    chooses.  Zero is ``'0'``; NaN and infinities are :data:`NA` (a plain ``str``).

    >>> directed(0.147, 1, "upper"), directed(-0.147, 1, "upper"), directed(-0.147, 1, "lower")
    ('0.2', '-0.1', '-0.2')
    >>> directed(2.8001, direction="upper", decimals=1), directed(-0.04, direction="upper", decimals=1)
    ('2.9', '0.0')
    >>> directed(0.147, 3, "lower"), directed(0.1, 2, "upper"), directed(1e7, 1, "upper")
    ('0.147', '0.10', '10\\\\,000\\\\,000')
    >>> directed(8.41e-14, 2, "upper", form="scientific"), directed(0.99e-12, 1, "upper", form="scientific")
    ('\\\\ensuremath{8.5\\\\times10^{-14}}', '\\\\ensuremath{10^{-12}}')
    """
    x = float(x)
    if direction not in ("lower", "upper"):
        raise ValueError(f"direction {direction!r}: 'lower' or 'upper'")
    if not math.isfinite(x):
        return NA
    if form == "auto":
        form = "plain" if 0.01 <= abs(x) < 1e4 else "scientific"
    if decimals is not None:
        if decimals < 0:
            raise ValueError(f"decimals = {decimals}: zero or more")
        scaled = Fraction(repr(x)) * Fraction(10) ** decimals
        m = math.floor(scaled) if direction == "lower" else math.ceil(scaled)
        text = _decimal_text(abs(m), -decimals, min_decimals) if decimals > 0 else _decimal_text(abs(m), 0)
        return Bound(("-" if m < 0 else "") + text, x, direction)
    if x == 0:
        return Bound("0", x, direction)
    sign, m, k = _directed_digits(x, n, direction)
    minus = "-" if sign < 0 else ""
    if form == "plain":
        return Bound(minus + _decimal_text(m, k, min_decimals), x, direction)
    if form != "scientific":
        raise ValueError(f"form {form!r}: 'plain', 'scientific' or 'auto'")
    power = k + len(str(m)) - 1
    if m == 10 ** (len(str(m)) - 1):  # a mantissa of 1: 10^{k}, as scientific() writes it
        return Bound(rf"\ensuremath{{{minus}10^{{{power}}}}}", x, direction)
    mantissa = _decimal_text(m, -(len(str(m)) - 1))
    return Bound(rf"\ensuremath{{{minus}{mantissa}\times10^{{{power}}}}}", x, direction)


def at_least(x: float, n: int = 2, min_decimals: int = 0, form: str = "plain", decimals: int | None = None) -> str:
    """*x* rounded DOWN to *n* significant digits, for "at least", "more than", "exceeds", ...:
    the text is never more than *x* (towards minus infinity, so -1.23 gives -1.3).

    >>> at_least(305.29, 2), at_least(0.0999, 2), at_least(54771.9), at_least(-1.23), at_least(0.0)
    ('300', '0.099', '54\\\\,000', '-1.3', '0')
    >>> at_least(float("nan"))
    '\\\\NumberNA{}'
    """
    return directed(x, n, "lower", min_decimals, form, decimals)


def up_to(x: float, n: int = 2, min_decimals: int = 0, form: str = "plain", decimals: int | None = None) -> str:
    """*x* rounded UP to *n* significant digits, for "up to", "at most", "below", "within", ...:
    the text is never less than *x* (towards plus infinity, so -1.27 gives -1.2).

    >>> up_to(0.147, 1), up_to(0.147), up_to(0.0999, 2), up_to(9.96, 2), up_to(-1.27), up_to(2.0, 2, 1)
    ('0.2', '0.15', '0.10', '10', '-1.2', '2.0')
    >>> up_to(54771.9, 3), up_to(1000.0001, 1)
    ('54\\\\,800', '2000')
    """
    return directed(x, n, "upper", min_decimals, form, decimals)


#: "at most X" is "up to X"
at_most = up_to


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
    """The machine of a benchmark's header comment: its CPU model and cores where the header names
    the model (:func:`cpu_model_of`), else the architecture and cores of '... (x86_64, 2 cores, Python ...)'.

    >>> machine_of(["written by b.py on 2026-12-02 (x86_64, 2 cores, Python 3.11.7); load 1"])
    'x86\\\\_64, 2 cores'
    >>> machine_of(["written by b.py on 2026-12-07 (x86_64, 2 cores, Python 3.11.7); CPU AMD EPYC (family 25, model 1); x"])
    'AMD EPYC (family 25, model 1), 2 cores'
    """
    for note in notes:
        m = re.search(r"\(([^,()]+), (\d+) cores?", note)
        if m:
            try:
                where = cpu_model_of(notes)
            except ValueError:
                where = m.group(1).replace("_", r"\_")
            return f"{where}, {m.group(2)} cores"
    raise ValueError("no machine description in the header comments")


def cpu_model_of(notes):
    """The CPU model of a benchmark's header comment '...; CPU AMD EPYC (family 25, model 17); ...'
    (:func:`study.provenance` writes it), as LaTeX text: '(R)' and '(TM)' dropped, TeX's special
    characters escaped.

    >>> cpu_model_of(["written by b.py on 2026-12-04 (x86_64, 2 cores, Python 3.11.7); CPU Intel(R) Xeon(R) CPU @ 2.20GHz; x"])
    'Intel Xeon CPU @ 2.20GHz'
    """
    for note in notes:
        m = re.search(r"(?:^|; )CPU ([^;]+)", note)
        if m:
            name = re.sub(r"\((?:R|TM|tm)\)", "", m.group(1))
            name = " ".join(name.split())
            return re.sub(r"([&%$#_{}])", r"\\\1", name).replace("~", r"\textasciitilde{}").replace("^", r"\^{}")
    raise ValueError("no CPU model in the header comments")


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


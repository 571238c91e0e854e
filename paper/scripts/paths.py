"""Where the paper's figure scripts read and write, and in which mode they run.

Every script beside this module (``fig_*.py``, ``table_coursework.py``, ``make_numbers.py``)
imports it as ``import paths``: Python puts a running script's own folder first on its module
search path, so that works when a script is run as ``python paper/scripts/fig_X.py``.  The
scripts read their inputs only from ``DATA``/``DERIVED`` and write only into ``FIGURES``; this
is the one place that knows where the repository keeps its files (the analysis they call,
:mod:`study`, takes paths).

* ``ROOT``: the repository; ``DATA``: ``data/`` (inputs with provenance, ``data/README.md``);
  ``DERIVED``: ``data/derived/`` (benchmark outputs; each file names the command that
  regenerates it).
* ``FIGURES``: ``paper/figures/``, or the folder named by the environment variable
  ``BUBBLEOPTICS_FIGURES_DIR`` (used by the tests to write into a temporary folder).  It is
  created on demand by :func:`figures_dir`, never at import.
* Quick mode (coarser grids, same figures): ``--quick`` on a script's command line or
  ``BUBBLEOPTICS_QUICK=1`` in the environment (``make_figures.py --quick`` sets the latter).
"""

from __future__ import annotations

import argparse
import os
import re
from pathlib import Path

__all__ = ["ROOT", "DATA", "DERIVED", "COURSEWORK_TABLE", "TIMING", "FIGURES", "PAPER", "figures_dir", "parse_args",
           "paper_source"]

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "data"
DERIVED = DATA / "derived"
PAPER = ROOT / "paper"

#: The coursework's table 4.1 (transcribed; provenance in data/README.md).
COURSEWORK_TABLE = DATA / "coursework_table_4_1.csv"
#: Our re-run of it, written by benchmarks/coursework_table.py.
TIMING = DERIVED / "coursework_table.csv"

FIGURES = Path(os.environ.get("BUBBLEOPTICS_FIGURES_DIR") or ROOT / "paper" / "figures").resolve()


def figures_dir() -> Path:
    """``FIGURES``, created if missing."""
    FIGURES.mkdir(parents=True, exist_ok=True)
    return FIGURES


_INPUT = re.compile(r"\\input\{((?:sections/)?[A-Za-z0-9_]+)\}")


def paper_source(paper=None) -> str:
    """The text of ``paper.tex`` with its ``\\input{preamble}`` and every ``\\input{sections/NAME}``
    replaced by that file (one level; the sections input nothing), as LaTeX reads it, followed by
    the document body of ``supplement.tex`` (from its ``\\begin{document}``, expanded the same way)
    when there is one: what the tests scan for typed numbers, macros and figure slots in both PDFs.
    A missing input file is an error naming it (``numbers`` is the generated macro file, left as is)."""
    folder = Path(paper) if paper is not None else PAPER

    def expand(match):
        if match.group(1) == "numbers":
            return match.group(0)
        path = folder / f"{match.group(1)}.tex"
        if not path.exists():
            raise FileNotFoundError(f"paper.tex inputs {match.group(1)}, but {path} does not exist")
        return path.read_text(encoding="utf-8")

    text = _INPUT.sub(expand, (folder / "paper.tex").read_text(encoding="utf-8"))
    supplement = folder / "supplement.tex"
    if supplement.exists():
        body = supplement.read_text(encoding="utf-8")
        body = body[body.find("\\begin{document}"):] if "\\begin{document}" in body else body
        text += "\n" + _INPUT.sub(expand, body)
    return text


def parse_args(description: str, argv=None) -> argparse.Namespace:
    """The figure scripts' command line: ``[--quick]``; ``quick`` is also on with BUBBLEOPTICS_QUICK."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--quick", action="store_true", help="coarser grids (also: BUBBLEOPTICS_QUICK=1)")
    args = parser.parse_args(argv)
    args.quick = args.quick or os.environ.get("BUBBLEOPTICS_QUICK", "") not in ("", "0")
    return args

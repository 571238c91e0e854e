"""The paper's own paths module (``paper/scripts/paths.py``), loaded by file for the paper tests.

``source()`` is the text LaTeX reads: ``paper.tex`` with its ``\\input{sections/...}`` files
expanded (:func:`paths.paper_source`), so the tests scan every section, not only the skeleton.
"""

import importlib.util
from pathlib import Path

PAPER = Path(__file__).resolve().parents[1] / "paper"


def _paths_module():
    spec = importlib.util.spec_from_file_location("_paper_paths", PAPER / "scripts" / "paths.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def source(paper=PAPER):
    """paper.tex with its sections expanded."""
    return _paths_module().paper_source(paper)

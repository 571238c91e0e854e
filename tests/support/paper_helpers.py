"""The paper's own paths module (``paper/scripts/paths.py``), loaded by file for the paper tests.

``source()`` is the text LaTeX reads: ``paper.tex`` with its ``\\input{sections/...}`` files
expanded (:func:`paths.paper_source`), so the tests scan every section, not only the skeleton.
``quick_figures()`` runs ``make_figures.py --quick`` once per test session, shared by the
pytest-xdist workers (a lock file in the session's temporary folder), for the two test modules
that need every figure.
"""

import fcntl
import importlib.util
import os
import subprocess
import sys
from pathlib import Path

PAPER = Path(__file__).resolve().parents[2] / "paper"


def _paths_module():
    spec = importlib.util.spec_from_file_location("_paper_paths", PAPER / "scripts" / "paths.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def source(paper=PAPER):
    """paper.tex with its sections expanded."""
    return _paths_module().paper_source(paper)


def _session_folder(tmp_path_factory):
    """The temporary folder of this test session that every xdist worker sees (each worker's own
    base folder is one level below it); without xdist, the session's base folder itself."""
    base = tmp_path_factory.getbasetemp()
    return base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base


def quick_figures(tmp_path_factory):
    """``(folder, returncode, output)`` of one ``make_figures.py --quick`` into a temporary folder,
    run by the first test that asks in this session and reused by the others (they wait for it)."""
    root = _session_folder(tmp_path_factory)
    out, done = root / "paper-quick-figures", root / "paper-quick-figures.returncode"
    log = root / "paper-quick-figures.log"
    with open(root / "paper-quick-figures.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not done.exists():
            env = dict(os.environ, BUBBLEOPTICS_FIGURES_DIR=str(out), MPLBACKEND="Agg")
            env.pop("BUBBLEOPTICS_QUICK", None)
            proc = subprocess.run([sys.executable, str(PAPER / "scripts" / "make_figures.py"), "--quick"], env=env,
                                  capture_output=True, text=True, timeout=900)
            log.write_text(proc.stdout + proc.stderr, encoding="utf-8")
            done.write_text(str(proc.returncode), encoding="utf-8")
    return out, int(done.read_text(encoding="utf-8")), log.read_text(encoding="utf-8")

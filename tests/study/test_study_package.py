"""The study package's place in the repository: what it imports, what it exports, who uses it.

* ``study`` lives beside the two packages, not in the wheel: it may import both, neither imports
  it, and importing it adds none of the heavy libraries (scipy, matplotlib, colour-science) nor the
  test extra's mpmath and tmm.
* Every module has a curated ``__all__`` whose names exist.
* The slow references stay independent of the fast code: :mod:`study.reference`
  imports nothing of bubbleoptics, and says what to install when mpmath is missing.
* One CIEDE2000 and no script reaching another by path, in the repository's code: benchmarks,
  paper scripts, notebooks and the package.
"""

import ast
import importlib
import json
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.api

ROOT = Path(__file__).resolve().parents[2]
STUDY = ROOT / "study"
MODULES = sorted(p.stem for p in STUDY.glob("*.py") if p.stem != "__init__")
HEAVY = ("scipy", "matplotlib", "colour", "mpmath", "tmm")


def _python(code):
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, cwd=ROOT)
    assert out.returncode == 0, out.stderr
    return out.stdout


def test_the_package_has_its_modules():
    assert {"coursework", "fits", "fronts", "metrics", "results", "reference", "stability", "tradeoffs",
            "film_colour"} <= set(MODULES)


def test_import_adds_no_heavy_library_and_bubbleoptics_does_not_import_it():
    code = f"""
import json, sys
import bubbleoptics
before = set(sys.modules)
import study
after_init = set(sys.modules)
for name in {[m for m in MODULES if m != "reference"]!r}:
    __import__("study." + name)
print(json.dumps(dict(bubbleoptics_imports_study="study" in before,
                      added=sorted(m.split(".")[0] for m in after_init - before))))
"""
    result = json.loads(_python(code))
    assert not result["bubbleoptics_imports_study"]
    assert not set(result["added"]) & set(HEAVY), result["added"]


def test_neither_package_imports_the_study():
    for package in ("bubbleoptics", "tracer"):
        for path in (ROOT / package).rglob("*.py"):
            tree = ast.parse(path.read_text(encoding="utf-8"))
            imported = {alias.name for node in ast.walk(tree) if isinstance(node, ast.Import) for alias in node.names}
            imported |= {node.module or "" for node in ast.walk(tree)
                         if isinstance(node, ast.ImportFrom) and node.level == 0}
            assert not any(m == "study" or m.startswith("study.") for m in imported), path


@pytest.mark.parametrize("name", MODULES)
def test_each_module_has_all(name):
    module = importlib.import_module(f"study.{name}")
    assert module.__all__ and all(hasattr(module, n) for n in module.__all__), name
    assert module.__doc__ and len(module.__doc__) > 100


def test_init_reexports_a_short_list():
    import study as study

    assert 10 <= len(study.__all__) <= 30
    assert all(hasattr(study, n) for n in study.__all__)


def test_reference_is_independent_of_the_package():
    """The slow references import only the standard library, mpmath and (lazily) tmm."""
    tree = ast.parse((STUDY / "reference.py").read_text(encoding="utf-8"))
    imported = {alias.name.split(".")[0] for node in ast.walk(tree) if isinstance(node, ast.Import)
                for alias in node.names}
    imported |= {(node.module or "").split(".")[0] for node in ast.walk(tree)
                 if isinstance(node, ast.ImportFrom) and node.level == 0}
    assert not any(isinstance(node, ast.ImportFrom) and node.level > 0 for node in ast.walk(tree))
    assert imported <= {"__future__", "math", "mpmath", "tmm"}, imported


def test_reference_says_what_to_install_without_mpmath():
    code = """
import sys
sys.modules["mpmath"] = None  # as if the test extra were not installed
try:
    import study.reference
except ImportError as exc:
    print(exc)
"""
    assert "pip install 'bubbleoptics[test]'" in _python(code)


def _code_files():
    for folder in ("benchmarks", "paper/scripts", "bubbleoptics", "study", "tracer"):
        yield from (ROOT / folder).rglob("*.py")
    yield from (ROOT / "notebooks").glob("*.ipynb")


def _code_of(path):
    if path.suffix == ".ipynb":
        cells = json.loads(path.read_text(encoding="utf-8"))["cells"]
        return "\n".join("".join(c["source"]) for c in cells if c["cell_type"] == "code")
    return path.read_text(encoding="utf-8")


def test_one_ciede2000():
    users = sorted(str(p.relative_to(ROOT)) for p in _code_files() if "CIE 2000" in _code_of(p))
    assert users == ["study/metrics.py"]


def test_no_script_imports_another_by_path():
    for path in _code_files():
        code = _code_of(path)
        for forbidden in ("spec_from_file_location", "sys.path", "run_path(", "SourceFileLoader"):
            assert forbidden not in code, f"{path.relative_to(ROOT)}: {forbidden}"

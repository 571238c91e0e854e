"""benchmarks/profile_render.py's helpers: numba's mangled names shortened to dotted paths, and
the perf JIT map it writes, checked against the addresses numba reports (no perf needed)."""

import importlib.util
import os
import subprocess
import sys
from pathlib import Path

import numba
import pytest

ROOT = Path(__file__).resolve().parents[2]
_spec = importlib.util.spec_from_file_location("_bench_profile_render", ROOT / "benchmarks" / "profile_render.py")
pr = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(pr)


@pytest.mark.api
def test_short_name_reads_the_mangled_path():
    assert (pr.short_name("_ZN6tracer7kernels9thickness14film_thicknessB3v48B38c8tJTIcFKzyF2ILShI4CrgQElQb0HgiVCJIE")
            == "tracer.kernels.thickness.film_thickness")
    assert pr.short_name("_ZN8__main__3addB2v1Edd") == "__main__.add"
    assert pr.short_name("sin") == "sin"  # libm's own names pass through


@pytest.mark.reference
def test_perf_map_places_each_function_where_numba_put_it():
    @numba.njit  # compiled here, not loaded from a cache: its object code is available
    def _profiled_add(a, b):
        return a * b + 1.0

    assert _profiled_add(2.0, 3.0) == 7.0
    n = pr.write_perf_map()
    path = f"/tmp/perf-{os.getpid()}.map"
    try:
        entries = [line.split() for line in open(path) if line.strip()]
    finally:
        os.unlink(path)
    assert n == len(entries) > 0
    spans = {name: (int(a, 16), int(s, 16)) for a, s, name in entries}
    cres = next(iter(_profiled_add.overloads.values()))
    name = cres.fndesc.llvm_func_name
    assert pr.short_name(name).endswith("_profiled_add")
    start, size = spans[name]
    assert start == cres.library.get_pointer_to_function(name) and size > 0
    ordered = sorted(spans.values())
    assert all(a + s <= b for (a, s), (b, _) in zip(ordered, ordered[1:]))  # no two functions overlap


@pytest.mark.api
def test_missing_scene_file_is_a_one_line_error(tmp_path):
    out = subprocess.run([sys.executable, str(ROOT / "benchmarks" / "profile_render.py"), "--scene",
                          str(tmp_path / "none.txt")], capture_output=True, text=True)
    assert out.returncode == 2 and "--scene: no such scene file" in out.stderr and "Traceback" not in out.stderr

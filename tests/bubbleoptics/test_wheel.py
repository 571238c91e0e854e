"""The wheel that ``pip install .`` builds, installed the way a user installs it: built from a
copy of the sources, installed into a fresh virtual environment outside the checkout, and used
from a folder outside it (``tracer image``, a simulated film, ``import`` of every subpackage).

Every other test runs on the editable install of the checkout, which finds any file of the
tree whether or not the wheel would hold it; this one is the check that the wheel holds them.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = ("bubbleoptics", "tracer")
pytestmark = pytest.mark.api


def _run(args, cwd, env, timeout=900):
    proc = subprocess.run([str(a) for a in args], cwd=cwd, env=env, capture_output=True, text=True, timeout=timeout)
    assert proc.returncode == 0, f"{' '.join(map(str, args))}: exit {proc.returncode}\n{proc.stdout}\n{proc.stderr}"
    return proc


def _subpackages():
    """Every package of the checkout (a folder with an __init__.py), as a dotted name."""
    found = []
    for top in PACKAGES:
        for init in sorted((ROOT / top).rglob("__init__.py")):
            if "__pycache__" not in init.parts:
                found.append(".".join(init.parent.relative_to(ROOT).parts))
    return found


def _reuse_numba_cache(site: Path):
    """Copy the checkout's numba cache beside each installed source file that is byte for byte
    the checkout's, and give that file the checkout file's modification time (numba's cache is
    keyed on the source's path, modification time and size, and on each function's bytecode).
    Returns how many source files got their cache."""
    reused = 0
    for top in PACKAGES:
        for installed in (site / top).rglob("*.py"):
            rel = installed.relative_to(site)
            mine, cache = ROOT / rel, (ROOT / rel).parent / "__pycache__"
            files = sorted(cache.glob(f"{installed.stem}.*.nb[ic]")) if cache.is_dir() else []
            if not files or mine.read_bytes() != installed.read_bytes():
                continue  # no cache, or the checkout changed since the copy: numba compiles it
            stat = mine.stat()
            os.utime(installed, ns=(stat.st_atime_ns, stat.st_mtime_ns))
            (installed.parent / "__pycache__").mkdir(exist_ok=True)
            for f in files:
                shutil.copy2(f, installed.parent / "__pycache__" / f.name)
            reused += 1
    return reused


def test_the_wheel_installs_and_runs_outside_the_checkout(tmp_path):
    """Build the wheel (``pip wheel --no-build-isolation`` of a copy of the sources, so the
    checkout gets no build folder), install it with ``--no-deps`` into a fresh venv whose
    third-party packages are the project venv's (one path line in a ``.pth`` file: that folder's
    own ``.pth`` files, the editable install's hooks among them, are not processed, so the
    wheel's copy is the one imported, which the test checks), then from a folder outside the
    checkout import every subpackage, render the built-in scene with ``tracer image`` and a
    simulated film from a series the installed film-flow package computes.

    Why the renders are 4 x 4 and reuse the checkout's compiled kernels: a fresh copy of the
    package compiles every numba kernel on its first call (minutes on two cores; the JIT cannot
    be switched off, the integrator reads numba records by attribute).  Each installed file that
    is byte for byte the checkout's gets the checkout's numba cache and modification time
    (:func:`_reuse_numba_cache`), so that numba loads what the suite compiled from the same
    source; a kernel without a cache (the checkout's not built yet, or changed) compiles as
    usual, only slower.
    """
    src, dist, venv, work = tmp_path / "src", tmp_path / "dist", tmp_path / "venv", tmp_path / "work"
    ignore = shutil.ignore_patterns("__pycache__", "*.pyc", "*.nbi", "*.nbc", "*.egg-info", "build")
    src.mkdir()
    for name in ("pyproject.toml", "README.md"):
        shutil.copy2(ROOT / name, src / name)
    for top in PACKAGES:
        shutil.copytree(ROOT / top, src / top, ignore=ignore)
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME", "VIRTUAL_ENV")}
    _run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "--no-index", "--quiet",
          "--wheel-dir", dist, src], cwd=tmp_path, env=env)
    (wheel,) = dist.glob("bubbleoptics-*.whl")
    tops = {name.split("/")[0] for name in zipfile.ZipFile(wheel).namelist()}
    assert {"bubbleoptics", "tracer"} <= tops and "study" not in tops, tops  # the studies stay in the checkout

    _run([sys.executable, "-m", "venv", "--without-pip", venv], cwd=tmp_path, env=env)
    python = venv / "bin" / "python"
    site = Path(_run([python, "-c", "import sysconfig; print(sysconfig.get_path('purelib'))"], tmp_path,
                     env).stdout.strip())
    (site / "project-venv.pth").write_text(sysconfig.get_path("purelib") + "\n")  # numpy, numba, ...
    _run([sys.executable, "-m", "pip", "--python", python, "install", "--no-deps", "--no-index", "--quiet", wheel],
         cwd=tmp_path, env=env)
    _reuse_numba_cache(site)

    # every package of the checkout is in the wheel, and imports from the fresh venv
    work.mkdir()
    subpackages = _subpackages()
    assert "bubbleoptics.filmflow" in subpackages and "tracer.editor" in subpackages
    check = ("import importlib, json, sys\n"
             f"names = {subpackages!r}\n"
             "print(json.dumps({n: importlib.import_module(n).__file__ for n in names}))\n")
    files = json.loads(_run([python, "-c", check], work, env).stdout)
    for name, file in files.items():
        assert Path(file).is_relative_to(site), (name, file)  # the wheel's copy, not the checkout's
    assert (site / "bubbleoptics" / "colour_tables.npz").is_file()

    # one version source: the installed metadata, the CLI and the package agree
    import bubbleoptics

    version = _run([venv / "bin" / "tracer", "--version"], work, env).stdout.strip()
    assert version == f"tracer (bubbleoptics) {bubbleoptics.__version__}", version

    # tracer image of the built-in scene
    _run([venv / "bin" / "tracer", "image", "plain.png", "--width", "4", "--height", "4", "--quiet"], work, env)
    assert (work / "plain.png").stat().st_size > 0

    # a simulated film: a series computed by the installed film-flow models, drawn by tracer image
    simulate = ("from bubbleoptics.filmflow import FilmGrid, FilmParameters, PlugFlow\n"
                "p = FilmParameters()\n"
                "PlugFlow(p, FilmGrid(8, 16, p.radius)).run(t_end=0.02, dt=0.005, seed=1).save('film.npz')\n")
    _run([python, "-c", simulate], work, env)
    (work / "scene.toml").write_text(
        '[camera]\nposition = [0, 0.3, 4]\nlook_at = [0, 0, 0]\nfov_deg = 40\n[environment]\nkind = "sky"\n'
        '[[bubbles]]\nname = "b"\ncenter = [0, 0, 0]\nradius = 1\n'
        '[bubbles.film]\nkind = "simulated"\npath = "film.npz"\ntime = 0.01\n', encoding="utf-8")
    proc = _run([venv / "bin" / "tracer", "image", "scene.toml", "film.png", "--width", "4", "--height", "4",
                 "--quiet"], work, env)
    assert proc.stderr == "" and (work / "film.png").stat().st_size > 0
    assert sorted(p.name for p in work.iterdir()) == ["film.npz", "film.png", "plain.png", "scene.toml"]

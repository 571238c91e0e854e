"""``python -m bubbleoptics.demo`` end to end: it runs, writes both PNGs atomically and says where."""

from __future__ import annotations

import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

EXPECTED = ("reflectance_vs_thickness.png", "interference_colors.png")
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def demo_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("demo") / "nested" / "out"  # the demo must create missing folders
    env = dict(os.environ, MPLBACKEND="Agg")
    proc = subprocess.run(
        [sys.executable, "-m", "bubbleoptics.demo", "--out", str(out)],
        capture_output=True, text=True, env=env, timeout=300,
    )
    return proc, out


def test_exit_status_and_printed_paths(demo_run):
    proc, out = demo_run
    assert proc.returncode == 0, proc.stderr
    printed = [line for line in proc.stdout.splitlines() if line.strip()]
    assert len(printed) == len(EXPECTED), proc.stdout
    for line, name in zip(printed, EXPECTED):
        path = pathlib.Path(line)
        assert path.is_absolute(), line
        assert path.resolve() == (out / name).resolve()


def test_only_the_figures_are_left(demo_run):
    _, out = demo_run
    assert sorted(p.name for p in out.iterdir()) == sorted(EXPECTED)  # no stray temporary files


@pytest.mark.parametrize("name", EXPECTED)
def test_valid_png(demo_run, name):
    import matplotlib.image as mpimg

    _, out = demo_run
    path = out / name
    assert path.read_bytes()[:8] == PNG_SIGNATURE
    img = mpimg.imread(path)
    assert img.ndim == 3 and img.shape[2] in (3, 4)
    assert img.shape[0] >= 300 and img.shape[1] >= 1000
    assert np.all((img >= 0) & (img <= 1))


def test_color_strip_is_not_uniform(demo_run):
    import matplotlib.image as mpimg

    _, out = demo_run
    rgb = mpimg.imread(out / "interference_colors.png")[..., :3]
    # the strips fill most of the figure: many distinct saturated colours must be there, not just
    # the white background, black text and grey frame
    chroma = rgb.max(axis=-1) - rgb.min(axis=-1)
    assert (chroma > 0.3).mean() > 0.2
    distinct = np.unique((rgb[chroma > 0.3] * 15).round().astype(int), axis=0)
    assert len(distinct) > 30
    # along the most colourful row (one running through a strip) every channel varies strongly
    row = rgb[np.argmax((chroma > 0.3).sum(axis=1))]
    assert np.ptp(row, axis=0).min() > 0.5


def test_overwrites_existing_files(tmp_path):
    from bubbleoptics.demo import main

    (tmp_path / EXPECTED[0]).write_bytes(b"stale")
    assert main(["--out", str(tmp_path)]) == 0
    assert (tmp_path / EXPECTED[0]).read_bytes()[:8] == PNG_SIGNATURE
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(EXPECTED)

"""The data behind the paper's chapters on movies, living films and the editor says what their prose says.

The prose of ``paper/sections/{film_flow,movies,editor}.tex`` states some comparisons in words
("converges at second order", "two estimates bracket the apex", "misses its target"); these tests
check them against the committed CSVs, so that regenerated data that contradicts the words fails
here rather than printing a wrong sentence.  The scaling model of the movies chapter is evaluated
by :func:`study.movie_cost.model_movie_seconds`, checked against a literal evaluation and the benchmark's own rows.  Reading CSVs
only: milliseconds.
"""

import csv
import importlib
import math
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DERIVED = ROOT / "data" / "derived"
SCRIPTS = ROOT / "paper" / "scripts"


def _rows(name):
    lines = [ln for ln in (DERIVED / name).read_text(encoding="utf-8").splitlines() if not ln.startswith("#")]
    return list(csv.DictReader(lines))


def _plugin(name):
    if str(SCRIPTS) not in sys.path:
        sys.path.insert(0, str(SCRIPTS))
    return importlib.import_module(name)


@pytest.fixture(scope="module")
def verification():
    return _rows("film_flow_verification.csv")


def _series(rows, check, quantity):
    return dict(sorted((int(r["grid"].split("x")[0]), float(r["value"])) for r in rows
                       if r["check"] == check and r["quantity"] == quantity))


def _orders(errors):
    ns = sorted(errors)
    return [math.log2(errors[a] / errors[b]) for a, b in zip(ns, ns[1:])]


@pytest.mark.regression
def test_film_flow_orders_are_those_the_chapter_names(verification):
    """Apex law and equilibrium: second order; profile: first order; transient: first order
    (its coarsest pair not yet asymptotic, as in tests/bubbleoptics/test_film_flow.py)."""
    assert all(1.8 < o < 2.2 for o in _orders(_series(verification, "apex", "max_relative_error")))
    assert all(1.9 < o < 2.1 for o in _orders(_series(verification, "equilibrium", "max_relative_error")))
    assert all(0.9 < o < 1.1 for o in _orders(_series(verification, "profile", "max_abs_error_h_over_h0")))
    transient = _orders(_series(verification, "transient", "max_abs_difference_h_over_h0"))
    assert 0.6 < transient[0] < 1.3 and all(0.85 < o < 1.3 for o in transient[1:])
    # the stored log2 ratios are those of the stored errors
    stored = _series(verification, "equilibrium", "order")
    assert list(stored.values()) == pytest.approx(_orders(_series(verification, "equilibrium", "max_relative_error")),
                                                  rel=1e-3)


@pytest.mark.regression
def test_film_flow_conserves_to_rounding(verification):
    values = {r["quantity"]: float(r["value"]) for r in verification if r["check"] == "conservation"}
    assert set(values) == {"rigid_volume_per_step", "plug_volume_per_step", "plug_surfactant_per_step",
                           "rigid_evaporated", "plug_evaporated"}
    assert max(values.values()) < 1e-11


@pytest.mark.regression
def test_black_film_time_lies_between_the_two_estimates(verification):
    """The chapter: h_eq(0)/E < simulated apex time < h0/E; first cell before the apex before all;
    the rigid law's time is months (more than 30 days), and the frames span the apex time."""
    v = {r["quantity"]: float(r["value"]) for r in verification if r["check"] == "black"}
    assert v["t_equilibrium_apex"] < v["t_apex"] < v["t_uniform"]
    assert v["t_first"] <= v["t_apex"] <= v["t_all"]
    assert v["t_rigid"] > 30 * 86400
    # the estimates themselves, from the cited parameters
    from bubbleoptics.filmflow import FilmParameters

    p = FilmParameters()
    a = p.equilibrium_exponent
    assert v["t_uniform"] == pytest.approx(p.h0 / p.evaporation, rel=1e-3)
    assert v["t_equilibrium_apex"] == pytest.approx(p.h0 * a / math.sinh(a) * math.exp(-a) / p.evaporation, rel=1e-3)
    times = [float(r["value"]) for r in verification if r["check"] == "frames" and r["quantity"] == "time"]
    assert min(times) < v["t_apex"] <= max(times)


@pytest.mark.api
def test_film_flow_frames_are_small_images(verification):
    import numpy as np

    path = DERIVED / "film_flow_verification.npz"
    assert path.stat().st_size < 2_000_000
    data = np.load(path)
    frames = data["frames"]
    size = int(float(next(r["value"] for r in verification if r["quantity"] == "size")))
    assert frames.dtype == np.uint8 and frames.shape[1:] == (size, size, 3)
    assert len(frames) == len(data["frame_times"])
    assert frames.std() > 5  # not blank


@pytest.mark.reference
def test_movie_model_matches_a_literal_evaluation_and_the_benchmark_rows():
    """study.movie_cost.model_movie_seconds (used by benchmarks/movie.py and numbers_movies.py)
    against the model of its docstring written out here frame by frame, from the measured rows,
    and against the model rows the benchmark wrote."""
    from study.movie_cost import MODEL_MOVIE, model_movie_seconds

    rows = _rows("movie.csv")
    (dask,) = [r for r in rows if r["case"] == "dask"]
    cpu, overhead = float(dask["frame_cpu_seconds"]), float(dask["overhead_per_frame_seconds"])
    startup = float(dask["cluster_startup_seconds"])
    encode = float(dask["encode_seconds_median"]) / int(dask["frames"])
    pixels = int(dask["width"]) * int(dask["height"])
    models = [r for r in rows if r["case"].startswith("model ")]
    assert sorted(int(r["workers"]) for r in models) == sorted(_plugin("numbers_movies").MODEL_WORKERS)
    m = MODEL_MOVIE
    for r in models:
        workers = int(r["workers"])
        # literally: deal the frames out to the workers one round at a time
        frame = cpu * (m["width"] * m["height"] / pixels) * m["spp"]
        left, wall = m["frames"], startup
        while left > 0:
            wall += frame + overhead
            left -= min(workers, left)
        wall += m["frames"] * encode * m["width"] * m["height"] / pixels
        seconds, frame_s, rounds, _ = model_movie_seconds(workers, cpu, overhead, startup, encode, pixels)
        assert seconds == pytest.approx(wall, rel=1e-12)
        assert frame_s == pytest.approx(frame, rel=1e-12)
        assert rounds == math.ceil(m["frames"] / workers)
        assert seconds == pytest.approx(float(r["seconds_median"]), rel=2e-3)
        assert frame_s == pytest.approx(float(r["frame_compute_seconds"]), rel=2e-3)


@pytest.mark.regression
def test_editor_flags_follow_the_csv():
    """The chapter's \\ifnum flags say 'meets' exactly when the median is within the target."""
    ne = _plugin("numbers_editor")
    out = ne.editor({"derived": DERIVED})
    for case, key in (("first_preview", "Preview"), ("full_resolution", "Full")):
        (r,) = [r for r in _rows("editor.csv") if r["case"] == case]
        within = float(r["ms_median"]) <= float(r["target_ms"])
        assert out[f"Ed{key}Meets"] == ("1" if within else "0")
        assert (r["meets_target"] == "True") == within

"""study.fronts and .tradeoffs: Pareto fronts, time to equal error, and the verdict on
the tracer's defaults.

* ``analytic``: hand-made Pareto sets and curves; a hand-made study of two scenes whose verdict
  is known.
* ``reference``: the front against its literal O(n²) definition; the committed study
  (``data/derived/time_vs_error.csv``) read back and checked against the definition.
* ``api``: argument errors, the settings of the sweeps, the reference images' round trip.
"""

import math
from pathlib import Path

import numpy as np
import pytest

from study import pareto_front, time_at_error, tradeoffs
from study.fronts import time_ratio_curve

DERIVED = Path(__file__).resolve().parents[2] / "data" / "derived"
DEFAULTS = dict(spectral=True, spectral_samples=16, spectral_method="auto", threshold=1e-3, spp=1, depth=10)


@pytest.mark.analytic
def test_pareto_front_hand_made():
    #            0    1    2    3    4    5    6    7       8
    times = [1.0, 2.0, 3.0, 2.5, 2.0, 4.0, 3.0, np.nan, 0.5]
    errors = [5.0, 3.0, 1.0, 4.0, 3.5, 0.5, 1.0, 0.0, 9.0]
    # 3 is dominated by 1; 4 by 1 (same time, larger error); 6 duplicates 2 (both kept);
    # 7 has a NaN; 8 is the fastest and so on the front; 5 is the most accurate
    assert pareto_front(times, errors).tolist() == [8, 0, 1, 2, 6, 5]


@pytest.mark.analytic
def test_pareto_front_edge_cases():
    assert pareto_front([], []).tolist() == []
    assert pareto_front([1.0], [1.0]).tolist() == [0]
    assert pareto_front([1.0, 2.0, 3.0], [1.0, 1.0, 1.0]).tolist() == [0]  # equal error: the fastest
    assert pareto_front([1.0, 2.0, 3.0], [3.0, 2.0, 1.0]).tolist() == [0, 1, 2]  # all trade-offs
    with pytest.raises(ValueError, match="same length"):
        pareto_front([1.0, 2.0], [1.0])


@pytest.mark.reference
@pytest.mark.parametrize("seed", range(5))
def test_pareto_front_against_literal_definition(seed):
    """Against the definition applied pair by pair (O(n²)), on integer grids full of ties."""
    rng = np.random.default_rng(seed)
    t = rng.integers(0, 8, 60).astype(float)
    e = rng.integers(0, 8, 60).astype(float)
    literal = [
        i for i in range(t.size)
        if not any(t[j] <= t[i] and e[j] <= e[i] and (t[j] < t[i] or e[j] < e[i]) for j in range(t.size))
    ]
    assert sorted(pareto_front(t, e).tolist()) == literal


# ------------------------------------------------------------------ time to equal error (analytic)


@pytest.mark.analytic
def test_time_at_error_power_law():
    """On error = t^-1/2 (a Monte Carlo curve) the log-log interpolation is exact between points."""
    t = np.array([1.0, 4.0, 16.0, 64.0])
    e = t**-0.5
    for target in (0.9, 0.3, 0.2, 0.125):
        assert time_at_error(t, e, target) == pytest.approx(target**-2, rel=1e-12)
    assert time_at_error(t[::-1], e[::-1], 0.25) == pytest.approx(16.0)  # order of the points does not matter
    assert math.isnan(time_at_error(t, e, 2.0)) and math.isnan(time_at_error(t, e, 0.01))


@pytest.mark.analytic
def test_time_ratio_curve_of_two_power_laws():
    """Two Monte Carlo curves e = c t^-1/2: at equal error the time ratio is (c_slow / c_fast)^2 at
    every target, and the targets span exactly the errors both curves reach."""
    t = np.array([1.0, 4.0, 16.0, 64.0])
    slow = (t, 3.0 * t**-0.5)  # errors 3 .. 0.375
    fast = (t, 1.0 * t**-0.5)  # errors 1 .. 0.125
    targets, ratios = time_ratio_curve(slow, fast, n=9)
    assert targets.min() == pytest.approx(0.375) and targets.max() == pytest.approx(1.0)
    assert np.all(np.diff(np.log(targets)) > 0)
    np.testing.assert_allclose(ratios, 9.0, rtol=1e-9)
    # curves whose errors never meet: nothing to compare
    empty = time_ratio_curve((t, 100.0 * t**-0.5), fast)
    assert empty[0].size == 0 and empty[1].size == 0


# ------------------------------------------------------------------ the defaults' verdict


def _row(scene, factor, value, seconds, error, *, spp=1, threshold=1e-3, default=False, runs=None, method="auto"):
    return dict(scene=scene, factor=factor, value=value, transport="spectral", spectral_samples=16.0,
                spectral_method=method, threshold=threshold, spp=float(spp), depth=10.0, width=8.0, height=8.0,
                seconds=seconds, seconds_runs=runs or f"{seconds}", mean_de00=error, p95_de00=error, rmse=error,
                interior_mean_de00=error, interior_p95_de00=error, speedup_vs_reference=100.0 / seconds,
                is_default=float(default))


def _study(default_seconds, default_error, other_seconds, other_error, runs=None):
    rows = []
    for scene in ("a", "b"):
        rows.append(_row(scene, "reference", "reference", 100.0, 0.0, spp=16, threshold=0.0))
        rows.append(_row(scene, "default", "default", default_seconds, default_error, default=True, runs=runs))
        rows.append(_row(scene, "spp", "4", other_seconds, other_error, spp=4, runs=runs))
    return rows


@pytest.mark.analytic
def test_assess_defaults_on_the_front_qualify():
    result = tradeoffs.assess(_study(1.0, 0.2, 4.0, 0.1), DEFAULTS)
    assert result["default_ok"] and not result["problems"]
    assert result["proposal"] == tradeoffs.key(DEFAULTS)
    assert tradeoffs.change_advice(result) == ""


@pytest.mark.analytic
def test_assess_dominated_defaults_fail_and_get_advice():
    """Another setting as accurate and faster beyond the timing noise dominates the defaults."""
    result = tradeoffs.assess(_study(4.0, 0.2, 1.0, 0.1), DEFAULTS, tol=0.1)
    assert not result["default_ok"]
    assert any("dominated" in p for p in result["problems"])
    assert result["proposal"][4] == 4  # spp 4
    assert "spp: 1 -> 4" in tradeoffs.change_advice(result)


@pytest.mark.analytic
def test_assess_the_same_render_timed_twice_never_dominates():
    """A row whose image is the defaults' own (every error equal: e.g. "point" where "auto"
    chooses point) is the same render timed twice, however much faster it was measured."""
    rows = _study(4.0, 0.2, 8.0, 0.1)
    for scene in ("a", "b"):
        rows.append(_row(scene, "spectral", "16", 1.0, 0.2, method="point"))
    result = tradeoffs.assess(rows, DEFAULTS, tol=0.1)
    assert result["default_ok"], result["problems"]
    # a faster row with a different image (even slightly) still dominates
    for r in rows:
        if r["spectral_method"] == "point":
            r["mean_de00"] = 0.19
    assert not tradeoffs.assess(rows, DEFAULTS, tol=0.1)["default_ok"]


@pytest.mark.analytic
def test_assess_timing_noise_protects_the_defaults():
    """Faster by less than the noise (runs spread by 50 %) is no dominance."""
    result = tradeoffs.assess(_study(1.2, 0.2, 1.0, 0.1, runs="0.8 1.2 1.6"), DEFAULTS)
    assert result["tol"] == pytest.approx(2 / 3)
    assert result["default_ok"]


@pytest.mark.analytic
def test_assess_targets():
    result = tradeoffs.assess(_study(1.0, 0.7, 4.0, 0.6), DEFAULTS)  # both above the 0.5 target
    assert not result["default_ok"] and result["proposal"] is None
    assert any("> 0.5" in p for p in result["problems"])


@pytest.mark.api
def test_configurations_sweep_around_the_defaults():
    configs = tradeoffs.configurations(DEFAULTS, band=False)
    assert configs[0] == ("default", "default", DEFAULTS)
    factors = {f for f, _, _ in configs}
    assert factors == {"default", "spectral", "threshold", "spp", "depth", "grid"}
    assert not any(s["spectral_method"] == "band" for _, _, s in configs)
    # every one-factor sweep passes through the defaults
    for factor in ("threshold", "spp", "depth"):
        assert tradeoffs.key(DEFAULTS) in {tradeoffs.key(s) for f, _, s in configs if f == factor}
    assert any(s["spectral_method"] == "band" for _, _, s in tradeoffs.configurations(DEFAULTS, band=True))
    kw = tradeoffs.render_kwargs(dict(DEFAULTS, spectral=False), 32)
    assert kw["width"] == kw["height"] == 32 and not kw["spectral"] and "spectral_samples" not in kw


@pytest.mark.api
def test_references_round_trip(tmp_path):
    rng = np.random.default_rng(0)
    refs = {"s": dict(image=rng.uniform(0, 1, (4, 5, 3)), interior=rng.uniform(size=(4, 5)) > 0.5,
                      bubble=rng.uniform(size=(4, 5)) > 0.5, seconds=2.0, seconds_ideal=0.1,
                      floor_errors=dict(mean_de00=0.3))}
    folder = tradeoffs.save_references(refs, 4, 16, tmp_path / "refs", written_by="test")
    back = tradeoffs.load_references(folder, 4, 16)
    np.testing.assert_allclose(back["s"]["image"], refs["s"]["image"], rtol=1e-7)  # float32 on disk
    np.testing.assert_array_equal(back["s"]["interior"], refs["s"]["interior"])
    assert back["s"]["seconds"] == 2.0 and back["s"]["floor_errors"] == dict(mean_de00=0.3)
    assert tradeoffs.load_references(folder, 8, 16) is None  # another size: not these references
    assert tradeoffs.load_references(tmp_path / "nothing", 4, 16) is None
    big = tradeoffs.save_references(refs, 4, 16, tmp_path / "small", overflow=tmp_path / "big", max_bytes=10)
    assert big == tmp_path / "big" and (big / "meta.json").exists()


@pytest.mark.reference
@pytest.mark.skipif(not (DERIVED / "time_vs_error.csv").exists(), reason="no data/derived/time_vs_error.csv")
def test_committed_study_fronts_follow_the_definition():
    """Each scene of the committed study: the front of scene_front is the set of settings no other
    setting beats in both time and interior error (checked pair by pair), and the defaults row is
    one of the settings."""
    _, rows = tradeoffs.read_rows(DERIVED / "time_vs_error.csv")
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    assert scenes
    for scene in scenes:
        sf = tradeoffs.scene_front(rows, scene)
        pts = sf["points"]
        t = [r["seconds"] for r in pts]
        e = [r["interior_mean_de00"] for r in pts]
        literal = {i for i in range(len(pts)) if not any(
            t[j] <= t[i] and e[j] <= e[i] and (t[j] < t[i] or e[j] < e[i]) for j in range(len(pts)))}
        assert set(sf["front"].tolist()) == literal
        assert len({tradeoffs.row_key(r) for r in pts}) == len(pts)  # every setting once
        assert tradeoffs.row_key(sf["default"]) in {tradeoffs.row_key(r) for r in pts}
        assert sf["reference_seconds"] > max(t)

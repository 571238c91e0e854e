"""Verification of the film-flow black-film run (benchmarks/film_flow_verification.py --only dt,
--only evaporation): the time-step study converges, and the black-film time falls as the
evaporation rate rises.  Small grids: each test takes seconds."""

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from bubbleoptics.filmflow import FilmParameters
from study import film_flow as ff

#: a tiny grid, and steps of a fraction of the time a Gibbs (Marangoni) wave takes to cross one
#: of its cells (about 5 ms on 16 rows): the range where the first-order splitting shows its order
TINY_GRID = (16, 32)
TINY_STEPS = (0.0025, 0.00125, 0.000625)
#: six times the cited evaporation: black in ~10 s, so the three runs take ~27,000 steps
FAST = 6.0


def _fast_film(multiple=FAST):
    p = FilmParameters()
    return p.replace(evaporation=multiple * p.evaporation)


@pytest.mark.analytic
def test_observed_order_and_richardson_of_an_exact_first_order_sequence():
    """f(dt) = 2 + 3 dt: every observed order is 1 and Richardson's estimate is exactly 2."""
    steps = [0.1 / 2**k for k in range(5)]
    values = [2 + 3 * dt for dt in steps]
    assert ff.observed_orders(values) == pytest.approx([1.0, 1.0, 1.0], abs=1e-9)
    assert ff.richardson(values[-2], values[-1], 1.0) == pytest.approx(2.0, abs=1e-12)
    assert math.isnan(ff.richardson(values[-2], values[-1], -0.3))
    with pytest.raises(ValueError, match="three values"):
        ff.observed_orders([1.0, 2.0])


@pytest.mark.regression
def test_time_step_study_converges_at_a_positive_order_on_a_tiny_grid():
    """The black-film run (six times the cited evaporation, so it is black in ~10 s) at three
    steps halving each time: the apex's black-film time converges with an observed order in
    (0.5, 2) (the scheme is first order; measured 0.91), the apex thickness at 4 s with a
    positive one (0.38: still approaching its asymptotic range), both monotone in the step, and
    Richardson's estimate lies beyond the finest value, on the side the sequence moves to (for the
    black-film time, by less than the whole spread)."""
    p = _fast_film()
    runs = [ff.black_film_run(p, TINY_GRID, dt, probe_s=4.0) for dt in TINY_STEPS]
    for name, band in (("t_apex", (0.5, 2.0)), ("apex_probe_nm", (0.0, 2.5))):
        values = [getattr(r, name) for r in runs]
        orders = ff.observed_orders(values)
        assert all(band[0] < o < band[1] for o in orders), (name, values, orders)
        diffs = [b - a for a, b in zip(values, values[1:])]
        assert all(d * diffs[0] > 0 for d in diffs), (name, values)  # monotone in the step
        extrapolated = ff.richardson(values[-2], values[-1], orders[-1])
        assert (extrapolated - values[-1]) * diffs[0] > 0
        if name == "t_apex":  # near first order: the estimate is about one more difference away
            assert abs(extrapolated - values[-1]) < abs(values[-1] - values[0])
    assert all(r.t_first <= r.t_apex + 1.0 for r in runs)


@pytest.mark.property
@settings(max_examples=8, deadline=None)
@given(st.lists(st.floats(0.25, 4.0), min_size=2, max_size=4, unique=True))
def test_black_film_time_falls_as_the_evaporation_rate_rises(multiples):
    """On an 8 x 16 grid (50 ms steps): for any rates E (0.25-4 x the cited one) the apex's
    black-film time is strictly decreasing in E, evaporation does most of the apex's thinning
    and drainage (at the apex, an outflow) the rest, so E t_black lies between
    h_eq(0) - h_black and h_apex(0) - h_black."""
    multiples = sorted(multiples)
    runs = [ff.black_film_run(_fast_film(m), (8, 16), 0.05, probe_s=0.0) for m in multiples]
    times = [r.t_apex for r in runs]
    assert all(math.isfinite(t) for t in times)
    for (m1, t1), (m2, t2) in zip(zip(multiples, times), zip(multiples[1:], times[1:])):
        if m2 > m1 * (1 + 1e-6):
            assert t2 < t1, (multiples, times)
    for m, r in zip(multiples, runs):
        p = _fast_film(m)
        thinned = p.evaporation * r.t_apex * 1e9
        assert ff.equilibrium_apex_nm(p) - r.threshold_nm < thinned < r.apex_start_nm - r.threshold_nm
        assert 0.5 < r.evaporated_share < 1.0


@pytest.mark.regression
def test_without_evaporation_the_film_never_turns_black():
    """E = 0: the apex settles near the equilibrium's h_eq(0) (within 5 %, on 8 x 16) and no cell
    gets black in 60 s."""
    p = FilmParameters(evaporation=0.0)
    r = ff.black_film_run(p, (8, 16), 0.05, probe_s=0.0, t_max=60.0)
    assert math.isnan(r.t_apex) and math.isnan(r.t_first)
    assert r.apex_end_nm == pytest.approx(ff.equilibrium_apex_nm(p), rel=0.05)

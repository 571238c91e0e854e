"""study.film_flow: the analyses of notebooks/07_film_flow.ipynb, each against a closed form."""

import math

import numpy as np
import pytest

from bubbleoptics.filmflow import FilmGrid, FilmParameters, RigidDrainage
from study import film_flow as ff


@pytest.mark.analytic
def test_first_order_range_of_a_two_beam_curve():
    """Y = sin²(2π n d / λ): maximum at λ/4n, first minimum after it at λ/2n, and Y reaches a
    fraction f of the maximum at d = arcsin(√f) λ / (2π n)."""
    n, lam, f = 1.33, 550.0, 0.05
    d = np.linspace(0.0, 600.0, 60001)  # 0.01 nm
    fo = ff.first_order_range(d, np.sin(2 * np.pi * n * d / lam) ** 2, black_fraction=f)
    assert fo.peak_nm == pytest.approx(lam / (4 * n), abs=0.01)
    assert fo.end_nm == pytest.approx(lam / (2 * n), abs=0.01)
    assert fo.black_below_nm == pytest.approx(math.asin(math.sqrt(f)) * lam / (2 * math.pi * n), abs=1e-3)
    assert fo.peak_Y == pytest.approx(1.0, abs=1e-6) and fo.end_Y == pytest.approx(0.0, abs=1e-6)


@pytest.mark.analytic
def test_a_linear_table_is_exact_at_its_nodes_and_twice_too_bright_halfway_to_the_first():
    """Near d = 0 the film's luminance grows as d², so the chord from 0 to the first node, read
    halfway, is (1/2) / (1/4) = 2 times the exact value; at the nodes the table is exact."""
    step = 1.0  # nm of OPD: the first node at 0.376 nm of thickness, deep in the d² regime
    node = step / (2 * 1.33)
    exact = ff.film_luminance([0.5 * node, node, 2 * node], n_film=1.33, illuminant=None)
    table = ff.opd_table_luminance([0.5 * node, node, 2 * node], step, n_film=1.33)
    assert table[0] / exact[0] == pytest.approx(2.0, rel=1e-3)
    assert table[1:] == pytest.approx(exact[1:], rel=1e-12)


@pytest.mark.analytic
def test_rigid_black_time_is_where_the_simulated_apex_reaches_the_threshold():
    """rigid_black_time inverts the apex law, and RigidDrainage's top cell (64 rows) gets there."""
    p = FilmParameters(evaporation=0.0, perturbation=0.0)
    h0 = p.h0 * 1e9
    t = ff.rigid_black_time(h0, p.drainage_time, 0.5 * h0)
    assert t == pytest.approx(3 * p.drainage_time, rel=1e-14)
    m = RigidDrainage(p, FilmGrid(64, 4, p.radius))
    s = m.step(m.initial_state(seed=0), t)
    assert s.h[0, 0] * 1e9 == pytest.approx(0.5 * h0, rel=1e-3)


@pytest.mark.analytic
def test_first_crossing_interpolates_linearly():
    assert ff.first_crossing([0.0, 2.0, 4.0], [90.0, 40.0, 20.0], 30.0) == pytest.approx(3.0)
    assert ff.first_crossing([0.0, 1.0], [10.0, 5.0], 30.0) == 0.0
    assert math.isnan(ff.first_crossing([0.0, 1.0], [50.0, 40.0], 30.0))


@pytest.mark.api
def test_bad_inputs_are_refused():
    with pytest.raises(ValueError, match="threshold_nm"):
        ff.rigid_black_time(100.0, 1.0, 200.0)
    with pytest.raises(ValueError, match="no local maximum"):
        ff.first_order_range(np.arange(5.0), np.arange(5.0))
    with pytest.raises(ValueError, match="black_fraction"):
        ff.first_order_range(np.arange(5.0), np.arange(5.0), black_fraction=1.5)

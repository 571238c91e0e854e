"""Simulated films in the tracer (tracer.simulated): a bubbleoptics.filmflow.ThicknessSeries drawn
as the map it shows at the film time, from Python, from TOML and in movies (the ``time`` command)."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

import tracer
from bubbleoptics.filmflow import FilmGrid, ThicknessSeries
from tracer.movie_commands import Timeline
from tracer.scene import Bubble, Camera, Environment, FilmProfile, Scene
from tracer.simulated import resolve_simulated_films, sampled_film
from cli_helpers import assert_one_line, run  # tests/cli_helpers.py

SMALL = dict(width=24, height=20, depth=3, progress=False)


def series(values_nm, times=None, shape=(6, 12)):
    """A series whose every cell holds values_nm[i] at times[i] (uniform films in time)."""
    values_nm = np.asarray(values_nm, float)
    times = np.arange(len(values_nm), dtype=float) if times is None else times
    h = values_nm[:, None, None] * np.ones((1, *shape))
    return ThicknessSeries(h, times, FilmGrid(*shape, 0.04), {"note": "test"}, "test")


def bubble_scene(film):
    return Scene(bubbles=[Bubble(center=(0.0, 0.0, 0.0), radius=1.0, film=film, name="b")],
                 camera=Camera(position=(0.0, 0.3, 4.0), look_at=(0.0, 0.0, 0.0), fov_deg=40.0),
                 environment=Environment(kind="sky"))


@pytest.mark.analytic
def test_a_uniform_series_renders_as_the_uniform_film():
    uniform = tracer.render(bubble_scene(FilmProfile(kind="uniform", thickness_nm=420.0)), **SMALL)
    simulated = tracer.render(bubble_scene(FilmProfile(kind="simulated", series=series([420.0]))), **SMALL)
    assert np.allclose(simulated, uniform, rtol=0, atol=1e-12)


@pytest.mark.analytic
def test_the_film_time_interpolates_linearly_between_stored_steps():
    """900 nm at t = 0 and 700 nm at t = 2: at time 1 the bubble is the uniform 800 nm film,
    and after the last step it stays at 700 nm."""
    s = series([900.0, 700.0], times=np.array([0.0, 2.0]))
    at = {t: tracer.render(bubble_scene(FilmProfile(kind="simulated", series=s, time_s=t)), **SMALL)
          for t in (1.0, 5.0)}
    for t, d in ((1.0, 800.0), (5.0, 700.0)):
        ref = tracer.render(bubble_scene(FilmProfile(kind="uniform", thickness_nm=d)), **SMALL)
        assert np.allclose(at[t], ref, rtol=0, atol=1e-9)
    assert not np.allclose(at[1.0], at[5.0])


@pytest.mark.analytic
def test_the_map_rows_are_the_series_faces_and_columns_its_cells():
    """A film that varies with θ only, h = 100 + 50 j on cell row j: the map has n_theta + 1
    rows, means of neighbouring rows inside and ring means at the poles."""
    h = (100.0 + 50.0 * np.arange(6))[:, None] * np.ones((1, 12))
    s = ThicknessSeries(h[None], [0.0], FilmGrid(6, 12, 0.04), {}, "test")
    table = sampled_film(FilmProfile(kind="simulated", series=s)).table
    assert table.shape == (7, 12)
    assert np.allclose(table[:, 0], [100, 125, 175, 225, 275, 325, 350])


@pytest.mark.api
def test_a_film_thinner_than_its_rupture_thickness_pops_the_bubble():
    s = series([40.0, 4.0], times=np.array([0.0, 1.0]))
    film = FilmProfile(kind="simulated", series=s, rupture_nm=5.0)
    assert len(resolve_simulated_films(bubble_scene(film)).bubbles) == 1
    assert resolve_simulated_films(bubble_scene(film), 1.0).bubbles == []
    popped = tracer.render(bubble_scene(dataclasses.replace(film, time_s=1.0)), **SMALL)
    empty = tracer.render(dataclasses.replace(bubble_scene(film), bubbles=[]), **SMALL)
    assert np.array_equal(popped, empty)


@pytest.mark.api
def test_a_simulated_film_needs_a_series():
    with pytest.raises(ValueError, match="must be a bubbleoptics.filmflow.ThicknessSeries"):
        tracer.render(bubble_scene(FilmProfile(kind="simulated")), **SMALL)


def write_scene(tmp_path, film_lines, name="scene.toml"):
    path = tmp_path / name
    path.write_text(
        "[camera]\nposition = [0, 0.3, 4]\nlook_at = [0, 0, 0]\nfov_deg = 40\n"
        "[environment]\nkind = \"sky\"\n"
        "[[bubbles]]\nname = \"b\"\ncenter = [0, 0, 0]\nradius = 1\n"
        "[bubbles.film]\n" + film_lines, encoding="utf-8")
    return path


@pytest.mark.api
def test_toml_reads_a_series_and_writes_it_back(tmp_path):
    series([900.0, 500.0], times=np.array([0.0, 4.0])).save(tmp_path / "film.npz")
    path = write_scene(tmp_path, 'kind = "simulated"\npath = "film.npz"\ntime = 1.5\nrupture_nm = 3\n')
    scene = tracer.load_scene(path)
    film = scene.bubbles[0].film
    assert film.kind == "simulated" and film.time_s == 1.5 and film.rupture_nm == 3.0
    assert np.array_equal(film.series.h_nm, series([900.0, 500.0]).h_nm)
    again = tmp_path / "again.toml"
    tracer.io.save_toml_scene(scene, again)
    assert (tmp_path / "again.bubble0.film.npz").is_file()
    assert np.array_equal(tracer.render(tracer.load_scene(again), **SMALL), tracer.render(scene, **SMALL))


BAD_FILMS = {
    "not an npz": ('kind = "simulated"\npath = "film.npy"\n', "film.npy", "is a .npz file"),
    "missing file": ('kind = "simulated"\npath = "none.npz"\n', None, "file not found: none.npz"),
    "not a series": ('kind = "simulated"\npath = "other.npz"\n', "other.npz", "is not a ThicknessSeries file"),
    "negative time": ('kind = "simulated"\npath = "film.npz"\ntime = -1\n', None, "time"),
    "negative rupture": ('kind = "simulated"\npath = "film.npz"\nrupture_nm = -2\n', None, "rupture_nm"),
    "no path": ('kind = "simulated"\n', None, "path"),
    "unknown key": ('kind = "simulated"\npath = "film.npz"\nthickness_nm = 3\n', None, "thickness_nm"),
}


@pytest.mark.api
@pytest.mark.parametrize("case", BAD_FILMS)
def test_bad_simulated_films_are_one_line_with_file_and_line(tmp_path, capsys, case):
    film_lines, extra, what = BAD_FILMS[case]
    series([500.0]).save(tmp_path / "film.npz")
    np.save(tmp_path / "film.npy", np.ones((3, 3)))
    np.savez(tmp_path / "other.npz", a=np.ones(3))
    path = write_scene(tmp_path, film_lines)
    status, out, err = run(["image", path, tmp_path / "out.png", "--width", "8", "--height", "8"], capsys)
    assert status == 2 and out == ""
    assert_one_line(err)
    assert err.startswith(f"{path}:") and what in err, err
    assert not (tmp_path / "out.png").exists()


@pytest.mark.reference
def test_the_time_command_advances_the_film_and_each_frame_is_tracer_image_of_its_scene(tmp_path, capsys):
    """A film thinning from 900 to 300 nm over 6 s; ``time 6`` over ``render 3`` shows it at 2, 4
    and 6 s: each frame against tracer image of a uniform film of that thickness (the series is
    uniform in space), within one 8-bit step, and the frames differ."""
    import imageio.v3 as iio

    series([900.0, 300.0], times=np.array([0.0, 6.0])).save(tmp_path / "film.npz")
    scene = write_scene(tmp_path, 'kind = "simulated"\npath = "film.npz"\n')
    commands = tmp_path / "c.txt"
    commands.write_text("time 6\nrender 3\n")
    tiny = ["--width", "24", "--height", "20", "--depth", "3", "--quiet"]
    assert run(["movie", scene, tmp_path / "m", commands, *tiny], capsys)[0] == 0
    frames = [iio.imread(p).astype(int) for p in sorted((tmp_path / "m").glob("*.png"))]
    assert len(frames) == 3
    for frame, d in zip(frames, (700.0, 500.0, 300.0)):
        uniform = write_scene(tmp_path, f'kind = "uniform"\nthickness_nm = {d}\n', name=f"u{d:.0f}.toml")
        assert run(["image", uniform, tmp_path / "u.png", *tiny], capsys)[0] == 0
        assert np.abs(frame - iio.imread(tmp_path / "u.png").astype(int)).max() <= 1
    assert np.abs(frames[0] - frames[2]).max() > 5
    tl = Timeline.from_file(tracer.load_scene(scene), commands)
    assert [t for _, t in tl.scenes()] == pytest.approx([2.0, 4.0, 6.0])
    assert all(f.scene.bubbles[0].film.kind == "map" for f in tl.frames())  # frames carry maps, not series


@pytest.mark.api
def test_a_bubble_pops_mid_movie(tmp_path):
    s = series([40.0, 2.0], times=np.array([0.0, 4.0]))
    scene = bubble_scene(FilmProfile(kind="simulated", series=s, rupture_nm=10.0))
    tl = Timeline(scene).time(4.0).render(4)
    assert [len(sc.bubbles) for sc, _ in tl.scenes()] == [1, 1, 1, 0]  # 30.5, 21, 11.5, 2 nm
    result = tracer.render_movie(scene, tl, Path(tmp_path) / "m", **{k: v for k, v in SMALL.items()
                                                                        if k != "progress"}, progress=False)
    assert result.frames == 4

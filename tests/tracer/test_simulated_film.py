"""Simulated films in the tracer (tracer.scene.simulated): a bubbleoptics.filmflow.ThicknessSeries drawn
as the map it shows at the film time, from Python, from TOML and in movies (the ``time`` command)."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

import tracer
from bubbleoptics.filmflow import FilmGrid, ThicknessSeries
from tracer.movie.timeline import Timeline
from tracer.scene import Bubble, Camera, Environment, FilmProfile, Scene
from tracer.scene.simulated import resolve_simulated_films, sampled_film
from cli_helpers import assert_one_line, run  # tests/support/cli_helpers.py

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
    tracer.scene.load.save_toml_scene(scene, again)
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


# ------------------------------------------------------------------ damaged or hostile series files
def _member_data_offset(path, member):
    """Where the (compressed) data of *member* starts in the zip file *path*."""
    import struct
    import zipfile

    with zipfile.ZipFile(path) as z:
        info = z.getinfo(member)
    raw = Path(path).read_bytes()
    name_len, extra_len = struct.unpack("<HH", raw[info.header_offset + 26:info.header_offset + 30])
    return info.header_offset + 30 + name_len + extra_len, info.compress_size


def _rewrite(path, **members):
    """The series file *path* with some members replaced (plain np.savez of the rest)."""
    with np.load(path) as z:
        arrays = {k: z[k] for k in z.files}
    arrays.update(members)
    np.savez(path, **arrays)


def _declared_only(path, member, header, data=b""):
    """Replace *member* of the zip *path* by a .npy header (a dict for numpy's writer) and *data*."""
    import io
    import zipfile

    buf = io.BytesIO()
    np.lib.format.write_array_header_1_0(buf, header)
    with zipfile.ZipFile(path) as z:
        others = {i.filename: z.read(i) for i in z.infolist() if i.filename != f"{member}.npy"}
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        for name, content in others.items():
            z.writestr(name, content)
        z.writestr(f"{member}.npy", buf.getvalue() + data)


def _break(kind, path):
    if kind == "truncated":
        path.write_bytes(path.read_bytes()[: path.stat().st_size // 2])
    elif kind == "corrupted":  # bytes in the middle of the thickness's deflate stream
        start, size = _member_data_offset(path, "h_nm.npy")
        raw = bytearray(path.read_bytes())
        raw[start + size // 3:start + size // 3 + 40] = bytes(range(40))
        path.write_bytes(bytes(raw))
    elif kind == "corrupted deep":  # valid numbers over a larger series' stored (np.savez) data: the CRC-32 tells
        series([500.0, 400.0], shape=(64, 128)).save(path)
        _rewrite(path)
        start, size = _member_data_offset(path, "h_nm.npy")
        raw = bytearray(path.read_bytes())
        raw[start + size - 80:start + size - 40] = b"A" * 40  # 12.07 nm as float32
        path.write_bytes(bytes(raw))
    elif kind == "random bytes":
        path.write_bytes(np.random.default_rng(5).bytes(500))
    elif kind == "2-D h_nm":
        _rewrite(path, h_nm=np.ones((6, 12), np.float32))
    elif kind == "array radius":
        _rewrite(path, radius=np.ones(3))
    elif kind == "pickled h_nm":
        _rewrite(path, h_nm=np.array([{"a": 1}], dtype=object))
    elif kind == "integer h_nm":
        _rewrite(path, h_nm=np.ones((2, 6, 12), np.int64))
    elif kind == "beyond float32":
        _rewrite(path, h_nm=np.full((2, 6, 12), 1e300))
    elif kind == "negative":
        _rewrite(path, h_nm=-np.ones((2, 6, 12), np.float32))
    elif kind == "nan":
        _rewrite(path, h_nm=np.full((2, 6, 12), np.nan, np.float32))
    elif kind == "times not increasing":
        _rewrite(path, times=np.array([1.0, 1.0]))
    elif kind == "parameters not json":
        _rewrite(path, parameters=np.array("{" * 100_000))
    elif kind == "huge shape":  # the header of a (64, 4096, 8192) array, the data never read
        _declared_only(path, "h_nm", {"descr": "<f4", "fortran_order": False, "shape": (64, 4096, 8192)})
    elif kind == "size mismatch":  # a header that promises more data than the member holds
        _declared_only(path, "h_nm", {"descr": "<f4", "fortran_order": False, "shape": (2, 6, 12)}, b"\0" * 100)
    else:
        raise AssertionError(kind)


DAMAGED = {
    "truncated": "not a readable .npz archive",
    "corrupted": "film.npz:h_nm: cannot read its array header (BadZipFile: Bad CRC-32",
    "corrupted deep": "film.npz:h_nm: cannot read it (BadZipFile: Bad CRC-32",
    "random bytes": "not a readable .npz archive",
    "2-D h_nm": "film.npz:h_nm: must be a 3-D array",
    "array radius": "film.npz:radius: must have shape ()",
    "pickled h_nm": "film.npz:h_nm: must be float32 or float64",
    "integer h_nm": "film.npz:h_nm: must be float32 or float64",
    "beyond float32": "film.npz:h_nm: must be finite and >= 0 nanometres (frame 0",
    "negative": "film.npz:h_nm: must be finite and >= 0",
    "nan": "film.npz:h_nm: must be finite and >= 0",
    "times not increasing": "film.npz:times: must be finite and strictly increasing",
    "parameters not json": "film.npz:parameters: must be a JSON object",
    "huge shape": "film.npz:h_nm: 64 x 4096 x 8192 values are 8 GiB as float32, more than the 2 GiB",
    "size mismatch": "film.npz:h_nm: the archive says",
}


@pytest.mark.api
@pytest.mark.parametrize("kind", DAMAGED)
def test_a_damaged_series_file_is_one_line_naming_the_file_and_key(tmp_path, capsys, kind):
    """Each damage, through ``tracer image``: exit 2, one line ``SCENE:LINE: key: FILE:KEY: what``
    (no traceback, no advice to unpickle), nothing written; and the same from Python."""
    from bubbleoptics.filmflow.series import SeriesFileError

    film = tmp_path / "film.npz"
    series([500.0, 400.0]).save(film)
    _break(kind, film)
    path = write_scene(tmp_path, 'kind = "simulated"\npath = "film.npz"\n')
    status, out, err = run(["image", path, tmp_path / "out.png", "--width", "8", "--height", "8"], capsys)
    assert status == 2 and out == ""
    assert_one_line(err)
    assert err.startswith(f"{path}:") and "bubbles[0].film.path" in err and DAMAGED[kind] in err, err
    assert "allow_pickle" not in err and len(err) < 400
    assert sorted(p.name for p in tmp_path.iterdir()) == ["film.npz", "scene.toml"]
    with pytest.raises(SeriesFileError) as info:
        ThicknessSeries.load(film)
    assert "\n" not in str(info.value) and str(info.value).startswith(str(film))


@pytest.mark.api
def test_a_series_larger_than_the_memory_available_is_refused_before_reading(tmp_path, monkeypatch):
    from bubbleoptics.filmflow import series as series_module

    film = tmp_path / "film.npz"
    series([500.0] * 8, shape=(64, 128)).save(film)
    monkeypatch.setattr(series_module, "available_memory_bytes", lambda: 100_000)
    with pytest.raises(ValueError, match=r"film.npz:h_nm: 8 x 64 x 128 values need 0.00024\d* GiB as float32, more "
                                         r"than the 9.31e-05 GiB of memory available"):
        ThicknessSeries.load(film)


@pytest.mark.api
def test_a_series_is_read_a_frame_at_a_time(tmp_path):
    """Loading 16 float64 frames keeps the float32 result and about one frame more, not the
    float64 array, its float32 copy and whole-array temporaries of the checks."""
    import tracemalloc

    shape = (256, 512)
    frames = np.random.default_rng(1).random((16, *shape)) * 900.0
    film = tmp_path / "film.npz"
    ThicknessSeries(frames, np.arange(16.0), FilmGrid(*shape, 0.04), {}, "test").save(film)
    _rewrite(film, h_nm=frames)  # float64 on disk, as another writer might leave it
    tracemalloc.start()
    try:
        back = ThicknessSeries.load(film)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    result = back.h_nm.nbytes
    assert back.h_nm.dtype == np.float32 and np.array_equal(back.h_nm, frames.astype(np.float32))
    assert peak < result + 4 * frames[0].nbytes, (peak, result)  # the result, and a few float64 frames

"""The numbers of the movies chapter (paper/sections/movies.tex), a plug-in of make_numbers.py.

* ``movies``: ``data/derived/movie.csv`` (``benchmarks/movie.py``): serial against a Dask
  LocalCluster, Dask's overhead a frame, the encoder's share, one large image here and as row
  tiles, and the scaling model.  The model (a 3840x2160, 64-spp, one-minute movie on 8, 64 and
  512 one-core workers; assumptions in ``benchmarks/movie.py``'s docstring) is evaluated here
  again from the measured rows by :func:`study.movie_cost.model_movie_seconds` (the function the
  benchmark uses, with :data:`study.movie_cost.MODEL_MOVIE`), and checked against the benchmark's own model rows: a
  difference of more than 1 % makes the section n/a.
* ``moviefiles``: the example commands files in ``data/movies/`` (frames and what they do).
"""

from __future__ import annotations

import re

from macros import date_of, machine_of, read_commented_csv, significant
from paths import ROOT

MODEL_WORKERS = (8, 64, 512)
_WORDS = {8: "Eight", 64: "SixtyFour", 512: "FiveTwelve"}


def _tile_image():
    """The benchmark's large image (``TILE_IMAGE = dict(...)`` in ``benchmarks/movie.py``), read
    from its source text: the CSV does not record its samples per pixel."""
    text = (ROOT / "benchmarks" / "movie.py").read_text(encoding="utf-8")
    m = re.search(r"^TILE_IMAGE = dict\(([^)]*)\)", text, flags=re.MULTILINE)
    return {k.strip(): int(v) for k, v in (item.split("=") for item in m.group(1).split(","))}


def _tiles_per_worker():
    from tracer.rendering.dask import TILES_PER_WORKER

    return TILES_PER_WORKER


def _median_and_range(name, row, columns, scale, units):
    """``{NAME+unit: median, NAME+Min+unit: min, NAME+Max+unit: max}`` of *row*'s three *columns*
    (median, min, max) times *scale*, two significant digits."""
    return {f"{name}{tag}{unit}": significant(scale * float(row[column]), 2)
            for tag, column, unit in zip(("", "Min", "Max"), columns, units)}


def movies(dirs):
    notes, rows = read_commented_csv(dirs["derived"] / "movie.csv")
    from study.movie_cost import MODEL_MOVIE, model_movie_seconds

    by_case = {}
    for r in rows:
        by_case.setdefault(r["case"], []).append(r)
    (serial,), (dask,) = by_case["serial"], by_case["dask"]
    (here,), (tiles,) = by_case["image here"], by_case["image tiles"]
    f = lambda r, k: float(r[k])  # noqa: E731
    frames = int(f(dask, "frames"))
    size = int(f(dask, "width"))
    out = {
        "MovieDate": date_of(notes), "MovieMachine": machine_of(notes),
        "MovieFrames": str(frames), "MovieSize": str(size), "MovieWorkers": str(int(f(dask, "workers"))),
        "MovieSerialFps": significant(f(serial, "frames_per_second"), 2),
        "MovieDaskFps": significant(f(dask, "frames_per_second"), 2),
        "MovieEncodeShare": significant(100 * f(serial, "encode_share"), 2),
        "MovieFrameCpuS": significant(f(dask, "frame_cpu_seconds"), 2),
        "MovieFrameComputeS": significant(f(dask, "frame_compute_seconds"), 2),
        "MovieOverheadPercent": significant(100 * f(dask, "overhead_fraction"), 2),
        "MovieStartupS": significant(f(dask, "cluster_startup_seconds"), 2),
        "MovieFirstFrameS": significant(f(dask, "first_frame_seconds"), 2),
        "MovieTileWidth": str(int(f(here, "width"))), "MovieTileHeight": str(int(f(here, "height"))),
        "MovieTileSpp": str(_tile_image()["spp"]),
        "MovieTilesPerWorker": str(_tiles_per_worker()),
    }
    for name, row in (("MovieSerial", serial), ("MovieDask", dask), ("MovieImageHere", here), ("MovieImageTiles", tiles)):
        out.update(_median_and_range(name, row, ("seconds_median", "seconds_min", "seconds_max"), 1.0, ("S", "", "")))
    out.update(_median_and_range("MovieOverhead", dask, ("overhead_per_frame_seconds", "overhead_min", "overhead_max"),
                                 1e3, ("Ms", "Ms", "Ms")))
    load = re.search(r"load average ([0-9.]+) before, ([0-9.]+) after", notes[0])
    if load:
        out["MovieLoadBefore"], out["MovieLoadAfter"] = load.group(1), load.group(2)
    reps = re.search(r"(\d+) repeats", notes[0])
    if reps:
        out["MovieRepeats"] = reps.group(1)
    # the model, again, from the measured rows
    model = MODEL_MOVIE
    out.update(MovieModelWidth=str(model["width"]), MovieModelHeight=str(model["height"]),
               MovieModelSpp=str(model["spp"]), MovieModelFrames=str(model["frames"]),
               MovieModelMinutes=format(model["frames"] / 24 / 60, "g"))
    stored = {int(f(r, "workers")): r for r in rows if r["case"].startswith("model ")}
    encode_per_frame = f(dask, "encode_seconds_median") / frames
    for w in MODEL_WORKERS:
        seconds, frame, rounds, encode = model_movie_seconds(w, f(dask, "frame_cpu_seconds"),
                                                             f(dask, "overhead_per_frame_seconds"),
                                                             f(dask, "cluster_startup_seconds"), encode_per_frame,
                                                             size * size)
        if abs(seconds / f(stored[w], "seconds_median") - 1) > 0.01:
            raise ValueError(f"the model for {w} workers gives {seconds:.4g} s, the CSV {stored[w]['seconds_median']}")
        word = _WORDS[w]
        out[f"MovieModelHours{word}"] = significant(seconds / 3600, 2)
        out[f"MovieModelEfficiency{word}"] = significant(100 * model["frames"] * frame / (w * seconds), 2)
        out[f"MovieModelRounds{word}"] = str(rounds)
        out[f"MovieModelWorkers{word}"] = str(w)
        if w == MODEL_WORKERS[-1]:
            idle = rounds * w - model["frames"]  # workers without a frame in the last round
            out["MovieModelIdleLast"] = str(idle)
            out["MovieModelIdlePercent"] = significant(100 * idle / w, 2)
            out["MovieModelEncodeShare"] = significant(100 * encode / seconds, 2)
        if w == MODEL_WORKERS[0]:
            out["MovieModelFrameMin"] = significant(frame / 60, 2)
    return out


MOVIE_MACROS = (["MovieDate", "MovieMachine", "MovieFrames", "MovieSize", "MovieWorkers", "MovieSerialS", "MovieSerialMin",
                 "MovieSerialMax", "MovieDaskS", "MovieDaskMin", "MovieDaskMax", "MovieSerialFps", "MovieDaskFps",
                 "MovieEncodeShare", "MovieFrameCpuS", "MovieFrameComputeS", "MovieOverheadMs", "MovieOverheadMinMs",
                 "MovieOverheadMaxMs", "MovieOverheadPercent", "MovieStartupS", "MovieFirstFrameS", "MovieTileWidth",
                 "MovieTileHeight", "MovieImageHereS", "MovieImageHereMin", "MovieImageHereMax", "MovieImageTilesS",
                 "MovieImageTilesMin", "MovieImageTilesMax", "MovieTileSpp", "MovieLoadBefore", "MovieLoadAfter",
                 "MovieRepeats", "MovieModelWidth", "MovieModelHeight", "MovieModelSpp", "MovieModelFrames",
                 "MovieModelMinutes", "MovieModelEncodeShare", "MovieModelFrameMin",
                 "MovieModelIdleLast", "MovieModelIdlePercent", "MovieTilesPerWorker"]
                + [f"MovieModel{k}{_WORDS[w]}" for w in MODEL_WORKERS
                   for k in ("Hours", "Efficiency", "Rounds", "Workers")])


def movie_files(dirs):
    """The orbit example: its frames and degrees (``render K``, ``camera orbit D``)."""
    text = (dirs["data"] / "movies" / "builtin_orbit.txt").read_text(encoding="utf-8")
    body = "\n".join(line.split("#", 1)[0] for line in text.splitlines())
    renders = [int(x) for x in re.findall(r"^\s*render\s+(\d+)", body, flags=re.M)]
    orbit = re.findall(r"^\s*camera\s+orbit\s+([-0-9.eE]+)", body, flags=re.M)
    if not renders or len(orbit) != 1:
        raise ValueError("builtin_orbit.txt: expected renders and one camera orbit")
    return {"OrbitFrames": str(sum(renders)), "OrbitDegrees": format(float(orbit[0]), "g")}


SECTIONS = {
    "movies": (["derived/movie.csv", "benchmarks/movie.py"], movies, MOVIE_MACROS),
    "moviefiles": (["data/movies/builtin_orbit.txt"], movie_files, ["OrbitFrames", "OrbitDegrees"]),
}

"""A seeded mutator of scene files and command lines, and the contract every case must keep.

Used by ``tests/tracer/test_hardening.py`` (``test_fuzz_contract``, a bounded run in the suite) and runnable on its own for a long
hunt::

    python tests/support/fuzz_inputs.py --cases 1500 --seed 7

The contract: a run of ``tracer`` either exits 0 with a finite image written and nothing on
stderr (no warning, no traceback), or exits 2 with exactly one line on stderr and no file
written (no image, no temporary file).  The cases run in this process, calling
:func:`tracer.cli.main` (so a crash kills the run, and compiled kernels are reused).

The newer inputs have their own kinds of case (:data:`KINDS`), each under the same contract::

    python tests/support/fuzz_inputs.py --kind series --cases 200 --seed 7

``series``: damaged simulated-film files (bytes cut, overwritten or added; members replaced by
arrays of other shapes, dtypes and values, or by headers promising huge arrays) drawn by
``tracer image``; ``address``: ``--scheduler`` addresses of every scheme and shape (and a
server that answers junk) and ``--workers`` counts, to ``tracer image`` and ``tracer movie``;
``filmflow``: film-flow parameters, time steps and run lengths at their extremes, through the
Python API (a ValueError of one line, or a finite result); ``commands``: mutated movie commands
files rendered by ``tracer movie`` (frames capped at :data:`FUZZ_MAX_FRAMES` meanwhile, so that
a mutated ``render K`` stays cheap or is refused like any count beyond the cap).
"""

from __future__ import annotations

import contextlib
import io
import random
import re
import sys
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from net_helpers import JUNK, tcp_server  # tests/support/net_helpers.py

ROOT = Path(__file__).resolve().parents[2]
SCENES = sorted((ROOT / "data" / "scenes").glob("*.toml")) + sorted((ROOT / "data" / "scenes").glob("*.txt"))

#: Values a number in a file or an option may become: extremes, non-numbers, other scripts' digits.
EXTREMES = [
    "0", "-0", "1", "-1", "1e-300", "-1e-300", "1e-320", "1e300", "-1e300", "1e308", "-1e308", "1.7e308",
    "nan", "inf", "-inf", "18446744073709551616", "9223372036854775807", "-9223372036854775808",
    "1" * 400, "9" * 5000, "١٠٠", "３００", "0x10", "1_000", "", "abc", "1e", "--1", "1.5", "255", "256", "-255",
    "0.999999999", "1e-12", "1e12", "100000000",
]
#: Options and the values they may get on the command line.
OPTIONS = {
    "--depth": ["1", "2", "10", "24", "25", "1000", "1001", "0", "-1", "9223372036854775807", "1e3", "x"],
    "--spp": ["1", "2", "3", "65537", "0", "1e9", "2.5"],
    "--threshold": ["0", "1e-3", "1", "1e308", "-1e-3", "nan", "inf", "x"],
    "--spectral-samples": ["1", "2", "3", "16", "421", "422", "0", "100000000"],
    "--spectral-method": ["auto", "point", "band", "bogus"],
    "--seed": ["0", "1", "9223372036854775807", "18446744073709551616", "-1"],
    "--background": ["0,0,0", "0.5,0.5,0.5", "1e308,1e308,1e308", "nan,0,0", "1,2", "-1,0,0"],
    "--bits": ["8", "16", "12"],
    "--width": ["1", "7", "0", "65536", "1e9", "３"],
    "--height": ["1", "5", "0", "-5", "1e9"],
    "--exposure": ["0", "2", "-3.5", "64", "65", "nan", "x"],
    "--view": ["clip", "aces", "agx"],
}

_NUMBER_TOKEN = re.compile(r"(?<![\w.])[+-]?(?:\d+\.?\d*(?:[eE][+-]?\d+)?|\.\d+)(?![\w.])", re.ASCII)


@dataclass
class Case:
    """One run: a scene text (or None: the built-in scene), its suffix, and the options."""

    name: str
    text: str | None
    suffix: str
    options: list
    out_suffix: str = ".png"


def mutate_text(rng: random.Random, text: str) -> str:
    """*text* with one to three random edits: a number replaced by an extreme, a line deleted,
    duplicated or swapped, the file cut short, or a character inserted."""
    for _ in range(rng.randint(1, 3)):
        lines = text.split("\n")
        kind = rng.random()
        if kind < 0.6:
            spans = [m.span() for m in _NUMBER_TOKEN.finditer(text)]
            if spans:
                a, b = rng.choice(spans)
                text = text[:a] + rng.choice(EXTREMES) + text[b:]
                continue
        if kind < 0.7 and len(lines) > 1:
            del lines[rng.randrange(len(lines))]
        elif kind < 0.8:
            i = rng.randrange(len(lines))
            lines.insert(i, lines[i])
        elif kind < 0.88 and len(lines) > 1:
            i, j = rng.randrange(len(lines)), rng.randrange(len(lines))
            lines[i], lines[j] = lines[j], lines[i]
        elif kind < 0.94:
            return text[: rng.randrange(len(text) + 1)]
        else:
            pos = rng.randrange(len(text) + 1)
            text = text[:pos] + rng.choice(["[", "]", "=", '"', "#", "\t", "\x00", "é", " "]) + text[pos:]
            continue
        text = "\n".join(lines)
    return text


def make_cases(n: int, seed: int = 0) -> list[Case]:
    """*n* cases: mostly mutated scene files rendered tiny, some mutated command lines."""
    rng = random.Random(seed)
    sources = [(p.name, p.read_text(encoding="utf-8"), p.suffix) for p in SCENES]
    cases = []
    for i in range(n):
        name, text, suffix = rng.choice(sources)
        options = ["--width", "6", "--height", "5", "--quiet"]
        if rng.random() < 0.75:
            text = mutate_text(rng, text)
            name = f"{i}:{name} mutated"
        if rng.random() < 0.35:
            for opt in rng.sample(sorted(OPTIONS), rng.randint(1, 3)):
                options += [opt, rng.choice(OPTIONS[opt])]
            name += " " + " ".join(options[5:])
        if rng.random() < 0.05:
            text, suffix = None, ""
        cases.append(Case(name, text, suffix, options, rng.choice([".png", ".png", ".png", ".npy", ".exr", ".hdr",
                                                                   ".npz"])))
    return cases


def run_case(case: Case, folder: Path):
    """Run *case* in *folder* (empty); returns ``(status, stderr, out path, warnings)``."""
    from tracer.cli import main

    out = folder / f"out{case.out_suffix}"
    args = ["image"]
    if case.text is not None:
        scene = folder / f"scene{case.suffix}"
        scene.write_text(case.text, encoding="utf-8", errors="surrogateescape")
        args.append(str(scene))
    args += [str(out)] + case.options
    err = io.StringIO()
    with warnings.catch_warnings(record=True) as caught, contextlib.redirect_stderr(err):
        warnings.simplefilter("always")
        with np.errstate(divide="warn", over="warn", invalid="warn", under="ignore"):  # NumPy's defaults
            try:
                status = main(args)
            except SystemExit as exc:  # argparse's exit (status 2 with a one-line message)
                status = exc.code
            except Exception as exc:  # a traceback the user would have seen
                import traceback

                frame = traceback.extract_tb(exc.__traceback__)[-1]
                status = f"an exception: {type(exc).__name__}: {exc} ({frame.filename}:{frame.lineno})"
    return status, err.getvalue(), out, [str(w.message) for w in caught]


def check_case(case: Case, folder: Path) -> str | None:
    """None if *case* keeps the contract, else what broke it."""
    status, err, out, caught = run_case(case, folder)
    left = sorted(p.name for p in folder.iterdir() if not p.name.startswith("scene"))
    if status == 0:
        # the one thing exit 0 may print: a scene file's own warnings (FILE:LINE: ... skipped)
        err = "".join(line for line in err.splitlines(True) if not re.match(r".*scene\.\w+:\d+: .*skipped", line))
        if err or caught:
            return f"exit 0 but printed {err!r} / warnings {caught}"
        if not out.is_file():
            return "exit 0 but no image"
        if case.out_suffix == ".npy" and not np.all(np.isfinite(np.load(out))):
            return "exit 0 with a non-finite image"
        if case.out_suffix == ".npz" and not np.all(np.isfinite(np.load(out)["radiance"])):
            return "exit 0 with a non-finite spectral image"
        if left != [out.name]:
            return f"exit 0 but left {left}"
        return None
    if status == 2:
        return _one_line(status, err, (), left)
    return f"exit {status}: {err[-2000:]!r}"


def replay(n, seed, index):
    """Case *index* of ``make_cases(n, seed)`` run with warnings as errors (for its traceback)."""
    import tempfile

    case = make_cases(n, seed)[index]
    with tempfile.TemporaryDirectory() as tmp:
        if case.text is not None:
            print(case.text)
        print(case.options)
        with warnings.catch_warnings(), np.errstate(divide="raise", over="raise", invalid="raise"):
            warnings.simplefilter("error")
            from tracer.cli import _main

            args = ["image"] + ([str(Path(tmp) / f"scene{case.suffix}")] if case.text is not None else [])
            if case.text is not None:
                Path(args[1]).write_text(case.text, encoding="utf-8", errors="surrogateescape")
            _main(args + [str(Path(tmp) / f"out{case.out_suffix}")] + case.options)


# ------------------------------------------------------------------------------------------
# the newer inputs: series files, Dask addresses, film-flow parameters, movie commands
# ------------------------------------------------------------------------------------------
#: The kinds of case of the newer inputs (``make_input_cases``).
KINDS = ("series", "address", "filmflow", "commands")
#: The most frames a fuzzed movie may have (tracer.movie.timeline.MAX_FRAMES meanwhile).
FUZZ_MAX_FRAMES = 12

SIMULATED_SCENE = ('[camera]\nposition = [0, 0.3, 4]\nlook_at = [0, 0, 0]\nfov_deg = 40\n[environment]\n'
                   'kind = "sky"\n[[bubbles]]\nname = "b"\ncenter = [0, 0, 0]\nradius = 1\n'
                   '[bubbles.film]\nkind = "simulated"\npath = "film.npz"\ntime = 0.5\n')


@dataclass
class InputCase:
    """One case of a newer input: its *kind* (:data:`KINDS`), a name saying what it is, and
    what it needs (``data``: the series file's bytes, the command line, the API call, the
    commands text)."""

    kind: str
    name: str
    data: dict


def _series_bytes(rng: random.Random) -> tuple[bytes, str]:
    """A damaged (or, now and then, intact) series file and what was done to it."""
    import io
    import zipfile

    from bubbleoptics.filmflow import FilmGrid, ThicknessSeries

    nrng = np.random.default_rng(rng.randrange(2**32))
    nt, nph = rng.choice([(4, 8), (6, 12), (5, 7)])
    n = rng.randint(1, 3)
    h = nrng.random((n, nt, nph)) * 900.0
    buf = io.BytesIO()
    series = ThicknessSeries(h, np.arange(n, dtype=float), FilmGrid(nt, nph, 0.04), {"seed": 1}, "fuzz")
    with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as z:
        members = dict(format=np.array("bubbleoptics.filmflow.ThicknessSeries/1"), h_nm=series.h_nm,
                       times=series.times, theta=series.grid.theta, phi=series.grid.phi,
                       radius=np.array(series.grid.radius), model=np.array("fuzz"),
                       parameters=np.array('{"seed": 1}'))
        what = "intact"
        kind = rng.random()
        if kind < 0.45:  # a member replaced
            key = rng.choice(sorted(members))
            value = rng.choice([
                np.float64(1e300), np.array(np.nan), np.zeros(0), np.ones((2, 2)), np.ones((1, 4, 8, 2)),
                np.full((n, nt, nph), -1.0), np.full((n, nt, nph), np.inf), np.full((n, nt, nph), 1e300),
                np.ones((n, nt, nph), dtype=np.int16), np.ones((n, nt, nph), dtype=bool),
                np.ones((n, nt, nph), dtype=complex), np.array(["x"] * 3), np.array("x" * 300),
                np.array([3.0, 1.0, 2.0][:n]), np.array("[" * 5000), np.array("[1, 2]"), np.array(1e-300),
                np.asfortranarray(h.transpose(0, 2, 1)).transpose(0, 2, 1), np.array(-0.04), np.array(1e20),
                np.array([{"a": 1}], dtype=object),
            ])
            members[key] = value
            what = f"{key} = {getattr(value, 'dtype', '?')} {getattr(value, 'shape', '?')}"
        elif kind < 0.55:  # a member missing
            key = rng.choice(sorted(members))
            del members[key]
            what = f"no {key}"
        elif kind < 0.65:  # a header that promises a huge array
            key = rng.choice(["h_nm", "times", "parameters"])
            head = io.BytesIO()
            shape = rng.choice([(64, 4096, 8192), (2**40,), (1, 4096, 8192), (10**6, 4, 4)])
            np.lib.format.write_array_header_1_0(head, {"descr": "<f4" if key != "parameters" else "<U1000000",
                                                        "fortran_order": False, "shape": shape})
            z.writestr(f"{key}.npy", head.getvalue() + b"\0" * rng.randrange(0, 4096))
            del members[key]
            what = f"{key} header {shape}"
        for key, value in members.items():
            with z.open(f"{key}.npy", "w") as f:
                np.lib.format.write_array(f, np.asanyarray(value), allow_pickle=True)
    raw = bytearray(buf.getvalue())
    kind = rng.random()
    if what == "intact" and kind < 0.3:
        cut = rng.randrange(len(raw))
        raw = raw[:cut]
        what = f"cut at {cut} of {len(buf.getvalue())}"
    elif what == "intact" and kind < 0.6:
        at, k = rng.randrange(len(raw)), rng.randint(1, 64)
        raw[at:at + k] = bytes(rng.randrange(256) for _ in range(min(k, len(raw) - at)))
        what = f"{k} bytes overwritten at {at}"
    elif what == "intact" and kind < 0.7:
        raw = bytearray(rng.randbytes(rng.randrange(1, 2000)))
        what = "random bytes"
    return bytes(raw), what


def _address(rng: random.Random, junk):
    scheme = rng.choice(["tcp://", "tcp://", "TCP://", "", "tls://", "inproc://", "ucx://", "ws://", "wss://",
                         "http://", "tcp:/", "tcp:///", "://", "unix://"])
    host = rng.choice(["127.0.0.1", "localhost", "", "[::1]", "::1", "a b", "é", "h" * 300, "127.0.0.1/x",
                       "user@127.0.0.1", "[::1", "0.0.0.0"])
    port = rng.choice([":1", ":1", ":0", ":65536", ":x", ":" + "9" * 50, ":-1", ":1:2", ":", ":８７８６"])
    if rng.random() < 0.1:
        return junk  # a server that answers junk
    return scheme + host + port


def make_input_cases(kind: str, n: int, seed: int = 0) -> list[InputCase]:
    """*n* cases of the newer input *kind* (:data:`KINDS`) from *seed*."""
    import os

    rng = random.Random(f"{kind}:{seed}")
    cases = []
    if kind == "series":
        for i in range(n):
            raw, what = _series_bytes(rng)
            cases.append(InputCase(kind, f"{i}: {what}", {"film": raw}))
    elif kind == "address":
        cores = len(os.sched_getaffinity(0))
        for i in range(n):
            command = rng.choice(["image", "movie"])
            if rng.random() < 0.7:
                option = ["--scheduler", None]  # the address is filled in at run time (the junk server's port)
                pick = rng.random()
            else:
                option = ["--workers", rng.choice(["0", "-1", "x", "1.5", str(cores + 1), "1024", "1" * 400, "١",
                                                   "", "1e3"])]
                pick = None
            cases.append(InputCase(kind, f"{i}: {command} {option[0]}", {"command": command, "option": option,
                                                                         "pick": pick, "rng": rng.random()}))
    elif kind == "filmflow":
        from bubbleoptics.filmflow.limits import PARAMETER_LIMITS

        values = [0, 0.0, -0.0, -1.0, 1e-300, 1e300, 1.7e308, float("nan"), float("inf"), -float("inf"), 10**400,
                  True, "1", None, np.float32(0.5), np.int64(2), 0.5, 1e-6, 2e-6, 1.0]
        for i in range(n):
            kw = {}
            for name in rng.sample(sorted(PARAMETER_LIMITS), rng.randint(0, 3)):
                lo, hi, _, _ = PARAMETER_LIMITS[name]
                kw[name] = rng.choice(values + [lo, hi, lo / 2 if lo else -1e-9, hi * 2, lo * 1.0000001])
            call = {"kw": kw, "model": rng.choice(["RigidDrainage", "PlugFlow"]),
                    "what": rng.choice(["run", "run", "step"]),
                    "t_end": rng.choice(values + [0.01, 0.02, 1e9, 1e10, 1e-9]),
                    "dt": rng.choice(values + [0.005, 0.01, 1e-9, 1e6, 1e7]),
                    "save_every": rng.choice([1, 2, 0, -1, 1.5, True, 10**30, np.int64(3)])}
            cases.append(InputCase(kind, f"{i}: {call}", call))
    elif kind == "commands":
        bases = {"coursework_drift.txt": (ROOT / "data" / "scenes" / "coursework_three_bubbles.txt",
                                          "render 1\nmove пузырь3 1200 -100 0\nset пузырь3 thickness 100\n"
                                          "camera orbit 5\nlight 1 0 0 1000 2\nrender 3\n"),
                 "builtin_orbit.txt": (None, "camera orbit 360\nscale old 1.5\nrotate old 0 1 0 45\n"
                                             "light add 1 2 3 1\ncamera fov 30\ntime 2\nrender 4\n")}
        for i in range(n):
            name = rng.choice(sorted(bases))
            scene, text = bases[name]
            for _ in range(rng.randint(0, 2)):
                text = mutate_text(rng, text)
            out = rng.choice(["m", "m.gif", "m.mp4"] * 3 + ["m.png"])
            cases.append(InputCase(kind, f"{i}: {name} mutated -> {out}", {"scene": scene, "text": text, "out": out}))
    else:
        raise ValueError(f"kind must be one of {', '.join(KINDS)}, got {kind!r}")
    return cases


def _cli(args):
    """``(status, stderr, warnings)`` of ``tracer ARGS`` in this process."""
    from tracer.cli import main

    err = io.StringIO()
    with warnings.catch_warnings(record=True) as caught, contextlib.redirect_stderr(err):
        warnings.simplefilter("always")
        with np.errstate(divide="warn", over="warn", invalid="warn", under="ignore"):
            try:
                status = main([str(a) for a in args])
            except SystemExit as exc:
                status = exc.code
            except Exception as exc:  # a traceback the user would have seen
                import traceback

                frame = traceback.extract_tb(exc.__traceback__)[-1]
                status = f"an exception: {type(exc).__name__}: {exc} ({frame.filename}:{frame.lineno})"
    return status, err.getvalue(), [str(w.message) for w in caught if "distributed" not in str(w.filename)]


def _one_line(status, err, caught, left, allowed_left=()):
    """The exit-2 half of the contract: one short line, no warning, nothing written."""
    lines = err.rstrip("\n").split("\n")
    if len(lines) != 1 or not lines[0]:
        return f"exit 2 with {len(lines)} lines: {err[-1500:]!r}"
    if len(lines[0]) > 400:
        return f"exit 2 with a {len(lines[0])}-character line"
    if caught:
        return f"exit 2 with warnings {caught}"
    extra = sorted(set(left) - set(allowed_left))
    return f"exit 2 but left {extra}" if extra else None


def check_input_case(case: InputCase, folder: Path, junk_address=None) -> str | None:
    """None if *case* keeps the contract (run in the empty *folder*), else what broke it."""
    if case.kind == "filmflow":
        return _check_filmflow(case)
    inputs = set()
    if case.kind == "series":
        (folder / "film.npz").write_bytes(case.data["film"])
        (folder / "scene.toml").write_text(SIMULATED_SCENE, encoding="utf-8")
        inputs = {"film.npz", "scene.toml"}
        out = folder / "out.png"
        args = ["image", folder / "scene.toml", out, "--width", "6", "--height", "5", "--quiet"]
    elif case.kind == "address":
        (folder / "c.txt").write_text("render 2\n")
        inputs = {"c.txt"}
        option = list(case.data["option"])
        if option[1] is None:
            option[1] = _address(random.Random(case.data["rng"]), junk_address or "tcp://127.0.0.1:1")
        out = folder / ("out.png" if case.data["command"] == "image" else "m")
        args = [case.data["command"], out] + ([folder / "c.txt"] if case.data["command"] == "movie" else [])
        args += ["--width", "4", "--height", "4", "--quiet"] + option
    else:  # commands
        (folder / "c.txt").write_text(case.data["text"], encoding="utf-8", errors="surrogateescape")
        inputs = {"c.txt"}
        out = folder / case.data["out"]
        args = ["movie"] + ([case.data["scene"]] if case.data["scene"] else []) + [out, folder / "c.txt",
                                                                                    "--width", "4", "--height", "4",
                                                                                    "--depth", "2", "--quiet"]
    if case.kind == "commands":
        from tracer.movie import timeline as movie_timeline

        saved, movie_timeline.MAX_FRAMES = movie_timeline.MAX_FRAMES, FUZZ_MAX_FRAMES
        try:
            status, err, caught = _cli(args)
        finally:
            movie_timeline.MAX_FRAMES = saved
    else:
        status, err, caught = _cli(args)
    left = sorted(p.name for p in folder.iterdir() if p.name not in inputs)
    if status == 2:
        return _one_line(status, err, caught, left)
    if status != 0:
        return f"exit {status}: {err[-2000:]!r}"
    if err or caught:
        return f"exit 0 but printed {err!r} / warnings {caught}"
    if case.kind == "address":
        return f"exit 0 for {args[-2:]}: the address or count should have been refused"
    expected = [out.name] + ([out.name + ".cache"] if case.kind == "commands" else [])
    if left != sorted(expected):
        return f"exit 0 but left {left} (expected {sorted(expected)})"
    if case.kind == "series":
        import imageio.v3 as iio

        if not np.all(np.isfinite(iio.imread(out))):
            return "exit 0 with a non-finite image"
    return None


def _check_filmflow(case: InputCase) -> str | None:
    from bubbleoptics.filmflow import FilmGrid, FilmParameters, PlugFlow, RigidDrainage

    d = case.data
    t_end, dt = d["t_end"], d["dt"]
    try:  # a valid run of many steps is cut to a few (the limits are what is fuzzed, not the models' speed)
        if float(t_end) / float(dt) > 40 and 1e-9 <= float(dt) <= 1e6:
            t_end = float(dt) * 7
    except (TypeError, ValueError, OverflowError, ZeroDivisionError):
        pass
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with np.errstate(divide="warn", over="warn", invalid="warn", under="ignore"):
            try:
                p = FilmParameters(**d["kw"])
                model = {"RigidDrainage": RigidDrainage, "PlugFlow": PlugFlow}[d["model"]](p, FilmGrid(4, 8, p.radius))
                if d["what"] == "run":
                    result = model.run(t_end=t_end, dt=dt, save_every=d["save_every"], seed=0).h_nm
                else:
                    s = model.step(model.initial_state(0), dt)
                    result = s.h
            except ValueError as err:
                text = str(err)
                if "\n" in text or len(text) > 400 or not text:
                    return f"a ValueError of {text.count(chr(10)) + 1} lines / {len(text)} characters: {text[:300]!r}"
                result = None
            except Exception as err:  # noqa: BLE001 - anything else is a failure of the contract
                return f"an exception: {type(err).__name__}: {err}"
    if caught:
        return f"warnings {[str(w.message) for w in caught]}"
    if result is not None and not (np.all(np.isfinite(result)) and result.min() >= 0):
        return "a result that is not finite and >= 0"
    return None


def run_input_cases(kind: str, n: int, seed: int, folder: Path) -> list[str]:
    """Run ``make_input_cases(kind, n, seed)`` in subfolders of *folder*; the failures."""
    failures = []
    with tcp_server(JUNK) as junk:
        for i, case in enumerate(make_input_cases(kind, n, seed)):
            sub = folder / f"{kind}-{i}"
            sub.mkdir()
            problem = check_input_case(case, sub, junk)
            if problem:
                failures.append(f"{case.name}: {problem}")
    return failures


def main(argv=None):
    import argparse
    import tempfile

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--cases", type=int, default=300)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--kind", choices=("image",) + KINDS, default="image",
                   help="scene files and options of tracer image (image), or one of the newer inputs")
    p.add_argument("--replay", type=int, help="run this case with warnings as errors and show its traceback")
    a = p.parse_args(argv)
    if a.kind != "image":
        with tempfile.TemporaryDirectory() as tmp:
            failures = run_input_cases(a.kind, a.cases, a.seed, Path(tmp))
        for f in failures:
            print(f)
        print(f"{a.cases} {a.kind} cases (seed {a.seed}), {len(failures)} broke the contract")
        return 1 if failures else 0
    if a.replay is not None:
        return replay(a.cases, a.seed, a.replay)
    failures = 0
    for case in make_cases(a.cases, a.seed):
        with tempfile.TemporaryDirectory() as tmp:
            problem = check_case(case, Path(tmp))
        if problem:
            failures += 1
            print(f"{case.name}: {problem}")
    print(f"{a.cases} cases, {failures} broke the contract")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

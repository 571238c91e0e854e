"""A seeded mutator of scene files and command lines, and the contract every case must keep.

Used by ``tests/test_fuzz.py`` (a bounded run in the suite) and runnable on its own for a long
hunt::

    python tests/fuzz_inputs.py --cases 1500 --seed 7

The contract (issue 9): a run of ``tracer`` either exits 0 with a finite image written and
nothing on stderr (no warning, no traceback), or exits 2 with exactly one line on stderr and no
file written (no image, no temporary file).  The cases run in this process, calling
:func:`tracer.cli.main` (so a crash kills the run, and compiled kernels are reused).
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

ROOT = Path(__file__).resolve().parents[1]
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
        lines = err.rstrip("\n").split("\n")
        if len(lines) != 1 or not lines[0]:
            return f"exit 2 with {len(lines)} lines: {err!r}"
        if len(lines[0]) > 400:
            return f"exit 2 with a {len(lines[0])}-character line"
        if left:
            return f"exit 2 but left {left}"
        return None
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


def main(argv=None):
    import argparse
    import tempfile

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--cases", type=int, default=300)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--replay", type=int, help="run this case with warnings as errors and show its traceback")
    a = p.parse_args(argv)
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

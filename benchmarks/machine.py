"""The machine the benchmarks run on: its CPU, memory and software, in a second.

Run:  python benchmarks/machine.py [--out PATH]
Writes ``data/derived/machine.csv`` (``quantity,value`` rows).

Every benchmark's header (:func:`study.provenance`) names the architecture, the number of cores
and, since this file was added, the CPU model (:func:`study.results.cpu_model`: ``/proc/cpuinfo``'s
``model name`` with its family and model numbers).  Headers written before that name no model;
this file records it, with what else a reader comparing timings needs (clock, cache, memory, the
cores this process may use, the versions of Python, NumPy and numba).  ``make bench`` runs it
first.  Nothing is timed.
"""

from __future__ import annotations

import argparse
import os
import platform
from pathlib import Path

from study import provenance, write_csv
from study.results import cpu_model

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "data" / "derived" / "machine.csv"


def _first_fields(path):
    """{key: value} of the first block of a ``key : value`` file (``/proc/cpuinfo``), {} without it."""
    fields = {}
    try:
        with open(path, encoding="utf-8", errors="replace") as lines:
            for line in lines:
                key, sep, value = line.partition(":")
                if not sep:
                    if fields:
                        break
                    continue
                fields.setdefault(key.strip(), " ".join(value.split()))
    except OSError:
        pass
    return fields


def rows():
    """The ``(quantity, value)`` rows of machine.csv (values as text; empty where unknown)."""
    import numba
    import numpy

    cpu = _first_fields("/proc/cpuinfo")
    memory = _first_fields("/proc/meminfo")
    usable = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    values = {
        "cpu_model": cpu_model(),
        "vendor": cpu.get("vendor_id", ""),
        "cpu_mhz": cpu.get("cpu MHz", ""),
        "cache": cpu.get("cache size", ""),
        "logical_cpus": str(os.cpu_count()),
        "usable_cpus": str(usable),
        "memory_total": memory.get("MemTotal", ""),
        "machine": platform.machine(),
        "system": f"{platform.system()} {platform.release()}",
        "python": platform.python_version(),
        "numpy": numpy.__version__,
        "numba": numba.__version__,
    }
    return [{"quantity": key, "value": value} for key, value in values.items()]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=OUT, help="the file to write (default data/derived/machine.csv)")
    args = parser.parse_args(argv)
    path = write_csv(args.out, rows(), provenance("benchmarks/machine.py", "nothing timed; "
                                                  "regenerate with: python benchmarks/machine.py"),
                     lineterminator="\n")
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

"""The CPU model of the machine the benchmarks ran on, from the benchmarks' headers.

* ``machine``: every ``data/derived/*.csv``; the header that :func:`study.provenance` writes names
  the CPU model (``; CPU AMD EPYC (family 25, model 17);``, from ``/proc/cpuinfo``) since
  ``benchmarks/machine.py`` was added; the newest such header gives ``\\CpuModel`` and its date
  ``\\CpuModelDate``, the oldest such date ``\\CpuModelFirstDate`` (files written earlier name only the architecture and the cores, so their
  headers count for nothing here, but are counted: ``\\CpuUnnamedCount`` of them against
  ``\\CpuNamedCount`` that name a model, ``\\CpuModelCount`` distinct models, listed with the number of files of each in ``\\CpuModelList``).  No header with a model:
  all n/a, with a warning.

A plug-in of :mod:`make_numbers` (its ``SECTIONS`` format).
"""

from macros import cpu_model_of, date_of


def _header(path):
    """The leading ``#`` comment lines of *path*, without the ``#``."""
    notes = []
    with open(path, encoding="utf-8") as lines:
        for line in lines:
            if not line.startswith("#"):
                break
            notes.append(line[1:].strip())
    return notes


def machine(dirs):
    named, unnamed = [], 0
    for path in sorted(dirs["derived"].glob("*.csv")):
        notes = _header(path)
        try:
            named.append((date_of(notes), path.name, cpu_model_of(notes)))
        except ValueError:
            unnamed += 1
            continue
    if not named:
        raise ValueError("no header of data/derived/*.csv names the CPU model (run benchmarks/machine.py)")
    date, _, model = max(named)
    models = sorted({m for _, _, m in named})
    per_model = [(sum(1 for _, _, m in named if m == name), name) for name in models]
    listed = [f"{name} in {count}" for count, name in sorted(per_model, reverse=True)]
    model_list = listed[0] if len(listed) == 1 else ", ".join(listed[:-1]) + " and " + listed[-1]
    return {"CpuModel": model, "CpuModelDate": date, "CpuModelFirstDate": min(named)[0],
            "CpuNamedCount": str(len(named)),
            "CpuUnnamedCount": str(unnamed), "CpuModelCount": str(len(models)), "CpuModelList": model_list}


SECTIONS = {"machine": (["derived/*.csv (the CPU model in their headers)"], machine,
                        ["CpuModel", "CpuModelDate", "CpuModelFirstDate", "CpuNamedCount", "CpuUnnamedCount", "CpuModelCount",
                         "CpuModelList"])}

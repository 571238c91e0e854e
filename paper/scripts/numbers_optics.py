"""The optics-speed table's numbers, a plug-in of ``make_numbers.py``.

* ``optics``: ``data/derived/optics_speed.csv`` (``benchmarks/optics_speed.py``, ``make bench``).
"""

from __future__ import annotations

import re

from macros import (NA, date_of, group_digits, load_average_of, machine_of, read_commented_csv, scientific, significant,
                    up_to)

#: where these macros stand in numbers.tex (make_numbers.py)
ORDER = 1


def _range(lo, hi, n=2):
    """'[3.9, 4.6]': a range of runs, each end to *n* significant digits."""
    return f"[{significant(lo, n)}, {significant(hi, n)}]"


def optics(dirs):
    """The optics table (``benchmarks/optics_speed.py``): medians, and the fastest and slowest runs
    (``min_seconds``, ``max_seconds``) and range of each ratio (``ratio_min``, ``ratio_max``) as
    ``*Range`` macros, ``[lo, hi]``; the machine's load average from the header.

    Ours is timed with one thread and with two (column ``threads``), the peers with one: the
    plain macros (``SweepMsOurs``, ``NsOurs``, ``SpeedupColour`` ...) are ours with one thread and
    the peers' ratios to it (like for like), the ``...Two`` ones ours with two threads and the
    ratios to that, ``OursThreadSpeedup`` and ``XYZThreadSpeedup`` ours' speed-up from one thread
    to two (all from the same run, paired within its rounds)."""
    notes, rows = read_commented_csv(dirs["derived"] / "optics_speed.csv")
    sweep = [r for r in rows if r["case"] == "sweep"]

    def pick(rows_, test, threads="1"):
        found = [r for r in rows_ if test(r["implementation"]) and r["threads"] == threads]
        if len(found) != 1:
            raise ValueError(f"expected one matching row, found {len(found)}")
        return found[0]

    impl = {
        "Ours": pick(sweep, lambda s: s.startswith("bubbleoptics.")),
        "OursTwo": pick(sweep, lambda s: s.startswith("bubbleoptics."), "2"),
        "Colour": pick(sweep, lambda s: "thin_film_tmm" in s),
        "Numpy": pick(sweep, lambda s: "NumPy" in s),
        "Tmm": pick(sweep, lambda s: s.startswith("tmm.")),
    }
    ours = impl["Ours"]
    points = float(ours["median_seconds"]) / (float(ours["ns_per_evaluation"]) * 1e-9)
    before, after = load_average_of(notes)
    out = {
        "OpticsMachine": machine_of(notes),
        "OpticsDate": date_of(notes),
        "OpticsLoadBefore": before,
        "OpticsLoadAfter": after,
        "SweepPoints": group_digits(str(int(round(points, -3)))),
    }
    for key, r in impl.items():
        ms = 3 if key == "Tmm" else 2
        out[f"SweepMs{key}"] = significant(1e3 * float(r["median_seconds"]), ms)
        out[f"SweepMsRange{key}"] = _range(1e3 * float(r["min_seconds"]), 1e3 * float(r["max_seconds"]), ms)
        out[f"SweepRepeats{key}"] = str(int(r["repeats"]))
        out[f"Ns{key}"] = significant(float(r["ns_per_evaluation"]), 2 if key != "Colour" else 3)
        if not key.startswith("Ours"):
            n = 3 if key in ("Colour", "Tmm") else 2
            out[f"Speedup{key}"] = significant(float(r["ratio_to_bubbleoptics"]), n)
            out[f"SpeedupRange{key}"] = _range(float(r["ratio_min"]), float(r["ratio_max"]), n)
            out[f"Speedup{key}Two"] = significant(float(r["ratio_to_bubbleoptics_2_threads"]), n)
            out[f"SpeedupRange{key}Two"] = _range(float(r["ratio_2_threads_min"]), float(r["ratio_2_threads_max"]), n)
            out[f"Dev{key}"] = up_to(float(r["max_abs_deviation_from_bubbleoptics"]), 2, form="scientific")  # a maximum: "by up to"
    # one thread over two: ours' one-thread row over ours with two, paired within a round
    out["OursThreadSpeedup"] = significant(float(ours["ratio_to_bubbleoptics_2_threads"]), 2)
    out["OursThreadSpeedupRange"] = _range(float(ours["ratio_2_threads_min"]), float(ours["ratio_2_threads_max"]))
    two = impl["OursTwo"]  # ours with two threads over ours with one
    out["OursTwoRatio"] = significant(float(two["ratio_to_bubbleoptics"]), 2)
    out["OursTwoRatioRange"] = _range(float(two["ratio_min"]), float(two["ratio_max"]))
    m = re.search(r"colour-science (\d+(?:\.\d+)+)", impl["Colour"]["implementation"])
    out["ColourVersion"] = m.group(1) if m else NA
    m = re.search(r"(\d+) points", impl["Tmm"]["implementation"])
    out["TmmSampled"] = m.group(1) if m else NA
    xyz = [r for r in rows if r["case"].startswith("spectrum_to_XYZ")]
    xyz_ours = pick(xyz, lambda s: s.startswith("bubbleoptics."))
    xyz_two = pick(xyz, lambda s: s.startswith("bubbleoptics."), "2")
    xyz_colour = pick(xyz, lambda s: s.startswith("colour-science"))
    for key, r in (("XYZOursUs", xyz_ours), ("XYZOursTwoUs", xyz_two)):
        out[key] = significant(1e6 * float(r["median_seconds"]), 2)
        out[f"{key}Range"] = _range(1e6 * float(r["min_seconds"]), 1e6 * float(r["max_seconds"]), 2)
    out["XYZColourUs"] = significant(1e6 * float(xyz_colour["median_seconds"]), 3)
    out["XYZColourUsRange"] = _range(1e6 * float(xyz_colour["min_seconds"]), 1e6 * float(xyz_colour["max_seconds"]),
                                     3)
    out["SpeedupXYZ"] = significant(float(xyz_colour["ratio_to_bubbleoptics"]), 3)
    out["SpeedupXYZRange"] = _range(float(xyz_colour["ratio_min"]), float(xyz_colour["ratio_max"]), 3)
    out["SpeedupXYZTwo"] = significant(float(xyz_colour["ratio_to_bubbleoptics_2_threads"]), 3)
    out["SpeedupXYZTwoRange"] = _range(float(xyz_colour["ratio_2_threads_min"]),
                                       float(xyz_colour["ratio_2_threads_max"]), 3)
    out["XYZThreadSpeedup"] = significant(float(xyz_ours["ratio_to_bubbleoptics_2_threads"]), 2)
    out["XYZThreadSpeedupRange"] = _range(float(xyz_ours["ratio_2_threads_min"]),
                                          float(xyz_ours["ratio_2_threads_max"]))
    out["XYZDev"] = scientific(float(xyz_colour["max_abs_deviation_from_bubbleoptics"]), 1)
    m = re.search(r"\((\d+) samples\)", xyz_ours["case"])
    out["XYZSamples"] = m.group(1) if m else NA
    return out


_IMPLS = ("Ours", "OursTwo", "Colour", "Numpy", "Tmm")
_PEERS = ("Colour", "Numpy", "Tmm")
OPTICS_MACROS = (
    ["OpticsMachine", "OpticsDate", "OpticsLoadBefore", "OpticsLoadAfter", "SweepPoints"]
    + [f"SweepMs{k}" for k in _IMPLS]
    + [f"SweepMsRange{k}" for k in _IMPLS]
    + [f"SweepRepeats{k}" for k in _IMPLS]
    + [f"Ns{k}" for k in _IMPLS]
    + [f"Speedup{k}" for k in _PEERS]
    + [f"SpeedupRange{k}" for k in _PEERS]
    + [f"Speedup{k}Two" for k in _PEERS]
    + [f"SpeedupRange{k}Two" for k in _PEERS]
    + [f"Dev{k}" for k in _PEERS]
    + ["OursThreadSpeedup", "OursThreadSpeedupRange", "OursTwoRatio", "OursTwoRatioRange"]
    + ["ColourVersion", "TmmSampled", "XYZOursUs", "XYZOursUsRange", "XYZOursTwoUs", "XYZOursTwoUsRange",
       "XYZColourUs", "XYZColourUsRange", "SpeedupXYZ", "SpeedupXYZRange", "SpeedupXYZTwo", "SpeedupXYZTwoRange",
       "XYZThreadSpeedup", "XYZThreadSpeedupRange", "XYZDev", "XYZSamples"]
)

SECTIONS = {
    "optics": (["derived/optics_speed.csv"], optics, OPTICS_MACROS),
}

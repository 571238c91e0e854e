"""Figure: the coursework's table 4.1 against our re-run: render time against trace depth, log scale.

Run:  python paper/scripts/fig_coursework_table.py [--quick]
Reads ``data/coursework_table_4_1.csv`` (the coursework, on the machine its notes name) and
``data/derived/coursework_table.csv`` (ours, written by ``benchmarks/coursework_table.py``);
writes ``fig_coursework_table.pdf``/``.png``.

Colours: one, two, three bubbles.  Open circles, dotted: the coursework.  Squares, solid: our
exhaustive tree (the coursework's algorithm, threshold 0).  Triangles, dashed: our default, pruned.
Ours are medians of the benchmark's interleaved runs; the thick bars span the interquartile range,
the thin ones the fastest to the slowest run (an isolated slow run is one disturbed by other work
on the shared two-core machine, not the algorithm).  Exhaustive and pruned points are drawn a
little left and right of their depth so that their bars do not hide each other.
Quick mode draws the same figure (it only reads tables).
"""

import re
import sys

import numpy as np
from matplotlib.lines import Line2D

import paths
import style
from study import load_coursework_table, load_timing, timing_series
from study.coursework import timing_spread

SCENES = {1: "one bubble", 2: "two bubbles", 3: "three bubbles"}
OFFSET = {"coursework": 0.0, "exhaustive": -0.12, "pruned": 0.12}  # in depth, so bars do not overlap
SOURCES = {  # label, marker, line style, filled marker
    "coursework": ("coursework ({machine})", "o", ":", False),  # the machine from the table's notes
    "exhaustive": ("ours, exhaustive", "s", "-", True),
    "pruned": ("ours, pruned", "^", "--", True),
}


def main(argv=None):
    paths.parse_args(__doc__.splitlines()[0], argv)
    coursework = load_coursework_table(paths.COURSEWORK_TABLE)
    timing = load_timing(paths.TIMING)
    found = re.search(r"on an? (.+?) \(", " ".join(coursework["notes"]))  # as numbers_coursework_fits.py's
    machine = found.group(1) if found else "its machine"

    fig = style.figure(height=2.7)
    ax = fig.subplots()
    colors = [c["color"] for c in style.matplotlib.rcParams["axes.prop_cycle"]]
    for (nb, name), color in zip(SCENES.items(), colors):
        series = {"coursework": (coursework["depth"], coursework["seconds"][nb])}
        for mode in ("exhaustive", "pruned"):
            depth, median, low, high = timing_spread(timing, nb, mode)
            series[mode] = (depth, median)
            _, runs = timing_series(timing, nb, mode, "seconds_runs")
            x = depth + OFFSET[mode]
            ax.vlines(x, np.nanmin(runs, axis=1), np.nanmax(runs, axis=1), color=color, linewidth=0.5)
            ax.vlines(x, low, high, color=color, linewidth=2.0, alpha=0.6)
        for source, (depth, seconds) in series.items():
            _, marker, ls, filled = SOURCES[source]
            ax.plot(depth + OFFSET[source], seconds, ls, marker=marker, color=color,
                    markerfacecolor=color if filled else "white", markeredgewidth=0.7, markersize=3.5, clip_on=False)
    ax.set_yscale("log")
    ax.set_xlabel("trace depth")
    ax.set_ylabel("render time, $960 \\times 960$ (s)")
    ax.set_xticks(range(1, 11))
    ax.set_xlim(0.7, 10.3)
    ax.grid(True, which="major", axis="y")

    scene_handles = [Line2D([], [], color=c, label=n) for n, c in zip(SCENES.values(), colors)]
    source_handles = [Line2D([], [], color="0.3", linestyle=ls, marker=m, markerfacecolor="0.3" if f else "white",
                             markeredgewidth=0.7, label=label.format(machine=machine))
                      for label, m, ls, f in SOURCES.values()]
    first = ax.legend(handles=source_handles, loc="upper left")
    ax.add_artist(first)
    ax.legend(handles=scene_handles, loc="center right", bbox_to_anchor=(1.0, 0.38))
    for path in style.savefig(fig, "fig_coursework_table"):
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

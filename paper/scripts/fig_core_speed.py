"""Figure: the tracer core's speed as a ratio to the floor kernel, per scene, one and two threads.

Run:  python paper/scripts/fig_core_speed.py [--quick]
Reads ``data/derived/throughput.csv`` (``benchmarks/throughput.py``): each case's render time
divided by the floor kernel's (one camera ray, three spheres, one mirror bounce) timed just
before it with the same thread count.  Markers: medians over the repeats; bars: the fastest to
the slowest repeat's ratio.  Writes ``fig_core_speed.pdf``/``.png``.  Quick mode draws the
same figure (it only reads the table).
"""

import sys

import numpy as np

import paths
import style
from study import read_commented_csv

DATA = paths.DERIVED / "throughput.csv"
CASES = [("empty", "10", "empty"), ("coursework_1_bubble", "1", "1 bubble, d1"),
         ("coursework_1_bubble", "10", "1 bubble, d10"), ("coursework_2_bubbles", "1", "2 bubbles, d1"),
         ("coursework_2_bubbles", "10", "2 bubbles, d10"), ("coursework_3_bubbles", "1", "3 bubbles, d1"),
         ("coursework_3_bubbles", "10", "3 bubbles, d10"), ("builtin", "10", "built-in, d10")]
THREADS = {"1": ("1 thread", "o", -0.12), "2": ("2 threads", "s", 0.12)}


def main(argv=None):
    paths.parse_args(__doc__.splitlines()[0], argv)
    _, rows = read_commented_csv(DATA)
    by = {(r["case"], r["depth"], r["threads"]): r for r in rows}
    fig = style.figure(height=2.5)
    ax = fig.subplots()
    colors = [c["color"] for c in style.matplotlib.rcParams["axes.prop_cycle"]]
    x = np.arange(len(CASES))
    for (t, (label, marker, dx)), color in zip(THREADS.items(), colors):
        med, lo, hi = (np.array([float(by[(c, d, t)][f"ratio_to_floor_{k}"]) for c, d, _ in CASES])
                       for k in ("median", "min", "max"))
        ax.errorbar(x + dx, med, yerr=[med - lo, hi - med], fmt=marker, color=color, markersize=3.5,
                    elinewidth=0.8, capsize=1.5, label=label)
    ax.set_yscale("log")
    ax.set_yticks([1, 2, 5, 10, 20, 50])
    ax.set_yticklabels(["1", "2", "5", "10", "20", "50"])
    ax.set_ylim(1, 50)
    ax.set_xticks(x)
    ax.set_xticklabels([name for _, _, name in CASES], rotation=35, ha="right")
    ax.set_ylabel("render time / floor kernel")
    ax.grid(True, which="major", axis="y")
    ax.legend(loc="upper left")
    for path in style.savefig(fig, "fig_core_speed"):
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

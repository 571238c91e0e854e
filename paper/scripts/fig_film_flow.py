"""Figure: the film-flow simulation verified, and a film turning black on a rendered bubble.

Run:  python paper/scripts/fig_film_flow.py [--quick]
Reads ``data/derived/film_flow_verification.csv`` and ``.npz``, ``film_flow_dt.csv`` and
``film_flow_evaporation.csv`` (all written by ``benchmarks/film_flow_verification.py``); writes
``fig_film_flow.pdf``/``.png`` (page wide).

(a) Rigid drainage: the apex (top cell row) against the law h0 (1 + t/τ)^(-1/2), steps of τ/20.
(b) Convergence under grid refinement: the largest errors of the four checks against the number
    of rows, with slopes 1 and 2 for reference.
(c) Plug flow with the cited defaults: the apex, the thinnest and the thickest cell against time,
    the black-film threshold, and the two estimates h0/q_e and h_eq(0)/q_e.
(d) The rendered frames stored by the benchmark (8-bit sRGB), at the film times printed above them.
(e) The time-step study (``film_flow_dt.csv``): the apex's black-film time against the step on two
    grids, Richardson's estimate and h_eq(0)/q_e.
(f) The evaporation study (``film_flow_evaporation.csv``): the apex's black-film time against the
    evaporation rate, with h_eq(0)/q_e and h0/q_e.
Quick mode draws the same figure (it only reads stored data).
"""

import sys

import numpy as np

import paths
import style
from study import read_commented_csv

CSV = paths.DERIVED / "film_flow_verification.csv"
NPZ = paths.DERIVED / "film_flow_verification.npz"
DT_CSV = paths.DERIVED / "film_flow_dt.csv"
EVAPORATION_CSV = paths.DERIVED / "film_flow_evaporation.csv"
CHECKS = {  # check, quantity -> label, marker
    ("apex", "max_relative_error"): ("rigid: apex vs law", "o"),
    ("profile", "max_abs_error_h_over_h0"): ("rigid: profile vs characteristics", "s"),
    ("equilibrium", "max_relative_error"): ("plug: equilibrium", "^"),
    ("transient", "max_abs_difference_h_over_h0"): ("plug: transient vs finer grid", "D"),
}


def main(argv=None):
    paths.parse_args(__doc__.splitlines()[0], argv)
    _, rows = read_commented_csv(CSV)
    data = np.load(NPZ)
    value = {(r["check"], r["quantity"]): float(r["value"]) for r in rows if r["check"] == "black"}

    fig = style.figure(width=style.PAGE_WIDTH, height=6.3)
    top, bottom, studies = fig.subfigures(3, 1, height_ratios=(1.25, 1.0, 1.25))
    ax_a, ax_b, ax_c = top.subplots(1, 3)

    t, apex, law = data["apex_t_over_tau"][1:], data["apex_nm"][1:], data["apex_law_nm"][1:]
    ax_a.loglog(t, law, "k-", linewidth=0.8, label=r"$h_0(1+t/\tau)^{-1/2}$")
    shown = np.unique(np.geomspace(1, len(t), 40).astype(int) - 1)  # evenly spaced on the log axis
    ax_a.loglog(t[shown], apex[shown], "o", markersize=2.5, markerfacecolor="none", markeredgewidth=0.6,
                label=f"simulated, {int(data['apex_rows'])} rows")
    ax_a.axvspan(1, 10, color="0.92", zorder=0)
    ax_a.set_xlabel(r"$t/\tau$")
    ax_a.set_ylabel("apex thickness (nm)")
    ax_a.legend(loc="lower left")
    ax_a.set_title("(a) rigid drainage", loc="left")

    for (check, quantity), (label, marker) in CHECKS.items():
        pts = sorted((int(r["grid"].split("x")[0]), float(r["value"])) for r in rows
                     if r["check"] == check and r["quantity"] == quantity)
        n, e = np.array(pts).T
        ax_b.loglog(n, e, marker=marker, markersize=3, linewidth=0.8, label=label)
    n_ref = np.array([16.0, 256.0])
    ax_b.loglog(n_ref, 3e-2 * (n_ref / 16) ** -1, ":", color="0.5", linewidth=0.8)
    ax_b.loglog(n_ref, 2e-3 * (n_ref / 16) ** -2, "--", color="0.5", linewidth=0.8)
    ax_b.text(256, 3e-2 / 16 * 1.25, "slope 1", color="0.4", ha="right", va="bottom")
    ax_b.text(256, 2e-3 / 256 * 1.25, "slope 2", color="0.4", ha="right", va="bottom")
    ax_b.set_ylim(1e-7, 0.1)
    ax_b.set_xlabel(r"rows $n_\theta$")
    ax_b.set_ylabel("largest error")
    ax_b.set_xticks([16, 32, 64, 128, 256], ["16", "32", "64", "128", "256"])
    ax_b.minorticks_off()
    ax_b.legend(loc="lower left", handlelength=1.5)
    ax_b.set_title("(b) convergence", loc="left")

    tb = data["black_times"]
    ax_c.plot(tb, data["black_max_nm"], color="0.6", linewidth=0.8, label="thickest cell")
    ax_c.plot(tb, data["black_apex_nm"], linewidth=1.0, label="apex (top row)")
    ax_c.plot(tb, data["black_min_nm"], linewidth=0.8, label="thinnest cell")
    black_nm = value[("black", "threshold")]
    ax_c.axhline(black_nm, color="k", linewidth=0.6, linestyle=":")
    ax_c.axvline(value[("black", "t_uniform")], color="0.4", linewidth=0.7, linestyle="-.", label="$h_0/q_e$")
    ax_c.axvline(value[("black", "t_equilibrium_apex")], color="0.4", linewidth=0.7, linestyle="--",
                 label=r"$h_{eq}(0)/q_e$")
    ax_c.set_xlabel("film time (s)")
    ax_c.set_ylabel("thickness (nm)")
    ax_c.set_xlim(0, tb[-1])
    ax_c.set_ylim(0, None)
    ax_c.legend(loc="upper right")
    ax_c.set_title("(c) plug flow, evaporating", loc="left")

    frames, times = data["frames"], data["frame_times"]
    axes = bottom.subplots(1, len(frames))
    for k, (ax, img, tf) in enumerate(zip(axes, frames, times)):
        ax.imshow(img, interpolation="lanczos")
        ax.set_axis_off()
        label = f"t = {tf:.0f} s"
        ax.set_title(("(d) " if k == 0 else "") + label, loc="left" if k == 0 else "center")
    ax_e, ax_f = studies.subplots(1, 2)
    dt_panel(ax_e)
    evaporation_panel(ax_f)
    for path in style.savefig(fig, "fig_film_flow"):
        print(f"wrote {path}")
    return 0



def dt_panel(ax):
    """(e) the apex's black-film time against the step, each grid of film_flow_dt.csv."""
    _, rows = read_commented_csv(DT_CSV)
    grids = sorted({r["grid"] for r in rows}, key=lambda g: int(g.split("x")[0]))
    for grid, marker in zip(grids, "os^D"):
        runs = sorted((r for r in rows if r["grid"] == grid), key=lambda r: float(r["dt_s"]))
        dt = np.array([float(r["dt_s"]) for r in runs])
        t = np.array([float(r["t_apex_s"]) for r in runs])
        nt, nph = grid.split("x")
        (line,) = ax.semilogx(1e3 * dt, t, marker=marker, markersize=3, linewidth=0.8,
                              label=rf"${nt}\times{nph}$ cells")
        rich = float(runs[0]["richardson_t_apex_s"]) if runs[0]["richardson_t_apex_s"] else float("nan")
        if np.isfinite(rich):
            ax.plot([1e3 * dt[0]], [rich], marker="*", markersize=6, color=line.get_color(), linestyle="none",
                    label=f"Richardson, {nt}" + r"$\times$" + f"{nph}")
    _, evap = read_commented_csv(EVAPORATION_CSV)
    t_eq = float(next(r["t_eq_apex_s"] for r in evap if float(r["evaporation_multiple"]) == 1.0))
    ax.axhline(t_eq, color="0.4", linewidth=0.7, linestyle="--", label=r"$h_{eq}(0)/q_e$")
    ax.axvline(10.0, color="0.75", linewidth=0.6, linestyle=":", zorder=0)
    ax.text(10.0 * 1.08, t_eq + 0.15, "panel (c)'s step", color="0.4", ha="left", va="bottom")
    ax.set_xlabel(r"time step $\Delta t$ (ms)")
    ax.set_ylabel("apex black-film time (s)")
    ax.legend(loc="upper left")
    ax.set_title(r"(e) time-step study, cited $q_e$", loc="left")


def evaporation_panel(ax):
    """(f) the apex's black-film time against the evaporation rate (film_flow_evaporation.csv)."""
    _, rows = read_commented_csv(EVAPORATION_CSV)
    rows = [r for r in rows if float(r["evaporation_multiple"]) > 0]
    e_all = np.array(sorted({float(r["evaporation_m_per_s"]) for r in rows}))
    e_line = np.geomspace(e_all[0] / 1.3, e_all[-1] * 1.3, 50)
    heq = float(rows[0]["h_eq_apex_nm"]) * 1e-9
    h0 = float(rows[0]["t_uniform_s"]) * float(rows[0]["evaporation_m_per_s"])
    ax.loglog(e_line, h0 / e_line, color="0.6", linewidth=0.7, linestyle="-.", label="$h_0/q_e$")
    ax.loglog(e_line, heq / e_line, color="0.3", linewidth=0.7, linestyle="--", label=r"$h_{eq}(0)/q_e$")
    runs = sorted({(r["grid"], float(r["dt_s"])) for r in rows}, key=lambda k: int(k[0].split("x")[0]))
    inset = ax.inset_axes([0.17, 0.1, 0.34, 0.32])
    for (grid, dt), marker in zip(runs, "os^D"):
        sel = sorted((r for r in rows if r["grid"] == grid and float(r["dt_s"]) == dt),
                     key=lambda r: float(r["evaporation_m_per_s"]))
        e = np.array([float(r["evaporation_m_per_s"]) for r in sel])
        t = np.array([float(r["t_apex_s"]) for r in sel])
        nt, nph = grid.split("x")
        (points,) = ax.loglog(e, t, marker=marker, markersize=3.5 if marker == "o" else 3, markerfacecolor="none",
                              markeredgewidth=0.8, linestyle="none",
                              label=rf"${nt}\times{nph}$, $\Delta t$ = {1e3 * dt:g} ms")
        ratio = np.array([float(r["t_apex_over_t_eq_apex"]) for r in sel])
        inset.semilogx(e, ratio, marker=marker, markersize=2.5, markerfacecolor="none", markeredgewidth=0.7,
                       linewidth=0.6, color=points.get_color())
    inset.set_ylim(1.0, 1.08)
    inset.set_yticks([1.0, 1.04, 1.08])
    inset.minorticks_off()
    inset.set_xticks([])
    inset.set_title(r"ratio $t\,q_e/h_{eq}(0)$", fontsize=7, pad=2)
    inset.tick_params(labelsize=7)
    ax.set_xlabel(r"evaporation rate $q_e$ (m s$^{-1}$)")
    ax.set_ylabel("apex black-film time (s)")
    ax.legend(loc="upper right")
    ax.set_title("(f) black film against evaporation", loc="left")


if __name__ == "__main__":
    sys.exit(main())

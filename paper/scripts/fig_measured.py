"""Figure: a measured foam film (Ziapkoff et al. 2026) and a bubble's apex against the optics and the thinning laws.

Run:  python paper/scripts/fig_measured.py [--quick]
Reads ``data/measured/optifik_comparison.csv``, ``optifik_thinning.csv`` and ``optifik_figure.npz``
(written by ``python -m study.measured``), ``oospectro_bubble_stated_thickness.csv`` and
``oospectro_bubble_curves.csv`` (``python paper/scripts/numbers_measured.py``); provenance in
``data/measured/README.md``; writes
``fig_measured.pdf``/``.png`` (page wide).

(a) Four spectra of the TTAB film in absolute reflectance (smoothed) and the exact reflectance of a
    water film of the fitted thickness (gain 1), offset by 0.08 each.
(b) The thickness fitted by the exact optics against the authors' (fringe extrema, Scheludko), with
    ±5 % about equality; triangles: the bubble's spectra (oospectro) against its stated thicknesses
    (``oospectro_bubble_comparison.csv``, the same calibration and fit, n = 1.33).
(c) The thickness against the acquisition index: the authors' and ours, and the fits of
    h1 [1 + (t - t1)/τ]^(-1/(ν-1)) to the authors' with the rate exponent ν free and held at 3
    and 5/2 (ν, not the paper's β, which is the optical phase).
(d) A bubble (the thicknesses stated in oospectro, TTAB at 10 cmc; the point taken as the apex)
    against time (the file index read as ms) with the fits of dh/dt = -c h^3 - q_e (the apex of this project's rigid
    drainage with evaporation) and of its two parts alone.
Quick mode draws the same figure (it only reads stored data).
"""

import sys

import numpy as np

import paths
import style
from study import measured, read_commented_csv

MEASURED = paths.DATA / "measured"


def main(argv=None):
    paths.parse_args(__doc__.splitlines()[0], argv)
    _, rows = read_commented_csv(MEASURED / "optifik_comparison.csv")
    _, laws = read_commented_csv(MEASURED / "optifik_thinning.csv")
    data = np.load(MEASURED / "optifik_figure.npz")

    fig = style.figure(width=style.PAGE_WIDTH, height=2.5)
    ax_a, ax_b, ax_c, ax_d = fig.subplots(1, 4)

    wl = data["wavelength_nm"]
    for k, index in enumerate(data["examples"]):
        off = 0.08 * k
        row = next(r for r in rows if int(r["time_index"]) == int(index))
        ax_a.plot(wl, data[f"measured_{index}"] + off, color=f"C{k}", linewidth=1.2, alpha=0.55)
        ax_a.plot(wl, data[f"model_fit_{index}"] + off, color=f"C{k}", linewidth=0.7, linestyle="--")
        ax_a.text(455, float(data[f"model_fit_{index}"][0]) + off + 0.012, f"{float(row['fit_nm']):.0f} nm",
                  fontsize=7, va="bottom")
    ax_a.plot([], [], color="0.4", linewidth=1.2, alpha=0.55, label="measured")
    ax_a.plot([], [], color="0.4", linewidth=0.7, linestyle="--", label="exact, fitted $d$")
    ax_a.set_xlim(450, 800)
    ax_a.set_xticks([450, 550, 650, 750])
    ax_a.set_xlabel("wavelength (nm)")
    ax_a.set_ylabel("reflectance + offset")
    ax_a.set_ylim(-0.01, 0.42)
    ax_a.legend(loc="upper center", ncol=2, fontsize=7)
    ax_a.set_title("(a) spectra", loc="left")

    st = np.array([float(r["stated_nm"]) for r in rows if r["stated_nm"]])
    ft = np.array([float(r["fit_nm"]) for r in rows if r["stated_nm"]])
    good = (st >= 200) & (st < 800)
    line = np.array([50.0, 6000.0])
    ax_b.fill_between(line, 0.95 * line, 1.05 * line, color="0.88", linewidth=0)
    ax_b.loglog(line, line, "k-", linewidth=0.6)
    ax_b.loglog(st[good], ft[good], "o", markersize=2.5, markerfacecolor="none", markeredgewidth=0.6,
                label="200–800 nm")
    ax_b.loglog(st[~good], ft[~good], "x", markersize=3, markeredgewidth=0.6, label="outside")
    _, comp = read_commented_csv(MEASURED / "oospectro_bubble_comparison.csv")
    bs = np.array([float(r["stated_nm"]) for r in comp if r["stated_nm"]])
    bf = np.array([float(r["fit_nm"]) for r in comp if r["stated_nm"]])
    ax_b.loglog(bs, bf, "^", markersize=2.5, markerfacecolor="none", markeredgewidth=0.6, color="C2",
                label="bubble")
    ax_b.set_xlim(60, 6000)
    ax_b.set_ylim(15, 6000)
    ax_b.set_xlabel("stated thickness (nm)")
    ax_b.set_ylabel("fitted thickness (nm)")
    ax_b.legend(loc="upper left", fontsize=7)
    ax_b.set_title("(b) thickness", loc="left")

    t_st = np.array([int(r["time_index"]) for r in rows if r["stated_nm"]], dtype=float)
    order = np.argsort(t_st)
    t_st, h_st = t_st[order], st[order]
    mine = [(int(r["time_index"]), float(r["fit_nm"])) for r in rows if int(r["in_envelope"])]
    t_f, h_f = np.array(mine, dtype=float).T
    ax_c.semilogy(t_f, h_f, ".", markersize=1.5, color="C1", label="fitted here")
    ax_c.semilogy(t_st, h_st, "o", markersize=2, markerfacecolor="none", markeredgewidth=0.5, color="C0",
                  label="authors")
    tt = np.linspace(t_st[0], t_st[-1], 300)
    free = next(r for r in laws if r["source"] == "stated" and r["law"] == "free")
    for beta, style_, label in ((None, "k-", rf"$\nu$ = {float(free['beta']):.1f} (free)"),
                                (3.0, "k:", r"$\nu$ = 3 (rigid)"),
                                (2.5, "k--", r"$\nu$ = 5/2 ($t^{-2/3}$)")):
        fit = measured.fit_thinning_law(t_st, h_st, beta=beta, interval=False)
        ax_c.semilogy(tt, fit.h1_nm * (1 + (tt - t_st[0]) / fit.tau) ** (-fit.alpha), style_, linewidth=0.7,
                      label=label)
    ax_c.set_ylim(20, 6000)
    ax_c.set_xlabel("acquisition index (no unit stated)")
    ax_c.set_ylabel("thickness (nm)")
    ax_c.legend(loc="upper right", fontsize=7)
    ax_c.set_title("(c) thinning", loc="left")

    _, bub = read_commented_csv(MEASURED / "oospectro_bubble_stated_thickness.csv")
    _, cur = read_commented_csv(MEASURED / "oospectro_bubble_curves.csv")
    t_b = np.array([float(r["time_index"]) for r in bub]) / 1000
    h_b = np.array([float(r["stated_nm"]) for r in bub])
    tt = np.array([float(r["t_s"]) for r in cur])
    ax_d.plot(t_b, h_b, "o", markersize=2, markerfacecolor="none", markeredgewidth=0.5, color="C0",
              label="stated")
    for law, style_, label in (("rigid drainage + evaporation", "k-", "rigid + $q_e$"),
                               ("rigid drainage only", "k:", "rigid only"),
                               ("evaporation only", "k--", "$q_e$ only")):
        ax_d.plot(tt, [float(r[law]) for r in cur], style_, linewidth=0.7, label=label)
    ax_d.set_ylim(0, 4500)
    ax_d.set_xlabel("time (s; index as ms)")
    ax_d.set_ylabel("thickness (nm)")
    ax_d.legend(loc="upper right", fontsize=7)
    ax_d.set_title("(d) a bubble", loc="left")

    for path in style.savefig(fig, "fig_measured"):
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

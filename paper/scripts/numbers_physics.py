"""The two-beam model's error and water's index, a plug-in of ``make_numbers.py``.

* ``physics``: computed here with :mod:`bubbleoptics` (the two-beam error, water's index): a
  few milliseconds, no data file.
"""

from __future__ import annotations

import math

from macros import plain, significant, up_to

#: where these macros stand in numbers.tex (make_numbers.py)
ORDER = 6


TWO_BEAM_WL_NM = (380.0, 780.0)  # the range over which the two-beam model's largest error is quoted
TWO_BEAM_MAX_D_NM = 2000.0
TWO_BEAM_EXAMPLE = (1.2, 550.0, 150.0)  # the worked example: angle (rad), wavelength and film thickness (nm)
WATER_INDEX_AT = ((400.0, "FourHundred"), (550.0, "FiveFifty"), (700.0, "SevenHundred"))  # nm, macro suffix


def physics(dirs):
    import numpy as np

    import bubbleoptics as bo

    out = {}
    wl = np.arange(TWO_BEAM_WL_NM[0], TWO_BEAM_WL_NM[1] + 1.0, 5.0)
    d = np.linspace(0.0, TWO_BEAM_MAX_D_NM, 2001)[:, None]
    out["TwoBeamWlMin"], out["TwoBeamWlMax"] = (plain(x) for x in TWO_BEAM_WL_NM)
    out["TwoBeamMaxThicknessUm"] = plain(TWO_BEAM_MAX_D_NM / 1000)
    import fig_thin_film  # the curve Fig. 1 draws: the two-beam error at one wavelength

    _, _, _, gap, peak = fig_thin_film.two_beam_gap()
    out["TwoBeamFigNm"] = plain(fig_thin_film.TWO_BEAM_NM)
    out["TwoBeamErrFig"] = up_to(gap, 2)  # "off by up to"
    out["TwoBeamRelFig"] = up_to(100 * gap / peak, 2)
    for deg, word in ((0, "Normal"), (60, "Sixty"), (75, "SeventyFive")):
        theta = np.deg2rad(deg)
        R = bo.film_reflectance(wl, d, theta)
        R2 = bo.two_beam_reflectance(wl, d, theta)
        err = np.abs(R2 - R)
        out[f"TwoBeamErr{word}"] = significant(err.max(), 2)
        out[f"TwoBeamPeak{word}"] = significant(R.max(), 2)
        out[f"TwoBeamRel{word}"] = significant(100 * err.max() / R.max(), 2)
    theta, wl_x, d_x = TWO_BEAM_EXAMPLE  # s light, radians, nm, nm
    out["TwoBeamExampleDeg"] = significant(math.degrees(theta), 3)
    out["TwoBeamExampleWlNm"], out["TwoBeamExampleThicknessNm"] = plain(wl_x), plain(d_x)
    out["TwoBeamExampleExact"] = f"{float(bo.film_reflectance(wl_x, d_x, theta, polarization='s')):.3f}"
    out["TwoBeamExampleCoursework"] = f"{float(bo.two_beam_reflectance(wl_x, d_x, theta, polarization='s')):.3f}"
    n = bo.water_refractive_index(np.array([wl for wl, _ in WATER_INDEX_AT]))
    for value, (wl, word) in zip(n, WATER_INDEX_AT):
        out[f"WaterIndex{word}"] = f"{float(value):.4f}"
        out[f"WaterIndexNm{word}"] = plain(wl)
    r01 = ((n[1] - 1) / (n[1] + 1)) ** 2
    out["WaterRNormal"] = significant(float(r01), 2)
    return out


PHYSICS_MACROS = (
    ["TwoBeamWlMin", "TwoBeamWlMax", "TwoBeamMaxThicknessUm", "TwoBeamFigNm", "TwoBeamErrFig", "TwoBeamRelFig"]
    + [f"TwoBeam{what}{w}" for what in ("Err", "Peak", "Rel") for w in ("Normal", "Sixty", "SeventyFive")]
    + ["TwoBeamExampleDeg", "TwoBeamExampleWlNm", "TwoBeamExampleThicknessNm", "TwoBeamExampleExact",
       "TwoBeamExampleCoursework", "WaterRNormal"]
    + [f"WaterIndex{what}{w}" for what in ("", "Nm") for w in ("FourHundred", "FiveFifty", "SevenHundred")]
)

SECTIONS = {
    "physics": (["bubbleoptics (computed)"], physics, PHYSICS_MACROS),
}

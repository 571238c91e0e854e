"""The renderer's defaults, a plug-in of ``make_numbers.py``.

* ``defaults``: the renderer's defaults, from :data:`tracer.DEFAULTS` (what :func:`tracer.render` uses), and the film
  thickness at which its default spectral method switches (:func:`bubbleoptics.point_sampling_limit_nm`).
"""

from __future__ import annotations

from macros import scientific, significant

#: where these macros stand in numbers.tex (make_numbers.py)
ORDER = 11


def defaults(dirs):
    import tracer

    import bubbleoptics as bo

    defaults_ = tracer.DEFAULTS  # what tracer.render uses for an argument left at None
    bands = defaults_["spectral_samples"]
    return {
        "DefaultBands": str(bands),
        "DefaultThreshold": scientific(defaults_["threshold"], 1),
        "DefaultDepth": str(defaults_["depth"]),
        "DefaultMethod": rf"\texttt{{{defaults_['spectral_method']}}}",
        "DefaultAliasLimitUm": significant(float(bo.point_sampling_limit_nm(bands)) / 1000, 2),
        "AutoSwitchUm": significant(float(bo.point_sampling_limit_nm(bands)) / tracer.prepare.pack.AUTO_FRINGE_BANDS
                                    / 1000, 2),
        "AutoFringeBands": significant(tracer.prepare.pack.AUTO_FRINGE_BANDS, 2),
        # where auto would switch with twice the default bands (the thick-film alternative of the study)
        "AutoSwitchDoubleBandsUm": significant(float(bo.point_sampling_limit_nm(2 * bands))
                                               / tracer.prepare.pack.AUTO_FRINGE_BANDS / 1000, 2),
        "DoubleBands": str(2 * bands),
    }


DEFAULTS_MACROS = ["DefaultBands", "DefaultThreshold", "DefaultDepth", "DefaultMethod", "DefaultAliasLimitUm",
                   "AutoSwitchDoubleBandsUm", "DoubleBands",
                   "AutoSwitchUm", "AutoFringeBands"]

SECTIONS = {
    "defaults": (["tracer.DEFAULTS"], defaults, DEFAULTS_MACROS),
}

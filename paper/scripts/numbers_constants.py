"""Constants of the code that the text quotes, a plug-in of ``make_numbers.py``.

* ``constants``: the spectral grid of :mod:`bubbleoptics.colorimetry`, the aliasing onset's
  definition (:mod:`study.stability`), the lookup tables of :mod:`study.film_colour` and the
  windows of ``fig_bandlimited.py``.
"""

from __future__ import annotations

import inspect

from macros import plain, significant

#: where these macros stand in numbers.tex (make_numbers.py)
ORDER = 12


def constants(dirs):
    """Constants of the code that the text quotes: the spectral grid, the aliasing onset's
    definition, and the lookup tables of :mod:`study.film_colour` (the Blender-like
    table's size and spacing are those of Blender's source, as that module's docstring cites)."""
    import fig_bandlimited  # the running-maximum window its caption states
    from bubbleoptics import colorimetry, point_sampling_limit_nm
    from study import film_colour, reference, stability

    grid = colorimetry.DEFAULT_WAVELENGTHS_NM
    return {
        "MaxBands": str(colorimetry.MAX_BANDS),
        "GridStepNm": plain(grid[1] - grid[0]),
        "BandLowNm": plain(grid[0]),
        "BandHighNm": plain(grid[-1]),
        "BandSpanNm": plain(grid[-1] - grid[0]),
        "OnsetDeltaE": plain(stability.ONSET_DE00),
        "OnsetWindowUm": plain(stability.ONSET_WINDOW_NM / 1000),
        "LutStepNm": plain(film_colour.LUT_STEP_NM),
        "BlenderTableSize": str(film_colour.BLENDER_TABLE_SIZE),
        "BlenderStepNm": significant(film_colour.BLENDER_STEP_NM, 3),
        "BlenderMaxOpdUm": significant(film_colour.BLENDER_MAX_OPD_NM / 1000, 3),
        "BlenderTerms": str(film_colour.BLENDER_TERMS),
        "BlWindowUm": plain(fig_bandlimited.WINDOW_NM / 1000),
        "ExposureMaxUm": plain(fig_bandlimited.EXPOSURE_MAX_NM / 1000),
        "FringeWlNm": plain(inspect.signature(point_sampling_limit_nm).parameters["wavelength_nm"].default),
        "ReferenceDigits": str(inspect.signature(reference.fresnel_mp).parameters["dps"].default),
        "GrazingWlNm": plain(stability.WAVELENGTH_NM),
    }


CONSTANTS_MACROS = ["MaxBands", "GridStepNm", "BandLowNm", "BandHighNm", "BandSpanNm", "OnsetDeltaE",
                    "OnsetWindowUm", "LutStepNm", "BlenderTableSize", "BlenderStepNm", "BlenderMaxOpdUm",
                    "BlenderTerms", "BlWindowUm", "ExposureMaxUm", "FringeWlNm", "ReferenceDigits", "GrazingWlNm"]

SECTIONS = {
    "constants": (["bubbleoptics (constants)"], constants, CONSTANTS_MACROS),
}

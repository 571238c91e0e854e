"""Facts from elsewhere that the text quotes, a plug-in of ``make_numbers.py``.

* ``facts``: :data:`FACTS`, each with its source (cited in the paper where it is used).
"""

from __future__ import annotations

#: where these macros stand in numbers.tex (make_numbers.py)
ORDER = 13


#: Facts from elsewhere that the text quotes: name -> (value, source).  The source is cited in the
#: paper where the fact is used.
FACTS = {
    "BlenderGaussVersion": ("4.2", "the Blender entry of paper/references.bib (cited where it is used): thin "
                                   "film in the Principled BSDF since 4.2, the Gaussian fit of Belcour & Barla"),
    "SellmeierMinNm": ("182", "Daimon & Masumura (2007), the range of their fit for water at 20 C; cited there"),
    "SellmeierMaxNm": ("1129", "the same"),
    "MonolayerNm": ("2", "order of magnitude of a surfactant monolayer (a film's two faces), as in Mysels et al. "
                         "(1959), cited in the introduction"),
}


def facts(dirs):
    return {name: value for name, (value, _source) in FACTS.items()}


SECTIONS = {
    "facts": (["FACTS (sources beside each)"], facts, list(FACTS)),
}

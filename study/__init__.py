"""study: the analysis behind the benchmarks, notebooks and paper.

One importable place for what the repository's scripts share, so that a number in the paper and
the same number in a notebook come from one piece of code (the model: scikit-image's
``skimage.metrics``).  It lives beside the two packages and may use both; nothing finds the
repository's files by itself: every loader takes its path.

Re-exported here (the everyday names):

* :mod:`.results` -- the benchmarks' result files: :func:`write_csv` (the one writer, provenance
  comment first, :func:`provenance`), :func:`read_commented_csv` (the one reader; as NumPy
  columns :func:`read_columns`, :func:`rows_to_columns`), :func:`wall_times` (the one timing loop);
* :mod:`.coursework` -- the coursework's timing table 4.1 and our re-run of it:
  :func:`load_coursework_table`, :func:`load_timing`, :func:`timing_series`;
* :mod:`.fits` -- growth laws of run time against depth: :func:`fit_polynomial`,
  :func:`fit_exponential`, :func:`fit_affine_exponential`, :func:`compare_fits`,
  :func:`holdout_errors`;
* :mod:`.fronts` -- :func:`pareto_front`, :func:`time_at_error`;
* :mod:`.metrics` -- the one CIEDE2000 (colour-science's): :func:`delta_e00_XYZ`,
  :func:`delta_e00` (linear sRGB images), :func:`delta_e00_images` (renders, negatives clipped).

Imported by name (``from study import stability``):

* :mod:`.stability` -- grazing incidence and thick-film aliasing (``benchmarks/stability.py``);
* :mod:`.tradeoffs` -- run time against error of the tracer's settings (``benchmarks/time_vs_error.py``);
* :mod:`.film_colour` -- the published approaches the band-limited colour is compared with
  (``benchmarks/bandlimited_colour.py``);
* :mod:`.film_flow` -- living films (``notebooks/07_film_flow.ipynb``): the first-order colour
  range, a lookup table in OPD steps, black-film times;
* :mod:`.reference` -- slow, literal, independent references (mpmath at 40 digits, tmm); needs
  the ``test`` extra.

Neither ``bubbleoptics`` nor ``tracer`` imports this package, which is not part of the wheel (it is imported from the checkout); it imports neither scipy nor
matplotlib nor colour-science at import (each function imports what it uses).
"""

from .coursework import COURSEWORK_COLUMNS, load_coursework_table, load_timing, timing_series
from .fits import Comparison, Fit, compare_fits, fit_affine_exponential, fit_exponential, fit_polynomial, holdout_errors
from .fronts import pareto_front, time_at_error
from .metrics import delta_e00, delta_e00_images, delta_e00_XYZ
from .results import provenance, read_columns, read_commented_csv, rows_to_columns, wall_times, write_csv

__all__ = [
    "write_csv",
    "provenance",
    "read_commented_csv",
    "read_columns",
    "rows_to_columns",
    "wall_times",
    "COURSEWORK_COLUMNS",
    "load_coursework_table",
    "load_timing",
    "timing_series",
    "Fit",
    "Comparison",
    "fit_polynomial",
    "fit_exponential",
    "fit_affine_exponential",
    "compare_fits",
    "holdout_errors",
    "pareto_front",
    "time_at_error",
    "delta_e00_XYZ",
    "delta_e00",
    "delta_e00_images",
]

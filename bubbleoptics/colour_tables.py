"""Write ``bubbleoptics/colour_tables.npz``: colour-science's results that a render needs.

``python -m bubbleoptics.colour_tables`` recomputes every array with colour-science and writes
the file that :func:`bubbleoptics.colorimetry.colour_tables` reads, so that neither
``import bubbleoptics`` nor a render imports colour-science (one to several seconds of
start-up).  Run it after upgrading colour-science; ``tests/bubbleoptics/test_colorimetry.py`` fails while
the shipped file and colour-science disagree.

Nothing in the package imports this module; it imports colour-science.
"""

import argparse
import sys
import warnings

import numpy as np

from .atomic import write_atomically
from .colorimetry import COLOUR_TABLES_PATH, DEFAULT_OBSERVER, DEFAULT_WAVELENGTHS_NM, _weights

__all__ = ["compute_colour_tables", "write_colour_tables", "main"]


def compute_colour_tables() -> dict:
    """The arrays of ``colour_tables.npz``, computed now by colour-science (see
    :func:`bubbleoptics.colorimetry.colour_tables` for what each one is)."""
    import colour

    wl = DEFAULT_WAVELENGTHS_NM
    basis = colour.recovery.MSDS_BASIS_FUNCTIONS_sRGB_MALLETT2019
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # extrapolation below 380 nm warns
        basis = basis.copy().align(colour.SpectralShape(wl[0], wl[-1], 1.0)).values
    srgb = colour.RGB_COLOURSPACES["sRGB"]
    dominant = [float(colour.dominant_wavelength(p, srgb.whitepoint)[0]) for p in srgb.primaries]
    return {
        "wavelengths_nm": np.array(wl, dtype=float),
        "xyz_weights_d65": np.array(_weights(wl, "D65", DEFAULT_OBSERVER), dtype=float),
        "rgb_basis_mallett2019": np.array(basis, dtype=float),
        "srgb_dominant_wavelengths_nm": np.array(dominant, dtype=float),
    }


def write_colour_tables(path=COLOUR_TABLES_PATH):
    """Compute the tables and write them to *path* (atomically); return *path*."""
    import colour

    tables = compute_colour_tables()
    tables["colour_science_version"] = np.array(colour.__version__)

    def write(tmp):
        with open(tmp, "wb") as f:  # a file object: np.savez(name) would append ".npz" to the name
            np.savez(f, **tables)

    write_atomically(path, write)
    return path


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m bubbleoptics.colour_tables", description=__doc__.split("\n")[0])
    parser.add_argument("--out", default=COLOUR_TABLES_PATH, help="where to write (default: the package's file)")
    print(write_colour_tables(parser.parse_args(argv).out))
    return 0


if __name__ == "__main__":
    sys.exit(main())

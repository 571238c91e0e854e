"""Start-up: ``import tracer`` and loading a scene stay clear of the heavy imports.

colour-science (which pulls in scipy), matplotlib and trimesh take seconds to import; a render
needs none of them (``bubbleoptics.colorimetry`` reads colour-science's results from its shipped
tables), so only the functions that use them import them.
"""

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.api
def test_importing_bubbleoptics_and_loading_a_scene_do_not_import_colour_science():
    """A render's start-up: colour-science, scipy, matplotlib and trimesh stay out.

    A fresh process, so that nothing an earlier test imported counts.  numba itself imports the
    bare ``scipy`` package (to check its version) and, when its CPU target first loads its
    implementations (the first call of any compiled function), ``scipy.linalg`` (a BLAS check
    in numba.np.arraymath); so what counts is what comes after numba has compiled one function.
    """
    code = ("import sys, numba\n"
            "numba.njit(lambda x: x + 1)(1)\n"
            "before = set(sys.modules)\n"
            "import bubbleoptics as bo, tracer\n"
            "bo.band_spectral_weights(16); bo.rgb_reflectance_basis(16)\n"
            "tracer.load_scene('data/scenes/bubbles_sky.toml')\n"
            "tracer.load_scene('data/coursework_scenes/listing_3_2.txt')  # 8-bit sRGB colours\n"
            "heavy = ('colour', 'scipy', 'matplotlib', 'trimesh')\n"
            "print(sorted({m.split('.')[0] for m in set(sys.modules) - before if m.startswith(heavy)}))\n")
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]", out.stdout

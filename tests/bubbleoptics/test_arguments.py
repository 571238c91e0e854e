"""Argument checking: every bad argument raises ValueError naming the argument and the reason.

The physics behind each rule (units: nm, radians, n + ik with k >= 0):

* wavelengths are positive and thicknesses non-negative lengths;
* a refractive index has a positive real part; k >= 0 is absorption in the exp(+i k z)
  convention (Born & Wolf §1.6, Byrnes arXiv:1603.02720 §2), k < 0 would be gain;
* the incidence (outside) medium must be lossless, or the angle of incidence is not a real
  angle (Born & Wolf §13.2: in an absorbing medium the planes of constant phase and amplitude
  differ);
* |theta| <= pi/2 radians (degrees are the most common mistake, and the message says so);
* the water index is a Sellmeier fit valid for 182-1129 nm only (Daimon & Masumura 2007).

These tests freeze the error contract of the public API, so they carry the ``regression``
marker.  Each ``match`` is a regular expression searched in the message.
"""

import math

import numpy as np
import pytest

import bubbleoptics as bo

FILM_FUNCS = [bo.film_reflectance, bo.film_transmittance, bo.film_rt]
ALL_FILM_FUNCS = FILM_FUNCS + [bo.two_beam_reflectance]
NAN, INF = float("nan"), float("inf")


def _film_call(func, **overrides):
    """Call a film function with valid defaults, some overridden."""
    kwargs = dict(wavelength_nm=550.0, thickness_nm=300.0, theta=0.3, n_film=1.33, n_outside=1.0)
    if func is not bo.two_beam_reflectance:
        kwargs["n_inside"] = None
    kwargs.update(overrides)
    return func(**kwargs)


# ---------------------------------------------------------------------------------------------
# Film functions
# ---------------------------------------------------------------------------------------------
BAD_FILM_ARGS = [
    # (overrides, regex that the message must contain)
    ({"thickness_nm": -1.0}, r"thickness_nm must be >= 0"),
    ({"thickness_nm": [10.0, -2.0, 3.0]}, r"thickness_nm must be >= 0.*-2\.0.*index \(1,\)"),
    ({"thickness_nm": -1e-300}, r"thickness_nm"),
    ({"wavelength_nm": 0.0}, r"wavelength_nm must be > 0"),
    ({"wavelength_nm": -550.0}, r"wavelength_nm must be > 0"),
    ({"wavelength_nm": [[500.0, 600.0], [700.0, -1.0]]}, r"wavelength_nm.*index \(1, 1\)"),
    ({"wavelength_nm": NAN}, r"wavelength_nm must be finite"),
    ({"wavelength_nm": INF}, r"wavelength_nm must be finite"),
    ({"wavelength_nm": [500.0, -INF]}, r"wavelength_nm must be finite"),
    ({"thickness_nm": NAN}, r"thickness_nm must be finite"),
    ({"thickness_nm": INF}, r"thickness_nm must be finite"),
    ({"theta": NAN}, r"theta must be finite"),
    ({"theta": [0.1, INF]}, r"theta must be finite"),
    ({"n_film": complex(1.33, NAN)}, r"n_film must be finite"),
    ({"n_film": complex(INF, 0.0)}, r"n_film must be finite"),
    ({"n_film": NAN}, r"n_film must be finite"),
    ({"n_outside": INF}, r"n_outside must be finite"),
    ({"n_outside": NAN}, r"n_outside must be finite"),
    ({"n_film": 1.33 - 0.01j}, r"n_film must have k >= 0"),
    ({"n_film": [1.33, 1.5 - 1e-12j]}, r"n_film must have k >= 0.*index \(1,\)"),
    ({"n_outside": 1.0 + 0.1j}, r"n_outside must be real"),
    ({"n_outside": 1.0 - 0.1j}, r"n_outside must be real"),
    ({"n_film": 0.0}, r"n_film must have a positive real part"),
    ({"n_film": -1.33}, r"n_film must have a positive real part"),
    ({"n_film": -1.33 + 0.5j}, r"n_film must have a positive real part"),
    ({"n_outside": 0.0}, r"n_outside must have a positive real part"),
    ({"n_outside": -1.0}, r"n_outside must have a positive real part"),
    ({"theta": 2.0}, r"theta must satisfy \|theta\| <= pi/2 radians.*not degrees"),
    ({"theta": -90.0}, r"theta.*radians"),
    ({"theta": 45.0}, r"theta.*radians"),
    ({"theta": math.pi / 2 + 1e-15}, r"theta.*radians"),
    ({"theta": np.nextafter(-math.pi / 2, -4.0)}, r"theta.*radians"),
    ({"wavelength_nm": "550"}, r"wavelength_nm must be numeric"),
    ({"wavelength_nm": None}, r"wavelength_nm"),
    ({"thickness_nm": [[1.0, 2.0], [3.0]]}, r"thickness_nm could not be converted"),
    ({"theta": [0.1, 0.2, 0.3], "thickness_nm": [1.0, 2.0]}, r"incompatible shapes"),
    ({"n_film": None, "wavelength_nm": 150.0}, r"wavelength_nm must lie within 182-1129 nm"),
    ({"n_film": None, "wavelength_nm": [500.0, 1200.0]}, r"wavelength_nm must lie within 182-1129 nm"),
]

BAD_INSIDE_ARGS = [
    ({"n_inside": 1.5 - 0.01j}, r"n_inside must have k >= 0"),
    ({"n_inside": NAN}, r"n_inside must be finite"),
    ({"n_inside": complex(1.5, INF)}, r"n_inside must be finite"),
    ({"n_inside": 0.0}, r"n_inside must have a positive real part"),
    ({"n_inside": -2.0}, r"n_inside must have a positive real part"),
    ({"n_inside": [1.0, 1.5, 2.0], "wavelength_nm": [500.0, 600.0]}, r"incompatible shapes"),
]


@pytest.mark.api
@pytest.mark.parametrize("func", ALL_FILM_FUNCS, ids=lambda f: f.__name__)
@pytest.mark.parametrize("overrides, match", BAD_FILM_ARGS, ids=lambda x: repr(x)[:60] if isinstance(x, dict) else "")
def test_film_functions_reject_bad_arguments(func, overrides, match):
    """Bad wavelength, thickness, angle or index raises ValueError naming the argument.

    Physics: lengths are positive (thickness may be 0), indices n + ik need n > 0 and k >= 0
    (Born & Wolf §1.6), the incidence medium must be lossless (Born & Wolf §13.2), angles are
    radians with |theta| <= pi/2, and the default water index (Daimon & Masumura 2007) is
    valid only on 182-1129 nm.
    """
    with pytest.raises(ValueError, match=match):
        _film_call(func, **overrides)


@pytest.mark.api
@pytest.mark.parametrize("func", FILM_FUNCS, ids=lambda f: f.__name__)
@pytest.mark.parametrize("overrides, match", BAD_INSIDE_ARGS, ids=lambda x: repr(x)[:60] if isinstance(x, dict) else "")
def test_film_functions_reject_bad_inside_medium(func, overrides, match):
    """A bad inside medium (k < 0: gain; n <= 0; NaN; wrong shape) is named in the error."""
    with pytest.raises(ValueError, match=match):
        _film_call(func, **overrides)


@pytest.mark.api
@pytest.mark.parametrize("func", ALL_FILM_FUNCS, ids=lambda f: f.__name__)
@pytest.mark.parametrize("pol", ["S", "P", "unpolarised", "both", "", None, 0, 2])
def test_unknown_polarization(func, pol):
    """Polarization must be exactly "s" (TE), "p" (TM) or "unpolarized" (Born & Wolf §1.5.2)."""
    with pytest.raises(ValueError, match=r"polarization must be one of 's', 'p', 'unpolarized'"):
        _film_call(func, polarization=pol)


@pytest.mark.api
def test_incompatible_shapes_message_names_arguments_and_shapes():
    """A broadcasting error lists each argument with its shape, so the culprit is visible.

    (NumPy broadcasting rules; the physics needs one wavelength per film-index value when the
    index is given per wavelength.)
    """
    wl = np.linspace(400.0, 700.0, 3)
    with pytest.raises(ValueError, match=r"wavelength_nm \(3,\).*thickness_nm \(2,\)"):
        bo.film_reflectance(wl, [100.0, 200.0], 0.0, 1.33)
    with pytest.raises(ValueError, match=r"wavelength_nm \(3,\).*n_film \(4,\)"):
        bo.film_reflectance(wl, 100.0, 0.0, np.full(4, 1.33))
    with pytest.raises(ValueError, match=r"theta \(2, 5\)"):
        bo.film_transmittance(wl, 100.0, np.zeros((2, 5)), 1.33)
    with pytest.raises(ValueError, match=r"n1 \(2,\).*n2 \(3,\)"):
        bo.fresnel_coefficients([1.0, 1.2], [1.5, 1.3, 1.2], 0.2)
    with pytest.raises(ValueError, match=r"wavelength_nm \(3,\).*thickness_nm \(2,\)"):
        bo.two_beam_reflectance(wl, [100.0, 200.0], 0.0, 1.33)
    with pytest.raises(ValueError, match=r"wavelength_nm \(3,\).*n_layers\[1\] \(2,\)"):
        bo.multilayer_reflectance(wl, [1.3, [1.4, 1.5]], [1.0, 2.0], 0.0)


@pytest.mark.api
@pytest.mark.parametrize("quantities", ["X", "", "RTX", "r"])
def test_film_rt_unknown_quantities(quantities):
    """``film_rt(quantities=...)`` accepts "RT", "R" or "T"; anything else is an error.

    (Asking for a quantity that does not exist should not silently return an empty or
    partial tuple.)
    """
    with pytest.raises(ValueError, match=r"quantities"):
        bo.film_rt(550.0, 300.0, 0.3, 1.33, quantities=quantities)


# ---------------------------------------------------------------------------------------------
# Fresnel coefficients
# ---------------------------------------------------------------------------------------------
@pytest.mark.api
@pytest.mark.parametrize(
    "args, match",
    [
        ((1.0, 1.5, 2.0), r"theta1 must satisfy \|theta\| <= pi/2 radians.*not degrees"),
        ((1.0, 1.5, -30.0), r"theta1.*radians"),
        ((1.0 + 0.1j, 1.5, 0.2), r"n1 must be real"),
        ((1.0, 1.5 - 0.1j, 0.2), r"n2 must have k >= 0"),
        ((NAN, 1.5, 0.2), r"n1 must be finite"),
        ((1.0, complex(NAN, 0), 0.2), r"n2 must be finite"),
        ((1.0, 1.5, INF), r"theta1 must be finite"),
        ((0.0, 1.5, 0.2), r"n1 must have a positive real part"),
        ((1.0, -1.5, 0.2), r"n2 must have a positive real part"),
        (([1.0, 1.2], [1.5, 1.3, 1.2], 0.2), r"incompatible shapes.*n1 \(2,\).*n2 \(3,\)"),
    ],
)
def test_fresnel_rejects_bad_arguments(args, match):
    """Fresnel coefficients need a real positive n1 (lossless incidence medium, Born & Wolf
    §13.2), n2 with n > 0 and k >= 0, and |theta1| <= pi/2 radians; errors name the argument."""
    with pytest.raises(ValueError, match=match):
        bo.fresnel_coefficients(*args)


# ---------------------------------------------------------------------------------------------
# Multilayer
# ---------------------------------------------------------------------------------------------
ML_FUNCS = [bo.multilayer_reflectance, bo.multilayer_transmittance, bo.multilayer_rt]


@pytest.mark.api
@pytest.mark.parametrize("func", ML_FUNCS, ids=lambda f: f.__name__)
@pytest.mark.parametrize(
    "args, kwargs, match",
    [
        ((550.0, [1.3, 1.4], [1.0], 0.0), {}, r"n_layers has 2 layers but thicknesses_nm has 1"),
        ((550.0, [1.3], [1.0, 2.0, 3.0], 0.0), {}, r"n_layers has 1 layers? but thicknesses_nm has 3"),
        ((550.0, [], [], 0.0), {}, r"n_layers must hold at least one layer"),
        ((550.0, 1.3, 1.0, 0.0), {}, r"n_layers"),
        ((550.0, [1.3, 1.4 - 0.1j], [1.0, 2.0], 0.0), {}, r"n_layers\[1\] must have k >= 0"),
        ((550.0, [0.0, 1.4], [1.0, 2.0], 0.0), {}, r"n_layers\[0\] must have a positive real part"),
        ((550.0, [1.3, NAN], [1.0, 2.0], 0.0), {}, r"n_layers\[1\] must be finite"),
        ((550.0, [1.3, 1.4], [1.0, -2.0], 0.0), {}, r"thicknesses_nm\[1\] must be >= 0"),
        ((550.0, [1.3, 1.4], [INF, 2.0], 0.0), {}, r"thicknesses_nm\[0\] must be finite"),
        ((-550.0, [1.3, 1.4], [1.0, 2.0], 0.0), {}, r"wavelength_nm must be > 0"),
        ((550.0, [1.3, 1.4], [1.0, 2.0], 3.0), {}, r"theta must satisfy.*radians"),
        ((550.0, [1.3, 1.4], [1.0, 2.0], 0.0), {"n_outside": 1 + 0.1j}, r"n_outside must be real"),
        ((550.0, [1.3, 1.4], [1.0, 2.0], 0.0), {"n_inside": 1 - 0.1j}, r"n_inside must have k >= 0"),
        ((550.0, [1.3, 1.4], [1.0, 2.0], 0.0), {"polarization": "x"}, r"polarization must be one of"),
        (([500.0, 600.0, 700.0], [1.3, [1.4, 1.5]], [1.0, 2.0], 0.0), {}, r"incompatible shapes.*n_layers\[1\] \(2,\)"),
    ],
)
def test_multilayer_rejects_bad_arguments(func, args, kwargs, match):
    """A stack needs one thickness per layer, at least one layer, and valid indices, lengths
    and angle for every layer (Born & Wolf §1.6.2); errors name the layer, e.g. ``n_layers[1]``."""
    with pytest.raises(ValueError, match=match):
        func(*args, **kwargs)


# ---------------------------------------------------------------------------------------------
# Water index, colour
# ---------------------------------------------------------------------------------------------
@pytest.mark.api
@pytest.mark.parametrize("wl", [181.9, 100.0, 1129.5, 2000.0, [500.0, 1130.0], [[181.0]], [[500.0, 1130.0]], 0.0, -5.0])
def test_water_index_outside_fitted_range(wl):
    """Daimon & Masumura's Sellmeier fit holds on 182-1129 nm only (its poles lie just outside:
    sqrt(C_i) = 71-162 nm and 3.27 µm), so other wavelengths are refused, naming the range."""
    with pytest.raises(ValueError, match=r"wavelength_nm must lie within 182-1129 nm"):
        bo.water_refractive_index(wl)


@pytest.mark.api
@pytest.mark.parametrize("wl", [NAN, INF, "500"])
def test_water_index_non_numeric(wl):
    """A non-finite or non-numeric wavelength is named as such."""
    with pytest.raises(ValueError, match=r"wavelength_nm must be (finite|numeric)"):
        bo.water_refractive_index(wl)


@pytest.mark.api
def test_water_index_accepts_the_range_ends():
    """The end points 182 and 1129 nm themselves are inside the fitted range."""
    n = bo.water_refractive_index([182.0, 1129.0])
    assert np.all(np.isfinite(n)) and n[0] > n[1] > 1.3


@pytest.mark.api
@pytest.mark.parametrize("shape", [(4, 5), (6, 4), (), (5,), (2, 3, 7)])
def test_spectrum_to_XYZ_wrong_last_axis(shape):
    """Spectra must have the wavelength on the last axis (CIE 15:2004 §7 sums over wavelength)."""
    wl = np.linspace(400.0, 700.0, 6)
    with pytest.raises(ValueError, match=r"values must have the wavelength on its last axis"):
        bo.spectrum_to_XYZ(np.ones(shape), wl)
    # the right last axis works, whatever the leading shape
    assert bo.spectrum_to_XYZ(np.ones(shape[:-1] + (6,) if shape else (6,)), wl).shape[-1] == 3

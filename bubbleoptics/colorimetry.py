"""Spectrum to colour: CIE XYZ and display sRGB, with colour-science's data and methods.

Colour matching functions, illuminants, the sRGB encoding and chromatic adaptation all come
from colour-science; this module only precomputes colour-science's *Integration* method as a
matrix, so that many spectra convert with one matrix product, and applies it to film spectra.

Start-up: importing colour-science takes one to several seconds (it pulls in scipy), which a
render would pay before its first ray.  So colour-science is imported only inside the
functions that need its general machinery (any illuminant or observer, chromatic adaptation),
and what the ray tracer needs is read from ``colour_tables.npz`` beside this file: the 1 nm
CIE 1931 2° x D65 weights, the Mallett-Yuksel basis and the dominant wavelengths of the sRGB
primaries, each computed by colour-science
(:mod:`bubbleoptics.colour_tables` writes the file, ``python -m bubbleoptics.colour_tables``;
a reference test recomputes it).  The sRGB transfer functions are written here for the same
reason (:func:`linear_srgb_to_srgb`, :func:`srgb_to_linear_srgb`).
"""

import functools
import os
import warnings

import numpy as np

from . import _args
from .film import film_reflectance, film_transmittance
from .kernels import srgb_decode_array, srgb_decode_nb, srgb_encode_array, srgb_encode_nb

__all__ = [
    "DEFAULT_OBSERVER",
    "DEFAULT_WAVELENGTHS_NM",
    "MAX_BANDS",
    "spectral_weights",
    "band_spectral_weights",
    "rgb_reflectance_basis",
    "XYZ_TO_LINEAR_SRGB",
    "COLOUR_TABLES_PATH",
    "colour_tables",
    "srgb_dominant_wavelengths",
    "linear_srgb_to_srgb",
    "srgb_to_linear_srgb",
    "spectrum_to_XYZ",
    "XYZ_to_display_sRGB",
    "film_color",
]

DEFAULT_OBSERVER = "CIE 1931 2 Degree Standard Observer"

#: colour-science's default spectral shape (360-780 nm at 1 nm): the "1 nm reference".
DEFAULT_WAVELENGTHS_NM = np.arange(360.0, 781.0, 1.0)
#: The most bands :func:`band_spectral_weights` and :func:`rgb_reflectance_basis` make of
#: 360-780 nm: 421, one per 1 nm table sample (narrower bands would hold no sample).
MAX_BANDS = DEFAULT_WAVELENGTHS_NM.size

_DEFAULT_GRID = tuple(DEFAULT_WAVELENGTHS_NM.tolist())

#: colour-science's results that the tracer needs, tabulated (see the module docstring).
COLOUR_TABLES_PATH = os.path.join(os.path.dirname(os.path.abspath(__file__)), "colour_tables.npz")


@functools.cache
def colour_tables() -> dict:
    """The arrays of ``colour_tables.npz`` (read-only), read once.

    ``wavelengths_nm`` (421,): :data:`DEFAULT_WAVELENGTHS_NM`; ``xyz_weights_d65`` (3, 421):
    :func:`spectral_weights` of that grid under D65 for the CIE 1931 2° observer;
    ``rgb_basis_mallett2019`` (421, 3): the Mallett-Yuksel basis on that grid;
    ``srgb_dominant_wavelengths_nm`` (3,); ``colour_science_version``: the version that
    computed them.
    """
    with np.load(COLOUR_TABLES_PATH, allow_pickle=False) as f:
        tables = {key: f[key] for key in f.files}
    for arr in tables.values():
        arr.flags.writeable = False
    if not np.array_equal(tables["wavelengths_nm"], DEFAULT_WAVELENGTHS_NM):
        raise RuntimeError(f"{COLOUR_TABLES_PATH} is not on DEFAULT_WAVELENGTHS_NM: regenerate it"
                           " with python -m bubbleoptics.colour_tables")
    return tables


def _resolve_illuminant(illuminant):
    import colour

    if illuminant is None or isinstance(illuminant, colour.SpectralDistribution):
        return illuminant
    try:
        return colour.SDS_ILLUMINANTS[illuminant]
    except KeyError:
        raise ValueError(
            f"illuminant must be None, a colour.SpectralDistribution or one of colour.SDS_ILLUMINANTS "
            f"(got {illuminant!r}); for example 'D65', 'A', 'E'"
        ) from None


def _resolve_observer(observer):
    import colour

    try:
        return colour.MSDS_CMFS[observer]
    except KeyError:
        raise ValueError(
            f"observer must be one of colour.MSDS_CMFS, e.g. {DEFAULT_OBSERVER!r} (got {observer!r})"
        ) from None


@functools.lru_cache(maxsize=32)
def _weights_cached(wavelengths, illuminant, observer):
    if (illuminant, observer) == ("D65", DEFAULT_OBSERVER) and wavelengths == _DEFAULT_GRID:
        return colour_tables()["xyz_weights_d65"]
    return _weights(np.array(wavelengths), illuminant, observer)


def _weights(wl, illuminant, observer):
    """colour-science's Integration method as a (3, N) matrix (imports colour-science)."""
    import colour

    cmfs = _resolve_observer(observer)
    sd_illuminant = _resolve_illuminant(illuminant)
    # colour-science's Integration method is linear in the spectrum (interpolation onto the CMF
    # grid and constant extrapolation included), so its matrix is its response to the basis.
    basis = colour.MultiSpectralDistributions(np.eye(wl.size), wl, labels=[str(i) for i in range(wl.size)])
    with warnings.catch_warnings(), colour.utilities.suppress_warnings(colour_runtime_warnings=True):
        warnings.simplefilter("ignore")
        xyz = colour.msds_to_XYZ(basis, cmfs, sd_illuminant, method="Integration")
    w = np.asarray(xyz, dtype=float).reshape(wl.size, 3).T / 100.0
    w.flags.writeable = False
    return w


def spectral_weights(wavelengths_nm, illuminant="D65", observer=DEFAULT_OBSERVER):
    """The (3, N) matrix *W* with ``XYZ = W @ values`` for spectra sampled at *wavelengths_nm*.

    Equal to colour-science's ``sd_to_XYZ(..., method="Integration") / 100`` (ASTM E308 /
    CIE 15:2004 integration: the spectrum is interpolated onto the CMF grid, Sprague for uniform
    sampling, cubic spline otherwise, extrapolated as a constant, and
    :math:`X = k\\sum_\\lambda \\bar x(\\lambda) S(\\lambda) R(\\lambda)\\Delta\\lambda` with
    :math:`k = 1/\\sum\\bar y S\\Delta\\lambda`), so Y = 1 for a perfect reflector.  Cached per
    wavelength grid, illuminant and observer.

    Parameters
    ----------
    wavelengths_nm : 1-D array_like, strictly increasing, in nm.
    illuminant : name in ``colour.SDS_ILLUMINANTS`` (default ``"D65"``), a
        ``colour.SpectralDistribution``, or ``None`` for the equal-energy illuminant E (use it for
        spectra that are already radiances).
    observer : name in ``colour.MSDS_CMFS``.

    The default case (:data:`DEFAULT_WAVELENGTHS_NM`, D65, CIE 1931 2°) is read from
    :func:`colour_tables` without importing colour-science.
    """
    wl = _args.real_array("wavelengths_nm", wavelengths_nm, minimum=0.0, strict=True)
    if wl.ndim != 1 or wl.size < 2:
        raise ValueError(f"wavelengths_nm must be 1-D with at least 2 samples (got shape {wl.shape})")
    if np.any(np.diff(wl) <= 0):
        raise ValueError("wavelengths_nm must be strictly increasing")
    if not isinstance(illuminant, (str, type(None))):  # a SpectralDistribution: not cached
        return _weights(wl, illuminant, observer)
    return _weights_cached(tuple(wl.tolist()), illuminant, observer)


def _check_bands(n_bands, lo_nm, hi_nm):
    """*n_bands* as an int: at least 1, and at most one band per 1 nm table sample in [lo, hi]."""
    samples = int(np.count_nonzero((DEFAULT_WAVELENGTHS_NM >= lo_nm) & (DEFAULT_WAVELENGTHS_NM <= hi_nm)))
    if isinstance(n_bands, bool) or int(n_bands) != n_bands or not 1 <= n_bands <= max(samples, 1):
        raise ValueError(f"n_bands must be an integer from 1 to {samples} (one band per 1 nm table sample "
                         f"of {lo_nm:g}-{hi_nm:g} nm at most), got {n_bands!r}")
    return int(n_bands)


def band_spectral_weights(n_bands, illuminant="D65", observer=DEFAULT_OBSERVER, lo_nm=360.0, hi_nm=780.0):
    """Centres (N,) and XYZ weights (3, N) of *n_bands* equal wavelength bands over [lo, hi] nm.

    A spectrum known by one value per band is taken as constant over its band, so its XYZ is
    the 1 nm integration of :func:`spectral_weights` (colour-science's Integration method over
    ``DEFAULT_WAVELENGTHS_NM``) summed over each band: ``W_band = W_1nm @ B`` with B the
    band-membership matrix (each 1 nm sample belongs to the band containing it; a sample on a
    boundary is split equally).  With 421 bands over 360-780 nm this *is* the 1 nm reference.
    Used by the tracer's spectral transport.

    >>> from bubbleoptics import band_spectral_weights
    >>> wl, W = band_spectral_weights(16)
    >>> wl.shape, W.shape, round(float(W[1].sum()), 12)  # a perfect reflector still has Y = 1
    ((16,), (3, 16), 1.0)
    """
    n_bands = _check_bands(n_bands, lo_nm, hi_nm)
    fine = DEFAULT_WAVELENGTHS_NM[(DEFAULT_WAVELENGTHS_NM >= lo_nm) & (DEFAULT_WAVELENGTHS_NM <= hi_nm)]
    w_fine = spectral_weights(DEFAULT_WAVELENGTHS_NM, illuminant, observer)
    w_fine = w_fine[:, (DEFAULT_WAVELENGTHS_NM >= lo_nm) & (DEFAULT_WAVELENGTHS_NM <= hi_nm)]
    edges = np.linspace(lo_nm, hi_nm, n_bands + 1)
    if n_bands == fine.size:  # one band per 1 nm sample: identity
        return fine.copy(), w_fine.copy()
    membership = np.zeros((fine.size, n_bands))
    for i, lam in enumerate(fine):
        inside = np.flatnonzero((lam >= edges[:-1]) & (lam <= edges[1:]))
        membership[i, inside] = 1.0 / inside.size
    centres = 0.5 * (edges[:-1] + edges[1:])
    return centres, w_fine @ membership


def rgb_reflectance_basis(n_bands, lo_nm=360.0, hi_nm=780.0):
    """(N, 3) band-averaged spectra of linear sRGB red, green and blue (Mallett & Yuksel 2019).

    A linear-sRGB reflectance ``rgb`` becomes the band spectrum ``basis @ rgb``; the basis
    (colour-science's ``MSDS_BASIS_FUNCTIONS_sRGB_MALLETT2019``, 380-780 nm) sums to one at
    every wavelength, so white stays flat, and every in-gamut colour maps to a spectrum within
    [0, 1] that reproduces it under D65 (L. Mallett and C. Yuksel, "Spectral Primary
    Decomposition for Rendering with sRGB Reflectance", EGSR 2019).  Extrapolated as constant
    outside 380-780 nm, as colour-science does.  The basis on :data:`DEFAULT_WAVELENGTHS_NM`
    (colour-science's ``align`` to 360-780 nm at 1 nm, Sprague interpolation) is read from
    :func:`colour_tables`; aligning to a narrower range gives the same values at each
    wavelength, so the range is cut from it.

    >>> from bubbleoptics import rgb_reflectance_basis
    >>> basis = rgb_reflectance_basis(16)
    >>> basis.shape, bool(abs(basis.sum(axis=1) - 1).max() < 1e-5)  # white stays flat
    ((16, 3), True)
    """
    n_bands = _check_bands(n_bands, lo_nm, hi_nm)
    inside_range = (DEFAULT_WAVELENGTHS_NM >= lo_nm) & (DEFAULT_WAVELENGTHS_NM <= hi_nm)
    fine = DEFAULT_WAVELENGTHS_NM[inside_range]
    b = colour_tables()["rgb_basis_mallett2019"][inside_range]
    edges = np.linspace(lo_nm, hi_nm, n_bands + 1)
    out = np.empty((n_bands, 3))
    for k in range(n_bands):
        inside = (fine >= edges[k]) & (fine <= edges[k + 1])
        out[k] = b[inside].mean(axis=0)
    return out


#: Linear sRGB from CIE XYZ, D65 white: the matrix as IEC 61966-2-1:1999 publishes it (four
#: decimals), which is colour-science's ``RGB_COLOURSPACES["sRGB"].matrix_XYZ_to_RGB``
#: (tests/bubbleoptics/test_colorimetry.py checks that they are equal).
XYZ_TO_LINEAR_SRGB = np.array([[3.2406, -1.5372, -0.4986],
                               [-0.9689, 1.8758, 0.0415],
                               [0.0557, -0.2040, 1.0570]])
XYZ_TO_LINEAR_SRGB.flags.writeable = False


def srgb_dominant_wavelengths():
    """Dominant wavelengths (nm) of the sRGB red, green and blue primaries, (3,).

    colour-science's ``dominant_wavelength`` of each primary's chromaticity against the D65
    white point (CIE 1931 2°), which it rounds to the 1 nm samples of the spectral locus; read
    from :func:`colour_tables`.

    >>> from bubbleoptics.colorimetry import srgb_dominant_wavelengths
    >>> srgb_dominant_wavelengths().tolist()
    [611.0, 549.0, 464.0]
    """
    return colour_tables()["srgb_dominant_wavelengths_nm"].copy()


#: Arrays of at most this many values, each finite and within +-_PY_PATH_BOUND, go through the
#: scalar kernel's Python function (``py_func``: the same formula run by CPython on Python floats,
#: with the C library's pow as in the compiled kernel, so the same bits), not the compiled array
#: kernel: a scene file's few colours then compile nothing before the render's own compile
#: (0.13 s of a sphere-only first render; docs/performance.md).  NaN, infinities and larger values
#: take the compiled kernel (CPython's ``**`` raises OverflowError where C's pow gives inf).
_PY_PATH_MAX_SIZE = 64
_PY_PATH_BOUND = 1e6


def _elementwise(kernel, scalar, a):
    """Apply a 1-D array kernel of :mod:`bubbleoptics.kernels`, or for a few values its
    scalar kernel *scalar* uncompiled (see ``_PY_PATH_MAX_SIZE``), to any array (a new float array)."""
    a = np.asarray(a, dtype=float)
    flat = np.ascontiguousarray(a).ravel()
    if flat.size <= _PY_PATH_MAX_SIZE and bool(np.all(np.abs(flat) <= _PY_PATH_BOUND)):
        out = np.array([scalar.py_func(v) for v in flat.tolist()], dtype=float)
    else:
        out = np.empty_like(flat)
        kernel(flat, out)
    return out.reshape(a.shape)[()]


def linear_srgb_to_srgb(x):
    """The sRGB encoding (IEC 61966-2-1:1999): linear-light values to display sRGB.

    .. math::  V = 12.92\\,L \\ (L \\le 0.0031308), \\qquad V = 1.055\\,L^{1/2.4} - 0.055

    Elementwise on any array; values outside [0, 1] are not clipped (negative values stay on
    the linear segment), NaN gives NaN.  Equal to ``colour.cctf_encoding(x, function="sRGB")``
    to a relative 1e-15 (NumPy's vectorised power, which colour-science uses, can differ from
    the C library's by an ulp), and to the bit to the formula with the C library's pow; written here only so that a render need not import colour-science
    (start-up time; the formula is :func:`bubbleoptics.kernels.srgb_encode_nb`).

    >>> from bubbleoptics.colorimetry import linear_srgb_to_srgb
    >>> round(float(linear_srgb_to_srgb(0.18)), 7)
    0.4613561
    """
    return _elementwise(srgb_encode_array, srgb_encode_nb, x)


def srgb_to_linear_srgb(v):
    """The sRGB decoding (IEC 61966-2-1:1999): display sRGB values to linear light.

    .. math::  L = V/12.92 \\ (V \\le 0.0031308 \\cdot 12.92), \\qquad L = ((V + 0.055)/1.055)^{2.4}

    The inverse of :func:`linear_srgb_to_srgb`; the break point is the encoded 0.0031308, as in
    colour-science (the standard rounds it to 0.04045; no 8- or 16-bit code lies between the
    two).  Equal to ``colour.cctf_decoding(v, function="sRGB")`` to a relative 1e-15.  An 8-bit code
    ``c`` decodes as ``srgb_to_linear_srgb(c / 255)``.

    >>> from bubbleoptics.colorimetry import srgb_to_linear_srgb
    >>> round(float(srgb_to_linear_srgb(128 / 255)), 6)
    0.215861
    """
    return _elementwise(srgb_decode_array, srgb_decode_nb, v)


def spectrum_to_XYZ(values, wavelengths_nm, illuminant="D65", observer=DEFAULT_OBSERVER):
    """CIE XYZ of spectra (reflectances or transmittances) under an illuminant, Y = 1 for a perfect reflector.

    .. math::  X_i = \\frac{\\sum_\\lambda \\bar x_i(\\lambda)S(\\lambda)R(\\lambda)\\Delta\\lambda}
                           {\\sum_\\lambda \\bar y(\\lambda)S(\\lambda)\\Delta\\lambda}

    (CIE 15:2004 §7), computed as one matrix product with :func:`spectral_weights`; equals
    ``colour.sd_to_XYZ(sd, cmfs, illuminant, method="Integration") / 100`` to 1e-10.

    Parameters
    ----------
    values : array_like (..., N), the spectra, wavelength on the last axis.
    wavelengths_nm : array_like (N,), in nm.
    illuminant, observer : see :func:`spectral_weights`.

    Returns
    -------
    ndarray (..., 3).

    Examples
    --------
    >>> import numpy as np
    >>> from bubbleoptics import spectrum_to_XYZ
    >>> wl = np.arange(380.0, 781.0, 5.0)
    >>> XYZ = spectrum_to_XYZ(np.ones_like(wl), wl)  # perfect reflector under D65
    >>> [round(float(v), 4) for v in XYZ]
    [0.9505, 1.0, 1.0888]
    """
    v = _args.real_array("values", values)
    wl = np.asarray(wavelengths_nm, dtype=float)
    if v.ndim == 0 or v.shape[-1] != wl.size:
        raise ValueError(
            f"values must have the wavelength on its last axis: shape {v.shape} does not end in "
            f"{wl.size} (the number of wavelengths_nm)"
        )
    return v @ spectral_weights(wl, illuminant, observer).T


def _whitepoint_xy(illuminant, observer, wl):
    import colour

    if isinstance(illuminant, str):
        ccs = colour.CCS_ILLUMINANTS.get(observer, {})
        if illuminant in ccs:
            return np.asarray(ccs[illuminant], dtype=float)
    return colour.XYZ_to_xy(spectrum_to_XYZ(np.ones(wl.size), wl, illuminant, observer))


def XYZ_to_display_sRGB(XYZ, illuminant="D65", observer=DEFAULT_OBSERVER, gamut="clip"):
    """Display sRGB (IEC 61966-2-1, encoded, in [0, 1]) of XYZ with Y = 1 for white.

    Uses ``colour.XYZ_to_sRGB`` with the illuminant's white point (CAT02 adaptation to D65
    when the illuminant is not D65), then the sRGB encoding.

    Out-of-gamut colours (``gamut="clip"``, the default) are clipped per channel in *linear*
    sRGB to [0, 1] before encoding: a negative channel (the saturated blue-greens of
    higher-order interference) becomes 0, so the hue shifts slightly toward the gamut boundary
    while lightness ordering is kept.  ``gamut="none"`` returns the encoded values unclipped
    (possibly outside [0, 1]; negative linear values encode as negative).
    """
    if gamut not in ("clip", "none"):
        raise ValueError(f"gamut must be 'clip' or 'none' (got {gamut!r})")
    import colour

    XYZ = np.asarray(XYZ, dtype=float)
    wp = _whitepoint_xy(illuminant, observer, DEFAULT_WAVELENGTHS_NM)
    rgb = colour.XYZ_to_sRGB(XYZ, illuminant=wp, apply_cctf_encoding=False)
    if gamut == "clip":
        rgb = np.clip(rgb, 0.0, 1.0)
    return colour.cctf_encoding(rgb, function="sRGB")


def film_color(
    thickness_nm,
    theta=0.0,
    n_film=None,
    n_outside=1.0,
    n_inside=None,
    illuminant="D65",
    observer=DEFAULT_OBSERVER,
    polarization="unpolarized",
    *,
    wavelengths_nm=None,
    quantity="reflectance",
    gamut="clip",
):
    """Display sRGB colour of a thin film seen in reflection (or transmission) under an illuminant.

    Computes the exact film spectrum (:func:`film_reflectance`) at *wavelengths_nm* (default
    360-780 nm every 1 nm, the grid of the CIE 1931 tables in colour-science), converts it to
    XYZ (:func:`spectrum_to_XYZ`) and to display sRGB (:func:`XYZ_to_display_sRGB`; see there
    for out-of-gamut handling).  A perfect reflector maps to sRGB white.

    Parameters
    ----------
    thickness_nm : array_like, film thickness in nm (>= 0).
    theta : array_like, angle of incidence in radians (broadcasts with *thickness_nm*).
    n_film : None (water, :func:`water_refractive_index`), a scalar, or an array (N,) given per
        wavelength of *wavelengths_nm*.
    n_outside, n_inside, polarization : as :func:`film_reflectance`.
    illuminant, observer : see :func:`spectral_weights`.
    quantity : ``"reflectance"`` (default) or ``"transmittance"``.

    Returns
    -------
    ndarray (..., 3), encoded sRGB, the leading shape that of thickness and theta broadcast.

    Examples
    --------
    >>> import numpy as np
    >>> from bubbleoptics import film_color
    >>> film_color(0.0).tolist()  # no film, no reflection: black
    [0.0, 0.0, 0.0]
    >>> [round(v, 3) for v in film_color(10.0).tolist()]  # R ~ 1/lambda^2: a dark blue-grey
    [0.018, 0.026, 0.04]
    >>> film_color(np.linspace(0, 2000, 500), theta=np.pi / 3).shape
    (500, 3)
    """
    if quantity not in ("reflectance", "transmittance"):
        raise ValueError(f"quantity must be 'reflectance' or 'transmittance' (got {quantity!r})")
    wl = DEFAULT_WAVELENGTHS_NM if wavelengths_nm is None else _args.real_array("wavelengths_nm", wavelengths_nm)
    d = _args.real_array("thickness_nm", thickness_nm, minimum=0.0)
    th = _args.angle_array("theta", theta)
    lead = _args.broadcast_shape(thickness_nm=d, theta=th)
    func = film_reflectance if quantity == "reflectance" else film_transmittance
    spectrum = func(wl, d[..., None], th[..., None], n_film, n_outside, n_inside, polarization)
    spectrum = np.broadcast_to(spectrum, lead + (wl.size,))
    XYZ = spectrum_to_XYZ(spectrum, wl, illuminant, observer)
    return XYZ_to_display_sRGB(XYZ, illuminant, observer, gamut)

"""RGB-to-spectrum liftings other than the tracer's, as band spectra on the tracer's grid.

The tracer turns an RGB colour (a material's, a light's, an environment's) into a spectrum by
the Mallett-Yuksel basis (:func:`bubbleoptics.rgb_reflectance_basis`, normalised in
``tracer.prepare.pack.channel_setup`` so that a colour seen directly comes back unchanged).
That choice is one of several; the Cycles comparison (``benchmarks/peer_cycles_lifting.py``)
asks how much its attribution depends on it.  Each lifting here takes linear-sRGB triples
(..., 3), read as reflectances under D65 (the tracer's convention: a channel value is a factor
on D65, so (1, 1, 1) is a flat spectrum), and returns their band spectra (..., C) on the
tracer's grid of *n_bands* equal bands over 360-780 nm: the spectrum at 1 nm, averaged over
each band as :func:`bubbleoptics.rgb_reflectance_basis` does (a sample on a band edge counts in
both bands; 421 bands are the 1 nm samples themselves).  The implementations are colour-science's (imported when called):

* ``"Mallett2019"`` -- the tracer's own lifting (``channel_setup``'s normalised basis), linear;
* ``"Jakob2019"`` -- Jakob & Hanika's sigmoid of a quadratic (``find_coefficients_Jakob2019``,
  ``sd_Jakob2019``), fitted to the colour's CIELAB under D65 and the CIE 1931 observer: smooth,
  within (0, 1), non-linear in the colour; about 0.2 s per colour;
* ``"Smits1999"`` -- Smits' piecewise-constant white/cyan/magenta/yellow/red/green/blue spectra
  (``RGB_to_sd_Smits1999``, sRGB primaries, white flat), ten bins over 380-720 nm, aligned to
  1 nm by colour-science's interpolation and constant extrapolation: piecewise linear in the
  colour;
* ``"Otsu2018"`` -- Otsu, Yamamoto & Hachisuka's PCA of measured reflectances in clusters
  (``XYZ_to_sd_Otsu2018``, its reference dataset, 380-730 nm, extrapolated as constant).

:func:`to_rgb` is the tracer's band pipeline back to linear sRGB (D65 band weights, the inverse
of what the liftings are checked against; the tests check each lifting independently with
colour-science's ``sd_to_XYZ``).  A lifting other than Mallett-Yuksel does not return exactly
its colour through the 64-band pipeline; :func:`corrected` adds the Mallett-Yuksel spectrum of
the residual so that it does (the tracer's normalisation, for the others), and
:func:`linear_fit` gives the best basis (C, 3) for a set of colours, which is how a non-linear
lifting enters the tracer (whose environment lookup is linear in RGB).
"""

from __future__ import annotations

import numpy as np

__all__ = ["METHODS", "band_average", "lift", "to_rgb", "corrected", "linear_fit", "xyz_of_rgb"]

#: The liftings, the tracer's first.
METHODS = ("Mallett2019", "Jakob2019", "Smits1999", "Otsu2018")

_FINE = np.arange(360.0, 781.0, 1.0)


def band_average(fine_values, n_bands, lo_nm=360.0, hi_nm=780.0):
    """(..., C): values at 1 nm over [lo, hi] (..., N) averaged over *n_bands* equal bands, the
    samples on a band's edges counting in it (as :func:`bubbleoptics.rgb_reflectance_basis`)."""
    v = np.asarray(fine_values, float)
    fine = np.arange(lo_nm, hi_nm + 0.5, 1.0)
    if v.shape[-1] != fine.size:
        raise ValueError(f"expected {fine.size} samples at 1 nm over {lo_nm:g}-{hi_nm:g} nm, got {v.shape[-1]}")
    if n_bands == fine.size:  # one band per sample: the samples themselves
        return v.copy()
    edges = np.linspace(lo_nm, hi_nm, n_bands + 1)
    m = ((fine[:, None] >= edges[None, :-1]) & (fine[:, None] <= edges[None, 1:])).astype(float)
    return v @ (m / m.sum(axis=0))


def xyz_of_rgb(rgb):
    """CIE XYZ (Y = 1 for white, D65) of linear sRGB (..., 3) (the tracer's matrix, inverted)."""
    from bubbleoptics.colorimetry import XYZ_TO_LINEAR_SRGB

    return np.asarray(rgb, float) @ np.linalg.inv(XYZ_TO_LINEAR_SRGB).T


def _fine_shape():
    import colour

    return colour.SpectralShape(360.0, 780.0, 1.0)


def _aligned(sd):
    """A colour-science spectrum's values at 1 nm over 360-780 nm (its own interpolation, constant
    extrapolation)."""
    return sd.copy().align(_fine_shape()).values


def _jakob2019_fine(rgb):
    from colour.recovery import find_coefficients_Jakob2019, sd_Jakob2019

    coefficients, _error = find_coefficients_Jakob2019(xyz_of_rgb(rgb))
    return sd_Jakob2019(coefficients, _fine_shape()).values


def _smits1999_fine(rgb):
    import warnings

    from colour.recovery import RGB_to_sd_Smits1999

    with warnings.catch_warnings():  # its ten bins' float spacing is "not uniform": the minimum interval is used
        warnings.filterwarnings("ignore", message=".*not uniform, using minimum interval")
        return _aligned(RGB_to_sd_Smits1999(np.asarray(rgb, float)))


def _otsu2018_fine(rgb):
    from colour.recovery import XYZ_to_sd_Otsu2018

    return _aligned(XYZ_to_sd_Otsu2018(xyz_of_rgb(rgb)))


_FINE_LIFTINGS = {"Jakob2019": _jakob2019_fine, "Smits1999": _smits1999_fine, "Otsu2018": _otsu2018_fine}


def lift(rgb, method, n_bands):
    """Band spectra (..., n_bands) of the linear-sRGB reflectances *rgb* (..., 3) by *method*
    (one of :data:`METHODS`), one colour at a time for the non-linear ones."""
    rgb = np.asarray(rgb, float)
    if rgb.shape[-1] != 3:
        raise ValueError(f"rgb must have 3 components in its last axis, got shape {rgb.shape}")
    if method == "Mallett2019":
        from tracer.prepare.pack import channel_setup

        _, _, basis = channel_setup(True, n_bands)
        return rgb @ basis.T
    if method not in _FINE_LIFTINGS:
        raise ValueError(f"unknown lifting {method!r}: one of {', '.join(METHODS)}")
    flat = rgb.reshape(-1, 3)
    fine = np.array([_FINE_LIFTINGS[method](c) for c in flat]).reshape(flat.shape[0], _FINE.size)
    return band_average(fine, n_bands).reshape(rgb.shape[:-1] + (n_bands,))


def to_rgb(spectra):
    """Linear sRGB (..., 3) of band spectra (..., C) under D65: the tracer's ``to_rgb``."""
    from tracer.prepare.pack import channel_setup

    spectra = np.asarray(spectra, float)
    _, matrix, _ = channel_setup(True, spectra.shape[-1])
    return spectra @ matrix.T


def corrected(spectra, rgb):
    """*spectra* (..., C) plus the Mallett-Yuksel spectrum of what they miss of *rgb* (..., 3)
    through :func:`to_rgb`, so that they return *rgb* exactly (the residual is small; the
    spectrum's shape, which the film sees, is the lifting's)."""
    from tracer.prepare.pack import channel_setup

    spectra = np.asarray(spectra, float)
    _, _, basis = channel_setup(True, spectra.shape[-1])
    return spectra + (np.asarray(rgb, float) - to_rgb(spectra)) @ basis.T


def linear_fit(rgb, spectra):
    """The basis B (C, 3) with ``rgb @ B.T`` closest to *spectra* (P, C) in least squares, for
    the colours *rgb* (P, 3): a non-linear lifting made linear over these colours (the tracer
    multiplies an environment's RGB by one such basis); and the fit's largest absolute
    residual."""
    rgb = np.asarray(rgb, float).reshape(-1, 3)
    spectra = np.asarray(spectra, float).reshape(rgb.shape[0], -1)
    solution, *_ = np.linalg.lstsq(rgb, spectra, rcond=None)  # (3, C)
    residual = float(np.abs(rgb @ solution - spectra).max())
    return solution.T, residual

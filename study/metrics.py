"""Colour and image differences: the project's one CIEDE2000, and the errors of a render.

Every colour difference in the repository (benchmarks, notebooks, paper) is
:func:`delta_e00_XYZ` or :func:`delta_e00` (which converts linear sRGB and calls it): CIE L*a*b*
by ``colour.XYZ_to_Lab`` and CIEDE2000 by ``colour.delta_E(..., method="CIE 2000")`` of
colour-science (CIE 142-2001; Sharma, Wu & Dalal 2005, Color Res. Appl. 30, 21).  About 1-2 is a
just-noticeable difference side by side.

colour-science is imported inside the functions (``import study`` stays light).
"""

from __future__ import annotations

import numpy as np

__all__ = ["delta_e00_XYZ", "delta_e00", "delta_e00_images", "rmse", "finite_image"]

_OBSERVER = "CIE 1931 2 Degree Standard Observer"


def delta_e00_XYZ(XYZ_a, XYZ_b, illuminant="D65", exposure=1.0):
    """CIEDE2000 ΔE00 between two arrays of CIE XYZ colours (last axis X, Y, Z).

    Both are multiplied by *exposure* (a camera's exposure: Y = 1 is the white, L* = 100), taken
    to CIE L*a*b* relative to *illuminant*'s white (``colour.XYZ_to_Lab``), and compared with
    ``colour.delta_E(..., method="CIE 2000")``.

    Parameters
    ----------
    XYZ_a, XYZ_b : array_like ``(..., 3)``, broadcast against each other.
    illuminant : name of a CIE 1931 2° illuminant in ``colour.CCS_ILLUMINANTS`` (``"D65"``,
        ``"E"``, ...) or its chromaticity coordinates ``(x, y)``.
    exposure : factor applied to both colours first.

    Returns
    -------
    ndarray of shape ``broadcast(XYZ_a, XYZ_b).shape[:-1]``.

    Example
    -------
    >>> white = np.array([0.95047, 1.0, 1.08883])
    >>> float(delta_e00_XYZ(white, white)), round(float(delta_e00_XYZ(white, 0.5 * white)), 2)
    (0.0, 15.28)
    """
    import colour

    white = colour.CCS_ILLUMINANTS[_OBSERVER][illuminant] if isinstance(illuminant, str) else illuminant
    lab_a = colour.XYZ_to_Lab(exposure * np.asarray(XYZ_a, dtype=float), white)
    lab_b = colour.XYZ_to_Lab(exposure * np.asarray(XYZ_b, dtype=float), white)
    return np.asarray(colour.delta_E(lab_a, lab_b, method="CIE 2000"), dtype=float)


def delta_e00(rgb_a, rgb_b):
    """Per-pixel CIEDE2000 colour difference ΔE00 between two linear-sRGB images.

    Each image (array ``(..., 3)``, linear sRGB, *not* gamma-encoded; the tracer's output) is
    converted to CIE XYZ with the sRGB primaries and D65 white (``colour.RGB_to_XYZ``, no
    decoding) and compared by :func:`delta_e00_XYZ` relative to that white.  Values are
    absolute: linear RGB (1, 1, 1) is white with Y = 1 and L* = 100, so scale HDR images by the
    same exposure before comparing.

    Returns
    -------
    ndarray of shape ``broadcast(rgb_a, rgb_b).shape[:-1]``.

    Example
    -------
    >>> a = np.full((2, 2, 3), 0.5)
    >>> delta_e00(a, a).tolist()
    [[0.0, 0.0], [0.0, 0.0]]
    """
    import colour

    a = np.asarray(rgb_a, dtype=float)
    b = np.asarray(rgb_b, dtype=float)
    if a.shape[-1:] != (3,) or b.shape[-1:] != (3,):
        raise ValueError(f"images must have 3 channels in the last axis (got {a.shape} and {b.shape})")
    a, b = np.broadcast_arrays(a, b)
    space = colour.RGB_COLOURSPACES["sRGB"]
    white = space.whitepoint

    def xyz(rgb):
        return colour.RGB_to_XYZ(rgb, space, illuminant=white, chromatic_adaptation_transform=None,
                                 apply_cctf_decoding=False)

    return delta_e00_XYZ(xyz(a), xyz(b), white)


def delta_e00_images(image, reference):
    """Per-pixel ΔE00 (:func:`delta_e00`) of two renders in linear sRGB, negative values clipped
    to 0 first: spectral transport can leave saturated colours slightly outside the sRGB gamut,
    and L*a*b* of a negative RGB is not a colour.

    Example
    -------
    >>> float(delta_e00_images([[-0.1, 0.5, 0.5]], [[0.0, 0.5, 0.5]])[0])
    0.0
    """
    return delta_e00(np.clip(image, 0.0, None), np.clip(reference, 0.0, None))


def rmse(a, b):
    """Root mean square difference of two arrays (over every element: pixels and channels).

    Example
    -------
    >>> rmse([0.0, 0.0], [3.0, 4.0]) == (12.5) ** 0.5
    True
    """
    return float(np.sqrt(np.mean((np.asarray(a, dtype=float) - np.asarray(b, dtype=float)) ** 2)))


def finite_image(image):
    """``(image with non-finite values set to 0, number of pixels that had one)``, as
    ``tracer.save_image`` writes such pixels.

    Example
    -------
    >>> clean, bad = finite_image([[[np.nan, 0.5, 0.5], [0.2, 0.2, 0.2]]])
    >>> clean[0, 0].tolist(), bad
    ([0.0, 0.5, 0.5], 1)
    """
    image = np.asarray(image, dtype=float)
    bad = ~np.isfinite(image).all(axis=-1)
    return np.where(np.isfinite(image), image, 0.0), int(bad.sum())

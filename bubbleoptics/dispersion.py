"""Refractive indices of the media in a soap bubble.

Units: wavelength in nm; the index is dimensionless (real: water's absorption coefficient in the
visible, k ~ 1e-9 (Hale & Querry 1973), is negligible for films a few microns thick).
"""

import numpy as np

from . import _args
from .kernels import water_index_array

__all__ = ["water_refractive_index", "WATER_DAIMON2007_RANGE_NM"]

#: Wavelength range (nm) over which the Daimon & Masumura (2007) fit was measured.
WATER_DAIMON2007_RANGE_NM = (182.0, 1129.0)


def water_refractive_index(wavelength_nm):
    """Refractive index of liquid water at 20 °C, Daimon & Masumura (2007).

    .. math::  n^2(\\lambda) - 1 = \\sum_{i=1}^{4}\\frac{B_i\\lambda^2}{\\lambda^2 - C_i}

    with :math:`\\lambda` in µm and the four-term Sellmeier coefficients fitted to
    measurements on distilled water from 182 to 1129 nm (M. Daimon and A. Masumura,
    "Measurement of the refractive index of distilled water from the near-infrared region to
    the ultraviolet region", *Appl. Opt.* **46**, 3811-3820 (2007), doi:10.1364/AO.46.003811).
    The default index of a soap film: the surfactant layers (~2 nm) change a micron-scale
    film's optical thickness by well under 1 %.

    Parameters
    ----------
    wavelength_nm : array_like, vacuum wavelength in nm, within 182-1129 nm.

    Returns
    -------
    ndarray of float (NumPy scalar for scalar input).

    Raises
    ------
    ValueError outside the fitted range (the Sellmeier form has poles just outside it).

    Examples
    --------
    >>> from bubbleoptics import water_refractive_index
    >>> round(float(water_refractive_index(587.6)), 4)  # sodium D line
    1.3334
    """
    lo, hi = WATER_DAIMON2007_RANGE_NM
    wl = _args.real_array("wavelength_nm", wavelength_nm)
    bad = (wl < lo) | (wl > hi)
    if bad.any():
        value = wl[tuple(np.argwhere(bad)[0])] if wl.ndim else wl
        raise ValueError(
            f"wavelength_nm must lie within {lo:g}-{hi:g} nm for the Daimon & Masumura (2007) water "
            f"index (got {float(value)!r}); pass n_film explicitly outside that range"
        )
    out = water_index_array(np.ascontiguousarray(wl.reshape(-1))).reshape(wl.shape)
    return out[()] if out.ndim == 0 else out

"""bubbleoptics: exact thin-film optics and colour of soap bubbles.

Units everywhere: wavelength and thickness in nanometres, angles in radians, complex refractive
index ``n + ik`` with ``k >= 0``.  Polarization is ``"s"``, ``"p"`` or ``"unpolarized"``.

The physics lives once, as numba kernels in :mod:`bubbleoptics.kernels`; the functions below
broadcast over them like NumPy ufuncs, and the ray tracer (:mod:`tracer`) calls the same kernels.

Importing it changes no process-wide setting: an application that runs parallel kernels on a
shared machine may call :func:`bubbleoptics.resources.prefer_workqueue_threads` (the ``tracer``
command does).
"""

from .bandlimited import film_color_bandlimited, film_reflectance_band, point_sampling_limit_nm
from .colorimetry import (
    XYZ_to_display_sRGB,
    band_spectral_weights,
    film_color,
    rgb_reflectance_basis,
    spectral_weights,
    spectrum_to_XYZ,
)
from .dispersion import water_refractive_index
from .film import film_reflectance, film_rt, film_transmittance, two_beam_reflectance
from .fresnel import FresnelCoefficients, fresnel_coefficients
from .multilayer import multilayer_reflectance, multilayer_rt, multilayer_transmittance



def _installed_version() -> str:
    """The version of the installed distribution (pyproject.toml's, the one source)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("bubbleoptics")
    except PackageNotFoundError:  # a source tree that is not installed
        return "0+unknown"


__version__ = _installed_version()

__all__ = [
    "film_reflectance",
    "film_transmittance",
    "film_rt",
    "two_beam_reflectance",
    "fresnel_coefficients",
    "FresnelCoefficients",
    "multilayer_reflectance",
    "multilayer_transmittance",
    "multilayer_rt",
    "water_refractive_index",
    "spectrum_to_XYZ",
    "spectral_weights",
    "band_spectral_weights",
    "rgb_reflectance_basis",
    "XYZ_to_display_sRGB",
    "film_color",
    "film_reflectance_band",
    "film_color_bandlimited",
    "point_sampling_limit_nm",
]

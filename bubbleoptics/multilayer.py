"""Reflectance and transmittance of a stack of films (transfer matrices).

A soap film is really surfactant | water | surfactant; this module computes such stacks.
Units: nm, radians, complex index n + ik with k >= 0.
"""

import numpy as np

from . import _args
from .kernels import multilayer_array

__all__ = ["multilayer_reflectance", "multilayer_transmittance", "multilayer_rt"]


def multilayer_rt(
    wavelength_nm, n_layers, thicknesses_nm, theta, n_outside=1.0, n_inside=None, polarization="unpolarized"
):
    """(R, T) of a stack of layers between an outside and an inside medium.

    Characteristic-matrix method (Abelès; Born & Wolf, *Principles of Optics*, 7th ed.,
    §1.6.2; Macleod, *Thin-Film Optical Filters*, §2.2), with each layer's matrix scaled by its
    phase factor so thick absorbing layers cannot overflow (see
    :func:`bubbleoptics.kernels.multilayer_rt_nb`).  For one layer it equals
    :func:`film_reflectance` to rounding.

    Parameters
    ----------
    wavelength_nm : array_like, vacuum wavelength in nm (> 0).
    n_layers : sequence of array_like, one complex index n + ik per layer (outermost first);
        each may be an array (for example per wavelength) broadcasting with the other arguments.
    thicknesses_nm : sequence of array_like, one thickness (>= 0, nm) per layer.
    theta : array_like, angle of incidence in the outside medium (radians, |theta| <= pi/2).
    n_outside, n_inside, polarization : as for :func:`film_reflectance`.

    Returns
    -------
    (R, T), each of the broadcast shape.

    Examples
    --------
    >>> import numpy as np
    >>> from bubbleoptics import multilayer_reflectance, film_reflectance
    >>> wl = np.array([450.0, 550.0, 650.0])
    >>> R3 = multilayer_reflectance(wl, [1.45, 1.333, 1.45], [2.0, 500.0, 2.0], 0.3)
    >>> R1 = film_reflectance(wl, 500.0, 0.3, 1.333)
    >>> bool(np.all(np.abs(R3 - R1) < 0.01))  # 2 nm of surfactant changes little
    True
    """
    pol = _args.polarization_code(polarization)
    n_layers = _layer_list("n_layers", n_layers)
    thicknesses_nm = _layer_list("thicknesses_nm", thicknesses_nm)
    if len(n_layers) != len(thicknesses_nm):
        raise ValueError(
            f"n_layers has {len(n_layers)} layers but thicknesses_nm has {len(thicknesses_nm)}"
        )
    if len(n_layers) == 0:
        raise ValueError("n_layers must hold at least one layer")
    wl = _args.real_array("wavelength_nm", wavelength_nm, minimum=0.0, strict=True)
    th = _args.angle_array("theta", theta)
    n0 = _args.index_array("n_outside", n_outside, real=True)
    nm = n0.astype(complex) if n_inside is None else _args.index_array("n_inside", n_inside)
    ns = [_args.index_array(f"n_layers[{j}]", v) for j, v in enumerate(n_layers)]
    ds = [_args.real_array(f"thicknesses_nm[{j}]", v, minimum=0.0) for j, v in enumerate(thicknesses_nm)]
    named = {"wavelength_nm": wl, "theta": th, "n_outside": n0, "n_inside": nm}
    named.update({f"n_layers[{j}]": v for j, v in enumerate(ns)})
    named.update({f"thicknesses_nm[{j}]": v for j, v in enumerate(ds)})
    shape = _args.broadcast_shape(**named)
    wl_f, cos_f, n0_f, nm_f = _args.flat_optical(shape, wl, np.cos(th), n0, nm)
    n_stack = np.stack(_args.flat_optical(shape, *ns), axis=-1)
    d_stack = np.stack(_args.flat_optical(shape, *ds), axis=-1)
    r, t = multilayer_array(wl_f, n_stack, d_stack, cos_f, n0_f, nm_f, pol)
    r = r.reshape(shape)
    t = t.reshape(shape)
    if r.ndim == 0:
        return r[()], t[()]
    return r, t


def _layer_list(name, seq):
    """A per-layer sequence whose entries may be scalars or arrays of different shapes."""
    if isinstance(seq, np.ndarray):
        if seq.ndim == 0:
            raise ValueError(f"{name} must be a sequence with one entry per layer (got a scalar)")
        return list(seq)
    if isinstance(seq, (str, bytes)) or not hasattr(seq, "__len__"):
        raise ValueError(f"{name} must be a sequence with one entry per layer (got {type(seq).__name__})")
    return list(seq)


def multilayer_reflectance(
    wavelength_nm, n_layers, thicknesses_nm, theta, n_outside=1.0, n_inside=None, polarization="unpolarized"
):
    """Reflectance of a stack of layers; arguments as :func:`multilayer_rt`."""
    return multilayer_rt(wavelength_nm, n_layers, thicknesses_nm, theta, n_outside, n_inside, polarization)[0]


def multilayer_transmittance(
    wavelength_nm, n_layers, thicknesses_nm, theta, n_outside=1.0, n_inside=None, polarization="unpolarized"
):
    """Transmittance of a stack of layers; arguments as :func:`multilayer_rt`."""
    return multilayer_rt(wavelength_nm, n_layers, thicknesses_nm, theta, n_outside, n_inside, polarization)[1]

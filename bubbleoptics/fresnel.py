"""Fresnel coefficients of a single interface (pure functions, as pbrt keeps them)."""

from typing import NamedTuple

import numpy as np

from . import _args
from .kernels import fresnel_array

__all__ = ["FresnelCoefficients", "fresnel_coefficients"]


class FresnelCoefficients(NamedTuple):
    """Amplitude (complex) and power (real) coefficients of one interface."""

    rs: np.ndarray
    rp: np.ndarray
    ts: np.ndarray
    tp: np.ndarray
    Rs: np.ndarray
    Rp: np.ndarray
    Ts: np.ndarray
    Tp: np.ndarray


def fresnel_coefficients(n1, n2, theta1):
    """Fresnel amplitude coefficients rs, rp, ts, tp and power coefficients of one interface.

    .. math::

        r_s = \\frac{n_1\\cos\\theta_1 - n_2\\cos\\theta_2}{n_1\\cos\\theta_1 + n_2\\cos\\theta_2},\\quad
        t_s = \\frac{2n_1\\cos\\theta_1}{n_1\\cos\\theta_1 + n_2\\cos\\theta_2},\\quad
        r_p = \\frac{n_2\\cos\\theta_1 - n_1\\cos\\theta_2}{n_2\\cos\\theta_1 + n_1\\cos\\theta_2},\\quad
        t_p = \\frac{2n_1\\cos\\theta_1}{n_2\\cos\\theta_1 + n_1\\cos\\theta_2}

    (Born & Wolf, *Principles of Optics*, 7th ed., §1.5.2; signs as in Byrnes' ``tmm``,
    arXiv:1603.02720), with :math:`n_2\\cos\\theta_2 = \\sqrt{(n_2-n_1)(n_2+n_1) + n_1^2\\cos^2\\theta_1}`
    (no cancellation near grazing incidence) and the differences in the numerators evaluated
    from exact identities (no cancellation near index match).  Power coefficients:
    :math:`R = |r|^2`, :math:`T_s = \\operatorname{Re}(n_2\\cos\\theta_2)/(n_1\\cos\\theta_1)|t_s|^2`,
    :math:`T_p = \\operatorname{Re}(n_2\\overline{\\cos\\theta_2})/(n_1\\cos\\theta_1)|t_p|^2`.

    Parameters
    ----------
    n1 : array_like, real index of the incidence medium (> 0).
    n2 : array_like, complex index n + ik of the second medium (k >= 0).
    theta1 : array_like, angle of incidence in radians, |theta1| <= pi/2.

    Returns
    -------
    FresnelCoefficients with fields rs, rp, ts, tp (complex) and Rs, Rp, Ts, Tp (float), each of
    the broadcast shape.

    Examples
    --------
    >>> import numpy as np
    >>> from bubbleoptics import fresnel_coefficients
    >>> f = fresnel_coefficients(1.0, 1.5, 0.0)
    >>> round(float(f.Rs), 6), round(float(f.Rs + f.Ts), 12)  # ((1-1.5)/(1+1.5))^2, energy
    (0.04, 1.0)
    >>> brewster = np.arctan(1.5)
    >>> bool(fresnel_coefficients(1.0, 1.5, brewster).Rp < 1e-30)
    True
    """
    a1 = _args.index_array("n1", n1, real=True)
    a2 = _args.index_array("n2", n2)
    th = _args.angle_array("theta1", theta1)
    shape = _args.broadcast_shape(n1=a1, n2=a2, theta1=th)
    f1, f2, fc = _args.flat_optical(shape, a1, a2, np.cos(th))
    amp, power = fresnel_array(f1, f2, fc)

    def unflat(x):
        x = x.reshape(shape)
        return x[()] if x.ndim == 0 else x

    return FresnelCoefficients(*(unflat(a) for a in amp), *(unflat(p) for p in power))

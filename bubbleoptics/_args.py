"""Argument checking and broadcasting shared by the public NumPy API.

Every public function validates its inputs here, so that bad arguments raise one
``ValueError`` naming the argument and saying why, before any numba code runs.
"""

import numpy as np

from .kernels import POL_P, POL_S, POL_UNPOLARIZED

_POLARIZATIONS = {"s": POL_S, "p": POL_P, "unpolarized": POL_UNPOLARIZED}


def polarization_code(polarization):
    """Map ``"s"``, ``"p"`` or ``"unpolarized"`` to the kernels' integer code."""
    try:
        return _POLARIZATIONS[polarization]
    except (KeyError, TypeError):
        raise ValueError(
            f"polarization must be one of 's', 'p', 'unpolarized' (got {polarization!r})"
        ) from None


def _as_array(name, value, dtype):
    try:
        arr = np.asarray(value)
    except Exception as exc:  # ragged lists and the like
        raise ValueError(f"{name} could not be converted to an array: {exc}") from None
    if arr.dtype == object or arr.dtype.kind not in "biufc":
        raise ValueError(f"{name} must be numeric (got dtype {arr.dtype})")
    if dtype is float and arr.dtype.kind == "c":
        if np.any(arr.imag != 0):
            raise ValueError(f"{name} must be real (got complex values)")
        arr = arr.real
    return arr.astype(dtype, copy=False)


def _first_bad(mask):
    idx = np.argwhere(mask)[0]
    return tuple(int(i) for i in idx) if idx.size else ()


def real_array(name, value, *, minimum=None, strict=False, maximum=None):
    """A finite float array, optionally bounded; raises ValueError naming *name*."""
    arr = _as_array(name, value, float)
    bad = ~np.isfinite(arr)
    if bad.any():
        where = _first_bad(bad)
        raise ValueError(f"{name} must be finite (got {arr[where]!r} at index {where})")
    if minimum is not None:
        bad = arr <= minimum if strict else arr < minimum
        if bad.any():
            where = _first_bad(bad)
            rel = ">" if strict else ">="
            raise ValueError(f"{name} must be {rel} {minimum} (got {arr[where]!r} at index {where})")
    if maximum is not None:
        bad = arr > maximum
        if bad.any():
            where = _first_bad(bad)
            raise ValueError(f"{name} must be <= {maximum} (got {arr[where]!r} at index {where})")
    return arr


def index_array(name, value, *, real=False):
    """A complex refractive index array n + ik with n > 0 and k >= 0 (k == 0 if *real*)."""
    arr = _as_array(name, value, complex)
    bad = ~np.isfinite(arr)
    if bad.any():
        where = _first_bad(bad)
        raise ValueError(f"{name} must be finite (got {arr[where]!r} at index {where})")
    bad = arr.real <= 0
    if bad.any():
        where = _first_bad(bad)
        raise ValueError(f"{name} must have a positive real part n (got {arr[where]!r} at index {where})")
    if real:
        bad = arr.imag != 0
        if bad.any():
            where = _first_bad(bad)
            raise ValueError(
                f"{name} must be real: the incidence medium has to be lossless for the angle of "
                f"incidence to be defined (got {arr[where]!r} at index {where})"
            )
        return arr.real.copy()
    bad = arr.imag < 0
    if bad.any():
        where = _first_bad(bad)
        raise ValueError(
            f"{name} must have k >= 0 in n + ik (absorbing media have k > 0; got {arr[where]!r} "
            f"at index {where})"
        )
    # Normalise -0.0 imaginary parts so the kernels' branch choice sees +0.0.
    return arr + 0.0


def angle_array(name, value):
    """Angles of incidence in radians, |theta| <= pi/2 (R and T are even in theta)."""
    arr = real_array(name, value)
    bad = np.abs(arr) > np.pi / 2
    if bad.any():
        where = _first_bad(bad)
        raise ValueError(
            f"{name} must satisfy |theta| <= pi/2 radians (got {arr[where]!r} at index {where}); "
            "angles are in radians, not degrees"
        )
    return arr


def broadcast_shape(**arrays):
    """np.broadcast_shapes with an error message that names the arguments."""
    try:
        return np.broadcast_shapes(*(a.shape for a in arrays.values()))
    except ValueError:
        desc = ", ".join(f"{k} {v.shape}" for k, v in arrays.items())
        raise ValueError(f"arguments have incompatible shapes for broadcasting: {desc}") from None


def split_outer_inner(shape, optical_shape, d):
    """Split a broadcast *shape* into 'optical' (outer) and 'thickness-only' (inner) axes.

    The film setup depends on wavelength, angle and indices but not on thickness; the axes
    along which only the thickness varies need no setup of their own.  Returns
    ``(perm, n_outer, n_inner, d2)`` where ``perm`` orders the axes outer-first, and ``d2`` is
    the thickness as a (1, n_inner) array when it varies along inner axes only (no copy of the
    full grid), else (n_outer, n_inner).
    """
    ndim = len(shape)
    opt = (1,) * (ndim - len(optical_shape)) + tuple(optical_shape)
    inner = [ax for ax in range(ndim) if opt[ax] == 1 and shape[ax] > 1]
    outer = [ax for ax in range(ndim) if ax not in inner]
    perm = outer + inner
    n_outer = int(np.prod([shape[ax] for ax in outer], dtype=np.int64))
    n_inner = int(np.prod([shape[ax] for ax in inner], dtype=np.int64))
    d_pad = d.reshape((1,) * (ndim - d.ndim) + d.shape)
    if all(d_pad.shape[ax] == 1 for ax in outer):
        inner_shape = tuple(shape[ax] if ax in inner else 1 for ax in range(ndim))
        d2 = np.broadcast_to(d_pad, inner_shape).reshape(1, n_inner)
    else:
        d2 = np.ascontiguousarray(np.broadcast_to(d_pad, shape).transpose(perm)).reshape(n_outer, n_inner)
    return perm, n_outer, n_inner, np.ascontiguousarray(d2, dtype=np.float64)


def unsplit(out2, shape, perm):
    """Inverse of :func:`split_outer_inner` for an (n_outer, n_inner) result."""
    permuted = out2.reshape([shape[ax] for ax in perm])
    if perm != sorted(perm):
        permuted = permuted.transpose(np.argsort(perm))
    return permuted[()] if permuted.ndim == 0 else permuted


def flat_optical(shape_pad, *arrays):
    """Broadcast each array to *shape_pad* and flatten (C order) into contiguous 1-D arrays."""
    return tuple(np.ascontiguousarray(np.broadcast_to(a, shape_pad).reshape(-1)) for a in arrays)

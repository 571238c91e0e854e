"""Broadcasting and shapes of the public API, in the style of colour-science's n-dimensional tests.

Every public function is a "ufunc" over its array arguments: an optical quantity at one
(wavelength, thickness, angle, media) point does not depend on the other points it is computed
with.  So for any shapes that broadcast, the result must equal, element by element, the result
of calling the function on the scalars; scalars must give 0-d results; empty inputs give empty
outputs.  The film code moves the thickness-only axes to the end before evaluating (the
"axes-permutation fast path" in ``bubbleoptics._args.split_outer_inner``), so the tests put
the thickness along every axis, alone and jointly with other arguments.

The scalar loop is the slow, literal reference of these comparisons (marker ``reference``).
Equality is to 1e-15 absolute, i.e. the same kernel evaluated on the same numbers.
"""


import numpy as np
import pytest

import bubbleoptics as bo

POLS = ["s", "p", "unpolarized"]
TOL = dict(rtol=0, atol=1e-15)


def _elem(a, idx):
    """Element of *a* (broadcast against a grid) at grid index *idx*."""
    a = np.asarray(a)
    if a.ndim == 0:
        return a[()]
    sub = idx[len(idx) - a.ndim:]
    return a[tuple(i if s > 1 else 0 for i, s in zip(sub, a.shape))]


def _loop(func, args, **kwargs):
    """Elementwise reference: *func* on the scalar elements of the broadcast *args*."""
    shape = np.broadcast_shapes(*(np.shape(a) for a in args))
    outs = None
    for idx in np.ndindex(*shape):
        r = func(*(_elem(a, idx) for a in args), **kwargs)
        r = r if isinstance(r, tuple) else (r,)
        if outs is None:
            outs = [np.empty(shape, dtype=np.asarray(x).dtype) for x in r]
        for o, x in zip(outs, r):
            o[idx] = x
    return outs


# A fixed set of inputs exercising every branch: lossless, absorbing, TIR at the back,
# evanescent film, grazing, zero thickness.
WL6 = np.array([380.0, 450.0, 532.0, 633.0, 700.0, 1064.0])
D6 = np.array([0.0, 12.5, 250.0, 777.7, 3000.0, 1e5])
TH6 = np.array([0.0, 0.3, -0.7, 1.2, 1.5, np.pi / 2])
N1_6 = np.array([1.33, 1.5 + 0.01j, 2.4, 1.0, 1.7 + 0.5j, 1.2])
N0_6 = np.array([1.0, 1.0, 1.33, 1.5, 1.0, 1.2])
N2_6 = np.array([1.0, 1.52, 1.0, 1.0, 2.0 + 0.3j, 1.8])


# ---------------------------------------------------------------------------------------------
# Scalars
# ---------------------------------------------------------------------------------------------
@pytest.mark.reference
@pytest.mark.parametrize("pol", POLS)
def test_scalars_give_numpy_scalars(pol):
    """Scalar inputs give NumPy scalars (0-d), for every public function.

    (Optics is pointwise: one wavelength, thickness and angle give one R and one T.)
    """
    outs = [
        bo.film_reflectance(550.0, 300.0, 0.3, 1.33, polarization=pol),
        bo.film_transmittance(550.0, 300.0, 0.3, 1.33, polarization=pol),
        *bo.film_rt(550.0, 300.0, 0.3, 1.33, polarization=pol),
        bo.two_beam_reflectance(550.0, 300.0, 0.3, 1.33, polarization=pol),
        bo.multilayer_reflectance(550.0, [1.45, 1.33], [2.0, 300.0], 0.3, polarization=pol),
        bo.multilayer_transmittance(550.0, [1.45, 1.33], [2.0, 300.0], 0.3, polarization=pol),
        *bo.multilayer_rt(550.0, [1.45, 1.33], [2.0, 300.0], 0.3, polarization=pol),
        bo.water_refractive_index(550.0),
        bo.film_reflectance(550.0, 300.0, 0.3),  # default water film
        *bo.fresnel_coefficients(1.0, 1.5, 0.3),
    ]
    for x in outs:
        assert np.ndim(x) == 0
        assert isinstance(x, (np.generic, np.ndarray)), type(x)
        assert np.isfinite(x)
    assert isinstance(outs[0], np.floating)
    f = bo.fresnel_coefficients(1.0, 1.5, 0.3)
    assert np.iscomplexobj(f.rs) and np.iscomplexobj(f.tp)
    assert np.isrealobj(f.Rs) and np.isrealobj(f.Tp)
    # 0-d arrays in give 0-d results too
    assert np.ndim(bo.film_reflectance(np.array(550.0), np.array(300.0), np.array(0.3), np.array(1.33))) == 0


# ---------------------------------------------------------------------------------------------
# n-dimensional: tile and reshape, colour-science style
# ---------------------------------------------------------------------------------------------
SHAPES = [(6,), (2, 3), (3, 2, 1), (1, 2, 3, 1)]


@pytest.mark.reference
@pytest.mark.parametrize("pol", POLS)
@pytest.mark.parametrize("shape", SHAPES, ids=str)
def test_film_nd_arrays_equal_scalar_results(pol, shape):
    """The film functions on n-dimensional inputs equal the scalar results element by element.

    Every argument is an array of the same shape (reshaped from 6 distinct cases covering
    lossless, absorbing, total internal reflection, tunnelling and grazing incidence), so no
    element may depend on another (Born & Wolf §7.6.1: the Airy sum is pointwise).
    """
    args = [a.reshape(shape) for a in (WL6, D6, TH6, N1_6, N0_6, N2_6)]
    R, T = bo.film_rt(*args, polarization=pol)
    R_ref, T_ref = _loop(lambda *a: bo.film_rt(*a, polarization=pol), args)
    assert R.shape == T.shape == shape
    np.testing.assert_allclose(R, R_ref, **TOL)
    np.testing.assert_allclose(T, T_ref, **TOL)
    np.testing.assert_allclose(bo.film_reflectance(*args, polarization=pol), R_ref, **TOL)
    np.testing.assert_allclose(bo.film_transmittance(*args, polarization=pol), T_ref, **TOL)
    # tiled: the same six cases repeated give the same numbers in every tile
    tiled = [np.tile(a.reshape(-1), 4).reshape((4,) + shape) for a in (WL6, D6, TH6, N1_6, N0_6, N2_6)]
    Rt = bo.film_reflectance(*tiled, polarization=pol)
    assert Rt.shape == (4,) + shape
    for k in range(4):
        np.testing.assert_allclose(Rt[k], R_ref, **TOL)


@pytest.mark.reference
@pytest.mark.parametrize("pol", POLS)
@pytest.mark.parametrize("shape", SHAPES, ids=str)
def test_other_functions_nd_arrays_equal_scalar_results(pol, shape):
    """two_beam_reflectance, fresnel_coefficients, multilayer_rt and water_refractive_index are
    pointwise too: n-dimensional inputs equal the scalar loop (Born & Wolf §1.5.2, §1.6.2)."""
    wl, d, th, n1, n0, n2 = (a.reshape(shape) for a in (WL6, D6, TH6, N1_6, N0_6, N2_6))
    # two-beam model
    (ref,) = _loop(lambda *a: bo.two_beam_reflectance(*a, polarization=pol), [wl, d, th, n1, n0])
    np.testing.assert_allclose(bo.two_beam_reflectance(wl, d, th, n1, n0, pol), ref, **TOL)
    # Fresnel coefficients (all eight fields)
    f = bo.fresnel_coefficients(n0, n2, th)
    refs = _loop(lambda *a: tuple(bo.fresnel_coefficients(*a)), [n0, n2, th])
    for got, want in zip(f, refs):
        assert got.shape == shape
        np.testing.assert_allclose(got, want, **TOL)
    # multilayer: per-layer indices and thicknesses as arrays
    layers_n = [n1, 1.45 + 0.0 * n1, n1]
    layers_d = [d, 2.0, d / 3]
    R, T = bo.multilayer_rt(wl, layers_n, layers_d, th, n0, n2, pol)
    R_ref, T_ref = _loop(
        lambda w, a, b, t, o, i: bo.multilayer_rt(w, [a, 1.45, a], [b, 2.0, b / 3], t, o, i, pol),
        [wl, n1, d, th, n0, n2],
    )
    assert R.shape == shape
    np.testing.assert_allclose(R, R_ref, **TOL)
    np.testing.assert_allclose(T, T_ref, **TOL)
    # water
    (n_ref,) = _loop(bo.water_refractive_index, [wl])
    np.testing.assert_allclose(bo.water_refractive_index(wl), n_ref, rtol=0, atol=0)


# ---------------------------------------------------------------------------------------------
# The thickness fast path: thickness along any axes, alone or jointly with others
# ---------------------------------------------------------------------------------------------
WL = np.array([400.0, 500.0, 600.0, 700.0])
TH = np.array([0.0, 0.5, 1.2])
D = np.array([0.0, 5.0, 150.0, 420.0, 1e4])


@pytest.mark.reference
@pytest.mark.parametrize("pol", POLS)
@pytest.mark.parametrize("n_film, n_inside", [(1.33, None), (1.5 + 0.02j, 1.2), (None, None)])
def test_thickness_axis_permutations(pol, n_film, n_inside):
    """Thickness along the last, middle or first axis, or varying jointly with wavelength,
    gives the scalar results (the physics is pointwise, Born & Wolf §7.6.1)."""
    cases = {
        "wl0 th1 d2": (WL[:, None, None], D[None, None, :], TH[None, :, None]),
        "d0 th1 wl2": (WL[None, None, :], D[:, None, None], TH[None, :, None]),
        "th0 d1 wl2": (WL[None, None, :], D[None, :, None], TH[:, None, None]),
        "d along 0 only": (WL[None, :], D[:, None], 0.4),
        "d 2-D with wl": (WL[:, None], np.outer(WL, [0.1, 0.5, 1.0]) / 1.33, TH[None, :]),
        "d full 3-D": (WL[:, None, None], np.random.default_rng(7).uniform(0, 2000, (4, 3, 5)), TH[None, :, None]),
        "d with singleton axes": (WL[:, None, None, None], D[None, :, None, None], TH[None, None, None, :]),
        "only d varies": (550.0, D, 0.3),
        "d (1, n)": (WL[:, None], D[None, :], 0.3),
    }
    for name, (wl, d, th) in cases.items():
        kw = dict(n_film=n_film, n_outside=1.0, n_inside=n_inside, polarization=pol)
        R, T = bo.film_rt(wl, d, th, **kw)
        R_ref, T_ref = _loop(lambda w, dd, t: bo.film_rt(w, dd, t, **kw), [wl, d, th])
        assert R.shape == np.broadcast_shapes(np.shape(wl), np.shape(d), np.shape(th)), name
        np.testing.assert_allclose(R, R_ref, **TOL, err_msg=name)
        np.testing.assert_allclose(T, T_ref, **TOL, err_msg=name)


@pytest.mark.reference
@pytest.mark.parametrize("pol", ["s", "unpolarized"])
def test_random_axis_placements(pol):
    """Each of the six film arguments placed along a random subset of three axes (or scalar):
    the result equals the scalar loop.  60 random layouts (fixed seed) cover the combinations
    of "optical" axes (wavelength, angle, media) and "thickness-only" axes that the fast path
    separates."""
    rng = np.random.default_rng(2024)
    grid = (2, 3, 4)
    pools = {
        "wavelength_nm": lambda s: rng.uniform(300, 900, s),
        "thickness_nm": lambda s: np.where(rng.random(s) < 0.2, 0.0, rng.uniform(0, 3000, s)),
        "theta": lambda s: rng.uniform(-1.5, 1.5, s),
        "n_film": lambda s: rng.uniform(1.0, 2.5, s) + 1j * np.where(rng.random(s) < 0.5, 0, rng.uniform(0, 0.3, s)),
        "n_outside": lambda s: rng.uniform(1.0, 1.6, s),
        "n_inside": lambda s: rng.uniform(1.0, 2.5, s) + 0j,
    }
    for _ in range(60):
        args = {}
        for name, make in pools.items():
            axes = [ax for ax in range(3) if rng.random() < 0.4]
            shape = tuple(grid[ax] if ax in axes else 1 for ax in range(3))
            leading_ones = next((i for i, n in enumerate(shape) if n > 1), 3)
            shape = shape[rng.integers(0, leading_ones + 1):]  # drop some leading singleton axes
            args[name] = make(shape)[()] if shape == () else make(shape)
        R, T = bo.film_rt(**args, polarization=pol)
        R_ref, T_ref = _loop(lambda *a: bo.film_rt(*a, polarization=pol), list(args.values()))
        layout = {k: np.shape(v) for k, v in args.items()}
        np.testing.assert_allclose(R, R_ref, **TOL, err_msg=str(layout))
        np.testing.assert_allclose(T, T_ref, **TOL, err_msg=str(layout))


@pytest.mark.reference
@pytest.mark.parametrize("pol", POLS)
def test_film_index_per_wavelength(pol):
    """The film index may be given per wavelength (dispersion), broadcasting with thickness
    and angle; equals the scalar results, and equals the default water film when given the
    water index (Daimon & Masumura 2007)."""
    wl = np.linspace(380.0, 780.0, 9)
    n_w = bo.water_refractive_index(wl)
    n_abs = n_w + 1j * np.linspace(0, 0.05, wl.size)
    d = np.array([0.0, 100.0, 550.0, 1200.0])[:, None]
    th = np.array([0.0, 0.8])[:, None, None]
    for n in (n_w, n_abs):
        R = bo.film_reflectance(wl, d, th, n, polarization=pol)
        assert R.shape == (2, 4, 9)
        (ref,) = _loop(lambda w, dd, t, nn: bo.film_reflectance(w, dd, t, nn, polarization=pol), [wl, d, th, n])
        np.testing.assert_allclose(R, ref, **TOL)
    np.testing.assert_array_equal(bo.film_reflectance(wl, d, th, polarization=pol),
                                  bo.film_reflectance(wl, d, th, n_w, polarization=pol))
    # per-wavelength layer indices in a multilayer
    R = bo.multilayer_reflectance(wl, [1.45, n_abs, 1.45], [2.0, d, 2.0], th, polarization=pol)
    assert R.shape == (2, 4, 9)
    (ref,) = _loop(lambda w, dd, t, nn: bo.multilayer_reflectance(w, [1.45, nn, 1.45], [2.0, dd, 2.0], t,
                                                                  polarization=pol), [wl, d, th, n_abs])
    np.testing.assert_allclose(R, ref, **TOL)


@pytest.mark.reference
def test_non_contiguous_and_integer_inputs():
    """Views with negative strides, Fortran order and integer dtypes give the same numbers."""
    wl = np.linspace(400.0, 700.0, 7)
    d = np.asfortranarray(np.linspace(0, 900, 12).reshape(3, 4))
    R = bo.film_reflectance(wl[::-1][:, None, None], d[None, :, :], 0.4, 1.33)
    R_ref = bo.film_reflectance(np.ascontiguousarray(wl[::-1])[:, None, None], np.ascontiguousarray(d)[None], 0.4, 1.33)
    np.testing.assert_array_equal(R, R_ref)
    np.testing.assert_allclose(bo.film_reflectance(np.array([500, 600]), np.array([100, 0]), 0, 1.33),
                               bo.film_reflectance([500.0, 600.0], [100.0, 0.0], 0.0, 1.33), **TOL)


# ---------------------------------------------------------------------------------------------
# Empty arrays
# ---------------------------------------------------------------------------------------------
@pytest.mark.reference
@pytest.mark.parametrize("shape", [(0,), (0, 3), (3, 0), (2, 0, 4)], ids=str)
def test_empty_inputs_give_empty_outputs(shape):
    """No wavelengths (or no thicknesses) in, nothing out: every function returns an empty
    array of the broadcast shape."""
    e = np.empty(shape)
    wl = np.full(shape, 550.0)
    assert bo.film_reflectance(wl, 100.0, 0.3, 1.33).shape == shape
    assert bo.film_transmittance(550.0, e, 0.3, 1.33).shape == shape
    R, T = bo.film_rt(550.0, 100.0, e, 1.33)
    assert R.shape == T.shape == shape
    assert bo.film_reflectance(np.full(shape, 550.0), 100.0, 0.3).shape == shape  # water default
    assert bo.film_reflectance(550.0, 100.0, 0.3, np.empty(shape, complex)).shape == shape
    assert bo.two_beam_reflectance(wl, 100.0, 0.3, 1.33).shape == shape
    assert all(x.shape == shape for x in bo.fresnel_coefficients(1.0, 1.5, e))
    R, T = bo.multilayer_rt(wl, [1.45, 1.33], [2.0, 100.0], 0.3)
    assert R.shape == T.shape == shape
    assert bo.water_refractive_index(wl).shape == shape
    # an empty axis broadcast against a full one
    assert bo.film_reflectance(WL[:, None], np.empty((1, 0)), 0.3, 1.33).shape == (4, 0)
    assert bo.film_reflectance(np.empty((0, 1)), D[None, :], 0.3, 1.33).shape == (0, 5)

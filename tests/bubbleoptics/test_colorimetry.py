"""Colour: spectrum_to_XYZ, film_color, the shipped colour tables and the sRGB curve against colour-science."""

import warnings

import colour
import numpy as np
import pytest

import bubbleoptics as bo

OBSERVER = "CIE 1931 2 Degree Standard Observer"
CMFS = colour.MSDS_CMFS[OBSERVER]


def colour_XYZ(values, wl, illuminant="D65"):
    """colour-science's own result, one SpectralDistribution at a time (divided by 100)."""
    sd = colour.SpectralDistribution(values, wl)
    ill = None if illuminant is None else colour.SDS_ILLUMINANTS[illuminant]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return np.asarray(colour.sd_to_XYZ(sd, CMFS, ill, method="Integration")) / 100


@pytest.mark.reference
@pytest.mark.parametrize(
    "wl",
    [
        np.arange(360.0, 781.0, 1.0),  # the CMF grid itself
        np.arange(380.0, 781.0, 5.0),  # uniform, interpolated (Sprague) and extrapolated
        np.arange(400.0, 701.0, 20.0),  # coarse
        np.array([380.0, 400, 430, 470, 520, 580, 650, 700, 780]),  # non-uniform (cubic spline)
    ],
    ids=["1nm", "5nm", "20nm", "nonuniform"],
)
@pytest.mark.parametrize("illuminant", ["D65", "A", None])
def test_spectrum_to_XYZ_matches_colour_science(wl, illuminant):
    """spectrum_to_XYZ == colour.sd_to_XYZ(..., method="Integration") / 100 to 1e-10.

    Random spectra (not the basis our weights were built from), so this checks that the
    precomputed matrix reproduces colour-science's whole pipeline, interpolation included.
    """
    rng = np.random.default_rng(7)
    spectra = rng.uniform(0, 1, (12, wl.size))
    ours = bo.spectrum_to_XYZ(spectra, wl, illuminant=illuminant)
    for k in range(spectra.shape[0]):
        np.testing.assert_allclose(ours[k], colour_XYZ(spectra[k], wl, illuminant), rtol=0, atol=1e-10)


@pytest.mark.analytic
def test_perfect_reflector_has_unit_luminance():
    """Y = 1 for a perfect reflector under any illuminant (the normalisation k of CIE 15)."""
    wl = np.arange(380.0, 781.0, 5.0)
    for ill in ("D65", "A", "D50", None):
        assert bo.spectrum_to_XYZ(np.ones(wl.size), wl, ill)[1] == pytest.approx(1.0, abs=1e-12)


@pytest.mark.reference
def test_spectrum_to_XYZ_broadcasts_over_leading_axes():
    """(..., N) -> (..., 3): a stack of spectra equals converting them one by one."""
    wl = np.arange(380.0, 781.0, 10.0)
    spectra = np.random.default_rng(1).uniform(0, 1, (2, 3, wl.size))
    ours = bo.spectrum_to_XYZ(spectra, wl)
    assert ours.shape == (2, 3, 3)
    np.testing.assert_allclose(ours[1, 2], colour_XYZ(spectra[1, 2], wl), atol=1e-10)


def colour_pipeline_film_rgb(thickness, theta, illuminant="D65"):
    """The colour-science pipeline: film spectrum at 1 nm -> sd_to_XYZ -> XYZ_to_sRGB, clipped."""
    wl = np.arange(360.0, 781.0, 1.0)
    R = bo.film_reflectance(wl, thickness, theta)
    XYZ = colour_XYZ(R, wl, illuminant)
    wp = colour.CCS_ILLUMINANTS[OBSERVER][illuminant]
    rgb = colour.XYZ_to_sRGB(XYZ, illuminant=wp, apply_cctf_encoding=False)
    return colour.cctf_encoding(np.clip(rgb, 0, 1), function="sRGB")


@pytest.mark.reference
@pytest.mark.parametrize("theta", [0.0, np.pi / 3])
@pytest.mark.parametrize("illuminant", ["D65", "A"])
def test_film_color_matches_colour_pipeline(theta, illuminant):
    """film_color within 0.005 per channel of the colour-science pipeline, 0-2 µm."""
    d = np.linspace(0, 2000, 41)
    ours = bo.film_color(d, theta, illuminant=illuminant)
    ref = np.array([colour_pipeline_film_rgb(x, theta, illuminant) for x in d])
    assert np.max(np.abs(ours - ref)) <= 0.005


@pytest.mark.reference
def test_film_color_with_coarse_wavelengths_close_to_1nm():
    """A 5 nm grid (interpolated by colour-science's Sprague method) stays within 0.005 below 1 µm."""
    d = np.linspace(0, 1000, 21)
    fine = bo.film_color(d)
    coarse = bo.film_color(d, wavelengths_nm=np.arange(380.0, 781.0, 5.0))
    assert np.max(np.abs(fine - coarse)) <= 0.005


@pytest.mark.analytic
def test_film_color_limits():
    """d = 0 is black (R = 0); a perfect-reflector-like film at grazing incidence is white.

    At theta -> pi/2, R -> 1 at every wavelength (Fresnel), so the colour tends to sRGB white.
    """
    assert np.all(bo.film_color(0.0) == 0.0)
    white = bo.film_color(500.0, theta=np.pi / 2 - 1e-9)
    np.testing.assert_allclose(white, 1.0, atol=1e-4)


@pytest.mark.analytic
def test_film_color_is_in_unit_range_and_gamut_option():
    """Clipped output lies in [0, 1]; gamut='none' may leave it but agrees where in gamut."""
    d = np.linspace(0, 3000, 301)
    clipped = bo.film_color(d)
    raw = bo.film_color(d, gamut="none")
    assert clipped.min() >= 0.0 and clipped.max() <= 1.0
    inside = np.all((raw >= 0) & (raw <= 1), axis=-1)
    assert inside.any()
    np.testing.assert_allclose(clipped[inside], raw[inside], atol=1e-12)


@pytest.mark.analytic
def test_film_color_transmittance_complements_reflectance():
    """Lossless film: T = 1 - R per wavelength, so XYZ_T = XYZ_white - XYZ_R (linearity)."""
    wl = np.arange(360.0, 781.0, 1.0)
    R = bo.film_reflectance(wl, 420.0, 0.4)
    T = bo.film_transmittance(wl, 420.0, 0.4)
    white = bo.spectrum_to_XYZ(np.ones(wl.size), wl)
    np.testing.assert_allclose(bo.spectrum_to_XYZ(T, wl), white - bo.spectrum_to_XYZ(R, wl), atol=1e-13)


@pytest.mark.reference
def test_water_dispersion_matters_at_oblique_incidence():
    """colour-science 0.4.7's thin_film_tmm takes refraction angles from the first wavelength.

    We agree with tmm per wavelength (tests/bubbleoptics/test_reference_tmm.py); here we record that the
    discrepancy against it (up to ~0.009 in R) is real and caused by dispersion, so that
    a future colour-science fix shows up as this test failing loudly rather than silently.
    """
    from colour.phenomena import thin_film_tmm

    wl = np.linspace(380.0, 780.0, 81)
    n = bo.water_refractive_index(wl)
    d = np.linspace(0, 2000, 41)
    theta = np.deg2rad([0.0, 60.0, 80.0])
    ours = bo.film_reflectance(wl[:, None, None], d, theta[None, :, None], n[:, None, None])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        theirs = thin_film_tmm(np.array([np.ones_like(wl), n, np.ones_like(wl)]), d, wl, np.rad2deg(theta))[0]
    theirs = theirs.mean(axis=-1)
    assert np.max(np.abs(ours[:, 0] - theirs[:, 0])) < 1e-12  # normal incidence: no angle, agree
    assert np.max(np.abs(ours[0] - theirs[0])) < 1e-12  # first wavelength: its own angle, agree
    assert np.max(np.abs(ours - theirs)) > 1e-3  # oblique, other wavelengths: they differ


# ------------------------------------------------------------------------------------------
# What a render uses without importing colour-science: the shipped tables and the sRGB curve
# ------------------------------------------------------------------------------------------
@pytest.mark.reference
def test_shipped_colour_tables_are_what_colour_science_computes():
    """colour_tables.npz == a fresh computation by colour-science (python -m bubbleoptics.colour_tables).

    1e-12 absolute on the weights and the basis (values of order 0.01-1) allows for a
    different summation order on another machine; the wavelengths are exact.
    """
    from bubbleoptics.colorimetry import colour_tables
    from bubbleoptics.colour_tables import compute_colour_tables

    shipped, fresh = colour_tables(), compute_colour_tables()
    assert set(shipped) - {"colour_science_version"} == set(fresh)
    np.testing.assert_array_equal(shipped["wavelengths_nm"], fresh["wavelengths_nm"])
    np.testing.assert_array_equal(shipped["srgb_dominant_wavelengths_nm"], fresh["srgb_dominant_wavelengths_nm"])
    for key in ("xyz_weights_d65", "rgb_basis_mallett2019"):
        assert shipped[key].shape == fresh[key].shape, key
        np.testing.assert_allclose(shipped[key], fresh[key], rtol=0, atol=1e-12, err_msg=key)


@pytest.mark.reference
def test_srgb_constants_match_colour_science():
    """The XYZ -> linear sRGB matrix (IEC 61966-2-1) and the primaries' dominant wavelengths."""
    from bubbleoptics.colorimetry import XYZ_TO_LINEAR_SRGB, srgb_dominant_wavelengths

    srgb = colour.RGB_COLOURSPACES["sRGB"]
    np.testing.assert_array_equal(XYZ_TO_LINEAR_SRGB, srgb.matrix_XYZ_to_RGB)
    expected = [float(colour.dominant_wavelength(p, srgb.whitepoint)[0]) for p in srgb.primaries]
    assert srgb_dominant_wavelengths().tolist() == expected == [611.0, 549.0, 464.0]


@pytest.mark.reference
@pytest.mark.parametrize("n_bands", [3, 16, 421])
def test_band_weights_from_the_tables_equal_the_colour_science_path(n_bands):
    """band_spectral_weights as computed before the tables: colour-science's Integration matrix
    on the 1 nm grid (the uncached path, ``_weights``), summed over bands."""
    from bubbleoptics.colorimetry import DEFAULT_WAVELENGTHS_NM, _weights

    wl, W = bo.band_spectral_weights(n_bands)
    w_fine = _weights(DEFAULT_WAVELENGTHS_NM, "D65", OBSERVER)
    assert W[1].sum() == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_allclose(W.sum(axis=1), w_fine.sum(axis=1), rtol=0, atol=1e-12)  # bands partition
    if n_bands == 421:  # one band per 1 nm sample: the 1 nm weights themselves
        np.testing.assert_allclose(W, w_fine, rtol=0, atol=1e-12)


@pytest.mark.reference
@pytest.mark.parametrize("n_bands,lo,hi", [(3, 360.0, 780.0), (16, 360.0, 780.0), (421, 360.0, 780.0),
                                           (16, 400.0, 700.0)])
def test_rgb_basis_from_the_tables_equals_colour_science_align(n_bands, lo, hi):
    """rgb_reflectance_basis as computed before the tables: colour-science's ``align`` of the
    Mallett-Yuksel basis onto [lo, hi] at 1 nm, averaged over each band (the tables hold
    360-780 nm and cut narrower ranges from it)."""
    mallett = colour.recovery.MSDS_BASIS_FUNCTIONS_sRGB_MALLETT2019
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fine = mallett.copy().align(colour.SpectralShape(lo, hi, 1.0))
    edges = np.linspace(lo, hi, n_bands + 1)
    expected = np.array([fine.values[(fine.wavelengths >= a) & (fine.wavelengths <= b)].mean(axis=0)
                         for a, b in zip(edges[:-1], edges[1:])])
    np.testing.assert_allclose(bo.rgb_reflectance_basis(n_bands, lo, hi), expected, rtol=0, atol=1e-14)


@pytest.mark.reference
def test_srgb_transfer_functions_equal_colour_science_and_the_literal_formula():
    """linear_srgb_to_srgb / srgb_to_linear_srgb against colour.cctf_encoding / cctf_decoding
    ("sRGB") to a relative 1e-15, and to the bit against the standard's formula evaluated one value at a
    time with Python's ``math.pow`` (the C library's pow, which the numba kernels call too).
    colour-science goes through NumPy's ``power``, whose vectorised float64 loop (NumPy 2.4)
    can differ from the C library's by an ulp (a few ulp of the encoded value near the break
    point, where 1.055 x^(1/2.4) - 0.055 loses a bit or two).

    Over [-0.5, 1.5] (values outside [0, 1] included), every 16-bit code, and around both
    break points.
    """
    import math

    from bubbleoptics.colorimetry import linear_srgb_to_srgb, srgb_to_linear_srgb

    x = np.concatenate([np.linspace(-0.5, 1.5, 100001), np.arange(65536) / 65535,
                        0.0031308 + np.arange(-50, 51) * 2e-18, 0.0031308 * 12.92 + np.arange(-50, 51) * 7e-18])
    np.testing.assert_allclose(linear_srgb_to_srgb(x), colour.cctf_encoding(x, function="sRGB"), rtol=1e-15, atol=0)
    np.testing.assert_allclose(srgb_to_linear_srgb(x), colour.cctf_decoding(x, function="sRGB"), rtol=1e-15, atol=0)

    def encode(v):
        return 12.92 * v if v <= 0.0031308 else 1.055 * math.pow(v, 1 / 2.4) - 0.055

    def decode(v):
        return v / 12.92 if v <= 0.0031308 * 12.92 else math.pow((v + 0.055) / 1.055, 2.4)

    np.testing.assert_array_equal(linear_srgb_to_srgb(x), [encode(v) for v in x.tolist()])
    np.testing.assert_array_equal(srgb_to_linear_srgb(x), [decode(v) for v in x.tolist()])


@pytest.mark.api
def test_srgb_transfer_functions_give_the_same_bits_for_a_few_values_as_for_many():
    """A few values (a scene's colours) go through the scalar kernels uncompiled, many through the
    compiled array kernels (bubbleoptics.colorimetry._elementwise): the same values give the same
    bits either way, across both break points, outside [0, 1], at the bound of the uncompiled path
    and beyond it (where CPython's ``**`` would overflow), and with NaN and infinities."""
    from bubbleoptics import colorimetry as cm

    rng = np.random.default_rng(11)
    values = np.concatenate([rng.uniform(-0.5, 1.5, 40), [0.0, 1.0, 0.0031308, 0.0031308 * 12.92, -0.0,
                                                         cm._PY_PATH_BOUND, -cm._PY_PATH_BOUND, 5e-324]])
    assert values.size <= cm._PY_PATH_MAX_SIZE
    filler = np.full(cm._PY_PATH_MAX_SIZE + 1, 0.25)  # makes the call take the compiled kernel
    for f in (cm.linear_srgb_to_srgb, cm.srgb_to_linear_srgb):
        few = f(values)
        many = f(np.concatenate([values, filler]))[: values.size]
        np.testing.assert_array_equal(few, many)
        assert few.dtype == np.float64 and few.shape == values.shape
        # beyond the bound, and NaN or inf: the compiled kernel, no OverflowError
        wild = f(np.array([1e300, -1e300, np.inf, -np.inf, np.nan, 0.5]))
        assert np.isnan(wild[4]) and np.isfinite(wild[5]) and wild[2] == np.inf
    assert np.isinf(cm.srgb_to_linear_srgb(1e300))


@pytest.mark.analytic
def test_srgb_transfer_functions_shapes_limits_and_nan():
    """Scalars give scalars, arrays keep their shape, 0 and 1 are fixed points, the two invert
    each other, the curve is continuous at its break point, and NaN stays NaN."""
    from bubbleoptics.colorimetry import linear_srgb_to_srgb, srgb_to_linear_srgb

    assert np.ndim(linear_srgb_to_srgb(0.5)) == 0 and np.ndim(srgb_to_linear_srgb(0.5)) == 0
    x = np.random.default_rng(3).uniform(0, 1, (4, 5, 3))
    assert linear_srgb_to_srgb(x).shape == (4, 5, 3)
    np.testing.assert_allclose(srgb_to_linear_srgb(linear_srgb_to_srgb(x)), x, rtol=1e-14, atol=1e-16)
    assert linear_srgb_to_srgb([0.0, 1.0]).tolist() == pytest.approx([0.0, 1.0], abs=1e-15)
    below, above = linear_srgb_to_srgb(np.nextafter(0.0031308, [0.0, 1.0]))
    assert above - below == pytest.approx(0.0, abs=1e-7)  # continuous (the standard's rounding: 5e-8)
    assert np.isnan(linear_srgb_to_srgb(np.nan)) and np.isnan(srgb_to_linear_srgb([np.nan])).all()

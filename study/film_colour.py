"""Published ways to a thin film's colour from few values, rebuilt to compare with ours.

The anchors of ``benchmarks/bandlimited_colour.py`` (whose docstring says which rows compare what)
and of ``paper/scripts/fig_bandlimited.py``: a free-standing lossless film of one constant index,
its reflectance written as its exact Fourier series in optical path difference (OPD),
:func:`fourier_film_XYZ`, with each term's XYZ from a *sensitivity* S(OPD) of one of three kinds.

**The Gaussian fit** (:func:`bb_film_XYZ`), illuminant E and a non-dispersive film: the Gaussian
fit of the CMFs in Fourier space by L. Belcour and P. Barla, "A Practical Extension to Microfacet
Theory for the Modeling of Varying Iridescence", ACM TOG 36(4), 65 (SIGGRAPH 2017), also used by
Blender 4.2's thin film: the film's exact Fourier series in optical path difference,
:math:`R = (1 - T_{inc}) - 2T_{inc}\\sum_m \\rho^m\\cos(2\\pi m\\,{\\rm OPD}/\\lambda)` (summed
to convergence, so only the CMF fit is tested), with each term's XYZ from their published
Gaussian-fit sensitivity (constants as in the paper's supplemental code).

**The exact lookup table** (:func:`lut_table`, :func:`lut_film_XYZ`): the same Fourier series, each
term's XYZ from a lookup table of the *exact* sensitivity :math:`S({\\rm OPD}) = \\int \\bar{\\mathbf{x}}(\\lambda) E(\\lambda)
\\cos(2\\pi\\,{\\rm OPD}/\\lambda)\\,d\\lambda`, i.e. ``spectral_weights(WL, illuminant=None) @
cos(2 pi OPD / WL)``: the very 1 nm weights of the reference (CIE 1931 2°, 360-780 nm, the CMFs
beyond 780 nm folded into 780 nm as colour-science's integration does), normalized alike (S(0)
is the perfect white under E, Y = 1).  Tabulated every ``LUT_STEP_NM`` = 1 nm of OPD from 0 to
``LUT_MAX_OPD_NM`` = 64.8 µm, linearly interpolated, S = 0 beyond.  Why there: the first term
needs OPD = 2 d n cos(theta_1) <= 53.2 µm for films up to 20 µm at up to 60°; 64.8 µm =
(360 nm)^2 / (2 x 1 nm) is where the 1 nm sum stops resolving cos(2 pi OPD / lambda) at 360 nm
(beyond, it aliases: |S| up to 0.25 at 100-300 µm, an artefact of the sampling, not of the
CMFs), and by then the resolved S has decayed to |S| < 3e-5 (S(0) ~ 1; |S| < 1e-3 from 20 µm on).
Terms m >= 2 whose m OPD lies beyond the table are dropped; they carry at most 2 T rho^m of the
white.  The film index is the constant n = 1.33: one table in OPD cannot hold a
wavelength-dependent index, so the table ignores dispersion by construction.

What this is: the approach attributed to Blender 5.0 ("its lookup table ignores dispersion"), rebuilt here with the exact integral; *not* Blender's table, which is coarser.

**The Blender-like table** (:func:`blender_like_table`).  A reconstruction from the parameters of
Blender's published source, not Blender run: the files were read in a stored code index (no code,
data or text copied here), and the parameters reimplemented:

* ``intern/cycles/doc/precompute/thin_film_table.py`` (blender/blender), the generator of the
  table: the CIE 1931 2° CMFs at 1 nm over 360-830 nm, a zero added at 359 and at 831 nm, cubic
  splines in wavelength (zero outside), sampled at N = 1022 wavenumbers nu_j = j pi/60 µm^-1
  (0-53.5 µm^-1) with the weight cmf(1/nu) / nu^2, and Fourier-transformed (real FFT): 512
  complex entries per channel, entry k at OPD = k / (N pi/60 µm^-1) = k x 18.69 nm, up to
  9.55 µm.  Only 31 of the samples fall in 359-831 nm (one every 8 nm of wavelength at 400 nm,
  16 nm at 555 nm, 26 nm at 700 nm), so the entries are a coarse Riemann sum of the integral.
  The script's comment says the table covers 0-60 µm; sampled in 1/µm as it is, it reaches
  9.55 µm (60 µm would hold for an angular wavenumber, 2 pi / lambda).
* ``intern/cycles/kernel/closure/bsdf_util.h`` (the thin-film sensitivity lookup and Airy
  summation) with ``intern/cycles/kernel/util/lookup_table.h`` (blender/blender): the table is read at
  x = 2 pi OPD / 60 µm, clamped to [0, 1], times 511, linearly interpolated: the same nodes, and
  the last entry held for every OPD beyond 9.55 µm; the series stops after m = 3; the film has one
  index (no dispersion), OPD = 2 n d cos(theta_film).
* ``intern/cycles/scene/shader.cpp`` (``compute_thin_film_table``): at start-up the XYZ entries are
  taken to the working RGB (BT.709 without an OpenColorIO role) and each RGB channel divided by its
  DC (OPD = 0) entry, so that a white film's RGB is (1, 1, 1).

Here the CMFs are colour-science's (the same CIE table), the spline scipy's ``CubicSpline``, the
entries the direct sum ``weights @ exp(-2 pi i OPD / lambda)`` at the nodes (:func:`lut_table`
with ``samples``), checked at every run against NumPy's real FFT of the samples.  RGB or XYZ: the
conversion, the linear interpolation of real and imaginary parts and the series are all linear,
so evaluating in RGB and reading the result back in XYZ equals evaluating in XYZ with a table
multiplied by one fixed matrix; the RGB step is done literally anyway (BT.709 matrix of
colour-science; back to XYZ by the matrix that takes RGB (1, 1, 1) to the reference's white under
E, since a white film is (1, 1, 1) in Blender).  Its only effect is the per-channel normalization,
a white correction of < 0.4 % (the spline-sampled CMFs' white differs from the reference's by
about 1e-3 in XYZ).  Complex entries: the kernel weights each entry by the reflection phasor
exp(i m phi) (real times real plus imaginary times imaginary); for this free-standing dielectric
film the phasor is +1 in both polarizations, below and above Brewster's angle, so only the real
part enters and the imaginary part, kept in the table, does not change the colour.

Versions: two revisions of that kernel and start-up code were found.  One stores and interpolates
each RGB channel's magnitude and unwrapped phase (entry = magnitude x cos(phase - m phi)); a later
one, which also handles conductor substrates, stores and interpolates real and imaginary parts.
The default follows the later; ``polar=True`` (:func:`lut_sensitivity`) the earlier.  Which
release ships which was not checked: it is attributed to Blender 5.0, a third-party port of
the later revision says it follows Blender 5.2 (Cycles 5.2.1); and the index did not name the
repository of the ``shader.cpp`` and ``bsdf_util.h`` revisions that hold the thin film (found by
their text; blender/blender's own stored copies under those paths predate it).  Not modelled (not
parameters of the table): float32 storage; the kernel's clamp of the final RGB to [0, 1]; its
blend of the film index towards the ambient one for very thin films (below 1 nm in the later
revision: only d = 0 here, black either way; below 30 nm in the earlier).  The table's own error
is largest on thin films (a few nm to a few hundred nm), where the linear interpolation over
18.7 nm of OPD misses the curvature of S; the coarse CMF sampling and the held last value add a
small error at every thickness (every film with OPD above 9.55 µm, d > 3.6 µm at normal
incidence, gets the same held terms).

**The check** (:func:`check_lut`): at thicknesses whose OPD falls on table nodes (where
the interpolation is exact), the table's series equals the direct 1 nm integration of
``film_reflectance(..., n_film=1.33)`` to 1e-11 in XYZ (Y of white = 1) up to 2 µm (every term
that matters lies in the table there) and to 1e-5 up to 20 µm (the dropped terms).

Units: thickness and OPD in nm, angles in radians, XYZ with the white under E at Y = 1.
NumPy only, plus colour-science and scipy inside :func:`blender_like_table` (imported there).
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "OBSERVER", "bb_sensitivity", "fourier_film_XYZ", "bb_film_XYZ", "LUT_STEP_NM", "LUT_MAX_OPD_NM", "lut_table",
    "lut_sensitivity", "lut_film_XYZ", "BLENDER_N_SAMPLES", "BLENDER_DNU_PER_UM", "BLENDER_TABLE_SIZE",
    "BLENDER_STEP_NM", "BLENDER_MAX_OPD_NM", "BLENDER_TERMS", "blender_like_table", "check_lut",
]

OBSERVER = "CIE 1931 2 Degree Standard Observer"

# Belcour & Barla (2017), supplemental code, evalSensitivity: XYZ CMFs fitted in wavenumber by
# Gaussians (one per channel, two for x), Fourier-transformed in closed form; OPD in m.
_BB_VAL = np.array([5.4856e-13, 4.4201e-13, 5.2481e-13])
_BB_POS = np.array([1.6810e06, 1.7953e06, 2.2084e06])
_BB_VAR = np.array([4.3278e09, 9.3046e09, 6.6121e09])
_BB_X2 = (9.7470e-14, 2.2399e06, 4.5282e09)  # value, position, variance of x's second lobe
_BB_NORM = 1.0685e-7


def bb_sensitivity(opd_nm):
    """Belcour-Barla's XYZ sensitivity S(OPD) (shift 0) for OPD in nm; shape (..., 3)."""
    phase = 2.0 * np.pi * np.asarray(opd_nm, float)[..., None] * 1e-9
    xyz = _BB_VAL * np.sqrt(2.0 * np.pi * _BB_VAR) * np.cos(_BB_POS * phase) * np.exp(-_BB_VAR * phase**2)
    v, p, s = _BB_X2
    xyz[..., 0] += v * np.sqrt(2.0 * np.pi * s) * np.cos(p * phase[..., 0]) * np.exp(-s * phase[..., 0] ** 2)
    return xyz / _BB_NORM


def fourier_film_XYZ(d, theta, n_film, sensitivity, n_terms=None):
    """XYZ (illuminant E) of a free-standing lossless film of constant index by its Fourier series in
    OPD, each term's XYZ from ``sensitivity(OPD in nm) -> (..., 3)`` (``sensitivity(0)``: the white).
    The series runs to convergence (rho^m > 1e-17), or stops after *n_terms* terms m >= 1 if given."""
    import bubbleoptics as bo

    f = bo.fresnel_coefficients(1.0, n_film, theta)
    q1 = np.sqrt(n_film**2 - np.sin(theta) ** 2)
    opd = 2.0 * d * q1  # nm; 2 beta = 2 pi OPD / lambda
    out = 0.0
    for rho in (float(f.Rs), float(f.Rp)):  # free-standing film: rho = R01, T_inc = (1-R01)/(1+R01)
        t_inc = (1.0 - rho) / (1.0 + rho)
        xyz = (1.0 - t_inc) * sensitivity(0.0) * np.ones_like(opd)[..., None]
        m = 1
        while rho**m > 1e-17 and (n_terms is None or m <= n_terms):
            xyz = xyz - 2.0 * t_inc * rho**m * sensitivity(m * opd)
            m += 1
        out = out + 0.5 * xyz
    return out


def bb_film_XYZ(d, theta, n_film):
    """XYZ (illuminant E) of a free-standing lossless film by the Fourier series x Gaussian fit."""
    return fourier_film_XYZ(d, theta, n_film, bb_sensitivity)


# The lookup-table anchor (module docstring): the exact S(OPD) of the 1 nm CMFs under E, every
# LUT_STEP_NM of OPD up to LUT_MAX_OPD_NM = (360 nm)^2 / (2 x 1 nm), where the 1 nm sum stops
# resolving cos(2 pi OPD / lambda) at the shortest wavelength.
LUT_STEP_NM = 1.0
LUT_MAX_OPD_NM = 64800.0


def lut_table(step_nm=LUT_STEP_NM, max_opd_nm=LUT_MAX_OPD_NM, samples=None):
    """(OPD nodes in nm (K,), S (K, 3)): S(OPD) = spectral_weights(WL, illuminant=None) @ cos(2 pi OPD / WL),
    the exact sensitivity of the tabulated 1 nm CMFs under E (S(0): the perfect white, Y = 1).

    With *samples* = (wavelengths in nm (J,), weights (3, J)), the table is of those samples instead and
    complex, S(OPD) = weights @ exp(-2 pi i OPD / wavelengths): its real part is the cosine sum above,
    its imaginary part the sine sum that a film whose reflections shift the phase by other than 0 or pi
    would need (:func:`blender_like_table` uses this)."""
    if samples is None:
        import bubbleoptics as bo
        from bubbleoptics.colorimetry import DEFAULT_WAVELENGTHS_NM as WL

        W = bo.spectral_weights(WL, illuminant=None)  # (3, 421), the weights of the 1 nm reference
    else:
        WL, W = samples
    opd = step_nm * np.arange(int(np.floor(max_opd_nm / step_nm + 1e-9)) + 1)
    k = 2.0 * np.pi / WL
    S = np.empty((opd.size, 3), float if samples is None else complex)
    for i in range(0, opd.size, 4096):
        if samples is None:
            S[i : i + 4096] = np.cos(opd[i : i + 4096, None] * k) @ W.T
        else:
            S[i : i + 4096] = np.exp(-1j * opd[i : i + 4096, None] * k) @ W.T
    return opd, S


def lut_sensitivity(table, opd_nm, hold_last=False, polar=False):
    """S(OPD) linearly interpolated in *table* (from :func:`lut_table` or :func:`blender_like_table`), (..., 3).

    Beyond the last node: 0, or the last node's value if *hold_last* (Blender's clamped lookup).  A
    complex table is interpolated in its real and imaginary parts (or, if *polar*, in its magnitude and
    unwrapped phase) and its real part returned: the term's weight for a reflection phasor of +1, which
    is this film's (module docstring).  A table with a third element, a (3, 3) matrix, holds another
    colour space's channels (Blender's working RGB); the matrix takes the interpolated values to XYZ."""
    nodes, S = table[:2]
    x = np.asarray(opd_nm, float)

    def interp(F):
        return np.stack([np.interp(x, nodes, F[:, c], right=F[-1, c] if hold_last else 0.0) for c in range(3)],
                        axis=-1)

    if not np.iscomplexobj(S):
        out = interp(S)
    elif polar:
        out = interp(np.abs(S)) * np.cos(interp(np.unwrap(np.angle(S), axis=0)))
    else:
        out = interp(S.real)  # the imaginary part, interpolated alike, is multiplied by Im(phasor^m) = 0
    return out @ table[2].T if len(table) > 2 else out


def lut_film_XYZ(d, theta, n_film, table, n_terms=None, hold_last=False, polar=False):
    """XYZ (illuminant E) of a free-standing lossless film by the Fourier series x the lookup table
    (*n_terms*: :func:`fourier_film_XYZ`; *hold_last*, *polar*: :func:`lut_sensitivity`)."""
    return fourier_film_XYZ(d, theta, n_film, lambda opd: lut_sensitivity(table, opd, hold_last, polar),
                            n_terms=n_terms)


# The table rebuilt like Blender's (module docstring): the CIE 1931 2 deg CMFs (1 nm, 360-830 nm, a zero
# added at 359 and at 831 nm) cubic-spline interpolated in wavelength, sampled at BLENDER_N_SAMPLES
# wavenumbers nu_j = j * BLENDER_DNU_PER_UM (weight cmf(1/nu_j) / nu_j^2, the Jacobian d lambda / d nu),
# Fourier-transformed (a real FFT: BLENDER_TABLE_SIZE complex entries, entry k at OPD = k / (N dnu), every
# BLENDER_STEP_NM = 18.69 nm to BLENDER_MAX_OPD_NM = 9.549 um; the kernel reads it at x = 2 pi OPD / 60 um,
# clamped to [0, 1], times 511: the same nodes), taken to the working RGB (BT.709) and each channel divided
# by its DC entry; the kernel's series stops after BLENDER_TERMS terms.  Parameters only, read in
# Blender's source (paths in the module docstring); no code or data copied.
BLENDER_N_SAMPLES = 1022
BLENDER_DNU_PER_UM = np.pi / 60.0
BLENDER_TABLE_SIZE = BLENDER_N_SAMPLES // 2 + 1
BLENDER_STEP_NM = 1000.0 / (BLENDER_N_SAMPLES * BLENDER_DNU_PER_UM)
BLENDER_MAX_OPD_NM = (BLENDER_TABLE_SIZE - 1) * BLENDER_STEP_NM
BLENDER_TERMS = 3


def blender_like_table():
    """(OPD nodes in nm (512,), S (512, 3) complex, in BT.709 RGB with S(0) = (1, 1, 1), RGB -> XYZ (3, 3)): the
    lookup table rebuilt like Blender's (comment above), for :func:`lut_film_XYZ` with ``n_terms=BLENDER_TERMS,
    hold_last=True``.  The RGB -> XYZ matrix takes RGB (1, 1, 1) to the reference's white under E (Y = 1), as
    a white film's RGB is (1, 1, 1) in Blender whatever its CMFs.  Checked on construction: the entries equal
    the real FFT of the samples (AssertionError otherwise)."""
    import bubbleoptics as bo
    import colour
    from bubbleoptics.colorimetry import DEFAULT_WAVELENGTHS_NM as WL
    from scipy.interpolate import CubicSpline

    cmfs = colour.MSDS_CMFS[OBSERVER]
    lam = np.concatenate([[cmfs.wavelengths[0] - 1.0], cmfs.wavelengths, [cmfs.wavelengths[-1] + 1.0]])
    spline = CubicSpline(lam, np.vstack([np.zeros(3), cmfs.values, np.zeros(3)]), extrapolate=False)
    nu = BLENDER_DNU_PER_UM * np.arange(1, BLENDER_N_SAMPLES)  # 1/um; nu = 0 has weight 0
    weights = np.nan_to_num(spline(1000.0 / nu)).T / nu**2  # (3, N - 1), 0 outside 359-831 nm
    nodes, S = lut_table(BLENDER_STEP_NM, BLENDER_MAX_OPD_NM, samples=(1000.0 / nu, weights))
    fft = np.fft.rfft(np.hstack([np.zeros((3, 1)), weights]), axis=1).T
    if nodes.size != BLENDER_TABLE_SIZE or not np.allclose(S, fft, rtol=0.0, atol=1e-9 * np.abs(fft).max()):
        raise AssertionError(f"Blender-like table: {nodes.size} nodes, max |table - FFT| {np.abs(S - fft).max():.1e}")
    M = colour.models.RGB_COLOURSPACE_BT709.matrix_XYZ_to_RGB
    rgb = S @ M.T
    white = bo.spectral_weights(WL, illuminant=None).sum(axis=1)  # the reference's white under E, Y = 1
    return nodes, rgb / rgb[0].real, np.linalg.inv(M) @ np.diag(M @ white)


def check_lut(table, n_film=1.33, max_thickness_nm=20000.0, tol_thin=1e-11, tol_all=1e-5, every=37):
    """Independent check of the table: at thicknesses whose OPD is a table node (so the interpolation is
    exact), :func:`lut_film_XYZ` must equal the direct 1 nm integration of ``film_reflectance`` with the
    same constant index, to *tol_thin* in XYZ (Y of white = 1) up to 2 µm (every term above 1e-16 lies in
    the table there) and to *tol_all* up to *max_thickness_nm* (terms beyond the table are dropped).
    Raises AssertionError (not an ``assert`` statement, so ``python -O`` keeps it); returns
    {theta_deg: (worst error up to 2 µm, worst error overall)}."""
    import bubbleoptics as bo
    from bubbleoptics.colorimetry import DEFAULT_WAVELENGTHS_NM as WL

    nodes, S = table
    step = nodes[1] - nodes[0]
    WE = bo.spectral_weights(WL, illuminant=None)
    out = {}
    for theta_deg in (0.0, 60.0):
        th = np.deg2rad(theta_deg)
        q1 = np.sqrt(n_film**2 - np.sin(th) ** 2)
        opd = step * np.arange(0, int(2.0 * max_thickness_nm * q1 / step) + 1, every)  # table nodes
        if opd[-1] > nodes[-1]:
            raise AssertionError(f"the table ends at OPD {nodes[-1]:.0f} nm, the films need {opd[-1]:.0f} nm")
        d = opd / (2.0 * q1)
        direct = bo.film_reflectance(WL, d[:, None], th, n_film) @ WE.T
        err = np.abs(lut_film_XYZ(d, th, n_film, table) - direct).max(axis=-1)
        thin = d <= 2000.0
        out[theta_deg] = (float(err[thin].max()), float(err.max()))
        if not (out[theta_deg][0] <= tol_thin and out[theta_deg][1] <= tol_all):
            raise AssertionError(f"lookup table vs direct 1 nm integration at {theta_deg:g} deg: max |dXYZ| "
                                 f"{out[theta_deg][0]:.2e} up to 2 um (tolerance {tol_thin:g}), "
                                 f"{out[theta_deg][1]:.2e} up to {max_thickness_nm:g} nm (tolerance {tol_all:g})")
    return out

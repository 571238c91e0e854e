"""Film colour from few spectral samples: aliasing of point sampling against band-limited methods.

Run:  python benchmarks/bandlimited_colour.py [--thicknesses N] [--repeats N] [--quick]
Writes ``data/derived/bandlimited_colour.csv``.

Setting: a free-standing water film (Daimon & Masumura 2007 dispersion) in air, unpolarized,
thickness 0-20 µm (4001 values), angles of incidence 0° and 60°, CIE 1931 2° observer, D65.
Reference: the 1 nm spectrum, 360-780 nm (``bubbleoptics.film_color(..., wavelengths_nm=None)``
before display encoding).  Error: CIE ΔE00 (``colour.delta_E(..., method="CIE 2000")``) of
``colour.XYZ_to_Lab`` with the illuminant's white, per thickness; the table gives its median,
95th percentile, maximum, and the thickness of the maximum over 0-20 µm, and the median and
maximum over 0-2 µm alone (the saturated low orders; over 0-20 µm the grey thick films, where
every method but point sampling converges, pull the median down).  These compare the colours
as reflected: a water film reflects at most ~8 %, so they are dark (L* below ~35) and their
differences small.  ``dE00_max_exposed`` and ``dE00_median_0_2um_exposed`` compare them after
the exposure ``exposure`` = 1 / (the reference's largest Y over 0-1 µm), which makes the
brightest film white, as ``benchmarks/stability.py``, notebook 01 and a camera exposed for the
bubble show them: every difference grows (2-3x).

Methods (N bands of equal width over 360-780 nm):

* ``point``: R sampled at the N band centres, weights ``band_spectral_weights(N)`` (what the
  tracer does today);
* ``band_mean``: one value per band, R averaged uniformly in wavelength over the band
  (``film_reflectance_band``), same weights: what a renderer carrying one value per band can use;
* ``band_mean_phase``: the same averaged uniformly in phase (the atan2 closed form alone,
  ``kernels.film_band_average``);
* ``bandlimited``: ``film_XYZ_bandlimited`` -- CMFs x D65 as continuous piecewise polynomials of
  degree ``order`` in wavenumber, integrated exactly against the film's band moments.

Second block, illuminant E and a non-dispersive film (n = 1.33), the setting of the Gaussian
fit of the CMFs in Fourier space by L. Belcour and P. Barla, "A Practical Extension to Microfacet
Theory for the Modeling of Varying Iridescence", ACM TOG 36(4), 65 (SIGGRAPH 2017), also used by
Blender 4.2's thin film: the film's exact Fourier series in optical path difference,
:math:`R = (1 - T_{inc}) - 2T_{inc}\\sum_m \\rho^m\\cos(2\\pi m\\,{\\rm OPD}/\\lambda)` (summed
to convergence, so only the CMF fit is tested), with each term's XYZ from their published
Gaussian-fit sensitivity (constants as in the paper's supplemental code).  Its reference is the 1 nm
spectrum under E with the same n; ``gaussian_fit_vs_dispersive`` compares it with the water
(dispersive) reference under E instead, adding the error of ignoring dispersion.

In the same block, ``lut_nondispersive``: the same Fourier series, each term's XYZ from a lookup
table of the *exact* sensitivity :math:`S({\\rm OPD}) = \\int \\bar{\\mathbf{x}}(\\lambda) E(\\lambda)
\\cos(2\\pi\\,{\\rm OPD}/\\lambda)\\,d\\lambda`, i.e. ``spectral_weights(WL, illuminant=None) @
cos(2 pi OPD / WL)``: the very 1 nm weights of the reference (CIE 1931 2°, 360-780 nm, the CMFs
beyond 780 nm folded into 780 nm as colour-science's integration does), normalized alike (S(0)
is the perfect white under E, Y = 1).  Tabulated every ``LUT_STEP_NM`` = 1 nm of OPD from 0 to
``LUT_MAX_OPD_NM`` = 64.8 µm, linearly interpolated, S = 0 beyond.  Why there: the first term
needs OPD = 2 d n cos(theta_1) <= 53.2 µm here (20 µm at normal incidence); 64.8 µm =
(360 nm)^2 / (2 x 1 nm) is where the 1 nm sum stops resolving cos(2 pi OPD / lambda) at 360 nm
(beyond, it aliases: |S| up to 0.25 at 100-300 µm, an artefact of the sampling, not of the
CMFs), and by then the resolved S has decayed to |S| < 3e-5 (S(0) ~ 1; |S| < 1e-3 from 20 µm on).
Terms m >= 2 whose m OPD lies beyond the table are dropped; they carry at most 2 T rho^m of the
white.  The film index is the constant n = 1.33: one table in OPD cannot hold a
wavelength-dependent index, so the table ignores dispersion by construction.

``lut_nondispersive`` against the constant-index reference measures the table's own error
(interpolation and the dropped terms; tiny).  ``lut_nondispersive_vs_dispersive`` against the
water reference measures the cost of ignoring dispersion with n = 1.33 (below water's index at
every wavelength in 360-780 nm: 1.348-1.329, 1.33 near 725 nm), and
``lut_nondispersive_n555_vs_dispersive`` the same with the constant index set to water's at
555 nm (the peak of y-bar, 1.3345): the choice of the single index is part of the cost.  Ours is
the exact 1 nm integral on a 1 nm grid, so its error against the dispersive reference is that
of ignoring dispersion alone, essentially a lower bound for any table of this kind with the same
constant index, whatever its resolution; another table adds its own error, which can partly
offset the dispersion error at some thicknesses (the Gaussian fit's maximum at 60° is lower).

What this is: the approach the project's issue attributes to Blender 5.0 ("its lookup table
ignores dispersion"), rebuilt here with the exact integral; *not* Blender's table, which is coarser.

``lut_blender_like`` (against the n = 1.33 reference: the table's own error) and
``lut_blender_like_vs_dispersive`` (against the water reference): the same series with a table
built like Blender's (:func:`blender_like_table`).  A reconstruction from the parameters of
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
multiplied by one fixed matrix; the script does the RGB step literally anyway (BT.709 matrix of
colour-science; back to XYZ by the matrix that takes RGB (1, 1, 1) to the reference's white under
E, since a white film is (1, 1, 1) in Blender).  Its only effect is the per-channel normalization,
a white correction of < 0.4 % (the spline-sampled CMFs' white differs from the reference's by
about 1e-3 in XYZ).  Complex entries: the kernel weights each entry by the reflection phasor
exp(i m phi) (real times real plus imaginary times imaginary); for this free-standing dielectric
film the phasor is +1 in both polarizations, below and above Brewster's angle, so only the real
part enters and the imaginary part, kept in the table, does not change these rows.

Versions: two revisions of that kernel and start-up code were found.  One stores and interpolates
each RGB channel's magnitude and unwrapped phase (entry = magnitude x cos(phase - m phi)); a later
one, which also handles conductor substrates, stores and interpolates real and imaginary parts.
The rows follow the later; the run prints the earlier's errors (``polar=True``, not a row).  Which
release ships which was not checked: the project's issue says Blender 5.0, a third-party port of
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

Checked at every run (:func:`check_lut`): at thicknesses whose OPD falls on table nodes (where
the interpolation is exact), the table's series equals the direct 1 nm integration of
``film_reflectance(..., n_film=1.33)`` to 1e-11 in XYZ (Y of white = 1) up to 2 µm (every term
that matters lies in the table there) and to 1e-5 up to 20 µm (the dropped terms).

``bandlimited_water``: ``film_XYZ_bandlimited`` (16 bands, order 3, illuminant E) of the water film
against the water reference under E, the like-for-like companion of the two ``_vs_dispersive``
rows.

Times: wall time per colour (XYZ only, after a warm-up call), median and minimum of the repeats,
numba kernels on all of this machine's cores; the Gaussian fit and the lookup table are plain
NumPy (vectorized; the tables' construction, about a second, is not included) and are timed for
completeness only.
"""

import argparse
import datetime
import os
import platform
import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.append(str(Path(__file__).resolve().parent))  # for scripts loaded by file path (notebooks)
from _results import wall_times, write_csv  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "data" / "derived" / "bandlimited_colour.csv"
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


def timed(func, repeats):
    """(median, minimum) wall time of *repeats* calls after one untimed warm-up call.

    The minimum is the one to compare on a shared machine (the others' load only adds time).
    """
    times = wall_times(func, repeats)
    return float(np.median(times)), float(np.min(times))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--thicknesses", type=int, default=4001, help="thickness samples over 0-20 um")
    parser.add_argument("--repeats", type=int, default=5, help="timed runs (median)")
    parser.add_argument("--quick", action="store_true", help="401 thicknesses, 2 repeats (smoke test)")
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args(argv)
    if args.quick:
        args.thicknesses, args.repeats = 401, 2

    import colour

    import bubbleoptics as bo
    from bubbleoptics.bandlimited import film_XYZ_bandlimited
    from bubbleoptics.colorimetry import DEFAULT_WAVELENGTHS_NM as WL

    d = np.linspace(0.0, 20000.0, args.thicknesses)
    thin = d <= 2000.0  # the first interference orders, where the colours are saturated
    rows = []

    def lab(XYZ, ill):
        wp = colour.CCS_ILLUMINANTS[OBSERVER][ill]
        return colour.XYZ_to_Lab(XYZ, wp)

    def reference(XYZ, ill):
        """The reference colours as Lab, as reflected and after the exposure k that makes the
        brightest film of 0-1 um white (as benchmarks/stability.py and notebook 01 show them)."""
        k = 1.0 / XYZ[d <= 1000.0, 1].max()
        return dict(lab=lab(XYZ, ill), lab_exposed=lab(k * XYZ, ill), exposure=k)

    def dE00(XYZ, ref, ill):
        """Per-thickness CIEDE2000 against *ref*, as reflected and after the reference's exposure."""
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            e = np.asarray(colour.delta_E(lab(XYZ, ill), ref["lab"], method="CIE 2000"))
            e_exp = np.asarray(colour.delta_E(lab(ref["exposure"] * XYZ, ill), ref["lab_exposed"],
                                              method="CIE 2000"))
        return e, e_exp

    def record(method, n_bands, order, ill, theta_deg, XYZ, ref, seconds, note=""):
        t_med, t_min = seconds
        e, e_exp = dE00(XYZ, ref, ill)
        rows.append(
            dict(
                method=method,
                n_bands=n_bands,
                order=order,
                illuminant=ill,
                theta_deg=theta_deg,
                dE00_median=float(np.median(e)),
                dE00_p95=float(np.percentile(e, 95)),
                dE00_max=float(e.max()),
                worst_thickness_nm=float(d[int(np.argmax(e))]),
                dE00_median_0_2um=float(np.median(e[thin])),
                dE00_max_0_2um=float(e[thin].max()),
                ns_per_colour=1e9 * t_med / d.size,
                ns_per_colour_min=1e9 * t_min / d.size,
                note=note,
                exposure=float(ref["exposure"]),
                dE00_max_exposed=float(e_exp.max()),
                dE00_median_0_2um_exposed=float(np.median(e_exp[thin])),
            )
        )
        r = rows[-1]
        print(
            f"{method:36s} N={str(n_bands):>4s} L={str(order):>2s} {ill:3s} {theta_deg:4.0f}°  "
            f"median {r['dE00_median']:6.3f}  p95 {r['dE00_p95']:6.3f}  max {r['dE00_max']:6.3f} "
            f"(at {r['worst_thickness_nm']:7.0f} nm)  0-2um: {r['dE00_median_0_2um']:6.3f} {r['dE00_max_0_2um']:6.3f}  "
            f"{r['ns_per_colour']:6.0f} ns/colour (min {r['ns_per_colour_min']:.0f})",
            flush=True,
        )

    W1 = bo.spectral_weights(WL)
    for theta_deg in (0.0, 60.0):
        th = np.deg2rad(theta_deg)
        ref_xyz = bo.film_reflectance(WL, d[:, None], th) @ W1.T
        ref = reference(ref_xyz, "D65")
        t = timed(lambda: bo.film_reflectance(WL, d[:, None], th) @ W1.T, args.repeats)
        record("reference_1nm", 421, "", "D65", theta_deg, ref_xyz, ref, t)
        for N in (4, 8, 16):
            wl, Wb = bo.band_spectral_weights(N)

            def point(wl=wl, Wb=Wb):
                return bo.film_reflectance(wl, d[:, None], th) @ Wb.T

            record("point", N, "", "D65", theta_deg, point(), ref, timed(point, args.repeats))

            def band_mean(Wb=Wb, N=N):
                return bo.film_reflectance_band(N, d, th) @ Wb.T

            record("band_mean", N, 6, "D65", theta_deg, band_mean(), ref, timed(band_mean, args.repeats))

            def band_mean_phase(Wb=Wb, N=N):
                return bo.film_reflectance_band(N, d, th, weighting="phase") @ Wb.T

            record("band_mean_phase", N, 0, "D65", theta_deg, band_mean_phase(), ref,
                   timed(band_mean_phase, args.repeats))
            for L in (2, 3, 4, 8):

                def bandlimited(N=N, L=L):
                    return film_XYZ_bandlimited(d, th, N, order=L)

                record("bandlimited", N, L, "D65", theta_deg, bandlimited(), ref,
                       timed(bandlimited, args.repeats), "default" if L == 3 else "")

    # Illuminant E, non-dispersive film: the Gaussian CMF fit of Belcour & Barla (2017) and the lookup table
    WE = bo.spectral_weights(WL, illuminant=None)
    n_const = 1.33
    t0 = time.perf_counter()
    table = lut_table()
    t_table = time.perf_counter() - t0
    nodes, S = table
    tail = nodes >= 53200.0
    checked = check_lut(table, n_const)
    print(f"lookup table: {nodes.size} nodes every {LUT_STEP_NM:g} nm of OPD to {nodes[-1]:.0f} nm, built in "
          f"{t_table:.2f} s; S(0) = {np.array2string(S[0], precision=6)}; max |S| over OPD 53.2-64.8 um "
          f"{np.abs(S[tail]).max():.1e}; check against the direct 1 nm integration at table nodes, max |dXYZ| "
          + ", ".join(f"{k:g} deg: {a:.1e} (<= 2 um), {b:.1e} (<= 20 um)" for k, (a, b) in checked.items()),
          flush=True)
    bl_table = blender_like_table()
    bl_nodes, bl_S, bl_to_xyz = bl_table
    bl_S0_xyz = bl_S[0].real @ bl_to_xyz.T
    print(f"Blender-like table: {bl_nodes.size} complex entries every {BLENDER_STEP_NM:.3f} nm of OPD to "
          f"{bl_nodes[-1]:.0f} nm (value held beyond), series stopped after m = {BLENDER_TERMS}; S(0) in XYZ "
          f"{np.array2string(bl_S0_xyz, precision=6)}; held value in XYZ "
          f"{np.array2string(bl_S[-1].real @ bl_to_xyz.T, precision=5)}; |Re S - exact S| at its nodes, max "
          f"{np.abs(bl_S.real @ bl_to_xyz.T - lut_sensitivity(table, bl_nodes)).max():.1e}", flush=True)
    n_555 = float(bo.water_refractive_index(555.0))
    lut_note = (f"n=1.33; NumPy; exact 1 nm S(OPD) every {LUT_STEP_NM:g} nm to {nodes[-1] / 1000:g} um; "
                "linear interpolation")
    for theta_deg in (0.0, 60.0):
        th = np.deg2rad(theta_deg)
        ref_const = reference(bo.film_reflectance(WL, d[:, None], th, n_const) @ WE.T, "E")
        ref_water = reference(bo.film_reflectance(WL, d[:, None], th) @ WE.T, "E")
        bb = bb_film_XYZ(d, th, n_const)
        t = timed(lambda: bb_film_XYZ(d, th, n_const), args.repeats)
        record("gaussian_fit_BB2017", "", "", "E", theta_deg, bb, ref_const, t, "n=1.33; NumPy")
        record("gaussian_fit_vs_dispersive", "", "", "E", theta_deg, bb, ref_water, t,
               "n=1.33 against the water reference")
        wl, Wb = bo.band_spectral_weights(16, illuminant=None)
        pt = bo.film_reflectance(wl, d[:, None], th, n_const) @ Wb.T
        record("point", 16, "", "E", theta_deg, pt, ref_const, (float("nan"), float("nan")), "n=1.33")
        ours = film_XYZ_bandlimited(d, th, 16, n_film=n_const, illuminant=None, order=3)
        record("bandlimited", 16, 3, "E", theta_deg, ours, ref_const, (float("nan"), float("nan")), "n=1.33")
        lut = lut_film_XYZ(d, th, n_const, table)
        t = timed(lambda: lut_film_XYZ(d, th, n_const, table), args.repeats)
        record("lut_nondispersive", "", "", "E", theta_deg, lut, ref_const, t, lut_note)
        record("lut_nondispersive_vs_dispersive", "", "", "E", theta_deg, lut, ref_water, t,
               "n=1.33 against the water reference")
        record("lut_nondispersive_n555_vs_dispersive", "", "", "E", theta_deg, lut_film_XYZ(d, th, n_555, table),
               ref_water, t, f"n={n_555:.4f} (water at 555 nm) against the water reference")

        def blender_like(polar=False):
            return lut_film_XYZ(d, th, n_const, bl_table, n_terms=BLENDER_TERMS, hold_last=True, polar=polar)

        bl = blender_like()
        t = timed(blender_like, args.repeats)
        record("lut_blender_like", "", "", "E", theta_deg, bl, ref_const, t,
               f"n=1.33; NumPy; like Blender's table (rebuilt from its source): {bl_nodes.size} complex entries "
               f"every {BLENDER_STEP_NM:.1f} nm to {bl_nodes[-1] / 1000:.2f} um, last held; "
               f"m <= {BLENDER_TERMS}; RGB per-channel DC normalization")
        record("lut_blender_like_vs_dispersive", "", "", "E", theta_deg, bl, ref_water, t,
               "n=1.33 against the water reference")
        # Not a row: the earlier revision's interpolation in magnitude and unwrapped phase (module docstring)
        e_polar, e_polar_exp = dE00(blender_like(polar=True), ref_const, "E")
        print(f"{'  (magnitude/phase interpolation)':36s} {theta_deg:4.0f}°  median {np.median(e_polar):6.3f}  "
              f"max {e_polar.max():6.3f} (at {d[int(np.argmax(e_polar))]:7.0f} nm)  max exposed "
              f"{e_polar_exp.max():6.3f}", flush=True)

        def ours_water():
            return film_XYZ_bandlimited(d, th, 16, illuminant=None, order=3)

        record("bandlimited_water", 16, 3, "E", theta_deg, ours_water(), ref_water, timed(ours_water, args.repeats),
               "water against the water reference")

    write_csv(args.out, rows,
              f"written by benchmarks/bandlimited_colour.py on {datetime.date.today()}; "
              f"{d.size} thicknesses 0-20000 nm; {platform.processor() or platform.machine()}, "
              f"{os.cpu_count()} CPUs; regenerate with: python benchmarks/bandlimited_colour.py",
              float_format="{:.4g}")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()

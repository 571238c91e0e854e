"""Measured soap films against the exact optics and the film-flow laws (the paper's Measurement section).

The measurements are white-light reflection spectra of horizontal foam films of TTAB and other
surfactant solutions, published with the thickness their authors deduced from each spectrum
(Ziapkoff, Boulogne, Salonen & Rio 2026, *Eur. Phys. J. E* 49, 4, doi:10.1140/epje/s10189-025-00545-9;
the spectra are the test data of their library optifik; provenance, licence and checksums in
``data/measured/README.md``).  What is compared:

* **optics**: :func:`fit_thickness` fits the exact reflectance of a free water film
  (:func:`bubbleoptics.film_reflectance`, normal incidence, water after Daimon & Masumura 2007 by
  default) to a measured spectrum, the thickness by a scan over the fringe orders refined with
  :func:`scipy.optimize.minimize_scalar`, an instrument gain (and optionally a linear tilt of it
  across the band) by linear least squares at each thickness.  :func:`rms_at_thickness` is the
  same with the thickness held at the authors' value.  The authors' thickness is independent of
  this code: they located fringe extrema, Fourier-transformed the spectrum or inverted the
  normalised intensity (Scheludko), with an index :func:`cauchy_index`.
* **thinning**: :func:`fit_thinning_law` fits :math:`h(t) = h_1\\,[1 + (t - t_1)/\\tau]^{-\\alpha}`
  (the solution of :math:`\\dot h = -c\\,h^{\\beta}` with :math:`\\beta = 1 + 1/\\alpha`) to a
  measured thickness series.  The rate exponent β does not depend on the time origin or unit,
  so it is what can be compared: 3 for the rigid-interface drainage of
  :class:`bubbleoptics.filmflow.RigidDrainage` (its apex law :math:`h_0(1+t/\\tau)^{-1/2}`),
  5/2 for the :math:`t^{-2/3}` marginal-regeneration thinning of bubble caps (Lhuissier &
  Villermaux 2012, *J. Fluid Mech.* 696, 5-44), 0 for thinning by evaporation alone.

Loaders: :func:`load_spectrum` (the two-column ``.xy`` text files: wavelength in nm, intensity in
the spectrometer's normalised units), :func:`read_known_values` (the authors' small YAML files
of thicknesses), :func:`load_stated_thicknesses` (the CSV transcription of them committed in
``data/measured/``).  Every loader takes a path; nothing here knows where the repository keeps
its files.

Units: wavelength and thickness in nm, angles in radians, the film index ``n + ik``; times in the
unit of the series given (the acquisition index of the files' names for the optifik series).
scipy is imported inside the fits only.
"""

from __future__ import annotations

import csv
import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

__all__ = [
    "FIT_BAND_NM",
    "OPTIFIK_CAUCHY",
    "cauchy_index",
    "load_spectrum",
    "read_known_values",
    "load_stated_thicknesses",
    "series_time",
    "model_reflectance",
    "ThicknessFit",
    "fit_thickness",
    "rms_at_thickness",
    "ThinningFit",
    "fit_thinning_law",
    "THINNING_EXPONENTS",
    "smooth",
    "quarter_wave_reflectance",
    "lamp_envelope",
    "calibrated_reflectance",
    "OPTIFIK_SERIES",
    "OPTIFIK_VOID",
    "OPTIFIK_ENVELOPE_FROM",
    "OPTIFIK_EXAMPLES",
    "optifik_series",
    "optifik_stated",
    "compare_optifik",
    "thinning_rows",
    "main",
]

#: Cauchy coefficients (A, B in nm²) of the film index the optifik authors use for their TTAB
#: series, n(λ) = A + B/λ² (their tests ``tests/test_SV*.py``; 1.3344 at 550 nm).
OPTIFIK_CAUCHY = (1.324188, 3102.060378)

#: The thinning-rate exponents β of dh/dt = -c h^β that the measured β is compared with.
THINNING_EXPONENTS = {
    "rigid drainage (this project's model, no evaporation)": 3.0,
    "marginal regeneration, h ~ t^-2/3 (Lhuissier & Villermaux 2012)": 2.5,
    "evaporation only": 0.0,
}

_MIN_POINTS = 20


def cauchy_index(wavelength_nm, a=OPTIFIK_CAUCHY[0], b=OPTIFIK_CAUCHY[1]):
    """The Cauchy index :math:`n(\\lambda) = a + b/\\lambda^2` (λ in nm, b in nm²).

    >>> round(float(cauchy_index(550.0)), 4)
    1.3344
    """
    wl = np.asarray(wavelength_nm, dtype=float)
    if np.any(~np.isfinite(wl)) or np.any(wl <= 0):
        raise ValueError("wavelength_nm must be finite and > 0")
    return a + b / wl**2


#: The wavelengths the spectra are compared over, nm (the spectrometer's trustworthy range).
FIT_BAND_NM = (450.0, 800.0)


def load_spectrum(path, wavelength_min=FIT_BAND_NM[0], wavelength_max=FIT_BAND_NM[1]):
    """``(wavelength_nm, intensity)`` of a two-column text spectrum, cut to [min, max] nm.

    The columns are separated by a comma (optifik's ``.xy`` files), or by white space.  Rows
    whose intensity is not finite (the ``nan`` of some spectrometer exports) are dropped.

    Raises ``FileNotFoundError`` for a missing file and ``ValueError`` for a file that is not two
    numeric columns, whose wavelengths do not increase strictly, or that keeps fewer than
    20 finite points in the band.
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"no spectrum file {path}")
    if not wavelength_min < wavelength_max:
        raise ValueError(f"wavelength_min must be < wavelength_max (got {wavelength_min}, {wavelength_max})")
    rows = []
    for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        text = line.strip()
        if not text or text.startswith("#"):
            continue
        parts = [p for p in re.split(r"[,\s;]+", text) if p]
        if len(parts) != 2:
            raise ValueError(f"{path}:{number}: expected two columns (wavelength, intensity), got {len(parts)}")
        try:
            rows.append((float(parts[0]), float(parts[1])))
        except ValueError:
            raise ValueError(f"{path}:{number}: not a number: {text!r}") from None
    if not rows:
        raise ValueError(f"{path}: no data rows")
    data = np.array(rows)
    wl, inten = data[:, 0], data[:, 1]
    if not np.all(np.isfinite(wl)) or np.any(np.diff(wl) <= 0):
        raise ValueError(f"{path}: the wavelengths must be finite and strictly increasing")
    keep = (wl >= wavelength_min) & (wl <= wavelength_max) & np.isfinite(inten)
    if keep.sum() < _MIN_POINTS:
        raise ValueError(f"{path}: only {int(keep.sum())} finite points in [{wavelength_min}, {wavelength_max}] nm "
                         f"(at least {_MIN_POINTS} needed)")
    return wl[keep], inten[keep]


def read_known_values(path):
    """The authors' thickness file (optifik's ``known_value.yaml`` / ``sampleN.yaml``) as
    ``(metadata, {file name: thickness in nm})``.

    Reads the small YAML subset these files use: ``key: value`` lines at the top level and one
    mapping ``known_thicknesses:`` of ``  name.xy: number`` lines; ``#`` starts a comment (the
    authors comment out the spectra they exclude).  Anything else raises ``ValueError``.
    """
    path = Path(path)
    meta, values, inside = {}, {}, False
    for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        text = line.split("#", 1)[0].rstrip()
        if not text.strip():
            continue
        m = re.fullmatch(r"(\s*)([^:\s]+)\s*:\s*(.*)", text)
        if not m:
            raise ValueError(f"{path}:{number}: not a 'key: value' line: {line!r}")
        indent, key, value = m.groups()
        if not indent:
            inside = key == "known_thicknesses"
            if inside and value:
                raise ValueError(f"{path}:{number}: known_thicknesses must be a mapping")
            if not inside:
                meta[key] = value.strip()
        elif inside:
            try:
                values[key] = float(value)
            except ValueError:
                raise ValueError(f"{path}:{number}: thickness is not a number: {value!r}") from None
        else:
            raise ValueError(f"{path}:{number}: indented line outside known_thicknesses")
    if not values:
        raise ValueError(f"{path}: no known_thicknesses")
    return meta, values


def load_stated_thicknesses(path):
    """The committed transcription ``data/measured/optifik_stated_thickness.csv`` as a list of
    dicts (``series``, ``file``, ``time_index`` (int), ``stated_nm`` (float), ``index_model``),
    leading ``#`` lines skipped.  Raises ``ValueError`` for a missing column or a thickness
    that is not a positive number."""
    path = Path(path)
    with path.open(encoding="utf-8", newline="") as f:
        lines = [line for line in f if not line.startswith("#")]
    reader = csv.DictReader(lines)
    need = {"series", "file", "time_index", "stated_nm", "index_model"}
    if reader.fieldnames is None or not need <= set(reader.fieldnames):
        raise ValueError(f"{path}: needs the columns {sorted(need)} (got {reader.fieldnames})")
    out = []
    for row in reader:
        h = float(row["stated_nm"])
        if not (math.isfinite(h) and h > 0):
            raise ValueError(f"{path}: stated_nm must be > 0 (row {row})")
        out.append({**row, "time_index": int(row["time_index"]), "stated_nm": h})
    return out


def series_time(file_name):
    """The acquisition index in an optifik file name: ``'T14143.xy'`` -> 14143, ``'003582.xy'``
    -> 3582.  Within one series it increases with time (the thicknesses decrease with it); its
    unit is not stated by the source."""
    m = re.fullmatch(r"T?(\d+)\.xy", Path(file_name).name)
    if not m:
        raise ValueError(f"not an optifik spectrum name: {file_name!r}")
    return int(m.group(1))


def model_reflectance(wavelength_nm, thickness_nm, n_film=None):
    """Reflectance of a free-standing film at normal incidence (:func:`bubbleoptics.film_reflectance`);
    *n_film* ``None`` is water (Daimon & Masumura 2007), else an index or an array per wavelength."""
    from bubbleoptics import film_reflectance

    return film_reflectance(wavelength_nm, thickness_nm, 0.0, n_film)


def smooth(intensity, window=11, order=3):
    """Savitzky-Golay smoothing (scipy), *window* points of degree *order* (as optifik's analysis)."""
    from scipy.signal import savgol_filter

    return savgol_filter(np.asarray(intensity, dtype=float), window, order)


def quarter_wave_reflectance(wavelength_nm, n_film=None):
    """The largest reflectance a free film can have at each wavelength, that of a quarter-wave
    film (thickness λ/4n), :math:`4r^2/(1+r^2)^2` with r = (n-1)/(n+1), evaluated by
    :func:`bubbleoptics.film_reflectance`."""
    from bubbleoptics import water_refractive_index

    wl = np.asarray(wavelength_nm, dtype=float)
    n = water_refractive_index(wl) if n_film is None else np.broadcast_to(np.real(n_film), wl.shape)
    return np.asarray(model_reflectance(wl, wl / (4 * n), n_film), dtype=float)


def lamp_envelope(intensities, background, window=11, order=3):
    """The instrument's response times the largest reflectance at each wavelength, estimated from
    a series of spectra of one thinning film on one wavelength grid: the maximum over the series
    of the smoothed ``intensity - background`` (the Scheludko envelope; every wavelength passes
    through a reflectance maximum while the film thins through the interference orders), smoothed
    once more.  *intensities*: (n_spectra, n_wavelengths)."""
    stack = np.asarray(intensities, dtype=float)
    if stack.ndim != 2 or stack.shape[0] < 2 or stack.shape[1] != np.shape(background)[-1]:
        raise ValueError("intensities must be (n_spectra >= 2, n_wavelengths) on the background's grid")
    env = np.max([smooth(row - background, window, order) for row in stack], axis=0)
    env = smooth(env, 4 * window + 1, order)
    if np.any(env <= 0):
        raise ValueError("the envelope is not positive everywhere: the series never reflects at some wavelength")
    return env


def calibrated_reflectance(wavelength_nm, intensity, background, envelope, n_film=None):
    """A measured spectrum in absolute reflectance: ``(intensity - background) / envelope``
    times :func:`quarter_wave_reflectance`."""
    wl = np.asarray(wavelength_nm, dtype=float)
    return (np.asarray(intensity, dtype=float) - background) / envelope * quarter_wave_reflectance(wl, n_film)


@dataclass(frozen=True)
class ThicknessFit:
    """A thickness fitted to a measured spectrum.

    ``thickness_nm``; ``sigma_nm``: its standard error from the curvature of the residual (the
    noise only: the model's error is not in it); ``gain``, ``tilt``: the instrument factor
    ``gain * (1 + tilt * x)``, *x* running from -1 to 1 across the band; ``rms``: the RMS
    residual in the spectrum's units; ``rms_relative``: that over the measured peak-to-peak;
    ``runner_up_nm`` and ``runner_up_rms``: the best fit at another fringe order (more than a
    quarter of a fringe away), a measure of how unique the answer is; ``n_points``."""

    thickness_nm: float
    sigma_nm: float
    gain: float
    tilt: float
    rms: float
    rms_relative: float
    runner_up_nm: float
    runner_up_rms: float
    n_points: int


def _design(wl, thickness, n_film, tilt):
    r = np.asarray(model_reflectance(wl, thickness, n_film), dtype=float)
    if not tilt:
        return r[:, None]
    x = (2 * wl - (wl[0] + wl[-1])) / (wl[-1] - wl[0])
    return np.column_stack([r, r * x])


def _solve(wl, y, thickness, n_film, tilt, gain=None):
    a = _design(wl, thickness, n_film, tilt)
    if gain is not None:
        coef = np.array([float(gain)] + ([0.0] if tilt else []))
    else:
        coef, *_ = np.linalg.lstsq(a, y, rcond=None)
    resid = y - a @ coef
    return coef, float(np.sqrt(np.mean(resid**2))), resid


def _prepare(wavelength_nm, intensity, background, n_film):
    wl = np.asarray(wavelength_nm, dtype=float)
    y = np.asarray(intensity, dtype=float)
    if wl.ndim != 1 or wl.shape != y.shape or wl.size < _MIN_POINTS:
        raise ValueError(f"wavelength_nm and intensity must be 1-D of one length >= {_MIN_POINTS}")
    if not (np.all(np.isfinite(wl)) and np.all(np.isfinite(y))):
        raise ValueError("wavelength_nm and intensity must be finite")
    if background is not None:
        b = np.asarray(background, dtype=float)
        if b.shape != y.shape:
            raise ValueError(f"background must have the spectrum's shape {y.shape} (got {b.shape})")
        y = y - b
    if n_film is not None and np.ndim(n_film) == 1 and np.shape(n_film) != wl.shape:
        raise ValueError("an n_film array must have one value per wavelength")
    return wl, y


def rms_at_thickness(wavelength_nm, intensity, thickness_nm, background=None, n_film=None, tilt=False, gain=None):
    """``(rms, rms_relative, gain, tilt)`` of the model at a given thickness (gain and tilt fitted,
    as in :func:`fit_thickness`, unless *gain* is given)."""
    wl, y = _prepare(wavelength_nm, intensity, background, n_film)
    coef, rms, _ = _solve(wl, y, float(thickness_nm), n_film, tilt and gain is None, gain)
    tilt = tilt and gain is None
    return rms, rms / float(np.ptp(y)), float(coef[0]), float(coef[1] / coef[0]) if tilt else 0.0


def fit_thickness(wavelength_nm, intensity, thickness_range=(20.0, 6000.0), background=None, n_film=None,
                  tilt=False, step_nm=None, gain=None):
    """Fit the film thickness to a measured reflection spectrum (least squares); a :class:`ThicknessFit`.

    The measured intensity (minus *background*, e.g. the spectrum with no film, if given) is
    modelled as ``gain * (1 + tilt * x) * R(λ; d)``, *R* the exact reflectance
    (:func:`model_reflectance`); *gain* given holds the gain at that value (1 for a spectrum in
    absolute reflectance, :func:`calibrated_reflectance`) and drops the tilt.  The thickness *d* is scanned over *thickness_range* (nm) in
    steps of a tenth of the finest fringe spacing (``step_nm`` to override), the gain and tilt
    solved linearly at each, then the best minimum is refined with
    :func:`scipy.optimize.minimize_scalar` (bounded, within one step either side).
    """
    from scipy.optimize import minimize_scalar

    wl, y = _prepare(wavelength_nm, intensity, background, n_film)
    tilt = tilt and gain is None
    lo, hi = map(float, thickness_range)
    if not 0 <= lo < hi:
        raise ValueError(f"thickness_range must satisfy 0 <= low < high (got {thickness_range})")
    n_mid = float(np.mean(np.real(cauchy_index(wl) if n_film is None else n_film)))
    if step_nm is None:  # the phase 4π n d / λ changes by 2π every λ/(2n): a tenth of the finest
        step_nm = float(wl[0]) / (2 * n_mid) / 10
    grid = np.arange(lo, hi + step_nm, step_nm)
    if tilt:
        rms = np.array([_solve(wl, y, d, n_film, tilt, gain)[1] for d in grid])
    else:  # one linear parameter (or none): the whole scan at once
        r = np.asarray(model_reflectance(wl[None, :], grid[:, None], n_film), dtype=float)
        g = np.full(grid.size, float(gain)) if gain is not None else (r @ y) / np.maximum((r * r).sum(axis=1), 1e-300)
        rms = np.sqrt(np.mean((y[None, :] - g[:, None] * r) ** 2, axis=1))
    best = int(np.argmin(rms))
    a, b = grid[max(best - 1, 0)], grid[min(best + 1, grid.size - 1)]
    res = minimize_scalar(lambda d: _solve(wl, y, d, n_film, tilt, gain)[1], bounds=(a, b), method="bounded",
                          options={"xatol": 1e-3})
    d_best = float(res.x)
    coef, rms_best, resid = _solve(wl, y, d_best, n_film, tilt, gain)
    # runner-up: the best grid point more than a quarter fringe (λ_max / 8n) from the answer
    far = np.abs(grid - d_best) > float(wl[-1]) / (8 * n_mid)
    j = int(np.argmin(np.where(far, rms, np.inf))) if far.any() else best
    # standard error from the Gauss-Newton curvature, all linear parameters profiled out
    eps = max(1e-3, 1e-6 * d_best)
    jac = (_design(wl, d_best + eps, n_film, tilt) - _design(wl, d_best - eps, n_film, tilt)) @ coef / (2 * eps)
    full = jac[:, None] if gain is not None else np.column_stack([jac, _design(wl, d_best, n_film, tilt)])
    dof = max(wl.size - full.shape[1], 1)
    s2 = float(resid @ resid) / dof
    try:
        cov = s2 * np.linalg.inv(full.T @ full)
        sigma = float(np.sqrt(max(cov[0, 0], 0.0)))
    except np.linalg.LinAlgError:
        sigma = math.inf
    return ThicknessFit(thickness_nm=d_best, sigma_nm=sigma, gain=float(coef[0]),
                        tilt=float(coef[1] / coef[0]) if tilt else 0.0, rms=rms_best,
                        rms_relative=rms_best / float(np.ptp(y)), runner_up_nm=float(grid[j]),
                        runner_up_rms=float(rms[j]), n_points=int(wl.size))


@dataclass(frozen=True)
class ThinningFit:
    """:math:`h(t) = h_1[1 + (t - t_1)/\\tau]^{-\\alpha}` fitted to a thickness series (t_1 the
    first time given, h_1 fitted); ``beta = 1 + 1/alpha`` is the exponent of the thinning rate
    :math:`-\\dot h \\propto h^{\\beta}`; ``rms_log``: the RMS of ln(h_measured/h_fit);
    ``beta_interval``: a 95 % interval of β from the profile of the residual (F test),
    ``(nan, nan)`` when β was held fixed."""

    h1_nm: float
    tau: float
    alpha: float
    beta: float
    rms_log: float
    n_points: int
    beta_interval: tuple


def _thinning_residual(params, t, h, alpha=None):
    if alpha is None:
        ln_h1, ln_tau, ln_alpha = params
        alpha = math.exp(min(max(ln_alpha, -30.0), 30.0))
    else:
        ln_h1, ln_tau = params
    tau = math.exp(min(max(ln_tau, -300.0), 300.0))
    return ln_h1 - alpha * np.log1p((t - t[0]) / tau) - np.log(h)


def fit_thinning_law(times, thickness_nm, beta=None, interval=True):
    """Fit the power-law thinning :math:`h_1[1 + (t - t_1)/\\tau]^{-\\alpha}` in log space
    (:func:`scipy.optimize.least_squares`); *beta* given holds the rate exponent at that value
    (α = 1/(β - 1), β > 1); *interval* False skips the profile interval of β.  Returns a
    :class:`ThinningFit`.  The times must increase strictly."""
    from scipy.optimize import least_squares
    from scipy.stats import f as f_dist

    t = np.asarray(times, dtype=float)
    h = np.asarray(thickness_nm, dtype=float)
    if t.ndim != 1 or t.shape != h.shape or t.size < 5:
        raise ValueError("times and thickness_nm must be 1-D of one length >= 5")
    if np.any(np.diff(t) <= 0) or not np.all(np.isfinite(h)) or np.any(h <= 0):
        raise ValueError("times must increase strictly and thicknesses be finite and > 0")
    span = float(t[-1] - t[0])
    if beta is not None and not (math.isfinite(float(beta)) and float(beta) > 1):
        raise ValueError(f"beta must be > 1 (got {beta!r})")
    fixed = None if beta is None else 1.0 / (float(beta) - 1.0)

    def solve(alpha):
        best = None
        for tau0 in span * np.array([1e-3, 1e-2, 1e-1, 1.0, 10.0]):
            x0 = [math.log(h[0]), math.log(tau0)] + ([] if alpha is not None else [math.log(0.5)])
            r = least_squares(_thinning_residual, x0, args=(t, h, alpha), method="lm")
            if best is None or r.cost < best.cost:
                best = r
        return best

    res = solve(fixed)
    alpha = fixed if fixed is not None else math.exp(res.x[2])
    rss = 2 * res.cost
    interval = (math.nan, math.nan)
    if fixed is None and interval:  # profile: the betas whose best fit is within the F-test bound of the optimum
        n, p = t.size, 3
        bound = rss * (1 + f_dist.ppf(0.95, 1, n - p) / (n - p))
        betas = np.linspace(1.05, 12.0, 220)
        prof = np.array([2 * solve(1.0 / (b - 1.0)).cost for b in betas])
        ok = betas[prof <= bound]
        if ok.size:
            interval = (float(ok.min()), float(ok.max()))
    return ThinningFit(h1_nm=math.exp(res.x[0]), tau=math.exp(res.x[1]), alpha=alpha, beta=1.0 + 1.0 / alpha,
                       rms_log=math.sqrt(rss / t.size), n_points=int(t.size), beta_interval=interval)


# ---------------------------------------------------------------- the optifik TTAB series
#: The optifik folders of the one time-resolved TTAB film (Victor Ziapkoff's series; its
#: acquisition indices run on from spectraVictor1 into spectraVictor2/order5 ... order0).
OPTIFIK_SERIES = ("spectraVictor1", "spectraVictor2/order5", "spectraVictor2/order4", "spectraVictor2/order3",
                  "spectraVictor2/order2", "spectraVictor2/order1", "spectraVictor2/order0")
#: The spectrum the optifik authors take as "no film" for the series (their tests' ``void.xy``).
OPTIFIK_VOID = "spectraVictor2/void.xy"
#: Indices from which the envelope is taken: the film is then thinner than the first order
#: that the spectra resolve fully (spectraVictor2, 744 nm and below).
OPTIFIK_ENVELOPE_FROM = 5543
#: The spectra shown in the figure (acquisition indices).
OPTIFIK_EXAMPLES = (5612, 7016, 9217, 14211)


def optifik_series(source_dir):
    """``(wavelength_nm, void, [(time_index, folder, file, intensity)])`` of the TTAB series in an
    optifik ``data/`` folder *source_dir* (duplicates across folders kept once, by index)."""
    source = Path(source_dir)
    wl, void = load_spectrum(source / OPTIFIK_VOID)
    seen, spectra = set(), []
    for folder in OPTIFIK_SERIES:
        for path in sorted((source / folder).glob("T*.xy")):
            index = series_time(path.name)
            if index in seen:
                continue
            seen.add(index)
            w, inten = load_spectrum(path)
            if w.shape != wl.shape or not np.allclose(w, wl):
                raise ValueError(f"{path}: not on the wavelength grid of {OPTIFIK_VOID}")
            spectra.append((index, folder, path.name, inten))
    if not spectra:
        raise ValueError(f"{source}: no spectra of the series {OPTIFIK_SERIES}")
    spectra.sort(key=lambda s: s[0])
    return wl, void, spectra


def optifik_stated(source_dir):
    """The authors' thicknesses of the series: ``{time_index: (folder, file, thickness_nm)}``
    from the ``known_value.yaml`` files (the first folder that states an index wins)."""
    source = Path(source_dir)
    out = {}
    for folder in OPTIFIK_SERIES:
        _, values = read_known_values(source / folder / "known_value.yaml")
        for name, h in values.items():
            out.setdefault(series_time(name), (folder, name, h))
    return out


def compare_optifik(source_dir):
    """Every spectrum of the series against the exact optics: a list of row dicts (the columns of
    ``optifik_comparison.csv``) and the figure's arrays (a dict)."""
    wl, void, spectra = optifik_series(source_dir)
    stated = optifik_stated(source_dir)
    env = lamp_envelope([s[3] for s in spectra if s[0] >= OPTIFIK_ENVELOPE_FROM], void)
    n_cauchy = cauchy_index(wl)
    rows, shown = [], {}
    for index, folder, name, inten in spectra:
        r_meas = smooth(calibrated_reflectance(wl, inten, void, env))
        fit = fit_thickness(wl, r_meas, gain=1.0)
        fit_c = fit_thickness(wl, r_meas, gain=1.0, n_film=n_cauchy)
        free = fit_thickness(wl, r_meas)
        h_stated = stated.get(index, (None, None, math.nan))[2]
        at = rms_at_thickness(wl, r_meas, h_stated, gain=1.0) if math.isfinite(h_stated) else (math.nan,)
        rows.append({"time_index": index, "folder": folder, "file": name, "stated_nm": h_stated,
                     "fit_nm": fit.thickness_nm, "fit_sigma_nm": fit.sigma_nm, "fit_cauchy_nm": fit_c.thickness_nm,
                     "rms_fit": fit.rms, "rms_at_stated": at[0], "runner_up_nm": fit.runner_up_nm,
                     "runner_up_rms": fit.runner_up_rms, "free_gain": free.gain, "free_gain_fit_nm": free.thickness_nm,
                     "peak_reflectance": float(np.max(r_meas)), "in_envelope": int(index >= OPTIFIK_ENVELOPE_FROM)})
        if index in OPTIFIK_EXAMPLES:
            shown[index] = (r_meas, fit.thickness_nm, h_stated)
    grid = np.arange(FIT_BAND_NM[0], FIT_BAND_NM[1] + 1e-9, 2.0)
    arrays = {"wavelength_nm": grid, "examples": np.array(sorted(shown)),
              "quarter_wave_R": quarter_wave_reflectance(grid)}
    for index, (r_meas, h_fit, h_st) in sorted(shown.items()):
        arrays[f"measured_{index}"] = np.interp(grid, wl, r_meas)  # smoothed, resampled to 2 nm
        arrays[f"model_fit_{index}"] = np.asarray(model_reflectance(grid, h_fit), dtype=float)
        arrays[f"model_stated_{index}"] = np.asarray(model_reflectance(grid, h_st), dtype=float)
    return rows, arrays


def thinning_rows(rows, min_nm=30.0):
    """The thinning-law fits of the series (rows of ``optifik_thinning.csv``): the authors'
    thicknesses, and ours where the envelope holds (index >= :data:`OPTIFIK_ENVELOPE_FROM`,
    thicker than *min_nm*, before the film first falls below it), each with β free and β held at
    each value of :data:`THINNING_EXPONENTS` that is > 1."""
    out = []
    stated = [(r["time_index"], r["stated_nm"]) for r in rows if math.isfinite(r["stated_nm"])]
    ours = []
    for r in rows:
        if r["time_index"] < OPTIFIK_ENVELOPE_FROM:
            continue
        if r["fit_nm"] < min_nm:
            break
        ours.append((r["time_index"], r["fit_nm"]))
    for source, pts in (("stated", stated), ("fitted", ours)):
        t, h = np.array(pts, dtype=float).T
        free = fit_thinning_law(t, h)
        out.append({"source": source, "law": "free", "beta": free.beta, "beta_low": free.beta_interval[0],
                    "beta_high": free.beta_interval[1], "rms_log": free.rms_log, "n_points": free.n_points,
                    "t_first": t[0], "t_last": t[-1], "h_first_nm": h[0], "h_last_nm": h[-1]})
        for law, beta in THINNING_EXPONENTS.items():
            if beta <= 1:
                continue
            held = fit_thinning_law(t, h, beta=beta)
            out.append({"source": source, "law": law, "beta": beta, "beta_low": math.nan, "beta_high": math.nan,
                        "rms_log": held.rms_log, "n_points": held.n_points, "t_first": t[0], "t_last": t[-1],
                        "h_first_nm": h[0], "h_last_nm": h[-1]})
    return out


def main(argv=None):
    """``python -m study.measured SOURCE OUT``: SOURCE an optifik ``data/`` folder, OUT the folder
    for ``optifik_stated_thickness.csv``, ``optifik_comparison.csv``, ``optifik_thinning.csv`` and
    ``optifik_figure.npz``."""
    import argparse

    from .results import provenance, write_csv

    ap = argparse.ArgumentParser(description=main.__doc__.splitlines()[0])
    ap.add_argument("source", type=Path)
    ap.add_argument("out", type=Path)
    args = ap.parse_args(argv)
    regen = f"regenerate with: python -m study.measured {args.source} {args.out}"
    cite = ("source: github.com/sciunto-org/optifik (GPL-3.0) at commit ff527391194fc24915d68e2b61987fc1ad21c162, "
            "data/spectraVictor1 and data/spectraVictor2; Ziapkoff, Boulogne, Salonen, Rio, Eur. Phys. J. E 49, 4 "
            "(2026), doi:10.1140/epje/s10189-025-00545-9; see data/measured/README.md")
    stated = optifik_stated(args.source)
    write_csv(args.out / "optifik_stated_thickness.csv",
              [{"series": "TTAB (Ziapkoff)", "file": f"{folder}/{name}", "time_index": index, "stated_nm": h,
                "index_model": "Cauchy 1.324188 + 3102.060378/lambda^2"}
               for index, (folder, name, h) in sorted(stated.items())],
              [provenance("study/measured.py", regen),
               "the authors' thicknesses (nm) transcribed from their known_value.yaml files, not measured here; " + cite],
              float_format=None)
    rows, arrays = compare_optifik(args.source)
    write_csv(args.out / "optifik_comparison.csv", rows,
              [provenance("study/measured.py", regen), cite,
               "fit_nm: exact free-film reflectance (bubbleoptics, water after Daimon & Masumura 2007, normal "
               "incidence) fitted to the spectrum in absolute reflectance (gain 1): (I - void)/envelope x R_quarter-wave, "
               f"envelope = max over the spectra from index {OPTIFIK_ENVELOPE_FROM} of the smoothed I - void; "
               "450-800 nm; rms in reflectance units; free_gain: the gain when it is fitted too"],
              float_format="{:.6g}", na_rep="")
    write_csv(args.out / "optifik_thinning.csv", thinning_rows(rows),
              [provenance("study/measured.py", regen), cite,
               "h(t) = h1 [1 + (t - t1)/tau]^(-1/(beta-1)) fitted in log space; t: acquisition index (unit not stated "
               "by the source); beta_low/high: 95 % profile interval"],
              float_format="{:.6g}", na_rep="")
    np.savez_compressed(args.out / "optifik_figure.npz", **arrays)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

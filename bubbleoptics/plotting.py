"""Small matplotlib helpers for thin-film plots, shared by the notebooks, the demo and figure scripts.

Nothing here runs at import time: matplotlib is imported inside the functions, and no backend is
chosen globally.  The helpers draw on an ``Axes`` you pass in, so they work in a notebook (with
pyplot and the inline backend) as well as in a headless script.  For scripts, :func:`new_figure`
makes a figure bound to the Agg canvas without touching pyplot, so no display is ever needed,
and :func:`save_figure_atomic` writes it to disk all at once.

Units: thickness and wavelength in nm, angles in radians (labels show degrees).
"""

import os
import tempfile

import numpy as np

from .colorimetry import DEFAULT_WAVELENGTHS_NM, XYZ_to_display_sRGB, spectrum_to_XYZ
from .film import film_reflectance, two_beam_reflectance

__all__ = [
    "new_figure",
    "save_figure_atomic",
    "wavelength_line_color",
    "film_strip_colors",
    "plot_reflectance_vs_thickness",
    "plot_color_strip",
]

_MODELS = ("exact", "two_beam")
_SUBPLOTS_KEYS = ("sharex", "sharey", "squeeze", "width_ratios", "height_ratios", "subplot_kw", "gridspec_kw")


def new_figure(nrows=1, ncols=1, **kwargs):
    """A pyplot-free figure on the Agg canvas, and its axes: safe without a display.

    Keyword arguments accepted by ``Figure.subplots`` (``sharex``, ``sharey``, ``squeeze``,
    ``width_ratios``, ``height_ratios``, ``subplot_kw``, ``gridspec_kw``) go there; the rest go
    to ``matplotlib.figure.Figure`` (``figsize``, ``layout``, ``dpi``...).  The layout defaults
    to ``"constrained"``.  The figure is not registered with pyplot, so it never opens a window
    and is freed when dropped.

    Example::

        fig, ax = new_figure(figsize=(6, 3))
        plot_color_strip(ax, np.linspace(0, 2000, 1001))
        save_figure_atomic(fig, "strip.png", dpi=150)
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    sub_kw = {key: kwargs.pop(key) for key in _SUBPLOTS_KEYS if key in kwargs}
    kwargs.setdefault("layout", "constrained")
    fig = Figure(**kwargs)
    FigureCanvasAgg(fig)
    return fig, fig.subplots(nrows, ncols, **sub_kw)


def _umask():
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def save_figure_atomic(fig, path, **savefig_kwargs):
    """Save *fig* to *path* atomically: write a temporary file in the same folder, then rename.

    A reader never sees a half-written image, and an existing file is only replaced once the new
    one is complete.  The format is taken from *path*'s suffix unless ``format=`` is given.
    Returns the absolute path written, as a string.

    Example::

        save_figure_atomic(fig, "out/reflectance.png", dpi=150)
    """
    path = os.path.abspath(os.fspath(path))
    folder, name = os.path.split(path)
    savefig_kwargs.setdefault("format", os.path.splitext(name)[1].lstrip(".").lower() or "png")
    fd, tmp = tempfile.mkstemp(prefix=f".{name}.", suffix=".tmp", dir=folder)
    try:
        with os.fdopen(fd, "wb") as handle:
            fig.savefig(handle, **savefig_kwargs)
        os.chmod(tmp, 0o666 & ~_umask())  # mkstemp makes the file private; give it the usual mode
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise
    return path


def wavelength_line_color(wavelength_nm, width_nm=8.0):
    """An RGB tuple that looks like light of *wavelength_nm*, for colouring plot lines.

    The colour of a narrow Gaussian line (standard deviation *width_nm*) under the equal-energy
    illuminant, clipped to the sRGB gamut, scaled so its largest channel is 0.9 (darker than
    full brightness so yellow-greens stay visible on white).

    Example::

        ax.plot(d, R, color=wavelength_line_color(550.0))
    """
    wl = DEFAULT_WAVELENGTHS_NM
    line = np.exp(-0.5 * ((wl - float(wavelength_nm)) / width_nm) ** 2)
    rgb = XYZ_to_display_sRGB(spectrum_to_XYZ(line, wl, illuminant="E"), illuminant="E")
    top = rgb.max()
    return tuple(float(c) for c in (0.9 * rgb / top if top > 0 else rgb))


def _spectra(model, wavelengths_nm, thickness_nm, theta, n_film, n_outside, n_inside, polarization):
    if model == "exact":
        return film_reflectance(wavelengths_nm, thickness_nm, theta, n_film, n_outside, n_inside, polarization)
    if model == "two_beam":
        if n_inside is not None:
            raise ValueError("the two-beam model is for a free-standing film: n_inside must be None")
        return two_beam_reflectance(wavelengths_nm, thickness_nm, theta, n_film, n_outside, polarization)
    raise ValueError(f"model must be one of {_MODELS} (got {model!r})")


def film_strip_colors(
    thickness_nm,
    theta=0.0,
    *,
    model="exact",
    exposure=1.0,
    n_film=None,
    n_outside=1.0,
    n_inside=None,
    polarization="unpolarized",
    illuminant="D65",
    wavelengths_nm=None,
):
    """Display sRGB of a film seen in reflection, one colour per thickness, and the exposure used.

    With ``model="exact"`` and ``exposure=1`` this is :func:`bubbleoptics.film_color` (the same
    spectrum, XYZ and sRGB steps).  ``model="two_beam"`` uses the coursework's two-beam spectra
    (:func:`bubbleoptics.two_beam_reflectance`) instead.  *exposure* multiplies XYZ before the
    sRGB conversion, like a camera exposure: ``1.0`` is absolute (a perfect reflector is white,
    so a water film, reflecting at most ~8 % at normal incidence, looks dark), ``"auto"`` scales
    the brightest thickness in the strip to Y = 1.

    Parameters
    ----------
    thickness_nm : 1-D array_like, thicknesses in nm.
    theta : float, angle of incidence in radians.
    n_film : None (water, dispersive), a scalar, or an array given per wavelength of
        *wavelengths_nm*.
    wavelengths_nm : spectral grid in nm (default 360-780 nm every 1 nm).

    Returns
    -------
    (rgb, exposure) : ndarray (N, 3) in [0, 1], and the float exposure factor applied.

    Example::

        rgb, k = film_strip_colors(np.linspace(0, 2000, 401), np.deg2rad(60), exposure="auto")
    """
    wl = DEFAULT_WAVELENGTHS_NM if wavelengths_nm is None else np.asarray(wavelengths_nm, dtype=float)
    d = np.asarray(thickness_nm, dtype=float)
    if d.ndim != 1:
        raise ValueError(f"thickness_nm must be 1-D (got shape {d.shape})")
    spectra = _spectra(model, wl, d[:, None], theta, n_film, n_outside, n_inside, polarization)
    XYZ = spectrum_to_XYZ(spectra, wl, illuminant)
    if isinstance(exposure, str):
        if exposure != "auto":
            raise ValueError(f"exposure must be a positive number or 'auto' (got {exposure!r})")
        brightest = float(XYZ[:, 1].max())
        k = 1.0 / brightest if brightest > 0 else 1.0
    else:
        k = float(exposure)
        if not k > 0:
            raise ValueError(f"exposure must be positive (got {exposure!r})")
    return XYZ_to_display_sRGB(k * XYZ, illuminant), k


def plot_reflectance_vs_thickness(
    ax,
    thickness_nm,
    wavelengths_nm=(450.0, 550.0, 650.0),
    theta=0.0,
    *,
    model="exact",
    polarization="unpolarized",
    n_film=None,
    n_outside=1.0,
    n_inside=None,
    label="{wavelength:g} nm",
    **line_kwargs,
):
    """Plot reflectance *R* against film thickness, one line per wavelength, on *ax*.

    Each line has the colour of its wavelength (:func:`wavelength_line_color`) unless ``color``
    is given.  ``model="exact"`` draws the Airy sum (:func:`bubbleoptics.film_reflectance`),
    ``model="two_beam"`` the coursework's two-beam model; draw both on one axes with, e.g.,
    ``linestyle="--"`` for the second.  *label* is a format string with the field
    ``wavelength`` (or None for unlabelled lines).  *n_film* is None (water, dispersive), a
    scalar, or one value per wavelength.  The axis labels are set only if still empty.

    Returns the list of ``Line2D``.

    Example::

        d = np.linspace(0, 2000, 2001)
        plot_reflectance_vs_thickness(ax, d, theta=np.deg2rad(60))
        plot_reflectance_vs_thickness(ax, d, theta=np.deg2rad(60), model="two_beam",
                                      linestyle="--", label=None)
        ax.legend()
    """
    d = np.asarray(thickness_nm, dtype=float)
    wl = np.atleast_1d(np.asarray(wavelengths_nm, dtype=float))
    if n_film is not None and np.ndim(n_film) == 1:
        n_film = np.asarray(n_film)[:, None]
    R = np.broadcast_to(
        _spectra(model, wl[:, None], d[None, :], theta, n_film, n_outside, n_inside, polarization),
        (wl.size, d.size),
    )
    lines = []
    for w, row in zip(wl, R):
        kw = dict(line_kwargs)
        kw.setdefault("color", wavelength_line_color(w))
        kw["label"] = None if label is None else label.format(wavelength=w)
        lines.extend(ax.plot(d, row, **kw))
    if not ax.get_xlabel():
        ax.set_xlabel("film thickness d (nm)")
    if not ax.get_ylabel():
        ax.set_ylabel("reflectance R")
    return lines


def plot_color_strip(
    ax,
    thickness_nm,
    theta=0.0,
    *,
    model="exact",
    exposure="auto",
    label=None,
    rgb=None,
    **optics,
):
    """Draw the interference colours of a film as a horizontal strip over thickness (nm) on *ax*.

    The colours come from :func:`film_strip_colors` (keyword arguments *optics*: ``n_film``,
    ``n_outside``, ``n_inside``, ``polarization``, ``illuminant``, ``wavelengths_nm``), or pass
    precomputed colours as *rgb* (N, 3).  *exposure* defaults to ``"auto"`` (the brightest
    thickness of the strip is white) so the colour sequence is visible; pass ``1.0`` for absolute
    colours, or one number to several strips to compare their brightness.  *thickness_nm* must be
    evenly spaced.  The y axis carries *label* (default: the angle in degrees, and the exposure
    if it is not 1).

    Returns the ``AxesImage``.

    Example::

        d = np.linspace(0, 2000, 2001)
        fig, axes = new_figure(2, 1, figsize=(8, 2), sharex=True)
        for ax, deg in zip(axes, (0, 60)):
            plot_color_strip(ax, d, np.deg2rad(deg))
    """
    d = np.asarray(thickness_nm, dtype=float)
    if d.ndim != 1 or d.size < 2:
        raise ValueError(f"thickness_nm must be 1-D with at least 2 values (got shape {d.shape})")
    step = np.diff(d)
    if not np.allclose(step, step[0], rtol=1e-6, atol=0.0) or step[0] <= 0:
        raise ValueError("thickness_nm must be evenly spaced and increasing")
    k = None
    if rgb is None:
        rgb, k = film_strip_colors(d, theta, model=model, exposure=exposure, **optics)
    rgb = np.clip(np.asarray(rgb, dtype=float), 0.0, 1.0)
    half = step[0] / 2
    image = ax.imshow(
        rgb[None, :, :],
        aspect="auto",
        interpolation="nearest",
        extent=(d[0] - half, d[-1] + half, 0.0, 1.0),
    )
    ax.set_yticks([])
    if label is None:
        label = f"{np.rad2deg(theta):.4g}°"
        if k is not None and not np.isclose(k, 1.0):
            label += f"\n×{k:.3g}"
    ax.set_ylabel(label, rotation=0, ha="right", va="center")
    if not ax.get_xlabel():
        ax.set_xlabel("film thickness d (nm)")
    return image

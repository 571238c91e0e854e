"""The Python driver: render a scene to a linear-RGB array (and, if asked, its per-band
spectral image).  Saving is :mod:`tracer.rendering.output` (``save_image`` is re-exported here)."""

from __future__ import annotations

import sys
import time
from dataclasses import dataclass, field

import numpy as np

from ..kernels.records import RAY_COUNT_KINDS, PackedScene
from ..scene.limits import BYTES_PER_PIXEL, SPECTRAL_METHODS, check_memory, check_settings
from .local import RenderCancelled, render_here, render_in_parts, warm_up
from .output import SpectralImage, save_image
from ..prepare.pack import pack_scene
from ..scene.model import Scene

__all__ = ["render", "render_with_stats", "render_spectral", "resolve_settings", "RenderStats", "save_image",
           "DEFAULTS", "RenderCancelled", "render_in_parts"]

#: Render defaults.  ``threshold``: a child ray whose largest throughput channel is at most
#: this is not traced (1e-3 is below the 8-bit display step of 1/255 after the sRGB curve for
#: mid-tones, so pruned branches cannot change a displayed pixel by more than about one step
#: per pruned branch); 0 traces the coursework's exhaustive tree.  ``spectral_samples``: 16 bands.
#: Both are revisited by the run-time-against-error study (notebooks/04).  ``spectral_method``:
#: ``"auto"`` evaluates films at the band centres unless a film is thick enough to alias there,
#: then averages them over each band (:func:`tracer.prepare.pack.resolve_spectral_method`).
DEFAULTS = dict(width=960, height=960, depth=10, spp=1, threshold=1e-3, spectral_samples=16, seed=0,
                spectral_method="auto")


@dataclass
class RenderStats:
    """What a render did: seconds (compilation excluded), rays by kind, mode."""

    render_seconds: float = 0.0
    rays: dict = field(default_factory=dict)
    spectral: bool = False
    channels: int = 3
    spectral_method: str = ""  # "point" or "band" in spectral mode (what "auto" chose), "" in RGB
    spectral_image: SpectralImage | None = None  # render_with_stats(..., spectral_image=True)


def resolve_settings(scene: Scene, names=None, spectral_image=False, **given) -> dict:
    """The render settings: each one *given* (not None), else the scene's ``[render]`` table
    (``scene.render_defaults``), else :data:`DEFAULTS`; checked against
    :mod:`tracer.scene.limits` (``names`` maps a setting to what the caller calls it in errors, e.g.
    ``--depth``) and for memory (with a per-band image if *spectral_image*), before any work.
    Raises :class:`tracer.scene.limits.LimitError`.

    >>> from tracer import Scene
    >>> resolve_settings(Scene(render_defaults={"spp": 4}), width=64)["spp"]
    4
    >>> resolve_settings(Scene(), depth=10**8)
    Traceback (most recent call last):
    ...
    tracer.scene.limits.LimitError: depth must be an integer from 1 to 1000, got 100000000
    """
    unknown = set(given) - set(DEFAULTS)
    if unknown:
        raise TypeError(f"unknown render setting(s): {', '.join(sorted(unknown))}")
    settings = dict(DEFAULTS)
    # the [render] table's render settings (its display settings, exposure and view, are the
    # outputs': tracer.rendering.output)
    settings.update({k: v for k, v in scene.render_defaults.items() if k in DEFAULTS})
    settings.update({k: v for k, v in given.items() if v is not None})
    settings = check_settings(settings, names)
    if settings["spectral_method"] not in SPECTRAL_METHODS:
        raise ValueError(f"{(names or {}).get('spectral_method', 'spectral_method')} must be one of "
                         f"'auto', 'point', 'band', got {settings['spectral_method']!r}")
    check_memory(settings["width"], settings["height"],
                 BYTES_PER_PIXEL + (8 * settings["spectral_samples"] if spectral_image else 0))
    return settings


def render_with_stats(
    scene: Scene,
    *,
    width=None,
    height=None,
    depth=None,
    spp=None,
    threshold=None,
    spectral_samples=None,
    seed=None,
    spectral=None,
    spectral_method=None,
    progress=None,
    spectral_image=False,
    client=None,
    cancel=None,
):
    """Render and return ``(image, RenderStats)``; see :func:`render`.

    *cancel*: None, a ``threading.Event`` or a callable; while the render runs it is polled
    every few milliseconds, and once it is set (returns true) the kernel stops at its next ray
    and :class:`RenderCancelled` is raised (the scene editor's preview: a newer edit cancels
    the render of the previous one).

    *spectral_image*: also keep each pixel's radiance per wavelength band, returned as
    ``stats.spectral_image`` (a :class:`tracer.rendering.output.SpectralImage`; :func:`render_spectral`).
    """
    s = resolve_settings(scene, width=width, height=height, depth=depth, spp=spp, threshold=threshold,
                         spectral_samples=spectral_samples, seed=seed, spectral_method=spectral_method,
                         spectral_image=spectral_image)
    width, height, depth, spp, threshold = s["width"], s["height"], s["depth"], s["spp"], s["threshold"]
    seed, spectral_samples, spectral_method = s["seed"], s["spectral_samples"], s["spectral_method"]
    spectral = _spectral_transport(spectral, spectral_image)
    packed = pack_scene(scene, spectral_samples=spectral_samples, force_spectral=spectral,
                        spectral_method=spectral_method)
    show = sys.stderr.isatty() if progress is None else progress
    t0 = time.perf_counter()
    if client is None:
        # a first render says that it compiles (unless progress=False)
        warm_up(packed, notice=None if progress is False else (lambda line: print(line, file=sys.stderr, flush=True)),
                helper=True)
        t0 = time.perf_counter()
        image, counts, spectrum = render_here(packed, s, 0, height, spectral_image, show, cancel)
    else:
        if cancel is not None:
            raise ValueError("cancel applies to a local render, not to one on a Dask cluster (client)")
        from .dask import render_tiles

        image, counts, spectrum = render_tiles(client, packed, s, spectral_image, show)
    seconds = time.perf_counter() - t0
    total = counts.sum(axis=0)
    rays = {kind: int(n) for kind, n in zip(RAY_COUNT_KINDS, total)}
    rays["total"] = sum(rays.values())
    method = ("band" if packed.band_mode else "point") if packed.spectral else ""
    stats = RenderStats(seconds, rays, packed.spectral, packed.rgb_basis.shape[0], method)
    if spectral_image:
        stats.spectral_image = _spectral_image(packed, spectrum, image, method)
    return image, stats


def _spectral_transport(spectral, spectral_image):
    """The ``spectral`` argument of :func:`tracer.prepare.pack.pack_scene`: a spectral image needs
    spectral transport, so it forces it (``spectral=None`` becomes True) and refuses False."""
    if not spectral_image:
        return spectral
    if spectral is not None and not spectral:
        raise ValueError("a spectral image needs spectral transport: spectral=False cannot be combined with it")
    return True


def _spectral_image(packed: PackedScene, spectrum, image, method):
    from bubbleoptics.colorimetry import XYZ_TO_LINEAR_SRGB

    to_rgb = np.array(packed.to_rgb)
    return SpectralImage(radiance=spectrum, wavelengths_nm=np.array(packed.wavelengths),
                         band_edges_nm=np.array(packed.band_edges), to_rgb=to_rgb,
                         to_xyz=np.linalg.solve(XYZ_TO_LINEAR_SRGB, to_rgb), rgb=image, spectral_method=method)


def render(scene: Scene, *, width=None, height=None, depth=None, spp=None, threshold=None,
           spectral_samples=None, seed=None, spectral=None, spectral_method=None, progress=None, client=None):
    """Render *scene* to an (height, width, 3) float64 array of linear sRGB radiance.

    The values are radiance, not display values: **they may be greater than 1** (highlights,
    the sky) **and negative**.  A negative channel is a colour outside the sRGB gamut: the
    saturated, nearly spectral colours of thin films (and any spectrum whose XYZ falls outside
    the sRGB triangle) need a negative amount of some primary; the renderer keeps them, so
    that the image converts exactly to XYZ and to wider gamuts.  What the outputs do with them
    (:func:`tracer.save_image`, :mod:`tracer.rendering.output`): ``.png`` clips each channel to [0, 1]
    in linear light before the sRGB curve (``view="clip"``, the default) or compresses them
    into the display gamut with the ACES 2.0 view (``view="aces"``); ``.npy`` and ``.exr`` keep
    them as they are (``.exr`` of halves saturates at +-65504); ``.hdr`` (Radiance RGBE, which
    stores no sign) writes them as 0.  RGB transport (a scene without bubbles, or
    ``spectral=False``) stays within [0, inf) for in-gamut scene colours.

    Every setting left at None takes its value from the scene's ``[render]`` table (a TOML
    file's, ``scene.render_defaults``), else from :data:`DEFAULTS`; all are checked against
    :mod:`tracer.scene.limits` before any work (:func:`resolve_settings`).

    Parameters
    ----------
    width, height : image size in pixels (1-65535, and the image must fit in memory).
    depth : maximum ray generation (1 = camera rays only), as the coursework's "trace depth"
        (1-1000; at most 24 when ``threshold`` is 0).
    spp : samples per pixel (stratified jitter; the pixel centre when 1), 1-65536.
    threshold : pruning threshold on a child ray's throughput (0 = exhaustive tree).
    spectral_samples : wavelength bands for spectral transport (used when the scene has bubbles,
        or when ``spectral=True``), 1-421; ``spectral=False`` forces RGB transport.
    spectral_method : ``"point"`` (films evaluated at the band centres), ``"band"`` (each
        band's film averaged over the band in closed form: no aliasing on thick films), or
        ``"auto"`` (the default: ``"band"`` only when a film is thick enough for point samples to
        alias, :func:`tracer.prepare.pack.resolve_spectral_method`).
    seed : random seed (0 to 2**63 - 1); the image depends on it but not on the thread count.
    progress : show a progress bar (default: when stderr is a terminal).
    client : a :class:`distributed.Client`: render the image as tiles of rows on its Dask
        cluster (:func:`tracer.rendering.dask.render_tiles`); the same image, bit for bit, as here.

    The per-band image behind the RGB one: :func:`render_spectral`.
    """
    return render_with_stats(scene, width=width, height=height, depth=depth, spp=spp, threshold=threshold,
                             spectral_samples=spectral_samples, seed=seed, spectral=spectral,
                             spectral_method=spectral_method, progress=progress, client=client)[0]


def render_spectral(scene: Scene, *, width=None, height=None, depth=None, spp=None, threshold=None,
                    spectral_samples=None, seed=None, spectral=None, spectral_method=None,
                    progress=None, client=None) -> SpectralImage:
    """Render *scene* and return its :class:`~tracer.rendering.output.SpectralImage`: each pixel's mean
    radiance per wavelength band (``radiance``, (height, width, spectral_samples)), the bands'
    centres and edges in nm, the matrices to linear sRGB and CIE XYZ, and the RGB image of the
    same render (``rgb``, what :func:`render` returns for this scene with ``spectral=True``).
    Save it with :func:`tracer.save_spectral` (``.npz``).

    The bands are those of the spectral transport, so a spectral image is always spectral: for
    a scene without bubbles (which :func:`render` traces in RGB) this renders with
    ``spectral=True``, and its ``rgb`` is that render's, which differs from the RGB-transport
    image of :func:`render` (the scene's RGB colours enter through a spectral basis:
    :func:`tracer.prepare.pack.channel_setup`).  ``spectral=False`` is refused with a
    :class:`ValueError`.  Other parameters as in :func:`render`.  Memory: the cube is
    height x width x spectral_samples float64 (16 bands at 960x960: 118 MB).  The first spectral
    image after installing compiles the integrator's per-band variant into numba's cache (about
    as long as the first render's compilation).

    >>> import tracer
    >>> cube = tracer.render_spectral(tracer.default_scene(), width=8, height=6, progress=False)
    >>> cube.radiance.shape, cube.wavelengths_nm.shape, cube.band_edges_nm[[0, -1]].tolist()
    ((6, 8, 16), (16,), [360.0, 780.0])
    """
    _, stats = render_with_stats(scene, width=width, height=height, depth=depth, spp=spp, threshold=threshold,
                                 spectral_samples=spectral_samples, seed=seed, spectral=spectral,
                                 spectral_method=spectral_method, progress=progress, spectral_image=True,
                                 client=client)
    return stats.spectral_image

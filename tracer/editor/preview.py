"""The editor's preview: a progressive, cancellable render in a background thread, and the film
seen at a picked pixel.

:class:`PreviewRenderer` renders every request first at a sixth of the width and height
(1/36 of the pixels), then at full resolution, handing each stage to a callback; a newer request
cancels the render in progress (the kernel's ``stop``: :func:`tracer.rendering.local.render_in_parts`) so
that the person always waits for the latest edit only.  The renders of every editor in the
process take turns in one thread (:mod:`tracer.editor.scheduler`).

:func:`film_at_pixel` is what the picked pixel shows beside the image: it casts the pixel's
camera ray (the ray through the pixel's centre, as the renderer's first sample) against the
scene's bubbles and, at the *first bubble it hits*, evaluates that bubble's film thickness there
(:func:`tracer.kernels.thickness.film_thickness`, the renderer's own profile) and the reflectance spectrum of
its front film at that angle of incidence (:func:`bubbleoptics.film_reflectance`, 360-780 nm every 1 nm), with the
colour of that spectrum under D65 (:func:`bubbleoptics.film_color`). It ignores what lies in
front of the bubble (a sphere, a mesh) and the light that reaches it: it shows the film, not the
pixel's radiance.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from ..rendering.output import display_codes
from ..prepare.pack import pack_scene
from ..rendering.api import resolve_settings
from ..rendering.local import PARALLEL_LOCK, RenderCancelled, render_in_parts
from .scheduler import BACKGROUND, INTERACTIVE, STEP_SECONDS
from .scheduler import scheduler as default_scheduler

__all__ = ["PreviewRenderer", "PreviewImage", "film_at_pixel", "PREVIEW_DIVISOR"]

#: The first stage's image is the full one's width and height divided by this (160 x 160 of a
#: 960 x 960 image, 1/36 of its pixels: about a third of the page's 560-pixel view, refined
#: within a second; docs/editor.md gives the latency this buys).
PREVIEW_DIVISOR = 6


@dataclass
class PreviewImage:
    """One stage of a preview: 8-bit display codes (H, W, 3), ``stage`` "preview" or "full",
    the request's ``version``, the render's seconds, and the full stage's ``linear`` image."""

    codes: np.ndarray
    stage: str
    version: int
    seconds: float
    linear: np.ndarray | None = None


class PreviewRenderer:
    """Renders the latest requested scene progressively, as jobs of the process's
    :class:`~tracer.editor.scheduler.RenderScheduler` (shared fairly with every other editor).

    ``request(scene, settings, exposure, version)``: *settings* are :func:`tracer.render`
    keyword arguments (width and height are the full stage's).  The scene is packed once for
    both stages.  ``on_image(PreviewImage)`` is called from the scheduler's thread for each
    finished stage of the latest request; a stage of a request that was overtaken is never
    delivered.  ``on_error(request_version, exception)`` receives a render's failure.
    """

    def __init__(self, on_image, on_error=None, divisor=PREVIEW_DIVISOR, scheduler=None):
        self.on_image = on_image
        self.on_error = on_error
        self.divisor = divisor
        self._scheduler = scheduler or default_scheduler()
        self._closed = False

    def request(self, scene, settings, exposure=0.0, version=0):
        """Render *scene* (cancelling any render of this preview in progress)."""
        if self._closed:
            return
        job = (scene, dict(settings), float(exposure), version)
        on_error = None if self.on_error is None else (lambda exc: self.on_error(version, exc))
        self._scheduler.submit(self, "render", lambda cancel: self._stages(job, cancel), on_error)

    def pick(self, scene, col, row, width, height, on_pick):
        """The film at a picked pixel (:func:`film_at_pixel`), as an interactive job:
        ``on_pick(FilmSample or None)`` from the scheduler's thread."""
        if self._closed:
            return

        def steps(cancel):
            sample = film_at_pixel(scene, col, row, width, height) if scene.bubbles else None
            if not cancel.is_set():
                on_pick(sample)
            return
            yield  # a generator of one step

        self._scheduler.submit(self, "pick", steps)

    def close(self):
        """Cancel this preview's renders (their kernels stop at their next ray)."""
        self._closed = True
        self._scheduler.cancel(self)

    @property
    def busy(self) -> bool:
        return not self._scheduler.idle(self, timeout=0)

    def idle(self, timeout=None) -> bool:
        """Wait until no request of this preview is pending or rendering (True), or *timeout*
        seconds (False)."""
        return self._scheduler.idle(self, timeout)

    def _stages(self, job, cancel):
        """The job's steps: settings and packing, the preview stage in one step, the full
        stage in parts of about STEP_SECONDS."""
        scene, settings, exposure, version = job
        s = resolve_settings(scene, **settings)
        packed = pack_scene(scene, spectral_samples=s["spectral_samples"], spectral_method=s["spectral_method"])
        w, h = s["width"], s["height"]
        d = self.divisor
        stages = [("preview", max(1, w // d), max(1, h // d))] if d > 1 and min(w, h) >= d else []
        stages.append(("full", w, h))
        for stage, sw, sh in stages:
            yield INTERACTIVE if stage == "preview" else BACKGROUND
            busy = 0.0  # this stage's own time, not the turns of other editors' jobs
            t0 = time.perf_counter()
            parts = render_in_parts(packed, {**s, "width": sw, "height": sh}, stop=cancel,
                                    call_seconds=STEP_SECONDS if stage == "full" else 1e9)
            while True:
                try:
                    next(parts)
                except StopIteration as finished:
                    image = finished.value[0]
                    break
                if stage == "full":
                    busy += time.perf_counter() - t0
                    yield BACKGROUND
                    t0 = time.perf_counter()
            codes = display_codes(image, exposure=exposure)
            busy += time.perf_counter() - t0
            if cancel.is_set():
                raise RenderCancelled("overtaken")
            self.on_image(PreviewImage(codes, stage, version, busy, image if stage == "full" else None))


# ------------------------------------------------------------------------------------------
# the picked pixel
# ------------------------------------------------------------------------------------------
@dataclass
class FilmSample:
    """The film at a picked pixel (:func:`film_at_pixel`)."""

    bubble: str
    thickness_nm: float
    angle_deg: float
    wavelengths_nm: np.ndarray
    reflectance: np.ndarray
    srgb: tuple  # display sRGB in [0, 1] of the reflectance spectrum under D65


def _camera_ray(scene, px, py, width, height):
    from ..prepare.pack import camera_record
    from ..kernels.sampling import camera_ray

    cam = camera_record(scene.camera)[0]
    return np.array(cam["origin"], float), np.array(camera_ray(cam, px, py, width, height))


def film_at_pixel(scene, col, row, width, height):
    """The film of the first bubble that the camera ray through the centre of pixel
    (*col*, *row*) of a *width* x *height* image meets (see the module docstring), as a
    :class:`FilmSample`; None when the ray meets no bubble.  It waits for a render running in
    another thread (:data:`tracer.rendering.local.PARALLEL_LOCK`)."""
    if not scene.bubbles:
        return None
    with PARALLEL_LOCK:  # packing and the spectra run parallel kernels (see tracer.rendering.local.PARALLEL_LOCK)
        return _film_sample(scene, col, row, width, height)


def _film_sample(scene, col, row, width, height):
    from bubbleoptics import film_color, film_reflectance
    from bubbleoptics.colorimetry import DEFAULT_WAVELENGTHS_NM

    from ..kernels.thickness import film_thickness
    from ..kernels.geometry import intersect_sphere
    from ..prepare.pack import film_index, pack_scene

    o, d = _camera_ray(scene, col + 0.5, row + 0.5, width, height)
    best, best_t = None, math.inf
    for i, b in enumerate(scene.bubbles):
        t, _ = intersect_sphere(o, d, np.asarray(b.center, float), float(b.radius), 0.0, math.inf)
        if t < best_t:
            best, best_t = i, t
    if best is None:
        return None
    b = scene.bubbles[best]
    p = o + best_t * d
    n = (p - np.asarray(b.center, float)) / float(b.radius)
    n /= np.linalg.norm(n)
    packed = pack_scene(_only_bubbles(scene, [b]), spectral_samples=1)
    thickness = float(film_thickness(packed.films[0], packed.film_maps, n))
    cos_i = min(1.0, abs(float(np.dot(d, n))))
    theta = math.acos(cos_i)
    wl = DEFAULT_WAVELENGTHS_NM  # 360-780 nm every 1 nm, film_color's grid
    n_film = None if b.n_film == "water" else film_index(b, wl)
    R = np.asarray(film_reflectance(wl, thickness, theta, n_film), float)
    srgb = np.asarray(film_color(thickness, theta, n_film), float)
    return FilmSample(b.name, thickness, math.degrees(theta), wl, R, tuple(srgb.tolist()))


def _only_bubbles(scene, bubbles):
    """*scene* with only *bubbles* (and nothing else to pack)."""
    import dataclasses

    return dataclasses.replace(scene, spheres=[], meshes=[], bubbles=list(bubbles))

"""The editor's preview: a progressive, cancellable render in a background thread, and the film
seen at a picked pixel.

:class:`PreviewRenderer` renders every request first at a quarter of the width and height
(1/16 of the pixels), then at full resolution, handing each stage to a callback; a newer request
cancels the render in progress (:func:`tracer.render.render_with_stats`'s ``cancel``) so that
the person always waits for the latest edit only.

:func:`film_at_pixel` is what the picked pixel shows beside the image: it casts the pixel's
camera ray (the ray through the pixel's centre, as the renderer's first sample) against the
scene's bubbles and, at the *first bubble it hits*, evaluates that bubble's film thickness there
(:func:`tracer.films.film_thickness`, the renderer's own profile) and the reflectance spectrum of
its front film at that angle of incidence (:func:`bubbleoptics.film_reflectance`, 360-780 nm every 1 nm), with the
colour of that spectrum under D65 (:func:`bubbleoptics.film_color`). It ignores what lies in
front of the bubble (a sphere, a mesh) and the light that reaches it: it shows the film, not the
pixel's radiance.
"""

from __future__ import annotations

import math
import threading
import time
from dataclasses import dataclass

import numpy as np

from ..output import display_codes
from ..render import PARALLEL_LOCK, RenderCancelled, render_with_stats

__all__ = ["PreviewRenderer", "PreviewImage", "film_at_pixel", "PREVIEW_DIVISOR"]

#: The first stage's image is the full one's width and height divided by this.
PREVIEW_DIVISOR = 4


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
    """Renders the latest requested scene progressively in one background thread.

    ``request(scene, settings, exposure, version)``: *settings* are :func:`tracer.render`
    keyword arguments (width and height are the full stage's). ``on_image(PreviewImage)`` is
    called from the worker thread for each finished stage of the latest request; a stage of a
    request that was overtaken is never delivered.  ``on_error(request_version, exception)``
    receives a render's failure.
    """

    def __init__(self, on_image, on_error=None, divisor=PREVIEW_DIVISOR):
        self.on_image = on_image
        self.on_error = on_error
        self.divisor = divisor
        self._lock = threading.Condition()
        self._job = None
        self._cancel = threading.Event()
        self._closed = False
        self.busy = False
        self._thread = threading.Thread(target=self._run, name="tracer-editor-preview", daemon=True)
        self._thread.start()

    def request(self, scene, settings, exposure=0.0, version=0):
        """Render *scene* (cancelling any render in progress)."""
        with self._lock:
            self._job = (scene, dict(settings), float(exposure), version)
            self._cancel.set()
            self._lock.notify()

    def close(self):
        with self._lock:
            self._closed = True
            self._cancel.set()
            self._lock.notify()

    def idle(self, timeout=None) -> bool:
        """Wait until no request is pending or rendering (True), or *timeout* seconds (False)."""
        end = None if timeout is None else time.monotonic() + timeout
        with self._lock:
            while self._job is not None or self.busy:
                left = None if end is None else end - time.monotonic()
                if left is not None and left <= 0:
                    return False
                self._lock.wait(left if left is not None else 0.05)
        return True

    def _run(self):
        while True:
            with self._lock:
                while self._job is None and not self._closed:
                    self._lock.wait()
                if self._closed:
                    return
                job, self._job = self._job, None
                self._cancel = cancel = threading.Event()
                self.busy = True
            try:
                self._render(job, cancel)
            except RenderCancelled:
                pass
            except Exception as exc:  # reported, and the thread lives on for the next request
                if self.on_error is not None:
                    self.on_error(job[3], exc)
            finally:
                with self._lock:
                    self.busy = False
                    self._lock.notify_all()

    def _render(self, job, cancel):
        scene, settings, exposure, version = job
        w, h = settings["width"], settings["height"]
        d = self.divisor
        stages = [("preview", max(1, w // d), max(1, h // d))] if d > 1 and min(w, h) >= d else []
        stages.append(("full", w, h))
        for stage, sw, sh in stages:
            t0 = time.perf_counter()
            # the whole stage under the lock: packing and the display codes run parallel kernels
            # too, which must not meet another thread's (another session's render, a picked pixel)
            with PARALLEL_LOCK:
                image, _ = render_with_stats(scene, **{**settings, "width": sw, "height": sh}, progress=False,
                                             cancel=cancel)
                codes = display_codes(image, exposure=exposure)
            if cancel.is_set():
                raise RenderCancelled("overtaken")
            self.on_image(PreviewImage(codes, stage, version, time.perf_counter() - t0,
                                       image if stage == "full" else None))


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
    from ..pack import _camera_record
    from ..sampling import camera_ray

    cam = _camera_record(scene.camera)[0]
    return np.array(cam["origin"], float), np.array(camera_ray(cam, px, py, width, height))


def film_at_pixel(scene, col, row, width, height):
    """The film of the first bubble that the camera ray through the centre of pixel
    (*col*, *row*) of a *width* x *height* image meets (see the module docstring), as a
    :class:`FilmSample`; None when the ray meets no bubble.  It waits for a render running in
    another thread (:data:`tracer.render.PARALLEL_LOCK`)."""
    if not scene.bubbles:
        return None
    with PARALLEL_LOCK:  # packing and the spectra run parallel kernels (see tracer.render.PARALLEL_LOCK)
        return _film_at_pixel(scene, col, row, width, height)


def _film_at_pixel(scene, col, row, width, height):
    from bubbleoptics import film_color, film_reflectance
    from bubbleoptics.colorimetry import DEFAULT_WAVELENGTHS_NM

    from ..films import film_thickness
    from ..geometry import intersect_sphere
    from ..pack import _film_index, pack_scene

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
    n_film = None if b.n_film == "water" else _film_index(b, wl)
    R = np.asarray(film_reflectance(wl, thickness, theta, n_film), float)
    srgb = np.asarray(film_color(thickness, theta, n_film), float)
    return FilmSample(b.name, thickness, math.degrees(theta), wl, R, tuple(srgb.tolist()))


def _only_bubbles(scene, bubbles):
    """*scene* with only *bubbles* (and nothing else to pack)."""
    import dataclasses

    return dataclasses.replace(scene, spheres=[], meshes=[], bubbles=list(bubbles))

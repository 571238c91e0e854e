"""Render a movie: frames of a :class:`~tracer.movie.timeline.Timeline`, cached, then assembled.

:func:`render_movie` renders each frame of the timeline that its cache does not hold yet,
here (one process, all numba threads) or on a Dask cluster (``client``, or ``workers=N`` for a
:class:`distributed.LocalCluster`, or ``scheduler=ADDRESS``), and writes the movie:

* ``OUT.mp4``: H.264 in yuv420p (``imageio-ffmpeg``; width and height must be even);
* ``OUT.gif``: an animated GIF (imageio's Pillow writer, looping);
* any other ``OUT``: a folder of lossless frames ``0000.png``, ``0001.png``, ...

Frames are cached as PNG files in the folder ``OUT.cache`` next to ``OUT``, each named by the
hash of its description (:meth:`~tracer.movie.frames.Frame.key`: the scene as the frame shows
it, the render settings, the film time, the bit depth), and written atomically; a movie
interrupted (Ctrl-C, a lost worker) and run again with the same arguments renders only the
frames the cache lacks. ``OUT`` itself is written at the end, atomically (a temporary file or
folder beside it, then renamed). Everything a movie needs is checked before any work: a bad
output, commands or setting writes nothing at all.

A frame's image is :func:`render_frame_png` of its description: the same function serially and
on every worker, a module-level function (so that workers import it and load the numba kernels
from the on-disk cache, :func:`tracer.rendering.dask.worker_numba_cache_stats`), and the image does not depend on the
thread count, so distributed frames are bit for bit the serial ones.
"""

from __future__ import annotations

import contextlib
import os
import re
import shutil
import sys
import tempfile
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from bubbleoptics.atomic import write_atomically

from ..rendering.dask import check_cluster_options, cluster_client
from .frames import Frame
from .timeline import Timeline
from ..rendering.api import resolve_settings, save_image
from ..scene.model import Scene

__all__ = ["render_movie", "render_frame_files", "render_frame_png", "check_movie_output", "check_spectral_output",
           "movie_cache_folder", "MovieResult", "DEFAULT_FPS"]

DEFAULT_FPS = 24
#: A folder movie's frame files (and what an existing OUT folder may hold to be replaced).
_FRAME_FILE = re.compile(r"\d{4,}\.png")
#: A spectral folder's frame files.
_SPECTRAL_FILE = re.compile(r"\d{4,}\.npz")
#: Suffixes that mean a file, not a folder of frames: refused rather than made into a folder.
_NOT_A_MOVIE = {".png", ".npy", ".jpg", ".jpeg", ".tif", ".tiff", ".webp", ".avi", ".mov", ".mkv", ".webm", ".txt",
                ".toml"}


@dataclass
class MovieResult:
    """What :func:`render_movie` did: the movie's path, its frame count, how many frames were
    rendered now (the rest came from the cache), the cache folder, and seconds spent rendering
    and encoding."""

    path: Path
    frames: int
    rendered: int
    cache: Path
    render_seconds: float = 0.0
    encode_seconds: float = 0.0


# ------------------------------------------------------------------------------------------
# output
# ------------------------------------------------------------------------------------------
def _kind(out: Path):
    suffix = out.suffix.lower()
    return {".mp4": "mp4", ".gif": "gif"}.get(suffix, "folder")


def movie_cache_folder(out) -> Path:
    """The frame cache of the movie *out*: the folder ``OUT.cache`` beside it."""
    out = Path(out)
    return out.with_name(out.name + ".cache")


def check_movie_output(out) -> tuple[Path, str]:
    """``(Path, kind)`` for the movie output *out* (kind ``"mp4"``, ``"gif"`` or ``"folder"``),
    checked before any work: its folder exists and is writable, an ``.mp4``/``.gif`` is not a
    folder, and a folder movie is not a file nor a folder holding anything but frames
    ``NNNN.png`` (a previous movie, which is replaced). ValueError otherwise."""
    out = Path(out)
    kind = _kind(out)
    folder = out.parent
    if not out.name or out.name in (".", ".."):
        raise ValueError(f"{out}: give the movie a name (OUT.mp4, OUT.gif or a folder name)")
    if kind == "folder" and out.suffix.lower() in _NOT_A_MOVIE:
        raise ValueError(f"{out}: a movie is written as .mp4, .gif or a folder of PNG frames (a name without "
                         f"{out.suffix})")
    if not folder.is_dir():
        raise ValueError(f"{out}: folder {folder} does not exist")
    if kind != "folder" and out.is_dir():
        raise ValueError(f"{out}: is a folder, not a file name")
    if kind == "folder":
        _check_frame_folder(out, _FRAME_FILE, "a movie not ending in .mp4 or .gif is a folder of PNG frames")
    cache = movie_cache_folder(out)
    if cache.exists() and not cache.is_dir():
        raise ValueError(f"{cache}: the frame cache's name is taken by a file")
    try:
        with tempfile.NamedTemporaryFile(dir=folder, prefix=f".{out.name}.", suffix=".probe"):
            pass
    except OSError as err:
        raise ValueError(f"{out}: cannot write in folder {folder} ({err.strerror or err})") from None
    return out, kind


def _check_frame_folder(out: Path, pattern, what):
    """*out* may become a folder of frame files matching *pattern* (``NNNN`` and a suffix): it
    is not a file, and if it exists it holds only such frames (a previous movie's, which are
    replaced)."""
    if out.exists() and not out.is_dir():
        raise ValueError(f"{out}: is a file; {what}")
    if out.is_dir():
        others = sorted(p.name for p in out.iterdir() if not pattern.fullmatch(p.name))
        if others:
            suffix = pattern.pattern.rsplit(".", 1)[-1]
            raise ValueError(f"{out}: the folder exists and holds other files than frames NNNN.{suffix} "
                             f"({', '.join(others[:3])}{', ...' if len(others) > 3 else ''}); give a new folder name")


def check_spectral_output(spectral_out, out) -> Path:
    """The folder *spectral_out* that receives a movie's per-frame spectral images
    ``0000.npz``, ... (:func:`tracer.save_spectral`), checked before any work like a folder
    movie (:func:`check_movie_output`), and neither the movie *out* nor its cache."""
    spectral_out = Path(spectral_out)
    if not spectral_out.name or spectral_out.name in (".", ".."):
        raise ValueError(f"{spectral_out}: give the spectral images' folder a name")
    if spectral_out.suffix.lower() in _NOT_A_MOVIE | {".npz", ".mp4", ".gif"}:
        raise ValueError(f"{spectral_out}: a movie's spectral images go into a folder of frames NNNN.npz "
                         f"(a name without {spectral_out.suffix})")
    if not spectral_out.parent.is_dir():
        raise ValueError(f"{spectral_out}: folder {spectral_out.parent} does not exist")
    if spectral_out.resolve() in (Path(out).resolve(), movie_cache_folder(out).resolve()):
        raise ValueError(f"{spectral_out}: the spectral images need a folder of their own (not the movie or "
                         "its cache)")
    _check_frame_folder(spectral_out, _SPECTRAL_FILE, "a movie's spectral images go into a folder")
    return spectral_out


# ------------------------------------------------------------------------------------------
# one frame (the task)
# ------------------------------------------------------------------------------------------
def render_frame_files(frame: Frame, bits: int = 8) -> tuple[bytes, bytes | None]:
    """The PNG file (bytes) of *frame*, and its spectral image's ``.npz`` file (bytes) if it is
    spectral (else None): :func:`tracer.render` of its scene with its settings, saved by
    :func:`tracer.save_image` (and :func:`tracer.save_spectral`) with its display settings,
    exactly as ``tracer image`` saves them.

    The task every worker runs: a module-level function, so a worker imports ``tracer`` (and
    loads its kernels from numba's cache) rather than receiving a pickled copy.
    """
    from ..rendering.output import save_spectral
    from ..rendering.api import render_with_stats

    image, stats = render_with_stats(frame.scene, **frame.settings, progress=False, spectral_image=frame.spectral)
    with tempfile.TemporaryDirectory(prefix="tracer-frame-") as tmp:
        png, npz = Path(tmp) / "frame.png", Path(tmp) / "frame.npz"
        save_image(image, png, bits=bits, **frame.display)
        if frame.spectral:
            save_spectral(stats.spectral_image, npz)
        return png.read_bytes(), (npz.read_bytes() if frame.spectral else None)


def render_frame_png(frame: Frame, bits: int = 8) -> bytes:
    """The PNG file (bytes) of *frame* (:func:`render_frame_files`)."""
    return render_frame_files(frame, bits)[0]


# ------------------------------------------------------------------------------------------
# rendering the frames as they are planned
# ------------------------------------------------------------------------------------------
#: Frames in flight on a cluster per worker (at least 8): enough to keep every worker busy while
#: results come back, few enough that the frames waiting hold little memory.
FRAMES_IN_FLIGHT_PER_WORKER = 4


class _FrameRenderer:
    """Renders the frames :func:`render_movie` hands it, one at a time, into the cache: here, as
    each arrives, or on *client*'s cluster with at most a window of frames in flight (so a
    million-frame movie is neither planned nor submitted all at once)."""

    def __init__(self, client, cache: Path, bits: int, bar):
        self.client, self.cache, self.bits, self.bar = client, cache, bits, bar
        self.in_flight = {}  # Dask key -> frame key
        self.completed = None
        if client is not None:
            from distributed import as_completed

            self.completed = as_completed(with_results=True)
            workers = len(client.scheduler_info().get("workers", {}))
            self.window = max(8, FRAMES_IN_FLIGHT_PER_WORKER * workers)

    def pending(self, key) -> bool:
        return f"tracer-frame-{key}" in self.in_flight

    def store(self, key, files):
        png, npz = files
        if npz is not None:  # first: a frame counts as cached once its .png is there
            write_atomically(self.cache / f"{key}.npz", lambda tmp: Path(tmp).write_bytes(npz))
        write_atomically(self.cache / f"{key}.png", lambda tmp: Path(tmp).write_bytes(png))
        if self.bar is not None:
            self.bar.update(1)

    def submit(self, frame, key):
        if self.client is None:
            self.store(key, render_frame_files(frame, self.bits))
            return
        future = self.client.submit(render_frame_files, frame, self.bits, key=f"tracer-frame-{key}", retries=3,
                                    pure=False)
        self.in_flight[future.key] = key
        self.completed.add(future)
        while len(self.in_flight) >= self.window:
            self._collect_one()

    def _collect_one(self):
        future, files = next(self.completed)
        self.store(self.in_flight.pop(future.key), files)

    def finish(self):
        while self.in_flight:
            self._collect_one()

    def cancel(self):
        if self.client is not None and self.completed is not None:
            self.client.cancel(list(self.completed.futures))


class _CachePaths(Sequence):
    """The cache files of a movie's frames in order, made from their keys (32 bytes each) when
    asked for: a movie of a million frames does not hold a million paths."""

    def __init__(self, cache: Path, digests, suffix=".png"):
        self.cache, self.digests, self.suffix = cache, digests, suffix

    def __len__(self):
        return len(self.digests)

    def __getitem__(self, i):
        if isinstance(i, slice):
            return [self[j] for j in range(*i.indices(len(self)))]
        return self.cache / f"{self.digests[i].tobytes().hex()}{self.suffix}"


# ------------------------------------------------------------------------------------------
# assembling
# ------------------------------------------------------------------------------------------
def _read_png(path):
    import imageio.v3 as iio

    return iio.imread(path)


def _write_mp4(out: Path, paths, fps):
    import imageio_ffmpeg

    first = _read_png(paths[0])
    h, w = first.shape[:2]

    def write(tmp):
        writer = imageio_ffmpeg.write_frames(tmp, (w, h), fps=fps, codec="libx264", pix_fmt_in="rgb24",
                                             pix_fmt_out="yuv420p", macro_block_size=1, quality=None,
                                             output_params=["-f", "mp4", "-crf", "18"], ffmpeg_log_level="error")
        writer.send(None)
        try:
            for p in paths:
                writer.send(_read_png(p)[..., :3].tobytes())
        finally:
            writer.close()

    write_atomically(out, write)


def _write_gif(out: Path, paths, fps):
    import imageio.v3 as iio
    import numpy as np

    frames = np.stack([_read_png(p)[..., :3] for p in paths])
    write_atomically(out, lambda tmp: iio.imwrite(tmp, frames, extension=".gif", duration=1000.0 / fps, loop=0))


def _write_folder(out: Path, paths, suffix=".png"):
    digits = max(4, len(str(len(paths) - 1)))
    tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.", suffix=".tmp", dir=out.parent))
    old = None
    try:
        for i, p in enumerate(paths):
            shutil.copyfile(p, tmp / f"{i:0{digits}d}{suffix}")
        os.chmod(tmp, 0o777 & ~_umask())
        if out.is_dir():  # a previous movie (check_movie_output allowed it): swap it out
            old = Path(tempfile.mkdtemp(prefix=f".{out.name}.", suffix=".old", dir=out.parent))
            os.replace(out, old / "movie")
        os.replace(tmp, out)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        if old is not None and (old / "movie").is_dir() and not out.exists():
            os.replace(old / "movie", out)
        raise
    finally:
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)


def _umask():
    m = os.umask(0)
    os.umask(m)
    return m


# ------------------------------------------------------------------------------------------
# the movie
# ------------------------------------------------------------------------------------------
def render_movie(scene, commands, out, *, client=None, workers=None, scheduler=None, fps=DEFAULT_FPS, bits=8,
                 exposure=None, view=None, spectral_out=None, progress=None, names=None,
                 **render_options) -> MovieResult:
    """Render the movie of *commands* applied to *scene* into *out*; returns a :class:`MovieResult`.

    Parameters
    ----------
    scene : a :class:`~tracer.scene.Scene`, or a scene file's path.
    commands : a :class:`~tracer.movie.timeline.Timeline` (built on *scene*), or a commands
        file's path (``docs/movies.md``).
    out : ``NAME.mp4`` (H.264, yuv420p: even width and height), ``NAME.gif``, or a folder name
        (frames ``0000.png``...). Frames are cached in ``OUT.cache`` (:func:`movie_cache_folder`).
    client : a :class:`distributed.Client` to render the frames on; or *workers* (a
        LocalCluster of that many one-thread processes, started and stopped here) or
        *scheduler* (the address of a running scheduler); default: here, serially.
    fps : frames per second of an ``.mp4`` or ``.gif`` (1-1000).
    bits : PNG bit depth of the frames (16 only for a folder of frames).
    exposure, view : the frames' display settings, as :func:`tracer.save_image`'s (stops, and
        ``"clip"`` or ``"aces"``); None: the scene's ``[render]`` table, else 0 and ``"clip"``.
    spectral_out : a folder that receives each frame's spectral image ``0000.npz``, ...
        (:func:`tracer.save_spectral`); this renders the frames with spectral transport, as
        ``tracer image --spectral-out`` does.
    progress : a progress bar over frames (default: when stderr is a terminal).
    names : what the caller calls each render setting in errors (the command line's options).
    render_options : :func:`tracer.render`'s settings (width, height, depth, spp, threshold,
        spectral_samples, seed, spectral_method), else the scene's ``[render]`` table, else
        :data:`tracer.DEFAULTS`.

    Everything is checked before any work (ValueError, or a :class:`~tracer.scene.errors.SceneError`
    ``FILE:LINE: ...`` for the scene and the commands), and nothing is written then.  Frames
    are then made, keyed and rendered one at a time (:meth:`Timeline.iter_frames
    <tracer.movie.timeline.Timeline.iter_frames>`; on a cluster a window of them in flight), so
    the first frame of the longest movie renders at once and memory stays flat; the cluster is
    reached, and the cache folder made, at the first frame the cache lacks.
    """
    out, kind = check_movie_output(out)
    if not isinstance(scene, Scene):
        from ..scene.load import load_scene

        scene = load_scene(scene)
    timeline = commands if isinstance(commands, Timeline) else Timeline.from_file(scene, commands)
    settings = resolve_settings(scene, names=names, **render_options)
    if isinstance(fps, bool) or not isinstance(fps, (int, float)) or not 1 <= fps <= 1000:
        raise ValueError(f"{(names or {}).get('fps', 'fps')} must be a number from 1 to 1000, got {fps!r}")
    if bits not in (8, 16):
        raise ValueError(f"bits must be 8 or 16, got {bits!r}")
    if bits == 16 and kind != "folder":
        raise ValueError(f"{out}: 16-bit frames are for a folder of PNG frames; an .{kind} holds 8-bit colour")
    if kind == "mp4" and (settings["width"] % 2 or settings["height"] % 2):
        w, h = (names or {}).get("width", "width"), (names or {}).get("height", "height")
        raise ValueError(f"{out}: an .mp4 (H.264, yuv420p) needs an even width and height, got "
                         f"{settings['width']} x {settings['height']} ({w}, {h})")
    check_cluster_options(client, workers, scheduler, names)
    from ..rendering.output import DISPLAY_DEFAULTS, check_display_settings

    table = scene.render_defaults
    display = check_display_settings(table.get("exposure", DISPLAY_DEFAULTS["exposure"]) if exposure is None
                                     else exposure, table.get("view", DISPLAY_DEFAULTS["view"]) if view is None
                                     else view, names)
    if spectral_out is not None:
        spectral_out = check_spectral_output(spectral_out, out)
    frames = timeline.iter_frames(settings, display, spectral=spectral_out is not None)
    n_frames = len(timeline)

    # Frames are planned, keyed and rendered one at a time: the first renders at once, however
    # long the movie, and what is kept per frame is its key (32 bytes).  The cluster is reached
    # (and the cache folder made) at the first frame the cache lacks: nothing is written when
    # it cannot be reached.
    cache = movie_cache_folder(out)
    digests = np.zeros((n_frames, 32), dtype=np.uint8)
    show = sys.stderr.isatty() if progress is None else progress
    bar = None
    if show:
        from tqdm import tqdm

        bar = tqdm(total=n_frames, unit="frame", desc="movie", file=sys.stderr)
    rendered = 0
    t_render = time.perf_counter()
    renderer = None
    try:
        with contextlib.ExitStack() as stack:
            for i, frame in enumerate(frames):
                key = frame.key(bits)
                digests[i] = np.frombuffer(bytes.fromhex(key), dtype=np.uint8)
                cached = (cache / f"{key}.png").is_file() and (not frame.spectral or (cache / f"{key}.npz").is_file())
                if cached or (renderer is not None and renderer.pending(key)):  # identical frames render once
                    if bar is not None:
                        bar.update(1)
                    continue
                if renderer is None:
                    c = stack.enter_context(cluster_client(client, workers, scheduler, names))
                    cache.mkdir(exist_ok=True)
                    renderer = _FrameRenderer(c, cache, bits, bar)
                    stack.callback(renderer.cancel)
                renderer.submit(frame, key)
                rendered += 1
            if renderer is not None:
                renderer.finish()
    finally:
        if bar is not None:
            bar.close()
    paths = _CachePaths(cache, digests)
    spectral_paths = _CachePaths(cache, digests, ".npz")
    t_encode = time.perf_counter()
    if kind == "mp4":
        _write_mp4(out, paths, fps)
    elif kind == "gif":
        _write_gif(out, paths, fps)
    else:
        _write_folder(out, paths)
    if spectral_out is not None:
        _write_folder(spectral_out, spectral_paths, ".npz")
    t_end = time.perf_counter()
    return MovieResult(out, n_frames, rendered, cache, t_encode - t_render, t_end - t_encode)

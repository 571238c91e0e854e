"""A movie's frames: :class:`Frame`, one self-contained image of a movie, and its cache key
(:func:`frame_key`: the frame's description and the renderer's own fingerprint)."""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import importlib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..scene.limits import DISPLAY_DEFAULTS
from ..scene.model import Scene

__all__ = ["Frame", "frame_key", "renderer_fingerprint"]


@dataclass
class Frame:
    """One image of a movie, self-contained: render ``scene`` with ``settings`` (the resolved
    keyword arguments of :func:`tracer.render`) and save it as a PNG with ``display`` (the
    keyword arguments ``exposure`` and ``view`` of :func:`tracer.save_image`).

    ``index`` is the frame's place in the movie (0-based), ``time`` the film time in seconds
    (the ``time`` commands so far), ``line`` the ``render`` command's line that made it;
    ``spectral``: the frame also keeps its per-band spectral image (``tracer image
    --spectral-out``), which renders it with spectral transport.
    """

    index: int
    scene: Scene
    settings: dict
    time: float = 0.0
    line: int | None = None
    display: dict = field(default_factory=lambda: dict(DISPLAY_DEFAULTS))
    spectral: bool = False

    def key(self, bits=8) -> str:
        """The hash that names this frame's image in a cache: of everything that decides its
        pixels (the scene, the settings, the display settings, whether it is spectral, the film
        time, the PNG bit depth), not of its index."""
        return frame_key(self, bits)


def _feed(h, obj):
    """Feed a canonical byte form of *obj* (dataclasses, arrays, numbers, strings, containers)
    to the hash *h*: equal values give equal bytes, and every float is taken bit for bit."""
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        h.update(b"D" + type(obj).__name__.encode())
        for f in dataclasses.fields(obj):
            if isinstance(obj, Scene) and f.name in ("source", "render_defaults"):
                continue  # where the scene came from does not change a pixel
            h.update(b"." + f.name.encode())
            _feed(h, getattr(obj, f.name))
    elif isinstance(obj, np.ndarray):
        a = np.ascontiguousarray(obj)
        h.update(b"A" + a.dtype.str.encode() + repr(a.shape).encode())
        h.update(a.reshape(-1).view(np.uint8) if a.size else b"")  # its bytes, without a copy
    elif isinstance(obj, (bool, np.bool_)):
        h.update(b"b1" if obj else b"b0")
    elif isinstance(obj, (int, np.integer)):
        h.update(b"i" + str(int(obj)).encode() + b";")
    elif isinstance(obj, (float, np.floating)):
        h.update(b"f" + float(obj).hex().encode() + b";")
    elif isinstance(obj, complex):
        h.update(b"c" + obj.real.hex().encode() + b"," + obj.imag.hex().encode() + b";")
    elif isinstance(obj, str):
        data = obj.encode()
        h.update(b"s" + str(len(data)).encode() + b":" + data)
    elif obj is None:
        h.update(b"N")
    elif isinstance(obj, (list, tuple)):
        h.update(b"L" + str(len(obj)).encode() + b":")
        for item in obj:
            _feed(h, item)
    elif isinstance(obj, dict):
        h.update(b"M" + str(len(obj)).encode() + b":")
        for k in sorted(obj, key=str):
            _feed(h, str(k))
            _feed(h, obj[k])
    else:
        raise TypeError(f"cannot hash a {type(obj).__name__} in a frame description")


#: What decides a frame's pixels besides its description: every source file of the two packages
#: but the scene editor's, and the colour tables (renderer_fingerprint).
_RENDERER_PARTS = ("bubbleoptics", "tracer")


@functools.lru_cache(maxsize=1)
def renderer_fingerprint() -> str:
    """The hex SHA-256 of the renderer: the bytes of every ``.py`` file of ``bubbleoptics`` and
    ``tracer`` (the scene editor's excepted) and of the colour tables, with the numba and NumPy
    versions.  Any edit to the code that makes a pixel changes it, so a movie's cache never
    hands back an image of another renderer."""
    import numba

    h = hashlib.sha256(f"numba {numba.__version__} numpy {np.__version__}".encode())
    for name in _RENDERER_PARTS:
        root = Path(importlib.import_module(name).__file__).parent
        files = [f for f in root.rglob("*") if f.suffix in (".py", ".npz") and "editor" not in f.relative_to(root).parts]
        for f in sorted(files, key=lambda f: f.relative_to(root).as_posix()):
            h.update(f"{name}/{f.relative_to(root).as_posix()}".encode() + b"\0")
            h.update(hashlib.sha256(f.read_bytes()).digest())
    return h.hexdigest()


def frame_key(frame: Frame, bits=8) -> str:
    """The hex SHA-256 of *frame*'s description (see :meth:`Frame.key`) and of the renderer
    (:func:`renderer_fingerprint`), so that a changed renderer does not reuse cached images."""
    h = hashlib.sha256()
    _feed(h, ("bubbleoptics movie frame", renderer_fingerprint(), int(bits)))
    _feed(h, frame.scene)
    _feed(h, frame.settings)
    _feed(h, {k: (float(v) if k == "exposure" else v) for k, v in frame.display.items()})
    _feed(h, bool(frame.spectral))
    _feed(h, float(frame.time))
    return h.hexdigest()


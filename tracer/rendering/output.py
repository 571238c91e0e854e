"""Film to file: what a render's linear-RGB image becomes on a display and in a file.

A render (:func:`tracer.render`) is linear sRGB radiance, unbounded: values above 1 (bright
reflections, the sun in the sky) and below 0 (saturated spectral colours of thin films lie
outside the sRGB gamut, and a colour outside it has a negative channel).  This module keeps
that radiance intact in the float outputs and forms a display image from it for PNGs:

=========  =========================================================================================
suffix     what is written
=========  =========================================================================================
``.png``   a display image, sRGB-encoded 8- or 16-bit codes, after the display settings below
``.npy``   the linear radiance as float64 (H, W, 3), unchanged (NumPy)
``.exr``   the linear radiance as float32 or half (``bits=32``/``16``), negatives and values
           above 1 kept, NaN kept (OpenEXR, ``pip install 'bubbleoptics[exr]'``)
``.hdr``   Radiance RGBE (OpenCV, ``pip install 'bubbleoptics[hdr]'``): one 8-bit mantissa per
           channel and a shared exponent, so each pixel's largest channel is kept to within 1/128
           of itself and the others to within 1/128 of the largest; RGBE cannot store
           negatives, so they are written as 0 (and NaN as 0)
``.npz``   the spectral image (:class:`SpectralImage`, :func:`save_spectral`): radiance per
           wavelength band with the band centres and edges, and the RGB image
=========  =========================================================================================

**Display settings** (PNG only; a float output always holds the radiance as rendered):

* ``exposure``: stops, the image times 2**exposure before the view transform;
* ``view``: how the exposed radiance becomes display values in [0, 1] --
  ``"clip"`` (the default): each channel clipped to [0, 1] in linear light (NaN as 0), then the
  sRGB curve; negatives become 0 and everything above 1 white;
  ``"aces"``: the ACES 2.0 output transform for an sRGB display (SDR, 100 nits, Rec.709
  primaries) from OpenColorIO's built-in ACES config (:data:`ACES_CONFIG`, ``pip install
  'bubbleoptics[view]'``): a filmic curve that rolls highlights off towards white instead of
  clipping them and compresses out-of-gamut colours (negative channels) into the display's
  gamut instead of clipping each channel.  Scene 1.0 shows at about 0.71 and 0.18 at about
  0.35 (display-encoded; ``"clip"`` shows 0.18 at 0.46), so it needs about three quarters of
  a stop more exposure than ``"clip"`` for the same mid-grey.

Why ACES 2.0 from OpenColorIO and not AgX or a hand-written filmic curve: it is the one
filmic view transform maintained as a library on PyPI (OpenColorIO, Academy Software
Foundation; the transform is the Academy's ACES 2.0 output transform, built into the
library, no LUT files), it handles the out-of-gamut colours of thin films by design, and
it has the same purpose as AgX (Blender's AgX exists only as LUT files in Blender's own
OpenColorIO config, which no package on PyPI ships).  colour-hdri's tone-mapping operators
(Reinhard, Hable's filmic) are per-channel curves that leave negatives and hue shifts to the
caller.

Memory: the display image is formed in chunks of :data:`CHUNK_PIXELS` pixels, so saving a PNG
costs little beyond the file's own codes (``benchmarks/output_memory.py``).
"""

from __future__ import annotations

import functools
import os
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from bubbleoptics.atomic import write_atomically

from ..scene.limits import DISPLAY_DEFAULTS, MAX_EXPOSURE, VIEWS

__all__ = [
    "save_image",
    "save_spectral",
    "load_spectral",
    "check_output_path",
    "check_display_settings",
    "is_display_output",
    "display_image",
    "display_codes",
    "SpectralImage",
    "VIEWS",
    "DISPLAY_DEFAULTS",
    "OUTPUT_SUFFIXES",
    "MAX_EXPOSURE",
    "ACES_CONFIG",
]

#: The suffixes :func:`save_image` and :func:`save_spectral` write, and what they hold.
OUTPUT_SUFFIXES = {
    ".png": "sRGB display image (8 or 16 bits)",
    ".npy": "linear RGB, float64",
    ".exr": "linear RGB, OpenEXR float or half",
    ".hdr": "linear RGB, Radiance RGBE",
    ".npz": "the spectral image",
}
#: The allowed ``bits`` per suffix, the first the default (``None`` means: no such setting).
BITS = {".png": (8, 16), ".exr": (32, 16), ".npy": (None,), ".hdr": (None,), ".npz": (None,)}
#: The optional writers: suffix (or view) -> (module to import, what to install).
WRITERS = {
    ".exr": ("OpenEXR", "pip install 'bubbleoptics[exr]' (the OpenEXR package)"),
    ".hdr": ("cv2", "pip install 'bubbleoptics[hdr]' (opencv-python-headless)"),
    "aces": ("PyOpenColorIO", "pip install 'bubbleoptics[view]' (opencolorio >= 2.5)"),
}
#: OpenColorIO's built-in config (ACES 2.0, OCIO 2.5 and later) and the conversion the
#: ``"aces"`` view applies: from this colour space to this display and view.
ACES_CONFIG = "ocio://cg-config-v4.0.0_aces-v2.0_ocio-v2.5"
ACES_FROM = "Linear Rec.709 (sRGB)"
ACES_DISPLAY = "sRGB - Display"
ACES_VIEW = "ACES 2.0 - SDR 100 nits (Rec.709)"
#: The display image is formed this many pixels at a time (6 MB of float64).
CHUNK_PIXELS = 1 << 18
#: zlib level of 8-bit PNGs: 3 writes a render faster than Pillow's default 6, for a somewhat
#: larger file (docs/performance.md).
PNG_COMPRESS_LEVEL = 3
#: The largest finite half-precision float; an ``.exr`` of halves saturates there.
HALF_MAX = 65504.0
#: Larger values are written (and shown) as this: float32 and OpenColorIO hold no more.
_FLOAT32_BIG = 3e38
#: sRGB (Rec.709) primaries and D65 white (CIE xy), as OpenEXR's ``chromaticities`` attribute.
SRGB_CHROMATICITIES = (0.64, 0.33, 0.30, 0.60, 0.15, 0.06, 0.3127, 0.3290)


# ------------------------------------------------------------------------------------------
# Checks
# ------------------------------------------------------------------------------------------
def _check_exposure(exposure):
    if isinstance(exposure, bool) or not isinstance(exposure, (int, float, np.integer, np.floating)) \
            or not -MAX_EXPOSURE <= float(exposure) <= MAX_EXPOSURE:
        raise ValueError(f"exposure must be a number of stops in [{-MAX_EXPOSURE:g}, {MAX_EXPOSURE:g}] "
                         f"(got {exposure!r})")
    return float(exposure)


def _check_view(view):
    if view not in VIEWS:
        raise ValueError(f"view must be one of {', '.join(map(repr, VIEWS))} (got {view!r})")
    return view


def check_display_settings(exposure=0.0, view="clip", names=None) -> dict:
    """``{"exposure": float, "view": str}`` checked: exposure a number of stops within
    +-:data:`MAX_EXPOSURE`, view one of :data:`VIEWS` with its library installed; else
    ValueError (one line; *names* maps ``exposure``/``view`` to what the caller calls them).

    >>> check_display_settings(1, "clip")
    {'exposure': 1.0, 'view': 'clip'}
    """
    names = names or {}
    try:
        exposure = _check_exposure(exposure)
        view = _check_view(view)
    except ValueError as err:
        text = str(err)
        for key in ("exposure", "view"):
            if text.startswith(key):
                text = names.get(key, key) + text[len(key):]
        raise ValueError(text) from None
    missing = _writer_missing(view)
    if missing:
        raise ValueError(f"{names.get('view', 'view')} {view!r} {missing}")
    return {"exposure": exposure, "view": view}


def _writer_missing(key):
    """The one-line reason the optional writer for *key* (a suffix or a view) is missing, or None."""
    if key not in WRITERS:
        return None
    module, install = WRITERS[key]
    try:
        __import__(module)
    except ImportError:
        return f"needs {module}, which is not installed: {install}"
    if key == "aces":
        try:
            _aces_processor()
        except Exception as exc:  # an OpenColorIO without the ACES 2.0 config
            return f"needs OpenColorIO's built-in config {ACES_CONFIG} ({exc}): {install}"
    return None


def _resolve_bits(suffix, bits, where):
    allowed = BITS[suffix]
    if bits is None:
        return allowed[0]
    if isinstance(bits, bool) or bits not in allowed:
        if allowed == (None,):
            raise ValueError(f"{where}: bits does not apply to {suffix} (it applies to .png: 8 or 16, "
                             f".exr: 16 (half) or 32 (float))")
        raise ValueError(f"{where}: bits for {suffix} must be {' or '.join(map(str, sorted(allowed)))} "
                         f"(got {bits!r})")
    return int(bits)


def _check_settings(path, suffix, bits, exposure, view):
    if suffix not in OUTPUT_SUFFIXES:
        raise ValueError(f"{path}: output must end in {', '.join(list(OUTPUT_SUFFIXES)[:-1])} or "
                         f"{list(OUTPUT_SUFFIXES)[-1]} (got {suffix or 'no suffix'!r})")
    bits = _resolve_bits(suffix, bits, path)
    exposure = _check_exposure(exposure)
    view = _check_view(view)
    if suffix != ".png" and (exposure != 0.0 or view != "clip"):
        raise ValueError(f"{path}: exposure and view apply to display images (.png); {suffix} holds the "
                         "linear radiance as rendered (leave them at 0 and 'clip')")
    return bits, exposure, view


def check_output_path(path, *, bits=None, exposure=0.0, view="clip"):
    """Check, before rendering, that :func:`save_image` (or :func:`save_spectral` for ``.npz``)
    can write *path* with these settings; return it as a :class:`~pathlib.Path`.

    Checked: the suffix is one of :data:`OUTPUT_SUFFIXES`; *bits* suits it (``.png``: 8 or 16,
    ``.exr``: 16 or 32, others: None); *exposure* and *view* are valid and, unless at their
    defaults, the output is a display image (``.png``); the writer for the suffix (and the
    view) is installed; the folder exists and a file can be created in it (a temporary file
    is made there and removed); *path* is not a folder.  Raises :class:`ValueError` with one
    line naming *path* and what is allowed.

    >>> import tempfile
    >>> folder = tempfile.mkdtemp()
    >>> check_output_path(f"{folder}/out.png", bits=16).name
    'out.png'
    >>> check_output_path(f"{folder}/out.jpg")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ValueError: .../out.jpg: output must end in .png, .npy, .exr, .hdr or .npz (got '.jpg')
    """
    path = Path(path)
    suffix = path.suffix.lower()
    _check_settings(path, suffix, bits, exposure, view)
    for key in (suffix, view):
        missing = _writer_missing(key)
        if missing:
            what = f"writing {suffix}" if key == suffix else f"view {view!r}"
            raise ValueError(f"{path}: {what} {missing}")
    folder = path.parent
    if not folder.is_dir():
        raise ValueError(f"{path}: folder {folder} does not exist")
    if path.is_dir():
        raise ValueError(f"{path}: is a folder, not a file name")
    try:
        fd, probe = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".check", dir=folder)
    except OSError as exc:
        raise ValueError(f"{path}: cannot create a file in {folder} ({exc.strerror or exc})") from None
    os.close(fd)
    os.unlink(probe)
    return path


# ------------------------------------------------------------------------------------------
# The display image
# ------------------------------------------------------------------------------------------
@functools.lru_cache(maxsize=1)
def _aces_processor():
    import PyOpenColorIO as ocio

    config = ocio.Config.CreateFromFile(ACES_CONFIG)
    processor = config.getProcessor(ACES_FROM, ACES_DISPLAY, ACES_VIEW, ocio.TRANSFORM_DIR_FORWARD)
    return processor.getDefaultCPUProcessor()


def _aces(linear):
    """The ACES view of a chunk of linear sRGB (..., 3): display values as float32 (not clipped)."""
    buf = np.clip(linear, -_FLOAT32_BIG, _FLOAT32_BIG, out=np.empty(linear.shape, np.float32))  # inf: finite
    np.nan_to_num(buf, copy=False, nan=0.0)
    _aces_processor().applyRGB(buf.reshape(-1, 3))
    return buf


def _check_image(image):
    image = np.asarray(image)
    if image.ndim != 3 or image.shape[2] != 3:
        raise ValueError(f"image must have shape (H, W, 3) (got {image.shape})")
    if image.dtype.kind not in "fiu":
        raise ValueError(f"image must hold real numbers (got {image.dtype})")
    return image if image.dtype == np.float64 else image.astype(np.float64)


def _code_chunks(image, exposure, view, bits):
    """``(first row, codes)`` of consecutive row blocks of the display image: unsigned codes
    0..2**bits - 1 of the sRGB-encoded display values (see :func:`display_codes`).

    The ``"clip"`` view is one parallel numba kernel per block.  OpenColorIO's ACES view costs
    about a microsecond a pixel on one thread and releases the GIL, so its blocks are formed
    on as many threads as numba uses, a group of blocks at a time (memory: one block each)."""
    from bubbleoptics.kernels import srgb_encode_quantized_array

    levels = float(2 ** bits - 1)
    dtype = np.uint8 if bits == 8 else np.uint16
    h, w, _ = image.shape
    scale = 2.0 ** exposure
    step = max(1, CHUNK_PIXELS // max(w, 1))
    starts = range(0, h, step)

    def block(r0):
        part = image[r0:r0 + step]
        if scale != 1.0:
            with np.errstate(over="ignore"):  # overflow to inf: shown as white, as any value > 1
                part = part * scale  # exact for whole stops (a power of two)
        codes = np.empty(part.shape, dtype)
        if view == "clip":
            srgb_encode_quantized_array(np.ascontiguousarray(part).reshape(-1), levels, codes.reshape(-1))
        else:
            shown = _aces(part)
            np.clip(shown, 0.0, 1.0, out=shown)
            codes[...] = np.rint(shown * np.float32(levels))
        return codes

    if view == "clip" or len(starts) == 1:
        for r0 in starts:
            yield r0, block(r0)
        return
    import numba
    from concurrent.futures import ThreadPoolExecutor

    n = max(1, numba.get_num_threads())
    with ThreadPoolExecutor(n) as pool:
        for g in range(0, len(starts), n):
            group = starts[g:g + n]
            yield from zip(group, pool.map(block, group))


def display_codes(image, *, exposure=0.0, view="clip", bits=8):
    """The integer codes a PNG of *image* stores: (H, W, 3) uint8 (``bits=8``) or uint16 (16).

    *image* is linear sRGB (any real values); it is multiplied by ``2**exposure`` and shown
    through the *view* transform (module docstring): ``"clip"`` clips each channel to [0, 1]
    (NaN as 0), encodes it with the sRGB curve and rounds to the nearest code
    (:func:`bubbleoptics.kernels.srgb_encode_quantized_array`, half to even); ``"aces"``
    applies OpenColorIO's ACES 2.0 sRGB view, whose output is display-encoded already, and
    rounds that.  ``exposure=0, view="clip"`` (the defaults) is the plain sRGB encoding of the
    clipped image (colour-science's, rounded: ``tests/tracer/test_output.py``).

    >>> display_codes(np.array([[[-0.5, 0.5, 2.0]]]))
    array([[[  0, 188, 255]]], dtype=uint8)
    >>> display_codes(np.array([[[0.25, 0.5, 1.0]]]), exposure=1.0)   # one stop up: doubled
    array([[[188, 255, 255]]], dtype=uint8)
    """
    image = _check_image(image)
    exposure = _check_exposure(exposure)
    view = _check_view(view)
    if bits not in (8, 16):
        raise ValueError(f"bits must be 8 or 16 (got {bits!r})")
    out = np.empty(image.shape, np.uint8 if bits == 8 else np.uint16)
    for r0, codes in _code_chunks(image, exposure, view, bits):
        out[r0:r0 + codes.shape[0]] = codes
    return out


def display_image(image, *, exposure=0.0, view="clip"):
    """The display-encoded sRGB values (H, W, 3) float64 in [0, 1] of *image* (linear sRGB)
    shown with *exposure* (stops) and *view* (module docstring), before rounding to codes:
    for plotting (``matplotlib.pyplot.imshow`` takes it as it is).

    >>> [round(v, 4) for v in display_image(np.array([[[0.0, 0.18, 1.0]]]))[0, 0].tolist()]
    [0.0, 0.4614, 1.0]
    """
    from bubbleoptics.colorimetry import linear_srgb_to_srgb

    image = _check_image(image)
    exposure = _check_exposure(exposure)
    view = _check_view(view)
    with np.errstate(over="ignore"):
        x = image * 2.0 ** exposure
    if view == "clip":
        x = np.nan_to_num(np.clip(x, 0.0, 1.0), nan=0.0)
        return linear_srgb_to_srgb(x)
    return np.clip(_aces(x), 0.0, 1.0).astype(np.float64)


# ------------------------------------------------------------------------------------------
# Writers
# ------------------------------------------------------------------------------------------
def _write_png8(path, image, exposure, view):
    # Pillow (the writer imageio itself uses for PNG), fed a block of rows at a time: the
    # image's own codes (3 bytes a pixel, 4 in Pillow's memory) and one block, never a
    # full-size float temporary
    from PIL import Image

    h, w, _ = image.shape
    picture = Image.new("RGB", (w, h))
    for r0, codes in _code_chunks(image, exposure, view, 8):
        picture.paste(Image.fromarray(codes, mode="RGB"), (0, r0))
    write_atomically(path, lambda tmp: picture.save(tmp, format="PNG", compress_level=PNG_COMPRESS_LEVEL))


def _write_png16(path, image, exposure, view):
    # Pillow has no 16-bit-per-channel RGB mode; pypng writes it, from an iterator of rows
    # already packed as big-endian bytes (pypng's own packing of integer rows is pure Python)
    import png

    h, w, _ = image.shape

    def rows():
        for _, codes in _code_chunks(image, exposure, view, 16):
            packed = codes.astype(">u2").view(np.uint8).reshape(codes.shape[0], w * 6)
            for row in packed:
                yield row.tobytes()

    def write(tmp):
        with open(tmp, "wb") as f:
            png.Writer(width=w, height=h, bitdepth=16, greyscale=False).write_packed(f, rows())

    write_atomically(path, write)


def _write_npy(path, array):
    def write(tmp):  # through a file object: np.save(name) would append ".npy" to the temp name
        with open(tmp, "wb") as f:
            np.save(f, array)

    write_atomically(path, write)


def _write_exr(path, image, bits):
    import OpenEXR

    limit, dtype = (HALF_MAX, np.float16) if bits == 16 else (_FLOAT32_BIG, np.float32)
    pixels = np.clip(image, -limit, limit, out=np.empty(image.shape, dtype))  # no overflow to inf
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage,
              "chromaticities": SRGB_CHROMATICITIES}

    def write(tmp):
        with OpenEXR.File(header, {"RGB": pixels}) as f:
            f.write(tmp)

    write_atomically(path, write)


def _write_hdr(path, image):
    # OpenCV encodes the image (RGBE, run-length coded scanlines); a Radiance file is a header
    # and then independent scanlines, so it is encoded a block of rows at a time and the
    # blocks' scanlines follow one header for the whole image (OpenCV copies whatever it is
    # given, and imencode holds the whole file in memory)
    import cv2

    h, w, _ = image.shape
    step = max(1, CHUNK_PIXELS // max(w, 1))

    def scanlines(r0):
        rgb = image[r0:r0 + step]
        bgr = np.clip(rgb[..., ::-1], 0.0, _FLOAT32_BIG, out=np.empty(rgb.shape, np.float32))  # no negatives
        np.nan_to_num(bgr, copy=False, nan=0.0)
        ok, encoded = cv2.imencode(".hdr", bgr)
        if not ok:
            raise OSError(f"{path}: OpenCV could not encode the image as .hdr")
        data = encoded.tobytes()
        end = data.index(b"\n", data.index(b"\n\n") + 2) + 1  # past the header and the size line
        header = data[:data.index(b"\n\n") + 2]
        return header, data[end:]

    def write(tmp):
        with open(tmp, "wb") as f:
            for r0 in range(0, h, step):
                header, data = scanlines(r0)
                if r0 == 0:
                    f.write(header + f"-Y {h} +X {w}\n".encode("ascii"))
                f.write(data)

    write_atomically(path, write)


def save_image(image, path, *, bits=None, exposure=0.0, view="clip"):
    """Save a linear-sRGB image (H, W, 3); the suffix of *path* says how (module docstring).

    ``.png``: a display image, sRGB-encoded 8-bit codes (``bits=16``: 16-bit), from the image
    times ``2**exposure`` shown through *view* (``"clip"``, the default: each channel clipped
    to [0, 1] in linear light, NaN as 0, then the sRGB curve; ``"aces"``: OpenColorIO's ACES 2.0
    sRGB view), rounded to the nearest code (:func:`display_codes`).
    ``.npy``: the image as float64, unchanged.  ``.exr``: float32 (``bits=32``, the default) or
    half (``bits=16``: values beyond +-65504 saturate there), negatives and NaN kept, with the
    sRGB primaries as its chromaticities.  ``.hdr``: Radiance RGBE, negatives and NaN as 0.
    Exposure and view apply to ``.png`` only; the float outputs hold the radiance as rendered.

    The file is written atomically (a temporary file in the same folder, then renamed), so a
    failed write leaves nothing behind.  Returns *path*.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".npz":
        raise ValueError(f"{path}: a .npz output holds a spectral image: use tracer.save_spectral")
    bits, exposure, view = _check_settings(path, suffix, bits, exposure, view)
    missing = _writer_missing(suffix) or (_writer_missing(view) if suffix == ".png" else None)
    if missing:
        raise ValueError(f"{path}: {'view ' + repr(view) if suffix == '.png' else 'writing ' + suffix} {missing}")
    image = _check_image(image)
    if suffix == ".npy":
        _write_npy(path, image)
    elif suffix == ".png":
        (_write_png8 if bits == 8 else _write_png16)(path, image, exposure, view)
    elif suffix == ".exr":
        _write_exr(path, image, bits)
    else:
        _write_hdr(path, image)
    return path


# ------------------------------------------------------------------------------------------
# The spectral image
# ------------------------------------------------------------------------------------------
@dataclass
class SpectralImage:
    """A render's radiance per wavelength band, with what it takes to read it.

    ``radiance`` (H, W, C): each pixel's radiance in each of the C bands, as a factor on
    the D65 illuminant's spectrum (the spectral transport's unit, :func:`tracer.prepare.pack.channel_setup`:
    a perfect white reflector under a white light is about 1 in every band);
    ``wavelengths_nm`` (C,): the band centres, ``band_edges_nm`` (C + 1,): their edges (equal
    bands over 360-780 nm), ``to_rgb`` (3, C): the matrix that takes a pixel's bands to linear
    sRGB (so ``radiance @ to_rgb.T`` is the RGB image), ``to_xyz`` (3, C): to CIE XYZ
    (CIE 1931 2°, Y of D65 = 1); ``rgb`` (H, W, 3): the linear-sRGB image the renderer made
    from the same samples (equal to ``radiance @ to_rgb.T`` up to rounding);
    ``spectral_method``: ``"point"`` or ``"band"`` (films at the band centres, or averaged over
    each band).
    """

    radiance: np.ndarray
    wavelengths_nm: np.ndarray
    band_edges_nm: np.ndarray
    to_rgb: np.ndarray
    to_xyz: np.ndarray
    rgb: np.ndarray
    spectral_method: str = ""

    def to_linear_rgb(self):
        """``radiance @ to_rgb.T``: linear sRGB (H, W, 3)."""
        return self.radiance @ self.to_rgb.T

    def to_XYZ(self):
        """``radiance @ to_xyz.T``: CIE XYZ (H, W, 3)."""
        return self.radiance @ self.to_xyz.T


_SPECTRAL_FIELDS = ("radiance", "wavelengths_nm", "band_edges_nm", "to_rgb", "to_xyz", "rgb")


def save_spectral(spectral, path):
    """Save a :class:`SpectralImage` as ``.npz`` (uncompressed; written atomically).

    One file with named arrays rather than an ``.npy`` and a sidecar: the cube cannot be
    separated from its wavelengths, and ``np.load(path)`` gives every field by name
    (``radiance``, ``wavelengths_nm``, ``band_edges_nm``, ``to_rgb``, ``to_xyz``, ``rgb``,
    ``spectral_method``, ``units``) without pickles.  :func:`load_spectral` reads it back.
    """
    path = Path(path)
    if path.suffix.lower() != ".npz":
        raise ValueError(f"{path}: a spectral image is saved as .npz (got {path.suffix or 'no suffix'!r})")
    if not isinstance(spectral, SpectralImage):
        raise ValueError(f"{path}: expected a tracer.SpectralImage (from tracer.render_spectral), "
                         f"got {type(spectral).__name__}")
    arrays = {name: np.asarray(getattr(spectral, name), dtype=np.float64) for name in _SPECTRAL_FIELDS}
    arrays["spectral_method"] = np.array(spectral.spectral_method)
    arrays["units"] = np.array("radiance: per band, a factor on D65 (perfect white reflector under white "
                               "light ~ 1); wavelengths in nm; rgb: linear sRGB")

    def write(tmp):
        with open(tmp, "wb") as f:
            np.savez(f, **arrays)

    write_atomically(path, write)
    return path


def load_spectral(path) -> SpectralImage:
    """Read back a file written by :func:`save_spectral`."""
    with np.load(path, allow_pickle=False) as f:
        return SpectralImage(**{name: f[name] for name in _SPECTRAL_FIELDS},
                             spectral_method=str(f["spectral_method"]))


def is_display_output(path) -> bool:
    """True for outputs that the display settings (exposure, view) apply to (``.png``)."""
    return Path(path).suffix.lower() == ".png"

"""The outputs (tracer.rendering.output): display settings, float files, the spectral image, output checks.

* Display: at exposure 0 with the ``clip`` view a PNG is byte for byte the plain recipe written
  out here (the sRGB codes of the whole image, one Pillow or pypng write), and its codes are NumPy's
  rounding of colour-science's sRGB encoding; exposure is a factor 2**stops; the ``aces`` view
  is OpenColorIO's own ACES 2.0 output transform (compared with OpenColorIO called here by
  another route), monotone, 0 at 0 and saturating at 1.
* Float files are read back: ``.exr`` with OpenEXR, ``.hdr`` with a Radiance RGBE decoder
  written out here (and OpenCV), each within its format's precision.
* The spectral image: its bands converted with the scene's ``to_rgb`` give the RGB image;
  its wavelengths are the transport's.
* ``check_output_path``: one-line errors naming the path, nothing left behind.
"""

import sys
import tracemalloc
from pathlib import Path

import numpy as np
import pytest

import tracer
from tracer.rendering import output
from tracer.rendering.output import check_output_path, display_codes, display_image, save_image
from cli_helpers import run  # tests/support/cli_helpers.py

pytestmark = pytest.mark.api

ROOT = Path(__file__).resolve().parents[2]
LISTING_3_1 = ROOT / "data" / "coursework_scenes" / "listing_3_1.txt"
ONE_BUBBLE = ROOT / "data" / "scenes" / "coursework_one_bubble.txt"
SMALL = dict(width=12, height=9, depth=3, progress=False)


def test_image(h=37, w=23, seed=0):
    """Linear RGB with negatives, values above 1, exact 0 and 1, and NaN."""
    rng = np.random.default_rng(seed)
    image = rng.uniform(-0.2, 1.6, (h, w, 3))
    image[0, 0] = (0.0, 1.0, np.nan)
    image[0, 1] = (0.0031308, 0.5, 1e300)
    return image


test_image.__test__ = False  # a helper, not a test


@pytest.fixture
def small_chunks(monkeypatch):
    """Blocks of 50 pixels, so that a small image is formed in many blocks (and a partial last one)."""
    monkeypatch.setattr(output, "CHUNK_PIXELS", 50)


def aces_or_skip():
    pytest.importorskip("PyOpenColorIO")
    if output._writer_missing("aces"):
        pytest.skip(output._writer_missing("aces"))


def read_png(path):
    import png

    w, h, rows, info = png.Reader(filename=str(path)).read()
    return np.array([np.asarray(r) for r in rows]).reshape(h, w, 3), info


# ------------------------------------------------------------------------------------------
# Display: exposure and view
# ------------------------------------------------------------------------------------------
def test_clip_at_exposure_0_is_the_earlier_png_byte_for_byte(tmp_path, small_chunks):
    from PIL import Image

    from bubbleoptics.kernels import srgb_encode_quantized_array

    image = test_image()
    # the plain recipe: codes of the whole image, Pillow from the whole array, zlib level 3
    codes = np.empty(image.size, np.uint8)
    srgb_encode_quantized_array(image.ravel(), 255.0, codes)
    Image.fromarray(codes.reshape(image.shape), mode="RGB").save(tmp_path / "old.png", format="PNG", compress_level=3)
    save_image(image, tmp_path / "new.png")
    assert (tmp_path / "new.png").read_bytes() == (tmp_path / "old.png").read_bytes()
    save_image(image, tmp_path / "explicit.png", bits=8, exposure=0.0, view="clip")
    assert (tmp_path / "explicit.png").read_bytes() == (tmp_path / "old.png").read_bytes()


def test_clip_16_bit_is_the_earlier_png_byte_for_byte(tmp_path, small_chunks):
    import png

    from bubbleoptics.kernels import srgb_encode_quantized_array

    image = test_image()
    h, w, _ = image.shape
    codes = np.empty(image.size, np.uint16)
    srgb_encode_quantized_array(image.ravel(), 65535.0, codes)
    with open(tmp_path / "old.png", "wb") as f:
        png.Writer(width=w, height=h, bitdepth=16, greyscale=False).write(f, codes.reshape(h, w * 3))
    save_image(image, tmp_path / "new.png", bits=16)
    assert (tmp_path / "new.png").read_bytes() == (tmp_path / "old.png").read_bytes()


@pytest.mark.reference
@pytest.mark.parametrize("bits", [8, 16])
def test_clip_codes_are_colour_science_encoding_rounded(bits, small_chunks):
    import colour

    image = test_image()
    top = 2 ** bits - 1
    expected = np.round(colour.cctf_encoding(np.clip(np.nan_to_num(image, nan=0.0), 0, 1), "sRGB") * top)
    assert np.array_equal(display_codes(image, bits=bits), expected)


@pytest.mark.parametrize("view", ["clip", "aces"])
def test_one_stop_doubles_the_linear_values(view, small_chunks):
    if view == "aces":
        aces_or_skip()
    image = test_image()
    assert np.array_equal(display_codes(image, exposure=1, view=view), display_codes(2 * image, view=view))
    assert np.array_equal(display_codes(image, exposure=-2, view=view), display_codes(image / 4, view=view))
    assert np.array_equal(display_image(image, exposure=1, view=view), display_image(2 * image, view=view))
    half = display_codes(image, exposure=0.5, view=view, bits=16)
    assert np.array_equal(half, display_codes(image * 2 ** 0.5, view=view, bits=16))


@pytest.mark.parametrize("view", ["clip", "aces"])
def test_extreme_values_and_exposures_warn_nothing(view):
    if view == "aces":
        aces_or_skip()
    image = test_image()  # holds 1e300 and NaN
    image[1, 1] = (-1e300, np.inf, -np.inf)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for exposure in (64, -64, 0):
            codes = display_codes(image, exposure=exposure, view=view)
            shown = display_image(image, exposure=exposure, view=view)
            assert np.all(np.isfinite(shown)) and shown.min() >= 0 and shown.max() <= 1
    assert codes[0, 1, 2] == 255  # 1e300: full blue
    if view == "clip":
        assert codes[0, 0, 2] == 0  # NaN as 0 (the aces view renders that pixel's green with some blue)


def test_exposure_is_a_display_setting_not_a_change_of_the_image(tmp_path):
    image = test_image()
    before = image.copy()
    save_image(image, tmp_path / "o.png", exposure=3)
    assert np.array_equal(image, before, equal_nan=True)


def test_display_image_rounds_to_display_codes(small_chunks):
    image = test_image()
    for exposure in (0.0, 1.5):
        shown = display_image(image, exposure=exposure)
        assert shown.min() >= 0 and shown.max() <= 1
        assert np.array_equal(np.round(shown * 255), display_codes(image, exposure=exposure))


@pytest.mark.property
def test_aces_view_is_monotone_zero_at_zero_and_saturates():
    aces_or_skip()
    grey = np.concatenate([[0.0], np.geomspace(1e-6, 1e6, 400)])
    ramp = np.repeat(grey[:, None], 3, axis=1)[None]
    shown = display_image(ramp, view="aces")[0]
    assert np.abs(shown - shown[:, 1:2]).max() < 2e-6  # grey stays grey (to float32 rounding)
    v = shown[:, 1]
    assert v[0] == 0.0
    assert np.all(np.diff(v) >= 0) and np.all(v <= 1.0)
    assert np.all(np.diff(v[(grey > 1e-3) & (grey < 50)]) > 0)  # strictly increasing where it matters
    codes = display_codes(ramp, view="aces")[0, :, 0]
    assert codes[0] == 0 and codes[-1] == 255 and np.all(np.diff(codes.astype(int)) >= 0)
    # out-of-gamut and huge values stay displayable
    odd = np.array([[[-0.2, 1.0, 0.1], [-1.0, 2.0, -0.5], [np.nan, 0.5, 0.5], [np.inf, 0.0, 0.0]]])
    shown = display_image(odd, view="aces")
    assert np.all(np.isfinite(shown)) and shown.min() >= 0 and shown.max() <= 1
    assert shown[0, 3, 0] == pytest.approx(1.0, abs=1e-3)  # infinite red shows as full red


@pytest.mark.reference
def test_aces_view_is_opencolorios_own_output(small_chunks):
    """OpenColorIO called here through a DisplayViewTransform (the module asks getProcessor for
    the display and view by name), on the whole image in float32, rounded with NumPy."""
    aces_or_skip()
    import PyOpenColorIO as ocio

    config = ocio.Config.CreateFromFile(output.ACES_CONFIG)
    transform = ocio.DisplayViewTransform(src="Linear Rec.709 (sRGB)", display="sRGB - Display",
                                          view="ACES 2.0 - SDR 100 nits (Rec.709)")
    cpu = config.getProcessor(transform).getDefaultCPUProcessor()
    image = np.nan_to_num(test_image(), nan=0.0)
    image[0, 1] = (0.1, 0.5, 50.0)
    for exposure in (0.0, 2.0):
        buf = (image * 2.0 ** exposure).astype(np.float32)
        cpu.applyRGB(buf)
        expected = np.rint(np.clip(buf, 0, 1) * np.float32(255))
        assert np.array_equal(display_codes(image, exposure=exposure, view="aces"), expected)


@pytest.mark.regression
def test_aces_grey_scale_frozen():
    """Values of OpenColorIO 2.6's ACES 2.0 sRGB view, frozen (what the module docstring quotes)."""
    aces_or_skip()
    grey = np.array([[[0.18] * 3, [1.0] * 3, [4.0] * 3]])
    assert display_image(grey, view="aces")[0, :, 0] == pytest.approx([0.3492, 0.7067, 0.8999], abs=2e-3)


def test_view_without_opencolorio_is_a_clear_error(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "PyOpenColorIO", None)  # import fails
    with pytest.raises(ValueError) as info:
        check_output_path(tmp_path / "o.png", view="aces")
    message = str(info.value)
    assert "\n" not in message and "o.png" in message and "pip install" in message and "opencolorio" in message
    with pytest.raises(ValueError, match="pip install"):
        save_image(test_image(), tmp_path / "o.png", view="aces")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), 65, -64.5, "1", True, None])
def test_bad_exposure(bad, tmp_path):
    with pytest.raises(ValueError, match="exposure"):
        display_codes(test_image(), exposure=bad)
    with pytest.raises(ValueError, match="exposure"):
        check_output_path(tmp_path / "o.png", exposure=bad)


def test_bad_view(tmp_path):
    with pytest.raises(ValueError, match="view must be one of 'clip', 'aces'"):
        display_image(test_image(), view="agx")
    with pytest.raises(ValueError, match="view"):
        save_image(test_image(), tmp_path / "o.png", view="filmic")


def test_saving_a_png_holds_no_full_size_float_temporary(tmp_path, monkeypatch):
    """NumPy's allocations (tracemalloc) while saving a 29 MB image: blocks of rows, never a
    copy of it (a float temporary would be 100 %, the full uint8 codes 12.5 %).  What is left
    is fixed: the blocks, and zlib's and pypng's buffers (up to about 5 MB; Pillow's own image
    buffer, 4 bytes a pixel, is outside tracemalloc)."""
    monkeypatch.setattr(output, "CHUNK_PIXELS", 20000)
    ramp = np.add.outer(np.linspace(-0.1, 1.5, 2400), np.linspace(0.0, 0.3, 500))
    image = ramp[..., None] * np.array([1.0, 0.7, 0.4])
    cases = [dict(), dict(exposure=1.0), dict(bits=16, exposure=-1.0)]
    if not output._writer_missing("aces"):
        cases.append(dict(view="aces", exposure=1.0))
    for kwargs in cases:
        save_image(np.ones((4, 4, 3)), tmp_path / "warm.png", **kwargs)
        tracemalloc.start()
        save_image(image, tmp_path / "o.png", **kwargs)
        _, peak = tracemalloc.get_traced_memory()
        tracemalloc.stop()
        assert peak < 0.25 * image.nbytes, (kwargs, peak, image.nbytes)


# ------------------------------------------------------------------------------------------
# Float outputs
# ------------------------------------------------------------------------------------------
def test_npy_keeps_the_image(tmp_path):
    image = test_image()
    save_image(image, tmp_path / "o.npy")
    assert np.array_equal(np.load(tmp_path / "o.npy"), image, equal_nan=True)


def read_exr(path):
    import OpenEXR

    with OpenEXR.File(str(path)) as f:
        header = dict(f.header())  # (before the channels: reading them first empties the header)
        return np.array(f.channels()["RGB"].pixels), header


@pytest.mark.parametrize("bits", [None, 32, 16])
def test_exr_round_trip(tmp_path, bits):
    pytest.importorskip("OpenEXR")
    image = test_image()
    image[0, 1, 2] = 1e6  # beyond a half
    save_image(image, tmp_path / "o.exr", bits=bits)
    back, header = read_exr(tmp_path / "o.exr")
    assert back.shape == image.shape
    assert back.dtype == (np.float16 if bits == 16 else np.float32)
    assert header["chromaticities"] == pytest.approx(output.SRGB_CHROMATICITIES, abs=1e-6)
    back = back.astype(np.float64)
    assert np.isnan(back[0, 0, 2]) and not np.isnan(np.delete(back.ravel(), 2)).any()  # NaN kept
    ok = np.isfinite(image) & (np.abs(image) < 60000)
    rel = 2.0 ** -11 if bits == 16 else 2.0 ** -24  # half / float rounding, relative
    assert np.all(np.abs(back[ok] - image[ok]) <= rel * np.abs(image[ok]) + 1e-300)
    assert (back < 0).any() and (back > 1).any()  # negatives and values above 1 kept
    assert back[0, 1, 2] == (output.HALF_MAX if bits == 16 else 1e6)


def decode_rgbe(data):
    """A Radiance .hdr file (header, then flat or new-style run-length scanlines) as float (H, W, 3):
    written out here from the format's description (Ward, Graphics Gems II, 1991; Radiance's
    color.c), independent of the writer."""
    end = data.index(b"\n\n") + 2
    header = data[:end].decode("ascii")
    assert header.startswith("#?") and "FORMAT=32-bit_rle_rgbe" in header
    eol = data.index(b"\n", end)
    size = data[end:eol].split()
    assert size[0] == b"-Y" and size[2] == b"+X"
    h, w = int(size[1]), int(size[3])
    pos = eol + 1
    rgbe = np.zeros((h, w, 4), np.uint8)
    for y in range(h):
        if 8 <= w < 32768 and data[pos] == 2 and data[pos + 1] == 2 and (data[pos + 2] << 8 | data[pos + 3]) == w:
            pos += 4
            for c in range(4):  # each component run-length coded in turn
                x = 0
                while x < w:
                    n = data[pos]
                    pos += 1
                    if n > 128:  # a run
                        rgbe[y, x:x + n - 128, c] = data[pos]
                        pos += 1
                        x += n - 128
                    else:
                        rgbe[y, x:x + n, c] = np.frombuffer(data, np.uint8, n, pos)
                        pos += n
                        x += n
        else:
            rgbe[y] = np.frombuffer(data, np.uint8, 4 * w, pos).reshape(w, 4)
            pos += 4 * w
    e = rgbe[..., 3].astype(int)
    scale = np.where(e > 0, np.ldexp(1.0, e - 136), 0.0)
    return rgbe[..., :3] * scale[..., None]


@pytest.mark.reference
@pytest.mark.parametrize("w", [23, 300])  # flat scanlines (narrower than 8 are not the case here) and RLE
def test_hdr_round_trip(tmp_path, w, small_chunks):
    cv2 = pytest.importorskip("cv2")
    image = test_image(h=7, w=w)
    image[1, :5] = [[0.0, 0.0, 0.0], [1e-30, 0, 0], [5.0, 5.0, 5.0], [300.0, 0.01, -1.0], [-1.0, -1.0, -1.0]]
    image[0, 1, 2] = 1e3
    save_image(image, tmp_path / "o.hdr")
    back = decode_rgbe((tmp_path / "o.hdr").read_bytes())
    assert back.shape == image.shape
    target = np.maximum(np.nan_to_num(image, nan=0.0), 0.0)  # RGBE holds no negatives (nor NaN)
    top = target.max(axis=2, keepdims=True)
    # an 8-bit mantissa per channel on the exponent of the pixel's largest channel
    assert np.all(np.abs(back - target) <= top / 128 + 1e-300)
    big = top[..., 0] > 1e-20
    assert np.all(np.abs(back.max(axis=2)[big] - top[big, 0]) <= top[big, 0] / 128)
    assert np.array_equal(back[1, 4], [0, 0, 0]) and back[1, 3, 2] == 0.0
    read = cv2.imread(str(tmp_path / "o.hdr"), cv2.IMREAD_UNCHANGED)[..., ::-1]
    assert np.allclose(read, back, rtol=1e-6, atol=0)
    # written in blocks of rows (here 50 pixels each): the same bytes as OpenCV's whole image
    whole = cv2.imencode(".hdr", np.clip(np.nan_to_num(image, nan=0.0), 0, None)[..., ::-1].astype(np.float32))[1]
    assert (tmp_path / "o.hdr").read_bytes() == whole.tobytes()


@pytest.mark.parametrize("suffix,module", [(".exr", "OpenEXR"), (".hdr", "cv2")])
def test_missing_float_writer_is_a_one_line_error(tmp_path, monkeypatch, suffix, module):
    monkeypatch.setitem(sys.modules, module, None)
    target = tmp_path / f"o{suffix}"
    for call in (lambda: check_output_path(target), lambda: save_image(test_image(), target)):
        with pytest.raises(ValueError) as info:
            call()
        message = str(info.value)
        assert "\n" not in message and str(target) in message and suffix in message and "pip install" in message
    assert list(tmp_path.iterdir()) == []


# ------------------------------------------------------------------------------------------
# check_output_path
# ------------------------------------------------------------------------------------------
BAD_OUTPUTS = {
    "suffix": ("o.jpg", {}, "output must end in .png, .npy, .exr, .hdr or .npz"),
    "no suffix": ("o", {}, "output must end in"),
    "png 32 bits": ("o.png", dict(bits=32), "bits for .png must be 8 or 16"),
    "exr 8 bits": ("o.exr", dict(bits=8), "bits for .exr must be 16 or 32"),
    "npy bits": ("o.npy", dict(bits=16), "bits does not apply to .npy"),
    "npy exposure": ("o.npy", dict(exposure=1.0), "exposure and view apply to display images (.png)"),
    "exr view": ("o.exr", dict(view="aces"), "exposure and view apply to display images"),
    "npz exposure": ("o.npz", dict(exposure=-1.0), "exposure and view apply"),
    "missing folder": ("no/such/o.png", {}, "does not exist"),
}


@pytest.mark.parametrize("name,kwargs,what", BAD_OUTPUTS.values(), ids=BAD_OUTPUTS.keys())
def test_check_output_path_errors(tmp_path, name, kwargs, what):
    target = tmp_path / name
    with pytest.raises(ValueError) as info:
        check_output_path(target, **kwargs)
    message = str(info.value)
    assert "\n" not in message and message.startswith(f"{target}: ") and what in message, message
    assert list(tmp_path.iterdir()) == []


def test_check_output_path_accepts_and_leaves_nothing(tmp_path):
    for name, kwargs in [("a.png", {}), ("b.PNG", dict(bits=16, exposure=-3.5)), ("c.npy", {}), ("d.npz", {})]:
        assert check_output_path(tmp_path / name, **kwargs) == tmp_path / name
    assert list(tmp_path.iterdir()) == []


def test_check_output_path_folder_and_unwritable(tmp_path):
    (tmp_path / "o.png").mkdir()
    with pytest.raises(ValueError, match="is a folder"):
        check_output_path(tmp_path / "o.png")
    if Path("/proc/self").is_dir():  # no file can be created there, even by root
        with pytest.raises(ValueError, match=r"^/proc/self/o\.png: cannot create a file in /proc/self"):
            check_output_path("/proc/self/o.png")


def test_save_image_rejects_bad_images(tmp_path):
    with pytest.raises(ValueError, match=r"shape \(H, W, 3\)"):
        save_image(np.zeros((4, 4)), tmp_path / "o.png")
    with pytest.raises(ValueError, match="spectral image"):
        save_image(np.zeros((4, 4, 3)), tmp_path / "o.npz")
    assert list(tmp_path.iterdir()) == []


def test_one_save_image_under_every_public_name():
    import tracer.rendering

    assert tracer.rendering.save_image is tracer.save_image is output.save_image


def test_command_line_choices_are_the_modules():
    import tracer.cli
    from tracer.scene import limits

    assert output.MAX_EXPOSURE is limits.MAX_EXPOSURE and output.VIEWS is limits.VIEWS  # one home
    parser = tracer.cli.build_parser()
    image = parser._subparsers._group_actions[0].choices["image"]
    view = next(a for a in image._actions if a.dest == "view")
    assert tuple(view.choices) == output.VIEWS


# ------------------------------------------------------------------------------------------
# The spectral image
# ------------------------------------------------------------------------------------------
@pytest.mark.analytic
@pytest.mark.parametrize("kwargs", [dict(), dict(spp=2, spectral_samples=8, seed=3)])
def test_spectral_cube_converts_to_the_rgb_image(kwargs):
    from tracer.prepare.pack import channel_setup

    scene = tracer.default_scene()
    cube = tracer.render_spectral(scene, **SMALL, **kwargs)
    image = tracer.render(scene, **SMALL, **kwargs)
    n = kwargs.get("spectral_samples", 16)
    assert cube.radiance.shape == (9, 12, n) and cube.rgb.shape == (9, 12, 3)
    assert np.array_equal(cube.rgb, image)  # the same samples as a plain render
    assert np.allclose(cube.radiance @ cube.to_rgb.T, image, rtol=0, atol=1e-12)
    assert np.allclose(cube.to_linear_rgb(), image, rtol=0, atol=1e-12)
    wl, to_rgb, _ = channel_setup(True, n)
    assert np.array_equal(cube.wavelengths_nm, wl) and np.array_equal(cube.to_rgb, to_rgb)
    assert np.allclose(cube.band_edges_nm, np.linspace(360, 780, n + 1), rtol=0, atol=1e-12)
    assert np.allclose(0.5 * (cube.band_edges_nm[1:] + cube.band_edges_nm[:-1]), wl, rtol=0, atol=1e-12)
    from bubbleoptics import band_spectral_weights

    assert np.allclose(cube.to_xyz, band_spectral_weights(n)[1], rtol=0, atol=1e-12)
    assert cube.spectral_method in ("point", "band")
    if not kwargs:
        assert (image < 0).any()  # the built-in scene's films leave the sRGB gamut: kept, not clipped


def test_spectral_image_of_an_rgb_scene_renders_spectrally():
    scene = tracer.load_scene(LISTING_3_1)  # no bubbles: render() traces it in RGB
    _, stats = tracer.render_with_stats(scene, **SMALL)
    assert not stats.spectral and stats.spectral_image is None
    cube = tracer.render_spectral(scene, **SMALL)
    assert cube.radiance.shape[2] == 16
    assert np.array_equal(cube.rgb, tracer.render(scene, spectral=True, **SMALL))
    assert np.allclose(cube.to_linear_rgb(), cube.rgb, rtol=0, atol=1e-12)
    with pytest.raises(ValueError, match="spectral transport"):
        tracer.render_spectral(scene, spectral=False, **SMALL)


def test_spectral_npz_round_trip(tmp_path):
    cube = tracer.render_spectral(tracer.default_scene(), **SMALL)
    tracer.save_spectral(cube, tmp_path / "c.npz")
    with np.load(tmp_path / "c.npz", allow_pickle=False) as f:  # plain arrays, no pickles
        assert set(f.files) == {"radiance", "wavelengths_nm", "band_edges_nm", "to_rgb", "to_xyz", "rgb",
                                "spectral_method", "units"}
        assert np.array_equal(f["radiance"], cube.radiance)
    back = tracer.load_spectral(tmp_path / "c.npz")
    for name in ("radiance", "wavelengths_nm", "band_edges_nm", "to_rgb", "to_xyz", "rgb"):
        assert np.array_equal(getattr(back, name), getattr(cube, name))
    assert back.spectral_method == cube.spectral_method
    with pytest.raises(ValueError, match=r"\.npz"):
        tracer.save_spectral(cube, tmp_path / "c.npy")
    with pytest.raises(ValueError, match="SpectralImage"):
        tracer.save_spectral(cube.radiance, tmp_path / "d.npz")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["c.npz"]


# ------------------------------------------------------------------------------------------
# Command line and TOML
# ------------------------------------------------------------------------------------------

TINY = ["--width", "12", "--height", "9", "--depth", "3", "--quiet"]


def test_cli_exposure_and_view(tmp_path, capsys):
    image = tracer.render(tracer.load_scene(ONE_BUBBLE), **SMALL)
    assert run(["image", ONE_BUBBLE, tmp_path / "o.png", "--exposure", "1", "--view", "clip", *TINY], capsys)[0] == 0
    assert np.array_equal(read_png(tmp_path / "o.png")[0], display_codes(image * 2))
    if not output._writer_missing("aces"):
        assert run(["image", ONE_BUBBLE, tmp_path / "a.png", "--exposure", "2", "--view", "aces", "--bits", "16",
                    *TINY], capsys)[0] == 0
        assert np.array_equal(read_png(tmp_path / "a.png")[0], display_codes(image, exposure=2, view="aces", bits=16))


def test_cli_spectral_outputs(tmp_path, capsys):
    status, out, err = run(["image", ONE_BUBBLE, tmp_path / "o.npy", "--spectral-out", tmp_path / "c.npz", *TINY],
                           capsys)
    assert (status, out, err) == (0, "", "")
    cube = tracer.load_spectral(tmp_path / "c.npz")
    assert np.array_equal(np.load(tmp_path / "o.npy"), cube.rgb)
    assert np.allclose(cube.to_linear_rgb(), cube.rgb, rtol=0, atol=1e-12)
    assert run(["image", ONE_BUBBLE, tmp_path / "only.npz", *TINY], capsys)[0] == 0
    assert np.array_equal(tracer.load_spectral(tmp_path / "only.npz").radiance, cube.radiance)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["c.npz", "o.npy", "only.npz"]


CLI_BAD = {
    "exposure with npy": (["o.npy", "--exposure", "1"], "exposure and view apply to display images"),
    "view with npz": (["o.npz", "--view", "aces"], "exposure and view apply"),
    "bits 32 png": (["o.png", "--bits", "32"], "bits for .png must be 8 or 16"),
    "spectral out png": (["o.png", "--spectral-out", "c.png"], "must end in .npz"),
    "exposure nan": (["o.png", "--exposure", "nan"], "--exposure"),
    "exposure 100": (["o.png", "--exposure", "100"], "[-64, 64]"),
    "view agx": (["o.png", "--view", "agx"], "--view"),
}


@pytest.mark.parametrize("argv,what", CLI_BAD.values(), ids=CLI_BAD.keys())
def test_cli_bad_output_options(tmp_path, capsys, argv, what):
    argv = [tmp_path / a if a.endswith((".npy", ".npz", ".png")) else a for a in argv]
    status, out, err = run(["image", ONE_BUBBLE, *argv, *TINY], capsys)
    assert (status, out) == (2, "")
    assert err.count("\n") == 1 and "Traceback" not in err and what in err, err
    assert list(tmp_path.iterdir()) == []


TOML = """\
[[bubbles]]
center = [0, 0, 0]
radius = 1

[render]
width = 12
height = 9
"""


def test_toml_display_settings(tmp_path, capsys):
    from tracer.scene.toml_read import parse_toml_text

    scene = parse_toml_text(TOML + 'exposure = 1.5\nview = "clip"\n')
    assert scene.render_defaults["exposure"] == 1.5 and scene.render_defaults["view"] == "clip"
    path = tmp_path / "s.toml"
    path.write_text(TOML + "exposure = -1\n")
    assert run(["image", path, tmp_path / "o.png", "--depth", "2", "--quiet"], capsys)[0] == 0
    image = tracer.render(tracer.load_scene(path), width=12, height=9, depth=2, progress=False)
    assert np.array_equal(read_png(tmp_path / "o.png")[0], display_codes(image / 2))
    # the command line's option wins; a float output ignores the scene's display settings
    assert run(["image", path, tmp_path / "p.png", "--depth", "2", "--quiet", "--exposure", "0"], capsys)[0] == 0
    assert np.array_equal(read_png(tmp_path / "p.png")[0], display_codes(image))
    assert run(["image", path, tmp_path / "o.npy", "--depth", "2", "--quiet"], capsys)[0] == 0
    assert np.array_equal(np.load(tmp_path / "o.npy"), image)


@pytest.mark.parametrize("text,what", [
    ("exposure = 65\n", "render.exposure: must be <= 64, got 65"),
    ("exposure = -100\n", "render.exposure: must be >= -64, got -100"),
    ('exposure = "2"\n', "render.exposure: must be a number, got a string"),
    ('view = "agx"\n', "render.view: must be one of 'clip', 'aces', got 'agx'"),
])
def test_toml_display_settings_errors(tmp_path, text, what):
    from tracer.scene.errors import SceneError

    path = tmp_path / "s.toml"
    path.write_text(TOML + text)
    with pytest.raises(SceneError) as info:
        tracer.load_scene(path)
    assert str(info.value) == f"{path}:8: {what}"

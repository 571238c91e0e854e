"""The scene editor in a real browser, as a person uses it: Playwright drives the system's
Chromium (launched by its path, no browser download) against ``tracer edit`` serving on a free
port in a subprocess (one per xdist worker, each with its own files).

Where Chromium is missing these tests skip with one line saying how to get it, except under CI
(``CI`` set), where they fail: CI must run them.
"""

from __future__ import annotations

import io
import os
import tempfile
import time
from pathlib import Path

import numpy as np
import pytest

from tracer.editor.testing import editor_server, launch, require_browser

require_browser()
pytestmark = pytest.mark.browser

ROOT = Path(__file__).resolve().parents[2]
SIZE = 400


def _pixels(png_bytes):
    import imageio.v3 as iio

    return iio.imread(io.BytesIO(png_bytes)).astype(int)


def _settles_to(editor, expected, seconds=10.0):
    """Whether the editor's image becomes pixel for pixel *expected* (screenshot bytes) within
    *seconds*: the browser may paint the new image a moment after its version is on the page
    (under load, a screenshot can still catch the one before)."""
    end = time.monotonic() + seconds
    while True:
        if np.array_equal(_pixels(editor.screenshot()), _pixels(expected)):
            return True
        if time.monotonic() > end:
            return False
        editor.page.wait_for_timeout(100)


@pytest.fixture(scope="module")
def root(tmp_path_factory):
    """The served editor's root folder: every file the page loads or saves is in it."""
    return tmp_path_factory.mktemp("editor-root")


@pytest.fixture(scope="module")
def scene_file(root):
    import tracer
    from tracer.scene.toml_write import save_toml_scene

    path = root / "bubbles.toml"
    save_toml_scene(tracer.default_scene(), path)
    return path


@pytest.fixture(scope="module")
def browser():
    with launch() as b:
        yield b


@pytest.fixture(scope="module")
def server(root):
    with editor_server(width=SIZE, height=SIZE, cwd=ROOT, args=("--root", str(root))) as url:
        yield url


def test_load_fills_lists_and_bad_file_keeps_scene(editor, scene_file, root):
    bad = root / "bad.toml"
    bad.write_text("[camera]\nposition = [0, 0, 5]\nfov_deg = 'wide'\n", encoding="utf-8")
    before = editor.options("objects")
    editor.fill("scene_path", bad)
    editor.button("Load").click()
    assert editor.expect_message("scene_path", f"{bad}:").startswith(f"{bad}:")  # the loader's FILE:LINE
    assert editor.options("objects") == before

    editor.fill("scene_path", scene_file)
    editor.click_and_wait("Load")
    assert editor.options("objects") == ["young (bubble)", "middle-aged (bubble)", "old (bubble)"]
    assert len(editor.options("lights")) == 1

    # a file chosen in the browser, in the coursework's format
    v = editor.version()
    editor.page.locator(".editor-upload input[type=file]").set_input_files(
        str(ROOT / "data" / "scenes" / "coursework_three_bubbles.txt"))
    editor.wait_full(v)
    assert sum(o.endswith("(bubble)") for o in editor.options("objects")) == 3
    assert "coursework_three_bubbles.txt" in editor.status()


def test_change_light_intensity_changes_pixels_and_bad_values_change_nothing(editor):
    editor.select("lights", "1:")
    before = editor.screenshot()
    editor.fill("intensity", "abc")
    editor.button("Change").click()
    editor.expect_message("intensity", "'abc' is not a number")
    editor.fill("intensity", "-1")
    editor.button("Change").click()
    editor.expect_message("intensity", "intensity must be >= 0")
    editor.page.wait_for_timeout(300)
    assert editor.screenshot() == before  # the previous image stays

    editor.fill("intensity", "12")
    editor.click_and_wait("Change")
    after = _pixels(editor.screenshot())
    assert np.abs(after - _pixels(before)).max() > 20
    assert not editor.message("intensity").is_visible()
    assert editor.options("lights")[0].endswith("intensity 12")


def test_add_and_delete_light(editor):
    for k, v in zip(("x", "y", "z", "intensity"), (-3, 2, 4, 1.5)):
        editor.fill(k, v)
    editor.click_and_wait("Add")
    assert editor.options("lights")[-1] == "2: (-3, 2, 4) intensity 1.5"
    editor.select("lights", "1:")
    editor.click_and_wait("Delete")
    assert editor.options("lights") == ["1: (-3, 2, 4) intensity 1.5"]
    editor.click_and_wait("Undo")
    assert len(editor.options("lights")) == 2


def test_move_object_pick_pixel_and_save_then_load_gives_the_same_render(editor, root):
    editor.select("objects", "old")
    before = _pixels(editor.screenshot())
    editor.fill("dx", "-0.4")
    editor.click_and_wait("Change geometry")
    moved = _pixels(editor.screenshot())
    assert np.abs(moved - before).max() > 20

    # the picked pixel's film: click the middle of the big bubble ("young", left)
    box = editor.page.locator(".editor-image").bounding_box()
    editor.page.mouse.click(box["x"] + 0.3 * box["width"], box["y"] + 0.45 * box["height"])
    pick = editor.page.locator(".editor-pick")
    pick.get_by_text("young").wait_for()
    pick.get_by_text(" nm at ").wait_for()

    out_scene, img1, img2 = root / "edited.toml", root / "a.png", root / "b.png"
    editor.fill("out_scene", "edited.toml")  # names relative to the root
    editor.button("Save scene").click()
    editor.page.locator(".editor-status").get_by_text("saved edited.toml").wait_for()
    editor.fill("out_image", img1)  # or absolute, inside it
    editor.button("Save image").click()
    editor.page.locator(".editor-status").get_by_text("saved a.png").wait_for()

    editor.fill("scene_path", "edited.toml")
    editor.click_and_wait("Load")
    editor.fill("out_image", "b.png")
    editor.button("Save image").click()
    editor.page.locator(".editor-status").get_by_text("saved b.png").wait_for()
    assert np.array_equal(_pixels(img1.read_bytes()), _pixels(img2.read_bytes()))
    assert out_scene.is_file()


def test_parameters_settings_clear_and_readme_screenshot(editor):
    editor.select("objects", "young")
    editor.fill("swirl", "3")
    editor.button("Change parameters").click()
    editor.expect_message("swirl", "swirl must be >= 0 and <= 1, got 3")
    editor.fill("swirl", "0.6")
    editor.click_and_wait("Change parameters")
    # camera orbit, then undo: the render comes back pixel for pixel
    before = editor.screenshot()
    editor.click_and_wait("Orbit")
    assert np.abs(_pixels(editor.screenshot()) - _pixels(before)).max() > 20
    editor.click_and_wait("Undo")
    assert _settles_to(editor, before)
    editor.fill("depth", "0")
    editor.button("Apply settings").click()
    editor.expect_message("depth", "depth must be an integer from 1 to 64 in the editor")

    box = editor.page.locator(".editor-image").bounding_box()
    editor.page.mouse.click(box["x"] + 0.3 * box["width"], box["y"] + 0.45 * box["height"])
    editor.page.locator(".editor-pick").get_by_text("young").wait_for()
    editor.page.wait_for_timeout(1500)  # the spectrum's plot is drawn after its data arrive
    # the README's screenshot: written into docs/images/ when BUBBLEOPTICS_UPDATE_SCREENSHOT=1
    # (so that an ordinary test run leaves the checkout as it was), else to a temporary file;
    # either way it must be a real picture of the editor
    out = ROOT / "docs" / "images" / "editor.png"
    if os.environ.get("BUBBLEOPTICS_UPDATE_SCREENSHOT") != "1":
        out = Path(tempfile.mkdtemp(prefix="editor-shot-")) / "editor.png"
    editor.page.screenshot(path=str(out) + f".{os.getpid()}.tmp", type="png")
    os.replace(str(out) + f".{os.getpid()}.tmp", out)
    shot = _pixels(out.read_bytes())
    assert shot.shape[0] >= 400 and shot.shape[1] >= 600 and shot.std() > 10  # a page, not a blank

    editor.button("Clear").click()
    editor.page.locator(".editor-stage .stage-cleared").wait_for()

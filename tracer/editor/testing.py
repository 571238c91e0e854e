"""Driving the editor in a real browser (Playwright and a system Chromium), for the browser tests
(``tests/tracer/test_editor_browser.py``) and the latency benchmark (``benchmarks/editor_latency.py``).

Chromium is the system's (Debian's ``chromium`` package), launched by its path: no browser is
downloaded.  :func:`chromium_path` finds it (``TRACER_CHROMIUM``, else ``chromium`` /
``chromium-browser`` / ``google-chrome`` on PATH).
"""

from __future__ import annotations

import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from contextlib import contextmanager

__all__ = ["chromium_path", "CHROMIUM_HINT", "require_browser", "editor_server", "launch", "EditorPage"]

#: What to do when no Chromium is found (one line).
CHROMIUM_HINT = ("no Chromium for the editor's browser tests: on Debian/Ubuntu `sudo apt-get install chromium` "
                 "(make test does it when run as root), or set TRACER_CHROMIUM=/path/to/chromium")


def chromium_path():
    """The system Chromium's path, or None."""
    given = os.environ.get("TRACER_CHROMIUM")
    if given:
        return given if os.path.exists(given) else None
    for name in ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable"):
        found = shutil.which(name)
        if found:
            return found
    return None


class Served(str):
    """The URL of a served editor (with its token), and what the tests need besides:
    ``port``, ``token``, ``base`` (the URL without the token), ``proc`` (the process) and
    :meth:`log` (what it printed so far)."""

    def log(self) -> str:
        self._log.seek(0)
        return self._log.read()


def require_browser():
    """For a browser test module, at its top: skip the module, with one line saying what to
    install, when Panel, Playwright or Chromium is missing; except that under CI (``CI`` set)
    a missing Chromium is an error, since CI must run these tests."""
    import pytest

    pytest.importorskip("panel", reason="the scene editor needs Panel: pip install 'bubbleoptics[editor]'")
    pytest.importorskip("playwright", reason="the browser tests need Playwright: pip install 'bubbleoptics[test]'")
    if chromium_path() is None:
        if os.environ.get("CI"):
            raise RuntimeError(CHROMIUM_HINT)
        pytest.skip(CHROMIUM_HINT, allow_module_level=True)


@contextmanager
def editor_server(scene=None, *, width=320, height=320, cwd=None, timeout=120, stop=signal.SIGTERM, args=(),
                  check_exit=True):
    """``tracer edit --no-browser`` in a subprocess on a free port, with extra command-line
    *args*; yields its URL (a :class:`Served`: the token in its query), then stops it with the
    signal *stop* (SIGTERM; SIGINT is Ctrl-C) and checks that it exits with status 0."""
    import re

    from .app import free_port

    port = free_port()
    cmd = [sys.executable, "-m", "tracer", "edit", "--no-browser", "--port", str(port), "--width", str(width),
           "--height", str(height), *args] + ([os.fspath(scene)] if scene is not None else [])
    log = tempfile.TemporaryFile(mode="w+")  # not a pipe: a full pipe would stall the server
    proc = subprocess.Popen(cmd, cwd=cwd, stdout=log, stderr=subprocess.STDOUT, text=True)
    end = time.monotonic() + timeout
    try:
        while True:
            if proc.poll() is not None:
                log.seek(0)
                raise RuntimeError(f"tracer edit exited with {proc.returncode}: {log.read()[-2000:]}")
            log.seek(0)
            m = re.search(r"serving (http://\S+)", log.read())
            if m:
                try:  # a connection, not a request: a GET of the page would open an editor session
                    socket.create_connection(("127.0.0.1", port), timeout=2).close()
                    break
                except OSError:
                    pass
            if time.monotonic() > end:
                raise RuntimeError("tracer edit did not start")
            time.sleep(0.1)
        url = Served(m.group(1))
        url.port, url.proc, url._log = port, proc, log
        url.token = (re.search(r"[?&]token=([^&]+)", url) or [None, None])[1]
        url.base = f"http://127.0.0.1:{port}/"
        yield url
    finally:
        proc.send_signal(stop)
        try:
            proc.wait(timeout=20)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
        log.close()
    if check_exit and proc.returncode != 0:
        raise RuntimeError(f"tracer edit did not stop cleanly on signal {stop} (status {proc.returncode})")


@contextmanager
def launch(path=None, args=()):
    """A headless Chromium (Playwright's sync API) launched by its path, with extra *args*
    (e.g. ``--host-resolver-rules=...``)."""
    from playwright.sync_api import sync_playwright

    path = path or chromium_path()
    flags = ["--no-sandbox"] if hasattr(os, "geteuid") and os.geteuid() == 0 else []
    flags += ["--disable-gpu", "--disable-background-networking", "--disable-component-update", "--disable-sync",
              "--no-first-run", *args]
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=path, args=flags)
        try:
            yield browser
        finally:
            browser.close()


# JavaScript run in the page: the preview's canvas (the one drawn at the image's size, found
# through Panel's shadow roots) and a cheap fingerprint of its pixels.
_FIND_CANVAS = """(side) => {
  const out = [];
  const walk = (root) => {
    for (const el of root.querySelectorAll('*')) {
      if (el.tagName === 'CANVAS') out.push(el);
      if (el.shadowRoot) walk(el.shadowRoot);
    }
  };
  walk(document);
  const dpr = window.devicePixelRatio || 1;
  return out.find(c => c.width === Math.round(side * dpr)) || null;
}"""
_FINGERPRINT = """(c) => {
  const s = window.__small || (window.__small = Object.assign(document.createElement('canvas'), {width: 96, height: 96}));
  const g = s.getContext('2d', {willReadFrequently: true});
  g.drawImage(c, 0, 0, 96, 96);
  const d = g.getImageData(0, 0, 96, 96).data;
  let h = 0;
  for (let i = 0; i < d.length; i += 4) h = (h * 31 + d[i] + 7 * d[i + 1] + 13 * d[i + 2]) >>> 0;
  return h;
}"""
# window.__record(canvas): from now on, the page's time of every click (window.__clicks) and of
# every change of the canvas's pixels (window.__changes), checked every animation frame.
_RECORD = """(c) => {
  const fp = %s;
  window.__clicks = []; window.__changes = [];
  if (!window.__clickHook) {
    window.addEventListener('click', () => window.__clicks.push(performance.now()), true);
    window.__clickHook = true;
  }
  let last = fp(c);
  window.__recording = true;
  const tick = () => {
    const now = fp(c);
    if (now !== last) { window.__changes.push(performance.now()); last = now; }
    if (window.__recording) requestAnimationFrame(tick);
  };
  requestAnimationFrame(tick);
}""" % _FINGERPRINT
# Installed once: window.__watch(canvas) starts polling the canvas every animation frame and
# resolves with performance.now() when its fingerprint changes.
_WATCH = """(c) => {
  const fp = %s;
  window.__watch = (canvas) => {
    const start = fp(canvas);
    return new Promise((resolve) => {
      const tick = () => { if (fp(canvas) !== start) resolve(performance.now()); else requestAnimationFrame(tick); };
      requestAnimationFrame(tick);
    });
  };
  window.__canvas = c;
}""" % _FINGERPRINT


class EditorPage:
    """A page with the editor open, and the steps a person takes in it."""

    def __init__(self, browser, url, view_px=560, timeout=60):
        self.page = browser.new_page(viewport={"width": 1300, "height": 1200})
        self.page.set_default_timeout(timeout * 1000)
        self.page.goto(url)
        self.view_px = view_px
        self.wait_full(0)

    def field(self, name):
        return self.page.locator(f".field-{name} input")

    def message(self, name):
        return self.page.locator(f".message-{name} .msg")

    def button(self, name):
        return self.page.get_by_role("button", name=name, exact=True)

    def fill(self, name, text):
        box = self.field(name)
        box.fill(str(text))
        box.press("Enter")

    def version(self, stage="full"):
        loc = self.page.locator(f".editor-stage .stage-{stage}")
        return int(loc.get_attribute("data-version")) if loc.count() else -1

    def wait_full(self, after, timeout=180):
        """Wait until the full-resolution image of a version newer than *after* is shown."""
        end = time.monotonic() + timeout
        while self.version("full") <= after:
            if time.monotonic() > end:
                raise TimeoutError(f"no full image after version {after}")
            self.page.wait_for_timeout(20)
        return self.version("full")

    def shown(self):
        """The version on screen, whatever its stage (-1: none)."""
        loc = self.page.locator(".editor-stage span")
        return int(loc.get_attribute("data-version")) if loc.count() else -1

    def click_and_wait(self, button):
        v = self.version()
        self.button(button).click()
        return self.wait_full(v)

    def expect_message(self, name, text):
        """Wait until field *name*'s inline message contains *text*; returns the message."""
        self.page.locator(f".message-{name}").get_by_text(text).wait_for()
        return self.message(name).inner_text()

    def status(self):
        loc = self.page.locator(".editor-status .msg")
        return loc.inner_text() if loc.count() else ""

    def screenshot(self, path=None):
        return self.page.locator(".editor-image").screenshot(path=path)

    def select(self, which, label_start):
        sel = self.page.locator("select").nth({"objects": 0, "lights": 1}[which])
        options = sel.locator("option").all_inner_texts()
        label = next(o for o in options if o.startswith(label_start))
        sel.select_option(label=label)
        return label

    def options(self, which):
        return self.page.locator("select").nth({"objects": 0, "lights": 1}[which]).locator("option").all_inner_texts()

    def canvas(self):
        return self.page.evaluate_handle(_FIND_CANVAS, self.view_px)

    def watch(self):
        """Start watching the preview's canvas; returns a handle whose promise resolves with the
        page's time at the next change of its pixels."""
        c = self.canvas()
        self.page.evaluate(_WATCH, c)
        return self.page.evaluate_handle("() => window.__watch(window.__canvas)")

    def record(self):
        """Start recording clicks and changes of the preview's pixels (:meth:`recorded`)."""
        self.page.evaluate(_RECORD, self.canvas())

    def recorded(self):
        """``(click times, pixel change times)`` in ms of page time since :meth:`record`; stops it."""
        return self.page.evaluate("() => { window.__recording = false; return [window.__clicks, window.__changes]; }")

    def now(self):
        return self.page.evaluate("() => performance.now()")

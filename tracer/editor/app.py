"""The scene editor's Panel app: the coursework's Qt window as Panel widgets.

The left column holds the coursework's functions with its button names: **Load**, the objects
and lights lists, **Change** / **Add** / **Delete** (lights), **Change parameters** and
**Change geometry** (objects), **Clear**; then what it lacked: the camera's orbit and zoom, the
render settings, **Undo**, **Save image**, **Save scene**, **Save commands**.  The right column
is the preview (a Bokeh image: click it to pick a pixel) and the picked pixel's film: its
reflectance spectrum and colour (:func:`tracer.editor.preview.film_at_pixel`).

Every edit goes through :class:`tracer.editor.model.EditorModel`; a bad value shows its message
under its field and changes nothing (the previous image stays).  Each change renders a small
preview (a sixth of the width and height), then the full image
(:class:`tracer.editor.preview.PreviewRenderer`).

Files are read and written through a :class:`tracer.scene.file_access.FileAccess`: a served editor
confines them to its root folder, reads regular files only within a size limit, and never
writes over a file.  Reading and writing run in a thread pool, off the server's event loop;
the renders run in the scheduler's thread (:mod:`tracer.editor.scheduler`).  Who may connect
at all is :mod:`tracer.editor.security`'s.
"""

from __future__ import annotations

import asyncio
import html
import io
import os
import signal
import socket
import sys
import threading
import time
import weakref
from concurrent.futures import ThreadPoolExecutor
from functools import partial
from pathlib import Path

import numpy as np
from bubbleoptics.messages import shorten
import panel as pn
from bokeh.events import ConnectionLost, Tap
from bokeh.models import ColumnDataSource
from bokeh.plotting import figure

from ..scene.errors import SceneError
from ..scene.file_access import ANYWHERE, FileAccess, FileAccessError
from ..scene.load import load_scene
from ..movie.commands import BUBBLE_FIELDS, FILM_KIND_FIELDS, PHONG_FIELDS
from ..rendering.output import display_codes
from ..scene.model import Scene
from .model import MAX_SIDE, EditorModel, FieldError, format_number
from .preview import PreviewRenderer
from .scheduler import scheduler

__all__ = ["EditorApp", "serve", "free_port", "MAX_SESSIONS", "MAX_SCENE_BYTES", "MAX_ASSET_BYTES",
           "MAX_IMAGE_PIXELS"]

#: The image's size (pixels) unless the scene's [render] table or the caller gives one.
DEFAULT_SIZE = 960
#: The preview's side on the page, in CSS pixels.
VIEW_PX = 560
#: The most editors (browser tabs) a server keeps open at once; another tab is told to wait.
MAX_SESSIONS = 8
#: The largest scene file (or upload) a served editor reads, in bytes.
MAX_SCENE_BYTES = 8 * 2**20
#: The largest file a served editor's scene may name (a mesh, an image, a film), in bytes.
MAX_ASSET_BYTES = 64 * 2**20
#: The most pixels an environment image of a served editor's scene may have (4096 x 2048).
MAX_IMAGE_PIXELS = 4096 * 2048
#: Reading and writing files, off the server's event loop.
_IO = ThreadPoolExecutor(max_workers=2, thread_name_prefix="tracer-editor-io")

_FILM_FIELDS = [f for f in BUBBLE_FIELDS if f != "shininess"]
#: The editors alive in this process (their previews are stopped when the server stops).
_APPS = weakref.WeakSet()
#: A widget's caption: ``label`` from Panel 1.9 on (``name`` is deprecated there), ``name`` before.
_LABEL = "label" if "label" in pn.widgets.TextInput.param else "name"


def _button(text):
    return pn.widgets.Button(**{_LABEL: text})


class _Field:
    """A labelled text field with its inline message below it."""

    def __init__(self, name, label=None, value="", width=110):
        self.name = name
        self.input = pn.widgets.TextInput(**{_LABEL: label or name}, value=str(value), width=width,
                                          css_classes=[f"field-{name}"])
        self.message = pn.pane.HTML("", visible=False, css_classes=["field-message", f"message-{name}"],
                                    styles={"color": "#b00020", "font-size": "12px"}, margin=(0, 5), width=width + 60)
        self.panel = pn.Column(self.input, self.message, margin=0)

    @property
    def value(self):
        return self.input.value

    @value.setter
    def value(self, v):
        self.input.value = str(v)

    def error(self, text):
        self.message.object = f'<span class="msg">{html.escape(text)}</span>'
        self.message.visible = True

    def clear(self):
        if self.message.visible:
            self.message.object = ""
            self.message.visible = False


def _number_text(v):
    if isinstance(v, (tuple, list)):
        return " ".join(format_number(x) for x in v)
    if isinstance(v, (int, float, np.floating)) and not isinstance(v, bool):
        return format_number(v)
    return str(v)


class EditorApp:
    """The editor for *scene* (a :class:`tracer.Scene`, a scene file's path, or None: the
    built-in scene).  ``layout`` is the Panel object to show; ``width`` and ``height`` the full
    image's size (default: the scene's ``[render]`` table, else 960 x 960)."""

    def __init__(self, scene=None, *, width=None, height=None, view_px=VIEW_PX, access: FileAccess = ANYWHERE):
        self.access = access
        if scene is not None and not isinstance(scene, Scene):
            scene = load_scene(scene, access)
        rd = (scene.render_defaults if scene is not None else {})
        self.width = int(width or rd.get("width", DEFAULT_SIZE))
        self.height = int(height or rd.get("height", DEFAULT_SIZE))
        self.model = EditorModel(scene, size=(self.width, self.height))
        self._doc = pn.state.curdoc
        self._closed = False
        self.image = None  # the last full-resolution linear image
        self.image_codes = None  # its display codes (8-bit sRGB at the exposure)
        self.image_version = -1  # the version they show
        self.stage = ""  # the stage on screen: "", "preview", "full", "cleared"
        self.shown_version = 0
        self.pick = None
        self._t_edit = None
        self._server_ms, self._render_ms = {}, {}
        self._build(view_px)
        self.preview = PreviewRenderer(self._on_image, self._on_render_error)
        _APPS.add(self)
        self._fill_lists()
        if self.model.budget_notes:
            self._say("the scene's render settings are beyond the editor's budget: "
                      + ", ".join(self.model.budget_notes))
        if self._served():  # the first render once the page is connected (an image sent earlier can be lost)
            pn.state.onload(self.refresh)
            pn.state.on_session_destroyed(lambda context: self.close())
            # the tab is gone (closed, reloaded, its network lost): stop its renders now, not when
            # Bokeh discards the unused session many seconds later
            self._doc.on_event(ConnectionLost, lambda event: self.close())
        else:
            self.refresh()

    def close(self):
        """Cancel this editor's renders (a served page's session does this when its tab goes)."""
        self._closed = True
        self.preview.close()

    @property
    def closed(self) -> bool:
        return self._closed

    def _served(self):
        return self._doc is not None and getattr(self._doc, "session_context", None) is not None

    # -- layout ----------------------------------------------------------------------------
    def _build(self, view_px):
        F = _Field
        self.scene_path = F("scene_path", "scene file", getattr(self.model.loaded, "source", ""), width=300)
        self.load_button = _button("Load")
        # or a file from the person's computer: read from memory (never written to the server's
        # disk), its FILE:LINE messages naming it, the files it names looked for in the root
        self.upload = pn.widgets.FileInput(accept=".toml,.txt,.scene", css_classes=["editor-upload"])
        self.objects = pn.widgets.Select(**{_LABEL: "objects"}, options=[], size=6, width=300)
        self.lights = pn.widgets.Select(**{_LABEL: "lights"}, options=[], size=4, width=300)
        self.light_fields = {k: F(k) for k in ("x", "y", "z", "intensity")}
        self.change_button = _button("Change")
        self.add_button = _button("Add")
        self.delete_button = _button("Delete")
        self.param_fields = {k: F(k) for k in list(PHONG_FIELDS) + ["shininess_bubble", "n_film"] + _FILM_FIELDS}
        setattr(self.param_fields["shininess_bubble"].input, _LABEL, "shininess")
        self.profile = pn.widgets.Select(**{_LABEL: "profile"}, options=["uniform", "draining", "map"], width=110)
        self.params_button = _button("Change parameters")
        self.geometry_fields = {k: F(k, value=v) for k, v in (("dx", 0), ("dy", 0), ("dz", 0), ("k", 1))}
        self.geometry_button = _button("Change geometry")
        self.camera_fields = {"orbit": F("orbit", "orbit (degrees)", 15), "zoom": F("zoom", "zoom (factor)", 1.25)}
        self.orbit_button = _button("Orbit")
        self.zoom_button = _button("Zoom")
        s = self.model.settings
        self.setting_fields = {"depth": F("depth", value=s["depth"]), "spp": F("spp", value=s["spp"]),
                               "spectral_samples": F("spectral_samples", "bands", s["spectral_samples"]),
                               "exposure": F("exposure", value=format_number(s["exposure"]))}
        self.settings_button = _button("Apply settings")
        self.undo_button = _button("Undo")
        self.clear_button = _button("Clear")
        self.out_image = F("out_image", "image file (.png)", "editor.png", width=220)
        self.save_image_button = _button("Save image")
        self.out_scene = F("out_scene", "scene file (.toml)", "edited.toml", width=220)
        self.save_scene_button = _button("Save scene")
        self.out_commands = F("out_commands", "commands file (.txt)", "edits.txt", width=220)
        self.save_commands_button = _button("Save commands")
        # the same three files as downloads to the person's computer (no server path at all)
        self.download_image = pn.widgets.FileDownload(callback=self._image_download, filename="editor.png",
                                                      label="Download image", css_classes=["download-image"])
        self.download_scene = pn.widgets.FileDownload(callback=self._scene_download, filename="edited.toml",
                                                      label="Download scene", css_classes=["download-scene"])
        self.download_commands = pn.widgets.FileDownload(callback=self._commands_download, filename="edits.txt",
                                                         label="Download commands",
                                                         css_classes=["download-commands"])
        self.status = pn.pane.HTML("", css_classes=["editor-status"], width=560)
        self.stage_text = pn.pane.HTML("", css_classes=["editor-stage"])

        # the preview: an RGBA image in a Bokeh figure (Tap gives the picked pixel)
        w, h = self.width, self.height
        side = view_px
        fw, fh = (side, max(1, round(side * h / w))) if w >= h else (max(1, round(side * w / h)), side)
        self.source = ColumnDataSource(data=dict(image=[np.zeros((1, 1), np.uint32)]))
        fig = figure(width=fw, height=fh, x_range=(0, w), y_range=(0, h), tools="tap", toolbar_location=None,
                     min_border=0, outline_line_color=None, match_aspect=True)
        fig.axis.visible = False
        fig.grid.visible = False
        fig.image_rgba(image="image", x=0, y=0, dw=w, dh=h, source=self.source)
        fig.on_event(Tap, self._on_tap)
        self.figure = fig
        self._view_size = (fw, fh)
        self.image_pane = pn.Column(pn.pane.Bokeh(fig, margin=0), css_classes=["editor-image"], width=fw, height=fh,
                                    margin=0)
        self.spectrum_source = ColumnDataSource(data=dict(wl=[], R=[]))
        spec = figure(width=300, height=220, title="picked pixel: film reflectance", x_axis_label="wavelength (nm)",
                      y_axis_label="R", toolbar_location=None, x_range=(360, 780))
        spec.line("wl", "R", source=self.spectrum_source, line_width=2)
        self.spectrum = pn.pane.Bokeh(spec)
        self.swatch = pn.pane.HTML("", width=300, css_classes=["editor-pick"])

        for button, handler in [
            (self.load_button, self.on_load), (self.save_image_button, self.on_save_image),
            (self.save_scene_button, self.on_save_scene), (self.save_commands_button, self.on_save_commands),
        ]:
            button.on_click(self._async_handler(handler))
        self.upload.param.watch(self._async_handler(self.on_upload), "value")
        for button, handler in [
            (self.change_button, self.on_change_light),
            (self.add_button, self.on_add_light), (self.delete_button, self.on_delete_light),
            (self.params_button, self.on_change_parameters), (self.geometry_button, self.on_change_geometry),
            (self.orbit_button, self.on_orbit), (self.zoom_button, self.on_zoom),
            (self.settings_button, self.on_settings), (self.undo_button, self.on_undo),
            (self.clear_button, self.on_clear),
        ]:
            button.on_click(lambda event, h=handler: self._guard(h))
        self.objects.param.watch(lambda e: self._fill_object_form(), "value")
        self.lights.param.watch(lambda e: self._fill_light_form(), "value")
        self.profile.param.watch(lambda e: self._show_film_fields(), "value")

        def row(fields):
            return pn.Row(*[f.panel for f in fields], margin=0)

        pf = self.param_fields
        self.phong_box = pn.Column(row([pf[k] for k in ("color", "ambient", "diffuse")]),
                                   row([pf[k] for k in ("specular", "transmission", "shininess", "ior")]), margin=0)
        self.film_box = pn.Column(pn.Row(self.profile, pf["n_film"].panel, pf["shininess_bubble"].panel, margin=0),
                                  row([pf[k] for k in ("thickness_nm", "top_nm", "bottom_nm")]),
                                  row([pf[k] for k in ("exponent", "swirl", "swirl_scale")]), margin=0)
        controls = pn.Column(
            pn.pane.Markdown("### Scene"), pn.Row(self.scene_path.panel, self.load_button), self.upload,
            self.objects, self.lights,
            pn.pane.Markdown("### Light"), row(self.light_fields.values()),
            pn.Row(self.change_button, self.add_button, self.delete_button),
            pn.pane.Markdown("### Object"), self.phong_box, self.film_box, self.params_button,
            row(self.geometry_fields.values()), self.geometry_button,
            pn.pane.Markdown("### Camera and render"),
            pn.Row(self.camera_fields["orbit"].panel, self.orbit_button, self.camera_fields["zoom"].panel,
                   self.zoom_button),
            row(self.setting_fields.values()), self.settings_button,
            pn.Row(self.undo_button, self.clear_button),
            pn.Row(self.out_image.panel, self.save_image_button), pn.Row(self.out_scene.panel, self.save_scene_button),
            pn.Row(self.out_commands.panel, self.save_commands_button),
            pn.Row(self.download_image, self.download_scene, self.download_commands),
            width=620,
        )
        view = pn.Column(self.image_pane, self.stage_text, self.status,
                         pn.Row(self.spectrum, self.swatch))
        self.layout = pn.Row(controls, view, css_classes=["tracer-editor"])

    # -- filling the lists and forms --------------------------------------------------------
    def _fill_lists(self):
        objs = self.model.objects()
        labels = [f"{name} ({kind})" for name, kind in objs]
        self._object_names = dict(zip(labels, (n for n, _ in objs)))
        keep = self.objects.value if self.objects.value in labels else (labels[0] if labels else None)
        self.objects.options = labels
        self.objects.value = keep
        lights = self.model.lights
        labels = [f"{i + 1}: ({', '.join(format_number(c) for c in l.position)}) intensity "
                  f"{format_number(l.intensity)}" for i, l in enumerate(lights)]
        number = self.selected_light()
        self.lights.options = labels
        self.lights.value = labels[min(number, len(labels)) - 1] if labels and number else (labels[0] if labels else None)
        self._fill_object_form()
        self._fill_light_form()

    def selected_light(self):
        """The selected light's number (from 1), or None."""
        v = self.lights.value
        return int(v.split(":")[0]) if v else None

    def selected_object(self):
        return self._object_names.get(self.objects.value)

    def _fill_light_form(self):
        n = self.selected_light()
        if n is None or n > len(self.model.lights):
            return
        light = self.model.lights[n - 1]
        for k, v in zip("xyz", light.position):
            self.light_fields[k].value = format_number(v)
        self.light_fields["intensity"].value = format_number(light.intensity)

    def _fill_object_form(self):
        name = self.selected_object()
        if name is None:
            self.phong_box.visible = self.film_box.visible = False
            return
        params = self.model.parameters(name)
        bubble = "profile" in params
        self.phong_box.visible, self.film_box.visible = not bubble, bubble
        for k, v in params.items():
            key = "shininess_bubble" if bubble and k == "shininess" else k
            if key == "profile":
                self.profile.value = v
            elif key in self.param_fields:
                self.param_fields[key].value = _number_text(v)
        self._show_film_fields()

    def _show_film_fields(self):
        for k in _FILM_FIELDS:
            self.param_fields[k].panel.visible = k in FILM_KIND_FIELDS.get(self.profile.value, ())

    # -- actions ----------------------------------------------------------------------------
    def _all_fields(self):
        groups = (self.light_fields, self.param_fields, self.geometry_fields, self.camera_fields, self.setting_fields)
        return [f for g in groups for f in g.values()] + [self.scene_path, self.out_image, self.out_scene,
                                                          self.out_commands]

    def _guard(self, handler):
        """Run a button's handler: a FieldError goes under its field (or to the status line),
        nothing else changes."""
        self._t_edit = time.perf_counter()
        with pn.io.hold():  # the form's changes go to the page in one message
            self._guard_held(handler)

    def _async_handler(self, handler):
        """A Panel callback that runs *handler* (a generator: it yields ``(function, args)``
        to run in the file thread pool and receives the result) without blocking the server's
        event loop: the file work runs in :data:`_IO`, the widgets change on the loop."""

        async def callback(event):
            self._t_edit = time.perf_counter()
            for f in self._all_fields():
                f.clear()
            steps = handler()
            result, failure = None, None
            try:
                while True:
                    try:
                        work = steps.send(result) if failure is None else steps.throw(failure)
                    except StopIteration as done:
                        message = done.value
                        break
                    failure = None
                    try:
                        result = await asyncio.get_running_loop().run_in_executor(_IO, partial(*work))
                    except Exception as exc:
                        failure = exc
            except Exception as exc:
                with pn.io.hold():
                    self._report(exc)
                return
            with pn.io.hold():
                self._say(message or "")

        return callback

    def _guard_held(self, handler):
        for f in self._all_fields():
            f.clear()
        try:
            message = handler()
        except Exception as exc:
            self._report(exc)
            return
        self._say(message or "")

    def _report(self, exc):
        """Show a handler's failure: under its field, and on the status line."""
        try:
            raise exc
        except FieldError as err:
            field = self._field_for(err.field)
            if field is not None:
                field.error(str(err))
            self._say(str(err), error=True)
            return
        except SceneError as err:
            self.scene_path.error(str(err))
            self._say(str(err), error=True)
            return
        except (ValueError, OSError) as err:
            self._say(_one_line(err), error=True)
        except MemoryError:
            self._say("out of memory: the file or the render is too large for this server", error=True)

    def _field_for(self, name):
        for group in (self.light_fields, self.geometry_fields, self.camera_fields, self.setting_fields):
            if name in group:
                return group[name]
        if name == "shininess" and self.film_box.visible:
            return self.param_fields["shininess_bubble"]
        if name in self.param_fields:
            return self.param_fields[name]
        return {"light": self.light_fields["x"]}.get(name)

    def _say(self, text, error=False):
        color = "#b00020" if error else "#333"
        text = _one_line(text)
        self.status.object = f'<span class="msg" style="color:{color}">{html.escape(text)}</span>' if text else ""

    def _edited(self, message):
        self.refresh()  # first: the render starts while the lists and forms are updated
        self._fill_lists()
        return message

    def on_load(self):
        """**Load** the scene file in the path field (read in the file thread pool)."""
        path = self.scene_path.value.strip()
        if not path:
            raise FieldError("scene_path", "give a scene file's path (TOML or the coursework's format)")
        scene = yield (load_scene, path, self.access)  # SceneError: the old scene stays
        self.model.replace(scene)  # FieldError for a name with a control character
        self._edited(None)
        return self._loaded_message(path)

    def _loaded_message(self, name):
        notes = self.model.budget_notes
        return f"loaded {name}" + (f" (render settings within the editor's budget: {', '.join(notes)})"
                                   if notes else "")

    def on_upload(self):
        """**Load** a file chosen in the browser (the file input): parsed from memory."""
        if self.upload.value is None:
            return None
        name = Path(self.upload.filename or "scene.toml").name
        data = self.upload.value
        limit = self.access.max_scene_bytes or self.access.max_bytes
        if limit is not None and len(data) > limit:
            raise FieldError("scene_path", f"{name}: {len(data):,} bytes, more than the {limit:,} allowed for a scene"
                                           " file")
        scene = yield (_parse_upload, name, data, self.access)
        self.model.replace(scene)
        self._edited(None)
        return self._loaded_message(name)

    def on_change_light(self):
        n = self.selected_light()
        if n is None:
            raise FieldError("light", "select a light first")
        f = self.light_fields
        self.model.change_light(n, f["x"].value, f["y"].value, f["z"].value, f["intensity"].value)
        return self._edited(f"light {n} changed")

    def on_add_light(self):
        f = self.light_fields
        self.model.add_light(f["x"].value, f["y"].value, f["z"].value, f["intensity"].value)
        n = len(self.model.lights)
        self._fill_lists()
        self.lights.value = self.lights.options[n - 1]
        return self._edited(f"light {n} added")

    def on_delete_light(self):
        n = self.selected_light()
        if n is None:
            raise FieldError("light", "select a light first")
        self.model.delete_light(n)
        return self._edited(f"light {n} deleted")

    def on_change_parameters(self):
        name = self.selected_object()
        if name is None:
            raise FieldError(None, "select an object first")
        params = self.model.parameters(name)
        given = {}
        for k in params:
            if k == "profile":
                given[k] = self.profile.value
            elif k == "shininess" and "profile" in params:
                given[k] = self.param_fields["shininess_bubble"].value
            elif self.param_fields[k].panel.visible or "profile" not in params:
                given[k] = self.param_fields[k].value
        self.model.change_parameters(name, **given)
        return self._edited(f"{name}: parameters changed")

    def on_change_geometry(self):
        name = self.selected_object()
        if name is None:
            raise FieldError(None, "select an object first")
        g = self.geometry_fields
        self.model.change_geometry(name, g["dx"].value, g["dy"].value, g["dz"].value, g["k"].value)
        return self._edited(f"{name}: geometry changed")

    def on_orbit(self):
        self.model.orbit(self.camera_fields["orbit"].value)
        return self._edited("camera turned")

    def on_zoom(self):
        self.model.zoom(self.camera_fields["zoom"].value)
        return self._edited("camera zoomed")

    def on_settings(self):
        self.model.set_settings(**{k: f.value for k, f in self.setting_fields.items()})
        return self._edited("render settings applied")

    def on_undo(self):
        if not self.model.undo():
            return "nothing to undo"
        s = self.model.settings
        for k, f in self.setting_fields.items():
            f.value = format_number(s[k]) if k == "exposure" else s[k]
        return self._edited("undone")

    def on_clear(self):
        """**Clear** the screen (the next change, or an undo, renders again)."""
        self._show(np.zeros((1, 1, 3), np.uint8), "cleared", self.model.version)
        return "cleared"

    def _saved(self, path, renamed, what=""):
        shown = self.access.relative(path)
        return f"saved {shown}" + (what and f" ({what})") + (
            " (a file of the name asked for exists: never overwritten)" if renamed else "")

    def _save(self, field, suffixes, make_files):
        """Write new files named after *field*'s text (:meth:`FileAccess.save_new`), in the
        file thread pool; a stop of the server waits for a save in progress."""
        text = field.value.strip()
        if not text:
            raise FieldError(field.name, f"{getattr(field.input, _LABEL)}: give a file name")
        try:
            return (yield (_save_new, self.access, text, suffixes, make_files))
        except FileAccessError as err:
            raise FieldError(field.name, str(err)) from None

    def _full_image(self, field=None):
        """The full image's display codes (of the latest edit, at its exposure)."""
        if self.image_codes is None or self.image_version != self.model.version:
            raise FieldError(field, "the full-resolution image of the latest edit is not rendered yet: wait until"
                                    " it is shown, then save")
        return self.image_codes

    def on_save_image(self):
        codes = self._full_image("out_image")
        path, renamed = yield from self._save(self.out_image, (".png",), lambda stem: {f"{stem}.png": _png_bytes(codes)})
        return self._saved(path, renamed)

    def on_save_scene(self):
        files = self.model.scene_files_maker()  # the scene as it is now, not after a later edit
        path, renamed = yield from self._save(self.out_scene, (".toml",), files)
        return self._saved(path, renamed)

    def on_save_commands(self):
        data = self.model.commands_text().encode("utf-8")
        path, renamed = yield from self._save(self.out_commands, (".txt",), lambda stem: {f"{stem}.txt": data})
        return self._saved(path, renamed, f"{len(data.splitlines()) - 3} edits")

    # -- downloads (the browser's: Panel's FileDownload asks for the bytes on a click) -------------
    def _image_download(self):
        try:
            return io.BytesIO(_png_bytes(self._full_image()))
        except FieldError as err:
            self._say(str(err), error=True)
            return None

    def _scene_download(self):
        try:
            files = self.model.scene_files_maker()("edited")
        except ValueError as err:
            self._say(_one_line(err), error=True)
            return None
        if len(files) == 1:
            self.download_scene.filename = "edited.toml"
            return io.BytesIO(next(iter(files.values())))
        import zipfile

        out = io.BytesIO()  # the TOML file and the arrays it names, in one archive
        with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as z:
            for name, data in files.items():
                z.writestr(name, data)
        self.download_scene.filename = "edited.zip"
        out.seek(0)
        return out

    def _commands_download(self):
        return io.BytesIO(self.model.commands_text().encode("utf-8"))

    # -- rendering --------------------------------------------------------------------------
    def refresh(self):
        """Render the model's scene: a small preview, then the full image."""
        self.preview.request(self.model.scene, self.model.render_settings(self.width, self.height),
                             self.model.settings["exposure"], self.model.version)

    def _on_image(self, shown):
        if shown.version != self.model.version:
            return  # an edit came after it: its own render follows
        if shown.linear is not None:
            self.image, self.image_codes, self.image_version = shown.linear, shown.codes, shown.version
        codes = _fit(shown.codes, self._view_size) if shown.stage == "full" else shown.codes
        self._schedule(partial(self._show, codes, shown.stage, shown.version, shown.seconds))

    def _on_render_error(self, version, exc):
        self._schedule(partial(self._say, f"render failed: {exc}", True))

    def _schedule(self, fn):
        if self._closed:
            return
        if self._served():
            self._doc.add_next_tick_callback(fn)
        else:  # a notebook (or no document yet): Panel and Bokeh push the change themselves
            fn()
            pn.io.push_notebook(self.image_pane)

    def _show(self, codes, stage, version, seconds=0.0):
        h, w = codes.shape[:2]
        rgba = np.empty((h, w, 4), np.uint8)
        rgba[..., :3] = codes[..., :3]
        rgba[..., 3] = 255
        self.source.data = dict(image=[np.ascontiguousarray(rgba[::-1]).view(np.uint32)[..., 0]])
        self.stage, self.shown_version = stage, version
        text = {"preview": f"preview {w}x{h} (render {seconds * 1e3:.0f} ms), refining...",
                "full": f"{w}x{h} (render {seconds * 1e3:.0f} ms)", "cleared": "cleared"}[stage]
        # the server's share of the wait: from the button's handler to this image being sent
        server_ms = (time.perf_counter() - self._t_edit) * 1e3 if self._t_edit else 0.0
        self._server_ms[stage] = server_ms
        self._render_ms[stage] = seconds * 1e3
        data = " ".join(f'data-{k}-{st}="{v[st]:.1f}"' for k, v in (("server", self._server_ms),
                                                                    ("render", self._render_ms)) for st in v)
        self.stage_text.object = f'<span class="stage-{stage}" data-version="{version}" {data}>{text}</span>'

    def _on_tap(self, event):
        col, row = int(event.x), self.height - 1 - int(event.y)
        if not (0 <= col < self.width and 0 <= row < self.height):
            return
        # a job of the render scheduler: it takes its turn between render steps, the page waits not
        self.preview.pick(self.model.scene, col, row, self.width, self.height,
                          lambda sample: self._schedule(partial(self._show_pick, col, row, sample)))

    def _show_pick(self, col, row, sample):
        self.pick = (col, row, sample)
        if sample is None:
            self.spectrum_source.data = dict(wl=[], R=[])
            self.swatch.object = f"pixel ({col}, {row}): no bubble"
            return
        self.spectrum_source.data = dict(wl=sample.wavelengths_nm, R=sample.reflectance)
        r, g, b = (int(round(255 * min(1.0, max(0.0, c)))) for c in sample.srgb)
        self.swatch.object = (
            f'<div style="display:flex;gap:8px;align-items:center"><div style="width:48px;height:48px;'
            f'background:rgb({r},{g},{b});border:1px solid #888"></div><div>pixel ({col}, {row}): '
            f'<span class="pick-name">{html.escape(sample.bubble)}</span>, film {sample.thickness_nm:.0f} nm at '
            f'{sample.angle_deg:.1f}°<br>colour #{r:02x}{g:02x}{b:02x} (D65)</div></div>')


# ------------------------------------------------------------------------------------------
# serving
# ------------------------------------------------------------------------------------------
def free_port(address="127.0.0.1") -> int:
    """A TCP port free on *address* now."""
    with socket.socket() as s:
        s.bind((address, 0))
        return s.getsockname()[1]


def _one_line(text) -> str:
    """A message as one line of at most 300 characters (a file's text never spills into it)."""
    text = " ".join(str(text).split())
    return shorten(text, 300)


def _parse_upload(name, data, access):
    """The scene in an uploaded file's bytes (never written to disk): the files it names are
    looked for in *access*'s root."""
    from ..scene.block_format import parse_coursework_text, split_lines
    from ..scene.text import decode_scene_bytes
    from ..scene.toml_read import parse_toml_text

    text = decode_scene_bytes(name, data)
    if name.lower().endswith(".toml"):
        return parse_toml_text(text, name, access, base=access.root or Path.cwd())
    return parse_coursework_text(split_lines(text), name)


_SAVES_LOCK = threading.Condition()
_SAVES_RUNNING = [0]


def _save_new(access, text, suffixes, make_files):
    """:meth:`FileAccess.save_new`, counted: a stop of the server waits for it to end."""
    with _SAVES_LOCK:
        _SAVES_RUNNING[0] += 1
    try:
        return access.save_new(text, suffixes, make_files)
    finally:
        with _SAVES_LOCK:
            _SAVES_RUNNING[0] -= 1
            _SAVES_LOCK.notify_all()


def _wait_for_saves(timeout):
    end = time.monotonic() + timeout
    with _SAVES_LOCK:
        while _SAVES_RUNNING[0] and time.monotonic() < end:
            _SAVES_LOCK.wait(0.02)
        return not _SAVES_RUNNING[0]


def _png_bytes(codes) -> bytes:
    """Display codes (8-bit sRGB, :func:`tracer.rendering.output.display_codes`) as the PNG that
    :func:`tracer.rendering.output.save_image` writes."""
    from PIL import Image

    from ..rendering.output import PNG_COMPRESS_LEVEL

    out = io.BytesIO()
    Image.fromarray(codes, mode="RGB").save(out, format="PNG", compress_level=PNG_COMPRESS_LEVEL)
    return out.getvalue()


def _fit(codes, size):
    """Display codes shrunk to fit *size* (the canvas's pixels): what is sent to the page (the
    saved image keeps every pixel)."""
    h, w = codes.shape[:2]
    fw, fh = size
    if w <= fw and h <= fh:
        return codes
    from PIL import Image

    return np.asarray(Image.fromarray(np.ascontiguousarray(codes[..., :3])).resize((fw, fh), Image.Resampling.BOX))


def _warm_up_steps(scene):
    """The scheduler job that loads the compiled kernels a first edit needs (a tiny render, its
    display codes, a picked pixel, colour-science), so that the first change is as quick as
    the next ones."""
    from bubbleoptics import film_color

    from ..scene.builtin import default_scene
    from ..rendering.api import render_with_stats
    from .preview import film_at_pixel
    from .scheduler import BACKGROUND

    def steps(cancel):
        yield BACKGROUND
        s = scene if scene is not None else default_scene()
        display_codes(render_with_stats(s, width=8, height=8, progress=False, cancel=cancel)[0])
        yield BACKGROUND
        if s.bubbles:
            film_at_pixel(s, 4, 4, 8, 8)
        yield BACKGROUND
        import colour  # noqa: F401  (colour-science: film_color's first call imports it, seconds)

        film_color(300.0)

    return steps


def check_serve_options(address, token, width=None, height=None):
    """Refuse what ``serve`` must not start with (ValueError, one line)."""
    from .security import is_loopback

    if token is False and not is_loopback(address):
        raise ValueError(f"--no-token serves only this machine's loopback (127.0.0.1), not --address {address}:"
                         " anyone on the network could use the editor as you")
    if isinstance(token, str) and (len(token) < 16 or not token.isprintable() or " " in token):
        raise ValueError("--token must be at least 16 printable characters without spaces")
    for name, v in (("--width", width), ("--height", height)):
        if v is not None and not 1 <= int(v) <= MAX_SIDE:
            raise ValueError(f"{name} must be an integer from 1 to {MAX_SIDE} in the editor, got {v}")


def serve(scene=None, *, port=5006, address="127.0.0.1", show=True, width=None, height=None, quiet=False,
          root=None, token=None, allow_hosts=(), max_sessions=MAX_SESSIONS):
    """Serve the editor for *scene* at http://ADDRESS:PORT/ until Ctrl-C or SIGTERM (then the
    server stops within about a second and this returns 0).  *port* 0 picks a free one.  Each
    browser tab gets its own editor (and its own scene), up to *max_sessions* at once.

    *token*: None (a new random one, printed in the URL), a string (that one), or False (none:
    only on a loopback *address*, with a warning).  *root*: the folder (default: the working
    folder) that every file the page loads or saves resolves inside.  *allow_hosts*: names
    besides this machine's that a request's Host may give (a reverse proxy's).  See
    :mod:`tracer.editor.security`.
    """
    from .security import (TokenAuth, allowed_hosts, guard_component_resources, is_loopback, new_secret, new_token,
                           refuse_foreign_hosts)

    check_serve_options(address, token, width, height)
    access = FileAccess(root if root is not None else Path.cwd(), max_bytes=MAX_ASSET_BYTES,
                        max_pixels=MAX_IMAGE_PIXELS, max_scene_bytes=MAX_SCENE_BYTES)
    if scene is not None and not isinstance(scene, Scene):
        scene = load_scene(scene)  # the command line's own file: a bad one fails here, before the server starts
    if scene is not None:
        EditorModel.check_names(scene)
    token = new_token() if token is None else (token or None)
    port = port or free_port(address)
    # in the background, so that the server answers at once (a first edit meanwhile waits for it)
    warm = object()
    scheduler().submit(warm, "warm-up", _warm_up_steps(scene))

    def app():
        live = [a for a in list(_APPS) if not a.closed]
        if len(live) >= max_sessions:
            return pn.pane.Markdown(f"### tracer scene editor\n\n{len(live)} editors are open on this server, the"
                                    f" most it keeps at once: close one of them (or wait a minute), then reload.",
                                    css_classes=["editor-full"])
        return EditorApp(scene, width=width, height=height, access=access).layout

    hosts = allowed_hosts(address, allow_hosts)
    origins = sorted(f"{h}:{port}" for h in hosts if ":" not in h)  # Bokeh's allowlist takes no IPv6
    secret = new_secret()
    server = pn.serve({"/": app}, port=port, address=address, websocket_origin=origins, show=False,
                      start=False, title="tracer scene editor", verbose=False,
                      auth_provider=TokenAuth(token, port), cookie_secret=secret.decode(),
                      sign_sessions=True, secret_key=secret, generate_session_ids=True,
                      websocket_max_message_size=MAX_SCENE_BYTES * 4 // 3 + 2**20)
    # Bokeh's Server keeps its Tornado application as _tornado (Panel reaches it the same way)
    refuse_foreign_hosts(server._tornado, hosts)
    guard_component_resources(server._tornado)
    shown_host = "127.0.0.1" if address in ("0.0.0.0", "::", "") else address
    url = f"http://{shown_host}:{port}/" + (f"?token={token}" if token else "")
    if not quiet:
        print(f"tracer edit: serving {url} (Ctrl-C to stop)", flush=True)
        print(f"tracer edit: files load and save inside {access.root}", flush=True)
        user = os.environ.get("USER") or os.environ.get("USERNAME") or "you"
        if token is None:
            print(f"tracer edit: warning: no token (--no-token): anyone who can reach port {port} of this machine,"
                  f" every user of it included, can read and write files inside {access.root} as {user}",
                  file=sys.stderr, flush=True)
        if not is_loopback(address):
            print(f"tracer edit: warning: serving on {address}, not only this machine: anyone on the network who"
                  f" has the token can read and write files inside {access.root} as {user}, and plain HTTP"
                  " carries the token unencrypted (use a trusted network, or a TLS proxy)",
                  file=sys.stderr, flush=True)

    def stop(*_):  # SIGTERM and Ctrl-C: stop the event loop (from the signal, thread-safely)
        server.io_loop.asyncio_loop.call_soon_threadsafe(server.io_loop.stop)

    previous = {sig: signal.signal(sig, stop) for sig in (signal.SIGTERM, signal.SIGINT)}
    try:
        server.start()
        if show:
            server.io_loop.add_callback(partial(_open_browser, url))
        server.io_loop.start()
    except KeyboardInterrupt:
        pass
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
        stopped = _shutdown(server)
    if not quiet:
        print("tracer edit: stopped", file=sys.stderr, flush=True)
    if not stopped and not quiet:
        print("tracer edit: numba is still compiling a kernel (it cannot be stopped); nothing is being written",
              file=sys.stderr, flush=True)
    return 0


def _shutdown(server, seconds=1.0) -> bool:
    """Stop serving: every editor's renders cancelled (their kernels stop at their next ray),
    the saves in progress finished, the server closed.  False if the render thread is still
    busy after *seconds* (numba compiling)."""
    for editor in list(_APPS):
        editor.close()
    stopped = scheduler().close(timeout=seconds)
    _wait_for_saves(seconds)
    try:
        server.stop(wait=False)
    except Exception:  # a server that never started
        pass
    if stopped:
        from ..rendering.local import PARALLEL_LOCK

        # no parallel kernel may start while the interpreter exits (numba's workqueue layer
        # aborts the process when its threads are torn down mid-kernel)
        PARALLEL_LOCK.acquire(timeout=seconds)
    return stopped


def _open_browser(url):
    import webbrowser

    if os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY") or sys.platform in ("darwin", "win32"):
        webbrowser.open(url)

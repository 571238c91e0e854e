"""The scene editor's Panel app: the coursework's Qt window as Panel widgets.

The left column holds the coursework's functions with its button names: **Load**, the objects
and lights lists, **Change** / **Add** / **Delete** (lights), **Change parameters** and
**Change geometry** (objects), **Clear**; then what it lacked: the camera's orbit and zoom, the
render settings, **Undo**, **Save image**, **Save scene**, **Save commands**.  The right column
is the preview (a Bokeh image: click it to pick a pixel) and the picked pixel's film: its
reflectance spectrum and colour (:func:`tracer.editor.preview.film_at_pixel`).

Every edit goes through :class:`tracer.editor.model.EditorModel`; a bad value shows its message
under its field and changes nothing (the previous image stays).  Each change renders a
quarter-size preview, then the full image (:class:`tracer.editor.preview.PreviewRenderer`).
"""

from __future__ import annotations

import html
import os
import signal
import socket
import sys
import threading
import time
import weakref
from functools import partial
from pathlib import Path

import numpy as np
import panel as pn
from bokeh.events import Tap
from bokeh.models import ColumnDataSource
from bokeh.plotting import figure

from ..errors import SceneError
from ..io import load_scene
from ..movie_commands import BUBBLE_FIELDS, FILM_KIND_FIELDS, PHONG_FIELDS
from ..output import display_codes, save_image
from ..scene import Scene
from .model import EditorModel, FieldError, format_number
from .preview import PreviewRenderer, film_at_pixel

__all__ = ["EditorApp", "serve", "free_port"]

#: The image's size (pixels) unless the scene's [render] table or the caller gives one.
DEFAULT_SIZE = 960
#: The preview's side on the page, in CSS pixels.
VIEW_PX = 560
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

    def __init__(self, scene=None, *, width=None, height=None, view_px=VIEW_PX):
        if scene is None or isinstance(scene, Scene):
            self.model = EditorModel(scene)
        else:
            self.model = EditorModel(load_scene(scene))
        rd = self.model.loaded.render_defaults
        self.width = int(width or rd.get("width", DEFAULT_SIZE))
        self.height = int(height or rd.get("height", DEFAULT_SIZE))
        self._doc = pn.state.curdoc
        self.image = None  # the last full-resolution linear image
        self.stage = ""  # the stage on screen: "", "preview", "full", "cleared"
        self.shown_version = 0
        self.pick = None
        self._t_edit = None
        self._server_ms, self._render_ms = {}, {}
        self._build(view_px)
        self.preview = PreviewRenderer(self._on_image, self._on_render_error)
        _APPS.add(self)
        self._fill_lists()
        if self._served():  # the first render once the page is connected (an image sent earlier can be lost)
            pn.state.onload(self.refresh)
            pn.state.on_session_destroyed(lambda context: self.close())
        else:
            self.refresh()

    def close(self):
        """Stop the preview's thread (a served page's session does this when it ends)."""
        self.preview.close()
        if self._upload_dir is not None:
            self._upload_dir.cleanup()

    def _served(self):
        return self._doc is not None and getattr(self._doc, "session_context", None) is not None

    # -- layout ----------------------------------------------------------------------------
    def _build(self, view_px):
        F = _Field
        self.scene_path = F("scene_path", "scene file", getattr(self.model.loaded, "source", ""), width=300)
        self.load_button = _button("Load")
        # or a file from the person's computer: saved under its own name in a folder of this
        # session's, then loaded as a path is (its FILE:LINE messages name that copy)
        self.upload = pn.widgets.FileInput(accept=".toml,.txt,.scene", css_classes=["editor-upload"])
        self._upload_dir = None
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
        self.out_commands = F("out_commands", "commands file", "edits.txt", width=220)
        self.save_commands_button = _button("Save commands")
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
        self.image_pane = pn.Column(pn.pane.Bokeh(fig, margin=0), css_classes=["editor-image"], width=fw, height=fh,
                                    margin=0)
        self.spectrum_source = ColumnDataSource(data=dict(wl=[], R=[]))
        spec = figure(width=300, height=220, title="picked pixel: film reflectance", x_axis_label="wavelength (nm)",
                      y_axis_label="R", toolbar_location=None, x_range=(360, 780))
        spec.line("wl", "R", source=self.spectrum_source, line_width=2)
        self.spectrum = pn.pane.Bokeh(spec)
        self.swatch = pn.pane.HTML("", width=300, css_classes=["editor-pick"])

        for button, handler in [
            (self.load_button, self.on_load), (self.change_button, self.on_change_light),
            (self.add_button, self.on_add_light), (self.delete_button, self.on_delete_light),
            (self.params_button, self.on_change_parameters), (self.geometry_button, self.on_change_geometry),
            (self.orbit_button, self.on_orbit), (self.zoom_button, self.on_zoom),
            (self.settings_button, self.on_settings), (self.undo_button, self.on_undo),
            (self.clear_button, self.on_clear), (self.save_image_button, self.on_save_image),
            (self.save_scene_button, self.on_save_scene), (self.save_commands_button, self.on_save_commands),
        ]:
            button.on_click(lambda event, h=handler: self._guard(h))
        self.upload.param.watch(lambda e: self._guard(self.on_upload), "value")
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

    def _guard_held(self, handler):
        for f in self._all_fields():
            f.clear()
        try:
            message = handler()
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
            self._say(str(err), error=True)
            return
        self._say(message or "")

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
        self.status.object = f'<span class="msg" style="color:{color}">{html.escape(text)}</span>' if text else ""

    def _edited(self, message):
        self.refresh()  # first: the render starts while the lists and forms are updated
        self._fill_lists()
        return message

    def on_load(self):
        path = self.scene_path.value.strip()
        if not path:
            raise FieldError("scene_path", "give a scene file's path (TOML or the coursework's format)")
        self.model.load(path)  # SceneError: the old scene stays
        self._edited(None)
        return f"loaded {path}"

    def on_upload(self):
        """**Load** a file chosen in the browser (the file input)."""
        import tempfile

        if self.upload.value is None:
            return None
        name = Path(self.upload.filename or "scene.toml").name
        if self._upload_dir is None:
            self._upload_dir = tempfile.TemporaryDirectory(prefix="tracer-edit-")
        path = Path(self._upload_dir.name) / name
        path.write_bytes(self.upload.value)
        self.scene_path.value = str(path)
        return self.on_load()

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

    def _out_path(self, field):
        text = field.value.strip()
        if not text:
            raise FieldError(field.name, f"{getattr(field.input, _LABEL)}: give a file name")
        return Path(text).expanduser()

    def on_save_image(self):
        path = self._out_path(self.out_image)
        if path.suffix.lower() != ".png":
            raise FieldError("out_image", f"the image is saved as PNG: give a name ending in .png, got {path.name!r}")
        if not self.preview.idle(timeout=120) or self.image is None:
            raise FieldError("out_image", "no full-resolution image yet")
        save_image(self.image, path, exposure=self.model.settings["exposure"])
        return f"saved {path}"

    def on_save_scene(self):
        path = self._out_path(self.out_scene)
        if path.suffix.lower() != ".toml":
            raise FieldError("out_scene", f"a scene is saved as TOML: give a name ending in .toml, got {path.name!r}")
        self.model.save_scene(path)
        return f"saved {path}"

    def on_save_commands(self):
        path = self._out_path(self.out_commands)
        self.model.save_commands(path)
        return f"saved {path} ({len(self.model.commands_text().splitlines()) - 3} edits)"

    # -- rendering --------------------------------------------------------------------------
    def refresh(self):
        """Render the model's scene: a quarter-size preview, then the full image."""
        self.preview.request(self.model.scene, self.model.render_settings(self.width, self.height),
                             self.model.settings["exposure"], self.model.version)

    def _on_image(self, shown):
        if shown.version != self.model.version:
            return  # an edit came after it: its own render follows
        if shown.linear is not None:
            self.image = shown.linear
        self._schedule(partial(self._show, shown.codes, shown.stage, shown.version, shown.seconds))

    def _on_render_error(self, version, exc):
        self._schedule(partial(self._say, f"render failed: {exc}", True))

    def _schedule(self, fn):
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
        # in a thread: the pick waits for a render in progress, the page must not
        scene = self.model.scene
        threading.Thread(target=self._pick, args=(scene, col, row), name="tracer-editor-pick", daemon=True).start()

    def _pick(self, scene, col, row):
        sample = film_at_pixel(scene, col, row, self.width, self.height)
        self._schedule(partial(self._show_pick, col, row, sample))

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
            f'{sample.bubble}, film {sample.thickness_nm:.0f} nm at {sample.angle_deg:.1f}°<br>'
            f'colour #{r:02x}{g:02x}{b:02x} (D65)</div></div>')


# ------------------------------------------------------------------------------------------
# serving
# ------------------------------------------------------------------------------------------
def free_port(address="127.0.0.1") -> int:
    """A TCP port free on *address* now."""
    with socket.socket() as s:
        s.bind((address, 0))
        return s.getsockname()[1]


def warm_up(scene=None):
    """Load the compiled kernels a first edit needs (a tiny render, its display codes, a picked
    pixel) so that the first person's first change is as quick as the next ones."""
    from ..builtin import default_scene
    from ..render import PARALLEL_LOCK, render

    from bubbleoptics import film_color

    scene = scene if scene is not None else default_scene()
    import importlib

    with PARALLEL_LOCK:
        display_codes(render(scene, width=8, height=8, progress=False))
        film_at_pixel(scene, 4, 4, 8, 8)
    importlib.import_module("colour")  # colour-science, which film_color's first call imports (seconds)
    with PARALLEL_LOCK:
        film_color(300.0)


def serve(scene=None, *, port=5006, address="127.0.0.1", show=True, width=None, height=None, quiet=False):
    """Serve the editor for *scene* at http://ADDRESS:PORT/ until Ctrl-C or SIGTERM (then the
    server stops and this returns).  *port* 0 picks a free one.  Each browser tab gets its own
    editor (and its own scene)."""
    if scene is not None and not isinstance(scene, Scene):
        scene = load_scene(scene)  # a bad file fails here, before the server starts
    port = port or free_port(address)
    # in the background, so that the server answers at once (a first edit meanwhile waits for it)
    threading.Thread(target=warm_up, args=(scene,), name="tracer-editor-warm-up", daemon=True).start()

    def app():
        return EditorApp(scene, width=width, height=height).layout

    origins = [f"{host}:{port}" for host in {address, "localhost", "127.0.0.1"}]
    server = pn.serve({"/": app}, port=port, address=address, websocket_origin=origins, show=False,
                      start=False, title="tracer scene editor", verbose=False)
    url = f"http://{address}:{port}/"
    if not quiet:
        print(f"tracer edit: serving {url} (Ctrl-C to stop)", flush=True)

    def stop(*_):  # SIGTERM stops the server as Ctrl-C does
        raise KeyboardInterrupt

    previous = signal.signal(signal.SIGTERM, stop)
    try:
        server.start()
        if show:
            server.io_loop.add_callback(partial(_open_browser, url))
        server.io_loop.start()
    except KeyboardInterrupt:
        pass
    finally:
        signal.signal(signal.SIGTERM, previous)
        server.stop()
        _quiesce()
    if not quiet:
        print("tracer edit: stopped", file=sys.stderr, flush=True)
    return 0


def _quiesce(seconds=30.0):
    """Stop every editor's preview and keep numba's thread pool idle from now on: the renders in
    flight stop at their next ray, and the lock that every parallel kernel takes is taken here
    and not given back, so that no kernel runs while the interpreter exits (numba's workqueue
    layer aborts the process when its threads are torn down mid-kernel)."""
    from ..render import PARALLEL_LOCK

    for editor in list(_APPS):
        editor.close()
    PARALLEL_LOCK.acquire(timeout=seconds)


def _open_browser(url):
    import webbrowser

    if os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY") or sys.platform in ("darwin", "win32"):
        webbrowser.open(url)

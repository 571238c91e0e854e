"""The scene editor's model: the scene being edited, its edits, undo and validation, no widgets.

Every edit is one or more lines of the movie commands file (``docs/movies.md``), applied with
:meth:`tracer.Timeline.command` to a :class:`~tracer.Timeline` of the scene as loaded: the
editor and the movies share one vocabulary, and the edits made since loading save as a commands
file (:meth:`EditorModel.commands_text`) that ``tracer movie`` (or
:meth:`tracer.Timeline.from_file` on the loaded scene) replays to the edited scene.

Values come from text fields, so every edit takes numbers or strings.  A bad value raises
:class:`FieldError` naming the field and the allowed range, and changes nothing.

>>> import tracer
>>> m = EditorModel(tracer.default_scene())
>>> m.change_light(1, 0, 3, 4, "2.5").lights[0].intensity
2.5
>>> m.change_light(1, 0, 3, 4, "-1")
Traceback (most recent call last):
...
tracer.editor.model.FieldError: intensity must be >= 0 and <= 1e+15, got -1
>>> m.undo(); m.lights[0].intensity
True
2.0
"""

from __future__ import annotations

import math
import shlex
from pathlib import Path

from bubbleoptics.atomic import write_atomically
from bubbleoptics.messages import shorten

from ..scene.file_access import ANYWHERE, FileAccess, check_name
from ..scene.load import load_scene
from ..scene.limits import MAX_EXPOSURE, MAX_MAGNITUDE, check_setting
from ..movie.commands import BUBBLE_FIELDS, PHONG_FIELDS, SWITCH_FIELDS
from ..movie.timeline import Timeline
from ..rendering.api import DEFAULTS
from ..scene.builtin import default_scene
from ..scene.model import Bubble, Scene

__all__ = ["EditorModel", "FieldError", "FIELDS", "SETTINGS", "EDITOR_LIMITS", "MAX_SIDE", "MAX_WORK", "render_work",
           "check_field", "check_settings_field", "format_number"]


class FieldError(ValueError):
    """A bad value for one field of the editor: ``field`` (None when the edit as a whole is
    refused) and the one-line message (``str(err)``) naming the allowed range."""

    def __init__(self, field, message):
        super().__init__(message)
        self.field = field


# field: (number of values, lowest, highest, lowest excluded), as tracer.movie.commands' field tables
_ANY = (1, -MAX_MAGNITUDE, MAX_MAGNITUDE, False)
#: Every numeric field of the editor's forms and its allowed range: the optical parameters
#: are the commands file's (:data:`tracer.movie.commands.PHONG_FIELDS`, ``BUBBLE_FIELDS``).
FIELDS = {
    **{c: _ANY for c in ("x", "y", "z", "dx", "dy", "dz", "orbit")},
    "intensity": (1, 0.0, MAX_MAGNITUDE, False),
    "k": (1, 0.0, MAX_MAGNITUDE, True),
    "zoom": (1, 0.0, MAX_MAGNITUDE, True),
    **PHONG_FIELDS,
    **BUBBLE_FIELDS,
}
#: The render settings the editor changes: the CLI's limits (:mod:`tracer.scene.limits`) within the
#: editor's render budget below, and the display exposure in stops.
SETTINGS = ("depth", "spp", "spectral_samples", "exposure")

#: The editor's render budget.  An editor is a server that other people's clicks make work, so
#: what one click may cost is bounded: each setting has a cap, and a full image may cost at most
#: :data:`MAX_WORK` (pixels x spp x bands x depth), 16 times what the defaults cost at 960 x 960
#: (a few seconds of this machine's time at most, against hours that the command line's limits
#: allow).  Deeper, finer renders are for ``tracer image`` with the saved scene.
EDITOR_LIMITS = {"depth": 64, "spp": 256, "spectral_samples": 128}
#: The largest width or height of the editor's image (pixels).
MAX_SIDE = 4096
#: The most work a full image may take: width x height x spp x spectral_samples x depth.
MAX_WORK = 16 * 960 * 960 * DEFAULTS["spp"] * DEFAULTS["spectral_samples"] * DEFAULTS["depth"]


def render_work(width, height, settings) -> int:
    """What a full image of *settings* costs in the budget's unit (see :data:`MAX_WORK`)."""
    return int(width) * int(height) * int(settings["spp"]) * int(settings["spectral_samples"]) * int(settings["depth"])


def format_number(v) -> str:
    """A number as the commands file writes it: the shortest text that reads back to the same
    float (``300``, ``0.25``, ``1e-05``)."""
    v = float(v)
    return str(int(v)) if v.is_integer() and abs(v) < 1e15 else repr(v)


def _range(lo, hi, lo_open):
    return f"{'>' if lo_open else '>='} {lo:g} and <= {hi:g}"


def check_field(field, value):
    """*value* (a number or the text of a field) checked against :data:`FIELDS`: a float, or a
    tuple of floats for a field of several numbers (``color``: "R G B"); else
    :class:`FieldError` naming the field and its range."""
    count, lo, hi, lo_open = FIELDS[field]
    words = value.replace(",", " ").split() if isinstance(value, str) else (
        list(value) if isinstance(value, (tuple, list)) else [value])
    if len(words) != count:
        raise FieldError(field, f"{field} takes {count} number{'s' if count > 1 else ''}, got {len(words)}"
                         + (f": {value!r}" if isinstance(value, str) and value.strip() else ""))
    out = []
    for w in words:
        try:
            v = float(w)
        except (TypeError, ValueError):
            raise FieldError(field, f"{field}: {str(w)[:40]!r} is not a number") from None
        if not math.isfinite(v) or (v <= lo if lo_open else v < lo) or v > hi:
            raise FieldError(field, f"{field} must be {_range(lo, hi, lo_open)}, got {w}")
        out.append(v)
    return tuple(out) if count > 1 else out[0]


def check_settings_field(name, value):
    """A render setting of :data:`SETTINGS` from a number or text (the CLI's limits), else
    :class:`FieldError`."""
    if name == "exposure":
        try:
            v = float(value)
        except (TypeError, ValueError):
            raise FieldError(name, f"exposure: {str(value)[:40]!r} is not a number") from None
        if not -MAX_EXPOSURE <= v <= MAX_EXPOSURE:
            raise FieldError(name, f"exposure must be a number of stops from {-MAX_EXPOSURE:g} to "
                                   f"{MAX_EXPOSURE:g}, got {value}")
        return v
    cap = EDITOR_LIMITS[name]
    try:
        value = int(value) if isinstance(value, str) and value.strip().lstrip("+-").isdigit() else value
        v = check_setting(name, value)
        if v > cap:
            raise ValueError
    except ValueError:
        shown = str(value).strip()
        shown = shorten(shown)
        raise FieldError(name, f"{name} must be an integer from 1 to {cap} in the editor (its render budget;"
                               f" tracer image renders more), got {shown}") from None
    return v


def _fit_budget(settings, width, height):
    """*settings* within the editor's caps and :data:`MAX_WORK` (spp lowered first, then the
    bands, then the depth), and a note of each change."""
    out, notes = dict(settings), []
    for k, cap in EDITOR_LIMITS.items():
        if out[k] > cap:
            notes.append(f"{k} {out[k]} -> {cap}")
            out[k] = cap
    for k in ("spp", "spectral_samples", "depth"):
        work = render_work(width, height, out)
        if work > MAX_WORK:
            fit = max(1, out[k] * MAX_WORK // work)
            notes.append(f"{k} {out[k]} -> {fit}")
            out[k] = fit
    return out, notes


def _name(name) -> str:
    """An object's name as a field of a commands line (quoted when needed)."""
    return shlex.quote(name) if name else "''"


class EditorModel:
    """The scene being edited: the scene as loaded, the edits since (command lines), the render
    settings, and undo.  ``version`` counts the changes (a preview re-renders when it moves)."""

    def __init__(self, scene: Scene | None = None, size=(960, 960)):
        self.size = (int(size[0]), int(size[1]))
        if not (1 <= self.size[0] <= MAX_SIDE and 1 <= self.size[1] <= MAX_SIDE):
            raise FieldError(None, f"the editor's image is at most {MAX_SIDE} x {MAX_SIDE} pixels, got"
                                   f" {self.size[0]} x {self.size[1]}")
        self._reset(scene if scene is not None else default_scene())

    @staticmethod
    def check_names(scene) -> Scene:
        """*scene* if every object's and material's name is printable text (a newline in a
        name would put a line of its own into the commands file), else :class:`FieldError`."""
        for obj in scene.spheres + scene.bubbles + scene.meshes:
            for name, what in ((obj.name, "an object's name"),
                               (getattr(getattr(obj, "material", None), "name", ""), "a material's name")):
                try:
                    check_name(name, what)
                except ValueError as err:
                    raise FieldError("scene_path", str(err)) from None
        return scene

    def _reset(self, scene):
        self.check_names(scene)
        self.loaded = scene
        self.settings = {k: scene.render_defaults.get(k, DEFAULTS.get(k, 0.0)) for k in SETTINGS}
        self.settings["exposure"] = float(scene.render_defaults.get("exposure", 0.0))
        fitted, self.budget_notes = _fit_budget({k: self.settings[k] for k in EDITOR_LIMITS}, *self.size)
        self.settings.update(fitted)
        self._history = []  # undo steps: ("lines", [line, ...]) or ("settings", previous settings)
        self._timeline = Timeline(scene)
        self.version = getattr(self, "version", 0) + 1

    # -- loading ----------------------------------------------------------------------------
    def load(self, path, access: FileAccess = ANYWHERE):
        """Load the scene file *path* (either format) and forget the edits; a bad file raises
        :class:`tracer.SceneError` (``FILE:LINE: ...``) and keeps the scene that was loaded.
        *access*: which files it and its assets may be (:class:`tracer.scene.file_access.FileAccess`)."""
        return self.replace(load_scene(path, access))

    def replace(self, scene: Scene):
        """Edit *scene* from now on (a scene read elsewhere: :meth:`load`), forgetting the edits."""
        self._reset(scene)
        return self

    # -- what the lists show ------------------------------------------------------------------
    @property
    def scene(self) -> Scene:
        """The edited scene (a copy), with the editor's render settings as its ``[render]`` table."""
        scene = self._timeline.scene
        defaults = dict(self.loaded.render_defaults)
        defaults.update(self.settings)
        scene.render_defaults = defaults
        scene.source = self.loaded.source
        return scene

    @property
    def lights(self):
        return self._timeline.scene.lights

    def objects(self):
        """``[(name, kind), ...]``: the scene's spheres, bubbles and meshes ("sphere", "bubble", "mesh")."""
        s = self._timeline.scene
        return [(o.name, kind[:-1]) for kind in ("spheres", "bubbles", "meshes") for o in getattr(s, kind)]

    def object(self, name):
        """The object named *name* (the first, when names repeat)."""
        s = self._timeline.scene
        for o in s.spheres + s.bubbles + s.meshes:
            if o.name == name:
                return o
        raise KeyError(name)

    def parameters(self, name) -> dict:
        """The optical parameters of object *name* as the "Change parameters" form shows them
        (field: value); a bubble's include its film's kind (``profile``) and index (``n_film``)."""
        o = self.object(name)
        if isinstance(o, Bubble):
            f = o.film
            out = {"shininess": o.shininess, "profile": f.kind, "n_film": o.n_film}
            out.update({k: getattr(f, k) for k in BUBBLE_FIELDS if k != "shininess"})
            return out
        return {k: getattr(o.material, k) for k in PHONG_FIELDS}

    # -- edits -------------------------------------------------------------------------------
    def _apply(self, lines, field=None):
        """Apply command *lines* as one undo step (all or nothing)."""
        self._timeline = self._replay(self._lines() + lines, field)
        self._history.append(("lines", lines))
        self.version += 1
        return self

    def _replay(self, lines, field=None):
        tl = Timeline(self.loaded)
        for line in lines:
            try:
                tl.command(line)
            except ValueError as err:
                raise FieldError(field, str(err)) from None
        return tl

    def _lines(self):
        return [line for kind, step in self._history if kind == "lines" for line in step]

    def _light_number(self, number):
        try:
            n = int(number)
        except (TypeError, ValueError):
            raise FieldError("light", f"light: {number!r} is not a light's number") from None
        if not 1 <= n <= len(self.lights):
            have = f"1 to {len(self.lights)}" if self.lights else "none"
            raise FieldError("light", f"no light {n}: the scene's lights are {have}")
        return n

    def change_light(self, number, x, y, z, intensity):
        """**Change**: move light *number* (from 1) to (x, y, z) and give it *intensity*."""
        n = self._light_number(number)
        values = [check_field(f, v) for f, v in zip(("x", "y", "z", "intensity"), (x, y, z, intensity))]
        return self._apply([f"light {n} " + " ".join(map(format_number, values))])

    def add_light(self, x, y, z, intensity):
        """**Add**: a white point light at (x, y, z) (numbered after the others)."""
        values = [check_field(f, v) for f, v in zip(("x", "y", "z", "intensity"), (x, y, z, intensity))]
        return self._apply(["light add " + " ".join(map(format_number, values))])

    def delete_light(self, number):
        """**Delete**: light *number* (the later ones move down by one)."""
        return self._apply([f"light delete {self._light_number(number)}"])

    def change_parameters(self, name, **fields):
        """**Change parameters** of object *name*: each given field (:meth:`parameters`' names)
        that differs from its value now, as one undo step; a bubble's ``profile`` switches first,
        so that the fields of the new kind apply."""
        now = self.parameters(name)
        lines = []
        for f in sorted(fields, key=lambda f: f not in SWITCH_FIELDS):
            value = fields[f]
            if f not in now:
                raise FieldError(f, f"{self._kind(name)} '{name}' has no field '{f}' (fields: {', '.join(now)})")
            if f in SWITCH_FIELDS:
                value = str(value).strip()
                if value != str(now[f]):
                    lines.append(f"set {_name(name)} {f} {value}")
                continue
            v = check_field(f, value)
            if v != (tuple(now[f]) if f == "color" else now[f]):
                words = v if isinstance(v, tuple) else (v,)
                lines.append(f"set {_name(name)} {f} " + " ".join(map(format_number, words)))
        if not lines:
            return self
        try:
            return self._apply(lines)
        except FieldError as err:
            field = next((f for f in fields if f"{f} " in str(err) or f"'{f}'" in str(err)), None)
            raise FieldError(field, str(err)) from None

    def _kind(self, name):
        return dict(self.objects()).get(name, "object")

    def change_geometry(self, name, dx=0, dy=0, dz=0, k=1):
        """**Change geometry** of object *name*: translate by (dx, dy, dz), then scale by *k*
        about its centre, as one undo step."""
        d = [check_field(f, v) for f, v in zip(("dx", "dy", "dz"), (dx, dy, dz))]
        k = check_field("k", k)
        lines = []
        if any(d):
            lines.append(f"move {_name(name)} " + " ".join(map(format_number, d)))
        if k != 1:
            lines.append(f"scale {_name(name)} {format_number(k)}")
        return self._apply(lines) if lines else self

    def orbit(self, degrees):
        """Turn the camera by *degrees* about its look-at point (around its up axis)."""
        return self._apply([f"camera orbit {format_number(check_field('orbit', degrees))}"])

    def zoom(self, factor):
        """Zoom the camera's lens by *factor* (> 1 closer): tan(fov/2) divided by it."""
        f = check_field("zoom", factor)
        fov = self._timeline.scene.camera.fov_deg
        new = math.degrees(2 * math.atan(math.tan(math.radians(fov) / 2) / f))
        return self._apply([f"camera fov {format_number(new)}"], field="zoom")

    def set_settings(self, **given):
        """Render settings (:data:`SETTINGS`: depth, spp, spectral_samples, exposure), one undo step."""
        new = dict(self.settings)
        for name, value in given.items():
            if name not in SETTINGS:
                raise FieldError(name, f"unknown setting {name!r} (settings: {', '.join(SETTINGS)})")
            new[name] = check_settings_field(name, value)
        work = render_work(*self.size, new)
        if work > MAX_WORK:
            changed = [k for k in ("spp", "spectral_samples", "depth") if new[k] != self.settings[k]]
            raise FieldError(changed[0] if changed else "spp",
                             f"over the editor's render budget: {self.size[0]} x {self.size[1]} pixels x spp {new['spp']}"
                             f" x bands {new['spectral_samples']} x depth {new['depth']} = {work:.3g}, at most"
                             f" {MAX_WORK:.3g} (16 times the defaults at 960 x 960)")
        if new != self.settings:
            self._history.append(("settings", dict(self.settings)))
            self.settings = new
            self.version += 1
        return self

    def undo(self) -> bool:
        """Undo the last edit (True), or nothing is left to undo (False)."""
        if not self._history:
            return False
        kind, step = self._history.pop()
        if kind == "settings":
            self.settings = step
        else:
            self._timeline = self._replay(self._lines())
        self.version += 1
        return True

    @property
    def can_undo(self) -> bool:
        return bool(self._history)

    # -- saving ------------------------------------------------------------------------------
    def commands_text(self) -> str:
        """The edits since loading as a movie commands file (``docs/movies.md``): the edits, then
        ``render 1`` (one frame, the edited scene). The render settings are not commands:
        ``tracer movie`` takes them as options (``--depth --spp --spectral-samples``)."""
        s = self.settings
        head = [f"# edits of {self.loaded.source} in the scene editor (tracer edit)",
                f"# render settings: --depth {s['depth']} --spp {s['spp']} --spectral-samples "
                f"{s['spectral_samples']} (exposure {format_number(s['exposure'])})"]
        return "\n".join(head + self._lines() + ["render 1"]) + "\n"

    def save_commands(self, path) -> Path:
        """Write :meth:`commands_text` to *path* (atomically)."""
        path = Path(path)
        write_atomically(path, lambda tmp: Path(tmp).write_text(self.commands_text(), encoding="utf-8"))
        return path

    def save_scene(self, path) -> Path:
        """**Save scene**: the edited scene as TOML (its render settings in ``[render]``)."""
        from ..scene.toml_write import save_toml_scene

        return save_toml_scene(self.scene, path, header=self._scene_header())

    def _scene_header(self):
        return f"saved by the scene editor from {self.loaded.source}"

    def scene_files_maker(self):
        """For **Save scene**: a function of a name's stem that gives the files of the edited
        scene as it is now, ``{file name: bytes}``: the TOML file ``stem.toml`` and the arrays
        it names beside it (an image environment, thickness maps), made in a temporary folder
        (:meth:`tracer.scene.file_access.FileAccess.save_new` then links them into place)."""
        import tempfile

        from ..scene.toml_write import save_toml_scene

        scene, header = self.scene, self._scene_header()

        def files(stem):
            with tempfile.TemporaryDirectory(prefix="tracer-edit-save-") as tmp:
                save_toml_scene(scene, Path(tmp) / f"{stem}.toml", header=header)
                return {p.name: p.read_bytes() for p in sorted(Path(tmp).iterdir())}

        return files

    def render_settings(self, width, height) -> dict:
        """Keyword arguments of :func:`tracer.render` for a *width* x *height* image."""
        s = self.settings
        return dict(width=int(width), height=int(height), depth=s["depth"], spp=s["spp"],
                    spectral_samples=s["spectral_samples"])

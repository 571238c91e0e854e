"""The :class:`Timeline`: a scene and its changes, frame by frame (the coursework's ``-film``).

Each method of :class:`Timeline` is one command of the commands file (:mod:`tracer.movie.commands`
has the format, ``docs/movies.md`` an example); ``render K`` spreads every change since the
previous ``render`` linearly over K frames (frame k of K shows k/K of it).

:class:`Timeline` is the same vocabulary as Python methods (a notebook builds one without a
file); :meth:`Timeline.from_file` and :meth:`Timeline.from_text` call those methods line by line
(:mod:`tracer.movie.commands`) and report every problem as :class:`CommandsError`, ``COMMANDS:LINE: what is wrong``.
:meth:`Timeline.frames` resolves the timeline into one self-contained :class:`Frame` per
image (the scene as it is then, and the render settings), which any process can render alone.

Interpolation, per change (``t = k/K``): a move translates by ``t * d``; a scale multiplies
sizes by ``1 + t (k - 1)`` (the radius changes linearly); a rotation turns by ``t * degrees``;
``set``, ``light N``, ``camera position``/``look_at``/``fov`` move each number linearly from
its value before the change to the new one; ``camera orbit`` turns by ``t * degrees``; an added
light fades in (intensity ``t * I``) and a deleted light fades out (``(1 - t) I``, gone at the
last frame).
"""

from __future__ import annotations

import dataclasses
import difflib
import math
import os
from dataclasses import dataclass, field

import numpy as np

from bubbleoptics.messages import shorten

from ..scene.block_format import LineReader, split_lines
from ..scene.errors import SceneError
from ..scene.limits import DISPLAY_DEFAULTS, MAX_INDEX, MAX_MAGNITUDE
from ..scene.model import Camera, PointLight, Scene
from ..scene.text import read_scene_text
from .commands import (BUBBLE_FIELDS, FIELD_ALIASES, FILM_KIND_FIELDS, PHONG_FIELDS, SWITCH_FIELDS, CommandsError,
                       dispatch, tokens)
from .frames import Frame

__all__ = ["Timeline", "MAX_FRAMES"]

#: The most frames a timeline may hold (a minute at 24 fps is 1440).
MAX_FRAMES = 1_000_000


# ------------------------------------------------------------------------------------------
# the working state a change edits
# ------------------------------------------------------------------------------------------
@dataclass
class _State:
    """A scene being edited, its lights' identities (stable across deletions) and the film time.

    Copies share arrays and unchanged objects' fields; every edit replaces what it changes
    (new tuples, new arrays, new dataclass instances), never mutates them, so a copy never
    sees another's edits, and a material shared by two objects stays shared only until one of
    them is edited.
    """

    scene: Scene
    light_ids: list = field(default_factory=list)
    time: float = 0.0

    def copy(self):
        s = self.scene
        scene = dataclasses.replace(
            s,
            spheres=[dataclasses.replace(o) for o in s.spheres],
            bubbles=[dataclasses.replace(o) for o in s.bubbles],
            meshes=[dataclasses.replace(o) for o in s.meshes],
            lights=[dataclasses.replace(o) for o in s.lights],
            camera=dataclasses.replace(s.camera),
            render_defaults={},
        )
        return _State(scene, list(self.light_ids), self.time)

    def obj(self, ref):
        kind, i = ref
        return getattr(self.scene, kind)[i]

    def put(self, ref, obj):
        kind, i = ref
        getattr(self.scene, kind)[i] = obj

    def light_index(self, light_id):
        return self.light_ids.index(light_id)


def _add(a, b, t):
    """``a + t * b`` for tuples of numbers."""
    return tuple(float(x) + t * float(y) for x, y in zip(a, b))


def _sub(a, b):
    return tuple(float(x) - float(y) for x, y in zip(a, b))


def _rotation(axis, degrees):
    """The 3x3 matrix of a right-handed turn by *degrees* about the unit vector *axis*
    (Rodrigues' formula)."""
    x, y, z = axis
    a = math.radians(degrees)
    c, s = math.cos(a), math.sin(a)
    C = 1.0 - c
    return np.array([
        [c + x * x * C, x * y * C - z * s, x * z * C + y * s],
        [y * x * C + z * s, c + y * y * C, y * z * C - x * s],
        [z * x * C - y * s, z * y * C + x * s, c + z * z * C],
    ])


def _mesh_centre(vertices):
    """A mesh's centre: the middle of its bounding box."""
    return 0.5 * (vertices.min(axis=0) + vertices.max(axis=0))


# Each change is a callable change(state, t) applying the fraction t in [0, 1] of itself.
@dataclass
class _Move:
    ref: tuple
    d: tuple

    def __call__(self, st, t):
        o = st.obj(self.ref)
        if self.ref[0] == "meshes":
            st.put(self.ref, dataclasses.replace(o, vertices=o.vertices + t * np.asarray(self.d)))
        else:
            st.put(self.ref, dataclasses.replace(o, center=_add(o.center, self.d, t)))


@dataclass
class _Scale:
    ref: tuple
    k: float

    def __call__(self, st, t):
        f = 1.0 + t * (self.k - 1.0)
        o = st.obj(self.ref)
        if self.ref[0] == "meshes":
            c = _mesh_centre(o.vertices)
            st.put(self.ref, dataclasses.replace(o, vertices=c + f * (o.vertices - c)))
        else:
            st.put(self.ref, dataclasses.replace(o, radius=float(o.radius) * f))


@dataclass
class _Rotate:
    ref: tuple
    axis: tuple
    degrees: float

    def __call__(self, st, t):
        R = _rotation(self.axis, t * self.degrees)
        o = st.obj(self.ref)
        if self.ref[0] == "meshes":
            c = _mesh_centre(o.vertices)
            st.put(self.ref, dataclasses.replace(o, vertices=c + (o.vertices - c) @ R.T))
        elif self.ref[0] == "bubbles":  # the film turns with the bubble (its up direction)
            up = tuple((R @ np.asarray(o.film.up, float)).tolist())
            st.put(self.ref, dataclasses.replace(o, film=dataclasses.replace(o.film, up=up)))
        # a sphere's uniform material looks the same however it is turned


@dataclass
class _Set:
    ref: tuple
    name: str  # the field
    delta: tuple

    def __call__(self, st, t):
        o = st.obj(self.ref)
        if self.ref[0] == "bubbles":
            if self.name == "shininess":
                st.put(self.ref, dataclasses.replace(o, shininess=o.shininess + t * self.delta[0]))
            else:
                value = getattr(o.film, self.name) + t * self.delta[0]
                st.put(self.ref, dataclasses.replace(o, film=dataclasses.replace(o.film, **{self.name: value})))
        else:  # a copy of the material: another object sharing it keeps its own
            old = getattr(o.material, self.name)
            value = _add(old, self.delta, t) if self.name == "color" else old + t * self.delta[0]
            st.put(self.ref, dataclasses.replace(o, material=dataclasses.replace(o.material, **{self.name: value})))


@dataclass
class _Switch:
    ref: tuple
    name: str  # profile or n_film (SWITCH_FIELDS)
    value: object

    def __call__(self, st, t):
        if t < 1.0:
            return
        o = st.obj(self.ref)
        if self.name == "profile":
            st.put(self.ref, dataclasses.replace(o, film=dataclasses.replace(o.film, kind=self.value)))
        else:
            st.put(self.ref, dataclasses.replace(o, n_film=self.value))


def _switch_value(f, values):
    """The value of switch field *f* (:data:`SWITCH_FIELDS`) given as the words *values*."""
    if len(values) != 1:
        raise ValueError(f"{f} takes 1 value, got {len(values)}")
    v = str(values[0])
    if f == "profile":
        if v not in SWITCH_FIELDS["profile"]:
            raise ValueError(f"profile must be 'uniform' or 'draining', got {v!r}")
        return v
    if v == "water":
        return v
    try:
        n = float(v)
    except ValueError:
        raise ValueError(f"n_film must be 'water' or a number > 0 and <= {MAX_INDEX:g}, got {v!r}") from None
    if not 0 < n <= MAX_INDEX:
        raise ValueError(f"n_film must be 'water' or a number > 0 and <= {MAX_INDEX:g}, got {v}")
    return n


@dataclass
class _LightSet:
    light_id: int
    d_position: tuple
    d_intensity: float

    def __call__(self, st, t):
        i = st.light_index(self.light_id)
        light = st.scene.lights[i]
        st.scene.lights[i] = dataclasses.replace(light, position=_add(light.position, self.d_position, t),
                                                 intensity=light.intensity + t * self.d_intensity)


@dataclass
class _LightAdd:
    light_id: int
    position: tuple
    intensity: float

    def __call__(self, st, t):
        st.scene.lights.append(PointLight(position=self.position, intensity=t * self.intensity))
        st.light_ids.append(self.light_id)


@dataclass
class _LightDelete:
    light_id: int

    def __call__(self, st, t):
        i = st.light_index(self.light_id)
        if t >= 1.0:
            del st.scene.lights[i]
            del st.light_ids[i]
        else:
            light = st.scene.lights[i]
            st.scene.lights[i] = dataclasses.replace(light, intensity=(1.0 - t) * light.intensity)


@dataclass
class _CameraSet:
    name: str  # position, look_at or fov_deg
    delta: tuple

    def __call__(self, st, t):
        cam = st.scene.camera
        if self.name == "fov_deg":
            value = cam.fov_deg + t * self.delta[0]
        else:
            value = _add(getattr(cam, self.name), self.delta, t)
        st.scene.camera = dataclasses.replace(cam, **{self.name: value})


@dataclass
class _CameraOrbit:
    degrees: float

    def __call__(self, st, t):
        cam = st.scene.camera
        up = np.asarray(cam.up, float)
        R = _rotation(up / np.linalg.norm(up), t * self.degrees)
        look = np.asarray(cam.look_at, float)
        position = look + R @ (np.asarray(cam.position, float) - look)
        st.scene.camera = dataclasses.replace(cam, position=tuple(position.tolist()))


@dataclass
class _Time:
    seconds: float

    def __call__(self, st, t):
        st.time += t * self.seconds


# ------------------------------------------------------------------------------------------
# the timeline
# ------------------------------------------------------------------------------------------
def _finite(value, what):
    v = float(value)
    if not math.isfinite(v):
        raise ValueError(f"{what} must be a finite number, got {value!r}")
    if abs(v) > MAX_MAGNITUDE:
        raise ValueError(f"{what} {v:g} is outside -{MAX_MAGNITUDE:g} to {MAX_MAGNITUDE:g} (tracer.scene.limits)")
    return v


def _vector(values, what):
    values = tuple(values)
    if len(values) != 3:
        raise ValueError(f"{what} needs 3 numbers, got {len(values)}")
    return tuple(_finite(v, f"{what} ({c})") for v, c in zip(values, "xyz"))


def _check_point(p, what):
    for v, c in zip(p, "xyz"):
        if not abs(v) <= MAX_MAGNITUDE:
            raise ValueError(f"{what} ({c}) would be {v:g}, outside -{MAX_MAGNITUDE:g} to {MAX_MAGNITUDE:g}")


class Timeline:
    """The frames of a movie, built command by command from a starting scene.

    Each method is one command of the commands file (``docs/movies.md``); changes accumulate
    until :meth:`render`, which spreads them linearly over its frames. Objects are named as
    in the scene (``Sphere.name``, ``Bubble.name``, ``Mesh.name``), lights numbered from 1 in
    the scene's current list. A bad value raises ValueError before anything changes.

    >>> import tracer
    >>> tl = Timeline(tracer.default_scene())
    >>> tl.move("old", 0.3, 0.0, 0.0).render(3)
    Timeline(3 frames)
    >>> [round(s.bubbles[2].center[0], 2) for s, _ in tl.scenes()]   # 1/3, 2/3, 3/3 of the move
    [0.4, 0.5, 0.6]
    """

    def __init__(self, scene: Scene):
        self._start = _State(scene, list(range(len(scene.lights))))
        self._state = self._start.copy()  # the scene after every change so far, complete
        self._next_light_id = len(scene.lights)
        self._pending = []  # changes since the last render
        self._pending_line = None
        self._segments = []  # (start state, changes, frame count, line)
        self._n_frames = 0
        self._line = None  # the line being read (from_text), for frames' provenance
        self._names = {}
        for kind in ("spheres", "bubbles", "meshes"):
            for i, o in enumerate(getattr(scene, kind)):
                self._names.setdefault(o.name, []).append((kind, i))

    def __repr__(self):
        return f"Timeline({self._n_frames} frames)"

    def __len__(self):
        return self._n_frames

    # -- reading a file -----------------------------------------------------------------
    @classmethod
    def from_file(cls, scene: Scene, path) -> "Timeline":
        """The timeline of the commands file *path* (UTF-8) applied to *scene*; CommandsError."""
        path = os.fspath(path)
        try:
            text = read_scene_text(path)
        except SceneError as err:
            raise CommandsError(err.path, err.line, err.message.replace("scene file", "commands file")) from None
        return cls.from_text(scene, text, path)

    @classmethod
    def from_text(cls, scene: Scene, text: str, path="<commands>") -> "Timeline":
        """The timeline of commands-file *text*; every problem is a :class:`CommandsError`
        ``PATH:LINE: what is wrong``, and so is a file that renders nothing or leaves changes
        after its last ``render``."""
        tl = cls(scene)
        reader = LineReader(path)
        for lineno, line in enumerate(split_lines(text[1:] if text.startswith("\ufeff") else text), start=1):
            try:
                words = tokens(line)
            except ValueError as err:
                raise CommandsError(path, lineno, str(err)) from None
            if not words:
                continue
            tl._line = lineno
            try:
                dispatch(tl, reader, lineno, words)
            except SceneError as err:  # a number, from the scene files' reader
                raise CommandsError(path, err.line, err.message) from None
            except ValueError as err:
                raise CommandsError(path, lineno, f"{words[0]}: {err}") from None
        tl._line = None
        if tl._pending:
            raise CommandsError(path, tl._pending_line,
                                "this change comes after the last 'render' and would never be shown: "
                                "add a 'render K' after it")
        if not tl._n_frames:
            raise CommandsError(path, None, "no frames: the file has no 'render K' command")
        return tl

    # -- one command at a time (the scene editor) ------------------------------------------
    @property
    def scene(self) -> Scene:
        """The scene after every change so far (complete, whether or not rendered yet); a
        copy, so editing it changes nothing here."""
        return self._state.copy().scene

    def command(self, line: str) -> "Timeline":
        """Apply one line of the commands file (``docs/movies.md``), e.g. ``'light 1 0 2 3 1.5'``;
        a blank or comment-only line does nothing.  A bad line raises ValueError with the message
        the file would give after ``COMMANDS:LINE:``, and changes nothing.  The scene editor
        applies its edits this way, so that its edit log is a commands file."""
        try:
            words = tokens(line)
            if words:
                dispatch(self, LineReader("<command>"), None, words)
        except SceneError as err:  # a number, from the scene files' reader (it names the verb)
            raise ValueError(err.message) from None
        except ValueError as err:
            raise ValueError(f"{words[0]}: {err}" if words else str(err)) from None
        return self

    # -- objects --------------------------------------------------------------------------
    def _ref(self, name):
        refs = self._names.get(name)
        if not refs:
            known = shorten(", ".join(repr(n) for n in self._names) or "none", 200)
            close = difflib.get_close_matches(name, list(self._names), n=1) if len(name) <= 200 else []
            hint = f"; did you mean '{close[0]}'?" if close else ""
            shown = shorten(name, 60)
            raise ValueError(f"no object named '{shown}'{hint} (the scene's objects: {known})")
        if len(refs) > 1:
            raise ValueError(f"{len(refs)} objects are named '{name}': a commands file cannot tell them apart")
        return refs[0]

    def _change(self, change):
        """Apply *change* to the complete state (checking the result), then keep it pending."""
        trial = self._state.copy()
        change(trial, 1.0)
        _check_state(trial)
        self._state = trial
        if not self._pending:
            self._pending_line = self._line
        self._pending.append(change)
        return self

    def move(self, name, dx, dy, dz):
        """Translate object *name* by (dx, dy, dz) scene units."""
        ref = self._ref(name)
        return self._change(_Move(ref, _vector((dx, dy, dz), "the move")))

    def scale(self, name, k):
        """Scale object *name* uniformly by *k* > 0 about its centre (a mesh's: the middle of
        its bounding box)."""
        ref = self._ref(name)
        k = _finite(k, "the factor")
        if not k > 0:
            raise ValueError(f"the factor must be > 0, got {k:g}")
        return self._change(_Scale(ref, k))

    def rotate(self, name, axis_x, axis_y, axis_z, degrees):
        """Turn object *name* by *degrees* (right-handed) about the axis through its centre.
        A mesh's vertices turn; a bubble's film turns (its ``up``: the draining profile; the
        swirl's waves are fixed in world directions by the renderer and do not turn); a sphere
        looks the same."""
        ref = self._ref(name)
        axis = np.asarray(_vector((axis_x, axis_y, axis_z), "the axis"))
        m = np.abs(axis).max()
        if not m > 0:
            raise ValueError("the axis must not be the zero vector")
        axis = axis / m
        axis = tuple((axis / np.linalg.norm(axis)).tolist())
        return self._change(_Rotate(ref, axis, _finite(degrees, "the angle")))

    def set(self, name, field_name, *values):
        """Set an optical parameter of object *name* (:data:`PHONG_FIELDS` for spheres and
        meshes, :data:`BUBBLE_FIELDS` and :data:`SWITCH_FIELDS` for bubbles, as the TOML format
        names them; ``colour`` and ``thickness`` are accepted for ``color`` and ``thickness_nm``)."""
        ref = self._ref(name)
        o = self._state.obj(ref)
        f = FIELD_ALIASES.get(field_name, field_name)
        if ref[0] == "bubbles" and f in SWITCH_FIELDS:
            return self._change(_Switch(ref, f, _switch_value(f, values)))
        if ref[0] == "bubbles":
            allowed = ("shininess",) + FILM_KIND_FIELDS[o.film.kind] + tuple(SWITCH_FIELDS)
            table = BUBBLE_FIELDS
            what = f"bubble '{name}' ({o.film.kind} film)"
        else:
            allowed, table = tuple(PHONG_FIELDS), PHONG_FIELDS
            what = f"{ref[0][:-1]} '{name}'"
        if f not in allowed:
            raise ValueError(f"{what} has no field '{field_name}' (fields: {', '.join(allowed)})")
        count, lo, hi, lo_open = table[f]
        if len(values) != count:
            raise ValueError(f"{f} takes {count} number{'s' if count > 1 else ''}, got {len(values)}")
        new = tuple(_finite(v, f) for v in values)
        for v in new:
            if (v <= lo if lo_open else v < lo) or v > hi:
                rel = ">" if lo_open else ">="
                raise ValueError(f"{f} must be {rel} {lo:g} and <= {hi:g}, got {v:g}")
        if ref[0] == "bubbles":
            old = (o.shininess,) if f == "shininess" else (getattr(o.film, f),)
        else:
            old = getattr(o.material, f)
            old = tuple(old) if f == "color" else (old,)
        return self._change(_Set(ref, f, _sub(new, old)))

    # -- lights ---------------------------------------------------------------------------
    def _light_id(self, number):
        n = len(self._state.light_ids)
        if isinstance(number, bool) or not isinstance(number, (int, np.integer)) or not 1 <= number <= n:
            have = f"lights 1 to {n}" if n > 1 else ("light 1" if n == 1 else "no lights")
            raise ValueError(f"no light {number}: the scene has {have}")
        return self._state.light_ids[number - 1]

    @staticmethod
    def _intensity(value):
        v = _finite(value, "the intensity")
        if v < 0:
            raise ValueError(f"the intensity must be >= 0, got {v:g}")
        return v

    def light(self, number, x, y, z, intensity):
        """Move light *number* (1-based) to (x, y, z) and give it *intensity*."""
        lid = self._light_id(number)
        light = self._state.scene.lights[self._state.light_index(lid)]
        position = _vector((x, y, z), "the position")
        return self._change(_LightSet(lid, _sub(position, light.position),
                                      self._intensity(intensity) - light.intensity))

    def light_add(self, x, y, z, intensity):
        """Add a white point light (it fades in over the next ``render``); it is numbered
        after the scene's current lights."""
        position = _vector((x, y, z), "the position")
        intensity = self._intensity(intensity)
        self._next_light_id += 1
        return self._change(_LightAdd(self._next_light_id, position, intensity))

    def light_delete(self, number):
        """Delete light *number* (it fades out over the next ``render``); later lights'
        numbers go down by one."""
        return self._change(_LightDelete(self._light_id(number)))

    # -- camera ---------------------------------------------------------------------------
    def camera_position(self, x, y, z):
        """Move the camera to (x, y, z) (it keeps looking at its look-at point)."""
        p = _vector((x, y, z), "the position")
        return self._change(_CameraSet("position", _sub(p, self._state.scene.camera.position)))

    def camera_look_at(self, x, y, z):
        """Point the camera at (x, y, z)."""
        p = _vector((x, y, z), "the look-at point")
        return self._change(_CameraSet("look_at", _sub(p, self._state.scene.camera.look_at)))

    def camera_orbit(self, degrees):
        """Turn the camera by *degrees* about its look-at point, around its up axis."""
        return self._change(_CameraOrbit(_finite(degrees, "the angle")))

    def camera_fov(self, degrees):
        """Set the camera's vertical field of view (0 < degrees < 180)."""
        v = _finite(degrees, "the field of view")
        if not 0 < v < 180:
            raise ValueError(f"the field of view must be > 0 and < 180 degrees, got {v:g}")
        return self._change(_CameraSet("fov_deg", (v - self._state.scene.camera.fov_deg,)))

    # -- time and frames ------------------------------------------------------------------
    def time(self, seconds):
        """Advance the film's time by *seconds* >= 0 over the next ``render`` (each frame's
        :attr:`Frame.time`): a simulated film (:mod:`tracer.scene.simulated`) shows its series that
        much later than its own ``time``."""
        v = _finite(seconds, "the time")
        if v < 0:
            raise ValueError(f"the time must be >= 0 seconds, got {v:g}")
        return self._change(_Time(v))

    def render(self, frames):
        """Render *frames* (an integer >= 1) frames, spreading every change since the last
        ``render`` linearly over them: frame k of K shows k/K of it."""
        if isinstance(frames, bool) or not isinstance(frames, (int, np.integer)) or frames < 1:
            raise ValueError(f"the frame count must be an integer >= 1, got {frames!r}")
        if self._n_frames + frames > MAX_FRAMES:
            raise ValueError(f"a movie has at most {MAX_FRAMES:,} frames; this one would have "
                             f"{self._n_frames + frames:,}")
        start = self._segment_start()
        changes = tuple(self._pending)
        for k in (1, frames):  # the camera of every frame must have a direction: check the ends...
            _check_camera(_apply(start, changes, k / frames).scene.camera, k)
        if any(isinstance(c, (_CameraSet, _CameraOrbit)) for c in changes):
            _check_cameras_between(start.scene.camera, changes, frames)  # ...and, when it moves, those between
        self._segments.append((start, changes, int(frames), self._line))
        self._n_frames += int(frames)
        self._pending = []
        self._pending_line = None
        return self

    def _segment_start(self):
        if not self._segments:
            return self._start
        start, changes, _, _ = self._segments[-1]
        return _apply(start, changes, 1.0)

    @property
    def pending(self) -> int:
        """The number of changes made since the last :meth:`render` (not yet in any frame)."""
        return len(self._pending)

    def _shown(self):
        """Yield ``(scene, time, line)`` for every frame, in order, one at a time."""
        from ..scene.simulated import resolve_simulated_films

        for start, changes, count, line in self._segments:
            for k in range(1, count + 1):
                st = _apply(start, changes, k / count)
                yield resolve_simulated_films(st.scene, st.time), st.time, line

    def scenes(self):
        """Yield ``(scene, time)`` for every frame, in order: the scene as the frame shows it
        (its simulated films as the maps they show at the film time, popped bubbles gone:
        :func:`tracer.scene.simulated.resolve_simulated_films`) and the film time in seconds."""
        for scene, time, _ in self._shown():
            yield scene, time

    def iter_frames(self, settings=None, display=None, spectral=False):
        """An iterator of the :class:`Frame` of every image, each made when it is asked for (a
        movie of a million frames starts rendering at once, and holds one frame at a time),
        with a copy of *settings* (resolved render settings, e.g. from
        :func:`tracer.rendering.api.resolve_settings`; None: the scene's defaults), of *display*
        (``exposure`` and ``view``; None: 0 and ``"clip"``) and the flag *spectral*. ValueError
        (at once, not at the first frame) if changes were made after the last :meth:`render`."""
        if self._pending:
            raise ValueError(f"{len(self._pending)} change(s) after the last render would never be shown: "
                             "call render(K) after them")
        if settings is None:
            from ..rendering.api import resolve_settings

            settings = resolve_settings(self._start.scene)
        settings, display, spectral = dict(settings), dict(display or DISPLAY_DEFAULTS), bool(spectral)
        return (Frame(i, scene, dict(settings), time, line, dict(display), spectral)
                for i, (scene, time, line) in enumerate(self._shown()))

    def frames(self, settings=None, display=None, spectral=False) -> list[Frame]:
        """Every :class:`Frame` at once, as a list (:meth:`iter_frames`, which a long movie
        should use instead)."""
        return list(self.iter_frames(settings, display, spectral))


def _apply(start: _State, changes, t) -> _State:
    st = start.copy()
    for change in changes:
        change(st, t)
    return st


def _check_state(st: _State):
    """The complete state after a change: every position and size within the scene limits."""
    s = st.scene
    for o in s.spheres + s.bubbles:
        _check_point(o.center, f"{o.name}'s centre")
        if not 0 < o.radius <= MAX_MAGNITUDE:
            raise ValueError(f"{o.name}'s radius would be {o.radius:g}, outside (0, {MAX_MAGNITUDE:g}]")
    for m in s.meshes:
        if not np.all(np.abs(m.vertices) <= MAX_MAGNITUDE):
            raise ValueError(f"{m.name}'s vertices would leave -{MAX_MAGNITUDE:g} to {MAX_MAGNITUDE:g}")
    for i, light in enumerate(s.lights):
        _check_point(light.position, f"light {i + 1}'s position")
    cam = s.camera
    _check_point(cam.position, "the camera's position")
    _check_point(cam.look_at, "the camera's look-at point")


def _check_camera(cam: Camera, k):
    try:
        cam.basis()
    except ValueError as err:
        raise ValueError(f"frame {k} of this render: {err}") from None


#: Frames whose cameras :func:`_check_cameras_between` computes at once (memory: a few MB).
_CAMERA_CHUNK = 65536


def _camera_paths(camera: Camera, changes, k, frames):
    """``(positions, look_at points)``, arrays (len(k), 3), of the camera at frames *k* (an
    integer array) of a render of *frames* frames with *changes*: the camera changes applied in
    order, as :class:`_CameraSet` and :class:`_CameraOrbit` do one frame at a time."""
    up = np.asarray(camera.up, float)
    axis = up / np.linalg.norm(up)
    t = (np.asarray(k) / frames)[:, None]
    pos = np.tile(np.asarray(camera.position, float), (len(k), 1))
    look = np.tile(np.asarray(camera.look_at, float), (len(k), 1))
    for c in changes:
        if isinstance(c, _CameraOrbit):
            a = np.radians(t[:, 0] * c.degrees)
            cos, sin = np.cos(a)[:, None], np.sin(a)[:, None]
            v = pos - look  # Rodrigues' formula, as _rotation(axis, t degrees) @ v
            pos = look + v * cos + np.cross(axis, v) * sin + axis * (v @ axis)[:, None] * (1.0 - cos)
        elif isinstance(c, _CameraSet) and c.name == "position":
            pos = pos + t * np.asarray(c.delta, float)
        elif isinstance(c, _CameraSet) and c.name == "look_at":
            look = look + t * np.asarray(c.delta, float)
    return pos, look


def _check_cameras_between(camera: Camera, changes, frames):
    """:func:`_check_camera` of frames 2 to *frames* - 1 of a render whose *changes* move the
    camera, as arrays (:func:`_camera_paths`, a chunk of frames at a time), with Camera.basis's
    two tests (look_at not at the position; up not parallel to the viewing direction): a render
    of a million frames is checked in about a second, before any is rendered."""
    up = np.asarray(camera.up, float)
    up_unit = up / np.abs(up).max()
    up_unit = up_unit / np.linalg.norm(up_unit)
    for k0 in range(2, frames, _CAMERA_CHUNK):
        k = np.arange(k0, min(frames, k0 + _CAMERA_CHUNK))
        pos, look = _camera_paths(camera, changes, k, frames)
        with np.errstate(over="ignore", invalid="ignore"):
            fwd = look - pos
            scale = np.abs(fwd).max(axis=1)
            bad = ~(np.isfinite(scale) & (scale > 0))
            if bad.any():
                i = int(np.argmax(bad))
                what = "coincides with" if not np.any(fwd[i]) else "is too far (overflow) from"
                raise ValueError(f"frame {int(k[i])} of this render: camera look_at {what} its position")
            fwd = fwd / scale[:, None]
            fwd = fwd / np.linalg.norm(fwd, axis=1)[:, None]
            parallel = ~(np.linalg.norm(np.cross(fwd, up_unit), axis=1) > 1e-12)
        if parallel.any():
            raise ValueError(f"frame {int(k[np.argmax(parallel)])} of this render: camera up vector is parallel "
                             "to the viewing direction")


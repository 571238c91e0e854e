"""The tracer's native scene format: TOML, read with the standard library's ``tomllib`` and checked.

A scene file has these tables, all optional except that at least one object must exist::

    [scene]          unit (metadata), description, ambient
    [camera]         position, look_at, up, fov_deg, mirror
    [environment]    kind = "sky" | "constant" | "image", and the keys of that kind
    [render]         default render settings (width, height, depth, spp, spectral_samples,
                     threshold, seed, spectral_method)
    [materials.NAME] color, ambient, diffuse, specular, transmission, shininess, ior
    [[spheres]]      name, center, radius, material
    [[bubbles]]      name, center, radius, n_film, shininess, film_model, and a [bubbles.film] table
    [[meshes]]       name, path | vertices + faces (0-based) [+ normals], material, translate,
                     scale, shading
    [[lights]]       position, intensity | power, color, falloff, radius, samples

Every key is checked: an unknown key (a typo) is an error naming it, as is a value of the wrong
type or out of range.  Errors carry the line of the offending key where it can be found (a
light scan of the text, :class:`_Locator`).  Files the scene names (images, thickness maps,
meshes) are read by :mod:`tracer.scene.assets`.  The full description, with examples, is
``docs/scene-format.md``; :mod:`tracer.scene.toml_write` writes a Scene back as TOML.
"""

from __future__ import annotations

import difflib
import math
import os
import re
import tomllib
import warnings
from functools import partial
from pathlib import Path

import numpy as np
import tomli_w

from bubbleoptics.colorimetry import srgb_to_linear_srgb
from bubbleoptics.messages import shorten

from .assets import AssetError, load_environment_image, load_film_map, load_film_series, load_mesh_file
from ..kernels.geometry import degenerate_triangles
from .errors import SceneError, SceneWarning
from .file_access import ANYWHERE, FileAccess, FileAccessError, check_name
from ..kernels.records import FILM_MODELS
from .limits import LIMITS, MAX_EXHAUSTIVE_DEPTH, MAX_EXPOSURE, MAX_INDEX, MAX_MAGNITUDE, SPECTRAL_METHODS, VIEWS
from .model import (
    LIGHT_FALLOFFS,
    MAX_LIGHT_SAMPLES,
    Bubble,
    Camera,
    Environment,
    FilmProfile,
    Material,
    Mesh,
    PointLight,
    Scene,
    Sphere,
)
from .text import read_scene_text

__all__ = ["load_toml_scene", "parse_toml_text"]

_HEX_COLOR = re.compile(r"#([0-9a-fA-F]{2})([0-9a-fA-F]{2})([0-9a-fA-F]{2})")

# ==========================================================================================
# Finding the line of a key (best effort; only used to point error messages at a line)
# ==========================================================================================
class _Locator:
    """Maps key paths such as ("bubbles", 1, "film", "top_nm") to the line they are on.

    A light scan of the text, not a parser: it follows [table] and [[array]] headers, dotted
    keys and multi-line arrays and strings well enough for well-formed files (the only kind it
    sees: tomllib has accepted the file before any semantic error can be raised).
    """

    _KEY_PART = re.compile(r"\s*(?:([A-Za-z0-9_-]+)|\"((?:[^\"\\]|\\.)*)\"|'([^']*)')\s*")

    def __init__(self, text: str):
        self.lines: dict[tuple, int] = {}
        self._arrays: dict[tuple, int] = {}
        self._scan(text)

    def line(self, keypath) -> int | None:
        kp = tuple(keypath)
        while kp:
            if kp in self.lines:
                return self.lines[kp]
            kp = kp[:-1]
        return None

    def _keys(self, s: str, pos: int = 0):
        """Parse a dotted key at s[pos:]; return (keys, position after it) or (None, pos)."""
        keys = []
        while True:
            m = self._KEY_PART.match(s, pos)
            if not m:
                return (keys or None), pos
            bare, basic, literal = m.groups()
            if bare is not None:
                keys.append(bare)
            elif literal is not None:
                keys.append(literal)
            else:
                try:
                    keys.append(tomllib.loads(f'k = "{basic}"')["k"])
                except tomllib.TOMLDecodeError:
                    keys.append(basic)
            pos = m.end()
            if pos < len(s) and s[pos] == ".":
                pos += 1
                continue
            return keys, pos

    def _resolve(self, keys):
        out = ()
        for k in keys:
            out += (k,)
            if out in self._arrays:
                out += (self._arrays[out] - 1,)
        return out

    def _scan(self, text: str):
        current: tuple = ()
        depth = 0  # open brackets/braces of a value continued on later lines
        ml = None  # the delimiter of a multi-line string we are inside
        for lineno, raw in enumerate(text.split("\n"), start=1):
            pos = 0
            if ml is not None:
                end = raw.find(ml)
                if end < 0:
                    continue
                ml, pos = None, end + 3
            elif depth == 0:
                s = raw.strip()
                if not s or s.startswith("#"):
                    continue
                lead = len(raw) - len(raw.lstrip())
                if s.startswith("[["):
                    keys, _ = self._keys(raw, lead + 2)
                    if keys:
                        base = self._resolve(keys[:-1]) + (keys[-1],)
                        n = self._arrays.get(base, 0)
                        self._arrays[base] = n + 1
                        current = base + (n,)
                        self.lines.setdefault(current, lineno)
                    continue
                if s.startswith("["):
                    keys, _ = self._keys(raw, lead + 1)
                    if keys:
                        current = self._resolve(keys)
                        self.lines.setdefault(current, lineno)
                    continue
                keys, pos = self._keys(raw, lead)
                if not keys or pos >= len(raw) or raw[pos] != "=":
                    continue
                self.lines.setdefault(current + tuple(keys), lineno)
                pos += 1
            depth, ml = self._value_state(raw, pos, depth)

    @staticmethod
    def _value_state(s: str, pos: int, depth: int):
        """Bracket depth and open multi-line string after scanning s[pos:]."""
        i, n = pos, len(s)
        while i < n:
            c = s[i]
            if c == "#":
                break
            if s.startswith('"""', i) or s.startswith("'''", i):
                delim = s[i:i + 3]
                end = s.find(delim, i + 3)
                if end < 0:
                    return depth, delim
                i = end + 3
                continue
            if c == '"':
                i += 1
                while i < n and s[i] != '"':
                    i += 2 if s[i] == "\\" else 1
            elif c == "'":
                end = s.find("'", i + 1)
                i = n if end < 0 else end
            elif c in "[{":
                depth += 1
            elif c in "]}":
                depth = max(0, depth - 1)
            i += 1
        return depth, None


# ==========================================================================================
# Reading
# ==========================================================================================
def _toml_key(k: str) -> str:
    """One key as TOML writes it (bare, or a quoted basic string), as tomli-w formats it."""
    return tomli_w.dumps({k: 0}).rsplit(" = ", 1)[0]


def _keyname(kp) -> str:
    out = ""
    for k in kp:
        if isinstance(k, int):
            out += f"[{k}]"
        else:
            k = _toml_key(k)
            out += f".{k}" if out else k
    return out


class _Ctx:
    def __init__(self, path: str, text: str, access: FileAccess = ANYWHERE, base=None):
        self.path = path
        self.text = text
        self.access = access
        if base is not None:
            self.base = Path(base)
        elif path != "<string>":
            self.base = access.resolve(path).parent  # relative to the root, when confined
        else:
            self.base = access.root or Path.cwd()
        self._loc = None

    def line(self, kp):
        if self._loc is None:
            self._loc = _Locator(self.text)
        return self._loc.line(kp)

    def error(self, kp, message) -> SceneError:
        return SceneError(self.path, self.line(kp), message)

    def bad(self, kp, message) -> SceneError:
        return self.error(kp, f"{_keyname(kp)}: {message}")

    # -- structure ----------------------------------------------------------------------------
    def table(self, kp, value, what=None) -> dict:
        if not isinstance(value, dict):
            raise self.bad(kp, f"must be a table{f' ({what})' if what else ''}, got {_typename(value)}")
        return value

    def keys(self, kp, table: dict, allowed, required=(), where=None):
        where = where or (f"[{_keyname(kp)}]" if kp else "the top level")
        for key in table:
            if key not in allowed:
                close = difflib.get_close_matches(key, list(allowed), n=1)
                hint = f"; did you mean '{close[0]}'?" if close else ""
                raise self.error(
                    kp + (key,),
                    f"unknown key '{_short(key, 40)}' in {where}{hint} (allowed: {', '.join(sorted(allowed))})",
                )
        for key in required:
            if key not in table:
                raise self.error(kp, f"{where} needs a '{key}' key")

    def array_of_tables(self, kp, value) -> list:
        if isinstance(value, dict) or not isinstance(value, list):
            raise self.bad(kp, f"must be an array of tables (write [[{_keyname(kp)}]]), got {_typename(value)}")
        for i, item in enumerate(value):
            self.table(kp + (i,), item)
        return value

    # -- values -------------------------------------------------------------------------------
    def number(self, kp, v, lo=None, hi=None, lo_open=False, hi_open=False) -> float:
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise self.bad(kp, f"must be a number, got {_typename(v)}")
        raw = v
        try:
            v = float(v)
        except OverflowError:  # an integer too large for a float
            v = math.inf
        if not math.isfinite(v):
            raise self.bad(kp, f"must be a finite number, got {_short(raw)}")
        if lo is not None and (v <= lo if lo_open else v < lo):
            rel = ">" if lo_open else ">="
            raise self.bad(kp, f"must be {rel} {lo:g}, got {v:g}")
        if hi is not None and (v >= hi if hi_open else v > hi):
            raise self.bad(kp, f"must be {'<' if hi_open else '<='} {hi:g}, got {v:g}")
        if abs(v) > MAX_MAGNITUDE:
            raise self.bad(kp, f"must be within -{MAX_MAGNITUDE:g} to {MAX_MAGNITUDE:g} (tracer.scene.limits), got {v!r}")
        return v

    def integer(self, kp, v, lo=None, hi=None) -> int:
        if isinstance(v, bool) or not isinstance(v, int):
            raise self.bad(kp, f"must be an integer, got {_typename(v)}")
        if hi is not None and not lo <= v <= hi:
            raise self.bad(kp, f"must be an integer from {lo} to {hi}, got {_short(v)}")
        if lo is not None and v < lo:
            raise self.bad(kp, f"must be >= {lo}, got {_short(v)}")
        return int(v)

    def string(self, kp, v) -> str:
        if not isinstance(v, str):
            raise self.bad(kp, f"must be a string, got {_typename(v)}")
        return v

    def vec3(self, kp, v, nonzero=False) -> tuple[float, float, float]:
        if not isinstance(v, list) or len(v) != 3:
            raise self.bad(kp, f"must be an array of 3 numbers [x, y, z], got {_short(v)}")
        out = tuple(self.number(kp, x) for x in v)
        if nonzero and not any(out):
            raise self.bad(kp, "must not be the zero vector")
        return out

    def color(self, kp, v, albedo=True) -> tuple[float, float, float]:
        """Linear RGB [r, g, b] (in [0, 1] for an albedo, >= 0 otherwise) or sRGB "#rrggbb"."""
        if isinstance(v, str):
            m = _HEX_COLOR.fullmatch(v)
            if not m:
                raise self.bad(kp, f"'{v}' is not a colour: use \"#rrggbb\" (sRGB) or [r, g, b] (linear)")
            return tuple(srgb_to_linear_srgb(np.array([int(g, 16) for g in m.groups()]) / 255.0).tolist())
        if not isinstance(v, list) or len(v) != 3:
            raise self.bad(kp, f"must be a colour [r, g, b] (linear) or \"#rrggbb\" (sRGB), got {_short(v)}")
        return tuple(self.number(kp, x, 0.0, 1.0 if albedo else None) for x in v)

    def asset(self, kp, load, full: Path):
        """``load(full)`` (a :mod:`tracer.scene.assets` loader), its AssetError as this key's SceneError."""
        try:
            return load(full)
        except AssetError as exc:
            raise self.bad(kp, str(exc)) from None

    def name(self, kp, v) -> str:
        """An object's or a material's name: text without control characters (a newline would
        start a new line in a movie commands file that names the object)."""
        try:
            return check_name(self.string(kp, v), "the name")
        except ValueError as exc:
            raise self.bad(kp, str(exc)) from None

    def file(self, kp, v) -> Path:
        """The file a key names, resolved against the scene file's folder and checked by the
        scene's :class:`~tracer.scene.file_access.FileAccess` (inside its root, a regular file, not
        too large)."""
        rel = self.string(kp, v)
        try:
            full = self.access.resolve(rel, base=self.base)
            if not os.path.lexists(full):
                raise self.bad(kp, f"file not found: {rel} (looked for {self.access.relative(full)})")
            self.access.check_file(full, shown=rel)
        except FileAccessError as exc:
            raise self.bad(kp, str(exc)) from None
        return full


def _typename(v) -> str:
    return {bool: "a boolean", int: "an integer", float: "a number", str: "a string",
            list: "an array", dict: "a table"}.get(type(v), type(v).__name__)


def _short(v, limit=60) -> str:
    s = v if isinstance(v, str) and limit != 60 else repr(v)
    return shorten(s, limit)


_TOP = {"scene", "camera", "environment", "render", "materials", "spheres", "bubbles", "meshes", "lights"}
_MATERIAL_KEYS = {"color", "ambient", "diffuse", "specular", "transmission", "shininess", "ior"}
_ENV_KEYS = {
    "constant": {"kind", "color", "intensity"},
    "sky": {"kind", "intensity", "up", "sun_direction"},
    "image": {"kind", "path", "intensity", "up"},
}
_SWIRL_KEYS = {"swirl", "swirl_scale", "seed", "up"}  # the renderer applies swirl to every kind
_FILM_KEYS = {
    "uniform": {"kind", "thickness_nm"} | _SWIRL_KEYS,
    "draining": {"kind", "top_nm", "bottom_nm", "exponent"} | _SWIRL_KEYS,
    "map": {"kind", "path"} | _SWIRL_KEYS,
    "simulated": {"kind", "path", "time", "rupture_nm"} | _SWIRL_KEYS,
}
_RENDER_INT = {k: LIMITS[k] for k in ("width", "height", "depth", "spp", "spectral_samples", "seed")}
#: number keys: (lowest, highest or None)
_RENDER_FLOAT = {"threshold": (0.0, None), "exposure": (-MAX_EXPOSURE, MAX_EXPOSURE)}
_RENDER_CHOICE = {"spectral_method": SPECTRAL_METHODS, "view": VIEWS}


def parse_toml_text(text: str, path="<string>", access: FileAccess = ANYWHERE, base=None) -> Scene:
    """Build a Scene from TOML text; ``path`` names it in errors and anchors relative paths
    (*base*, when given, anchors them instead: an uploaded file has no folder of its own).
    *access* (:class:`tracer.scene.file_access.FileAccess`) says which files the scene may name."""
    path = os.fspath(path)
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        msg = str(exc)
        line = getattr(exc, "lineno", None)
        m = re.search(r"\s*\(at line (\d+), column (\d+)\)", msg)
        if m:
            line = line or int(m.group(1))
            msg = msg[: m.start()] + f" (column {m.group(2)})"
        elif re.search(r"\(at end of document\)", msg):
            line = line or len(text.split("\n"))
        raise SceneError(path, line, f"invalid TOML: {msg}") from None
    except ValueError:  # tomllib hands Python's int() an integer of more than 4300 digits
        m = re.search(r"\d{4300,}", text)
        line = text[: m.start()].count("\n") + 1 if m else None
        raise SceneError(path, line, f"a number of {len(m.group()) if m else 'thousands of'} digits is too large")\
            from None

    c = _Ctx(path, text, access, base)
    c.keys((), doc, _TOP, where="the top level")
    scene = Scene(source=path)

    sc = c.table(("scene",), doc.get("scene", {}))
    c.keys(("scene",), sc, {"unit", "description", "ambient"})
    if "unit" in sc and not c.string(("scene", "unit"), sc["unit"]).strip():
        raise c.bad(("scene", "unit"), "must not be empty")
    if "description" in sc:
        c.string(("scene", "description"), sc["description"])
    if "ambient" in sc:
        scene.ambient = c.color(("scene", "ambient"), sc["ambient"], albedo=False)

    if "camera" in doc:
        scene.camera = _camera(c, doc["camera"])
    if "environment" in doc:
        scene.environment = _environment(c, doc["environment"])
    if "render" in doc:
        scene.render_defaults = _render(c, doc["render"])

    materials = {}
    mats = c.table(("materials",), doc.get("materials", {}))
    for name, t in mats.items():
        materials[name] = _material(c, ("materials", name), t, name, inline=False)

    for i, t in enumerate(c.array_of_tables(("spheres",), doc.get("spheres", []))):
        kp = ("spheres", i)
        c.keys(kp, t, {"name", "center", "radius", "material"}, ("center", "radius"), "[[spheres]]")
        name = c.name(kp + ("name",), t["name"]) if "name" in t else Sphere.__dataclass_fields__["name"].default
        scene.spheres.append(Sphere(
            center=c.vec3(kp + ("center",), t["center"]),
            radius=c.number(kp + ("radius",), t["radius"], 0.0, lo_open=True),
            material=_material_ref(c, kp, t, materials, name),
            name=name,
        ))

    for i, t in enumerate(c.array_of_tables(("bubbles",), doc.get("bubbles", []))):
        scene.bubbles.append(_bubble(c, ("bubbles", i), t))

    for i, t in enumerate(c.array_of_tables(("meshes",), doc.get("meshes", []))):
        scene.meshes.append(_mesh(c, ("meshes", i), t, materials))

    for i, t in enumerate(c.array_of_tables(("lights",), doc.get("lights", []))):
        scene.lights.append(_light(c, ("lights", i), t, sc.get("unit", "m")))

    if not (scene.spheres or scene.bubbles or scene.meshes):
        raise SceneError(path, None, "no objects: the file has no [[spheres]], [[bubbles]] or [[meshes]]")
    return scene


_LIGHT_KEYS = {"position", "intensity", "power", "color", "falloff", "radius", "samples"}


def _light(c: _Ctx, kp, t, unit) -> PointLight:
    """A [[lights]] table: a point or spherical light, unattenuated (the coursework's) or with
    inverse-square falloff in physical units (intensity in W/sr or power in W, lengths in m)."""
    c.keys(kp, t, _LIGHT_KEYS, ("position",), "[[lights]]")
    d = PointLight(position=(0.0, 0.0, 0.0))
    falloff = c.string(kp + ("falloff",), t.get("falloff", d.falloff))
    if falloff not in LIGHT_FALLOFFS:
        raise c.bad(kp + ("falloff",), f"must be one of {', '.join(map(repr, LIGHT_FALLOFFS))}, got '{falloff}'")
    physical = falloff == "inverse_square"
    if physical and unit != "m":
        raise c.bad(kp + ("falloff",), f"'inverse_square' takes lengths in metres, but [scene] unit is '{unit}':"
                                       " write the scene in metres (unit = \"m\")")
    if "power" in t:
        if "intensity" in t:
            raise c.bad(kp + ("power",), "give either 'intensity' (W/sr) or 'power' (W), not both")
        if not physical:
            raise c.bad(kp + ("power",), "a power in watts needs falloff = \"inverse_square\" (the default"
                                         " \"none\" is the coursework's light, which does not dim with distance)")
        # an isotropic source of power P has the radiant intensity P / 4 pi in every direction
        intensity = c.number(kp + ("power",), t["power"], 0.0) / (4.0 * math.pi)
    else:
        intensity = c.number(kp + ("intensity",), t.get("intensity", d.intensity), 0.0)
    samples = t.get("samples", d.samples)
    if isinstance(samples, bool) or not isinstance(samples, int) or not 1 <= samples <= MAX_LIGHT_SAMPLES:
        raise c.bad(kp + ("samples",), f"must be an integer from 1 to {MAX_LIGHT_SAMPLES}, got {_short(samples)}")
    return PointLight(
        position=c.vec3(kp + ("position",), t["position"]),
        intensity=intensity,
        color=c.color(kp + ("color",), t["color"], albedo=False) if "color" in t else d.color,
        radius=c.number(kp + ("radius",), t.get("radius", d.radius), 0.0),
        falloff=falloff,
        samples=samples,
    )


def _camera(c: _Ctx, t) -> Camera:
    kp = ("camera",)
    c.table(kp, t)
    c.keys(kp, t, {"position", "look_at", "up", "fov_deg", "mirror"})
    d = Camera()
    mirror = t.get("mirror", False)
    if not isinstance(mirror, bool):
        raise c.bad(kp + ("mirror",), f"must be true or false, got {mirror!r}")
    cam = Camera(
        position=c.vec3(kp + ("position",), t["position"]) if "position" in t else d.position,
        look_at=c.vec3(kp + ("look_at",), t["look_at"]) if "look_at" in t else d.look_at,
        up=c.vec3(kp + ("up",), t["up"], nonzero=True) if "up" in t else d.up,
        fov_deg=c.number(kp + ("fov_deg",), t.get("fov_deg", d.fov_deg), 0.0, lo_open=True),
        mirror=mirror,
    )
    if not cam.fov_deg < 180.0:
        raise c.bad(kp + ("fov_deg",), f"must be below 180 degrees, got {cam.fov_deg:g}")
    try:
        cam.basis()
    except ValueError as exc:
        raise c.error(kp, f"[camera]: {exc}") from None
    return cam


def _environment(c: _Ctx, t) -> Environment:
    kp = ("environment",)
    c.table(kp, t)
    kind = c.string(kp + ("kind",), t.get("kind", "sky"))
    if kind not in _ENV_KEYS:
        raise c.bad(kp + ("kind",), f"must be one of {', '.join(map(repr, _ENV_KEYS))}, got '{kind}'")
    c.keys(kp, t, _ENV_KEYS[kind], ("path",) if kind == "image" else (),
           where=f"[environment] of kind '{kind}'")
    env = Environment(kind=kind)
    if "color" in t:
        env.color = c.color(kp + ("color",), t["color"], albedo=False)
    if "intensity" in t:
        env.intensity = c.number(kp + ("intensity",), t["intensity"], 0.0)
    if "up" in t:
        env.up = c.vec3(kp + ("up",), t["up"], nonzero=True)
    if "sun_direction" in t:
        env.sun_direction = c.vec3(kp + ("sun_direction",), t["sun_direction"], nonzero=True)
    if kind == "image":
        env.image = c.asset(kp + ("path",), partial(load_environment_image, access=c.access),
                            c.file(kp + ("path",), t["path"]))
    return env


def _render(c: _Ctx, t) -> dict:
    kp = ("render",)
    c.table(kp, t)
    c.keys(kp, t, set(_RENDER_INT) | set(_RENDER_FLOAT) | set(_RENDER_CHOICE))
    out = {}
    for key, v in t.items():
        if key in _RENDER_INT:
            out[key] = c.integer(kp + (key,), v, *_RENDER_INT[key])
        elif key in _RENDER_CHOICE:
            if v not in _RENDER_CHOICE[key]:
                raise c.bad(kp + (key,), f"must be one of {', '.join(map(repr, _RENDER_CHOICE[key]))}, got {_short(v)}")
            out[key] = v
        else:
            out[key] = c.number(kp + (key,), v, *_RENDER_FLOAT[key])
    if out.get("threshold", 1.0) == 0.0 and out.get("depth", 1) > MAX_EXHAUSTIVE_DEPTH:
        raise c.bad(kp + ("depth",), f"must be at most {MAX_EXHAUSTIVE_DEPTH} when render.threshold is 0 (the "
                                     f"exhaustive tree has up to 2^depth - 1 rays a sample), got {out['depth']}")
    return out


def _material(c: _Ctx, kp, t, name, inline) -> Material:
    c.table(kp, t, "a material")
    allowed = _MATERIAL_KEYS | ({"name"} if inline else set())
    c.keys(kp, t, allowed, where="an inline material" if inline else f"[{_keyname(kp)}]")
    d = Material()
    unit = dict(lo=0.0, hi=1.0)
    return Material(
        name=c.name(kp + ("name",), t["name"]) if "name" in t else name,
        color=c.color(kp + ("color",), t["color"]) if "color" in t else d.color,
        ambient=c.number(kp + ("ambient",), t.get("ambient", d.ambient), **unit),
        diffuse=c.number(kp + ("diffuse",), t.get("diffuse", d.diffuse), **unit),
        specular=c.number(kp + ("specular",), t.get("specular", d.specular), **unit),
        transmission=c.number(kp + ("transmission",), t.get("transmission", d.transmission), **unit),
        shininess=c.number(kp + ("shininess",), t.get("shininess", d.shininess), 0.0),
        ior=c.number(kp + ("ior",), t.get("ior", d.ior), 0.0, MAX_INDEX, lo_open=True),
    )


def _material_ref(c: _Ctx, kp, t, materials, owner) -> Material:
    if "material" not in t:
        return Material()
    v = t["material"]
    kp = kp + ("material",)
    if isinstance(v, str):
        if v not in materials:
            known = ", ".join(sorted(materials)) or "none"
            raise c.bad(kp, f"no material named '{v}' (defined in [materials]: {known})")
        return materials[v]
    if isinstance(v, dict):
        return _material(c, kp, v, owner, inline=True)
    raise c.bad(kp, f"must be a material's name or an inline table, got {_typename(v)}")


def _bubble(c: _Ctx, kp, t) -> Bubble:
    c.keys(kp, t, {"name", "center", "radius", "n_film", "shininess", "film", "film_model"}, ("center", "radius"),
           "[[bubbles]]")
    d = Bubble(center=(0.0, 0.0, 0.0), radius=1.0)
    n_film = t.get("n_film", d.n_film)
    if isinstance(n_film, str):
        if n_film != "water":
            raise c.bad(kp + ("n_film",), f"must be \"water\" or a number, got '{n_film}'")
    else:
        n_film = c.number(kp + ("n_film",), n_film, 0.0, MAX_INDEX, lo_open=True)
    film_model = c.string(kp + ("film_model",), t.get("film_model", d.film_model))
    if film_model not in FILM_MODELS:
        raise c.bad(kp + ("film_model",), f"must be one of {', '.join(map(repr, FILM_MODELS))}, got '{film_model}'")
    return Bubble(
        center=c.vec3(kp + ("center",), t["center"]),
        radius=c.number(kp + ("radius",), t["radius"], 0.0, lo_open=True),
        film=_film(c, kp + ("film",), t["film"]) if "film" in t else FilmProfile(),
        n_film=n_film,
        shininess=c.number(kp + ("shininess",), t.get("shininess", d.shininess), 0.0),
        name=c.name(kp + ("name",), t["name"]) if "name" in t else d.name,
        film_model=film_model,
    )


def _film(c: _Ctx, kp, t) -> FilmProfile:
    c.table(kp, t, "the film profile")
    kind = c.string(kp + ("kind",), t.get("kind", "uniform"))
    if kind not in _FILM_KEYS:
        raise c.bad(kp + ("kind",), f"must be one of {', '.join(map(repr, _FILM_KEYS))}, got '{kind}'")
    c.keys(kp, t, _FILM_KEYS[kind], ("path",) if kind in ("map", "simulated") else (), f"a film of kind '{kind}'")
    f = FilmProfile(kind=kind)
    nm = dict(lo=0.0)
    if "thickness_nm" in t:
        f.thickness_nm = c.number(kp + ("thickness_nm",), t["thickness_nm"], **nm)
    if "top_nm" in t:
        f.top_nm = c.number(kp + ("top_nm",), t["top_nm"], **nm)
    if "bottom_nm" in t:
        f.bottom_nm = c.number(kp + ("bottom_nm",), t["bottom_nm"], **nm)
    if "exponent" in t:
        f.exponent = c.number(kp + ("exponent",), t["exponent"], 0.0, lo_open=True)
    if "swirl" in t:
        f.swirl = c.number(kp + ("swirl",), t["swirl"], 0.0, 1.0)
    if "swirl_scale" in t:
        f.swirl_scale = c.number(kp + ("swirl_scale",), t["swirl_scale"], 0.0, lo_open=True)
    if "seed" in t:
        f.seed = c.integer(kp + ("seed",), t["seed"], 0)
    if "up" in t:
        f.up = c.vec3(kp + ("up",), t["up"], nonzero=True)
    if kind == "map":
        pkp = kp + ("path",)
        f.table = c.asset(pkp, load_film_map, c.file(pkp, t["path"]))
    if kind == "simulated":
        pkp = kp + ("path",)
        f.series = c.asset(pkp, load_film_series, c.file(pkp, t["path"]))
        if "time" in t:
            f.time_s = c.number(kp + ("time",), t["time"], 0.0)
        if "rupture_nm" in t:
            f.rupture_nm = c.number(kp + ("rupture_nm",), t["rupture_nm"], 0.0)
    return f


#: ``[[meshes]] shading``: "auto" is smooth when the mesh has vertex normals (from its file or
#: the inline ``normals``), flat otherwise.
_SHADING = ("auto", "smooth", "flat")


def _mesh(c: _Ctx, kp, t, materials) -> Mesh:
    c.keys(kp, t, {"name", "path", "vertices", "faces", "normals", "material", "translate", "scale", "shading"},
           (), "[[meshes]]")
    name = c.name(kp + ("name",), t["name"]) if "name" in t else "mesh"
    shading = c.string(kp + ("shading",), t["shading"]) if "shading" in t else "auto"
    if shading not in _SHADING:
        raise c.bad(kp + ("shading",), f"must be one of {', '.join(map(repr, _SHADING))}, got {_short(shading)}")
    normals = None
    if "path" in t:
        for key in ("vertices", "faces", "normals"):
            if key in t:
                hint = " (a mesh file carries its own normals)" if key == "normals" else ""
                raise c.bad(kp + (key,), f"give either 'path' or 'vertices' and 'faces', not both{hint}")
        verts, faces, normals = c.asset(kp + ("path",), partial(load_mesh_file, access=c.access),
                                        c.file(kp + ("path",), t["path"]))
        fkp = kp + ("path",)
    else:
        for key in ("vertices", "faces"):
            if key not in t:
                raise c.error(kp, f"[[meshes]] needs 'path' (a mesh file) or 'vertices' and 'faces'; '{key}' is missing")
        vkp, fkp = kp + ("vertices",), kp + ("faces",)
        vs = t["vertices"]
        if not isinstance(vs, list) or not vs:
            raise c.bad(vkp, "must be a non-empty array of [x, y, z] points")
        verts = np.array([c.vec3(vkp, v) for v in vs], dtype=np.float64)
        fs = t["faces"]
        if not isinstance(fs, list) or not fs:
            raise c.bad(fkp, "must be a non-empty array of [i, j, k] vertex indices (0-based)")
        rows = []
        for f in fs:
            if not isinstance(f, list) or len(f) != 3:
                raise c.bad(fkp, f"each face is [i, j, k] (a triangle), got {_short(f)}")
            row = [c.integer(fkp, i) for i in f]
            for i in row:
                if not 0 <= i < len(verts):
                    raise c.bad(fkp, f"face {row} names vertex {i}, but there are {len(verts)} vertices"
                                     f" (indices count from 0 in TOML)")
            rows.append(row)
        faces = np.array(rows, dtype=np.int64)
        if "normals" in t:
            nkp = kp + ("normals",)
            ns = t["normals"]
            if not isinstance(ns, list) or len(ns) != len(verts):
                raise c.bad(nkp, f"must be an array of one [x, y, z] normal per vertex ({len(verts)}),"
                                 f" got {_short(ns) if not isinstance(ns, list) else f'{len(ns)} entries'}")
            normals = np.array([c.vec3(nkp, n, nonzero=True) for n in ns], dtype=np.float64)
    if "scale" in t:
        verts = verts * c.number(kp + ("scale",), t["scale"], 0.0, lo_open=True)
    if "translate" in t:
        verts = verts + np.array(c.vec3(kp + ("translate",), t["translate"]))
    if not np.abs(verts).max() <= MAX_MAGNITUDE:  # scale can carry a file's vertices beyond it
        raise c.bad(kp + ("scale",) if "scale" in t else fkp,
                    f"the mesh's vertices reach {np.abs(verts).max():g}, beyond {MAX_MAGNITUDE:g} (tracer.scene.limits)")
    if shading == "auto":
        shading = "smooth" if normals is not None else "flat"
    bad = degenerate_triangles(verts[faces])
    if bad.all():
        raise c.bad(fkp, f"the mesh has no usable face: all {len(faces)} have zero area")
    if bad.any():
        warnings.warn(f"{c.path}:{c.line(fkp)}: {_keyname(kp)}: {int(bad.sum())} zero-area face(s)"
                      " skipped", SceneWarning, stacklevel=3)
        faces = faces[~bad]
    return Mesh(vertices=np.ascontiguousarray(verts), faces=np.ascontiguousarray(faces),
                material=_material_ref(c, kp, t, materials, name), name=name, normals=normals, shading=shading)


def load_toml_scene(path, access: FileAccess = ANYWHERE) -> Scene:
    """Read a TOML scene file; raises SceneError('FILE:LINE: ...') on any problem (*access*:
    which files it and its assets may be, :class:`tracer.scene.file_access.FileAccess`)."""
    path = os.fspath(path)
    return parse_toml_text(read_scene_text(path, access), path, access)


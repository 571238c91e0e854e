"""The tracer's native scene format: TOML (read with the standard library's ``tomllib``).

A scene file has these tables, all optional except that at least one object must exist::

    [scene]          unit (metadata), description, ambient
    [camera]         position, look_at, up, fov_deg, mirror
    [environment]    kind = "sky" | "constant" | "image", and the keys of that kind
    [render]         default render settings (width, height, depth, spp, spectral_samples,
                     threshold, seed)
    [materials.NAME] color, ambient, diffuse, specular, transmission, shininess, ior
    [[spheres]]      name, center, radius, material
    [[bubbles]]      name, center, radius, n_film, shininess, and a [bubbles.film] table
    [[meshes]]       name, path | vertices + faces (0-based), material, translate, scale
    [[lights]]       position, intensity, color

Every key is checked: an unknown key (a typo) is an error naming it, as is a value of the wrong
type or out of range.  Errors carry the line of the offending key where it can be found.  The
full description, with examples, is ``docs/scene-format.md``.

:func:`scene_to_toml_text` writes a Scene back as TOML (by hand, with strict escaping, and
checked by parsing it again), and :func:`seed_to_toml` converts a seed-format file.
"""

from __future__ import annotations

import difflib
import math
import os
import re
import tomllib
import warnings
from pathlib import Path

import numpy as np

from .errors import SceneError, SceneWarning
from .scene import (
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
from .seedformat import degenerate_faces, load_seed_scene, read_scene_text

__all__ = [
    "load_toml_scene",
    "parse_toml_text",
    "scene_to_toml_text",
    "save_toml_scene",
    "seed_to_toml",
    "IMAGE_SUFFIXES",
]

#: Image files an ``[environment] kind = "image"`` may name, and what reads them.
IMAGE_SUFFIXES = {
    ".npy": "numpy (float32/float64, (H, W, 3), linear RGB)",
    ".png": "Pillow (8-bit sRGB, decoded to linear)",
    ".jpg": "Pillow (8-bit sRGB, decoded to linear)",
    ".jpeg": "Pillow (8-bit sRGB, decoded to linear)",
    ".hdr": "OpenCV, if opencv-python-headless is installed (Radiance RGBE, linear)",
    ".exr": "OpenEXR, if the OpenEXR package is installed (linear)",
}

_BARE_KEY = re.compile(r"[A-Za-z0-9_-]+")
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
def _keyname(kp) -> str:
    out = ""
    for k in kp:
        if isinstance(k, int):
            out += f"[{k}]"
        else:
            k = k if _BARE_KEY.fullmatch(k) else _quote(k)
            out += f".{k}" if out else k
    return out


class _Ctx:
    def __init__(self, path: str, text: str):
        self.path = path
        self.text = text
        self.base = Path(path).resolve().parent if path != "<string>" else Path.cwd()
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
                    f"unknown key '{key}' in {where}{hint} (allowed: {', '.join(sorted(allowed))})",
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
    def number(self, kp, v, lo=None, hi=None, lo_open=False) -> float:
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise self.bad(kp, f"must be a number, got {_typename(v)}")
        v = float(v)
        if not math.isfinite(v):
            raise self.bad(kp, f"must be a finite number, got {v}")
        if lo is not None and (v <= lo if lo_open else v < lo):
            rel = ">" if lo_open else ">="
            raise self.bad(kp, f"must be {rel} {lo:g}, got {v:g}")
        if hi is not None and v > hi:
            raise self.bad(kp, f"must be <= {hi:g}, got {v:g}")
        return v

    def integer(self, kp, v, lo=None) -> int:
        if isinstance(v, bool) or not isinstance(v, int):
            raise self.bad(kp, f"must be an integer, got {_typename(v)}")
        if lo is not None and v < lo:
            raise self.bad(kp, f"must be >= {lo}, got {v}")
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
            from .seedformat import srgb8_to_linear

            return srgb8_to_linear([int(g, 16) for g in m.groups()])
        if not isinstance(v, list) or len(v) != 3:
            raise self.bad(kp, f"must be a colour [r, g, b] (linear) or \"#rrggbb\" (sRGB), got {_short(v)}")
        return tuple(self.number(kp, x, 0.0, 1.0 if albedo else None) for x in v)

    def file(self, kp, v) -> Path:
        rel = self.string(kp, v)
        full = (self.base / rel) if not os.path.isabs(rel) else Path(rel)
        if not full.is_file():
            raise self.bad(kp, f"file not found: {rel} (looked for {full})")
        return full


def _typename(v) -> str:
    return {bool: "a boolean", int: "an integer", float: "a number", str: "a string",
            list: "an array", dict: "a table"}.get(type(v), type(v).__name__)


def _short(v) -> str:
    s = repr(v)
    return s if len(s) <= 60 else s[:57] + "..."


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
}
_RENDER_INT = {"width": 1, "height": 1, "depth": 1, "spp": 1, "spectral_samples": 1, "seed": 0}
_RENDER_FLOAT = {"threshold": 0.0}
_RENDER_CHOICE = {"spectral_method": ("auto", "point", "band")}


def parse_toml_text(text: str, path="<string>") -> Scene:
    """Build a Scene from TOML text; ``path`` names it in errors and anchors relative paths."""
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

    c = _Ctx(path, text)
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
        name = c.string(kp + ("name",), t["name"]) if "name" in t else Sphere.__dataclass_fields__["name"].default
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
        kp = ("lights", i)
        c.keys(kp, t, {"position", "intensity", "color"}, ("position",), "[[lights]]")
        scene.lights.append(PointLight(
            position=c.vec3(kp + ("position",), t["position"]),
            intensity=c.number(kp + ("intensity",), t.get("intensity", 1.0), 0.0),
            color=c.color(kp + ("color",), t["color"], albedo=False) if "color" in t else (1.0, 1.0, 1.0),
        ))

    if not (scene.spheres or scene.bubbles or scene.meshes):
        raise SceneError(path, None, "no objects: the file has no [[spheres]], [[bubbles]] or [[meshes]]")
    return scene


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
        env.image = _load_image(c, kp + ("path",), c.file(kp + ("path",), t["path"]))
    return env


def _render(c: _Ctx, t) -> dict:
    kp = ("render",)
    c.table(kp, t)
    c.keys(kp, t, set(_RENDER_INT) | set(_RENDER_FLOAT) | set(_RENDER_CHOICE))
    out = {}
    for key, v in t.items():
        if key in _RENDER_INT:
            out[key] = c.integer(kp + (key,), v, _RENDER_INT[key])
        elif key in _RENDER_CHOICE:
            if v not in _RENDER_CHOICE[key]:
                raise c.bad(kp + (key,), f"must be one of {', '.join(map(repr, _RENDER_CHOICE[key]))}, got {v!r}")
            out[key] = v
        else:
            out[key] = c.number(kp + (key,), v, _RENDER_FLOAT[key])
    return out


def _material(c: _Ctx, kp, t, name, inline) -> Material:
    c.table(kp, t, "a material")
    allowed = _MATERIAL_KEYS | ({"name"} if inline else set())
    c.keys(kp, t, allowed, where="an inline material" if inline else f"[{_keyname(kp)}]")
    d = Material()
    unit = dict(lo=0.0, hi=1.0)
    return Material(
        name=c.string(kp + ("name",), t["name"]) if "name" in t else name,
        color=c.color(kp + ("color",), t["color"]) if "color" in t else d.color,
        ambient=c.number(kp + ("ambient",), t.get("ambient", d.ambient), **unit),
        diffuse=c.number(kp + ("diffuse",), t.get("diffuse", d.diffuse), **unit),
        specular=c.number(kp + ("specular",), t.get("specular", d.specular), **unit),
        transmission=c.number(kp + ("transmission",), t.get("transmission", d.transmission), **unit),
        shininess=c.number(kp + ("shininess",), t.get("shininess", d.shininess), 0.0),
        ior=c.number(kp + ("ior",), t.get("ior", d.ior), 0.0, lo_open=True),
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
    c.keys(kp, t, {"name", "center", "radius", "n_film", "shininess", "film"}, ("center", "radius"),
           "[[bubbles]]")
    d = Bubble(center=(0.0, 0.0, 0.0), radius=1.0)
    n_film = t.get("n_film", d.n_film)
    if isinstance(n_film, str):
        if n_film != "water":
            raise c.bad(kp + ("n_film",), f"must be \"water\" or a number, got '{n_film}'")
    else:
        n_film = c.number(kp + ("n_film",), n_film, 0.0, lo_open=True)
    return Bubble(
        center=c.vec3(kp + ("center",), t["center"]),
        radius=c.number(kp + ("radius",), t["radius"], 0.0, lo_open=True),
        film=_film(c, kp + ("film",), t["film"]) if "film" in t else FilmProfile(),
        n_film=n_film,
        shininess=c.number(kp + ("shininess",), t.get("shininess", d.shininess), 0.0),
        name=c.string(kp + ("name",), t["name"]) if "name" in t else d.name,
    )


def _film(c: _Ctx, kp, t) -> FilmProfile:
    c.table(kp, t, "the film profile")
    kind = c.string(kp + ("kind",), t.get("kind", "uniform"))
    if kind not in _FILM_KEYS:
        raise c.bad(kp + ("kind",), f"must be one of {', '.join(map(repr, _FILM_KEYS))}, got '{kind}'")
    c.keys(kp, t, _FILM_KEYS[kind], ("path",) if kind == "map" else (), f"a film of kind '{kind}'")
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
        full = c.file(pkp, t["path"])
        if full.suffix.lower() != ".npy":
            raise c.bad(pkp, f"a thickness map is a .npy file, got '{full.name}'")
        table = _load_npy(c, pkp, full)
        if table.ndim != 2 or table.shape[0] < 2 or table.shape[1] < 1:
            raise c.bad(pkp, f"a thickness map is a 2-D array (N_theta >= 2, N_phi >= 1), got shape {table.shape}")
        table = table.astype(np.float64)
        if not np.all(np.isfinite(table)) or (table < 0).any():
            raise c.bad(pkp, "thickness map values must be finite and >= 0 (nanometres)")
        f.table = np.ascontiguousarray(table)
    return f


def _mesh(c: _Ctx, kp, t, materials) -> Mesh:
    c.keys(kp, t, {"name", "path", "vertices", "faces", "material", "translate", "scale"}, (), "[[meshes]]")
    name = c.string(kp + ("name",), t["name"]) if "name" in t else "mesh"
    if "path" in t:
        for key in ("vertices", "faces"):
            if key in t:
                raise c.bad(kp + (key,), "give either 'path' or 'vertices' and 'faces', not both")
        verts, faces = _load_mesh_file(c, kp + ("path",), c.file(kp + ("path",), t["path"]))
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
    if "scale" in t:
        verts = verts * c.number(kp + ("scale",), t["scale"], 0.0, lo_open=True)
    if "translate" in t:
        verts = verts + np.array(c.vec3(kp + ("translate",), t["translate"]))
    bad = degenerate_faces(verts, faces)
    if bad.all():
        raise c.bad(fkp, f"the mesh has no usable face: all {len(faces)} have zero area")
    if bad.any():
        warnings.warn(f"{c.path}:{c.line(fkp)}: {_keyname(kp)}: {int(bad.sum())} zero-area face(s)"
                      " skipped", SceneWarning, stacklevel=3)
    return Mesh(vertices=np.ascontiguousarray(verts), faces=np.ascontiguousarray(faces[~bad]),
                material=_material_ref(c, kp, t, materials, name), name=name)


def _load_mesh_file(c: _Ctx, kp, full: Path):
    try:
        import trimesh
    except ImportError:
        raise c.bad(kp, "reading mesh files needs the 'trimesh' package (pip install trimesh)") from None
    try:
        mesh = trimesh.load(str(full), force="mesh", process=False)
    except Exception as exc:  # trimesh raises many kinds for unreadable files
        raise c.bad(kp, f"cannot read mesh '{full.name}': {exc}") from None
    verts = np.asarray(getattr(mesh, "vertices", np.empty((0, 3))), dtype=np.float64).reshape(-1, 3)
    faces = np.asarray(getattr(mesh, "faces", np.empty((0, 3))), dtype=np.int64).reshape(-1, 3)
    if len(faces) == 0:
        raise c.bad(kp, f"mesh '{full.name}' has no triangles")
    if not np.all(np.isfinite(verts)):
        raise c.bad(kp, f"mesh '{full.name}' has non-finite vertex coordinates")
    return verts, faces


def _load_npy(c: _Ctx, kp, full: Path) -> np.ndarray:
    try:
        arr = np.load(full, allow_pickle=False)
    except Exception as exc:
        raise c.bad(kp, f"cannot read '{full.name}' as a .npy array: {exc}") from None
    if not isinstance(arr, np.ndarray) or arr.dtype.kind not in "fiu":
        raise c.bad(kp, f"'{full.name}' must hold a numeric array")
    return arr


def _load_image(c: _Ctx, kp, full: Path) -> np.ndarray:
    """An equirectangular environment image as linear RGB float32 (H, W, 3)."""
    suffix = full.suffix.lower()
    if suffix not in IMAGE_SUFFIXES:
        raise c.bad(kp, f"unsupported image type '{suffix}' (supported: {', '.join(IMAGE_SUFFIXES)})")
    if suffix == ".npy":
        img = _load_npy(c, kp, full)
        if img.dtype.kind != "f":
            raise c.bad(kp, f"a .npy environment holds float32/float64 linear RGB, got {img.dtype}")
    elif suffix in (".png", ".jpg", ".jpeg"):
        from PIL import Image

        try:
            with Image.open(full) as im:
                srgb = np.asarray(im.convert("RGB"), dtype=np.float64) / 255.0
        except Exception as exc:
            raise c.bad(kp, f"cannot read image '{full.name}': {exc}") from None
        import colour

        img = np.asarray(colour.cctf_decoding(srgb, function="sRGB"), dtype=np.float64)
    elif suffix == ".hdr":
        try:
            import cv2
        except ImportError:
            raise c.bad(kp, "reading .hdr needs OpenCV (pip install opencv-python-headless);"
                            " or convert the image to a .npy array") from None
        bgr = cv2.imread(str(full), cv2.IMREAD_ANYDEPTH | cv2.IMREAD_COLOR)
        if bgr is None:
            raise c.bad(kp, f"cannot read image '{full.name}'")
        img = np.ascontiguousarray(bgr[..., ::-1])
    else:  # .exr
        try:
            import OpenEXR
        except ImportError:
            raise c.bad(kp, "reading .exr needs the OpenEXR package (pip install OpenEXR);"
                            " or convert the image to a .npy array") from None
        try:
            with OpenEXR.File(str(full)) as f:
                ch = f.channels()
                if "RGB" in ch:
                    img = np.asarray(ch["RGB"].pixels)
                elif "RGBA" in ch:
                    img = np.asarray(ch["RGBA"].pixels)[..., :3]
                elif all(k in ch for k in "RGB"):
                    img = np.stack([np.asarray(ch[k].pixels) for k in "RGB"], axis=-1)
                else:
                    raise ValueError(f"no R, G, B channels (has {', '.join(ch)})")
        except Exception as exc:
            raise c.bad(kp, f"cannot read image '{full.name}': {exc}") from None
    if img.ndim != 3 or img.shape[2] != 3 or img.shape[0] < 1 or img.shape[1] < 1:
        raise c.bad(kp, f"an environment image is (H, W, 3) RGB, got shape {img.shape}")
    img = np.ascontiguousarray(img, dtype=np.float32)
    if not np.all(np.isfinite(img)) or (img < 0).any():
        raise c.bad(kp, "environment image values must be finite and >= 0 (linear RGB)")
    return img


def load_toml_scene(path) -> Scene:
    """Read a TOML scene file; raises SceneError('FILE:LINE: ...') on any problem."""
    path = os.fspath(path)
    return parse_toml_text(read_scene_text(path), path)


# ==========================================================================================
# Writing
# ==========================================================================================
def _quote(s: str) -> str:
    """A TOML basic string: backslash, quote and control characters escaped."""
    out = ['"']
    for ch in s:
        o = ord(ch)
        if ch == "\\":
            out.append("\\\\")
        elif ch == '"':
            out.append('\\"')
        elif ch in "\b\t\n\f\r":
            out.append({"\b": "\\b", "\t": "\\t", "\n": "\\n", "\f": "\\f", "\r": "\\r"}[ch])
        elif o < 0x20 or o == 0x7F:
            out.append(f"\\u{o:04X}")
        else:
            out.append(ch)
    out.append('"')
    return "".join(out)


def _key(k: str) -> str:
    return k if _BARE_KEY.fullmatch(k) else _quote(k)


def _val(v) -> str:
    if isinstance(v, (bool, np.bool_)):
        return "true" if v else "false"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        v = float(v)
        if not math.isfinite(v):
            raise ValueError(f"cannot write the non-finite number {v} to TOML")
        return repr(v)
    if isinstance(v, str):
        return _quote(v)
    if isinstance(v, (list, tuple, np.ndarray)):
        return "[" + ", ".join(_val(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{_key(k)} = {_val(x)}" for k, x in v.items()) + " }" if v else "{}"
    raise TypeError(f"cannot write {type(v).__name__} to TOML")


def _table(lines, header, items):
    lines.append(header)
    for k, v in items.items():
        lines.append(f"{_key(k)} = {_val(v)}")
    lines.append("")


def _material_dict(m: Material) -> dict:
    return {"color": list(m.color), "ambient": m.ambient, "diffuse": m.diffuse, "specular": m.specular,
            "transmission": m.transmission, "shininess": m.shininess, "ior": m.ior}


def scene_to_toml_text(scene: Scene, toml_path=None, *, unit: str = "m", header: str | None = None) -> str:
    """The scene as TOML text that :func:`parse_toml_text` reads back to an equal Scene.

    Arrays that TOML cannot hold sensibly (an image environment, a thickness map) are saved as
    ``.npy`` files beside ``toml_path`` and named relative to it; without ``toml_path`` such a
    scene raises ValueError.  Meshes are written inline (vertices and 0-based faces).
    ``unit`` goes to ``[scene] unit``; ``header`` (lines of text) becomes a leading comment.
    """
    toml_path = Path(toml_path) if toml_path is not None else None

    def save_array(arr, suffix):
        if toml_path is None:
            raise ValueError("this scene holds an array (image environment or thickness map):"
                             " give toml_path so it can be saved as .npy beside the TOML file")
        name = f"{toml_path.stem}.{suffix}.npy"
        np.save(toml_path.parent / name, arr)
        return name

    lines: list[str] = []
    if header:
        lines += [f"# {ln}".rstrip() for ln in header.splitlines()] + [""]
    _table(lines, "[scene]", {"unit": unit, "ambient": list(scene.ambient)})
    cam = scene.camera
    _table(lines, "[camera]", {"position": list(cam.position), "look_at": list(cam.look_at),
                               "up": list(cam.up), "fov_deg": cam.fov_deg,
                               **({"mirror": True} if cam.mirror else {})})
    env = scene.environment
    e = {"kind": env.kind}
    if env.kind == "constant":
        e.update(color=list(env.color), intensity=env.intensity)
    elif env.kind == "sky":
        e.update(intensity=env.intensity, up=list(env.up), sun_direction=list(env.sun_direction))
    elif env.kind == "image":
        if env.image is None:
            raise ValueError("image environment without an image")
        e.update(path=save_array(np.asarray(env.image), "environment"), intensity=env.intensity,
                 up=list(env.up))
    else:
        raise ValueError(f"unknown environment kind {env.kind!r}")
    _table(lines, "[environment]", e)
    if scene.render_defaults:
        _table(lines, "[render]", dict(scene.render_defaults))

    # Materials: one [materials.NAME] per distinct name; a second, different material under a
    # name already taken is written inline with its name.
    named: dict[str, Material] = {}
    for obj in scene.spheres + scene.meshes:
        named.setdefault(obj.material.name, obj.material)
    for name, m in named.items():
        _table(lines, f"[materials.{_key(name)}]", _material_dict(m))

    def mat_ref(m: Material):
        if named.get(m.name) == m:
            return m.name
        return {"name": m.name, **_material_dict(m)}

    for s in scene.spheres:
        _table(lines, "[[spheres]]", {"name": s.name, "center": list(s.center), "radius": s.radius,
                                      "material": mat_ref(s.material)})
    for i, b in enumerate(scene.bubbles):
        _table(lines, "[[bubbles]]", {"name": b.name, "center": list(b.center), "radius": b.radius,
                                      "n_film": b.n_film, "shininess": b.shininess})
        f = b.film
        fd = {"kind": f.kind}
        if f.kind == "uniform":
            fd["thickness_nm"] = f.thickness_nm
        elif f.kind == "draining":
            fd.update(top_nm=f.top_nm, bottom_nm=f.bottom_nm, exponent=f.exponent)
        elif f.kind == "map":
            if f.table is None:
                raise ValueError(f"bubble {b.name!r}: a film map without a table")
            fd.update(path=save_array(np.asarray(f.table), f"bubble{i}.film"))
        else:
            raise ValueError(f"bubble {b.name!r}: unknown film kind {f.kind!r}")
        default = FilmProfile()
        for key in ("swirl", "swirl_scale", "seed", "up"):  # all of them for draining, else if set
            if f.kind == "draining" or getattr(f, key) != getattr(default, key):
                fd[key] = list(getattr(f, key)) if key == "up" else getattr(f, key)
        _table(lines, "[bubbles.film]", fd)
    for m in scene.meshes:
        _table(lines, "[[meshes]]", {"name": m.name, "material": mat_ref(m.material)})
        lines.pop()
        for key, rows in (("vertices", np.asarray(m.vertices, float)), ("faces", np.asarray(m.faces, int))):
            lines.append(f"{key} = [")
            lines += [f"    {_val(list(r))}," for r in rows]
            lines.append("]")
        lines.append("")
    for light in scene.lights:
        _table(lines, "[[lights]]", {"position": list(light.position), "intensity": light.intensity,
                                     "color": list(light.color)})
    text = "\n".join(lines).rstrip("\n") + "\n"
    tomllib.loads(text)  # what we write must parse
    return text


def save_toml_scene(scene: Scene, toml_path, *, unit: str = "m", header: str | None = None) -> Path:
    """Write the scene to ``toml_path`` (UTF-8), with any arrays as .npy files beside it."""
    toml_path = Path(toml_path)
    text = scene_to_toml_text(scene, toml_path, unit=unit, header=header)
    toml_path.write_text(text, encoding="utf-8")
    return toml_path


def seed_to_toml(seed_path, toml_path) -> Path:
    """Convert a seed-format scene file to TOML (the Scene read back from it is equal)."""
    scene = load_seed_scene(seed_path)
    header = (
        f"Converted from the seed-format file {Path(seed_path).name} by tracer.tomlformat.seed_to_toml.\n"
        "Units are the seed's screen-like units; the camera is Camera.seed_default().\n"
        "See docs/scene-format.md for how each seed field maps to these keys."
    )
    return save_toml_scene(scene, toml_path, unit="seed", header=header)


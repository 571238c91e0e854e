"""Writing a Scene as TOML: :func:`scene_to_toml_text` and :func:`save_toml_scene`.

The text is written by ``tomli_w.dumps`` from a plain dict of the scene (numbers as Python
floats, so each is written in its shortest round-tripping form and read back bit for bit),
and parsed again with ``tomllib`` before it is returned.  Arrays that TOML cannot hold
sensibly (an image environment, a thickness map) are saved as ``.npy`` files beside the TOML
file.  :mod:`tracer.scene.toml_read` reads the result back to an equal Scene.
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np
import tomli_w

from bubbleoptics.atomic import write_atomically

from .model import FilmProfile, Material, PointLight, Scene

__all__ = ["scene_to_toml_text", "save_toml_scene"]


def _plain(v):
    """*v* as the str, bool, int, float, list and dict that tomli-w writes (numpy included)."""
    if isinstance(v, (bool, np.bool_)):
        return bool(v)
    if isinstance(v, (int, np.integer)):
        return int(v)
    if isinstance(v, (float, np.floating)):
        v = float(v)
        if not math.isfinite(v):
            raise ValueError(f"cannot write the non-finite number {v} to TOML")
        return v
    if isinstance(v, str):
        return v
    if isinstance(v, (list, tuple, np.ndarray)):
        return [_plain(x) for x in v]
    if isinstance(v, dict):
        return {k: _plain(x) for k, x in v.items()}
    raise TypeError(f"cannot write {type(v).__name__} to TOML")


def _material_dict(m: Material) -> dict:
    return {"color": m.color, "ambient": m.ambient, "diffuse": m.diffuse, "specular": m.specular,
            "transmission": m.transmission, "shininess": m.shininess, "ior": m.ior}


def _environment_dict(env, save_array) -> dict:
    e = {"kind": env.kind}
    if env.kind == "constant":
        e.update(color=env.color, intensity=env.intensity)
    elif env.kind == "sky":
        e.update(intensity=env.intensity, up=env.up, sun_direction=env.sun_direction)
    elif env.kind == "image":
        if env.image is None:
            raise ValueError("image environment without an image")
        e.update(path=save_array(np.asarray(env.image), "environment"), intensity=env.intensity, up=env.up)
    else:
        raise ValueError(f"unknown environment kind {env.kind!r}")
    return e


def _light_dict(light: PointLight, unit: str) -> dict:
    """A light's table: position, intensity, colour, and falloff, radius and samples where they
    differ from a point light's defaults (so a coursework light is written with position, intensity and colour only)."""
    ld = {"position": light.position, "intensity": light.intensity, "color": light.color}
    default = PointLight(position=light.position)
    if light.falloff != default.falloff:
        if light.falloff == "inverse_square" and unit != "m":
            raise ValueError(f"a light with inverse-square falloff takes lengths in metres: write the scene"
                             f" with unit='m' (got unit={unit!r})")
        ld["falloff"] = light.falloff
    if light.radius != default.radius:
        ld["radius"] = light.radius
    if light.samples != default.samples:
        ld["samples"] = light.samples
    return ld


def _film_dict(b, i, save_array) -> dict:
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
    elif f.kind == "simulated":
        if f.series is None:
            raise ValueError(f"bubble {b.name!r}: a simulated film without a series")
        fd.update(path=save_array(f.series, f"bubble{i}.film"), time=f.time_s, rupture_nm=f.rupture_nm)
    else:
        raise ValueError(f"bubble {b.name!r}: unknown film kind {f.kind!r}")
    default = FilmProfile()
    for key in ("swirl", "swirl_scale", "seed", "up"):  # all of them for draining, else if set
        if f.kind == "draining" or getattr(f, key) != getattr(default, key):
            fd[key] = getattr(f, key)
    return fd


def scene_to_toml_text(scene: Scene, toml_path=None, *, unit: str = "m", header: str | None = None) -> str:
    """The scene as TOML text that :func:`tracer.scene.toml_read.parse_toml_text` reads back to an equal Scene.

    Arrays that TOML cannot hold sensibly (an image environment, a thickness map) are saved as
    ``.npy`` files beside ``toml_path`` (``NAME.environment.npy``, ``NAME.bubble0.film.npy``)
    and named relative to it; without ``toml_path`` such a scene raises ValueError.  Materials
    become ``[materials.NAME]`` tables named after ``Material.name`` (a second, different
    material under a name already used is written with its object, with its name); meshes are
    written with their vertices, 0-based faces, vertex normals (if any) and shading.  ``unit``
    goes to ``[scene] unit``; ``header`` (lines of text) becomes a leading comment.  A non-finite
    number is a ValueError.
    """
    toml_path = Path(toml_path) if toml_path is not None else None

    def save_array(arr, suffix):
        """Save *arr* beside the TOML file: an array as ``.npy``, a thickness series as its own
        ``.npz`` (:meth:`bubbleoptics.filmflow.ThicknessSeries.save`); returns the file's name."""
        if toml_path is None:
            raise ValueError("this scene holds an array (image environment, thickness map or series):"
                             " give toml_path so it can be saved beside the TOML file")
        if not isinstance(arr, np.ndarray):  # a ThicknessSeries
            name = f"{toml_path.stem}.{suffix}.npz"
            arr.save(toml_path.parent / name)
            return name
        name = f"{toml_path.stem}.{suffix}.npy"

        def write(tmp):
            with open(tmp, "wb") as f:  # a file object: np.save(name) would append ".npy" to the name
                np.save(f, arr)

        write_atomically(toml_path.parent / name, write)
        return name

    cam = scene.camera
    doc = {
        "scene": {"unit": unit, "ambient": scene.ambient},
        "camera": {"position": cam.position, "look_at": cam.look_at, "up": cam.up, "fov_deg": cam.fov_deg,
                   **({"mirror": True} if cam.mirror else {})},
        "environment": _environment_dict(scene.environment, save_array),
    }
    if scene.render_defaults:
        doc["render"] = dict(scene.render_defaults)

    # Materials: one [materials.NAME] per distinct name; a second, different material under a
    # name already taken is written with its object, with its name.
    named: dict[str, Material] = {}
    for obj in scene.spheres + scene.meshes:
        named.setdefault(obj.material.name, obj.material)
    if named:
        doc["materials"] = {name: _material_dict(m) for name, m in named.items()}

    def mat_ref(m: Material):
        return m.name if named.get(m.name) == m else {"name": m.name, **_material_dict(m)}

    objects = {
        "spheres": [{"name": s.name, "center": s.center, "radius": s.radius, "material": mat_ref(s.material)}
                    for s in scene.spheres],
        "bubbles": [{"name": b.name, "center": b.center, "radius": b.radius, "n_film": b.n_film,
                     "shininess": b.shininess, **({} if b.film_model == "airy" else {"film_model": b.film_model}),
                     "film": _film_dict(b, i, save_array)}
                    for i, b in enumerate(scene.bubbles)],
        "meshes": [{"name": m.name, "material": mat_ref(m.material),
                    "vertices": np.asarray(m.vertices, float), "faces": np.asarray(m.faces, int),
                    **({} if m.normals is None else {"normals": np.asarray(m.normals, float)}),
                    "shading": m.shading}
                   for m in scene.meshes],
        "lights": [_light_dict(light, unit) for light in scene.lights],
    }
    doc.update((key, items) for key, items in objects.items() if items)
    text = tomli_w.dumps(_plain(doc))
    if header:
        text = "".join(f"# {ln}".rstrip() + "\n" for ln in header.splitlines()) + "\n" + text
    tomllib.loads(text)  # what we write must parse
    return text


def save_toml_scene(scene: Scene, toml_path, *, unit: str = "m", header: str | None = None) -> Path:
    """Write the scene to ``toml_path`` (UTF-8, atomically), with any arrays as .npy files beside it."""
    toml_path = Path(toml_path)
    text = scene_to_toml_text(scene, toml_path, unit=unit, header=header)
    write_atomically(toml_path, lambda tmp: Path(tmp).write_text(text, encoding="utf-8"))
    return toml_path

"""Convert a scene file in the coursework's text format to TOML: :func:`coursework_to_toml`.

The scene read back from the TOML file is equal, field by field, to the one read from the
coursework file (``tests/tracer/test_scene_io.py`` checks this for every such file in ``data/``).
"""

from __future__ import annotations

from pathlib import Path

from .block_format import load_coursework_scene
from .toml_write import save_toml_scene

__all__ = ["coursework_to_toml"]


def coursework_to_toml(coursework_path, toml_path) -> Path:
    """Convert a coursework-format scene file to TOML (the Scene read back from it is equal)."""
    scene = load_coursework_scene(coursework_path)
    header = (
        f"Converted from the coursework-format file {Path(coursework_path).name} by\n"
        "tracer.scene.convert.coursework_to_toml. Units are the coursework's screen-like\n"
        "units; the camera is Camera.coursework_default(). See docs/scene-format.md for how each\n"
        "coursework field maps to these keys."
    )
    return save_toml_scene(scene, toml_path, unit="coursework", header=header)

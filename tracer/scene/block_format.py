"""Reader for the coursework's text scene format (its section 3.1, listings 3.1 and 3.2).

A scene file is UTF-8 text made of blocks separated by blank lines.  Each block starts with a
tag line::

    s NAME      sphere:   centre "x y z", radius, material (5 lines)
    b NAME      bubble:   outer centre, outer radius, outer material,
                          inner centre, inner radius, inner material
    t NAME      triangulated object: "v x y z" lines, "f i j k" lines (vertices counted
                from 1), a line "-", material
    l           light:    position "x y z", intensity in [0, 1]
                (a block whose first line is exactly "1" is also a light: the PDF
                transcription of the coursework reads the tag "l" as the digit one)

and a material is five lines: ``R G B`` (integers 0-255), ``ka kd ks kt`` (each in [0, 1]),
the specular exponent (>= 0), the refraction index (> 0) and the dispersion (>= 0).  Lines
whose first non-blank character is ``#`` are comments (an extension: the coursework has none).

How each field becomes a :mod:`tracer.scene` object, and why, is in ``docs/scene-format.md``.
Every problem raises :class:`tracer.scene.errors.SceneError` with the 1-based line to blame.
"""

from __future__ import annotations

import math
import os
import re
import warnings
from decimal import Decimal

import numpy as np

from bubbleoptics.colorimetry import srgb_to_linear_srgb
from bubbleoptics.messages import shorten

from ..kernels.geometry import degenerate_triangles
from .errors import SceneError, SceneWarning
from .limits import MAX_INDEX, MAX_MAGNITUDE
from .model import (
    COURSEWORK_NM_PER_UNIT,
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
from .file_access import ANYWHERE, FileAccess, check_name
from .text import read_scene_text

__all__ = ["load_coursework_scene", "parse_coursework_text", "split_lines", "LineReader", "srgb8_to_linear",
           "CONCENTRIC_RTOL"]

#: A bubble's inner centre may differ from its outer centre by at most this times the outer radius.
CONCENTRIC_RTOL = 1e-9

# ASCII digits only: Python's \d also matches other scripts' digits ("١٠٠", "３００"), which
# float() and int() would accept
_NUMBER = re.compile(r"[+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?", re.ASCII)
_INTEGER = re.compile(r"[+-]?\d+", re.ASCII)
_NON_FINITE = {"nan", "inf", "infinity"}

_KINDS = {"s": "sphere", "b": "bubble", "t": "triangulated object", "l": "light", "1": "light"}


def srgb8_to_linear(rgb) -> tuple[float, float, float]:
    """Decode 8-bit sRGB components (0-255) to linear RGB in [0, 1] (IEC 61966-2-1,
    :func:`bubbleoptics.colorimetry.srgb_to_linear_srgb`)."""
    return tuple(srgb_to_linear_srgb(np.asarray(rgb, dtype=float) / 255.0).tolist())


class LineReader:
    """Holds the file's name for error messages and parses fields of one line."""

    def __init__(self, path: str):
        self.path = path

    def error(self, line, message):
        return SceneError(self.path, line, message)

    def number(self, line, token, what):
        if _NUMBER.fullmatch(token):
            value = float(token)
            if not math.isfinite(value):
                raise self.error(line, f"{what}: {shorten(token)} is too large (not a finite number)")
            if abs(value) > MAX_MAGNITUDE:
                raise self.error(line, f"{what}: {shorten(token)} is outside -{MAX_MAGNITUDE:g} to {MAX_MAGNITUDE:g} "
                                       "(tracer.scene.limits)")
            return value
        if token.lower().lstrip("+-") in _NON_FINITE:
            raise self.error(line, f"{what} is {token}: it must be a finite number")
        raise self.error(line, f"{what}: '{shorten(token)}' is not a number")

    def numbers(self, line, fields, names, what):
        if len(fields) != len(names):
            raise self.error(
                line,
                f"{what}: expected {len(names)} number{'s' if len(names) > 1 else ''}"
                f" ({' '.join(names)}), found {len(fields)} field{'s' if len(fields) != 1 else ''}"
                + (f" '{shorten(' '.join(fields), 60)}'" if fields else ""),
            )
        return [self.number(line, tok, f"{what} ({name})" if len(names) > 1 else what)
                for tok, name in zip(fields, names)]

    def integer(self, line, token, what):
        if not _INTEGER.fullmatch(token):
            raise self.error(line, f"{what}: '{shorten(token)}' is not an integer")
        if len(token.lstrip("+-")) > 30:  # beyond every range here (and int() refuses 4300+ digits)
            raise self.error(line, f"{what}: {shorten(token)} is too large")
        return int(token)


class _Block:
    """The lines of one block, consumed in order; knows where the block ends."""

    def __init__(self, reader: LineReader, lines, at_eof: bool):
        self.r = reader
        self.lines = lines  # [(lineno, text)], non-empty
        self.pos = 0
        self.at_eof = at_eof
        self.end_line = lines[-1][0] + 1  # the line after the block's last line
        self.label = "block"

    def take(self, what):
        """The next line's fields, or an error at the line after the block."""
        if self.pos >= len(self.lines):
            where = "the file ends" if self.at_eof else "the block ends (blank line)"
            raise self.r.error(self.end_line, f"{self.label}: {where} before its {what}")
        line, text = self.lines[self.pos]
        self.pos += 1
        return line, text.split()

    def peek(self):
        return self.lines[self.pos] if self.pos < len(self.lines) else None

    def finish(self):
        if self.pos < len(self.lines):
            line, text = self.lines[self.pos]
            raise self.r.error(
                line,
                f"unexpected line '{shorten(text.strip(), 60)}' after the end of {self.label}"
                " (blocks must be separated by a blank line)",
            )

    # -- field groups ----------------------------------------------------------------------
    def vector(self, what):
        line, fields = self.take(f"{what} (x y z)")
        return line, tuple(self.r.numbers(line, fields, ("x", "y", "z"), f"{self.label}: {what}"))

    def scalar(self, what):
        line, fields = self.take(what)
        (value,) = self.r.numbers(line, fields, ("value",), f"{self.label}: {what}")
        return line, value

    def radius(self, what="radius"):
        line, value = self.scalar(what)
        if not value > 0:
            raise self.r.error(line, f"{self.label}: {what} must be positive, got {value:g}")
        return line, value

    def material(self, name, which=""):
        """Five material lines -> (Material, dispersion, exponent line)."""
        pre = f"{which} " if which else ""
        line, fields = self.take(f"{pre}material colour (R G B)")
        what = f"{self.label}: {pre}colour"
        if len(fields) != 3:
            raise self.r.error(line, f"{what}: expected 3 integers (R G B), found {len(fields)} fields")
        rgb = []
        for tok, ch in zip(fields, "RGB"):
            if _NUMBER.fullmatch(tok) and not _INTEGER.fullmatch(tok):
                raise self.r.error(line, f"{what} ({ch}): '{shorten(tok)}' is not an integer 0-255")
            v = self.r.integer(line, tok, f"{what} ({ch})")
            if not 0 <= v <= 255:
                raise self.r.error(line, f"{what} ({ch}) = {shorten(str(v))} is outside 0-255")
            rgb.append(v)

        line, fields = self.take(f"{pre}material coefficients (ka kd ks kt)")
        coeffs = self.r.numbers(line, fields, ("ka", "kd", "ks", "kt"), f"{self.label}: {pre}coefficients")
        for value, cname in zip(coeffs, ("ka", "kd", "ks", "kt")):
            if not 0.0 <= value <= 1.0:
                raise self.r.error(line, f"{self.label}: {pre}coefficient {cname} = {value:g} is outside [0, 1]")

        exp_line, exponent = self.scalar(f"{pre}specular exponent")
        if exponent < 0:
            raise self.r.error(exp_line, f"{self.label}: {pre}specular exponent must be >= 0, got {exponent:g}")
        line, index = self.scalar(f"{pre}refraction index")
        if not 0 < index <= MAX_INDEX:
            raise self.r.error(line, f"{self.label}: {pre}refraction index must be > 0 and <= {MAX_INDEX:g}, "
                                     f"got {index:g}")
        line, dispersion = self.scalar(f"{pre}dispersion")
        if dispersion < 0:
            raise self.r.error(line, f"{self.label}: {pre}dispersion must be >= 0, got {dispersion:g}")

        ka, kd, ks, kt = coeffs
        mat = Material(name=name, color=srgb8_to_linear(rgb), ambient=ka, diffuse=kd, specular=ks,
                       transmission=kt, shininess=exponent, ior=index)
        return mat, dispersion


# ------------------------------------------------------------------------------------------
def split_lines(text: str) -> list[str]:
    """Lines without their ends (LF or CRLF); a final line end does not start another line."""
    lines = text.split("\n")
    if lines and lines[-1] == "":
        lines.pop()
    return [ln[:-1] if ln.endswith("\r") else ln for ln in lines]


def _blocks(lines):
    """Yield (lines of a block as (lineno, text), ends_at_eof), skipping comment lines."""
    current = []
    for lineno, text in enumerate(lines, start=1):
        stripped = text.strip()
        if stripped.startswith("#"):
            continue
        if stripped:
            current.append((lineno, text))
        elif current:
            yield current, False
            current = []
    if current:
        yield current, True


def parse_coursework_text(lines, path="<string>") -> Scene:
    """Build a Scene from coursework-format text (a string, or its lines without line ends)."""
    path = os.fspath(path)
    if isinstance(lines, str):
        lines = split_lines(lines[1:] if lines.startswith("\ufeff") else lines)
    r = LineReader(path)
    scene = Scene(
        camera=Camera.coursework_default(),
        environment=Environment(kind="constant", color=(0.0, 0.0, 0.0)),
        ambient=(1.0, 1.0, 1.0),
        source=path,
    )
    for block_lines, at_eof in _blocks(lines):
        blk = _Block(r, block_lines, at_eof)
        tag_line, tag_text = block_lines[0]
        parts = tag_text.split(maxsplit=1)
        tag = parts[0]
        name = parts[1].strip() if len(parts) > 1 else ""
        if tag not in _KINDS:
            raise r.error(
                tag_line,
                f"unknown block tag '{shorten(tag)}': a block starts with s (sphere), b (bubble),"
                " t (triangulated object) or l (light)",
            )
        kind = _KINDS[tag]
        blk.pos = 1
        if kind == "light":
            if name:
                raise r.error(tag_line, f"a light's tag line is just '{tag}', found '{shorten(tag_text.strip(), 60)}'")
            blk.label = f"light {len(scene.lights) + 1}"
            _, position = blk.vector("position")
            line, intensity = blk.scalar("intensity")
            if not 0.0 <= intensity <= 1.0:
                raise r.error(line, f"{blk.label}: intensity {intensity:g} is outside [0, 1]")
            scene.lights.append(PointLight(position=position, intensity=intensity))
        else:
            if not name:
                raise r.error(tag_line, f"a {kind} needs a name: '{tag} NAME'")
            try:
                check_name(name, f"the {kind}'s name")
            except ValueError as exc:
                raise r.error(tag_line, str(exc)) from None
            blk.label = f"{kind} '{shorten(name)}'"
            if kind == "sphere":
                scene.spheres.append(_sphere(blk, name))
            elif kind == "bubble":
                scene.bubbles.append(_bubble(blk, name))
            else:
                scene.meshes.append(_mesh(blk, name, tag_line))
        blk.finish()
    if not (scene.spheres or scene.bubbles or scene.meshes):
        what = "is empty" if not any(ln.strip() for ln in lines) else "has no spheres, bubbles or triangulated objects"
        raise SceneError(path, None, f"no objects: the file {what}")
    return scene


def _sphere(blk: _Block, name: str) -> Sphere:
    _, center = blk.vector("centre")
    _, radius = blk.radius()
    material, _dispersion = blk.material(name)  # dispersion: validated, unused (see docs)
    return Sphere(center=center, radius=radius, material=material, name=name)


def _bubble(blk: _Block, name: str) -> Bubble:
    r = blk.r
    _, c_out = blk.vector("outer centre")
    _, r_out = blk.radius("outer radius")
    tok_out = blk.lines[blk.pos - 1][1].split()[0]
    outer, _ = blk.material(name, "outer")
    c_in_line, c_in = blk.vector("inner centre")
    offset = math.dist(c_in, c_out)
    if offset > CONCENTRIC_RTOL * r_out:
        raise r.error(
            c_in_line,
            f"{blk.label}: the inner sphere must be concentric with the outer (centres differ by"
            f" {offset:g}; a film of varying thickness is not expressible in the coursework's format; use TOML)",
        )
    r_in_line, r_in = blk.radius("inner radius")
    tok_in = blk.lines[blk.pos - 1][1].split()[0]
    if r_in > r_out:
        raise r.error(r_in_line, f"{blk.label}: the inner radius {r_in:g} is larger than the"
                                 f" outer radius {r_out:g}")
    blk.material(name, "inner")  # validated, then ignored: thin-film optics decides (see docs)
    # The thickness is the difference of the radii as written, taken in decimal so that
    # 100 - 99.9 is exactly 0.1 (binary floats would give 0.09999999999999432).
    thickness = float((Decimal(tok_out) - Decimal(tok_in)) * Decimal(repr(COURSEWORK_NM_PER_UNIT)))
    return Bubble(
        center=c_out,
        radius=r_out,
        film=FilmProfile(kind="uniform", thickness_nm=thickness),
        n_film=outer.ior,
        shininess=outer.shininess,
        name=name,
    )


def _mesh(blk: _Block, name: str, tag_line: int) -> Mesh:
    r = blk.r
    vertices, faces = [], []  # faces: (line, (i, j, k)) with 1-based indices
    while True:
        nxt = blk.peek()
        if nxt is None:
            where = "the file ends" if blk.at_eof else "the block ends (blank line)"
            raise r.error(blk.end_line, f"{blk.label}: {where} without the '-' line that closes"
                                        " its vertex and face list (and before its material)")
        line, text = nxt
        fields = text.split()
        if fields[0] == "-" and len(fields) == 1:
            blk.pos += 1
            break
        if fields[0] == "v":
            vertices.append(tuple(r.numbers(line, fields[1:], ("x", "y", "z"), f"{blk.label}: vertex")))
        elif fields[0] == "f":
            if len(fields) != 4:
                raise r.error(line, f"{blk.label}: a face is 'f i j k' (a triangle: three vertex"
                                    f" numbers), found {len(fields) - 1} numbers")
            idx = tuple(r.integer(line, tok, f"{blk.label}: face vertex number") for tok in fields[1:])
            faces.append((line, idx))
        else:
            hint = " (is the '-' line before the material missing?)" if _NUMBER.fullmatch(fields[0]) else ""
            raise r.error(line, f"{blk.label}: expected 'v x y z', 'f i j k' or '-',"
                                f" found '{shorten(text.strip(), 60)}'{hint}")
        blk.pos += 1
    material, _dispersion = blk.material(name)

    n = len(vertices)
    if not faces:
        raise r.error(tag_line, f"{blk.label} has no faces ('f i j k' lines)")
    for line, idx in faces:
        for i in idx:
            if i == 0:
                raise r.error(line, f"{blk.label}: vertex numbers count from 1; 0 names no vertex")
            if not 1 <= i <= n:
                raise r.error(line, f"{blk.label}: the face names vertex {i}, but the object has"
                                    f" {n} vert{'ex' if n == 1 else 'ices'}")
    verts = np.array(vertices, dtype=np.float64).reshape(-1, 3)
    tri = np.array([idx for _, idx in faces], dtype=np.int64) - 1
    keep = ~degenerate_triangles(verts[tri])
    if not keep.any():
        raise r.error(tag_line, f"{blk.label} has no usable face: all {len(faces)} have zero area")
    for (line, idx), ok in zip(faces, keep):
        if not ok:
            warnings.warn(f"{r.path}:{line}: {blk.label}: face {' '.join(map(str, idx))} has zero"
                          " area and is skipped", SceneWarning, stacklevel=2)
    return Mesh(vertices=verts, faces=tri[keep], material=material, name=name)


def load_coursework_scene(path, access: FileAccess = ANYWHERE) -> Scene:
    """Read a coursework-format scene file; raises SceneError('FILE:LINE: ...') on any problem
    (*access*: :func:`tracer.scene.text.read_scene_text`)."""
    path = os.fspath(path)
    return parse_coursework_text(split_lines(read_scene_text(path, access)), path)

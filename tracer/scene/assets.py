"""Files a TOML scene names: environment images, thickness maps (.npy) and mesh files.

Each loader takes the file's full path and returns the array(s) the :class:`~tracer.scene.Scene`
holds, or raises :class:`AssetError` saying what is wrong with the file; the TOML reader
(:mod:`tracer.scene.toml_read`) turns that into a ``FILE:LINE: key: what is wrong``
:class:`~tracer.scene.errors.SceneError` naming the scene file and the key that named the asset.

The readers are imported when a file needs them: Pillow for PNG and JPEG, trimesh for meshes,
OpenCV for ``.hdr`` and OpenEXR for ``.exr`` (the last two optional: without them such a file
is an error saying what to install).  Formats and their conventions: ``docs/scene-format.md``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from bubbleoptics.colorimetry import srgb_to_linear_srgb

from .file_access import ANYWHERE, FileAccess, FileAccessError
from .limits import MAX_MAGNITUDE

__all__ = ["AssetError", "IMAGE_SUFFIXES", "load_environment_image", "load_film_map", "load_mesh_file"]

#: Image files an ``[environment] kind = "image"`` may name, and what reads them.
IMAGE_SUFFIXES = {
    ".npy": "numpy (float32/float64, (H, W, 3), linear RGB)",
    ".png": "Pillow (8-bit sRGB, decoded to linear)",
    ".jpg": "Pillow (8-bit sRGB, decoded to linear)",
    ".jpeg": "Pillow (8-bit sRGB, decoded to linear)",
    ".hdr": "OpenCV, if opencv-python-headless is installed (Radiance RGBE, linear)",
    ".exr": "OpenEXR, if the OpenEXR package is installed (linear)",
}


class AssetError(ValueError):
    """A file named by a scene that cannot be used; the message says why, without the location."""


def _load_npy(full: Path) -> np.ndarray:
    try:
        arr = np.load(full, allow_pickle=False)
    except Exception as exc:
        raise AssetError(f"cannot read '{full.name}' as a .npy array: {exc}") from None
    if not isinstance(arr, np.ndarray) or arr.dtype.kind not in "fiu":
        raise AssetError(f"'{full.name}' must hold a numeric array")
    return arr


def load_film_map(full: Path) -> np.ndarray:
    """A bubble's thickness map: a 2-D ``.npy`` array (N_theta >= 2, N_phi >= 1) of nm >= 0, as float64."""
    if full.suffix.lower() != ".npy":
        raise AssetError(f"a thickness map is a .npy file, got '{full.name}'")
    table = _load_npy(full)
    if table.ndim != 2 or table.shape[0] < 2 or table.shape[1] < 1:
        raise AssetError(f"a thickness map is a 2-D array (N_theta >= 2, N_phi >= 1), got shape {table.shape}")
    table = table.astype(np.float64)
    if not np.all(np.isfinite(table)) or (table < 0).any():
        raise AssetError("thickness map values must be finite and >= 0 (nanometres)")
    return np.ascontiguousarray(table)


def load_film_series(full: Path):
    """A simulated film's thickness series: a ``.npz`` written by
    :meth:`bubbleoptics.filmflow.ThicknessSeries.save` (``bubbleoptics.filmflow``), read by
    :meth:`~bubbleoptics.filmflow.ThicknessSeries.load`, which checks the archive, every array's
    header and the decompressed size before it reads the thickness (one frame at a time); its
    one-line ``FILE:KEY: what is wrong`` names the file as the scene does."""
    from bubbleoptics.filmflow import ThicknessSeries

    if full.suffix.lower() != ".npz":
        raise AssetError(f"a film's thickness series is a .npz file (ThicknessSeries.save), got '{full.name}'")
    try:
        return ThicknessSeries.load(full)
    except ValueError as exc:  # SeriesFileError: the file, damaged or not a series
        raise AssetError(str(exc).replace(str(full), full.name)) from None
    except OSError as exc:  # cannot be opened (permissions, a folder, ...)
        raise AssetError(f"cannot read '{full.name}' as a thickness series ({exc.strerror or exc})") from None


def load_mesh_file(full: Path, access: FileAccess = ANYWHERE) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """Vertices (V, 3) float64, 0-based faces (F, 3) int64 and vertex normals (V, 3) float64 or
    ``None`` of a mesh file, read by trimesh.

    ``trimesh.load_scene(path, process=False)``: vertices are neither merged nor reordered,
    polygons are triangulated by trimesh.  Every triangle mesh of the file is taken, placed by
    the file's own scene graph (a glTF node's transform; OBJ, PLY and STL have none), and
    concatenated.  The normals are the file's own (OBJ ``vn``, PLY ``nx ny nz``) when every
    mesh of the file has them, ``None`` otherwise.  (trimesh keeps the normals a file gave in a
    mesh's cache, under ``"vertex_normals"``; that is how its own exporters tell them from
    computed ones, and how they are told apart here.  ``trimesh.load(force="mesh")`` would drop
    them.)  Nothing is copied that need not be: a 1M-triangle binary PLY is read into the
    arrays trimesh makes.

    Under a confined *access* (:class:`tracer.scene.file_access.FileAccess` with a root: the scene
    editor) the file's bytes are read first, within its size limit, and trimesh decodes them
    from memory with no resolver, so that a file naming other files (an OBJ's ``mtllib``, a
    glTF's external buffers) cannot make it read anything else.
    """
    try:
        import trimesh
    except ImportError:
        raise AssetError("reading mesh files needs the 'trimesh' package (pip install trimesh)") from None
    try:
        if access.confined:
            import io

            data = _read(full, access)
            source = dict(file_obj=io.BytesIO(data), file_type=full.suffix.lower().lstrip("."))
        else:
            source = dict(file_obj=str(full))
        loaded = trimesh.load_scene(**source, process=False)
    except AssetError:
        raise
    except Exception as exc:  # trimesh raises many kinds for unreadable files
        raise AssetError(f"cannot read mesh '{full.name}': {exc}") from None
    parts = []
    for node in loaded.graph.nodes_geometry:
        matrix, name = loaded.graph[node]
        geom = loaded.geometry.get(name)
        if not isinstance(geom, trimesh.Trimesh) or len(geom.faces) == 0:
            continue  # point clouds, paths, empty meshes
        verts = np.asarray(geom.vertices, dtype=np.float64).reshape(-1, 3)
        faces = np.asarray(geom.faces, dtype=np.int64).reshape(-1, 3)
        normals = geom._cache["vertex_normals"] if "vertex_normals" in geom._cache else None
        if normals is not None:
            normals = np.asarray(normals, dtype=np.float64).reshape(-1, 3)
            if normals.shape != verts.shape:
                normals = None
        matrix = np.asarray(matrix, dtype=np.float64)
        if not np.array_equal(matrix, np.eye(4)):
            rot = matrix[:3, :3]
            verts = verts @ rot.T + matrix[:3, 3]
            if normals is not None:
                with np.errstate(all="ignore"):
                    normals = normals @ np.linalg.inv(rot)  # the inverse transpose, row by row
            if np.linalg.det(rot) < 0:
                faces = faces[:, ::-1]  # a mirroring transform: keep the winding's meaning
        parts.append((verts, faces, normals))
    if not parts:
        raise AssetError(f"mesh '{full.name}' has no triangles")
    if len(parts) == 1:
        verts, faces, normals = parts[0]
    else:
        offsets = np.cumsum([0] + [len(p[0]) for p in parts[:-1]])
        verts = np.concatenate([p[0] for p in parts])
        faces = np.concatenate([p[1] + off for p, off in zip(parts, offsets)])
        normals = np.concatenate([p[2] for p in parts]) if all(p[2] is not None for p in parts) else None
    if not np.isfinite(verts).all():
        raise AssetError(f"mesh '{full.name}' has non-finite vertex coordinates")
    largest = max(float(verts.max()), -float(verts.min()))
    if largest > MAX_MAGNITUDE:
        raise AssetError(f"mesh '{full.name}' has a vertex coordinate of magnitude {largest:g}, beyond"
                         f" {MAX_MAGNITUDE:g} (tracer.scene.limits)")
    if faces.min() < 0 or faces.max() >= len(verts):
        bad = int(faces.max() if faces.max() >= len(verts) else faces.min())
        raise AssetError(f"mesh '{full.name}' has a face naming vertex {bad} (0-based), but there are"
                         f" {len(verts)} vertices")
    return np.ascontiguousarray(verts), np.ascontiguousarray(faces), \
        (None if normals is None else np.ascontiguousarray(normals))


def _read(full: Path, access: FileAccess) -> bytes:
    try:
        return access.read_bytes(full, shown=full.name)
    except FileAccessError as exc:
        raise AssetError(str(exc)) from None


def _radiance_size(full: Path):
    """(width, height) from a Radiance ``.hdr`` header (its resolution line, ``-Y H +X W``)."""
    import re

    with open(full, "rb") as fh:
        head = fh.read(65536)
    m = re.search(rb"\n\n([-+][XY]) (\d+) ([-+][XY]) (\d+)", head)
    if not m:
        raise AssetError(f"cannot read image '{full.name}': no Radiance resolution line")
    first, a, _, b = m.groups()
    return (int(b), int(a)) if first.endswith(b"Y") else (int(a), int(b))


def image_size(full: Path):
    """An environment image's (width, height), read from its header without decoding it."""
    suffix = full.suffix.lower()
    try:
        if suffix == ".npy":
            shape = np.load(full, mmap_mode="r", allow_pickle=False).shape
            return (shape[1], shape[0]) if len(shape) >= 2 else (shape[0] if shape else 1, 1)
        if suffix in (".png", ".jpg", ".jpeg"):
            from PIL import Image

            with Image.open(full) as im:
                return im.size
        if suffix == ".hdr":
            return _radiance_size(full)
        import OpenEXR

        with OpenEXR.File(str(full), header_only=True) as f:
            (x0, y0), (x1, y1) = f.header()["dataWindow"]
            return int(x1) - int(x0) + 1, int(y1) - int(y0) + 1
    except AssetError:
        raise
    except Exception as exc:
        raise AssetError(f"cannot read image '{full.name}': {exc}") from None


def load_environment_image(full: Path, access: FileAccess = ANYWHERE) -> np.ndarray:
    """An equirectangular environment image as linear RGB float32 (H, W, 3), values finite and >= 0.

    8-bit PNG and JPEG are sRGB, decoded with :func:`bubbleoptics.colorimetry.srgb_to_linear_srgb`;
    ``.npy``, ``.hdr`` and ``.exr`` are linear already (:data:`IMAGE_SUFFIXES`).  When *access*
    limits the pixels of an image (:class:`tracer.scene.file_access.FileAccess`), the size is read
    from the file's header (:func:`image_size`) and checked before anything is decoded: a small
    compressed file can hold a huge image.
    """
    suffix = full.suffix.lower()
    if suffix not in IMAGE_SUFFIXES:
        raise AssetError(f"unsupported image type '{suffix}' (supported: {', '.join(IMAGE_SUFFIXES)})")
    try:
        access.check_file(full, shown=full.name)
        if access.max_pixels is not None:
            access.check_pixels(*image_size(full), full.name)
    except FileAccessError as exc:
        raise AssetError(str(exc)) from None
    if suffix == ".npy":
        img = _load_npy(full)
        if img.dtype.kind != "f":
            raise AssetError(f"a .npy environment holds float32/float64 linear RGB, got {img.dtype}")
    elif suffix in (".png", ".jpg", ".jpeg"):
        from PIL import Image

        try:
            with Image.open(full) as im:
                srgb = np.asarray(im.convert("RGB"), dtype=np.float64) / 255.0
        except Exception as exc:
            raise AssetError(f"cannot read image '{full.name}': {exc}") from None
        img = srgb_to_linear_srgb(srgb)
    elif suffix == ".hdr":
        try:
            import cv2
        except ImportError:
            raise AssetError("reading .hdr needs OpenCV (pip install opencv-python-headless);"
                             " or convert the image to a .npy array") from None
        bgr = cv2.imread(str(full), cv2.IMREAD_ANYDEPTH | cv2.IMREAD_COLOR)
        if bgr is None:
            raise AssetError(f"cannot read image '{full.name}'")
        img = np.ascontiguousarray(bgr[..., ::-1])
    else:  # .exr
        try:
            import OpenEXR
        except ImportError:
            raise AssetError("reading .exr needs the OpenEXR package (pip install OpenEXR);"
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
            raise AssetError(f"cannot read image '{full.name}': {exc}") from None
    if img.ndim != 3 or img.shape[2] != 3 or img.shape[0] < 1 or img.shape[1] < 1:
        raise AssetError(f"an environment image is (H, W, 3) RGB, got shape {img.shape}")
    img = np.ascontiguousarray(img, dtype=np.float32)
    if not np.all(np.isfinite(img)) or (img < 0).any():
        raise AssetError("environment image values must be finite and >= 0 (linear RGB)")
    return img

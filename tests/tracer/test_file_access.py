"""``tracer.scene.file_access``: the confinement of a served editor's files to its root folder, regular
files only within a size limit, images checked from their header, and saves that never write
over a file (unit tests; the attacks through the served page: tests/tracer/test_editor_attacks.py)."""

from __future__ import annotations

import os
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from tracer.scene.errors import SceneError
from tracer.scene.file_access import ANYWHERE, FileAccess, FileAccessError, check_name
from tracer.scene.load import load_scene

pytestmark = pytest.mark.api

SCENE = """[[spheres]]
center = [0, 0, 0]
radius = 1
"""


@pytest.fixture()
def tree(tmp_path):
    """A root folder with a scene in it, and a secret file beside the root."""
    root = tmp_path / "root"
    (root / "sub").mkdir(parents=True)
    (root / "s.toml").write_text(SCENE, encoding="utf-8")
    (tmp_path / "secret.txt").write_text("root:*:19000:0:99999:7:::\n", encoding="utf-8")
    return root, tmp_path / "secret.txt"


def test_paths_resolve_inside_the_root_or_are_refused_alike(tree):
    root, secret = tree
    access = FileAccess(root)
    assert access.resolve("s.toml") == root / "s.toml"
    assert access.resolve("sub/../s.toml") == root / "s.toml"
    assert access.resolve(root / "s.toml") == root / "s.toml"
    messages = []
    for outside in ("../secret.txt", str(secret), "../no-such-file.txt", str(secret.parent / "nothing"),
                    "sub/../../secret.txt", "/etc/shadow", "/dev/zero"):
        with pytest.raises(FileAccessError, match="outside the folder") as info:
            access.resolve(outside)
        messages.append(str(info.value).replace(outside, "PATH"))
    # an existing file and a missing one get the same message: nothing can be learnt of the disk
    assert len(set(messages)) == 1
    with pytest.raises(FileAccessError, match="home folder"):
        access.resolve("~/s.toml")
    with pytest.raises(FileAccessError, match="NUL"):
        access.resolve("s.toml\x00.png")


def test_a_symbolic_link_inside_the_root_to_outside_is_refused(tree):
    root, secret = tree
    (root / "link.toml").symlink_to(secret)
    (root / "dir").symlink_to(secret.parent)
    access = FileAccess(root)
    for name in ("link.toml", "dir/secret.txt"):
        with pytest.raises(FileAccessError, match="outside the folder"):
            access.resolve(name)
    with pytest.raises(SceneError, match="outside the folder") as info:
        load_scene("link.toml", access)
    assert "root:" not in str(info.value)  # the other file's content is never in a message


def test_only_regular_files_are_read_and_a_fifo_never_blocks(tree):
    root, _ = tree
    fifo = root / "pipe.toml"
    os.mkfifo(fifo)
    access = FileAccess(root)
    result = []

    def read():
        try:
            access.read_bytes(fifo)
        except FileAccessError as exc:
            result.append(str(exc))

    t = threading.Thread(target=read, daemon=True)
    t.start()
    t.join(5)
    assert not t.is_alive() and result and "not a regular file" in result[0]
    with pytest.raises(FileAccessError, match="not a regular file"):
        access.check_file(fifo)
    with pytest.raises(FileAccessError, match="is a directory"):
        access.read_bytes(root / "sub")
    with pytest.raises(FileAccessError, match="not a regular file"):  # unconfined too: never a device
        ANYWHERE.read_bytes(Path("/dev/zero"))


def test_size_limits_are_checked_before_reading(tree):
    root, _ = tree
    big = root / "big.toml"
    big.write_bytes(b"#" * 5000)
    access = FileAccess(root, max_bytes=10_000, max_scene_bytes=4096)
    assert len(access.read_bytes(big)) == 5000
    with pytest.raises(FileAccessError, match="5,000 bytes, more than the 4,096 allowed"):
        access.read_bytes(big, scene=True)
    with pytest.raises(SceneError, match="more than the 4,096 allowed"):
        load_scene("big.toml", access)


def test_assets_of_a_confined_scene_stay_inside_the_root(tree):
    root, secret = tree
    np.save(secret.parent / "env.npy", np.ones((2, 4, 3)))
    np.save(root / "env.npy", np.ones((2, 4, 3)))
    access = FileAccess(root)
    for path in ("../env.npy", str(secret.parent / "env.npy")):
        (root / "a.toml").write_text(SCENE + f'[environment]\nkind = "image"\npath = "{path}"\n', encoding="utf-8")
        with pytest.raises(SceneError, match=r"a\.toml:\d+: environment\.path: .*outside the folder"):
            load_scene(root / "a.toml", access)
        assert load_scene(root / "a.toml").environment.image.shape == (2, 4, 3)  # unconfined: read from anywhere
    (root / "a.toml").write_text(SCENE + '[environment]\nkind = "image"\npath = "env.npy"\n', encoding="utf-8")
    assert load_scene("a.toml", access).environment.image.shape == (2, 4, 3)


def test_an_image_with_too_many_pixels_is_refused_from_its_header(tree):
    """A small compressed PNG can hold a huge image: its size is read from the header first."""
    from PIL import Image

    root, _ = tree
    Image.new("RGB", (3000, 2000)).save(root / "sky.png")
    assert (root / "sky.png").stat().st_size < 100_000
    (root / "a.toml").write_text(SCENE + '[environment]\nkind = "image"\npath = "sky.png"\n', encoding="utf-8")
    with pytest.raises(SceneError, match="an image of 3000 x 2000 pixels, more than the 1,000,000 pixels"):
        load_scene("a.toml", FileAccess(root, max_pixels=1_000_000))
    assert load_scene("a.toml", FileAccess(root, max_pixels=6_000_000)).environment.image.shape == (2000, 3000, 3)


def test_a_confined_mesh_cannot_name_other_files(tree):
    """An OBJ's ``mtllib`` (or a glTF's external buffer) is not followed under a root: trimesh
    decodes the file's own bytes with no resolver."""
    root, secret = tree
    (root / "m.obj").write_text(f"mtllib {secret}\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", encoding="utf-8")
    (root / "a.toml").write_text('[[meshes]]\npath = "m.obj"\n', encoding="utf-8")
    scene = load_scene("a.toml", FileAccess(root))
    assert scene.meshes[0].faces.shape == (1, 3)


def test_save_new_never_overwrites_and_leaves_no_temporary_file(tree):
    root, _ = tree
    access = FileAccess(root)
    (root / "edits.txt").write_text("mine\n", encoding="utf-8")
    path, renamed = access.save_new("edits.txt", (".txt",), lambda stem: {f"{stem}.txt": b"new\n"})
    assert (path, renamed) == (root / "edits-2.txt", True)
    assert (root / "edits.txt").read_text() == "mine\n" and path.read_bytes() == b"new\n"
    # a scene and the arrays beside it move together to a free stem
    (root / "scene.toml").write_text("old", encoding="utf-8")
    path, renamed = access.save_new("scene.toml", (".toml",),
                                    lambda stem: {f"{stem}.toml": b"t", f"{stem}.environment.npy": b"a"})
    assert path == root / "scene-2.toml" and (root / "scene-2.environment.npy").read_bytes() == b"a"
    for bad, match in (("x.pth", "ending in .txt"), ("../x.txt", "outside the folder"),
                       ("nowhere/x.txt", "no folder"), ("a\nb.txt", "control character")):
        with pytest.raises(FileAccessError, match=match):
            access.save_new(bad, (".txt",), lambda stem: {f"{stem}.txt": b""})
    assert not [p for p in root.rglob("*") if p.name.endswith(".tmp")]
    assert not (root.parent / "x.txt").exists()


def test_a_dangling_symbolic_link_is_not_written_through(tree):
    root, _ = tree
    target = root.parent / "planted.txt"
    (root / "out.txt").symlink_to(target)
    path, renamed = FileAccess(root).save_new("out.txt", (".txt",), lambda stem: {f"{stem}.txt": b"x"})
    assert renamed and path == root / "out-2.txt" and not target.exists()
    (root / "in.txt").symlink_to(root / "sub" / "later.txt")  # dangling, but inside: a new name
    path, renamed = FileAccess(root).save_new("in.txt", (".txt",), lambda stem: {f"{stem}.txt": b"x"})
    assert renamed and path == root / "in-2.txt" and not target.exists() and not (root / "sub" / "later.txt").exists()


@pytest.mark.parametrize("name, ok", [("young", True), ("a b 'c' ☃", True), ("x" * 200, True), ("x" * 201, False),
                                      ("a\nb", False), ("a\rb", False), ("a\x1bb", False), ("a\u202eb", False)])
def test_names_are_printable_text(name, ok):
    if ok:
        assert check_name(name) == name
    else:
        with pytest.raises(ValueError):
            check_name(name)


def test_reading_a_scene_anywhere_still_works_and_never_blocks_on_a_pipe(tmp_path):
    (tmp_path / "s.toml").write_text(SCENE, encoding="utf-8")
    assert load_scene(tmp_path / "s.toml").spheres
    os.mkfifo(tmp_path / "p.toml")
    t0 = time.monotonic()
    with pytest.raises(SceneError, match=r"p\.toml: not a regular file"):
        load_scene(tmp_path / "p.toml")
    assert time.monotonic() - t0 < 5

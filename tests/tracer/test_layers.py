"""The tracer's layers, as its folders show them: each imports only the layers below it, no module
imports another's private name, and no two modules import each other.

Bottom to top: ``kernels`` (numba code on packed arrays), ``scene`` (the scene model and its
files), ``prepare`` (a scene into packed arrays), ``rendering`` (images), ``movie`` (frames in
time), then ``cli`` and ``editor`` on top (docs/architecture.md).  ``tracer/__init__.py`` and
``__main__.py`` gather the public API and sit above all.
"""

import ast
from pathlib import Path

import pytest

pytestmark = pytest.mark.api

TRACER = Path(__file__).resolve().parents[2] / "tracer"
LAYERS = ["kernels", "scene", "prepare", "rendering", "movie", "cli|editor"]


def _layer(module):
    """The layer index of a dotted module name under tracer (None for tracer itself)."""
    parts = module.split(".")
    if len(parts) < 2:
        return None
    for i, names in enumerate(LAYERS):
        if parts[1] in names.split("|"):
            return i
    return len(LAYERS)  # __main__


def _modules():
    for path in sorted(TRACER.rglob("*.py")):
        parts = path.relative_to(TRACER.parent).with_suffix("").parts
        is_package = parts[-1] == "__init__"
        name = ".".join(parts[:-1] if is_package else parts)
        yield name, path, is_package


MODULES = list(_modules())


def _imports(name, path, is_package):
    """(module imported, names taken from it) for every import in *path*, relative ones resolved."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    package = name if is_package else name.rsplit(".", 1)[0]
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield alias.name, ()
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - node.level + 1]
                module = ".".join(base + ([node.module] if node.module else []))
            else:
                module = node.module or ""
            yield module, tuple(alias.name for alias in node.names)


def _tracer_imports(name, path, is_package):
    for module, names in _imports(name, path, is_package):
        if module == "tracer" or module.startswith("tracer."):
            yield module, names


def test_the_layers_are_folders():
    for names in LAYERS:
        for layer in names.split("|"):
            assert (TRACER / layer).is_dir() or (TRACER / f"{layer}.py").is_file(), layer
    top = sorted(p.name for p in TRACER.glob("*.py"))
    assert top == ["__init__.py", "__main__.py", "cli.py"], top


@pytest.mark.parametrize("name,path,is_package", MODULES, ids=[m[0] for m in MODULES])
def test_each_module_imports_only_its_own_layer_and_those_below(name, path, is_package):
    own = _layer(name)
    if own is None:
        return  # tracer/__init__.py gathers the public API from every layer
    for module, _ in _tracer_imports(name, path, is_package):
        other = _layer(module)
        assert other is not None and other <= own, f"{name} (layer {LAYERS[own]}) imports {module}"


@pytest.mark.parametrize("name,path,is_package", MODULES, ids=[m[0] for m in MODULES])
def test_no_module_imports_another_modules_private_name(name, path, is_package):
    for module, names in _tracer_imports(name, path, is_package):
        private = [n for n in names if n.startswith("_")]
        assert not private, f"{name} imports {private} from {module}"


def test_no_two_modules_import_each_other():
    edges = {name: {m for m, names in _tracer_imports(name, path, is_package)} |
             {f"{m}.{n}" for m, names in _tracer_imports(name, path, is_package) for n in names}
             for name, path, is_package in MODULES}
    known = set(edges)
    graph = {a: {b for b in targets if b in known and b != a} for a, targets in edges.items()}
    for a, targets in graph.items():
        for b in targets:
            if b.startswith(a + ".") or a.startswith(b + "."):
                continue  # a package and its own modules
            assert a not in graph.get(b, ()), f"{a} and {b} import each other"


def test_every_name_imported_from_the_tracer_exists():
    """Each ``from tracer.x import name`` names something module ``tracer.x`` defines (a moved
    name fails here, not at the first call of the function that imports it)."""
    import importlib
    import importlib.util

    for name, path, is_package in MODULES:
        for module, names in _tracer_imports(name, path, is_package):
            target = importlib.import_module(module)
            for n in names:
                assert hasattr(target, n) or importlib.util.find_spec(f"{module}.{n}"), f"{name}: {module}.{n}"

"""The package's layout keeps its promises: layers import only the layers above them, no module
reaches into another module's underscore names, and the top level stays small."""

from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1] / "src" / "ergohandover"
LAYERS = ("ergonomics", "io", "twin", "scene", "landscape", "envs", "learning", "study", "cli")
TOP_LEVEL = {"__init__.py", "errors.py", "ranges.py", "frames.py", "sim.py", "executor.py"}


def imports(path: Path):
    """(absolute module, imported names) for every ``from ... import`` of the package."""
    inside = path.is_relative_to(PACKAGE)
    package = path.relative_to(PACKAGE).parts[:-1] if inside else ()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[: len(package) - node.level + 1]
                module = ".".join([*base, *(node.module.split(".") if node.module else [])])
            elif node.module and node.module.startswith("ergohandover"):
                module = node.module.removeprefix("ergohandover").lstrip(".")
            else:
                continue
            yield module, [alias.name for alias in node.names]


def test_the_top_level_holds_at_most_six_modules():
    modules = {p.name for p in PACKAGE.glob("*.py")}
    assert modules == TOP_LEVEL and len(modules) <= 6
    assert {p.name for p in PACKAGE.iterdir() if p.is_dir() and p.name != "__pycache__"} == set(
        LAYERS)


def test_layers_import_only_the_layers_above_them():
    for path in PACKAGE.rglob("*.py"):
        layer = path.relative_to(PACKAGE).parts[0]
        if layer not in LAYERS:
            continue
        for module, _ in imports(path):
            target = module.split(".")[0]
            if target in LAYERS and target != layer:
                assert LAYERS.index(target) < LAYERS.index(layer), (
                    f"{path.relative_to(PACKAGE)} imports {module}")


def test_no_module_imports_another_modules_private_names():
    for path in [*PACKAGE.rglob("*.py"), *PACKAGE.parents[1].glob("experiments/**/*.py")]:
        for module, names in imports(path):
            private = [n for n in names if n.startswith("_") and not n.startswith("__")]
            assert not private, f"{path.name} imports {private} from {module}"
        tree = ast.parse(path.read_text())
        aliases = module_aliases(tree)
        for node in ast.walk(tree):
            # module._name(...) on an imported module (not self._x or obj._x of its own class)
            if (isinstance(node, ast.Attribute) and node.attr.startswith("_")
                    and not node.attr.startswith("__") and isinstance(node.value, ast.Name)
                    and node.value.id in aliases):
                raise AssertionError(f"{path.name} uses {node.value.id}.{node.attr}")


def module_aliases(tree: ast.Module) -> set[str]:
    """Names bound to imported modules of the package."""
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names |= {a.asname or a.name for a in node.names if a.name.startswith("ergohandover")}
        if isinstance(node, ast.ImportFrom) and (node.level or (node.module or "").startswith(
                "ergohandover")):
            names |= {a.asname or a.name for a in node.names}
    return names

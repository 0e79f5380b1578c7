"""The package's layout keeps its promises: layers import only the layers above them, no module
reaches into another module's underscore names, and the top level stays small."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "src" / "ergohandover"
LAYERS = ("ergonomics", "io", "twin", "workload", "capture", "scene", "landscape", "robustness",
          "envs", "search", "viewer", "study", "cli")
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


def module_graph() -> dict[str, set[str]]:
    """Each module of the package (a package by its face) -> the modules it imports, at the
    top or inside a function (``from . import sub`` imports ``sub``, not the face)."""
    modules = {}
    for path in PACKAGE.rglob("*.py"):
        parts = path.relative_to(PACKAGE).with_suffix("").parts
        modules[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    graph = {}
    for name, path in modules.items():
        found = set()
        for module, names in imports(path):
            subs = {f"{module}.{n}" if module else n for n in names} & set(modules)
            found |= subs
            if module in modules and len(subs) < len(names):
                found.add(module)
        graph[name] = found - {name}
    return graph


def test_the_package_has_no_import_cycle():
    graph = module_graph()
    done: set[str] = set()

    def visit(name: str, path: tuple[str, ...]) -> None:
        for nxt in sorted(graph[name]):
            assert nxt not in path, f"import cycle: {' -> '.join((*path, nxt))}"
            if nxt not in done:
                visit(nxt, (*path, nxt))
        done.add(name)

    for name in sorted(graph):
        if name not in done:
            visit(name, (name,))


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


@pytest.mark.slow
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


ROOT = PACKAGE.parents[1]
EXPERIMENTS = ROOT / "experiments"
CACHE_NAMES = {"cache_dir", "landscape_path"}
"""The cache's own names: only ergohandover.landscape may use them (the landscape door,
ergohandover.landscape.store, is every other module's way to a cached landscape)."""
ANALYSIS_MAY_IMPORT = {"io.atomic": None, "search.registry": {"SEARCHERS"},
                       "search.statistics": {"wilson"},
                       "landscape.stats": {"plot_distributions"},
                       "workload.flags": {"LIFTING_INDEX_SCOPE", "flag_column"}}
"""What experiments/analysis/ may take from the package: writing files, the agents' names,
arithmetic on numbers read from results/ (flags of action limits and cut-offs among them) and
a plot; nothing that evaluates or sweeps."""


def script_imports(path: Path):
    """Every module a script imports (``import x`` and ``from x import ...``), with its names."""
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield alias.name, []
        elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
            yield node.module, [alias.name for alias in node.names]


def test_scripts_import_no_sibling_study_script_and_nothing_from_the_cli():
    for path in EXPERIMENTS.rglob("*.py"):
        text = path.read_text()
        assert "sys.path.insert" not in text, f"{path.relative_to(ROOT)} edits sys.path"
        for module, _ in script_imports(path):
            assert not module.split(".")[0].startswith(("study_", "run_all")), (
                f"{path.relative_to(ROOT)} imports the script {module}")
            assert not module.startswith("ergohandover.cli"), (
                f"{path.relative_to(ROOT)} imports {module}")


@pytest.mark.slow
def test_nothing_outside_the_landscape_layer_touches_the_cache():
    for path in [*PACKAGE.rglob("*.py"), *EXPERIMENTS.rglob("*.py")]:
        if path.is_relative_to(PACKAGE / "landscape"):
            continue
        for module, names in [*imports(path), *script_imports(path)]:
            touched = CACHE_NAMES & set(names)
            assert not touched, f"{path.relative_to(ROOT)} imports {touched} from {module}"
            # The package's face, not its modules: ergohandover.landscape, never .cache.
            inner = module.removeprefix("ergohandover.")
            assert inner != "landscape.cache", f"{path.relative_to(ROOT)} imports {module}"


def test_the_analysis_scripts_read_results_and_compute_nothing_of_the_model():
    for path in (EXPERIMENTS / "analysis").glob("*.py"):
        for module, names in script_imports(path):
            if not module.startswith("ergohandover"):
                continue
            inner = module.removeprefix("ergohandover.")
            assert inner in ANALYSIS_MAY_IMPORT, f"{path.name} imports {module}"
            allowed = ANALYSIS_MAY_IMPORT[inner]
            assert allowed is None or set(names) <= allowed, f"{path.name}: {names} of {module}"


def test_no_committed_optimum_is_copied_into_code():
    import pandas as pd

    stats = pd.read_csv(ROOT / "results" / "landscape" / "stats.csv")
    for _, row in stats.iterrows():
        copied = f"{row['best_x']:.3f}, {row['best_y']:.3f}, {row['best_z']:.3f}"
        for path in [*PACKAGE.rglob("*.py"), *EXPERIMENTS.rglob("*.py")]:
            assert copied not in path.read_text(), f"{path.relative_to(ROOT)} holds {copied}"


def test_modules_stay_a_few_hundred_lines():
    for path in [*PACKAGE.rglob("*.py"), *EXPERIMENTS.rglob("*.py")]:
        lines = len(path.read_text().splitlines())
        assert lines <= 450, f"{path.relative_to(ROOT)} has {lines} lines"


NOT_ERRORS = {"ergohandover.executor.Stopped": "a stop signal: a KeyboardInterrupt, so that every "
              "layer unwinds as on Ctrl-C and the command exits 130 or 143, not 2",
              "ergohandover.search.protocol.Spent": "control flow: a spent budget ends a "
              "searcher's loop inside search.run and never leaves it"}
"""Exception classes that are not errors, with the reason."""


def test_every_error_of_the_package_derives_from_one_base():
    import importlib
    import inspect
    import pkgutil

    import ergohandover
    from ergohandover.errors import ErgohandoverError

    found = []
    for info in pkgutil.walk_packages(ergohandover.__path__, "ergohandover."):
        if info.name.endswith("__main__"):  # running it is what importing it does
            continue
        module = importlib.import_module(info.name)
        for name, cls in inspect.getmembers(module, inspect.isclass):
            if cls.__module__ == module.__name__ and issubclass(cls, BaseException):
                found.append(f"{module.__name__}.{name}")
                if f"{module.__name__}.{name}" not in NOT_ERRORS:
                    assert issubclass(cls, ErgohandoverError), f"{module.__name__}.{name}"
    assert set(NOT_ERRORS) <= set(found)  # an exemption for a class that is gone is stale


def test_each_study_part_has_one_door():
    """``run_all.py --only PART`` runs a part; no script of its own beside it."""
    assert not sorted(p.name for p in EXPERIMENTS.glob("study_*.py"))

"""The package's layers (../shared/ARCHITECTURE.md): a module imports only its own layer or lower ones.

Checked on the source: every ``import scenariominer.X`` / ``from scenariominer.X import`` of every
module, including imports inside functions (lazy imports are still dependencies).
"""

from __future__ import annotations

import ast
from pathlib import Path

import scenariominer

ROOT = Path(scenariominer.__file__).parent

#: Layer of each top-level package or module, lowest first. A module may import a module of its own
#: layer or of a lower one. ``testing`` ships fakes and builders for tests and may use anything below
#: the faces (api, cli, server).
LAYERS: dict[str, int] = {
    "errors": 0,
    "_optional": 0,
    "schema": 0,
    "progress": 0,
    "config": 1,
    "exec": 1,  # generic: maps a stage's function over items; stages below api take an Executor
    "geometry": 1,
    "data": 2,
    "map": 2,
    "synth": 3,
    "sim": 3,
    "tags": 3,
    "events": 4,
    "llm": 4,
    "retrieval": 4,
    "store": 5,
    "explain": 6,
    "mine": 6,
    "represent": 6,
    "cbr": 6,
    "eval": 7,
    "testing": 7,
    "api": 8,
    "cli": 9,
    "server": 9,
    "__main__": 9,
}


def _imports(path: Path) -> set[str]:
    out: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            parts = node.module.split(".")
            if parts[0] == "scenariominer":
                out.update([parts[1]] if len(parts) > 1 else [a.name for a in node.names])
        elif isinstance(node, ast.Import):
            out.update(a.name.split(".")[1] for a in node.names if a.name.startswith("scenariominer."))
    return out


def _package(path: Path) -> str:
    return path.relative_to(ROOT).parts[0].removesuffix(".py")


def test_every_package_has_a_layer() -> None:
    names = {_package(p) for p in ROOT.rglob("*.py")} - {"__init__"}
    assert names <= set(LAYERS), sorted(names - set(LAYERS))


def test_no_module_imports_a_layer_above_it() -> None:
    violations = []
    for path in sorted(ROOT.rglob("*.py")):
        pkg = _package(path)
        if pkg == "__init__":
            continue
        for target in _imports(path):
            if target in LAYERS and LAYERS[target] > LAYERS[pkg]:
                violations.append(f"{path.relative_to(ROOT)} imports {target}")
    assert violations == []


def test_the_checker_sees_lazy_imports(tmp_path: Path) -> None:
    module = tmp_path / "m.py"
    module.write_text(
        "def f():\n    from scenariominer.api.mining import mine\n    import scenariominer.cli\n", "utf-8"
    )
    assert _imports(module) == {"api", "cli"}

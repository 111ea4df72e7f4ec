"""The layers as folders: import-linter's contracts (pyproject.toml) hold, they see an import
inside a function, every module of the package lies in a layer, docs/architecture.md names the
layers in the contract's order, and no private name is imported from another folder."""

from __future__ import annotations

import ast
import os
import re
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PACKAGE = ROOT / "symkf"
CONTRACTS = {c["id"]: c for c in tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["importlinter"]["contracts"]}
LAYERS = [[m.strip() for m in line.split("|")] for line in CONTRACTS["layers"]["layers"]]

pytest.importorskip("importlinter")


def _lint(root: Path) -> subprocess.CompletedProcess:
    """``lint-imports`` on the package under ``root`` with the contracts of ``root/pyproject.toml``."""
    script = ("import sys; from importlinter.cli import lint_imports; "
              "sys.exit(lint_imports(config_filename='pyproject.toml', no_cache=True))")
    env = {**os.environ, "PYTHONPATH": str(root)}
    return subprocess.run([sys.executable, "-c", script], cwd=root, env=env, capture_output=True, text=True,
                           timeout=120)


def test_every_contract_is_kept():
    out = _lint(ROOT)
    assert out.returncode == 0, out.stdout + out.stderr
    assert re.search(rf"Contracts: {len(CONTRACTS)} kept, 0 broken", out.stdout), out.stdout


@pytest.mark.parametrize("module, imported", [
    ("exact/blocks.py", "from ..engine import rates"),           # the substrate reaching the engine
    ("model/iid.py", "from ..io import files"),                  # a model reaching the file reader
    ("engine/rows.py", "from ..numeric import montecarlo"),     # the engine reaching the simulation
])
def test_an_import_inside_a_function_that_climbs_a_layer_breaks_the_contract(tmp_path, module, imported):
    shutil.copytree(PACKAGE, tmp_path / "symkf", ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copy(ROOT / "pyproject.toml", tmp_path)
    path = tmp_path / "symkf" / module
    path.write_text(path.read_text() + f"\n\ndef _climb():\n    {imported}\n    return None\n")
    out = _lint(tmp_path)
    assert out.returncode == 1 and "BROKEN" in out.stdout
    assert f"symkf.{module[:-3].replace('/', '.')} -> symkf.{imported.split()[1].strip('.')}.{imported.split()[3]}" \
        in out.stdout.replace("\n", " "), out.stdout


def _modules() -> list[str]:
    return sorted(".".join(p.relative_to(ROOT).with_suffix("").parts) for p in PACKAGE.rglob("*.py"))


def test_every_module_lies_in_a_layer():
    layered = {name for line in LAYERS for name in line}
    for module in _modules():
        parts = module.split(".")
        if parts[1:] == ["__init__"]:
            continue   # the facade: its imports are under TYPE_CHECKING or lazy, by name
        assert parts[1] in layered, f"{module} is in no layer of the contract in pyproject.toml"


def test_the_architecture_page_lists_the_contracts_layers_in_order():
    page = (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")
    table = re.search(r"<!-- layers -->\n(.*?)<!-- /layers -->", page, re.S)
    assert table, "docs/architecture.md has no layers table"
    cells = [re.split(r"(?<!\\)\|", line) for line in table.group(1).splitlines() if line.startswith("|")]
    rows = [re.findall(r"`(\w+)`", row[1]) for row in cells if "`" in row[1]]
    assert rows == LAYERS, "docs/architecture.md's layers table differs from the contract in pyproject.toml"


def test_no_private_name_is_imported_from_another_folder():
    found = []
    for path in PACKAGE.rglob("*.py"):
        parts = list(path.relative_to(ROOT).with_suffix("").parts)
        package = parts[:-1]
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and node.level:
                source = package[:len(package) - node.level + 1] + (node.module.split(".") if node.module else [])
                if source[:2] != package[:2]:
                    found += [f"{'.'.join(parts)} imports {a.name} from {'.'.join(source)}" for a in node.names
                              if a.name.startswith("_") and not a.name.startswith("__")]
    assert not found, found

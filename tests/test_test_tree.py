"""The layout of tests/: its folders mirror the layers of symkf/, test files are named uniquely
across the tree (pytest imports them by file name), tests/conftest.py is the only conftest, and
every test file or test the repository cites (README.md, docs/, tests/README.md, .ci/run,
benchmarks/, proofs/, comments in symkf/) exists."""

from __future__ import annotations

import ast
import collections
import re

import pytest

from conftest import ROOT

TESTS = ROOT / "tests"
#: folders of tests/ that hold data, not tests
DATA = {"corpus", "__pycache__"}
#: a test file, optionally with the test it names: tests/engine/test_oracle.py::test_...
CITED = re.compile(r"\btests/((?:\w+/)*test_\w+\.py)(?:::(\w+))?")


def _folders() -> list[str]:
    return sorted(p.name for p in TESTS.iterdir() if p.is_dir() and p.name not in DATA and not p.name.startswith("."))


def test_every_folder_of_tests_is_a_layer_of_the_package():
    assert _folders(), "tests/ has no folders"
    assert [f for f in _folders() if not (ROOT / "symkf" / f / "__init__.py").is_file()] == []


def test_test_file_names_are_unique_and_there_is_one_conftest():
    files = collections.Counter(p.name for p in TESTS.rglob("test_*.py") if DATA.isdisjoint(p.parts))
    assert [name for name, count in files.items() if count > 1] == []
    assert [str(p.relative_to(TESTS)) for p in TESTS.rglob("conftest.py")] == ["conftest.py"]
    assert list(TESTS.rglob("__init__.py")) == []


def _citing_files() -> list:
    pages = [ROOT / "README.md", TESTS / "README.md", ROOT / ".ci" / "run", *sorted((ROOT / "docs").glob("*.md"))]
    code = [*sorted((ROOT / "symkf").rglob("*.py")), *sorted((ROOT / "benchmarks").glob("*.py")),
            *sorted((ROOT / "proofs").glob("*"))]
    return [p for p in pages + code if p.is_file()]


def _citations() -> list[tuple[str, str, str | None]]:
    return [(str(page.relative_to(ROOT)), m.group(1), m.group(2)) for page in _citing_files()
            for m in CITED.finditer(page.read_text(encoding="utf-8", errors="replace"))]


def test_the_repository_cites_tests():
    cited = {path for _, path, _ in _citations()}
    assert {"engine/test_oracle.py", "numeric/test_montecarlo.py"} <= cited


@pytest.mark.parametrize("where, path, name", _citations(), ids=lambda v: v or "")
def test_every_cited_test_exists(where, path, name):
    target = TESTS / path
    assert target.is_file(), f"{where} cites tests/{path}, which does not exist"
    if name:
        defined = {node.name for node in ast.parse(target.read_text(encoding="utf-8")).body
                   if isinstance(node, (ast.FunctionDef, ast.ClassDef))}
        assert name in defined, f"{where} cites tests/{path}::{name}, which is not a test of that file"

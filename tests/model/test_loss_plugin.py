"""A loss model from another installed package: the worked example of docs/losses.md, built as a
package of its own (its pyproject.toml and module from the page), installed into a temporary
directory and used by the `symkf` command in a new process through the `symkf.losses` entry-point
group; a kind whose entry point cannot be loaded is reported by name, and the others keep working.
The installs are the full tier's (pip builds the packages, with a package index where this
environment cannot build them itself)."""

from __future__ import annotations

import importlib.util
import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
import sympy as sp

from conftest import ROOT
from symkf.exact.numbers import parse_exact


PAGE = (ROOT / "docs" / "losses.md").read_text(encoding="utf-8")
SYSTEM = '[system]\nA = [["0", "-2"], ["2", "0"]]\n[[sensors]]\nC = [["1", "0"]]\n[[sensors]]\nC = [["1", "1"]]\n'


def _block(language: str, index: int) -> str:
    return re.findall(rf"^```{language}\n(.*?)^```", PAGE, re.M | re.S)[index]


def _builds_here() -> bool:
    """Whether this environment can build the package itself (setuptools with its own
    bdist_wheel, from 70.1, or the wheel package): then the build needs no package index."""
    if importlib.util.find_spec("setuptools") is None:
        return False
    import setuptools
    return tuple(map(int, setuptools.__version__.split(".")[:2])) >= (70, 1) or \
        importlib.util.find_spec("wheel") is not None


def _install(packages: list[Path], target: Path) -> None:
    """``pip install --no-deps --target``, without build isolation where this environment can build."""
    isolation = ["--no-build-isolation"] if _builds_here() else []
    out = subprocess.run([sys.executable, "-m", "pip", "install", "-q", "--no-deps", *isolation, "--target",
                          str(target), *map(str, packages)], capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr[-3000:]


def _symkf(args: list[str], site: Path, cwd: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(site), *filter(None, [os.environ.get("PYTHONPATH")])])}
    return subprocess.run([sys.executable, "-m", "symkf", *args], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=300)


@pytest.fixture(scope="module")
def installed(tmp_path_factory) -> Path:
    """The page's package, and a broken one whose entry point names a module that does not exist,
    installed into one temporary site directory."""
    base = tmp_path_factory.mktemp("plugins")
    good = base / "common-outage"
    good.mkdir()
    (good / "pyproject.toml").write_text(_block("toml", 0), encoding="utf-8")
    (good / "common_outage.py").write_text(_block("python", 0), encoding="utf-8")
    broken = base / "broken-kind"
    broken.mkdir()
    (broken / "pyproject.toml").write_text(
        _block("toml", 0).replace('name = "common-outage"', 'name = "broken-kind"')
        .replace('py-modules = ["common_outage"]', 'py-modules = ["broken_kind"]')
        .replace('common-outage = "common_outage:CommonOutage"', 'broken-kind = "no_such_module:Model"'),
        encoding="utf-8")
    (broken / "broken_kind.py").write_text('"""Installs an entry point that cannot be loaded."""\n', encoding="utf-8")
    site = base / "site"
    _install([good, broken], site)
    return site


def test_the_worked_example_uses_public_names_only():
    module = _block("python", 0)
    imported = re.findall(r"^from (symkf[\w.]*) import (.+)$", module, re.M)
    assert imported and all(not name.strip().startswith("_") for _, names in imported for name in names.split(","))


@pytest.mark.full
def test_an_installed_model_works_from_the_command_line(installed, tmp_path):
    path = tmp_path / "outage.toml"
    path.write_text(SYSTEM + '[loss]\nkind = "common-outage"\noutage = "1/20"\nloss = ["1/10", "1/5"]\n',
                    encoding="utf-8")
    out = _symkf(["analyze", str(path), "--json"], installed, tmp_path)
    assert out.returncode == 0, out.stderr
    report = json.loads(out.stdout)
    # alpha^4 rho^2 = 16 (69/1000)(6/25) = 828/3125, derived on the page: the margin is its square root
    verdict = report["verdict"]
    assert parse_exact(verdict["margins"][0]["exact"], "margin") ** 2 == sp.Rational(828, 3125)
    assert parse_exact(verdict["certificate"][0]["alpha^(2g) rho^g"], "certificate") == sp.Rational(828, 3125)
    assert verdict["stable"] is True and report["loss"]["kind"] == "common-outage"


@pytest.mark.full
def test_a_kind_that_cannot_load_is_named_and_the_others_still_work(installed, tmp_path):
    broken = tmp_path / "broken.toml"
    broken.write_text(SYSTEM + '[loss]\nkind = "broken-kind"\n', encoding="utf-8")
    out = _symkf(["analyze", str(broken)], installed, tmp_path)
    assert out.returncode == 2 and "Traceback" not in out.stderr
    assert "kind 'broken-kind' is installed but unusable" in out.stderr and "no_such_module:Model" in out.stderr
    iid = tmp_path / "iid.toml"
    iid.write_text(SYSTEM + '[loss]\nkind = "iid"\nloss = ["1/16", "1/16"]\n', encoding="utf-8")
    out = _symkf(["analyze", str(iid), "--json"], installed, tmp_path)
    assert out.returncode == 0, out.stderr

"""Packaging: a lean core install (the convex solvers and scipy are extras, the exact engine,
verify and simulate run without them), lazy imports that keep the public API and dir() to it,
example data shipped in the package, the README's set-up commands the ones CI runs, --version /
--quiet, optional extras that name their install command."""

from __future__ import annotations

import re
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

import symkf
import symkf as sk
from symkf import cli, examples
from symkf.errors import ExtraNotInstalledError, InputError

from conftest import ROOT


def _python(code: str) -> str:
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                          cwd=ROOT).stdout.strip()


def test_import_loads_no_heavy_dependency():
    loaded = _python("import sys, symkf; print(sorted(m for m in ('sympy', 'numpy', 'scipy', 'flint', 'tqdm', 'numba') "
                     "if m in sys.modules))")
    assert loaded == "[]"


def test_numba_loads_only_when_a_filter_runs():
    # the compiled kernel (symkf.numeric.square_root) costs ~0.4 s to import: the exact engine never pays it
    out = _python("import sys, symkf, symkf.numeric.filters, symkf.numeric.montecarlo, symkf.numeric.verify; "
                  "symkf.stability(symkf.System(A=[[2, 0], [0, 1]], sensors=[symkf.Sensor(C=[[1, 1]])]), "
                  "symkf.IID(['1/2'])); print('numba' in sys.modules)")
    assert out == "False"


def test_every_public_name_resolves_and_stability_stays_a_function():
    # importing the subpackage symkf.bounds must not rebind symkf.bounds (the atlas function) to it
    out = _python("import symkf, symkf.bounds.atlas, symkf.engine.stability, symkf.run.sweep, symkf.io.families; "
                  "print(callable(symkf.stability), callable(symkf.sweep), "
                  "all(hasattr(symkf, n) for n in symkf.__all__))")
    assert out == "True True True"
    for name in symkf.__all__:
        assert getattr(symkf, name) is not None
    assert set(symkf.__all__) <= set(dir(symkf))
    with pytest.raises(AttributeError, match="no attribute 'nonsense'"):
        symkf.nonsense  # noqa: B018


def test_version_is_the_packages():
    pyproject = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    assert pyproject["tool"]["setuptools"]["dynamic"]["version"] == {"attr": "symkf.__version__"}
    run = subprocess.run([sys.executable, "-m", "symkf", "--version"], capture_output=True, text=True, cwd=ROOT)
    assert run.returncode == 0 and run.stdout.strip() == f"symkf {symkf.__version__}"


def test_examples_are_package_data():
    names = [p.stem for p in examples.systems()]
    assert "ge-two-sensors" in names and "rotation-pi12-four-sensors" in names
    assert [p.stem for p in examples.systems("network")] == [
        "markov-shared-channel", "quevedo-example3", "quevedo-robot", "quevedo-semi-markov-network"]
    assert examples.family("ge-recovery").is_file() and examples.system("fusion/pendulum").is_file()
    assert examples.directory().parent == Path(symkf.__file__).parent / "io"
    with pytest.raises(InputError, match="no example 'nope' in systems/; known: .*ge-two-sensors"):
        examples.system("nope")
    # the wheel carries them: every example file matches a package-data pattern of pyproject.toml
    pyproject = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    patterns = pyproject["tool"]["setuptools"]["package-data"]["symkf"]
    package = Path(symkf.__file__).parent
    for path in examples.directory().rglob("*.toml"):
        assert any(path.relative_to(package).match(p) for p in patterns), path


def test_readme_test_command_is_what_ci_runs():
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    blocks = re.findall(r"^```\n(.*?)\n```", readme.split("## A five-minute tour")[0], re.M | re.S)
    assert len(blocks) == 2, "the README keeps exactly two set-up commands"
    demo, tests = blocks
    assert demo == "pip install -e . && symkf demo"
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    marked = ci.split("# --- the README's test command (keep identical to README.md) ---\n")[1]
    assert marked.splitlines()[0] == f"# {tests}"
    steps = [s for s in re.findall(r'^step "[^"]+" (.*)$', marked, re.M) if s != "tex_done"]  # a wait, not a command
    assert " && ".join(steps[:len(tests.split(" && "))]) == tests


def test_quiet_disables_progress_bars(monkeypatch, capsys):
    from symkf.run import progress
    monkeypatch.delenv("TQDM_DISABLE", raising=False)
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)
    assert not progress.progress(3, "x").disable
    monkeypatch.setenv("TQDM_DISABLE", "1")
    assert progress.progress(3, "x").disable
    seen = []
    monkeypatch.delenv("TQDM_DISABLE")
    monkeypatch.setitem(cli.COMMANDS, "demo", cli.Command(
        "demo", "", lambda p: None, lambda args: seen.append(progress.progress(3, "x").disable) or {}))
    assert cli.main(["demo", "--quiet", "--json"]) == 0 and cli.main(["demo", "--json"]) == 0
    assert seen == [True, False]
    assert "TQDM_DISABLE" not in __import__("os").environ


def test_strategies_without_hypothesis_name_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "hypothesis", None)
    monkeypatch.delitem(sys.modules, "symkf.model.strategies", raising=False)
    with pytest.raises(ExtraNotInstalledError, match=r"symkf.model.strategies needs hypothesis: pip install "
                                                     r"'symkf\[strategies\]'"):
        import symkf.model.strategies  # noqa: F401


def test_core_dependencies_leave_the_convex_solvers_to_extras():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    core = {re.split(r"[<>=!~\[ ]", r)[0] for r in project["dependencies"]}
    assert not core & {"scipy", "cvxpy", "clarabel", "scs"}
    extras = project["optional-dependencies"]
    assert {re.split(r"[<>=]", r)[0] for r in extras["sdp"]} == {"cvxpy", "clarabel", "scipy"}
    assert "symkf[fusion,sdp]" in extras["test"] and "symkf[fusion,sdp]" in extras["docs"]


BLOCKER = """
import importlib.abc, sys
class Block(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path, target=None):
        if name.split('.')[0] in ('scipy', 'cvxpy', 'clarabel'):
            raise ImportError(f'blocked: {name}')
sys.meta_path.insert(0, Block())
from symkf import cli
for argv in (['critical', 'design-rotation', '--json'], ['simulate', 'design-rotation', '--horizon', '10',
             '--paths', '50', '--json'], ['verify', 'design-rotation', '--paths', '300', '--horizon', '16', '--json']):
    print(argv[0], cli.main(argv + ['--quiet']))
"""


def test_exact_engine_verify_and_simulate_run_without_scipy_and_cvxpy():
    run_ = subprocess.run([sys.executable, "-c", BLOCKER], capture_output=True, text=True, cwd=ROOT)
    statuses = [line for line in run_.stdout.splitlines() if re.fullmatch(r"[a-z]+ \d+", line)]
    assert statuses == ["critical 0", "simulate 0", "verify 0"], run_.stderr


QUARTER_TURN = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="s1")])


def test_missing_extras_name_the_install_command(monkeypatch):
    monkeypatch.setitem(sys.modules, "cvxpy", None)
    from symkf.capacity import mare_stabilizable
    with pytest.raises(ExtraNotInstalledError, match=r"mare_stabilizable.*pip install 'symkf\[sdp\]'"):
        mare_stabilizable(QUARTER_TURN, sk.IID(["1/2"]))
    from symkf.fusion import optimal_weights
    with pytest.raises(ExtraNotInstalledError, match=r"Problem 2.*pip install 'symkf\[sdp\]'"):
        optimal_weights(np.eye(2), np.array([[1.0], [1.0]]), method="sdp")
    monkeypatch.setitem(sys.modules, "scipy", None)
    for name in [m for m in sys.modules if m.startswith("symkf.fusion")]:
        monkeypatch.delitem(sys.modules, name)
    with pytest.raises(ExtraNotInstalledError, match=r"symkf.fusion.*pip install 'symkf\[fusion\]'"):
        import symkf.fusion  # noqa: F401


def test_dir_lists_only_the_public_api():
    names = dir(sk)
    assert not {"Any", "TYPE_CHECKING", "sys", "importlib", "types"} & set(names)
    assert {"verify", "simulate", "Verification", "Simulation", "System", "__version__"} <= set(names)


def test_every_module_compiles_without_a_warning():
    # an invalid escape in a string ("\ ") is a SyntaxWarning that the command line prints as a note
    import warnings
    from conftest import ROOT
    for path in sorted((ROOT / "symkf").rglob("*.py")):
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            compile(path.read_text(encoding="utf-8"), str(path), "exec")

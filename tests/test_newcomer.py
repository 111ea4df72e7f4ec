"""symkf as a newcomer meets it: a lean core install, shipped examples by name, output in words,
result objects, honest simulation output, and the small habits of the ecosystem."""

from __future__ import annotations

import json
import re
import subprocess
import sys
import tomllib
import warnings
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
import sympy as sp

import symkf as sk
from symkf import cli, examples
from symkf.io import files
from symkf.errors import ExtraNotInstalledError, InputError
from symkf.io.families import grid_family, systems_family
from symkf.engine.stability import pattern_words
from conftest import ROOT

DESIGN = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="s1")])
#: the aperiodic rotation (3/2) R(theta), cos theta = 3/5, on a Gilbert-Elliott channel: every
#: reception resets the rank, so rho = P(stay lost) = 1/2 and the margin is 9/4 * 1/2 = 9/8
#: (tests/test_engine.py): E[tr P_k] diverges by 9/8 per step
DIVERGING = (sk.System(A=[["9/10", "-6/5"], ["6/5", "9/10"]], sensors=[sk.Sensor(C=[[1, 0]], name="s1")]),
             sk.GilbertElliott(["1/4"], ["1/2"]))


def run(capsys, *argv: str) -> tuple[int, str, str]:
    status = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return status, out, err


# --- 1. the lean core install ------------------------------------------------------------------

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


def test_missing_extras_name_the_install_command(monkeypatch):
    monkeypatch.setitem(sys.modules, "cvxpy", None)
    from symkf.capacity import mare_stabilizable
    with pytest.raises(ExtraNotInstalledError, match=r"mare_stabilizable.*pip install 'symkf\[sdp\]'"):
        mare_stabilizable(DESIGN, sk.IID(["1/2"]))
    from symkf.fusion import optimal_weights
    with pytest.raises(ExtraNotInstalledError, match=r"Problem 2.*pip install 'symkf\[sdp\]'"):
        optimal_weights(np.eye(2), np.array([[1.0], [1.0]]), method="sdp")
    monkeypatch.setitem(sys.modules, "scipy", None)
    for name in [m for m in sys.modules if m.startswith("symkf.fusion")]:
        monkeypatch.delitem(sys.modules, name)
    with pytest.raises(ExtraNotInstalledError, match=r"symkf.fusion.*pip install 'symkf\[fusion\]'"):
        import symkf.fusion  # noqa: F401


# --- 2. shipped examples by name ----------------------------------------------------------------

def test_examples_lists_and_copies(capsys, tmp_path, monkeypatch):
    status, out, _ = run(capsys, "examples")
    assert status == 0
    assert all(e.name in out for e in examples.catalog()) and "families" in out
    status, out, _ = run(capsys, "examples", "--json")
    listed = json.loads(out)["examples"]
    assert [e["name"] for e in listed] == [e.name for e in examples.catalog()]
    assert {e["kind"] for e in listed} == {"system", "network", "fusion", "family"}
    monkeypatch.chdir(tmp_path)
    status, out, _ = run(capsys, "examples", "ge-two-sensors")
    assert status == 0 and (tmp_path / "ge-two-sensors.toml").read_text() == examples.system("ge-two-sensors").read_text()
    status, _, err = run(capsys, "examples", "nope")
    assert status == 2 and "no shipped example 'nope'; known: aperiodic-rotation" in err


def test_every_command_takes_a_shipped_name(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)   # no such files here: the names resolve to the package's
    by_path = run(capsys, "critical", examples.system("ge-two-sensors"), "--vary", "recovery", "--json")
    by_name = run(capsys, "critical", "ge-two-sensors", "--vary", "recovery", "--json")
    assert by_name == by_path and by_name[0] == 0
    assert examples.resolve("quevedo-robot") == examples.system("network/quevedo-robot")
    assert examples.resolve("rotation-periods.toml") == examples.family("rotation-periods")
    (tmp_path / "ge-two-sensors").write_text("not toml")   # an existing file wins over a name
    assert examples.resolve("ge-two-sensors") == Path("ge-two-sensors")
    status, out, err = run(capsys, "analyze", "no-such-thing")
    assert status == 2 and out == "" and "no such file; shipped examples are taken by name" in err


# --- 6. words for people ------------------------------------------------------------------------

#: a JSON object or a Python repr of a list/tuple/string in text meant for people
REPR = re.compile(r"""\{\s*["']|\[\s*\(|\[\s*['"]|\(\s*['"]|\[\s*\[\s*['"]""")


def _readable(text: str) -> list[str]:
    """The lines of ``text`` that carry a repr or exceed 120 characters without a long number."""
    return [line for line in text.splitlines()
            if REPR.search(line) or (len(line) > 120 and not re.search(r"\d{30}", line))]


def test_text_output_is_words(capsys):
    commands = [["demo"], ["analyze", "aperiodic-rotation"], ["analyze", "ge-two-sensors"],
                ["analyze", "quevedo-semi-markov-network"], ["critical", "rotation-pi12-four-sensors"],
                ["examples"], ["reproduce", "sui-theorem12", "--quick"], ["reproduce", "--list"],
                ["simulate", "ge-two-sensors", "--horizon", "12", "--paths", "60"],
                ["verify", "design-rotation", "--paths", "300", "--horizon", "16"]]
    for argv in commands:
        status, out, err = run(capsys, *argv, "--quiet")
        assert status == 0, (argv, err)
        assert _readable(out) == [], argv
    assert _readable("ok\n{\"modulus\": \"2\"}\nonly [('s1', 0)] received\n" + "x" * 121) == [
        "{\"modulus\": \"2\"}", "only [('s1', 0)] received", "x" * 121]


def test_a_high_degree_modulus_is_shown_by_its_decimal_and_degree(capsys, tmp_path):
    """``A = cos(pi/211)``: the modulus's minimal polynomial has degree 105 and 40-digit
    coefficients; the report names the degree and where the exact data is instead of printing it,
    and the margin is exact: ``cos(pi/211)^2 * 1/2`` (no packet received, loss 1/2)."""
    path = tmp_path / "s.toml"
    path.write_text('[system]\nA = [["cos(pi/211)"]]\n[[sensors]]\nC = [["1"]]\n[loss]\nkind = "iid"\nloss = ["1/2"]\n')
    status, out, _ = run(capsys, "analyze", path, "--quiet")
    assert status == 0 and _readable(out) == [] and max(map(len, out.splitlines())) < 300, out
    assert "a root of a degree-105 polynomial" in out and "0.9998891599" in out
    status, out, _ = run(capsys, "analyze", path, "--json")
    doc = json.loads(out)
    assert doc["blocks"][0]["modulus_degree"] == 105 and len(doc["blocks"][0]["modulus"]) > 4000
    S, loss = files.load(path)
    m = sk.stability(S, loss).margins[0]
    lo, hi = map(sp.Rational, m.refine(sp.Rational(1, 10 ** 30)).interval)
    value = sp.cos(sp.pi / 211) ** 2 / 2
    assert m.minpoly.degree() == 105 and sp.N(value - lo, 20) >= 0 and sp.N(hi - value, 20) >= 0 and hi - lo < 1e-30


def test_the_margin_of_a_cosine_is_its_square_over_the_loss():
    """``A = cos(pi/23)``, one sensor, loss 1/3: margin ``cos(pi/23)^2 / 3``, whose minimal
    polynomial sympy computes on its own (an independent witness of flint's arithmetic)."""
    S = sk.System(A=[["cos(pi/23)"]], sensors=[sk.Sensor(C=[[1]])])
    m = sk.stability(S, sk.IID(["1/3"])).margins[0]
    x = sp.Symbol("x")
    assert sp.Poly(m.minpoly, x).monic() == sp.Poly(sp.minimal_polynomial(sp.cos(sp.pi / 23) ** 2 / 3, x), x).monic()
    lo, hi = map(sp.Rational, m.refine(sp.Rational(1, 10 ** 20)).interval)
    assert sp.N(sp.cos(sp.pi / 23) ** 2 / 3 - lo, 20) >= 0 and sp.N(hi - sp.cos(sp.pi / 23) ** 2 / 3, 20) >= 0


def test_patterns_in_words():
    assert pattern_words([("s1", 0)]) == "s1 received at phase 0 only"
    assert pattern_words([]) == "nothing received"
    assert pattern_words([("s1", 1), ("s2", 0), ("s1", 0)]) == \
        "s1 received at phases 0 and 1, s2 at phase 0, nothing else"
    assert "decisive pattern: s1 received at phase 0 only;" in str(sk.stability(DESIGN, sk.IID(["1/10"])))


# --- 7. internal words --------------------------------------------------------------------------

def test_no_internal_words_reach_users():
    # papers are cited by authors and title, never by the team's file names or brief
    internal = re.compile(r"[Ss]eed 00\d|seeds/|DESIGN\.md|DESIGN example|DESIGN rotation")
    files = [p for p in [*(ROOT / "symkf").rglob("*"), *(ROOT / "docs").glob("*.md"), *(ROOT / "examples").glob("*"),
                         *(ROOT / "proofs").glob("*"), ROOT / "README.md"]
             if p.is_file() and p.suffix in (".py", ".md", ".toml")]
    found = [f"{p.relative_to(ROOT)}:{i}" for p in files
             for i, line in enumerate(p.read_text(encoding="utf-8").splitlines(), 1) if internal.search(line)]
    assert found == []


# --- 4, 5. result objects and honest simulation output ------------------------------------------

def test_verify_is_an_object_with_todays_json():
    r = sk.verify(DESIGN, sk.IID(["1/20"]), paths=3000, seed=0)
    assert isinstance(r, sk.Verification) and r.stable and r.outcome == "consistent"
    assert r.margin.exact == 2 * sp.sqrt(5) / 5 and r.critical_common_loss_rate.exact == sp.Rational(1, 16)
    doc = r.to_json()
    assert list(doc) == ["theory", "simulation", "outcome", "rate_consistent", "reason"]
    assert doc["theory"]["margins"][0]["exact"] == "2*sqrt(5)/5" and json.loads(json.dumps(doc)) == doc
    assert repr(r).startswith("<Verification consistent: exact margin 2*sqrt(5)/5 ~ 0.894427 (stable)")
    assert r"\frac{2 \sqrt{5}}{5}" in r._repr_latex_() and "CONSISTENT" in r._repr_html_()
    assert str(r).splitlines()[0] == "theory:     stable (Theorem 4 with eq. (36))"


def test_simulate_never_prints_an_interval_the_data_cannot_support():
    # a filter diverging by 9/8 per step: plain Monte Carlo loses the mean to rare bursts early;
    # no interval is given from there on, every given one is positive, and the text says why
    system, loss = DIVERGING
    for seed in range(20):   # decisive on each of 20 seeds (checked before landing)
        sim = sk.simulate(system, loss, horizon=60, paths=300, seed=seed)
        r = sim.resolved_until
        assert sim.stable is False and sim.growth_rate.exact == sp.Rational(9, 8)
        assert 1 <= r < 40 and not sim.resolved[r:].any()       # seen: 9 to 11 at 300 paths
        assert all(sim.interval(k)[0] > 0 for k in range(r)) and sim.interval(r) is None
    doc = sim.to_json()
    assert doc["low"][r:] == [None] * (60 - r) and doc["resolved_until"] == r
    # computed once per simulation (per call, to_json was quadratic in the horizon), and read-only
    assert sim.resolved is sim.resolved and not sim.resolved.flags.writeable
    assert "the filter diverges (exact growth 9/8 ~ 1.125 per step)" in doc["notes"][0]
    assert "not resolved" in str(sim) and "[-" not in str(sim)


def test_simulate_says_where_and_why_the_curve_stops(capsys):
    system, loss = DIVERGING
    sim = sk.simulate(system, loss, horizon=200, paths=200, seed=0, curve=True)
    stop = sim.curve.stop_reason
    assert sim.curve.float_cap is not None and sim.curve.ks[-1] < 200
    assert stop.startswith(f"the importance-sampled curve stops at k = {sim.curve.ks[-1]} of 200: beyond k = ")
    assert stop in sim.to_json()["notes"] and "montecarlo.float_horizon" in str(sim)
    assert repr(sim).startswith("<Simulation of E[tr P_k]: 200 paths x 200 steps, seed 0")
    assert "not resolved" in sim._repr_html_() and r"\text{not resolved}" in sim._repr_latex_()


def test_a_stable_simulation_is_resolved_throughout():
    # losses 1/1000: a path carrying 10 % of the sum needs three alternating losses (the period-2
    # blind pattern, tr P x 4^3), 8e-9 per path, 3e-4 over these 20 x 2000 paths; at 1/100 it is
    # 8e-6 per path, 27 % over 20 seeds (seeds 14 and 19 of the per-sensor sampler have one)
    for seed in range(20):
        sim = sk.simulate(DESIGN, sk.IID(["1/1000"]), horizon=12, paths=2000, seed=seed)
        assert sim.resolved_until == 12 and sim.notes() == []
        assert np.all(sim.estimate.low > 0) and np.all(sim.estimate.low <= sim.estimate.mean)


# --- 10. small things ---------------------------------------------------------------------------

def test_one_probability_for_every_sensor():
    assert sk.IID("1/10", d=3).loss == (sp.Rational(1, 10),) * 3
    ge = sk.GilbertElliott(fail="1/4", recover=["1/2", "1/3"])
    assert ge.fail == (sp.Rational(1, 4),) * 2 and sk.GilbertElliott("1/4", "1/2", d=2).d == 2
    with pytest.raises(InputError, match="loss: a single probability needs d, the number of sensors"):
        sk.IID("1/10")
    with pytest.raises(InputError, match=r"loss: 1 probabilities for d = 2 sensors"):
        sk.IID(["1/10"], d=2)


def test_warnings_point_at_the_callers_line():
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        sk.System(A=[[0.1, 0], [0, 2]], sensors=[sk.Sensor(C=[[1, 1]])], rationalize=True)
    assert [Path(w.filename).name for w in caught] == ["test_newcomer.py"]


def test_dir_lists_only_the_public_api():
    names = dir(sk)
    assert not {"Any", "TYPE_CHECKING", "sys", "importlib", "types"} & set(names)
    assert {"verify", "simulate", "Verification", "Simulation", "System", "__version__"} <= set(names)


def test_strategy_errors_offer_what_strategies_take():
    strategies = pytest.importorskip("symkf.model.strategies")
    from hypothesis.errors import InvalidArgument
    with pytest.raises(InvalidArgument) as info:
        strategies.rotation_systems(scale=0.3)
    assert str(info.value) == "scale: the float 0.3 is not exact; give the string '0.3', a Fraction or a Decimal"


def test_statespace_has_sampling_time_one_and_says_there_is_no_input():
    pytest.importorskip("control")
    from symkf.model.statespace import to_statespace
    G = to_statespace(DESIGN)
    assert G.dt == 1 and G.input_labels == ["no_input"] and not G.B.any()


def test_bare_command_prints_usage_and_help_names_json(capsys):
    status, out, _ = run(capsys)
    assert status == 2 and out.startswith("usage: symkf") and "--json" in out and "examples" in out
    assert cli.main(["analyze", "--help"]) == 0
    assert cli.FILE_HELP in " ".join(capsys.readouterr().out.split())


def test_json_errors_go_to_stdout_too(capsys, tmp_path):
    status, out, err = run(capsys, "analyze", tmp_path / "missing.toml", "--json")
    doc = json.loads(out)
    assert status == 2 and doc["error"]["type"] == "UsageError" and doc["error"]["exit_status"] == 2
    assert doc["schema_version"] == cli.SCHEMA_VERSION and err.count("\n") == 1
    unseen = tmp_path / "unseen.toml"   # the mode 3 is unstable and no sensor sees it
    unseen.write_text('[system]\nA = [["2", "0"], ["0", "3"]]\n[[sensors]]\nC = [["1", "0"]]\n'
                      '[loss]\nkind = "iid"\nloss = ["1/10"]\n')
    status, out, _ = run(capsys, "analyze", unseen, "--json")
    assert status == 3 and json.loads(out)["error"]["exit_status"] == 3
    status, out, err = run(capsys, "simulate", unseen, "--paths", "5", "--json")    # no --horizon
    assert status == 2 and json.loads(out)["error"]["message"] == err.strip() and "--horizon" in err


def test_families_in_memory():
    def rotation(g):
        c, s = sp.cos(sp.pi / g), sp.sin(sp.pi / g)
        return sk.System(A=[[2 * c, -2 * s], [2 * s, 2 * c]], sensors=[sk.Sensor(C=[[1, 0]])])
    from symkf import tables
    table = tables.family_table(grid_family(rotation, {"g": [2, 3]}), progress=False)
    # eps_c = 2^(-2g/(g - 1)) (the rotation-periods family's hand derivation, d = 1)
    assert [r["cells"][0]["exact"] for r in table.to_json()["rows"]] == ["1/16", "1/8"]
    family = systems_family([(DESIGN, sk.IID(["1/20"])), (DESIGN, sk.IID(["1/10"]))], compute="stability")
    checked = sk.verify_family(family, paths=2000, horizon=40, progress=False)
    assert [m.label for m in checked] == ["system = 1", "system = 2"]
    assert [m.verification.stable for m in checked] == [True, False]      # margins 0.894, 1.265
    assert checked.counts()["consistent"] == 2 and repr(checked).startswith("<FamilyVerification systems: 2 members")


# --- 3, 8. offline docs, notebooks ---------------------------------------------------------------

def test_offline_check_finds_assets_from_other_hosts(tmp_path):
    sys.path.insert(0, str(ROOT / "docs"))
    try:
        from offline import _check, external_assets
    finally:
        sys.path.remove(str(ROOT / "docs"))
    (tmp_path / "a.html").write_text('<script src="_static/mathjax/tex-chtml.js"></script>'
                                     '<link rel="stylesheet" href="_static/x.css"><a href="https://x.org">x</a>')
    assert external_assets(tmp_path) == []
    (tmp_path / "b.html").write_text('<script defer src="https://cdn.jsdelivr.net/npm/mathjax@3/es5/tex.js">'
                                     '</script><link rel="stylesheet" href="//fonts.example/f.css">')
    assert external_assets(tmp_path) == ["b.html: https://cdn.jsdelivr.net/npm/mathjax@3/es5/tex.js",
                                         "b.html: //fonts.example/f.css"]
    app = SimpleNamespace(builder=SimpleNamespace(format="html"), outdir=str(tmp_path))
    with pytest.raises(RuntimeError, match="b.html: https://cdn.jsdelivr.net"):   # the build fails
        _check(app, None)


def test_no_text_bars_in_a_kernel_without_widgets(monkeypatch):
    from symkf.run import progress
    monkeypatch.delenv("TQDM_DISABLE", raising=False)
    monkeypatch.setitem(sys.modules, "ipykernel", sys)          # "a Jupyter kernel runs"
    monkeypatch.setitem(sys.modules, "ipywidgets", None)       # without ipywidgets
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert progress.progress(3, "x").disable
    monkeypatch.delitem(sys.modules, "ipykernel")
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)
    assert not progress.progress(3, "x").disable

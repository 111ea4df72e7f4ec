"""``verify`` over a family: serial, local processes and Dask give identical reports; the CLI."""

from __future__ import annotations

import importlib
import json
import os

import pytest
import sympy as sp

from symkf.exact.numbers import sympify as exact
from symkf import cli, examples
from symkf.errors import FileFormatError
from symkf.io.families import load_family
from symkf.io.family_verification import is_family_file, verify_family
from symkf.numeric.verify import verify

# A = 2 R(pi/2), C = [1 0] (the example design-rotation.toml): eps_c = 1/16, and for i.i.d. loss eps the
# limiting margin is alpha^2 rho = 4 sqrt(eps) (hand-derived: the period-2 bursts lose one phase)
FAMILY = """
[family]
name = "rotation-loss"
[grid]
eps = ["1/50", "1/10", "1/8"]
[system]
A = [["0", "-2"], ["2", "0"]]
[[sensors]]
name = "s1"
C = [["1", "0"]]
[loss]
kind = "iid"
loss = ["eps"]
"""
RUN = {"paths": 2000, "horizon": 40}
#: the family's base seed; the simulation is checked with SYMKF_TEST_SEED = 0..19 before landing
SEED = 7 + 9 * int(os.environ.get("SYMKF_TEST_SEED", "0"))
# the same system scaled by alpha, without a [loss] template
NO_LOSS = FAMILY.split("[loss]")[0].replace('eps = ["1/50", "1/10", "1/8"]', 'alpha = ["2", "3"]') \
    .replace('"-2"], ["2"', '"-alpha"], ["alpha"')


@pytest.fixture(scope="module")
def path(tmp_path_factory):
    p = tmp_path_factory.mktemp("fam") / "rotation-loss.toml"
    p.write_text(FAMILY)
    return p


@pytest.fixture(scope="module")
def serial(path):
    return verify_family(path, seed=SEED, **RUN).to_dict()["members"]


def test_members_report_hand_derived_theory_and_agree(serial):
    assert [r["member"] for r in serial] == ["eps = 1/50", "eps = 1/10", "eps = 1/8"]
    assert [r["point"] for r in serial] == [{"eps": "1/50"}, {"eps": "1/10"}, {"eps": "1/8"}]
    margins = [4 * sp.sqrt(sp.Rational(e)) for e in ("1/50", "1/10", "1/8")]
    assert [exact(r["theory"]["margins"][0]["exact"]) for r in serial] == margins
    assert [r["theory"]["stable"] for r in serial] == [m < 1 for m in margins] == [True, False, False]
    assert {r["theory"]["critical_common_loss_rate"]["exact"] for r in serial} == {"1/16"}
    assert [r["outcome"] for r in serial] == ["consistent"] * 3


def test_seeds_follow_member_index(path, serial):
    # member i runs with seeds seed + 3i .. seed + 3i + 2: its report is verify()'s with that seed
    assert [r["seed"] for r in serial] == [SEED, SEED + 3, SEED + 6]
    assert [r["simulation"]["seeds"] for r in serial] == [list(range(SEED + 3 * i, SEED + 3 * i + 3)) for i in range(3)]
    system, loss = load_family(path).members[1].system()
    alone = verify(system, loss, seed=SEED + 3, **RUN).to_dict()
    assert {k: serial[1][k] for k in alone} == alone


def test_processes_match_serial(path, serial):
    assert verify_family(path, jobs=2, seed=SEED, **RUN).to_dict()["members"] == serial


def test_dask_local_cluster_matches_serial(path, serial, dask_cluster):
    assert verify_family(path, scheduler=dask_cluster.scheduler_address, seed=SEED, **RUN).to_dict()["members"] == serial


@pytest.mark.parametrize("A", [[[0]], [[0, 1], [0, 0]]])
def test_a_nilpotent_system_is_verified_stable_at_every_loss(A):
    # rho(A) = 0: no eigen-block decides (its modes vanish after n steps), so no decisive pattern
    # steers the sampling and the margin is 0; verify used to index the blocks by None and take
    # the max of no margins
    import symkf as sk
    S = sk.System(A=A, sensors=[sk.Sensor(C=[[1] + [0] * (len(A) - 1)])])
    for loss in (sk.IID(["1"]), sk.GilbertElliott(["1/2"], ["1/2"])):
        r = verify(S, loss, paths=200, seed=0)
        assert r.verdict.stable and r.verdict.limiting_block is None
        assert r.outcome == "consistent"


def test_family_needs_a_loss_template(tmp_path):
    p = tmp_path / "noloss.toml"
    p.write_text(NO_LOSS)
    with pytest.raises(FileFormatError, match=r"noloss\.toml: \[loss\]: verify needs a loss model"):
        verify_family(p)


def test_inapplicable_member_is_recorded(tmp_path):
    # Gilbert-Elliott with fail = beta: beta = 1/10 is decided, beta = 0 breaks Assumption 2's
    # positivity (a Jordan block, once refused here, is now decided)
    p = tmp_path / "positivity.toml"
    p.write_text(FAMILY.replace('eps = ["1/50", "1/10", "1/8"]', 'beta = ["1/10", "0"]')
                 .replace('kind = "iid"\nloss = ["eps"]', 'kind = "gilbert-elliott"\nfail = ["beta"]\nrecover = ["1/2"]'))
    reports = verify_family(p, paths=200, horizon=10).to_dict()["members"]
    assert reports[1]["outcome"] == "inapplicable" and "Assumption 2" in reports[1]["reason"]
    assert reports[0]["outcome"] != "inapplicable"


def test_detects_family_files(path, tmp_path):
    assert is_family_file(path)
    assert not is_family_file(examples.system("design-rotation"))
    assert not is_family_file(tmp_path / "missing.toml")


def test_cli_plain_json_and_disagreement_status(path, serial, capsys, monkeypatch):
    argv = ["verify", str(path), "--seed", str(SEED), "--paths", "2000", "--horizon", "40"]
    assert cli.main(argv + ["--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["family"] == str(path) and out["members"] == json.loads(json.dumps(serial))
    assert cli.main(argv + ["--jobs", "2"]) == 0
    read, *lines = capsys.readouterr().out.splitlines()
    assert read == f"read: {path}"
    assert len(lines) == 4 and lines[0].startswith("eps = 1/50") and lines[0].endswith("CONSISTENT")
    assert "theory stable     growth 1; simulation" in lines[0]   # a stable member's growth 1, not "1 ~ 1"
    assert f"seeds {SEED + 3}, {SEED + 4}, {SEED + 5}" in lines[1] and lines[3] == ("3 members: 3 consistent, 0 undecided, 0 contradiction, "
                                                        "0 inapplicable, 0 breakdown")

    verify_module = importlib.import_module("symkf.numeric.verify")   # symkf.verify is the function
    monkeypatch.setattr(verify_module, "simulated_verdict", _contrary(verify_module.simulated_verdict))
    assert cli.main(argv) == 1
    assert "CONTRADICTION" in capsys.readouterr().out


def _contrary(simulated_verdict):
    """A simulation that always contradicts the theory (to check the exit status): its rate
    interval is moved to the other side of 1, far from the exact rate."""
    def contrary(system, loss, v, **kw):
        wrong = [1.4, 1.6] if v.stable else [0.5, 0.6]
        return {**simulated_verdict(system, loss, v, **kw), "verdict": "unstable" if v.stable else "stable",
                "rate": sum(wrong) / 2, "rate_interval": wrong}
    return contrary


def test_breakdown_is_recorded_in_the_members_row(path, monkeypatch):
    verify_module = importlib.import_module("symkf.numeric.verify")   # symkf.verify is the function
    from symkf.errors import NumericalBreakdownError

    def breaks(system, loss, v, **kw):
        if v.stable:
            raise NumericalBreakdownError("P lost positive semidefiniteness")
        return simulated_verdict(system, loss, v, **kw)
    simulated_verdict = verify_module.simulated_verdict
    monkeypatch.setattr(verify_module, "simulated_verdict", breaks)
    reports = verify_family(path, seed=SEED, **RUN).to_dict()["members"]
    assert [r["outcome"] for r in reports] == ["breakdown", "consistent", "consistent"]
    assert reports[0]["reason"] == "member eps = 1/50: P lost positive semidefiniteness"
    assert cli.main(["verify", str(path), "--seed", str(SEED), "--paths", "2000", "--horizon", "40"]) == 0


def test_cli_family_without_loss_is_bad_input(tmp_path, capsys):
    p = tmp_path / "noloss.toml"
    p.write_text(NO_LOSS)
    assert cli.main(["verify", str(p)]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1 and "[loss]" in err


def test_undecided_near_threshold_names_the_float64_horizon():
    # ge-two-sensors' system (A = 2 R(pi/2), C1 = [1 0], C2 = [1 1]) with i.i.d. losses 2/5: the
    # decisive pattern loses s1 and s2 at one phase and s1 at the other, 16 eps^3 per period 2,
    # so the margin is 4 (2/5)^(3/2) = 1.0119, 1.2 % above 1.  alpha = 2 caps the horizon at 40
    # steps (h = 12): the derived allowance ln(3/2)/12 = 3.4 % cannot be beaten by more paths
    from symkf.io import files
    from symkf.model.iid import IID
    system, _ = files.load(examples.directory() / "systems" / "ge-two-sensors.toml")
    rep = verify(system, IID(["2/5", "2/5"]), seed=SEED, paths=4000).to_dict()
    assert rep["theory"]["margins"][0]["exact"] == "8*sqrt(10)/25"
    assert rep["outcome"] == "undecided" and rep["simulation"]["horizons"] == [12, 24, 36]
    assert "beyond what float64 resolves here (the horizon is capped at 36" in rep["reason"]

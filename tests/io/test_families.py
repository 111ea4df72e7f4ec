"""Parameter families (symkf.io.families): built in memory from a function and a grid or from a list
of systems, and refused when read if they have more members than the cap."""

from __future__ import annotations

import time

import pytest
import sympy as sp

import symkf as sk
from symkf.errors import BudgetError
from symkf.io.families import grid_family, systems_family

QUARTER_TURN = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="s1")])


def test_families_in_memory():
    def rotation(g):
        c, s = sp.cos(sp.pi / g), sp.sin(sp.pi / g)
        return sk.System(A=[[2 * c, -2 * s], [2 * s, 2 * c]], sensors=[sk.Sensor(C=[[1, 0]])])
    from symkf import tables
    table = tables.family_table(grid_family(rotation, {"g": [2, 3]}), progress=False)
    # eps_c = 2^(-2g/(g - 1)) (the rotation-periods family's hand derivation, d = 1)
    assert [r["cells"][0]["exact"] for r in table.to_json()["rows"]] == ["1/16", "1/8"]
    family = systems_family([(QUARTER_TURN, sk.IID(["1/20"])), (QUARTER_TURN, sk.IID(["1/10"]))], compute="stability")
    checked = sk.verify_family(family, paths=2000, horizon=40, progress=False)
    assert [m.label for m in checked] == ["system = 1", "system = 2"]
    assert [m.verification.stable for m in checked] == [True, False]      # margins 0.894, 1.265
    assert checked.counts()["consistent"] == 2 and repr(checked).startswith("<FamilyVerification systems: 2 members")


def test_family_members_budgeted(tmp_path):
    """A family of 10^4 members is refused when read, before any member is built."""
    from symkf.io.families import load_family
    path = tmp_path / "big.toml"
    path.write_text('[family]\n[grid]\na = { from = 1, to = 1000 }\nb = { from = 1, to = 10 }\n'
                    '[system]\nA = [["a", "b"], ["0", "2"]]\n[[sensors]]\nC = [["1", "1"]]\n')
    with pytest.raises(BudgetError, match="number of family members is 10000, above the cap 2000.*--max-members"):
        load_family(path)


THREE = [sk.Sensor(C=[[1, 0]], name="a"), sk.Sensor(C=[[0, 1]], name="b"), sk.Sensor(C=[[1, 1]], name="c")]


def test_fewest_sensors_as_a_family_column():
    # 2R(pi/2): one sensor needs 16 eps < 1, a pair with c 16 eps^3 < 1, all three 16 eps^4 < 1 (by hand)
    from symkf import tables
    S = sk.System(A=[[0, -2], [2, 0]], sensors=THREE)
    family = systems_family([(S, sk.IID(e, d=3)) for e in ("1/20", "1/10", "2/5", "1/2")], compute="fewest_sensors")
    cells = [r["cells"][0] for r in tables.family_table(family, progress=False).to_json()["rows"]]
    assert [None if c["sensors"] is None else len(c["sensors"]) for c in cells] == [1, 2, 3, None]
    assert "c" in cells[1]["sensors"]


def test_critical_recovery_rate_as_a_family_column():
    from symkf import tables
    S = sk.System(A=[[0, -2], [2, 0]], sensors=THREE[:1])
    family = systems_family([(S, sk.GilbertElliott(["1/10"], ["1/2"]))], compute="critical_recovery_rate")
    cell = tables.family_table(family, progress=False).to_json()["rows"][0]["cells"][0]
    q = sk.critical_recovery_rate(S, ["1/10"])
    assert float(cell["decimal"]) == pytest.approx(float(q.evalf(15)), rel=1e-5)
    iid = systems_family([(S, sk.IID(["1/10"]))], compute="critical_recovery_rate")
    with pytest.raises(sk.SymkfError, match="needs Gilbert-Elliott channels"):
        tables.family_table(iid, progress=False)


def test_a_huge_range_is_refused_before_it_is_built(tmp_path):
    from symkf.io.families import load_family
    path = tmp_path / "huge.toml"
    path.write_text('[family]\nkind = "rotation"\n[grid]\nperiod = { from = 2, to = 1000000000 }\n'
                    '[constants]\nalpha = "2"\n')
    start = time.process_time()
    with pytest.raises(sk.SymkfError, match="the range has 999999999 values, more than 1000"):
        load_family(path)    # 4 GB in 6 s, then a refusal, when the list was built first
    assert time.process_time() - start < 1
    with pytest.raises(BudgetError, match="the number of values of grid period is 100000000"):
        grid_family(lambda period: QUARTER_TURN, {"period": range(10 ** 8)})

"""Parameter families (symkf.io.families): built in memory from a function and a grid or from a list
of systems, refused when read if they have more members than the cap, and every query as a column
(each cell the direct API call on its member, and hand-derived values)."""

from __future__ import annotations

import re
import time

import pytest
import sympy as sp

import symkf as sk
from symkf.errors import BudgetError
from symkf.io.families import evaluate, grid_family, systems_family

QUARTER_TURN = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="s1")])


def test_families_in_memory():
    def rotation(g):
        c, s = sp.cos(sp.pi / g), sp.sin(sp.pi / g)
        return sk.System(A=[[2 * c, -2 * s], [2 * s, 2 * c]], sensors=[sk.Sensor(C=[[1, 0]])])
    from symkf import tables
    table = tables.family_table(grid_family(rotation, {"g": [2, 3]}), progress=False)
    # eps_c = 2^(-2g/(g - 1)) (the rotation-periods family's hand derivation, d = 1)
    assert [r["cells"][0]["exact"] for r in table.to_dict()["rows"]] == ["1/16", "1/8"]
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
    cells = [r["cells"][0] for r in tables.family_table(family, progress=False).to_dict()["rows"]]
    assert [None if c["sensors"] is None else len(c["sensors"]) for c in cells] == [1, 2, 3, None]
    assert "c" in cells[1]["sensors"]


def test_critical_recovery_rate_as_a_family_column():
    from symkf import tables
    S = sk.System(A=[[0, -2], [2, 0]], sensors=THREE[:1])
    family = systems_family([(S, sk.GilbertElliott(["1/10"], ["1/2"]))], compute="critical_recovery_rate")
    cell = tables.family_table(family, progress=False).to_dict()["rows"][0]["cells"][0]
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


#: 2R(pi/2) watched along both axes: over a period of two steps a loss of both sensors once leaves
#: one direction unseen, so the filter is stable iff 16 eps_1 eps_2 < 1 (i.i.d.), by hand
CROSS = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="s1"), sk.Sensor(C=[[0, 1]], name="s2")])


def _cells(outcome):
    return {column.plain: value for column, value in outcome.columns}


def test_per_sensor_critical_loss_rates_are_the_direct_calls_and_the_hand_values():
    loss = sk.IID(["1/8", "1/2"])
    (outcome,) = systems_family([(CROSS, loss)], compute="critical_loss_rate_per_sensor").evaluate(progress=False)
    cells = _cells(outcome)
    assert cells["eps_c(s1)"].exact == sp.Rational(1, 8) and cells["eps_c(s2)"].exact == sp.Rational(1, 2)
    for name in ("s1", "s2"):
        assert cells[f"eps_c({name})"] == sk.critical_loss_rate(CROSS, name, others=["1/8", "1/2"])
    # one sensor: its own critical rate is the common one, 1/16 (16 eps < 1)
    (alone,) = systems_family([(QUARTER_TURN, sk.IID(["1/10"]))],
                              compute="critical_loss_rate_per_sensor").evaluate(progress=False)
    assert _cells(alone)["eps_c(s1)"].exact == sp.Rational(1, 16)


def test_per_sensor_critical_recovery_rates_are_the_direct_calls_and_the_hand_values():
    """ge-two-sensors (C = [1, 0], [1, 1] on 2R(pi/2), fail 1/4): with s2's recovery 1/2, s2 lost
    through a period contributes (1 - 1/2)^2 and s1, free at one phase, q/4 + (1 - q)^2, so
    16 (1/4) (q/4 + (1 - q)^2) < 1, i.e. (4q - 3)(q - 1) < 0: q_c(s1) = 3/4."""
    S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="s1"), sk.Sensor(C=[[1, 1]], name="s2")])
    loss = sk.GilbertElliott(["1/4", "1/4"], ["1/2", "1/2"])
    (outcome,) = systems_family([(S, loss)], compute="critical_recovery_rate_per_sensor").evaluate(progress=False)
    cells = _cells(outcome)
    assert cells["q_c(s1)"].exact == sp.Rational(3, 4)
    for name in ("s1", "s2"):
        assert cells[f"q_c({name})"] == sk.critical_recovery_rate(S, ["1/4", "1/4"], recover=["1/2", "1/2"],
                                                                  sensor=name)


def test_stability_margin_column_is_the_verdicts_margin():
    # one sensor, i.i.d. loss 1/25: 16 eps per period of two steps, margin sqrt(16/25) = 4/5 (by hand)
    loss = sk.IID(["1/25"])
    (outcome,) = systems_family([(QUARTER_TURN, loss)], compute="stability_margin").evaluate(progress=False)
    assert outcome.value.exact == sp.Rational(4, 5) == sk.stability(QUARTER_TURN, loss).limiting_margin.exact


def test_a_list_of_queries_gives_their_columns_in_order_on_an_in_memory_grid():
    def crossed(e):
        return CROSS, sk.IID([e, "1/2"])
    family = grid_family(crossed, {"e": ["1/25", "1/8"]}, compute=["critical_loss_rate", "stability_margin",
                                                                   "critical_loss_rate_per_sensor"])
    first, second = family.evaluate(progress=False)
    assert [c.plain for c, _ in first.columns] == ["critical loss rate", "margin", "eps_c(s1)", "eps_c(s2)"]
    # common: 16 eps^2 < 1; margins sqrt(16 e / 2): 2 sqrt(2)/5 and 1; s1's critical loss 1/(16/2),
    # s2's 1/(16 e) (at most 1)
    assert [v.exact for _, v in first.columns] == [sp.Rational(1, 4), 2 * sp.sqrt(2) / 5, sp.Rational(1, 8), 1]
    assert [v.exact for _, v in second.columns] == [sp.Rational(1, 4), 1, sp.Rational(1, 8), sp.Rational(1, 2)]
    assert evaluate(family.members[0]) == first


def test_a_query_whose_assumptions_fail_leaves_the_others_standing():
    # fail = 0: the joint chain has a zero transition (Sui-You-Fu Assumption 2 fails), which the
    # margin needs and the critical common i.i.d. loss rate does not
    from symkf.io.families import Inapplicable
    family = systems_family([(QUARTER_TURN, sk.GilbertElliott(["0"], ["1/2"]))],
                            compute=["critical_loss_rate", "stability_margin"])
    ((_, rate), (_, margin)), = [o.columns for o in family.evaluate(progress=False)]
    assert rate.exact == sp.Rational(1, 16) and isinstance(margin, Inapplicable) and "Assumption 2" in margin.reason


def test_a_query_without_its_loss_model_names_the_member_and_the_query():
    family = systems_family([CROSS], compute="critical_loss_rate_per_sensor")
    with pytest.raises(sk.SymkfError, match='member system = 1: compute = "critical_loss_rate_per_sensor" needs a loss'):
        family.evaluate(progress=False)


def test_a_query_on_the_wrong_loss_model_names_the_query():
    family = systems_family([(CROSS, sk.IID(["1/8", "1/2"]))],
                            compute=["critical_loss_rate", "critical_recovery_rate_per_sensor"])
    with pytest.raises(sk.SymkfError, match='"critical_recovery_rate_per_sensor" needs Gilbert-Elliott channels'):
        family.evaluate(progress=False)


@pytest.mark.parametrize("compute, message", [
    ('["stability", "stability"]', "queries repeat"),
    ("[]", "a query name or a non-empty list"),
    ('["margin"]', "'margin' is not one of"),
    ('["critical_loss_rate", "stability_margin"]', 'compute = "stability_margin" needs a loss model'),
    ('["critical_loss_rate", "critical_arrival_rate"]', '[[actuators]]: compute = "critical_arrival_rate" needs actuators'),
])
def test_bad_compute_lists_are_refused_naming_the_key(tmp_path, compute, message):
    from symkf.io.families import load_family
    path = tmp_path / "f.toml"
    path.write_text(f'[family]\ncompute = {compute}\n[grid]\na = [2, 3]\n[system]\nA = [["a"]]\n'
                    '[[sensors]]\nC = [["1"]]\n')
    with pytest.raises(sk.SymkfError, match=re.escape(message)):
        load_family(path)


def test_critical_arrival_rate_column_is_the_direct_call_and_the_hand_values():
    # lqg-input-rank: A = diag(a, 5/4), B = [[1, b], [1, 1]] on one channel.  b = 1: rank B = 1 and
    # nu_c = 1 - 1/(5a/4)^2; b = 0: B invertible and nu_c = 1 - 1/a^2; eps_c = 1/a^2 (by hand)
    from symkf import examples
    from symkf.io.families import load_family
    family = load_family(examples.family("lqg-input-rank"))
    assert [m.label for m in family.members[:2]] == ["a = 3/2, b = 1", "a = 3/2, b = 0"]
    hand = [(sp.Rational(4, 9), sp.Rational(161, 225)), (sp.Rational(4, 9), sp.Rational(5, 9)),
            (sp.Rational(1, 4), sp.Rational(21, 25)), (sp.Rational(1, 4), sp.Rational(3, 4)),
            (sp.Rational(1, 9), sp.Rational(209, 225)), (sp.Rational(1, 9), sp.Rational(8, 9))]
    for member, (outcome, (eps_c, nu_c)) in zip(family.members, zip(family.evaluate(progress=False), hand)):
        (_, rate), (column, threshold) = outcome.columns
        assert column.plain == "critical arrival rate" and rate.exact == eps_c
        assert threshold.exact.exact == nu_c == sk.control.critical_arrival_rate(member.system()[0]).exact.exact


def test_actuators_of_a_family_file_reach_every_member_as_in_a_system_file():
    from symkf import examples
    from symkf.io.families import load_family
    member = load_family(examples.family("lqg-input-rank")).members[1]     # a = 3/2, b = 0
    system, loss = member.system()
    assert system.actuator_names == ("u",) and loss is None
    assert system.B == sp.Matrix([[1, 0], [1, 1]]) and system.A == sp.diag(sp.Rational(3, 2), sp.Rational(5, 4))


def test_a_bad_actuator_list_in_a_family_file_is_refused_when_read(tmp_path):
    from symkf.io.families import load_family
    path = tmp_path / "f.toml"
    path.write_text('[family]\ncompute = "critical_arrival_rate"\n[grid]\na = [2, 3]\n[system]\nA = [["a"]]\n'
                    '[[sensors]]\nC = [["1"]]\n[actuators]\nB = [["1"]]\n')
    with pytest.raises(sk.SymkfError, match=re.escape("[[actuators]] must list tables, one per actuator")):
        load_family(path)


def test_a_built_member_without_actuators_names_the_query_that_needs_them():
    family = systems_family([QUARTER_TURN], compute="critical_arrival_rate")
    with pytest.raises(sk.SymkfError, match=re.escape('compute = "critical_arrival_rate" needs actuators')):
        family.evaluate(progress=False)


def test_an_unreachable_unstable_mode_leaves_the_control_cell_inapplicable():
    # B = e_1 never reaches the mode 3: no arrival rate stabilises, the critical loss rate stands
    from symkf.io.families import Inapplicable
    S = sk.System(A=[[2, 0], [0, 3]], sensors=[sk.Sensor(C=[[1, 1]])], actuators=[sk.Actuator(B=[[1], [0]])])
    (outcome,) = systems_family([S], compute=["critical_loss_rate", "critical_arrival_rate"]).evaluate(progress=False)
    (_, rate), (_, control) = outcome.columns
    assert rate.exact == sp.Rational(1, 9) and isinstance(control, Inapplicable)
    assert "the eigenvalue 3 of A" in control.reason and "not stabilizable" in control.reason

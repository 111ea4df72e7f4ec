"""Resource budgets (symkf.budget): caps raised in a block and restored after it, unknown caps and
caps beyond what Python can serve refused, and the digits of ``critical --digits``: a billion refused
at once naming the memory cap, 5000 served once --max-digits is raised (in a forked child under
hard limits, conftest.limited).  The caps each layer applies are tested with that layer."""

from __future__ import annotations

import pytest
import sympy as sp

from symkf import budget, cli
from symkf.errors import BudgetError, InputError
from symkf.exact.numbers import parse_exact

from conftest import ROTATION, limited, one_line, run, system_file


def test_caps_can_be_raised_and_are_restored():
    """sum of 7 square roots of primes: degree 2^7 = 128 > 64 (default); with the cap raised it
    parses (and the cap returns to its default after the block)."""
    text = "+".join(f"sqrt({p})" for p in (2, 3, 5, 7, 11, 13, 17))
    with pytest.raises(BudgetError, match="is 128, above the cap 64"):
        parse_exact(text, "x")
    with budget.limits(max_degree=128):
        assert parse_exact(text, "x") == sum(sp.sqrt(p) for p in (2, 3, 5, 7, 11, 13, 17))
    assert budget.LIMITS.max_degree == 64




def test_digits_beyond_python_are_a_usage_error(capsys, tmp_path):
    """--max-digits 10^15 made Python's int-to-text limit overflow a C int (OverflowError, exit 70)."""
    path = tmp_path / "s.toml"
    path.write_text(ROTATION)
    status, _, err = run(capsys, "critical", path, "--digits", "1000000000", "--max-digits", "1000000000000000")
    assert status == 2 and "--max-digits" in one_line(err) and str(budget.MAX_DIGITS_CAP) in err
    with pytest.raises(InputError, match="max_digits: 1000000000000000 is above"):
        with budget.limits(max_digits=10 ** 15):
            pass
    with pytest.raises(InputError, match="unknown cap"):
        with budget.limits(max_degre=3):
            pass


def test_a_billion_digits_refused_at_once(tmp_path):
    """`critical --digits 1e9` with --max-digits raised ran for minutes (conversions quadratic in
    the digits); its memory (64 bytes per digit at least: 6.4e10) is refused naming the cap."""
    path = system_file(tmp_path, "2")
    code, err = limited(cli.main, ["critical", str(path), "--digits", "1000000000", "--max-digits", "1000000000"])
    assert code == 2 and err.count("\n") == 1 and "--digits" in err and "--max-memory" in err, err


def test_raised_digit_cap_serves_beyond_pythons_int_limit(tmp_path):
    """--digits 100000 was exit 70 (Python's 4300-digit int <-> str limit); above the default cap it
    is refused, and with --max-digits raised 5000 digits are served: A = [cbrt(3)] has the
    irrational critical rate 3^(-2/3), whose isolating interval at 10^-5002 has endpoints of
    about 19700 characters (the conversion limit follows the cap)."""
    path = tmp_path / "cube.toml"
    path.write_text('[system]\nA = [["root(3, 3)"]]\n[[sensors]]\nC = [["1"]]\n')
    code, err = limited(cli.main, ["critical", str(path), "--digits", "5000", "--max-digits", "6000", "--json"])
    assert code == 0, err


def test_price_sums_the_units_at_their_costs_and_refuses_above_max_work():
    """2 * 10^6 screen points at 0.5 µs and 2 * 10^8 incidences at 0.08 µs: 1 + 16 = 17 CPU-s,
    under the default 60 000 CPU-ms; with the cap at 15 000 the same step is refused before it starts, the message
    naming the estimate, its units, the cap and the option that raises it."""
    assert budget.COSTS["screen point"] == 0.5e-6 and budget.COSTS["incidence"] == 0.08e-6
    assert budget.price("block", "a screen", screen_point=2 * 10 ** 6, incidence=2 * 10 ** 8) == pytest.approx(17)
    with budget.limits(max_work=15_000), pytest.raises(BudgetError) as refused:
        budget.price("block", "a screen", screen_point=2 * 10 ** 6, incidence=2 * 10 ** 8)
    assert str(refused.value) == ("block: the estimated work of a screen is 17 CPU-s, above the cap max_work = "
                                  "15000 CPU-ms; raise it with symkf.budget.limits(max_work=...) or the command-line "
                                  "option --max-work (the estimate: 2000000 screen points at 0.5 µs, 200000000 "
                                  "incidences at 0.08 µs)")
    assert budget.affordable("incidence") == pytest.approx(60 / 0.08e-6)
    # beside 2 * 10^7 screen points (10 CPU-s), 50 CPU-s are left; beside 2 * 10^8 (100 CPU-s), none
    assert budget.affordable("incidence", screen_point=2 * 10 ** 7) == pytest.approx(50 / 0.08e-6)
    assert budget.affordable("incidence", screen_point=2 * 10 ** 8) == 0


def test_an_astronomical_estimate_is_priced_without_overflow():
    with pytest.raises(BudgetError, match=r"is about 10\^34 CPU-s, .*\(the estimate: about 10\^42 incidences at 0.08 µs\)"):
        budget.price("block", "a screen", incidence=10 ** 42)


@pytest.mark.parametrize("call, message", [
    (lambda: budget.seconds(flops=1), "flops: not a kind of work; the kinds are"),
    (lambda: budget.affordable("flops"), "flops: not a kind of work"),
    (lambda: budget.seconds(incidence=float("nan")), "incidence: expected a number of units >= 0, got nan"),
    (lambda: budget.seconds(incidence=-1), "incidence: expected a number of units >= 0, got -1"),
    (lambda: budget.seconds(incidence="10"), "incidence: expected a number of units >= 0, got '10'"),
])
def test_a_unit_of_work_is_a_known_kind_and_a_count(call, message):
    with pytest.raises(InputError, match=message):
        call()


def _burn(seconds):
    import time
    end = time.process_time() + seconds
    while time.process_time() < end:
        pass


def test_a_meter_refuses_the_round_that_would_pass_the_cap_after_the_first():
    from symkf.errors import BudgetError
    with budget.limits(max_work=250):    # 0.25 CPU-s; rounds of 0.06 CPU-s: after 4 rounds 0.24 + 0.06 > 0.25
        meter = budget.Meter("symkf.design.example", "the rounds")
        with pytest.raises(BudgetError, match=r"^symkf.design.example: the rounds spent 0.2\d+ CPU-s in 4 rounds, and "
                                              r"one more \(up to 0.0\d+ CPU-s\) would pass the cap max_work = 250"):
            for _ in range(10):
                meter.round()
                _burn(0.06)
    assert meter.rounds == 4
    with budget.limits(max_work=1):      # the first round always runs: its own steps are priced
        budget.Meter("e", "w").round()


def test_the_covering_search_is_metered():
    # 2R(pi/2) with three sensors needs more than one covering round at loss 1/10 (the docstring's example)
    import symkf as sk
    from symkf.errors import BudgetError
    S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="a"), sk.Sensor(C=[[0, 1]], name="b"),
                                                sk.Sensor(C=[[1, 1]], name="c")])
    with budget.limits(max_work=1), pytest.raises(BudgetError, match="symkf.design: the covering search .* in 1 rounds"):
        sk.design.select_sensors(S, sk.IID("1/10", d=3), costs={"a": 5, "b": 2, "c": 3})
    # the row generation of allocate_channels makes at least two rounds (the first only proposes)
    with budget.limits(max_work=1), pytest.raises(BudgetError, match="symkf.design.allocate_channels: the row generation"):
        sk.design.allocate_channels(S)


def test_a_meter_of_known_rounds_refuses_when_the_rest_at_the_recent_cost_would_pass_the_cap():
    """1000 rounds of 0.02 CPU-s under a cap of 2 CPU-s: once a tenth of the cap (0.2 CPU-s, ten
    rounds) is spent, the 990 left at 0.02 each project about 20 CPU-s, so the eleventh round is
    refused, naming the projection; 50 such rounds (1 CPU-s in all) run to the end."""
    from symkf.errors import BudgetError
    with budget.limits(max_work=2000):
        meter = budget.Meter("symkf.fusion.example", "the steps", rounds=1000)
        with pytest.raises(BudgetError, match=r"^symkf.fusion.example: the steps spent 0.2\d* CPU-s in 1[01] of 1000 "
                                              r"rounds; the 99\d left at 0.0\d+ CPU-s each \(the mean of the last [5-9]\) "
                                              r"would take (19|20|21)(\.\d)? CPU-s in all, above the cap max_work = 2000"):
            for _ in range(1000):
                meter.round()
                _burn(0.02)
        assert meter.rounds in (10, 11)
        meter = budget.Meter("symkf.fusion.example", "the steps", rounds=50)
        for _ in range(50):
            meter.round()
            _burn(0.02)
        assert meter.rounds == 50

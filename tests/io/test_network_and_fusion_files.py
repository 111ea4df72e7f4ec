"""System files with joint Markov and sensor-network losses, and fusion files (symkf.io.files).

The example files in symkf/io/examples/systems/network and symkf/io/examples/systems/fusion must hold exactly
the data that symkf/network/reproduce.py and symkf/fusion/pendulum.py build, and the command
line must decide them (exit 0) or name the assumption that fails and what applies (exit 3).
"""

from __future__ import annotations

import itertools
import json
import warnings
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from conftest import run
from symkf.exact.numbers import sympify as exact, to_exact_matrix
from symkf import budget, examples
from symkf.io import files
from symkf.errors import BudgetError, InputError, SymkfError
from symkf.model.markov import MarkovLoss
from symkf.network import (MarkovNetworkState, NetworkLoss, PeriodicDynamics, SemiMarkovNetworkState, SensorTree,
                           theorem1, theorem2)
from symkf.network import reproduce as rep
from symkf.engine.stability import stability

NETWORK = examples.directory() / "systems" / "network"
FUSION = examples.directory() / "systems" / "fusion"
R = sp.Rational


def write(tmp_path: Path, text: str, name: str = "f.toml") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def dynamics(system) -> PeriodicDynamics:
    return PeriodicDynamics(system.A, [s.C for s in system.sensors])


# -- the papers' example systems equal what the reproduction code builds -----------------------

def test_example3_file_is_the_reproduction_data():
    system, loss = files.load(NETWORK / "quevedo-example3.toml")
    dyn = rep.example3_dynamics()
    assert isinstance(loss, NetworkLoss) and isinstance(loss.state, MarkovNetworkState)
    assert loss.tree == rep.example3_tree()
    assert system.A == dyn.A[0] and [s.C for s in system.sensors] == list(dyn.C)
    assert loss.state.P == sp.Matrix([[R(9, 10), R(1, 10)], [R(3, 10), R(7, 10)]])
    phi = [["19/20", "1/2"], ["19/20", "1/2"], ["19/20", "19/20"], ["19/20", "19/20"], ["19/20", "19/20"]]
    assert loss.phi == to_exact_matrix(phi, "phi")
    assert loss.state.initial == sp.Matrix([[R(3, 4), R(1, 4)]])     # stationary law of P


def test_example3_engine_agrees_with_hand_derivation_and_theorem1():
    system, loss = files.load(NETWORK / "quevedo-example3.toml")
    v = stability(system, loss)
    # Every C_m has a non-zero entry in each 1-D eigen-block, so block i's filter loses rank only
    # when no sensor is heard: theta = 0 iff E1 and E2 both fail, Pr = (1 - phi_1j)(1 - phi_2j).
    # rho = spectral radius of P diag(1/400, 1/4) = (709 + 7 sqrt(9769)) / 8000.
    M = sp.Matrix([[R(9, 10), R(1, 10)], [R(3, 10), R(7, 10)]]) * sp.diag(R(1, 400), R(1, 4))
    rho = max(M.eigenvals(), key=lambda e: float(e))
    assert sp.simplify(rho - (709 + 7 * sp.sqrt(9769)) / 8000) == 0
    for margin, alpha in zip(v.margins, (R(11, 10), 1, R(9, 10))):
        assert sp.simplify(margin.exact - alpha ** 2 * rho) == 0
    assert v.stable
    assert theorem1(loss, dynamics(system)).holds            # sufficient (Theorem 1), so consistent


def test_one_network_state_is_decided_on_the_tree_chain(tmp_path):
    # The file's NetworkLoss goes to the engine as is: its chain holds only the theta vectors the
    # tree can produce.  (induced_loss would lump it onto all 2^5 vectors, whose impossible ones
    # have zero rows, and the engine would refuse it under Assumption 2.)  With i.i.d. links of
    # success 9/10 nothing is heard iff E1 and E2 fail: rho = 1/100, margins alpha^2 / 100.
    text = (NETWORK / "quevedo-example3.toml").read_text().split("[loss]")[0]
    path = write(tmp_path, text + '[loss]\nkind = "network"\nparents = [0, 0, 1, 2, 2]\nP = [["1"]]\n'
                 'phi = [["9/10"], ["9/10"], ["9/10"], ["9/10"], ["9/10"]]\n')
    system, loss = files.load(path)
    assert [m.exact for m in stability(system, loss).margins] == [R(121, 10000), R(1, 100), R(81, 10000)]


def test_robot_file_is_the_reproduction_data():
    system, loss = files.load(NETWORK / "quevedo-robot.toml")
    tree, dyn, phi = rep.robot_network()
    assert isinstance(loss.state, SemiMarkovNetworkState)
    assert loss.tree == tree and system.A == dyn.A[0] and [s.C for s in system.sensors] == list(dyn.C)
    assert loss.phi == to_exact_matrix(phi, "phi")
    assert loss.state.q == to_exact_matrix(rep.ROBOT_Q, "rep.ROBOT_Q")
    assert loss.state.holding == tuple(rep.ROBOT_HOLDING) and loss.state.sigma == 30


def test_semi_markov_network_file_is_the_reproduction_instance():
    system, loss = files.load(NETWORK / "quevedo-semi-markov-network.toml")
    assert system.A == to_exact_matrix(rep.VIIC_A, "rep.VIIC_A")
    assert system.sensors[0].C == to_exact_matrix(rep.VIIC_C1, "C1")
    assert loss.tree.parents == (0,) and loss.phi == sp.Matrix([[R(19, 20), R(19, 20)]])
    assert loss.state.q == sp.Matrix([[R(1, 2)] * 2] * 2) and loss.state.holding == tuple(rep.VIIC_HOLDING)
    # the instance viic_simulation checks: Theorem 2 (corrected and as printed) holds
    t2 = theorem2(loss, dynamics(system))
    assert t2.holds and t2.holds_paper


def test_markov_example_margin_is_hand_derived():
    system, loss = files.load(NETWORK / "markov-shared-channel.toml")
    assert type(loss) is MarkovLoss and loss.order == 1
    P = loss.chain.P
    assert loss.chain.emit == ((1, 1), (1, 0), (0, 1), (0, 0))
    # g = 2; rank is lost iff both packets are lost at every step of one phase:
    # rho^2 = (P^2)[00, 00], margin alpha^4 rho^2 = 16 * 37/1000 = 74/125
    assert (P ** 2)[3, 3] == R(37, 1000)
    v = stability(system, loss)
    assert v.certificate[0].margin_power == R(74, 125) and v.stable


# -- the command line on the example files -------------------------------------------------------

@pytest.mark.parametrize("name, critical", [
    ("quevedo-example3", sp.Rational(100, 121) ** R(1, 5)),   # five sensors see the 11/10 block
    ("quevedo-robot", R(20, 21)),                             # S1, S4 see the 21/20 block
    ("quevedo-semi-markov-network", R(16, 25)),               # 1 / (5/4)^2
    ("markov-shared-channel", R(1, 4))])                      # 16 eps^2 < 1 per period
def test_critical_exits_0(capsys, name, critical):
    status, out, err = run(capsys, "critical", NETWORK / f"{name}.toml", "--json")
    assert status == 0, err
    assert sp.simplify(exact(json.loads(out)["critical_loss_rate"]["exact"]) - critical) == 0


@pytest.mark.parametrize("name", ["quevedo-example3", "markov-shared-channel"])
def test_analyze_decides(capsys, name):
    status, out, err = run(capsys, "analyze", NETWORK / f"{name}.toml")
    assert status == 0 and "stable" in out and err == ""


def test_analyze_semi_markov_robot_and_viic_decided(capsys):
    # the robot's lifted chain (4 positions, holding counters up to 30, theta) has 560 states;
    # both eigen-blocks (21/20, seen by S1 and S4; 1, seen by S3 and S4) have their margins as
    # roots of degree-56 polynomials, 0.153956 and 0.091163 (cross-checked in tests/exact/test_perron.py)
    status, out, err = run(capsys, "analyze", NETWORK / "quevedo-robot.toml")
    assert status == 0 and err == "" and out.splitlines()[3] == "stable (Theorem 7 with eq. (36))"
    assert "[0.153956, 0.153956]" in out and "[0.091163, 0.091163]" in out
    status, out, err = run(capsys, "analyze", NETWORK / "quevedo-semi-markov-network.toml")
    assert status == 0 and "margin alpha^2 rho = 5/64" in out and "irreducible lifted chain" in out


def test_analyze_markov_network_with_zero_transition_names_theorem1(capsys, tmp_path):
    # the robot's chain q read as a Markov network state (Sec. VII-B): q_13 = 0
    text = (NETWORK / "quevedo-robot.toml").read_text()
    text = text.replace("q = [[", "P = [[").split("holding = ")[0] + "phi = " + text.split("phi = ")[1]
    path = write(tmp_path, text)
    system, loss = files.load(path)
    assert isinstance(loss.state, MarkovNetworkState) and loss.state.P[0, 2] == 0
    status, out, err = run(capsys, "analyze", path)
    assert status == 3 and "symkf.network.theorem1" in err and "Assumption 2" in err


# -- the file forms ------------------------------------------------------------------------------

HEADER = '[system]\nA = [["2", "0"], ["0", "3"]]\n[[sensors]]\nC = [["1", "0"]]\n[[sensors]]\nC = [["0", "1"]]\n'


def test_markov_order_two_equals_the_constructor(tmp_path):
    states = [(1, 1), (1, 0), (0, 1), (0, 0)]
    histories = list(itertools.product(states, repeat=2))
    # a chain where the next vector's law depends on both previous ones
    rows = [[R(1 + (i + j) % 3, 10), R(2, 10), R(3, 10), R(4 - (i + j) % 3, 10)]
            for i, j in itertools.product(range(4), repeat=2)]
    initial = [R(1, 16)] * 16
    toml = HEADER + '[loss]\nkind = "markov"\norder = 2\nstates = [[1, 1], [1, 0], [0, 1], [0, 0]]\nP = [' + \
        ", ".join("[" + ", ".join(f'"{p}"' for p in row) + "]" for row in rows) + "]\ninitial = [" + \
        ", ".join(f'"{p}"' for p in initial) + "]\n"
    _, loss = files.load(write(tmp_path, toml))
    direct = MarkovLoss({h: dict(zip(states, row)) for h, row in zip(histories, rows)}, order=2,
                        initial=dict(zip(histories, initial)))
    assert loss.chain == direct.chain and loss.order == 2


def test_states_may_come_in_any_order(tmp_path):
    P = '[["1/2", "1/2", "0", "0"], ["1/4", "1/4", "1/4", "1/4"], ["1/8", "1/8", "1/4", "1/2"], ' \
        '["1/4", "1/4", "1/4", "1/4"]]'
    a = files.load(write(tmp_path, HEADER + f'[loss]\nkind = "markov"\nstates = [[0, 0], [0, 1], [1, 0], [1, 1]]\n'
                         f'P = {P}\n', "a.toml"))[1]
    table = a.table
    assert table[((0, 0),)] == {(0, 0): R(1, 2), (0, 1): R(1, 2), (1, 0): 0, (1, 1): 0}
    assert table[((1, 0),)][(1, 1)] == R(1, 2)


def test_holding_as_list_or_table_and_rationalize(tmp_path):
    base = '[system]\nA = [["2"]]\n[[sensors]]\nC = [["1"]]\n[loss]\nkind = "network"\nparents = [0]\n'
    exact = files.load(write(tmp_path, base + 'q = [["0", "1"], ["1", "0"]]\n'
                             'holding = [["0", "1/2", "1/2"], { 3 = "1" }]\nphi = [["9/10", "1/2"]]\n'
                             'initial = ["1", "0"]\n', "a.toml"))[1]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        floats = files.load(write(tmp_path, 'rationalize = true\n' + base + 'q = [[0, 1], [1, 0]]\n'
                                  'holding = [{ 2 = 0.5, 3 = 0.5 }, [0, 0, 1]]\nphi = [[0.9, 0.5]]\n'
                                  'initial = [1, 0]\n', "b.toml"))[1]
    assert not caught  # TOML decimals are exact (the file's text), nothing was rationalized
    assert exact.state.holding == floats.state.holding == ({2: R(1, 2), 3: R(1, 2)}, {3: 1})
    assert exact.phi == floats.phi and exact.state.initial == sp.Matrix([[1, 0]])
    assert exact.chain == floats.chain


def test_network_chain_limit(tmp_path):
    base = '[system]\nA = [["2"]]\n[[sensors]]\nC = [["1"]]\n[loss]\nkind = "network"\nparents = [0]\n'
    path = write(tmp_path, base + 'q = [["1"]]\nholding = [{ 999999 = "1" }]\nphi = [["1/2"]]\n')
    with pytest.raises(BudgetError,
                       match=r"key 'holding'.*999999 x 2\^1.*is 1999998, above the cap 4096.*--max-network-chain"):
        files.load(path)
    small = write(tmp_path, base + 'q = [["1"]]\nholding = [{ 3 = "1" }]\nphi = [["1/2"]]\n', "small.toml")
    files.load(small)
    with budget.limits(max_network_chain=5), pytest.raises(BudgetError, match="3 x 2\\^1.*is 6, above the cap 5"):
        files.load(small)


# -- fusion files --------------------------------------------------------------------------------

def test_pendulum_fusion_file_is_the_reproduction_model():
    from symkf.fusion import pendulum_model
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")     # the printed decimals, each noted as taken exactly
        model = files.load_fusion(FUSION / "pendulum.toml")
    ref = pendulum_model()
    assert np.array_equal(model.A, ref.A) and np.array_equal(model.Q, ref.Q)
    assert model.arrival == ref.arrival and model.assumption2 == ref.assumption2
    assert all(a.C == b.C and a.R == b.R and a.name == b.name for a, b in zip(model.sensors, ref.sensors))
    assert model.description == ref.description


def test_discrete_fusion_file(tmp_path):
    from symkf.fusion import FusionModel
    from symkf.model.system import Sensor
    path = write(tmp_path, '[fusion]\nA = [["1/2", "1"], ["0", "2"]]\nQ = [["1", "0"], ["0", "1"]]\n'
                 'arrival = ["9/10", "4/5"]\n[[sensors]]\nC = [["1", "0"]]\n[[sensors]]\nC = [["0", "1"]]\n')
    model = files.load_fusion(path)
    ref = FusionModel.discrete([["1/2", 1], [0, 2]], [[1, 0], [0, 1]], [Sensor([[1, 0]]), Sensor([[0, 1]])],
                               ["9/10", "4/5"])
    assert np.array_equal(model.A, ref.A) and model.assumption2 == ref.assumption2
    # (1 - min lambda) rho(A)^2 = (1/5) 4 = 4/5
    assert model.assumption2.exact == R(4, 5) and model.assumption2.holds


@pytest.mark.parametrize("text, key", [
    ('[fusion]\nA = [["2"]]\nQ = [["1"]]\nTs = "1"\narrival = ["1/2"]\n[[sensors]]\nC = [["1"]]\n', "'Ts'"),
    ('[fusion]\nA = [["2"]]\nQ = [["1"]]\narrival = [true]\n[[sensors]]\nC = [["1"]]\n', "arrival[0]"),
    ('[fusion]\nA = [["2"]]\narrival = ["1/2"]\n[[sensors]]\nC = [["1"]]\n', "'Q'"),
    ('[fusion]\nA = [["2"]]\nQ = [["1"]]\narrival = ["3/2"]\n[[sensors]]\nC = [["1"]]\n', "arrival[0]"),
    ('[system]\nA = [["2"]]\n[fusion]\n', "'system'")])
def test_broken_fusion_files(tmp_path, text, key):
    path = write(tmp_path, text)
    with pytest.raises(InputError) as info:
        files.load_fusion(path)
    assert str(path) in str(info.value) and key in str(info.value) and "\n" not in str(info.value)


def test_a_fusion_file_is_not_a_system_file(capsys):
    status, out, err = run(capsys, "analyze", FUSION / "pendulum.toml")
    assert status == 2 and "symkf.io.files.load_fusion" in err and str(FUSION / "pendulum.toml") in err


# -- round trips and corruption of network files (hypothesis; derandomized in CI) ---------------

PROPS = settings(max_examples=25, deadline=None,
                 suppress_health_check=[HealthCheck.function_scoped_fixture])


@st.composite
def network_files(draw):
    """(TOML text, M, parents, P, phi) of a random small Markov network over a 1-D plant."""
    M, B = draw(st.integers(1, 3)), draw(st.integers(1, 2))
    order = draw(st.permutations(range(1, M + 1)))      # a tree: each node's parent comes earlier
    parents = [0] * M
    for k, m in enumerate(order):
        parents[m - 1] = draw(st.sampled_from([0] + list(order[:k])))
    prob = st.fractions(0, 1, max_denominator=9)
    P = []
    for _ in range(B):
        row = [draw(st.fractions(Fraction(1, 9), 1, max_denominator=9)) for _ in range(B)]
        P.append([x / sum(row) for x in row])
    phi = [[draw(prob) for _ in range(B)] for _ in range(M)]
    q = lambda rows: "[" + ", ".join("[" + ", ".join(f'"{x}"' for x in r) + "]" for r in rows) + "]"
    text = ('[system]\nA = [["2"]]\n' + '[[sensors]]\nC = [["1"]]\n' * M +
            f'[loss]\nkind = "network"\nparents = {parents}\nP = {q(P)}\nphi = {q(phi)}\n')
    return text, parents, P, phi


@PROPS
@given(case=network_files())
def test_network_file_round_trip(tmp_path_factory, case):
    text, parents, P, phi = case
    _, loss = files.load(write(tmp_path_factory.mktemp("n"), text))
    direct = NetworkLoss(SensorTree(parents), MarkovNetworkState(P), phi)
    assert loss.chain == direct.chain


# wrong wherever it lands: out of [0, 1] or not a number (a TOML float is an exact decimal, and 0.5 is a
# fine phi entry: a random run put it there)
JUNK = st.sampled_from(['"3/2"', '"-1/3"', "1.5", '"x"', "[1]", "true", '{ a = 1 }', '"sqrt(-1)"', "7"])


@PROPS
@given(case=network_files(), junk=JUNK, data=st.data())
def test_corrupted_network_file_is_refused_in_one_line(tmp_path_factory, case, junk, data):
    text, parents, P, phi = case
    numbers = [i for i in range(len(text)) if text.startswith('"', i) and text[i + 1:i + 2].isdigit()
               and text.rfind("[loss]", 0, i) >= 0]
    i = data.draw(st.sampled_from(numbers))
    j = text.index('"', i + 1) + 1
    path = write(tmp_path_factory.mktemp("n"), text[:i] + junk + text[j:])
    with pytest.raises(SymkfError) as info:
        files.load(path)
    message = str(info.value)
    assert str(path) in message and "\n" not in message and info.value.exit_status == 2


def test_induced_loss_lives_on_the_vectors_the_tree_can_produce():
    """Example 3 tree, one network state, links 9/10: theta_3 = 1 needs theta_1 = 1 (relay), so 15 of
    the 32 receival vectors occur; the lumped MarkovLoss lives on them and the engine gives the
    same margins as on the NetworkLoss itself (hand-checked: 121/10000, 1/100, 81/10000)."""
    from symkf.network import induced_loss
    S, L = files.load(NETWORK / "quevedo-example3.toml")
    net = NetworkLoss(L.tree, MarkovNetworkState([[1]]), [["9/10"]] * 5)
    lumped = induced_loss(net)
    assert type(lumped) is MarkovLoss and len(lumped.vectors) == 15
    expected = [sp.Rational(121, 10000), sp.Rational(1, 100), sp.Rational(81, 10000)]
    assert [m.exact for m in stability(S, lumped).margins] == [m.exact for m in stability(S, net).margins] == expected


def test_markov_loss_refuses_a_vector_without_a_row():
    with pytest.raises(SymkfError, match=r"leads to \(0,\), which no history contains"):
        MarkovLoss({(1,): {(1,): "1/2", (0,): "1/2"}})

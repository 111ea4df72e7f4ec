"""The loss-model interface (symkf.model.loss.LossModel): every kind answers for itself.

For each kind (i.i.d., Gilbert-Elliott, joint Markov, Markov and semi-Markov network losses,
independent parts): its independent factors reproduce the joint chain's law exactly, its file and
JSON forms read back to the same model, its words, its validator's errors, and its sampler's law
against exact enumeration of short sequences; then the same models through verdict tables, the
CLI's text and JSON reports and figure titles.  The probabilities a model takes: exact, one per
sensor (or one for all with d), rationalized on request, refused above 1."""

from __future__ import annotations

import itertools
import json
import math

import numpy as np
import pytest
import sympy as sp

import symkf as sk
from symkf import cli, examples, tables
from symkf.engine.blocks import block_rows
from symkf.errors import AssumptionError, BudgetError, FileFormatError, InexactInputError, InputError, ShapeError
from symkf.exact.algebraic import sign
from symkf.io import files
from symkf.model.codec import from_table
from symkf.model.gilbert_elliott import GilbertElliott
from symkf.model.iid import IID
from symkf.model.independent import Independent
from symkf.model.loss import LossModel, checked
from symkf.model.markov import MarkovLoss
from symkf.network import MarkovNetworkState, NetworkLoss, SemiMarkovNetworkState, SensorTree
from symkf.numeric.filters import sample_receptions
from symkf.numeric.montecarlo import exact_mean_covariances, simulate_traces
from symkf.numeric.receptions import draw

from conftest import ROOT, ROTATION, limited, one_line, refused_at_once, run

R = sp.Rational


def markov() -> MarkovLoss:
    """Two sensors on a shared channel, sensor 0 more reliable than sensor 1 (asymmetric)."""
    v = [(1, 1), (1, 0), (0, 1), (0, 0)]
    rows = {(1, 1): ["7/10", "1/5", "1/20", "1/20"], (1, 0): ["1/2", "1/4", "1/8", "1/8"],
            (0, 1): ["2/5", "1/5", "1/5", "1/5"], (0, 0): ["1/4", "1/4", "1/4", "1/4"]}
    return MarkovLoss({h: dict(zip(v, p)) for h, p in rows.items()})


MODELS = {
    "iid": lambda: IID(["1/10", "1/4"]),
    "gilbert-elliott": lambda: GilbertElliott(["1/10", "1/3"], ["1/2", "1/5"]),
    "gilbert-elliott-initial": lambda: GilbertElliott(["1/10", "1/3"], ["1/2", "1/5"], initial_received=["1", "1/2"]),
    "markov": markov,
    "network": lambda: NetworkLoss(SensorTree([0, 1]), MarkovNetworkState([["9/10", "1/10"], ["3/10", "7/10"]]),
                                   [["19/20", "1/2"], ["9/10", "3/4"]]),
    "semi-markov-network": lambda: NetworkLoss(SensorTree([0, 0]), SemiMarkovNetworkState(
        [["0", "1"], ["1", "0"]], [{1: "1/2", 2: "1/2"}, [1]]), [["9/10", "1/5"], ["4/5", "1/2"]]),
    "independent": lambda: Independent([GilbertElliott(["1/10"], ["1/2"]), IID(["1/4"])]),
}
WORDS = {"iid": "i.i.d. losses 1/10, 1/4",
         "gilbert-elliott": "Gilbert-Elliott channels, fail 1/10, 1/3, recover 1/2, 1/5",
         "gilbert-elliott-initial": "Gilbert-Elliott channels, fail 1/10, 1/3, recover 1/2, 1/5",
         "markov": "a joint Markov chain of order 1 on 4 receival vectors",
         "network": "a sensor tree of 2 links over a Markov network state with 2 states (Quevedo et al.)",
         "semi-markov-network": "a sensor tree of 2 links over a semi-Markov network state with 2 states "
                                "(Quevedo et al.)",
         "independent": "independent parts: sensor 0 Gilbert-Elliott channels, fail 1/10, recover 1/2; "
                        "sensor 1 i.i.d. losses 1/4"}
SEQUENCES = list(itertools.product(itertools.product((1, 0), repeat=2), repeat=3))   # d = 2, 3 steps


@pytest.mark.parametrize("name", MODELS)
def test_factors_reproduce_the_joint_law(name):
    loss = MODELS[name]()
    independent = loss.bernoulli is not None or loss.kind in ("gilbert-elliott", "independent")
    assert [f.sensors for f in loss.factors] == ([(0,), (1,)] if independent else [(0, 1)])
    for f in loss.factors:   # each factor a stochastic exact chain
        assert all(sum(f.chain.P.row(r)) == 1 for r in range(f.chain.P.rows)) and sum(f.chain.initial) == 1
    # the product of the factors' laws is the joint chain's, sequence by sequence, exactly
    assert all(sp.simplify(loss.sequence_probability(s) - loss.chain.sequence_probability(s)) == 0
               for s in SEQUENCES)
    assert sum(loss.sequence_probability(s) for s in SEQUENCES) == 1
    P, init, emit = loss.numeric()   # the float view multiplies the factors out in the joint order
    ref = loss.chain.numeric()
    assert np.allclose(P, ref[0], atol=1e-15) and np.allclose(init, ref[1]) and np.array_equal(emit, ref[2])


def test_independent_factors_are_the_sensors_chains():
    ge = MODELS["gilbert-elliott"]()
    f0, f1 = ge.factors
    assert f1.chain.P == sp.Matrix([[R(2, 3), R(1, 3)], [R(1, 5), R(4, 5)]])
    assert f1.chain.initial == sp.Matrix([[R(3, 8), R(5, 8)]])      # (1/5) / (1/3 + 1/5) = 3/8 by hand
    iid = MODELS["iid"]()
    assert iid.factors[1].chain.P == sp.Matrix([[R(3, 4), R(1, 4)]] * 2) and iid.bernoulli == (R(1, 10), R(1, 4))
    assert ge.bernoulli is None and markov().bernoulli is None


# -- independent sensors: the per-sensor factors against the joint chain ---------------------------

q = sp.Symbol("q", positive=True)
INDEPENDENT = [
    sk.IID(["1/10", "1/3", "2/7"]),
    sk.IID(["0", "1", "1/2"]),
    sk.GilbertElliott(["1/10", "1/5", "1/7"], ["1/2", "1/3", "3/4"]),
    sk.GilbertElliott(["1/10", "0"], ["1/2", "1/3"], initial_received=["1", "1/9"]),
    sk.GilbertElliott(["1/10", "1/4"], [q, "1/3"]),
]


def _joint_positivity_failure(loss: LossModel) -> bool:
    """The reference: every transition of the joint 2^d-state chain, as LossModel checks it."""
    P = loss.chain.P
    return any(not P[r, s].free_symbols and sign(P[r, s]) <= 0
               for r, s in itertools.product(range(P.shape[0]), repeat=2))


@pytest.mark.parametrize("loss", INDEPENDENT, ids=repr)
def test_independent_sensors_agree_with_the_joint_chain(loss):
    assert loss.symbols == LossModel.symbols.fget(loss)
    if loss.bernoulli is None:  # i.i.d. losses need no positivity (Theorem 4)
        assert (loss.positivity_failure() is not None) == _joint_positivity_failure(loss)
    if loss.symbols:
        with pytest.raises(sk.SymkfError, match="have no value"):
            loss.numeric()
        return
    fast, ref = loss.numeric(), loss.chain.numeric()
    assert np.array_equal(fast[2], ref[2])
    # Kronecker products round each factor once: d factors, relative error below d ulp
    assert np.allclose(fast[0], ref[0], rtol=4e-16 * loss.d, atol=0)
    assert np.allclose(fast[1], ref[1], rtol=4e-16 * loss.d, atol=0)


def _system(d: int = 2) -> sk.System:
    return sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, j]], name=f"s{j}") for j in range(d)])


@pytest.mark.parametrize("name", MODELS)
def test_file_and_json_forms_read_back(tmp_path, name):
    loss = MODELS[name]()
    path = tmp_path / "loss.toml"
    path.write_text('[system]\nA = [["0", "-2"], ["2", "0"]]\n[[sensors]]\nC = [["1", "0"]]\n'
                    '[[sensors]]\nC = [["1", "1"]]\n' + loss.to_toml(), encoding="utf-8")
    _, from_file = files.load(path)
    from_json = from_table(json.loads(json.dumps(loss.to_dict())), 2)
    for other in (from_file, from_json):
        assert type(other) is type(loss) and other.to_table() == loss.to_table()
        assert other.chain.P == loss.chain.P and other.chain.initial == loss.chain.initial
    assert loss.to_table()["kind"] == loss.kind and LossModel.KINDS[loss.kind] is type(loss)


@pytest.mark.parametrize("name", MODELS)
def test_words_say_the_model(name):
    loss = MODELS[name]()
    assert loss.words() == WORDS[name]
    plain = loss.label[1]
    assert plain and all(isinstance(k, str) and isinstance(v, tuple) for k, _, v in loss.fields())


def test_one_validator_one_error_type_per_failure():
    S3, iid = _system(3), MODELS["iid"]()
    for call in (lambda: sk.stability(S3, iid), lambda: simulate_traces(S3, iid, 3, 2),
                 lambda: sample_receptions(iid, 3, 2, np.random.default_rng(0), d=3),
                 lambda: sk.stability_conditions(S3, iid), lambda: sk.second_order.theorem12(S3, iid),
                 lambda: exact_mean_covariances(S3, iid, 2)):
        with pytest.raises(ShapeError, match=r"loss: the model has 2 sensor\(s\), the system has 3"):
            call()
    for call in (lambda: sk.stability(_system(), "iid"), lambda: simulate_traces(_system(), [0.1], 3, 2)):
        with pytest.raises(InputError, match="expected a symkf loss model|must be a LossModel"):
            call()
    with pytest.raises(InputError, match=r"symbols \['q'\] have no value"):
        simulate_traces(_system(), IID(["q", "1/2"]), 3, 2)
    with pytest.raises(AssumptionError, match="Assumption 2") as info:   # positivity: a channel never fails
        checked(GilbertElliott(["0", "1/2"], ["1/2", "1/2"]), _system(), positive=True)
    assert "sensor 0" in str(info.value)
    for call, assumption in ((lambda: sk.capacity.transmission_capacity(markov()), "Yang et al."),
                             (lambda: sk.second_order.theorem12(_system(), markov()), "Assumption 4")):
        with pytest.raises(AssumptionError, match=assumption) as info:
            call()
        assert "a joint Markov chain of order 1" in str(info.value)


def _wrong_law(name: str, p: dict) -> dict:
    """A wrong law of the same model: i.i.d. losses with the two sensors swapped; any other kind
    with the same marginals of every sensor at every step, but independent across sensors and time."""
    if name == "iid":
        swapped = IID(MODELS[name]().loss[::-1])
        return {s: float(swapped.sequence_probability(s)) for s in SEQUENCES}
    marginal = {(k, j): sum(q for s, q in p.items() if s[k][j]) for k in range(3) for j in range(2)}
    return {s: math.prod(marginal[k, j] if s[k][j] else 1 - marginal[k, j] for k in range(3) for j in range(2))
            for s in SEQUENCES}


def _z(counts: dict, p: dict, N: int) -> float:
    """The largest standardised deviation ``|count - N p| / sqrt(N p (1 - p))`` over the sequences."""
    return max(abs(counts[s] - N * q) / math.sqrt(max(N * q * (1 - q), 1.0)) for s, q in p.items())


@pytest.mark.parametrize("name", MODELS)
def test_sampling_law_matches_exact_enumeration(name, seed=7):
    # every 3-step receival sequence of the 2 sensors: the count of 40 000 sampled paths lies within
    # 5 standard deviations of N p (each of 64 sequences: a false alarm has probability < 4e-5 per
    # seed; checked for 20 seeds), never counted when p = 0, and a wrong law is rejected by a margin
    loss, N = MODELS[name](), 40_000
    gamma = draw(loss, 3, N, np.random.default_rng(seed))                      # (horizon, paths, d)
    assert gamma.shape == (3, N, 2) and gamma.dtype == bool
    weights = 2 ** np.arange(5, -1, -1)
    found = np.bincount(gamma.transpose(1, 0, 2).reshape(N, 6).astype(int) @ weights, minlength=64)
    counts = {s: int(found[np.array([g for v in s for g in v]) @ weights]) for s in SEQUENCES}
    p = {s: float(loss.sequence_probability(s)) for s in SEQUENCES}
    assert _z(counts, p, N) < 5
    assert all(counts[s] == 0 for s in SEQUENCES if p[s] == 0)
    assert _z(counts, _wrong_law(name, p), N) > 15


def test_independent_sensors_never_build_the_joint_chain():
    ge = GilbertElliott(["1/10"] * 16, ["1/2"] * 16)
    with pytest.raises(BudgetError, match="max_markov_states"):
        ge.chain
    with pytest.raises(BudgetError, match="max_memory"):
        ge.numeric()
    gamma = draw(ge, 40, 500, np.random.default_rng(1))           # 16 two-state chains: 320 kB
    assert gamma.shape == (40, 500, 16) and 0.8 < gamma.mean() < 0.87   # stationary P(received) = 5/6
    S = sk.System(A=[[0, -1], [1, 0]], sensors=[sk.Sensor(C=[[1, j % 3]]) for j in range(16)])
    assert simulate_traces(S, ge, 10, 64, seed=0).shape == (64, 10)


# -- sizes priced from the shape, before a probability is read -------------------------------------

#: every vector of 9 sensors: a joint chain of 2^9 = 512 states, above max_markov_states (256)
VECTORS9 = list(itertools.product((1, 0), repeat=9))
#: a row of 512 distinct probabilities summing to 1 (a cache of parsed texts cannot help)
ROW9 = [f"1/{2 ** (k + 1)}" for k in range(511)] + ["1/" + str(2 ** 511)]

HUGE_TABLES = {
    "iid loss": ({"kind": "iid", "loss": ["1/10"] * 10 ** 6}, 10 ** 6, "max_sensors"),
    "gilbert-elliott fail": ({"kind": "gilbert-elliott", "fail": ["1/10"] * 10 ** 6, "recover": ["1/2"] * 10 ** 6},
                             10 ** 6, "max_sensors"),
    "markov on 9 sensors": ({"kind": "markov", "states": [list(v) for v in VECTORS9], "P": [ROW9] * 512}, 9,
                            "max_markov_states"),
    "markov P of a million rows": ({"kind": "markov", "states": [[1], [0]], "P": [["1/2", "1/2"]] * 10 ** 6}, 1,
                                   "max_markov_states"),
    "markov initial": ({"kind": "markov", "states": [[1], [0]], "P": [["1/2", "1/2"]] * 2,
                        "initial": ["1/2"] * 10 ** 6}, 1, "max_markov_states"),
    "network P": ({"kind": "network", "parents": [0], "phi": [["1/2"]], "P": [["1/5000"] * 5000] * 5000}, 1,
                  "max_network_chain"),
    "network holding": ({"kind": "network", "parents": [0], "phi": [["1/2"]], "q": [["1"]],
                         "holding": [["1/10"] * 10 ** 6]}, 1, "max_network_chain"),
}


@pytest.mark.parametrize("name", HUGE_TABLES)
def test_a_loss_table_too_large_is_refused_from_its_shape_at_once(name):
    # converted every probability first: 8 sensors' joint chain 44.7 s, a million i.i.d. losses > 60 s
    table, d, cap = HUGE_TABLES[name]
    code, err = limited(refused_at_once, lambda: from_table(table, d, "f.toml: [loss]"), cap)
    assert code == 0, err
    assert err.startswith(("0.", "1.")) and "f.toml: [loss]" in err


@pytest.mark.parametrize("build, cap", [
    (lambda: MarkovLoss({v: dict(zip(VECTORS9, ROW9)) for v in VECTORS9}), "max_markov_states"),
    (lambda: MarkovLoss({(1,): {(1,): "1/2", (0,): "1/2"}, (0,): {(1,): "1/2", (0,): "1/2"}},
                        initial={k: "1/2" for k in range(10 ** 6)}), "max_markov_states"),
    (lambda: MarkovNetworkState([["1"]] * 5000), "max_network_chain"),
    (lambda: SemiMarkovNetworkState([["1"]], [["1/10"] * 10 ** 6]), "max_network_chain"),
    (lambda: SensorTree([0] * 10 ** 6), "max_sensors"),
], ids=["markov on 9 sensors", "markov initial", "network P", "holding law", "sensor tree"])
def test_a_model_too_large_is_refused_from_its_shape_at_once(build, cap):
    code, err = limited(refused_at_once, build, cap)
    assert code == 0, err


# -- the probabilities a model takes --------------------------------------------------------------

def test_one_probability_for_every_sensor():
    assert sk.IID("1/10", d=3).loss == (sp.Rational(1, 10),) * 3
    ge = sk.GilbertElliott(fail="1/4", recover=["1/2", "1/3"])
    assert ge.fail == (sp.Rational(1, 4),) * 2 and sk.GilbertElliott("1/4", "1/2", d=2).d == 2
    with pytest.raises(InputError, match=r"loss: 1 probabilities for d = 2 sensors"):
        sk.IID(["1/10"], d=2)


THREE_SENSORS = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]]), sk.Sensor(C=[[1, 1]]),
                                                          sk.Sensor(C=[[0, 1]])])


def test_a_common_iid_rate_takes_the_systems_number_of_sensors():
    common, listed = sk.IID("1/10"), sk.IID("1/10", d=3)
    assert checked(common, THREE_SENSORS).loss == listed.loss == (sp.Rational(1, 10),) * 3
    # by hand: A = 2R(pi/2), g = 2; of the six rows C_j A^k, C_1 = (1, 0) and C_3 A = (-2, 0) span
    # one line, so a blind period loses the other four: alpha^4 rho^2 = 16 eps^4, margin 4 eps^2 = 1/25
    v = sk.stability(THREE_SENSORS, common)
    assert v == sk.stability(THREE_SENSORS, listed) and v.margins[0] == sp.Rational(1, 25)
    assert sk.critical_alpha(THREE_SENSORS, common) == sk.critical_alpha(THREE_SENSORS, listed)
    assert np.array_equal(simulate_traces(THREE_SENSORS, common, 15, 40, seed=2),
                          simulate_traces(THREE_SENSORS, listed, 15, 40, seed=2))
    assert sk.simulate(THREE_SENSORS, common, horizon=8, paths=20, seed=1).to_dict() == \
        sk.simulate(THREE_SENSORS, listed, horizon=8, paths=20, seed=1).to_dict()


def test_a_common_iid_rate_in_a_file_takes_the_systems_sensors(tmp_path):
    path = tmp_path / "common.toml"
    path.write_text('[system]\nA = [["0", "-2"], ["2", "0"]]\n' + '[[sensors]]\nC = [["1", "0"]]\n'
                    '[[sensors]]\nC = [["1", "1"]]\n[loss]\nkind = "iid"\nloss = "1/10"\n')
    system, loss = files.load(path)
    assert loss.loss == (sp.Rational(1, 10),) * 2 and system.d == 2


def test_a_common_iid_rate_without_a_system_names_the_missing_sensor_count():
    common = sk.IID("1/10")
    assert repr(common) == "IID('1/10')" and common.to_dict() == {"kind": "iid", "loss": "1/10"}
    for use in (lambda: common.loss, lambda: common.chain, lambda: common.factors, lambda: Independent([common]),
                lambda: checked(common), lambda: sk.capacity.transmission_capacity(common)):
        with pytest.raises(InputError, match=r"IID\('1/10'\) is a common rate with no number of sensors"):
            use()


@pytest.mark.parametrize("build", [
    lambda r: sk.IID([0.1, 0.2], rationalize=r),
    lambda r: sk.GilbertElliott([0.1], [0.3], rationalize=r),
    lambda r: sk.MarkovLoss({(1,): {(1,): 0.9, (0,): 0.1}, (0,): {(1,): 0.3, (0,): 0.7}}, rationalize=r),
])
def test_rationalize_exists_on_every_loss_constructor(build):
    """The refusal names rationalize; every loss constructor takes it (it was a TypeError)."""
    with pytest.raises(InexactInputError, match="rationalize"):
        build(False)
    with pytest.warns(UserWarning, match="shortest decimal") as record:
        model = build(True)
    assert len(record) == 1 and model.chain.P.has(sp.Float) is False


def test_rationalize_iid_gives_the_decimals():
    with pytest.warns(UserWarning):
        assert sk.IID([0.1, 0.25], rationalize=True).loss == (R(1, 10), R(1, 4))


def test_loss_above_one_refused_before_evaluation():
    """root(2, 3) > 1 is not a probability: refused with the value, without a hang."""
    with pytest.raises(sk.errors.ProbabilityError, match="not a probability"):
        sk.IID(["root(2, 3)"])




def test_loss_table_without_kind_is_refused(capsys, tmp_path):
    """docs/formats.md says kind is required; it was read as iid."""
    path = tmp_path / "nokind.toml"
    path.write_text(ROTATION + '[loss]\nloss = ["1/10"]\n')
    with pytest.raises(FileFormatError, match=r"\[loss\]: key 'kind' missing"):
        files.load(path)
    status, _, err = run(capsys, "analyze", path)
    assert status == 2 and f"{path}: [loss]: key 'kind' missing" in one_line(err)


# -- every loss kind through tables, reports and figures -----------------------------------------

EXAMPLES = {"iid": "cv-three-sensors", "gilbert-elliott": "ge-two-sensors", "markov": "network/markov-shared-channel",
            "network": "network/quevedo-example3", "independent": "paired-channels"}


def test_verdict_table_of_a_joint_markov_loss():
    # raised AttributeError: 'MarkovLoss' object has no attribute 'fail' (tables treated every
    # non-i.i.d. loss as Gilbert-Elliott)
    table = tables.verdict_table([examples.system("network/markov-shared-channel")], progress=False)
    (row,) = table.to_dict()["rows"]
    assert row["cells"][0]["kind"] == "markov" and row["cells"][0]["order"] == 1
    assert row["cells"][1] == "stable" and row["cells"][3]["exact"] == "sqrt(370)/25"
    assert "joint Markov: order = 1, vectors = 4" in str(table)
    assert r"\nu = 1" in table.to_latex()


def test_verdict_table_has_every_loss_kind():
    table = tables.verdict_table([examples.system(n) for n in EXAMPLES.values()], progress=False)
    cells = [row["cells"][0] for row in table.to_dict()["rows"]]
    assert [c["kind"] for c in cells] == list(EXAMPLES)
    text, latex = str(table), table.to_latex()
    for plain, tex in (("i.i.d.:", "i.i.d."), ("Gilbert-Elliott:", "Gilbert--Elliott"), ("joint Markov:", r"\nu"),
                       ("network:", r"\phi"), ("independent:", "d_i")):
        assert plain in text and tex in latex


@pytest.mark.parametrize("kind", EXAMPLES)
def test_cli_reports_say_the_loss_model(capsys, kind):
    path = str(examples.system(EXAMPLES[kind]))
    _, loss = files.load(path)
    assert cli.main(["analyze", path, "--json", "--quiet"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["loss"]["kind"] == kind and from_table(doc["loss"], loss.d).to_table() == loss.to_table()
    assert cli.main(["analyze", path, "--quiet"]) == 0
    assert f"loss model: {loss.words()}" in capsys.readouterr().out


def test_simulate_text_says_the_loss_model(capsys):
    path = str(examples.system(EXAMPLES["markov"]))
    assert cli.main(["simulate", path, "--horizon", "4", "--paths", "20", "--quiet"]) == 0
    assert "a joint Markov chain of order 1 on 4 receival vectors" in capsys.readouterr().out


@pytest.mark.parametrize("name", ["markov", "network"])
def test_figure_titles_say_every_loss_model(name):
    pytest.importorskip("matplotlib")
    from symkf.numeric.montecarlo import mean_trace_curve
    from symkf.reports import plots
    S, loss = _system(), MODELS[name]()
    title = plots.mean_trace_figure(S, loss, mean_trace_curve(S, loss, 8, 40, seed=0)).axes[0].get_title()
    assert loss.words() in title and "Yang" not in title   # their bounds are for i.i.d. losses: not drawn, not named


def test_docs_worked_example_adds_a_model_in_one_place(tmp_path):
    # docs/losses.md: the class and the hand-derived margin, then the model through a system file,
    # JSON, the sampler and a verdict table without any other change to symkf
    import re
    page = (ROOT / "docs" / "losses.md").read_text(encoding="utf-8")
    blocks = re.findall(r"^```python\n(.*?)^```", page, re.M | re.S)
    assert len(blocks) == 2
    namespace: dict = {}
    for block in blocks:
        exec(compile(block, "docs/losses.md", "exec"), namespace)   # the second block asserts the margin
    cls, loss = namespace["CommonOutage"], namespace["loss"]
    try:
        path = tmp_path / "outage.toml"
        path.write_text('[system]\nA = [["0", "-2"], ["2", "0"]]\n[[sensors]]\nC = [["1", "0"]]\n'
                        '[[sensors]]\nC = [["1", "1"]]\n' + loss.to_toml(), encoding="utf-8")
        S, read = files.load(path)
        assert isinstance(read, cls) and read.chain.P == loss.chain.P
        assert from_table(json.loads(json.dumps(loss.to_dict())), 2).to_table() == loss.to_table()
        assert sk.stability(S, read).margins[0].exact ** 2 == R(828, 3125)
        p = {s: float(loss.sequence_probability(s)) for s in SEQUENCES}
        assert abs(p[((0, 0),) * 3] - (69 / 1000) ** 3) < 1e-15
        gamma = draw(loss, 3, 40_000, np.random.default_rng(3))
        weights = 2 ** np.arange(5, -1, -1)
        found = np.bincount(gamma.transpose(1, 0, 2).reshape(-1, 6).astype(int) @ weights, minlength=64)
        counts = {s: int(found[np.array([g for v in s for g in v]) @ weights]) for s in SEQUENCES}
        assert _z(counts, p, 40_000) < 5
        (row,) = tables.verdict_table([path], progress=False).to_dict()["rows"]
        assert row["cells"][0]["kind"] == "common-outage" and row["cells"][1] == "stable"
    finally:
        del LossModel.KINDS["common-outage"]


@pytest.mark.parametrize("name", ["iid", "gilbert-elliott", "gilbert-elliott-initial"])
def test_hyperplane_rate_of_independent_sensors_is_the_joint_chains(name):
    # the closed forms (i.i.d.: prod_j loss_j^(k_j); Gilbert-Elliott: product of 2x2 traces) against
    # the Perron root of the joint chain's restricted transfer (eq. 36), hyperplane by hyperplane
    from symkf.engine.blocks import block_rows
    from symkf.engine.rates import hyperplane_rate, perron_root, restricted_transfer
    loss = MODELS[name]()
    (br,) = block_rows(_system())
    assert len(br.hyperplanes) == 4
    for H in br.hyperplanes:
        assert sp.simplify(hyperplane_rate(br, H, loss) - perron_root(restricted_transfer(br, H, loss))) == 0
    (H,) = [H for H in br.hyperplanes if [br.elements[i].sensor for i in H] == [0]][:1]
    if name == "iid":   # sensor 0 received at one phase: 1/10 (its other phase) * (1/4)^2 (sensor 1's two)
        assert hyperplane_rate(br, H, loss) == R(1, 10) * R(1, 16)


@pytest.mark.parametrize("name", MODELS)
def test_channel_fail_is_asked_of_the_model(name, capsys):
    """``critical --vary recovery`` asks the model for its channels' fail rates: Gilbert-Elliott
    channels give theirs, every other model None (and the command says what it needs)."""
    loss = MODELS[name]()
    assert loss.channel_fail == ((R(1, 10), R(1, 3)) if name.startswith("gilbert") else None)
    S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]]), sk.Sensor(C=[[1, 1]])])
    if loss.channel_fail is None:
        with pytest.raises(cli.UsageError, match="needs Gilbert-Elliott channels.*not " + loss.words()[:12]):
            cli.VARY["recovery"](S, loss, "", "f.toml")
    else:
        key, value, _ = cli.VARY["recovery"](S, loss, "", "f.toml")
        assert key == "critical_recovery_rate" and value == sk.critical_recovery_rate(S, fail=["1/10", "1/3"])


@pytest.mark.parametrize("name", MODELS)
def test_channel_recover_is_asked_of_the_model(name):
    """``critical --vary recovery=NAME`` holds the other channels' recovery at the model's:
    Gilbert-Elliott channels give theirs, every other model None; parts and selections pass them on."""
    assert MODELS[name]().channel_recover == ((R(1, 2), R(1, 5)) if name.startswith("gilbert") else None)
    parts = Independent([GilbertElliott(["1/4"], ["1/3"]), GilbertElliott(["1/4", "1/5"], ["1/2", "2/3"])])
    assert parts.channel_recover == (R(1, 3), R(1, 2), R(2, 3))
    assert sk.Selected(parts, [0, 2]).channel_recover == (R(1, 3), R(2, 3))


# -- independent parts: groups of sensors on channels of their own ---------------------------

def _pair_of(ge: GilbertElliott) -> MarkovLoss:
    """The joint chain of two independent Gilbert-Elliott channels, as one MarkovLoss."""
    v = [(1, 1), (1, 0), (0, 1), (0, 0)]
    P = [ge.sensor_matrix(0), ge.sensor_matrix(1)]
    return MarkovLoss({a: {b: P[0][1 - a[0], 1 - b[0]] * P[1][1 - a[1], 1 - b[1]] for b in v} for a in v})


def test_paired_channels_example_by_hand():
    """The shipped example: 24/25 per step, derived in its comments ((P^2)[00, 00] = 6/25 per pair)."""
    S, loss = files.load(examples.system("paired-channels"))
    assert isinstance(loss, Independent) and [f.sensors for f in loss.factors] == [(0, 1), (2, 3)]
    v = sk.stability(S, loss)
    assert v.stable and v.margins[0].exact == R(24, 25) and v.certificate[0].margin_power == R(576, 625)
    assert set(v.certificate[0].decisive_elements) in ({("x1", 0), ("x2", 0), ("y1", 1), ("y2", 1)},
                                                       {("x1", 1), ("x2", 1), ("y1", 0), ("y2", 0)})


def test_independent_pairs_are_the_sensors_channels():
    """Sixteen sensors on the period-24 block, in eight pairs whose joint chains are products of two
    Gilbert-Elliott channels: the same law as sixteen independent channels, so the same exact
    margins, through joint factors of four states instead of two-state ones; the joint chain of all
    sixteen (4^8 states) is never built."""
    rng = np.random.default_rng(5)
    A = sp.diag(2 * sp.Matrix([[sp.sqrt(3) / 2, -R(1, 2)], [R(1, 2), sp.sqrt(3) / 2]]),
                2 * sp.Matrix([[sp.sqrt(2) / 2, -sp.sqrt(2) / 2], [sp.sqrt(2) / 2, sp.sqrt(2) / 2]]))
    rows = [[int(x) for x in rng.integers(-2, 3, 4)] for _ in range(16)]
    fail = [R(1, 10 + j % 3) for j in range(16)]
    recover = [R(1, 2 + j % 2) for j in range(16)]
    ge = GilbertElliott(fail, recover)
    pairs = Independent([_pair_of(GilbertElliott(fail[j:j + 2], recover[j:j + 2])) for j in range(0, 16, 2)])
    S1, S2 = (sk.System(A=A, sensors=[sk.Sensor(C=[r]) for r in rows]) for _ in range(2))
    a, b = sk.stability(S1, ge), sk.stability(S2, pairs)
    assert a.margins[0] == b.margins[0] and a.stable == b.stable
    assert "chain" not in pairs.__dict__ and len(pairs.factors) == 8


def test_independent_pairs_equal_the_joint_chain():
    """Two correlated pairs on 2R(pi/3) (period 3): the Markov search over the two pair chains equals
    the first maximum over every hyperplane of the joint chain's restricted transfer (16 states,
    built here only as the reference)."""
    from symkf.engine.rates import perron_root, restricted_transfer
    from symkf.engine.search import block_rate
    from symkf.exact.algebraic import AlgebraicNumber
    pair = MarkovLoss({(1, 1): {(1, 1): "4/5", (1, 0): "1/20", (0, 1): "1/20", (0, 0): "1/10"},
                       (1, 0): {(1, 1): "1/2", (1, 0): "1/5", (0, 1): "1/10", (0, 0): "1/5"},
                       (0, 1): {(1, 1): "1/2", (1, 0): "1/10", (0, 1): "1/5", (0, 0): "1/5"},
                       (0, 0): {(1, 1): "2/5", (1, 0): "1/10", (0, 1): "1/10", (0, 0): "2/5"}})
    loss = Independent([pair, markov()])
    A = 2 * sp.Matrix([[R(1, 2), -sp.sqrt(3) / 2], [sp.sqrt(3) / 2, R(1, 2)]])
    rows = ([1, 0], [0, 1], [1, 1], [1, -1])
    (br,), (full,) = (block_rows(sk.System(A=A, sensors=[sk.Sensor(C=[r]) for r in rows])) for _ in range(2))
    got = block_rate(br, loss)
    best = None
    for H in full.hyperplanes:
        v = AlgebraicNumber.from_expr(perron_root(restricted_transfer(full, H, loss)))
        if best is None or v > best[1]:
            best = (H, v)
    assert got.hyperplane == best[0] and sp.simplify(got.per_period - best[1].exact) == 0


def test_independent_parts_are_checked_and_refused_in_one_line(tmp_path):
    with pytest.raises(InputError, match=r"argument 'parts' must be a list or tuple of a LossModel"):
        Independent([IID(["1/2"]), "1/2"])
    with pytest.raises(InputError, match="at least one"):
        Independent([])
    bad = Independent([GilbertElliott(["1/10"], ["0"]), IID(["1/4"])])
    with pytest.raises(AssumptionError, match=r"part 0 \(sensors 0 to 0\): recover\[0\] = 0"):
        checked(bad, positive=True)
    nested = Independent([Independent([IID(["1/4"])]), IID(["1/5"])])
    assert len(nested.parts) == 2 and nested.bernoulli == (R(1, 4), R(1, 5))
    path = tmp_path / "s.toml"
    path.write_text('[system]\nA = [["2"]]\n[[sensors]]\nC = [["1"]]\n[loss]\nkind = "independent"\n'
                    '[[loss.parts]]\nkind = "iid"\nloss = ["1/2"]\n', encoding="utf-8")
    with pytest.raises(sk.errors.FileFormatError, match=r"\[loss\] parts\[0\]: missing key 'sensors'"):
        files.load(path)
    deep = {"kind": "iid", "loss": ["1/2"]}
    for _ in range(3000):   # a JSON object nested past Python's recursion limit: one line, no RecursionError
        deep = {"kind": "independent", "parts": [{"sensors": 1, **deep}]}
    with pytest.raises(sk.errors.FileFormatError, match=r"parts\[0\]: kind 'independent' cannot be a part"):
        from_table(deep, 1)

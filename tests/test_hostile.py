"""Hostile input (issue 17): no code execution through any entry point, and the one safe parser.

Every payload, if it ran, would create the file ``MARK`` (in a temporary directory): the tests
assert that it never exists and that the entry point answers with symkf's InputError.
"""

from __future__ import annotations

import itertools
import re
from pathlib import Path

import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

import symkf as sk
from symkf import budget
from symkf.errors import BudgetError, InputError, SymkfError
from symkf.exact.numbers import parse_exact

#: code that would create ``{mark}`` if any part of it were evaluated as Python or by sympify
PAYLOADS = (
    "__import__('os').system('touch {mark}')",
    "open('{mark}', 'w')",
    "sqrt.__globals__['__builtins__']['open']('{mark}', 'w')",
    "cos.__init__.__globals__['__builtins__']['exec'](\"open('{mark}','w')\")",
    "exec(\"open('{mark}','w')\")",
    "eval(\"open('{mark}','w')\")",
    "().__class__.__base__.__subclasses__()",
    "Symbol('x').__class__.__mro__",
    "[open('{mark}', 'w') for x in (1,)]",
    "(lambda: open('{mark}', 'w'))()",
    "sympify(\"open('{mark}','w')\")",
    "S(\"open('{mark}','w')\")",
    "1 if open('{mark}', 'w') else 0",
    "__builtins__",
    "sqrt(*[open('{mark}', 'w')])",
    "root(2, n=open('{mark}', 'w'))",
    "Rational(1, 2).__class__",
    "Integer(1)",
    "x.y",
    "2 @ 3",
)


@pytest.fixture
def mark(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # a payload writing a relative path would land here
    return tmp_path / "MARK"


def payloads(mark: Path) -> list[str]:
    return [p.format(mark=mark) for p in PAYLOADS]


def _system():
    return sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="s1"), sk.Sensor(C=[[1, 1]], name="s2")])


def _entry_points():
    """The 13 library entry points of issue 17, each taking the payload as its one string."""
    from symkf.reports import plots
    from symkf import second_order
    from symkf.network import fading
    S = _system()
    region = sk.stability_region(S) if hasattr(sk, "stability_region") else None
    from symkf.engine.region import stability_region
    region = stability_region(S)
    S2 = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]])])
    cs = second_order.congruent_sets(S2)
    return {
        "IID": lambda p: sk.IID([p]),
        "GilbertElliott fail": lambda p: sk.GilbertElliott([p], ["1/2"]),
        "GilbertElliott recover": lambda p: sk.GilbertElliott(["1/2"], [p]),
        "MarkovLoss": lambda p: sk.MarkovLoss({(1,): {(1,): p, (0,): "1/2"}, (0,): {(1,): "1/2", (0,): "1/2"}}),
        "StabilityRegion.contains": lambda p: region.contains(p, "1/2"),
        "StabilityRegion.conditions": lambda p: region.conditions([p, "1/2"]),
        "StabilityRegion.boundary_at": lambda p: region.boundary_at(p),
        "plots.rotation_system scale": lambda p: plots.rotation_system(p, "pi/2"),
        "plots.rotation_system angle": lambda p: plots.rotation_system("2", p),
        "plots.critical_angle_figure": lambda p: plots.critical_angle_figure(p),
        "fading.Rayleigh": lambda p: fading.Rayleigh(p),
        "fading.Nakagami": lambda p: fading.Nakagami(p, 1),
        "congruent_sets.p_star": lambda p: cs.p_star([p]),
        # beyond the issue's 13: everything else that reads a number from a string
        "System A": lambda p: sk.System(A=[[p]], sensors=[sk.Sensor(C=[[1]])]),
        "Sensor C": lambda p: sk.Sensor(C=[[p]]),
        "IID.subs value": lambda p: sk.IID(["e"]).subs({"e": p}),
        "IID.subs key": lambda p: sk.IID(["e"]).subs({p: "1/2"}),
        "AlgebraicNumber.from_expr": lambda p: sk.AlgebraicNumber.from_expr(p),
        "critical_loss_rate others": lambda p: sk.critical_loss_rate(S, "s1", others=["1/2", p]),
    }


ENTRY_NAMES = list(_entry_points())


@pytest.mark.parametrize("name", ENTRY_NAMES)
def test_payloads_never_run_and_are_input_errors(mark, name):
    call = _entry_points()[name]
    for payload in payloads(mark):
        with pytest.raises(InputError):
            call(payload)
        assert not mark.exists(), f"{name} ran {payload!r}"


# ---- no string evaluator in symkf (the walk over every public callable: test_payload_walk.py) --

def test_no_string_evaluation_left_in_symkf():
    """sympy's sympify/S/parse_expr/nsimplify (which evaluate strings, also inside containers)
    and Python's eval/exec appear nowhere in symkf: outside data reaches sympy through
    symkf.exact.numbers, which calls none of them."""
    root = Path(sk.__file__).parent
    banned = ("parse_expr", "eval(", "exec(", "sp.S(", "sympy.S(", "sp.sympify", "sympy.sympify",
              "from sympy import sympify", "nsimplify(", "kernS")
    offenders = []
    for path in root.rglob("*.py"):
        for i, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            code = re.sub(r"``.*?``", "", line.split("#")[0]).replace("evalf(", "").replace("literal_eval(", "")
            if any(t in code for t in banned):
                offenders.append(f"{path.relative_to(root)}:{i}: {line.strip()}")
    assert offenders == []


# ---- the grammar ---------------------------------------------------------------------------

#: strings of the grammar, built from its pieces, each with the value sympy gives the same
#: expression built from trusted sympy objects (no string reaches sympy's own parser)
_ATOMS = st.one_of(st.integers(0, 10 ** 6).map(lambda k: (str(k), sp.Integer(k))),
                   st.sampled_from([("0.5", sp.Rational(1, 2)), ("1e-3", sp.Rational(1, 1000)),
                                    ("2.25", sp.Rational(9, 4)), (".75", sp.Rational(3, 4)), ("pi", sp.pi), ("I", sp.I)]),
                   st.fractions(min_value=-100, max_value=100, max_denominator=50).map(
                       lambda f: (f"({f})", sp.Rational(f.numerator, f.denominator))))

_OPS = {"+": lambda a, b: a + b, "-": lambda a, b: a - b, "*": lambda a, b: a * b,
        "/": lambda a, b: a / b if b != 0 else sp.zoo}


def _grow(children):
    return st.one_of(
        st.tuples(children, st.sampled_from(list(_OPS)), children).map(
            lambda t: (f"({t[0][0]}{t[1]}{t[2][0]})", _OPS[t[1]](t[0][1], t[2][1]))),
        children.map(lambda c: (f"sqrt({c[0]})", sp.sqrt(c[1]))),
        st.tuples(children, st.integers(-3, 3)).map(
            lambda t: (f"({t[0][0]})^{t[1]}", t[0][1] ** t[1] if t[0][1] != 0 or t[1] >= 0 else sp.zoo)),
        st.tuples(st.integers(-12, 12), st.integers(1, 12), st.sampled_from(["cos", "sin"])).map(
            lambda t: (f"{t[2]}({t[0]}*pi/{t[1]})", getattr(sp, t[2])(t[0] * sp.pi / t[1]))),
        st.tuples(st.integers(-12, 12), st.integers(1, 12)).map(
            lambda t: (f"exp({t[0]}*pi*I/{t[1]})", sp.exp(t[0] * sp.pi * sp.I / t[1]))))


GRAMMAR = st.recursive(_ATOMS, _grow, max_leaves=6)


@settings(max_examples=150, deadline=None)
@given(GRAMMAR)
def test_grammar_strings_parse_exactly_or_are_refused_cleanly(case):
    """Strings of the grammar give the same value as sympy's own evaluation of the same
    (trusted) expression, or a clear refusal: a budget cap or division by zero."""
    text, trusted = case
    try:
        value = parse_exact(text, "x")
    except BudgetError:
        return
    except InputError as exc:
        assert "division by zero" in str(exc) or "exponent" in str(exc), exc
        return
    if trusted.has(sp.zoo, sp.nan):
        return
    assert sp.simplify(value - trusted) == 0 or abs(complex(sp.N(value - trusted, 30))) < 1e-25


@settings(max_examples=300, deadline=None)
@given(st.text(alphabet=st.sampled_from(list("0123456789.+-*/^()eEjIpisqrtcoxn_,[]{}'\"=<>!@#$%&|~;: \\\n")),
               max_size=40))
def test_strings_outside_the_grammar_are_input_errors(text):
    """Any string: an exact value or InputError, nothing else escapes."""
    try:
        value = parse_exact(text, "x", symbols=True)
    except InputError:
        return
    assert isinstance(value, sp.Expr) and not value.has(sp.Float)


# ---- budgets -------------------------------------------------------------------------------

@pytest.mark.parametrize("text, cap", [
    ("exp(2*pi*I/99991)", "max_angle_denominator"),
    ("sqrt(" * 20 + "2" + ")" * 20, "max_nesting"),
    ("root(2, 99999)", "max_degree"),
    ("root(2, 10**12)", "max_degree"),
    ("cos(pi/1000000007)", "max_angle_denominator"),
    ("+".join(f"sqrt({p})" for p in (2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37)), "max_degree"),
    ("9^9^9", "max_exponent"),
    ("1e999999", "max_digits"),
])
def test_issue_hangs_are_refused_at_once_naming_the_option(text, cap):
    """Each of these ran past 85 CPU-s, to gigabytes, or aborted the interpreter inside FLINT."""
    for call in (lambda: sk.IID([text]), lambda: sk.System(A=[[text]], sensors=[sk.Sensor(C=[[1]])])):
        with pytest.raises(BudgetError, match=budget.OPTIONS[cap]):
            call()


def test_long_number_text_is_refused_naming_the_cap_and_its_option():
    """"1+1+...+1" with 501 ones is 1001 characters: above max_number_length (1000) before it is
    parsed; with the cap raised it parses to 501."""
    text = "+".join(["1"] * 501)
    with pytest.raises(BudgetError, match=r"x: the length of the number's text \(characters\) is 1001, "
                                          r"above the cap 1000; .*max_number_length=.*--max-number-length"):
        parse_exact(text, "x")
    with budget.limits(max_number_length=1001):
        assert parse_exact(text, "x") == 501


def test_caps_can_be_raised_and_are_restored():
    """sum of 7 square roots of primes: degree 2^7 = 128 > 64 (default); with the cap raised it
    parses (and the cap returns to its default after the block)."""
    text = "+".join(f"sqrt({p})" for p in (2, 3, 5, 7, 11, 13, 17))
    with pytest.raises(BudgetError, match="is 128, above the cap 64"):
        parse_exact(text, "x")
    with budget.limits(max_degree=128):
        assert parse_exact(text, "x") == sum(sp.sqrt(p) for p in (2, 3, 5, 7, 11, 13, 17))
    assert budget.LIMITS.max_degree == 64


def test_sympy_input_is_budgeted_too():
    with pytest.raises(BudgetError, match="--max-angle-denominator"):
        sk.System(A=[[sp.cos(sp.pi / 1000000007)]], sensors=[sk.Sensor(C=[[1]])])


@pytest.mark.parametrize("build, option", [
    (lambda: sk.System(A=[[2]], sensors=[sk.Sensor(C=[[1]]) for _ in range(65)]), "--max-sensors"),
    (lambda: sk.System(A=[[1 if i == j else 0 for j in range(1000)] for i in range(1000)],
                       sensors=[sk.Sensor(C=[[1] * 1000])]), "--max-dimension"),
    (lambda: sk.IID(["1/2"] * 65), "--max-sensors"),
    (lambda: sk.MarkovLoss({h: {(0,): "1/2", (1,): "1/2"} for h in itertools.product([(0,), (1,)], repeat=8)},
                           order=8), "--max-markov-states"),
])
def test_large_inputs_refused_early(build, option):
    with pytest.raises(BudgetError, match=option):
        build()


def test_loss_above_one_refused_before_evaluation():
    """root(2, 3) > 1 is not a probability: refused with the value, without a hang."""
    with pytest.raises(sk.errors.ProbabilityError, match="not a probability"):
        sk.IID(["root(2, 3)"])


def test_not_algebraic_loss_is_an_input_error():
    """cos(pi*sqrt(2)) is transcendental: refused by the parser, in a loss as in A."""
    for call in (lambda: sk.IID(["cos(pi*sqrt(2))"]), lambda: sk.System(A=[["cos(pi*sqrt(2))"]], sensors=[sk.Sensor(C=[[1]])])):
        with pytest.raises(InputError, match="rational multiple of pi"):
            call()


def test_symbol_errors_are_symkf_errors():
    assert issubclass(BudgetError, SymkfError)


def test_field_of_a_matrix_is_budgeted_per_diagonal_block():
    """Six distinct square roots on a diagonal: six 1x1 blocks, each decided in its own field of
    degree 2, so the system is accepted; its critical loss rate is 1/13 (one sensor sees every
    mode; the largest |lambda|^2 = 13 decides: 13 * loss < 1).  Coupled by a superdiagonal of
    ones the six form one triangular block, whose eigenvalues are still its diagonal entries: the
    entries' field of degree 2^6 = 64 is the cap, and the value is the same.  Closed into a cycle
    (a one in the corner) the block is not triangular: the entries' field 64 times size 6 is 384 > 64.
    A rotation by pi/7 (cos and sin in Q(zeta_28), phi(28) = 12) is a rotation block of cyclotomic
    degree 12."""
    primes = (2, 3, 5, 7, 11, 13)
    for coupling in (0, 1):
        S = sk.System([[f"sqrt({p})" if i == j else coupling * int(j == i + 1) for j in range(6)]
                       for i, p in enumerate(primes)], [sk.Sensor([[1] * 6])])
        assert sk.critical_loss_rate(S).exact == sp.Rational(1, 13)
    with pytest.raises(BudgetError, match=r"diagonal block rows 1-6 .* is 384, above the cap 64.*--max-degree"):
        sk.System([[f"sqrt({p})" if i == j else int(j == (i + 1) % 6) for j in range(6)] for i, p in enumerate(primes)],
                  [sk.Sensor([[1] * 6])])
    S = sk.System([["2*cos(pi/7)", "-2*sin(pi/7)"], ["2*sin(pi/7)", "2*cos(pi/7)"]], [sk.Sensor([[1, 0]])])
    assert S.n == 2


def test_cyclotomic_rotations_pass_the_default_caps():
    """Rotation blocks of trigonometric constants stay in Q(zeta_m) (m = 4q): 2R(2 pi/97) has
    cyclotomic degree phi(388) = 192 <= 1024 and is decided, to the value the engine gave before the
    cost model with --max-degree raised (2^(192/193)/4), as is 2R(2 pi/401) (phi(1604) = 800,
    2^(800/801)/4); 2R(2 pi/521) has phi(2084) = 1040 > 1024.  A 1x1 cos(pi/97)
    is its own eigenvalue (real, modulus cos(pi/97) < 1: stable for every loss rate).  The same
    constants off the rotation pattern give eigenvalues of degree up to 2 * 192 in a generic
    extension: refused under max_degree, at once."""
    rot = lambda t: [[f"2*cos({t})", f"-2*sin({t})"], [f"2*sin({t})", f"2*cos({t})"]]  # noqa: E731
    S = sk.System(rot("2*pi/97"), [sk.Sensor([[1, 0]]), sk.Sensor([[0, 1]])])
    assert sk.critical_loss_rate(S).exact == 2 ** sp.Rational(192, 193) / 4
    S = sk.System(rot("2*pi/401"), [sk.Sensor([[1, 0]]), sk.Sensor([[0, 1]])])
    assert sk.critical_loss_rate(S).exact == 2 ** sp.Rational(800, 801) / 4
    with pytest.raises(BudgetError, match="is 1040, above the cap 1024.*--max-cyclotomic-degree"):
        sk.System(rot("2*pi/521"), [sk.Sensor([[1, 0]])])
    assert sk.critical_loss_rate(sk.System([["cos(pi/97)"]], [sk.Sensor([[1]])])).exact == 1
    with pytest.raises(BudgetError, match="is 384, above the cap 64.*--max-degree"):
        sk.System([["cos(2*pi/97)", 1], [1, "sin(2*pi/97)"]], [sk.Sensor([[1, 0]])])
    # +-i cos(pi/97): a complex eigenvalue of degree 96 whose squared modulus cos(pi/97)^2 is
    # irrational, so |lambda| needs a resultant of degree 2 * 96^2: generic, refused
    with pytest.raises(BudgetError, match="is 384, above the cap 64.*--max-degree"):
        sk.System([[0, "-cos(pi/97)"], ["cos(pi/97)", 0]], [sk.Sensor([[1, 0]])])


def test_family_members_budgeted(tmp_path):
    """A family of 10^4 members is refused when read, before any member is built."""
    from symkf.io.families import load_family
    path = tmp_path / "big.toml"
    path.write_text('[family]\n[grid]\na = { from = 1, to = 1000 }\nb = { from = 1, to = 10 }\n'
                    '[system]\nA = [["a", "b"], ["0", "2"]]\n[[sensors]]\nC = [["1", "1"]]\n')
    with pytest.raises(BudgetError, match="number of family members is 10000, above the cap 2000.*--max-members"):
        load_family(path)

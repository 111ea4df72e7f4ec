"""No code execution through any entry point: every payload, if it ran, would create the file
``MARK`` (in a temporary directory); the tests assert that it never exists and that the entry
point answers with symkf's InputError, and that no string evaluator (sympify, parse_expr, eval,
exec, ...) is left in symkf.  (Every public callable and parameter: tests/test_payload_walk.py.)"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import symkf as sk
from symkf.errors import InputError

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
    """Thirteen library entry points that read a number from a string, and beyond them everything else
    that does, each taking the payload as its one string."""
    from symkf import second_order
    from symkf.network import fading
    from symkf.reports import plots
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
        # beyond those 13: everything else that reads a number from a string
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

"""The payload walk: every public callable of symkf, every parameter, ten input forms.

Each call passes a payload that would create the file ``MARK`` (in a temporary directory) if
any part of it were evaluated as Python, in one of :data:`FORMS` (a bare string, containers of
it, a numpy object array, objects whose dunder methods return it), in the target parameter and
in every required one.  The walk asserts

* no marker file (no execution) and no call reaching sympy's string evaluator (the session
  guard of ``conftest.py`` turns that into :class:`conftest.StringEvaluation`);
* no untranslated exception.  The rule: a public callable given bad input raises a
  :class:`symkf.errors.SymkfError` (which names the argument); nothing else counts as an answer.
  Exempt by contract: ``KeyboardInterrupt`` (never raised by a payload), ``SystemExit`` from
  ``symkf.cli.main``'s argument parser (the command line's exit status), and hypothesis's
  ``InvalidArgument`` from :mod:`symkf.model.strategies` (the contract of a hypothesis strategy's
  arguments; its message names the argument).  A call that
  runs out of its CPU budget (:data:`CPU_PER_CALL`: a payload was accepted as legitimate data
  by a parameter that takes anything, and real work started) is a skip, counted and reported.

The full walk (every callable x parameter x form x payload) runs in the ``full`` tier; the fast
tier walks a deterministic sample: every callable, each parameter with one form (rotating).
"""

from __future__ import annotations

import collections
import functools
import importlib
import inspect
import pkgutil
import signal
import sys
import time
import traceback
import zlib
from fractions import Fraction
from pathlib import Path
from typing import Any, Callable

import numpy as np
import pytest
import sympy as sp

import symkf as sk
from symkf.errors import SymkfError
from symkf.model.loss import LossChain

from conftest import ORIGINAL, StringEvaluation

#: code that would create ``{mark}`` if evaluated as Python (by sympify or eval)
PAYLOADS = (
    "__import__('os').system('touch {mark}')",
    "open('{mark}', 'w')",
)


class StrPayload:
    """An object that prints as the payload."""

    def __init__(self, payload: str):
        self.payload = payload

    def __str__(self) -> str:
        return self.payload

    __repr__ = __str__

    def __format__(self, spec: str) -> str:
        return self.payload


class NumberPayload:
    """An object that claims to be a number and returns the payload when asked for one."""

    def __init__(self, payload: str):
        self.payload = payload

    def __float__(self):
        return self.payload

    __index__ = __int__ = __complex__ = __float__


#: the ten input forms
FORMS: dict[str, Callable[[str], Any]] = {
    "string": lambda p: p,
    "list": lambda p: [p, p],
    "nested list": lambda p: [[p, p], [p, p]],
    "tuple": lambda p: (p, p),
    "dict": lambda p: {p: p, "x": p},
    "set": lambda p: {p},
    "numpy object array": lambda p: np.array([[p, p], [p, p]], dtype=object),
    "str/repr/format object": StrPayload,
    "float/index object": NumberPayload,
    "nested mix": lambda p: {"k": (frozenset({p}), [p, {p: (p,)}])},
}

#: CPU seconds one call may take before it is stopped and counted as a skip
CPU_PER_CALL = 1.0


def _system() -> sk.System:
    return sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="s1"), sk.Sensor(C=[[1, 1]], name="s2")])


def _samples() -> dict[type, Callable[[], Any]]:
    """A valid instance of each class whose methods the walk calls, built on first use."""
    from symkf import examples, montecarlo, output, second_order, tables
    from symkf.io import families
    from symkf.engine import oracle, region, rows as observability
    from symkf.engine.blocks import block_rows
    from symkf.exact import spectral
    from symkf.model import strategies
    from symkf.capacity import mare, theorems
    from symkf.exact import algebraic, field
    from symkf.fusion import covariance, model as fmodel, pendulum, remote
    from symkf.fusion.local_filters import LocalFilters, local_filters
    from symkf.network import compare, dynamics, fading, loss as nloss, state, tree
    S = _system()
    iid = lambda: sk.IID(["1/10", "1/5"])  # noqa: E731
    ge = lambda: sk.GilbertElliott(["1/20", "1/20"], ["1/2", "1/2"])  # noqa: E731
    lf = lambda: local_filters(pendulum.pendulum_model())  # noqa: E731
    markov = lambda: state.MarkovNetworkState([["9/10", "1/10"], ["3/10", "7/10"]])  # noqa: E731
    return {
        sk.System: _system, sk.IID: iid, sk.GilbertElliott: ge,
        sk.MarkovLoss: lambda: sk.MarkovLoss({(1,): {(1,): "1/2", (0,): "1/2"}, (0,): {(1,): "1/2", (0,): "1/2"}}),
        LossChain: lambda: iid().chain,
        algebraic.AlgebraicNumber: lambda: algebraic.AlgebraicNumber.from_expr(sp.sqrt(2)),
        field.NumberField: lambda: field.NumberField([sp.sqrt(2)]),
        region.StabilityRegion: lambda: region.stability_region(S),
        region.Constraint: lambda: region.stability_region(S).constraints[0],
        second_order.CongruentSets: lambda: second_order.congruent_sets(
            sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]])])),
        oracle.RawRegression: lambda: oracle.RawRegression(S.A, [s.C for s in S.sensors], 2),
        observability.BlockRows: lambda: block_rows(S)[0],
        spectral.Eigenvalue: lambda: spectral.eigenvalues(S.A)[0],
        mare.MARE: lambda: mare.MARE(S, iid()),
        theorems.WonhamDecomposition: lambda: theorems.wonham_decomposition(S),
        families.Family: lambda: families.load_family(examples.family("rotation-periods")),
        families.Member: lambda: families.load_family(examples.family("rotation-periods")).members[0],
        tables.Table: lambda: tables.family_table(examples.family("rotation-periods")),
        tables.Cell: lambda: tables.Cell.text("a"),
        montecarlo.BurstPlan: lambda: montecarlo.verdict_plan(S, sk.stability(S, iid())),
        montecarlo.TraceEstimate: lambda: montecarlo.estimate_mean_trace(S, iid(), 3, 4, seed=1),
        montecarlo.MeanTraceCurve: lambda: montecarlo.mean_trace_curve(S, iid(), 3, 4, seed=1),
        output.Planned: lambda: output.plan(Path("walk-out.txt"), "--out"),
        strategies.Rotation: lambda: strategies.Rotation(S, sp.Integer(2), Fraction(1, 4)),
        fmodel.FusionModel: pendulum.pendulum_model,
        LocalFilters: lf,
        covariance.HoldingTimeCovariance: lambda: covariance.HoldingTimeCovariance(lf()),
        remote.RemoteFusion: lambda: remote.RemoteFusion(lf()),
        tree.SensorTree: lambda: tree.SensorTree([0, 1]),
        dynamics.PeriodicDynamics: lambda: dynamics.PeriodicDynamics.from_system(S),
        state.MarkovNetworkState: markov,
        state.SemiMarkovNetworkState: lambda: state.SemiMarkovNetworkState(
            [["0", "1"], ["1", "0"]], [{1: "1"}, {1: "1/2", 2: "1/2"}]),
        nloss.NetworkLoss: lambda: nloss.NetworkLoss(tree.SensorTree([0, 1]), markov(), [["1/2", "1/2"]] * 2),
        compare.NetworkExample: lambda: compare.example("iid-scalar"),
        fading.Rayleigh: lambda: fading.Rayleigh(1),
        fading.Nakagami: lambda: fading.Nakagami(1, 1),
        fading.Rician: lambda: fading.Rician(1, 1),
        fading.UserGain: lambda: fading.UserGain(lambda g: sp.exp(-g), lambda g: sp.exp(-g)),
    }


def public_callables() -> list[tuple[str, Callable]]:
    """(qualified name, callable): every public function and class of every symkf module, and
    the public methods, class methods and static methods of each class (bound to a sample
    instance where the walk has one, see :func:`_samples`)."""
    samples = _samples()
    seen, out = set(), []
    for info in pkgutil.walk_packages(sk.__path__, "symkf."):
        if info.name.endswith("__main__"):
            continue
        module = importlib.import_module(info.name)
        for name, obj in vars(module).items():
            if name.startswith("_") or not callable(obj) or getattr(obj, "__module__", "") != module.__name__:
                continue
            if id(obj) in seen or isinstance(obj, type) and issubclass(obj, BaseException):
                continue
            seen.add(id(obj))
            qual = f"{module.__name__}.{name}"
            out.append((qual, obj))
            if not isinstance(obj, type):
                continue
            instance = None
            for attr, member in vars(obj).items():
                if attr.startswith("_"):
                    continue
                if isinstance(member, (classmethod, staticmethod)):
                    out.append((f"{qual}.{attr}", getattr(obj, attr)))
                elif inspect.isfunction(member) and obj in samples:
                    if instance is None:
                        instance = samples[obj]()
                    out.append((f"{qual}.{attr}", getattr(instance, attr)))
    return out


class _Timeout(BaseException):
    """Not an Exception: code under test that catches Exception cannot swallow it."""


#: whether a call is under the CPU timer: a profiling signal that arrives after the call (it counts
#: every thread's CPU, and a busy machine delays its handler) must not raise in the walk itself
_ARMED = False
#: whether the CPU timer fired during the current call: a C library that calls back into Python
#: (numpy promoting structured dtypes) replaces the :class:`_Timeout` raised there by an error of
#: its own, which is the timer's doing, not the code's
_FIRED = False


def _alarm(signum, frame):
    global _FIRED
    if not _ARMED:
        return
    _FIRED = True
    # re-armed first: a raise inside a weakref callback or __del__ is printed as unraisable and
    # lost, and the call would run on unbounded; the repeat comes 0.1 CPU-s later
    signal.setitimer(signal.ITIMER_PROF, 0.1)
    raise _Timeout


def _limited(call: Callable[[], Any], cpu: float) -> BaseException | None:
    """Run ``call`` under ``cpu`` CPU-seconds: None, the exception it raised, or a :class:`_Timeout`
    (also when the timer fired and another exception came out)."""
    global _ARMED, _FIRED
    _FIRED = False
    try:
        try:
            _ARMED = True
            signal.setitimer(signal.ITIMER_PROF, cpu)
            call()
        finally:
            _ARMED = False
            signal.setitimer(signal.ITIMER_PROF, 0)
    except BaseException as exc:  # noqa: BLE001 - the walks classify every outcome
        _ARMED = False
        signal.setitimer(signal.ITIMER_PROF, 0)
        return _Timeout() if _FIRED and not isinstance(exc, _Timeout) else exc
    return None


def _parameters(fn: Callable) -> list[inspect.Parameter] | None:
    try:
        return [p for p in inspect.signature(fn).parameters.values()
                if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY)]
    except (TypeError, ValueError):
        return None


def _call(fn: Callable, params: list[inspect.Parameter], target: inspect.Parameter, value: Any) -> None:
    """``fn`` with ``value`` in ``target`` and in every required parameter."""
    args, kwargs = [], {}
    for p in params:
        if p is not target and p.default is not p.empty:
            continue
        if p.kind == p.KEYWORD_ONLY:
            kwargs[p.name] = value
        else:
            args.append(value)
    fn(*args, **kwargs)


def _allowed(qualname: str, exc: BaseException) -> bool:
    from hypothesis.errors import InvalidArgument
    return isinstance(exc, (SymkfError, KeyboardInterrupt)) or \
        isinstance(exc, SystemExit) and qualname == "symkf.cli.main" or \
        isinstance(exc, InvalidArgument) and qualname.startswith("symkf.model.strategies.")


def walk(mark: Path, select: Callable[[str, str, str, int], bool]) -> dict:
    """Run the walk over the (callable, parameter, form, payload index) that ``select`` keeps;
    returns the figures and the findings."""
    callables = public_callables()
    for module in ("cvxpy", "control", "matplotlib.pyplot", "distributed"):  # no timer may stop an import halfway
        try:
            importlib.import_module(module)
        except ImportError:
            pass
    figures = collections.Counter()
    executions, reached, untranslated, skips = [], [], collections.Counter(), []
    examples: dict = {}
    walked = set()
    old = signal.signal(signal.SIGPROF, _alarm)
    t0 = time.process_time()
    try:
        for qualname, fn in callables:
            params = _parameters(fn)
            if params is None:
                continue
            figures["callables"] += 1
            figures["parameters"] += len(params)
            targets = params or [None]
            for target in targets:
                for form, make in FORMS.items():
                    for k, payload in enumerate(PAYLOADS):
                        if not select(qualname, target.name if target else "", form, k):
                            continue
                        walked.add(qualname)
                        value = make(payload.format(mark=mark))
                        figures["calls"] += 1
                        exc = _limited(lambda: _call(fn, params, target, value) if target else fn(), CPU_PER_CALL)
                        if isinstance(exc, _Timeout):
                            skips.append(f"{qualname}({target.name if target else ''}) {form}")
                        elif isinstance(exc, StringEvaluation):
                            reached.append(f"{qualname}({target.name}) {form}")
                        elif exc is not None and not _allowed(qualname, exc):
                            key = (qualname, target.name if target else "", type(exc).__name__)
                            untranslated[key] += 1
                            examples.setdefault(key, f"{form}: {str(exc)[:160]}")
                        if mark.exists():
                            executions.append(f"{qualname}({target.name}) {form}")
                            mark.unlink()
    finally:
        signal.signal(signal.SIGPROF, old)
    figures["walked callables"] = len(walked)
    figures["forms"] = len(FORMS)
    figures["payloads"] = len(PAYLOADS)
    figures["executions"] = len(executions)
    figures["string evaluations reached"] = len(reached)
    figures["untranslated"] = sum(untranslated.values())
    figures["skips"] = len(skips)
    figures["cpu"] = round(time.process_time() - t0, 1)
    return {"figures": figures, "executions": executions, "reached": reached, "untranslated": untranslated,
            "examples": examples, "skips": skips}


def _report(result: dict) -> str:
    lines = [", ".join(f"{k} {v}" for k, v in result["figures"].items())]
    lines += [f"EXECUTED {e}" for e in result["executions"]]
    lines += [f"REACHED {e}" for e in result["reached"][:50]]
    lines += [f"{n} x {q}({p}) {t}: {result['examples'][(q, p, t)]}"
              for (q, p, t), n in sorted(result["untranslated"].items())]
    lines += [f"skip {s}" for s in result["skips"]]
    return "\n".join(lines)


@pytest.fixture
def mark(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # a payload writing a relative path, or an output, lands here
    return tmp_path / "MARK"


def _check(result: dict) -> None:
    print(_report(result))
    assert not result["executions"] and not result["reached"] and not result["untranslated"], _report(result)


def _sample(qualname: str, param: str, form: str, k: int) -> bool:
    """The fast tier's deterministic sample: the first payload, one form per parameter, rotating
    over the forms by a hash of the callable and parameter names."""
    names = list(FORMS)
    return k == 0 and names[zlib.crc32(f"{qualname}.{param}".encode()) % len(names)] == form


def test_walk_sample(mark):
    result = walk(mark, _sample)
    assert result["figures"]["callables"] > 400
    _check(result)


@pytest.mark.full
def test_walk_full(mark):
    result = walk(mark, lambda *_: True)
    _check(result)


# ------------------------------------------------------------------ hostile values

@functools.cache
def _deep(levels: int) -> list:
    """A list nested ``levels`` deep, built once (building and freeing it is most of a call's cost)."""
    value: list = []
    for _ in range(levels):
        value = [value]
    return value


#: values of the right shape of no parameter, each a class of input that once reached a raw Python
#: error, a C library's abort or a hang: non-finite numbers of every library, sizes past the machine's
#: integers, empty and nested containers, numbers priced like the text of the safe parser
HOSTILE: dict[str, Callable[[], Any]] = {
    "sympy oo": lambda: sp.oo, "sympy nan": lambda: sp.nan,
    "float nan": lambda: float("nan"), "float inf": lambda: float("inf"),
    "-1": lambda: -1, "0": lambda: 0, "numpy -5": lambda: np.int64(-5), "True": lambda: True, "None": lambda: None,
    "10**100": lambda: 10 ** 100, "2**63": lambda: 2 ** 63,
    "empty string": lambda: "", "bytes": lambda: b"\x00\xff", "object": object, "1+1j": lambda: 1 + 1j,
    "empty list": list, "empty array": lambda: np.zeros((0, 0)),
    "nan array": lambda: np.full((2, 2), np.nan), "list nested 10**5 deep": lambda: _deep(10 ** 5),
    "a million characters": lambda: "1" * 10 ** 6, "symbol": lambda: sp.Symbol("x"),
    "sum of ten radicals": lambda: sum(sp.sqrt(p) for p in (2, 3, 5, 7, 11, 13, 17, 19, 23, 29)),
    "10**(10**10)": lambda: sp.Pow(10, 10 ** 10, evaluate=False),
    "Fraction(1, 10**400)": lambda: Fraction(1, 10 ** 400), "fullwidth sqrt(2)": lambda: "ｓｑｒｔ(2)",
    "/dev/zero": lambda: Path("/dev/zero"),
}

#: CPU seconds a hostile value may run (it was accepted as data and real work started: a skip)
CPU_PER_HOSTILE = 0.3


def hostile_calls(qualname: str, fn: Callable, select: Callable[[str, str], bool]) -> dict:
    """Every parameter of ``fn`` with every :data:`HOSTILE` value that ``select(parameter, value
    name)`` keeps; the untranslated exceptions by (parameter, type), an example of each, the skips."""
    params = _parameters(fn)
    found, examples, skips, calls = collections.Counter(), {}, [], 0
    if params is None:
        return {"found": found, "examples": examples, "skips": skips, "calls": calls}
    old = signal.signal(signal.SIGPROF, _alarm)
    try:
        for target in params or [None]:
            name = target.name if target else ""
            for form, make in HOSTILE.items():
                if not select(f"{qualname}.{name}", form):
                    continue
                calls += 1
                exc = _limited(lambda: _call(fn, params, target, make()) if target else fn(), CPU_PER_HOSTILE)
                if isinstance(exc, _Timeout):
                    skips.append(f"{qualname}({name}) {form}")
                elif isinstance(exc, StringEvaluation):
                    found[(name, "string evaluation")] += 1
                elif exc is not None and not _allowed(qualname, exc):
                    found[(name, type(exc).__name__)] += 1
                    examples.setdefault((name, type(exc).__name__), f"{form}: {str(exc)[:160]} ({_raised_at(exc)})")
    finally:
        signal.signal(signal.SIGPROF, old)
    return {"found": found, "examples": examples, "skips": skips, "calls": calls}


def _raised_at(exc: BaseException) -> str:
    """Where ``exc`` was raised: the innermost frame of its traceback and the innermost in symkf."""
    frames = traceback.extract_tb(exc.__traceback__)
    if not frames:
        return "no traceback"
    ours = [f for f in frames if "/symkf/" in f.filename]
    shown = [frames[-1]] + ([ours[-1]] if ours and ours[-1] is not frames[-1] else [])
    return ", in ".join(f"{Path(f.filename).name}:{f.lineno} {f.name}" for f in shown)


#: wall seconds one callable may take in the forked walk before its child is counted as hung
HANG_SECONDS = 60


def _forked_calls(callables: list[tuple[str, Callable]], select: Callable[[str, str], bool]) -> list:
    """:func:`hostile_calls` of each callable in forked children, so that a death (a C library's
    abort, a segmentation fault) or a hang past :data:`HANG_SECONDS` is seen and counted instead of
    ending the walk: a child goes through the callables in turn, sending each one's result as it
    finishes (and leaves after a callable that left a thread running); after a death the next child
    starts at the callable that follows.  A finding counts only as it reproduces from a clean state:
    one made in a child that ran other callables before is made again in a child of its own, whose
    result replaces it.  ``(qualname, result)`` in order, the result a string for a death."""
    out, fresh = _children(callables, select, every=False)
    for i, (qualname, result) in enumerate(out):
        if not isinstance(result, str) and result.get("found") and i not in fresh:
            out[i] = _children([callables[i]], select, every=True)[0][0]
    return out


def _children(callables: list[tuple[str, Callable]], select: Callable[[str, str], bool],
              every: bool) -> tuple[list, set[int]]:
    """The forked runs of :func:`_forked_calls` (with ``every``, a child for each callable) and the
    indices of the callables that ran first in their child."""
    import os
    import pickle
    import struct
    import threading
    out, fresh, start = [], set(), 0
    while start < len(callables):
        fresh.add(start)
        read, write = os.pipe()
        pid = os.fork()
        if pid == 0:   # the child: report and leave without running the parent's clean-up
            os.close(read)
            with os.fdopen(write, "wb") as pipe:
                for i in range(start, len(callables)):
                    qualname, fn = callables[i]
                    try:
                        data = pickle.dumps(hostile_calls(qualname, fn, select))
                    except BaseException as exc:  # noqa: BLE001 - reported as the child's own failure
                        data = pickle.dumps({"failure": repr(exc)[:300]})
                    pipe.write(struct.pack("<Q", len(data)) + data)
                    pipe.flush()
                    if every or threading.active_count() > 1:   # a thread the call left running: a fresh child goes on
                        break
            os._exit(0)
        os.close(write)
        signal.signal(signal.SIGALRM, lambda *_: os.kill(pid, signal.SIGKILL))
        with os.fdopen(read, "rb") as pipe:
            while start < len(callables):
                signal.alarm(HANG_SECONDS)
                header = pipe.read(8)
                data = pipe.read(struct.unpack("<Q", header)[0]) if len(header) == 8 else b""
                signal.alarm(0)
                if not data:
                    break
                out.append((callables[start][0], pickle.loads(data)))
                start += 1
        _, status = os.waitpid(pid, 0)
        if start < len(callables) and not (os.WIFEXITED(status) and os.WEXITSTATUS(status) == 0):
            signal_number = os.WTERMSIG(status) if os.WIFSIGNALED(status) else "?"
            out.append((callables[start][0], f"ended by signal {signal_number}"))
            start += 1
    return out, fresh


def hostile_walk(prefix: str, select: Callable[[str, str], bool], forked: bool) -> dict:
    """:func:`hostile_calls` over every public callable whose name starts with ``prefix``; with
    ``forked``, in forked children (:func:`_forked_calls`)."""
    for module in ("cvxpy", "control", "matplotlib.pyplot", "distributed"):  # imported outside the CPU timer
        try:
            importlib.import_module(module)
        except ImportError:
            pass
    callables = [(qualname, fn) for qualname, fn in public_callables() if qualname.startswith(prefix)]
    results = _forked_calls(callables, select) if forked else \
        [(qualname, hostile_calls(qualname, fn, select)) for qualname, fn in callables]
    figures, lines, deaths = collections.Counter(callables=len(callables)), [], []
    for qualname, result in results:
        if isinstance(result, str):
            deaths.append(f"{qualname}: {result}")
            continue
        if "failure" in result:
            deaths.append(f"{qualname}: the walk itself failed: {result['failure']}")
            continue
        figures["calls"] += result["calls"]
        figures["skips"] += len(result["skips"])
        for (name, kind), count in sorted(result["found"].items()):
            figures["untranslated"] += count
            lines.append(f"{count} x {qualname}({name}) {kind}: {result['examples'].get((name, kind), '')}")
    figures["deaths"] = len(deaths)
    return {"figures": figures, "findings": lines, "deaths": deaths}


def _one_hostile_value(key: str, form: str) -> bool:
    """The fast tier's sample: one hostile value per parameter, rotating by a hash of its name."""
    names = list(HOSTILE)
    return names[zlib.crc32(key.encode()) % len(names)] == form


def _hostile_check(result: dict) -> None:
    report = "\n".join([", ".join(f"{k} {v}" for k, v in result["figures"].items()),
                        *[f"DEATH {d}" for d in result["deaths"]], *result["findings"]])
    print(report)
    assert not result["deaths"] and not result["findings"], report


def test_hostile_values_sample(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)   # an accepted path argument writes here
    result = hostile_walk("symkf.", _one_hostile_value, forked=False)
    assert result["figures"]["callables"] > 400
    _hostile_check(result)


#: the walk's share per subpackage, so that the full tier's workers take them in parallel
SUBPACKAGES = ("symkf.arguments", "symkf.budget", "symkf.cli", "symkf.errors", "symkf.output", "symkf.reproduction",
               "symkf.exact", "symkf.run", "symkf.model", "symkf.engine", "symkf.numeric", "symkf.network",
               "symkf.capacity", "symkf.fusion", "symkf.design", "symkf.control", "symkf.io", "symkf.reports", "symkf.bounds")


@pytest.mark.full
@pytest.mark.parametrize("prefix", SUBPACKAGES)
def test_hostile_values_everywhere(prefix, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    _hostile_check(hostile_walk(prefix, lambda *_: True, forked=True))


def test_the_forked_walk_counts_a_death_and_a_hang_and_goes_on_after_them_and_a_left_thread(monkeypatch):
    import faulthandler
    import os
    monkeypatch.setattr(sys.modules[__name__], "HANG_SECONDS", 1)

    def ok():
        return None

    def crash():
        faulthandler.disable()   # the child's own report of the fault is not this test's output
        os.kill(os.getpid(), signal.SIGSEGV)

    def hang():
        time.sleep(30)

    def thread():   # a thread left running: the next callable starts in a fresh child, no death
        import threading
        threading.Thread(target=time.sleep, args=(5,), daemon=True).start()

    results = _forked_calls([("ok1", ok), ("crash", crash), ("ok2", ok), ("hang", hang), ("thread", thread),
                             ("ok3", ok)], lambda key, form: form == "None")
    assert [q for q, _ in results] == ["ok1", "crash", "ok2", "hang", "thread", "ok3"]
    assert results[1][1] == f"ended by signal {int(signal.SIGSEGV)}"
    assert results[3][1] == f"ended by signal {int(signal.SIGKILL)}"
    assert [results[i][1]["calls"] for i in (0, 2, 4, 5)] == [1, 1, 1, 1]


def test_the_forked_walk_counts_a_finding_only_as_it_reproduces_in_a_child_of_its_own():
    state = []

    def leave_state():
        state.append(1)

    def fail_after_state():
        if state:
            raise RuntimeError("depends on an earlier call in the same child")

    def fail_always():
        raise RuntimeError("a finding")

    results = dict(_forked_calls([("leave", leave_state), ("after", fail_after_state), ("always", fail_always)],
                                 lambda key, form: form == "None"))
    assert not results["after"]["found"] and results["always"]["found"]
    assert results["always"]["examples"][("", "RuntimeError")] == \
        f"None: a finding (test_payload_walk.py:{fail_always.__code__.co_firstlineno + 1} fail_always)"


def test_subpackages_cover_every_module():
    modules = {info.name for info in pkgutil.walk_packages(sk.__path__, "symkf.") if not info.name.endswith("__main__")}
    assert sorted(m for m in modules if not m.startswith(SUBPACKAGES)) == []


def test_the_walk_can_see_an_execution(mark, monkeypatch):
    """The detector works: with the session guard lifted, sympy's own sympify of a tuple (not
    strict inside containers) runs the payload and the marker appears."""
    import sympy.parsing.sympy_parser as parser
    for name in ("parse_expr", "eval_expr"):
        monkeypatch.setattr(parser, name, ORIGINAL[name])
    sp.sympify((PAYLOADS[1].format(mark=mark),), strict=True)
    assert mark.exists()


def test_guard_refuses_string_evaluation():
    with pytest.raises(StringEvaluation):
        sp.sympify("1+1")
    with pytest.raises(StringEvaluation):
        sp.Matrix([["1"]])


def _confirmed_holes(p: str) -> dict[str, Callable[[], Any]]:
    """The calls that created the marker file before the walk found them, each with its form."""
    from symkf.model import statespace as control
    from symkf.model import system as model, strategies
    from symkf.engine import oracle, region
    from symkf.exact import algebraic, field
    from symkf.exact.numbers import sympify
    x = algebraic.x
    return {
        "numbers.sympify tuple": lambda: sympify((p,)),
        "numbers.sympify dict": lambda: sympify({p: p}),
        "numbers.sympify set": lambda: sympify({p}),
        "AlgebraicNumber(poly={...})": lambda: algebraic.AlgebraicNumber({p: 1}, 0),
        "AlgebraicNumber.from_root tuple": lambda: algebraic.AlgebraicNumber.from_root((p,), 0, 1),
        "AlgebraicNumber.from_root dict": lambda: algebraic.AlgebraicNumber.from_root({p: 1}, 0, 1),
        "AlgebraicNumber.from_root lo": lambda: algebraic.AlgebraicNumber.from_root(sp.Poly(x ** 2 - 2, x), [p], 2),
        "AlgebraicNumber.refine(width=[...])": lambda: algebraic.AlgebraicNumber.from_expr(sp.sqrt(2)).refine([p]),
        "exact.algebraic.sign": lambda: algebraic.sign((p,)),
        "sympy_to_fmpz": lambda: algebraic.sympy_to_fmpz({p: 1}),
        "NumberField.convert": lambda: field.NumberField([sp.sqrt(2)]).convert((p,)),
        "check_positive_definite": lambda: model.check_positive_definite(np.array([[p]], dtype=object), "M"),
        "control.float_matrix": lambda: control.float_matrix(np.array([[p]], dtype=object), "M"),
        "gilbert_elliott_losses": lambda: strategies.gilbert_elliott_losses(1, max_denominator=[p]),
        "roots_in_unit": lambda: region.roots_in_unit((p,), sp.Symbol("t")),
        "iid_probability": lambda: oracle.iid_probability([(p,)]),
    }


@pytest.mark.parametrize("name", list(_confirmed_holes("")))
def test_confirmed_holes_are_refused_without_running(mark, name):
    """Each with the guard lifted, as on a user's machine: the payload never runs and the call
    is refused with symkf's error (hypothesis's InvalidArgument for the strategy)."""
    from hypothesis.errors import InvalidArgument
    import sympy.parsing.sympy_parser as parser
    with pytest.MonkeyPatch.context() as m:
        for evaluator in ("parse_expr", "eval_expr"):
            m.setattr(parser, evaluator, ORIGINAL[evaluator])
        with pytest.raises((SymkfError, InvalidArgument)):
            _confirmed_holes(PAYLOADS[0].format(mark=mark))[name]()
    assert not mark.exists()


def test_a_call_whose_timeout_a_library_turned_into_its_own_error_counts_as_a_timeout():
    import numpy as np

    def converting():   # as numpy does when the timer interrupts a structured-dtype promotion
        try:
            rows = np.arange(4000, dtype=np.int64).reshape(1000, 4)
            while True:
                np.unique(rows, axis=0)
        except BaseException:
            raise TypeError("Cannot compare structured arrays unless they have a common dtype") from None

    old = signal.signal(signal.SIGPROF, _alarm)
    try:
        assert isinstance(_limited(converting, 0.05), _Timeout)
        assert isinstance(_limited(lambda: int("x"), 0.05), ValueError)
    finally:
        signal.signal(signal.SIGPROF, old)

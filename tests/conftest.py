"""Shared test set-up.

The string guard: sympy evaluates a string as Python (``parse_expr`` -> ``eval_expr`` -> ``eval``)
whenever ``sympify``, ``S``, ``Matrix``, ``Poly``, ``Tuple``, ... meet one, also inside a tuple,
dict or set.  symkf reads outside strings only through its own parser
(:func:`symkf.exact.numbers.parse_exact`), so for the whole test run the evaluators raise
:class:`StringEvaluation`: any path of symkf that reaches them fails whatever test exercises it.
It is a BaseException, so no ``except Exception`` in the code under test can swallow it.

Hypothesis profiles: ``ci`` (derandomized: the same examples on every run, no example database),
loaded when ``HYPOTHESIS_PROFILE=ci`` or ``CI`` is set (``.ci/run`` sets the former), and ``dev``
otherwise: new random examples on every local run, failures kept in ``.hypothesis/`` and replayed
first.  A test's own ``@settings`` give its number of examples, never its randomness.
"""

from __future__ import annotations

import importlib
import os
import resource
import signal
import sys
import tempfile
import time
import traceback
from pathlib import Path

import pytest
import sympy
import sympy.parsing.sympy_parser as sympy_parser
import sympy.physics.units  # noqa: F401  imported lazily by simplify; it sympifies constant strings of its own
from hypothesis import settings


# A test run started in the background of a non-interactive shell inherits SIGINT ignored, and so
# would every symkf it starts (Python installs no KeyboardInterrupt handler then): the interrupt
# tests would send Ctrl-C into the void.  A Python handler is reset to the default on exec.
if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)

settings.register_profile("ci", derandomize=True, database=None, deadline=None, print_blob=True)
settings.register_profile("dev", deadline=None, print_blob=True)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE") or ("ci" if os.environ.get("CI") else "dev"))

#: the repository (tests that read README.md, docs/, examples/, proofs/ or pyproject.toml, or run
#: ``python -m symkf`` from the source tree, import it from here: ``from conftest import ROOT``)
ROOT = Path(__file__).resolve().parent.parent


def rotation(angle, scale=2) -> sympy.Matrix:
    """``scale R(angle)``: the rotation blocks the tests build their systems from."""
    c, s = sympy.cos(angle), sympy.sin(angle)
    return scale * sympy.Matrix([[c, -s], [s, c]])


def stacked_rotations(orders, rows):
    """``diag(2R(2 pi/q) for q in orders)`` watched by one sensor per row (``s1``, ``s2``, ...):
    rotations of one modulus from different cyclotomic fields, one eigen-block over their compositum."""
    import symkf as sk
    return sk.System(A=sympy.diag(*(rotation(2 * sympy.pi / q) for q in orders)),
                     sensors=[sk.Sensor(C=[r], name=f"s{j + 1}") for j, r in enumerate(rows)])


def period_24_block(d):
    """``diag(2R(pi/6), 2R(pi/4))`` (one eigen-block of modulus 2 and period 24) watched by ``d``
    integer sensor rows, the first ``d`` nonzero rows of ``{-2, ..., 2}^4`` in lexicographic order:
    the many-sensor systems whose priced work the tests check."""
    import itertools
    import symkf as sk
    picked = [r for r in itertools.product(range(-2, 3), repeat=4) if any(r)][:d]
    return sk.System(A=sympy.diag(rotation(sympy.pi / 6), rotation(sympy.pi / 4)),
                     sensors=[sk.Sensor(C=[list(r)], name=f"s{j + 1}") for j, r in enumerate(picked)])


def refused_within(seconds, match, call):
    """``call()`` refused by symkf's BudgetError (its message matching ``match``) within ``seconds``
    CPU-s: a priced step refused before its work starts."""
    import time
    from symkf.errors import BudgetError
    start = time.process_time()
    with pytest.raises(BudgetError, match=match):
        call()
    assert time.process_time() - start < seconds


# -- processes: the interrupt, writer and output tests watch the processes they start -------------

#: a system file of A = 2 R(pi/2) with one sensor, for the command-line tests (append a [loss])
ROTATION = '[system]\nA = [["0", "-2"], ["2", "0"]]\n[[sensors]]\nname = "s1"\nC = [["1", "0"]]\n'


def run(capsys, *argv) -> tuple[int, str, str]:
    """``symkf ARGV`` in this process: (exit status, stdout, stderr)."""
    from symkf import cli
    status = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return status, out, err


def one_line(err: str) -> str:
    """``err`` after checking that it is one line and holds no traceback."""
    assert err.count("\n") == 1 and "Traceback" not in err, err
    return err


def wait_for(condition, timeout: float, what: str) -> None:
    """Poll ``condition()`` until it holds; fail the test naming ``what`` after ``timeout`` seconds."""
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > deadline:
            pytest.fail(f"timed out after {timeout} s waiting for {what}")
        time.sleep(0.05)


def cpu_seconds(pid: int) -> float:
    """The CPU time (user + system) process ``pid`` has used, 0 once it is gone (from /proc)."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rpartition(")")[2].split()
    except OSError:
        return 0.0
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


# -- hard limits: heavy and hostile input runs in a forked child under a CPU and a memory limit ----

#: CPU seconds and extra address space (over the parent's) of one case: a hang, not slow work
#: (the entries cos(pi/517) and sin(-14 pi/3619) = -sin(2 pi/517), degree-230 algebraic numbers,
#: took 33 and 60 CPU-s on a 2.0 GHz Zen 1 core in isolating the roots of their margins'
#: polynomials; recognised as images of 2 cos(2 pi/517) they take 1.3 and 2.1 CPU-s on a Zen 5)
CPU_SECONDS = 120
EXTRA_MEMORY = 1536 * 1024 ** 2


def _vm_size() -> int:
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmSize:"):
            return int(line.split()[1]) * 1024
    return 0


def limited(fn, *args, memory: int = EXTRA_MEMORY) -> tuple[int, str]:
    """Run ``fn(*args)`` (returning an exit status) in a forked child under the limits (``memory``
    bytes of address space beyond the parent's); returns (exit status, stderr).  A child killed by a signal (SIGXCPU, SIGKILL, SIGSEGV) is -signal.
    A regression that hangs or allocates gigabytes fails its test instead of taking the machine
    down (tests/test_resource_limits.py::test_the_limits_are_real checks the harness itself)."""
    memory += _vm_size()
    with tempfile.TemporaryFile() as err:
        pid = os.fork()
        if pid == 0:  # the child: never returns into pytest
            status = 99
            try:
                resource.setrlimit(resource.RLIMIT_CPU, (CPU_SECONDS, CPU_SECONDS))
                resource.setrlimit(resource.RLIMIT_AS, (memory, memory))
                os.dup2(err.fileno(), 2)
                devnull = os.open(os.devnull, os.O_WRONLY)
                os.dup2(devnull, 1)
                sys.stdout, sys.stderr = open(1, "w", closefd=False), open(2, "w", closefd=False)
                status = fn(*args)
            except BaseException as exc:  # noqa: BLE001 - reported through the status
                print(f"Traceback-free report: {type(exc).__name__}: {exc}", file=sys.stderr)
                status = 98
            finally:
                sys.stderr.flush()
                os._exit(status)
        _, wait = os.waitpid(pid, 0)
        err.seek(0)
        text = err.read().decode(errors="replace")
    code = os.waitstatus_to_exitcode(wait)
    return code, text


def library(call) -> int:
    """0 when ``call()`` returns, 2 or 3 for symkf's own errors, 70 for anything else."""
    import symkf as sk
    try:
        call()
    except sk.SymkfError as exc:
        return exc.exit_status
    except Exception as exc:  # noqa: BLE001
        print(f"untranslated {type(exc).__name__}: {exc}", file=sys.stderr)
        return 70
    return 0


def refused_at_once(call, cap: str | None = None, seconds: float = 1.0) -> int:
    """For :func:`limited`: 0 when ``call()`` raises symkf's refusal within ``seconds`` of CPU time (its own, so a loaded machine does not fail it), naming the
    cap ``cap`` (when given) and its command-line option; 1 otherwise (the message and time on stderr)."""
    import time
    import symkf as sk
    from symkf import budget
    start = time.process_time()
    try:
        call()
    except sk.SymkfError as exc:
        took = time.process_time() - start
        print(f"{took:.3f} s: {exc}", file=sys.stderr)
        named = cap is None or f"{cap}=" in str(exc) and budget.OPTIONS[cap] in str(exc)
        return 0 if took < seconds and named else 1
    print("accepted", file=sys.stderr)
    return 1


def system_file(tmp: Path, entry: str, loss: str = "1/2", name: str = "s.toml") -> Path:
    """A system file of one state ``A = [[entry]]``, one sensor and the i.i.d. ``loss``."""
    path = tmp / name
    path.write_text(f'[system]\nA = [["{entry}"]]\n[[sensors]]\nC = [["1"]]\n[loss]\nkind = "iid"\nloss = ["{loss}"]\n')
    return path


# -- the fusion set-ups of tests/fusion (arXiv:2012.04896), built once per run --------------------

#: a 3-state plant, stable but for 11/10, each sensor seeing part of it
FUSION_A3 = [["11/10", "1/5", 0], [0, "9/10", 0], [0, 0, "1/2"]]


def small_fusion_model(arrival=("1/2", "3/5", "4/5")):
    """Three sensors on ``FUSION_A3`` (observable dimensions 2, 1, 2) with the i.i.d. ``arrival`` rates."""
    from symkf import Sensor
    from symkf.fusion import FusionModel
    sensors = [Sensor([[1, 0, 0]], name="a"), Sensor([[0, 0, 1]], [[2]], name="b"), Sensor([[0, 1, 1]], name="c")]
    return FusionModel.discrete(FUSION_A3, [[1, 0, 0], [0, 1, 0], [0, 0, 1]], sensors, list(arrival))


@pytest.fixture(scope="session")
def small_fusion():
    """The local filters of :func:`small_fusion_model`."""
    from symkf.fusion import local_filters
    return local_filters(small_fusion_model())


@pytest.fixture(scope="session")
def pendulum_fusion():
    """The local filters of the inverted pendulum of the paper's Section 4 (ten sensors)."""
    from symkf.fusion import local_filters, pendulum_model
    return local_filters(pendulum_model())


#: the module (``sympy.core.sympify`` as an attribute is the function)
_sympify_module = importlib.import_module("sympy.core.sympify")


class StringEvaluation(BaseException):
    """sympy was asked to evaluate a string as Python."""


#: the evaluators as sympy defines them (test_payload_walk lifts the guard to show its detector works)
ORIGINAL = {"parse_expr": sympy_parser.parse_expr, "eval_expr": sympy_parser.eval_expr,
            "kernS": _sympify_module.kernS}

#: sympy functions that sympify strings they build themselves from numbers (nsimplify writes
#: mpmath's identification of a float, e.g. '((6+sqrt(20))/2)', and parses it; simplify and
#: radsimp call it): no outside text reaches them
_OWN_STRINGS = frozenset({"nsimplify_real"})


def _short(path: str) -> str:
    return "symkf/" + path.rsplit("/symkf/", 1)[1] if "/symkf/" in path else path.rsplit("/", 1)[-1]


def _refuse(name: str):
    original = ORIGINAL[name]

    def refuse(*args, **kwargs):
        stack = traceback.extract_stack()[:-1]
        if any(f.name in _OWN_STRINGS and "/sympy/" in f.filename for f in stack[-6:]):
            return original(*args, **kwargs)
        callers = [f"{_short(f.filename)}:{f.lineno} ({f.name})" for f in stack
                   if "/sympy/" not in f.filename and ("/symkf/" in f.filename or "/tests/" in f.filename)]
        raise StringEvaluation(f"sympy's {name} reached with {args[:1]!r} from {callers[-1:]}: outside data "
                               "must go through symkf.exact.numbers (parse_exact / sympify)")
    return refuse


# sympify imports parse_expr from sympy_parser at each call, so patching the module suffices;
# the top-level re-export and kernS (sympify of a string without the parser's import) too
sympy_parser.parse_expr, sympy_parser.eval_expr = _refuse("parse_expr"), _refuse("eval_expr")
sympy.parse_expr = sympy_parser.parse_expr
_sympify_module.kernS = _refuse("kernS")


@pytest.fixture(scope="session")
def dask_cluster():
    """One local dask cluster of two worker processes for the whole run (starting one, its workers
    importing symkf, costs seconds)."""
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        yield cluster


#: the longest tests (a minute or more each on a 2-core runner) start first: with ``pytest -n auto``
#: a long test collected last (test_wheel.py sorts last) leaves the other workers idle at the end
LONGEST = ("test_wheel.py::test_a_newcomer_session_runs", "test_pendulum.py::test_reproduce_full",
           "test_spectral.py::test_sqrt2_matrix_analyze", "test_payload_walk.py::test_walk_full",
           "test_atlas.py::test_no_row_violated", "test_resource_limits.py::test_fuzz_under_limits_long",
           "test_second_order.py::test_full_family", "test_output.py::test_two_runs_writing")


def pytest_collection_modifyitems(items):
    """The ``LONGEST`` tests in its order (longest first), then the others in collection order."""
    rank = lambda item: next((i for i, name in enumerate(LONGEST) if name in item.nodeid), len(LONGEST))  # noqa: E731
    items.sort(key=rank)

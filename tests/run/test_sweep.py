"""symkf.sweep: serial, local processes and Dask give identical exact results, in order."""

import functools
import re

import time

import pytest
import sympy as sp

from symkf import IID, Sensor, System
from symkf.errors import AssumptionError, InputError
from symkf.io.families import load_family
from symkf.engine.stability import critical_alpha, critical_loss_rate, stability
from symkf.run.sweep import sweep

ROTATIONS = """
[family]
kind = "rotation"
[grid]
period = [2, 3, 4]
sensors = [1, 2]
[constants]
alpha = "2"
"""


def rotation(g: int) -> System:
    c, s = f"2*cos(pi/{g})", f"2*sin(pi/{g})"
    return System([[c, "-" + s], [s, c]], [Sensor([[1, 0]])])


@pytest.fixture(scope="module")
def family(tmp_path_factory):
    path = tmp_path_factory.mktemp("fam") / "rot.toml"
    path.write_text(ROTATIONS)
    return load_family(path)


@pytest.fixture(scope="module")
def serial(family):
    return family.evaluate()


def _same(a, b):
    """Exact equality, including the exact expression each value carries."""
    return len(a) == len(b) and all(x.value == y.value and x.value.exact == y.value.exact
                                    and x.periods == y.periods for x, y in zip(a, b))


def test_serial_values_are_the_hand_derived_ones(serial):
    # A = 2 R(pi/g), d identical sensors C = [1, 0]: eps_c = 2^(-2g / (d (g - 1))).
    expected = [sp.Integer(2) ** sp.Rational(-2 * g, d * (g - 1)) for g in (2, 3, 4) for d in (1, 2)]
    assert [o.value.exact for o in serial] == expected
    assert [o.periods for o in serial] == [(2,), (2,), (3,), (3,), (4,), (4,)]


def test_processes_match_serial(family, serial):
    assert _same(family.evaluate(jobs=2), serial)


def test_dask_local_cluster_matches_serial(family, serial, dask_cluster):
    import distributed

    with distributed.Client(dask_cluster) as client:
        assert _same(family.evaluate(scheduler=client), serial)
        assert _same(family.evaluate(scheduler=dask_cluster.scheduler_address), serial)
        # a symkf error raised on a worker comes back with its type and attributes
        with pytest.raises(AssumptionError, match="Assumption 1") as info:
            sweep(functools.partial(critical_alpha, loss=IID(["1/2"])),
                  [System([[2, 0], [0, 3]], [Sensor([[1, 1]])])], scheduler=client)
        assert info.value.assumption.startswith("Assumption 1")


def test_generic_functions_and_order():
    systems = [rotation(g) for g in (5, 2, 3)]  # the serial run fills their caches; jobs=2 must still ship them
    expected = [sp.sqrt(2) / 8, sp.Rational(1, 16), sp.Rational(1, 8)]
    for jobs in (1, 2):
        assert [v.exact for v in sweep(critical_loss_rate, systems, jobs=jobs)] == expected
    verdicts = sweep(functools.partial(stability, loss=IID(["1/20"])), systems[1:], jobs=2)
    assert [v.stable for v in verdicts] == [True, True]
    # A = 2 R(pi/2), loss 1/20: alpha^4 eps = 16/20, so alpha^2 rho = sqrt(4/5).
    assert verdicts[0].margins[0].exact == 2 * sp.sqrt(5) / 5


def test_worker_errors_are_reraised_exactly():
    bad = [System([[2, 0], [0, 3]], [Sensor([[1, 1]])])]
    task = functools.partial(critical_alpha, loss=IID(["1/2"]))
    with pytest.raises(AssumptionError) as serial_error:
        sweep(task, bad)
    with pytest.raises(AssumptionError) as process_error:
        sweep(task, bad * 2, jobs=2)
    assert str(process_error.value) == str(serial_error.value)
    assert process_error.value.applies_instead == serial_error.value.applies_instead


@pytest.mark.parametrize("kwargs, message", [
    ({"jobs": 0}, "jobs: expected a positive integer"),
    ({"jobs": True}, "jobs: expected a positive integer"),
    ({"jobs": 2, "scheduler": "tcp://127.0.0.1:8786"}, "not both"),
    ({"scheduler": 42}, "scheduler: expected a Dask scheduler address"),
    ({"scheduler": "__builtins__"}, "scheduler: expected a Dask scheduler address"),   # never reaches distributed
    ({"scheduler": "tcp://host:8786/x"}, "scheduler: expected a Dask scheduler address"),
    ({"scheduler": "tcp://127.0.0.1:99999"}, "scheduler: expected a Dask scheduler address"),  # port above 65535
])
def test_bad_arguments(kwargs, message):
    with pytest.raises(InputError, match=message):
        sweep(abs, [1, 2], **kwargs)


def _slow_abs(x: int) -> int:
    time.sleep(1.5)
    return abs(x)


def test_progress_only_when_asked_or_on_a_terminal(capsys):
    assert sweep(abs, [-1, -2]) == [1, 2]
    assert capsys.readouterr().err == ""          # pytest's stderr is not a terminal
    # asked for on a pipe: plain lines, the first after 2 s, then the end
    assert sweep(_slow_abs, [-1, -2], progress=True) == [1, 2]
    lines = capsys.readouterr().err.splitlines()
    assert re.fullmatch(r"symkf sweep: 50% after \d s", lines[0]) and re.fullmatch(r"symkf sweep: done after \d s", lines[-1])


def _max_degree(_: object) -> int:
    from symkf import budget
    return budget.LIMITS.max_degree


def test_workers_run_under_the_callers_caps():
    # symkf.budget is per process: without passing the caps, workers would see the default 64
    from symkf import budget
    with budget.limits(max_degree=200):
        assert sweep(_max_degree, range(3), jobs=2, progress=False) == [200, 200, 200]
    assert sweep(_max_degree, range(3), jobs=2, progress=False) == [budget.Limits.max_degree] * 3


def _started(task: int) -> tuple[int, float]:
    import time
    start = time.monotonic()  # CLOCK_MONOTONIC: one clock for all processes of the machine
    time.sleep(0.2)
    return -task, start


def test_costliest_tasks_start_first_and_results_keep_their_order():
    """With ``cost``, local processes take the tasks by decreasing cost (1 and 0 wait for a free
    worker, so they start >= 0.2 s after 3 and 2); the results stay in task order."""
    out = sweep(_started, range(4), jobs=2, progress=False, cost=lambda t: t)
    assert [v for v, _ in out] == [0, -1, -2, -3]
    starts = [s for _, s in out]
    assert min(starts[0], starts[1]) >= max(starts[2], starts[3]) + 0.15

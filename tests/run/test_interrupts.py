"""Interrupts and parallel work (symkf.run.sweep and the command line): Ctrl-C and SIGTERM cancel
the queued work, stop the workers and end with one line (exit 130 / 143), a killed parent leaves
no orphan, and no partial file is left."""

from __future__ import annotations

import contextlib
import gc
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from symkf import cli
from symkf.run.sweep import sweep

from conftest import ROOT, cpu_seconds, wait_for

#: members of about 10 CPU-s each (2 R(2 pi/g) for primes g > 200, under raised caps): every
#: signal arrives while both workers compute
SLOW_FAMILY = ('[family]\nname = "slow"\nkind = "rotation"\n[grid]\nperiod = [1601, 1607, 1609, 1613]\nsensors = [1]\n'
               '[constants]\nalpha = "2"\n')
CAPS = ["--max-cyclotomic-degree", "2000", "--max-angle-denominator", "4000", "--max-degree", "1000"]


def _processes() -> dict[int, tuple[int, int, str]]:
    """pid -> (parent pid, process group, state) of every process (psutil if installed, else /proc)."""
    try:
        import psutil
    except ImportError:
        psutil = None
    out = {}
    if psutil is not None:
        for p in psutil.process_iter(["ppid", "status"]):
            try:
                out[p.pid] = (p.info["ppid"], os.getpgid(p.pid), "Z" if p.info["status"] == psutil.STATUS_ZOMBIE else "R")
            except (ProcessLookupError, psutil.Error):
                pass
        return out
    for entry in Path("/proc").iterdir():
        try:
            fields = (entry / "stat").read_text().rpartition(")")[2].split()
        except (OSError, ValueError):
            continue
        if entry.name.isdigit():
            out[int(entry.name)] = (int(fields[1]), int(fields[2]), fields[0])
    return out


def children(pid: int) -> list[int]:
    return [p for p, (ppid, _, state) in _processes().items() if ppid == pid and state != "Z"]


def living_in_group(group: int) -> list[int]:
    """Processes of the process group ``group`` still alive (zombies excepted: they compute nothing)."""
    return [p for p, (_, pgid, state) in _processes().items() if pgid == group and state != "Z"]


def _started_with_workers(argv: list[str], cwd: Path, workers: int = 2, busy: bool = False) -> subprocess.Popen:
    """``argv`` in a session of its own, once ``workers`` child processes run (``busy``: once each
    has computed for 0.3 CPU-s, i.e. is inside a task whatever the machine's load)."""
    if not Path("/proc").is_dir():
        pytest.skip("needs /proc (Linux) to watch the worker processes")
    proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=cwd,
                            start_new_session=True)
    wait_for(lambda: len(children(proc.pid)) >= workers or proc.poll() is not None, 60, "the worker processes")
    assert proc.poll() is None, proc.communicate()
    if busy:
        wait_for(lambda: all(cpu_seconds(p) >= 0.3 for p in children(proc.pid)) or proc.poll() is not None, 60,
                 "the workers to compute")
    else:
        time.sleep(0.3)   # the workers are inside their first task
    return proc


def table_run(tmp_path: Path) -> subprocess.Popen:
    family = tmp_path / "slow.toml"
    family.write_text(SLOW_FAMILY)
    return _started_with_workers([sys.executable, "-m", "symkf", "table", str(family), "--jobs", "2",
                                  "--latex", str(tmp_path / "out.tex"), *CAPS], tmp_path, busy=True)


def finished(proc: subprocess.Popen, timeout: float = 15) -> tuple[int, str, str, float]:
    start = time.monotonic()
    out, err = proc.communicate(timeout=timeout)
    return proc.returncode, out, err, time.monotonic() - start


def assert_nothing_left(proc: subprocess.Popen, tmp_path: Path | None = None) -> None:
    """No process of the run's group computes on, and no table or partial file was written."""
    wait_for(lambda: not living_in_group(proc.pid), 10, "the workers to end")
    if tmp_path is not None:
        assert sorted(p.name for p in tmp_path.iterdir()) == ["slow.toml"]


@pytest.mark.parametrize("signum, to, status, message", [
    (signal.SIGINT, "group", 130, "symkf table: interrupted\n"),        # Ctrl-C in a terminal
    pytest.param(signal.SIGINT, "parent", 130, "symkf table: interrupted\n", marks=pytest.mark.full),
    pytest.param(signal.SIGTERM, "parent", 143, "symkf table: terminated (SIGTERM)\n", marks=pytest.mark.full),
    pytest.param(signal.SIGKILL, "parent", -signal.SIGKILL, "", marks=pytest.mark.full),
])
def test_a_signal_stops_the_table_and_its_workers(tmp_path, signum, to, status, message):
    """`symkf table FAMILY --jobs 2` once did not stop on SIGINT (to the parent or the whole
    group) within 40 s, SIGTERM ended it without a message, and after SIGKILL of the parent its
    two workers kept computing as orphans."""
    proc = table_run(tmp_path)
    (os.killpg if to == "group" else os.kill)(proc.pid, signum)
    code, out, err, seconds = finished(proc)
    assert (code, out, err) == (status, "", message) and seconds < 10
    assert_nothing_left(proc, tmp_path)


def test_a_second_ctrl_c_during_the_clean_up_still_exits_130(tmp_path):
    """Two Ctrl-C: the second, once the first had stopped the workers and written its message,
    while Python ended the process, killed the command by SIGINT (status -2; or a traceback from
    an atexit handler) instead of the status 130 it had decided on."""
    proc = table_run(tmp_path)
    os.killpg(proc.pid, signal.SIGINT)
    first = proc.stderr.readline()
    with contextlib.suppress(ProcessLookupError):   # the run may have ended before the second came
        os.killpg(proc.pid, signal.SIGINT)
    code, out, err, seconds = finished(proc)
    assert (code, out, first + err) == (130, "", "symkf table: interrupted\n") and seconds < 10
    assert_nothing_left(proc, tmp_path)


SLEEPERS = ("import importlib, time\nsweep = importlib.import_module('symkf.run.sweep')\n"
            "{}sweep.sweep(time.sleep, [30] * 4, jobs=2)\n")


@pytest.mark.parametrize("watch", ["prctl", "watchdog"])
def test_workers_die_with_their_parent(watch):
    """The same without the exact engine's CPU time: workers sleeping in a task, parent killed;
    by the kernel's parent-death signal (Linux) or by the workers' watchdog thread (elsewhere)."""
    without_prctl = "sweep._kill_on_parent_death = lambda: False\n" if watch == "watchdog" else ""
    proc = _started_with_workers([sys.executable, "-c", SLEEPERS.format(without_prctl)], ROOT)
    proc.kill()
    finished(proc)
    assert_nothing_left(proc)


def _sleep_or_fail(seconds: float) -> float:
    if seconds < 0:
        raise ValueError("this task fails")
    time.sleep(seconds)
    return seconds


def _interrupt_the_parent(seconds: float) -> float:
    if seconds < 0:      # one task only: a signal arriving after the test has caught its interrupt would stop pytest
        os.kill(os.getppid(), signal.SIGINT)
    time.sleep(abs(seconds))
    return seconds


def _children() -> set:
    import multiprocessing
    return set(multiprocessing.active_children())


def _no_workers_left(before: set) -> None:
    # the children that were there before the sweep (the session's dask cluster, when this pytest
    # worker ran a test that started it) are not the sweep's
    wait_for(lambda: _children() <= before, 5, "the workers to end")


def test_a_failing_task_cancels_the_queued_ones():
    """A task's error ends the sweep at once: the queued tasks are cancelled and the worker still
    sleeping is stopped (before, the pool waited for every queued task)."""
    start, before = time.monotonic(), _children()
    with pytest.raises(ValueError, match="this task fails"):
        sweep(_sleep_or_fail, [30, -1, 30, 30], jobs=2, progress=False)
    assert time.monotonic() - start < 10
    _no_workers_left(before)


def test_ctrl_c_in_the_caller_stops_the_workers():
    """KeyboardInterrupt in the caller (here sent by a worker to its parent) stops the workers,
    which ignore SIGINT themselves."""
    # no collection during the sweep: an interrupt that lands in a finalizer (the __del__ of an
    # earlier test's object, collected in the middle of the sweep) is printed and ignored by Python,
    # whatever the sweep does; what is tested here is the sweep's own handling of the interrupt
    gc.collect()
    gc.disable()
    try:
        start, before = time.monotonic(), _children()
        with pytest.raises(KeyboardInterrupt):
            sweep(_interrupt_the_parent, [-30, 30, 30], jobs=2, progress=False)
    finally:
        gc.enable()
    assert time.monotonic() - start < 10
    _no_workers_left(before)


def test_ctrl_c_while_the_command_line_is_imported(monkeypatch, capsys):
    """`symkf` (and `python -m symkf`) interrupted before symkf.cli is even imported: one line,
    exit 130, no traceback (simulated: an import that raises KeyboardInterrupt)."""
    import importlib.abc

    import symkf.__main__ as entry

    class Interrupting(importlib.abc.MetaPathFinder):
        def find_spec(self, name, path=None, target=None):
            if name == "symkf.cli":
                raise KeyboardInterrupt
    monkeypatch.delitem(sys.modules, "symkf.cli")
    monkeypatch.setattr(sys, "meta_path", [Interrupting(), *sys.meta_path])
    assert entry.run() == 130
    assert capsys.readouterr().err == "symkf: interrupted\n"


def test_sigterm_is_raised_like_ctrl_c_during_a_command():
    previous = signal.getsignal(signal.SIGTERM)
    with pytest.raises(cli.Terminated):
        with cli._interrupted_once(restore=True):
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(5)
    assert signal.getsignal(signal.SIGTERM) is previous
    assert issubclass(cli.Terminated, KeyboardInterrupt)    # every clean-up of Ctrl-C runs for it


def test_only_the_first_interrupt_is_raised_and_the_handlers_come_back():
    before = {s: signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM)}
    with pytest.raises(KeyboardInterrupt):
        with cli._interrupted_once(restore=True):
            try:
                os.kill(os.getpid(), signal.SIGINT)
                time.sleep(5)
            finally:   # the clean-up the first started is not cut short by a second, nor a SIGTERM
                os.kill(os.getpid(), signal.SIGINT)
                os.kill(os.getpid(), signal.SIGTERM)
                time.sleep(0.1)
    assert {s: signal.getsignal(s) for s in before} == before
    with cli._interrupted_once(restore=False):   # the process's entry point: ignored while Python ends it
        pass
    try:
        assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN and signal.getsignal(signal.SIGTERM) is signal.SIG_IGN
    finally:
        for s, handler in before.items():
            signal.signal(s, handler)


#: A = 2 R(pi/2) watched by [1 0] with i.i.d. loss 1/2
SYSTEM_TEXT = '[system]\nA = [[0, -2], [2, 0]]\n[[sensors]]\nC = [[1, 0]]\n[loss]\nkind = "iid"\nloss = ["1/2"]\n'


@pytest.fixture
def system(tmp_path):
    path = tmp_path / "system.toml"
    path.write_text(SYSTEM_TEXT)
    return path


def test_ctrl_c_is_one_line_and_exit_130(system):
    """Ctrl-C inside the simulation: the signal is sent once the process has used 2.5 CPU-s (its
    imports take well under that), not after a wall-clock delay that a loaded machine stretches."""
    proc = subprocess.Popen([sys.executable, "-m", "symkf", "simulate", str(system), "--paths", "600000",
                             "--horizon", "100"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT)
    deadline = time.monotonic() + 120
    while cpu_seconds(proc.pid) < 2.5 and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.05)
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == 130 and err == "symkf simulate: interrupted\n" and out == ""

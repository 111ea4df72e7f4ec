"""Progress (symkf.run.progress): bars only on a terminal, plain lines without control codes where
no bar can be drawn (a Jupyter kernel without widgets, a file), bars that move with the paths
simulated and the members done, notes on lines of their own, workers that draw nothing, and
"still working" notes on stderr that can be silenced."""

from __future__ import annotations

import io
import re
import sys
import time
import warnings

import symkf as sk

from symkf.numeric.montecarlo import divergence_test
from symkf.run.progress import note, progress, still_working
from symkf.run.sweep import sweep


def test_progress_only_on_a_terminal(monkeypatch):
    assert progress(3, "x").disable                       # pytest's stderr is not a terminal

    class Terminal:
        def isatty(self):
            return True

        def write(self, s):
            return len(s)

        def flush(self):
            pass
    monkeypatch.setattr(sys, "stderr", Terminal())
    assert not progress(3, "x").disable
    assert progress(3, "x", enabled=False).disable


def test_plain_lines_on_stdout_in_a_kernel_without_widgets(monkeypatch, capsys):
    from symkf.run import progress
    monkeypatch.delenv("TQDM_DISABLE", raising=False)
    monkeypatch.setitem(sys.modules, "ipykernel", sys)          # "a Jupyter kernel runs"
    monkeypatch.setitem(sys.modules, "ipywidgets", None)       # without ipywidgets
    clock = iter(range(0, 1000, 5)).__next__                    # 5 s between readings
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with progress.progress(4, "x", clock=clock) as bar:
            assert bar.mode == "lines"
            for _ in range(4):
                bar.update()
    out, err = capsys.readouterr()
    assert err == "" and out.splitlines()[0] == "x: 25% after 5 s" and out.splitlines()[-1].startswith("x: done")
    assert "\r" not in out and "\x1b" not in out
    monkeypatch.delitem(sys.modules, "ipykernel")
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)
    assert not progress.progress(3, "x").disable


class _Clock:
    """A clock that moves 100 s at every reading: every plain line is due."""

    def __init__(self):
        self.now = 0.0

    def __call__(self):
        self.now += 100
        return self.now


def _percentages(text: str, desc: str) -> list[int]:
    return [int(p) for p in re.findall(rf"^{desc}: +(\d+)% after", text, re.M)]


def test_simulation_moves_the_bar_with_each_batch_of_paths():
    """70 000 paths are three batches (32 768, 32 768, 4 464) in each of the three runs (horizons
    h, 2h, 3h): the caller's bar passes nine increasing fractions, the first 32 768 h / (70 000 6h)
    = 7.8 %, not one jump when the simulation ends."""
    system = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]])])
    stream = io.StringIO()
    with progress(1, "verify", enabled=True, file=stream, clock=_Clock(), every=1) as bar:
        divergence_test(system, sk.IID(loss=["1/10"]), seed=0, paths=70_000, horizon=36)
        assert bar.fraction == 1
    seen = _percentages(stream.getvalue(), "verify")
    # (a line may also come from the bar's redrawing thread: it shows one of these fractions, or 0)
    assert seen == sorted(seen) and sorted(set(seen) - {0})[:3] == [8, 16, 17] and len(set(seen)) >= 8
    assert seen[-1] == 100


def test_plain_lines_carry_no_control_codes():
    stream = io.StringIO()
    with progress(3, "x", enabled=True, file=stream, clock=_Clock(), every=1) as bar:
        bar.update()
        bar.note("x: a finished task")
        bar.update(2)
    text = stream.getvalue()
    assert "x: a finished task\n" in text and _percentages(text, "x") == [33, 100]
    assert not re.search("[\r\x1b\x08]", text)


def test_a_reporter_inside_another_moves_its_next_step_and_draws_nothing():
    stream = io.StringIO()
    with progress(2, "outer", enabled=True, file=stream) as outer:
        outer.update()
        with progress(4, "inner", enabled=True) as inner:
            inner.update()
            assert inner.disable and outer.fraction == (1 + 1 / 4) / 2
            with inner.part(1):   # a part of the inner's steps: one step of four, halfway
                with progress(2, "innermost") as innermost:
                    innermost.update()
            assert outer.fraction == (1 + 2 / 4) / 2
        outer.update()
        assert outer.fraction == 1
    assert "inner" not in stream.getvalue()


def test_a_note_goes_above_the_bar_on_a_line_of_its_own():
    class Terminal(io.StringIO):
        def isatty(self):
            return True

    stream = Terminal()
    with progress(2, "x", file=stream) as bar:
        assert bar.mode == "bar"
        bar.update()
        bar.note("compiling the kernel...")
    text = stream.getvalue()
    before, after = text.split("compiling the kernel...")
    assert before.endswith("\r") and after.startswith("\n") and after.count("50%") >= 1


def _drawn_in_a_worker(_):
    return progress(3, "x", enabled=True).disable


def test_workers_draw_nothing_and_the_parent_prints_a_line_per_finished_task(capsys):
    assert sweep(_drawn_in_a_worker, [1, 2, 3], jobs=2, progress=True, desc="s",
                 label=lambda t: f"t{t}") == [True] * 3
    err = capsys.readouterr().err
    done = re.findall(r"^s: t(\d) done \((\d) of 3\)$", err, re.M)
    assert sorted(t for t, _ in done) == ["1", "2", "3"] and [k for _, k in done] == ["1", "2", "3"]
    assert not re.search("[\r\x1b]", err)


def test_still_working_is_quiet_while_a_bar_shows_the_elapsed_time(capsys):
    with still_working("symkf verify", after=0.05, every=0.05, enabled=True):
        with progress(2, "verify", enabled=True, every=100):
            time.sleep(0.3)
    assert "still working" not in capsys.readouterr().err


def test_still_working_is_quiet_while_a_reporter_builds_its_view(capsys, monkeypatch):
    """A reporter counts as drawing from the moment it is entered: a view that takes 0.3 s to build
    (a tqdm bar starting under load) leaves a still_working reporter that wakes meanwhile quiet."""
    from symkf.run import progress as module
    built = module._Lines.__init__

    def slow(self, p):
        time.sleep(0.3)
        built(self, p)
    monkeypatch.setattr(module._Lines, "__init__", slow)
    with still_working("symkf verify", after=0.05, every=0.05, enabled=True):
        with progress(2, "verify", enabled=True, every=100):
            pass
    assert "still working" not in capsys.readouterr().err


def test_still_working_notes_on_stderr_and_silenceable(capsys):
    from symkf.run.progress import still_working
    with still_working("symkf analyze", after=0.05, every=0.05, enabled=True):
        time.sleep(0.3)
    lines = capsys.readouterr().err.splitlines()
    assert len(lines) >= 2 and all(line.startswith("symkf analyze: still working, ") for line in lines)
    with still_working("symkf analyze", after=0.01, every=0.01, enabled=False):
        time.sleep(0.1)
    assert capsys.readouterr().err == ""


def test_compiling_says_so_only_when_it_takes_long(capsys):
    import time
    from symkf.run.progress import compiling
    with compiling("the 4-state filter kernel", after=0.05, enabled=True):
        time.sleep(0.3)
    assert capsys.readouterr().err == ("compiling the 4-state filter kernel (numba, once per installation; "
                                       "`symkf warm` compiles ahead)...\n")
    with compiling("the 4-state filter kernel", after=5, enabled=True):
        pass
    assert capsys.readouterr().err == ""


def test_a_worker_prints_no_notes(capsys):
    from symkf.run.progress import compiling, silenced
    with silenced(), compiling("the kernel", after=0.01, enabled=True), \
            still_working("symkf verify", after=0.01, every=0.01, enabled=True):
        time.sleep(0.2)
    assert capsys.readouterr().err == ""

"""Progress (symkf.run.progress): bars only on a terminal or when asked, none in a Jupyter kernel
without widgets, and "still working" notes on stderr that can be silenced."""

from __future__ import annotations

import sys
import time
import warnings

from symkf.run.progress import progress


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


def test_no_text_bars_in_a_kernel_without_widgets(monkeypatch):
    from symkf.run import progress
    monkeypatch.delenv("TQDM_DISABLE", raising=False)
    monkeypatch.setitem(sys.modules, "ipykernel", sys)          # "a Jupyter kernel runs"
    monkeypatch.setitem(sys.modules, "ipywidgets", None)       # without ipywidgets
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert progress.progress(3, "x").disable
    monkeypatch.delitem(sys.modules, "ipykernel")
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)
    assert not progress.progress(3, "x").disable


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

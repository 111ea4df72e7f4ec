"""Outputs that never destroy data, Ctrl-C and --jobs (issue 17, item 4)."""

from __future__ import annotations

import json
import os
import resource
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from conftest import cpu_seconds

from symkf import cli
from conftest import ROOT

#: A = 2 R(pi/2) watched by [1 0] with i.i.d. loss 1/2
SYSTEM_TEXT = '[system]\nA = [[0, -2], [2, 0]]\n[[sensors]]\nC = [[1, 0]]\n[loss]\nkind = "iid"\nloss = ["1/2"]\n'


def run(capsys, *argv) -> tuple[int, str, str]:
    status = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return status, out, err


@pytest.fixture
def family(tmp_path):
    """A small family (two members, a fraction of a second); its LaTeX table is about 1 kB."""
    path = tmp_path / "fam.toml"
    path.write_text('[family]\n[grid]\na = ["2", "3"]\n[system]\nA = [["a", "0"], ["0", "a/2"]]\n'
                    '[[sensors]]\nC = [["1", "1"]]\n')
    return path


def test_rerun_replaces_its_own_output(capsys, tmp_path, family):
    """Issue 24: rerunning `symkf table ... --latex table.tex` replaces the table (atomically, no
    --force needed); --force is still accepted."""
    out = tmp_path / "out.tex"
    out.write_text("an earlier table")
    for extra in ([], [], ["--force"]):
        status, stdout, err = run(capsys, "table", family, "--latex", out, "--json", *extra)
        assert status == 0 and err == "" and out.read_text().startswith("\\begin{table}")
        assert json.loads(stdout)["latex"] == str(out)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fam.toml", "out.tex"]


def test_input_file_is_never_overwritten(capsys, family):
    before = family.read_bytes()
    for extra in ([], ["--force"]):
        status, _, err = run(capsys, "table", family, "--latex", family, *extra)
        assert status == 2 and "is the input file" in err and family.read_bytes() == before


@pytest.mark.parametrize("target, message", [("missing/out.tex", "does not exist"), ("/dev/full", "not a regular file"),
                                             (".", "not a regular file")])
def test_bad_output_path_refused_before_computing(capsys, tmp_path, family, target, message, monkeypatch):
    """The family is not evaluated at all (it would take seconds): the check comes first."""
    monkeypatch.chdir(tmp_path)
    import symkf.reports.tables as tables
    monkeypatch.setattr(tables, "family_table", lambda *a, **k: pytest.fail("computed before checking the output"))
    status, out, err = run(capsys, "table", family, "--latex", target)
    assert status == 2 and out == "" and message in err and err.count("\n") == 1


def test_failed_write_keeps_the_old_file(tmp_path, family):
    """ulimit -f: the write fails midway; the old file is untouched and no partial file is left."""
    out = tmp_path / "out.tex"
    out.write_text("old")

    def small_files():
        resource.setrlimit(resource.RLIMIT_FSIZE, (512, 512))
    proc = subprocess.run([sys.executable, "-m", "symkf", "table", str(family), "--latex", str(out), "--force"],
                          capture_output=True, text=True, preexec_fn=small_files, cwd=ROOT, timeout=300)
    assert proc.returncode == 2 and f"--latex {out}: cannot write (File too large)" in proc.stderr
    assert out.read_text() == "old" and sorted(p.name for p in tmp_path.iterdir()) == ["fam.toml", "out.tex"]


@pytest.fixture
def system(tmp_path):
    path = tmp_path / "system.toml"
    path.write_text(SYSTEM_TEXT)
    return path


def test_plot_written_to_the_path_reported(capsys, tmp_path, system):
    pytest.importorskip("matplotlib")
    target = tmp_path / "plot_noext"
    status, out, _ = run(capsys, "simulate", system, "--paths", "20", "--horizon", "5", "--plot", target, "--json")
    assert status == 0 and json.loads(out)["plot"] == str(target)
    assert target.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and not (tmp_path / "plot_noext.png").exists()


def test_jobs_capped_at_the_cpu_count(capsys, monkeypatch, family):
    seen = {}
    import symkf.reports.tables as tables
    monkeypatch.setattr(tables, "family_table", lambda path, jobs, scheduler: seen.setdefault("jobs", jobs) and 1/0)
    run(capsys, "table", family, "--jobs", "1000")
    assert seen["jobs"] == len(os.sched_getaffinity(0))
    seen.clear()
    run(capsys, "table", family, "--jobs", "1000", "--oversubscribe")
    assert seen["jobs"] == 1000


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


def test_still_working_notes_on_stderr_and_silenceable(capsys):
    from symkf.run.progress import still_working
    with still_working("symkf analyze", after=0.05, every=0.05, enabled=True):
        time.sleep(0.3)
    lines = capsys.readouterr().err.splitlines()
    assert len(lines) >= 2 and all(line.startswith("symkf analyze: still working, ") for line in lines)
    with still_working("symkf analyze", after=0.01, every=0.01, enabled=False):
        time.sleep(0.1)
    assert capsys.readouterr().err == ""


@pytest.mark.parametrize("command", ["table", "analyze", "verify"])
def test_unreadable_input_is_exit_2(capsys, monkeypatch, family, command):
    """An unreadable file (PermissionError; simulated, the tests may run as root) was exit 70 in
    ``table``: every reader goes through files.read_toml."""
    real_open = Path.open

    def deny(self, *args, **kwargs):
        if self == family:
            raise PermissionError(13, "Permission denied")
        return real_open(self, *args, **kwargs)
    monkeypatch.setattr(Path, "open", deny)
    status, out, err = run(capsys, command, family)
    assert status == 2 and out == "" and "cannot read (Permission denied)" in err and err.count("\n") == 1

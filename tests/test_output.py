"""The one writer of every file symkf writes (symkf.output): never over an input, never through a
symbolic link, never half a file, never over a file another run wrote meanwhile (a rerun replaces
its own output), output paths checked before computing, and nothing else in symkf writes a file."""

from __future__ import annotations

import ast
import errno
import json
import os
import re
import resource
import subprocess
import sys
import time
from pathlib import Path

import pytest

from symkf import examples, output
from symkf.errors import OutputError

from conftest import ROOT, cpu_seconds, one_line, run, wait_for

FAMILY_TEXT = ('[family]\n[grid]\na = ["2", "3"]\n[system]\nA = [["a", "0"], ["0", "a/2"]]\n'
               '[[sensors]]\nC = [["1", "1"]]\n')


def leftovers(directory: Path) -> list[str]:
    """Temporary files of the writer left in ``directory`` (there must never be any)."""
    return sorted(p.name for p in directory.iterdir() if p.name.endswith(".part"))


@pytest.fixture
def family(tmp_path):
    path = tmp_path / "fam.toml"
    path.write_text(FAMILY_TEXT)
    return path


@pytest.fixture
def no_table(monkeypatch):
    """Refusals come before the family is evaluated."""
    import symkf.reports.tables as tables
    monkeypatch.setattr(tables, "family_table", lambda *a, **k: pytest.fail("computed before checking the output"))


# -- a rerun replaces its own output; a bad target is refused before computing -----------------------

def test_rerun_replaces_its_own_output(capsys, tmp_path, family):
    """Rerunning `symkf table ... --latex table.tex` replaces the table (atomically, no
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


#: A = 2 R(pi/2) watched by [1 0] with i.i.d. loss 1/2
SYSTEM_TEXT = '[system]\nA = [[0, -2], [2, 0]]\n[[sensors]]\nC = [[1, 0]]\n[loss]\nkind = "iid"\nloss = ["1/2"]\n'


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


@pytest.mark.parametrize("extension", ["svg", "pdf", "svgz", "eps"])
def test_the_same_figure_command_writes_the_same_bytes(capsys, tmp_path, system, extension):
    # matplotlib wrote the time of saving (SVG to the microsecond, PDF and PostScript to the
    # second, compressed SVG in its gzip header) and random SVG ids: no two runs were alike
    pytest.importorskip("matplotlib")
    written = []
    for k in range(2):
        target = tmp_path / f"plot{k}.{extension}"
        status, _, _ = run(capsys, "simulate", system, "--paths", "20", "--horizon", "5", "--plot", target)
        assert status == 0
        written.append(target.read_bytes())
        time.sleep(1.05)   # the next second: a date to the second would differ
    assert written[0] == written[1] and len(written[0]) > 1000


FAMILY = examples.family("rotation-periods")


def test_too_long_output_name_is_exit_2(capsys, tmp_path):
    """A 300-character file name: OSError (File name too long) in output.plan was exit 70."""
    target = tmp_path / ("a" * 300 + ".tex")
    status, out, err = run(capsys, "table", FAMILY, "--latex", target)
    assert status == 2 and out == ""
    assert "--latex" in one_line(err) and "above the file system's limit" in err


# -- inputs are never written over, whatever names them -------------------------------------------

def test_hard_link_to_the_input_is_refused(capsys, tmp_path, family, no_table):
    link = tmp_path / "out.tex"
    os.link(family, link)
    status, out, err = run(capsys, "table", family, "--latex", link, "--force")
    assert status == 2 and out == "" and err.count("\n") == 1
    assert f"--latex {link}: is the input file {family} (a hard link to it)" in err
    assert family.read_text() == FAMILY_TEXT


def test_input_by_another_path_is_refused(capsys, tmp_path, family, no_table):
    (tmp_path / "sub").mkdir()
    other = tmp_path / "sub" / ".." / "fam.toml"
    status, _, err = run(capsys, "table", family, "--latex", other)
    assert status == 2 and "is the input file" in err and family.read_text() == FAMILY_TEXT


@pytest.mark.parametrize("points_to", ["input", "other", "nothing"])
def test_symbolic_link_is_never_written_through_nor_replaced(capsys, tmp_path, family, no_table, points_to):
    other = tmp_path / "notes.txt"
    other.write_text("notes")
    link = tmp_path / "out.tex"
    link.symlink_to({"input": family, "other": other, "nothing": tmp_path / "missing"}[points_to])
    status, _, err = run(capsys, "table", family, "--latex", link, "--force")
    assert status == 2 and f"--latex {link}: is a symbolic link" in err and err.count("\n") == 1
    assert link.is_symlink() and family.read_text() == FAMILY_TEXT and other.read_text() == "notes"
    assert not (tmp_path / "missing").exists()


def test_a_directory_reached_through_a_symbolic_link_is_the_users_own(capsys, tmp_path, family):
    """--latex through a linked directory writes into the directory it names, and reruns replace
    that output; inside it, the input (by the link) and a linked target file are still refused."""
    (tmp_path / "real").mkdir()
    linked = tmp_path / "linked"
    linked.symlink_to(tmp_path / "real", target_is_directory=True)
    for _ in range(2):
        status, _, err = run(capsys, "table", family, "--latex", linked / "out.tex")
        assert status == 0 and err == "" and (tmp_path / "real" / "out.tex").read_text().startswith("\\begin{table}")
    assert leftovers(tmp_path / "real") == [] and sorted(p.name for p in (tmp_path / "real").iterdir()) == ["out.tex"]
    (tmp_path / "notes.txt").write_text("notes")
    (tmp_path / "real" / "notes.tex").symlink_to(tmp_path / "notes.txt")
    status, _, err = run(capsys, "table", family, "--latex", linked / "notes.tex", "--force")
    assert status == 2 and f"--latex {linked / 'notes.tex'}: is a symbolic link" in one_line(err)
    assert (tmp_path / "notes.txt").read_text() == "notes"
    (tmp_path / "real" / "fam.toml").write_text(FAMILY_TEXT)
    status, _, err = run(capsys, "table", tmp_path / "real" / "fam.toml", "--latex", linked / "fam.toml", "--force")
    assert status == 2 and "is the input file" in one_line(err)


@pytest.mark.parametrize("points_to, message", [
    ("missing", "the directory {link} (a symbolic link to {target}) does not exist"),   # was "File exists"
    ("file", "the directory {link} (a symbolic link to {target}) is not a directory"),  # was "does not exist"
])
def test_a_linked_directory_that_is_none_says_where_it_points(tmp_path, points_to, message):
    target = tmp_path / ("notes.txt" if points_to == "file" else "missing")
    if points_to == "file":
        target.write_text("notes")
    link = tmp_path / "linked"
    link.symlink_to(target)
    expected = message.format(link=link, target=target)
    with pytest.raises(OutputError, match=re.escape(f"--latex {link / 'out.tex'}: {expected}")):
        output.plan(link / "out.tex", "--latex")
    with pytest.raises(OutputError, match=re.escape(f"--outdir {link}: {expected}")):
        output.plan_directory(link, "--outdir")
    assert not (tmp_path / "missing").exists() and (points_to != "file" or target.read_text() == "notes")


def test_reproduce_figure_symlinked_to_an_input(capsys, tmp_path):
    """`reproduce sui-theorem12 --outdir rep --quick` with rep/sui_theorem12.png a link to an input
    once replaced the input with a PNG (exit 0)."""
    pytest.importorskip("matplotlib")
    precious = tmp_path / "system.toml"
    precious.write_text("[system]\nA = [[2]]\n")
    rep = tmp_path / "rep"
    rep.mkdir()
    (rep / "sui_theorem12.png").symlink_to(precious)
    status, out, err = run(capsys, "reproduce", "sui-theorem12", "--outdir", rep, "--quick")
    assert status == 2 and out == "" and "sui_theorem12.png: is a symbolic link" in err and err.count("\n") == 1
    assert precious.read_text() == "[system]\nA = [[2]]\n" and leftovers(rep) == []


def test_a_file_read_in_the_run_is_an_input(tmp_path, family):
    """Python: the family file a table was computed from is protected, and so is any file read
    in the run, without naming it."""
    from symkf.io.families import load_family
    from symkf.reports.tables import family_table
    table = family_table(family)
    with pytest.raises(OutputError, match="is the input file"):
        table.write(family)
    system = tmp_path / "system.toml"
    system.write_text("[system]\nA = [[2]]\n[[sensors]]\nC = [[1]]\n")
    with output.run():
        from symkf.io import files
        files.load(system)
        with pytest.raises(OutputError, match="is the input file"):
            output.write_text(system, "x")
        load_family(family)
        with pytest.raises(OutputError, match="is the input file"):
            output.write_text(family, "x")
    assert system.read_text().startswith("[system]") and family.read_text() == FAMILY_TEXT
    assert table.write(tmp_path / "t.tex") == tmp_path / "t.tex"


# -- concurrent runs never clobber each other ------------------------------------------------------

def test_a_new_target_taken_meanwhile_is_not_replaced(tmp_path):
    target = tmp_path / "table.tex"
    planned = output.plan(target, "--latex")
    target.write_text("the other run's table")       # another run got there first
    with pytest.raises(OutputError, match="appeared while this run was computing"):
        planned.put_text("ours")
    assert target.read_text() == "the other run's table" and leftovers(tmp_path) == []
    assert output.plan(target, "--latex").put_text("ours") == target    # planned anew: replaced


def test_a_target_changed_meanwhile_is_not_replaced_unless_forced(tmp_path):
    target = tmp_path / "table.tex"
    target.write_text("old")
    planned = output.plan(target, "--latex")
    replacement = tmp_path / "other.tex"
    replacement.write_text("the other run's table")
    os.replace(replacement, target)
    with pytest.raises(OutputError, match="changed while this run was computing.*pass --force"):
        planned.put_text("ours")
    assert target.read_text() == "the other run's table"
    assert output.plan(target, "--latex", force=True).put_text("ours") == target
    assert target.read_text() == "ours" and leftovers(tmp_path) == []


def test_the_refusal_names_force_in_the_callers_terms(tmp_path):
    # a command-line option or argument (--latex, NAME) takes --force; a Python parameter force=True
    target = tmp_path / "copy.toml"
    target.write_text("edited")
    for option, hint in (("NAME", "pass --force to replace it"), ("--latex", "pass --force to replace it"),
                         ("path", "pass force=True to replace it")):
        with pytest.raises(OutputError) as refused:
            output.plan(target, option, keep_existing=True)
        assert hint in str(refused.value) and ("force=True" in str(refused.value)) == (option == "path")


def test_a_target_changed_after_the_run_started_is_not_replaced(tmp_path):
    """Files planned late (reproduce's figures) are compared with the start of the run; the
    run's own earlier outputs are replaced."""
    target = tmp_path / "figure.png"
    with output.run():
        after_the_start = time.time_ns()
        # file systems stamp changes from a coarse clock (the last timer tick, up to ms behind):
        # the other run changes the file until its stamp is after this run's start
        for _ in range(1000):
            target.write_bytes(b"the other run's figure")
            if target.stat().st_ctime_ns > after_the_start:
                break
            time.sleep(0.001)
        with pytest.raises(OutputError, match="changed after this run started"):
            output.plan(target, "outdir")
        assert output.plan(target, "outdir", force=True).put_text("ours") == target
        assert output.plan(target, "outdir").put_text("ours again") == target   # our own output
    assert target.read_text() == "ours again"


def test_concurrent_run_on_the_command_line(capsys, tmp_path, family, monkeypatch):
    """Two runs writing the same new table: the one finishing second refuses (exit 2)."""
    import symkf.reports.tables as tables
    real = tables.family_table
    out = tmp_path / "out.tex"

    def computed_while_another_run_finishes(*args, **kwargs):
        out.write_text("the other run's table")
        return real(*args, **kwargs)
    monkeypatch.setattr(tables, "family_table", computed_while_another_run_finishes)
    status, _, err = run(capsys, "table", family, "--latex", out)
    assert status == 2 and "appeared while this run was computing" in err and err.count("\n") == 1
    assert out.read_text() == "the other run's table" and leftovers(tmp_path) == []


# -- paths refused, errors translated --------------------------------------------------------------

@pytest.mark.parametrize("argv, message", [
    (["table", "FAMILY", "--latex", ""], "--latex: expected a file path, got ''"),
    (["simulate", "FAMILY", "--paths", "2", "--horizon", "2", "--plot", ""], "--plot: expected a file path"),
    (["reproduce", "sui-theorem12", "--outdir", ""], "--outdir: expected a directory path"),
    (["table", "FAMILY", "--latex", "x" * 300 + ".tex"], "the file name is 304 bytes, above the file system's limit"),
])
def test_bad_paths_are_refused_before_computing(capsys, tmp_path, family, no_table, monkeypatch, argv, message):
    """`--latex ""` exited 0 and wrote nothing; a 300-character name was an OSError (exit 70)."""
    monkeypatch.chdir(tmp_path)
    status, out, err = run(capsys, *[family if a == "FAMILY" else a for a in argv])
    assert status == 2 and out == "" and message in err and err.count("\n") == 1 and len(err) < 400
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fam.toml"]


@pytest.mark.parametrize("path", ["a\0b", b"out.tex", 12, None])
def test_what_is_not_a_path_is_refused(path):
    for call in (lambda: output.plan(path, "--latex"), lambda: output.write_text(path, "x"),
                 lambda: output.plan_directory(path, "--outdir")):
        with pytest.raises(OutputError, match="expected a (file|directory) path, got"):
            call()


@pytest.mark.parametrize("code", [errno.ENOSPC, errno.EACCES, errno.EFBIG, errno.ENAMETOOLONG, errno.EIO])
@pytest.mark.parametrize("where", ["fsync", "replace"])
def test_os_errors_name_the_file_and_leave_nothing(tmp_path, monkeypatch, code, where):
    """Each error of the operating system (simulated: the tests may run as root, whom EACCES
    spares) is an OutputError naming the file; the old file stays and no partial file is left."""
    target = tmp_path / "out.tex"
    target.write_text("old")
    planned = output.plan(target, "--latex")

    def fail(*args, **kwargs):
        raise OSError(code, os.strerror(code))
    monkeypatch.setattr(os, where, fail)
    with pytest.raises(OutputError) as info:
        planned.put_text("new")
    monkeypatch.undo()
    assert str(info.value).startswith(f"--latex {target}: cannot write ({os.strerror(code)})")
    assert target.read_text() == "old" and leftovers(tmp_path) == []


def test_unwritable_directory(tmp_path):
    if os.geteuid() == 0:
        pytest.skip("root writes into read-only directories")
    (tmp_path / "ro").mkdir(mode=0o555)
    with pytest.raises(OutputError, match="is not writable"):
        output.plan(tmp_path / "ro" / "out.tex", "--latex")


def test_interrupted_write_leaves_nothing(tmp_path):
    target = tmp_path / "out.tex"

    def interrupted(f):
        f.write(b"half")
        raise KeyboardInterrupt
    with pytest.raises(KeyboardInterrupt):
        output.plan(target, "--latex").write(interrupted)
    assert list(tmp_path.iterdir()) == []


@pytest.mark.full
def test_figure_under_ulimit_f(tmp_path):
    """Under `ulimit -f 8` a figure was once left truncated (exit 70); a figure (about 20 kB)
    above 8 KiB now fails whole, naming the file, and the old file stays."""
    pytest.importorskip("matplotlib")
    target = tmp_path / "figure.png"
    target.write_bytes(b"old figure")
    script = ("import sys\nfrom matplotlib.figure import Figure\nfrom symkf import output\n"
              "from symkf.errors import OutputError\nfig = Figure()\nfig.add_subplot().plot(range(100))\n"
              "try:\n    output.save_figure(fig, sys.argv[1], 'outdir')\n"
              "except OutputError as exc:\n    print(exc)\n")

    def small_files():
        resource.setrlimit(resource.RLIMIT_FSIZE, (8 * 1024, 8 * 1024))
    proc = subprocess.run([sys.executable, "-c", script, str(target)], capture_output=True, text=True,
                          preexec_fn=small_files, cwd=ROOT, timeout=120)
    assert proc.returncode == 0 and proc.stdout.startswith(f"outdir {target}: cannot write (File too large)")
    assert target.read_bytes() == b"old figure" and leftovers(tmp_path) == []


@pytest.mark.full
def test_reproduce_under_ulimit_f(tmp_path):
    """The command that left a truncated figure: `ulimit -f 8; symkf reproduce sui-theorem12 --outdir rep
    --quick`."""
    pytest.importorskip("matplotlib")

    def small_files():
        resource.setrlimit(resource.RLIMIT_FSIZE, (8 * 1024, 8 * 1024))
    rep = tmp_path / "rep"
    proc = subprocess.run([sys.executable, "-m", "symkf", "reproduce", "sui-theorem12", "--outdir", str(rep),
                           "--quick"], capture_output=True, text=True, preexec_fn=small_files, cwd=ROOT, timeout=300)
    assert proc.returncode == 2 and proc.stdout == ""
    assert proc.stderr == (f"symkf reproduce: outdir {rep / 'sui_theorem12.png'}: cannot write (File too large); "
                           "the previous file, if any, is unchanged and no partial file is left\n")
    assert list(rep.iterdir()) == []


def test_python_writers_go_through_the_writer(tmp_path):
    """Table.write and the plot functions taking ``path`` refuse a link like the command line."""
    pytest.importorskip("matplotlib")
    from symkf.reports import plots
    from symkf.reports.tables import family_table
    (tmp_path / "fam.toml").write_text(FAMILY_TEXT)
    link = tmp_path / "link"
    link.symlink_to(tmp_path / "fam.toml")
    with pytest.raises(OutputError, match="is a symbolic link"):
        family_table(tmp_path / "fam.toml").write(link)
    with pytest.raises(OutputError, match="path .*link: is a symbolic link"):
        plots.critical_angle_figure(max_denominator=2, path=link)
    assert (tmp_path / "fam.toml").read_text() == FAMILY_TEXT
    plots.critical_angle_figure(max_denominator=2, path=tmp_path / "angles.pdf")
    assert (tmp_path / "angles.pdf").read_bytes()[:5] == b"%PDF-" and leftovers(tmp_path) == []


def test_a_copied_example_is_replaced_only_with_force(capsys, tmp_path, monkeypatch):
    """`symkf examples NAME` copies a file for the user to edit: unlike an output, a second copy
    does not replace the first (edited) one without --force."""
    monkeypatch.chdir(tmp_path)
    assert run(capsys, "examples", "ge-two-sensors")[0] == 0
    copy = tmp_path / "ge-two-sensors.toml"
    copy.write_text("# my edits\n")
    status, _, err = run(capsys, "examples", "ge-two-sensors")
    assert status == 2 and "exists (perhaps edited); pass --force" in err and copy.read_text() == "# my edits\n"
    assert run(capsys, "examples", "ge-two-sensors", "--force")[0] == 0 and copy.read_text() != "# my edits\n"


def test_json_reports_the_written_path(capsys, tmp_path, family):
    out = tmp_path / "out.tex"
    status, stdout, _ = run(capsys, "table", family, "--latex", out, "--json")
    assert status == 0 and json.loads(stdout)["latex"] == str(out) and leftovers(tmp_path) == []


# -- nothing else in symkf writes a file -----------------------------------------------------------

#: methods that write a file, whatever the receiver
_WRITING_METHODS = {"savefig", "write_text", "write_bytes", "to_csv", "to_parquet", "to_hdf", "tofile", "touch",
                    "mkdir", "symlink_to", "hardlink_to", "dump_npy"}
#: module functions that write a file (module as imported, name)
_WRITING_FUNCTIONS = {("json", "dump"), ("pickle", "dump"), ("marshal", "dump"), ("toml", "dump"),
                      ("tomli_w", "dump"), ("yaml", "dump"), ("os", "write"), ("os", "replace"), ("os", "rename"),
                      ("os", "link"), ("os", "symlink"), ("os", "makedirs"), ("os", "mkdir"), ("os", "mkfifo"),
                      ("os", "truncate")}
_NUMPY_WRITES = {"save", "savez", "savez_compressed", "savetxt"}
_OPEN_FOR_WRITING = ("O_WRONLY", "O_RDWR", "O_CREAT", "O_APPEND", "O_TRUNC")


def _writes(call: ast.Call) -> str | None:
    """What makes ``call`` a file write, or None."""
    func = call.func
    name = func.attr if isinstance(func, ast.Attribute) else func.id if isinstance(func, ast.Name) else None
    owner = func.value.id if isinstance(func, ast.Attribute) and isinstance(func.value, ast.Name) else None
    if owner == "os" and name == "open":
        flags = ast.unparse(call.args[1]) if len(call.args) > 1 else ""
        return "os.open for writing" if any(f in flags for f in _OPEN_FOR_WRITING) else None
    if name == "open":
        if call.args and ast.unparse(call.args[0]) == "os.devnull":
            return None       # cli.py: stdout to /dev/null once the reader of a pipe has left
        args = call.args[1:] if isinstance(func, ast.Name) else call.args
        mode = args[0] if args else next((k.value for k in call.keywords if k.arg == "mode"), None)
        if mode is None or isinstance(mode, ast.Constant) and not set(str(mode.value)) & set("wax+"):
            return None
        return f"open(..., {ast.unparse(mode)})"
    if owner == "output":
        return None           # symkf.output.write_text, save_figure: the writer itself
    if (owner, name) in _WRITING_FUNCTIONS:
        return f"{owner}.{name}"
    if owner in ("shutil", "tempfile") or owner in ("np", "numpy") and name in _NUMPY_WRITES:
        return f"{owner}.{name}"
    if name in _WRITING_METHODS:
        return name
    # Path.replace(target), Path.rename(target): one argument (str.replace takes two)
    if name in ("replace", "rename") and len(call.args) == 1 and not call.keywords:
        return f".{name}(target)"
    return None


def test_only_the_writer_writes_files():
    """A source scan of symkf/: every file write (open for writing, savefig, write_text, json.dump,
    os.replace, ...) is in symkf/output.py; a new direct write anywhere else fails here."""
    package = ROOT / "symkf"
    found = []
    for path in sorted(package.rglob("*.py")):
        if path == package / "output.py":
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Call) and (what := _writes(node)):
                found.append(f"{path.relative_to(ROOT)}:{node.lineno}: {what}")
    assert found == [], "files written around symkf.output:\n" + "\n".join(found)


def test_the_scan_sees_each_kind_of_write():
    """The scan itself: each form of write is caught, reads are not."""
    caught = ["fig.savefig(p)", "Path(p).write_text('x')", "open(p, 'w')", "open(p, mode='ab')", "json.dump(d, f)",
              "os.replace(a, b)", "np.save(p, a)", "df.to_csv(p)", "os.makedirs(d)", "tempfile.mkstemp()",
              "open(p, m)", "shutil.copy(a, b)", "os.open(p, os.O_WRONLY | os.O_CREAT)", "path.open('wb')",
              "path.replace(target)", "Path(p).mkdir()", "pickle.dump(x, f)"]
    missed = ["output.write_text(p, 'x')", "open(p)", "open(p, 'rb')", "path.open('r')", "path.open()", "json.dumps(d)", "s.replace('a', 'b')",
              "open(os.devnull, 'w')", "sys.stdout.write('x')", "os.open(p, os.O_RDONLY | os.O_NONBLOCK)",
              "d.copy()", "np.asarray(x)"]
    assert [c for c in caught if not _writes(ast.parse(c).body[0].value)] == []
    assert [c for c in missed if _writes(ast.parse(c).body[0].value)] == []


@pytest.mark.full
def test_two_runs_writing_the_same_new_table(tmp_path):
    """Two `symkf table` processes on one new --latex file: the quick run writes it, the slow one
    (started first, finishing last) refuses instead of silently replacing it.  The quick run starts
    once the slow one has used 3 CPU-s (imports and planning take about 1), so the slow run has
    planned its output and refuses when putting it in place; the slow family (five prime
    rotations, three sensors) takes about 30 CPU-s, the quick one about 1."""
    slow = tmp_path / "slow.toml"
    slow.write_text('[family]\nkind = "rotation"\n[grid]\nperiod = [401, 409, 419, 421, 431]\nsensors = [3]\n'
                    '[constants]\nalpha = "2"\n')
    (tmp_path / "fam.toml").write_text(FAMILY_TEXT)
    out = tmp_path / "table.tex"
    caps = ["--max-cyclotomic-degree", "2000", "--max-angle-denominator", "2000"]
    first = subprocess.Popen([sys.executable, "-m", "symkf", "table", str(slow), "--latex", str(out), *caps],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT)
    wait_for(lambda: cpu_seconds(first.pid) >= 3 or first.poll() is not None, 120, "the slow run to plan")
    second = subprocess.run([sys.executable, "-m", "symkf", "table", str(tmp_path / "fam.toml"), "--latex", str(out)],
                            capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert first.poll() is None, "the slow run finished before the quick one: the test proves nothing"
    _, err = first.communicate(timeout=300)
    assert second.returncode == 0 and first.returncode == 2
    assert err == (f"symkf table: --latex {out}: appeared while this run was computing (another run writing the "
                   "same file?); not replaced: pass --force to replace it anyway, or choose another path\n")
    assert "fam" in out.read_text() and leftovers(tmp_path) == []


def _symkf_classes() -> list[type]:
    """Every class defined in an importable symkf module (modules needing a missing extra skipped)."""
    import importlib
    import inspect
    import pkgutil

    import symkf
    from symkf.errors import SymkfError

    found: dict[str, type] = {}
    for info in pkgutil.walk_packages(symkf.__path__, "symkf."):
        if info.name.endswith("__main__"):
            continue
        try:
            module = importlib.import_module(info.name)
        except (ImportError, SymkfError):
            continue
        for _, cls in inspect.getmembers(module, inspect.isclass):
            if cls.__module__ == info.name:
                found[f"{cls.__module__}.{cls.__qualname__}"] = cls
    return list(found.values())


def test_every_class_with_a_json_form_is_a_json_document():
    """A class giving to_json or to_dict gives both, through output.JsonDocument: to_json is
    never a subclass's own (where it returned a dict, or a list)."""
    classes = [c for c in _symkf_classes() if hasattr(c, "to_json") or hasattr(c, "to_dict")]
    assert len(classes) >= 15
    for cls in classes:
        assert issubclass(cls, output.JsonDocument), cls
        assert cls.to_json is output.JsonDocument.to_json, cls


def test_public_objects_give_a_dict_and_json_text():
    import sympy as sp

    import symkf as sk

    S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]], name="s1"), sk.Sensor(C=[[1, 1]], name="s2")])
    loss = sk.IID(["1/10", "1/10"])
    objects = [S, loss, sk.GilbertElliott(fail=["1/20", "1/20"], recover=["1/2", "1/2"]),
               sk.critical_loss_rate(S), sk.stability(S, loss), sk.AlgebraicNumber.from_expr(sp.sqrt(2)),
               sk.design.allocate_channels(S), sk.simulate(S, loss, horizon=5, paths=20, seed=1),
               sk.eigen_blocks(S.A)[0]]
    for obj in objects:
        d, text = obj.to_dict(), obj.to_json()
        assert isinstance(d, dict) and isinstance(text, str), type(obj)
        assert json.loads(text) == json.loads(output.json_text(d)), type(obj)
    # one sensor: the critical rate 1/16 (|lambda| = 2, governing period 2, one row per period:
    # alpha^4 eps = 16 eps = 1)
    one = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]])])
    assert json.loads(sk.critical_loss_rate(one).to_json())["exact"] == "1/16"
    assert json.loads(S.to_json(indent=None))["system"]["A"] == [["0", "-2"], ["2", "0"]]


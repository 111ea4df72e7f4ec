"""The README and the docs work verbatim from a wheel: build it, install it in a fresh virtual
environment, and from a directory outside the source tree run every ``symkf`` command the
README and the docs show (shipped examples are taken by name) and every doctest of the docs'
pages.  One environment serves both, as a user builds it: the core install runs a newcomer's session,
then the extras are added for the pages' commands. The full tier (pip needs a package index)."""

from __future__ import annotations

import re
import subprocess
import sys
import venv

import pytest
from conftest import ROOT

#: the extras the docs' commands need: figures (--plot) and the fusion example's SDP baseline
EXTRAS = "plot,fusion,sdp"


def documented_commands() -> list[str]:
    """Every runnable ``symkf`` command of README.md and docs/*.md, in order, once each: the
    ``$ symkf ...`` lines of code blocks and the inline ``symkf ...`` spans, leaving out
    synopses (placeholders such as FILE, NAME, [--option]) and bare command names."""
    found: list[str] = []
    for page in [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]:
        text = page.read_text(encoding="utf-8")
        spans = re.findall(r"^\$ (symkf .*)$", text, re.M) + re.findall(r"`(symkf [a-z][^`]*)`", text.replace("\n", " "))
        for command in spans:
            words = command.split()
            synopsis = any(w.isupper() or w.startswith("[") or "|" in w or re.fullmatch(r"[A-Z]+\.\w+", w)
                           for w in words[2:]) or "FILE" in command
            # a subcommand, not a quoted message ("symkf table: fam.toml: --scheduler: cannot connect ...")
            runnable = re.fullmatch(r"[a-z]+", words[1]) is not None and (
                words[1] in ("demo", "examples") or (len(words) > 2 and not words[2].startswith("-")))
            if runnable and not synopsis and command not in found:
                found.append(command)
    return found


def test_documented_commands_are_found():
    commands = documented_commands()
    assert "symkf critical rotation-pi12-four-sensors --digits 20" in commands
    assert "symkf verify ge-recovery --jobs 2" in commands
    assert not any("FILE" in c or "NAME" in c for c in commands)


@pytest.fixture(scope="module")
def wheel(tmp_path_factory):
    """The wheel of this source tree, built once for the tests of this file."""
    dist = tmp_path_factory.mktemp("dist")
    subprocess.run([sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", "-w", dist, ROOT], check=True)
    return next(dist.glob("symkf-*.whl"))


def installed(wheel, tmp_path) -> tuple:
    """A fresh virtual environment with the wheel installed (no extras), an empty working
    directory outside the source tree and the environment variables to run it with."""
    env_dir = tmp_path / "venv"
    venv.create(env_dir, with_pip=True)
    python = env_dir / "bin" / "python"
    install(python, wheel)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    return python, elsewhere, {"PATH": f"{env_dir / 'bin'}:/usr/bin:/bin", "HOME": str(tmp_path), "TQDM_DISABLE": "1"}


def install(python, wheel, extras: str = "") -> None:
    """pip-install the wheel (with ``extras``) into ``python``'s environment; modules are compiled
    when first imported, as a user's would be, not all at install."""
    requirement = f"symkf[{extras}] @ {wheel.as_uri()}" if extras else f"symkf @ {wheel.as_uri()}"
    subprocess.run([python, "-m", "pip", "install", "-q", "--no-compile", requirement], check=True)


#: a newcomer's first session on the core install (no extras): copy an example and edit it, sweep the
#: critical recovery rate in a family table, decide the constant-velocity tracker with its singular
#: white-acceleration noise, and ask for a reproduction that needs an extra
NEWCOMER = r"""
set -e
symkf examples ge-two-sensors >/dev/null
sed -i 's|recover = \["1/2", "1/2"\]|recover = ["9/10", "9/10"]|' ge-two-sensors.toml
symkf analyze ge-two-sensors > edited.txt
cat > ge-sweep.toml <<'TOML'
[family]
compute = "critical_recovery_rate"
[grid]
fail = ["1/10", "1/4", "1/2"]
[system]
A = [["0", "-2"], ["2", "0"]]
[[sensors]]
C = [["1", "0"]]
[[sensors]]
C = [["1", "1"]]
[loss]
kind = "gilbert-elliott"
fail = ["fail", "fail"]
recover = ["1/2", "1/2"]
TOML
symkf table ge-sweep.toml --latex ge-sweep.tex > sweep.txt
cat > tracker.toml <<'TOML'
[system]
A = [["1", "1"], ["0", "1"]]
Q = [["1/4", "1/2"], ["1/2", "1"]]
[[sensors]]
C = [["1", "0"]]
[loss]
kind = "iid"
loss = ["9/10"]
TOML
symkf analyze tracker.toml > tracker.txt
set +e
symkf reproduce fusion-pendulum > extra.txt 2>&1
echo "exit $?" >> extra.txt
"""


@pytest.mark.full
def test_a_newcomer_session_runs_on_the_core_install_and_the_documented_commands_with_the_extras(wheel, tmp_path):
    # one environment, in the order a user takes: the core install first, then the extras added
    python, here, env = installed(wheel, tmp_path)
    run = subprocess.run(["bash", "-c", NEWCOMER], cwd=here, env=env, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr[-2000:]
    edited = (here / "edited.txt").read_text()
    assert edited.startswith("read: ge-two-sensors.toml") and "recover 9/10, 9/10" in edited
    assert "\nstable (Theorem" in edited                      # the shipped file (recover 1/2) is NOT stable
    sweep = (here / "sweep.txt").read_text()
    assert "0.525553" in sweep and "0.565084" in sweep and "0.628277" in sweep and (here / "ge-sweep.tex").is_file()
    tracker = " ".join((here / "tracker.txt").read_text().split())   # the text wraps at 100 columns
    assert "stable (Theorem" in tracker and "Q singular, (A, Q^(1/2)) controllable (PBH)" in tracker
    extra = (here / "extra.txt").read_text()
    assert "symkf[fusion]" in extra and extra.rstrip().endswith("exit 2") and "Traceback" not in extra

    install(python, wheel, EXTRAS)
    elsewhere = tmp_path / "docs"
    elsewhere.mkdir()
    failures = []
    for command in documented_commands():
        run = subprocess.run(["bash", "-c", command], cwd=elsewhere, env=env, capture_output=True, text=True)
        if run.returncode != 0:
            failures.append(f"{command}: exit {run.returncode}: {run.stderr.strip()[-300:]}")
    # the pages' doctests, with the installed package (doctest is in the standard library)
    pages = [p for p in sorted((ROOT / "docs").glob("*.md")) if ">>> " in p.read_text(encoding="utf-8")]
    check = ("import doctest, sys\n"
             "fails = sum(doctest.testfile(p, module_relative=False, optionflags=doctest.ELLIPSIS).failed "
             "for p in sys.argv[1:])\nsys.exit(1 if fails else 0)")
    run = subprocess.run([python, "-c", check, *map(str, pages)], cwd=elsewhere, env=env, capture_output=True,
                         text=True)
    if run.returncode != 0:
        failures.append(f"doctests of {[p.name for p in pages]}: {run.stdout[-2000:]}")
    assert failures == []
    assert (elsewhere / "table.tex").is_file() and (elsewhere / "out.png").is_file()

"""The README and the docs work verbatim from a wheel: build it, install it in a fresh virtual
environment, and from a directory outside the source tree run every ``symkf`` command the
README and the docs show (shipped examples are taken by name) and every doctest of the docs'
pages.  The full tier (pip needs a package index; about a minute of installing)."""

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
            runnable = words[1] in ("demo", "examples") or (len(words) > 2 and not words[2].startswith("-"))
            if runnable and not synopsis and command not in found:
                found.append(command)
    return found


def test_documented_commands_are_found():
    commands = documented_commands()
    assert "symkf critical rotation-pi12-four-sensors --digits 20" in commands
    assert "symkf verify ge-recovery --jobs 2" in commands
    assert not any("FILE" in c or "NAME" in c for c in commands)


@pytest.mark.full
def test_readme_and_docs_run_verbatim_from_a_wheel(tmp_path):
    dist = tmp_path / "dist"
    subprocess.run([sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", "-w", dist, ROOT], check=True)
    wheel = next(dist.glob("symkf-*.whl"))
    env_dir = tmp_path / "venv"
    venv.create(env_dir, with_pip=True)
    python = env_dir / "bin" / "python"
    subprocess.run([python, "-m", "pip", "install", "-q", f"symkf[{EXTRAS}] @ {wheel.as_uri()}"], check=True)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    env = {"PATH": f"{env_dir / 'bin'}:/usr/bin:/bin", "HOME": str(tmp_path), "TQDM_DISABLE": "1"}
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

"""The example files shipped in the package (symkf.io.examples): listed and copied by ``symkf
examples``, taken by name by every command, an existing file winning over a name."""

from __future__ import annotations

import json
from pathlib import Path

from conftest import run
from symkf import examples


def test_examples_lists_and_copies(capsys, tmp_path, monkeypatch):
    status, out, _ = run(capsys, "examples")
    assert status == 0
    assert all(e.name in out for e in examples.catalog()) and "families" in out
    status, out, _ = run(capsys, "examples", "--json")
    listed = json.loads(out)["examples"]
    assert [e["name"] for e in listed] == [e.name for e in examples.catalog()]
    assert {e["kind"] for e in listed} == {"system", "network", "fusion", "family"}
    monkeypatch.chdir(tmp_path)
    status, out, _ = run(capsys, "examples", "ge-two-sensors")
    assert status == 0 and (tmp_path / "ge-two-sensors.toml").read_text() == examples.system("ge-two-sensors").read_text()
    status, _, err = run(capsys, "examples", "nope")
    assert status == 2 and "no shipped example 'nope'; known: aperiodic-rotation" in err


def test_every_command_takes_a_shipped_name(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)   # no such files here: the names resolve to the package's
    by_path = run(capsys, "critical", examples.system("ge-two-sensors"), "--vary", "recovery", "--json")
    by_name = run(capsys, "critical", "ge-two-sensors", "--vary", "recovery", "--json")
    assert by_name == by_path and by_name[0] == 0
    assert examples.resolve("quevedo-robot") == examples.system("network/quevedo-robot")
    assert examples.resolve("rotation-periods.toml") == examples.family("rotation-periods")
    (tmp_path / "ge-two-sensors").write_text("not toml")   # an existing file wins over a name
    assert examples.resolve("ge-two-sensors") == Path("ge-two-sensors")
    status, out, err = run(capsys, "analyze", "no-such-thing")
    assert status == 2 and out == "" and "no such file; shipped examples are taken by name" in err


def test_listing_shows_each_summary_as_a_whole_first_sentence(capsys):
    # quevedo-robot's comment: its first sentence ends "uniform on 5..10." on the file's third
    # line, past "Sec. VII-A" (an abbreviation, not a sentence end)
    robot = next(e for e in examples.catalog() if e.name == "quevedo-robot")
    assert robot.summary.startswith("Quevedo, Ahlen, Johansson, Sec. VII-A, Example 4: a robot moving")
    assert robot.summary.endswith("psi_4 uniform on 5..10.")
    status, out, _ = run(capsys, "examples")
    words = " ".join(line.strip() for line in out.splitlines())
    assert status == 0 and not any(line.endswith(" ...") for line in out.splitlines())
    assert all(e.summary in words for e in examples.catalog())
    assert max(map(len, out.splitlines())) <= 100

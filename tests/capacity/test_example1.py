"""Yang et al., Example 1 (symkf.capacity.example1): G_k <= E[P_k^-] <= V_k reproduced, the example
script, and the shipped system file holding the reproduction's data."""

from __future__ import annotations

import subprocess
import sys

from symkf import examples
from symkf.capacity import reproduce_yang_example1
from symkf.io import files

from conftest import ROOT


def test_reproduce_yang_example1(tmp_path):
    out = reproduce_yang_example1(str(tmp_path), horizon=25, paths=4000, seed=7)
    assert out["example"] == "yang-example1" and all(out["checks"].values()), out["checks"]
    assert (tmp_path / "yang_example1.png").stat().st_size > 10_000
    res = out["results"]
    assert res["trace_G"][0] == 0 and res["trace_V"][0] == res["trace_EP"][0] == 2.0


def test_example_script_runs():
    done = subprocess.run([sys.executable, str(ROOT / "examples" / "yang_example1.py"), "--paths", "500"],
                          capture_output=True, text=True, timeout=300, cwd=ROOT)
    assert done.returncode == 0, done.stderr
    assert '"yang-example1"' in done.stdout


SYSTEMS = examples.directory() / "systems"


def test_yang_example1_file_matches_the_reproduction_data():
    from symkf.capacity.example1 import example1_system
    S, loss = files.load(SYSTEMS / "yang-example1.toml")
    S2, loss2 = example1_system()
    assert (S.A, S.C, S.Q, loss.loss) == (S2.A, S2.C, S2.Q, loss2.loss)

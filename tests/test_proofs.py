"""Every file in proofs/ states a claim and exits 0 when its check passes."""

import runpy
import sys
from pathlib import Path

import pytest

PROOFS = sorted(p for p in (Path(__file__).parent.parent / "proofs").glob("*.py"))


@pytest.mark.parametrize("path", PROOFS, ids=[p.stem for p in PROOFS])
def test_proof_passes(path, monkeypatch):
    monkeypatch.setattr(sys, "argv", [str(path)])
    module = runpy.run_path(str(path))
    assert bool(module["main"]()), f"{path.name} printed FAIL"

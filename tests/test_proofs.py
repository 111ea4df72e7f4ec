"""Every file in proofs/ states a claim and exits 0 when its check passes."""

import runpy
import sys
from pathlib import Path

import pytest
from conftest import ROOT

PROOFS = sorted(p for p in (ROOT / "proofs").glob("*.py"))
#: proofs over exhaustive families that take tens of seconds: the ``full`` tier
FULL = {"quevedo_theorem1_sufficient_vs_exact"}


@pytest.mark.parametrize("path", [pytest.param(p, marks=pytest.mark.full) if p.stem in FULL else p for p in PROOFS],
                         ids=[p.stem for p in PROOFS])
def test_proof_passes(path, monkeypatch):
    monkeypatch.setattr(sys, "argv", [str(path)])
    module = runpy.run_path(str(path))
    assert bool(module["main"]()), f"{path.name} printed FAIL"


def test_readme_lists_every_proof():
    readme = (Path(__file__).parent.parent / "proofs" / "README.md").read_text()
    listed = {p.stem for p in PROOFS if f"`{p.name}`" in readme}
    assert listed == {p.stem for p in PROOFS}, f"missing from proofs/README.md: {sorted({p.stem for p in PROOFS} - listed)}"

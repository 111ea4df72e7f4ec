"""Sui-You-Fu, Remark 11: dependent sensors merge into one with arrival 1 - (1 - p_i)(1 - p_j).

Claim: if ``rank col{C_i, C_j} = 1`` (both nonzero), receiving sensor ``i`` is
equivalent to receiving sensor ``j``; the pair can be replaced by one sensor
with loss ``(1 - p_i)(1 - p_j)``, so Assumption 6 loses no generality.

Method: exhaustive check over a stated finite family, exact.  Systems
``2 R(2 pi/m)`` (``m = 3, 4, 6``) and ``2 diag(e^(3 pi i/2), e^(pi i/2))``, sensor
rows ``C = [1, 2]`` and ``C' = c C`` (``c = 2, -1/3``) plus an independent
sensor ``[3, -1]``, losses ``(a, b, 1/5)`` for ``(a, b)`` in ``LOSSES``:
the engine's margin (``symkf.stability``, which does not merge) for the
unmerged system equals its margin for the merged system with loss ``a b``, and
``symkf.second_order`` reports the merge and gives the same margin and the
same critical loss rate as the engine.
"""

from __future__ import annotations

import itertools
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import sympy as sp  # noqa: E402

from symkf import IID, Sensor, System, critical_loss_rate, stability  # noqa: E402
from symkf import second_order as so  # noqa: E402

R = sp.Rational


def rotation(m: int) -> sp.Matrix:
    th = 2 * sp.pi / m
    return sp.Matrix([[2 * sp.cos(th), -2 * sp.sin(th)], [2 * sp.sin(th), 2 * sp.cos(th)]])


MATRICES = [rotation(3), rotation(4), rotation(6), sp.diag(-2 * sp.I, 2 * sp.I)]
LOSSES = [(R(1, 10), R(1, 2)), (R(1, 3), R(1, 3)), (R(1, 2), R(1, 10)), (R(1, 2), R(1, 2))]


def main() -> bool:
    ok = True
    C, other = sp.Matrix([[1, 2]]), sp.Matrix([[3, -1]])
    for A, c in itertools.product(MATRICES, (2, R(-1, 3))):
        pair = System(A=A, sensors=[Sensor(C=C, name="s1"), Sensor(C=c * C, name="s2"), Sensor(C=other, name="s3")])
        cs = so.congruent_sets(pair)
        good = (cs.merges == ((0, 1),) and cs.names[0] == "s1+s2"
                and so.critical_loss_rate(pair) == critical_loss_rate(pair))
        for a, b in LOSSES:
            merged = System(A=A, sensors=[Sensor(C=C), Sensor(C=other)])
            m_pair = stability(pair, IID([a, b, R(1, 5)])).margins[0]
            m_merged = stability(merged, IID([a * b, R(1, 5)])).margins[0]
            v = so.theorem12(pair, IID([a, b, R(1, 5)]))
            good &= m_pair == m_merged == v.margins[0] and any("Remark 11" in s for s in v.assumptions)
        ok &= good
        print(f"{'ok ' if good else 'BAD'} A = {A.tolist()}, C_s2 = {c} C_s1: merged {cs.names}, "
              f"critical loss {so.critical_loss_rate(pair)}")
    print("PASS" if ok else "FAIL")
    return ok


if __name__ == "__main__":
    raise SystemExit(0 if main() else 1)

"""Sui-You-Fu, eq. (35): P(R_{N g}) = u M^N v, checked on examples against enumeration.

Claim: with ``M`` the matrix of eqs. (33)-(34) over (rank-deficient projected
pattern, loss-chain state), the probability that the regression matrix
``O_{N g}`` is rank deficient is ``u M^N v`` (``v`` the start state, ``u`` all
ones), for the projection period ``g`` (the governing period, see
``proofs/sui_theorem12.py``; eq. 35 is printed with ``tau``).

Method: exact brute force on a stated family.  ``symkf.engine.rates.m_matrix`` against
``symkf.engine.rates.probability_rank_deficient`` (all ``2^(d N g)`` receival patterns,
rank of ``O_{N g}`` tested directly), for ``N = 1..4`` with ``d N g <= 12``:

* ``A = 2 R(pi/2)`` (``tau = 4``, ``g = 2``), ``C = [1, 0]``, i.i.d. loss ``eps`` (a symbol);
* the same system under a Gilbert-Elliott channel (fail 1/10, recover 1/2);
* ``A = 2 R(2 pi/3)`` (``g = 3``), ``C_1 = [1, 0]``, ``C_2 = C_1 A`` (congruent), i.i.d. losses (1/3, 1/5).
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import sympy as sp  # noqa: E402

from symkf import IID, GilbertElliott, Sensor, System  # noqa: E402
from symkf.engine.rates import m_matrix, probability_rank_deficient  # noqa: E402
from symkf.engine.blocks import block_rows  # noqa: E402

R = sp.Rational
eps = sp.Symbol("eps", positive=True)
third = sp.Matrix([[-1, -sp.sqrt(3)], [sp.sqrt(3), -1]])  # 2 R(2 pi/3)
CASES = [
    ("2R(pi/2), C = [1, 0], iid eps", System(A=[[0, -2], [2, 0]], sensors=[Sensor(C=[[1, 0]])]), IID([eps])),
    ("2R(pi/2), C = [1, 0], Gilbert-Elliott", System(A=[[0, -2], [2, 0]], sensors=[Sensor(C=[[1, 0]])]),
     GilbertElliott(fail=[R(1, 10)], recover=[R(1, 2)])),
    ("2R(2pi/3), C_2 = C_1 A, iid (1/3, 1/5)",
     System(A=third, sensors=[Sensor(C=[[1, 0]]), Sensor(C=sp.Matrix([[1, 0]]) * third)]), IID([R(1, 3), R(1, 5)])),
]


def main() -> bool:
    ok = True
    for label, S, loss in CASES:
        (br,) = block_rows(S)
        M, _ = m_matrix(br, loss)
        g = br.class_period
        power = sp.eye(M.shape[0])
        for N in range(1, 5):
            if S.d * N * g > 12:
                break
            power = power * M
            u_M_v = sp.expand(sum(power[:, 0]))
            enum = sp.expand(probability_rank_deficient(S, loss, N * g)[0])
            good = sp.simplify(u_M_v - enum) == 0
            ok &= good
            print(f"{'ok ' if good else 'BAD'} {label}: g = {g}, N = {N}: u M^N v = P(R_{N * g}) = "
                  f"{sp.factor(enum) if enum.free_symbols else enum}")
    print("PASS" if ok else "FAIL")
    return ok


if __name__ == "__main__":
    raise SystemExit(0 if main() else 1)

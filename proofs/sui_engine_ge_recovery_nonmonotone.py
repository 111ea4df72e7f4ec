"""Claim checked: under Gilbert-Elliott losses, mean-square stability is NOT monotone in the
recovery probability q = P(received | lost last); a faster-recovering channel can destabilise.

Source: Sui-You-Fu, Theorem 9 and eqs. (33)-(36) (stability under Markov losses iff
alpha^2 rho(M) < 1); the intuition that faster recovery helps (as for the critical loss rate of
i.i.d. losses, which is monotone) is what fails.  symkf.engine.recovery.critical_recovery_rate therefore
refuses (AssumptionError) when the stable set is not an interval (q_c, 1), and
stable_recovery_intervals returns the exact set.

Counterexample: A = (sqrt(6)/2) R(pi/2) (alpha^2 = 3/2, governing period 2), C = [1 0], one
sensor, fail f = 1/2.  Rows C A^k alternate between e1 and e2 directions, so the decisive
patterns lose every packet at one phase.  The restricted two-state transfer over one period is
P diag(0, 1) P (states received, lost), of trace f q + (1 - q)^2, so the margin is
alpha^4 (q/2 + (1 - q)^2) = 9/4 (q/2 + (1 - q)^2) < 1  iff  2/3 < q < 5/6.

Method: (1) symbolic identity: the engine's margin polynomial equals the hand-derived one;
(2) exact stable set from the engine equals (2/3, 5/6); (3) independent check: the Perron root of
the full M matrix (eqs. 33-34, built by symkf.engine.rates.m_matrix over projected patterns and chain
states, no hyperplane shortcut) computed exactly at q = 3/5, 3/4, 9/10 gives alpha^4 rho(M) =
above 1, below 1, above 1; (4) brute force: P(R_N) from enumerating all 2^N loss patterns
(N = 12) is compared with u M^(N/2) v.
"""

import sympy as sp

import symkf as sk
from symkf.engine.rates import m_matrix, perron_root, probability_rank_deficient
from symkf.errors import AssumptionError
from symkf.exact.algebraic import AlgebraicNumber
from symkf.engine.blocks import block_rows
from symkf.engine.region import ge_margins
from symkf.engine.recovery import critical_recovery_rate, stable_recovery_intervals

SYSTEM = sk.System(A=[[0, "-sqrt(6)/2"], ["sqrt(6)/2", 0]], sensors=[sk.Sensor(C=[[1, 0]])])


def main() -> bool:
    q = sp.Symbol("q")
    checks = {}
    margins = ge_margins(SYSTEM, sk.GilbertElliott(["1/2"], [q]))
    checks["margin polynomial"] = margins == [sp.expand(sp.Rational(9, 4) * (q / 2 + (1 - q) ** 2))]
    checks["stable set (2/3, 5/6)"] = stable_recovery_intervals(SYSTEM, ["1/2"]) == (
        (sp.Rational(2, 3), sp.Rational(5, 6)),)
    try:
        critical_recovery_rate(SYSTEM, ["1/2"])
        checks["critical_recovery_rate refuses"] = False
    except AssumptionError:
        checks["critical_recovery_rate refuses"] = True
    (br,) = block_rows(SYSTEM)
    for r, stable in [("3/5", False), ("3/4", True), ("9/10", False)]:
        loss = sk.GilbertElliott(["1/2"], [r])
        M, _ = m_matrix(br, loss)
        margin = AlgebraicNumber.from_expr(sp.Rational(9, 4) * perron_root(M))
        checks[f"full M at q = {r}"] = (margin < 1) is stable
        checks[f"verdict at q = {r}"] = sk.stability(SYSTEM, loss).stable is stable
    loss = sk.GilbertElliott(["1/2"], ["3/4"])
    M, _ = m_matrix(br, loss)
    v = sp.Matrix([1] + [0] * (M.shape[0] - 1))
    checks["eq. 35 against enumeration, N = 12"] = sp.expand(sum(M ** 6 * v)) == \
        probability_rank_deficient(SYSTEM, loss, 12)[0]
    for name, ok in checks.items():
        print(f"{'ok ' if ok else 'BAD'} {name}")
    ok = all(checks.values())
    print("PASS" if ok else "FAIL")
    return ok


if __name__ == "__main__":
    raise SystemExit(0 if main() else 1)

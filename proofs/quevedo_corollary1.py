"""Quevedo-Ahlén-Johansson, Corollary 1 (eq. 24) and its reductions in Sec. VI.

Claims:
(a) one sensor with C_1 of full column rank: Theorem 1's nu_i ||A||^2 equals
    ||A||^2 sum_j p_ij (1 - phi_{1|j})  (eq. 24), since r(k) = gamma_1(k);
(b) B = {1, 2}, phi_{1|1} = 1, phi_{1|2} = 0 (Markovian dropouts): the condition
    becomes ||A||^2 max(p12, p22) < 1, and the loss process is the two-state
    Gilbert-Elliott chain with fail = p12 and recover = p21;
(c) |B| = 1: Pr{gamma_1 = 0} ||A||^2 < 1 (i.i.d. dropouts);
(d) footnote 6: B = {1, 2}, phi = (1, 0), p21 = p11, p12 = p22 gives i.i.d.
    dropouts with probability p22 and the condition p22 ||A||^2 < 1.

Method: symbolic identities in the transition probabilities and phi's
(sympy), through symkf's general Theorem 1 code (J from the exact rank of
C(k)); the loss processes are compared entrywise as exact chains.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import sympy as sp  # noqa: E402

from symkf.model.gilbert_elliott import GilbertElliott  # noqa: E402
from symkf.network import (MarkovNetworkState, NetworkLoss, PeriodicDynamics, SensorTree, corollary1_lhs, phi_symbol,
                           theorem1)

p12, p21 = sp.symbols("p12 p21", positive=True)
A = [[2, 1], [0, "1/2"]]
DYN = PeriodicDynamics(A, [[[1, 0], [0, 1]]])


def _report(name: str, ok: bool) -> bool:
    print(("PASS" if ok else "FAIL") + f": {name}")
    return ok


def main() -> bool:
    ok = True
    tree = SensorTree([0])
    P = [[1 - p12, p12], [p21, 1 - p21]]
    loss = NetworkLoss(tree, MarkovNetworkState(P, initial=[1, 0]), "symbols")
    t1 = theorem1(loss, DYN)
    a2 = t1.norms[0].exact
    cor = corollary1_lhs(sp.Matrix(P), [phi_symbol(1, 1), phi_symbol(1, 2)], DYN.A[0])
    ok &= _report("(a) Theorem 1 with M = 1 equals eq. (24)",
                  all(sp.expand(t1.lhs[(i, 0)] - cor[i - 1]) == 0 for i in (1, 2)))
    ge = {phi_symbol(1, 1): 1, phi_symbol(1, 2): 0}
    reduced = [sp.expand(c.subs(ge)) for c in cor]
    ok &= _report("(b) phi = (1, 0): ||A||^2 p_i2 for i = 1, 2, i.e. ||A||^2 max(p12, p22)",
                  reduced == [sp.expand(a2 * p12), sp.expand(a2 * (1 - p21))])
    gel = NetworkLoss(tree, MarkovNetworkState(P, initial=[1, 0]), [[1, 0]]).as_markov_loss()
    ref = GilbertElliott(fail=[p12], recover=[p21], initial_received=[1])
    ok &= _report("(b) the receival process is Gilbert-Elliott(fail = p12, recover = p21)",
                  sp.simplify(gel.chain.P - ref.chain.P) == sp.zeros(2, 2)
                  and sp.simplify(gel.chain.initial - ref.chain.initial) == sp.zeros(1, 2))
    iid = theorem1(NetworkLoss(tree, MarkovNetworkState([[1]]), "symbols"), DYN)
    ok &= _report("(c) |B| = 1: (1 - phi_{1|1}) ||A||^2",
                  sp.expand(iid.lhs[(1, 0)] - (1 - phi_symbol(1, 1)) * a2) == 0)
    e = sp.Symbol("e", positive=True)  # the dropout probability p22 = p12
    fn6 = [[1 - e, e], [1 - e, e]]
    l6 = NetworkLoss(tree, MarkovNetworkState(fn6, initial=[1 - e, e]), [[1, 0]])
    c6 = theorem1(l6, DYN)
    m6 = l6.as_markov_loss()
    iid_chain = all(sp.simplify(m6.chain.P[r, s] - (1 - e if m6.chain.emit[s] == (1,) else e)) == 0
                    for r in range(2) for s in range(2))
    ok &= _report("(d) footnote 6: i.i.d. dropouts with probability p22 and condition p22 ||A||^2",
                  iid_chain and all(sp.expand(c6.lhs[(i, 0)] - e * a2) == 0 for i in (1, 2)))
    print("PASS" if ok else "FAIL")
    return ok


if __name__ == "__main__":
    raise SystemExit(0 if main() else 1)

"""Claim checked: what the fusion paper's (arXiv:2012.04896) Problem 3 ("Transformed linear programming") really is.

Source: Optimal linear sensor fusion over lossy channels (arXiv:2012.04896), Problem 3 (eq. 22) and Theorem 1, Appendix D:
``max 1/2 tr(Lambda_1)`` s.t. ``W' V_o = I``, ``2 Sigma W = V_o Lambda_1'``,
said to be the dual of Problem 2 and a linear program.

Finding: its constraints are exactly the KKT conditions of Problem 1, and on
them ``Lambda_1' = W' V_o Lambda_1' = 2 W' Sigma W``, so the objective equals
``tr(W' Sigma W)`` and is the same at every feasible point: Problem 3 is a
(consistent, rank-deficient) linear system, not an optimisation problem, and
not the Lagrange dual of Problem 2 (whose dual function involves
``Vo' Sigma^+ Vo``, a concave quadratic in Lambda_1).  Solving it is solving
the KKT system, which is what ``optimal_weights(method="problem3")`` does.

Method: exact (sympy ``linsolve``) on the instances of
``proofs/fusion_closed_form.py``: the general solution of the constraint
system is computed with its free parameters, and ``tr(Lambda_1)/2`` is shown
to be a constant (no free parameter left) equal to ``tr(W*' Sigma W*)`` of
Theorem 2's closed form.
"""

import random
import sys
from pathlib import Path

import sympy as sp

sys.path.insert(0, str(Path(__file__).resolve().parent))
from fusion_closed_form import instance  # noqa: E402


def main() -> bool:
    rng = random.Random(3)
    ok, checked = True, 0
    for k in range(12):
        Sigma, Vo = instance(rng)
        if Vo.rank() < 2:
            continue
        nN = Sigma.shape[0]
        W = sp.Matrix(nN, 2, lambda i, j: sp.Symbol(f"w{i}_{j}"))
        L = sp.Matrix(2, 2, lambda i, j: sp.Symbol(f"l{i}_{j}"))
        eqs = list(W.T * Vo - sp.eye(2)) + list(2 * Sigma * W - Vo * L.T)
        unknowns = list(W) + list(L)
        (sol,) = sp.linsolve(eqs, unknowns)
        sub = dict(zip(unknowns, sol))
        objective = sp.simplify(L.subs(sub).trace() / 2)
        free = objective.free_symbols
        M = sp.eye(nN) - Vo * Vo.pinv()
        Wc = (sp.eye(nN) - (M * Sigma * M).pinv() * M * Sigma) * Vo.T.pinv()
        optimum = sp.simplify((Wc.T * Sigma * Wc).trace())
        n_free = len(set().union(*[sp.sympify(s).free_symbols for s in sol]))
        good = not free and sp.simplify(objective - optimum) == 0
        ok &= good
        checked += 1
        print(f"instance {k}: feasible set has {n_free} free parameters, objective = {objective} "
              f"(constant: {not free}), Theorem 2 optimum = {optimum}")
    ok &= checked >= 8
    print("PASS" if ok else "FAIL")
    return ok


if __name__ == "__main__":
    raise SystemExit(0 if main() else 1)

"""The programmes of design queries: the cheapest set meeting covering constraints (an integer
programme) and the cheapest channel qualities meeting linear ones (a linear programme).

Both run on HiGHS through SciPy (``scipy.optimize.milp`` and ``linprog``) when SciPy is installed
(the ``design`` extra), else on a pure-Python fallback: a depth-first branch and bound with
fractional-knapsack bounds for the covering programme, SymPy's exact simplex
(``sympy.solvers.simplex.linprog``) for the linear one.  Their answers only propose: the design
queries decide what they return with the exact engine (:mod:`symkf.design.constraints`).
"""
from __future__ import annotations

import math
from fractions import Fraction
from typing import Sequence

from ..arguments import check_public
from ..errors import InputError


def _scipy():
    try:
        from scipy import optimize
    except ImportError:
        return None
    return optimize


def _relaxed(rows: Sequence[Sequence[float]], needs: Sequence[float], tol: float):
    """Rows with infinite weights capped (one such sensor meets the row alone) and needs relaxed by ``tol``."""
    out = []
    for w, need in zip(rows, needs):
        top = need + 1.0
        out.append(([min(x, top) for x in w], need - tol * (1.0 + abs(need))))
    return out


def cheapest_cover(costs: Sequence[float], rows: Sequence[Sequence[float]], needs: Sequence[float],
                   tol: float, solver: str = "auto") -> tuple[int, ...] | None:
    """The cheapest set ``T`` of indices with ``sum_{j in T} rows[c][j] >= needs[c] - tol`` for every
    row ``c`` (ties: the first found), or None when even all indices fall short.

    ``solver``: ``"highs"`` (SciPy's ``milp``, exact gap 0), ``"python"`` (branch and bound) or
    ``"auto"`` (HiGHS when SciPy is installed)."""
    data = _relaxed(rows, needs, tol)
    d = len(costs)
    if any(sum(w) < need for w, need in data):
        return None
    optimize = _scipy() if solver in ("auto", "highs") else None
    if solver == "highs" and optimize is None:
        raise InputError("solver: 'highs' needs SciPy (pip install 'symkf[design]'); 'python' needs nothing")
    if not data:
        return tuple(j for j in range(d) if costs[j] <= 0)
    if optimize is not None:
        import numpy as np
        W = np.array([w for w, _ in data])
        lb = np.array([need for _, need in data])
        res = optimize.milp(np.array(costs, dtype=float),
                            constraints=optimize.LinearConstraint(W, lb, np.inf),
                            integrality=np.ones(d), bounds=optimize.Bounds(0, 1),
                            options={"mip_rel_gap": 0.0})
        if res.x is None:
            return None
        return tuple(j for j in range(d) if res.x[j] > 0.5)
    return _branch_and_bound(list(costs), data)


def _branch_and_bound(costs: list[float], data: list[tuple[list[float], float]]) -> tuple[int, ...] | None:
    d = len(costs)
    free = [j for j in range(d) if costs[j] <= 0]    # costless sensors never hurt: monotone
    order = sorted((j for j in range(d) if costs[j] > 0), key=lambda j: costs[j])
    by_ratio = [sorted((j for j in range(d) if w[j] > 0), key=lambda j: costs[j] / w[j]) for w, _ in data]
    best: list = [math.inf, None]
    position = {j: p for p, j in enumerate(order)}

    def bound(p: int, sums: list[float]) -> float:
        """Fractional knapsack per unmet row over the undecided indices (order[p:]): a lower bound."""
        worst = 0.0
        for c, (w, need) in enumerate(data):
            short = need - sums[c]
            if short <= 0:
                continue
            cost = 0.0
            for j in by_ratio[c]:
                if j in free or position[j] < p:
                    continue
                if w[j] >= short:
                    cost += costs[j] * short / w[j]
                    short = 0.0
                    break
                cost += costs[j]
                short -= w[j]
            if short > 0:
                return math.inf
            worst = max(worst, cost)
        return worst

    def visit(p: int, chosen: list[int], cost: float, sums: list[float]) -> None:
        if all(s >= need for s, (_, need) in zip(sums, data)):
            if cost < best[0]:
                best[0], best[1] = cost, tuple(sorted(chosen + free))
            return
        if p == len(order) or cost + bound(p, sums) >= best[0]:
            return
        j = order[p]
        visit(p + 1, chosen + [j], cost + costs[j], [s + w[j] for s, (w, _) in zip(sums, data)])
        visit(p + 1, chosen, cost, sums)

    start = [sum(w[j] for j in free) for w, _ in data]
    visit(0, [], 0.0, start)
    return best[1]


def cheapest_point(costs: Sequence[Fraction], rows: Sequence[Sequence[int]], needs: Sequence[Fraction],
                   solver: str = "auto") -> tuple[list[float], Fraction]:
    """``min costs . x`` over ``rows x >= needs, x >= 0`` (integer rows, rational costs and needs):
    a minimiser and a lower bound of the optimum that holds exactly.  HiGHS's dual values ``y``,
    clipped at 0 and scaled until ``rows^T y <= costs`` holds in rationals, bound it by weak
    duality (``needs . y``); the fallback's exact simplex gives the optimum itself."""
    if not costs or len(needs) != len(rows) or any(len(row) != len(costs) for row in rows):
        raise InputError(f"rows: expected one row of {len(costs)} integers (one per cost) for each of the "
                         f"{len(needs)} needs, and at least one cost")
    optimize = _scipy() if solver in ("auto", "highs") else None
    if solver == "highs" and optimize is None:
        raise InputError("solver: 'highs' needs SciPy (pip install 'symkf[design]'); 'python' needs nothing")
    if optimize is not None:
        import numpy as np
        res = optimize.linprog(np.array([float(c) for c in costs]), A_ub=-np.array(rows, dtype=float),
                               b_ub=-np.array([float(b) for b in needs]), bounds=(0, None), method="highs")
        if res.status != 0:
            raise InputError(f"the channel-allocation programme has no solution ({res.message})")
        y = [Fraction(max(-float(v), 0.0)) for v in res.ineqlin.marginals]
        used = [sum((y[c] * rows[c][j] for c in range(len(y))), Fraction(0)) for j in range(len(costs))]
        scale = min([Fraction(1)] + [c / u for c, u in zip(costs, used) if u > 0])
        return [float(v) for v in res.x], max(Fraction(0), scale * sum((a * b for a, b in zip(y, needs)), Fraction(0)))
    import sympy as sp
    from sympy.solvers.simplex import linprog    # min c.x over A x <= b, x >= 0, exactly
    value, point = linprog([sp.Rational(c.numerator, c.denominator) for c in costs],
                           A=[[-int(k) for k in row] for row in rows],
                           b=[-sp.Rational(n.numerator, n.denominator) for n in needs])
    return [float(v) for v in point], Fraction(int(value.p), int(value.q))


check_public(globals())

"""Capacity conditions against exact critical loss rates (Yang et al., Theorems 2, 5 and 6).

For ``N`` sensors sharing one i.i.d. loss probability ``eps`` the capacity is
``C = -(N/2) ln eps``, so each capacity condition is a loss threshold:

* ``ln rho(A)`` (Theorem 2, necessary): stability forces ``eps < rho(A)^{-2/N}``;
* ``h(A)`` (Theorem 6's level): ``C > h(A)`` iff ``eps < M(A)^{-2/N}``; it
  guarantees a *good allocation* exists, not stability at equal rates;
* Theorem 5's per-sensor test (sufficient for ``V_k``, hence for stability):
  ``eps < min_i exp(-2 r_i)``, ``r_i = max_j h(A_ij)``, best over row orders.

The exact critical ``eps*`` comes from the exact engine
(``symkf.engine.stability.critical_loss_rate``); these functions take it as input so
that they can be checked against hand-derived values.
"""

from __future__ import annotations

import itertools
from typing import Any, Sequence

import sympy as sp

from .. import budget
from ..arguments import check_public
from ..exact.algebraic import AlgebraicNumber
from ..model.loss import LossModel
from ..model.system import System
from .lower import lower_bound_converges
from ..exact.spectral import spectral_radius
from .quantities import _require_iid, capacity_exceeds, mahler_measure
from .theorems import theorem5_sufficient, wonham_decomposition

def _orders(system: System) -> list[list[tuple[int, int]] | None]:
    rows = [(i, r) for i, s in enumerate(system.sensors) for r in range(s.m)]
    return [list(p) for p in itertools.permutations(rows)] if len(rows) <= budget.LIMITS.max_order_rows else [None]


def theorem5_common_threshold(system: System) -> AlgebraicNumber:
    """The largest common loss allowed by Theorem 5's per-sensor test, ``min_i max_j M(A_ij)^{-2}``,
    maximised over row orders (all orders up to ``budget.Limits.max_order_rows`` rows, else the given one)."""
    best = None
    for order in _orders(system):
        dec = wonham_decomposition(system, order)
        worst = max(dec.requirement(i) for i in range(system.d))
        best = worst if best is None or worst < best else best
    return 1 / (best * best)  # in AlgebraicNumber arithmetic: best.exact may be a root of degree C(n, k)


def _num(x: AlgebraicNumber) -> dict[str, Any]:
    return {"exact": str(x.exact), "decimal": float(x)}


def critical_loss_comparison(system: System, critical_loss: Any) -> dict[str, Any]:
    """Common-rate thresholds from ``ln rho``, ``h(A)`` and Theorem 5 beside the exact ``eps*``.

    ``tight_*`` says whether a threshold equals ``eps*`` exactly; ``consistent``
    whether the necessary one is ``>= eps*`` and Theorem 5's is ``<= eps*``.
    """
    N = system.d
    exact = AlgebraicNumber.from_expr(critical_loss.exact if isinstance(critical_loss, AlgebraicNumber)
                                      else critical_loss)
    rho_t = AlgebraicNumber.from_expr(sp.radsimp(spectral_radius(system.A).exact ** sp.Rational(-2, N)))
    h_t = AlgebraicNumber.from_expr(sp.radsimp(mahler_measure(system.A).exact ** sp.Rational(-2, N)))
    t5 = theorem5_common_threshold(system)
    return {
        "system": system.name or "", "sensors": N,
        "exact": _num(exact), "ln_rho": _num(rho_t), "entropy": _num(h_t), "theorem5": _num(t5),
        "tight_ln_rho": rho_t == exact, "tight_entropy": h_t == exact, "tight_theorem5": t5 == exact,
        "entropy_sufficient_here": h_t <= exact,
        "consistent": rho_t >= exact and t5 <= exact,
    }


def verdict_comparison(system: System, loss: LossModel, exact_stable: bool) -> dict[str, Any]:
    """For given (possibly unequal) rates: which capacity conditions hold, beside the exact verdict."""
    nec = lower_bound_converges(system, loss)
    t5 = theorem5_sufficient(system, loss)
    return {
        "loss": [str(e) for e in _require_iid(loss)], "exact_stable": exact_stable,
        "C_gt_ln_rho": nec, "C_gt_entropy": capacity_exceeds(loss, mahler_measure(system.A)),
        "theorem5_per_sensor": t5,
        "consistent": (nec or not exact_stable) and (exact_stable or not t5),
    }


def comparison_table(rows: Sequence[dict[str, Any]]) -> str:
    """A Markdown table of :func:`critical_loss_comparison` rows."""
    def cell(r: dict, key: str) -> str:
        mark = " (tight)" if r.get(f"tight_{key}") else ""
        return f"{r[key]['exact']} ≈ {r[key]['decimal']:.4g}{mark}"
    out = ["| system | N | exact eps* | ln rho(A): eps < rho^(-2/N) | h(A): eps < M^(-2/N) | Theorem 5 per sensor |",
           "|---|---|---|---|---|---|"]
    for r in rows:
        out.append(f"| {r['system']} | {r['sensors']} | {r['exact']['exact']} ≈ {r['exact']['decimal']:.4g} | "
                   f"{cell(r, 'ln_rho')} | {cell(r, 'entropy')} | {cell(r, 'theorem5')} |")
    return "\n".join(out)

check_public(globals())

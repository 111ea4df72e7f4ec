"""Mo, Sinopoli, "Kalman filtering with intermittent observations: tail distribution and critical
value", IEEE TAC 57(3), 2012 (and "Towards finding the critical value for Kalman filtering with
intermittent observations", arXiv:1005.2442, 2010).

* Non-degenerate systems: ``A`` diagonalizable and every *equiblock* (the eigenvalues of one
  modulus) one-step observable (``C`` times the block's eigenvectors of full column rank);
  then ``eps_c = 1/rho(A)^2`` (i.i.d.), and over a Gilbert-Elliott channel the filter is stable
  iff ``(1 - q) rho(A)^2 < 1`` with ``q = P(received | lost last)``, symkf's ``recover``
  (a loss run continues with probability ``1 - q``).
* The degenerate second-order case: two eigenvalues of modulus ``r`` whose ratio is a primitive
  ``p``-th root of unity, one measurement row: ``eps_c = r^(-2p/(p-1))``.  Checked here by
  the hyperplane argument: rows ``C A^k`` and ``C A^j`` are dependent iff ``k = j (mod p)``,
  so the estimate stays singular iff every received packet has one residue mod ``p``, with
  probability ``~ eps^(N (p - 1)/p)`` over ``N`` steps; ``p`` is the block's governing period
  (least ``k`` with ``A^k`` a scalar multiple of ``I``), not the period ``tau``.
"""

from __future__ import annotations

import sympy as sp

from ..arguments import check_public
from ..exact.linalg import rank
from ..model.system import System
from ..exact.spectral import spectral_radius
from . import hypotheses as hyp
from .row import EXACT, Hypothesis, Quantity, Row, number, row
from .sinopoli import inverse_rho_squared

CITATION = ("Y. Mo, B. Sinopoli, \"Kalman filtering with intermittent observations: tail distribution "
            "and critical value\", IEEE Trans. Autom. Control 57(3), 2012")


def _non_degenerate(system: System, quantity: Quantity, channel: Hypothesis) -> list[Hypothesis]:
    return [hyp.one_sensor(system), channel, hyp.unstable(system), hyp.controllable_noise(system),
            hyp.diagonalizable(system), hyp.non_degenerate(system)]


def non_degenerate(system: System, quantity: Quantity) -> Row:
    """``eps_c = 1/rho(A)^2`` for non-degenerate systems (i.i.d.)."""
    return row("mo-sinopoli", "Mo, Sinopoli 2012, non-degenerate", CITATION,
               "eps_c = 1/rho(A)^2 for non-degenerate (A, C)", EXACT,
               _non_degenerate(system, quantity, hyp.iid(quantity)), quantity, inverse_rho_squared(system, quantity))


def gilbert_elliott(system: System, quantity: Quantity) -> Row:
    """Stable iff ``(1 - q) rho(A)^2 < 1``: the set ``q > 1 - 1/rho(A)^2`` (non-degenerate)."""
    rho = spectral_radius(system.A)
    q = 1 - 1 / rho.exact ** 2
    return row("mo-sinopoli-ge", "Mo, Sinopoli 2012, Gilbert-Elliott", CITATION,
               "stable iff (1 - q) rho(A)^2 < 1, q = P(received | lost last), non-degenerate (A, C)", EXACT,
               _non_degenerate(system, quantity, hyp.gilbert_elliott(quantity)), quantity,
               lambda: (quantity.above(q), number(q)))


def degenerate_pair(system: System) -> list[Hypothesis]:
    """Two simple eigenvalues of one modulus and one independent measurement row."""
    out = [hyp.second_order(system)]
    if system.n != 2:
        return out
    blocks = system.eigen_blocks()
    pair = len(blocks) == 1 and len(blocks[0].members) == 2
    found = ", ".join(str(e) for b in blocks for e in b.eigenvalues)
    out.append(Hypothesis("equal-modulus pair", pair,
                          "two distinct eigenvalues of one modulus" if pair else f"eigenvalues {found}"))
    r = rank(sp.Matrix(system.C))
    out.append(Hypothesis("rank C = 1", r == 1, f"one independent measurement row (degenerate): rank C = {r}"))
    return out


def ratio_order(system: System) -> int | None:
    """``p``: the order of ``lambda_1 / lambda_2`` as a root of unity (the governing period), or None."""
    return system.eigen_blocks()[0].governing_period


def degenerate(system: System, quantity: Quantity) -> Row:
    """``eps_c = r^(-2p/(p-1))`` for the degenerate second-order system."""
    hyps = [hyp.one_sensor(system), hyp.iid(quantity), *degenerate_pair(system)]
    if all(h.holds for h in hyps):
        block = system.eigen_blocks()[0]
        p = ratio_order(system)
        hyps.append(Hypothesis("periodic ratio", p is not None,
                               f"lambda_1/lambda_2 a root of unity of order p = {p}" if p is not None else block.proof))
    r = spectral_radius(system.A).exact

    def value() -> tuple:
        p = ratio_order(system)
        v = sp.radsimp(r ** sp.Rational(-2 * p, p - 1))
        return quantity.below(v), number(v)

    return row("mo-sinopoli-degenerate", "Mo, Sinopoli 2012, degenerate", CITATION,
               "eps_c = r^(-2p/(p-1)), lambda_1/lambda_2 a primitive p-th root of unity", EXACT,
               hyps, quantity, value)


ROWS = (non_degenerate, gilbert_elliott, degenerate)


check_public(globals())

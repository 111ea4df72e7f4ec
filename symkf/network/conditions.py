"""Sufficient conditions for Markov network states (Quevedo-Ahlén-Johansson, Sec. V-VI).

* ``r(k) = 1`` iff ``C(k)`` (eq. 14) has full column rank (eq. 19); ``J`` is the
  set of link-outcome vectors ``gamma(k)`` with ``r(k) = 1`` (Example 3),
  found with the exact rank or from a user's rule on ``theta``.
* ``Pr{r(k) = 1 | Xi = j} = sum_{g in J} prod_m phi_{m|j}^{g_m} (1 - phi_{m|j})^{1 - g_m}``.
* ``nu_i = sum_j p_ij Pr{r(k) = 0 | Xi(k) = j}`` (eqs. 20-21).
* Theorem 1 (eq. 22): exponential boundedness if
  ``rho* = max_{i, k} nu_i ||A(k)||^2 < 1``; ``rho*`` is the smallest
  admissible ``rho``.
* Corollary 1 (eq. 24): one sensor, ``C_1`` full column rank, ``r = gamma_1``.
"""

from __future__ import annotations

import itertools
import math
import sys
from dataclasses import dataclass
from typing import Callable, Sequence

import sympy as sp

from .. import budget
from ..arguments import check_public
from ..errors import AssumptionError, InputError
from ..exact.algebraic import AlgebraicNumber
from ..exact.linalg import echelon_extended, field_of, rank, span_key
from ..exact.numbers import to_exact_matrix
from .dynamics import PeriodicDynamics, spectral_norm_squared
from .loss import NetworkLoss, bernoulli_product
from .state import MarkovNetworkState
from .tree import SensorTree, Vector

Rule = Callable[[Vector], bool]


def full_rank_configurations(tree: SensorTree, dynamics: PeriodicDynamics | None = None,
                             rule: Rule | None = None) -> tuple[Vector, ...]:
    """The set ``J`` of ``gamma`` vectors for which ``C(k)`` has full column rank (Example 3).

    Either ``dynamics`` (exact rank of ``C(k)``, eq. 14) or ``rule(theta) -> bool``
    decides; vectors are listed in increasing lexicographic order, as in the paper: all
    ``2^M`` are visited, refused above ``budget.Limits.max_patterns`` (``Pr{r = 1}`` itself
    needs no listing: :func:`full_rank_probability_of`).
    """
    if (dynamics is None) == (rule is None):
        raise InputError("give exactly one of dynamics (exact rank of C(k)) or rule(theta) -> bool")
    if dynamics is not None and dynamics.M != tree.M:
        raise InputError(f"dynamics: {dynamics.M} sensor blocks C_m for a tree of {tree.M} sensors")
    budget.check("max_patterns", 2 ** tree.M, "tree", f"the 2^{tree.M} link-outcome vectors gamma that listing J visits")
    cache: dict[Vector, bool] = {}

    def full(theta: Vector) -> bool:
        if theta not in cache:
            cache[theta] = (bool(rule(theta)) if rule is not None
                            else rank(dynamics.C_of(theta)) == dynamics.n)
        return cache[theta]

    return tuple(g for g in itertools.product((0, 1), repeat=tree.M) if full(tree.theta(g)))


def full_rank_probability_of(tree: SensorTree, dynamics: PeriodicDynamics, phi: Sequence[sp.Expr]) -> sp.Expr:
    """``Pr{r(k) = 1}``: the probability that ``C(k)`` (eq. 14) has full column rank when link ``m``
    succeeds with probability ``phi[m - 1]``, independently (Example 3's sum over ``J``, with
    :func:`full_rank_probability`), without listing the ``2^M`` vectors ``gamma``.

    The sensors are visited in depth-first order from the gateway: sensor ``m``'s rows join the
    span of those received so far when its link succeeds, and its whole subtree is passed over
    when it fails (``theta = 0`` below a failed link, Remark 2).  The probability of full rank from
    a sensor on depends only on the span so far (exact, the reduced echelon basis over the field
    of the ``C_m``), so each (sensor, span) is solved once: at most ``sum_{k < n} C(M + 1, k + 1)``
    states (a span of rank ``r`` is spanned by at most ``r`` of the sensors before it; rows in
    general position reach the bound), refused above ``budget.Limits.max_span_states`` before
    the search starts.
    Full rank is reached with probability 1 from a full span, 0 when too few rows are left.
    The result is a polynomial in the ``phi`` (expanded).
    """
    if dynamics.M != tree.M:
        raise InputError(f"dynamics: {dynamics.M} sensor blocks C_m for a tree of {tree.M} sensors")
    if len(phi) != tree.M:
        raise InputError(f"phi: {len(phi)} link probabilities for a tree of {tree.M} sensors")
    n = dynamics.n
    budget.check("max_span_states", sum(math.comb(tree.M + 1, k + 1) for k in range(n)), "tree",
                 f"the (sensor, span) states of Pr{{C(k) of full column rank}} for {tree.M} sensors in dimension {n} "
                 f"(at most sum_{{k < n}} C(M + 1, k + 1): rows in general position reach it)")
    K = field_of(*dynamics.C)
    rows = [K.matrix(C) for C in dynamics.C]
    order: list[int] = []
    after: list[int] = []

    def visit(m: int) -> None:   # depth-first from the gateway; after[i]: the first node past i's subtree
        for c in tree.children(m):
            i = len(order)
            order.append(c)
            after.append(0)
            visit(c)
            after[i] = len(order)
    visit(0)
    left = [0] * (tree.M + 1)   # rows of the sensors from position i on: an upper bound of what can join
    for i in range(tree.M - 1, -1, -1):
        left[i] = left[i + 1] + len(rows[order[i] - 1])
    values = list(dict.fromkeys(phi))
    ring, *gens = sp.polys.rings.ring([f"phi{k}" for k in range(len(values))], sp.QQ)
    link = [gens[values.index(p)] for p in phi]
    memo: dict = {}

    def full(i: int, basis: dict):
        if len(basis) == n:
            return ring.one
        if len(basis) + left[i] < n:
            return ring.zero
        state = (i, span_key(basis))
        if state not in memo:
            m = order[i]
            x = link[m - 1]
            memo[state] = x * full(i + 1, echelon_extended(K, basis, rows[m - 1], n)) + (1 - x) * full(after[i], basis)
        return memo[state]

    depth = sys.getrecursionlimit()
    sys.setrecursionlimit(max(depth, 4 * tree.M + 100))   # one level per sensor, a few frames each
    try:
        poly = full(0, {})
    finally:
        sys.setrecursionlimit(depth)
    return sp.expand(poly.as_expr().xreplace(dict(zip(ring.symbols, values))))


def is_up_set(J: Sequence[Vector]) -> bool:
    """Whether ``J`` is closed under turning links on (then Pr{r = 1} grows with every phi)."""
    members = set(J)
    return all(g[:m] + (1,) + g[m + 1:] in members for g in members for m in range(len(g)))


def full_rank_probability(J: Sequence[Vector], phi: Sequence[sp.Expr]) -> sp.Expr:
    """``Pr{r(k) = 1 | Xi = j}`` given the column ``phi = (phi_{1|j}, ..., phi_{M|j})`` (Example 3)."""
    return sp.Add(*[bernoulli_product(g, phi) for g in J])


def _markov(loss: NetworkLoss) -> MarkovNetworkState:
    if not isinstance(loss.state, MarkovNetworkState):
        raise AssumptionError("the network state is semi-Markov", assumption="Assumption 1 (Quevedo et al.)",
                              applies_instead="symkf.network.semi_markov.theorem2")
    return loss.state


def nu(loss: NetworkLoss, J: Sequence[Vector], phi: sp.MatrixBase | None = None) -> tuple[sp.Expr, ...]:
    """``nu_i = sum_j p_ij (1 - Pr{r = 1 | Xi = j})`` for ``i = 1..|B|`` (eq. 21)."""
    return _nu(loss, lambda column: full_rank_probability(J, column), phi)


def _nu(loss: NetworkLoss, probability: Callable[[list], sp.Expr], phi: sp.MatrixBase | None) -> tuple[sp.Expr, ...]:
    """:func:`nu` with ``Pr{r = 1 | Xi = j}`` from ``probability(phi column j)``."""
    st = _markov(loss)
    phi = loss.phi if phi is None else phi
    miss = [1 - probability(list(phi.col(j))) for j in range(st.B)]
    return tuple(sp.expand(sum(st.p(i, j) * miss[j - 1] for j in range(1, st.B + 1)))
                 for i in range(1, st.B + 1))


@dataclass(frozen=True)
class Theorem1:
    """Theorem 1 of Quevedo et al. evaluated on a network model.

    ``lhs[(i, k)] = nu_i ||A(k)||^2``; ``rho`` is their maximum, the smallest
    admissible ``rho`` in (22); ``holds`` says ``rho < 1``.  ``nu`` is
    evaluated at ``phi_lower`` when some ``phi`` came from quadrature
    (``certified_by_bounds``): ``J`` is an up-set, so this can only raise ``nu``.
    With symbolic data ``rho`` and ``holds`` are None and ``condition`` lists
    the inequalities ``nu_i ||A(k)||^2 < 1``.  ``J`` is listed when a ``rule`` decides (a
    black box: only listing applies it); it is None when the exact rank decides, and
    ``Pr{r = 1}`` comes from :func:`full_rank_probability_of`, which lists nothing.
    """

    J: tuple[Vector, ...] | None
    nu: tuple[sp.Expr, ...]
    norms: tuple[AlgebraicNumber, ...]
    lhs: dict
    rho: AlgebraicNumber | None
    holds: bool | None
    condition: tuple[sp.Expr, ...]
    certified_by_bounds: bool


def theorem1(loss: NetworkLoss, dynamics: PeriodicDynamics, rule: Rule | None = None) -> Theorem1:
    """Theorem 1 (eq. 22): ``max_{i,k} nu_i ||A(k)||^2 <= rho < 1`` implies exponential boundedness."""
    bounded = loss.from_quadrature
    if rule is None:   # full column rank is an up-set: more rows never lower the rank, nor links theta
        J = None
        nus = _nu(loss, lambda column: full_rank_probability_of(loss.tree, dynamics, column),
                  loss.phi_lower if bounded else None)
    else:
        J = full_rank_configurations(loss.tree, rule=rule)
        if bounded and not is_up_set(J):
            raise AssumptionError("J is not closed under extra successful links, so lower bounds on phi "
                                  "do not bound nu", assumption="monotone full-rank rule",
                                  applies_instead="exact phi values")
        nus = nu(loss, J, loss.phi_lower if bounded else None)
    norms = tuple(spectral_norm_squared(a) for a in dynamics.A)
    lhs = {(i, k): sp.expand(v * a.exact) for i, v in enumerate(nus, start=1)
           for k, a in enumerate(norms)}
    condition = tuple(sp.Lt(e, 1) for e in dict.fromkeys(lhs.values()))
    if any(v.free_symbols for v in nus):
        return Theorem1(J, nus, norms, lhs, None, None, condition, bounded)
    rho = max(AlgebraicNumber.from_expr(e) for e in lhs.values())
    return Theorem1(J, nus, norms, lhs, rho, rho < 1, condition, bounded)


def corollary1_lhs(P: sp.MatrixBase, phi: Sequence[sp.Expr], A: sp.MatrixBase) -> tuple[sp.Expr, ...]:
    """Corollary 1 (eq. 24): ``||A||^2 sum_j p_ij (1 - phi_{1|j})`` for each ``i`` (one sensor, LTI)."""
    A = A if isinstance(A, sp.MatrixBase) else to_exact_matrix(A, "A")  # user rows: the safe parser
    a = spectral_norm_squared(A).exact if not A.free_symbols else sp.Symbol("normA2", positive=True)
    B = P.shape[0]
    return tuple(sp.expand(a * sum(P[i, j] * (1 - phi[j]) for j in range(B))) for i in range(B))

check_public(globals())

"""Decay rates of P(R_N(i)) and the M matrix (Sui-You-Fu eqs. 33-36, Theorem 9).

``rho_i = lim sup P(R_N(i))^(1/N)`` (eq. 36).  With ``g`` the block's
projection period and ``H`` ranging over the maximal rank-deficient element
sets (hyperplanes, :mod:`symkf.observability`):

* i.i.d. losses: ``rho_i^g = max_H prod_{(j, r) not in H} loss_j`` -- the
  probability that every element outside ``H`` is lost for a whole period;
* Markov losses (a first-order :class:`~symkf.losses.LossChain`):
  ``rho_i^g = max_H rho(M_H)`` with ``M_H`` the one-period transfer matrix of
  the chain restricted to steps whose received elements lie in ``H``; these
  are the diagonal blocks ``E_ii`` of M for the maximal deficient patterns, so
  this is eq. (36) without building M.  It holds for aperiodic blocks as well
  (symkf's extension, docs/sui.md): an element received infinitely often spans
  its class projections, the other receptions are boundedly many and add
  polynomial factors only; with every class a single eigenvalue (rotations by
  irrational angles) ``g = 1`` and the decisive ``H`` is typically empty, the
  rate of the chain restricted to "everything lost".

The full M (eqs. 33-34) over (projected pattern, chain state) is built only
for checking ``P(R_{Ng}) = u M^N v`` (eq. 35) against enumeration.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import Sequence

import flint
import numpy as np  # outside counts from BlockRows.inside
import sympy as sp
from sympy.polys.matrices import DomainMatrix

from .exact.arguments import check_public
from .errors import AperiodicError, InputError
from .exact import perron
from .exact.algebraic import AlgebraicNumber
from .exact.numbers import sympify
from .losses import IID, GilbertElliott, LossModel
from .model import System
from .observability import BlockRows, _set, block_deficient, block_rows


@dataclass(frozen=True)
class BlockRate:
    """``rho_i^g`` for one block: the exact value, the decisive hyperplane and the candidates compared
    exactly (under i.i.d. losses only the near-heaviest hyperplanes when :meth:`BlockRows.heaviest`
    applies, else one hyperplane per exponent vector or every hyperplane)."""

    per_period: sp.Expr
    hyperplane: frozenset[int]
    candidates: tuple[tuple[frozenset[int], sp.Expr], ...]


def perron_root(M: sp.MatrixBase) -> sp.Expr:
    """Spectral radius of a non-negative exact matrix (Perron-Frobenius: its largest real eigenvalue).

    Rational matrices go through :func:`symkf.exact.perron.perron_root` (sparse: strongly
    connected components, merged identical rows, flint characteristic polynomials)."""
    if M.shape == (1, 1):
        return sympify(M[0, 0])
    dm = DomainMatrix.from_Matrix(M).to_sparse()
    if dm.domain.is_QQ or dm.domain.is_ZZ:
        K = dm.domain
        rows = {r: {c: flint.fmpq(int(K.numer(v)), int(K.denom(v))) for c, v in row.items()}
                for r, row in dm.rep.items()}
    else:
        rows = {}
        for (r, c), v in M.todok().items():
            rows.setdefault(r, {})[c] = v
    return perron.perron_root(rows, M.shape[0]).exact


def _received_ok(br: BlockRows, H: frozenset[int], vec: Sequence[int], phase: int) -> bool:
    return all(not g or br.elements.index(_el(br, j, phase)) in H for j, g in enumerate(vec))


def _el(br: BlockRows, j: int, phase: int):
    return br.elements[j * br.class_period + phase]


def _outside(br: BlockRows, H: frozenset[int], sensor: int) -> int:
    return sum(1 for i, e in enumerate(br.elements) if e.sensor == sensor and i not in H)


def _maximum(candidates: list[tuple[frozenset[int], sp.Expr]]) -> tuple[frozenset[int], sp.Expr]:
    if any(v.free_symbols for _, v in candidates):
        raise InputError("loss: symbolic loss parameters have no numeric decay rate; "
                         "use symkf.region.stability_conditions for the stability region as conditions")
    return max(candidates, key=lambda hv: AlgebraicNumber.from_expr(hv[1]))


def outside_counts(br: BlockRows, weights: Sequence[float] | None = None) -> dict[tuple[int, ...], frozenset[int]]:
    """Per distinct exponent vector ``(k_1, ..., k_d)`` -- the number of sensor ``j``'s elements
    outside a hyperplane ``H`` -- one such ``H``.  Under i.i.d. losses ``H`` decays at
    ``prod_j loss_j^(k_j)`` per period, so hyperplanes sharing a vector are interchangeable.

    ``weights`` (per sensor, floats >= 0): only the hyperplanes that may maximise ``sum_{e in H}
    weights[sensor e]`` (:meth:`BlockRows.heaviest`), which is all a caller minimising ``prod_j
    c_j^(k_j)`` with ``c_j = exp(-weights[j])`` needs; every hyperplane when the screen does not
    apply or every hyperplane is already known (cached: counting is then cheaper than the
    screen).  The screen's sets in lexicographic order keep the enumeration's tie-break (the
    first maximiser)."""
    if weights is not None and "inside" not in br.__dict__:
        heaviest = br.heaviest([weights[e.sensor] for e in br.elements])
        if heaviest is not None:
            return _outside_vectors(br, sorted(heaviest, key=sorted))
    return _outside_vectors(br, br.inside)


def _outside_vectors(br: BlockRows, inside) -> dict[tuple[int, ...], frozenset[int]]:
    """:func:`outside_counts` of the hyperplanes ``inside`` (boolean rows or index sets, in
    lexicographic order: the first hyperplane of each vector is kept)."""
    if not isinstance(inside, np.ndarray):
        rows = np.zeros((len(inside), len(br.elements)), dtype=bool)
        for h, H in enumerate(inside):
            rows[h, list(H)] = True
        inside = rows
    sensor = np.array([e.sensor for e in br.elements])
    per_sensor = (sensor[:, None] == np.arange(sensor.max() + 1)).astype(np.int64)  # elements x d
    outside = (~inside).astype(np.int64) @ per_sensor                               # hyperplanes x d
    _, first = np.unique(outside, axis=0, return_index=True)
    return {tuple(outside[h].tolist()): _set(inside[h]) for h in sorted(first.tolist())}


def _weights(loss: IID) -> list[float] | None:
    """``-log loss_j`` per sensor: the slowest-decaying hyperplane maximises ``sum_{e in H} -log
    loss_(sensor e)``; None when a loss is 0 or symbolic (then every hyperplane is compared)."""
    if loss.symbols or any(e == 0 for e in loss.loss):
        return None
    return [-float(sp.log(e).evalf(20)) for e in loss.loss]


def block_rate(br: BlockRows, loss: LossModel) -> BlockRate:
    """``rho_i^g`` (per projection period) for one block, exactly (eq. 36)."""
    if isinstance(loss, IID):
        counts = outside_counts(br, _weights(loss))
        cands = [(H, sp.Mul(*[e ** k for e, k in zip(loss.loss, ks)])) for ks, H in counts.items()]
    else:  # aperiodic blocks too: their elements' generators are class projections (docs/sui.md)
        cands = [(H, sympify(ge_rate(br, H, loss) if isinstance(loss, GilbertElliott)
                                else perron_root(restricted_transfer(br, H, loss)))) for H in br.hyperplanes]
    H, best = _maximum(cands)
    return BlockRate(best, H, tuple(cands))


def ge_rate(br: BlockRows, H: frozenset[int], loss: GilbertElliott) -> sp.Expr:
    """``rho(M_H)`` for independent Gilbert-Elliott channels: the product over sensors of the
    Perron roots of their 2x2 restricted transfers.  A sensor with an element outside ``H``
    has a singular factor ``P diag(0, 1)`` in its transfer, so its Perron root is the trace,
    a polynomial in (fail, recover); a sensor entirely inside ``H`` has transfer ``P^g``
    (stochastic), rate 1."""
    rates = []
    for j in range(loss.d):
        M = _restricted_sensor_transfer(br, H, loss, j)
        rates.append(sp.expand(M.trace()) if _outside(br, H, j) else sp.Integer(1))
    return sp.Mul(*rates)


def _aperiodic(br: BlockRows) -> AperiodicError:
    return AperiodicError(f"the eigen-block of modulus {br.block.modulus} is aperiodic ({br.block.proof})",
                          assumption="eq. (35) (Sui-You-Fu): M over projected patterns needs a periodic block",
                          applies_instead="symkf.decay.block_rate, which decides aperiodic blocks")


def restricted_transfer(br: BlockRows, H: frozenset[int], loss: LossModel) -> sp.Matrix:
    """One-period transfer of the loss chain restricted to steps received inside ``H``.

    Sparse (sympy's DomainMatrix): lifted semi-Markov chains have hundreds of states."""
    ch = loss.chain
    S = len(ch.states)
    P = DomainMatrix.from_Matrix(ch.P).to_sparse()
    K = P.domain
    M = DomainMatrix.eye(S, K).to_sparse()
    for r in range(1, br.class_period + 1):
        phase = r % br.class_period
        D = DomainMatrix.diag([K.one if _received_ok(br, H, ch.emit[s], phase) else K.zero for s in range(S)], K)
        M = M * P * D.to_sparse()
    return M.to_Matrix()


def _restricted_sensor_transfer(br: BlockRows, H: frozenset[int], loss: GilbertElliott, j: int) -> sp.Matrix:
    """Gilbert-Elliott channels are independent, so the transfer factorises over sensors."""
    P = loss.sensor_matrix(j)
    M = sp.eye(2)
    for r in range(1, br.class_period + 1):
        phase = r % br.class_period
        inside = br.elements.index(_el(br, j, phase)) in H
        M = M * P * sp.diag(1 if inside else 0, 1)  # states (received, lost)
    return M


# -- the full M matrix and brute force ------------------------------------------------
def m_matrix(br: BlockRows, loss: LossModel) -> tuple[sp.Matrix, list]:
    """M (eqs. 33-34) over (deficient projected pattern, chain state); column convention.

    State ``(frozenset(), None)`` is the start (before time 0).  ``P(R_{Ng}(i)) =
    sum of M^N`` applied to the start vector (eq. 35).
    """
    if not br.block.is_periodic:
        raise _aperiodic(br)
    ch = loss.chain
    S = len(ch.states)
    start = (frozenset(), None)
    index = {start: 0}
    order = [start]
    cols: dict[tuple, dict[tuple, sp.Expr]] = {}
    frontier = [start]
    while frontier:
        state = frontier.pop()
        dist = {state: sp.Integer(1)}
        for phase in range(br.class_period):
            nxt: dict[tuple, sp.Expr] = {}
            for (pat, x), p in dist.items():
                row = ch.initial.row(0) if x is None else ch.P.row(x)
                for y in range(S):
                    if row[y] == 0:
                        continue
                    new = pat | {br.elements.index(_el(br, j, phase)) for j, g in enumerate(ch.emit[y]) if g}
                    new = frozenset(new)
                    if br.deficient(new):
                        key = (new, y)
                        nxt[key] = nxt.get(key, 0) + p * row[y]
            dist = nxt
        cols[state] = dist
        for key in dist:
            if key not in index:
                index[key] = len(order)
                order.append(key)
                frontier.append(key)
    M = sp.zeros(len(order), len(order))
    for src, dist in cols.items():
        for dst, p in dist.items():
            M[index[dst], index[src]] += p
    return M, order


def probability_rank_deficient(system: System, loss: LossModel, N: int) -> tuple[sp.Expr, ...]:
    """``P(R_N(i))`` per eigen-block by enumerating all ``2^(dN)`` receival patterns (brute force)."""
    if loss.d != system.d:
        raise InputError(f"loss model has {loss.d} sensors, the system {system.d}")
    if loss.d * N > 18:
        raise InputError(f"enumeration of 2^{loss.d * N} patterns is too large; use m_matrix")
    totals = [sp.Integer(0)] * len(block_rows(system))
    for pattern in itertools.product(itertools.product((1, 0), repeat=loss.d), repeat=N):
        flags = block_deficient(system, pattern) if N else (True,) * len(totals)
        if any(flags):
            p = loss.chain.sequence_probability(pattern)
            totals = [t + p if f else t for t, f in zip(totals, flags)]
    return tuple(sympify(sp.expand(t)) for t in totals)

check_public(globals())

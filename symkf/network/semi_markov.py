"""Theorem 2 of Quevedo et al.: semi-Markov network states (Quevedo-Ahlén-Johansson, Sec. VII).

Over a holding period ``[k_l, k_l + delta - 1]`` the state is constant,
``Xi = j``, and the ``theta(k)`` are i.i.d. with law ``Pr{theta | Xi = j}``.
``varrho(k_l) = 1`` iff ``O(k_l + Delta_l - 1, k_l)`` has full column rank
(eq. 30), where ``O(k + t, k) = col(C(k) Phi(k, k), ..., C(k + t) Phi(k + t, k))``.

``pi_j(delta) = Pr{varrho = 0 | Xi(k_l) = j, Delta_l = delta}`` is computed
by dynamic programming over the exact row space spanned so far (and, as a
cross-check, by enumerating every ``theta`` sequence).

The paper's eq. (31) ends with ``mu_i(delta) = sum_j q_ij pi_j(delta)``.  That
last step treats ``Pr{Xi(k_l) = j | Xi(k_l - 1) = i, Delta_l = delta}`` as
``q_ij``, but the holding time depends on the state entered (eq. 27), so the
conditional law is ``q_ij psi_j(delta) / sum_j' q_ij' psi_j'(delta)``.  With the
definition kept, the left-hand side of (32) becomes

    sum_delta sum_j q_ij psi_j(delta) pi_j(delta) ||Phi(k_l + delta, k_l)||^2,

which is what Lemma 4's proof bounds.  :func:`theorem2` reports both; only
the corrected form is a valid sufficient condition
(``proofs/quevedo_theorem2_counterexample.py``).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from fractions import Fraction
from typing import Sequence

import sympy as sp

from ..arguments import check_public
from ..errors import AssumptionError
from ..exact.linalg import echelon_extended, field_of, rank, span_key
from .dynamics import PeriodicDynamics, certified_less_than_one, interval_sum, spectral_norm_squared
from .loss import NetworkLoss
from .state import SemiMarkovNetworkState
from .tree import Vector


def observability_matrix(dynamics: PeriodicDynamics, thetas: Sequence[Vector], k: int = 0) -> sp.Matrix:
    """``O(k + t, k)`` for received-sensor vectors ``thetas = (theta(k), ..., theta(k + t))`` (Sec. VII-B)."""
    return sp.Matrix.vstack(*[dynamics.C_of(th) * dynamics.Phi(k + s, k) for s, th in enumerate(thetas)])


def rank_deficiency_probabilities(loss: NetworkLoss, dynamics: PeriodicDynamics, j: int,
                                  horizon: int, phase: int = 0) -> tuple[sp.Expr, ...]:
    """``(pi_j(1), ..., pi_j(horizon))``: Pr{O(k + delta - 1, k) is rank deficient | Xi = j on the window}.

    ``k`` is any time with ``k = phase (mod T)``.  Dynamic programming over the
    exact row space spanned by the received rows ``C_m Phi(k + s, k)`` (reduced echelon bases over
    the field of all of them, :func:`symkf.exact.linalg.echelon_extended`).
    """
    law = [(t, p) for t, p in loss.theta_law(j).items() if p != 0]
    n = dynamics.n
    blocks = [[dynamics.C[m] * dynamics.Phi(phase + s, phase) for m in range(dynamics.M)] for s in range(horizon)]
    K = field_of(*[B for step in blocks for B in step])
    spaces: dict = {(): ({}, sp.Integer(1))}  # span key -> (reduced echelon basis, probability)
    out = []
    for step in blocks:
        rows = [K.matrix(B) for B in step]
        received = {t: [r for m in range(dynamics.M) if t[m] for r in rows[m]] for t, _ in law}
        nxt: dict = {}
        for basis, p in spaces.values():
            for t, pt in law:
                grown = echelon_extended(K, basis, received[t], n)
                if len(grown) == n:   # full rank stays full: those paths leave the computation
                    continue
                key = span_key(grown)
                nxt[key] = (grown, nxt[key][1] + p * pt if key in nxt else p * pt)
        spaces = {key: (basis, sp.expand(p)) for key, (basis, p) in nxt.items()}
        out.append(sp.expand(sum((p for _, p in spaces.values()), sp.Integer(0))))
    return tuple(out)


def rank_deficiency_probability_by_enumeration(loss: NetworkLoss, dynamics: PeriodicDynamics, j: int,
                                               delta: int, phase: int = 0) -> sp.Expr:
    """``pi_j(delta)`` by enumerating every ``theta`` sequence and taking exact ranks (brute force)."""
    law = [(t, p) for t, p in loss.theta_law(j).items() if p != 0]
    total = sp.Integer(0)
    for seq in itertools.product(law, repeat=delta):
        if rank(observability_matrix(dynamics, [t for t, _ in seq], phase)) < dynamics.n:
            total += sp.Mul(*[p for _, p in seq])
    return sp.expand(total)


@dataclass(frozen=True)
class Theorem2:
    """Theorem 2 of Quevedo et al. on a semi-Markov network model.

    For each previous state ``i`` and phase ``k_l mod T``:
    ``lhs_paper[(i, phase)]`` is the left-hand side of (32) with (31) as
    printed; ``lhs[(i, phase)]`` uses the definition of ``mu`` (the corrected,
    valid condition).  ``pi[(j, phase)][delta - 1] = pi_j(delta)``;
    ``mu[(i, phase)][delta - 1]`` is the definition of (31),
    ``mu_paper`` its last line.  ``holds`` / ``holds_paper``: the maximum is
    < 1 (then ``rho = max^(1/sigma)``); None when data are symbolic.
    """

    sigma: int
    pi: dict
    mu: dict
    mu_paper: dict
    norms: dict
    lhs: dict
    lhs_paper: dict
    holds: bool | None
    holds_paper: bool | None
    bounds: dict
    bounds_paper: dict


def theorem2(loss: NetworkLoss, dynamics: PeriodicDynamics) -> Theorem2:
    """Evaluate condition (32) of Theorem 2, as printed and as corrected (module docstring)."""
    st = loss.state
    if not isinstance(st, SemiMarkovNetworkState):
        raise AssumptionError("the network state is Markov (Assumption 1)", assumption="Assumption 3 (Quevedo et al.)",
                              applies_instead="NetworkState.as_semi_markov() or symkf.network.conditions.theorem1")
    B, sigma, T = st.B, st.sigma, dynamics.T
    deltas = range(1, sigma + 1)
    pi = {(j, ph): rank_deficiency_probabilities(loss, dynamics, j, sigma, ph)
          for j in range(1, B + 1) for ph in range(T)}
    norms = {(ph, d): spectral_norm_squared(dynamics.Phi(ph + d, ph)) for ph in range(T) for d in deltas}
    mu, mu_paper, coeff, coeff_paper = {}, {}, {}, {}
    for i, ph in itertools.product(range(1, B + 1), range(T)):
        joint = [sp.expand(sum(st.qij(i, j) * st.psi(j, d) * pi[(j, ph)][d - 1] for j in range(1, B + 1)))
                 for d in deltas]
        p_delta = [sum(st.qij(i, j) * st.psi(j, d) for j in range(1, B + 1)) for d in deltas]
        mu[(i, ph)] = tuple(sp.cancel(a / b) if b != 0 else None for a, b in zip(joint, p_delta))
        mu_paper[(i, ph)] = tuple(sp.expand(sum(st.qij(i, j) * pi[(j, ph)][d - 1] for j in range(1, B + 1)))
                                  for d in deltas)
        coeff[(i, ph)] = joint
        coeff_paper[(i, ph)] = [sp.expand(m * p) for m, p in zip(mu_paper[(i, ph)], p_delta)]
    keys = list(coeff)

    def lhs_of(c):
        return {k: sp.expand(sum(c[k][d - 1] * norms[(k[1], d)].exact for d in deltas)) for k in keys}

    def decide(c):
        if any(v.free_symbols for k in keys for v in c[k]):
            return None, {}
        bounds = {k: interval_sum(c[k], [norms[(k[1], d)] for d in deltas]) for k in keys}
        return all(certified_less_than_one(c[k], [norms[(k[1], d)] for d in deltas]) for k in keys), bounds

    holds, bounds = decide(coeff)
    holds_paper, bounds_paper = decide(coeff_paper)
    return Theorem2(sigma, pi, mu, mu_paper, norms, lhs_of(coeff), lhs_of(coeff_paper),
                    holds, holds_paper, bounds, bounds_paper)


def smallest_rho(bounds: dict, sigma: int) -> tuple[float, float]:
    """Bounds on the smallest admissible ``rho = (max lhs)^(1/sigma)`` from exact interval bounds."""
    lo = max(b[0] for b in bounds.values())
    hi = max(b[1] for b in bounds.values())
    return float(Fraction(lo)) ** (1 / sigma), float(Fraction(hi)) ** (1 / sigma)

check_public(globals())

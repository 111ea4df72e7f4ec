"""Network-state processes Xi(k) (Quevedo-Ahlén-Johansson, Sec. III-A and VII-A).

``MarkovNetworkState``: Assumption 1, ``p_ij = Pr{Xi(k+1) = j | Xi(k) = i}`` (eq. 4).
``SemiMarkovNetworkState``: Assumption 3, an embedded chain ``q_ij`` at the
jump instants ``k_l`` and holding times ``Delta_l = k_{l+1} - k_l`` with law
``psi_i(delta)`` given the state entered at ``k_l`` (eqs. 26-28), bounded by
``sigma``.  States are numbered ``1..|B|`` as in the paper; probabilities are
exact numbers or sympy symbols.
"""

from __future__ import annotations

from typing import Any, Mapping, Sequence

import sympy as sp

from .. import budget
from ..arguments import check_public, count, index
from ..errors import InputError, ProbabilityError
from ..exact.numbers import substitution, sympify
from ..model.loss import probability, stationary_law


def stochastic_matrix(rows: Any, entry: str) -> sp.ImmutableMatrix:
    """An exact row-stochastic matrix; ``entry`` names it in errors."""
    if isinstance(rows, sp.MatrixBase):
        rows = rows.tolist()
    if isinstance(rows, (str, bytes)) or not isinstance(rows, Sequence) or not rows:
        raise InputError(f"{entry}: expected a square list of rows of probabilities")
    B = len(rows)
    # each network state is at least one state of the lifted chain: priced before a probability is read
    budget.check("max_network_chain", B, entry, "the number of network states")
    out = []
    for i, row in enumerate(rows, start=1):
        if isinstance(row, (str, bytes)) or not isinstance(row, Sequence) or len(row) != B:
            raise InputError(f"{entry}: row {i} must hold {B} probabilities (one per state)")
        probs = [probability(p, f"{entry}[{i}][{j}]") for j, p in enumerate(row, start=1)]
        total = sp.simplify(sum(probs))
        if total != 1:
            raise ProbabilityError(f"{entry}: row {i} sums to {total}, not 1")
        out.append(probs)
    return sp.ImmutableMatrix(out)


def _initial(initial: Any, B: int, default: sp.MatrixBase, entry: str) -> sp.ImmutableMatrix:
    if initial is None:
        return sp.ImmutableMatrix(default)
    if isinstance(initial, (str, bytes)) or not isinstance(initial, Sequence) or len(initial) != B:
        raise InputError(f"{entry}: expected {B} probabilities, one per network state")
    probs = [probability(p, f"{entry}[{j}]") for j, p in enumerate(initial, start=1)]
    if sp.simplify(sum(probs)) != 1:
        raise ProbabilityError(f"{entry}: sums to {sp.simplify(sum(probs))}, not 1")
    return sp.ImmutableMatrix([probs])


class MarkovNetworkState:
    """Assumption 1: ``Xi`` is a Markov chain on ``{1..|B|}`` with transition matrix ``P``.

    ``initial`` is the law of ``Xi(0)``; by default the stationary law.
    """

    def __init__(self, P: Any, initial: Sequence[Any] | None = None):
        self.P = stochastic_matrix(P, "P")
        self.B = self.P.shape[0]
        default = None if initial is not None else stationary_law(self.P, "P")
        self.initial = _initial(initial, self.B, default, "initial")

    def p(self, i: int, j: int) -> sp.Expr:
        """``p_ij`` (eq. 4), states numbered from 1."""
        N = self.P.rows
        return self.P[index(i, N, "i", 1) - 1, index(j, N, "j", 1) - 1]

    def subs(self, values: Mapping[Any, Any]) -> "MarkovNetworkState":
        """A copy with symbols in ``P`` and the initial law replaced by exact values."""
        values = substitution(values, "subs", self.P.free_symbols | self.initial.free_symbols)
        return MarkovNetworkState(self.P.subs(values), initial=list(self.initial.subs(values)))

    def as_semi_markov(self) -> "SemiMarkovNetworkState":
        """The same process as in Assumption 3 with ``q_ij = p_ij`` and ``psi_j(1) = 1`` (Sec. VII-B)."""
        return SemiMarkovNetworkState(self.P, [{1: 1}] * self.B, initial=list(self.initial))

    def __repr__(self) -> str:
        return f"MarkovNetworkState(P={self.P.tolist()})"


class SemiMarkovNetworkState:
    """Assumption 3: embedded chain ``q`` and holding-time laws ``holding[i-1] = {delta: psi_i(delta)}``.

    A holding law may also be a list ``[psi_i(1), psi_i(2), ...]``.  Supports
    must be finite (Theorem 2 needs ``Delta_l <= sigma``).  ``initial`` is the
    law of ``Xi(k_0)``, ``k_0 = 0`` being a jump instant (eq. 25); by default
    the stationary law of the embedded chain.
    """

    def __init__(self, q: Any, holding: Sequence[Any], initial: Sequence[Any] | None = None):
        self.q = stochastic_matrix(q, "q")
        self.B = self.q.shape[0]
        if isinstance(holding, (str, bytes)) or not isinstance(holding, Sequence) or len(holding) != self.B:
            raise InputError(f"holding: expected {self.B} holding-time laws, one per network state")
        self.holding = tuple(self._holding_law(h, i) for i, h in enumerate(holding, start=1))
        self.sigma = max(max(h) for h in self.holding)
        default = None if initial is not None else stationary_law(self.q, "q")
        self.initial = _initial(initial, self.B, default, "initial")

    @staticmethod
    def _holding_law(law: Any, i: int) -> dict[int, sp.Expr]:
        entry = f"holding[{i}]"
        if isinstance(law, Mapping):
            items = list(law.items())
        elif isinstance(law, Sequence) and not isinstance(law, (str, bytes)):
            items = list(enumerate(law, start=1))
        else:
            raise InputError(f"{entry}: expected {{delta: probability}} or a list psi(1), psi(2), ...")
        budget.check("max_network_chain", len(items), entry, "the number of holding times")
        out: dict[int, sp.Expr] = {}
        for delta, p in items:
            if isinstance(delta, bool) or not isinstance(delta, int) or delta < 1:
                raise InputError(f"{entry}: holding time {delta!r} must be a positive integer "
                                 "(Delta_l in N, eq. 26)")
            value = probability(p, f"{entry}[{delta}]")
            if value != 0:
                out[delta] = value
        if not out:
            raise InputError(f"{entry}: the holding-time law is empty")
        total = sp.simplify(sum(out.values()))
        if total != 1:
            raise ProbabilityError(f"{entry}: sums to {total}, not 1 (Theorem 2 needs a bounded "
                                   "support holding all the mass)")
        return dict(sorted(out.items()))

    def psi(self, i: int, delta: int) -> sp.Expr:
        """``psi_i(delta) = Pr{Delta_l = delta | Xi(k_l) = i}`` (eq. 28)."""
        return self.holding[index(i, len(self.holding), "i", 1) - 1].get(count(delta, "delta"), sp.Integer(0))

    def qij(self, i: int, j: int) -> sp.Expr:
        """``q_ij`` (eq. 28), states numbered from 1."""
        N = self.q.rows
        return self.q[index(i, N, "i", 1) - 1, index(j, N, "j", 1) - 1]

    def subs(self, values: Mapping[Any, Any]) -> "SemiMarkovNetworkState":
        """A copy with symbols in ``q``, the holding laws and the initial law replaced by exact values."""
        values = substitution(values, "subs", self.q.free_symbols | self.initial.free_symbols)
        holding = [{d: sympify(p).subs(values) for d, p in h.items()} for h in self.holding]
        return SemiMarkovNetworkState(self.q.subs(values), holding, initial=list(self.initial.subs(values)))

    def __repr__(self) -> str:
        return f"SemiMarkovNetworkState(q={self.q.tolist()}, sigma={self.sigma})"

check_public(globals())

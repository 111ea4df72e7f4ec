"""The packet-loss process induced by a sensor tree over a network-state channel (Quevedo et al.).

Given ``Xi(k) = j`` the links succeed independently, ``gamma_m(k) = 1`` with
probability ``phi_{m|j}`` (eq. 9), and sensor ``m`` is heard at the gateway
iff ``theta_m(k) = 1`` (Remark 2).  :class:`NetworkLoss` lifts the network
state together with the link outcomes into one first-order chain
(:class:`symkf.model.loss.LossChain`) whose receival vectors are the
``theta(k)``, so the filter, the Monte Carlo code and the exact engine use
it unchanged:

* Markov network state (Assumption 1): chain states ``(j, theta)``;
* semi-Markov (Assumption 3): ``(j, c, theta)`` where ``c`` counts the steps
  left in the current holding period (``c = Delta_l`` at ``k_l``).

Link outcomes enter only through ``theta``, and the next state's law depends
only on ``(j, c)``, so grouping the ``gamma`` vectors with equal ``theta`` is
an exact lumping.
"""

from __future__ import annotations

import itertools
import re
from functools import cached_property
from typing import ClassVar, TYPE_CHECKING, Any, Mapping, Sequence

import sympy as sp

from .. import budget
from ..arguments import check_public, index
from ..errors import AssumptionError, FileFormatError, InputError
from ..exact.numbers import substitution
from ..model.codec import entry, exact_values, within
from ..model.loss import LossChain, LossModel, probability
from ..model.markov import MarkovLoss
from .fading import SuccessProbability
from .state import MarkovNetworkState, SemiMarkovNetworkState
from .tree import SensorTree, Vector

#: the caps on a network state's transition matrix in a file: the lifted chain has at least one
#: state per network state
_MATRIX = ("max_network_chain", "max_network_chain")

if TYPE_CHECKING:
    from .dynamics import PeriodicDynamics


def phi_symbol(m: int, j: int) -> sp.Symbol:
    """The symbol ``phi_{m|j}`` (eq. 9)."""
    return sp.Symbol(f"phi_{{{m}|{j}}}", positive=True)


def bernoulli_product(vector: Sequence[int], probs: Sequence[sp.Expr]) -> sp.Expr:
    """``prod_m p_m^{v_m} (1 - p_m)^{1 - v_m}``: the law of independent links."""
    if len(vector) != len(probs):   # zip would drop the links past the shorter one: a wrong law
        raise InputError(f"phi: {len(probs)} link probabilities for a vector of {len(vector)} links")
    return sp.Mul(*[p if v else 1 - p for v, p in zip(vector, probs)])


class NetworkLoss(LossModel):
    """Losses of a sensor tree whose links fade according to a network state (Quevedo et al.).

    ``phi[m-1][j-1] = phi_{m|j}``: an exact number, a sympy expression, a
    :class:`~symkf.network.fading.SuccessProbability` (its rational value is
    used, its lower bound by :attr:`phi_lower`, and :attr:`from_quadrature` is set), or ``phi="symbols"`` for the
    symbols ``phi_{m|j}``.  The emitted receival vector is
    ``(theta_1, ..., theta_M)``: sensor ``m`` of the System is node ``S_m``.
    """

    def positivity_failure(self) -> str | None:
        """Markov network states: Assumption 2's positivity.  Semi-Markov states: irreducibility.

        The holding-time counter of a semi-Markov state (Assumption 3) counts down
        deterministically, so most transitions of the lifted chain are 0 and positivity cannot
        hold.  What the decay-rate argument needs is that every state carrying the rate of
        ``P(R_N)`` is visited infinitely often (docs/quevedo.md, "Semi-Markov states decided
        exactly"): an irreducible finite chain gives ``P(R_N) = u M_H^N v`` up to polynomial
        factors with the Perron root of every restricted transfer attained."""
        if not isinstance(self.state, SemiMarkovNetworkState):
            return super().positivity_failure()
        n = len(self.chain.states)
        edges = self.chain.P.todok()  # the non-zero transitions only: lifted chains are sparse
        if any(v.free_symbols for v in edges.values()):
            return None
        succ: list[list[int]] = [[] for _ in range(n)]
        pred: list[list[int]] = [[] for _ in range(n)]
        for r, s in edges:
            succ[r].append(s)
            pred[s].append(r)
        for graph, word in ((succ, "reached from"), (pred, "reach")):
            seen, stack = {0}, [0]
            while stack:
                for s in graph[stack.pop()]:
                    if s not in seen:
                        seen.add(s)
                        stack.append(s)
            if len(seen) < n:
                missing = self.chain.states[min(set(range(n)) - seen)]
                return (f"the chain state {missing} (network state, holding counter, theta) cannot be {word} "
                        f"the state {self.chain.states[0]}: the lifted semi-Markov chain is not irreducible")
        return None

    kind = "network"
    label = ("network", "network")

    #: the keys of its ``[loss]`` table
    keys: ClassVar[frozenset[str]] = frozenset({"kind", "parents", "phi", "P", "q", "holding", "initial"})

    @classmethod
    def read_table(cls, table: dict, where: str, d: int, rationalize: bool = False) -> "NetworkLoss":
        """The model of a ``[loss]`` table (or its JSON object) for ``d`` sensors; ``where`` names it in errors."""
        parents = entry(table, "parents", where)
        if not isinstance(parents, list):
            raise FileFormatError(f"{where} key 'parents': expected a list, parents[m-1] = Par(S_m) (0 = gateway)")
        tree = SensorTree(parents)
        if tree.M != d:
            raise FileFormatError(f"{where} key 'parents': the tree has {tree.M} sensor node(s), the system has "
                                  f"{d} sensor(s); sensor m of [[sensors]] is node S_m")
        markov, semi = "P" in table, "q" in table or "holding" in table
        if markov == semi:
            raise FileFormatError(f"{where}: give 'P' (Markov network state, Assumption 1) or 'q' and 'holding' "
                                  "(semi-Markov, Assumption 3), not " + ("both" if markov else "neither"))
        initial = table.get("initial")
        initial = None if initial is None else exact_values(initial, f"{where} initial", rationalize, start=1,
                                                            caps=("max_network_chain",))
        if markov:
            state = MarkovNetworkState(exact_values(table["P"], f"{where} P", rationalize, start=1, caps=_MATRIX),
                                       initial)
            hidden = state.B
        else:
            q = exact_values(entry(table, "q", where), f"{where} q", rationalize, start=1, caps=_MATRIX)
            holding = _holding(entry(table, "holding", where), where, rationalize)
            state = SemiMarkovNetworkState(q, holding, initial)
            hidden = sum(max(h) for h in state.holding)
        budget.check("max_network_chain", hidden * 2 ** tree.M, f"{where} key '{'P' if markov else 'holding'}'",
                     f"the bound {hidden} x 2^{tree.M} on the states of the lifted chain")
        phi = exact_values(entry(table, "phi", where), f"{where} phi", rationalize, start=1,
                           caps=("max_sensors", "max_network_chain"))
        return cls(tree, state, phi)

    @property
    def assumption(self) -> str:
        """What :func:`symkf.engine.stability.stability` checked of this loss process (its verdict says it)."""
        if isinstance(self.state, SemiMarkovNetworkState):
            return "semi-Markov network state with an irreducible lifted chain (symkf's extension, docs/quevedo.md)"
        return "Markov with positive transitions (Assumption 2)"

    @property
    def applies_without_positivity(self) -> str:
        """Quevedo et al.'s sufficient condition for this network state (the exact engine needs Assumption 2)."""
        n = 2 if isinstance(self.state, SemiMarkovNetworkState) else 1
        return f"Theorem {n} of Quevedo et al. (sufficient): symkf.network.theorem{n}(loss, PeriodicDynamics(A, [C_1, ..., C_M]))"

    def __init__(self, tree: SensorTree, state: MarkovNetworkState | SemiMarkovNetworkState,
                 phi: Sequence[Sequence[Any]] | str):
        if not isinstance(tree, SensorTree):
            raise InputError(f"tree: expected a SensorTree, got {type(tree).__name__}")
        if not isinstance(state, (MarkovNetworkState, SemiMarkovNetworkState)):
            raise InputError("state: expected a MarkovNetworkState (Assumption 1) or "
                             f"SemiMarkovNetworkState (Assumption 3), got {type(state).__name__}")
        self.tree, self.state = tree, state
        self.d = tree.M
        M, B = tree.M, state.B
        if isinstance(phi, str):
            if phi != "symbols":
                raise InputError(f"phi: {phi!r}; give a table phi[m][j] or the string 'symbols'")
            phi = [[phi_symbol(m, j) for j in range(1, B + 1)] for m in range(1, M + 1)]
        if isinstance(phi, (str, bytes)) or not isinstance(phi, Sequence) or len(phi) != M:
            raise InputError(f"phi: expected {M} rows (one per link E_1..E_{M}) of {B} probabilities")
        values, lower = [], []
        for m, row in enumerate(phi, start=1):
            if isinstance(row, (str, bytes)) or not isinstance(row, Sequence) or len(row) != B:
                raise InputError(f"phi[{m}]: expected {B} probabilities phi_{{{m}|j}}, one per network state")
            vrow, lrow = [], []
            for j, p in enumerate(row, start=1):
                if isinstance(p, SuccessProbability):
                    vrow.append(p.value)
                    lrow.append(p.lower)
                else:
                    vrow.append(probability(p, f"phi[{m}][{j}] (phi_{{{m}|{j}}})"))
                    lrow.append(vrow[-1])
            values.append(vrow)
            lower.append(lrow)
        self.phi = sp.ImmutableMatrix(values)
        self.phi_lower = sp.ImmutableMatrix(lower)
        self.from_quadrature = any(isinstance(p, SuccessProbability) for row in phi for p in row)

    # -- laws given the network state ------------------------------------------------
    @cached_property
    def link_vectors(self) -> tuple[Vector, ...]:
        """All link-outcome vectors ``(gamma_1, ..., gamma_M)``."""
        return tuple(itertools.product((1, 0), repeat=self.d))

    def link_law(self, j: int, phi: sp.MatrixBase | None = None) -> dict[Vector, sp.Expr]:
        """``Pr{gamma(k) = g | Xi(k) = j}`` for every ``g`` (links independent given ``Xi``, eq. 5)."""
        phi = self.phi if phi is None else phi
        j = index(j, phi.cols, "j", 1)
        col = [phi[m, j - 1] for m in range(self.d)]
        return {g: bernoulli_product(g, col) for g in self.link_vectors}

    @cached_property
    def theta_vectors(self) -> tuple[Vector, ...]:
        """The distinct ``theta`` vectors the tree can produce."""
        return tuple(dict.fromkeys(self.tree.theta(g) for g in self.link_vectors))

    def theta_law(self, j: int) -> dict[Vector, sp.Expr]:
        """``Pr{theta(k) = t | Xi(k) = j}`` (Remark 2: theta's sharing links are dependent)."""
        out = {t: sp.Integer(0) for t in self.theta_vectors}
        for g, p in self.link_law(j).items():
            out[self.tree.theta(g)] += p
        return {t: sp.factor(p) for t, p in out.items()}

    # -- the lifted chain ----------------------------------------------------------------
    def _build_chain(self) -> LossChain:
        B = self.state.B
        laws = {j: {t: p for t, p in self.theta_law(j).items() if p != 0} for j in range(1, B + 1)}
        if isinstance(self.state, MarkovNetworkState):
            hidden = [(j,) for j in range(1, B + 1)]
            start = {(j,): self.state.initial[0, j - 1] for j in range(1, B + 1)}

            def step(h):
                return {(j,): self.state.p(h[0], j) for j in range(1, B + 1)}
        else:
            st = self.state
            hidden = [(j, c) for j in range(1, B + 1) for c in range(1, max(st.holding[j - 1]) + 1)]
            start = {(j, c): st.initial[0, j - 1] * st.psi(j, c) for j, c in hidden}

            def step(h):
                j, c = h
                if c > 1:
                    return {(j, c - 1): sp.Integer(1)}
                return {(i, d): st.qij(j, i) * st.psi(i, d) for i, d in hidden}
        states = [h + (t,) for h in hidden for t in laws[h[0]]]
        index = {s: n for n, s in enumerate(states)}
        P = sp.zeros(len(states), len(states))
        for s in states:
            for h2, p in step(s[:-1]).items():
                if p != 0:
                    for t, pt in laws[h2[0]].items():
                        P[index[s], index[h2 + (t,)]] += p * pt
        init = [start[s[:-1]] * laws[s[0]][s[-1]] for s in states]
        return LossChain(tuple(states), tuple(s[-1] for s in states), sp.ImmutableMatrix(P),
                         sp.ImmutableMatrix([init]))

    def as_markov_loss(self) -> MarkovLoss:
        """The ``theta`` process as a first-order :class:`MarkovLoss`, when it is one.

        This holds exactly when the lifted chain lumps onto ``theta``: every
        chain state emitting the same ``theta`` has the same law of the next
        ``theta`` (e.g. one network state, or ``phi`` in ``{0, 1}`` with a
        different ``theta`` per state: the Gilbert-Elliott case of Sec. VI).
        """
        ch = self.chain
        rows: dict[Vector, dict[Vector, sp.Expr]] = {}
        for r, t in enumerate(ch.emit):
            nxt = {v: sp.Integer(0) for v in self.theta_vectors}
            for s, v in enumerate(ch.emit):
                nxt[v] += ch.P[r, s]
            nxt = {v: sp.simplify(p) for v, p in nxt.items()}
            reach = ch.initial[0, r] != 0 or any(ch.P[x, r] != 0 for x in range(len(ch.states)))
            if not reach:
                continue
            if t in rows and any(sp.simplify(rows[t][v] - nxt[v]) != 0 for v in nxt):
                raise AssumptionError(
                    f"chain states emitting theta = {t} predict different next receival laws",
                    assumption="first-order Markov receival process",
                    applies_instead="NetworkLoss.chain (a hidden-Markov LossChain)")
            rows[t] = nxt
        # the chain lives on the theta the tree can produce (a relay's children are never received
        # without it); the others have probability 0 and would break Assumption 2's positivity
        table = {t: {v: p for v, p in nxt.items() if v in rows} for t, nxt in rows.items()}
        initial = {v: sp.Integer(0) for v in table}
        for r, t in enumerate(ch.emit):
            if t in initial:
                initial[t] += ch.initial[0, r]
        return MarkovLoss(table, order=1, initial={v: sp.simplify(p) for v, p in initial.items()})

    def subs(self, values: Mapping[Any, Any]) -> "NetworkLoss":
        """A copy with symbols in ``phi`` and in the network state's laws replaced by exact values."""
        values = substitution(values, "subs", self.phi.free_symbols)
        phi = [[p.subs(values) for p in self.phi.row(m)] for m in range(self.d)]
        return NetworkLoss(self.tree, self.state.subs(values), phi)

    def words(self) -> str:
        kind = "semi-Markov" if isinstance(self.state, SemiMarkovNetworkState) else "Markov"
        return (f"a sensor tree of {self.d} links over a {kind} network state with {self.state.B} states "
                "(Quevedo et al.)")

    def fields(self) -> tuple[tuple[str, str, tuple[sp.Expr, ...]], ...]:
        return (("phi", r"\phi", tuple(self.phi.values()) or (sp.Integer(0),)), ("states", "|B|", (sp.Integer(self.state.B),)))

    def to_table(self) -> dict[str, Any]:
        def rows(M: sp.MatrixBase) -> list[list[str]]:
            return [[str(p) for p in M.row(i)] for i in range(M.shape[0])]
        out: dict[str, Any] = {"kind": self.kind, "parents": list(self.tree.parents), "phi": rows(self.phi)}
        if isinstance(self.state, SemiMarkovNetworkState):
            out["q"] = rows(self.state.q)
            out["holding"] = [{str(k): str(p) for k, p in h.items()} for h in self.state.holding]
        else:
            out["P"] = rows(self.state.P)
        out["initial"] = [str(p) for p in self.state.initial]
        return out

    def to_dict(self) -> dict[str, Any]:
        return self._with_chain(self.to_table())

    def __repr__(self) -> str:
        return f"NetworkLoss({self.tree!r}, {self.state!r})"


def _holding(value: Any, where: str, rationalize: bool) -> list[Any]:
    """Holding-time laws as lists ``[psi(1), ...]`` or tables ``{delta: psi(delta)}`` (TOML keys are text)."""
    if not isinstance(value, list):
        raise FileFormatError(f"{where} key 'holding': expected a list of holding-time laws, one per network state")
    within("max_network_chain", len(value), f"{where} key 'holding'", "the number of holding-time laws (network states)")
    laws = []
    for i, law in enumerate(value, start=1):
        if isinstance(law, dict):
            within("max_network_chain", len(law), f"{where} holding[{i}]", "the number of holding times")
            bad = [k for k in law if not re.fullmatch(r"[1-9][0-9]{0,5}", k)]
            if bad:
                raise FileFormatError(f"{where} key 'holding[{i}]': holding time {bad[0]!r} is not a positive "
                                      "integer below 10^6")
            law = {int(k): exact_values(p, f"{where} holding[{i}][{k}]", rationalize, caps=()) for k, p in law.items()}
        laws.append(exact_values(law, f"{where} holding[{i}]", rationalize, start=1, caps=("max_network_chain",))
                    if isinstance(law, list) else law)
    return laws


def induced_loss(loss: NetworkLoss, dynamics: PeriodicDynamics | None = None) -> LossModel:
    """The loss model the exact engine (``symkf.stability``) should take for a Markov network.

    Needs Assumption 1 and, when ``dynamics`` is given, a time-invariant ``A``.
    Returns the first-order :class:`MarkovLoss` of ``theta`` when the lifted
    chain lumps onto it, else ``loss`` itself (a :class:`LossModel` whose
    ``.chain`` is the hidden-Markov :class:`LossChain` on ``(Xi, theta)``).
    """
    if not isinstance(loss.state, MarkovNetworkState):
        raise AssumptionError("the network state is semi-Markov", assumption="Assumption 1 (Quevedo et al.)",
                              applies_instead="NetworkLoss.chain (the counter-augmented chain)")
    if dynamics is not None and dynamics.T != 1:
        raise AssumptionError(f"A(k) has period {dynamics.T}", assumption="time-invariant A",
                              applies_instead="symkf.network.conditions.theorem1")
    try:
        return loss.as_markov_loss()
    except AssumptionError:
        return loss

check_public(globals())

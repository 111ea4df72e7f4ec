"""A joint Markov chain of finite order on the receival vectors (Sui-You-Fu Assumption 2,
lifted to first order as in Remark 3)."""
from __future__ import annotations

import itertools
from typing import Any, ClassVar, Mapping

import sympy as sp

from .. import budget
from ..errors import FileFormatError, InputError, ProbabilityError
from ..arguments import check_public
from ..exact.numbers import rationalization, substitution, sympify
from .loss import (LossChain, LossModel, Vector, probability, stationary_law)
from .codec import built, entry, exact_values, positive_int, within


class MarkovLoss(LossModel):
    """A joint Markov chain of finite order ``nu`` on the receival vectors.

    ``table`` maps a history (a tuple of ``nu`` receival vectors, oldest
    first; for ``nu = 1`` a bare vector is accepted) to a mapping from next
    receival vector to its probability.  The chain lives on the receival vectors
    that occur in the histories (all of ``{0, 1}^d``, or fewer when some cannot
    occur, e.g. a relay's children are never received without it): every history
    over them must appear, each row must sum to 1 and lead only to them.
    ``initial`` gives the law of the first window; by default the stationary law
    of the lifted chain.  This is Sui-You-Fu Assumption 2 (order ``nu``, lifted as in Remark 3).

    Parameters
    ----------
    table : mapping
        ``{history: {next receival vector: probability}}``; receival vectors are tuples of 0/1
        of length ``d``, probabilities exact numbers or sympy symbols.
    order : int, default 1
        The order ``nu`` of the chain.
    initial : mapping, optional
        ``{window: probability}``, the law of the first ``nu`` receival vectors.

    Raises
    ------
    InputError
        A malformed key or vector, a missing history, a row leading outside the occurring
        vectors, or no unique stationary law when ``initial`` is omitted.
    ProbabilityError
        A probability outside ``[0, 1]``, or a row (or ``initial``) not summing to 1.

    Examples
    --------
    One sensor whose channel fails with probability 1/10 after a reception and recovers with
    probability 1/2 after a loss: the chain of ``GilbertElliott(["1/10"], ["1/2"])``.  Its
    stationary law is ``(5/6, 1/6)`` (by hand: ``(1/2) / (1/10 + 1/2) = 5/6``):

    >>> import symkf as sk
    >>> m = sk.MarkovLoss({(1,): {(1,): "9/10", (0,): "1/10"},
    ...                    (0,): {(1,): "1/2", (0,): "1/2"}})
    >>> m.d, m.order, m.chain.initial
    (1, 1, Matrix([[5/6, 1/6]]))

    It gives the same verdict as the Gilbert-Elliott model: for ``A = 2`` the decisive pattern
    is a run of losses, which lasts with probability ``1 - 1/2`` per step, so the margin is
    ``alpha^2 rho = 4 * 1/2 = 2`` (not stable):

    >>> S = sk.System(A=[[2]], sensors=[sk.Sensor(C=[[1]])])
    >>> [sk.stability(S, loss).margins[0].exact
    ...  for loss in (m, sk.GilbertElliott(["1/10"], ["1/2"]))]
    [2, 2]
    """

    def __init__(self, table: Mapping[Any, Mapping[Any, Any]], order: int = 1,
                 initial: Mapping[Any, Any] | None = None, *, rationalize: bool | str = False):
        with rationalization("MarkovLoss"):
            self._read(table, order, initial, rationalize)

    def _read(self, table: Mapping[Any, Mapping[Any, Any]], order: int, initial: Mapping[Any, Any] | None,
              rationalize: bool | str) -> None:
        if not isinstance(order, int) or order < 1:
            raise InputError(f"order: must be a positive integer, got {order!r}")
        if not isinstance(table, Mapping) or not table:
            raise InputError("table: expected a non-empty mapping history -> {next vector: probability}")
        self.order = order
        # the chain's size is priced from the table's shape before any probability is read: one
        # row per history, each with at most one entry per receival vector (a chain state)
        budget.check("max_markov_states", len(table), "MarkovLoss", "the number of rows (histories, chain states)")
        first = next(iter(table))
        hist0 = (first,) if order == 1 and _is_vector(first) else first
        self.d = len(hist0[0])
        budget.check("max_sensors", self.d, "MarkovLoss", "the length of a receival vector (sensors)")
        shapes: dict[tuple[Vector, ...], tuple[Any, Mapping[Any, Any]]] = {}
        for key, row in table.items():
            hist = (tuple(key),) if order == 1 and _is_vector(key) else tuple(tuple(v) for v in key)
            if len(hist) != order or any(len(v) != self.d or set(v) - {0, 1} for v in hist):
                raise InputError(f"table key {key!r}: expected {order} receival vector(s) of length {self.d}")
            if not isinstance(row, Mapping):
                raise InputError(f"table[{key!r}]: expected a mapping next vector -> probability")
            budget.check("max_markov_states", len(row), "MarkovLoss", f"the number of entries of row {key!r}")
            shapes[hist] = key, row
        occurring = {v for hist in shapes for v in hist}
        vecs = tuple(v for v in itertools.product((1, 0), repeat=self.d) if v in occurring)
        self.vectors = vecs
        budget.check("max_markov_states", len(vecs) ** order, "MarkovLoss", "the number of histories (chain states)")
        rows: dict[tuple[Vector, ...], dict[Vector, sp.Expr]] = {}
        for hist, (key, row) in shapes.items():
            probs = {}
            for nxt, p in row.items():
                nxt = tuple(nxt)
                if len(nxt) != self.d or set(nxt) - {0, 1}:
                    raise InputError(f"table[{key!r}] key {nxt!r}: not a 0/1 vector of length {self.d}")
                probs[nxt] = probability(p, f"table[{key!r}][{nxt!r}]", rationalize)
            total = sp.simplify(sum(probs.values()))
            if total != 1:
                raise ProbabilityError(f"table[{key!r}]: row sums to {total}, not 1")
            rows[hist] = probs
        missing = [h for h in itertools.product(vecs, repeat=order) if h not in rows]
        if missing:
            raise InputError(f"table: history {missing[0]!r} is missing ({len(missing)} of "
                             f"{len(vecs) ** order} histories over the occurring vectors have no row)")
        for hist, probs in rows.items():
            stray = [v for v in probs if v not in occurring]
            if stray:
                raise InputError(f"table[{hist!r}] leads to {stray[0]!r}, which no history contains: "
                                 "give its row, or leave it out if it cannot occur")
        self.table = rows
        if initial is not None and not isinstance(initial, Mapping):
            raise InputError("initial: expected a mapping window -> probability")
        if initial is not None:
            budget.check("max_markov_states", len(initial), "MarkovLoss", "the number of entries of initial")
        self._initial = None if initial is None else {
            k: probability(p, f"initial[{k!r}]", rationalize) for k, p in initial.items()}

    def _build_chain(self) -> LossChain:
        windows = tuple(itertools.product(self.vectors, repeat=self.order))
        index = {w: i for i, w in enumerate(windows)}
        rows = [[sp.Integer(0)] * len(windows) for _ in windows]   # lists: a 256-state chain's 65 536 entries
        for w in windows:
            for nxt, p in self.table[w].items():
                rows[index[w]][index[w[1:] + (nxt,)]] += p
        P = sp.Matrix(rows)
        if self._initial is None:
            init = stationary_law(P, "initial")
        else:
            init = sp.zeros(1, len(windows))
            for key, p in self._initial.items():
                w = (tuple(key),) if self.order == 1 and _is_vector(key) else tuple(tuple(v) for v in key)
                if w not in index:
                    raise InputError(f"initial key {key!r}: not a window of {self.order} receival vectors")
                init[0, index[w]] = probability(p, f"initial[{key!r}]")
            if sp.simplify(sum(init)) != 1:
                raise ProbabilityError(f"initial: sums to {sp.simplify(sum(init))}, not 1")
        return LossChain(windows, tuple(w[-1] for w in windows), sp.ImmutableMatrix(P),
                         sp.ImmutableMatrix(init))

    kind = "markov"
    label = ("joint Markov", "joint Markov")

    #: the keys of its ``[loss]`` table
    keys: ClassVar[frozenset[str]] = frozenset({"kind", "order", "states", "P", "initial"})

    @classmethod
    def read_table(cls, table: dict, where: str, d: int, rationalize: bool = False) -> "MarkovLoss":
        """The model of a ``[loss]`` table (or its JSON object) for ``d`` sensors; ``where`` names it in errors."""
        order = positive_int(table.get("order", 1), f"{where} key 'order'")
        states = entry(table, "states", where)
        # the chain's size is priced from its shape, before a vector is checked or a probability read
        if isinstance(states, list):
            within("max_markov_states", len(states), f"{where} key 'states'",
                   f"the number of histories (chain states), len(states)^order with order {order}", order)
        if not isinstance(states, list) or any(
                not isinstance(v, list) or len(v) != d or any(type(g) is not int or g not in (0, 1) for g in v)
                for v in states):
            raise FileFormatError(f"{where} key 'states': expected a list of 0/1 receival vectors of length {d} "
                                  "(one entry per sensor, 1 = received)")
        vectors = [tuple(v) for v in states]
        seen: set[tuple[int, ...]] = set()
        for v in vectors:
            if v in seen:
                raise FileFormatError(f"{where} key 'states': {list(v)} is listed twice")
            seen.add(v)
        P = exact_values(entry(table, "P", where), f"{where} P", rationalize,
                         caps=("max_markov_states", "max_markov_states"))
        rows = len(P) if isinstance(P, list) else 0
        if rows and isinstance(P[0], list) and len(vectors) < len(P[0]) <= 2 ** d:   # a vector left out of 'states'
            missing = next(v for v in itertools.product((1, 0), repeat=d) if v not in seen)
            raise FileFormatError(f"{where} key 'states': {list(missing)} is missing; 'P' has {len(P[0])} columns, "
                                  "one per vector of 'states'")
        # len(vectors) >= 2 rows per step of order: an order above rows.bit_length() cannot fit
        if order > rows.bit_length() or rows != len(vectors) ** order or any(
                not isinstance(row, list) or len(row) != len(vectors) for row in P):
            raise FileFormatError(f"{where} key 'P': expected {len(vectors)}^{order} rows (one per history) of "
                                  f"{len(vectors)} probabilities (one per next vector in 'states')")
        histories = list(itertools.product(vectors, repeat=order))
        initial = table.get("initial")
        if initial is not None:
            initial = exact_values(initial, f"{where} initial", rationalize, caps=("max_markov_states",))
            if not isinstance(initial, list) or len(initial) != len(histories):
                raise FileFormatError(f"{where} key 'initial': expected {len(histories)} probabilities, one per "
                                      "history (the rows of 'P')")
            initial = dict(zip(histories, initial))
        model = built(lambda: cls({h: dict(zip(vectors, row)) for h, row in zip(histories, P)}, order,
                                          initial), "key 'P'")
        built(lambda: model.chain, "key 'initial'")  # the initial law is checked when the chain is built
        return model

    def _reachable(self, r: int, s: int) -> bool:
        w, v = self.chain.states[r], self.chain.states[s]
        return w[1:] == v[:-1]

    def words(self) -> str:
        return f"a joint Markov chain of order {self.order} on {len(self.vectors)} receival vectors"

    def fields(self) -> tuple[tuple[str, str, tuple[sp.Expr, ...]], ...]:
        return (("order", r"\nu", (sp.Integer(self.order),)), ("vectors", r"|\Upsilon|", (sp.Integer(len(self.vectors)),)))

    def to_table(self) -> dict[str, Any]:
        histories = list(itertools.product(self.vectors, repeat=self.order))
        out = {"kind": self.kind, "order": self.order, "states": [list(v) for v in self.vectors],
               "P": [[str(self.table[h].get(v, 0)) for v in self.vectors] for h in histories]}
        if self._initial is not None:
            given = {(tuple(k),) if self.order == 1 and _is_vector(k) else tuple(map(tuple, k)): p
                     for k, p in self._initial.items()}
            out["initial"] = [str(given.get(h, 0)) for h in histories]
        return out

    def to_dict(self) -> dict[str, Any]:
        return self._with_chain(self.to_table())

    def subs(self, values: Mapping[Any, Any]) -> "MarkovLoss":
        values = substitution(values, "subs", self.symbols)
        table = {h: {n: sympify(p).subs(values) for n, p in row.items()} for h, row in self.table.items()}
        init = None if self._initial is None else {
            k: sympify(p).subs(values) for k, p in self._initial.items()}
        return MarkovLoss(table, self.order, init)

    def __repr__(self) -> str:
        return f"MarkovLoss(d={self.d}, order={self.order})"


def _is_vector(key: Any) -> bool:
    return isinstance(key, tuple) and all(isinstance(v, int) for v in key)


check_public(globals())

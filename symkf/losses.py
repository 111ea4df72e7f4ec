"""Packet-loss models (Sui-You-Fu Assumptions 2 and 4).

Every model is exposed to the rest of symkf as a :class:`LossChain`: a
first-order finite Markov chain whose state ``X_k`` determines the receival
vector ``(gamma_k^1, ..., gamma_k^d)`` (``1`` = packet received).  A joint
chain of order ``nu`` is lifted to windows of its last ``nu`` receival vectors
(Remark 3).  Parameters are exact numbers or sympy symbols.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from functools import cached_property
from typing import Any, Iterable, Mapping, Sequence

import flint
import numpy as np  # float chains for simulation (LossModel.numeric)
import sympy as sp

from . import budget
from .errors import AssumptionError, InputError, ProbabilityError
from .exact.algebraic import sign
from .exact.numbers import rationalization, substitution, to_exact

Vector = tuple[int, ...]


def _probability(value: Any, entry: str, rationalize: bool | str = False) -> sp.Expr:
    p = to_exact(value, entry, symbols=True, rationalize=rationalize)
    if not p.free_symbols:
        if not p.is_real:
            raise ProbabilityError(f"{entry}: {p} is not real")
        if sign(p) < 0 or sign(p - 1) > 0:
            raise ProbabilityError(f"{entry}: {p} is not a probability (must lie in [0, 1])")
    return p


def _scalar(values: Any) -> bool:
    return isinstance(values, (str, bytes)) or not isinstance(values, Iterable) or getattr(values, "ndim", 1) == 0


def _probabilities(values: Any, entry: str, rationalize: bool | str = False,
                   d: int | None = None) -> tuple[sp.Expr, ...]:
    """One exact probability per sensor; a single value is every sensor's when ``d`` sensors are given."""
    if d is not None and (isinstance(d, bool) or not isinstance(d, int) or d < 1):
        raise InputError(f"d: expected a positive number of sensors, got {d!r}")
    if _scalar(values):
        if d is None:
            raise InputError(f"{entry}: a single probability needs d, the number of sensors it applies to "
                             f"(e.g. d=2), or give a list with one probability per sensor")
        values = [values] * d
    if hasattr(values, "tolist"):  # a numpy array: its scalars as Python numbers
        values = values.tolist()
    values = list(values)
    if d is not None and len(values) != d:
        raise InputError(f"{entry}: {len(values)} probabilities for d = {d} sensors")
    budget.check("max_sensors", len(values), entry, "the number of sensors")
    out = tuple(_probability(v, f"{entry}[{i}]", rationalize) for i, v in enumerate(values))
    if not out:
        raise InputError(f"{entry}: the list is empty; give one probability per sensor")
    return out


@dataclass(frozen=True)
class LossChain:
    """A first-order chain on ``states`` with exact transition matrix ``P``.

    ``emit[s]`` is the receival vector in state ``s``; ``initial`` is the
    distribution of ``X_0``.
    """

    states: tuple[Any, ...]
    emit: tuple[Vector, ...]
    P: sp.ImmutableMatrix
    initial: sp.ImmutableMatrix  # 1 x S row

    @property
    def d(self) -> int:
        """Number of sensors (length of each receival vector)."""
        return len(self.emit[0])

    def numeric(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Float (P, initial, emit) for simulation; refuses free symbols."""
        require_numbers(self.P.free_symbols | self.initial.free_symbols)
        return _floats(self.P), _floats(self.initial).ravel(), np.array(self.emit, dtype=bool)

    def sequence_probability(self, seq: Sequence[Vector]) -> sp.Expr:
        """Exact probability that the first ``len(seq)`` receival vectors equal ``seq``."""
        if not seq:
            return sp.Integer(1)
        S = len(self.states)
        alpha = [self.initial[0, s] if self.emit[s] == tuple(seq[0]) else 0 for s in range(S)]
        for v in seq[1:]:
            alpha = [sum(alpha[r] * self.P[r, s] for r in range(S) if alpha[r] != 0)
                     if self.emit[s] == tuple(v) else 0 for s in range(S)]
        return sp.expand(sum(alpha))


def require_numbers(free: set) -> None:
    """Refuse a loss model with free symbols where numbers are needed (simulation)."""
    if free:
        raise InputError(f"loss model: symbols {sorted(map(str, free))} have no value; "
                         "substitute numbers (loss.subs({...})) before simulating")


def _floats(M: sp.MatrixBase) -> np.ndarray:
    """Entries as float64: rationals through flint (correctly rounded), others by evalf(30)."""
    return np.array([[float(flint.fmpq(int(v.p), int(v.q))) if v.is_Rational else float(v.evalf(30))
                      for v in M.row(i)] for i in range(M.shape[0])], dtype=float).reshape(M.shape)


def _independent_numeric(matrices: Sequence[sp.MatrixBase], initial: Sequence[sp.Expr]) \
        -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Float (P, initial, emit) of independent two-state sensors on states (received, lost):
    the joint chain on ``itertools.product((1, 0), repeat=d)`` is the Kronecker product
    of the sensors' chains, built in float64 without the 2^d x 2^d exact matrix."""
    require_numbers(set().union(*(M.free_symbols for M in matrices), *(sp.sympify(q).free_symbols for q in initial)))
    P, init = np.ones((1, 1)), np.ones(1)
    for M, q in zip(matrices, initial):
        P = np.kron(P, _floats(M))
        init = np.kron(init, _floats(sp.Matrix([[q, 1 - q]])).ravel())
    emit = np.array(list(itertools.product((1, 0), repeat=len(matrices))), dtype=bool)
    return P, init, emit


class LossModel:
    """Base class: subclasses build :attr:`chain`."""

    d: int

    @cached_property
    def chain(self) -> LossChain:
        return self._build_chain()

    def _build_chain(self) -> LossChain:  # pragma: no cover - abstract
        raise NotImplementedError

    @property
    def symbols(self) -> set[sp.Symbol]:
        """Free symbols of the transition matrix and initial law (empty for numeric models)."""
        return set(self.chain.P.free_symbols | self.chain.initial.free_symbols)

    def numeric(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Float (P, initial, emit) of :attr:`chain` for simulation; refuses free symbols."""
        return self.chain.numeric()

    def subs(self, values: Mapping[Any, Any]) -> "LossModel":
        """A copy with symbols replaced by exact values."""
        raise NotImplementedError

    def positivity_failure(self) -> str | None:
        """Why Assumption 2's positivity fails, or None when every transition is positive."""
        for r, s in itertools.product(range(len(self.chain.states)), repeat=2):
            if self._reachable(r, s):
                p = self.chain.P[r, s]
                if not p.free_symbols and sign(p) <= 0:
                    return (f"P(next = {self.chain.states[s]} | {self.chain.states[r]}) = {p}; "
                            "Assumption 2 needs every transition probability positive")
        return None

    def _reachable(self, r: int, s: int) -> bool:
        return True

    #: what applies when Assumption 2 fails (named in the error); None when nothing else does
    applies_without_positivity: str | None = None

    def require_positive(self) -> None:
        """Raise :class:`~symkf.errors.AssumptionError` (Assumption 2) unless every transition is positive."""
        why = self.positivity_failure()
        if why:
            raise AssumptionError(why, assumption="Assumption 2 (Sui-You-Fu)",
                                  applies_instead=self.applies_without_positivity)


class IID(LossModel):
    """Independent Bernoulli losses: sensor ``i`` loses each packet with probability ``loss[i]``.

    Sui-You-Fu Assumption 4 (arrival probability ``p_i = 1 - loss[i]``), independent across
    sensors and time.

    Parameters
    ----------
    loss : sequence or number
        One loss probability per sensor: exact numbers in ``[0, 1]`` (ints, Fractions, sympy
        numbers, strings such as ``"1/10"``) or sympy symbols
        (:func:`symkf.region.stability_conditions`); a single number is every sensor's and
        needs ``d``.
    d : int, optional
        The number of sensors: ``IID("1/10", d=3)`` is ``IID(["1/10"] * 3)``.

    Raises
    ------
    InputError
        ``loss`` is not a non-empty list, or an entry is not an exact number.
    ProbabilityError
        An entry is not real or lies outside ``[0, 1]``.

    Examples
    --------
    >>> import symkf as sk
    >>> loss = sk.IID(["1/10", "1/5"])
    >>> loss.d, loss.arrival
    (2, (9/10, 4/5))
    >>> sk.IID("1/10", d=3).loss
    (1/10, 1/10, 1/10)
    >>> sk.IID(["3/2"])
    Traceback (most recent call last):
    ...
    symkf.errors.ProbabilityError: loss[0]: 3/2 is not a probability (must lie in [0, 1])
    """

    def __init__(self, loss: Sequence[Any] | Any, *, d: int | None = None, rationalize: bool | str = False):
        with rationalization("IID"):
            self.loss = _probabilities(loss, "loss", rationalize, d)
        self.d = len(self.loss)

    @property
    def arrival(self) -> tuple[sp.Expr, ...]:
        """Arrival probabilities ``p_i = 1 - loss_i`` (Assumption 4)."""
        return tuple(1 - e for e in self.loss)

    def _build_chain(self) -> LossChain:
        vecs = tuple(itertools.product((1, 0), repeat=self.d))
        row = [sp.Mul(*[(1 - e) if g else e for g, e in zip(v, self.loss)]) for v in vecs]
        return LossChain(vecs, vecs, sp.ImmutableMatrix([row] * len(vecs)), sp.ImmutableMatrix([row]))

    def positivity_failure(self) -> str | None:
        # Independence makes (27) of Sui-You-Fu hold with beta = epsilon = 1,
        # so Theorem 4 needs no positivity for i.i.d. losses.
        return None

    @property
    def symbols(self) -> set[sp.Symbol]:
        return set().union(*(sp.sympify(e).free_symbols for e in self.loss))

    def numeric(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        rows = [sp.Matrix([[1 - e, e], [1 - e, e]]) for e in self.loss]
        return _independent_numeric(rows, self.arrival)

    def subs(self, values: Mapping[Any, Any]) -> "IID":
        values = substitution(values, "subs", self.symbols)
        return IID([e.subs(values) for e in self.loss])

    def __repr__(self) -> str:
        return f"IID(loss={[str(e) for e in self.loss]})"


class GilbertElliott(LossModel):
    """An independent two-state Markov channel per sensor.

    ``fail[i] = P(lost | received last)``, ``recover[i] = P(received | lost last)``.
    ``X_0`` is drawn from the stationary law ``P(received) = recover / (fail + recover)``
    unless ``initial_received`` gives ``P(gamma_0^i = 1)`` per sensor.  The channels are
    independent across sensors; the joint chain is Sui-You-Fu Assumption 2 with ``nu = 1``.

    Parameters
    ----------
    fail : sequence or number
        ``P(lost | received last)`` per sensor (exact numbers in ``[0, 1]`` or sympy symbols);
        a single number is every sensor's.
    recover : sequence or number
        ``P(received | lost last)`` per sensor, as many as ``fail``; a single number is every
        sensor's.
    initial_received : sequence, optional
        ``P(gamma_0^i = 1)`` per sensor; needed when ``fail[i] = recover[i] = 0``.
    d : int, optional
        The number of sensors, needed when both ``fail`` and ``recover`` are single numbers:
        ``GilbertElliott("1/4", "1/2", d=2)``.

    Raises
    ------
    InputError
        Lengths differ, an entry is not exact, or no stationary law exists without
        ``initial_received``.
    ProbabilityError
        An entry lies outside ``[0, 1]``.

    Examples
    --------
    The stationary reception probability is ``(1/2) / (1/20 + 1/2) = 10/11`` (by hand);
    :meth:`sensor_matrix` is the channel's chain on (received, lost):

    >>> import symkf as sk
    >>> ge = sk.GilbertElliott(fail=["1/20"], recover=["1/2"])
    >>> ge.initial_received
    (10/11,)
    >>> ge.sensor_matrix(0)
    Matrix([
    [19/20, 1/20],
    [  1/2,  1/2]])
    """

    def __init__(self, fail: Sequence[Any] | Any, recover: Sequence[Any] | Any,
                 initial_received: Sequence[Any] | None = None, *, d: int | None = None,
                 rationalize: bool | str = False):
        # a single fail or recover value is every sensor's: d sensors, or as many as the other list
        lists = [len(list(v)) for v in (fail, recover) if not _scalar(v)]
        d = d if d is not None or not lists else lists[0]
        with rationalization("GilbertElliott"):
            self.fail = _probabilities(fail, "fail", rationalize, d)
            self.recover = _probabilities(recover, "recover", rationalize, d)
            if initial_received is not None:
                initial_received = _probabilities(initial_received, "initial_received", rationalize)
        if len(self.fail) != len(self.recover):
            raise InputError(f"recover: {len(self.recover)} values for {len(self.fail)} sensors in fail")
        self.d = len(self.fail)
        if initial_received is None:
            for i, (f, r) in enumerate(zip(self.fail, self.recover)):
                if not (f + r).free_symbols and (f + r) == 0:
                    raise InputError(f"fail[{i}] = recover[{i}] = 0: no stationary law; give initial_received")
            self.initial_received = tuple(sp.cancel(r / (f + r)) for f, r in zip(self.fail, self.recover))
        else:
            self.initial_received = _probabilities(initial_received, "initial_received")
            if len(self.initial_received) != self.d:
                raise InputError(f"initial_received: {len(self.initial_received)} values for {self.d} sensors")

    def sensor_matrix(self, i: int) -> sp.ImmutableMatrix:
        """Transition matrix of sensor ``i`` on states (received, lost)."""
        f, r = self.fail[i], self.recover[i]
        return sp.ImmutableMatrix([[1 - f, f], [r, 1 - r]])

    def _build_chain(self) -> LossChain:
        vecs = tuple(itertools.product((1, 0), repeat=self.d))
        P = [[sp.Mul(*[self.sensor_matrix(i)[1 - a[i], 1 - b[i]] for i in range(self.d)])
              for b in vecs] for a in vecs]
        init = [sp.Mul(*[q if g else 1 - q for g, q in zip(v, self.initial_received)]) for v in vecs]
        return LossChain(vecs, vecs, sp.ImmutableMatrix(P), sp.ImmutableMatrix([init]))

    @property
    def symbols(self) -> set[sp.Symbol]:
        return set().union(*(sp.sympify(v).free_symbols for v in self.fail + self.recover + self.initial_received))

    def positivity_failure(self) -> str | None:
        # the joint transition is the product of the sensors' (independent channels), so it is
        # positive for every pair of states iff every sensor's 2x2 transition is positive
        for i in range(self.d):
            P = self.sensor_matrix(i)
            for r, s in itertools.product(range(2), repeat=2):
                if not P[r, s].free_symbols and sign(P[r, s]) <= 0:
                    state = ("received", "lost")
                    return (f"sensor {i}: P(next {state[s]} | {state[r]}) = {P[r, s]}, so the joint chain has "
                            "zero transitions; Assumption 2 needs every transition probability positive")
        return None

    def numeric(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return _independent_numeric([self.sensor_matrix(i) for i in range(self.d)], self.initial_received)

    def subs(self, values: Mapping[Any, Any]) -> "GilbertElliott":
        values = substitution(values, "subs", self.symbols)

        def s(xs):
            return [sp.sympify(x).subs(values) for x in xs]
        return GilbertElliott(s(self.fail), s(self.recover), s(self.initial_received))

    def __repr__(self) -> str:
        return (f"GilbertElliott(fail={[str(x) for x in self.fail]}, "
                f"recover={[str(x) for x in self.recover]})")


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
        first = next(iter(table))
        hist0 = (first,) if order == 1 and _is_vector(first) else first
        self.d = len(hist0[0])
        rows: dict[tuple[Vector, ...], dict[Vector, sp.Expr]] = {}
        for key, row in table.items():
            hist = (tuple(key),) if order == 1 and _is_vector(key) else tuple(tuple(v) for v in key)
            if len(hist) != order or any(len(v) != self.d or set(v) - {0, 1} for v in hist):
                raise InputError(f"table key {key!r}: expected {order} receival vector(s) of length {self.d}")
            probs = {}
            for nxt, p in row.items():
                nxt = tuple(nxt)
                if len(nxt) != self.d or set(nxt) - {0, 1}:
                    raise InputError(f"table[{key!r}] key {nxt!r}: not a 0/1 vector of length {self.d}")
                probs[nxt] = _probability(p, f"table[{key!r}][{nxt!r}]", rationalize)
            total = sp.simplify(sum(probs.values()))
            if total != 1:
                raise ProbabilityError(f"table[{key!r}]: row sums to {total}, not 1")
            rows[hist] = probs
        occurring = {v for hist in rows for v in hist}
        vecs = tuple(v for v in itertools.product((1, 0), repeat=self.d) if v in occurring)
        self.vectors = vecs
        budget.check("max_markov_states", len(vecs) ** order, "MarkovLoss", "the number of histories (chain states)")
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
        self._initial = None if initial is None else {
            k: _probability(p, f"initial[{k!r}]", rationalize) for k, p in initial.items()}

    def _build_chain(self) -> LossChain:
        windows = tuple(itertools.product(self.vectors, repeat=self.order))
        index = {w: i for i, w in enumerate(windows)}
        P = sp.zeros(len(windows), len(windows))
        for w in windows:
            for nxt, p in self.table[w].items():
                P[index[w], index[w[1:] + (nxt,)]] += p
        if self._initial is None:
            init = _stationary(P)
        else:
            init = sp.zeros(1, len(windows))
            for key, p in self._initial.items():
                w = (tuple(key),) if self.order == 1 and _is_vector(key) else tuple(tuple(v) for v in key)
                if w not in index:
                    raise InputError(f"initial key {key!r}: not a window of {self.order} receival vectors")
                init[0, index[w]] = _probability(p, f"initial[{key!r}]")
            if sp.simplify(sum(init)) != 1:
                raise ProbabilityError(f"initial: sums to {sp.simplify(sum(init))}, not 1")
        return LossChain(windows, tuple(w[-1] for w in windows), sp.ImmutableMatrix(P),
                         sp.ImmutableMatrix(init))

    def _reachable(self, r: int, s: int) -> bool:
        w, v = self.chain.states[r], self.chain.states[s]
        return w[1:] == v[:-1]

    def subs(self, values: Mapping[Any, Any]) -> "MarkovLoss":
        values = substitution(values, "subs", self.symbols)
        table = {h: {n: sp.sympify(p).subs(values) for n, p in row.items()} for h, row in self.table.items()}
        init = None if self._initial is None else {
            k: sp.sympify(p).subs(values) for k, p in self._initial.items()}
        return MarkovLoss(table, self.order, init)

    def __repr__(self) -> str:
        return f"MarkovLoss(d={self.d}, order={self.order})"


def _is_vector(key: Any) -> bool:
    return isinstance(key, tuple) and all(isinstance(v, int) for v in key)


def _stationary(P: sp.Matrix) -> sp.Matrix:
    """The unique stationary row vector of ``P`` (exact)."""
    S = P.shape[0]
    system = (P.T - sp.eye(S)).col_join(sp.ones(1, S))
    rhs = sp.zeros(S, 1).col_join(sp.Matrix([1]))
    try:
        sol = system.solve_least_squares(rhs) if S > 0 else None
        sol = sp.simplify(sol)
    except Exception:
        raise InputError("initial: the chain has no unique stationary law; give initial") from None
    if system * sol != rhs and sp.simplify(system * sol - rhs) != sp.zeros(S + 1, 1):
        raise InputError("initial: the chain has no unique stationary law; give initial")
    return sol.T

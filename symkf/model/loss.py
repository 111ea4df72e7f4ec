"""Packet-loss models (Sui-You-Fu Assumptions 2 and 4) behind one interface, :class:`LossModel`.

A model is a product of independent :class:`Factor` s, each a first-order finite Markov
chain (:class:`LossChain`) whose state determines the receivals of its sensors (``1`` =
packet received): one two-state chain per sensor for :class:`~symkf.model.iid.IID` and
:class:`~symkf.model.gilbert_elliott.GilbertElliott`, one joint chain for
:class:`~symkf.model.markov.MarkovLoss` and the network losses (:mod:`symkf.network.loss`), and
:class:`~symkf.model.independent.Independent` the parts' factors side by side (any of these on
consecutive groups of sensors).  A joint chain of order ``nu`` is lifted to windows of its last
``nu`` receival vectors (Remark 3).  Parameters are exact numbers or sympy symbols.  A model is
data: its factors, chain, capabilities, symbols, check against a system, file form and words.
The engine computes every rate from that data (:mod:`symkf.engine.rates`) and the simulation
draws from its factors (:func:`symkf.numeric.receptions.draw`); docs/losses.md shows how to add a
model, in symkf or in a package of its own.
"""

from __future__ import annotations

import itertools
import json
import math
from dataclasses import dataclass
from functools import cached_property
from typing import Any, ClassVar, Iterable, Mapping, Sequence

import flint
import numpy as np  # float chains for simulation (LossModel.numeric)
import sympy as sp
from sympy.polys.matrices import DomainMatrix

from ..output import JsonDocument
from .. import budget
from ..errors import AssumptionError, InputError, ProbabilityError, ShapeError
from ..exact.algebraic import sign
from ..arguments import check_public
from ..exact.numbers import to_exact

Vector = tuple[int, ...]


def probability(value: Any, entry: str, rationalize: bool | str = False) -> sp.Expr:
    p = to_exact(value, entry, symbols=True, rationalize=rationalize)
    if isinstance(p, sp.Rational):   # compared directly: a joint chain of 256 states has 65 536 entries
        if p.p < 0 or p.p > p.q:
            raise ProbabilityError(f"{entry}: {p} is not a probability (must lie in [0, 1])")
    elif not p.free_symbols:
        if not p.is_real:
            raise ProbabilityError(f"{entry}: {p} is not real")
        if sign(p) < 0 or sign(p - 1) > 0:
            raise ProbabilityError(f"{entry}: {p} is not a probability (must lie in [0, 1])")
    return p


def is_scalar(values: Any) -> bool:
    return isinstance(values, (str, bytes)) or not isinstance(values, Iterable) or getattr(values, "ndim", 1) == 0


def probabilities(values: Any, entry: str, rationalize: bool | str = False,
                   d: int | None = None) -> tuple[sp.Expr, ...]:
    """One exact probability per sensor; a single value is every sensor's when ``d`` sensors are given."""
    if d is not None and (isinstance(d, bool) or not isinstance(d, int) or d < 1):
        raise InputError(f"d: expected a positive number of sensors, got {d!r}")
    if d is not None:
        budget.check("max_sensors", d, "d", "the number of sensors")
    if is_scalar(values):
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
    out = tuple(probability(v, f"{entry}[{i}]", rationalize) for i, v in enumerate(values))
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
    """Entries as float64: rationals by Python's int division (correctly rounded; python-flint 0.7's
    fmpq has no float), others by evalf(30)."""
    return np.array([[int(v.p) / int(v.q) if v.is_Rational else float(v.evalf(30)) for v in row]
                     for row in M.tolist()], dtype=float).reshape(M.shape)


def stationary_law(P: sp.MatrixBase, entry: str) -> sp.ImmutableMatrix:
    """The unique stationary row vector ``pi = pi P`` of a stochastic matrix, exactly: a rational
    ``P`` by one solve in flint of ``P^T - I`` with a row replaced by ``sum(pi) = 1`` (the rows of
    ``P^T - I`` add up to 0, so the others keep its rank: the system is regular iff the law is
    unique; sympy's null space of a 256-state chain took minutes), an algebraic one by the null
    space of :class:`~sympy.polys.matrices.DomainMatrix`, with symbols by sympy; raises naming
    ``entry`` when it is not unique."""
    S = P.shape[0]
    dm = DomainMatrix.from_Matrix(sp.Matrix(P))
    symbolic = bool(P.free_symbols)
    if dm.domain.is_QQ or dm.domain.is_ZZ:
        K = dm.domain
        M = flint.fmpq_mat(S, S)
        for (r, c), v in dm.to_sparse().to_dok().items():   # M = P^T - I
            M[c, r] = flint.fmpq(int(K.numer(v)), int(K.denom(v)))
        for i in range(S):
            M[i, i] -= 1
        A = flint.fmpq_mat(M)
        for i in range(S):
            A[S - 1, i] = 1
        try:
            pi = A.solve(flint.fmpq_mat(S, 1, [0] * (S - 1) + [1]))
        except ZeroDivisionError:
            raise InputError(f"{entry}: the chain has {S - M.rank()} stationary laws; give `initial`") from None
        return sp.ImmutableMatrix([[sp.Rational(int(pi[i, 0].p), int(pi[i, 0].q)) for i in range(S)]])
    M = sp.Matrix(P).T - sp.eye(S)
    null = (M.nullspace(simplify=True) if symbolic else
            [sp.Matrix(v) for v in DomainMatrix.from_Matrix(M).to_field().nullspace().to_Matrix().tolist()])
    if len(null) != 1:
        raise InputError(f"{entry}: the chain has {len(null)} stationary laws; give `initial`")
    v = null[0]
    total = sum(v)
    return sp.ImmutableMatrix([[sp.simplify(x / total) if symbolic else x / total for x in v]])


@dataclass(frozen=True)
class LossFactor:
    """An independent piece of a loss model: a chain on ``P`` (float) driving ``sensors``.

    i.i.d. and Gilbert-Elliott sensors are independent, one two-state factor each
    (state 0 = received, 1 = lost); joint Markov and network losses are one factor on
    their :class:`~symkf.model.loss.LossChain`.  ``emit[s]`` are the factor's sensors'
    receivals in state ``s``.
    """

    sensors: tuple[int, ...]
    P: np.ndarray
    init: np.ndarray
    emit: np.ndarray

    @property
    def two_state(self) -> bool:
        """One sensor on states (received, lost): sampled together with the other such sensors."""
        return len(self.P) == 2 and len(self.sensors) == 1



@dataclass(frozen=True)
class Factor:
    """An independent factor of a loss model: the exact chain of the receptions of ``sensors``.

    ``chain.emit[s]`` lists those sensors' receivals in state ``s``.  i.i.d. and
    Gilbert-Elliott sensors are one two-state factor each (states: received, lost), a joint
    Markov or network model is one factor on its :class:`LossChain`.
    """

    sensors: tuple[int, ...]
    chain: LossChain

    def numeric(self) -> LossFactor:
        """The float view, for simulation (:mod:`symkf.numeric.receptions`)."""
        P, init, emit = self.chain.numeric()
        return LossFactor(self.sensors, P, init, emit)

    def sequence_probability(self, seq: Sequence[Vector]) -> sp.Expr:
        """Exact probability of ``seq`` (full receival vectors) restricted to this factor's sensors."""
        return self.chain.sequence_probability([tuple(v[j] for j in self.sensors) for v in seq])


_TWO = ((1,), (0,))  # a sensor's states: received, lost


def two_state_factor(j: int, P: sp.MatrixBase, received: sp.Expr) -> Factor:
    return Factor((j,), LossChain(_TWO, _TWO, sp.ImmutableMatrix(P), sp.ImmutableMatrix([[received, 1 - received]])))


def checked(loss: Any, system: Any = None, *, numbers: bool = False, positive: bool = False) -> "LossModel":
    """The one check of a loss model against a system (or a sensor count ``d``), returning the
    model for it: a model without a sensor count (``IID("1/10")``, a common rate) becomes the
    system's (:meth:`LossModel.with_sensors`), as NumPy broadcasts a scalar.

    Raises :class:`~symkf.errors.InputError` when ``loss`` is no symkf loss model,
    :class:`~symkf.errors.ShapeError` when its sensor count is not the system's, ``InputError``
    when ``numbers`` and it has free symbols, :class:`~symkf.errors.AssumptionError` when
    ``positive`` and Sui-You-Fu Assumption 2 fails (the model names what applies instead)."""
    if not isinstance(loss, LossModel):
        raise InputError("loss: expected a symkf loss model (IID, GilbertElliott, MarkovLoss, a network loss "
                         f"or Independent parts of these), got {type(loss).__name__}")
    if system is None:
        sized(loss, "loss")
    else:
        d = system if isinstance(system, int) else system.d
        # a common rate (IID("1/10")) meets its number of sensors here, and only here
        loss = loss.with_sensors(d) if loss.d is None else loss
        if loss.d != d:
            names = "" if isinstance(system, int) else f" ({', '.join(system.sensor_names)})"
            raise ShapeError(f"loss: the model has {loss.d} sensor(s), the system has {d}{names}")
    if numbers:
        require_numbers(loss.symbols)
    if positive:
        loss.require_positive()
    return loss


def sized(loss: "LossModel", entry: str) -> "LossModel":
    """``loss`` when it has a number of sensors; a common rate with none (``IID("1/10")`` where no
    system fixes ``d``) is an :class:`~symkf.errors.InputError` naming what is missing."""
    if loss.d is None:
        raise InputError(f"{entry}: {loss!r} is a common rate with no number of sensors here (no system gives "
                         f"one); give d (IID(\"1/10\", d=3)) or one probability per sensor")
    return loss


class LossModel(JsonDocument):
    """The loss-model interface: what a packet-loss process is, as data the rest of symkf reads.

    A new model is one class (docs/losses.md), in symkf or in an installed package that names it
    in the ``symkf.losses`` entry-point group:

    * :attr:`factors`: its independent factors as exact chains (per-sensor two-state chains,
      or one joint chain); :attr:`chain`, the joint chain, only where a query needs it (refused
      beyond ``budget`` ``max_markov_states`` before it is built);
    * capabilities: :attr:`bernoulli` (independent Bernoulli losses, Assumption 4) and
      :attr:`channel_fail` (independent two-state channels), from which the engine chooses its
      algorithms (:mod:`symkf.engine.rates`, :mod:`symkf.engine.region`);
    * :func:`checked` / :meth:`require_positive` / :meth:`require_bernoulli`: its check against a system;
    * :attr:`kind`, :attr:`keys`, :meth:`read_table`, :meth:`to_table`, :meth:`to_dict` (:meth:`to_json` its text): its file
      and JSON form (read back by :func:`symkf.model.codec.from_table`);
    * :meth:`words`, :attr:`label`, :meth:`fields`, :attr:`assumption`: its words for reports,
      tables and figures.
    """

    #: the ``[loss] kind`` of system files and JSON documents
    kind: ClassVar[str] = ""
    #: (LaTeX, plain) name for tables
    label: ClassVar[tuple[str, str]] = ("", "")
    #: kind -> model class, filled as the classes are defined
    KINDS: ClassVar[dict[str, type["LossModel"]]] = {}
    #: the keys of its ``[loss]`` table
    keys: ClassVar[frozenset[str]] = frozenset()
    #: the number of sensors; None for a common rate that takes the system's (:meth:`with_sensors`)
    d: int | None

    def with_sensors(self, d: int) -> "LossModel":
        """The model for ``d`` sensors, when :func:`checked` pairs it with a system: a model with
        its own sensor count is itself (a mismatch is the check's to report)."""
        return self

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        if "kind" in cls.__dict__:
            LossModel.KINDS[cls.kind] = cls

    # -- chains ------------------------------------------------------------------------
    @cached_property
    def chain(self) -> LossChain:
        """The joint first-order chain whose states emit the receival vectors (exact)."""
        return self._build_chain()

    def _build_chain(self) -> LossChain:  # pragma: no cover - abstract
        raise NotImplementedError

    @cached_property
    def factors(self) -> tuple[Factor, ...]:
        """The independent factors (one joint chain unless a subclass knows better)."""
        return (Factor(tuple(range(self.d)), self.chain),)

    @property
    def symbols(self) -> set[sp.Symbol]:
        """Free symbols of the transition matrix and initial law (empty for numeric models)."""
        return set(self.chain.P.free_symbols | self.chain.initial.free_symbols)

    def numeric(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Float (P, initial, emit) of the joint chain, for exact enumeration in float64; refuses
        free symbols.  Independent factors are multiplied out (Kronecker products) only after the
        size is checked against ``budget`` ``max_memory``."""
        require_numbers(self.symbols)
        if len(self.factors) == 1:
            return self.chain.numeric()
        size = math.prod(len(f.chain.states) for f in self.factors)
        budget.check("max_memory", 8 * size * size, "loss", f"the bytes of the joint {size}-state float chain "
                     "of independent sensors (simulation samples per sensor and never needs it)")
        P, init, emit = np.ones((1, 1)), np.ones(1), np.ones((1, 0), bool)
        for f in self.factors:   # sensor order: factors cover 0..d-1 in order
            fP, finit, femit = f.chain.numeric()
            P, init = np.kron(P, fP), np.kron(init, finit)
            emit = np.hstack([np.repeat(emit, len(femit), axis=0), np.tile(femit, (len(emit), 1))])
        return P, init, emit

    def sequence_probability(self, seq: Sequence[Vector]) -> sp.Expr:
        """Exact probability that the first ``len(seq)`` receival vectors equal ``seq`` (per factor)."""
        return sp.expand(sp.Mul(*[f.sequence_probability(seq) for f in self.factors]))

    def subs(self, values: Mapping[Any, Any]) -> "LossModel":
        """A copy with symbols replaced by exact values."""
        raise NotImplementedError

    # -- capabilities and checks ---------------------------------------------------------
    @property
    def bernoulli(self) -> tuple[sp.Expr, ...] | None:
        """Per-sensor loss probabilities when receptions are independent Bernoulli across sensors
        and time (Sui-You-Fu Assumption 4), else None."""
        return None

    @property
    def channel_fail(self) -> tuple[sp.Expr, ...] | None:
        """Per-sensor ``P(lost | received last)`` when the sensors are independent two-state
        Gilbert-Elliott channels: what :func:`symkf.engine.stability.critical_recovery_rate` holds fixed
        while it varies the recovery probability; else None."""
        return None

    @property
    def channel_recover(self) -> tuple[sp.Expr, ...] | None:
        """Per-sensor ``P(received | lost last)`` of the same channels (what a per-sensor
        :func:`symkf.engine.recovery.critical_recovery_rate` holds fixed for the other sensors); else None."""
        return None

    @property
    def assumption(self) -> str:
        """What :func:`symkf.engine.stability.stability` checked of this loss process (its verdict says it)."""
        return "Markov with positive transitions (Assumption 2)"

    def positivity_failure(self) -> str | None:
        """Why Assumption 2's positivity fails, or None when every transition is positive."""
        for (r, row), s in itertools.product(enumerate(self.chain.P.tolist()), range(len(self.chain.states))):
            if self._reachable(r, s):
                p = row[s]
                if not p.free_symbols and (p.p <= 0 if isinstance(p, sp.Rational) else sign(p) <= 0):
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

    def require_bernoulli(self, assumption: str, applies_instead: str | None) -> tuple[sp.Expr, ...]:
        """The per-sensor loss probabilities, or :class:`~symkf.errors.AssumptionError` naming
        ``assumption`` (a theorem for i.i.d. losses only) and what applies instead."""
        if self.bernoulli is None:
            raise AssumptionError(f"the loss model is {self.words()}, not independent Bernoulli (i.i.d.) losses",
                                  assumption=assumption, applies_instead=applies_instead)
        return self.bernoulli

    # -- words and file form ---------------------------------------------------------------
    def words(self) -> str:
        """The model as reports and figure titles say it."""
        return self.label[1] + " losses"

    def fields(self) -> tuple[tuple[str, str, tuple[sp.Expr, ...]], ...]:
        """(key, LaTeX symbol, values) of the parameters a table shows."""
        return ()

    def to_table(self) -> dict[str, Any]:
        """The ``[loss]`` table of a system file (numbers as exact strings); read back by :func:`symkf.model.codec.from_table`."""
        raise NotImplementedError

    def to_toml(self) -> str:
        """The ``[loss]`` table of a system file as TOML text (:meth:`to_table`)."""
        return "[loss]\n" + "".join(f"{k} = {_toml(v)}\n" for k, v in self.to_table().items())

    def to_dict(self) -> dict[str, Any]:
        """The JSON object of the model: :meth:`to_table` (joint chains add their lifted chain)."""
        return self.to_table()

    def _with_chain(self, out: dict[str, Any]) -> dict[str, Any]:
        """``out`` with the joint chain (states, receival vectors, P, initial law) as exact strings."""
        chain = self.chain
        shown = {p: str(p) for p in chain.P.values()} | {0: "0"}  # lifted chains: 10^5 entries, few values
        return {**out, "chain": {"states": [str(s) for s in chain.states], "emit": [list(v) for v in chain.emit],
                                 "P": [[shown[p] for p in row] for row in chain.P.tolist()],
                                 "initial": [str(p) for p in chain.initial]}}


    @classmethod
    def read_table(cls, table: dict, where: str, d: int, rationalize: bool = False) -> "LossModel":
        """The model of a ``[loss]`` table of kind :attr:`kind` (checked against :attr:`keys`)."""
        raise NotImplementedError



def exact_strings(values: Iterable[Any]) -> list[str]:
    return [str(v) for v in values]


def _toml(value: Any) -> str:
    """A TOML value of :meth:`LossModel.to_table`'s strings, integers, lists and tables (JSON
    string escapes are TOML's)."""
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, int) and not isinstance(value, bool):
        return str(value)
    if isinstance(value, list):
        return "[" + ", ".join(map(_toml, value)) + "]"
    if isinstance(value, dict):
        return "{ " + ", ".join(f"{json.dumps(str(k))} = {_toml(v)}" for k, v in value.items()) + " }"
    raise TypeError(f"no TOML form for {value!r}")   # pragma: no cover - to_table gives none



def check_joint_size(d: int) -> None:
    """Refuse the exact joint chain of ``d`` independent sensors before its ``2^d`` states are built."""
    if isinstance(d, bool) or not isinstance(d, int) or d < 1:
        raise InputError(f"d: expected a positive number of sensors, got {d!r}")
    budget.check_power("max_markov_states", 2, d, "loss", f"the number of states of the joint chain of {d} "
                       "independent sensors (symkf decides and samples them per sensor; this query needs the joint chain)")


check_public(globals())

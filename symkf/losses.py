"""Packet-loss models (Sui-You-Fu Assumptions 2 and 4) behind one interface, :class:`LossModel`.

A model is a product of independent :class:`Factor` s, each a first-order finite Markov
chain (:class:`LossChain`) whose state determines the receivals of its sensors (``1`` =
packet received): one two-state chain per sensor for :class:`IID` and
:class:`GilbertElliott`, one joint chain for :class:`MarkovLoss` and the network losses
(:mod:`symkf.network.loss`), and :class:`Independent` the parts' factors side by side (any of these
on consecutive groups of sensors).  A joint chain of order ``nu`` is lifted to windows of its last
``nu`` receival vectors (Remark 3).  Parameters are exact numbers or sympy symbols.  What a
model does (its factors, the exact rate of a hyperplane class, its check against a system,
its sampling, its file form and its words) is asked of the model: docs/losses.md shows how to
add one.
"""

from __future__ import annotations

import itertools
import json
import math
from dataclasses import dataclass
from functools import cached_property
from typing import Any, ClassVar, Iterable, Mapping, Sequence

import numpy as np  # float chains for simulation (LossModel.numeric)
import sympy as sp
from sympy.polys.matrices import DomainMatrix

from . import budget, receptions
from .errors import AssumptionError, InputError, ProbabilityError, ShapeError
from .exact.algebraic import sign
from .exact.arguments import check_public
from .exact.numbers import rationalization, substitution, sympify, to_exact
from .model import System
from .receptions import LossFactor

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
    """Entries as float64: rationals by Python's int division (correctly rounded; python-flint 0.7's
    fmpq has no float), others by evalf(30)."""
    return np.array([[int(v.p) / int(v.q) if v.is_Rational else float(v.evalf(30)) for v in row]
                     for row in M.tolist()], dtype=float).reshape(M.shape)


def stationary_law(P: sp.MatrixBase, entry: str) -> sp.ImmutableMatrix:
    """The unique stationary row vector ``pi = pi P`` of a stochastic matrix, exactly (a null space
    of ``P^T - I``: over the rationals by :class:`~sympy.polys.matrices.DomainMatrix`, with
    symbols by sympy); raises naming ``entry`` when it is not unique."""
    S = P.shape[0]
    M = sp.Matrix(P).T - sp.eye(S)
    if not M.free_symbols:
        dm = DomainMatrix.from_Matrix(M).to_field()
        null = [sp.Matrix(v) for v in dm.nullspace().to_Matrix().tolist()]
    else:
        null = M.nullspace(simplify=True)
    if len(null) != 1:
        raise InputError(f"{entry}: the chain has {len(null)} stationary laws; give `initial`")
    v = null[0]
    total = sum(v)
    return sp.ImmutableMatrix([[sp.simplify(x / total) if M.free_symbols else x / total for x in v]])


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
        """The float view, for simulation (:mod:`symkf.receptions`)."""
        P, init, emit = self.chain.numeric()
        return LossFactor(self.sensors, P, init, emit)

    def sequence_probability(self, seq: Sequence[Vector]) -> sp.Expr:
        """Exact probability of ``seq`` (full receival vectors) restricted to this factor's sensors."""
        return self.chain.sequence_probability([tuple(v[j] for j in self.sensors) for v in seq])


_TWO = ((1,), (0,))  # a sensor's states: received, lost


def _sensor_factor(j: int, P: sp.MatrixBase, received: sp.Expr) -> Factor:
    return Factor((j,), LossChain(_TWO, _TWO, sp.ImmutableMatrix(P), sp.ImmutableMatrix([[received, 1 - received]])))


def checked(loss: Any, system: Any = None, *, numbers: bool = False, positive: bool = False) -> "LossModel":
    """The one check of a loss model against a system (or a sensor count ``d``).

    Raises :class:`~symkf.errors.InputError` when ``loss`` is no symkf loss model,
    :class:`~symkf.errors.ShapeError` when its sensor count is not the system's, ``InputError``
    when ``numbers`` and it has free symbols, :class:`~symkf.errors.AssumptionError` when
    ``positive`` and Sui-You-Fu Assumption 2 fails (the model names what applies instead)."""
    if not isinstance(loss, LossModel):
        raise InputError("loss: expected a symkf loss model (IID, GilbertElliott, MarkovLoss, a network loss "
                         f"or Independent parts of these), got {type(loss).__name__}")
    if system is not None:
        d = system if isinstance(system, int) else system.d
        if loss.d != d:
            names = "" if isinstance(system, int) else f" ({', '.join(system.sensor_names)})"
            raise ShapeError(f"loss: the model has {loss.d} sensor(s), the system has {d}{names}")
    if numbers:
        require_numbers(loss.symbols)
    if positive:
        loss.require_positive()
    return loss


class LossModel:
    """The loss-model interface: everything the rest of symkf asks of a packet-loss process.

    A model answers for itself, so that a new one is added in one place (docs/losses.md):

    * :attr:`factors`: its independent factors as exact chains (per-sensor two-state chains,
      or one joint chain); :attr:`chain`, the joint chain, only where a query needs it (refused
      beyond ``budget`` ``max_markov_states`` before it is built);
    * :meth:`hyperplane_rate`: the exact decay rate of a hyperplane class (Sui-You-Fu eq. 36),
      through the rate functions of :mod:`symkf.decay`; :attr:`bernoulli` for the i.i.d. screen;
    * :func:`checked` / :meth:`require_positive` / :meth:`require_bernoulli`: its check against a system;
    * :meth:`sample`: receptions drawn per factor (memory linear in ``d``);
    * :attr:`kind`, :meth:`to_table`, :meth:`to_json`, :func:`from_table`: its file and JSON form;
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
    d: int

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

    # -- the exact engine ----------------------------------------------------------------
    @property
    def bernoulli(self) -> tuple[sp.Expr, ...] | None:
        """Per-sensor loss probabilities when receptions are independent Bernoulli across sensors
        and time (Sui-You-Fu Assumption 4), else None."""
        return None

    @property
    def channel_fail(self) -> tuple[sp.Expr, ...] | None:
        """Per-sensor ``P(lost | received last)`` when the sensors are independent two-state
        Gilbert-Elliott channels: what :func:`symkf.stability.critical_recovery_rate` holds fixed
        while it varies the recovery probability; else None."""
        return None

    def hyperplane_rate(self, br: Any, H: frozenset[int]) -> sp.Expr:
        """``rho(M_H)``: the exact decay rate per period of "received only inside ``H``" for the
        block rows ``br`` (Sui-You-Fu eq. 36), the Perron root of the restricted transfer."""
        from .decay import perron_root, restricted_transfer
        return perron_root(restricted_transfer(br, H, self))

    @property
    def assumption(self) -> str:
        """What :func:`symkf.stability.stability` checked of this loss process (its verdict says it)."""
        return "Markov with positive transitions (Assumption 2)"

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

    def require_bernoulli(self, assumption: str, applies_instead: str | None) -> tuple[sp.Expr, ...]:
        """The per-sensor loss probabilities, or :class:`~symkf.errors.AssumptionError` naming
        ``assumption`` (a theorem for i.i.d. losses only) and what applies instead."""
        if self.bernoulli is None:
            raise AssumptionError(f"the loss model is {self.words()}, not independent Bernoulli (i.i.d.) losses",
                                  assumption=assumption, applies_instead=applies_instead)
        return self.bernoulli

    def stability_conditions(self, system: System) -> sp.Basic:
        """Mean-square stability as conditions in the model's symbols (:func:`symkf.region.stability_conditions`)."""
        raise InputError(f"loss: stability conditions are given for IID and GilbertElliott, not {self.words()}; "
                         "substitute numbers and use symkf.stability.stability")

    # -- simulation ----------------------------------------------------------------------
    def sample(self, horizon: int, paths: int, rng: np.random.Generator) -> np.ndarray:
        """Receptions (horizon, paths, d) bool, 1 = received, drawn per factor (:func:`symkf.receptions.sample`)."""
        checked(self, numbers=True)
        return receptions.sample([f.numeric() for f in self.factors], horizon, paths, self.d, rng)

    # -- words and file form ---------------------------------------------------------------
    def words(self) -> str:
        """The model as reports and figure titles say it."""
        return self.label[1] + " losses"

    def fields(self) -> tuple[tuple[str, str, tuple[sp.Expr, ...]], ...]:
        """(key, LaTeX symbol, values) of the parameters a table shows."""
        return ()

    def to_table(self) -> dict[str, Any]:
        """The ``[loss]`` table of a system file (numbers as exact strings); read back by :func:`from_table`."""
        raise NotImplementedError

    def to_toml(self) -> str:
        """The ``[loss]`` table of a system file as TOML text (:meth:`to_table`)."""
        return "[loss]\n" + "".join(f"{k} = {_toml(v)}\n" for k, v in self.to_table().items())

    def to_json(self) -> dict[str, Any]:
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


def from_table(table: Mapping[str, Any], d: int, where: str = "loss") -> LossModel:
    """The loss model of a ``[loss]`` table or its JSON object (:meth:`LossModel.to_json`) for ``d``
    sensors: the reader of system files (:mod:`symkf.files`), so files and JSON share one codec."""
    from .files import read_loss
    return read_loss(dict(table), where, d)


def _strings(values: Iterable[Any]) -> list[str]:
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

    kind = "iid"
    label = ("i.i.d.", "i.i.d.")

    #: the keys of its ``[loss]`` table
    keys: ClassVar[frozenset[str]] = frozenset({"kind", "loss"})

    @classmethod
    def read_table(cls, table: dict, where: str, d: int, rationalize: bool = False) -> "IID":
        """The model of a ``[loss]`` table (or its JSON object) for ``d`` sensors; ``where`` names it in errors."""
        from .files import _exact, _get
        return cls(_exact(_get(table, "loss", where), f"{where} loss", rationalize))

    def _build_chain(self) -> LossChain:
        _joint_cap(self.d)
        vecs = tuple(itertools.product((1, 0), repeat=self.d))
        row = [sp.Mul(*[(1 - e) if g else e for g, e in zip(v, self.loss)]) for v in vecs]
        return LossChain(vecs, vecs, sp.ImmutableMatrix([row] * len(vecs)), sp.ImmutableMatrix([row]))

    @cached_property
    def factors(self) -> tuple[Factor, ...]:
        return tuple(_sensor_factor(j, [[1 - e, e], [1 - e, e]], 1 - e) for j, e in enumerate(self.loss))

    def positivity_failure(self) -> str | None:
        # Independence makes (27) of Sui-You-Fu hold with beta = epsilon = 1,
        # so Theorem 4 needs no positivity for i.i.d. losses.
        return None

    @property
    def symbols(self) -> set[sp.Symbol]:
        return set().union(*(sympify(e).free_symbols for e in self.loss))

    @property
    def bernoulli(self) -> tuple[sp.Expr, ...]:
        return self.loss

    def hyperplane_rate(self, br: Any, H: frozenset[int]) -> sp.Expr:
        """``prod_j loss_j^(k_j)``, ``k_j`` sensor ``j``'s elements outside ``H`` (every one lost)."""
        from .decay import _outside_vectors
        (ks,) = _outside_vectors(br, [H])
        return sp.Mul(*[e ** k for e, k in zip(self.loss, ks)])

    @property
    def assumption(self) -> str:
        return "i.i.d. (Assumption 4)"

    def stability_conditions(self, system: System) -> sp.Basic:
        from .region import stability_region
        return stability_region(system).conditions(self.loss)

    def words(self) -> str:
        return "i.i.d. losses " + ", ".join(map(str, self.loss))

    def fields(self) -> tuple[tuple[str, str, tuple[sp.Expr, ...]], ...]:
        return (("loss", r"\varepsilon", self.loss),)

    def to_table(self) -> dict[str, Any]:
        return {"kind": self.kind, "loss": _strings(self.loss)}

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
        self._initial_given = initial_received is not None
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

    kind = "gilbert-elliott"
    label = ("Gilbert--Elliott", "Gilbert-Elliott")

    #: the keys of its ``[loss]`` table
    keys: ClassVar[frozenset[str]] = frozenset({"kind", "fail", "recover", "initial_received"})

    @classmethod
    def read_table(cls, table: dict, where: str, d: int, rationalize: bool = False) -> "GilbertElliott":
        """The model of a ``[loss]`` table (or its JSON object) for ``d`` sensors; ``where`` names it in errors."""
        from .files import _exact, _get
        fail, recover = (_exact(_get(table, key, where), f"{where} {key}", rationalize) for key in ("fail", "recover"))
        initial = table.get("initial_received")
        initial = None if initial is None else _exact(initial, f"{where} initial_received", rationalize)
        return cls(fail, recover, initial)

    def _build_chain(self) -> LossChain:
        _joint_cap(self.d)
        vecs = tuple(itertools.product((1, 0), repeat=self.d))
        P = [[sp.Mul(*[self.sensor_matrix(i)[1 - a[i], 1 - b[i]] for i in range(self.d)])
              for b in vecs] for a in vecs]
        init = [sp.Mul(*[q if g else 1 - q for g, q in zip(v, self.initial_received)]) for v in vecs]
        return LossChain(vecs, vecs, sp.ImmutableMatrix(P), sp.ImmutableMatrix([init]))

    @cached_property
    def factors(self) -> tuple[Factor, ...]:
        return tuple(_sensor_factor(j, self.sensor_matrix(j), q) for j, q in enumerate(self.initial_received))

    @property
    def symbols(self) -> set[sp.Symbol]:
        return set().union(*(sympify(v).free_symbols for v in self.fail + self.recover + self.initial_received))

    def positivity_failure(self) -> str | None:
        # the joint transition is the product of the sensors' (independent channels), so it is
        # positive for every pair of states iff every sensor's 2x2 transition is positive
        for i in range(self.d):
            P = self.sensor_matrix(i)
            for r, s in itertools.product(range(2), repeat=2):
                if not P[r, s].free_symbols and sign(P[r, s]) <= 0:
                    state = ("received", "lost")
                    key = f"fail[{i}] = {self.fail[i]}" if r == 0 else f"recover[{i}] = {self.recover[i]}"
                    return (f"{key} (sensor {i}): P(next {state[s]} | {state[r]}) = {P[r, s]}, so the joint "
                            "chain has zero transitions; Assumption 2 needs every transition probability positive")
        return None

    @property
    def channel_fail(self) -> tuple[sp.Expr, ...]:
        return self.fail

    def hyperplane_rate(self, br: Any, H: frozenset[int]) -> sp.Expr:
        """The product over sensors of their 2x2 restricted transfers' Perron roots (:func:`symkf.decay.ge_rate`)."""
        from .decay import ge_rate
        return ge_rate(br, H, self)

    def stability_conditions(self, system: System) -> sp.Basic:
        from .region import _condition, ge_margins
        return sp.And(*[_condition(m) for m in ge_margins(system, self)])

    def words(self) -> str:
        return (f"Gilbert-Elliott channels, fail {', '.join(map(str, self.fail))}, "
                f"recover {', '.join(map(str, self.recover))}")

    def fields(self) -> tuple[tuple[str, str, tuple[sp.Expr, ...]], ...]:
        return (("fail", "f", self.fail), ("recover", "q", self.recover))

    def to_table(self) -> dict[str, Any]:
        out = {"kind": self.kind, "fail": _strings(self.fail), "recover": _strings(self.recover)}
        if self._initial_given:
            out["initial_received"] = _strings(self.initial_received)
        return out

    def subs(self, values: Mapping[Any, Any]) -> "GilbertElliott":
        values = substitution(values, "subs", self.symbols)

        def s(xs):
            return [sympify(x).subs(values) for x in xs]
        return GilbertElliott(s(self.fail), s(self.recover), s(self.initial_received) if self._initial_given else None)

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
            init = stationary_law(P, "initial")
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

    kind = "markov"
    label = ("joint Markov", "joint Markov")

    #: the keys of its ``[loss]`` table
    keys: ClassVar[frozenset[str]] = frozenset({"kind", "order", "states", "P", "initial"})

    @classmethod
    def read_table(cls, table: dict, where: str, d: int, rationalize: bool = False) -> "MarkovLoss":
        """The model of a ``[loss]`` table (or its JSON object) for ``d`` sensors; ``where`` names it in errors."""
        from .errors import FileFormatError
        from .files import _built, _exact, _get, _positive_int
        order = _positive_int(table.get("order", 1), f"{where} key 'order'")
        states = _get(table, "states", where)
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
        P = _exact(_get(table, "P", where), f"{where} P", rationalize)
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
            initial = _exact(initial, f"{where} initial", rationalize)
            if not isinstance(initial, list) or len(initial) != len(histories):
                raise FileFormatError(f"{where} key 'initial': expected {len(histories)} probabilities, one per "
                                      "history (the rows of 'P')")
            initial = dict(zip(histories, initial))
        model = _built(lambda: cls({h: dict(zip(vectors, row)) for h, row in zip(histories, P)}, order,
                                          initial), "key 'P'")
        _built(lambda: model.chain, "key 'initial'")  # the initial law is checked when the chain is built
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

    def to_json(self) -> dict[str, Any]:
        return self._with_chain(self.to_table())

    def subs(self, values: Mapping[Any, Any]) -> "MarkovLoss":
        values = substitution(values, "subs", self.symbols)
        table = {h: {n: sympify(p).subs(values) for n, p in row.items()} for h, row in self.table.items()}
        init = None if self._initial is None else {
            k: sympify(p).subs(values) for k, p in self._initial.items()}
        return MarkovLoss(table, self.order, init)

    def __repr__(self) -> str:
        return f"MarkovLoss(d={self.d}, order={self.order})"


class Independent(LossModel):
    """Independent loss models on consecutive groups of sensors: ``parts[0]`` drives the first
    ``parts[0].d`` sensors, ``parts[1]`` the next ``parts[1].d``, and so on.

    Sensors sharing a channel in small groups (a joint :class:`MarkovLoss` per group) beside
    Gilbert-Elliott or i.i.d. ones: the whole is a product of independent chains (Sui-You-Fu
    Assumption 2 with the product chain), its factors are the parts' factors, so the exact engine
    rates hyperplanes factor by factor and simulation samples them one by one; the joint chain of
    all sensors (the product of the parts' states) is built only where a query needs it.

    Parameters
    ----------
    parts : sequence of loss models
        At least one; an ``Independent`` part is flattened into its own parts.

    Raises
    ------
    InputError
        ``parts`` is empty or holds something that is not a loss model.

    Examples
    --------
    Two Gilbert-Elliott channels and one i.i.d. sensor, as one model of three sensors:

    >>> import symkf as sk
    >>> loss = sk.Independent([sk.GilbertElliott(["1/10", "1/5"], ["1/2", "1/2"]), sk.IID(["1/4"])])
    >>> loss.d, [f.sensors for f in loss.factors]
    (3, [(0,), (1,), (2,)])

    ``A = 2`` with one sensor on a part of its own: the decisive pattern is a run of losses, so
    the margin is ``4 (1 - recover) = 2`` (by hand):

    >>> S = sk.System(A=[[2]], sensors=[sk.Sensor(C=[[1]])])
    >>> sk.stability(S, sk.Independent([sk.GilbertElliott(["1/10"], ["1/2"])])).margins[0].exact
    2
    """

    def __init__(self, parts: Sequence[LossModel]):
        flat = [q for part in parts for q in (part.parts if isinstance(part, Independent) else [part])]
        if not flat:
            raise InputError("parts: give at least one loss model")
        self.parts = tuple(flat)
        self.d = sum(p.d for p in self.parts)

    def _offsets(self) -> list[int]:
        return list(itertools.accumulate([0] + [p.d for p in self.parts[:-1]]))

    @cached_property
    def factors(self) -> tuple[Factor, ...]:
        return tuple(Factor(tuple(start + j for j in f.sensors), f.chain)
                     for start, part in zip(self._offsets(), self.parts) for f in part.factors)

    def _build_chain(self) -> LossChain:
        chains = [f.chain for f in self.factors]
        budget.check("max_markov_states", math.prod(len(c.states) for c in chains), "loss",
                     "the number of states of the joint chain of independent parts (symkf decides and samples "
                     "them part by part; this query needs the joint chain)")
        states = tuple(itertools.product(*[range(len(c.states)) for c in chains]))
        P = sp.ImmutableMatrix([[sp.Mul(*[c.P[a, b] for c, a, b in zip(chains, x, y)]) for y in states] for x in states])
        init = sp.ImmutableMatrix([[sp.Mul(*[c.initial[0, a] for c, a in zip(chains, x)]) for x in states]])
        emit = tuple(tuple(g for c, a in zip(chains, x) for g in c.emit[a]) for x in states)
        return LossChain(tuple(tuple(c.states[a] for c, a in zip(chains, x)) for x in states), emit, P, init)

    @property
    def symbols(self) -> set[sp.Symbol]:
        return set().union(*(p.symbols for p in self.parts))

    @property
    def bernoulli(self) -> tuple[sp.Expr, ...] | None:
        losses = [p.bernoulli for p in self.parts]
        return None if None in losses else tuple(e for part in losses for e in part)

    @property
    def channel_fail(self) -> tuple[sp.Expr, ...] | None:
        fails = [p.channel_fail for p in self.parts]
        return None if None in fails else tuple(f for part in fails for f in part)

    def _first_failure(self) -> tuple[LossModel, str] | None:
        for i, (start, part) in enumerate(zip(self._offsets(), self.parts)):
            why = part.positivity_failure()
            if why:
                return part, f"part {i} (sensors {start} to {start + part.d - 1}): {why}"
        return None

    def positivity_failure(self) -> str | None:
        # the product chain's transitions are products of the parts': all positive iff each part's are
        failure = self._first_failure()
        return None if failure is None else failure[1]

    @property
    def applies_without_positivity(self) -> str | None:   # type: ignore[override]
        failure = self._first_failure()
        return None if failure is None else failure[0].applies_without_positivity

    @property
    def assumption(self) -> str:
        return "i.i.d. (Assumption 4)" if self.bernoulli is not None else super().assumption

    kind = "independent"
    label = ("independent", "independent")

    #: the keys of its ``[loss]`` table; each part's table adds ``sensors``, its number of sensors
    keys: ClassVar[frozenset[str]] = frozenset({"kind", "parts"})

    @classmethod
    def read_table(cls, table: dict, where: str, d: int, rationalize: bool = False) -> "Independent":
        """The model of a ``[loss]`` table (or its JSON object): ``parts``, a list of ``[loss]`` tables
        each with ``sensors``, the number of consecutive sensors it drives."""
        from .errors import FileFormatError
        from .files import _get, _positive_int, read_loss
        parts = _get(table, "parts", where)
        if not isinstance(parts, list) or not parts or not all(isinstance(t, dict) for t in parts):
            raise FileFormatError(f"{where} key 'parts': expected a non-empty list of [loss] tables, each with "
                                  "'sensors' (how many consecutive sensors it drives)")
        out = []
        for i, part in enumerate(parts):
            at = f"{where} parts[{i}]"
            if part.get("kind") == cls.kind:   # parts flatten: a nested list says nothing more (and recurses)
                raise FileFormatError(f"{at}: kind {cls.kind!r} cannot be a part; list its parts here instead")
            count = _positive_int(_get(part, "sensors", at), f"{at} key 'sensors'")
            out.append(read_loss({k: v for k, v in part.items() if k != "sensors"}, at, count, rationalize))
        return cls(out)

    def words(self) -> str:
        def which(a: int, k: int) -> str:
            return f"sensor {a}" if k == 1 else f"sensors {a}-{a + k - 1}"
        return "independent parts: " + "; ".join(f"{which(a, p.d)} {p.words()}" for a, p in zip(self._offsets(), self.parts))

    def fields(self) -> tuple[tuple[str, str, tuple[sp.Expr, ...]], ...]:
        return (("parts", "m", (sp.Integer(len(self.parts)),)),
                ("sensors", "d_i", tuple(sp.Integer(p.d) for p in self.parts)))

    def to_table(self) -> dict[str, Any]:
        return {"kind": self.kind, "parts": [{"sensors": p.d, **p.to_table()} for p in self.parts]}

    def to_json(self) -> dict[str, Any]:
        return {"kind": self.kind, "parts": [{"sensors": p.d, **p.to_json()} for p in self.parts]}

    def subs(self, values: Mapping[Any, Any]) -> "Independent":
        values = substitution(values, "subs", self.symbols)
        return Independent([p.subs({k: v for k, v in values.items() if k in p.symbols}) if p.symbols else p
                            for p in self.parts])

    def __repr__(self) -> str:
        return f"Independent({list(self.parts)!r})"


def _is_vector(key: Any) -> bool:
    return isinstance(key, tuple) and all(isinstance(v, int) for v in key)


def _joint_cap(d: int) -> None:
    """Refuse the exact joint chain of ``d`` independent sensors before its ``2^d`` states are built."""
    budget.check("max_markov_states", 2 ** d, "loss", f"the number of states of the joint chain of {d} "
                 "independent sensors (symkf decides and samples them per sensor; this query needs the joint chain)")


check_public(globals())

"""Gilbert-Elliott channels: an independent two-state Markov chain per sensor (Sui-You-Fu
Assumption 2 with independent sensors)."""
from __future__ import annotations

import itertools
from functools import cached_property
from typing import Any, ClassVar, Mapping, Sequence

import sympy as sp

from ..errors import InputError
from ..exact.algebraic import sign
from ..arguments import check_public, index
from ..exact.numbers import rationalization, substitution, sympify
from .loss import (Factor, LossChain, LossModel, check_joint_size, exact_strings, is_scalar, probabilities,
                   two_state_factor)
from .codec import entry, exact_values


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
        lists = [len(list(v)) for v in (fail, recover) if not is_scalar(v)]
        d = d if d is not None or not lists else lists[0]
        with rationalization("GilbertElliott"):
            self.fail = probabilities(fail, "fail", rationalize, d)
            self.recover = probabilities(recover, "recover", rationalize, d)
            if initial_received is not None:
                initial_received = probabilities(initial_received, "initial_received", rationalize)
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
            self.initial_received = probabilities(initial_received, "initial_received")
            if len(self.initial_received) != self.d:
                raise InputError(f"initial_received: {len(self.initial_received)} values for {self.d} sensors")

    def sensor_matrix(self, i: int) -> sp.ImmutableMatrix:
        """Transition matrix of sensor ``i`` on states (received, lost)."""
        i = index(i, self.d, "i")
        f, r = self.fail[i], self.recover[i]
        return sp.ImmutableMatrix([[1 - f, f], [r, 1 - r]])

    kind = "gilbert-elliott"
    label = ("Gilbert--Elliott", "Gilbert-Elliott")

    #: the keys of its ``[loss]`` table
    keys: ClassVar[frozenset[str]] = frozenset({"kind", "fail", "recover", "initial_received"})

    @classmethod
    def read_table(cls, table: dict, where: str, d: int, rationalize: bool = False) -> "GilbertElliott":
        """The model of a ``[loss]`` table (or its JSON object) for ``d`` sensors; ``where`` names it in errors."""
        fail, recover = (exact_values(entry(table, key, where), f"{where} {key}", rationalize) for key in ("fail", "recover"))
        initial = table.get("initial_received")
        initial = None if initial is None else exact_values(initial, f"{where} initial_received", rationalize)
        return cls(fail, recover, initial)

    def _build_chain(self) -> LossChain:
        check_joint_size(self.d)
        vecs = tuple(itertools.product((1, 0), repeat=self.d))
        P = [[sp.Mul(*[self.sensor_matrix(i)[1 - a[i], 1 - b[i]] for i in range(self.d)])
              for b in vecs] for a in vecs]
        init = [sp.Mul(*[q if g else 1 - q for g, q in zip(v, self.initial_received)]) for v in vecs]
        return LossChain(vecs, vecs, sp.ImmutableMatrix(P), sp.ImmutableMatrix([init]))

    @cached_property
    def factors(self) -> tuple[Factor, ...]:
        return tuple(two_state_factor(j, self.sensor_matrix(j), q) for j, q in enumerate(self.initial_received))

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

    @property
    def channel_recover(self) -> tuple[sp.Expr, ...]:
        return self.recover

    def words(self) -> str:
        return (f"Gilbert-Elliott channels, fail {', '.join(map(str, self.fail))}, "
                f"recover {', '.join(map(str, self.recover))}")

    def fields(self) -> tuple[tuple[str, str, tuple[sp.Expr, ...]], ...]:
        return (("fail", "f", self.fail), ("recover", "q", self.recover))

    def to_table(self) -> dict[str, Any]:
        out = {"kind": self.kind, "fail": exact_strings(self.fail), "recover": exact_strings(self.recover)}
        if self._initial_given:
            out["initial_received"] = exact_strings(self.initial_received)
        return out

    def subs(self, values: Mapping[Any, Any]) -> "GilbertElliott":
        values = substitution(values, "subs", self.symbols)

        def s(xs):
            return [sympify(x).subs(values) for x in xs]
        return GilbertElliott(s(self.fail), s(self.recover), s(self.initial_received) if self._initial_given else None)

    def __repr__(self) -> str:
        return (f"GilbertElliott(fail={[str(x) for x in self.fail]}, "
                f"recover={[str(x) for x in self.recover]})")


check_public(globals())

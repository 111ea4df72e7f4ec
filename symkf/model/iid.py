"""Independent Bernoulli losses per sensor (Sui-You-Fu Assumption 4)."""
from __future__ import annotations

import itertools
from functools import cached_property
from typing import Any, ClassVar, Mapping, Sequence

import sympy as sp

from ..arguments import check_public
from ..exact.numbers import rationalization, substitution, sympify
from .loss import (Factor, LossChain, LossModel, check_joint_size, exact_strings, is_scalar, probabilities,
                   probability, sized, two_state_factor)
from .codec import entry, exact_values


class IID(LossModel):
    """Independent Bernoulli losses: sensor ``i`` loses each packet with probability ``loss[i]``.

    Sui-You-Fu Assumption 4 (arrival probability ``p_i = 1 - loss[i]``), independent across
    sensors and time.

    Parameters
    ----------
    loss : sequence or number
        One loss probability per sensor: exact numbers in ``[0, 1]`` (ints, Fractions, sympy
        numbers, strings such as ``"1/10"``) or sympy symbols
        (:func:`symkf.engine.region.stability_conditions`); a single number is every sensor's.
    d : int, optional
        The number of sensors: ``IID("1/10", d=3)`` is ``IID(["1/10"] * 3)``.  Without it a
        single number is a common rate that takes the number of sensors of the system it meets,
        as NumPy broadcasts a scalar: in every public function given both (:mod:`symkf.arguments`),
        in :func:`symkf.model.loss.checked` and in a file's ``[loss]`` table; where no system
        gives one, the model refuses, naming the missing count.

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
    >>> S = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]]), sk.Sensor(C=[[0, 1]])])
    >>> sk.stability(S, sk.IID("1/10")) == sk.stability(S, sk.IID(["1/10", "1/10"]))
    True
    >>> sk.IID(["3/2"])
    Traceback (most recent call last):
    ...
    symkf.errors.ProbabilityError: loss[0]: 3/2 is not a probability (must lie in [0, 1])
    """

    def __init__(self, loss: Sequence[Any] | Any, *, d: int | None = None, rationalize: bool | str = False):
        with rationalization("IID"):
            if d is None and is_scalar(loss):
                self._common, self._loss, self.d = probability(loss, "loss", rationalize), None, None
            else:
                self._common, self._loss = None, probabilities(loss, "loss", rationalize, d)
                self.d = len(self._loss)

    @property
    def loss(self) -> tuple[sp.Expr, ...]:
        """The loss probability of each sensor (a common rate: once it meets a system)."""
        return sized(self, "loss")._loss

    def with_sensors(self, d: int) -> "IID":
        """A common rate (``IID("1/10")``) as every one of ``d`` sensors' rate."""
        return self if self._common is None else IID([self._common] * d)

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
        return cls(exact_values(entry(table, "loss", where), f"{where} loss", rationalize))

    def _build_chain(self) -> LossChain:
        loss = self.loss  # a common rate refuses here, before its missing d is used
        check_joint_size(self.d)
        vecs = tuple(itertools.product((1, 0), repeat=self.d))
        row = [sp.Mul(*[(1 - e) if g else e for g, e in zip(v, loss)]) for v in vecs]
        return LossChain(vecs, vecs, sp.ImmutableMatrix([row] * len(vecs)), sp.ImmutableMatrix([row]))

    @cached_property
    def factors(self) -> tuple[Factor, ...]:
        return tuple(two_state_factor(j, [[1 - e, e], [1 - e, e]], 1 - e) for j, e in enumerate(self.loss))

    def positivity_failure(self) -> str | None:
        # Independence makes (27) of Sui-You-Fu hold with beta = epsilon = 1,
        # so Theorem 4 needs no positivity for i.i.d. losses.
        return None

    @property
    def symbols(self) -> set[sp.Symbol]:
        return set().union(*(sympify(e).free_symbols for e in (self.loss if self.d else (self._common,))))

    @property
    def bernoulli(self) -> tuple[sp.Expr, ...]:
        return self.loss

    @property
    def assumption(self) -> str:
        return "i.i.d. (Assumption 4)"

    def words(self) -> str:
        return "i.i.d. losses " + (", ".join(map(str, self.loss)) if self.d else f"{self._common} at every sensor")

    def fields(self) -> tuple[tuple[str, str, tuple[sp.Expr, ...]], ...]:
        return (("loss", r"\varepsilon", self.loss),)

    def to_table(self) -> dict[str, Any]:
        return {"kind": self.kind, "loss": exact_strings(self.loss) if self.d else str(self._common)}

    def subs(self, values: Mapping[Any, Any]) -> "IID":
        values = substitution(values, "subs", self.symbols)
        return IID([e.subs(values) for e in self.loss] if self.d else sympify(self._common).subs(values))

    def __repr__(self) -> str:
        return f"IID(loss={[str(e) for e in self.loss]})" if self.d else f"IID({str(self._common)!r})"


check_public(globals())

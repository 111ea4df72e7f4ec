"""Independent groups of sensors, each with a loss model of its own (a product of their factors)."""
from __future__ import annotations

import itertools
import math
from functools import cached_property
from typing import Any, ClassVar, Mapping, Sequence

import sympy as sp

from .. import budget
from ..errors import FileFormatError, InputError
from ..arguments import check_public
from ..exact.numbers import substitution
from .loss import Factor, LossChain, LossModel, sized
from .codec import entry, positive_int, read_loss


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
        self.parts = tuple(sized(p, f"parts[{i}]") for i, p in enumerate(flat))
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

    @property
    def channel_recover(self) -> tuple[sp.Expr, ...] | None:
        recovers = [p.channel_recover for p in self.parts]
        return None if None in recovers else tuple(r for part in recovers for r in part)

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
        parts = entry(table, "parts", where)
        if not isinstance(parts, list) or not parts or not all(isinstance(t, dict) for t in parts):
            raise FileFormatError(f"{where} key 'parts': expected a non-empty list of [loss] tables, each with "
                                  "'sensors' (how many consecutive sensors it drives)")
        out = []
        for i, part in enumerate(parts):
            at = f"{where} parts[{i}]"
            if part.get("kind") == cls.kind:   # parts flatten: a nested list says nothing more (and recurses)
                raise FileFormatError(f"{at}: kind {cls.kind!r} cannot be a part; list its parts here instead")
            count = positive_int(entry(part, "sensors", at), f"{at} key 'sensors'")
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

    def to_dict(self) -> dict[str, Any]:
        return {"kind": self.kind, "parts": [{"sensors": p.d, **p.to_dict()} for p in self.parts]}

    def subs(self, values: Mapping[Any, Any]) -> "Independent":
        values = substitution(values, "subs", self.symbols)
        return Independent([p.subs({k: v for k, v in values.items() if k in p.symbols}) if p.symbols else p
                            for p in self.parts])

    def __repr__(self) -> str:
        return f"Independent({list(self.parts)!r})"


check_public(globals())

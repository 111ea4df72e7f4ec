"""The loss process of a subset of the sensors, as a model of its own: :class:`Selected`.

Design queries (which candidate sensors to install, :mod:`symkf.design`) decide a subset ``S``
of a system's sensors under the loss process all candidates share: the system of ``S`` alone
with the process seen through ``S``.  The chains are the model's own with the receivals of
``S`` only; transitions, and with them Assumption 2's positivity, are unchanged.
"""
from __future__ import annotations

from functools import cached_property
from typing import Any, ClassVar, Mapping, Sequence

import sympy as sp

from ..arguments import check_public
from ..errors import FileFormatError, InputError
from .codec import entry, positive_int, read_loss
from .loss import Factor, LossChain, LossModel, sized


def _indices(loss: Any, sensors: Any, entry: str) -> tuple[int, ...]:
    if not isinstance(loss, LossModel):
        raise InputError(f"loss: expected a symkf loss model, got {type(loss).__name__}")
    sized(loss, "loss")
    if isinstance(sensors, (str, bytes)) or not isinstance(sensors, Sequence):
        raise InputError(f"{entry}: expected a list of sensor indices, got {type(sensors).__name__}")
    out: list[int] = []
    for i, j in enumerate(sensors):
        if isinstance(j, bool) or not isinstance(j, int) or not 0 <= j < loss.d:
            raise InputError(f"{entry}[{i}]: {j!r} is not a sensor index of the model (0 to {loss.d - 1})")
        if j in out:
            raise InputError(f"{entry}[{i}]: sensor {j} is listed twice")
        out.append(j)
    return tuple(sorted(out))


class Selected(LossModel):
    """The loss process of the sensors ``sensors`` of ``loss`` alone, as a model of ``len(sensors)``
    sensors (numbered in increasing order of their indices in ``loss``).

    Each factor of ``loss`` that drives a selected sensor keeps its chain, its receivals cut to
    the selected sensors (a joint chain seen through some of its sensors is a hidden Markov chain:
    the engine's rates take the states, not the receivals, as the chain).

    Examples
    --------
    >>> import symkf as sk
    >>> ge = sk.GilbertElliott(["1/10", "1/5", "1/4"], ["1/2", "1/3", "1/2"])
    >>> sk.Selected(ge, [0, 2]).channel_fail, sk.Selected(sk.IID(["1/10", "1/5", "1/4"]), [1]).bernoulli
    ((1/10, 1/4), (1/5,))
    """

    kind = "selected"
    label = ("selected", "selected")
    keys: ClassVar[frozenset[str]] = frozenset({"kind", "sensors", "of", "loss"})

    def __init__(self, loss: LossModel, sensors: Sequence[int]):
        self.sensors = _indices(loss, sensors, "sensors")
        if not self.sensors:
            raise InputError("sensors: select at least one sensor")
        self.inner, self.d = loss, len(self.sensors)

    @cached_property
    def factors(self) -> tuple[Factor, ...]:
        new = {j: k for k, j in enumerate(self.sensors)}
        out = []
        for f in self.inner.factors:
            kept = [i for i, j in enumerate(f.sensors) if j in new]
            if kept:
                ch = f.chain
                emit = tuple(tuple(v[i] for i in kept) for v in ch.emit)
                out.append(Factor(tuple(new[f.sensors[i]] for i in kept), LossChain(ch.states, emit, ch.P, ch.initial)))
        return tuple(out)

    def _build_chain(self) -> LossChain:
        ch = self.inner.chain
        return LossChain(ch.states, tuple(tuple(v[j] for j in self.sensors) for v in ch.emit), ch.P, ch.initial)

    @property
    def symbols(self) -> set[sp.Symbol]:
        return self.inner.symbols

    @property
    def bernoulli(self) -> tuple[sp.Expr, ...] | None:
        losses = self.inner.bernoulli
        return None if losses is None else tuple(losses[j] for j in self.sensors)

    @property
    def channel_fail(self) -> tuple[sp.Expr, ...] | None:
        fails = self.inner.channel_fail
        return None if fails is None else tuple(fails[j] for j in self.sensors)

    @property
    def channel_recover(self) -> tuple[sp.Expr, ...] | None:
        recovers = self.inner.channel_recover
        return None if recovers is None else tuple(recovers[j] for j in self.sensors)

    def positivity_failure(self) -> str | None:
        return self.inner.positivity_failure()

    @property
    def applies_without_positivity(self) -> str | None:  # type: ignore[override]
        return self.inner.applies_without_positivity

    @property
    def assumption(self) -> str:
        return self.inner.assumption

    def words(self) -> str:
        return f"{self.inner.words()}; sensors {', '.join(map(str, self.sensors))} only"

    def fields(self) -> tuple[tuple[str, str, tuple[sp.Expr, ...]], ...]:
        return self.inner.fields() + (("sensors", "S", tuple(sp.Integer(j) for j in self.sensors)),)

    @classmethod
    def read_table(cls, table: dict, where: str, d: int, rationalize: bool = False) -> "Selected":
        """The model of a ``[loss]`` table: ``sensors``, the selected indices (``d`` of them), ``of``,
        the number of sensors of ``loss``, the ``[loss]`` table of the whole set."""
        inner, sensors = entry(table, "loss", where), entry(table, "sensors", where)
        if not isinstance(inner, Mapping) or not isinstance(sensors, list):
            raise FileFormatError(f"{where}: expected 'sensors' (a list of indices) and 'loss' (a [loss] table)")
        total = positive_int(entry(table, "of", where), f"{where} key 'of'")
        return cls(read_loss(inner, f"{where} loss", total, rationalize), sensors)

    def to_table(self) -> dict[str, Any]:
        return {"kind": self.kind, "sensors": list(self.sensors), "of": self.inner.d, "loss": self.inner.to_table()}

    def to_dict(self) -> dict[str, Any]:
        return {"kind": self.kind, "sensors": list(self.sensors), "of": self.inner.d, "loss": self.inner.to_dict()}

    def subs(self, values: Mapping[Any, Any]) -> "Selected":
        return Selected(self.inner.subs(values), self.sensors)

    def __repr__(self) -> str:
        return f"Selected({self.inner!r}, sensors={list(self.sensors)!r})"


check_public(globals())

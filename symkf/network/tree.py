"""Sensor-network trees rooted at the gateway (Quevedo-Ahlén-Johansson, Sec. II).

Sensor ``S_m`` (``m = 1..M``) sends to its parent ``Par(S_m)``; the gateway is
``S_0``.  Link ``E_m = (S_m, Par(S_m))`` succeeds when ``gamma_m(k) = 1``
(eq. 6).  Nothing is buffered and the network adds no delay, so the
measurement of ``S_m`` reaches the gateway iff every link on ``Path(S_m)``
succeeds: ``theta_m(k) = prod_{E_i in Edge(Path(S_m))} gamma_i(k)``
(Remark 2).  Relay nodes are sensors with an all-zero ``C`` (footnote 3).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Mapping, Sequence

from .. import budget
from ..arguments import check_public
from ..errors import InputError

Vector = tuple[int, ...]


@dataclass(frozen=True)
class SensorTree:
    """A directed tree on ``S_0..S_M`` given by ``parents[m - 1] = Par(S_m)`` (0 = gateway).

    ``SensorTree([0, 0, 1, 2, 2])`` is Fig. 4 of the paper: ``S_1, S_2`` talk to
    the gateway, ``S_3`` through ``S_1``, ``S_4`` and ``S_5`` through ``S_2``.
    A mapping ``{m: parent}`` with keys ``1..M`` is accepted too.
    """

    parents: tuple[int, ...]

    def __init__(self, parents: Sequence[int] | Mapping[int, int]):
        budget.check("max_sensors", len(parents), "parents", "the number of sensor nodes")
        if isinstance(parents, Mapping):
            M = len(parents)
            if sorted(parents) != list(range(1, M + 1)):
                raise InputError(f"parents: keys must be the sensors 1..{M}, got {sorted(parents)}")
            parents = [parents[m] for m in range(1, M + 1)]
        parents = tuple(parents)
        if not parents:
            raise InputError("parents: the tree needs at least one sensor S_1")
        M = len(parents)
        for m, p in enumerate(parents, start=1):
            if isinstance(p, bool) or not isinstance(p, int) or not 0 <= p <= M or p == m:
                raise InputError(f"parents[S_{m}] = {p!r}: must be 0 (gateway) or another sensor "
                                 f"1..{M}")
        object.__setattr__(self, "parents", parents)
        for m in range(1, M + 1):
            self.path(m)  # raises on a cycle

    @property
    def M(self) -> int:
        """Number of sensor nodes (the gateway excluded)."""
        return len(self.parents)

    def parent(self, m: int) -> int:
        """``Par(S_m)``."""
        self._check(m)
        return self.parents[m - 1]

    def path(self, m: int) -> tuple[int, ...]:
        """``Node(Path(S_m))``: ``(m, Par(S_m), ..., 0)``."""
        self._check(m)
        nodes = [m]
        while nodes[-1] != 0:
            nxt = self.parents[nodes[-1] - 1]
            if nxt in nodes:
                raise InputError(f"parents: S_{m} never reaches the gateway (cycle through S_{nxt}); "
                                 "the network must be a tree rooted at S_0")
            nodes.append(nxt)
        return tuple(nodes)

    def edges(self, m: int) -> tuple[int, ...]:
        """``Edge(Path(S_m))`` as link indices: link ``i`` is ``E_i = (S_i, Par(S_i))``."""
        return self.path(m)[:-1]

    @cached_property
    def _edge_sets(self) -> tuple[tuple[int, ...], ...]:
        return tuple(self.edges(m) for m in range(1, self.M + 1))

    def theta(self, gamma: Sequence[int]) -> Vector:
        """Sensor-to-gateway outcomes ``theta_m = prod_{i in Edge(Path(S_m))} gamma_i`` (Remark 2)."""
        if len(gamma) != self.M or set(gamma) - {0, 1}:
            raise InputError(f"gamma: expected a 0/1 vector of length {self.M}, got {tuple(gamma)!r}")
        return tuple(int(all(gamma[i - 1] for i in edges)) for edges in self._edge_sets)

    def children(self, m: int) -> tuple[int, ...]:
        """Nodes whose parent is ``S_m`` (``m = 0`` for the gateway)."""
        return tuple(i for i, p in enumerate(self.parents, start=1) if p == m)

    def _check(self, m: int) -> None:
        if isinstance(m, bool) or not isinstance(m, int) or not 1 <= m <= self.M:
            raise InputError(f"sensor index {m!r}: must be in 1..{self.M}")

    def __repr__(self) -> str:
        return f"SensorTree(parents={list(self.parents)})"

check_public(globals())

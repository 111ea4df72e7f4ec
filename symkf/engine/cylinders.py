"""Heaviest hyperplanes of an eigen-block spread over several diagonal blocks of ``A``, without
the compositum of their fields (rotations of one modulus from different cyclotomic fields).

``A`` is the direct sum of its diagonal blocks (:func:`symkf.exact.blocks.diagonal_blocks`); call
the ones holding eigenvalues of the block its *parts* ``p``.  A hyperplane of the block has a
normal ``u`` (in state coordinates, inside the block's invariant subspace) whose coordinates on
part ``p`` form ``u_p``, and sensor ``j``'s row at time ``k`` lies in it iff
``sum_p C_j,p A_p^k u_p = 0``.  Either:

* ``u_p = 0`` on some part ``p``: the hyperplane is a *cylinder* over the sub-system on the other
  parts' coordinates (a direct summand of ``A``), whose block has a class period ``g_S`` dividing
  ``g``: element ``(j, k)`` lies in it iff ``(j, k mod g_S)`` lies in the sub-system's
  hyperplane.  The heaviest cylinders are those of the sub-systems, lifted;
* ``u_p != 0`` on every part: its weight is bounded by *fibres* (:meth:`SplitRows._fibre_bound`).
  Scale the rows by ``|lambda|^-k``: part ``p`` then depends on ``k mod o_p`` only (``o_p`` the
  order of its eigenvalues' phases ``lambda / |lambda|``).  Fix a pair of parts ``i, j`` and
  ``k mod L`` (``L`` the lcm of the other parts' orders): within such a fibre the other parts
  contribute a constant, so the times in it that the hyperplane holds satisfy one affine
  equation in parts ``i, j`` with both linear parts nonzero, and they map one-to-one to phases
  ``k mod lcm(o_i, o_j)``.  Their number is at most ``mu``, the most points on such an affine
  hyperplane of the *lifted pair*: the block of modulus ``|lambda|`` of ``diag(A_i, A_j,
  |lambda| I)`` with rows ``(C_i, C_j, I)``, whose rows at phase ``a`` are those of the parts,
  scaled by ``|lambda|^-a``, beside a constant.  That ``mu`` comes from the lifted pair's own
  heaviest hyperplanes above a floor; a set of them whose normal vanishes on part ``i`` holds at
  most ``rho_i`` points of a full-support hyperplane per phase of part ``j`` (``rho_i``: the most
  points of one part's lifted orbit on an affine hyperplane).

When every full-support hyperplane is thus lighter than the heaviest cylinder, the cylinders are
the answer, exactly (each is confirmed over its sub-system's field).  Otherwise the block falls
back to its direct rows over the compositum, refused above ``budget.Limits.max_cyclotomic_degree``.

Under Markov losses the rate of a set is not a sum of weights: :func:`symkf.engine.search.markov_search`
runs each cylinder's own search (the same chains at the sub-system's class period), lifts its
candidates, and rules out the full-support hyperplanes by the fibres with the additive bound
``log rho(M_H) <= C + sum_(e in H) beta_e`` against the best lifted rate.  That bound counts a
long run's gain per element, so it decides when the full-support hyperplanes hold few elements:
2R(2 pi/5) + 2R(2 pi/7) + 2R(2 pi/9) with a second sensor that sees one part, far faster than the
direct rows (docs/performance.md); with one sensor they may hold 40 of 180 phases, the bound needs
fewer than 10, and the block falls back as above.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property, lru_cache
from typing import Any, Sequence

import numpy as np  # weights by phase and fibre
import sympy as sp

from .. import budget
from . import rows as observability
from ..arguments import check_public
from ..exact.blocks import diagonal_blocks
from ..exact.linalg import nullspace_rows
from ..model.system import Sensor, System
from ..exact.spectral import EigenBlock, support


@dataclass(frozen=True, eq=False)
class SplitRows:
    """:class:`~symkf.engine.rows.BlockRows` of a block over several parts, whose
    :meth:`heaviest` works part by part (module docstring); every other attribute is that of the
    direct rows over the compositum, built on first use (and refused there above the cap)."""

    system: System
    block: EigenBlock
    parts: tuple[tuple[int, ...], ...]   # the coordinates of each part (a diagonal block of A)
    orders: tuple[int, ...]              # per part, the lcm of its eigenvalues' phase orders
    class_period: int
    elements: tuple[observability.Element, ...]
    size: int

    def __getattr__(self, name: str) -> Any:
        if name.startswith("__") or name == "_direct":
            raise AttributeError(name)
        return getattr(self._direct, name)

    @cached_property
    def _direct(self) -> observability.BlockRows:
        return observability.direct_rows(self.system, self.block)

    def heaviest(self, weights: Sequence[float], floor: float | None = None) -> list[frozenset[int]] | None:
        """:meth:`symkf.engine.rows.BlockRows.heaviest`, by cylinders over the sub-systems
        without one part and a bound on the hyperplanes meeting every part (module docstring);
        None when that bound does not fall below the heaviest cylinder (or the floor)."""
        d, g = len(self.system.sensors), self.class_period
        w = np.asarray(weights, dtype=float).reshape(d, g)
        tol = 1e-9 * (1 + float(w.sum()))
        found: dict[frozenset[int], float] = {}
        for rows in self.cylinders:
            period = rows.class_period
            sub = w.reshape(d, g // period, period).sum(axis=1).ravel()
            sets = rows.heaviest(sub.tolist(), floor)
            if sets is None:
                return None
            for S in sets:
                found.setdefault(self.lift(rows, S), float(sub[sorted(S)].sum()))
        if not found:
            return None
        best = max(found.values())
        bar = best if floor is None else min(floor, best)
        if not self.meet_every_part_below(weights, bar - 2 * tol):
            return None
        return observability._maximal([S for S, v in found.items() if v >= bar - tol])

    def lift(self, rows: Any, S: frozenset[int]) -> frozenset[int]:
        """The elements of this block in the cylinder over the sub-system's hyperplane ``S``
        (element ``(j, a)`` of its class period ``g_S``): ``(j, a + m g_S)`` for every ``m``."""
        g, period = self.class_period, rows.class_period
        members = np.array(sorted(S), dtype=np.int64)
        j, a = np.divmod(members, period)
        return frozenset(((j * g + a)[:, None] + np.arange(0, g, period)[None, :]).ravel().tolist())

    def meet_every_part_below(self, weights: Sequence[float], bar: float) -> bool:
        """Whether every hyperplane whose normal meets every part weighs less than ``bar`` (weights
        >= 0 per element), by the fibres of some pair of parts (module docstring)."""
        return self._fibre_bound(np.asarray(weights, dtype=float).reshape(len(self.system.sensors), self.class_period), bar)

    @cached_property
    def live(self) -> list[int]:
        """The elements with a generator: those of the sensors that see some part (each part lies in
        a cylinder; a sensor's row at time k is nonzero iff it is at time 0)."""
        seen = {rows.elements[e].sensor for rows in self.cylinders for e in rows.live}
        return [e for e, element in enumerate(self.elements) if element.sensor in seen]

    def spanned(self, weights: Sequence[float], count: int = 9) -> list[frozenset[int]]:
        """No cheap guess of a heavy hyperplane (that of the direct rows needs the compositum):
        the caller goes to :meth:`heaviest`."""
        return []

    @cached_property
    def cylinders(self) -> list[Any]:
        """Per part left out, the rows of the sub-system on the other parts: every hyperplane whose
        normal vanishes on that part is one of theirs, lifted (:meth:`lift`)."""
        return [_sub_rows(self.system, self.block, [q for i, part in enumerate(self.parts) if i != p for q in part])
                for p in range(len(self.parts))]

    def _fibre_bound(self, w: np.ndarray, bar: float) -> bool:
        """Whether every hyperplane whose normal meets every part weighs less than ``bar``, by the
        fibres of some pair of parts (module docstring); pairs of larger fibres first."""
        d, g = w.shape
        if bar <= 0:
            return False
        tau = math.lcm(*self.orders)
        by_time = w[:, np.arange(tau) % g]   # the weight of each time of the phases' period
        pairs = sorted(((i, j) for i in range(len(self.parts)) for j in range(i + 1, len(self.parts))),
                       key=lambda ij: -math.lcm(self.orders[ij[0]], self.orders[ij[1]]))
        for i, j in pairs:
            pair = math.lcm(self.orders[i], self.orders[j])
            if int(sp.totient(pair)) > budget.LIMITS.max_cyclotomic_degree:
                continue
            L = math.lcm(*(o for q, o in enumerate(self.orders) if q not in (i, j)))
            fibres = -np.sort(-by_time.reshape(d, tau // L, L), axis=1)
            sums = np.concatenate([np.zeros((d, 1)), np.cumsum(fibres.sum(axis=2), axis=1)], axis=1) * g / tau
            # sums[j, m]: sensor j's heaviest m times per fibre, over all fibres, per element
            fits = [m for m in range(tau // L + 1) if sums[:, m].sum() < bar]
            cap = fits[-1] if fits else 0
            if cap == tau // L:
                return True
            if cap and all(self._most_per_fibre(s, i, j, cap) <= cap for s in range(d)):
                return True
        return False

    def _most_per_fibre(self, s: int, i: int, j: int, cap: int) -> int:
        """An upper bound on the times of sensor ``s`` that one fibre of parts ``i, j`` holds, exact
        up to ``cap`` (any answer above ``cap`` is only said to be above it): the lifted pair's
        hyperplanes of more than ``cap`` points, each counted as the full-support hyperplane
        points it can hold.  A sensor that sees only one part of the two, say ``i``, holds at most
        ``rho_i`` phases of it, each at most ``lcm(o_i, o_j) / o_i`` times in a fibre (one that
        sees neither holds all of a fibre or none)."""
        pair = math.lcm(self.orders[i], self.orders[j])
        sees = [any(self._rows_on(s, (p,))) for p in (i, j)]
        if sees.count(True) == 1:
            p = (i, j)[sees.index(True)]
            return self._rho(s, p) * pair // self.orders[p]
        lifted = self._lifted(s, (i, j))
        sets = None if lifted is None else lifted.heaviest([1.0] * len(lifted.elements), floor=cap + 0.5)
        if sets is None:
            return pair
        most = 0
        ni = len(self.parts[i])
        for S in sets:
            if len(S) <= cap:
                continue
            gens = [v for e in sorted(S) for v in lifted.generators[e]]
            normal = nullspace_rows(lifted.K, gens, lifted.size)
            if len(normal) != 1:
                return len(S)
            u = lifted.K.vecmat(normal[0], [list(r) for r in zip(*lifted.T)])
            on_i = any(not a.is_zero() for a in u[:ni])
            on_j = any(not a.is_zero() for a in u[ni:ni + len(self.parts[j])])
            phases = np.array(sorted(S), dtype=np.int64)
            if on_i and on_j:
                count = len(S)
            elif on_j:   # the set lies on a cylinder over part j: per phase of j, rho_i of part i
                count = min(len(S), self._rho(s, i) * len(np.unique(phases % self.orders[j])))
            else:
                count = min(len(S), self._rho(s, j) * len(np.unique(phases % self.orders[i])))
            most = max(most, count)
            if most > cap:
                return most
        return most

    def _rho(self, s: int, p: int) -> int:
        """The most phases of part ``p`` at which sensor ``s``'s rows lie on one affine hyperplane
        of that part (its lifted orbit's heaviest hyperplane; ``o_p`` when it does not apply)."""
        lifted = self._lifted(s, (p,))
        sets = None if lifted is None else lifted.heaviest([1.0] * len(lifted.elements))
        return max((len(S) for S in sets), default=0) if sets else self.orders[p]

    def _lifted(self, s: int, which: tuple[int, ...]) -> Any:
        """The rows of the lifted parts ``which`` for sensor ``s`` (module docstring), cached by
        the sensor's rows there; None when sensor ``s`` sees none of them."""
        index = [q for p in which for q in self.parts[p]]
        rows = self._rows_on(s, which)
        key = (which, tuple(rows))
        cache = self.__dict__.setdefault("_lifted_cache", {})
        if key not in cache:
            A = sp.diag(self.system.A.extract(index, index), self.block.modulus.exact * sp.eye(rows.rows))
            cache[key] = _sub_block(System._unchecked(A, [Sensor(C=rows.row_join(sp.eye(rows.rows)), name="lifted")]),
                                    self.block) if any(rows) else None
        return cache[key]

    def _rows_on(self, s: int, which: tuple[int, ...]) -> sp.Matrix:
        """Sensor ``s``'s rows on the coordinates of the parts ``which``."""
        C = self.system.sensors[s].C
        return C.extract(list(range(C.rows)), [q for p in which for q in self.parts[p]])


def _sub_block(system: System, block: EigenBlock) -> Any:
    """The rows of ``system``'s eigen-block of ``block``'s modulus, shared by equal sub-systems: the
    cylinders of the cylinders of five parts meet each sub-system of three parts twice and each
    lifted pair three times (:func:`_sub_block_of`)."""
    return _sub_block_of(sp.ImmutableMatrix(system.A), tuple((s.name, sp.ImmutableMatrix(s.C)) for s in system.sensors),
                         block.modulus, budget.LIMITS.max_cyclotomic_degree)


@lru_cache(maxsize=32)
def _sub_block_of(A: sp.ImmutableMatrix, sensors: tuple, modulus: Any, cap: int) -> Any:
    """:func:`_sub_block` of the system ``(A, sensors)``; ``cap`` (the cyclotomic cap that
    :func:`rows_of` reads) is part of the key."""
    system = System._unchecked(A, [Sensor(C=C, name=name) for name, C in sensors])
    sub = next(b for b in system.eigen_blocks() if b.modulus == modulus)
    return rows_of(system, sub)


def _sub_rows(system: System, block: EigenBlock, index: list[int]) -> Any:
    """The rows of ``block`` on the coordinates ``index`` (a union of parts): those of the
    sub-system ``(A[index, index], C[:, index])``."""
    sensors = [Sensor(C=s.C.extract(list(range(s.C.rows)), index), name=s.name) for s in system.sensors]
    return _sub_block(System._unchecked(system.A.extract(index, index), sensors), block)


def rows_of(system: System, block: EigenBlock) -> Any:
    """The rows of one eigen-block: :class:`SplitRows` when it spreads over three or more parts
    with a single class and its class period's field would exceed
    ``budget.Limits.max_cyclotomic_degree`` (the compositum the direct rows need), else
    :func:`symkf.engine.rows.direct_rows`."""
    if block.defective or len(block.classes) != 1 or \
            int(sp.totient(block.class_period)) <= budget.LIMITS.max_cyclotomic_degree:
        return observability.direct_rows(system, block)
    held = [set(support(system.A, [ev])) for ev in block.members]
    parts = [tuple(index) for index in diagonal_blocks(system.A) if set(index) <= set().union(*held)]
    phases = [ev.phase[0] for ev in block.members]
    if len(parts) < 3 or None in phases:
        return observability.direct_rows(system, block)
    orders = tuple(math.lcm(*(m for m, own in zip(phases, held) if own & set(part))) for part in parts)
    elements = tuple(observability.Element(j, r) for j in range(len(system.sensors)) for r in range(block.class_period))
    return SplitRows(system, block, tuple(parts), orders, block.class_period, elements, block.size)

check_public(globals())

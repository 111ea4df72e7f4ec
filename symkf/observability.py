"""Regression matrices, rank deficiency, projection (Sui-You-Fu eqs. 14-17, Algorithm 1).

For an eigen-block ``i`` in modal coordinates (``A T_i = T_i D_i``, ``D_i``
diagonal over the number field K of the block), the rows of ``O_N^i`` are
``C_j T_i D_i^k`` for the received pairs (sensor ``j``, time ``k``).  With
``g`` the block's class period, ``D_i^g`` is scalar on each class of
eigenvalues whose ratios are roots of unity, so:

* periodic block (one class, ``g`` the governing period): the row at time
  ``k`` is parallel to the row at ``k mod g``; O_N^i is rank deficient iff the
  projected pattern (Algorithm 1 with period ``g``) is, for every N;
* otherwise the row of an *element* (sensor ``j``, phase ``r``) received
  infinitely often spans its class components ``E_{j,r}``; a uniform bound on
  the zeros of non-degenerate linear recurrences (Evertse-Schlickewei-Schmidt)
  makes the finitely many other receptions irrelevant to decay rates.

Either way an element is a list of generator vectors over K, and the maximal
rank-deficient patterns are the hyperplanes of the matroid of all generators.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field
from functools import cached_property
from typing import Sequence

import flint
import sympy as sp

from .exact.field import Elem, NumberField
from .exact.linalg import nullspace_rows, rank_rows
from .model import System
from .spectral import EigenBlock, _eigen_with_factor, eigen_blocks


@dataclass(frozen=True)
class Element:
    """Sensor ``sensor`` at phase ``phase`` (time k with k mod period = phase)."""

    sensor: int
    phase: int


@dataclass(frozen=True, eq=False)
class BlockRows:
    """Rows of the regression matrix restricted to one eigen-block, per element."""

    block: EigenBlock
    K: NumberField
    period: int
    elements: tuple[Element, ...]
    generators: tuple[tuple[tuple[Elem, ...], ...], ...]  # per element
    size: int
    T: list = field(repr=False)      # modal eigenvector columns (n x n_i over K)
    diag: list = field(repr=False)   # the block's eigenvalues in K, repeated by multiplicity

    @cached_property
    def hyperplanes(self) -> tuple[frozenset[int], ...]:
        """Maximal sets of elements whose generators lie in a common hyperplane (indices)."""
        n = self.size
        gens = [(e, g) for e, gs in enumerate(self.generators) for g in gs]
        if n == 1:
            inside = frozenset(e for e, gs in enumerate(self.generators) if not gs)
            return (inside,)
        seen: dict[str, frozenset[int]] = {}
        vectors = _distinct([g for _, g in gens])
        for combo in itertools.combinations(vectors, n - 1):
            normal = nullspace_rows(self.K, combo, n)
            if len(normal) != 1:
                continue
            h = _normalize(self.K, normal[0])
            key = str([c.coeffs() for c in h])
            if key in seen:
                continue
            seen[key] = frozenset(e for e, gs in enumerate(self.generators)
                                  if all(self.K.dot(g, h).is_zero() for g in gs))
        sets = set(seen.values())
        return tuple(sorted((s for s in sets if not any(s < t for t in sets)), key=sorted))

    def deficient(self, pattern: frozenset[int]) -> bool:
        """Whether the elements in ``pattern`` leave O^i rank deficient."""
        rows = [g for e in pattern for g in self.generators[e]]
        return rank_rows(self.K, rows, self.size) < self.size


def _distinct(vectors: Sequence[tuple[Elem, ...]]) -> list[tuple[Elem, ...]]:
    out, keys = [], set()
    for v in vectors:
        k = str([c.coeffs() for c in v])
        if k not in keys:
            keys.add(k)
            out.append(v)
    return out


def _normalize(K: NumberField, h: Sequence[Elem]) -> list[Elem]:
    lead = next(c for c in h if not c.is_zero())
    inv = K.inv(lead)
    return [K.mul(c, inv) for c in h]


def block_rows(system: System) -> tuple[BlockRows, ...]:
    """The regression rows of every eigen-block of ``system.A`` over its period (cached)."""
    cached = system._cache.get("block_rows")
    if cached is None:
        cached = system._cache["block_rows"] = tuple(_block_rows(system, b) for b in eigen_blocks(system.A))
    return cached


def modal_form(A: sp.MatrixBase, block: EigenBlock, extra: Sequence[sp.MatrixBase] = ()) \
        -> tuple[NumberField, list[list[Elem]], list[Elem]]:
    """Exact modal form of one eigen-block: field K, eigenvector columns ``T_i`` (n x n_i), ``D_i``.

    K is the smallest field holding the entries of ``A``, of ``extra``
    matrices (the sensors' C) and the block's eigenvalues.
    """
    gens = [v for M in (A, *extra) for v in M if not sp.sympify(v).is_Rational]
    gens += [e.expr for e in block.members if not e.expr.is_Rational]
    K = NumberField(gens)
    n = A.shape[0]
    Ak = K.matrix(A)
    cols: list[list[Elem]] = []
    diag: list[Elem] = []
    for ev in block.members:
        lam = K.convert(ev.expr)
        shifted = [[(Ak[i][j] - lam) % K.modulus if i == j else Ak[i][j] for j in range(n)] for i in range(n)]
        basis = nullspace_rows(K, shifted, n)
        if len(basis) != ev.multiplicity:  # guarded by eigen_blocks' diagonalizability check
            raise AssertionError("eigenspace dimension mismatch")  # pragma: no cover
        cols.extend(basis)
        diag.extend([lam] * ev.multiplicity)
    T = [[cols[c][i] for c in range(len(cols))] for i in range(n)]
    return K, T, diag


def _block_rows(system: System, block: EigenBlock) -> BlockRows:
    K, T, diag = modal_form(system.A, block, [s.C for s in system.sensors])
    g = block.class_period
    class_of = [ci for ci, members in enumerate(block.classes)
                for m in members for _ in range(block.members[m].multiplicity)]
    elements, generators = [], []
    for j, sensor in enumerate(system.sensors):
        CT = [K.vecmat(K.matrix(sensor.C)[r], T) for r in range(sensor.m)]
        for phase in range(g):
            powers = [K.pow(lam, phase) for lam in diag]
            rows = [[K.mul(a, p) for a, p in zip(row, powers)] for row in CT]
            gens = []
            for c in range(len(block.classes)):
                for row in rows:
                    v = tuple(a if class_of[k] == c else flint.fmpq_poly([]) for k, a in enumerate(row))
                    if any(not a.is_zero() for a in v):
                        gens.append(v)
            elements.append(Element(j, phase))
            generators.append(tuple(_independent(K, gens, block.size)))
    return BlockRows(block, K, g, tuple(elements), tuple(generators), block.size, T, diag)


def _independent(K: NumberField, vectors: list[tuple[Elem, ...]], n: int) -> list[tuple[Elem, ...]]:
    """A maximal independent subset (generators of the same span, fewer rank tests later)."""
    out: list[tuple[Elem, ...]] = []
    for v in vectors:
        if rank_rows(K, out + [v], n) > len(out):
            out.append(v)
    return out


def regression_matrix(system: System, pattern: Sequence[Sequence[int]]) -> sp.Matrix:
    """``O_N = S_N col{C, CA, ..., CA^{N-1}}`` (eq. 14) for receival vectors ``pattern[k]``."""
    rows = []
    Ak = sp.eye(system.n)
    for vec in pattern:
        for j, s in enumerate(system.sensors):
            rows.append((s.C * Ak) * (1 if vec[j] else 0))
        Ak = Ak * system.A
    return sp.Matrix.vstack(*rows)


def block_deficient(system: System, pattern: Sequence[Sequence[int]]) -> tuple[bool, ...]:
    """Per eigen-block: is ``O_N^i`` column rank deficient for this pattern (eq. 32's R_N(i))?

    Computed directly from ``C_j A^k`` restricted to the block, without projection:
    the brute-force reference for Algorithm 1.
    """
    out = []
    for br in block_rows(system):
        K, T, diag = br.K, br.T, br.diag
        rows = []
        for k, vec in enumerate(pattern):
            powers = [K.pow(lam, k) for lam in diag]
            for j, s in enumerate(system.sensors):
                if vec[j]:
                    for row in K.matrix(s.C):
                        rows.append([K.mul(a, p) for a, p in zip(K.vecmat(row, T), powers)])
        out.append(rank_rows(K, rows, br.size) < br.size)
    return tuple(out)


def project(pattern: Sequence[Sequence[int]], period: int) -> frozenset[Element]:
    """Algorithm 1: the elements (sensor, k mod period) received at least once."""
    return frozenset(Element(j, k % period) for k, vec in enumerate(pattern) for j, g in enumerate(vec) if g)

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
        vectors = _distinct([g for _, g in gens])
        index = {_key(v): i for i, v in enumerate(vectors)}
        members = [[index[_key(g)] for g in gs] for gs in self.generators]
        spanning, partial = set(), set()
        for S in _generator_hyperplanes(self.K, vectors, n):
            s = frozenset(e for e, idx in enumerate(members) if all(i in S for i in idx))
            # s spans its hyperplane when it keeps all of S (S holds n - 1 independent vectors),
            # and then no other hyperplane's element set contains it
            (spanning if {i for e in s for i in members[e]} == S else partial).add(s)
        sets = spanning | {s for s in partial if not any(s < t for t in spanning | partial)}
        return tuple(sorted(sets, key=sorted))

    def deficient(self, pattern: frozenset[int]) -> bool:
        """Whether the elements in ``pattern`` leave O^i rank deficient."""
        rows = [g for e in pattern for g in self.generators[e]]
        return rank_rows(self.K, rows, self.size) < self.size


def _key(v: Sequence[Elem]) -> str:
    return str([c.coeffs() for c in v])


def _distinct(vectors: Sequence[tuple[Elem, ...]]) -> list[tuple[Elem, ...]]:
    out, keys = [], set()
    for v in vectors:
        k = _key(v)
        if k not in keys:
            keys.add(k)
            out.append(v)
    return out


def _reduction(K: NumberField, vectors: Sequence[Sequence[Elem]]) -> tuple[int, list[list[int]]]:
    """A prime ``p`` and the images of ``vectors`` under a ring map ``phi: Z_(p)[theta] -> F_p``.

    ``phi`` sends ``theta`` to a root of its minimal polynomial mod ``p``; ``p`` divides no
    denominator, so every linear relation over K maps to one over F_p."""
    p = 1 << 27
    while True:
        p = int(sp.nextprime(p))
        coeffs = [c for v in vectors for a in v for c in a.coeffs()] + list(K.modulus.coeffs())
        if any(int(c.q) % p == 0 for c in coeffs) or int(K.modulus.coeffs()[-1].p) % p == 0:
            continue
        mod = [int(c.p) * pow(int(c.q), -1, p) % p for c in K.modulus.coeffs()]
        roots = flint.nmod_poly(mod, p).roots()
        if not roots:
            continue
        r = int(roots[0][0])

        def phi(a: Elem) -> int:
            return sum(int(c.p) * pow(int(c.q), -1, p) * pow(r, i, p) for i, c in enumerate(a.coeffs())) % p
        return p, [[phi(a) for a in v] for v in vectors]


def _generator_hyperplanes(K: NumberField, vectors: Sequence[Sequence[Elem]], n: int) -> list[frozenset[int]]:
    """Every hyperplane spanned by ``vectors`` (distinct, in K^n), as the set of vectors it holds.

    Screened mod p, decided exactly: if ``n - 1`` vectors are independent mod p they are
    independent over K, and their exact span ``H`` holds ``v`` only if ``phi(v)`` lies in the
    span of their images (Cramer's identity ``m_0 v = sum m_k v_k`` with the minor ``m_0``
    nonzero mod p maps to F_p).  So the mod-p members are a superset of the exact ones, and each
    extra member is confirmed by an exact rank.  Combinations dependent mod p are decided exactly.
    """
    import numpy as np  # here, not at module level: only this screen needs numpy
    p, images = _reduction(K, vectors)
    W = np.array(images, dtype=np.int64)
    found: list[frozenset[int]] = []
    covered: set[tuple[int, ...]] = set()  # (n-1)-subsets of known hyperplanes: they span them or nothing
    for combo in itertools.combinations(range(len(vectors)), n - 1):
        if combo in covered:
            continue
        rows = [vectors[i] for i in combo]
        null, nullity = flint.nmod_mat([images[i] for i in combo], p).nullspace()
        if nullity == 1:
            h = np.array([int(null[i, 0]) for i in range(n)], dtype=np.int64)
            candidates = [int(i) for i in np.flatnonzero((W * h % p).sum(axis=1) % p == 0)]
            if len(candidates) == n - 1 or rank_rows(K, [vectors[i] for i in candidates], n) == n - 1:
                S = frozenset(candidates)
            else:  # a false zero mod p: confirm the extra members one by one
                S = frozenset(i for i in candidates if i in combo or rank_rows(K, rows + [vectors[i]], n) == n - 1)
        elif rank_rows(K, rows, n) == n - 1:  # unlucky prime: decide exactly
            (normal,) = nullspace_rows(K, rows, n)
            S = frozenset(i for i, v in enumerate(vectors) if K.dot(v, normal).is_zero())
        else:
            continue
        found.append(S)
        if len(S) > n - 1:
            covered.update(itertools.combinations(sorted(S), n - 1))
    return found


def block_rows(system: System) -> tuple[BlockRows, ...]:
    """The regression rows of every eigen-block of ``system.A`` over its period (cached)."""
    cached = system._cache.get("block_rows")
    if cached is None:
        aside = [b for b, _ in system.set_aside()]
        cached = system._cache["block_rows"] = tuple(
            _block_rows(system, b) for b in system.eigen_blocks() if b not in aside)
    return cached


def modal_form(A: sp.MatrixBase, block: EigenBlock, extra: Sequence[sp.MatrixBase] = ()) \
        -> tuple[NumberField, list[list[Elem]], list[Elem]]:
    """Exact modal form of one eigen-block: field K, eigenvector columns ``T_i`` (n x n_i), ``D_i``.

    K is the smallest field holding the entries of ``A``, of ``extra``
    matrices (the sensors' C) and the block's eigenvalues.  For an eigenvalue
    with Jordan chains the columns span its generalized eigenspace
    ``ker (A - lambda I)^m`` (``D_i`` then holds only its diagonal).
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
        if ev.defective:
            shifted = _matpow(K, shifted, ev.multiplicity)
        basis = nullspace_rows(K, shifted, n)
        if len(basis) != ev.multiplicity:
            raise AssertionError("generalized eigenspace dimension mismatch")  # pragma: no cover
        cols.extend(basis)
        diag.extend([lam] * ev.multiplicity)
    T = [[cols[c][i] for c in range(len(cols))] for i in range(n)]
    return K, T, diag


def _matmul(K: NumberField, X: Sequence[Sequence[Elem]], Y: Sequence[Sequence[Elem]]) -> list[list[Elem]]:
    return [K.vecmat(row, Y) for row in X]


def _matpow(K: NumberField, X: list[list[Elem]], k: int) -> list[list[Elem]]:
    out = X
    for _ in range(k - 1):
        out = _matmul(K, out, X)
    return out


def _block_rows(system: System, block: EigenBlock) -> BlockRows:
    K, T, diag = modal_form(system.A, block, [s.C for s in system.sensors])
    if block.defective:
        return _jordan_block_rows(system, block, K, T, diag)
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


def _jordan_block_rows(system: System, block: EigenBlock, K: NumberField, T: list, diag: list) -> BlockRows:
    """Generators of a block with Jordan chains (symkf's extension, docs/sui.md).

    With ``g`` the class period, ``A^g`` acts on the generalized eigenspace of class ``c``
    (columns ``T_c``) as ``c_c (I + N'_c)``, ``N'_c`` nilpotent: ``A^g T_c = c_c T_c (I + N'_c)``.
    The row of sensor j at time ``r + g t`` is then ``sum_c c_c^t sum_s binom(t, s) w_(c, s)`` with
    ``w_(c, s) = C_j A^r B_c^s T_c`` and ``B_c = A^g / c_c - I`` (``T_c N'_c = B_c T_c``).  Received
    at ``n_i`` or more times ``t`` (binomials of degree < n_i are independent functions of t) its
    rows span every ``w_(c, s)``: these are the element's generators.  With no Jordan chain
    ``B_c T_c = 0`` and they are today's class projections ``C_j A^r T_c``."""
    g = block.class_period
    Ak = K.matrix(system.A)
    class_of = [ci for ci, members in enumerate(block.classes)
                for m in members for _ in range(block.members[m].multiplicity)]
    zero = flint.fmpq_poly([])
    Ag = _matpow(K, Ak, g) if g > 1 else Ak
    B = []
    for c in range(len(block.classes)):
        inv = K.inv(K.pow(diag[class_of.index(c)], g))
        B.append([[(K.mul(a, inv) - (1 if i == j else 0)) % K.modulus for j, a in enumerate(row)]
                  for i, row in enumerate(Ag)])
    elements, generators = [], []
    for j, sensor in enumerate(system.sensors):
        rows = K.matrix(sensor.C)  # C_j A^r, r = phase
        for phase in range(g):
            gens = []
            for c in range(len(block.classes)):
                ws = rows
                for _ in range(block.size):
                    for w in _matmul(K, ws, T):
                        v = tuple(a if class_of[k] == c else zero for k, a in enumerate(w))
                        if any(not a.is_zero() for a in v):
                            gens.append(v)
                    ws = _matmul(K, ws, B[c])
            elements.append(Element(j, phase))
            generators.append(tuple(_independent(K, gens, block.size)))
            rows = _matmul(K, rows, Ak)
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
        jordan = br.block.defective  # rows C_j A^k T then (C_j T D^k otherwise)
        AkT, Ak = (T, K.matrix(system.A)) if jordan else (None, None)
        for k, vec in enumerate(pattern):
            powers = [K.pow(lam, k) for lam in diag]
            for j, s in enumerate(system.sensors):
                if vec[j]:
                    for row in K.matrix(s.C):
                        rows.append(K.vecmat(row, AkT) if jordan else
                                    [K.mul(a, p) for a, p in zip(K.vecmat(row, T), powers)])
            if jordan:
                AkT = _matmul(K, Ak, AkT)
        out.append(rank_rows(K, rows, br.size) < br.size)
    return tuple(out)


def project(pattern: Sequence[Sequence[int]], period: int) -> frozenset[Element]:
    """Algorithm 1: the elements (sensor, k mod period) received at least once."""
    return frozenset(Element(j, k % period) for k, vec in enumerate(pattern) for j, g in enumerate(vec) if g)

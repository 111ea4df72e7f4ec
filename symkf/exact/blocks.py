"""Diagonal blocks of a square matrix up to a symmetric permutation (a graph computation on its
sparsity pattern, used by the input cost model and by the per-block spectral engine)."""

from __future__ import annotations

import sympy as sp

from ..arguments import check_public


def diagonal_blocks(A: sp.MatrixBase) -> list[list[int]]:
    """The index sets of the diagonal blocks of ``A`` up to a symmetric permutation: the connected
    components of the graph with an edge ``i - j`` when ``A_ij != 0`` or ``A_ji != 0``.  ``A`` is
    their direct sum, so its eigenvalues, eigenspaces and Jordan chains are theirs, and each block
    is decided in the field of its own entries instead of the compositum of all of them (a stack of
    rotations in four cyclotomic fields)."""
    n = A.shape[0]
    parent = list(range(n))

    def root(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i
    for i in range(n):
        for j in range(i + 1, n):
            if A[i, j] != 0 or A[j, i] != 0:
                parent[root(i)] = root(j)
    groups: dict[int, list[int]] = {}
    for i in range(n):
        groups.setdefault(root(i), []).append(i)
    return list(groups.values())


check_public(globals())

"""Exact Perron roots of sparse non-negative rational matrices (Perron-Frobenius).

The spectral radius of a non-negative matrix is an eigenvalue (Perron-Frobenius) and, the
matrix being block triangular in the order of its graph's strongly connected components
(Frobenius normal form), it is the largest of its irreducible diagonal blocks' Perron roots; a
component without a cycle is a zero block.  Within a component, states with identical rows are
merged: if ``M = V W`` with ``V`` the 0/1 matrix of the classes and ``W`` their common rows,
``M`` and ``W V`` (rows summed over each class of columns) have the same non-zero eigenvalues.
Loss chains lifted by a hidden state (holding counters, network states) have many identical
rows, since the next law depends on the hidden state only.  The root itself is the largest real
root of the factors of an exact characteristic polynomial (python-flint), certified by
:class:`~symkf.exact.algebraic.AlgebraicNumber`'s isolating intervals.
"""

from __future__ import annotations

from typing import Mapping

import flint

from .algebraic import AlgebraicNumber

Rows = Mapping[int, Mapping[int, flint.fmpq]]


def strongly_connected_components(rows: Rows, n: int) -> list[list[int]]:
    """The strongly connected components of the graph ``r -> s`` for ``rows[r][s] != 0`` (Tarjan, iterative)."""
    index: dict[int, int] = {}
    low: dict[int, int] = {}
    on_stack: set[int] = set()
    stack: list[int] = []
    out: list[list[int]] = []
    for root in range(n):
        if root in index:
            continue
        work = [(root, iter(rows.get(root, {})))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            v, succ = work[-1]
            for w in succ:
                if w not in index:
                    index[w] = low[w] = len(index)
                    stack.append(w)
                    on_stack.add(w)
                    work.append((w, iter(rows.get(w, {}))))
                    break
                if w in on_stack:
                    low[v] = min(low[v], index[w])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[v])
                if low[v] == index[v]:
                    comp = []
                    while True:
                        w = stack.pop()
                        on_stack.discard(w)
                        comp.append(w)
                        if w == v:
                            break
                    out.append(comp)
    return out


def merge_identical_rows(rows: Rows, states: list[int]) -> dict[int, dict[int, flint.fmpq]]:
    """``W V`` on the classes of identical rows of ``rows`` restricted to ``states``, repeated
    until no two rows agree; classes are numbered ``0, 1, ...``.  Same non-zero spectrum."""
    inside = set(states)
    current = {s: {t: v for t, v in rows.get(s, {}).items() if t in inside} for s in states}
    while True:
        classes: dict[tuple, int] = {}
        of = {s: classes.setdefault(tuple(sorted(r.items())), len(classes)) for s, r in current.items()}
        if len(classes) == len(current):
            return current
        merged: dict[int, dict[int, flint.fmpq]] = {}
        for s, r in current.items():
            c = of[s]
            if c in merged:
                continue
            row: dict[int, flint.fmpq] = {}
            for t, v in r.items():
                row[of[t]] = row.get(of[t], 0) + v
            merged[c] = row
        current = merged


def largest_real_root(poly: flint.fmpz_poly) -> AlgebraicNumber | None:
    """The largest real root of an integer polynomial (certified), ``None`` if it has none."""
    best = None
    for f, _ in poly.factor()[1]:
        f = f if f.leading_coefficient() > 0 else -f
        reals = [i for i, (r, _) in enumerate(f.complex_roots()) if r.imag == 0]
        if reals:
            cand = AlgebraicNumber._irreducible(f, reals[-1])
            if best is None or cand > best:
                best = cand
    return best


def perron_root(rows: Rows, n: int) -> AlgebraicNumber:
    """``rho(M)`` of the non-negative ``n x n`` rational matrix with non-zero entries ``rows[r][s]``."""
    best = AlgebraicNumber._irreducible(flint.fmpz_poly([0, 1]), 0)
    for comp in strongly_connected_components(rows, n):
        if len(comp) == 1 and comp[0] not in rows.get(comp[0], {}):
            continue  # no cycle: a zero diagonal block
        q = merge_identical_rows(rows, comp)
        order = {s: i for i, s in enumerate(q)}
        dense = [[0] * len(q) for _ in q]
        for s, r in q.items():
            for t, v in r.items():
                dense[order[s]][order[t]] = v
        chi = flint.fmpq_mat(dense).charpoly()
        cand = largest_real_root(flint.fmpz_poly([int(c) for c in (chi * chi.denom()).coeffs()]))
        if cand is not None and cand > best:
            best = cand
    return best

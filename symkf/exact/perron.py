"""Exact Perron roots of sparse non-negative matrices with algebraic entries (Perron-Frobenius).

The spectral radius of a non-negative matrix is an eigenvalue (Perron-Frobenius) and, the
matrix being block triangular in the order of its graph's strongly connected components
(Frobenius normal form), it is the largest of its irreducible diagonal blocks' Perron roots; a
component without a cycle is a zero block.  Within a component, states with identical rows are
merged: if ``M = V W`` with ``V`` the 0/1 matrix of the classes and ``W`` their common rows,
``M`` and ``W V`` (rows summed over each class of columns) have the same non-zero eigenvalues.
Loss chains lifted by a hidden state (holding counters, network states) have many identical
rows, since the next law depends on the hidden state only.  The root itself is the largest real
root of the factors of an exact characteristic polynomial (python-flint), certified by
:class:`~symkf.exact.algebraic.AlgebraicNumber`'s isolating intervals; with entries in a number
field, the root of the norm polynomial inside a certified enclosure (:mod:`symkf.exact.perron_field`),
else the root of the norm polynomial at which the characteristic polynomial vanishes.
"""

from __future__ import annotations

from typing import Any, Mapping

import flint
import sympy as sp
from sympy.polys.polyerrors import PolynomialError

from ..arguments import check_public, float_array
from ..errors import BudgetError, InputError
from .algebraic import AlgebraicNumber, _real_roots, sympy_to_fmpz, x
from .perron_field import field_perron_root

Rows = Mapping[int, Mapping[int, Any]]


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


def merge_identical_rows(rows: Rows, states: list[int]) -> dict[int, dict[int, Any]]:
    """``W V`` on the classes of identical rows of ``rows`` restricted to ``states``, repeated
    until no two rows agree; classes are numbered ``0, 1, ...``.  Same non-zero spectrum."""
    inside = set(states)
    current = {s: {t: v for t, v in rows.get(s, {}).items() if t in inside} for s in states}
    while True:
        classes: dict[tuple, int] = {}
        of = {s: classes.setdefault(tuple(sorted(r.items())), len(classes)) for s, r in current.items()}
        if len(classes) == len(current):
            return current
        merged: dict[int, dict[int, Any]] = {}
        for s, r in current.items():
            c = of[s]
            if c in merged:
                continue
            row: dict[int, Any] = {}
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


def _block_root(block: dict[int, dict[int, Any]]) -> AlgebraicNumber | None:
    """Largest real eigenvalue of one merged irreducible block: flint for rationals, exact
    number-field arithmetic for algebraic entries (e.g. ``sqrt(2)/2``)."""
    order = {s: i for i, s in enumerate(block)}
    if all(isinstance(v, flint.fmpq) for r in block.values() for v in r.values()):
        dense = [[0] * len(block) for _ in block]
        for s, r in block.items():
            for t, v in r.items():
                dense[order[s]][order[t]] = v
        chi = flint.fmpq_mat(dense).charpoly()
        return largest_real_root(flint.fmpz_poly([int(c) for c in (chi * chi.denom()).coeffs()]))
    M = sp.zeros(len(block), len(block))
    for s, r in block.items():
        for t, v in r.items():
            M[order[s], order[t]] = v
    if M.free_symbols:
        raise InputError(f"loss: symbolic transition probabilities {sorted(map(str, M.free_symbols))} have no "
                         "numeric decay rate; use symkf.stability_conditions for the stability region")
    if len(block) == 1:
        return AlgebraicNumber.from_expr(M[0, 0])
    try:
        root = field_perron_root(M)
    except BudgetError:
        raise
    except InputError:  # entries that are not algebraic numbers: refused below, naming the block
        root = None
    if root is not None:
        return root
    try:
        chi = sp.Poly(M.charpoly(x).as_expr(), x, extension=True)
    except (PolynomialError, NotImplementedError):
        chi = None
    if chi is None or not (chi.domain.is_QQ or chi.domain.is_ZZ or chi.domain.is_AlgebraicField):
        raise InputError(f"an irreducible block of {len(block)} chain states has transition probabilities "
                         "that are not algebraic numbers (exact comparison of such numbers is not decidable "
                         "in general); give rational or algebraic probabilities")
    if not chi.domain.is_AlgebraicField:
        return largest_real_root(sympy_to_fmpz(chi))
    # coefficients in a number field K: the Perron root is the largest real root of the norm
    # N(x) in Q[x] (the product of chi's conjugates) that is a root of chi itself
    coeffs = [AlgebraicNumber.from_expr(c) for c in reversed(chi.all_coeffs())]
    for r in reversed(_real_roots(sympy_to_fmpz(chi.norm()))):
        if sum((c * r ** k for k, c in enumerate(coeffs)), AlgebraicNumber.from_expr(0)) == 0:
            return r
    return None


def perron_root(rows: Rows, n: int) -> AlgebraicNumber:
    """``rho(M)`` of the non-negative ``n x n`` matrix with non-zero entries ``rows[r][s]``:
    flint rationals (``fmpq``), or exact sympy numbers."""
    best = None
    for comp in strongly_connected_components(rows, n):
        if len(comp) == 1 and comp[0] not in rows.get(comp[0], {}):
            continue  # no cycle: a zero diagonal block
        cand = _block_root(merge_identical_rows(rows, comp))
        if cand is not None and (best is None or cand > best):
            best = cand
    return best if best is not None and best > 0 else AlgebraicNumber.from_expr(0)


def perron_float(M: Any) -> tuple[float, Any]:
    """The float twin of :func:`perron_root`, for simulation only (tilted burst laws): the spectral
    radius of a non-negative float64 matrix and a non-negative right Perron vector (``numpy.linalg.eig``)."""
    import numpy as np   # floats: the exact layer's only use of numpy
    M = float_array(M, "M")
    if M.ndim != 2 or M.shape[0] != M.shape[1] or M.size == 0 or not np.all(np.isfinite(M)) or np.any(M < 0):
        raise InputError(f"M: expected a non-empty square matrix of finite non-negative numbers, got shape {M.shape}")
    w, V = np.linalg.eig(M)
    i = int(np.argmax(w.real))
    return max(float(w[i].real), 0.0), np.abs(V[:, i].real)


check_public(globals())

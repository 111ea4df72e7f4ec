"""The regression rows of every eigen-block of a system: built directly
(:func:`symkf.engine.rows.direct_rows`), or through cylinders over sub-systems where a block
spreads over three or more parts whose compositum is too large
(:func:`symkf.engine.cylinders.rows_of`)."""

from __future__ import annotations

from typing import Sequence

from ..arguments import check_public
from ..model.system import System
from .cylinders import rows_of
from ..exact.linalg import rank_rows
from .rows import BlockRows, _matmul, is_conjugate_pair, modal_form


def block_rows(system: System) -> tuple[BlockRows, ...]:
    """The regression rows of every eigen-block of ``system.A`` over its period (cached)."""
    cached = system._cache.get("block_rows")
    if cached is None:
        aside = [b for b, _ in system.set_aside()]
        cached = system._cache["block_rows"] = tuple(
            rows_of(system, b) for b in system.eigen_blocks() if b not in aside)
    return cached


def block_deficient(system: System, pattern: Sequence[Sequence[int]]) -> tuple[bool, ...]:
    """Per eigen-block: is ``O_N^i`` column rank deficient for this pattern (eq. 32's R_N(i))?

    Computed directly from ``C_j A^k`` restricted to the block, without projection:
    the brute-force reference for Algorithm 1.
    """
    out = []
    for br in block_rows(system):
        K, T, diag = br.K, br.T, br.diag
        if is_conjugate_pair(system, br.block):  # rows mix the classes: the true modal form
            key = ("modal form", id(br.block))
            if key not in system._cache:
                system._cache[key] = modal_form(system.A, br.block, [s.C for s in system.sensors])
            K, T, diag = system._cache[key]
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

check_public(globals())

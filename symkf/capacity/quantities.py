"""Transmission capacity, Mahler measure and the two critical capacities (Yang et al.).

Yang et al. define, for sensor ``i`` with i.i.d. arrival rate ``lambda_i`` and
``sigma_i^2 = lambda_i (1 - lambda_i)`` (Section III-A, eq. 11 and Remark 1),

* ``q_i = lambda_i^2 / sigma_i^2 = lambda_i / (1 - lambda_i)``,
* the individual capacity ``C_i = 1/2 ln(1 + q_i) = -1/2 ln(1 - lambda_i)``,
* the overall capacity ``C = sum_i C_i``,

and compare ``C`` with ``ln rho(A)`` (eq. 16, necessary) and the topological
entropy ``h(A) = ln M(A)`` (eq. 29, sufficient for some allocation), where the
Mahler measure is ``M(A) = prod_i max(1, |lambda_i(A)|)`` over the
eigenvalues with multiplicity.

Capacities are returned as exact sympy logarithms.  Every comparison is decided
after exponentiating: ``C > ln x`` iff ``prod_i 1/(1 - lambda_i) > x^2``, a
comparison of real algebraic numbers that :class:`AlgebraicNumber` decides
exactly.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import sympy as sp

from .. import budget
from ..arguments import check_public, count, float_array
from ..errors import InputError
from ..exact.algebraic import AlgebraicNumber, subset_product
from ..exact.numbers import to_exact_matrix
from ..model.loss import LossModel, checked
from ..exact.spectral import eigenvalues, spectral_radius


def sequence_horizon(horizon: int, n: int) -> int:
    """``horizon`` checked as the length of a sequence of ``n x n`` bounds (``G_k``, ``V_k``,
    ``F_k``): an integer >= 1 whose matrices fit ``max_memory``."""
    horizon = count(horizon, "horizon", 1)
    budget.check("max_memory", 8 * n * n * horizon, "horizon", f"the bytes of {horizon} matrices {n}x{n}")
    return horizon


def initial_matrix(value: Any, n: int, entry: str) -> np.ndarray:
    """A sequence's first matrix given by the caller: finite, ``n x n``, as floats."""
    M = float_array(value, entry)
    if M.shape != (n, n) or not np.all(np.isfinite(M)):
        raise InputError(f"{entry}: expected a finite {n}x{n} matrix, got shape {M.shape}")
    return M


def _require_iid(loss: Any) -> tuple[sp.Expr, ...]:
    """The per-sensor loss probabilities of Bernoulli (i.i.d.) ``loss``, without symbols."""
    losses = checked(loss, numbers=True).require_bernoulli(
        "Bernoulli (i.i.d.) losses (Yang et al., Sec. II)", "symkf.stability (exact, any loss model)")
    return losses


def snr(loss: LossModel) -> tuple[sp.Expr, ...]:
    """``q_i = lambda_i / (1 - lambda_i)`` (eq. 11, Remark 1); ``oo`` for a lossless channel."""
    return tuple(sp.oo if e == 0 else sp.cancel((1 - e) / e) for e in _require_iid(loss))


def individual_capacities(loss: LossModel) -> tuple[sp.Expr, ...]:
    """``C_i = -1/2 ln(1 - lambda_i) = -1/2 ln(loss_i)`` (eq. 11 and Remark 1), exact."""
    return tuple(sp.oo if e == 0 else -sp.log(e) / 2 for e in _require_iid(loss))


def transmission_capacity(loss: LossModel) -> sp.Expr:
    """The overall transmission capacity ``C = sum_i C_i`` (Remark 1), an exact sympy logarithm.

    Parameters
    ----------
    loss : IID
        Bernoulli losses with numeric probabilities; ``loss_i = 1 - lambda_i``.

    Returns
    -------
    sympy.Expr
        ``-1/2 sum_i ln(loss_i)``; ``oo`` when some channel never loses.

    Raises
    ------
    InputError
        ``loss`` is no loss model, or has free symbols.
    AssumptionError
        ``loss`` is not i.i.d. (:meth:`~symkf.model.loss.LossModel.require_bernoulli`).

    Examples
    --------
    Losses 1/4 and 1/9: by hand ``C = -1/2 ln(1/4) - 1/2 ln(1/9) = ln 2 + ln 3 = ln 6``:

    >>> import sympy as sp
    >>> import symkf as sk
    >>> C = sk.capacity.transmission_capacity(sk.IID(["1/4", "1/9"]))
    >>> C, sp.simplify(C - sp.log(6))
    (log(4)/2 + log(9)/2, 0)
    """
    return sp.Add(*individual_capacities(loss))


def capacity_exponential(loss: LossModel) -> sp.Expr:
    """``exp(2 C) = prod_i 1 / (1 - lambda_i)``: the algebraic number behind every capacity test."""
    losses = _require_iid(loss)
    return sp.oo if any(e == 0 for e in losses) else 1 / sp.Mul(*losses)


def capacity_exceeds(loss: LossModel, x: Any) -> bool:
    """Exactly whether ``C > ln x`` for a positive algebraic ``x`` (``C > ln x`` iff ``exp(2C) > x^2``)."""
    e2c = capacity_exponential(loss)
    if e2c == sp.oo:
        return True
    x = AlgebraicNumber.from_expr(x.exact if isinstance(x, AlgebraicNumber) else x)
    if x < 0:
        raise InputError(f"capacity_exceeds: ln({x}) is undefined; x must be non-negative")
    if x == 0:
        return True  # ln 0 = -oo
    return AlgebraicNumber.from_expr(e2c) > AlgebraicNumber.from_expr(x.exact ** 2)


def mahler_measure(A: Any) -> AlgebraicNumber:
    """The Mahler measure ``M(A) = prod max(1, |lambda_i(A)|)`` with multiplicity (Section III-D), exact.

    Parameters
    ----------
    A : matrix-like
        A square matrix with exact entries.

    Returns
    -------
    AlgebraicNumber
        ``M(A) >= 1``; ``ln M(A)`` is the topological entropy (:func:`topological_entropy`).

    Raises
    ------
    ShapeError
        ``A`` is not square.

    Examples
    --------
    By hand: ``diag(2, 3, 1/2)`` has ``M = 2 * 3 * 1 = 6``; ``2R(pi/2)`` has eigenvalues
    ``+-2i``, so ``M = 2 * 2 = 4``:

    >>> import symkf as sk
    >>> sk.capacity.mahler_measure([[2, 0, 0], [0, 3, 0], [0, 0, "1/2"]]).exact
    6
    >>> sk.capacity.mahler_measure([[0, -2], [2, 0]]).exact
    4
    """
    # |lambda| |conj lambda| = lambda conj lambda: M is the absolute value of the product of the
    # eigenvalues outside the unit circle, taken per minimal polynomial (conjugation-closed sets)
    # and per multiplicity level, each a product of distinct conjugate roots
    outside: dict[tuple, tuple[Any, dict[int, int]]] = {}
    for ev in eigenvalues(A):
        if ev.modulus > 1:
            outside.setdefault(ev.key[0], (ev.minpoly, {}))[1][ev.root_index] = ev.multiplicity
    M = AlgebraicNumber.from_expr(1)
    for poly, roots in outside.values():
        for level in range(1, max(roots.values()) + 1):
            M = M * subset_product(poly, sorted(i for i, m in roots.items() if m >= level))
    return abs(M)


def topological_entropy(A: Any) -> sp.Expr:
    """``h(A) = ln M(A)`` (Bowen), exact."""
    return sp.log(mahler_measure(A).exact)


def critical_capacities(A: Any) -> tuple[sp.Expr, sp.Expr]:
    """``(ln rho(A), ln M(A))``: the lower critical capacity (eq. 16, Theorem 2) and the upper (eq. 29, Theorem 6).

    A transmission capacity ``C <= ln rho(A)`` makes ``E[P_k^-]`` diverge (Theorem 2); a budget
    ``C > ln M(A)`` can be allocated among the sensors so that the upper bound ``V_k``
    converges (Theorem 6, see :mod:`symkf.capacity.theorems`).

    Parameters
    ----------
    A : matrix-like
        A square matrix with exact entries.

    Returns
    -------
    tuple of sympy.Expr
        ``(ln rho(A), ln M(A))``, exact logarithms (``-oo`` for ``rho(A) = 0``).

    Raises
    ------
    ShapeError
        ``A`` is not square.

    Examples
    --------
    By hand: ``diag(2, 3)`` has ``rho = 3`` and ``M = 6``; for ``2R(pi/2)`` (eigenvalues
    ``+-2i``) ``rho = 2`` and ``M = 4``:

    >>> import symkf as sk
    >>> sk.capacity.critical_capacities([[2, 0], [0, 3]])
    (log(3), log(6))
    >>> sk.capacity.critical_capacities([[0, -2], [2, 0]])
    (log(2), log(4))
    """
    A = to_exact_matrix(A, "A")
    rho = spectral_radius(A)
    return (sp.log(rho.exact) if rho > 0 else -sp.oo), topological_entropy(A)

check_public(globals())

"""Primitive elements and exact representations in ``Q(theta)`` from certified embeddings.

A number field ``K = Q(theta)`` of degree ``d`` has ``d`` embeddings into C,
sending ``theta`` to the roots ``theta_l`` of its minimal polynomial ``m``.
An element ``v = p(theta)`` (``p`` in Q[x] of degree < d) takes the values
``v_l = p(theta_l)``, and the values at every embedding determine ``p`` by
Lagrange interpolation (:func:`interpolate`)::

    p = G / m'  (mod m),   G(z) = sum_l v_l m(z) / (z - theta_l).

``G`` is fixed by the Galois group, so its coefficients are rational; they are
integers when ``m`` is monic integral and ``v`` is an algebraic integer.
Certified acb balls for ``theta_l`` and ``v_l`` give balls for those
coefficients, and once each ball holds a single integer ``G`` is exact.

The values at every embedding come from the primitive element theorem
(:func:`adjoin`; Cohen, *A Course in Computational Algebraic Number Theory*,
sec. 3.6.2, Trager's norm): for ``theta' = beta + k theta``, if the
``d_beta d`` sums ``beta_i + k theta_j`` are pairwise distinct (proved by
pairwise disjoint balls), every automorphism of the normal closure that fixes
``theta'`` fixes ``beta`` and ``theta``, so ``Q(theta') = Q(theta, beta)``;
each conjugate of ``theta'`` is a unique sum ``beta_i + k theta_j``, which
gives the values of ``beta`` and ``theta`` at that embedding.  The minimal
polynomial of ``theta'`` is the factor of ``N(z) = prod (z - beta_i - k
theta_j)`` (an integer polynomial, read off certified balls) that vanishes
at ``theta'``; its degree is ``[Q(theta, beta) : Q]``, so ``beta`` lies in
``Q(theta)`` exactly when that degree is ``d``.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property, lru_cache
from itertools import count
from typing import Callable

import flint

from ..arguments import check_public
from ..errors import InputError
from .algebraic import _complex_roots, with_prec

_PRECS = (128, 256, 512, 1024, 2048, 4096, 8192, 16384)


@dataclass(frozen=True)
class Integral:
    """An algebraic integer: root ``index`` (flint's ordering) of the monic irreducible
    polynomial with coefficients ``coeffs`` (low to high)."""

    coeffs: tuple[int, ...]
    index: int

    @classmethod
    def of(cls, poly: flint.fmpz_poly, index: int) -> "Integral":
        return cls(tuple(int(c) for c in poly.coeffs()), index)

    @cached_property
    def poly(self) -> flint.fmpz_poly:
        return flint.fmpz_poly(list(self.coeffs))

    @property
    def degree(self) -> int:
        return len(self.coeffs) - 1

    def roots(self, prec: int) -> list[flint.acb]:
        """Isolating balls of all conjugates at ``prec`` bits (flint's ordering)."""
        return _roots(self.coeffs, prec)


@lru_cache(maxsize=256)
def _roots(coeffs: tuple[int, ...], prec: int) -> list[flint.acb]:
    return list(_complex_roots(coeffs, prec))


def integral_scale(poly: flint.fmpz_poly) -> tuple[int, flint.fmpz_poly]:
    """Least ``c > 0`` with ``c * b`` an algebraic integer for the roots ``b`` of the
    irreducible integer ``poly``, and the monic minimal polynomial of ``c * b``.

    ``c b`` has minimal polynomial ``sum a_i c^(n-i) x^i / a_n``; the least ``c``
    is found prime by prime from the valuations of the coefficients.
    """
    a = [int(v) for v in poly.coeffs()]
    n = len(a) - 1
    c = 1
    for p, e_lead in flint.fmpz(abs(a[n])).factor():
        p = int(p)

        def val(v: int) -> int:
            return _valuation(v, p) if v else 10 ** 9
        e = max(0, max(-((val(a[i]) - int(e_lead)) // (n - i)) for i in range(n)))
        c *= p ** e
    monic = [a[i] * c ** (n - i) // a[n] for i in range(n)] + [1]
    return c, flint.fmpz_poly(monic)


def _valuation(v: int, p: int) -> int:
    k = 0
    while v % p == 0:
        v //= p
        k += 1
    return k


@dataclass(frozen=True)
class Adjunction:
    """``theta' = beta + k theta`` with minimal polynomial ``prim.poly`` and its conjugates
    ``beta_i + k theta_j`` for ``(i, j)`` in ``pairs`` (one pair per root of ``prim.poly``)."""

    theta: Integral
    beta: Integral
    k: int
    prim: Integral
    pairs: tuple[tuple[int, int], ...]

    def values(self, prec: int) -> tuple[list[flint.acb], list[flint.acb], list[flint.acb]]:
        """Balls of ``theta'``, ``beta`` and ``theta`` at each embedding of ``Q(theta')``."""
        B, T = self.beta.roots(prec), self.theta.roots(prec)
        return with_prec(prec, lambda: ([B[i] + self.k * T[j] for i, j in self.pairs],
                                         [B[i] for i, _ in self.pairs], [T[j] for _, j in self.pairs]))


def _shifts():
    for k in count(1):
        yield k
        yield -k


@lru_cache(maxsize=256)
def adjoin(theta: Integral, beta: Integral) -> Adjunction:
    """A primitive element ``beta + k theta`` of ``Q(theta, beta)`` with all its conjugates."""
    for k in _shifts():
        if k > 64:  # pragma: no cover - finitely many k fail (each collision fixes k)
            raise InputError(f"no primitive element beta + k theta found for {beta} and {theta}")
        prec = _separating_prec(theta, beta, k)
        if prec is not None:
            return _adjunction(theta, beta, k, prec)
    raise AssertionError  # pragma: no cover


def _sums(theta: Integral, beta: Integral, k: int, prec: int) -> list[list[flint.acb]]:
    B, T = beta.roots(prec), theta.roots(prec)
    return with_prec(prec, lambda: [[b + k * t for t in T] for b in B])


def _separating_prec(theta: Integral, beta: Integral, k: int) -> int | None:
    """A precision at which the sums ``beta_i + k theta_j`` have pairwise disjoint balls
    (so they are distinct), or None when 1024 bits do not separate them."""
    for prec in (128, 1024):
        flat = [s for row in _sums(theta, beta, k, prec) for s in row]
        if all(not flat[a].overlaps(flat[b]) for a in range(len(flat)) for b in range(a)):
            return prec
    return None


def _adjunction(theta: Integral, beta: Integral, k: int, prec: int) -> Adjunction:
    N = None
    for prec in (p for p in _PRECS if p >= prec):
        sums = _sums(theta, beta, k, prec)
        flat = [s for row in sums for s in row]
        if N is None:
            N = with_prec(prec, lambda: flint.acb_poly.from_roots(flat).unique_fmpz_poly())
            if N is None:
                continue
            factors = [f for f, _ in N.factor()[1]]
        target = sums[beta.index][theta.index]
        hits = with_prec(prec, lambda: [f for f in factors if f(target).contains(0)])
        if len(hits) != 1:
            continue
        f = hits[0]
        pairs = with_prec(prec, lambda: tuple((i, j) for i, row in enumerate(sums)
                                               for j, s in enumerate(row) if f(s).contains(0)))
        if len(pairs) != f.degree():
            continue
        roots = _complex_roots(tuple(int(c) for c in f.coeffs()), prec)
        idx = [i for i, r in enumerate(roots) if r.overlaps(target)]
        if len(idx) == 1:
            return Adjunction(theta, beta, k, Integral.of(f, idx[0]), pairs)
    raise InputError(f"cannot certify the primitive element of {theta} and {beta}")  # pragma: no cover


def interpolate(poly: flint.fmpz_poly, nodes_values: Callable[[int], tuple[list[flint.acb], list[flint.acb]]]) \
        -> flint.fmpq_poly:
    """The ``p`` (degree < deg ``poly``) with ``p(theta_l) = v_l`` at every root ``theta_l``
    of the monic irreducible ``poly``; the values are those of one algebraic integer.

    ``nodes_values(prec)`` returns balls of all roots and the matching values.
    """
    D = poly.degree()
    coeffs = poly.coeffs()

    def numerator() -> flint.fmpz_poly | None:
        nodes, values = nodes_values(prec)
        acc = [flint.acb(0)] * D
        for t, v in zip(nodes, values):
            q = flint.acb(1)  # synthetic division: poly / (z - t), high to low
            acc[D - 1] += v
            for e in range(D - 1, 0, -1):
                q = coeffs[e] + t * q
                acc[e - 1] += v * q
        return flint.acb_poly(acc).unique_fmpz_poly()
    for prec in _PRECS:
        G = with_prec(prec, numerator)
        if G is not None:
            return (flint.fmpq_poly(G) * inverse(flint.fmpq_poly(poly.derivative()), flint.fmpq_poly(poly))) \
                % flint.fmpq_poly(poly)
    raise InputError(f"cannot interpolate over the roots of {poly}")  # pragma: no cover


def inverse(a: flint.fmpq_poly, modulus: flint.fmpq_poly) -> flint.fmpq_poly:
    """``a^(-1) mod modulus`` (``a`` coprime to ``modulus``)."""
    g, s, _ = a.xgcd(modulus)
    if g.degree() != 0:
        raise ZeroDivisionError("not invertible modulo the minimal polynomial")
    return (s / g) % modulus


def vanishes(poly: flint.fmpz_poly, p: flint.fmpq_poly, modulus: flint.fmpq_poly) -> bool:
    """Exactly whether ``poly(p(theta)) = 0`` in ``Q[x] / modulus``."""
    acc = flint.fmpq_poly([])
    for c in reversed(poly.coeffs()):
        acc = (acc * p + c) % modulus
    return acc.is_zero()

check_public(globals())

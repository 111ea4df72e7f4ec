"""Link success probabilities from fading channels (Quevedo-Ahlén-Johansson, Sec. III).

Given the network state ``Xi = j``, the power gain ``h_m`` of link ``E_m`` has a
state-dependent law (eq. 5).  With transmit power ``u = kappa_m(j, h)`` and
bit-rate ``b = eta_m(j, h)`` (Assumption 2, eq. 8, here depending on the
link's own gain) a packet gets through with probability ``f_m(h u, b)``
(eq. 7); with ``L`` transmission attempts over the same block,
``1 - (1 - f_m)^L`` (footnote 5).  Then (eq. 10)

    phi_{m|j} = E{ 1 - (1 - f_m(h kappa_m(j, h), eta_m(j, h)))^L | Xi = j }.

The expectation is an mpmath quadrature on ``[0, H]`` plus a tail.  Since the
integrand lies in ``[0, 1]``, the tail ``[H, inf)`` contributes a number in
``[0, Pr{h > H}]``, bounded rigorously (closed forms or a Chernoff bound); the
quadrature error on ``[0, H]`` is mpmath's tanh-sinh estimate, cross-checked
against Gauss-Legendre (the larger of the estimate and the discrepancy is
used).  The result is a :class:`SuccessProbability` with exact rational end
points ``lower <= phi <= upper``.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Any, Callable, Sequence

import mpmath
import sympy as sp

from ..arguments import check_public, described
from ..errors import InputError
from ..exact.numbers import to_exact

_DPS = 25
_TAIL = mpmath.mpf(10) ** -22
_DIGITS = 20


def _positive(value: Any, entry: str, zero: bool = False) -> mpmath.mpf:
    if isinstance(value, bool) or not isinstance(value, (int, float, Fraction, str, sp.Basic, mpmath.mpf)):
        raise InputError(f"{entry}: expected a positive number, got {value!r}")
    with mpmath.workdps(_DPS):
        v = mpmath.mpf(value) if isinstance(value, float) else mpmath.mpf(
            sp.N(value if isinstance(value, mpmath.mpf) else to_exact(value, entry, algebraic=False), _DPS))
    if not (v > 0 or zero and v == 0):
        raise InputError(f"{entry}: must be {'non-negative' if zero else 'positive'}, got {value!r}")
    return v


def _gain(h: Any, entry: str) -> mpmath.mpf:
    """A power gain: a finite real number ``>= 0`` as an mpmath number at the working precision."""
    try:
        with mpmath.workdps(_DPS):
            v = h if isinstance(h, mpmath.mpf) else mpmath.mpf(h) if isinstance(h, (int, float)) and \
                not isinstance(h, bool) else _positive(h, entry, zero=True)
    except (TypeError, ValueError):
        v = None
    if v is None or not mpmath.isfinite(v) or v < 0:
        raise InputError(f"{entry}: expected a finite power gain >= 0, got {described(h)}")
    return v


class GainDistribution:
    """Law of a power gain ``h >= 0``: ``pdf(h)`` and a rigorous upper bound ``tail(H) >= Pr{h > H}``
    (each law gives ``_density`` and ``_beyond``; the gain is checked here)."""

    def pdf(self, h: mpmath.mpf) -> mpmath.mpf:
        """Probability density of the power gain at ``h``."""
        return self._density(_gain(h, "h"))

    def tail(self, H: mpmath.mpf) -> mpmath.mpf:
        """A rigorous upper bound on ``Pr{h > H}``."""
        return self._beyond(_gain(H, "H"))

    def _density(self, h: mpmath.mpf) -> mpmath.mpf:  # pragma: no cover - abstract
        raise NotImplementedError

    def _beyond(self, H: mpmath.mpf) -> mpmath.mpf:  # pragma: no cover - abstract
        raise NotImplementedError

    def cutoff(self) -> mpmath.mpf:
        """A truncation point ``H`` with ``tail(H) <= 1e-25``."""
        H = mpmath.mpf(1)
        while self._beyond(H) > _TAIL:
            H *= 2
        return H


class Rayleigh(GainDistribution):
    """Rayleigh fading: the power gain is exponential with mean ``mean``."""

    def __init__(self, mean: Any):
        self.mean = _positive(mean, "Rayleigh mean")

    def _density(self, h: mpmath.mpf) -> mpmath.mpf:
        return mpmath.exp(-h / self.mean) / self.mean

    def _beyond(self, H: mpmath.mpf) -> mpmath.mpf:
        return mpmath.exp(-H / self.mean)

    def __repr__(self) -> str:
        return f"Rayleigh(mean={self.mean})"


class Nakagami(GainDistribution):
    """Nakagami-``m`` fading with spread ``omega``: the power gain is Gamma(``m``, ``omega/m``)."""

    def __init__(self, m: Any, omega: Any):
        self.m = _positive(m, "Nakagami m")
        if self.m < mpmath.mpf(1) / 2:
            raise InputError(f"Nakagami m = {m}: the shape parameter must be at least 1/2")
        self.omega = _positive(omega, "Nakagami omega")

    def _density(self, h: mpmath.mpf) -> mpmath.mpf:
        m, w = self.m, self.omega
        return (m / w) ** m * h ** (m - 1) * mpmath.exp(-m * h / w) / mpmath.gamma(m)

    def _beyond(self, H: mpmath.mpf) -> mpmath.mpf:
        return mpmath.gammainc(self.m, self.m * H / self.omega, mpmath.inf, regularized=True)

    def __repr__(self) -> str:
        return f"Nakagami(m={self.m}, omega={self.omega})"


class Rician(GainDistribution):
    """Rician fading with K-factor ``K`` and mean power ``mean`` (non-central chi-square, 2 dof)."""

    def __init__(self, K: Any, mean: Any):
        self.K = _positive(K, "Rician K", zero=True)
        self.mean = _positive(mean, "Rician mean")

    def _density(self, h: mpmath.mpf) -> mpmath.mpf:
        K, w = self.K, self.mean
        return ((K + 1) / w * mpmath.exp(-K - (K + 1) * h / w)
                * mpmath.besseli(0, 2 * mpmath.sqrt(K * (K + 1) * h / w)))

    def _beyond(self, H: mpmath.mpf) -> mpmath.mpf:
        # Chernoff: Pr{h > H} <= E[e^{th}] e^{-tH}, with the moment generating
        # function (1+K)/(1+K-tw) exp(K t w/(1+K-tw)) at t = (1+K)/(2w).
        K, w = self.K, self.mean
        t = (1 + K) / (2 * w)
        return 2 * mpmath.exp(K) * mpmath.exp(-t * H)

    def __repr__(self) -> str:
        return f"Rician(K={self.K}, mean={self.mean})"


class UserGain(GainDistribution):
    """A user-supplied law: ``pdf(h)`` and a rigorous tail bound ``tail(H) >= Pr{h > H}`` (mpmath)."""

    def __init__(self, pdf: Callable[[Any], Any], tail: Callable[[Any], Any]):
        if not callable(pdf) or not callable(tail):
            raise InputError("UserGain: pdf and tail must be callables h -> mpmath number")
        self._pdf, self._tail = pdf, tail

    def _density(self, h: mpmath.mpf) -> mpmath.mpf:
        return _returned(self._pdf, h, "pdf")

    def _beyond(self, H: mpmath.mpf) -> mpmath.mpf:
        return _returned(self._tail, H, "tail")


def _returned(fn: Callable[[Any], Any], h: mpmath.mpf, name: str) -> mpmath.mpf:
    """The user's ``fn(h)`` as a real mpmath number, or an :class:`InputError` naming what it returned."""
    value = fn(h)
    try:
        out = mpmath.mpf(value)
    except (TypeError, ValueError):
        out = None
    if out is None or mpmath.isnan(out):
        raise InputError(f"UserGain {name}({mpmath.nstr(h, 8)}) returned {described(value)}, not a real number")
    return out


def _rational(x: mpmath.mpf, direction: str) -> sp.Rational:
    """``x`` rounded outward to ``_DIGITS`` decimals ("down" or "up"), clipped to [0, 1]."""
    scaled = x * mpmath.mpf(10) ** _DIGITS
    n = int(mpmath.floor(scaled)) if direction == "down" else int(mpmath.ceil(scaled))
    return min(max(sp.Rational(n, 10 ** _DIGITS), sp.Integer(0)), sp.Integer(1))


@dataclass(frozen=True)
class SuccessProbability:
    """``phi_{m|j}`` from eq. (10): ``value`` with ``lower <= phi <= upper`` (exact rationals)."""

    value: sp.Rational
    lower: sp.Rational
    upper: sp.Rational
    quadrature_error: float
    tail_bound: float

    def __float__(self) -> float:
        return float(self.value)


def success_probability(gain: GainDistribution, f: Callable[[Any, Any], Any],
                        kappa: Callable[[Any], Any] | Any = 1,
                        eta: Callable[[Any], Any] | Any = 0,
                        attempts: int = 1, breakpoints: Sequence[Any] = ()) -> SuccessProbability:
    """``phi = E{1 - (1 - f(h kappa(h), eta(h)))^L}`` over the gain law (eqs. 7, 8, 10, footnote 5).

    ``kappa`` and ``eta`` are the power and bit-rate policies for the given
    network state, as functions of the link's gain or constants.  ``f(s, b)``
    must return a number in ``[0, 1]``.  ``breakpoints`` are gains where the
    integrand jumps (a threshold ``f``, a saturating policy), so the
    quadrature splits there.
    """
    if isinstance(attempts, bool) or not isinstance(attempts, int) or attempts < 1:
        raise InputError(f"attempts: the number L of transmissions must be a positive integer, got {attempts!r}")
    if not callable(f):
        raise InputError("f: expected the success function f(received_power, bit_rate) of eq. (7)")
    u = kappa if callable(kappa) else (lambda h, c=kappa: c)
    b = eta if callable(eta) else (lambda h, c=eta: c)
    with mpmath.workdps(_DPS):
        H = gain.cutoff()
        tail = gain._beyond(H)

        def integrand(h):
            s = mpmath.mpf(f(h * mpmath.mpf(u(h)), b(h)))
            if not 0 <= s <= 1:
                raise InputError(f"f returned {s} at gain {h}: a success probability must lie in [0, 1]")
            return (1 - (1 - s) ** attempts) * gain._density(h)

        cuts = sorted({mpmath.mpf(0), H, *(mpmath.mpf(p) for p in breakpoints if 0 < p < H)})
        value, err = mpmath.quad(integrand, cuts, error=True, maxdegree=8)
        check = mpmath.quad(integrand, cuts, method="gauss-legendre", maxdegree=8)
        err = max(abs(err), abs(value - check))
        lower = _rational(value - err, "down")
        upper = _rational(value + err + tail, "up")
        mid = _rational(value, "down")
    return SuccessProbability(min(max(mid, lower), upper), lower, upper, float(err), float(tail))


def threshold_success(threshold: Any) -> Callable[[Any, Any], Any]:
    """The outage model ``f(s, b) = 1{s >= threshold(b)}``; ``threshold`` is a number or a function of ``b``."""
    th = threshold if callable(threshold) else (lambda b, c=threshold: c)
    return lambda s, b: 1 if s >= mpmath.mpf(th(b)) else 0

check_public(globals())

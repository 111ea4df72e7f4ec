"""The fusion set-up of arXiv:2012.04896, Section 2: process (1), smart sensors (2), lossy channels (9).

:class:`FusionModel` holds the float matrices the filters run on and the
exact data that decide the assumptions:

* the observable subspace of every sensor and Assumption 1 (collective
  observability) by exact rank (:mod:`symkf.fusion.decomposition`);
* Assumption 2, ``(1 - min_i lambda_i) rho(A)^2 < 1``, as an exact expression
  with a certified interval (python-flint balls around the roots of the
  characteristic polynomial).

Two constructors: :meth:`FusionModel.discrete` for an exact discrete-time
``(A, Q)``, and :meth:`FusionModel.zoh` for a continuous-time ``(A_c, B_c)``
sampled by a zero-order hold (the inverted pendulum of Section 4).  For the
latter ``A = exp(A_c T_s)`` is computed with mpmath at 40 digits and rounded to
floats; the subspaces are decided on the exact ``A_c``.  That is legitimate
because ``exp(A_c T_s)`` and ``A_c`` have the same invariant subspaces unless
two eigenvalues of ``A_c`` differ by ``2 pi i k / T_s`` (k != 0), which is
impossible for algebraic ``A_c`` and rational ``T_s`` (the difference is
algebraic, ``2 pi k / T_s`` transcendental).
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Any, Sequence

import flint
import mpmath
import numpy as np
import sympy as sp

from ..arguments import check_public
from ..errors import AssumptionError, InputError, ProbabilityError
from ..exact.algebraic import sympy_to_fmpz
from ..exact.numbers import sympify, to_exact, to_exact_matrix
from ..model.iid import IID
from ..model.system import Sensor, check_positive_definite
from .decomposition import LocalModel, check_collective_observability, check_reachability, local_model

__all__ = ["Assumption2", "FusionModel"]


@dataclass(frozen=True)
class Assumption2:
    """``(1 - min_i lambda_i) rho(A)^2`` (arXiv:2012.04896, Assumption 2).

    ``exact`` is a sympy expression (None when the dominant eigenvalue is not
    real), ``interval`` certified rational bounds, ``holds`` the verdict
    ``value < 1`` decided from the interval.
    """

    exact: sp.Expr | None
    interval: tuple[Fraction, Fraction]
    rho_squared_interval: tuple[Fraction, Fraction]

    @property
    def holds(self) -> bool:
        return self.interval[1] < 1

    def __float__(self) -> float:
        return float((self.interval[0] + self.interval[1]) / 2)


def _bounds(x: flint.arb) -> tuple[Fraction, Fraction]:
    """Exact rational end points of an arb ball (its end points are binary floats)."""
    out = []
    for end in (x.lower(), x.upper()):
        man, exp = end.man_exp()
        out.append(Fraction(int(man)) * Fraction(2) ** int(exp))
    return out[0], out[1]


def _assumption2(A_exact: sp.Matrix, Ts: sp.Rational | None, loss_max: sp.Rational) -> Assumption2:
    """Certified ``(1 - min lambda) rho^2``; with ``Ts``, ``rho = exp(Ts max Re eig A_exact)``.

    Each root of the characteristic polynomial is enclosed in a flint ball; the
    maximum of the balls' ``|r|^2`` (or ``exp(2 Ts Re r)``) lies between the
    largest lower and the largest upper end point.
    """
    if any(not sympify(v).is_Rational for v in A_exact):
        raise InputError("A: the exact Assumption 2 check needs rational entries "
                         "(the spectral radius is then algebraic, or exp of an algebraic number)")
    lam = sp.Symbol("lam")
    charpoly = sp.Poly(A_exact.charpoly(lam).as_expr(), lam)
    poly = sympy_to_fmpz(charpoly)
    old = flint.ctx.prec
    try:
        for prec in (64, 256, 1024):
            flint.ctx.prec = prec
            roots = [r for r, mult in poly.complex_roots() for _ in range(mult)]
            t = flint.arb(Ts.p) / Ts.q if Ts is not None else None
            sizes = [abs(r) ** 2 if t is None else (2 * t * r.real).exp() for r in roots]
            ends = [_bounds(s) for s in sizes]
            rho2 = (max(e[0] for e in ends), max(e[1] for e in ends))
            value = (rho2[0] * Fraction(loss_max.p, loss_max.q), rho2[1] * Fraction(loss_max.p, loss_max.q))
            if not value[0] <= 1 <= value[1]:
                break
        else:
            raise AssumptionError("(1 - min lambda) rho(A)^2 is within 2^-1000 of 1",
                                  assumption="Assumption 2 (arXiv:2012.04896): decidable by certified intervals")
        best = max(range(len(ends)), key=lambda k: ends[k][1])
        dominant_real = roots[best].imag == 0 and all(
            k == best or ends[k][1] < ends[best][0] for k in range(len(ends)))
    finally:
        flint.ctx.prec = old
    exact = None
    if dominant_real:
        mid = float(roots[best].real.mid())
        root = min((r for r in charpoly.all_roots() if r.is_real), key=lambda r: abs(float(r) - mid))
        exact = loss_max * (root ** 2 if Ts is None else sp.exp(2 * Ts * root))
    return Assumption2(exact=exact, interval=value, rho_squared_interval=rho2)


def _float(M: sp.MatrixBase) -> np.ndarray:
    return np.array(sp.Matrix(M).evalf(30).tolist(), dtype=float)


def _arrival_rates(arrival: Sequence[Any], N: int) -> tuple[sp.Rational, ...]:
    if len(arrival) != N:
        raise InputError(f"arrival: {len(arrival)} rates given for {N} sensors")
    rates = []
    for i, lam in enumerate(arrival):
        value = to_exact(lam, f"arrival[{i}]")
        if not value.is_Rational or not 0 < value <= 1:
            raise ProbabilityError(f"arrival[{i}]: packet arrival rate lambda_{i + 1} = {value} "
                                   "must be a rational number in (0, 1] (arXiv:2012.04896, eq. 9)")
        rates.append(value)
    return tuple(rates)


@dataclass(frozen=True)
class FusionModel:
    """Process ``x+ = A x + w``, ``w ~ N(0, Q)``; sensors ``y_i = C_i x + v_i``; arrival rates ``lambda_i``.

    ``local`` holds each sensor's Kalman decomposition (eqs. 3-5).
    """

    A: np.ndarray
    Q: np.ndarray
    sensors: tuple[Sensor, ...]
    arrival: tuple[sp.Rational, ...]
    local: tuple[LocalModel, ...]
    assumption2: Assumption2
    description: str

    @property
    def n(self) -> int:
        """State dimension ``n``."""
        return self.A.shape[0]

    @property
    def N(self) -> int:
        """Number of sensors ``N``."""
        return len(self.local)

    @property
    def loss(self) -> IID:
        """The packet arrivals as a symkf loss model: i.i.d., sensor ``i`` lost with probability
        ``1 - lambda_i`` (arXiv:2012.04896, eq. 9); the simulation draws them from it."""
        return IID([1 - lam for lam in self.arrival])

    @property
    def names(self) -> tuple[str, ...]:
        """The sensors' names, in order."""
        return tuple(loc.name for loc in self.local)

    @property
    def C(self) -> np.ndarray:
        """Stacked ``C`` of all sensors (float), for the centralized filter."""
        return np.vstack([_float(s.C) for s in self.sensors])

    @property
    def R(self) -> np.ndarray:
        """Block-diagonal ``R`` of all sensors (float), for the centralized filter."""
        from scipy.linalg import block_diag
        return block_diag(*[loc.R for loc in self.local])

    @classmethod
    def _build(cls, A_exact: sp.Matrix, A: np.ndarray, Q: np.ndarray, sensors: Sequence[Sensor],
               arrival: Sequence[Any], reach: sp.Matrix, Ts: sp.Rational | None, description: str) -> "FusionModel":
        sensors = tuple(sensors)
        for i, s in enumerate(sensors):
            if not isinstance(s, Sensor):
                raise InputError(f"sensors[{i}]: expected a symkf.Sensor, got {type(s).__name__}")
            if s.C.shape[1] != A_exact.shape[0]:
                raise InputError(f"sensors[{i}] C: has {s.C.shape[1]} columns, A is "
                                 f"{A_exact.shape[0]}x{A_exact.shape[0]}")
        rates = _arrival_rates(arrival, len(sensors))
        check_collective_observability(A_exact, [s.C for s in sensors])
        check_reachability(A_exact, reach)
        names = [s.name or f"s{i + 1}" for i, s in enumerate(sensors)]
        local = tuple(local_model(names[i], A_exact, A, Q, s.C, _float(s.R)) for i, s in enumerate(sensors))
        a2 = _assumption2(A_exact, Ts, 1 - min(rates))
        return cls(A=A, Q=Q, sensors=sensors, arrival=rates, local=local, assumption2=a2, description=description)

    @classmethod
    def discrete(cls, A: Any, Q: Any, sensors: Sequence[Sensor], arrival: Sequence[Any]) -> "FusionModel":
        """Exact discrete-time model; ``Q`` positive semidefinite with ``(A, Q^(1/2))`` controllable."""
        A_exact = to_exact_matrix(A, "A")
        n = A_exact.shape[0]
        Q_exact = to_exact_matrix(Q, "Q", shape=(n, n))
        if any(v != 0 for v in (Q_exact - Q_exact.T)):
            raise InputError("Q: not symmetric")
        return cls._build(A_exact, _float(A_exact), _float(Q_exact), sensors, arrival, Q_exact, None,
                          "discrete-time model")

    @classmethod
    def zoh(cls, Ac: Any, Bc: Any, noise_variance: Any, Ts: Any, sensors: Sequence[Sensor],
            arrival: Sequence[Any]) -> "FusionModel":
        """Zero-order hold of ``dx/dt = A_c x + B_c u`` with ``u_k ~ N(0, sigma^2 I)`` held over ``T_s``.

        ``A = exp(A_c T_s)``, ``B = int_0^Ts exp(A_c s) ds B_c`` (mpmath, 40 digits,
        then floats) and ``Q = sigma^2 B B'`` as in eq. (28).
        """
        Ac_exact = to_exact_matrix(Ac, "A_c")
        n = Ac_exact.shape[0]
        Bc_exact = to_exact_matrix(Bc, "B_c")
        if Bc_exact.shape[0] != n:
            raise InputError(f"B_c: has {Bc_exact.shape[0]} rows, A_c is {n}x{n}")
        Ts_exact = to_exact(Ts, "Ts")
        sigma2 = to_exact(noise_variance, "noise_variance")
        if not Ts_exact.is_Rational or Ts_exact <= 0:
            raise InputError(f"Ts: the sampling time must be a positive rational, got {Ts_exact}")
        check_positive_definite(sp.Matrix([[sigma2]]), "noise_variance")
        m = Bc_exact.shape[1]
        with mpmath.workdps(40):
            aug = mpmath.matrix(n + m, n + m)
            for i in range(n):
                for j in range(n):
                    aug[i, j] = mpmath.mpf(sp.Rational(Ac_exact[i, j] * Ts_exact).p) / sp.Rational(Ac_exact[i, j] * Ts_exact).q
                for j in range(m):
                    aug[i, n + j] = mpmath.mpf(sp.Rational(Bc_exact[i, j] * Ts_exact).p) / sp.Rational(Bc_exact[i, j] * Ts_exact).q
            E = mpmath.expm(aug)
            F = np.array([[float(E[i, j]) for j in range(n + m)] for i in range(n + m)])
        A, B = F[:n, :n], F[:n, n:]
        Q = float(sigma2) * B @ B.T
        return cls._build(Ac_exact, A, Q, sensors, arrival, Bc_exact, Ts_exact,
                          f"zero-order hold of a continuous-time model, Ts = {Ts_exact}")

check_public(globals())

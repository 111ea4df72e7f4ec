"""Theorem 4 (Yang et al.): when does the upper bound V_k converge?

``V_k`` converges for every initial value (equivalently ``X = g_lambda(X)``
has a unique positive definite solution) iff

1) there are ``P > 0`` and ``L`` with
   ``P > (A - L Lambda H) P (A - L Lambda H)' + L ((Sigma^2 I_blk) o (H P H')) L'``  (22), and
2) ``[A - e^{jw} I, B]`` has full row rank for all real ``w``, ``B B' = Q``.

**Convex reformulation of 1).**  (22) says that the positive map
``T*(P) = (A - L Lambda H) P (.)' + L ((Sigma^2 I_blk) o (H P H')) L'`` has
spectral radius below one.  It is the adjoint of the second-moment map of
eq. 24, ``T(Y) = (A - L Lambda H)' Y (A - L Lambda H) + sum_i sigma_i^2 H_i' L_i' Y L_i H_i``
(``E[(Gamma - Lambda) X (Gamma - Lambda)] = (Sigma^2 I_blk) o X``), and
``rho(T) = rho(T*)``, so 1) holds iff some ``Y > 0`` has ``Y - T(Y) > 0``.
With ``Z_i = Y L_i R_i^{-1/2}`` (a change of variables, ``R_i > 0``) and
``M_0 = Y A - sum_i lambda_i Z_i C_i``, Schur complements turn this into the
homogeneous linear matrix inequality

    [ Y          M_0'  (Z_1 C_1)'        ...  (Z_N C_N)'       ]
    [ M_0        Y     0                 ...  0                ]
    [ Z_1 C_1    0     Y / sigma_1^2     ...  0                ]   > 0,
    [ ...                                ...                   ]
    [ Z_N C_N    0     0                 ...  Y / sigma_N^2    ]

linear in ``(Y, Z)``, with rational coefficients for rational ``A, C_i, lambda_i``
(``R`` drops out).  Sensors with ``lambda_i = 0`` are left out and those with
``lambda_i = 1`` have no variance block.  For one sensor with scalar ``C``
and ``n = 1`` it reduces to ``a^2 (1 - lambda) < 1`` (Sinopoli's threshold).

**Decision.**  First, ``C <= ln rho(A)`` (exact) proves that 1) fails:
``T(Y) >= c A' Y A`` with ``c = prod_i (1 - lambda_i)`` (the term of the
all-lost pattern), so ``rho(T) >= c rho(A)^2``.  Otherwise two semidefinite
programs are solved with cvxpy (Clarabel):
the primal ``max t : F(Y, Z) >= t I, Y <= I`` and the alternative
``max s : W >= s I, tr W = 1, <F_k, W> = 0`` for every basis matrix ``F_k`` of
the map ``(Y, Z) -> F`` (a ``W >= 0, W != 0`` orthogonal to the range of ``F``
proves infeasibility).  Neither answer is trusted as a float: the primal
solution is rounded to dyadic rationals and ``F > 0`` is verified exactly
(Sylvester's criterion); the dual ``W`` is rounded, projected exactly onto
``{<F_k, W> = 0}`` and ``W > 0`` verified exactly.  Close to the boundary
neither certificate verifies and the answer is ``None`` (undecided).  A
positive definite ``W`` cannot exist when ``A`` has an eigenvalue in the closed
unit disc (``Y = Re v v*`` for a left eigenvector ``v`` of that eigenvalue gives
``F(Y, 0) >= 0``, ``F != 0``), nor when part of the system is stabilizable
on its own (a ``Y`` supported there gives ``F(Y, Z) >= 0``, ``F != 0``); there
infeasibility is certified only through the ``ln rho(A)`` test.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Any, Sequence

import flint
import numpy as np
import sympy as sp

from ..exact.arguments import check_public
from ..errors import InputError, NotPositiveDefiniteError, require_extra
from ..exact.algebraic import expr_ball
from ..exact.numbers import sympify
from ..exact.linalg import field_of, rank, solve_rows
from ..losses import IID
from ..model import System, check_positive_definite
from ..spectral import eigenvalues
from .quantities import _require_iid, capacity_exceeds, spectral_radius


@dataclass(frozen=True)
class LMIVerdict:
    """Theorem 4 condition 1): ``holds`` (True / False / None = undecided) with its exact certificate."""

    holds: bool | None
    certificate: str
    primal_margin: float
    dual_margin: float
    gain: sp.ImmutableMatrix | None = None  # L (C coordinates) with A - L Lambda C mean-square stable


def _basis(system: System, loss: IID) -> tuple[list[sp.Matrix], int, list[tuple[int, int, int]]]:
    """Exact basis matrices F_k of the linear map (Y, Z) -> F, the number of Y coordinates, Z indices."""
    n = system.n
    arrival = [1 - e for e in _require_iid(loss)]
    if len(arrival) != system.d:
        raise InputError(f"loss: {len(arrival)} rates for {system.d} sensors")
    live = [i for i, a in enumerate(arrival) if a != 0]
    noisy = [i for i in live if arrival[i] != 1]
    size = n * (2 + len(noisy))

    def place(blocks: dict[tuple[int, int], sp.Matrix]) -> sp.Matrix:
        F = sp.zeros(size, size)
        for (r, c), B in blocks.items():
            F[r * n:(r + 1) * n, c * n:(c + 1) * n] += B
            if r != c:
                F[c * n:(c + 1) * n, r * n:(r + 1) * n] += B.T
        return F

    basis, zidx = [], []
    for a in range(n):
        for b in range(a, n):
            E = sp.zeros(n, n)
            E[a, b] = E[b, a] = 1
            diag = {(0, 0): E, (1, 1): E, (1, 0): E * system.A}
            diag.update({(2 + k, 2 + k): E / (arrival[i] * (1 - arrival[i])) for k, i in enumerate(noisy)})
            basis.append(place(diag))
    ny = len(basis)
    for i in live:
        C = system.sensors[i].C
        for r in range(n):
            for c in range(C.shape[0]):
                E = sp.zeros(n, C.shape[0])
                E[r, c] = 1
                blocks = {(1, 0): -arrival[i] * E * C}
                if i in noisy:
                    blocks[(2 + noisy.index(i), 0)] = E * C
                basis.append(place(blocks))
                zidx.append((i, r, c))
    return basis, ny, zidx


def _dyadic(v: float, bits: int = 40) -> Fraction:
    return Fraction(round(v * 2 ** bits), 2 ** bits)


def _positive_definite(M: sp.Matrix) -> bool:
    """Exact: Sylvester's criterion (python-flint over Q, certified signs otherwise)."""
    if all(v.is_Rational for v in M):
        F = flint.fmpq_mat([[flint.fmpq(int(v.p), int(v.q)) for v in row] for row in M.tolist()])
        k = M.shape[0]
        return all(flint.fmpq_mat([[F[i, j] for j in range(m)] for i in range(m)]).det() > 0
                   for m in range(1, k + 1))
    decided = _positive_definite_by_balls(M)
    if decided is not None:
        return decided
    try:
        check_positive_definite(M, "certificate")
    except NotPositiveDefiniteError:
        return False
    return True


def _positive_definite_by_balls(M: sp.Matrix, prec: int = 256) -> bool | None:
    """Sylvester's criterion on certified balls (python-flint ``arb``) around algebraic entries:
    True or False when every leading minor's sign is decided, None otherwise (the exact
    determinants of irrational entries cost minutes; the balls, milliseconds)."""
    k = M.shape[0]
    entries = [[expr_ball(sympify(v), prec).real for v in row] for row in M.tolist()]
    for m in range(1, k + 1):
        minor = flint.arb_mat([row[:m] for row in entries[:m]]).det()
        if not minor > 0:
            return False if minor < 0 else None
    return True


def _solve(G: sp.Matrix, b: sp.Matrix) -> sp.Matrix:
    """``G x = b`` exactly (``G`` invertible); with algebraic entries in their number field
    (:func:`symkf.exact.linalg.solve_rows`, a rational system solved by flint), not over sympy's
    algebraic domain (3.2 CPU-s for the 74 x 74 system of sixteen sensors at a simple rate, minutes
    at the 156-bit rates of a bisection) nor over generic expressions (minutes)."""
    if all(v.is_Rational for v in (*G, *b)):
        return G.LUsolve(b)
    K = field_of(G, b)
    value: dict[sp.Expr, Any] = {}   # the Gram matrix repeats few distinct entries
    rows = [[value.setdefault(v, K.convert(v)) for v in G.row(i)] for i in range(G.shape[0])]
    x = solve_rows(K, rows, [value.setdefault(v, K.convert(v)) for v in b])
    return sp.Matrix([K.to_sympy(a) for a in x])


def _entries(basis: list[sp.Matrix]) -> list[dict[tuple[int, int], sp.Expr]]:
    """The nonzero entries of each basis matrix: they hold a few dozen of ``size^2``, and products
    over them cost that many sympy operations, not ``size^2`` (the Gram matrix of 74 dense 72 x 72
    matrices, sixteen sensors, took 174 CPU-s)."""
    return [dict(B.todok()) for B in basis]


def _frobenius(P: dict[tuple[int, int], sp.Expr], Q: Any) -> sp.Expr:
    """``<P, Q>`` for ``P`` given by its nonzero entries and ``Q`` a matrix or another such dict."""
    if isinstance(Q, dict):
        return sp.Add(*[v * Q[k] for k, v in P.items() if k in Q])
    return sp.Add(*[v * Q[k] for k, v in P.items()])


def _combination(coefficients: Sequence[sp.Expr], entries: list[dict[tuple[int, int], sp.Expr]], size: int,
                 start: sp.Matrix | None = None) -> sp.Matrix:
    """``start + sum_k coefficients[k] F_k`` (``start`` default zero), over the basis' nonzero entries."""
    out = sp.zeros(size, size) if start is None else start.copy()
    for c, F in zip(coefficients, entries):
        if c != 0:
            for k, v in F.items():
                out[k] += c * v
    return out


def _to_numpy(F: dict[tuple[int, int], sp.Expr], size: int) -> np.ndarray:
    """A basis matrix given by its nonzero entries, in floats (each entry evaluated once)."""
    out = np.zeros((size, size))
    for k, v in F.items():
        out[k] = float(sp.N(v, 30))
    return out


def mare_stabilizable(system: System, loss: IID) -> LMIVerdict:
    """Decide Theorem 4's condition 1) (eq. 22) by the convex reformulation above, with exact certificates."""
    cp = require_extra("cvxpy", "sdp", "mare_stabilizable, the LMI of Yang et al. (Theorem 4),")

    if not capacity_exceeds(loss, spectral_radius(system.A)):
        return LMIVerdict(False, "C <= ln rho(A): rho(T) >= prod(1 - lambda_i) rho(A)^2 >= 1 (exact)",
                          0.0, np.inf)
    basis, ny, zidx = _basis(system, loss)
    entries = _entries(basis)
    size, n = basis[0].shape[0], system.n
    num = [_to_numpy(F, size) for F in entries]

    x, t = cp.Variable(len(num)), cp.Variable()
    F = sum(x[k] * num[k] for k in range(len(num)))
    Y = sum(x[k] * num[k][:n, :n] for k in range(ny))
    primal = cp.Problem(cp.Maximize(t), [(F + F.T) / 2 >> t * np.eye(size), (Y + Y.T) / 2 << np.eye(n)])
    primal.solve(solver=cp.CLARABEL)
    t_val = float(t.value) if t.value is not None else -np.inf
    if t_val > 0:
        xr = [_dyadic(v) for v in x.value]
        Fx = _combination([sp.Rational(v.numerator, v.denominator) for v in xr], entries, size)
        if _positive_definite(Fx):
            Yx = Fx[:n, :n]
            Z = {}
            for v, (i, r, c) in zip(xr[ny:], zidx):
                Z.setdefault(i, sp.zeros(n, system.sensors[i].m))[r, c] = sp.Rational(v.numerator, v.denominator)
            gain = sp.Matrix.hstack(*[Yx.inv() * Z.get(i, sp.zeros(n, s.m)) for i, s in enumerate(system.sensors)])
            return LMIVerdict(True, "F(Y, Z) > 0 verified exactly for rational (Y, Z)", t_val, -np.inf,
                              sp.ImmutableMatrix(gain))

    W, s = cp.Variable((size, size), symmetric=True), cp.Variable()
    dual = cp.Problem(cp.Maximize(s), [W >> s * np.eye(size), cp.trace(W) == 1]
                      + [cp.sum(cp.multiply(B, W)) == 0 for B in num])
    dual.solve(solver=cp.CLARABEL)
    s_val = float(s.value) if s.value is not None else -np.inf
    if s_val > 0:
        Wr = sp.Matrix(size, size, lambda i, j: sp.Rational(_dyadic((W.value[i, j] + W.value[j, i]) / 2)))
        gram = sp.Matrix(len(basis), len(basis), lambda i, j: _frobenius(entries[i], entries[j]))
        coef = _solve(gram, sp.Matrix([_frobenius(F, Wr) for F in entries]))
        Wp = _combination([-c for c in coef], entries, size, Wr)
        if _positive_definite(Wp):
            return LMIVerdict(False, "W > 0 with <F_k, W> = 0 for every k verified exactly "
                              "(no (Y, Z) gives F > 0)", t_val, s_val)
    return LMIVerdict(None, "undecided: neither certificate verifies (too close to the boundary)", t_val, s_val)


def unit_circle_condition(system: System) -> bool:
    """Theorem 4's condition 2), exactly: ``rank [A - mu I, Q] = n`` for every eigenvalue ``|mu| = 1``.

    (``[A - e^{jw} I, B]`` loses rank only at eigenvalues on the unit circle,
    and ``range B = range Q``.)  Always true when ``Q > 0``.
    """
    A, Q = sp.Matrix(system.A), sp.Matrix(system.Q)
    return all(rank(sp.Matrix.hstack(A - ev.expr * sp.eye(system.n), Q)) == system.n
               for ev in eigenvalues(A) if ev.modulus == 1)


def mare_converges(system: System, loss: IID) -> bool | None:
    """Theorem 4: ``V_k`` converges for every initial value iff conditions 1) and 2) hold (None: undecided)."""
    if not unit_circle_condition(system):
        return False
    return mare_stabilizable(system, loss).holds

check_public(globals())

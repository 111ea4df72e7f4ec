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
proves infeasibility; the primal's multiplier of ``F >= t I`` is such a ``W`` when the primal
optimum is ``t = 0``, and is tried first).  Neither answer is trusted as a float: the primal
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

from .. import budget
from ..arguments import check_public
from ..errors import InputError, require_extra
from ..exact.algebraic import with_prec
from ..exact.field import Elem, NumberField
from ..exact.linalg import field_of, positive_definite, rank, schur_positive, solve_rows
from ..model.loss import LossModel
from ..model.system import System
from ..numeric import convex
from ..exact.spectral import eigenvalues
from .quantities import _require_iid, capacity_exceeds, spectral_radius


@dataclass(frozen=True)
class LMIVerdict:
    """Theorem 4 condition 1): ``holds`` (True / False / None = undecided) with its exact certificate."""

    holds: bool | None
    certificate: str
    primal_margin: float
    dual_margin: float
    gain: sp.ImmutableMatrix | None = None  # L (C coordinates) with A - L Lambda C mean-square stable


def _basis(system: System, loss: LossModel) -> tuple[list[sp.Matrix], int, list[tuple[int, int, int]]]:
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


Entries = list[dict[tuple[int, int], Elem]]


def _entries(basis: list[sp.Matrix]) -> tuple[NumberField, Entries]:
    """The field of the basis' entries and each basis matrix's nonzero entries as its elements:
    they hold a few dozen of ``size^2``, and every product below runs over them, not over dense
    sympy matrices, sympy's rationals or the field of all ``size^2`` entries read one by one, each
    of which dominated the bounds atlas at sixteen sensors or a dense 8-state ``A``
    (docs/performance.md)."""
    nonzero = [B.todok() for B in basis]
    distinct = list({v: None for F in nonzero for v in F.values()})   # few: the basis repeats them
    K = field_of(sp.Matrix(1, len(distinct), distinct))
    value = {v: K.convert(v) for v in distinct}
    return K, [{k: value[v] for k, v in F.items()} for F in nonzero]


def _frobenius(K: NumberField, P: dict[tuple[int, int], Elem], Q: dict[tuple[int, int], Elem] | list[list[Elem]]
               ) -> Elem:
    """``<P, Q>`` for ``P`` given by its nonzero entries and ``Q`` a dense matrix or another such dict."""
    if isinstance(Q, dict):
        common = [k for k in P if k in Q]
        return K.dot([P[k] for k in common], [Q[k] for k in common])
    return K.dot(list(P.values()), [Q[i][j] for i, j in P])


def _combination(K: NumberField, coefficients: Sequence[Elem], entries: Entries, size: int,
                 start: list[list[Elem]] | None = None) -> list[list[Elem]]:
    """``start + sum_k coefficients[k] F_k`` (``start`` default zero), over the basis' nonzero entries."""
    zero = flint.fmpq_poly([])
    out = [[zero] * size for _ in range(size)] if start is None else [list(row) for row in start]
    touched = set()
    for c, F in zip(coefficients, entries):
        if not c.is_zero():
            for (i, j), v in F.items():
                out[i][j] = out[i][j] + c * v
                touched.add((i, j))
    for i, j in touched:
        out[i][j] = out[i][j] % K.modulus
    return out


def _entry_balls(K: NumberField, entries: Entries, prec: int, accuracy: int | None = None
                 ) -> list[tuple[int, int, int, flint.arb]]:
    """``(k, i, j, ball)`` for every nonzero entry ``(i, j)`` of every basis matrix ``F_k``: certified
    real balls at ``prec`` bits (or more, for ``accuracy``: :meth:`NumberField.real_balls`), converted
    in one call."""
    where = [(k, i, j) for k, F in enumerate(entries) for i, j in F]
    balls = K.real_balls([[v for F in entries for v in F.values()]], prec, accuracy)[0] if where else []
    return [(k, i, j, b) for (k, i, j), b in zip(where, balls)]


def _vectorised(entries: Entries, K: NumberField, size: int):
    """The basis in floats as one sparse matrix, ``vec(F_k)`` (column-major, size^2 rows) its column
    ``k``: the SDP's ``F = sum_k x_k F_k`` is one product (a sum of dense ``F_k`` is costly in memory and
    in cvxpy's canonicalisation at many sensors: docs/performance.md)."""
    from scipy import sparse
    nonzero = _entry_balls(K, entries, 64, accuracy=53)   # 64 bits alone gave NaN over four cyclotomic fields
    return sparse.csc_matrix(([float(b.mid()) for *_, b in nonzero],
                              ([j * size + i for _, i, j, _ in nonzero], [k for k, *_ in nonzero])),
                             shape=(size * size, len(entries)))


def _gram(K: NumberField, entries: Entries) -> list[list[Elem]]:
    """``<F_i, F_j>`` over the basis, symmetric: each pair once."""
    G = [[None] * len(entries) for _ in entries]
    for i, P in enumerate(entries):
        for j in range(i, len(entries)):
            G[i][j] = G[j][i] = _frobenius(K, P, entries[j])
    return G


def _orthogonal_positive(K: NumberField, entries: Entries, gram: list[list[Elem]], W: np.ndarray) -> bool:
    """Whether the float ``W``, rounded to dyadic rationals and projected exactly onto
    ``{<F_k, W> = 0 for every k}`` (the Gram system ``gram`` of the basis, in ``K``), is positive definite.

    Decided first on certified balls of that exact projection, ``W - sum_k c_k F_k`` with ``c``
    enclosing the exact solution of the Gram system (flint's certified solve), by
    :func:`_schur_positive`; only when a ball leaves it open, the projection in exact arithmetic
    (its rationals are large: converting them to balls, with the exact solve and combination, is
    the costly route, taken only when it must be)."""
    size = W.shape[0]
    Wr = [[_rational(_dyadic((W[i, j] + W[j, i]) / 2)) for j in range(size)] for i in range(size)]
    rhs = [_frobenius(K, P, Wr) for P in entries]
    decided = with_prec(256, lambda: _projected_positive(K, entries, gram, rhs, Wr))
    if decided is not None:
        return decided
    coef = solve_rows(K, gram, rhs)
    return positive_definite(K, _combination(K, [-c for c in coef], entries, size, Wr))


def _projected_positive(K: NumberField, entries: Entries, gram: list[list[Elem]], rhs: list[Elem],
                        start: list[list[Elem]]) -> bool | None:
    """:func:`_schur_positive` of ``start - sum_k c_k F_k``, ``gram c = rhs``, on certified balls at the
    current precision; None when the Gram matrix is not certified invertible or a pivot's sign stays open."""
    prec = flint.ctx.prec
    try:
        c = flint.arb_mat(K.real_balls(gram, prec)).solve(flint.arb_mat([[b] for b in K.real_balls([rhs], prec)[0]]))
    except ZeroDivisionError:
        return None
    M = flint.arb_mat(K.real_balls(start, prec))
    for k, i, j, v in _entry_balls(K, entries, prec):
        M[i, j] -= c[k, 0] * v
    return schur_positive(M.tolist())


def _rational(v: Fraction) -> Elem:
    return flint.fmpq_poly([flint.fmpq(v.numerator, v.denominator)])


def price_lmi(system: System, noisy: int, calls: int, entry: str) -> None:
    """Refuse, before the first is built, ``calls`` LMIs of :func:`mare_stabilizable` on ``system``
    with ``noisy`` sensors of arrival rates in (0, 1) whose estimated work is above ``max_work``: the
    basis matrices written entry by entry (:func:`_basis`: ``n^2`` per block, ``4 + noisy`` blocks
    per ``Y`` coordinate, 2 or 4 per ``Z`` coordinate) and the SDP over the LMI of size ``N = n (2 +
    noisy)`` with ``V`` coordinates (``N^2 V``)."""
    n, rows = system.n, sum(s.m for s in system.sensors)
    ny, nz = n * (n + 1) // 2, n * rows
    size = n * (2 + noisy)
    written = n * n * (ny * (4 + noisy) + nz * (4 if noisy else 2))
    budget.price(entry, f"{calls} LMIs of size {size} in {ny + nz} coordinates (Theorem 4's condition 1), "
                        f"n = {n}, {noisy} noisy sensors)",
                 lmi=calls, lmi_basis_entry=calls * written, lmi_sdp_entry=calls * size * size * (ny + nz))


def mare_stabilizable(system: System, loss: LossModel) -> LMIVerdict:
    """Decide Theorem 4's condition 1) (eq. 22) by the convex reformulation above, with exact certificates.

    The certificates are checked in the number field of ``A``, ``C_i`` and the loss rates
    (python-flint elements; :func:`symkf.exact.linalg.solve_rows` for the projection's Gram system,
    not sympy's algebraic domain, whose arithmetic is slow at the many-bit rates of a bisection)."""
    cp = require_extra("cvxpy", "sdp", "mare_stabilizable, the LMI of Yang et al. (Theorem 4),")

    if not capacity_exceeds(loss, spectral_radius(system.A)):
        return LMIVerdict(False, "C <= ln rho(A): rho(T) >= prod(1 - lambda_i) rho(A)^2 >= 1 (exact)",
                          0.0, np.inf)
    price_lmi(system, sum(1 for e in _require_iid(loss) if 0 < e < 1), 1, "symkf.capacity.mare_stabilizable")
    basis, ny, zidx = _basis(system, loss)
    K, entries = _entries(basis)
    # every certificate is checked in K, the compositum of all entries (no one trigonometric
    # constant's field, which field_of caps): four rotations 2R(2 pi/q), q = 5, 7, 9, 11, give
    # degree 1440, where the bisection's exact checks would not finish in reasonable time
    budget.check("max_cyclotomic_degree", K.degree, "A", "the degree of the field of the LMI's entries (A, C "
                 "and the loss rates), in which its certificates are checked")
    size, n = basis[0].shape[0], system.n
    vec = _vectorised(entries, K, size)

    x, t = cp.Variable(len(entries)), cp.Variable()
    F = cp.reshape(vec @ x, (size, size), order="F")
    Y = F[:n, :n]   # the Z coordinates' F_k vanish there
    positive = (F + F.T) / 2 >> t * np.eye(size)
    primal = cp.Problem(cp.Maximize(t), [positive, (Y + Y.T) / 2 << np.eye(n)])
    primal_status = convex.solve(primal)
    t_val = float(t.value) if t.value is not None else -np.inf
    if t_val > 0:
        xr = [_dyadic(v) for v in x.value]
        Fx = _combination(K, [_rational(v) for v in xr], entries, size)
        if positive_definite(K, Fx):
            Yx = sp.Matrix([[K.to_sympy(a) for a in row[:n]] for row in Fx[:n]])
            Z = {}
            for v, (i, r, c) in zip(xr[ny:], zidx):
                Z.setdefault(i, sp.zeros(n, system.sensors[i].m))[r, c] = sp.Rational(v.numerator, v.denominator)
            gain = sp.Matrix.hstack(*[Yx.inv() * Z.get(i, sp.zeros(n, s.m)) for i, s in enumerate(system.sensors)])
            return LMIVerdict(True, "F(Y, Z) > 0 verified exactly for rational (Y, Z)", t_val, -np.inf,
                              sp.ImmutableMatrix(gain))
    infeasible = "W > 0 with <F_k, W> = 0 for every k verified exactly (no (Y, Z) gives F > 0)"
    gram = _gram(K, entries)   # both candidate W are projected with it
    # the multiplier of F >= t I is such a W at t = 0, which saves the dual SDP below (a second solve)
    if positive.dual_value is not None and _orthogonal_positive(K, entries, gram, positive.dual_value):
        return LMIVerdict(False, infeasible, t_val, float(np.linalg.eigvalsh(positive.dual_value)[0]))
    W, s = cp.Variable((size, size), symmetric=True), cp.Variable()
    dual = cp.Problem(cp.Maximize(s), [W >> s * np.eye(size), cp.trace(W) == 1,
                                       vec.T @ cp.reshape(W, (size * size,), order="F") == 0])
    dual_status = convex.solve(dual)
    s_val = float(s.value) if s.value is not None else -np.inf
    if s_val > 0 and _orthogonal_positive(K, entries, gram, W.value):
        return LMIVerdict(False, infeasible, t_val, s_val)
    failed = [name for name, status in (("primal", primal_status), ("dual", dual_status)) if status == convex.FAILED]
    why = f"the SDP solver failed on the {' and '.join(failed)}" if failed else "too close to the boundary"
    return LMIVerdict(None, f"undecided: neither certificate verifies ({why})", t_val, s_val)


def unit_circle_condition(system: System) -> bool:
    """Theorem 4's condition 2), exactly: ``rank [A - mu I, Q] = n`` for every eigenvalue ``|mu| = 1``.

    (``[A - e^{jw} I, B]`` loses rank only at eigenvalues on the unit circle,
    and ``range B = range Q``.)  Always true when ``Q > 0``.
    """
    A, Q = sp.Matrix(system.A), sp.Matrix(system.Q)
    return all(rank(sp.Matrix.hstack(A - ev.expr * sp.eye(system.n), Q)) == system.n
               for ev in eigenvalues(A) if ev.modulus == 1)


def mare_converges(system: System, loss: LossModel) -> bool | None:
    """Theorem 4: ``V_k`` converges for every initial value iff conditions 1) and 2) hold (None: undecided)."""
    if not unit_circle_condition(system):
        return False
    return mare_stabilizable(system, loss).holds

check_public(globals())

"""Optimal unbiased linear fusion weights (arXiv:2012.04896, Problems 1-3, Theorem 2, Lemma 5).

Problem 1: ``min_W tr(W' Sigma W)`` subject to ``W' V_o = I(n)``, ``W`` nN x n,
``Sigma`` nN x nN symmetric PSD and (here) singular.  Three ways to the optimum:

``"closed-form"``
    Theorem 2 / Lemma 5 (Albert's Gauss-Markov theorem with singular
    covariance): ``W* = [I - (M Sigma M)^+ M Sigma] (V_o')^+`` with
    ``M = I - V_o V_o^+``.  It satisfies the KKT conditions exactly
    (``M Sigma W* = 0`` because ``(M Sigma M)^+ = M (M Sigma M)^+``, and
    ``W*' V_o = I`` because ``(M Sigma M)^+ V_o = 0``), see
    ``proofs/fusion_closed_form.py``.

``"sdp"``
    Problem 2 with the Schur-complement constraint ``[[I, W'], [W, X]] >= 0``
    (Lemma 4), solved by cvxpy with Clarabel.

``"problem3"``
    The paper calls Problem 3 (``max tr(Lambda_1)/2`` s.t. ``W' V_o = I``,
    ``2 Sigma W = V_o Lambda_1'``) a linear program and the dual of Problem 2.
    It is neither in any useful sense: its constraints are exactly the KKT
    conditions of Problem 1, and on them ``Lambda_1' = 2 W' Sigma W`` so the
    objective is constant (the optimal value).  Problem 3 is a consistent,
    rank-deficient **linear system**; it is solved here by least squares
    (minimum norm).  ``proofs/fusion_problem3.py`` checks this.

The minimiser ``W`` is not unique when ``Sigma`` is singular (add any ``D``
with ``Sigma D = 0``, ``D' V_o = 0``); ``W' Sigma W`` and ``Sigma W`` are.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg
from threadpoolctl import threadpool_limits

from .. import budget
from ..arguments import check_public, float_array
from ..errors import AssumptionError, InputError, NotPositiveDefiniteError, ShapeError, require_extra
from ..numeric import convex

__all__ = ["optimal_weights", "fused_covariance", "METHODS"]

METHODS = ("closed-form", "sdp", "problem3")
# Relative tolerance for "zero" in Sigma's symmetry / PSD checks and for ranks:
# Sigma is assembled in floating point, so exact zeros appear as rounding.
_RTOL = 1e-9


def _validate(Sigma: np.ndarray, Vo: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    Sigma = float_array(Sigma, "Sigma")
    Vo = float_array(Vo, "Vo")
    if Sigma.ndim != 2 or Sigma.shape[0] != Sigma.shape[1]:
        raise ShapeError(f"Sigma: must be square (nN x nN), got shape {Sigma.shape}")
    if Vo.ndim != 2 or Vo.shape[0] != Sigma.shape[0] or Vo.shape[1] > Vo.shape[0] or Vo.size == 0:
        raise ShapeError(f"Vo: must be nN x n with nN = {Sigma.shape[0]} rows of Sigma, got shape {Vo.shape}")
    if not (np.all(np.isfinite(Sigma)) and np.all(np.isfinite(Vo))):
        raise InputError("Sigma, Vo: entries must be finite")
    scale = max(np.abs(Sigma).max(), np.finfo(float).tiny)
    asym = np.abs(Sigma - Sigma.T).max()
    if asym > _RTOL * scale:
        i, j = np.unravel_index(np.argmax(np.abs(Sigma - Sigma.T)), Sigma.shape)
        raise NotPositiveDefiniteError(
            f"Sigma: not symmetric, entry [{i}][{j}] = {Sigma[i, j]:.6g} but [{j}][{i}] = {Sigma[j, i]:.6g} "
            "(Lemma 3, arXiv:2012.04896: Sigma is symmetric positive semidefinite)")
    Sigma = (Sigma + Sigma.T) / 2
    low = np.linalg.eigvalsh(Sigma)[0]
    if low < -_RTOL * scale * Sigma.shape[0]:
        raise NotPositiveDefiniteError(
            f"Sigma: not positive semidefinite, smallest eigenvalue {low:.6g} "
            "(Lemma 3, arXiv:2012.04896: Sigma is symmetric positive semidefinite)")
    s = np.linalg.svd(Vo, compute_uv=False)
    if s[-1] <= _RTOL * s[0]:
        raise AssumptionError(
            f"Vo ({Vo.shape[0]}x{Vo.shape[1]}) has rank < {Vo.shape[1]} (smallest singular value {s[-1]:.3g}), "
            "so W'Vo = I has no solution",
            assumption="Assumption 1 (arXiv:2012.04896): collective observability (Vo of full column rank)")
    return Sigma, Vo


class _ClosedForm:
    """Theorem 2's weights (arXiv:2012.04896) for one unbiasedness matrix ``Vo`` of full column
    rank: its null space and pseudo-inverse are computed once, for every ``Sigma`` asked."""

    def __init__(self, Vo: np.ndarray):
        # M = I - Vo Vo^+ = N N' with N an orthonormal basis of null(Vo'), so
        # (M Sigma M)^+ = N (N' Sigma N)^+ N'.  Computing it that way keeps its range
        # inside range(M) in floating point, hence W' Vo = I to rounding even when
        # Sigma's spectrum decays through the rounding level (the pendulum's does).
        self.N = scipy.linalg.null_space(Vo.T)
        self.pinv_VoT = scipy.linalg.pinv(Vo.T)

    def __call__(self, Sigma: np.ndarray) -> np.ndarray:
        """``W`` for a symmetric positive semidefinite ``Sigma`` (checked by the caller)."""
        N, pinv_VoT = self.N, self.pinv_VoT
        # Grouped as N ((N' Sigma N)^+ (N' Sigma (Vo')^+)): forming N (N' Sigma N)^+ N' first
        # multiplies rounding by the huge entries of that pseudo-inverse.
        # Singular values of N' Sigma N below Sigma's rounding level are zeros: relative to N' Sigma N
        # alone (pinv's default) an exactly zero N' Sigma N of size 1e-17 would be inverted.
        rounding = Sigma.shape[0] * np.finfo(float).eps * np.abs(Sigma).max()
        return pinv_VoT - N @ (scipy.linalg.pinv(N.T @ Sigma @ N, atol=rounding) @ (N.T @ Sigma @ pinv_VoT))


def _problem3(Sigma: np.ndarray, Vo: np.ndarray) -> np.ndarray:
    nN, n = Vo.shape
    # Unknowns [W; Lambda_1']: 2 Sigma W - Vo Lambda_1' = 0, Vo' W = I.
    K = np.block([[2 * Sigma, -Vo], [Vo.T, np.zeros((n, n))]])
    rhs = np.vstack([np.zeros((nN, n)), np.eye(n)])
    sol, *_ = scipy.linalg.lstsq(K, rhs)
    return sol[:nN]


def _sdp(Sigma: np.ndarray, Vo: np.ndarray) -> np.ndarray:
    cp = require_extra("cvxpy", "sdp", 'optimal_weights(method="sdp"), Problem 2 of arXiv:2012.04896,')

    nN, n = Vo.shape
    S = Sigma / max(np.abs(Sigma).max(), np.finfo(float).tiny)   # same minimiser, better scaled
    W = cp.Variable((nN, n))
    X = cp.Variable((nN, nN), symmetric=True)
    schur = cp.bmat([[np.eye(n), W.T], [W, X]])
    problem = cp.Problem(cp.Minimize(cp.trace(S @ X)), [W.T @ Vo == np.eye(n), schur >> 0])
    status = convex.solve(problem, tol_gap_abs=1e-10, tol_gap_rel=1e-10, tol_feas=1e-10)
    if status not in ("optimal", "optimal_inaccurate") or W.value is None:
        raise AssumptionError(f"the SDP solver returned status {status!r}",
                              assumption="Problem 2 (arXiv:2012.04896) solvable", applies_instead='method="closed-form"')
    return np.asarray(W.value)


def optimal_weights(Sigma: np.ndarray, Vo: np.ndarray, method: str = "closed-form") -> np.ndarray:
    """Stacked fusion weights ``W = [W_1 ... W_N]'`` (nN x n) solving Problem 1 of arXiv:2012.04896.

    ``method`` is ``"closed-form"`` (Theorem 2), ``"sdp"`` (Problem 2) or
    ``"problem3"`` (the KKT linear system the paper calls an LP); see the
    module docstring.  Raises :class:`NotPositiveDefiniteError` if ``Sigma``
    is not symmetric PSD, :class:`ShapeError` on mismatched shapes and
    :class:`AssumptionError` if ``Vo`` is rank deficient (Assumption 1).

    Floats: ``Sigma`` is assembled in floating point (eqs. 17-20), so the weights are floats too.

    Parameters
    ----------
    Sigma : numpy.ndarray
        The ``nN x nN`` symmetric positive semidefinite covariance of the stacked local errors
        (eq. 18, :func:`symkf.fusion.fusion_sigma`); it may be singular.
    Vo : numpy.ndarray
        The ``nN x n`` unbiasedness matrix, of full column rank (Assumption 1,
        :func:`symkf.fusion.unbiasedness_matrix`).
    method : {"closed-form", "sdp", "problem3"}, default "closed-form"
        Theorem 2's closed form, Problem 2's SDP (cvxpy, Clarabel), or Problem 3's KKT system.

    Returns
    -------
    numpy.ndarray
        ``W`` (``nN x n``) with ``W' V_o = I`` minimising ``tr(W' Sigma W)``;
        :func:`fused_covariance` gives ``W' Sigma W``.

    Raises
    ------
    InputError
        An unknown ``method`` or a non-finite entry.
    ShapeError
        ``Sigma`` is not square or ``Vo`` does not fit it.
    NotPositiveDefiniteError
        ``Sigma`` is not symmetric positive semidefinite.
    AssumptionError
        ``Vo`` is rank deficient, or the SDP solver fails.

    Examples
    --------
    Two independent unbiased scalar estimates with error variances 1 and 2 (``n = 1``,
    ``N = 2``): by hand the optimum is inverse-variance weighting, ``W = (2/3, 1/3)'``
    with fused variance ``1 / (1 + 1/2) = 2/3``; Problem 3's linear system gives the same:

    >>> import numpy as np
    >>> from symkf.fusion import fused_covariance, optimal_weights
    >>> Sigma, Vo = np.diag([1.0, 2.0]), np.ones((2, 1))
    >>> W = optimal_weights(Sigma, Vo)
    >>> W.round(9).tolist(), fused_covariance(Sigma, W).round(9).tolist()
    ([[0.666666667], [0.333333333]], [[0.666666667]])
    >>> np.allclose(optimal_weights(Sigma, Vo, method="problem3"), W)
    True

    A singular ``Sigma``: an error-free first estimate takes all the weight:

    >>> np.allclose(optimal_weights(np.diag([0.0, 1.0]), Vo), [[1.0], [0.0]])
    True
    """
    if method not in METHODS:
        raise InputError(f"method: expected one of {', '.join(METHODS)}, got {method!r}")
    Sigma = float_array(Sigma, "Sigma")
    M = Sigma.shape[0] if Sigma.ndim == 2 else 0
    budget.price("symkf.fusion.optimal_weights", f'the weights by method="{method}" for a {M} x {M} Sigma',
                 **({"weights_sdp_entry": M ** 4} if method == "sdp" else {"weights_cube": M ** 3}))
    # one BLAS thread, as priced: beside other work BLAS's threads spin, and a 512 x 512 closed form
    # cost 4 to 40 times its CPU
    with threadpool_limits(1):
        Sigma, Vo = _validate(Sigma, Vo)
        return {"closed-form": lambda Sigma, Vo: _ClosedForm(Vo)(Sigma), "sdp": _sdp,
                "problem3": _problem3}[method](Sigma, Vo)


def fused_covariance(Sigma: np.ndarray, W: np.ndarray) -> np.ndarray:
    """``P = W' Sigma W`` (eq. 19), the error covariance of the fused estimate."""
    Sigma, W = float_array(Sigma, "Sigma"), float_array(W, "W")
    if Sigma.ndim != 2 or W.ndim != 2 or Sigma.shape[0] != Sigma.shape[1] or W.shape[0] != Sigma.shape[0]:
        raise ShapeError(f"Sigma {Sigma.shape}, W {W.shape}: expected Sigma nN x nN and W nN x n")
    P = W.T @ Sigma @ W
    return (P + P.T) / 2

check_public(globals())

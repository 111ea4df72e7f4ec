"""Claim checked: the fusion paper's (arXiv:2012.04896) eq. (18) for the cross covariance P^(ij)_k of remote errors.

Source: Optimal linear sensor fusion over lossy channels (arXiv:2012.04896), eq. (18):
``P^(ij) = A_i^tau_i Gamma_ij A_j'^tau_j + sum_{t<min(tau_i,tau_j)} A_i^t V_i' Q V_j A_j'^t``.

Finding: false whenever ``tau_i != tau_j``.  The local errors in it are taken
at different times ``k - tau_i`` and ``k - tau_j``, so their covariance is not
the same-time ``Gamma_ij``, and the newer local error is correlated with the
process noise through which the older estimate is predicted.  The corrected
formula is in ``symkf/fusion/covariance.py``.

Method: (1) exact counterexample: scalar process ``x+ = 2x + w`` (q = 1), two
sensors ``y = x + v`` (r = 1), steady Kalman gains in Q(sqrt 5) (exact DARE),
holding times (1, 0).  The true cross covariance follows by hand from
``E_1 = 2 E_s1(k-1) + w_{k-1}`` and ``E_2 = E_s2(k) = (1-K)(2 E_s2(k-1) + w_{k-1}) - K v_k``:
``2 (1-K) 2 Gamma + (1-K) q``; (18) gives ``2 Gamma``.  (2) floating point on the
pendulum of Section 4: symkf's corrected formula agrees with the independent
step-by-step propagation of the joint error covariance to 1e-9 relative, (18)
does not.
"""

import sys
from pathlib import Path

import numpy as np
import sympy as sp

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))


def exact_counterexample() -> bool:
    a, q, r = sp.Integer(2), sp.Integer(1), sp.Integer(1)
    p = sp.Symbol("p", positive=True)
    P_pred = max(sp.solve(sp.Eq(p, a**2 * p - a**2 * p**2 / (p + r) + q), p), key=lambda s: float(s))
    K = sp.simplify(P_pred / (P_pred + r))
    G, F = 1 - K, (1 - K) * a
    gamma = sp.Symbol("gamma")
    Gamma = sp.solve(sp.Eq(gamma, G * (a * gamma * a + q) * G), gamma)[0]   # Lemma 2, i != j
    true = sp.simplify(a * Gamma * F + q * G)
    stated = sp.simplify(a * Gamma)
    differ = sp.simplify(true - stated) != 0
    print(f"exact: P* = {P_pred}, K = {K}, Gamma_12 = {sp.simplify(Gamma)}")
    print(f"  tau = (1, 0): true P^(12) = {sp.simplify(true)} = {float(true):.6f}, "
          f"eq. (18) gives {sp.simplify(stated)} = {float(stated):.6f}")
    from symkf import Sensor
    from symkf.fusion import FusionModel, local_filters, remote_error_covariance
    lf = local_filters(FusionModel.discrete([[2]], [[1]], [Sensor([[1]]), Sensor([[1]])], ["1/2", "1/2"]))
    propagated = remote_error_covariance(lf, (1, 0), method="propagation")[0, 1]
    print(f"  joint-covariance propagation (floats): {propagated:.6f}")
    return differ and abs(propagated - float(true)) < 1e-9


def pendulum() -> bool:
    from symkf.fusion import local_filters, pendulum_model, remote_error_covariance
    lf = local_filters(pendulum_model())
    m = lf.model
    ok = True
    for tau in [(0,) * 10, (2, 0, 1, 0, 3, 0, 0, 1, 0, 2), (5, 1, 0, 0, 0, 0, 2, 0, 0, 0)]:
        exact = remote_error_covariance(lf, tau, method="propagation")
        ours = remote_error_covariance(lf, tau)
        stated = np.block([[np.linalg.matrix_power(m.local[i].A, tau[i]) @ lf.block(i, j)
                          @ np.linalg.matrix_power(m.local[j].A, tau[j]).T
                          + sum((np.linalg.matrix_power(m.local[i].A, t) @ m.local[i].V.T @ m.Q @ m.local[j].V
                                 @ np.linalg.matrix_power(m.local[j].A, t).T for t in range(min(tau[i], tau[j]))),
                                np.zeros((m.local[i].n_o, m.local[j].n_o)))
                          for j in range(m.N)] for i in range(m.N)])
        scale = np.abs(exact).max()
        err_ours, err_stated = np.abs(ours - exact).max() / scale, np.abs(stated - exact).max() / scale
        equal_tau = len(set(tau)) == 1
        ok &= err_ours < 1e-9 and (err_stated < 1e-9 if equal_tau else err_stated > 1e-6)
        print(f"pendulum tau = {tau}: corrected formula rel. error {err_ours:.1e}, eq. (18) rel. error {err_stated:.1e}")
    return ok


def main() -> bool:
    ok = exact_counterexample() and pendulum()
    print("PASS" if ok else "FAIL")
    return ok


if __name__ == "__main__":
    raise SystemExit(0 if main() else 1)

"""Claim checked: the bound in the proof of Proposition 1 of the fusion paper (arXiv:2012.04896).

Source: Optimal linear sensor fusion over lossy channels (arXiv:2012.04896), Appendix E:
``tr E[P*_k] <= m sum_i n_i,o { E[rho_i^(2 tau)] (tr Pbar_i - tr Q~_i/(1 - rho_i^2)) + tr Q~_i/(1 - rho_i^2) }``
with ``m > sigma_max(W)^2``.  Its last step bounds ``tr(A^t X A'^t)`` by
``n rho(A)^(2t) tr X``, which fails for non-normal A.

Finding: the printed bound is false.  Counterexample (N = 1 sensor, so
``V_o = I``, ``W = I`` is the only feasible weight and m may be any number > 1):
``A = [[1/2, 20], [0, 1/2]]``, ``C = I``, ``Q = I``, ``R = I``, ``lambda = 1/2``.
The exact steady-state ``tr E[P_k]`` (Stein equations,
``symkf.fusion.expected_remote_covariance``, cross-checked by averaging the
holding-time covariance over the geometric law of tau) exceeds the bound for
every m close to 1.  The proposition's conclusion (finite limit) still holds:
symkf computes a valid bound instead (``symkf.fusion.proposition1_bound``).

Method: floating point with a decisive margin (the ratio is printed).
"""

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))


def main() -> bool:
    from symkf import Sensor
    from symkf.fusion import (FusionModel, expected_remote_covariance, local_filters, proposition1_bound,
                              remote_error_covariance)
    model = FusionModel.discrete([["1/2", 20], [0, "1/2"]], [[1, 0], [0, 1]],
                                 [Sensor([[1, 0], [0, 1]])], ["1/2"])
    lf = local_filters(model)
    true = float(np.trace(expected_remote_covariance(lf)))
    averaged = sum(0.5 ** (t + 1) * np.trace(remote_error_covariance(lf, (t,))) for t in range(200))
    b = proposition1_bound(lf)
    print(f"tr E[P*] = {true:.6g} (Stein), {averaged:.6g} (average over tau); "
          f"printed bound with m -> 1: {b.printed_bound:.6g}; valid bound: {b.bound:.6g}")
    ok = abs(true - averaged) < 1e-8 * true and true > 2 * b.printed_bound and abs(b.bound - true) < 1e-8 * true
    print("PASS" if ok else "FAIL")
    return ok


if __name__ == "__main__":
    raise SystemExit(0 if main() else 1)

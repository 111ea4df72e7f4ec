"""You, Fu and Xie's observation (Automatica 47(12), 2011): the critical loss rate can lie
*strictly* between Sinopoli et al.'s two bounds (``symkf reproduce you-2011-counterexample``).

The system: ``A = [[0, -4], [1, -2]]`` (eigenvalues ``2 e^(+-2 pi i/3)``, similar to
``2 R(2 pi/3)``), one scalar sensor ``C = [1 0]``.  Its eigenvalue ratio is a cube root of
unity, so it is degenerate in Mo and Sinopoli's sense with ``p = 3``:

* exact (Sui-You-Fu engine): ``eps_c = 2^(-2p/(p-1)) = 1/8``;
* Sinopoli et al.'s necessary bound: ``eps_c <= 1/rho(A)^2 = 1/4``;
* Sinopoli et al.'s LMI bound: ``eps_c >= 1 - lambda_max`` with ``1 - lambda_max`` certified in
  a bracket below ``1/8`` (exact certificates on both sides); for a scalar measurement it is
  ``1/M(A)^2 = 1/16`` (Elia's threshold; Yang et al., Corollary 1), which the bracket must hold.

The example is reconstructed from the statement of the result (a second-order system with a
periodic eigenvalue ratio); the paper's own numbers were not available to compare.
"""

from __future__ import annotations

from typing import Any

import sympy as sp

from ..arguments import check_public
from ..capacity.quantities import mahler_measure
from ..model.system import Sensor, System
from ..reproduction import reproduction
from ..engine.stability import critical_loss_rate
from ..numeric.verify import number_json
from . import sinopoli
from .row import number

SOURCE = ("K. You, M. Fu, L. Xie, \"Mean square stability for Kalman filtering with Markovian packet losses\", "
          "Automatica 47(12), 2011: the critical rate strictly between the bounds of Sinopoli et al. (2004), "
          "lower bound and LMI (Theorem 5)")


def system() -> System:
    """``A = [[0, -4], [1, -2]]`` (``2 R(2 pi/3)`` up to similarity), ``C = [1 0]``."""
    return System(A=[[0, -4], [1, -2]], sensors=[Sensor(C=[[1, 0]], name="s1")], name="you-2011-counterexample")


def reproduce_you_2011_counterexample(outdir: str | None = None, steps: int = sinopoli.LMI_STEPS) -> dict[str, Any]:
    """The three values, exact or certified, and the checks (``outdir`` is unused: no figure)."""
    S = system()
    exact = critical_loss_rate(S)
    lower_arrival = number(1 / max(b.modulus for b in S.eigen_blocks()).exact ** 2)
    lo, hi, certificates = sinopoli.lmi_bracket(S, steps)
    elia = number(1 / mahler_measure(S.A).exact ** 2)
    period = S.eigen_blocks()[0].governing_period
    closed = number(sp.Integer(2) ** sp.Rational(-2 * period, period - 1))
    results = {"system": {"A": str(S.A.tolist()), "C": str(S.C.tolist())},
               "exact_critical_loss": number_json(exact),
               "sinopoli_necessary_bound": number_json(lower_arrival),
               "sinopoli_lmi_bracket": [str(lo), str(hi)], "lmi_certificates": list(certificates),
               "elia_scalar_threshold": number_json(elia), "governing_period": period}
    checks = {
        "eps_c = 1/8 exactly (Sui-You-Fu engine)": exact == number(sp.Rational(1, 8)),
        "eps_c = r^(-2p/(p-1)) with p = 3 (Mo-Sinopoli degenerate closed form)": exact == closed,
        "Sinopoli's necessary bound 1/rho(A)^2 = 1/4 lies strictly above eps_c": lower_arrival > exact,
        "the LMI threshold's certified bracket lies strictly below eps_c": number(hi) < exact,
        "the LMI bracket holds Elia's scalar threshold 1/M(A)^2 = 1/16": number(lo) <= elia <= number(hi),
        "eps_c strictly between Sinopoli's two bounds": number(hi) < exact < lower_arrival,
    }
    return reproduction("you-2011-counterexample", SOURCE, results, checks)


check_public(globals())

"""The four source papers' conditions as symkf implements them, read as rows of the atlas.

* Sui, You, Fu, "Stability of Kalman filtering with multiple sensors involving lossy
  communications": Theorem 12's closed form for second-order systems, as corrected in
  :mod:`symkf.engine.second_order` (governing period, rank-one congruent sets); exact.
* Quevedo, Ahlén, Johansson, "State estimation over sensor networks with correlated wireless
  fading channels": Theorem 1 (eq. 22), ``max_i nu_i ||A||^2 < 1`` with ``nu_i`` the
  probability that the received ``C(k)`` lacks full column rank (:mod:`symkf.network`).  The
  sensors are a star (each talks to the gateway); i.i.d. losses are a one-state network, a
  Gilbert-Elliott channel the two-state network with ``phi = (1, 0)``.  Sufficient.
  (Theorem 2 with ``psi = 1`` reduces to Theorem 1, Sec. VII-B.)
* Yang, Zheng, Ren, Yang, Shi, Shi, "Multi-sensor Kalman filtering with intermittent
  measurements": with ``d`` sensors at a common loss ``eps`` the capacity is
  ``-(d/2) ln eps``; Theorem 2 (``C > ln rho(A)`` necessary) gives ``eps_c <= rho(A)^(-2/d)``
  and Theorem 5's per-sensor test (sufficient) ``eps_c >= min_i max_j M(A_ij)^(-2)``
  (:mod:`symkf.capacity.compare`).
* The fusion paper (arXiv:2012.04896): Assumption 2, ``(1 - min_i lambda_i) rho(A)^2 < 1``,
  bounds the *fused* estimate of smart sensors that send local estimates; it is shown beside
  the exact set of the raw-measurement filter, not compared with it (another estimator).
"""

from __future__ import annotations

import sympy as sp

from ..arguments import check_public
from ..engine import second_order as sui
from ..capacity.compare import theorem5_common_threshold
from ..model.system import System
from ..network.conditions import theorem1
from ..network.dynamics import PeriodicDynamics
from ..network.loss import NetworkLoss
from ..network.state import MarkovNetworkState
from ..network.tree import SensorTree
from ..engine.region import stable_intervals
from ..exact.spectral import spectral_radius
from . import hypotheses as hyp
from .row import EXACT, NECESSARY, OTHER, SUFFICIENT, Hypothesis, Quantity, Row, number, row

SUI = ("T. Sui, K. You, M. Fu, \"Stability of Kalman filtering with multiple sensors involving lossy "
       "communications\"")
QUEVEDO = ("D. E. Quevedo, A. Ahlén, K. H. Johansson, \"State estimation over sensor networks with "
           "correlated wireless fading channels\"")
YANG = ("C. Yang, J. Zheng, X. Ren, W. Yang, H. Shi, L. Shi, \"Multi-sensor Kalman filtering with "
        "intermittent measurements\"")
FUSION = "Optimal linear sensor fusion over lossy channels with collective observability (arXiv:2012.04896)"

t = sp.Symbol("t", positive=True)


def sui_theorem12(system: System, quantity: Quantity) -> Row:
    """Theorem 12 (eq. 38) as corrected: the second-order closed form (exact)."""
    def value() -> tuple:
        v = sui.critical_loss_rate(system)
        return quantity.below(v), v
    return row("sui-theorem12", "Sui, You, Fu, Thm. 12 (corr.)", SUI,
               "eps_c = min(1, alpha^(-2g/(g d - J))) for second-order systems (corrected eq. 38)", EXACT,
               [hyp.iid(quantity)], quantity, value)


def _network(system: System, quantity: Quantity) -> NetworkLoss:
    tree = SensorTree([0] * system.d)
    if quantity.iid:
        return NetworkLoss(tree, MarkovNetworkState([[1]]), [[1 - t]] * system.d)
    f = quantity.fail[0]
    return NetworkLoss(tree, MarkovNetworkState([[1 - f, f], [t, 1 - t]]), [[1, 0]])


def quevedo_theorem1(system: System, quantity: Quantity) -> Row:
    """Theorem 1 (eq. 22) on the star network carrying the system's channels (sufficient)."""
    multi = Hypothesis("one sensor for a Gilbert-Elliott channel", quantity.iid or system.d == 1,
                       "" if quantity.iid or system.d == 1 else
                       f"{system.d} Gilbert-Elliott channels form a product network state, not built here")

    def value() -> tuple:
        th = theorem1(_network(system, quantity), PeriodicDynamics.from_system(system))
        stable = stable_intervals(list(dict.fromkeys(th.lhs.values())), t)
        ends = len(stable) == 1 and (stable[0][0] == 0 if quantity.iid else stable[0][1] == 1)
        return stable, (stable[0][1] if quantity.iid else stable[0][0]) if ends else None

    return row("quevedo-theorem1", "Quevedo et al., Thm. 1", QUEVEDO,
               "exponentially bounded if max_i nu_i ||A||^2 < 1, nu_i = P(C(k) not of full column rank | i)",
               SUFFICIENT, [multi], quantity, value)


def yang_theorem2(system: System, quantity: Quantity) -> Row:
    """Theorem 2: ``C > ln rho(A)`` is necessary: ``eps_c <= rho(A)^(-2/d)``."""
    v = sp.radsimp(spectral_radius(system.A).exact ** sp.Rational(-2, system.d))
    return row("yang-theorem2", "Yang et al., Thm. 2", YANG,
               "C > ln rho(A) necessary: eps_c <= rho(A)^(-2/d)", NECESSARY,
               [hyp.iid(quantity), hyp.unstable(system)], quantity, lambda: (quantity.below(v), number(v)))


def yang_theorem5(system: System, quantity: Quantity) -> Row:
    """Theorem 5's per-sensor test ``C_i > max_j h(A_ij)`` (sufficient), best row order."""
    def value() -> tuple:
        v = theorem5_common_threshold(system)
        return quantity.below(v), v
    return row("yang-theorem5", "Yang et al., Thm. 5", YANG,
               "C_i > max_j h(A_ij) for every sensor: eps_c >= min_i max_j M(A_ij)^(-2)", SUFFICIENT,
               [hyp.iid(quantity), hyp.unstable(system)], quantity, value)


def fusion_assumption2(system: System, quantity: Quantity) -> Row:
    """Assumption 2 at a common loss: ``eps rho(A)^2 < 1`` (another estimator: not compared); with
    ``rho(A) = 0`` (a nilpotent A) it holds at every loss rate."""
    rho = spectral_radius(system.A).exact
    v = sp.radsimp(1 / rho ** 2) if rho else sp.Integer(1)
    observable = system.observable
    return row("fusion-assumption2", "Fusion paper, Assumption 2", FUSION,
               "fused local estimates bounded if (1 - min lambda_i) rho(A)^2 < 1 (smart sensors)", OTHER,
               [hyp.iid(quantity), Hypothesis("Assumption 1: collective observability", observable,
                                              "" if observable else "(A, C) is not observable")],
               quantity, lambda: (quantity.below(v), number(v)),
               note="local estimates are sent, not measurements: a bound for another estimator")


ROWS = (sui_theorem12, quevedo_theorem1, yang_theorem2, yang_theorem5, fusion_assumption2)


check_public(globals())

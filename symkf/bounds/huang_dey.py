"""Huang, Dey, "Stability of Kalman filtering with Markovian packet losses", Automatica 43(4), 2007.

Huang and Dey introduce *peak-covariance stability* (the covariance sampled where a loss run
ends) for Gilbert-Elliott losses and give sufficient conditions for it.  Implemented here is
the one-step-observable case (``C`` of full column rank): the peak covariance is stable if
``(1 - q) rho(A)^2 < 1``, ``q = P(received | lost last)`` (symkf's ``recover``).  Peak-covariance
stability implies mean-square stability when ``A`` has no defective eigenvalue on the unit
circle (Wu, Shi, Anderson, Johansson, "Kalman filtering over Gilbert-Elliott channels:
stability conditions and critical curve", IEEE TAC 63(4), 2018), so the condition is read as
sufficient for the exact (mean-square) stable set.  Their conditions for general observable
pairs (through the observability index) are not implemented: their precise statement was not
available to check.
"""

from __future__ import annotations

from ..arguments import check_public
from ..model.system import System
from ..exact.spectral import spectral_radius
from . import hypotheses as hyp
from .row import SUFFICIENT, Quantity, Row, number, row

CITATION = ("M. Huang, S. Dey, \"Stability of Kalman filtering with Markovian packet losses\", "
            "Automatica 43(4), 2007")


def peak_covariance(system: System, quantity: Quantity) -> Row:
    """Sufficient: ``q > 1 - 1/rho(A)^2`` with ``C`` of full column rank."""
    rho = spectral_radius(system.A)
    v = 1 - 1 / rho.exact ** 2
    return row("huang-dey", "Huang, Dey 2007, peak cov.", CITATION,
               "peak covariance stable if (1 - q) rho(A)^2 < 1 (C of full column rank)", SUFFICIENT,
               [hyp.one_sensor(system), hyp.gilbert_elliott(quantity), hyp.unstable(system),
                hyp.one_step_observable(system), hyp.no_defective_unit_circle_eigenvalue(system)], quantity,
               lambda: (quantity.above(v), number(v)))


ROWS = (peak_covariance,)


check_public(globals())

"""Plarre, Bullo, "On Kalman filtering for detectable systems with intermittent observations",
IEEE TAC 54(2), 2009.

Statement (the paper's abstract): when the observation matrix restricted to the observable
subspace is invertible, Sinopoli et al.'s lower bound on the critical arrival probability is
the critical probability, i.e. ``eps_c = 1/rho(A)^2``.  "Restricted to the observable
subspace" is read in the observability decomposition ``C = [C_o, 0]``: ``C_o`` injective
(:func:`~symkf.bounds.hypotheses.invertible_on_observable_subspace`).
"""

from __future__ import annotations

from ..arguments import check_public
from ..model.system import System
from . import hypotheses as hyp
from .row import EXACT, Quantity, Row, row
from .sinopoli import inverse_rho_squared

CITATION = ("K. Plarre, F. Bullo, \"On Kalman filtering for detectable systems with intermittent "
            "observations\", IEEE Trans. Autom. Control 54(2), 2009")


def critical_value(system: System, quantity: Quantity) -> Row:
    """``eps_c = 1/rho(A)^2`` when ``C_o`` is invertible (one sensor, i.i.d.)."""
    return row("plarre-bullo", "Plarre, Bullo 2009", CITATION,
               "eps_c = 1/rho(A)^2 when C restricted to the observable subspace is invertible", EXACT,
               [hyp.one_sensor(system), hyp.iid(quantity), hyp.unstable(system), hyp.controllable_noise(system),
                hyp.detectable(system), hyp.invertible_on_observable_subspace(system)], quantity,
               inverse_rho_squared(system, quantity))


ROWS = (critical_value,)


check_public(globals())

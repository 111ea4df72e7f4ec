"""LQG control over lossy networks: the control side of Schenato, Sinopoli, Franceschetti, Poolla
and Sastry, "Foundations of control and estimation over lossy networks", Proc. IEEE 95(1), 2007.

:mod:`.threshold` (the critical control-packet arrival rate, exact or certified).
"""

from .threshold import ControlThreshold, Quotient, critical_arrival_rate, quotient_bound

__all__ = ["critical_arrival_rate", "ControlThreshold", "Quotient", "quotient_bound"]

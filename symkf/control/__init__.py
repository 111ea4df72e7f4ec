"""LQG control over lossy networks: the control side of Schenato, Sinopoli, Franceschetti, Poolla
and Sastry, "Foundations of control and estimation over lossy networks", Proc. IEEE 95(1), 2007.

:mod:`.threshold` (the critical control-packet arrival rate: exact closed forms, the quotient
bound, certified brackets), :mod:`.loop` (TCP-like: the region over observation and control
arrival rates and the loop's verdict under any sensor loss model), :mod:`.udp` (UDP-like: the
paper's results with their hypotheses checked).
"""

from .loop import LoopVerdict, TcpRegion, control_stabilizable, lqg_stable, tcp_region
from .threshold import ControlThreshold, Quotient, critical_arrival_rate, quotient_bound
from .udp import UdpRegion, UdpRow, udp_region, udp_threshold

__all__ = ["critical_arrival_rate", "ControlThreshold", "Quotient", "quotient_bound", "tcp_region", "TcpRegion",
           "lqg_stable", "LoopVerdict", "control_stabilizable", "udp_region", "UdpRegion", "UdpRow", "udp_threshold"]

"""From analysis to design: which sensors to install and how reliable their channels must be.

* :mod:`.constraints`: the requirement a design meets and the exact constraints that rule sets out;
* :mod:`.programmes`: the covering and linear programmes (HiGHS through SciPy, or pure Python);
* :mod:`.selection`: the cheapest sensor set, and the front of cost against the critical loss rate;
* :mod:`.allocation`: the cheapest i.i.d. channel qualities, certified by the engine, and per-sensor
  Gilbert-Elliott recovery rates (a certified coordinate-wise minimum);
* :mod:`.improvement`: the most valuable single-channel upgrade, and the active constraints in words.
"""

from .allocation import Allocation, RecoveryAllocation, allocate_channels, allocate_recovery
from .improvement import ActiveConstraint, ActiveConstraints, Upgrade, Upgrades, active_constraints, upgrades
from .selection import ParetoFront, ParetoPoint, Selection, SelectionCertificate, pareto_front, select_sensors

__all__ = ["upgrades", "Upgrades", "Upgrade", "active_constraints", "ActiveConstraint", "ActiveConstraints", "allocate_channels", "Allocation", "select_sensors", "Selection", "SelectionCertificate", "pareto_front", "ParetoFront", "ParetoPoint"]

"""Transmission capacity and MARE bounds (Yang et al.).

Modules: :mod:`.quantities` (capacities, Mahler measure, critical capacities),
:mod:`.lower` (m(X), G_k, Theorems 1-2, Remark 3), :mod:`.mare` (g_lambda, V_k,
Theorem 3), :mod:`.convergence` (Theorem 4, exact LMI certificates),
:mod:`.theorems` (Wonham decomposition, Theorems 5-7, Corollaries 1-2, Lemma 2),
:mod:`.compare` (capacity conditions against exact critical loss rates),
:mod:`.example1` (Example 1, Fig. 2).
"""

from .compare import comparison_table, critical_loss_comparison, verdict_comparison
from .convergence import LMIVerdict, mare_converges, mare_stabilizable, unit_circle_condition
from .example1 import reproduce_yang_example1
from .lower import (information_lower_bound_sequence, lower_bound_converges, lower_bound_limit, lower_bound_sequence,
                    theorem2)
from .mare import MARE, hadamard_weight
from .quantities import (critical_capacities, individual_capacities, mahler_measure, snr, spectral_radius,
                         topological_entropy, transmission_capacity)
from .theorems import (capacity_bounds_meet, corollary1_critical_capacity, single_sensor_rates,
                       theorem5_requirements, theorem5_sufficient, theorem6_allocation, theorem7_necessary,
                       wonham_decomposition)

__all__ = [
    "transmission_capacity", "individual_capacities", "snr", "mahler_measure", "topological_entropy",
    "spectral_radius", "critical_capacities",
    "lower_bound_sequence", "lower_bound_converges", "lower_bound_limit", "theorem2",
    "information_lower_bound_sequence",
    "MARE", "hadamard_weight", "mare_stabilizable", "mare_converges", "unit_circle_condition", "LMIVerdict",
    "wonham_decomposition", "theorem5_requirements", "theorem5_sufficient", "theorem6_allocation",
    "theorem7_necessary", "corollary1_critical_capacity", "capacity_bounds_meet", "single_sensor_rates",
    "critical_loss_comparison", "verdict_comparison", "comparison_table", "reproduce_yang_example1",
]

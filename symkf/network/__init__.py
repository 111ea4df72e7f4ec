"""Sensor-network trees over correlated fading channels (Quevedo, Ahlén, Johansson).

* :mod:`.tree`: the tree rooted at the gateway, paths, ``theta = prod gamma`` (Remark 2);
* :mod:`.state`: Markov (Assumption 1) and semi-Markov (Assumption 3) network states;
* :mod:`.fading`: ``phi_{m|j}`` from gain laws, policies and success functions (eqs. 7-10);
* :mod:`.loss`: :class:`NetworkLoss`, the induced loss process as a :class:`~symkf.model.loss.LossChain`;
* :mod:`.dynamics`: periodic ``A(k)``, ``C_m``, exact spectral norms;
* :mod:`.conditions`: ``J``, ``Pr{r = 1 | Xi}``, ``nu_i``, Theorem 1, Corollary 1;
* :mod:`.semi_markov`: ``O(k + t, k)``, ``varrho``, ``mu``, Theorem 2 (as printed and corrected);
* :mod:`.reproduce`: the paper's examples.
"""

from .conditions import (Theorem1, corollary1_lhs, full_rank_configurations, full_rank_probability,
                         full_rank_probability_of, is_up_set, nu, theorem1)
from .dynamics import PeriodicDynamics, spectral_norm_squared
from .fading import Nakagami, Rayleigh, Rician, SuccessProbability, UserGain, success_probability, threshold_success
from .loss import NetworkLoss, induced_loss, phi_symbol
from .semi_markov import (Theorem2, observability_matrix, rank_deficiency_probabilities,
                          rank_deficiency_probability_by_enumeration, theorem2)
from .state import MarkovNetworkState, SemiMarkovNetworkState
from .tree import SensorTree

__all__ = [
    "SensorTree", "MarkovNetworkState", "SemiMarkovNetworkState", "NetworkLoss", "phi_symbol",
    "Rayleigh", "Rician", "Nakagami", "UserGain", "SuccessProbability", "success_probability",
    "threshold_success", "PeriodicDynamics", "spectral_norm_squared",
    "full_rank_configurations", "full_rank_probability", "full_rank_probability_of", "is_up_set", "nu",
    "theorem1", "Theorem1",
    "corollary1_lhs", "observability_matrix", "rank_deficiency_probabilities",
    "rank_deficiency_probability_by_enumeration", "theorem2", "Theorem2", "induced_loss",
]


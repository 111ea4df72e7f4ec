"""Optimal linear sensor fusion over lossy channels with collective observability (arXiv:2012.04896).

Modules, in the order of the paper: :mod:`.decomposition` (Kalman
decomposition per sensor, Assumption 1), :mod:`.model` (the set-up,
Assumption 2), :mod:`.local_filters` (Lemmas 1-2), :mod:`.covariance`
(eqs. 17-20, corrected eq. 18), :mod:`.weights` (Problems 1-3, Theorem 2),
:mod:`.stability` (Proposition 1), :mod:`.remote` (the remote estimator),
:mod:`.pendulum` (Section 4).
"""

from ..errors import require_extra

require_extra("scipy", "fusion", "symkf.fusion (the local filters' Riccati and Lyapunov equations)")

from .covariance import expected_remote_covariance, fusion_sigma, remote_error_covariance, unbiasedness_matrix  # noqa: E402
from .local_filters import local_filters  # noqa: E402
from .model import FusionModel  # noqa: E402
from .pendulum import pendulum_model, reproduce_fusion_pendulum  # noqa: E402
from .remote import simulate_fusion  # noqa: E402
from .stability import proposition1_bound  # noqa: E402
from .weights import fused_covariance, optimal_weights  # noqa: E402

__all__ = ["FusionModel", "local_filters", "remote_error_covariance", "fusion_sigma", "unbiasedness_matrix",
           "expected_remote_covariance", "optimal_weights", "fused_covariance", "proposition1_bound",
           "simulate_fusion", "reproduce_fusion_pendulum", "pendulum_model"]


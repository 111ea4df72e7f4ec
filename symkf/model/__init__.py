"""The model layer: what a system and a loss process *are*, as exact data.

:class:`~symkf.model.system.System` and :class:`~symkf.model.system.Sensor` hold ``A``, ``Q``,
``P0`` and the sensors' ``C``, ``R``; a loss model (one module each) holds its factors, chain,
capabilities, symbols, words and file form. Nothing here calls the engine or reads a file: the
codec (:mod:`symkf.model.codec`) turns tables already read into models and back.
"""

from .gilbert_elliott import GilbertElliott
from .iid import IID
from .independent import Independent
from .loss import Factor, LossChain, LossModel, checked
from .markov import MarkovLoss
from .system import Sensor, System

__all__ = ["System", "Sensor", "LossModel", "LossChain", "Factor", "IID", "GilbertElliott", "MarkovLoss", "Independent",
           "checked"]

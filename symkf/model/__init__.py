"""The model layer: what a system and a loss process *are*, as exact data.

:class:`~symkf.model.system.System`, :class:`~symkf.model.system.Sensor` and
:class:`~symkf.model.system.Actuator` hold ``A``, ``Q``, ``P0``, the sensors' ``C``, ``R`` and the
actuators' ``B``, ``U`` with the LQG weight ``W``; a loss model (one module each) holds its factors, chain,
capabilities, symbols, words and file form. Nothing here calls the engine or reads a file: the
codec (:mod:`symkf.model.codec`) turns tables already read into models and back.
"""

from .gilbert_elliott import GilbertElliott
from .iid import IID
from .independent import Independent
from .loss import Factor, LossChain, LossModel, checked
from .markov import MarkovLoss
from .system import Actuator, Sensor, System

__all__ = ["System", "Sensor", "Actuator", "LossModel", "LossChain", "Factor", "IID", "GilbertElliott", "MarkovLoss", "Independent",
           "checked"]

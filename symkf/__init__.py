"""symkf: exact, certified stability of multi-sensor Kalman filtering over lossy networks."""

from .errors import SymkfError
from .losses import IID, GilbertElliott, MarkovLoss
from .model import Sensor, System

__all__ = ["SymkfError", "System", "Sensor", "IID", "GilbertElliott", "MarkovLoss"]
__version__ = "0.1.0"

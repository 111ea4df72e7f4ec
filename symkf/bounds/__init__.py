"""The field's results side by side: every published bound and closed form for the critical loss
rate, beside the exact value, for any system (:func:`bounds`).

One module per source: :mod:`.sinopoli` (Sinopoli et al. 2004: the lower bound, C invertible, the LMI of Theorem 5),
:mod:`.plarre_bullo` (2009), :mod:`.mo_sinopoli` (2012), :mod:`.you_fu_xie` (2011),
:mod:`.huang_dey` (2007), :mod:`.sources` (the four papers symkf implements);
:mod:`.row` (a row and its exact comparison), :mod:`.hypotheses` (exact hypothesis checks),
:mod:`.atlas` (the rows together: text, JSON, LaTeX), :mod:`.figure` (bounds against a
parameter), :mod:`.counterexample` (You et al.'s counterexample, ``symkf reproduce``).
"""

from .atlas import RESULTS, Atlas, bounds, quantity
from .row import Hypothesis, Quantity, Row

__all__ = ["bounds", "Atlas", "Row", "Quantity", "Hypothesis", "RESULTS", "quantity"]

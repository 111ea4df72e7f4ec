"""Floats: the filter in square-root form and its compiled kernels, receptions drawn per
factor of a loss model, Monte Carlo with importance sampling, and theory against simulation.
Nothing above the engine is imported here."""

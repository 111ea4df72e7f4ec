"""Floats: the filter in square-root form and its compiled kernels, receptions drawn per
factor of a loss model, Monte Carlo with importance sampling, theory against simulation, and the
convex programmes (cvxpy) whose answers the layers above certify.
Nothing above the engine is imported here."""

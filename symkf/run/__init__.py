"""How work runs: serially, in processes or on a Dask scheduler, with progress bars. Knows no
Kalman word, so every layer may hand it work."""

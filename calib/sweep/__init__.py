"""One resumable, keyed runner for sweeps of independent FE runs (local processes or Dask)."""

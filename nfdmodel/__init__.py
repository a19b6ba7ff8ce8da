"""Runtime elastoplastic normal contact laws for DEM (Vu-Quoc & Zhang 1999). numpy/scipy only."""

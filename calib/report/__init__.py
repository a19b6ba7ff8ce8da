"""Result folders: the calibration (parameter file, CSVs, plots, VTU) and the collision report."""

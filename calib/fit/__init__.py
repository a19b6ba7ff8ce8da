"""Stage 2b, the fit: FE load paths -> Ca, Kc of the runtime law (least squares, the calibration
recipe, ``calibrate``), and the master table of the dimensionless constants."""

"""Stage 2b, the fit: FE load paths -> Ca, Kc of the runtime law (least squares, the calibration
recipe, ``calibrate``), the master table of the dimensionless constants, and the law fitted to
measurements (``measured``, ``nfdcal fit-data``). calib/fit/README.md lists the modules."""

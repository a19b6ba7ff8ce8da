"""Prediction bands of a vz law fitted to measurements (``nfdcal fit-data --plot``).

The fitted law's e(v_in) [-] and its standard error by the delta method (Bates & Watts 1988,
Nonlinear Regression Analysis and Its Applications, section 2.3),

    var e(v_in) = g^T Cov(log theta) g,   g = d e / d log theta,

a band e +- z se for the parameters' uncertainty (z = 1.96: 95 %), not for the scatter of single
tests. Cov(log theta): calib.fit.measured.regression.
"""
from __future__ import annotations

import numpy as np

from calib.fit.master_table import MasterTable
from calib.fit.measured.regression import FitResult, sensitivities, spec_bounds
from calib.fit.measured.specimen import Specimen, law_parameters, predict_impacts


def restitution_band(result: FitResult, v_in, specimen: Specimen, table: MasterTable | None,
                     z: float = 1.96) -> tuple[np.ndarray, np.ndarray]:
    """e(v_in) of the fitted law and its standard error by the delta method,
    var e = g^T Cov(log theta) g, g = d e / d log theta (forward differences); the band is
    e +- z se (z = 1.96: 95 % for the parameters' uncertainty, not the scatter of single tests)."""
    spec = result.spec
    centre = np.log([result.values[name] for name in spec.free])
    upper = spec_bounds(spec, specimen, table)[1]

    def restitution(log_theta):
        return predict_impacts(law_parameters(specimen, spec.values(log_theta), table), v_in)["e"]

    e = restitution(centre)
    gradient = sensitivities(restitution, centre, upper)
    se = np.sqrt(np.maximum(np.einsum("ij,jk,ik->i", gradient, result.covariance_log, gradient), 0.0))
    return e, z * se

"""Stage 2a, the finite-element solve: a sphere pressed on a rigid frictionless flat, axisymmetric.

Public names (import them from ``calib.fe``; the modules behind them are internals):
``ContactSolver`` (load steps: force or displacement control, exact active-set contact, Newton),
``ContactState`` / ``StepResult`` / ``StepNotConverged``, ``run_load_path``; the materials
``ElasticMaterial`` and ``VonMisesMaterial`` (radial return); ``LoadPathPlan`` and
``run_load_paths`` (shared loading branch, unloading paths).
"""
from calib.fe.elastic import ElasticMaterial
from calib.fe.recovery import contact_radius_from_gap, contact_radius_from_pressure
from calib.fe.solver import ContactSolver
from calib.fe.state import ContactState, StepNotConverged, StepRecord, StepResult
from calib.fe.von_mises import VonMisesMaterial, von_mises_stress
from calib.fe.loadpath import (LoadPathPlan, LoadPathResults, PathResult, advance, plastic_zone,
                              run_load_path, run_load_paths)

__all__ = ["ContactSolver", "ContactState", "StepNotConverged", "StepRecord", "StepResult",
           "contact_radius_from_gap", "contact_radius_from_pressure", "run_load_path",
           "ElasticMaterial", "VonMisesMaterial", "von_mises_stress", "LoadPathPlan",
           "LoadPathResults", "PathResult", "advance", "plastic_zone", "run_load_paths"]

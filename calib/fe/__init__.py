"""Stage 2, the finite-element solve: a sphere pressed on a rigid frictionless flat, axisymmetric.

Modules, in the order the solve uses them: ``axisym`` (strain with the hoop term, the 2 pi r
weight), ``material`` (the Material protocol, isotropic elastic constants), ``elastic`` and
``von_mises`` (the materials; radial return), ``forms`` (weak forms), ``dofs`` (rigid-plate
tie, contact candidates), ``state`` (states and step records), ``active_set``, ``newton``,
``rescue``, ``recovery`` (pressure, contact edge), ``linsolve`` (sparse direct solvers),
``solver`` (ContactSolver: one load step), ``loadpath`` (load paths with unloading). The impact of
the whole sphere: ``sphere_dofs`` (the free sphere's unknowns, its mass with a massless contact
boundary), ``newmark`` (ImpactSolver: one time step), ``impact`` (run_impact: first touch to free
flight).
Import the public names from ``calib.fe``.
"""
from calib.fe.elastic import ElasticMaterial
from calib.fe.impact import ImpactNotConverged, ImpactResult, run_impact
from calib.fe.loadpath import (LoadPathPlan, LoadPathResults, PathResult, advance, plastic_zone, run_load_path,
                               run_load_paths)
from calib.fe.material import Material, elastic_matrix, lame_constants
from calib.fe.newmark import ImpactSolver
from calib.fe.recovery import contact_radius_from_gap, contact_radius_from_pressure
from calib.fe.solver import ContactSolver
from calib.fe.state import ContactState, StepNotConverged, StepRecord, StepResult
from calib.fe.von_mises import VonMisesMaterial, von_mises_stress

__all__ = ["ContactSolver", "ContactState", "StepNotConverged", "StepRecord", "StepResult",
           "contact_radius_from_gap", "contact_radius_from_pressure", "run_load_path",
           "ElasticMaterial", "Material", "elastic_matrix", "lame_constants", "VonMisesMaterial",
           "von_mises_stress", "LoadPathPlan", "LoadPathResults", "PathResult", "advance", "plastic_zone", "run_load_paths",
           "ImpactSolver", "ImpactResult", "ImpactNotConverged", "run_impact"]

"""Stage 2, the finite-element solve: axisymmetric contact of a sphere, one core for four configurations.

The core: ``constraint`` (the contact constraint: the rigid flat, a deformable counter-body's dual
mortar gap of ``contact_pair``), ``contact_loop`` (the one active-set loop, ``active_set`` and
``newton`` inside), the steppers ``quasi_static`` (force or displacement control, ``rescue``) and
``newmark`` (Newmark's average acceleration), ``kinematics`` (small strain; the one place the
material is evaluated: ``axisym``, ``element_arrays``, ``forms``), the materials (``material``: the
protocol, ``elastic``, ``von_mises``, ``flow_curve``, ``rate_law``), ``linsolve`` (sparse direct solves, the factorisation cache),
``recovery`` (pressure, contact radius), ``state`` (states and step records). The configurations:
``solver`` (ContactSolver, the press; ``dofs``), ``two_body`` (TwoBodySolver, the pair press;
``condensation``), ``newmark`` (ImpactSolver, the impact; ``sphere_dofs``), ``impact_pair``
(PairImpactSolver, the pair impact; ``impact_pair_mesh``). The runs: ``loadpath`` (load paths
with unloading), ``impact`` (the impact time loop, the sphere's record), ``impact_pair_run`` (the
pair's record).
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
from calib.fe.flow_curve import (FlowCurve, LinearHardening, LudwikHardening, SwiftHardening, TabulatedFlowCurve,
                                  read_flow_curve)
from calib.fe.rate_law import CowperSymondsRate, JohnsonCookRate
from calib.fe.von_mises import HardeningMaterial, RateDependentMaterial, VonMisesMaterial, von_mises_stress

__all__ = ["ContactSolver", "ContactState", "StepNotConverged", "StepRecord", "StepResult",
           "contact_radius_from_gap", "contact_radius_from_pressure", "run_load_path",
           "ElasticMaterial", "Material", "elastic_matrix", "lame_constants", "VonMisesMaterial",
           "von_mises_stress", "HardeningMaterial", "FlowCurve", "LinearHardening", "SwiftHardening", "LudwikHardening",
           "TabulatedFlowCurve", "read_flow_curve", "JohnsonCookRate", "CowperSymondsRate",
           "RateDependentMaterial", "LoadPathPlan", "LoadPathResults", "PathResult", "advance", "plastic_zone", "run_load_paths",
           "ImpactSolver", "ImpactResult", "ImpactNotConverged", "run_impact"]

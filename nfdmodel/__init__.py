"""Runtime elastoplastic normal contact laws for DEM (Vu-Quoc & Zhang 1999). numpy/scipy only.

    from nfdmodel import (Material, ContactPair, yield_factor, VZParams, get_law, LAWS,
                          load_parameters, collide)

Force laws are pure vectorised functions ``(delta, state, params) -> (P, new_state)``
(one module per law: :mod:`nfdmodel.hertz`, :mod:`nfdmodel.vz`, :mod:`nfdmodel.thornton`,
:mod:`nfdmodel.walton_braun`; by name through :mod:`nfdmodel.registry`), also available as ``law.step(delta, state, params) -> (P, update)``
(a sparse :class:`HistoryUpdate`: only the contacts whose turning point moved) plus
``law.commit(state, update)`` (in place, for a caller that owns its history);
:func:`collide` simulates sphere-on-flat impacts (:mod:`nfdmodel.collision`); :class:`Friction` and
:func:`contact_step` add damping, friction, rolling and twisting resistance around a law
(:mod:`nfdmodel.friction`), :func:`oblique_collide` oblique impacts with spin (:mod:`nfdmodel.oblique`);
SI units throughout.
"""
from . import reference_case
from .collision import (CollisionHistory, CollisionReference, CollisionResult, TimeStepWarning, collide,
                        collide_repeated, collision_reference)
from .friction import Contact, ContactForces, Friction, FrictionState, contact_step, shear_coefficient
from .hertz import hertz_force, hertz_step
from .history import HertzState, HistoryUpdate, TurningPointHistory
from .materials import ContactPair, Material, yield_factor
from .native import backend, backend_info
from .oblique import ObliqueResult, oblique_collide
from .parameter_file import load_parameters, parameter_record
from .registry import LAWS, PYTHON_LAWS, ContactDetails, ContactLaw, get_law
from .thornton import ThorntonState, thornton_force, thornton_step
from .unlike import VZConstants, sphere_sphere_params, sphere_wall_params
from .validation import PlausibilityWarning, check_real
from .vz import VZParams, VZState, vz_force, vz_force_with_iterations, vz_newton_iterations, vz_step
from .vz_curve import NEWTON_MAX_ITERATIONS, NEWTON_TOLERANCE, vz_plastic_force
from .vz_table import VZTableParams, VZTableState, vz_table_force, vz_table_step
from .vz_unload import VZUnloadParams, VZUnloadState, vz_unload_force, vz_unload_step
from .walton_braun import WaltonBraunParams, WaltonBraunState, walton_braun_force, walton_braun_step
from .window import CalibrationWindow, RangeWarning

__all__ = [
    "Material", "ContactPair", "yield_factor", "VZParams", "WaltonBraunParams", "get_law", "LAWS",
    "ContactLaw", "ContactDetails", "HertzState", "TurningPointHistory", "VZState", "ThorntonState",
    "WaltonBraunState", "HistoryUpdate", "hertz_force", "vz_force", "vz_force_with_iterations",
    "vz_newton_iterations", "vz_plastic_force", "thornton_force", "walton_braun_force", "hertz_step",
    "vz_step", "thornton_step", "walton_braun_step", "NEWTON_TOLERANCE", "NEWTON_MAX_ITERATIONS",
    "check_real", "PlausibilityWarning", "reference_case",
    "load_parameters", "parameter_record", "collide", "collide_repeated", "collision_reference", "CollisionResult",
    "CollisionReference", "CollisionHistory", "TimeStepWarning", "CalibrationWindow", "RangeWarning",
    "VZTableParams", "VZTableState", "vz_table_force", "vz_table_step", "backend", "backend_info",
    "PYTHON_LAWS", "VZUnloadParams", "VZUnloadState", "vz_unload_force", "vz_unload_step",
    "Friction", "FrictionState", "Contact", "ContactForces", "contact_step", "shear_coefficient", "oblique_collide",
    "ObliqueResult", "VZConstants", "sphere_sphere_params", "sphere_wall_params",
]

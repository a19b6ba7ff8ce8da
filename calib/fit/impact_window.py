"""A calibration window chosen from the impacts the user will simulate (``--v-max``).

The constants hold on the loads they were fitted on (nfdmodel.window), so the load paths must
reach the largest force the DEM impacts produce. That force depends on the constants: for a
sphere of mass m* hitting a rigid flat at v_max, the energy balance of the law,

    (1/2) m* v_max^2 = W(delta_max) = integral_0^delta_max P(delta) d delta,

gives P_max (nfdmodel.collision_reference). So: estimate P_max with the best constants at hand
(the master table at (nu, E/sigma_Y), else the paper's Ca_hat, Kc_hat), calibrate on load paths
to P_top = MARGIN x that estimate (peaks at 1/3, 2/3 and 1 of it, the default recipe's
proportions), re-estimate with the new constants, and repeat until the window covers the impact
(at most MAX_ROUNDS FE calibrations; one or two in practice).

The FE bounds the window: P <= 1000 P_Y and contact radius <= 0.3 R (calib.fit.recipe). An
impact beyond that is refused before any meshing, naming the largest v_in this FE can vouch for
(the velocity whose impact reaches that load with the estimating constants).
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import Callable

from calib.fit import recipe
from calib.fit.calibration import CalibrationResult, calibrate
from calib.fit.master_table import MasterTable
from nfdmodel import ContactPair, Material, RangeWarning, VZParams, VZTableParams, collision_reference, get_law

MARGIN = 1.1            # load paths reach 10 % beyond the estimated P_max of the fastest impact
MAX_ROUNDS = 3          # FE calibrations at most
PEAK_FRACTIONS = (1.0 / 3.0, 2.0 / 3.0, 1.0)


@dataclass(frozen=True)
class ImpactWindow:
    """The outcome: the calibration whose window covers v_max, every round's P_top [N] and the
    P_max [N] its constants predict for v_max."""
    result: CalibrationResult
    v_max: float
    rounds: tuple[dict, ...]


def estimating_constants(material: Material, radius: float) -> tuple[VZParams, str]:
    """(VZParams, source): the master table's constants at (nu, E/sigma_Y), else the paper's."""
    pair = ContactPair.sphere_flat(material, radius)
    try:
        values = MasterTable.load().parameters(material.E, material.nu, material.sigma_y, radius, material.rho)
        return VZParams.from_dimensionless(pair, values["Ca_hat"], values["Kc_hat"]), "master table"
    except (ValueError, OSError):       # outside the table (or none shipped): the paper's constants
        reference = VZParams.reference()
        return VZParams.from_dimensionless(pair, reference.Ca_hat, reference.Kc_hat), "the paper's constants"


def _law_of(params) -> str:
    return "vz-table" if isinstance(params, VZTableParams) else "vz"


def impact_force(params, v_in: float) -> float:
    """P_max [N] of a sphere-on-flat impact at v_in [m/s] with the law ``params`` (VZParams or
    VZTableParams; energy balance)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RangeWarning)    # estimating beyond the window is the point
        return float(collision_reference(_law_of(params), params, [v_in]).P_max[0])


def reach_velocity(params, load: float) -> float:
    """The v_in [m/s] whose impact reaches ``load`` [N] with ``params`` (VZParams or
    VZTableParams): sqrt(2 W / m*), W the law's loading work to ``load``."""
    law = get_law(_law_of(params))
    delta = float(params.loading_approach(load))
    work = float(law.loading_work([delta], [load], params)[0])
    return math.sqrt(2.0 * work / params.pair.mass_star)


def check_reach(material: Material, radius: float, v_max: float) -> tuple[float, VZParams, str]:
    """(estimated P_max [N] of the impact at v_max, estimating constants, their source); a
    ValueError before any FE when the FE cannot reach it, naming the largest v_in it can vouch for."""
    params, source = estimating_constants(material, radius)
    pair = params.pair
    reach = min(recipe.MAX_LOAD_OVER_YIELD * pair.P_Y, recipe.largest_admissible_load(pair))
    try:
        needed = impact_force(params, v_max)
    except ValueError:                  # beyond the law's own domain: certainly beyond the FE's
        needed = math.inf
    if MARGIN * needed < recipe.MIN_WINDOW_OVER_P_Y * pair.P_Y:     # nothing plastic to fit
        v_least = reach_velocity(params, recipe.MIN_WINDOW_OVER_P_Y * pair.P_Y / MARGIN)
        raise ValueError(f"v_max out of range: an impact at {v_max:g} m/s reaches only about {needed / pair.P_Y:.3g} P_Y "
                         f"({source}); a calibration needs loads beyond {recipe.MIN_WINDOW_OVER_P_Y:g} P_Y: need v_max >= "
                         f"{v_least:.4g} m/s ({v_least / pair.v_Y:.4g} v_Y) for this material and R")
    if MARGIN * needed > reach:
        v_reach = reach_velocity(params, reach / MARGIN)
        reached = (f"reaches about {needed / pair.P_Y:.4g} P_Y" if math.isfinite(needed) else
                   "drives the law beyond its domain (contact radius above R*)")
        raise ValueError(f"v_max out of range: an impact at {v_max:g} m/s {reached} ({source}); this FE vouches for loads up to {reach / pair.P_Y:.4g} P_Y "
                         f"(P <= {recipe.MAX_LOAD_OVER_YIELD:g} P_Y and contact radius <= {recipe.CONTACT_RADIUS_LIMIT:g} R), "
                         f"i.e. v_in <= {v_reach:.4g} m/s ({v_reach / pair.v_Y:.4g} v_Y) for this material and R")
    return needed, params, source


def calibrate_for_impacts(material: Material, radius: float, v_max: float, *,
                          progress: Callable[[str], None] | None = None, ship: str = "radius",
                          unload: bool = True, **spec_options) -> ImpactWindow:
    """Calibrate until the window covers the impact at v_max [m/s] (module doc). ``spec_options``
    go to calib.fit.recipe.calibration_spec (mesh level or contact size, steps); ``unload``
    False: loading branches only (the radius fit)."""
    say = progress or (lambda message: None)
    needed, _, source = check_reach(material, radius, v_max)
    rounds = []
    pair = ContactPair.sphere_flat(material, radius)
    reach = min(recipe.MAX_LOAD_OVER_YIELD * pair.P_Y, recipe.largest_admissible_load(pair))
    for round_number in range(1, MAX_ROUNDS + 1):
        top = min(max(MARGIN * needed, recipe.MIN_WINDOW_OVER_P_Y * pair.P_Y), reach)   # never narrower than a fit needs
        say(f"window round {round_number}: v_max = {v_max:g} m/s needs about {needed / pair.P_Y:.4g} P_Y "
            f"({source}); load paths to {top / pair.P_Y:.4g} P_Y")
        spec = recipe.calibration_spec(material, radius, peaks=tuple(f * top for f in PEAK_FRACTIONS),
                                       **spec_options)
        result = calibrate(spec, progress=progress, ship=ship, unload=unload)
        shipped = result.shipped_params
        needed = impact_force(shipped, v_max)
        source = f"round {round_number} constants"
        covered = needed <= shipped.window_force * (1.0 + 1e-9)
        rounds.append({"round": round_number, "P_top": top, "P_top_over_P_Y": top / pair.P_Y,
                       "P_max_of_v_max": needed, "P_max_of_v_max_over_P_Y": needed / pair.P_Y,
                       "covered": covered})
        if covered:
            return ImpactWindow(result, v_max, tuple(rounds))
        if needed * MARGIN > reach * (1.0 + 1e-9) and top >= reach:
            break
    raise ValueError(f"v_max out of range: after {len(rounds)} calibration(s) the impact at {v_max:g} m/s still "
                     f"reaches {needed / pair.P_Y:.4g} P_Y, beyond the window ({rounds[-1]['P_top_over_P_Y']:.4g} P_Y); "
                     f"this FE vouches for loads up to {reach / pair.P_Y:.4g} P_Y")

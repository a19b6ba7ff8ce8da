"""A calibration window chosen from the impacts the user will simulate (``--v-max``).

The constants hold on the loads they were fitted on (nfdmodel.window), so the load paths must
reach the largest force the DEM impacts produce. That force depends on the constants: for a
sphere hitting a rigid flat, or an elastic counter-body, at v_max (the pair's m*, E*, R*:
calib.fit.recipe.contact_pair), the energy balance of the law,

    (1/2) m* v_max^2 = W(delta_max) = integral_0^delta_max P(delta) d delta,

gives P_max (nfdmodel.collision_reference). So: estimate P_max with the best constants at hand
(the master table at (nu, E/sigma_Y), else the paper's Ca_hat, Kc_hat), calibrate on load paths
to P_top = MARGIN x that estimate, re-estimate with the new constants, and repeat until the
window covers the impact (at most MAX_ROUNDS FE calibrations; one or two in practice).

The impacts below v_max load the contact anywhere from P_Y to P_top, and the vz-table law
(calib.fit.table_fit) takes its curvature factor C_R from the FE's unloading paths: so the
unloading peaks are log-spaced over the whole window,

    P_k = P_low (P_top / P_low)^(k / n),  k = 0 .. n,  n = ceil(PATHS_PER_DECADE log10(P_top / P_low)),

from P_low = LOWEST_PEAK_OVER_P_Y x P_Y, or higher where the calibration mesh (sized for P_top)
does not resolve the contact there (:func:`lowest_peak`), and the loading branch is stepped
geometrically (LOADING_STEPS_PER_DECADE increments per decade of load,
:class:`GeometricLoadPathPlan`), so every decade of the window has loading points and unloading
paths alike. The table's declared window starts at the lowest unloading peak (table_fit), the
load below which its C_R was not measured. The between-node error of the shipped law against FE
paths that did not build it is measured by calib.studies.between_nodes
(results/calibration/between_nodes.*).

The FE bounds the window (calib.fit.recipe.fe_reach): small strain P <= 1000 P_Y and contact radius
<= 0.2 R, finite strain P <= 1e4 P_Y and contact radius <= 0.45 R (its mesh ladder's error estimate:
recipe.REACH_ERROR). An impact beyond that is refused before any meshing, naming the largest v_in this
FE can vouch for (the velocity whose impact reaches that load with the estimating constants).
"""
from __future__ import annotations

import dataclasses
import math
import warnings
from dataclasses import dataclass
from typing import Callable

import numpy as np
from scipy.optimize import brentq

from calib.fe.kinematics import DEFAULT_KINEMATICS
from calib.fe.loadpath import LoadPathPlan
from calib.fit import recipe
from calib.fit.calibration import CalibrationResult, calibrate
from calib.fit.master_table import MasterTable
from nfdmodel import ContactPair, Material, RangeWarning, VZParams, collision_reference, get_law
from nfdmodel.parameter_file import law_of
from nfdmodel.validation import bound_text

MARGIN = 1.1            # load paths reach 10 % beyond the estimated P_max of the fastest impact
MAX_ROUNDS = 3          # FE calibrations at most
# the lowest unloading path [P_Y], on a mesh that resolves it: just past first yield, so a calibrated
# window starts there (the shipped master table's nodes start at calib.fit.vz_master_build's own)
LOWEST_PEAK_OVER_P_Y = 1.1
# ... and no lower than where the contact spans this many contact elements (estimated radius):
# on the mesh of a 1000 P_Y window (the reference sphere, 3.1e-4 m) the FE's approach at 1.5-8
# P_Y (1.6-2.8 elements) scatters by 3-5 % about the converged one, its e by ~1 % and its
# plastic radius vanishes at 1.5 P_Y; from 3 elements (10 P_Y) the approach is within 1 %
CONTACT_ELEMENTS_AT_LOWEST = 3.0
# Below COARSE_LOWEST_OVER_P_Y P_Y the dissipation of a path is a few % of its work (e > 0.97), and the FE's
# unloading resolves it only on a finer mesh: a path from 1.41 P_Y whose contact spans 3.3 elements (the
# reference sphere on contact elements 1.6e-4 m) returns more work than Hertz's (C_R 0.986 < 1). So a lowest
# path below it needs CONTACT_ELEMENTS_NEAR_YIELD elements across its contact (the --v-max graded mesh's
# GRADED_ELEMENTS_PER_CONTACT_RADIUS), else the window starts at COARSE_LOWEST_OVER_P_Y P_Y as on a coarse mesh.
COARSE_LOWEST_OVER_P_Y = 2.0
CONTACT_ELEMENTS_NEAR_YIELD = 12.0
PATHS_PER_DECADE = 2.5          # unloading paths per decade of load, at least
LOADING_STEPS_PER_DECADE = 16   # loading increments per decade of load
# The graded mesh of ``nfdcal calibrate --v-max`` (window_spec's elements_per_contact_radius): every contact
# radius from LOWEST_PEAK_OVER_P_Y P_Y to the top spans this many elements, the master table's node mesh
# (calib/scenes/builtin/sweeps/vz_master_grid.toml: 25 x 0.714, its force 0.25 % from the refined levels'),
# so the window's lowest path is resolved as well as its top.
GRADED_ELEMENTS_PER_CONTACT_RADIUS = 17.9


@dataclass(frozen=True)
class GeometricLoadPathPlan(LoadPathPlan):
    """A LoadPathPlan whose loading increments grow with the load: each load at most
    ``loading_ratio`` times the one before (and at most ``loading_step`` above it), every peak hit
    exactly, so a window of decades is sampled evenly in log P."""
    loading_ratio: float = 10.0 ** (1.0 / LOADING_STEPS_PER_DECADE)

    def __post_init__(self):
        super().__post_init__()
        if not (np.isfinite(self.loading_ratio) and self.loading_ratio > 1.0):
            raise ValueError(f"loading_ratio must be a finite number > 1, got {self.loading_ratio}")

    def loading_targets(self) -> list[float]:
        targets = [self.first_load if self.first_load is not None else min(self.loading_step, self.peaks[0])]
        for peak in self.peaks:
            last = targets[-1]
            n = max(1, math.ceil(math.log(peak / last) / math.log(self.loading_ratio) - 1e-9))
            while peak * (1.0 - (last / peak) ** (1.0 / n)) > self.loading_step * (1.0 + 1e-9):
                n += 1
            targets.extend(np.geomspace(last, peak, n + 1)[1:].tolist())
        return targets


def lowest_peak(pair: ContactPair, contact_size: float, lowest_over_P_Y: float = LOWEST_PEAK_OVER_P_Y,
                contact_radius: Callable[[ContactPair, float], float] = recipe.estimated_contact_radius) -> float:
    """The lowest unloading peak [N] on a mesh of contact element ``contact_size`` [m]:
    ``lowest_over_P_Y`` (LOWEST_PEAK_OVER_P_Y) x P_Y where the contact spans CONTACT_ELEMENTS_NEAR_YIELD
    elements there (or ``lowest_over_P_Y`` >= COARSE_LOWEST_OVER_P_Y), else COARSE_LOWEST_OVER_P_Y x P_Y;
    higher where the contact first spans CONTACT_ELEMENTS_AT_LOWEST elements. The contact radius
    ``contact_radius`` (pair, P) -> a [m] is the one the mesh is sized by (recipe.sizing_radius of the
    plan's kinematics): recipe.estimated_contact_radius (the default) for small strain and a counter-body,
    recipe.fe_contact_radius for finite strain on the rigid flat, 0.80-0.86 of the estimate at 1.1-8 P_Y,
    so the FE's contact at the lowest path spans the elements these thresholds ask for."""
    low = lowest_over_P_Y * pair.P_Y
    if lowest_over_P_Y < COARSE_LOWEST_OVER_P_Y and \
            contact_radius(pair, low) < CONTACT_ELEMENTS_NEAR_YIELD * contact_size * (1 - 1e-9):
        low = COARSE_LOWEST_OVER_P_Y * pair.P_Y       # near yield the mesh does not resolve the dissipation
    need = CONTACT_ELEMENTS_AT_LOWEST * contact_size
    if contact_radius(pair, low) >= need:
        return low
    high = 2.0 * low
    while contact_radius(pair, high) < need:
        high *= 2.0
    return float(brentq(lambda P: contact_radius(pair, P) - need, low, high, rtol=1e-9))


def window_peaks(low: float, top: float) -> tuple[float, ...]:
    """The unloading peaks [N] of a window from ``low`` to ``top`` [N]: log-spaced,
    PATHS_PER_DECADE per decade at least (module doc); the top alone when ``low`` >= ``top``."""
    if not low < top:
        return (float(top),)
    n = max(1, math.ceil(PATHS_PER_DECADE * math.log10(top / low) - 1e-9))
    return tuple(float(p) for p in np.geomspace(low, top, n + 1))


def with_unloading_across(spec: recipe.CalibrationSpec) -> recipe.CalibrationSpec:
    """``spec`` with unloading paths added below its lowest peak, from the lowest load its mesh
    resolves (:func:`lowest_peak`, log-spaced as :func:`window_peaks`), each moved to the
    nearest load its loading branch already steps to: the loading points, and with them the radius
    fit's Ca and Kc, are those of ``spec``'s own paths; the vz-table law's window reaches down to
    near P_Y (its C_R is measured only at unloading peaks, calib.fit.table_fit)."""
    plan = spec.plan
    targets = np.array(plan.loading_targets())
    wanted = window_peaks(lowest_peak(spec.pair, spec.mesh.contact_size,
                                      contact_radius=recipe.sizing_radius(spec.kinematics, spec.counter)),
                          plan.peaks[0])
    candidates = targets[(targets > spec.pair.P_Y) & (targets < plan.peaks[0] * (1 - 1e-9))]
    if not candidates.size:
        return spec
    added = {float(candidates[np.argmin(np.abs(np.log(candidates / p)))]) for p in wanted[:-1]}
    extended = dataclasses.replace(plan, peaks=tuple(sorted(added | set(plan.peaks))))
    if len(extended.loading_targets()) != targets.size or not np.allclose(extended.loading_targets(), targets,
                                                                          rtol=1e-12, atol=0.0):
        return spec                     # a plan whose steps the added peaks would move: its own paths only
    return dataclasses.replace(spec, plan=extended)


def window_spec(material: Material, radius: float, top: float, *, loading_steps: int | None = None,
                loading_steps_per_decade: float | None = None, elements_per_contact_radius: float | None = None,
                lowest_over_P_Y: float = LOWEST_PEAK_OVER_P_Y, **spec_options) -> recipe.CalibrationSpec:
    """The CalibrationSpec of a window to ``top`` [N]: the recipe's mesh for it, unloading paths at
    :func:`window_peaks` from :func:`lowest_peak` up, the loading branch stepped geometrically
    (LOADING_STEPS_PER_DECADE per decade, or ``loading_steps_per_decade``, or ``loading_steps``
    increments from the first load to the top); ``spec_options``: the mesh and unloading options of
    calib.fit.recipe.calibration_spec. ``elements_per_contact_radius`` N: the graded mesh on which
    the contact at every load from ``lowest_over_P_Y`` (LOWEST_PEAK_OVER_P_Y) x P_Y up spans N elements
    (recipe.mesh_for), so the window starts there."""
    if elements_per_contact_radius is not None:
        counter = spec_options.get("counter")
        pair = recipe.contact_pair(material, radius, counter)
        spec_options.update(elements_per_contact_radius=elements_per_contact_radius,
                            graded_from=recipe.sizing_radius(spec_options.get("kinematics", DEFAULT_KINEMATICS),
                                                             counter)(pair, min(lowest_over_P_Y * pair.P_Y, top)))
    spec = recipe.calibration_spec(material, radius, peaks=(top,), loading_steps=1, **spec_options)
    plan = spec.plan
    if loading_steps is not None:
        ratio = (top / plan.first_load) ** (1.0 / loading_steps)
    else:
        ratio = 10.0 ** (1.0 / (loading_steps_per_decade or LOADING_STEPS_PER_DECADE))
    peaks = window_peaks(lowest_peak(spec.pair, spec.mesh.contact_size, lowest_over_P_Y,
                                     recipe.sizing_radius(spec.kinematics, spec.counter)), top)
    return dataclasses.replace(spec, plan=GeometricLoadPathPlan(
        peaks=peaks, loading_step=top, unloading_steps=plan.unloading_steps,
        first_load=min(plan.first_load, peaks[0]), loading_ratio=ratio))


def window_top(pair: ContactPair, needed: float, kinematics: str = DEFAULT_KINEMATICS, counter=None) -> float:
    """The top [N] of the load paths for an impact reaching ``needed`` [N]: MARGIN beyond it,
    never narrower than a fit needs (recipe.MIN_WINDOW_OVER_P_Y), never beyond the reach of the FE
    in ``kinematics`` (on ``counter``: recipe.reach_kinematics)."""
    return min(max(MARGIN * needed, recipe.MIN_WINDOW_OVER_P_Y * pair.P_Y),
               recipe.fe_reach(pair, recipe.reach_kinematics(kinematics, counter)))


def impact_spec(material: Material, radius: float, needed: float, kinematics: str = DEFAULT_KINEMATICS,
                **spec_options) -> recipe.CalibrationSpec:
    """The CalibrationSpec of a calibration round for an impact reaching ``needed`` [N]:
    :func:`window_spec` to :func:`window_top`, in ``kinematics`` (``spec_options`` as there, ``counter``
    among them: the pair's)."""
    counter = spec_options.get("counter")
    return window_spec(material, radius, window_top(recipe.contact_pair(material, radius, counter), needed, kinematics,
                                                    counter), kinematics=kinematics, **spec_options)


@dataclass(frozen=True)
class ImpactWindow:
    """The outcome: the calibration whose window covers v_max, every round's P_top [N] and the
    P_max [N] its constants predict for v_max."""
    result: CalibrationResult
    v_max: float
    rounds: tuple[dict, ...]


def estimating_constants(material: Material, radius: float, counter=None, hardening=None) -> tuple[VZParams, str]:
    """(VZParams, source): the master table's constants at (nu, E/sigma_Y), else the paper's, on the
    pair's scales (the rigid flat, or ``counter``'s pair: E*, R*, m*). A hardening sphere (``hardening``, a
    calib.fe.flow_curve curve) on the rigid flat, inside the vz master table's hardening sheet: that sheet's
    vz-table law (calib.fit.vz_hardening; a VZTableParams; a curve other than linear read through its secant
    modulus); outside the sheet: the perfectly plastic constants (a softer estimate: the rounds of
    :func:`calibrate_for_impacts` widen the window)."""
    pair = recipe.contact_pair(material, radius, counter)
    if counter is None and hardening is not None and getattr(hardening, "H", 1.0) > 0.0:
        # only a hardening sphere reads the sheet (and the master table beside it)
        from calib.fit.vz_hardening import HardenedMasterTable, HardeningSheet
        from calib.fit.vz_master_table import VZMasterTable

        try:
            law = HardenedMasterTable(VZMasterTable.load(), HardeningSheet.load(),
                                      hardening.H / material.E if hasattr(hardening, "H") else hardening)
            return law.law(material, radius), "the vz master table's hardening sheet"
        except (ValueError, OSError):   # outside the sheet: the perfectly plastic estimate below
            pass
    try:
        values = MasterTable.load().parameters(material.E, material.nu, material.sigma_y, radius, material.rho)
        return VZParams.from_dimensionless(pair, values["Ca_hat"], values["Kc_hat"]), "master table"
    except (ValueError, OSError):       # outside the table (or none shipped): the paper's constants
        reference = VZParams.reference()
        return VZParams.from_dimensionless(pair, reference.Ca_hat, reference.Kc_hat), "the paper's constants"


def _law_of(params) -> str:
    return law_of(params)


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


# the share of the estimating law's full-contact load a suggested v_max may reach (the impact's P_max is estimated
# by that law, whose contact radius must stay below R*)
FULL_CONTACT_SHARE = 0.99


def estimable(params: VZParams, load: float) -> float:
    """``load`` [N], or less where the estimating law's contact radius passes R* (VZParams.full_contact_load, its
    linear plastic radius; FULL_CONTACT_SHARE of it): the largest load whose impact that law can estimate."""
    return min(load, FULL_CONTACT_SHARE * params.full_contact_load)


def check_reach(material: Material, radius: float, v_max: float,
                kinematics: str = DEFAULT_KINEMATICS, counter=None, hardening=None) -> tuple[float, VZParams, str]:
    """(estimated P_max [N] of the impact at v_max, estimating constants, their source); a
    ValueError before any FE when the FE in ``kinematics`` (on ``counter``: recipe.reach_kinematics)
    cannot reach it, naming the largest v_in it can vouch for (and, in small strain on the rigid
    flat, the finite strain's). ``hardening``: the sphere's flow curve (:func:`estimating_constants`)."""
    params, source = estimating_constants(material, radius, counter, hardening)
    pair = params.pair
    kinematics = recipe.reach_kinematics(kinematics, counter)
    reach = recipe.fe_reach(pair, kinematics)
    try:
        needed = impact_force(params, v_max)
    except ValueError:                  # beyond the law's own domain: certainly beyond the FE's
        needed = math.inf
    if MARGIN * needed < recipe.MIN_WINDOW_OVER_P_Y * pair.P_Y:     # nothing plastic to fit
        v_least = reach_velocity(params, recipe.MIN_WINDOW_OVER_P_Y * pair.P_Y / MARGIN)
        raise ValueError(f"v_max out of range: an impact at {v_max:g} m/s reaches only about {needed / pair.P_Y:.3g} P_Y "
                         f"({source}); a calibration needs loads beyond {recipe.MIN_WINDOW_OVER_P_Y:g} P_Y: need v_max >= "
                         f"{bound_text(v_least, '>=')} m/s ({v_least / pair.v_Y:.4g} v_Y) for this material and R")
    if MARGIN * needed > reach:
        v_reach = reach_velocity(params, estimable(params, reach / MARGIN))
        reached = (f"reaches about {needed / pair.P_Y:.4g} P_Y, its load paths {MARGIN - 1:.0%} beyond, "
                   f"{MARGIN * needed / pair.P_Y:.4g} P_Y" if math.isfinite(needed) else
                   "drives the law beyond its domain (contact radius above R*)")
        wider = ""
        if kinematics == DEFAULT_KINEMATICS and counter is None:
            v_finite = reach_velocity(params, estimable(params, recipe.fe_reach(pair, "finite-strain") / MARGIN))
            wider = f"; --kinematics finite vouches for v_max <= {bound_text(v_finite, '<=')} m/s"
        raise ValueError(f"v_max out of range: an impact at {v_max:g} m/s {reached} ({source}); this FE vouches for loads up to {reach / pair.P_Y:.4g} P_Y "
                         f"({recipe.reach_text(kinematics)}{'; on a counter-body its contact is small-strain' if counter else ''}), "
                         f"i.e. need v_max <= {bound_text(v_reach, '<=')} m/s ({v_reach / pair.v_Y:.4g} v_Y) for this material and R"
                         f"{wider}")
    return needed, params, source


def calibrate_for_impacts(material: Material, radius: float, v_max: float, *,
                          progress: Callable[[str], None] | None = None, ship: str = "radius",
                          unload: bool = True, meshes: int = 2, kinematics: str = DEFAULT_KINEMATICS,
                          hardening=None, **spec_options) -> ImpactWindow:
    """Calibrate until the window covers the impact at v_max [m/s] (module doc) with the FE in
    ``kinematics``. ``spec_options`` go to :func:`window_spec` (mesh level or contact size, steps);
    ``unload`` False: loading branches only (the radius fit); ``meshes``: as
    calib.fit.calibration.calibrate; ``hardening``: the sphere's flow curve (calib.fe.flow_curve; None:
    perfectly plastic), each round's FE and the first estimate (:func:`estimating_constants`) take it."""
    say = progress or (lambda message: None)
    counter = spec_options.get("counter")
    needed, _, source = check_reach(material, radius, v_max, kinematics, counter, hardening)
    rounds = []
    pair = recipe.contact_pair(material, radius, counter)
    reach = recipe.fe_reach(pair, recipe.reach_kinematics(kinematics, counter))
    for round_number in range(1, MAX_ROUNDS + 1):
        spec = impact_spec(material, radius, needed, kinematics, **spec_options)
        if hardening is not None:
            spec = dataclasses.replace(spec, hardening=hardening)
        top = spec.plan.peaks[-1]
        say(f"window round {round_number}: v_max = {v_max:g} m/s needs about {needed / pair.P_Y:.4g} P_Y "
            f"({source}); {len(spec.plan.peaks)} load paths from {spec.plan.peaks[0] / pair.P_Y:.4g} to "
            f"{top / pair.P_Y:.4g} P_Y")
        result = calibrate(spec, progress=progress, ship=ship, unload=unload, meshes=meshes)
        shipped = result.shipped_params
        needed = impact_force(shipped, v_max)
        source = f"round {round_number} constants"
        covered = needed <= shipped.window_force * (1.0 + 1e-9)
        rounds.append({"round": round_number, "P_top": top, "P_top_over_P_Y": top / pair.P_Y,
                       "unloading_peaks_over_P_Y": [p / pair.P_Y for p in spec.plan.peaks],
                       "P_max_of_v_max": needed, "P_max_of_v_max_over_P_Y": needed / pair.P_Y,
                       "covered": covered})
        if covered:
            return ImpactWindow(result, v_max, tuple(rounds))
        if needed * MARGIN > reach * (1.0 + 1e-9) and top >= reach:
            break
    raise ValueError(f"v_max out of range: after {len(rounds)} calibration(s) the impact at {v_max:g} m/s still "
                     f"reaches {needed / pair.P_Y:.4g} P_Y, beyond the window ({rounds[-1]['P_top_over_P_Y']:.4g} P_Y); "
                     f"this FE vouches for loads up to {reach / pair.P_Y:.4g} P_Y")

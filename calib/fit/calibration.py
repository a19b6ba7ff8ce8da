"""The calibration: FE load paths of a sphere on a rigid flat -> Ca, Kc of the runtime NFD law.

Vu-Quoc & Zhang (1999), sections 2-3 (SPEC sections 3, 6, 7):
  1. mesh the hemisphere (meshes.hemisphere), solve the elastic-perfectly plastic von Mises
     contact problem (calib.fe + calib.fe.von_mises) along force-driven load paths with unloading
     (calib.fe.loadpath);
  2. decompose the FE contact radius a_ep = a_e + a_p and fit Ca (a_p = Ca <P - P_Y>) and Kc
     (C_R = a_ep^2 / (R alpha) = 1 + Kc <P - P_Y>) by least squares (calib.fit);
  3. also fit (Ca, Kc) to the FE force-approach curves through the runtime law itself
     (nfdmodel vz), i.e. what a DEM code feels;
  4. drive nfdmodel's vz, thornton and hertz laws along the FE approach histories and compare.
The parameter file written from the result is read by ``nfdmodel.load_parameters``, so the
shipped runtime law is exactly the calibrated one.
"""
from __future__ import annotations

import time
from dataclasses import asdict, dataclass, field
from typing import Callable

import numpy as np

from calib.fit.least_squares import (ForceLawFit, RadiusLawData, RadiusLawFit, fit_force_law, fit_radius_law,
                       radius_law_data, relative_force_residuals, window_study)
from calib.fe.loadpath import LoadPathPlan, LoadPathResults, run_load_paths
from meshes.hemisphere import HemisphereMeshSpec
from nfdmodel import ContactPair, Material, VZParams, get_law

PAPER = {"Ca": 2.33e-7, "Kc": 2.69e-4, "alpha_max_1500": 1.56e-5, "e_1500": 0.737}

# E / sigma_Y a calibration accepts. Below 20 the yield contact itself is wide (a_Y/R =
# (pi/2) A_Y sigma_Y / E* > 0.12, SPEC section 2) and a small-strain, small-contact model is
# meaningless; an E typed in GPa with sigma_Y in Pa lands there. Above 1e4 the contact zone is
# below 1e-5 R wide and the mesh grading has not been tested.
E_OVER_SIGMA_Y_RANGE = (20.0, 1.0e4)
# The largest contact radius a calibration may reach, over R: beyond it the hemisphere is no
# longer a small-strain, a << R contact problem (Hertz needs a << R; at 0.3 R the contact
# edge has turned by 17 degrees).
CONTACT_RADIUS_LIMIT = 0.3
# The largest load a calibration runs to, over P_Y (issue 6 asks for 1000). Measured
# (results/stability/fe_stability.csv): the force-driven FE loads and unloads to 1000 P_Y at
# E/sigma_Y = 700 and 5000 (ContactSolver.rescue_step takes the steps the ordinary solve cannot);
# softer materials are limited first by CONTACT_RADIUS_LIMIT. Beyond ~400 P_Y the contact is
# fully plastic (P grows with the contact area, Johnson 1985 sec. 6.3) and a_p = Ca <P - P_Y>
# (paper eq. 2.5) is an extrapolation: fit such runs knowingly. The runtime law itself takes any
# P / P_Y (nfdmodel).
MAX_LOAD_OVER_YIELD = 1000.0
# Ca_hat used to ESTIMATE the plastic radius before the calibration (the reference's is 0.0258,
# the master table's span 0.024-0.028).
CA_HAT_ESTIMATE = 0.025


def estimated_contact_radius(pair: ContactPair, force) -> float:
    """Largest contact radius [m] expected at the force P [N] on the loading branch, before any
    FE run (sizes the refined mesh zone): Hertz's a_H below P_Y; above it
    max(1.3 a_H, a_H + Ca_hat <P/P_Y - 1> a_Y), the first the elastoplastic/Hertz radius ratio
    measured up to 41 P_Y (the reference FE: 1.47 / 1.135 mm at 1500 N), the second the
    plastic radius a_p = Ca <P - P_Y> (paper eq. 2.5) that dominates from ~43 P_Y on."""
    a_hertz = float(pair.hertz_radius(force))
    if force <= pair.P_Y:
        return a_hertz
    return max(1.3 * a_hertz, a_hertz + CA_HAT_ESTIMATE * (force / pair.P_Y - 1.0) * pair.a_Y)


def largest_admissible_load(pair: ContactPair) -> float:
    """The largest P_max [N] whose estimated contact radius stays within CONTACT_RADIUS_LIMIT R."""
    from scipy.optimize import brentq

    limit = CONTACT_RADIUS_LIMIT * pair.R_star
    if estimated_contact_radius(pair, pair.P_Y) >= limit:
        return 0.0
    hi = 2.0 * pair.P_Y
    while estimated_contact_radius(pair, hi) < limit:
        hi *= 2.0
    return float(brentq(lambda P: estimated_contact_radius(pair, P) - limit, pair.P_Y, hi, rtol=1e-6))


def check_calibration_inputs(material: Material, radius: float, largest_peak: float) -> None:
    """ValueError naming the parameter and its allowed range when a calibration cannot be
    meaningful: E / sigma_Y outside E_OVER_SIGMA_Y_RANGE, or a largest load P_max whose contact
    radius would exceed CONTACT_RADIUS_LIMIT R (small strain, a << R)."""
    ratio = material.E / material.sigma_y
    low, high = E_OVER_SIGMA_Y_RANGE
    if not low <= ratio <= high:
        hint = " (are E and sigma_Y both in Pa?)" if ratio < 1.0 or ratio > 1e6 else ""
        raise ValueError(f"E/sigma_Y out of range for a calibration: need {low:g} <= E/sigma_Y <= "
                         f"{high:g}, got {ratio:.3g} (E = {material.E:g} Pa, sigma_Y = "
                         f"{material.sigma_y:g} Pa){hint}")
    pair = ContactPair.sphere_flat(material, radius)
    if largest_peak > MAX_LOAD_OVER_YIELD * pair.P_Y:
        raise ValueError(f"P_max out of range: the largest load {largest_peak:.4g} N is "
                         f"{largest_peak / pair.P_Y:.4g} P_Y; the FE calibration runs to P_max <= "
                         f"{MAX_LOAD_OVER_YIELD:g} P_Y = {MAX_LOAD_OVER_YIELD * pair.P_Y:.4g} N for this "
                         f"material and R (tested to there; the NFD model's linear plastic radius is "
                         f"meant for the contained elastoplastic regime, below ~400 P_Y)")
    a_max = estimated_contact_radius(pair, largest_peak)
    if a_max > CONTACT_RADIUS_LIMIT * radius:
        P_limit = largest_admissible_load(pair)
        raise ValueError(f"P_max out of range: the largest load {largest_peak:.4g} N "
                         f"({largest_peak / pair.P_Y:.4g} P_Y) needs a contact radius of about "
                         f"{a_max / radius:.3g} R; the small-strain model needs a_max <= "
                         f"{CONTACT_RADIUS_LIMIT:g} R, i.e. P_max <= {P_limit:.4g} N "
                         f"({P_limit / pair.P_Y:.4g} P_Y) for this material and R")


@dataclass(frozen=True)
class CalibrationSpec:
    """What to calibrate: material, sphere radius R [m], mesh, load paths, Newton tolerance."""

    material: Material
    radius: float
    mesh: HemisphereMeshSpec
    plan: LoadPathPlan
    residual_tolerance: float = 1e-8
    contact_radius_method: str = "gap"

    def __post_init__(self):
        if not (np.isfinite(self.radius) and self.radius > 0):
            raise ValueError(f"radius R must be a finite length > 0 [m], got {self.radius}")
        if not np.isclose(self.mesh.radius, self.radius, rtol=1e-12):
            raise ValueError(f"mesh radius {self.mesh.radius} differs from the sphere radius R = {self.radius}")
        check_calibration_inputs(self.material, self.radius, self.plan.peaks[-1])
        a_max = estimated_contact_radius(self.pair, self.plan.peaks[-1])
        if self.mesh.refined_radius < 0.99 * a_max:   # a contact wider than the fine zone
            raise ValueError(f"mesh refined_radius {self.mesh.refined_radius:.4g} m is smaller than the "
                             f"estimated contact radius {a_max:.4g} m at P_max = {self.plan.peaks[-1]:.4g} N:"
                             f" need refined_radius >= {a_max:.4g} m (calibration.spec_for sizes it)")

    @property
    def pair(self) -> ContactPair:
        return ContactPair.sphere_flat(self.material, self.radius)


def reference_spec(contact_size: float | None = None) -> CalibrationSpec:
    """The paper's case: aluminium R = 0.1 m, E = 70 GPa, nu = 0.3, sigma_Y = 100 MPa,
    rho = 2699 kg/m^3; paths ABC, ADE, AFG (P_max = 500, 1000, 1500 N)."""
    mesh = HemisphereMeshSpec() if contact_size is None else HemisphereMeshSpec(contact_size=contact_size)
    return CalibrationSpec(material=Material.reference(), radius=0.1, mesh=mesh,
                           plan=LoadPathPlan(peaks=(500.0, 1000.0, 1500.0), loading_step=500.0 / 16,
                                             unloading_steps=16, first_load=20.0))


def spec_for(material: Material, radius: float, peaks_over_yield=(13.7, 27.4, 41.2),
             contact_size_over_a_max: float = 1.0 / 37.0, peaks=None) -> CalibrationSpec:
    """A calibration of any material scaled from the reference case: peaks as multiples of P_Y
    (the reference's 500/1000/1500 N are 13.7, 27.4, 41.2 P_Y), or ``peaks`` in N, and a mesh
    scaled by the largest contact radius, so that the discretisation error is the reference one."""
    pair = ContactPair.sphere_flat(material, radius)
    if peaks is None:
        peaks = tuple(float(k * pair.P_Y) for k in peaks_over_yield)
    peaks = tuple(sorted(float(p) for p in peaks))
    check_calibration_inputs(material, radius, peaks[-1])   # before sizing a mesh from it
    a_max = estimated_contact_radius(pair, peaks[-1])
    h = a_max * contact_size_over_a_max
    mesh = HemisphereMeshSpec(radius=radius, contact_size=h, refined_radius=1.1 * a_max,
                              refined_depth=0.35 * a_max, far_size=radius / 10)
    return CalibrationSpec(material=material, radius=radius, mesh=mesh,
                           plan=LoadPathPlan(peaks=peaks, loading_step=peaks[0] / 16,
                                             unloading_steps=16, first_load=min(0.5 * pair.P_Y, peaks[0])))


def first_yield_load(hemisphere, material: Material) -> float:
    """Force [N] at which the first quadrature point reaches the von Mises yield stress, from the
    elastic FE solution: its peak stress scales as P^(1/3) (Hertz, Johnson 1985 eq. 4.23), so two
    fixed-point updates P <- P (sigma_Y / q_max)^3 from the theoretical P_Y converge."""
    from calib.fe import ContactSolver
    from calib.fe.elastic import ElasticMaterial
    from calib.fe.von_mises import von_mises_stress

    solver = ContactSolver(hemisphere, ElasticMaterial(material.E, material.nu))
    pair = ContactPair.sphere_flat(material, hemisphere.radius)
    load = pair.P_Y
    for _ in range(3):
        result = solver.solve_force(solver.initial_state(), load)
        if not result.converged:
            raise RuntimeError(f"elastic first-yield solve at P = {load:g} N: {result.message}")
        q_max = float(von_mises_stress(solver.stress(result.state)).max())
        load *= (material.sigma_y / q_max) ** 3
    return float(load)


@dataclass
class ModelComparison:
    """A runtime law driven along one FE path's approach history."""

    law: str
    force: np.ndarray        # P [N] at the FE approaches
    restitution: float       # e = sqrt(elastic energy / (elastic + dissipated)) at the peak
    max_force_error: float   # max |P_law - P_FE| / P_max over the path


@dataclass
class CalibrationResult:
    spec: CalibrationSpec
    P_Y: float
    P_Y_fe: float
    load_paths: LoadPathResults
    radius_data: RadiusLawData
    radius_fit: RadiusLawFit
    window: list[dict]
    force_fit: ForceLawFit
    shipped: str                       # which fit the parameter file ships ("radius" or "force")
    comparisons: dict = field(repr=False)   # peak -> list[ModelComparison]
    mesh_info: dict = field(default_factory=dict)
    wall_time_s: float = 0.0
    timings: dict = field(default_factory=dict)
    solver: object = field(default=None, repr=False)  # the FE solver (for VTU output)
    radius_fit_force_error: dict = field(default_factory=dict)  # the force-fit metric, for the radius fit

    @property
    def params(self) -> VZParams:
        """The shipped runtime parameters."""
        if self.shipped == "force":
            return VZParams(self.spec.pair, self.force_fit.Ca, self.force_fit.Kc)
        return VZParams(self.spec.pair, self.radius_fit.Ca.slope, self.radius_fit.Kc.slope)


def drive_law(law_name: str, params, approach: np.ndarray) -> tuple[np.ndarray, float]:
    """Forces [N] of a runtime law along an approach history [m] (one contact), and its
    restitution at the largest approach: e^2 = elastic / (elastic + dissipated) energy there."""
    law = get_law(law_name)
    state = law.initial_state(1)
    forces = np.empty(approach.size)
    e = 1.0
    peak_index = int(np.argmax(approach))
    for k, delta in enumerate(approach):
        details = law.contact_state(np.array([delta]), state, params)
        state = details.state
        forces[k] = details.force[0]
        if k == peak_index:
            stored = float(details.elastic_energy[0] + details.dissipated_energy[0])
            e = float(np.sqrt(details.elastic_energy[0] / stored)) if stored > 0 else 1.0
    return forces, e


def _path_history(path) -> tuple[np.ndarray, np.ndarray]:
    approach = np.array([r["alpha"] for r in path.rows])
    force = np.array([max(r["P"], 0.0) for r in path.rows])
    return approach, force


def calibrate(spec: CalibrationSpec, progress: Callable[[str], None] | None = None,
              ship: str = "radius") -> CalibrationResult:
    """Run the FE load paths of ``spec`` and fit the NFD parameters (see module docstring)."""
    from calib.fe import ContactSolver
    from calib.fe.von_mises import VonMisesMaterial
    from meshes.hemisphere import hemisphere_mesh

    if ship not in ("radius", "force"):
        raise ValueError(f"ship must be 'radius' or 'force', got {ship!r}")
    say = progress or (lambda message: None)
    t0 = time.perf_counter()
    hemisphere = hemisphere_mesh(spec.mesh)
    t_mesh = time.perf_counter() - t0
    pair = spec.pair
    material = spec.material

    t1 = time.perf_counter()
    P_Y_fe = first_yield_load(hemisphere, material)
    t_yield = time.perf_counter() - t1
    say(f"first yield: P_Y(FE) = {P_Y_fe:.4g} N, theory {pair.P_Y:.4g} N")

    solver = ContactSolver(hemisphere, VonMisesMaterial(material.E, material.nu, material.sigma_y),
                           residual_tolerance=spec.residual_tolerance,
                           contact_radius_method=spec.contact_radius_method)
    paths = run_load_paths(solver, spec.plan, progress=say)

    loading = paths.loading_rows
    data = radius_law_data([r["P"] for r in loading], [r["alpha"] for r in loading],
                           [r["contact_radius"] for r in loading],
                           R_star=pair.R_star, E_star=pair.E_star, P_Y=pair.P_Y)
    radius_fit = fit_radius_law(data)
    window = window_study(data)

    histories = [_path_history(p) for p in paths.paths]

    def predict_force(approach, Ca, Kc):
        return drive_law("vz", VZParams(pair, Ca, Kc), approach)[0]

    force_floor = 0.05 * spec.plan.peaks[0]
    force_fit = fit_force_law(predict_force, histories, radius_fit.Ca.slope, radius_fit.Kc.slope,
                              force_floor=force_floor)
    radius_fit_force_error = relative_force_residuals(predict_force, histories, radius_fit.Ca.slope,
                                                      radius_fit.Kc.slope, force_floor)
    result = CalibrationResult(spec=spec, P_Y=pair.P_Y, P_Y_fe=P_Y_fe, load_paths=paths,
                               radius_data=data, radius_fit=radius_fit, window=window,
                               force_fit=force_fit, shipped=ship, comparisons={}, solver=solver,
                               radius_fit_force_error={
                                   "rms_relative_force_error": float(np.sqrt(np.mean(radius_fit_force_error**2))),
                                   "max_relative_force_error": float(np.abs(radius_fit_force_error).max())},
                               mesh_info={**spec.mesh.describe(), "elements": int(hemisphere.mesh.nelements),
                                          "dofs": int(solver.n_dofs)})
    for path, (approach, force) in zip(paths.paths, histories):
        comparisons = []
        other_fit = "force" if ship == "radius" else "radius"
        other_params = (VZParams(pair, force_fit.Ca, force_fit.Kc) if other_fit == "force"
                        else VZParams(pair, radius_fit.Ca.slope, radius_fit.Kc.slope))
        for label, law_name, params in (("vz", "vz", result.params),
                                        (f"vz ({other_fit} fit)", "vz", other_params),
                                        ("thornton", "thornton", pair), ("hertz", "hertz", pair)):
            law_force, e = drive_law(law_name, params, approach)
            comparisons.append(ModelComparison(label, law_force, e,
                                               float(np.abs(law_force - force).max() / path.peak)))
        result.comparisons[path.peak] = comparisons
    result.wall_time_s = time.perf_counter() - t0
    result.timings = {"mesh_s": t_mesh, "first_yield_s": t_yield, "load_paths_s": paths.wall_time_s,
                      "factorizations": paths.factorizations,
                      "fit_s": result.wall_time_s - t_mesh - t_yield - paths.wall_time_s}
    return result


def summary(result: CalibrationResult) -> dict:
    """The ``nfdcal calibrate --json`` object (SI units)."""
    params = result.params
    return {
        "Ca": params.Ca, "Kc": params.Kc, "Ca_hat": params.Ca_hat, "Kc_hat": params.Kc_hat,
        "P_Y": result.P_Y, "P_Y_fe": result.P_Y_fe,
        "P_Y_fe_rel_error": result.P_Y_fe / result.P_Y - 1.0,
        "shipped_fit": result.shipped,
        "radius_fit": {"Ca": result.radius_fit.Ca.slope, "Ca_se": result.radius_fit.Ca.standard_error,
                       "Ca_r2": result.radius_fit.Ca.r_squared, "Kc": result.radius_fit.Kc.slope,
                       "Kc_se": result.radius_fit.Kc.standard_error, "Kc_r2": result.radius_fit.Kc.r_squared,
                       "n_points": result.radius_fit.Ca.n_points, **result.radius_fit_force_error},
        "force_fit": asdict(result.force_fit),
        "wall_time_s": result.wall_time_s,
        "timings": result.timings,
        "mesh": result.mesh_info,
        "paths": [{"P_max": p.peak, "alpha_max": p.alpha_max, "e": p.restitution,
                   "alpha_residual": p.alpha_residual,
                   "P_max_reached": max(r["P"] for r in p.rows),
                   "steps": len(p.rows),
                   "models": {c.law: {"e": c.restitution, "max_force_error_rel": c.max_force_error}
                              for c in result.comparisons[p.peak]}}
                  for p in result.load_paths.paths],
    }

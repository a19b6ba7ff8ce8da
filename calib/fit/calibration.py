"""The calibration: FE load paths of a sphere on a rigid flat -> Ca, Kc of the runtime NFD law.

Vu-Quoc & Zhang (1999), sections 2-3 (README, The model: The NFD law on loading; The FE problem):
  1. mesh the hemisphere (meshes.hemisphere), solve the elastic-perfectly plastic von Mises
     contact problem (calib.fe + calib.fe.von_mises) along force-driven load paths with unloading
     (calib.fe.loadpath);
  2. decompose the FE contact radius a_ep = a_e + a_p and fit Ca (a_p = Ca <P - P_Y>) and Kc
     (C_R = a_ep^2 / (R alpha) = 1 + Kc <P - P_Y>) by least squares (calib.fit);
  3. also fit (Ca, Kc) to the FE force-approach curves through the runtime law itself
     (nfdmodel vz), i.e. what a DEM code feels;
  4. fit the vz-table law's tables (calib.fit.table_fit) to the FE loading curve and the work
     each unloading returned: the law for windows beyond two constants;
  5. drive nfdmodel's vz, vz-table, thornton and hertz laws along the FE approach histories and
     compare.
The parameter file written from the result is read by ``nfdmodel.load_parameters``, so the
shipped runtime law is exactly the calibrated one.
"""
from __future__ import annotations

import time
import warnings
from dataclasses import asdict, dataclass, field
from functools import cached_property
from typing import Callable

import numpy as np

from calib.fe import ContactSolver
from calib.fe.elastic import ElasticMaterial
from calib.fe.loadpath import LoadPathResults, run_load_paths
from calib.fe.von_mises import VonMisesMaterial, von_mises_stress
from calib.fit.least_squares import (ForceLawFit, RadiusLawData, RadiusLawFit, fit_force_law, fit_radius_law,
                                     radius_law_data, relative_force_residuals, window_study)
from calib.fit.recipe import CalibrationSpec, check_fittable
from calib.fit.table_fit import fit_tables
from calib.output import git_commit
from meshes.hemisphere import hemisphere_mesh
from nfdmodel import CalibrationWindow, ContactPair, Material, RangeWarning, VZParams, VZTableParams, get_law


def first_yield_load(hemisphere, material: Material) -> float:
    """Force [N] at which the first quadrature point reaches the von Mises yield stress, from the
    elastic FE solution: its peak stress scales as P^(1/3) (Hertz, Johnson 1985 eq. 4.23), so two
    fixed-point updates P <- P (sigma_Y / q_max)^3 from the theoretical P_Y converge."""

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
    force_fit: ForceLawFit | None     # None for a loading-only calibration
    shipped: str                       # which fit the parameter file ships (SHIPPABLE)
    comparisons: dict = field(repr=False)   # peak -> list[ModelComparison]
    mesh_info: dict = field(default_factory=dict)
    wall_time_s: float = 0.0
    timings: dict = field(default_factory=dict)
    solver: object = field(default=None, repr=False)  # the FE solver (for VTU output)
    radius_fit_force_error: dict = field(default_factory=dict)  # the force-fit metric, for the radius fit

    @property
    def params(self) -> VZParams:
        """The two-constant law's parameters (the force fit when that is shipped, else the radius
        fit), with the window they were fitted on."""
        if self.shipped == "force":
            return VZParams(self.spec.pair, self.force_fit.Ca, self.force_fit.Kc, self.fitted_window)
        return VZParams(self.spec.pair, self.radius_fit.Ca.slope, self.radius_fit.Kc.slope, self.fitted_window)

    @cached_property
    def table_params(self) -> VZTableParams | None:
        """The vz-table law fitted to the same loading points and the unloading paths' returned
        work (calib.fit.table_fit), or None when they do not determine an admissible table (no
        unloading path, too few points)."""
        try:
            return self.fit_table()
        except ValueError:
            return None

    def fit_table(self) -> VZTableParams:
        """:attr:`table_params`, or the ValueError saying why the FE paths determine none."""
        paths = self.load_paths.paths
        return fit_tables(self.radius_data, self.spec.pair, [p.peak for p in paths],
                          [p.unloading_work for p in paths], self.fitted_window)

    @property
    def shipped_params(self) -> VZParams | VZTableParams:
        """What the parameter file ships: the vz-table law (``shipped == "table"``) or the
        two-constant law of :attr:`params`."""
        return self.fit_table() if self.shipped == "table" else self.params

    @property
    def fitted_window(self) -> CalibrationWindow:
        """The loads the constants were fitted on: the FE loading points above P_Y (P/P_Y from
        the smallest to the largest, the largest FE contact radius / R*) and the FE that made them."""
        data, P_Y = self.radius_data, self.P_Y
        above = data.excess_force > 0
        mesh = self.mesh_info
        return CalibrationWindow(float(data.force[above].min()) / P_Y, float(data.force[above].max()) / P_Y,
                                 float(data.contact_radius[above].max()) / self.spec.pair.R_star,
                                 f"FE: mesh {mesh.get('key', '?')} ({mesh.get('dofs', '?')} dofs), "
                                 f"code {git_commit()}")


def drive_law(law_name: str, params, approach: np.ndarray) -> tuple[np.ndarray, float]:
    """Forces [N] of a runtime law along an approach history [m] (one contact), and its
    restitution at the largest approach: e^2 = elastic / (elastic + dissipated) energy there."""
    law = get_law(law_name)
    state = law.initial_state(1)
    forces = np.empty(approach.size)
    e = 1.0
    peak_index = int(np.argmax(approach))
    for k, delta in enumerate(approach):
        with warnings.catch_warnings():     # the FE's own paths: at their top the law may exceed
            warnings.simplefilter("ignore", RangeWarning)   # the window by its fit error
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


SHIPPABLE = ("radius", "force", "table")   # the paper's two constants, fitted to the radius or the force; the tables


def calibrate(spec: CalibrationSpec, progress: Callable[[str], None] | None = None,
              ship: str = "radius", unload: bool = True) -> CalibrationResult:
    """Run the FE load paths of ``spec`` and fit the NFD parameters (see module docstring).

    ``unload=False``: the loading branch only (about half the FE steps): the radius fit (which
    uses only loading points) and no force fit, model comparison or restitution.
    """

    if ship not in SHIPPABLE:
        raise ValueError(f"ship must be one of {', '.join(map(repr, SHIPPABLE))}, got {ship!r}")
    if ship in ("force", "table") and not unload:
        raise ValueError(f"ship = {ship!r} fits the load-unload paths: it needs unload=True")
    check_fittable(spec)                # before the mesh: a plan that cannot be fitted costs nothing
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
    paths = run_load_paths(solver, spec.plan, progress=say, unload=unload)

    loading = paths.loading_rows
    data = radius_law_data([r["P"] for r in loading], [r["alpha"] for r in loading],
                           [r["contact_radius"] for r in loading],
                           R_star=pair.R_star, E_star=pair.E_star, P_Y=pair.P_Y)
    radius_fit = fit_radius_law(data)
    window = window_study(data)

    histories = [_path_history(p) for p in paths.paths]
    force_fit, radius_fit_force_error = None, {}
    if unload:
        def predict_force(approach, Ca, Kc):
            return drive_law("vz", VZParams(pair, Ca, Kc), approach)[0]

        force_floor = 0.05 * spec.plan.peaks[0]
        force_fit = fit_force_law(predict_force, histories, radius_fit.Ca.slope, radius_fit.Kc.slope,
                                  force_floor=force_floor)
        residuals = relative_force_residuals(predict_force, histories, radius_fit.Ca.slope,
                                             radius_fit.Kc.slope, force_floor)
        radius_fit_force_error = {"rms_relative_force_error": float(np.sqrt(np.mean(residuals**2))),
                                  "max_relative_force_error": float(np.abs(residuals).max())}
    result = CalibrationResult(spec=spec, P_Y=pair.P_Y, P_Y_fe=P_Y_fe, load_paths=paths,
                               radius_data=data, radius_fit=radius_fit, window=window,
                               force_fit=force_fit, shipped=ship, comparisons={}, solver=solver,
                               radius_fit_force_error=radius_fit_force_error,
                               mesh_info={**spec.mesh.describe(), "elements": int(hemisphere.mesh.nelements),
                                          "dofs": int(solver.n_dofs)})
    for path, (approach, force) in zip(paths.paths, histories):
        comparisons = []
        other_fit = "force" if ship == "radius" else "radius"
        other_params = (VZParams(pair, force_fit.Ca, force_fit.Kc) if other_fit == "force"
                        else VZParams(pair, radius_fit.Ca.slope, radius_fit.Kc.slope))
        models = [("vz", "vz", result.params), (f"vz ({other_fit} fit)", "vz", other_params)]
        if result.table_params is not None:
            models.append(("vz-table", "vz-table", result.table_params))
        for label, law_name, params in models + [("thornton", "thornton", pair), ("hertz", "hertz", pair)]:
            law_force, e = drive_law(law_name, params, approach)
            comparisons.append(ModelComparison(label, law_force, e,
                                               float(np.abs(law_force - force).max() / path.peak)))
        result.comparisons[path.peak] = comparisons
    if ship == "table":
        try:
            result.fit_table()
        except ValueError as exc:
            raise ValueError(f"ship = 'table': {exc}") from None
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
        "window": params.window.record(),
        "table": (None if result.table_params is None else
                  {"P_over_P_Y": list(result.table_params.x), "a_p_over_a_Y": list(result.table_params.f),
                   "C_R": list(result.table_params.g)}),
        "shipped_fit": result.shipped,
        "radius_fit": {"Ca": result.radius_fit.Ca.slope, "Ca_se": result.radius_fit.Ca.standard_error,
                       "Ca_r2": result.radius_fit.Ca.r_squared, "Kc": result.radius_fit.Kc.slope,
                       "Kc_se": result.radius_fit.Kc.standard_error, "Kc_r2": result.radius_fit.Kc.r_squared,
                       "n_points": result.radius_fit.Ca.n_points, **result.radius_fit_force_error},
        "force_fit": None if result.force_fit is None else asdict(result.force_fit),
        "loading_only": not result.load_paths.paths,
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

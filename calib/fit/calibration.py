"""The calibration: FE load paths of a sphere on a rigid flat -> Ca, Kc of the runtime NFD law.

Vu-Quoc & Zhang (1999), sections 2-3 (nfdmodel/README.md, The NFD law on loading; calib/README.md,
The FE problem):
  1. mesh the hemisphere (meshes.hemisphere), solve the elastic-perfectly plastic von Mises
     contact problem (calib.fe + calib.fe.von_mises) along force-driven load paths with unloading
     (calib.fe.loadpath);
  2. decompose the FE contact radius a_ep = a_e + a_p and fit Ca (a_p = Ca <P - P_Y>) and Kc
     (C_R = a_ep^2 / (R alpha) = 1 + Kc <P - P_Y>) by least squares (calib.fit);
  3. also fit (Ca, Kc) to the FE force-approach curves through the runtime law itself
     (nfdmodel vz), i.e. what a DEM code feels;
  4. fit the vz-table law's tables (calib.fit.table_fit) to the FE loading curve and the work
     each unloading returned: the law for windows beyond two constants; with ``ship="unload"``
     also the vz-unload law (calib.fit.unload_ship: the FE's contact radius, dent and unloading
     exponent), checked against the paths it was fitted on and against interior paths held out;
  5. drive nfdmodel's vz, vz-table (vz-unload when shipped), thornton and hertz laws along the FE approach histories and
     compare;
  6. repeat 1-4 on a second mesh (contact element 2h, on another process while the first runs)
     and ship the Richardson-extrapolated constants with their estimated discretisation error
     (calib.fit.extrapolation).
The parameter file written from the result is read by ``nfdmodel.load_parameters``, so the
shipped runtime law is exactly the calibrated one.
"""
from __future__ import annotations

import dataclasses
import time
import warnings
from dataclasses import asdict, dataclass, field
from functools import cached_property
from typing import Callable

import numpy as np
from threadpoolctl import threadpool_limits

from calib.fe import ContactSolver
from calib.fe.elastic import ElasticMaterial
from calib.fe.kinematics import DEFAULT_KINEMATICS
from calib.fe.loadpath import LoadPathResults, run_load_paths, unloading_path
from calib.fe.von_mises import von_mises_material, von_mises_stress
from calib.fit import extrapolation
from calib.fit.extrapolation import Estimate
from calib.fit.least_squares import (ForceLawFit, RadiusLawData, RadiusLawFit, fit_force_law, fit_radius_law,
                                     radius_law_data, relative_force_residuals, window_study)
from calib.fit.recipe import CalibrationSpec, check_fittable, coarse_spec
from calib.fit import unload_ship
from calib.fit.table_fit import fit_tables
from calib.output import git_commit
from calib.sweep.runner import in_background
from meshes.hemisphere import hemisphere_mesh
from nfdmodel import (CalibrationWindow, ContactPair, Material, RangeWarning, VZParams, VZTableParams, VZUnloadParams,
                      get_law)

# What a shipped law must meet against the FE at every peak inside its window: |e_law / e_FE - 1| and
# max |P_law - P_FE| / P_max along loading and unloading (calib/README.md, Accuracy of a shipped law).
E_TARGET, FORCE_TARGET = 0.02, 0.05


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
    mesh_pair: dict | None = None     # the second mesh (calib.fit.extrapolation): None for one mesh

    def fitted_constants(self, fit: str) -> tuple[float, float]:
        """(Ca [m/N], Kc [1/N]) of this mesh's radius or force fit."""
        if fit == "force":
            return self.force_fit.Ca, self.force_fit.Kc
        return self.radius_fit.Ca.slope, self.radius_fit.Kc.slope

    def constants(self, fit: str) -> dict[str, Estimate] | None:
        """Ca and Kc of the radius or force fit from both meshes (extrapolated, with their error
        estimates), or None for a one-mesh calibration."""
        if self.mesh_pair is None or self.mesh_pair[f"{fit}_fit"] is None:
            return None
        coarse = self.mesh_pair[f"{fit}_fit"]
        fine = self.fitted_constants(fit)
        return {name: extrapolation.richardson(fine[k], coarse[k]) for k, name in enumerate(("Ca", "Kc"))}

    @property
    def params(self) -> VZParams:
        """The two-constant law's parameters (the force fit when that is shipped, else the radius
        fit; extrapolated from both meshes when there are two), with the window they were
        fitted on."""
        fit = "force" if self.shipped == "force" else "radius"
        estimates = self.constants(fit)
        Ca, Kc = ((estimates["Ca"].value, estimates["Kc"].value) if estimates is not None
                  else self.fitted_constants(fit))
        return VZParams(self.spec.pair, Ca, Kc, self.fitted_window)

    @cached_property
    def table_params(self) -> VZTableParams | None:
        """The vz-table law fitted to the same loading points and the unloading paths' returned
        work (calib.fit.table_fit), or None when they do not determine an admissible table (no
        unloading path, too few points)."""
        try:
            return self.fit_table()
        except ValueError:
            return None

    @cached_property
    def _fine_table_fit(self) -> VZTableParams | str:
        """This mesh's vz-table fit, or why its FE paths determine none (fitted once)."""
        paths = self.load_paths.paths
        try:
            return fit_tables(self.radius_data, self.spec.pair, [p.peak for p in paths],
                              [p.unloading_work for p in paths], self.fitted_window)
        except ValueError as exc:
            return str(exc)

    def fine_table(self) -> VZTableParams:
        """The vz-table law of this mesh alone (ValueError when its FE paths determine none)."""
        fit = self._fine_table_fit
        if isinstance(fit, str):
            raise ValueError(fit)
        return fit

    def _table_extrapolation(self) -> tuple[VZTableParams, tuple | None]:
        """This mesh's table and, when the second mesh has a table on the same nodes, its node
        values extrapolated (a_p/a_Y, C_R) with the largest estimated error; ValueError as
        :meth:`fine_table`."""
        table = self.fine_table()
        coarse = None if self.mesh_pair is None else self.mesh_pair.get("table")
        if coarse is None or len(coarse["P_over_P_Y"]) != len(table.x) or not np.allclose(
                coarse["P_over_P_Y"], table.x, rtol=1e-6, atol=0):     # other nodes: this mesh's table
            return table, None
        f, f_error = extrapolation.extrapolated_table(table.f, coarse["a_p_over_a_Y"])
        g, g_error = extrapolation.extrapolated_table(table.g, coarse["C_R"])
        return table, (f, g, max(f_error, g_error))

    def fit_table(self) -> VZTableParams:
        """:attr:`table_params`, or the ValueError saying why the FE paths determine none: the
        node values extrapolated from both meshes where the coarse mesh has a table on the same
        nodes and the result is admissible, else this mesh's."""
        table, extrapolated = self._table_extrapolation()
        if extrapolated is None:
            return table
        try:
            return VZTableParams(self.spec.pair, table.x, extrapolated[0], extrapolated[1], table.window)
        except ValueError:              # an inadmissible extrapolation: this mesh's table ships
            return table

    def table_rel_error_estimate(self) -> float | None:
        """The largest estimated relative error over the table's nodes (a_p/a_Y and C_R), or None."""
        try:
            _, extrapolated = self._table_extrapolation()
        except ValueError:
            return None
        return None if extrapolated is None else extrapolated[2]

    def path_estimates(self) -> list[dict[str, Estimate]] | None:
        """e and alpha_max of each load path from both meshes (not extrapolated: the fine mesh's,
        the change as the error estimate), or None for one mesh."""
        if self.mesh_pair is None:
            return None
        return [{"e": extrapolation.unextrapolated(path.restitution, coarse["e"]),
                 "alpha_max": extrapolation.unextrapolated(path.alpha_max, coarse["alpha_max"])}
                for path, coarse in zip(self.load_paths.paths, self.mesh_pair["paths"])]

    @cached_property
    def unload_params(self) -> VZUnloadParams:
        """The vz-unload law fitted to this mesh's loading points and unloading paths
        (calib.fit.unload_ship; ValueError when they determine none)."""
        return unload_ship.fit_unload(self)

    @property
    def shipped_params(self) -> VZParams | VZTableParams | VZUnloadParams:
        """What the parameter file ships: the vz-table law (``shipped == "table"``), the vz-unload
        law (``"unload"``) or the two-constant law of :attr:`params` on :meth:`two_constant_window`."""
        if self.shipped == "table":
            return self.fit_table()
        if self.shipped == "unload":
            return self.unload_params
        params = self.params
        return VZParams(params.pair, params.Ca, params.Kc, self.two_constant_window() or self.fitted_window)

    def two_constant_window(self) -> CalibrationWindow | None:
        """The window the two-constant law is shipped on: from the lowest to the highest peak of
        the longest run of consecutive FE paths at which it meets E_TARGET and FORCE_TARGET (the
        loads between them; those paths' peaks, P/P_Y); the fitted window without unloading paths
        (no e to check); None when it meets them at no path (then :attr:`shipped_params` keeps the
        fitted window and :func:`accuracy` records the miss; ``nfdcal calibrate`` refuses to ship it)."""
        meets = peaks_within_target(self, "vz")
        if meets is None:
            return self.fitted_window
        best, run = [], []
        for peak, ok in meets:
            run = run + [peak] if ok else []
            if len(run) > len(best):
                best = run
        if not best:
            return None
        return dataclasses.replace(self.fitted_window, P_min_over_P_Y=best[0] / self.P_Y,
                                   P_max_over_P_Y=best[-1] / self.P_Y)

    @property
    def fitted_window(self) -> CalibrationWindow:
        """The loads the constants were fitted on: the FE loading points above P_Y (P/P_Y from
        the smallest to the largest, the largest FE contact radius / R*) and the FE that made them."""
        data, P_Y = self.radius_data, self.P_Y
        above = data.excess_force > 0
        mesh = self.mesh_info
        return CalibrationWindow(float(data.force[above].min()) / P_Y, float(data.force[above].max()) / P_Y,
                                 float(data.contact_radius[above].max()) / self.spec.pair.R_star,
                                 f"FE{kinematics_note(self.spec.kinematics)}: mesh {mesh.get('key', '?')} "
                                 f"({mesh.get('dofs', '?')} dofs), code {git_commit()}")


def kinematics_note(kinematics: str) -> str:
    """' (finite-strain)' for a window's source, naming a kinematics other than the default, so the
    window is checked against that FE's reach (nfdmodel.window); '' for small strain (its sources unchanged)."""
    return "" if kinematics == DEFAULT_KINEMATICS else f" ({kinematics})"


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


# the paper's two constants, fitted to the radius or the force; the vz-table law; the vz-unload law
SHIPPABLE = ("radius", "force", "table", "unload")
SHIPPED_LAW = {"radius": "vz", "force": "vz", "table": "vz-table", "unload": "vz-unload"}


MESH_COUNTS = (1, 2)   # one mesh (studies of the FE itself), or two and Richardson extrapolation


def calibrate(spec: CalibrationSpec, progress: Callable[[str], None] | None = None,
              ship: str = "radius", unload: bool = True, meshes: int = 2,
              parallel: bool = True) -> CalibrationResult:
    """Run the FE load paths of ``spec`` and fit the NFD parameters (see module docstring).

    ``unload=False``: the loading branch only (about half the FE steps): the radius fit (which
    uses only loading points) and no force fit, model comparison or restitution.
    ``meshes=2`` (default): also solve the mesh with contact element 2h (calib.fit.recipe.
    coarse_spec) on another process when ``parallel`` and the machine allow, and ship the
    extrapolated constants (calib.fit.extrapolation); ``meshes=1``: this mesh's constants only.
    """

    if ship not in SHIPPABLE:
        raise ValueError(f"ship must be one of {', '.join(map(repr, SHIPPABLE))}, got {ship!r}")
    if ship in ("force", "table", "unload") and not unload:
        raise ValueError(f"ship = {ship!r} fits the load-unload paths: it needs unload=True")
    if meshes not in MESH_COUNTS:
        raise ValueError(f"meshes must be 1 or 2, got {meshes!r}")
    check_fittable(spec)                # before the mesh: a plan that cannot be fitted costs nothing
    say = progress or (lambda message: None)
    t0 = time.perf_counter()
    if meshes == 1:
        result = calibrate_mesh(spec, say, unload)
    else:
        coarse = coarse_spec(spec)
        for one in (spec, coarse):      # gmsh is a process-wide singleton: every mesh is built
            body_meshes(one)           # here, the other process only reads the cache
        say(f"second mesh: contact element {coarse.mesh.contact_size:.3g} m (Richardson extrapolation)")
        with in_background(mesh_figures_of, {"spec": coarse, "unload": unload}, parallel) as background:
            # the second mesh's process, once done, takes the top path's unloading of this mesh
            # if it gets to it first (the meshes' work is unequal: the finer one sets the wall time)
            def offload(peak, peak_state):
                return background.offer(unloading_of, {"spec": spec, "peak": peak, "peak_state": peak_state})

            result = calibrate_mesh(spec, say, unload, offload)
            result.mesh_pair = background()
        estimates = result.constants("radius")
        extrapolation.warn_if_not_asymptotic(estimates, (spec.mesh.contact_size, coarse.mesh.contact_size))
    result.shipped = ship
    if ship == "unload":                # before the comparison, which drives the shipped law
        try:
            result.unload_params
        except ValueError as exc:
            raise ValueError(f"ship = 'unload': {exc}") from None
    compare_models(result)
    if ship == "table":
        try:
            result.fit_table()
        except ValueError as exc:
            raise ValueError(f"ship = 'table': {exc}") from None
    result.wall_time_s = time.perf_counter() - t0
    result.timings["fit_s"] = (result.wall_time_s - result.timings["mesh_s"] - result.timings["first_yield_s"]
                               - result.timings["load_paths_s"])
    if result.mesh_pair is not None:
        result.timings["second_mesh_s"] = result.mesh_pair["wall_time_s"]
    return result


def calibrate_mesh(spec: CalibrationSpec, say: Callable[[str], None], unload: bool,
                   offload=None) -> CalibrationResult:
    """Steps 1-3 of the module docstring on the mesh of ``spec``: FE load paths, the radius fit and
    (``unload``) the force fit; no model comparison, no second mesh. ``offload``: as
    calib.fe.loadpath.run_load_paths takes it (a path's unloading offered to another process)."""
    # one BLAS thread: the FE's matrices are small (4x4, 12x12 per point), threads only contend,
    # most of all with the second mesh's process (measured: 1.5x the wall time, 2.3x the CPU)
    with threadpool_limits(limits=1, user_api="blas"):
        return _calibrate_mesh(spec, say, unload, offload)


def unloading_of(task: dict):
    """One path's unloading (calib.fe.loadpath.unloading_path) of the FE of ``task["spec"]`` from
    ``task["peak_state"]``, on this process: a task offered to the second mesh's process (module
    level: it runs there), with the same solver as the calibration's own, so the same rows."""
    spec = task["spec"]
    with threadpool_limits(limits=1, user_api="blas"):
        return unloading_path(_solver(spec, body_meshes(spec)), spec.plan, task["peak"], task["peak_state"])


def body_meshes(spec: CalibrationSpec):
    """The mesh of the FE of ``spec``: the hemisphere, or with a counter-body the pair of bodies
    (meshes.counter_body)."""
    if spec.counter is None:
        return hemisphere_mesh(spec.mesh)
    from meshes.counter_body import pair_mesh

    return pair_mesh(spec.mesh, spec.counter.mesh_spec(spec.mesh))


def _solver(spec: CalibrationSpec, mesh):
    """The FE solver of ``spec`` on ``mesh`` in ``spec.kinematics``: the rigid flat's, or the two-body
    FE's (calib.fe.two_body)."""
    material = spec.material
    sphere = von_mises_material(material.E, material.nu, material.sigma_y, spec.hardening)
    options = {"residual_tolerance": spec.residual_tolerance, "contact_radius_method": spec.contact_radius_method}
    if spec.counter is None:
        return ContactSolver(mesh, sphere, kinematics=spec.kinematics, **options)
    from calib.fe.two_body import TwoBodySolver

    return TwoBodySolver(mesh, sphere, spec.counter.fe_material(), kinematics=spec.kinematics, **options)


def _solver_and_first_yield(spec: CalibrationSpec, mesh):
    """(the FE solver of ``spec`` on ``mesh``, the FE's first-yield load [N]): the rigid flat's, or
    the two-body FE's with first yield in whichever body yields first."""
    material = spec.material
    solver = _solver(spec, mesh)
    if spec.counter is None:
        return solver, first_yield_load(mesh, material)
    from calib.fe.two_body import first_yield_loads

    counter = spec.counter
    loads = first_yield_loads(mesh, ElasticMaterial(material.E, material.nu), ElasticMaterial(counter.E, counter.nu),
                              (material.sigma_y, counter.sigma_y), spec.pair.P_Y, solver=solver)
    return solver, min(x for x in loads if x is not None)


def _calibrate_mesh(spec: CalibrationSpec, say: Callable[[str], None], unload: bool, offload=None) -> CalibrationResult:
    t0 = time.perf_counter()
    hemisphere = body_meshes(spec)
    t_mesh = time.perf_counter() - t0
    pair = spec.pair

    t1 = time.perf_counter()
    solver, P_Y_fe = _solver_and_first_yield(spec, hemisphere)
    t_yield = time.perf_counter() - t1
    say(f"first yield: P_Y(FE) = {P_Y_fe:.4g} N, theory {pair.P_Y:.4g} N")
    paths = run_load_paths(solver, spec.plan, progress=say, unload=unload, offload=offload)

    loading = paths.loading_rows
    data = radius_law_data([r["P"] for r in loading], [r["alpha"] for r in loading],
                           [r["contact_radius"] for r in loading],
                           R_star=pair.R_star, E_star=pair.E_star, P_Y=pair.P_Y)
    radius_fit = fit_radius_law(data)
    if not (radius_fit.Ca.slope > 0 and radius_fit.Kc.slope > 0):
        raise ValueError(f"P_max out of range: the FE contact radii up to {spec.plan.peaks[-1] / pair.P_Y:.3g} P_Y give "
                         f"Ca = {radius_fit.Ca.slope:.4g} m/N, Kc = {radius_fit.Kc.slope:.4g} 1/N (need both > 0): "
                         f"the plastic growth is lost in the discretisation error; load further (--peaks) or "
                         f"refine the mesh (--contact-size)")
    window = window_study(data)

    force_fit, radius_fit_force_error = None, {}
    if unload:
        histories = [_path_history(p) for p in paths.paths]

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
                               force_fit=force_fit, shipped="radius", comparisons={}, solver=solver,
                               radius_fit_force_error=radius_fit_force_error,
                               mesh_info={**spec.mesh.describe(), "elements": int(hemisphere.mesh.nelements),
                                          "dofs": int(solver.n_dofs),
                                          **({"counter": spec.counter.mesh_spec(spec.mesh).describe()}
                                             if spec.counter is not None else {})})
    result.wall_time_s = time.perf_counter() - t0
    result.timings = {"mesh_s": t_mesh, "first_yield_s": t_yield, "load_paths_s": paths.wall_time_s,
                      "factorizations": paths.factorizations}
    return result


def mesh_figures(result: CalibrationResult) -> dict:
    """What the extrapolation needs of one mesh's calibration (picklable, JSON-able): its mesh,
    wall time [s], both fits' (Ca [m/N], Kc [1/N]), the vz-table law's nodes, e and alpha_max [m]
    of each path."""
    try:
        table = result.fine_table()
        table = {"P_over_P_Y": list(table.x), "a_p_over_a_Y": list(table.f), "C_R": list(table.g)}
    except ValueError:
        table = None
    return {"contact_size": result.spec.mesh.contact_size, "dofs": result.mesh_info["dofs"],
            "elements": result.mesh_info["elements"], "wall_time_s": result.wall_time_s,
            "factorizations": result.timings["factorizations"], "P_Y_fe": result.P_Y_fe,
            "radius_fit": list(result.fitted_constants("radius")),
            "force_fit": None if result.force_fit is None else list(result.fitted_constants("force")),
            "table": table,
            "paths": [{"P_max": p.peak, "e": p.restitution, "alpha_max": p.alpha_max} for p in result.load_paths.paths]}


def mesh_figures_of(task: dict) -> dict:
    """:func:`mesh_figures` of ``calibrate_mesh(task["spec"])`` (module level: it runs on another
    process)."""
    return mesh_figures(calibrate_mesh(task["spec"], lambda message: None, task["unload"]))


def compare_models(result: CalibrationResult) -> None:
    """Step 5: the shipped law, the other fit, the vz-table law, Thornton and Hertz driven along
    each FE path's approach history (``result.comparisons``)."""
    pair = result.spec.pair
    result.__dict__.pop("table_params", None)    # the second mesh may have changed it
    result.comparisons = {}
    for path in result.load_paths.paths:
        approach, force = _path_history(path)
        other_fit = "radius" if result.shipped == "force" else "force"   # the fit "vz" is not
        other = result.constants(other_fit)
        other_params = VZParams(pair, *((other["Ca"].value, other["Kc"].value) if other is not None
                                        else result.fitted_constants(other_fit)))
        models = [("vz", "vz", result.params), (f"vz ({other_fit} fit)", "vz", other_params)]
        if result.table_params is not None:
            models.append(("vz-table", "vz-table", result.table_params))
        if result.shipped == "unload":
            models.append(("vz-unload", "vz-unload", result.unload_params))
        comparisons = []
        for label, law_name, params in models + [("thornton", "thornton", pair), ("hertz", "hertz", pair)]:
            law_force, e = drive_law(law_name, params, approach)
            comparisons.append(ModelComparison(label, law_force, e,
                                               float(np.abs(law_force - force).max() / path.peak)))
        result.comparisons[path.peak] = comparisons


def summary(result: CalibrationResult) -> dict:
    """The ``nfdcal calibrate --json`` object (SI units). Ca, Kc, Ca_hat, Kc_hat: the shipped
    two-constant law (extrapolated from two meshes), with ``*_rel_error_estimate`` its estimated
    relative discretisation error (None for a one-mesh calibration); ``radius_fit``/``force_fit``:
    the fits on the first (finer) mesh."""
    params = result.params
    errors = discretisation_errors(result)
    return {
        "Ca": params.Ca, "Kc": params.Kc, "Ca_hat": params.Ca_hat, "Kc_hat": params.Kc_hat,
        **errors,
        "P_Y": result.P_Y, "P_Y_fe": result.P_Y_fe,
        "P_Y_fe_rel_error": result.P_Y_fe / result.P_Y - 1.0,
        "window": params.window.record(),
        "shipped_window": result.shipped_params.window.record(),
        "table": (None if result.table_params is None else
                  {"P_over_P_Y": list(result.table_params.x), "a_p_over_a_Y": list(result.table_params.f),
                   "C_R": list(result.table_params.g), "window": result.table_params.window.record()}),
        "shipped_fit": result.shipped,
        "accuracy": accuracy(result),
        **({"vz_unload": unload_ship.figures(result, result.unload_params)} if result.shipped == "unload" else {}),
        "radius_fit": {"Ca": result.radius_fit.Ca.slope, "Ca_se": result.radius_fit.Ca.standard_error,
                       "Ca_r2": result.radius_fit.Ca.r_squared, "Kc": result.radius_fit.Kc.slope,
                       "Kc_se": result.radius_fit.Kc.standard_error, "Kc_r2": result.radius_fit.Kc.r_squared,
                       "n_points": result.radius_fit.Ca.n_points, **result.radius_fit_force_error},
        "force_fit": None if result.force_fit is None else asdict(result.force_fit),
        "loading_only": not result.load_paths.paths,
        "wall_time_s": result.wall_time_s,
        "timings": result.timings,
        "mesh": result.mesh_info,
        **({} if result.spec.hardening is None else {"hardening": result.spec.hardening.record()}),
        "paths": [{"P_max": p.peak, "alpha_max": p.alpha_max, "e": p.restitution,
                   "alpha_residual": p.alpha_residual,
                   "P_max_reached": max(r["P"] for r in p.rows),
                   "steps": len(p.rows),
                   **({} if result.mesh_pair is None else
                      {"e_rel_error_estimate": estimates["e"].rel_error_estimate,
                       "alpha_max_rel_error_estimate": estimates["alpha_max"].rel_error_estimate}),
                   "models": {c.law: {"e": c.restitution, "max_force_error_rel": c.max_force_error}
                              for c in result.comparisons[p.peak]}}
                  for p, estimates in zip(result.load_paths.paths,
                                          result.path_estimates() or [None] * len(result.load_paths.paths))],
    }


def peaks_within_target(result: CalibrationResult, law: str) -> list[tuple[float, bool]] | None:
    """(P_max [N], whether ``law`` ("vz", "vz-table", "vz-unload") meets E_TARGET and FORCE_TARGET there)
    for each FE path in load order, or None without unloading paths."""
    out = []
    for path in sorted(result.load_paths.paths, key=lambda p: p.peak):
        for c in result.comparisons.get(path.peak, []):
            if c.law == law:
                out.append((path.peak, bool(abs(c.restitution / path.restitution - 1.0) <= E_TARGET
                                            and c.max_force_error <= FORCE_TARGET)))
    return out or None


def accuracy(result: CalibrationResult) -> dict:
    """Each runtime law of the calibration (the two constants "vz", the table "vz-table", and the
    shipped "vz-unload") against the FE paths it was calibrated on: worst |e_law / e_FE - 1| and
    worst max |P_law - P_FE| / P_max over the paths, and whether both meet E_TARGET, FORCE_TARGET.
    ``shipped`` names the law the parameter file ships. {} without unloading paths (no e to compare)."""
    records = {}
    for path in result.load_paths.paths:
        for c in result.comparisons.get(path.peak, []):
            if c.law not in ("vz", "vz-table", "vz-unload"):
                continue
            record = records.setdefault(c.law, {"worst_e_error": 0.0, "worst_force_error": 0.0})
            e_error = c.restitution / path.restitution - 1.0
            if abs(e_error) >= abs(record["worst_e_error"]):
                record["worst_e_error"], record["e_error_at_P_max"] = e_error, path.peak
            record["worst_force_error"] = max(record["worst_force_error"], c.max_force_error)
    for law, record in records.items():
        record["within_target"] = bool(abs(record["worst_e_error"]) <= E_TARGET
                                       and record["worst_force_error"] <= FORCE_TARGET)
        record["P_max_within_target"] = [peak for peak, ok in peaks_within_target(result, law) if ok]
    if not records:
        return {}
    return {"laws": records, "shipped": SHIPPED_LAW[result.shipped],
            "targets": {"e_error": E_TARGET, "force_error": FORCE_TARGET}}


def discretisation_errors(result: CalibrationResult) -> dict:
    """The estimated relative discretisation errors of what a calibration ships (the keys of
    ``nfdcal calibrate --json``, the parameter file and the tables), and the meshes they come
    from; the errors are None for a one-mesh calibration."""
    fit = "force" if result.shipped == "force" else "radius"
    constants = result.constants(fit)
    paths = result.path_estimates()
    errors = {"Ca_rel_error_estimate": None, "Kc_rel_error_estimate": None, "e_rel_error_estimate": None,
              "alpha_rel_error_estimate": None, "table_rel_error_estimate": result.table_rel_error_estimate()}
    if constants is not None:
        errors["Ca_rel_error_estimate"] = constants["Ca"].rel_error_estimate
        errors["Kc_rel_error_estimate"] = constants["Kc"].rel_error_estimate
    if paths:
        errors["e_rel_error_estimate"] = max(p["e"].rel_error_estimate for p in paths)
        errors["alpha_rel_error_estimate"] = max(p["alpha_max"].rel_error_estimate for p in paths)
    errors["Ca_hat_rel_error_estimate"] = errors["Ca_rel_error_estimate"]   # exact scalings of Ca, Kc
    errors["Kc_hat_rel_error_estimate"] = errors["Kc_rel_error_estimate"]
    pair = result.mesh_pair
    errors["discretisation"] = {
        "meshes": 1 if pair is None else 2,
        "contact_sizes": [result.spec.mesh.contact_size] + ([] if pair is None else [pair["contact_size"]]),
        "dofs": [result.mesh_info["dofs"]] + ([] if pair is None else [pair["dofs"]]),
        "method": ("one mesh: no estimate" if pair is None else
                   f"Richardson extrapolation of Ca, Kc (and the vz-table nodes) from contact elements h and "
                   f"{extrapolation.REFINEMENT:g}h, order {extrapolation.ORDER:g}; error estimate: its sensitivity "
                   f"to the order +-{extrapolation.ORDER_SPREAD:g}; e and alpha: the finer mesh's, the change as "
                   f"the estimate"),
        "extrapolated": None if constants is None else {name: e.extrapolated for name, e in constants.items()},
        "Ca": None if constants is None else constants["Ca"].record(),
        "Kc": None if constants is None else constants["Kc"].record(),
        "second_mesh_wall_time_s": None if pair is None else pair["wall_time_s"]}
    return errors

"""The quasi-static FE at the dynamic FE's peak force: its load-unload path, thrown as an impact.

For each impact of the study (calib.studies.impact) the hemisphere with the sizes of the impact's
mesh (meshes.sphere.SphereMeshSpec.contact_zone) is pressed by the rigid plate to the impact's
P_max and unloaded, force-controlled (calib.fe.loadpath; loading increments growing geometrically,
calib.fit.impact_window.GeometricLoadPathPlan; the calibration's first load and unloading steps,
calib.fit.recipe). Its loop P(alpha), piecewise linear between the FE's steps but Hertzian
(P ~ x^(3/2)) on the elastic first load from alpha = 0 and on the last unloading step to the
residual approach (calib.fe.loadpath), is the contact of a quasi-static collision of the
sphere's mass m (calib.fit.loop_impact: e, contact time, works and the force at the dynamic
impact's v_in).

The dynamic FE differs from this by the sphere's inertia: stress waves, the vibration energy left
after separation, and a contact driven by the whole body's deceleration instead of a plate.
Units: SI.
"""
from __future__ import annotations

import math
import time

import numpy as np

from calib import output
from calib.fe.kinematics import DEFAULT_KINEMATICS
from calib.fe.loadpath import run_load_paths
from calib.fe.solver import ContactSolver
from calib.fe.von_mises import von_mises_material
from calib.fit import impact_window, recipe
from calib.fit.loop_impact import loop_impact
from meshes.hemisphere import hemisphere_mesh
from meshes.keys import stable_key
from meshes.sphere import SphereMeshSpec
from nfdmodel import Material

VERSION = 1                      # bump when the recipe changes: invalidates finished cases


def task_of(material: Material, radius: float, fine_row: dict, hardening=None,
            kinematics: str = DEFAULT_KINEMATICS) -> dict:
    """The quasi-static task of a finished dynamic impact of ``material`` on a sphere of ``radius``
    [m] (``fine_row``: the impact's ``fine`` row of calib.studies.impact; ``hardening``: the sphere's
    flow curve, calib.fe.flow_curve, None for perfect plasticity; ``kinematics``: the FE's,
    calib.fe.kinematics): its mesh and P_max; keyed by what decides the run."""
    task = {"E": material.E, "nu": material.nu, "sigma_y": material.sigma_y, "rho": material.rho, "R": float(radius),
            "v_in": float(fine_row["v_in"]), "P_max": float(fine_row["P_max"]),
            "mesh": {k: fine_row["mesh"][k] for k in ("radius", "contact_size", "refined_radius", "refined_depth",
                                                       "far_size", "growth")},
            **({} if hardening is None else {"hardening": hardening.record()}),
            **({} if kinematics == DEFAULT_KINEMATICS else {"kinematics": kinematics})}
    return {**task, "variant": "quasi-static", "key": stable_key({**task, "version": VERSION})}


def run_task(task: dict) -> dict:
    """The load-unload path of ``task`` and its quasi-static impact, as a row (never raises: a
    failure is a row with status "failed")."""
    from threadpoolctl import threadpool_limits    # one BLAS thread per FE process (calib/README.md)

    started = time.perf_counter()
    base = {"key": task["key"], "v_in": task["v_in"], "variant": task["variant"]}
    try:
        with threadpool_limits(1):
            material = Material(E=task["E"], nu=task["nu"], sigma_y=task["sigma_y"], rho=task["rho"])
            path = load_path(material, task["R"], SphereMeshSpec(**task["mesh"]), task["P_max"], task.get("hardening"),
                             task.get("kinematics", DEFAULT_KINEMATICS))
    except (ValueError, np.linalg.LinAlgError, RuntimeError) as exc:
        return {**base, "status": "failed", "error": str(exc), "wall_time_s": time.perf_counter() - started}
    return {**base, **thrown(path, sphere_mass(task), task["v_in"]), "status": "ok", "error": "",
            "wall_time_s": time.perf_counter() - started, "git_commit": output.git_commit()}


def sphere_mass(task: dict) -> float:
    """(4/3) pi R^3 rho [kg] of a task's sphere."""
    return 4.0 / 3.0 * math.pi * task["R"] ** 3 * task["rho"]


def load_path(material: Material, radius: float, mesh: SphereMeshSpec, peak: float, hardening=None,
              kinematics: str = DEFAULT_KINEMATICS) -> dict:
    """The FE load-unload path to ``peak`` [N] on the hemisphere of ``mesh``'s sizes (``hardening``: the
    flow curve's record, None for perfect plasticity; ``kinematics``: calib.fe.kinematics'): loading and unloading (alpha [m], P [N]) arrays
    from (0, 0) to the peak and back to the residual approach."""
    spec = recipe.calibration_spec(material, radius, peaks=(peak,))
    plan = impact_window.GeometricLoadPathPlan(peaks=spec.plan.peaks, loading_step=peak,
                                               unloading_steps=spec.plan.unloading_steps,
                                               first_load=spec.plan.first_load)
    hemisphere = hemisphere_mesh(mesh.contact_zone)
    solver = ContactSolver(hemisphere, von_mises_material(material.E, material.nu, material.sigma_y, hardening),
                           residual_tolerance=spec.residual_tolerance,
                           contact_radius_method=spec.contact_radius_method, kinematics=kinematics)
    paths = run_load_paths(solver, plan)
    path = paths.paths[0]
    loading = [r for r in path.rows if r["branch"] == "loading"]
    unloading = [r for r in path.rows if r["branch"] == "unloading"]
    return {"loading_alpha": [0.0] + [r["alpha"] for r in loading], "loading_P": [0.0] + [r["P"] for r in loading],
            "unloading_alpha": [path.alpha_max] + [r["alpha"] for r in unloading],
            "unloading_P": [path.peak_state.force] + [max(r["P"], 0.0) for r in unloading],
            "fe_restitution": path.restitution, "steps": len(loading) + len(unloading),
            "dofs": int(solver.n_dofs)}


def thrown(path: dict, mass: float, v_in: float) -> dict:
    """The quasi-static impact of a load-unload path (module docstring) on a mass ``mass`` [kg], the
    loading branch's force at the dynamic impact's ``v_in`` [m/s], and the error of the path's
    sampling: e and the contact time again from every other point of each branch (its ends kept),
    e_rel_error_estimate = |e_coarse / e - 1| / 3 (the trapezoidal work's second order), likewise
    contact_time_rel_error_estimate."""
    fine = loop_impact(path, mass, v_in)

    def every_other(values):
        values = np.asarray(values)
        return np.concatenate([values[:-1:2], values[-1:]])

    coarse = loop_impact({key: every_other(path[key]) for key in ("loading_alpha", "loading_P", "unloading_alpha",
                                                             "unloading_P")}, mass, v_in)
    return {**fine, "e_rel_error_estimate": abs(coarse["e"] / fine["e"] - 1.0) / 3.0,
            "contact_time_rel_error_estimate": abs(coarse["contact_time"] / fine["contact_time"] - 1.0) / 3.0,
            "fe_restitution": path["fe_restitution"], "steps": path["steps"], "dofs": path["dofs"], "path": path}


def compared(record: dict, quasi_static: dict) -> dict:
    """The dynamic FE over the quasi-static FE at the same P_max, as relative differences:
    e, contact time, alpha_max, dent, the velocity that reaches P_max, and P_max at the same v_in."""
    def change(a, b):
        return None if b in (None, 0.0) else float(a / b - 1.0)

    return {"e": change(record["e"], quasi_static["e"]),
            "contact_time": change(record["contact_time"], quasi_static["contact_time"]),
            "alpha_max": change(record["alpha_max"], quasi_static["alpha_max"]),
            "dent": change(record["dent"], quasi_static["dent"]),
            "v_in": change(record["v_in"], quasi_static["v_in_quasi_static"]),
            "P_max": change(record["P_max"], quasi_static["P_max_at_v_in"])}

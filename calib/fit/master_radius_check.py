"""The master table's laws against FE paths with the contact radius and load cycles.

The master table's check records keep no contact radius (calib.fit.vz_master_check), so the radius
of its vz-unload and vz-table laws (VZMasterTable.unload_law, .law) at a material it was not built
on is checked here against a direct FE run of that material (small strain unless ``kinematics`` names
another, calib.fe.kinematics; sphere of radius R on a rigid flat, a graded mesh of N elements across every
contact radius from the lowest peak up, calib.fit.recipe.mesh_for): load paths to the peaks x_i P_Y,
each unloaded to separation, and one cycle from the middle peak (calib.fe.cycles: partial unloads to
``fractions`` of P_max, reloads to P_max, the last on to ``overload`` P_max, then a full unload). Per
path and law (calib.fit.unload_check.unload_against_path, the FE's contact radius at the peak by the gap
extrapolation of calib.fe.recovery):

    radius error    = a_law / a_FE - 1 at the peak,  a_law = a_e(P_max) + a_p(P_max)
                      = a_Y (x^(1/3) + f(x)),  x = P_max / P_Y
                      (vz-table: f fitted to the force and the returned work; vz-unload: the
                      table's f_a, fitted to the nodes' FE contact radius)
    unloading error = max |P_law - P_FE| / P_max over the FE's unloading points
    dent error      = delta_res,law / alpha_res,FE - 1,   e error = e_law / e_FE - 1

and along the cycle (calib.fit.cycle_check.cycles_against_law): the largest |P_law - P_FE| / P_max
over the partial unloads and reloads, over the reload past the peak, and over the final unload
(of the overload's peak); and the radius along the partial unloads and reloads (the radius a
tangential spring k_t = 8 G* a reads after a partial unload; both laws: a = a_e(P) + a_p(P_max)):

    cycle radius error = max |a_law - a_FE| / a_FE(P_max)   over the rows with P >= 0.2 P_max

(on unloading the FE's edge, where the flattened profile meets the flat almost tangentially,
moves by jumps of about half an element, a_FE / (2 N): a resolution, not a target). The FE's own
discretisation on these figures: the same run on a coarser mesh (``mesh_spread``: the FE radius, dent, e
and unloading force of the two meshes).

The residual imprint (``rims``): after each path's separation the sphere's surface, relative to its
pole, against the undeformed one: the flattening w(r) = h_0(r) - h_res(r) (h the surface's height
above the pole) rises from 0 at the pole to the dent alpha_res, overshoots it in a low lip and returns
to it far out. The imprint's rim is where w first reaches alpha_res (the residual surface back on the
sphere, shifted by the dent; linear between the surface nodes), the lip's crest where w is largest
within 3 rims (:func:`residual_rim`); each against the FE's contact radius at the peak.
"""
from __future__ import annotations

import dataclasses
import time

import numpy as np

from calib.fe.kinematics import DEFAULT_KINEMATICS
from calib.fit import impact_window, recipe
from calib.fit.vz_master_table import VZMasterTable
from nfdmodel import ContactPair, Material

LAWS = ("vz-unload", "vz-table")


def fe_run(material: Material, R: float, peaks_over_P_Y: tuple[float, ...], elements_per_contact_radius: float,
           loading_steps_per_decade: float = 16.0, unloading_steps: int = 16,
           fractions: tuple[float, ...] = (0.5, 0.2), overload: float = 1.3, rims: bool = False,
           kinematics: str = DEFAULT_KINEMATICS) -> dict:
    """The FE paths and cycle of the module doc: ``paths`` (per peak: the loading approach and
    force to the peak, the contact radius there [m] (the gap extrapolation; ``radius_at_peak_pressure``:
    the pressure's, calib.fe.recovery, as the dynamic FE takes it), the unloading, alpha_max, alpha_res, e;
    with ``rims`` the residual imprint's rim and lip crest [m] and the lip's height [alpha_res], module doc),
    ``cycle`` (calib.fe.cycles.CycleRun), the mesh and the wall time [s]."""
    from calib.fe.cycles import CyclePlan, run_cycles
    from calib.fe.loadpath import run_load_paths, unloading_path
    from calib.fit.calibration import body_meshes, _solver

    pair = ContactPair.sphere_flat(material, R)
    peaks = tuple(float(x * pair.P_Y) for x in peaks_over_P_Y)
    spec = recipe.calibration_spec(material, R, peaks=peaks, unloading_steps=unloading_steps,
                                   elements_per_contact_radius=elements_per_contact_radius,
                                   graded_from=recipe.estimated_contact_radius(pair, peaks[0]),
                                   kinematics=kinematics)
    plan = impact_window.GeometricLoadPathPlan(peaks=peaks, loading_step=peaks[-1], unloading_steps=unloading_steps,
                                               first_load=min(spec.plan.first_load, peaks[0]),
                                               loading_ratio=10.0 ** (1.0 / loading_steps_per_decade))
    t0 = time.perf_counter()
    solver = _solver(spec, body_meshes(spec))
    results = run_load_paths(solver, plan)
    cycle = run_cycles(solver, plan, CyclePlan(fractions, overload), results) if fractions else None
    paths = []
    for p in results.paths:
        loading = [r for r in p.rows if r["branch"] == "loading"]
        unloading = [r for r in p.rows if r["branch"] == "unloading"]
        paths.append({"P_max": p.peak, "x": p.peak / pair.P_Y,
                      "loading_approach": np.array([r["alpha"] for r in loading]),
                      "loading_force": np.maximum([r["P"] for r in loading], 0.0),
                      "unloading_approach": np.array([r["alpha"] for r in unloading]),
                      "unloading_force": np.maximum([r["P"] for r in unloading], 0.0),
                      "alpha_max": p.alpha_max, "alpha_residual": p.alpha_residual,
                      "radius_at_peak": float(loading[-1]["contact_radius"]),
                      "radius_at_peak_pressure": float(loading[-1]["contact_radius_pressure"]), "e": p.restitution})
        if rims:      # the path's unloading again (the same rows bit for bit) for its state at separation
            separated = unloading_path(solver, plan, p.peak, p.peak_state).final_state
            paths[-1].update(residual_rim(solver, separated.displacement, p.alpha_residual))
    return {"pair": pair, "paths": paths, "cycle": cycle, "mesh": dataclasses.asdict(spec.mesh),
            "elements_per_contact_radius": elements_per_contact_radius, "kinematics": kinematics,
            "dofs": int(solver.basis.N) if hasattr(solver, "basis") else None,
            "wall_time_s": time.perf_counter() - t0}


def residual_rim(solver, displacement, dent: float) -> dict:
    """The residual imprint of the module doc from the surface candidates' displacement [m] at
    separation: ``rim`` and ``lip`` (its crest) [m], ``lip_height`` = max w / alpha_res [-]."""
    nodes = solver.candidate_nodes
    z0 = solver.node_z[nodes]
    z = z0 + displacement[solver.z_dof[nodes]]
    r = solver.candidate_r
    w = ((z0 - z0[0]) - (z - z[0])) / dent
    i = int(np.argmax(w >= 1.0))
    rim = r[i - 1] + (1.0 - w[i - 1]) * (r[i] - r[i - 1]) / (w[i] - w[i - 1]) if i > 0 else float("nan")
    near = np.nonzero((np.arange(r.size) >= i) & (r <= 3.0 * rim))[0]      # the lip, not the far surface
    crest = int(near[np.argmax(w[near])]) if near.size else i
    return {"residual_rim": float(rim), "residual_lip": float(r[crest]), "lip_height": float(w[crest])}


def laws_of(table: VZMasterTable, material: Material, R: float) -> dict:
    """The master table's laws (LAWS) of a sphere of ``material`` and radius R [m] on a rigid flat."""
    return {"vz-unload": table.unload_law(material, R), "vz-table": table.law(material, R)}


def compare(laws: dict, run: dict) -> dict:
    """Per path and law the figures of the module doc (``paths``), and per law the cycle's (``cycle``)."""
    from calib.fit.cycle_check import cycles_against_law
    from calib.fit.unload_check import unload_against_path

    out = {"paths": [], "cycle": {}}
    for path in run["paths"]:
        row = {"x": path["x"], "P_max": path["P_max"], "radius_fe": path["radius_at_peak"],
               "dent_fe_over_alpha_max": path["alpha_residual"] / path["alpha_max"], "e_fe": path["e"]}
        for name, law in laws.items():
            row[name] = unload_against_path(name, law, path)
        out["paths"].append(row)
    cycle = run["cycle"]
    if cycle is not None:
        for name, law in laws.items():
            out["cycle"][name] = cycles_against_law(name, law, cycle.rows, cycle.P_max, cycle.alpha_residual)
            out["cycle"][name]["radius_error"] = cycle_radius_error(name, law, cycle.rows, cycle.P_max)
        out["cycle_x"] = cycle.P_max / run["pair"].P_Y
    return out


def mesh_spread(fine: dict, coarse: dict) -> dict:
    """The two meshes' FE figures at each common peak: radius, dent and e changes (coarse / fine - 1)
    and the largest unloading force change [of P_max] at the fine mesh's unloading approaches."""
    out = []
    for f, c in zip(fine["paths"], coarse["paths"]):
        down_a, down_P = c["unloading_approach"][::-1], c["unloading_force"][::-1]
        inside = (f["unloading_approach"] >= down_a[0]) & (f["unloading_approach"] <= down_a[-1])
        P_c = np.interp(f["unloading_approach"][inside], down_a, down_P)
        out.append({"x": f["x"], "radius": c["radius_at_peak"] / f["radius_at_peak"] - 1.0,
                    "dent": c["alpha_residual"] / f["alpha_residual"] - 1.0, "e": c["e"] / f["e"] - 1.0,
                    "alpha_max": c["alpha_max"] / f["alpha_max"] - 1.0,
                    "unloading": float(np.abs(P_c - f["unloading_force"][inside]).max() / f["P_max"])
                    if inside.any() else None})
    return {"paths": out}


def cycle_radius_error(law_name: str, params, rows: list[dict], P_max: float) -> float:
    """The cycle radius error of the module doc: the law driven along the rows' approaches (one
    contact), max |a_law - a_FE| / a_FE(P_max) over the partial unloads and reloads (cycles 1..n)
    down to P = 0.2 P_max (below it the FE's edge spans the fewest elements)."""
    from calib.fit.cycle_check import drive_law

    _, radius, _ = drive_law(law_name, params, rows)
    cycle = np.array([r["cycle"] for r in rows])
    last = int(cycle.max())
    fe = np.array([r["contact_radius"] for r in rows])
    force = np.array([r["P"] for r in rows])
    peak = fe[(cycle == 0)][-1]
    partial = (cycle >= 1) & (cycle < last) & (force >= 0.2 * P_max * (1 - 1e-9))
    partial &= np.isin([r["branch"] for r in rows], ("unloading", "reloading"))
    return float(np.abs(radius[partial] - fe[partial]).max() / peak)

"""Builds the pair table (calib/data/pair_table.csv): the two-body FE over the rigid flat's, to the pair's reach.

A yielding sphere (E1, nu1, sigma_Y, R) on an elastic counter-body (E2, nu2) keeps the elastic contact of its Hertz
pair (E*, R*; Johnson 1985 eq. 4.22). What the counter-body changes after first yield is measured as two ratios of
the two-body FE (calib.fe.two_body) over the same sphere's rigid-flat FE, each on its own Hertz scales (P_Y,
delta_Y of its ContactPair), at equal P/P_Y, on the same mesh family in the same kinematics:

    Phi_D(s, P/P_Y)     = D_pair / D_rf      D = alpha / delta_Y on the loading branch   [-]
    Phi_e(s, P_max/P_Y) = e_pair / e_rf      e of a load-unload path (calib.fe.loadpath) [-]

over s = x / (1 + x) = E* / E2', x = E1' / E2', E' = E / (1 - nu^2) (s = 0: the rigid flat, both ratios 1; nu2
enters only through E2'), nu and E/sigma_Y (the contact size a/R* at a given P/P_Y). calib.fit.pair_table maps
the vz master table's rigid-flat law by them.

Cases: R = 0.1 m, sigma_Y = 100 MPa, E = sigma_Y (E/sigma_Y), nu2 = nu1, the counter an elastic flat:
nu in NUS, E/sigma_Y in E_OVER_SIGMA_YS, x in XS (PCHIP in s through s = 0 from these three matches the ratios
measured at x = 1/2 and 2 within 0.1 points to 41 P_Y; x = 1/2 extends the reach of the small x), finite-strain sphere (the counter-body stays linear
small strain), each pair to its reach (recipe.fe_reach: P <= 1000 P_Y, estimated a <= 0.2 R*), its rigid flat to
the largest of its pairs' tops. Mesh: graded, every contact radius from the lowest peak up spans
ELEMENTS_PER_CONTACT_RADIUS elements; the loading branch LOADING_STEPS_PER_DECADE geometric steps a decade,
unloading paths at PEAKS_OVER_YIELD below the top and at the top.

The held-out checks (CHECKS: materials, stiffness ratios and a counter-sphere off the table's nodes) run the
two-body FE alone, to be compared with the mapped law (calib.fit.pair_table.check_rows).

    python -m calib.fit.pair_table_build [--out results/pairs] [--workers 2] [--table-out calib/data/pair_table.csv]

Each FE case is one resumable task (``OUT/pair_table_cases/<key>.json``, calib.sweep.runner) keeping its FE data.
"""
from __future__ import annotations

import dataclasses
import time
from fractions import Fraction
from pathlib import Path

import numpy as np

from calib import output
from calib.fit import recipe
from calib.fit.counter import CounterBody
from meshes.keys import stable_key
from nfdmodel import ContactPair, Material

SIGMA_Y, R, RHO = 100e6, 0.1, 7800.0
NUS = (0.2, 0.3, 0.45)
E_OVER_SIGMA_YS = (200.0, 600.0, 2000.0)
XS = ("1/3", "1/2", "1", "3")                # E1'/E2', exact fractions
PEAKS_OVER_YIELD = (2.0, 5.0, 13.7, 41.2, 100.0, 300.0, 1000.0)
ELEMENTS_PER_CONTACT_RADIUS = 10.0
KINEMATICS = "finite-strain"
REACH_SAFETY = 0.97                          # the top: this fraction of the estimated reach when it binds
RIGID = "rigid"
VERSION = 1                                  # part of each task's key: bump when the FE or the plan changes
# Held-out checks: (nu, E/sigma_Y, x, counter R / R or None for a flat): an aluminium alloy, a brass and a steel on
# a steel floor, a sphere on a softer flat, two like-sized unlike spheres.
CHECKS = ((0.33, 250.0, "0.335", None), (0.34, 400.0, "0.49", None), (0.29, 1200.0, "1", None),
          (0.27, 1200.0, "2", None), (0.3, 400.0, "1", 1.0))


def material(nu: float, E_over_sigma_y: float) -> Material:
    return Material(SIGMA_Y * E_over_sigma_y, nu, SIGMA_Y, RHO)


def stiffness_ratio(x: str) -> float:
    return float(Fraction(x))


def counter(task: dict) -> CounterBody | None:
    """The elastic counter-body of E1'/E2' = x (nu2 = nu1, so E2 = E1 / x); None for the rigid flat."""
    if task["x"] == RIGID:
        return None
    radius = task.get("counter_R_over_R")
    return CounterBody(SIGMA_Y * task["E_over_sigma_y"] / stiffness_ratio(task["x"]), task["nu"],
                       R=None if radius is None else radius * R, rho=RHO)


def pair_of(task: dict) -> ContactPair:
    body, m = counter(task), material(task["nu"], task["E_over_sigma_y"])
    return ContactPair.sphere_flat(m, R) if body is None else body.pair(m, R)


def reach_over_yield(task: dict) -> float:
    """The case's top P/P_Y: 1000, or REACH_SAFETY of the two-body FE's estimated reach (3 digits)."""
    pair = pair_of(task)
    reach = recipe.fe_reach(pair) / pair.P_Y
    return 1000.0 if reach >= 1000.0 else float(f"{REACH_SAFETY * reach:.3g}")


def spec_of(task: dict) -> recipe.CalibrationSpec:
    """The recipe's spec of a case (module doc): graded mesh from the lowest peak's estimated contact radius,
    the geometric loading branch, unloading at the peaks below the top and at the top (``task["peaks"]``)."""
    from calib.fit.impact_window import LOADING_STEPS_PER_DECADE, GeometricLoadPathPlan

    pair = pair_of(task)
    peaks = tuple(p * pair.P_Y for p in task["peaks"])
    graded_from = recipe.estimated_contact_radius(pair, peaks[0])
    spec = recipe.calibration_spec(material(task["nu"], task["E_over_sigma_y"]), R, peaks=(peaks[-1],),
                                   loading_steps=1, counter=counter(task), kinematics=KINEMATICS,
                                   graded_from=graded_from, elements_per_contact_radius=ELEMENTS_PER_CONTACT_RADIUS)
    return dataclasses.replace(spec, plan=GeometricLoadPathPlan(
        peaks=peaks, loading_step=peaks[-1], unloading_steps=spec.plan.unloading_steps,
        first_load=min(spec.plan.first_load, peaks[0]), loading_ratio=10.0 ** (1.0 / LOADING_STEPS_PER_DECADE)))


def peaks_to(top: float, extra=()) -> list[float]:
    return sorted({p for p in PEAKS_OVER_YIELD if p < top * (1 - 1e-9)} | {top} | set(extra))


def case_task(nu: float, E_over_sigma_y: float, x: str, peaks, role: str, counter_R_over_R=None) -> dict:
    case = {"nu": float(nu), "E_over_sigma_y": float(E_over_sigma_y), "x": x, "peaks": [float(p) for p in peaks],
            "role": role, "counter_R_over_R": counter_R_over_R}
    return {"key": stable_key({**case, "version": VERSION, "mesh": spec_of(case).mesh.cache_key()}), **case}


def all_tasks() -> list[dict]:
    """The table's pairs, their rigid flats (peaks: every pair top of that material), the held-out checks."""
    tasks = []
    for nu in NUS:
        for ratio in E_OVER_SIGMA_YS:
            tops = {x: reach_over_yield({"nu": nu, "E_over_sigma_y": ratio, "x": x}) for x in XS}
            tasks += [case_task(nu, ratio, x, peaks_to(top), "table") for x, top in tops.items()]
            tasks.append(case_task(nu, ratio, RIGID, peaks_to(max(tops.values()), tops.values()), "table"))
    for nu, ratio, x, radius in CHECKS:
        top = reach_over_yield({"nu": nu, "E_over_sigma_y": ratio, "x": x, "counter_R_over_R": radius})
        tasks.append(case_task(nu, ratio, x, peaks_to(top), "check", radius))
    return sorted(tasks, key=lambda t: (t["role"] == "check", t["E_over_sigma_y"], t["nu"]))   # the cheap ones first


def build_meshes(tasks: list[dict]) -> None:
    """Mesh every task here, one at a time (gmsh is a process-wide singleton): workers read the cache."""
    from meshes.counter_body import pair_mesh
    from meshes.hemisphere import hemisphere_mesh

    for task in tasks:
        spec = spec_of(task)
        if spec.counter is None:
            hemisphere_mesh(spec.mesh)
        else:
            pair_mesh(spec.mesh, spec.counter.mesh_spec(spec.mesh))


def run_task(task: dict) -> dict:
    """The FE load paths of one case (no fit), in units of its pair's P_Y, delta_Y, R*; never raises."""
    from threadpoolctl import threadpool_limits

    from calib.fe.loadpath import run_load_paths
    from calib.fit.calibration import _body_meshes, _solver

    t0 = time.perf_counter()
    try:
        spec = spec_of(task)
        pair = spec.pair
        with threadpool_limits(limits=1, user_api="blas"):
            solver = _solver(spec, _body_meshes(spec))
            paths = run_load_paths(solver, spec.plan, unload=True)
        loading = [[r["P"] / pair.P_Y, r["alpha"] / pair.delta_Y, r["contact_radius"] / pair.R_star]
                   for r in paths.loading_rows]
        record = {"loading": loading, "dofs": int(solver.n_dofs), "contact_size": spec.mesh.contact_size,
                  "paths": [{"P_max_over_P_Y": p.peak / pair.P_Y, "e": p.restitution,
                             "rows": [[r["alpha"] / pair.delta_Y, r["P"] / pair.P_Y] for r in p.rows]}
                            for p in paths.paths]}
    except Exception as exc:                    # noqa: BLE001 - reported in the row, retried next run
        return {**task, "status": "failed", "error": f"{type(exc).__name__}: {exc}"[:400],
                "wall_time_s": time.perf_counter() - t0}
    return {**task, "status": "ok", **record, "wall_time_s": time.perf_counter() - t0,
            "git_commit": output.git_commit()}


def run(out, workers: int = 2, progress=None):
    """Every case through the sweep runner (resumable); returns the SweepResult."""
    from calib.sweep.runner import run_sweep

    tasks = all_tasks()
    build_meshes(tasks)
    return run_sweep(tasks, run_task, Path(out) / "pair_table_cases",
                     keep=lambda row: row.get("status") == "ok", workers=workers, progress=progress,
                     describe=lambda row: (f"{row['role']} nu {row['nu']:g} E/sigma_Y {row['E_over_sigma_y']:g} "
                                           f"x {row['x']} to {row['peaks'][-1]:g} P_Y ({row['status']}, "
                                           f"{row['wall_time_s']:.0f} s)"))

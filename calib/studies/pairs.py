"""What the rigid-flat substitution costs for unlike bodies, against the two-body FE: results/pairs/*

nfdmodel.ContactPair mixes a sphere (E1, nu1, sigma_Y1, R1) with a counter-body (E2, nu2, sigma_Y2 or
elastic, R2 or a flat) by putting the pair's

    1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2,   1/R* = 1/R1 + 1/R2        (Johnson 1985 eq. 4.22)

and the yield point of the body with the lower A_Y(nu) sigma_Y into the rigid-flat law, with that
body's rigid-flat constants ("the substitution"). The law is self-similar in P/P_Y, alpha/delta_Y and
a/a_Y (Vu-Quoc & Zhang 1999 eqs. 2.5, 3.6, 3.7), so the substitution predicts the pair's FE from the
yielding body's rigid-flat FE rescaled by the pair's P_Y, delta_Y, a_Y:

    P_sub(alpha)  = P_Y f(alpha / delta_Y)       f: the rigid-flat FE's P/P_Y against alpha/delta_Y
    a_sub(P)      = a_Y g(P / P_Y)               g: its a/a_Y against P/P_Y (loading)
    e_sub(P_max)  = e_rf(P_max / P_Y)            its restitution at the same P_max / P_Y

This study measures that against the two-body FE (calib.fe.two_body; e from each load-unload path by
calib.fe.loadpath.contact_work, as every calibration): per case the relative errors

    force error  = P_sub(alpha) / P_FE(alpha) - 1    at equal approach, loading points P >= P_Y
    radius error = a_sub(P) / a_FE(P) - 1            at equal force, the same points
    e error      = e_sub / e_FE - 1                  per path, P_max = 13.7, 27.4, 41.2 P_Y

(the law-free substitution: what a perfect rigid-flat law would carry over), and the same for what
nfdmodel ships: the two-constant vz law with the rigid-flat radius fit's Ca_hat, Kc_hat on the pair's
scales, driven along the pair FE's approach (``law_*``, with the law against its own rigid-flat FE as
``law_*_rigid``: the fit's own error, which a pair calibration keeps).

Grid: the sphere R1 = 0.1 m, E1 = 70 GPa, nu = 0.3 for both bodies; E1/E2 = 1/3, 1/2, 1, 2, 3; the
counter-body a flat or a sphere R2 = R1; which body yields: the sphere (counter elastic), the counter-body
(sphere elastic) or both (equal sigma_Y: both yield from the same load). Every body that yields first has
E/sigma_Y = 700 (the paper's aluminium), so one rigid-flat FE (E/sigma_Y = 700, nu = 0.3) is the
substitution's reference for every case. Load window: the calibration recipe's (calib.fit.recipe): paths
to 13.7, 27.4 and 41.2 P_Y of the pair, 16 loading steps to the first, 16 unloading steps. Mesh: the
recipe's ``coarse`` level (contact element a_max/10, both bodies) for the grid; one case (aluminium on a
steel-like flat, E1/E2 = 1/3, the sphere yielding) and the rigid flat again at ``default`` (a_max/37)
state the grid's mesh error.

    python -m calib.studies.pairs [--out results/pairs] [--workers 2] [--level coarse]

Each FE case is one resumable task (``OUT/cases/<key>.json``, calib.sweep.runner) keeping its FE data; the
comparison runs again from them (seconds). Writes OUT/pairs.csv, pairs.json, pairs.png and the measured map
calib/data/substitution_error.csv (read by calib.fit.substitution to steer users to a pair calibration).
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_limits

from calib import output
from calib.fe.loadpath import LoadPathPlan, run_load_paths
from calib.fit import recipe
from calib.fit.counter import CounterBody
from calib.fit.path_check import law_against_path
from calib.sweep.runner import run_sweep
from meshes.keys import stable_key
from nfdmodel import ContactPair, Material, VZParams

RATIOS = (1.0 / 3.0, 0.5, 1.0, 2.0, 3.0)      # E1 / E2
YIELDING = ("sphere", "counter", "both")       # which body has a yield stress
SHAPES = ("flat", "sphere")                    # the counter-body: a flat, or a sphere R2 = R1
E1, NU, RHO, R1 = 70e9, 0.3, 2699.0, 0.1
E_OVER_SIGMA_Y = 700.0                         # every first-yielding body: the paper's aluminium
# the "elastic" sphere's nominal sigma_Y for ContactPair (which needs one): E/20, the largest a calibration
# accepts (calib.fit.recipe.E_OVER_SIGMA_Y_RANGE); its FE is elastic, and A_Y E1/20 is 5x the counter's
# largest yield pressure in the grid, so the pair takes the counter's yield point
ELASTIC_SPHERE_E_OVER_SIGMA_Y = recipe.E_OVER_SIGMA_Y_RANGE[0]
PEAKS_OVER_YIELD = recipe.DEFAULT_PEAKS_OVER_YIELD
LEVEL, CHECK_LEVEL = "coarse", "default"
CHECK_CASE = {"E1_over_E2": 1.0 / 3.0, "yielding": "sphere", "shape": "flat"}
STEER_E_ERROR = 0.02                           # |e error| beyond which users are steered to a pair calibration
VERSION = 1                                    # part of each task's key: bump when the FE or the plan changes
DATA_FILE = Path(__file__).resolve().parents[1] / "data" / "substitution_error.csv"


# ----------------------------------------------------------------------------- cases
def case_bodies(E1_over_E2: float, yielding: str, shape: str) -> dict:
    """The two bodies of one case: the sphere's Material (a nominal sigma_Y when elastic), whether it
    yields, and the counter-body (calib.fit.counter.CounterBody)."""
    if yielding not in YIELDING:
        raise ValueError(f"yielding must be one of {', '.join(YIELDING)}, got {yielding!r}")
    if shape not in SHAPES:
        raise ValueError(f"shape must be one of {', '.join(SHAPES)}, got {shape!r}")
    E2 = E1 / E1_over_E2
    sigma_1 = E1 / (E_OVER_SIGMA_Y if yielding != "counter" else ELASTIC_SPHERE_E_OVER_SIGMA_Y)
    sigma_2 = {"sphere": None, "counter": E2 / E_OVER_SIGMA_Y, "both": sigma_1}[yielding]
    return {"sphere": Material(E1, NU, sigma_1, RHO), "sphere_yields": yielding != "counter",
            "counter": CounterBody(E2, NU, sigma_2, None if shape == "flat" else R1)}


def case_pair(case: dict) -> ContactPair:
    """The substitution's pair (nfdmodel.ContactPair.sphere_counter) of a case."""
    bodies = case_bodies(case["E1_over_E2"], case["yielding"], case["shape"])
    return bodies["counter"].pair(bodies["sphere"], R1)


def rigid_pair() -> ContactPair:
    """The yielding body's rigid-flat pair: E/sigma_Y = 700, nu = 0.3, R = R1."""
    return ContactPair.sphere_flat(Material(E1, NU, E1 / E_OVER_SIGMA_Y, RHO), R1)


# a task's plan: the study's (the recipe's) unless the task says otherwise (the tests' shorter paths)
PLAN = {"peaks_over_yield": PEAKS_OVER_YIELD, "steps_to_first_peak": recipe.LOADING_STEPS_TO_FIRST_PEAK,
        "unloading_steps": recipe.UNLOADING_STEPS}


def load_plan(pair: ContactPair, task: dict | None = None) -> LoadPathPlan:
    """The calibration recipe's load paths in units of the pair's P_Y (calib.fit.recipe), or the task's."""
    plan = {k: (task or {}).get(k, v) for k, v in PLAN.items()}
    peaks = tuple(float(k * pair.P_Y) for k in plan["peaks_over_yield"])
    return LoadPathPlan(peaks=peaks, loading_step=peaks[0] / plan["steps_to_first_peak"],
                        unloading_steps=plan["unloading_steps"], first_load=0.5 * pair.P_Y)


def meshes(pair: ContactPair, level, counter: CounterBody | None = None, top_over_yield: float | None = None) -> tuple:
    """(the sphere's mesh, the counter-body's or None) of the recipe's ``level`` (or a contact element of
    ``level`` x a_max when a number) for the pair's largest load."""
    a_max = recipe.estimated_contact_radius(pair, (top_over_yield or PEAKS_OVER_YIELD[-1]) * pair.P_Y)
    sphere = (recipe.mesh_for(R1, a_max, level=level) if isinstance(level, str)
              else recipe.mesh_for(R1, a_max, contact_size_over_a_max=float(level)))
    return sphere, (None if counter is None else counter.mesh_spec(sphere))


def _task_meshes(task: dict, pair: ContactPair, counter=None) -> tuple:
    return meshes(pair, task["level"], counter, max(task.get("peaks_over_yield", PEAKS_OVER_YIELD)))


def _plan_key(plan: dict) -> dict:
    """The plan's part of a task key: the peaks, and the steps only when not the study's."""
    return {"peaks": tuple(plan.get("peaks_over_yield", PEAKS_OVER_YIELD)),
            **{k: v for k, v in plan.items() if k != "peaks_over_yield" and v != PLAN[k]}}


def case_task(E1_over_E2: float, yielding: str, shape: str, level=LEVEL, **plan) -> dict:
    case = {"E1_over_E2": float(E1_over_E2), "yielding": yielding, "shape": shape, "level": level}
    bodies = case_bodies(E1_over_E2, yielding, shape)
    sphere_mesh, counter_mesh = _task_meshes({**case, **plan}, case_pair(case), bodies["counter"])
    key = stable_key({**case, "version": VERSION, "meshes": [sphere_mesh.cache_key(), counter_mesh.cache_key()],
                      **_plan_key(plan)})
    return {"key": key, "kind": "pair", **case, **plan}


def rigid_task(level=LEVEL, **plan) -> dict:
    sphere_mesh, _ = _task_meshes({"level": level, **plan}, rigid_pair())
    key = stable_key({"rigid": True, "level": level, "version": VERSION, "mesh": sphere_mesh.cache_key(),
                      **_plan_key(plan)})
    return {"key": key, "kind": "rigid", "level": level, **plan}


def grid_tasks(level: str = LEVEL, ratios=RATIOS, yielding=YIELDING, shapes=SHAPES) -> list[dict]:
    return [case_task(r, y, s, level) for s in shapes for y in yielding for r in ratios]


def build_meshes(tasks: list[dict]) -> None:
    """Mesh every task here, one at a time (gmsh is a process-wide singleton): workers read the cache."""
    from meshes.counter_body import pair_mesh
    from meshes.hemisphere import hemisphere_mesh

    for task in tasks:
        if task["kind"] == "rigid":
            hemisphere_mesh(_task_meshes(task, rigid_pair())[0])
        else:
            counter = case_bodies(task["E1_over_E2"], task["yielding"], task["shape"])["counter"]
            pair_mesh(*_task_meshes(task, case_pair(task), counter))


# ----------------------------------------------------------------------------- the FE
def _fe_record(paths, solver) -> dict:
    return {"loading": [{k: r[k] for k in ("P", "alpha", "contact_radius")} for r in paths.loading_rows],
            "paths": [{"P_max": p.peak, "e": p.restitution, "alpha_max": p.alpha_max,
                       "rows": [{k: r[k] for k in ("P", "alpha", "branch")} for r in p.rows]} for p in paths.paths],
            "dofs": int(solver.n_dofs)}


def run_task(task: dict) -> dict:
    """One FE case (runs in a worker; never raises: a failure is a row with its message)."""
    t0 = time.perf_counter()
    try:
        with threadpool_limits(limits=1, user_api="blas"):
            record = run_rigid(task) if task["kind"] == "rigid" else run_pair(task)
    except Exception as exc:                    # noqa: BLE001 - reported in the row, retried next run
        return {**task, "status": "failed", "error": f"{type(exc).__name__}: {exc}"[:400],
                "wall_time_s": time.perf_counter() - t0}
    return {**task, "status": "ok", **record, "wall_time_s": time.perf_counter() - t0,
            "git_commit": output.git_commit()}


def run_pair(task: dict) -> dict:
    """The two-body FE load paths of a case (calib.fe.two_body, the recipe's plan on the pair's P_Y)."""
    from calib.fe.elastic import ElasticMaterial
    from calib.fe.two_body import TwoBodySolver
    from calib.fe.von_mises import VonMisesMaterial
    from meshes.counter_body import pair_mesh

    bodies = case_bodies(task["E1_over_E2"], task["yielding"], task["shape"])
    sphere, counter = bodies["sphere"], bodies["counter"]
    pair = counter.pair(sphere, R1)
    sphere_fe = (VonMisesMaterial(sphere.E, sphere.nu, sphere.sigma_y) if bodies["sphere_yields"]
                 else ElasticMaterial(sphere.E, sphere.nu))
    sphere_mesh, counter_mesh = _task_meshes(task, pair, counter)
    solver = TwoBodySolver(pair_mesh(sphere_mesh, counter_mesh), sphere_fe, counter.fe_material(),
                           contact_radius_method="gap")
    paths = run_load_paths(solver, load_plan(pair, task))
    return {"fe": _fe_record(paths, solver), "contact_size": sphere_mesh.contact_size,
            "P_Y": pair.P_Y, "E_star": pair.E_star, "R_star": pair.R_star}


def run_rigid(task: dict) -> dict:
    """The yielding body's rigid-flat calibration (calib.fit.calibration, one mesh): its FE paths and
    the radius fit's Ca_hat, Kc_hat (what ``nfdcal calibrate`` ships)."""
    from calib.fit.calibration import calibrate, summary

    pair = rigid_pair()
    sphere_mesh, _ = _task_meshes(task, pair)
    spec = recipe.CalibrationSpec(material=Material(E1, NU, E1 / E_OVER_SIGMA_Y, RHO), radius=R1,
                                  mesh=sphere_mesh, plan=load_plan(pair, task))
    result = calibrate(spec, meshes=1)
    s = summary(result)
    return {"fe": _fe_record(result.load_paths, result.solver), "contact_size": sphere_mesh.contact_size,
            "P_Y": pair.P_Y, "E_star": pair.E_star, "R_star": pair.R_star,
            "Ca_hat": s["Ca_hat"], "Kc_hat": s["Kc_hat"], "window": s["window"]}


# ----------------------------------------------------------------------------- the comparison
def _scaled_loading(row: dict, pair: ContactPair) -> tuple:
    """(alpha/delta_Y, P/P_Y, a/a_Y) of the loading branch, from the origin."""
    rows = row["fe"]["loading"]
    x = np.array([0.0] + [r["alpha"] for r in rows]) / pair.delta_Y
    p = np.array([0.0] + [r["P"] for r in rows]) / pair.P_Y
    a = np.array([0.0] + [r["contact_radius"] for r in rows]) / pair.a_Y
    return x, p, a


def _path_arrays(path: dict) -> dict:
    return {"P_max": path["P_max"], "e": path["e"], "approach": np.array([r["alpha"] for r in path["rows"]]),
            "force": np.array([max(r["P"], 0.0) for r in path["rows"]])}


def compare(row: dict, rigid: dict) -> dict:
    """The substitution against one pair case's FE (module docstring): the law-free substitution and the
    vz law with the rigid-flat constants on the pair's scales."""
    pair, rpair = case_pair(row), rigid_pair()
    x, p, a = _scaled_loading(row, pair)
    xr, pr, ar = _scaled_loading(rigid, rpair)
    above = (p >= 1.0) & (x <= xr[-1])
    force_error = np.interp(x[above], xr, pr) / p[above] - 1.0
    reached = (p >= 1.0) & (p <= pr[-1] * (1 + 1e-9))
    radius_error = np.interp(p[reached], pr, ar) / a[reached] - 1.0
    rigid_e = {round(path["P_max"] / rpair.P_Y, 6): path["e"] for path in rigid["fe"]["paths"]}
    window = None
    params = VZParams.from_dimensionless(pair, rigid["Ca_hat"], rigid["Kc_hat"], window)
    rparams = VZParams.from_dimensionless(rpair, rigid["Ca_hat"], rigid["Kc_hat"], window)
    rigid_paths = {round(path["P_max"] / rpair.P_Y, 6): _path_arrays(path) for path in rigid["fe"]["paths"]}
    paths = []
    for path in row["fe"]["paths"]:
        k = round(path["P_max"] / pair.P_Y, 6)
        law = law_against_path("vz", params, _path_arrays(path))
        own = law_against_path("vz", rparams, rigid_paths[k])
        paths.append({"P_max_over_P_Y": k, "e_fe": path["e"], "e_sub": rigid_e[k], "e_error": rigid_e[k] / path["e"] - 1.0,
                      "alpha_max_over_delta_Y": path["alpha_max"] / pair.delta_Y,
                      "law_e": law["e_law"], "law_e_error": law["e_error"], "law_force_error": law["force_error"],
                      "law_e_error_rigid": own["e_error"], "law_force_error_rigid": own["force_error"]})
    e_errors = [q["e_error"] for q in paths]
    law_e = [q["law_e_error"] for q in paths]
    return {"E1_over_E2": row["E1_over_E2"], "yielding": row["yielding"], "shape": row["shape"],
            "E_star": pair.E_star, "R_star": pair.R_star, "P_Y": pair.P_Y,
            "force_error_min": float(force_error.min()), "force_error_max": float(force_error.max()),
            "force_error_top": float(force_error[-1]),
            "radius_error_min": float(radius_error.min()), "radius_error_max": float(radius_error.max()),
            "radius_error_top": float(radius_error[-1]),
            "e_error_min": min(e_errors), "e_error_max": max(e_errors),
            "law_e_error_min": min(law_e), "law_e_error_max": max(law_e),
            "law_e_error_rigid_max": max(abs(q["law_e_error_rigid"]) for q in paths),
            "law_force_error_max": max(q["law_force_error"] for q in paths),
            "law_force_error_rigid_max": max(q["law_force_error_rigid"] for q in paths),
            "paths": paths, "dofs": row["fe"]["dofs"], "contact_size": row["contact_size"],
            "wall_time_s": row["wall_time_s"]}


def _match(task: dict, case: dict) -> bool:
    return all(np.isclose(task[k], v) if isinstance(v, float) else task[k] == v for k, v in case.items())


def generate(out=output.RESULTS / "pairs", workers: int = 2, level: str = LEVEL, data_file=DATA_FILE,
             progress=None) -> dict:
    """Run (or resume) every case and the mesh check; write OUT/pairs.csv, .json, .png and ``data_file``."""
    from calib.studies import pairs_output

    out = Path(out)
    started = time.perf_counter()
    grid = grid_tasks(level)
    check = [case_task(CHECK_CASE["E1_over_E2"], CHECK_CASE["yielding"], CHECK_CASE["shape"], CHECK_LEVEL),
             rigid_task(CHECK_LEVEL)] if level != CHECK_LEVEL else []
    tasks = [rigid_task(level)] + grid + check
    build_meshes(tasks)
    sweep = run_sweep(tasks, run_task, out / "cases", keep=lambda row: row.get("status") == "ok",
                      workers=workers, progress=progress,
                      describe=lambda row: (f"{row['kind']} {row.get('shape', '')} {row.get('yielding', '')} "
                                            f"E1/E2 = {row.get('E1_over_E2', 1):.3g} ({row['status']}, "
                                            f"{row['wall_time_s']:.0f} s)"))
    by_key = {row["key"]: row for row in sweep.rows}
    rigid = by_key[tasks[0]["key"]]
    failures = [{k: row.get(k) for k in ("kind", "E1_over_E2", "yielding", "shape", "level", "error")}
                for row in sweep.rows if row["status"] != "ok"]
    rows = ([compare(by_key[t["key"]], rigid) for t in grid if by_key[t["key"]]["status"] == "ok"]
            if rigid["status"] == "ok" else [])
    mesh_check = None
    if check and all(by_key[t["key"]]["status"] == "ok" for t in check) and rigid["status"] == "ok":
        fine = compare(by_key[check[0]["key"]], by_key[check[1]["key"]])
        coarse = next((r for r in rows if _match(r, CHECK_CASE)), None)
        mesh_check = pairs_output.mesh_check(coarse, fine)
    wall = time.perf_counter() - started
    st = output.stamp(wall, mesh={"level": level, "contact_size_over_a_max": recipe.MESH_LEVELS[level]},
                      command="python -m calib.studies.pairs",
                      fe_wall_time_s=sum(row.get("wall_time_s", 0.0) for row in sweep.rows),
                      computed=sweep.computed, reused=sweep.reused)
    result = {"rows": rows, "failures": failures, "mesh_check": mesh_check, "stamp": st,
              "rigid_flat": {**{k: rigid.get(k) for k in ("Ca_hat", "Kc_hat", "window", "contact_size", "status", "error")},
                             "dofs": rigid.get("fe", {}).get("dofs")},
              "steer_e_error": STEER_E_ERROR}
    pairs_output.write(out, result, data_file)
    return result


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(output.RESULTS / "pairs"))
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--level", default=LEVEL, choices=tuple(recipe.MESH_LEVELS))
    ns = parser.parse_args(argv)
    from calib.studies.pairs_output import summary_lines

    result = generate(ns.out, workers=ns.workers, level=ns.level, progress=lambda m: print(m, file=sys.stderr))
    print("\n".join(summary_lines(result)))
    return 1 if result["failures"] else 0


if __name__ == "__main__":
    sys.exit(main())

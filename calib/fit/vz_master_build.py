"""Building the master table of the vz-table law from FE load-unload paths over the whole window.

In dimensionless form the vz-table law (nfdmodel.vz_table, calib.fit.table_fit) is two tables of
x = P/P_Y, the plastic radius f = a_p/a_Y and the curvature factor g = C_R, and for a sphere on a
rigid flat (small strain, peaks at multiples of P_Y) they depend only on nu and E/sigma_Y. Each node
(nu, E/sigma_Y) of the built-in scene ``vz_master_grid`` (calib/scenes/builtin/sweeps/vz_master_grid.toml)
is one calibration of ``nfdcal calibrate --v-max`` to the top of the scene's window, at most the
FE's reach (calib.fit.impact_window: unloading paths log-spaced from the lowest load its mesh
resolves to min(top, 1000 P_Y, a <= 0.2 R), loading stepped geometrically), on the scene's graded mesh
(``elements_per_contact_radius`` N and ``loading_steps_per_decade`` at level ``refinement``, as a
[[refine]] entry below; or, with ``contact_size_over_a_max``, a uniform contact element that
fraction of the largest contact radius) and, with ``meshes = 2``, on the mesh of contact element 2h
(calib.fit.extrapolation: node values Richardson-extrapolated, their
estimated relative error kept). The table stores f and g, and the vz-unload law's dent ratio
rho = delta_res/delta_max and unloading exponent m from each node's stored FE unloading paths
(calib.fit.unload_fit.unloading_nodes: rho = alpha_res/alpha_max, m = P_max (alpha_max - alpha_res)
/ W_u - 1; no FE run), resampled on common loads x_k
(NODES_PER_DECADE per decade from 1, and the top of each E/sigma_Y column; loads beyond a node's
window are empty) and each node's window [x_low, x_top].

Nodes of the scene's ``[[refine]]`` run again as a reference ladder (kind "refine"): graded
meshes (calib.fit.recipe.mesh_for: N elements across every contact radius from
TABLE_LOWEST_PEAK_OVER_P_Y x P_Y up) with ``loading_steps_per_decade``, refined
systematically by each ``refinement`` r (sizes / r, loading steps x r): against them
calib.fit.vz_master_check measures the table's discretisation error. The off-grid materials of the scene (``[[check]]``) run the same FE: their paths test the table
between its nodes in material and in load (calib.fit.vz_master_check) and are the data of the
fit-data benchmark (tests/benchmarks/fit_data_fe.py). Every node and check is one task of the one
sweep runner (calib.sweep.runner, ``OUT/nodes/<key>.json``): a rerun resumes, and the FE data of each
task (loading curve, each path's peak, e, loading and unloading work, unloading branch) is kept. A
one-mesh task's tables are refitted from those data on every run (:func:`refit_row`, no FE): its
works from the histories as the FE takes them (calib.fe.loadpath.contact_work), its tables by
calib.fit.table_fit; ``fit_version`` in the row says which fit it holds.

A node record keeps its loading rows' FE contact radius; for a record without it the node's loading
branch runs again alone (kind "loading", :func:`run_loading`: the node's spec, no unloading,
``OUT/loading/<key>.json``, the same sweep runner), its rows' force and approach the node's bit for bit
and with them the FE's contact radius. From it the vz-unload law's own radius f_a
(:func:`resample_radius`): f is fitted to the force and the returned work and overstates the FE's
radius by 1-6 %.

    nfdcal table vz_master_grid [--workers 2] [--out results/tables/vz_master_grid]
        [--master-out calib/data/vz_master_table.csv]
"""
from __future__ import annotations

import dataclasses
import time
from pathlib import Path
from typing import Callable

import numpy as np

from calib import output
from calib.fe.flow_curve import LinearHardening
from calib.fe.kinematics import DEFAULT_KINEMATICS
from calib.fit import impact_window, recipe
from calib.fit.calibration import calibrate
from calib.fit.vz_master_scene import (GRADED_KEYS, POWER_LAWS, TABLE_LOWEST_PEAK_OVER_P_Y, X_LIMIT, grid_mesh,
                                       loading_steps_of)
from calib.fit.vz_master_table import RADIUS_COLUMN
from meshes.keys import stable_key
from nfdmodel import CalibrationWindow, ContactPair, Material
from nfdmodel.window import FINITE_STRAIN
from nfdmodel.pchip import pchip_evaluate, pchip_slopes

SCENE = "vz_master_grid"
NODES_PER_DECADE = 8            # common table loads per decade of P/P_Y
TOP_MERGE = 0.02                # column tops (and common loads) closer than this, relative: one load
REACH_MARGIN = 1e-6             # the top load this far inside the FE's reach (its check is exact)
TASK_VERSION = 1                # part of a task's key: bump when the FE changes
FIT_VERSION = 2                 # the fit a row holds (1: trapezoid works; 2: Hertz's end segments), refit_row


def common_loads(limit: float = X_LIMIT) -> np.ndarray:
    """x_k = P/P_Y of the table: 1, then NODES_PER_DECADE per decade up to ``limit`` (X_LIMIT)."""
    n = int(round(NODES_PER_DECADE * np.log10(limit)))
    return np.geomspace(1.0, limit, n + 1)


def hardening_of(item: dict, material: Material):
    """The flow curve of a task or record (linear from H_over_E, or its power law), None if perfectly plastic."""
    if item.get("power_law"):
        law = item["power_law"]
        return POWER_LAWS[law["flow_curve"]](material.sigma_y, law["K_over_sigma_y"] * material.sigma_y, law["n"])
    if item.get("H_over_E", 0.0) > 0.0:
        return LinearHardening(material.sigma_y, item["H_over_E"] * material.E)
    return None


def task(scene: dict, nu: float, ratio: float, kind: str, name: str | None = None, refine: dict | None = None,
         top_over_P_Y: float | None = None, H_over_E: float = 0.0, power_law: dict | None = None) -> dict:
    """One calibration at the FE's reach (kind "node", "check" to ``top_over_P_Y`` or the scene's
    check top, or "refine": the node on the graded
    mesh of ``refine``, a [[refine]] entry: N elements across every contact radius, refined
    systematically by r, sizes / r and loading steps x r). Nodes and checks take the grid's graded
    mesh (its N, steps and r) unless the scene sets contact_size_over_a_max (a uniform mesh); a
    node is then the same task as the refined node of its level (the same key). ``H_over_E`` > 0: a sphere
    of linear isotropic hardening, sigma_y = sigma_Y + H eps_p with H = H_over_E E (its key names it; a
    perfectly plastic task's key is the grid's). ``power_law``: a check's Swift or Ludwik flow curve instead
    (calib.fit.vz_master_scene.power_law_of)."""
    material = Material(ratio * scene["sigma_y"], nu, scene["sigma_y"], scene["rho"])
    node_like = kind in ("node", "refine")
    if kind == "refine":
        name = name or (f"nu{nu:g}_E{ratio:g}sy_graded{refine['elements_per_contact_radius']:g}"
                        f"_r{refine['refinement']:g}" + ("" if refine.get("ladder", "both") == "both"
                                                         else f"_S{loading_steps_of(refine):.3g}"))
    else:
        refine = grid_mesh(scene)
    fields = {"nu": nu, "E_over_sigma_y": ratio, "sigma_y": scene["sigma_y"], "rho": scene["rho"],
              "R": scene["R"], "level": scene["level"], "version": TASK_VERSION,
              "contact_size_over_a_max": None if refine else scene["contact_size_over_a_max"],
              "top_over_P_Y": scene["top_over_P_Y"] if node_like else (top_over_P_Y or scene["check_top_over_P_Y"]),
              "meshes": scene["meshes"] if node_like else scene["check_meshes"]}
    if refine:
        fields.update({key: refine[key] for key in GRADED_KEYS})
    if scene["kinematics"] != DEFAULT_KINEMATICS:       # keys of small-strain tasks stay as they are
        fields.update(kinematics=scene["kinematics"], lowest_over_P_Y=lowest_over_P_Y(scene, material))
    if H_over_E > 0.0:                                  # keys of perfectly plastic tasks stay as they are
        fields["H_over_E"] = H_over_E
    if power_law:
        fields["power_law"] = power_law
    name = name or (f"nu{nu:g}_E{ratio:g}sy" + (f"_H{H_over_E:g}E" if H_over_E > 0.0 else ""))
    return {"key": stable_key(fields), "kind": kind, "name": name, "material": material, **fields}


def lowest_over_P_Y(scene: dict, material: Material) -> float:
    """The lowest unloading path of a task [P_Y]: TABLE_LOWEST_PEAK_OVER_P_Y, or (a scene with
    ``lowest_a_over_R``) the load whose FE contact radius (recipe.fe_contact_radius) is that fraction of R,
    between TABLE_LOWEST_PEAK_OVER_P_Y and ``lowest_max_over_P_Y``: a finite-strain reach scene starts where
    its contact is still small enough that small strain holds (recipe.KINEMATICS_PART_OVER_R) and joins the
    small-strain table there."""
    if scene["lowest_a_over_R"] is None:
        return TABLE_LOWEST_PEAK_OVER_P_Y
    pair = ContactPair.sphere_flat(material, scene["R"])
    load = recipe.largest_admissible_load(pair, scene["lowest_a_over_R"], recipe.fe_contact_radius) / pair.P_Y
    return float(min(max(load, TABLE_LOWEST_PEAK_OVER_P_Y), scene["lowest_max_over_P_Y"]))


def tasks_for(scene: dict) -> list[dict]:
    """The refined nodes, the finest (longest) first so that two workers end together, then the
    grid's nodes and the off-grid checks, the softer materials first (their reach, and so their FE,
    is the smallest: a partial run has whole E/sigma_Y columns). A refined node that is a node's
    own task (the same key) runs once, as the node."""
    nodes = [task(scene, nu, r, "node", H_over_E=h) for nu in scene["nu"] for r in scene["E_over_sigma_y"]
             for h in scene["H_over_E"]]
    checks = [task(scene, c["nu"], c["E_over_sigma_y"], "check", c["name"], top_over_P_Y=c["top_over_P_Y"],
                   H_over_E=c["H_over_E"], power_law=c["power_law"]) for c in scene["checks"]]
    node_keys = {t["key"] for t in nodes}
    ladder = {}
    for level in scene["refine"]:               # a level two ladders share runs once, under its first name
        refined = task(scene, level["nu"], level["E_over_sigma_y"], "refine", refine=level)
        ladder.setdefault(refined["key"], refined)
    refined = sorted((t for t in ladder.values() if t["key"] not in node_keys),
                     key=lambda t: (-t["refinement"], -t["E_over_sigma_y"]))
    return refined + sorted(nodes + checks, key=lambda t: t["E_over_sigma_y"])


def in_scene_words(rows: list[dict], tasks: list[dict]) -> list[dict]:
    """Each record whose key is one of ``tasks`` with that task's kind and name: what a record is (node,
    check, refined level) is the scene's word, and a level computed first for a ladder can be a node of a
    later recipe (the same FE, the same key)."""
    by_key = {t["key"]: t for t in tasks}
    return [{**r, "kind": by_key[r["key"]]["kind"], "name": by_key[r["key"]]["name"]} if r.get("key") in by_key
            else r for r in rows]


def task_spec(item: dict, pair: ContactPair) -> recipe.CalibrationSpec:
    """The CalibrationSpec of a task: its window to the FE's reach or its top, on its mesh."""
    kinematics = item.get("kinematics", DEFAULT_KINEMATICS)
    top = min(recipe.fe_reach(pair, kinematics) * (1.0 - REACH_MARGIN),      # inside the reach despite rounding
              item["top_over_P_Y"] * pair.P_Y)
    if item.get("refinement"):          # the graded, systematically refined ladder
        mesh = {"elements_per_contact_radius": item["elements_per_contact_radius"],
                "refinement": item["refinement"],
                "loading_steps_per_decade": loading_steps_of(item)}
    elif item["contact_size_over_a_max"]:
        mesh = {"contact_size_over_a_max": item["contact_size_over_a_max"]}
    else:
        mesh = {"level": item["level"]}
    spec = impact_window.window_spec(item["material"], item["R"], top,
                                     lowest_over_P_Y=item.get("lowest_over_P_Y", TABLE_LOWEST_PEAK_OVER_P_Y),
                                     kinematics=kinematics, **mesh)
    hardening = hardening_of(item, item["material"])
    if hardening is not None:
        spec = dataclasses.replace(spec, hardening=hardening)
    return spec


def run_task(item: dict) -> dict:
    """The calibration of one task (runs in a worker; never raises: a failure is a row)."""
    material, R = item["material"], item["R"]
    pair = ContactPair.sphere_flat(material, R)
    t0 = time.perf_counter()
    try:
        spec = task_spec(item, pair)
        result = calibrate(spec, ship="table", meshes=item["meshes"], parallel=False)
        table = result.fit_table()
        fine = result.fine_table()
    except Exception as exc:                    # noqa: BLE001 - reported in the row, retried next run
        return {"key": item["key"], "status": "failed", "name": item["name"],
                "error": f"{type(exc).__name__}: {exc}"[:300]}
    paths = result.load_paths
    return {"key": item["key"], "status": "ok", "kind": item["kind"], "name": item["name"],
            "nu": item["nu"], "E_over_sigma_y": item["E_over_sigma_y"], "sigma_y": item["sigma_y"],
            **({"H_over_E": item["H_over_E"]} if item.get("H_over_E", 0.0) > 0.0 else {}),
            **({"power_law": item["power_law"]} if item.get("power_law") else {}),
            "rho": item["rho"], "R": R, "level": item["level"], "meshes": item["meshes"],
            "P_Y": pair.P_Y, "a_Y": pair.a_Y, "delta_Y": pair.delta_Y, "P_Y_fe": result.P_Y_fe,
            "table": {"x": list(table.x), "f": list(table.f), "g": list(table.g)},
            "fine_table": {"x": list(fine.x), "f": list(fine.f), "g": list(fine.g)},
            "window": table.window.record(),
            "table_rel_error_estimate": result.table_rel_error_estimate(),
            "loading": {key: [r[key] for r in paths.loading_rows] for key in ("P", "alpha", "contact_radius")},
            "paths": [{"P_max": p.peak, "alpha_max": p.alpha_max, "alpha_residual": p.alpha_residual,
                       "e": p.restitution, "loading_work": p.loading_work, "unloading_work": p.unloading_work,
                       "unloading": {"P": [r["P"] for r in p.rows if r["branch"] == "unloading"],
                                     "alpha": [r["alpha"] for r in p.rows if r["branch"] == "unloading"]}}
                      for p in paths.paths],
            "mesh": dataclasses.asdict(spec.mesh), "dofs": result.mesh_info["dofs"],
            **({key: item[key] for key in GRADED_KEYS} if item.get("refinement") else {}),
            "wall_time_s": time.perf_counter() - t0, "git_commit": output.git_commit(), "fit_version": FIT_VERSION}


LOADING_FOLDER = "loading"          # OUT/loading/<key>.json: the nodes' loading branches with the FE's contact radius


def loading_task(node: dict) -> dict:
    """The loading-only rerun of a grid node's task (kind "loading"): its FE, mesh and loading steps,
    no unloading, keyed apart from the node (``node_key`` names it)."""
    fields = {k: v for k, v in node.items() if k not in ("key", "kind", "name", "material")}
    return {**node, "key": stable_key({**fields, "loading_only": True}), "kind": "loading", "node_key": node["key"]}


def loading_tasks(scene: dict) -> list[dict]:
    """The loading-only reruns of the grid's nodes (not the checks or the refined ladder), the softer first."""
    return [loading_task(t) for t in tasks_for(scene) if t["kind"] == "node"]


def run_loading(item: dict) -> dict:
    """The FE loading branch of a node's task (:func:`loading_task`; runs in a worker, never raises):
    the node's spec (its mesh, loading steps and peaks, so its loading loads), no unloading, each
    loading row's force P [N], approach alpha [m] and the FE's contact radius [m] (calib.fe.recovery,
    as the calibration's radius fit reads it)."""
    from threadpoolctl import threadpool_limits

    from calib.fe.loadpath import run_load_paths
    from calib.fit.calibration import body_meshes, _solver

    material, R = item["material"], item["R"]
    pair = ContactPair.sphere_flat(material, R)
    t0 = time.perf_counter()
    try:
        spec = task_spec(item, pair)
        with threadpool_limits(limits=1, user_api="blas"):     # as calibrate: small matrices, no threads
            solver = _solver(spec, body_meshes(spec))
            paths = run_load_paths(solver, spec.plan, unload=False)
    except Exception as exc:                    # noqa: BLE001 - reported in the row, retried next run
        return {"key": item["key"], "status": "failed", "name": item["name"],
                "error": f"{type(exc).__name__}: {exc}"[:300]}
    rows = paths.loading_rows
    return {"key": item["key"], "status": "ok", "kind": "loading", "name": item["name"], "node_key": item["node_key"],
            "nu": item["nu"], "E_over_sigma_y": item["E_over_sigma_y"], "sigma_y": item["sigma_y"],
            "rho": item["rho"], "R": R, "level": item["level"], "P_Y": pair.P_Y, "a_Y": pair.a_Y,
            "delta_Y": pair.delta_Y,
            "loading": {key: [r[key] for r in rows] for key in ("P", "alpha", "contact_radius")},
            "mesh": dataclasses.asdict(spec.mesh), "dofs": int(solver.basis.N),
            **({key: item[key] for key in GRADED_KEYS} if item.get("refinement") else {}),
            "wall_time_s": time.perf_counter() - t0, "git_commit": output.git_commit()}


def describe_loading(row: dict) -> str:
    if row.get("status") != "ok":
        return f"{row.get('name')} failed: {row.get('error')}"
    return f"{row['name']}: loading branch, {len(row['loading']['P'])} rows, {row['wall_time_s']:.0f} s"


def run_loading_radius(scene: dict, folder: str | Path, workers: int = 1, scheduler: str | None = None,
                       progress: Callable[[str], None] | None = None, node_keys=None) -> list[dict]:
    """The grid nodes' loading branches with the FE's contact radius (:func:`run_loading`,
    resumable, calib.sweep.runner) in ``folder``/loading, of the nodes ``node_keys`` (default every
    node); the rows."""
    from calib.sweep.runner import run_sweep

    tasks = [t for t in loading_tasks(scene) if node_keys is None or t["node_key"] in node_keys]
    if not tasks:
        return []
    result = run_sweep(tasks, run_loading, Path(folder) / LOADING_FOLDER, keep=is_finished,
                       workers=workers, scheduler=scheduler, progress=progress, describe=describe_loading)
    return result.rows


def keeps_radius(row: dict) -> bool:
    """A node record whose loading rows carry the FE's contact radius (no loading rerun needed)."""
    return "contact_radius" in row.get("loading", {})


def refit_row(row: dict) -> dict | None:
    """A stored task row with the current fit (FIT_VERSION), from its stored FE data: each path's
    works and e from its histories (calib.fit.vz_master_check.fe_paths, calib.fe.loadpath.contact_work),
    the tables from the loading curve and those works (calib.fit.table_fit.fit_tables, the window of
    the calibration: its loading points above P_Y, its reach and mesh). The row itself when current
    or failed; None for a two-mesh row (the second mesh's FE data are not kept: the task runs again)."""
    from calib.fit.least_squares import radius_law_data
    from calib.fit.table_fit import fit_tables
    from calib.fit.vz_master_check import fe_paths

    if row.get("status") != "ok" or row.get("fit_version", 1) == FIT_VERSION:
        return row
    if row["meshes"] != 1:
        return None
    pair = ContactPair.sphere_flat(Material(row["E_over_sigma_y"] * row["sigma_y"], row["nu"], row["sigma_y"],
                                            row["rho"]), row["R"])
    P, alpha = np.asarray(row["loading"]["P"], dtype=float), np.asarray(row["loading"]["alpha"], dtype=float)
    data = radius_law_data(P, alpha, np.full(P.size, np.nan),        # contact radii: not kept, not used
                           R_star=pair.R_star, E_star=pair.E_star, P_Y=pair.P_Y)
    window = dataclasses.replace(CalibrationWindow.from_record(row["window"]),
                                 P_min_over_P_Y=float(P[P > pair.P_Y].min() / pair.P_Y))
    paths = fe_paths(row)
    table = fit_tables(data, pair, [p["P_max"] for p in paths], [p["unloading_work"] for p in paths], window)
    record = {"x": list(table.x), "f": list(table.f), "g": list(table.g)}
    return {**row, "table": record, "fine_table": record, "window": table.window.record(),
            "paths": [{**stored, "e": p["e"], "loading_work": p["loading_work"], "unloading_work": p["unloading_work"]}
                      for stored, p in zip(row["paths"], paths)],
            "fit_version": FIT_VERSION, "fit_commit": output.git_commit()}


def is_finished(row: dict) -> bool:
    return row.get("status") == "ok"


def describe(row: dict) -> str:
    if row.get("status") != "ok":
        return f"{row.get('name')} failed: {row.get('error')}"
    if row.get("kind") == "loading":
        return describe_loading(row)
    return (f"{row['name']}: window {row['window']['P_min_over_P_Y']:.3g}-{row['window']['P_max_over_P_Y']:.4g} P_Y,"
            f" {len(row['paths'])} paths, {row['wall_time_s']:.0f} s")


def run(scene: dict, folder: str | Path, workers: int = 1, scheduler: str | None = None,
        progress: Callable[[str], None] | None = None,
        kinds: tuple = ("node", "check", "refine", "loading")) -> list[dict]:
    """Every task of ``scene`` (resumable, calib.sweep.runner) in ``folder``/nodes, and (kind
    "loading") the loading reruns in ``folder``/loading (:func:`run_loading_radius`) of the grid nodes whose
    records keep no contact radius; the rows."""
    from calib.sweep.runner import run_sweep

    tasks = [t for t in tasks_for(scene) if t["kind"] in kinds]
    result = run_sweep(tasks, run_task, Path(folder) / "nodes", keep=is_finished, workers=workers,
                       scheduler=scheduler, progress=progress, describe=describe, refit=refit_row)
    rows = in_scene_words(result.rows, tasks)
    if "loading" not in kinds:
        return rows
    without = {r["key"] for r in rows if r.get("kind") == "node" and r.get("status") == "ok" and not keeps_radius(r)}
    return rows + run_loading_radius(scene, folder, workers, scheduler, progress, node_keys=without)


def resample(row: dict, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """f, g of a node's table (nfdmodel's monotone interpolation of its nodes) at the common loads
    ``x`` inside its window [1, top]; NaN above it."""
    from calib.fit.vz_master_check import node_law

    params = node_law(row)      # on its window: a finite-strain node's reaches beyond the small strain's
    top = row["window"]["P_max_over_P_Y"]
    inside = x <= top * (1 + 1e-9)
    f, g = np.full(x.size, np.nan), np.full(x.size, np.nan)
    f[inside], g[inside] = params.tables(x[inside])
    return f, g


def unloading_nodes_of(row: dict) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(x_unload, rho, m) of a stored node row: the vz-unload law's dent and unloading exponent at
    its window's FE paths' peaks (calib.fit.unload_fit.unloading_nodes, the fit ``--ship unload`` uses), the
    returned work from the histories as the FE takes them (calib.fit.vz_master_check.fe_paths)."""
    from calib.fit.unload_fit import unloading_nodes
    from calib.fit.vz_master_check import fe_paths

    pair = ContactPair.sphere_flat(Material(row["E_over_sigma_y"] * row["sigma_y"], row["nu"], row["sigma_y"],
                                            row["rho"]), row["R"])
    # the paths of the node's window: a path below it is one the vz-table fit dropped (calib.fit.table_fit:
    # near P_Y the mesh does not resolve its unloading; E/sigma_Y 30, 1.15 P_Y: m 1.514 > 3/2, e ~ 1)
    low = row["window"]["P_min_over_P_Y"] * pair.P_Y * (1 - 1e-9)
    kept = [(stored, path) for stored, path in zip(row["paths"], fe_paths(row)) if stored["P_max"] >= low]
    return unloading_nodes(pair, [p["P_max"] for _, p in kept], [p["alpha_max"] for _, p in kept],
                           [s["alpha_residual"] for s, _ in kept], [p["unloading_work"] for _, p in kept])


def resample_unloading(row: dict, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """rho = delta_res/delta_max and m of a node's vz-unload tables (:func:`unloading_nodes_of`;
    nfdmodel's monotone interpolation of them, VZUnloadParams.unloading_tables) at the common loads
    ``x`` inside its window [1, top]; NaN above it."""
    x_unload, rho_nodes, m_nodes = unloading_nodes_of(row)
    top = row["window"]["P_max_over_P_Y"]
    inside = x <= top * (1 + 1e-9)
    at = np.clip(x[inside], 1.0, x_unload[-1])
    rho, m = np.full(x.size, np.nan), np.full(x.size, np.nan)
    rho[inside] = pchip_evaluate(x_unload, rho_nodes, pchip_slopes(x_unload, rho_nodes), at)[0]
    m[inside] = pchip_evaluate(x_unload, m_nodes, pchip_slopes(x_unload, m_nodes), at)[0]
    return rho, m


def table_loads(nodes: list[dict], limit: float = X_LIMIT) -> np.ndarray:
    """The table's loads: :func:`common_loads` (to ``limit``) and the top of each E/sigma_Y column (the
    lowest window top over its nu), so a material's window ends at its columns' top, not a step below."""
    tops = {}
    for row in nodes:
        top = row["window"]["P_max_over_P_Y"]
        tops[row["E_over_sigma_y"]] = min(tops.get(row["E_over_sigma_y"], top), top)
    kept = []
    for top in sorted(tops.values()):            # tops within TOP_MERGE of each other: the lowest
        if not kept or top > kept[-1] * (1 + TOP_MERGE):
            kept.append(top)
    x = common_loads(limit)
    x = x[x <= kept[-1] * (1 + 1e-9)]
    x = x[np.min(np.abs(np.log(x[:, None] / np.array(kept)[None, :])), axis=1) > np.log1p(TOP_MERGE)]
    return np.unique(np.concatenate([x, kept]))


RADIUS_RATIO_DEGREE = 3         # q(x) = a_FE / a_law: a polynomial of this degree in ln x, q(1) = 1
FINITE_RADIUS_RATIO_DEGREE = 4  # a finite-strain node's q: free, over its own loading points


def resample_radius(row: dict, loading: dict, x: np.ndarray) -> np.ndarray:
    """f_a = a_p/a_Y of the vz-unload law's contact radius a = a_Y (x^(1/3) + f_a) at the common loads
    ``x`` inside a node's window [1, top] (NaN above it), from the FE's contact radius a_FE along the
    node's loading branch (``loading``, its loading-only rerun, :func:`run_loading`):

        q(x) = a_FE / (a_Y (x^(1/3) + f(x))) = 1 + sum_{j=1..3} b_j (ln x)^j    (least squares over
               the loading points 1 < x <= top; f the node's vz-table f, :func:`resample`)
        f_a(x_k) = q(x_k) (x_k^(1/3) + f(x_k)) - x_k^(1/3)     (then >= 0 and non-decreasing)

    A finite-strain node (its window's source names it) serves the table only from its join up
    (above its lowest path, x_low = the window's P_min/P_Y, where a = 0.025 R): its q is a free
    quartic over its own loading points x_low <= x <= top, q(x) = sum_{j=0..4} c_j (ln max(x, x_low))^j
    (held at q(x_low) below them). Anchored at q(1) = 1 with a cubic, the fit spans 2.5 decades
    of which it serves the last one or two and missed the FE's radius there by up to 6.0 %
    (nu 0.49, E/sigma_Y 300); free over its own points, within 3 % (the FE's radius, recovered on
    12.5 elements across the contact, scatters about the quartic by 0.6-1.0 % rms on every node).

    A smooth q and not f_a node by node: between the table's loads the FE has two or three loading
    points, and the table's last loads lie closer (the column tops), where a free fit of each
    node's f_a swings and so would the law's continuation beyond the top. A ValueError when the
    rerun's loading branch is not the node's."""
    P, alpha = (np.asarray(loading["loading"][k], dtype=float) for k in ("P", "alpha"))
    if P.size != len(row["loading"]["P"]) or not (np.allclose(P, row["loading"]["P"], rtol=1e-9, atol=0.0)
                                                  and np.allclose(alpha, row["loading"]["alpha"], rtol=1e-9, atol=0.0)):
        raise ValueError(f"vz master table: the loading rerun {loading['key']} of node {row['name']} does not follow "
                         f"its loading branch (a different FE): run the scene again")
    from calib.fit.vz_master_check import node_law

    params = node_law(row)
    pair = params.pair
    load = P / pair.P_Y
    points = (load > 1.0) & (load <= row["window"]["P_max_over_P_Y"] * (1 + 1e-9))
    radius = np.asarray(loading["loading"]["contact_radius"], dtype=float)[points] / pair.a_Y
    q = radius / (np.cbrt(load[points]) + params.tables(load[points])[0])
    f, _ = resample(row, x)
    if FINITE_STRAIN in row["window"]["source"]:
        low = row["window"]["P_min_over_P_Y"]
        own = load[points] >= low * (1 - 1e-9)
        powers = np.arange(0, FINITE_RADIUS_RATIO_DEGREE + 1)
        c = np.linalg.lstsq(np.log(load[points][own])[:, None] ** powers, q[own], rcond=None)[0]
        ratio = (np.log(np.maximum(x, low))[:, None] ** powers) @ c
    else:
        powers = np.arange(1, RADIUS_RATIO_DEGREE + 1)
        b = np.linalg.lstsq(np.log(load[points])[:, None] ** powers, q - 1.0, rcond=None)[0]
        ratio = 1.0 + (np.log(x)[:, None] ** powers) @ b
    f_a = ratio * (np.cbrt(x) + f) - np.cbrt(x)     # NaN where f is
    inside = np.isfinite(f_a)
    f_a[inside] = np.maximum.accumulate(np.maximum(f_a[inside], 0.0))    # a plastic radius: >= 0, growing
    return f_a


def node_columns(row: dict, loading: dict | None, x: np.ndarray) -> dict[str, np.ndarray]:
    """A node's table columns at the loads ``x`` (NaN above its window): f, g (:func:`resample`), the
    vz-unload law's rho, m (:func:`resample_unloading`) and, with ``loading`` (the node's FE contact
    radius: its record or its loading rerun), its radius f_a (:func:`resample_radius`)."""
    f, g = resample(row, x)
    rho, m = resample_unloading(row, x)
    columns = {"a_p_over_a_Y": f, "C_R": g, "delta_res_over_delta_max": rho, "unloading_exponent": m}
    if loading is not None:
        columns[RADIUS_COLUMN] = resample_radius(row, loading, x)
    return columns


def node_rows(row: dict, columns: dict[str, np.ndarray], x: np.ndarray, window: tuple[float, float],
              rel_error) -> list[dict]:
    """The table's rows of one node: its columns (:func:`node_columns`) at the loads ``x``, its window
    (lowest unloading path, top) [P_Y] and estimated discretisation error."""
    return [{"nu": row["nu"], "E_over_sigma_y": row["E_over_sigma_y"], "P_over_P_Y": float(x[k]),
             "a_p_over_a_Y": float(columns["a_p_over_a_Y"][k]), "C_R": float(columns["C_R"][k]),
             "window_low": window[0], "window_top": window[1], "rel_error_estimate": rel_error,
             "delta_res_over_delta_max": float(columns["delta_res_over_delta_max"][k]),
             "unloading_exponent": float(columns["unloading_exponent"][k]),
             **({RADIUS_COLUMN: float(columns[RADIUS_COLUMN][k])} if RADIUS_COLUMN in columns else {})}
            for k in range(x.size)]


def loading_records(rows: list[dict]) -> dict:
    """The nodes' FE contact radius by node key: their loading reruns (kind "loading") and the node
    records that keep it; a ValueError naming the nodes without either when some have it."""
    nodes = [r for r in rows if r.get("kind") == "node" and r.get("status") == "ok"]
    loading = {r["node_key"]: r for r in rows if r.get("kind") == "loading" and r.get("status") == "ok"}
    loading.update({r["key"]: r for r in nodes if keeps_radius(r)})       # the node's own loading rows
    if loading and any(r["key"] not in loading for r in nodes):
        missing = [r["name"] for r in nodes if r["key"] not in loading]
        raise ValueError(f"vz master table: nodes without a loading rerun (contact radius): {', '.join(missing)}; "
                         f"run the scene to the end first")
    return loading


def master_rows(rows: list[dict]) -> list[dict]:
    """One row per grid node and table load: nu, E/sigma_Y, x, f, g, the node's window, its
    estimated discretisation error, the vz-unload law's rho and m and, when ``rows`` hold the nodes'
    FE contact radius (their records or their loading reruns, kind "loading"), the vz-unload law's
    contact radius f_a (:func:`resample_radius`)
    (the CSV of calib.fit.vz_master_table)."""
    nodes = [r for r in rows if r.get("kind") == "node" and r.get("status") == "ok"]
    loading = loading_records(rows)
    x = table_loads(nodes)
    out = []
    for row in nodes:
        columns = node_columns(row, loading[row["key"]] if loading else None, x)
        out += node_rows(row, columns, x, (row["window"]["P_min_over_P_Y"], row["window"]["P_max_over_P_Y"]),
                         row["table_rel_error_estimate"])
    return out


def write_master(rows: list[dict], path: str | Path, scene: dict, accuracy: str, accuracy_details: dict | None = None,
                 wall_time_s: float | None = None, joined: dict | None = None) -> Path:
    """calib/data/vz_master_table.{csv,json}: the table rows and its stamp (mesh, commit, accuracy).
    ``joined``: a finite-strain scene's table joined with the small-strain one's (calib.fit.vz_master_join:
    {"rows": the joined table's rows, "join": what the .json states of the join, "small_rows": the
    small-strain scene's records}); else the table of ``rows``."""
    path = Path(path)
    nodes = [r for r in rows if r.get("kind") == "node" and r.get("status") == "ok"]
    if len(nodes) != len(scene["nu"]) * len(scene["E_over_sigma_y"]):
        raise ValueError(f"vz master table: {len(nodes)} of {len(scene['nu']) * len(scene['E_over_sigma_y'])} grid "
                         f"nodes are calibrated; run the scene to the end first")
    table_rows = joined["rows"] if joined else master_rows(rows)
    loading = [r for r in rows if r.get("kind") == "loading" and r.get("status") == "ok"]
    if joined:                  # the small-strain scene's records are part of the table
        nodes += [r for r in joined["small_rows"] if r.get("kind") == "node"]
        loading += [r for r in joined["small_rows"] if r.get("kind") == "loading"]
    stamp = output.stamp(sum(r["wall_time_s"] for r in nodes + loading) if wall_time_s is None else wall_time_s,
                         mesh={**({"graded": grid_mesh(scene)} if grid_mesh(scene) else
                                  {"contact_size_over_a_max": scene["contact_size_over_a_max"]}
                                  if scene["contact_size_over_a_max"] else {"level": scene["level"]}),
                               "meshes": scene["meshes"]}, scene=scene["name"],
                         node_commits=sorted({r["git_commit"] for r in nodes}),
                         fit_commits=sorted({r.get("fit_commit", r["git_commit"]) for r in nodes}),
                         **({"loading_commits": sorted({r["git_commit"] for r in loading})} if loading else {}))
    meta = {"vz_master_table": {"scene": scene["name"], "axes": ["nu", "E_over_sigma_y", "P_over_P_Y"],
                                "nu": scene["nu"], "E_over_sigma_y": scene["E_over_sigma_y"],
                                "P_over_P_Y": sorted({r["P_over_P_Y"] for r in table_rows}), "accuracy": accuracy,
                                "accuracy_details": accuracy_details or {},
                                "definition": "a_p_over_a_Y = f, C_R = g of the vz-table law at P/P_Y (calib.fit."
                                              "table_fit) of the FE calibration at the node's reach (nfdcal calibrate "
                                              "--v-max), node values Richardson-extrapolated from two meshes when the "
                                              "scene has meshes = 2; empty above the node's window; window_low: its "
                                              "lowest unloading path; delta_res_over_delta_max = rho, "
                                              "unloading_exponent = m of the vz-unload law at P_max/P_Y (calib.fit."
                                              "unload_fit.unloading_nodes on the node's FE unloading paths, PCHIP "
                                              "between their peaks from rho = 0, m = 3/2 at P_Y; one mesh)"
                                              + ("; radius_a_p_over_a_Y = f_a, the vz-unload law's a_p/a_Y at P/P_Y "
                                                 "(its contact radius a = a_Y (x^(1/3) + f_a)): (x^(1/3) + f_a) = "
                                                 "q (x^(1/3) + f), q a cubic in ln x fitted to the FE's contact radius "
                                                 "along the node's loading branch (its loading-only rerun in loading/; "
                                                 "calib.fit.vz_master_build.resample_radius)"
                                                 if loading else ""),
                                **({"kinematics": scene["kinematics"], "join": joined["join"]} if joined else {})},
            "stamp": stamp}
    output.write_csv(path, table_rows, comment=output.stamp_comment(stamp))
    output.write_json(path.with_suffix(".json"), meta)
    return path

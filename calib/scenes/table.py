"""Parameter tables: calibrate every material of a scene's sweep, in parallel, resumably.

One row per material (SI units): inputs (E, nu, sigma_y, rho, R, E/sigma_Y), the yield point
(P_Y, a_Y, delta_Y from theory, the first-yield formulas; P_Y_fe, the FE first yield), the fit
(Ca, Kc and the dimensionless Ca_hat = Ca P_Y / a_Y, Kc_hat = Kc P_Y: extrapolated from two meshes,
calib.fit.extrapolation, with their estimated relative discretisation errors and both meshes'
values) with its quality (R^2 and standard error of each slope on the finer mesh, number of points), the mesh (contact size, dofs, key), the FE wall time
and the git commit. Ca and Kc are the radius fit of calib.fit.calibration (the paper's definition),
computed on the loading branch only (the unloading does not enter it) unless the scene unloads.

Each material's row is written atomically to ``OUT/materials/<key>.json`` as soon as it is
done; ``key`` hashes its inputs, load plan and mesh, so a rerun (or a run after an interruption)
recomputes nothing already done. A failed material is reported (status "failed" and the
error) and retried on the next run. Materials run through calib.sweep.runner: local processes,
or, with ``scheduler``, a Dask distributed cluster.
"""
from __future__ import annotations

import time
import traceback
from dataclasses import asdict
from pathlib import Path

from calib import output
from calib.fit import calibration, impact_window
from calib.fit.master_table import MasterTable
from calib.fit.recipe import check_fittable, coarse_spec
from calib.scenes.plan import calibration_spec, spec_options
from calib.scenes.schema import SceneError, hardening_label, rate_words
from calib.sweep.runner import cached_result, run_sweep
from meshes.keys import stable_key
from nfdmodel import VZParams

TABLE_VERSION = 2  # bump when the calibration recipe changes: invalidates cached rows (2: two meshes)
COLUMNS = ("name", "E", "nu", "sigma_y", "rho", "R", "E_over_sigma_y", "P_Y", "a_Y", "delta_Y",
           "P_Y_fe", "Ca", "Kc", "Ca_hat", "Kc_hat", "Ca_rel_error_estimate", "Kc_rel_error_estimate",
           "Ca_hat_rel_error_estimate", "Kc_hat_rel_error_estimate", "Ca_fine", "Kc_fine", "Ca_coarse",
           "Kc_coarse", "extrapolated", "Ca_r2", "Ca_se", "Kc_r2", "Kc_se", "n_points",
           "loading_only", "window_P_max_over_P_Y", "window_a_max_over_R", "contact_size", "dofs",
           "elements", "mesh_key", "fe_wall_time_s",
           "git_commit", "status", "error", "key")


def task_key(spec, loading_only: bool, v_max: float | None = None) -> str:
    """Hash of what determines a row: E, nu, sigma_Y, R, load plan, mesh, recipe version, the
    impact velocity the window must cover (when the load plan comes from it) and the sphere's flow
    curve (when it hardens); floats to 12
    digits (meshes.keys), so a library upgrade keeps finished rows finished."""
    m = spec.material
    fields = {"E": m.E, "nu": m.nu, "sigma_y": m.sigma_y, "R": spec.radius,
              "plan": asdict(spec.plan), "mesh": spec.mesh.cache_key(),
              "loading_only": loading_only, "version": TABLE_VERSION,
              "tolerance": spec.residual_tolerance}
    if v_max is not None:               # absent otherwise: the keys of existing rows stay valid
        fields["v_max"] = v_max
    if spec.hardening is not None:      # absent for perfect plasticity: the keys of existing rows stay valid
        fields["hardening"] = hardening_key(spec.hardening)
    return stable_key(fields)


def hardening_key(curve) -> dict:
    """What of a flow curve determines a row: its numbers, not the file they were read from."""
    return {k: v for k, v in curve.record().items() if k != "source"}


def tasks_for(scene) -> list[dict]:
    """One picklable task per material of ``scene``: its name, inputs, CalibrationSpec and key."""
    loading_only = not (scene.load_paths is not None and scene.load_paths.unload)
    out = []
    for material in scene.materials:
        spec = calibration_spec(scene, material)
        try:
            check_fittable(spec)        # before any mesh is built or worker started
        except ValueError as exc:
            raise SceneError(f"scene {scene.source}: material {material.name}: {exc}") from None
        v_max = scene.v_max(material)
        out.append({"name": material.name, "inputs": material.inputs(), "spec": spec,
                    "loading_only": loading_only, "key": task_key(spec, loading_only, v_max),
                    "v_max": v_max, "spec_options": spec_options(scene)})
    return out


def table_folder(scene, out: str | Path | None = None) -> Path:
    """Where ``run_table`` writes: ``out``, else results/tables/<scene name>."""
    return Path(out) if out is not None else output.RESULTS / "tables" / scene.name


def is_finished(row: dict) -> bool:
    """A material's stored result that a rerun reuses (a failed one is retried)."""
    return row.get("status") == "ok"


def finished_materials(scene, out: str | Path | None = None) -> int:
    """How many materials of ``scene`` are already calibrated in the table folder."""
    folder = table_folder(scene, out) / "materials"
    return sum(cached_result(folder, task["key"], is_finished) is not None for task in tasks_for(scene))


def calibrate_task(task: dict) -> dict:
    """Calibrate one material (runs in a worker): the table row, never raises."""
    spec = task["spec"]
    pair = spec.pair
    row = {**task["inputs"], "P_Y": pair.P_Y, "a_Y": pair.a_Y, "delta_Y": pair.delta_Y,
           "loading_only": task["loading_only"], "key": task["key"],
           "contact_size": spec.mesh.contact_size, "mesh_key": spec.mesh.cache_key(),
           "git_commit": output.git_commit(),
           **({} if spec.hardening is None else {"hardening": hardening_label(spec.hardening),
                                                 "flow_curve": spec.hardening.record()})}
    t0 = time.perf_counter()
    try:
        if task.get("v_max") is None:
            result = calibration.calibrate(spec, unload=not task["loading_only"])
        else:                           # the window from the impacts: one or more FE rounds
            result = impact_window.calibrate_for_impacts(spec.material, spec.radius, task["v_max"],
                                                         unload=not task["loading_only"], hardening=spec.hardening,
                                                         **task["spec_options"]).result
        fit, P_Y_fe, mesh = result.radius_fit, result.P_Y_fe, result.mesh_info
        estimates = result.constants("radius")      # both meshes: extrapolated, with error estimates
        if estimates is None:
            params = VZParams(pair, fit.Ca.slope, fit.Kc.slope)
        else:
            params = VZParams(pair, estimates["Ca"].value, estimates["Kc"].value)
            row.update({"Ca_rel_error_estimate": estimates["Ca"].rel_error_estimate,
                        "Kc_rel_error_estimate": estimates["Kc"].rel_error_estimate,
                        "Ca_hat_rel_error_estimate": estimates["Ca"].rel_error_estimate,
                        "Kc_hat_rel_error_estimate": estimates["Kc"].rel_error_estimate,
                        "Ca_fine": estimates["Ca"].fine, "Kc_fine": estimates["Kc"].fine,
                        "Ca_coarse": estimates["Ca"].coarse, "Kc_coarse": estimates["Kc"].coarse,
                        "extrapolated": estimates["Ca"].extrapolated and estimates["Kc"].extrapolated})
        window = result.fitted_window
        row.update({"contact_size": result.spec.mesh.contact_size, "mesh_key": result.spec.mesh.cache_key(),
                    "window_P_max_over_P_Y": window.P_max_over_P_Y, "window_a_max_over_R": window.a_max_over_R})
        row.update({"P_Y_fe": P_Y_fe, "Ca": params.Ca, "Kc": params.Kc, "Ca_hat": params.Ca_hat,
                    "Kc_hat": params.Kc_hat, "Ca_r2": fit.Ca.r_squared, "Ca_se": fit.Ca.standard_error,
                    "Kc_r2": fit.Kc.r_squared, "Kc_se": fit.Kc.standard_error,
                    "n_points": fit.Ca.n_points, "dofs": mesh["dofs"], "elements": mesh["elements"],
                    "status": "ok", "error": ""})
    except Exception as exc:  # a failed material must not stop the sweep: reported in its row
        row.update({"status": "failed", "error": f"{type(exc).__name__}: {exc}".splitlines()[0][:300],
                    "traceback": traceback.format_exc()[-2000:]})
    row["fe_wall_time_s"] = time.perf_counter() - t0
    return row


def run_table(scene, out: str | Path | None = None, workers: int = 2, scheduler: str | None = None,
              progress=None) -> dict:
    """Calibrate every material of ``scene`` not yet in ``OUT/materials/`` and write
    ``OUT/table.csv`` and ``OUT/table.json``. Returns {"rows", "computed", "reused", "failed", "path"}."""
    if scene.load_paths is None and scene.calibration_ship is None:
        raise ValueError(f"scene {scene.source}: a table needs [calibration] (and [load_paths]) to calibrate")
    if not (isinstance(workers, int) and 1 <= workers <= 64):
        raise ValueError(f"--workers must be an integer in [1, 64], got {workers!r}")
    say = progress or (lambda message: None)
    out = table_folder(scene, out)
    t0 = time.perf_counter()
    tasks = tasks_for(scene)
    sweep = run_sweep(tasks, calibrate_task, out / "materials",
                      keep=is_finished, mesh_of=lambda task: (task["spec"].mesh, coarse_spec(task["spec"]).mesh),
                      workers=workers, scheduler=scheduler, progress=say,
                      describe=lambda row: f"{row['name']} ({row['status']}, {row['fe_wall_time_s']:.0f} s)"
                      + (f" {row['error']}" if row["status"] != "ok" else ""))
    # a material renamed in the scene keeps its finished result (the key hashes what determines
    # it) under its new name
    # the sphere's rate law beside its constants (the quasi-static press does not see it: the keys and the FE
    # rows are the rate-independent sphere's)
    rated = {m.name: rate_label(m) for m in scene.materials if m.rate_law is not None}
    rows = [{**row, "name": task["name"], **({"rate_law": rated[task["name"]]} if task["name"] in rated else {})}
            for row, task in zip(sweep.rows, tasks)]
    failed = sum(row.get("status") != "ok" for row in rows)
    wall = time.perf_counter() - t0
    stamp = output.stamp(wall, scene=scene.source, mesh={"choice": scene.mesh.label()},
                         materials=len(rows), computed=sweep.computed, reused=sweep.reused,
                         workers=workers, scheduler=scheduler or "local processes",
                         **({"flow_curves": {name: curve.record() for name, curve in scene.hardening}}
                            if scene.hardening else {}),
                         **({"rate_laws": {m.name: {**m.rate_record(), "form": m.rate_form_used()}
                                           for m in scene.materials if m.rate_law is not None}} if rated else {}))
    # a hardening or rate-law column only in a table with such spheres: every other table as before
    columns = COLUMNS + tuple(c for c in ("hardening", "rate_law") if any(row.get(c) for row in rows))
    clean = [{c: row.get(c) for c in columns} for row in rows]
    output.write_csv(out / "table.csv", clean, columns=columns, comment=output.stamp_comment(stamp))
    output.write_json(out / "table.json", {"scene": scene.name, "rows": clean,
                                           "units": {"E": "Pa", "sigma_y": "Pa", "rho": "kg/m^3", "R": "m",
                                                     "P_Y": "N", "a_Y": "m", "delta_Y": "m", "Ca": "m/N",
                                                     "Kc": "1/N", "Ca_se": "m/N", "Kc_se": "1/N",
                                                     "contact_size": "m", "fe_wall_time_s": "s"},
                                           "stamp": stamp})
    return {"rows": clean, "computed": sweep.computed, "reused": sweep.reused, "failed": failed,
            "path": out / "table.csv"}


def rate_label(material) -> str:
    """A table row's rate_law cell: the law, its constants and the rate-aware law's form."""
    return f"{rate_words(material.rate_record(), ' ')} ({material.rate_form_used()})"


def write_master_table(rows: list[dict], path: str | Path, accuracy: str, scene_name: str,
                       accuracy_details: str = "", window_P_max_over_P_Y: float | None = None) -> Path:
    """The master table (calib/data/master_table.csv + .json) from the rows of a grid table:
    nu, E_over_sigma_y, Ca_hat, Kc_hat and the fit quality; every node must have succeeded.
    ``accuracy`` is the one-line statement ``nfdcal material`` prints; ``accuracy_details`` the
    full account (grid, recipe, validation, discretisation), kept in the .json only;
    ``window_P_max_over_P_Y``: the top of the grid's load plan, the window of every node."""
    path = Path(path)
    rated = [r["name"] for r in rows if r.get("rate_law")]
    if rated:
        raise ValueError(f"--master-out: the master table is of rate-independent spheres: material(s) "
                         f"{', '.join(rated)} state a rate law")
    hardening = [r["name"] for r in rows if r.get("hardening")]
    if hardening:
        raise ValueError(f"--master-out: the master table is of perfectly plastic spheres (no hardening dimension): "
                         f"material(s) {', '.join(hardening)} harden")
    failed = [r["name"] for r in rows if r.get("status") != "ok"]
    if failed:
        raise ValueError(f"cannot write the master table: material(s) {', '.join(failed)} failed")
    columns = ("nu", "E_over_sigma_y", "Ca_hat", "Kc_hat", "Ca_hat_rel_error_estimate", "Kc_hat_rel_error_estimate",
               "extrapolated", "Ca_r2", "Kc_r2", "contact_size", "dofs", "fe_wall_time_s", "git_commit")
    table_rows = [{c: r.get(c) for c in columns} for r in rows]
    MasterTable.from_rows([{k: float(v) for k, v in r.items() if k in ("nu", "E_over_sigma_y", "Ca_hat", "Kc_hat")}
                           for r in table_rows])  # validates a complete regular grid
    stamp = output.stamp(sum(r["fe_wall_time_s"] for r in rows), scene=scene_name)
    meta = {"master_table": {"accuracy": accuracy, "accuracy_details": accuracy_details or accuracy,
                             "window_P_max_over_P_Y": window_P_max_over_P_Y, "scene": scene_name,
                             "interpolation": "PCHIP in nu and in log10(E/sigma_Y) (scipy RegularGridInterpolator, method pchip)",
                             "definition": "Ca_hat = Ca P_Y / a_Y, Kc_hat = Kc P_Y (the dimensionless constants); radius fit "
                                           "on the FE loading branch to 13.7, 27.4, 41.2 P_Y, Richardson-extrapolated "
                                           "from two meshes (contact element h and 2h); *_rel_error_estimate: the "
                                           "estimated relative discretisation error of each node"},
            "stamp": stamp}
    output.write_csv(path, table_rows, columns=columns, comment=output.stamp_comment(stamp))
    output.write_json(path.with_suffix(".json"), meta)
    return path

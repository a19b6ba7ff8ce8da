"""results/stability/fe_stability.*: the FE calibration on stiff and extreme cases.

Regenerate with ``nfdcal stability --fe`` (part of plain ``nfdcal stability``; a few minutes on
2 cores, resumable: each finished run is ``OUT/fe_cases/<key>.json``, written atomically, and
a rerun recomputes nothing already there).

Each case (table CASES) is a full calibration (calib.fit.calibration.calibrate: first yield, load
paths with unloading, radius fit) of a sphere on a rigid flat at an extreme of the input space:
E / sigma_Y = 50 and 5000, nu = 0 and 0.49, P / P_Y up to 1000 (the calibration's limit,
calib.fit.recipe.MAX_LOAD_OVER_YIELD; 2000 P_Y must be refused), R = 1e-6 m and 10 m. It runs on
two meshes (contact element = MESH_RATIOS x the estimated largest contact radius, calib.fit.recipe) so that every result carries an error estimate: the change from the coarse to the fine
mesh (the discretisation converges at first order in h, results/calibration/mesh_ladder.csv, so
that change estimates the coarse mesh's error and bounds the fine one's). Columns:

  P_Y_fe_error      FE first yield / P_Y(nu) - 1 (P_Y = pi^3 R^2 (A_Y sigma_Y)^3 / (6 E*^2): the Hertz limit)
  alpha_max_over_delta_Y, contact_radius_over_R   at the largest load
  Ca_hat, Kc_hat, e, Ca_r2, Kc_r2                 the calibration (e of the largest path)
  model_alpha_error  vz law with the fitted Ca, Kc: delta(P_max) / alpha_FE - 1 (paper eq. 3.4)
  newton_max, steps, dofs, wall_time_s
  *_mesh_change     (fine rows) relative change of alpha_max, Ca_hat, Kc_hat, e from the coarse
                    mesh: the error estimate
  outcome           "ok", "clear error: <message>" (an input the model cannot represent: the
                    message names the parameter and its range) or "FAIL: <why>" (must not occur)
"""
from __future__ import annotations

import math
import time
from pathlib import Path

from calib import output
from calib.fit.calibration import calibrate
from calib.fit.recipe import calibration_spec
from calib.sweep.runner import run_sweep
from meshes.keys import stable_key
from nfdmodel import Material, VZParams, limits

DEFAULT_OUT = output.RESULTS / "stability"
CSV_NAME = "fe_stability.csv"
JSON_NAME = "fe_stability.json"
VERSION = 1                        # bump when the recipe changes: invalidates cached runs
MESH_RATIOS = (0.1, 0.05)          # contact element / estimated largest contact radius
LOADING_STEPS = 16                 # over the largest peak
UNLOADING_STEPS = 8
SIGMA_Y = 100e6                    # Pa; E = ratio x SIGMA_Y
DENSITY = 2700.0                   # kg/m^3 (does not enter the FE)

# peaks [P_Y] to half the default window and to the window itself (nfd_limits.h)
TO_THE_WINDOW = (limits.DEFAULT_WINDOW / 2, limits.DEFAULT_WINDOW)
# name, nu, E / sigma_Y, R [m], peaks [P_Y]; the last four must end in a clear error
CASES = (
    ("reference material", 0.3, 700.0, 0.1, TO_THE_WINDOW),
    ("soft: E/sigma_Y = 50", 0.3, 50.0, 0.1, TO_THE_WINDOW),
    ("stiff: E/sigma_Y = 5000", 0.3, 5000.0, 0.1, TO_THE_WINDOW),
    ("nu = 0", 0.0, 700.0, 0.1, TO_THE_WINDOW),
    ("nearly incompressible, soft: nu = 0.49, E/sigma_Y = 50", 0.49, 50.0, 0.1, TO_THE_WINDOW),
    ("nearly incompressible, stiff: nu = 0.49, E/sigma_Y = 5000", 0.49, 5000.0, 0.1, TO_THE_WINDOW),
    ("deep plastic: P = 100 P_Y, E/sigma_Y = 700", 0.3, 700.0, 0.1, (50.0, 100.0)),
    ("deep plastic: P = 100 P_Y, E/sigma_Y = 5000", 0.3, 5000.0, 0.1, (50.0, 100.0)),
    ("deep plastic, soft: P = 100 P_Y, E/sigma_Y = 100", 0.3, 100.0, 0.1, (50.0, 100.0)),
    ("fully plastic: P = 1000 P_Y, E/sigma_Y = 700", 0.3, 700.0, 0.1, (500.0, 1000.0)),
    ("fully plastic: P = 1000 P_Y, E/sigma_Y = 5000", 0.3, 5000.0, 0.1, (500.0, 1000.0)),
    ("micro sphere: R = 1 um", 0.3, 700.0, 1e-6, TO_THE_WINDOW),
    ("boulder: R = 10 m", 0.3, 700.0, 10.0, TO_THE_WINDOW),
    ("beyond the tested load: P = 2000 P_Y", 0.3, 5000.0, 0.1, (1000.0, 2000.0)),
    ("too large a contact: P = 100 P_Y at E/sigma_Y = 20", 0.3, 20.0, 0.1, (50.0, 100.0)),
    ("E typed in GPa (E/sigma_Y = 7e-7)", 0.3, 70.0 / 100e6, 0.1, TO_THE_WINDOW),
    ("beyond the tested range: E/sigma_Y = 1e5", 0.3, 1e5, 0.1, TO_THE_WINDOW),
)

COLUMNS = ("case", "nu", "E_over_sigma_y", "R", "P_max_over_P_Y", "mesh_ratio", "contact_size",
           "dofs", "P_Y_fe_error", "alpha_max_over_delta_Y", "contact_radius_over_R", "Ca_hat",
           "Kc_hat", "Ca_r2", "Kc_r2", "e", "model_alpha_error", "newton_max", "steps",
           "wall_time_s", "alpha_mesh_change", "Ca_hat_mesh_change", "Kc_hat_mesh_change",
           "e_mesh_change", "outcome", "key")


def _task(case, mesh_ratio: float) -> dict:
    name, nu, ratio, R, peaks = case
    key = stable_key({"case": case, "mesh_ratio": mesh_ratio, "version": VERSION,
                      "steps": [LOADING_STEPS, UNLOADING_STEPS]})
    return {"name": name, "nu": nu, "ratio": ratio, "R": R, "peaks": peaks, "mesh_ratio": mesh_ratio,
            "key": key}


def _spec(task):
    """The CalibrationSpec of a task, or the ValueError of an input the model cannot take."""
    material = Material(task["ratio"] * SIGMA_Y, task["nu"], SIGMA_Y, DENSITY)
    return calibration_spec(material, task["R"], peaks_over_yield=task["peaks"],
                            contact_size_over_a_max=task["mesh_ratio"], loading_steps=LOADING_STEPS,
                            unloading_steps=UNLOADING_STEPS)


def run_case(task: dict) -> dict:
    """One calibration (runs in a worker): the table row, never raises."""
    row = {key: None for key in COLUMNS}
    row.update(case=task["name"], nu=task["nu"], E_over_sigma_y=task["ratio"], R=task["R"],
               P_max_over_P_Y=max(task["peaks"]), mesh_ratio=task["mesh_ratio"], key=task["key"])
    t0 = time.perf_counter()
    try:
        spec = task.get("spec") or _spec(task)
    except ValueError as exc:
        row.update(outcome=f"clear error: {exc}", wall_time_s=time.perf_counter() - t0)
        return row
    try:
        result = calibrate(spec, meshes=1)   # the FE itself under test: one mesh
        pair, last = spec.pair, result.load_paths.paths[-1]
        params = VZParams(pair, result.radius_fit.Ca.slope, result.radius_fit.Kc.slope)
        peak_row = max(result.load_paths.loading_rows, key=lambda r: r["P"])
        rows = [r for p in result.load_paths.paths for r in p.rows]
        row.update(contact_size=spec.mesh.contact_size, dofs=result.mesh_info["dofs"],
                   P_Y_fe_error=result.P_Y_fe / pair.P_Y - 1.0,
                   alpha_max_over_delta_Y=last.alpha_max / pair.delta_Y,
                   contact_radius_over_R=peak_row["contact_radius"] / pair.R_star,
                   Ca_hat=params.Ca_hat, Kc_hat=params.Kc_hat, Ca_r2=result.radius_fit.Ca.r_squared,
                   Kc_r2=result.radius_fit.Kc.r_squared, e=last.restitution,
                   model_alpha_error=float(params.loading_approach(last.peak)) / last.alpha_max - 1.0,
                   newton_max=max(int(r["newton_iterations"]) for r in rows), steps=len(rows))
        numbers = [v for v in row.values() if isinstance(v, float)]
        if not all(math.isfinite(v) for v in numbers) or not 0.0 < last.restitution < 1.0:
            row["outcome"] = "FAIL: non-finite result or e outside (0, 1)"
        else:
            row["outcome"] = "ok"
    except ValueError as exc:
        row["outcome"] = f"clear error: {exc}"
    except Exception as exc:  # noqa: BLE001 - anything else is a failure of the solver: reported
        row["outcome"] = f"FAIL: {type(exc).__name__}: {str(exc).splitlines()[0][:300]}"
    row["wall_time_s"] = time.perf_counter() - t0
    return row


def _with_mesh_change(rows: list[dict]) -> list[dict]:
    """On each fine-mesh row, the relative change from the coarse-mesh row of the same case."""
    coarse = {r["case"]: r for r in rows if r["mesh_ratio"] == MESH_RATIOS[0]}
    for r in rows:
        c = coarse.get(r["case"])
        if r["mesh_ratio"] == MESH_RATIOS[0] or c is None or r["outcome"] != "ok" or c["outcome"] != "ok":
            continue
        for column, quantity in (("alpha_mesh_change", "alpha_max_over_delta_Y"),
                                 ("Ca_hat_mesh_change", "Ca_hat"), ("Kc_hat_mesh_change", "Kc_hat"),
                                 ("e_mesh_change", "e")):
            r[column] = r[quantity] / c[quantity] - 1.0
    return rows


def summarize(rows: list[dict]) -> dict:
    kinds = {}
    for r in rows:
        kinds[r["outcome"].split(":")[0]] = kinds.get(r["outcome"].split(":")[0], 0) + 1
    fine = [r for r in rows if r["outcome"] == "ok" and r["alpha_mesh_change"] is not None]

    def worst(column):
        return max((abs(r[column]) for r in fine), default=None)

    return {"runs": len(rows), "outcomes": kinds,
            "newton_max": max((r["newton_max"] for r in rows if r["newton_max"] is not None), default=0),
            "worst_mesh_change": {c: worst(c) for c in ("alpha_mesh_change", "Ca_hat_mesh_change",
                                                         "Kc_hat_mesh_change", "e_mesh_change")},
            "worst_P_Y_fe_error": max((abs(r["P_Y_fe_error"]) for r in rows if r["outcome"] == "ok"), default=None),
            "failures": [f"{r['case']} (mesh {r['mesh_ratio']}): {r['outcome']}" for r in rows
                         if r["outcome"].startswith("FAIL")]}


def generate(out_dir=DEFAULT_OUT, workers: int = 2, cases=CASES, progress=None) -> dict:
    """Run every case on both meshes (reusing finished runs), write fe_stability.csv/.json."""
    say = progress or (lambda message: None)
    started = time.perf_counter()
    out = Path(out_dir)
    tasks = [_task(case, ratio) for case in cases for ratio in MESH_RATIOS]
    for task in tasks:
        try:
            task["spec"] = _spec(task)
        except ValueError:
            pass                                                # run_case reports it
    # refusals depend on the code's limits: only "ok" runs are kept, refusals re-checked each run
    sweep = run_sweep(tasks, run_case, out / "fe_cases", keep=lambda row: row.get("outcome") == "ok",
                      mesh_of=lambda task: task["spec"].mesh if "spec" in task else None,
                      workers=workers, prune=True, progress=say,
                      describe=lambda row: f"{row['case']} (mesh {row['mesh_ratio']}): "
                                           f"{row['outcome'][:60]}, {row['wall_time_s']:.0f} s")
    rows = _with_mesh_change(sweep.rows)
    summary = summarize(rows)
    st = output.stamp(time.perf_counter() - started, command="nfdcal stability --fe",
                      mesh={"contact_size_over_a_max": list(MESH_RATIOS)},
                      computed=sweep.computed, reused=sweep.reused)
    output.write_csv(out / CSV_NAME, rows, COLUMNS, comment=output.stamp_comment(st))
    output.write_json(out / JSON_NAME, {"stamp": st, "summary": summary, "columns": list(COLUMNS),
                                        "rows": rows})
    return summary

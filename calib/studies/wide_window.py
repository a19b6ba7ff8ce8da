"""The two-constant law over wide load windows, against the FE: results/calibration/wide_window.*

DEM impacts load contacts to 10^2-10^5 P_Y. For E/sigma_Y = 100 (a hard metal, e.g. a bearing
steel: 210 GPa / 2 GPa), 700 (the paper's aluminium) and 5000 (a soft one, e.g. annealed pure
aluminium or copper) with nu = 0.3, sigma_Y = 100 MPa, R = 0.1 m, the FE loads a sphere on a rigid flat to 10, 30, 100, 300 and
1000 P_Y (as far as the small-strain FE reaches: contact radius <= 0.2 R, calib.fit.recipe) and
unloads it from each; Ca and Kc are fitted over the whole window (the radius fit, the paper's
definition, and the force fit), and the vz-table law's tables (calib.fit.table_fit: the FE's
loading curve and the work each unloading returned). Per path and law:

    force error = max |P_law(alpha) - P_FE(alpha)| / P_max   along loading and unloading
    e error     = e_law / e_FE - 1,  e^2 = elastic / (elastic + dissipated) energy at the peak

(the quasi-static restitution of the path), and the law's sphere-on-flat collision at the v_in
that reaches the same P_max (e_collision: the same loop, run dynamically). Target on every path:
force error <= 5 %, |e error| <= 2 %.

    python -m calib.studies.wide_window [--out results/calibration] [--workers 2]

Each material's FE is one resumable task (``OUT/wide_window/<key>.json``, calib.sweep.runner)
that keeps the FE data; the laws are refitted and compared from them on every run (seconds).
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

from calib import output
from calib.fe.loadpath import contact_work
from calib.fit import recipe
from calib.fit.calibration import E_TARGET, FORCE_TARGET, calibrate, summary
from calib.fit.least_squares import radius_law_data
from calib.fit.path_check import law_against_path
from calib.fit.table_fit import fit_tables
from calib.sweep.runner import run_sweep
from meshes.keys import stable_key
from nfdmodel import ContactPair, Material, VZParams

LOADS_OVER_YIELD = (10.0, 30.0, 100.0, 300.0, 1000.0)
STRENGTH_RATIOS = (100.0, 700.0, 5000.0)        # E / sigma_Y
NU, SIGMA_Y, RHO, RADIUS = 0.3, 100e6, 2699.0, 0.1   # E/sigma_Y = 700: the paper's aluminium
LOADING_STEPS = 400                             # increments to the largest peak


def material_task(ratio: float) -> dict:
    """The calibration of one material over the widest window the FE reaches (peaks it cannot
    reach are listed in ``unreachable``)."""
    material = Material(ratio * SIGMA_Y, NU, SIGMA_Y, RHO)
    pair = material_pair(ratio)
    reach = recipe.fe_reach(pair)
    peaks = tuple(k * pair.P_Y for k in LOADS_OVER_YIELD if k * pair.P_Y <= reach * (1 + 1e-9))
    if len(peaks) < len(LOADS_OVER_YIELD):      # as far as the FE reaches
        peaks += (reach,)
    spec = recipe.calibration_spec(material, RADIUS, peaks=peaks, loading_steps=LOADING_STEPS)
    key = stable_key({"ratio": ratio, "peaks": peaks, "mesh": spec.mesh.cache_key(), "steps": LOADING_STEPS})
    return {"key": key, "E_over_sigma_y": ratio, "spec": spec,
            "unreachable": [k for k in LOADS_OVER_YIELD if k * pair.P_Y > reach * (1 + 1e-9)],
            "reach_over_P_Y": reach / pair.P_Y}


def calibrate_material(task: dict) -> dict:
    """One material (runs in a worker): the FE load paths, the two-constant fits, and the FE data
    themselves, so the laws can be refitted and compared without the FE (:func:`compare_laws`)."""
    t0 = time.perf_counter()
    try:
        result = calibrate(task["spec"], meshes=1)   # the law's form, not its convergence: one mesh
        s = summary(result)
    except Exception as exc:                    # noqa: BLE001 - reported in the row, retried next run
        return {"key": task["key"], "status": "failed", "error": f"{type(exc).__name__}: {exc}"[:300]}
    P_Y = s["P_Y"]
    return {"key": task["key"], "status": "ok", "E_over_sigma_y": task["E_over_sigma_y"],
            "unreachable": task["unreachable"], "reach_over_P_Y": task["reach_over_P_Y"],
            "radius_fit": {"Ca_hat": s["Ca_hat"], "Kc_hat": s["Kc_hat"]},      # the paper's fit
            "force_fit": {"Ca_hat": s["force_fit"]["Ca"] * P_Y / result.spec.pair.a_Y,
                          "Kc_hat": s["force_fit"]["Kc"] * P_Y},
            "window": s["window"], "mesh": s["mesh"],
            "fe": {"loading": [{k: r[k] for k in ("P", "alpha", "contact_radius")} for r in result.load_paths.loading_rows],
                   "paths": [{"P_max": path.peak, "e": path.restitution,
                              "rows": [{k: r[k] for k in ("P", "alpha", "branch")} for r in path.rows]}
                             for path in result.load_paths.paths]},
            "wall_time_s": time.perf_counter() - t0, "git_commit": output.git_commit()}


def material_pair(ratio: float) -> ContactPair:
    """The study's sphere (R = 0.1 m) of E = ratio x sigma_Y on the rigid flat."""
    return ContactPair.sphere_flat(Material(ratio * SIGMA_Y, NU, SIGMA_Y, RHO), RADIUS)


def fe_paths(row: dict) -> list[dict]:
    """The stored FE paths: approach and force histories [m, N], peak, and the works as the FE
    takes them (calib.fe.loadpath.contact_work: the trapezoid rule, Hertz's (2/5) P |Delta alpha|
    on the segments from zero and to separation): e = sqrt(W_u / W_l) and the elastic work W_u [J]
    the unloading returned, so a stored row is read with the FE's current quadrature."""
    paths = []
    for path in row["fe"]["paths"]:
        approach = np.array([r["alpha"] for r in path["rows"]])
        force = np.array([max(r["P"], 0.0) for r in path["rows"]])
        top = int(np.argmax(approach))
        loading = contact_work(np.r_[0.0, approach[:top + 1]], np.r_[0.0, force[:top + 1]])
        returned = contact_work(approach[top:], force[top:])
        paths.append({"P_max": path["P_max"], "e": float(np.sqrt(returned / loading)), "approach": approach,
                      "force": force, "unloading_work": returned})
    return paths


def fitted_laws(row: dict) -> dict:
    """fit -> (law name, parameters): the two-constant law from the radius fit (the paper's) and
    from the force fit, and the vz-table law refitted from the stored FE data (calib.fit.table_fit;
    left out, with the reason in ``row['table_error']``, when not admissible)."""
    pair = material_pair(row["E_over_sigma_y"])
    laws = {fit: ("vz", VZParams(pair, row[f"{fit}_fit"]["Ca_hat"] * pair.a_Y / pair.P_Y,
                                 row[f"{fit}_fit"]["Kc_hat"] / pair.P_Y)) for fit in ("radius", "force")}
    loading = row["fe"]["loading"]
    data = radius_law_data([r["P"] for r in loading], [r["alpha"] for r in loading],
                           [r["contact_radius"] for r in loading], R_star=pair.R_star, E_star=pair.E_star,
                           P_Y=pair.P_Y)
    paths = fe_paths(row)
    try:
        laws["table"] = ("vz-table", fit_tables(data, pair, [p["P_max"] for p in paths],
                                                [p["unloading_work"] for p in paths]))
        row.pop("table_error", None)
    except ValueError as exc:
        row["table_error"] = str(exc)
    return laws


def compare_laws(row: dict) -> list[dict]:
    """Per FE path and fitted law: :func:`law_against_path`."""
    pair = material_pair(row["E_over_sigma_y"])
    laws = fitted_laws(row)
    return [{"E_over_sigma_y": row["E_over_sigma_y"], "P_max_over_P_Y": path["P_max"] / pair.P_Y, "fit": fit,
             **law_against_path(law, params, path)}
            for path in fe_paths(row) for fit, (law, params) in laws.items()]


def generate(out=output.RESULTS / "calibration", workers: int = 2, ratios=STRENGTH_RATIOS, progress=None) -> dict:
    """Run (or resume) every material and write OUT/wide_window.csv, .json and .png."""
    out = Path(out)
    started = time.perf_counter()
    tasks = [material_task(r) for r in ratios]
    sweep = run_sweep(tasks, calibrate_material, out / "wide_window", keep=lambda row: row.get("status") == "ok",
                      mesh_of=lambda task: task["spec"].mesh, workers=workers, progress=progress,
                      describe=lambda row: f"E/sigma_Y = {row.get('E_over_sigma_y')} ({row['status']})")
    rows = [path for row in sweep.rows if row.get("status") == "ok" for path in compare_laws(row)]
    for row in rows:
        row["meets_target"] = row["force_error"] <= FORCE_TARGET and abs(row["e_error"]) <= E_TARGET
    materials = [{**{k: row.get(k) for k in ("E_over_sigma_y", "status", "error", "radius_fit", "force_fit",
                                             "window", "unreachable", "reach_over_P_Y", "wall_time_s", "table_error")},
                  "table": _table_record(row)} for row in sweep.rows]
    st = output.stamp(time.perf_counter() - started, mesh={"loading_steps": LOADING_STEPS},
                      command="python -m calib.studies.wide_window", targets={"force_error": FORCE_TARGET,
                                                                          "e_error": E_TARGET})
    output.write_csv(out / "wide_window.csv", rows, comment=output.stamp_comment(st))
    output.write_json(out / "wide_window.json", {"materials": materials, "rows": rows, "stamp": st})
    _plot(rows, out / "wide_window.png")
    return {"materials": materials, "rows": rows,
            "failures": [m["E_over_sigma_y"] for m in materials if m["status"] != "ok"]}


def _table_record(row: dict) -> dict | None:
    if row.get("status") != "ok":
        return None
    table = fitted_laws(row).get("table")
    return None if table is None else {"P_over_P_Y": list(table[1].x), "a_p_over_a_Y": list(table[1].f),
                                       "C_R": list(table[1].g)}


FITS = (("radius", "o-", "vz, radius fit (the paper's)"), ("force", "s--", "vz, force fit"),
        ("table", "^:", "vz-table"))


def _plot(rows: list[dict], path: Path) -> None:
    """Force and e errors per path, and e against P_max: the FE path's (quasi-static) and the
    law's collision at the v_in reaching the same P_max."""
    plt = output.pyplot()
    fig, (ax_force, ax_e, ax_rest) = plt.subplots(1, 3, figsize=(16, 4.5))
    for k, ratio in enumerate(sorted({r["E_over_sigma_y"] for r in rows})):
        fe = sorted({(r["P_max_over_P_Y"], r["e_fe"]) for r in rows if r["E_over_sigma_y"] == ratio})
        ax_rest.plot(*zip(*fe), "*", ms=9, color=f"C{k}", label=f"E/sigma_Y = {ratio:g}: FE")
        for fit, marker, name in FITS:
            sel = [r for r in rows if r["E_over_sigma_y"] == ratio and r["fit"] == fit]
            x = [r["P_max_over_P_Y"] for r in sel]
            label = f"E/sigma_Y = {ratio:g}, {name}"
            ax_force.plot(x, [100 * r["force_error"] for r in sel], marker, color=f"C{k}", label=label)
            ax_e.plot(x, [100 * r["e_error"] for r in sel], marker, color=f"C{k}", label=label)
            collided = [r for r in sel if "e_collision" in r]
            ax_rest.plot([r["P_max_over_P_Y"] for r in collided], [r["e_collision"] for r in collided], marker,
                         color=f"C{k}", lw=0.8, ms=4)
    ax_force.axhline(100 * FORCE_TARGET, color="k", lw=0.8, ls=":")
    for sign in (1, -1):
        ax_e.axhline(sign * 100 * E_TARGET, color="k", lw=0.8, ls=":")
    for ax, label in ((ax_force, "max |P_law - P_FE| / P_max [%]"), (ax_e, "e_law / e_FE - 1 [%]"),
                      (ax_rest, "e")):
        ax.set_xscale("log"), ax.set_xlabel("P_max / P_Y of the path"), ax.set_ylabel(label), ax.grid(alpha=0.3)
    ax_force.set_title("force error along the FE load-unload path (target 5 %)", fontsize=9)
    ax_e.set_title("quasi-static restitution error (target 2 %)", fontsize=9)
    ax_rest.set_title("e: FE path (stars) and the law's collision at the same P_max (lines)", fontsize=9)
    ax_e.legend(fontsize=6)
    ax_rest.legend(fontsize=7)
    output.save_figure(fig, path)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(output.RESULTS / "calibration"))
    parser.add_argument("--workers", type=int, default=2)
    ns = parser.parse_args(argv)
    result = generate(ns.out, workers=ns.workers, progress=lambda m: print(m, file=sys.stderr))
    print(f"{'E/sigma_Y':>9} {'P_max/P_Y':>9} {'fit':>6} {'force err %':>11} {'e_FE':>7} {'e_law':>7} {'e err %':>8}")
    for r in result["rows"]:
        print(f"{r['E_over_sigma_y']:9g} {r['P_max_over_P_Y']:9.4g} {r['fit']:>6} {100 * r['force_error']:11.2f} "
              f"{r['e_fe']:7.4f} {r['e_law']:7.4f} {100 * r['e_error']:+8.2f}")
    return 1 if result["failures"] else 0


if __name__ == "__main__":
    sys.exit(main())

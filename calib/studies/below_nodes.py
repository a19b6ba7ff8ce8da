"""The vz master table's laws between P_Y and the nodes' lowest unloading path: results/tables/below_nodes.json

The master table's nodes unload from 2 P_Y up (calib.fit.vz_master_build); below that the vz-table law's
f and g run from Hertz's (f = 0, g = 1 at x = P/P_Y = 1) to the lowest node, and the vz-unload law's dent
ratio rho and exponent m from (0, 3/2) likewise (calib.fit.vz_master_table). Both laws declare their window
from P_Y on the strength of this check: FE load-unload paths to PEAKS_OVER_YIELD (1.2, 1.5, 1.8 P_Y) of
three off-grid materials (nu 0.29-0.34, E/sigma_Y 175, 400, 700; R = 0.1 m, sigma_Y = 100 MPa), small
strain, on the graded mesh on which every contact radius from 1.1 P_Y up spans ELEMENTS elements, the
loading branch STEPS_PER_DECADE geometric steps a decade. Per law and path:

    e error      = e_law / e_FE - 1          (the quasi-static cycle, the law driven along the FE's approach)
    force error  = max |P_law(alpha) - P_FE(alpha)| / P_max        along loading and unloading
    dent error   = (delta_res,law - delta_res,FE) / alpha_max      (delta_res,FE: the FE's approach where its
                   unloading force returns to 0, calib.fe.loadpath.separation_approach)

with the laws' dents delta_res = delta_max - a_e^2 / (g R*) (vz-table) and rho(x_m) delta_max (vz-unload).

The same FE at 12 table nodes (SHAPE_NODES, paths at SHAPE_PEAKS to the table's first load above 2 P_Y) measures
the dent's shape there, S = rho / rho(2.371 P_Y) (dent_shape): the vz-unload law's rho below the nodes' lowest
path (calib.fit.vz_master_table.DENT_SHAPE_BELOW). The three materials above are not among them.

    python -m calib.studies.below_nodes [--out results/tables]

Each material is one resumable task (``OUT/below_nodes_cases/<key>.json``, calib.sweep.runner).
"""
from __future__ import annotations

import argparse
import dataclasses
import sys
import time
from pathlib import Path

import numpy as np

from calib import output
from calib.report.index_format import read_json, study_header, table
from calib.sweep.runner import run_sweep
from meshes.keys import stable_key
from nfdmodel import ContactPair, Material

MATERIALS = ((0.3, 175.0), (0.34, 400.0), (0.29, 700.0))     # (nu, E/sigma_Y), off every node of the grid
PEAKS_OVER_YIELD = (1.2, 1.5, 1.8)
# The dent's shape near first yield (calib.fit.vz_master_table.DENT_SHAPE_BELOW) from FE paths at table nodes, to the
# table's first load above the nodes' lowest path (its common loads 10^(k/8) below it, and between)
SHAPE_NODES = tuple((nu, ratio) for nu in (0.2, 0.3, 0.4, 0.49) for ratio in (100.0, 1000.0, 5000.0))
SHAPE_PEAKS = (1.1, 1.2, 1.333521432163324, 1.5, 1.7782794100389228, 2.0, 2.371373705661655)
ELEMENTS, GRADED_FROM_OVER_P_Y, STEPS_PER_DECADE = 25.0, 1.1, 32.0
SIGMA_Y, RHO, R = 100e6, 2700.0, 0.1
LAWS = ("vz-table", "vz-unload")
VERSION = 1


def material(nu: float, E_over_sigma_y: float) -> Material:
    return Material(E_over_sigma_y * SIGMA_Y, nu, SIGMA_Y, RHO)


def spec_of(task: dict):
    """The CalibrationSpec of a task: the graded mesh and loading of the module doc, paths at the task's peaks
    (default PEAKS_OVER_YIELD)."""
    from calib.fit import impact_window

    m = material(task["nu"], task["E_over_sigma_y"])
    P_Y = ContactPair.sphere_flat(m, R).P_Y
    peaks = tuple(p * P_Y for p in task.get("peaks", PEAKS_OVER_YIELD))
    spec = impact_window.window_spec(m, R, peaks[-1], elements_per_contact_radius=ELEMENTS,
                                     lowest_over_P_Y=GRADED_FROM_OVER_P_Y, loading_steps_per_decade=STEPS_PER_DECADE)
    return dataclasses.replace(spec, plan=dataclasses.replace(spec.plan, peaks=peaks))


def case_task(nu: float, E_over_sigma_y: float, peaks: tuple = PEAKS_OVER_YIELD, role: str = "check") -> dict:
    case = {"nu": nu, "E_over_sigma_y": E_over_sigma_y}
    mesh = spec_of({**case, "peaks": peaks}).mesh.cache_key()
    key = stable_key({**case, "version": VERSION, "peaks": peaks, "mesh": mesh})
    return {"key": key, **case, "peaks": list(peaks), "role": role}


def run_task(task: dict) -> dict:
    """The FE load paths of one material (calib.fit.pair_table_build.load_paths_row); never raises."""
    from calib.fit.pair_table_build import load_paths_row

    return load_paths_row(task, spec_of)


def law_dent(law, name: str, x: float) -> float:
    """delta_res / delta_Y of a law unloaded from x = P_max/P_Y (module doc)."""
    D = float(law.scaled_approach(np.array([x]))[0])
    if name == "vz-unload":
        return float(law.unloading_tables(np.array([x]))[0][0]) * D
    f, g = (float(v[0]) for v in law.tables(np.array([x])))
    return D - np.cbrt(x) ** 2 / g


def compare(rows: list[dict], master) -> list[dict]:
    """Each FE path against both laws of its material (module doc)."""
    from calib.fit.calibration import drive_law

    out = []
    for row in rows:
        if row.get("status") != "ok":
            continue
        m = material(row["nu"], row["E_over_sigma_y"])
        laws = {"vz-table": master.law(m, R), "vz-unload": master.unload_law(m, R)}
        pair = laws["vz-table"].pair
        for path in row["paths"]:
            D, x = np.array(path["rows"]).T
            x = np.maximum(x, 0.0)
            peak = int(np.argmax(D))
            record = {"nu": row["nu"], "E_over_sigma_y": row["E_over_sigma_y"], "P_max_over_P_Y": path["P_max_over_P_Y"],
                      "e_fe": path["e"], "dent_fe_over_alpha_max": dent_ratio(path)}
            dent_fe = record["dent_fe_over_alpha_max"] * D[peak]
            for name, law in laws.items():
                force, e = drive_law(name, law, D * pair.delta_Y)
                record[name] = {"e_error": e / path["e"] - 1.0,
                                "force_error": float(np.abs(force / pair.P_Y - x).max() / x.max()),
                                "dent_error_of_alpha_max": (law_dent(law, name, path["P_max_over_P_Y"]) - dent_fe)
                                / D[peak]}
            out.append(record)
    return out


def dent_ratio(path: dict) -> float:
    """rho = delta_res / alpha_max of one FE path (delta_res: where its unloading force returns to 0)."""
    from calib.fe.loadpath import separation_approach

    D, x = np.array(path["rows"]).T
    peak = int(np.argmax(D))
    return float(separation_approach(D[peak:], np.maximum(x[peak:], 0.0)) / D[peak])


def dent_shape(rows: list[dict]) -> dict:
    """The FE's dent near first yield at the SHAPE_NODES: per node rho at SHAPE_PEAKS and S = rho / rho(x_a),
    x_a = SHAPE_PEAKS[-1]; over the nodes S's mean and its largest distance from it."""
    nodes = []
    for row in sorted(rows, key=lambda r: (r["nu"], r["E_over_sigma_y"])):
        paths = sorted(row["paths"], key=lambda p: p["P_max_over_P_Y"])
        rho = np.array([dent_ratio(p) for p in paths])
        nodes.append({"nu": row["nu"], "E_over_sigma_y": row["E_over_sigma_y"], "rho": rho.tolist(),
                      "shape": (rho / rho[-1]).tolist()})
    shapes = np.array([n["shape"] for n in nodes])
    mean = shapes.mean(axis=0)
    return {"x": list(SHAPE_PEAKS), "mean": mean.tolist(), "spread": np.abs(shapes - mean).max(axis=0).tolist(),
            "nodes": nodes}


def worst(paths: list[dict]) -> dict:
    """Per law, the largest |e error|, force error and |dent error| over the paths."""
    return {name: {quantity: float(max(abs(p[name][quantity]) for p in paths))
                   for quantity in ("e_error", "force_error", "dent_error_of_alpha_max")} for name in LAWS}


def generate(out: str | Path, progress=None) -> dict:
    from calib.fit.vz_master_table import VZMasterTable

    out = Path(out)
    started = time.perf_counter()
    checks = [case_task(*m) for m in MATERIALS]
    shapes = [case_task(*m, peaks=SHAPE_PEAKS, role="shape") for m in SHAPE_NODES]
    sweep = run_sweep(checks + shapes, run_task, out / "below_nodes_cases",
                      keep=lambda row: row.get("status") == "ok", workers=1, progress=progress,
                      describe=lambda row: f"nu {row['nu']:g} E/sigma_Y {row['E_over_sigma_y']:g} "
                                           f"({row['status']}, {row['wall_time_s']:.0f} s)")
    check_keys = {t["key"] for t in checks}
    paths = compare([r for r in sweep.rows if r["key"] in check_keys], VZMasterTable.load())
    shape = dent_shape([r for r in sweep.rows if r["key"] not in check_keys and r.get("status") == "ok"])
    mesh = {"elements_per_contact_radius": ELEMENTS, "graded_from_P_over_P_Y": GRADED_FROM_OVER_P_Y,
            "loading_steps_per_decade": STEPS_PER_DECADE, "dofs": sorted({r["dofs"] for r in sweep.rows if "dofs" in r})}
    st = output.stamp(time.perf_counter() - started, mesh=mesh, command="python -m calib.studies.below_nodes",
                      fe_wall_time_s=sum(row.get("wall_time_s", 0.0) for row in sweep.rows),
                      computed=sweep.computed, reused=sweep.reused)
    result = {"paths": paths, "worst": worst(paths), "checked_from_over_P_Y": PEAKS_OVER_YIELD[0],
              "dent_shape": shape, "stamp": st}
    output.write_json(out / "below_nodes.json", result)
    return result


def below_nodes(root: Path) -> list[str]:
    """The study's section of results/README.md (calib.report.results_index), from results/tables/below_nodes.json."""
    data = read_json(root / "tables" / "below_nodes.json")
    if data is None:
        return []
    mesh = data["stamp"]["mesh"]
    lines = study_header("The master table's laws below its nodes (`tables/below_nodes.json`)", data["stamp"],
                         "python -m calib.studies.below_nodes") + [
        "The vz master table's vz-table and vz-unload laws between P_Y and the nodes' lowest unloading path (2 P_Y) "
        "against FE load-unload paths of off-grid materials (R 0.1 m, small strain, graded mesh: every contact radius "
        f"from {mesh['graded_from_P_over_P_Y']:g} P_Y up spans {mesh['elements_per_contact_radius']:g} elements, "
        f"{mesh['loading_steps_per_decade']:g} loading steps a decade). Errors: e_law / e_FE - 1, the largest force "
        "difference over P_max, the dent difference over alpha_max:", ""]
    rows = [[f"{p['nu']:g}", f"{p['E_over_sigma_y']:g}", f"{p['P_max_over_P_Y']:.3g}", f"{p['e_fe']:.4f}",
             f"{100 * p['dent_fe_over_alpha_max']:.2f} %"]
            + [f"{100 * p[name][q]:+.2f} %" for name in LAWS for q in ("e_error", "force_error", "dent_error_of_alpha_max")]
            for p in data["paths"]]
    lines += table(["nu", "E/sigma_Y", "P_max/P_Y", "e_FE", "dent_FE / alpha_max"]
                   + [f"{name} {q}" for name in LAWS for q in ("e", "force", "dent")], rows)
    shape = data.get("dent_shape")
    if shape:
        lines += [f"The dent near first yield at {len(shape['nodes'])} table nodes (nu 0.2-0.49 x E/sigma_Y 100, 1000, "
                  f"5000; the same mesh), S = rho / rho at {shape['x'][-1]:.4g} P_Y over the nodes (the laws' "
                  "`DENT_SHAPE_BELOW`):", ""]
        lines += table(["P_max/P_Y"] + [f"{x:.4g}" for x in shape["x"]],
                       [["S, mean"] + [f"{v:.4f}" for v in shape["mean"]],
                        ["largest distance from it"] + [f"{v:.4f}" for v in shape["spread"]]])
    w = data["worst"]
    lines += ["Largest: " + "; ".join(f"{name} e {100 * w[name]['e_error']:.2f} %, force {100 * w[name]['force_error']:.2f} "
                                      f"%, dent {100 * w[name]['dent_error_of_alpha_max']:.2f} % of alpha_max"
                                      for name in LAWS) + ".", ""]
    return lines


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(output.RESULTS / "tables"))
    ns = parser.parse_args(argv)
    result = generate(ns.out, progress=lambda m: print(m, file=sys.stderr))
    print(f"{len(result['paths'])} paths; worst {result['worst']}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

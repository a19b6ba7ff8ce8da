"""The pair FE over the rigid flat's to high loads: Phi_e, Phi_D by P_max/P_Y and a/R*, results/pairs/ratios_high.*

The ratios of calib.studies.pair_ratios (a yielding sphere on an elastic flat of stiffness ratio x = E1'/E2',
E' = E / (1 - nu^2), nu2 = nu1, over the same sphere on the rigid flat, both on the pair's Hertz scales E*, R*):

    Phi_D = D_pair / D_rf     D = alpha / delta_Y on the loading branch, at equal P/P_Y
    Phi_e = e_pair / e_rf     e of a load-unload path (calib.fe.loadpath), at equal P_max/P_Y

carried to the two-body FE's reach (calib.fit.recipe.fe_reach: on a counter-body the small-strain reach,
P <= 1000 P_Y and an estimated contact radius <= 0.2 R*, whatever the sphere's kinematics), to tell a pair
table's load axis and whether the contact size a/R* (at a given P/P_Y: E/sigma_Y) must be an axis too.

Cases: nu 0.3, E/sigma_Y 1000 and 300 (R = 0.1 m, sigma_Y = 100 MPa), x = 1/3, 1, 3; each pair runs to the
largest of 100, 300, 1000 P_Y inside its reach (else 0.95 of the reach), the same sphere on the rigid flat to the
same P/P_Y in the same kinematics on the same mesh family (spec_of: graded, every contact radius from 5 P_Y up
spans 10 elements at ``coarse``). The load plan: as the recipe's window (calib.fit.impact_window.window_spec:
the loading branch LOADING_STEPS_PER_DECADE geometric steps a decade) with unloading paths at PEAKS_OVER_YIELD up
to the top, in units of each case's own P_Y, so pair and rigid flat unload at equal P_max/P_Y. Every case in
small strain and in finite strain (calib.fe.kinematics; the counter-body stays linear small-strain,
calib/README.md), to compare the two kinematics' ratios. The FE alone (calib.fe.loadpath.run_load_paths),
no law fit. a/R* is the FE's contact radius on the loading branch at the peak.

    python -m calib.studies.pair_ratios_high [--out results/pairs] [--level coarse]

Each FE case is one resumable task (``OUT/ratio_high_cases/<key>.json``); a case over MAX_CASE_S is reported,
not used. Writes OUT/ratios_high.csv and OUT/ratios_high.json.
"""
from __future__ import annotations

import argparse
import dataclasses
import sys
import time
from pathlib import Path

import numpy as np

from calib import output
from calib.fe.kinematics import DEFAULT_KINEMATICS
from calib.fit import recipe
from calib.report.index_format import read_json, study_header, table
from calib.studies.pair_ratios import R, RIGID, counter, material, stiffness_ratio
from calib.sweep.runner import run_sweep
from meshes.keys import stable_key
from nfdmodel import ContactPair, limits

NU, E_OVER_SIGMA_YS, XS = 0.3, (1000.0, 300.0), ("1/3", "1", "3")
TOPS_OVER_YIELD = (100.0, 300.0, 1000.0)
PEAKS_OVER_YIELD = (5.0, 13.7, limits.DEFAULT_WINDOW, 100.0, 300.0, 1000.0)   # the recipe's peaks and on
FINITE = tuple((r, x) for r in E_OVER_SIGMA_YS for x in XS)   # also run in finite strain, with their rigid flat
MAX_CASE_S = 360.0                             # a case slower than this is dropped (the study's time budget)
LEVEL = "coarse"
VERSION = 2
FINITE_STRAIN = "finite-strain"


def pair_of(E_over_sigma_y: float, x: str) -> ContactPair:
    body = counter(NU, E_over_sigma_y, x)
    m = material(NU, E_over_sigma_y)
    return ContactPair.sphere_flat(m, R) if body is None else body.pair(m, R)


def top_of(E_over_sigma_y: float, x: str) -> float:
    """The pair's top load over P_Y: the largest of TOPS_OVER_YIELD inside the two-body FE's reach."""
    pair = pair_of(E_over_sigma_y, x)
    reach = recipe.fe_reach(pair) / pair.P_Y
    inside = [t for t in TOPS_OVER_YIELD if t <= reach * (1 + 1e-9)]
    return max(inside) if inside else round(0.95 * reach, 1)


def spec_of(task: dict) -> recipe.CalibrationSpec:
    """The recipe's spec of a case: graded mesh (recipe.mesh_for), every contact radius from PEAKS_OVER_YIELD[0]
    P_Y to the top spanning 1 / MESH_LEVELS[level] elements (the small-strain estimate of the radius,
    recipe.estimated_contact_radius, in both kinematics: one mesh family), the geometric loading branch of
    calib.fit.impact_window, unloading at the peaks."""
    from calib.fit.impact_window import LOADING_STEPS_PER_DECADE, GeometricLoadPathPlan

    pair = pair_of(task["E_over_sigma_y"], task["x"])
    body = counter(NU, task["E_over_sigma_y"], task["x"])
    top = task["top"] * pair.P_Y
    graded_from = recipe.estimated_contact_radius(pair, PEAKS_OVER_YIELD[0] * pair.P_Y)
    spec = recipe.calibration_spec(material(NU, task["E_over_sigma_y"]), R, peaks=(top,), loading_steps=1,
                                   counter=body, kinematics=task["kinematics"], graded_from=graded_from,
                                   elements_per_contact_radius=1.0 / recipe.MESH_LEVELS[task["level"]])
    peaks = tuple(sorted({p * pair.P_Y for p in PEAKS_OVER_YIELD if p < task["top"] * (1 - 1e-9)} | {top}))
    return dataclasses.replace(spec, plan=GeometricLoadPathPlan(
        peaks=peaks, loading_step=top, unloading_steps=spec.plan.unloading_steps,
        first_load=min(spec.plan.first_load, peaks[0]), loading_ratio=10.0 ** (1.0 / LOADING_STEPS_PER_DECADE)))


def case_task(E_over_sigma_y: float, x: str, top: float, kinematics: str, level: str = LEVEL) -> dict:
    case = {"nu": NU, "E_over_sigma_y": float(E_over_sigma_y), "x": x, "top": float(top), "kinematics": kinematics,
            "level": level}
    return {"key": stable_key({**case, "version": VERSION, "mesh": spec_of(case).mesh.cache_key()}), **case}


def all_tasks(level: str = LEVEL) -> list[dict]:
    """Every pair case and its rigid flat at the same top and kinematics (each rigid flat once)."""
    tasks = {}
    for kinematics in (DEFAULT_KINEMATICS, FINITE_STRAIN):
        for ratio in E_OVER_SIGMA_YS:
            for x in XS:
                if kinematics == FINITE_STRAIN and (ratio, x) not in FINITE:
                    continue
                top = top_of(ratio, x)
                for body in (x, RIGID):
                    task = case_task(ratio, body, top, kinematics, level)
                    tasks[task["key"]] = task
    return sorted(tasks.values(), key=lambda t: (t["kinematics"] != DEFAULT_KINEMATICS, t["top"], -t["E_over_sigma_y"]))


class CaseTimeout(BaseException):
    """A case past MAX_CASE_S (a BaseException: the FE's own ``except Exception`` rescues do not catch it)."""


def run_task(task: dict) -> dict:
    """The FE load paths of one case (no fit); never raises. Stopped after MAX_CASE_S (SIGALRM: the sweep runs
    its tasks in this process), a row of status "timeout" that is stored, so not run again."""
    import signal

    from calib.fit.pair_table_build import load_paths_record

    def stop(signum, frame):
        raise CaseTimeout(f"over {MAX_CASE_S:.0f} s")

    t0 = time.perf_counter()
    previous = signal.signal(signal.SIGALRM, stop)
    signal.alarm(int(MAX_CASE_S))
    try:
        record = load_paths_record(spec_of(task))
    except (Exception, CaseTimeout) as exc:     # noqa: BLE001 - reported in the row
        return {**task, "status": "timeout" if isinstance(exc, CaseTimeout) else "failed",
                "error": f"{type(exc).__name__}: {exc}"[:400], "wall_time_s": time.perf_counter() - t0}
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)
    return {**task, "status": "ok", **record, "wall_time_s": time.perf_counter() - t0,
            "git_commit": output.git_commit()}


def at_peaks(row: dict, peaks: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(D, a/R*) of a case's loading branch at the loads ``peaks`` (P/P_Y), log-interpolated."""
    loading = np.array(row["loading"])
    logs = np.log(loading[:, 0])
    return np.interp(np.log(peaks), logs, loading[:, 1]), np.interp(np.log(peaks), logs, loading[:, 2])


def compare(rows: list[dict]) -> list[dict]:
    """Each pair path against its rigid flat's at the same P_max/P_Y (same top, kinematics, level)."""
    ok = {(r["E_over_sigma_y"], r["x"], r["top"], r["kinematics"]): r for r in rows
          if r["status"] == "ok" and r["wall_time_s"] <= MAX_CASE_S}
    cases = []
    for (ratio, x, top, kinematics), row in sorted(ok.items(), key=lambda kv: (kv[0][3], -kv[0][0], kv[0][1])):
        rigid = ok.get((ratio, RIGID, top, kinematics))
        if x == RIGID or rigid is None:
            continue
        rigid_e = {round(p["P_max_over_P_Y"], 6): p["e"] for p in rigid["paths"]}
        peaks = np.array([p["P_max_over_P_Y"] for p in row["paths"]])
        D_pair, a_pair = at_peaks(row, peaks)
        D_rf, a_rf = at_peaks(rigid, peaks)
        for k, path in enumerate(row["paths"]):
            e_rf = rigid_e.get(round(path["P_max_over_P_Y"], 6))
            if e_rf is None:
                continue
            cases.append({"x": stiffness_ratio(x), "E_over_sigma_y": ratio, "kinematics": kinematics,
                          "P_max_over_P_Y": path["P_max_over_P_Y"], "a_over_R_star": a_pair[k],
                          "a_over_R_rigid": a_rf[k], "e_pair": path["e"], "e_rf": e_rf, "phi_e": path["e"] / e_rf,
                          "phi_D": D_pair[k] / D_rf[k], "wall_time_s": row["wall_time_s"],
                          "rigid_wall_time_s": rigid["wall_time_s"], "dofs": row["dofs"]})
    return cases


CSV_COLUMNS = ("x", "E_over_sigma_y", "kinematics", "P_max_over_P_Y", "a_over_R_star", "a_over_R_rigid", "e_pair",
               "e_rf", "phi_e", "phi_D", "dofs", "wall_time_s", "rigid_wall_time_s")


def generate(out: str | Path, level: str = LEVEL, progress=None) -> dict:
    out = Path(out)
    started = time.perf_counter()
    tasks = all_tasks(level)
    sweep = run_sweep(tasks, run_task, out / "ratio_high_cases",
                      keep=lambda row: row.get("status") in ("ok", "timeout"),
                      workers=1, progress=progress,
                      describe=lambda row: (f"E/sigma_Y {row['E_over_sigma_y']:g} x {row['x']} to {row['top']:g} P_Y "
                                            f"{row['kinematics']} ({row['status']}, {row['wall_time_s']:.0f} s)"))
    result = {"cases": compare(sweep.rows),
              "runs": [{k: row.get(k) for k in ("E_over_sigma_y", "x", "top", "kinematics", "status", "wall_time_s",
                                                 "dofs", "error")} for row in sweep.rows]}
    mesh = {"level": level, "graded_from_P_over_P_Y": PEAKS_OVER_YIELD[0],
            "elements_per_contact_radius": 1 / recipe.MESH_LEVELS[level]}
    st = output.stamp(time.perf_counter() - started, mesh=mesh,
                      command="python -m calib.studies.pair_ratios_high"
                      + ("" if level == LEVEL else f" --level {level}"),
                      fe_wall_time_s=sum(row.get("wall_time_s", 0.0) for row in sweep.rows),
                      computed=sweep.computed, reused=sweep.reused)
    result["stamp"] = st
    output.write_csv(out / "ratios_high.csv", result["cases"], CSV_COLUMNS, comment=output.stamp_comment(st))
    output.write_json(out / "ratios_high.json", result)
    return result


def kinematics_line(cases: list[dict]) -> str:
    """Finite less small strain in Phi_e, largest |difference| with the pair's a/R* up to 0.05 and beyond."""
    by = {(c["x"], c["E_over_sigma_y"], round(c["P_max_over_P_Y"], 6), c["kinematics"]): c for c in cases}
    small, large = [], []
    for (x, ratio, peak, kinematics), c in by.items():
        other = by.get((x, ratio, peak, DEFAULT_KINEMATICS))
        if kinematics == FINITE_STRAIN and other is not None:
            (small if c["a_over_R_star"] <= 0.05 else large).append(c["phi_e"] - other["phi_e"])
    worst = [f"{100 * max(d, key=abs):+.2f} points over {len(d)} paths" if d else "no paths" for d in (small, large)]
    return f"Phi_e, finite less small strain: largest {worst[0]} with a/R* <= 0.05, {worst[1]} beyond."


def pair_ratios_high(root: Path) -> list[str]:
    """The study's section of results/README.md (calib.report.results_index), from results/pairs/ratios_high.json."""
    data = read_json(root / "pairs" / "ratios_high.json")
    if data is None:
        return []
    lines = study_header("The pair FE over the rigid flat's to high loads (`pairs/ratios_high.json`)", data["stamp"],
                         "python -m calib.studies.pair_ratios_high") + [
        "The ratios of the section above carried to the two-body FE's reach (P <= 1000 P_Y, estimated contact "
        "radius <= 0.2 R* whatever the kinematics), nu 0.3: Phi_e = e_pair / e_rf and Phi_D = D_pair / D_rf at "
        "equal P_max/P_Y, the pair's FE contact radius a/R* beside the rigid flat's a/R at that P/P_Y; each case "
        "and its rigid flat in the same kinematics on the same mesh family (graded: every contact radius from "
        f"{data['stamp']['mesh']['graded_from_P_over_P_Y']:g} P_Y up spans "
        f"{data['stamp']['mesh']['elements_per_contact_radius']:.3g} elements), one FE run's seconds each:", ""]
    rows = [[f"{c['x']:.3g}", f"{c['E_over_sigma_y']:g}", c["kinematics"], f"{c['P_max_over_P_Y']:.4g}",
             f"{c['a_over_R_star']:.4f}", f"{c['a_over_R_rigid']:.4f}", f"{c['e_pair']:.4f}", f"{c['e_rf']:.4f}",
             f"{c['phi_e']:.4f}", f"{c['phi_D']:.4f}", f"{c['wall_time_s']:.0f} / {c['rigid_wall_time_s']:.0f}"]
            for c in sorted(data["cases"], key=lambda c: (-c["E_over_sigma_y"], c["x"], c["P_max_over_P_Y"],
                                                          c["kinematics"]))]
    lines += table(["x", "E/sigma_Y", "kinematics", "P_max/P_Y", "a/R* (pair)", "a/R (rigid)", "e_pair", "e_rf",
                    "Phi_e", "Phi_D", "seconds (pair / rigid)"], rows)
    lines += [kinematics_line(data["cases"]), ""]
    dropped = [r for r in data["runs"] if r["status"] != "ok" or r["wall_time_s"] > MAX_CASE_S]
    if dropped:
        lines += ["Runs not used (failed, or over " f"{MAX_CASE_S:.0f} s): " + "; ".join(
            f"E/sigma_Y {r['E_over_sigma_y']:g} x {r['x']} to {r['top']:g} P_Y {r['kinematics']} "
            f"({r['status']}, {r['wall_time_s']:.0f} s)" for r in dropped) + ".", ""]
    return lines


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(output.RESULTS / "pairs"))
    parser.add_argument("--level", default=LEVEL, choices=tuple(recipe.MESH_LEVELS))
    ns = parser.parse_args(argv)
    result = generate(ns.out, level=ns.level, progress=lambda m: print(m, file=sys.stderr))
    print(f"{len(result['cases'])} pair paths")
    return 0


if __name__ == "__main__":
    sys.exit(main())

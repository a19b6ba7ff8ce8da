"""Builds the pair table (calib/data/pair_table.csv): the two-body FE over the rigid flat's, to the pair's reach.

A yielding sphere (E1, nu1, sigma_Y, R) on an elastic counter-body (E2, nu2) keeps the elastic contact of its Hertz
pair (E*, R*; Johnson 1985 eq. 4.22). What the counter-body changes after first yield is measured as two ratios of
the two-body FE (calib.fe.two_body) over the same sphere's rigid-flat FE, each on its own Hertz scales (P_Y,
delta_Y of its ContactPair), at equal P/P_Y, on the same mesh family in the same kinematics:

    Phi_D(s, P/P_Y)     = D_pair / D_rf      D = alpha / delta_Y on the loading branch   [-]
    Psi(s, P_max/P_Y)   = (1 - e_pair^2) / (1 - e_rf^2)   the dissipated share of the loading work of a
                                             load-unload path (calib.fe.loadpath)        [-]

over s = x / (1 + x) = E* / E2', x = E1' / E2', E' = E / (1 - nu^2) (s = 0: the rigid flat, both ratios 1; nu2
enters only through E2'), nu and E/sigma_Y (the contact size a/R* at a given P/P_Y). calib.fit.pair_table maps
the vz master table's rigid-flat law by them.

Phi_D rises above 1 once the contact is large (at nu 0.3, E/sigma_Y 200: 1.05 at 500 P_Y for x = 1, 1.13 at 1700
P_Y for x = 1/3). Measured cause: at equal P/P_Y the pair carries (1 + x)^2 times the rigid flat's force (P_Y
scales as 1/E*^2), and its contact is (1 + x) times wider over R* (1.95-2.12 at x = 1, 1.32-1.39 at x = 1/3); at
equal a/R* the two spheres carry the same force within 4.3 % beyond a/R* 0.2, and the pair's approach exceeds the
rigid flat's by the flat's elastic share (7.6-13.4 % at x = 1, 2.7-4.4 % at x = 1/3). The reading, not measured
apart: the finite sphere softens as its contact widens (its mean pressure falls with a/R, as Jackson & Green 2005
give), so the wider pair contact approaches further at the same scaled load.

Cases: R = 0.1 m, sigma_Y = 100 MPa, E = sigma_Y (E/sigma_Y), nu2 = nu1, the counter an elastic flat:
nu in NUS, E/sigma_Y in E_OVER_SIGMA_YS, x in XS (PCHIP in s through s = 0 from x = 1/3, 1, 3 matches the
ratios measured at x = 1/2 and 2 within 0.1 points to 41 P_Y, calib.studies.pair_ratios; x = 1/2 extends the
reach of the small x), finite-strain sphere (the counter-body stays linear small strain), each pair to its reach
(recipe.fe_reach in finite strain on an elastic flat, recipe.reach_kinematics: P <= 1e4 P_Y, a <= 0.45 R* as
recipe.fe_contact_radius estimates it), its rigid flat to the largest of its pairs' tops. Mesh: graded, every
contact radius from the lowest peak up spans ELEMENTS_PER_CONTACT_RADIUS elements; the loading branch
LOADING_STEPS_PER_DECADE geometric steps a decade, unloading paths at PEAKS_OVER_YIELD below the top and at the top.

The held-out checks (CHECKS: materials, stiffness ratios and a counter-sphere off the table's nodes) run the
two-body FE alone, to be compared with the mapped law (check_rows), each with one more unloading path just below
its law's window top when its own peaks stop short of it (top_check_tasks, run once the table is written).

    python -m calib.fit.pair_table_build [--out results/pairs] [--workers 2] [--table-out calib/data/pair_table.csv]

Each FE case is one resumable task (``OUT/pair_table_cases/<key>.json``, calib.sweep.runner) keeping its FE data.
The held-out checks' FE data also measure fit-data on a counter-body (calib.fit.pair_fit_check): its sigma_Y error
is the table's model-form level (the table's .json ``model_form``).
"""
from __future__ import annotations

import dataclasses
import time
from fractions import Fraction
from pathlib import Path

import numpy as np

from calib import output
from calib.fit import pair_fit_check, recipe
from calib.fit.counter import CounterBody
from calib.fit.pair_table import KINEMATICS
from meshes.keys import stable_key
from nfdmodel import ContactPair, Material, limits

SIGMA_Y, R, RHO = 100e6, 0.1, 7800.0
NUS = (0.2, 0.3, 0.45)
E_OVER_SIGMA_YS = (200.0, 400.0, 800.0, 2000.0)
XS = ("1/3", "1/2", "1", "3")                # E1'/E2', exact fractions
PEAKS_OVER_YIELD = (2.0, 5.0, 13.7, limits.DEFAULT_WINDOW, 100.0, 300.0, 1000.0, 3000.0)   # the recipe's and on
ELEMENTS_PER_CONTACT_RADIUS = 10.0
D_GRID_PER_DECADE = 8                        # Phi_D table loads a decade
REACH_SAFETY = 0.97                          # the top: this fraction of the estimated reach when it binds
RIGID = "rigid"
VERSION = 2                                  # part of each task's key: bump when the FE or the plan changes
# Held-out checks: (nu, E/sigma_Y, x, counter R / R or None for a flat): an aluminium alloy, a brass, a copper and a
# steel on a steel floor, a sphere on a flat 3/4 as stiff, a sphere on a softer flat, two like-sized unlike spheres.
CHECKS = ((0.33, 250.0, "0.335", None), (0.34, 560.0, "0.49", None), (0.34, 418.0, "0.573", None),
          (0.29, 1200.0, "1", None), (0.25, 600.0, "0.75", None), (0.27, 1200.0, "2", None), (0.3, 300.0, "1", 1.0))


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
    """The case's top P/P_Y: the reach's load, or REACH_SAFETY of the two-body FE's estimated reach (3 digits)."""
    pair, kinematics = pair_of(task), recipe.reach_kinematics(KINEMATICS, counter(task))
    largest = recipe.REACH[kinematics][0]
    reach = recipe.fe_reach(pair, kinematics) / pair.P_Y
    return largest if reach >= largest else float(f"{REACH_SAFETY * reach:.3g}")


def spec_of(task: dict, elements_per_contact_radius: float = ELEMENTS_PER_CONTACT_RADIUS) -> recipe.CalibrationSpec:
    """The recipe's spec of a case (module doc): graded mesh from the lowest peak's estimated contact radius,
    ``elements_per_contact_radius`` across every contact radius from there, the geometric loading branch,
    unloading at the peaks below the top and at the top (``task["peaks"]``)."""
    from calib.fit.impact_window import LOADING_STEPS_PER_DECADE, GeometricLoadPathPlan

    pair = pair_of(task)
    peaks = tuple(p * pair.P_Y for p in task["peaks"])
    graded_from = recipe.estimated_contact_radius(pair, peaks[0])
    spec = recipe.calibration_spec(material(task["nu"], task["E_over_sigma_y"]), R, peaks=(peaks[-1],),
                                   loading_steps=1, counter=counter(task), kinematics=KINEMATICS,
                                   graded_from=graded_from, elements_per_contact_radius=elements_per_contact_radius)
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
    from calib.fit.calibration import body_meshes

    for task in tasks:
        body_meshes(spec_of(task))


def load_paths_record(spec: recipe.CalibrationSpec) -> dict:
    """The FE load paths of ``spec`` (no fit, one BLAS thread), in units of its pair's P_Y, delta_Y, R*:
    "loading" [[P/P_Y, D, a/R*]], "paths" [{P_max_over_P_Y, e, rows [[D, P/P_Y]]}], "dofs", "contact_size"."""
    from threadpoolctl import threadpool_limits

    from calib.fe.loadpath import run_load_paths
    from calib.fit.calibration import body_meshes, _solver

    pair = spec.pair
    with threadpool_limits(limits=1, user_api="blas"):
        solver = _solver(spec, body_meshes(spec))
        paths = run_load_paths(solver, spec.plan, unload=True)
    loading = [[r["P"] / pair.P_Y, r["alpha"] / pair.delta_Y, r["contact_radius"] / pair.R_star]
               for r in paths.loading_rows]
    return {"loading": loading, "dofs": int(solver.n_dofs), "contact_size": spec.mesh.contact_size,
            "paths": [{"P_max_over_P_Y": p.peak / pair.P_Y, "e": p.restitution,
                       "rows": [[r["alpha"] / pair.delta_Y, r["P"] / pair.P_Y] for r in p.rows]}
                      for p in paths.paths]}


def load_paths_row(task: dict, spec_of_task) -> dict:
    """The sweep row of ``task``: its FE load paths (load_paths_record of ``spec_of_task(task)``), status, wall
    time and commit; never raises (a failure is a row, retried next run)."""
    t0 = time.perf_counter()
    try:
        record = load_paths_record(spec_of_task(task))
    except Exception as exc:                    # noqa: BLE001 - reported in the row, retried next run
        return {**task, "status": "failed", "error": f"{type(exc).__name__}: {exc}"[:400],
                "wall_time_s": time.perf_counter() - t0}
    return {**task, "status": "ok", **record, "wall_time_s": time.perf_counter() - t0,
            "git_commit": output.git_commit()}


def run_task(task: dict) -> dict:
    """The FE load paths of one case (load_paths_row); never raises."""
    return load_paths_row(task, spec_of)


def top_check_tasks(rows: list[dict], table) -> list[dict]:
    """One more FE case per held-out check whose own peaks stop short of its law's window top: unloading at
    PEAKS_OVER_YIELD[0] (the same graded mesh) and just below that top, so every check covers its whole window."""
    from calib.fit.pair_table import pair_law

    tasks = []
    for row in (r for r in rows if r["role"] == "check" and r["status"] == "ok"):
        law = pair_law(material(row["nu"], row["E_over_sigma_y"]), R, counter(row), table)["law"]
        top = float(f"{law.window.P_max_over_P_Y * (1 - 1e-3):.4g}")
        window_top = law.window.P_max_over_P_Y * (1 + 1e-6)
        if max(p["P_max_over_P_Y"] for p in row["paths"] if p["P_max_over_P_Y"] <= window_top) < 0.9 * top:
            tasks.append(case_task(row["nu"], row["E_over_sigma_y"], row["x"], (PEAKS_OVER_YIELD[0], top),
                                   "check", row["counter_R_over_R"]))
    return tasks


def run(out, workers: int = 2, progress=None, tasks: list[dict] | None = None):
    """Every case (default: all_tasks) through the sweep runner (resumable); returns the SweepResult."""
    from calib.sweep.runner import run_sweep

    tasks = all_tasks() if tasks is None else tasks
    build_meshes(tasks)
    return run_sweep(tasks, run_task, Path(out) / "pair_table_cases",
                     keep=lambda row: row.get("status") == "ok", workers=workers, progress=progress,
                     describe=lambda row: (f"{row['role']} nu {row['nu']:g} E/sigma_Y {row['E_over_sigma_y']:g} "
                                           f"x {row['x']} to {row['peaks'][-1]:g} P_Y ({row['status']}, "
                                           f"{row['wall_time_s']:.0f} s)"))


# ----------------------------------------------------------------------------- the table
def loading_at(row: dict, x: np.ndarray) -> np.ndarray:
    """D of a case's loading branch at the loads x (P/P_Y), linear in (ln x, ln D)."""
    loading = np.array(row["loading"])
    loading = loading[loading[:, 0] > 0]
    return np.exp(np.interp(np.log(x), np.log(loading[:, 0]), np.log(loading[:, 1])))


def node_rows(pair_row: dict, rigid_row: dict) -> list[dict]:
    """The table rows of one pair case: Phi_D on D_GRID_PER_DECADE loads a decade above P_Y to its top, Psi at
    its peaks (over its rigid flat's, at equal P/P_Y)."""
    top = pair_row["peaks"][-1]
    x = 10.0 ** (np.arange(1, int(np.floor(D_GRID_PER_DECADE * np.log10(top) - 1e-9)) + 1) / D_GRID_PER_DECADE)
    x = np.append(x[x < top * (1 - 1e-9)], top)
    X = stiffness_ratio(pair_row["x"])
    head = {"nu": pair_row["nu"], "E_over_sigma_y": pair_row["E_over_sigma_y"], "x": X, "s": X / (1.0 + X)}
    rows = [{**head, "quantity": "D", "P_over_P_Y": float(p), "phi": float(v)}
            for p, v in zip(x, loading_at(pair_row, x) / loading_at(rigid_row, x))]
    rigid_e = {round(p["P_max_over_P_Y"], 6): p["e"] for p in rigid_row["paths"]}
    for path in pair_row["paths"]:
        e_rf = rigid_e[round(path["P_max_over_P_Y"], 6)]
        rows.append({**head, "quantity": "loss", "P_over_P_Y": path["P_max_over_P_Y"],
                     "phi": (1.0 - path["e"] ** 2) / (1.0 - e_rf ** 2)})
    return rows


def table_rows(rows: list[dict]) -> list[dict]:
    """Every table case's node rows (module doc); ValueError when a case or its rigid flat is missing."""
    ok = {(r["nu"], r["E_over_sigma_y"], r["x"]): r for r in rows if r["role"] == "table" and r["status"] == "ok"}
    out = []
    for nu in NUS:
        for ratio in E_OVER_SIGMA_YS:
            for x in XS:
                if (nu, ratio, x) not in ok or (nu, ratio, RIGID) not in ok:
                    raise ValueError(f"the pair table needs the case nu {nu:g} E/sigma_Y {ratio:g} x {x} and its "
                                     f"rigid flat: run the build again (it resumes)")
                out += node_rows(ok[(nu, ratio, x)], ok[(nu, ratio, RIGID)])
    return out


def check_rows(rows: list[dict], table) -> list[dict]:
    """The pair law (calib.fit.pair_table.pair_law on ``table``, a PairTable) and the substitution (the vz
    master table's law on the pair's scales) driven along each held-out check's FE paths: e / e_FE - 1 and
    max |P - P_FE| / P_max per path, and whether its P_max is inside the law's window (``inside_window``)."""
    import warnings

    from calib.fit.calibration import drive_law
    from calib.fit.pair_table import pair_law

    out, seen = [], set()
    for row in (r for r in rows if r["role"] == "check" and r["status"] == "ok"):
        m, body = material(row["nu"], row["E_over_sigma_y"]), counter(row)
        found = pair_law(m, R, body, table)
        pair, law = found["law"].pair, found["law"]
        for path in row["paths"]:
            case = (row["nu"], row["E_over_sigma_y"], row["x"], row["counter_R_over_R"],
                    round(path["P_max_over_P_Y"], 6))
            if case in seen:
                continue            # (a top check repeats its check's lowest path)
            seen.add(case)
            fe = np.array(path["rows"])
            alpha, force = fe[:, 0] * pair.delta_Y, np.maximum(fe[:, 1], 0.0) * pair.P_Y
            errors = {}
            for name, params in (("pair_table", law), ("substitution", found["substitution"])):
                with warnings.catch_warnings():         # the FE's own paths: at the window's edge by rounding
                    warnings.simplefilter("ignore")
                    law_force, e = drive_law("vz-table", params, alpha)
                errors[name] = {"e_error": float(e / path["e"] - 1.0),
                                "force_error": float(np.abs(law_force - force).max() / force.max())}
            out.append({"nu": row["nu"], "E_over_sigma_y": row["E_over_sigma_y"], "x": stiffness_ratio(row["x"]),
                        "counter": "flat" if row["counter_R_over_R"] is None else
                        f"sphere R2 = {row['counter_R_over_R']:g} R", "P_max_over_P_Y": path["P_max_over_P_Y"],
                        "window_top": law.window.P_max_over_P_Y, "top_by": found["top_by"],
                        "inside_window": bool(path["P_max_over_P_Y"] <= law.window.P_max_over_P_Y * (1 + 1e-6)),
                        "e_fe": path["e"],
                        **{f"{name}_{k}": v for name, err in errors.items() for k, v in err.items()}})
    return sorted(out, key=lambda c: (c["nu"], c["E_over_sigma_y"], c["x"], c["counter"], c["P_max_over_P_Y"]))


def merged_checks(rows: list[dict]) -> list[dict]:
    """One row per held-out check pair: its paths and its top check's (calib.fit.pair_table_build.top_check_tasks)
    together, sorted by P_max, and the longer loading branch."""
    merged: dict = {}
    for row in (r for r in rows if r["role"] == "check" and r["status"] == "ok"):
        key = (row["nu"], row["E_over_sigma_y"], row["x"], row["counter_R_over_R"])
        into = merged.setdefault(key, {**row, "paths": {}})
        into["paths"].update({round(p["P_max_over_P_Y"], 6): p for p in row["paths"]})
        if row["loading"][-1][0] > into["loading"][-1][0]:
            into["loading"] = row["loading"]
    return [{**row, "paths": [row["paths"][k] for k in sorted(row["paths"])]} for row in merged.values()]


def check_specimen(row: dict):
    """(calib.fit.measured.specimen.Specimen on the check's counter-body, its true sigma_Y [Pa])."""
    from calib.fit.measured.specimen import Specimen

    m = material(row["nu"], row["E_over_sigma_y"])
    return Specimen(m.E, m.nu, R, m.rho, counter=counter(row)), m.sigma_y


# ----------------------------------------------------------------------------- outputs
CHECK_COLUMNS = ("nu", "E_over_sigma_y", "x", "counter", "P_max_over_P_Y", "window_top", "top_by", "inside_window",
                 "e_fe", "pair_table_e_error", "pair_table_force_error", "substitution_e_error", "substitution_force_error")


def accuracy(all_checks: list[dict]) -> str:
    """The table's one-line accuracy statement from its held-out checks' paths inside the laws' windows (and
    what the paths beyond them give)."""
    checks = [c for c in all_checks if c["inside_window"]]
    beyond = [c for c in all_checks if not c["inside_window"]]
    e = max(abs(c["pair_table_e_error"]) for c in checks)
    force = max(c["pair_table_force_error"] for c in checks)
    sub = max(abs(c["substitution_e_error"]) for c in checks)
    pairs = len({(c["nu"], c["E_over_sigma_y"], c["x"], c["counter"]) for c in checks})
    return (f"pair table: against the two-body FE of {pairs} held-out pairs ({len(checks)} paths up to "
            f"{max(c['P_max_over_P_Y'] for c in checks):.4g} P_Y), e within {100 * e:.2f} % and force within "
            f"{100 * force:.2f} % of P_max (the rigid-flat law on the pair's scales: e {100 * sub:.2f} %); the same "
            f"mesh family as the table ({ELEMENTS_PER_CONTACT_RADIUS:g} elements per contact radius, finite-strain "
            f"sphere), on the vz master table's law"
            + (f"; beyond the windows (the law extrapolated, not declared: {len(beyond)} paths to "
               f"{max(c['P_max_over_P_Y'] for c in beyond):.4g} P_Y) e {100 * max(abs(c['pair_table_e_error']) for c in beyond):.2f} %, "
               f"force {100 * max(c['pair_table_force_error'] for c in beyond):.2f} %" if beyond else ""))


def generate(out, table_out, workers: int = 2, progress=None) -> dict:
    """Run (or resume) every case, build the table, run (or resume) the checks at their window tops, and write
    the table CSV ``table_out`` with its .json (axes, accuracy, stamp), OUT/pair_table_checks.csv and
    OUT/pair_table.json."""
    from calib.fit.pair_table import COLUMNS, PairTable

    out, table_out = Path(out), Path(table_out)
    started = time.perf_counter()
    sweep = run(out, workers, progress)
    rows = table_rows(sweep.rows)
    table = PairTable(rows, {})
    extra = run(out, workers, progress, top_check_tasks(sweep.rows, table))
    runs = sweep.rows + extra.rows
    checks = check_rows(runs, table)
    statement = accuracy(checks) if checks else "no held-out checks"
    from calib.fit.vz_master_table import VZMasterTable

    master = VZMasterTable.load()
    fe_data = pair_fit_check.fe_data(merged_checks(runs), table, master, check_specimen)
    fits = pair_fit_check.fit_errors(fe_data, table, master)
    form = pair_fit_check.model_form(fits) if fits else {}
    mesh = {"elements_per_contact_radius": ELEMENTS_PER_CONTACT_RADIUS, "graded_from_P_over_P_Y": PEAKS_OVER_YIELD[0],
            "kinematics": KINEMATICS}
    st = output.stamp(time.perf_counter() - started, mesh=mesh, command="python -m calib.fit.pair_table_build",
                      fe_wall_time_s=sum(row.get("wall_time_s", 0.0) for row in runs),
                      computed=sweep.computed + extra.computed, reused=sweep.reused + extra.reused)
    axes = {"nu": list(NUS), "E_over_sigma_y": list(E_OVER_SIGMA_YS), "x": [stiffness_ratio(x) for x in XS]}
    output.write_csv(table_out, rows, COLUMNS, comment=output.stamp_comment(st))
    output.write_json(table_out.with_suffix(".json"), {"pair_table": {"axes": axes, "accuracy": statement,
                                                                       "model_form": form, "stamp": st}})
    output.write_json(out / "pair_fe_drops.json", {"rows": fe_data, "stamp": st})
    result = {"checks": checks, "accuracy": statement, "axes": axes, "table": str(table_out), "stamp": st,
              "model_form": form, "fit_checks": fits,
              "failures": [{k: row.get(k) for k in ("role", "nu", "E_over_sigma_y", "x", "error")}
                           for row in runs if row["status"] != "ok"],
              "runs": [{k: row.get(k) for k in ("role", "nu", "E_over_sigma_y", "x", "counter_R_over_R", "peaks",
                                                 "status", "wall_time_s", "dofs")} for row in runs]}
    output.write_csv(out / "pair_table_checks.csv", checks, CHECK_COLUMNS, comment=output.stamp_comment(st))
    output.write_json(out / "pair_table.json", result)
    return result


def main(argv=None) -> int:
    import argparse
    import sys

    from calib.fit.pair_table import DATA_FILE

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(output.RESULTS / "pairs"), help="the cases and the checks' folder")
    parser.add_argument("--table-out", default=str(DATA_FILE), help="the table CSV written (and its .json)")
    parser.add_argument("--workers", type=int, default=2, help="worker processes (default 2)")
    ns = parser.parse_args(argv)
    result = generate(ns.out, ns.table_out, ns.workers, progress=lambda m: print(m, file=sys.stderr))
    print(result["accuracy"])
    return 1 if result["failures"] else 0


if __name__ == "__main__":
    raise SystemExit(main())

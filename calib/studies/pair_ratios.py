"""A yielding sphere on an elastic flat over its rigid-flat FE: ratios over the stiffness ratio, results/pairs/ratios.*

For a sphere (E1, nu1, sigma_Y, R) pressed on an elastic flat (E2, nu2) the pair's Hertz scales (E*, R* = R and the
sphere's P_Y, delta_Y, a_Y; nfdmodel.ContactPair) carry the elastic contact exactly (Johnson 1985 eq. 4.22); what the
counter-body changes after first yield is measured here as two ratios of the two-body FE (calib.fe.two_body) to the
same sphere's rigid-flat FE on the same mesh level (so the meshes' error largely cancels), at equal P/P_Y:

    Phi_D(s, P/P_Y)     = D_pair / D_rf       D = alpha / delta_Y on the loading branch
    Phi_e(s, P_max/P_Y) = e_pair / e_rf       e of a load-unload path (calib.fe.loadpath.contact_work)

against the stiffness ratio x = E1' / E2', E' = E / (1 - nu^2), taken as s = x / (1 + x) = E* / E2' (s = 0: the
rigid flat, where both ratios are 1). The vz-table law's tables a_p/a_Y and C_R (calib.fit.table_fit) of each FE
are compared alike (f and g ratios at the peaks).

The mapped law, what a pair law without a pair FE would be: the rigid-flat D_rf (at the loading points) and e_rf (at
the peaks) of the sphere's own material, from its vz master table law (calib.fit.vz_master_table; its e from the
law's own loading and returned work) or from its same-mesh rigid-flat FE, times Phi_D, Phi_e at the pair's s (PCHIP
in s through Phi = 1 at s = 0; linear in nu between the measured nu), then the vz-table fit on the pair's scales
(calib.fit.table_fit.fit_tables: the loading curve D_pair and the returned work W_u = e_pair^2 W_l,pair):

    D_pair = D_rf Phi_D,   e_pair = e_rf Phi_e,   (f, g) = fit_tables(D_pair, W_u)

driven along each FE path of check materials that did not build the ratios (calib.fit.calibration.drive_law): e
and the largest force error against the pair FE, beside the substitution (the master table law on the pair's
scales, what nfdmodel does without a pair calibration).

Cases: R = 0.1 m, sigma_Y = 100 MPa, rho = 2700 kg/m^3, E = sigma_Y (E/sigma_Y), nu2 = nu1, the counter an elastic
flat; the calibration recipe's plan (calib.fit.recipe: paths to 13.7, 27.4, 41.2 P_Y of the pair with the
unloading paths below, calib.fit.impact_window.with_unloading_across), small strain, its ``coarse`` mesh level
(contact element a_max/10) unless --level says otherwise. The ratios: E/sigma_Y = 1000, nu 0.2, 0.3, 0.45, x = 1/3,
1/2, 1, 2, 3. The checks: (nu, E/sigma_Y) = (0.33, 400) at x = 1/2, 2; (0.3, 5000) at x = 1/3, 3; (0.3, 200) at
x = 1/3, 1 (x = 3 there reaches a = 0.2 R*, beyond the two-body FE's reach).

    python -m calib.studies.pair_ratios [--out results/pairs] [--workers 1] [--level coarse]

Each FE case is one resumable task (``OUT/ratio_cases/<key>.json``, calib.sweep.runner) keeping its FE data;
the comparison runs again from them (seconds). Writes OUT/ratios.csv and OUT/ratios.json.
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
from scipy.interpolate import PchipInterpolator

from calib import output
from calib.fit import recipe
from calib.fit.counter import CounterBody
from calib.fit.pair_table import law_curves
from calib.fit.pair_table_build import stiffness_ratio
from calib.report.index_format import read_json, study_header, table
from calib.sweep.runner import run_sweep
from meshes.keys import stable_key
from nfdmodel import CalibrationWindow, ContactPair, Material, VZTableParams

SIGMA_Y, R, RHO = 100e6, 0.1, 2700.0
RATIO_E_OVER_SIGMA_Y, RATIO_NUS = 1000.0, (0.2, 0.3, 0.45)
RATIO_XS = ("1/3", "1/2", "1", "2", "3")           # E1'/E2', exact fractions
CHECKS = ((0.33, 400.0, ("1/2", "2")), (0.3, 5000.0, ("1/3", "3")), (0.3, 200.0, ("1/3", "1")))
LEVEL = "coarse"
VERSION = 1                                         # part of each task's key: bump when the FE or the plan changes
RIGID = "rigid"


# ----------------------------------------------------------------------------- cases
def mapped_law(pair: ContactPair, x_loading, D_pair, peaks, e_pair,
               window: CalibrationWindow | None = None) -> VZTableParams:
    """The vz-table fit (calib.fit.table_fit) of the loading curve D_pair and the returned work e_pair^2 W_l,pair
    on ``pair``'s scales (x_loading, peaks in P/P_Y)."""
    from calib.fit.least_squares import radius_law_data
    from calib.fit.table_fit import LoadingWork, fit_tables

    above = x_loading > 1.0
    x, D = x_loading[above], D_pair[above]
    data = radius_law_data(x * pair.P_Y, D * pair.delta_Y, np.full(x.size, np.nan), R_star=pair.R_star,
                           E_star=pair.E_star, P_Y=pair.P_Y)
    work = e_pair ** 2 * LoadingWork(x, D)(peaks) * pair.P_Y * pair.delta_Y
    return fit_tables(data, pair, peaks * pair.P_Y, work, window)


def material(nu: float, E_over_sigma_y: float) -> Material:
    return Material(SIGMA_Y * E_over_sigma_y, nu, SIGMA_Y, RHO)


def counter(nu: float, E_over_sigma_y: float, x: str) -> CounterBody | None:
    """The elastic flat of E1'/E2' = x (nu2 = nu1, so E2 = E1 / x); None for the rigid flat."""
    return None if x == RIGID else CounterBody(SIGMA_Y * E_over_sigma_y / stiffness_ratio(x), nu)


def spec_of(task: dict) -> recipe.CalibrationSpec:
    """The calibration recipe's spec (its plan with the unloading paths below the lowest peak, as nfdcal calibrate)."""
    from calib.fit.impact_window import with_unloading_across

    spec = recipe.calibration_spec(material(task["nu"], task["E_over_sigma_y"]), R, level=task["level"],
                                   counter=counter(task["nu"], task["E_over_sigma_y"], task["x"]))
    return with_unloading_across(spec)


def case_task(nu: float, E_over_sigma_y: float, x: str, level: str = LEVEL) -> dict:
    case = {"nu": float(nu), "E_over_sigma_y": float(E_over_sigma_y), "x": x, "level": level}
    mesh = spec_of(case).mesh
    return {"key": stable_key({**case, "version": VERSION, "mesh": mesh.cache_key()}), **case}


def all_tasks(level: str = LEVEL) -> list[dict]:
    ratio = [case_task(nu, RATIO_E_OVER_SIGMA_Y, x, level) for nu in RATIO_NUS for x in (RIGID,) + RATIO_XS]
    check = [case_task(nu, ratio_, x, level) for nu, ratio_, xs in CHECKS for x in (RIGID,) + xs]
    return ratio + check


def build_meshes(tasks: list[dict]) -> None:
    """Mesh every task here, one at a time (gmsh is a process-wide singleton): workers read the cache."""
    from calib.fit.calibration import body_meshes

    for task in tasks:
        body_meshes(spec_of(task))


# ----------------------------------------------------------------------------- the FE
def run_task(task: dict) -> dict:
    """One calibration on one mesh (calib.fit.calibration, the vz-table law fitted); never raises."""
    from calib.fit.calibration import calibrate, summary

    t0 = time.perf_counter()
    try:
        spec = spec_of(task)
        result = calibrate(spec, meshes=1, ship="table")
        pair, s = spec.pair, summary(result)
        record = {"loading": [[r["P"] / pair.P_Y, r["alpha"] / pair.delta_Y] for r in result.load_paths.loading_rows],
                  "paths": [{"P_max_over_P_Y": p.peak / pair.P_Y, "e": p.restitution,
                             "e_table": s_path["models"]["vz-table"]["e"],
                             "rows": [[r["alpha"], r["P"]] for r in p.rows]}
                            for p, s_path in zip(result.load_paths.paths, s["paths"])],
                  "table": {k: s["table"][k] for k in ("P_over_P_Y", "a_p_over_a_Y", "C_R")},
                  "dofs": s["mesh"]["dofs"], "contact_size": spec.mesh.contact_size}
    except Exception as exc:                    # noqa: BLE001 - reported in the row, retried next run
        return {**task, "status": "failed", "error": f"{type(exc).__name__}: {exc}"[:400],
                "wall_time_s": time.perf_counter() - t0}
    return {**task, "status": "ok", **record, "wall_time_s": time.perf_counter() - t0,
            "git_commit": output.git_commit()}


# ----------------------------------------------------------------------------- the ratios
def curves(row: dict) -> tuple:
    """(loading P/P_Y, D, peaks P_max/P_Y, e) of one FE case."""
    loading = np.array(row["loading"])
    return (loading[:, 0], loading[:, 1], np.array([p["P_max_over_P_Y"] for p in row["paths"]]),
            np.array([p["e"] for p in row["paths"]]))


def case_ratios(pair_row: dict, rigid_row: dict) -> dict:
    """Phi_D at the rigid case's loading points, Phi_e and the tables' f, g ratios at the peaks."""
    xl, Dr, xp, er = curves(rigid_row)
    xl2, Dp, xp2, ep = curves(pair_row)
    if not np.allclose(xp, xp2, rtol=1e-9):
        raise ValueError("the pair and rigid-flat cases have different peaks")
    tables = []
    for row in (pair_row, rigid_row):
        t = row["table"]
        law = VZTableParams(ContactPair.sphere_flat(material(0.3, 1000.0), R), tuple(t["P_over_P_Y"]),
                            tuple(t["a_p_over_a_Y"]), tuple(t["C_R"]))     # dimensionless tables: any pair
        tables.append(law.tables(xp))
    return {"x_loading": xl, "phi_D": np.interp(np.log(xl), np.log(xl2), Dp) / Dr, "peaks": xp, "phi_e": ep / er,
            "e_pair": ep, "e_rf": er, "f_ratio": tables[0][0] / tables[1][0], "g_ratio": tables[0][1] / tables[1][1],
            "phi_D_peaks": np.interp(np.log(xp), np.log(xl2), Dp) / np.interp(np.log(xp), np.log(xl), Dr)}


class RatioTable:
    """Phi_D, Phi_e measured at (nu, s) on common loads: PCHIP in s (Phi = 1 at s = 0), linear in nu."""

    def __init__(self, by_case: dict):
        self.nus = np.array(sorted({nu for nu, _ in by_case}))
        xs = sorted({x for _, x in by_case}, key=stiffness_ratio)
        self.s = np.array([0.0] + [stiffness_ratio(x) / (1 + stiffness_ratio(x)) for x in xs])
        first = by_case[(self.nus[0], xs[0])]
        self.x_loading, self.peaks = first["x_loading"], first["peaks"]
        self.phi = {key: np.array([[np.ones_like(first[key])] + [by_case[(nu, x)][key] for x in xs] for nu in self.nus])
                    for key in ("phi_D", "phi_e")}            # (nu, s, load)

    def at(self, nu: float, x: float) -> tuple[np.ndarray, np.ndarray]:
        s = x / (1.0 + x)
        if not self.s[0] <= s <= self.s[-1] * (1 + 1e-12):
            raise ValueError(f"x = {x:g}: the ratios are measured for E1'/E2' up to {self.s[-1] / (1 - self.s[-1]):g}")
        out = []
        for key in ("phi_D", "phi_e"):
            by_nu = PchipInterpolator(self.s, self.phi[key], axis=1)(s)       # (nu, load)
            out.append(by_nu[0] if self.nus.size == 1 else
                       np.array([np.interp(nu, self.nus, by_nu[:, k]) for k in range(by_nu.shape[1])]))
        return out[0], out[1]


def against_fe(law, row: dict) -> list[dict]:
    """The law driven along each FE path's approach: e / e_FE - 1 and max |P - P_FE| / P_max."""
    import warnings

    from calib.fit.calibration import drive_law

    out = []
    for path in row["paths"]:
        rows = np.array(path["rows"])
        force = np.maximum(rows[:, 1], 0.0)
        with warnings.catch_warnings():         # the FE's own paths: beyond a table's window by its fit error
            warnings.simplefilter("ignore")
            law_force, e = drive_law("vz-table", law, rows[:, 0])
        out.append({"e_error": e / path["e"] - 1.0,
                    "force_error": float(np.abs(law_force - force).max() / force.max())})
    return out


def check_case(ratios: RatioTable, pair_row: dict, rigid_row: dict, master) -> dict:
    """The mapped law (from the vz master table and from the same-mesh rigid-flat FE) and the substitution (the
    master table's law on the pair's scales) against one check case's pair FE."""
    nu, ratio_, x = pair_row["nu"], pair_row["E_over_sigma_y"], stiffness_ratio(pair_row["x"])
    pair = counter(nu, ratio_, pair_row["x"]).pair(material(nu, ratio_), R)
    phi_D, phi_e = ratios.at(nu, x)
    xl, peaks = ratios.x_loading, ratios.peaks
    rl, rD, rpeaks, re = curves(rigid_row)
    values = master.tables(nu, ratio_)
    keep = values["x"] <= 1.5 * peaks[-1]
    master_law = VZTableParams(pair, tuple(values["x"][keep]), tuple(values["f"][keep]), tuple(values["g"][keep]))
    mD, me = law_curves(master_law, xl, peaks)
    laws = {"mapped_master": mapped_law(pair, xl, mD * phi_D, peaks, me * phi_e),
            "mapped_fe": mapped_law(pair, xl, np.interp(np.log(xl), np.log(rl), rD) * phi_D, peaks, re * phi_e),
            "substitution_master": master_law}
    out = {"nu": nu, "E_over_sigma_y": ratio_, "x": x, "peaks": list(peaks)}
    for name, law in laws.items():
        errors = against_fe(law, pair_row)
        out[name] = {"e_error": [r["e_error"] for r in errors], "force_error": [r["force_error"] for r in errors]}
    out["pair_table"] = {"e_error": [p["e_table"] / p["e"] - 1.0 for p in pair_row["paths"]]}
    out["substitution_fe"] = {"e_error": list(re / np.array([p["e"] for p in pair_row["paths"]]) - 1.0)}
    return out


def compare(rows: list[dict]) -> dict:
    """Every pair case against its rigid flat (ratios), the ratio table and the checks."""
    from calib.fit.vz_master_table import VZMasterTable

    ok = {(r["nu"], r["E_over_sigma_y"], r["x"]): r for r in rows if r["status"] == "ok"}
    cases, by_case = [], {}
    for (nu, ratio_, x), row in ok.items():
        rigid = ok.get((nu, ratio_, RIGID))
        if x == RIGID or rigid is None:
            continue
        r = case_ratios(row, rigid)
        if ratio_ == RATIO_E_OVER_SIGMA_Y:
            by_case[(nu, x)] = r
        for k, peak in enumerate(r["peaks"]):
            cases.append({"x": stiffness_ratio(x), "nu": nu, "E_over_sigma_y": ratio_, "P_max_over_P_Y": peak,
                          "e_pair": r["e_pair"][k], "e_substitution": r["e_rf"][k],
                          "e_error": r["e_rf"][k] / r["e_pair"][k] - 1.0, "phi_e": r["phi_e"][k],
                          "phi_D": r["phi_D_peaks"][k], "f_ratio": r["f_ratio"][k], "g_ratio": r["g_ratio"][k],
                          "wall_time_s": row["wall_time_s"], "rigid_wall_time_s": rigid["wall_time_s"],
                          "dofs": row["dofs"]})
    complete = all((nu, x) in by_case for nu in RATIO_NUS for x in RATIO_XS)
    checks = []
    if complete:
        ratios, master = RatioTable(by_case), VZMasterTable.load()
        for nu, ratio_, xs in CHECKS:
            for x in xs:
                if (nu, ratio_, x) in ok and (nu, ratio_, RIGID) in ok:
                    checks.append(check_case(ratios, ok[(nu, ratio_, x)], ok[(nu, ratio_, RIGID)], master))
    return {"cases": cases, "checks": checks, "spread": spread(cases)}


def spread(cases: list[dict]) -> list[dict]:
    """Per x and peak: Phi_e over the ratio materials (E/sigma_Y 1000, nu 0.2-0.45) and over all materials."""
    out = []
    for x in sorted({c["x"] for c in cases}):
        for peak in sorted({round(c["P_max_over_P_Y"], 6) for c in cases if c["x"] == x}):
            at = [c for c in cases if c["x"] == x and round(c["P_max_over_P_Y"], 6) == peak]
            train = [c["phi_e"] for c in at if c["E_over_sigma_y"] == RATIO_E_OVER_SIGMA_Y]
            every = [c["phi_e"] for c in at]
            out.append({"x": x, "P_max_over_P_Y": peak, "phi_e_nu_0.3": next(
                (c["phi_e"] for c in at if c["E_over_sigma_y"] == RATIO_E_OVER_SIGMA_Y and c["nu"] == 0.3), None),
                "phi_e_min": min(every), "phi_e_max": max(every),
                "phi_e_spread_ratio_materials": (max(train) - min(train)) if train else None,
                "phi_e_spread_all": max(every) - min(every), "materials": len(every)})
    return out


# ----------------------------------------------------------------------------- outputs
CSV_COLUMNS = ("x", "nu", "E_over_sigma_y", "P_max_over_P_Y", "e_pair", "e_substitution", "e_error", "phi_e", "phi_D",
               "f_ratio", "g_ratio", "dofs", "wall_time_s", "rigid_wall_time_s")


def generate(out: str | Path, workers: int = 1, level: str = LEVEL, progress=None) -> dict:
    out = Path(out)
    started = time.perf_counter()
    tasks = all_tasks(level)
    build_meshes(tasks)
    sweep = run_sweep(tasks, run_task, out / "ratio_cases", keep=lambda row: row.get("status") == "ok",
                      workers=workers, progress=progress,
                      describe=lambda row: (f"nu {row['nu']:g} E/sigma_Y {row['E_over_sigma_y']:g} x {row['x']} "
                                            f"({row['status']}, {row['wall_time_s']:.0f} s)"))
    result = compare(sweep.rows)
    result["failures"] = [{k: row.get(k) for k in ("nu", "E_over_sigma_y", "x", "error")}
                          for row in sweep.rows if row["status"] != "ok"]
    st = output.stamp(time.perf_counter() - started, mesh={"level": level,
                                                           "contact_size_over_a_max": recipe.MESH_LEVELS[level]},
                      command="python -m calib.studies.pair_ratios" + ("" if level == LEVEL else f" --level {level}"),
                      fe_wall_time_s=sum(row.get("wall_time_s", 0.0) for row in sweep.rows),
                      computed=sweep.computed, reused=sweep.reused)
    result["stamp"] = st
    output.write_csv(out / "ratios.csv", result["cases"], CSV_COLUMNS, comment=output.stamp_comment(st))
    output.write_json(out / "ratios.json", result)
    return result


def worst(values) -> float:
    return max(values, key=abs)


def summary_lines(result: dict) -> list[str]:
    lines = [f"{len(result['cases'])} pair paths, {len(result['failures'])} failed cases"]
    for c in result["checks"]:
        lines.append(f"check nu {c['nu']:g} E/sigma_Y {c['E_over_sigma_y']:g} x {c['x']:.3g}: e error mapped (master) "
                     f"{100 * worst(c['mapped_master']['e_error']):+.2f} %, mapped (same-mesh FE) "
                     f"{100 * worst(c['mapped_fe']['e_error']):+.2f} %, substitution (master) "
                     f"{100 * worst(c['substitution_master']['e_error']):+.2f} %")
    return lines


def pair_ratios(root: Path) -> list[str]:
    """The study's section of results/README.md (calib.report.results_index), from results/pairs/ratios.json."""
    data = read_json(root / "pairs" / "ratios.json")
    if data is None:
        return []
    lines = study_header("A sphere on an elastic flat: the pair FE over the rigid flat's (`pairs/ratios.json`)",
                         data["stamp"], "python -m calib.studies.pair_ratios") + [
        "A yielding sphere pressed on an elastic flat (two-body FE) against the same sphere on the rigid flat (same "
        "mesh level), on the pair's Hertz scales: Phi_e = e_pair / e_rf at equal P_max/P_Y, by the stiffness ratio "
        "x = E1'/E2' (nu2 = nu1). Its range over the materials (E/sigma_Y 200-5000, nu 0.2-0.45; at x = 3 "
        "E/sigma_Y 200 is out of the FE's reach) and its spread over nu 0.2-0.45 at E/sigma_Y 1000:", ""]
    rows = [[f"{s['x']:.3g}", f"{s['P_max_over_P_Y']:.3g}", f"{s['phi_e_nu_0.3']:.4f}",
             f"{s['phi_e_min']:.4f}-{s['phi_e_max']:.4f}", f"{100 * s['phi_e_spread_ratio_materials']:.2f}",
             f"{100 * s['phi_e_spread_all']:.2f}"]
            for s in data["spread"] if s["P_max_over_P_Y"] >= 7.0]
    lines += table(["x", "P_max/P_Y", "Phi_e (nu 0.3)", "Phi_e range", "spread over nu [points %]",
                    "spread, all [points %]"], rows)
    lines += ["The mapped law (the rigid-flat D and e times Phi_D, Phi_e interpolated in s = x/(1+x) and nu from "
              "E/sigma_Y 1000, then the vz-table fit) against the pair FE of materials that did not build the "
              "ratios; worst over the paths 2.15-41.2 P_Y, e / e_FE - 1 and max force error / P_max:", ""]
    rows = [[f"{c['nu']:g}", f"{c['E_over_sigma_y']:g}", f"{c['x']:.3g}",
             f"{100 * worst(c['mapped_master']['e_error']):+.2f} %",
             f"{100 * max(c['mapped_master']['force_error']):.2f} %",
             f"{100 * worst(c['mapped_fe']['e_error']):+.2f} %",
             f"{100 * worst(c['substitution_master']['e_error']):+.2f} %",
             f"{100 * max(c['substitution_master']['force_error']):.2f} %",
             f"{100 * worst(c['pair_table']['e_error']):+.2f} %"] for c in data["checks"]]
    lines += table(["nu", "E/sigma_Y", "x", "mapped (master table): e", "force", "mapped (same-mesh FE): e",
                    "substitution: e", "force", "pair calibration's own table: e"], rows)
    cases = data["cases"]
    if cases:
        pair_s, rigid_s = [c["wall_time_s"] for c in cases], [c["rigid_wall_time_s"] for c in cases]
        lines += [f"One calibration on this mesh: {min(pair_s):.0f}-{max(pair_s):.0f} s with the elastic flat, "
                  f"{min(rigid_s):.0f}-{max(rigid_s):.0f} s "
                  f"on the rigid flat; the FE of all cases: {data['stamp'].get('fe_wall_time_s', 0.0) / 60:.0f} min of "
                  f"worker time.", ""]
    return lines


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(output.RESULTS / "pairs"))
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--level", default=LEVEL, choices=tuple(recipe.MESH_LEVELS))
    ns = parser.parse_args(argv)
    result = generate(ns.out, workers=ns.workers, level=ns.level, progress=lambda m: print(m, file=sys.stderr))
    print("\n".join(summary_lines(result)))
    return 1 if result["failures"] else 0


if __name__ == "__main__":
    sys.exit(main())

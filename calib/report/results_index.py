"""results/README.md: an index of a results folder, generated from its own summary files.

``nfdcal results-readme [--out results] [--check]`` reads the summaries the commands write
(``calibration/calibration.json``, ``parameters.json``, ``mesh_ladder*.csv``, ``wide_window.json``, ``between_nodes.json``,
``identical_spheres.json``, ``hertz/hertz.json``, ``collision/summary.json``, ``tables/*/``, ``pairs/pairs.json``,
``stability/*.json``,
``lammps/summary.json``) and writes ``README.md`` beside them: per folder its files, the command
that regenerates them, its provenance stamp (code commit, mesh, wall time, date) and its key
figures. Every number in the file is read from those summaries, so the index is never older than
the results; a folder whose summary is missing is left out. ``render`` is a pure function of the
folder's contents (no clock, no machine), so ``--check`` can compare it with the file on disk.
"""
from __future__ import annotations

import math
import re
import textwrap
from pathlib import Path

from calib.report.index_format import (apct, files_line, g, num, pct, provenance, read_csv, read_json, section, span,
                                       study_header, table)
from calib.report.lammps_index import chung_ooi, heap, lammps
from nfdmodel import reference_case

README = "README.md"
GENERATOR = "nfdcal results-readme"
WIDTH = 110        # prose lines are wrapped to this width; table rows are not


# ---------------------------------------------------------------- sections
def calibration(root: Path) -> list[str]:
    folder = root / "calibration"
    cal, params = read_json(folder / "calibration.json"), read_json(folder / "parameters.json")
    if cal is None or params is None:
        return []
    rc = reference_case
    top = max(cal["paths"], key=lambda p: p["P_max"])
    radius, disc = cal["radius_fit"], cal["discretisation"]
    P_Y, a_Y = params["P_Y"], params["a_Y"]
    window = cal.get("shipped_window", cal["window"])
    lines = section("Reference calibration (`calibration/`)", folder, root, "nfdcal calibrate", cal["stamp"])
    lines += [f"The material of `parameters.json`: E = {params['material']['E']:g} Pa, nu = "
              f"{params['material']['nu']:g}, sigma_Y = {params['material']['sigma_y']:g} Pa, R = "
              f"{params['material']['R']:g} m; law `{params['law']}`, the {cal['shipped_fit']} fit shipped "
              f"(Ca and Kc: the two constants of the paper's law, fitted to the contact radius). "
              f"The paper: Vu-Quoc & Zhang (1999), Abaqus, 2141 CAX6 elements.", ""]
    fine = f"(the {disc['contact_sizes'][0]:g} m mesh alone: {{}}, R^2 {{:.3f}}, SE {{}})"
    lines += table(["quantity", "this FE", "paper"], [
        ["P_Y, first yield of a quadrature point [N]", f"{cal['P_Y_fe']:.4g} (theory {P_Y:.4g})", g(rc.P_Y)],
        [f"alpha at {top['P_max']:g} N [m]", g(top["alpha_max"]), g(rc.ALPHA_MAX_AFG)],
        [f"e of the path to {top['P_max']:g} N", f"{top['e']:.4f}", g(rc.E_AFG)],
        ["Ca [m/N], two meshes extrapolated", f"{g(cal['Ca'])}, estimated error {apct(cal['Ca_rel_error_estimate'])} "
         + fine.format(g(radius["Ca"]), radius["Ca_r2"], apct(radius["Ca_se"] / radius["Ca"], 1)), g(rc.CA)],
        ["Kc [1/N], the same", f"{g(cal['Kc'])}, estimated error {apct(cal['Kc_rel_error_estimate'])} "
         + fine.format(g(radius["Kc"]), radius["Kc_r2"], apct(radius["Kc_se"] / radius["Kc"], 1)), g(rc.KC)],
        ["Ca_hat = Ca P_Y / a_Y, Kc_hat = Kc P_Y (theory P_Y, a_Y)", f"{cal['Ca_hat']:.4f}, {cal['Kc_hat']:.4f}",
         f"{rc.CA * P_Y / a_Y:.4f}, {rc.KC * P_Y:.4f}"],
        ["calibrated window of the shipped law: P / P_Y, a_max / R", f"{window['P_min_over_P_Y']:.3g}..{window['P_max_over_P_Y']:.3g}, "
         f"{window['a_max_over_R']:.3g}", ""],
        ["wall time (both meshes) [s], factorisations of the first", f"{num(cal['wall_time_s'])}, "
         f"{cal['timings']['factorizations']}", ""],
    ])
    shipped = "vz-table" if cal["shipped_fit"] == "table" else "vz"
    labels = {"vz": f"vz, {'force' if cal['shipped_fit'] == 'force' else 'radius'} fit"}
    labels = {name: labels.get(name, name) + (" (shipped)" if name == shipped else "")
              for name in cal["paths"][0]["models"]}
    header = ["law"] + [f"e error, {p['P_max']:g} N" for p in cal["paths"]] + \
             [f"force error / P_max, {p['P_max']:g} N" for p in cal["paths"]]
    rows = [[labels.get(name, name)]
            + [pct(p["models"][name]["e"] / p["e"] - 1, 1) for p in cal["paths"]]
            + [apct(p["models"][name]["max_force_error_rel"], 1) for p in cal["paths"]]
            for name in cal["paths"][0]["models"]]
    lines += ["Each law driven along the FE's approach history of each path (`force_approach.png`): "
              "its restitution against the FE's and its largest force error:", ""]
    lines += table(header, rows)
    force = cal["force_fit"]
    lines += [f"The force fit: Ca = {g(force['Ca'])} m/N, Kc = {g(force['Kc'])} 1/N "
              f"(the radius fit on the finer mesh: {g(radius['Ca'])}, {g(radius['Kc'])}).", ""]
    return lines


def _order(coarse: float, middle: float, fine: float) -> float:
    """Observed convergence order of three rungs h, 2h, 4h."""
    return math.log2((middle - coarse) / (fine - middle))


def mesh_ladder(root: Path) -> list[str]:
    folder = root / "calibration"
    rungs, pairs = read_csv(folder / "mesh_ladder.csv"), read_csv(folder / "mesh_ladder_pairs.csv")
    if rungs is None or pairs is None:
        return []
    stamp, rows = rungs
    rows = sorted(rows, key=lambda r: -r["contact_size"])
    by_h = {r["contact_size"]: r for r in pairs[1]}
    lines = [f"## Mesh ladder of the reference calibration (`calibration/mesh_ladder*.csv`)", "",
             "Regenerate: `nfdcal calibrate --ladder`.", "", provenance(stamp), ""]
    out = []
    for r in rows:
        pair = by_h.get(r["contact_size"])
        out.append([f"{r['contact_size'] * 1e6:g}", r["dofs"], f"{r['Ca'] * 1e7:.4f}", f"{r['Kc'] * 1e4:.4f}",
                    f"{r['e_1500']:.4f}",
                    f"{pct(r['Ca_rel_error_vs_converged'])}, {pct(r['Kc_rel_error_vs_converged'])}",
                    num(r["wall_time_s"]),
                    "" if pair is None else
                    f"{pct(pair['Ca_rel_error_vs_converged'])} ({apct(pair['Ca_rel_error_estimate'])}), "
                    f"{pct(pair['Kc_rel_error_vs_converged'])} ({apct(pair['Kc_rel_error_estimate'])})",
                    "" if pair is None else num(pair["wall_time_parallel_s"])])
    lines += table(["h [um]", "dofs", "Ca [1e-7 m/N]", "Kc [1e-4 1/N]", "e at 1500 N",
                    "one mesh: Ca, Kc vs converged", "wall [s]",
                    "pair (h, 2h) extrapolated: Ca, Kc vs converged (estimate)", "pair wall, 2 processes [s]"], out)
    converged = {q: rows[-1][q] / (1 + rows[-1][f"{q}_rel_error_vs_converged"]) for q in ("Ca", "Kc")}
    orders = {q: ", ".join(f"{_order(*(rows[i + k][q] for k in range(3))):.2f}" for i in range(len(rows) - 2))
              for q in ("Ca", "Kc")}
    e = [r["e_1500"] for r in rows]
    alpha = [r["alpha_max_1500"] for r in rows]
    lines += [f"Converged (finest rungs extrapolated): Ca = {g(converged['Ca'])} m/N, Kc = {g(converged['Kc'])} 1/N. "
              f"Observed orders from three consecutive rungs: Ca {orders['Ca']}; Kc {orders['Kc']}. "
              f"Over the ladder e moves by {apct(max(e) / min(e) - 1)}, alpha by {apct(max(alpha) / min(alpha) - 1)}.",
              ""]
    return lines


def wide_window(root: Path) -> list[str]:
    data = read_json(root / "calibration" / "wide_window.json")
    if data is None:
        return []
    targets = data["stamp"].get("targets", {})
    lines = study_header("Wide windows: vz against vz-table (`calibration/wide_window.*`)", data["stamp"],
                         "python -m calib.studies.wide_window") + [
             "Force error = max |P_law - P_FE| / P_max along loading and unloading; e error = the law's "
             "quasi-static e against the FE path's; e collision = the law's own impact reaching that P_max"
             + (f"; targets {apct(targets['force_error'], 0)} and {apct(targets['e_error'], 0)}." if targets else "."),
             ""]
    names = {"radius": "vz, radius fit", "force": "vz, force fit", "table": "vz-table"}
    summary = []
    for fit, name in names.items():
        rows = [r for r in data["rows"] if r["fit"] == fit]
        if rows:
            summary.append([name, span([r["force_error"] for r in rows], apct), span([r["e_error"] for r in rows]),
                            f"{sum(r['meets_target'] for r in rows)} of {len(rows)}"])
    lines += table(["law, fitted over the whole window", "force error", "e error", "paths meeting both"], summary)
    by_path = {}
    for r in data["rows"]:
        by_path.setdefault((r["E_over_sigma_y"], r["P_max_over_P_Y"]), {})[r["fit"]] = r
    out = []
    for (ratio, load), fits in sorted(by_path.items()):
        cells = [f"{fits[f]['force_error'] * 100:.1f} %, {pct(fits[f]['e_error'])}" if f in fits else "-" for f in names]
        table_fit = fits.get("table")
        out.append([f"{ratio:g}", f"{load:.0f}", *cells,
                    pct(table_fit["e_collision_error"]) if table_fit else "-"])
    lines += table(["E/sigma_Y", "P_max/P_Y"] + [f"{n}: force, e error" for n in names.values()]
                   + ["vz-table, e collision error"], out)
    for m in data["materials"]:
        if m.get("unreachable"):
            lines += [f"At E/sigma_Y = {m['E_over_sigma_y']:g} the FE reaches {m['reach_over_P_Y']:.0f} P_Y: the paths "
                      f"to {', '.join(f'{x:g}' for x in m['unreachable'])} P_Y are beyond it.", ""]
    return lines


def between_nodes(root: Path) -> list[str]:
    data = read_json(root / "calibration" / "between_nodes.json")
    if data is None:
        return []
    targets = data["stamp"].get("targets", {})
    lines = study_header("Between the nodes of a shipped law (`calibration/between_nodes.*`)", data["stamp"],
                         "python -m calib.studies.between_nodes") + [
             "Each law a calibration ships, checked against FE load-unload paths that did not build it, at peaks "
             "between its unloading paths, inside its declared window and below it. e error = the law's "
             "quasi-static e against the FE path's; force error = max |P_law - P_FE| / P_max"
             + (f"; targets {apct(targets['e_error'], 0)} in e and {apct(targets['force_error'], 0)} in force "
                "inside the window." if targets else "."), ""]
    out = []
    for law in data["laws"]:
        window = law["window"]
        below = law.get("worst_e_error_below")
        out.append([f"{law['E_over_sigma_y']:g}", law["law"], f"{law['v_max']:g}",
                    f"{window['P_min_over_P_Y']:.3g} - {window['P_max_over_P_Y']:.0f}",
                    apct(law["worst_e_error_inside"]), apct(law["worst_force_error_inside"]),
                    apct(below) if below is not None else "-",
                    "yes" if law.get("meets_target_inside") else "no"])
    lines += table(["E/sigma_Y", "law", "v_max (m/s)", "window (P/P_Y)", "worst e error inside",
                    "worst force error inside", "worst e error below", "meets both inside"], out)
    for failure in data.get("failures", []):
        lines += [f"Not computed: {failure}", ""]
    return lines


def identical_spheres(root: Path) -> list[str]:
    data = read_json(root / "calibration" / "identical_spheres.json")
    if data is None:
        return []
    rigid, pair, d = data["rigid_flat"], data["identical_spheres"], data["differences"]
    lines = study_header("Two identical plastic spheres (`calibration/identical_spheres.json`)",
                         data["stamp"], "python -m calib.studies.identical_spheres") + [
             "The reference sphere calibrated against a counter-sphere of the same R and material (the two-body "
             "FE, calib.fe.two_body) and against the rigid flat, two meshes each: the symmetric pair's mid-plane "
             "is a rigid frictionless flat, so both must give the same constants (matching meshes: the "
             "differences are the Newton tolerance's, relative residual 1e-8).", ""]
    rows = [["Ca_hat", f"{rigid['Ca_hat']:.6g}", f"{pair['Ca_hat']:.6g}", g(d["Ca_hat"], 2)],
            ["Kc_hat", f"{rigid['Kc_hat']:.6g}", f"{pair['Kc_hat']:.6g}", g(d["Kc_hat"], 2)],
            ["P_Y(FE) [N]", f"{rigid['P_Y_fe']:.6g}", f"{pair['P_Y_fe']:.6g}", g(d["P_Y_fe"], 2)]]
    rows += [[f"e of the path to {a['P_max']:g} N", f"{a['e']:.6f}", f"{b['e']:.6f}", g(x, 2)]
             for a, b, x in zip(rigid["paths"], pair["paths"], d["e"])]
    rows += [["wall time (both meshes) [s]", num(rigid["wall_time_s"]), num(pair["wall_time_s"]), ""]]
    return lines + table(["quantity", "rigid flat", "two identical spheres", "relative difference"], rows)


def hertz(root: Path) -> list[str]:
    folder = root / "hertz"
    data = read_json(folder / "hertz.json")
    if data is None:
        return []
    top = data["top_load"]
    lines = section("Elastic FE against Hertz (`hertz/`)", folder, root, "nfdcal hertz && nfdcal hertz --ladder",
                    data["stamp"])
    lines += table(["at P = %g N" % round(top["P"]), "relative error"], [
        ["contact radius", pct(top["contact_radius_rel_error"])],
        ["peak pressure", pct(top["peak_pressure_rel_error"])],
        ["approach alpha", pct(top["alpha_rel_error"])],
        ["contact force against the plate's reaction", g(top["contact_force_rel_error"], 2)],
    ])
    lines += [f"Largest contact-radius error above first yield: {data['max_abs_contact_radius_error_m_above_36N'] * 1e6:.2f}"
              f" um. The approach follows alpha_Hertz - alpha_FE = k P / (E* R), k = "
              f"{data['alpha_finite_size']['coefficient_k']:.3f}: the finite hemisphere with a rigid top is "
              "stiffer than Hertz's half-space.", ""]
    ladder = read_csv(folder / "mesh_ladder.csv")
    if ladder:
        rows = [[f"{r['contact_size'] * 1e6:g}", r["n_dofs"], pct(r["contact_radius_gap_rel_error"]),
                 f"{r['contact_radius_pressure_max_abs_error_m'] * 1e6:.3g}", pct(r["peak_pressure_rel_error"]),
                 pct(r["alpha_rel_error"]), f"{r['finite_size_coefficient']:.3f}", num(r["wall_time_s"])]
                for r in sorted(ladder[1], key=lambda r: -r["contact_size"])]
        lines += ["Mesh ladder (`mesh_ladder.csv`, " + provenance(ladder[0])[len("Provenance: "):-1] + "):", ""]
        lines += table(["h [um]", "dofs", "contact radius error", "worst radius error above P_Y [um]",
                        "peak pressure error", "alpha error", "k", "wall [s]"], rows)
    return lines


def collision(root: Path) -> list[str]:
    folder = root / "collision"
    data = read_json(folder / "summary.json")
    if data is None:
        return []
    case, vz, th = data["case"], data["restitution_vz"], data["restitution_thornton"]
    window = data["vz_window"]
    lines = section("Collisions of the runtime laws (`collision/`)", folder, root,
                    data["stamp"].get("command", "nfdcal collide --report"), data["stamp"])
    lines += [f"Sphere on a rigid flat: R = {case['R']:g} m, mass {g(case['mass'])} kg, P_Y = {g(case['P_Y'])} N, "
              f"a_Y = {g(case['a_Y'])} m, delta_Y = {g(case['delta_Y'])} m, v_Y = {g(case['v_Y'])} m/s, "
              f"A_Y = {case['A_Y']:.5g}; vz constants from `{data['params_source']}` (Ca = {g(case['Ca'])} m/N, "
              f"Kc = {g(case['Kc'])} 1/N), window to {window['P_max_over_P_Y']:.3g} P_Y; dt = {vz['dt']:g} s.", ""]
    rows = [[f"{v:g}", f"{v / case['v_Y']:.1f}", f"{ev:.4f}", f"{et:.4f}", "yes" if inside else "no"]
            for v, ev, et, inside in zip(vz["v_in"], vz["e_velocity"], th["e_velocity"],
                                         window["in_calibrated_range"])]
    lines += table(["v_in [m/s]", "v_in / v_Y", "e, vz", "e, thornton", "vz inside its window"], rows)
    tc = data["thornton_closed_form_check"]
    lines += [f"e from velocities against e from energies: within {g(vz['max_relative_difference_e_velocity_e_energy'], 2)}"
              f" (vz), {g(th['max_relative_difference_e_velocity_e_energy'], 2)} (thornton); against the exact "
              f"energy balance: {g(vz['max_relative_error_vs_exact'], 2)}, {g(th['max_relative_error_vs_exact'], 2)}; "
              f"Thornton's closed form (paper eq. 1.11): {g(tc['max_relative_error'], 2)}.", ""]
    impact = data.get("impact_vz_v0.04")
    if impact:
        lines += [f"The vz impact at 0.04 m/s: P_max = {g(impact['P_max'])} N, delta_max = {g(impact['delta_max'])} m, "
                  f"residual {g(impact['delta_res'])} m, contact time {g(impact['contact_time'])} s.", ""]
    dt_rows = [[r["law"], f"{r['dt']:g}", r["steps"], g(r["error_e_velocity"], 2), g(r["error_P_max"], 2),
                num(r["wall_time_s"] * 1e3)] for r in data["dt_convergence"]]
    lines += ["Time-step convergence (largest error over the sweep's velocities, `dt_convergence.csv`):", ""]
    lines += table(["law", "dt [s]", "steps", "e error", "P_max error", "wall [ms]"], dt_rows)
    return lines


def _range(rows, key, fmt=apct) -> str:
    return span([r[key] for r in rows], fmt)


def master_table(root: Path) -> list[str]:
    folder = root / "tables" / "master_grid"
    data = read_json(folder / "table.json")
    if data is None:
        return []
    rows = [r for r in data["rows"] if r["status"] == "ok"]
    nus = sorted({r["nu"] for r in rows})
    ratios = sorted({r["E_over_sigma_y"] for r in rows})
    lines = section("The master table (`tables/master_grid/`, `tables/master_validation/`)",
                    (folder, root / "tables" / "master_validation"), root,
                    "nfdcal table master_grid --master-out calib/data/master_table.csv --accuracy ... "
                    "&& nfdcal table master_validation --check-master", data["stamp"])
    lines += [f"{len(rows)} nodes of {len(data['rows'])}: nu in {{{', '.join(f'{v:g}' for v in nus)}}} x "
              f"E/sigma_Y in {{{', '.join(f'{v:g}' for v in ratios)}}}; {sum(r['fe_wall_time_s'] for r in rows) / 60:.0f}"
              f" min of FE time; {min(r['dofs'] for r in rows)}-{max(r['dofs'] for r in rows)} dofs on the finer mesh.",
              ""]
    lines += table(["per node", "Ca_hat", "Kc_hat"], [
        ["estimated discretisation error (two meshes)", _range(rows, "Ca_hat_rel_error_estimate"),
         _range(rows, "Kc_hat_rel_error_estimate")],
        ["fit standard error", span([r["Ca_se"] / r["Ca"] for r in rows], apct),
         span([r["Kc_se"] / r["Kc"] for r in rows], apct)],
        ["fit R^2", span([r["Ca_r2"] for r in rows], lambda x: f"{x:.3f}"),
         span([r["Kc_r2"] for r in rows], lambda x: f"{x:.3f}")],
    ])
    check = read_json(root / "tables" / "master_validation" / "master_check.json")
    if check:
        lines += [f"Interpolation (PCHIP) against direct FE mid-cell (`master_validation/master_check.json`, "
                  f"limits {apct(check['stamp']['limits']['Ca_hat'], 0)} and {apct(check['stamp']['limits']['Kc_hat'], 0)}):", ""]
        lines += table(["nu", "E/sigma_Y", "Ca_hat error", "Kc_hat error", "within limits"],
                       [[f"{r['nu']:g}", f"{r['E_over_sigma_y']:g}", pct(r["Ca_hat_error"]), pct(r["Kc_hat_error"]),
                         "yes" if r["within_limits"] else "no"] for r in check["rows"]])
    stiffest = max(ratios)
    base = {r["nu"]: r for r in rows if r["E_over_sigma_y"] == stiffest}
    out = []
    for ratio in sorted(ratios, reverse=True)[1:]:
        cell = [r for r in rows if r["E_over_sigma_y"] == ratio and r["nu"] in base]
        out.append([f"{ratio:g}", span([r["window_a_max_over_R"] for r in cell], lambda x: f"{x:.3g}"),
                    span([r["Ca_hat"] / base[r["nu"]]["Ca_hat"] - 1 for r in cell], lambda x: pct(x, 1)),
                    span([r["Kc_hat"] / base[r["nu"]]["Kc_hat"] - 1 for r in cell], lambda x: pct(x, 1))])
    lines += [f"Do the constants depend on nu alone when a << R? Each node against its E/sigma_Y = {stiffest:g} "
              "value, over all nu:", ""]
    lines += table(["E/sigma_Y", "a_max / R", "Ca_hat change", "Kc_hat change"], out)
    reference = read_json(root / "calibration" / "calibration.json")
    node = next((r for r in rows if r["nu"] == reference_case.NU
                 and r["E_over_sigma_y"] == reference_case.E / reference_case.SIGMA_Y), None)
    if node and reference:
        lines += [f"The node (nu, E/sigma_Y) = ({node['nu']:g}, {node['E_over_sigma_y']:g}): Ca_hat = {node['Ca_hat']:.4g}, "
                  f"Kc_hat = {node['Kc_hat']:.4g}, against the reference calibration's {reference['Ca_hat']:.4g}, "
                  f"{reference['Kc_hat']:.4g} ({pct(node['Ca_hat'] / reference['Ca_hat'] - 1, 1)}, "
                  f"{pct(node['Kc_hat'] / reference['Kc_hat'] - 1, 1)}; its paths also unload).", ""]
    return lines


def vz_master_table(root: Path) -> list[str]:
    check = read_json(root / "tables" / "vz_master_grid" / "vz_master_check.json")
    shipped = read_json(Path(__file__).resolve().parents[1] / "data" / "vz_master_table.json")
    if check is None or shipped is None:
        return []
    law_table = shipped["vz_master_table"]
    lines = study_header("The master table of the load-dependent law (`tables/vz_master_grid/`)", shipped["stamp"],
                         "nfdcal table vz_master_grid --master-out calib/data/vz_master_table.csv")
    lines += [f"a_p/a_Y and C_R of the vz-table law at P/P_Y {law_table['P_over_P_Y'][0]:g}..{law_table['P_over_P_Y'][-1]:.4g} "
              f"({len(law_table['P_over_P_Y'])} loads) over nu {', '.join(f'{x:g}' for x in law_table['nu'])} x E/sigma_Y "
              f"{', '.join(f'{x:g}' for x in law_table['E_over_sigma_y'])}, each node an FE calibration with unloading "
              "paths log-spaced over its window (`nodes/`; `nfdcal material --v-max V` reads it). Accuracy, "
              f"against FE paths of off-grid materials (`vz_master_check.*`): {law_table['accuracy']}.", ""]
    rows = [[f"{r['nu']:g}", f"{r['E_over_sigma_y']:g}", f"{r['P_max_over_P_Y']:.3g}",
             f"{r['window_low']:.3g} - {r['window_top']:.0f}", "yes" if r["inside"] else "no",
             pct(r["e_error"]), apct(r["force_error"])] for r in check["rows"]]
    return lines + table(["nu", "E/sigma_Y", "P_max/P_Y", "window (P/P_Y)", "inside", "e error", "force error"], rows)


def fit_data_benchmark(root: Path) -> list[str]:
    data = read_json(root / "fit_data" / "fe_benchmark.json")
    if data is None:
        return []
    stamp = data["stamp"]
    targets = stamp.get("targets", {})
    materials = sorted({(f["nu"], f["E_over_sigma_y"]) for f in data["fits"] if not f["kind"].startswith("dyn: ")})
    dynamic = sorted({f["material"] for f in data["fits"] if f["kind"].startswith("dyn: ")})
    lines = study_header("fit-data on FE data the law did not make (`fit_data/`)", stamp,
                         "python tests/benchmarks/bench_fit_data_fe.py")
    lines += [f"sigma_Y recovered by `nfdcal fit-data --law vz-table` from FE drop tests (e; e and P_max; e, P_max and "
              f"the contact time) and FE force-approach curves of {len(materials)} materials that are not table nodes "
              "((nu, E/sigma_Y) = " + ", ".join(f"({nu:g}, {ratio:g})" for nu, ratio in materials) + ")"
              + (f" and from the drop tests of the dynamic FE (`nfdcal impact`, \"dyn\": {', '.join(dynamic)})"
                 if dynamic else "")
              + f", noise added to the FE data, {stamp.get('trials', '?')} trials per noise level and material "
              "(\"x2\": each drop test twice, half the trials); coverage = the share of 95 % intervals that hold the "
              "true sigma_Y, with its binomial 95 % interval (Clopper-Pearson); noise-free max = the method's bias; "
              "sd_CR = the Cramer-Rao spread of sigma_Y the data allow (noise / sqrt(sum (d r_i / d ln sigma_Y)^2), "
              "the law's sensitivities), and the share of fits within the target an unbiased estimator of that spread "
              "would reach"
              + (f"; targets |error| <= {apct(targets['abs_error'], 0)}, coverage >= {targets['coverage95']:.0%}."
                 if targets else "."), ""]
    lines += fit_data_findings(data["summary"], targets.get("abs_error", 0.03)) + [""]

    def coverage(r):
        return (f"{r['coverage95']:.0%} ({r['coverage95_low']:.0%}-{r['coverage95_high']:.0%})"
                if "coverage95_low" in r else f"{r['coverage95']:.0%}")

    def within(r):
        return f"{r['within_target']:.0%} / {r['within_target_cr']:.0%}" if "within_target_cr" in r else "-"

    rows = [[r["kind"], apct(r["noise"], 0), f"{r['fits']}", pct(r["bias"]), apct(r["rms_error"]),
             apct(r["max_abs_error"]), apct(r["noise_free_max_abs_error"]) if "noise_free_max_abs_error" in r else "-",
             apct(r["sd_cr"]) if "sd_cr" in r else "-", within(r), coverage(r),
             "yes" if r["meets_target"] else "no"] for r in data["summary"]]
    return lines + table(["data", "noise", "fits", "bias", "rms error", "max error", "noise-free max", "sd_CR",
                          "within target (measured / CR)", "95 % coverage (CI)", "meets both"], rows)


def fit_data_findings(summary: list[dict], target: float) -> list[str]:
    """The benchmark's findings in words: the bias against the target, the noisy error against the
    spread the data allow, the error with twice the drop tests."""
    by = {(r["kind"], r["noise"]): r for r in summary}
    kinds = [k for k in ("drops e", "drops e+P", "drops e+P+t", "force", "dyn: drops e", "dyn: drops e+P",
                         "dyn: drops e+P+t") if (k, 0.0) in by]
    out = []
    if kinds:
        worst = max(by[k, 0.0]["max_abs_error"] for k in kinds)
        out.append(f"Bias (noise-free data): largest error {apct(worst)} over the kinds (target {apct(target, 0)}).")
    for kind in ("drops e", "drops e+P"):
        r, twice = by.get((kind, 0.03)), by.get((f"{kind} x2", 0.03))
        if r is None or "sd_cr" not in r:
            continue
        text = (f"{kind} at 3 % noise, {r.get('n_drops', '?')} drop tests: rms error {apct(r['rms_error'])} against the "
                f"Cramer-Rao spread {apct(r['sd_cr'])}; {r['within_target']:.0%} of fits within {apct(target, 0)}, where "
                f"an unbiased estimator of that spread reaches {r['within_target_cr']:.0%}")
        if r["max_abs_error"] > target and r["noise_free_max_abs_error"] <= target and r["rms_error"] <= 1.25 * r["sd_cr"]:
            text += (f": the largest error {apct(r['max_abs_error'])} is the scatter of {r.get('n_drops', '?')} drop tests "
                     "at this noise (rms error within 1.25 sd_CR), not the method's bias")
        if twice is not None:
            text += (f". Twice the drop tests: rms {apct(twice['rms_error'])} (1/sqrt(2) of {apct(r['rms_error'])}: "
                     f"{apct(r['rms_error'] / math.sqrt(2))}), sd_CR {apct(twice['sd_cr'])}")
        out.append(text + ".")
    return out


def stability(root: Path) -> list[str]:
    folder = root / "stability"
    runtime, fe, fuzz, plugin = (read_json(folder / n) for n in ("runtime_stability.json", "fe_stability.json",
                                                                 "fuzz.json", "fuzz_lammps.json"))
    if runtime is None and fe is None and fuzz is None and plugin is None:
        return []
    lines = [f"## Stability (`stability/`)", "", files_line(root, folder), ""]
    if runtime:
        s = runtime["summary"]
        lines += [f"**Runtime** (`{runtime['stamp'].get('command', 'nfdcal stability')} --runtime`): {s['cases']} "
                  f"cases, " + ", ".join(f"{n} {k}" for k, n in s["outcomes"].items())
                  + f", {len(s['failures'])} failures; the backends disagree on {len(s.get('backends_disagree', []))}; "
                  f"at most {s['newton_max']} Newton iterations. " + provenance(runtime["stamp"]), ""]
        lines += table(["backend", "cases", "outcomes"],
                       [[name, b["cases"], ", ".join(f"{n} {k}" for k, n in b["outcomes"].items())]
                        for name, b in s.get("backends", {}).items()])
        worst = [[group, ", ".join(f"{k} {g(v, 2)}" for k, v in errs.items())]
                 for group, errs in s["worst_errors_of_ok_rows"].items()]
        lines += table(["group", "largest error of the cases that ran"], worst)
    if fe:
        s = fe["summary"]
        lines += [f"**FE** (`nfdcal stability --fe`): {s['runs']} runs, "
                  + ", ".join(f"{n} {k}" for k, n in s["outcomes"].items()) + f", {len(s['failures'])} failures; "
                  f"at most {s['newton_max']} Newton iterations. " + provenance(fe["stamp"]), ""]
        cases = {}
        for r in fe["rows"]:
            cases.setdefault(r["case"], []).append(r)
        out = []
        for name, runs in cases.items():
            fine = min(runs, key=lambda r: r["mesh_ratio"])
            if fine["outcome"] != "ok":
                out.append([name, fine["outcome"].split(":")[0], "", "", "", ""])
                continue
            out.append([name, "ok", f"{fine['Ca_hat']:.4g}, {fine['Kc_hat']:.4g}", f"{fine['e']:.3f}",
                        ", ".join(pct(fine[k] or 0.0, 1) for k in ("Ca_hat_mesh_change", "Kc_hat_mesh_change")),
                        fine["newton_max"]])
        lines += table(["case", "outcome", "Ca_hat, Kc_hat", "e", "mesh change Ca_hat, Kc_hat", "Newton max"], out)
    if fuzz:
        lines += [f"**Command-line fuzzer** (`{fuzz['stamp']['command']}`): slowest case "
                  f"{fuzz['slowest_case_s']:.2g} s. " + provenance(fuzz["stamp"]), ""]
        lines += table(["command", "cases", "successes", "clean errors", "failures"],
                       [[r["command"], r["cases"], r["successes"], r["clean_errors"], r["failures"]]
                        for r in fuzz["rows"]])
    if plugin:
        lines += [f"**LAMMPS plugin input fuzzer** (`{plugin['stamp']['command']}`): pair_coeff and wall-fix lines "
                  "of every law, each an impact that runs without creating energy or an ERROR line naming the "
                  "command and what is out of range. " + provenance(plugin["stamp"]), ""]
        lines += table(["law", "command", "cases", "ran", "refused", "failures"],
                       [[r["law"], r["command"], r["cases"], r["ran"], r["refused"], r["failures"]]
                        for r in plugin["rows"]])
    for path in sorted(folder.glob("mesh_ladder_nu*.csv")):
        stamp, rows = read_csv(path)
        rows = sorted(rows, key=lambda r: -r["contact_size"])
        lines += [f"**Mesh ladder at nu = {rows[0]['nu']:g}** (`{path.name}`, `nfdcal calibrate --ladder --nu "
                  f"{rows[0]['nu']:g} --out results/stability`): no volumetric locking if the coarse meshes are not "
                  "stiffer. " + provenance(stamp), ""]
        lines += table(["h [um]", "dofs", "Ca [1e-7 m/N]", "Kc [1e-4 1/N]", "e at 1500 N",
                        "change vs finest: alpha, contact radius, Ca, Kc"],
                       [[f"{r['contact_size'] * 1e6:g}", r["dofs"], f"{r['Ca'] * 1e7:.4f}", f"{r['Kc'] * 1e4:.4f}",
                         f"{r['e_1500']:.4f}", ", ".join(pct(r[f"{q}_rel_change_vs_finest"]) for q in
                                                         ("alpha_max_1500", "contact_radius_1500", "Ca", "Kc"))]
                        for r in rows])
    return lines


def impact(root: Path) -> list[str]:
    folder = root / "impact"
    data = read_json(folder / "impact.json")
    if data is None:
        return []
    case = data["case"]
    lines = section("Dynamic FE impacts of the whole sphere (`impact/`)", folder, root,
                    "nfdcal impact && nfdcal impact --convergence --v-in 0.04 (vz_table/: nfdcal calibrate --v-max 0.504 "
                    "--out results/impact/vz_table)", data["stamp"])
    lines += [f"The sphere (R = {case['R']:g} m, mass {g(case['mass'])} kg, v_Y = {g(case['v_Y'])} m/s, P_Y = "
              f"{g(case['P_Y'])} N) thrown at the rigid flat; e = rebound speed of the centre of mass over v_in, with "
              f"its estimated discretisation error (mesh and time step); qs FE = the quasi-static FE load-unload path to "
              f"the same P_max thrown as a collision; vz constants from `{data['vz_source']}`"
              + (f", vz-table from `{data['vz_table_source']}`" if data.get("vz_table_source") else "")
              + "; vibr. = vibration energy left after separation over the kinetic energy in; balance residual: "
              "over the kinetic energy in (at twice dt): the time discretisation's (calib.studies.impact).", ""]
    rows = []
    for r in data["impacts"]:
        m, qs = r["models"], r.get("quasi_static", {})
        law = lambda name: f"{m[name]['e']:.4f}" if name in m else "-"      # noqa: E731
        error = r.get("e_rel_error_estimate")
        rows.append([f"{r['v_in_over_v_Y']:.3g}", f"{r['P_max_over_P_Y']:.4g}",
                     f"{r['e']:.4f}" + (f" ± {error * r['e']:.4f}" if error is not None else ""),
                     f"{qs['e']:.4f}" if qs else "-", law("vz"), law("vz_table"), law("thornton"),
                     f"{m['thornton']['e_closed_form']:.4f}" if "thornton" in m else "-", law("mdr"),
                     f"{r['contact_time'] * 1e3:.4g}", f"{qs['contact_time'] * 1e3:.4g}" if qs else "-",
                     g(r["vibration_fraction"], 2), g(r["balance_residual_fraction"], 2)
                     + (f" ({g(r['balance_residual_fraction_coarse_dt'], 2)})"
                        if r.get("balance_residual_fraction_coarse_dt") is not None else "")])
    lines += table(["v_in / v_Y", "P_max / P_Y", "e, FE", "e, qs FE", "vz", "vz-table", "Thornton", "Thornton closed",
                    "LAMMPS mdr", "t_c FE [ms]", "t_c qs FE [ms]", "vibr.", "balance residual"], rows)
    limit = data.get("quasi_static") or {}
    if limit:
        from calib.studies.impact_output import quasi_static_words

        lines += ["Dynamic over quasi-static FE at the same P_max: " + quasi_static_words(limit) + ".", ""]
    convergence = read_json(folder / "convergence.json")
    if convergence:
        runs = [[r["ladder"], f"{r['contact_size'] * 1e6:g}", r["steps_per_contact"], r["dofs"], f"{r['e']:.5f}",
                 g(r.get("e_error"), 2), num(r["wall_time_s"])] for r in convergence["runs"]]
        lines += [f"Convergence at v_in = {convergence['v_in']:g} m/s ({convergence['v_in_over_v_Y']:.3g} v_Y; "
                  f"`convergence.json`, e_error against the extrapolated value):", ""]
        lines += table(["ladder", "h [um]", "steps per contact", "dofs", "e", "e error", "wall [s]"], runs)
    return lines


def pairs(root: Path) -> list[str]:
    data = read_json(root / "pairs" / "pairs.json")
    if data is None:
        return []
    from calib.studies.pairs_output import column_spans

    lines = section("Unlike bodies: the rigid-flat substitution against the two-body FE (`pairs/`)", root / "pairs",
                    root, data["stamp"].get("command", "python -m calib.studies.pairs"), data["stamp"])
    rigid = data["rigid_flat"]
    lines += ["The rigid-flat law with the pair's E*, R* and the yielding body's constants (nfdmodel.ContactPair) "
              "against the FE of both bodies: substitution / FE - 1 of the force at equal approach and the contact "
              "radius at equal force (loading, 1..41.2 P_Y) and of e at equal P_max/P_Y (paths to 13.7, 27.4, 41.2 "
              "P_Y); nu = 0.3, the first-yielding body E/sigma_Y = 700. The substitution column carries the "
              "rigid-flat FE itself over (law-free); the vz column is the two constants of the rigid-flat radius "
              f"fit (Ca_hat {rigid['Ca_hat']:.4f}, Kc_hat {rigid['Kc_hat']:.4f}) on the pair's scales, whose own "
              "error against the rigid-flat FE a pair calibration keeps.", ""]
    out = [[c["shape"], c["yielding"], ", ".join(f"{x:.3g}" for x in c["ratios"]), c["force_error"],
            c["radius_error"], c["e_error"], c["law_e_error"]] for c in column_spans(data["rows"])]
    lines += table(["counter-body", "yields", "E1/E2", "force error", "contact radius error", "e error",
                    "vz law e error"], out)
    steer = data.get("steer_e_error", 0.02)
    over = [r for r in data["rows"] if max(abs(r["e_error_min"]), abs(r["e_error_max"])) > steer]
    lines += ["Two spheres of equal radius: the columns where the sphere and where the counter-body yields are one "
              "problem mirrored, and the FE gives them equal (a check of the two-body FE).",
              "", f"In {len(over)} of {len(data['rows'])} cases the substitution misses e by more than {apct(steer, 0)}: "
              "there the tools name a pair calibration (calib/data/substitution_error.csv, calib.fit.substitution).", ""]
    check = data.get("mesh_check")
    if check and "largest_change" in check:
        case = check["case"]
        lines += [f"Mesh: the grid's contact element is a_max/10 (the recipe's coarse level); at the default level "
                  f"(a_max/37) the case E1/E2 = {case['E1_over_E2']:.3g}, {case['shape']} counter-body, {case['yielding']} "
                  f"yielding, moves each error by at most {100 * check['largest_change']:.2f} points (e error "
                  f"{span([check['default']['e_error_min'], check['default']['e_error_max']])} against "
                  f"{span([check['grid']['e_error_min'], check['grid']['e_error_max']])}).", ""]
    if "fe_wall_time_s" in data["stamp"]:
        lines += [f"The FE of the {len(data['rows'])} cases, the rigid flat and the mesh check: "
                  f"{data['stamp']['fe_wall_time_s'] / 60:.0f} min of worker time.", ""]
    for failure in data.get("failures", []):
        lines += [f"Not computed: {failure}", ""]
    return lines


def other(root: Path) -> list[str]:
    known = {"calibration", "hertz", "collision", "tables", "stability", "lammps", "impact", "fit_data", "pairs",
             README}
    rest = sorted(p.name + ("/" if p.is_dir() else "") for p in root.iterdir()
                  if not p.name.startswith(".") and p.name not in known)
    if (root / "tables").is_dir():     # parameter tables of other scenes
        rest += sorted(f"tables/{p.name}/" for p in (root / "tables").iterdir()
                       if p.is_dir() and p.name not in ("master_grid", "master_validation"))
    if not rest:
        return []
    lines = ["## Other files", ""]
    notes = {"linear_solvers.md": " (the FE's sparse direct solver against the alternatives; "
                                  "`tests/benchmarks/bench_linear_solvers.py`)"}
    lines += [f"- [`{n}`]({n}){notes.get(n, '')}" for n in rest]
    return lines + [""]


SECTIONS = (calibration, mesh_ladder, wide_window, between_nodes, identical_spheres, hertz, collision, impact,
            master_table, vz_master_table, fit_data_benchmark, pairs, stability, lammps, chung_ooi, heap, other)


def read_section(make, root: Path) -> list[str]:
    """``make(root)``; a summary without what the index reads (another version's, a damaged one) is
    a ValueError naming the section, never a traceback."""
    try:
        return make(root)
    except (KeyError, TypeError, IndexError, AttributeError, ZeroDivisionError, StopIteration) as exc:
        raise ValueError(f"the summary files of the section '{make.__name__}' lack what the index reads "
                         f"({type(exc).__name__}: {exc}); regenerate them") from None


def render(root: str | Path) -> str:
    """The text of ``root``/README.md, from the summary files under ``root``."""
    root = Path(root)
    if not root.is_dir():
        raise ValueError(f"no results folder at {root} (run a command that writes results first)")
    bodies = [lines for lines in (read_section(s, root) for s in SECTIONS) if lines]
    titles = [b[0][3:] for b in bodies]
    anchor = lambda t: "".join(c for c in t.lower().replace(" ", "-") if c.isalnum() or c in "-_")
    head = ["# Results", "",
            f"Generated by `{GENERATOR}` from the summary files in this folder: do not edit it by hand.",
            f"`{GENERATOR} --check` exits 1 when this file differs from what the summaries give. Each section",
            "names its files, the command that regenerates them and their provenance (code commit, mesh, wall time,",
            "date)."]
    guides = [name for name in ("README.md", "calib/README.md", "nfdmodel/README.md") if (root.parent / name).is_file()]
    if guides:   # inside a checkout: where the quantities are defined
        head += ["What the quantities mean: " + ", ".join(f"[{n}](../{n})" for n in guides) + "."]
    head += ["", "Contents:", ""] + [f"- [{t}](#{anchor(t)})" for t in titles] + [""]
    lines = [wrap(line) for line in head + [line for body in bodies for line in body]]
    return "\n".join(lines).rstrip("\n") + "\n"


def wrap(line: str) -> str:
    """A prose line (or list item) folded to ``WIDTH``; headings and table rows as they are."""
    if len(line) <= WIDTH or line.startswith(("|", "#")):
        return line
    indent = "  " if line.startswith("- ") else ""
    rows = textwrap.wrap(line, WIDTH, subsequent_indent=indent, break_long_words=False, break_on_hyphens=False)
    for i in range(1, len(rows)):   # a continuation must not read as Markdown (a list item, a heading, a table)
        while MARKUP_START.match(rows[i]) and " " in rows[i - 1].strip():
            head, _, word = rows[i - 1].rpartition(" ")
            rows[i - 1], rows[i] = head, indent + word + " " + rows[i].lstrip()
    return "\n".join(rows)


MARKUP_START = re.compile(r"^\s*([-+*>#=|]|\d+[.)])(\s|$)")

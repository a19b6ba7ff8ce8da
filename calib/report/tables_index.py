"""The master tables' sections of results/README.md (calib.report.results_index): the master table of Ca_hat,
Kc_hat (results/tables/master_grid, master_validation; ``nfdcal table``) and the vz master table
(results/tables/vz_master_grid, calib/data/vz_master_table.json; calib.fit.vz_master_check), its hardening sheet
(results/tables/vz_master_reach_hardening, calib/data/vz_hardening_table.json; calib.fit.vz_hardening_build) and the
pair table (results/pairs/pair_table.json, calib/data/pair_table.csv; calib.fit.pair_table_build).
"""
from __future__ import annotations

from pathlib import Path

from calib.report.index_format import apct, pct, read_json, section, span, study_header, table
from nfdmodel import limits, reference_case


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
    shipped = read_json(Path(__file__).resolve().parents[1] / "data" / "vz_master_table.json")
    scene = (shipped or {}).get("vz_master_table", {}).get("scene", "vz_master_grid")
    check = read_json(root / "tables" / scene / "vz_master_check.json")
    if check is None or shipped is None:
        return []
    law_table = shipped["vz_master_table"]
    lines = study_header(f"The master table of the load-dependent law (`tables/{scene}/`)", shipped["stamp"],
                         f"nfdcal table {scene} --master-out calib/data/vz_master_table.csv")
    unloading = check.get("unloading_rows") or []
    join = law_table.get("join")
    if join:
        joins = [j["x_join"] for j in join["join_over_P_Y"]]
        lines += [f"Finite-strain nodes (`nodes/`) joined with the small-strain grid's (`tables/"
                  f"{join['small_strain_scene']}/nodes/`, {join['small_strain_scene']}'s own checks and reference "
                  f"ladder there): each node takes the small-strain values below the load where the FE's contact "
                  f"radius is {join['join_a_over_R']:g} R (or the small grid's top), {min(joins):.3g}-{max(joins):.4g} "
                  f"P_Y over the nodes, and the finite strain's above, to {limits.FE_FINITE_MAX_LOAD_OVER_YIELD:g} P_Y or a = "
                  f"{limits.FE_FINITE_MAX_CONTACT_RADIUS_OVER_R:g} R. The checks below: "
                  f"the finite-strain off-grid materials (`nodes/`, to the reach) and the small-strain ones' paths below "
                  f"their join.", ""]
    lines += [f"a_p/a_Y and C_R of the vz-table law at P/P_Y {law_table['P_over_P_Y'][0]:g}..{law_table['P_over_P_Y'][-1]:.4g} "
              f"({len(law_table['P_over_P_Y'])} loads) over nu {', '.join(f'{x:g}' for x in law_table['nu'])} x E/sigma_Y "
              f"{', '.join(f'{x:g}' for x in law_table['E_over_sigma_y'])}, each node an FE calibration with unloading "
              "paths log-spaced over its window (`nodes/`; `nfdcal material --v-max V` reads it)"
              + (", and the vz-unload law's dent ratio delta_res/delta_max and unloading exponent m from the same "
                 "nodes' unloading paths (`nfdcal material --v-max V --law vz-unload`)" if unloading else "")
              + (", its contact radius a_p/a_Y from the FE's contact radius along the nodes' loading branches "
                 "(`loading/`: each node's loading rerun alone, the same loads)" if "radius_a_p_over_a_Y"
                 in law_table.get("definition", "") else "")
              + f". Accuracy, against FE paths of off-grid materials (`vz_master_check.*`): {law_table['accuracy']}.",
              ""]
    rows = [[f"{r['nu']:g}", f"{r['E_over_sigma_y']:g}", f"{r['P_max_over_P_Y']:.3g}",
             f"{r['window_low']:.3g} - {r['window_top']:.0f}", "yes" if r["inside"] else "no",
             pct(r["e_error"]), apct(r["force_error"])] for r in check["rows"]]
    lines += table(["nu", "E/sigma_Y", "P_max/P_Y", "window (P/P_Y)", "inside", "e error", "force error"], rows)
    if not unloading:
        return lines
    lines += ["", "Along the same FE unloading curves, the table's vz-unload law against its vz-table law (dent: "
              "delta_res / alpha_res,FE - 1; unloading: max |P_law - P_FE| / P_max over the FE's unloading points):", ""]
    rows = [[f"{r['nu']:g}", f"{r['E_over_sigma_y']:g}", f"{r['P_max_over_P_Y']:.3g}", "yes" if r["inside"] else "no",
             f"{r['dent_fe_over_alpha_max']:.3g}"]
            + [value for law in ("vz-unload", "vz-table") for value in
               (pct(r[f"{law} dent_error"]), apct(r[f"{law} unloading_error"]), pct(r[f"{law} e_error"]))]
            for r in unloading]
    return lines + table(["nu", "E/sigma_Y", "P_max/P_Y", "inside", "FE dent/alpha_max", "vz-unload dent",
                          "vz-unload unloading", "vz-unload e", "vz-table dent", "vz-table unloading", "vz-table e"], rows)


def pair_table(root: Path) -> list[str]:
    """The pair table's section (results/pairs/pair_table.json, calib.fit.pair_table_build)."""
    data = read_json(root / "pairs" / "pair_table.json")
    if data is None:
        return []
    axes, runs = data["axes"], data["runs"]
    lines = study_header("The pair table (`pairs/pair_table.json`, `calib/data/pair_table.csv`)", data["stamp"],
                         "python -m calib.fit.pair_table_build") + [
        "A yielding sphere on an elastic flat over the same sphere on the rigid flat (two-body FE, finite-strain "
        f"sphere, {data['stamp']['mesh']['elements_per_contact_radius']:g} elements per contact radius), each to "
        f"its reach: Phi_D and the dissipation ratio Psi at nu {', '.join(f'{v:g}' for v in axes['nu'])}, E/sigma_Y "
        f"{', '.join(f'{v:g}' for v in axes['E_over_sigma_y'])}, E1'/E2' "
        f"{', '.join(f'{v:.3g}' for v in axes['x'])}; {len(runs)} FE runs, "
        f"{sum(r['wall_time_s'] or 0.0 for r in runs) / 60:.0f} min of worker time. `nfdcal material --counter-E "
        "... --v-max` maps the vz master table's law by them. Against the two-body FE of held-out pairs (not "
        "nodes), up to the law's window top (the lowest of the pair table's, the vz master table's, the "
        "two-body FE's reach and the load to which these checks meet 2 % in e and 5 % in force) and the paths "
        "beyond it (marked beyond), e / e_FE - 1 and max force error / P_max, beside the rigid-flat law on the "
        "pair's scales (the substitution):", ""]
    rows = [[f"{c['nu']:g}", f"{c['E_over_sigma_y']:g}", f"{c['x']:.3g}", c["counter"], f"{c['P_max_over_P_Y']:.4g}",
             f"{c['window_top']:.4g} ({c['top_by']})" + ("" if c.get("inside_window", True) else ", beyond"),
             pct(c["pair_table_e_error"]), apct(c["pair_table_force_error"]),
             pct(c["substitution_e_error"]), apct(c["substitution_force_error"])] for c in data["checks"]]
    lines += table(["nu", "E/sigma_Y", "E1'/E2'", "counter-body", "P_max/P_Y", "window top P/P_Y", "e", "force",
                    "substitution: e", "force"], rows)
    return lines + [f"Accuracy statement: {data['accuracy']}.", ""]


def hardening_sheet(root: Path) -> list[str]:
    """The hardening sheet's section (calib/data/vz_hardening_table.json and its scene's
    results/tables/<scene>/vz_hardening_check.json; calib.fit.vz_hardening_build)."""
    shipped = read_json(Path(__file__).resolve().parents[1] / "data" / "vz_hardening_table.json")
    if shipped is None:
        return []
    sheet = shipped["vz_hardening_table"]
    folder = root / "tables" / sheet["scene"]
    check = read_json(folder / "vz_hardening_check.json")
    if check is None:
        return []
    join = sheet.get("join")
    lines = section(f"The vz master table's hardening sheet (`tables/{sheet['scene']}/`)", folder, root,
                    (f"nfdcal table {join['small_strain_scene']}; " if join else "")
                    + f"nfdcal table {sheet['scene']} --master-out calib/data/vz_hardening_table.csv",
                    shipped["stamp"])
    kinematics = (f"small strain (scene {join['small_strain_scene']}, the grid's mesh) below a = "
                  f"{join['join_a_over_R']:g} R, finite strain (vz_master_reach's mesh) from it to 1e4 P_Y or 0.45 R"
                  if join else "the grid's mesh and window, small strain")
    lines += [f"Spheres of linear isotropic hardening sigma_y = sigma_Y + H eps_p at nu "
              f"{', '.join(f'{v:g}' for v in sheet['nu'])}, E/sigma_Y {', '.join(f'{v:g}' for v in sheet['E_over_sigma_y'])}"
              f" and H/E {', '.join(f'{v:g}' for v in sheet['H_over_E'])} ({kinematics}): "
              "`nfdcal material --hardening-modulus H --v-max V` adds the hardening's share of the tables measured "
              "there" + (" (PCHIP in nu between)" if len(sheet["nu"]) > 1 else "") + " to the vz master table's "
              "(calib.fit.vz_hardening). Against direct FE of hardening spheres off "
              "the sheet's nodes (a small-strain check's paths below the join), each path's e / e_FE - 1 and largest "
              "force error / P_max of the hardened law and of the perfectly plastic master law at the same material, "
              "and the vz-unload law's:", ""]
    plain = {(r["name"], round(r["P_max_over_P_Y"], 9)): r for r in check["perfectly plastic"]}
    unloading = {(r["name"], round(r["P_max_over_P_Y"], 9)): r for r in check["unloading"]}
    rows = []
    for r in check["vz-table"]:
        key = (r["name"], round(r["P_max_over_P_Y"], 9))
        p, u = plain.get(key), unloading.get(key, {})
        hardening = f"{r['H_over_E']:g}" if "H_over_E" in r else r["flow_curve"]
        rows.append([f"{r['nu']:g}", f"{r['E_over_sigma_y']:g}", hardening, f"{r['P_max_over_P_Y']:.4g}",
                     "yes" if r["inside"] else "no", pct(r["e_error"]), apct(r["force_error"]),
                     pct(u["vz-unload e_error"]) if "vz-unload e_error" in u else "-",
                     apct(u["vz-unload dent_error_of_alpha_max"]) if "vz-unload dent_error_of_alpha_max" in u else "-",
                     pct(p["e_error"]) if p else "-", apct(p["force_error"]) if p else "-"])
    lines += table(["nu", "E/sigma_Y", "H/E or flow curve (K/sigma_Y, n)", "P_max/P_Y", "inside", "e", "force",
                    "vz-unload e", "vz-unload dent/alpha_max", "perfectly plastic: e", "force"], rows)
    flow = check["accuracy"].get("flow_curves")
    return lines + [f"Accuracy statement: {check['accuracy']['statement']}.", ""] + (
        [f"Power-law flow curves (`nfdcal material --flow-curve CSV`: the curve read at each load as the linear "
         f"hardening of its secant modulus to Tabor's representative strain, calib.fit.vz_hardening.effective_hardening):"
         f" {flow['statement']}.", ""] if flow else [])

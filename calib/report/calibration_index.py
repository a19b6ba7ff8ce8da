"""The reference calibration's section of results/README.md (calib.report.results_index): its constants
against the paper's and each law along the FE's paths, read from results/calibration/calibration.json and
parameters.json (written by ``nfdcal calibrate``, calib.report.calibration).
"""
from __future__ import annotations

from pathlib import Path

from calib.report.index_format import apct, g, num, pct, read_json, section, table
from nfdmodel import reference_case


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

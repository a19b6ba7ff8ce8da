"""The between-nodes study's section of results/README.md (calib.report.results_index): read from
results/calibration/between_nodes.json (calib.studies.between_nodes).
"""
from __future__ import annotations

from pathlib import Path

from calib.report.index_format import apct, read_json, study_header, table


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

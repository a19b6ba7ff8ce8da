"""The wide-window study's section of results/README.md (calib.report.results_index): read from
results/calibration/wide_window.json (calib.studies.wide_window).
"""
from __future__ import annotations

from pathlib import Path

from calib.report.index_format import apct, pct, read_json, span, study_header, table


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

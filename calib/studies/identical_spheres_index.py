"""The identical-spheres study's section of results/README.md (calib.report.results_index): read from
results/calibration/identical_spheres.json (calib.studies.identical_spheres).
"""
from __future__ import annotations

from pathlib import Path

from calib.report.index_format import g, num, read_json, study_header, table


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

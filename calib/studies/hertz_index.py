"""The Hertz validation's section of results/README.md (calib.report.results_index): read from
results/hertz/hertz.json and mesh_ladder.csv (``nfdcal hertz``, calib.studies.hertz).
"""
from __future__ import annotations

from pathlib import Path

from calib.report.index_format import g, num, pct, provenance, read_csv, read_json, section, table


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

"""The reference calibration's mesh ladder in results/README.md (calib.report.results_index): read from
results/calibration/mesh_ladder*.csv (``nfdcal calibrate --ladder``, calib.studies.mesh_ladder).
"""
from __future__ import annotations

import math
from pathlib import Path

from calib.report.index_format import apct, g, num, pct, provenance, read_csv, table


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
    lines = ["## Mesh ladder of the reference calibration (`calibration/mesh_ladder*.csv`)", "",
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

"""Files of the unlike-pair study (calib.studies.pairs): results/pairs/pairs.{csv,json,png}, the measured map
calib/data/substitution_error.csv, the mesh check and the printed summary.

Errors are relative, signed: substitution / two-body FE - 1 (force at equal approach, contact radius at equal
force, restitution e at equal P_max / P_Y; calib.studies.pairs).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from calib import output
from calib.report.index_format import apct, read_json, section, span, table


KEYS = ("force_error", "radius_error", "e_error")
CSV_COLUMNS = ("shape", "yielding", "E1_over_E2", "E_star", "R_star", "P_Y",
               "force_error_min", "force_error_max", "force_error_top", "radius_error_min", "radius_error_max",
               "radius_error_top", "e_error_min", "e_error_max", "e_error_13.7", "e_error_27.4", "e_error_41.2",
               "law_e_error_min", "law_e_error_max", "law_e_error_rigid_max", "law_force_error_max",
               "law_force_error_rigid_max", "dofs", "contact_size", "wall_time_s")
DATA_COLUMNS = ("shape", "yielding", "E1_over_E2", "force_error_min", "force_error_max", "radius_error_min",
                "radius_error_max", "e_error_min", "e_error_max")
MARKERS = {"sphere": "o-", "counter": "s--", "both": "^:"}
COLOURS = {"flat": "C0", "sphere": "C3"}


def mesh_check(coarse: dict | None, fine: dict) -> dict:
    """The check case at the default mesh against the grid's mesh: each error at both and the change."""
    record = {"case": {k: fine[k] for k in ("E1_over_E2", "yielding", "shape")}, "default": {}, "grid": {},
              "change": {}, "contact_size": {"default": fine["contact_size"]}}
    for key in ("force_error_min", "force_error_max", "radius_error_min", "radius_error_max", "e_error_min",
                "e_error_max", "law_e_error_min", "law_e_error_max"):
        record["default"][key] = fine[key]
        if coarse is not None:
            record["grid"][key] = coarse[key]
            record["change"][key] = fine[key] - coarse[key]
    if coarse is not None:
        record["contact_size"]["grid"] = coarse["contact_size"]
        record["largest_change"] = max(abs(v) for k, v in record["change"].items() if not k.startswith("law"))
    return record


def csv_rows(rows: list[dict]) -> list[dict]:
    out = []
    for row in rows:
        flat = {k: row[k] for k in CSV_COLUMNS if k in row}
        for path in row["paths"]:
            flat[f"e_error_{path['P_max_over_P_Y']:g}"] = path["e_error"]
        out.append(flat)
    return out


def write(out: Path, result: dict, data_file: Path | None) -> None:
    st = result["stamp"]
    output.write_csv(out / "pairs.csv", csv_rows(result["rows"]), CSV_COLUMNS, comment=output.stamp_comment(st))
    output.write_json(out / "pairs.json", result)
    if result["rows"]:
        plot(result["rows"], out / "pairs.png")
    if data_file is not None and result["rows"]:
        comment = ("the rigid-flat substitution against the two-body FE (python -m calib.studies.pairs):\n"
                   "relative errors substitution / FE - 1 of the force at equal approach, the contact radius at\n"
                   "equal force and e at equal P_max/P_Y, over loads 1..41.2 P_Y; E1/E2 of sphere/counter-body,\n"
                   "nu = 0.3, the counter a flat or a sphere R2 = R1; yielding: which body has a yield stress\n"
                   "(both: equal sigma_Y)\n"
                   + output.stamp_comment({k: st[k] for k in ("git_commit", "mesh", "created_utc")}))
        output.write_csv(data_file, result["rows"], DATA_COLUMNS, comment=comment)


def plot(rows: list[dict], path: Path) -> None:
    """Force, contact radius and e errors against E1/E2: the value at the largest load (line) and the range
    over the loads (bar)."""
    plt = output.pyplot()
    fig, axes = plt.subplots(1, 3, figsize=(16, 4.6))
    titles = {"force_error": "force at equal approach (loading, P >= P_Y)",
              "radius_error": "contact radius at equal force (loading, P >= P_Y)",
              "e_error": "e at equal P_max/P_Y (paths to 13.7, 27.4, 41.2 P_Y)"}
    for shape in sorted({r["shape"] for r in rows}):
        for yielding in MARKERS:
            sel = sorted((r for r in rows if r["shape"] == shape and r["yielding"] == yielding),
                         key=lambda r: r["E1_over_E2"])
            if not sel:
                continue
            x = np.array([r["E1_over_E2"] for r in sel])
            for ax, key in zip(axes, KEYS):
                low = 100 * np.array([r[f"{key}_min"] for r in sel])
                high = 100 * np.array([r[f"{key}_max"] for r in sel])
                top = (100 * np.array([r[f"{key}_top"] for r in sel]) if f"{key}_top" in sel[0]
                       else 100 * np.array([r["paths"][-1][key] for r in sel]))
                ax.plot(x, top, MARKERS[yielding], color=COLOURS[shape], ms=4,
                        label=f"{shape} counter-body, {yielding} yield{'s' if yielding != 'both' else ''}")
                ax.vlines(x * (1.02 if shape == "sphere" else 1.0), low, high, color=COLOURS[shape], lw=3, alpha=0.35)
    for ax, key in zip(axes, KEYS):
        ax.set_xscale("log")
        ax.set_xticks([1 / 3, 0.5, 1, 2, 3], ["1/3", "1/2", "1", "2", "3"])
        ax.minorticks_off()
        ax.axhline(0.0, color="k", lw=0.6)
        ax.set_xlabel("E1 / E2 (sphere / counter-body)")
        ax.set_ylabel("substitution / two-body FE - 1 [%]")
        ax.set_title(titles[key], fontsize=9)
        ax.grid(alpha=0.3)
    for sign in (1, -1):
        axes[2].axhline(sign * 2.0, color="k", lw=0.8, ls=":")
    axes[0].legend(fontsize=7)
    fig.suptitle("The rigid-flat substitution (E*, R*, the yielding body's constants) against the two-body FE: "
                 "line at the largest load, bar the range", fontsize=10)
    output.save_figure(fig, path)


def _span(rows, key) -> str:
    low, high = min(r[f"{key}_min"] for r in rows), max(r[f"{key}_max"] for r in rows)
    return f"{100 * low:+.2f}..{100 * high:+.2f} %"


def column_spans(rows: list[dict]) -> list[dict]:
    """Per (shape, yielding) column: the ranges of each error over E1/E2 and the loads."""
    columns = []
    for shape in sorted({r["shape"] for r in rows}):
        for yielding in MARKERS:
            sel = [r for r in rows if r["shape"] == shape and r["yielding"] == yielding]
            if sel:
                columns.append({"shape": shape, "yielding": yielding, "rows": sel,
                                **{key: _span(sel, key) for key in KEYS + ("law_e_error",)},
                                "ratios": sorted(r["E1_over_E2"] for r in sel)})
    return columns


def summary_lines(result: dict) -> list[str]:
    rows = result["rows"]
    lines = [f"{'shape':>6} {'yields':>7} {'E1/E2':>6} {'force err %':>15} {'radius err %':>15} {'e err %':>15} "
             f"{'vz law e err %':>15}"]
    for r in sorted(rows, key=lambda r: (r["shape"], r["yielding"], r["E1_over_E2"])):
        lines.append(f"{r['shape']:>6} {r['yielding']:>7} {r['E1_over_E2']:6.3g} "
                     + " ".join(f"{100 * r[f'{k}_min']:+7.2f}..{100 * r[f'{k}_max']:+6.2f}"
                                for k in KEYS + ("law_e_error",)))
    for failure in result["failures"]:
        lines.append(f"failed: {failure}")
    if result["mesh_check"] is not None and "largest_change" in result["mesh_check"]:
        lines.append(f"mesh check: largest change of an error from the grid's mesh to the default: "
                     f"{100 * result['mesh_check']['largest_change']:.2f} points")
    lines.append(f"wall time {result['stamp']['wall_time_s']:.0f} s")
    return lines


def pairs(root: Path) -> list[str]:
    data = read_json(root / "pairs" / "pairs.json")
    if data is None:
        return []
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

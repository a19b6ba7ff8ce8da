"""The files of ``nfdcal impact``: impact.csv, impact.json (stamped), drop_tests.csv, impact.png, histories.png.

impact.csv   one row per velocity: v_in, v_in / v_Y, the FE's e, P_max [N], contact_time [s],
             alpha_max [m] (approach of the centre of mass), dent [m], the energy fractions of the
             kinetic energy in (plastic work, residual-stress energy, vibration energy, balance
             residual), each compared quantity's estimated relative discretisation error, and the
             quasi-static laws' e, P_max, contact time (vz, vz-table, Thornton and its closed form,
             Hertz), LAMMPS' mdr restitution where known, the quasi-static FE path at the same P_max
             (quasi_static_*: e, the v_in that reaches P_max, P_max at the dynamic v_in, contact time,
             alpha_max, dent) and the dynamic FE's relative difference to it (dynamic_over_quasi_static_*)
impact.json  the same records with the case, the vz constants' source and the provenance stamp
             (calib.output.stamp)
drop_tests.csv  v_in, e, P_max, contact_time: the impacts as ``nfdcal fit-data --impacts`` reads
             drop tests (calib.studies.impact_drops)
impact.png   e, P_max / P_Y and contact time against v_in / v_Y: the FE (error bars: the estimate)
             against the laws and the quasi-static FE paths (e, contact time: at the same P_max;
             P_max: the path's loading branch at the same v_in)
histories.png  the FE's contact force and approach against time, one curve per velocity
Definitions: calib.fe.impact; the study: calib.studies.impact.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from calib import output
from calib.report.index_format import g, num, read_json, section, table

from calib.studies import impact_drops

LAW_COLUMNS = (("vz", "e"), ("vz", "P_max"), ("vz", "contact_time"), ("vz", "delta_max"), ("vz", "delta_res"),
               ("vz_table", "e"), ("vz_table", "P_max"), ("vz_table", "contact_time"),
               ("thornton", "e"), ("thornton", "e_closed_form"), ("thornton", "P_max"), ("thornton", "contact_time"),
               ("hertz", "P_max"), ("hertz", "contact_time"), ("mdr", "e"))
COLUMNS = ("v_in", "v_in_over_v_Y", "P_max_over_P_Y", "e", "P_max", "contact_time", "alpha_max", "dent",
           "contact_radius_max", "plastic_fraction", "residual_stress_fraction", "vibration_fraction",
           "balance_residual_fraction", "e_rel_error_estimate", "P_max_rel_error_estimate",
           "contact_time_rel_error_estimate", "alpha_max_rel_error_estimate", "dent_rel_error_estimate",
           "dt", "steps", "dofs", "contact_size", "wall_time_s", "cpu_time_s")
QUASI_STATIC_COLUMNS = ("e", "v_in_quasi_static", "P_max_at_v_in", "contact_time", "alpha_max", "dent", "wall_time_s")
CHANGE_COLUMNS = ("e", "contact_time", "alpha_max", "dent", "v_in", "P_max")


def flat(record: dict) -> dict:
    """A record with the laws' predictions as columns (``vz_e``, ``thornton_P_max``, ...)."""
    models = record["models"]
    static, change = record.get("quasi_static", {}), record.get("dynamic_over_quasi_static", {})
    return {**{k: record[k] for k in COLUMNS},
            **{f"{law}_{key}": models[law].get(key, "") for law, key in LAW_COLUMNS if law in models},
            **{f"quasi_static_{key}": static[key] for key in QUASI_STATIC_COLUMNS if key in static},
            **{f"dynamic_over_quasi_static_{key}": change[key] for key in CHANGE_COLUMNS if key in change}}


def quasi_static_words(limit: dict) -> str:
    """``quasi_static_limit`` in one sentence."""
    parts = []
    for key, name in (("e", "e"), ("contact_time", "the contact time"), ("P_max", "P_max at the same v_in")):
        fails = limit[f"{key}_fails_from_v_in_over_v_Y"]
        verdict = ("no error estimate" if not limit["error_estimated"] else
                   "within the errors at every v_in" if fails is None else f"beyond the errors from {fails:.3g} v_Y")
        parts.append(f"{name} {limit[f'largest_{key}_change']:+.2%} at most (at "
                     f"{limit[f'largest_{key}_change_at_v_in_over_v_Y']:.3g} v_Y; {verdict})")
    return "; ".join(parts) + f"; vibration energy left at most {limit['vibration']['largest_fraction']:.2g} of the kinetic energy in"


def write(out: Path, records: list[dict], rows: list[dict], summary: dict, plots: bool) -> list[Path]:
    """Write the files into ``out`` (a staging folder: the caller swaps the set in); their paths."""
    out = Path(out)
    table = [flat(r) for r in records]
    extra = ([f"{law}_{key}" for law, key in LAW_COLUMNS] + [f"quasi_static_{key}" for key in QUASI_STATIC_COLUMNS]
             + [f"dynamic_over_quasi_static_{key}" for key in CHANGE_COLUMNS])
    columns = list(COLUMNS) + [name for name in extra if any(name in row for row in table)]
    written = [output.write_csv(out / "impact.csv", table, columns, comment=output.stamp_comment(summary["stamp"])),
               output.write_json(out / "impact.json", {**summary, "impacts": records}),
               impact_drops.write_fit_data_file(out / "drop_tests.csv", records, summary["stamp"])]
    if plots:
        written += [plot_comparison(out / "impact.png", records, summary), plot_histories(out / "histories.png", rows)]
    return [Path(p) for p in written]


def plot_comparison(path: Path, records: list[dict], summary: dict) -> Path:
    plt = output.pyplot()
    x = np.array([r["v_in_over_v_Y"] for r in records])
    P_Y = summary["case"]["P_Y"]
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.4))
    panels = (("e", "restitution e", 1.0), ("P_max", "P_max / P_Y", 1.0 / P_Y), ("contact_time", "contact time [ms]", 1e3))
    styles = {"vz": ("C0", "-", f"vz law ({summary['vz_source']})"),
              "vz_table": ("C1", "-", f"vz-table law ({summary.get('vz_table_source')})"),
              "thornton": ("C2", "--", "Thornton"),
              "hertz": ("0.5", ":", "Hertz"), "mdr": ("C4", "-.", "LAMMPS granular mdr")}
    for ax, (key, label, scale) in zip(axes, panels):
        error = np.array([abs(r[f"{key}_rel_error_estimate"] or 0.0) * r[key] for r in records]) * scale
        ax.errorbar(x, np.array([r[key] for r in records]) * scale, yerr=error, fmt="o", color="C3", capsize=3,
                    label="dynamic FE (whole sphere)")
        for law, (colour, line, name) in styles.items():
            known = [(xi, r["models"][law][key] * scale) for xi, r in zip(x, records) if key in r["models"].get(law, {})]
            if known:
                ax.plot(*zip(*known), line, color=colour, marker=".", label=name)
        column = "P_max_at_v_in" if key == "P_max" else key      # P_max: the path's at the same v_in
        static = [(xi, r["quasi_static"][column] * scale) for xi, r in zip(x, records) if "quasi_static" in r]
        if static:
            ax.plot(*zip(*static), "s", mfc="none", color="k", label="quasi-static FE path (same P_max; P_max: same v_in)")
        if key == "e" and all("thornton" in r["models"] for r in records):
            ax.plot(x, [r["models"]["thornton"]["e_closed_form"] for r in records], "x", color="C2",
                    label="Thornton closed form")
        ax.set_xscale("log")
        if key == "P_max":
            ax.set_yscale("log")
        ax.set_xlabel("v_in / v_Y")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    # in the P_max panel's empty lower right, off the restitution points
    axes[1].legend(*axes[0].get_legend_handles_labels(), fontsize=7, loc="lower right")
    fig.suptitle("Impact of the whole sphere on a rigid flat: dynamic FE against the quasi-static laws")
    return output.save_figure(fig, path)


def plot_histories(path: Path, rows: list[dict]) -> Path:
    plt = output.pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.4))
    fine = sorted((r for r in rows if r["variant"] == "fine"), key=lambda r: r["v_in"])
    for k, row in enumerate(fine):
        history = row["history"]
        t = np.asarray(history["time"]) / row["contact_time"]
        label = f"v_in = {row['v_in']:.3g} m/s"
        axes[0].plot(t, np.asarray(history["P"]) / row["P_max"], color=f"C{k}", label=label)
        axes[1].plot(t, np.asarray(history["alpha"]) / row["alpha_max"], color=f"C{k}", label=label)
    for ax, label in zip(axes, ("P / P_max", "approach of the centre of mass / its largest")):
        ax.set_xlabel("t / contact time")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    return output.save_figure(fig, path)


def impact(root: Path) -> list[str]:
    folder = root / "impact"
    data = read_json(folder / "impact.json")
    if data is None:
        return []
    case = data["case"]
    lines = section("Dynamic FE impacts of the whole sphere (`impact/`)", folder, root,
                    "nfdcal impact --params results/calibration/parameters.json --table-params "
                    "results/impact/vz_table/parameters.json --lammps-restitution results/lammps/restitution.csv && "
                    "nfdcal impact --convergence --v-in 0.04 (vz_table/: nfdcal calibrate --v-max 0.504 "
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
        lines += ["Dynamic over quasi-static FE at the same P_max: " + quasi_static_words(limit) + ".", ""]
    convergence = read_json(folder / "convergence.json")
    if convergence:
        runs = [[r["ladder"], f"{r['contact_size'] * 1e6:g}", r["steps_per_contact"], r["dofs"], f"{r['e']:.5f}",
                 g(r.get("e_error"), 2), num(r["wall_time_s"])] for r in convergence["runs"]]
        lines += [f"Convergence at v_in = {convergence['v_in']:g} m/s ({convergence['v_in_over_v_Y']:.3g} v_Y; "
                  f"`convergence.json`, e_error against the extrapolated value):", ""]
        lines += table(["ladder", "h [um]", "steps per contact", "dofs", "e", "e error", "wall [s]"], runs)
    return lines

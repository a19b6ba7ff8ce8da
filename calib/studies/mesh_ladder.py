"""The calibration on a ladder of meshes: how Ca, Kc, e and alpha converge, against wall time.

The reference sphere and its load paths (R = 0.1 m; 500, 1000, 1500 N) on contact element sizes
1.6e-4 ... 1e-5 m of the reference mesh family; another material (e.g. nu = 0.45 or 0.49, to
look for volumetric locking of the 6-node triangles under nearly incompressible plastic flow)
runs on the same meshes and paths. Per quantity: the observed order of convergence from every
three consecutive rungs, the converged value (the three finest rungs extrapolated with their
observed order), each rung's error against it, and each two consecutive rungs as the two-mesh
calibration ships them (calib.fit.extrapolation): its estimated and its true error against wall
time (results/calibration/mesh_ladder.csv, mesh_ladder_pairs.csv, mesh_ladder.png).
"""
from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from calib import output
from calib.fit import extrapolation
from calib.fit.calibration import calibrate, summary
from calib.fit.recipe import reference_spec
from calib.sweep.runner import run_sweep
from meshes.keys import stable_key

LADDER_SIZES = (1.6e-4, 8e-5, 4e-5, 2e-5, 1e-5)  # contact element sizes [m]
LADDER_VERSION = 3   # part of each rung's key: the wall times are results (2: element-array assembly; 3: e from
                     # the works with Hertz's end segments, calib.fe.loadpath.contact_work)


def ladder_rung(task: dict) -> dict:
    """One rung: the calibration of ``task["spec"]`` and its figures at 1500 N (one row)."""
    spec, size = task["spec"], task["contact_size"]
    result = calibrate(spec, meshes=1)   # one mesh: the rung is the point
    s = summary(result)
    top = s["paths"][-1]
    peak_row = max(result.load_paths.loading_rows, key=lambda r: r["P"])
    row = {"contact_size": size, "nu": spec.material.nu, "E_over_sigma_y":
           spec.material.E / spec.material.sigma_y,
           "elements": s["mesh"]["elements"], "dofs": s["mesh"]["dofs"],
           "contact_radius_1500": peak_row["contact_radius"],
           "Ca": s["Ca"], "Kc": s["Kc"], "Ca_r2": s["radius_fit"]["Ca_r2"],
           "Kc_r2": s["radius_fit"]["Kc_r2"], "P_Y_fe": s["P_Y_fe"],
           "alpha_max_1500": top["alpha_max"], "e_1500": top["e"],
           "alpha_residual_1500": top["alpha_residual"], "wall_time_s": s["wall_time_s"],
           "factorizations": s["timings"]["factorizations"],
           "git_commit": output.git_commit()}
    row["key"] = task["key"]
    return row


def ladder_tasks(sizes=LADDER_SIZES, material=None) -> list[dict]:
    """One task per rung: {key, spec, contact_size}; the key covers everything that changes a
    rung (mesh, material, load plan, tolerance), so a finished rung is found again in OUT/ladder."""
    tasks = []
    for size in sizes:
        spec = reference_spec(contact_size=size)
        if material is not None:
            spec = dataclasses.replace(spec, material=material)
        recipe = {"material": dataclasses.asdict(spec.material), "plan": dataclasses.asdict(spec.plan),
                  "tolerance": spec.residual_tolerance, "radius_method": spec.contact_radius_method,
                  "version": LADDER_VERSION}
        tasks.append({"key": spec.mesh.cache_key() + "-" + stable_key(recipe, 12),
                      "spec": spec, "contact_size": size})
    return tasks


def mesh_ladder(sizes=LADDER_SIZES, out: str | Path = output.RESULTS / "calibration", progress=None,
                material=None, name: str = "mesh_ladder") -> Path:
    """Ca, Kc, e, alpha and contact radius of the reference load paths (500/1000/1500 N on the
    R = 0.1 m sphere; ``material`` defaults to the reference aluminium) on a ladder of meshes,
    with wall times.

    Each rung is written to ``out/ladder/<key>.json`` (key: mesh, material, plan) as soon as it
    finishes and reused on the next call (an interrupted ladder resumes; delete the folder to
    recompute). Writes ``<name>.csv`` and ``<name>.png`` (values and wall time against size).
    """
    out = Path(out)
    tasks = ladder_tasks(sizes, material)
    # one rung at a time: the wall times are part of the result
    rows = run_sweep(tasks, ladder_rung, out / "ladder", mesh_of=lambda task: task["spec"].mesh,
                     progress=progress, describe=lambda row: f"contact size {row['contact_size']:g} m").rows
    analysis = converged_values(rows)
    pairs = extrapolated_pairs(rows, analysis)
    for row in rows:  # error against the converged value (the three finest rungs' extrapolation)
        for key in CONVERGED_KEYS:
            row[f"{key}_rel_error_vs_converged"] = row[key] / analysis[key]["converged"] - 1.0
    stamp = output.stamp(sum(r["wall_time_s"] for r in rows), mesh={"sizes": list(sizes)},
                         converged={key: value for key, value in analysis.items()})
    columns = list(dict.fromkeys(k for row in rows for k in row))
    output.write_csv(out / f"{name}.csv", rows, columns=columns, comment=output.stamp_comment(stamp))
    output.write_csv(out / f"{name}_pairs.csv", pairs, columns=list(pairs[0]), comment=output.stamp_comment(stamp))
    plot_ladder(rows, pairs, analysis, out / f"{name}.png")
    return out / f"{name}.csv"


CONVERGED_KEYS = ("Ca", "Kc", "e_1500", "alpha_max_1500")


def observed_order(coarse: float, middle: float, fine: float, ratio: float = 2.0) -> float | None:
    """p = log(|Q_4h - Q_2h| / |Q_2h - Q_h|) / log(r) from three meshes h, 2h, 4h (None when the
    changes are not of one sign: no asymptotic convergence to read an order from)."""
    d_coarse, d_fine = middle - coarse, fine - middle
    if d_coarse * d_fine <= 0:
        return None
    return float(np.log(abs(d_coarse) / abs(d_fine)) / np.log(ratio))


def converged_values(rows: list[dict]) -> dict:
    """Per quantity: the observed orders of every three consecutive rungs and the converged
    value, Richardson-extrapolated from the three finest rungs with their observed order (the
    finest rung itself when they do not converge monotonically, e.g. e and alpha at mesh noise)."""
    out = {}
    for key in CONVERGED_KEYS:
        values = [r[key] for r in rows]
        orders = [observed_order(*values[k:k + 3]) for k in range(len(values) - 2)]
        p = orders[-1] if orders else None
        finest = values[-1]
        converged = finest + (finest - values[-2]) / (2.0 ** p - 1.0) if p is not None and p > 0 else finest
        out[key] = {"converged": float(converged), "observed_orders": orders,
                    "extrapolated": bool(p is not None and p > 0)}
    return out


def extrapolated_pairs(rows: list[dict], analysis: dict) -> list[dict]:
    """Each two consecutive rungs (h, 2h) as a two-mesh calibration would ship them
    (calib.fit.extrapolation): Ca, Kc extrapolated, e the finer mesh's, with the estimated error,
    the error against the converged value, and the wall time on two cores (the slower mesh) and on one."""
    pairs = []
    for coarse, fine in zip(rows[:-1], rows[1:]):
        pair = {"contact_size": fine["contact_size"], "second_contact_size": coarse["contact_size"],
                "wall_time_parallel_s": max(fine["wall_time_s"], coarse["wall_time_s"]),
                "wall_time_serial_s": fine["wall_time_s"] + coarse["wall_time_s"]}
        for key in CONVERGED_KEYS:
            estimate = (extrapolation.richardson if key in ("Ca", "Kc") else extrapolation.unextrapolated)(
                fine[key], coarse[key])
            pair.update({key: estimate.value, f"{key}_extrapolated": estimate.extrapolated,
                         f"{key}_rel_error_estimate": estimate.rel_error_estimate,
                         f"{key}_rel_error_vs_converged": estimate.value / analysis[key]["converged"] - 1.0})
        pairs.append(pair)
    return pairs


def plot_ladder(rows: list[dict], pairs: list[dict], analysis: dict, path: Path) -> None:
    """Left: |error vs converged| against h. Right: error against wall time, single meshes and
    extrapolated pairs (two cores), so a user can pick accuracy for time."""
    plt = output.pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(11.5, 4.4))
    h = [r["contact_size"] for r in rows]
    floor = 1e-6                        # a log axis has no zero: errors below this are drawn here
    styles = {"Ca": ("C0", "o"), "Kc": ("C1", "s"), "e_1500": ("C2", "^"), "alpha_max_1500": ("C3", "v")}
    labels = {"Ca": "Ca", "Kc": "Kc", "e_1500": "e (1500 N)", "alpha_max_1500": "alpha (1500 N)"}
    def shown(key, items):          # a quantity whose "converged" value is the finest rung has no error there
        return items if analysis[key]["extrapolated"] else items[:-1]

    for key in CONVERGED_KEYS:
        color, marker = styles[key]
        axes[0].plot(shown(key, h), [max(abs(r[f"{key}_rel_error_vs_converged"]), floor) for r in shown(key, rows)],
                     marker + "-", color=color, label=labels[key] + ("" if analysis[key]["extrapolated"] else
                                                                     " (vs the finest mesh)"))
    axes[0].set_xscale("log"); axes[0].set_yscale("log")
    axes[0].set_xlabel("contact element size h [m]"); axes[0].set_ylabel("|relative error vs converged|")
    axes[0].legend(fontsize=8); axes[0].grid(alpha=0.3, which="both")
    for key in ("Ca", "Kc", "e_1500"):
        color, marker = styles[key]
        axes[1].plot([r["wall_time_s"] for r in shown(key, rows)],
                     [max(abs(r[f"{key}_rel_error_vs_converged"]), floor) for r in shown(key, rows)],
                     marker + "-", color=color, label=f"{labels[key]}, one mesh")
        if key in extrapolation.EXTRAPOLATED:      # e ships the finer mesh's value: same points
            axes[1].plot([p["wall_time_parallel_s"] for p in pairs],
                         [max(abs(p[f"{key}_rel_error_vs_converged"]), floor) for p in pairs], marker + "--",
                         color=color, mfc="none", label=f"{labels[key]}, two meshes (h, 2h) extrapolated")
    axes[1].set_xscale("log"); axes[1].set_yscale("log")
    axes[1].set_xlabel("wall time [s] (two meshes: on two cores)"); axes[1].set_ylabel("|relative error vs converged|")
    axes[1].legend(fontsize=7); axes[1].grid(alpha=0.3, which="both")
    orders = ", ".join(f"{labels[k]} " + "/".join("-" if p is None else f"{p:.2f}" for p in analysis[k]["observed_orders"])
                       for k in ("Ca", "Kc"))
    fig.suptitle(f"Mesh ladder, nu = {rows[-1].get('nu', 0.3):g}: converged = three finest rungs extrapolated; "
                 f"observed orders {orders}", fontsize=9)
    output.save_figure(fig, path)

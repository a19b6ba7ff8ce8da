"""The calibration on a ladder of meshes: how Ca, Kc, e and alpha converge, against wall time.

The reference sphere and its load paths (R = 0.1 m; 500, 1000, 1500 N) on contact element sizes
1.6e-4 ... 2e-5 m of the reference mesh family; another material (e.g. nu = 0.45 or 0.49, to
look for volumetric locking of the 6-node triangles under nearly incompressible plastic flow)
runs on the same meshes and paths. The change of each quantity against the finest rung
estimates the discretisation error (first order in h, results/calibration/mesh_ladder.csv).
"""
from __future__ import annotations

import dataclasses
from pathlib import Path

from calib import output
from calib.fit.calibration import calibrate, summary
from calib.fit.recipe import reference_spec
from calib.sweep.runner import run_sweep
from meshes.keys import stable_key

LADDER_SIZES = (1.6e-4, 8e-5, 4e-5, 2e-5)  # contact element sizes [m]


def ladder_rung(task: dict) -> dict:
    """One rung: the calibration of ``task["spec"]`` and its figures at 1500 N (one row)."""
    spec, size = task["spec"], task["contact_size"]
    result = calibrate(spec)
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
    tasks = []
    for size in sizes:
        spec = reference_spec(contact_size=size)
        if material is not None:
            spec = dataclasses.replace(spec, material=material)
        # the key covers everything that changes a rung: mesh, material, load plan, tolerance
        recipe = {"material": dataclasses.asdict(spec.material), "plan": dataclasses.asdict(spec.plan),
                  "tolerance": spec.residual_tolerance, "radius_method": spec.contact_radius_method}
        tasks.append({"key": spec.mesh.cache_key() + "-" + stable_key(recipe, 12),
                      "spec": spec, "contact_size": size})
    # one rung at a time: the wall times are part of the result
    rows = run_sweep(tasks, ladder_rung, out / "ladder", mesh_of=lambda task: task["spec"].mesh,
                     progress=progress, describe=lambda row: f"contact size {row['contact_size']:g} m").rows
    finest = rows[-1]
    for row in rows:  # change against the finest rung: the discretisation error estimate
        for key in ("Ca", "Kc", "e_1500", "alpha_max_1500", "contact_radius_1500"):
            if key in row and key in finest:
                row[f"{key}_rel_change_vs_finest"] = row[key] / finest[key] - 1.0
    stamp = output.stamp(sum(r["wall_time_s"] for r in rows), mesh={"sizes": list(sizes)})
    columns = list(dict.fromkeys(k for row in rows for k in row))
    output.write_csv(out / f"{name}.csv", rows, columns=columns, comment=output.stamp_comment(stamp))

    plt = output.pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    h = [r["contact_size"] for r in rows]
    for key, label in (("Ca", "Ca"), ("Kc", "Kc"), ("e_1500", "e (1500 N)"), ("alpha_max_1500", "alpha (1500 N)")):
        axes[0].plot(h, [abs(r[f"{key}_rel_change_vs_finest"]) + 1e-6 for r in rows[:-1]] + [float("nan")], "o-", label=label)
    axes[0].set_xscale("log"); axes[0].set_yscale("log")
    axes[0].set_xlabel("contact element size h [m]"); axes[0].set_ylabel("|relative change vs finest mesh|")
    axes[0].legend(); axes[0].grid(alpha=0.3, which="both")
    axes[1].plot([r["wall_time_s"] for r in rows[:-1]], [abs(r["Ca_rel_change_vs_finest"]) + 1e-6 for r in rows[:-1]], "o-", label="Ca")
    axes[1].plot([r["wall_time_s"] for r in rows[:-1]], [abs(r["Kc_rel_change_vs_finest"]) + 1e-6 for r in rows[:-1]], "s-", label="Kc")
    axes[1].plot([r["wall_time_s"] for r in rows[:-1]], [abs(r["e_1500_rel_change_vs_finest"]) + 1e-6 for r in rows[:-1]], "^-", label="e")
    axes[1].set_xscale("log"); axes[1].set_yscale("log")
    axes[1].set_xlabel("wall time of the calibration [s]"); axes[1].set_ylabel("|relative change vs finest mesh|")
    axes[1].legend(); axes[1].grid(alpha=0.3, which="both")
    fig.suptitle(f"Load paths on a mesh ladder, nu = {finest.get('nu', 0.3):g} (finest: h = {finest['contact_size']:g} m)")
    output.save_figure(fig, out / f"{name}.png")
    return out / f"{name}.csv"

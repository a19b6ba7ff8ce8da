"""The dynamic FE impact's discretisation error against its run time (``nfdcal impact --convergence``).

At one velocity, two ladders through the sweep runner (finished runs reused from OUT/cases/):

  time step  dt = t_c / N, N = N0 / 4, N0 / 2, N0, 2 N0 on the impact's mesh (calib.studies.impact);
  mesh       contact element h0, 2 h0, 4 h0 (the refined zone kept) at N0.

Errors: each ladder against the Richardson extrapolation of its two finest runs for first order
(calib/README.md, Mesh convergence), Q* = Q_f + (Q_f - Q_c), f the finer and c the coarser run;
the observed order of the three finest runs, log2((Q_1 - Q_2) / (Q_2 - Q_3)) (1 coarsest), is
reported beside it (the time step measures below 1 although Newmark's rule is second order on
smooth motion: the contact's onset and release at each node fall inside steps).
Writes convergence.csv (one row per run), convergence.json (stamped) and convergence.png (the
relative errors of e, P_max and contact time against the run's CPU time, which a shared machine's
load does not inflate as it does the wall time).
"""
from __future__ import annotations

import dataclasses
import math
import time
from pathlib import Path
from typing import Callable

from calib import output
from calib.studies import impact

DT_FACTORS = (0.25, 0.5, 1.0, 2.0)      # N / N0
MESH_FACTORS = (4.0, 2.0, 1.0)          # h / h0
QUANTITIES = ("e", "P_max", "contact_time", "alpha_max", "dent")
COLUMNS = ("ladder", "contact_size", "steps_per_contact", "dofs", "steps", "e", "P_max", "contact_time", "alpha_max",
           "dent", "vibration_energy", "balance_residual", "kinetic_in", "wall_time_s", "cpu_time_s",
           "e_error", "P_max_error", "contact_time_error", "alpha_max_error", "dent_error")


def tasks(setup: impact.ImpactSetup, v_in: float) -> list[dict]:
    """The runs of both ladders (one shared), keyed like calib.studies.impact's."""
    fine = impact.impact_mesh(setup, v_in)
    runs = {}
    for ladder, factor in [("dt", f) for f in DT_FACTORS] + [("mesh", f) for f in MESH_FACTORS]:
        h = fine.contact_size * (factor if ladder == "mesh" else 1.0)
        mesh = dataclasses.replace(fine, contact_size=h, refined_radius=max(fine.refined_radius, 2 * h),
                                   refined_depth=max(fine.refined_depth, 2 * h), far_size=max(fine.far_size, h))
        steps = int(round(setup.steps_per_contact * (factor if ladder == "dt" else 1.0)))
        task = impact.task_of(setup, v_in, f"h = {h:.3g} m, N = {steps}", mesh, steps)
        runs[task["key"]] = task
    return list(runs.values())


def run(setup: impact.ImpactSetup, v_in: float, out: Path, *, workers: int = 1,
        progress: Callable[[str], None] | None = None, plots: bool = True) -> dict:
    """Both ladders at v_in [m/s]; writes the files into ``out`` as one set; returns the summary."""
    started = time.perf_counter()
    impact.check_reach(setup, [v_in])
    todo = tasks(setup, v_in)
    for spec in {task["mesh"]["contact_size"]: task["mesh"] for task in todo}.values():
        impact.sphere_mesh(impact.SphereMeshSpec(**spec))
    swept = impact.run_sweep(todo, impact.run_task, Path(out) / "cases", keep=lambda row: row.get("status") == "ok",
                             workers=workers, progress=progress,
                             describe=lambda row: f"{row['v_in']:g} m/s: {row.get('wall_time_s', 0):.1f} s")
    rows = [{**row, "variant": task["variant"]} for task, row in zip(todo, swept.rows)]
    failed = [row for row in rows if row["status"] != "ok"]
    if failed:
        raise ValueError(f"the FE impact {failed[0]['variant']} failed: {failed[0]['error']}")
    by_variant = {task["variant"]: (task, row) for task, row in zip(todo, rows)}
    h0, N0 = todo[0]["mesh"]["contact_size"], setup.steps_per_contact
    dt_rows = sorted((row for task, row in by_variant.values() if task["mesh"]["contact_size"] == h0),
                     key=lambda row: row["dt"], reverse=True)
    mesh_rows = sorted((row for task, row in by_variant.values() if by_variant[row["variant"]][0]["steps_per_contact"] == N0),
                       key=lambda row: row["mesh"]["contact_size"], reverse=True)
    table, extrapolated, orders = [], {}, {}
    for ladder, rows, order in (("dt", dt_rows, 1), ("mesh", mesh_rows, 1)):
        extrapolated[ladder] = {q: rows[-1][q] + (rows[-1][q] - rows[-2][q]) / (2 ** order - 1) for q in QUANTITIES}
        orders[ladder] = {q: _order(*(row[q] for row in rows[-3:])) for q in QUANTITIES}
        for row in rows:
            table.append({"ladder": ladder, "contact_size": row["mesh"]["contact_size"],
                          "steps_per_contact": by_variant[row["variant"]][0]["steps_per_contact"],
                          **{k: row[k] for k in ("dofs", "steps", "e", "P_max", "contact_time", "alpha_max", "dent",
                                                 "vibration_energy", "balance_residual", "kinetic_in", "wall_time_s")},
                          "cpu_time_s": row.get("cpu_time_s"),
                          **{f"{q}_error": _relative(row[q], extrapolated[ladder][q]) for q in QUANTITIES}})
    summary = {"v_in": v_in, "v_in_over_v_Y": v_in / setup.pair.v_Y, "contact_size": h0, "steps_per_contact": N0,
               "extrapolated": extrapolated, "observed_order": orders, "runs": table,
               "stamp": output.stamp(time.perf_counter() - started, mesh=mesh_rows[-1]["mesh"],
                                     computed=swept.computed, reused=swept.reused)}
    with output.all_or_nothing(out, name="impact-convergence") as staging:
        output.write_csv(staging / "convergence.csv", table, COLUMNS, comment=output.stamp_comment(summary["stamp"]))
        output.write_json(staging / "convergence.json", summary)
        if plots:
            plot(staging / "convergence.png", table, summary)
    return summary


def _relative(value: float, reference: float) -> float | None:
    return None if reference == 0.0 else abs(value / reference - 1.0)


def _order(coarse: float, middle: float, fine: float) -> float | None:
    """Observed order of three runs halving the step or element: log2 of the ratio of changes."""
    first, second = middle - coarse, fine - middle
    return math.log2(first / second) if second != 0.0 and first / second > 0 else None


def lines(summary: dict) -> list[str]:
    """The readable answer: one line per run, errors against the extrapolated values."""
    out = [f"v_in = {summary['v_in']:g} m/s ({summary['v_in_over_v_Y']:.3g} v_Y); errors against the Richardson"
           f" extrapolation of each ladder",
           f"{'ladder':<6} {'h [m]':>9} {'N':>5} {'dofs':>7} {'e':>8} {'err e':>8} {'P_max':>9} {'err P':>8} "
           f"{'t_c [ms]':>9} {'err t_c':>8} {'wall s':>7} {'CPU s':>7}"]
    for r in summary["runs"]:
        out.append(f"{r['ladder']:<6} {r['contact_size']:>9.3g} {r['steps_per_contact']:>5} {r['dofs']:>7} "
                   f"{r['e']:>8.5f} {r['e_error']:>8.2e} {r['P_max']:>9.5g} {r['P_max_error']:>8.2e} "
                   f"{r['contact_time'] * 1e3:>9.5f} {r['contact_time_error']:>8.2e} {r['wall_time_s']:>7.1f} "
                   f"{r['cpu_time_s'] or 0.0:>7.1f}")
    orders = summary["observed_order"]
    out.append("observed order, dt: " + ", ".join(f"{q} {v:.2f}" for q, v in orders["dt"].items() if v is not None)
               + "; mesh: " + ", ".join(f"{q} {v:.2f}" for q, v in orders["mesh"].items() if v is not None))
    return out


def plot(path: Path, table: list[dict], summary: dict) -> Path:
    plt = output.pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.4))
    for ax, ladder in zip(axes, ("dt", "mesh")):
        rows = [r for r in table if r["ladder"] == ladder]
        for k, q in enumerate(("e", "P_max", "contact_time")):
            points = [(r["cpu_time_s"] or r["wall_time_s"], r[f"{q}_error"]) for r in rows if r[f"{q}_error"]]
            if points:
                ax.loglog(*zip(*points), "o-", color=f"C{k}", label=q)
        ax.set_xlabel("CPU time of the run [s]")
        ax.set_ylabel("relative error (against the extrapolation)")
        ax.set_title("time-step ladder" if ladder == "dt" else "mesh ladder")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=8)
    fig.suptitle(f"Impact at v_in = {summary['v_in']:g} m/s: discretisation error against run time")
    return output.save_figure(fig, path)

"""``nfdcal table SCENE``: calibrate every material of a scene's sweep into a parameter table.

    nfdcal table master_grid                          # the master-table grid (built-in scene)
    nfdcal table my_sweep.toml --workers 2            # local processes (default 2)
    nfdcal table my_sweep.toml --scheduler tcp://10.0.0.5:8786    # a Dask distributed cluster
    nfdcal table master_grid --master-out calib/data/master_table.csv --accuracy "..."

Writes OUT/table.csv and OUT/table.json (one row per material: inputs, P_Y, a_Y, Ca, Kc, Ca_hat,
Kc_hat, R^2 and standard errors, mesh, FE wall time, git commit) and one JSON per finished
material in OUT/materials/: a rerun resumes and recomputes nothing already done.
"""
from __future__ import annotations


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser("table", help="calibrate a sweep of materials into a parameter table",
                                   description=__doc__.split("\n\n")[0])
    parser.add_argument("scene", help="scene file (.toml) or built-in scene name")
    parser.add_argument("--out", default=None, help="output folder (default results/tables/NAME)")
    parser.add_argument("--workers", default="2", help="local worker processes (default 2)")
    parser.add_argument("--scheduler", default=None, metavar="ADDRESS",
                        help="Dask distributed scheduler address (tcp://host:port): run there instead")
    parser.add_argument("--master-out", default=None, metavar="CSV",
                        help="also write the master table (nu, E/sigma_Y -> Ca_hat, Kc_hat) here (grid scenes)")
    parser.add_argument("--accuracy", default="not validated against off-grid FE calibrations",
                        help="accuracy statement stored with the master table")
    parser.add_argument("--dry-run", action="store_true", help="print the plan and exit")
    parser.add_argument("--json", action="store_true", help="print the rows as JSON")
    parser.add_argument("--quiet", action="store_true", help="no progress messages")
    parser.set_defaults(run=run)


def run(ns) -> int:
    from calib import report, scenes, tables

    try:
        workers = int(ns.workers)
    except ValueError:
        raise ValueError(f"--workers must be an integer in [1, 64], got {ns.workers!r}") from None
    scene = scenes.load_scene(ns.scene)
    if scene.calibration_ship is None:
        raise ValueError(f"scene {scene.source}: a table needs a [calibration] section")
    if ns.master_out and not scene.is_grid:
        raise ValueError("--master-out needs a scene with a [grid] (nu x E_over_sigma_y)")
    stages = [s for s in scenes.plan(scene) if s.stage == "calibration"]
    if ns.dry_run:
        print(scenes.format_plan(scene, stages))
        return 0
    progress = scenes.terminal_progress(ns.quiet, sum(s.estimate_s for s in stages) / max(1, min(workers, len(stages))))
    result = tables.run_table(scene, ns.out, workers=workers, scheduler=ns.scheduler, progress=progress)
    if ns.master_out:
        tables.write_master_table(result["rows"], ns.master_out, ns.accuracy, scene.name)
    if ns.json:
        print(report.to_json(result["rows"]), end="")
    else:
        print(f"table {scene.name}: {len(result['rows'])} material(s), {result['computed']} calibrated, "
              f"{result['reused']} reused, {result['failed']} failed; written to {result['path']}")
    return 1 if result["failed"] else 0

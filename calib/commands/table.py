"""``nfdcal table SCENE``: calibrate every material of a scene's sweep into a parameter table.

    nfdcal table master_grid                          # the master-table grid (built-in scene)
    nfdcal table my_sweep.toml --workers 2            # local processes (default 2)
    nfdcal table my_sweep.toml --scheduler tcp://10.0.0.5:8786    # a Dask distributed cluster
    nfdcal table master_grid --master-out calib/data/master_table.csv --accuracy "..."
    nfdcal table master_validation --check-master     # off-grid FE against the interpolation
    nfdcal table vz_master_grid --master-out calib/data/vz_master_table.csv   # the vz master table
                                                      # (calib.fit.vz_master_build)
    nfdcal table vz_master_hardening --master-out calib/data/vz_hardening_table.csv   # its hardening
                                                      # sheet (calib.fit.vz_hardening_build)

Writes OUT/table.csv and OUT/table.json (one row per material: inputs, P_Y, a_Y, Ca, Kc, Ca_hat,
Kc_hat, R^2 and standard errors, mesh, FE wall time, git commit) and one JSON per finished
material in OUT/materials/: a rerun resumes and recomputes nothing already done. With
--check-master also OUT/master_check.csv and .json: each material's Ca_hat, Kc_hat interpolated
in the shipped master table against its own FE calibration (limits 3 % and 5 %; exit code 1 if
a material is outside them). --hardening-modulus H or --flow-curve CSV (--flow-curve-extrapolation)
give every material's sphere that isotropic hardening (as a scene's [calibration] hardening entry
does): each row is then the FE calibration of the hardening sphere, keyed by its flow curve
(the rows of perfectly plastic spheres keep their keys); --master-out and --check-master, of the
perfectly plastic master table, are refused with it. --rate-law johnson-cook|cowper-symonds with its constants
(--rate-form: the rate-aware law's form), or a scene's rate_law, states every sphere's strain-rate dependence in a
rate_law column beside its constants: the press is quasi-static, so the constants and the rows' keys are the
rate-independent sphere's (``nfdcal collide --Ca --Kc --rate-law`` runs the row's law); --master-out and
--check-master are refused with it.
"""
from __future__ import annotations

from calib.commands.common import (add_hardening_arguments, add_rate_form_argument, add_rate_law_arguments,
                                   add_summary_arguments, flow_curve_from_args, hardening_given, print_summary,
                                   rate_form_from_args, rate_law_from_args, rate_law_given, with_v_max)


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser("table", help="calibrate a sweep of materials into a parameter table",
                                   description=__doc__.split("\n\n")[0])
    parser.add_argument("scene", help="scene file (.toml) or built-in scene name")
    parser.add_argument("--out", default=None, help="output folder (default results/tables/NAME)")
    parser.add_argument("--workers", default="2", help="local worker processes (default 2)")
    parser.add_argument("--scheduler", default=None, metavar="ADDRESS",
                        help="Dask distributed scheduler address (tcp://host:port): run there instead")
    parser.add_argument("--master-out", default=None, metavar="CSV",
                        help="also write the master table (nu, E/sigma_Y -> Ca_hat, Kc_hat; grid scenes), or "
                             "vz_master_grid's vz master table, or vz_master_hardening's hardening sheet, here")
    parser.add_argument("--accuracy", default="not validated against off-grid FE calibrations",
                        help="one-line accuracy statement of the master table (printed by nfdcal material)")
    parser.add_argument("--accuracy-details", default="", metavar="TEXT",
                        help="the full account of the master table's accuracy (kept in its .json)")
    parser.add_argument("--check-master", action="store_true",
                        help="compare every material with the shipped master table's interpolation")
    parser.add_argument("--dry-run", action="store_true", help="print the plan and exit")
    parser.add_argument("--v-max", default=None, metavar="V",
                        help="calibrate every material for impacts up to V [m/s] (replaces the scene's load-path"
                             " peaks: calib.fit.impact_window)")
    add_hardening_arguments(parser)
    add_rate_law_arguments(parser, "every sphere's strain-rate dependence, stated in each row beside its constants "
                                   "(the press is quasi-static: the constants are the rate-independent sphere's): "
                                   "johnson-cook or cowper-symonds; default: the scene's, else rate-independent")
    add_rate_form_argument(parser)
    add_summary_arguments(parser)
    parser.set_defaults(run=run, shipped=master_checked)    # calib.commands.targets: the tables read


def master_checked(ns) -> tuple[str, ...]:
    """The shipped table the command reads: the master table with --check-master (calib.commands.targets)."""
    return ("table",) if ns.check_master else ()


def run(ns) -> int:
    from calib.fit import vz_master_scene

    if vz_master_scene.is_vz_master_scene(ns.scene):
        return run_vz_master(ns)
    return run_parameter_table(ns)


def run_vz_master(ns) -> int:
    """The vz master table's scene: every node and check to the FE's reach, resumably; with
    --master-out the vz master table (calib.fit.vz_master_build)."""
    from pathlib import Path

    from calib.commands.progress import progress_reporter
    from calib.fit import vz_master_build, vz_master_scene

    try:
        workers = int(ns.workers)
    except ValueError:
        raise ValueError(f"--workers must be an integer in [1, 64], got {ns.workers!r}") from None
    if not 1 <= workers <= 64:
        raise ValueError(f"--workers must be an integer in [1, 64], got {ns.workers!r}")
    if ns.v_max is not None or ns.check_master:
        raise ValueError("--v-max and --check-master do not apply to a vz master scene (its nodes run to the FE's reach)")
    if hardening_given(ns) is not None:
        raise ValueError(f"{hardening_given(ns)}: the vz master table is of perfectly plastic spheres (no hardening "
                         f"dimension): give the hardening to a scene of [[material]] tables or a [grid]")
    if rate_law_given(ns) is not None or getattr(ns, "rate_form", None) is not None:
        raise ValueError(f"{rate_law_given(ns) or '--rate-form'}: the vz master table is of rate-independent spheres: "
                         f"give the rate law to a scene of [[material]] tables or a [grid]")
    scene = vz_master_scene.load_scene(ns.scene)
    sheet = vz_master_scene.is_hardening_sheet(scene)
    folder = Path(ns.out or Path("results") / "tables" / scene["name"])
    tasks = vz_master_build.tasks_for(scene)
    if ns.dry_run:
        loading = vz_master_build.loading_tasks(scene)
        lines = [f"{t['kind']} {t['name']}: nu {t['nu']:g}, E/sigma_Y {t['E_over_sigma_y']:g}"
                 + (f", H/E {t['H_over_E']:g}" if t.get("H_over_E") else "") for t in tasks + loading]
        print_summary(ns, {"scene": scene["name"], "tasks": len(tasks) + len(loading), "folder": str(folder)},
                      lines + [f"{len(tasks)} calibration(s) to the FE's reach in {folder}/nodes, {len(loading)} "
                               f"nodes' loading branches with the FE's contact radius in {folder}/loading (for node records "
                               f"without it)"])
        return 0
    with progress_reporter(ns.quiet, None) as progress:
        rows = vz_master_build.run(scene, folder, workers=workers, scheduler=ns.scheduler, progress=progress)
    failed = [r for r in rows if r.get("status") != "ok"]
    result = {"scene": scene["name"], "folder": str(folder), "tasks": len(rows), "failed": len(failed)}
    lines = [vz_master_build.describe(r) for r in rows]
    if ns.master_out and not failed and sheet:
        from calib.fit import vz_hardening_build, vz_master_join

        joined = vz_master_join.joined_table(scene, rows) if scene["joins"] else None
        checked = vz_hardening_build.build(rows, ns.master_out, folder, scene=scene, joined=joined)
        result["hardening_sheet"], result["accuracy"] = str(ns.master_out), checked
        lines.append(f"hardening sheet written to {ns.master_out}; accuracy {checked['statement']}")
    elif ns.master_out and not failed:
        from calib.fit import vz_master_check

        joined = None
        if scene["joins"]:          # a finite-strain scene: its nodes beyond the small-strain scene's
            from calib.fit import vz_master_join

            joined = vz_master_join.joined_table(scene, rows)
        path = vz_master_build.write_master(rows, ns.master_out, scene, ns.accuracy, joined=joined)
        checked = vz_master_check.measure_and_state(rows + (joined["check_rows"] if joined else []), path, folder,
                                                    ladder=joined["ladder"] if joined else None)
        result["master_table"], result["accuracy"] = str(path), checked
        lines.append(f"vz master table written to {path}; accuracy {checked['statement']}")
    lines.append(f"scene {scene['name']}: {len(rows)} task(s), {len(failed)} failed; FE data in {folder}/nodes and "
                 f"{folder}/loading")
    print_summary(ns, result, lines)
    return 1 if failed else 0


def with_hardening(scene, ns):
    """``scene`` with every sphere's hardening from the flags (unchanged without them); refused
    when the scene gives its own. A window from impacts (--v-max) is then sized for the hardening sphere
    (calib.fit.impact_window.calibrate_for_impacts)."""
    given = hardening_given(ns)
    if given is None:
        return scene
    if scene.hardening:
        raise ValueError(f"{given}: scene {scene.source} gives its spheres' hardening: give it there or here, not both")
    import dataclasses

    curves = tuple((m.name, flow_curve_from_args(ns, m.material())) for m in scene.materials)
    return dataclasses.replace(scene, hardening=tuple((name, c) for name, c in curves if c is not None))


def with_rate_law(scene, ns):
    """``scene`` with every sphere's rate law from --rate-law and its constants (--rate-form: its rate-aware
    law's form), unchanged without them; refused when the scene gives its own. The press is quasi-static: the rows
    are the rate-independent sphere's constants, the rate law stated beside them."""
    given = rate_law_given(ns)
    if given is None:
        if getattr(ns, "rate_form", None) is not None:
            rate_form_from_args(ns)             # --rate-form alone: refused naming --rate-law
        return scene
    rate = rate_law_from_args(ns).record()
    if any(m.rate_law is not None for m in scene.materials):
        raise ValueError(f"{given}: scene {scene.source} gives its spheres' rate law: give it there or here, not both")
    import dataclasses

    materials = tuple(type(m)(**{**m.model_dump(), **m.rate_keys(rate), "rate_form": rate_form_from_args(ns)})
                      for m in scene.materials)
    return dataclasses.replace(scene, materials=materials)


def run_parameter_table(ns) -> int:
    from calib import output, scenes
    from calib.commands.progress import progress_reporter

    try:
        workers = int(ns.workers)
    except ValueError:
        raise ValueError(f"--workers must be an integer in [1, 64], got {ns.workers!r}") from None
    scene = with_rate_law(with_hardening(with_v_max(scenes.load_scene(ns.scene), ns.v_max), ns), ns)
    if scene.calibration_ship is None:
        raise ValueError(f"scene {scene.source}: a table needs a [calibration] section")
    if any(m.rate_law is not None for m in scene.materials) and (ns.master_out or ns.check_master):
        raise ValueError(f"{'--master-out' if ns.master_out else '--check-master'}: the master table is of "
                         f"rate-independent spheres; this table's spheres state a rate law: drop the flag")
    if scene.hardening and (ns.master_out or ns.check_master):
        raise ValueError(f"{'--master-out' if ns.master_out else '--check-master'}: the master table is of perfectly "
                         f"plastic spheres (no hardening dimension); this table's spheres harden: drop the flag")
    if ns.master_out and not scene.is_grid:
        raise ValueError("--master-out needs a scene with a [grid] (nu x E_over_sigma_y)")
    stages = [s for s in scenes.plan(scene) if s.stage == "calibration"]
    if ns.dry_run:
        folder, finished = scenes.table_folder(scene, ns.out), scenes.finished_materials(scene, ns.out)
        print_summary(ns, scenes.plan_summary(scene, stages, folder, finished),
                      scenes.format_plan(scene, stages, folder, finished))
        return 0
    estimate_s = sum(s.estimate_s for s in stages) / max(1, min(workers, len(stages)))
    with progress_reporter(ns.quiet, estimate_s) as progress:
        result = scenes.run_table(scene, ns.out, workers=workers, scheduler=ns.scheduler, progress=progress)
    if ns.master_out:
        ratios = scene.load_paths.P_max_over_P_Y if scene.load_paths is not None else None
        scenes.write_master_table(result["rows"], ns.master_out, ns.accuracy, scene.name,
                                  accuracy_details=ns.accuracy_details,
                                  window_P_max_over_P_Y=max(ratios) if ratios else None)
    outside = 0
    if ns.check_master:
        from pathlib import Path

        from calib.fit.master_table import CHECK_LIMITS, MasterTable, check_against_fe

        table = MasterTable.load()
        checks = check_against_fe(result["rows"], table)
        folder = Path(result["path"]).parent
        import json

        table_stamp = json.loads(table.path.with_suffix(".json").read_text(encoding="utf-8")).get("stamp", {})
        try:
            table_name = output.display_path(table.path)
        except ValueError:
            table_name = str(table.path)
        stamp = output.stamp(0.0, table=table_name, limits=CHECK_LIMITS,
                             table_commit=table_stamp.get("git_commit"))
        output.write_csv(folder / "master_check.csv", checks, comment=output.stamp_comment(stamp))
        output.write_json(folder / "master_check.json", {"rows": checks, "stamp": stamp})
        outside = sum(not c["within_limits"] for c in checks)
        result["master_check"] = checks
    lines = [f"{c['name']}: Ca_hat {100 * c['Ca_hat_error']:+.2f} %, Kc_hat {100 * c['Kc_hat_error']:+.2f} %"
             f" (table vs FE){'' if c['within_limits'] else '  OUTSIDE the limits'}"
             for c in result.get("master_check", [])]
    lines.append(f"table {scene.name}: {len(result['rows'])} material(s), {result['computed']} calibrated, "
                 f"{result['reused']} reused, {result['failed']} failed; written to {result['path']}")
    print_summary(ns, result, lines)
    return 1 if result["failed"] or outside else 0

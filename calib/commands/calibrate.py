"""``nfdcal calibrate``: FE load paths of a sphere on a rigid flat -> the NFD law of a DEM contact.

The plastic contact radius is a_p = Ca <P - P_Y> and the curvature factor 1 + Kc <P - P_Y>
(Vu-Quoc & Zhang 1999, eq. 2.5; nfdmodel/README.md, The NFD law on loading); Ca [m/N] and Kc [1/N] are
fitted by least squares to FE load paths that go beyond first yield P_Y [N], and always printed
and recorded. The parameter file ships, by default, the vz-table law fitted to the same paths
(calib.fit.table_fit: load-dependent a_p and C_R), which meets the targets of
calib.fit.calibration (E_TARGET in e, FORCE_TARGET in force) where the two constants miss them;
``--ship radius`` or ``force`` ships the two constants on the FE paths where they meet them;
``--ship unload`` the vz-unload law (calib.fit.unload_ship: the FE's contact radius, dent and
unloading exponent as tables; nfdmodel, the C kernel and the LAMMPS plugin run it), with its dent, contact radius at the
peak, unloading force and e against the FE paths it was fitted on and against interior paths held
out of its fit.

    nfdcal calibrate                      # the reference case, results into results/calibration
    nfdcal calibrate --json               # also print the summary object (Ca, Kc, Ca_hat, ...)
    nfdcal calibrate --E 210e9 --nu 0.29 --sigma-y 1.2e9 --R 0.005 --out my_steel

``--rate-law johnson-cook|cowper-symonds`` with its constants (``nfdcal impact``'s flags) and ``--rate-form``:
the press is quasi-static, the rate law's rate-independent limit, so the constants are the rate-independent
sphere's; the parameter file states the rate law ("rate_law", the rate-aware law of the form on the shipped vz
or vz-table law: nfdmodel/parameter_file.py), so ``collide --params`` and ``export lammps`` run the rate-aware
law. Refused in one line with --ship unload, --ladder, a hardening or a counter-body (not measured there).

Writes the parameter file (parameters.json, read by ``nfdmodel.load_parameters`` and by
``nfdcal collide --params``), per-step CSVs, plots and VTU files into --out. Progress goes to
stderr when it is a terminal (silence it with --quiet).
"""
from __future__ import annotations

import dataclasses

from calib.commands.common import (HARDENING_HELP, KINEMATICS_FLAG, add_counter_arguments, add_hardening_arguments,
                                   add_material_arguments, add_rate_form_argument, add_rate_law_arguments,
                                   add_summary_arguments,
                                   counter_folder_name, counter_from_args, flow_curve_from_args,
                                   hardening_folder_name, hardening_given, hardening_line, is_reference,
                                   material_folder_name,
                                   material_from_args, number, print_summary, rate_form_from_args,
                                   rate_law_folder_name, rate_law_from_args, rate_law_given, rate_law_line)
from nfdmodel import CalibrationWindow, reference_case
from nfdmodel.validation import check_solid


CYCLE_OVERLOAD = 1.3    # --cycles: the last reload's peak over P_max (past the turning point)
TWO_CONSTANTS = ("radius", "force")     # the --ship values that ship the paper's two constants


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "calibrate", help="FE calibration of the NFD law: Ca, Kc and the vz-table law (the reference case by default)",
        description=__doc__.split("\n\n")[0])
    add_material_arguments(parser)
    add_hardening_arguments(parser)
    add_rate_law_arguments(parser, "the sphere's strain-rate dependence, stated in the parameter file (the "
                                   "rate-aware law of --rate-form on the shipped vz or vz-table law; the press is "
                                   "quasi-static, the rate-independent limit): johnson-cook (R = 1 + C ln(max(eps_dot "
                                   "/ eps_dot_0, 1))) or cowper-symonds (R = 1 + (eps_dot / D)^(1/q)); default: "
                                   "rate-independent")
    add_rate_form_argument(parser)
    add_counter_arguments(parser)
    parser.add_argument("--peaks", nargs="+", metavar="P_MAX", default=None,
                        help=f"P_max of the load paths [N] (default: {' '.join(f'{p:g}' for p in reference_case.PEAKS)}"
                             " for the reference case, else 13.7 27.4 41.2 x P_Y)")
    parser.add_argument("--v-max", default=None, metavar="V",
                        help="calibrate for impacts up to V [m/s]: the load paths reach the force such an impact"
                             " produces (re-estimated with the new constants until covered), unloading paths"
                             " log-spaced over the whole window, which is declared from the lowest; not with --peaks")
    parser.add_argument("--contact-size", default=None,
                        help="element size at the contact [m] (default: the reference mesh, scaled"
                             " with the contact radius for other materials)")
    parser.add_argument("--ship", default="table", choices=("radius", "force", "table", "unload"),
                        help="which law the parameter file ships: the vz-table law (table, the default: it meets"
                             " the accuracy targets), the paper's two constants fitted to the contact radius"
                             " (radius) or to the force (force), declared only over the FE paths where they meet"
                             " the targets, or the vz-unload law (unload: also the FE's dent, contact radius and"
                             " unloading curve)")
    parser.add_argument("--kinematics", default="auto", choices=("auto",) + tuple(KINEMATICS_FLAG),
                        help="the FE's kinematics: small strain, finite strain (total Lagrangian, Hencky strain; the"
                             " sphere on the rigid flat or an elastic counter-body, not with --ladder or"
                             " --counter-sigma-y; on the rigid flat it reaches 1e4 P_Y and a/R 0.45, small strain 1000"
                             " P_Y and a/R 0.2) or auto (the default: finite strain where the plan's contact radius"
                             " passes 0.1 R, where the two part by more than 2 %%, or its load the small-strain"
                             " reach; small strain below)")
    parser.add_argument("--cycles", default=None, metavar="FRACTIONS",
                        help="also run FE load cycles (calib.fe.cycles) from the middle load path's peak P_max: partial"
                             " unloads to these fractions of P_max (e.g. 0.5,0.2), each reloaded to P_max, the last on"
                             f" to {CYCLE_OVERLOAD:g} P_max, then a full unload; the vz-table and vz-unload laws checked"
                             " against them (cycles.csv, cycles.json)")
    parser.add_argument("--out", default=None, help="output folder (default results/calibration for the"
                        " reference case; for another material or other options a folder of its own below it,"
                        " e.g. results/calibration/E<E>_nu<nu>_sy<sigma_y>_R<R>_peaks<P1>-<P2>); one"
                        " calibration per folder: a run clears the files of the previous one there and refuses"
                        " a folder another run is writing")
    parser.add_argument("--no-plots", action="store_true", help="skip PNG and VTU outputs")
    parser.add_argument("--ladder", action="store_true",
                        help="reference sphere and paths on a ladder of 5 meshes: Ca, Kc, e, alpha"
                             " against wall time; material flags (not --R) for e.g. a locking study"
                             " at nu = 0.49 (resumes: finished rungs are kept in OUT/ladder/)")
    parser.add_argument("--dry-run", action="store_true",
                        help="print the plan (mesh, dofs, FE steps, estimated time, output folder) and exit")
    add_summary_arguments(parser)
    parser.set_defaults(run=run)


def accuracy_lines(accuracy: dict) -> list[str]:
    """Each law of the calibration against its own FE paths, the shipped one named, a miss of the
    targets said and the law that meets them offered (calib.fit.calibration.accuracy)."""
    if not accuracy:
        return []
    targets = accuracy["targets"]
    bounds = f"{targets['e_error']:.0%} in e, {targets['force_error']:.0%} in force"
    lines = [f"{law} law against these FE paths: e {r['worst_e_error']:+.2%}, force {r['worst_force_error']:.2%} at "
             f"worst" + ("; shipped" if law == accuracy["shipped"] else "")
             + ("" if r["within_target"] else f" (beyond the targets {bounds})")
             for law, r in accuracy["laws"].items()]
    shipped, table = accuracy["laws"].get(accuracy["shipped"]), accuracy["laws"].get("vz-table")
    if shipped is not None and not shipped["within_target"] and table is not None and table["within_target"]:
        lines.append("  the vz-table law meets them on every path: --ship table (the default)")
    return lines


def folder_name(ns, material, radius: float, peaks, contact_size, ship: str, v_max, counter=None,
                hardening=None, rate=None) -> str:
    """The default folder of a calibration under results/calibration: "" for the reference one
    (which ``collide --report`` reads), else a name made of every option that differs from it
    (material and R, the hardening, the rate law and its form, the counter-body, --kinematics, --peaks,
    --contact-size, --ship, --v-max), so that each folder holds one calibration."""
    parts = [] if is_reference(ns) else [material_folder_name(material, radius)]
    if hardening is not None:
        parts.append(hardening_folder_name(hardening))
    if rate is not None:
        parts.append(f"{rate_law_folder_name(rate)}_{rate_form_from_args(ns)}")
    if counter is not None:
        parts.append(counter_folder_name(counter))
    if getattr(ns, "kinematics", "small") not in ("small", "auto"):
        parts.append(f"{ns.kinematics}-strain")
    if ns.peaks is not None:            # the set of peaks, in any order, is one calibration (recipe sorts them)
        parts.append("peaks" + "-".join(f"{p:g}" for p in sorted(peaks)))
    if contact_size is not None:
        parts.append(f"h{contact_size:g}")
    if ship != "table":
        parts.append(f"ship-{ship}")
    if v_max is not None:
        parts.append(f"vmax{v_max:g}")
    return "_".join(parts)


def plan_ladder(ns, material, name: str, mesh_ladder) -> int:
    """--ladder --dry-run: the rungs (mesh, dofs, FE steps, estimated time), which are finished
    (kept in OUT/ladder/ from an earlier run) and the files the ladder writes."""
    from pathlib import Path

    from calib.report import calibration as calibration_report
    from calib.scenes.plan import calibration_stage, format_stages, stages_summary

    out = Path(ns.out or calibration_report.DEFAULT_OUT)
    tasks = mesh_ladder.ladder_tasks(material=material)
    stages = [calibration_stage(task["spec"], f"h = {task['contact_size']:g} m", calibrate=True, unload=True,
                                elastic=False, meshes=1) for task in tasks]
    done = [task["contact_size"] for task in tasks if (out / "ladder" / f"{task['key']}.json").is_file()]
    summary = {**stages_summary(stages, out), "rungs_done": done, "writes": [f"{name}.csv", f"{name}_pairs.csv",
                                                                            f"{name}.png"]}
    sizes = ", ".join(f"{task['contact_size']:g}" for task in tasks)
    print_summary(ns, summary, [f"mesh ladder of {len(tasks)} meshes (contact elements {sizes} m), {len(done)} finished in "
                                f"{out / 'ladder'}; writes {', '.join(summary['writes'])} into {out}"]
                + format_stages(stages))
    return 0


def parse_cycles(text) -> tuple[float, ...] | None:
    """--cycles FRACTIONS: comma-separated P/P_max, each in (0, 1); None when not given."""
    if text is None:
        return None
    return tuple(number("--cycles", part.strip(), low=0.0, high=1.0, unit="x P_max, comma-separated (e.g. 0.5,0.2)")
                 for part in str(text).split(","))


def write_cycles(result, fractions, out, progress) -> dict | None:
    """--cycles: the FE cycles from the calibration's committed peak state (calib.fe.cycles), the
    laws against them (calib.fit.cycle_check), cycles.csv (the rows) and cycles.json (the figures)
    in ``out``; without --cycles the files of an earlier run's cycles are removed. None without."""
    from pathlib import Path

    from calib import output

    out = Path(out)
    if fractions is None:
        if (out / ".cycles.files").is_file():
            with output.all_or_nothing(out, name="cycles"):
                pass
        return None
    from calib.fe.cycles import CyclePlan, closed_cycles, run_cycles
    from calib.fit.cycle_check import cycles_against_law, laws_of_calibration

    if not result.load_paths.paths:
        raise ValueError("--cycles starts from a load path's peak: the calibration has no unloading paths")
    plan = CyclePlan(fractions, CYCLE_OVERLOAD)
    progress(f"cycles from P_max = {plan.peak_of(result.spec.plan):g} N: unloads to {', '.join(f'{f:g}' for f in fractions)}"
             f" P_max, the last reload on to {CYCLE_OVERLOAD:g} P_max")
    run = run_cycles(result.solver, result.spec.plan, plan, result.load_paths)
    fitted = laws_of_calibration(result)
    laws = {name: cycles_against_law(name, params, run.rows, run.P_max, run.alpha_residual)
            for name, params in fitted["laws"].items()}
    summary = {"fractions": list(fractions), "overload": CYCLE_OVERLOAD, "P_max": run.P_max,
               "overload_peak": run.overload_peak, "alpha_max": run.alpha_max, "alpha_residual": run.alpha_residual,
               "closed_cycles": closed_cycles(run), "laws": laws, "laws_not_fitted": fitted["not_fitted"],
               "rows": len(run.rows), "file": "cycles.csv"}
    columns = ["cycle", "branch", "alpha", "P", "contact_radius", "plastic_zone_depth", "plastic_zone_radius",
               "yielded_points"]
    with output.all_or_nothing(out, name="cycles") as staging:
        output.write_csv(staging / "cycles.csv", run.rows, columns,
                         comment="FE load cycles (calib.fe.cycles); SI units: alpha [m], P [N], radii [m]")
        output.write_json(staging / "cycles.json", summary)
    return summary


def cycle_lines(cycles: dict | None) -> list[str]:
    if cycles is None:
        return []
    lines = [f"cycles from P_max {cycles['P_max']:.4g} N (unloads to {', '.join(f'{f:g}' for f in cycles['fractions'])}"
             f" P_max, overload to {cycles['overload_peak']:.4g} N): residual alpha {cycles['alpha_residual']:.4e} m"]
    lines += [f"  cycle {c['cycle']} to {c['fraction']:.3g} P_max: work in {c['work_in']:.4e} J, out "
              f"{c['work_out']:.4e} J; reload at P_max {c['reload_alpha_at_peak_error']:+.2e} alpha_max from the "
              f"turning point" for c in cycles["closed_cycles"]]
    lines += [f"  {law} against the cycles: partial unloads and reloads {r['partial_error']:.2%} of P_max, final "
              f"unload {r['final_unloading_error']:.2%}, dent {r['dent_error']:+.2%}"
              + ("" if r["within"] else " (beyond 2 %)") for law, r in cycles["laws"].items()]
    lines += [f"  {law} not fitted: {why}" for law, why in cycles["laws_not_fitted"].items()]
    return lines


def v_max_mesh(contact_size) -> dict:
    """The mesh options of a --v-max calibration: the contact element --contact-size, else the graded
    mesh on which every contact radius from the lowest path (impact_window.LOWEST_PEAK_OVER_P_Y P_Y) up
    spans impact_window.GRADED_ELEMENTS_PER_CONTACT_RADIUS elements, so the window starts there."""
    from calib.fit import impact_window

    if contact_size is not None:
        return {"contact_size": contact_size}
    return {"elements_per_contact_radius": impact_window.GRADED_ELEMENTS_PER_CONTACT_RADIUS}


def kinematics_line(ns, spec) -> str:
    """'kinematics: finite-strain (auto: ...); the FE vouches for P <= ...': the plan's kinematics, why
    (--kinematics auto), the FE's reach in it and that reach's error estimate (calib.fit.recipe)."""
    from calib.fit import recipe

    pair = spec.pair
    chosen = recipe.reach_kinematics(spec.kinematics, spec.counter)
    why = ""
    if ns.kinematics == "auto":
        a_top = recipe.fe_contact_radius(pair, spec.plan.peaks[-1]) / pair.R_star
        why = (f" (auto: the plan reaches about a/R* {a_top:.3g}, {spec.plan.peaks[-1] / pair.P_Y:.4g} P_Y; finite "
               f"strain above a/R* {recipe.KINEMATICS_PART_OVER_R:g}, where the two part by more than 2 %)")
    return (f"kinematics: {spec.kinematics}{why}; the FE vouches for up to {recipe.fe_reach(pair, chosen) / pair.P_Y:.4g}"
            f" P_Y here ({recipe.reach_text(chosen)})")


def counter_absent(ns) -> bool:
    return all(getattr(ns, key, None) is None for key in ("counter_E", "counter_nu", "counter_sigma_y", "counter_R",
                                                         "counter_rho"))


def run(ns) -> int:
    from calib import output
    from calib.commands.progress import progress_reporter
    from calib.fit import calibration, impact_window, recipe, unload_ship
    from calib.report import calibration as calibration_report
    from calib.studies import mesh_ladder
    from nfdmodel.parameter_file import law_of, stated_rate_law

    rate, form = rate_law_from_args(ns), rate_form_from_args(ns)
    if rate is not None:                # stated in the parameter file: the rate-aware law on the shipped law
        for flag, given in (("--ship unload", ns.ship == "unload"), ("--ladder", ns.ladder),
                            ("--counter-E", not counter_absent(ns))):
            if given:
                raise ValueError(f"{rate_law_given(ns)} out of range with {flag}: the rate-aware law scales sigma_Y of "
                                 f"a perfectly plastic sphere's vz or vz-table law on the rigid flat")
    kinematics = KINEMATICS_FLAG.get(ns.kinematics)         # None: auto, chosen from the plan below
    if ns.kinematics == "finite" and (ns.ladder or getattr(ns, "counter_sigma_y", None) is not None):
        raise ValueError("--kinematics finite takes a calibration on the rigid flat or an elastic counter-body (the"
                         " ladder and a plastic counter-body are small-strain): drop --ladder and --counter-sigma-y,"
                         " or use --kinematics small")
    cycles = parse_cycles(ns.cycles)
    if ns.ladder:
        if cycles is not None:
            raise ValueError("--cycles runs load cycles of one calibration: the --ladder compares meshes on the "
                             "reference paths; drop one of them")
        hardening_flags = any(getattr(ns, key) is not None for key in HARDENING_HELP)
        if ns.R is not None or ns.peaks is not None or ns.contact_size is not None or not counter_absent(ns) \
                or hardening_flags:
            raise ValueError("--ladder runs the reference sphere and load paths on its own meshes:"
                             " do not combine it with --R, --peaks, --contact-size, the --counter-* flags,"
                             " --hardening-modulus or --flow-curve")
        material = None if is_reference(ns) else material_from_args(ns)[0]
        name = "mesh_ladder" if material is None else f"mesh_ladder_nu{material.nu:g}_E{material.E:g}_sy{material.sigma_y:g}"
        if ns.dry_run:
            return plan_ladder(ns, material, name, mesh_ladder)
        with progress_reporter(ns.quiet) as progress:
            path = mesh_ladder.mesh_ladder(out=ns.out or calibration_report.DEFAULT_OUT,
                                           progress=progress, material=material, name=name)
        print_summary(ns, {"out": str(path)}, [f"mesh ladder written to {path}"])
        return 0
    material, radius = material_from_args(ns)
    hardening = flow_curve_from_args(ns, material)
    if rate is not None and hardening is not None:
        raise ValueError(f"{rate_law_given(ns)} out of range with {hardening_given(ns)}: the rate-aware law scales "
                         f"sigma_Y of a perfectly plastic sphere's vz or vz-table law on the rigid flat")
    counter = counter_from_args(ns, material)
    contact_size = number("--contact-size", ns.contact_size)
    if contact_size is not None and not contact_size > 0:
        raise ValueError(f"--contact-size out of range: need > 0 m, got {contact_size:g}")
    peaks = None if ns.peaks is None else tuple(number("--peaks", p) for p in ns.peaks)
    if peaks is not None and not all(p > 0 for p in peaks):
        raise ValueError(f"--peaks out of range: need forces > 0 N, got {' '.join(f'{p:g}' for p in peaks)}")
    v_max = number("--v-max", ns.v_max, None, low=0.0, unit="m/s")
    ship = ns.ship
    if v_max is not None:
        if peaks is not None:
            raise ValueError("--v-max sets the load paths from the impacts: do not combine it with --peaks")
        check_solid("v_in", v_max)
        needed, params, _ = impact_window.check_reach(material, radius, v_max,   # before any mesh
                                                      kinematics or "finite-strain", counter, hardening)
        if kinematics is None:
            kinematics = recipe.chosen_kinematics(params.pair, impact_window.window_top(
                params.pair, needed, "finite-strain", counter), counter)
        spec = impact_window.impact_spec(material, radius, needed, kinematics, counter=counter,
                                         **v_max_mesh(contact_size))
        if hardening is not None:
            spec = dataclasses.replace(spec, hardening=hardening)
    else:
        spec = recipe.calibration_spec(material, radius, peaks=peaks, contact_size=contact_size, counter=counter,
                                       kinematics=kinematics or recipe.reach_kinematics("finite-strain", counter))
        if kinematics is None:
            kinematics = recipe.chosen_kinematics(spec.pair, spec.plan.peaks[-1], counter)
        if kinematics != spec.kinematics:   # its mesh sized by the chosen kinematics' radius (recipe.sizing_radius)
            spec = recipe.calibration_spec(material, radius, peaks=peaks, contact_size=contact_size, counter=counter,
                                           kinematics=kinematics)
        if hardening is not None:
            spec = dataclasses.replace(spec, hardening=hardening)
        if peaks is None:               # C_R is measured at unloading peaks: paths from near P_Y, Ca and Kc unchanged
            spec = impact_window.with_unloading_across(spec)
    try:                                # before any mesh: name the flag that sets the load plan
        recipe.check_fittable(spec)
    except ValueError as exc:
        raise ValueError(f"--peaks: {exc}" if peaks is not None else str(exc)) from None
    default_out = calibration_report.DEFAULT_OUT / folder_name(ns, material, radius, peaks, contact_size, ship, v_max,
                                                               counter, hardening, rate)
    if ns.dry_run:
        from calib.scenes.plan import calibration_stage, format_stages, stages_summary

        stages = [calibration_stage(spec, "sphere", calibrate=True, unload=True, elastic=False)]
        folder = ns.out or default_out
        print_summary(ns, stages_summary(stages, folder),
                      [f"calibration of E = {material.E:.4g} Pa, nu = {material.nu:g}, sigma_Y = "
                       f"{material.sigma_y:.4g} Pa, R = {radius:g} m; P_Y = {spec.pair.P_Y:.4g} N"]
                      + ([hardening_line(hardening)] if hardening is not None else [])
                      + ([f"{rate_law_line(rate, '')}; stated in the parameter file ({form} rate-aware law)"]
                         if rate is not None else [])
                      + ([f"{counter.label()} (the dofs below count both bodies)"]
                         if counter is not None else [])
                      + [kinematics_line(ns, spec)]
                      + [f"outputs: {folder}"] + format_stages(stages)
                      + ([f"then load cycles from the middle path's peak: unloads to {', '.join(f'{f:g}' for f in cycles)} "
                          f"P_max, the last reload on to {CYCLE_OVERLOAD:g} P_max, a full unload (cycles.csv)"]
                         if cycles is not None else []))
        return 0
    rounds = None
    with output.one_writer(ns.out or default_out), progress_reporter(ns.quiet) as progress:
        if v_max is None:
            result = calibration.calibrate(spec, progress=progress, ship=ship)
        else:                           # round 1 is the plan above; more rounds if it falls short
            found = impact_window.calibrate_for_impacts(material, radius, v_max, progress=progress, ship=ship,
                                                        kinematics=kinematics, counter=counter, hardening=hardening,
                                                        **v_max_mesh(contact_size))
            result, rounds = found.result, list(found.rounds)
        if ship in TWO_CONSTANTS and result.load_paths.paths and result.two_constant_window() is None:
            record = calibration.accuracy(result)["laws"]["vz"]
            raise ValueError(f"--ship {ship}: the two constants (Ca = {result.params.Ca:.4g} m/N, Kc = "
                             f"{result.params.Kc:.4g} 1/N) meet the targets at no FE path (e {record['worst_e_error']:+.2%}, "
                             f"force {record['worst_force_error']:.2%} at worst): nothing shipped; --ship table (the "
                             f"default) ships the law that meets them")
        rate_entry = None if rate is None else stated_rate_law(result.shipped_params, rate.record(), form)
        out = calibration_report.write(result, ns.out or default_out, plots=not ns.no_plots,
                                       vtu=not ns.no_plots, rate_law=rate_entry)
        cycle_summary = write_cycles(result, cycles, out, progress)
    summary = {**calibration.summary(result), "out": str(out),
               **({"counter_body": counter.describe()} if counter is not None else {}),
               **({"rate_law": rate_entry} if rate is not None else {})}
    if cycle_summary is not None:
        summary["cycles"] = cycle_summary
    if rounds is not None:
        summary["v_max"] = {"v_max": v_max, "rounds": rounds}
    lines = ([hardening_line(hardening)] if hardening is not None else []) + (
        [f"{rate_law_line(rate, '')}; the parameter file states the {form} rate-aware law on the shipped "
         f"{law_of(result.shipped_params)} law (the press: its rate-independent limit)"] if rate is not None else []) + (
        [counter.label() + f"; the pair's E* = {spec.pair.E_star:.4g} Pa, R* = {spec.pair.R_star:.4g} m, "
                                f"m* = {spec.pair.mass_star:.4g} kg"]
             if counter is not None else []) + [f"Ca = {summary['Ca']:.4g} m/N (Ca_hat {summary['Ca_hat']:.4g}), Kc = {summary['Kc']:.4g} 1/N "
             f"(Kc_hat {summary['Kc_hat']:.4g}), P_Y = {summary['P_Y']:.4g} N (FE first yield "
             f"{summary['P_Y_fe']:.4g} N), {summary['wall_time_s']:.1f} s"]
    mesh = summary.get("discretisation") or {}
    if summary.get("Ca_rel_error_estimate") is not None:
        lines.append(f"  mesh-converged: extrapolated from contact elements {mesh['contact_sizes'][0]:.3g} and "
                     f"{mesh['contact_sizes'][1]:.3g} m; estimated discretisation error Ca "
                     f"{summary['Ca_rel_error_estimate']:.2%}, Kc {summary['Kc_rel_error_estimate']:.2%}"
                     + (f", e {summary['e_rel_error_estimate']:.2%}, alpha {summary['alpha_rel_error_estimate']:.2%}"
                        if summary.get("e_rel_error_estimate") is not None else ""))
    lines += [f"  P_max {p['P_max']:8.4g} N: alpha_max {p['alpha_max']:.4e} m, e {p['e']:.4f}"
              + " (" + ", ".join(f"{law} {p['models'][law]['e']:.4f}" for law in ("vz", "vz-table")
                                 if law in p["models"]) + ")"
              + f", residual alpha {p['alpha_residual']:.4e} m" for p in summary["paths"]]
    if summary.get("table") is not None:
        table = summary["table"]
        lines.append(f"vz-table law: {len(table['P_over_P_Y'])} nodes to {table['P_over_P_Y'][-1]:.4g} P_Y, a_p/a_Y "
                     f"{table['a_p_over_a_Y'][-1]:.4g} and C_R {table['C_R'][-1]:.4g} at the last"
                     + {"table": "; shipped", "unload": "; shipped: the vz-unload law"}.get(
                         ship, f"; shipped: the {ship} fit of the two constants"))
    lines += accuracy_lines(summary.get("accuracy") or {})
    lines += cycle_lines(cycle_summary)
    if "vz_unload" in summary:
        lines += unload_ship.lines(summary["vz_unload"])
    window = CalibrationWindow.from_record(summary["shipped_window"])     # from the lowest path it meets
    if ship in TWO_CONSTANTS and summary.get("accuracy"):
        lines.append(f"two constants shipped on P/P_Y {window.P_min_over_P_Y:.4g}-{window.P_max_over_P_Y:.4g} only: "
                     f"the FE paths where they meet the targets")
    lines.append(f"calibrated window: {window.describe()}"
                 + (f"; covers impacts up to v_in = {v_max:g} m/s ({len(rounds)} FE calibration(s): "
                    f"it reaches {rounds[-1]['P_max_of_v_max_over_P_Y']:.4g} P_Y)" if rounds else ""))
    print_summary(ns, summary, lines + [f"results written to {out}"])
    return 0

"""``nfdcal impact``: the whole sphere thrown at the rigid flat by the dynamic FE, against the laws.

The sphere (mass (4/3) pi R^3 rho) flies at v_in toward a rigid frictionless flat, hits it,
rebounds and separates; Newmark's average acceleration with the exact active set
(calib.fe.newmark, calib.fe.impact). Per velocity: e (rebound speed of the centre of mass over
v_in), P_max, contact time, alpha_max (approach of the centre of mass), the residual dent and the
energy balance (kinetic in and out, plastic work, residual-stress and vibration energy, the
residual), each with its estimated discretisation error (a run on the doubled contact element
and one at twice the time step), against the quasi-static laws (vz, Thornton, Hertz).

    nfdcal impact                                  # the reference sphere at 0.5, 2, 10, 30 v_Y -> results/impact
    nfdcal impact --params results/calibration/parameters.json --table-params results/impact/vz_table/parameters.json \
        --lammps-restitution results/lammps/restitution.csv      # compared with those files
    nfdcal impact --v-in 0.04 --json               # one impact, the record as JSON
    nfdcal impact --sigma-y 1e11 --v-in 0.04       # never yields: Hertz's limit
    nfdcal impact --convergence --v-in 0.04        # error against run time: dt and mesh ladders
    nfdcal impact --rate-law cowper-symonds --cs-D 6500 --cs-q 4 --v-in 0.04   # a rate-dependent sphere
    nfdcal impact --drops drops.csv                # drop tests (fit-data's file) against the FE: OUT/drops.csv
    nfdcal fit-data --impacts results/impact/drop_tests.csv --E 7e10 --nu 0.3 --R 0.1 --rho 2699   # the reverse
    nfdcal impact --counter-E 2.1e11 --counter-nu 0.28 --v-in 0.04   # on an elastic steel flat (a held block)
    nfdcal impact --counter-E 7e10 --counter-R 0.1 --counter-rho 2699 --v-in 0.08   # two free spheres, 0.08 m/s relative
    nfdcal impact --kinematics finite --v-in 0.04  # finite strain (total Lagrangian, Hencky strain): OUT .../finite-strain

With --counter-E (and --counter-nu, --counter-sigma-y, --counter-R, --counter-rho: a counter-sphere's
density, required; a flat's default the sphere's) the sphere hits a deformable
counter-body instead (calib.fe.impact_pair, calib.studies.impact_pair): a free counter-sphere
(--v-in: the relative velocity, the pair starting in its centre-of-mass frame; e: the relative
normal velocity ratio) or a flat block with its far face held; each impact beside Hertz's for the
pair's E*, R* and reduced mass, with the same error estimate (both meshes' contact element doubled,
dt doubled; --no-error-estimate: the fine impact only). Not with --drops, --convergence, --params,
--table-params, --lammps-restitution, --no-quasi-static, --no-plots (a pair impact has neither
quasi-static comparison nor plots) or --kinematics finite (the two-body FE is small-strain).

--kinematics finite runs the impact and its quasi-static path with finite strain (calib.fe.kinematics
FiniteStrain; the run keys and the default folder name say so); small strain is the default.

The laws are compared with the files given alone: --params (vz: the two constants of a parameter
file, a calibration's whichever law it ships; else the master table's), --table-params (a vz-table
law) and --lammps-restitution (LAMMPS' mdr restitution, the reference sphere's); nothing under
./results is read unless named. The output names each file compared with.

Velocities run through the sweep runner (--workers processes; resumable: each finished impact is
OUT/cases/<key>.json and a rerun reuses it). Writes impact.csv, impact.json, drop_tests.csv, impact.png,
histories.png into --out (calib.studies.impact_output); --convergence writes convergence.*.
"""
from __future__ import annotations

import os

from calib.commands.common import (KINEMATICS_FLAG, add_counter_arguments, add_hardening_arguments, add_material_arguments,
                                   add_rate_law_arguments, add_summary_arguments, counter_from_args,
                                   flow_curve_from_args, hardening_folder_name, hardening_line, integer, is_reference,
                                   material_from_args, number, print_summary, rate_law_folder_name, rate_law_from_args,
                                   rate_law_line)
from calib.commands.targets import refuse_output_over_input

# the files written into --out (calib.studies.impact_output, impact_drops, impact_convergence, impact_pair)
OUT_FILES = ("impact.csv", "impact.json", "drop_tests.csv", "drops.csv", "impact.png", "histories.png",
             "convergence.csv", "convergence.json", "convergence.png", "impact_pair.csv", "impact_pair.json",
             "repeat.csv", "repeat.json")


def add_parser(subparsers) -> None:
    from calib.studies.impact_drops import MOST_VELOCITIES as MOST_DROP_VELOCITIES

    parser = subparsers.add_parser(
        "impact", help="dynamic FE impact of the whole sphere: e, P_max, contact time, energy balance",
        description=__doc__.split("\n\n")[0])
    add_material_arguments(parser)
    add_hardening_arguments(parser)
    add_rate_law_arguments(parser)
    add_counter_arguments(parser)
    parser.add_argument("--v-in", nargs="+", metavar="V", default=None,
                        help="impact velocities [m/s] (> 0; default: 0.5 2 10 30 x v_Y of the material)")
    parser.add_argument("--drops", default=None, metavar="CSV",
                        help="drop tests (fit-data's impacts file: v_in, e; optional P_max, contact_time): the FE at"
                             " their velocities, each test against it in OUT/drops.csv (not with --v-in); more than"
                             f" {MOST_DROP_VELOCITIES} distinct velocities: the FE at {MOST_DROP_VELOCITIES} spread in log"
                             " v_in, the tests against it interpolated (said in the output)")
    parser.add_argument("--repeat", default=None, metavar="N",
                        help="N impacts at each --v-in on the same spot (integer 1 .. 10): the dent and residual"
                             " stresses carried over, the vibrations let die out between impacts; e, P_max, dent of"
                             " each, beside the laws' repeated impacts (OUT/repeat.json, repeat.csv; no error"
                             " estimate, quasi-static path or plots)")
    parser.add_argument("--unload-params", default=None, metavar="FILE",
                        help="with --repeat: a vz-unload parameter file (nfdcal calibrate --ship unload) whose law"
                             " the FE is also compared with")
    parser.add_argument("--steps-per-contact", default=None,
                        help="time steps per estimated contact time (integer 10 .. 10000, default 100)")
    parser.add_argument("--contact-size", default=None,
                        help="element size at the contact [m] (default: the calibration's mesh for the impact)")
    parser.add_argument("--params", default=None, metavar="FILE",
                        help="parameter file whose vz constants the FE is compared with (a calibration's"
                             " parameters.json, whichever law it ships; default: the master table's constants)")
    parser.add_argument("--table-params", default=None, metavar="FILE",
                        help="vz-table parameter file the FE is also compared with (e.g. nfdcal calibrate --v-max's;"
                             " default: none)")
    parser.add_argument("--lammps-restitution", default=None, metavar="CSV",
                        help="LAMMPS' granular mdr restitution of the reference sphere (restitution.csv of"
                             " tests/benchmarks/bench_lammps.py) the FE is also compared with (default: none)")
    parser.add_argument("--kinematics", default="small", choices=tuple(KINEMATICS_FLAG),
                        help="the FE's kinematics: small strain (the default) or finite strain (total Lagrangian,"
                             " Hencky strain; the sphere on the rigid flat, not with --counter-E)")
    parser.add_argument("--no-error-estimate", action="store_true",
                        help="run the fine impact only (no discretisation error estimate: a third of the work)")
    parser.add_argument("--no-quasi-static", action="store_true",
                        help="skip the quasi-static FE load-unload path to each impact's P_max (the comparison of the"
                             " dynamic FE with the quasi-static assumption)")
    parser.add_argument("--convergence", action="store_true",
                        help="at the first --v-in (default 0.04 m/s): time-step and mesh ladders, error against run time")
    parser.add_argument("--workers", default=None,
                        help="processes for the velocities (integer >= 1, default: 2 or the machine's cores if fewer)")
    parser.add_argument("--out", default=None,
                        help="output folder (default results/impact, or a folder below it named by what differs from"
                             " the reference sphere)")
    parser.add_argument("--no-plots", action="store_true", help="skip the PNG plots")
    parser.add_argument("--dry-run", action="store_true",
                        help="print the plan (velocities, meshes, runs, estimated time, output folder) and exit")
    add_summary_arguments(parser)
    # calib.commands.targets: the master table read without --params, the files written into --out
    parser.set_defaults(run=run, shipped=("table",), writes_into=OUT_FILES)


def options(ns):
    """(setup, velocities, workers) from the flags, every value checked before any work; with a
    counter-body, setup is a calib.studies.impact_pair.PairImpactSetup."""
    from nfdmodel.validation import check_solid

    from calib.studies import impact, impact_files

    material, radius = material_from_args(ns)
    contact_size = number("--contact-size", ns.contact_size, None, low=0.0, unit="m")
    steps = integer("--steps-per-contact", ns.steps_per_contact, impact.DEFAULT_STEPS_PER_CONTACT, 10, 10000)
    workers = integer("--workers", ns.workers, min(2, os.cpu_count() or 1), 1, 256)
    hardening = flow_curve_from_args(ns, material)
    rate_law = rate_law_from_args(ns)
    setup = impact.ImpactSetup(material=material, radius=radius, contact_size=contact_size, steps_per_contact=steps,
                               hardening=hardening, rate_law=rate_law, kinematics=KINEMATICS_FLAG[ns.kinematics])
    counter = counter_from_args(ns, material)
    if counter is not None and ns.kinematics != "small":
        raise ValueError("--kinematics finite is for the rigid flat: the pair impact's two-body FE is small-strain"
                         " (use --kinematics small with --counter-E)")
    if rate_law is not None:
        for flag, given in (("--counter-E", counter is not None),
                            ("--lammps-restitution", ns.lammps_restitution is not None)):
            if given:
                raise ValueError(f"{flag} is for a rate-independent sphere: do not combine it with --rate-law")
    if hardening is not None:
        for flag, given in (("--counter-E", counter is not None),
                            ("--lammps-restitution", ns.lammps_restitution is not None)):
            if given:
                raise ValueError(f"{flag} is for a perfectly plastic sphere: do not combine it with "
                                 f"--hardening-modulus or --flow-curve")
    if counter is not None:
        from calib.studies import impact_pair

        for flag, given in (("--drops", ns.drops is not None), ("--convergence", ns.convergence),
                            ("--params", ns.params is not None), ("--table-params", ns.table_params is not None),
                            ("--lammps-restitution", ns.lammps_restitution is not None),
                            ("--no-quasi-static", ns.no_quasi_static),
                            ("--no-plots", ns.no_plots)):
            if given:
                raise ValueError(f"{flag} is for the rigid flat: do not combine it with --counter-E")
        setup = impact_pair.PairImpactSetup(setup, counter)
        velocities = (impact_pair.study_velocities(setup) if ns.v_in is None else
                      tuple(check_solid("v_in", number("--v-in", v, low=0.0, unit="m/s")) for v in ns.v_in))
        return setup, tuple(sorted(set(velocities))), workers
    if ns.drops is not None:
        from calib.studies import impact_drops

        if ns.v_in is not None or ns.convergence:
            raise ValueError("--drops sets the velocities from the drop tests: do not combine it with --v-in or --convergence")
        velocities = impact_drops.velocities(impact_drops.read(ns.drops))
    elif ns.v_in is None:
        velocities = (impact.CONVERGENCE_VELOCITY,) if ns.convergence else impact.study_velocities(setup)
        if not ns.convergence:
            impact.check_study_velocities(setup)     # names --sigma-y: no --v-in was given
    else:
        velocities = tuple(check_solid("v_in", number("--v-in", v, low=0.0, unit="m/s")) for v in ns.v_in)
    for flag, path in (("--params", ns.params), ("--table-params", ns.table_params),
                       ("--lammps-restitution", ns.lammps_restitution)):
        if path is not None and not os.path.isfile(path):
            raise ValueError(f"{flag} {path}: no such file")
    impact_files.law_parameters(setup, ns.params)      # refused before any work: another law's or material's file
    impact_files.table_parameters(setup, ns.table_params)
    if ns.lammps_restitution is not None:     # refused before any work: another sphere, a file without its columns
        try:
            impact_files.mdr_table(setup, ns.lammps_restitution)
        except ValueError as exc:
            raise ValueError(f"--lammps-restitution {exc}") from None
    return setup, tuple(sorted(set(velocities))), workers


def default_out(ns, setup) -> str:
    """results/impact for the reference sphere with the default mesh and steps, else a folder below
    it named by what differs."""
    from calib.studies import impact

    if hasattr(setup, "counter"):
        c, m = setup.counter, setup.sphere.material
        parts = [f"pair_E{m.E:g}_nu{m.nu:g}_sy{m.sigma_y:g}_R{setup.sphere.radius:g}_counterE{c.E:g}_nu{c.nu:g}"
                 f"_sy{c.sigma_y or 0:g}_R{c.R or 0:g}" + ("" if c.rho is None else f"_rho{c.rho:g}")]
        if setup.sphere.contact_size is not None:
            parts.append(f"h{setup.sphere.contact_size:g}")
        if setup.sphere.steps_per_contact != impact.DEFAULT_STEPS_PER_CONTACT:
            parts.append(f"steps{setup.sphere.steps_per_contact}")
        return str(impact.DEFAULT_OUT / "_".join(parts))
    material = setup.material
    parts = [] if is_reference(ns) else [f"E{material.E:g}_nu{material.nu:g}_sy{material.sigma_y:g}_R{setup.radius:g}"]
    if setup.hardening is not None:
        parts.append(hardening_folder_name(setup.hardening))
    if setup.rate_law is not None:
        parts.append(rate_law_folder_name(setup.rate_law))
    if setup.contact_size is not None:
        parts.append(f"h{setup.contact_size:g}")
    if setup.steps_per_contact != impact.DEFAULT_STEPS_PER_CONTACT:
        parts.append(f"steps{setup.steps_per_contact}")
    if getattr(ns, "kinematics", "small") != "small":
        parts.append(f"{ns.kinematics}-strain")
    return str(impact.DEFAULT_OUT / "_".join(parts)) if parts else str(impact.DEFAULT_OUT)


def compared_with(ns, hardening=None, rate_law=None) -> str:
    """The files the laws are compared with, as the output names them (the master table's constants
    are a perfectly plastic sphere's, said so for a ``hardening`` one; every law is rate-independent,
    said so for a sphere with a ``rate_law``)."""
    master = "master table's constants" + (" (of the perfectly plastic sphere)" if hardening is not None else "")
    return ("laws compared with" + (" (rate-independent: calibrated by the quasi-static press)" if rate_law is not None
                                    else "") + ": vz " + (f"constants of {ns.params}" if ns.params else master)
            + (f"; vz-table of {ns.table_params}" if ns.table_params else "")
            + (f"; LAMMPS mdr restitution of {ns.lammps_restitution}" if ns.lammps_restitution else "")
            + "; Thornton; Hertz")


def plan(ns, setup, velocities, variants, out) -> int:
    """--dry-run: the runs, their meshes and an estimate of the time; nothing is computed."""
    from pathlib import Path

    from calib.studies import impact, impact_convergence

    impact.check_reach(setup, velocities)
    tasks = impact.tasks_for(setup, velocities, variants) if not ns.convergence else \
        impact_convergence.tasks(setup, velocities[0])
    runs = impact.planned_runs(tasks, Path(out) / "cases")
    total = sum(r["estimate_s"] for r in runs if not r["finished"])
    summary = {"out": out, "runs": runs, "estimated_total_s": total,
               "compared_with": {"params": ns.params, "table_params": ns.table_params,
                                 "lammps_restitution": ns.lammps_restitution}}
    lines = [f"{len(runs)} FE impact(s) of E = {setup.material.E:.4g} Pa, nu = {setup.material.nu:g}, sigma_Y = "
             f"{setup.material.sigma_y:.4g} Pa, rho = {setup.material.rho:g} kg/m^3, R = {setup.radius:g} m"
             + ("" if setup.hardening is None else f", hardening {setup.hardening.record()['flow_curve']}")
             + ("" if setup.rate_law is None else f", rate law {setup.rate_law.record()['rate_law']}")
             + ("" if ns.kinematics == "small" else ", finite strain") + f"; outputs: {out}",
             f"{'v_in [m/s]':>11} {'variant':<16} {'contact el.':>11} {'dofs':>8} {'steps':>6} {'est. s':>7} finished"]
    lines += [f"{r['v_in']:>11.4g} {r['variant']:<16} {r['contact_size']:>11.3g} ~{r['dofs_estimate']:>7} "
              f"{r['steps_estimate']:>6} {r['estimate_s']:>7.0f} {'yes' if r['finished'] else 'no'}" for r in runs]
    lines.append(f"estimated total: {total:.0f} s on one process ({impact.SECONDS_PER_STEP_AT_13K_DOFS} s per elastoplastic "
                 f"time step at 13k dofs, linear in dofs; elastic runs are faster)")
    lines.append(compared_with(ns, setup.hardening, setup.rate_law))
    print_summary(ns, summary, lines)
    return 0


def drop_lines(drops, records, out) -> list[str]:
    """--drops: each test against the FE in OUT/drops.csv; the summary as lines."""
    from calib import output
    from calib.studies import impact_drops

    rows = impact_drops.compare(impact_drops.read(drops), records)
    path = impact_drops.write_comparison(out / "drops.csv", rows, output.stamp(0.0, drop_tests=str(drops)))
    s = impact_drops.summary(rows)
    extra = "".join(f", {key.replace('_ratio_mean', '')} test/FE - 1 = {s[key]:+.2%} (mean)"
                    for key in ("P_max_ratio_mean", "contact_time_ratio_mean") if key in s)
    lines = [f"drop tests {drops}: {s['tests']} tests, e_test - e_FE = {s['e_change_mean']:+.4f} (mean), "
             f"{s['e_change_rms']:.4f} (rms){extra}; per test: {path}"]
    if s["interpolated"]:
        lines.append(f"{s['interpolated']} of the {s['tests']} tests against the FE interpolated: {s['interpolation']}")
    return lines


def run(ns) -> int:
    from pathlib import Path

    from calib import output
    from calib.commands.progress import progress_reporter
    from calib.studies import impact, impact_convergence

    if ns.repeat is not None or ns.unload_params is not None:
        return run_repeat(ns)
    setup, velocities, workers = options(ns)
    if hasattr(setup, "counter"):
        return run_pair(ns, setup, velocities, workers)
    variants = ("fine",) if ns.no_error_estimate else impact.VARIANTS
    out = ns.out or default_out(ns, setup)
    refuse_output_over_input(ns, {"out": out})        # the default folder too: no file it writes is an input
    if ns.dry_run:
        return plan(ns, setup, velocities, variants, out)
    with output.one_writer(out), progress_reporter(ns.quiet) as progress:
        if ns.convergence:
            summary = impact_convergence.run(setup, velocities[0], Path(out), workers=workers, progress=progress,
                                             plots=not ns.no_plots)
            print_summary(ns, summary, impact_convergence.lines(summary))
            return 0
        records = impact.study(setup, velocities, Path(out), workers=workers, progress=progress, variants=variants,
                               params_file=ns.params, table_file=ns.table_params, mdr_file=ns.lammps_restitution,
                               plots=not ns.no_plots, quasi_static=not ns.no_quasi_static)
    lines = [f"{'v_in [m/s]':>10} {'v/v_Y':>7} {'e':>7} {'vz e':>7} {'P_max [N]':>10} {'vz P_max':>9} "
             f"{'t_c [ms]':>8} {'vz t_c':>7} {'dent [m]':>9} {'vibr.':>8} {'balance':>9} {'err e':>7} {'qs e':>7}"]
    for r in records:
        vz = r["models"].get("vz", r["models"]["hertz"])
        error = r["e_rel_error_estimate"]
        lines.append(f"{r['v_in']:>10.4g} {r['v_in_over_v_Y']:>7.3g} {r['e']:>7.4f} {vz['e']:>7.4f} {r['P_max']:>10.4g} "
                     f"{vz['P_max']:>9.4g} {r['contact_time'] * 1e3:>8.4f} {vz['contact_time'] * 1e3:>7.4f} "
                     f"{r['dent']:>9.3g} {r['vibration_fraction']:>8.2g} {r['balance_residual_fraction']:>9.2g} "
                     + (f"{error:>7.2%}" if error is not None else f"{'-':>7}")
                     + (f" {r['quasi_static']['e']:>7.4f}" if "quasi_static" in r else f" {'-':>7}"))
    lines.append("vibr., balance: vibration energy and the energy balance's residual over the kinetic energy in;"
                 " err e: estimated discretisation error of e; qs e: the quasi-static FE path's at the same P_max")
    worst = impact.largest_vibration(records)
    lines.append(f"largest vibration energy left: {worst['largest_fraction']:.2g} of the kinetic energy in, at "
                 f"{worst['v_in_over_v_Y']:.3g} v_Y (returned to the rebound it would change e by "
                 f"{worst['e_change_if_returned']:.2g})")
    if ns.drops is not None:
        lines += drop_lines(ns.drops, records, Path(out))
    from calib.studies import impact_output

    limit = impact.quasi_static_limit(records)
    if limit:
        lines.append("dynamic over quasi-static FE at the same P_max: " + impact_output.quasi_static_words(limit))
    lines.append(compared_with(ns, setup.hardening, setup.rate_law))
    lines.append(f"results written to {out}")
    if setup.rate_law is not None:
        lines.insert(0, rate_law_line(setup.rate_law) + "; the quasi-static FE paths its rate-independent limit")
    if setup.hardening is not None:
        lines.insert(0, hardening_line(setup.hardening))
    print_summary(ns, records, lines)
    return 0


def run_repeat(ns) -> int:
    """--repeat N: the FE's repeated impacts beside the laws' (calib.studies.impact_repeat)."""
    from pathlib import Path

    from calib import output
    from calib.commands.progress import progress_reporter
    from calib.studies import impact, impact_files, impact_repeat

    if ns.repeat is None:
        raise ValueError("--unload-params applies to --repeat only")
    repeat = integer("--repeat", ns.repeat, 1, 1, impact_repeat.MAX_REPEAT)
    for flag, given in (("--counter-E", counter_from_args(ns, material_from_args(ns)[0]) is not None),
                        ("--drops", ns.drops is not None), ("--convergence", ns.convergence),
                        ("--lammps-restitution", ns.lammps_restitution is not None), ("--dry-run", ns.dry_run)):
        if given:
            raise ValueError(f"{flag} is not for repeated impacts: do not combine it with --repeat")
    if ns.v_in is None:
        raise ValueError("--repeat needs --v-in: the impact velocities [m/s] (> 0)")
    setup, velocities, _ = options(ns)
    vz, source = impact_files.law_parameters(setup, ns.params)
    laws, sources = {"vz": vz}, {"vz": source}
    table = impact_files.table_parameters(setup, ns.table_params)
    if table is not None:
        laws["vz-table"], sources["vz-table"] = table, output.display_path(ns.table_params)
    if ns.unload_params is not None:
        laws["vz-unload"] = impact_repeat.unload_parameters(setup, ns.unload_params)
        sources["vz-unload"] = output.display_path(ns.unload_params)
    impact.check_reach(setup, velocities)
    out = ns.out or default_out(ns, setup)
    refuse_output_over_input(ns, {"out": out})
    with output.one_writer(out), progress_reporter(ns.quiet) as progress:
        records = impact_repeat.study(setup, velocities, repeat, Path(out), laws, sources, progress=progress)
    names = list(laws)
    lines = [f"{'v_in [m/s]':>10} {'v/v_Y':>6} {'repeat':>6} {'e FE':>8} " + " ".join(f"{'e ' + n:>12}" for n in names)
             + f" {'P_max [N]':>10} {'dent [m]':>10} {'W_p [J]':>9}"]
    lines += [f"{r['v_in']:>10.4g} {r['v_in_over_v_Y']:>6.3g} {r['repeat']:>6} {r['e']:>8.5f} "
              + " ".join(f"{r['e_' + n]:>12.5f}" for n in names)
              + f" {r['P_max']:>10.4g} {r['dent']:>10.4g} {r['plastic_work']:>9.3g}" for r in records]
    lines.append("e FE: the dynamic FE's, each impact from the last one's residual state (dent and residual stresses"
                 " carried over); e <law>: the law's impact of the same index, the contact's history carried over")
    lines.append("laws compared with: " + "; ".join(f"{n} of {s}" for n, s in sources.items()))
    lines.append(f"results written to {out}")
    print_summary(ns, records, lines)
    return 0


def run_pair(ns, setup, velocities, workers) -> int:
    """--counter-E: the sphere on a deformable counter-body (calib.studies.impact_pair)."""
    from pathlib import Path

    from calib import output
    from calib.commands.progress import progress_reporter
    from calib.studies import impact, impact_pair

    out = ns.out or default_out(ns, setup)
    refuse_output_over_input(ns, {"out": out})        # the default folder too: no file it writes is an input
    variants = impact_pair.FINE if ns.no_error_estimate else impact.VARIANTS
    impact_pair.check_pair(setup, velocities, over_v_Y=ns.v_in is None)   # what the two-body FE handles, before any mesh
    impact.check_reach(setup.contact_setup, velocities)
    if ns.dry_run:
        tasks = impact_pair.tasks_for(setup, velocities, variants)
        summary = {"out": out, "counter": setup.counter.describe(), "mass_star": setup.pair.mass_star, "runs": [
            {"v_in": t["v_in"], "variant": t["variant"], "contact_size": t["sphere_mesh"]["contact_size"],
             "steps_per_contact": t["steps_per_contact"],
             "finished": (Path(out) / "cases" / f"{t['key']}.json").is_file()} for t in tasks]}
        lines = [f"{len(tasks)} FE pair impact(s) of the sphere E = {setup.sphere.material.E:.4g} Pa, R = "
                 f"{setup.sphere.radius:g} m on the {setup.counter.label()} (the pair's m* = "
                 f"{setup.pair.mass_star:.4g} kg); outputs: {out}"]
        lines += [f"v_in = {r['v_in']:.4g} m/s ({r['variant']}), contact element {r['contact_size']:.3g} m, "
                  f"{r['steps_per_contact']} steps per contact, finished: {'yes' if r['finished'] else 'no'}"
                  for r in summary["runs"]]
        print_summary(ns, summary, lines)
        return 0
    with output.one_writer(out), progress_reporter(ns.quiet) as progress:
        records = impact_pair.study(setup, velocities, Path(out), workers=workers, progress=progress,
                                    variants=variants)
    lines = [f"{setup.counter.label()}; the pair's m* = {setup.pair.mass_star:.4g} kg",
             f"{'v_in [m/s]':>10} {'v/v_Y':>7} {'e':>8} {'P_max [N]':>10} {'Hertz':>10} {'t_c [ms]':>8} {'Hertz':>8} "
             f"{'left':>8} {'balance':>9} {'err e':>8} {'err P':>7} {'err t_c':>7} {'wall s':>7}"]
    for r in records:
        h = r["hertz"]
        lines.append(f"{r['v_in']:>10.4g} {r['v_in_over_v_Y']:>7.3g} {r['e']:>8.5f} {r['P_max']:>10.4g} {h['P_max']:>10.4g} "
                     f"{r['contact_time'] * 1e3:>8.4f} {h['contact_time'] * 1e3:>8.4f} {r['energy_left_fraction']:>8.2g} "
                     f"{r['balance_residual_fraction']:>9.2g} "
                     + "".join(f"{r[f'{q}_rel_error_estimate']:>{w}.2%} " if r[f"{q}_rel_error_estimate"] is not None
                               else f"{'-':>{w}} " for q, w in (("e", 8), ("P_max", 7), ("contact_time", 7)))
                     + f"{r['wall_time_s_all_runs']:>7.1f}")
    lines.append("v_in: relative velocity of approach; e: relative normal velocity of separation over v_in; Hertz: the"
                 " pair's elastic impact (E*, R*, m*); left: internal energy left in the bodies, balance: the energy"
                 " balance's residual, both over the kinetic energy in; err: estimated discretisation error (doubled contact element and doubled dt);"
                 " wall s: all runs of the velocity")
    lines.append(f"results written to {out}")
    print_summary(ns, records, lines)
    return 0

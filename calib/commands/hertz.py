"""``nfdcal hertz``: the Hertz-limit validation of the FE contact solver.

An elastic sphere pressed on a rigid flat (or, with --counter-E [--counter-nu --counter-R], on an
elastic counter-body: the two-body FE, Hertz with the pair's E* and R*) must reproduce Hertz's contact radius
a = (3 P R / (4 E*))^(1/3), approach alpha = a^2 / R and peak pressure p0 = 3 P / (2 pi a^2),
with E* = E / (1 - nu^2) (nfdmodel/README.md, Hertz contact). Default: the reference sphere
(R = 0.1 m, E = 70 GPa, nu = 0.3), force-controlled from 1 N to 1500 N on the default mesh;
writes results/hertz/ (with a counter-body a folder of its own below it, named by the sphere and the
counter-body as calibrate names its folder; hertz.json, hertz_steps.csv, pressure_profile.csv, contact_radius.png,
approach.png, peak_pressure.png, pressure_profile.png). The material flags are those of every
command (--R --E --nu; --sigma-y and --rho are accepted and unused: the run is elastic).
``--ladder`` runs the mesh ladder instead (mesh_ladder.csv, mesh_ladder.png). With a counter-body, one warning
line on stderr where the rigid-flat law with the pair's E*, R* is measured to miss the pair by more than 2 % in e
once it yields (calib.fit.substitution), naming the pair calibration.
Prints the errors at the top load against Hertz (on a terminal a progress line on stderr meanwhile, none
with ``--quiet``); ``--json`` prints the summary object instead
(its ``top_load`` entry: P, alpha, contact_radius, contact_radius_hertz, contact_radius_rel_error,
peak_pressure_rel_error, alpha_rel_error, wall_time_s).
"""
from __future__ import annotations

from pathlib import Path

from calib.commands.common import (add_counter_arguments, add_material_arguments, add_summary_arguments,
                                   counter_folder_name, counter_from_args, material_folder_name, material_from_args,
                                   number, print_summary)
from nfdmodel import reference_case

DEFAULT_OUT = "results/hertz"
P_MIN = 1.0                          # first load [N]
P_MAX = max(reference_case.PEAKS)    # the reference case's largest peak [N]


def add_parser(subparsers):
    p = subparsers.add_parser("hertz", help="validate the FE contact solver against Hertz",
                              description=__doc__.splitlines()[0])
    p.add_argument("--P-min", dest="P_min", default=None, help=f"first load [N] (> 0, default {P_MIN:g})")
    p.add_argument("--P-max", dest="P_max", default=None, help=f"top load [N] (> P_min, default {P_MAX:g})")
    p.add_argument("--steps", type=int, default=25, help="number of loads, geometric (2 .. 1000, default 25)")
    add_material_arguments(p)
    add_counter_arguments(p, density=False)
    p.add_argument("--contact-size", dest="contact_size", default=None,
                   help="element size at the contact [m] (> 0; default mesh: 4e-5 for R = 0.1)")
    p.add_argument("--ladder", action="store_true",
                   help="run the mesh ladder (contact sizes 1.6e-4 ... 1e-5 m) instead")
    p.add_argument("--out", default=None, help=f"output folder (default {DEFAULT_OUT}; with a counter-body a folder of"
                                               f" its own below it, named by the sphere and the counter-body)")
    p.add_argument("--dry-run", action="store_true",
                   help="print the plan (mesh, dofs, steps, estimated time, output folder) and exit")
    add_summary_arguments(p)
    p.set_defaults(run=run)
    return p


def run(ns) -> int:
    # everything is checked before any FE work
    P_min = number("--P-min", ns.P_min, P_MIN, low=0.0, unit="N")
    P_max = number("--P-max", ns.P_max, P_MAX, low=0.0, unit="N")
    if not P_max > P_min:
        raise ValueError(f"--P-max must be > --P-min = {P_min:g} N, got {P_max:g}")
    if not 2 <= ns.steps <= 1000:
        raise ValueError(f"--steps must be in [2, 1000], got {ns.steps}")
    material, radius = material_from_args(ns)
    counter = counter_from_args(ns, material)
    contact_size = number("--contact-size", ns.contact_size, None, low=0.0, unit="m")
    if counter is not None and ns.ladder:
        raise ValueError("--ladder runs the rigid flat's mesh ladder: do not combine it with the --counter-* flags")
    if counter is not None:             # what the two-body FE handles, before any mesh (dry run too)
        from calib.fit.counter import check_counter, check_counter_covers, hertz_contact
        from calib.studies.hertz import hertz_spec

        check_counter(material, radius, counter, hertz_contact((P_min, P_max)), f"loads {P_min:g} .. {P_max:g} N")
        check_counter_covers(counter, hertz_spec(material, radius, P_max, contact_size, counter=counter))
    if counter is not None:             # an unlike pair: where the rigid-flat law would miss it, say so
        from calib.fit.substitution import warn_substitution

        warn_substitution(material, radius, counter)

    from pathlib import Path

    from calib.studies.hertz import write_hertz_results, write_ladder_results

    out = Path(ns.out) if ns.out else default_out(material, radius, counter)
    if ns.dry_run:
        from calib.scenes.plan import format_stages, hertz_stage, stages_summary
        from calib.studies.hertz import LADDER_CONTACT_SIZES, hertz_spec

        sizes = [h * radius / reference_case.R for h in LADDER_CONTACT_SIZES] if ns.ladder else [contact_size]
        stages = [hertz_stage(hertz_spec(material, radius, P_max, h, counter=counter), "sphere", (P_min, P_max),
                              ns.steps) for h in sizes]
        print_summary(ns, stages_summary(stages, out), [f"outputs: {out}"] + format_stages(stages))
        return 0
    from calib.commands.progress import progress_reporter

    with progress_reporter(ns.quiet) as progress:
        progress(f"hertz: {'mesh ladder' if ns.ladder else 'elastic FE'}, {ns.steps} loads {P_min:g} .. {P_max:g} N")
        if ns.ladder:
            summary = write_ladder_results(out, radius=radius, material=material,
                                           P_min=P_min, P_max=P_max, steps=ns.steps)
        else:
            from calib.fe import StepNotConverged

            try:
                summary = write_hertz_results(out, radius=radius, material=material, P_min=P_min, P_max=P_max,
                                              steps=ns.steps, contact_size=contact_size, counter=counter)
            except StepNotConverged as exc:     # one line, exit 2: what failed and what to change
                raise ValueError(f"--P-min, --P-max: the FE did not converge ({exc}); the run's checks passed, so "
                                 f"this load range or mesh is beyond what it was tested on: try other loads or "
                                 f"--contact-size") from None
    print_summary(ns, summary, ladder_lines(summary, out) if ns.ladder else hertz_lines(summary, out))
    return 0


def default_out(material, radius: float, counter) -> Path:
    """results/hertz, the rigid-flat validation; with a counter-body a folder of its own below it,
    named as calibrate names it (sphere and counter-body: E<E>_nu<nu>_sy<sigma_y>_R<R>_on_E<E2>_...)."""
    if counter is None:
        return Path(DEFAULT_OUT)
    return Path(DEFAULT_OUT) / f"{material_folder_name(material, radius)}_{counter_folder_name(counter)}"


def hertz_lines(summary: dict, out) -> list[str]:
    """The readable summary: the case, then FE against Hertz at the top load."""
    case, top, mesh = summary["case"], summary["top_load"], summary["stamp"]["mesh"]
    counter = case.get("counter_body")
    on = ""
    if counter is not None:
        shape = "flat" if counter["R"] is None else f"sphere R = {counter['R']:g} m"
        on = (f" on a {shape} of E = {counter['E']:.4g} Pa, nu = {counter['nu']:g} (E* = {case['E_star']:.4g} Pa,"
              f" R* = {case['R_star']:.4g} m)")
    return [f"Hertz check: R = {case['radius']:g} m, E = {case['E']:.4g} Pa, nu = {case['nu']:g}{on}; "
            f"{case['steps']} loads {case['P_min']:g} .. {case['P_max']:g} N; mesh: contact element "
            f"{mesh['contact_size']:.3g} m, {mesh['n_dofs']} dofs; {summary['stamp']['wall_time_s']:.1f} s",
            f"at P = {top['P']:.4g} N, FE against Hertz:",
            f"  contact radius {top['contact_radius']:.5g} m ({100 * top['contact_radius_rel_error']:+.3f} %)",
            f"  peak pressure  {top['peak_pressure']:.5g} Pa ({100 * top['peak_pressure_rel_error']:+.3f} %)",
            f"  approach       {top['alpha']:.5g} m ({100 * top['alpha_rel_error']:+.3f} %; the finite"
            f" hemisphere is stiffer than Hertz's half-space)",
            f"results written to {out}"]


def ladder_lines(summary: dict, out) -> list[str]:
    """The readable summary of the mesh ladder: one line per mesh."""
    lines = [f"{'contact size m':>15} {'dofs':>7} {'wall s':>7} {'a error %':>10} {'p0 error %':>11}"]
    for r in summary["rows"]:
        lines.append(f"{r['contact_size']:15.3g} {r['n_dofs']:7d} {r['wall_time_s']:7.1f} "
                     f"{100 * r['contact_radius_pressure_rel_error']:+10.4f} {100 * r['peak_pressure_rel_error']:+11.4f}")
    lines.append(f"default mesh: contact size {summary['default_choice']['contact_size']:.3g} m; "
                 f"results written to {out}")
    return lines

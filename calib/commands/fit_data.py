"""``nfdcal fit-data``: the vz law's sigma_Y (and parameters) from measurements, without an FE model.

    nfdcal fit-data --impacts drops.csv --E 70e9 --nu 0.3 --R 0.1 --rho 2700 [--noise 0.01] [--json]
    nfdcal fit-data --force-approach press.csv --E ... --law vz --sigma-y 100e6 --free --plot fit.png

Drop tests (v_in [m/s], e [-], optional P_max [N], contact_time [s], dent [m], radius [m]: the imprint's, taken
as the contact radius at the peak, calib.fit.measured.imprint) and/or quasi-static
force-approach curves (approach [m], force [N], optional test) of a sphere on a rigid flat are
fitted through the runtime law (calib.fit.measured states the equations).

The default law (``--law vz-table``): the constrained model on the load-dependent law of the vz
master table (calib.fit.measured.table_law: a_p/a_Y and C_R against P/P_Y from FE paths over the
whole window), sigma_Y alone, its standard error and 95 % interval including the law's model-form
error measured against off-grid FE; --noise states the data's relative noise, against which
(with the model-form level) the residual is judged. A fit whose residuals lie far above the
law's measured level and the stated noise (none stated: the largest plausible scatter), or whose
95 % interval is wider than sigma_Y, is no fit: refused in one line (exit 2, nothing written)
with the likely cause (calib.fit.measured.table_refusal: a column in other units, a wrong
specimen). Drop tests whose loads P/P_Y at the fitted sigma_Y lie outside the window the table
measured are left out of the default fit and named; an e up to 1.001 (an FE's round-off about an
elastic impact) is kept as measured. When the law is not given and the data lie outside the vz
master table (nu, the fitted E/sigma_Y, fewer than two drop tests or a force curve's peak inside
the window), fit-data refuses with one line (exit 2) naming which and ``--law vz``: the two-constant law is biased against the FE by +13 % (drop tests) to +35 %
(force curves) on sigma_Y with intervals that miss the truth (results/fit_data/fe_benchmark),
so it is used only when asked for, never as a silent substitute. Given ``--law vz-table``
explicitly, data reaching beyond the table's window are fitted and the summary says so.

``--law vz``: the two-constant law: the constrained model fits sigma_Y alone with Ca_hat, Kc_hat
from the master table at (nu, E / sigma_Y); --free fits Ca_hat, Kc_hat (and sigma_Y when the
data determine it). Both are fitted and compared by AICc, in words. --sigma-y is the
constrained fit's start and the value the free fit holds when the data do not determine
sigma_Y. --free, --table, --plot and --force apply to this law only. --params-out and --plot
(a PNG) never replace an existing file unless --overwrite is given. Bad data: one line naming
the file, the row and the column (exit 2). Data the law cannot fit are refused (exit 2,
nothing written) with their likely cause (calib.fit.measured.diagnosis: a column in other
units, swapped columns, a wrong material): a fit at the edge of the model's range, data all
below first yield, and a residual far above any plausible scatter (calib.fit.measured.scatter);
--force reports and writes such a fit, flagged; likewise a fit whose 95 % interval of sigma_Y
is wider than its value. Repeated v_in are evaluated once and many
distinct ones interpolated (calib.fit.measured.specimen), so 100k rows fit in seconds.

``--rate-law cowper-symonds --cs-q q`` or ``--rate-law johnson-cook [--jc-reference-rate RATE]``: sigma_Y and
the rate law's free constant (Cowper-Symonds' D, Johnson-Cook's C; --cs-D or --jc-C is the fit's start)
fitted together to drop tests at several speeds on the rate-aware vz-table law
(calib.fit.measured.rate_fit: each test's strain rate eps_dot = v_in / (c a_ref), sigma_Y R(eps_dot)),
each with its 95 % interval (statistical, the table's model-form error, the rate-aware law's c). When
the speeds span too little (R nearly constant across the tests) the data determine only sigma_Y R at
the tests' mean strain rate: fit-data refuses in one line (exit 2) naming that combination, its value
and standard error (and, when the residuals exceed the law's measured level, that the rate-aware law
does not describe the data to it). Drop tests only (a force curve carries no strain rate; no dent column); --params-out
writes the vz-table law with the fitted rate law ("rate_law", nfdmodel/parameter_file.py). ``--rate-form relaxing``
fits the relaxing rate-aware law (nfdmodel.rate_relaxing) and writes its form. ``--sigma-y S --hold-sigma-y``
holds sigma_Y at a quasi-static value (a tensile test's) and fits the rate constant alone; ``--sigma-y-uncertainty
REL`` (the held value's relative standard uncertainty) widens the constant's interval by its response.

``--counter-E E2 [--counter-nu NU2] [--counter-R R2 --counter-rho RHO2]``: the tests hit an elastic flat (a floor
of that material) or sphere, not a rigid flat: sigma_Y is fitted on the pair law of the pair table
(calib.fit.pair_table: the vz master table's law mapped by the two-body FE's departure from the rigid flat's) on
the pair's E*, R*, m*, within the pair table's nodes (nu, E/sigma_Y, E1'/E2'); its model-form error adds the pair
table's, measured by this fit on the two-body FE of held-out pairs (calib.fit.pair_table_build). Drop tests on
e and P_max, or force-approach curves; refused in one line (exit 2): a yielding counter-body, --pair, --law vz,
--rate-law, and dent, radius or contact_time columns (not measured on pairs).

``--hardening-modulus H`` [Pa]: the sphere hardens linearly, sigma_y = sigma_Y + H eps_p, with H known (a tensile
test's slope against the plastic strain): sigma_Y is fitted on the vz master table's law with the hardening sheet's
share at H/E (calib.fit.vz_hardening; its window ends at the sheet's top, the finite strain's reach).
Refused in one line (exit 2): --flow-curve, --law vz, --rate-law and --counter-E with it.

``--fit-hardening``: sigma_Y and H fitted together on the same law (calib.fit.measured.hardening_fit), each with its
95 % interval (statistical and the measured model-form terms); drop tests whose contacts pass about 0.05 R (the
finite strain's reach of the sheet) determine H, smaller ones only the flow stress at a plastic strain of a few
1e-3: then refused in one line (exit 2) naming sigma_Y + H eps_*, its value and standard error
(calib.commands.fit_data_hardening). Refused with it: --hardening-modulus, --flow-curve, --rate-law, --counter-E,
--pair, --law vz.
"""
from __future__ import annotations

import time

from calib.commands.common import (MATERIAL_RANGES, add_counter_arguments, add_hardening_arguments,
                                   add_rate_form_argument, add_rate_law_arguments, counter_from_args,
                                   add_summary_arguments, flag_name, hardening_given, number, print_summary,
                                   rate_form_from_args, rate_law_given, refuse_flow_curve)

SPECIMEN_FLAGS = ("E", "nu", "R", "rho")
# what ends a default fit's refusal outside the vz master table (module doc)
OUTSIDE_ADVICE = ("--law vz fits the two-constant law (sigma_Y biased against the FE: results/fit_data/fe_benchmark)")

# e alone fixes v_in / v_Y (v_Y ~ sigma_Y^(5/2)): a v_in slip is a sigma_Y slip, invisible in the residual
E_ONLY = ("e alone fixes only v_in / v_Y (v_Y ~ sigma_Y^(5/2)): v_in in other units moves sigma_Y by that factor^(2/5) "
          "(cm/s: x6.3, mm/s: x15.8) with no sign in the residual; a P_max or contact_time column checks the units")


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser("fit-data", help="Ca, Kc (and sigma_Y) from drop tests or force-approach curves; --rate-law: sigma_Y and "
                                        "a rate constant from drop tests at several speeds",
                                   description=__doc__.split("\n\n")[0])
    parser.add_argument("--impacts", default=None, metavar="CSV",
                        help="drop tests: columns v_in [m/s], e [-]; optional P_max [N], contact_time [s], dent [m] "
                             "(the residual indentation depth), radius [m] (the imprint's radius, taken as the contact "
                             "radius at the peak); dent and radius are fitted on the vz master table's vz-unload law")
    parser.add_argument("--force-approach", dest="force_approach", default=None, metavar="CSV",
                        help="quasi-static curves: columns approach [m], force [N]; optional test (a label "
                             "per virgin specimen)")
    for key, text in (("E", "Young's modulus [Pa]"), ("nu", "Poisson's ratio (0 <= nu < 0.5)"),
                      ("R", "sphere radius [m]"), ("rho", "density [kg/m^3]")):
        parser.add_argument(flag_name(key), dest=key, default=None, help=f"{text} (required)")
    parser.add_argument("--sigma-y", dest="sigma_y", default=None,
                        help="yield stress [Pa]: the constrained fit's start, the free fit's value when the data "
                             "do not determine it (default: estimated)")
    parser.add_argument("--law", default=None, choices=("vz-table", "vz"),
                        help="vz-table (default): the load-dependent law of the vz master table, sigma_Y fitted over "
                             "the data's whole window (data outside the table: refused, exit 2); vz: the two-constant "
                             "law of the master table (Ca_hat, Kc_hat)")
    parser.add_argument("--noise", default=None, metavar="REL",
                        help="the data's stated relative noise (e.g. 0.01), with the vz-table law")
    parser.add_argument("--vz-table", default=None, metavar="CSV",
                        help="vz master table CSV for the vz-table law (default: the shipped one)")
    parser.add_argument("--free", action="store_true",
                        help="with --law vz: use the free model (Ca_hat, Kc_hat fitted)")
    parser.add_argument("--pair", action="store_true",
                        help="the tests are head-on impacts (or presses) of two identical spheres, v_in their "
                             "relative speed (default: a sphere on a massive rigid flat)")
    parser.add_argument("--table", default=None, metavar="CSV",
                        help="with --law vz: the two-constant master table CSV (default: the shipped one)")
    parser.add_argument("--params-out", default=None, metavar="JSON",
                        help="write a parameter file (nfdmodel.load_parameters, nfdcal collide --params)")
    parser.add_argument("--plot", default=None, metavar="PNG",
                        help="draw the data against the fitted law (a PNG image: the name ends in .png)")
    parser.add_argument("--overwrite", action="store_true",
                        help="replace an existing --params-out or --plot file (refused otherwise)")
    parser.add_argument("--force", action="store_true",
                        help="report and write a fit whose residual is far above any plausible scatter (refused "
                             "otherwise), flagged as such in the summary and the parameter file")
    add_rate_law_arguments(parser, "fit sigma_Y with one rate constant free on the rate-aware vz-table law "
                                   "(drop tests at several speeds): cowper-symonds (D fitted, --cs-q given) or "
                                   "johnson-cook (C fitted, --jc-reference-rate given, default 1 /s)",
                           {"jc_C": "with --rate-law johnson-cook: the fitted C's start [-] (1e-4 to 1; default: a "
                                    "coarse scan)",
                            "cs_D": "with --rate-law cowper-symonds: the fitted D's start [1/s] (1e-3 to 1e12; "
                                    "default: a coarse scan)",
                            "cs_q": "Cowper-Symonds' exponent q [-] (0.5 to 20; required with --rate-law "
                                    "cowper-symonds: held while D is fitted)"})
    add_rate_form_argument(parser)
    parser.add_argument("--hold-sigma-y", action="store_true",
                        help="with --rate-law and --sigma-y: hold sigma_Y at --sigma-y (a quasi-static measurement, "
                             "such as a tensile test's) and fit the rate constant alone")
    parser.add_argument("--sigma-y-uncertainty", default=None, metavar="REL",
                        help="with --hold-sigma-y: the held sigma_Y's relative standard uncertainty (0 to 0.5, "
                             "default 0), carried into the rate constant's interval")
    add_hardening_arguments(parser)     # --hardening-modulus: the vz master table's hardening sheet
    parser.add_argument("--fit-hardening", action="store_true",
                        help="fit sigma_Y and the linear hardening's plastic modulus H together on the vz master "
                             "table's hardening sheet (drop tests over the finite strain's reach determine H; where "
                             "the data do not, refused naming the flow stress sigma_Y + H eps_* they determine)")
    add_counter_arguments(parser)       # the pair law of the pair table (module doc)
    parser.add_argument("--pair-table", default=None, metavar="CSV",
                        help="pair table CSV for --counter-E (default: the shipped one)")
    add_summary_arguments(parser, progress=False)
    parser.set_defaults(run=run, shipped=("table", "vz_table"))   # calib.commands.targets: the tables read


def specimen_from_args(ns):
    """The Specimen (E, nu, R, rho) and the --sigma-y value (None when not given) from the flags;
    every error names the flag and its range."""
    from calib.fit.measured.specimen import Specimen
    from nfdmodel.materials import check_radius
    from nfdmodel.validation import check_solid

    missing = [flag_name(k) for k in SPECIMEN_FLAGS if getattr(ns, k) is None]
    if missing:
        raise ValueError(f"missing {', '.join(missing)}: the specimen's material and size are needed (SI units)")
    values = {k: number(flag_name(k), getattr(ns, k), **MATERIAL_RANGES[k]) for k in SPECIMEN_FLAGS}
    check_solid("E", values["E"])
    check_solid("rho", values["rho"])
    check_radius("R", values["R"])
    sigma_y = number("--sigma-y", ns.sigma_y, None, **MATERIAL_RANGES["sigma_y"])
    if sigma_y is not None:
        check_solid("sigma_y", sigma_y)
    return Specimen(values["E"], values["nu"], values["R"], values["rho"], bool(ns.pair)), sigma_y


def hardening_record(sigma_y: float, H: float) -> dict:
    """The parameter file's "hardening" entry of the fitted sphere (calib.fe.flow_curve.LinearHardening.record)."""
    from calib.fe.flow_curve import LinearHardening

    return LinearHardening(sigma_y, H).record()


def known_hardening(ns, specimen) -> float:
    """H/E of ``--hardening-modulus H`` (0: no hardening flag, or H = 0), the linear hardening fitted with
    (module doc); one line naming the flag for what the hardening sheet does not hold (--flow-curve: run's
    refuse_flow_curve, before any input is read)."""
    if hardening_given(ns) is None:
        return 0.0
    H = number("--hardening-modulus", ns.hardening_modulus, low=0.0, low_inclusive=True, high=specimen.E,
               high_inclusive=True, unit="Pa (the plastic modulus, at most E)")
    if H == 0.0:
        return 0.0
    other = ("--law vz" if ns.law == "vz" else rate_law_given(ns) or
             ("--counter-E" if getattr(ns, "counter_E", None) is not None else None))
    if other is not None:
        raise ValueError(f"--hardening-modulus out of range with {other}: the hardening sheet is measured on the "
                         f"vz-table law of a sphere on a rigid flat, rate-independent")
    return H / specimen.E


def with_counter(ns, specimen):
    """The specimen on the counter-body of the --counter-* flags (module doc); one line naming the flag for what
    the pair table does not measure."""
    import dataclasses

    counter = counter_from_args(ns, specimen)
    if counter is None:
        if ns.pair_table is not None:
            raise ValueError("--pair-table needs --counter-E (the pair table maps the law onto a counter-body)")
        return specimen
    refused = [("--counter-sigma-y", counter.sigma_y is not None, "an elastic counter-body"),
               ("--pair", ns.pair, "a sphere on a counter-body, not two identical spheres"),
               ("--law", ns.law == "vz", "the vz-table law (--law vz-table)"),
               ("--rate-law", rate_law_given(ns) is not None, "a rate-independent law")]
    for flag, given, what in refused:
        if given:
            raise ValueError(f"{flag} out of range with --counter-E: fit-data on a counter-body takes {what}, the "
                             f"pair table's law")
    return dataclasses.replace(specimen, counter=counter, pair_table=ns.pair_table)


def refuse_unmeasured_columns(data, specimen) -> None:
    """On a counter-body: a dent, radius or contact_time column named in one line (the pair table measures the
    loading and e, not those)."""
    if specimen.counter is None or data.impacts is None:
        return
    for column in ("dent", "radius", "contact_time"):
        if getattr(data.impacts, column, None) is not None:
            raise ValueError(f"{data.impacts.path}: column '{column}' out of range with --counter-E: the pair table "
                             f"measures e, P_max and the loading force on a counter-body, not the {column}; give "
                             f"v_in, e and P_max")


def tested(specimen) -> str:
    """'sphere on flat', 'two identical spheres' or the counter-body's label."""
    if specimen.counter is not None:
        return f"sphere on {specimen.counter.label().removeprefix('counter-body: ')}"
    return "two identical spheres" if specimen.two_spheres else "sphere on flat"


def check_outputs(ns) -> None:
    """Before any work: each output path names a regular file (or nothing yet), an existing file only
    with --overwrite, --params-out and --plot differ (calib.commands.targets; the dispatcher has
    refused an output over an input and a plot name not ending in .png)."""
    from calib.commands.targets import refuse_existing

    refuse_existing(ns, ("params_out", "plot"))


def summary_of(choice, data, specimen, files) -> dict:
    """The --json object (SI units; calib.fit.measured defines every figure)."""
    result = choice.result
    values, errors = result.values, result.standard_errors
    out = {}
    for key in ("sigma_y", "Ca", "Kc", "Ca_hat", "Kc_hat"):
        out[key] = values[key]
        out[f"{key}_se"] = errors[key]
    pair = result.params.pair
    fits = {}
    for name, fit in (("constrained", choice.constrained), ("free", choice.free)):
        if fit is not None:
            fits[name] = {"fitted": list(fit.spec.free), "values": fit.values, "standard_errors": fit.standard_errors,
                          "rms_residual": fit.rms_residual, "note": fit.note}
    out.update({
        "P_Y": pair.P_Y, "a_Y": pair.a_Y, "delta_Y": pair.delta_Y, "v_Y": pair.v_Y,
        "model": {"chosen": choice.used, "fitted": list(result.spec.free), "why": choice.why,
                  "preferred_by_aicc": choice.preferred, "note": result.note,
                  **({"free_model_error": choice.free_error} if choice.free_error else {})},
        "aic": {name: fit.aic for name, fit in (("constrained", choice.constrained), ("free", choice.free))
                if fit is not None},
        "aicc": {name: fit.aicc for name, fit in (("constrained", choice.constrained), ("free", choice.free))
                 if fit is not None},
        "correlation": {"parameters": list(result.spec.free), "matrix": result.correlation.tolist()},
        "identifiability": result.identifiability,
        "window": result.params.window.record(),
        "n_points": result.n_points,
        "rms_residual": result.rms_residual,
        "rms_residual_by_group": {k: float((v @ v / v.size) ** 0.5) for k, v in result.residuals.items()},
        "scatter": result.scatter.record(),
        "residuals": {k: v.tolist() for k, v in result.residuals.items()},
        "fits": fits,
        "files": files,
        "specimen": {"E": specimen.E, "nu": specimen.nu, "R": specimen.R, "rho": specimen.rho,
                     "tested": tested(specimen)},
        "units": {"sigma_y": "Pa", "Ca": "m/N", "Kc": "1/N", "P_Y": "N", "a_Y": "m", "delta_Y": "m", "v_Y": "m/s",
                  "residuals": "relative: (law - measured) / measured; force: / max(|P|, 0.05 x smallest peak)"},
    })
    return out


def _percent(value, error, noise_free: str = "") -> str:
    if error is None:
        return "held"
    return f"+- {100 * error / value:.2g} %" + (f", {noise_free}" if noise_free else "")


def fit_or_cause(data, specimen, table, model: str, sigma_y, force: bool):
    """Both models fitted (calib.fit.measured.models.fit_measurements) and the warning to print
    with --force (else ""). Data the law cannot fit: a ValueError naming the likely cause
    (calib.fit.measured.diagnosis), unless ``force`` accepts a fit far above plausible scatter."""
    from calib.fit.measured import diagnosis
    from calib.fit.measured.interval import Z95
    from calib.fit.measured.models import fit_measurements
    from calib.fit.measured.regression import DataMismatch

    try:
        choice = fit_measurements(data, specimen, table, model, sigma_y)
    except DataMismatch as exc:
        raise ValueError(f"{exc}; {diagnosis.likely_cause(data, specimen, table, model, sigma_y)}") from None
    scatter = choice.result.scatter
    warning = ""
    if not scatter.plausible:
        warning = diagnosis.implausible_fit_message(scatter, choice.used,
                                                    diagnosis.likely_cause(data, specimen, table, model, sigma_y))
        if not force:
            raise ValueError(f"{warning}; nothing written (--force reports and writes this fit anyway)")
    value, se = choice.result.values["sigma_y"], choice.result.standard_errors.get("sigma_y")
    if "sigma_y" in choice.result.spec.free and se is not None and 2 * Z95 * se > value:
        # an interval wider than the value is no fit
        wide = (f"the data do not determine sigma_Y: {value:.4g} Pa +- {100 * se / value:.2g} % (standard error), its "
                f"95 % interval wider than the value; more tests over a wider range of loads (drop tests from 2 to "
                f"100 v_Y, or a force-approach curve) would")
        if not force:
            raise ValueError(f"{wide}; nothing written (--force reports and writes this fit anyway)")
        warning = f"{warning}; {wide}" if warning else wide
    return choice, warning


def run(ns) -> int:
    import sys

    from calib import output
    from calib.fit.master_table import MasterTable
    from calib.fit.measured import data as measured_data
    from calib.fit.measured import imprint

    started = time.perf_counter()
    refuse_flow_curve(ns, "fit-data")
    if ns.impacts is None and ns.force_approach is None:
        raise ValueError("give --impacts CSV (drop tests) or --force-approach CSV (or both)")
    specimen, sigma_y = specimen_from_args(ns)
    if ns.fit_hardening:
        from calib.commands.fit_data_hardening import run_hardening_fit

        check_outputs(ns)
        return run_hardening_fit(ns, specimen, started)
    H_over_E = known_hardening(ns, specimen)
    specimen = with_counter(ns, specimen)
    check_outputs(ns)
    rate_form_from_args(ns)             # --rate-form without --rate-law: one line
    if ns.sigma_y_uncertainty is not None and not ns.hold_sigma_y:
        raise ValueError("--sigma-y-uncertainty is the held sigma_Y's uncertainty: give --hold-sigma-y with it")
    if ns.hold_sigma_y and rate_law_given(ns) is None:
        raise ValueError("--hold-sigma-y applies to --rate-law (sigma_Y held, the rate constant fitted); without it "
                         "give --sigma-y alone")
    if rate_law_given(ns) is not None:
        from calib.commands.fit_data_rate import run_rate_law

        return run_rate_law(ns, specimen, sigma_y, started)
    if ns.law != "vz":
        return run_table_law(ns, specimen, sigma_y, started, H_over_E)
    if ns.noise is not None or ns.vz_table is not None:
        raise ValueError("--noise and --vz-table apply to the vz-table law (the default), not to --law vz")
    table = MasterTable.load(ns.table)
    data = measured_data.Measurements(
        impacts=measured_data.read_impacts(ns.impacts) if ns.impacts else None,
        forces=measured_data.read_force_approach(ns.force_approach) if ns.force_approach else None)
    if data.impacts is not None and data.impacts.dent is not None:
        raise ValueError(f"{ns.impacts}: column 'dent' is fitted on the vz master table's vz-unload law (the default "
                         f"law, --law vz-table), not on --law vz (the two-constant law's dent is not measured)")
    imprint.refuse_on_vz(data.impacts, ns.impacts)
    choice, warning = fit_or_cause(data, specimen, table, "free" if ns.free else "constrained", sigma_y, ns.force)
    if warning:
        print(f"nfdcal fit-data: warning: {warning}; reported and written as --force asks", file=sys.stderr)
    result = choice.result
    summary = summary_of(choice, data, specimen, data.files)
    if warning:
        summary["implausible"] = warning
    if ns.params_out:
        from calib.report.parameter_file import write_parameter_file

        fit = {"source": "measurements", "files": data.files, "model": summary["model"],
               "standard_errors": {k: summary[f"{k}_se"] for k in ("sigma_y", "Ca", "Kc", "Ca_hat", "Kc_hat")},
               "correlation": summary["correlation"], "aicc": summary["aicc"], "n_points": result.n_points,
               "rms_residual": result.rms_residual, "scatter": summary["scatter"],
               **({"implausible": warning} if warning else {})}
        # a parameter file describes the sphere on a rigid flat: from two-sphere tests, the same material
        write_parameter_file(ns.params_out, specimen.sphere_flat_params(result.params), specimen.R,
                             specimen.material(result.values["sigma_y"]),
                             {**fit, "tested": tested(specimen)},
                             output.stamp(time.perf_counter() - started))
        summary["params_out"] = ns.params_out
    if ns.plot:
        from calib.report.measurements import plot_fit

        plot_fit(ns.plot, choice, data, specimen, table)
        summary["plot"] = ns.plot
    values, errors = result.values, result.standard_errors
    counts = ", ".join(f"{n} {k} value(s)" for k, n in data.group_sizes().items())
    window = result.params.window
    scatter = result.scatter
    noise_free = "" if scatter.estimable else (
        "the master table's uncertainty only" if choice.used == "constrained" else "numerical precision only")
    summary["law"] = "vz"
    lines = [
        "law: vz (two constants Ca_hat, Kc_hat; --law vz)",
        f"{choice.used} model fitted to {counts} ({', '.join(data.files)}): {', '.join(result.spec.free)}",
        *([f"WARNING: {warning}"] if warning else []),
        *([] if scatter.estimable else [
            f"scatter: not estimable: the law reproduces these data to {result.rms_residual:.1g} (rms relative "
            f"residual), as noise-free (synthetic) or identical values do; the standard errors below are then the "
            f"law's numerical precision"
            + (" and the master table's uncertainty" if choice.used == "constrained" else "")
            + ", not a measurement's precision"]),
        *([] if scatter.within_repeats else [f"lack of fit: {scatter.describe_lack_of_fit()}"]),
        f"sigma_Y = {values['sigma_y']:.4g} Pa ({_percent(values['sigma_y'], errors['sigma_y'], noise_free)})",
        f"Ca = {values['Ca']:.4g} m/N ({_percent(values['Ca'], errors['Ca'], noise_free)}), Kc = {values['Kc']:.4g} "
        f"1/N ({_percent(values['Kc'], errors['Kc'], noise_free)})",
        f"Ca_hat = {values['Ca_hat']:.4g} ({_percent(values['Ca_hat'], errors['Ca_hat'], noise_free)}), Kc_hat = "
        f"{values['Kc_hat']:.4g} ({_percent(values['Kc_hat'], errors['Kc_hat'], noise_free)})"
        + (" (from the master table)" if choice.used == "constrained" else ""),
        f"first yield: P_Y = {summary['P_Y']:.4g} N, a_Y = {summary['a_Y']:.4g} m, v_Y = {summary['v_Y']:.4g} m/s",
        f"model: {choice.why}",
        *([f"note: {result.note}"] if result.note else []),
        *[("identifiability: " if k == 0 else "  ") + part
          for k, part in enumerate(result.identifiability["summary"].split("; "))],
        f"window: {window.describe()} (the data's range; beyond it the constants are an extrapolation)",
        *([f"window beyond the FE's reach: {', '.join(window.beyond_fe_reach())}: no FE calibration vouches for the "
           f"law there, the master table's constants included"] if window.beyond_fe_reach() else []),
        f"rms residual: {100 * result.rms_residual:.3g} % ("
        + ", ".join(f"{k} {100 * v:.3g} %" for k, v in summary["rms_residual_by_group"].items()) + ")",
    ] + ([f"parameter file written to {ns.params_out}"] if ns.params_out else []) \
      + ([f"plot written to {ns.plot}"] if ns.plot else [])
    print_summary(ns, summary, lines)
    return 0


def run_table_law(ns, specimen, sigma_y, started: float, H_over_E: float = 0.0) -> int:
    """The vz-table law (``--law vz-table``, the default when --law is not given): sigma_Y on the vz
    master table's law (calib.fit.measured.table_law), with ``H_over_E`` > 0 the hardening sheet's
    (calib.fit.vz_hardening). By default, data outside the table are refused naming ``--law vz`` (module doc)."""
    from calib import output
    from calib.fit.measured import data as measured_data
    from calib.fit.measured import imprint, table_refusal
    from calib.fit.measured.data import E_ROUND_OFF
    from calib.fit.measured.table_law import pair_table_of
    from calib.fit.vz_master_table import VZMasterTable

    default = ns.law is None
    for flag, given in (("--free", ns.free), ("--plot", ns.plot), ("--force", ns.force), ("--table", ns.table)):
        if given:
            raise ValueError(f"{flag} applies to --law vz (the two-constant law), not to the vz-table law"
                             + (" (the default): give --law vz" if default else ""))
    noise = number("--noise", ns.noise, None, low=0.0, high=0.5, high_inclusive=True)
    table = VZMasterTable.load(ns.vz_table)
    sheet = None
    if H_over_E:
        from calib.fit.vz_hardening import HardenedMasterTable, HardeningSheet

        sheet = HardeningSheet.load()
        sheet.check(H_over_E)
        table = HardenedMasterTable(table, sheet, H_over_E)
    data = measured_data.Measurements(
        impacts=measured_data.read_impacts(ns.impacts) if ns.impacts else None,
        forces=measured_data.read_force_approach(ns.force_approach) if ns.force_approach else None)
    imprint.check_radius(data.impacts, specimen.R)
    refuse_unmeasured_columns(data, specimen)
    try:
        table.check(specimen.nu, float(table.E_over_sigma_y[0]))      # nu inside the table, before the data
    except ValueError as exc:
        raise ValueError(f"{exc}; {OUTSIDE_ADVICE}" if default else str(exc)) from None
    try:
        result, used, left_out = table_refusal.fit_in_window(data, specimen, table, sigma_y, noise, default)
    except ValueError as exc:
        raise ValueError(f"{exc}; {table_refusal.likely_cause(data, specimen, table, noise)}"
                         + (f"; {OUTSIDE_ADVICE}" if default else "")) from None
    why = table_refusal.refusal(result, table, noise)
    if why:
        raise ValueError(f"{', '.join(data.files)}: {why}; {table_refusal.likely_cause(data, specimen, table, noise)}; "
                         f"nothing written")
    why = table_refusal.undetermined(result)
    if why:
        raise ValueError(f"{', '.join(data.files)}: {why}")
    law = result.law
    window = law.window
    # the data's loads at the point estimate, within the law's model-form uncertainty of the edge
    # (calib.fit.measured.table_refusal), never widened by the fit's own interval
    factor = table_refusal.tolerance(result)
    outside = (result.data_window[1] > window.P_max_over_P_Y * factor
               or result.data_window[0] < window.P_min_over_P_Y / factor)
    if default and outside:
        raise ValueError(f"{', '.join(data.files)}: the data's loads P/P_Y {result.data_window[0]:.3g}.."
                         f"{result.data_window[1]:.4g} reach outside the vz master table's window "
                         f"{window.P_min_over_P_Y:.3g}..{window.P_max_over_P_Y:.4g} at this material"
                         + (f" (fewer than {table_refusal.MIN_TESTS} drop tests inside)" if data.impacts is not None
                            else "") + f"; --law vz-table fits them on the table's law beyond its measured window, "
                         f"{OUTSIDE_ADVICE}")
    above_one = [float(x) for x in data.impacts.e if x > 1.0] if data.impacts is not None else []
    pair = law.pair
    low, high = result.interval95
    summary = {"law": "vz-table", "law_from": "default" if default else "--law",
               "sigma_y": result.sigma_y, "sigma_y_se": result.se,
               "sigma_y_se_statistical": result.se_stat, "sigma_y_se_model_form": result.se_model,
               "sigma_y_interval95": [low, high], "model_form_uncertainty": result.uncertainty,
               "rms_residual": result.rms_residual,
               "rms_residual_by_group": {k: float((v @ v / v.size) ** 0.5) for k, v in result.residuals.items()},
               "residuals": {k: v.tolist() for k, v in result.residuals.items()},
               "consistent": result.consistent, "verdict": result.verdict, "noise": noise,
               "left_out": left_out, "e_above_1": above_one,
               **({"note": E_ONLY} if result.uncertainty["kind"] == "drops e" else {}),
               "data_window_P_over_P_Y": list(result.data_window), "law_window": law.window.record(),
               "P_Y": pair.P_Y, "a_Y": pair.a_Y, "delta_Y": pair.delta_Y, "v_Y": pair.v_Y,
               "table": {"P_over_P_Y": list(law.x), "a_p_over_a_Y": list(law.f), "C_R": list(law.g)},
               "files": data.files, "vz_master_table": str(table.path), "accuracy": table.accuracy,
               **({"hardening": hardening_record(result.sigma_y, H_over_E * specimen.E),
                   "hardening_sheet": str(sheet.path), "hardening_accuracy": sheet.accuracy} if sheet else {}),
               "tested": tested(specimen),
               **({"counter": specimen.counter.describe(), "pair_table": str(pair_table_of(specimen).path),
                   "pair_table_accuracy": pair_table_of(specimen).accuracy} if specimen.counter is not None else {}),
               "units": {"sigma_y": "Pa", "P_Y": "N", "a_Y": "m", "delta_Y": "m", "v_Y": "m/s",
                         "residuals": "relative: (law - measured) / measured; force: / max(|P|, 0.05 x smallest peak)"}}
    if ns.params_out:
        from calib.report.parameter_file import write_parameter_file
        from nfdmodel import ContactPair, VZTableParams

        counter = specimen.counter
        shipped = law if counter is not None else VZTableParams(
            ContactPair.sphere_flat(specimen.material(result.sigma_y), specimen.R), law.x, law.f, law.g, law.window)
        write_parameter_file(ns.params_out, shipped, specimen.R, specimen.material(result.sigma_y),
                             {"source": "measurements", "files": data.files,
                              "model": "vz-table (vz master table)" if counter is None else
                              "vz-table (pair table on the vz master table)",
                              "sigma_y_se": result.se, "sigma_y_interval95": [low, high], "verdict": result.verdict},
                             output.stamp(time.perf_counter() - started),
                             counter=None if counter is None else counter.describe(),
                             **({"hardening": summary["hardening"]} if sheet else {}))
        summary["params_out"] = ns.params_out
    loads_out = ", ".join(f"{t['P_over_P_Y']:.4g}" for t in left_out)
    lines = [f"law: vz-table (the vz master table's load-dependent law; "
             + ("the default" if default else "--law vz-table") + ")",
             f"vz-table model (vz master table) fitted to {', '.join(f'{v.size} {k}' for k, v in result.residuals.items())} "
             f"value(s) ({', '.join(data.files)}): sigma_Y",
             f"sigma_Y = {result.sigma_y:.4g} Pa +- {100 * result.se / result.sigma_y:.2g} % (statistical "
             f"{100 * result.se_stat / result.sigma_y:.2g} %, model form {100 * result.se_model / result.sigma_y:.2g} %); "
             f"95 % interval {low:.4g}..{high:.4g} Pa (k {result.uncertainty['coverage_factor']:.3g}, "
             f"{result.uncertainty['dof_statistical']:.3g} statistical degrees of freedom; calib.fit.measured.interval)",
             f"first yield: P_Y = {pair.P_Y:.4g} N, a_Y = {pair.a_Y:.4g} m, v_Y = {pair.v_Y:.4g} m/s",
             f"data window: P/P_Y {result.data_window[0]:.3g}..{result.data_window[1]:.4g}; the law's measured window "
             f"{window.P_min_over_P_Y:.3g}..{window.P_max_over_P_Y:.4g}"
             + (" (the data reach outside it: there the law is not measured)" if outside else ""),
             *([f"left out: row(s) {', '.join(str(t['row']) for t in left_out)} (P/P_Y {loads_out}): outside the "
                f"law's measured window; --law vz-table fits every test, beyond the window too"] if left_out else []),
             *([f"note: {E_ONLY}"] if result.uncertainty["kind"] == "drops e" else []),
             *([f"e above 1: {len(above_one)} test(s), up to {max(above_one):.6g}: kept as measured (accepted up "
                f"to 1 + {E_ROUND_OFF:g}: round-off about an elastic impact)"] if above_one else []),
             f"rms residual: " + ", ".join(f"{k} {100 * v:.3g} %" for k, v in summary["rms_residual_by_group"].items()),
             f"model: {result.verdict}",
             *([f"tested: {tested(specimen)}; pair table accuracy: {pair_table_of(specimen).accuracy}"]
               if specimen.counter is not None else []),
             *([f"hardening (known): sigma_y = sigma_Y + H eps_p, H = {H_over_E * specimen.E:.4g} Pa (H/E {H_over_E:.4g}), "
                f"the hardening sheet's share at {sheet.nu_label} ({sheet.path.name}); its accuracy: {sheet.accuracy}"]
               if sheet else []),
             f"table accuracy: {table.accuracy}"] + ([f"parameter file written to {ns.params_out}"] if ns.params_out else [])
    print_summary(ns, summary, lines)
    return 0

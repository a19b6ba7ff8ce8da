"""``nfdcal collide``: sphere-on-rigid-flat impacts with a runtime contact law.

A sphere of mass m = (4/3) pi R^3 rho hits the flat at v_in; m d2(delta)/dt2 = -P(delta) is
integrated with leap-frog until it leaves at v_out; the restitution is e = -v_out / v_in
(nfdmodel/README.md, Restitution and collisions).

    nfdcal collide --law vz --v-in 0.02 0.04 0.1 [--dt 1e-6] [--json]
    nfdcal collide --v-in 0.1 --angle 10 30 60 --mu 0.3 [--omega W] [--plot e_t.png]   # oblique
    nfdcal collide --params results/calibration/parameters.json --v-in 0.0167 --repeat 3   # 3 impacts, one spot
    nfdcal collide --report [--params FILE] [--out results/collision]   # regenerate results/collision/

Material flags default to the paper's reference case (aluminium sphere, R = 0.1 m). --Ca --Kc
default to the constants of the sphere the flags give: the paper's calibration for the reference
sphere, its dimensionless constants at another radius, the master table's for another material
(as ``nfdcal material``; outside the table an error); or they come from a calibrated parameter
file (--params FILE, which also sets the material; its law, vz, vz-table or vz-unload, is the default --law,
and the two table laws need one). --dt defaults to "auto": the shortest estimated contact time /
2000 or its unloading phase / 100, whichever is smaller (about 3e-7 s for the reference case at
0.02..0.2 m/s; the paper used 1e-6 s). A dt too large for the contact prints one warning line on
stderr (nfdmodel.TimeStepWarning; oblique impacts: the same check at the fastest normal speed); a dt beyond
the leap-frog stability limit is an error. Each record (and --json) also gives the contact's state at
the end, as the LAMMPS plugin reports a contact: dent (delta_res) and delta_max [m], and
dissipated_plastic [J], the energy the contact dissipated (nfdmodel.CollisionResult).
Bad input: a ValueError naming the parameter and its range (the dispatcher prints one line and
exits with code 2).

Oblique impacts (--angle, incidence from the normal [deg], each with each --v-in speed): the
sphere also slides and spins (--omega [rad/s] about the axis of rolling, |omega| R <= 1e4 m/s), with
Mindlin friction --mu (k_t = 8 G*, 1/G* = (2 - nu)/G + (2 - nu_2)/G_2 of the sphere and the
counter-body a --params file states, 8 G/(2 - nu) on a rigid flat; --tangential the variant, default
mindlin_rescale/force), --damping MODEL VALUE and --x-gamma-t, --rolling sds K GAMMA MU, --twisting
marshall | sds K GAMMA MU (nfdmodel.oblique_collide, the models of LAMMPS's granular styles); prints
e_n, e_t = v_t'/v_t, beta = -V'/V (the contact point; '-' where undefined: e_t at normal incidence),
the rebound angle and spin; --plot FILE draws e_t and beta against the incidence angle (an existing
file only with --overwrite).

--repeat N: N impacts of each sphere on the same spot (nfdmodel.collide_repeated): after each separation
the sphere is re-launched at v_in from first touch (delta = the dent delta_res), the contact's history
(turning point, dent, unloading curve) carried over, so it reloads along the unloading curve to the turning
point and loads on the virgin curve beyond; one record per impact with its index repeat (1..N), its e
(= e_velocity), the dent and delta_max [m] from the first impact's first touch.

--rate-law johnson-cook|cowper-symonds with --jc-C [--jc-reference-rate] or --cs-D --cs-q (impact's flags): the
rate-aware law on the --law vz or vz-table law (the master table's vz constants, or a --params file's law) in
the form of --rate-form: relaxing (the default, nfdmodel.rate_relaxing: sigma_Y s, s following the contact's
strain rate) or fixed (nfdmodel.rate_aware: sigma_Y R(eps_dot), eps_dot = v_in / (c a_ref) fixed at first
contact); each record adds strain_rate [1/s] at first contact and rate_factor (R, or s at the turning point). Normal impacts only (--repeat too; not the oblique flags).
A --params file that states a rate law ("rate_law", nfdmodel/parameter_file.py) runs the same rate-aware
law without the flags; --rate-law and its constants replace the file's.

--report: the restitution sweep, time-step convergence and plots of the vz law with the paper's
constants, or with the two constants of --params FILE (a calibration's parameters.json, whichever
law it ships, e.g. results/calibration/parameters.json); no other file is read, and the output names
the source.
"""
from __future__ import annotations

from calib.commands.common import (MATERIAL_DEFAULTS, RATE_AWARE_ACCURACY, RATE_RELAXING_ACCURACY,
                                   add_material_arguments, add_rate_form_argument, add_rate_law_arguments,
                                   add_summary_arguments, file_hardening_line, integer, material_flags, number,
                                   print_summary, rate_form_from_args, rate_law_from_args)
from nfdmodel import LAWS, PYTHON_LAWS, reference_case
from nfdmodel.reference_case import is_reference_sphere
from nfdmodel.collision import MAX_REPEAT

LAW_NAMES = tuple(LAWS) + tuple(PYTHON_LAWS)   # every registered law, in the registry's order
FILE_LAWS = ("vz", "vz-table", "vz-unload")   # the laws a parameter file holds (nfdmodel.parameter_file)
DEFAULTS = {**MATERIAL_DEFAULTS, "Ca": reference_case.CA, "Kc": reference_case.KC}   # the paper's calibration
# the files --report writes into --out (calib.report.collision)
REPORT_FILES = ("restitution.csv", "restitution.png", "impact_v0.04.csv", "impact_v0.04.png", "dt_convergence.csv",
                "dt_convergence.png", "summary.json")


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser(
        "collide", help="sphere-on-flat impact: restitution, peak force, contact time",
        description=__doc__.split("\n\n")[0] + " Prints a table, or a JSON list with --json "
        "(keys v_in, v_out, e_velocity, e_energy, P_max, contact_time; SI units).")
    # Numbers are parsed in run() so bad values give one line from the dispatcher (exit 2).
    parser.add_argument("--law", default=None, help=f"force law: {', '.join(LAW_NAMES)} (default vz, or the"
                        " law of the --params file)")
    parser.add_argument("--v-in", nargs="+", metavar="V", help="incoming velocities [m/s] (> 0)")
    parser.add_argument("--repeat", default=None, metavar="N",
                        help=f"N impacts of each sphere on the same spot (integer 1 .. {MAX_REPEAT}, default 1): the"
                             " contact's history (dent, turning point) carried over, the sphere re-launched at v_in;"
                             " one record per impact with its index repeat (1..N) and its e")
    parser.add_argument("--dt", default="auto", help="time step [s] (> 0) or 'auto' (default)")
    add_summary_arguments(parser, progress=False)
    add_material_arguments(parser)
    parser.add_argument("--Ca", default=None, help="vz plastic-radius rate [m/N] (default: the material's, from "
                        f"the master table; {DEFAULTS['Ca']:g} for the reference sphere)")
    parser.add_argument("--Kc", default=None, help="vz curvature rate [1/N] (default: the material's, from the "
                        f"master table; {DEFAULTS['Kc']:g} for the reference sphere)")
    parser.add_argument("--params", default=None, metavar="FILE",
                        help="calibrated parameter file (JSON from `nfdcal calibrate`): material, Ca, Kc")
    add_rate_law_arguments(parser, "the rate-aware law (--rate-form): the --law vz or vz-table law with "
                           "sigma_Y scaled by R(eps_dot), eps_dot = v_in / (c a_ref): johnson-cook "
                           "(R = 1 + C ln(max(eps_dot / eps_dot_0, 1))) or cowper-symonds (R = 1 + (eps_dot / D)^(1/q)); "
                           "default: rate-independent")
    add_rate_form_argument(parser)
    parser.add_argument("--K1", default=None, help="walton-braun loading stiffness [N/m] "
                        "(default: vz secant to 40 P_Y)")
    parser.add_argument("--K2", default=None, help="walton-braun unloading stiffness [N/m] (>= K1)")
    parser.add_argument("--angle", nargs="+", metavar="DEG", help="oblique impacts: incidence angles from the "
                        "normal [deg] (0 <= angle < 90), each at each --v-in speed")
    parser.add_argument("--mu", default=None, help="oblique impacts: Mindlin friction coefficient (default 0: "
                        "frictionless)")
    parser.add_argument("--tangential", default="mindlin_rescale/force", help="oblique impacts: LAMMPS's Mindlin "
                        "variant of --mu (default mindlin_rescale/force, the one for a plastic law)")
    parser.add_argument("--omega", default=None, help="oblique impacts: incoming spin [rad/s] about the axis "
                        "of rolling (default 0)")
    parser.add_argument("--damping", nargs="+", default=None, metavar="ARG", help="oblique impacts: normal "
                        "damping MODEL VALUE, LAMMPS's: viscoelastic c [1/(m s)], tsuji e or coeff_restitution e "
                        "(default none)")
    parser.add_argument("--x-gamma-t", default=None, help="oblique impacts: tangential damping in units of the "
                        "normal damping's prefactor (default 0)")
    parser.add_argument("--rolling", nargs="+", default=None, metavar="ARG", help="oblique impacts: rolling "
                        "resistance 'sds K_ROLL GAMMA_ROLL MU_ROLL' [N/m, N s/m, -] (default none)")
    parser.add_argument("--twisting", nargs="+", default=None, metavar="ARG", help="oblique impacts: twisting "
                        "resistance 'marshall' (from --mu's k_t) or 'sds K_TWIST GAMMA_TWIST MU_TWIST' "
                        "[N m/rad, N m s/rad, m] (default none)")
    parser.add_argument("--plot", default=None, metavar="PNG", help="oblique impacts: a PNG of e_t and beta "
                        "against the incidence angle (the name ends in .png)")
    parser.add_argument("--overwrite", action="store_true", help="replace an existing --plot file (refused "
                        "without it)")
    parser.add_argument("--report", action="store_true",
                        help="regenerate the collision results (CSV, JSON, PNG) into --out, vz with the paper's"
                             " constants or those of --params FILE")
    parser.add_argument("--out", default=None, help="folder for --report (default results/collision)")
    # calib.commands.targets: the master table read without --params, the files --report writes into --out
    parser.set_defaults(run=run, shipped=("table",), writes_into=REPORT_FILES)


def material_constants(pair, material, radius: float):
    """The vz law of a sphere given by its material flags alone (calib.fit.master_table.vz_constants); outside
    the master table a ValueError naming the table's range and what to give instead."""
    from calib.fit.master_table import vz_constants

    try:
        return vz_constants(material, radius)[0]
    except ValueError as exc:
        raise ValueError(f"{exc}; or give --Ca and --Kc, or --params FILE") from None


def build_params(ns):
    """(law name, law parameters) from the command-line namespace."""
    from nfdmodel import ContactPair, Material, VZParams, WaltonBraunParams, get_law, load_parameters
    from nfdmodel.parameter_file import law_of
    from nfdmodel.vz import check_si_constants

    flags = material_flags(ns)
    if ns.law is not None:
        get_law(ns.law)                 # an unknown law is named before anything is read
    if ns.params is not None:
        given = [f"--{k.replace('_', '-')}" for k, v in {**flags, "Ca": ns.Ca, "Kc": ns.Kc}.items()
                 if v is not None]
        if given:
            raise ValueError(f"--params sets the material, Ca and Kc: do not combine it with {', '.join(given)}")
    file_params = load_parameters(ns.params) if ns.params is not None else None
    law = get_law(ns.law if ns.law is not None else law_of(file_params)).name
    if law == "vz-table" and ns.params is None:
        raise ValueError("--law vz-table needs --params FILE (a vz-table parameter file: nfdcal calibrate, or "
                         "nfdcal material --params-out); without --params give --law vz, thornton, hertz or "
                         "walton-braun")
    if law == "vz-unload" and ns.params is None:
        raise ValueError("--law vz-unload needs --params FILE (a vz-unload parameter file: nfdcal calibrate --ship "
                         "unload); without --params give --law vz, thornton, hertz or walton-braun")
    if ns.params is not None:
        params = file_params
        held = law_of(file_params)
        if law in FILE_LAWS and law != held:
            raise ValueError(f"--law {law} out of range for --params {ns.params}: the file holds the {held} law; "
                             f"give --law {held} (or no --law), or one of thornton, hertz, walton-braun")
    else:
        values = {k: number(f"--{k.replace('_', '-')}", v, DEFAULTS[k]) for k, v in flags.items()}
        material = Material(values["E"], values["nu"], values["sigma_y"], values["rho"])
        pair = ContactPair.sphere_flat(material, values["R"])
        if ns.Ca is None and ns.Kc is None:
            params = material_constants(pair, material, values["R"])
        elif (ns.Ca is None or ns.Kc is None) and not is_reference_sphere(material.E, material.nu, values["R"], material.sigma_y):
            raise ValueError("--Ca, --Kc out of range: give both for this sphere, or neither (then the master "
                             "table's constants for its material); the defaults are the reference sphere's")
        else:                           # constants typed by hand: no window stated
            params = VZParams(pair, number("--Ca", ns.Ca, DEFAULTS["Ca"]), number("--Kc", ns.Kc, DEFAULTS["Kc"]), None)
            # a dimensionless number typed in the SI flag (the README's Ca_hat 0.026) is refused
            check_si_constants(pair, None if ns.Ca is None else params.Ca, None if ns.Kc is None else params.Kc,
                               ("--Ca", "--Kc"))
    rate = rate_law_from_args(ns)
    form = rate_form_from_args(ns)
    if rate is not None:
        return rate_aware(law, params, rate, form)
    stated = file_rate_law(ns.params) if ns.params is not None else None
    if stated is not None:                      # the file's rate law (nfdmodel/parameter_file.py, "rate_law")
        from nfdmodel.rate_aware import BASE_LAWS

        if law not in BASE_LAWS:
            raise ValueError(f"--law {law} out of range for --params {ns.params}: the file states a rate law, which "
                             f"scales sigma_Y of its {law_of(file_params)} law; give --law {law_of(file_params)} "
                             f"(or no --law)")
        return stated.law(law, params)
    if law == "walton-braun" and (ns.K1 is not None or ns.K2 is not None):
        default = WaltonBraunParams.from_vz(params)
        K1 = number("--K1", ns.K1, default.K1)
        return law, WaltonBraunParams(params.pair, K1, number("--K2", ns.K2, max(default.K2, K1)))
    if law != "walton-braun" and (ns.K1 is not None or ns.K2 is not None):
        raise ValueError("--K1/--K2 apply to --law walton-braun only")
    return law, params


def file_rate_law(path):
    """The parameter file's "rate_law" entry (nfdmodel.parameter_file.StatedRate), None without one."""
    from nfdmodel.parameter_file import rate_law_of_file

    return rate_law_of_file(path)


def rate_aware(law: str, params, rate, form: str = "fixed"):
    """(the rate-aware ContactLaw of ``form``, its parameters) of the base ``law`` and the FE's rate law ``rate``
    (calib.fe.rate_law); the base must scale with sigma_Y (vz, vz-table), else one line naming --law."""
    from nfdmodel.rate_aware import BASE_LAWS
    from nfdmodel.rate_relaxing import rate_form_law
    from nfdmodel.strain_rate import rate_law_of

    if law not in BASE_LAWS:
        raise ValueError(f"--rate-law needs a law whose constants scale with sigma_Y: --law {' or '.join(BASE_LAWS)} "
                         f"(or a vz or vz-table --params file), got --law {law}")
    return rate_form_law(form, law, params, rate_law_of(rate.record()))


def run(ns) -> int:
    import sys
    import warnings

    if ns.report:
        if ns.repeat is not None:
            raise ValueError("--repeat is for the impacts of --v-in: do not combine it with --report")
        from calib.report.collision import DEFAULT_OUT, generate

        velocities = [number("--v-in", v, low=0.0, unit="m/s") for v in ns.v_in] if ns.v_in else None
        from calib.commands.targets import refuse_output_over_input

        refuse_output_over_input(ns, {"out": ns.out or DEFAULT_OUT})   # the default folder too
        out, source = generate(ns.out or DEFAULT_OUT, params_file=ns.params, velocities=velocities)
        print_summary(ns, {"out": str(out), "vz_parameters": source},
                      [f"collision results written to {out} (vz parameters: {source})"])
        return 0
    if ns.out is not None:
        raise ValueError("--out applies to --report only")
    dt = None if str(ns.dt).strip().lower() == "auto" else number("--dt", ns.dt)
    if dt is not None and dt <= 0:
        raise ValueError(f"--dt out of range: need dt > 0 s, got {dt:g}")
    if not ns.v_in:
        raise ValueError("--v-in is required: one or more incoming velocities [m/s] (> 0)")
    import numpy as np

    from nfdmodel import collide

    velocities = np.array([number("--v-in", v) for v in ns.v_in])
    if ns.plot is not None:
        from calib.commands.targets import check_plot_name, refuse_existing

        check_plot_name(ns)
        refuse_existing(ns, ("plot",))          # before any work: an existing PNG only with --overwrite
    elif ns.overwrite:
        raise ValueError("--overwrite applies to --plot only")
    repeat = integer("--repeat", ns.repeat, 1, 1, MAX_REPEAT)
    law, params = build_params(ns)
    if any(value is not None for value in (ns.angle, ns.mu, ns.omega, ns.plot, ns.damping, ns.x_gamma_t,
                                           ns.rolling, ns.twisting)):
        if ns.repeat is not None:
            raise ValueError("--repeat is for normal impacts: do not combine it with the oblique flags")
        if ns.rate_law is not None:
            raise ValueError("--rate-law is for normal impacts: do not combine it with the oblique flags")
        if getattr(law, "name", law) in ("rate-aware", "rate-relaxing"):
            raise ValueError(f"--params {ns.params} states a rate law (the rate-aware law), which is for normal "
                             f"impacts: do not combine it with the oblique flags")
        return run_oblique(ns, law, params, velocities, dt)
    if ns.repeat is not None:
        return run_repeated(ns, law, params, velocities, dt, repeat)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = collide(law, params, velocities, dt=dt)
    for warning in caught:
        print(f"nfdcal collide: warning: {warning.message}", file=sys.stderr)
    records = result.records()
    law = getattr(law, "name", law)
    rate_lines = []
    if law in ("rate-aware", "rate-relaxing"):   # eps_dot at first contact and R (relaxing: s at the turning point)
        for record, rate, factor in zip(records, params.strain_rate(velocities), params.rate_factor(velocities)):
            record.update(strain_rate=float(rate), rate_factor=float(factor))
        rate_lines = ([f"rate-aware {params.base_law} law: sigma_Y R(eps_dot), eps_dot = v_in / (c a_ref), c = "
                       f"{params.c:g}; {params.rate_law.record()}", f"  {RATE_AWARE_ACCURACY}"]
                      if law == "rate-aware" else
                      [f"rate-relaxing {params.base_law} law: sigma_Y s, ds/dt = k (E*/sigma_Y) (eps_dot - "
                       f"eps_dot_s(s)), eps_dot = v_n / (c a_ref), c = {params.c:g}, k = {params.k:g}; "
                       f"{params.rate_law.record()}; R: s at the turning point", f"  {RATE_RELAXING_ACCURACY}"])
        rate_lines += [f"  v_in {r['v_in']:g} m/s: eps_dot = {r['strain_rate']:.4g} /s, R = {r['rate_factor']:.5f}"
                       for r in records]
    pair = params.pair
    lines = [f"law {law}: R* = {pair.R_star:g} m, E* = {pair.E_star:.4g} Pa, m* = {pair.mass_star:.4g} kg, "
             f"P_Y = {pair.P_Y:.4g} N, "
             f"v_Y = {pair.v_Y:.4g} m/s, dt = {result.dt:.3g} s, {result.steps} steps, "
             f"{result.wall_time_s:.3f} s",
             f"{'v_in m/s':>10} {'v_out m/s':>11} {'e_velocity':>11} {'e_energy':>9} {'P_max N':>10} "
             f"{'contact_time s':>15} {'in window':>9}"]
    window = {True: "yes", False: "NO", None: "-"}
    lines += [f"{r['v_in']:10.4g} {r['v_out']:11.5g} {r['e_velocity']:11.6f} {r['e_energy']:9.6f} "
              f"{r['P_max']:10.5g} {r['contact_time']:15.6g} {window[r['in_calibrated_range']]:>9}" for r in records]
    lines += rate_lines
    if getattr(params, "window", None) is not None and law in ("vz", "vz-unload"):
        lines.append(f"calibrated window: {params.window.describe()} ({params.window.source})")
    hardening = None if ns.params is None else file_hardening_line(ns.params)
    if hardening is not None:
        lines.append(f"law calibrated with {hardening}")
    print_summary(ns, records, lines)
    return 0


def run_repeated(ns, law: str, params, velocities, dt, repeat: int) -> int:
    """--repeat N: N impacts per velocity on one contact (nfdmodel.collide_repeated); one record per
    impact: v_in, repeat (1..N), e (= e_velocity), the collide keys, dent (delta_res) and delta_max [m]
    (both from the first touch of the first impact)."""
    import sys
    import warnings

    from nfdmodel import collide_repeated

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        results = collide_repeated(law, params, velocities, repeat, dt=dt)
    for message in dict.fromkeys(str(warning.message) for warning in caught):     # each once, not once per impact
        print(f"nfdcal collide: warning: {message}", file=sys.stderr)
    records = []
    for i in range(velocities.size):
        for k, result in enumerate(results, start=1):
            record = result.records()[i]
            records.append({"v_in": record["v_in"], "repeat": k, "e": record["e_velocity"], **record})
    pair = params.pair
    law = getattr(law, "name", law)                # the rate-aware law is passed as its ContactLaw
    lines = [f"law {law}: {repeat} impacts per velocity on one contact, its history carried over; R* = "
             f"{pair.R_star:g} m, m* = {pair.mass_star:.4g} kg, P_Y = {pair.P_Y:.4g} N, v_Y = {pair.v_Y:.4g} m/s, "
             f"dt = {results[0].dt:.3g} s",
             f"{'v_in m/s':>10} {'repeat':>6} {'e':>9} {'P_max N':>10} {'dent m':>10} {'delta_max m':>11} "
             f"{'contact_time s':>15}"]
    lines += [f"{r['v_in']:10.4g} {r['repeat']:>6} {r['e']:9.6f} {r['P_max']:10.5g} {r['dent']:10.4g} "
              f"{r['delta_max']:11.4g} {r['contact_time']:15.6g}" for r in records]
    print_summary(ns, records, lines)
    return 0


def oblique_friction(ns, params, mu: float):
    """The Friction of --mu/--tangential/--damping/--x-gamma-t/--rolling/--twisting: k_t = 8 G* of
    the two bodies (nfdmodel.friction.shear_coefficient): with --params the sphere and the counter-body
    the file states (none: a rigid flat), else the sphere of the material flags on a rigid flat."""
    from types import SimpleNamespace

    from nfdmodel.friction import Friction, shear_coefficient
    from nfdmodel.materials import youngs_modulus
    from nfdmodel.parameter_file import elastic_bodies

    if ns.params is not None:
        sphere, counter = elastic_bodies(ns.params)
    else:                   # the sphere's E and nu (on a rigid flat E* = E/(1 - nu^2)): all k_t reads
        sphere, counter = SimpleNamespace(E=youngs_modulus(params.pair.E_star, params.pair.nu), nu=params.pair.nu), None
    models = {}
    if ns.damping is not None:
        if len(ns.damping) != 2:
            raise ValueError(f"--damping out of range: need MODEL VALUE (viscoelastic c, tsuji e or "
                             f"coeff_restitution e), got {' '.join(ns.damping)!r}")
        models.update(damping=ns.damping[0], damping_value=number("--damping", ns.damping[1]))
    if ns.x_gamma_t is not None:
        models["x_gamma_t"] = number("--x-gamma-t", ns.x_gamma_t, low=0.0, low_inclusive=True)
    for name, values, names in (("rolling", ns.rolling, ("k_roll", "gamma_roll", "mu_roll")),
                                ("twisting", ns.twisting, ("k_twist", "gamma_twist", "mu_twist"))):
        if values is None:
            continue
        model, rest = values[0], values[1:]
        wanted = 3 if model == "sds" else 0
        if len(rest) != wanted:
            forms = "'sds K GAMMA MU'" + (" or 'marshall'" if name == "twisting" else "")
            raise ValueError(f"--{name} out of range: need {forms} or 'none', got {' '.join(values)!r}")
        models[name] = model
        models.update({key: number(f"--{name}", value) for key, value in zip(names, rest)})
    if mu > 0:
        models.update(tangential=ns.tangential, k_t=shear_coefficient(sphere, counter), mu=mu)
    elif models.get("twisting") == "marshall" or "x_gamma_t" in models:
        raise ValueError("--mu out of range: --twisting marshall and --x-gamma-t need the tangential model, "
                         "mu > 0")
    try:
        return Friction(**models)
    except ValueError as exc:         # Friction names its own field: name the flag that gave it
        field = str(exc).split()[0]
        raise ValueError(f"{_FRICTION_FLAGS.get(field, '--' + field.replace('_', '-'))}: {exc}") from None


# the flag of each Friction field oblique_friction sets
_FRICTION_FLAGS = {"e": "--damping", "damping": "--damping", "damping_value": "--damping", "x_gamma_t": "--x-gamma-t",
                   "tangential": "--tangential", "k_t": "--mu", "mu": "--mu", "rolling": "--rolling",
                   "k_roll": "--rolling", "gamma_roll": "--rolling", "mu_roll": "--rolling", "twisting": "--twisting",
                   "k_twist": "--twisting", "gamma_twist": "--twisting", "mu_twist": "--twisting"}


def run_oblique(ns, law: str, params, speeds, dt) -> int:
    """The oblique impacts of --angle/--mu/--omega (module doc): a table or JSON records, --plot."""
    import sys

    import numpy as np

    from nfdmodel import collision_reference, limits
    from nfdmodel.collision import STEPS_PER_CONTACT_AUTO, coarse_time_step
    from nfdmodel.oblique import oblique_collide

    for speed in speeds:             # the speed as typed, before its split into normal and tangential parts
        if not 0.0 < speed <= limits.V_IN_MAX:
            raise ValueError(f"--v-in out of range: need 0 < v_in <= {limits.V_IN_MAX:g} m/s (the impact speed, "
                             f"before its split into normal and tangential parts), got {speed:g}")
    angles = np.array([number("--angle", a, low=0.0, low_inclusive=True, high=90.0, unit="deg")
                       for a in (ns.angle or ["0"])])
    mu = number("--mu", ns.mu, 0.0, low=0.0, low_inclusive=True)
    pair = params.pair
    spin_max = limits.V_IN_MAX / pair.R_star      # the sphere's surface speed within v_in's range
    omega = number("--omega", ns.omega, 0.0, unit="rad/s")
    if abs(omega) > spin_max:
        raise ValueError(f"--omega out of range: need |omega| <= {spin_max:g} rad/s (the surface speed R omega within "
                         f"v_in's {limits.V_IN_MAX:g} m/s at R = {pair.R_star:g} m), got {omega:g}")
    friction = oblique_friction(ns, params, mu)
    speed, angle = (values.ravel() for values in np.meshgrid(speeds, angles, indexing="ij"))
    normal = np.maximum(speed * np.cos(np.radians(angle)), 1e-300)
    if dt is None:                                         # collide's automatic dt at the slowest normal speed
        dt = float(collision_reference(law, params, [normal.min()]).contact_time_estimate[0]) / STEPS_PER_CONTACT_AUTO
    else:                                                  # a given dt: collide's check at the fastest normal speed
        coarse = coarse_time_step(collision_reference(law, params, [normal.max()]), dt)
        if coarse is not None:
            print(f"nfdcal collide: warning: {coarse}", file=sys.stderr)
    result = oblique_collide(law, params, friction, speed, angle, omega, dt=dt)
    def defined(value):               # e_t at normal incidence (v_t = 0), beta without slip: no number
        return float(value) if np.isfinite(value) else None

    records = [{"v_in": float(s), "angle": float(a), "e_n": float(en), "e_t": defined(et), "beta": defined(b),
                "angle_out": float(ao), "omega_out": float(w), "P_max": float(p), "contact_time": float(ct)}
               for s, a, en, et, b, ao, w, p, ct in zip(speed, angle, result.e_n, result.e_t, result.beta,
                                                        result.angle_out, result.omega_out, result.P_max,
                                                        result.contact_time)]
    def shown(value):
        return f"{'-':>9}" if value is None else f"{value:9.5f}"

    lines = [f"law {law}, oblique: R = {pair.R_star:g} m, mu = {mu:g}, omega_in = {omega:g} rad/s, dt = {dt:.3g} s",
             f"{'v_in m/s':>10} {'angle deg':>10} {'e_n':>9} {'e_t':>9} {'beta':>9} {'angle_out':>10} "
             f"{'omega_out':>11} {'P_max N':>10} {'contact s':>11}"]
    lines += [f"{r['v_in']:10.4g} {r['angle']:10.4g} {r['e_n']:9.5f} {shown(r['e_t'])} {shown(r['beta'])} "
              f"{r['angle_out']:10.4f} {r['omega_out']:11.5g} {r['P_max']:10.5g} {r['contact_time']:11.4g}"
              for r in records]
    if any(r["e_t"] is None for r in records):
        lines.append("e_t = v_t'/v_t is not defined at normal incidence (v_t = 0): shown '-'")
    if any(r["beta"] is None for r in records):
        lines.append("beta = -V'/V is not defined without an incoming slip (V = v_t - R omega = 0): shown '-'")
    if ns.plot is not None:
        plot_oblique(ns.plot, records, law, mu)
        lines.append(f"plot written to {ns.plot}")
    print_summary(ns, records, lines)
    return 0


def plot_oblique(path: str, records: list[dict], law: str, mu: float) -> None:
    """e_t and beta against the incidence angle, one line per speed."""
    from pathlib import Path

    import numpy as np

    from calib.output import pyplot, save_figure

    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(9, 3.5))
    for speed in sorted({r["v_in"] for r in records}):
        rows = [r for r in records if r["v_in"] == speed and r["angle"] > 0.0]
        for ax, key in zip(axes, ("e_t", "beta")):
            ax.plot([r["angle"] for r in rows], [np.nan if r[key] is None else r[key] for r in rows], marker="o",
                    ms=3, label=f"{speed:g} m/s")
    for ax, label in zip(axes, ("e_t = v_t' / v_t (centre)", "beta = -V' / V (contact point)")):
        ax.set_xlabel("incidence angle from the normal [deg]")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[0].legend()
    fig.suptitle(f"{law}, Mindlin friction mu = {mu:g}: tangential restitution")
    save_figure(fig, Path(path))

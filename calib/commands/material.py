"""``nfdcal material``: Ca, Kc of a new material from the master table, without an FE run.

    nfdcal material --E 205e9 --nu 0.29 --sigma-y 655e6 --R 0.005 --json
    nfdcal material ... --params-out steel.json     # a parameter file for nfdmodel.load_parameters
    nfdcal material ... --v-max 0.5                 # the vz-table law for impacts up to 0.5 m/s
    nfdcal material ... --v-max 0.5 --law vz-unload --params-out law.json   # the vz-unload law
    nfdcal material ... --v-max 0.5 --hardening-modulus 2e9     # a linearly hardening sphere's
    nfdcal material ... --v-max 0.5 --flow-curve tensile.csv    # a sphere of a measured flow curve

Interpolates Ca_hat, Kc_hat over (nu, E / sigma_Y) in the shipped master table
(calib/data/master_table.csv; nfdmodel/README.md: the dimensionless constants), then
Ca = Ca_hat a_Y / P_Y, Kc = Kc_hat / P_Y. Prints Ca [m/N], Kc [1/N], Ca_hat, Kc_hat, first yield
P_Y [N], a_Y [m], delta_Y [m] and the master table's one-line accuracy statement (the full account is
in its .json, named by ``accuracy_details``). Outside the master table: one line naming the parameter and its
range (exit 2).

With ``--v-max V`` (spelled as ``nfdcal calibrate --v-max``): the vz-table law (a_p/a_Y and C_R
against P/P_Y) from the vz master table (calib/data/vz_master_table.csv, calib.fit.vz_master_table),
declared on the window its surrounding nodes measured; an impact at V beyond that window is refused
(one line naming the largest v_in the vz master table vouches for, exit 2). ``--law vz-unload``
gives the vz-unload law instead (nfdmodel.vz_unload: the same loading, the FE's dent ratio
delta_res/delta_max and unloading exponent m from the same table, VZMasterTable.unload_law), on the
same window; ``nfdcal collide --law vz-unload --params`` runs its parameter file.

``--rate-law johnson-cook|cowper-symonds`` with its constants (``nfdcal collide``'s flags), with ``--v-max``:
the vz-table law as above with the strain-rate dependence of sigma_Y stated in the form of --rate-form
(relaxing, the default: nfdmodel.rate_relaxing; fixed: nfdmodel.rate_aware, sigma_Y R(eps_dot), eps_dot =
v_n0 / (c a_ref) at first contact); its parameter file carries the "rate_law" entry
(nfdmodel/parameter_file.py), so ``nfdcal collide --params`` runs the rate-aware law and ``nfdcal export
lammps`` writes the plugin's ``rate`` keyword. The summary gives eps_dot and R at v_max. Refused in one line
(exit 2) without ``--v-max`` (the two-constant answer has no law to scale) and with ``--law vz-unload`` (the
rate-aware law scales vz and vz-table only). The master table's law is measured on rate-independent FE: the
rate factor is the rate law's, applied as the rate-aware law states.

With ``--counter-E E2 [--counter-nu NU2] [--counter-R R2 --counter-rho RHO2] [--counter-sigma-y S2]`` and
``--v-max``: the sphere on that elastic counter-body (a flat, or a sphere), the pair law from the pair table
(calib/data/pair_table.csv, calib.fit.pair_table: the two-body FE over the rigid flat's in loading approach and
dissipated work, by s = E*/E2', P/P_Y, nu and E/sigma_Y, mapping the vz master table's law node by node), no FE run;
its window from P_Y to the lowest of the pair table's top, the vz master table's and the two-body FE's reach on the
pair. Its parameter file states the counter-body (``nfdcal collide --params``, ``nfdcal export lammps
--like-params-out`` take it as a calibrated pair's). Refused in one line (exit 2) without ``--v-max``, with ``--law
vz-unload`` or ``--rate-law`` (not measured on pairs), outside the pair table (nu, E/sigma_Y, E1'/E2') and for a
counter-body that yields at or before the sphere: ``nfdcal calibrate --counter-E ...`` calibrates those pairs by FE.

``--hardening-modulus H`` with ``--v-max``: the law (vz-table or vz-unload) of a sphere of linear isotropic
hardening sigma_y = sigma_Y + H eps_p, the vz master table's tables plus the hardening's share measured by the
hardening sheet (calib/data/vz_hardening_table.csv, calib.fit.vz_hardening: nu 0.2, 0.3, 0.49 and H/E 0 to the
sheet's top; the window ends at its top, the finite strain's reach, 1e4 P_Y or 0.45 R); its parameter file
states the flow curve ("hardening"). ``--flow-curve CSV`` (a tensile test's true flow curve) with ``--v-max``:
the same, the curve read at each load as the linear hardening of its secant modulus to Tabor's representative
strain 0.2 a/R (calib.fit.vz_hardening.effective_hardening; its accuracy on FE of Swift and Ludwik spheres is
printed). Refused in one line (exit 2): without ``--v-max``, H/E (or a curve's secant modulus in the window)
beyond the sheet, with ``--counter-E`` or ``--rate-law``.

``--params-out`` never names a table the command reads (the shipped ones included: a clash is one line,
exit 2, calib.commands.targets) and replaces an existing file only with ``--overwrite``.
"""
from __future__ import annotations

from calib.commands.common import (RATE_AWARE_ACCURACY, RATE_RELAXING_ACCURACY, add_counter_arguments,
                                   add_hardening_arguments, add_material_arguments, hardening_line,
                                   add_rate_form_argument, add_rate_law_arguments, add_summary_arguments,
                                   counter_from_args, flow_curve_from_args, hardening_given, material_from_args,
                                   print_summary, rate_form_from_args, rate_law_from_args, rate_law_given)

LAWS = ("vz-table", "vz-unload")      # the laws --v-max reads from the vz master table


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser("material",
                                   help="Ca, Kc from the master table, or (--v-max) the vz-table law from the vz master "
                                        "table (--rate-law: with its strain-rate dependence; --counter-E: on an elastic "
                                        "counter-body, by the pair table); no FE",
                                   description=__doc__.split("\n\n")[0])
    add_material_arguments(parser)
    add_hardening_arguments(parser)     # with --v-max: --hardening-modulus, the vz master table's hardening sheet
    parser.add_argument("--table", default=None, metavar="CSV", help="master table CSV (default: the shipped one)")
    parser.add_argument("--v-max", default=None, metavar="V",
                        help="the vz-table law for impacts up to V [m/s] from the vz master table (no FE)")
    parser.add_argument("--law", default=None, choices=LAWS,
                        help="with --v-max: the law from the vz master table, vz-table (default) or vz-unload (the "
                             "FE's dent and unloading exponent)")
    parser.add_argument("--vz-table", default=None, metavar="CSV",
                        help="vz master table CSV for --v-max (default: the shipped one)")
    add_rate_law_arguments(parser, "with --v-max: the vz-table law with the strain-rate dependence of sigma_Y "
                                   "stated (the rate-aware law of --rate-form; written to --params-out): "
                                   "johnson-cook (R = 1 + C ln(max(eps_dot / eps_dot_0, 1))) or cowper-symonds "
                                   "(R = 1 + (eps_dot / D)^(1/q)); not with --law vz-unload")
    add_rate_form_argument(parser)
    add_counter_arguments(parser)       # with --v-max: the pair law from the pair table
    parser.add_argument("--pair-table", default=None, metavar="CSV",
                        help="pair table CSV for --counter-E (default: the shipped one)")
    parser.add_argument("--params-out", default=None, metavar="JSON",
                        help="write a parameter file (read by nfdmodel.load_parameters, nfdcal collide --params); "
                             "never one of the tables read, an existing file only with --overwrite")
    parser.add_argument("--overwrite", action="store_true", help="replace an existing --params-out file (refused "
                                                                 "otherwise)")
    add_summary_arguments(parser, progress=False)
    parser.set_defaults(run=run, shipped=("table", "vz_table", "pair_table"))   # calib.commands.targets: the tables read


def run(ns) -> int:
    from calib.commands.targets import refuse_existing
    from calib.fit.master_table import MasterTable

    material, radius = material_from_args(ns)
    hardening = sheet_hardening(ns, material)
    counter = counter_from_args(ns, material)
    refuse_existing(ns, ("params_out",))
    if ns.v_max is not None:
        return run_vz_table(ns, material, radius, counter, hardening)
    if hardening:
        raise ValueError(f"{hardening_given(ns)} needs --v-max (the vz master table's hardening sheet); the "
                         f"two-constant master table is of perfectly plastic spheres")
    if counter is not None or ns.pair_table is not None:
        raise ValueError("--counter-E needs --v-max (the pair law from the pair table is a vz-table law); the "
                         "two-constant master table is the rigid flat's")
    if ns.vz_table is not None or ns.law is not None or rate_law_given(ns) is not None:
        flag = ("--vz-table" if ns.vz_table is not None else "--law" if ns.law is not None
                else rate_law_given(ns))
        raise ValueError(f"{flag} needs --v-max (the vz master table's laws); without it the two-constant table answers")
    table = MasterTable.load(ns.table)
    values = table.parameters(material.E, material.nu, material.sigma_y, radius, material.rho)
    if ns.params_out:
        from calib import output
        from calib.report.parameter_file import write_parameter_file
        from nfdmodel import CalibrationWindow, ContactPair, VZParams

        params = VZParams.from_dimensionless(ContactPair.sphere_flat(material, radius), values["Ca_hat"],
                                             values["Kc_hat"], CalibrationWindow.from_record(values["window"]))
        write_parameter_file(ns.params_out, params, radius, material,
                             {"shipped": "master table", "accuracy": values["accuracy"],
                              "table": values["table"]}, output.stamp(0.0),
                             Ca_rel_error_estimate=values["Ca_rel_error_estimate"],
                             Kc_rel_error_estimate=values["Kc_rel_error_estimate"])
        values["params_out"] = ns.params_out
    print_summary(ns, values, [
        f"Ca = {values['Ca']:.4g} m/N, Kc = {values['Kc']:.4g} 1/N (Ca_hat = {values['Ca_hat']:.4g}, "
        f"Kc_hat = {values['Kc_hat']:.4g})",
        f"first yield: P_Y = {values['P_Y']:.4g} N, a_Y = {values['a_Y']:.4g} m, delta_Y = {values['delta_Y']:.4g} m",
        f"calibrated window: P/P_Y {values['window']['P_min_over_P_Y']:g}..{values['window']['P_max_over_P_Y']:g}, "
        f"a/R* <= {values['window']['a_max_over_R']:.3g} (beyond it the constants are an extrapolation)",
        f"accuracy: {values['accuracy']}"]
        + ([f"parameter file written to {ns.params_out}"] if ns.params_out else []))
    return 0


def sheet_hardening(ns, material):
    """The hardening the vz master table's hardening sheet answers (calib.fit.vz_hardening): H/E of
    ``--hardening-modulus H`` (0.0: no hardening flag, or H = 0), or the flow curve of ``--flow-curve``
    (calib.fe.flow_curve.TabulatedFlowCurve, read through its secant modulus: hardened_tables)."""
    if hardening_given(ns) is None:
        return 0.0
    curve = flow_curve_from_args(ns, material)
    if curve is None:
        return 0.0
    return float(curve.H / material.E) if hasattr(curve, "H") else curve


def vz_table_law(material, radius: float, table_csv=None, law_name: str = "vz-table", counter=None,
                 pair_table_csv=None, hardening=0.0) -> dict:
    """The vz-table law of ``material`` (sphere of ``radius`` [m]) from the vz master table (module
    doc), what ``--v-max`` answers and writes: {"law": VZTableParams, "table": VZMasterTable,
    "values": its tables' record, "v_in_window": (v_low, v_top) [m/s], the impacts of a sphere on a
    rigid flat that reach the window's ends}. The law does not depend on v_max (v_max is checked
    against v_top only). ``law_name`` "vz-unload": the table's vz-unload law (VZUnloadParams).
    ``counter`` (calib.fit.counter.CounterBody): the pair law of calib.fit.pair_table on that
    counter-body (then also "pair": its pair_law record, "counter": the counter-body). ``hardening`` (H/E > 0 or
    a flow curve: :func:`sheet_hardening`): the law of that hardening sphere (calib.fit.vz_hardening; then also
    "sheet": the hardening sheet)."""
    from calib.fit import impact_window
    from calib.fit.vz_master_table import VZMasterTable
    from nfdmodel import ContactPair

    table = VZMasterTable.load(table_csv)
    extra = {}
    if hardening:
        from calib.fit.vz_hardening import HardeningSheet, hardened_tables

        extra = {"sheet": HardeningSheet.load()}
        values = hardened_tables(table, extra["sheet"], material.nu, material.E / material.sigma_y, hardening)
    else:
        values = table.tables(material.nu, material.E / material.sigma_y)
    if counter is not None:
        from calib.fit.pair_table import PairTable, pair_law

        extra = {"pair": pair_law(material, radius, counter, PairTable.load(pair_table_csv), table),
                 "counter": counter}
        law = extra["pair"]["law"]
    else:
        pair = ContactPair.sphere_flat(material, radius)
        law = table.vz_unload_of(values, pair) if law_name == "vz-unload" else table.vz_table_of(values, pair)
    window, P_Y = law.window, law.pair.P_Y
    return {"law": law, "table": table, "values": values,
            "v_in_window": (impact_window.reach_velocity(law, window.P_min_over_P_Y * P_Y),
                            impact_window.reach_velocity(law, window.P_max_over_P_Y * P_Y)), **extra}


def write_vz_table_law(path, found: dict, material, radius: float, rate_law: dict | None = None) -> None:
    """The parameter file of a vz_table_law answer (nfdmodel.load_parameters reads it back); ``rate_law``:
    its "rate_law" entry (a nfdmodel.strain_rate record), None for a rate-independent sphere."""
    from calib import output
    from calib.report.parameter_file import write_parameter_file

    table = found["table"]
    fit = {"shipped": "vz master table", "accuracy": table.accuracy, "table": str(table.path)}
    counter = found.get("counter")
    if counter is not None:
        pair_table = found["pair"]["table"]
        fit = {"shipped": "pair table on the vz master table", "accuracy": f"{pair_table.accuracy}; {table.accuracy}",
               "table": str(table.path), "pair_table": str(pair_table.path)}
    sheet = found.get("sheet")
    if sheet is not None:
        fit = {**fit, "accuracy": f"{table.accuracy}; hardening: {sheet.accuracy}", "hardening_sheet": str(sheet.path)}
    write_parameter_file(path, found["law"], radius, material, fit, output.stamp(0.0),
                         counter=None if counter is None else counter.describe(),
                         table_rel_error_estimate=found["values"]["rel_error_estimate"],
                         **({"rate_law": dict(rate_law)} if rate_law is not None else {}),
                         **({"hardening": found["hardening"]} if "hardening" in found else {}))


def run_vz_table(ns, material, radius, counter=None, hardening=0.0) -> int:
    """``--v-max``: the vz-table law of the material from the vz master table, on ``counter`` the pair law
    from the pair table, with ``hardening`` (:func:`sheet_hardening`) the hardening sheet's (module doc)."""
    from calib.commands.common import number
    from calib.fit import impact_window
    from nfdmodel.validation import bound_text, check_solid

    v_max = number("--v-max", ns.v_max, None, low=0.0, unit="m/s")
    check_solid("v_in", v_max)
    if ns.table is not None:
        raise ValueError("--table is the two-constant master table; with --v-max give --vz-table")
    law_name = ns.law or "vz-table"
    rate = rate_law_from_args(ns)
    form = rate_form_from_args(ns)
    if rate is not None and law_name == "vz-unload":
        raise ValueError("--rate-law out of range for --law vz-unload: the rate-aware law scales sigma_Y of the "
                         "vz-table (or vz) law only; give --law vz-table (or no --law)")
    if counter is not None and (law_name != "vz-table" or rate is not None):
        flag = "--law" if law_name != "vz-table" else rate_law_given(ns)
        raise ValueError(f"{flag} out of range with --counter-E: the pair table maps the vz-table law, rate-"
                         f"independent (give no {flag}, or calibrate the pair by FE: nfdcal calibrate --counter-E ...)")
    if counter is None and ns.pair_table is not None:
        raise ValueError("--pair-table needs --counter-E (the pair table maps the law onto a counter-body)")
    if hardening and (counter is not None or rate is not None):
        flag = "--counter-E" if counter is not None else rate_law_given(ns)
        raise ValueError(f"{hardening_given(ns)} out of range with {flag}: the hardening sheet is measured on a sphere "
                         f"on a rigid flat, rate-independent; run the FE of this sphere instead, nfdcal calibrate "
                         f"{hardening_given(ns)} ... --peaks ...")
    found = vz_table_law(material, radius, ns.vz_table, law_name, counter, ns.pair_table, hardening)
    H_over_E = hardening if isinstance(hardening, float) else 0.0
    if hardening:
        from calib.fe.flow_curve import LinearHardening

        curve = LinearHardening(material.sigma_y, H_over_E * material.E) if H_over_E else hardening
        found["hardening"] = curve.record()
    law, table, values = found["law"], found["table"], found["values"]
    pair = law.pair
    window = law.window
    v_low, v_top = found["v_in_window"]
    pair_found = found.get("pair")
    if v_max > v_top * (1 + 1e-9):
        whose = ("the vz master table's window for this material" if pair_found is None else
                 f"the pair law's window ({pair_found['top_rule']})")
        raise ValueError(f"v_max out of range: {whose} ends at "
                         f"{window.P_max_over_P_Y:.4g} P_Y: need v_max <= {bound_text(v_top, '<=')} m/s ({v_top / pair.v_Y:.4g} v_Y)")
    P_max = impact_window.impact_force(law, v_max)
    summary = {"law": law_name, "v_max": v_max, "P_max_of_v_max": P_max, "P_max_of_v_max_over_P_Y": P_max / pair.P_Y,
               "table": {"P_over_P_Y": list(law.x), "a_p_over_a_Y": list(law.f), "C_R": list(law.g)},
               "window": window.record(), "v_in_window": [v_low, v_top],
               "P_Y": pair.P_Y, "a_Y": pair.a_Y, "delta_Y": pair.delta_Y, "v_Y": pair.v_Y,
               "E_over_sigma_y": material.E / material.sigma_y,
               "rel_error_estimate": values["rel_error_estimate"],
               "units": {"P_Y": "N", "a_Y": "m", "delta_Y": "m", "v_max": "m/s", "v_Y": "m/s"},
               "source": "vz master table interpolation", "table_file": str(table.path), "accuracy": table.accuracy}
    accuracy = table.accuracy
    hardening_lines = []
    if hardening:
        sheet = found["sheet"]
        accuracy = f"{table.accuracy}; hardening: {sheet.accuracy if H_over_E else sheet.flow_curve_accuracy}"
        summary.update(hardening=found["hardening"], hardening_sheet_file=str(sheet.path),
                       accuracy=accuracy, source="vz master table and its hardening sheet",
                       **({"H_over_E": H_over_E} if H_over_E else {"hardening_read_as": values["hardening_read_as"]}))
        what = (f"sigma_y = sigma_Y + H eps_p, H = {H_over_E * material.E:.4g} Pa (H/E = {H_over_E:.4g})" if H_over_E
                else f"{hardening_line(found['hardening'])}, {values['hardening_read_as']}")
        hardening_lines = [f"{'hardening: ' if H_over_E else ''}{what}; the hardening's share of the tables from {sheet.path.name} (measured "
                           f"at {sheet.nu_label}, {sheet.kinematics}: the window ends at the sheet's top)"]
    counter_lines = []
    if pair_found is not None:
        accuracy = f"{pair_found['table'].accuracy}; {table.accuracy}"
        summary.update(source="pair table on the vz master table", pair_table_file=str(pair_found["table"].path),
                       accuracy=accuracy, counter_body=found["counter"].describe(),
                       E1_over_E2_plane_strain=pair_found["stiffness_ratio"], window_top_by=pair_found["top_by"],
                       window_tops_over_P_Y=pair_found["tops"], E_star=pair.E_star, R_star=pair.R_star)
        summary["units"].update(E_star="Pa", R_star="m")
        counter_lines = [f"{found['counter'].label()}; E1'/E2' = {pair_found['stiffness_ratio']:.4g}, the pair's "
                         f"E* = {pair.E_star:.4g} Pa, R* = {pair.R_star:.4g} m; window top "
                         f"{pair_found['top_rule']}"]
    unloading = []
    if law_name == "vz-unload":
        rho, m = law.unloading_tables(P_max / pair.P_Y)
        summary["table"].update({"x_unload": list(law.x_unload), "delta_res_over_delta_max": list(law.dent),
                                 "unloading_exponent": list(law.exponent)})
        summary.update({"delta_res_over_delta_max_of_v_max": float(rho), "unloading_exponent_of_v_max": float(m)})
        unloading = [f"vz-unload law at v_max: dent delta_res/delta_max = {float(rho):.4g}, unloading exponent "
                     f"m = {float(m):.4g} (tables over P_max/P_Y 1..{law.x_unload[-1]:.4g})"]
    rating = []
    if rate is not None:
        rating = rate_summary(summary, law, rate, v_max, form)
    if ns.params_out:
        write_vz_table_law(ns.params_out, found, material, radius,
                           None if rate is None else summary["rate_law"])
        summary["params_out"] = ns.params_out
    below = (f"; impacts below {v_low:.3g} m/s load under the lowest measured path (C_R there follows a_p)"
             if v_max > v_low else "")
    print_summary(ns, summary, [
        f"{law_name} law: {len(law.x)} nodes, P/P_Y 1..{law.x[-1]:.4g}; C_R = {law.g[-1]:.4g}, a_p/a_Y = {law.f[-1]:.4g} at the top",
        f"first yield: P_Y = {pair.P_Y:.4g} N, a_Y = {pair.a_Y:.4g} m, delta_Y = {pair.delta_Y:.4g} m, v_Y = {pair.v_Y:.4g} m/s",
        f"window: P/P_Y {window.P_min_over_P_Y:.3g}..{window.P_max_over_P_Y:.4g} (impacts {v_low:.3g}..{v_top:.3g} m/s); "
        f"v_max = {v_max:g} m/s reaches {P_max / pair.P_Y:.4g} P_Y{below}",
        *hardening_lines, *counter_lines, *unloading, *rating, f"accuracy: {accuracy}"] + ([f"parameter file written to {ns.params_out}"] if ns.params_out else []))
    return 0


def rate_summary(summary: dict, law, rate, v_max: float, form: str = "fixed") -> list[str]:
    """Add the rate law (its record with its form's constants, the parameter file's "rate_law" entry), eps_dot
    [1/s] at first contact and R at v_max (fixed: at first contact, nfdmodel.rate_aware; relaxing: s at the
    turning point, nfdmodel.rate_relaxing) to ``summary``; the lines that say them."""
    from nfdmodel.parameter_file import rate_law_entry
    from nfdmodel.rate_relaxing import rate_form_law
    from nfdmodel.strain_rate import rate_law_of

    _, params = rate_form_law(form, "vz-table", law, rate_law_of(rate.record()))
    strain_rate, factor = float(params.strain_rate(v_max)[0]), float(params.rate_factor(v_max)[0])
    accuracy = RATE_AWARE_ACCURACY if form == "fixed" else RATE_RELAXING_ACCURACY
    summary.update(rate_law=rate_law_entry(params), strain_rate_of_v_max=strain_rate, rate_factor_of_v_max=factor,
                   rate_law_accuracy=accuracy)
    summary["units"]["strain_rate_of_v_max"] = "1/s"
    record = params.rate_law.record()
    constants = ", ".join(f"{k} = {v:g}" for k, v in record.items() if k != "rate_law")
    if form == "fixed":
        return [f"rate-aware law: sigma_Y R(eps_dot), {record['rate_law']} ({constants}), eps_dot = v_n0 / (c a_ref), "
                f"c = {params.c:g}; at v_max: eps_dot = {strain_rate:.4g} /s, R = {factor:.5f}; {accuracy}"]
    return [f"rate-relaxing law: sigma_Y s, {record['rate_law']} ({constants}), ds/dt = k (E*/sigma_Y) (v_n / (c "
            f"a_ref) - eps_dot_s(s)), c = {params.c:g}, k = {params.k:g}; at v_max: eps_dot = {strain_rate:.4g} /s "
            f"at first contact, s = {factor:.5f} at the turning point; {accuracy}"]
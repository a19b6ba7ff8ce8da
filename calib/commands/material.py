"""``nfdcal material``: Ca, Kc of a new material from the master table, without an FE run.

    nfdcal material --E 205e9 --nu 0.29 --sigma-y 655e6 --R 0.005 --json
    nfdcal material ... --params-out steel.json     # a parameter file for nfdmodel.load_parameters

Interpolates Ca_hat, Kc_hat over (nu, E / sigma_Y) in the shipped master table
(calib/data/master_table.csv; nfdmodel/README.md: the dimensionless constants), then
Ca = Ca_hat a_Y / P_Y, Kc = Kc_hat / P_Y. Prints Ca [m/N], Kc [1/N], Ca_hat, Kc_hat, first yield
P_Y [N], a_Y [m], delta_Y [m] and the table's one-line accuracy statement (the full account is in
the table's .json, named by ``accuracy_details``). Outside the table: one line naming the parameter and the table's
range (exit 2).
"""
from __future__ import annotations

from calib.commands.common import add_material_arguments, add_summary_arguments, material_from_args, print_summary


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser("material", help="Ca, Kc of a material from the master table (no FE)",
                                   description=__doc__.split("\n\n")[0])
    add_material_arguments(parser)
    parser.add_argument("--table", default=None, help="master table CSV (default: the shipped one)")
    parser.add_argument("--params-out", default=None, metavar="JSON",
                        help="write a parameter file (read by nfdmodel.load_parameters, nfdcal collide --params)")
    add_summary_arguments(parser, progress=False)
    parser.set_defaults(run=run)


def run(ns) -> int:
    from calib.fit.master_table import MasterTable

    material, radius = material_from_args(ns)
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

"""``nfdcal fit-data --fit-hardening``: sigma_Y and the plastic modulus H of a linearly hardening sphere together.

The command's half for the hardening fit (calib.commands.fit_data states the flags): fits sigma_Y and H on the vz
master table's law with its hardening sheet (calib.fit.measured.hardening_fit), refuses in one line (exit 2) what
it cannot fit (a best fit at the table's or the sheet's edge) or the data do not separate (naming the flow stress
sigma_Y + H eps_* they determine), prints the summary and writes --params-out (the vz-table law of the fitted
sphere with its "hardening" entry).
"""
from __future__ import annotations

import time

from calib.commands.common import number, print_summary

# the flags the hardening fit does not take, and what it takes instead
REFUSED = (("--free", "free", "--law vz (the two-constant law)"), ("--plot", "plot", "--law vz"),
           ("--force", "force", "--law vz"), ("--table", "table", "--law vz"),
           ("--hardening-modulus", "hardening_modulus", "a known H (fit-data --hardening-modulus H fits sigma_Y "
                                                        "alone)"),
           ("--rate-law", "rate_law", "a rate-dependent sphere (fit-data --rate-law)"),
           ("--counter-E", "counter_E", "a sphere on an elastic counter-body (the sheet is measured on a rigid flat)"),
           ("--pair", "pair", "two identical spheres (the sheet is measured on a rigid flat)"))


def refuse_other_fits(ns) -> None:
    """One line naming the first flag the hardening fit does not take, and what that flag belongs to."""
    for flag, key, belongs in REFUSED:
        if getattr(ns, key, None):
            raise ValueError(f"{flag} out of range with --fit-hardening: it belongs to {belongs}; --fit-hardening "
                             f"fits sigma_Y and H on the hardened vz-table law of a sphere on a rigid flat")
    if ns.law == "vz":
        raise ValueError("--fit-hardening fits the hardened vz-table law: give --law vz-table (or no --law)")


def run_hardening_fit(ns, specimen, started: float) -> int:
    """The hardening fit (module doc)."""
    from calib import output
    from calib.fit.measured import data as measured_data
    from calib.fit.measured import hardening_fit, imprint
    from calib.fit.vz_hardening import HardeningSheet
    from calib.fit.vz_master_table import VZMasterTable

    refuse_other_fits(ns)
    noise = number("--noise", ns.noise, None, low=0.0, high=0.5, high_inclusive=True)
    table, sheet = VZMasterTable.load(ns.vz_table), HardeningSheet.load()
    data = measured_data.Measurements(
        impacts=measured_data.read_impacts(ns.impacts) if ns.impacts else None,
        forces=measured_data.read_force_approach(ns.force_approach) if ns.force_approach else None)
    imprint.check_radius(data.impacts, specimen.R)
    result = hardening_fit.fit(data, specimen, table, sheet, noise)
    why = hardening_fit.refusal(result)
    if why:
        raise ValueError(f"{', '.join(data.files)}: {why}; nothing written")
    values, spread, law = result.values, result.spread, result.law
    sigma_y, H = values["sigma_y"], values["hardening_modulus"]
    pair = law.pair
    window = law.window
    outside = (result.data_window[1] > window.P_max_over_P_Y * (1 + 1e-9)
               or result.data_window[0] < window.P_min_over_P_Y * (1 - 1e-9))
    summary = {"law": "vz-table (hardened)", "sigma_y": sigma_y, "hardening_modulus": H, "H_over_E": result.H_over_E,
               "standard_errors": spread["se"], "standard_errors_statistical": spread["se_stat"],
               "standard_errors_model_form": spread["se_model"],
               "interval95": {k: list(v) for k, v in spread["interval95"].items()},
               "correlation": spread["correlation"], "identifiability": result.identifiability,
               "uncertainty": result.uncertainty, "consistent": result.consistent, "verdict": result.verdict,
               "rms_residual_by_group": {k: float((v @ v / v.size) ** 0.5) for k, v in result.residuals.items()},
               "residuals": {k: v.tolist() for k, v in result.residuals.items()}, "noise": noise,
               "data_window_P_over_P_Y": list(result.data_window), "law_window": window.record(),
               "P_Y": pair.P_Y, "a_Y": pair.a_Y, "delta_Y": pair.delta_Y, "v_Y": pair.v_Y,
               "table": {"P_over_P_Y": list(law.x), "a_p_over_a_Y": list(law.f), "C_R": list(law.g)},
               "files": data.files, "vz_master_table": str(table.path), "accuracy": table.accuracy,
               "hardening_sheet": str(sheet.path), "hardening_accuracy": sheet.accuracy,
               "units": {"sigma_y": "Pa", "hardening_modulus": "Pa", "P_Y": "N", "a_Y": "m", "delta_Y": "m",
                         "v_Y": "m/s", "residuals": "relative: (law - measured) / measured"}}
    if ns.params_out:
        from calib.fe.flow_curve import LinearHardening
        from calib.report.parameter_file import write_parameter_file
        from nfdmodel import ContactPair, VZTableParams

        material = specimen.material(sigma_y)
        flat = VZTableParams(ContactPair.sphere_flat(material, specimen.R), law.x, law.f, law.g, window)
        write_parameter_file(ns.params_out, flat, specimen.R, material,
                             {"source": "measurements", "files": data.files,
                              "model": "vz-table (vz master table and its hardening sheet), sigma_Y and H fitted",
                              "standard_errors": spread["se"], "interval95": summary["interval95"],
                              "verdict": result.verdict},
                             output.stamp(time.perf_counter() - started),
                             hardening=LinearHardening(sigma_y, H).record())
        summary["params_out"] = ns.params_out
    lines = [f"law: vz-table of a linearly hardening sphere, sigma_y = sigma_Y + H eps_p (the vz master table and its "
             f"hardening sheet, the share at {sheet.nu_label})",
             f"fitted to {', '.join(f'{v.size} {k}' for k, v in result.residuals.items())} value(s) "
             f"({', '.join(data.files)}): sigma_Y and H"]
    for key, label in (("sigma_y", "sigma_Y"), ("hardening_modulus", "H")):
        low, high = spread["interval95"][key]
        lines.append(f"{label} = {values[key]:.4g} Pa +- {100 * spread['se'][key] / values[key]:.2g} % (statistical "
                     f"{100 * spread['se_stat'][key] / values[key]:.2g} %, model form "
                     f"{100 * spread['se_model'][key] / values[key]:.2g} %); 95 % interval {low:.4g}..{high:.4g} Pa")
    lines += [f"H/E = {result.H_over_E:.4g}; correlation of sigma_Y and H: {spread['correlation']:+.3f}",
              "identifiability: " + result.identifiability["summary"],
              f"first yield: P_Y = {pair.P_Y:.4g} N, a_Y = {pair.a_Y:.4g} m, v_Y = {pair.v_Y:.4g} m/s",
              f"data window: P/P_Y {result.data_window[0]:.3g}..{result.data_window[1]:.4g}; the law's measured window "
              f"{window.P_min_over_P_Y:.3g}..{window.P_max_over_P_Y:.4g}"
              + (" (the data reach outside it: there the law is not measured)" if outside else ""),
              "rms residual: " + ", ".join(f"{k} {100 * v:.3g} %" for k, v in summary["rms_residual_by_group"].items()),
              f"model: {result.verdict}",
              f"accuracy: {table.accuracy}; hardening: {sheet.accuracy}"] \
        + ([f"parameter file written to {ns.params_out}"] if ns.params_out else [])
    print_summary(ns, summary, lines)
    return 0

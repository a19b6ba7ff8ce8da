"""``nfdcal fit-data --rate-law``: sigma_Y and one rate constant from drop tests at several speeds.

The command's half for the rate law (calib.commands.fit_data states the flags): reads the rate law's
fixed constant (Cowper-Symonds' q, Johnson-Cook's eps_dot_0) and the free one's start, fits both on the
rate-aware vz-table law (calib.fit.measured.rate_fit), refuses in one line (exit 2) what it cannot fit or
the data do not separate (naming the combination they determine), prints the summary and writes
--params-out (the vz-table law with the fitted "rate_law" entry).
"""
from __future__ import annotations

import time

from calib.commands.common import number, print_summary, rate_form_from_args

# the flags the rate fit does not take (each applies to another of fit-data's fits)
OTHER_FITS = (("--free", "free"), ("--plot", "plot"), ("--force", "force"), ("--table", "table"))


def rate_flags(ns) -> tuple[str, float, float | None]:
    """(kind, the fixed constant, the free constant's start or None) from --rate-law and its constants; one
    line naming the flag and its range."""
    kind = ns.rate_law
    if kind not in ("cowper-symonds", "johnson-cook"):
        given = "--rate-law" if kind is not None else next(
            f"--{k.replace('_', '-')}" for k in ("jc_C", "jc_reference_rate", "cs_D", "cs_q")
            if getattr(ns, k) is not None)
        raise ValueError(f"{given}: give --rate-law cowper-symonds (D fitted, --cs-q given) or johnson-cook (C fitted, "
                         f"--jc-reference-rate given)" + (f", got {kind!r}" if kind is not None else ""))
    if kind == "cowper-symonds":
        if ns.jc_C is not None or ns.jc_reference_rate is not None:
            raise ValueError("--jc-C and --jc-reference-rate are constants of --rate-law johnson-cook, not of "
                             "cowper-symonds")
        if ns.cs_q is None:
            raise ValueError("--rate-law cowper-symonds needs --cs-q (its exponent q, 0.5 to 20; e.g. mild steel 5): "
                             "fit-data fits D with q given")
        fixed = number("--cs-q", ns.cs_q, low=0.5, low_inclusive=True, high=20.0, high_inclusive=True)
        start = number("--cs-D", ns.cs_D, None, low=1e-3, low_inclusive=True, high=1e12, high_inclusive=True,
                       unit="1/s")
        return kind, fixed, start
    if ns.cs_D is not None or ns.cs_q is not None:
        raise ValueError("--cs-D and --cs-q are constants of --rate-law cowper-symonds, not of johnson-cook")
    fixed = number("--jc-reference-rate", ns.jc_reference_rate, 1.0, low=1e-6, low_inclusive=True, high=1e6,
                   high_inclusive=True, unit="1/s")
    start = number("--jc-C", ns.jc_C, None, low=1e-4, low_inclusive=True, high=1.0, high_inclusive=True)
    return kind, fixed, start


def run_rate_law(ns, specimen, sigma_y, started: float) -> int:
    """The rate fit (module doc)."""
    from calib import output
    from calib.fit.measured import data as measured_data
    from calib.fit.measured import rate_fit
    from calib.fit.vz_master_table import VZMasterTable

    for flag, key in OTHER_FITS:
        if getattr(ns, key):
            raise ValueError(f"{flag} applies to --law vz (the two-constant law), not to the --rate-law fit")
    if ns.law == "vz":
        raise ValueError("--rate-law fits the rate-aware vz-table law: give --law vz-table (or no --law)")
    kind, fixed, start = rate_flags(ns)
    noise = number("--noise", ns.noise, None, low=0.0, high=0.5, high_inclusive=True)
    if ns.force_approach is not None:
        raise ValueError(f"--rate-law fits drop tests at several speeds: --force-approach {ns.force_approach} is "
                         f"quasi-static, with no strain rate; fit it without --rate-law")
    form = rate_form_from_args(ns)
    if ns.hold_sigma_y and sigma_y is None:
        raise ValueError("--hold-sigma-y needs --sigma-y (the quasi-static yield stress to hold) [Pa]")
    table = VZMasterTable.load(ns.vz_table)
    data = measured_data.Measurements(impacts=measured_data.read_impacts(ns.impacts), forces=None)
    held_uncertainty = number("--sigma-y-uncertainty", ns.sigma_y_uncertainty, 0.0, low=0.0, low_inclusive=True,
                              high=0.5, high_inclusive=True)
    result = rate_fit.fit(data, specimen, table, kind, fixed, sigma_y, start, noise, form, ns.hold_sigma_y,
                          held_uncertainty)
    why = rate_fit.refusal(result)
    if why:
        raise ValueError(f"{', '.join(data.files)}: {why}; nothing written")
    name, values = result.name, result.values
    params = result.params
    pair = params.pair
    record = {key: value for key, value in params.record().items() if key != "base_law"}
    summary = {"law": f"rate-aware vz-table ({form})", "rate_law": record, "sigma_y": values["sigma_y"],
               name: values[name], "sigma_y_held": bool(ns.hold_sigma_y),
               "fixed": {rate_fit.FIXED[kind]: fixed},
               "standard_errors": result.se, "standard_errors_statistical": result.se_stat,
               "standard_errors_model_form": result.se_model,
               "interval95": {k: list(v) for k, v in result.interval95.items()}, "correlation": result.correlation,
               "identifiability": result.identifiability, "uncertainty": result.uncertainty,
               "strain_rate": result.strain_rates.tolist(), "rate_factor": result.rate_factors.tolist(),
               "rms_residual": result.rms_residual,
               "rms_residual_by_group": {k: float((v @ v / v.size) ** 0.5) for k, v in result.residuals.items()},
               "residuals": {k: v.tolist() for k, v in result.residuals.items()}, "verdict": result.verdict,
               "noise": noise, "data_window_P_over_P_Y": list(result.data_window),
               "law_window": params.base.window.record(), "P_Y": pair.P_Y, "v_Y": pair.v_Y,
               "files": data.files, "vz_master_table": str(table.path),
               "units": {"sigma_y": "Pa", name: rate_fit.UNITS[name], "strain_rate": "1/s", "P_Y": "N",
                         "v_Y": "m/s", "residuals": "relative: (law - measured) / measured"}}
    if ns.params_out:
        from calib.report.parameter_file import write_parameter_file
        from nfdmodel import ContactPair, VZTableParams

        base = params.base
        material = specimen.material(values["sigma_y"])
        flat = VZTableParams(ContactPair.sphere_flat(material, specimen.R), base.x, base.f, base.g, base.window)
        write_parameter_file(ns.params_out, flat, specimen.R, material,
                             {"source": "measurements", "files": data.files,
                              "model": f"rate-aware vz-table ({form}; vz master table), {kind}",
                              "standard_errors": result.se, "interval95": summary["interval95"],
                              "verdict": result.verdict},
                             output.stamp(time.perf_counter() - started), rate_law=record)
        summary["params_out"] = ns.params_out
    unit = rate_fit.UNITS[name]
    said = (f"sigma_Y R(eps_dot), eps_dot = v_in / (c a_ref), c = {params.c:g}" if form == "fixed" else
            f"relaxing: sigma_Y s, ds/dt = k (E*/sigma_Y) (v_n / (c a_ref) - eps_dot_s(s)), c = {params.c:g}, "
            f"k = {params.k:g}")
    lines = [f"law: rate-aware vz-table (the vz master table's law, {said}), {kind} with {rate_fit.FIXED[kind]} = "
             f"{fixed:g} given",
             f"fitted to {', '.join(f'{v.size} {k}' for k, v in result.residuals.items())} value(s) "
             f"({', '.join(data.files)}): " + (f"{name}, sigma_Y held at {values['sigma_y']:.4g} Pa"
                                               if ns.hold_sigma_y else f"sigma_Y and {name}")]
    for key, label in (("sigma_y", "sigma_Y"), (name, name)):
        if key not in result.interval95:           # held
            continue
        low, high = result.interval95[key]
        said_unit = "Pa " if key == "sigma_y" else ("" if unit == "-" else f"{unit} ")    # C is dimensionless
        lines.append(f"{label} = {values[key]:.4g} {said_unit}+- "
                     f"{100 * result.se[key] / values[key]:.2g} % (statistical {100 * result.se_stat[key] / values[key]:.2g} "
                     f"%, model form {100 * result.se_model[key] / values[key]:.2g} %); 95 % interval {low:.4g}..{high:.4g}")
    if result.correlation is not None:
        lines.append(f"correlation of sigma_Y and {name}: {result.correlation:+.3f}")
    else:
        response = result.uncertainty["sigma_y_response"][name]
        lines.append(f"sigma_Y held: a 1 % error in it moves {name} by {response:+.3g} %")
    lines += [f"tests: eps_dot {result.strain_rates.min():.3g}..{result.strain_rates.max():.3g} /s, R "
              + ("" if form == "fixed" else "(s at the turning point) ") +
              f"{result.rate_factors.min():.4g}..{result.rate_factors.max():.4g}",
              "identifiability: " + result.identifiability["summary"],
              f"data window: P/P_Y {result.data_window[0]:.3g}..{result.data_window[1]:.4g} (at sigma_Y R); the law's "
              f"measured window {params.base.window.P_min_over_P_Y:.3g}..{params.base.window.P_max_over_P_Y:.4g}",
              "rms residual: " + ", ".join(f"{k} {100 * v:.3g} %" for k, v in summary["rms_residual_by_group"].items()),
              f"model: {result.verdict}"] + ([f"parameter file written to {ns.params_out}"] if ns.params_out else [])
    print_summary(ns, summary, lines)
    return 0

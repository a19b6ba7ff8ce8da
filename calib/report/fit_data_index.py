"""fit-data's benchmark section of results/README.md (calib.report.results_index): sigma_Y recovered from FE
data the law did not make, read from results/fit_data/fe_benchmark.json (tests/benchmarks/bench_fit_data_fe.py).
"""
from __future__ import annotations

import math
from pathlib import Path

from calib.report.index_format import apct, pct, read_json, study_header, table


def fit_data_benchmark(root: Path) -> list[str]:
    data = read_json(root / "fit_data" / "fe_benchmark.json")
    if data is None:
        return []
    stamp = data["stamp"]
    targets = stamp.get("targets", {})
    materials = sorted({(f["nu"], f["E_over_sigma_y"]) for f in data["fits"] if not f["kind"].startswith("dyn: ")})
    dynamic = sorted({f["material"] for f in data["fits"] if f["kind"].startswith("dyn: ")})
    lines = study_header("fit-data on FE data the law did not make (`fit_data/`)", stamp,
                         "python tests/benchmarks/bench_fit_data_fe.py")
    lines += [f"sigma_Y recovered by `nfdcal fit-data --law vz-table` from FE drop tests (e; e and P_max; e, P_max and "
              f"the contact time) and FE force-approach curves of {len(materials)} materials that are not table nodes "
              "((nu, E/sigma_Y) = " + ", ".join(f"({nu:g}, {ratio:g})" for nu, ratio in materials) + ")"
              + (f" and from the drop tests of the dynamic FE (`nfdcal impact`, \"dyn\": {', '.join(dynamic)})"
                 if dynamic else "")
              + f", noise added to the FE data, {stamp.get('trials', '?')} trials per noise level and material "
              "(\"x2\": each drop test twice, half the trials); coverage = the share of 95 % intervals that hold the "
              "true sigma_Y, with its binomial 95 % interval (Clopper-Pearson); noise-free max = the method's bias; "
              "sd_CR = the Cramer-Rao spread of sigma_Y the data allow (noise / sqrt(sum (d r_i / d ln sigma_Y)^2), "
              "the law's sensitivities), and the share of fits within the target an unbiased estimator of that spread "
              "would reach"
              + (f"; targets |error| <= {apct(targets['abs_error'], 0)}, coverage >= {targets['coverage95']:.0%}."
                 if targets else "."), ""]
    lines += fit_data_findings(data["summary"], targets.get("abs_error", 0.03)) + [""]

    def coverage(r):
        return (f"{r['coverage95']:.0%} ({r['coverage95_low']:.0%}-{r['coverage95_high']:.0%})"
                if "coverage95_low" in r else f"{r['coverage95']:.0%}")

    def within(r):
        return f"{r['within_target']:.0%} / {r['within_target_cr']:.0%}" if "within_target_cr" in r else "-"

    rows = [[r["kind"], apct(r["noise"], 0), f"{r['fits']}", pct(r["bias"]), apct(r["rms_error"]),
             apct(r["max_abs_error"]), apct(r["noise_free_max_abs_error"]) if "noise_free_max_abs_error" in r else "-",
             apct(r["sd_cr"]) if "sd_cr" in r else "-", within(r), coverage(r),
             "yes" if r["meets_target"] else "no"] for r in data["summary"]]
    return lines + table(["data", "noise", "fits", "bias", "rms error", "max error", "noise-free max", "sd_CR",
                          "within target (measured / CR)", "95 % coverage (CI)", "meets both"], rows)


def fit_data_findings(summary: list[dict], target: float) -> list[str]:
    """The benchmark's findings in words: the bias against the target, the noisy error against the
    spread the data allow, the error with twice the drop tests."""
    by = {(r["kind"], r["noise"]): r for r in summary}
    kinds = [k for k in ("drops e", "drops e+P", "drops e+P+t", "force", "dyn: drops e", "dyn: drops e+P",
                         "dyn: drops e+P+t") if (k, 0.0) in by]
    out = []
    if kinds:
        worst = max(by[k, 0.0]["max_abs_error"] for k in kinds)
        out.append(f"Bias (noise-free data): largest error {apct(worst)} over the kinds (target {apct(target, 0)}).")
    for kind in ("drops e", "drops e+P"):
        r, twice = by.get((kind, 0.03)), by.get((f"{kind} x2", 0.03))
        if r is None or "sd_cr" not in r:
            continue
        text = (f"{kind} at 3 % noise, {r.get('n_drops', '?')} drop tests: rms error {apct(r['rms_error'])} against the "
                f"Cramer-Rao spread {apct(r['sd_cr'])}; {r['within_target']:.0%} of fits within {apct(target, 0)}, where "
                f"an unbiased estimator of that spread reaches {r['within_target_cr']:.0%}")
        if r["max_abs_error"] > target and r["noise_free_max_abs_error"] <= target and r["rms_error"] <= 1.25 * r["sd_cr"]:
            text += (f": the largest error {apct(r['max_abs_error'])} is the scatter of {r.get('n_drops', '?')} drop tests "
                     "at this noise (rms error within 1.25 sd_CR), not the method's bias")
        if twice is not None:
            text += (f". Twice the drop tests: rms {apct(twice['rms_error'])} (1/sqrt(2) of {apct(r['rms_error'])}: "
                     f"{apct(r['rms_error'] / math.sqrt(2))}), sd_CR {apct(twice['sd_cr'])}")
        out.append(text + ".")
    return out

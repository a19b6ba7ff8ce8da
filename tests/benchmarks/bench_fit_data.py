"""Benchmark: how well ``nfdcal fit-data`` recovers known parameters from synthetic drop tests.

Not a timed test: prints, over seeded trials, the bias of the estimates (mean estimate / true - 1,
with the standard error of that mean; target: unbiased within 1 %) and the coverage (the share of
trials whose true value lies within 2 standard errors of the estimate; target >= 90 %).

Data: the paper's aluminium sphere (E = 70 GPa, nu = 0.3, R = 0.1 m, rho = 2699 kg/m^3), e(v_in)
from the law itself (nfdmodel.collision_reference, the exact quasi-static restitution), each
trial with its own noise level drawn from 1..3 % (multiplicative Gaussian on e, a measured
e capped at 1 as the reader refuses e > 1):

    constrained   sigma_Y = 100 MPa, Ca_hat, Kc_hat of the master table; 12 tests at 2..100 v_Y;
                  fitted: sigma_Y alone (started by the fit's own scan, no --sigma-y)
    free          Ca_hat = 0.032, Kc_hat = 0.014 (off the table), sigma_Y = 100 MPa given;
                  20 tests at 1.5..300 v_Y; fitted: Ca_hat, Kc_hat (and sigma_Y if the
                  identifiability analysis finds it determined: the last column counts those trials)

A second table tests the refusal of implausible fits (calib.fit.measured.scatter) on the same
two designs at fixed noise levels (0, 1, 3 % must never be refused; 10 and 20 % show where the
chi-square test against the ceiling of plausible scatter starts to refuse): per noise level, the
largest chi2 / threshold of the e residuals over the trials and the number of fits refused, as
implausible or as data the model cannot fit (calib.fit.measured.regression.DataMismatch).

Usage: .venv/bin/python tests/benchmarks/bench_fit_data.py [--trials 50] [--seed 1] [--refusal-trials 20]
"""
from __future__ import annotations

import argparse
import time

import numpy as np

from calib.fit.master_table import MasterTable
from calib.fit.measured import data as measured_data
from calib.fit.measured.models import fit_constrained, fit_free
from calib.fit.measured.regression import DataMismatch
from calib.fit.measured.specimen import Specimen, law_parameters, predict_impacts

ALUMINIUM = Specimen(E=70e9, nu=0.3, R=0.1, rho=2699.0)
SIGMA_Y = 100e6
FREE_TRUTH = {"Ca_hat": 0.032, "Kc_hat": 0.014}


def synthetic(params, v_over_v_Y, rng, noise=None) -> tuple[measured_data.Measurements, float]:
    noise = rng.uniform(0.01, 0.03) if noise is None else noise
    v = params.pair.v_Y * v_over_v_Y
    e = predict_impacts(params, v)["e"]
    e = np.minimum(e * (1.0 + noise * rng.standard_normal(v.size)), 1.0)
    return measured_data.Measurements(impacts=measured_data.ImpactData("synthetic", v, e, None, None,
                                                                       np.arange(1, v.size + 1))), noise


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trials", type=int, default=50)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--refusal-trials", type=int, default=20, help="trials per noise level of the second table")
    ns = parser.parse_args(argv)
    table = MasterTable.load()
    rng = np.random.default_rng(ns.seed)
    constrained_truth = law_parameters(ALUMINIUM, {"sigma_y": SIGMA_Y}, table)
    free_truth = law_parameters(ALUMINIUM, {"sigma_y": SIGMA_Y, **FREE_TRUTH}, None)
    records = {("constrained", "sigma_y"): [], ("free", "Ca_hat"): [], ("free", "Kc_hat"): []}
    sigma_fitted = 0
    started = time.perf_counter()
    for _ in range(ns.trials):
        data, _ = synthetic(constrained_truth, np.geomspace(2.0, 100.0, 12), rng)
        fit = fit_constrained(data, ALUMINIUM, table)
        records[("constrained", "sigma_y")].append((fit.values["sigma_y"], fit.standard_errors["sigma_y"]))
        data, _ = synthetic(free_truth, np.geomspace(1.5, 300.0, 20), rng)
        fit = fit_free(data, ALUMINIUM, SIGMA_Y, None, table)
        sigma_fitted += "sigma_y" in fit.spec.free
        for name in FREE_TRUTH:
            records[("free", name)].append((fit.values[name], fit.standard_errors[name]))
    truth = {"sigma_y": SIGMA_Y, **FREE_TRUTH}
    print(f"{ns.trials} trials, seed {ns.seed}, noise 1..3 % on e, {time.perf_counter() - started:.0f} s")
    print("| model | parameter | true | mean estimate | bias | median relative SE | coverage (2 SE) | sigma_Y fitted |")
    print("|---|---|---|---|---|---|---|---|")
    for (model, name), rows in records.items():
        estimate = np.array([r[0] for r in rows])
        se = np.array([r[1] for r in rows])
        true = truth[name]
        bias = estimate.mean() / true - 1.0
        bias_se = estimate.std(ddof=1) / np.sqrt(estimate.size) / true
        coverage = np.mean(np.abs(estimate - true) <= 2.0 * se)
        print(f"| {model} | {name} | {true:.4g} | {estimate.mean():.4g} | {100 * bias:+.2f} % (+- {100 * bias_se:.2f}) "
              f"| {100 * np.median(se / estimate):.2f} % | {100 * coverage:.0f} % | "
              f"{sigma_fitted if model == 'free' else '-'} of {ns.trials} |")

    plausibility(ns.refusal_trials, ns.seed, table, constrained_truth, free_truth)


PLAUSIBILITY_NOISE = (0.0, 0.01, 0.03, 0.10, 0.20)


def plausibility(trials: int, seed: int, table, constrained_truth, free_truth) -> None:
    """The second table (module doc)."""
    rng = np.random.default_rng(seed + 1)
    started = time.perf_counter()
    rows = []
    for noise in PLAUSIBILITY_NOISE:
        ratios, refused, mismatched = {"constrained": [], "free": []}, {"constrained": 0, "free": 0}, \
            {"constrained": 0, "free": 0}
        for _ in range(trials):
            for model, truth, design in (("constrained", constrained_truth, np.geomspace(2.0, 100.0, 12)),
                                         ("free", free_truth, np.geomspace(1.5, 300.0, 20))):
                data, _ = synthetic(truth, design, rng, noise)
                try:
                    fit = (fit_constrained(data, ALUMINIUM, table) if model == "constrained"
                           else fit_free(data, ALUMINIUM, SIGMA_Y, None, table))
                except DataMismatch:
                    mismatched[model] += 1
                    continue
                group = fit.scatter.groups["e"]
                ratios[model].append(group["chi2"] / group["threshold"])
                refused[model] += not fit.scatter.plausible
        rows.append((noise, ratios, refused, mismatched))
    print(f"\nrefusal of implausible fits: {trials} trials per noise level, {time.perf_counter() - started:.0f} s")
    print("| noise on e | model | largest chi2 / threshold | refused as implausible | refused as not fittable |")
    print("|---|---|---|---|---|")
    for noise, ratios, refused, mismatched in rows:
        for model in ("constrained", "free"):
            largest = f"{max(ratios[model]):.3g}" if ratios[model] else "-"
            print(f"| {100 * noise:g} % | {model} | {largest} | {refused[model]} of {trials} | "
                  f"{mismatched[model]} of {trials} |")


if __name__ == "__main__":
    main()

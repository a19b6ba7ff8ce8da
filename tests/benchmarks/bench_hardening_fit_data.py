"""Benchmark: sigma_Y and H fitted together (calib.fit.measured.hardening_fit) on FE drop tests of hardening spheres.

Not a timed test: for each finite-strain [[check]] sphere of the hardening sheet's scene (vz_master_reach_hardening:
FE load-unload paths from 50 P_Y to the window's top, off the sheet's nodes in nu, E/sigma_Y and H/E) fits sigma_Y
and H to the FE's own drop tests (e and P_max at each path's impact speed) and prints

- noise-free: ln(fitted / true) of sigma_Y and H (what the fit's model-form terms U_LN_SIGMA_Y, U_LN_H are the rms
  of, over these checks and the data kinds of ``--kinds``);
- noisy trials (``--trials`` per check, e and P_max each times 1 + N(0, ``--noise``), the fit told that noise):
  the rms error of sigma_Y and H, the share of trials whose 95 % intervals hold the true sigma_Y and H (target
  >= 90 %), with the shipped model-form terms and with terms held out (the rms over the other checks' noise-free
  fits, so no check's interval is widened by its own error), the share in which the data determine H
  (statistical relative standard error <= 10 %), and the CPU time per fit.

The targets of the hardening fit: sigma_Y within 3 %, H within 10 % where the data determine it, coverage >= 90 %.
About 1-2 s of CPU per fit (6-7 drop tests, e and P_max).
Usage: .venv/bin/python tests/benchmarks/bench_hardening_fit_data.py [--trials 20] [--noise 0.01] [--seed 1]
       [--kinds "drops e+P"]
"""
from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import numpy as np

from calib.fit import vz_hardening, vz_master_build, vz_master_join, vz_master_scene
from calib.fit.measured import hardening_fit, two_parameter
from calib.fit.vz_master_check import fe_datasets, measurements
from calib.fit.vz_master_table import VZMasterTable

ROOT = Path(__file__).resolve().parents[2]
SCENE = "vz_master_reach_hardening"


def finite_checks() -> list[dict]:
    """The finite-strain scene's [[check]] records of linear hardening (results/tables/vz_master_reach_hardening;
    its power-law checks have no one H to fit)."""
    scene = vz_master_scene.load_scene(SCENE)
    rows = vz_master_join.scene_records(scene, ROOT / "results" / "tables" / SCENE)
    return [r for r in rows if r.get("kind") == "check" and not r.get("power_law")]


def fit_once(kind: str, values: dict, sets: dict, master, sheet, noise: float | None):
    return hardening_fit.fit(measurements(kind, values, "fe"), sets["specimen"], master, sheet, noise=noise)


def held_out_interval(result, u_ln_sigma_y: float, u_ln_H: float) -> dict:
    """The fit's 95 % intervals with the model-form terms U_LN_SIGMA_Y, U_LN_H replaced (the statistical part and
    the table's own term kept): calib.fit.measured.two_parameter.intervals."""
    names = ("sigma_y", "hardening_modulus")
    spread, values = result.spread, result.values
    v_stat = np.diag([(spread["se_stat"][k] / values[k]) ** 2 for k in names])
    u_table = result.uncertainty["u_ln_sigma_y_table"]
    v_model = np.diag([u_table**2 + u_ln_sigma_y**2, u_ln_H**2])
    n = int(round(result.uncertainty["dof_statistical"])) + 2
    return two_parameter.intervals(names, values, v_stat, v_model, n)["interval95"]


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trials", type=int, default=20, help="noisy trials per check and data kind")
    parser.add_argument("--noise", type=float, default=0.01, help="relative scatter of e and P_max")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--kinds", nargs="+", default=["drops e+P"], help="data kinds (calib.fit.vz_master_check)")
    ns = parser.parse_args(argv)
    master, sheet = VZMasterTable.load(), vz_hardening.HardeningSheet.load()
    rng = np.random.default_rng(ns.seed)
    truths = ("sigma_y", "hardening_modulus")
    cases = []
    for row in finite_checks():
        sets = fe_datasets(row, vz_hardening.HardenedMasterTable(master, sheet, row["H_over_E"]))
        truth = {"sigma_y": sets["sigma_y"], "hardening_modulus": row["H_over_E"] * sets["specimen"].E}
        clean = {**sets["drops"], "approach": sets["force"][0], "force": sets["force"][1]}
        for kind in ns.kinds:
            result = fit_once(kind, clean, sets, master, sheet, None)
            cases.append({"row": row, "sets": sets, "truth": truth, "clean": clean, "kind": kind,
                          "exact": {key: math.log(result.values[key] / truth[key]) for key in truths}})
    print(f"sheet {sheet.path.name} ({sheet.nu_label}); model form U_LN_SIGMA_Y {hardening_fit.U_LN_SIGMA_Y:g}, "
          f"U_LN_H {hardening_fit.U_LN_H:g}; {ns.trials} trials per row, noise {100 * ns.noise:g} % on e and P_max")
    for key, name in (("sigma_y", "ln sigma_Y"), ("hardening_modulus", "ln H")):
        rms = math.sqrt(np.mean([c["exact"][key] ** 2 for c in cases]))
        print(f"noise-free rms of {name} over the rows: {rms:.3g}")
    print("| check | kind | paths | P_max/P_Y | noise-free sigma_Y | noise-free H | rms sigma_Y | rms H | "
          "95 % covers sigma_Y (held out) | 95 % covers H (held out) | H determined | s per fit |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for case in cases:
        others = [c["exact"] for c in cases if c["row"]["name"] != case["row"]["name"]]
        held = [math.sqrt(np.mean([e[key] ** 2 for e in others])) if others else 0.0 for key in truths]
        truth, clean, sets = case["truth"], case["clean"], case["sets"]
        started = time.process_time()
        errors, covered, covered_held, determined = [], dict.fromkeys(truths, 0), dict.fromkeys(truths, 0), 0
        for _ in range(ns.trials):
            scatter = {key: clean[key] * (1.0 + ns.noise * rng.standard_normal(clean[key].size))
                       for key in ("e", "P_max")}
            try:
                noisy = fit_once(case["kind"], {**clean, **scatter}, sets, master, sheet, ns.noise)
            except ValueError:          # a fit on a bound: counted as not covering
                continue
            errors.append({key: math.log(noisy.values[key] / truth[key]) for key in truths})
            intervals = held_out_interval(noisy, *held)
            for key in truths:
                low, high = noisy.interval95[key]
                covered[key] += low <= truth[key] <= high
                low, high = intervals[key]
                covered_held[key] += low <= truth[key] <= high
            determined += noisy.identifiability["hardening_determined"]
        per_fit = (time.process_time() - started) / max(ns.trials, 1)
        rms = {key: math.sqrt(np.mean([e[key] ** 2 for e in errors])) if errors else math.nan for key in truths}
        exact, P_Y = case["exact"], case["row"]["P_Y"]
        print(f"| {case['row']['name']} | {case['kind']} | {clean['v_in'].size} | {clean['P_max'].min() / P_Y:.3g}-"
              f"{clean['P_max'].max() / P_Y:.4g} | {100 * exact['sigma_y']:+.2f} % | "
              f"{100 * exact['hardening_modulus']:+.1f} % | {100 * rms['sigma_y']:.2f} % | "
              f"{100 * rms['hardening_modulus']:.1f} % | {covered['sigma_y']}/{ns.trials} "
              f"({covered_held['sigma_y']}/{ns.trials}) | {covered['hardening_modulus']}/{ns.trials} "
              f"({covered_held['hardening_modulus']}/{ns.trials}) | {determined}/{ns.trials} | {per_fit:.1f} |")


if __name__ == "__main__":
    main()

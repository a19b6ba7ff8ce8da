"""Benchmark: ``nfdcal fit-data --rate-law`` on dynamic FE drop tests with a rate-dependent sphere.

Not a timed test: for each series of tests/data/rate_fe_drops.json (``nfdcal impact --rate-law`` on the coarse
mesh, the reference aluminium, five rate laws; ``--fe`` reruns those FE impacts first, about 5 minutes on one
core, and prints their e beside the stored ones) fits, on each form of the rate-aware vz-table law (fixed and
relaxing; calib.fit.measured.rate_fit), sigma_Y and the rate constant together, and the constant alone with
sigma_Y held at the FE sphere's (``fit-data --hold-sigma-y``), each to e alone and to e, P_max and contact time,
and prints: R over the tests at the FE's constants (relaxing: s at the turning point) and the law's e there
against the FE's, the fitted values against the FE's (targets: 3 %, 10 %), their statistical relative standard
errors, sigma_Y R at the tests' mean strain rate against the FE sphere's, the 95 % intervals (over the truth)
and whether they cover it, whether fit-data refuses, and each fit's run time (the figures of
calib/fit/README.md, Strain-rate dependence). About 8 minutes without --fe. ``--trials N`` instead: N noisy
trials per series of the held relaxing fit on e with 1 % scatter (accepted, rms error, interval coverage).
Usage: .venv/bin/python tests/benchmarks/bench_rate_fit_data.py [--fe | --trials N]
"""
from __future__ import annotations

import argparse
import contextlib
import io
import json
import tempfile
import time
from pathlib import Path

import numpy as np

from calib.cli import main
from calib.fit.measured import data as measured_data
from calib.fit.measured import rate_fit
from calib.fit.measured.specimen import Specimen
from calib.fit.vz_master_table import VZMasterTable
from nfdmodel.strain_rate import rate_law_of

DATA = Path(__file__).resolve().parents[1] / "data" / "rate_fe_drops.json"
FLAGS = {"cowper-symonds": ("--cs-D", "D", "--cs-q", "q"), "johnson-cook": ("--jc-C", "C", "--jc-reference-rate",
                                                                            "reference_rate")}


def rerun_fe(law: dict, speeds, folder: Path) -> np.ndarray:
    free, name, fixed, fixed_name = FLAGS[law["rate_law"]]
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        code = main(["impact", "--v-in", *map(str, speeds), "--contact-size", "1.6e-4", "--rate-law", law["rate_law"],
                     free, str(law[name]), fixed, str(law[fixed_name]), "--no-error-estimate", "--no-quasi-static",
                     "--no-plots", "--workers", "1", "--out", str(folder), "--json", "--quiet"])
    assert code == 0
    return np.array([record["e"] for record in json.loads(printed.getvalue())])


def main_(fe: bool) -> None:
    data = json.loads(DATA.read_text(encoding="utf-8"))
    sigma_y = data["specimen"]["sigma_y"]
    specimen, table = Specimen(70e9, 0.3, 0.1, 2699.0, False), VZMasterTable.load(None)
    print(f"{data['made_by']}")
    with tempfile.TemporaryDirectory() as folder:
        for series, entry in data["series"].items():
            law, tests = entry["rate_law"], entry["tests"]
            kind = law["rate_law"]
            name, fixed = rate_fit.FREE[kind], law[rate_fit.FIXED[kind]]
            v = np.array([t["v_in"] for t in tests])
            stored = np.array([t["e"] for t in tests])
            if fe:
                again = rerun_fe(law, v, Path(folder) / series.replace(" ", "_"))
                print(f"{series}: FE e rerun {np.round(again, 4)} against stored {np.round(stored, 4)}")
            for form in rate_fit.LENGTH_FACTOR:
                truth = rate_fit.rate_params(specimen, table, kind, sigma_y, law[name], fixed, form=form)
                e_law = rate_fit.predict(truth, v)["e"]
                _, factors = rate_fit.rates_and_factors(truth, v)
                print(f"{series}, {form} form: v_in {v.min():g}..{v.max():g} m/s, R at the FE's constants "
                      f"{factors.min():.3f}..{factors.max():.3f}; e at them against the FE's: "
                      f"{np.round(100 * (e_law / stored - 1), 2)} %")
                for held in (False, True):
                    for columns in (("v_in", "e"), ("v_in", "e", "P_max", "contact_time")):
                        path = Path(folder) / "drops.csv"
                        path.write_text(",".join(columns) + "\n" + "".join(
                            ",".join(repr(float(t[c])) for c in columns) + "\n" for t in tests))
                        started = time.perf_counter()
                        try:
                            found = rate_fit.fit(measured_data.Measurements(
                                impacts=measured_data.read_impacts(path), forces=None), specimen, table, kind, fixed,
                                sigma_y if held else None, form=form, hold_sigma_y=held)
                        except ValueError as refused:        # fit-data's one-line refusal before any figure
                            print(f"  {'sigma_Y held' if held else 'both':>12} {'+'.join(columns[1:]):>20}: refused: "
                                  f"{str(refused).split(': ', 1)[1]}")
                            continue
                        print_fit(found, "+".join(columns[1:]), held, sigma_y, law, name,
                                  time.perf_counter() - started)


def print_fit(found, data: str, held: bool, sigma_y: float, law: dict, name: str, seconds: float) -> None:
    """One row: the fit against the FE's constants, its intervals and fit-data's verdict."""
    flow = found.identifiability["determined_combination"]
    flow_truth = sigma_y * float(rate_law_of(law).factor(flow["strain_rate"]))
    rel = found.identifiability["relative_se"]
    truths = {"sigma_y": sigma_y, name: law[name]}
    fitted = [key for key in truths if key in found.interval95]
    print(f"  {'sigma_Y held' if held else 'both':>12} {data:>20}: "
          + ", ".join(f"{key} {100 * (found.values[key] / truths[key] - 1):+8.1f} % (statistical SE "
                      f"{100 * rel[key]:.2g} %)" for key in fitted)
          + f"; sigma_Y R at {flow['strain_rate']:.3g} /s {100 * (flow['value'] / flow_truth - 1):+.2f} %; 95 % "
          + ", ".join(f"{key} {low / truths[key]:.3g}..{high / truths[key]:.3g} x "
                      f"({'covers' if low <= truths[key] <= high else 'misses'})"
                      for key in fitted for low, high in [found.interval95[key]])
          + "; " + ("refused" if rate_fit.refusal(found) else "accepted") + f"; {seconds:.1f} s")


def noisy_trials(trials: int, noise: float, seed: int = 1) -> None:
    """The held relaxing fit (e alone, ``--noise``) on each FE series' e scattered by ``noise`` (relative, normal):
    how often fit-data accepts, the rms error of the accepted constants, and how often their 95 % interval covers
    the FE's constant."""
    data = json.loads(DATA.read_text(encoding="utf-8"))
    sigma_y = data["specimen"]["sigma_y"]
    specimen, table = Specimen(70e9, 0.3, 0.1, 2699.0, False), VZMasterTable.load(None)
    rng = np.random.default_rng(seed)
    print(f"\nsigma_Y held, relaxing form, e alone with {100 * noise:g} % scatter, {trials} trials per series:")
    print("| FE rate law | accepted | rms error of the constant % | 95 % interval covers (of accepted) |\n"
          "|---|---|---|---|")
    with tempfile.TemporaryDirectory() as folder:
        for series, entry in data["series"].items():
            law, tests = entry["rate_law"], entry["tests"]
            kind = law["rate_law"]
            name, fixed = rate_fit.FREE[kind], law[rate_fit.FIXED[kind]]
            errors, covered = [], 0
            for _ in range(trials):
                path = Path(folder) / "drops.csv"
                path.write_text("v_in,e\n" + "".join(f"{t['v_in']!r},{t['e'] * (1 + noise * rng.standard_normal())!r}\n"
                                                     for t in tests))
                try:
                    found = rate_fit.fit(measured_data.Measurements(impacts=measured_data.read_impacts(path),
                                                                    forces=None), specimen, table, kind, fixed, sigma_y,
                                         noise=noise, form="relaxing", hold_sigma_y=True)
                except ValueError:
                    continue
                if rate_fit.refusal(found):
                    continue
                errors.append(found.values[name] / law[name] - 1.0)
                low, high = found.interval95[name]
                covered += low <= law[name] <= high
            accepted = len(errors)
            rms = f"{100 * np.sqrt(np.mean(np.square(errors))):.1f}" if accepted else "-"
            print(f"| {series} | {accepted} of {trials} | {rms} | {covered} of {accepted} |", flush=True)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--fe", action="store_true", help="rerun the FE impacts of the stored data first")
    parser.add_argument("--trials", type=int, default=0, help="noisy trials of the held relaxing fit per series "
                                                              "(1 %% scatter; about 6 s each)")
    arguments = parser.parse_args()
    if arguments.trials:
        noisy_trials(arguments.trials, 0.01)
    else:
        main_(arguments.fe)

"""Benchmark: ``nfdcal fit-data --rate-law`` on dynamic FE drop tests with a rate-dependent sphere.

Not a timed test: for each series of tests/data/rate_fe_drops.json (``nfdcal impact --rate-law`` on the coarse
mesh, the reference aluminium, five rate laws; ``--fe`` reruns those FE impacts first, about 5 minutes on one
core, and prints their e beside the stored ones) fits sigma_Y and the rate constant on the rate-aware vz-table
law (calib.fit.measured.rate_fit) to e alone and to e, P_max and contact time, and prints: R over the tests at
the FE's constants, the fitted sigma_Y and constant against the FE's (targets: 3 %, 10 %), their statistical
relative standard errors, sigma_Y R at the tests' mean strain rate against the FE sphere's, the 95 % intervals
(over the truth) and whether they cover it, whether fit-data refuses, and the rate-aware law's e at the FE's
own constants against the FE's (the figures of calib/fit/README.md, Strain-rate dependence). About 1 minute
without --fe.
Usage: .venv/bin/python tests/benchmarks/bench_rate_fit_data.py [--fe]
"""
from __future__ import annotations

import argparse
import contextlib
import io
import json
import tempfile
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
            truth = rate_fit.rate_params(specimen, table, kind, sigma_y, law[name], fixed)
            e_law = rate_fit.predict(truth, v)["e"]
            print(f"{series}: v_in {v.min():g}..{v.max():g} m/s, R at the FE's constants "
                  f"{truth.rate_factor(v).min():.3f}..{truth.rate_factor(v).max():.3f}; rate-aware e at them against "
                  f"the FE's: {np.round(100 * (e_law / stored - 1), 2)} %")
            for columns in (("v_in", "e"), ("v_in", "e", "P_max", "contact_time")):
                path = Path(folder) / "drops.csv"
                path.write_text(",".join(columns) + "\n" + "".join(
                    ",".join(repr(float(t[c])) for c in columns) + "\n" for t in tests))
                found = rate_fit.fit(measured_data.Measurements(impacts=measured_data.read_impacts(path), forces=None),
                                     specimen, table, kind, fixed)
                flow = found.identifiability["determined_combination"]
                flow_truth = sigma_y * float(rate_law_of(law).factor(flow["strain_rate"]))
                rel = found.identifiability["relative_se"]
                covers = {key: found.interval95[key][0] <= truth_value <= found.interval95[key][1]
                          for key, truth_value in (("sigma_y", sigma_y), (name, law[name]))}
                print(f"  {'+'.join(columns[1:]):>20}: sigma_Y {100 * (found.values['sigma_y'] / sigma_y - 1):+6.1f} %, "
                      f"{name} {100 * (found.values[name] / law[name] - 1):+8.1f} % (statistical relative SE "
                      f"{100 * rel['sigma_y']:.2g} %, {100 * rel[name]:.2g} %); sigma_Y R at {flow['strain_rate']:.3g} /s "
                      f"{100 * (flow['value'] / flow_truth - 1):+.2f} %; 95 % intervals "
                      + ", ".join(f"{key} {low / truth:.3g}..{high / truth:.3g} x "
                                  f"({'covers' if covers[key] else 'misses'})"
                                  for key, truth in (("sigma_y", sigma_y), (name, law[name]))
                                  for low, high in [found.interval95[key]])
                      + "; " + ("refused" if rate_fit.refusal(found) else "accepted"))


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--fe", action="store_true", help="rerun the FE impacts of the stored data first")
    main_(parser.parse_args().fe)

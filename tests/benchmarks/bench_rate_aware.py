"""Benchmark: the rate-aware law (nfdmodel.rate_aware) against the dynamic FE with the rate law, 3 speeds x 2 laws.

Not a timed test: runs ``nfdcal impact`` on the coarse mesh (contact element 1.6e-4 m, 100 steps per contact,
no error estimate) at 0.01, 0.02 and 0.04 m/s for the rate-independent sphere, Cowper-Symonds D = 40 /s,
q = 5 (mild steel) and Johnson-Cook C = 0.05, eps_dot_0 = 1e-3 /s, and prints each FE e beside the
rate-aware law's on the shipped vz-table law (results/calibration/parameters.json) and the rate-independent
law's, with their differences (target: the rate-aware law within 2 % in e). Also prints c, the constant of
eps_dot = v_n0 / (c a_ref) that matches the FE's Cowper-Symonds e at 0.02 m/s (how RATE_LENGTH_FACTOR was
fixed). About 1 minute on one core.
Usage: .venv/bin/python tests/benchmarks/bench_rate_aware.py [--out DIR]
"""
from __future__ import annotations

import argparse
import contextlib
import io
import json
import tempfile
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

from calib.cli import main
from nfdmodel import collide, collision_reference, load_parameters
from nfdmodel.rate_aware import LAW, RATE_LENGTH_FACTOR, RateAwareParams
from nfdmodel.strain_rate import CowperSymonds, JohnsonCook

SHIPPED = Path(__file__).resolve().parents[2] / "results" / "calibration" / "parameters.json"
SPEEDS = (0.01, 0.02, 0.04)
CASES = {"rate-independent": ([], None),
         "cowper-symonds": (["--rate-law", "cowper-symonds", "--cs-D", "40", "--cs-q", "5"], CowperSymonds(40.0, 5.0)),
         "johnson-cook": (["--rate-law", "johnson-cook", "--jc-C", "0.05", "--jc-reference-rate", "1e-3"],
                          JohnsonCook(0.05, 1e-3))}


def fe_restitution(flags, out: Path) -> np.ndarray:
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        code = main(["impact", "--v-in", *map(str, SPEEDS), "--contact-size", "1.6e-4", *flags, "--no-error-estimate",
                     "--no-quasi-static", "--no-plots", "--workers", "1", "--out", str(out), "--json", "--quiet"])
    assert code == 0
    return np.array([record["e"] for record in json.loads(printed.getvalue())])


def main_(out: Path) -> None:
    table = load_parameters(SHIPPED)
    v = np.array(SPEEDS)
    independent = collide("vz-table", table, v, dt=None).e_velocity
    for name, (flags, rate_law) in CASES.items():
        fe = fe_restitution(flags, out / name)
        print(f"{name}: FE e {np.round(fe, 4)}; rate-independent law {np.round(independent, 4)} "
              f"({np.round(100 * (independent / fe - 1), 2)} %)")
        if rate_law is None:
            continue
        params = RateAwareParams("vz-table", table, rate_law)
        law = collide(LAW, params, v, dt=None).e_velocity
        print(f"  rate-aware law (c = {RATE_LENGTH_FACTOR:g}): R {np.round(params.rate_factor(v), 4)}, e "
              f"{np.round(law, 4)} ({np.round(100 * (law / fe - 1), 2)} %)")
        if name == "cowper-symonds":
            target = fe[SPEEDS.index(0.02)]
            c = brentq(lambda c: collision_reference(LAW, RateAwareParams("vz-table", table, rate_law, c),
                                                     [0.02]).restitution[0] - target, 2.0, 500.0)
            print(f"  c matching the FE's e at 0.02 m/s: {c:.3g}")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default=None, help="folder for the FE runs (default: a temporary one)")
    args = parser.parse_args()
    if args.out is None:
        with tempfile.TemporaryDirectory() as folder:
            main_(Path(folder))
    else:
        main_(Path(args.out))

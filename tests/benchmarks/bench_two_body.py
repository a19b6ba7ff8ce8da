"""Benchmark: the sphere on a deformable counter-body (target: a converged two-body calibration,
both meshes and the error estimate, in at most 60 s on 2 cores).

Not a timed test: prints two tables.
1. ``nfdcal hertz`` with a counter-body on the default mesh (aluminium R = 0.1 m on a steel sphere
   R = 0.05 m and on a steel flat, 1..500 N): contact radius and peak pressure against Hertz with
   the pair's E* and R* (targets 0.5 % and 2 %), wall time.
2. ``nfdcal calibrate`` of aluminium on an elastic steel flat, converged as shipped: two meshes
   (the second on another process), Richardson extrapolation and its error estimates of Ca, Kc
   and e (the benchmark stops if they are missing); wall time against the target, each mesh's
   time, Ca_hat, Kc_hat, e; and the rigid-flat calibration of the same sphere for comparison.
Usage: .venv/bin/python tests/benchmarks/bench_two_body.py [--skip-calibration]
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

TARGET_S = 60.0
STEEL = ["--counter-E", "200e9", "--counter-nu", "0.28"]


def nfdcal(*args) -> tuple[dict, float]:
    command = Path(sys.executable).with_name("nfdcal")
    with tempfile.TemporaryDirectory() as out:
        t0 = time.perf_counter()
        proc = subprocess.run([str(command), *args, "--json", "--out", out], capture_output=True, text=True,
                              check=True)
        return json.loads(proc.stdout), time.perf_counter() - t0


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--skip-calibration", action="store_true", help="the Hertz table only")
    ns = parser.parse_args(argv)
    print(f"{'Hertz, counter-body':28} {'dofs':>7} {'wall s':>7} {'a err %':>8} {'p0 err %':>9}")
    for label, extra in (("steel sphere R = 0.05 m", ["--counter-R", "0.05"]), ("steel flat", [])):
        summary, wall = nfdcal("hertz", "--P-max", "500", *STEEL, *extra)
        top = summary["top_load"]
        print(f"{label:28} {summary['stamp']['mesh']['n_dofs']:7d} {wall:7.1f} "
              f"{100 * top['contact_radius_rel_error']:+8.3f} {100 * top['peak_pressure_rel_error']:+9.3f}")
    if ns.skip_calibration:
        return 0
    print(f"\n{'calibration (two meshes)':28} {'wall s':>7} {'mesh 1 s':>8} {'mesh 2 s':>8} {'Ca_hat':>8} "
          f"{'Kc_hat':>8} {'Ca err %':>9} {'Kc err %':>9} {'e (41 P_Y)':>10} {'e err %':>8}")
    for label, extra in (("Al on a rigid flat", []), ("Al on an elastic steel flat", STEEL)):
        summary, wall = nfdcal("calibrate", "--quiet", "--no-plots", *extra)
        top, timings = summary["paths"][-1], summary["timings"]
        errors = [summary.get("Ca_rel_error_estimate"), summary.get("Kc_rel_error_estimate"),
                  top.get("e_rel_error_estimate")]
        if any(x is None for x in errors):
            raise SystemExit(f"{label}: the calibration shipped no error estimate (one mesh)")
        first = timings["mesh_s"] + timings["first_yield_s"] + timings["load_paths_s"]
        print(f"{label:28} {wall:7.1f} {first:8.1f} {timings['second_mesh_s']:8.1f} {summary['Ca_hat']:8.4f} "
              f"{summary['Kc_hat']:8.4f} {100 * errors[0]:9.2f} {100 * errors[1]:9.2f} {top['e']:10.4f} "
              f"{100 * errors[2]:8.2f}")
    print(f"target: a two-body calibration in at most {TARGET_S:g} s on 2 cores")
    return 0


if __name__ == "__main__":
    sys.exit(main())

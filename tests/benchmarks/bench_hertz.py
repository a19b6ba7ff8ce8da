"""Benchmark: the whole `nfdcal hertz` at the default mesh (target <= 10 s on 2 cores).

Not a timed test: prints a table of wall times (whole command as a subprocess, and the split
mesh / setup / steps / assembly / solve from the run's own stamp) and the Hertz errors.
Usage: .venv/bin/python tests/benchmarks/bench_hertz.py [--repeat 2]
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

TARGET_S = 10.0


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=2)
    ns = parser.parse_args(argv)
    nfdcal = Path(sys.executable).with_name("nfdcal")
    rows = []
    for k in range(ns.repeat):
        with tempfile.TemporaryDirectory() as out:
            t0 = time.perf_counter()
            proc = subprocess.run([str(nfdcal), "hertz", "--json", "--out", out],
                                  capture_output=True, text=True, check=True)
            wall = time.perf_counter() - t0
        summary = json.loads(proc.stdout)
        st, top = summary["stamp"], summary["top_load"]
        rows.append({"run": k + 1, "command_s": wall, "solver_run_s": st["wall_time_s"],
                     "mesh_s": st["time_mesh_s"], "steps_s": st["time_steps_s"],
                     "assembly_s": st["time_assembly_s"], "solve_s": st["time_solve_s"],
                     "factorizations": summary["factorizations"],
                     "a_err_%": 100 * top["contact_radius_rel_error"],
                     "p0_err_%": 100 * top["peak_pressure_rel_error"],
                     "alpha_err_%": 100 * top["alpha_rel_error"]})
    keys = list(rows[0])
    print(" ".join(f"{k:>14s}" for k in keys))
    for r in rows:
        print(" ".join(f"{r[k]:14.4g}" if isinstance(r[k], float) else f"{r[k]:>14}" for k in keys))
    best = min(r["command_s"] for r in rows)
    print(f"best whole command: {best:.2f} s (target <= {TARGET_S} s): "
          f"{'OK' if best <= TARGET_S else 'OVER'}")


if __name__ == "__main__":
    main()

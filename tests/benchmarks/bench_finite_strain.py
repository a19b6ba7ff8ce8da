"""Benchmark: the finite-strain press against the small-strain press on the same coarse mesh (target:
finite strain at most 3x the CPU time of small strain).

Not a timed test: prints one table, a row per kinematics (CPU time, sub-steps, Newton iterations, the
force and contact radius reached) and the CPU-time ratio. The press is the reference sphere
(nfdmodel.reference_case) on the rigid flat under displacement control, calib.fe.loadpath.run_press,
to the approach ``--approach`` x R (default 0.1: a/R about 0.48).
Usage: .venv/bin/python tests/benchmarks/bench_finite_strain.py [--approach 0.1] [--contact-size 0.04]
"""
from __future__ import annotations

import argparse
import tempfile
import time

import numpy as np

from calib.fe import ContactSolver, VonMisesMaterial
from calib.fe.loadpath import run_press
from meshes.hemisphere import HemisphereMeshSpec, hemisphere_mesh
from nfdmodel import reference_case as rc

TARGET_RATIO = 3.0


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--approach", type=float, default=0.1, help="the last approach / R")
    parser.add_argument("--contact-size", type=float, default=0.04, help="contact element / R")
    parser.add_argument("--steps", type=int, default=12, help="log-spaced approaches from 2e-4 R")
    ns = parser.parse_args(argv)
    R = rc.R
    spec = HemisphereMeshSpec(radius=R, contact_size=ns.contact_size * R, refined_radius=0.6 * R,
                              refined_depth=0.3 * R, far_size=R / 6)
    approaches = np.geomspace(2e-4, ns.approach, ns.steps) * R
    rows = []
    with tempfile.TemporaryDirectory() as cache:
        mesh = hemisphere_mesh(spec, cache_dir=cache)
        for name in ("small-strain", "finite-strain"):
            solver = ContactSolver(mesh, VonMisesMaterial(rc.E, rc.NU, rc.SIGMA_Y), kinematics=name)
            t0 = time.process_time()
            at_targets, steps, _ = run_press(solver, approaches)
            cpu = time.process_time() - t0
            last = at_targets[-1].record
            rows.append((name, solver.n_dofs, cpu, len(steps), sum(r.record.newton_iterations for r in steps),
                         last.P, last.contact_radius / R))
    print(f"{'kinematics':14s} {'dofs':>6s} {'cpu_s':>8s} {'steps':>6s} {'newton':>7s} {'P_N':>11s} {'a/R':>7s}")
    for name, dofs, cpu, n_steps, newton, P, a in rows:
        print(f"{name:14s} {dofs:6d} {cpu:8.2f} {n_steps:6d} {newton:7d} {P:11.5g} {a:7.4f}")
    ratio = rows[1][2] / rows[0][2]
    print(f"finite / small CPU time: {ratio:.2f} (target <= {TARGET_RATIO:g})")


if __name__ == "__main__":
    main()

"""Benchmark: a mesh and step ladder of the finite-strain press at a/R about 0.3 and 0.45, with the
observed orders and Richardson-extrapolated values.

Not a timed test: prints tables. The press is the reference sphere (nfdmodel.reference_case, E/sigma_Y
700, perfectly plastic) on the rigid flat under displacement control, calib.fe.loadpath.run_press (each
increment halved where Newton fails), to fixed approaches ``--approaches`` x R (default 0.035 and 0.085:
a/R about 0.3 and 0.45 in finite strain). At each approach the force P and the contact radius a are read.

Meshes: the hemisphere mesh (meshes.hemisphere), refined zone 0.6 R x 0.3 R, growth 0.2 beyond; ``--levels``
meshes (default 3) whose contact element and far-field size scale by ``--ratio`` (default sqrt 2: contact
elements R/20, R/28.3, R/40, R/56.6, ...; far field R/6, R/8.5, R/12, ...), each three consecutive ones a
ladder. Steps: the approaches log-spaced from 2e-4 R, ``--steps`` intervals to the first approach and half
as many between later ones, times 1, 2 and 4 (a step ratio of 2 in log-approach; run_press halves further
where Newton needs it). The mesh ladder runs at the finest step (x4), the step ladder on the coarsest and
finest meshes.

For three values f1, f2, f3 (coarse to fine) at a constant refinement ratio r:

    p     = ln((f1 - f2) / (f2 - f3)) / ln r                       (observed order)
    f_ext = f3 + (f3 - f2) / (r^p - 1)                              (Richardson extrapolation)
    err   = (f_ext - f3) / f_ext                                    (the estimated error of f3)

(Roache 1998, Verification and Validation in Computational Science and Engineering, ch. 5). When the
differences change sign (no monotone convergence) p is undefined, and when p <= 0 (diverging) f_ext is;
printed as "-". The spread (max - min) / f3 of the three is printed beside: where the ladder is not in its
asymptotic range it is the error estimate. The finite-strain force is compared with the
small-strain press on the same meshes (``--no-small`` skips those runs).
Usage: .venv/bin/python tests/benchmarks/ladder_finite_strain.py [--approaches 0.035 0.085] [--steps 9]
       [--levels 3] [--no-small]   (about 2 minutes on one core; --levels 4 about 6)
"""
from __future__ import annotations

import argparse
import sys
import tempfile
import time

import numpy as np

from calib.fe import ContactSolver, VonMisesMaterial
from calib.fe.loadpath import run_press
from meshes.hemisphere import HemisphereMeshSpec, hemisphere_mesh
from nfdmodel import reference_case as rc

R = rc.R
FIRST = 2e-4          # the first approach / R (elastic, below yield's tenth)
STEP_FACTORS = (1, 2, 4)   # the step ladder: intervals per segment x these


def mesh_spec(level: int, ratio: float) -> HemisphereMeshSpec:
    """Level 0, 1, 2: contact element R/20, far field R/6, each divided by ratio^level."""
    scale = ratio ** level
    return HemisphereMeshSpec(radius=R, contact_size=R / (20.0 * scale), refined_radius=0.6 * R,
                              refined_depth=0.3 * R, far_size=R / (6.0 * scale))


def approach_path(targets, steps: int, factor: int) -> np.ndarray:
    """Log-spaced approaches [m] from FIRST R through each target: steps x factor intervals to the
    first target, (steps // 2) x factor between later ones (each target a point of the path)."""
    points, start = [FIRST], FIRST
    for i, target in enumerate(targets):
        n = (steps if i == 0 else max(steps // 2, 1)) * factor
        points.extend(np.geomspace(start, target, n + 1)[1:])
        start = target
    return np.array(points) * R


def press(mesh, kinematics: str, path: np.ndarray, targets) -> dict:
    """One press; the force [N] and contact radius [m] at each target, sub-steps, CPU time [s]."""
    solver = ContactSolver(mesh, VonMisesMaterial(rc.E, rc.NU, rc.SIGMA_Y), kinematics=kinematics)
    t0 = time.process_time()
    at_points, steps, _ = run_press(solver, path)
    cpu = time.process_time() - t0
    records = [at_points[int(np.argmin(np.abs(path - t * R)))].record for t in targets]
    print(f"{kinematics} {solver.n_dofs} dofs, {len(steps)} steps, {cpu:.1f} s", file=sys.stderr, flush=True)
    return {"P": np.array([r.P for r in records]), "a": np.array([r.contact_radius for r in records]),
            "steps": len(steps), "cpu": cpu, "dofs": solver.n_dofs}


def richardson(f1: float, f2: float, f3: float, ratio: float):
    """(observed order, extrapolated value, relative error of f3, spread): the order None when the
    differences change sign or vanish, the extrapolation and its error None unless the order is
    positive (converging); the spread (max - min) / |f3| of the three."""
    d12, d23 = f1 - f2, f2 - f3
    spread = (max(f1, f2, f3) - min(f1, f2, f3)) / abs(f3)
    if d12 * d23 <= 0.0:
        return None, None, None, spread
    p = np.log(d12 / d23) / np.log(ratio)
    if p <= 0.0:
        return p, None, None, spread
    extrapolated = f3 + (f3 - f2) / (ratio ** p - 1.0)
    return p, extrapolated, (extrapolated - f3) / extrapolated, spread


def ladder_rows(label: str, runs: list, targets, ratio: float) -> list[str]:
    lines = []
    for quantity, unit, scale in (("P", "N", 1.0), ("a", "R", R)):
        for j, target in enumerate(targets):
            values = [run[quantity][j] / scale for run in runs]
            p, extrapolated, error, spread = richardson(*values, ratio)
            p_text = f"{p:6.2f}" if p is not None else f"{'-':>6s}"
            ext_text = f"{extrapolated:11.5g}" if extrapolated is not None else f"{'-':>11s}"
            err_text = f"{100 * error:+8.2f}" if error is not None else f"{'-':>8s}"
            lines.append(f"{label:16s} {quantity + ' [' + unit + ']':8s} {target:7.3f} "
                         + " ".join(f"{v:11.5g}" for v in values)
                         + f" {p_text} {ext_text} {err_text} {100 * spread:8.2f}")
    return lines


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--approaches", type=float, nargs="+", default=[0.035, 0.085], help="approaches / R")
    parser.add_argument("--steps", type=int, default=9, help="log intervals to the first approach (coarsest step)")
    parser.add_argument("--ratio", type=float, default=np.sqrt(2.0), help="mesh refinement ratio")
    parser.add_argument("--levels", type=int, default=3, help="meshes (>= 3; each consecutive three a ladder)")
    parser.add_argument("--no-small", action="store_true", help="skip the small-strain presses")
    ns = parser.parse_args(argv)
    targets = sorted(ns.approaches)
    levels = range(max(ns.levels, 3))
    finest_step = STEP_FACTORS[-1]
    kinds = ("finite-strain",) + (() if ns.no_small else ("small-strain",))
    runs = {}
    with tempfile.TemporaryDirectory() as cache:
        meshes = [hemisphere_mesh(mesh_spec(level, ns.ratio), cache_dir=cache) for level in levels]
        for level, mesh in enumerate(meshes):
            for kinematics in kinds:
                runs[kinematics, level, finest_step] = press(mesh, kinematics, approach_path(targets, ns.steps,
                                                                                             finest_step), targets)
        for level in (levels[0], levels[-1]):
            for factor in STEP_FACTORS[:-1]:
                runs["finite-strain", level, factor] = press(meshes[level], "finite-strain",
                                                              approach_path(targets, ns.steps, factor), targets)
    print(f"{'run':34s} {'dofs':>6s} {'steps':>6s} {'cpu_s':>7s}  " + "  ".join(
        f"P(alpha {t:g} R) [N]    a/R" for t in targets))
    for (kinematics, level, factor), run in runs.items():
        name = f"{kinematics} h=R/{20 * ns.ratio ** level:.1f} steps x{factor}"
        print(f"{name:34s} {run['dofs']:6d} {run['steps']:6d} {run['cpu']:7.1f}  " + "  ".join(
            f"{P:16.6g} {a / R:6.4f}" for P, a in zip(run["P"], run["a"])))
    print()
    print(f"{'ladder':16s} {'quantity':8s} {'alpha/R':>7s} {'coarse':>11s} {'middle':>11s} {'fine':>11s}"
          f" {'p':>6s} {'extrap':>11s} {'err_%':>8s} {'spread_%':>8s}")
    for first in levels[:-2]:
        label = f"mesh R/{20 * ns.ratio ** first:.0f}-{20 * ns.ratio ** (first + 2):.0f}"
        print("\n".join(ladder_rows(label, [runs["finite-strain", level, finest_step]
                                            for level in range(first, first + 3)], targets, ns.ratio)))
    for level in (levels[0], levels[-1]):
        label = f"step R/{20 * ns.ratio ** level:.0f}"
        print("\n".join(ladder_rows(label, [runs["finite-strain", level, f] for f in STEP_FACTORS], targets, 2.0)))
    if not ns.no_small:
        print()
        print("finite / small strain force - 1 [%] per mesh (coarse to fine)")
        finite, small = ([runs[kind, level, finest_step] for level in levels] for kind in kinds)
        for j, target in enumerate(targets):
            per_mesh = [100 * (f["P"][j] / s["P"][j] - 1.0) for f, s in zip(finite, small)]
            print(f"alpha {target:g} R: " + " ".join(f"{d:+7.2f}" for d in per_mesh))

if __name__ == "__main__":
    main()

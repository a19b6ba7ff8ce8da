"""Benchmark: the plan's contact radius (calib.fit.recipe.fe_contact_radius) and its finite-strain time estimate
(calib.scenes.plan) against the FE's loading branch.

Not a timed test: prints a table. For each material (E/sigma_Y and nu; sigma_Y 250 MPa, R 5 mm) and kinematics the
FE runs the loading branch of the ``nfdcal calibrate --v-max`` plan to ``--top`` P_Y (or the finite strain's reach,
a/R 0.45): force control, loads stepped geometrically (16 per decade), on the graded mesh with ``--elements``
contact elements across every contact radius from 1.1 P_Y (6: coarse; 17.9: the command's default). At each load
from 8 P_Y it compares the FE's contact radius with the plan's,

    radius error = a_plan / a_FE - 1   (fe_contact_radius; and the mesh-sizing estimated_contact_radius's),

within each kinematics' reach (small strain a/R <= 0.2, finite strain a/R <= 0.45), and the CPU time of each load
step with the plan's (calib.scenes.plan.step_seconds x finite_strain_step_cost for finite strain).
Usage: .venv/bin/python tests/benchmarks/plan_radius.py [--elements 6] [--top 2000]
       [--materials 100:0.3 400:0.34 700:0.3 2000:0.29] [--kinematics finite-strain small-strain]
"""
from __future__ import annotations

import argparse
import time

from calib.fe import ContactSolver
from calib.fe.loadpath import advance
from calib.fe.state import StepNotConverged
from calib.fit import impact_window, recipe
from calib.fit.calibration import von_mises_material
from calib.scenes.plan import finite_strain_step_cost, step_seconds
from meshes.hemisphere import hemisphere_mesh
from nfdmodel import ContactPair, Material

SIGMA_Y, R = 250e6, 0.005
FROM_OVER_P_Y = 8.0


def loading_branch(material: Material, top_over_P_Y: float, kinematics: str, elements: float) -> tuple[list, int]:
    """(rows (P/P_Y, a_FE/R, cpu s), dofs) of the --v-max plan's loading branch in ``kinematics``."""
    pair = ContactPair.sphere_flat(material, R)
    top = min(top_over_P_Y * pair.P_Y, 0.999 * recipe.fe_reach(pair, "finite-strain"))
    spec = impact_window.window_spec(material, R, top, kinematics="finite-strain", elements_per_contact_radius=elements)
    solver = ContactSolver(hemisphere_mesh(spec.mesh), von_mises_material(material.E, material.nu, material.sigma_y,
                                                                         None),
                           kinematics=kinematics, residual_tolerance=spec.residual_tolerance,
                           contact_radius_method=spec.contact_radius_method)
    state, rows = solver.initial_state(), []
    for target in spec.plan.loading_targets():
        records = []
        t0 = time.process_time()
        try:
            state = advance(solver, state, "force", target, spec.plan.min_step_fraction,
                            lambda result, before: records.append(result.record))
        except StepNotConverged:
            break
        rows.append((records[-1].P / pair.P_Y, records[-1].contact_radius / R, time.process_time() - t0))
    return rows, solver.n_dofs


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elements", type=float, default=6.0, help="contact elements across every contact radius")
    parser.add_argument("--top", type=float, default=2000.0, help="the largest load [P_Y]")
    parser.add_argument("--materials", nargs="+", default=["100:0.3", "400:0.34", "700:0.3", "2000:0.29"],
                        help="E/sigma_Y:nu")
    parser.add_argument("--kinematics", nargs="+", default=["finite-strain", "small-strain"])
    ns = parser.parse_args(argv)
    print(f"{'E/sY':>6s} {'nu':>5s} {'kinematics':13s} {'dofs':>6s} {'P/P_Y':>8s} {'a/R FE':>7s} {'plan %':>7s} "
          f"{'mesh-est %':>10s} {'cpu s':>7s} {'plan s':>7s}")
    worst = {}
    for item in ns.materials:
        ratio, nu = (float(v) for v in item.split(":"))
        material = Material(ratio * SIGMA_Y, nu, SIGMA_Y, 8500.0)
        pair = ContactPair.sphere_flat(material, R)
        for kinematics in ns.kinematics:
            rows, dofs = loading_branch(material, ns.top, kinematics, ns.elements)
            reach = recipe.REACH[kinematics][1]
            cpu = plan = 0.0
            for k, (x, a, seconds) in enumerate(rows):
                cost = finite_strain_step_cost(x, "loading", dofs) if kinematics == "finite-strain" else 1.0
                cpu, plan = cpu + seconds, plan + step_seconds(dofs) * cost
                if x < FROM_OVER_P_Y or a > reach:
                    continue
                error = recipe.fe_contact_radius(pair, x * pair.P_Y) / (a * R) - 1.0
                mesh_error = recipe.estimated_contact_radius(pair, x * pair.P_Y) / (a * R) - 1.0
                low, high = worst.get(kinematics, (0.0, 0.0))
                worst[kinematics] = (min(low, error), max(high, error))
                if k % 4 == 0 or k == len(rows) - 1:
                    print(f"{ratio:6g} {nu:5g} {kinematics:13s} {dofs:6d} {x:8.4g} {a:7.4f} {100 * error:+7.1f} "
                          f"{100 * mesh_error:+10.1f} {seconds:7.3f} {step_seconds(dofs) * cost:7.3f}")
            print(f"{ratio:6g} {nu:5g} {kinematics:13s} loading branch to {rows[-1][0]:.4g} P_Y: cpu {cpu:.1f} s, "
                  f"plan {plan:.1f} s ({len(rows)} steps)")
    for kinematics, (low, high) in worst.items():
        print(f"plan radius error, {kinematics} (>= {FROM_OVER_P_Y:g} P_Y, within its reach): "
              f"{100 * low:+.1f} .. {100 * high:+.1f} %")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

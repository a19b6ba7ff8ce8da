"""Benchmark: the dynamic FE impact on a deformable counter-body, checked and timed on the impact's mesh.

Not a timed test: on the mesh ``nfdcal impact`` uses at 0.04 m/s (the default mesh; ``--coarse``:
contact element 1.6e-4 m) with one BLAS thread, prints
  * symmetry: two identical elastoplastic reference spheres at +-0.04 m/s against the one sphere on
    the rigid flat at 0.04 m/s (calib.fe.newmark): the relative differences of e, P_max, t_c;
  * Hertz: elastic aluminium on a free elastic steel sphere (R2 = R / 2) and on an elastic steel
    block, at 0.04 m/s: P_max, t_c, alpha_max against Hertz's impact with the pair's E*, R*, m*
    (Johnson 1985, 11.4), and the energy balance's residual over the kinetic energy in;
  * block size: e, P_max, t_c on blocks of L = R, 2 R (the default), 4 R;
each with its wall and CPU time (the time per impact; the machine's load average is printed).
Usage: .venv/bin/python tests/benchmarks/bench_impact_pair.py [--coarse] [--steps-per-contact 100]
       [--skip symmetry hertz block]
"""
from __future__ import annotations

import argparse
import dataclasses
import os
import time

from threadpoolctl import threadpool_limits

from calib.fe import ElasticMaterial, VonMisesMaterial
from calib.fe.impact import run_impact
from calib.fe.impact_pair import PairImpactSolver
from calib.fe.impact_pair_mesh import impact_pair_mesh
from calib.fe.impact_pair_run import hertz_pair_impact, run_pair_impact
from calib.fe.newmark import ImpactSolver
from calib.studies import impact
from meshes.counter_body import BlockMeshSpec
from meshes.sphere import SphereMeshSpec, sphere_mesh
from nfdmodel import reference_case as rc

V_IN = 0.04
STEEL = (2.1e11, 0.28, 7800.0)
COARSE = SphereMeshSpec(radius=rc.R, contact_size=1.6e-4, refined_radius=1.6e-3, refined_depth=5e-4, far_size=1e-2,
                        growth=0.3)


def timed(function):
    wall, cpu = time.perf_counter(), time.process_time()
    out = function()
    return out, time.perf_counter() - wall, time.process_time() - cpu


def symmetry(spec, steps) -> list[str]:
    def plastic():
        return VonMisesMaterial(rc.E, rc.NU, rc.SIGMA_Y)

    flat, w1, c1 = timed(lambda: run_impact(ImpactSolver(sphere_mesh(spec), plastic(), rc.RHO), V_IN,
                                            steps_per_contact=steps))
    pair, w2, c2 = timed(lambda: run_pair_impact(PairImpactSolver(impact_pair_mesh(spec, spec), plastic(), plastic(),
                                                                  rc.RHO, rc.RHO), 2 * V_IN, steps_per_contact=steps))
    return [f"symmetry (elastoplastic, 24 v_Y): rigid flat e = {flat.e:.6f}, P_max = {flat.P_max:.6g} N, "
            f"t_c = {flat.contact_time * 1e3:.6f} ms ({flat.dofs} dofs, {w1:.1f} s wall, {c1:.1f} s CPU)",
            f"  two spheres at +-v: e - e_flat = {pair.e - flat.e:+.2e}, P_max {pair.P_max / flat.P_max - 1:+.2e}, "
            f"t_c {pair.contact_time / flat.contact_time - 1:+.2e}, momentum change {pair.momentum_change:.1e} "
            f"({pair.dofs} unknowns, {w2:.1f} s wall, {c2:.1f} s CPU)"]


def hertz(spec, steps) -> list[str]:
    E2, nu2, rho2 = STEEL
    lines = []
    for name, counter in (("steel sphere R/2", SphereMeshSpec(**{**dataclasses.asdict(spec), "radius": rc.R / 2})),
                          ("steel block L = 2R", BlockMeshSpec(**{**dataclasses.asdict(spec), "radius": 2 * rc.R}))):
        solver = PairImpactSolver(impact_pair_mesh(spec, counter), ElasticMaterial(rc.E, rc.NU),
                                  ElasticMaterial(E2, nu2), rc.RHO, rho2)
        r, wall, cpu = timed(lambda: run_pair_impact(solver, V_IN, steps_per_contact=steps))
        h = hertz_pair_impact(r.E_star, r.R_star, r.reduced_mass, V_IN)
        lines.append(f"Hertz, elastic aluminium on {name}: P_max {r.P_max / h['P_max'] - 1:+.2e}, t_c "
                     f"{r.contact_time / h['contact_time'] - 1:+.2e}, alpha_max {r.alpha_max / h['alpha_max'] - 1:+.2e}; "
                     f"e = {r.e:.6f}, energy left {r.energy_left / r.kinetic_in:.1e}, balance "
                     f"{r.balance_residual / r.kinetic_in:+.1e} (contact work {r.contact_work / r.kinetic_in:+.1e}) "
                     f"of KE_in ({r.dofs} unknowns, {r.steps} steps, {wall:.1f} s wall, {cpu:.1f} s CPU)")
    return lines


def block(spec, steps) -> list[str]:
    E2, nu2, rho2 = STEEL
    rows = []
    for L in (rc.R, 2 * rc.R, 4 * rc.R):
        counter = BlockMeshSpec(**{**dataclasses.asdict(spec), "radius": L, "far_size": min(L, max(spec.far_size, 2e-2))})
        solver = PairImpactSolver(impact_pair_mesh(spec, counter), VonMisesMaterial(rc.E, rc.NU, rc.SIGMA_Y),
                                  ElasticMaterial(E2, nu2), rc.RHO, rho2)
        r, wall, cpu = timed(lambda: run_pair_impact(solver, V_IN, steps_per_contact=steps))
        rows.append((L, r, wall, cpu))
    _, ref, _, _ = rows[1]
    return [f"block L = {L / rc.R:g} R (elastoplastic aluminium on elastic steel, 0.04 m/s): e = {r.e:.6f} "
            f"({r.e - ref.e:+.1e}), P_max {r.P_max / ref.P_max - 1:+.2e}, t_c {r.contact_time / ref.contact_time - 1:+.2e} "
            f"against L = 2 R ({r.dofs} unknowns, {wall:.1f} s wall, {cpu:.1f} s CPU)" for L, r, wall, cpu in rows]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--coarse", action="store_true")
    parser.add_argument("--steps-per-contact", type=int, default=impact.DEFAULT_STEPS_PER_CONTACT)
    parser.add_argument("--skip", nargs="*", default=(), choices=("symmetry", "hertz", "block"))
    ns = parser.parse_args(argv)
    spec = COARSE if ns.coarse else impact.impact_mesh(impact.reference_setup(), V_IN)
    with threadpool_limits(1):
        for name, part in (("symmetry", symmetry), ("hertz", hertz), ("block", block)):
            if name not in ns.skip:
                for line in part(spec, ns.steps_per_contact):
                    print(line, flush=True)
    print(f"mesh: contact element {spec.contact_size:g} m, {ns.steps_per_contact} steps per contact; load average "
          f"{os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")


if __name__ == "__main__":
    main()

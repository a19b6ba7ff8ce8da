"""Benchmark: the complete reference calibration, both meshes (target <= 20 s wall on 2 cores).

Not a timed test: prints a table of where the time goes on the finer mesh (first yield, loading
branch, each unloading; Newton iterations, factorisations, assembly and solve seconds), the
second mesh (on another process), the total wall time against the target, the peak memory of
both processes, and the cost of one factorisation against one elastic Hertz-limit solve
measured in the same run (a ratio, robust on a shared machine). ``--serial`` runs the two
meshes one after the other, for the two-core speed-up.
Usage: .venv/bin/python tests/benchmarks/bench_calibration.py [--serial]
"""
from __future__ import annotations

import argparse
import resource
import time

TARGET_S = 20.0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--serial", action="store_true", help="both meshes on this process, one after the other")
    ns = parser.parse_args()
    from calib.fe import ContactSolver
    from calib.fe.elastic import ElasticMaterial
    from calib.fit.calibration import calibrate, summary
    from calib.fit.recipe import coarse_spec, reference_spec
    from meshes.hemisphere import hemisphere_mesh

    spec = reference_spec()
    hemisphere_mesh(spec.mesh), hemisphere_mesh(coarse_spec(spec).mesh)   # meshing is cached: not timed
    t0, cpu0 = time.perf_counter(), time.process_time()
    result = calibrate(spec, parallel=not ns.serial)
    total, cpu = time.perf_counter() - t0, time.process_time() - cpu0
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    s = summary(result)

    stages = [("loading branch", result.load_paths.loading_rows)]
    stages += [(f"unloading from {p.peak:g} N", [r for r in p.rows if r["branch"] == "unloading"])
               for p in result.load_paths.paths]
    pair = result.mesh_pair
    print(f"reference calibration: mesh h = {spec.mesh.contact_size:g} m ({result.mesh_info['dofs']} dofs) and "
          f"2h = {pair['contact_size']:g} m ({pair['dofs']} dofs), {'serial' if ns.serial else 'two processes'}")
    print(f"{'stage (mesh h)':<24}{'steps':>6}{'newton':>8}{'active sets':>12}{'factor.':>8}{'assembly s':>11}"
          f"{'solve s':>9}{'wall s':>8}")
    for name, rows in stages:
        print(f"{name:<24}{len(rows):>6}{sum(r['newton_iterations'] for r in rows):>8}"
              f"{sum(r['active_set_iterations'] for r in rows):>12}{sum(r['factorizations'] for r in rows):>8}"
              f"{sum(r['time_assembly_s'] for r in rows):>11.2f}{sum(r['time_solve_s'] for r in rows):>9.2f}"
              f"{sum(r['wall_time_s'] for r in rows):>8.2f}")
    print(f"{'mesh 2h (whole)':<24}{'':>6}{'':>8}{'':>12}{pair['factorizations']:>8}{'':>11}{'':>9}"
          f"{pair['wall_time_s']:>8.2f}")
    for key, value in result.timings.items():
        print(f"  {key}: {value:.3g}" if isinstance(value, float) else f"  {key}: {value}")
    own = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"peak memory: {own:.0f} MB (this process)" + ("" if ns.serial else f", {children.ru_maxrss / 1024:.0f} MB (the second mesh's process)"))
    # on a shared machine the CPU seconds say what the wall time would be on two free cores
    print(f"CPU time: {cpu:.1f} s (this process), {children.ru_utime + children.ru_stime:.1f} s (the second mesh's)")
    print(f"shipped: Ca = {s['Ca']:.5g} m/N (est. error {s['Ca_rel_error_estimate']:.2%}), Kc = {s['Kc']:.5g} 1/N "
          f"(est. error {s['Kc_rel_error_estimate']:.2%})")

    # one elastic Hertz-limit solve on the same mesh, as the unit of cost
    solver = ContactSolver(hemisphere_mesh(spec.mesh), ElasticMaterial(spec.material.E, spec.material.nu))
    t1 = time.perf_counter()
    solver.solve_force(solver.initial_state(), 1500.0)
    hertz_solve = time.perf_counter() - t1
    print(f"total {total:.1f} s (target <= {TARGET_S:g} s: {'met' if total <= TARGET_S else 'NOT met'}); "
          f"one elastic 1500 N solve {hertz_solve:.3f} s; calibration = {total / hertz_solve:.0f} elastic solves")


if __name__ == "__main__":
    main()

"""Benchmark: the complete reference calibration at the default mesh (target <= 60 s on 2 cores).

Not a timed test: prints a table of where the time goes (mesh, first yield, loading branch,
each unloading, fit), the Newton iterations and factorisations per stage, and the cost of one
factorisation against one elastic Hertz-limit solve measured in the same run (a ratio, robust on
a shared machine).
Usage: .venv/bin/python tests/benchmarks/bench_calibration.py
"""
from __future__ import annotations

import time

TARGET_S = 60.0


def main() -> None:
    from calib.fe import ContactSolver
    from calib.fe.elastic import ElasticMaterial
    from calib.fit.calibration import calibrate
    from calib.fit.recipe import reference_spec
    from meshes.hemisphere import hemisphere_mesh

    spec = reference_spec()
    t0 = time.perf_counter()
    result = calibrate(spec)
    total = time.perf_counter() - t0

    stages = [("loading branch", result.load_paths.loading_rows)]
    stages += [(f"unloading from {p.peak:g} N", [r for r in p.rows if r["branch"] == "unloading"])
               for p in result.load_paths.paths]
    print(f"reference calibration, mesh h = {spec.mesh.contact_size:g} m, {result.mesh_info['dofs']} dofs")
    print(f"{'stage':<24}{'steps':>6}{'newton':>8}{'active sets':>12}{'factor.':>8}{'assembly s':>11}"
          f"{'solve s':>9}{'wall s':>8}")
    for name, rows in stages:
        print(f"{name:<24}{len(rows):>6}{sum(r['newton_iterations'] for r in rows):>8}"
              f"{sum(r['active_set_iterations'] for r in rows):>12}{sum(r['factorizations'] for r in rows):>8}"
              f"{sum(r['time_assembly_s'] for r in rows):>11.2f}{sum(r['time_solve_s'] for r in rows):>9.2f}"
              f"{sum(r['wall_time_s'] for r in rows):>8.2f}")
    for key, value in result.timings.items():
        print(f"  {key}: {value:.3g}" if isinstance(value, float) else f"  {key}: {value}")

    # one elastic Hertz-limit solve on the same mesh, as the unit of cost
    solver = ContactSolver(hemisphere_mesh(spec.mesh), ElasticMaterial(spec.material.E, spec.material.nu))
    t1 = time.perf_counter()
    solver.solve_force(solver.initial_state(), 1500.0)
    hertz_solve = time.perf_counter() - t1
    print(f"total {total:.1f} s (target <= {TARGET_S:g} s: {'met' if total <= TARGET_S else 'NOT met'}); "
          f"one elastic 1500 N solve {hertz_solve:.3f} s; calibration = {total / hertz_solve:.0f} elastic solves")


if __name__ == "__main__":
    main()

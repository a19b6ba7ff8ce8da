"""Benchmark: a hardening calibration against the elastic-perfectly plastic (EPP) one on the same mesh
(target: at most 1.3x the EPP calibration's time).

Not a timed test: prints one table, a row per sphere: the reference sphere (nfdmodel.reference_case,
paths to 500, 1000, 1500 N) perfectly plastic, with linear hardening at H/E = 0.001, 0.01, 0.1
(``nfdcal calibrate --hardening-modulus H``), a tabulated flow curve read from a CSV (``--flow-curve``:
Swift's curve below sampled at 9 points, flat beyond), and the flow curves the API takes (Swift
K = 4 sigma_Y, n = 0.25; Ludwik K = 3 sigma_Y, n = 0.4, whose infinite initial slope starts the return
by bisection). Each is calibrated by calib.fit.calibration.calibrate on one mesh (``meshes=1``, the
same mesh for all; ``--level`` or ``--contact-size``), ``--repeat`` times with the order reversed every
other repeat; the ratios are the medians over repeats of each run's time over the EPP run's of the
same repeat (the machine is shared: CPU time is the robust one). Per sphere: median wall and CPU time
[s], both ratios, the return mapping's calls (every material evaluation, failed step attempts
included) and their seconds, the Newton iterations of the accepted steps, the loading and unloading
steps (step cuts included), the largest approach alpha_max [um] and e of each path, and P / P_EPP at
the top path's alpha_max (the force the EPP sphere needs for the same approach, from its loading
branch: > 1 with hardening). ``--csv PATH`` writes the rows.
Usage: .venv/bin/python tests/benchmarks/bench_hardening.py [--level coarse] [--repeat 3] [--csv PATH]
"""
from __future__ import annotations

import argparse
import dataclasses
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np

from nfdmodel import reference_case as rc

TARGET_RATIO = 1.3
CASES = ("epp", "linear-0.001", "linear-0.01", "linear-0.1", "table", "swift", "ludwik")
# the tabulated curve's points [-]: a tensile test's flow curve to 20 % plastic strain
TABLE_STRAINS = (0.0, 0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2)


def flow_curves(E: float, sigma_y: float, folder: Path) -> dict:
    """The sphere's flow curve of each case (None: perfectly plastic); the table through a CSV, as
    ``--flow-curve`` reads it."""
    from calib.fe.flow_curve import (FLOW_CURVE_COLUMNS, LinearHardening, LudwikHardening, SwiftHardening,
                                     read_flow_curve)

    swift = SwiftHardening(sigma_y, 4.0 * sigma_y, 0.25)
    table = folder / "flow_curve.csv"
    stresses = swift.yield_stress(np.array(TABLE_STRAINS))
    table.write_text(",".join(FLOW_CURVE_COLUMNS) + "\n"
                     + "".join(f"{e:.17g},{s:.17g}\n" for e, s in zip(TABLE_STRAINS, stresses)))
    curves = {"epp": None, "table": read_flow_curve(table, "flat", sigma_y=sigma_y), "swift": swift,
              "ludwik": LudwikHardening(sigma_y, 3.0 * sigma_y, 0.4)}
    for ratio in (0.001, 0.01, 0.1):
        curves[f"linear-{ratio:g}"] = LinearHardening(sigma_y, ratio * E)
    return curves


class ReturnMappingClock:
    """Counts and times calib.fe.von_mises.return_mapping, the one place the von Mises materials
    (perfect and hardening) are evaluated, while installed (this process only)."""

    def __init__(self):
        import calib.fe.von_mises as von_mises

        self.module, self.original = von_mises, von_mises.return_mapping
        self.calls, self.seconds = 0, 0.0

    def __call__(self, *args, **kwargs):
        t0 = time.perf_counter()
        try:
            return self.original(*args, **kwargs)
        finally:
            self.seconds += time.perf_counter() - t0
            self.calls += 1

    def __enter__(self):
        self.calls, self.seconds = 0, 0.0
        self.module.return_mapping = self
        return self

    def __exit__(self, *exc):
        self.module.return_mapping = self.original


def run_case(spec, curve) -> dict:
    """One calibration of ``spec`` with the flow curve ``curve`` on its one mesh: times and figures."""
    from calib.fit.calibration import calibrate

    spec = spec if curve is None else dataclasses.replace(spec, hardening=curve)
    with ReturnMappingClock() as clock:
        t0, cpu0 = time.perf_counter(), time.process_time()
        result = calibrate(spec, meshes=1)
        wall, cpu = time.perf_counter() - t0, time.process_time() - cpu0
    paths = result.load_paths
    unloading = [r for p in paths.paths for r in p.rows if r["branch"] == "unloading"]
    return {"wall": wall, "cpu": cpu, "calls": clock.calls, "rm_s": clock.seconds,
            "newton": sum(r["newton_iterations"] for r in paths.loading_rows + unloading),
            "loading_steps": len(paths.loading_rows), "unloading_steps": len(unloading),
            "alpha_max": [p.alpha_max for p in paths.paths], "e": [p.restitution for p in paths.paths],
            "peaks": [p.peak for p in paths.paths], "dofs": result.mesh_info["dofs"],
            "branch": (np.array([r["alpha"] for r in paths.loading_rows]),
                       np.array([r["P"] for r in paths.loading_rows]))}


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--level", default="coarse", choices=("coarse", "default", "fine"),
                        help="mesh level (coarse: contact element 1.6e-4 m on the reference sphere, a_max / 10 otherwise)")
    parser.add_argument("--contact-size", type=float, default=None, help="contact element [m] (overrides --level)")
    parser.add_argument("--E-over-sigma-y", type=float, default=None,
                        help="another sphere: the reference's E, nu, R with sigma_Y = E / this (default: the reference's 700)")
    parser.add_argument("--repeat", type=int, default=3, help="runs of every sphere (order reversed every other)")
    parser.add_argument("--cases", default=",".join(CASES), help=f"comma-separated subset of {','.join(CASES)}")
    parser.add_argument("--csv", type=Path, default=None, help="also write the rows to this CSV")
    ns = parser.parse_args(argv)
    cases = [c.strip() for c in ns.cases.split(",") if c.strip()]
    unknown = sorted(set(cases) - set(CASES))
    if unknown or not cases:
        parser.error(f"--cases must name some of {','.join(CASES)}, got {ns.cases!r}")
    if ns.repeat < 1:
        parser.error(f"--repeat must be an integer >= 1, got {ns.repeat}")
    cases = ["epp"] + [c for c in cases if c != "epp"]

    from calib.fit.recipe import calibration_spec, reference_spec
    from meshes.hemisphere import hemisphere_mesh
    from nfdmodel import Material

    if ns.E_over_sigma_y is None:
        spec = reference_spec(level=ns.level, contact_size=ns.contact_size)
    else:
        reference = Material.reference()
        material = dataclasses.replace(reference, sigma_y=reference.E / ns.E_over_sigma_y)
        spec = calibration_spec(material, rc.R, level=ns.level, contact_size=ns.contact_size)
    hemisphere_mesh(spec.mesh)                          # meshing is cached: not timed
    runs = {name: [] for name in cases}
    with tempfile.TemporaryDirectory() as folder:
        curves = flow_curves(spec.material.E, spec.material.sigma_y, Path(folder))
        for k in range(ns.repeat):
            for name in (cases if k % 2 == 0 else cases[::-1]):
                runs[name].append(run_case(spec, curves[name]))

    epp = runs["epp"]
    E = spec.material.E
    alpha_epp, force_epp = epp[0]["branch"]
    rows = []
    for name in cases:
        one = runs[name]
        first = one[0]
        curve = curves[name]
        rows.append({
            "case": name,
            "flow_curve": "perfectly plastic" if curve is None else curve.record()["flow_curve"],
            "H0_over_E": 0.0 if curve is None else float(curve.modulus(0.0)) / E,
            "wall_s": statistics.median(r["wall"] for r in one),
            "cpu_s": statistics.median(r["cpu"] for r in one),
            "wall_ratio": statistics.median(r["wall"] / e["wall"] for r, e in zip(one, epp)),
            "cpu_ratio": statistics.median(r["cpu"] / e["cpu"] for r, e in zip(one, epp)),
            "return_mapping_calls": first["calls"],
            "return_mapping_s": statistics.median(r["rm_s"] for r in one),
            "newton_iterations": first["newton"],
            "loading_steps": first["loading_steps"], "unloading_steps": first["unloading_steps"],
            **{f"alpha_max_um_{p:g}N": a * 1e6 for p, a in zip(first["peaks"], first["alpha_max"])},
            **{f"e_{p:g}N": e for p, e in zip(first["peaks"], first["e"])},
            "P_over_P_epp_same_alpha": first["peaks"][-1] / float(np.interp(first["alpha_max"][-1], alpha_epp,
                                                                            force_epp)),
        })

    peaks = epp[0]["peaks"]
    sphere = ("reference sphere" if ns.E_over_sigma_y is None else
              f"reference sphere with sigma_Y = E / {ns.E_over_sigma_y:g} = {spec.material.sigma_y:.4g} Pa")
    print(f"hardening calibrations against EPP: {sphere}, one mesh h = {spec.mesh.contact_size:g} m "
          f"({epp[0]['dofs']} dofs), P_max = {', '.join(f'{p:g}' for p in peaks)} N, "
          f"{ns.repeat} repeat(s), medians")
    header = (f"{'case':<13}{'H0/E':>8}{'wall s':>8}{'cpu s':>8}{'wall x':>8}{'cpu x':>7}{'RM calls':>9}"
              f"{'RM s':>7}{'newton':>7}{'load':>5}{'unl.':>5}" + "".join(f"{'amax' + str(i + 1):>7}" for i in
                                                                        range(len(peaks)))
              + "".join(f"{'e' + str(i + 1):>7}" for i in range(len(peaks))) + f"{'P/P_epp':>8}")
    print(header)
    for row in rows:
        alphas = [row[f"alpha_max_um_{p:g}N"] for p in peaks]
        es = [row[f"e_{p:g}N"] for p in peaks]
        h0 = "inf" if not np.isfinite(row["H0_over_E"]) else f"{row['H0_over_E']:.3g}"
        print(f"{row['case']:<13}{h0:>8}{row['wall_s']:>8.2f}{row['cpu_s']:>8.2f}{row['wall_ratio']:>8.2f}"
              f"{row['cpu_ratio']:>7.2f}{row['return_mapping_calls']:>9}{row['return_mapping_s']:>7.2f}"
              f"{row['newton_iterations']:>7}{row['loading_steps']:>5}{row['unloading_steps']:>5}"
              + "".join(f"{a:>7.4g}" for a in alphas) + "".join(f"{e:>7.4f}" for e in es)
              + f"{row['P_over_P_epp_same_alpha']:>8.4f}")
    print("amax_i [um], e_i: path i's largest approach and restitution; P/P_epp: the top peak over the EPP "
          "force at the same approach; RM: the return mapping (all material evaluations)")
    worst = max(rows[1:], key=lambda r: r["cpu_ratio"], default=None)
    if worst is not None:
        print(f"largest CPU-time ratio {worst['cpu_ratio']:.2f} ({worst['case']}; wall {worst['wall_ratio']:.2f}): "
              f"target <= {TARGET_RATIO:g}x EPP {'met' if worst['cpu_ratio'] <= TARGET_RATIO else 'NOT met'}")
    if ns.csv is not None:
        from calib import output

        total = sum(r["wall"] for one in runs.values() for r in one)
        output.write_csv(ns.csv, rows, comment=output.stamp_comment(output.stamp(total, spec.mesh.describe(),
                                                                                 repeat=ns.repeat)))
        print(f"written to {ns.csv}")


if __name__ == "__main__":
    main()

"""Benchmark: a finite-strain calibration on the coarsest mesh to a/R about 0.3, its shipped law against
FE paths held out of it.

Not a timed test: prints a table. The sphere is brass (E 100 GPa, nu 0.34, sigma_Y 250 MPa, R 5 mm,
rho 8500 kg/m^3; ``--E`` another E [Pa]: at E/sigma_Y 100 the FE's contact radius at the top is near the
estimate's, at 400 (brass) about half of it, the linear plastic radius of the estimate overstating the
fully plastic contact's). The calibration is ``nfdcal calibrate --v-max``'s (calib.fit.impact_window.window_spec:
unloading paths log-spaced from the lowest load the mesh resolves, loading stepped geometrically) to the
load whose estimated contact radius is ``--a-over-R`` R (default 0.3), in finite strain, on one mesh of
contact element ``--contact-size-over-a-max`` x a_max (default 0.1: the recipe's "coarse" level; a_max the FE's
contact radius in finite strain, recipe.sizing_radius). Then the
FE runs a load-unload path on the same mesh to the geometric midpoint between each pair of consecutive
unloading peaks (paths the law never saw), and the shipped vz-table law is driven along each
(calib.fit.path_check.law_against_path):

    force error = max |P_law(alpha) - P_FE(alpha)| / P_max,   e error = e_law / e_FE - 1

Targets (calib.fit.calibration): force within 5 %, e within 2 %.
Usage: .venv/bin/python tests/benchmarks/reach_finite_calibration.py [--a-over-R 0.3] [--E 1e11]
       [--contact-size-over-a-max 0.1] [--kinematics finite-strain]
"""
from __future__ import annotations

import argparse
import dataclasses
import time

import numpy as np

from calib.fe.loadpath import run_load_paths
from calib.fit import impact_window, recipe
from calib.fit.calibration import E_TARGET, FORCE_TARGET, _solver, calibrate
from calib.fit.path_check import law_against_path
from calib.studies.between_nodes import fe_path, path_record
from meshes.hemisphere import hemisphere_mesh
from nfdmodel import ContactPair, Material
from nfdmodel.parameter_file import law_of

R = 0.005


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--a-over-R", type=float, default=0.3, help="the top's estimated contact radius / R")
    parser.add_argument("--contact-size-over-a-max", type=float, default=0.1, help="contact element / a_max")
    parser.add_argument("--kinematics", default="finite-strain", help="the FE's kinematics")
    parser.add_argument("--E", type=float, default=100e9, help="Young's modulus [Pa] (brass: 100e9)")
    ns = parser.parse_args(argv)
    material = Material(ns.E, 0.34, 250e6, 8500.0)
    pair = ContactPair.sphere_flat(material, R)
    top = recipe.largest_admissible_load(pair, ns.a_over_R, recipe.estimated_contact_radius)
    spec = impact_window.window_spec(material, R, top, kinematics=ns.kinematics,
                                     contact_size_over_a_max=ns.contact_size_over_a_max)
    t0 = time.perf_counter()
    result = calibrate(spec, ship="table", meshes=1)
    wall = time.perf_counter() - t0
    law = result.shipped_params
    print(f"E/sigma_Y {material.E / material.sigma_y:g}, {ns.kinematics}, mesh h = {spec.mesh.contact_size:.3g} m ({result.mesh_info.get('dofs', '?')} dofs), "
          f"top {top / pair.P_Y:.4g} P_Y (a/R {ns.a_over_R:g} estimated), calibration {wall:.0f} s; shipped "
          f"{law_of(law)} on {law.window.describe()}")
    for p in sorted(result.load_paths.paths, key=lambda p: p.peak):
        print(f"  node {p.peak / pair.P_Y:9.4g} P_Y: e_FE {p.restitution:.4f}")
    peaks = np.array(spec.plan.peaks)
    mesh = hemisphere_mesh(spec.mesh)
    print(f"{'held out [P_Y]':>15s} {'a/R (FE)':>9s} {'e_FE':>7s} {'e_law':>7s} {'e err %':>8s} {'force err %':>11s} {'s':>5s}")
    worst_e = worst_force = 0.0
    for x in np.sqrt(peaks[1:] * peaks[:-1]):
        t1 = time.perf_counter()
        path = run_load_paths(_solver(spec, mesh), dataclasses.replace(spec.plan, peaks=(float(x),), loading_step=float(x))).paths[0]
        radius = max(r["contact_radius"] for r in path.rows) / R
        rec = law_against_path(law_of(law), law, fe_path(path_record(path.peak, path.restitution, path.rows)))
        worst_e, worst_force = max(worst_e, abs(rec["e_error"])), max(worst_force, rec["force_error"])
        print(f"{x / pair.P_Y:15.4g} {radius:9.4f} {rec['e_fe']:7.4f} {rec['e_law']:7.4f} {100 * rec['e_error']:+8.2f} "
              f"{100 * rec['force_error']:11.2f} {time.perf_counter() - t1:5.0f}")
    print(f"worst: e {100 * worst_e:.2f} % (target {100 * E_TARGET:g} %), force {100 * worst_force:.2f} % "
          f"(target {100 * FORCE_TARGET:g} %)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

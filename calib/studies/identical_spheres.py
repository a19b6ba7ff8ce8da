"""Two identical plastic spheres against the rigid flat: results/calibration/identical_spheres.json

Two identical spheres (radius R, E, nu, sigma_Y) pressed together are symmetric about their
contact plane, which stays plane and carries no shear: each sphere is a sphere on a rigid
frictionless flat (Johnson 1985, Contact Mechanics, section 4.2). With the pair's constants

    R* = R / 2,   E* = E / (2 (1 - nu^2)),   P_Y = pi^3 R*^2 (A_Y sigma_Y)^3 / (6 E*^2)    [m, Pa, N]

(the rigid flat's P_Y: R*^2 / E*^2 is unchanged), the approach of the two far points is twice one
sphere's, so the two-body calibration (calib.fe.two_body, the sphere against a counter-sphere of
the same R and material) must give the rigid flat's Ca_hat = Ca P_Y / a_Y, Kc_hat = Kc P_Y and e
of every unloading path. This study runs both calibrations of the reference sphere on its default
mesh, two meshes each and the Richardson extrapolation (calib.fit.calibration.calibrate), and
writes their constants and relative differences. On matching meshes (the counter-sphere's mesh
is the sphere's, mirrored) the dual mortar constraint is node to node and the two discrete
problems are the same, so the differences are the Newton tolerance's (relative residual 1e-8),
not a discretisation error.

    python -m calib.studies.identical_spheres [--out results/calibration]
"""
from __future__ import annotations

import argparse
import dataclasses
import sys
import time
from pathlib import Path

from calib import output
from calib.fit import recipe
from calib.fit.calibration import calibrate, summary
from calib.fit.counter import CounterBody

COMMAND = "python -m calib.studies.identical_spheres"


def identical_counter(spec: recipe.CalibrationSpec) -> recipe.CalibrationSpec:
    """``spec`` with a counter-body: a sphere of the same radius and material."""
    m = spec.material
    return dataclasses.replace(spec, counter=CounterBody(m.E, m.nu, m.sigma_y, spec.radius))


def differences(rigid: dict, pair: dict) -> dict:
    """Relative differences pair / rigid - 1 of the shipped constants, each mesh's radius fit,
    P_Y(FE) and e of every path (summaries of calib.fit.calibration.summary)."""
    out = {name: pair[name] / rigid[name] - 1.0 for name in ("Ca_hat", "Kc_hat", "P_Y_fe")}
    # the finer mesh's own fit (P_Y and a_Y of the pair are the rigid flat's, so Ca, Kc compare as they are)
    out.update({f"fine_mesh_{name}": pair["radius_fit"][name] / rigid["radius_fit"][name] - 1.0
                for name in ("Ca", "Kc")})
    out["e"] = [b["e"] / a["e"] - 1.0 for a, b in zip(rigid["paths"], pair["paths"])]
    out["alpha_max_half"] = [0.5 * b["alpha_max"] / a["alpha_max"] - 1.0 for a, b in zip(rigid["paths"], pair["paths"])]
    return out


def _record(s: dict) -> dict:
    keys = ("Ca", "Kc", "Ca_hat", "Kc_hat", "Ca_rel_error_estimate", "Kc_rel_error_estimate", "P_Y", "P_Y_fe",
            "wall_time_s", "mesh")
    return {**{k: s[k] for k in keys}, "radius_fit": {k: s["radius_fit"][k] for k in ("Ca", "Kc")},
            "paths": [{k: p.get(k) for k in ("P_max", "e", "alpha_max", "alpha_residual", "e_rel_error_estimate")}
                      for p in s["paths"]]}


def generate(out=output.RESULTS / "calibration", spec: recipe.CalibrationSpec | None = None, progress=None) -> dict:
    """Both calibrations of ``spec`` (default: the reference sphere) and OUT/identical_spheres.json."""
    say = progress or (lambda message: None)
    started = time.perf_counter()
    spec = spec or recipe.reference_spec()
    say("the sphere on the rigid flat")
    rigid = summary(calibrate(spec))
    say("two identical spheres")
    pair = summary(calibrate(identical_counter(spec)))
    data = {"rigid_flat": _record(rigid), "identical_spheres": _record(pair), "differences": differences(rigid, pair),
            "stamp": output.stamp(time.perf_counter() - started, mesh=pair["mesh"], command=COMMAND,
                                  material=dataclasses.asdict(spec.material), R=spec.radius)}
    output.write_json(Path(out) / "identical_spheres.json", data)
    return data


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(output.RESULTS / "calibration"))
    ns = parser.parse_args(argv)
    data = generate(ns.out, progress=lambda m: print(m, file=sys.stderr))
    d = data["differences"]
    print(f"identical spheres / rigid flat - 1: Ca_hat {d['Ca_hat']:+.2e}, Kc_hat {d['Kc_hat']:+.2e}, "
          f"e {', '.join(f'{x:+.2e}' for x in d['e'])}; wall {data['stamp']['wall_time_s']:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""``nfdcal hertz``: the Hertz-limit validation of the FE contact solver (issue 3).

Default: the reference sphere (R = 0.1 m, E = 70 GPa, nu = 0.3), elastic, force-controlled from
1 N to 1500 N on the default mesh; writes results/hertz/ (hertz.json, hertz_steps.csv,
pressure_profile.csv, contact_radius.png, approach.png, peak_pressure.png, pressure_profile.png).
``--ladder`` runs the mesh ladder instead (mesh_ladder.csv, mesh_ladder.png).
``--json`` prints the summary object (its ``top_load`` entry: P, alpha, contact_radius,
contact_radius_hertz, contact_radius_rel_error, peak_pressure_rel_error, alpha_rel_error,
wall_time_s) on stdout.
"""
from __future__ import annotations

import math

DEFAULT_OUT = "results/hertz"


def add_parser(subparsers):
    p = subparsers.add_parser("hertz", help="validate the FE contact solver against Hertz",
                              description=__doc__.splitlines()[0])
    p.add_argument("--P-min", dest="P_min", type=float, default=1.0, help="first load [N] (1)")
    p.add_argument("--P-max", dest="P_max", type=float, default=1500.0, help="top load [N] (1500)")
    p.add_argument("--steps", type=int, default=25, help="number of loads, geometric (25)")
    p.add_argument("--radius", type=float, default=0.1, help="sphere radius R [m] (0.1)")
    p.add_argument("--E", type=float, default=70e9, help="Young's modulus [Pa] (70e9)")
    p.add_argument("--nu", type=float, default=0.3, help="Poisson's ratio [-] (0.3)")
    p.add_argument("--contact-size", dest="contact_size", type=float, default=None,
                   help="element size at the contact [m] (default mesh: 4e-5 for R = 0.1)")
    p.add_argument("--ladder", action="store_true",
                   help="run the mesh ladder (contact sizes 1.6e-4 ... 1e-5 m) instead")
    p.add_argument("--out", default=None, help=f"output folder (default {DEFAULT_OUT})")
    p.add_argument("--json", action="store_true", help="print the summary as JSON on stdout")
    p.set_defaults(run=run)
    return p


def _validate(ns):
    def finite_positive(name, value):
        if not (math.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be a finite number > 0, got {value}")

    finite_positive("--P-min", ns.P_min)
    finite_positive("--P-max", ns.P_max)
    if not ns.P_max > ns.P_min:
        raise ValueError(f"--P-max must be > --P-min = {ns.P_min}, got {ns.P_max}")
    if not 2 <= ns.steps <= 1000:
        raise ValueError(f"--steps must be in [2, 1000], got {ns.steps}")
    finite_positive("--radius", ns.radius)
    finite_positive("--E", ns.E)
    if not (math.isfinite(ns.nu) and 0 <= ns.nu < 0.5):
        raise ValueError(f"--nu must be in [0, 0.5), got {ns.nu}")
    if ns.contact_size is not None:
        finite_positive("--contact-size", ns.contact_size)


def run(ns) -> int:
    _validate(ns)
    import json
    from pathlib import Path

    from calib import output
    from calib.studies.hertz import write_hertz_results, write_ladder_results

    out = Path(ns.out) if ns.out else Path(DEFAULT_OUT)
    if ns.ladder:
        summary = write_ladder_results(out, radius=ns.radius, E=ns.E, nu=ns.nu,
                                       P_min=ns.P_min, P_max=ns.P_max, steps=ns.steps)
    else:
        summary = write_hertz_results(out, radius=ns.radius, E=ns.E, nu=ns.nu, P_min=ns.P_min,
                                      P_max=ns.P_max, steps=ns.steps,
                                      contact_size=ns.contact_size)
    if ns.json:
        print(output.to_json(summary), end="")
    else:
        print(json.dumps(summary.get("top_load", summary.get("default_choice")), indent=2))
        print(f"results written to {out}")
    return 0

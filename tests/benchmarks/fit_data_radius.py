"""fit-data's imprint radius (``radius`` column, calib.fit.measured.imprint) on FE drop tests the law did
not make: the model-form level of the radius kinds and sigma_Y recovered.

Per material (the three off-grid [[check]] materials of tests/benchmarks/master_unload_radius.py, sigma_Y
100 MPa, R = 0.1 m): direct FE load paths (calib.fit.master_radius_check.fe_run, finite strain as the
table above a = 0.05 R (--kinematics small-strain: the small-strain FE), the graded mesh of the table's
nodes, 17.9 elements across every contact radius from the lowest peak up, 16 loading steps per decade, 16
unloading steps) to 3, 7, 16, 40 and 100 P_Y, each unloaded to separation. Each path
is a noise-free drop test as calib.fit.vz_master_check takes them: v_in = sqrt(2 W_l / m*), e = sqrt(W_u /
W_l), the dent alpha_res and the radius the FE's contact radius at the peak (the gap extrapolation,
calib.fe.recovery; the pressure's is printed beside it). fit-data's vz-table fit (calib.fit.measured.
table_law.fit, no model-form term) per data kind gives ln(sigma_fit / sigma_true); over the materials
its rms is the kind's model-form level (imprint.MODEL_FORM), the rms residual per group its residual level.

Then the dynamic FE's own drop tests (results/impact/impact.json: aluminium, nu 0.3, E/sigma_Y 700, off the
table's E/sigma_Y nodes; contact_radius_max, the pressure extrapolation) through ``nfdcal fit-data``.

    .venv/bin/python tests/benchmarks/fit_data_radius.py [--load JSON] [--save JSON] [--rims] [--trials N [--noise REL]]

--save writes the FE drop tests (tests/data/vz_master_radius_fe.json is this file); --load reads them
instead of running the FE (about 1-2 minutes per material on one core). --rims also measures the FE's
residual imprint after separation (calib.fit.master_radius_check.residual_rim: where the flattening
reaches the dent, and the crest of the low lip beyond) against its contact radius at the peak.

Measured (the module doc of calib/fit/measured/imprint.py states them): the law's radius within -0.52..+0.66 % of
the FE's (the pressure extrapolation +0.9..+4.3 % above the gap's); sigma_Y from e and radius -0.10, +0.19, -0.31 %
(rms 0.22 %), with dents too rms 0.39 %; the residual rim -12.1..-12.6 % of the peak radius at 3 P_Y, -2.4..-6.5 % at
7-100 P_Y, sigma_Y with the rim as radius -0.29..+0.29 %; the dynamic FE's drop tests +0.37 %, interval covering 1e8 Pa.
--trials 40 (1 % noise on e and radius, 120 fits each, about 4 minutes): e and radius 95 % coverage 0.950, rms error
1.30 %, largest 3.40 %; e alone 0.950, 1.52 %, 4.38 %.
"""
import argparse
import json
import math
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from calib.fe.kinematics import KINEMATICS  # noqa: E402
from calib.fit.measured.data import ImpactData, Measurements  # noqa: E402
from calib.fit.measured.specimen import Specimen  # noqa: E402
from calib.fit.measured.table_law import fit  # noqa: E402
from calib.fit.vz_master_table import VZMasterTable  # noqa: E402

SIGMA_Y, RHO, R = 100e6, 2700.0, 0.1
MATERIALS = [(0.22, 2000.0), (0.38, 1500.0), (0.25, 150.0)]
PEAKS = (3.0, 7.0, 16.0, 40.0, 100.0)      # P_max / P_Y, inside the vz-unload law's window (from 2 P_Y)
N = 25.0 / 1.4                             # elements across every contact radius: the nodes' graded mesh
KINDS = {"drops e": (), "drops e+dent": ("dent",), "drops e+radius": ("radius",),
         "drops e+dent+radius": ("dent", "radius")}
DYNAMIC = ROOT / "results" / "impact" / "impact.json"


def fe_drop_tests(nu: float, ratio: float, kinematics: str, rims: bool = False) -> dict:
    """The FE drop tests of one material (module doc)."""
    from calib.fe.loadpath import contact_work
    from calib.fit.master_radius_check import fe_run
    from nfdmodel import Material

    run = fe_run(Material(ratio * SIGMA_Y, nu, SIGMA_Y, RHO), R, PEAKS, N, fractions=(), rims=rims,
                 kinematics=kinematics)
    pair = run["pair"]
    tests = []
    for p in run["paths"]:
        work = contact_work(np.r_[0.0, p["loading_approach"]], np.r_[0.0, p["loading_force"]])
        tests.append({"P_max_over_P_Y": p["x"], "P_max": p["P_max"], "v_in": math.sqrt(2 * work / pair.mass_star),
                      "e": p["e"], "radius": p["radius_at_peak"], "radius_pressure": p["radius_at_peak_pressure"],
                      "dent": p["alpha_residual"], "alpha_max": p["alpha_max"],
                      **{k: p[k] for k in ("residual_rim", "residual_lip", "lip_height") if k in p}})
    return {"nu": nu, "E_over_sigma_y": ratio, "sigma_y": SIGMA_Y, "rho": RHO, "R": R,
            "elements_per_contact_radius": N, "kinematics": kinematics, "dofs": run["dofs"],
            "wall_time_s": run["wall_time_s"], "tests": tests}


def measurements(row: dict, kind: str) -> Measurements:
    """The drop tests of one stored material ``row`` as fit-data reads them, with the columns of ``kind``."""
    tests = row["tests"]
    column = {name: np.array([t[name] for t in tests]) for name in ("v_in", "e", "dent", "radius")}
    extra = KINDS[kind]
    return Measurements(impacts=ImpactData(f"{row['nu']}_{row['E_over_sigma_y']}_drops.csv", column["v_in"],
                                           column["e"], None, None, np.arange(1, len(tests) + 1),
                                           column["dent"] if "dent" in extra else None,
                                           column["radius"] if "radius" in extra else None))


def specimen(row: dict) -> Specimen:
    return Specimen(row["E_over_sigma_y"] * row["sigma_y"], row["nu"], row["R"], row["rho"])


def levels(rows: list[dict], table: VZMasterTable) -> dict:
    """Per kind: ln(sigma_fit / sigma_true) per material and its rms; the rms residual per group."""
    out = {}
    for kind in KINDS:
        errors, residuals = [], {}
        for row in rows:
            result = fit(measurements(row, kind), specimen(row), table, model_form={})
            errors.append(math.log(result.sigma_y / row["sigma_y"]))
            for group, r in result.residuals.items():
                residuals.setdefault(group, []).append(float(np.sqrt(np.mean(r**2))))
        out[kind] = {"errors": errors, "sigma_y": float(np.sqrt(np.mean(np.square(errors)))),
                     "residual_rms": {g: float(np.sqrt(np.mean(np.square(v)))) for g, v in residuals.items()}}
    return out


def coverage(rows: list[dict], table: VZMasterTable, noise: float, trials: int, seed: int = 1) -> dict:
    """Per kind ("drops e+radius", "drops e"): the FE drop tests with ``noise`` (relative, normal) on e and
    the radius, ``trials`` per material, fitted with --noise stated: fits, 95 % coverage, rms and largest
    |ln(sigma_fit / sigma_true)|."""
    rng = np.random.default_rng(seed)
    out = {}
    for kind in ("drops e+radius", "drops e"):
        covered, errors = 0, []
        for row in rows:
            for _ in range(trials):
                tests = [{**t, "e": t["e"] * (1 + noise * rng.standard_normal()),
                          "radius": t["radius"] * (1 + noise * rng.standard_normal())} for t in row["tests"]]
                try:
                    result = fit(measurements({**row, "tests": tests}, kind), specimen(row), table, noise=noise)
                except ValueError:
                    continue
                errors.append(math.log(result.sigma_y / row["sigma_y"]))
                covered += result.interval95[0] <= row["sigma_y"] <= result.interval95[1]
        errors = np.abs(errors)
        out[kind] = {"fits": int(errors.size), "coverage95": covered / max(errors.size, 1),
                     "rms_error": float(np.sqrt(np.mean(errors**2))), "max_error": float(errors.max())}
    return out


def dynamic_fit() -> dict:
    """``nfdcal fit-data --json`` on the dynamic FE's drop tests with their contact_radius_max (module doc)."""
    import tempfile

    case = json.loads(DYNAMIC.read_text(encoding="utf-8"))
    c = case["case"]
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "drops.csv"
        path.write_text("v_in,e,radius\n" + "".join(f"{t['v_in']!r},{t['e']!r},{t['contact_radius_max']!r}\n"
                                                   for t in case["impacts"]))
        out = subprocess.run([sys.executable, "-m", "calib.cli", "fit-data", "--impacts", str(path), "--E", repr(c["E"]),
                              "--nu", repr(c["nu"]), "--R", repr(c["R"]), "--rho", repr(c["rho"]), "--json"],
                             capture_output=True, text=True, cwd=ROOT)
    if out.returncode:
        raise SystemExit(out.stderr)
    return {"truth": c["sigma_y"], **json.loads(out.stdout)}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--load", type=Path, help="the FE drop tests written by --save (no FE run)")
    parser.add_argument("--save", type=Path, help="write the FE drop tests here (JSON)")
    parser.add_argument("--trials", type=int, default=0, help="noisy trials per material (--noise on e and radius)")
    parser.add_argument("--noise", type=float, default=0.01, help="relative noise of the trials (default 0.01)")
    parser.add_argument("--kinematics", choices=KINEMATICS, default="finite-strain",
                        help="the FE's kinematics (default finite-strain: the table's above a = 0.05 R)")
    parser.add_argument("--rims", action="store_true", help="also the FE's residual imprint rim after separation "
                                                             "(each path unloaded a second time)")
    args = parser.parse_args(argv)
    table = VZMasterTable.load()
    started = time.perf_counter()
    if args.load:
        rows = json.loads(args.load.read_text(encoding="utf-8"))["rows"]
    else:
        rows = [fe_drop_tests(nu, ratio, args.kinematics, args.rims) for nu, ratio in MATERIALS]
    if args.save:
        from calib import output

        output.write_json(args.save, {"source": "tests/benchmarks/fit_data_radius.py --save: direct FE load paths "
                                                "(calib.fit.master_radius_check.fe_run, fractions=(), kinematics per "
                                                "row) of three off-grid materials of the vz master table; radius: "
                                                "the FE's contact radius at the peak (gap), radius_pressure: the "
                                                "pressure extrapolation's",
                                      "rows": rows, "stamp": output.stamp(time.perf_counter() - started)})
    print("FE drop tests (quasi-static FE paths): the law's radius at the FE's P_max against the FE's (gap; pressure)")
    for row in rows:
        law = table.unload_law(specimen(row).material(row["sigma_y"]), row["R"])
        print(f"nu {row['nu']:g} E/sigma_Y {row['E_over_sigma_y']:g} ({row['wall_time_s']:.0f} s FE): " + ", ".join(
            f"{t['P_max_over_P_Y']:.3g} P_Y {100 * (float(law.contact_radius_at(t['P_max'])) / t['radius'] - 1):+.2f} % "
            f"({100 * (t['radius_pressure'] / t['radius'] - 1):+.2f} %)" for t in row["tests"]))
    for row in rows:
        if all("residual_rim" in t for t in row["tests"]):
            print(f"nu {row['nu']:g} E/sigma_Y {row['E_over_sigma_y']:g}: the residual imprint's rim (lip crest, its "
                  f"height / dent) against the FE's contact radius at the peak: " + ", ".join(
                      f"{t['P_max_over_P_Y']:.3g} P_Y {100 * (t['residual_rim'] / t['radius'] - 1):+.2f} % "
                      f"({100 * (t['residual_lip'] / t['radius'] - 1):+.1f} %, {t['lip_height']:.3f})"
                      for t in row["tests"]))
    with_rims = [row for row in rows if all("residual_rim" in t for t in row["tests"])]
    if with_rims:        # the residual rim read as the imprint's radius: what the modelling choice costs
        errors = [math.log(fit(measurements({**row, "tests": [{**t, "radius": t["residual_rim"]} for t in row["tests"]]},
                                            "drops e+radius"), specimen(row), table, model_form={}).sigma_y
                           / row["sigma_y"]) for row in with_rims]
        print("sigma_Y from e and the residual rim taken as the radius: "
              + ", ".join(f"{100 * e:+.2f} %" for e in errors))
    measured = levels(rows, table)
    print("\nkind                  ln(sigma_fit/sigma_true) per material        rms      residual rms per group")
    for kind, m in measured.items():
        print(f"{kind:20s}  " + "  ".join(f"{100 * e:+7.3f} %" for e in m["errors"])
              + f"   {100 * m['sigma_y']:6.3f} %   " + ", ".join(f"{g} {100 * v:.3f} %" for g, v in m["residual_rms"].items()))
    print("\nMODEL_FORM = " + json.dumps({"sigma_y": {k: round(measured[k]["sigma_y"], 6) for k in KINDS if "radius" in k},
                                         "residual_rms": {f"{k}: {g}": round(v, 6) for k in KINDS if "radius" in k
                                                          for g, v in measured[k]["residual_rms"].items()}}))
    if args.trials:
        for kind, c in coverage(rows, table, args.noise, args.trials).items():
            print(f"{kind}, {100 * args.noise:g} % noise on e and radius, {c['fits']} fits: 95 % coverage "
                  f"{c['coverage95']:.3f}, rms error {100 * c['rms_error']:.2f} %, largest {100 * c['max_error']:.2f} %")
    result = dynamic_fit()
    low, high = result["sigma_y_interval95"]
    print(f"\ndynamic FE drop tests (results/impact/impact.json, e and contact_radius_max): sigma_Y "
          f"{result['sigma_y']:.5g} Pa ({100 * (result['sigma_y'] / result['truth'] - 1):+.2f} %), 95 % interval "
          f"{low:.5g}..{high:.5g} Pa (covers the truth: {low <= result['truth'] <= high}); radius residuals "
          + ", ".join(f"{100 * r:+.2f} %" for r in result["residuals"]["radius"])
          + f"; left out {[t['row'] for t in result['left_out']]}")


if __name__ == "__main__":
    main()

"""Benchmark: sigma_Y recovered by fit-data's vz-table model (its default) from FE data the law did not make.

The project's FE stands in for the laboratory (material known): the off-grid materials of the
scene vz_master_grid (calib/scenes/builtin/sweeps/vz_master_grid.toml, ``[[check]]``; not table nodes,
nu 0.22-0.45, E/sigma_Y 150-3000), each an FE calibration at the FE's reach with unloading paths
log-spaced over its window (their data in results/tables/vz_master_grid/nodes/, kind "check").
From each material:

    drop tests      one per FE load-unload path whose peak lies inside the table's window at that
                    material: v_in = sqrt(2 W_l / m*) (the FE's loading work), e = sqrt(W_u / W_l)
                    (the work the FE returned), P_max the FE peak; fitted on e alone ("drops e")
                    and on e and P_max ("drops e+P"), and with the contact time of the FE loop
                    thrown as a quasi-static impact (calib.studies.impact_quasistatic; "drops e+P+t")
    force-approach  the FE loading branch to the highest path's peak and its unloading ("force")

    repeated       the drop tests twice at each FE speed, the noise drawn anew ("drops e x2",
                    "drops e+P x2"; 3 % noise, half the trials): twice the tests, the
                    statistical error falls as 1/sqrt(2)

    dynamic FE     the drop tests of ``nfdcal impact`` (results/impact/drop_tests.csv: the whole
                   sphere of the reference aluminium, E/sigma_Y 700, nu 0.3, not a table node, thrown
                   at the rigid flat; e, P_max, contact time of the dynamic FE) inside the table's
                   window ("dyn: ..."; the table's own model-form error)

with 0 % noise (one trial) and 1 %, 3 % multiplicative Gaussian noise (``--trials`` seeded trials
each; e capped at 1) on every measured value. Fitted: sigma_Y alone (calib.fit.measured.table_law,
no start given), its 95 % interval including the law's model-form error, measured on the other
check materials (leave one out: a material does not set its own interval). Printed and written
(results/fit_data/fe_benchmark.csv, .json, stamped): per data kind and noise level, over the
materials and trials, the bias (mean of sigma_fit / sigma_true - 1), the rms and largest error,
the coverage of the 95 % intervals with its binomial 95 % interval (Clopper-Pearson,
scipy.stats.binomtest), and what the data allow: the Cramer-Rao spread of ln sigma_Y,

    sd_CR = noise / sqrt(sum_i (d r_i / d ln sigma_Y)^2)       (r_i the relative residuals fitted)

(the law's sensitivities at the true sigma_Y; d ln e / d ln sigma_Y is 0-0.5 over a drop-test
window, so one drop test at 3 % noise alone determines sigma_Y to about 7-10 %), rms over the
materials, and the share of fits within 3 % an unbiased estimator of that spread would reach,
2 Phi(0.03 / sd_CR) - 1, averaged over the materials. Targets: the noise-free largest error (the
method's bias) within 3 %, |error| of noisy fits within 3 %, coverage >= 90 %. For comparison,
the noise-free data also go through the two-constant constrained model (``nfdcal fit-data
--law vz``: Ca_hat, Kc_hat of the master table; "vz: ..." rows; its interval: +-1.96 SE).

Usage: .venv/bin/python tests/benchmarks/bench_fit_data_fe.py [--trials 30] [--seed 1]
       [--nodes results/tables/vz_master_grid/nodes] [--impacts results/impact] [--out results/fit_data]
"""
from __future__ import annotations

import argparse
import json
import math
import time
from pathlib import Path

import numpy as np
from scipy import stats

from calib import output
from calib.fit.measured.table_law import fit, residuals, table_law
from calib.fit.vz_master_check import DATA_KINDS, fe_datasets, measurements
from calib.fit.vz_master_table import VZMasterTable

NOISES = (0.0, 0.01, 0.03)
REPEATED = ("drops e x2", "drops e+P x2")      # each drop test twice (module doc)
REPEATED_NOISE = 0.03                          # ... at this noise, in the first half of the trials
KINDS = DATA_KINDS + REPEATED
DYNAMIC_KINDS = ("dyn: drops e", "dyn: drops e+P", "dyn: drops e+P+t")   # the dynamic FE's impacts
CR_STEP = 1e-3                                 # the central-difference step in ln sigma_Y of sd_CR
TARGET_ERROR, TARGET_COVERAGE = 0.03, 0.90


def noisy(sets: dict, noise: float, rng, repeats: int = 1) -> dict:
    """The FE data with multiplicative Gaussian noise, each drop test ``repeats`` times."""
    def draw(size):
        return noise * rng.standard_normal(size) if noise else np.zeros(size)

    d = {k: np.tile(v, repeats) for k, v in sets["drops"].items()}
    e = np.minimum(d["e"] * (1 + draw(d["e"].size)), 1.0)
    P = d["P_max"] * (1 + draw(d["P_max"].size))
    t = d["contact_time"] * (1 + draw(d["contact_time"].size))
    approach, force = sets["force"]
    force = force * (1 + draw(force.size))
    return {"v_in": d["v_in"], "e": e, "P_max": P, "contact_time": t, "approach": approach, "force": force}


def base_kind(kind: str) -> str:
    return kind.removesuffix(" x2")


def information(sets: dict, table: VZMasterTable, name: str) -> dict:
    """Per data kind: sum_i (d r_i / d ln sigma_Y)^2 of the noise-free data at the true sigma_Y
    (module doc: sd_CR = noise / sqrt of it)."""
    out = {}
    for kind in KINDS:
        values = noisy(sets, 0.0, None, 2 if kind in REPEATED else 1)
        data = measurements(base_kind(kind), values, name)
        ends = [residuals(table_law(sets["specimen"], sets["sigma_y"] * math.exp(h), table), data)
                for h in (CR_STEP, -CR_STEP)]
        out[kind] = float(sum(np.sum(((ends[0][g] - ends[1][g]) / (2 * CR_STEP)) ** 2) for g in ends[0]))
    return out


def left_out_model_form(table: VZMasterTable, name: str) -> dict:
    """u per data kind from the other check materials' noise-free fit errors (the table's .json):
    the material under test does not set its own interval."""
    errors = table.meta.get("accuracy_details", {}).get("sigma_y_fit_errors", {})
    others = [e for n, e in errors.items() if n != name]
    return {kind: float(np.sqrt(np.mean([e[kind] ** 2 for e in others]))) for kind in DATA_KINDS} if others else {}


def run(nodes: Path, trials: int, seed: int, table: VZMasterTable) -> list[dict]:
    rows = [json.loads(p.read_text()) for p in sorted(nodes.glob("*.json"))]
    rows = sorted([r for r in rows if r.get("kind") == "check" and r.get("status") == "ok"],
                  key=lambda r: r["E_over_sigma_y"])
    rng = np.random.default_rng(seed)
    out = []
    for row in rows:
        sets = fe_datasets(row, table)
        form = left_out_model_form(table, row["name"])
        info = information(sets, table, row["name"])
        for noise in NOISES:
            for trial in range(1 if noise == 0 else trials):
                values = {1: noisy(sets, noise, rng)}
                if noise == REPEATED_NOISE and trial < max(trials // 2, 1):
                    values[2] = noisy(sets, noise, rng, 2)
                for kind in KINDS:
                    repeats = 2 if kind in REPEATED else 1
                    if repeats not in values:
                        continue
                    record = {"material": row["name"], "nu": row["nu"], "E_over_sigma_y": row["E_over_sigma_y"],
                              "kind": kind, "noise": noise, "trial": trial,
                              "n_drops": int(values[repeats]["v_in"].size),
                              "window_low": sets["window"][0], "window_top": sets["window"][1],
                              "sd_cr": noise / math.sqrt(info[kind]) if info[kind] > 0 else math.inf}
                    try:
                        result = fit(measurements(base_kind(kind), values[repeats], row["name"]), sets["specimen"],
                                     table, noise=noise or None, model_form=form)
                    except ValueError as exc:
                        out.append({**record, "error": str(exc)[:200]})
                        continue
                    low, high = result.interval95
                    out.append({**record, "sigma_y_error": result.sigma_y / sets["sigma_y"] - 1.0,
                                "se_rel": result.se / result.sigma_y, "se_stat_rel": result.se_stat / result.sigma_y,
                                "se_model_rel": result.se_model / result.sigma_y,
                                "interval_rel": [low / sets["sigma_y"] - 1.0, high / sets["sigma_y"] - 1.0],
                                "dof_statistical": result.uncertainty["dof_statistical"],
                                "covered": bool(low <= sets["sigma_y"] <= high), "rms_residual": result.rms_residual,
                                "consistent": result.consistent})
        for kind in ("drops e", "force"):
            out.append(two_constant_fit(kind, noisy(sets, 0.0, rng), sets, row))
    return out


def dynamic(impacts: Path, trials: int, seed: int, table: VZMasterTable) -> list[dict]:
    """The dynamic FE's drop tests (``nfdcal impact``: the whole sphere thrown at the rigid flat,
    impacts/drop_tests.csv, the material in impacts/impact.json) inside the table's window, fitted
    as the checks' (kinds "dyn: drops e", "dyn: drops e+P", "dyn: drops e+P+t"), the table's own
    model-form error (the material is not a check)."""
    from calib.fit.measured.data import read_impacts
    from calib.fit.measured.specimen import Specimen
    from nfdmodel import Material

    case = json.loads((impacts / "impact.json").read_text())["case"]
    material = Material(case["E"], case["nu"], case["sigma_y"], case["rho"])
    data = read_impacts(impacts / "drop_tests.csv")
    law = table.law(material, case["R"])
    pair_P_Y, top = law.pair.P_Y, law.window.P_max_over_P_Y
    keep = data.P_max <= top * pair_P_Y
    sets = {"specimen": Specimen(material.E, material.nu, case["R"], material.rho), "sigma_y": material.sigma_y,
            "drops": {"v_in": data.v_in[keep], "e": data.e[keep], "P_max": data.P_max[keep],
                      "contact_time": data.contact_time[keep]},
            "force": (np.zeros(1), np.zeros(1)), "window": (float(data.P_max[keep].min() / pair_P_Y), top)}
    name = f"dynamic FE E/sigma_Y {material.E / material.sigma_y:g}, nu {material.nu:g}"
    rng = np.random.default_rng(seed + 1)
    out = []
    for noise in NOISES:
        for trial in range(1 if noise == 0 else trials):
            values = noisy(sets, noise, rng)
            for kind in DYNAMIC_KINDS:
                record = {"material": name, "nu": material.nu, "E_over_sigma_y": material.E / material.sigma_y,
                          "kind": kind, "noise": noise, "trial": trial, "n_drops": int(keep.sum()),
                          "window_low": sets["window"][0], "window_top": top}
                result = fit(measurements(kind.removeprefix("dyn: "), values, name), sets["specimen"], table,
                             noise=noise or None)
                low, high = result.interval95
                out.append({**record, "sigma_y_error": result.sigma_y / sets["sigma_y"] - 1.0,
                            "se_rel": result.se / result.sigma_y, "covered": bool(low <= sets["sigma_y"] <= high),
                            "rms_residual": result.rms_residual, "consistent": result.consistent})
    return out


def two_constant_fit(kind: str, values: dict, sets: dict, row: dict) -> dict:
    """The noise-free data through the two-constant constrained model (module doc)."""
    from calib.fit.master_table import MasterTable
    from calib.fit.measured.models import fit_constrained

    record = {"material": row["name"], "nu": row["nu"], "E_over_sigma_y": row["E_over_sigma_y"],
              "kind": f"vz: {kind}", "noise": 0.0, "trial": 0}
    try:
        result = fit_constrained(measurements(kind, values, row["name"]), sets["specimen"], MasterTable.load())
    except ValueError as exc:
        return {**record, "error": str(exc)[:200]}
    estimate, se = result.values["sigma_y"], result.standard_errors["sigma_y"] or 0.0
    return {**record, "sigma_y_error": estimate / sets["sigma_y"] - 1.0, "se_rel": se / estimate,
            "covered": bool(abs(estimate - sets["sigma_y"]) <= 1.959964 * se), "rms_residual": result.rms_residual}


def summarise(rows: list[dict]) -> list[dict]:
    """Per data kind and noise level (module doc); ``noise_free_max_abs_error``: the kind's
    noise-free largest error, the method's bias, stated on every row of the kind."""
    out = []
    for kind in KINDS + DYNAMIC_KINDS + ("vz: drops e", "vz: force"):
        for noise in NOISES:
            sel = [r for r in rows if r["kind"] == kind and r["noise"] == noise]
            ok = [r for r in sel if "sigma_y_error" in r]
            if not sel:
                continue
            err = np.array([r["sigma_y_error"] for r in ok]) if ok else np.array([np.nan])
            covered = sum(r["covered"] for r in ok)
            ci = stats.binomtest(covered, len(ok)).proportion_ci(0.95) if ok else None
            s = {"kind": kind, "noise": noise, "fits": len(sel), "failed": len(sel) - len(ok),
                 "materials": len({r["material"] for r in sel}),
                 "n_drops": int(np.median([r["n_drops"] for r in sel])) if "n_drops" in sel[0] else None,
                 "bias": float(np.mean(err)), "rms_error": float(np.sqrt(np.mean(err**2))),
                 "max_abs_error": float(np.max(np.abs(err))),
                 "within_target": float(np.mean(np.abs(err) <= TARGET_ERROR)),
                 "coverage95": covered / len(ok) if ok else float("nan"),
                 "coverage95_low": float(ci.low) if ci else float("nan"),
                 "coverage95_high": float(ci.high) if ci else float("nan"),
                 "median_se_rel": float(np.median([r["se_rel"] for r in ok])) if ok else float("nan")}
            if noise and "sd_cr" in sel[0]:
                sd = {r["material"]: r["sd_cr"] for r in sel}
                s["sd_cr"] = float(np.sqrt(np.mean(np.square(list(sd.values())))))
                s["within_target_cr"] = float(np.mean([2 * stats.norm.cdf(TARGET_ERROR / v) - 1 for v in sd.values()]))
            out.append(s)
    for s in out:
        free = [r for r in out if r["kind"] == base_kind(s["kind"]) and r["noise"] == 0]
        s["noise_free_max_abs_error"] = free[0]["max_abs_error"] if free else float("nan")
        s["bias_met"] = bool(s["noise_free_max_abs_error"] <= TARGET_ERROR)
        s["coverage_met"] = bool(s["coverage95"] >= TARGET_COVERAGE and s["failed"] == 0)
        s["meets_target"] = bool(s["max_abs_error"] <= TARGET_ERROR and s["coverage_met"])
    return out


def repo_relative(path) -> str:
    """``path`` relative to the checkout when inside it (stamps name no machine's folders)."""
    path, root = Path(path).resolve(), Path(__file__).resolve().parents[2]
    return path.relative_to(root).as_posix() if path.is_relative_to(root) else str(path)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--trials", type=int, default=30)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--nodes", default="results/tables/vz_master_grid/nodes")
    parser.add_argument("--table", default=None, help="vz master table CSV (default: the shipped one)")
    parser.add_argument("--impacts", default="results/impact", help="the dynamic FE impacts (nfdcal impact)")
    parser.add_argument("--out", default="results/fit_data")
    ns = parser.parse_args(argv)
    started = time.perf_counter()
    table = VZMasterTable.load(ns.table)
    rows = run(Path(ns.nodes), ns.trials, ns.seed, table) + dynamic(Path(ns.impacts), ns.trials, ns.seed, table)
    summary = summarise(rows)
    print(f"{'data':13s} {'noise':>5s} {'fits':>4s} {'fail':>4s} {'bias':>7s} {'rms':>7s} {'max|e|':>7s} "
          f"{'sd_CR':>6s} {'<=3%':>5s} {'CR<=3%':>6s} {'cover95 (CI)':>16s} {'se':>6s}  target")
    for s in summary:
        cr = (f"{100 * s['sd_cr']:5.2f}% {100 * s['within_target']:4.0f}% {100 * s['within_target_cr']:5.0f}%"
              if "sd_cr" in s else f"{'':6s} {100 * s['within_target']:4.0f}% {'':6s}")
        print(f"{s['kind']:13s} {100 * s['noise']:4.0f}% {s['fits']:4d} {s['failed']:4d} {100 * s['bias']:+6.2f}% "
              f"{100 * s['rms_error']:6.2f}% {100 * s['max_abs_error']:6.2f}% {cr} {100 * s['coverage95']:4.0f}% "
              f"({100 * s['coverage95_low']:3.0f}-{100 * s['coverage95_high']:3.0f}%) "
              f"{100 * s['median_se_rel']:5.2f}%  {'met' if s['meets_target'] else 'NOT met'}")
    per_material = {}
    for r in rows:
        if "sigma_y_error" in r and r["noise"] == 0:
            per_material.setdefault(r["material"], {})[r["kind"]] = r["sigma_y_error"]
    for name, errors in per_material.items():
        print(f"  {name}: noise-free error " + ", ".join(f"{k} {100 * v:+.2f} %" for k, v in errors.items()))
    out = Path(ns.out)
    stamp = output.stamp(time.perf_counter() - started, command="python tests/benchmarks/bench_fit_data_fe.py "
                         + " ".join(argv or []), trials=ns.trials, seed=ns.seed, table=repo_relative(table.path),
                         targets={"abs_error": TARGET_ERROR, "coverage95": TARGET_COVERAGE})
    output.write_csv(out / "fe_benchmark.csv", summary, comment=output.stamp_comment(stamp))
    output.write_json(out / "fe_benchmark.json", {"summary": summary, "fits": rows, "stamp": stamp})
    print(f"written to {out}/fe_benchmark.csv, .json ({time.perf_counter() - started:.0f} s)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

"""Benchmark: the relaxing rate-aware law's two constants fitted to the dynamic FE, and checked where not fitted.

Not a timed test. The relaxing law (nfdmodel.rate_relaxing: ds/dt = k (E*/sigma_Y) (v_n / (c a_ref) -
eps_dot_s(s)), s = 1 at first contact, held from the turning point) against ``nfdcal impact --rate-law`` (the
dynamic FE with the rate law) on 71 impacts, each law on the vz master table's vz-table law of its sphere:
- FIT: bench_rate_materials.py's six spheres (E/sigma_Y 300, 700, 1500; nu 0.25, 0.3, 0.4; R 0.05, 0.1 m) at 6,
  12, 24 v_Y with Cowper-Symonds D 40 q 5 and D 2 q 1 (36 impacts, coarse mesh): k and c by minimax of the e
  error (a grid of k 1.0-1.5 by 0.1 and c 5-6.5 by 0.25, then by 0.05 around its best);
- HELD OUT: the DEM sphere (mild steel, R 2 mm, 0.03-0.3 m/s, Cowper-Symonds D 40.4 q 5 and Johnson-Cook C 0.06
  from 1 /s; the impact's default mesh; 6) and tests/data/rate_fe_drops.json (the reference sphere, five rate
  laws, 0.0025-0.16 m/s; 29).
The law's e is its continuous-time impact (rate_relaxing.relaxing_reference; collide's leap-frog at its automatic
dt lies within 0.02 % of it, printed for the held-out DEM impacts). Printed: the fitted k, c against the shipped
RELAXATION_STIFFNESS, RELAXING_LENGTH_FACTOR; per impact the FE's e, the relaxing law's error at the shipped
constants and the error of the law fixed at first contact (nfdmodel.rate_aware, c = 26); the max and rms per
group; c_e, the c whose relaxing e equals each impact's (k as shipped): its rms ln(c_e / c) and its slope with
v_in per sphere and rate law (the model form fit-data's rate fit takes for the relaxing form: rate_fit.U_LN_C,
U_C_TREND); each form's rms and max error in e, P_max and contact time on the FIT impacts (their case folders'
impact.json: rate_fit.RATE_LAW_LEVEL, fit-data's misfit level); collide's cost per
impact, relaxing (its numpy time loop around the compiled step) against fixed (the compiled loop), and the
compiled step's cost per contact-step, relaxing against fixed, on 1e5 loading contacts. The FE records are
bench_rate_materials.py's, kept in ``--out`` (a first run makes them: about 10 minutes on one core; with them,
about 6 minutes).
Usage: .venv/bin/python tests/benchmarks/bench_rate_relaxing.py [--out DIR]
"""
from __future__ import annotations

import argparse
import json
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

import bench_rate_materials as materials
from calib.fit.measured.specimen import Specimen
from calib.fit.measured.table_law import table_law
from calib.fit.vz_master_table import VZMasterTable
from nfdmodel import RangeWarning, collide, rate_aware
from nfdmodel.rate_relaxing import (LAW, RELAXATION_STIFFNESS, RELAXING_LENGTH_FACTOR, RelaxingRateParams,
                                    relaxing_reference)
from nfdmodel.strain_rate import CowperSymonds, JohnsonCook, rate_law_of

COARSE_K = np.arange(1.0, 1.501, 0.1)
COARSE_C = np.arange(5.0, 6.501, 0.25)
FINE_STEP = 0.05


def cases(out: Path, table) -> list:
    """(group, name, base law, rate law, v_in [m/s], FE e) of the 71 impacts."""
    found, bases = [], {}

    def base_of(material, rho):
        if (material, rho) not in bases:
            E, nu, sigma_y, R = material
            bases[material, rho] = table_law(Specimen(E, nu, R, rho), sigma_y, table)
        return bases[material, rho]

    records = materials.fe_records(out, fine=False)
    for name, material in materials.MATERIALS.items():
        v_Y = materials.pair_of(material).v_Y
        for law, rate in materials.RATE_LAWS.items():
            if rate is not None:
                for multiple, e in zip(materials.MULTIPLES, records[name][law]):
                    found.append(("fit", f"{name} CS {law[3:]} {multiple:g} v_Y", base_of(material, materials.RHO),
                                  CowperSymonds(*rate), multiple * v_Y, e))
    dem = materials.dem_records(out)
    for law, (kind, first, second) in materials.DEM_RATE_LAWS.items():
        rate = CowperSymonds(first, second) if kind == "cowper-symonds" else JohnsonCook(first, second)
        for v, e in zip(materials.DEM_SPEEDS, dem[law]):
            found.append(("held out", f"DEM {law} {v:g} m/s", base_of(materials.DEM_SPHERE, materials.DEM_RHO),
                          rate, v, e))
    drops = json.loads(materials.DATA.read_text(encoding="utf-8"))
    specimen = drops["specimen"]
    material = (specimen["E"], specimen["nu"], specimen["sigma_y"], specimen["R"])
    for series, entry in drops["series"].items():
        for test in entry["tests"]:
            found.append(("held out", f"drops {series} {test['v_in']:g} m/s", base_of(material, specimen["rho"]),
                          rate_law_of(entry["rate_law"]), test["v_in"], test["e"]))
    return found


def errors(group: list, k: float, c: float) -> np.ndarray:
    """The relaxing law's e error [%] per impact of ``group`` at (k, c)."""
    return np.array([100.0 * (float(relaxing_reference(RelaxingRateParams("vz-table", base, rate, c, k), [v])
                                    .restitution[0]) / e - 1.0) for _, _, base, rate, v, e in group])


def fit(group: list) -> tuple:
    """(max |error| %, k, c) by minimax over the coarse grid, then by FINE_STEP around its best."""
    best = min((np.abs(errors(group, k, c)).max(), k, c) for k in COARSE_K for c in COARSE_C)
    _, k0, c0 = best
    fine = [(np.abs(errors(group, k, c)).max(), k, c)
            for k in k0 + FINE_STEP * np.arange(-2, 3) for c in c0 + FINE_STEP * np.arange(-5, 6)]
    return min([best] + fine)


def matching_c(base, rate, v, e) -> float:
    """c_e: the c whose relaxing e (k as shipped) equals the FE's e, by a root find (nan where none in 0.5-500)."""
    from scipy.optimize import brentq

    def gap(c):
        params = RelaxingRateParams("vz-table", base, rate, c)
        return float(relaxing_reference(params, [v]).restitution[0]) - e

    low, high = gap(0.5), gap(500.0)
    return brentq(gap, 0.5, 500.0, xtol=1e-4) if low * high < 0.0 else float("nan")


def c_spread(every: list) -> None:
    """The spread of c_e over the impacts (what fit-data's model form for c would take): rms ln(c_e / c) and, per
    sphere and rate law (3 speeds or more), the slope d ln c_e / d ln v_in."""
    found = np.array([matching_c(base, rate, v, e) for _, _, base, rate, v, e in every])
    ok = np.isfinite(found)
    ln = np.log(found[ok] / RELAXING_LENGTH_FACTOR)
    print(f"\nc_e (k {RELAXATION_STIFFNESS:g}): {ok.sum()} of {len(every)} impacts have one, "
          f"{found[ok].min():.3g}..{found[ok].max():.3g}; rms ln(c_e / {RELAXING_LENGTH_FACTOR:g}) "
          f"{np.sqrt(np.mean(ln**2)):.3f}")
    series = {}
    for (group, name, base, rate, v, e), c_e in zip(every, found):
        key = (id(base), repr(rate))
        series.setdefault(key, []).append((v, c_e))
    slopes = []
    for points in series.values():
        points = np.array([p for p in points if np.isfinite(p[1])])
        if len(points) >= 3:
            slopes.append(np.polyfit(np.log(points[:, 0]), np.log(points[:, 1]), 1)[0])
    slopes = np.array(slopes)
    print(f"d ln c_e / d ln v_in over {slopes.size} spheres and rate laws: {slopes.min():+.2f}..{slopes.max():+.2f}, "
          f"rms {np.sqrt(np.mean(slopes**2)):.2f}")


def force_and_time_levels(out: Path, table) -> None:
    """The rms and max error of each form's e, P_max and contact time against the FE on the FIT impacts (their case
    folders' impact.json under ``out``): the level of noise-free FE drop tests fit-data's rate fit takes
    (calib.fit.measured.rate_fit.RATE_LAW_LEVEL)."""
    errors_of = {form: {key: [] for key in ("e", "P_max", "contact_time")} for form in ("fixed", "relaxing")}
    for name, material in materials.MATERIALS.items():
        E, nu, sigma_y, R = material
        base = table_law(Specimen(E, nu, R, materials.RHO), sigma_y, table)
        for law, rate in materials.RATE_LAWS.items():
            if rate is None:
                continue
            folder = out / f"{name}-{law}".replace(" ", "_").replace("/", "")
            impacts = json.loads((folder / "impact.json").read_text(encoding="utf-8"))["impacts"]
            v = np.array([impact["v_in"] for impact in impacts])
            for form, reference in (("fixed", rate_aware.rate_aware_reference(
                    rate_aware.RateAwareParams("vz-table", base, CowperSymonds(*rate)), v)),
                    ("relaxing", relaxing_reference(RelaxingRateParams("vz-table", base, CowperSymonds(*rate)), v))):
                law_values = {"e": reference.restitution, "P_max": reference.P_max,
                              "contact_time": reference.contact_time_estimate}
                for key, values in law_values.items():
                    errors_of[form][key] += list(values / np.array([impact[key] for impact in impacts]) - 1.0)
    print("\n| form | e: rms, max % | P_max: rms, max % | contact time: rms, max % |\n|---|---|---|---|")
    for form, found in errors_of.items():
        print(f"| {form} | " + " | ".join(f"{100 * np.sqrt(np.mean(np.square(x))):.2f}, {100 * np.abs(x).max():.2f}"
                                         for x in map(np.array, found.values())) + " |")


def fixed_error(base, rate, v, e) -> float:
    params = rate_aware.RateAwareParams("vz-table", base, rate)
    return 100.0 * (float(rate_aware.rate_aware_reference(params, [v]).restitution[0]) / e - 1.0)


def main_(out: Path) -> None:
    warnings.simplefilter("ignore", RangeWarning)
    table = VZMasterTable.load(None)
    every = cases(out, table)
    fitted = [case for case in every if case[0] == "fit"]
    held = [case for case in every if case[0] != "fit"]
    started = time.perf_counter()
    worst, k, c = fit(fitted)
    print(f"fitted on the {len(fitted)} FIT impacts ({time.perf_counter() - started:.0f} s): k {k:.3g}, c {c:.3g} "
          f"(max {worst:.2f} %); shipped k {RELAXATION_STIFFNESS:g}, c {RELAXING_LENGTH_FACTOR:g}")
    shipped = errors(every, RELAXATION_STIFFNESS, RELAXING_LENGTH_FACTOR)
    print("\n| group | impact | FE e | relaxing e err % | fixed e err % |\n|---|---|---|---|---|")
    fixed = []
    for (group, name, base, rate, v, e), error in zip(every, shipped):
        fixed.append(fixed_error(base, rate, v, e))
        print(f"| {group} | {name} | {e:.4f} | {error:+.2f} | {fixed[-1]:+.2f} |")
    fixed = np.array(fixed)
    print("\n| group | impacts | relaxing: max, rms % | beyond 2 % | fixed: max, rms % | beyond 2 % |")
    print("|---|---|---|---|---|---|")
    for label, mask in (("fit", [g == "fit" for g, *_ in every]), ("held out", [g != "fit" for g, *_ in every]),
                        ("all", [True] * len(every))):
        mask = np.array(mask)
        mine, theirs = shipped[mask], fixed[mask]
        print(f"| {label} | {mask.sum()} | {np.abs(mine).max():.2f}, {np.sqrt(np.mean(mine**2)):.2f} | "
              f"{(np.abs(mine) > 2).sum()} | {np.abs(theirs).max():.2f}, {np.sqrt(np.mean(theirs**2)):.2f} | "
              f"{(np.abs(theirs) > 2).sum()} |")
    c_spread(every)
    force_and_time_levels(out, table)
    dem = [case for case in held if case[1].startswith("DEM")]
    print("\ncollide at the automatic dt against the continuous-time impact (DEM impacts), and the cost per impact:")
    for _, name, base, rate, v, e in dem:
        params = RelaxingRateParams("vz-table", base, rate)
        started = time.perf_counter()
        loop = collide(LAW, params, [v], dt=None)
        relaxing_time = time.perf_counter() - started
        started = time.perf_counter()
        collide(rate_aware.LAW, rate_aware.RateAwareParams("vz-table", base, rate), [v], dt=loop.dt)
        fixed_time = time.perf_counter() - started
        exact = float(relaxing_reference(params, [v]).restitution[0])
        print(f"  {name}: collide e {loop.e_velocity[0]:.5f}, continuous {exact:.5f} "
              f"({100 * (loop.e_velocity[0] / exact - 1):+.3f} %), {loop.steps} steps: relaxing {relaxing_time:.2f} s, "
              f"fixed {fixed_time:.3f} s")
    relaxing, fixed = kernel_cost(dem[-1][2], dem[-1][3])
    print(f"compiled step, {dem[-1][1]}'s law, 1e5 contacts loading: relaxing {relaxing:.0f} ns, fixed {fixed:.0f} ns "
          f"per contact-step ({relaxing / fixed:.2f} x; each step through nfdmodel's Python step and commit)")


def kernel_cost(base, rate, contacts: int = 100_000, steps: int = 20) -> tuple:
    """(relaxing, fixed) compiled step cost [ns per contact-step]: ``contacts`` contacts loading together at 0.1 m/s
    (each step moves every turning point: the element's solve runs on all), best of 3 runs of ``steps`` steps after
    the first touch (whose a_ref, the same in both, is not timed)."""
    from nfdmodel import native

    costs = []
    for law, params in ((LAW, RelaxingRateParams("vz-table", base, rate)),
                        (rate_aware.LAW, rate_aware.RateAwareParams("vz-table", base, rate))):
        best = float("inf")
        speed = np.full(contacts, 0.1)
        increment = 0.1 * params.pair.delta_Y
        for _ in range(3):
            state = law.initial_state(contacts)
            with native.use_backend("native"):
                _, update = law.step(np.full(contacts, increment), state, params, velocity=speed)   # first touch
                law.commit(state, update)
                started = time.perf_counter()
                for step in range(2, steps + 2):
                    _, update = law.step(np.full(contacts, step * increment), state, params, velocity=speed)
                    law.commit(state, update)
                best = min(best, (time.perf_counter() - started) / (contacts * steps) * 1e9)
        costs.append(best)
    return tuple(costs)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default=None, help="folder of the FE records (bench_rate_materials.py's; default: a "
                        "temporary folder)")
    args = parser.parse_args()
    if args.out is None:
        with tempfile.TemporaryDirectory() as folder:
            main_(Path(folder))
    else:
        main_(Path(args.out))

"""The shipped laws between their nodes, against FE paths that did not build them:
results/calibration/between_nodes.*

``nfdcal calibrate --v-max V`` ships the vz-table law, whose C_R nodes are the FE unloading paths
(calib.fit.impact_window, calib.fit.table_fit); ``nfdcal calibrate`` ships the paper's two
constants fitted on paths to 13.7, 27.4 and 41.2 P_Y. A law must hold at every load of its
declared window, not only where it was fitted. For E/sigma_Y = 700 (the paper's aluminium),
100 and 5000 (nu = 0.3, sigma_Y = 100 MPa, R = 0.1 m) this study calibrates, on the recipe's
mesh level (two meshes, as the commands do):

- ``log``: ``nfdcal calibrate --v-max V``, V = V_MAX or the fastest impact the FE vouches for
  (unloading paths log-spaced from the lowest load its mesh resolves to the top);
- ``thirds``: the same top with three unloading paths at 1/3, 2/3 and 1 of it, the default
  recipe's proportions (the fewest paths a table takes);
- ``narrow``: ``nfdcal calibrate`` (two constants, the radius fit; the reference paths 500,
  1000, 1500 N for the paper's aluminium).

Then the FE runs a load-unload path to each check peak on the mesh the recipe sizes for that
peak (the FE of ``nfdcal calibrate --peaks P``, loading stepped as the calibration's): the
geometric midpoints between consecutive unloading peaks of ``log`` and of ``narrow`` (between
the lowest loading point of its window and its first peak too), the peaks themselves (the law
at its nodes against a mesh sized for them), and the midpoint between P_Y and the lowest
unloading peak (below the declared window of ``log``). Per law and check path, as
calib.studies.wide_window:

    force error = max |P_law(alpha) - P_FE(alpha)| / P_max   along loading and unloading
    e error     = e_law / e_FE - 1     (the quasi-static cycle; e_collision: the law's impact at
                                        the v_in reaching the same P_max)

Target inside each law's declared window: force error <= 5 %, |e error| <= 2 %.
The calibrations' wall times (the FE cost of log against thirds) are in the JSON.

    python -m calib.studies.between_nodes [--out results/calibration] [--workers 1]
        [--ratios 700 100 5000] [--level default] [--plans log thirds narrow] [--prune]

Each calibration and each check path is one resumable task (``OUT/between_nodes/calibrations/``
and ``checks/<key>.json``, calib.sweep.runner) keeping its FE data; the comparison runs again
from them (seconds). The stored run (three materials, default level, one worker, a 2-core
machine shared with other work): 23 min for the nine calibrations, 28 min for the 52 check
paths (4 s to 5 min each).
"""
from __future__ import annotations

import argparse
import dataclasses
import math
import sys
import time
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_limits

from calib import output
from calib.fe import ContactSolver
from calib.fe.loadpath import contact_work, run_load_paths
from calib.fe.von_mises import VonMisesMaterial
from calib.fit import impact_window, recipe
from calib.fit.calibration import E_TARGET, FORCE_TARGET, calibrate
from calib.fit.path_check import law_against_path
from calib.sweep.runner import run_sweep
from meshes.hemisphere import hemisphere_mesh
from meshes.keys import stable_key
from nfdmodel import CalibrationWindow, ContactPair, Material, VZParams, VZTableParams

STRENGTH_RATIOS = (700.0, 100.0, 5000.0)            # E / sigma_Y
NU, SIGMA_Y, RHO, RADIUS = 0.3, 100e6, 2699.0, 0.1   # E/sigma_Y = 700: the paper's aluminium
V_MAX = 2.0                 # [m/s], or the fastest impact the FE vouches for
THIRDS = (1.0 / 3.0, 2.0 / 3.0, 1.0)
PLANS = ("log", "thirds", "narrow")
LAW_NAMES = {"log": "vz-table, paths log-spaced over the window (--v-max)",
             "thirds": "vz-table, paths at 1/3, 2/3, 1 of the top",
             "narrow": "vz, two constants (nfdcal calibrate)"}
SAME_PEAK = 1e-6            # relative: a check peak this close to an unloading peak is that node
MERGE = 0.02                # relative: check peaks closer than this are one path
CALIBRATION_VERSION = 3     # part of a calibration's key: bump when the FE or the fits change
CHECK_VERSION = 1           # part of a check path's key: bump when its FE changes


def study_material(ratio: float) -> Material:
    return Material(ratio * SIGMA_Y, NU, SIGMA_Y, RHO)


def study_v_max(ratio: float) -> float:
    """V_MAX, or (below it) the fastest impact the FE vouches for, rounded down to two digits."""
    material = study_material(ratio)
    params, _ = impact_window.estimating_constants(material, RADIUS)
    pair = params.pair
    fastest = impact_window.reach_velocity(params, recipe.fe_reach(pair) / impact_window.MARGIN)
    if fastest >= V_MAX:
        return V_MAX
    unit = 10.0 ** (math.floor(math.log10(fastest)) - 1)
    return math.floor(fastest / unit * (1 + 1e-12)) * unit


# ----------------------------------------------------------------------------- the calibrations
def calibration_task(ratio: float, plan: str, level: str) -> dict:
    """One calibration of the study: ``plan`` in PLANS (module doc)."""
    material = study_material(ratio)
    v_max = study_v_max(ratio)
    key = stable_key({"ratio": ratio, "plan": plan, "level": level, "v_max": v_max,
                      "version": CALIBRATION_VERSION, "kind": "calibration"})
    return {"key": key, "kind": "calibration", "E_over_sigma_y": ratio, "plan": plan, "level": level,
            "v_max": v_max, "material": material}


def thirds_spec(material: Material, v_max: float, level: str) -> recipe.CalibrationSpec:
    """Three paths at THIRDS of the first round's top of ``--v-max``, the recipe's loading steps."""
    needed, _, _ = impact_window.check_reach(material, RADIUS, v_max)
    top = impact_window.window_top(ContactPair.sphere_flat(material, RADIUS), needed)
    return recipe.calibration_spec(material, RADIUS, peaks=tuple(f * top for f in THIRDS), level=level)


def run_calibration(task: dict) -> dict:
    """The calibration (runs in a worker): the shipped law, its unloading peaks, its mesh, its
    FE paths and its wall time."""
    material, plan = task["material"], task["plan"]
    t0 = time.perf_counter()
    try:
        rounds = None
        if plan == "log":
            found = impact_window.calibrate_for_impacts(material, RADIUS, task["v_max"], ship="table",
                                                        level=task["level"])
            result, rounds = found.result, list(found.rounds)
        elif plan == "thirds":
            result = calibrate(thirds_spec(material, task["v_max"], task["level"]), ship="table")
        else:
            result = calibrate(recipe.calibration_spec(material, RADIUS, level=task["level"]))
        params = result.shipped_params
    except Exception as exc:                    # noqa: BLE001 - reported in the row, retried next run
        return {"key": task["key"], "status": "failed", "error": f"{type(exc).__name__}: {exc}"[:300]}
    pair = result.spec.pair
    law = ({"law": "vz-table", "x": list(params.x), "f": list(params.f), "g": list(params.g)}
           if isinstance(params, VZTableParams) else {"law": "vz", "Ca": params.Ca, "Kc": params.Kc})
    return {"key": task["key"], "status": "ok", "kind": "calibration", "E_over_sigma_y": task["E_over_sigma_y"],
            "plan": plan, "level": task["level"], "v_max": task["v_max"], "rounds": rounds,
            "shipped": {**law, "window": params.window.record()},
            "unloading_peaks_over_P_Y": [p / pair.P_Y for p in result.spec.plan.peaks],
            "mesh": dataclasses.asdict(result.spec.mesh), "dofs": result.mesh_info["dofs"],
            "loading_steps": len(result.spec.plan.loading_targets()),
            "fe_steps": len(result.load_paths.loading_rows) + sum(
                r["branch"] == "unloading" for p in result.load_paths.paths for r in p.rows),
            "paths": [path_record(p.peak, p.restitution, p.rows) for p in result.load_paths.paths],
            "table_rel_error_estimate": result.table_rel_error_estimate(),
            "wall_time_s": time.perf_counter() - t0, "timings": result.timings, "git_commit": output.git_commit()}


def shipped_law(row: dict) -> tuple[str, object]:
    """(law name, parameters) of a calibration row."""
    pair = ContactPair.sphere_flat(study_material(row["E_over_sigma_y"]), RADIUS)
    shipped = row["shipped"]
    window = CalibrationWindow.from_record(shipped["window"])
    if shipped["law"] == "vz-table":
        return "vz-table", VZTableParams(pair, tuple(shipped["x"]), tuple(shipped["f"]), tuple(shipped["g"]), window)
    return "vz", VZParams(pair, shipped["Ca"], shipped["Kc"], window)


# ----------------------------------------------------------------------------- the check paths
def check_peaks(calibrations: dict) -> dict[float, str]:
    """Check peak [P/P_Y] -> why it is checked, from one material's calibration rows (plan -> row):
    the midpoints between the unloading peaks of ``log`` (and below its lowest), the peaks
    themselves, and the midpoints of ``narrow``'s window and peaks."""
    peaks = {}
    log = calibrations.get("log")
    if log is not None:
        nodes = log["unloading_peaks_over_P_Y"]
        peaks[math.sqrt(nodes[0])] = "below the lowest unloading path of log"
        peaks.update({math.sqrt(a * b): "between unloading paths of log" for a, b in zip(nodes, nodes[1:])})
        peaks.update({x: "an unloading peak of log" for x in nodes})
    narrow = calibrations.get("narrow")
    if narrow is not None:
        nodes = [narrow["shipped"]["window"]["P_min_over_P_Y"]] + narrow["unloading_peaks_over_P_Y"]
        peaks.update({math.sqrt(a * b): "between the paths of narrow" for a, b in zip(nodes, nodes[1:])})
        peaks.update({x: "an unloading peak of narrow" for x in nodes[1:]})
    merged = {}
    for x in sorted(peaks):
        if merged and x <= max(merged) * (1.0 + MERGE):
            continue
        merged[x] = peaks[x]
    return merged


def check_task(ratio: float, x: float, reason: str, level: str = "default", *, material: Material | None = None,
               mesh=None) -> dict:
    """The FE path to x P_Y on the recipe's mesh for that peak (module doc), or on ``mesh``;
    ``material``: the study's of E/sigma_Y = ``ratio`` unless given."""
    material = material or study_material(ratio)
    pair = ContactPair.sphere_flat(material, RADIUS)
    spec = recipe.calibration_spec(material, RADIUS, peaks=(x * pair.P_Y,), level=level)
    spec = dataclasses.replace(spec, mesh=mesh or spec.mesh, plan=impact_window.GeometricLoadPathPlan(
        peaks=spec.plan.peaks, loading_step=spec.plan.peaks[-1], unloading_steps=spec.plan.unloading_steps,
        first_load=spec.plan.first_load))
    key = stable_key({"material": dataclasses.asdict(material), "x": x, "mesh": spec.mesh.cache_key(),
                      "plan": dataclasses.asdict(spec.plan), "version": CHECK_VERSION, "kind": "check"})
    return {"key": key, "kind": "check", "E_over_sigma_y": ratio, "P_max_over_P_Y": x, "reason": reason,
            "spec": spec}


def run_check(task: dict) -> dict:
    """The FE of one check path (runs in a worker): no fit, only the path."""
    spec = task["spec"]
    t0 = time.perf_counter()
    try:
        with threadpool_limits(limits=1, user_api="blas"):   # as calib.fit.calibration: small matrices
            solver = ContactSolver(hemisphere_mesh(spec.mesh), VonMisesMaterial(
                spec.material.E, spec.material.nu, spec.material.sigma_y),
                residual_tolerance=spec.residual_tolerance, contact_radius_method=spec.contact_radius_method)
            path = run_load_paths(solver, spec.plan).paths[0]
    except Exception as exc:                    # noqa: BLE001 - reported in the row, retried next run
        return {"key": task["key"], "status": "failed", "error": f"{type(exc).__name__}: {exc}"[:300]}
    return {"key": task["key"], "status": "ok", "kind": "check", "E_over_sigma_y": task["E_over_sigma_y"],
            "P_max_over_P_Y": task["P_max_over_P_Y"], "reason": task["reason"],
            "mesh": dataclasses.asdict(spec.mesh), "dofs": int(solver.n_dofs),
            **path_record(path.peak, path.restitution, path.rows),
            "wall_time_s": time.perf_counter() - t0, "git_commit": output.git_commit()}


def path_record(peak: float, e: float, rows: list[dict]) -> dict:
    return {"P_max": peak, "e": e, "rows": [{k: r[k] for k in ("P", "alpha", "branch")} for r in rows]}


def fe_path(record: dict) -> dict:
    """A stored FE path as calib.fit.path_check.law_against_path takes it, its e from
    :func:`path_restitution`."""
    approach = np.array([r["alpha"] for r in record["rows"]])
    force = np.array([max(r["P"], 0.0) for r in record["rows"]])
    return {"P_max": record["P_max"], "e": path_restitution(approach, force), "approach": approach, "force": force}


def path_restitution(approach: np.ndarray, force: np.ndarray) -> float:
    """e = sqrt(W_u / W_l) of an FE load-unload path (approach [m], force [N], from the first
    load to separation), the works as calib.fe.loadpath takes them (contact_work: Hertz's
    (2/5) P alpha on the segments from zero and to separation)."""
    top = int(np.argmax(approach))
    loading = contact_work(np.r_[0.0, approach[:top + 1]], np.r_[0.0, force[:top + 1]])
    return float(np.sqrt(contact_work(approach[top:], force[top:]) / loading))


# ----------------------------------------------------------------------------- the comparison
def where(x: float, window: CalibrationWindow, nodes) -> str:
    """'node', 'between', 'below window' or 'above window' of a check peak x [P/P_Y]."""
    if x < window.P_min_over_P_Y * (1.0 - SAME_PEAK):
        return "below window"
    if x > window.P_max_over_P_Y * (1.0 + SAME_PEAK):
        return "above window"
    return "node" if any(abs(x / node - 1.0) <= SAME_PEAK for node in nodes) else "between"


def compare(calibrations: list[dict], checks: list[dict]) -> list[dict]:
    """Per material, law and check path: the errors (module doc)."""
    rows = []
    for calibration in calibrations:
        law, params = shipped_law(calibration)
        nodes = calibration["unloading_peaks_over_P_Y"]
        for check in checks:
            if check["E_over_sigma_y"] != calibration["E_over_sigma_y"]:
                continue
            x = check["P_max_over_P_Y"]
            place = where(x, params.window, nodes)
            errors = law_against_path(law, params, fe_path(check))
            rows.append({"E_over_sigma_y": check["E_over_sigma_y"], "plan": calibration["plan"], "law": law,
                         "P_max_over_P_Y": x, "where": place, "reason": check["reason"],
                         **errors, "meets_target": (errors["force_error"] <= FORCE_TARGET
                                                    and abs(errors["e_error"]) <= E_TARGET),
                         "e_fe_loadpath": check["e"], "check_dofs": check["dofs"]})
    return rows


def summarize(rows: list[dict], calibrations: list[dict]) -> list[dict]:
    """Per material and law: its window, nodes, FE cost and the worst errors inside its window
    (between nodes, at nodes) and below it."""
    out = []
    for calibration in calibrations:
        mine = [r for r in rows if r["E_over_sigma_y"] == calibration["E_over_sigma_y"]
                and r["plan"] == calibration["plan"]]

        def worst(places, key):
            values = [abs(r[key]) for r in mine if r["where"] in places and key in r]
            return max(values) if values else None

        out.append({"E_over_sigma_y": calibration["E_over_sigma_y"], "plan": calibration["plan"],
                    "law": LAW_NAMES[calibration["plan"]], "v_max": calibration["v_max"],
                    "window": calibration["shipped"]["window"],
                    "unloading_peaks_over_P_Y": calibration["unloading_peaks_over_P_Y"],
                    "calibration_wall_time_s": calibration["wall_time_s"], "dofs": calibration["dofs"],
                    "table_rel_error_estimate": calibration.get("table_rel_error_estimate"),
                    "loading_steps": calibration["loading_steps"], "fe_steps": calibration["fe_steps"],
                    "rounds": calibration["rounds"],
                    **{f"worst_{key}_{name}": worst(places, key)
                       for name, places in (("between", ("between",)), ("inside", ("between", "node")),
                                            ("below", ("below window",)))
                       for key in ("e_error", "e_collision_error", "force_error")},
                    "meets_target_inside": all(r["meets_target"] for r in mine if r["where"] in ("between", "node"))})
    return out


# ----------------------------------------------------------------------------- the study
def generate(out=output.RESULTS / "calibration", workers: int = 1, ratios=STRENGTH_RATIOS, level: str = "default",
             plans=PLANS, progress=None, prune: bool = False) -> dict:
    """Run (or resume) the calibrations, then the check paths, and write OUT/between_nodes.csv,
    .json and .png; ``prune``: delete stored tasks this run does not have (of another version)."""
    out = Path(out)
    folder = out / "between_nodes"
    started = time.perf_counter()
    ok = lambda row: row.get("status") == "ok"      # noqa: E731
    calibrations = run_sweep([calibration_task(r, p, level) for r in ratios for p in plans], run_calibration,
                             folder / "calibrations", keep=ok, workers=workers, progress=progress, prune=prune,
                             describe=lambda row: f"calibration {row.get('E_over_sigma_y')} {row.get('plan')} "
                                                  f"({row['status']})").rows
    done = [c for c in calibrations if ok(c)]
    tasks = []
    for ratio in ratios:
        mine = {c["plan"]: c for c in done if c["E_over_sigma_y"] == ratio}
        tasks += [check_task(ratio, x, reason, level) for x, reason in check_peaks(mine).items()]
    checks = run_sweep(tasks, run_check, folder / "checks", keep=ok, mesh_of=lambda task: task["spec"].mesh,
                       workers=workers, progress=progress, prune=prune,
                       describe=lambda row: f"check {row.get('E_over_sigma_y')} at "
                                            f"{row.get('P_max_over_P_Y', 0):.4g} P_Y ({row['status']})").rows
    rows = compare(done, [c for c in checks if ok(c)])
    summary = summarize(rows, done)
    failures = [{k: row.get(k) for k in ("key", "error")} for row in calibrations + checks if not ok(row)]
    st = output.stamp(time.perf_counter() - started, mesh={"level": level},
                      command="python -m calib.studies.between_nodes",
                      targets={"force_error": FORCE_TARGET, "e_error": E_TARGET})
    output.write_csv(out / "between_nodes.csv", rows, columns=COLUMNS, comment=output.stamp_comment(st))
    output.write_json(out / "between_nodes.json", {"laws": summary, "failures": failures,
                                                   "check_paths": [{k: c.get(k) for k in (
                                                       "E_over_sigma_y", "P_max_over_P_Y", "reason", "e", "dofs",
                                                       "wall_time_s")} for c in checks if ok(c)],
                                                   "rows": rows, "stamp": st})
    if rows:
        _plot(rows, out / "between_nodes.png")
    return {"laws": summary, "rows": rows, "failures": failures}


COLUMNS = ("E_over_sigma_y", "plan", "law", "P_max_over_P_Y", "where", "reason", "force_error", "e_fe", "e_law",
           "e_error", "v_in", "v_in_over_v_Y", "e_collision", "e_collision_error", "meets_target", "e_fe_loadpath", "check_dofs")
MARKERS = {"log": "o-", "thirds": "s--", "narrow": "^:"}


def _plot(rows: list[dict], path: Path) -> None:
    """e error and force error against the check peak, per material and law, up to the top of
    each law's window (beyond it the law warns that it extrapolates)."""
    plt = output.pyplot()
    fig, (ax_e, ax_force) = plt.subplots(1, 2, figsize=(13, 4.5))
    for k, ratio in enumerate(sorted({r["E_over_sigma_y"] for r in rows})):
        for plan, marker in MARKERS.items():
            sel = sorted((r for r in rows if r["E_over_sigma_y"] == ratio and r["plan"] == plan
                          and r["where"] != "above window"), key=lambda r: r["P_max_over_P_Y"])
            if not sel:
                continue
            x = [r["P_max_over_P_Y"] for r in sel]
            label = f"E/sigma_Y = {ratio:g}, {LAW_NAMES[plan]}"
            ax_e.plot(x, [100 * r["e_error"] for r in sel], marker, color=f"C{k}", label=label, ms=4)
            ax_force.plot(x, [100 * r["force_error"] for r in sel], marker, color=f"C{k}", ms=4)
            outside = [r for r in sel if r["where"] not in ("between", "node")]
            ax_e.plot([r["P_max_over_P_Y"] for r in outside], [100 * r["e_error"] for r in outside], "x", color="k", ms=7)
    for sign in (1, -1):
        ax_e.axhline(sign * 100 * E_TARGET, color="k", lw=0.8, ls=":")
    ax_force.axhline(100 * FORCE_TARGET, color="k", lw=0.8, ls=":")
    for ax, label in ((ax_e, "e_law / e_FE - 1 [%]"), (ax_force, "max |P_law - P_FE| / P_max [%]")):
        ax.set_xscale("log"), ax.set_xlabel("P_max / P_Y of the FE check path"), ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    ax_e.set_title("quasi-static e against FE paths the law did not see (x: below its window;"
                   " beyond it: not shown)", fontsize=9)
    ax_force.set_title("force error along those paths (target 5 %)", fontsize=9)
    ax_e.legend(fontsize=6)
    output.save_figure(fig, path)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(output.RESULTS / "calibration"))
    parser.add_argument("--workers", type=int, default=1)
    parser.add_argument("--ratios", type=float, nargs="+", default=list(STRENGTH_RATIOS))
    parser.add_argument("--level", default="default", choices=tuple(recipe.MESH_LEVELS))
    parser.add_argument("--plans", nargs="+", default=list(PLANS), choices=PLANS)
    parser.add_argument("--prune", action="store_true", help="delete stored tasks this run does not have")
    ns = parser.parse_args(argv)
    result = generate(ns.out, workers=ns.workers, ratios=tuple(ns.ratios), level=ns.level, plans=tuple(ns.plans),
                      progress=lambda m: print(m, file=sys.stderr), prune=ns.prune)
    print(f"{'E/sY':>5} {'plan':>7} {'P/P_Y':>8} {'where':>13} {'force %':>8} {'e_FE':>7} {'e_law':>7} {'e err %':>8}"
          f" {'e_coll err %':>12}")
    for r in result["rows"]:
        print(f"{r['E_over_sigma_y']:5g} {r['plan']:>7} {r['P_max_over_P_Y']:8.4g} {r['where']:>13} "
              f"{100 * r['force_error']:8.2f} {r['e_fe']:7.4f} {r['e_law']:7.4f} {100 * r['e_error']:+8.2f} "
              f"{100 * r.get('e_collision_error', float('nan')):+12.2f}")
    return 1 if result["failures"] else 0


if __name__ == "__main__":
    sys.exit(main())

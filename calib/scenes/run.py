"""Running a scene: every stage of every material, written to the scene's output folder."""
from __future__ import annotations

import time
import warnings
from pathlib import Path

import numpy as np

from calib import output
from calib.fe import ContactSolver
from calib.fe.elastic import ElasticMaterial
from calib.fe.loadpath import run_load_paths
from calib.fe.von_mises import von_mises_material
from calib.fit import calibration, impact_window
from calib.fit.master_table import vz_constants
from calib.report import calibration as calibration_report
from calib.scenes.plan import (calibration_spec, hertz_mesh_spec, impact_setup, pair_impact_setup, plastic_needed,
                               spec_options)
from calib.scenes.schema import Scene, rate_words, stage_pair
from calib.studies.hertz import plot_hertz, run_hertz
from meshes.hemisphere import hemisphere_mesh
from nfdmodel import collide
from nfdmodel.parameter_file import stated_rate_law
from nfdmodel.rate_relaxing import rate_form_law
from nfdmodel.strain_rate import rate_law_of


# ----------------------------------------------------------------------------- run
def _run_hertz(scene, material, out, progress) -> dict:
    counter = None if scene.hertz.counter is None else scene.hertz.counter.counter_body(material)
    low, top = scene.hertz.loads(stage_pair(material, scene.hertz.counter))
    spec = hertz_mesh_spec(scene, material)
    progress(f"hertz validation: {material.name}, P = {low:.4g} .. {top:.4g} N"
             + ("" if counter is None else f" on the {counter.label()}"))
    run = run_hertz(spec, material=material.material(), radius=material.R,
                    loads=np.geomspace(low, top, scene.hertz.steps), counter=counter)
    summary = {"material": material.inputs(), "top_load": run.top_load, "mesh": run.mesh,
               "finite_size_coefficient": run.finite_size_coefficient, "wall_time_s": run.wall_time_s,
               **({} if counter is None else {"counter_body": counter.describe()})}
    stamp = output.stamp(run.wall_time_s, mesh=run.mesh)
    output.write_json(out / "hertz.json", {**summary, "stamp": stamp})
    if scene.outputs.histories:
        output.write_csv(out / "hertz_steps.csv", run.rows, comment=output.stamp_comment(stamp))
    if scene.outputs.plots:
        plot_hertz(out, run, material.material(), material.R)
    return summary


def _run_load_paths(scene, material, out, progress) -> dict:
    """Load paths without calibration: elastic material when every P_max < P_Y."""
    t0 = time.perf_counter()
    spec = calibration_spec(scene, material)
    elastic = not plastic_needed(scene, material)
    if elastic:
        fe_material = ElasticMaterial(material.E, material.nu)
    else:                               # the sphere's hardening, when the scene gives one
        fe_material = von_mises_material(material.E, material.nu, material.sigma_y, scene.flow_curve(material))
    hemisphere = hemisphere_mesh(spec.mesh)
    solver = ContactSolver(hemisphere, fe_material)
    progress(f"load paths: {material.name}, {'elastic' if elastic else 'elastoplastic'}, "
             f"P_max = {', '.join(f'{p:.4g}' for p in spec.plan.peaks)} N")
    result = run_load_paths(solver, spec.plan, progress=progress, unload=scene.load_paths.unload)
    rows = result.loading_rows + [r for p in result.paths for r in p.rows if r["branch"] == "unloading"]
    paths_out = [{"P_max": p.peak, "alpha_max": p.alpha_max, "alpha_residual": p.alpha_residual,
                  "e": p.restitution} for p in result.paths]
    mesh = {**spec.mesh.describe(), "dofs": int(solver.n_dofs), "elements": int(hemisphere.mesh.nelements)}
    wall = time.perf_counter() - t0
    summary = {"material": material.inputs(), "elastic": elastic, "P_Y": material.pair().P_Y,
               "peaks": list(spec.plan.peaks), "unload": scene.load_paths.unload, "paths": paths_out,
               "steps": len(rows), "mesh": mesh, "wall_time_s": wall}
    stamp = output.stamp(wall, mesh=mesh)
    output.write_json(out / "load_paths.json", {**summary, "stamp": stamp})
    if scene.outputs.histories:
        output.write_csv(out / "load_paths.csv", rows, comment=output.stamp_comment(stamp))
    if scene.outputs.plots:
        plt = output.pyplot()
        fig, ax = plt.subplots(figsize=(6, 4))
        ax.plot([r["alpha"] * 1e6 for r in rows], [r["P"] for r in rows], "o-", ms=3)
        ax.set_xlabel("approach alpha [um]"); ax.set_ylabel("P [N]"); ax.grid(alpha=0.3)
        ax.set_title(f"{material.name}: FE load paths")
        output.save_figure(fig, out / "force_approach.png")
    return summary


def _run_calibration(scene, material, out, progress) -> tuple[dict, object]:
    spec = calibration_spec(scene, material)
    progress(f"calibration: {material.name}, P_max = {', '.join(f'{p:.4g}' for p in spec.plan.peaks)} N")
    unload = scene.load_paths is None or scene.load_paths.unload
    v_max = scene.v_max(material)
    if v_max is None:
        result = calibration.calibrate(spec, progress=progress, ship=scene.calibration_ship, unload=unload)
    else:                               # round 1 is the spec above; more rounds if it falls short
        result = impact_window.calibrate_for_impacts(material.material(), material.R, v_max, progress=progress,
                                                     ship=scene.calibration_ship, unload=unload,
                                                     hardening=scene.flow_curve(material),
                                                     **spec_options(scene)).result
    rate_entry = (None if material.rate_law is None     # so `collide --params` runs the same law
                  else stated_rate_law(result.shipped_params, material.rate_record(), material.rate_form_used()))
    if unload and (scene.outputs.histories or scene.outputs.plots or scene.outputs.vtu):
        calibration_report.write(result, out, plots=scene.outputs.plots, vtu=scene.outputs.vtu, rate_law=rate_entry)
    else:  # the parameter file, the summary and (loading only) the loading history
        stamp = output.stamp(result.wall_time_s, mesh=result.mesh_info, timings=result.timings)
        calibration_report.write_calibration_parameters(out / "parameters.json", result, stamp, rate_entry)
        output.write_json(out / "calibration.json", {**calibration.summary(result), "stamp": stamp})
        if scene.outputs.histories:
            output.write_csv(out / "loading.csv", result.load_paths.loading_rows,
                             comment=output.stamp_comment(stamp))
    s = calibration.summary(result)
    laws = {"vz": result.params, "vz-table": result.table_params}
    counter = scene.calibration_counter
    return {**({} if counter is None else {"counter_body": counter.counter_body(material).describe()}),
            **{k: s[k] for k in ("Ca", "Kc", "Ca_hat", "Kc_hat", "P_Y", "P_Y_fe", "wall_time_s", "mesh", "window",
                                 "table")},
            "loading_only": not unload, "shipped_fit": s["shipped_fit"], "v_max": v_max,
            **({} if rate_entry is None else {"rate_law": rate_entry})}, laws


def rate_aware_law(material, law: str, params):
    """(ContactLaw, parameters) of the rate-aware law (nfdmodel.rate_relaxing.rate_form_law, the material's
    rate_form) on the base ``law`` with ``params``, None for a rate-independent sphere."""
    record = material.rate_record()
    if record is None:
        return None
    return rate_form_law(material.rate_form_used(), law, params, rate_law_of(record))


def _run_collision(scene, material, out, calibrated, progress) -> dict:
    """The scene's impacts with every law; vz and vz-table with this scene's calibration
    (``calibrated``: law -> parameters) or, without one, vz with the master table's constants."""
    pair = material.pair()
    source = "calibration"
    params = None if calibrated is None else calibrated["vz"]
    if params is None and "vz" in scene.collision.laws:     # the constants `nfdcal collide` takes for it
        params, source = vz_constants(material.material(), material.R)
    velocities = scene.collision.velocities(pair)
    progress(f"collision: {material.name}, {len(velocities)} velocities, laws {', '.join(scene.collision.laws)}")
    rows = []
    t0 = time.perf_counter()
    for law in scene.collision.laws:
        if law == "vz-table" and calibrated["vz-table"] is None:
            raise ValueError(f"collision.laws: 'vz-table': {material.name}'s FE paths determine no "
                             f"table (calibrate with ship = 'table' to see why)")
        law_params = calibrated["vz-table"] if law == "vz-table" else (params if params is not None else pair)
        # vz and vz-table of a rate-dependent sphere: the rate-aware law on them (schema: no other law takes one)
        rated = None if law == "hertz" else rate_aware_law(material, law, law_params)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            result = collide(*((law, law_params) if rated is None else rated), velocities, dt=None)
        # a rate-aware law's strain rate [1/s] at first contact and its factor (R; relaxing: s at the turning point)
        rates = {} if rated is None else {"strain_rate": rated[1].strain_rate(velocities),
                                          "rate_factor": rated[1].rate_factor(velocities)}
        rows += [{"law": law, "v_in_over_v_Y": r["v_in"] / pair.v_Y, **r, **{k: v[i] for k, v in rates.items()}}
                 for i, r in enumerate(result.records())]
    rate = material.rate_record()
    stamp = output.stamp(time.perf_counter() - t0, vz_parameters=source,
                         **({} if rate is None else {"rate_law": rate, "rate_form": material.rate_form_used()}))
    output.write_csv(out / "collision.csv", rows, columns=dict.fromkeys(k for r in rows for k in r),
                     comment=output.stamp_comment(stamp))
    if scene.outputs.plots:
        plot_restitution(rows, pair.v_Y, f"{material.name}: sphere on rigid flat", out / "collision.png")
    restitution = {law: {"v_in": [r["v_in"] for r in rows if r["law"] == law],
                         "e": [r["e_velocity"] for r in rows if r["law"] == law]}
                   for law in scene.collision.laws}
    return {"rows": len(rows), "vz_parameters": source, "restitution": restitution,
            **({} if rate is None else {"rate_law": rate, "rate_form": material.rate_form_used()})}


def _run_pair_impact(scene, material, out, progress) -> dict:
    """The two-body impacts on the [impact.counter] body into OUT/impact/ (calib.studies.impact_pair)."""
    from calib.studies import impact, impact_pair

    setup = pair_impact_setup(scene, material)
    velocities = tuple(sorted(set(scene.impact.velocities(setup.pair))))
    progress(f"impact: {material.name}, {len(velocities)} velocities (two-body dynamic FE on the {setup.counter.label()})")
    records = impact_pair.study(setup, velocities, out / "impact", progress=progress,
                                variants=impact.VARIANTS if scene.impact.error_estimate else impact_pair.FINE)
    return {"out": str(out / "impact"), "counter_body": setup.counter.describe(),
            "impacts": [{"v_in": r["v_in"], "e": r["e"], "P_max": r["P_max"], "contact_time": r["contact_time"],
                         "e_rel_error_estimate": r.get("e_rel_error_estimate"), "quasi_static_e": None}
                        for r in records]}


def _run_impact(scene, material, out, progress) -> dict:
    """The scene's dynamic FE impacts (calib.studies.impact) into OUT/impact/: per v_in the FE's e,
    P_max, contact time and, where run, the quasi-static FE's e at the same P_max; on an
    [impact.counter] body, the two-body impacts (``_run_pair_impact``)."""
    from calib.studies import impact

    if scene.impact.counter is not None:
        return _run_pair_impact(scene, material, out, progress)
    stage = scene.impact
    setup = impact_setup(scene, material)
    velocities = tuple(sorted(set(stage.velocities(material.pair()))))
    progress(f"impact: {material.name}, {len(velocities)} velocities (dynamic FE of the whole sphere)")
    records = impact.study(setup, velocities, out / "impact", variants=impact.VARIANTS if stage.error_estimate
                           else ("fine",), plots=scene.outputs.plots, quasi_static=stage.quasi_static, progress=progress)
    return {"out": str(out / "impact"),
            "impacts": [{"v_in": r["v_in"], "e": r["e"], "P_max": r["P_max"], "contact_time": r["contact_time"],
                         "e_rel_error_estimate": r["e_rel_error_estimate"],
                         "quasi_static_e": r.get("quasi_static", {}).get("e")} for r in records]}


def plot_restitution(rows: list[dict], v_Y: float, title: str, path: Path) -> None:
    """e(v_in / v_Y) of every law in ``rows`` (collision records with a "law" key) into ``path``."""
    plt = output.pyplot()
    fig, ax = plt.subplots(figsize=(6, 4))
    for law in dict.fromkeys(r["law"] for r in rows):
        sel = [r for r in rows if r["law"] == law]
        ax.plot([r["v_in"] / v_Y for r in sel], [r["e_velocity"] for r in sel], "o-", ms=3, label=law)
    inside = [r["v_in"] / v_Y for r in rows if r.get("in_calibrated_range")]
    if inside:                 # where the vz constants are not an extrapolation
        ax.axvspan(min(r["v_in"] for r in rows) / v_Y, max(inside), color="C2", alpha=0.12, lw=0,
                   label="vz: inside its calibrated window")
    ax.set_xscale("log")
    ax.set_xlabel(f"v_in / v_Y  (v_Y = {v_Y:.3g} m/s)")
    ax.set_ylabel("coefficient of restitution e = -v_out / v_in")
    ax.set_title(title, fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    output.save_figure(fig, path)


def run_scene(scene: Scene, out: str | Path | None = None, progress=None) -> dict:
    """Run every stage of every material of ``scene``; returns the summary (also written to
    OUT/scene.json). One folder per material when the scene has several."""
    say = progress or (lambda message: None)
    base = scene.out_dir(out)
    t0 = time.perf_counter()
    results = []
    n = len(scene.materials)
    for k, material in enumerate(scene.materials, 1):
        folder = base / material.name if n > 1 else base
        if n > 1 and progress is not None:  # name the material in each message
            say = lambda message, head=f"material {k}/{n} ({material.name}): ": progress(head + message)  # noqa: E731
        entry = {"material": material.inputs()}
        calibrated = None
        if scene.hertz is not None:
            entry["hertz"] = _run_hertz(scene, material, folder, say)
        if scene.calibration_ship is not None:
            entry["calibration"], calibrated = _run_calibration(scene, material, folder, say)
        elif scene.load_paths is not None:
            entry["load_paths"] = _run_load_paths(scene, material, folder, say)
        if scene.collision is not None:
            entry["collision"] = _run_collision(scene, material, folder, calibrated, say)
        if scene.impact is not None:
            entry["impact"] = _run_impact(scene, material, folder, say)
        results.append(entry)
    wall = time.perf_counter() - t0
    summary = {"scene": scene.name, "source": scene.source, "stages": scene.stages(), "materials": results,
               "out": str(base), "wall_time_s": wall}
    output.write_json(base / "scene.json", {**summary, "stamp": output.stamp(wall)})
    return summary


def summary_lines(summary: dict) -> list[str]:
    """The readable account of a scene run: a line per material and stage, then where it went."""
    lines = [f"scene {summary['scene']}: {', '.join(summary['stages'])} done in {summary['wall_time_s']:.1f} s"]
    for entry in summary["materials"]:
        m = entry["material"]
        lines.append(f"{m['name']} (E {m['E']:.4g} Pa, nu {m['nu']:g}, sigma_Y {m['sigma_y']:.4g} Pa, R {m['R']:g} m):")
        for stage in ("hertz", "calibration", "impact"):
            if "counter_body" in entry.get(stage, {}):
                c = entry[stage]["counter_body"]
                lines.append(f"  {stage} on a counter-{c['shape']}: E {c['E']:.4g} Pa, nu {c['nu']:g}, "
                             + ("elastic" if c["sigma_y"] is None else f"sigma_Y {c['sigma_y']:.4g} Pa")
                             + ("" if c["R"] is None else f", R {c['R']:g} m"))
        if "hertz" in entry:
            top = entry["hertz"]["top_load"]
            lines.append(f"  hertz: at P = {top['P']:.4g} N contact radius {100 * top['contact_radius_rel_error']:+.3f} %,"
                         f" peak pressure {100 * top['peak_pressure_rel_error']:+.3f} % against Hertz")
        if "calibration" in entry:
            c = entry["calibration"]
            lines.append(f"  calibration: Ca = {c['Ca']:.4g} m/N (Ca_hat {c['Ca_hat']:.4g}), Kc = {c['Kc']:.4g} 1/N "
                         f"(Kc_hat {c['Kc_hat']:.4g}), P_Y = {c['P_Y']:.4g} N, {c['wall_time_s']:.1f} s")
        if "load_paths" in entry:
            lp = entry["load_paths"]
            paths = ", ".join(f"P_max {p['P_max']:.4g} N" + (f" e {p['e']:.4f}" if p.get("e") is not None else "")
                              for p in lp["paths"])
            lines.append(f"  load paths ({'elastic' if lp['elastic'] else 'elastoplastic'}): {paths}")
        if "collision" in entry:
            c = entry["collision"]
            for law, r in c["restitution"].items():
                rated = "rate_law" in c and law != "hertz"
                lines.append(f"  collision {law}" + (f" (rate-aware, {c['rate_form']}: {rate_words(c['rate_law'])})"
                                                     if rated else "")
                             + f": e = {min(r['e']):.4f} .. {max(r['e']):.4f} over v_in = "
                             f"{min(r['v_in']):.4g} .. {max(r['v_in']):.4g} m/s")
        for r in entry.get("impact", {}).get("impacts", ()):
            lines.append(f"  impact (dynamic FE) at v_in = {r['v_in']:.4g} m/s: e = {r['e']:.4f}, P_max = {r['P_max']:.4g} N, "
                         f"contact time {r['contact_time'] * 1e3:.4g} ms"
                         + (f"; quasi-static FE e = {r['quasi_static_e']:.4f}" if r["quasi_static_e"] is not None else ""))
    lines.append(f"results in {summary['out']}")
    return lines

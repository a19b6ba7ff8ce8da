"""The plan of a scene: FE specs per material and stage, mesh size and run-time estimates (--dry-run)."""
from __future__ import annotations

import dataclasses
import os
from dataclasses import asdict, dataclass

import meshio
import numpy as np

from calib.fit import impact_window, recipe
from calib.scenes.schema import (SECONDS_PER_STEP_AT_12K_DOFS, LoadPathStage, Scene, SceneError, SceneMaterial,
                                 hardening_label, rate_words, stage_pair)
from meshes.hemisphere import estimate_dofs, mesh_path
from meshes.sphere import SphereMeshSpec
from meshes.sphere import mesh_path as sphere_mesh_path
from nfdmodel.reference_case import is_reference_sphere


# ----------------------------------------------------------------------------- FE specs
def spec_options(scene: Scene) -> dict:
    """The mesh and step options of the scene's calibrations (calib.fit.recipe.calibration_spec)."""
    stage = scene.load_paths or LoadPathStage()
    return {"level": scene.mesh.level, "contact_size": scene.mesh.contact_size,
            "contact_size_over_a_max": scene.mesh.contact_size_over_a_max,
            "loading_steps": stage.loading_steps, "unloading_steps": stage.unloading_steps}


def calibration_spec(scene: Scene, material: SceneMaterial):
    """The CalibrationSpec of one material of ``scene`` (calib.fit.recipe: load paths and mesh);
    with a v_max, the first round of calib.fit.impact_window (refused here when the FE cannot
    reach the impact)."""
    stage = scene.load_paths or LoadPathStage()
    counter = scene.calibration_counter
    try:
        v_max = scene.v_max(material)
        if v_max is None:
            peaks = stage.peaks(stage_pair(material, counter))
        else:
            curve = scene.flow_curve(material)     # a hardening sphere's window: estimated with its flow curve
            needed, _, _ = impact_window.check_reach(material.material(), material.R, v_max, hardening=curve)
            spec = impact_window.impact_spec(material.material(), material.R, needed, **spec_options(scene))
            return spec if curve is None else dataclasses.replace(spec, hardening=curve)
        spec = recipe.calibration_spec(material.material(), material.R, peaks=peaks, **spec_options(scene),
                                       counter=None if counter is None else counter.counter_body(material))
        curve = scene.flow_curve(material)      # absent for perfect plasticity: the spec (and its key) unchanged
        return spec if curve is None else dataclasses.replace(spec, hardening=curve)
    except ValueError as exc:
        raise SceneError(f"scene {scene.source}: material {material.name}: {exc}") from None


def hertz_mesh_spec(scene: Scene, material: SceneMaterial):
    """The mesh of the scene's Hertz stage for ``material`` (calib.fit.recipe.hertz_mesh; on a
    counter-body, at the pair's Hertz radius)."""
    pair = stage_pair(material, scene.hertz.counter)
    _, top = scene.hertz.loads(pair)
    reference = scene.hertz.counter is None and is_reference_sphere(material.E, material.nu, material.R)
    return recipe.hertz_mesh(pair, top, reference=reference,
                             level=scene.mesh.level, contact_size=scene.mesh.contact_size,
                             contact_size_over_a_max=scene.mesh.contact_size_over_a_max)


def mesh_dofs(spec) -> tuple[int, bool]:
    """(dofs, exact) of a mesh (a hemisphere's or a counter-body's block): counted from the cached
    file if there is one, else estimated."""
    from meshes.counter_body import BlockMeshSpec, block_path

    path = block_path(spec) if isinstance(spec, BlockMeshSpec) else mesh_path(spec)
    if path.is_file():
        try:

            raw = meshio.read(path, file_format="gmsh")
            return int(2 * (raw.cells_dict["triangle6"].max() + 1)), True
        except Exception:  # a corrupt cache entry is rebuilt at run time: estimate
            pass
    return estimate_dofs(spec), False


def fe_dofs(spec) -> tuple[int, bool]:
    """(dofs, exact) of the FE of a CalibrationSpec: the sphere's mesh, plus the counter-body's
    (calib.fit.counter) when there is one."""
    dofs, exact = mesh_dofs(spec.mesh)
    if spec.counter is None:
        return dofs, exact
    counter_dofs, counter_exact = mesh_dofs(spec.counter.mesh_spec(spec.mesh))
    return dofs + counter_dofs, exact and counter_exact


def step_seconds(dofs: int) -> float:
    """Estimated wall time of one FE load step [s] (linear in dofs, from the reference run)."""
    return SECONDS_PER_STEP_AT_12K_DOFS * max(dofs, 500) / 12112.0


# A finite-strain FE step's cost over step_seconds (the small-strain reference's), measured on the --v-max plans'
# meshes (CPU time; calib/fit/README.md, The plan: contact radius and time; tests/benchmarks/plan_radius.py): a
# loading step to P/P_Y = 10^FINITE_COST_LOG_LOADS costs FINITE_COST_LOADING reference steps, an unloading step
# FINITE_COST_UNLOADING (each on 12,112 dofs), and per step the cost grows as dofs^FINITE_COST_DOFS_EXPONENT beyond
# step_seconds' linear growth (the factorisation's fill-in: per Newton iteration 20,038 dofs cost 13-18x 3,174).
# Newton takes 3-5 iterations per loading step to 10 P_Y, 7-15 to 100 P_Y, 40-150 beyond (the plastic zone
# spreading; near the top the increment is halved 2-7 times), an unloading step 3-6; a finite-strain iteration
# costs 1.8-2x a small-strain one. Against the FE: the brass calibration at 3 m/s 1153 s planned, 1472 s taken;
# loading branches on the command's graded meshes (12,844-20,038 dofs) -12..+11 %; on coarser meshes the plan
# errs high (fewer iterations at high load).
FINITE_COST_LOG_LOADS = (0.0, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5)
FINITE_COST_LOADING = (0.5, 0.9, 2.0, 8.0, 30.0, 40.0, 45.0)
FINITE_COST_UNLOADING = (0.6, 0.6, 0.6, 0.6, 0.6, 0.6, 0.6)
FINITE_COST_DOFS_EXPONENT = 0.47


def finite_strain_step_cost(load_over_P_Y: float, branch: str = "loading", dofs: int = 12112) -> float:
    """A finite-strain FE step's cost [reference steps, step_seconds(dofs)] at P/P_Y on the ``branch`` ("loading",
    or "unloading": a step of the unloading from that peak) on a mesh of ``dofs`` (the tables above)."""
    table = FINITE_COST_LOADING if branch == "loading" else FINITE_COST_UNLOADING
    log_load = float(np.log10(max(load_over_P_Y, 1.0)))
    size = (max(dofs, 500) / 12112.0) ** FINITE_COST_DOFS_EXPONENT
    return float(np.interp(log_load, FINITE_COST_LOG_LOADS, table)) * size


def fe_seconds(spec, dofs: int, *, unload: bool, calibrate: bool) -> float:
    """Estimated wall time [s] of ``spec``'s load paths on a mesh of ``dofs``: step_seconds per step (and the
    calibration's 3 first-yield solves); with finite strain each step x finite_strain_step_cost at its load."""
    plan, P_Y = spec.plan, spec.pair.P_Y
    n_unload = plan.unloading_steps * len(plan.peaks) if unload else 0
    if spec.kinematics != "finite-strain":
        return (len(plan.loading_targets()) + n_unload + (3 if calibrate else 0)) * step_seconds(dofs)
    steps = sum(finite_strain_step_cost(load / P_Y, "loading", dofs) for load in plan.loading_targets())
    if unload:
        steps += plan.unloading_steps * sum(finite_strain_step_cost(peak / P_Y, "unloading", dofs)
                                            for peak in plan.peaks)
    return (steps + (3 if calibrate else 0)) * step_seconds(dofs)


# ----------------------------------------------------------------------------- plan
@dataclass
class PlannedStage:
    stage: str
    material: str
    mesh_key: str
    mesh_cached: bool
    dofs: int
    dofs_exact: bool
    fe_steps: int
    elastic: bool
    estimate_s: float
    detail: str = ""


def plastic_needed(scene: Scene, material: SceneMaterial) -> bool:
    """Does this material's stage need the return mapping? Not when every load stays below P_Y
    (theory; the FE's first yield is within 1 % of it at the default mesh) and nothing is calibrated."""
    if scene.calibration_ship is not None:
        return True
    if scene.load_paths is None:
        return False
    pair = material.pair()
    return max(scene.load_paths.peaks(pair)) >= pair.P_Y


def hertz_stage(spec, material_name: str, loads: tuple[float, float], steps: int) -> PlannedStage:
    """The Hertz validation of one material on mesh ``spec``: elastic, ``steps`` loads."""
    dofs, exact = mesh_dofs(spec)
    return PlannedStage("hertz", material_name, spec.cache_key(), mesh_path(spec).is_file(), dofs, exact,
                        steps, True, steps * step_seconds(dofs) / 3,  # elastic: no Newton re-assembly
                        f"elastic, P = {loads[0]:.4g} .. {loads[1]:.4g} N")


def calibration_stage(spec, material_name: str, *, calibrate: bool, unload: bool, elastic: bool,
                      meshes: int = 2) -> PlannedStage:
    """The load paths (and, with ``calibrate``, the fit) of one material's CalibrationSpec on
    ``meshes`` meshes (2: the calibration's extrapolated pair; 1: one mesh, a ladder's rung); a
    plan that cannot be fitted is refused here, so --dry-run refuses it too."""
    if calibrate:
        recipe.check_fittable(spec)
    dofs, exact = fe_dofs(spec)
    n_load = len(spec.plan.loading_targets())
    n_unload = spec.plan.unloading_steps * len(spec.plan.peaks) if unload else 0
    steps = n_load + n_unload + (3 if calibrate else 0)
    seconds = fe_seconds(spec, dofs, unload=unload, calibrate=calibrate) / (3 if elastic else 1)
    second = ""
    if calibrate and meshes == 2:       # the second mesh of the extrapolation (calib.fit.extrapolation)
        coarse = recipe.coarse_spec(spec)
        coarse_dofs, _ = fe_dofs(coarse)
        coarse_seconds = fe_seconds(coarse, coarse_dofs, unload=unload, calibrate=calibrate)
        parallel = (os.cpu_count() or 1) >= 2
        seconds = max(seconds, coarse_seconds) if parallel else seconds + coarse_seconds
        second = f"; second mesh h = {coarse.mesh.contact_size:.3g} m (~{coarse_dofs} dofs)"
    if spec.kinematics == "finite-strain":
        factor = fe_seconds(spec, dofs, unload=unload, calibrate=calibrate) / (steps * step_seconds(dofs))
        second += (f"; finite strain: {factor:.2g}x the small-strain reference's time per step (measured by load and "
                   f"dofs, calib.scenes.plan.finite_strain_step_cost)")
    return PlannedStage("calibration" if calibrate else "load_paths", material_name, spec.mesh.cache_key(),
                        mesh_path(spec.mesh).is_file(), dofs, exact, steps, elastic, seconds,
                        f"{'elastic' if elastic else 'elastoplastic'}, P_max = "
                        f"{', '.join(f'{p:.4g}' for p in spec.plan.peaks)} N, "
                        f"{'loading and unloading' if unload else 'loading only'}" + second)


def plan(scene: Scene) -> list[PlannedStage]:
    """What ``run`` will do, per material and stage, with meshes and an estimated wall time."""
    out = []
    for material in scene.materials:
        if scene.hertz is not None:
            out.append(hertz_stage(hertz_mesh_spec(scene, material), material.name,
                                   scene.hertz.loads(stage_pair(material, scene.hertz.counter)), scene.hertz.steps))
        if scene.load_paths is not None:
            try:
                stage = calibration_stage(calibration_spec(scene, material), material.name,
                                          calibrate=scene.calibration_ship is not None,
                                          unload=scene.load_paths.unload,
                                          elastic=not plastic_needed(scene, material))
                out.append(with_hardening(stage, scene, material))
            except ValueError as exc:
                if isinstance(exc, SceneError):
                    raise
                raise SceneError(f"scene {scene.source}: material {material.name}: {exc}") from None
        if scene.collision is not None:
            rated = (f"; vz, vz-table rate-aware ({material.rate_form_used()}): {rate_words(material.rate_record())}"
                     if material.rate_law is not None else "")
            out.append(PlannedStage("collision", material.name, "-", True, 0, True, 0, False, 1.0,
                                    f"laws {', '.join(scene.collision.laws)}{rated}"))
        if scene.impact is not None:
            stage = with_hardening(impact_stage(scene, material), scene, material)
            if material.rate_law is not None:
                stage = dataclasses.replace(stage, detail=f"{stage.detail}; {rate_words(material.rate_record())}")
            out.append(stage)
    return out


def with_hardening(stage: PlannedStage, scene: Scene, material: SceneMaterial) -> PlannedStage:
    """``stage`` whose detail names the sphere's hardening, when it has one (and the FE is plastic)."""
    curve = scene.flow_curve(material)
    if curve is None or stage.elastic:
        return stage
    return dataclasses.replace(stage, detail=f"{stage.detail}; {hardening_label(curve)}")


def impact_setup(scene, material):
    """The ImpactSetup (calib.studies.impact) of ``material`` with the scene's mesh choice and steps."""
    from calib.studies.impact import ImpactSetup

    mesh = scene.mesh
    return ImpactSetup(material=material.material(), radius=material.R, contact_size=mesh.contact_size,
                       level=mesh.level if mesh.level not in (None, "default") else None,
                       steps_per_contact=scene.impact.steps_per_contact, hardening=scene.flow_curve(material),
                       rate_law=material.rate())


def pair_impact_setup(scene, material):
    """The PairImpactSetup (calib.studies.impact_pair) of ``material`` on the [impact.counter] body."""
    from calib.studies.impact_pair import PairImpactSetup

    return PairImpactSetup(impact_setup(scene, material), scene.impact.counter.counter_body(material))


def impact_stage(scene: Scene, material: SceneMaterial) -> PlannedStage:
    """The planned dynamic FE impacts of ``material`` (calib.studies.impact: the fine runs, and the
    coarse-mesh and coarse-dt ones with the error estimate); refused here when beyond the FE's reach."""
    from calib.studies import impact

    if scene.impact.counter is not None:
        return pair_impact_stage(scene, material)
    setup = impact_setup(scene, material)
    velocities = tuple(sorted(set(scene.impact.velocities(material.pair()))))
    try:
        impact.check_reach(setup, velocities)
    except ValueError as exc:
        raise SceneError(f"scene {scene.source}: impact.v_in: material {material.name}: {exc}") from None
    tasks = impact.tasks_for(setup, velocities, impact.VARIANTS if scene.impact.error_estimate else ("fine",))
    runs = impact.planned_runs(tasks, scene.out_dir() / (material.name if len(scene.materials) > 1 else "")
                               / "impact" / "cases")
    largest = max(runs, key=lambda r: r["dofs_estimate"])
    mesh = SphereMeshSpec(**tasks[-1]["mesh"])
    return PlannedStage("impact", material.name, mesh.cache_key(), sphere_mesh_path(mesh).is_file(),
                        largest["dofs_estimate"], False, sum(r["steps_estimate"] for r in runs), False,
                        sum(r["estimate_s"] for r in runs if not r["finished"]),
                        f"{len(tasks)} FE impacts at v_in = {', '.join(f'{v:.4g}' for v in velocities)} m/s"
                        + ("; quasi-static FE paths at their P_max" if scene.impact.quasi_static else ""))


def pair_impact_stage(scene: Scene, material: SceneMaterial) -> PlannedStage:
    """The planned two-body impacts of ``material`` on the [impact.counter] body (calib.studies.impact_pair)."""
    from meshes.counter_body import BlockMeshSpec

    from calib.studies import impact, impact_pair

    setup = pair_impact_setup(scene, material)
    velocities = tuple(sorted(set(scene.impact.velocities(setup.pair))))
    try:
        impact.check_reach(setup.contact_setup, velocities)
    except ValueError as exc:
        raise SceneError(f"scene {scene.source}: impact.v_in: material {material.name}: {exc}") from None
    tasks = impact_pair.tasks_for(setup, velocities, impact.VARIANTS if scene.impact.error_estimate else impact_pair.FINE)
    sphere = SphereMeshSpec(**tasks[-1]["sphere_mesh"])
    counter = (BlockMeshSpec if tasks[-1]["counter_block"] else SphereMeshSpec)(**tasks[-1]["counter_mesh"])
    dofs = sphere.estimate_dofs() + (counter.estimate_dofs() if isinstance(counter, SphereMeshSpec)
                                     else estimate_dofs(counter))
    steps = len(tasks) * (int(1.1 * setup.sphere.steps_per_contact) + 10)
    return PlannedStage("impact", material.name, sphere.cache_key(), sphere_mesh_path(sphere).is_file(), dofs, False,
                        steps, False, steps * impact.SECONDS_PER_STEP_AT_13K_DOFS * dofs / 13000,
                        f"{len(tasks)} two-body FE impacts at v_in = {', '.join(f'{v:.4g}' for v in velocities)} m/s "
                        f"on the {setup.counter.label()}")


def format_stages(stages: list[PlannedStage]) -> list[str]:
    """A table of the stages and the estimated total."""
    lines = [f"{'stage':<12} {'material':<20} {'mesh':<17} {'cached':<7} {'dofs':>8} {'steps':>6} {'est. s':>8}  detail"]
    for s in stages:
        dofs = f"{s.dofs}" if s.dofs_exact else f"~{s.dofs}"
        lines.append(f"{s.stage:<12} {s.material:<20} {s.mesh_key:<17} {('yes' if s.mesh_cached else 'build'):<7} "
                     f"{dofs:>8} {s.fe_steps:>6} {s.estimate_s:>8.0f}  {s.detail}")
    total = sum(s.estimate_s for s in stages)
    lines.append(f"estimated total: {total:.0f} s on one process (from the reference: "
                 f"{SECONDS_PER_STEP_AT_12K_DOFS} s per FE step at 12k dofs, linear in dofs)")
    return lines


def stages_summary(stages: list[PlannedStage], folder) -> dict:
    """Planned stages as a JSON-able object: the folder that will be written, the stages, the estimate."""
    return {"out": str(folder), "stages": [asdict(s) for s in stages],
            "estimated_total_s": sum(s.estimate_s for s in stages)}


def plan_summary(scene: Scene, stages: list[PlannedStage], folder, finished: int | None = None) -> dict:
    """The plan of a scene as a JSON-able object (``stages_summary`` and the scene's choices)."""
    summary = {"scene": scene.name, "source": scene.source, "materials": len(scene.materials),
               "mesh": scene.mesh.label(),
               "outputs": {"plots": scene.outputs.plots, "vtu": scene.outputs.vtu,
                           "histories": scene.outputs.histories},
               **stages_summary(stages, folder)}
    if finished is not None:
        summary["finished_materials"] = finished
    if scene.hardening:                 # absent for perfectly plastic spheres: their plans unchanged
        summary["hardening"] = {name: curve.record() for name, curve in scene.hardening}
    rated = {m.name: {**m.rate_record(), "form": m.rate_form_used()} for m in scene.materials if m.rate_law is not None}
    if rated:                           # absent for rate-independent spheres: their plans unchanged
        summary["rate_laws"] = rated
    return summary


def format_plan(scene: Scene, stages: list[PlannedStage], folder, finished: int | None = None) -> list[str]:
    """The plan as readable lines: where the results go, a line per stage, the estimated time;
    ``finished``: how many materials the folder already holds (a table reuses them)."""
    lines = [f"scene {scene.name} ({scene.source}): {len(scene.materials)} material(s), mesh {scene.mesh.label()}",
             f"outputs: {folder} (plots {'on' if scene.outputs.plots else 'off'}, vtu "
             f"{'on' if scene.outputs.vtu else 'off'}, histories {'on' if scene.outputs.histories else 'off'})"]
    if finished is not None:
        lines.append(f"finished: {finished} of {len(scene.materials)} material(s) already in {folder}/materials "
                     f"(reused, not recomputed)")
    return lines + format_stages(stages)

"""The plan of a scene: FE specs per material and stage, mesh size and run-time estimates (--dry-run)."""
from __future__ import annotations

from dataclasses import dataclass

import meshio

from calib.fit import recipe
from calib.scenes.schema import SECONDS_PER_STEP_AT_12K_DOFS, LoadPathStage, Scene, SceneError, SceneMaterial
from meshes.hemisphere import estimate_dofs, mesh_path


# ----------------------------------------------------------------------------- FE specs
def calibration_spec(scene: Scene, material: SceneMaterial):
    """The CalibrationSpec of one material of ``scene`` (calib.fit.recipe: load paths and mesh)."""
    stage = scene.load_paths or LoadPathStage()
    try:
        return recipe.calibration_spec(material.material(), material.R, peaks=stage.peaks(material.pair()),
                                       level=scene.mesh.level, contact_size=scene.mesh.contact_size,
                                       contact_size_over_a_max=scene.mesh.contact_size_over_a_max,
                                       loading_steps=stage.loading_steps,
                                       unloading_steps=stage.unloading_steps)
    except ValueError as exc:
        raise SceneError(f"scene {scene.source}: material {material.name}: {exc}") from None


def hertz_mesh_spec(scene: Scene, material: SceneMaterial):
    """The mesh of the scene's Hertz stage for ``material`` (calib.fit.recipe.hertz_mesh)."""
    pair = material.pair()
    _, top = scene.hertz.loads(pair)
    return recipe.hertz_mesh(pair, top, reference=recipe.is_reference_sphere(material.E, material.nu, material.R),
                             level=scene.mesh.level, contact_size=scene.mesh.contact_size,
                             contact_size_over_a_max=scene.mesh.contact_size_over_a_max)


def mesh_dofs(spec) -> tuple[int, bool]:
    """(dofs, exact) of a mesh: counted from the cached file if there is one, else estimated."""
    path = mesh_path(spec)
    if path.is_file():
        try:

            raw = meshio.read(path, file_format="gmsh")
            return int(2 * (raw.cells_dict["triangle6"].max() + 1)), True
        except Exception:  # a corrupt cache entry is rebuilt at run time: estimate
            pass
    return estimate_dofs(spec), False


def step_seconds(dofs: int) -> float:
    """Estimated wall time of one FE load step [s] (linear in dofs, from the reference run)."""
    return SECONDS_PER_STEP_AT_12K_DOFS * max(dofs, 500) / 12112.0


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


def plan(scene: Scene) -> list[PlannedStage]:
    """What ``run`` will do, per material and stage, with meshes and an estimated wall time."""
    out = []
    for material in scene.materials:
        if scene.hertz is not None:
            spec = hertz_mesh_spec(scene, material)
            dofs, exact = mesh_dofs(spec)
            steps = scene.hertz.steps
            out.append(PlannedStage("hertz", material.name, spec.cache_key(), mesh_path(spec).is_file(), dofs, exact,
                                    steps, True, steps * step_seconds(dofs) / 3,  # elastic: no Newton re-assembly
                                    f"elastic, P = {scene.hertz.loads(material.pair())[0]:.4g} .. "
                                    f"{scene.hertz.loads(material.pair())[1]:.4g} N"))
        if scene.load_paths is not None:
            spec = calibration_spec(scene, material)
            if scene.calibration_ship is not None:
                try:
                    recipe.check_fittable(spec)    # a plan that cannot be fitted: refused at --dry-run
                except ValueError as exc:
                    raise SceneError(f"scene {scene.source}: material {material.name}: {exc}") from None
            dofs, exact = mesh_dofs(spec.mesh)
            elastic = not plastic_needed(scene, material)
            n_load = len(spec.plan.loading_targets())
            n_unload = (spec.plan.unloading_steps + 0) * len(spec.plan.peaks) if scene.load_paths.unload else 0
            steps = n_load + n_unload + (3 if scene.calibration_ship else 0)
            name = "calibration" if scene.calibration_ship else "load_paths"
            out.append(PlannedStage(name, material.name, spec.mesh.cache_key(), mesh_path(spec.mesh).is_file(),
                                    dofs, exact, steps, elastic,
                                    steps * step_seconds(dofs) / (3 if elastic else 1),
                                    f"{'elastic' if elastic else 'elastoplastic'}, P_max = "
                                    f"{', '.join(f'{p:.4g}' for p in spec.plan.peaks)} N, "
                                    f"{'loading and unloading' if scene.load_paths.unload else 'loading only'}"))
        if scene.collision is not None:
            out.append(PlannedStage("collision", material.name, "-", True, 0, True, 0, False, 1.0,
                                    f"laws {', '.join(scene.collision.laws)}"))
    return out


def format_plan(scene: Scene, stages: list[PlannedStage]) -> str:
    lines = [f"scene {scene.name} ({scene.source}): {len(scene.materials)} material(s), mesh {scene.mesh.label()}",
             f"outputs: {scene.out_dir()} (plots {'on' if scene.outputs.plots else 'off'}, vtu "
             f"{'on' if scene.outputs.vtu else 'off'}, histories {'on' if scene.outputs.histories else 'off'})",
             f"{'stage':<12} {'material':<20} {'mesh':<17} {'cached':<7} {'dofs':>8} {'steps':>6} {'est. s':>8}  detail"]
    for s in stages:
        dofs = f"{s.dofs}" if s.dofs_exact else f"~{s.dofs}"
        lines.append(f"{s.stage:<12} {s.material:<20} {s.mesh_key:<17} {('yes' if s.mesh_cached else 'build'):<7} "
                     f"{dofs:>8} {s.fe_steps:>6} {s.estimate_s:>8.0f}  {s.detail}")
    total = sum(s.estimate_s for s in stages)
    lines.append(f"estimated total: {total:.0f} s on one process (from the reference: "
                 f"{SECONDS_PER_STEP_AT_12K_DOFS} s per FE step at 12k dofs, linear in dofs)")
    return "\n".join(lines)

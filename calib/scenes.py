"""Scenes: a TOML file that declares materials, a mesh level, what to run and which outputs.

    [scene]        name = "steel", description = "..."
    [mesh]         level = "coarse" | "default" | "fine"   or   contact_size = 4e-5  [m]
                   or contact_size_over_a_max = 0.05 (element size / largest contact radius)
    [[material]]   name, E [Pa], nu [-], sigma_y [Pa], rho [kg/m^3], R [m]   (one table per material)
    [grid]         nu = [...], E_over_sigma_y = [...], sigma_y, rho, R   (a sweep: every pair)
    [hertz]        P_max [N] or P_max_over_P_Y, P_min [N] (default P_max / 1000), steps (25)
    [load_paths]   P_max = [N, ...] or P_max_over_P_Y = [...], unload (true), loading_steps (48,
                   increments up to the largest P_max), unloading_steps (16)
    [calibration]  ship = "radius" | "force"            (fit Ca, Kc; needs [load_paths] above P_Y)
    [collision]    v_in = [m/s, ...] or v_in_over_v_Y = [...], laws = ["vz", "thornton", "hertz"]
    [outputs]      out (folder, default results/scenes/<name>), plots, vtu, histories (booleans)

The file is parsed with the standard library (tomllib) and validated into frozen dataclasses
before anything runs: an unknown key, a wrong type or an out-of-range value is a ValueError
naming the file, the key and the allowed range. Only what a scene asks for is computed: a scene
whose loads all stay below P_Y (and that does not calibrate) uses the elastic material and never
runs the return mapping; a scene with ``unload = false`` never unloads; plots, VTU files and
histories are written only on request; meshes come from the cache (meshes.hemisphere).
"""
from __future__ import annotations

import math
import sys
import time
import tomllib
from dataclasses import dataclass, field, replace
from importlib import resources
from pathlib import Path

from calib import report

# contact element size / largest contact radius for each mesh level (spec_for's convention:
# the reference default mesh, 4e-5 m at a_max = 1.48e-3 m, is 1/37)
MESH_LEVELS = {"coarse": 0.1, "default": 1.0 / 37.0, "fine": 1.0 / 74.0}
# the reference sphere's own mesh family (HemisphereMeshSpec(contact_size=...)) [m]
REFERENCE_CONTACT_SIZES = {"coarse": 1.6e-4, "default": 4e-5, "fine": 2e-5}
REFERENCE_PEAKS = (500.0, 1000.0, 1500.0)
DEFAULT_PEAKS_OVER_YIELD = (13.7, 27.4, 41.2)  # the reference peaks in units of P_Y
LAW_NAMES = ("vz", "thornton", "hertz", "walton-braun")
# Wall time per FE step against dofs, calibrated on the reference calibration
# (12,112 dofs, 97 FE steps + 3 first-yield solves, 54-58 s on 2 cores): ~0.57 s per step.
SECONDS_PER_STEP_AT_12K_DOFS = 0.57

SCHEMA = {
    "scene": {"name": str, "description": str},
    "mesh": {"level": str, "contact_size": float, "contact_size_over_a_max": float},
    "material": {"name": str, "E": float, "nu": float, "sigma_y": float, "rho": float, "R": float},
    "grid": {"nu": list, "E_over_sigma_y": list, "sigma_y": float, "rho": float, "R": float},
    "hertz": {"P_max": float, "P_max_over_P_Y": float, "P_min": float, "steps": int},
    "load_paths": {"P_max": list, "P_max_over_P_Y": list, "unload": bool, "loading_steps": int,
                   "unloading_steps": int},
    "calibration": {"ship": str},
    "collision": {"v_in": list, "v_in_over_v_Y": list, "laws": list},
    "outputs": {"out": str, "plots": bool, "vtu": bool, "histories": bool},
}


class SceneError(ValueError):
    """A scene file that does not validate (a ValueError: the CLI prints one line, exit 2)."""


# ----------------------------------------------------------------------------- schema
@dataclass(frozen=True)
class SceneMaterial:
    """One sphere: E [Pa], nu [-], sigma_y [Pa], rho [kg/m^3], R [m]."""

    name: str
    E: float
    nu: float
    sigma_y: float
    rho: float
    R: float

    def material(self):
        from nfdmodel import Material

        return Material(self.E, self.nu, self.sigma_y, self.rho)

    def pair(self):
        from nfdmodel import ContactPair

        return ContactPair.sphere_flat(self.material(), self.R)

    @property
    def is_reference(self) -> bool:
        return (self.E, self.nu, self.sigma_y, self.R) == (70e9, 0.3, 100e6, 0.1)

    def inputs(self) -> dict:
        return {"name": self.name, "E": self.E, "nu": self.nu, "sigma_y": self.sigma_y,
                "rho": self.rho, "R": self.R, "E_over_sigma_y": self.E / self.sigma_y}


@dataclass(frozen=True)
class MeshChoice:
    level: str | None = "default"
    contact_size: float | None = None             # [m], explicit
    contact_size_over_a_max: float | None = None  # explicit ratio

    def label(self) -> str:
        if self.contact_size is not None:
            return f"contact_size={self.contact_size:g}"
        if self.contact_size_over_a_max is not None:
            return f"contact_size_over_a_max={self.contact_size_over_a_max:g}"
        return str(self.level)

    def ratio(self) -> float:
        return self.contact_size_over_a_max if self.contact_size_over_a_max is not None else MESH_LEVELS[self.level or "default"]


@dataclass(frozen=True)
class HertzStage:
    P_max: float | None = None
    P_max_over_P_Y: float | None = None
    P_min: float | None = None
    steps: int = 25

    def loads(self, pair) -> tuple[float, float]:
        top = self.P_max if self.P_max is not None else (self.P_max_over_P_Y or 41.2) * pair.P_Y
        return (self.P_min if self.P_min is not None else top / 1000.0), top


@dataclass(frozen=True)
class LoadPathStage:
    P_max: tuple[float, ...] | None = None
    P_max_over_P_Y: tuple[float, ...] | None = None
    unload: bool = True
    loading_steps: int = 48
    unloading_steps: int = 16

    def peaks(self, pair) -> tuple[float, ...]:
        if self.P_max is not None:
            return tuple(sorted(self.P_max))
        ratios = self.P_max_over_P_Y if self.P_max_over_P_Y is not None else DEFAULT_PEAKS_OVER_YIELD
        return tuple(sorted(k * pair.P_Y for k in ratios))


@dataclass(frozen=True)
class CollisionStage:
    v_in: tuple[float, ...] | None = None
    v_in_over_v_Y: tuple[float, ...] | None = None
    laws: tuple[str, ...] = ("vz", "thornton", "hertz")

    def velocities(self, pair) -> tuple[float, ...]:
        return self.v_in if self.v_in is not None else tuple(k * pair.v_Y for k in self.v_in_over_v_Y)


@dataclass(frozen=True)
class Outputs:
    out: str | None = None
    plots: bool = False
    vtu: bool = False
    histories: bool = True


@dataclass(frozen=True)
class Scene:
    """A validated scene (see the module docstring)."""

    name: str
    materials: tuple[SceneMaterial, ...]
    mesh: MeshChoice = MeshChoice()
    hertz: HertzStage | None = None
    load_paths: LoadPathStage | None = None
    calibration_ship: str | None = None   # None: no calibration
    collision: CollisionStage | None = None
    outputs: Outputs = Outputs()
    description: str = ""
    source: str = ""
    is_grid: bool = False

    def out_dir(self, override: str | Path | None = None) -> Path:
        if override is not None:
            return Path(override)
        return Path(self.outputs.out) if self.outputs.out else report.REPO_ROOT / "results" / "scenes" / self.name

    def stages(self) -> list[str]:
        names = []
        if self.hertz is not None:
            names.append("hertz")
        if self.calibration_ship is not None:
            names.append("calibration")
        elif self.load_paths is not None:
            names.append("load_paths")
        if self.collision is not None:
            names.append("collision")
        return names


# ----------------------------------------------------------------------------- parsing
def _fail(source: str, key: str, message: str):
    raise SceneError(f"scene {source}: {key}: {message}")


def _number(source, key, value, low=None, high=None, low_open=True, high_open=False, integer=False):
    kind = "an integer" if integer else "a number"
    if isinstance(value, bool) or not isinstance(value, (int, float)) or (integer and not isinstance(value, int)):
        _fail(source, key, f"must be {kind}, got {value!r} ({type(value).__name__})")
    value = int(value) if integer else float(value)
    if not math.isfinite(value):
        _fail(source, key, f"must be finite, got {value}")
    lo = "" if low is None else (f"> {low:g}" if low_open else f">= {low:g}")
    hi = "" if high is None else (f"< {high:g}" if high_open else f"<= {high:g}")
    allowed = " and ".join(s for s in (lo, hi) if s)
    if low is not None and (value <= low if low_open else value < low):
        _fail(source, key, f"out of range: need {allowed}, got {value:g}")
    if high is not None and (value >= high if high_open else value > high):
        _fail(source, key, f"out of range: need {allowed}, got {value:g}")
    return value


def _numbers(source, key, value, **bounds) -> tuple:
    if not isinstance(value, list) or not value:
        _fail(source, key, f"must be a non-empty list of numbers, got {value!r}")
    return tuple(_number(source, f"{key}[{k}]", v, **bounds) for k, v in enumerate(value))


MATERIAL_BOUNDS = {"E": {"low": 0}, "nu": {"low": 0, "low_open": False, "high": 0.5, "high_open": True},
                   "sigma_y": {"low": 0}, "rho": {"low": 0}, "R": {"low": 0}}


def _table(source, data, section, required=False) -> dict | None:
    if section not in data:
        if required:
            _fail(source, f"[{section}]", "missing section")
        return None
    value = data[section]
    if not isinstance(value, dict):
        _fail(source, f"[{section}]", f"must be a table, got {type(value).__name__}")
    unknown = sorted(set(value) - set(SCHEMA[section]))
    if unknown:
        _fail(source, f"{section}.{unknown[0]}", f"unknown key (allowed: {', '.join(SCHEMA[section])})")
    return value


def _bool(source, key, value):
    if not isinstance(value, bool):
        _fail(source, key, f"must be true or false, got {value!r}")
    return value


def parse_scene(data: dict, source: str = "<scene>") -> Scene:
    """Validate the TOML data of a scene into a Scene (SceneError on any problem)."""
    unknown = sorted(set(data) - set(SCHEMA))
    if unknown:
        _fail(source, unknown[0], f"unknown section (allowed: {', '.join(SCHEMA)})")
    head = _table(source, data, "scene") or {}
    name = head.get("name", Path(source).stem)
    if not isinstance(name, str) or not name or not all(c.isalnum() or c in "-_." for c in name):
        _fail(source, "scene.name", f"must be a non-empty name of letters, digits, '-', '_', '.', got {name!r}")
    description = head.get("description", "")
    if not isinstance(description, str):
        _fail(source, "scene.description", "must be a string")

    mesh_data = _table(source, data, "mesh") or {}
    if len(mesh_data) > 1:
        _fail(source, "mesh", f"give one of level, contact_size, contact_size_over_a_max, got {sorted(mesh_data)}")
    mesh = MeshChoice()
    if "level" in mesh_data:
        if mesh_data["level"] not in MESH_LEVELS:
            _fail(source, "mesh.level", f"must be one of {', '.join(MESH_LEVELS)}, got {mesh_data['level']!r}")
        mesh = MeshChoice(level=mesh_data["level"])
    elif "contact_size" in mesh_data:
        mesh = MeshChoice(level=None, contact_size=_number(source, "mesh.contact_size", mesh_data["contact_size"], low=0))
    elif "contact_size_over_a_max" in mesh_data:
        mesh = MeshChoice(level=None, contact_size_over_a_max=_number(
            source, "mesh.contact_size_over_a_max", mesh_data["contact_size_over_a_max"], low=0, high=0.25))

    # materials: [[material]] tables or a [grid]
    materials = []
    is_grid = False
    if "material" in data and "grid" in data:
        _fail(source, "grid", "give either [[material]] tables or a [grid], not both")
    if "material" in data:
        entries = data["material"]
        entries = [entries] if isinstance(entries, dict) else entries
        if not isinstance(entries, list) or not entries or not all(isinstance(e, dict) for e in entries):
            _fail(source, "material", "must be one or more [[material]] tables")
        for k, entry in enumerate(entries):
            unknown = sorted(set(entry) - set(SCHEMA["material"]))
            if unknown:
                _fail(source, f"material[{k}].{unknown[0]}", f"unknown key (allowed: {', '.join(SCHEMA['material'])})")
            missing = [key for key in MATERIAL_BOUNDS if key not in entry]
            if missing:
                _fail(source, f"material[{k}].{missing[0]}", "missing (need E, nu, sigma_y, rho, R)")
            values = {key: _number(source, f"material[{k}].{key}", entry[key], **bounds)
                      for key, bounds in MATERIAL_BOUNDS.items()}
            label = entry.get("name", f"material{k}")
            if not isinstance(label, str):
                _fail(source, f"material[{k}].name", "must be a string")
            materials.append(SceneMaterial(name=label, **values))
    elif "grid" in data:
        grid = _table(source, data, "grid")
        for key in SCHEMA["grid"]:
            if key not in grid:
                _fail(source, f"grid.{key}", "missing (need nu, E_over_sigma_y, sigma_y, rho, R)")
        nus = _numbers(source, "grid.nu", grid["nu"], **MATERIAL_BOUNDS["nu"])
        ratios = _numbers(source, "grid.E_over_sigma_y", grid["E_over_sigma_y"], low=1)
        fixed = {key: _number(source, f"grid.{key}", grid[key], **MATERIAL_BOUNDS[key]) for key in ("sigma_y", "rho", "R")}
        materials = [SceneMaterial(name=f"nu{nu:g}_E{ratio:g}sy", E=ratio * fixed["sigma_y"], nu=nu, **fixed)
                     for nu in nus for ratio in ratios]
        is_grid = True
    else:
        _fail(source, "material", "missing: give [[material]] tables or a [grid]")
    if len({m.name for m in materials}) != len(materials):
        _fail(source, "material.name", "names must be unique")

    hertz = None
    hertz_data = _table(source, data, "hertz")
    if hertz_data is not None:
        if "P_max" in hertz_data and "P_max_over_P_Y" in hertz_data:
            _fail(source, "hertz", "give P_max or P_max_over_P_Y, not both")
        hertz = HertzStage(
            P_max=_number(source, "hertz.P_max", hertz_data["P_max"], low=0) if "P_max" in hertz_data else None,
            P_max_over_P_Y=(_number(source, "hertz.P_max_over_P_Y", hertz_data["P_max_over_P_Y"], low=0, high=1e4)
                            if "P_max_over_P_Y" in hertz_data else None),
            P_min=_number(source, "hertz.P_min", hertz_data["P_min"], low=0) if "P_min" in hertz_data else None,
            steps=_number(source, "hertz.steps", hertz_data.get("steps", 25), low=2, low_open=False, high=1000, integer=True))
        for m in materials:
            low, top = hertz.loads(m.pair())
            if not top > low:
                _fail(source, "hertz.P_min", f"must be < P_max = {top:g} N, got {low:g}")

    load_paths = None
    lp = _table(source, data, "load_paths")
    if lp is not None:
        if "P_max" in lp and "P_max_over_P_Y" in lp:
            _fail(source, "load_paths", "give P_max or P_max_over_P_Y, not both")
        load_paths = LoadPathStage(
            P_max=_numbers(source, "load_paths.P_max", lp["P_max"], low=0) if "P_max" in lp else None,
            P_max_over_P_Y=(_numbers(source, "load_paths.P_max_over_P_Y", lp["P_max_over_P_Y"], low=0, high=1e4)
                            if "P_max_over_P_Y" in lp else None),
            unload=_bool(source, "load_paths.unload", lp.get("unload", True)),
            loading_steps=_number(source, "load_paths.loading_steps", lp.get("loading_steps", 48), low=2,
                                  low_open=False, high=10000, integer=True),
            unloading_steps=_number(source, "load_paths.unloading_steps", lp.get("unloading_steps", 16), low=2,
                                    low_open=False, high=1000, integer=True))

    ship = None
    cal = _table(source, data, "calibration")
    if cal is not None:
        ship = cal.get("ship", "radius")
        if ship not in ("radius", "force"):
            _fail(source, "calibration.ship", f"must be 'radius' or 'force', got {ship!r}")
        if ship == "force" and load_paths is not None and not load_paths.unload:
            _fail(source, "calibration.ship", "'force' fits the unloading too: needs load_paths.unload = true")
        if load_paths is None:
            load_paths = LoadPathStage()
        for m in materials:
            peaks = load_paths.peaks(m.pair())
            if not max(peaks) > 2 * m.pair().P_Y:
                _fail(source, "load_paths.P_max", f"calibration needs loads above P_Y: the largest P_max must be "
                      f"> 2 P_Y = {2 * m.pair().P_Y:.4g} N for material {m.name!r}, got {max(peaks):.4g} N")

    collision = None
    col = _table(source, data, "collision")
    if col is not None:
        if ("v_in" in col) == ("v_in_over_v_Y" in col):
            _fail(source, "collision", "give exactly one of v_in [m/s] or v_in_over_v_Y")
        laws = col.get("laws", ["vz", "thornton", "hertz"])
        if not isinstance(laws, list) or not laws or any(law not in LAW_NAMES for law in laws):
            _fail(source, "collision.laws", f"must be a non-empty list of {', '.join(LAW_NAMES)}, got {laws!r}")
        collision = CollisionStage(
            v_in=_numbers(source, "collision.v_in", col["v_in"], low=0) if "v_in" in col else None,
            v_in_over_v_Y=(_numbers(source, "collision.v_in_over_v_Y", col["v_in_over_v_Y"], low=0, high=1e4)
                           if "v_in_over_v_Y" in col else None),
            laws=tuple(laws))

    out_data = _table(source, data, "outputs") or {}
    out = out_data.get("out")
    if out is not None and (not isinstance(out, str) or not out):
        _fail(source, "outputs.out", "must be a folder path (string)")
    outputs = Outputs(out=out, **{k: _bool(source, f"outputs.{k}", out_data[k])
                                  for k in ("plots", "vtu", "histories") if k in out_data})
    if hertz is None and load_paths is None and collision is None:
        _fail(source, "scene", "nothing to run: add [hertz], [load_paths], [calibration] or [collision]")
    return Scene(name=name, materials=tuple(materials), mesh=mesh, hertz=hertz, load_paths=load_paths,
                 calibration_ship=ship, collision=collision, outputs=outputs, description=description,
                 source=source, is_grid=is_grid)


def builtin_scenes() -> dict[str, Path]:
    """Name -> path of the scenes shipped in calib/scenes/."""
    folder = resources.files("calib") / "scenes"
    return {Path(str(p)).stem: Path(str(p)) for p in folder.iterdir() if str(p).endswith(".toml")}


def load_scene(path_or_name: str | Path) -> Scene:
    """Read and validate a scene: a file path, or the name of a built-in scene."""
    path = Path(path_or_name)
    if not path.is_file():
        builtin = builtin_scenes()
        if str(path_or_name) in builtin:
            path = builtin[str(path_or_name)]
        else:
            raise FileNotFoundError(f"scene file not found: {path_or_name} (built-in scenes: "
                                    f"{', '.join(sorted(builtin))})")
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(f"scene {path}: not valid TOML: {exc}") from None
    return parse_scene(data, str(path))


# ----------------------------------------------------------------------------- FE specs
def mesh_spec(scene_mesh: MeshChoice, material: SceneMaterial, a_max: float):
    """The hemisphere mesh for a largest contact radius ``a_max`` [m] (spec_for's recipe), or the
    reference mesh family for the reference sphere (so its cached meshes are reused)."""
    from meshes.hemisphere import HemisphereMeshSpec

    if material.is_reference and scene_mesh.contact_size_over_a_max is None and a_max <= 1.5e-3:
        size = scene_mesh.contact_size or REFERENCE_CONTACT_SIZES[scene_mesh.level or "default"]
        return HemisphereMeshSpec(contact_size=size)
    h = scene_mesh.contact_size if scene_mesh.contact_size is not None else a_max * scene_mesh.ratio()
    R = material.R
    refined_radius = min(max(1.1 * a_max, 2 * h), 0.9 * R)
    refined_depth = min(max(0.35 * a_max, 2 * h), 0.9 * R)
    return HemisphereMeshSpec(radius=R, contact_size=h, refined_radius=refined_radius,
                              refined_depth=refined_depth, far_size=max(R / 10, h))


def calibration_spec(scene: Scene, material: SceneMaterial):
    """The CalibrationSpec of one material of ``scene`` (load paths and mesh)."""
    from calib.calibration import CalibrationSpec, check_calibration_inputs, estimated_contact_radius
    from calib.loadpath import LoadPathPlan

    pair = material.pair()
    stage = scene.load_paths or LoadPathStage()
    peaks = stage.peaks(pair)
    try:
        check_calibration_inputs(material.material(), material.R, peaks[-1])
    except ValueError as exc:
        _fail(scene.source, f"material {material.name}", str(exc))
    a_max = estimated_contact_radius(pair, peaks[-1])
    plan = LoadPathPlan(peaks=peaks, loading_step=peaks[-1] / stage.loading_steps,
                        unloading_steps=stage.unloading_steps,
                        first_load=min(0.5 * pair.P_Y, peaks[0], 20.0 if material.is_reference else math.inf))
    return CalibrationSpec(material=material.material(), radius=material.R,
                           mesh=mesh_spec(scene.mesh, material, a_max), plan=plan)


def hertz_mesh_spec(scene: Scene, material: SceneMaterial):
    pair = material.pair()
    _, top = scene.hertz.loads(pair)
    return mesh_spec(scene.mesh, material, float(pair.hertz_radius(top)))


def estimate_dofs(spec) -> int:
    """Degrees of freedom of the P2 mesh of ``spec`` without meshing: elements ~ integral of
    1 / (area of an equilateral triangle of size h(r, z)) over the section, dofs ~ 4.12 x
    elements (both constants fitted on the reference default mesh: 2,939 elements, 12,112 dofs)."""
    import numpy as np

    R = spec.radius
    # polar-like quadrature refined towards the pole, where h is smallest
    n = 400
    s = np.geomspace(1e-7, 1.0, n) * R  # distance from the pole
    theta = np.linspace(0, np.pi / 2, 60)
    S, T = np.meshgrid(s, theta, indexing="ij")
    r, z = S * np.cos(T), S * np.sin(T)
    inside = r**2 + (z - R) ** 2 <= R**2
    h = spec.size_at(r, z)
    density = np.where(inside, 1.0 / (np.sqrt(3) / 4 * h**2), 0.0) * S  # Jacobian s
    elements = np.trapezoid(np.trapezoid(density, theta, axis=1), s)
    return int(4.12 * elements * ESTIMATE_CALIBRATION)


ESTIMATE_CALIBRATION = 1.0  # set below on first use against the reference mesh


def _calibrate_estimator():
    global ESTIMATE_CALIBRATION
    from meshes.hemisphere import HemisphereMeshSpec

    if ESTIMATE_CALIBRATION == 1.0:
        raw = estimate_dofs(HemisphereMeshSpec())
        ESTIMATE_CALIBRATION = 12112.0 / raw


def mesh_dofs(spec) -> tuple[int, bool]:
    """(dofs, exact) of a mesh: counted from the cached file if there is one, else estimated."""
    from meshes.hemisphere import mesh_path

    path = mesh_path(spec)
    if path.is_file():
        try:
            import meshio

            raw = meshio.read(path, file_format="gmsh")
            return int(2 * (raw.cells_dict["triangle6"].max() + 1)), True
        except Exception:  # a corrupt cache entry is rebuilt at run time: estimate
            pass
    _calibrate_estimator()
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
    from meshes.hemisphere import mesh_path

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


# ----------------------------------------------------------------------------- progress
class Progress:
    """Progress lines on stderr with elapsed time and an estimate of what is left; silent when
    ``enabled`` is false (--quiet, or stderr not a terminal)."""

    def __init__(self, enabled: bool, total_estimate_s: float = 0.0, stream=None):
        self.enabled = enabled
        self.total = total_estimate_s
        self.start = time.perf_counter()
        self.stream = stream or sys.stderr
        self.prefix = ""

    def __call__(self, message: str) -> None:
        if not self.enabled:
            return
        elapsed = time.perf_counter() - self.start
        left = f", ~{max(self.total - elapsed, 0):.0f} s left" if self.total else ""
        print(f"  [{elapsed:6.1f} s{left}] {self.prefix}{message}", file=self.stream, flush=True)


def terminal_progress(quiet: bool, total_estimate_s: float = 0.0) -> Progress:
    return Progress(not quiet and sys.stderr.isatty(), total_estimate_s)


# ----------------------------------------------------------------------------- run
def run_loading_branch(solver, plan, progress=None) -> list[dict]:
    """The loading branch of ``plan`` only (a loading-only scene never unloads): one history
    row per accepted FE step, as in calib.loadpath.run_load_paths."""
    from calib.loadpath import advance, plastic_zone

    say = progress or (lambda message: None)
    quadrature_r, quadrature_z = solver.basis.mapping.F(solver.basis.X)
    rows: list[dict] = []

    def record(result, before):
        rows.append({"path": "loading", "branch": "loading", **result.record.as_dict(),
                     **plastic_zone(result.state, quadrature_r, quadrature_z)})

    state = solver.initial_state()
    targets = plan.loading_targets()
    for k, target in enumerate(targets, 1):
        state = advance(solver, state, "force", target, plan.min_step_fraction, record)
        say(f"load step {k}/{len(targets)}: P = {state.force:.4g} N")
    return rows


def calibrate_loading_only(spec, progress=None) -> dict:
    """Ca, Kc from the loading branch alone (the radius fit of calib.calibration, which uses only
    the loading points): about half the FE steps of a full calibration. Returns a dict with the
    fit, P_Y (theory and FE first yield), mesh, wall time and the loading rows."""
    from calib.calibration import first_yield_load
    from calib.fe import ContactSolver
    from calib.fit import fit_radius_law, radius_law_data
    from calib.plasticity import VonMisesMaterial
    from meshes.hemisphere import hemisphere_mesh

    t0 = time.perf_counter()
    hemisphere = hemisphere_mesh(spec.mesh)
    pair = spec.pair
    material = spec.material
    P_Y_fe = first_yield_load(hemisphere, material)
    solver = ContactSolver(hemisphere, VonMisesMaterial(material.E, material.nu, material.sigma_y),
                           residual_tolerance=spec.residual_tolerance,
                           contact_radius_method=spec.contact_radius_method)
    rows = run_loading_branch(solver, spec.plan, progress)
    data = radius_law_data([r["P"] for r in rows], [r["alpha"] for r in rows],
                           [r["contact_radius"] for r in rows],
                           R_star=pair.R_star, E_star=pair.E_star, P_Y=pair.P_Y)
    fit = fit_radius_law(data)
    return {"fit": fit, "P_Y_fe": P_Y_fe, "rows": rows, "wall_time_s": time.perf_counter() - t0,
            "mesh": {**spec.mesh.describe(), "elements": int(hemisphere.mesh.nelements), "dofs": int(solver.n_dofs)}}


def _run_hertz(scene, material, out, progress) -> dict:
    import numpy as np

    from calib.hertz_validation import run_hertz

    pair = material.pair()
    low, top = scene.hertz.loads(pair)
    spec = hertz_mesh_spec(scene, material)
    progress(f"hertz validation: {material.name}, P = {low:.4g} .. {top:.4g} N")
    run = run_hertz(spec, radius=material.R, E=material.E, nu=material.nu,
                    loads=np.geomspace(low, top, scene.hertz.steps))
    summary = {"material": material.inputs(), "top_load": run.top_load, "mesh": run.mesh,
               "finite_size_coefficient": run.finite_size_coefficient, "wall_time_s": run.wall_time_s}
    stamp = report.stamp(run.wall_time_s, mesh=run.mesh)
    report.write_json(out / "hertz.json", {**summary, "stamp": stamp})
    if scene.outputs.histories:
        report.write_csv(out / "hertz_steps.csv", run.rows, comment=report.stamp_comment(stamp))
    if scene.outputs.plots:
        from calib.hertz_validation import _plot_hertz

        _plot_hertz(out, run, material.R, material.E, material.nu)
    return summary


def _run_load_paths(scene, material, out, progress) -> dict:
    """Load paths without calibration: elastic material when every P_max < P_Y."""
    from calib.fe import ContactSolver
    from calib.loadpath import run_load_paths
    from calib.materials import ElasticMaterial
    from meshes.hemisphere import hemisphere_mesh

    t0 = time.perf_counter()
    spec = calibration_spec(scene, material)
    elastic = not plastic_needed(scene, material)
    if elastic:
        fe_material = ElasticMaterial(material.E, material.nu)
    else:
        from calib.plasticity import VonMisesMaterial

        fe_material = VonMisesMaterial(material.E, material.nu, material.sigma_y)
    hemisphere = hemisphere_mesh(spec.mesh)
    solver = ContactSolver(hemisphere, fe_material)
    progress(f"load paths: {material.name}, {'elastic' if elastic else 'elastoplastic'}, "
             f"P_max = {', '.join(f'{p:.4g}' for p in spec.plan.peaks)} N")
    paths_out = []
    if scene.load_paths.unload:
        result = run_load_paths(solver, spec.plan, progress=progress)
        rows = [r for p in result.paths for r in p.rows if r["branch"] == "unloading"]
        rows = result.loading_rows + rows
        paths_out = [{"P_max": p.peak, "alpha_max": p.alpha_max, "alpha_residual": p.alpha_residual,
                      "e": p.restitution} for p in result.paths]
    else:
        rows = run_loading_branch(solver, spec.plan, progress)
    mesh = {**spec.mesh.describe(), "dofs": int(solver.n_dofs), "elements": int(hemisphere.mesh.nelements)}
    wall = time.perf_counter() - t0
    summary = {"material": material.inputs(), "elastic": elastic, "P_Y": material.pair().P_Y,
               "peaks": list(spec.plan.peaks), "unload": scene.load_paths.unload, "paths": paths_out,
               "steps": len(rows), "mesh": mesh, "wall_time_s": wall}
    stamp = report.stamp(wall, mesh=mesh)
    report.write_json(out / "load_paths.json", {**summary, "stamp": stamp})
    if scene.outputs.histories:
        report.write_csv(out / "load_paths.csv", rows, comment=report.stamp_comment(stamp))
    if scene.outputs.plots:
        plt = report.pyplot()
        fig, ax = plt.subplots(figsize=(6, 4))
        ax.plot([r["alpha"] * 1e6 for r in rows], [r["P"] for r in rows], "o-", ms=3)
        ax.set_xlabel("approach alpha [um]"); ax.set_ylabel("P [N]"); ax.grid(alpha=0.3)
        ax.set_title(f"{material.name}: FE load paths")
        report.save_figure(fig, out / "force_approach.png")
    return summary


def _run_calibration(scene, material, out, progress) -> tuple[dict, object]:
    from calib import calibration, calibration_report

    spec = calibration_spec(scene, material)
    progress(f"calibration: {material.name}, P_max = {', '.join(f'{p:.4g}' for p in spec.plan.peaks)} N")
    if not scene.load_paths.unload:
        res = calibrate_loading_only(spec, progress)
        from nfdmodel import VZParams, parameter_record

        params = VZParams(spec.pair, res["fit"].Ca.slope, res["fit"].Kc.slope)
        stamp = report.stamp(res["wall_time_s"], mesh=res["mesh"])
        record = parameter_record(params, material.R, spec.material)
        record.update({"fit": {"shipped": "radius", "loading_only": True,
                               "Ca_r2": res["fit"].Ca.r_squared, "Ca_se": res["fit"].Ca.standard_error,
                               "Kc_r2": res["fit"].Kc.r_squared, "Kc_se": res["fit"].Kc.standard_error},
                       "P_Y_fe": res["P_Y_fe"], "mesh": res["mesh"], "stamp": stamp})
        report.write_json(out / "parameters.json", record)
        if scene.outputs.histories:
            report.write_csv(out / "loading.csv", res["rows"], comment=report.stamp_comment(stamp))
        return {"Ca": params.Ca, "Kc": params.Kc, "Ca_hat": params.Ca_hat, "Kc_hat": params.Kc_hat,
                "P_Y": spec.pair.P_Y, "P_Y_fe": res["P_Y_fe"], "wall_time_s": res["wall_time_s"],
                "mesh": res["mesh"], "loading_only": True}, params
    result = calibration.calibrate(spec, progress=progress, ship=scene.calibration_ship)
    if scene.outputs.histories or scene.outputs.plots or scene.outputs.vtu:
        calibration_report.write(result, out, plots=scene.outputs.plots, vtu=scene.outputs.vtu)
    else:  # the parameter file and the summary only
        stamp = report.stamp(result.wall_time_s, mesh=result.mesh_info, timings=result.timings)
        report.write_json(out / "parameters.json", calibration_report.parameter_file(result, stamp))
        report.write_json(out / "calibration.json", {**calibration.summary(result), "stamp": stamp})
    s = calibration.summary(result)
    return {**{k: s[k] for k in ("Ca", "Kc", "Ca_hat", "Kc_hat", "P_Y", "P_Y_fe", "wall_time_s", "mesh")},
            "loading_only": False, "shipped_fit": s["shipped_fit"]}, result.params


def _run_collision(scene, material, out, params, progress) -> dict:
    import warnings

    from nfdmodel import collide

    pair = material.pair()
    source = "calibration"
    if params is None and "vz" in scene.collision.laws:
        from calib.master_table import MasterTable

        table = MasterTable.load()
        values = table.parameters(material.E, material.nu, material.sigma_y, material.R, material.rho)
        from nfdmodel import VZParams

        params = VZParams.from_dimensionless(pair, values["Ca_hat"], values["Kc_hat"])
        source = f"master table ({table.meta.get('accuracy', 'accuracy not stated')})"
    velocities = scene.collision.velocities(pair)
    progress(f"collision: {material.name}, {len(velocities)} velocities, laws {', '.join(scene.collision.laws)}")
    rows = []
    t0 = time.perf_counter()
    for law in scene.collision.laws:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            result = collide(law, params if params is not None else pair, velocities, dt=None)
        rows += [{"law": law, "v_in_over_v_Y": r["v_in"] / pair.v_Y, **r} for r in result.records()]
    stamp = report.stamp(time.perf_counter() - t0, vz_parameters=source)
    report.write_csv(out / "collision.csv", rows, comment=report.stamp_comment(stamp))
    return {"rows": len(rows), "vz_parameters": source}


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
        if isinstance(say, Progress):
            say.prefix = f"material {k}/{n} ({material.name}): " if n > 1 else ""
        entry = {"material": material.inputs()}
        params = None
        if scene.hertz is not None:
            entry["hertz"] = _run_hertz(scene, material, folder, say)
        if scene.calibration_ship is not None:
            entry["calibration"], params = _run_calibration(scene, material, folder, say)
        elif scene.load_paths is not None:
            entry["load_paths"] = _run_load_paths(scene, material, folder, say)
        if scene.collision is not None:
            entry["collision"] = _run_collision(scene, material, folder, params, say)
        results.append(entry)
    wall = time.perf_counter() - t0
    summary = {"scene": scene.name, "source": scene.source, "stages": scene.stages(), "materials": results,
               "wall_time_s": wall}
    report.write_json(base / "scene.json", {**summary, "stamp": report.stamp(wall)})
    return summary

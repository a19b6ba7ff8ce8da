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
import tomllib
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

from calib import output

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
        return Path(self.outputs.out) if self.outputs.out else output.RESULTS / "scenes" / self.name

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
    """Name -> path of the scenes shipped in calib/scenes/builtin/."""
    folder = resources.files("calib.scenes") / "builtin"
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

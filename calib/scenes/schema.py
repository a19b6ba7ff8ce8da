"""Scenes: a TOML file that declares materials, a mesh level, what to run and which outputs.

    [scene]        name = "steel", description = "..."
    [mesh]         level = "coarse" | "default" | "fine"   or   contact_size = 4e-5  [m]
                   or contact_size_over_a_max = 0.05 (element size / largest contact radius)
    [[material]]   name, E [Pa], nu [-], sigma_y [Pa], rho [kg/m^3], R [m]   (one table per material);
                   hardening_modulus H [Pa] (0 <= H <= E: sigma = sigma_Y + H eps_p) or flow_curve (a CSV
                   plastic_strain,stress from sigma_y, relative to the scene's folder) with
                   flow_curve_extrapolation ("flat", the default, or "slope"): the sphere's isotropic
                   hardening (calib.fe.flow_curve) in the calibration, load-path and impact FE;
                   rate_law ("johnson-cook" with jc_C [-], jc_reference_rate [1/s] (default 1), or
                   "cowper-symonds" with cs_D [1/s], cs_q [-]; nfdmodel.limits' ranges) and rate_form
                   ("relaxing", the default, or "fixed"): the sphere's strain-rate dependence
                   (calib.fe.rate_law) in the impact FE, the collision stage's rate-aware vz and vz-table
                   (nfdmodel.rate_relaxing.rate_form_law) and the calibration's parameter file ("rate_law");
                   refused with a counter-body, with another collision law but hertz, with hardening and
                   a collision stage
    [grid]         nu = [...], E_over_sigma_y = [...], sigma_y, rho, R   (a sweep: every pair)
    [hertz]        P_max [N] or P_max_over_P_Y, P_min [N] (default P_max / 1000), steps (25)
    [load_paths]   P_max = [N, ...] or P_max_over_P_Y = [...], unload (true), loading_steps (48,
                   increments up to the largest P_max), unloading_steps (16)
    [calibration]  ship = "radius" | "force" | "table"  (fit Ca, Kc and the vz-table law; needs [load_paths] above P_Y)
                   hardening_modulus or flow_curve (+ flow_curve_extrapolation): every material's hardening,
                   as in [[material]] (not both places; load paths from [load_paths], not v_max)
                   v_max [m/s] or v_max_from = "collision": load paths to the force of the fastest
                   impact (calib.fit.impact_window) instead of [load_paths] P_max
    [collision]    v_in = [m/s, ...] or v_in_over_v_Y = [...], laws = ["vz", "thornton", "hertz"]
                   (vz without a calibration: calib.fit.master_table.vz_constants, refused for a
                   hardening sphere)
    [impact]       v_in = [m/s, ...] or v_in_over_v_Y = [...]: the dynamic FE impact of the whole sphere
                   (``nfdcal impact``, calib.studies.impact) against the laws and the quasi-static FE;
                   error_estimate (true: the coarse-mesh and coarse-dt runs too), quasi_static (true),
                   steps_per_contact (100); the scene's mesh contact_size or level sizes its mesh
    [outputs]      out (folder, default results/scenes/<name>), plots, vtu, histories (booleans)
    [hertz.counter], [calibration.counter], [impact.counter]
                   E [Pa], nu (default: the sphere's), sigma_y [Pa] (absent: elastic), R [m] (absent:
                   a flat), rho [kg/m^3] (a counter-sphere's, required by calibration and impact: the
                   pair's m*; a flat's default the sphere's): the stage presses the sphere on this
                   deformable counter-body instead of the rigid flat (calib.fit.counter.CounterBody,
                   whose checks apply), as the commands' --counter-E/-nu/-sigma-y/-R/-rho do; the impact stage then runs the two-body impact
                   (calib.studies.impact_pair: the error estimate as error_estimate says, no quasi-static
                   comparison); a
                   calibration on a counter-body takes its load paths from [load_paths] (not v_max)
                   and its constants are the pair's, so no [collision] stage goes with it

The file is parsed with the standard library (tomllib) and validated by pydantic models (frozen,
unknown keys forbidden, types strict: a string is not a number, 1 is not true) before anything
runs. A validation error becomes ONE line naming the file, the key path and the allowed range,
e.g. ``scene my.toml: material[0].nu: out of range: need >= 0 and < 0.5, got 0.6`` (the range is
read from the models' JSON schema, so it is stated where it is declared). Only what a scene asks
for is computed: a scene whose loads all stay below P_Y (and that does not calibrate) uses the
elastic material and never runs the return mapping; a scene with ``unload = false`` never
unloads; plots, VTU files and histories are written only on request; meshes come from the cache
(meshes.hemisphere).
"""
from __future__ import annotations

import tomllib
from dataclasses import dataclass
from importlib import resources
from pathlib import Path
from typing import Annotated, Literal

from pydantic import AfterValidator, BaseModel, ConfigDict, Field, Strict, ValidationError, model_validator

from calib import output
from calib.fit.recipe import DEFAULT_PEAKS_OVER_YIELD, MESH_LEVELS
from calib.scenes.errors import one_line
from nfdmodel import LAWS, ContactPair, Material, limits

# Wall time per FE step against dofs, calibrated on the reference calibration
# (12,112 dofs, 97 FE steps + 3 first-yield solves, 54-58 s on 2 cores): ~0.57 s per step.
SECONDS_PER_STEP_AT_12K_DOFS = 0.57


class SceneError(ValueError):
    """A scene file that does not validate (a ValueError: the CLI prints one line, exit 2)."""


# ----------------------------------------------------------------------------- value types
# Strict: TOML gives real types, so "70e9" (a string) or true (a boolean) is an error, not a number.
Number = Annotated[float, Strict(), Field(allow_inf_nan=False)]
Positive = Annotated[Number, Field(gt=0)]
Ratio = Annotated[Number, Field(gt=0, le=1e4)]          # a multiple of P_Y or v_Y
PoissonRatio = Annotated[Number, Field(ge=0, lt=limits.NU_MAX)]
Flag = Annotated[bool, Strict()]
# every law of the registry (nfdmodel.registry) but vz-unload, whose unloading tables no scene stage fits
Law = Literal[tuple(name for name in LAWS if name != "vz-unload")]


def _list_of(item):
    """A non-empty TOML array of ``item``, kept as a tuple (frozen, hashable)."""
    return Annotated[tuple[item, ...], Field(min_length=1)]


def _check_name(name: str) -> str:
    if not name or not all(c.isalnum() or c in "-_." for c in name):
        raise ValueError(f"must be a non-empty name of letters, digits, '-', '_', '.', got {name!r}")
    return name


Name = Annotated[str, AfterValidator(_check_name)]


class _Table(BaseModel):
    """A TOML table: frozen, and a key the model does not declare is an error."""

    model_config = ConfigDict(frozen=True, extra="forbid")


# ----------------------------------------------------------------------------- scene objects
HARDENING_KEYS = ("hardening_modulus", "flow_curve", "flow_curve_extrapolation")


class _Hardening(_Table):
    """A sphere's isotropic hardening (calib.fe.flow_curve): the plastic modulus H [Pa] of the linear
    flow curve sigma = sigma_Y + H eps_p, or a tabulated flow curve (CSV) and its extrapolation."""

    hardening_modulus: Annotated[Number, Field(ge=0)] | None = None
    flow_curve: Annotated[str, Field(min_length=1)] | None = None
    flow_curve_extrapolation: Literal["flat", "slope"] | None = None

    @model_validator(mode="after")
    def _one_curve(self):
        if self.hardening_modulus is not None and self.flow_curve is not None:
            raise ValueError("hardening_modulus and flow_curve both give the flow curve: give one of them")
        if self.flow_curve_extrapolation is not None and self.flow_curve is None:
            raise ValueError("flow_curve_extrapolation extends a flow_curve table: give the table too")
        return self

    def hardening_given(self) -> bool:
        return any(getattr(self, key) is not None for key in HARDENING_KEYS)


def flow_curve_of(entry: _Hardening, sigma_y: float, E: float, folder: Path):
    """The FlowCurve of a scene's hardening entry for a sphere of ``sigma_y``, ``E`` [Pa] (None: perfectly
    plastic, also for H = 0); a ValueError of one line "key: ..." otherwise."""
    from calib.fe.flow_curve import LinearHardening, read_flow_curve

    if entry.hardening_modulus is not None:
        if entry.hardening_modulus > E:
            raise ValueError(f"hardening_modulus: out of range: need >= 0 and <= E = {E:g} Pa, got "
                             f"{entry.hardening_modulus:g}")
        return LinearHardening(sigma_y, entry.hardening_modulus) if entry.hardening_modulus > 0 else None
    if entry.flow_curve is None:
        return None
    path = Path(entry.flow_curve)
    try:
        return read_flow_curve(path if path.is_absolute() else folder / path, entry.flow_curve_extrapolation or "flat",
                               sigma_y=sigma_y)
    except ValueError as exc:
        raise ValueError(f"flow_curve: {exc}") from None


def rate_words(record: dict, separator: str = ", ") -> str:
    """A rate law's record in a few words: its name and constants (a plan's, a summary's; a table row's with
    ``separator`` " ")."""
    return f"{record['rate_law']} " + separator.join(f"{k} {v:g}" for k, v in record.items() if k != "rate_law")


def hardening_label(curve) -> str:
    """A sphere's flow curve in a few words (a plan's and a table row's)."""
    record = curve.record()
    if record["flow_curve"] == "linear":
        return f"hardening H = {record['hardening_modulus']:.4g} Pa"
    return f"flow curve {Path(record['source']).name} ({record['extrapolation']})"


RATE_CONSTANTS = {"johnson-cook": ("jc_C", "jc_reference_rate"), "cowper-symonds": ("cs_D", "cs_q")}
RATE_KEYS = ("rate_law", "jc_C", "jc_reference_rate", "cs_D", "cs_q", "rate_form")


class _Rate(_Table):
    """A sphere's strain-rate dependence (calib.fe.rate_law, the commands' --rate-law and its constants):
    rate_law "johnson-cook" with jc_C [-] and jc_reference_rate [1/s] (default 1), or "cowper-symonds" with
    cs_D [1/s] and cs_q [-]; rate_form (the collision stage's rate-aware law): "relaxing" (the default) or
    "fixed". The ranges are nfdmodel.limits' (the commands' too)."""

    rate_law: Literal["johnson-cook", "cowper-symonds"] | None = None
    jc_C: Annotated[Number, Field(ge=0, le=limits.JC_C_MAX)] | None = None
    jc_reference_rate: Annotated[Number, Field(ge=limits.JC_REFERENCE_RATE_MIN,
                                               le=limits.JC_REFERENCE_RATE_MAX)] | None = None
    cs_D: Annotated[Number, Field(ge=limits.CS_D_MIN, le=limits.CS_D_MAX)] | None = None
    cs_q: Annotated[Number, Field(ge=limits.CS_Q_MIN, le=limits.CS_Q_MAX)] | None = None
    rate_form: Literal["relaxing", "fixed"] | None = None

    @model_validator(mode="after")
    def _one_rate_law(self):
        given = [key for key in RATE_KEYS[1:] if getattr(self, key) is not None]
        if self.rate_law is None:
            if given:
                raise ValueError(f"{given[0]} belongs to a rate law: give rate_law = \"johnson-cook\" or "
                                 f"\"cowper-symonds\" too")
            return self
        for other, keys in RATE_CONSTANTS.items():
            for key in keys:
                if other != self.rate_law and getattr(self, key) is not None:
                    raise ValueError(f"{key} is a constant of rate_law {other!r}, not of {self.rate_law!r}")
        needed = ("jc_C",) if self.rate_law == "johnson-cook" else ("cs_D", "cs_q")
        missing = [key for key in needed if getattr(self, key) is None]
        if missing:
            raise ValueError(f"rate_law {self.rate_law!r} needs {' and '.join(needed)}")
        return self

    def rate_record(self) -> dict | None:
        """The rate law's record (calib.fe.rate_law's and nfdmodel.strain_rate's), None without one."""
        if self.rate_law == "johnson-cook":
            return {"rate_law": self.rate_law, "C": self.jc_C,
                    "reference_rate": 1.0 if self.jc_reference_rate is None else self.jc_reference_rate}
        if self.rate_law == "cowper-symonds":
            return {"rate_law": self.rate_law, "D": self.cs_D, "q": self.cs_q}
        return None

    @staticmethod
    def rate_keys(record: dict) -> dict:
        """The entry's keys of a rate law's record (the inverse of :meth:`rate_record`)."""
        if record["rate_law"] == "johnson-cook":
            return {"rate_law": record["rate_law"], "jc_C": record["C"], "jc_reference_rate": record["reference_rate"]}
        return {"rate_law": record["rate_law"], "cs_D": record["D"], "cs_q": record["q"]}

    def rate(self):
        """The calib.fe.rate_law RateLaw of the dynamic FE, None without one."""
        if self.rate_law is None:
            return None
        from calib.fe.rate_law import rate_law_from_record

        return rate_law_from_record(self.rate_record())

    def rate_form_used(self) -> str:
        """The collision stage's rate-aware law: relaxing unless rate_form says fixed."""
        return self.rate_form or "relaxing"


class SceneMaterial(_Hardening, _Rate):
    """One sphere: E [Pa], nu [-], sigma_y [Pa], rho [kg/m^3], R [m]; its hardening (_Hardening) and
    strain-rate dependence (_Rate)."""

    name: str
    E: Positive
    nu: PoissonRatio
    sigma_y: Positive
    rho: Positive
    R: Positive

    def material(self) -> Material:
        return Material(self.E, self.nu, self.sigma_y, self.rho)

    def pair(self) -> ContactPair:
        return ContactPair.sphere_flat(self.material(), self.R)

    def inputs(self) -> dict:
        return {"name": self.name, "E": self.E, "nu": self.nu, "sigma_y": self.sigma_y,
                "rho": self.rho, "R": self.R, "E_over_sigma_y": self.E / self.sigma_y}


class MeshChoice(_Table):
    """One of: a level (coarse, default, fine), an element size at the contact [m], or that size
    over the largest contact radius."""

    level: Literal["coarse", "default", "fine"] | None = "default"
    contact_size: Positive | None = None
    contact_size_over_a_max: Annotated[Number, Field(gt=0, le=0.25)] | None = None

    @model_validator(mode="before")
    @classmethod
    def _one_choice(cls, data):
        if isinstance(data, dict):
            given = sorted(k for k in ("level", "contact_size", "contact_size_over_a_max") if data.get(k) is not None)
            if len(given) > 1:
                raise ValueError(f"give one of level, contact_size, contact_size_over_a_max, got {given}")
            if given and given[0] != "level":
                data = {**data, "level": None}
        return data

    def label(self) -> str:
        if self.contact_size is not None:
            return f"contact_size={self.contact_size:g}"
        if self.contact_size_over_a_max is not None:
            return f"contact_size_over_a_max={self.contact_size_over_a_max:g}"
        return str(self.level)

    def ratio(self) -> float:
        return self.contact_size_over_a_max if self.contact_size_over_a_max is not None else MESH_LEVELS[self.level or "default"]


class SceneCounter(_Table):
    """A stage's counter-body: E [Pa], nu [-] (None: the sphere's), sigma_y [Pa] (None: elastic),
    R [m] (None: a flat), rho [kg/m^3] (a counter-sphere's is required by the calibration and
    impact stages, whose m* it enters; a flat's default the sphere's); calib.fit.counter.CounterBody
    validates it against nfdmodel.limits."""

    E: Positive
    nu: PoissonRatio | None = None
    sigma_y: Positive | None = None
    R: Positive | None = None
    rho: Positive | None = None

    def counter_body(self, material: SceneMaterial):
        """The calib.fit.counter.CounterBody under ``material``'s sphere (ValueError out of range)."""
        from calib.fit.counter import CounterBody

        return CounterBody(self.E, material.nu if self.nu is None else self.nu, self.sigma_y, self.R, self.rho)


def stage_pair(material: SceneMaterial, counter: SceneCounter | None) -> ContactPair:
    """The Hertz pair of ``material``'s sphere on the stage's counter-body (the rigid flat: None)."""
    return material.pair() if counter is None else counter.counter_body(material).pair(material.material(), material.R)


class HertzStage(_Table):
    """Elastic loading from P_min to P_max [N] (or P_max_over_P_Y x P_Y) in ``steps`` loads."""

    counter: SceneCounter | None = None
    P_max: Positive | None = None
    P_max_over_P_Y: Ratio | None = None
    P_min: Positive | None = None
    steps: Annotated[int, Strict(), Field(ge=2, le=1000)] = 25

    @model_validator(mode="after")
    def _one_top(self):
        if self.P_max is not None and self.P_max_over_P_Y is not None:
            raise ValueError("give P_max or P_max_over_P_Y, not both")
        return self

    def loads(self, pair) -> tuple[float, float]:
        top = self.P_max if self.P_max is not None else (self.P_max_over_P_Y or limits.DEFAULT_WINDOW) * pair.P_Y
        return (self.P_min if self.P_min is not None else top / 1000.0), top


class LoadPathStage(_Table):
    """Load paths to each P_max [N] (or P_max_over_P_Y x P_Y), unloaded unless ``unload`` is false."""

    P_max: _list_of(Positive) | None = None
    P_max_over_P_Y: _list_of(Ratio) | None = None
    unload: Flag = True
    loading_steps: Annotated[int, Strict(), Field(ge=2, le=10000)] = 48
    unloading_steps: Annotated[int, Strict(), Field(ge=2, le=1000)] = 16

    @model_validator(mode="after")
    def _one_peak_list(self):
        if self.P_max is not None and self.P_max_over_P_Y is not None:
            raise ValueError("give P_max or P_max_over_P_Y, not both")
        return self

    def peaks(self, pair) -> tuple[float, ...]:
        if self.P_max is not None:
            return tuple(sorted(self.P_max))
        ratios = self.P_max_over_P_Y if self.P_max_over_P_Y is not None else DEFAULT_PEAKS_OVER_YIELD
        return tuple(sorted(k * pair.P_Y for k in ratios))


class _Velocities(_Table):
    """Impact velocities: v_in [m/s] or v_in_over_v_Y (x v_Y)."""

    v_in: _list_of(Positive) | None = None
    v_in_over_v_Y: _list_of(Ratio) | None = None

    @model_validator(mode="after")
    def _one_velocity_list(self):
        if (self.v_in is None) == (self.v_in_over_v_Y is None):
            raise ValueError("give exactly one of v_in [m/s] or v_in_over_v_Y")
        return self

    def velocities(self, pair) -> tuple[float, ...]:
        return self.v_in if self.v_in is not None else tuple(k * pair.v_Y for k in self.v_in_over_v_Y)


class CollisionStage(_Velocities):
    """Impacts at v_in [m/s] (or v_in_over_v_Y x v_Y) with each of ``laws``."""

    laws: _list_of(Law) = ("vz", "thornton", "hertz")


class ImpactStage(_Velocities):
    """Dynamic FE impacts at v_in [m/s] (or v_in_over_v_Y x v_Y): calib.studies.impact."""

    counter: SceneCounter | None = None
    error_estimate: Flag = True
    quasi_static: Flag = True
    steps_per_contact: Annotated[int, Strict(), Field(ge=10, le=10000)] = 100


class Outputs(_Table):
    out: Annotated[str, Field(min_length=1)] | None = None
    plots: Flag = False
    vtu: Flag = False
    histories: Flag = True


# ----------------------------------------------------------------------------- the file
class _Head(_Table):
    name: Name | None = None     # default: the file's stem
    description: str = ""


class _Grid(_Table):
    nu: _list_of(PoissonRatio)
    E_over_sigma_y: _list_of(Annotated[Number, Field(gt=1)])
    sigma_y: Positive
    rho: Positive
    R: Positive


class _Calibration(_Hardening):
    ship: Literal["radius", "force", "table"] = "radius"
    v_max: Positive | None = None                     # [m/s]: the window covers impacts up to it
    v_max_from: Literal["collision"] | None = None    # ... or up to the [collision] stage's fastest
    counter: SceneCounter | None = None

    @model_validator(mode="after")
    def _one_v_max(self):
        if self.v_max is not None and self.v_max_from is not None:
            raise ValueError("give v_max or v_max_from, not both")
        if self.counter is not None and (self.v_max is not None or self.v_max_from is not None):
            raise ValueError("the impact window (v_max, v_max_from) is sized for the rigid flat: on a counter-body "
                             "give the load paths' P_max in [load_paths]")
        return self


class SceneFile(_Table):
    """The TOML document as written (sections and keys); ``parse_scene`` turns it into a Scene."""

    scene: _Head = _Head()
    mesh: MeshChoice = MeshChoice()
    material: _list_of(SceneMaterial) | None = None
    grid: _Grid | None = None
    hertz: HertzStage | None = None
    load_paths: LoadPathStage | None = None
    calibration: _Calibration | None = None
    collision: CollisionStage | None = None
    impact: ImpactStage | None = None
    outputs: Outputs = Outputs()

    @model_validator(mode="before")
    @classmethod
    def _material_tables(cls, data):
        """One [material] table is a list of one; an unnamed material is material<k>."""
        if isinstance(data, dict) and "material" in data:
            entries = data["material"]
            entries = [entries] if isinstance(entries, dict) else entries
            if isinstance(entries, list):
                entries = [{"name": f"material{k}", **e} if isinstance(e, dict) else e for k, e in enumerate(entries)]
            data = {**data, "material": entries}
        return data

    @model_validator(mode="after")
    def _consistent(self):
        if self.material is not None and self.grid is not None:
            raise ValueError("grid: give either [[material]] tables or a [grid], not both")
        if self.material is None and self.grid is None:
            raise ValueError("material: missing: give [[material]] tables or a [grid]")
        if self.material is not None and len({m.name for m in self.material}) != len(self.material):
            raise ValueError("material.name: names must be unique")
        if (self.calibration is not None and self.calibration.ship in ("force", "table")
                and self.load_paths is not None and not self.load_paths.unload):
            raise ValueError(f"calibration.ship: {self.calibration.ship!r} fits the unloading too: needs "
                             f"load_paths.unload = true")
        if (self.collision is not None and "vz-table" in self.collision.laws
                and (self.calibration is None or (self.load_paths is not None and not self.load_paths.unload))):
            raise ValueError("collision.laws: 'vz-table' takes its tables from this scene's FE: needs a "
                             "[calibration] stage with load_paths.unload = true")
        if (self.hertz is None and self.load_paths is None and self.calibration is None and self.collision is None
                and self.impact is None):
            raise ValueError("scene: nothing to run: add [hertz], [load_paths], [calibration], [collision] or [impact]")
        if self.calibration is not None and self.calibration.counter is not None and self.collision is not None:
            raise ValueError("collision: the laws of [collision] are the rigid flat's; with calibration.counter "
                             "run the pair's impacts by [impact] with an [impact.counter] table")
        if self.calibration is not None and self.calibration.v_max_from == "collision" and self.collision is None:
            raise ValueError("calibration.v_max_from: 'collision' needs a [collision] stage")
        if (self.calibration is not None and (self.calibration.v_max or self.calibration.v_max_from)
                and self.load_paths is not None and (self.load_paths.P_max or self.load_paths.P_max_over_P_Y)):
            raise ValueError("calibration.v_max: sets the load paths' P_max: do not give load_paths.P_max too")
        return self


@dataclass(frozen=True)
class Scene:
    """A validated scene (see the module docstring)."""

    name: str
    materials: tuple[SceneMaterial, ...]
    mesh: MeshChoice = MeshChoice()
    hertz: HertzStage | None = None
    load_paths: LoadPathStage | None = None
    calibration_ship: str | None = None   # None: no calibration
    calibration_v_max: float | None = None      # [m/s]: the window from the impacts (impact_window)
    calibration_v_max_from_collision: bool = False
    calibration_counter: SceneCounter | None = None
    collision: CollisionStage | None = None
    impact: ImpactStage | None = None
    outputs: Outputs = Outputs()
    description: str = ""
    source: str = ""
    is_grid: bool = False
    hardening: tuple = ()       # (material name, calib.fe.flow_curve FlowCurve) of each hardening sphere

    def flow_curve(self, material):
        """The FlowCurve of ``material``'s sphere, None when perfectly plastic."""
        return dict(self.hardening).get(material.name)

    def out_dir(self, override: str | Path | None = None) -> Path:
        if override is not None:
            return Path(override)
        return Path(self.outputs.out) if self.outputs.out else output.RESULTS / "scenes" / self.name

    def v_max(self, material) -> float | None:
        """The impact velocity [m/s] the calibration window of ``material`` must cover, if any."""
        if self.calibration_v_max is not None:
            return self.calibration_v_max
        if self.calibration_v_max_from_collision and self.collision is not None:
            return max(self.collision.velocities(material.pair()))
        return None

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
        if self.impact is not None:
            names.append("impact")
        return names


# ----------------------------------------------------------------------------- parsing
def parse_scene(data: dict, source: str = "<scene>") -> Scene:
    """Validate the TOML data of a scene into a Scene (SceneError on any problem)."""
    try:
        file = SceneFile.model_validate(data)
    except ValidationError as exc:
        raise SceneError(one_line(exc, source, SceneFile)) from None

    name = file.scene.name if file.scene.name is not None else Path(source).stem
    try:
        _check_name(name)
    except ValueError as exc:
        raise SceneError(f"scene {source}: scene.name: {exc}") from None

    if file.grid is not None:
        grid = file.grid
        materials = tuple(SceneMaterial(name=f"nu{nu:g}_E{ratio:g}sy", E=ratio * grid.sigma_y, nu=nu,
                                        sigma_y=grid.sigma_y, rho=grid.rho, R=grid.R)
                          for nu in grid.nu for ratio in grid.E_over_sigma_y)
    else:
        materials = file.material

    # each counter-body checked under each sphere (calib.fit.counter.CounterBody's ranges)
    for stage in ("hertz", "calibration", "impact"):
        counter = getattr(getattr(file, stage), "counter", None)
        for m in materials if counter is not None else ():
            try:
                body = counter.counter_body(m)
                if stage != "hertz":        # the pair's m* enters the parameter file and the impact
                    body.require_density("rho")
            except ValueError as exc:
                raise SceneError(f"scene {source}: {stage}.counter: {exc}") from None
    # rules that need each material's contact physics (P_Y)
    if file.hertz is not None:
        for m in materials:
            low, top = file.hertz.loads(stage_pair(m, file.hertz.counter))
            if not top > low:
                raise SceneError(f"scene {source}: hertz.P_min: must be < P_max = {top:g} N, got {low:g}")
    load_paths = file.load_paths
    if file.calibration is not None:
        load_paths = load_paths or LoadPathStage()
        for m in materials:
            pair = stage_pair(m, file.calibration.counter)
            P_Y = pair.P_Y
            peaks = load_paths.peaks(pair)
            if file.calibration.v_max is not None or file.calibration.v_max_from is not None:
                continue                # the load paths come from the impacts (checked when planned)
            if not max(peaks) > 2 * P_Y:
                raise SceneError(f"scene {source}: load_paths.P_max: calibration needs loads above P_Y: the largest "
                                 f"P_max must be > 2 P_Y = {2 * P_Y:.4g} N for material {m.name!r}, got {max(peaks):.4g} N")
    hardening = _hardening(file, materials, source)
    _check_rate_laws(file, materials, hardening, source)
    return Scene(name=name, materials=materials, mesh=file.mesh, hertz=file.hertz, load_paths=load_paths,
                 calibration_ship=None if file.calibration is None else file.calibration.ship,
                 calibration_v_max=None if file.calibration is None else file.calibration.v_max,
                 calibration_v_max_from_collision=file.calibration is not None and file.calibration.v_max_from == "collision",
                 calibration_counter=None if file.calibration is None else file.calibration.counter,
                 collision=file.collision, impact=file.impact, outputs=file.outputs, description=file.scene.description,
                 source=source, is_grid=file.grid is not None, hardening=hardening)


def _hardening(file: SceneFile, materials, source: str) -> tuple:
    """(name, FlowCurve) of each hardening sphere of the scene, each entry checked before any work."""
    scene_wide = file.calibration is not None and file.calibration.hardening_given()
    folder = Path(source).parent
    out = []
    for k, m in enumerate(materials):
        if scene_wide and m.hardening_given():
            raise SceneError(f"scene {source}: material[{k}].{next(key for key in HARDENING_KEYS if getattr(m, key) is not None)}"
                             f": the hardening is given in [calibration] too: give it in one place")
        entry, where = (file.calibration, "calibration") if scene_wide else (m, f"material[{k}]")
        try:
            curve = flow_curve_of(entry, m.sigma_y, m.E, folder)
        except ValueError as exc:
            raise SceneError(f"scene {source}: {where}.{exc}") from None
        if curve is not None:
            out.append((m.name, curve))
    if out and file.impact is not None and file.impact.counter is not None:
        raise SceneError(f"scene {source}: impact.counter: the two-body impact FE is of perfectly plastic spheres: "
                         f"drop the hardening or the [impact.counter] table")
    if out and file.calibration is None and file.collision is not None and "vz" in file.collision.laws:
        raise SceneError(f"scene {source}: collision.laws: 'vz' without a [calibration] takes the master table's "
                         f"constants, a perfectly plastic sphere's, and {out[0][0]!r} hardens: add a [calibration] "
                         f"stage (its FE calibrates the hardening sphere)")
    return tuple(out)


def _check_rate_laws(file: SceneFile, materials, hardening: tuple, source: str) -> None:
    """Refuse, in one line naming the key, a rate law where a stage cannot carry it: the two-body FE (impact or
    calibration on a counter-body) and the collision laws other than the rate-aware vz and vz-table (and the
    elastic Hertz), and a hardening sphere's collisions (the rate-aware law is measured on perfect plasticity)."""
    hardens = {name for name, _ in hardening}
    for k, m in enumerate(materials):
        if m.rate_law is None:
            continue
        key = f"scene {source}: material[{k}].rate_law"
        for stage in ("calibration", "impact"):
            if getattr(getattr(file, stage), "counter", None) is not None:
                raise SceneError(f"{key}: the two-body FE of [{stage}.counter] is of rate-independent spheres: drop "
                                 f"the rate law or the [{stage}.counter] table")
        if file.collision is None:
            continue
        other = [law for law in file.collision.laws if law not in ("vz", "vz-table", "hertz")]
        if other:
            raise SceneError(f"{key}: the rate-aware law scales sigma_Y of vz and vz-table: collision.laws must be "
                             f"vz, vz-table or hertz (elastic) with a rate law, got {other[0]!r}")
        if m.name in hardens:
            raise SceneError(f"{key}: the rate-aware law is measured on perfectly plastic spheres and {m.name!r} "
                             f"hardens: drop the [collision] stage (the [impact] FE takes both)")


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

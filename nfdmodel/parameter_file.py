"""The calibrated parameter file (JSON, written by ``nfdcal calibrate``), read into VZParams.

Format (the record ``parameter_record`` builds):
    {"law": "vz", "Ca": m/N, "Kc": 1/N, "Ca_hat": -, "Kc_hat": -, "P_Y": N, "a_Y": m,
     "delta_Y": m, "material": {"E": Pa, "nu": -, "sigma_y": Pa, "rho": kg/m^3, "R": m},
     "window": {"P_min_over_P_Y": -, "P_max_over_P_Y": -, "a_max_over_R": -, "source": text}, ...}
The vz-table law ("law": "vz-table") states its nodes instead of Ca, Kc:
    "table": {"P_over_P_Y": [-], "a_p_over_a_Y": [-], "C_R": [-]}
and the vz-unload law ("law": "vz-unload", nfdmodel.vz_unload) the same "table" and its unloading
nodes over the turning point x_m = P_max/P_Y:
    "unloading": {"P_max_over_P_Y": [-], "dent": [delta_res/delta_max], "exponent": [m]}
A vz or vz-table file may state the strain-rate dependence of the sphere's flow stress, the rate-aware
law on its law (nfdmodel.rate_aware, nfdmodel.strain_rate; ``nfdcal collide --params`` runs it, ``nfdcal
export lammps`` writes the plugin's ``rate`` keyword):
    "rate_law": {"rate_law": "johnson-cook", "C": -, "reference_rate": 1/s, "c": -}
              | {"rate_law": "cowper-symonds", "D": 1/s, "q": -, "c": -}
("c" of eps_dot = v_n0 / (c a_ref) optional, default RATE_LENGTH_FACTOR; "reference_rate" optional, 1 /s;
"form" optional, "fixed" (R fixed at first contact, nfdmodel.rate_aware) or "relaxing" (the factor follows the
strain rate, nfdmodel.rate_relaxing, with "k" its element stiffness; c and k default to that law's)).
A calibration against a deformable counter-body (``nfdcal calibrate --counter-E ...``) also states it:
    "counter_body": {"shape": "flat" | "sphere", "E": Pa, "nu": -, "sigma_y": Pa | null, "R": m | null,
                     "rho": kg/m^3 | null}
and the pair (E*, R*, the yield point, m*) is ContactPair.sphere_counter's; absent or null: a rigid flat.
A counter-sphere needs its "rho" (the pair's reduced mass m* = m1 m2 / (m1 + m2)); a flat's is
not part of m* (null: the sphere's). "mass_star" [kg] states m*, checked like P_Y.
Written by a calibration, also the estimated relative discretisation errors (``ERROR_KEYS``:
numbers >= 0, or null for one mesh) and how they were obtained ("discretisation").
Only law, material and the law's own keys (Ca, Kc; table; table and unloading) are needed; a file
without "window" (written before windows were recorded) is read with the default recipe's window,
1..41.2 P_Y, and a RangeWarning saying so; any other key must be one of ``KEYS`` (a typo is named,
never ignored), every number a JSON number (a string is refused); P_Y, a_Y, delta_Y, mass_star,
Ca_hat, Kc_hat, when present, must agree with the values recomputed here (relative 1e-4),
so a stale or hand-edited file is caught.
"""
from __future__ import annotations

import json
import math
import warnings
from dataclasses import dataclass
from pathlib import Path
from types import SimpleNamespace

from .materials import ContactPair, Material
from .vz import VZParams
from .validation import PlausibilityWarning
from .vz_table import VZTableParams
from .vz_unload import VZUnloadParams
from .window import CalibrationWindow, RangeWarning

_CONSISTENCY = 1e-4
# the estimated relative discretisation errors of the FE calibration (two meshes, Richardson
# extrapolation; null for a one-mesh calibration): each a number >= 0 [-] or null
ERROR_KEYS = ("Ca_rel_error_estimate", "Kc_rel_error_estimate", "Ca_hat_rel_error_estimate",
              "Kc_hat_rel_error_estimate", "table_rel_error_estimate", "e_rel_error_estimate",
              "alpha_rel_error_estimate")
# the keys a parameter file may hold: what parameter_record writes, and what nfdcal adds around it
# ("hardening": the sphere's flow curve the FE calibrated, absent for perfect plasticity; the law's
# constants carry it, the runtime reads nothing of it)
KEYS = ("law", "Ca", "Kc", "Ca_hat", "Kc_hat", "table", "unloading", "P_Y", "a_Y", "delta_Y", "mass_star", "material", "counter_body", "window",
        "units", "fit", "fe_errors", "mesh", "stamp") + ERROR_KEYS + ("discretisation", "hardening", "rate_law")
TABLE_KEYS = ("P_over_P_Y", "a_p_over_a_Y", "C_R")     # the vz-table law: nodes x, f, g
UNLOADING_KEYS = ("P_max_over_P_Y", "dent", "exponent")  # the vz-unload law: nodes x_unload, dent, exponent
LAWS = ("vz", "vz-table", "vz-unload")                   # the laws a parameter file may ship
MATERIAL_KEYS = ("E", "nu", "sigma_y", "rho", "R")
# the deformable counter-body the constants were calibrated against (absent or null: a rigid flat):
# shape "flat" or "sphere", E [Pa], nu, sigma_y [Pa] (null: elastic), R [m] (null: a flat); and
# COUNTER_DENSITY, rho [kg/m^3], required for a sphere (null or absent for a flat: the sphere's)
COUNTER_KEYS = ("shape", "E", "nu", "sigma_y", "R")
COUNTER_DENSITY = "rho"
# the "rate_law" entry: its keys per rate law (nfdmodel.strain_rate's record) and c of the rate-aware law
RATE_LAW_KEYS = {"johnson-cook": ("rate_law", "C", "reference_rate", "c", "form", "k"),
                 "cowper-symonds": ("rate_law", "D", "q", "c", "form", "k")}
RATE_BASE_LAWS = ("vz", "vz-table")                      # the laws whose constants scale with sigma_Y


def law_of(params) -> str:
    """The name of the law a parameter file's parameters are for: "vz-unload", "vz-table" or "vz"."""
    if isinstance(params, VZUnloadParams):
        return "vz-unload"
    return "vz-table" if isinstance(params, VZTableParams) else "vz"


def rate_law_entry(rate_params) -> dict:
    """The "rate_law" entry of a parameter file whose law is ``rate_params``' base law: the record of the
    rate-aware RateAwareParams or RelaxingRateParams (nfdmodel.rate_relaxing.rate_form_law) without its base
    law, which the file's own law states."""
    entry = rate_params.record()
    entry.pop("base_law")
    return entry


def stated_rate_law(params, rate_record: dict, form: str) -> dict:
    """The "rate_law" entry of the parameter file of ``params`` (a vz or vz-table law) for a sphere of the rate
    law ``rate_record`` (nfdmodel.strain_rate's record), run as the rate-aware law of ``form``."""
    from .rate_relaxing import rate_form_law
    from .strain_rate import rate_law_of

    return rate_law_entry(rate_form_law(form, law_of(params), params, rate_law_of(rate_record))[1])


def parameter_record(params: VZParams | VZTableParams | VZUnloadParams, R: float, material: Material,
                     counter: dict | None = None, rate_law: dict | None = None) -> dict:
    """The core of a parameter file for ``params`` (sphere of radius R [m] on a rigid flat, or on
    the deformable ``counter`` body, a COUNTER_KEYS record): the vz constants, the vz-table law's
    nodes, or the vz-unload law's nodes and unloading nodes; ``rate_law``: the "rate_law" entry
    (a JohnsonCook or CowperSymonds record, with "c" when not the default)."""
    pair = params.pair
    if isinstance(params, VZTableParams):
        law = {"law": law_of(params), "table": {"P_over_P_Y": list(params.x), "a_p_over_a_Y": list(params.f),
                                            "C_R": list(params.g)}}
        if isinstance(params, VZUnloadParams):
            law.update(unloading={"P_max_over_P_Y": list(params.x_unload), "dent": list(params.dent),
                                                   "exponent": list(params.exponent)})
    else:
        law = {"law": "vz", "Ca": params.Ca, "Kc": params.Kc, "Ca_hat": params.Ca_hat, "Kc_hat": params.Kc_hat}
    return {**law, "P_Y": pair.P_Y, "a_Y": pair.a_Y, "delta_Y": pair.delta_Y, "mass_star": pair.mass_star,
            "material": {"E": material.E, "nu": material.nu, "sigma_y": material.sigma_y,
                         "rho": material.rho, "R": R},
            **({"counter_body": dict(counter)} if counter is not None else {}),
            **({"rate_law": dict(rate_law)} if rate_law is not None else {}),
            **({"window": params.window.record()} if params.window is not None else {}),
            "units": {"Ca": "m/N", "Kc": "1/N", "P_Y": "N", "a_Y": "m", "delta_Y": "m", "E": "Pa",
                      "sigma_y": "Pa", "rho": "kg/m^3", "R": "m", "mass_star": "kg"}}


def _check_keys(path, data: dict, allowed: tuple, where: str) -> None:
    """ValueError naming every key of ``data`` that is not ``allowed`` (a typo is never ignored)."""
    unknown = [key for key in data if key not in allowed]
    if unknown:
        raise ValueError(f"parameter file {path}: unknown key(s){where}: "
                         f"{', '.join(map(repr, unknown))}; allowed: {', '.join(allowed)}")


def _check_object(path, value, keys, name: str, alternative: str = "", optional: tuple = ()) -> None:
    """ValueError naming the file and ``name`` unless ``value`` is an object with exactly ``keys``
    (and any of ``optional``)."""
    if not isinstance(value, dict):
        raise ValueError(f"parameter file {path}: '{name}' must be an object with {', '.join(keys)}{alternative}, "
                         f"got {value!r}")
    _check_keys(path, value, keys + optional, f" in '{name}'")
    missing = [k for k in keys if k not in value]
    if missing:
        raise ValueError(f"parameter file {path}: {name}: missing key(s) {', '.join(missing)}")


def _pair(path, material: Material, R, counter) -> ContactPair:
    """The contact pair of the file: the sphere on a rigid flat, or on its counter-body."""
    if counter is None:
        return ContactPair.sphere_flat(material, R)
    _check_object(path, counter, COUNTER_KEYS, "counter_body", " or null", (COUNTER_DENSITY,))
    if counter["shape"] != ("flat" if counter["R"] is None else "sphere"):
        raise ValueError(f"counter_body: shape must be 'flat' (R null) or 'sphere' (R a radius), got "
                         f"{counter['shape']!r} with R = {counter['R']!r}")
    rho = counter.get(COUNTER_DENSITY)
    if counter["shape"] == "sphere" and rho is None:
        raise ValueError(f"parameter file {path}: counter_body.rho missing: a counter-sphere's density [kg/m^3] sets "
                         f"the pair's m* = m1 m2 / (m1 + m2)")
    return ContactPair.sphere_counter(material, R, counter["E"], counter["nu"], counter["sigma_y"], counter["R"], rho)


def load_parameters(path) -> VZParams | VZTableParams | VZUnloadParams:
    """VZParams (law "vz"), VZTableParams (law "vz-table") or VZUnloadParams (law "vz-unload") for
    the pair described by the JSON parameter file at ``path``: the sphere on a rigid flat, or on
    its "counter_body".

    Raises FileNotFoundError if the file is missing, ValueError naming the key for a corrupted
    file, a missing or out-of-range value, or derived values inconsistent with the material.
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"parameter file not found: {path}")
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ValueError(f"parameter file {path} is not valid JSON: {exc}") from None
    if not isinstance(data, dict):
        raise ValueError(f"parameter file {path}: expected a JSON object at the top level")
    _check_keys(path, data, KEYS, "")
    for key in ERROR_KEYS:
        value = data.get(key)
        if value is not None and (not isinstance(value, (int, float)) or isinstance(value, bool)
                                  or not math.isfinite(value) or value < 0):
            raise ValueError(f"parameter file {path}: {key} must be a number >= 0 or null, got {value!r}")
    law = data.get("law", "vz")
    if law not in LAWS:
        raise ValueError(f"parameter file {path}: law must be one of {', '.join(map(repr, LAWS))}, got {law!r}")
    material_data = data.get("material")
    if not isinstance(material_data, dict):
        raise ValueError(f"parameter file {path}: missing 'material' object (E, nu, sigma_y, rho, R)")
    _check_keys(path, material_data, MATERIAL_KEYS, " in 'material'")
    missing = [k for k in MATERIAL_KEYS if k not in material_data]
    missing += [k for k in {"vz": ("Ca", "Kc"), "vz-table": ("table",), "vz-unload": ("table", "unloading")}[law]
                if k not in data]
    if missing:
        raise ValueError(f"parameter file {path}: missing key(s) {', '.join(missing)}")
    if law != "vz":
        _check_object(path, data["table"], TABLE_KEYS, "table")
    if law == "vz-unload":
        _check_object(path, data["unloading"], UNLOADING_KEYS, "unloading")
    elif "unloading" in data:
        raise ValueError(f"parameter file {path}: 'unloading' belongs to law 'vz-unload', not {law!r}")
    if "window" in data:
        try:
            window = CalibrationWindow.from_record(data["window"])
        except ValueError as exc:
            raise ValueError(f"parameter file {path}: {exc}") from None
    else:
        window = CalibrationWindow.assumed_default()
    with warnings.catch_warnings(record=True) as noted:
        warnings.simplefilter("always", PlausibilityWarning)
        try:
            material = Material(material_data["E"], material_data["nu"], material_data["sigma_y"],
                                material_data["rho"])
            pair = _pair(path, material, material_data["R"], data.get("counter_body"))
            if law == "vz":
                params = VZParams(pair, data["Ca"], data["Kc"], window)
            elif law == "vz-table":
                table = data["table"]
                params = VZTableParams(pair, table["P_over_P_Y"], table["a_p_over_a_Y"], table["C_R"],
                                       window if "window" in data else None)
            else:
                table, unloading = data["table"], data["unloading"]
                params = VZUnloadParams(pair, table["P_over_P_Y"], table["a_p_over_a_Y"], table["C_R"],
                                        window if "window" in data else None, unloading["P_max_over_P_Y"],
                                        unloading["dent"], unloading["exponent"])
        except ValueError as exc:
            # an implausible value (R = 100: millimetres?) is the likely cause: name it in the error
            hints = "; ".join(str(w.message) for w in noted if issubclass(w.category, PlausibilityWarning))
            raise ValueError(f"parameter file {path}: {exc}" + (f" (note: {hints})" if hints else "")) from None
    for note in noted:
        warnings.warn_explicit(note.message, note.category, note.filename, note.lineno)
    derived = {"P_Y": params.pair.P_Y, "a_Y": params.pair.a_Y, "delta_Y": params.pair.delta_Y,
               "mass_star": params.pair.mass_star}
    if law == "vz":
        derived.update(Ca_hat=params.Ca_hat, Kc_hat=params.Kc_hat)
    elif "Ca" in data or "Kc" in data:
        raise ValueError(f"parameter file {path}: law {law!r} takes its 'table', not Ca/Kc")
    for key, value in derived.items():
        if key in data:
            stored = data[key]
            if not isinstance(stored, (int, float)) or isinstance(stored, bool) or not math.isfinite(stored):
                raise ValueError(f"parameter file {path}: {key} must be a finite number, got {stored!r}")
            if abs(stored - value) > _CONSISTENCY * abs(value):
                raise ValueError(f"parameter file {path}: {key} = {stored:g} disagrees with "
                                 f"{value:g} recomputed from the material (relative tolerance "
                                 f"{_CONSISTENCY:g})")
    if "rate_law" in data:
        _rate_law(path, data["rate_law"], law)
    if "window" not in data and law == "vz":   # said once the file is known to be good (one line for a bad one)
        warnings.warn(f"parameter file {path} states no calibrated window (written before windows were "
                      f"recorded): assuming {window.describe()}, the default recipe's", RangeWarning, stacklevel=2)
    return params


@dataclass(frozen=True)
class StatedRate:
    """A parameter file's "rate_law" entry: the rate law (a JohnsonCook or CowperSymonds), its form
    ("fixed" or "relaxing"), c and k (None: the form's default; k only for "relaxing")."""

    rate_law: object
    form: str = "fixed"
    c: float | None = None
    k: float | None = None

    def law(self, base_law: str, base):
        """(ContactLaw, parameters) of this rate-aware law on ``base`` (nfdmodel.rate_relaxing.rate_form_law)."""
        from .rate_relaxing import rate_form_law

        return rate_form_law(self.form, base_law, base, self.rate_law, self.c, self.k)


def _rate_law(path, entry, law: str) -> StatedRate:
    """The StatedRate of a file's "rate_law" entry, or a ValueError naming the file and key."""
    from .rate_relaxing import RATE_FORMS
    from .strain_rate import rate_law_of
    from .validation import check_real

    if law not in RATE_BASE_LAWS:
        raise ValueError(f"parameter file {path}: rate_law needs a law whose constants scale with sigma_Y "
                         f"({', '.join(RATE_BASE_LAWS)}), not {law!r}")
    kind = entry.get("rate_law") if isinstance(entry, dict) else None
    if kind not in RATE_LAW_KEYS:
        raise ValueError(f"parameter file {path}: rate_law must be an object with rate_law one of "
                         f"{', '.join(RATE_LAW_KEYS)}, got {entry!r}")
    _check_keys(path, entry, RATE_LAW_KEYS[kind], " in 'rate_law'")
    form = entry.get("form", "fixed")
    if form not in RATE_FORMS:
        raise ValueError(f"parameter file {path}: rate_law.form must be one of {', '.join(RATE_FORMS)}, got {form!r}")
    for key, value in entry.items():
        if key not in ("rate_law", "form") and (not isinstance(value, (int, float)) or isinstance(value, bool)):
            raise ValueError(f"parameter file {path}: rate_law.{key} must be a number, got {value!r}")
    if "k" in entry and form != "relaxing":
        raise ValueError(f"parameter file {path}: rate_law.k is the relaxing law's element stiffness: give "
                         f"\"form\": \"relaxing\" or no k")
    try:
        c = None if "c" not in entry else check_real("c", entry["c"], low=0.0, unit="(eps_dot = v_n0 / (c a_ref))")
        k = None if "k" not in entry else check_real("k", entry["k"], low=0.0, unit="(the element's stiffness)")
        return StatedRate(rate_law_of(entry), form, c, k)
    except ValueError as exc:
        raise ValueError(f"parameter file {path}: rate_law: {exc}") from None


def rate_law_of_file(path) -> StatedRate | None:
    """The rate-aware law the parameter file at ``path`` states (its "rate_law" entry as a StatedRate), None
    when it states none; load_parameters checks the entry."""
    data = json.loads(Path(path).read_text(encoding="utf-8"))
    if not isinstance(data, dict) or "rate_law" not in data:
        return None
    return _rate_law(path, data["rate_law"], data.get("law", "vz"))


def elastic_bodies(path) -> tuple[SimpleNamespace, SimpleNamespace | None]:
    """(sphere, counter-body) of the parameter file at ``path`` (load_parameters checks it), each with
    its Young's modulus E [Pa] and Poisson's ratio nu [-]; counter-body None: a rigid flat. What a
    model of the two materials reads (the Mindlin coefficient k_t = 8 G*, nfdmodel.friction)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")            # said once, by the caller's own load_parameters
        load_parameters(path)
    data = json.loads(Path(path).read_text(encoding="utf-8"))
    counter = data.get("counter_body")
    sphere = SimpleNamespace(E=float(data["material"]["E"]), nu=float(data["material"]["nu"]))
    return sphere, None if counter is None else SimpleNamespace(E=float(counter["E"]), nu=float(counter["nu"]))

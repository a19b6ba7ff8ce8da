"""Reading a vz master scene (calib/scenes/builtin/sweeps/*.toml, or a .toml path): its [vz_master] grid of nu and
E/sigma_Y (and H/E for a hardening sheet), the graded mesh of its nodes, its off-grid [[check]] materials (a linear
hardening or a Swift or Ludwik flow curve) and its [[refine]] ladders (LADDERS), each field checked with a ValueError
naming it. What the scene computes: calib.fit.vz_master_build.
"""
from __future__ import annotations

import tomllib
from pathlib import Path

from calib.fe.flow_curve import LudwikHardening, SwiftHardening
from calib.fe.kinematics import DEFAULT_KINEMATICS
from calib.fit import impact_window, recipe

BUILTIN = Path(__file__).resolve().parent.parent / "scenes" / "builtin" / "sweeps"   # not scenes of the schema
X_LIMIT = recipe.MAX_LOAD_OVER_YIELD     # the common loads reach the FE's reach in P/P_Y
# The lowest unloading path of a node [P_Y] (impact_window.window_spec's lowest_over_P_Y): the shipped
# table's nodes start there (calibrations start at impact_window.LOWEST_PEAK_OVER_P_Y)
TABLE_LOWEST_PEAK_OVER_P_Y = 2.0
# the largest hardening of a sheet's sphere: the plastic modulus H of sigma_y = sigma_Y + H eps_p over E
MAX_H_OVER_E = 0.2


def is_vz_master_scene(name: str) -> bool:
    """Whether ``name`` (a built-in scene name or a .toml path) is a vz master-table scene."""
    path = scene_path(name)
    if path is None:
        return False
    try:
        return "vz_master" in tomllib.loads(path.read_text(encoding="utf-8"))
    except (OSError, tomllib.TOMLDecodeError):
        return False


def scene_path(name: str) -> Path | None:
    path = Path(name)
    if path.suffix == ".toml" and path.is_file():
        return path
    builtin = BUILTIN / f"{name}.toml"
    return builtin if builtin.is_file() else None


def load_scene(name: str) -> dict:
    """The scene's [vz_master] grid and [[check]] materials (ValueError naming a bad field)."""
    path = scene_path(name)
    if path is None:
        raise ValueError(f"scene not found: {name!r}")
    raw = tomllib.loads(path.read_text(encoding="utf-8"))
    grid = raw.get("vz_master", {})
    scene = {"name": raw.get("scene", {}).get("name", path.stem), "source": str(path),
             "nu": [float(v) for v in grid.get("nu", [])],
             "E_over_sigma_y": [float(v) for v in grid.get("E_over_sigma_y", [])],
             "sigma_y": float(grid.get("sigma_y", 100e6)), "rho": float(grid.get("rho", 2700.0)),
             "R": float(grid.get("R", 0.1)), "level": str(grid.get("level", "default")),
             "contact_size_over_a_max": (float(grid["contact_size_over_a_max"]) if "contact_size_over_a_max" in grid
                                         else None),
             "graded": ({"elements_per_contact_radius": float(grid["elements_per_contact_radius"]),
                         "loading_steps_per_decade": float(grid["loading_steps_per_decade"]),
                         "refinement": float(grid.get("refinement", 1.0))}
                        if "elements_per_contact_radius" in grid else None),
             "top_over_P_Y": float(grid.get("top_over_P_Y", X_LIMIT)),
             "check_top_over_P_Y": float(grid.get("check_top_over_P_Y", grid.get("top_over_P_Y", X_LIMIT))),
             "meshes": int(grid.get("meshes", 2)), "check_meshes": int(grid.get("check_meshes", 1)),
             "kinematics": str(grid.get("kinematics", DEFAULT_KINEMATICS)),
             "joins": (str(grid["joins"]) if "joins" in grid else None),
             "lowest_a_over_R": (float(grid["lowest_a_over_R"]) if "lowest_a_over_R" in grid else None),
             "lowest_max_over_P_Y": float(grid.get("lowest_max_over_P_Y", TABLE_LOWEST_PEAK_OVER_P_Y)),
             "H_over_E": [float(v) for v in grid.get("H_over_E", [0.0])],
             "checks": [{"name": str(c["name"]), "nu": float(c["nu"]), "E_over_sigma_y": float(c["E_over_sigma_y"]),
                         "H_over_E": float(c.get("H_over_E", 0.0)), "power_law": power_law_of(c, path),
                         "top_over_P_Y": float(c.get("top_over_P_Y", grid.get("check_top_over_P_Y",
                                                                             grid.get("top_over_P_Y", X_LIMIT))))}
                        for c in raw.get("check", [])],
             "refine": [level for k, c in enumerate(raw.get("refine", [])) for level in refine_levels(c, path, k)]}
    # a hardening sheet (H_over_E beside 0) may hold one nu: the hardening's share of the tables is measured
    # at it and checked at other nu (calib.fit.vz_hardening)
    for axis in ("E_over_sigma_y", "H_over_E") if is_hardening_sheet(scene) else ("nu", "E_over_sigma_y"):
        if len(scene[axis]) < 2:
            raise ValueError(f"scene {path}: [vz_master] {axis} needs at least 2 values")
    for value in scene["H_over_E"] + [c["H_over_E"] for c in scene["checks"]]:
        if not 0.0 <= value <= MAX_H_OVER_E:
            raise ValueError(f"scene {path}: H_over_E must be in [0, {MAX_H_OVER_E:g}], got {value:g}")
    for refine in scene["refine"] + ([scene["graded"]] if scene["graded"] else []):
        if "nu" in refine and (refine["nu"] not in scene["nu"]
                               or refine["E_over_sigma_y"] not in scene["E_over_sigma_y"]):
            raise ValueError(f"scene {path}: [[refine]] nu {refine['nu']:g}, E_over_sigma_y "
                             f"{refine['E_over_sigma_y']:g} is not a node of the grid")
        if not refine["elements_per_contact_radius"] > impact_window.CONTACT_ELEMENTS_AT_LOWEST:
            raise ValueError(f"scene {path}: [[refine]] elements_per_contact_radius must be > "
                             f"{impact_window.CONTACT_ELEMENTS_AT_LOWEST:g}, "
                             f"got {refine['elements_per_contact_radius']:g}")
        if not loading_steps_of(refine) >= 1.0:
            raise ValueError(f"scene {path}: [[refine]] loading_steps_per_decade must be >= 1, got "
                             f"{loading_steps_of(refine):g}")
        if not 0.5 <= refine["refinement"] <= 4.0:
            raise ValueError(f"scene {path}: [[refine]] refinement must be in [0.5, 4], got {refine['refinement']:g}")
    if scene["kinematics"] not in recipe.REACH:
        raise ValueError(f"scene {path}: [vz_master] kinematics must be one of {', '.join(recipe.REACH)}, "
                         f"got {scene['kinematics']!r}")
    for key in ("meshes", "check_meshes"):
        if scene[key] not in (1, 2):
            raise ValueError(f"scene {path}: [vz_master] {key} must be 1 or 2, got {scene[key]}")
    return scene


# A [[refine]] entry's ladder: "both" refines every mesh size and the loading steps at once (sizes / r, steps x r,
# elements_per_contact_radius and loading_steps_per_decade at r = 1); "mesh" refines the sizes alone at
# loading_steps_per_decade (a number); "steps" the loading steps alone (a list) on the mesh of refinement (a number).
LADDERS = ("both", "mesh", "steps")
GRADED_KEYS = ("elements_per_contact_radius", "loading_steps_per_decade", "refinement")


def refine_levels(entry: dict, path, index: int = 0) -> list[dict]:
    """The levels of the ``index``-th [[refine]] entry (LADDERS): each the node's nu and E/sigma_Y, N elements
    across every contact radius at refinement r and loading_steps_per_decade S at r = 1 (S r per decade at the
    level: a mesh or step ladder's held or listed steps over r, so a level two ladders share is one task), its
    ``ladder`` and ``entry`` (not in the task's key); ValueError naming a bad field."""
    ladder = entry.get("ladder", "both")
    if ladder not in LADDERS:
        raise ValueError(f"scene {path}: [[refine]] ladder must be one of {', '.join(LADDERS)}, got {ladder!r}")
    listed = "loading_steps_per_decade" if ladder == "steps" else "refinement"
    for key in ("refinement", "loading_steps_per_decade"):
        value = entry.get(key, [1.0] if key == listed == "refinement" else 0.0)
        if isinstance(value, list) != (key == listed):
            raise ValueError(f"scene {path}: [[refine]] ladder {ladder!r}: {key} must be "
                             f"{'a list' if key == listed else 'one number'}")
    for r in entry.get("refinement", [1.0]) if listed == "refinement" else [entry.get("refinement", 1.0)]:
        if not 0.5 <= float(r) <= 4.0:          # before the steps are divided by it
            raise ValueError(f"scene {path}: [[refine]] refinement must be in [0.5, 4], got {float(r):g}")
    base = {"nu": float(entry["nu"]), "E_over_sigma_y": float(entry["E_over_sigma_y"]),
            "elements_per_contact_radius": float(entry.get("elements_per_contact_radius", 0.0)),
            "ladder": ladder, "entry": index}
    steps = entry.get("loading_steps_per_decade", 0.0)
    if ladder == "both":
        return [{**base, "loading_steps_per_decade": float(steps), "refinement": float(r)}
                for r in entry.get("refinement", [1.0])]
    if ladder == "mesh":
        return [{**base, "loading_steps_per_decade": float(steps) / float(r), "refinement": float(r)}
                for r in entry["refinement"]]
    r = float(entry.get("refinement", 1.0))
    return [{**base, "loading_steps_per_decade": float(s) / r, "refinement": r} for s in steps]


def loading_steps_of(level: dict) -> float:
    """The loading steps per decade of a graded task, level or record: loading_steps_per_decade x refinement."""
    return level["loading_steps_per_decade"] * level["refinement"]


# a [[check]]'s power-law flow curve (calib.fe.flow_curve): Swift sigma_y = K (eps0 + eps_p)^n or Ludwik
# sigma_y = sigma_Y + K eps_p^n, K in units of the sphere's sigma_Y
POWER_LAWS = {"swift": SwiftHardening, "ludwik": LudwikHardening}


def power_law_of(check: dict, path) -> dict | None:
    """A [[check]]'s flow_curve = "swift"|"ludwik" with K_over_sigma_y and n, as a task states it (None: the
    check's H_over_E, linear hardening); ValueError naming a bad field."""
    kind = check.get("flow_curve")
    if kind is None:
        return None
    if kind not in POWER_LAWS or "H_over_E" in check:
        raise ValueError(f"scene {path}: [[check]] {check.get('name')}: flow_curve must be one of "
                         f"{', '.join(POWER_LAWS)} (and no H_over_E beside it), got {kind!r}")
    K, n = float(check.get("K_over_sigma_y", 0.0)), float(check.get("n", 0.0))
    if not (K > (1.0 if kind == "swift" else 0.0) and 0.0 < n <= 1.0):
        raise ValueError(f"scene {path}: [[check]] {check.get('name')}: K_over_sigma_y must be > "
                         f"{1 if kind == 'swift' else 0} and n in (0, 1], got {K:g} and {n:g}")
    return {"flow_curve": kind, "K_over_sigma_y": K, "n": n}


def is_hardening_sheet(scene: dict) -> bool:
    """Whether ``scene`` is a hardening sheet (an H_over_E axis beside 0; calib.fit.vz_hardening), not a grid."""
    return len(scene["H_over_E"]) > 1


def grid_mesh(scene: dict) -> dict | None:
    """The graded mesh of the grid's nodes and checks ([vz_master] N, steps, r), or None for the
    uniform mesh of contact_size_over_a_max (or the recipe's level)."""
    return None if scene["contact_size_over_a_max"] else scene.get("graded")

"""The vz master table over the finite-strain reach: a small-strain scene's nodes joined with a finite-strain one's.

The small-strain grid (vz_master_grid) ends at the small strain's reach, 140 P_Y (a = 0.2 R) for the soft
columns, 250 P_Y elsewhere; the finite-strain grid (vz_master_reach, ``[vz_master] joins``) runs the same
nodes (nu, E/sigma_Y) to the finite strain's reach, 1e4 P_Y or a = 0.45 R (calib.fit.recipe.REACH), from
a load where the contact is still small. Each node of the joined table takes the small-strain node's values
below its join load and the finite-strain node's from it on:

    x_join = min(x_top,small, x(a_FE = JOIN_A_OVER_R R))    [P/P_Y]

x(a) the load whose FE contact radius (calib.fit.recipe.fe_contact_radius) is a, never below the
finite-strain node's lowest unloading path. Below a = JOIN_A_OVER_R R finite and small strain agree
within 0.3-1.5 % in force (the reference sphere, recipe.KINEMATICS_PART_OVER_R), so the table keeps
every small-strain figure where it holds and the finite strain's where the kinematics part (+2.7..4.1 %
at 0.1 R, +11..17 % at 0.22-0.25 R). A node's window runs from the small node's lowest unloading path
to the finite node's top; its columns (f, g, rho, m, f_a: calib.fit.vz_master_build.node_columns) switch
at x_join together, so the vz-unload law's radius and its loading stay one node's.

    nfdcal table vz_master_reach --master-out calib/data/vz_master_table.csv
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from calib.fit import recipe, vz_master_build, vz_master_scene
from calib.fit.vz_master_check import material_of
from nfdmodel import ContactPair

JOIN_A_OVER_R = 0.05            # the joined table's switch to finite strain: contact radius / R
REACH_LIMIT = recipe.REACH["finite-strain"][0]      # the joined table's loads reach the finite strain's P/P_Y


def pair_of(row: dict) -> ContactPair:
    return ContactPair.sphere_flat(*material_of(row))


def join_load(small: dict, finite: dict) -> float:
    """x_join [P/P_Y] of a node (module docstring): its small-strain record ``small``, finite-strain ``finite``."""
    pair = pair_of(finite)
    part = recipe.largest_admissible_load(pair, JOIN_A_OVER_R, recipe.fe_contact_radius) / pair.P_Y
    lowest = finite["paths"][0]["P_max"] / pair.P_Y
    return float(max(min(small["window"]["P_max_over_P_Y"], part), lowest))


def node_of(row: dict) -> tuple[float, float, float]:
    """A record's node: (nu, E/sigma_Y, H/E), H/E 0 for a perfectly plastic sphere."""
    return row["nu"], row["E_over_sigma_y"], row.get("H_over_E", 0.0)


def nodes_of(rows: list[dict]) -> dict:
    return {node_of(r): r for r in rows if r.get("kind") == "node" and r.get("status") == "ok"}


def joined_rows(small_rows: list[dict], finite_rows: list[dict], hardening: bool = False) -> list[dict]:
    """The joined table's rows (module docstring): one per node and load, the small node's columns below
    x_join and the finite node's from it on (each row with its node's H_over_E when ``hardening``: the
    hardening sheet, calib.fit.vz_hardening); a ValueError naming the nodes either scene lacks."""
    small, finite = nodes_of(small_rows), nodes_of(finite_rows)
    missing = sorted(set(small) ^ set(finite))
    if missing:
        raise ValueError(f"vz master table: nodes (nu, E/sigma_Y, H/E) {missing} are in one scene's results and not "
                         f"in the other's: run both to the end first")
    small_loading = vz_master_build.loading_records(small_rows)
    finite_loading = vz_master_build.loading_records(finite_rows)
    x = vz_master_build.table_loads(list(finite.values()), REACH_LIMIT)    # the finite nodes' windows
    out = []
    for node in sorted(small):
        below, beyond = small[node], finite[node]
        columns_below = vz_master_build.node_columns(below, small_loading.get(below["key"]), x)
        columns_beyond = vz_master_build.node_columns(beyond, finite_loading.get(beyond["key"]), x)
        switch = x >= join_load(below, beyond) * (1 - 1e-9)
        columns = {name: np.where(switch, columns_beyond[name], values) for name, values in columns_below.items()
                   if name in columns_beyond}
        errors = [r["table_rel_error_estimate"] for r in (below, beyond) if r["table_rel_error_estimate"] is not None]
        rows = vz_master_build.node_rows(below, columns, x, (below["window"]["P_min_over_P_Y"],
                                                            beyond["window"]["P_max_over_P_Y"]),
                                         max(errors) if errors else None)
        out += [{"H_over_E": node[2], **r} for r in rows] if hardening else rows
    return out


def scene_records(scene: dict, folder: str | Path) -> list[dict]:
    """The finished records of the vz master scene ``scene`` (its nodes, checks and refined ladder, and the
    nodes' loading reruns), read from ``folder`` (its results: nodes/, loading/); a ValueError when a grid
    node is missing."""
    import json

    folder = Path(folder)
    rows = [json.loads(p.read_text(encoding="utf-8"))
            for sub in ("nodes", vz_master_build.LOADING_FOLDER) for p in sorted((folder / sub).glob("*.json"))]
    tasks = vz_master_build.tasks_for(scene)
    keys = {t["key"] for t in tasks if t["kind"] == "node"}
    known = {t["key"] for t in tasks}
    rows = vz_master_build.in_scene_words([r for r in rows if r.get("status") == "ok" and (
        r.get("key") in known or r.get("node_key") in keys)], tasks)
    found = {r["key"] for r in rows if r.get("kind") == "node"}
    if found != keys:
        raise ValueError(f"vz master table: {len(keys - found)} of {len(keys)} nodes of scene {scene['name']} are "
                         f"not in {folder}/nodes: run `nfdcal table {scene['name']}` to the end first")
    return rows


def join_record(small_scene: dict, small_rows: list[dict], finite_rows: list[dict]) -> dict:
    """What the joined table's .json states of the join: the small-strain scene, JOIN_A_OVER_R and each
    node's x_join [P/P_Y]."""
    small, finite = nodes_of(small_rows), nodes_of(finite_rows)
    return {"small_strain_scene": small_scene["name"], "join_a_over_R": JOIN_A_OVER_R,
            "join_over_P_Y": [{"nu": nu, "E_over_sigma_y": ratio, **({"H_over_E": h} if h else {}),
                               "x_join": join_load(small[(nu, ratio, h)], finite[(nu, ratio, h)])}
                              for nu, ratio, h in sorted(small)]}


def joined_table(scene: dict, rows: list[dict], folder: str | Path | None = None) -> dict:
    """The ``joined`` argument of vz_master_build.write_master (and of calib.fit.vz_hardening_build.build for a
    hardening sheet) for the finite-strain scene ``scene`` (``[vz_master] joins``) and its records ``rows``: the
    small-strain scene (``small_scene``) and its records from ``folder`` (default results/tables/<its name>), the
    joined rows and the join's record (a hardening sheet: no discretisation ladder, ``ladder`` None)."""
    small_scene = vz_master_scene.load_scene(scene["joins"])
    small_rows = scene_records(small_scene, folder or Path("results") / "tables" / small_scene["name"])
    hardening = vz_master_scene.is_hardening_sheet(scene)
    return {"rows": joined_rows(small_rows, rows, hardening=hardening),
            "small_scene": small_scene, "join": join_record(small_scene, small_rows, rows),
            "small_rows": [r for r in small_rows if r.get("kind") in ("node", "loading")],
            "check_rows": small_strain_checks(small_rows),
            "ladder": None if hardening else join_ladders(scene, small_rows, rows)}


def join_ladders(scene: dict, small_rows: list[dict], finite_rows: list[dict]) -> dict:
    """The ``ladder`` of calib.fit.vz_master_check.measure_and_state for the joined table: the small-strain
    nodes and their refined ladder (kind "refine"), each row's paths below its node's join load (the
    small-strain part's discretisation, ``rows``), and the clause on the finite-strain part (``note``):
    its own reference ladder (the finite scene's [[refine]] rows, each row's paths from the join load up,
    ``finite``: calib.fit.vz_master_check.discretisation) where the scene has one, else the one mesh, and its mesh
    and step errors apart where the scene's ladders cross (``finite_apart``: calib.fit.vz_master_ladders), whose bound
    the note states when measured."""
    from calib.fit.vz_master_check import discretisation, discretisation_statement
    from calib.fit.vz_master_ladders import mesh_and_step_errors, mesh_and_step_statement

    small, finite = nodes_of(small_rows), nodes_of(finite_rows)

    def part(source: list[dict], nodes: dict, below: bool) -> list[dict]:
        rows = []
        for row in source:
            node = (row.get("nu"), row.get("E_over_sigma_y"), row.get("H_over_E", 0.0))
            if row.get("kind") in ("node", "refine") and node in nodes:
                x_join = join_load(small[node], finite[node]) * row["P_Y"] * (1 - 1e-9)
                rows.append({**row, "paths": [p for p in row["paths"] if (p["P_max"] < x_join) == below]})
        return rows

    rows = part(small_rows, finite, below=True)
    above = part(finite_rows, small, below=False)
    measured = discretisation(above)
    apart = mesh_and_step_errors(scene, above)
    graded = scene.get("graded") or {}
    apart_clause = mesh_and_step_statement(apart, lead=": ")
    if apart_clause or measured:
        # the crossing ladders' bound where they exist: a ladder refining both holds its steps per element, and
        # with them the step error (calib/fit/README.md)
        note = (" (the small-strain part, below each node's join); the finite-strain part above it"
                + (apart_clause or discretisation_statement(measured, lead=": ")))
    elif graded:
        note = (f" (the small-strain part, below each node's join); the finite-strain part above it: one graded mesh, "
                f"{graded.get('elements_per_contact_radius', 0) * graded.get('refinement', 0):.3g} elements across "
                f"every contact radius and {graded.get('loading_steps_per_decade', 0) * graded.get('refinement', 0):.3g} "
                f"loading steps per decade, its discretisation not measured")
    else:
        note = ""
    return {"rows": rows, "note": note, "finite": measured, "finite_apart": apart}


def small_strain_checks(small_rows: list[dict]) -> list[dict]:
    """The small-strain scene's checks where they test the joined table: each check's paths whose peak
    lies below its material's JOIN_A_OVER_R R (where the table is the small strain's and the two
    kinematics agree; above it a small-strain path measures the kinematics, not the table)."""
    out = []
    for row in small_rows:
        if row.get("kind") == "check":
            pair = pair_of(row)
            part = recipe.largest_admissible_load(pair, JOIN_A_OVER_R, recipe.fe_contact_radius)
            paths = [p for p in row["paths"] if p["P_max"] <= part]
            if paths:
                out.append({**row, "paths": paths})
    return out

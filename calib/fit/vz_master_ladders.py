"""The FE's mesh error and loading-step error apart: a node's mesh ladder and step ladder that cross.

A ladder that refines every mesh size and the loading steps at once (a [[refine]] entry's ladder "both",
calib.fit.vz_master_check.discretisation) sees the sum of the two errors; where they have opposite signs its
changes oscillate or stop shrinking, and the order it observes is neither's. Two ladders of one node that share
their finest level (calib.fit.vz_master_scene.refine_levels) measure them apart:

    mesh ladder:  every size / r at the finest level's loading steps S
    step ladder:  the loading steps S per decade refined at the finest level's mesh

Each is measured as the combined ladder is (calib.fit.vz_master_check.ladder_errors: every level's table and the
node's driven along the finest FE's paths inside every window, the changes between consecutive levels, the order
observed from three levels, Richardson's error of the finest level, e_mesh and e_steps), and per path the node
table's error against the converged FE is bounded by

    |e_table - e_finest| + e_mesh + e_steps        (and alike in force, of P_max)   [-]

the finest level's two errors added, each estimated with the other parameter held at its finest value
(Roache 1998, Verification and Validation in Computational Science and Engineering, ch. 5: a temporal and a
spatial study of one solution, each at the other's finest discretisation).
"""
from __future__ import annotations

from calib.fit import vz_master_build
from calib.fit.vz_master_check import ladder_errors
from calib.fit.vz_master_scene import loading_steps_of

CROSS = ("mesh", "steps")
# what each ladder refines, level by level: the mesh's refinement r, the loading steps per decade
FINER = {"mesh": lambda row: row["refinement"], "steps": loading_steps_of}


def crossing_ladders(scene: dict, rows: list[dict]) -> dict:
    """Per node of ``scene`` with a finished mesh or step ladder (at least two levels; the longest entry of each
    kind, its finest three levels): the rows of each, from the coarsest ({(nu, E/sigma_Y): {kind: rows}})."""
    by_key = {r["key"]: r for r in rows if r.get("status") == "ok"}
    entries: dict = {}
    for level in scene["refine"]:
        if level["ladder"] in CROSS:
            item = vz_master_build.task(scene, level["nu"], level["E_over_sigma_y"], "refine", refine=level)
            if item["key"] in by_key:
                node = (level["nu"], level["E_over_sigma_y"])
                ladder = (level["ladder"], level["entry"])
                entries.setdefault(node, {}).setdefault(ladder, []).append(by_key[item["key"]])
    out: dict = {}
    for node, ladders in entries.items():
        for kind in CROSS:
            found = [rows_ for (k, _), rows_ in ladders.items() if k == kind and len(rows_) >= 2]
            if found:
                out.setdefault(node, {})[kind] = sorted(max(found, key=len), key=FINER[kind])[-3:]
    return out


def mesh_and_step_errors(scene: dict, rows: list[dict]) -> dict:
    """The mesh and step errors apart at each node of ``scene`` with crossing ladders, from ``rows`` (its finished
    records, the grid's nodes among them; module doc): per node ``mesh`` and ``steps`` (ladder_errors' entries,
    ``ratios`` of the sizes and of the loading steps), ``shared_finest`` (both ladders end on one level), and where
    they do, per path the table's bound against the converged FE (``by_path``) and its largest; ``worst`` over the
    nodes. {} without crossing ladders."""
    nodes = {(r["nu"], r["E_over_sigma_y"]): r for r in rows if r.get("kind") == "node" and r.get("status") == "ok"}
    out = []
    for key, ladders in sorted(crossing_ladders(scene, rows).items()):
        if key not in nodes:
            continue
        entry = {"nu": key[0], "E_over_sigma_y": key[1]}
        for kind, ladder in ladders.items():
            levels = [FINER[kind](row) for row in ladder]
            ratios = [fine / coarse for coarse, fine in zip(levels, levels[1:])]
            measured = ladder_errors(ladder, ratios, nodes[key])
            if measured:
                entry[kind] = measured
        entry["shared_finest"] = bool(all(kind in ladders for kind in CROSS)
                                      and ladders["mesh"][-1]["key"] == ladders["steps"][-1]["key"])
        if entry["shared_finest"] and all(kind in entry for kind in CROSS):
            entry["by_path"] = combined_paths(entry["mesh"], entry["steps"])
            if entry["by_path"]:
                entry.update({f"{q}_error_estimate": max(p[f"{q}_error_estimate"] for p in entry["by_path"])
                              for q in ("e", "force")})
        if any(kind in entry for kind in CROSS):
            out.append(entry)
    if not out:
        return {}
    bounded = [n for n in out if "e_error_estimate" in n]
    worst = ({f"{q}_error_estimate": max(n[f"{q}_error_estimate"] for n in bounded) for q in ("e", "force")}
             if bounded else {})
    return {"nodes": out, "worst": worst,
            "definition": "per node with a mesh ladder (every size / r at the finest level's loading steps) and a "
                          "step ladder (the loading steps x r at the finest level's mesh) that share their finest "
                          "level: each measured as calib.fit.vz_master_check.ladder_errors (changes, observed order, "
                          "the finest level's Richardson error); per path the node table's error against the "
                          "converged FE bounded by |table - finest| + the mesh error + the step error"}


def combined_paths(mesh: dict, steps: dict) -> list[dict]:
    """Per path both ladders measured (the same finest FE, so the same peaks): the table's change from the finest
    level, the finest level's mesh and step errors, and their sum, the bound (module doc), in e and force."""
    by_peak = {round(p["P_max_over_P_Y"], 6): p for p in steps["by_path"]}
    out = []
    for p in mesh["by_path"]:
        s = by_peak.get(round(p["P_max_over_P_Y"], 6))
        if s is None:
            continue
        row = {"P_max_over_P_Y": p["P_max_over_P_Y"], "fe_e_mesh": p["fe_e"], "fe_e_steps": s["fe_e"]}
        for q in ("e", "force"):
            change = abs(p[f"table_{q}_change"])
            row.update({f"table_{q}_change": change, f"mesh_{q}_error": p[f"finest_{q}_error_estimate"],
                        f"steps_{q}_error": s[f"finest_{q}_error_estimate"],
                        f"{q}_error_estimate": change + p[f"finest_{q}_error_estimate"]
                        + s[f"finest_{q}_error_estimate"]})
        out.append(row)
    return out


def mesh_and_step_statement(measured: dict, lead: str = "; ") -> str:
    """The clause of the accuracy statement on the mesh and step errors apart, after ``lead`` ("" when no node has
    the bound: both ladders, one finest level)."""
    nodes = [n for n in measured.get("nodes", []) if "e_error_estimate" in n]
    if not nodes:
        return ""
    parts = []
    for n in nodes:
        ladders = []
        for kind in ("mesh", "steps"):
            m = n[kind]
            if kind == "mesh":
                what = (f"mesh {m['elements_per_contact_radius'][0]:.3g}-{m['elements_per_contact_radius'][-1]:.3g} "
                        f"elements across every contact radius at {m['loading_steps_per_decade'][-1]:.3g} loading "
                        f"steps per decade")
            else:
                what = (f"loading steps {m['loading_steps_per_decade'][0]:.3g}-{m['loading_steps_per_decade'][-1]:.3g} "
                        f"per decade at {m['elements_per_contact_radius'][-1]:.3g} elements")
            orders = ", ".join(f"{q} " + (f"{m['order'][q]['order_raw']:.2g}" if m["order"][q]["status"]
                                         in ("observed", "bounded") else f"not observed ({m['order'][q]['status']})")
                               for q in ("e", "force"))
            ladders.append(f"{what}, orders {orders}, the finest level's own error e "
                           f"{100 * m['finest_e_error_estimate']:.2g} %, force "
                           f"{100 * m['finest_force_error_estimate']:.2g} %")
        m = n["mesh"]
        parts.append(f"at nu {n['nu']:g} E/sigma_Y {n['E_over_sigma_y']:g} ({'; '.join(ladders)}): the table differs "
                     f"from the finest level by e {100 * m['table_e_change_max']:.2g} %, force "
                     f"{100 * m['table_force_change_max']:.2g} % of P_max and is within e "
                     f"{100 * n['e_error_estimate']:.2g} %, force {100 * n['force_error_estimate']:.2g} % of the "
                     f"converged FE")
    return f"{lead}the mesh and the loading steps apart, " + "; ".join(parts)

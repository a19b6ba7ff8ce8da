"""Building and checking the vz master table's hardening sheet (calib.fit.vz_hardening) from the FE records of
the scene vz_master_hardening (calib/scenes/builtin/sweeps/vz_master_hardening.toml: nu 0.3 x the grid's E/sigma_Y x
H/E 0, 0.005, 0.02, 0.05, the grid's mesh and window; calib.fit.vz_master_build runs it) or of the finite-strain
scene vz_master_reach_hardening joined with it (the same nodes to 1e4 P_Y or 0.45 R; calib.fit.vz_master_join,
as the vz master table joins its two grids): each node's tables on the sheet's loads (vz_master_build.node_columns),
and the hardened laws against the scenes' [[check]] FE paths of hardening spheres off the nodes
(calib.fit.vz_master_check; a small-strain check's paths below the join), beside the perfectly plastic master law
on the same paths.

    nfdcal table vz_master_hardening [--workers 2]
    nfdcal table vz_master_reach_hardening [--workers 2] --master-out calib/data/vz_hardening_table.csv
"""
from __future__ import annotations

from pathlib import Path

from calib import output
from calib.fit import vz_master_build, vz_master_check, vz_master_scene
from calib.fit.vz_hardening import REPRESENTATIVE_STRAIN_FACTOR, SCENE, HardenedMasterTable, HardeningSheet
from calib.fit.vz_master_table import RADIUS_COLUMN, UNLOADING_COLUMNS, VZMasterTable


def sheet_rows(rows: list[dict]) -> list[dict]:
    """The sheet's CSV rows from the scene's records: each node's columns (calib.fit.vz_master_build.node_columns)
    on the sheet's loads, its H/E beside nu and E/sigma_Y."""
    nodes = sorted((r for r in rows if r.get("kind") == "node" and r.get("status") == "ok"),
                   key=lambda r: (r.get("H_over_E", 0.0), r["nu"], r["E_over_sigma_y"]))
    loading = vz_master_build.loading_records(rows)
    x = vz_master_build.table_loads(nodes)
    out = []
    for row in nodes:
        columns = vz_master_build.node_columns(row, loading[row["key"]], x)
        window = (row["window"]["P_min_over_P_Y"], row["window"]["P_max_over_P_Y"])
        out += [{"H_over_E": row.get("H_over_E", 0.0), **r}
                for r in vz_master_build.node_rows(row, columns, x, window, row["table_rel_error_estimate"])]
    return out


def check_rows(rows: list[dict], master: VZMasterTable, sheet: HardeningSheet) -> dict:
    """The hardened laws against the scene's [[check]] FE paths (calib.fit.vz_master_check.check_material and
    check_unloading at each check's H/E, or its power-law flow curve read through its secant modulus:
    calib.fit.vz_hardening.hardened_tables) and, for contrast, the perfectly plastic master law on the same paths.
    Each row carries its check's H_over_E, or its flow curve ("flow_curve": "swift K/sigma_Y n")."""
    out = {"vz-table": [], "unloading": [], "perfectly plastic": []}
    for row in (r for r in rows if r.get("kind") == "check" and r.get("status") == "ok"):
        if row.get("power_law"):
            law = row["power_law"]
            hardening = vz_master_build.hardening_of(row, vz_master_check.material_of(row)[0])
            tag = {"flow_curve": f"{law['flow_curve']} {law['K_over_sigma_y']:g} {law['n']:g}"}
        else:
            hardening, tag = row["H_over_E"], {"H_over_E": row["H_over_E"]}
        hardened = HardenedMasterTable(master, sheet, hardening)
        out["vz-table"] += [{**tag, **r} for r in vz_master_check.check_material(row, hardened)]
        out["unloading"] += [{**tag, **r} for r in vz_master_check.check_unloading(row, hardened)]
        out["perfectly plastic"] += [{**tag, **r} for r in vz_master_check.check_material(row, master)]
    return out


def summary(checked: dict) -> dict:
    """The largest errors inside the windows: e and force of the vz-table law, the vz-unload law's e, dent
    and unloading force, and the perfectly plastic law's e and force on the same paths."""
    def largest(rows, key):
        values = [abs(r[key]) for r in rows if r["inside"] and r.get(key) is not None]
        return max(values) if values else None

    inside = [r for r in checked["vz-table"] if r["inside"]]
    return {"paths": len(inside), "checks": len({r["name"] for r in inside}),
            "vz-table": {"e_error": largest(checked["vz-table"], "e_error"),
                         "force_error": largest(checked["vz-table"], "force_error")},
            "vz-unload": {"e_error": largest(checked["unloading"], "vz-unload e_error"),
                          "unloading_error": largest(checked["unloading"], "vz-unload unloading_error"),
                          "dent_error_of_alpha_max": largest(checked["unloading"], "vz-unload dent_error_of_alpha_max")},
            "perfectly plastic": {"e_error": largest(checked["perfectly plastic"], "e_error"),
                                  "force_error": largest(checked["perfectly plastic"], "force_error")},
            "nu_range": f"{min(r['nu'] for r in inside):g}-{max(r['nu'] for r in inside):g}" if inside else ""}


def split(checked: dict) -> tuple[dict, dict]:
    """(linear, power law): ``checked`` split into the checks of linear hardening and of power-law flow curves."""
    return ({kind: [r for r in rows if "flow_curve" not in r] for kind, rows in checked.items()},
            {kind: [r for r in rows if "flow_curve" in r] for kind, rows in checked.items()})


def statement(measured: dict, what: str = "hardening spheres") -> str:
    """The sheet's accuracy in one sentence (:func:`summary`; ``what``: the checks' spheres)."""
    if not measured["paths"]:
        return f"not checked against FE paths of {what}"
    t, u, p = measured["vz-table"], measured["vz-unload"], measured["perfectly plastic"]
    return (f"against direct FE of {measured['checks']} {what} off the sheet's nodes ({measured['paths']} "
            f"load-unload paths inside the window, nu {measured['nu_range']}{measured.get('range', '')}): "
            f"vz-table e within {100 * t['e_error']:.2g} %, force within {100 * t['force_error']:.2g} % of P_max; "
            f"vz-unload e within {100 * u['e_error']:.2g} %, unloading force {100 * u['unloading_error']:.2g} % of "
            f"P_max, dent {100 * u['dent_error_of_alpha_max']:.2g} % of alpha_max; the perfectly plastic master law "
            f"on the same paths: e {100 * p['e_error']:.2g} %, force {100 * p['force_error']:.2g} %")


def build(rows: list[dict], path: str | Path, folder: str | Path, master: VZMasterTable | None = None,
          scene: dict | None = None, joined: dict | None = None) -> dict:
    """Write the sheet (calib/data/vz_hardening_table.{csv,json}: its rows, stamp and measured accuracy) from the
    records ``rows`` of ``scene`` (default vz_master_hardening), check it with the master table (default: the
    shipped one) against the scene's [[check]] FE paths (``folder``/vz_hardening_check.{csv,json}) and return the
    summary with its statement. ``joined``: a finite-strain scene's sheet joined with the small-strain one's
    (calib.fit.vz_master_join.joined_table): its rows, and the small-strain checks' paths below the join."""
    path, folder = Path(path), Path(folder)
    scene = scene or vz_master_scene.load_scene(SCENE)
    nodes = [r for r in rows if r.get("kind") == "node" and r.get("status") == "ok"]
    expected = len(scene["nu"]) * len(scene["E_over_sigma_y"]) * len(scene["H_over_E"])
    if len(nodes) != expected:
        raise ValueError(f"hardening sheet: {len(nodes)} of {expected} nodes are calibrated; run "
                         f"nfdcal table {scene['name']} to the end first")
    table = joined["rows"] if joined else sheet_rows(rows)
    loading = [r for r in rows if r.get("kind") == "loading" and r.get("status") == "ok"]
    meshes = {"graded": vz_master_scene.grid_mesh(scene), "meshes": scene["meshes"]}
    if joined:                  # the small-strain scene's records are part of the sheet
        small_scene = joined["small_scene"]
        meshes = {"below the join": {"graded": vz_master_scene.grid_mesh(small_scene), "meshes": small_scene["meshes"]},
                  "from the join": meshes}
        nodes += [r for r in joined["small_rows"] if r.get("kind") == "node"]
        loading += [r for r in joined["small_rows"] if r.get("kind") == "loading"]
    stamp = output.stamp(sum(r["wall_time_s"] for r in nodes + loading), mesh=meshes, scene=scene["name"],
                         node_commits=sorted({r["git_commit"] for r in nodes}))
    meta = {"scene": scene["name"], "axes": ["H_over_E", "E_over_sigma_y", "P_over_P_Y"], "nu": scene["nu"],
            "H_over_E": scene["H_over_E"], "E_over_sigma_y": scene["E_over_sigma_y"],
            "kinematics": scene["kinematics"], **({"join": joined["join"]} if joined else {}),
            "check_folder": str(folder),
            "definition": "the columns of calib/data/vz_master_table.csv of a sphere of linear isotropic hardening "
                          "sigma_y = sigma_Y + H eps_p, H = H_over_E E, at nu (calib.fit.vz_hardening)",
            "columns": ["a_p_over_a_Y", "C_R", *UNLOADING_COLUMNS, RADIUS_COLUMN]}
    output.write_csv(path, table, comment=output.stamp_comment(stamp))
    output.write_json(path.with_suffix(".json"), {"vz_hardening_table": meta, "stamp": stamp})
    master = master or VZMasterTable.load()
    checked = check_rows(rows + (joined["check_rows"] if joined else []), master, HardeningSheet.load(path))
    linear, power = split(checked)
    measured = summary(linear)
    inside = [r for r in linear["vz-table"] if r["inside"]]
    measured["H_over_E_range"] = (f"{min(r['H_over_E'] for r in inside):g}-{max(r['H_over_E'] for r in inside):g}"
                                  if inside else "")
    measured["range"] = f", H/E {measured['H_over_E_range']}"
    measured["statement"] = statement(measured)
    flow = summary(power)
    flow["statement"] = statement(flow, f"spheres of Swift and Ludwik flow curves (each read as the linear hardening "
                                        f"of its secant modulus to {REPRESENTATIVE_STRAIN_FACTOR:g} a/R)")
    measured["flow_curves"] = flow
    check_stamp = output.stamp(0.0, table=str(path), master_table=str(master.path))
    output.write_csv(folder / "vz_hardening_check.csv", checked["vz-table"], comment=output.stamp_comment(check_stamp))
    output.write_json(folder / "vz_hardening_check.json", {**checked, "accuracy": measured, "stamp": check_stamp})
    output.write_json(path.with_suffix(".json"), {"vz_hardening_table": {**meta, "accuracy": measured["statement"],
                                                                         "accuracy_flow_curves": flow["statement"],
                                                                         "accuracy_details": measured},
                                                  "stamp": stamp})
    return measured

"""The vz master table against direct FE at materials between its nodes (its stated accuracy).

For each off-grid material of the scene (calib.fit.vz_master_build, kind "check": the same FE
calibration at the FE's reach, unloading paths log-spaced over its window, so their peaks lie
between the table's load nodes too), the law interpolated in the table (calib.fit.vz_master_table)
is driven along every FE load-unload path (calib.studies.wide_window.law_against_path):

    force error = max |P_law(alpha) - P_FE(alpha)| / P_max    along loading and unloading [-]
    e error     = e_law / e_FE - 1     (the quasi-static cycle to the FE's largest approach) [-]

A path counts as inside when its peak lies in the table's window at that material.

The table's discretisation error is measured at the scene's refined nodes (kind "refine": a node
run again on a finer mesh, contact element h_f against the nodes' h): the node's table and the
finer mesh's, both driven along the finer FE's paths inside both windows, differ by

    e change     = e_h / e_hf - 1,    force change = max |P_h(alpha) - P_hf(alpha)| / P_max

and the node mesh's own error is estimated from that change by Richardson's r^p / (r^p - 1) with
r = h / h_f and p = calib.fit.extrapolation.ORDER (:func:`discretisation`).

What that error does to an inverse fit is measured directly: fit-data's vz-table model
(calib.fit.measured.table_law) fits sigma_Y to each check material's noise-free FE data (drop
tests from the paths inside the window, v_in = sqrt(2 W_l / m*), e = sqrt(W_u / W_l), P_max the FE
peak; the force-approach curve of the highest such path), and the rms of ln(sigma_fit / sigma_true)
over the materials, per kind of data, is the model-form standard uncertainty fit-data adds to
its statistical one (the table's .json, ``model_form.sigma_y``).
"""
from __future__ import annotations

import math

import numpy as np

from calib.fit.measured.data import ForceApproachData, ImpactData, Measurements
from calib.fit.measured.specimen import Specimen
from calib.fit.vz_master_table import VZMasterTable
from nfdmodel import ContactPair, Material

DATA_KINDS = ("drops e", "drops e+P", "force")


def material_of(row: dict) -> tuple[Material, float]:
    return Material(row["E_over_sigma_y"] * row["sigma_y"], row["nu"], row["sigma_y"], row["rho"]), row["R"]


def fe_paths(row: dict) -> list[dict]:
    """Each FE load-unload path of a stored task row: its approach [m] and force [N] history
    (the loading rows up to its peak, then its unloading), P_max [N], loading and unloading work [J]
    and e = sqrt(W_u / W_l), the works from the histories as calib.fe.loadpath takes them
    (contact_work), so a stored row is read with the FE's current quadrature."""
    from calib.fe.loadpath import contact_work

    P = np.asarray(row["loading"]["P"], dtype=float)
    alpha = np.asarray(row["loading"]["alpha"], dtype=float)
    out = []
    for path in row["paths"]:
        up = P <= path["P_max"] * (1 + 1e-9)
        down_alpha = np.asarray(path["unloading"]["alpha"], dtype=float)
        down_P = np.maximum(np.asarray(path["unloading"]["P"], dtype=float), 0.0)
        loading_work = contact_work(np.r_[0.0, alpha[up]], np.r_[0.0, P[up]])
        unloading_work = contact_work(np.r_[alpha[up][-1], down_alpha], np.r_[P[up][-1], down_P])
        out.append({"approach": np.concatenate([alpha[up], down_alpha]),
                    "force": np.concatenate([P[up], path["unloading"]["P"]]), "P_max": path["P_max"],
                    "e": float(np.sqrt(unloading_work / loading_work)), "loading_work": loading_work,
                    "unloading_work": unloading_work, "alpha_max": path["alpha_max"],
                    "loading_points": int(up.sum())})
    return out


def loading_force_error(law, path: dict) -> float | None:
    """rms of (P_law - P_FE) / P_FE along the FE loading branch inside the law's window [-]."""
    from calib.fit.calibration import drive_law

    n = path["loading_points"]
    approach, force = path["approach"][:n], path["force"][:n]
    above = force >= law.window.P_min_over_P_Y * law.pair.P_Y * (1 - 1e-9)
    predicted, _ = drive_law("vz-table", law, approach)
    return float(np.sqrt(np.mean((predicted[above] / force[above] - 1.0) ** 2))) if above.any() else None


def check_material(row: dict, table: VZMasterTable) -> list[dict]:
    """Per FE path of one check row: the interpolated law's errors (module doc)."""
    from calib.studies.wide_window import law_against_path

    material, R = material_of(row)
    law = table.law(material, R)
    window = law.window
    out = []
    for path in fe_paths(row):
        x = path["P_max"] / law.pair.P_Y
        compared = law_against_path("vz-table", law, path)
        out.append({"name": row["name"], "nu": row["nu"], "E_over_sigma_y": row["E_over_sigma_y"],
                    "P_max_over_P_Y": x, "inside": bool(window.P_min_over_P_Y * (1 - 1e-9) <= x
                                                        <= window.P_max_over_P_Y * (1 + 1e-9)),
                    "window_low": window.P_min_over_P_Y, "window_top": window.P_max_over_P_Y,
                    "e_fe": compared["e_fe"], "e_law": compared["e_law"], "e_error": compared["e_error"],
                    "force_error": compared["force_error"],
                    "loading_force_rms_error": loading_force_error(law, path)})
    return out


def fe_datasets(row: dict, table: VZMasterTable) -> dict:
    """The noise-free drop tests and force-approach curve of one FE row (module doc): the specimen,
    the true sigma_Y [Pa], drops (v_in [m/s], e, P_max [N]), force (approach [m], force [N])."""
    material, R = material_of(row)
    pair = ContactPair.sphere_flat(material, R)
    window = table.law(material, R).window
    inside = [p for p in fe_paths(row) if window.P_min_over_P_Y * (1 - 1e-9) <= p["P_max"] / pair.P_Y
              <= window.P_max_over_P_Y * (1 + 1e-9)]
    if not inside:
        raise ValueError(f"{row['name']}: no FE path inside the table's window {window.describe()}")
    drops = {"v_in": np.array([math.sqrt(2 * p["loading_work"] / pair.mass_star) for p in inside]),
             "e": np.array([math.sqrt(p["unloading_work"] / p["loading_work"]) for p in inside]),
             "P_max": np.array([p["P_max"] for p in inside])}
    top = max(inside, key=lambda p: p["P_max"])
    return {"specimen": Specimen(material.E, material.nu, R, material.rho), "sigma_y": material.sigma_y,
            "drops": drops, "force": (top["approach"], top["force"]),
            "window": (window.P_min_over_P_Y, window.P_max_over_P_Y)}


def measurements(kind: str, values: dict, name: str) -> Measurements:
    """Measurements of one DATA_KINDS from ``values`` (v_in, e, P_max, approach, force)."""
    if kind == "force":
        return Measurements(forces=ForceApproachData(f"{name}_force.csv", (("fe", values["approach"], values["force"]),)))
    rows = np.arange(1, values["v_in"].size + 1)
    P = values["P_max"] if kind == "drops e+P" else None
    return Measurements(impacts=ImpactData(f"{name}_drops.csv", values["v_in"], values["e"], P, None, rows))


def fit_errors(row: dict, table: VZMasterTable) -> dict:
    """ln(sigma_fit / sigma_true) of the vz-table fit to one row's noise-free FE data, per kind."""
    from calib.fit.measured.table_law import fit

    sets = fe_datasets(row, table)
    values = {**sets["drops"], "approach": sets["force"][0], "force": sets["force"][1]}
    out = {"residual_rms": {}}
    for kind in DATA_KINDS:
        result = fit(measurements(kind, values, row["name"]), sets["specimen"], table, model_form={})
        out[kind] = math.log(result.sigma_y / sets["sigma_y"])
        for group, r in result.residuals.items():
            out["residual_rms"][f"{kind}: {group}"] = float(np.sqrt(np.mean(r**2)))
    return out


def node_law(row: dict):
    """The vz-table law of one stored node (or refined node) row, on its window."""
    from nfdmodel import CalibrationWindow, VZTableParams

    material, R = material_of(row)
    table = row["table"]
    return VZTableParams(ContactPair.sphere_flat(material, R), tuple(table["x"]), tuple(table["f"]),
                         tuple(table["g"]), CalibrationWindow.from_record(row["window"]))


def discretisation(rows: list[dict]) -> dict:
    """The table's discretisation error at each refined node (module doc): per node the largest
    e and force change between its table and the finer mesh's along the finer FE paths, the
    Richardson estimates of the node mesh's error, each law's errors against the finer FE, and
    the FE's own e change at peaks both meshes unload from; ``worst``: the largest over the nodes.
    {} without refined nodes."""
    from calib.fit import extrapolation
    from calib.fit.calibration import drive_law
    from calib.studies.wide_window import law_against_path

    nodes = {(r["nu"], r["E_over_sigma_y"]): r for r in rows if r.get("kind") == "node" and r.get("status") == "ok"}
    out = []
    for fine in (r for r in rows if r.get("kind") == "refine" and r.get("status") == "ok"):
        node = nodes.get((fine["nu"], fine["E_over_sigma_y"]))
        if node is None:
            continue
        coarse_law, fine_law = node_law(node), node_law(fine)
        low = max(coarse_law.window.P_min_over_P_Y, fine_law.window.P_min_over_P_Y) * (1 - 1e-9)
        top = min(coarse_law.window.P_max_over_P_Y, fine_law.window.P_max_over_P_Y) * (1 + 1e-9)
        node_e = {round(p["P_max"] / node["P_Y"], 6): p["e"] for p in fe_paths(node)}
        paths = []
        for path in fe_paths(fine):
            x = path["P_max"] / fine["P_Y"]
            if not low <= x <= top:
                continue
            P_coarse, e_coarse = drive_law("vz-table", coarse_law, path["approach"])
            P_fine, e_fine = drive_law("vz-table", fine_law, path["approach"])
            fe_e = node_e.get(round(x, 6))
            paths.append({"P_max_over_P_Y": x, "e_change": e_coarse / e_fine - 1.0,
                          "force_change": float(np.abs(P_coarse - P_fine).max() / path["P_max"]),
                          "e_error_vs_fine_fe": law_against_path("vz-table", coarse_law, path)["e_error"],
                          "force_error_vs_fine_fe": law_against_path("vz-table", coarse_law, path)["force_error"],
                          "fine_e_error_vs_fine_fe": law_against_path("vz-table", fine_law, path)["e_error"],
                          "fe_e_change": None if fe_e is None else fe_e / path["e"] - 1.0})
        if not paths:
            continue
        ratio = node["mesh"]["contact_size"] / fine["mesh"]["contact_size"]
        factor = ratio ** extrapolation.ORDER / (ratio ** extrapolation.ORDER - 1.0)
        e_change = max(abs(p["e_change"]) for p in paths)
        force_change = max(p["force_change"] for p in paths)
        fe_changes = [abs(p["fe_e_change"]) for p in paths if p["fe_e_change"] is not None]
        out.append({"nu": node["nu"], "E_over_sigma_y": node["E_over_sigma_y"], "paths": len(paths),
                    "contact_size_ratio": ratio, "contact_sizes": [node["mesh"]["contact_size"], fine["mesh"]["contact_size"]],
                    "dofs": [node["dofs"], fine["dofs"]], "fine_wall_time_s": fine["wall_time_s"],
                    "e_change_max": e_change, "force_change_max": force_change,
                    "e_error_estimate": factor * e_change, "force_error_estimate": factor * force_change,
                    "fe_e_change_max": max(fe_changes) if fe_changes else None,
                    "richardson_factor": factor, "by_path": paths})
    if not out:
        return {}
    return {"nodes": out, "worst": {key: max(n[key] for n in out) for key in
                                    ("e_change_max", "force_change_max", "e_error_estimate", "force_error_estimate")},
            "definition": "per refined node: the node's table and the table of the same node on a finer mesh, "
                          "both driven along the finer FE's paths inside both windows: e_change = e_h / e_hf - 1, "
                          "force_change = max |P_h - P_hf| / P_max; *_error_estimate: Richardson's r^p / (r^p - 1) "
                          "times the change (r = h / h_f, p = calib.fit.extrapolation.ORDER); fe_e_change: the FE's "
                          "own e at peaks both meshes unload from"}


def accuracy(rows: list[dict]) -> dict:
    """Summary of :func:`check_material` rows inside the window: largest and rms e error, largest
    force error and rms loading force error."""
    inside = [r for r in rows if r["inside"]]
    if not inside:
        return {"paths": 0}
    e = np.array([r["e_error"] for r in inside])
    force = np.array([r["force_error"] for r in inside])
    loading = np.array([r["loading_force_rms_error"] for r in inside if r["loading_force_rms_error"] is not None])
    return {"paths": len(inside), "materials": len({r["name"] for r in inside}),
            "e_error_max": float(np.abs(e).max()), "e_error_rms": float(np.sqrt(np.mean(e**2))),
            "e_error_mean": float(e.mean()),
            "force_error_max": float(force.max()), "loading_force_error_rms": float(np.sqrt(np.mean(loading**2)))}


def measure_and_state(rows: list[dict], table_path, folder) -> dict:
    """Check the table at ``table_path`` against every finished check row: write
    FOLDER/vz_master_check.{csv,json} and state the measured accuracy in the table's .json
    (``accuracy``, ``accuracy_details``, ``model_form``: the rms e and loading-force errors inside
    the window, the u_g of calib.fit.measured.table_law). Returns the accuracy summary."""
    import json
    from pathlib import Path

    from calib import output

    table = VZMasterTable.load(table_path)
    checks = [r for r in rows if r.get("kind") == "check" and r.get("status") == "ok"]
    compared = [c for row in checks for c in check_material(row, table)]
    summary = accuracy(compared)
    errors = {row["name"]: fit_errors(row, table) for row in checks}
    sigma_form = {kind: float(np.sqrt(np.mean([e[kind] ** 2 for e in errors.values()]))) for kind in DATA_KINDS} \
        if errors else {}
    groups = sorted({g for e in errors.values() for g in e["residual_rms"]})
    residual_form = {g: float(np.sqrt(np.mean([e["residual_rms"][g] ** 2 for e in errors.values()]))) for g in groups}
    summary["sigma_y_fit_errors"] = errors
    summary["discretisation"] = discretisation(rows)
    stamp = output.stamp(0.0, table=str(table_path))
    folder = Path(folder)
    output.write_csv(folder / "vz_master_check.csv", compared, comment=output.stamp_comment(stamp))
    output.write_json(folder / "vz_master_check.json", {"rows": compared, "accuracy": summary, "stamp": stamp})
    if summary.get("paths"):
        statement = (f"against direct FE at {summary['materials']} off-grid materials ({summary['paths']} load-unload "
                     f"paths inside the window, peaks between the load nodes): e within {100 * summary['e_error_max']:.2g} % "
                     f"(rms {100 * summary['e_error_rms']:.2g} %), force within {100 * summary['force_error_max']:.2g} % "
                     f"of P_max, loading force rms {100 * summary['loading_force_error_rms']:.2g} %; sigma_Y fitted to "
                     f"their noise-free FE data rms " + ", ".join(f"{k} {100 * v:.2g} %" for k, v in sigma_form.items()))
        statement += discretisation_statement(summary["discretisation"])
    else:
        statement = "not checked against off-grid FE"
    meta_path = Path(table_path).with_suffix(".json")
    meta = json.loads(meta_path.read_text(encoding="utf-8"))
    meta["vz_master_table"].update({"accuracy": statement, "accuracy_details": summary,
                                    "discretisation": summary["discretisation"],
                                    "model_form": {"sigma_y": sigma_form, "residual_rms": residual_form,
                                                   "definition": "rms of ln(sigma_fit / sigma_true) of fit-data's "
                                                                 "vz-table model on the noise-free FE data of the "
                                                                 "off-grid check materials, per kind of data; "
                                                                 "residual_rms: the rms residual of those fits per "
                                                                 "kind and group"}})
    output.write_json(meta_path, meta)
    return {**summary, "statement": statement}


def discretisation_statement(measured: dict) -> str:
    """The clause of the accuracy statement on the measured discretisation error."""
    from calib.fit import extrapolation

    if not measured:
        return "; discretisation not measured"
    nodes = measured["nodes"]
    worst = measured["worst"]
    where = ", ".join(f"nu {n['nu']:g} E/sigma_Y {n['E_over_sigma_y']:g}" for n in nodes)
    ratio = min(n["contact_size_ratio"] for n in nodes)
    return (f"; discretisation (against a {ratio:.2g}x finer contact element at {where}): e "
            f"{100 * worst['e_change_max']:.2g} %, force {100 * worst['force_change_max']:.2g} % of P_max (Richardson "
            f"estimate of the table's error at order {extrapolation.ORDER:g}, not observed: e "
            f"{100 * worst['e_error_estimate']:.2g} %, force {100 * worst['force_error_estimate']:.2g} %)")

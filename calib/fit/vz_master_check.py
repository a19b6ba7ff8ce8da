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
r = h / h_f (:func:`discretisation`). With a second finer mesh h_ff (a third mesh) the order is
observed (:func:`observed_order`, Roache 1998, Verification and Validation in Computational Science
and Engineering, ch. 5): from the change d1 (h -> h_f) and d2 (h_f -> h_ff) of one quantity at the same
points (e: per path; force: (P - P') / P_max at every sample of every path), their rms |d1|, |d2| and,
for r = h / h_f = h_f / h_ff,

    p = ln(|d1| / |d2|) / ln r     (Q_h = Q + C h^p; unequal ratios: the root of
                                    |d1| / |d2| = r2^p (r1^p - 1) / (r2^p - 1))

bounded to [ORDER_RANGE]; when the changes oscillate (d1 . d2 <= 0) or do not shrink, the order is
not observed and the estimate is the bounding one, Richardson's factor at the range's lowest order.
With two meshes p = calib.fit.extrapolation.ORDER, assumed.

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
ORDER_RANGE = (0.5, 4.0)          # the orders an observed one is bounded to (first order: contact edge;
                                  # fourth: beyond the quadratic elements' smooth-solution rate)


def material_of(row: dict) -> tuple[Material, float]:
    return Material(row["E_over_sigma_y"] * row["sigma_y"], row["nu"], row["sigma_y"], row["rho"]), row["R"]


def fe_paths(row: dict) -> list[dict]:
    """Each FE load-unload path of a stored task row: its approach [m] and force [N] history
    (the loading rows up to its peak, then its unloading), P_max [N], loading and unloading work [J]
    and e = sqrt(W_u / W_l), the works from the histories as calib.fe.loadpath takes them
    (contact_work), so a stored row is read with the FE's current quadrature."""
    from calib.fe.loadpath import contact_work, loading_count_to_peak

    P = np.asarray(row["loading"]["P"], dtype=float)
    alpha = np.asarray(row["loading"]["alpha"], dtype=float)
    out = []
    for path in row["paths"]:
        up = np.arange(P.size) < loading_count_to_peak(P, path["P_max"])
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


def richardson_factor(ratio: float, order: float) -> float:
    """r^p / (r^p - 1): the coarse mesh's error over its change to the mesh ``ratio`` times finer."""
    return ratio**order / (ratio**order - 1.0)


def observed_order(coarse, fine, ratio: float, fine_ratio: float | None = None) -> dict:
    """The observed order of one quantity (module doc) from its signed changes ``coarse`` (h -> h / r1,
    r1 = ``ratio``) and ``fine`` (h / r1 -> h / (r1 r2), r2 = ``fine_ratio``, default r1) at the same
    points: ``order`` (None when not observed), ``order_raw`` (before the bounds), ``status``
    ("observed", "bounded", "oscillating", "not converging"), ``order_used`` (the observed order
    bounded to ORDER_RANGE, or its lowest when not observed), ``richardson_factor`` (at order_used,
    r1), ``rms`` of both changes."""
    from scipy.optimize import brentq

    d1, d2 = np.asarray(coarse, dtype=float).ravel(), np.asarray(fine, dtype=float).ravel()
    if d1.size == 0 or d1.size != d2.size:
        raise ValueError(f"observed order: the two changes need the same points, got {d1.size} and {d2.size}")
    r1, r2 = float(ratio), float(ratio if fine_ratio is None else fine_ratio)
    rms1, rms2 = float(np.sqrt(np.mean(d1**2))), float(np.sqrt(np.mean(d2**2)))
    low, high = ORDER_RANGE
    out = {"rms": [rms1, rms2], "ratios": [r1, r2], "order": None, "order_raw": None, "order_range": list(ORDER_RANGE)}
    if rms2 == 0.0 or float(np.dot(d1, d2)) <= 0.0:
        status = "oscillating"
    elif rms1 <= rms2:
        status = "not converging"
    else:
        target = math.log(rms1 / rms2)
        if abs(math.log(r1 / r2)) < 1e-6:
            raw = target / math.log(r1)
        else:                                  # the ratio of changes grows with p from ln r1 / ln r2
            def gap(p):
                return p * math.log(r2) + math.log(math.expm1(p * math.log(r1)) / math.expm1(p * math.log(r2))) - target
            raw = brentq(gap, 1e-6, 50.0) if gap(1e-6) < 0.0 < gap(50.0) else None
        status = "not converging" if raw is None else ("observed" if low <= raw <= high else "bounded")
        out["order_raw"] = raw
        if raw is not None:
            out["order"] = min(max(raw, low), high)
    used = low if out["order"] is None else out["order"]
    return {**out, "status": status, "order_used": used, "richardson_factor": richardson_factor(r1, used)}


def _compare(coarse_law, fine_law, path: dict) -> tuple[float, np.ndarray]:
    """The e change e_c / e_f - 1 and the force change (P_c - P_f) / P_max along one FE path."""
    from calib.fit.calibration import drive_law

    P_coarse, e_coarse = drive_law("vz-table", coarse_law, path["approach"])
    P_fine, e_fine = drive_law("vz-table", fine_law, path["approach"])
    return e_coarse / e_fine - 1.0, (P_coarse - P_fine) / path["P_max"]


def discretisation(rows: list[dict]) -> dict:
    """The table's discretisation error at each refined node (module doc): per node the largest
    e and force change between its table and the finer mesh's along the finest FE's paths, the
    Richardson estimates of the node mesh's error (at the order observed from a third mesh when the
    node has two finer ones, else at the assumed calib.fit.extrapolation.ORDER), each law's errors
    against the finer FE, and the FE's own e change at peaks both meshes unload from; ``worst``: the
    largest over the nodes. {} without refined nodes."""
    from calib.fit import extrapolation
    from calib.studies.wide_window import law_against_path

    nodes = {(r["nu"], r["E_over_sigma_y"]): r for r in rows if r.get("kind") == "node" and r.get("status") == "ok"}
    finer = {}
    for r in rows:
        if r.get("kind") == "refine" and r.get("status") == "ok" and (r["nu"], r["E_over_sigma_y"]) in nodes:
            finer.setdefault((r["nu"], r["E_over_sigma_y"]), []).append(r)
    out = []
    for key, refined in sorted(finer.items()):
        node = nodes[key]
        ladder = [node] + sorted(refined, key=lambda r: -r["mesh"]["contact_size"])[:2]
        laws = [node_law(r) for r in ladder]
        fine = ladder[1]
        finest = ladder[-1]
        low = max(law.window.P_min_over_P_Y for law in laws) * (1 - 1e-9)
        top = min(law.window.P_max_over_P_Y for law in laws) * (1 + 1e-9)
        node_e = {round(p["P_max"] / node["P_Y"], 6): p["e"] for p in fe_paths(node)}
        fine_e = {round(p["P_max"] / fine["P_Y"], 6): p["e"] for p in fe_paths(fine)}
        paths, e_changes, force_changes = [], [[], []], [[], []]
        for path in fe_paths(finest):
            x = path["P_max"] / finest["P_Y"]
            if not low <= x <= top:
                continue
            changes = [_compare(laws[k], laws[k + 1], path) for k in range(len(laws) - 1)]
            for k, (de, dP) in enumerate(changes):
                e_changes[k].append(de)
                force_changes[k].append(dP)
            fe_e = node_e.get(round(x, 6))
            reference = fine_e.get(round(x, 6)) if finest is not fine else path["e"]
            entry = {"P_max_over_P_Y": x, "e_change": changes[0][0],
                     "force_change": float(np.abs(changes[0][1]).max()),
                     "e_error_vs_fine_fe": law_against_path("vz-table", laws[0], path)["e_error"],
                     "force_error_vs_fine_fe": law_against_path("vz-table", laws[0], path)["force_error"],
                     "fine_e_error_vs_fine_fe": law_against_path("vz-table", laws[-1], path)["e_error"],
                     "fe_e_change": None if fe_e is None or reference is None else fe_e / reference - 1.0}
            if len(changes) > 1:
                entry.update({"e_change_fine": changes[1][0], "force_change_fine": float(np.abs(changes[1][1]).max()),
                              "fe_e_change_fine": None if reference is None else reference / path["e"] - 1.0})
            paths.append(entry)
        if not paths:
            continue
        sizes = [r["mesh"]["contact_size"] for r in ladder]
        ratios = [sizes[k] / sizes[k + 1] for k in range(len(sizes) - 1)]
        e_change = max(abs(p["e_change"]) for p in paths)
        force_change = max(p["force_change"] for p in paths)
        fe_changes = [abs(p["fe_e_change"]) for p in paths if p["fe_e_change"] is not None]
        entry = {"nu": node["nu"], "E_over_sigma_y": node["E_over_sigma_y"], "paths": len(paths),
                 "contact_size_ratio": ratios[0], "contact_size_ratios": ratios, "contact_sizes": sizes,
                 "dofs": [r["dofs"] for r in ladder], "wall_time_s": [r["wall_time_s"] for r in ladder],
                 "fine_wall_time_s": fine["wall_time_s"],
                 "e_change_max": e_change, "force_change_max": force_change,
                 "fe_e_change_max": max(fe_changes) if fe_changes else None, "by_path": paths}
        if len(ladder) == 3:
            entry["e_change_fine_max"] = max(abs(p["e_change_fine"]) for p in paths)
            entry["force_change_fine_max"] = max(p["force_change_fine"] for p in paths)
            orders = {"e": observed_order(e_changes[0], e_changes[1], ratios[0], ratios[1]),
                      "force": observed_order(np.concatenate(force_changes[0]), np.concatenate(force_changes[1]),
                                              ratios[0], ratios[1])}
            entry["order"] = orders
            e_factor, force_factor = orders["e"]["richardson_factor"], orders["force"]["richardson_factor"]
            entry["order_basis"] = "observed"
        else:
            e_factor = force_factor = richardson_factor(ratios[0], extrapolation.ORDER)
            entry["order_basis"] = f"assumed {extrapolation.ORDER:g}"
        entry.update({"richardson_factor": {"e": e_factor, "force": force_factor},
                      "e_error_estimate": e_factor * e_change, "force_error_estimate": force_factor * force_change})
        out.append(entry)
    if not out:
        return {}
    worst = {key: max(n[key] for n in out) for key in
             ("e_change_max", "force_change_max", "e_error_estimate", "force_error_estimate")}
    for key in ("e_change_fine_max", "force_change_fine_max"):
        if all(key in n for n in out):
            worst[key] = max(n[key] for n in out)
    return {"nodes": out, "worst": worst,
            "definition": "per refined node (nodes: contact element h, h_f, h_ff): the tables of the node and of the "
                          "same node on the finer meshes, all driven along the finest FE's paths inside every window: "
                          "e_change = e_h / e_hf - 1, force_change = max |P_h - P_hf| / P_max (*_fine: h_f against "
                          "h_ff); order: the observed order per quantity, p = ln(|d1| / |d2|) / ln r from the rms over "
                          "the paths (e) or over every sample of every path (force, (P_h - P_hf) / P_max) of the "
                          "two changes, bounded to ORDER_RANGE " + f"{list(ORDER_RANGE)}" + "; when the changes "
                          "oscillate (d1 . d2 <= 0) or do not shrink, not observed and the bounding estimate taken "
                          "(p = the range's lowest); with one finer mesh p = calib.fit.extrapolation.ORDER, assumed; "
                          "*_error_estimate: Richardson's r^p / (r^p - 1) times the worst path's change "
                          "(r = h / h_f); fe_e_change: the FE's own e at peaks the node and the first finer mesh "
                          "unload from"}


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
    if not measured:
        return "; discretisation not measured"
    nodes = measured["nodes"]
    worst = measured["worst"]
    where = ", ".join(f"nu {n['nu']:g} E/sigma_Y {n['E_over_sigma_y']:g}" for n in nodes)
    ratio = min(n["contact_size_ratio"] for n in nodes)
    orders = []
    for n in nodes:
        if "order" not in n:
            orders.append(f"{n['order_basis']}")
            continue
        parts = []
        for q in ("e", "force"):
            o = n["order"][q]
            parts.append(f"{q} {o['order_raw']:.2g}" + (f" (bounded to {o['order']:.2g})" if o["status"] == "bounded" else "")
                         if o["order_raw"] is not None and o["status"] in ("observed", "bounded")
                         else f"{q} not observed ({o['status']}; bounding estimate at {o['order_used']:g})")
        orders.append(", ".join(parts))
    order_text = "; ".join(f"E/sigma_Y {n['E_over_sigma_y']:g}: {o}" for n, o in zip(nodes, orders))
    return (f"; discretisation (against a {ratio:.2g}x finer contact element at {where}): e "
            f"{100 * worst['e_change_max']:.2g} %, force {100 * worst['force_change_max']:.2g} % of P_max; Richardson "
            f"estimate of the table's error e {100 * worst['e_error_estimate']:.2g} %, force "
            f"{100 * worst['force_error_estimate']:.2g} % at the order {order_text}")

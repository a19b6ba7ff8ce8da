"""The vz master table against direct FE at materials between its nodes (its stated accuracy).

For each off-grid material of the scene (calib.fit.vz_master_build, kind "check": the same FE
calibration at the FE's reach, unloading paths log-spaced over its window, so their peaks lie
between the table's load nodes too), the law interpolated in the table (calib.fit.vz_master_table)
is driven along every FE load-unload path (calib.fit.path_check.law_against_path):

    force error = max |P_law(alpha) - P_FE(alpha)| / P_max    along loading and unloading [-]
    e error     = e_law / e_FE - 1     (the quasi-static cycle to the FE's largest approach) [-]

A path counts as inside when its peak lies in the table's window at that material.

The table's vz-unload law (VZMasterTable.unload_law: the same loading at the table's loads, its own
contact radius f_a, the dent ratio rho and the unloading exponent m interpolated as f and g) and, for contrast, its vz-table law are driven along
the same FE paths in what a DEM code reads after a contact (calib.fit.unload_check; the check
records keep no contact radius, so the radius is not checked here: calib.fit.master_radius_check
checks it against direct FE runs that record it):

    dent error      = delta_res,law / alpha_res,FE - 1   (and of alpha_max where the dent is small)
    unloading error = max |P_law - P_FE| / P_max over the FE's unloading points
    e error         = e_law / e_FE - 1   (the energies at the peak)

The table's discretisation error is measured against a reference FE at the scene's refined nodes
(kind "refine"): the node run again on graded meshes (meshes.hemisphere, grading: N elements across
every contact radius from the lowest path up, where the nodes' uniform mesh sized on the largest
contact puts a few under the lowest paths) with more loading steps, refined systematically, every
element size divided by r and the loading steps multiplied by r (Roache 1998, Verification and
Validation in Computational Science and Engineering, ch. 5). Every level's table and the node's are
driven along the finest level's FE paths inside every window; between consecutive levels

    e change     = e_k / e_k+1 - 1,    force change = max |P_k(alpha) - P_k+1(alpha)| / P_max

and with three levels the order is observed (:func:`observed_order`) from the change d1 (level 1 ->
2) and d2 (2 -> 3) of one quantity at the same points (e: per path; force: (P - P') / P_max at every
sample of every path), their rms |d1|, |d2| and, for r = r1 = r2,

    p = ln(|d1| / |d2|) / ln r     (Q_h = Q + C h^p; unequal ratios: the root of
                                    |d1| / |d2| = r2^p (r1^p - 1) / (r2^p - 1))

bounded to [ORDER_RANGE]; when the changes oscillate (d1 . d2 <= 0) or do not shrink, the order is
not observed and the range's lowest is taken (the bounding estimate). The finest level's own error
is Richardson's |d2| / (r^p - 1), and the node table's error against the converged FE is bounded by
its difference from the finest level plus that (:func:`discretisation`). With two levels p =
calib.fit.extrapolation.ORDER, assumed.

What that error does to an inverse fit is measured directly: fit-data's vz-table model
(calib.fit.measured.table_law) fits sigma_Y to each check material's noise-free FE data (drop
tests from the paths inside the window, v_in = sqrt(2 W_l / m*), e = sqrt(W_u / W_l), P_max the FE
peak, the contact time of the FE loop thrown as a quasi-static impact of the mass m*
(calib.fit.loop_impact; within 0.7 % of the dynamic FE's); the force-approach curve of
the highest such path), and the rms of ln(sigma_fit / sigma_true)
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

DATA_KINDS = ("drops e", "drops e+P", "drops e+P+t", "drops e+dent", "force")   # t: the contact time; dent: delta_res
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
    from calib.fit.path_check import law_against_path

    material, R = material_of(row)
    law = table.law(material, R)
    window = law.window
    out = []
    for path in fe_paths(row):
        x = path["P_max"] / law.pair.P_Y
        try:
            compared = law_against_path("vz-table", law, path)
        except ValueError:
            if x <= window.P_max_over_P_Y:
                raise
            continue            # beyond the window, past where the law is defined at all: nothing to compare
        out.append({"name": row["name"], "nu": row["nu"], "E_over_sigma_y": row["E_over_sigma_y"],
                    "P_max_over_P_Y": x, "inside": bool(window.P_min_over_P_Y * (1 - 1e-9) <= x
                                                        <= window.P_max_over_P_Y * (1 + 1e-9)),
                    "window_low": window.P_min_over_P_Y, "window_top": window.P_max_over_P_Y,
                    "e_fe": compared["e_fe"], "e_law": compared["e_law"], "e_error": compared["e_error"],
                    "force_error": compared["force_error"],
                    "loading_force_rms_error": loading_force_error(law, path)})
    return out


def unload_path(row: dict, stored: dict, path: dict) -> dict:
    """One FE path of a stored row (``stored``: its record, ``path``: its fe_paths entry) as
    calib.fit.unload_check.unload_against_path reads it; the record keeps no contact radius."""
    n = path["loading_points"]
    return {"loading_approach": path["approach"][:n], "loading_force": np.maximum(path["force"][:n], 0.0),
            "unloading_approach": np.asarray(stored["unloading"]["alpha"], dtype=float),
            "unloading_force": np.maximum(np.asarray(stored["unloading"]["P"], dtype=float), 0.0),
            "P_max": path["P_max"], "alpha_max": path["alpha_max"], "alpha_residual": stored["alpha_residual"],
            "radius_at_peak": None, "e": path["e"]}


def check_unloading(row: dict, table: VZMasterTable) -> list[dict]:
    """Per FE path of one check row: the table's vz-unload law and, for contrast, its vz-table law in
    dent, unloading force and e (calib.fit.unload_check.unload_against_path; module doc)."""
    from calib.fit.unload_check import unload_against_path

    material, R = material_of(row)
    laws = {"vz-unload": table.unload_law(material, R), "vz-table": table.law(material, R)}
    window = laws["vz-table"].window
    out = []
    for stored, path in zip(row["paths"], fe_paths(row)):
        x = path["P_max"] / laws["vz-table"].pair.P_Y
        record = {"name": row["name"], "nu": row["nu"], "E_over_sigma_y": row["E_over_sigma_y"], "P_max_over_P_Y": x,
                  "inside": bool(window.P_min_over_P_Y * (1 - 1e-9) <= x <= window.P_max_over_P_Y * (1 + 1e-9)),
                  "dent_fe_over_alpha_max": stored["alpha_residual"] / path["alpha_max"]}
        fe = unload_path(row, stored, path)
        try:
            for name, law in laws.items():
                compared = unload_against_path(name, law, fe)
                record.update({f"{name} {key}": compared[key] for key in UNLOAD_FIGURES})
        except ValueError:
            if record["inside"] or x < window.P_min_over_P_Y:
                raise
            continue            # beyond the window, past where the law is defined at all: nothing to compare
        out.append(record)
    return out


UNLOAD_FIGURES = ("dent_error", "dent_error_of_alpha_max", "unloading_error", "e_error")


def unloading_accuracy(rows: list[dict]) -> dict:
    """Summary of :func:`check_unloading` rows inside the window, per law: the largest |dent error|,
    where it exceeds the 3 % target the largest |dent error| of alpha_max there, the largest unloading
    force error [of P_max] and |e error|, and how many paths meet the dent target (3 % or 0.5 % of
    alpha_max, calib.fit.unload_check)."""
    from calib.fit.unload_check import DENT_TARGET, DENT_TARGET_OF_ALPHA_MAX

    inside = [r for r in rows if r["inside"]]
    if not inside:
        return {"paths": 0}
    out = {"paths": len(inside), "materials": len({r["name"] for r in inside})}
    for law in ("vz-unload", "vz-table"):
        dent = np.array([r[f"{law} dent_error"] for r in inside])
        of_max = np.array([r[f"{law} dent_error_of_alpha_max"] for r in inside])
        beyond = np.abs(dent) > DENT_TARGET
        out[law] = {"dent_error_max": float(np.abs(dent).max()),
                    "dent_error_of_alpha_max_beyond_3pct": float(np.abs(of_max[beyond]).max()) if beyond.any() else 0.0,
                    "dent_within_target": int(np.sum(~beyond | (np.abs(of_max) <= DENT_TARGET_OF_ALPHA_MAX))),
                    "unloading_error_max": float(max(r[f"{law} unloading_error"] for r in inside)),
                    "e_error_max": float(max(abs(r[f"{law} e_error"]) for r in inside))}
    return out


def unloading_statement(summary: dict) -> str:
    """The clause of the accuracy statement on the dent and the unloading curve."""
    if not summary.get("paths"):
        return ""
    parts = []
    for law in ("vz-unload", "vz-table"):
        s = summary[law]
        parts.append(f"{law} dent within {100 * s['dent_error_max']:.2g} % ({s['dent_within_target']} of "
                     f"{summary['paths']} paths within 3 % or 0.5 % of alpha_max), unloading force within "
                     f"{100 * s['unloading_error_max']:.2g} % of P_max, e within {100 * s['e_error_max']:.3g} %")
    return (f"; along the same FE unloading curves ({summary['paths']} paths): " + "; ".join(parts))


def fe_datasets(row: dict, table: VZMasterTable) -> dict:
    """The noise-free drop tests and force-approach curve of one FE row (module doc): the specimen,
    the true sigma_Y [Pa], drops (v_in [m/s], e, P_max [N]), force (approach [m], force [N])."""
    material, R = material_of(row)
    pair = ContactPair.sphere_flat(material, R)
    window = table.law(material, R).window
    inside = [{**p, "alpha_residual": stored["alpha_residual"]} for stored, p in zip(row["paths"], fe_paths(row))
              if window.P_min_over_P_Y * (1 - 1e-9) <= p["P_max"] / pair.P_Y
              <= window.P_max_over_P_Y * (1 + 1e-9)]
    if not inside:
        raise ValueError(f"{row['name']}: no FE path inside the table's window {window.describe()}")
    v_in = np.array([math.sqrt(2 * p["loading_work"] / pair.mass_star) for p in inside])
    drops = {"v_in": v_in, "e": np.array([math.sqrt(p["unloading_work"] / p["loading_work"]) for p in inside]),
             "P_max": np.array([p["P_max"] for p in inside]),
             "contact_time": np.array([contact_time(p, pair.mass_star, v) for p, v in zip(inside, v_in)]),
             "dent": np.array([p["alpha_residual"] for p in inside])}
    top = max(inside, key=lambda p: p["P_max"])
    return {"specimen": Specimen(material.E, material.nu, R, material.rho), "sigma_y": material.sigma_y,
            "drops": drops, "force": (top["approach"], top["force"]),
            "window": (window.P_min_over_P_Y, window.P_max_over_P_Y)}


def contact_time(path: dict, mass: float, v_in: float) -> float:
    """The contact time [s] of one FE load-unload path (fe_paths) thrown as a quasi-static impact of
    ``mass`` [kg] at ``v_in`` [m/s] (calib.fit.loop_impact: m alpha'' = -P(alpha) along
    the loop, Hertzian first load and last unloading segment)."""
    from calib.fit.loop_impact import loop_impact

    n = path["loading_points"]
    approach, force = np.asarray(path["approach"], float), np.maximum(np.asarray(path["force"], float), 0.0)
    loop = {"loading_alpha": np.r_[0.0, approach[:n]], "loading_P": np.r_[0.0, force[:n]],
            "unloading_alpha": approach[n - 1:], "unloading_P": force[n - 1:]}
    return float(loop_impact(loop, mass, v_in)["contact_time"])


def measurements(kind: str, values: dict, name: str) -> Measurements:
    """Measurements of one DATA_KINDS from ``values`` (v_in, e, P_max, contact_time, approach, force)."""
    if kind == "force":
        return Measurements(forces=ForceApproachData(f"{name}_force.csv", (("fe", values["approach"], values["force"]),)))
    rows = np.arange(1, values["v_in"].size + 1)
    P = values["P_max"] if kind in ("drops e+P", "drops e+P+t") else None
    t = values["contact_time"] if kind == "drops e+P+t" else None
    dent = values["dent"] if kind == "drops e+dent" else None
    return Measurements(impacts=ImpactData(f"{name}_drops.csv", values["v_in"], values["e"], P, t, rows, dent))


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
    import warnings

    from nfdmodel import CalibrationWindow, PlausibilityWarning, VZTableParams

    material, R = material_of(row)
    table = row["table"]
    with warnings.catch_warnings():
        # the window is the node's own FE's: its last loading step passes the FE's stated reach
        # (a = 0.45 R) by less than a step, which that FE computed
        warnings.simplefilter("ignore", PlausibilityWarning)
        window = CalibrationWindow.from_record(row["window"])
    return VZTableParams(ContactPair.sphere_flat(material, R), tuple(table["x"]), tuple(table["f"]),
                         tuple(table["g"]), window)


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


def ladder_errors(ladder: list[dict], ratios: list[float], node: dict) -> dict | None:
    """One node's ladder (its rows ordered from the coarsest, each ``ratios`` [k] times finer than the one before,
    in the mesh, the loading steps or both): every level's table and ``node``'s driven along the finest FE's paths
    inside every window; the changes between consecutive levels, their order and the finest level's own
    (Richardson) error, the node table's difference from the finest level (:func:`discretisation`'s entry of the
    node). None when no path lies inside every window."""
    from calib.fit import extrapolation
    from calib.fit.path_check import law_against_path

    laws = [node_law(r) for r in ladder]
    node_table = node_law(node)
    finest = ladder[-1]
    low = max(law.window.P_min_over_P_Y for law in laws + [node_table]) * (1 - 1e-9)
    top = min(law.window.P_max_over_P_Y for law in laws + [node_table]) * (1 + 1e-9)
    fe_e = [{round(p["P_max"] / r["P_Y"], 6): p["e"] for p in fe_paths(r)} for r in ladder]
    paths, e_changes, force_changes = [], [[] for _ in ratios], [[] for _ in ratios]
    node_e, node_force = [], []
    for path in fe_paths(finest):
        x = path["P_max"] / finest["P_Y"]
        if not low <= x <= top:
            continue
        changes = [_compare(laws[k], laws[k + 1], path) for k in range(len(ratios))]
        for k, (de, dP) in enumerate(changes):
            e_changes[k].append(de)
            force_changes[k].append(dP)
        de_node, dP_node = _compare(node_table, laws[-1], path)
        node_e.append(de_node)
        node_force.append(dP_node)
        against = law_against_path("vz-table", node_table, path)
        paths.append({"P_max_over_P_Y": x, "fe_e": [levels.get(round(x, 6)) for levels in fe_e],
                      "e_changes": [c[0] for c in changes],
                      "force_changes": [float(np.abs(c[1]).max()) for c in changes],
                      "table_e_change": de_node, "table_force_change": float(np.abs(dP_node).max()),
                      "table_e_error_vs_finest_fe": against["e_error"],
                      "table_force_error_vs_finest_fe": against["force_error"]})
    if not paths:
        return None
    if len(ratios) == 2:
        orders = {"e": observed_order(e_changes[0], e_changes[1], ratios[0], ratios[1]),
                  "force": observed_order(np.concatenate(force_changes[0]), np.concatenate(force_changes[1]),
                                          ratios[0], ratios[1])}
        basis = "observed"
    else:
        assumed = {"order_used": extrapolation.ORDER, "status": "assumed"}
        orders = {"e": dict(assumed), "force": dict(assumed)}
        basis = f"assumed {extrapolation.ORDER:g}"
    r_last = ratios[-1]
    finest_factor = {q: 1.0 / (r_last ** orders[q]["order_used"] - 1.0) for q in ("e", "force")}
    finest_e = [finest_factor["e"] * abs(d) for d in e_changes[-1]]
    finest_force = [finest_factor["force"] * float(np.abs(d).max()) for d in force_changes[-1]]
    for entry, fe, ff in zip(paths, finest_e, finest_force):
        entry.update({"finest_e_error_estimate": fe, "finest_force_error_estimate": ff,
                      "table_e_error_estimate": abs(entry["table_e_change"]) + fe,
                      "table_force_error_estimate": entry["table_force_change"] + ff})
    return {"nu": node["nu"], "E_over_sigma_y": node["E_over_sigma_y"], "paths": len(paths),
            "refinements": [r["refinement"] for r in ladder], "ratios": ratios,
            "elements_per_contact_radius": [r["elements_per_contact_radius"] * r["refinement"] for r in ladder],
            "loading_steps_per_decade": [r["loading_steps_per_decade"] * r["refinement"] for r in ladder],
            "contact_sizes": [r["mesh"]["contact_size"] for r in ladder],
            "dofs": [r["dofs"] for r in ladder], "wall_time_s": [r["wall_time_s"] for r in ladder],
            "order": orders, "order_basis": basis,
            "e_change_max": [max(abs(d) for d in ch) for ch in e_changes],
            "force_change_max": [max(float(np.abs(d).max()) for d in ch) for ch in force_changes],
            "finest_e_error_estimate": max(finest_e), "finest_force_error_estimate": max(finest_force),
            "table_e_change_max": max(abs(d) for d in node_e),
            "table_force_change_max": max(float(np.abs(d).max()) for d in node_force),
            "e_error_estimate": max(p["table_e_error_estimate"] for p in paths),
            "force_error_estimate": max(p["table_force_error_estimate"] for p in paths),
            "by_path": paths}


def discretisation(rows: list[dict]) -> dict:
    """The table's discretisation error at each node with a reference ladder (module doc): the
    refined rows of the node (graded meshes refined systematically by r, kind "refine", and the node
    itself when it is one of them) ordered by
    refinement, every law driven along the finest FE's paths inside every window. Per node: the
    changes between consecutive levels (e, force), their observed order (three levels; two: the
    assumed calib.fit.extrapolation.ORDER), the finest level's own error d_last / (r^p - 1)
    (Richardson), the node table's difference from the finest level, and the table's error
    against the converged FE bounded by the sum of the two; the FE's own e at each peak on every
    level; ``worst``: the largest over the nodes. {} without a ladder. The ladder refines both at once through
    the node: its levels share the node's loading_steps_per_decade at r = 1 (calib.fit.vz_master_scene.refine_levels),
    its loading steps per element across the contact; the mesh and step ladders apart: calib.fit.vz_master_ladders."""
    nodes = {(r["nu"], r["E_over_sigma_y"]): r for r in rows if r.get("kind") == "node" and r.get("status") == "ok"}
    ladders = {}
    for r in rows:
        if (r.get("kind") in ("refine", "node") and r.get("status") == "ok" and r.get("refinement")
                and (r["nu"], r["E_over_sigma_y"]) in nodes):
            # a ladder refining both shares its steps at r = 1; a mesh or step ladder's levels do not
            steps = round(r["loading_steps_per_decade"], 9)
            ladders.setdefault((r["nu"], r["E_over_sigma_y"]), {}).setdefault(steps, []).append(r)
    out = []
    for key, by_steps in sorted(ladders.items()):
        through_node = by_steps.get(round(nodes[key]["loading_steps_per_decade"], 9), [])
        ladder = sorted(through_node, key=lambda r: r["refinement"])[-3:]
        if len(ladder) < 2:
            continue
        ratios = [ladder[k + 1]["refinement"] / ladder[k]["refinement"] for k in range(len(ladder) - 1)]
        measured = ladder_errors(ladder, ratios, nodes[key])
        if measured:
            out.append(measured)
    if not out:
        return {}
    worst = {key: max(n[key] for n in out) for key in
             ("table_e_change_max", "table_force_change_max", "finest_e_error_estimate",
              "finest_force_error_estimate", "e_error_estimate", "force_error_estimate")}
    node, path = max(((n, p) for n in out for p in n["by_path"]), key=lambda np_: np_[1]["table_e_error_estimate"])
    worst["e_error_estimate_at"] = {"nu": node["nu"], "E_over_sigma_y": node["E_over_sigma_y"],
                                    "P_max_over_P_Y": path["P_max_over_P_Y"], "fe_e": path["fe_e"]}
    return {"nodes": out, "worst": worst,
            "definition": "per node with a reference ladder (graded meshes, N elements across every contact radius, "
                          "sizes / r and loading steps x r): every level's table and the node's, driven along the "
                          "finest FE's paths inside every window; e_changes[k] = e_k / e_k+1 - 1, force_changes[k] = "
                          "max |P_k - P_k+1| / P_max between levels k and k + 1; order: observed from the rms of the "
                          "two changes (e: over the paths; force: over every sample), p = ln(|d1| / |d2|) / ln r, "
                          "bounded to ORDER_RANGE " + f"{list(ORDER_RANGE)}" + ", its lowest when the changes "
                          "oscillate or do not shrink (two levels: calib.fit.extrapolation.ORDER, assumed); "
                          "finest_*_error_estimate: Richardson's |d_last| / (r^p - 1), the finest level's own error; "
                          "table_*_change: the node table against the finest level's; *_error_estimate: the node "
                          "table's error against the converged FE, |table change| + the finest level's error"}


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


def measure_and_state(rows: list[dict], table_path, folder, ladder: dict | None = None) -> dict:
    """Check the table at ``table_path`` against every finished check row: write
    FOLDER/vz_master_check.{csv,json} and state the measured accuracy in the table's .json
    (``accuracy``, ``accuracy_details``, ``model_form``: the rms e and loading-force errors inside
    the window, the u_g of calib.fit.measured.table_law). Returns the accuracy summary. ``ladder``:
    the discretisation's own rows and what it covers ({"rows": ..., "note": ..., "finite": ...}; a joined
    table's small-strain ladder below its join and its finite-strain part's measured discretisation,
    calib.fit.vz_master_join.join_ladders), else ``rows``'."""
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
    summary["discretisation"] = discretisation(ladder["rows"] if ladder else rows)
    if ladder and ladder.get("finite"):
        summary["finite_strain_discretisation"] = ladder["finite"]
    if ladder and ladder.get("finite_apart"):
        summary["finite_strain_mesh_and_steps"] = ladder["finite_apart"]
    unloading = [c for row in checks for c in check_unloading(row, table)] if table.has_unloading else []
    summary["unloading"] = unloading_accuracy(unloading) if unloading else {"paths": 0}
    stamp = output.stamp(0.0, table=str(table_path))
    folder = Path(folder)
    output.write_csv(folder / "vz_master_check.csv", compared, comment=output.stamp_comment(stamp))
    output.write_json(folder / "vz_master_check.json", {"rows": compared, "unloading_rows": unloading,
                                                          "accuracy": summary, "stamp": stamp})
    if summary.get("paths"):
        statement = (f"against direct FE at {summary['materials']} off-grid materials ({summary['paths']} load-unload "
                     f"paths inside the window, between the nodes in material, most also in load): e within {100 * summary['e_error_max']:.2g} % "
                     f"(rms {100 * summary['e_error_rms']:.2g} %), force within {100 * summary['force_error_max']:.2g} % "
                     f"of P_max, loading force rms {100 * summary['loading_force_error_rms']:.2g} %; sigma_Y fitted to "
                     f"their noise-free FE data rms " + ", ".join(f"{k} {100 * v:.2g} %" for k, v in sigma_form.items()))
        statement += (discretisation_statement(summary["discretisation"]) + (ladder["note"] if ladder else "")
                      + unloading_statement(summary["unloading"]))
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


def discretisation_statement(measured: dict, lead: str = "; ") -> str:
    """The clause of the accuracy statement on the measured discretisation error, after ``lead``."""
    if not measured:
        return f"{lead}discretisation not measured"
    nodes = measured["nodes"]
    worst = measured["worst"]
    parts = []
    for n in nodes:
        orders = []
        for q in ("e", "force"):
            o = n["order"][q]
            if o["status"] == "assumed":
                orders.append(f"{q} assumed {o['order_used']:g}")
            elif o["status"] in ("observed", "bounded"):
                orders.append(f"{q} {o['order_raw']:.2g}" + (f" (bounded to {o['order']:.2g})"
                                                             if o["status"] == "bounded" else ""))
            else:
                orders.append(f"{q} not observed ({o['status']}; bounding estimate at {o['order_used']:g})")
        parts.append(f"nu {n['nu']:g} E/sigma_Y {n['E_over_sigma_y']:g}, orders " + ", ".join(orders))
    first, at = nodes[0], worst["e_error_estimate_at"]
    return (f"{lead}discretisation, against the reference FE (graded meshes, {first['elements_per_contact_radius'][0]:.3g}"
            f"-{first['elements_per_contact_radius'][-1]:.3g} elements across every contact radius, "
            f"{first['loading_steps_per_decade'][0]:.3g}-{first['loading_steps_per_decade'][-1]:.3g} loading steps per "
            f"decade; {'; '.join(parts)}): the table differs from its finest level by e "
            f"{100 * worst['table_e_change_max']:.2g} %, force {100 * worst['table_force_change_max']:.2g} % of P_max; "
            f"that level's own error (Richardson) e {100 * worst['finest_e_error_estimate']:.2g} %, force "
            f"{100 * worst['finest_force_error_estimate']:.2g} %; the table against the converged FE within e "
            f"{100 * worst['e_error_estimate']:.2g} %, force {100 * worst['force_error_estimate']:.2g} %, the e bound "
            f"largest at E/sigma_Y {at['E_over_sigma_y']:g}, P_max {at['P_max_over_P_Y']:.4g} P_Y (the levels' FE e "
            + ", ".join(f"{e:.4f}" for e in at["fe_e"] if e is not None) + ")")

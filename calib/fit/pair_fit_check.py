"""fit-data on a counter-body against the two-body FE: the pair law's model-form error in sigma_Y.

The held-out checks of the pair table build (calib.fit.pair_table_build: pairs off every node, their two-body FE
load-unload paths, finite-strain sphere) become what a user measures on such a pair:

    drop tests    v_in = sqrt(2 W_l(P_max) / m*), e, P_max of each path inside the pair law's window,
                  W_l = int P d(alpha) along the path's loading branch from P = 0 (calib.fe.loadpath.contact_work),
                  m* the pair's (a flat is held: the sphere's mass)                       [m/s, -, N]
    force curve   the FE's loading branch to the window's top: approach alpha [m], force P [N]

(quasi-static: the law is rate-independent and so is this FE). fit-data's fit of sigma_Y on the pair law
(calib.fit.measured.table_law.fit with no model-form term of its own) recovers the FE's sigma_Y to
ln(sigma_fit / sigma_Y); the rms over the pairs per data kind ("drops e", "drops e+P", "force") is the pair
table's model-form level u (its .json ``model_form``), with the fit's rms residual per data group. A fit
fit-data refuses on these data is kept with its reason (``refused``) and left out of the levels.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from calib.fe.loadpath import contact_work
from calib.fit.counter import CounterBody
from calib.fit.measured.data import ForceApproachData, ImpactData, Measurements
from calib.fit.measured.specimen import Specimen
from calib.fit.measured.table_law import fit, table_law
from nfdmodel import ContactPair

KINDS = ("drops e", "drops e+P", "force")


def loading_branch(path: dict) -> np.ndarray:
    """[[D, P/P_Y]] of a path's rows up to its peak, from (0, 0)."""
    rows = np.array(path["rows"])
    peak = int(np.argmax(rows[:, 1]))
    return np.vstack([[0.0, 0.0], rows[:peak + 1]])


def drop_tests(row: dict, pair: ContactPair, top: float) -> dict:
    """v_in [m/s], e [-], P_max [N] of the check ``row``'s paths with P_max <= top [P/P_Y] (module doc)."""
    tests = {"v_in": [], "e": [], "P_max": []}
    for path in row["paths"]:
        if path["P_max_over_P_Y"] > top * (1 + 1e-6):
            continue
        branch = loading_branch(path)
        work = contact_work(branch[:, 0] * pair.delta_Y, branch[:, 1] * pair.P_Y)
        tests["v_in"].append(math.sqrt(2.0 * work / pair.mass_star))
        tests["e"].append(path["e"])
        tests["P_max"].append(path["P_max_over_P_Y"] * pair.P_Y)
    return {k: np.array(v) for k, v in tests.items()}


def force_curve(row: dict, pair: ContactPair, top: float) -> tuple[np.ndarray, np.ndarray]:
    """alpha [m], P [N] of the check's loading branch to top [P/P_Y]."""
    loading = np.array(row["loading"])
    loading = loading[loading[:, 0] <= top * (1 + 1e-6)]
    return loading[:, 1] * pair.delta_Y, loading[:, 0] * pair.P_Y


def fe_data(rows: list[dict], pair_table, master, specimen_of) -> list[dict]:
    """The drop tests and loading curve of each check ``rows`` to its pair law's window top (module doc), in SI
    units, with the specimen, its counter-body and its true sigma_Y: what fit_errors and fit-data's tests fit.
    ``specimen_of(row)``: (Specimen on the row's counter-body, true sigma_Y [Pa])."""
    out = []
    for row in rows:
        specimen, sigma_y = specimen_of(row)
        law = table_law(dataclasses.replace(specimen, pair_table=pair_table), sigma_y, master)
        top = law.window.P_max_over_P_Y
        alpha, force = force_curve(row, law.pair, top)
        out.append({"nu": row["nu"], "E_over_sigma_y": row["E_over_sigma_y"], "x": row["x"], "sigma_y": sigma_y,
                    "E": specimen.E, "R": specimen.R, "rho": specimen.rho, "counter": specimen.counter.describe(),
                    "window_top_over_P_Y": top, "P_Y": law.pair.P_Y,
                    "drops": {k: v.tolist() for k, v in drop_tests(row, law.pair, top).items()},
                    "loading": {"alpha": alpha.tolist(), "P": force.tolist()}})
    return out


def measurements(data: dict, kind: str) -> Measurements:
    """The data of ``kind`` (KINDS) fit-data reads from one fe_data row."""
    if kind == "force":
        loading = data["loading"]
        return Measurements(forces=ForceApproachData("fe_force_approach.csv", (
            ("1", np.array(loading["alpha"]), np.array(loading["P"])),)))
    drops = {k: np.array(v) for k, v in data["drops"].items()}
    return Measurements(impacts=ImpactData("fe_drops.csv", drops["v_in"], drops["e"],
                                           drops["P_max"] if kind == "drops e+P" else None, None,
                                           np.arange(1, drops["e"].size + 1)))


def specimen_of_data(data: dict, pair_table) -> Specimen:
    """The Specimen of one fe_data row, on its counter-body, fitted with ``pair_table``."""
    body = data["counter"]
    counter = CounterBody(body["E"], body["nu"], body["sigma_y"], body["R"], body["rho"])
    return Specimen(data["E"], data["nu"], data["R"], data["rho"], counter=counter, pair_table=pair_table)


def fit_errors(rows: list[dict], pair_table, master) -> list[dict]:
    """Per fe_data row and kind: the fitted sigma_Y's ln error and the rms residual per group (module doc)."""
    out = []
    for data in rows:
        specimen = specimen_of_data(data, pair_table)
        for kind in KINDS:
            case = {"nu": data["nu"], "E_over_sigma_y": data["E_over_sigma_y"], "x": data["x"],
                    "counter_R": data["counter"]["R"], "kind": kind, "top": data["window_top_over_P_Y"]}
            try:
                result = fit(measurements(data, kind), specimen, master, model_form={})
            except ValueError as exc:             # a refused fit is a finding: kept, named, not averaged
                out.append({**case, "refused": str(exc)})
                continue
            rms = {name: float(np.sqrt(np.mean(r ** 2))) for name, r in result.residuals.items()}
            out.append({**case, "sigma_y_error": math.log(result.sigma_y / data["sigma_y"]), "residual_rms": rms})
    return out


def model_form(errors: list[dict]) -> dict:
    """The pair table's model-form record from ``fit_errors``: "sigma_y" {kind: rms ln error}, "residual_rms"
    {"kind: group": rms}, and the pairs it was measured on."""
    form, residual = {}, {}
    refused = [e for e in errors if "refused" in e]
    for kind in KINDS:
        of_kind = [e for e in errors if e["kind"] == kind and "refused" not in e]
        if not of_kind:
            continue
        form[kind] = float(np.sqrt(np.mean([e["sigma_y_error"] ** 2 for e in of_kind])))
        for group in of_kind[0]["residual_rms"]:
            residual[f"{kind}: {group}"] = float(np.sqrt(np.mean([e["residual_rms"][group] ** 2 for e in of_kind])))
    return {"sigma_y": form, "residual_rms": residual, "pairs": len({(e["nu"], e["E_over_sigma_y"], e["x"],
                                                                     e["counter_R"]) for e in errors}),
            "refused": [{k: e[k] for k in ("nu", "E_over_sigma_y", "x", "kind", "refused")} for e in refused],
            "definition": "fit-data's sigma_Y on the pair law from the two-body FE's quasi-static drop tests and "
                          "loading curve of the held-out pairs (calib.fit.pair_fit_check): rms ln(sigma_fit / "
                          "sigma_Y) per data kind, rms residual per group"}


"""A law against the FE's load cycles (calib.fe.cycles), paths it was not fitted on.

The law (nfdmodel's ContactLaw.contact_state, one contact) is driven along the FE's approach
history of the cycles, alpha_k [m] row by row, and its force P_law(alpha_k) [N] set against the
FE's P_k (negative FE forces at separation as 0):

    partial error   = max |P_law - P_FE| / P_max over the rows of the partial unloads and reloads
                      (cycles 1..n, branches unloading and reloading)
    overload error  = max |P_law - P_FE| / P_max over the loading past the peak (cycle n)
    final error     = max |P_law - P_FE| / P_over over the final unload from P_over = overload P_max
    loading error   = max |P_law - P_FE| / P_max over the first loading (cycle 0)
    dent error      = delta_res,law / alpha_res,FE - 1 after the final unload, and
                      (delta_res,law - alpha_res,FE) / alpha_over (alpha_over the FE's approach at P_over)

The target: the force along unloading and reloading within 2 % of P_max (CYCLE_TARGET).
"""
from __future__ import annotations

import warnings

import numpy as np

from nfdmodel import RangeWarning, get_law

CYCLE_TARGET = 0.02
CHECKED_LAWS = ("vz-table", "vz-unload")


def law_along_rows(law_name: str, params, rows: list[dict]) -> tuple[np.ndarray, float]:
    """The law's forces [N] at the rows' approaches, in order, and its dent delta_res [m] after the last."""
    forces, _, dent = drive_law(law_name, params, rows)
    return forces, dent


def drive_law(law_name: str, params, rows: list[dict]) -> tuple[np.ndarray, np.ndarray, float]:
    """One contact of the law driven along the rows' approaches, in order: its forces [N], contact
    radii a_ep [m] and its dent delta_res [m] after the last row."""
    law = get_law(law_name)
    state = law.initial_state(1)
    forces, radii = np.empty(len(rows)), np.empty(len(rows))
    dent = 0.0
    with warnings.catch_warnings():      # the overload may pass the window's top by the fit error
        warnings.simplefilter("ignore", RangeWarning)
        for k, row in enumerate(rows):
            details = law.contact_state(np.array([row["alpha"]]), state, params)
            state = details.state
            forces[k], radii[k] = details.force[0], details.a_ep[0]
            dent = float(details.delta_res[0])
    return forces, radii, dent


def cycles_against_law(law_name: str, params, rows: list[dict], P_max: float, alpha_residual: float) -> dict:
    """The figures of the module doc for one law; ``rows``: calib.fe.cycles.CycleRun.rows, ``P_max``
    [N] the cycles' peak, ``alpha_residual`` [m] the FE's after the final unload."""
    forces, dent = law_along_rows(law_name, params, rows)
    fe = np.maximum([r["P"] for r in rows], 0.0)
    cycle = np.array([r["cycle"] for r in rows])
    branch = np.array([r["branch"] for r in rows])
    last = int(cycle.max())
    error = np.abs(forces - fe)
    partial = (cycle >= 1) & (cycle < last) & np.isin(branch, ("unloading", "reloading"))
    overload = (cycle == last - 1) & (branch == "loading")
    final = cycle == last
    P_over = float(fe[overload].max())
    alpha_over = float(np.array([r["alpha"] for r in rows])[overload].max())
    per_cycle = {f"{c}-{b}": float(error[(cycle == c) & (branch == b)].max() / P_max)
                 for c in range(1, last) for b in ("unloading", "reloading")}
    partial_error = float(error[partial].max() / P_max)
    return {"law": law_name, "partial_error": partial_error, "per_branch": per_cycle,
            "overload_error": float(error[overload].max() / P_max),
            "final_unloading_error": float(error[final].max() / P_over),
            "loading_error": float(error[cycle == 0].max() / P_max),
            "dent": dent, "dent_fe": alpha_residual, "dent_error": dent / alpha_residual - 1.0,
            "dent_error_of_alpha_max": (dent - alpha_residual) / alpha_over,
            "within": bool(partial_error <= CYCLE_TARGET and error[final].max() / P_over <= CYCLE_TARGET)}


def laws_of_calibration(result) -> dict:
    """The laws checked (CHECKED_LAWS) from a calibration (calib.fit.calibration.CalibrationResult)
    with unloading paths: its vz-table fit, and the vz-unload fit (calib.fit.unload_fit) of its
    loading rows and unloading paths; a law whose fit fails is left out with the reason."""
    from calib.fit.unload_fit import fit_unload_law

    laws, reasons = {}, {}
    try:
        laws["vz-table"] = result.fit_table()
    except ValueError as exc:
        reasons["vz-table"] = str(exc)
    loading, paths = result.load_paths.loading_rows, result.load_paths.paths
    try:
        laws["vz-unload"] = fit_unload_law([r["P"] for r in loading], [r["alpha"] for r in loading],
                                           [r["contact_radius"] for r in loading], result.spec.pair,
                                           [p.peak for p in paths], [p.alpha_max for p in paths],
                                           [p.alpha_residual for p in paths], [p.unloading_work for p in paths])
    except ValueError as exc:
        reasons["vz-unload"] = str(exc)
    return {"laws": laws, "not_fitted": reasons}

"""The vz-unload law of a calibration (``nfdcal calibrate --ship unload``): fitted on its FE paths,
checked against them and against paths held out of the fit.

fit: calib.fit.unload_fit on the calibration's loading points (force [N], approach [m], contact
radius [m]) and every unloading path of this mesh (peak, alpha_max, alpha_res, returned work), declared
on the calibration's fitted window from the lowest peak up (the dent and exponent are measured from
there; below it they are interpolated towards Hertz's). One mesh: the dent and the exponent are not
extrapolated over two meshes.

figures, per FE path (calib.fit.unload_check and its targets):
    dent error      = delta_res,law / alpha_res,FE - 1   (or of alpha_max: (delta_res,law - alpha_res,FE) / alpha_max)
    radius error    = a_law / a_FE - 1 at the peak
    unloading error = max |P_law - P_FE| / P_max over the FE's unloading points
    e error         = e_law / e_FE - 1
"fit": the shipped law against each path it was fitted on; "held_out": for each path strictly between
the lowest and the highest (leave one out), the law fitted on the other paths against it: the law
between its nodes, on a path it was not fitted on. The lowest and the highest path are never held
out (without them the law would extrapolate, not interpolate).
"""
from __future__ import annotations

import dataclasses

import numpy as np

from calib.fit.unload_check import (DENT_TARGET, DENT_TARGET_OF_ALPHA_MAX, E_TARGET, RADIUS_TARGET,
                                    UNLOADING_TARGET, unload_against_path)
from calib.fit.unload_fit import fit_unload_law
from nfdmodel import VZUnloadParams

TARGETS = {"dent_error": DENT_TARGET, "dent_error_of_alpha_max": DENT_TARGET_OF_ALPHA_MAX,
           "radius_error": RADIUS_TARGET, "unloading_error": UNLOADING_TARGET, "e_error": E_TARGET}


def _loading(result) -> dict:
    rows = result.load_paths.loading_rows
    return {key: np.array([r[key] for r in rows], dtype=float) for key in ("P", "alpha", "contact_radius")}


def fit_unload(result, leave_out: float | None = None) -> VZUnloadParams:
    """The vz-unload law of the calibration ``result`` (calib.fit.calibration.CalibrationResult)
    from its loading points and its unloading paths but the one of peak ``leave_out`` [N]; a
    ValueError when these do not determine it."""
    loading = _loading(result)
    paths = [p for p in result.load_paths.paths if p.peak != leave_out]
    if not paths:
        raise ValueError("the vz-unload law needs unloading paths (calibrate with unloading)")
    above = [p.peak for p in paths if p.peak > result.P_Y]
    if not above:
        raise ValueError("the vz-unload fit needs at least one FE unloading path from above P_Y")
    window = dataclasses.replace(result.fitted_window, P_min_over_P_Y=min(above) / result.P_Y)
    return fit_unload_law(loading["P"], loading["alpha"], loading["contact_radius"], result.spec.pair,
                          [p.peak for p in paths], [p.alpha_max for p in paths], [p.alpha_residual for p in paths],
                          [p.unloading_work for p in paths], window)


def fe_path(result, path) -> dict:
    """One FE path of ``result`` as calib.fit.unload_check.unload_against_path reads it [SI]."""
    loading = _loading(result)
    to_peak = np.arange(loading["P"].size) < sum(1 for r in path.rows if r["branch"] == "loading")
    unloading = [r for r in path.rows if r["branch"] != "loading"]
    return {"loading_approach": loading["alpha"][to_peak], "loading_force": np.maximum(loading["P"][to_peak], 0.0),
            "unloading_approach": np.array([r["alpha"] for r in unloading]),
            "unloading_force": np.array([max(r["P"], 0.0) for r in unloading]), "P_max": path.peak,
            "alpha_max": path.alpha_max, "alpha_residual": path.alpha_residual,
            "radius_at_peak": float(loading["contact_radius"][to_peak][-1]), "e": path.restitution}


def figures(result, params: VZUnloadParams | None = None) -> dict:
    """{"fit": [...], "held_out": [...], "targets": TARGETS}: per path (P_max [N] and the figures of
    unload_against_path) the shipped law ``params`` (None: fitted here) against the paths it was
    fitted on, and each interior path held out of its own fit (module doc)."""
    params = fit_unload(result) if params is None else params
    paths = sorted(result.load_paths.paths, key=lambda p: p.peak)
    fit = [unload_against_path("vz-unload", params, fe_path(result, p)) for p in paths]
    held_out = []
    for path in paths[1:-1]:
        try:
            law = fit_unload(result, leave_out=path.peak)
        except ValueError:              # the other paths determine no admissible law: no figure
            continue
        held_out.append(unload_against_path("vz-unload", law, fe_path(result, path)))
    return {"fit": fit, "held_out": held_out, "targets": dict(TARGETS)}


def worst(records: list[dict]) -> dict | None:
    """The worst of each figure over ``records`` (signed, largest magnitude; the force errors are
    >= 0), and whether every record meets the targets; None for no record."""
    if not records:
        return None
    out = {key: max((r[key] for r in records), key=abs) for key in
           ("dent_error", "dent_error_of_alpha_max", "radius_error", "unloading_error", "loading_error", "e_error")}
    out["within"] = all(r["within"] for r in records)
    return out


def lines(record: dict) -> list[str]:
    """The calibrate summary's lines of :func:`figures` (fit and held out, the worst of each)."""
    out = []
    for key, label in (("fit", "against the FE paths it was fitted on"),
                       ("held_out", "against FE paths held out of its fit, one at a time")):
        w = worst(record[key])
        if w is None:
            out.append(f"vz-unload law {label}: no interior path to hold out (needs 3 or more unloading paths)")
            continue
        peaks = ", ".join(f"{r['P_max']:.4g}" for r in record[key])
        out.append(f"vz-unload law {label} (P_max {peaks} N): dent {w['dent_error']:+.2%} "
                   f"({w['dent_error_of_alpha_max']:+.2%} of alpha_max), contact radius at the peak "
                   f"{w['radius_error']:+.2%}, unloading force {w['unloading_error']:.2%} of P_max, "
                   f"e {w['e_error']:+.2%} at worst"
                   + ("" if w["within"] else " (beyond the targets: dent 3 % or 0.5 % of alpha_max, radius 2 %, "
                                             "unloading 2 %, e 1 %)"))
    return out

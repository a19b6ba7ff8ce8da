"""Identifiability of the vz law's parameters from measurements (``nfdcal fit-data``): which
parameters the data determine, and which drop tests would determine the rest.

J's columns (calib.fit.measured.regression: J = d r_w / d ln theta, the weighted residuals'
derivatives at the fit) are relative sensitivities, so its singular values compare parameters
without units: the condition number s_max / s_min says how nearly some combination of parameters
leaves the data unchanged (the right singular vector of s_min names it), and a parameter is
*determined* when its relative standard error sqrt(Cov(ln theta)_jj) is at most
``DETERMINED_RELATIVE_SE`` (10 %). For impacts the report also names the v_in window whose tests
would determine all three (sigma_Y, Ca_hat, Kc_hat): the expected standard errors of the present
data plus ten tests spread geometrically over each candidate window of v_in / v_Y, at the present
scatter (Cov = (J^T J)^-1 with the new rows appended to J; Bates & Watts 1988, Nonlinear
Regression Analysis and Its Applications, section 2.3).
"""
from __future__ import annotations

import numpy as np

from calib.fit.measured.data import Measurements
from calib.fit.measured.regression import FitResult, sensitivities
from calib.fit.measured.scatter import REFERENCE_SCATTER
from calib.fit.measured.specimen import Specimen, law_parameters, predict_impacts, relative_residuals

DETERMINED_RELATIVE_SE = 0.10   # a parameter is determined by the data when its relative SE <= 10 %
SUGGESTED_WINDOWS = ((1.2, 3.0), (3.0, 10.0), (10.0, 30.0), (30.0, 100.0), (100.0, 300.0), (1.5, 300.0))
TESTS_PER_SUGGESTED_WINDOW = 10


def with_identifiability(result: FitResult, data: Measurements, specimen: Specimen) -> FitResult:
    """``result`` with its identifiability report (module doc)."""
    free = result.spec.free
    u, singular, vt = np.linalg.svd(result.jacobian, full_matrices=False)
    relative = {name: float(np.sqrt(result.covariance_log[i, i])) for i, name in enumerate(free)}
    determined = {name: rel <= DETERMINED_RELATIVE_SE for name, rel in relative.items()}
    weakest = {name: float(v) for name, v in zip(free, vt[-1] * np.sign(vt[-1][np.argmax(np.abs(vt[-1]))]))}
    said = [f"{name} to {100 * rel:.2g} %" for name, rel in relative.items()]
    text = f"the data determine {', '.join(said)} (relative standard errors)"
    scatter = result.scatter
    if scatter is not None and not scatter.estimable:
        at_reference = ", ".join(f"{name} to {100 * rel:.2g} %" for name, rel in scatter.se_at_reference.items())
        text = (f"the data lie on the law to its numerical precision (noise-free or identical values): their scatter "
                f"cannot be estimated, so the relative standard errors ({', '.join(said)}) are the law's numerical "
                f"precision, not a measurement's" + (f"; at 1 % scatter the same tests would determine {at_reference}"
                                                     if at_reference else ""))
    loose = [name for name, ok in determined.items() if not ok]
    if loose:
        combination = " ".join(f"{v:+.2f} ln {name}" for name, v in weakest.items())
        text += (f"; not determined (> {100 * DETERMINED_RELATIVE_SE:g} %): {', '.join(loose)}; the data "
                 f"barely change along {combination}")
    si = {name: result.standard_errors[name] / result.values[name] for name in ("Ca", "Kc")
          if result.standard_errors[name] is not None}
    if si:
        text += "; the law's " + ", ".join(f"{name} [{'m/N' if name == 'Ca' else '1/N'}] to {100 * rel:.2g} %"
                                           for name, rel in si.items())
    report = {"parameters": list(free), "singular_values": [float(s) for s in singular],
              "Ca_Kc_relative_se": si,
              "condition_number": float(singular[0] / singular[-1]), "relative_se": relative,
              "determined": determined, "weakest_combination": weakest, "summary": text}
    if data.impacts is not None:
        report["suggested_v_in"] = suggest_velocities(result, data, specimen)
        report["summary"] += "; " + report["suggested_v_in"]["summary"]
    return FitResult(**{**result.__dict__, "identifiability": report})


def suggest_velocities(result: FitResult, data: Measurements, specimen: Specimen) -> dict:
    """Which drop tests would determine sigma_Y, Ca_hat and Kc_hat together: for each candidate
    window of v_in / v_Y (``SUGGESTED_WINDOWS``), the relative standard errors expected from the
    present data (every group, weighted by its scatter) plus ten tests spread geometrically over
    the window at the present scatter of e: Cov = (J^T J)^-1 with the new rows appended to J.
    Noise-free data (calib.fit.measured.scatter): at 1 % scatter in every group instead."""
    names = ("sigma_y", "Ca_hat", "Kc_hat")
    centre = np.log([result.values[name] for name in names])
    pair = result.params.pair
    noise_free = result.scatter is not None and not result.scatter.estimable
    scale = {name: REFERENCE_SCATTER for name in result.group_scale} if noise_free else result.group_scale
    sizes = data.group_sizes()
    candidates = {w: pair.v_Y * np.geomspace(w[0], w[1], TESTS_PER_SUGGESTED_WINDOW) for w in SUGGESTED_WINDOWS}
    every_v = np.concatenate(list(candidates.values()))

    def residuals(log_theta) -> np.ndarray:        # the new tests are at fixed v_in [m/s]
        law = law_parameters(specimen, dict(zip(names, np.exp(log_theta))), None)
        groups = relative_residuals(data, law)
        present = [groups[name] / scale[name] for name in sizes]
        return np.concatenate(present + [np.log(predict_impacts(law, every_v)["e"]) / scale["e"]])

    try:
        jac = sensitivities(residuals, centre)
    except ValueError as exc:
        return {"summary": f"no suggestion of v_in ({exc})", "windows": []}
    n_present = sum(sizes.values())
    present = jac[:n_present]
    rows, start = [], n_present
    for window, v in candidates.items():
        block = jac[start:start + v.size]
        start += v.size
        try:
            expected = np.sqrt(np.diag(np.linalg.inv(present.T @ present + block.T @ block)))
        except np.linalg.LinAlgError:
            continue
        if not np.isfinite(expected).all():
            continue
        rows.append({"v_in_over_v_Y": list(window), "v_in": [float(v[0]), float(v[-1])],
                     "expected_relative_se": dict(zip(names, map(float, expected)))})
    if not rows:
        return {"summary": "no v_in window determines sigma_Y, Ca_hat and Kc_hat together", "windows": []}
    best = min(rows, key=lambda r: max(r["expected_relative_se"].values()))
    worst = max(best["expected_relative_se"].values())
    lo, hi = best["v_in"]
    tests = (f"{TESTS_PER_SUGGESTED_WINDOW} more drop tests at v_in = {lo:.3g}..{hi:.3g} m/s "
             f"({best['v_in_over_v_Y'][0]:g}..{best['v_in_over_v_Y'][1]:g} v_Y)"
             + (f" (at {100 * REFERENCE_SCATTER:g} % scatter)" if noise_free else ""))
    expected = ", ".join(f"{k} {100 * v:.2g} %" for k, v in best["expected_relative_se"].items())
    if worst <= DETERMINED_RELATIVE_SE:
        summary = f"{tests} would determine sigma_Y, Ca_hat and Kc_hat together (expected: {expected})"
    else:
        other = (["measure P_max in the drop tests"] if "P_max" not in sizes else []) + \
                (["add a force-approach curve"] if data.forces is None else []) + \
                ["give sigma_Y (a tensile test) with --free"]
        summary = (f"the most informative addition, {tests}, would still leave sigma_Y, Ca_hat, Kc_hat at "
                   f"{expected}: these data hardly separate them ({' or '.join(other)})")
    return {"best": best, "windows": rows, "summary": summary, "v_Y": float(pair.v_Y),
            "data_v_in_over_v_Y": [float(data.impacts.v_in.min() / pair.v_Y),
                                   float(data.impacts.v_in.max() / pair.v_Y)]}


def joint_relative_se(result: FitResult, data: Measurements, specimen: Specimen) -> dict | None:
    """Relative standard errors of sigma_Y, Ca_hat and Kc_hat fitted together, evaluated at
    ``result`` (Cov = s^2 (J^T J)^-1 of the three-parameter problem, s^2 = sum r_w^2 / (n - 3));
    None when the data cannot separate them at all (J^T J singular)."""
    names = ("sigma_y", "Ca_hat", "Kc_hat")
    centre = np.log([result.values[name] for name in names])
    sizes, scale = data.group_sizes(), result.group_scale

    def residuals(log_theta):
        groups = relative_residuals(data, law_parameters(specimen, dict(zip(names, np.exp(log_theta))), None))
        return np.concatenate([groups[name] / scale[name] for name in sizes])

    jac = sensitivities(residuals, centre)
    r = residuals(centre)
    if r.size <= len(names):
        return None
    try:
        covariance = np.linalg.inv(jac.T @ jac) * float(r @ r) / (r.size - len(names))
    except np.linalg.LinAlgError:
        return None
    se = np.sqrt(np.diag(covariance))
    return dict(zip(names, map(float, se))) if np.isfinite(se).all() else None

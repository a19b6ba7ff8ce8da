"""The two models of the vz law fitted to measurements and the choice between them (``nfdcal
fit-data``).

**Models** (``MODELS``):

    constrained     theta = (sigma_Y); Ca_hat, Kc_hat = the master table at (nu, E / sigma_Y)
                    (calib.fit.master_table), so one parameter carries the FE's knowledge; its
                    standard errors include the table's own uncertainty.
    free            theta = (Ca_hat, Kc_hat), and sigma_Y too when the data determine it: the
                    three-parameter fit is kept only if each relative standard error is at most
                    ``DETERMINED_RELATIVE_SE`` (calib.fit.measured.identifiability); otherwise
                    sigma_Y is held at the given value (or the constrained estimate) and the
                    identifiability report says why.

Each is one least-squares fit (calib.fit.measured.regression).

**Model choice: AICc** (Akaike 1974, IEEE Trans. Autom. Control 19, 716; small-sample correction
Hurvich & Tsai 1989, Biometrika 76, 297; Burnham & Anderson 2002, Model Selection and Multimodel
Inference, ch. 2). With Gaussian scatter of unknown variance per group,

    AIC  = sum_k n_k ln(RSS_k / n_k) + 2 K,   K = p + (number of groups)
    AICc = AIC + 2 K (K + 1) / (n - K - 1)

and the free model is preferred only when its AICc is lower by more than 2 (within 2 both are
supported, and the simpler one, which carries the master table's FE information, is kept).
AICc rather than BIC: the vz law is an approximation of the contact, never the true model that
BIC's consistency argument assumes; the question is which model predicts e at other speeds
better, which is what AIC estimates, and drop-test sets are small (10-30 tests), where AIC
without the correction over-fits. No verdict says that the data agree with a model whose
residual exceeds the data's scatter (plausible scatter, or the scatter between repeats:
calib.fit.measured.scatter); it says by how much instead.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from calib.fit.master_table import RELATIVE_UNCERTAINTY, MasterTable
from calib.fit.measured.data import Measurements
from calib.fit.measured.identifiability import DETERMINED_RELATIVE_SE, joint_relative_se, with_identifiability
from calib.fit.measured.regression import DataMismatch, FitResult, ModelSpec, fit_model, sensitivities, sigma_y_bounds
from calib.fit.measured.specimen import Specimen, law_parameters, relative_residuals
from nfdmodel import VZParams

MODELS = ("constrained", "free")
AICC_MARGIN = 2.0               # the free model must beat the constrained one's AICc by more than this


def _fit(data: Measurements, specimen: Specimen, spec: ModelSpec, start: dict, table: MasterTable | None,
         note: str = "") -> FitResult:
    """One least-squares fit with its identifiability report."""
    return with_identifiability(fit_model(data, specimen, spec, start, table, note), data, specimen)


def starting_sigma_y(data: Measurements, specimen: Specimen, table: MasterTable, given: float | None) -> float:
    """The constrained model's start [Pa]: ``given``, else the best of 25 values of E / sigma_Y
    spread geometrically over the master table (a coarse scan, so the fit starts in the right basin)."""
    low, high = sigma_y_bounds(specimen, "constrained", table)
    if given is not None:
        return float(np.clip(given, low, high))
    best, best_cost, refused = None, math.inf, {}
    for sigma_y in np.geomspace(low, high, 25):
        try:
            groups = relative_residuals(data, law_parameters(specimen, {"sigma_y": sigma_y}, table))
        except ValueError as exc:
            refused.setdefault(str(exc), float(sigma_y))
            continue
        cost = sum(float(np.mean(g**2)) for g in groups.values())
        if cost < best_cost:
            best, best_cost = float(sigma_y), cost
    if best is None:
        reason, at = next(iter(refused.items()))
        raise DataMismatch(f"{', '.join(data.files)}: the law cannot be evaluated for these data at any yield stress "
                           f"of the master table (sigma_Y {low:.3g}..{high:.3g} Pa); at {at:.3g} Pa: {reason}")
    return best


def check_table_covers(specimen: Specimen, table: MasterTable) -> None:
    """A ValueError when the specimen's nu lies outside the master table's nu range, naming both:
    the constrained model takes Ca_hat, Kc_hat from the table."""
    low, high = float(table.nu[0]), float(table.nu[-1])
    if not low <= specimen.nu <= high:
        raise ValueError(f"nu = {specimen.nu:g} is outside the master table's nu range {low:g}..{high:g}: the "
                         f"constrained model takes Ca_hat, Kc_hat from that table; fit the free model (--free with "
                         f"--sigma-y, the yield stress from a tensile test) or calibrate this material by FE "
                         f"(nfdcal calibrate)")


def fit_constrained(data: Measurements, specimen: Specimen, table: MasterTable,
                    sigma_y_start: float | None = None) -> FitResult:
    """sigma_Y alone; Ca_hat, Kc_hat from the master table at (nu, E / sigma_Y); the standard
    errors include the table's own uncertainty (:func:`with_table_uncertainty`)."""
    check_table_covers(specimen, table)
    start = starting_sigma_y(data, specimen, table, sigma_y_start)
    result = _fit(data, specimen, ModelSpec("constrained", ("sigma_y",)), {"sigma_y": start}, table)
    return with_table_uncertainty(result, data, specimen, table)


def with_table_uncertainty(result: FitResult, data: Measurements, specimen: Specimen,
                           table: MasterTable) -> FitResult:
    """The constrained model's standard errors with the master table's own uncertainty added.

    The table's Ca_hat, Kc_hat carry relative errors eps_c, eps_k (standard uncertainties u_c,
    u_k: calib.fit.master_table.RELATIVE_UNCERTAINTY, systematic, independent). The fitted
    ln sigma_Y moves with them by s_c eps_c + s_k eps_k, s_j = -(J_s . J_j) / (J_s . J_s) (the
    least-squares response, J the weighted residuals' derivatives in ln sigma_Y, ln Ca_hat,
    ln Kc_hat at the fit). Each reported quantity q (sigma_Y, Ca_hat, Kc_hat, Ca, Kc) then has
    Var ln q = (dq/d eta)^2 Var_fit(ln sigma_Y) + (dq/d eps_c)^2 u_c^2 + (dq/d eps_k)^2 u_k^2, the
    derivatives by forward differences of the chain eta, eps -> sigma_Y -> table -> q
    (calib.fit.measured.regression.sensitivities)."""
    sizes, scale = data.group_sizes(), result.group_scale
    log_sigma = math.log(result.values["sigma_y"])
    table_values = {"Ca_hat": result.values["Ca_hat"], "Kc_hat": result.values["Kc_hat"]}

    def residuals(theta):              # ln sigma_Y, ln Ca_hat, ln Kc_hat, the table bypassed
        values = dict(zip(("sigma_y", "Ca_hat", "Kc_hat"), np.exp(theta)))
        groups = relative_residuals(data, law_parameters(specimen, values, None))
        return np.concatenate([groups[name] / scale[name] for name in sizes])

    centre = np.array([log_sigma, math.log(table_values["Ca_hat"]), math.log(table_values["Kc_hat"])])
    jac = sensitivities(residuals, centre)
    along = float(jac[:, 0] @ jac[:, 0])
    if not along > 0.0:
        return result
    response = -(jac[:, 1:].T @ jac[:, 0]) / along          # s_c, s_k

    def reported(noise):                 # (eta, eps_c, eps_k) -> ln of sigma_Y, Ca_hat, Kc_hat, Ca, Kc
        sigma_y = math.exp(log_sigma + noise[0] + response @ noise[1:])
        law = law_parameters(specimen, {"sigma_y": sigma_y}, table)
        Ca_hat, Kc_hat = law.Ca_hat * math.exp(noise[1]), law.Kc_hat * math.exp(noise[2])
        law = VZParams.from_dimensionless(law.pair, Ca_hat, Kc_hat)
        return np.log([sigma_y, Ca_hat, Kc_hat, law.Ca, law.Kc])

    gradient = sensitivities(reported, np.zeros(3))
    variance = np.array([float(result.covariance_log[0, 0]), RELATIVE_UNCERTAINTY["Ca_hat"] ** 2,
                         RELATIVE_UNCERTAINTY["Kc_hat"] ** 2])
    relative = np.sqrt(gradient**2 @ variance)
    names = ("sigma_y", "Ca_hat", "Kc_hat", "Ca", "Kc")
    errors = {**result.standard_errors,
              **{name: float(result.values[name] * r) for name, r in zip(names, relative)}}
    note = (result.note + " " if result.note else "") + (
        f"standard errors include the master table's own uncertainty ({100 * RELATIVE_UNCERTAINTY['Ca_hat']:.1f} % "
        f"Ca_hat, {100 * RELATIVE_UNCERTAINTY['Kc_hat']:.1f} % Kc_hat)")
    return dataclasses.replace(result, standard_errors=errors, note=note)


def fit_free(data: Measurements, specimen: Specimen, sigma_y: float, start: dict | None = None,
             table: MasterTable | None = None, free_sigma_y: bool | None = None,
             sigma_y_source: str = "given") -> FitResult:
    """Ca_hat, Kc_hat, and sigma_Y when the data determine it (module doc). First Ca_hat, Kc_hat
    with sigma_Y held at ``sigma_y`` [Pa]; then, when the three-parameter problem evaluated there
    has every relative standard error <= DETERMINED_RELATIVE_SE (or ``free_sigma_y`` is True), all
    three, kept if they stay determined. ``free_sigma_y`` False: sigma_Y held. ``start``: the
    starting Ca_hat, Kc_hat (default: the master table at sigma_Y, else the paper's)."""
    if start is None:
        start = {"Ca_hat": 0.0258, "Kc_hat": 0.0109}
        if table is not None:
            try:
                start = dict(zip(("Ca_hat", "Kc_hat"), table.lookup(specimen.nu, specimen.E / sigma_y)))
            except ValueError:
                pass
    held_note = f"sigma_Y held at {sigma_y:.4g} Pa ({sigma_y_source})"
    held = _fit(data, specimen, ModelSpec("free", ("Ca_hat", "Kc_hat"), {"sigma_y": sigma_y}),
                     start, table, note=held_note)
    if free_sigma_y is False:
        return held
    joint = joint_relative_se(held, data, specimen) if data.n_points > 3 else None
    if joint is None and not free_sigma_y:
        return FitResult(**{**held.__dict__, "note": f"{held_note}: the data cannot fit sigma_Y with Ca_hat, Kc_hat"})
    said = ", ".join(f"{name} to {100 * rel:.2g} %" for name, rel in joint.items()) if joint else ""
    if free_sigma_y or max(joint.values()) <= DETERMINED_RELATIVE_SE:
        try:
            three = _fit(data, specimen, ModelSpec("free", ("sigma_y", "Ca_hat", "Kc_hat")), {**held.values}, table,
                         note="sigma_Y fitted with Ca_hat, Kc_hat (the data determine all three)")
        except DataMismatch as exc:
            if free_sigma_y:
                raise
            return FitResult(**{**held.__dict__, "note": f"{held_note}: fitted together with Ca_hat, Kc_hat: {exc}"})
        if free_sigma_y or all(three.identifiability["determined"].values()):
            return three
        said = ", ".join(f"{name} to {100 * rel:.2g} %" for name, rel in three.identifiability["relative_se"].items())
    return FitResult(**{**held.__dict__, "note": f"{held_note}: fitted together, the data would determine {said} "
                                                 f"(relative standard errors; > {100 * DETERMINED_RELATIVE_SE:g} % is "
                                                 f"not determined)"})


@dataclass(frozen=True)
class ModelChoice:
    """Both fits (``free`` None when the data cannot carry it: ``free_error`` says why), the model
    used, the one AICc prefers, and why in words."""

    constrained: FitResult | None
    free: FitResult | None
    used: str
    preferred: str | None
    why: str
    free_error: str = ""

    @property
    def result(self) -> FitResult:
        return self.free if self.used == "free" else self.constrained


def misfit(fit: FitResult) -> str:
    """In words, how the fit's residual exceeds the data's scatter (calib.fit.measured.scatter),
    or "" when it does not."""
    scatter = fit.scatter
    if scatter is None:
        return ""
    if not scatter.plausible:
        return "far above any plausible scatter (" + scatter.describe_implausible() + ")"
    if not scatter.within_repeats:
        return "beyond the scatter between repeats (" + scatter.describe_lack_of_fit() + ")"
    return ""


def compare(constrained: FitResult | None, free: FitResult | None, requested: str,
            free_error: str = "", constrained_error: str = "") -> ModelChoice:
    """The model used is the one ``requested``; AICc's verdict (module doc) is reported in words."""
    reason = "requested (--free)" if requested == "free" else "the default (the master table's constants)"
    if constrained is None or free is None:
        missing = "constrained" if constrained is None else "free"
        error = constrained_error if constrained is None else free_error
        return ModelChoice(constrained, free, requested, None,
                           f"{requested} model: {reason}; the {missing} model could not be fitted ({error}), so "
                           f"no comparison", free_error)
    if constrained.aicc is None or free.aicc is None:
        a, b, label = constrained.aic, free.aic, "AIC"
    else:
        a, b, label = constrained.aicc, free.aicc, "AICc"
    difference = a - b
    preferred = "free" if difference > AICC_MARGIN else "constrained"
    if preferred == "free":
        verdict = (f"the data favour the free model ({label} {b:.1f} against {a:.1f} constrained, lower by "
                   f"{difference:.1f} > {AICC_MARGIN:g}): the measured contact differs from the master table's "
                   f"Ca_hat, Kc_hat beyond the scatter")
        if misfit(free):
            verdict += f"; but the free model too leaves residuals {misfit(free)}"
    elif misfit(constrained):
        verdict = (f"the free model's extra parameters do not lower {label} by more than {AICC_MARGIN:g} ({a:.1f} "
                   f"constrained, {b:.1f} free), but the constrained model leaves residuals {misfit(constrained)}: "
                   f"these data do not agree with the master table's Ca_hat, Kc_hat"
                   + (", nor with the free model's" if misfit(free) else ""))
    else:
        verdict = (f"the constrained model suffices ({label} {a:.1f} against {b:.1f} free; the free model's "
                   f"extra parameters do not lower it by more than {AICC_MARGIN:g}): the data agree with the "
                   f"master table's Ca_hat, Kc_hat")
    advice = ""
    if preferred != requested:
        advice = "; rerun with --free to use it" if preferred == "free" else "; the constrained model would do"
    return ModelChoice(constrained, free, requested, preferred, f"{requested} model: {reason}; {verdict}{advice}",
                       free_error)


def fit_measurements(data: Measurements, specimen: Specimen, table: MasterTable, requested: str = "constrained",
                     sigma_y: float | None = None) -> ModelChoice:
    """Both models fitted to ``data`` (module doc), the ``requested`` one used. ``sigma_y`` [Pa]:
    the constrained fit's start and the free fit's held value (default: the constrained estimate)."""
    if requested not in MODELS:
        raise ValueError(f"model must be one of {', '.join(MODELS)}, got {requested!r}")
    constrained, constrained_error, mismatch = None, "", False
    try:
        constrained = fit_constrained(data, specimen, table, sigma_y)
    except ValueError as exc:
        if requested == "constrained":
            raise
        constrained_error, mismatch = str(exc), isinstance(exc, DataMismatch)
    free, free_error = None, ""
    try:
        held = sigma_y if sigma_y is not None else (constrained.values["sigma_y"] if constrained else None)
        if held is None:
            raise (DataMismatch if mismatch else ValueError)(
                f"give --sigma-y (the constrained model, which would estimate it, could not be fitted: "
                f"{constrained_error})")
        start = ({"Ca_hat": constrained.values["Ca_hat"], "Kc_hat": constrained.values["Kc_hat"]}
                 if constrained else None)
        free = fit_free(data, specimen, held, start, table,
                        sigma_y_source="given" if sigma_y is not None else "the constrained model's estimate")
    except ValueError as exc:
        if requested == "free":
            raise
        free_error = str(exc)
    return compare(constrained, free, requested, free_error, constrained_error)

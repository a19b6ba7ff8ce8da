"""The vz law's parameters fitted to measurements: drop tests e(v_in) and quasi-static
force-approach curves of a sphere on a rigid flat (``nfdcal fit-data``).

**Data** (CSV, SI units, one header line, lines starting with '#' are comments):

    impacts         v_in [m/s] > 0, e [-] in (0, 1]; optional P_max [N] > 0, contact_time [s] > 0
                    (an empty cell: not measured in that test). One row per drop test, repeats
                    at the same v_in allowed.
    force-approach  approach [m], force [N] along one or more load-unload cycles of one
                    contact, in the order measured; optional test (a label): rows with the same
                    label are one history on a fresh (virgin) specimen, in file order.

**The law** (README, The model; Vu-Quoc & Zhang 1999, Proc. R. Soc. Lond. A 455, eqs. 2.5,
3.4-3.7, 3.19-3.22), for a sphere of radius R on a rigid flat (R* = R, E* = E / (1 - nu^2)):

    P_Y = pi^3 R*^2 (A_Y(nu) sigma_Y)^3 / (6 E*^2) [N],   a_Y = (3 P_Y R* / (4 E*))^(1/3) [m]
    a_p = Ca <P - P_Y>,  C_R = 1 + Kc <P - P_Y>,  Ca = Ca_hat a_Y / P_Y [m/N],  Kc = Kc_hat / P_Y [1/N]

What the law predicts for the data:

    impacts         the exact quasi-static impact by energy balance (nfdmodel.collision_reference):
                    (1/2) m v_in^2 = W_l(delta_max), e = sqrt(W_u / W_l), P_max, contact time
                    t_load + t_unload. The law is rate-independent, so this is what a time-stepped
                    collision converges to (``collide``, O(dt^2)) and what a drop test measures.
                    Scaled, e = e(v_in / v_Y; Ca_hat, Kc_hat) exactly, with
                    v_Y = sqrt(4 P_Y delta_Y / (5 m)) proportional to sigma_Y^(5/2).
    force-approach  the law driven along each test's measured approach
                    (calib.fit.calibration.drive_law, the driver of the FE force fit).

**Models** (``MODELS``):

    constrained     theta = (sigma_Y); Ca_hat, Kc_hat = the master table at (nu, E / sigma_Y)
                    (calib.fit.master_table), so one parameter carries the FE's knowledge.
    free            theta = (Ca_hat, Kc_hat), and sigma_Y too when the data determine it: the
                    three-parameter fit is kept only if each relative standard error is at most
                    ``DETERMINED_RELATIVE_SE``; otherwise sigma_Y is held at the given value (or
                    the constrained estimate) and the identifiability report says why.

**Least squares** (scipy.optimize.least_squares, trust-region reflective, theta in log space
so every parameter stays positive, inside ``BOUNDS``). Residuals are relative,
r = (y_law - y) / y for e, P_max and the contact time, and r = (P_law - P) / max(|P|, P_floor)
for the forces with P_floor = 0.05 x the smallest test's peak force (the FE force fit's
weighting); each group k (e, P_max, contact_time, force) is weighted by 1 / s_k, s_k its RMS
residual (re-estimated twice), so groups of different scatter count by their precision.
Standard errors (Bates & Watts 1988, Nonlinear Regression Analysis and Its Applications,
section 2.3):

    Cov(log theta) = s^2 (J^T J)^-1,   s^2 = sum(r_w^2) / (n - p),   J = d r_w / d log theta
    SE(theta_j) = theta_j SE(log theta_j),   Corr_ij = Cov_ij / sqrt(Cov_ii Cov_jj)

and derived quantities (Ca [m/N], Kc [1/N], Ca_hat of the constrained model) by the delta method
through their gradients in log theta.

**Identifiability.** J's columns are relative sensitivities (d r / d ln theta), so its singular
values compare parameters without units: the condition number s_max / s_min says how nearly
some combination of parameters leaves the data unchanged (the right singular vector of s_min
names it), and a parameter is *determined* when its relative standard error is at most 10 %.
For impacts the report also names the v_in window whose tests would determine all three
(sigma_Y, Ca_hat, Kc_hat): the expected standard errors of the present data plus ten tests spread
geometrically over each candidate window of v_in / v_Y, at the present scatter.

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
without the correction over-fits.
"""
from __future__ import annotations

import dataclasses
import math
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy import optimize

from calib.fit.calibration import drive_law
from calib.fit.master_table import MasterTable
from calib.fit.measured_data import ForceApproachData, ImpactData
from nfdmodel import (CalibrationWindow, ContactPair, Material, PlausibilityWarning, RangeWarning, VZParams,
                      collision_reference)

MODELS = ("constrained", "free")
DETERMINED_RELATIVE_SE = 0.10   # a parameter is determined by the data when its relative SE <= 10 %
AICC_MARGIN = 2.0               # the free model must beat the constrained one's AICc by more than this
# log-space bounds: E / sigma_Y as the FE calibration accepts it (20..1e4; the constrained model:
# the master table's 50..5000); the dimensionless constants around the FE's 0.024-0.034, 0.010-0.016
E_OVER_SIGMA_Y_RANGE = (20.0, 1e4)
BOUNDS = {"Ca_hat": (1e-3, 1.0), "Kc_hat": (1e-5, 1.0)}
SUGGESTED_WINDOWS = ((1.2, 3.0), (3.0, 10.0), (10.0, 30.0), (30.0, 100.0), (100.0, 300.0), (1.5, 300.0))
TESTS_PER_SUGGESTED_WINDOW = 10
_PENALTY = 10.0                 # residual of an inadmissible trial point (the step is rejected)


# ---------------------------------------------------------------- the specimen and the law

@dataclass(frozen=True)
class Specimen:
    """What the user knows: E [Pa], nu [-], R [m], rho [kg/m^3] of the sphere, and how it was
    tested: ``two_spheres`` False, a sphere on a massive rigid flat (R* = R, E* = E/(1 - nu^2),
    m* = m); True, head-on impacts of two identical spheres (R* = R/2, E* = E/(2(1 - nu^2)),
    m* = m/2, v_in the relative speed, the approach that of the two centres). The law's
    dimensionless constants Ca_hat, Kc_hat are the material's either way (a << R)."""

    E: float
    nu: float
    R: float
    rho: float
    two_spheres: bool = False

    def material(self, sigma_y: float) -> Material:
        return Material(self.E, self.nu, sigma_y, self.rho)

    def pair(self, sigma_y: float) -> ContactPair:
        """The tested contact pair."""
        with warnings.catch_warnings():          # the radius was checked (and warned about) once
            warnings.simplefilter("ignore", PlausibilityWarning)
            material = self.material(sigma_y)
            if self.two_spheres:
                return ContactPair.sphere_sphere(material, self.R, material, self.R)
            return ContactPair.sphere_flat(material, self.R)

    def sphere_flat_params(self, params: VZParams) -> VZParams:
        """The fitted law for this sphere on a rigid flat (what a parameter file describes): the
        same sigma_Y, Ca_hat, Kc_hat and window (in P/P_Y), the pair's own P_Y and a_Y."""
        if not self.two_spheres:
            return params
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", PlausibilityWarning)
            pair = ContactPair.sphere_flat(self.material(params.pair.sigma_y), self.R)
        return VZParams.from_dimensionless(pair, params.Ca_hat, params.Kc_hat, params.window)

    def sigma_y_bounds(self, model: str, table: MasterTable | None) -> tuple[float, float]:
        """[Pa]: E / sigma_Y inside the master table (constrained) or 20..1e4 (free)."""
        if model == "constrained" and table is not None:
            low, high = float(table.E_over_sigma_y[0]), float(table.E_over_sigma_y[-1])
        else:
            low, high = E_OVER_SIGMA_Y_RANGE
        return self.E / high * (1 + 1e-9), self.E / low * (1 - 1e-9)


def law_parameters(specimen: Specimen, values: dict, table: MasterTable | None) -> VZParams:
    """VZParams from ``values`` (sigma_y [Pa], and Ca_hat, Kc_hat; the master table's at
    (nu, E / sigma_Y) when absent)."""
    pair = specimen.pair(values["sigma_y"])
    if "Ca_hat" in values:
        Ca_hat, Kc_hat = values["Ca_hat"], values["Kc_hat"]
    else:
        Ca_hat, Kc_hat = table.lookup(specimen.nu, specimen.E / values["sigma_y"])
    return VZParams.from_dimensionless(pair, Ca_hat, Kc_hat)


def predict_impacts(params: VZParams, v_in) -> dict:
    """e [-], P_max [N], contact_time [s] of sphere-on-flat impacts at ``v_in`` [m/s] (module doc)."""
    reference = collision_reference("vz", params, v_in)
    return {"e": reference.restitution, "P_max": reference.P_max, "contact_time": reference.contact_time_estimate}


def predict_forces(params: VZParams, forces: ForceApproachData) -> list[np.ndarray]:
    """The law's force [N] along each test's measured approach (a virgin contact per test)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RangeWarning)
        return [drive_law("vz", params, approach)[0] for _, approach, _ in forces.tests]


@dataclass(frozen=True)
class Measurements:
    """Everything measured on one specimen: drop tests and/or force-approach curves."""

    impacts: ImpactData | None = None
    forces: ForceApproachData | None = None

    def __post_init__(self):
        if self.impacts is None and self.forces is None:
            raise ValueError("no data: give drop tests (impacts) or force-approach curves, or both")

    @property
    def n_points(self) -> int:
        return sum(d.n_points for d in (self.impacts, self.forces) if d is not None)

    @property
    def files(self) -> list[str]:
        return [d.path for d in (self.impacts, self.forces) if d is not None]

    def relative_residuals(self, params: VZParams) -> dict[str, np.ndarray]:
        """Per group (e, P_max, contact_time, force): the relative residuals of the law (module doc)."""
        out = {}
        if self.impacts is not None:
            predicted = predict_impacts(params, self.impacts.v_in)
            out["e"] = predicted["e"] / self.impacts.e - 1.0
            for name in ("P_max", "contact_time"):
                measured = getattr(self.impacts, name)
                if measured is not None and np.isfinite(measured).any():
                    seen = np.isfinite(measured)
                    out[name] = predicted[name][seen] / measured[seen] - 1.0
        if self.forces is not None:
            floor = self.forces.force_floor
            predicted = predict_forces(params, self.forces)
            out["force"] = np.concatenate([(p - f) / np.maximum(np.abs(f), floor)
                                           for p, (_, _, f) in zip(predicted, self.forces.tests)])
        return out

    def group_sizes(self) -> dict[str, int]:
        sizes = {}
        if self.impacts is not None:
            sizes["e"] = int(self.impacts.e.size)
            for name in ("P_max", "contact_time"):
                measured = getattr(self.impacts, name)
                if measured is not None and np.isfinite(measured).any():
                    sizes[name] = int(np.isfinite(measured).sum())
        if self.forces is not None:
            sizes["force"] = self.forces.n_points
        return sizes


# ---------------------------------------------------------------- one least-squares fit

@dataclass(frozen=True)
class ModelSpec:
    """A model to fit: its name, the parameters fitted (in log space) and those held fixed."""

    model: str
    free: tuple
    fixed: dict = field(default_factory=dict)

    def values(self, log_theta) -> dict:
        return {**self.fixed, **dict(zip(self.free, np.exp(np.asarray(log_theta, dtype=float))))}


@dataclass(frozen=True)
class FitResult:
    """One fitted model (SI; the module doc defines every figure).

    values: sigma_y [Pa], Ca_hat, Kc_hat, Ca [m/N], Kc [1/N]; standard_errors: the same keys, None
    for a value held fixed; correlation: between the fitted parameters ``spec.free``;
    residuals: relative, per group; group_scale: s_k; rss: unweighted per group; aic, aicc;
    identifiability: the report; params: the law (VZParams, with the data's window).
    """

    spec: ModelSpec
    values: dict
    standard_errors: dict
    covariance_log: np.ndarray
    correlation: np.ndarray
    residuals: dict
    group_scale: dict
    rss: dict
    n_points: int
    aic: float
    aicc: float | None
    identifiability: dict
    params: VZParams
    note: str = ""

    @property
    def rms_residual(self) -> float:
        everything = np.concatenate(list(self.residuals.values()))
        return float(np.sqrt(np.mean(everything**2)))


def _jacobian(fun, x, lower, upper, step=1e-4) -> np.ndarray:
    """Central differences of ``fun`` at ``x`` (one-sided at a bound), columns per parameter."""
    x = np.asarray(x, dtype=float)
    columns = []
    for j in range(x.size):
        up, down = x.copy(), x.copy()
        up[j] = min(x[j] + step, upper[j])
        down[j] = max(x[j] - step, lower[j])
        columns.append((fun(up) - fun(down)) / (up[j] - down[j]))
    return np.column_stack(columns)


def _spec_bounds(spec: ModelSpec, specimen: Specimen, table) -> tuple[np.ndarray, np.ndarray]:
    bounds = {"sigma_y": specimen.sigma_y_bounds(spec.model, table), **BOUNDS}
    lower = np.log([bounds[name][0] for name in spec.free])
    upper = np.log([bounds[name][1] for name in spec.free])
    return lower, upper


def fit_model(data: Measurements, specimen: Specimen, spec: ModelSpec, start: dict,
              table: MasterTable | None, note: str = "") -> FitResult:
    """Least squares of ``spec`` to ``data`` from ``start`` (module doc); a ValueError when the data
    hold no more points than the model has parameters."""
    p = len(spec.free)
    if data.n_points <= p:
        raise ValueError(f"{', '.join(data.files)}: {data.n_points} data point(s), the {spec.model} model has {p} "
                         f"parameter(s) ({', '.join(spec.free)}): need at least {p + 1} rows to fit and "
                         f"estimate the scatter")
    lower, upper = _spec_bounds(spec, specimen, table)
    sizes = data.group_sizes()
    scale = {name: 1.0 for name in sizes}

    def parameters(log_theta) -> VZParams:
        return law_parameters(specimen, spec.values(log_theta), table)

    def weighted(log_theta) -> np.ndarray:
        try:
            groups = data.relative_residuals(parameters(log_theta))
        except ValueError:                         # inadmissible trial constants: reject the step
            return np.full(sum(sizes.values()), _PENALTY)
        return np.concatenate([groups[name] / scale[name] for name in sizes])

    x = np.clip(np.log([start[name] for name in spec.free]), lower + 1e-12, upper - 1e-12)
    for _ in range(3 if len(sizes) > 1 else 1):  # re-weight the groups by their scatter
        solution = optimize.least_squares(weighted, x, bounds=(lower, upper), method="trf", x_scale=1.0,
                                          diff_step=1e-6, xtol=1e-10, ftol=1e-12, gtol=1e-12)
        x = solution.x
        groups = data.relative_residuals(parameters(x))
        scale = {name: max(float(np.sqrt(np.mean(groups[name] ** 2))), 1e-12) for name in sizes}
    params = parameters(x)
    groups = data.relative_residuals(params)
    residual = np.concatenate([groups[name] / scale[name] for name in sizes])
    jac = _jacobian(weighted, x, lower, upper)
    n = residual.size
    variance = float(residual @ residual) / (n - p)
    singular = np.linalg.svd(jac, compute_uv=False)
    if not (singular.size and singular[-1] > 1e-12 * max(singular[0], 1e-300)):
        raise ValueError(f"the {spec.model} model's parameters ({', '.join(spec.free)}) are not determined by "
                         f"{', '.join(data.files)}: the law's prediction does not change with "
                         f"{'some of them' if p > 1 else spec.free[0]} over these data (are all tests elastic, "
                         f"e = 1?)")
    covariance = np.linalg.inv(jac.T @ jac) * variance
    sd = np.sqrt(np.diag(covariance))
    correlation = covariance / np.outer(sd, sd)

    def derived(log_theta) -> np.ndarray:
        law = parameters(log_theta)
        return np.log([law.pair.sigma_y, law.Ca_hat, law.Kc_hat, law.Ca, law.Kc])

    names = ("sigma_y", "Ca_hat", "Kc_hat", "Ca", "Kc")
    gradient = _jacobian(derived, x, lower, upper)
    derived_sd = np.sqrt(np.maximum(np.einsum("ij,jk,ik->i", gradient, covariance, gradient), 0.0))
    values = dict(zip(names, np.exp(derived(x))))
    values = {k: float(v) for k, v in values.items()}
    standard_errors = {k: (float(values[k] * s) if np.any(np.abs(gradient[i]) > 1e-9) else None)
                       for i, (k, s) in enumerate(zip(names, derived_sd))}
    rss = {name: float(groups[name] @ groups[name]) for name in sizes}
    K = p + len(sizes)
    aic = float(sum(sizes[k] * math.log(max(rss[k] / sizes[k], 1e-300)) for k in sizes) + 2 * K)
    aicc = aic + 2.0 * K * (K + 1) / (n - K - 1) if n - K - 1 > 0 else None
    params = VZParams(params.pair, params.Ca, params.Kc, data_window(params, data))
    result = FitResult(spec, values, standard_errors, covariance, correlation, groups, scale, rss, n, aic, aicc,
                       {}, params, note)
    return _with_identifiability(result, jac, data, specimen, table)


def data_window(params: VZParams, data: Measurements) -> CalibrationWindow:
    """The loads the data reach, as P / P_Y: the law's P_max of each drop test and the measured
    forces above P_Y; a/R* the law's contact radius at the top (nfdmodel.window)."""
    P_Y = params.pair.P_Y
    loads = []
    if data.impacts is not None:
        loads.append(predict_impacts(params, data.impacts.v_in)["P_max"])
    if data.forces is not None:
        loads.extend(force for _, _, force in data.forces.tests)
    loads = np.concatenate(loads) / P_Y
    above = loads[loads > 1.0]
    low = float(above.min()) if above.size else 1.0
    high = max(float(loads.max()), low)
    a_max = float(params.contact_radius_at(high * P_Y)) / params.pair.R_star
    sources = ", ".join(Path(f).name for f in data.files)
    return CalibrationWindow(low, high, min(a_max, 1.0), f"measurements ({sources}), fitted by nfdcal fit-data")


# ---------------------------------------------------------------- identifiability

def _with_identifiability(result: FitResult, jac: np.ndarray, data: Measurements, specimen: Specimen,
                          table) -> FitResult:
    """``result`` with its identifiability report (module doc)."""
    free = result.spec.free
    u, singular, vt = np.linalg.svd(jac, full_matrices=False)
    relative = {name: float(np.sqrt(result.covariance_log[i, i])) for i, name in enumerate(free)}
    determined = {name: rel <= DETERMINED_RELATIVE_SE for name, rel in relative.items()}
    weakest = {name: float(v) for name, v in zip(free, vt[-1] * np.sign(vt[-1][np.argmax(np.abs(vt[-1]))]))}
    said = [f"{name} to {100 * rel:.2g} %" for name, rel in relative.items()]
    text = f"the data determine {', '.join(said)} (relative standard errors)"
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
    the window at the present scatter of e: Cov = (J^T J)^-1 with the new rows appended to J."""
    names = ("sigma_y", "Ca_hat", "Kc_hat")
    centre = np.log([result.values[name] for name in names])
    pair = result.params.pair
    scale = result.group_scale
    sizes = data.group_sizes()
    candidates = {w: pair.v_Y * np.geomspace(w[0], w[1], TESTS_PER_SUGGESTED_WINDOW) for w in SUGGESTED_WINDOWS}
    every_v = np.concatenate(list(candidates.values()))

    def residuals(log_theta) -> np.ndarray:        # the new tests are at fixed v_in [m/s]
        law = law_parameters(specimen, dict(zip(names, np.exp(log_theta))), None)
        groups = data.relative_residuals(law)
        present = [groups[name] / scale[name] for name in sizes]
        return np.concatenate(present + [np.log(predict_impacts(law, every_v)["e"]) / scale["e"]])

    try:
        jac = _jacobian(residuals, centre, centre - 1.0, centre + 1.0)
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
             f"({best['v_in_over_v_Y'][0]:g}..{best['v_in_over_v_Y'][1]:g} v_Y)")
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


# ---------------------------------------------------------------- the two models and the choice

def starting_sigma_y(data: Measurements, specimen: Specimen, table: MasterTable, given: float | None) -> float:
    """The constrained model's start [Pa]: ``given``, else the best of 25 values of E / sigma_Y
    spread geometrically over the master table (a coarse scan, so the fit starts in the right basin)."""
    low, high = specimen.sigma_y_bounds("constrained", table)
    if given is not None:
        return float(np.clip(given, low, high))
    best, best_cost = None, math.inf
    for sigma_y in np.geomspace(low, high, 25):
        try:
            groups = data.relative_residuals(law_parameters(specimen, {"sigma_y": sigma_y}, table))
        except ValueError:
            continue
        cost = sum(float(np.mean(g**2)) for g in groups.values())
        if cost < best_cost:
            best, best_cost = float(sigma_y), cost
    if best is None:
        raise ValueError("no yield stress inside the master table's range reproduces these data")
    return best


def fit_constrained(data: Measurements, specimen: Specimen, table: MasterTable,
                    sigma_y_start: float | None = None) -> FitResult:
    """sigma_Y alone; Ca_hat, Kc_hat from the master table at (nu, E / sigma_Y); the standard
    errors include the table's own uncertainty (:func:`with_table_uncertainty`)."""
    start = starting_sigma_y(data, specimen, table, sigma_y_start)
    result = fit_model(data, specimen, ModelSpec("constrained", ("sigma_y",)), {"sigma_y": start}, table)
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
    derivatives by central differences of the chain eta, eps -> sigma_Y -> table -> q."""
    from calib.fit.master_table import RELATIVE_UNCERTAINTY

    sizes, scale = data.group_sizes(), result.group_scale
    log_sigma = math.log(result.values["sigma_y"])
    table_values = {"Ca_hat": result.values["Ca_hat"], "Kc_hat": result.values["Kc_hat"]}

    def residuals(theta):              # ln sigma_Y, ln Ca_hat, ln Kc_hat, the table bypassed
        values = dict(zip(("sigma_y", "Ca_hat", "Kc_hat"), np.exp(theta)))
        groups = data.relative_residuals(law_parameters(specimen, values, None))
        return np.concatenate([groups[name] / scale[name] for name in sizes])

    centre = np.array([log_sigma, math.log(table_values["Ca_hat"]), math.log(table_values["Kc_hat"])])
    jac = _jacobian(residuals, centre, centre - 1.0, centre + 1.0)
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

    step = 1e-5
    gradient = np.column_stack([(reported(step * e) - reported(-step * e)) / (2 * step) for e in np.eye(3)])
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


def joint_relative_se(result: FitResult, data: Measurements, specimen: Specimen) -> dict | None:
    """Relative standard errors of sigma_Y, Ca_hat and Kc_hat fitted together, evaluated at
    ``result`` (Cov = s^2 (J^T J)^-1 of the three-parameter problem, s^2 = sum r_w^2 / (n - 3));
    None when the data cannot separate them at all (J^T J singular)."""
    names = ("sigma_y", "Ca_hat", "Kc_hat")
    centre = np.log([result.values[name] for name in names])
    sizes, scale = data.group_sizes(), result.group_scale

    def residuals(log_theta):
        groups = data.relative_residuals(law_parameters(specimen, dict(zip(names, np.exp(log_theta))), None))
        return np.concatenate([groups[name] / scale[name] for name in sizes])

    jac = _jacobian(residuals, centre, centre - 1.0, centre + 1.0)
    r = residuals(centre)
    if r.size <= len(names):
        return None
    try:
        covariance = np.linalg.inv(jac.T @ jac) * float(r @ r) / (r.size - len(names))
    except np.linalg.LinAlgError:
        return None
    se = np.sqrt(np.diag(covariance))
    return dict(zip(names, map(float, se))) if np.isfinite(se).all() else None


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
    held = fit_model(data, specimen, ModelSpec("free", ("Ca_hat", "Kc_hat"), {"sigma_y": sigma_y}),
                     start, table, note=held_note)
    if free_sigma_y is False:
        return held
    joint = joint_relative_se(held, data, specimen) if data.n_points > 3 else None
    if joint is None and not free_sigma_y:
        return FitResult(**{**held.__dict__, "note": f"{held_note}: the data cannot fit sigma_Y with Ca_hat, Kc_hat"})
    said = ", ".join(f"{name} to {100 * rel:.2g} %" for name, rel in joint.items()) if joint else ""
    if free_sigma_y or max(joint.values()) <= DETERMINED_RELATIVE_SE:
        three = fit_model(data, specimen, ModelSpec("free", ("sigma_y", "Ca_hat", "Kc_hat")),
                          {**held.values}, table, note="sigma_Y fitted with Ca_hat, Kc_hat (the data determine all three)")
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
    constrained, constrained_error = None, ""
    try:
        constrained = fit_constrained(data, specimen, table, sigma_y)
    except ValueError as exc:
        if requested == "constrained":
            raise
        constrained_error = str(exc)
    free, free_error = None, ""
    try:
        held = sigma_y if sigma_y is not None else (constrained.values["sigma_y"] if constrained else None)
        if held is None:
            raise ValueError("give --sigma-y (the constrained model, which would estimate it, could not be fitted)")
        start = ({"Ca_hat": constrained.values["Ca_hat"], "Kc_hat": constrained.values["Kc_hat"]}
                 if constrained else None)
        free = fit_free(data, specimen, held, start, table,
                        sigma_y_source="given" if sigma_y is not None else "the constrained model's estimate")
    except ValueError as exc:
        if requested == "free":
            raise
        free_error = str(exc)
    return compare(constrained, free, requested, free_error, constrained_error)


def restitution_band(result: FitResult, v_in, specimen: Specimen, table: MasterTable | None,
                     z: float = 1.96) -> tuple[np.ndarray, np.ndarray]:
    """e(v_in) of the fitted law and its standard error by the delta method,
    var e = g^T Cov(log theta) g, g = d e / d log theta (central differences); the band is
    e +- z se (z = 1.96: 95 % for the parameters' uncertainty, not the scatter of single tests)."""
    spec = result.spec
    centre = np.log([result.values[name] for name in spec.free])
    lower, upper = _spec_bounds(spec, specimen, table)

    def restitution(log_theta):
        return predict_impacts(law_parameters(specimen, spec.values(log_theta), table), v_in)["e"]

    e = restitution(centre)
    gradient = _jacobian(restitution, centre, lower, upper)
    se = np.sqrt(np.maximum(np.einsum("ij,jk,ik->i", gradient, result.covariance_log, gradient), 0.0))
    return e, z * se

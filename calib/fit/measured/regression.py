"""One least-squares fit of the vz law to measurements (``nfdcal fit-data``): a model's
parameters theta, their standard errors and correlations, the law's window.

**Least squares** (scipy.optimize.least_squares, trust-region reflective, theta in log space
so every parameter stays positive, inside ``BOUNDS``). The residuals are the relative ones of
calib.fit.measured.specimen; each group k (e, P_max, contact_time, force) is weighted by 1 / s_k,
s_k its RMS residual (re-estimated twice), so groups of different scatter count by their
precision. Standard errors (Bates & Watts 1988, Nonlinear Regression Analysis and Its
Applications, section 2.3):

    Cov(log theta) = s^2 (J^T J)^-1,   s^2 = sum(r_w^2) / (n - p),   J = d r_w / d log theta
    SE(theta_j) = theta_j SE(log theta_j),   Corr_ij = Cov_ij / sqrt(Cov_ii Cov_jj)

and derived quantities (Ca [m/N], Kc [1/N], Ca_hat of the constrained model) by the delta method
through their gradients in log theta. The fit also returns AIC and AICc (calib.fit.measured.models
defines them and chooses the model by them).

**Jacobian**: least_squares' own central differences (jac="3-point", relative step 1e-6 in
log theta, one-sided at a bound), in the iterations and, re-weighted to the final group scales,
in Cov. Measured on the examples of tests/test_fit_data.py, J agrees with a Richardson-extrapolated
reference to 1e-10..3e-8, where forward differences ("2-point") at the same step give 1e-6..1e-5;
bench_fit_data's 50 trials cost 4612 law evaluations and 20 s of CPU with "3-point", 3792 and
17 s with "2-point". No analytic J: the residuals pass through the law's energy balance
(nfdmodel.collision_reference's Newton solve), its history-dependent force driver and the
master table's PCHIP; an analytic J would state the law's equations a second time. Gradients at a
fixed point (the delta method, the identifiability report, the table's uncertainty) are forward
differences of scipy.optimize.approx_fprime (:func:`sensitivities`, to about 1e-7).

**Bounds**: sigma_Y such that E / sigma_Y lies inside the master table (constrained model) or
in 20..1e4 (free model, as the FE calibration accepts it); Ca_hat, Kc_hat around the FE's
0.024-0.034, 0.010-0.016. Inside them the law refuses constants that create energy and drop
tests beyond full contact; there the residuals continue smoothly (calib.fit.measured.domain),
and a fit that ends there is a ValueError naming what the law refuses.

**Data the model cannot fit** (:class:`DataMismatch`, a ValueError; calib.fit.measured.diagnosis
names the likely cause): a fit that ends beyond the law's domain, on a bound (the bound is no
estimate: the data ask for a value the model does not cover), with J singular (the data do not
change with a parameter), or with no measured value beyond first yield (every drop test slower
than v_Y, every force below P_Y: there the law is Hertz's whatever sigma_Y, Ca_hat and Kc_hat).
Each fit also carries the verdict of calib.fit.measured.scatter on its residuals.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy import optimize

from calib.fit.master_table import MasterTable
from calib.fit.measured.data import Measurements
from calib.fit.measured.domain import extended_residuals
from calib.fit.measured.scatter import Scatter, assess
from calib.fit.measured.specimen import Specimen, law_parameters, predict_impacts
from nfdmodel import CalibrationWindow, PlausibilityWarning, VZParams

# log-space bounds: E / sigma_Y as the FE calibration accepts it (20..1e4; the constrained model:
# the master table's 50..5000); the dimensionless constants around the FE's 0.024-0.034, 0.010-0.016
E_OVER_SIGMA_Y_RANGE = (20.0, 1e4)
BOUNDS = {"Ca_hat": (1e-3, 1.0), "Kc_hat": (1e-5, 1.0)}
JACOBIAN = "3-point"            # least_squares' finite differences of the weighted residuals (module doc)
DIFF_STEP = 1e-6                # their relative step in log theta
STEP = float(np.sqrt(np.finfo(float).eps))   # forward differences elsewhere: the library's relative step


class DataMismatch(ValueError):
    """The data do not fit the model for a reason of the data (module doc: best beyond the law's
    domain or on a bound, J singular, all below first yield): calib.fit.measured.diagnosis names
    the likely cause."""


def sigma_y_bounds(specimen: Specimen, model: str, table: MasterTable | None) -> tuple[float, float]:
    """[Pa]: E / sigma_Y inside the master table (constrained) or 20..1e4 (free)."""
    if model == "constrained" and table is not None:
        low, high = float(table.E_over_sigma_y[0]), float(table.E_over_sigma_y[-1])
    else:
        low, high = E_OVER_SIGMA_Y_RANGE
    return specimen.E / high * (1 + 1e-9), specimen.E / low * (1 - 1e-9)


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
    identifiability: the report (calib.fit.measured.identifiability; empty until attached);
    params: the law (VZParams, with the data's window); jacobian: J = d r_w / d log theta at the fit.
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
    jacobian: np.ndarray | None = None
    scatter: Scatter | None = None

    @property
    def rms_residual(self) -> float:
        everything = np.concatenate(list(self.residuals.values()))
        return float(np.sqrt(np.mean(everything**2)))


def sensitivities(fun, x, upper=None) -> np.ndarray:
    """d fun / d x at ``x``, one column per parameter, by scipy's forward differences
    (scipy.optimize.approx_fprime) with the library's relative step sqrt(eps) max(1, |x_j|); a
    backward step where a forward one would pass ``upper`` (a bound of the fit)."""
    x = np.asarray(x, dtype=float)
    step = STEP * np.maximum(1.0, np.abs(x))
    if upper is not None:
        step = np.where(x + step > upper, -step, step)
    return np.reshape(optimize.approx_fprime(x, fun, step), (-1, x.size))


def spec_bounds(spec: ModelSpec, specimen: Specimen, table) -> tuple[np.ndarray, np.ndarray]:
    bounds = {"sigma_y": sigma_y_bounds(specimen, spec.model, table), **BOUNDS}
    lower = np.log([bounds[name][0] for name in spec.free])
    upper = np.log([bounds[name][1] for name in spec.free])
    return lower, upper


def fit_model(data: Measurements, specimen: Specimen, spec: ModelSpec, start: dict,
              table: MasterTable | None, note: str = "") -> FitResult:
    """Least squares of ``spec`` to ``data`` from ``start`` (module doc); a ValueError when the data
    hold no more points than the model has parameters, do not determine them, or are fitted best
    where the law cannot be evaluated."""
    p = len(spec.free)
    if data.n_points <= p:
        raise ValueError(f"{', '.join(data.files)}: {data.n_points} data point(s), the {spec.model} model has {p} "
                         f"parameter(s) ({', '.join(spec.free)}): need at least {p + 1} rows to fit and "
                         f"estimate the scatter")
    lower, upper = spec_bounds(spec, specimen, table)
    sizes = data.group_sizes()
    scale = {name: 1.0 for name in sizes}

    def parameters(log_theta) -> VZParams:
        return law_parameters(specimen, spec.values(log_theta), table)

    def weighted(log_theta) -> np.ndarray:       # continued beyond the law's domain (calib.fit.measured.domain)
        groups = extended_residuals(specimen, spec.values(log_theta), table, data).residuals
        return np.concatenate([groups[name] / scale[name] for name in sizes])

    x = np.clip(np.log([start[name] for name in spec.free]), lower + 1e-12, upper - 1e-12)
    for _ in range(3 if len(sizes) > 1 else 1):  # re-weight the groups by their scatter
        solution = optimize.least_squares(weighted, x, jac=JACOBIAN, bounds=(lower, upper), method="trf",
                                          x_scale=1.0, diff_step=DIFF_STEP, xtol=1e-10, ftol=1e-12, gtol=1e-12)
        x, solved_scale = solution.x, scale
        extended = extended_residuals(specimen, spec.values(x), table, data)
        groups = extended.residuals
        scale = {name: max(float(np.sqrt(np.mean(groups[name] ** 2))), 1e-12) for name in sizes}
    if extended.beyond:
        raise DataMismatch(f"{', '.join(data.files)}: the {spec.model} model fits these data best where the vz law "
                           f"cannot be evaluated: {'; '.join(extended.beyond)}")
    params = parameters(x)
    check_beyond_first_yield(data, spec, specimen, params, x <= lower + 1e-6)
    check_inside_bounds(data, spec, specimen, x, solution.active_mask, (lower, upper), table)
    residual = np.concatenate([groups[name] / scale[name] for name in sizes])
    n = residual.size
    # least_squares' J at its solution, its rows re-weighted from the scales it solved with to the final ones
    jac = solution.jac * np.concatenate([np.full(sizes[name], solved_scale[name] / scale[name])
                                         for name in sizes])[:, None]
    variance = float(residual @ residual) / (n - p)
    singular = np.linalg.svd(jac, compute_uv=False)
    if not (singular.size and singular[-1] > 1e-12 * max(singular[0], 1e-300)):
        raise DataMismatch(f"the {spec.model} model's parameters ({', '.join(spec.free)}) are not determined by "
                           f"{', '.join(data.files)}: the law's prediction does not change with "
                           f"{'some of them' if p > 1 else spec.free[0]} over these data")
    unscaled = np.linalg.inv(jac.T @ jac)
    covariance = unscaled * variance
    unscaled_sd = np.sqrt(np.diag(unscaled))      # the correlation does not depend on s^2 (0 for exact data)
    correlation = unscaled / np.outer(unscaled_sd, unscaled_sd)

    def derived(log_theta) -> np.ndarray:
        law = parameters(log_theta)
        return np.log([law.pair.sigma_y, law.Ca_hat, law.Kc_hat, law.Ca, law.Kc])

    names = ("sigma_y", "Ca_hat", "Kc_hat", "Ca", "Kc")
    gradient = sensitivities(derived, x, upper)
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
    unweighted = jac * np.concatenate([np.full(sizes[name], scale[name]) for name in sizes])[:, None]
    scatter = assess(data, {name: groups[name] for name in sizes}, p, unweighted, spec.free)
    return FitResult(spec, values, standard_errors, covariance, correlation, groups, scale, rss, n, aic, aicc,
                     {}, params, note, jac, scatter)


def _range(values: np.ndarray, unit: str = "") -> str:
    low, high = float(values.min()), float(values.max())
    return (f"{low:.3g}" if low == high else f"{low:.3g}..{high:.3g}") + (f" {unit}" if unit else "")


def check_beyond_first_yield(data: Measurements, spec: ModelSpec, specimen: Specimen, params: VZParams,
                             at_lower_bound) -> None:
    """A DataMismatch when no measured value lies beyond first yield at the fit's sigma_Y: every drop
    test slower than v_Y, every force below P_Y. Below first yield the law is Hertz's whatever
    sigma_Y, Ca_hat and Kc_hat, so such data determine none of them (only a lower bound of sigma_Y);
    the message says which data would. ``at_lower_bound``: per fitted parameter, whether it ended
    on its lower bound."""
    pair = params.pair
    beyond = 0
    if data.impacts is not None:
        beyond += int(np.count_nonzero(data.impacts.v_in > pair.v_Y))
    if data.forces is not None:
        beyond += sum(int(np.count_nonzero(force > pair.P_Y)) for _, _, force in data.forces.tests)
    if beyond:
        return
    if "sigma_y" not in spec.free:
        where = "held"
    elif at_lower_bound[spec.free.index("sigma_y")]:
        where = f"the softest material the {spec.model} model admits, E/sigma_Y = {specimen.E / pair.sigma_y:.4g}"
    else:
        where = "fitted"
    what = "sigma_Y" if "sigma_y" in spec.free else ", ".join(spec.free)
    said, wanted = [], []
    if data.impacts is not None:
        e = data.impacts.e
        dissipated = (f"; their e = {_range(e)} < 1 is dissipation the vz law does not have below first "
                      f"yield (damping, adhesion, vibration of the set-up)") if float(e.min()) < 1.0 else ""
        said.append(f"every drop test ({Path(data.impacts.path).name}: v_in = {_range(data.impacts.v_in, 'm/s')}) is "
                    f"slower than first yield, v_Y = {pair.v_Y:.3g} m/s{dissipated}")
        wanted.append("drop tests faster than v_Y (v_Y grows as sigma_Y^(5/2))")
    if data.forces is not None:
        peak = max(float(force.max()) for _, _, force in data.forces.tests)
        said.append(f"every force of {Path(data.forces.path).name} (at most {peak:.4g} N) is below first yield, "
                    f"P_Y = {pair.P_Y:.4g} N")
        wanted.append("force-approach curves loaded beyond P_Y (P_Y grows as sigma_Y^3)")
    raise DataMismatch(f"the {spec.model} model cannot fit {what} to these data: at sigma_Y = {pair.sigma_y:.4g} Pa "
                       f"({where}) {' and '.join(said)}; there the law is Hertz's, whatever Ca_hat, Kc_hat and for any "
                       f"larger sigma_Y, so these data do not determine {what}: {' or '.join(wanted)} would")


def check_inside_bounds(data: Measurements, spec: ModelSpec, specimen: Specimen, x, active_mask, bounds,
                        table) -> None:
    """A DataMismatch when a fitted parameter ends on a bound of the fit (module doc: Bounds): the data
    ask for a value the model does not cover, and the bound is no estimate."""
    for i in np.flatnonzero(active_mask):
        name, value = spec.free[i], float(np.exp(x[i]))
        side = "lower" if active_mask[i] < 0 else "upper"
        low, high = (float(np.exp(b[i])) for b in bounds)
        if name == "sigma_y":
            ratio = specimen.E / value
            cover = ("the master table" if spec.model == "constrained" and table is not None
                     else f"the {spec.model} model")
            softer = side == "lower"
            raise DataMismatch(f"{', '.join(data.files)}: the {spec.model} model fits these data best at sigma_Y = "
                               f"{value:.4g} Pa, E/sigma_Y = {ratio:.4g}, the edge of {cover} (E/sigma_Y "
                               f"{specimen.E / high:.4g}..{specimen.E / low:.4g}): the data ask for a "
                               f"{'softer' if softer else 'harder'} material (a {'lower' if softer else 'higher'} "
                               f"sigma_Y) than it covers; check the data's units and the material flags, or calibrate "
                               f"this material by FE (nfdcal calibrate)")
        raise DataMismatch(f"{', '.join(data.files)}: the {spec.model} model fits these data best at {name} = "
                           f"{value:.4g}, the {side} end of its range ({low:.4g}..{high:.4g}): the data ask for a "
                           f"{name} the vz law's fit does not cover; check the data's units and the material flags")


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
    with warnings.catch_warnings():     # the command states the final fit's reach (beyond_fe_reach), once
        warnings.simplefilter("ignore", PlausibilityWarning)
        return CalibrationWindow(low, high, min(a_max, 1.0), f"measurements ({sources}), fitted by nfdcal fit-data")

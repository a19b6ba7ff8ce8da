"""The 95 % interval of a one-parameter fit whose residual groups carry their own estimated scale
(fit-data's vz-table model, calib.fit.measured.table_law: theta = ln sigma_Y; groups e, P_max,
contact_time, force).

**Statistical variance.** The fit weights group g (n_g relative residuals r_g, sensitivities
J_g = d r_g / d theta) by w_g = 1 / s_g^2, s_g its rms residual: with several groups it is the
Graybill-Deal weighted mean of the groups' estimates, and the weights themselves are estimated
from a few residuals each. With the information I = sum_g w_g J_g.J_g and each group's share
f_g = w_g J_g.J_g / I (its part of the hat matrix's trace, so nu_g = n_g - f_g degrees of freedom
and sigma_g^2 ~ r_g.r_g / nu_g):

    V_lin  = sum_g f_g w_g sigma_g^2 / I                          (the sandwich of the linearised fit)
    V_stat = V_lin (1 + 4 sum_g f_g (1 - f_g) / nu_g)             (Meier 1953, Biometrics 9:59-73)
    nu     = V_lin^2 / sum_g (f_g w_g sigma_g^2 / I)^2 / nu_g     (Satterthwaite 1946)

Meier's factor is the first-order variance the estimated weights add. Two groups of six with
their own scatter 1:1 and 1:4: the interval covers a common mean in 93.4 and 94.9 % of 3000
simulated series, s^2 / J_w.J_w at n - 1 = 11 degrees of freedom in 88.8 and 90.7 %
(tests/test_fit_data_interval.py).
One group: f = 1, V_stat = r.r / (n - 1) / J.J with n - 1 degrees of freedom, the usual formula.

**Curvature.** At a few percent noise per test, sigma_Y's sensitivities (d ln e / d ln sigma_Y
0.0-0.5 over a drop-test window) change across the interval, and a symmetric interval from the
slope at the fit misses more often on one side (a mean fitted through exp(theta):
tests/test_fit_data_interval.py). The
statistical half-widths are read off the profile of the weighted sum of squares S(theta) (the
weights of the fit held; Bates & Watts 1988, Nonlinear regression analysis, ch. 6, the profile t):

    d(theta) = sqrt((S(theta) - S(theta_hat)) / J_w.J_w),   d(theta_hat -+ L_-+) = k_stat sqrt(V_stat)

(d = |theta - theta_hat| for a linear model), k_stat = t(0.975, nu): u_-+ = L_-+ / k_stat.

**Model-form part.** u (stated, infinite degrees of freedom) combines with each side:
the interval is theta_hat - k sqrt(u_-^2 + u^2) .. theta_hat + k sqrt(u_+^2 + u^2), k Student's t
at the Welch-Satterthwaite degrees of freedom (V_stat + u^2)^2 / (V_stat^2 / nu) (JCGM 100:2008, G.4).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import optimize, stats

Z95 = 1.959963984540054            # the two-sided 95 % normal quantile (infinite degrees of freedom)
PROFILE_RTOL = 1e-3                # the profile's end points, relative to the target half-width


def coverage_factor(v_stat: float, v_model: float, dof: float) -> float:
    """The 95 % coverage factor k of Var = v_stat + v_model (module doc): Student's t at the
    Welch-Satterthwaite degrees of freedom (v_stat + v_model)^2 / (v_stat^2 / dof); Z95 when v_stat
    carries no estimated part (dof < 1 or v_stat = 0)."""
    if dof < 1 or not v_stat > 0.0 or not math.isfinite(v_stat):
        return Z95
    effective = (v_stat + v_model) ** 2 / (v_stat ** 2 / dof)
    return float(stats.t.ppf(0.975, effective))


@dataclass(frozen=True)
class Statistical:
    """V_stat [-] in theta^2 and its degrees of freedom nu; V_lin without Meier's factor (module doc)."""
    variance: float
    dof: float
    linear: float


def statistical_variance(residuals: dict, sensitivities: dict, scale: dict) -> Statistical:
    """V_stat and nu (module doc) from the unweighted residuals r_g, their sensitivities J_g and the
    fit's scales s_g per group."""
    info = {g: float(sensitivities[g] @ sensitivities[g]) / scale[g] ** 2 for g in residuals}
    total = sum(info.values())
    if not total > 0.0:
        return Statistical(math.inf, 0.0, math.inf)
    share = {g: info[g] / total for g in residuals}
    dof = {g: max(residuals[g].size - share[g], 1e-9) for g in residuals}
    part = {g: share[g] * float(residuals[g] @ residuals[g]) / dof[g] / scale[g] ** 2 / total for g in residuals}
    linear = sum(part.values())
    meier = 1.0 + 4.0 * sum(share[g] * (1.0 - share[g]) / dof[g] for g in residuals)
    spread = sum(part[g] ** 2 / dof[g] for g in residuals)
    nu = linear ** 2 / spread if spread > 0.0 else 0.0
    return Statistical(linear * meier, nu, linear)


def profile_half_widths(theta: float, distance, target: float, bounds: tuple) -> tuple[float, float]:
    """L_-, L_+ [-]: where the profile distance ``distance(theta)`` (module doc) reaches ``target``
    below and above ``theta`` (scipy.optimize.brentq), each at most the way to ``bounds`` (the
    table's edge: the data do not bound sigma_Y further there)."""
    out, seen = [], {}
    for sign, edge in ((-1.0, bounds[0]), (1.0, bounds[1])):
        room = abs(edge - theta)

        def excess(L):                # each point once: the bracket's ends are brentq's first calls
            if (sign, L) not in seen:
                seen[sign, L] = distance(theta + sign * L) - target
            return seen[sign, L]

        L = min(target, room)
        while L < room and excess(L) < 0.0:
            L = min(2.0 * L, room)
        if excess(L) < 0.0:
            out.append(room)
            continue
        out.append(float(optimize.brentq(excess, 0.0, L, xtol=PROFILE_RTOL * target)))
    return out[0], out[1]


@dataclass(frozen=True)
class Interval:
    """The 95 % interval in theta (low, high), the coverage factor k, the statistical part and the
    profile's standard uncertainties u_-, u_+ [-] (module doc)."""
    low: float
    high: float
    k: float
    statistical: Statistical
    u_minus: float
    u_plus: float


def interval95(theta: float, residuals: dict, sensitivities: dict, scale: dict, weighted_sum, at_fit: float,
               u: float, bounds: tuple) -> Interval:
    """The 95 % interval of theta (module doc). ``weighted_sum(theta)``: S, the fit's weighted sum of
    squares (inf where the model cannot be evaluated), ``at_fit`` its value at ``theta``; ``u``: the
    model-form standard uncertainty; ``bounds``: the fit's range of theta."""
    stat = statistical_variance(residuals, sensitivities, scale)
    k = coverage_factor(stat.variance, u * u, stat.dof)
    if not (stat.variance > 0.0 and math.isfinite(stat.variance)):
        half = k * math.sqrt(stat.variance + u * u)
        return Interval(theta - half, theta + half, k, stat, math.sqrt(stat.variance), math.sqrt(stat.variance))
    along = sum(float(sensitivities[g] @ sensitivities[g]) / scale[g] ** 2 for g in residuals)
    k_stat = coverage_factor(stat.variance, 0.0, stat.dof)

    def distance(x):                  # finite where the model cannot be evaluated: beyond any target
        rise = weighted_sum(x) - at_fit
        return math.sqrt(max(rise, 0.0) / along) if math.isfinite(rise) else 1e6

    low, high = profile_half_widths(theta, distance, k_stat * math.sqrt(stat.variance), bounds)
    u_minus, u_plus = low / k_stat, high / k_stat
    return Interval(theta - k * math.hypot(u_minus, u), theta + k * math.hypot(u_plus, u), k, stat, u_minus, u_plus)

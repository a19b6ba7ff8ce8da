"""The fit of sigma_Y and one more constant together (``nfdcal fit-data --rate-law``, ``--fit-hardening``): the
weighted least squares, its covariance and the 95 % intervals that calib.fit.measured.rate_fit and
calib.fit.measured.hardening_fit share.

**Least squares.** theta (2,) in logarithms (ln sigma_Y, ln k); each data group's relative residuals r_g
(e, P_max, contact_time, ...) weighted by 1 / s_g, s_g its rms residual, re-estimated after each solve
(three solves with several groups, one with one); scipy.optimize.least_squares (trf) inside the bounds,
started at the best point of a grid.

**Covariance.** V_stat = s^2 (J^T J)^-1, J = d r_w / d theta at the fit (central differences, STEP),
s^2 = r_w.r_w / (n - 2) (a pseudo-inverse where J is rank-deficient). The 95 % interval per parameter:
theta_j +- k_j sqrt(Cov_jj), Cov = V_stat + V_model, k_j Student's t at the Welch-Satterthwaite degrees of
freedom of V_stat (n - 2) and V_model (infinite) (calib.fit.measured.interval; JCGM 100:2008, G.4); the
values and intervals in SI, exp(theta).
"""
from __future__ import annotations

import itertools
import math
from collections.abc import Callable

import numpy as np
from scipy import optimize

from calib.fit.measured.interval import coverage_factor

STEP = 1e-5                   # central differences in theta


def solve(groups: Callable[..., dict], sizes: dict, grid: list, lower: np.ndarray, upper: np.ndarray):
    """(theta, the groups' residuals at it, the groups' scales, weighted(theta, **kw)): the weighted least
    squares of the module doc; ``groups(theta, **kw)`` the relative residuals per group (a ValueError or
    non-finite values: an inadmissible theta), ``grid`` the starting values of each parameter."""
    scale = {group: 1.0 for group in sizes}

    def weighted(theta, **kw):
        g = groups(theta, **kw)
        return np.concatenate([g[group] / scale[group] for group in sizes])

    def cost(theta):
        try:
            r = weighted(np.asarray(theta, dtype=float))
        except ValueError:
            return math.inf
        return float(r @ r) if np.isfinite(r).all() else math.inf

    theta = np.array(min(itertools.product(*grid), key=cost), dtype=float)
    theta = np.clip(theta, lower + 1e-9, upper - 1e-9)
    for _ in range(3 if len(sizes) > 1 else 1):       # re-weight the groups by their scatter
        solution = optimize.least_squares(weighted, theta, bounds=(lower, upper), method="trf", x_scale=1.0,
                                          diff_step=1e-6, xtol=1e-12, ftol=1e-12, gtol=1e-12)
        theta = solution.x
        g = groups(theta)
        scale.update({group: max(float(np.sqrt(np.mean(g[group] ** 2))), 1e-9) for group in sizes})
    return theta, g, dict(scale), weighted


def covariance(weighted: Callable, theta: np.ndarray) -> dict:
    """J, V_stat, (J^T J)^-1, n and whether J is rank-deficient at ``theta`` (module doc)."""
    r = weighted(theta)
    jac = np.column_stack([(weighted(theta + STEP * unit) - weighted(theta - STEP * unit)) / (2 * STEP)
                           for unit in np.eye(theta.size)])
    n = r.size
    s2 = float(r @ r) / max(n - theta.size, 1)
    singular = np.linalg.svd(jac, compute_uv=False)
    degenerate = not (singular[-1] > 1e-10 * max(singular[0], 1e-300))
    information = jac.T @ jac
    inverse = np.linalg.pinv(information) if degenerate else np.linalg.inv(information)
    return {"jac": jac, "v_stat": s2 * inverse, "inverse": inverse, "n": n, "degenerate": degenerate}


def intervals(names: tuple, values: dict, v_stat: np.ndarray, v_model: np.ndarray, n: int) -> dict:
    """Standard errors (combined, statistical, model-form; SI), 95 % intervals and the correlation of the two
    parameters (None with one; module doc)."""
    total = v_stat + v_model
    se, se_stat, se_model, interval = {}, {}, {}, {}
    for j, key in enumerate(names):
        k = coverage_factor(float(v_stat[j, j]), float(v_model[j, j]), n - len(names))
        se[key] = values[key] * math.sqrt(total[j, j])
        se_stat[key] = values[key] * math.sqrt(v_stat[j, j])
        se_model[key] = values[key] * math.sqrt(v_model[j, j])
        half = min(k * math.sqrt(total[j, j]), 700.0)      # a finite interval even where the data say nothing
        interval[key] = (values[key] * math.exp(-half), values[key] * math.exp(half))
    sd = np.sqrt(np.maximum(np.diag(total), 1e-300))
    return {"se": se, "se_stat": se_stat, "se_model": se_model, "interval95": interval,
            "correlation": float(total[0, 1] / (sd[0] * sd[1])) if len(names) > 1 else None}

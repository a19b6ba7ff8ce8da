"""Least-squares extraction of the NFD parameters Ca and Kc from FE contact-radius histories.

Vu-Quoc & Zhang (1999), section 3: on the loading branch beyond first yield the
elastoplastic contact radius splits additively, a_ep = a_e + a_p, with

    a_e = (3 P R* / (4 E*))^(1/3)          Hertz radius at the same force      [m]
    a_p = Ca <P - P_Y>                     plastic radius (paper 2.5)           [m], Ca [m/N]
    C_R = a_ep^2 / (R* alpha) = 1 + Kc <P - P_Y>   curvature factor (paper 3.6)  [-], Kc [1/N]

Both are lines through the origin in x = P - P_Y, so each parameter is a one-coefficient least
squares fit over the loading points with P > P_Y. The FE's C_R(P) is not exactly linear, so the
result depends on the fit window: ``window_study`` reports Ca and Kc against the largest load used.
``fit_force_law`` instead fits both at once by minimising the runtime law's force error along
the FE's approach history, i.e. what a DEM simulation actually feels.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np
from scipy import optimize

from nfdmodel.hertz_contact import hertz_radius


@dataclass(frozen=True)
class LineFit:
    """y = slope * x fitted through the origin (ordinary least squares).

    standard_error: standard error of the slope, sqrt(s^2 / sum x^2), s^2 = SSres / (n - 1).
    r_squared: 1 - SSres / SStot with SStot about the mean of y (comparable to a line with an
    intercept; can be negative when a line through the origin is a poor model).
    x_max: the largest x used (the fit window).
    """

    slope: float
    standard_error: float
    r_squared: float
    n_points: int
    x_max: float

    @property
    def relative_standard_error(self) -> float:
        return self.standard_error / abs(self.slope) if self.slope else float("inf")


def fit_through_origin(x: np.ndarray, y: np.ndarray) -> LineFit:
    """Ordinary least squares of y = slope * x (no intercept), with its standard error and R^2."""
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    if x.shape != y.shape or x.ndim != 1:
        raise ValueError(f"x and y must be 1-D arrays of equal length, got shapes {x.shape}, {y.shape}")
    if x.size < 2:
        raise ValueError(f"need at least 2 points with P > P_Y to fit, got {x.size}")
    if not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
        raise ValueError("fit data contain NaN or infinite values")
    sxx = float(x @ x)
    slope = float(x @ y) / sxx
    residual = y - slope * x
    ss_res = float(residual @ residual)
    ss_tot = float(((y - y.mean()) ** 2).sum())
    variance = ss_res / (x.size - 1)
    return LineFit(
        slope=slope,
        standard_error=float(np.sqrt(variance / sxx)),
        r_squared=1.0 - ss_res / ss_tot if ss_tot > 0 else 1.0,
        n_points=int(x.size),
        x_max=float(x.max()),
    )


@dataclass(frozen=True)
class RadiusLawData:
    """The quantities of the contact-radius decomposition along a loading branch (all SI)."""

    force: np.ndarray            # P [N]
    approach: np.ndarray         # alpha [m]
    contact_radius: np.ndarray   # a_ep [m], from the FE
    elastic_radius: np.ndarray   # a_e = Hertz radius at P [m]
    plastic_radius: np.ndarray   # a_p = a_ep - a_e [m]
    curvature_factor: np.ndarray  # C_R = a_ep^2 / (R* alpha) [-]
    excess_force: np.ndarray     # P - P_Y [N]


def radius_law_data(force, approach, contact_radius, *, R_star: float, E_star: float,
                    P_Y: float) -> RadiusLawData:
    """Decompose FE contact radii into elastic and plastic parts (paper 2.4-2.5, 3.4-3.6)."""
    force = np.asarray(force, dtype=float)
    approach = np.asarray(approach, dtype=float)
    contact_radius = np.asarray(contact_radius, dtype=float)
    elastic_radius = hertz_radius(np.clip(force, 0.0, None), R_star, E_star)
    with np.errstate(divide="ignore", invalid="ignore"):
        curvature = np.where(approach > 0, contact_radius**2 / (R_star * approach), np.nan)
    return RadiusLawData(force, approach, contact_radius, elastic_radius,
                         contact_radius - elastic_radius, curvature, force - P_Y)


@dataclass(frozen=True)
class RadiusLawFit:
    """Ca from a_p vs P - P_Y and Kc from C_R - 1 vs P - P_Y (paper section 3)."""

    Ca: LineFit  # slope [m/N]
    Kc: LineFit  # slope [1/N]


def fit_radius_law(data: RadiusLawData, P_fit_max: float | None = None) -> RadiusLawFit:
    """Least squares of the two radius laws on loading points with P_Y < P <= P_fit_max."""
    mask = data.excess_force > 0
    if P_fit_max is not None:
        mask &= data.force <= P_fit_max * (1 + 1e-12)
    x = data.excess_force[mask]
    return RadiusLawFit(Ca=fit_through_origin(x, data.plastic_radius[mask]),
                        Kc=fit_through_origin(x, data.curvature_factor[mask] - 1.0))


def window_study(data: RadiusLawData, min_points: int = 3) -> list[dict]:
    """Ca and Kc against the largest load used in the fit: one row per admissible window."""
    rows = []
    loads = np.sort(data.force[data.excess_force > 0])
    for P_fit_max in loads[min_points - 1:]:
        fit = fit_radius_law(data, P_fit_max)
        rows.append({"P_fit_max": float(P_fit_max), "Ca": fit.Ca.slope, "Ca_se": fit.Ca.standard_error,
                     "Ca_r2": fit.Ca.r_squared, "Kc": fit.Kc.slope, "Kc_se": fit.Kc.standard_error,
                     "Kc_r2": fit.Kc.r_squared, "n_points": fit.Ca.n_points})
    return rows


INADMISSIBLE_RESIDUAL = 1e3     # relative force error scored for constants the law refuses


@dataclass(frozen=True)
class ForceLawFit:
    """Ca, Kc minimising the relative force error of the runtime law along FE approach histories."""

    Ca: float
    Kc: float
    rms_relative_force_error: float
    max_relative_force_error: float
    n_points: int


def fit_force_law(predict_force, histories: Sequence[tuple[np.ndarray, np.ndarray]],
                  Ca0: float, Kc0: float, force_floor: float) -> ForceLawFit:
    """Fit (Ca, Kc) so that ``predict_force(alpha_history, Ca, Kc)`` matches the FE forces.

    predict_force: drives the runtime law along one approach history [m] and returns the forces
        [N] (the same vectorised law that ships, so fit and runtime cannot drift apart).
    histories: (approach, force) pairs from the FE, e.g. one per load path.
    force_floor: forces below it are weighted as if equal to it [N] (relative error of small
        forces near separation would otherwise dominate).
    The residual is (P_law - P_FE) / max(P_FE, force_floor); parameters are fitted in log space so
    they stay positive. Constants the law refuses (a turning point that would create energy:
    C_R growing fast against a_p, tried on paths from a few P_Y) score INADMISSIBLE_RESIDUAL at
    every point, so the fit stays among admissible ones.
    """
    points = sum(len(approach) for approach, _ in histories)

    def residuals(log_params):
        try:
            return relative_force_residuals(predict_force, histories, *np.exp(log_params), force_floor)
        except ValueError:
            return np.full(points, INADMISSIBLE_RESIDUAL)

    solution = optimize.least_squares(residuals, np.log([Ca0, Kc0]), method="lm", xtol=1e-12, ftol=1e-12)
    Ca, Kc = np.exp(solution.x)
    res = residuals(solution.x)
    return ForceLawFit(Ca=float(Ca), Kc=float(Kc), rms_relative_force_error=float(np.sqrt(np.mean(res**2))),
                       max_relative_force_error=float(np.abs(res).max()), n_points=int(res.size))


def relative_force_residuals(predict_force, histories, Ca: float, Kc: float,
                             force_floor: float) -> np.ndarray:
    """(P_law - P_FE) / max(P_FE, force_floor) at every point of every history (the metric
    ``fit_force_law`` minimises; it scores any given (Ca, Kc) too)."""
    parts = []
    for approach, force in histories:
        predicted = predict_force(np.asarray(approach, float), Ca, Kc)
        parts.append((predicted - force) / np.maximum(np.abs(force), force_floor))
    return np.concatenate(parts)

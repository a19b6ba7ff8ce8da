"""The vz-table law's tables from the FE: the loading curve and the energy each unloading returns.

In dimensionless form (x = P/P_Y, D = alpha/delta_Y, a_Y and delta_Y the contact radius and
approach at first yield) the vz-table law (nfdmodel.vz_table) loads along

    D(x) = (x^(1/3) + f(x))^2 / g(x),     f = a_p/a_Y (f(1) = 0, non-decreasing),  g = C_R (g(1) = 1)

and unloads from x_m along a Hertz curve with C_R = g(x_m) frozen, which returns the elastic work

    W_u(x_m) = (2/5) P_max (delta_max - delta_res) = (2/5) P_Y delta_Y x_m^(5/3) / g(x_m).

So the FE fixes the two tables through what a DEM contact needs, the force-approach curve and the
restitution (e^2 = W_u / W_l, W_l the loading work: Hertz to first yield, (2/5) P_Y delta_Y,
then the trapezoid rule on the FE's loading points):

1. g at each FE unloading path's peak from the elastic work the FE returned there:
   g(x_m) = (2/5) P_Y delta_Y x_m^(5/3) / W_u,FE (at least the C_R that returns E2_CEILING of
   W_l: discretisation noise can leave the FE's e above 1 near first yield); between the peaks
   from the lowest, x_1, up, g - 1 the monotone piecewise cubic (PCHIP, nfdmodel.pchip) through
   them in (ln(x - 1), ln(g - 1)): exact for any power law g - 1 = K (x - 1)^p, the paper's
   line (p = 1) and the FE's C_R (p ~ 0.5 from 10 to 265 P_Y, results/calibration/wide_window)
   alike. Below x_1, g - 1 = k f with k = (g - 1) / f at x_1, the paper's proportion (where
   g - 1 = (Kc_hat / Ca_hat) f): a load-unload cycle near first yield then returns less work
   than it took as long as k < 10/3 (e^2 = 1 + (x - 1) (0.6 g' - 2 f') / 0.4 + ... at x = 1), so k is
   at most K_BELOW_LOWEST_MAX = 3.
2. f at every FE loading point above P_Y from the loading curve: f = sqrt(D_FE g) - x^(1/3) from
   x_1 up, below it the non-negative root of (x^(1/3) + f)^2 = D_FE (1 + k f); least squares on
   the node values with the piecewise-linear interpolant of the nodes as the model, through
   non-negative increments (scipy.optimize.lsq_linear with bounds), so f is monotone by
   construction. Nodes: x = 1, the peaks, and geometric nodes up to the largest load
   (NODES_PER_DECADE per decade, at most half the loading points; those within 10 % of a peak
   dropped; one between 1 and x_1 at least).

So the law's loading curve is the FE's and its restitution the FE's at every path. g - 1 = k f
between the peaks too, the paper's proportion taken piecewise, would make the loading curve
decrease with f where C_R grows fast against a_p (below ~10 P_Y: f and g then fit the curve as
steps, e several per cent off between the paths); C_R interpolated in the load does not. The
runtime interpolates the same nodes monotonically (PCHIP). The contact radius the law implies,
a_Y (x^(1/3) + f), is the one consistent with that curve and that energy, not the FE's measured
one (whose tables, in the paper's definition C_R = a_ep^2 / (R* alpha), make small cycles near
first yield create energy and miss the restitution by several per cent over wide windows:
results/calibration/wide_window). VZTableParams checks its own admissibility.

The table's window starts at the lowest unloading peak: below it C_R follows a_p, not a
measured C_R (the laws' e there: results/calibration/between_nodes), so the paths must
start low (calib.fit.impact_window.window_peaks) for the window to reach down.
"""
from __future__ import annotations

import dataclasses
import math
from typing import Sequence

import numpy as np
from scipy.optimize import lsq_linear

from calib.fit.least_squares import RadiusLawData
from nfdmodel import CalibrationWindow, ContactPair, VZTableParams
from nfdmodel.pchip import pchip_evaluate, pchip_slopes

NODES_PER_DECADE = 8            # geometric nodes per decade of load, first yield to the largest load
# The largest proportion k = (g - 1) / f below the lowest unloading peak x_1 (module doc: a cycle near first
# yield returns less work than it took only for k < 10/3). Near yield the FE's f(x_1) and g(x_1) are
# differences of nearly equal numbers: a path from 1.1 P_Y (brass, E/sigma_Y 400, the graded mesh of 17.9
# elements per contact radius; e_FE 0.9999) gives k above 10/3 and a table that creates energy at 1.03 P_Y;
# capped, the table below x_1 dissipates, its loading curve still the FE's.
K_BELOW_LOWEST_MAX = 3.0
MIN_NODE_COUNT = 3              # ... at least (fewer loading points above P_Y: refused)
NODE_CLEARANCE = 0.1            # geometric nodes closer than this (in ln x) to a peak are dropped
E2_CEILING = 1.0 - 1e-6         # e^2 at a peak at most this (e < 1: the law creates no energy)
NEAR_YIELD = 1.5                # a lowest peak below this x is dropped when the table with it creates energy


def node_count(x_max: float) -> int:
    """Geometric nodes from 1 to x_max: NODES_PER_DECADE per decade (the same on every mesh of a
    load plan, so two meshes' tables extrapolate node by node)."""
    return max(MIN_NODE_COUNT, math.ceil(NODES_PER_DECADE * math.log10(x_max) - 1e-9) + 1)


def table_nodes(x_max: float, peaks: Sequence[float] = (), count: int | None = None) -> np.ndarray:
    """Node loads x = P/P_Y: 1, the ``peaks`` (x), and ``count`` (default :func:`node_count`)
    geometric nodes up to ``x_max``."""
    peaks = np.asarray([p for p in peaks if 1.0 < p <= x_max], dtype=float)
    geometric = np.geomspace(1.0, x_max, count or node_count(x_max))
    if peaks.size:
        distance = np.abs(np.log(geometric[:, None] / peaks[None, :])).min(axis=1)
        geometric = geometric[(distance > NODE_CLEARANCE) | (geometric == 1.0)]
    return np.unique(np.concatenate([geometric, peaks]))


def hat_basis(nodes: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Piecewise-linear interpolation weights (len(x), len(nodes)) of the node values at x."""
    basis = np.zeros((x.size, nodes.size))
    k = np.clip(np.searchsorted(nodes, x, side="right") - 1, 0, nodes.size - 2)
    t = np.clip((x - nodes[k]) / (nodes[k + 1] - nodes[k]), 0.0, 1.0)
    rows = np.arange(x.size)
    basis[rows, k] = 1.0 - t
    basis[rows, k + 1] = t
    return basis


class LoadingWork:
    """W_l(x) / (P_Y delta_Y), the loading work to x = P/P_Y >= 1 on the FE's loading curve
    (points x, D = alpha/delta_Y above P_Y, increasing in x): (2/5) to first yield (Hertz), then
    the trapezoid rule on P d alpha; between the points, linear in (ln x, ln W)."""

    def __init__(self, x: np.ndarray, D: np.ndarray):
        xs, Ds = np.concatenate([[1.0], x]), np.concatenate([[1.0], D])
        self.log_x = np.log(xs)
        self.log_D = np.log(Ds)
        self.log_work = np.log(0.4 + np.concatenate([[0.0], np.cumsum(0.5 * (xs[1:] + xs[:-1]) * np.diff(Ds))]))

    def __call__(self, x) -> np.ndarray:
        return np.exp(np.interp(np.log(x), self.log_x, self.log_work))

    def approach(self, x) -> np.ndarray:
        """D at x, linear in (ln x, ln D) between the points."""
        return np.exp(np.interp(np.log(x), self.log_x, self.log_D))


def fit_tables(data: RadiusLawData, pair: ContactPair, peaks: Sequence[float], unloading_work: Sequence[float],
               window: CalibrationWindow | None = None, count: int | None = None) -> VZTableParams:
    """VZTableParams from the FE loading points above P_Y and the elastic work [J] the FE returned
    unloading from each peak [N] (module doc), declared on ``window`` from the lowest peak up
    (its source kept; None: the peaks to the largest load); a ValueError when they do not
    determine the nodes or the table is not admissible.

    A table that creates energy with a lowest peak below NEAR_YIELD P_Y is fitted again without that
    peak (its window then starts at the next one): there e_FE ~ 0.9999 and the table's f, g are
    differences of nearly equal numbers (brass, E/sigma_Y 400, from 1.1 P_Y: a cycle to 1.091 P_Y
    returned 1.0001 of its work).
    """
    try:
        return _fit_tables(data, pair, peaks, unloading_work, window, count)
    except ValueError as exc:
        order = np.argsort(np.asarray(peaks, dtype=float))
        near_yield = np.asarray(peaks, dtype=float)[order] < NEAR_YIELD * pair.P_Y
        if "create energy" not in str(exc) or not near_yield[0] or near_yield.size < 3:
            raise
        keep = order[1:]
        return _fit_tables(data, pair, np.asarray(peaks, dtype=float)[keep],
                           np.asarray(unloading_work, dtype=float)[keep], window, count)


def _fit_tables(data: RadiusLawData, pair: ContactPair, peaks: Sequence[float], unloading_work: Sequence[float],
                window: CalibrationWindow | None, count: int | None) -> VZTableParams:
    """:func:`fit_tables` on every peak given."""
    above = data.excess_force > 0
    order = np.argsort(data.force[above])
    x = data.force[above][order] / pair.P_Y
    D = data.approach[above][order] / pair.delta_Y
    count = min(count or node_count(float(x.max())), x.size // 2)    # coarse load steps: two points per node
    if count < MIN_NODE_COUNT:
        raise ValueError(f"the FE loading branch has {x.size} points above P_Y: need >= {2 * MIN_NODE_COUNT} "
                         f"to fit a table")
    peaks = np.asarray(peaks, dtype=float)
    work = np.asarray(unloading_work, dtype=float)
    keep = (peaks > pair.P_Y) & (peaks <= data.force.max() * (1 + 1e-9))
    if not keep.any():
        raise ValueError("the vz-table fit needs at least one FE unloading path from above P_Y")
    if not np.all(work[keep] > 0):
        raise ValueError("unloading_work out of range: need > 0 at every peak")
    x_peaks = peaks[keep] / pair.P_Y
    work = work[keep][np.argsort(x_peaks)] / (pair.P_Y * pair.delta_Y)
    x_peaks = np.sort(x_peaks)
    loading_work = LoadingWork(x, D)
    # g = (2/5) x^(5/3) / W_u at the peaks; at least the C_R that returns E2_CEILING of W_l
    g_peaks = 0.4 * x_peaks ** (5.0 / 3.0) / np.minimum(work, E2_CEILING * loading_work(x_peaks))
    if not np.all(g_peaks > 1.0):
        k = int(np.argmin(g_peaks))
        raise ValueError(f"the FE unloading from P/P_Y = {x_peaks[k]:.4g} returns the work of C_R = {g_peaks[k]:.4g} <= 1 "
                         f"(more than Hertz's): the mesh does not resolve the contact there")
    log_x, log_g = np.log(x_peaks - 1.0), np.log(g_peaks - 1.0)
    slopes = pchip_slopes(log_x, log_g) if x_peaks.size > 1 else np.zeros(1)

    def measured_curvature(at):         # from the lowest peak up: g - 1 PCHIP in (ln(x - 1), ln(g - 1))
        if x_peaks.size == 1:
            return np.full(np.shape(at), g_peaks[0])
        return 1.0 + np.exp(pchip_evaluate(log_x, log_g, slopes, np.log(np.asarray(at) - 1.0))[0])

    x_1 = x_peaks[0]
    g_1 = float(g_peaks[0])
    f_1 = float(np.sqrt(loading_work.approach(x_1) * g_1) - np.cbrt(x_1))
    if not f_1 > 0:
        raise ValueError(f"the FE loading curve gives no plastic radius at the lowest unloading peak, P/P_Y = "
                         f"{x_1:.4g}: the tables are not determined below it")
    k = min((g_1 - 1.0) / f_1, K_BELOW_LOWEST_MAX)
    c = np.cbrt(x)
    b = 2.0 * c - D * k                 # (c + f)^2 = D (1 + k f): f^2 + b f + c^2 - D = 0
    root = 0.5 * (-b + np.sqrt(np.maximum(b * b - 4.0 * (c * c - D), 0.0)))
    target = np.clip(root, 0.0, f_1)     # f <= f(x_1) below x_1 (the root runs away where k D > 2 x^(1/3))
    measured = x >= x_1
    target[measured] = np.sqrt(D[measured] * measured_curvature(x[measured])) - c[measured]
    nodes = table_nodes(float(x.max()), x_peaks, count)
    if not np.any((nodes > 1.0) & (nodes < x_1)):     # proportional end slopes at x = 1 (module doc)
        nodes = np.unique(np.concatenate([nodes, [np.sqrt(x_1)]]))
    cumulative = np.cumsum(hat_basis(nodes, x)[:, ::-1], axis=1)[:, ::-1][:, 1:]   # column j: sum of basis k >= j
    f = np.concatenate([[0.0], np.cumsum(lsq_linear(cumulative, target, bounds=(0.0, np.inf)).x)])
    g = 1.0 + k * f
    g[nodes >= x_1] = measured_curvature(nodes[nodes >= x_1])
    if window is None:
        window = CalibrationWindow(float(x_1), float(nodes[-1]), None, "the FE unloading paths")
    elif window.P_min_over_P_Y < x_1:               # (a single path at the top: the top, to rounding)
        window = dataclasses.replace(window, P_min_over_P_Y=float(min(x_1, window.P_max_over_P_Y)))
    return VZTableParams(pair, tuple(nodes), tuple(f), tuple(g), window)

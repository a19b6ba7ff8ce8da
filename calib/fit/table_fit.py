"""The vz-table law's tables from the FE: the loading curve and the energy each unloading returns.

In dimensionless form (x = P/P_Y, D = alpha/delta_Y, a_Y and delta_Y the contact radius and
approach at first yield) the vz-table law (nfdmodel.vz_table) loads along

    D(x) = (x^(1/3) + f(x))^2 / g(x),     f = a_p/a_Y (f(1) = 0, non-decreasing),  g = C_R (g(1) = 1)

and unloads from x_m along a Hertz curve with C_R = g(x_m) frozen, which returns the elastic work

    W_u(x_m) = (2/5) P_max (delta_max - delta_res) = (2/5) P_Y delta_Y x_m^(5/3) / g(x_m).

So the FE fixes the two tables through what a DEM contact needs, the force-approach curve and the
restitution (e^2 = W_u / W_l):

1. g at each FE unloading path's peak from the elastic work the FE returned there:
   g(x_m) = (2/5) P_Y delta_Y x_m^(5/3) / W_u,FE. Between first yield (g = 1) and the peaks,
   g - 1 follows the plastic radius piecewise linearly, g = G(f), as in the paper's law, where
   g - 1 = (Kc_hat / Ca_hat) f; this also keeps small load-unload cycles near first yield from
   returning more work than they took.
2. f at every FE loading point above P_Y from the loading curve: f = sqrt(D_FE g) - x^(1/3),
   least squares on the node values with the piecewise-linear interpolant of the nodes as the
   model, through non-negative increments (scipy.optimize.lsq_linear with bounds), so f is
   monotone by construction. Nodes: x = 1, the peaks, and geometric nodes up to the largest load
   (NODE_COUNT of them, at most half the loading points; those within 10 % of a peak dropped).

Steps 1-2 are repeated (g depends on f, f on g) until f settles. The runtime interpolates the
same nodes monotonically (PCHIP), a second-order difference on these smooth data. The result
meets the FE's loading curve and its restitution at every peak by construction; the contact
radius it implies, a_Y (x^(1/3) + f), is the one consistent with that curve and that energy, not
the FE's measured one (whose tables, in the paper's definition C_R = a_ep^2 / (R* alpha), make
small cycles near first yield create energy and miss the restitution by several per cent over
wide windows: results/calibration/wide_window). VZTableParams checks its own admissibility.
"""
from __future__ import annotations

from typing import Sequence

import numpy as np
from scipy.optimize import lsq_linear

from calib.fit.least_squares import RadiusLawData
from nfdmodel import CalibrationWindow, ContactPair, VZTableParams

NODE_COUNT = 17                 # geometric nodes from first yield to the largest load
MIN_NODE_COUNT = 3              # ... at least (fewer loading points above P_Y: refused)
NODE_CLEARANCE = 0.1            # geometric nodes closer than this (in ln x) to a peak are dropped
FIXED_POINT_ITERATIONS = 50     # f <-> g; settles to 1e-12 in under 10 on the FE data
FIXED_POINT_TOLERANCE = 1e-12


def table_nodes(x_max: float, peaks: Sequence[float] = (), count: int = NODE_COUNT) -> np.ndarray:
    """Node loads x = P/P_Y: 1, the ``peaks`` (x), and geometric nodes up to ``x_max``."""
    peaks = np.asarray([p for p in peaks if 1.0 < p <= x_max], dtype=float)
    geometric = np.geomspace(1.0, x_max, count)
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


def curvature_at_peaks(pair: ContactPair, peaks, unloading_work) -> np.ndarray:
    """g(x_m) = (2/5) P_Y delta_Y x_m^(5/3) / W_u: the frozen C_R whose Hertz unloading returns
    the elastic work W_u [J] from the peak P_max [N] (module doc, step 1)."""
    x = np.asarray(peaks, dtype=float) / pair.P_Y
    work = np.asarray(unloading_work, dtype=float)
    if not np.all(work > 0):
        raise ValueError("unloading_work out of range: need > 0 at every peak")
    return 0.4 * pair.P_Y * pair.delta_Y * x ** (5.0 / 3.0) / work


def fit_tables(data: RadiusLawData, pair: ContactPair, peaks: Sequence[float], unloading_work: Sequence[float],
               window: CalibrationWindow | None = None, count: int = NODE_COUNT) -> VZTableParams:
    """VZTableParams from the FE loading points above P_Y and the elastic work [J] the FE returned
    unloading from each peak [N] (module doc); a ValueError when they do not determine the
    nodes or the table is not admissible."""
    above = data.excess_force > 0
    x = data.force[above] / pair.P_Y
    D = data.approach[above] / pair.delta_Y
    count = min(count, x.size // 2)    # coarse load steps: fewer nodes, two points per node
    if count < MIN_NODE_COUNT:
        raise ValueError(f"the FE loading branch has {x.size} points above P_Y: need >= {2 * MIN_NODE_COUNT} "
                         f"to fit a table")
    peaks = np.asarray(peaks, dtype=float)
    keep = (peaks > pair.P_Y) & (peaks <= data.force.max() * (1 + 1e-9))
    if not keep.any():
        raise ValueError("the vz-table fit needs at least one FE unloading path from above P_Y")
    x_peaks = np.concatenate([[1.0], peaks[keep] / pair.P_Y])
    g_peaks = np.concatenate([[1.0], curvature_at_peaks(pair, peaks[keep], np.asarray(unloading_work)[keep])])
    order = np.argsort(x_peaks)
    x_peaks, g_peaks = x_peaks[order], g_peaks[order]
    nodes = table_nodes(float(x.max()), x_peaks[1:], count)
    basis = hat_basis(nodes, x)
    cumulative = np.cumsum(basis[:, ::-1], axis=1)[:, ::-1][:, 1:]     # column j: sum of basis k >= j
    g_points = np.exp(np.interp(np.log(x), np.log(x_peaks), np.log(g_peaks)))   # first guess
    f = np.zeros(nodes.size)
    for _ in range(FIXED_POINT_ITERATIONS):
        target = np.sqrt(D * g_points) - np.cbrt(x)
        increments = lsq_linear(cumulative, target, bounds=(0.0, np.inf)).x
        f_new = np.concatenate([[0.0], np.cumsum(increments)])
        settled = np.abs(f_new - f).max() <= FIXED_POINT_TOLERANCE * max(1.0, f_new[-1])
        f = f_new
        f_peaks = np.interp(x_peaks, nodes, f)
        if not np.all(np.diff(f_peaks) > 0):
            k = int(np.argmin(np.diff(f_peaks)))
            raise ValueError(f"the FE loading curve gives no plastic growth between the peaks at P/P_Y = "
                             f"{x_peaks[k]:.4g} and {x_peaks[k + 1]:.4g}: the tables are not determined")
        g_points = np.interp(basis @ f, f_peaks, g_peaks)
        if settled:
            break
    g = np.interp(f, f_peaks, g_peaks)
    return VZTableParams(pair, tuple(nodes), tuple(f), tuple(g), window)

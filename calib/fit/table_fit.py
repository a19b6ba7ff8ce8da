"""The vz-table law's tables from the FE loading points (nfdmodel.vz_table).

On the loading branch beyond first yield the FE gives, per load P, the plastic radius
a_p = a_ep - a_e and the curvature factor C_R = a_ep^2 / (R* alpha) (calib.fit.least_squares).
In dimensionless form, x = P / P_Y:

    f(x) = a_p / a_Y  (f(1) = 0, non-decreasing),     g(x) = C_R  (g(1) = 1, > 0)

are least-squares fits of their node values at ``nodes`` (geometric from 1 to the largest load,
NODE_COUNT of them) with the piecewise-linear interpolant of the nodes as the model (linear in
the node values): f through its increments, each >= 0 (scipy.optimize.lsq_linear with bounds),
so f is monotone by construction; g free above 0. The runtime interpolates the same nodes
monotonically (PCHIP), which differs from the linear model by a second-order term on these
smooth data. The resulting VZTableParams checks its own admissibility (delta(P) increasing, no
energy created).
"""
from __future__ import annotations

import numpy as np
from scipy.optimize import lsq_linear

from calib.fit.least_squares import RadiusLawData
from nfdmodel import CalibrationWindow, ContactPair, VZTableParams

NODE_COUNT = 9                  # nodes from first yield to the largest load (geometric)
SMALLEST_CURVATURE = 1e-3       # lower bound of g at the nodes (C_R > 0)


def table_nodes(x_max: float, count: int = NODE_COUNT) -> np.ndarray:
    """Node loads x = P/P_Y: 1, then geometric up to ``x_max`` (``count`` in all)."""
    return np.geomspace(1.0, x_max, count)


def hat_basis(nodes: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Piecewise-linear interpolation weights (len(x), len(nodes)) of the node values at x."""
    basis = np.zeros((x.size, nodes.size))
    k = np.clip(np.searchsorted(nodes, x, side="right") - 1, 0, nodes.size - 2)
    t = np.clip((x - nodes[k]) / (nodes[k + 1] - nodes[k]), 0.0, 1.0)
    rows = np.arange(x.size)
    basis[rows, k] = 1.0 - t
    basis[rows, k + 1] = t
    return basis


def fit_tables(data: RadiusLawData, pair: ContactPair, window: CalibrationWindow | None = None,
               count: int = NODE_COUNT) -> VZTableParams:
    """VZTableParams from the FE loading points above P_Y (module doc); a ValueError when the
    points do not determine the nodes or the table is not admissible."""
    above = data.excess_force > 0
    x = data.force[above] / pair.P_Y
    if x.size < 2 * count:
        raise ValueError(f"the FE loading branch has {x.size} points above P_Y: need >= {2 * count} to fit "
                         f"a table of {count} nodes")
    nodes = table_nodes(float(x.max()), count)
    basis = hat_basis(nodes, x)
    # f: node values as cumulative increments (>= 0) from f(1) = 0
    cumulative = np.cumsum(basis[:, ::-1], axis=1)[:, ::-1][:, 1:]     # column j: sum of basis k >= j
    increments = lsq_linear(cumulative, data.plastic_radius[above] / pair.a_Y, bounds=(0.0, np.inf)).x
    f = np.concatenate([[0.0], np.cumsum(increments)])
    # g: node values above 0 with g(1) = 1
    target = data.curvature_factor[above] - basis[:, 0]
    g = np.concatenate([[1.0], lsq_linear(basis[:, 1:], target, bounds=(SMALLEST_CURVATURE, np.inf)).x])
    return VZTableParams(pair, tuple(nodes), tuple(f), tuple(g), window)

"""The vz-unload law's tables from the FE: its contact radius, loading curve, dent and unloading.

The vz-unload law (nfdmodel.vz_unload) loads along D(x) = (x^(1/3) + f(x))^2 / g(x) with the
contact radius a = a_Y (x^(1/3) + f(x)) at the turning point (x = P/P_Y, D = alpha/delta_Y),
and unloads from x_m along P = P_max ((delta - delta_res)/(delta_max - delta_res))^m(x_m),
delta_res = rho(x_m) delta_max. Its unloading does not depend on g, so each table is fitted to
the FE quantity it stands for:

1. f from the FE's contact radius on loading: f = a_FE/a_Y - x^(1/3) at every loading point above
   P_Y, least squares on the node values with the piecewise-linear interpolant of the nodes as
   the model, through non-negative increments from f(1) = 0 (scipy.optimize.lsq_linear), so f is
   monotone by construction (the paper's a_ep = a_e + a_p, eq. 2.4);
2. g from the FE's loading curve given f: g = (x^(1/3) + f(x))^2 / D_FE at the same points (f the
   runtime's PCHIP of the nodes), least squares on the node values from g(1) = 1 (the paper's
   C_R = a_ep^2 / (R* alpha), eq. 3.6, with the fitted radius);
3. at each FE unloading path's peak x_m: rho = alpha_res / alpha_max (the FE's residual approach,
   calib.fe.loadpath) and m = P_max (alpha_max - alpha_res) / W_u - 1 (W_u the elastic work the
   FE returned: the power curve through the FE's peak and dent returns the FE's work, so e is
   the FE's); nodes x = 1 (rho = 0, m = 3/2: Hertz) and the peaks.

Nodes of f and g as the vz-table fit's (calib.fit.table_fit.table_nodes). The window starts at the
lowest unloading peak: below it rho and m are interpolated towards Hertz's, not measured.
VZUnloadParams checks its own admissibility (D increasing, e <= 1).
"""
from __future__ import annotations

from typing import Sequence

import numpy as np
from scipy.optimize import lsq_linear

from calib.fit.table_fit import MIN_NODE_COUNT, hat_basis, node_count, table_nodes
from nfdmodel import CalibrationWindow, ContactPair, VZUnloadParams
from nfdmodel.pchip import pchip_evaluate, pchip_slopes
from nfdmodel.vz_unload import HERTZ_EXPONENT


def unloading_nodes(pair: ContactPair, peaks: Sequence[float], alpha_max: Sequence[float],
                    alpha_residual: Sequence[float], unloading_work: Sequence[float]):
    """(x_unload, rho, m) from the FE paths' peaks [N], peak approaches [m], residual approaches
    [m] and returned work [J] (module doc, step 3), with the Hertz node x = 1 first."""
    peaks = np.asarray(peaks, dtype=float)
    keep = peaks > pair.P_Y
    if not keep.any():
        raise ValueError("the vz-unload fit needs at least one FE unloading path from above P_Y")
    order = np.argsort(peaks[keep])
    P_max = peaks[keep][order]
    alpha_max = np.asarray(alpha_max, dtype=float)[keep][order]
    alpha_res = np.asarray(alpha_residual, dtype=float)[keep][order]
    work = np.asarray(unloading_work, dtype=float)[keep][order]
    if not (np.all(work > 0) and np.all((alpha_res >= 0) & (alpha_res < alpha_max))):
        raise ValueError("unloading paths out of range: need returned work > 0 and 0 <= alpha_res < alpha_max")
    rho = alpha_res / alpha_max
    m = P_max * (alpha_max - alpha_res) / work - 1.0
    return (np.concatenate([[1.0], P_max / pair.P_Y]), np.concatenate([[0.0], rho]),
            np.concatenate([[HERTZ_EXPONENT], m]))


def fit_unload_law(force, approach, contact_radius, pair: ContactPair, peaks: Sequence[float],
                   alpha_max: Sequence[float], alpha_residual: Sequence[float], unloading_work: Sequence[float],
                   window: CalibrationWindow | None = None, count: int | None = None) -> VZUnloadParams:
    """VZUnloadParams from the FE loading points (force [N], approach [m], contact radius [m]) and
    the FE unloading paths (module doc); declared on ``window`` (None: the lowest peak to the
    largest load). A ValueError when they do not determine the tables or these are inadmissible."""
    force, approach, radius = (np.asarray(v, dtype=float) for v in (force, approach, contact_radius))
    above = force > pair.P_Y
    order = np.argsort(force[above])
    x = force[above][order] / pair.P_Y
    D = approach[above][order] / pair.delta_Y
    A = radius[above][order] / pair.a_Y
    count = min(count or node_count(float(x.max())), x.size // 2)
    if count < MIN_NODE_COUNT:
        raise ValueError(f"the FE loading branch has {x.size} points above P_Y: need >= {2 * MIN_NODE_COUNT} "
                         f"to fit a table")
    x_unload, rho, m = unloading_nodes(pair, peaks, alpha_max, alpha_residual, unloading_work)
    nodes = table_nodes(float(x.max()), x_unload[1:], count)
    basis = hat_basis(nodes, x)
    cumulative = np.cumsum(basis[:, ::-1], axis=1)[:, ::-1][:, 1:]   # column j: sum of basis k >= j
    c = np.cbrt(x)
    f = np.concatenate([[0.0], np.cumsum(lsq_linear(cumulative, A - c, bounds=(0.0, np.inf)).x)])
    f_points = pchip_evaluate(nodes, f, pchip_slopes(nodes, f), x)[0]
    g_target = (c + f_points) ** 2 / D
    g = np.concatenate([[1.0], 1.0 + np.linalg.lstsq(basis[:, 1:], g_target - 1.0, rcond=None)[0]])
    if window is None:
        window = CalibrationWindow(float(x_unload[1]), float(nodes[-1]), float(radius.max() / pair.R_star),
                                   "the FE unloading paths")
    return VZUnloadParams(pair, tuple(nodes), tuple(f), tuple(g), window, tuple(x_unload), tuple(rho), tuple(m))

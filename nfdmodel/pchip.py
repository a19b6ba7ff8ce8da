"""Monotone piecewise-cubic tables (PCHIP, Fritsch & Carlson 1980), explicit enough to port.

Nodes x_0 < ... < x_{n-1} with values y_k; on [x_k, x_{k+1}], with h = x_{k+1} - x_k and
t = (x - x_k) / h, the cubic Hermite interpolant

    y(x) = (2t^3 - 3t^2 + 1) y_k + (t^3 - 2t^2 + t) h d_k + (-2t^3 + 3t^2) y_{k+1} + (t^3 - t^2) h d_{k+1}

takes node slopes d_k that keep monotone data monotone (the formulas scipy's PchipInterpolator
uses, Fritsch & Butland 1984): with secants s_k = (y_{k+1} - y_k) / h_k,
    interior: d_k = 0 if s_{k-1} s_k <= 0, else (w1 + w2) / (w1 / s_{k-1} + w2 / s_k),
              w1 = 2 h_k + h_{k-1}, w2 = h_k + 2 h_{k-1};
    ends:     d_0 = ((2 h_0 + h_1) s_0 - h_0 s_1) / (h_0 + h_1), set to 0 if its sign differs
              from s_0, and to 3 s_0 if s_0, s_1 differ in sign and |d_0| > 3 |s_0| (likewise
              at the last node); two nodes: the straight line.
Beyond the last node the table continues as the straight line of its last slope (below the
first node, of its first slope). The interpolant is C1; linear data are reproduced exactly.
"""
from __future__ import annotations

import numpy as np


def pchip_slopes(x, y) -> np.ndarray:
    """Node slopes d_k of the monotone piecewise-cubic interpolant (module doc); ``y`` of shape (n, ...): the
    slopes of each column along its first axis."""
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    h = np.diff(x).reshape((-1,) + (1,) * (y.ndim - 1))
    s = np.diff(y, axis=0) / h
    if x.size == 2:
        return np.stack([s[0], s[0]])
    d = np.zeros_like(y)
    w1 = 2.0 * h[1:] + h[:-1]
    w2 = h[1:] + 2.0 * h[:-1]
    same_sign = s[:-1] * s[1:] > 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        harmonic = (w1 + w2) / (w1 / s[:-1] + w2 / s[1:])
    d[1:-1] = np.where(same_sign, harmonic, 0.0)
    d[0] = _end_slope(h[0], h[1], s[0], s[1])
    d[-1] = _end_slope(h[-1], h[-2], s[-1], s[-2])
    return d


def _end_slope(h0, h1, s0, s1):
    d = ((2.0 * h0 + h1) * s0 - h0 * s1) / (h0 + h1)
    d = np.where(np.sign(d) != np.sign(s0), 0.0, d)
    return np.where((np.sign(s0) != np.sign(s1)) & (np.abs(d) > np.abs(3.0 * s0)), 3.0 * s0, d)


def pchip_evaluate(x_nodes, y_nodes, d_nodes, x, derivative: bool = False):
    """(value, slope) of the table at ``x`` (any shape; slope only when ``derivative``); y_nodes of shape (n, ...)
    with a scalar ``x``: every column's."""
    x = np.asarray(x, dtype=float)
    n = x_nodes.shape[0]
    k = np.clip(np.searchsorted(x_nodes, x, side="right") - 1, 0, n - 2)
    x0, x1 = x_nodes[k], x_nodes[k + 1]
    h = x1 - x0
    t = (x - x0) / h
    y0, y1, d0, d1 = y_nodes[k], y_nodes[k + 1], d_nodes[k], d_nodes[k + 1]
    t2 = t * t
    t3 = t2 * t
    value = (2 * t3 - 3 * t2 + 1) * y0 + (t3 - 2 * t2 + t) * h * d0 + (3 * t2 - 2 * t3) * y1 + (t3 - t2) * h * d1
    slope = ((6 * t2 - 6 * t) * (y0 - y1) / h + (3 * t2 - 4 * t + 1) * d0 + (3 * t2 - 2 * t) * d1) if derivative else None
    above, below = x > x_nodes[-1], x < x_nodes[0]          # straight continuations
    if above.any() or below.any():
        value = np.where(above, y_nodes[-1] + d_nodes[-1] * (x - x_nodes[-1]), value)
        value = np.where(below, y_nodes[0] + d_nodes[0] * (x - x_nodes[0]), value)
        if derivative:
            slope = np.where(above, d_nodes[-1], np.where(below, d_nodes[0], slope))
    return value, slope

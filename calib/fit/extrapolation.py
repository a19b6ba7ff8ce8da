"""Mesh-converged constants from two meshes: Richardson extrapolation, with an error estimate.

A quantity Q computed with contact element h converges as Q(h) = Q_0 + C h^p + o(h^p). The
calibration solves two meshes, h and r h (r = REFINEMENT = 2), and ships

    Q_0 ~ Q_h + (Q_h - Q_rh) / (r^p - 1)                              (Richardson extrapolation)

with p = ORDER = 1: the observed order of Ca and Kc on the reference mesh ladder
(results/calibration/mesh_ladder.csv, contact element 160/80/40/20/10 um: first order, the
contact edge is located to within an element). The estimated relative error of the shipped
value is how far it moves when the true order is anywhere in [ORDER - ORDER_SPREAD,
ORDER + ORDER_SPREAD] (the observed orders over the ladder, with a margin):

    err = |Q_h - Q_rh| max_{p' = p +- dp} |1/(r^p' - 1) - 1/(r^p - 1)| / |Q_0|       [-]

Two meshes are in the asymptotic range when refinement moves Q the way it does on every
ladder measured (Ca and Kc grow: the coarse mesh underestimates the plastic radius) by at most
ASYMPTOTIC_CHANGE; otherwise a MeshWarning says so and the fine mesh's value ships, with
|Q_h - Q_rh| / |Q_h| as its error estimate (Roache 1998, Verification and Validation in
Computational Science and Engineering, ch. 5).

e and alpha are not extrapolated: on the ladder they change by < 0.1 % with either sign (they
are integrals of the FE force-approach curve, converged at the default mesh); the fine mesh's
value is reported with |Q_h - Q_rh| / |Q_h| as its error estimate.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import asdict, dataclass

import numpy as np

REFINEMENT = 2.0          # r: the second mesh's contact element is r h
ORDER = 1.0               # p: the observed order of Ca, Kc on the reference ladder
ORDER_SPREAD = 0.15       # dp: the spread of the observed orders over the ladder
ASYMPTOTIC_CHANGE = 0.10  # |Q_h / Q_rh - 1| above this: the pair is not in the asymptotic range
EXTRAPOLATED = ("Ca", "Kc")   # the two-constant law; Ca_hat, Kc_hat scale with them exactly


class MeshWarning(UserWarning):
    """Two meshes of a calibration are not in the asymptotic range: their extrapolation is not
    trusted and the fine mesh's value ships."""


@dataclass(frozen=True)
class Estimate:
    """A quantity from two meshes: the shipped value, both meshes' values and the estimated
    relative discretisation error of the shipped value [-]."""
    value: float
    fine: float
    coarse: float
    rel_error_estimate: float
    extrapolated: bool

    def record(self) -> dict:
        return asdict(self)


def order_sensitivity(ratio: float = REFINEMENT, order: float = ORDER, spread: float = ORDER_SPREAD) -> float:
    """max over p' = p +- dp of |1/(r^p' - 1) - 1/(r^p - 1)|: the largest error of the
    extrapolation per unit change Q_h - Q_rh when the true order is within dp of p (the lower
    order's side: 1/(r^p - 1) is convex)."""
    nominal = 1.0 / (ratio ** order - 1.0)
    return max(abs(1.0 / (ratio ** (order + sign * spread) - 1.0) - nominal) for sign in (-1.0, 1.0))


def richardson(fine: float, coarse: float, ratio: float = REFINEMENT, order: float = ORDER) -> Estimate:
    """The extrapolated value of a quantity that grows under refinement (Ca, Kc), or the fine
    value when the pair is not in the asymptotic range (see the module docstring)."""
    change = fine - coarse
    if not (fine > 0 and coarse > 0) or not (0.0 <= change <= ASYMPTOTIC_CHANGE * abs(coarse)):
        return Estimate(fine, fine, coarse, abs(change) / abs(fine) if fine else math.inf, False)
    value = fine + change / (ratio ** order - 1.0)
    return Estimate(value, fine, coarse, abs(change) * order_sensitivity(ratio, order) / abs(value), True)


def unextrapolated(fine: float, coarse: float) -> Estimate:
    """A quantity converged to its mesh noise (e, alpha): the fine value, |change| / |fine|."""
    return Estimate(fine, fine, coarse, abs(fine - coarse) / abs(fine) if fine else 0.0, False)


def extrapolated_table(fine: np.ndarray, coarse: np.ndarray, ratio: float = REFINEMENT,
                       order: float = ORDER) -> tuple[np.ndarray, float]:
    """Node values of a law table (a_p/a_Y or C_R at the same P/P_Y nodes on both meshes),
    extrapolated node by node, and the largest error estimate over the nodes relative to the
    table's largest value (a_p/a_Y starts at 0 at first yield: node-wise ratios mean nothing)."""
    fine, coarse = np.asarray(fine, dtype=float), np.asarray(coarse, dtype=float)
    value = fine + (fine - coarse) / (ratio ** order - 1.0)
    scale = max(float(np.abs(value).max()), 1e-300)
    return value, float(np.max(np.abs(fine - coarse)) * order_sensitivity(ratio, order) / scale)


def warn_if_not_asymptotic(estimates: dict, contact_sizes: tuple[float, float]) -> None:
    """One MeshWarning naming the constants whose two meshes are not in the asymptotic range."""
    outside = [name for name, estimate in estimates.items() if not estimate.extrapolated]
    if outside:
        details = ", ".join(f"{name} {estimates[name].coarse:.4g} -> {estimates[name].fine:.4g}"
                            for name in outside)
        warnings.warn(f"meshes with contact element {contact_sizes[1]:.3g} m and {contact_sizes[0]:.3g} m are not"
                      f" in the asymptotic range for {details} (expected: growth by at most "
                      f"{ASYMPTOTIC_CHANGE:.0%}); shipping the fine mesh's value, its error estimate the change",
                      MeshWarning, stacklevel=3)

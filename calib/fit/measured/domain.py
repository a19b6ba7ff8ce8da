"""Where the vz law can be evaluated during a fit to measurements, and how the fit's residuals
continue beyond (``nfdcal fit-data``).

Inside the fit's box bounds (calib.fit.measured.regression.BOUNDS) the law still refuses two
kinds of trial point:

    constants      (Ca_hat, Kc_hat) that nfdmodel.VZParams refuses: Kc_hat above the largest
                   admissible Kc_hat*(Ca_hat), where the loading curve delta(P) stops increasing
                   or a load-unload cycle creates energy (0.0005 at Ca_hat = 0.001, 0.066 at
                   0.026, 2.7 at 1; nfdmodel.vz.vz_largest_admissible_Kc)
    full contact   a drop test faster than v* = sqrt(2 W_l(P) / m*) [m/s] at P = (1 - 1e-6) P_fc,
                   the speed at which the law's contact radius a_e + Ca (P - P_Y) reaches R* at
                   the load P_fc (nfdmodel.VZParams.full_contact_load; nfdmodel.collision_reference
                   refuses faster impacts)

Neither boundary is a box in (ln sigma_Y, ln Ca_hat, ln Kc_hat): Kc_hat* grows 5000-fold over the
Ca_hat bounds, and v* depends on all three, so bounds cannot hold the fit inside; a
reparametrisation would need Kc_hat*(Ca_hat) in closed form, and it is a bisection on the law's
own energy check. So beyond each boundary the residuals continue by their first-order Taylor
expansion about it, in the coordinate that crosses it:

    r(Kc_hat) = r(Kc_hat*) + (dr / d ln Kc_hat)(Kc_hat*) ln(Kc_hat / Kc_hat*)      Kc_hat > Kc_hat*
    y(v_i)    = y(v*) + (dy / d ln v)(v*) ln(v_i / v*)      (y = e, P_max, contact time; v_i > v*)

with one-sided slopes at the boundary (relative step ``STEP``). The continued residuals and their
first derivatives match the law's on the boundary, so the least-squares cost is continuous and
continuously differentiable; Kc_hat* comes from a bisection to 1e-6 relative, but an error
delta in it changes the continued residuals only by O(delta^2). When the data's best fit lies
inside, the continuation's slopes lead the trust region back; a fit that ends beyond a boundary
(the data ask for what the law refuses) is a ValueError naming it (calib.fit.measured.regression).

Why not a penalty: rows p = ln(Kc_hat / Kc_hat*) / 1e-3 appended to the law's residuals at the
nearest admissible point are continuous too, but those residuals stop depending on Kc_hat beyond
the boundary, a kink on which scipy's trust region collapses: from Kc_hat = 0.1 (15 % beyond
Kc_hat* at Ca_hat = 0.032) such a fit takes 805 law evaluations and stops on the boundary, far
from the data's best fit (Kc_hat = 0.0139), which the continuation reaches in 37
(tests/test_fit_data.py::test_a_start_the_law_refuses_walks_back_to_the_usual_fit).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from calib.fit.master_table import MasterTable
from calib.fit.measured.data import Measurements
from calib.fit.measured.specimen import Specimen, dimensionless_constants, predict_impacts, relative_residuals
from nfdmodel import ContactPair, VZParams, get_law
from nfdmodel.vz import vz_largest_admissible_Kc

STEP = 1e-6                     # the one-sided step in ln Kc_hat and ln v_in of the continuation's slopes
REACH_MARGIN = 1e-6             # v*: the impact that loads to (1 - this) x the full-contact load


@dataclass(frozen=True)
class Extended:
    """The residuals per group (calib.fit.measured.specimen.relative_residuals), continued beyond
    the law's domain, and in words what lies beyond it (empty inside)."""

    residuals: dict
    beyond: tuple = ()


def full_contact_speed(params: VZParams) -> float:
    """v* [m/s]: the impact speed whose loading work reaches (1 - REACH_MARGIN) x the
    full-contact load (module doc), (1/2) m* v*^2 = W_l(P)."""
    load = params.full_contact_load * (1.0 - REACH_MARGIN)
    work = get_law("vz").loading_work(np.array([params.loading_approach(load)]), np.array([load]), params)
    return math.sqrt(2.0 * float(work[0]) / params.pair.mass_star)


def largest_admissible_Kc_hat(pair: ContactPair, Ca_hat: float) -> float:
    """Kc_hat* [-]: the largest Kc_hat the vz law admits with ``Ca_hat`` (to 1e-6 relative, on
    the admissible side; nfdmodel.vz.vz_largest_admissible_Kc)."""
    return vz_largest_admissible_Kc(pair, Ca_hat * pair.a_Y / pair.P_Y) * pair.P_Y


def impact_predictions(params: VZParams, v_in: np.ndarray) -> tuple[dict, tuple]:
    """The law's e [-], P_max [N], contact_time [s] at ``v_in`` [m/s], continued beyond v*
    (module doc), and in words whether any test lies there."""
    v_reach = full_contact_speed(params)
    beyond = v_in > v_reach
    if not beyond.any():
        return predict_impacts(params, v_in), ()
    speeds = np.concatenate([np.minimum(v_in, v_reach), [v_reach * math.exp(-STEP), v_reach]])
    at = predict_impacts(params, speeds)
    t = np.log(np.maximum(v_in / v_reach, 1.0))
    predicted = {name: y[:-2] + (y[-1] - y[-2]) / STEP * t for name, y in at.items()}
    fastest = float(v_in.max())
    return predicted, (f"the fastest drop test, v_in = {fastest:.6g} m/s, is beyond {v_reach:.6g} m/s, where the "
                       f"law's contact radius reaches R* = {params.pair.R_star:g} m",)


def _residuals(data: Measurements, params: VZParams) -> Extended:
    if data.impacts is None:
        return Extended(relative_residuals(data, params))
    predicted, beyond = impact_predictions(params, data.impacts.v_in)
    return Extended(relative_residuals(data, params, predicted), beyond)


def extended_residuals(specimen: Specimen, values: dict, table: MasterTable | None,
                       data: Measurements) -> Extended:
    """The residuals of the law at ``values`` (sigma_y [Pa], Ca_hat, Kc_hat: the master table's
    when absent) for ``data``, continued beyond the law's domain (module doc)."""
    pair, Ca_hat, Kc_hat = dimensionless_constants(specimen, values, table)
    try:
        params = VZParams.from_dimensionless(pair, Ca_hat, Kc_hat)
    except ValueError:
        largest = largest_admissible_Kc_hat(pair, Ca_hat)
        if not Kc_hat > largest:               # refused for another reason: nothing to continue along
            raise
    else:
        return _residuals(data, params)
    at = _residuals(data, VZParams.from_dimensionless(pair, Ca_hat, largest))
    below = _residuals(data, VZParams.from_dimensionless(pair, Ca_hat, largest * math.exp(-STEP)))
    t = math.log(Kc_hat / largest)
    continued = {name: r + (r - below.residuals[name]) / STEP * t for name, r in at.residuals.items()}
    return Extended(continued, (f"Kc_hat = {Kc_hat:.6g} is above {largest:.6g}, the largest the vz law admits at "
                                f"Ca_hat = {Ca_hat:.6g} (beyond it the loading curve stops increasing or a load-unload "
                                f"cycle creates energy)",) + at.beyond)

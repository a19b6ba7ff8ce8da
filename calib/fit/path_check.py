"""A law against one FE load-unload path: how closely a fitted law follows the FE where it was not fitted.

Per path (its approach alpha [m], force P [N], peak P_max [N] and restitution e) and law:

    force error = max |P_law(alpha) - P_FE(alpha)| / P_max   along loading and unloading
    e error     = e_law / e_FE - 1,  e^2 = elastic / (elastic + dissipated) energy at the peak

(the law driven along the FE's approach history, calib.fit.calibration.drive_law: the quasi-static
restitution of the path), and the law's sphere-on-flat collision at the v_in that reaches the same
P_max (calib.fit.impact_window.reach_velocity; e_collision: the same loop, run dynamically). The
targets of calib.fit.calibration (E_TARGET, FORCE_TARGET) judge them; the studies
(calib.studies.wide_window, between_nodes, pairs) and the vz master table's check use it.
"""
from __future__ import annotations

import warnings

import numpy as np

from calib.fit.calibration import drive_law
from calib.fit.impact_window import reach_velocity
from nfdmodel import RangeWarning, collide


def law_against_path(law: str, params, path: dict) -> dict:
    """One law along one FE path (``approach`` [m], ``force`` [N], ``P_max`` [N], ``e``): the
    force error along the path, the quasi-static cycle's e and the law's collision e at the v_in
    reaching the same P_max (module docstring; no collision keys beyond the law's domain)."""
    law_force, e_law = drive_law(law, params, path["approach"])
    v_in = reach_velocity(params, path["P_max"])     # the law's impact reaching the same P_max
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RangeWarning)
            e_collision = float(collide(law, params, [v_in]).e_velocity[0])
    except ValueError:                  # beyond the law's domain: no impact to compare
        e_collision = float("nan")
    return {"force_error": float(np.abs(law_force - path["force"]).max() / path["P_max"]),
            "e_fe": path["e"], "e_law": e_law, "e_error": e_law / path["e"] - 1.0,
            "v_in": v_in, "v_in_over_v_Y": v_in / params.pair.v_Y,
            **({"e_collision": e_collision, "e_collision_error": e_collision / path["e"] - 1.0}
               if e_collision == e_collision else {})}

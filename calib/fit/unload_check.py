"""A law against one FE load-unload path in what a DEM code reads: dent, radius, unloading, e.

Per path (the FE's loading approaches and forces to the peak P_max [N], its contact radius a_FE
[m] there, its unloading approaches and forces, its residual approach alpha_res [m] and its
restitution e) and law, the law driven along the FE's approach history (one contact,
nfdmodel's ContactLaw.contact_state):

    dent error      = delta_res,law / alpha_res,FE - 1     (delta_res of the law's turning point)
    dent error / alpha_max = (delta_res,law - alpha_res,FE) / alpha_max
    radius error    = a_law / a_FE - 1 at the peak          (a_law = a_e(P) + a_p(P_max))
    unloading error = max |P_law - P_FE| / P_max over the FE's unloading points
    loading error   = max |P_law - P_FE| / P_max over the FE's loading points
    e error         = e_law / e_FE - 1,   e^2 = elastic / (elastic + dissipated) energy at the peak

The law's targets: dent within 3 % (or 0.5 % of alpha_max), radius within 2 %, unloading within
2 % of P_max, e within 1 % (DENT_TARGET, DENT_TARGET_OF_ALPHA_MAX, RADIUS_TARGET, UNLOADING_TARGET,
E_TARGET).
"""
from __future__ import annotations

import warnings

import numpy as np

from nfdmodel import RangeWarning, get_law

DENT_TARGET, DENT_TARGET_OF_ALPHA_MAX, RADIUS_TARGET, UNLOADING_TARGET, E_TARGET = 0.03, 0.005, 0.02, 0.02, 0.01


def unload_against_path(law_name: str, params, path: dict) -> dict:
    """``path``: ``loading_approach``, ``loading_force`` (to the peak, the last point the peak),
    ``unloading_approach``, ``unloading_force``, ``P_max``, ``alpha_max``, ``alpha_residual``,
    ``radius_at_peak`` (None: not known; radius_error None, not judged), ``e`` [SI]; the figures of
    the module doc, and ``within`` (all targets met)."""
    law = get_law(law_name)
    state = law.initial_state(1)
    approach = np.concatenate([path["loading_approach"], path["unloading_approach"]])
    forces = np.empty(approach.size)
    peak = len(path["loading_approach"]) - 1
    with warnings.catch_warnings():      # the FE's own paths: at their top the law may exceed
        warnings.simplefilter("ignore", RangeWarning)   # the window by its fit error
        for k, delta in enumerate(approach):
            details = law.contact_state(np.array([delta]), state, params)
            state = details.state
            forces[k] = details.force[0]
            if k == peak:
                radius, dent = float(details.a_ep[0]), float(details.delta_res[0])
                stored = float(details.elastic_energy[0] + details.dissipated_energy[0])
                e_law = float(np.sqrt(details.elastic_energy[0] / stored)) if stored > 0 else 1.0
    P_max, alpha_max, alpha_res = path["P_max"], path["alpha_max"], path["alpha_residual"]
    loading_error = float(np.abs(forces[:peak + 1] - path["loading_force"]).max() / P_max)
    unloading_error = float(np.abs(forces[peak + 1:] - path["unloading_force"]).max() / P_max)
    dent_error, dent_of_alpha_max = dent / alpha_res - 1.0, (dent - alpha_res) / alpha_max
    radius_fe = path.get("radius_at_peak")          # None: the FE record keeps no contact radius
    radius_error = None if radius_fe is None else radius / radius_fe - 1.0
    e_error = e_law / path["e"] - 1.0
    within = ((abs(dent_error) <= DENT_TARGET or abs(dent_of_alpha_max) <= DENT_TARGET_OF_ALPHA_MAX)
              and (radius_error is None or abs(radius_error) <= RADIUS_TARGET) and unloading_error <= UNLOADING_TARGET
              and abs(e_error) <= E_TARGET)
    return {"P_max": P_max, "dent_error": dent_error, "dent_error_of_alpha_max": dent_of_alpha_max,
            "radius_error": radius_error, "unloading_error": unloading_error, "loading_error": loading_error,
            "e_fe": path["e"], "e_law": e_law, "e_error": e_error, "within": bool(within)}

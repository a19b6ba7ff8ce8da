"""The active set of frictionless unilateral contact: its warm start and its update.

Signorini conditions at every surface node i: gap g_i = z0_i + u_z,i >= 0, reaction
lambda_i >= 0, g_i lambda_i = 0. The primal active-set strategy (Wriggers 2006, Computational
Contact Mechanics, ch. 6) solves equilibrium with the active nodes held at g = 0, then releases
active nodes with a tensile reaction and adds open nodes that penetrate, until neither exists.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

from calib.fe.state import ContactState
from nfdmodel.hertz_contact import hertz_radius
from nfdmodel.materials import plane_strain_modulus


def predict_active_set(state: ContactState, control: str, target: float, candidate_r,
                       sphere_radius: float, material):
    """Warm start of the active set: the nodes inside a predicted contact radius.

    The previous step's radius scaled by a power of the load: the exponent measured over
    the previous step when there is one (elastoplastic contacts grow faster than Hertz's),
    else the Hertz similarity a ~ P^(1/3) (force control) or a ~ alpha^(1/2) (displacement
    control) (Johnson 1985, eq. 4.22-4.23); on the first
    step, the Hertz radius itself when the material has E and nu. A wrong guess costs only
    active-set iterations (the loop corrects it either way); it saves most of them because
    the primal active set otherwise grows by about one ring of nodes per iteration.
    ``candidate_r`` [m]: r of the contact candidate nodes (sorted); ``sphere_radius`` [m]: R.
    """
    previous = state.force if control == "force" else state.alpha
    if state.contact_radius > 0 and previous > 0 and target > 0:
        if state.radius_exponents is not None:  # learnt from the last step (plasticity
            exponent = state.radius_exponents[0 if control == "force" else 1]  # grows a faster)
        else:
            exponent = 1.0 / 3.0 if control == "force" else 0.5
        predicted = state.contact_radius * (target / previous) ** exponent
    elif target > 0 and hasattr(material, "E") and hasattr(material, "nu"):
        E_star = plane_strain_modulus(material.E, material.nu)
        predicted = (hertz_radius(target, sphere_radius, E_star) if control == "force"
                     else np.sqrt(sphere_radius * target))
    else:
        return state.active.copy() | (np.arange(state.active.size) == 0)
    active = candidate_r <= predicted
    active[0] = target > 0 or state.active[0]  # the pole: force control needs a support
    if control == "displacement" and state.active.any():
        # a node that separated inside the last contact stays open (the pole lifts off at a/R 0.28 on
        # contact elements R/100): pulled back onto the flat, Newton stalls at a residual of 0.04
        active &= state.active | (candidate_r > candidate_r[state.active].max())
    return active


class ActiveSetUpdate(NamedTuple):
    """``settled``: the set satisfies the contact conditions; else ``active`` is the next set to
    try, or None when every candidate has been tried before (the set cycles)."""

    settled: bool
    active: np.ndarray | None


def next_active_set(active, reaction, gap, visited: set, *, force_tolerance: float,
                    gap_tolerance: float, force_scale: float, length_scale: float,
                    force_control: bool) -> ActiveSetUpdate:
    """The active set after one equilibrium solve: release tensile, add penetrating nodes.

    active (bool per candidate node), reaction [N] (> 0 compressive), gap [m] at the candidates;
    ``visited``: the sets (``tobytes()``) already solved, to which the new one is added.
    A reaction is tensile below -``force_tolerance`` (reactions are only known to the Newton
    tolerance: noise, e.g. at the pole whose P2 weight 2 pi r vanishes, must not flip the set);
    a node penetrates below -``gap_tolerance``. A set seen before (cycling between two sets)
    is answered by changing only the single worst node, its violation measured as reaction /
    ``force_scale`` or gap / ``length_scale``; if that set was seen too, the set cycles. Under
    force control the plate needs a support: an empty set keeps the node with the smallest gap.
    """
    tensile = active & (reaction < -force_tolerance)
    penetrating = ~active & (gap < -gap_tolerance)
    if not (tensile.any() or penetrating.any()):
        return ActiveSetUpdate(True, None)
    new_active = (active | penetrating) & ~tensile
    if new_active.tobytes() in visited:
        violation = np.where(tensile, -reaction / force_scale, 0.0)
        violation = np.maximum(violation, np.where(penetrating, -gap / length_scale, 0.0))
        worst = int(np.argmax(violation))
        new_active = active.copy()
        new_active[worst] = not active[worst]
        if new_active.tobytes() in visited:
            return ActiveSetUpdate(False, None)
    if force_control and not new_active.any():
        new_active[int(np.argmin(gap))] = True
    visited.add(new_active.tobytes())
    return ActiveSetUpdate(False, new_active)

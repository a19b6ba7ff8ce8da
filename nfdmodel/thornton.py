"""Thornton (1997) elastic-perfectly plastic contact (law name "thornton").

Hertz up to first yield, then the mean contact pressure is capped at p_Y = A_Y sigma_Y:

    loading    P = P_Y + pi p_Y R* (delta - delta_Y)                     for delta > delta_Y
    unloading  P = (4/3) E* sqrt(R_p*) <delta - delta_p>^(3/2), from the turning point (P*, delta*),
               a*^2 = (2 P* + P_Y) / (2 pi p_Y), R_p* = 4 E* a*^3 / (3 P*), delta_p = delta* - a*^2 / R_p*

(Thornton 1997, J. Appl. Mech. 64, 383, eqs. 10-16); reloading retraces unloading. Its impact on a
rigid flat has the closed-form restitution (Thornton 1997; paper eq. 1.11), r = v_Y / v_in <= 1:

    e = sqrt(6 sqrt(3)/5) sqrt(1 - r^2/6) [r / (r + 2 sqrt(6/5 - r^2/5))]^(1/4)   [-]

This module is the one home of Thornton's formulas (tests/test_formula_homes.py) and the law as one unit:
its history (:class:`ThorntonState`; its parameters are a bare ContactPair), numpy kernel and ``LAW``; the
scalar specification is ``nfdmodel.reference.thornton_step``.
"""
from __future__ import annotations

import math

import numpy as np

from . import native
from .contact_law import ContactLaw
from .hertz import hertz_kernel
from .history import TurningPointHistory, check_delta, check_state, restore_shape, step_and_commit
from .materials import ContactPair, as_pair
from .turning_point import turning_point_step

TINY = 1e-300                   # [N] keeps a zero force out of a division


class ThorntonState(TurningPointHistory):
    """History of the Thornton law (delta_res is Thornton's delta_p)."""


def _thornton_unloading(P_max, delta_max, pair: ContactPair):
    """Thornton (1997) unloading from (P*, delta*) [SI]: a*^2 = (2 P* + P_Y)/(2 pi p_Y),
    R_p* = 4 E* a*^3 / (3 P*), delta_p = delta* - a*^2 / R_p*; returns (delta_p, (4/3) E* sqrt(R_p*))."""
    a_sq = (2.0 * P_max + pair.P_Y) / (2.0 * math.pi * pair.p_Y)
    R_p = 4.0 * pair.E_star * a_sq * np.sqrt(a_sq) / (3.0 * P_max)
    return np.maximum(delta_max - a_sq / R_p, 0.0), 4.0 / 3.0 * pair.E_star * np.sqrt(R_p)


def _thornton_loading_branch(pair: ContactPair):
    def branch(delta, _state, _index, out=None):
        plastic = delta > pair.delta_Y
        force = np.where(plastic, pair.P_Y + math.pi * pair.p_Y * pair.R_star * (delta - pair.delta_Y),
                         hertz_kernel(delta, pair))
        delta_p, stiffness = _thornton_unloading(np.maximum(force, TINY), delta, pair)
        return {"P_max": force, "delta_res": np.where(plastic, delta_p, 0.0),
                "unloading_stiffness": np.where(plastic, stiffness, pair.hertz_stiffness)}, 0

    return branch


def thornton_step(delta, state: ThorntonState, params):
    """One Thornton step without committing it: (P [N], :class:`HistoryUpdate`) (see
    :func:`thornton_force`); ``state`` is not modified."""
    pair = as_pair(params, "thornton")
    check_state(state, ThorntonState, "thornton")
    delta, shape = check_delta(delta, state.n)
    if native.active():
        force, update, _ = native.turning_point_step(native.law_loading("thornton", native.kernel_params(pair)),
                                                     delta, state, pair, True)
    else:
        force, update = turning_point_step(delta, state, _thornton_loading_branch(pair), True, pair)
    return restore_shape(force, shape), update


def thornton_force(delta, state: ThorntonState, params):
    """Thornton (1997) force [N]: Hertz up to delta_Y, then P = P_Y + pi p_Y R* (delta - delta_Y)
    (p_Y = A_Y sigma_Y); unloading from (P*, delta*) Hertzian with the enlarged radius R_p*:
    P = (4/3) E* sqrt(R_p*) (delta - delta_p)^(3/2) (Thornton 1997). params: a ContactPair.
    Pure: :func:`thornton_step` + a copying commit."""
    return step_and_commit(thornton_step, delta, state, params)


def thornton_closed_form(v_in, v_Y):
    """Thornton (1997) restitution, paper eq. 1.11, r = v_Y/v_in (valid for v_in >= v_Y; both [m/s]):
    e = sqrt(6 sqrt(3)/5) sqrt(1 - r^2/6) [r / (r + 2 sqrt(6/5 - r^2/5))]^(1/4) [-]."""
    r = v_Y / np.asarray(v_in, dtype=float)
    return (np.sqrt(6.0 * np.sqrt(3.0) / 5.0) * np.sqrt(1.0 - r**2 / 6.0)
            * (r / (r + 2.0 * np.sqrt(6.0 / 5.0 - r**2 / 5.0))) ** 0.25)


def thornton_loading_work(delta_max, pair: ContactPair):
    delta_max = np.asarray(delta_max, dtype=float)
    elastic_part = np.minimum(delta_max, pair.delta_Y)
    plastic_part = np.maximum(delta_max - pair.delta_Y, 0.0)
    return (0.4 * pair.hertz_stiffness * elastic_part**2 * np.sqrt(elastic_part)
            + pair.P_Y * plastic_part + 0.5 * math.pi * pair.p_Y * pair.R_star * plastic_part**2)


def thornton_radii(force, a_e, state: ThorntonState, pair: ContactPair):
    """(a_p, a_ep) [m]: after yield the contact radius at the turning point is a* (a*^2 =
    (2 P* + P_Y) / (2 pi p_Y), Thornton 1997) and on unloading a ~ P^(1/3) at the fixed R_p*,
    a_ep = a* (P / P*)^(1/3); below yield the Hertz radius a_e; a_p = a_ep - a_e >= 0."""
    yielded = state.P_max > pair.P_Y
    a_sq = np.where(yielded, (2.0 * state.P_max + pair.P_Y) / (2.0 * math.pi * pair.p_Y), 0.0)
    s = force / np.maximum(state.P_max, TINY)
    a_ep = np.where(yielded, np.sqrt(a_sq) * np.cbrt(s), a_e)
    return np.maximum(a_ep - a_e, 0.0), a_ep


LAW = ContactLaw("thornton", "Thornton (1997) elastic-perfectly plastic contact", thornton_force, ThorntonState,
                 lambda delta_max, P_max, pair: thornton_loading_work(delta_max, pair), 1.5, thornton_step,
                 params_function=lambda params: as_pair(params, "thornton"), radii_function=thornton_radii,
                 collision_params=native.kernel_params)

"""Hertz elastic contact (Johnson 1985, Contact Mechanics, eq. 4.23): no history.

    P = (4/3) E* sqrt(R*) <delta>^(3/2)    [N],  delta the approach [m]

Its parameters are a bare ContactPair and its state the shared no-history ``HertzState``
(:mod:`nfdmodel.history`); the scalar specification is ``nfdmodel.reference.hertz_step``.
"""
from __future__ import annotations

import numpy as np

from . import native
from .contact_law import ContactLaw
from .history import HertzState, check_delta, check_force, check_state, empty_update, restore_shape, step_and_commit
from .materials import as_pair


def hertz_step(delta, state: HertzState, params):
    """Hertz (Johnson 1985 eq. 4.23): P = (4/3) E* sqrt(R*) <delta>^(3/2) [N] and an empty
    :class:`HistoryUpdate` (no history). params: a ContactPair (or anything with .pair)."""
    pair = as_pair(params, "hertz")
    check_state(state, HertzState, "hertz")
    delta, shape = check_delta(delta, state.n)
    if native.active():
        return restore_shape(native.hertz_forces(delta, pair), shape), empty_update(state, state.n)
    with np.errstate(over="ignore"):     # an overflowing force is check_force's ValueError
        force = hertz_kernel(delta, pair)
    return restore_shape(check_force(force, delta, pair), shape), empty_update(state, state.n)


def hertz_force(delta, state: HertzState, params):
    """Hertz (Johnson 1985 eq. 4.23): P = (4/3) E* sqrt(R*) <delta>^(3/2) [N]; no history.

    params: a ContactPair (or anything with .pair). Returns (P, state) (the state unchanged).
    """
    return step_and_commit(hertz_step, delta, state, params)


def hertz_kernel(delta, pair):
    d = np.maximum(delta, 0.0)
    force = np.sqrt(d)
    force *= d
    force *= pair.hertz_stiffness
    return force


def hertz_work(delta_max, P_max, pair):
    """Work of Hertz loading to delta_max: (2/5) k_H delta_max^(5/2) [J]."""
    d = np.maximum(delta_max, 0.0)
    return 0.4 * pair.hertz_stiffness * d**2 * np.sqrt(d)


LAW = ContactLaw("hertz", "Hertz elastic contact (Johnson 1985)", hertz_force, HertzState, hertz_work, 1.5, hertz_step,
                 params_function=lambda params: as_pair(params, "hertz"), collision_params=native.kernel_params)

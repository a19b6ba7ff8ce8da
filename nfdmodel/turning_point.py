"""The kernel the elastoplastic laws share: unloading and reloading about a turning point.

Each contact remembers its turning point (delta_max, P_max), the approach delta_res at which
the unloading curve through it reaches P = 0, and that curve's constant K_u. Unloading AND
reloading below delta_max follow

    P = K_u <delta - delta_res>^n

with n = 3/2 (vz, thornton: Hertzian unloading) or n = 1 (walton-braun); K_u and delta_res are
fixed when the turning point moves so that the curve passes through (delta_max, P_max): the force
is continuous at every turning point, reloading retraces unloading, a constant delta gives a
constant force, and delta <= delta_res is separation (P = 0, re-contact above it). For vz this
is the paper's eq. 3.22, K_u = (4/3) E* C_Rmax^(3/2) sqrt(R*). Beyond delta_max the contact
loads on the law's virgin curve (its ``loading_branch``) and the turning point moves.
"""
from __future__ import annotations

import numpy as np

from .history import HistoryUpdate, check_force, empty_update, field_names
from .materials import ContactPair

BLOCK = 16384                   # contacts per block of the step kernel (temporaries stay in cache)


def elastic_energy(force, delta, delta_res, exponent):
    """The elastic energy [J] a contact returns if it unloads from approach ``delta`` [m] at force
    ``force`` [N] on its unloading curve P = K_u <delta - delta_res>^n (module doc): the curve's
    integral from delta_res to delta, E_el = P <delta - delta_res> / (n + 1) (n = ``exponent``; a
    Hertz contact: delta_res = 0, n = 3/2). On the virgin curve at the turning point it is the energy
    the unloading returns (e^2 = E_el / W); the plastic energy dissipated so far is the work minus it.
    The C kernel's nfd_elastic_energy is the same formula."""
    return force * np.maximum(delta - delta_res, 0.0) / (exponent + 1.0)


def blocks(n: int):
    """Slices of at most BLOCK contacts covering 0..n-1 (one slice(None) when n <= BLOCK)."""
    if n <= BLOCK:
        return (slice(None),)
    return tuple(slice(first, min(first + BLOCK, n)) for first in range(0, n, BLOCK))


def turning_point_step(delta, state, loading_branch, three_halves: bool, pair: ContactPair):
    """:func:`step_kernel` with numpy's overflow and invalid-value warnings off: a force that
    overflows (delta ~ 1e300 m) ends in check_force's ValueError naming delta, never in a
    warning first."""
    with np.errstate(over="ignore", invalid="ignore"):
        return step_kernel(delta, state, loading_branch, three_halves, pair)


def step_kernel(delta, state, loading_branch, three_halves: bool, pair: ContactPair):
    """Force and sparse trial history of a turning-point law (module doc): (P, HistoryUpdate).

    Unloading/reloading for all contacts: P = K_u <delta - delta_res>^n (n = 3/2 if
    ``three_halves``, else 1); then, for the contacts with delta > delta_max,
    ``loading_branch(delta, state, index, out) -> (new field values, iterations)`` on the virgin
    curve (it may write the values into the arrays of the dict ``out``, or None, and return
    those arrays), which moves their turning point (P_max is the new force, delta_max the new approach).
    ``state`` is not modified; the update's arrays share no memory with ``delta`` or ``state``.

    Work is done in blocks of BLOCK contacts (loading contacts for the loading branch) so that
    the temporaries stay in cache; every operation is elementwise, so the result does not
    depend on the blocking. ``delta`` is checked by the caller (:func:`check_delta`); the
    overflow check of the force (:func:`check_force`, ValueError naming delta) uses a sum
    taken block by block while the forces are in cache, instead of one more pass.
    """
    n = delta.shape[0]
    force = np.empty(n)
    loading_mask = np.empty(n, dtype=bool)
    gap_buffer = np.empty(min(n, BLOCK))
    arrays = (delta, force, state.delta_res, state.unloading_stiffness, state.delta_max, loading_mask)
    force_sum = 0.0
    add = np.add.reduce
    for d, f, delta_res, stiffness, delta_max, mask in (
            (arrays,) if n <= BLOCK else (tuple(a[block] for a in arrays) for block in blocks(n))):
        gap = gap_buffer if f.shape[0] == gap_buffer.shape[0] else gap_buffer[:f.shape[0]]
        np.subtract(d, delta_res, out=gap)
        np.maximum(gap, 0.0, out=gap)
        if three_halves:
            np.sqrt(gap, out=f)
            f *= gap
            f *= stiffness
        else:
            np.multiply(gap, stiffness, out=f)
        force_sum += add(f)
        np.greater(d, delta_max, out=mask)
    loading = loading_mask.nonzero()[0]                  # (np.flatnonzero without its wrappers)
    k = loading.shape[0]
    if k == 0:
        update = empty_update(state, n)
    elif k <= BLOCK:
        delta_loading = delta[loading]
        new_values, iterations = loading_branch(delta_loading, state, loading)
        P = new_values["P_max"]
        force[loading] = P
        force_sum += add(P)
        update = HistoryUpdate(loading, type(state)(delta_max=delta_loading, **new_values), n, int(iterations))
    else:
        values = {name: np.empty(k) for name in field_names(type(state))}
        iterations = 0
        for block in blocks(k):
            index = loading[block]
            delta_loading = np.take(delta, index, out=values["delta_max"][block], mode="clip")
            out = {name: values[name][block] for name in values if name != "delta_max"}
            new_values, block_iterations = loading_branch(delta_loading, state, index, out)
            for name, array in new_values.items():
                if array is not out[name]:          # not written in place by the branch
                    values[name][block] = array
            P = new_values["P_max"]
            force[index] = P
            force_sum += add(P)
            iterations = max(iterations, int(block_iterations))
        update = HistoryUpdate(loading, type(state)(**values), n, iterations)
    # force_sum covers every entry of force (and the overwritten unloading values: a false
    # alarm there only triggers the exact elementwise test)
    check_force(force, delta, pair, float(force_sum))
    return force, update

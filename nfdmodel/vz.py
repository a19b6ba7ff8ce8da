"""The Vu-Quoc & Zhang (1999) elastoplastic NFD law as a runtime kernel (law name "vz").

Loading beyond the turning point: Hertz up to delta_Y, then the root of the corrected F(P) on
the loading curve (nfdmodel.vz_curve). Unloading and reloading below delta_max: a_p and C_R
frozen at P_max, P = (4/3) E* C_Rmax^(3/2) sqrt(R*) <delta - delta_res>^(3/2) (paper eqs.
3.19-3.22; nfdmodel.turning_point). Separation for delta <= delta_res, re-contact above it.
"""
from __future__ import annotations

import dataclasses

import numpy as np

from . import native
from .contact_law import ContactLaw, plastic_radii
from .hertz import hertz_kernel
from .history import VZState, apply_update, check_delta, check_state, restore_shape, step_and_commit
from .parameters import VZParams
from .turning_point import turning_point_step
from .vz_curve import vz_loading_work, vz_plastic_solve, vz_turning_point
from .window import check_contact_radius_below_R


def vz_params(params) -> VZParams:
    """``params`` when it is a VZParams, else a ValueError naming params."""
    if not isinstance(params, VZParams):
        raise ValueError(f"params for law 'vz' must be VZParams, got {type(params).__name__}")
    return params


def _kernel_params(params: VZParams) -> tuple:
    return native.kernel_params(params.pair, params.Ca, params.Kc, params.window_force, c1=params.c1)


def _vz_loading_branch(params: VZParams):
    pair = params.pair
    radius_per_cube_root = params.c1 * params.Ca        # a_e = (3 R*/(4 E*))^(1/3) P^(1/3)

    def branch(delta, state, index, out=None):
        if delta.min() > pair.delta_Y:          # all plastic (the usual case; delta is finite)
            out = {} if out is None else out
            start = state.a_e_max[index]
            start /= radius_per_cube_root       # P^(1/3) at the old turning point
            P, cube_root, iterations = vz_plastic_solve(delta, start, params, start_is_cube_root=True,
                                                         out=out.get("P_max"))
            a_e_max = np.multiply(cube_root, radius_per_cube_root, out=out.get("a_e_max"))
            delta_res, stiffness = vz_turning_point(
                delta, P, cube_root, params, a_e=a_e_max,
                out=(out.get("delta_res"), out.get("unloading_stiffness")))
            return ({"P_max": P, "delta_res": delta_res, "unloading_stiffness": stiffness,
                     "a_e_max": a_e_max}, int(iterations.max()))
        # Hertz below yield: delta_res = 0, K_u = k_H, a = sqrt(R delta)
        out = {"P_max": hertz_kernel(delta, pair), "delta_res": np.zeros_like(delta),
               "unloading_stiffness": np.full_like(delta, pair.hertz_stiffness),
               "a_e_max": np.sqrt(pair.R_star * np.maximum(delta, 0.0))}
        plastic = np.flatnonzero(delta > pair.delta_Y)
        if plastic.size == 0:
            return out, 0
        delta_plastic = delta[plastic]
        start = state.a_e_max[index[plastic]] / radius_per_cube_root
        P, cube_root, iterations = vz_plastic_solve(delta_plastic, start, params, start_is_cube_root=True)
        out["P_max"][plastic] = P
        out["a_e_max"][plastic] = a_e_max = cube_root * radius_per_cube_root
        out["delta_res"][plastic], out["unloading_stiffness"][plastic] = vz_turning_point(
            delta_plastic, P, cube_root, params, a_e=a_e_max)
        return out, int(iterations.max())

    return branch


def vz_step(delta, state: VZState, params: VZParams):
    """One vz step without committing it: (P [N], :class:`HistoryUpdate`); ``state`` is not modified.

    The force is :func:`vz_force`'s; the update holds the contacts with delta > delta_max, their
    new turning point (delta_max, P_max, delta_res, K_u = (4/3) E* C_Rmax^(3/2) sqrt(R*), a_e,max;
    paper eqs. 3.19-3.22) and the largest Newton iteration count of the step.
    """
    vz_params(params)
    check_state(state, VZState, "vz")
    delta, shape = check_delta(delta, state.n)
    if native.active():
        pair = params.pair
        force, update, (_, beyond, largest_P, widest, widest_radius, _) = native.turning_point_step(
            native.law_loading("vz", _kernel_params(params)), delta, state, pair, True)
        if update.size:
            check_contact_radius_below_R(widest_radius, pair.R_star, float(update.values.delta_max[widest]), params)
            if beyond:
                update = dataclasses.replace(update, beyond_window=beyond, largest_load_over_P_Y=largest_P / pair.P_Y)
        return restore_shape(force, shape), update
    force, update = turning_point_step(delta, state, _vz_loading_branch(params), True, params.pair)
    if update.size:                  # sparse: only the contacts whose turning point moved
        update = _check_reach(update, params)
    return restore_shape(force, shape), update


def _check_reach(update, params: VZParams):
    """The contacts that loaded in this step against R* (ValueError) and the calibrated window
    (counted in the update; ContactLaw.step warns): a few passes over the loading contacts only."""
    pair = params.pair
    P_max = update.values.P_max
    radius = update.values.a_e_max + params.Ca * np.maximum(P_max - pair.P_Y, 0.0)
    largest = int(np.argmax(radius))
    check_contact_radius_below_R(float(radius[largest]), pair.R_star, float(update.values.delta_max[largest]),
                                 params)
    P_limit = params.window_force
    if not float(P_max.max()) > P_limit:
        return update
    beyond = int(np.count_nonzero(P_max > P_limit))
    return dataclasses.replace(update, beyond_window=beyond, largest_load_over_P_Y=float(P_max.max()) / pair.P_Y)


def vz_force_with_iterations(delta, state: VZState, params: VZParams):
    """:func:`vz_force` that also returns the largest number of Newton iterations of the step."""
    force, update = vz_step(delta, state, params)
    return force, apply_update(state, update, copy=True), update.newton_iterations


def vz_force(delta, state: VZState, params: VZParams):
    """Vu-Quoc & Zhang (1999) displacement-driven NFD force P(delta, history) [N].

    Loading beyond the turning point (delta > delta_max): Hertz for delta <= delta_Y, else the
    root of the corrected F(P) (:func:`vz_plastic_force`, paper eqs. 3.4-3.14). Unloading and
    reloading below delta_max (paper eqs. 3.19-3.22): a_p and C_R frozen at P_max,
    P = (4/3) E* C_Rmax^(3/2) sqrt(R*) <delta - delta_res>^(3/2), which retraces back to
    (delta_max, P_max) and then continues plastically; separation (P = 0) for delta <= delta_res,
    re-contact above it. Any (R*, E*). Pure: :func:`vz_step` + a copying commit.
    """
    return step_and_commit(vz_step, delta, state, params)


def vz_newton_iterations(delta, state: VZState, params: VZParams) -> np.ndarray:
    """Newton iterations per contact for one vz step (0 where no Newton solve is needed)."""
    delta, _ = check_delta(delta, state.n)
    counts = np.zeros(delta.shape[0], dtype=np.int64)
    plastic = np.flatnonzero((delta > state.delta_max) & (delta > params.pair.delta_Y))
    if plastic.size:
        start = state.a_e_max[plastic] / (params.c1 * params.Ca)
        _, _, counts[plastic] = vz_plastic_solve(delta[plastic], start, params, start_is_cube_root=True)
    return counts


LAW = ContactLaw("vz", "Vu-Quoc & Zhang (1999) elastoplastic NFD model", vz_force, VZState, vz_loading_work, 1.5,
                 vz_step, params_function=vz_params, radii_function=plastic_radii, fitted=True,
                 collision_params=_kernel_params)

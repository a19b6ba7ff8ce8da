"""Walton & Braun (1986) bilinear hysteretic spring (law name "walton-braun").

    loading     P = K1 delta                                   [N]
    unloading   P = K2 <delta - delta_res>,  delta_res = delta_max - P_max / K2

K1 <= K2 [N/m]; a collision's restitution is e = sqrt(K1 / K2). Reloading retraces unloading.
"""
from __future__ import annotations

import numpy as np

from . import native
from .contact_law import ContactLaw
from .history import WaltonBraunState, check_delta, check_state, restore_shape, step_and_commit
from .parameters import VZParams, WaltonBraunParams, as_pair
from .turning_point import turning_point_step


def walton_braun_params(params) -> WaltonBraunParams:
    """WaltonBraunParams as given, or the defaults of a VZParams / ContactPair (:meth:`WaltonBraunParams.from_vz`)."""
    if isinstance(params, WaltonBraunParams):
        return params
    if isinstance(params, VZParams):
        return WaltonBraunParams.from_vz(params)
    return WaltonBraunParams.from_pair(as_pair(params, "walton-braun"))


def _walton_braun_loading_branch(params: WaltonBraunParams):
    def branch(delta, _state, _index, out=None):
        force = params.K1 * delta
        return {"P_max": force, "delta_res": delta - force / params.K2,
                "unloading_stiffness": np.full_like(delta, params.K2)}, 0

    return branch


def walton_braun_force(delta, state: WaltonBraunState, params):
    """Walton & Braun (1986) force [N]: P = K1 delta on loading, P = K2 <delta - delta_res> on
    unloading/reloading with delta_res = delta_max - P_max/K2 (Walton & Braun 1986).

    params: WaltonBraunParams; a VZParams or ContactPair gives the documented defaults
    (:meth:`WaltonBraunParams.from_vz`, secants through the turning point at 40 P_Y).
    Pure: :func:`walton_braun_step` + a copying commit.
    """
    return step_and_commit(walton_braun_step, delta, state, params)


def walton_braun_step(delta, state: WaltonBraunState, params):
    """One Walton-Braun step without committing it: (P [N], :class:`HistoryUpdate`) (see
    :func:`walton_braun_force`); ``state`` is not modified."""
    wb = walton_braun_params(params)
    check_state(state, WaltonBraunState, "walton-braun")
    delta, shape = check_delta(delta, state.n)
    if native.active():
        force, update, _ = native.turning_point_step(native.law_loading("walton-braun", _kernel_params(wb)),
                                                     delta, state, wb.pair, False)
    else:
        force, update = turning_point_step(delta, state, _walton_braun_loading_branch(wb), False, wb.pair)
    return restore_shape(force, shape), update


def _kernel_params(wb: WaltonBraunParams) -> tuple:
    return native.kernel_params(wb.pair, K1=wb.K1, K2=wb.K2)


LAW = ContactLaw("walton-braun", "Walton & Braun (1986) bilinear hysteretic spring", walton_braun_force,
                 WaltonBraunState, lambda delta_max, P_max, wb: 0.5 * wb.K1 * np.maximum(delta_max, 0.0) ** 2, 1.0,
                 walton_braun_step, params_function=walton_braun_params, collision_params=_kernel_params)

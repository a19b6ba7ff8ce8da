"""Walton & Braun (1986) bilinear hysteretic spring (law name "walton-braun").

    loading     P = K1 delta                                   [N]
    unloading   P = K2 <delta - delta_res>,  delta_res = delta_max - P_max / K2

K1 <= K2 [N/m]; a collision's restitution is e = sqrt(K1 / K2). Reloading retraces unloading.
The law as one unit: its parameters (:class:`WaltonBraunParams`), history (:class:`WaltonBraunState`),
numpy kernel and ``LAW``; the scalar specification is ``nfdmodel.reference.walton_braun_step``.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import native
from .contact_law import ContactLaw
from .history import TurningPointHistory, check_delta, check_state, restore_shape, step_and_commit
from .materials import ContactPair, as_pair
from .turning_point import turning_point_step
from .validation import check_real
from .vz import VZParams
from .vz_curve import vz_residual_approach


class WaltonBraunState(TurningPointHistory):
    """History of the Walton-Braun law (delta_res = delta_max - P_max / K2)."""


@dataclass(frozen=True)
class WaltonBraunParams:
    """Walton & Braun (1986) stiffnesses: K1 [N/m] > 0 loading, K2 [N/m] >= K1 unloading.

    e = sqrt(K1/K2) in a collision. Defaults from a pair (:meth:`from_vz`): secants of the vz
    loading and unloading curves through a reference turning point.
    """

    pair: ContactPair
    K1: float
    K2: float

    def __post_init__(self):
        if not isinstance(self.pair, ContactPair):
            raise ValueError(f"pair must be a ContactPair, got {type(self.pair).__name__}")
        object.__setattr__(self, "K1", check_real("K1", self.K1, low=0.0, unit="N/m"))
        object.__setattr__(self, "K2", check_real("K2", self.K2, low=self.K1, low_inclusive=True,
                                                  unit="N/m (K2 >= K1, otherwise energy is created)"))

    @classmethod
    def from_vz(cls, vz_params: "VZParams", P_ref: float | None = None) -> "WaltonBraunParams":
        """Secant stiffnesses of the vz model through the turning point at P_ref [N].

        K1 = P_ref / delta_max (loading secant), K2 = P_ref / (delta_max - delta_res) (unloading
        secant), so that e = sqrt(K1/K2) equals the vz energy ratio of a triangle-shaped cycle.
        P_ref defaults to 40 P_Y (the paper's AFG load path: 1500 N ~ 41 P_Y).
        """
        pair = vz_params.pair
        P_ref = 40.0 * pair.P_Y if P_ref is None else check_real("P_ref", P_ref, low=pair.P_Y, unit="N")
        delta_max = float(vz_params.loading_approach(P_ref))
        delta_res = vz_residual_approach(delta_max, np.asarray(P_ref), vz_params)
        return cls(pair, P_ref / delta_max, P_ref / (delta_max - float(delta_res)))

    @classmethod
    def from_pair(cls, pair: ContactPair) -> "WaltonBraunParams":
        """Defaults for a bare pair: :meth:`from_vz` with the paper's dimensionless Ca_hat, Kc_hat."""
        reference = VZParams.reference()
        return cls.from_vz(VZParams.from_dimensionless(pair, reference.Ca_hat, reference.Kc_hat))


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

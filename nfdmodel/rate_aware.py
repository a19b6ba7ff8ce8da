"""The rate-aware law: a base law whose yield stress is scaled by the contact's strain rate (law "rate-aware").

The flow stress of a rate-dependent metal is sigma_Y R(eps_dot) (nfdmodel.strain_rate: Johnson & Cook 1983,
Cowper & Symonds 1957). A contact's strain rate is taken from the normal approach speed at first contact
v_n0 [m/s] and the contact size,

    eps_dot = v_n0 / (c a_ref)                                                               [1/s]

a_ref [m] the contact radius the rate-independent base law reaches at the peak of a sphere-on-flat impact
at v_n0 (its energy balance, nfdmodel.collision_reference, with the pair's m*), c [-] a constant calibrated
once against the dynamic FE with the rate law (RATE_LENGTH_FACTOR, nfdmodel/README.md). The factor
R = R(eps_dot) is fixed at first contact (the history's ``rate_factor``; 0 until the contact first
touches) and held for the contact's life: the law is the base law with p_Y = A_Y(nu) sigma_Y R.

The base laws whose constants are dimensionless in (R*, E*, p_Y) (vz's Ca_hat = Ca P_Y / a_Y, Kc_hat =
Kc P_Y; vz-table's f, g over P/P_Y) scale exactly with p_Y: P_Y ~ p_Y^3, delta_Y ~ p_Y^2, a_Y ~ p_Y, so

    P(delta; R) = R^3 P_0(delta / R^2)                                                        [N]

with the history held in the base law's units at R = 1 (delta_max, delta_res ~ R^2, P_max ~ R^3, a_e,max ~
R, K_u ~ R^0): each step maps the contacts into the base law's units, steps the base law (its numpy or
compiled kernel) and maps the trial history back. The base constants' dimensionless values are held
while sigma_Y changes (their weak dependence on E*/sigma_Y is neglected, as the master table's radius
transfer does). Units SI. The scalar specification: nfdmodel.reference.rate_aware_step. The compiled
kernel: nfd_rate.h (nfd_rate_step, R found there as here), which the native backend and collide run.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from . import limits, native
from .collision import CollisionReference, collision_reference
from .contact_law import ContactLaw
from .history import HistoryUpdate, TurningPointHistory, apply_update, check_delta, check_state, restore_shape
from .registry import LAWS
from .strain_rate import CowperSymonds, JohnsonCook
from .validation import check_real
from .vz import VZParams, VZState
from .vz_table import VZTableParams, VZTableState

# c of eps_dot = v_n0 / (c a_ref): fitted once to the dynamic FE (Cowper-Symonds D 40 /s, q 5, 0.02 m/s, coarse
# mesh: 26.2 on that mesh's vz-table, 29 on the shipped one; nfdmodel/README.md, The rate-aware law); nfd_limits.h
RATE_LENGTH_FACTOR = limits.RATE_LENGTH_FACTOR
# the base laws and their history classes (the laws whose constants scale with p_Y)
BASE_LAWS = {"vz": (VZParams, VZState), "vz-table": (VZTableParams, VZTableState)}
# the power of R each history field scales with (module doc)
FIELD_POWERS = {"delta_max": 2.0, "P_max": 3.0, "delta_res": 2.0, "unloading_stiffness": 0.0, "a_e_max": 1.0}


@dataclass(frozen=True)
class RateAwareState(TurningPointHistory):
    """History of the rate-aware law [SI]: the turning point (delta_max, P_max, delta_res,
    unloading_stiffness), a_e_max [m] (the vz base's Hertz radius at P_max; 0 for vz-table) and
    rate_factor [-], R fixed at first contact (0: never touched)."""

    a_e_max: np.ndarray
    rate_factor: np.ndarray


@dataclass(frozen=True)
class RateAwareParams:
    """The rate-aware law: ``base_law`` "vz" or "vz-table" with its parameters ``base`` (the rate-independent
    law), ``rate_law`` a JohnsonCook or CowperSymonds, ``c`` the constant of eps_dot = v_n0 / (c a_ref)."""

    base_law: str
    base: object
    rate_law: object
    c: float = RATE_LENGTH_FACTOR

    def __post_init__(self):
        if self.base_law not in BASE_LAWS:
            raise ValueError(f"base_law must be one of {', '.join(BASE_LAWS)} (a law whose constants scale with "
                             f"sigma_Y), got {self.base_law!r}")
        if type(self.base) is not BASE_LAWS[self.base_law][0]:
            raise ValueError(f"base for base_law {self.base_law!r} must be {BASE_LAWS[self.base_law][0].__name__}, "
                             f"got {type(self.base).__name__}")
        if not isinstance(self.rate_law, (JohnsonCook, CowperSymonds)):
            raise ValueError(f"rate_law must be a JohnsonCook or CowperSymonds, got {type(self.rate_law).__name__}")
        object.__setattr__(self, "c", check_real("c", self.c, low=0.0, unit="(eps_dot = v_n0 / (c a_ref))"))

    @property
    def pair(self):
        return self.base.pair

    @property
    def window(self):
        return self.base.window

    def reference_radius(self, speed):
        """a_ref [m]: the base law's contact radius at the peak of its impact at ``speed`` [m/s] (> 0)."""
        peak = collision_reference(BASE_LAWS_LAW[self.base_law], self.base, speed).P_max
        return self.base.contact_radius_at(peak)

    def strain_rate(self, speed):
        """eps_dot = v_n0 / (c a_ref) [1/s] of first contacts at the normal speeds ``speed`` [m/s]; 0 where
        speed <= 0 (a contact formed without approach)."""
        speed = np.atleast_1d(np.asarray(speed, dtype=float))
        rate = np.zeros(speed.shape)
        moving = speed > 0.0
        if moving.any():
            rate[moving] = speed[moving] / (self.c * self.reference_radius(speed[moving]))
        return rate

    def rate_factor(self, speed):
        """R(eps_dot) [-] fixed at first contact at the normal speeds ``speed`` [m/s]."""
        return self.rate_law.factor(self.strain_rate(speed))

    def record(self) -> dict:
        return {"base_law": self.base_law, **self.rate_law.record(), "c": self.c}


BASE_LAWS_LAW = {name: LAWS[name] for name in BASE_LAWS}


def rate_aware_params(params) -> RateAwareParams:
    if type(params) is not RateAwareParams:     # the relaxing law's (a subclass) is another law's
        raise ValueError(f"params for law 'rate-aware' must be RateAwareParams, got {type(params).__name__}")
    return params


def _base_state(state: RateAwareState, factor, base_state_type):
    """The contacts' history in the base law's units (R = 1)."""
    return base_state_type(**{f.name: getattr(state, f.name) / factor ** FIELD_POWERS[f.name]
                              for f in dataclasses.fields(base_state_type)})


def rate_aware_step(delta, state: RateAwareState, params: RateAwareParams, velocity=None):
    """One step without committing it: (P [N], HistoryUpdate). ``velocity``: the normal approach speed
    d delta / dt [m/s] per contact, needed where a contact first touches (rate_factor 0, delta > 0)."""
    params = rate_aware_params(params)
    check_state(state, RateAwareState, "rate-aware")
    delta, shape = check_delta(delta, state.n)
    factor = state.rate_factor.copy()
    touching = np.flatnonzero((factor == 0.0) & (delta > 0.0))
    speeds = approach_speeds(velocity, state.n, touching, "the rate-aware law", "first touch")
    if native.active():
        compiled = _compiled_step(delta, speeds, state, params)
        if compiled is not None:
            return restore_shape(compiled[0], shape), compiled[1]
    if touching.size:
        factor[touching] = params.rate_factor(speeds[touching])
    force, index, values, update = step_at_factors(delta, state, params, factor, touching)
    largest = update.largest_load_over_P_Y
    return restore_shape(force, shape), HistoryUpdate(index, RateAwareState(**values), state.n,
                                                      update.newton_iterations, update.beyond_window, largest)


def approach_speeds(velocity, n: int, needed, law: str, which: str) -> np.ndarray:
    """The normal approach speeds [m/s] of n contacts from ``velocity`` (zeros where none is needed); a one-line
    ValueError when the contacts ``needed`` (those that ``which`` in this step) have none or a non-finite one."""
    if not needed.size:
        return np.zeros(n)
    if velocity is None:
        raise ValueError(f"velocity out of range: {law} needs the normal approach speed [m/s] of the contacts that "
                         f"{which} in this step")
    speeds = np.broadcast_to(np.asarray(velocity, dtype=float).reshape(-1), (n,))
    if not np.isfinite(speeds[needed]).all():
        raise ValueError("velocity out of range: need finite normal approach speeds [m/s]")
    return speeds


def step_at_factors(delta, state: RateAwareState, params: RateAwareParams, factor, changed):
    """The base law stepped with p_Y scaled by each contact's ``factor`` R (0: untouched, R = 1):
    P = R^3 P_0(delta / R^2) [N] (flat), the index of the contacts whose history changes (the base law's
    moved turning points and ``changed``), their history fields in SI (FIELD_POWERS, rate_factor) and the
    base law's HistoryUpdate."""
    scale = np.where(factor > 0.0, factor, 1.0)
    base_law = BASE_LAWS_LAW[params.base_law]
    base_type = BASE_LAWS[params.base_law][1]
    force, update = base_law.step_function(delta / scale**2, _base_state(state, scale, base_type), params.base)
    force = force.reshape(-1) * scale**3
    index = np.union1d(update.index, changed).astype(np.int64)
    values = {name: getattr(state, name)[index].copy() for name in FIELD_POWERS}
    moved = np.searchsorted(index, update.index)
    for f in dataclasses.fields(base_type):
        values[f.name][moved] = getattr(update.values, f.name) * scale[update.index] ** FIELD_POWERS[f.name]
    values["rate_factor"] = factor[index]
    return force, index, values, update


def compiled_kernel(params: RateAwareParams) -> native.RateKernel:
    """The law as the compiled kernel takes it (nfd_rate.h, native.RateKernel): the base law's code, its
    constants at R = 1 and tables, the rate law's code and constants, c (of either form: RateAwareParams or the
    relaxing law's subclass)."""
    if not isinstance(params, RateAwareParams):
        raise ValueError(f"params of the rate-aware laws must be RateAwareParams, got {type(params).__name__}")
    base = params.base
    if params.base_law == "vz":
        kernel, table = BASE_LAWS_LAW["vz"].collision_params(base), None
    else:
        kernel, table = native.kernel_params(base.pair, window_P_max=base.window_force), native.kernel_table(base)
    rate = params.rate_law
    constants = ((limits.RATE_JOHNSON_COOK, rate.C, rate.reference_rate) if isinstance(rate, JohnsonCook)
                 else (limits.RATE_COWPER_SYMONDS, rate.D, rate.q))
    return native.RateKernel(limits.LAW_CODES[params.base_law], kernel, table, (*constants, params.c))


def _compiled_step(delta, speeds, state: RateAwareState, params: RateAwareParams):
    """(P [N], HistoryUpdate) of the step in the compiled kernel (nfd_rate_step), or None where a contact
    failed there (its radius at R*, an overflow): the numpy path then names the cause in its words."""
    pair = params.pair
    return compiled_update(native.rate_step(compiled_kernel(params), pair.mass_star, delta, speeds, state),
                           RateAwareState, state.n, pair.P_Y)


def compiled_update(result: tuple, state_type, n: int, P_Y: float):
    """(P [N], HistoryUpdate of ``state_type``) from a compiled rate step's ``result`` (native.rate_step,
    with or without k: force, index, values, status, iterations, beyond, largest P_max at R = 1), or None where
    a contact failed there (status < 0)."""
    force, index, values, status, iterations, beyond, largest = result
    if status < 0:
        return None
    return force, HistoryUpdate(index, state_type(**values), n, int(iterations), int(beyond),
                                largest / P_Y if beyond else 0.0)


def rate_aware_force(delta, state: RateAwareState, params: RateAwareParams, velocity=None):
    """The pure law: (P [N], new_state)."""
    force, update = rate_aware_step(delta, state, params, velocity)
    return force, apply_update(state, update, copy=True)


def rate_aware_loading_work(delta_max, P_max, params: RateAwareParams, rate_factor=None):
    """Work on the virgin curve up to (delta_max, P_max) [J] at the rate factor ``rate_factor`` (R^5 W_0)."""
    params = rate_aware_params(params)
    scale = np.ones(np.shape(delta_max)) if rate_factor is None else np.where(rate_factor > 0, rate_factor, 1.0)
    return scale**5 * BASE_LAWS_LAW[params.base_law].loading_work(delta_max / scale**2, P_max / scale**3, params.base)


def rate_aware_reference(params: RateAwareParams, v_in) -> CollisionReference:
    """The exact impact at v_in [m/s] by energy balance: the base law's at v_in / R^(5/2) mapped back
    (W ~ R^5, delta ~ R^2, P ~ R^3, times ~ R^(-1/2))."""
    params = rate_aware_params(params)
    v = np.atleast_1d(np.asarray(v_in, dtype=float)).reshape(-1)
    factor = params.rate_factor(v)
    base = collision_reference(BASE_LAWS_LAW[params.base_law], params.base, v / factor**2.5)
    return CollisionReference(v, base.delta_max * factor**2, base.P_max * factor**3, base.delta_res * factor**2,
                              base.loading_work * factor**5, base.restitution,
                              base.contact_time_estimate / np.sqrt(factor),
                              base.unloading_time_estimate / np.sqrt(factor))


def _radii(force, a_e, state, params):
    scale = np.where(state.rate_factor > 0, state.rate_factor, 1.0)
    a_p = scale * params.base.plastic_radius(state.P_max / scale**3)
    return a_p, a_e + a_p


LAW = ContactLaw("rate-aware", "a base law (vz, vz-table) with sigma_Y scaled by the strain rate at first contact",
                 rate_aware_force, RateAwareState, rate_aware_loading_work, 1.5, rate_aware_step,
                 params_function=rate_aware_params, radii_function=_radii, takes_velocity=True,
                 reference_function=rate_aware_reference, collision_params=compiled_kernel)

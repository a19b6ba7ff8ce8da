"""The relaxing rate-aware law (law "rate-relaxing"): the rate factor follows the contact's strain rate.

The rate-aware law (nfdmodel.rate_aware) holds R = R(eps_dot) fixed from first contact. In a rate-dependent
solid the flow stress falls as the approach slows towards the turning point, by how much depending on the rate
law's shape at low rates (Johnson-Cook's flow stress returns to sigma_y below eps_dot_0); the fixed factor
misses this (nfdmodel/README.md, The relaxing rate-aware law). Here the factor s [-] of the flow stress, the
base law's p_Y = A_Y(nu) sigma_Y s, is one viscoplastic element driven by the contact's strain rate:

    ds/dt = k (E*/sigma_Y) (eps_dot - eps_dot_s(s)),   s >= 1, s = 1 at first contact            [1/s]
    eps_dot = v_n / (c a_ref)                                                                   [1/s]

eps_dot_s(s) the strain rate at which the rate law's flow stress is s sigma_Y (JohnsonCook.rate_at,
CowperSymonds.rate_at), v_n [m/s] the normal approach speed, a_ref [m] the rate-independent base law's
contact radius at the peak of an impact at the speed of first contact (as the rate-aware law's), k [-] and
c [-] two constants fitted once to the dynamic FE (RELAXATION_STIFFNESS, RELAXING_LENGTH_FACTOR). s rises
from 1 while the overstress builds, and relaxes as eps_dot falls; it moves only while the contact loads
beyond its turning point and is held while it unloads or reloads below it. The force is the base law's
at p_Y scaled by s, P = s^3 P_0(delta / s^2) (nfdmodel.rate_aware.step_at_factors).

One step integrates the element by backward Euler over the step's loading increment, dt = (delta -
delta_max) / v_n (the leap-frog's time step, with no dt argument), and keeps the loading work W [J] by the
trapezoid rule (the virgin curve depends on the path: the history's ``loading_work``, which
ContactLaw.dissipated_energy takes). Units SI. The scalar specification: nfdmodel.reference.rate_relaxing_step.
The compiled kernel: nfd_rate.h's relaxing form (nfd_rate_relaxing_step, each step; nfdmodel.collide runs its
time loop in numpy around it); the LAMMPS plugin: ``rate ... relaxing K``.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp
from scipy.sparse import coo_matrix

from . import limits, native
from .collision import CollisionReference, _unloading_time_factor
from .contact_law import ContactLaw
from .turning_point import elastic_energy
from .history import HistoryUpdate, apply_update, check_delta, check_state, restore_shape
from .rate_aware import (BASE_LAWS, BASE_LAWS_LAW, RateAwareParams, RateAwareState, _radii, approach_speeds,
                         compiled_kernel, compiled_update, rate_aware_loading_work, step_at_factors)
from .validation import check_real

# k and c of the element (module doc): fitted once, to the dynamic FE of six spheres (E/sigma_Y 300-1500,
# nu 0.25-0.4, R 0.05-0.1 m) at 6, 12, 24 v_Y with Cowper-Symonds D 40 q 5 and D 2 q 1 (nfdmodel/README.md);
# nfd_limits.h
RELAXATION_STIFFNESS = limits.RELAXATION_STIFFNESS
RELAXING_LENGTH_FACTOR = limits.RELAXING_LENGTH_FACTOR


@dataclass(frozen=True)
class RelaxingRateState(RateAwareState):
    """History of the relaxing law [SI]: the rate-aware law's (rate_factor the element's s, 0: never touched),
    strain_rate_per_speed [1/m] = 1 / (c a_ref) fixed at first contact, loading_work [J] along the virgin
    path to the turning point."""

    strain_rate_per_speed: np.ndarray
    loading_work: np.ndarray


@dataclass(frozen=True)
class RelaxingRateParams(RateAwareParams):
    """The relaxing law: the rate-aware law's ``base_law``, ``base``, ``rate_law`` and ``c``, and ``k`` the
    element's stiffness in units of E*/sigma_Y (module doc)."""

    c: float = RELAXING_LENGTH_FACTOR
    k: float = RELAXATION_STIFFNESS

    def __post_init__(self):
        super().__post_init__()
        object.__setattr__(self, "k", check_real("k", self.k, low=0.0, unit="(the element's stiffness / (E*/sigma_Y))"))

    @property
    def element_stiffness(self) -> float:
        """k E*/sigma_Y [-] of ds/dt = k (E*/sigma_Y) (eps_dot - eps_dot_s(s))."""
        pair = self.pair
        return self.k * pair.E_star / pair.sigma_y

    def strain_rate_per_speed(self, speed):
        """1 / (c a_ref) [1/m] of first contacts at the normal speeds ``speed`` [m/s]; 0 where speed <= 0."""
        speed = np.atleast_1d(np.asarray(speed, dtype=float))
        per_speed = np.zeros(speed.shape)
        moving = speed > 0.0
        if moving.any():
            per_speed[moving] = 1.0 / (self.c * self.reference_radius(speed[moving]))
        return per_speed

    def strain_rate(self, speed):
        """eps_dot = v_n0 / (c a_ref) [1/s] that drives the element at first contact (normal speeds ``speed``)."""
        speed = np.atleast_1d(np.asarray(speed, dtype=float))
        return np.maximum(speed, 0.0) * self.strain_rate_per_speed(speed)

    def rate_factor(self, speed):
        """s [-] at the turning point of impacts at the normal speeds ``speed`` [m/s] (> 0)."""
        return turning_factor(self, speed)

    def record(self) -> dict:
        return {**super().record(), "form": "relaxing", "k": self.k}


def relaxing_params(params) -> RelaxingRateParams:
    if not isinstance(params, RelaxingRateParams):
        raise ValueError(f"params for law 'rate-relaxing' must be RelaxingRateParams, got {type(params).__name__}")
    return params


def relaxed_factor(factor, per_speed, increment, speed, rate_law, stiffness):
    """s after one loading increment [-]: the root s >= 1 of backward Euler's
    F(s) = s - factor - K (per_speed increment - eps_dot_s(s) increment / speed) = 0 (K = ``stiffness``,
    ``increment`` [m] > 0, ``speed`` [m/s] > 0; F increases with s), by Newton's method from the start factor
    inside the bracket [1, factor + K per_speed increment], bisecting where a Newton step leaves the bracket or
    F' is not finite; 1 where F(1) >= 0 (the flow stress relaxed to sigma_Y)."""
    drive = factor + stiffness * per_speed * increment            # s without relaxation: the upper bracket
    relax = stiffness * increment / speed                         # K dt

    def residual(s, drive, relax):
        with np.errstate(invalid="ignore", over="ignore"):
            return s - drive + relax * rate_law.rate_at(s)

    result = np.ones_like(drive)
    open_ = residual(result, drive, relax) < 0.0
    if not open_.any():
        return result
    drive, relax = drive[open_], relax[open_]
    low, high = np.ones_like(drive), np.maximum(drive, 1.0)
    s = np.clip(factor[open_], 1.0, high)
    for _ in range(limits.RATE_FACTOR_ITERATIONS):
        value = residual(s, drive, relax)
        with np.errstate(invalid="ignore", over="ignore"):
            slope = 1.0 + relax * rate_law.rate_slope(s)
        low = np.where(value < 0.0, s, low)
        high = np.where(value < 0.0, high, s)
        with np.errstate(invalid="ignore", over="ignore", divide="ignore"):
            newton = s - value / slope
        inside = np.isfinite(newton) & (newton >= low) & (newton <= high)
        step = np.where(inside, newton, 0.5 * (low + high))
        done = np.abs(step - s) <= limits.RATE_FACTOR_TOLERANCE * step
        s = step
        if done.all():
            break
    result[open_] = s
    return result


def rate_relaxing_step(delta, state: RelaxingRateState, params: RelaxingRateParams, velocity=None):
    """One step without committing it: (P [N], HistoryUpdate). ``velocity``: the normal approach speed
    d delta / dt [m/s] per contact, needed where a contact touches first or loads beyond its turning point."""
    params = relaxing_params(params)
    check_state(state, RelaxingRateState, "rate-relaxing")
    delta, shape = check_delta(delta, state.n)
    factor = state.rate_factor.copy()
    per_speed = state.strain_rate_per_speed.copy()
    touching = np.flatnonzero((factor == 0.0) & (delta > 0.0))
    loading = np.flatnonzero((delta > state.delta_max) & (delta > 0.0))
    speeds = approach_speeds(velocity, state.n, loading, "the rate-relaxing law", "touch first or load")
    if native.active():
        compiled = _compiled_step(delta, speeds, state, params)
        if compiled is not None:
            return restore_shape(compiled[0], shape), compiled[1]
    if touching.size:
        factor[touching] = 1.0
        per_speed[touching] = params.strain_rate_per_speed(speeds[touching])
    moving = loading[speeds[loading] > 0.0]      # an approach that does not move holds s
    if moving.size:
        factor[moving] = relaxed_factor(factor[moving], per_speed[moving], delta[moving] - state.delta_max[moving],
                                        speeds[moving], params.rate_law, params.element_stiffness)
    changed = np.union1d(touching, loading)
    force, index, values, update = step_at_factors(delta, state, params, factor, changed)
    values["strain_rate_per_speed"] = per_speed[index]
    increment = delta[index] - state.delta_max[index]        # > 0: loaded beyond the turning point (trapezoid)
    values["loading_work"] = state.loading_work[index] + np.where(
        increment > 0.0, 0.5 * (state.P_max[index] + force[index]) * increment, 0.0)
    largest = update.largest_load_over_P_Y
    return restore_shape(force, shape), HistoryUpdate(index, RelaxingRateState(**values), state.n,
                                                      update.newton_iterations, update.beyond_window, largest)


def _compiled_step(delta, speeds, state: RelaxingRateState, params: RelaxingRateParams):
    """(P [N], HistoryUpdate) of the step in the compiled kernel (nfd_rate_relaxing_step), or None where a contact
    failed there: the numpy path then names the cause in its words."""
    pair = params.pair
    return compiled_update(native.rate_step(compiled_kernel(params), pair.mass_star, delta, speeds, state, params.k,
                                            params.element_stiffness), RelaxingRateState, state.n, pair.P_Y)


def rate_relaxing_force(delta, state: RelaxingRateState, params: RelaxingRateParams, velocity=None):
    """The pure law: (P [N], new_state)."""
    force, update = rate_relaxing_step(delta, state, params, velocity)
    return force, apply_update(state, update, copy=True)


def _turning_points(params: RelaxingRateParams, speeds, per_speeds):
    """(delta_max [m], s, t_load [s], P_max [N], the base law's virgin history there), arrays over the impacts at
    ``speeds`` [m/s] (> 0, first contacts driven at ``per_speeds`` [1/m] = 1 / (c a_ref)), in continuous time:
    m* d2delta/dt2 = -s^3 P_0(delta / s^2) with the element's ds/dt (module doc). Every impact is one block of
    one system, in its own time tau = t / T_H (T_H its Hertz contact time, so the blocks move alike), Radau
    (rtol 1e-9) until the last reaches its turning point; each one's is where its own approach speed falls
    through zero."""
    base_law = BASE_LAWS_LAW[params.base_law]
    base_state = BASE_LAWS[params.base_law][1]
    mass, stiffness = params.pair.mass_star, params.element_stiffness
    speeds, per_speeds = np.asarray(speeds, dtype=float), np.asarray(per_speeds, dtype=float)
    n = speeds.size
    virgin = base_state.virgin(n)
    hertz = params.pair.hertz_contact_time(speeds)

    def rates(tau, y):                      # d/dtau = T_H d/dt of (delta, v_n, x) per impact, s = max(x, 1)
        delta, approach, x = y.reshape(n, 3).T
        s = np.maximum(x, 1.0)
        # x free below 1 keeps the right side continuous; while loading the drive only falls, so once x
        # passes below 1 it stays there, as s = 1 does in the law
        dx = stiffness * (per_speeds * np.maximum(approach, 0.0) - params.rate_law.rate_at(x))
        force, _ = base_law.force_function(np.maximum(delta, 0.0) / s**2, virgin, params.base)
        return (hertz[:, None] * np.column_stack([approach, -force * s**3 / mass, dx])).ravel()

    rows = np.repeat(np.arange(3 * n).reshape(n, 3), 3, axis=1).ravel()
    columns = np.tile(np.arange(3 * n).reshape(n, 3), (1, 3)).ravel()

    def jacobian(tau, y):                   # each impact's 3 x 3 block, the element's row exact (its kink at s = 1)
        delta, approach, x = y.reshape(n, 3).T
        s = np.maximum(x, 1.0)
        u = np.maximum(delta, 0.0) / s**2
        step = 1e-7 * np.maximum(u, 1e-9 * np.max(speeds * hertz))
        force, _ = base_law.force_function(u, virgin, params.base)
        slope = (base_law.force_function(u + step, virgin, params.base)[0] - force) / step     # dP_0/du
        block = np.zeros((n, 3, 3))
        block[:, 0, 1] = 1.0
        block[:, 1, 0] = -s * slope / mass
        block[:, 1, 2] = np.where(x > 1.0, -(3.0 * s**2 * force - 2.0 * delta * slope) / mass, 0.0)
        block[:, 2, 1] = np.where(approach > 0.0, stiffness * per_speeds, 0.0)
        block[:, 2, 2] = -stiffness * params.rate_law.rate_slope(x)
        return coo_matrix(((hertz[:, None, None] * block).ravel(), (rows, columns)), shape=(3 * n, 3 * n)).tocsc()

    # the event of impact i: its approach speed falls through zero; the last of them ends the run
    turnings = [lambda tau, y, i=i: y[3 * i + 1] for i in range(n)]
    last = lambda tau, y: np.max(y[1::3])                           # noqa: E731
    last.terminal = True
    for event in (*turnings, last):
        event.direction = -1
    solution = solve_ivp(rates, (0.0, 10.0), np.column_stack([np.zeros(n), speeds, np.ones(n)]).ravel(),
                         method="Radau", events=[*turnings, last], rtol=1e-9,
                         atol=1e-12 * np.column_stack([speeds * hertz, speeds, np.ones(n)]).ravel(),
                         jac=jacobian)
    missing = [float(v) for v, taus in zip(speeds, solution.t_events[:n]) if not taus.size]
    if missing:
        raise ValueError(f"v_in out of range: the rate-relaxing impact at {missing[0]:g} m/s found no turning point")
    delta, _, s = np.array([states[0][3 * i:3 * i + 3] for i, states in enumerate(solution.y_events[:n])]).T
    s = np.maximum(s, 1.0)
    force, state = base_law.force_function(delta / s**2, virgin, params.base)
    t_load = hertz * np.array([taus[0] for taus in solution.t_events[:n]])
    return delta, s, t_load, force * s**3, state


def turning_factor(params: RelaxingRateParams, v_in):
    """s [-] at the turning point of impacts at ``v_in`` [m/s] (> 0; continuous time, :func:`_turning_points`)."""
    params = relaxing_params(params)
    v = np.atleast_1d(np.asarray(v_in, dtype=float)).reshape(-1)
    return _turning_points(params, v, params.strain_rate_per_speed(v))[1]


def relaxing_reference(params: RelaxingRateParams, v_in) -> CollisionReference:
    """The impact at v_in [m/s] in continuous time (:func:`_turning_points`), then the base law's elastic unloading
    at the factor s reached there (the returned work s^5 times the base law's): the specification collide's time
    loop converges to as dt -> 0."""
    params = relaxing_params(params)
    v = np.atleast_1d(np.asarray(v_in, dtype=float)).reshape(-1)
    base_law = BASE_LAWS_LAW[params.base_law]
    delta, s, t_load, P_max, state = _turning_points(params, v, params.strain_rate_per_speed(v))
    delta_res = state.delta_res * s**2
    work = 0.5 * params.pair.mass_star * v**2          # all of it taken at the turning point
    e = np.sqrt(elastic_energy(P_max, delta, delta_res, base_law.exponent_of(state)) / work)
    t_unload = _unloading_time_factor(1.5) * (delta - delta_res) / (e * v)
    return CollisionReference(v, delta, P_max, delta_res, work, e, t_load + t_unload, t_unload)


LAW = ContactLaw("rate-relaxing", "a base law (vz, vz-table) with sigma_Y scaled by a rate factor that follows "
                 "the contact's strain rate", rate_relaxing_force, RelaxingRateState, rate_aware_loading_work, 1.5,
                 rate_relaxing_step, params_function=relaxing_params, radii_function=_radii, takes_velocity=True,
                 reference_function=relaxing_reference)

# the rate-aware laws by their form: R fixed at first contact (nfdmodel.rate_aware) or relaxing (this module)
RATE_FORMS = ("fixed", "relaxing")


def rate_form_law(form: str, base_law: str, base, rate_law, c: float | None = None, k: float | None = None):
    """(ContactLaw, parameters) of the rate-aware law of ``form`` "fixed" (RateAwareParams, c default
    RATE_LENGTH_FACTOR) or "relaxing" (RelaxingRateParams, c and k default RELAXING_LENGTH_FACTOR,
    RELAXATION_STIFFNESS) on the base law ``base_law`` with parameters ``base``."""
    from . import rate_aware

    if form == "fixed":
        if k is not None:
            raise ValueError("k out of range: the fixed rate-aware law has no element stiffness (form relaxing)")
        return rate_aware.LAW, RateAwareParams(base_law, base, rate_law, *(() if c is None else (c,)))
    if form == "relaxing":
        return LAW, RelaxingRateParams(base_law, base, rate_law, RELAXING_LENGTH_FACTOR if c is None else c,
                                       RELAXATION_STIFFNESS if k is None else k)
    raise ValueError(f"form must be one of {', '.join(RATE_FORMS)}, got {form!r}")

"""Oblique impacts of a sphere on a rigid flat, with friction, rolling resistance and spin; vectorised.

A solid sphere (radius R = the pair's R*, mass m = the pair's m*, moment of inertia I = 2 m R^2/5)
hits the flat z = 0 with normal speed v_n > 0 (towards the flat), tangential speed v_t along x and
spin omega about y; the contact is a law of :mod:`nfdmodel.registry` with the models of
:class:`nfdmodel.friction.Friction` (n = +z, R_j = 0: the flat is rigid and still). No gravity.
Integrated as LAMMPS's ``fix nve/sphere`` (velocity Verlet), so that a LAMMPS run of the same impact
gives the same numbers up to round-off:

    v += F dt/(2m),  x += v dt,  omega += T dt/(2I);  F, T at the new position;  v += F dt/(2m),
    omega += T dt/(2I)

from first touch (z = R, F = 0) until the sphere leaves the flat (z > R after the contact). With
V = v_t - R omega the slip velocity of the contact point (the sphere's point on the flat):

    e_n   = v_n' / v_n                    normal restitution (v_n' the rebound speed)
    e_t   = v_t' / v_t                    tangential restitution of the centre (Wu, Thornton & Li 2009)
    beta  = -V' / V                       of the contact point (Maw, Barber & Fawcett 1976; -1: no
                                          tangential force, 1: a reversed slip velocity)
    angle = atan(v_t' / v_n')             rebound angle from the normal [deg]

Gross sliding throughout the impact (V never reverses) gives the closed forms v_t - v_t' =
mu (v_n + v_n') and omega' - omega = 5 mu (v_n + v_n') / (2 R) (Coulomb: the tangential impulse is
mu times the normal one). Energy, per impact, exactly for the time-stepped path (velocity Verlet
moves kinetic energy by F (x_(k+1) - x_(k-1))/2 + T (omega_(k+1/2) + omega_(k-1/2)) dt/2 per step):

    kinetic energy lost = work_normal (the normal law's hysteresis, plus damping) + work_friction
    (tangential, rolling and twisting resistance: Coulomb sliding, tangential damping)

SI units; angles in degrees.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .friction import Contact, Friction, FrictionState, contact_step
from .parameters import as_pair
from .registry import get_law
from .validation import check_real

_MAX_STEPS = 10**6


@dataclass(frozen=True)
class ObliqueResult:
    """Per impact (arrays of the broadcast inputs): v_n, v_t [m/s], omega [rad/s], angle [deg] in;
    v_n_out, v_t_out, omega_out, angle_out out; e_n, e_t, beta (module doc); P_max [N]; contact_time
    [s]; kinetic_energy_lost, work_normal, work_friction [J]; steps of the longest impact."""

    v_n: np.ndarray
    v_t: np.ndarray
    omega: np.ndarray
    angle: np.ndarray
    v_n_out: np.ndarray
    v_t_out: np.ndarray
    omega_out: np.ndarray
    angle_out: np.ndarray
    e_n: np.ndarray
    e_t: np.ndarray
    beta: np.ndarray
    P_max: np.ndarray
    contact_time: np.ndarray
    kinetic_energy_lost: np.ndarray
    work_normal: np.ndarray
    work_friction: np.ndarray
    steps: int


def oblique_collide(law_name: str, params, friction: Friction, speed, angle, omega=0.0, dt: float = 1e-7,
                    max_steps: int = _MAX_STEPS) -> ObliqueResult:
    """Impacts at ``speed`` [m/s] and incidence ``angle`` [deg] from the normal (v_n = speed
    cos(angle), v_t = speed sin(angle)) with spin ``omega`` [rad/s] about y (the axis the rolling
    of the incoming sphere turns about: omega = v_t / R rolls without slip). Inputs broadcast.
    ValueError naming a bad input, or max_steps when the sphere does not leave the flat."""
    law = get_law(law_name)
    p = law.params_from(params)
    pair = as_pair(p, law.name)
    if not isinstance(friction, Friction):
        raise ValueError(f"friction must be a nfdmodel.friction.Friction, got {type(friction).__name__}")
    dt = check_real("dt", dt, low=0.0, unit="s")
    speed, angle, omega = np.broadcast_arrays(np.asarray(speed, dtype=float), np.asarray(angle, dtype=float),
                                              np.asarray(omega, dtype=float))
    shape = speed.shape
    speed, angle, omega = speed.ravel(), angle.ravel(), omega.ravel()
    for name, values, low, high in (("speed", speed, 0.0, None), ("angle", angle, 0.0, 90.0)):
        for value in values:
            check_real(name, value, low=low, low_inclusive=name == "angle", high=high, high_inclusive=False,
                       unit="m/s" if name == "speed" else "deg")
    for value in omega:
        check_real("omega", value, unit="rad/s")
    n = speed.size
    R, m = pair.R_star, pair.mass_star
    v_n, v_t = speed * np.cos(np.radians(angle)), speed * np.sin(np.radians(angle))
    x = np.zeros((n, 3))
    x[:, 2] = R
    v = np.stack([v_t, np.zeros(n), -v_n], axis=1)
    w = np.stack([np.zeros(n), omega, np.zeros(n)], axis=1)
    ke_in = 0.5 * m * np.einsum("ij,ij->i", v, v) + 0.2 * m * R * R * np.einsum("ij,ij->i", w, w)
    force, torque = np.zeros((n, 3)), np.zeros((n, 3))
    state, springs = law.initial_state(n), FrictionState.virgin(n)
    dtf, dtir = 0.5 * dt / m, (0.5 * dt / 0.4) / (R * R * m)
    normal = np.tile([0.0, 0.0, 1.0], (n, 1))
    done = np.zeros(n, dtype=bool)
    touched = np.zeros(n, dtype=bool)
    P_max, contact_steps = np.zeros(n), np.zeros(n, dtype=np.int64)
    work_normal, work_friction = np.zeros(n), np.zeros(n)
    previous_x, w_half = x.copy(), w.copy()        # x_(k-1) and omega_(k-1/2)
    F_n_last = np.zeros(n)
    step = 0
    while not done.all():
        if step >= max_steps:
            raise ValueError(f"max_steps = {max_steps} reached before the sphere left the flat: increase max_steps "
                             f"or dt (dt = {dt:g} s)")
        step += 1
        v += dtf * force
        x_new = x + dt * v
        w += dtir * torque
        # the work of last step's forces over x_(k+1) - x_(k-1) and omega_(k+1/2) + omega_(k-1/2) (module doc)
        moved = (x_new - previous_x) * 0.5
        work_step_n = F_n_last * moved[:, 2]
        work_step_t = np.einsum("ij,ij->i", force, moved) - work_step_n + np.einsum(
            "ij,ij->i", torque, (w + w_half) * (0.5 * dt))
        w_half = w.copy()
        work_normal -= np.where(done, 0.0, work_step_n)
        work_friction -= np.where(done, 0.0, work_step_t)
        previous_x, x = x, x_new
        delta = R - x[:, 2]
        touching = (delta > 0.0) & ~done
        contact = Contact(normal, delta, R, 0.0, v, w, np.zeros((n, 3)), m, dt)
        forces, new_state, new_springs = contact_step(law, p, friction, contact, state, springs)
        state = new_state if touching.all() else _keep(law, state, new_state, touching)
        springs = FrictionState(np.where(touching[:, None], new_springs.xi_t, 0.0),
                                np.where(touching[:, None], new_springs.xi_roll, 0.0),
                                np.where(touching, new_springs.theta_twist, 0.0),
                                np.where(touching, new_springs.a_previous, 0.0))
        force = np.where(touching[:, None], forces.force, 0.0)
        torque = np.where(touching[:, None], forces.torque_i, 0.0)
        F_n_last = np.where(touching, forces.F_n, 0.0)
        P_max = np.maximum(P_max, np.where(touching, forces.P, 0.0))
        contact_steps += touching
        touched |= touching
        v += dtf * force
        w += dtir * torque
        done |= touched & ~touching & (v[:, 2] > 0.0)
    v_n_out, v_t_out, omega_out = v[:, 2], v[:, 0], w[:, 1]
    slip_in, slip_out = v_t - R * omega, v_t_out - R * omega_out
    ke_out = 0.5 * m * np.einsum("ij,ij->i", v, v) + 0.2 * m * R * R * np.einsum("ij,ij->i", w, w)
    with np.errstate(divide="ignore", invalid="ignore"):
        e_t = np.where(v_t != 0.0, v_t_out / v_t, np.nan)
        beta = np.where(slip_in != 0.0, -slip_out / slip_in, np.nan)

    def shaped(values):
        return np.reshape(values, shape)

    return ObliqueResult(shaped(v_n), shaped(v_t), shaped(omega), shaped(angle), shaped(v_n_out), shaped(v_t_out),
                         shaped(omega_out), shaped(np.degrees(np.arctan2(v_t_out, v_n_out))), shaped(v_n_out / v_n),
                         shaped(e_t), shaped(beta), shaped(P_max), shaped(contact_steps * dt),
                         shaped(ke_in - ke_out), shaped(work_normal), shaped(work_friction), step)


def _keep(law, state, new_state, touching):
    """The new history where touching, a virgin one elsewhere (a sphere off the flat forgets)."""
    from .history import HertzState, field_names
    if isinstance(state, HertzState):
        return new_state
    virgin = law.initial_state(touching.size)
    return type(state)(**{name: np.where(touching, getattr(new_state, name), getattr(virgin, name))
                          for name in field_names(type(state))})


def slip_closed_form(result: ObliqueResult, mu: float, R: float) -> tuple[np.ndarray, np.ndarray]:
    """(v_t - v_t', omega' - omega) of gross sliding throughout the impact: mu (v_n + v_n') and
    5 mu (v_n + v_n') / (2 R) (a solid sphere; the Coulomb impulse mu J_n at the arm R)."""
    impulse = mu * (result.v_n + result.v_n_out)
    return impulse, 2.5 * impulse / R


def incidence_angles(count: int = 30, largest: float = 85.0) -> np.ndarray:
    """Incidence angles [deg] for a sweep, denser near the normal where e_t changes fastest."""
    return largest * np.sin(np.linspace(0.0, 0.5 * math.pi, count)) ** 1.5

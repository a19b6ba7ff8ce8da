"""Oblique impacts of a sphere on a rigid flat or of two spheres, with friction, rolling resistance and
spin; vectorised.

A solid sphere i (moment of inertia I = 2 m R^2/5) hits either the flat z = 0 (radius R = the
pair's R*, mass m = the pair's m*) or a second solid sphere j (``partner = (R_j, m_j)``; then R_i
and m_i follow from the pair's R* and m*: 1/R_i = 1/R* - 1/R_j, 1/m_i = 1/m* - 1/m_j), at
relative normal speed v_n > 0, relative tangential speed v_t along x and spins omega_i, omega_j
about y; the contact is a law of :mod:`nfdmodel.registry` with the models of
:class:`nfdmodel.friction.Friction` (n from j to i, +z at first touch; a flat: R_j = 0, rigid and
still). Two spheres start in their centre-of-mass frame (v_i = m_j v/(m_i + m_j), v_j = -m_i
v/(m_i + m_j)). No gravity. Integrated as LAMMPS's ``fix nve/sphere`` (velocity Verlet) with the
geometry of its granular pair styles (delta = R_i + R_j - |x_i - x_j|, n = (x_i - x_j)/|x_i -
x_j|), so that a LAMMPS run of the same impact gives the same numbers up to round-off:

    v += F dt/(2m),  x += v dt,  omega += T dt/(2I);  F, T at the new position;  v += F dt/(2m),
    omega += T dt/(2I)

from first touch (delta = 0, F = 0) until the bodies part (delta < 0 after the contact). All
velocities below are of i relative to j (a flat: i's own), in, along the normal at first touch,
out, along the normal at parting (the line of centres of two spheres turns during the contact by
about v_t t_c / (R_i + R_j)); with V = v_t - (R_i omega_i + R_j omega_j) the slip velocity of the
contact point:

    e_n   = v_n' / v_n                    normal restitution (v_n' the rebound speed)
    e_t   = v_t' / v_t                    tangential restitution of the centres (Wu, Thornton & Li 2009)
    beta  = -V' / V                       of the contact point (Maw, Barber & Fawcett 1976; -1: no
                                          tangential force, 1: a reversed slip velocity)
    angle = atan(v_t' / v_n')             rebound angle from the normal [deg]

Gross sliding throughout the impact (V never reverses) gives the closed forms v_t - v_t' =
mu (v_n + v_n') and, per sphere, omega' - omega = 5 mu m* (v_n + v_n') / (2 m R) (Coulomb: the
tangential impulse is mu times the normal one, m* (v_n + v_n'); on a flat m = m*, R = R*: 5 mu
(v_n + v_n') / (2 R)). On a flat these hold to round-off. Between two spheres the line of centres
turns while the spheres slide (by normal_turn ~ v_t t_c / (R_i + R_j)), so the velocities of the
fixed frame hold them to O(normal_turn tan(angle)); the impulses hold the Coulomb law |J_t| =
mu J_n to round-off, and the spins 5 mu J_n / (2 m R) to O(delta_max / R) (LAMMPS's torque arm
R - delta/2). Energy, per impact, exactly for the time-stepped path (velocity
Verlet moves each body's kinetic energy by F (x_(k+1) - x_(k-1))/2 + T (omega_(k+1/2) +
omega_(k-1/2)) dt/2 per step):

    kinetic energy lost = work_normal (the normal law's hysteresis, plus damping) + work_friction
    (tangential, rolling and twisting resistance: Coulomb sliding, tangential damping)

SI units; angles in degrees.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .friction import Contact, Friction, FrictionState, contact_step
from .materials import as_pair
from .registry import get_law
from .validation import check_real

_MAX_STEPS = 10**6


@dataclass(frozen=True)
class ObliqueResult:
    """Per impact (arrays of the broadcast inputs): v_n, v_t [m/s], omega, omega_partner [rad/s],
    angle [deg] in; v_n_out, v_t_out, omega_out, omega_partner_out, angle_out out (velocities of i
    relative to j); v_t_i_out, v_t_j_out [m/s] each body's tangential velocity out (a flat: 0);
    e_n, e_t, beta (module doc); P_max [N]; contact_time [s]; kinetic_energy_lost, work_normal,
    work_friction [J]; delta_max [m]; impulse_n, impulse_t [N s] the normal force's and the
    tangential force's (along the tangent of each step's normal, in the x-z plane) impulses on i;
    normal_turn [rad] the angle the contact normal turned by at parting (a flat: 0); velocities
    (..., 4, 3) out in the fixed frame: v_i, v_j [m/s], omega_i, omega_j [rad/s]; steps of the
    longest impact."""

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
    omega_partner: np.ndarray | None = None
    omega_partner_out: np.ndarray | None = None
    v_t_i_out: np.ndarray | None = None
    v_t_j_out: np.ndarray | None = None
    delta_max: np.ndarray | None = None
    impulse_n: np.ndarray | None = None
    impulse_t: np.ndarray | None = None
    normal_turn: np.ndarray | None = None
    velocities: np.ndarray | None = None


@dataclass
class _Body:
    """One body's state over n impacts: x, v, w (n, 3) [m, m/s, rad/s]; mass [kg] and radius [m]
    (a flat: inf and 0, never moved)."""

    x: np.ndarray
    v: np.ndarray
    w: np.ndarray
    mass: float
    radius: float

    @property
    def moves(self) -> bool:
        return math.isfinite(self.mass)

    def kinetic(self) -> np.ndarray:
        if not self.moves:
            return np.zeros(self.x.shape[0])
        return (0.5 * self.mass * np.einsum("ij,ij->i", self.v, self.v)
                + 0.2 * self.mass * self.radius * self.radius * np.einsum("ij,ij->i", self.w, self.w))


def _partner(pair, partner):
    """(R_i, m_i, R_j, m_j) of sphere i and its partner: a flat (partner None) or a sphere (R_j, m_j)."""
    R, m = pair.R_star, pair.mass_star
    if partner is None:
        return R, m, 0.0, math.inf
    try:
        R_j, m_j = (float(value) for value in partner)
    except (TypeError, ValueError):
        raise ValueError(f"partner must be (R_j [m], m_j [kg]) of the second sphere, got {partner!r}") from None
    check_real("partner R_j", R_j, low=R, unit="m")
    check_real("partner m_j", m_j, low=m, unit="kg")
    return 1.0 / (1.0 / R - 1.0 / R_j), 1.0 / (1.0 / m - 1.0 / m_j), R_j, m_j


def oblique_collide(law_name: str, params, friction: Friction, speed, angle, omega=0.0, dt: float = 1e-7,
                    max_steps: int = _MAX_STEPS, partner=None, omega_partner=0.0) -> ObliqueResult:
    """Impacts at relative ``speed`` [m/s] and incidence ``angle`` [deg] from the normal (v_n =
    speed cos(angle), v_t = speed sin(angle)) with spin ``omega`` [rad/s] of sphere i about y (the
    axis the rolling of the incoming sphere turns about: omega = v_t / R rolls on a flat without
    slip), on a flat (partner None) or on a sphere ``partner = (R_j [m], m_j [kg])`` spinning at
    ``omega_partner`` about y (module doc). Inputs broadcast. ValueError naming a bad input, or
    max_steps when the bodies do not part."""
    law = get_law(law_name)
    p = law.params_from(params)
    pair = as_pair(p, law.name)
    if not isinstance(friction, Friction):
        raise ValueError(f"friction must be a nfdmodel.friction.Friction, got {type(friction).__name__}")
    dt = check_real("dt", dt, low=0.0, unit="s")
    R_i, m_i, R_j, m_j = _partner(pair, partner)
    arrays = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (speed, angle, omega, omega_partner)))
    shape = arrays[0].shape
    speed, angle, omega, omega_j = (a.ravel() for a in arrays)
    for name, values, low, high in (("speed", speed, 0.0, None), ("angle", angle, 0.0, 90.0)):
        for value in values:
            check_real(name, value, low=low, low_inclusive=name == "angle", high=high, high_inclusive=False,
                       unit="m/s" if name == "speed" else "deg")
    for name, values in (("omega", omega), ("omega_partner", omega_j)):
        for value in values:
            check_real(name, value, unit="rad/s")
    n = speed.size
    m_star = pair.mass_star
    v_n, v_t = speed * np.cos(np.radians(angle)), speed * np.sin(np.radians(angle))
    relative = np.stack([v_t, np.zeros(n), -v_n], axis=1)
    zeros = np.zeros((n, 3))
    body_i = _Body(np.tile([0.0, 0.0, R_i], (n, 1)), relative.copy(), np.stack([np.zeros(n), omega, np.zeros(n)], 1),
                   m_i, R_i)
    body_j = _Body(zeros.copy(), zeros.copy(), zeros.copy(), m_j, R_j)
    if body_j.moves:
        share = m_i / (m_i + m_j)
        body_i.v = relative * (1.0 - share)
        body_j.v = relative * -share
        body_j.x[:, 2] = -R_j
        body_j.w[:, 1] = omega_j
    ke_in = body_i.kinetic() + body_j.kinetic()
    state, springs = law.initial_state(n), FrictionState.virgin(n)
    force, torque_i, torque_j = zeros.copy(), zeros.copy(), zeros.copy()
    normal = np.tile([0.0, 0.0, 1.0], (n, 1))
    done = np.zeros(n, dtype=bool)
    touched = np.zeros(n, dtype=bool)
    P_max, delta_max, contact_steps = np.zeros(n), np.zeros(n), np.zeros(n, dtype=np.int64)
    work_normal, work_friction = np.zeros(n), np.zeros(n)
    # x_(k-1) and omega_(k-1/2) of both bodies, for the work of each step (module doc)
    previous = [body_i.x.copy(), body_j.x.copy()]
    w_half = [body_i.w.copy(), body_j.w.copy()]
    F_n_last, n_last = np.zeros(n), normal.copy()
    n_parting = normal.copy()           # the contact normal of each impact's last touching step
    impulse_n, impulse_t = np.zeros(n), np.zeros(n)
    step = 0
    while not done.all():
        if step >= max_steps:
            raise ValueError(f"max_steps = {max_steps} reached before the bodies parted: increase max_steps "
                             f"or dt (dt = {dt:g} s)")
        step += 1
        moved, total = [], np.zeros(n)
        for k, (body, F, T) in enumerate(((body_i, force, torque_i), (body_j, -force, torque_j))):
            if not body.moves:
                moved.append(zeros)
                continue
            dtf, dtir = 0.5 * dt / body.mass, (0.5 * dt / 0.4) / (body.radius * body.radius * body.mass)
            body.v += dtf * F
            x_new = body.x + dt * body.v
            body.w += dtir * T
            # the work of last step's forces over x_(k+1) - x_(k-1) and omega_(k+1/2) + omega_(k-1/2)
            shift = (x_new - previous[k]) * 0.5
            moved.append(shift)
            total += np.einsum("ij,ij->i", F, shift) + np.einsum("ij,ij->i", T, (body.w + w_half[k]) * (0.5 * dt))
            w_half[k] = body.w.copy()
            previous[k], body.x = body.x, x_new
        work_step_n = F_n_last * np.einsum("ij,ij->i", n_last, moved[0] - moved[1])
        work_normal -= np.where(done, 0.0, work_step_n)
        work_friction -= np.where(done, 0.0, total - work_step_n)
        if body_j.moves:
            gap = body_i.x - body_j.x
            r = np.sqrt(np.einsum("ij,ij->i", gap, gap))
            normal = gap * (1.0 / r)[:, None]
            delta = (R_i + R_j) - r
        else:
            delta = R_i - body_i.x[:, 2]
        touching = (delta > 0.0) & ~done
        contact = Contact(normal, delta, R_i, R_j, body_i.v - body_j.v, body_i.w, body_j.w, m_star, dt)
        forces, new_state, new_springs = contact_step(law, p, friction, contact, state, springs)
        state = new_state if touching.all() else _keep(law, state, new_state, touching)
        springs = FrictionState(np.where(touching[:, None], new_springs.xi_t, 0.0),
                                np.where(touching[:, None], new_springs.xi_roll, 0.0),
                                np.where(touching, new_springs.theta_twist, 0.0),
                                np.where(touching, new_springs.a_previous, 0.0))
        force = np.where(touching[:, None], forces.force, 0.0)
        torque_i = np.where(touching[:, None], forces.torque_i, 0.0)
        torque_j = np.where(touching[:, None], forces.torque_j, 0.0)
        F_n_last, n_last = np.where(touching, forces.F_n, 0.0), normal
        n_parting = np.where(touching[:, None], normal, n_parting)
        # each step's force acts for dt (two half kicks); F_t along the tangent of its normal, in x-z
        impulse_n += F_n_last * dt
        tangent_k = np.stack([normal[:, 2], np.zeros(n), -normal[:, 0]], axis=1)
        impulse_t += np.where(touching, np.einsum("ij,ij->i", forces.F_t, tangent_k), 0.0) * dt
        P_max = np.maximum(P_max, np.where(touching, forces.P, 0.0))
        delta_max = np.maximum(delta_max, np.where(touching, delta, 0.0))
        contact_steps += touching
        touched |= touching
        for body, F, T in ((body_i, force, torque_i), (body_j, -force, torque_j)):
            if body.moves:
                body.v += (0.5 * dt / body.mass) * F
                body.w += ((0.5 * dt / 0.4) / (body.radius * body.radius * body.mass)) * T
        done |= touched & ~touching & (body_i.v[:, 2] - body_j.v[:, 2] > 0.0)
    v_out = body_i.v - body_j.v
    # out in the frame of the normal at parting (two spheres: the line of centres turned during
    # the contact; a flat: +z, x)
    if body_j.moves:
        tangent = np.stack([n_parting[:, 2], np.zeros(n), -n_parting[:, 0]], axis=1)
        tangent /= np.sqrt(np.einsum("ij,ij->i", tangent, tangent))[:, None]
        v_n_out, v_t_out = np.einsum("ij,ij->i", v_out, n_parting), np.einsum("ij,ij->i", v_out, tangent)
        v_t_i, v_t_j = np.einsum("ij,ij->i", body_i.v, tangent), np.einsum("ij,ij->i", body_j.v, tangent)
    else:
        v_n_out, v_t_out = v_out[:, 2], v_out[:, 0]
        v_t_i, v_t_j = body_i.v[:, 0], body_j.v[:, 0]
    omega_out, omega_j_out = body_i.w[:, 1], body_j.w[:, 1]
    slip_in = v_t - (R_i * omega + R_j * omega_j)
    slip_out = v_t_out - (R_i * omega_out + R_j * omega_j_out)
    ke_out = body_i.kinetic() + body_j.kinetic()
    with np.errstate(divide="ignore", invalid="ignore"):
        e_t = np.where(v_t != 0.0, v_t_out / v_t, np.nan)
        beta = np.where(slip_in != 0.0, -slip_out / slip_in, np.nan)

    def shaped(values):
        return np.reshape(values, shape)

    return ObliqueResult(shaped(v_n), shaped(v_t), shaped(omega), shaped(angle), shaped(v_n_out), shaped(v_t_out),
                         shaped(omega_out), shaped(np.degrees(np.arctan2(v_t_out, v_n_out))), shaped(v_n_out / v_n),
                         shaped(e_t), shaped(beta), shaped(P_max), shaped(contact_steps * dt),
                         shaped(ke_in - ke_out), shaped(work_normal), shaped(work_friction), step,
                         shaped(omega_j), shaped(omega_j_out), shaped(v_t_i), shaped(v_t_j),
                         shaped(delta_max), shaped(impulse_n), shaped(impulse_t),
                         shaped(np.arctan2(n_parting[:, 0], n_parting[:, 2])),
                         np.stack([body_i.v, body_j.v, body_i.w, body_j.w], axis=1).reshape(shape + (4, 3)))


def _keep(law, state, new_state, touching):
    """The new history where touching, a virgin one elsewhere (a sphere off the flat forgets)."""
    from .history import HertzState, field_names
    if isinstance(state, HertzState):
        return new_state
    virgin = law.initial_state(touching.size)
    return type(state)(**{name: np.where(touching, getattr(new_state, name), getattr(virgin, name))
                          for name in field_names(type(state))})


def slip_closed_form(result: ObliqueResult, mu: float, R: float, mass_ratio: float = 1.0
                     ) -> tuple[np.ndarray, np.ndarray]:
    """(v_t - v_t', omega' - omega) of gross sliding throughout the impact: mu (v_n + v_n') and
    5 mu (m*/m) (v_n + v_n') / (2 R) for a solid sphere of radius R and mass m (the Coulomb impulse
    mu J_n at the arm R, J_n = m* (v_n + v_n')); mass_ratio = m*/m (a flat: 1)."""
    impulse = mu * (result.v_n + result.v_n_out)
    return impulse, 2.5 * mass_ratio * impulse / R


def incidence_angles(count: int = 30, largest: float = 85.0) -> np.ndarray:
    """Incidence angles [deg] for a sweep, denser near the normal where e_t changes fastest."""
    return largest * np.sin(np.linspace(0.0, 0.5 * math.pi, count)) ** 1.5

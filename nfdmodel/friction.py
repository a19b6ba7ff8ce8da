"""Friction, rolling and twisting resistance and normal damping around the normal laws, vectorised.

The numpy reference (and fallback) of the C kernel's ``nfd_friction.h``, operation for operation,
as LAMMPS's ``pair_style granular`` defines its sub-models (``damping viscoelastic | tsuji |
coeff_restitution``, ``tangential mindlin``, ``rolling sds``, ``twisting marshall | sds``), with
the contact radius of the normal law in use. Per contact, SI units, n the unit normal from body j
to body i, delta the overlap, v = v_i - v_j, R* and m* the effective radius and mass:

    P        the normal law's force (the law's own step; friction never changes it)
    a        its contact radius: sqrt(R* delta) (Hertz) until the contact first yields, then vz:
             a_e + a_p = (3 P R*/(4 E*))^(1/3) + Ca <P_max - P_Y>; vz-table: a_Y (x^(1/3) + f(x_max));
             thornton: (3 P R_p/(4 E*))^(1/3), R_p its enlarged curvature; walton-braun: sqrt(R* delta)
    F_n      = P - eta v.n; eta = 0 (none), c m* a (viscoelastic), c sqrt(m* P/delta) (tsuji,
             coeff_restitution; c from the restitution e, :func:`damping_coefficient`)
    F_t      Mindlin-Deresiewicz (1953), LAMMPS's ``mindlin``: the spring xi_t, rotated into the
             tangent plane (length kept) and advanced by v_t dt, v_t = v - (v.n) n - (R_i w_i +
             R_j w_j) x n; F_t = -k_t a xi_t - x_gamma_t eta v_t, |F_t| <= mu |F_n| (Coulomb sliding:
             xi_t set back to the capped force minus the damping, its force at most the cap; LAMMPS
             stores the damping beyond the cap too); k_t = 8 G*, 1/G* = (2 - nu_i)/G_i + (2 - nu_j)/G_j
    rolling  SDS (Luding 2008): xi_roll advanced by v_roll dt, v_roll = R* (w_i - w_j) x n;
             F_r = -k_roll xi_roll - gamma_roll v_roll, |F_r| <= mu_roll |F_n|; torque R* n x F_r
    twisting theta advanced by w_twist dt, w_twist = (w_i - w_j).n; M = -k theta - gamma w_twist,
             |M| <= mu |F_n|; Marshall (2009): k = k_t a^2/2, gamma = x_gamma_t eta a^2/2,
             mu = 2 mu_t a/3; SDS: given
    torques  on i: -(R_i - delta/2) n x F_t + R* n x F_r + M n; on j: -(R_j - delta/2) n x F_t
             - R* n x F_r - M n (a flat wall, R_j = 0: arm R_i)

All four of LAMMPS's Mindlin variants are kept, under LAMMPS's names: ``mindlin`` (the
displacement spring above), ``mindlin_rescale`` (the spring first scaled by a/a_old where the
contact radius shrank), ``mindlin/force`` (the spring is the elastic force, advanced by
-k_t a v_t dt) and ``mindlin_rescale/force``. ``mindlin`` is what the elastic limit is checked
with against LAMMPS. For a plastic law use a /force variant, ``mindlin_rescale/force``: a plastic
contact keeps its plastic radius a_p to separation, so a displacement spring loaded at first touch
(a small) and released at a_p returns more work than it took -- measured on vz impacts at 2..10
degrees: up to 19 % of the incoming tangential energy created, e_t > 1 (tests/test_oblique.py) --
while the incremental force takes each increment at the stiffness of its moment and dissipates
at every angle; the rescale then lets the force follow the elastic radius a_e down on unloading.
nfdmodel/README.md (Friction, rolling and twisting) states the models in full.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from . import limits
from .hertz_contact import hertz_radius
from .materials import Material, as_pair
from .validation import check_real

DAMPING = {"none": limits.DAMPING_NONE, "viscoelastic": limits.DAMPING_VISCOELASTIC, "tsuji": limits.DAMPING_TSUJI,
           "coeff_restitution": limits.DAMPING_COEFF_RESTITUTION}
TANGENTIAL = {"none": limits.TANGENTIAL_NONE, "mindlin": limits.TANGENTIAL_MINDLIN,
              "mindlin_rescale": limits.TANGENTIAL_MINDLIN_RESCALE, "mindlin/force": limits.TANGENTIAL_MINDLIN_FORCE,
              "mindlin_rescale/force": limits.TANGENTIAL_MINDLIN_RESCALE_FORCE}
ROLLING = {"none": limits.ROLLING_NONE, "sds": limits.ROLLING_SDS}
TWISTING = {"none": limits.TWISTING_NONE, "marshall": limits.TWISTING_MARSHALL, "sds": limits.TWISTING_SDS}
# LAMMPS's constants of the coeff_restitution damping: sqrt(3/2) and 2 sqrt(5/6)
_ROOT_3_2, _TWO_ROOT_5_6 = 1.22474487139158894067, 1.82574185835055380345


def shear_coefficient(material_i: Material, material_j: Material | None = None) -> float:
    """k_t = 8 G* [Pa], the Mindlin coefficient of two bodies (``tangential mindlin NULL``):
    1/G* = (2 - nu_i)/G_i + (2 - nu_j)/G_j, G = E/(2 (1 + nu)); material_j None: a rigid flat."""
    factor_i = 2.0 * (2.0 - material_i.nu) * (1.0 + material_i.nu) / material_i.E
    factor_j = 0.0 if material_j is None else 2.0 * (2.0 - material_j.nu) * (1.0 + material_j.nu) / material_j.E
    return 8.0 * (1.0 / (factor_i + factor_j))


def damping_coefficient(model: str, value: float) -> float:
    """c of the damping prefactor: viscoelastic, value = c [1/(m s)]; tsuji, value = e:
    c = 1.2728 - 4.2783 e + 11.087 e^2 - 22.348 e^3 + 27.467 e^4 - 18.022 e^5 + 4.8218 e^6
    (Marshall 2009 eq. 53, as LAMMPS 22 Jul 2025 computes it); coeff_restitution:
    c = -sqrt(5) ln e / sqrt(pi^2 + ln^2 e) (a Hertz contact of restitution e)."""
    if model == "viscoelastic":
        return float(value)
    if model == "tsuji":
        e = value
        e2 = e * e
        e4 = e2 * e2
        c = 1.2728 - 4.2783 * e + 11.087 * e2
        c += -22.348 * (e2 * e) + 27.467 * e4
        c += -18.022 * (e4 * e) + 4.8218 * (e4 * e2)
        return c
    if model == "coeff_restitution":
        log_e = math.log(value)
        return -_ROOT_3_2 * _TWO_ROOT_5_6 * log_e / math.sqrt(math.pi * math.pi + log_e * log_e)
    return 0.0


def _choice(name: str, value: str, allowed: dict) -> str:
    if value not in allowed:
        raise ValueError(f"{name} out of range: need one of {', '.join(allowed)}, got {value!r}")
    return value


def _non_negative(name: str, value: float, unit: str = "") -> float:
    return check_real(name, value, low=0.0, low_inclusive=True, unit=unit)


@dataclass(frozen=True)
class Friction:
    """The contact models around the normal law, as LAMMPS's granular keywords (default: none).

    damping: "none" | "viscoelastic" (damping_value = c [1/(m s)]) | "tsuji" | "coeff_restitution"
    (damping_value = the restitution e in (0, 1]); tangential: "none" | "mindlin" with k_t [Pa]
    (8 G*: :func:`shear_coefficient`), x_gamma_t [-] and mu [-]; rolling: "none" | "sds" with
    k_roll [N/m], gamma_roll [N s/m], mu_roll [-]; twisting: "none" | "marshall" (needs mindlin) |
    "sds" with k_twist [N m/rad], gamma_twist [N m s/rad], mu_twist [m]."""

    damping: str = "none"
    damping_value: float = 0.0
    tangential: str = "none"
    k_t: float = 0.0
    x_gamma_t: float = 0.0
    mu: float = 0.0
    rolling: str = "none"
    k_roll: float = 0.0
    gamma_roll: float = 0.0
    mu_roll: float = 0.0
    twisting: str = "none"
    k_twist: float = 0.0
    gamma_twist: float = 0.0
    mu_twist: float = 0.0
    damping_c: float = field(init=False, repr=False)

    def __post_init__(self):
        _choice("damping", self.damping, DAMPING)
        _choice("tangential", self.tangential, TANGENTIAL)
        _choice("rolling", self.rolling, ROLLING)
        _choice("twisting", self.twisting, TWISTING)
        if self.damping in ("tsuji", "coeff_restitution"):
            low_open = self.damping == "coeff_restitution"
            check_real("e", self.damping_value, low=0.0, low_inclusive=not low_open, high=1.0, high_inclusive=True)
        else:
            _non_negative("damping_value", self.damping_value, "1/(m s)")
        for name in ("x_gamma_t", "gamma_roll", "k_twist", "gamma_twist", "mu_twist"):
            _non_negative(name, getattr(self, name))
        for name in ("mu", "mu_roll"):
            check_real(name, getattr(self, name), low=0.0, low_inclusive=True, high=limits.MU_MAX, high_inclusive=True)
        if self.tangential != "none":
            check_real("k_t", self.k_t, low=0.0, unit="Pa")
        if self.rolling == "sds":
            check_real("k_roll", self.k_roll, low=0.0, unit="N/m")
        if self.twisting == "sds":
            check_real("k_twist", self.k_twist, low=0.0, unit="N m/rad")
        if self.twisting == "marshall" and self.tangential == "none":
            raise ValueError("twisting out of range: marshall takes its stiffness from the tangential model: "
                             "need tangential mindlin, got tangential none")
        object.__setattr__(self, "damping_c", damping_coefficient(self.damping, self.damping_value))

    @classmethod
    def mindlin(cls, mu: float, material_i: Material, material_j: Material | None = None, variant: str = "mindlin",
                **more) -> "Friction":
        """Mindlin friction mu with k_t = 8 G* of the two materials (None: a rigid flat); variant:
        mindlin, mindlin_rescale, mindlin/force or mindlin_rescale/force."""
        return cls(tangential=variant, k_t=shear_coefficient(material_i, material_j), mu=mu, **more)

    @property
    def none(self) -> bool:
        """True when no model is on: the contact is the normal law alone."""
        return (self.damping, self.tangential, self.rolling, self.twisting) == ("none",) * 4


@dataclass
class FrictionState:
    """The springs of n contacts [SI]: xi_t (n, 3) as seen from body i (body j sees -xi_t): the
    tangential displacement [m], or the elastic tangential force [N] of the /force variants;
    xi_roll (n, 3) [m]; theta_twist (n,) [rad]; a_previous (n,) [m] the contact radius of the last
    step (the rescale variants); zeros for a new contact."""

    xi_t: np.ndarray
    xi_roll: np.ndarray
    theta_twist: np.ndarray
    a_previous: np.ndarray

    @classmethod
    def virgin(cls, n: int) -> "FrictionState":
        return cls(np.zeros((n, 3)), np.zeros((n, 3)), np.zeros(n), np.zeros(n))

    def copy(self) -> "FrictionState":
        return FrictionState(self.xi_t.copy(), self.xi_roll.copy(), self.theta_twist.copy(), self.a_previous.copy())


@dataclass(frozen=True)
class Contact:
    """One step's geometry and motion of n contacts: n (n, 3) unit normal from j to i; delta (n,)
    [m]; R_i, R_j [m] (R_j = 0: a flat wall); v (n, 3) = v_i - v_j [m/s]; omega_i, omega_j (n, 3)
    [rad/s]; m_star [kg]; dt [s]. Scalars broadcast."""

    n: np.ndarray
    delta: np.ndarray
    R_i: np.ndarray
    R_j: np.ndarray
    v: np.ndarray
    omega_i: np.ndarray
    omega_j: np.ndarray
    m_star: np.ndarray
    dt: float


@dataclass(frozen=True)
class ContactForces:
    """force (n, 3) on i [N] (j: -force); torque_i, torque_j (n, 3) [N m]; P the normal law's force
    [N]; F_n = P + normal damping [N]; a the contact radius [m]; F_t (n, 3) the tangential force [N]."""

    force: np.ndarray
    torque_i: np.ndarray
    torque_j: np.ndarray
    P: np.ndarray
    F_n: np.ndarray
    a: np.ndarray
    F_t: np.ndarray


def _dot(a, b):
    return a[:, 0] * b[:, 0] + a[:, 1] * b[:, 1] + a[:, 2] * b[:, 2]


def _len(a):
    return np.sqrt(a[:, 0] * a[:, 0] + a[:, 1] * a[:, 1] + a[:, 2] * a[:, 2])


def _cross(a, b):
    return np.stack([a[:, 1] * b[:, 2] - a[:, 2] * b[:, 1], a[:, 2] * b[:, 0] - a[:, 0] * b[:, 2],
                     a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]], axis=1)


def _rotate_rescale(v, n, where):
    """v[where] projected into the plane normal to n, its length kept (in place)."""
    along, length = _dot(v, n), _len(v)
    projected = v - along[:, None] * n
    size = _len(projected)
    scale = np.where(size > 0.0, length / np.where(size > 0.0, size, 1.0), 0.0)
    v[where] = (projected * scale[:, None])[where]


def contact_radius(law_name: str, delta, P, state, params):
    """The contact radius [m] of each contact after the step (new history ``state``, force P)."""
    pair = as_pair(params, law_name)
    hertz = np.sqrt(np.maximum(np.asarray(delta, dtype=float), 0.0) * pair.R_star)
    if law_name not in ("vz", "vz-table", "vz-unload", "thornton"):
        return hertz
    yielded = state.P_max > pair.P_Y
    if law_name == "vz":
        plastic = hertz_radius(P, pair.R_star, pair.E_star) + params.plastic_radius(state.P_max)
    elif law_name in ("vz-table", "vz-unload"):
        plastic = params.plastic_radius(state.P_max) + hertz_radius(P, pair.R_star, pair.E_star)
    else:
        root_R_p = 3.0 * state.unloading_stiffness / (4.0 * pair.E_star)    # K_u = (4/3) E* sqrt(R_p*)
        plastic = hertz_radius(P, root_R_p * root_R_p, pair.E_star)         # Hertz at the enlarged radius R_p*
    return np.where(yielded, plastic, hertz)


def damping_prefactor(friction: Friction, m_star, a, P, delta):
    """eta [N s/m] per contact: the normal damping force is -eta v.n."""
    if friction.damping == "viscoelastic":
        return friction.damping_c * m_star * a
    if friction.damping in ("tsuji", "coeff_restitution"):
        safe = np.where(delta > 0.0, delta, 1.0)
        s = np.where(delta > 0.0, m_star * P / safe, 0.0)
        return friction.damping_c * np.sqrt(np.maximum(s, 0.0))
    return np.zeros_like(np.asarray(a, dtype=float))


def tangential_mindlin(xi, a_previous, a, n, v_t, dt, stiffness, gamma_t, F_cap, update, variant="mindlin"):
    """LAMMPS's ``mindlin`` and its variants: advance the springs xi (n, 3) in place (update; the
    rescale variants also a_previous), return F_t (n, 3). rescale: where the contact radius a
    shrank below a_previous, xi is first scaled by a / a_previous; /force: xi is the elastic force,
    advanced by -k_t a dt v_t (else the displacement, advanced by dt v_t, the force -k_t a xi)."""
    rescale, force_form = "rescale" in variant, variant.endswith("/force")
    if rescale:
        shrink = a < a_previous
        xi[shrink] *= (a / np.where(shrink, a_previous, 1.0))[shrink][:, None]
    if update:
        along = np.abs(_dot(xi, n))
        rotate = (along if force_form else along * stiffness) > limits.FRAME_EPSILON * F_cap
        _rotate_rescale(xi, n, rotate)
        xi += (-stiffness * dt)[:, None] * v_t if force_form else dt * v_t
        if rescale:
            a_previous[:] = a
    damping = -gamma_t[:, None] * v_t
    F_t = (xi if force_form else -stiffness[:, None] * xi) + damping
    magnitude = _len(F_t)
    slide = magnitude > F_cap
    if np.any(slide):
        moving = slide & (_len(xi) != 0.0)
        scale = F_cap / np.where(slide, magnitude, 1.0)
        capped = F_t * scale[:, None]
        # the spring keeps the elastic part of the capped force, at most the cap itself: damping
        # beyond the cap stored in it would be returned as work later (README: how ours differs)
        elastic = capped - damping
        size = _len(elastic)
        over = size > F_cap * (1.0 + limits.CAP_SLACK)      # not the round-off of an undamped cap
        elastic *= np.where(over, F_cap / np.where(over, size, 1.0), 1.0)[:, None]
        if force_form:
            xi[moving] = elastic[moving]
        else:
            back = -1.0 / np.where(moving, stiffness, 1.0)
            xi[moving] = (elastic * back[:, None])[moving]
        F_t = np.where(moving[:, None], capped, np.where(slide[:, None], 0.0, F_t))
    return F_t


def rolling_sds(xi, n, v_roll, dt, friction: Friction, F_cap, update):
    """SDS rolling: advance xi (n, 3) in place (update), return F_r (n, 3)."""
    spring = xi.copy()
    k, gamma = friction.k_roll, friction.gamma_roll
    if update:
        rotate = np.abs(_dot(spring, n)) * k > limits.FRAME_EPSILON * F_cap
        _rotate_rescale(spring, n, rotate)
        spring += dt * v_roll
    F_r = -k * spring + -gamma * v_roll
    magnitude = _len(F_r)
    slide = magnitude > F_cap
    if np.any(slide):
        moving = slide & (_len(spring) != 0.0)
        magnitude_inv = 1.0 / np.where(slide, magnitude, 1.0)
        back = -F_cap * (1.0 / k) * magnitude_inv
        spring[moving] = (back[:, None] * F_r + (-gamma * (1.0 / k)) * v_roll)[moving]
        F_r = np.where(moving[:, None], F_r * (F_cap * magnitude_inv)[:, None], np.where(slide[:, None], 0.0, F_r))
    if update:
        xi[:] = spring
    return F_r


def twisting(theta, w, dt, k, gamma, M_cap, update):
    """Twisting: advance theta (n,) in place (update), return the torque M (n,) about n."""
    if update:
        theta += w * dt
    M = -k * theta - gamma * w
    sign = np.sign(w)
    cap = np.abs(M) > M_cap
    theta[cap] = ((M_cap * sign - gamma * w) / np.where(cap, k, 1.0))[cap]
    return np.where(cap, -M_cap * sign, M)


def contact_step(law, params, friction: Friction, contact: Contact, state, fstate: FrictionState, update=True):
    """One step of n contacts: (ContactForces, the normal law's new history, the new springs).
    ``state`` and ``fstate`` are not modified. update=False evaluates the stored springs without
    advancing them (a set-up step). law: a ContactLaw (nfdmodel.get_law)."""
    p = law.params_from(params)
    n_vec = np.asarray(contact.n, dtype=float)
    count = n_vec.shape[0]

    def each(value):
        return np.broadcast_to(np.asarray(value, dtype=float), (count,))

    def each3(value):
        return np.broadcast_to(np.asarray(value, dtype=float), (count, 3))

    delta, R_i, R_j, m_star = each(contact.delta), each(contact.R_i), each(contact.R_j), each(contact.m_star)
    v, omega_i, omega_j = each3(contact.v), each3(contact.omega_i), each3(contact.omega_j)
    dt = float(contact.dt)
    P, new_state = law.force_function(delta, state, p)
    P = np.asarray(P, dtype=float).reshape(-1)
    a = contact_radius(law.name, delta, P, new_state, p)
    eta = damping_prefactor(friction, m_star, a, P, delta)
    v_n = _dot(v, n_vec)
    F_n = P + -eta * v_n
    F_crit = np.abs(F_n)
    out = fstate.copy()
    F_t = np.zeros((count, 3))
    if friction.tangential != "none":
        spin = _cross(R_i[:, None] * omega_i + R_j[:, None] * omega_j, n_vec)
        v_t = (v - v_n[:, None] * n_vec) - spin
        F_t = tangential_mindlin(out.xi_t, out.a_previous, a, n_vec, v_t, dt, friction.k_t * a,
                                 friction.x_gamma_t * eta, F_crit * friction.mu, update, friction.tangential)
    force = F_n[:, None] * n_vec + F_t
    turn = _cross(n_vec, F_t)
    wall = R_j == 0.0
    arm_i = np.where(wall, R_i, R_i - 0.5 * delta)
    arm_j = np.where(wall, 0.0, R_j - 0.5 * delta)
    torque_i = -turn * arm_i[:, None]
    torque_j = -turn * arm_j[:, None]
    relrot = omega_i - omega_j
    R_star = as_pair(p, law.name).R_star
    if friction.rolling == "sds":
        v_roll = _cross(relrot, n_vec) * R_star
        F_r = rolling_sds(out.xi_roll, n_vec, v_roll, dt, friction, friction.mu_roll * F_crit, update)
        roll = R_star * _cross(n_vec, F_r)
        torque_i = torque_i + roll
        torque_j = torque_j - roll
    if friction.twisting != "none":
        if friction.twisting == "marshall":
            k = 0.5 * friction.k_t * a * a
            gamma = 0.5 * (friction.x_gamma_t * eta) * a * a
            mu = 2.0 / 3.0 * friction.mu * a
        else:
            k, gamma, mu = friction.k_twist, friction.gamma_twist, friction.mu_twist
        M = twisting(out.theta_twist, _dot(relrot, n_vec), dt, k, gamma, mu * F_crit, update)
        torque_i = torque_i + M[:, None] * n_vec
        torque_j = torque_j - M[:, None] * n_vec
    torque_j = np.where(wall[:, None], 0.0, torque_j)
    return ContactForces(force, torque_i, torque_j, P, F_n, a, F_t), new_state, out


def kernel_friction(friction: Friction) -> tuple:
    """The nfd_friction struct as the compiled binding takes it (its fields in order)."""
    return (DAMPING[friction.damping], friction.damping_c, TANGENTIAL[friction.tangential], float(friction.k_t),
            float(friction.x_gamma_t), float(friction.mu), ROLLING[friction.rolling], float(friction.k_roll),
            float(friction.gamma_roll), float(friction.mu_roll), TWISTING[friction.twisting],
            float(friction.k_twist), float(friction.gamma_twist), float(friction.mu_twist))


def compiled_contact_step(law, params, friction: Friction, contact: Contact, state, fstate: FrictionState,
                          update=True):
    """:func:`contact_step` through the C kernel (nfd_contact_step of nfd_friction.h, compiled
    into nfdmodel._native): the same results, to round-off. ValueError when it is not built, or
    naming the first contact whose normal law failed."""
    from . import native
    from .history import HertzState, field_names
    from .limits import LAW_CODES
    if native._native is None:
        raise ValueError(f"backend 'native' is not available: {native._MISSING}")
    p = law.params_from(params)
    pair = as_pair(p, law.name)
    table = None
    if law.name in ("vz-table", "vz-unload"):
        kernel = native.kernel_params(pair, window_P_max=p.window_force)
        table = native.kernel_table(p)
    else:
        kernel = law.collision_params(p)
    n_vec = np.asarray(contact.n, dtype=float)
    count = n_vec.shape[0]
    columns = [n_vec, contact.delta, contact.R_i, contact.R_j, contact.v, contact.omega_i, contact.omega_j,
               contact.m_star]
    geometry = np.ascontiguousarray(np.column_stack([np.broadcast_to(np.asarray(c, dtype=float).reshape(count, -1)
                                                                     if np.ndim(c) > 1 else
                                                                     np.broadcast_to(np.asarray(c, dtype=float),
                                                                                     (count,))[:, None],
                                                                     (count, np.shape(c)[-1] if np.ndim(c) > 1 else 1))
                                                     for c in columns]))
    zeros = np.zeros(count)
    fifth = "unloading_exponent" if hasattr(state, "unloading_exponent") else "a_e_max"   # (nfd_history's 5th)
    normal = [zeros] * 5 if isinstance(state, HertzState) else [
        state.delta_max, state.P_max, state.delta_res, state.unloading_stiffness, getattr(state, fifth, zeros)]
    history = np.ascontiguousarray(np.column_stack(normal + [fstate.xi_t, fstate.xi_roll, fstate.theta_twist,
                                                             fstate.a_previous]))
    out = np.empty((count, 28))
    status, at = native._native.contact_step(LAW_CODES[law.name], kernel, table, kernel_friction(friction),
                                             bool(update), float(contact.dt), geometry, history, out)
    if status < 0:
        law.force_function(np.asarray(contact.delta, dtype=float).reshape(-1)[at:at + 1],
                           law.initial_state(1), p)       # the numpy law names the cause in its words
        raise ValueError(f"delta out of range at contact {at}: the normal law failed (status {status})")
    if isinstance(state, HertzState):
        new_state = state
    else:
        values = dict(zip(("delta_max", "P_max", "delta_res", "unloading_stiffness", fifth), out[:, :5].T))
        new_state = type(state)(**{name: values[name].copy() for name in field_names(type(state))})
    forces = ContactForces(out[:, 13:16], out[:, 16:19], out[:, 19:22], out[:, 22], out[:, 23], out[:, 24],
                           out[:, 25:28])
    return forces, new_state, FrictionState(out[:, 5:8].copy(), out[:, 8:11].copy(), out[:, 11].copy(),
                                            out[:, 12].copy())

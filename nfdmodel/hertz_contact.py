"""Hertz's elastic contact of two bodies: contact radius, pressure, approach and impact (SI units).

With the effective radius R* [m] and modulus E* [Pa] of the pair (nfdmodel.materials), at the
normal force P [N] (Johnson 1985, Contact Mechanics, eqs. 4.22-4.23):

    a  = (3 P R* / (4 E*))^(1/3)        contact radius [m]
    P  = 4 E* a^3 / (3 R*)              the same, solved for the force [N]
    p0 = 3 P / (2 pi a^2)               peak pressure [Pa];  p(r) = p0 sqrt(1 - r^2/a^2), r <= a
    delta = a^2 / R*                    approach [m];  P = k_H delta^(3/2), k_H = (4/3) E* sqrt(R*)

and an elastic impact of reduced mass m* [kg] at v [m/s] (Johnson 1985 eq. 11.24; section 11.4):

    delta_max = (5 m* v^2 / (4 k_H))^(2/5) [m],   P_max = k_H delta_max^(3/2) [N],
    t_c = 2.8683 (m*^2 / (R* E*^2 v))^(1/5) [s],

the approach delta_max following from the impact's energy W = (1/2) m* v^2 = (2/5) k_H delta_max^(5/2).

This module is the one home of these formulas (tests/test_formula_homes.py); ContactPair's
hertz_* methods and every caller use it. Each function takes floats or numpy arrays.
"""
from __future__ import annotations

import math

import numpy as np

from . import limits

HERTZ_IMPACT_TIME = limits.HERTZ_IMPACT_TIME    # [-] t_c (R* E*^2 v / m*^2)^(1/5) (Johnson eq. 11.24; nfd_limits.h)


def hertz_radius(force, R_star, E_star):
    """Contact radius a = (3 P R* / (4 E*))^(1/3) [m] at force P [N] (Johnson 1985 eq. 4.22)."""
    return np.cbrt(3.0 * force * R_star / (4.0 * E_star))


def hertz_force_at_radius(radius, R_star, E_star):
    """The force P = 4 E* a^3 / (3 R*) [N] whose Hertz contact radius is a [m] (Johnson 1985 eq. 4.22)."""
    return 4.0 * E_star * radius ** 3 / (3.0 * R_star)


def hertz_peak_pressure(force, radius):
    """Peak pressure p0 = 3 P / (2 pi a^2) [Pa] of force P [N] on a contact of radius a [m]
    (Johnson 1985 eq. 4.23)."""
    return 3.0 * force / (2.0 * math.pi * radius ** 2)


def hertz_stiffness(R_star, E_star):
    """k_H = (4/3) E* sqrt(R*) [N/m^1.5] in Hertz's P = k_H delta^(3/2) (Johnson 1985 eq. 4.23)."""
    return 4.0 / 3.0 * E_star * math.sqrt(R_star)


def hertz_impact_approach(mass_star, stiffness, v_in):
    """Largest approach delta_max = (5 m* v^2 / (4 k_H))^(2/5) [m] of an elastic impact at v [m/s]
    of reduced mass m* [kg] on Hertz's stiffness k_H [N/m^1.5] ((1/2) m* v^2 = (2/5) k_H delta^(5/2))."""
    return (5.0 * mass_star * v_in ** 2 / (4.0 * stiffness)) ** 0.4


def hertz_impact_force(mass_star, stiffness, v_in):
    """Largest force P_max = k_H (5 m* v^2 / (4 k_H))^(3/5) [N] of an elastic impact at v [m/s]
    (hertz_impact_approach's delta_max, P = k_H delta_max^(3/2) in one power)."""
    return stiffness * (5.0 * mass_star * v_in ** 2 / (4.0 * stiffness)) ** 0.6


def hertz_approach_at_work(work, stiffness):
    """The approach delta = (W / ((2/5) k_H))^(2/5) [m] whose Hertz loading work is W [J]
    (W = (2/5) k_H delta^(5/2), k_H [N/m^1.5])."""
    return (work / (0.4 * stiffness)) ** 0.4


def hertz_impact_time(mass_star, R_star, E_star, v_in):
    """Duration t_c = 2.8683 (m*^2 / (R* E*^2 v))^(1/5) [s] of an elastic Hertz impact at v [m/s]
    (Johnson 1985 eq. 11.24)."""
    return HERTZ_IMPACT_TIME * (mass_star ** 2 / (R_star * E_star ** 2 * v_in)) ** 0.2

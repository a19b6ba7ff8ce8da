"""Oblique impacts of two spheres (nfdmodel.oblique_collide with a partner) against closed forms and
against the sphere-on-flat impact, which the law did not produce.

- Gross sliding: the tangential impulse is mu times the normal one to round-off (measured 2e-15);
  each sphere's spin changes by 5 mu J_n / (2 m R) within delta_max / R (LAMMPS's torque arm R -
  delta/2; measured 1e-4 against 2.6e-4); the relative tangential velocity by mu (v_n + v_n')
  within the normal's turn times tan(angle) (the line of centres turns while the spheres slide;
  measured 0.6 % at a turn of 2.3e-3 rad and 80 deg); the tangential momentum of the two is
  conserved to round-off.
- Energy: the kinetic energy of both spheres lost equals the normal plus the frictional work to
  1e-11 of the kinetic energy (measured 7e-13), with rolling, twisting and normal damping; the
  sliding impacts dissipate, the plastic law's normal work is its hysteresis.
- A partner a million times larger and 10^18 times heavier is a flat (a different code path: both
  bodies move, the geometry from the centres): the sphere-on-flat impact's normal rebound and
  peak force within 1e-5 (the partner's curvature changes R* by 1e-6; measured 1.6e-6), its
  tangential rebound, spin and e_t within 1e-3 (measured 6e-4), beta within 2e-3 (measured
  8.6e-4; a difference of velocities, near 0 at 70 deg) (between spheres LAMMPS's
  torque arm is R - delta/2, on a wall R, delta/R = 1e-4, amplified near sticking).
- The normal restitution of an oblique impact is the head-on one at the same normal speed,
  within the normal's turn (the centrifugal term of the turning line of centres).
"""
from __future__ import annotations

import numpy as np
import pytest

from nfdmodel import ContactPair, Material, VZParams
from nfdmodel.friction import Friction
from nfdmodel.oblique import oblique_collide, slip_closed_form

pytestmark = pytest.mark.laws      # rerun on the numpy kernels by .ci/run (tests/test_markers.py)

ALUMINIUM = Material.reference()
R_I, R_J = 0.01, 0.008
PAIR = ContactPair.sphere_sphere(ALUMINIUM, R_I, ALUMINIUM, R_J)
M_I, M_J = ALUMINIUM.sphere_mass(R_I), ALUMINIUM.sphere_mass(R_J)
PARAMS = {"hertz": PAIR, "vz": VZParams.from_dimensionless(PAIR, 0.026, 0.0098)}
DT = 1e-7


@pytest.mark.parametrize("law", ["hertz", "vz"])
def test_gross_sliding_of_two_spheres_gives_the_coulomb_impulse(law):
    mu, angles = 0.2, np.array([80.0, 85.0])
    friction = Friction.mindlin(mu, ALUMINIUM, ALUMINIUM)
    r = oblique_collide(law, PARAMS[law], friction, 0.5, angles, -30.0, dt=DT, partner=(R_J, M_J),
                        omega_partner=12.0)
    np.testing.assert_allclose(-r.impulse_t, mu * r.impulse_n, rtol=1e-13)
    for R, m, spin_in, spin_out in ((R_I, M_I, r.omega, r.omega_out), (R_J, M_J, r.omega_partner,
                                                                       r.omega_partner_out)):
        closed = 2.5 * mu * r.impulse_n / (m * R)
        assert (np.abs((spin_out - spin_in) / closed - 1.0) <= r.delta_max / R).all()
    slip, spin = slip_closed_form(r, mu, R_I, PAIR.mass_star / M_I)
    turn = np.abs(r.normal_turn) * np.tan(np.radians(angles))
    assert (np.abs((r.v_t - r.v_t_out) / slip - 1.0) <= turn).all() and (turn < 0.05).all()
    momentum = M_I * r.velocities[:, 0, 0] + M_J * r.velocities[:, 1, 0]
    assert np.abs(momentum).max() <= 1e-13 * M_I * 0.5
    assert (r.beta < 0.0).all()


@pytest.mark.parametrize("law", ["hertz", "vz"])
def test_two_spheres_lose_the_normal_plus_the_frictional_work(law):
    friction = Friction.mindlin(0.3, ALUMINIUM, ALUMINIUM, rolling="sds", k_roll=1000.0, gamma_roll=0.01,
                                mu_roll=0.1, twisting="marshall", damping="viscoelastic", damping_value=0.3)
    angles = np.array([0.0, 15.0, 45.0, 80.0])
    r = oblique_collide(law, PARAMS[law], friction, 0.5, angles, -10.0, dt=DT, partner=(R_J, M_J),
                        omega_partner=25.0)
    kinetic = 0.5 * PAIR.mass_star * 0.5 ** 2
    np.testing.assert_allclose(r.kinetic_energy_lost, r.work_normal + r.work_friction, rtol=0.0, atol=1e-11 * kinetic)
    assert (r.work_friction[2:] > 0.0).all()
    if law == "vz":
        assert (r.work_normal > 0.01 * kinetic).all()


def test_a_huge_heavy_partner_is_a_flat():
    material = ALUMINIUM
    flat_pair = ContactPair.sphere_flat(material, R_I)
    R_big, m_big = 1e6 * R_I, 1e18 * M_I
    pair = ContactPair(1.0 / (1.0 / R_I + 1.0 / R_big), flat_pair.E_star, material.sigma_y, material.nu,
                       M_I * m_big / (M_I + m_big))
    friction = Friction.mindlin(0.3, material, rolling="sds", k_roll=1000.0, mu_roll=0.1)
    angles = np.array([5.0, 30.0, 70.0])
    flat = oblique_collide("vz", VZParams.from_dimensionless(flat_pair, 0.026, 0.0098), friction, 0.5, angles, 20.0,
                           dt=DT)
    sphere = oblique_collide("vz", VZParams.from_dimensionless(pair, 0.026, 0.0098), friction, 0.5, angles, 20.0,
                             dt=DT, partner=(R_big, m_big))
    for name in ("v_n_out", "e_n", "P_max"):
        np.testing.assert_allclose(getattr(sphere, name), getattr(flat, name), rtol=1e-5, err_msg=name)
    for name in ("v_t_out", "omega_out", "e_t"):
        np.testing.assert_allclose(getattr(sphere, name), getattr(flat, name), rtol=1e-3, err_msg=name)
    np.testing.assert_allclose(sphere.beta, flat.beta, rtol=0.0, atol=2e-3)


def test_the_normal_restitution_of_two_spheres_is_the_head_on_one():
    friction = Friction.mindlin(0.3, ALUMINIUM, ALUMINIUM)
    angles = np.array([10.0, 30.0, 60.0])
    for law in ("hertz", "vz"):
        r = oblique_collide(law, PARAMS[law], friction, 0.5, angles, 0.0, dt=DT, partner=(R_J, M_J))
        head_on = oblique_collide(law, PARAMS[law], friction, 0.5 * np.cos(np.radians(angles)), 0.0, 0.0, dt=DT,
                                  partner=(R_J, M_J))
        assert (np.abs(r.e_n - head_on.e_n) <= np.abs(r.normal_turn)).all()


@pytest.mark.parametrize("partner, message", [((0.001, M_J), r"^partner R_j out of range: need partner R_j > "),
                                              ((R_J, -1.0), r"^partner m_j out of range"),
                                              ("sphere", r"^partner must be \(R_j \[m\], m_j \[kg\]\)")])
def test_a_bad_partner_is_named(partner, message):
    with pytest.raises(ValueError, match=message):
        oblique_collide("hertz", PAIR, Friction(), 0.5, 30.0, 0.0, dt=DT, partner=partner)

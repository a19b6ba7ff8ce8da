"""Oblique impacts with friction (nfdmodel/oblique.py) against closed forms the law does not produce.

- Gross sliding throughout the impact (incidence far beyond the sticking range): the tangential
  velocity drops by mu (v_n + v_n') and the spin grows by 5 mu (v_n + v_n') / (2 R), to round-off
  (measured: 4e-15), for the elastic and the plastic laws. (With normal damping the normal force
  F_n = P - eta v.n turns negative at the end of the contact, where the cap is mu |F_n|: LAMMPS's
  definition, without its limit_damping; the closed form then no longer holds.)
- The normal restitution of an oblique impact equals the head-on one at the same normal speed
  (the tangential force has no normal component, and friction never changes the normal force):
  bit for bit.
- Energy: the kinetic energy lost equals the normal work (the law's hysteresis, plus damping) plus
  the frictional work (Coulomb sliding, rolling, twisting) to round-off of the kinetic energy
  (measured: 2e-12 over 1300 steps); without friction the frictional work is 0 exactly; the normal work equals the
  law's dissipated energy at its turning point (nfdmodel's ContactLaw.dissipated_energy, an
  integral of the loading and unloading curves) within the time step's O(dt^2) (measured: 3e-6);
  a sliding contact dissipates (work_friction > 0).
- Tangential elasticity (a Hertz-Mindlin contact at 45 degrees): the contact point's slip velocity
  reverses (beta > 0), which a Coulomb slider alone cannot do.
"""
from __future__ import annotations

import numpy as np
import pytest

from nfdmodel import ContactPair, Material, VZParams, get_law
from nfdmodel.friction import Friction
from nfdmodel.oblique import oblique_collide, slip_closed_form

pytestmark = pytest.mark.laws      # rerun on the numpy kernels by .ci/run (tests/test_markers.py)

ALUMINIUM = Material.reference()
R = 0.01
PAIR = ContactPair.sphere_flat(ALUMINIUM, R)
VZ = VZParams.from_dimensionless(PAIR, 0.026, 0.0098)
PARAMS = {"hertz": PAIR, "vz": VZ, "thornton": PAIR}
DT = 1e-7


@pytest.mark.parametrize("law", ["hertz", "vz", "thornton"])
def test_gross_sliding_gives_the_coulomb_impulse(law):
    """mu = 0.2 at 80 and 85 degrees (tan(angle) = 5.7, 11.4 >> 7 mu / 2 (1 + e)): the contact slides
    from first touch to separation, the tangential impulse is mu times the normal one."""
    friction = Friction.mindlin(0.2, ALUMINIUM)
    result = oblique_collide(law, PARAMS[law], friction, 0.5, [80.0, 85.0], -30.0, dt=DT)
    slip, spin = slip_closed_form(result, 0.2, R)
    np.testing.assert_allclose(result.v_t - result.v_t_out, slip, rtol=1e-13)
    np.testing.assert_allclose(result.omega_out - result.omega, spin, rtol=1e-13)
    assert (result.beta < 0.0).all()                        # still sliding forwards at separation


@pytest.mark.parametrize("law", ["hertz", "vz"])
def test_the_normal_restitution_is_the_head_on_one_at_the_same_normal_speed(law):
    friction = Friction.mindlin(0.3, ALUMINIUM, rolling="sds", k_roll=1000.0, mu_roll=0.1, twisting="marshall",
                                damping="viscoelastic", damping_value=0.3)
    angles = np.array([10.0, 30.0, 60.0])
    oblique = oblique_collide(law, PARAMS[law], friction, 0.5, angles, 20.0, dt=DT)
    head_on = oblique_collide(law, PARAMS[law], friction, 0.5 * np.cos(np.radians(angles)), 0.0, 0.0, dt=DT)
    np.testing.assert_array_equal(oblique.e_n, head_on.e_n)
    np.testing.assert_array_equal(oblique.P_max, head_on.P_max)
    assert (oblique.e_n < 0.9).all() if law == "vz" else np.allclose(oblique.e_n, 0.99, atol=0.01)


@pytest.mark.parametrize("law", ["hertz", "vz", "thornton"])
def test_the_kinetic_energy_lost_is_the_normal_plus_the_frictional_work(law):
    friction = Friction.mindlin(0.3, ALUMINIUM, rolling="sds", k_roll=1000.0, gamma_roll=0.01, mu_roll=0.1,
                                twisting="marshall")
    speed, angles = 0.5, np.array([0.0, 15.0, 45.0, 80.0])
    result = oblique_collide(law, PARAMS[law], friction, speed, angles, -10.0, dt=DT)
    kinetic = 0.5 * PAIR.mass_star * speed ** 2
    np.testing.assert_allclose(result.kinetic_energy_lost, result.work_normal + result.work_friction,
                               rtol=0.0, atol=1e-11 * kinetic)
    assert (result.work_friction[1:] > 0.0).all()
    frictionless = oblique_collide(law, PARAMS[law], Friction(), speed, angles, 0.0, dt=DT)
    assert not frictionless.work_friction.any()
    np.testing.assert_allclose(frictionless.kinetic_energy_lost, frictionless.work_normal, rtol=0.0,
                               atol=1e-11 * kinetic)
    # the normal work is the law's own hysteresis: its loading work minus what unloading returns,
    # from the turning point of the head-on impact at the same normal speed
    v_n = speed * np.cos(np.radians(angles))
    contact_law = get_law(law)
    state = contact_law.initial_state(angles.size)
    delta_max = np.array([_turning_point(contact_law, PARAMS[law], v) for v in v_n])
    _, state = contact_law.force_function(delta_max, state, PARAMS[law])
    dissipated = contact_law.dissipated_energy(state, PARAMS[law])
    scale = 0.5 * PAIR.mass_star * v_n ** 2
    np.testing.assert_allclose(result.work_normal, dissipated, rtol=0.0, atol=1e-5 * scale.max())


def _turning_point(law, params, v_n: float) -> float:
    """delta_max of the impact (energy balance: the loading work equals (1/2) m v_n^2)."""
    from nfdmodel import collision_reference
    return float(collision_reference(law.name, params, [v_n]).delta_max[0])


def test_an_elastic_contact_reverses_its_slip():
    """Hertz-Mindlin at 45 degrees, mu = 0.3 (below the gross-sliding range): the tangential spring
    stores energy and gives it back, the contact point's slip velocity reverses (beta > 0, the
    regime of Maw, Barber & Fawcett), which a Coulomb slider alone cannot do."""
    result = oblique_collide("hertz", PAIR, Friction.mindlin(0.3, ALUMINIUM), 0.5, 45.0, 0.0, dt=DT)
    assert 0.0 < float(result.beta) < 1.0
    assert float(result.e_n) == pytest.approx(1.0, abs=1e-6)


@pytest.mark.parametrize("keywords, message", [
    (dict(speed=-1.0), r"^speed out of range: need speed > 0 m/s"),
    (dict(angle=90.0), r"^angle out of range: need angle >= 0 and angle < 90 deg"),
    (dict(omega=float("inf")), r"^omega must be finite"),
    (dict(dt=0.0), r"^dt out of range: need dt > 0 s"),
])
def test_bad_impacts_are_named(keywords, message):
    arguments = dict(speed=0.5, angle=30.0, omega=0.0, dt=DT) | keywords
    with pytest.raises(ValueError, match=message):
        oblique_collide("hertz", PAIR, Friction(), arguments["speed"], arguments["angle"], arguments["omega"],
                        dt=arguments["dt"])


def test_on_a_plastic_contact_the_force_variants_dissipate_and_the_displacement_spring_creates_energy():
    """Which Mindlin variant for a plastic law: a vz contact at 2..10 degrees sticks; the plain
    displacement spring (mindlin, mindlin_rescale: F_t = -k_t a xi) is loaded while the contact
    radius is small (first touch) and released at the large plastic radius a_p it keeps to
    separation, so it returns more work than it took: negative frictional work, e_t > 1 (measured:
    up to 19 % of the incoming tangential energy created). The incremental force variants
    (mindlin/force, mindlin_rescale/force: dF_t = -k_t a dxi) dissipate at every angle, as on the
    elastic Hertz contact, where all four do."""
    angles = np.array([2.0, 5.0, 10.0, 30.0, 60.0])
    incoming = 0.5 * PAIR.mass_star * (0.5 * np.sin(np.radians(angles))) ** 2
    for variant in ("mindlin", "mindlin_rescale", "mindlin/force", "mindlin_rescale/force"):
        friction = Friction.mindlin(0.3, ALUMINIUM, variant=variant)
        plastic = oblique_collide("vz", VZ, friction, 0.5, angles, 0.0, dt=DT)
        elastic = oblique_collide("hertz", PAIR, friction, 0.5, angles, 0.0, dt=DT)
        assert (elastic.work_friction > 0.0).all()
        if variant.endswith("/force"):
            assert (plastic.work_friction > 0.1 * incoming).all() and (plastic.e_t < 1.0).all()
        else:
            assert (plastic.work_friction[:3] < -0.03 * incoming[:3]).all() and (plastic.e_t[:3] > 1.0).all()


def test_nfdcal_collide_oblique(tmp_path, capsys):
    """nfdcal collide --angle --mu --omega --json: nfdmodel.oblique_collide's numbers (gross sliding
    at 80 degrees: the Coulomb closed form); --plot writes the e_t and beta figure; a bad angle is
    one line, exit 2."""
    import json

    from calib import cli
    plot = tmp_path / "e_t.png"
    assert cli.main(["collide", "--v-in", "0.05", "--angle", "30", "80", "--mu", "0.2", "--omega", "-1",
                     "--dt", "1e-6", "--plot", str(plot), "--json"]) == 0
    records = json.loads(capsys.readouterr().out)
    assert [r["angle"] for r in records] == [30.0, 80.0] and plot.stat().st_size > 10_000
    friction = Friction.mindlin(0.2, ALUMINIUM, variant="mindlin_rescale/force")
    reference = oblique_collide("vz", VZParams.reference(), friction, 0.05, [30.0, 80.0], -1.0, dt=1e-6)
    for record, e_n, e_t, omega in zip(records, reference.e_n, reference.e_t, reference.omega_out):
        assert (record["e_n"], record["e_t"], record["omega_out"]) == pytest.approx((e_n, e_t, omega), rel=1e-12)
    sliding = records[1]
    v_n, v_t = 0.05 * np.cos(np.radians(80.0)), 0.05 * np.sin(np.radians(80.0))
    v_t_out = sliding["e_t"] * v_t
    assert v_t - v_t_out == pytest.approx(0.2 * v_n * (1.0 + sliding["e_n"]), rel=1e-12)
    assert cli.main(["collide", "--v-in", "0.05", "--angle", "95", "--mu", "0.2"]) == 2
    assert capsys.readouterr().err.strip() == \
        "nfdcal collide: error: --angle out of range: need --angle >= 0 and --angle < 90 deg, got 95"

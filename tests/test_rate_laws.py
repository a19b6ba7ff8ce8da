"""Strain-rate dependence (calib.fe.rate_law: Johnson-Cook, Cowper-Symonds; calib.fe.von_mises.RateDependentMaterial).

A strain-rate step of a uniaxial test at constant strain rate against the closed form sigma_Y R(rate), the
consistent tangent with the rate term against central differences, R = 1 (C = 0, D = inf) against the
rate-independent material bit for bit, the accumulated plastic work against sigma_y R d eps_p; the dynamic
FE impact of a rate-dependent sphere against the rate-independent one (its energy balance, e and the
dent at two speeds) on the coarse mesh; the command flags refused in one line.
"""
import math

import numpy as np
import pytest

from calib.fe.flow_curve import LinearHardening, SwiftHardening
from calib.fe.rate_law import CowperSymondsRate, JohnsonCookRate
from calib.fe.von_mises import HardeningMaterial, RateDependentMaterial

E, NU, SIGMA_Y = 70e9, 0.3, 100e6            # aluminium, as tests/test_hardening.py
LATERAL = [0, 2, 3]                          # rr, tt, rz: stress-free in a uniaxial test along z
LAWS = {"johnson-cook": JohnsonCookRate(0.05, 1.0),          # C, eps_dot_0 [1/s]
        "cowper-symonds": CowperSymondsRate(6500.0, 4.0)}    # D [1/s], q: aluminium (Jones 2012, table 8.1)


def closed_form_factor(name, rate):
    """R(rate) written from the laws' definitions (Johnson & Cook 1983; Cowper & Symonds 1957)."""
    if name == "johnson-cook":
        return 1.0 + 0.05 * math.log(max(rate / 1.0, 1.0))
    return 1.0 + (rate / 6500.0) ** (1.0 / 4.0)


def solve_uniaxial(material, strain_zz, state, guess, time_step, tolerance=1e-13):
    """eps_zz prescribed, the lateral strains by Newton with the consistent tangent (s_rr = s_tt = s_rz = 0)."""
    unknowns = np.array(guess, dtype=float)
    for _ in range(40):
        strain = np.empty((1, 1, 4))
        strain[0, 0, LATERAL] = unknowns
        strain[0, 0, 1] = strain_zz
        stress, tangent, trial = material.update(strain, state, time_step=time_step)
        residual = stress[0, 0, LATERAL]
        if np.abs(residual).max() <= tolerance * SIGMA_Y:
            return strain, stress, trial
        unknowns = unknowns - np.linalg.solve(tangent[0, 0][np.ix_(LATERAL, LATERAL)], residual)
    raise AssertionError("mixed-control Newton did not converge")


def uniaxial_path(material, rates, steps, increment=2e-5):
    """Uniaxial loading at the strain rates ``rates`` [1/s] in turn, ``steps`` steps of d eps_zz = increment
    each (dt = increment / rate): the stress sigma_zz [Pa] at the end of each rate, the final state."""
    state, guess, strain_zz, ends = material.initial_state(1, 1), np.zeros(3), 0.0, []
    for rate in rates:
        for _ in range(steps):
            strain_zz += increment
            strain, stress, state = solve_uniaxial(material, strain_zz, state, guess, increment / rate)
            guess = strain[0, 0, LATERAL]
        ends.append(stress[0, 0, 1])
    return ends, state


@pytest.mark.parametrize("name", sorted(LAWS))
def test_strain_rate_step_follows_the_closed_form(name):
    """Perfect plasticity at a constant strain rate flows at sigma_Y R(rate) (steady: d eps_p = d eps); the rate
    stepped 1e2 -> 1e4 -> 1e2 /s the flow stress jumps to sigma_Y R(1e4) and back."""
    material = RateDependentMaterial(E, NU, LinearHardening(SIGMA_Y), LAWS[name])
    rates = (1e2, 1e4, 1e2)
    ends, _ = uniaxial_path(material, rates, 600)       # the transient after a step: measured 3e-11 at 500 steps
    for rate, stress in zip(rates, ends):
        assert stress == pytest.approx(SIGMA_Y * closed_form_factor(name, rate), rel=1e-9)
    assert ends[1] / ends[0] == pytest.approx(closed_form_factor(name, 1e4) / closed_form_factor(name, 1e2), rel=1e-9)


@pytest.mark.parametrize("name", sorted(LAWS))
def test_rate_step_of_a_hardening_material_scales_its_flow_stress(name):
    """Linear hardening: right after the rate steps up the stress is sigma_y(eps_bar) R(eps_p rate), the plastic
    rate the step's own (the return's equation, checked with the state's eps_bar and the closed-form R)."""
    H = 0.05 * E
    material = RateDependentMaterial(E, NU, LinearHardening(SIGMA_Y, H), LAWS[name])
    increment = 2e-5
    ends, state = uniaxial_path(material, (1e2,), 150, increment)
    eps_before = state.equivalent_plastic_strain[0, 0]
    _, stress, after = solve_uniaxial(material, 151 * increment, state, np.zeros(3), increment / 1e4)
    eps_after = after.equivalent_plastic_strain[0, 0]
    plastic_rate = (eps_after - eps_before) / (increment / 1e4)
    assert stress[0, 0, 1] == pytest.approx((SIGMA_Y + H * eps_after) * closed_form_factor(name, plastic_rate),
                                            rel=1e-10)
    assert stress[0, 0, 1] > ends[0] + H * (eps_after - eps_before)      # more than the hardening alone


def central_difference_tangent(material, strain, state, time_step, step=1e-9):
    columns = []
    for j in range(4):
        plus, minus = strain.copy(), strain.copy()
        plus[0, 0, j] += step
        minus[0, 0, j] -= step
        columns.append((material.update(plus, state, time_step=time_step)[0][0, 0]
                        - material.update(minus, state, time_step=time_step)[0][0, 0]) / (2 * step))
    return np.array(columns).T


@pytest.mark.parametrize("curve", ["linear", "swift"])
@pytest.mark.parametrize("name", sorted(LAWS))
def test_consistent_tangent_with_the_rate_term_matches_central_differences(name, curve):
    flow = LinearHardening(SIGMA_Y, 0.05 * E) if curve == "linear" else SwiftHardening(SIGMA_Y, 4.0 * SIGMA_Y, 0.25)
    material = RateDependentMaterial(E, NU, flow, LAWS[name])
    state = material.initial_state(1, 1)
    _, _, state = material.update(np.array([[[0.001, -0.004, 0.0015, 0.002]]]), state, time_step=1e-6)
    assert state.equivalent_plastic_strain[0, 0] > 0
    strain = np.array([[[0.0013, -0.0052, 0.0016, 0.0031]]])
    time_step = 1e-6
    _, tangent, trial = material.update(strain, state, time_step=time_step)
    rate = (trial.equivalent_plastic_strain - state.equivalent_plastic_strain)[0, 0] / time_step
    assert rate > 1e2                                       # the rate term matters: R(rate) well above 1
    numeric = central_difference_tangent(material, strain, state, time_step)
    assert np.abs(tangent[0, 0] - numeric).max() < 1e-7 * np.abs(tangent[0, 0]).max()     # measured 3.6e-10 - 5.5e-10
    # without the rate term the tangent would be off by far more than that
    static = HardeningMaterial(E, NU, flow).update(strain, state)[1][0, 0]
    assert np.abs(static - numeric).max() > 1e-3 * np.abs(numeric).max()


@pytest.mark.parametrize("law", [JohnsonCookRate(0.0, 1.0), CowperSymondsRate(math.inf, 5.0),
                                 CowperSymondsRate(1e300, 5.0)], ids=["C=0", "D=inf", "D=1e300"])
def test_unit_factor_is_the_rate_independent_material(law):
    """R = 1: stress, tangent and plastic strain of HardeningMaterial, bit for bit (C = 0, D = inf) or to 1e-12."""
    flow = SwiftHardening(SIGMA_Y, 4.0 * SIGMA_Y, 0.25)
    rate, plain = RateDependentMaterial(E, NU, flow, law), HardeningMaterial(E, NU, flow)
    rng = np.random.default_rng(7)
    state_r, state_p = rate.initial_state(3, 2), plain.initial_state(3, 2)
    exact = law.is_unity
    for k in range(1, 6):
        strain = 0.002 * k * rng.standard_normal((3, 2, 4))
        stress_r, tangent_r, state_r = rate.update(strain, state_r, time_step=1e-6)
        stress_p, tangent_p, state_p = plain.update(strain, state_p)
        if exact:
            assert np.array_equal(stress_r, stress_p) and np.array_equal(tangent_r, tangent_p)
            assert np.array_equal(state_r.plastic_strain, state_p.plastic_strain)
        else:
            np.testing.assert_allclose(stress_r, stress_p, rtol=1e-12, atol=1e-12 * SIGMA_Y)
            np.testing.assert_allclose(tangent_r, tangent_p, rtol=1e-12, atol=1e-12 * E)
    assert state_p.equivalent_plastic_strain.max() > 0.005


@pytest.mark.parametrize("name", sorted(LAWS))
def test_plastic_work_accumulates_the_rate_dependent_flow_stress(name):
    """Perfect plasticity in the steady flow at 1e4 /s: the work the state accumulates grows by sigma_Y R(1e4) per
    unit plastic strain (not a function of eps_bar: above sigma_Y eps_bar); with R = 1 it is sigma_Y eps_bar."""
    material = RateDependentMaterial(E, NU, LinearHardening(SIGMA_Y), LAWS[name])
    _, state = uniaxial_path(material, (1e2, 1e4), 600)
    _, state_on = uniaxial_path(material, (1e2, 1e4, 1e4), 600)        # 600 steps more of the steady flow at 1e4 /s
    added_work = state_on.plastic_work[0, 0] - state.plastic_work[0, 0]
    added_eps = state_on.equivalent_plastic_strain[0, 0] - state.equivalent_plastic_strain[0, 0]
    assert added_eps == pytest.approx(600 * 2e-5, rel=1e-9)
    assert added_work / added_eps == pytest.approx(SIGMA_Y * closed_form_factor(name, 1e4), rel=1e-9)
    assert state_on.plastic_work[0, 0] > 1.05 * SIGMA_Y * state_on.equivalent_plastic_strain[0, 0]
    state_fast = state_on
    assert material.dissipated_work(state_fast, np.ones((1, 1))) == state_fast.plastic_work[0, 0]
    unity = RateDependentMaterial(E, NU, LinearHardening(SIGMA_Y), JohnsonCookRate(0.0))
    _, state_unity = uniaxial_path(unity, (1e2,), 150)
    assert state_unity.plastic_work[0, 0] == pytest.approx(SIGMA_Y * state_unity.equivalent_plastic_strain[0, 0],
                                                           rel=1e-12)


@pytest.mark.parametrize("make, needle", [
    (lambda: JohnsonCookRate(-0.1), "C out of range"),
    (lambda: JohnsonCookRate(0.05, 0.0), "reference_rate out of range"),
    (lambda: CowperSymondsRate(-1.0, 5.0), "D out of range"),
    (lambda: CowperSymondsRate(40.4, 0.0), "q out of range"),
    (lambda: RateDependentMaterial(E, NU, LinearHardening(SIGMA_Y), "fast"), "rate_law must be"),
])
def test_bad_rate_law_parameters_are_refused_naming_them(make, needle):
    with pytest.raises(ValueError, match=needle):
        make()


# ------------------------------------------------------------------------------------------------
# the dynamic FE impact (coarse whole sphere, 40 steps per contact)
# ------------------------------------------------------------------------------------------------
def test_rate_dependent_impact_closes_its_energy_balance_and_keeps_a_smaller_dent(mesh_cache):
    """At 0.02 and 0.04 m/s (12 and 24 v_Y) against the rate-independent sphere at the same speed, measured:
    Cowper-Symonds (aluminium, D = 6500 /s, q = 4): e 0.836 / 0.813 and 0.766 / 0.744 (+2.83 % and +2.91 %),
    dent 2.35 / 2.77 and 5.78 / 6.62 um; Johnson-Cook (C = 0.05, eps_dot_0 = 1 /s): dent 2.68 / 2.77 and 6.33 /
    6.62 um, e 0.808 / 0.813 and 0.739 / 0.744 (the viscoplastic relaxation where the contact slows dissipates
    more than the raised flow stress saves at so small a C). The energy balance closes with the plastic work
    accumulated as sigma : d eps_p, as the rate-independent one's does."""
    from calib.fe.impact import run_impact
    from calib.fe.newmark import ImpactSolver
    from calib.fe.von_mises import VonMisesMaterial
    from meshes.sphere import SphereMeshSpec, sphere_mesh

    spec = SphereMeshSpec(radius=0.1, contact_size=1.6e-4, refined_radius=1.6e-3, refined_depth=5e-4, far_size=1e-2,
                          growth=0.3)
    mesh = sphere_mesh(spec, cache_dir=mesh_cache)
    materials = {"independent": VonMisesMaterial(E, NU, SIGMA_Y),
                 **{name: RateDependentMaterial(E, NU, LinearHardening(SIGMA_Y), law) for name, law in LAWS.items()}}
    records = {(name, v): run_impact(ImpactSolver(mesh, material, 2699.0), v, steps_per_contact=40).record()
               for v in (0.02, 0.04) for name, material in materials.items()}
    rise = {}
    for v in (0.02, 0.04):
        independent = records["independent", v]
        for name in LAWS:
            record = records[name, v]
            assert record["dent"] < 0.97 * independent["dent"]
            assert abs(record["balance_residual"]) < 1e-3 * record["kinetic_in"]
            assert abs(record["internal_work_error"]) < 0.02 * record["plastic_work"]
        rise[v] = records["cowper-symonds", v]["e"] / independent["e"] - 1.0
        assert records["cowper-symonds", v]["P_max"] > independent["P_max"]
    assert 0.02 < rise[0.02] < rise[0.04] < 0.04


# ------------------------------------------------------------------------------------------------
# the commands: --rate-law, --jc-C, --jc-reference-rate, --cs-D, --cs-q
# ------------------------------------------------------------------------------------------------
RATE_REFUSALS = [
    ("impact", ["--rate-law", "jc"], "--rate-law must be one of johnson-cook, cowper-symonds"),
    ("impact", ["--rate-law", "johnson-cook"], "needs --jc-C"),
    ("impact", ["--jc-C", "0.1"], "--jc-C is a constant of --rate-law"),
    ("impact", ["--rate-law", "johnson-cook", "--jc-C", "2"], "--jc-C out of range"),
    ("impact", ["--rate-law", "johnson-cook", "--jc-C", "0.1", "--jc-reference-rate", "0"],
     "--jc-reference-rate out of range"),
    ("impact", ["--rate-law", "johnson-cook", "--jc-C", "0.1", "--cs-q", "4"], "--cs-q is a constant of --rate-law"),
    ("impact", ["--rate-law", "cowper-symonds", "--cs-D", "40"], "needs --cs-D and --cs-q"),
    ("impact", ["--rate-law", "cowper-symonds", "--cs-D", "-1", "--cs-q", "5"], "--cs-D out of range"),
    ("impact", ["--rate-law", "cowper-symonds", "--cs-D", "40", "--cs-q", "50"], "--cs-q out of range"),
    ("impact", ["--rate-law", "cowper-symonds", "--cs-D", "40", "--cs-q", "5", "--counter-E", "2e11"],
     "--counter-E is for a rate-independent sphere"),
    ("calibrate", ["--rate-law", "johnson-cook", "--jc-C", "0.1", "--ship", "unload"],
     "--rate-law out of range with --ship unload"),
    ("calibrate", ["--rate-law", "johnson-cook", "--jc-C", "0.1", "--hardening-modulus", "1e9"],
     "--rate-law out of range with --hardening-modulus"),
    ("calibrate", ["--rate-law", "johnson-cook", "--jc-C", "0.1", "--counter-E", "2e11"],
     "--rate-law out of range with --counter-E"),
    ("calibrate", ["--rate-form", "fixed"], "--rate-form is the form of the --rate-law law"),
]


@pytest.mark.parametrize("command, flags, needle", RATE_REFUSALS, ids=[needle for _, _, needle in RATE_REFUSALS])
def test_rate_law_flags_refused_in_one_line_exit_2(command, flags, needle, capsys):
    from calib.cli import main

    assert main([command, "--quiet", "--dry-run", *flags]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and needle in err, err


def test_rate_law_is_in_the_run_keys_and_the_rate_independent_keys_stay():
    """A rate law adds "rate_law" to the impact's task (a key of its own, a folder of its own); without one the
    task and its key are the rate-independent run's, so every shipped figure stays."""
    import argparse

    from calib.commands.common import rate_law_from_args
    from calib.studies.impact import ImpactSetup, task_of
    from meshes.sphere import SphereMeshSpec
    from nfdmodel import reference_case
    from nfdmodel.materials import Material

    plain = ImpactSetup(material=Material.reference(), radius=reference_case.R)
    mesh = SphereMeshSpec(radius=reference_case.R, contact_size=4e-5, refined_radius=1e-3, refined_depth=5e-4,
                          far_size=1e-2, growth=0.3)
    ns = argparse.Namespace(rate_law="cowper-symonds", jc_C=None, jc_reference_rate=None, cs_D="6500", cs_q="4")
    law = rate_law_from_args(ns)
    rated = ImpactSetup(material=Material.reference(), radius=reference_case.R, rate_law=law)
    task_plain, task_rated = task_of(plain, 0.04, "fine", mesh, 40), task_of(rated, 0.04, "fine", mesh, 40)
    assert "rate_law" not in task_plain and task_rated["rate_law"] == {"rate_law": "cowper-symonds", "D": 6500.0,
                                                                       "q": 4.0}
    assert task_rated["key"] != task_plain["key"]
    assert {k: v for k, v in task_rated.items() if k not in ("rate_law", "key")} == \
        {k: v for k, v in task_plain.items() if k != "key"}


@pytest.mark.parametrize("name", sorted(LAWS))
def test_return_converges_from_a_round_off_overstress_to_a_large_one(name):
    """The consistency condition q_trial - 3 mu dgamma - sigma_Y R(dgamma / dt) = 0 (perfect plasticity) holds to
    1e-13 q_trial for overstresses from 1e-11 to 1 sigma_Y. Cowper-Symonds' R' is infinite at dgamma = 0 (solved in
    (dgamma / dt D)^(1/q)); its dgamma is read from the stress by the law's inverse dt D (sigma / sigma_Y - 1)^q,
    which keeps the digits (q_trial - sigma) / (3 mu) loses where dgamma is below round-off."""
    from calib.fe.rate_law import RateDependentFlow

    dt = 1e-6
    flow = RateDependentFlow(LinearHardening(SIGMA_Y), LAWS[name], dt)
    q_trial = SIGMA_Y * (1.0 + np.logspace(-11, 0, 23))
    three_mu = 3 * E / (2 * (1 + NU))
    stress, modulus = flow.return_stress(q_trial, np.full(q_trial.shape, 0.01), three_mu)
    assert np.isfinite(modulus).all() and (modulus >= 0).all() and (stress >= SIGMA_Y).all()
    if name == "cowper-symonds":
        dgamma = dt * 6500.0 * (stress / SIGMA_Y - 1.0) ** 4.0
        residual = q_trial - three_mu * dgamma - stress
    else:
        dgamma = (q_trial - stress) / three_mu
        residual = stress - SIGMA_Y * np.array([closed_form_factor(name, d / dt) for d in dgamma])
    assert np.abs(residual).max() <= 1e-13 * q_trial.max()

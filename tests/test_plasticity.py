"""Verification of the von Mises radial return (calib.fe.von_mises).

Closed forms (uniaxial stress, pure shear, proportional paths), an independent scalar reference
written with full 3x3 tensors, the consistent tangent against central finite differences, and
quadratic convergence of Newton's method with that tangent.
"""
import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from calib.fe.material import elastic_matrix
from calib.fe.von_mises import (YIELD_TOLERANCE, PlasticState, VonMisesMaterial, equivalent_plastic_strain_increment,
                                radial_return, von_mises_stress, yielded_points)

# The reference case: aluminium (E 70 GPa, nu 0.3, sigma_Y 100 MPa).
E, NU, SIGMA_Y = 70e9, 0.3, 100e6
YIELD_STRAIN = SIGMA_Y / E
MU = E / (2 * (1 + NU))
K = E / (3 * (1 - 2 * NU))
LATERAL = [0, 2, 3]  # rr, tt, rz: the stress-free components of a uniaxial test along z


def random_points(rng, n, strain_scale=6.0, plastic_scale=3.0):
    """Random total and committed plastic strains (n, 1, 4), in multiples of the yield strain."""
    strain = rng.uniform(-strain_scale, strain_scale, (n, 1, 4)) * YIELD_STRAIN
    plastic_old = rng.uniform(-plastic_scale, plastic_scale, (n, 1, 4)) * YIELD_STRAIN
    plastic_old[..., 2] = -plastic_old[..., 0] - plastic_old[..., 1]  # plastic strain is isochoric
    return strain, plastic_old


def trial_von_mises(strain, plastic_old, E=E, nu=NU):
    return von_mises_stress(np.einsum("ij,...j->...i", elastic_matrix(E, nu), strain - plastic_old))


# ------------------------------------------------------------------------------------------
# independent scalar reference: one point, Python floats, full 3x3 tensors and 3x3x3x3 moduli
# ------------------------------------------------------------------------------------------
VOIGT_PAIRS = [(0, 0), (1, 1), (2, 2), (0, 1)]  # index 0 = r, 1 = z, 2 = theta


def kronecker(i, j):
    return 1.0 if i == j else 0.0


def voigt_strain_to_tensor(voigt):
    tensor = [[0.0] * 3 for _ in range(3)]
    tensor[0][0], tensor[1][1], tensor[2][2] = voigt[0], voigt[1], voigt[2]
    tensor[0][1] = tensor[1][0] = 0.5 * voigt[3]  # engineering shear gamma_rz = 2 eps_rz
    return tensor


def reference_return(strain_voigt, plastic_voigt, E, nu, sigma_y):
    """Radial return for one point, Simo & Hughes Box 3.1/3.2 in tensor notation."""
    lam = E * nu / ((1 + nu) * (1 - 2 * nu))
    mu = E / (2 * (1 + nu))
    bulk = lam + 2 * mu / 3
    strain = voigt_strain_to_tensor(strain_voigt)
    plastic = voigt_strain_to_tensor(plastic_voigt)
    elastic = [[strain[i][j] - plastic[i][j] for j in range(3)] for i in range(3)]
    trace = sum(elastic[i][i] for i in range(3))
    trial = [[lam * trace * kronecker(i, j) + 2 * mu * elastic[i][j] for j in range(3)]
             for i in range(3)]
    pressure = sum(trial[i][i] for i in range(3)) / 3
    dev = [[trial[i][j] - pressure * kronecker(i, j) for j in range(3)] for i in range(3)]
    norm = math.sqrt(sum(dev[i][j] ** 2 for i in range(3) for j in range(3)))
    q_trial = math.sqrt(1.5) * norm

    def symmetric_identity(i, j, k, l):
        return 0.5 * (kronecker(i, k) * kronecker(j, l) + kronecker(i, l) * kronecker(j, k))

    moduli = [[[[0.0] * 3 for _ in range(3)] for _ in range(3)] for _ in range(3)]
    increment = [[0.0] * 3 for _ in range(3)]
    if q_trial <= sigma_y * (1 + YIELD_TOLERANCE):
        stress = trial
        for i, j, k, l in np.ndindex(3, 3, 3, 3):
            moduli[i][j][k][l] = (lam * kronecker(i, j) * kronecker(k, l)
                                  + 2 * mu * symmetric_identity(i, j, k, l))
    else:
        delta_gamma = (q_trial - sigma_y) / (3 * mu)
        flow = [[dev[i][j] / norm for j in range(3)] for i in range(3)]
        stress = [[trial[i][j] - 2 * mu * delta_gamma * math.sqrt(1.5) * flow[i][j]
                   for j in range(3)] for i in range(3)]
        increment = [[delta_gamma * math.sqrt(1.5) * flow[i][j] for j in range(3)]
                     for i in range(3)]
        theta = 1 - 3 * mu * delta_gamma / q_trial
        for i, j, k, l in np.ndindex(3, 3, 3, 3):
            deviatoric_identity = (symmetric_identity(i, j, k, l)
                                   - kronecker(i, j) * kronecker(k, l) / 3)
            moduli[i][j][k][l] = (bulk * kronecker(i, j) * kronecker(k, l)
                                  + 2 * mu * theta * (deviatoric_identity
                                                      - flow[i][j] * flow[k][l]))
    # Voigt: plain stress components; d sigma_ij = C_ijkl d eps_kl and the eps_rz, eps_zr terms
    # together give C_ij01 * gamma_rz, so the Voigt matrix takes C_{ij,kl} unchanged.
    stress_voigt = [stress[i][j] for i, j in VOIGT_PAIRS]
    increment_voigt = [increment[0][0], increment[1][1], increment[2][2], 2 * increment[0][1]]
    tangent_voigt = [[moduli[i][j][k][l] for (k, l) in VOIGT_PAIRS] for (i, j) in VOIGT_PAIRS]
    return np.array(stress_voigt), np.array(tangent_voigt), np.array(increment_voigt)


def assert_matches_reference(strain, plastic_old, E, nu, sigma_y):
    stress, tangent, increment = radial_return(strain, plastic_old, E, nu, sigma_y)
    for e in range(strain.shape[0]):
        for q in range(strain.shape[1]):
            ref_stress, ref_tangent, ref_increment = reference_return(
                list(strain[e, q]), list(plastic_old[e, q]), E, nu, sigma_y)
            stress_scale = max(sigma_y, np.abs(ref_stress).max())
            np.testing.assert_allclose(stress[e, q], ref_stress, rtol=0, atol=1e-12 * stress_scale)
            np.testing.assert_allclose(tangent[e, q], ref_tangent, rtol=0, atol=1e-12 * E)
            np.testing.assert_allclose(increment[e, q], ref_increment, rtol=0,
                                       atol=1e-12 * max(np.abs(strain[e, q]).max(), sigma_y / E))


def strain_components(scale):
    return st.lists(st.floats(-scale, scale, allow_nan=False), min_size=4, max_size=4)


@settings(max_examples=300, deadline=None)
@given(strain=strain_components(8.0), plastic=strain_components(4.0),
       nu=st.floats(0.0, 0.49), E_value=st.floats(1e9, 400e9), sigma_y=st.floats(1e6, 2e9))
def test_agrees_with_scalar_tensor_reference(strain, plastic, nu, E_value, sigma_y):
    yield_strain = sigma_y / E_value
    strain = np.array(strain).reshape(1, 1, 4) * yield_strain
    plastic = np.array(plastic).reshape(1, 1, 4) * yield_strain  # not isochoric: any history
    assert_matches_reference(strain, plastic, E_value, nu, sigma_y)


def test_vectorised_batch_agrees_with_scalar_reference():
    rng = np.random.default_rng(1)
    strain, plastic_old = random_points(rng, 60)
    strain, plastic_old = strain.reshape(20, 3, 4), plastic_old.reshape(20, 3, 4)
    plastic = yielded_points(radial_return(strain, plastic_old, E, NU, SIGMA_Y)[2])
    assert 0 < plastic.sum() < plastic.size  # a mixed batch, both branches in one call
    assert_matches_reference(strain, plastic_old, E, NU, SIGMA_Y)


# ------------------------------------------------------------------------------------------
# elastic branch
# ------------------------------------------------------------------------------------------
def test_elastic_below_yield_returns_elastic_stress_and_moduli():
    rng = np.random.default_rng(2)
    strain, plastic_old = random_points(rng, 200)
    # Scale the elastic strain so that every point lies strictly inside the yield surface.
    q_trial = trial_von_mises(strain, plastic_old)
    factor = rng.uniform(0.0, 0.99, q_trial.shape) * SIGMA_Y / q_trial
    strain = plastic_old + factor[..., None] * (strain - plastic_old)
    stress, tangent, increment = radial_return(strain, plastic_old, E, NU, SIGMA_Y)
    # Hooke's law in tensor form, sigma = lambda tr(e) 1 + 2 mu e, e = eps - eps_p, written in
    # plain stress components (independent of D); the shear e_rz is half the engineering gamma_rz
    lam = E * NU / ((1 + NU) * (1 - 2 * NU))
    e = strain - plastic_old
    trace = e[..., 0] + e[..., 1] + e[..., 2]
    expected = np.stack([lam * trace + 2 * MU * e[..., 0], lam * trace + 2 * MU * e[..., 1],
                         lam * trace + 2 * MU * e[..., 2], 2 * MU * (0.5 * e[..., 3])], axis=-1)
    np.testing.assert_allclose(stress, expected, rtol=0, atol=4e-16 * np.abs(expected).max())
    D = elastic_matrix(E, NU)
    assert np.array_equal(tangent, np.broadcast_to(D, tangent.shape))  # bit for bit
    assert np.array_equal(increment, np.zeros_like(increment))
    assert not yielded_points(increment).any()
    assert (von_mises_stress(stress) < SIGMA_Y).all()


def test_elastic_matrix_is_the_contract_D():
    lam = E * NU / ((1 + NU) * (1 - 2 * NU))
    D = elastic_matrix(E, NU)
    np.testing.assert_allclose(D[:3, :3], lam + 2 * MU * np.eye(3), rtol=1e-15)
    assert D[3, 3] == pytest.approx(MU, rel=1e-15)
    assert not D[3, :3].any() and not D[:3, 3].any()


def test_zero_strain_gives_zero_stress_and_no_nan():
    zeros = np.zeros((3, 2, 4))
    stress, tangent, increment = radial_return(zeros, zeros, E, NU, SIGMA_Y)
    assert not stress.any() and not increment.any()
    assert np.isfinite(tangent).all()
    assert np.array_equal(tangent[1, 1], elastic_matrix(E, NU))


def test_pure_pressure_never_yields():
    strain = np.full((1, 1, 4), -50 * YIELD_STRAIN)
    strain[..., 3] = 0.0
    stress, tangent, increment = radial_return(strain, np.zeros_like(strain), E, NU, SIGMA_Y)
    np.testing.assert_allclose(stress[0, 0, :3], 3 * K * strain[0, 0, 0], rtol=1e-14)
    assert not increment.any()


# ------------------------------------------------------------------------------------------
# plastic branch: closed forms
# ------------------------------------------------------------------------------------------
def test_plastic_points_return_exactly_to_the_yield_surface():
    rng = np.random.default_rng(3)
    strain, plastic_old = random_points(rng, 2000, strain_scale=50.0)
    stress, _, increment = radial_return(strain, plastic_old, E, NU, SIGMA_Y)
    plastic = yielded_points(increment)
    assert plastic.sum() > 1000
    np.testing.assert_allclose(von_mises_stress(stress)[plastic], SIGMA_Y, rtol=1e-12)
    # Plastic flow is isochoric and the equivalent increment is (q_trial - sigma_y) / (3 mu).
    trace = increment[..., 0] + increment[..., 1] + increment[..., 2]
    assert (np.abs(trace) <= 1e-14 * np.abs(increment).max(-1)).all()
    q_trial = trial_von_mises(strain, plastic_old)
    np.testing.assert_allclose(equivalent_plastic_strain_increment(increment)[plastic],
                               (q_trial[plastic] - SIGMA_Y) / (3 * MU), rtol=1e-12)
    # Pressure is unaffected by the return (the flow is deviatoric).
    np.testing.assert_allclose(stress[..., :3].sum(-1),
                               3 * K * (strain - plastic_old)[..., :3].sum(-1),
                               rtol=0, atol=1e-12 * np.abs(stress).max())


def solve_uniaxial(material, strain_zz, state, guess, tolerance=1e-13, max_iterations=25):
    """Mixed control: eps_zz prescribed, (eps_rr, eps_tt, gamma_rz) solved so that
    s_rr = s_tt = s_rz = 0, by Newton with the consistent tangent. Returns strain, stress,
    trial state and the history of iterates."""
    unknowns = np.array(guess, dtype=float)
    iterates = [unknowns.copy()]
    for _ in range(max_iterations):
        strain = np.empty((1, 1, 4))
        strain[0, 0, LATERAL] = unknowns
        strain[0, 0, 1] = strain_zz
        stress, tangent, trial_state = material.update(strain, state)
        residual = stress[0, 0, LATERAL]
        if np.abs(residual).max() <= tolerance * material.sigma_y:
            return strain, stress, trial_state, iterates
        jacobian = tangent[0, 0][np.ix_(LATERAL, LATERAL)]
        unknowns = unknowns - np.linalg.solve(jacobian, residual)
        iterates.append(unknowns.copy())
    raise AssertionError("mixed-control Newton did not converge")


def test_uniaxial_stress_path_plateaus_at_yield_and_unloads_elastically():
    material = VonMisesMaterial(E, NU, SIGMA_Y)
    state = material.initial_state(1, 1)
    loading = np.linspace(0.0, 4.0, 41)[1:] * YIELD_STRAIN
    # Unload by 1.9 eps_y: down to -0.9 sigma_y, short of reversed yield at -sigma_y.
    unloading = 4.0 * YIELD_STRAIN - np.linspace(0.0, 1.9, 20)[1:] * YIELD_STRAIN
    guess = np.zeros(3)
    for step, strain_zz in enumerate(np.concatenate([loading, unloading])):
        strain, stress, state, _ = solve_uniaxial(material, strain_zz, state, guess)
        guess = strain[0, 0, LATERAL]
        plastic_zz = state.plastic_strain[0, 0, 1]
        if step < len(loading):
            # s_zz = E eps_zz until yield, then exactly sigma_y.
            assert stress[0, 0, 1] == pytest.approx(min(E * strain_zz, SIGMA_Y), rel=1e-12)
            assert plastic_zz == pytest.approx(max(strain_zz - YIELD_STRAIN, 0.0),
                                               rel=1e-11, abs=1e-14 * YIELD_STRAIN)
        else:
            # Elastic unloading along slope E from (4 eps_y, sigma_y); plastic strain frozen.
            assert stress[0, 0, 1] == pytest.approx(SIGMA_Y - E * (4 * YIELD_STRAIN - strain_zz),
                                                    rel=1e-11, abs=1e-12 * SIGMA_Y)
            assert plastic_zz == pytest.approx(3 * YIELD_STRAIN, rel=1e-11)
        plastic_strain = state.plastic_strain[0, 0]
        assert abs(plastic_strain[:3].sum()) <= 1e-14 * YIELD_STRAIN  # isochoric flow
        np.testing.assert_allclose(plastic_strain[[0, 2]], -0.5 * plastic_zz,
                                   atol=1e-14 * YIELD_STRAIN)
        # Lateral strain closed form: -nu s_zz / E - eps_p_zz / 2.
        np.testing.assert_allclose(strain[0, 0, [0, 2]], -NU * stress[0, 0, 1] / E - plastic_zz / 2,
                                   rtol=1e-11)
    assert state.equivalent_plastic_strain[0, 0] == pytest.approx(3 * YIELD_STRAIN, rel=1e-11)


def test_pure_shear_path_plateaus_at_shear_yield_stress():
    material = VonMisesMaterial(E, NU, SIGMA_Y)
    state = material.initial_state(1, 1)
    shear_yield_stress = SIGMA_Y / math.sqrt(3)
    shear_yield_strain = shear_yield_stress / MU
    path = np.concatenate([np.linspace(0, 5, 51)[1:], 5 - np.linspace(0, 10, 101)[1:]])
    stresses = []
    for gamma in path * shear_yield_strain:
        strain = np.array([0.0, 0.0, 0.0, gamma]).reshape(1, 1, 4)
        stress, _, state = material.update(strain, state)
        assert not stress[0, 0, :3].any()  # no normal stress from pure shear, exactly
        assert not state.plastic_strain[0, 0, :3].any()
        stresses.append(stress[0, 0, 3])
    stresses = np.array(stresses)
    loading = path[:50]
    np.testing.assert_allclose(stresses[:50], np.minimum(loading, 1.0) * shear_yield_stress,
                               rtol=1e-12)
    # Reversed: elastic from +tau_y down to -tau_y (gamma from 5 to 3), then the -tau_y plateau.
    reversed_path = path[50:]
    expected = np.maximum(shear_yield_stress - MU * (5 - reversed_path) * shear_yield_strain,
                          -shear_yield_stress)
    np.testing.assert_allclose(stresses[50:], expected, rtol=1e-12, atol=1e-12 * SIGMA_Y)
    # Plastic shear strain: +4 gamma_y on loading, then back 8 gamma_y on reversal.
    assert state.plastic_strain[0, 0, 3] == pytest.approx(-4 * shear_yield_strain, rel=1e-12)
    # Equivalent plastic strain of pure shear: gamma_p / sqrt(3), accumulated over 4 + 8 gamma_y.
    assert state.equivalent_plastic_strain[0, 0] == pytest.approx(
        12 * shear_yield_strain / math.sqrt(3), rel=1e-12)


def test_one_big_step_is_exact_for_a_proportional_path():
    rng = np.random.default_rng(4)
    n_directions = 50
    direction = rng.normal(size=(n_directions, 1, 4))
    final_strain = 20 * YIELD_STRAIN * direction / np.linalg.norm(direction, axis=-1, keepdims=True)
    # Exact solution: pressure K tr(eps); deviator along dev(eps) with |s| = sqrt(2/3) sigma_y.
    deviatoric_tensor = final_strain.copy()
    deviatoric_tensor[..., :3] -= final_strain[..., :3].mean(-1, keepdims=True)
    deviatoric_tensor[..., 3] *= 0.5  # tensor component eps_rz
    norm = np.sqrt((deviatoric_tensor[..., :3] ** 2).sum(-1) + 2 * deviatoric_tensor[..., 3] ** 2)
    assert (2 * MU * norm > math.sqrt(2 / 3) * SIGMA_Y).all()  # all end plastic
    unit = deviatoric_tensor / norm[..., None]
    exact_stress = math.sqrt(2 / 3) * SIGMA_Y * unit
    exact_stress[..., :3] += K * final_strain[..., :3].sum(-1, keepdims=True)
    exact_plastic = (norm - math.sqrt(2 / 3) * SIGMA_Y / (2 * MU))[..., None] * unit
    exact_plastic[..., 3] *= 2  # engineering shear

    stress, _, increment = radial_return(final_strain, np.zeros_like(final_strain), E, NU, SIGMA_Y)
    np.testing.assert_allclose(stress, exact_stress, rtol=0, atol=1e-12 * np.abs(exact_stress).max())
    np.testing.assert_allclose(increment, exact_plastic, rtol=0, atol=1e-12 * 20 * YIELD_STRAIN)

    # Many small steps along the same ray reach the same state.
    material = VonMisesMaterial(E, NU, SIGMA_Y)
    state = material.initial_state(n_directions, 1)
    for fraction in np.linspace(0, 1, 201)[1:]:
        small_step_stress, _, state = material.update(fraction * final_strain, state)
    np.testing.assert_allclose(small_step_stress, exact_stress, rtol=0,
                               atol=1e-12 * np.abs(exact_stress).max())
    np.testing.assert_allclose(state.plastic_strain, exact_plastic, rtol=0,
                               atol=1e-12 * 20 * YIELD_STRAIN)


# ------------------------------------------------------------------------------------------
# consistent tangent
# ------------------------------------------------------------------------------------------
@pytest.mark.parametrize("nu", [0.0, 0.3, 0.49])
def test_consistent_tangent_matches_central_differences(nu):
    rng = np.random.default_rng(5)
    yield_strain = SIGMA_Y / E
    n_points = 400
    strain, plastic_old = random_points(rng, n_points)
    # Half the points inside, half outside the yield surface, none within 2 % of it, so the
    # central differences straddle no kink.
    target_ratio = np.where(np.arange(n_points) < n_points // 2,
                            rng.uniform(0.05, 0.98, n_points), rng.uniform(1.02, 6.0, n_points))
    q_trial = trial_von_mises(strain, plastic_old, E, nu)[:, 0]
    elastic_part = (strain - plastic_old) * (target_ratio * SIGMA_Y / q_trial)[:, None, None]
    strain = plastic_old + elastic_part
    stress, tangent, increment = radial_return(strain, plastic_old, E, nu, SIGMA_Y)
    plastic = yielded_points(increment)[:, 0]
    assert plastic.sum() == n_points // 2

    step = 1e-6 * yield_strain
    perturbations = step * np.concatenate([np.eye(4), -np.eye(4)])  # (8, 4)
    perturbed = strain + perturbations[None]  # (n, 8, 4): one "quadrature point" per perturbation
    perturbed_stress, _, _ = radial_return(perturbed, np.repeat(plastic_old, 8, axis=1),
                                           E, nu, SIGMA_Y)
    # column j of the tangent = (stress(e + h u_j) - stress(e - h u_j)) / 2h
    fd_tangent = ((perturbed_stress[:, :4] - perturbed_stress[:, 4:]) / (2 * step)).transpose(0, 2, 1)
    error = np.linalg.norm(fd_tangent - tangent[:, 0], axis=(1, 2)) \
        / np.linalg.norm(tangent[:, 0], axis=(1, 2))
    assert error.max() < 1e-6, f"max relative FD error {error.max():.2e}"
    # Independently of the FD check: the plastic tangent is symmetric and annihilates the
    # flow direction (engineering-shear form), as a perfectly plastic tangent must.
    plastic_tangent = tangent[plastic, 0]
    np.testing.assert_allclose(plastic_tangent, plastic_tangent.transpose(0, 2, 1),
                               rtol=0, atol=1e-12 * E)
    flow = increment[plastic, 0] / np.linalg.norm(increment[plastic, 0], axis=-1, keepdims=True)
    assert np.abs(np.einsum("pij,pj->pi", plastic_tangent, flow)).max() < 1e-9 * E


def test_newton_with_consistent_tangent_converges_quadratically():
    """Uniaxial stress after a shear pre-strain: one large step, non-proportional, so the flow
    direction changes from iterate to iterate (a linear problem would converge in one step)."""
    material = VonMisesMaterial(E, NU, SIGMA_Y)
    plastic_old = np.array([0.4, -1.0, 0.6, 2.5]) * YIELD_STRAIN
    state = PlasticState(plastic_strain=plastic_old.reshape(1, 1, 4),
                         equivalent_plastic_strain=np.zeros((1, 1)))
    strain_zz = plastic_old[1] + 6.0 * YIELD_STRAIN
    # Exact solution: s = sigma_y e_zz; eps = eps_p_old + D^-1 s + c [-1/2, 1, -1/2, 0].
    flow_zz = strain_zz - plastic_old[1] - YIELD_STRAIN
    exact = np.array([plastic_old[0] - NU * YIELD_STRAIN - flow_zz / 2,
                      plastic_old[2] - NU * YIELD_STRAIN - flow_zz / 2,
                      plastic_old[3]])
    _, stress, _, iterates = solve_uniaxial(material, strain_zz, state, guess=np.zeros(3),
                                            tolerance=1e-15)
    assert stress[0, 0, 1] == pytest.approx(SIGMA_Y, rel=1e-12)
    errors = np.array([np.abs(x - exact).max() / YIELD_STRAIN for x in iterates])
    assert errors[-1] < 1e-12
    assert len(iterates) <= 8
    # Quadratic: e_{k+1} <= C e_k^2 while the error is above round-off.
    ratios = [errors[k + 1] / errors[k] ** 2 for k in range(len(errors) - 1)
              if errors[k + 1] > 1e-13]
    assert len(ratios) >= 2
    assert max(ratios) < 10.0, f"errors {errors}"


# ------------------------------------------------------------------------------------------
# symmetry, interface, validation
# ------------------------------------------------------------------------------------------
def test_swapping_rr_and_tt_swaps_the_result():
    rng = np.random.default_rng(6)
    strain, plastic_old = random_points(rng, 300)
    swap = [2, 1, 0, 3]
    stress, tangent, increment = radial_return(strain, plastic_old, E, NU, SIGMA_Y)
    s_stress, s_tangent, s_increment = radial_return(strain[..., swap], plastic_old[..., swap],
                                                     E, NU, SIGMA_Y)
    np.testing.assert_allclose(s_stress, stress[..., swap], rtol=0, atol=1e-13 * np.abs(stress).max())
    np.testing.assert_allclose(s_tangent, tangent[..., swap, :][..., swap], rtol=0, atol=1e-13 * E)
    np.testing.assert_allclose(s_increment, increment[..., swap], rtol=0,
                               atol=1e-13 * np.abs(increment).max())


def test_von_mises_stress_of_simple_states():
    stresses = np.array([[0.0, 7.0, 0.0, 0.0],     # uniaxial
                         [3.0, 3.0, 3.0, 0.0],     # hydrostatic
                         [0.0, 0.0, 0.0, 2.0]])    # pure shear: q = sqrt(3) tau
    np.testing.assert_allclose(von_mises_stress(stresses), [7.0, 0.0, 2 * math.sqrt(3)],
                               atol=1e-15)
    # Pure shear gamma_p: equivalent plastic strain gamma_p / sqrt(3).
    assert equivalent_plastic_strain_increment([0.0, 0.0, 0.0, 3.0]) == pytest.approx(math.sqrt(3))
    assert equivalent_plastic_strain_increment([-0.5, 1.0, -0.5, 0.0]) == pytest.approx(1.0)


def test_material_interface_is_pure_and_commits_nothing():
    material = VonMisesMaterial(E, NU, SIGMA_Y)
    assert material.is_linear is False
    assert np.array_equal(material.elastic_tangent(), elastic_matrix(E, NU))
    assert material.shear_modulus == pytest.approx(MU) and material.bulk_modulus == pytest.approx(K)
    state = material.initial_state(4, 3)
    assert state.plastic_strain.shape == (4, 3, 4) and state.equivalent_plastic_strain.shape == (4, 3)
    rng = np.random.default_rng(7)
    strain = rng.uniform(-1.5, 1.5, (4, 3, 4)) * YIELD_STRAIN
    strain_copy = strain.copy()
    stress, tangent, trial = material.update(strain, state)
    assert np.array_equal(strain, strain_copy)
    assert not state.plastic_strain.any() and not state.equivalent_plastic_strain.any()
    assert stress.shape == (4, 3, 4) and tangent.shape == (4, 3, 4, 4)
    for array in (stress, tangent, trial.plastic_strain, trial.equivalent_plastic_strain):
        assert array.dtype == np.float64 and array.flags.c_contiguous
    yielded = material.yielded(state, trial)
    assert yielded.any() and not yielded.all()
    assert (trial.equivalent_plastic_strain[yielded] > 0).all()
    assert not trial.equivalent_plastic_strain[~yielded].any()
    # Same strain, committed state: nothing further yields (the point sits on the surface).
    _, _, again = material.update(strain, trial)
    assert not material.yielded(trial, again).any()
    with pytest.raises(dataclasses.FrozenInstanceError):
        material.sigma_y = 1.0
    with pytest.raises(dataclasses.FrozenInstanceError):
        trial.plastic_strain = None


@pytest.mark.parametrize("kwargs, name", [
    ({"E": 0.0}, "E"), ({"E": -1.0}, "E"), ({"E": math.inf}, "E"),
    ({"nu": 0.5}, "nu"), ({"nu": -0.1}, "nu"), ({"nu": math.nan}, "nu"),
    ({"sigma_y": 0.0}, "sigma_y"), ({"sigma_y": -5.0}, "sigma_y"), ({"sigma_y": "1e8"}, "sigma_y"),
])
def test_bad_parameters_raise_value_error_naming_them(kwargs, name):
    params = {"E": E, "nu": NU, "sigma_y": SIGMA_Y, **kwargs}
    with pytest.raises(ValueError, match=rf"^{name}\b"):
        VonMisesMaterial(**params)
    zeros = np.zeros((1, 1, 4))
    with pytest.raises(ValueError, match=rf"^{name}\b"):
        radial_return(zeros, zeros, params["E"], params["nu"], params["sigma_y"])


def test_bad_arrays_raise_value_error_naming_them():
    good = np.zeros((2, 3, 4))
    with pytest.raises(ValueError, match="strain_total"):
        radial_return(np.zeros((2, 3, 3)), good, E, NU, SIGMA_Y)
    with pytest.raises(ValueError, match="strain_total"):
        radial_return(np.zeros((6, 4)), good, E, NU, SIGMA_Y)
    bad = good.copy()
    bad[1, 1, 1] = np.nan
    with pytest.raises(ValueError, match="strain_total"):
        radial_return(bad, good, E, NU, SIGMA_Y)
    with pytest.raises(ValueError, match="plastic_strain_old"):
        radial_return(good, np.zeros((2, 2, 4)), E, NU, SIGMA_Y)
    material = VonMisesMaterial(E, NU, SIGMA_Y)
    with pytest.raises(ValueError, match="state"):
        material.update(good, {"plastic_strain": good})
    with pytest.raises(ValueError, match="n_qp"):
        material.initial_state(3, 0)
    with pytest.raises(ValueError, match="n_elements"):
        material.initial_state(2.5, 3)
    with pytest.raises(ValueError, match="equivalent_plastic_strain"):
        PlasticState(plastic_strain=good, equivalent_plastic_strain=np.zeros(6))

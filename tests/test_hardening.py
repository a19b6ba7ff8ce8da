"""Von Mises plasticity with isotropic hardening (calib.fe.flow_curve, calib.fe.von_mises.return_mapping,
HardeningMaterial).

The return mapping against closed forms (uniaxial stress and pure shear with linear, Swift, Ludwik and
tabulated flow curves), the consistent tangent against central finite differences, H = 0 against the
perfectly plastic VonMisesMaterial, a very large H against elasticity, a table equal to a linear curve,
the plastic work against an independent quadrature of sigma : d eps_p, bad flow-curve files refused in
one line; and the FE press of a hardening sphere against the perfectly plastic one on the coarse mesh.
"""
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from calib.fe import ContactSolver, LoadPathPlan, VonMisesMaterial, run_load_paths
from calib.fe.flow_curve import (LinearHardening, LudwikHardening, SwiftHardening, TabulatedFlowCurve,
                                 read_flow_curve)
from calib.fe.material import elastic_matrix
from calib.fe.von_mises import HardeningMaterial, return_mapping, yielded_points

from conftest import PAIR

E, NU, SIGMA_Y = 70e9, 0.3, 100e6            # aluminium, as tests/test_plasticity.py
YIELD_STRAIN = SIGMA_Y / E
MU = E / (2 * (1 + NU))
LATERAL = [0, 2, 3]                          # rr, tt, rz: stress-free in a uniaxial test along z
H_LINEAR = 0.05 * E                          # 3.5 GPa: an aluminium alloy's order of magnitude

CURVES = {
    "linear": LinearHardening(SIGMA_Y, H_LINEAR),
    "swift": SwiftHardening(SIGMA_Y, 4.0 * SIGMA_Y, 0.25),
    "ludwik": LudwikHardening(SIGMA_Y, 3.0 * SIGMA_Y, 0.4),
    "table": TabulatedFlowCurve([0.0, 0.002, 0.01, 0.05], [SIGMA_Y, 1.1 * SIGMA_Y, 1.3 * SIGMA_Y, 1.5 * SIGMA_Y],
                                extrapolation="slope"),
}


def uniaxial_strain_of_stress(curve, stress):
    """eps_zz = sigma / E + eps_p(sigma) of a uniaxial test: the closed form written from the curve's
    definition (eps_p the inverse of sigma_y, 0 below sigma_Y), not from its methods."""
    if stress <= SIGMA_Y:
        return stress / E
    if isinstance(curve, LinearHardening):
        plastic = (stress - SIGMA_Y) / curve.H
    elif isinstance(curve, SwiftHardening):
        plastic = (stress / curve.K) ** (1 / curve.n) - (SIGMA_Y / curve.K) ** (1 / curve.n)
    elif isinstance(curve, LudwikHardening):
        plastic = ((stress - SIGMA_Y) / curve.K) ** (1 / curve.n)
    else:   # the table, inverted segment by segment (np.interp of stress -> strain), slope beyond
        strain, table_stress = curve.strain, curve.stress
        if stress <= table_stress[-1]:
            plastic = float(np.interp(stress, table_stress, strain))
        else:
            slope = (table_stress[-1] - table_stress[-2]) / (strain[-1] - strain[-2])
            plastic = strain[-1] + (stress - table_stress[-1]) / slope
    return stress / E + plastic


def solve_uniaxial(material, strain_zz, state, guess, tolerance=1e-13):
    """eps_zz prescribed, (eps_rr, eps_tt, gamma_rz) by Newton with the consistent tangent so that
    s_rr = s_tt = s_rz = 0; (strain, stress, trial state)."""
    unknowns = np.array(guess, dtype=float)
    for _ in range(30):
        strain = np.empty((1, 1, 4))
        strain[0, 0, LATERAL] = unknowns
        strain[0, 0, 1] = strain_zz
        stress, tangent, trial = material.update(strain, state)
        residual = stress[0, 0, LATERAL]
        if np.abs(residual).max() <= tolerance * SIGMA_Y:
            return strain, stress, trial
        unknowns = unknowns - np.linalg.solve(tangent[0, 0][np.ix_(LATERAL, LATERAL)], residual)
    raise AssertionError("mixed-control Newton did not converge")


@pytest.mark.parametrize("name", sorted(CURVES))
def test_uniaxial_stress_follows_the_closed_form(name):
    """sigma_zz(eps_zz) to 20 eps_y (eps_p to 1.4 %) against eps = sigma / E + eps_p(sigma); then elastic
    unloading with slope E, and the equivalent plastic strain equal to the axial plastic strain."""
    curve = CURVES[name]
    material = HardeningMaterial(E, NU, curve)
    state, guess = material.initial_state(1, 1), np.zeros(3)
    errors = []
    for strain_zz in np.linspace(0.0, 20.0, 81)[1:] * YIELD_STRAIN:
        strain, stress, state = solve_uniaxial(material, strain_zz, state, guess)
        guess = strain[0, 0, LATERAL]
        exact = brentq(lambda s: uniaxial_strain_of_stress(curve, s) - strain_zz, 0.0, 10 * SIGMA_Y, xtol=1e-14,
                       rtol=1e-15)
        errors.append(abs(stress[0, 0, 1] - exact) / exact)
        assert state.equivalent_plastic_strain[0, 0] == pytest.approx(
            state.plastic_strain[0, 0, 1], rel=1e-10, abs=1e-15)
    assert max(errors) < 1e-11, f"{name}: max relative error {max(errors):.2e}"
    peak_stress, peak_strain = stress[0, 0, 1], 20 * YIELD_STRAIN
    assert peak_stress > 1.05 * SIGMA_Y                                     # it hardened
    _, stress, after = solve_uniaxial(material, peak_strain - YIELD_STRAIN, state, guess)
    assert stress[0, 0, 1] == pytest.approx(peak_stress - SIGMA_Y, rel=1e-11)   # elastic unloading
    np.testing.assert_array_equal(after.plastic_strain, state.plastic_strain)


@pytest.mark.parametrize("name", sorted(CURVES))
def test_pure_shear_follows_the_closed_form(name):
    """gamma_rz alone: tau = sigma_y(eps_bar) / sqrt(3) with eps_bar = (gamma - tau / mu) / sqrt(3), and no
    normal stress at all."""
    curve = CURVES[name]
    material = HardeningMaterial(E, NU, curve)
    state = material.initial_state(1, 1)
    shear_yield_strain = SIGMA_Y / math.sqrt(3) / MU
    errors = []
    for gamma in np.linspace(0.0, 30.0, 61)[1:] * shear_yield_strain:
        stress, _, state = material.update(np.array([0.0, 0.0, 0.0, gamma]).reshape(1, 1, 4), state)
        assert not stress[0, 0, :3].any()

        def equilibrium(tau):   # eps_bar from the strain less eps_bar(sigma_y = sqrt(3) tau) of the curve
            return (gamma - tau / MU) / math.sqrt(3) - (uniaxial_strain_of_stress(curve, math.sqrt(3) * tau)
                                                        - math.sqrt(3) * tau / E)

        exact = MU * gamma if gamma <= shear_yield_strain else brentq(
            equilibrium, SIGMA_Y / math.sqrt(3), MU * gamma, xtol=1e-14, rtol=1e-15)
        errors.append(abs(stress[0, 0, 3] - exact) / exact)
    assert max(errors) < 1e-11, f"{name}: max relative error {max(errors):.2e}"


@pytest.mark.parametrize("name", sorted(CURVES))
def test_consistent_tangent_matches_central_differences(name):
    """C = K 1(x)1 + 2 mu theta I_dev - 2 mu theta_bar n(x)n against central differences of the stress,
    at random points with random committed plastic strain and eps_bar (half elastic, half plastic)."""
    curve = CURVES[name]
    rng = np.random.default_rng(11)
    n = 400
    plastic_old = rng.uniform(-3, 3, (n, 1, 4)) * YIELD_STRAIN
    plastic_old[..., 2] = -plastic_old[..., 0] - plastic_old[..., 1]
    equivalent_old = rng.uniform(0.0, 0.03, (n, 1))
    direction = rng.normal(size=(n, 1, 4))
    ratio = np.where(np.arange(n) < n // 2, rng.uniform(0.1, 0.98, n), rng.uniform(1.02, 4.0, n))
    trial = direction @ elastic_matrix(E, NU)
    mean = trial[..., :3].mean(-1, keepdims=True)
    dev = np.concatenate([trial[..., :3] - mean, trial[..., 3:]], axis=-1)
    q = np.sqrt(1.5 * ((dev[..., :3] ** 2).sum(-1) + 2 * dev[..., 3] ** 2))
    scale = ratio[:, None] * curve.yield_stress(equivalent_old) / q
    strain = plastic_old + direction * scale[..., None]
    stress, tangent, increment = return_mapping(strain, plastic_old, equivalent_old, E, NU, curve)
    assert yielded_points(increment).sum() == n // 2
    step = 1e-7 * YIELD_STRAIN
    perturbations = step * np.concatenate([np.eye(4), -np.eye(4)])
    perturbed = return_mapping(strain + perturbations[None], np.repeat(plastic_old, 8, axis=1),
                               np.repeat(equivalent_old, 8, axis=1), E, NU, curve)[0]
    fd = ((perturbed[:, :4] - perturbed[:, 4:]) / (2 * step)).transpose(0, 2, 1)
    error = np.linalg.norm(fd - tangent[:, 0], axis=(1, 2)) / np.linalg.norm(tangent[:, 0], axis=(1, 2))
    assert error.max() < 1e-6, f"{name}: max relative FD error {error.max():.2e}"
    np.testing.assert_allclose(tangent, tangent.transpose(0, 1, 3, 2), rtol=0, atol=1e-12 * E)


def random_sequence(rng, n=300, steps=6):
    """Strain increments of a non-proportional path through the yield surface, (steps, n, 1, 4)."""
    return np.cumsum(rng.uniform(-2.5, 2.5, (steps, n, 1, 4)) * YIELD_STRAIN, axis=0)


def run_sequence(material, strains):
    state = material.initial_state(*strains.shape[1:3])
    out = []
    for strain in strains:
        stress, tangent, state = material.update(strain, state)
        out.append((stress, tangent, state.plastic_strain, state.equivalent_plastic_strain))
    return out, state


def test_zero_hardening_is_the_perfectly_plastic_material_bit_for_bit():
    strains = random_sequence(np.random.default_rng(12))
    reference, reference_state = run_sequence(VonMisesMaterial(E, NU, SIGMA_Y), strains)
    hardening, state = run_sequence(HardeningMaterial(E, NU, LinearHardening(SIGMA_Y, 0.0)), strains)
    for a, b in zip(reference, hardening):
        for x, y in zip(a, b):
            np.testing.assert_array_equal(x, y)
    weight = np.random.default_rng(1).uniform(1e-9, 2e-9, strains.shape[1:3])
    material = HardeningMaterial(E, NU, LinearHardening(SIGMA_Y, 0.0))
    assert material.dissipated_work(state, weight) == VonMisesMaterial(E, NU, SIGMA_Y).dissipated_work(
        reference_state, weight)


@pytest.mark.parametrize("curve", [LudwikHardening(SIGMA_Y, 0.0, 0.5),
                                   TabulatedFlowCurve([0.0, 1.0], [SIGMA_Y, SIGMA_Y], source="flat")],
                         ids=["ludwik-K0", "flat-table"])
def test_zero_hardening_through_the_newton_iteration_is_perfect_plasticity(curve):
    """A nonlinear curve's Newton path with sigma_y = sigma_Y gives the perfectly plastic figures to 1e-12."""
    strains = random_sequence(np.random.default_rng(13))
    reference, _ = run_sequence(VonMisesMaterial(E, NU, SIGMA_Y), strains)
    other, _ = run_sequence(HardeningMaterial(E, NU, curve), strains)
    for a, b in zip(reference, other):
        np.testing.assert_allclose(b[0], a[0], rtol=0, atol=1e-12 * SIGMA_Y)
        np.testing.assert_allclose(b[1], a[1], rtol=0, atol=1e-12 * E)
        np.testing.assert_allclose(b[2], a[2], rtol=0, atol=1e-12 * YIELD_STRAIN)


def test_very_large_hardening_approaches_elasticity():
    """|sigma - D eps| / |D eps| <= 3 mu / H (the return's 3 mu dgamma, dgamma = f / (3 mu + H))."""
    rng = np.random.default_rng(14)
    strain = rng.uniform(-10, 10, (200, 1, 4)) * YIELD_STRAIN
    elastic = strain @ elastic_matrix(E, NU)
    previous = None
    for ratio in (1e2, 1e4, 1e6):
        material = HardeningMaterial(E, NU, LinearHardening(SIGMA_Y, ratio * E))
        stress, tangent, _ = material.update(strain, material.initial_state(200, 1))
        error = np.abs(stress - elastic).max() / np.abs(elastic).max()
        assert error <= 3 * MU / (ratio * E)
        assert np.abs(tangent - elastic_matrix(E, NU)).max() <= 3 * MU / (ratio * E) * 2 * MU * 2
        assert previous is None or error < previous / 50
        previous = error


def test_table_equal_to_a_linear_curve_gives_its_results():
    linear = LinearHardening(SIGMA_Y, H_LINEAR)
    knots = np.array([0.0, 0.001, 0.004, 0.01])
    table = TabulatedFlowCurve(knots, SIGMA_Y + H_LINEAR * knots, extrapolation="slope")
    strains = random_sequence(np.random.default_rng(15), steps=10)
    a, state_a = run_sequence(HardeningMaterial(E, NU, linear), strains)
    b, state_b = run_sequence(HardeningMaterial(E, NU, table), strains)
    assert state_a.equivalent_plastic_strain.max() > knots[-1]            # the extrapolation is used
    for x, y in zip(a, b):
        np.testing.assert_allclose(y[0], x[0], rtol=0, atol=1e-12 * SIGMA_Y)
        np.testing.assert_allclose(y[1], x[1], rtol=0, atol=1e-12 * E)
        np.testing.assert_allclose(y[3], x[3], rtol=1e-12, atol=1e-18)
    weight = np.full(strains.shape[1:3], 1e-9)
    assert HardeningMaterial(E, NU, table).dissipated_work(state_b, weight) == pytest.approx(
        HardeningMaterial(E, NU, linear).dissipated_work(state_a, weight), rel=1e-12)
    flat = TabulatedFlowCurve(knots, SIGMA_Y + H_LINEAR * knots, extrapolation="flat")
    assert flat.yield_stress(0.02) == pytest.approx(SIGMA_Y + H_LINEAR * 0.01)
    assert table.yield_stress(0.02) == pytest.approx(SIGMA_Y + H_LINEAR * 0.02)


@pytest.mark.parametrize("name", sorted(CURVES))
def test_plastic_work_is_the_integral_of_stress_on_plastic_strain(name):
    """dissipated_work against the trapezoidal sum of sigma : d eps_p along a uniaxial path in 400 steps."""
    material = HardeningMaterial(E, NU, CURVES[name])
    state, guess = material.initial_state(1, 1), np.zeros(3)
    work, previous_stress, previous_plastic = 0.0, np.zeros(4), np.zeros(4)
    for strain_zz in np.linspace(0.0, 40.0, 401)[1:] * YIELD_STRAIN:
        strain, stress, state = solve_uniaxial(material, strain_zz, state, guess)
        guess = strain[0, 0, LATERAL]
        d_plastic = state.plastic_strain[0, 0] - previous_plastic
        weights = np.array([1.0, 1.0, 1.0, 1.0])          # plain stress . engineering strain
        work += 0.5 * float((stress[0, 0] + previous_stress) @ (weights * d_plastic))
        previous_stress, previous_plastic = stress[0, 0], state.plastic_strain[0, 0].copy()
    assert material.dissipated_work(state, np.ones((1, 1))) == pytest.approx(work, rel=1e-4)


BAD_TABLES = {
    "not monotone": ("plastic_strain,stress\n0,1e8\n0.01,1.2e8\n0.02,1.1e8\n", "column stress"),
    "not from zero": ("plastic_strain,stress\n0.001,1e8\n0.01,1.2e8\n", "column plastic_strain"),
    "negative strain": ("plastic_strain,stress\n-0.01,1e8\n0,1e8\n0.01,1.2e8\n", "column plastic_strain"),
    "strain repeated": ("plastic_strain,stress\n0,1e8\n0.01,1.2e8\n0.01,1.3e8\n", "column plastic_strain"),
    "not sigma_Y": ("plastic_strain,stress\n0,1.2e8\n0.01,1.3e8\n", "column stress"),
    "wrong header": ("strain,stress\n0,1e8\n0.01,1.2e8\n", "header"),
    "not a number": ("plastic_strain,stress\n0,1e8\n0.01,abc\n", "column stress"),
    "one row": ("plastic_strain,stress\n0,1e8\n", "two rows"),
}


@pytest.mark.parametrize("case", sorted(BAD_TABLES))
def test_bad_flow_curves_are_refused_in_one_line_naming_file_and_column(tmp_path, case):
    text, named = BAD_TABLES[case]
    path = tmp_path / "curve.csv"
    path.write_text(text)
    with pytest.raises(ValueError) as error:
        read_flow_curve(path, sigma_y=SIGMA_Y)
    message = str(error.value)
    assert "\n" not in message and str(path) in message and named in message, message


def test_a_good_flow_curve_file_is_read(tmp_path):
    path = tmp_path / "copper.csv"
    path.write_text("plastic_strain,stress\n0,1e8\n0.01,1.5e8\n0.1,2e8\n")
    curve = read_flow_curve(path, extrapolation="slope", sigma_y=SIGMA_Y)
    assert curve.sigma_y == SIGMA_Y and curve.yield_stress(0.005) == pytest.approx(1.25e8)
    assert curve.record()["extrapolation"] == "slope"
    with pytest.raises(ValueError, match="flow_curve_extrapolation must be one of flat, slope"):
        read_flow_curve(path, extrapolation="linear")


@pytest.mark.parametrize("make, name", [
    (lambda: LinearHardening(SIGMA_Y, -1.0), "hardening_modulus"),
    (lambda: SwiftHardening(SIGMA_Y, 4e8, 1.5), "n"),
    (lambda: SwiftHardening(SIGMA_Y, -4e8, 0.2), "K"),
    (lambda: LudwikHardening(0.0, 4e8, 0.2), "sigma_y"),
    (lambda: HardeningMaterial(E, NU, "linear"), "flow_curve"),
])
def test_bad_parameters_are_refused_naming_them(make, name):
    with pytest.raises(ValueError, match=name):
        make()


# ------------------------------------------------------------------------------------------------
# the FE press of a hardening sphere
# ------------------------------------------------------------------------------------------------
PRESS_PLAN = LoadPathPlan(peaks=(20 * PAIR.P_Y,), loading_step=2 * PAIR.P_Y, first_load=0.9 * PAIR.P_Y,
                          unloading_steps=8)


@pytest.fixture(scope="module")
def presses(coarse_mesh):
    """The reference sphere (aluminium, R = 0.1 m) pressed to 20 P_Y on the coarse mesh, perfectly plastic,
    with linear hardening H = E / 20 and with Swift's curve (K = 4 sigma_Y, n = 0.25)."""
    out = {}
    for name, material in (("perfect", VonMisesMaterial(E, NU, SIGMA_Y)),
                           ("linear", HardeningMaterial(E, NU, CURVES["linear"])),
                           ("swift", HardeningMaterial(E, NU, CURVES["swift"]))):
        solver = ContactSolver(coarse_mesh, material)
        out[name] = run_load_paths(solver, PRESS_PLAN)
    return out


@pytest.mark.parametrize("name", ["linear", "swift"])
def test_hardening_sphere_is_stiffer_and_keeps_a_smaller_dent(presses, name):
    """Measured on this mesh: at a given approach the force is 0.3-1.6 % (linear) and 0.5-2.4 % (Swift)
    higher beyond 3 P_Y, the dent 7.8 % and 11.7 % smaller, e 0.823 and 0.831 against 0.808."""
    perfect, hardening = presses["perfect"], presses[name]
    alpha_p = np.array([r["alpha"] for r in perfect.loading_rows])
    force_p = np.array([r["P"] for r in perfect.loading_rows])
    alpha_h = np.array([r["alpha"] for r in hardening.loading_rows])
    force_h = np.array([r["P"] for r in hardening.loading_rows])
    np.testing.assert_allclose(force_h, force_p, rtol=1e-9)                  # the same force steps
    # at the first load (0.9 P_Y, a few points of the coarse mesh just flowing) the two barely differ
    np.testing.assert_allclose(alpha_h[0], alpha_p[0], rtol=1e-6)
    # beyond: the hardening sphere needs less approach for a force, so at a given approach its force is
    # higher (P(alpha) of the perfect sphere interpolated at the hardening sphere's approaches)
    plastic = force_p > 3 * PAIR.P_Y
    assert np.all(alpha_h[plastic] < alpha_p[plastic])
    force_at_alpha = np.interp(alpha_h[plastic], alpha_p, force_p)
    assert np.all(force_h[plastic] > force_at_alpha)
    dent_p, dent_h = perfect.paths[0].alpha_residual, hardening.paths[0].alpha_residual
    assert 0 < dent_h < dent_p
    eps_p = perfect.paths[0].peak_state.material_state.equivalent_plastic_strain
    eps_h = hardening.paths[0].peak_state.material_state.equivalent_plastic_strain
    assert np.isfinite(eps_h).all() and 0 < eps_h.max() < eps_p.max() < 0.1
    assert hardening.paths[0].restitution > perfect.paths[0].restitution


def test_hardening_sphere_impact_rebounds_faster_and_closes_its_energy_balance(mesh_cache):
    """The dynamic FE (coarse whole sphere, 0.04 m/s = 24 v_Y, 40 steps per contact): with H = E / 20 e is
    higher, P_max higher and the dent smaller than perfectly plastic (measured: e 0.764 / 0.744, P_max 1437 /
    1419 N, dent 6.12 / 6.62 um); the energy balance with the hardening plastic work closes as well as the
    perfectly plastic one's (residual 2.6e-4 / 7.1e-4 of the kinetic energy in)."""
    from calib.fe.impact import run_impact
    from calib.fe.newmark import ImpactSolver
    from meshes.sphere import SphereMeshSpec, sphere_mesh

    spec = SphereMeshSpec(radius=0.1, contact_size=1.6e-4, refined_radius=1.6e-3, refined_depth=5e-4, far_size=1e-2,
                          growth=0.3)
    mesh = sphere_mesh(spec, cache_dir=mesh_cache)
    records = {name: run_impact(ImpactSolver(mesh, material, 2699.0), 0.04, steps_per_contact=40).record()
               for name, material in (("perfect", VonMisesMaterial(E, NU, SIGMA_Y)),
                                      ("linear", HardeningMaterial(E, NU, CURVES["linear"])))}
    perfect, linear = records["perfect"], records["linear"]
    assert linear["e"] > perfect["e"] + 0.01
    assert linear["P_max"] > perfect["P_max"]
    assert 0 < linear["dent"] < 0.95 * perfect["dent"]
    for record in records.values():
        assert abs(record["balance_residual"]) < 1e-3 * record["kinetic_in"]
        assert abs(record["internal_work_error"]) < 0.02 * record["plastic_work"]


# ------------------------------------------------------------------------------------------------
# the commands: --hardening-modulus, --flow-curve, --flow-curve-extrapolation
# ------------------------------------------------------------------------------------------------
@pytest.fixture
def curve_files(tmp_path):
    files = {"GOOD": "plastic_strain,stress\n0,1e8\n0.01,1.5e8\n0.1,2e8\n",
             "FALLS": "plastic_strain,stress\n0,1e8\n0.01,1.5e8\n0.1,1.2e8\n",
             "OTHER_SY": "plastic_strain,stress\n0,2e8\n0.01,2.5e8\n"}
    for name, text in files.items():
        (tmp_path / f"{name}.csv").write_text(text)
    return tmp_path


CLI_REFUSALS = [
    (["--hardening-modulus", "-1e9"], "--hardening-modulus out of range"),
    (["--hardening-modulus", "1e12"], "--hardening-modulus out of range"),     # above E: a unit slip
    (["--hardening-modulus", "abc"], "--hardening-modulus"),
    (["--hardening-modulus", "1e9", "--flow-curve", "GOOD"], "give one of them"),
    (["--flow-curve-extrapolation", "slope"], "give the table too"),
    (["--flow-curve", "GOOD", "--flow-curve-extrapolation", "linear"], "must be one of flat, slope"),
    (["--flow-curve", "FALLS"], "FALLS.csv: column stress must be monotone"),
    (["--flow-curve", "OTHER_SY"], "give --sigma-y as the table's first stress"),
    (["--flow-curve", "MISSING"], "MISSING.csv: cannot read it"),
]


@pytest.mark.parametrize("command", ["calibrate", "impact"])
@pytest.mark.parametrize("flags, needle", CLI_REFUSALS, ids=[needle for _, needle in CLI_REFUSALS])
def test_hardening_flags_refused_in_one_line_exit_2(command, flags, needle, curve_files, capsys):
    from calib.cli import main

    flags = [str(curve_files / f"{f}.csv") if f in ("GOOD", "FALLS", "OTHER_SY", "MISSING") else f for f in flags]
    assert main([command, "--quiet", "--dry-run", *flags]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and needle in err, err


@pytest.mark.parametrize("command", ["calibrate", "impact"])
def test_zero_hardening_modulus_is_the_perfectly_plastic_run(command, capsys):
    """--hardening-modulus 0: the same plan (mesh keys, folder) as no flag, so every figure is the EPP one's."""
    from calib.cli import main

    assert main([command, "--quiet", "--dry-run", "--json"]) == 0
    plain = capsys.readouterr().out
    assert main([command, "--quiet", "--dry-run", "--json", "--hardening-modulus", "0"]) == 0
    assert capsys.readouterr().out == plain
    assert main([command, "--quiet", "--dry-run", "--hardening-modulus", "3.5e9"]) == 0
    out = capsys.readouterr().out
    assert "H3.5e+09" in out and "hardening" in out


def test_calibration_of_a_hardening_sphere_records_its_flow_curve(tmp_path, curve_files):
    """The library calibration on the coarse mesh with --flow-curve's table: the summary and the parameter
    file state the curve, nfdmodel reads the file, and an impact of the perfectly plastic sphere refuses it
    as --params (and the hardening one takes it)."""
    import dataclasses

    from calib import output
    from calib.cli import main
    from calib.fit import calibration, recipe
    from calib.report.calibration import write_calibration_parameters
    from conftest import COARSE
    from nfdmodel import load_parameters

    curve = read_flow_curve(curve_files / "GOOD.csv", extrapolation="slope", sigma_y=SIGMA_Y)
    spec = recipe.reference_spec(contact_size=COARSE.contact_size)
    spec = dataclasses.replace(spec, hardening=curve, plan=LoadPathPlan(peaks=(500.0, 1000.0), loading_step=250.0,
                                                                        unloading_steps=4, first_load=20.0))
    result = calibration.calibrate(spec, meshes=1)
    summary = calibration.summary(result)
    assert summary["hardening"] == curve.record()
    path = write_calibration_parameters(tmp_path / "parameters.json", result, output.stamp(0.0))
    load_parameters(path)
    with pytest.raises(ValueError, match="hardening"):
        dataclasses.replace(spec, hardening=LinearHardening(2 * SIGMA_Y, 1e9))
    assert main(["impact", "--quiet", "--dry-run", "--v-in", "0.04", "--params", str(path)]) == 2
    assert main(["impact", "--quiet", "--dry-run", "--v-in", "0.04", "--params", str(path), "--flow-curve",
                 str(curve_files / "GOOD.csv"), "--flow-curve-extrapolation", "slope"]) == 0


class _NoRoot(LinearHardening):
    """A flow curve whose return mapping never finds its root (calib.fe.flow_curve raises ArithmeticError)."""

    def return_stress(self, *args, **kwargs):
        raise ArithmeticError("flow curve test: the return mapping did not converge")


def test_a_return_mapping_without_root_fails_the_step_not_the_run(coarse_mesh):
    """A return mapping that raises at an iterate fails that Newton solve like divergence (a step the
    stepper retries smaller, or a StepNotConverged naming the material), never an ArithmeticError."""
    solver = ContactSolver(coarse_mesh, HardeningMaterial(E, NU, _NoRoot(SIGMA_Y, E / 20)))
    result = solver.solve_force(solver.initial_state(), 20 * PAIR.P_Y)
    assert not result.converged and "material: flow curve test" in result.message


# ------------------------------------------------------------------------------------------------
# table, scenes, material, fit-data; parameter files in collide and export
# ------------------------------------------------------------------------------------------------
SCENE = """[scene]
name = "hard"
[mesh]
level = "coarse"
[[material]]
name = "al"
E = 70e9
nu = 0.3
sigma_y = 1e8
rho = 2700.0
R = 0.01
{material}
[load_paths]
P_max_over_P_Y = [5.0, 10.0]
[calibration]
ship = "radius"
{calibration}
"""


def write_scene(folder, material: str = "", calibration: str = "", extra: str = ""):
    path = folder / "hard.toml"
    path.write_text(SCENE.format(material=material, calibration=calibration) + extra)
    return path


def one_line_refusal(capsys, argv, needle):
    from calib.cli import main

    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and needle in err, err
    return err


@pytest.mark.parametrize("command", ["fit-data"])
@pytest.mark.parametrize("flags", [["--flow-curve", "GOOD"],
                                   ["--flow-curve", "GOOD", "--flow-curve-extrapolation", "slope"]])
def test_master_table_commands_refuse_a_flow_curve_naming_calibrate(command, flags, curve_files, capsys):
    """fit-data answers a linear hardening from the vz master table's hardening sheet (tests/test_vz_hardening.py),
    a tabulated flow curve not: one line saying so and naming the calibration to run instead, exit 2, before any
    input is read (material answers a flow curve: tests/test_vz_hardening.py)."""
    flags = [str(curve_files / "GOOD.csv") if f == "GOOD" else f for f in flags]
    extra = ["--impacts", str(curve_files / "none.csv")] if command == "fit-data" else ["--v-max", "1"]
    err = one_line_refusal(capsys, [command, *extra, *flags], "linear hardening only")
    assert err.split(": ")[2].startswith("--flow-curve") and "nfdcal calibrate --flow-curve" in err


def test_material_answers_zero_hardening_as_the_perfectly_plastic_sphere(capsys):
    from calib.cli import main

    assert main(["material", "--json"]) == 0
    plain = capsys.readouterr().out
    assert main(["material", "--json", "--hardening-modulus", "0"]) == 0
    assert capsys.readouterr().out == plain


def test_table_flags_give_every_sphere_the_flow_curve_in_the_plan(curve_files, capsys):
    """table --hardening-modulus / --flow-curve (--flow-curve-extrapolation): accepted, recorded in the
    plan (each stage's detail and the JSON's records); H = 0 the perfectly plastic plan."""
    import json

    from calib.cli import main

    assert main(["table", "copper", "--dry-run", "--json"]) == 0
    plain = json.loads(capsys.readouterr().out)
    assert "hardening" not in plain
    assert main(["table", "copper", "--dry-run", "--json", "--hardening-modulus", "0"]) == 0
    assert json.loads(capsys.readouterr().out) == plain
    assert main(["table", "copper", "--dry-run", "--json", "--hardening-modulus", "2e9"]) == 0
    planned = json.loads(capsys.readouterr().out)
    assert planned["hardening"] == {"copper_c11000": {"flow_curve": "linear", "sigma_y": 69e6, "hardening_modulus": 2e9}}
    assert planned["stages"][0]["detail"].endswith("hardening H = 2e+09 Pa")
    assert main(["table", "copper", "--dry-run", "--json", "--hardening-modulus", "2e9", "--v-max", "0.05"]) == 0
    sized = json.loads(capsys.readouterr().out)     # the impact window sized for the hardening sphere
    assert sized["hardening"] == planned["hardening"] and sized["stages"][0]["detail"].endswith("hardening H = 2e+09 Pa")
    scene = write_scene(curve_files)
    assert main(["table", str(scene), "--dry-run", "--flow-curve", str(curve_files / "GOOD.csv"),
                 "--flow-curve-extrapolation", "slope"]) == 0
    assert "flow curve GOOD.csv (slope)" in capsys.readouterr().out


TABLE_REFUSALS = [
    (["copper", "--hardening-modulus", "1e12"], "--hardening-modulus out of range"),
    (["copper", "--flow-curve", "GOOD"], "give --sigma-y as the table's first stress"),
    (["copper", "--hardening-modulus", "1e9", "--flow-curve", "GOOD"], "give one of them"),
    (["copper", "--hardening-modulus", "1e9", "--master-out", "m.csv"], "--master-out: the master table is of perfectly"),
    (["copper", "--hardening-modulus", "1e9", "--check-master"], "--check-master: the master table is of perfectly"),
    (["vz_master_grid", "--hardening-modulus", "1e9"], "the vz master table is of perfectly plastic spheres"),
    (["SCENE_H", "--hardening-modulus", "1e9"], "gives its spheres' hardening: give it there or here, not both"),
]


@pytest.mark.parametrize("argv, needle", TABLE_REFUSALS, ids=[n for _, n in TABLE_REFUSALS])
def test_table_refuses_hardening_it_cannot_run_in_one_line(argv, needle, curve_files, capsys):
    scene = write_scene(curve_files, material="hardening_modulus = 1e9")
    argv = [{"GOOD": str(curve_files / "GOOD.csv"), "SCENE_H": str(scene)}.get(a, a) for a in argv]
    one_line_refusal(capsys, ["table", *argv, "--dry-run", "--out", str(curve_files / "out")], needle)


def test_scene_hardening_entries_are_planned_and_applied(curve_files, capsys):
    """A [[material]] or [calibration] hardening entry: the scene's plan names it, each stage's spec
    carries the flow curve, and the flow curve's file is read relative to the scene."""
    from calib.cli import main
    from calib.scenes import load_scene
    from calib.scenes.plan import calibration_spec

    for material, calibration, named in (("hardening_modulus = 2e9", "", "hardening H = 2e+09 Pa"),
                                         ("", 'flow_curve = "GOOD.csv"\nflow_curve_extrapolation = "slope"',
                                          "flow curve GOOD.csv (slope)")):
        path = write_scene(curve_files, material, calibration)
        assert main(["run", str(path), "--dry-run"]) == 0
        assert named in capsys.readouterr().out
        scene = load_scene(path)
        spec = calibration_spec(scene, scene.materials[0])
        assert spec.hardening is scene.flow_curve(scene.materials[0]) and spec.hardening is not None
    assert load_scene(write_scene(curve_files, "hardening_modulus = 0.0")).hardening == ()


SCENE_REFUSALS = [
    ({"material": "hardening_modulus = -1.0"}, "material[0].hardening_modulus: out of range: need >= 0, got -1"),
    ({"material": "hardening_modulus = 1e12"}, "material[0].hardening_modulus: out of range: need >= 0 and <= E = 7e+10 Pa"),
    ({"material": 'hardening_modulus = "1e9"'}, "material[0].hardening_modulus: must be a number"),
    ({"material": 'hardening_modulus = 1e9\nflow_curve = "GOOD.csv"'}, "give one of them"),
    ({"material": 'flow_curve_extrapolation = "slope"'}, "give the table too"),
    ({"calibration": 'flow_curve = "GOOD.csv"\nflow_curve_extrapolation = "linear"'},
     "calibration.flow_curve_extrapolation: must be one of flat, slope"),
    ({"calibration": 'flow_curve = "FALLS.csv"'}, "calibration.flow_curve: flow curve"),
    ({"material": 'flow_curve = "OTHER_SY.csv"'}, "material[0].flow_curve: flow curve"),
    ({"material": 'flow_curve = "MISSING.csv"'}, "cannot read it"),
    ({"material": "hardening_modulus = 1e9", "calibration": "hardening_modulus = 1e9"}, "give it in one place"),
    ({"material": "hardening_modulus = 1e9", "extra": "[impact]\nv_in = [1.0]\n[impact.counter]\nE = 2e11\nrho = 7800.0\n"},
     "impact.counter: the two-body impact FE is of perfectly plastic spheres"),
]


@pytest.mark.parametrize("case, needle", SCENE_REFUSALS, ids=[n for _, n in SCENE_REFUSALS])
def test_scene_hardening_refused_in_one_line_naming_the_key(case, needle, curve_files, capsys):
    path = write_scene(curve_files, case.get("material", ""), case.get("calibration", ""), case.get("extra", ""))
    one_line_refusal(capsys, ["run", str(path), "--dry-run"], needle)


# the table keys of perfectly plastic rows, computed by main's calib.scenes.table before the hardening
# dimension of rows existed (tasks_for of each built-in scene, and of SCENE without hardening)
KEYS_BEFORE_HARDENING = {"aluminium_on_steel": ["7d7559bd6940a51b"], "copper": ["a6eef8b623a5abd2"],
                         "hertz": ["458b653cc7c44f68"], "reference": ["7164526f8d6c5049"],
                         "steel": ["3148cd7fe90294fd"], "SCENE": ["5ca6f43886cd8983"],
                         "master_validation": ["7a6c5270112a3514", "d9628923ef8810cb", "f35369db0824585b",
                                               "2402a4b8ec46b212"]}


@pytest.mark.parametrize("name", sorted(KEYS_BEFORE_HARDENING))
def test_rows_without_hardening_keep_their_cache_keys(name, tmp_path):
    from calib.scenes import load_scene
    from calib.scenes.table import tasks_for

    scene = load_scene(write_scene(tmp_path) if name == "SCENE" else name)
    keys = [task["key"] for task in tasks_for(scene)][:4]
    assert keys == KEYS_BEFORE_HARDENING[name]


def test_hardening_rows_are_keyed_by_the_curve_not_its_file(curve_files, tmp_path):
    from calib.scenes import load_scene
    from calib.scenes.table import tasks_for

    (tmp_path / "copy.csv").write_text((curve_files / "GOOD.csv").read_text())
    keys = [tasks_for(load_scene(write_scene(curve_files, text)))[0]["key"]
            for text in ("", "hardening_modulus = 1e9", "hardening_modulus = 2e9", 'flow_curve = "GOOD.csv"',
                         f'flow_curve = "{tmp_path / "copy.csv"}"')]
    assert keys[0] == KEYS_BEFORE_HARDENING["SCENE"][0]
    assert len(set(keys[:4])) == 4 and keys[3] == keys[4]


def test_a_coarse_table_row_of_a_hardening_sphere(curve_files):
    """One coarse table row with H = 2 GPa: calibrated, the hardening column and the stamp's flow curve
    recorded; a rerun reuses it; the master table refuses it."""
    import json

    from calib.cli import main
    from calib.scenes.table import write_master_table

    out = curve_files / "table"
    argv = ["table", str(write_scene(curve_files, "hardening_modulus = 2e9")), "--workers", "1", "--quiet",
            "--out", str(out)]
    assert main(argv) == 0
    table = json.loads((out / "table.json").read_text())
    row = table["rows"][0]
    assert row["status"] == "ok" and row["hardening"] == "hardening H = 2e+09 Pa" and row["Ca"] > 0
    assert table["stamp"]["flow_curves"]["al"]["hardening_modulus"] == 2e9
    assert "hardening" in (out / "table.csv").read_text().splitlines()[-2]
    assert main(argv + ["--json"]) == 0
    with pytest.raises(ValueError, match="no hardening dimension"):
        write_master_table(table["rows"], curve_files / "m.csv", "", "hard")


@pytest.fixture
def hardening_params(tmp_path):
    """A parameter file as a hardening calibration writes it: its law and the "hardening" record."""
    import json

    from calib.cli import main
    from nfdmodel import reference_case

    path = tmp_path / "vz.json"
    assert main(["material", "--params-out", str(path), "--quiet"]) == 0
    data = json.loads(path.read_text())
    data["hardening"] = LinearHardening(reference_case.SIGMA_Y, 3.5e9).record()   # the file's sphere
    path.write_text(json.dumps(data))
    return path


def test_collide_and_export_name_the_files_flow_curve(hardening_params, capsys):
    from calib.cli import main

    assert main(["material", "--params-out", str(hardening_params.parent / "plain.json"), "--quiet"]) == 0
    capsys.readouterr()
    for name, shown in (("plain.json", False), ("vz.json", True)):
        assert main(["collide", "--params", str(hardening_params.parent / name), "--v-in", "1"]) == 0
        out = capsys.readouterr().out
        assert ("law calibrated with the sphere's isotropic hardening: sigma_y = sigma_Y + H eps_p, H = 3.5e+09 Pa"
                in out) is shown
        assert main(["export", "lammps", "--params", str(hardening_params.parent / name)]) == 0
        lines = capsys.readouterr().out.splitlines()
        assert lines[0].startswith("# nfdcal export lammps")
        assert (lines[1] == "# calibrated with the sphere's isotropic hardening: sigma_y = sigma_Y + H eps_p, "
                            "H = 3.5e+09 Pa") is shown
        assert lines[1 + shown].startswith("pair_style nfd/vz")

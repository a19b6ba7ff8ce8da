"""The dynamic FE impact of the whole sphere (meshes.sphere, calib.fe.sphere_dofs, calib.fe.newmark,
calib.fe.impact, nfdcal impact), checked against what the FE did not produce: the sphere's mass,
rigid flight, Hertz's elastic impact (Johnson 1985, eq. 11.24 and section 11.4), the discrete
energy identity of the trapezoidal rule, and the quasi-static vz law of the reference calibration.
Coarse meshes (1.6e-4 m at the contact) and few steps keep each impact to seconds."""
import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest

from calib.cli import main
from calib.fe import ElasticMaterial, VonMisesMaterial
from calib.fe.impact import contact_time_estimate, residual_state, run_impact
from calib.fe.newmark import ImpactSolver
from calib.studies.impact import STUDY_VELOCITIES_OVER_V_Y
from meshes.hemisphere import HemisphereMeshSpec
from meshes.sphere import SphereMeshSpec, sphere_mesh
from calib.report.parameter_file import two_constant_law
from nfdmodel import ContactPair, Material, collision_reference, reference_case

R, E, NU, SIGMA_Y, RHO = (reference_case.R, reference_case.E, reference_case.NU, reference_case.SIGMA_Y,
                          reference_case.RHO)
COARSE = SphereMeshSpec(radius=R, contact_size=1.6e-4, refined_radius=1.6e-3, refined_depth=5e-4, far_size=1e-2,
                        growth=0.3)
PAIR = ContactPair.sphere_flat(Material(E, NU, SIGMA_Y, RHO), R)
MASS = 4.0 / 3.0 * math.pi * R ** 3 * RHO
V_IN = 0.04                       # m/s: 24 v_Y, the benchmark's impact
REFERENCE_PARAMETERS = Path(__file__).resolve().parent.parent / "results" / "calibration" / "parameters.json"


def hertz_impact(v_in: float) -> tuple[float, float, float]:
    """(P_max [N], alpha_max [m], contact time [s]) of Hertz's elastic impact (Johnson 1985, 11.4):
    (1/2) m v^2 = (2/5) k alpha^(5/2), P = k alpha^(3/2), t = 2.868 (m^2 / (R E*^2 v))^(1/5)."""
    k = PAIR.hertz_stiffness
    alpha = (5.0 * MASS * v_in ** 2 / (4.0 * k)) ** 0.4
    return k * alpha ** 1.5, alpha, 2.868 * (MASS ** 2 / (R * PAIR.E_star ** 2 * v_in)) ** 0.2


@pytest.fixture(scope="module")
def mesh(mesh_cache):
    return sphere_mesh(COARSE, cache_dir=mesh_cache)


@pytest.fixture(scope="module")
def elastic(mesh):
    return ImpactSolver(mesh, ElasticMaterial(E, NU), RHO)


@pytest.fixture(scope="module")
def plastic(mesh):
    return ImpactSolver(mesh, VonMisesMaterial(E, NU, SIGMA_Y), RHO)


@pytest.fixture(scope="module")
def elastic_impact(elastic):
    return run_impact(elastic, V_IN, steps_per_contact=50)


@pytest.fixture(scope="module")
def plastic_impact(plastic):
    return run_impact(plastic, V_IN, steps_per_contact=40)


# ---------------------------------------------------------------- the mesh and the mass
def test_sphere_mesh_is_the_half_disc_with_the_hemisphere_sizes(mesh):
    from skfem import Basis, ElementTriP2, Functional

    basis = Basis(mesh.mesh, ElementTriP2())
    assert Functional(lambda w: 1.0 + 0.0 * w.x[0]).assemble(basis) == pytest.approx(math.pi * R ** 2 / 2, rel=1e-5)
    assert Functional(lambda w: 2 * math.pi * w.x[0]).assemble(basis) == pytest.approx(4 / 3 * math.pi * R ** 3,
                                                                                         rel=1e-5)
    assert np.all(basis.mapping.detDF(basis.X) > 0)
    assert set(mesh.boundaries) == {"axis", "surface"}
    assert mesh.radius == pytest.approx(R)
    hemisphere = HemisphereMeshSpec(**{k: getattr(COARSE, k) for k in ("radius", "contact_size", "refined_radius",
                                                                      "refined_depth", "far_size", "growth")})
    assert COARSE.cache_key() != hemisphere.cache_key()
    assert COARSE.size_at(1e-4, 1e-4) == hemisphere.size_at(1e-4, 1e-4)
    with pytest.raises(ValueError, match="contact_size"):
        SphereMeshSpec(contact_size=0.0)


def test_mass_is_the_whole_spheres_and_the_contact_boundary_is_massless(elastic):
    dofs = elastic.dofs
    assert dofs.mass == pytest.approx(MASS, rel=1e-6)              # the discrete volume to O(h^4)
    assert elastic.momentum(dofs.translation) == pytest.approx(dofs.mass, rel=1e-12)   # rescaled to keep it
    assert 0 < dofs.massless_fraction < 1e-6
    assert np.all(elastic.massless[dofs.candidate_q])
    state = elastic.initial_state(V_IN)
    assert state.kinetic_energy == pytest.approx(0.5 * dofs.mass * V_IN ** 2, rel=1e-12)
    assert dofs.candidate_r[0] == 0.0
    assert COARSE.refined_radius - COARSE.contact_size < dofs.candidate_r[-1] <= COARSE.refined_radius


def test_free_flight_is_an_exact_rigid_translation(elastic):
    state = elastic.initial_state(V_IN)
    away = dataclasses.replace(state, velocity=-state.velocity)                 # leaving the flat
    dt = 1e-5
    step = elastic.solve_step(away, dt, force_scale=MASS * V_IN / 1e-3)
    assert step.converged and not step.state.in_contact
    np.testing.assert_allclose(step.state.q, dt * V_IN * elastic.dofs.translation, rtol=0, atol=1e-12 * dt * V_IN)
    assert step.state.kinetic_energy == pytest.approx(state.kinetic_energy, rel=1e-12)
    assert elastic.centre_of_mass_displacement(step.state.q) == pytest.approx(dt * V_IN, rel=1e-12)


# ---------------------------------------------------------------- Hertz's elastic impact
def test_elastic_impact_is_hertzs(elastic_impact):
    r = elastic_impact
    P_max, alpha_max, t_c = hertz_impact(V_IN)
    # measured on this mesh: e - 1 = +2e-5 (the discrete contact work), P_max +0.3 %, alpha_max and the
    # contact time -0.3 % (the whole sphere is a little stiffer than Hertz's half-spaces: the same
    # finite-size effect as the hemisphere's, calib.studies.hertz)
    assert abs(r.e - 1.0) < 1e-3
    assert r.P_max == pytest.approx(P_max, rel=0.01)
    assert r.alpha_max == pytest.approx(alpha_max, rel=0.01)
    assert r.contact_time == pytest.approx(t_c, rel=0.01)
    assert r.time_P_max == pytest.approx(r.contact_time / 2, rel=0.01)        # Hertz's impact is symmetric
    assert r.dent == 0.0 and r.plastic_work == 0.0 and r.residual_stress_energy == 0.0
    assert 0 <= r.vibration_energy < 1e-4 * r.kinetic_in                       # quasi-static: t_c >> wave transit
    assert r.recontacts == 0 and r.halvings == 0


def test_contact_time_estimate_is_hertzs_for_an_elastic_sphere():
    assert contact_time_estimate(ElasticMaterial(E, NU), RHO, R, V_IN) == pytest.approx(hertz_impact(V_IN)[2],
                                                                                      rel=1e-3)


def test_separation_is_found_inside_the_step(elastic_impact):
    r = elastic_impact
    t, P = r.history["time"], r.history["P"]
    last = int(np.flatnonzero(P > 0)[-1])
    assert t[last] <= r.contact_time <= t[last + 1]
    assert P[last] < 1e-3 * r.P_max                      # the steps land on the separation ...
    assert r.contact_time - t[last] < 0.05 * r.dt        # ... inside the step, not on the step grid


def test_energy_identity_of_the_trapezoidal_rule_holds_to_round_off(elastic_impact, plastic_impact):
    for r in (elastic_impact, plastic_impact):
        # KE_in - KE_final = W_int - W_contact - W_residual exactly (calib.fe.newmark); the balance
        # residual is that identity's left side less what the constitutive model stores and dissipates
        identity = (r.balance_residual - r.internal_work_error + r.contact_work - r.solver_residual_work)
        assert abs(identity) < 1e-9 * r.kinetic_in
        assert abs(r.solver_residual_work) < 1e-8 * r.kinetic_in


def test_elastic_energy_balance_closes_to_the_contact_work(elastic_impact):
    r = elastic_impact
    assert abs(r.internal_work_error) < 1e-12 * r.kinetic_in          # elastic: the trapezoid is exact
    assert abs(r.balance_residual) < 1e-3 * r.kinetic_in
    assert r.balance_residual == pytest.approx(-r.contact_work, rel=1e-6, abs=1e-12 * r.kinetic_in)


# ---------------------------------------------------------------- the elastoplastic impact
def test_elastoplastic_impact_against_the_law_and_its_energy(plastic_impact):
    r = plastic_impact
    params = two_constant_law(REFERENCE_PARAMETERS)     # the reference calibration's Ca, Kc
    law = collision_reference("vz", params, [V_IN])
    # measured on this mesh: e 0.743 against the law's 0.758, P_max 1417 against 1488 N, the contact
    # time 0.976 against 0.980 ms (the default mesh: 0.7428, 1419 N, 0.973 ms)
    assert r.e == pytest.approx(law.restitution[0], rel=0.05)
    assert r.P_max == pytest.approx(law.P_max[0], rel=0.10)
    assert r.contact_time == pytest.approx(law.contact_time_estimate[0], rel=0.05)
    assert 0 < r.dent < r.alpha_max
    assert r.dent == pytest.approx(law.delta_res[0], rel=0.25)
    kinetic = r.kinetic_in
    assert r.kinetic_out == pytest.approx(r.e ** 2 * kinetic, rel=1e-12)
    assert r.plastic_work > 0.3 * kinetic and r.residual_stress_energy > 0
    assert 0 <= r.vibration_energy < 1e-3 * kinetic
    assert abs(r.balance_residual) < 2e-3 * kinetic
    total = r.kinetic_out + r.plastic_work + r.residual_stress_energy + r.vibration_energy + r.balance_residual
    assert total == pytest.approx(kinetic, rel=1e-12)


def test_residual_state_of_an_unyielded_sphere_is_zero(elastic, plastic):
    assert residual_state(plastic, plastic.initial_state(V_IN)) == (0.0, 0.0)


def test_run_impact_refuses_bad_input(elastic):
    for v in (0.0, -1.0, float("nan")):
        with pytest.raises(ValueError, match="v_in"):
            run_impact(elastic, v)
    with pytest.raises(ValueError, match="steps_per_contact"):
        run_impact(elastic, V_IN, steps_per_contact=5)


# ---------------------------------------------------------------- nfdcal impact
def test_command_writes_the_records_and_resumes(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    monkeypatch.chdir(tmp_path)
    out = tmp_path / "out"
    argv = ["impact", "--v-in", "0.01", "--contact-size", "1.6e-4", "--steps-per-contact", "20",
            "--no-error-estimate", "--workers", "1", "--out", str(out), "--json", "--no-plots", "--quiet"]
    assert main(argv) == 0
    records = json.loads(capsys.readouterr().out)
    assert len(records) == 1
    record = records[0]
    for key in ("v_in", "e", "P_max", "contact_time", "alpha_max", "dent", "kinetic_in", "kinetic_out", "plastic_work",
                "residual_stress_energy", "vibration_energy", "balance_residual", "models"):
        assert key in record
    assert 0.8 < record["e"] < 1.0 and record["models"]["vz"]["e"] < 1.0
    assert {p.name for p in out.iterdir()} >= {"impact.csv", "impact.json", "cases"}
    # the quasi-static FE path to the same P_max (another solver: the hemisphere pressed by a plate) gives
    # the same e and contact time within 1 % at 6 v_Y, where the sphere keeps no vibration to speak of
    change = record["dynamic_over_quasi_static"]
    assert abs(change["e"]) < 0.01 and abs(change["contact_time"]) < 0.01 and abs(change["v_in"]) < 0.01
    assert record["vibration_fraction"] < 1e-4
    assert (out / "drop_tests.csv").is_file() and (out / "quasi_static_cases").is_dir()
    assert len(list((out / "cases").glob("*.json"))) == 1
    summary = json.loads((out / "impact.json").read_text())
    assert summary["stamp"]["computed"] == 1 and "git_commit" in summary["stamp"]
    assert main(argv) == 0                                          # the finished impact is reused
    assert json.loads((out / "impact.json").read_text())["stamp"]["reused"] == 1
    capsys.readouterr()


@pytest.mark.parametrize("flags, named", [(["--v-in", "0"], "--v-in"), (["--v-in", "fast"], "--v-in"),
                                          (["--v-in", "10"], "--v-in"), (["--workers", "0"], "--workers"),
                                          (["--steps-per-contact", "9"], "--steps-per-contact"),
                                          (["--steps-per-contact", "50.5"], "--steps-per-contact"),
                                          (["--params", "missing.json"], "--params"), (["--E", "70"], "E"),
                                          (["--contact-size", "-1"], "--contact-size")])
def test_command_refuses_bad_input_in_one_line(flags, named, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["impact", *flags, "--dry-run"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and named in err and "Traceback" not in err


def test_dry_run_plans_without_computing(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["impact", "--dry-run", "--json"]) == 0
    plan = json.loads(capsys.readouterr().out)
    assert len(plan["runs"]) == 3 * len(STUDY_VELOCITIES_OVER_V_Y)        # fine, coarse mesh, coarse dt
    assert plan["out"] == "results/impact" and plan["estimated_total_s"] > 0
    assert not (tmp_path / "results").exists()

"""The dynamic FE impact of the sphere on a deformable counter-body (calib.fe.impact_pair_mesh,
calib.fe.impact_pair, calib.fe.impact_pair_run, calib.studies.impact_pair, nfdcal impact --counter-*),
checked against what the two-body code did not produce: the one-sphere solver on the rigid flat
(two identical spheres are its mirror image), Hertz's elastic impact of the pair (Johnson 1985,
section 11.4, with E*, R* and the reduced mass), conservation of momentum, and the discrete
energy identity of the trapezoidal rule. Coarse meshes (1.6e-4 m at the contact), few steps."""
import dataclasses
import json
import math

import pytest

from calib.cli import main
from calib.fe import ElasticMaterial, VonMisesMaterial
from calib.fe.impact import run_impact
from calib.fe.impact_pair import PairImpactSolver
from calib.fe.impact_pair_mesh import impact_pair_mesh
from calib.fe.impact_pair_run import hertz_pair_impact, run_pair_impact
from calib.fe.newmark import ImpactSolver
from calib.fit.counter import CounterBody
from calib.studies import impact
from calib.studies.impact_pair import COMPARED, PairImpactSetup, block_size_effect, pair_meshes
from meshes.counter_body import BlockMeshSpec
from meshes.sphere import SphereMeshSpec, sphere_mesh
from nfdmodel import Material, reference_case

R, E, NU, SIGMA_Y, RHO = (reference_case.R, reference_case.E, reference_case.NU, reference_case.SIGMA_Y,
                          reference_case.RHO)
COARSE = SphereMeshSpec(radius=R, contact_size=1.6e-4, refined_radius=1.6e-3, refined_depth=5e-4, far_size=1e-2,
                        growth=0.3)
STEEL_E, STEEL_NU, STEEL_RHO = 2.1e11, 0.28, 7800.0
V = 0.04                          # m/s: 24 v_Y of the reference sphere on the rigid flat


def energy_identity(result) -> float:
    """|balance - (internal-work error - contact work - residual work)| / KE_in: the trapezoidal
    rule's discrete energy identity (calib.fe.newmark) closes the balance exactly."""
    expected = result.internal_work_error - result.contact_work - result.solver_residual_work
    return abs(result.balance_residual - expected) / result.kinetic_in


@pytest.mark.parametrize("plastic", [False, True], ids=["elastic", "plastic"])
def test_two_identical_spheres_are_the_sphere_on_the_rigid_flat(plastic, mesh_cache):
    """At +-v the mid-plane of two identical spheres is a rigid frictionless flat: the pair at the
    relative velocity 2 v gives the rigid-flat solver's e, P_max and contact time at v."""
    def material():
        return VonMisesMaterial(E, NU, SIGMA_Y) if plastic else ElasticMaterial(E, NU)

    steps = 30
    flat = run_impact(ImpactSolver(sphere_mesh(COARSE, cache_dir=mesh_cache), material(), RHO), V,
                      steps_per_contact=steps)
    solver = PairImpactSolver(impact_pair_mesh(COARSE, COARSE, mesh_cache), material(), material(), RHO, RHO)
    pair = run_pair_impact(solver, 2 * V, steps_per_contact=steps)
    assert pair.v1_in == pytest.approx(V, rel=1e-12) and pair.v2_in == pytest.approx(V, rel=1e-12)
    assert pair.e == pytest.approx(flat.e, abs=1e-6)
    assert pair.P_max == pytest.approx(flat.P_max, rel=1e-6)
    assert pair.contact_time == pytest.approx(flat.contact_time, rel=1e-6)
    assert pair.alpha_max == pytest.approx(2 * flat.alpha_max, rel=1e-6)        # both bodies' approach
    assert pair.plastic_work == pytest.approx(2 * flat.plastic_work, rel=1e-5, abs=1e-12 * flat.kinetic_in)
    assert pair.momentum_change < 1e-10
    assert energy_identity(pair) < 1e-9
    if plastic:
        assert pair.e < 0.8                       # it did yield: this is no elastic check in disguise


@pytest.fixture(scope="module")
def steel_sphere(mesh_cache):
    """An aluminium sphere on a free steel sphere of half its radius, both elastic."""
    counter = dataclasses.replace(COARSE, radius=R / 2, far_size=5e-3)
    solver = PairImpactSolver(impact_pair_mesh(COARSE, counter, mesh_cache), ElasticMaterial(E, NU),
                              ElasticMaterial(STEEL_E, STEEL_NU), RHO, STEEL_RHO)
    return solver, run_pair_impact(solver, V, steps_per_contact=40)


@pytest.fixture(scope="module")
def steel_block(mesh_cache):
    """An elastic aluminium sphere on an elastic steel block of L = 2 R, far face held."""
    block = BlockMeshSpec(**{**dataclasses.asdict(COARSE), "radius": 2 * R, "far_size": 2e-2})
    solver = PairImpactSolver(impact_pair_mesh(COARSE, block, mesh_cache), ElasticMaterial(E, NU),
                              ElasticMaterial(STEEL_E, STEEL_NU), RHO, STEEL_RHO)
    return solver, run_pair_impact(solver, V, steps_per_contact=40)


def test_doubled_dt_change_shrinks_at_second_order(steel_sphere):
    """The estimate's dt part (calib.studies.impact.error_estimates) on the elastic pair: the
    change from doubling dt falls about 4x when dt halves (the average-acceleration scheme is
    second order on smooth elastic motion; 3.2-4.1x measured at 10/20/40 steps per contact), so it
    measures the time discretisation and not noise; no mesh run: its part stays None."""
    solver, at_40 = steel_sphere
    at_10, at_20 = (run_pair_impact(solver, V, steps_per_contact=n).record() for n in (10, 20))
    coarse = impact.error_estimates({"fine": at_20, "coarse dt": at_10}, COMPARED)
    fine = impact.error_estimates({"fine": at_40.record(), "coarse dt": at_20}, COMPARED)
    for key in ("P_max", "contact_time", "alpha_max"):
        assert 2.5 < abs(coarse[f"{key}_dt_change"] / fine[f"{key}_dt_change"]) < 6.5, key
        assert fine[f"{key}_mesh_change"] is None and fine[f"{key}_rel_error_estimate"] is None
    assert abs(fine["e_dt_change"]) < abs(coarse["e_dt_change"]) < 2e-3


@pytest.mark.parametrize("case", ["steel_sphere", "steel_block"])
def test_unlike_elastic_bodies_give_hertz_impact_of_the_pair(case, request):
    """Contact time, P_max and alpha_max within 1.5 % of Hertz's with the pair's E*, R* and m*
    computed here from the inputs (the coarse mesh and 40 steps: 0.3 % measured); e -> 1 less
    what stays in the bodies as vibration."""
    solver, result = request.getfixturevalue(case)
    E_star = 1.0 / ((1 - NU ** 2) / E + (1 - STEEL_NU ** 2) / STEEL_E)
    m1 = 4.0 / 3.0 * math.pi * R ** 3 * RHO
    if case == "steel_sphere":
        R2, m2 = R / 2, 4.0 / 3.0 * math.pi * (R / 2) ** 3 * STEEL_RHO
        R_star, m_star = R * R2 / (R + R2), m1 * m2 / (m1 + m2)
    else:
        R_star, m_star = R, m1
    assert result.E_star == pytest.approx(E_star, rel=1e-12) and result.R_star == pytest.approx(R_star, rel=1e-12)
    assert result.reduced_mass == pytest.approx(m_star, rel=1e-3)             # the discrete masses
    hertz = hertz_pair_impact(E_star, R_star, m_star, V)
    for key in ("contact_time", "P_max", "alpha_max"):
        assert getattr(result, key) == pytest.approx(hertz[key], rel=0.015), key
    assert abs(result.e - 1.0) < 2e-3
    # e^2 = 1 - (energy left in the bodies) / KE_in, up to the discrete contact work (first order in dt)
    assert abs(result.e ** 2 - (1.0 - result.energy_left / result.kinetic_in)) <= \
        1.1 * abs(result.contact_work) / result.kinetic_in + 1e-9
    assert energy_identity(result) < 1e-9
    assert abs(result.balance_residual) < 1e-3 * result.kinetic_in
    if case == "steel_sphere":
        assert result.momentum_change < 1e-10
        assert result.v1_in * solver.masses[0] == pytest.approx(result.v2_in * solver.masses[1], rel=1e-12)
    else:
        assert result.momentum_change is None


def test_the_block_is_large_enough(steel_block, mesh_cache):
    """Halving the held block (L = 2 R to R) changes e by < 1e-4, P_max and the contact time by < 0.3 %:
    the contact lasts many wave returns 2 L / c_L, so the block responds quasi-statically."""
    _, default = steel_block
    block = BlockMeshSpec(**{**dataclasses.asdict(COARSE), "radius": R, "far_size": 2e-2})
    solver = PairImpactSolver(impact_pair_mesh(COARSE, block, mesh_cache), ElasticMaterial(E, NU),
                              ElasticMaterial(STEEL_E, STEEL_NU), RHO, STEEL_RHO)
    half = run_pair_impact(solver, V, steps_per_contact=40)
    c_L = math.sqrt(STEEL_E * (1 - STEEL_NU) / (STEEL_RHO * (1 + STEEL_NU) * (1 - 2 * STEEL_NU)))
    assert default.contact_time > 10 * 2 * (2 * R) / c_L
    assert abs(half.e - default.e) < 1e-4
    assert half.P_max == pytest.approx(default.P_max, rel=3e-3)
    assert half.contact_time == pytest.approx(default.contact_time, rel=3e-3)


def test_study_meshes_follow_the_counter_body():
    """A counter-sphere gets a sphere mesh of its radius, a flat a block of L = 2 R (or the size
    asked); a softer pair widens the sphere's refined zone."""
    sphere = impact.ImpactSetup(Material(E, NU, SIGMA_Y, RHO), R, contact_size=1.6e-4)
    soft = PairImpactSetup(sphere, CounterBody(E / 3, NU))
    own, counter = pair_meshes(soft, V)
    assert isinstance(counter, BlockMeshSpec) and counter.radius == pytest.approx(2 * R)
    assert own.refined_radius > impact.impact_mesh(sphere, V).refined_radius
    _, counter = pair_meshes(PairImpactSetup(sphere, CounterBody(E, NU, R=R / 2)), V)
    assert isinstance(counter, SphereMeshSpec) and counter.radius == pytest.approx(R / 2)
    _, counter = pair_meshes(PairImpactSetup(sphere, CounterBody(E, NU), block_size=R), V)
    assert counter.radius == pytest.approx(R)
    with pytest.raises(ValueError, match="flat"):
        block_size_effect(PairImpactSetup(sphere, CounterBody(E, NU, R=R)), V, [R])


@pytest.mark.parametrize("flags, named", [(["--counter-E", "2e11", "--counter-nu", "0.6"], "--counter-nu"),
                                          (["--counter-E", "-1"], "--counter-E"),
                                          (["--counter-nu", "0.3"], "--counter-E"),
                                          (["--counter-E", "2e11", "--counter-R", "0"], "--counter-R"),
                                          (["--counter-E", "2e11", "--convergence"], "--convergence"),
                                          (["--counter-E", "2e11", "--params", "p.json"], "--params"),
                                          (["--counter-E", "2e11", "--no-quasi-static"], "--no-quasi-static"),
                                          (["--counter-E", "2e11", "--no-plots"], "--no-plots")])
def test_counter_flags_refuse_bad_input_in_one_line(flags, named, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["impact", *flags, "--dry-run"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and named in err and "Traceback" not in err


def test_counter_dry_run_plans_the_pair(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(["impact", "--counter-E", "2.1e11", "--counter-R", "0.05", "--counter-rho", "7850", "--dry-run",
                 "--json"]) == 0
    plan = json.loads(capsys.readouterr().out)
    assert len(plan["runs"]) == 9 and plan["counter"]["shape"] == "sphere" and plan["counter"]["R"] == 0.05
    assert {r["variant"] for r in plan["runs"]} == set(impact.VARIANTS)
    assert plan["out"].startswith("results/impact/pair_") and not (tmp_path / "results").exists()


def test_counter_command_writes_the_records_and_resumes(tmp_path, monkeypatch, capsys):
    """nfdcal impact on an elastic steel flat, far below first yield: Hertz's impact of the pair,
    with its error estimate (doubled contact element on both meshes, doubled dt) finite,
    non-negative and no smaller than the fine run's distance from Hertz's P_max and contact time;
    --no-error-estimate: the fine impact alone."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    monkeypatch.chdir(tmp_path)
    out = tmp_path / "out"
    argv = ["impact", "--counter-E", "2.1e11", "--counter-nu", "0.28", "--v-in", "0.001", "--contact-size", "1.6e-4",
            "--steps-per-contact", "20", "--workers", "1", "--out", str(out), "--json", "--quiet"]
    assert main(argv) == 0
    (record,) = json.loads(capsys.readouterr().out)
    E_star = 1.0 / ((1 - NU ** 2) / E + (1 - STEEL_NU ** 2) / STEEL_E)
    hertz = hertz_pair_impact(E_star, R, 4.0 / 3.0 * math.pi * R ** 3 * RHO, 0.001)
    assert record["P_max"] == pytest.approx(hertz["P_max"], rel=0.02)
    assert record["contact_time"] == pytest.approx(hertz["contact_time"], rel=0.02)
    assert abs(record["e"] - 1.0) < 5e-3 and abs(record["balance_residual_fraction"]) < 5e-3
    for key in ("e", "P_max", "contact_time", "alpha_max"):
        for field in ("mesh_change", "dt_change", "rel_error_estimate"):
            assert math.isfinite(record[f"{key}_{field}"]), (key, field)
        assert record[f"{key}_rel_error_estimate"] >= 0.0
        assert record[f"{key}_rel_error_estimate"] == pytest.approx(
            abs(record[f"{key}_mesh_change"]) + abs(record[f"{key}_dt_change"]), rel=1e-12)
    for key in ("P_max", "contact_time"):
        assert abs(record[key] / hertz[key] - 1.0) <= 1.5 * record[f"{key}_rel_error_estimate"], key
    assert {p.name for p in out.iterdir()} == {"impact_pair.csv", "impact_pair.json", "cases"}
    assert main(argv) == 0                                          # the finished impacts are reused
    assert json.loads((out / "impact_pair.json").read_text())["stamp"]["reused"] == 3
    capsys.readouterr()
    assert main([*argv, "--no-error-estimate"]) == 0                # the fine impact alone, reused
    (alone,) = json.loads(capsys.readouterr().out)
    assert alone["e"] == record["e"] and alone["e_rel_error_estimate"] is None
    assert json.loads((out / "impact_pair.json").read_text())["stamp"]["reused"] == 1

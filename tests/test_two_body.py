"""The sphere on a deformable counter-body (calib.fe.two_body, calib.fe.contact_pair,
meshes.counter_body), verified against what it did not produce: the exact uniform-stress solution
(contact patch test), Hertz's closed form with the pair's E* and R*, the rigid-flat FE
(calib.fe.solver) for a very stiff counter-body and for two identical spheres (the mid-plane of
the symmetric problem is a rigid frictionless flat), and first yield at the pair's Hertz P_Y.
Coarse meshes (about 1 s per solve); finer meshes in tests/benchmarks/bench_two_body.py.
"""
from types import SimpleNamespace

import numpy as np
import pytest

from calib.fe import ContactSolver, ElasticMaterial, LoadPathPlan, VonMisesMaterial, run_load_paths
from calib.fe.two_body import TwoBodySolver, first_yield_loads
from meshes.counter_body import BlockMeshSpec, pair_mesh
from meshes.hemisphere import HemisphereMeshSpec, hemisphere_mesh
from nfdmodel import ContactPair, Material

ALUMINIUM = Material(70e9, 0.3, 100e6, 2700.0)
STEEL = Material(200e9, 0.28, 500e6, 7800.0)
R1 = 0.1
P = 500.0        # [N]: a Hertz radius of 0.6-0.9 mm on these pairs


def spec(radius, contact_size=1e-4, kind=HemisphereMeshSpec, refined=2e-3):
    """A sphere (or block) mesh refined over the contact of the Hertz checks."""
    return kind(radius=radius, contact_size=contact_size, refined_radius=refined, refined_depth=refined / 2,
                far_size=radius / 10)


def elastic(material):
    return ElasticMaterial(material.E, material.nu)


def flat_pair(sphere: Material, flat) -> ContactPair:
    """The Hertz pair of a sphere of radius R1 on an elastic half-space (R* = R1)."""
    E_star = 1.0 / ((1 - sphere.nu ** 2) / sphere.E + (1 - flat.nu ** 2) / flat.E)
    return ContactPair(R1, E_star, sphere.sigma_y, sphere.nu, 1.0)


def loaded(solver, load=P):
    result = solver.solve_force(solver.initial_state(), load)
    assert result.converged, result.message
    return result


def test_two_blocks_transmit_a_uniform_pressure_exactly(mesh_cache):
    """Contact patch test: two unlike blocks with non-matching meshes (different sizes, gradings)
    under a rigid plate carry the uniform uniaxial stress -P / (pi L^2) exactly (the solution lies
    in both FE spaces); every contact node has that pressure, to round-off."""
    L = 0.01
    upper = BlockMeshSpec(radius=L, contact_size=7e-4, refined_radius=3e-3, refined_depth=3e-3, far_size=2.1e-3)
    lower = BlockMeshSpec(radius=L, contact_size=4.3e-4, refined_radius=4e-3, refined_depth=3e-3,
                          far_size=1.7e-3, growth=0.3)
    blocks = pair_mesh(upper, lower, cache_dir=mesh_cache)
    solver = TwoBodySolver(blocks, elastic(ALUMINIUM), elastic(STEEL), contact_zone=1.0)
    upper_r = np.sort(solver.node_r[np.abs(solver.node_z) < 1e-12 * L])
    assert not np.allclose(upper_r[::2], upper_r[1::2])            # the two faces' nodes differ
    result = loaded(solver, 1000.0)
    p = 1000.0 / (np.pi * L ** 2)
    carrying = result.state.active & (solver.candidate_weight > 0)
    assert carrying.sum() == solver.candidate_r.size - 1             # all but the pole (weight 0)
    np.testing.assert_allclose(result.pressure[carrying], p, rtol=1e-9)
    stress = solver.stress(result.state)
    np.testing.assert_allclose(stress[..., 1], -p, rtol=1e-9)
    assert np.abs(stress[..., [0, 2, 3]]).max() < 1e-9 * p


@pytest.mark.parametrize("counter", ["sphere", "block"])
def test_two_elastic_bodies_give_hertz_with_the_pairs_modulus_and_radius(mesh_cache, counter):
    """Aluminium sphere on a steel sphere (R2 = R1 / 2) or a steel block: contact radius within
    0.5 % and peak pressure within 2 % of Hertz with 1/E* = sum (1 - nu^2)/E and 1/R* = sum 1/R
    (Johnson 1985, eqs. 4.22-4.23)."""
    if counter == "sphere":
        mesh = pair_mesh(spec(R1), spec(R1 / 2), cache_dir=mesh_cache)
        pair = ContactPair.sphere_sphere(ALUMINIUM, R1, STEEL, R1 / 2)
    else:
        mesh = pair_mesh(spec(R1), spec(2 * R1, kind=BlockMeshSpec), cache_dir=mesh_cache)
        pair = flat_pair(ALUMINIUM, STEEL)
    record = loaded(TwoBodySolver(mesh, elastic(ALUMINIUM), elastic(STEEL))).record
    assert record.contact_radius == pytest.approx(float(pair.hertz_radius(P)), rel=5e-3)
    assert record.peak_pressure == pytest.approx(float(pair.hertz_peak_pressure(P)), rel=2e-2)
    assert record.contact_force == pytest.approx(P, rel=1e-8)       # the contact carries the plate's load


def test_the_condensed_elastic_counter_body_is_the_whole_one(mesh_cache):
    """The static condensation of an elastic counter-body onto its contact surface is exact: the
    same approach, contact radius and peak pressure as with every dof of both bodies, to 1e-10."""
    mesh = pair_mesh(spec(R1), spec(R1 / 2), cache_dir=mesh_cache)
    condensed, whole = (TwoBodySolver(mesh, elastic(ALUMINIUM), elastic(STEEL), condense=flag) for flag in (True, False))
    assert condensed.n_q < 0.6 * whole.n_q
    a, b = loaded(condensed).record, loaded(whole).record
    for name in ("alpha", "contact_radius", "peak_pressure"):
        assert getattr(a, name) == pytest.approx(getattr(b, name), rel=1e-10), name


def test_the_block_is_large_enough(mesh_cache):
    """Domain size: contact radius and peak pressure do not change with the block's size L (within
    0.05 %); the approach of the far points grows with L towards the half-space's as 1/L (the
    Boussinesq far field): doubling L halves the change."""
    records = [loaded(TwoBodySolver(pair_mesh(spec(R1), spec(L, kind=BlockMeshSpec), cache_dir=mesh_cache),
                                    elastic(ALUMINIUM), elastic(STEEL))).record for L in (0.05, 0.1, 0.2)]
    for record in records[1:]:
        assert record.contact_radius == pytest.approx(records[0].contact_radius, rel=5e-4)
        assert record.peak_pressure == pytest.approx(records[0].peak_pressure, rel=5e-4)
    changes = np.diff([r.alpha for r in records])
    assert np.all(changes > 0)
    assert changes[1] / changes[0] == pytest.approx(0.5, abs=0.1)
    assert changes[1] / records[-1].alpha < 1e-3


def test_a_very_stiff_counter_body_gives_the_rigid_flat(mesh_cache):
    """E2 = 1e4 E1: approach, contact radius and peak pressure within 1e-3 of the rigid-flat FE on
    the same sphere mesh (the block's compliance is 1e-4 of the sphere's)."""
    stiff = SimpleNamespace(E=1e4 * ALUMINIUM.E, nu=0.3)
    two = loaded(TwoBodySolver(pair_mesh(spec(R1), spec(2 * R1, kind=BlockMeshSpec), cache_dir=mesh_cache),
                               elastic(ALUMINIUM), elastic(stiff))).record
    rigid = loaded(ContactSolver(hemisphere_mesh(spec(R1), cache_dir=mesh_cache), elastic(ALUMINIUM))).record
    for name in ("alpha", "contact_radius", "peak_pressure"):
        assert getattr(two, name) == pytest.approx(getattr(rigid, name), rel=1e-3), name


def test_two_identical_spheres_give_the_rigid_flat_half_problem(mesh_cache):
    """Two identical elastic-plastic spheres: the mid-plane is a rigid frictionless flat, so along
    a loading into plasticity (to 4 P_Y) each sphere's approach (alpha / 2), the contact radius and
    the plastic zone are the rigid-flat FE's on the same mesh (matching meshes: the dual mortar
    constraint is node to node)."""
    mesh = spec(R1, contact_size=1.6e-4, refined=1.6e-3)
    material = VonMisesMaterial(ALUMINIUM.E, ALUMINIUM.nu, ALUMINIUM.sigma_y)
    pair = ContactPair.sphere_flat(ALUMINIUM, R1)
    plan = LoadPathPlan(peaks=(4 * pair.P_Y,), loading_step=pair.P_Y, first_load=0.5 * pair.P_Y)
    two = run_load_paths(TwoBodySolver(pair_mesh(mesh, mesh, cache_dir=mesh_cache), material, material), plan,
                         unload=False).loading_rows
    rigid = run_load_paths(ContactSolver(hemisphere_mesh(mesh, cache_dir=mesh_cache), material), plan,
                           unload=False).loading_rows
    assert [r["P"] for r in two] == pytest.approx([r["P"] for r in rigid], rel=1e-9)
    assert [r["alpha"] / 2 for r in two] == pytest.approx([r["alpha"] for r in rigid], rel=1e-6)
    assert [r["contact_radius"] for r in two] == pytest.approx([r["contact_radius"] for r in rigid], rel=1e-6)
    assert two[-1]["yielded_points"] == 2 * rigid[-1]["yielded_points"] > 0


@pytest.mark.parametrize("sphere, counter, R2, yields", [(ALUMINIUM, STEEL, R1 / 2, 0), (STEEL, ALUMINIUM, None, 1)])
def test_first_yield_in_the_weaker_body_at_the_pairs_hertz_load(mesh_cache, sphere, counter, R2, yields):
    """The body with the lower A_Y(nu) sigma_Y yields first (aluminium: the sphere on a steel
    sphere, the block under a steel sphere), at the P_Y of the pair's Hertz field,
    pi^3 R*^2 (A_Y sigma_Y)^3 / (6 E*^2) (Johnson 1985 eq. 3.45, Vu-Quoc & Zhang 1999 eq. 3.7),
    within 1.5 %; the other body is still elastic there (its own first yield beyond 10 P_Y)."""
    pair = (ContactPair.sphere_sphere(sphere, R1, counter, R2) if R2 is not None
            else ContactPair(R1, flat_pair(sphere, counter).E_star, counter.sigma_y, counter.nu, 1.0))
    h = pair.a_Y / 10
    counter_spec = spec(R2, h, refined=2 * pair.a_Y) if R2 is not None else spec(2 * R1, h, BlockMeshSpec, 2 * pair.a_Y)
    mesh = pair_mesh(spec(R1, h, refined=2 * pair.a_Y), counter_spec, cache_dir=mesh_cache)
    loads = first_yield_loads(mesh, elastic(sphere), elastic(counter), (sphere.sigma_y, counter.sigma_y), pair.P_Y)
    assert loads[yields] == pytest.approx(pair.P_Y, rel=1.5e-2)
    assert loads[1 - yields] > 10 * pair.P_Y


def test_counter_flags_take_their_ranges_from_the_limits_table(capsys):
    """--counter-E outside the solid range of nfd_limits.h: one line naming the flag and the range
    nfdmodel.limits states, exit code 2, before any FE work."""
    from calib.cli import main
    from nfdmodel import limits

    assert main(["hertz", "--counter-E", "1"]) == 2
    message = capsys.readouterr().err.strip()
    assert "\n" not in message and "--counter-E" in message
    assert f"{limits.E_MIN:g}" in message and f"{limits.E_MAX:g}" in message


def test_a_parameter_file_states_the_counter_body_and_is_read_back_as_the_pair(tmp_path):
    """parameter_record with the counter-body; load_parameters rebuilds the pair from it (E*, R*,
    yield point), and a file whose P_Y is the rigid flat's is refused as inconsistent."""
    import json

    from nfdmodel import VZParams, load_parameters, parameter_record

    counter = {"shape": "sphere", "E": STEEL.E, "nu": STEEL.nu, "sigma_y": None, "R": R1 / 2, "rho": STEEL.rho}
    pair = ContactPair.sphere_counter(ALUMINIUM, R1, STEEL.E, STEEL.nu, None, R1 / 2, STEEL.rho)
    record = parameter_record(VZParams(pair, 2e-7, 1e-4), R1, ALUMINIUM, counter)
    path = tmp_path / "pair.json"
    path.write_text(json.dumps(record))
    loaded_pair = load_parameters(path).pair
    assert (loaded_pair.E_star, loaded_pair.R_star, loaded_pair.P_Y) == pytest.approx((pair.E_star, R1 / 3, pair.P_Y))
    record["P_Y"] = ContactPair.sphere_flat(ALUMINIUM, R1).P_Y
    path.write_text(json.dumps(record))
    with pytest.raises(ValueError, match="P_Y"):
        load_parameters(path)


def test_calibrate_plans_the_pair_before_any_fe(capsys):
    """nfdcal calibrate --dry-run with a counter-body: the load plan in units of the pair's P_Y
    (nfdmodel.ContactPair.sphere_counter), the counter-body named, no FE run."""
    import json

    from calib.cli import main

    assert main(["calibrate", "--dry-run", "--json", "--counter-E", f"{STEEL.E:g}", "--counter-nu", f"{STEEL.nu:g}"]) == 0
    plan = json.loads(capsys.readouterr().out)
    assert main(["calibrate", "--dry-run", "--counter-E", f"{STEEL.E:g}", "--counter-nu", f"{STEEL.nu:g}"]) == 0
    text = capsys.readouterr().out
    pair = ContactPair.sphere_counter(Material.reference(), R1, STEEL.E, STEEL.nu)
    assert f"P_Y = {pair.P_Y:.4g} N" in text and "counter-body: flat" in text
    assert "on_E2e+11_nu0.28_sy-elastic_flat" in json.dumps(plan)


def test_dry_run_counts_the_dofs_of_both_bodies(tmp_path):
    """The --dry-run estimate of a two-body FE (calib.scenes.plan.fe_dofs) against the meshed pair:
    the sphere's and the block's dofs, each estimated without meshing, add up to the pair mesh's
    (P2: two dofs per node) within 15 %."""
    from calib.fit import recipe
    from calib.fit.counter import CounterBody
    from calib.scenes.plan import fe_dofs
    from meshes.hemisphere import estimate_dofs

    counter = CounterBody(STEEL.E, STEEL.nu)
    calibration = recipe.calibration_spec(ALUMINIUM, R1, counter=counter, contact_size=4e-4)
    sphere, block = calibration.mesh, counter.mesh_spec(calibration.mesh)
    meshed = 2 * pair_mesh(sphere, block, cache_dir=tmp_path).mesh.doflocs.shape[1]
    assert estimate_dofs(sphere) + estimate_dofs(block) == pytest.approx(meshed, rel=0.15)
    planned, _ = fe_dofs(calibration)
    assert planned == pytest.approx(meshed, rel=0.15)
    assert planned > 1.5 * estimate_dofs(sphere)     # the counter-body is counted

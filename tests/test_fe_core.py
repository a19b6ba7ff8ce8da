"""The one FE core (calib.fe.contact_loop, calib.fe.constraint, calib.fe.quasi_static,
calib.fe.newmark, calib.fe.kinematics): press, pair press, impact and pair impact are configurations
of one loop, and a material model or a kinematics plugs in at one place.

Verified against what the core did not produce: a material written here, in the test, from the
Lame form sigma = lambda tr(eps) I + 2 mu eps (not calib.fe.material.elastic_matrix), runs unchanged
in all four configurations and gives the ElasticMaterial results (two implementations of Hooke's
law); a kinematics registered here is the one all four use; every step of each configuration passes
through the one active-set loop. Coarse meshes.
"""
import dataclasses

import numpy as np
import pytest

import calib.fe.contact_loop
import calib.fe.kinematics
from calib.fe import ContactSolver, ElasticMaterial
from calib.fe.impact import run_impact
from calib.fe.impact_pair import PairImpactSolver
from calib.fe.impact_pair_mesh import impact_pair_mesh
from calib.fe.impact_pair_run import run_pair_impact
from calib.fe.kinematics import KINEMATICS, SmallStrain, build_kinematics
from calib.fe.linsolve import FactorCache
from calib.fe.newmark import ImpactSolver
from calib.fe.two_body import TwoBodySolver
from meshes.counter_body import BlockMeshSpec, pair_mesh
from meshes.hemisphere import HemisphereMeshSpec
from meshes.sphere import SphereMeshSpec, sphere_mesh
from nfdmodel import reference_case

R, E, NU, RHO = reference_case.R, reference_case.E, reference_case.NU, reference_case.RHO
SPHERE = SphereMeshSpec(radius=R, contact_size=1.6e-4, refined_radius=1.6e-3, refined_depth=5e-4, far_size=1e-2,
                        growth=0.3)
HEMISPHERE = HemisphereMeshSpec(radius=R, contact_size=1e-4, refined_radius=2e-3, refined_depth=1e-3, far_size=R / 10)
BLOCK = BlockMeshSpec(radius=2 * R, contact_size=1e-4, refined_radius=2e-3, refined_depth=1e-3, far_size=R / 5)
P = 300.0        # [N]: a Hertz contact radius of about 0.9 mm on these meshes
V = 0.005        # [m/s]: an elastic impact (3 v_Y of the reference aluminium would yield)


@dataclasses.dataclass(frozen=True)
class LameElastic:
    """Hooke's law in Lame form, sigma = lambda tr(eps) I + 2 mu eps (engineering shear gamma_rz =
    2 eps_rz, so sigma_rz = mu gamma_rz), with its tangent by finite differences of sigma: a
    calib.fe.material.Material written here, to plug into the core."""

    E: float
    nu: float
    is_linear = True

    def initial_state(self, n_elements, n_qp):
        return None

    def _stress(self, strain):
        lam = self.E * self.nu / ((1 + self.nu) * (1 - 2 * self.nu))
        mu = self.E / (2 * (1 + self.nu))
        trace = strain[..., 0] + strain[..., 1] + strain[..., 2]
        stress = 2 * mu * strain
        stress[..., :3] += lam * trace[..., None]
        stress[..., 3] = mu * strain[..., 3]
        return stress

    def update(self, strain, committed, elements=None):
        strain = np.asarray(strain, dtype=float)
        tangent = np.stack([self._stress(np.broadcast_to(np.eye(4)[j], strain.shape).copy()) for j in range(4)],
                           axis=-1)                      # d sigma_i / d eps_j of a linear law
        return self._stress(strain), tangent, committed

    def dissipated_work(self, state, weight):
        return 0.0


@pytest.fixture(scope="module")
def meshes(mesh_cache):
    from meshes.hemisphere import hemisphere_mesh
    return {"hemisphere": hemisphere_mesh(HEMISPHERE, cache_dir=mesh_cache),
            "pair": pair_mesh(HEMISPHERE, BLOCK, cache_dir=mesh_cache),
            "sphere": sphere_mesh(SPHERE, cache_dir=mesh_cache),
            "impact_pair": impact_pair_mesh(SPHERE, SPHERE, mesh_cache)}


def configurations(meshes, material):
    """(name, figures) of each configuration with ``material`` (a factory) for every body."""
    press = ContactSolver(meshes["hemisphere"], material())
    pair = TwoBodySolver(meshes["pair"], material(), material())
    yield "press", press.solve_force(press.initial_state(), P).record
    yield "pair press", pair.solve_force(pair.initial_state(), P).record
    yield "impact", run_impact(ImpactSolver(meshes["sphere"], material(), RHO), V, steps_per_contact=20)
    yield "pair impact", run_pair_impact(PairImpactSolver(meshes["impact_pair"], material(), material(), RHO, RHO),
                                         2 * V, steps_per_contact=20)


def figures(result) -> dict:
    keys = ("alpha", "P", "contact_radius", "e", "P_max", "contact_time", "alpha_max")
    return {key: getattr(result, key) for key in keys if hasattr(result, key)}


def test_a_material_written_outside_the_fe_runs_in_every_configuration(meshes):
    """Hooke's law written here (Lame form, tangent by differences) gives ElasticMaterial's figures in
    the press, the pair press, the impact and the pair impact: the Material protocol is the one place
    a material model plugs in."""
    ours = dict(configurations(meshes, lambda: LameElastic(E, NU)))
    theirs = dict(configurations(meshes, lambda: ElasticMaterial(E, NU)))
    assert set(ours) == {"press", "pair press", "impact", "pair impact"}
    for name in ours:
        for key, value in figures(theirs[name]).items():
            assert figures(ours[name])[key] == pytest.approx(value, rel=1e-9), (name, key)


def test_every_configuration_solves_its_steps_in_the_one_loop(meshes, monkeypatch):
    """The press, the pair press, the impact and the pair impact each call calib.fe.contact_loop's
    loop, with its constraint: the rigid flat or the mortar gap."""
    seen = []
    loop = calib.fe.contact_loop.solve_contact

    def counting(solver, constraint, *args, **kwargs):
        seen.append((type(solver).__name__, type(constraint).__name__))
        return loop(solver, constraint, *args, **kwargs)

    for module in ("calib.fe.quasi_static", "calib.fe.newmark"):
        monkeypatch.setattr(f"{module}.solve_contact", counting)
    for _ in configurations(meshes, lambda: ElasticMaterial(E, NU)):
        pass
    assert set(seen) == {("ContactSolver", "RigidFlat"), ("TwoBodySolver", "MortarContact"),
                         ("ImpactSolver", "RigidFlat"), ("PairImpactSolver", "MortarContact")}


def test_a_kinematics_registered_in_its_module_is_the_one_every_configuration_uses(meshes, monkeypatch):
    """Adding a kinematics is adding a class to calib.fe.kinematics.KINEMATICS: each configuration's
    ``kinematics`` option takes it, and its strains and forces are the ones the solve uses."""
    calls = []

    class Counted(SmallStrain):
        def correction(self, material, displacement, committed):
            calls.append(type(material).__name__)
            return super().correction(material, displacement, committed)

    monkeypatch.setitem(KINEMATICS, "counted", Counted)
    press = ContactSolver(meshes["hemisphere"], LameElastic(E, NU), kinematics="counted")
    assert isinstance(press.kinematics, Counted)
    impact = ImpactSolver(meshes["sphere"], LameElastic(E, NU), RHO, kinematics="counted")
    run_impact(impact, V, steps_per_contact=10)
    assert calls and set(calls) == {"LameElastic"}
    with pytest.raises(ValueError, match="kinematics must be one of"):
        TwoBodySolver(meshes["pair"], ElasticMaterial(E, NU), ElasticMaterial(E, NU), kinematics="finite strain")
    with pytest.raises(ValueError, match="small-strain"):
        build_kinematics("large", press.elements, np.eye(4))
    assert calib.fe.kinematics.DEFAULT_KINEMATICS in KINEMATICS


def test_factorisations_are_kept_by_key_and_refactorised_while_the_pattern_repeats():
    """calib.fe.linsolve.FactorCache: a linear material's factorisation is found again by its key (no
    new one); a nonlinear one with the same pattern is refactorised numerically, bit-identical to a
    fresh factorisation; a new pattern is factorised afresh."""
    import scipy.sparse as sp

    from calib.fe.linsolve import factorize

    A = sp.diags([4.0, 5.0, 6.0]) + sp.diags([1.0, 1.0], 1) + sp.diags([1.0, 1.0], -1)
    cache = FactorCache()
    kept = cache.factor(A.tocsr(), ("force", b"1"))
    assert cache.cached(("force", b"1")) is kept and cache.count == 1
    first = cache.factor(A.tocsr(), None, b"p")
    B = (A * 2.0).tocsr()
    again = cache.factor(B, None, b"p")
    assert again is first and cache.count == 3
    b = np.array([1.0, 2.0, 3.0])
    assert np.array_equal(again.solve(b), factorize(B).solve(b))
    assert cache.factor(B, None, b"q") is not first

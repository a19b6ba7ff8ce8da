"""Shared test fixtures: the coarse reference meshes, solvers on them, the coarse calibration.

Coarse meshes keep the suite fast (seconds per FE path); the default mesh runs only in tests
marked ``slow`` (``pytest -m "not slow"`` skips them) and in the benchmarks and results/.
"""
import dataclasses

import pytest

from calib.fe import ContactSolver, ElasticMaterial, LoadPathPlan, VonMisesMaterial
from calib.fit import calibration, recipe
from meshes.hemisphere import HemisphereMeshSpec, hemisphere_mesh
from nfdmodel import ContactPair, Material, reference_case

R, E, NU, SIGMA_Y = reference_case.R, reference_case.E, reference_case.NU, reference_case.SIGMA_Y
# the reference sphere with 1.6e-4 m elements at the contact: 5-10 across it, seconds per path
COARSE = HemisphereMeshSpec(radius=R, contact_size=1.6e-4, refined_radius=1.6e-3,
                            refined_depth=5e-4, far_size=1e-2, growth=0.3)
# the Hertz formulas of the reference sphere (sigma_Y and rho do not enter them)
PAIR = ContactPair.sphere_flat(Material(E, NU, SIGMA_Y, reference_case.RHO), R)


@pytest.fixture(scope="session")
def mesh_cache(tmp_path_factory):
    """A mesh cache of the test session's own (the user's cache is never touched)."""
    return tmp_path_factory.mktemp("meshes")


@pytest.fixture(scope="session")
def coarse_mesh(mesh_cache):
    return hemisphere_mesh(COARSE, cache_dir=mesh_cache)


@pytest.fixture(scope="session")
def elastic_solver(coarse_mesh):
    return ContactSolver(coarse_mesh, ElasticMaterial(E, NU))


@pytest.fixture(scope="session")
def plastic_solver(coarse_mesh):
    return ContactSolver(coarse_mesh, VonMisesMaterial(E, NU, SIGMA_Y))


@pytest.fixture(scope="session")
def coarse_calibration():
    """The reference calibration on the coarse mesh, paths to 500 and 1000 N in 125 N steps."""
    spec = recipe.reference_spec(contact_size=COARSE.contact_size)
    spec = dataclasses.replace(spec, plan=LoadPathPlan(peaks=(500.0, 1000.0), loading_step=125.0,
                                                       unloading_steps=8, first_load=20.0))
    return calibration.calibrate(spec, meshes=1)


# a small grid scene for the sweep tests: coarse meshes, the loading branch only
TINY_GRID_SCENE = """
[scene]
name = "{name}"
[mesh]
contact_size_over_a_max = 0.12
[grid]
nu = {nu}
E_over_sigma_y = {ratio}
sigma_y = 100e6
rho = 2700.0
R = 0.1
[load_paths]
P_max_over_P_Y = [20.0]
unload = false
loading_steps = {steps}
[calibration]
"""

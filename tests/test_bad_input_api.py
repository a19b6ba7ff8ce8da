"""Bad input through the Python API (nfdmodel, the FE, meshes, parameter files): a ValueError or
FileNotFoundError naming the parameter and its range, never a traceback from deep inside, NaN or
a silently accepted value. Every case is its own test.
"""
import math
from types import SimpleNamespace

import meshio
import numpy as np
import pytest

from calib.fe import ContactSolver
from calib.fe.elastic import ElasticMaterial
from calib.fe.von_mises import VonMisesMaterial
from meshes.hemisphere import HemisphereMeshSpec, hemisphere_mesh, load_msh
from nfdmodel import ContactPair, Material, VZParams, collide, get_law, load_parameters

pytestmark = pytest.mark.laws      # rerun on the numpy kernels by .ci/run (tests/test_markers.py)


@pytest.fixture(scope="module")
def api(tmp_path_factory):
    """Files and objects the Python API cases need: a contact pair, broken files, a coarse mesh."""
    tmp_path = tmp_path_factory.mktemp("api")
    corrupt = tmp_path / "corrupt.msh"
    corrupt.write_text("$MeshFormat\ngarbage")
    truncated = tmp_path / "p.json"
    truncated.write_text('{"law": "vz", "Ca": 2.3')
    empty_msh = tmp_path / "empty.msh"
    empty_msh.write_text("")
    binary = tmp_path / "binary.json"
    binary.write_bytes(b"\xff\xfe\x00garbage")
    linear_msh = tmp_path / "linear.msh"
    meshio.write_points_cells(str(linear_msh), np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]),
                              [("triangle", np.array([[0, 1, 2]]))], file_format="gmsh22", binary=False)
    mesh = hemisphere_mesh(HemisphereMeshSpec(contact_size=1.6e-4))
    return SimpleNamespace(tmp_path=tmp_path, pair=VZParams.reference().pair, empty_msh=empty_msh, binary=binary, corrupt=corrupt,
                           truncated=truncated,
                           linear_msh=linear_msh, mesh=mesh,
                           solver=ContactSolver(mesh, VonMisesMaterial(70e9, 0.3, 100e6)))


def elastic_solver(api, **options):
    return ContactSolver(api.mesh, ElasticMaterial(70e9, 0.3), **options)


# (id, call(api), text the error must contain)
API_CASES = [
    ("Material nu=0.5", lambda api: Material(70e9, 0.5, 100e6, 2700), "nu"),
    ("Material E=nan", lambda api: Material(math.nan, 0.3, 100e6, 2700), "E"),
    ("VonMises sigma_y<0", lambda api: VonMisesMaterial(70e9, 0.3, -1.0), "sigma_y"),
    ("mesh contact_size=0", lambda api: HemisphereMeshSpec(contact_size=0.0), "contact_size"),
    ("load_msh missing", lambda api: load_msh(api.tmp_path / "missing.msh"), "missing.msh"),
    ("vz force delta=nan",
     lambda api: get_law("vz").force(np.array([np.nan]), get_law("vz").initial_state(1), VZParams.reference()),
     "delta"),
    ("VZParams Kc<0", lambda api: VZParams(ContactPair.sphere_flat(Material.reference(), 0.1), 2.33e-7, -1.0), "Kc"),
    ("load_msh corrupt", lambda api: load_msh(api.corrupt), "corrupt.msh"),
    ("load_parameters truncated", lambda api: load_parameters(api.truncated), "p.json"),
    ("solve_force inf", lambda api: api.solver.solve_force(api.solver.initial_state(), math.inf), "force"),
    ("Material E=True", lambda api: Material(True, 0.3, 100e6, 2700), "E must be a number"),
    ("Material rho='heavy'", lambda api: Material(70e9, 0.3, 100e6, "heavy"), "rho must be a number"),
    ("sphere_flat R<0", lambda api: ContactPair.sphere_flat(Material.reference(), -0.1), "R out of range"),
    ("sphere_flat R=1e-200", lambda api: ContactPair.sphere_flat(Material.reference(), 1e-200), "R, rho out of range"),
    ("VZParams Ca=1e-300", lambda api: VZParams(api.pair, 1e-300, 0.0), "Ca out of range"),
    ("VZParams Kc=inf", lambda api: VZParams(api.pair, 2.33e-7, math.inf), "Kc must be finite"),
    ("VZParams Kc_hat too large", lambda api: VZParams.from_dimensionless(api.pair, 0.026, 0.5),
     "admissible range is 0 <= Kc"),
    ("vz step: NaN among 1e5 contacts named by index",
     lambda api: get_law("vz").step(np.where(np.arange(100000) == 77777, np.nan, 1e-6), get_law("vz").initial_state(100000),
                                    VZParams.reference()), "contact 77777 is nan (1 of 100000 contacts)"),
    ("vz full contact of a sphere that yields beyond its radius",
     lambda api: VZParams.from_dimensionless(ContactPair.sphere_flat(Material(70e9, 0.3, 1e11, 2700), 0.1), 0.026,
                                             0.0098).full_contact_load, "the vz law has no domain"),
    ("initial_state n=2.5", lambda api: get_law("vz").initial_state(2.5), "n must be a whole number"),
    ("get_law ' Plastic '", lambda api: get_law(" Plastic "), "law must be one of"),
    ("hertz force delta=1e300",
     lambda api: get_law("hertz").force(np.array([1e300]), get_law("hertz").initial_state(1), api.pair),
     "delta out of range: the force overflows"),
    ("collide dt=1e-300", lambda api: collide("vz", VZParams.reference(), [0.1], dt=1e-300), "dt out of range"),
    ("collide max_steps=0", lambda api: collide("vz", VZParams.reference(), [0.1], max_steps=0),
     "max_steps out of range"),
    ("load_parameters binary", lambda api: load_parameters(api.binary), "not valid JSON"),
    ("load_parameters missing", lambda api: load_parameters(api.tmp_path / "nowhere.json"), "not found"),
    ("mesh radius=True", lambda api: HemisphereMeshSpec(radius=True), "radius must be a finite number > 0"),
    ("mesh growth=2", lambda api: HemisphereMeshSpec(growth=2.0), "growth must be in (0, 1]"),
    ("mesh radius=1e-3", lambda api: HemisphereMeshSpec(radius=1e-3), "refined_radius must be in (0, radius"),
    ("load_msh empty", lambda api: load_msh(api.empty_msh), "empty.msh"),        # guards: meshio's sys.exit(1)
    ("load_msh linear", lambda api: load_msh(api.linear_msh), "no 6-node triangles"),
    ("VonMises sigma_y=nan", lambda api: VonMisesMaterial(70e9, 0.3, math.nan), "sigma_y"),
    ("VonMises nu=0.5", lambda api: VonMisesMaterial(70e9, 0.5, 100e6), "nu"),
    ("Elastic E=True", lambda api: ElasticMaterial(True, 0.3), "E must be a number (E > 0"),
    ("Elastic nu=nan", lambda api: ElasticMaterial(70e9, math.nan), "nu must be finite (nu >= 0 and nu < 0.5"),
    ("solver residual_tolerance=nan", lambda api: elastic_solver(api, residual_tolerance=math.nan),
     "residual_tolerance"),
    ("solver max_newton_iterations=2.5", lambda api: elastic_solver(api, max_newton_iterations=2.5),
     "max_newton_iterations"),
    ("solver contact_radius_method=magic", lambda api: elastic_solver(api, contact_radius_method="magic"),
     "contact_radius_method"),
    ("solver linear_solver=mumps", lambda api: elastic_solver(api, linear_solver="mumps"), "linear_solver"),
    ("solver quadrature_order=0", lambda api: elastic_solver(api, quadrature_order=0), "quadrature_order"),
    ("solver quadrature_order=4.0", lambda api: elastic_solver(api, quadrature_order=4.0), "quadrature_order"),
]


@pytest.mark.parametrize("call, needle", [c[1:] for c in API_CASES], ids=[c[0] for c in API_CASES])
def test_python_api_bad_input(call, needle, api):
    with pytest.raises((ValueError, FileNotFoundError)) as info:
        call(api)
    assert needle in str(info.value), (needle, str(info.value))


def test_float32_inputs_are_numbers_not_errors():
    """float32 scalars (from user arrays) are valid everywhere a number is."""
    f = np.float32
    assert HemisphereMeshSpec(radius=f(0.1)).radius == pytest.approx(0.1)   # guards: a float32 refused
    pair = ContactPair.sphere_flat(Material(f(70e9), f(0.3), f(100e6), f(2699)), f(0.1))
    params = VZParams(pair, f(2.33e-7), f(2.69e-4))
    result = collide("vz", params, np.array([0.05], dtype=f), dt=f(1e-6))
    assert np.isfinite(result.e_velocity).all() and 0 < result.e_velocity[0] < 1

"""Bad inputs across the CLI, scene files, mesh files and the Python API (first list;
tests/test_bad_input.py holds the second).

Each must be answered by a clear error naming the parameter (and its range where there is one):
from the CLI, exit code 2 and ONE line on stderr, never a traceback. Every case is its own test,
so a failure names its case.
"""
import math
from types import SimpleNamespace

import numpy as np
import pytest

from calib.cli import main
from calib.fe import ContactSolver
from calib.fe.von_mises import VonMisesMaterial
from meshes.hemisphere import HemisphereMeshSpec, hemisphere_mesh, load_msh
from nfdmodel import ContactPair, Material, VZParams, get_law, load_parameters

CLI_CASES = [
    (["collide", "--law", "vz", "--v-in", "0.1", "--nu", "0.5"], "nu"),
    (["collide", "--law", "vz", "--v-in", "0.1", "--E", "0"], "E"),
    (["collide", "--law", "vz", "--v-in", "0.1", "--E", "abc"], "--E"),
    (["collide", "--law", "vz", "--v-in", "nan"], "v-in"),
    (["collide", "--law", "vz", "--v-in", "0.1", "--dt", "-1e-6"], "dt"),
    (["collide", "--law", "plastic-magic", "--v-in", "0.1"], "law"),
    (["collide", "--law", "vz", "--v-in", "0.1", "--Kc=-1e-4"], "Kc"),
    (["collide", "--law", "vz", "--v-in", "0.1", "--sigma-y", "inf"], "sigma-y"),
    (["collide", "--law", "vz", "--v-in", "0.1", "--params", "/nonexistent/parameters.json"], "parameters.json"),
    (["collide", "--law", "vz", "--v-in", "0.1", "--params", "PARAMS", "--Ca", "1e-7"], "--params"),
    (["calibrate", "--quiet", "--nu", "-0.1"], "nu"),
    (["calibrate", "--quiet", "--R", "0"], "R"),
    (["calibrate", "--quiet", "--peaks", "nan"], "peaks"),
    (["calibrate", "--quiet", "--contact-size", "-1"], "contact-size"),
    (["hertz", "--E", "-70e9"], "E"),
    (["run", "/nonexistent/scene.toml"], "scene.toml"),
    (["run", "SCENE_UNKNOWN_KEY"], "colour"),
    (["run", "SCENE_BAD_NU"], "nu"),
    (["run", "SCENE_NOT_TOML"], "scene"),
    (["material", "--E", "70e9", "--nu", "0.3", "--sigma-y", "100e6", "--R", "-0.1"], "R"),
    (["material", "--E", "70e9", "--nu", "0.495", "--sigma-y", "100e6", "--R", "0.1"], "nu"),
]


@pytest.fixture
def files(tmp_path):
    params = tmp_path / "parameters.json"
    params.write_text('{"law": "vz", "Ca": 2.33e-7, "Kc": 2.69e-4, "material": '
                      '{"E": 70e9, "nu": 0.3, "sigma_y": 100e6, "rho": 2699, "R": 0.1}}')
    unknown = tmp_path / "unknown.toml"
    unknown.write_text('[scene]\nname = "x"\ncolour = "red"\n[[material]]\nname = "a"\nE = 70e9\nnu = 0.3\n'
                       'sigma_y = 100e6\nrho = 2700.0\nR = 0.1\n')
    bad_nu = tmp_path / "bad_nu.toml"
    bad_nu.write_text('[scene]\nname = "x"\n[[material]]\nname = "a"\nE = 70e9\nnu = 0.6\n'
                      'sigma_y = 100e6\nrho = 2700.0\nR = 0.1\n')
    not_toml = tmp_path / "not.toml"
    not_toml.write_text("this is [not toml")
    return {"PARAMS": str(params), "SCENE_UNKNOWN_KEY": str(unknown), "SCENE_BAD_NU": str(bad_nu),
            "SCENE_NOT_TOML": str(not_toml)}


@pytest.mark.parametrize("argv, names", CLI_CASES, ids=[" ".join(a) for a, _ in CLI_CASES])
def test_cli_bad_input_is_one_line_and_exit_code_2(argv, names, files, capsys):
    argv = [files.get(a, a) for a in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert "Traceback" not in err and len(err.splitlines()) == 1, err
    assert names in err, err


@pytest.fixture(scope="module")
def api(tmp_path_factory):
    """Broken files and a coarse-mesh solver for the Python API cases."""
    tmp_path = tmp_path_factory.mktemp("api")
    corrupt = tmp_path / "corrupt.msh"
    corrupt.write_text("$MeshFormat\ngarbage")
    truncated = tmp_path / "p.json"
    truncated.write_text('{"law": "vz", "Ca": 2.3')
    solver = ContactSolver(hemisphere_mesh(HemisphereMeshSpec(contact_size=1.6e-4)), VonMisesMaterial(70e9, 0.3, 100e6))
    return SimpleNamespace(tmp_path=tmp_path, corrupt=corrupt, truncated=truncated, solver=solver)


# (id, call(api), name the error must contain)
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
]


@pytest.mark.parametrize("call, name", [c[1:] for c in API_CASES], ids=[c[0] for c in API_CASES])
def test_python_api_bad_input(call, name, api):
    with pytest.raises((ValueError, FileNotFoundError)) as info:
        call(api)
    assert name in str(info.value), (name, str(info.value))

"""Issue 6: a list of bad inputs across the CLI, scene files, mesh files and the Python API.

Each must be answered by a clear error naming the parameter (and its range where there is one):
from the CLI, exit code 2 and ONE line on stderr, never a traceback.
"""
import math

import numpy as np
import pytest

from calib.cli import main

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


@pytest.mark.parametrize("argv, names", CLI_CASES, ids=[" ".join(a[:1] + a[-2:]) for a, _ in CLI_CASES])
def test_cli_bad_input_is_one_line_and_exit_code_2(argv, names, files, capsys):
    argv = [files.get(a, a) for a in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert "Traceback" not in err and len(err.splitlines()) == 1, err
    assert names in err, err


def test_python_api_bad_inputs(tmp_path):
    from calib.fe import ContactSolver
    from calib.fe.von_mises import VonMisesMaterial
    from meshes.hemisphere import HemisphereMeshSpec, hemisphere_mesh, load_msh
    from nfdmodel import ContactPair, Material, VZParams, get_law, load_parameters

    cases = [
        (lambda: Material(70e9, 0.5, 100e6, 2700), "nu"),
        (lambda: Material(math.nan, 0.3, 100e6, 2700), "E"),
        (lambda: VonMisesMaterial(70e9, 0.3, -1.0), "sigma_y"),
        (lambda: HemisphereMeshSpec(contact_size=0.0), "contact_size"),
        (lambda: load_msh(tmp_path / "missing.msh"), "missing.msh"),
        (lambda: get_law("vz").force(np.array([np.nan]), get_law("vz").initial_state(1), VZParams.reference()), "delta"),
        (lambda: VZParams(ContactPair.sphere_flat(Material.reference(), 0.1), 2.33e-7, -1.0), "Kc"),
    ]
    corrupt = tmp_path / "corrupt.msh"
    corrupt.write_text("$MeshFormat\ngarbage")
    cases.append((lambda: load_msh(corrupt), "corrupt.msh"))
    truncated = tmp_path / "p.json"
    truncated.write_text('{"law": "vz", "Ca": 2.3')
    cases.append((lambda: load_parameters(truncated), "p.json"))
    solver = ContactSolver(hemisphere_mesh(HemisphereMeshSpec(contact_size=1.6e-4)), VonMisesMaterial(70e9, 0.3, 100e6))
    cases.append((lambda: solver.solve_force(solver.initial_state(), math.inf), "force"))
    for call, name in cases:
        with pytest.raises((ValueError, FileNotFoundError)) as info:
            call()
        assert name in str(info.value), (name, str(info.value))

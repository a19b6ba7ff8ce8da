"""Bad input, second list (tests/test_bad_inputs_everywhere.py and test_nfd_cli.py hold the
first): each bad input gets a clear error naming the parameter and its range. From the CLI: exit
code 2, ONE line on stderr, no traceback. Most of these once gave a traceback (OverflowError,
ZeroDivisionError), an endless loop, NaN, or a silently accepted value. Every case is its own
test, so a failure names its case.
"""
import json
import math
import os
import subprocess
import sys
from types import SimpleNamespace

import meshio
import numpy as np
import pytest

from calib import output
from calib.cli import main
from calib.fe import ContactSolver
from calib.fe.elastic import ElasticMaterial
from calib.fe.von_mises import VonMisesMaterial
from meshes.hemisphere import HemisphereMeshSpec, hemisphere_mesh, load_msh
from nfdmodel import ContactPair, Material, VZParams, collide, get_law, load_parameters

# (argv, text the one-line error must contain)
CLI_CASES = [
    # collide: values that passed validation but broke deep inside
    (["collide", "--v-in", "0.1", "--dt", "1e-300"], "dt out of range"),              # endless loop
    (["collide", "--v-in", "1e300"], "v_in out of range"),                              # "delta must be finite"
    (["collide", "--v-in", "1e-300"], "v_in out of range"),                             # NaN to integer
    (["collide", "--v-in", "0.1", "--R", "1e200"], "R out of range for a particle"),    # OverflowError traceback
    (["collide", "--v-in", "0.1", "--E", "1e-300"], "E out of range for a solid"),      # ZeroDivisionError traceback
    (["collide", "--v-in", "0.1", "--sigma-y", "1e300"], "sigma_y out of range for a solid"),  # OverflowError traceback
    (["collide", "--v-in", "0.1", "--E", "70"], "did you give GPa? 70 GPa = 7e+10 Pa"),  # "Ca out of range" before
    (["collide", "--v-in", "1e10"], "v_in out of range for an impact"),                   # "dt out of range" before
    (["collide", "--v-in", "0.1", "--Ca", "1e300"], "Ca out of range"),                 # NaN in the checks
    (["collide", "--v-in", "0.1", "--Kc", "0.01"], "admissible range is 0 <= Kc <="),   # loading curve turns back
    (["collide", "--v-in", "0.1", "--dt", "1e-3"], "stability limit"),                  # e > 1 before
    (["collide", "--law", "walton-braun", "--v-in", "0.1", "--K1", "2e8", "--K2", "1e8"], "K2 out of range"),
    (["collide", "--v-in", "0.1", "--out", "somewhere"], "--out applies to --report only"),
    (["collide", "--v-in", "0.1", "--params", "PARAMS_NAN"], "Ca must be finite"),
    (["collide", "--v-in", "0.1", "--params", "PARAMS_BOOL"], "rho must be a number"),  # rho = true was 1.0
    (["collide", "--v-in", "0.1", "--params", "PARAMS_EMPTY"], "not valid JSON"),
    (["collide", "--v-in", "0.1", "--params", "PARAMS_INCOMPLETE"], "missing key(s) R"),
    (["collide", "--v-in", "0.1", "--params", "PARAMS_STALE"], "P_Y must be a finite number"),
    (["collide", "--v-in", "0.1", "--params", "PARAMS_DIR"], "not found"),
    (["collide", "--v-in", "0.1", "--params", "PARAMS_NAN", "--nu", "0.3"], "do not combine it with --nu"),
    # hertz (FE validation): checked before any FE work
    (["hertz", "--P-min", "10", "--P-max", "5"], "--P-max must be > --P-min"),
    (["hertz", "--steps", "1"], "--steps must be in [2, 1000]"),
    (["hertz", "--nu", "0.5"], "--nu out of range: need --nu >= 0 and --nu < 0.5"),
    (["hertz", "--R", "nan"], "--R must be finite (--R > 0 m)"),
    (["hertz", "--contact-size", "inf"], "--contact-size"),
    (["hertz", "--E", "abc"], "--E must be a number"),     # material flags are parsed like every command's
]

# argparse's own errors: SystemExit(2) from the parser, one line
ARGPARSE_CASES = [(["hertz", "--steps", "2.5"], "--steps"), (["collide", "--v-in"], "--v-in"),
                  (["no-such-command"], "invalid choice")]


@pytest.fixture
def files(tmp_path):
    good = {"law": "vz", "Ca": 2.33e-7, "Kc": 2.69e-4,
            "material": {"E": 70e9, "nu": 0.3, "sigma_y": 100e6, "rho": 2699, "R": 0.1}}
    paths = {}

    def write(name, text):
        path = tmp_path / name
        path.write_text(text)
        paths[name.split(".")[0].upper()] = str(path)

    write("params_nan.json", json.dumps(good).replace("2.33e-07", "NaN"))   # json accepts NaN
    write("params_bool.json", json.dumps({**good, "material": {**good["material"], "rho": True}}))
    write("params_empty.json", "")
    write("params_incomplete.json", json.dumps({**good, "material": {k: v for k, v in good["material"].items() if k != "R"}}))
    write("params_stale.json", json.dumps({**good, "P_Y": "36.6"}))
    (tmp_path / "params_dir.json").mkdir()
    paths["PARAMS_DIR"] = str(tmp_path / "params_dir.json")
    return paths


@pytest.mark.parametrize("argv, needle", CLI_CASES, ids=[" ".join(a) for a, _ in CLI_CASES])
def test_cli_bad_input_one_line_exit_2(argv, needle, files, capsys):
    argv = [files.get(a, a) for a in argv]
    assert main(argv) == 2
    captured = capsys.readouterr()
    err = captured.err.strip()
    assert "Traceback" not in err and len(err.splitlines()) == 1, err
    assert needle in err, err
    assert captured.out == ""


@pytest.mark.parametrize("argv, needle", ARGPARSE_CASES, ids=[" ".join(a) for a, _ in ARGPARSE_CASES])
def test_cli_usage_errors_one_line_exit_2(argv, needle, capsys):
    with pytest.raises(SystemExit) as info:
        main(argv)
    assert info.value.code == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and needle in err and "Traceback" not in err, err


@pytest.mark.parametrize("argv, needle", [
    (["collide", "--v-in", "0.1", "--R", "1e200"], "R out of range for a particle"),
    (["collide", "--v-in", "0.1", "--dt", "1e-300"], "dt out of range"),
    (["collide", "--v-in", "0.1", "--dt", "-1e-6"], "dt out of range"),
    (["hertz", "--nu", "0.7"], "--nu"),
], ids=["collide R 1e200", "collide dt 1e-300", "collide dt -1e-6", "hertz nu 0.7"])
def test_cli_bad_input_in_a_real_process(argv, needle):
    """The console entry point as users run it: exit code 2, one line, no traceback."""
    proc = subprocess.run([sys.executable, "-m", "calib.cli", *argv], capture_output=True, text=True,
                          timeout=60)
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and needle in lines[0] and "Traceback" not in proc.stderr


def test_stability_command_bad_output_folder(tmp_path, monkeypatch, capsys):
    """`nfdcal stability --out FILE` fails at once (not after the run) with one line."""
    blocker = tmp_path / "a_file"
    blocker.write_text("x")
    assert main(["stability", "--out", str(blocker / "sub")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--out" in err


# ----------------------------------------------------------------------------------- Python API
@pytest.fixture(scope="module")
def api(tmp_path_factory):
    """Files and objects the Python API cases need: a contact pair, broken files, a coarse mesh."""
    tmp_path = tmp_path_factory.mktemp("api")
    empty_msh = tmp_path / "empty.msh"
    empty_msh.write_text("")
    binary = tmp_path / "binary.json"
    binary.write_bytes(b"\xff\xfe\x00garbage")
    linear_msh = tmp_path / "linear.msh"
    meshio.write_points_cells(str(linear_msh), np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]),
                              [("triangle", np.array([[0, 1, 2]]))], file_format="gmsh22", binary=False)
    return SimpleNamespace(tmp_path=tmp_path, pair=VZParams.reference().pair, empty_msh=empty_msh, binary=binary,
                           linear_msh=linear_msh, mesh=hemisphere_mesh(HemisphereMeshSpec(contact_size=1.6e-4)))


def elastic_solver(api, **options):
    return ContactSolver(api.mesh, ElasticMaterial(70e9, 0.3), **options)


# (id, call(api), text the error must contain)
API_CASES = [
    ("Material E=True", lambda api: Material(True, 0.3, 100e6, 2700), "E must be a number"),
    ("Material rho='heavy'", lambda api: Material(70e9, 0.3, 100e6, "heavy"), "rho must be a number"),
    ("sphere_flat R<0", lambda api: ContactPair.sphere_flat(Material.reference(), -0.1), "R out of range"),
    ("sphere_flat R=1e-200", lambda api: ContactPair.sphere_flat(Material.reference(), 1e-200), "R, rho out of range"),
    ("VZParams Ca=1e-300", lambda api: VZParams(api.pair, 1e-300, 0.0), "Ca out of range"),
    ("VZParams Kc=inf", lambda api: VZParams(api.pair, 2.33e-7, math.inf), "Kc must be finite"),
    ("VZParams Kc_hat too large", lambda api: VZParams.from_dimensionless(api.pair, 0.026, 0.5),
     "admissible range is 0 <= Kc"),
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
    ("load_msh empty", lambda api: load_msh(api.empty_msh), "empty.msh"),        # meshio's sys.exit(1) before
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
    assert HemisphereMeshSpec(radius=f(0.1)).radius == pytest.approx(0.1)   # rejected before
    pair = ContactPair.sphere_flat(Material(f(70e9), f(0.3), f(100e6), f(2699)), f(0.1))
    params = VZParams(pair, f(2.33e-7), f(2.69e-4))
    result = collide("vz", params, np.array([0.05], dtype=f), dt=f(1e-6))
    assert np.isfinite(result.e_velocity).all() and 0 < result.e_velocity[0] < 1


# -------------------------------------------------------------------------- interrupted writes
@pytest.mark.parametrize("interrupt", [KeyboardInterrupt, OSError])
def test_a_write_killed_midway_leaves_the_old_file_and_no_partial_one(tmp_path, monkeypatch, interrupt):
    """calib.report writes to a temporary file and renames it: an exception (Ctrl-C, disk full)
    during the write leaves the previous result intact and no temporary file behind."""
    target = tmp_path / "result.json"
    output.write_json(target, {"P_max": 1.0})
    before = target.read_text()

    def dying_fsync(fd):
        raise interrupt("killed during the write")

    monkeypatch.setattr(os, "fsync", dying_fsync)
    with pytest.raises(interrupt):
        output.write_json(target, {"P_max": 2.0, "rows": list(range(10000))})
    with pytest.raises(interrupt):
        output.write_csv(tmp_path / "new.csv", [{"a": 1.0}])
    assert target.read_text() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["result.json"]


def test_a_nan_row_never_reaches_a_result_file(tmp_path):
    with pytest.raises(ValueError, match="non-finite"):
        output.write_json(tmp_path / "r.json", {"rows": [{"e": np.float64("nan")}]})
    assert not any(tmp_path.iterdir())


@pytest.mark.parametrize("argv", [
    ["calibrate", "--peaks", "10"],                                   # below P_Y = 36.6 N
    ["calibrate", "--peaks", "20", "37"],                             # one load step above P_Y
    ["calibrate", "--E", "210e9", "--nu", "0.29", "--sigma-y", "1.2e9", "--R", "0.005", "--peaks", "1e-3"],
], ids=["below first yield", "one point above first yield", "another material below first yield"])
def test_a_plan_that_cannot_be_fitted_is_refused_before_any_fe(argv, tmp_path, capsys, monkeypatch):
    import meshes.hemisphere

    monkeypatch.setattr(meshes.hemisphere, "build_msh", lambda *a, **k: pytest.fail("meshed"))
    assert main(argv + ["--out", str(tmp_path / "out"), "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "P_max out of range" in err[0] and "smallest admissible largest P_max" in err[0]
    assert not (tmp_path / "out").exists()


def test_a_mesh_beyond_this_machine_is_refused_before_meshing(tmp_path, capsys, monkeypatch):
    """--contact-size 3e-7 (CLI): the estimate, the machine's limit and the smallest admissible
    element, before any meshing; --contact-size 1e-9 and contact_size = 1e-12 (a scene, even at
    --dry-run) are below a millionth of the radius: refused, naming the smallest element."""
    import meshes.hemisphere

    monkeypatch.setattr(meshes.hemisphere, "build_msh", lambda *a, **k: pytest.fail("meshed"))
    scene = tmp_path / "tiny.toml"
    scene.write_text('[scene]\nname = "tiny"\n[[material]]\nname = "al"\nE = 70e9\nnu = 0.3\n'
                     'sigma_y = 100e6\nrho = 2700.0\nR = 0.1\n[mesh]\ncontact_size = 1e-12\n'
                     '[load_paths]\nP_max = [500.0, 1000.0]\n[calibration]\nship = "radius"\n')
    for argv, words in ((["calibrate", "--contact-size", "3e-7", "--out", str(tmp_path / "out")], ("dofs", "GB")),
                        (["calibrate", "--contact-size", "1e-9", "--out", str(tmp_path / "out")], ("1e-07 m",)),
                        (["run", str(scene), "--dry-run"], ("1e-07 m",))):
        assert main(argv + ["--quiet"] if argv[0] == "calibrate" else argv) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "contact_size out of range" in err[0] and "need contact_size >=" in err[0]
        assert all(word in err[0] for word in words), err[0]


PARAMETER_FILE = {"law": "vz", "Ca": 2.33e-7, "Kc": 2.69e-4,
                  "material": {"E": 70e9, "nu": 0.3, "sigma_y": 100e6, "rho": 2699, "R": 0.1}}


@pytest.mark.parametrize("change, message", [
    (lambda d: d.update(kc=1e-4), "unknown key(s): 'kc'"),
    (lambda d: d["material"].update(Rho=2700), "unknown key(s) in 'material': 'Rho'"),
    (lambda d: d.update(Ca="2.33e-7"), "Ca must be a number"),
    (lambda d: d["material"].update(E="70e9"), "E must be a number"),
    (lambda d: d.pop("Kc"), "missing key(s) Kc"),
], ids=["unknown key", "unknown material key", "number as text", "material number as text", "missing key"])
def test_parameter_files_follow_one_rule(change, message, tmp_path, capsys):
    """Exact types, unknown keys named, missing keys named: one line, exit 2 (nfdcal collide)."""
    import copy
    import json

    data = copy.deepcopy(PARAMETER_FILE)
    change(data)
    path = tmp_path / "p.json"
    path.write_text(json.dumps(data))
    assert main(["collide", "--params", str(path), "--v-in", "0.05"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message in err[0], err


def test_a_radius_in_millimetres_is_named_as_such(tmp_path, capsys):
    """R = 100 in a parameter file (the reference sphere's 100 mm typed as metres): the error
    that follows (Kc out of range for that pair) names the likely slip, in one line."""
    import json

    path = tmp_path / "p.json"
    path.write_text(json.dumps({**PARAMETER_FILE, "material": {**PARAMETER_FILE["material"], "R": 100.0}}))
    assert main(["collide", "--params", str(path), "--v-in", "0.05"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "did you give mm? 100 mm = 0.1 m" in err[0], err

"""Bad input on the command line: each gets a clear error naming the parameter and its range,
exit code 2 and ONE line on stderr, never a traceback, never a silently accepted value. Every case
is its own test, so a failure names its case; the comment after a case names the failure it
guards against (an endless loop, an overflow, NaN, a misleading message).
"""
import json
import subprocess
import sys

import pytest

from calib.cli import main

# (argv, text the one-line error must contain)
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
    # the deformable counter-body: checked before any FE work, ranges from nfdmodel.limits
    (["calibrate", "--quiet", "--counter-E", "70"], "--counter-E out of range for a solid"),
    (["calibrate", "--quiet", "--counter-E", "2e11", "--counter-nu", "0.5"], "--counter-nu out of range"),
    (["calibrate", "--quiet", "--counter-E", "2e11", "--counter-sigma-y", "1e300"], "--counter-sigma-y out of range"),
    (["calibrate", "--quiet", "--counter-E", "2e11", "--counter-R", "0"], "--counter-R out of range"),
    (["calibrate", "--quiet", "--counter-R", "0.1"], "--counter-E out of range"),          # a counter-body needs E
    (["calibrate", "--quiet", "--counter-E", "2e11", "--v-max", "50"], "v_max out of range"),   # beyond the pair's reach
    (["calibrate", "--quiet", "--kinematics", "finite", "--v-max", "50"], "v_max out of range"),  # beyond the finite reach
    (["calibrate", "--quiet", "--kinematics", "finite", "--counter-E", "2e11", "--counter-sigma-y", "5e8"],
     "--kinematics finite"),                                   # a plastic counter-body is small-strain
    (["impact", "--quiet", "--kinematics", "finite", "--counter-E", "2e11", "--v-in", "0.04"], "--kinematics finite"),
    (["calibrate", "--quiet", "--kinematics", "finite", "--ladder"], "--kinematics finite"),
    (["hertz", "--counter-E", "abc"], "--counter-E"),
    (["hertz", "--counter-E", "2e11", "--ladder"], "--ladder"),
    # the counter-body that makes the case impossible is named with its range (was: "contact_size ...
    # 5.3e-09", "P_max <= 0 N", a StepNotConverged traceback)
    (["calibrate", "--quiet", "--counter-E", "2e11", "--counter-sigma-y", "1e4"],
     "--counter-sigma-y out of range for the FE: need 20 <= E2/sigma_Y2 <= 10000"),
    (["calibrate", "--quiet", "--counter-E", "1e5"], "need --counter-E >= "),
    (["hertz", "--counter-E", "1e5", "--P-max", "1"], "--P-max must be > --P-min = 1 N"),
    (["hertz", "--counter-E", "1e5", "--P-min", "0.1", "--P-max", "1"], "need --counter-E >= "),
    (["run", "/nonexistent/scene.toml"], "scene.toml"),
    (["run", "SCENE_UNKNOWN_KEY"], "colour"),
    (["run", "SCENE_BAD_NU"], "nu"),
    (["run", "SCENE_NOT_TOML"], "scene"),
    (["material", "--E", "70e9", "--nu", "0.3", "--sigma-y", "100e6", "--R", "-0.1"], "R"),
    (["material", "--E", "70e9", "--nu", "0.495", "--sigma-y", "100e6", "--R", "0.1"], "nu"),
    # collide: values that passed validation but broke deep inside
    (["collide", "--v-in", "0.1", "--dt", "1e-300"], "dt out of range"),              # guards: an endless loop
    (["collide", "--v-in", "1e300"], "v_in out of range"),                              # guards: a misleading "delta must be finite"
    (["collide", "--v-in", "1e-300"], "v_in out of range"),                             # guards: NaN cast to an integer
    (["collide", "--v-in", "0.1", "--R", "1e200"], "R out of range for a particle"),    # guards: an OverflowError traceback
    (["collide", "--v-in", "0.1", "--E", "1e-300"], "E out of range for a solid"),      # guards: a ZeroDivisionError traceback
    (["collide", "--v-in", "0.1", "--sigma-y", "1e300"], "sigma_y out of range for a solid"),  # guards: an OverflowError traceback
    (["collide", "--v-in", "0.1", "--E", "70"], "did you give GPa? 70 GPa = 7e+10 Pa"),  # guards: a misleading "Ca out of range"
    (["collide", "--v-in", "1e10"], "v_in out of range for an impact"),                   # guards: a misleading "dt out of range"
    (["collide", "--v-in", "0.1", "--Ca", "1e300"], "Ca out of range"),                 # guards: NaN inside the checks
    (["collide", "--v-in", "0.1", "--Kc", "0.01"], "admissible range is 0 <= Kc <="),   # the loading curve turns back
    (["collide", "--v-in", "0.1", "--dt", "1e-3"], "stability limit"),                  # guards: e > 1
    (["collide", "--law", "walton-braun", "--v-in", "0.1", "--K1", "2e8", "--K2", "1e8"], "K2 out of range"),
    (["collide", "--v-in", "0.1", "--out", "somewhere"], "--out applies to --report only"),
    (["collide", "--v-in", "0.1", "--params", "PARAMS_NAN"], "Ca must be finite"),
    (["collide", "--v-in", "0.1", "--params", "PARAMS_BOOL"], "rho must be a number"),  # guards: rho = true read as 1.0
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
    (["hertz", "--E", "abc"], "--E must be a number"),
    # numbers as a person writes them: float() alone reads 0_05 as 5 and 1_500 as 1500
    (["collide", "--v-in", "0_05"], "no '_' (0_05 is not 0.05)"),
    (["collide", "--v-in", "0.1", "--E", "70_000e6"], "--E must be a number"),
    (["calibrate", "--quiet", "--peaks", "1_500"], "--peaks must be a number"),
    (["calibrate", "--quiet", "--peaks", "500", "500", "--dry-run"], "need distinct forces, got 500 more than once"),
    (["calibrate", "--quiet", "--peaks", "500", "1000", "500", "--dry-run"], "got 500 more than once"),
    (["material", "--E", "70e9", "--nu", "0.3", "--sigma-y", "100_e6", "--R", "0.1"], "must be a number"),
    (["hertz", "--R", "0x1p-3"], "--R must be a number"),
    # an output that is one of the inputs: never overwritten, not even with --overwrite
    (["fit-data", "--impacts", "IMPACTS_GOOD", "--E", "70e9", "--nu", "0.3", "--R", "0.1", "--rho", "2699",
      "--params-out", "IMPACTS_GOOD", "--overwrite"], "it is the input --impacts"),
    (["fit-data", "--impacts", "IMPACTS_GOOD", "--E", "70e9", "--nu", "0.3", "--R", "0.1", "--rho", "2699",
      "--plot", "IMPACTS_LINK", "--overwrite"], "it is the input --impacts"),
    (["material", "--table", "TABLE_COPY", "--params-out", "TABLE_COPY"], "it is the input --table"),
    (["fit-data", "--impacts", "IMPACTS_UNDERSCORE", "--E", "70e9", "--nu", "0.3", "--R", "0.1", "--rho", "2699"],
     "not a number: '0_05' (digits only"),     # material flags are parsed like every command's
]

# argparse's own errors: SystemExit(2) from the parser, one line
ARGPARSE_CASES = [(["hertz", "--steps", "2.5"], "--steps"), (["collide", "--v-in"], "--v-in"),
                  (["no-such-command"], "invalid choice")]


@pytest.fixture
def files(tmp_path):
    """Input files the CLI cases name by a placeholder (PARAMS, SCENE_..., PARAMS_...)."""
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
    write("impacts_underscore.csv", "v_in,e\n0.02,0.8\n0_05,0.7\n0.1,0.65\n")
    write("impacts_good.csv", "v_in,e\n0.02,0.8\n0.05,0.7\n0.1,0.65\n")
    (tmp_path / "impacts_link.csv").symlink_to(tmp_path / "impacts_good.csv")
    paths["IMPACTS_LINK"] = str(tmp_path / "impacts_link.csv")
    write("table_copy.csv", "nu,E_over_sigma_y,Ca_hat,Kc_hat\n")
    (tmp_path / "params_dir.json").mkdir()
    paths["PARAMS_DIR"] = str(tmp_path / "params_dir.json")
    return {**paths, "PARAMS": str(params), "SCENE_UNKNOWN_KEY": str(unknown), "SCENE_BAD_NU": str(bad_nu),
            "SCENE_NOT_TOML": str(not_toml)}


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


@pytest.mark.parametrize("argv", [
    ["calibrate", "--peaks", "10"],                                   # below P_Y = 36.6 N
    ["calibrate", "--peaks", "20", "37"],                             # one load step above P_Y
    ["calibrate", "--E", "210e9", "--nu", "0.29", "--sigma-y", "1.2e9", "--R", "0.005", "--peaks", "1e-3"],
    # windows narrower than 5 P_Y (P_Y = 36.6 N): the FE ran, then a failed or energy-creating fit
    ["calibrate", "--peaks", "40", "50"], ["calibrate", "--peaks", "90"], ["calibrate", "--peaks", "50", "80"],
    ["calibrate", "--peaks", "60", "100"],
    ["calibrate", "--E", "210e9", "--nu", "0.29", "--sigma-y", "1.2e9", "--R", "0.005", "--peaks", "20", "35"],
], ids=["below first yield", "one point above first yield", "another material below first yield",
        "to 1.4 P_Y", "to 2.5 P_Y", "to 2.2 P_Y", "to 2.7 P_Y", "another material to 2 P_Y"])
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

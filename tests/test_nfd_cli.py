"""`nfdcal collide` and nfdmodel.load_parameters: output, material flags, parameter files, and
bad input (exit code 2, one line naming the parameter and its range; each case its own test)."""
import json
import re

import numpy as np
import pytest

from calib.cli import build_parser, main
from nfdmodel import Material, VZParams, load_parameters, parameter_record

pytestmark = pytest.mark.laws      # rerun on the numpy kernels by .ci/run (tests/test_markers.py)


def run_cli(capsys, *args):
    code = main(["collide", *args])
    out = capsys.readouterr()
    return code, out.out, out.err


def test_json_output_keys_and_values(capsys):
    code, out, err = run_cli(capsys, "--law", "vz", "--v-in", "0.02", "0.04", "--dt", "1e-6", "--json")
    assert code == 0 and err == ""
    records = json.loads(out)
    assert [set(r) for r in records] == [{"v_in", "v_out", "e_velocity", "e_energy", "P_max",
                                          "contact_time", "in_calibrated_range", "P_max_over_window", "dent",
                                          "delta_max", "dissipated_plastic"}] * 2
    assert records[1]["v_in"] == 0.04
    assert records[1]["e_velocity"] == pytest.approx(0.7589, abs=2e-4)
    assert records[1]["e_velocity"] == pytest.approx(-records[1]["v_out"] / 0.04)
    assert records[1]["e_energy"] == pytest.approx(records[1]["e_velocity"], rel=2e-3)


@pytest.mark.parametrize("law", ["vz", "thornton", "hertz", "walton-braun"])
def test_table_output_for_every_law(capsys, law):
    code, out, _ = run_cli(capsys, "--law", law, "--v-in", "0.05")
    assert code == 0
    assert "e_velocity" in out and "contact_time" in out and f"law {law}" in out


def test_material_flags_change_the_answer(capsys):
    _, ref, _ = run_cli(capsys, "--v-in", "0.05", "--dt", "1e-6", "--json")
    _, soft, _ = run_cli(capsys, "--v-in", "0.05", "--dt", "1e-6", "--json", "--sigma-y", "50e6",
                         "--R", "0.05", "--E", "70e9", "--nu", "0.3", "--rho", "2699")
    assert json.loads(soft)[0]["P_max"] < json.loads(ref)[0]["P_max"]


BAD_INPUTS = [
    (["--law", "elastic", "--v-in", "0.1"], "law must be one of"),
    (["--v-in", "0.1", "--nu", "0.5"], "nu out of range"),
    (["--v-in", "0.1", "--nu", "-0.1"], "nu out of range"),
    (["--v-in", "0.1", "--E", "0"], "E out of range"),
    (["--v-in", "0.1", "--sigma-y", "-1"], "sigma_y out of range"),
    (["--v-in", "0.1", "--R", "0"], "R out of range"),
    (["--v-in", "0.1", "--rho", "0"], "rho out of range"),
    (["--v-in", "0.1", "--Ca", "0"], "Ca out of range"),
    (["--v-in", "0.1", "--Kc=-1e-4"], "Kc out of range"),
    (["--v-in", "0.1", "--dt", "0"], "--dt out of range"),
    (["--v-in", "0.1", "--dt", "-1"], "--dt out of range"),
    (["--v-in", "nan"], "--v-in must be finite"),
    (["--v-in", "inf"], "--v-in must be finite"),
    (["--v-in", "0"], "v_in out of range"),
    (["--v-in", "abc"], "--v-in must be a number"),
    (["--v-in", "0.1", "--E", "seventy"], "--E must be a number"),
    ([], "--v-in is required"),
    (["--v-in", "0.1", "--params", "/nonexistent/params.json"], "not found"),
    (["--v-in", "0.1", "--K1", "1e8"], "walton-braun only"),
]


@pytest.mark.parametrize("args, needle", BAD_INPUTS, ids=[" ".join(a) or "no flags" for a, _ in BAD_INPUTS])
def test_bad_input_exits_2_with_one_line(capsys, args, needle):
    code, out, err = run_cli(capsys, *args)
    assert code == 2
    assert out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1 and needle in lines[0] and "Traceback" not in err


def write_parameter_file(tmp_path, **overrides):
    params = VZParams.reference()
    record = parameter_record(params, 0.1, Material.reference())
    record.update(overrides)
    path = tmp_path / "params.json"
    path.write_text(json.dumps(record))
    return path


def test_load_parameters_round_trip_and_cli(tmp_path, capsys):
    path = write_parameter_file(tmp_path, Ca=2.0e-7, Ca_hat=2.0e-7 * 36.63733200265177 / 0.00032933873920585466)
    params = load_parameters(path)
    assert params.Ca == 2.0e-7 and params.Kc == 2.69e-4 and params.pair.R_star == 0.1
    code, out, _ = run_cli(capsys, "--v-in", "0.04", "--params", str(path), "--json")
    assert code == 0 and json.loads(out)[0]["e_velocity"] > 0
    code, _, err = run_cli(capsys, "--v-in", "0.04", "--params", str(path), "--Ca", "1e-7")
    assert code == 2 and "do not combine" in err


@pytest.mark.parametrize("content, needle", [
    ("{not json", "not valid JSON"),
    ("[1, 2]", "JSON object"),
    (json.dumps({"Ca": 1e-7, "Kc": 1e-4}), "missing 'material'"),
    (json.dumps({"Ca": 1e-7, "material": {"E": 70e9, "nu": 0.3, "sigma_y": 1e8, "rho": 2699, "R": 0.1}}),
     "missing key(s) Kc"),
    (json.dumps({"law": "hertz", "Ca": 1e-7, "Kc": 0}), "law must be one of 'vz', 'vz-table', 'vz-unload'"),
], ids=["not json", "not an object", "no material", "no Kc", "law hertz"])
def test_load_parameters_bad_files(tmp_path, content, needle):
    path = tmp_path / "bad.json"
    path.write_text(content)
    with pytest.raises(ValueError, match=None) as info:
        load_parameters(path)
    assert needle in str(info.value)


@pytest.mark.parametrize("overrides, error, match", [
    ({"P_Y": 40.0}, ValueError, "P_Y"),
    ({"material": {"E": 70e9, "nu": 0.7, "sigma_y": 1e8, "rho": 2699, "R": 0.1}}, ValueError, "nu out of range"),
], ids=["P_Y inconsistent", "nu 0.7"])
def test_load_parameters_inconsistent_and_out_of_range(tmp_path, overrides, error, match):
    with pytest.raises(error, match=match):
        load_parameters(write_parameter_file(tmp_path, **overrides))


def test_load_parameters_missing_file(tmp_path):
    with pytest.raises(FileNotFoundError):
        load_parameters(tmp_path / "missing.json")


def test_report_generates_results(tmp_path, capsys, monkeypatch):
    import calib.report.collision as report

    # a short dt ladder keeps the test fast; the full ladder is what `--report` writes
    monkeypatch.setattr(report, "DT_LADDER", (2e-6, 1e-6))
    monkeypatch.setattr(report, "SWEEP_VELOCITIES", np.array([0.02, 0.1, 0.2]))
    code = main(["collide", "--report", "--out", str(tmp_path)])
    assert code == 0
    for name in ("restitution.csv", "restitution.png", "impact_v0.04.csv", "impact_v0.04.png",
                 "dt_convergence.csv", "dt_convergence.png", "summary.json"):
        assert (tmp_path / name).stat().st_size > 0
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["stamp"]["git_commit"]
    assert summary["thornton_closed_form_check"]["max_relative_error"] < 5e-3


@pytest.mark.parametrize("argv, dest, value", [
    (["collide", "--dt", "-1e-6"], "dt", "-1e-6"),                             # one value
    (["collide", "--Kc", "-1E-4", "--json"], "Kc", "-1E-4"),
    (["collide", "--v-in", "0.1", "-1e-3"], "v_in", ["0.1", "-1e-3"]),           # several values
    (["export", "lammps", "--params", "p.json", "--wall", "zlo", "-1e-3"], "wall", ["zlo", "-1e-3"]),
    (["collide", "--dt", "-.5"], "dt", "-.5"),
], ids=["dt", "Kc", "v-in", "wall", "no leading digit"])
def test_a_negative_number_may_follow_its_flag(argv, dest, value):
    assert getattr(build_parser().parse_args(argv), dest) == value


@pytest.mark.parametrize("argv", [["collide", "--law", "-vz"], ["collide", "--dt", "auto", "-1e-6"]],
                         ids=["not a number", "a stray value"])
def test_what_is_not_a_flags_value_stays_a_usage_error(argv, capsys):
    with pytest.raises(SystemExit) as info:
        main(argv)
    assert info.value.code == 2 and len(capsys.readouterr().err.strip().splitlines()) == 1


@pytest.mark.parametrize("angles", [[], ["--angle", "10", "30"]])
def test_a_coarse_time_step_is_one_warning_line(capsys, angles):
    """nfdcal collide --dt of 6 steps per contact (the head-on and the oblique impacts): e off the
    converged e by more than 1e-3, one warning line naming the steps per contact and a dt that
    resolves it (nfd_limits.h's NFD_STEPS_PER_CONTACT_MIN, nfdmodel.collide's TimeStepWarning);
    at 100 steps per contact no warning."""
    from nfdmodel import collision_reference, limits

    contact = float(collision_reference("vz", VZParams.reference(), [0.05]).contact_time_estimate[0])
    e = {}
    for per_contact in (6, 100, 2000):
        code, out, err = run_cli(capsys, "--law", "vz", "--v-in", "0.05", "--dt", repr(contact / per_contact),
                                 "--json", *angles)
        assert code == 0
        e[per_contact] = json.loads(out)[0]["e_n" if angles else "e_velocity"]
        coarse = [line for line in err.splitlines() if "is too large for this contact" in line]
        if per_contact == 6:
            steps = re.search(rf"\(([\d.]+) steps, need >= {limits.STEPS_PER_CONTACT_MIN}\)", coarse[0] if coarse else "")
            assert len(coarse) == 1 and steps and 5.9 < float(steps.group(1)) < 6.2, err      # oblique: cos 10 deg
            assert coarse[0].startswith("nfdcal collide: warning: dt = ") and "use dt <= " in coarse[0]
        else:
            assert coarse == [], err
    assert abs(e[6] - e[2000]) > 1e-3 and abs(e[100] - e[2000]) < 5e-4

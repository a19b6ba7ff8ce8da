"""A parameter file's rate law ("rate_law", nfdmodel/parameter_file.py): ``nfdcal collide --params`` runs the
rate-aware law it states (the same records as the flags --rate-law ... on the file without the entry),
``nfdcal export lammps`` writes the plugin's ``rate`` keyword, bad entries are refused in one line naming
the key. The plugin running the exported lines: tests/test_lammps_rate.py."""
import contextlib
import io
import json
from pathlib import Path

import pytest

from calib.cli import main
from nfdmodel import load_parameters, parameter_record
from nfdmodel.parameter_file import StatedRate, rate_law_of_file
from nfdmodel.strain_rate import CowperSymonds, JohnsonCook

pytestmark = pytest.mark.laws

SHIPPED = Path(__file__).resolve().parent.parent / "results" / "calibration" / "parameters.json"   # vz-table


def with_entry(folder: Path, entry, name: str = "rate.json") -> Path:
    data = json.loads(SHIPPED.read_text(encoding="utf-8"))
    data["rate_law"] = entry
    path = folder / name
    path.write_text(json.dumps(data))
    return path


def run_cli(*args) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(args))
    return code, out.getvalue(), err.getvalue()


def test_collide_params_runs_the_file_s_rate_law(tmp_path):
    path = with_entry(tmp_path, {"rate_law": "cowper-symonds", "D": 40.0, "q": 5.0})
    assert rate_law_of_file(path) == StatedRate(CowperSymonds(40.0, 5.0))
    code, out, _ = run_cli("collide", "--params", str(path), "--v-in", "0.01", "0.04", "--json")
    flags = run_cli("collide", "--params", str(SHIPPED), "--v-in", "0.01", "0.04", "--rate-law", "cowper-symonds",
                    "--cs-D", "40", "--cs-q", "5", "--rate-form", "fixed", "--json")     # a file without a form: fixed
    assert code == 0 and flags[0] == 0
    records, expected = json.loads(out), json.loads(flags[1])
    for record, other in zip(records, expected):
        assert record["rate_factor"] > 1.0
        for key in ("e_velocity", "P_max", "contact_time", "rate_factor", "strain_rate"):
            assert record[key] == other[key], key
    # the flags replace the file's rate law
    code, out, _ = run_cli("collide", "--params", str(path), "--v-in", "0.01", "--rate-law", "johnson-cook",
                           "--jc-C", "0.05", "--rate-form", "fixed", "--json")
    assert code == 0 and json.loads(out)[0]["rate_factor"] < json.loads(flags[1])[0]["rate_factor"]


def test_c_and_the_reference_rate_are_read_and_written(tmp_path):
    path = with_entry(tmp_path, {"rate_law": "johnson-cook", "C": 0.05, "reference_rate": 0.5, "c": 20.0})
    assert rate_law_of_file(path) == StatedRate(JohnsonCook(0.05, 0.5), "fixed", 20.0)
    code, out, _ = run_cli("export", "lammps", "--params", str(path), "--wall", "zlo", "0")
    assert code == 0
    assert f"pair_coeff 1 1 file {path.resolve()} rate johnson-cook 0.05 0.5 c 20.0" in out
    assert "fix nfd_wall all nfd/wall/vz-table zlo 0.0 file" in out and out.count(" rate johnson-cook ") == 2
    path = with_entry(tmp_path, {"rate_law": "cowper-symonds", "D": 40.4, "q": 5})
    code, out, _ = run_cli("export", "lammps", "--params", str(path))
    assert code == 0 and out.rstrip().endswith("rate cowper-symonds 40.4 5.0")
    code, out, _ = run_cli("export", "lammps", "--params", str(SHIPPED))
    assert code == 0 and " rate " not in out


def test_parameter_record_writes_the_entry(tmp_path):
    params = load_parameters(SHIPPED)
    data = json.loads(SHIPPED.read_text(encoding="utf-8"))
    entry = {"rate_law": "cowper-symonds", "D": 40.0, "q": 5.0}
    record = parameter_record(params, data["material"]["R"], _material(data), rate_law=entry)
    path = tmp_path / "written.json"
    path.write_text(json.dumps(record))
    load_parameters(path)
    assert rate_law_of_file(path) == StatedRate(CowperSymonds(40.0, 5.0))


def _material(data):
    from nfdmodel import Material

    m = data["material"]
    return Material(m["E"], m["nu"], m["sigma_y"], m["rho"])


@pytest.mark.parametrize("entry, needle", [
    ({"rate_law": "power", "D": 1.0}, "rate_law must be an object with rate_law one of johnson-cook, cowper-symonds"),
    ("cowper-symonds", "rate_law must be an object"),
    ({"rate_law": "cowper-symonds", "D": -1.0, "q": 5.0}, "rate_law: D out of range"),
    ({"rate_law": "cowper-symonds", "D": 40.0, "q": "5"}, "rate_law.q must be a number"),
    ({"rate_law": "cowper-symonds", "D": 40.0, "q": 5.0, "C": 0.1}, "unknown key(s) in 'rate_law': 'C'"),
    ({"rate_law": "johnson-cook", "C": 0.05, "c": 0.0}, "rate_law: c out of range"),
])
def test_bad_entries_are_refused_naming_the_key(tmp_path, entry, needle):
    path = with_entry(tmp_path, entry)
    with pytest.raises(ValueError) as info:
        load_parameters(path)
    assert needle in str(info.value) and str(path) in str(info.value)
    code, _, err = run_cli("collide", "--params", str(path), "--v-in", "0.01")
    assert code == 2 and needle in err and "\n" not in err.strip()


def test_cli_refusals_one_line_exit_2(tmp_path):
    path = with_entry(tmp_path, {"rate_law": "cowper-symonds", "D": 40.0, "q": 5.0})
    for args, needle in ((["collide", "--params", str(path), "--v-in", "0.01", "--law", "thornton"],
                          "the file states a rate law"),
                         (["collide", "--params", str(path), "--v-in", "0.01", "--angle", "30"],
                          "states a rate law (the rate-aware law), which is for normal impacts")):
        code, _, err = run_cli(*args)
        assert code == 2 and needle in err and "\n" not in err.strip(), err

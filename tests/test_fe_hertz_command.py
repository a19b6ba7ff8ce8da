"""`nfdcal hertz` end to end on a coarse mesh: JSON keys, files, bad input."""
import json

import pytest

from calib.cli import main

TOP_KEYS = {"P", "alpha", "contact_radius", "contact_radius_hertz", "contact_radius_rel_error",
            "peak_pressure_rel_error", "alpha_rel_error", "wall_time_s"}


def test_hertz_json_and_files(tmp_path, capsys):
    code = main(["hertz", "--json", "--out", str(tmp_path), "--contact-size", "1.6e-4",
                 "--steps", "4", "--P-min", "50"])
    assert code == 0
    summary = json.loads(capsys.readouterr().out)
    top = summary["top_load"]
    assert TOP_KEYS <= set(top)
    assert top["P"] == pytest.approx(1500.0, rel=1e-4)
    assert abs(top["contact_radius_rel_error"]) < 5e-3
    assert abs(top["peak_pressure_rel_error"]) < 2e-2
    for name in ("hertz.json", "hertz_steps.csv", "pressure_profile.csv", "contact_radius.png",
                 "approach.png", "peak_pressure.png", "pressure_profile.png"):
        assert (tmp_path / name).stat().st_size > 0


@pytest.mark.parametrize("args, word", [(["--P-max", "-3"], "--P-max"), (["--nu", "0.5"], "--nu"),
                                        (["--steps", "1"], "--steps"),
                                        (["--P-min", "10", "--P-max", "5"], "--P-max")])
def test_hertz_bad_input_is_one_line_exit_2(args, word, capsys, tmp_path):
    assert main(["hertz", "--out", str(tmp_path)] + args) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and word in err

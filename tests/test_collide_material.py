"""nfdcal collide's vz constants follow the sphere the flags describe: never the reference
sphere's SI Ca, Kc (fitted for R = 0.1 m aluminium) on another sphere."""
import json

import pytest

from calib.cli import main
from nfdmodel import ContactPair, Material, VZParams, collide

STEEL = ["--E", "205e9", "--nu", "0.29", "--sigma-y", "655e6", "--rho", "7850"]


def run_json(argv, capsys):
    assert main(argv + ["--json"]) == 0, capsys.readouterr().err
    return json.loads(capsys.readouterr().out)


@pytest.mark.parametrize("radius", ["0.001", "0.02", "3"])
def test_the_reference_solid_at_another_radius_keeps_its_restitution(radius, capsys):
    """Ca_hat, Kc_hat depend on nu and E/sigma_Y only, and v_Y does not depend on R: the same
    solid at any radius has the same e(v_in) (dimensional analysis)."""
    reference = run_json(["collide", "--law", "vz", "--v-in", "0.05"], capsys)[0]
    scaled = run_json(["collide", "--law", "vz", "--v-in", "0.05", "--R", radius], capsys)[0]
    assert reference["e_velocity"] == pytest.approx(0.7282, abs=1e-3)
    assert scaled["e_velocity"] == pytest.approx(reference["e_velocity"], rel=1e-5)


@pytest.mark.parametrize("flags", [STEEL + ["--R", "0.005"], STEEL + ["--R", "0.1"],
                                   ["--E", "70e9", "--nu", "0.3", "--sigma-y", "300e6", "--R", "0.01"],
                                   ["--E", "3e9", "--nu", "0.4", "--sigma-y", "60e6", "--rho", "1200", "--R", "0.002"]],
                         ids=["steel 5 mm", "steel 0.1 m", "hard aluminium 1 cm", "polymer 2 mm"])
def test_another_material_takes_the_master_tables_constants(flags, tmp_path, capsys):
    """Material flags alone give the same impact as the parameter file nfdcal material writes for
    that material (the master table of FE calibrations), with its window."""
    params_file = tmp_path / "material.json"
    assert main(["material", *flags, "--params-out", str(params_file)]) == 0
    capsys.readouterr()
    by_flags = run_json(["collide", "--law", "vz", "--v-in", "0.05", "0.5", *flags], capsys)
    by_file = run_json(["collide", "--law", "vz", "--v-in", "0.05", "0.5", "--params", str(params_file)], capsys)
    for row_flags, row_file in zip(by_flags, by_file):
        assert row_flags["e_velocity"] == pytest.approx(row_file["e_velocity"], rel=1e-9)
        assert row_flags["in_calibrated_range"] == row_file["in_calibrated_range"]


def test_the_reference_sphere_is_unchanged(capsys):
    row = run_json(["collide", "--law", "vz", "--v-in", "0.05"], capsys)[0]
    pair = ContactPair.sphere_flat(Material.reference(), 0.1)
    expected = collide("vz", VZParams(pair, 2.33e-7, 2.69e-4, VZParams.reference().window), [0.05], dt=None)
    assert row["e_velocity"] == expected.e_velocity[0]


@pytest.mark.parametrize("argv, needle", [
    (["--E", "205e9", "--nu", "0.29", "--sigma-y", "15e6"], "outside the master table"),
    (STEEL + ["--Ca", "2.33e-7"], "--Ca, --Kc out of range: give both"),
    (STEEL + ["--Kc", "1e-4"], "--Ca, --Kc out of range: give both"),
], ids=["outside the table", "Ca alone", "Kc alone"])
def test_constants_that_cannot_follow_the_material_are_refused(argv, needle, capsys):
    assert main(["collide", "--law", "vz", "--v-in", "0.05", *argv]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and needle in err[0], err


@pytest.mark.parametrize("asked, held", [("vz", "vz-table"), ("vz-table", "vz")])
def test_a_parameter_file_of_another_law_is_named(asked, held, tmp_path, capsys):
    from nfdmodel import VZTableParams, parameter_record

    pair = ContactPair.sphere_flat(Material.reference(), 0.1)
    params = (VZTableParams(pair, (1.0, 10.0, 41.0), (0.0, 0.25, 0.9), (1.0, 1.1, 1.3)) if held == "vz-table"
              else VZParams.reference())
    path = tmp_path / "p.json"
    path.write_text(json.dumps(parameter_record(params, 0.1, Material.reference())))
    assert main(["collide", "--law", asked, "--v-in", "0.05", "--params", str(path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"the file holds the {held} law; give --law {held}" in err[0], err

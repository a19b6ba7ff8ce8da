"""The impact study's comparisons: the quasi-static FE path thrown as a collision (against Hertz's
closed form and numerical quadrature), drop tests against the FE (fit-data's file both ways), and
scenes with an [impact] stage (plan and bad input)."""
import json
import math

import numpy as np
import pytest
from scipy.integrate import quad

from calib.cli import main
from calib.fit.loop_impact import segment_time
from calib.scenes.plan import plan
from calib.scenes.schema import SceneError, parse_scene
from calib.studies import impact_drops, impact_files
from calib.studies.impact_quasistatic import thrown
from nfdmodel import ContactPair, Material

MATERIAL = {"E": 7e10, "nu": 0.3, "sigma_y": 1e8, "rho": 2699.0, "R": 0.1}


@pytest.mark.parametrize("c0, c1, c2", [(1.0, 0.5, -2.0), (1.0, -1.0, 0.3), (2.0, 3.0, 0.0), (1e-4, 2.0, -1.5),
                                        (0.0, 1.0, -0.5)])
def test_segment_time_is_the_integral(c0, c1, c2):
    """int dx / sqrt(c0 + c1 x + c2 x^2) in closed form against adaptive quadrature (the last case
    starts at a turning point: the 1/sqrt singularity)."""
    length = 0.5
    expected, _ = quad(lambda x: 1.0 / math.sqrt(c0 + c1 * x + c2 * x * x), 0.0, length, limit=200)
    assert segment_time(length, c0, c1, c2) == pytest.approx(expected, rel=1e-7)


def test_an_elastic_loop_thrown_is_hertzs_impact():
    """The Hertz curve P = K alpha^(3/2) as a load-unload path: e = 1, v_in that reaches its peak,
    and the contact time 2.868 (m^2 / (R E*^2 v_in))^(1/5) (Johnson 1985, eq. 11.24)."""
    pair = ContactPair.sphere_flat(Material(MATERIAL["E"], MATERIAL["nu"], MATERIAL["sigma_y"], MATERIAL["rho"]),
                                   MATERIAL["R"])
    m, v = pair.mass_star, 0.3 * pair.v_Y
    K = pair.hertz_stiffness
    alpha_max = (5.0 * m * v ** 2 / (4.0 * K)) ** 0.4
    alpha = np.linspace(0.0, alpha_max, 401)
    force = K * alpha ** 1.5
    path = {"loading_alpha": alpha, "loading_P": force, "unloading_alpha": alpha[::-1], "unloading_P": force[::-1],
            "fe_restitution": 1.0, "steps": 0, "dofs": 0}
    result = thrown(path, m, v)
    assert result["e"] == pytest.approx(1.0, abs=1e-12)
    assert result["v_in_quasi_static"] == pytest.approx(v, rel=1e-4)      # trapezoidal work of 400 segments
    assert result["contact_time"] == pytest.approx(float(pair.hertz_contact_time(v)), rel=1e-3)
    assert result["P_max_at_v_in"] == pytest.approx(force[-1], rel=1e-4)


def test_drop_tests_are_compared_at_their_velocity(tmp_path):
    """Tests at the FE's velocities get the FE's values; between them e is interpolated in log v_in;
    more distinct velocities than MOST_VELOCITIES are spread over their range."""
    path = tmp_path / "drops.csv"
    path.write_text("v_in,e,P_max\n0.01,0.9,100\n0.04,0.7,\n0.02,0.8,210\n")
    tests = impact_drops.read(path)
    assert impact_drops.velocities(tests) == (0.01, 0.02, 0.04)
    records = [{"v_in": 0.01, "e": 0.88, "P_max": 95.0, "contact_time": 1e-3},
               {"v_in": 0.04, "e": 0.72, "P_max": 400.0, "contact_time": 8e-4}]
    rows = {r["v_in"]: r for r in impact_drops.compare(tests, records)}
    assert rows[0.01]["e_fe"] == 0.88 and rows[0.01]["e_change"] == pytest.approx(0.02)
    assert rows[0.01]["P_max_ratio"] == pytest.approx(100.0 / 95.0 - 1.0)
    assert rows[0.02]["e_fe"] == pytest.approx(0.80)                       # halfway in log v_in
    assert rows[0.02]["P_max_fe"] == pytest.approx(math.sqrt(95.0 * 400.0))
    assert "P_max" not in rows[0.04]
    many = tmp_path / "many.csv"
    many.write_text("v_in,e\n" + "".join(f"{v:g},0.8\n" for v in np.geomspace(0.01, 0.1, 20)))
    spread = impact_drops.velocities(impact_drops.read(many))
    assert len(spread) == impact_drops.MOST_VELOCITIES and spread[0] == pytest.approx(0.01)
    assert spread[-1] == pytest.approx(0.1)


def scene(**impact):
    return parse_scene({"mesh": {"level": "coarse"}, "material": {"name": "al", **MATERIAL},
                        "impact": {"v_in_over_v_Y": [0.5, 20.0], **impact}}, "test.toml")


def test_a_scene_plans_its_impacts():
    planned = [s for s in plan(scene(error_estimate=False)) if s.stage == "impact"]
    assert len(planned) == 1 and planned[0].estimate_s > 0 and "2 FE impacts" in planned[0].detail
    with_error = [s for s in plan(scene()) if s.stage == "impact"][0]
    assert "6 FE impacts" in with_error.detail


@pytest.mark.parametrize("impact, named", [({"steps_per_contact": 5}, "impact.steps_per_contact"),
                                           ({"laws": ["vz"]}, "impact.laws"),
                                           ({"v_in_over_v_Y": [1e4]}, "impact.v_in")])
def test_a_scene_refuses_bad_impacts_in_one_line(impact, named):
    with pytest.raises(SceneError, match=named.replace(".", r"\.")) as caught:
        plan(scene(**impact))
    assert "\n" not in str(caught.value)


def test_command_runs_a_scene_impact_dry(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "s.toml").write_text('[mesh]\nlevel = "coarse"\n[[material]]\nname = "al"\nE = 7e10\nnu = 0.3\n'
                                     'sigma_y = 1e8\nrho = 2699.0\nR = 0.1\n[impact]\nv_in = [0.01]\n')
    assert main(["run", "s.toml", "--dry-run", "--json"]) == 0
    planned = json.loads(capsys.readouterr().out)
    assert "impact" in json.dumps(planned)
    assert not (tmp_path / "results").exists()


def a_results_tree(root):
    """A ./results tree whose comparison inputs are damaged: reading any of them would fail."""
    for name in ("calibration/parameters.json", "impact/vz_table/parameters.json", "lammps/restitution.csv"):
        (root / "results" / name).parent.mkdir(parents=True, exist_ok=True)
        (root / "results" / name).write_text("{ damaged", encoding="utf-8")


def test_impact_reads_no_results_tree_unless_named(tmp_path, monkeypatch, capsys):
    """nfdcal impact compares with the files its flags name and with nothing under ./results."""
    from calib.studies import impact
    from nfdmodel import VZParams, parameter_record, reference_case

    monkeypatch.chdir(tmp_path)
    a_results_tree(tmp_path)
    setup = impact.reference_setup()
    params, source = impact_files.law_parameters(setup)
    assert "results" not in source and "master table" in source
    assert impact_files.table_parameters(setup) is None and impact_files.mdr_table(setup) is None
    assert "mdr" not in impact.law_predictions(setup, 0.04, params)
    assert main(["impact", "--v-in", "0.04", "--dry-run", "--json"]) == 0
    planned = json.loads(capsys.readouterr().out)
    assert planned["compared_with"] == {"params": None, "table_params": None, "lammps_restitution": None}
    assert main(["impact", "--v-in", "0.04", "--dry-run"]) == 0
    assert "laws compared with: vz master table's constants; Thornton; Hertz" in capsys.readouterr().out

    # named, they are read: a vz file, LAMMPS' restitution
    vz = tmp_path / "vz.json"
    vz.write_text(json.dumps(parameter_record(VZParams.reference(), reference_case.R, Material.reference())))
    csv_file = tmp_path / "mdr.csv"
    csv_file.write_text("v_in_over_v_Y,e_mdr_lammps\n1.0,0.9\n100.0,0.5\n", encoding="utf-8")
    params, source = impact_files.law_parameters(setup, vz)
    assert source == "vz.json" and params.Ca == VZParams.reference().Ca
    mdr = impact_files.mdr_table(setup, csv_file)
    assert impact.law_predictions(setup, 10.0 * setup.pair.v_Y, params, mdr=mdr)["mdr"]["e"] == pytest.approx(0.7)
    assert main(["impact", "--v-in", "0.04", "--dry-run", "--params", "vz.json", "--lammps-restitution",
                 "mdr.csv"]) == 0
    assert "vz constants of vz.json; LAMMPS mdr restitution of mdr.csv" in capsys.readouterr().out
    for flags, named in ((["--lammps-restitution", "results/lammps/restitution.csv"], "not a restitution CSV"),
                         (["--lammps-restitution", "mdr.csv", "--E", "2e11"], "reference sphere"),
                         (["--table-params", "none.json"], "--table-params none.json: no such file")):
        assert main(["impact", "--v-in", "0.04", "--dry-run", *flags]) == 2
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and named in err


def test_collision_report_reads_no_results_tree_unless_named(tmp_path, monkeypatch):
    """nfdcal collide --report: the paper's constants unless --params names a file."""
    import calib.report.collision as report

    monkeypatch.chdir(tmp_path)
    a_results_tree(tmp_path)
    monkeypatch.setattr(report, "DT_LADDER", (2e-6, 1e-6))
    monkeypatch.setattr(report, "SWEEP_VELOCITIES", np.array([0.02, 0.1]))
    out, source = report.generate(tmp_path / "collision")
    assert source == "paper (Vu-Quoc & Zhang 1999)"
    assert json.loads((out / "summary.json").read_text())["params_source"] == source

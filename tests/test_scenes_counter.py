"""Scenes with a deformable counter-body: the [hertz.counter], [calibration.counter] and
[impact.counter] tables (validated by calib.fit.counter.CounterBody's checks, one line, exit 2),
their plan, and a coarse run whose stages use the pair (checked against Hertz with the pair's E*)."""
import json
import math

import pytest

from calib import scenes
from calib.scenes.schema import stage_pair
from test_scenes import MATERIAL, nfdcal, write  # tests/, on the path under pytest

STEEL = "E = 210e9\nnu = 0.28\n"


@pytest.mark.parametrize("body, words", [
    (MATERIAL + "[impact]\nv_in = [0.01]\n[impact.counter]\nE = 1e30\n", ["impact.counter", "counter E", "2e+12"]),
    (MATERIAL + "[hertz]\n[hertz.counter]\nE = 2e11\nnu = 0.6\n", ["hertz.counter.nu", "out of range", "< 0.5"]),
    (MATERIAL + "[hertz]\n[hertz.counter]\nE = 2e11\nR = -1.0\n", ["hertz.counter.R", "out of range", "> 0"]),
    (MATERIAL + "[hertz]\n[hertz.counter]\nnu = 0.3\n", ["hertz.counter.E", "missing"]),
    (MATERIAL + "[impact]\nv_in = [0.01]\n[impact.counter]\nE = 2e11\ndensity = 7800.0\n",
     ["impact.counter.density", "unknown key"]),
    (MATERIAL + "[impact]\nv_in = [0.01]\n[impact.counter]\nE = 2e11\nR = 0.05\n", ["impact.counter", "rho", "density"]),
    (MATERIAL + "[impact]\nv_in = [0.01]\n[impact.counter]\nE = 2e11\nR = 0.05\nrho = 7.8\n",
     ["impact.counter", "rho", "did you give g/cm^3"]),
    (MATERIAL + "[calibration]\nv_max = 0.1\n[calibration.counter]\n" + STEEL, ["calibration", "rigid flat", "P_max"]),
    (MATERIAL + "[load_paths]\n[calibration]\n[calibration.counter]\n" + STEEL + "[collision]\nv_in = [0.01]\n",
     ["collision", "impact.counter"]),
], ids=["E beyond solids", "nu", "R", "E missing", "unknown key", "sphere without rho", "rho in g/cm^3", "with v_max",
        "with collision"])
def test_invalid_counter_table_is_one_line_exit_2(tmp_path, monkeypatch, capsys, body, words):
    path = write(tmp_path, body)
    with pytest.raises(ValueError) as info:
        scenes.load_scene(path)
    message = str(info.value)
    assert str(path) in message and "\n" not in message
    for word in words:
        assert word in message, message
    assert nfdcal(monkeypatch, "run", "--dry-run", path) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("nfdcal run: error: scene") and len(err.splitlines()) == 1


def test_counter_defaults_to_the_sphere_s_nu_and_sets_the_stage_s_pair(tmp_path):
    scene = scenes.load_scene(write(tmp_path, MATERIAL + "[hertz]\nP_max_over_P_Y = 1.0\n[hertz.counter]\nE = 70e9\n"))
    material = scene.materials[0]
    counter = scene.hertz.counter.counter_body(material)
    assert counter.nu == 0.3 and counter.is_flat and counter.sigma_y is None
    pair = stage_pair(material, scene.hertz.counter)
    assert pair.E_star == pytest.approx(material.pair().E_star / 2, rel=1e-12)        # two equal half-spaces
    assert scene.hertz.loads(pair)[1] == pytest.approx(pair.P_Y, rel=1e-12)


def test_builtin_pair_scene_plans_every_stage_on_the_counter_body(monkeypatch, capsys):
    assert nfdcal(monkeypatch, "run", "aluminium_on_steel", "--dry-run", "--json") == 0
    plan = json.loads(capsys.readouterr().out)
    stages = {s["stage"]: s for s in plan["stages"]}
    assert set(stages) == {"hertz", "calibration", "impact"}
    assert "two-body" in stages["impact"]["detail"] and "counter-body: flat" in stages["impact"]["detail"]
    # the calibration's dofs count both bodies (calib.scenes.plan.fe_dofs)
    rigid = scenes.load_scene("reference")
    rigid_dofs = scenes.plan(rigid)[0].dofs
    assert stages["calibration"]["dofs"] > rigid_dofs


def test_coarse_pair_scene_runs_hertz_and_impact_on_the_counter_body(tmp_path, monkeypatch):
    """An elastic steel flat under the aluminium sphere: the Hertz stage's contact radius within 5 % of
    Hertz's with the pair's E* on this coarse mesh (the rigid flat's differs by 10 %: 1 / E* is 1.34x
    larger on steel); the impact stage's P_max and contact time within 2 % of Hertz's impact of the pair."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    path = write(tmp_path, """
        [scene]
        name = "pair"
        [mesh]
        contact_size = 1.6e-4
        """ + MATERIAL + """
        [hertz]
        P_min = 10.0
        P_max = 300.0
        steps = 3
        [hertz.counter]
        E = 210e9
        nu = 0.28
        [impact]
        v_in = [0.002]
        steps_per_contact = 30
        error_estimate = false
        [impact.counter]
        E = 210e9
        nu = 0.28
        [outputs]
        histories = false
        """)
    scene = scenes.load_scene(path)
    summary = scenes.run_scene(scene, tmp_path / "out")
    entry = summary["materials"][0]
    assert entry["hertz"]["counter_body"]["E"] == 210e9 and "counter" in entry["hertz"]["mesh"]
    assert abs(entry["hertz"]["top_load"]["contact_radius_rel_error"]) < 0.05
    (impact,) = entry["impact"]["impacts"]
    record = json.loads((tmp_path / "out" / "impact" / "impact_pair.json").read_text())["impacts"][0]
    hertz = record["hertz"]
    E_star = 1.0 / ((1 - 0.3 ** 2) / 70e9 + (1 - 0.28 ** 2) / 210e9)
    m = 4.0 / 3.0 * math.pi * 0.1 ** 3 * 2699.0
    assert hertz["contact_time"] == pytest.approx(2.868 * (m ** 2 / (0.1 * E_star ** 2 * 0.002)) ** 0.2, rel=1e-3)
    assert impact["P_max"] == pytest.approx(hertz["P_max"], rel=0.02)          # below first yield: Hertz
    assert impact["contact_time"] == pytest.approx(hertz["contact_time"], rel=0.02)
    assert 0.99 < impact["e"] < 1.002
    assert any("impact on a counter-flat" in line for line in scenes.summary_lines(summary))

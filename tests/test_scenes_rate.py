"""Scenes with a rate-dependent sphere: a [[material]] rate_law entry reaches the dynamic FE of [impact], the
rate-aware law of [collision] and the parameter file of [calibration]; where a stage cannot carry it, the scene
is refused in one line naming the key (coarse meshes only)."""
import json

import pytest

from calib import scenes
from nfdmodel import collide, limits, load_parameters
from nfdmodel.parameter_file import rate_law_of_file
from test_scenes import MATERIAL as SCENE_MATERIAL, nfdcal, write  # tests/, on the path under pytest

# the aluminium sphere of tests/test_rate_laws.py (test_scenes' MATERIAL): R 0.1 m, its coarse dynamic FE in about
# a second
MATERIAL = "[mesh]\ncontact_size = 1.6e-4\n" + SCENE_MATERIAL
COWPER_SYMONDS = 'rate_law = "cowper-symonds"\ncs_D = 6500.0\ncs_q = 4.0\n'
# a loading-only calibration on the coarse mesh
LOADING_CALIBRATION = '[load_paths]\nP_max = [700.0]\nunload = false\nloading_steps = 8\n[calibration]\n'
COARSE = MATERIAL.replace("contact_size = 1.6e-4", 'level = "coarse"')
IMPACT = """
[collision]
v_in = [0.04]
laws = ["vz", "hertz"]
[impact]
v_in = [0.04]
error_estimate = false
quasi_static = false
steps_per_contact = 40
"""


def restitution(summary: dict) -> tuple[float, float]:
    """(the vz law's e, the dynamic FE's e) of a one-speed scene summary."""
    entry = summary["materials"][0]
    return entry["collision"]["restitution"]["vz"]["e"][0], entry["impact"]["impacts"][0]["e"]


@pytest.mark.laws
def test_the_rate_law_raises_e_in_the_law_as_in_the_dynamic_fe(tmp_path):
    """Cowper-Symonds D 6500 /s, q 4 on the aluminium sphere at 0.04 m/s (24 v_Y): the scene's dynamic FE with
    the rate law and its relaxing rate-aware vz law (the paper's constants: the reference solid), each against the
    same scene rate-independent. Measured: e 0.7653 / 0.7432 in the FE (+2.97 %), 0.7840 / 0.7589 in the law
    (+3.31 %): the rate law's share of e agrees within 0.4 %, though the coarse FE's e is 2.1-2.4 % below the
    law's."""
    rated = scenes.run_scene(scenes.load_scene(write(tmp_path, MATERIAL + COWPER_SYMONDS + IMPACT, "rated.toml")),
                             tmp_path / "rated")
    plain = scenes.run_scene(scenes.load_scene(write(tmp_path, MATERIAL + IMPACT, "plain.toml")), tmp_path / "plain")
    (law_rated, fe_rated), (law_plain, fe_plain) = restitution(rated), restitution(plain)
    rise_law, rise_fe = law_rated / law_plain, fe_rated / fe_plain
    assert 1.02 < rise_fe < 1.04 and 1.02 < rise_law < 1.05
    assert rise_law / rise_fe == pytest.approx(1.0, abs=0.01)
    case = json.loads((tmp_path / "rated" / "impact" / "impact.json").read_text())["case"]
    assert case["rate_law"] == {"rate_law": "cowper-symonds", "D": 6500.0, "q": 4.0}
    collision = rated["materials"][0]["collision"]
    assert collision["rate_form"] == "relaxing" and "rate_law" not in plain["materials"][0]["collision"]
    # the CSV states the strain rate at first contact and the relaxed factor at the turning point, vz only
    lines = [line.split(",") for line in (tmp_path / "rated" / "collision.csv").read_text().splitlines()
             if not line.startswith("#")]
    rows = [dict(zip(lines[0], line)) for line in lines[1:]]
    vz, hertz = (next(r for r in rows if r["law"] == law) for law in ("vz", "hertz"))
    assert float(vz["strain_rate"]) > 0 and 1.0 < float(vz["rate_factor"]) < 2.0
    assert hertz["strain_rate"] == "" and float(hertz["e_velocity"]) == pytest.approx(1.0, abs=1e-6)


@pytest.mark.laws
def test_rate_form_fixed_runs_the_law_collide_runs(tmp_path, monkeypatch, capsys):
    """rate_form = "fixed": the scene's e is `nfdcal collide --rate-law ... --rate-form fixed`'s for the same
    sphere (the master table's constants), not the relaxing form's (the default)."""
    text = MATERIAL + COWPER_SYMONDS + '[collision]\nv_in = [0.02, 0.08]\nlaws = ["vz"]\n'
    relaxing = scenes.run_scene(scenes.load_scene(write(tmp_path, text, "relaxing.toml")), tmp_path / "relaxing")
    fixed = scenes.run_scene(scenes.load_scene(write(tmp_path, text.replace("cs_q = 4.0", 'cs_q = 4.0\nrate_form = '
                                                                           '"fixed"'), "fixed.toml")), tmp_path / "fixed")
    e_fixed = fixed["materials"][0]["collision"]["restitution"]["vz"]["e"]
    e_relaxing = relaxing["materials"][0]["collision"]["restitution"]["vz"]["e"]
    assert all(f != pytest.approx(r, rel=1e-3) for f, r in zip(e_fixed, e_relaxing))
    assert nfdcal(monkeypatch, "collide", "--E", "70e9", "--nu", "0.3", "--sigma-y", "100e6", "--rho", "2699",
                  "--R", "0.1", "--v-in", "0.02", "0.08", "--rate-law", "cowper-symonds", "--cs-D", "6500",
                  "--cs-q", "4", "--rate-form", "fixed", "--json") == 0
    records = json.loads(capsys.readouterr().out)
    assert [r["e_velocity"] for r in records] == pytest.approx(e_fixed, rel=1e-9)


@pytest.mark.laws
def test_the_calibration_s_parameter_file_states_the_rate_law(tmp_path, monkeypatch):
    """A calibration of a rate-dependent sphere: its press is quasi-static (the rate-independent limit), and
    its parameter file states the rate law, so the file runs in `collide --params` as the scene's collisions
    did."""
    path = write(tmp_path, COARSE + COWPER_SYMONDS + LOADING_CALIBRATION
                 + '[collision]\nv_in = [0.02, 0.05]\nlaws = ["vz"]\n')
    summary = scenes.run_scene(scenes.load_scene(path), tmp_path / "out")
    entry = summary["materials"][0]
    stated = rate_law_of_file(tmp_path / "out" / "parameters.json")
    assert stated.form == "relaxing" and entry["calibration"]["rate_law"]["rate_law"] == "cowper-symonds"
    law, params = stated.law("vz", load_parameters(tmp_path / "out" / "parameters.json"))
    direct = collide(law, params, [0.02, 0.05], dt=None)
    assert entry["collision"]["restitution"]["vz"]["e"] == pytest.approx(direct.e_velocity.tolist(), rel=1e-9)


HARDENING = "hardening_modulus = 1e9\n"
REFUSALS = [
    ('cs_D = 40.0\n', "[collision]\nv_in = [0.1]\n", "material[0]: cs_D belongs to a rate law"),
    ('rate_law = "cowper-symonds"\ncs_D = 40.0\n', "[collision]\nv_in = [0.1]\n", "needs cs_D and cs_q"),
    ('rate_law = "johnson-cook"\n', "[collision]\nv_in = [0.1]\n", "'johnson-cook' needs jc_C"),
    ('rate_law = "johnson-cook"\njc_C = 0.1\ncs_q = 4.0\n', "[collision]\nv_in = [0.1]\n",
     "cs_q is a constant of rate_law 'cowper-symonds'"),
    ('rate_law = "cowper-symonds"\ncs_D = 40.0\ncs_q = 50.0\n', "[collision]\nv_in = [0.1]\n",
     f"material[0].cs_q: out of range: need >= {limits.CS_Q_MIN:g} and <= {limits.CS_Q_MAX:g}, got 50"),
    ('rate_law = "johnson-cook"\njc_C = 1.5\n', "[collision]\nv_in = [0.1]\n", "material[0].jc_C: out of range"),
    ('rate_law = "jc"\n', "[collision]\nv_in = [0.1]\n", "must be one of johnson-cook, cowper-symonds"),
    ('rate_form = "fixed"\n', "[collision]\nv_in = [0.1]\n", "rate_form belongs to a rate law"),
    (COWPER_SYMONDS, '[collision]\nv_in = [0.1]\nlaws = ["vz", "thornton"]\n', "got 'thornton'"),
    (COWPER_SYMONDS, "[impact]\nv_in = [0.01]\n[impact.counter]\nE = 2e11\n", "[impact.counter] is of rate-independent"),
    (COWPER_SYMONDS, "[load_paths]\nP_max = [700.0]\n[calibration]\n[calibration.counter]\nE = 2e11\nrho = 7800.0\n",
     "[calibration.counter] is of rate-independent"),
    (COWPER_SYMONDS + HARDENING, '[collision]\nv_in = [0.1]\nlaws = ["hertz"]\n', "measured on perfectly plastic"),
    (HARDENING, '[collision]\nv_in = [0.1]\n', "'vz' without a [calibration] takes the master table's"),
]


@pytest.mark.parametrize("material, stages, needle", REFUSALS, ids=[needle for _, _, needle in REFUSALS])
def test_a_rate_law_a_stage_cannot_carry_is_refused_in_one_line(tmp_path, monkeypatch, capsys, material, stages,
                                                                 needle):
    path = write(tmp_path, MATERIAL + material + stages)
    with pytest.raises(scenes.SceneError) as info:
        scenes.load_scene(path)
    assert needle in str(info.value) and "\n" not in str(info.value)
    assert nfdcal(monkeypatch, "run", "--dry-run", path) == 2
    err = capsys.readouterr().err.strip()
    assert needle in err and len(err.splitlines()) == 1


def test_a_table_states_the_rate_law_beside_the_rate_independent_constants(tmp_path, monkeypatch, capsys):
    """`nfdcal table --rate-law` (or a scene's rate_law): each row's constants and key are the rate-independent
    sphere's (the press is quasi-static: a finished row is reused), the rate law in a rate_law column."""
    from calib.scenes.table import tasks_for

    plain = write(tmp_path, COARSE + LOADING_CALIBRATION, "plain.toml")
    rated = write(tmp_path, COARSE + COWPER_SYMONDS + LOADING_CALIBRATION, "rated.toml")
    assert [t["key"] for t in tasks_for(scenes.load_scene(rated))] == \
        [t["key"] for t in tasks_for(scenes.load_scene(plain))]
    out = tmp_path / "table"
    assert nfdcal(monkeypatch, "table", plain, "--out", out, "--workers", "1", "--quiet", "--json") == 0
    first = json.loads(capsys.readouterr().out)
    assert "rate_law" not in first["rows"][0]
    assert nfdcal(monkeypatch, "table", plain, "--out", out, "--workers", "1", "--quiet", "--json", "--rate-law",
                  "johnson-cook", "--jc-C", "0.05", "--rate-form", "fixed") == 0
    second = json.loads(capsys.readouterr().out)
    assert second["reused"] == 1 and second["rows"][0]["Ca"] == first["rows"][0]["Ca"]
    assert second["rows"][0]["rate_law"] == "johnson-cook C 0.05 reference_rate 1 (fixed)"
    header = [line for line in (out / "table.csv").read_text().splitlines() if not line.startswith("#")][0]
    assert header.endswith(",rate_law")


@pytest.mark.parametrize("scene, flags, needle", [
    ("rated", ["--rate-law", "cowper-symonds", "--cs-D", "40", "--cs-q", "5"], "gives its spheres' rate law"),
    ("plain", ["--rate-form", "fixed"], "--rate-form is the form of the --rate-law law"),
    ("rated", ["--check-master"], "--check-master: the master table is of rate-independent spheres"),
    ("vz_master_reach", ["--rate-law", "johnson-cook", "--jc-C", "0.1"], "the vz master table is of rate-independent"),
])
def test_a_table_refuses_what_a_rate_law_cannot_go_with_in_one_line(tmp_path, monkeypatch, capsys, scene, flags,
                                                                      needle):
    text = MATERIAL + (COWPER_SYMONDS if scene == "rated" else "") + LOADING_CALIBRATION
    path = scene if scene.startswith("vz_") else write(tmp_path, text)
    assert nfdcal(monkeypatch, "table", path, "--dry-run", *flags) == 2
    err = capsys.readouterr().err.strip()
    assert needle in err and len(err.splitlines()) == 1


def test_the_plan_names_the_rate_law_and_rate_independent_plans_stay(tmp_path, monkeypatch, capsys):
    rated = write(tmp_path, MATERIAL + COWPER_SYMONDS + IMPACT, "rated.toml")
    assert nfdcal(monkeypatch, "run", rated, "--dry-run", "--json") == 0
    plan = json.loads(capsys.readouterr().out)
    assert plan["rate_laws"] == {"al": {"rate_law": "cowper-symonds", "D": 6500.0, "q": 4.0, "form": "relaxing"}}
    details = {s["stage"]: s["detail"] for s in plan["stages"]}
    assert "rate-aware (relaxing): cowper-symonds D 6500, q 4" in details["collision"]
    assert details["impact"].endswith("cowper-symonds D 6500, q 4")
    assert nfdcal(monkeypatch, "run", write(tmp_path, MATERIAL + IMPACT, "plain.toml"), "--dry-run", "--json") == 0
    plain = json.loads(capsys.readouterr().out)
    assert "rate_laws" not in plain and "cowper" not in json.dumps(plain["stages"])


@pytest.mark.laws
def test_calibrate_states_the_rate_law_in_its_parameter_file(tmp_path, capsys):
    """`nfdcal calibrate --rate-law`: the press's constants are the rate-independent sphere's (the same as
    without the flags), and the parameter file states the rate-aware law of --rate-form on the shipped law,
    which `collide --params` runs: e above the rate-independent file's at the same speeds."""
    from calib.cli import main

    common = ["calibrate", "--json", "--quiet", "--contact-size", "1.6e-4", "--peaks", "300", "--no-plots"]
    assert main(common + ["--out", str(tmp_path / "plain")]) == 0
    plain = json.loads(capsys.readouterr().out)
    assert main(common + ["--out", str(tmp_path / "rated"), "--rate-law", "cowper-symonds", "--cs-D", "6500",
                          "--cs-q", "4", "--rate-form", "fixed"]) == 0
    rated = json.loads(capsys.readouterr().out)
    assert (rated["Ca"], rated["Kc"]) == (plain["Ca"], plain["Kc"])
    # the fixed form's entry: its c, and no "form" (a file without one states the fixed law)
    assert rated["rate_law"] == {"rate_law": "cowper-symonds", "D": 6500.0, "q": 4.0, "c": limits.RATE_LENGTH_FACTOR}
    stated = rate_law_of_file(tmp_path / "rated" / "parameters.json")
    assert stated.form == "fixed" and rate_law_of_file(tmp_path / "plain" / "parameters.json") is None
    params = load_parameters(tmp_path / "rated" / "parameters.json")
    e_plain = collide("vz-table", load_parameters(tmp_path / "plain" / "parameters.json"), [0.02, 0.04], dt=None)
    e_rated = collide(*stated.law("vz-table", params), [0.02, 0.04], dt=None)
    assert all(e_rated.e_velocity > e_plain.e_velocity * 1.01)

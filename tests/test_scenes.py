"""Scenes: validation before anything runs, the dry-run plan, and leaving out what a scene does
not need (coarse meshes only)."""
import io
import json
import textwrap

import pytest

from calib import cli, scenes
from calib.commands.progress import progress_reporter
from meshes.hemisphere import estimate_dofs

COMMANDS = cli.COMMAND_MODULES + tuple(c for c in ("run", "table", "material") if c not in cli.COMMAND_MODULES)

MATERIAL = """
[[material]]
name = "al"
E = 70e9
nu = 0.3
sigma_y = 100e6
rho = 2699.0
R = 0.1
"""


def nfdcal(monkeypatch, *argv):
    monkeypatch.setattr(cli, "COMMAND_MODULES", COMMANDS)
    return cli.main([str(a) for a in argv])


def write(tmp_path, text, name="scene.toml"):
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return path


def test_builtin_scenes_validate_and_cite_their_sources():
    found = scenes.builtin_scenes()
    assert {"reference", "hertz", "steel", "copper", "master_grid"} <= set(found)
    for name, path in found.items():
        scene = scenes.load_scene(name)
        assert scene.stages()
        assert path.read_text().lstrip().startswith("#")  # a comment with the source of the values


@pytest.mark.parametrize("body, words", [
    ('[mesh]\nlevel = "coarse"\nrefinement = 2\n' + MATERIAL + "[hertz]\n", ["mesh.refinement", "unknown key", "allowed"]),
    ("[bogus]\n" + MATERIAL, ["bogus", "unknown section"]),
    (MATERIAL.replace("nu = 0.3", "nu = 0.6") + "[hertz]\n", ["material[0].nu", "out of range", "< 0.5", "0.6"]),
    (MATERIAL.replace("E = 70e9", 'E = "hard"') + "[hertz]\n", ["material[0].E", "must be a number", "str"]),
    (MATERIAL.replace("R = 0.1", "") + "[hertz]\n", ["material[0].R", "missing"]),
    ('[mesh]\nlevel = "medium"\n' + MATERIAL + "[hertz]\n", ["mesh.level", "coarse, default, fine"]),
    (MATERIAL + "[load_paths]\nP_max = [10.0]\n[calibration]\n", ["load_paths.P_max", "> 2 P_Y"]),
    (MATERIAL + "[load_paths]\nunload = 1\n", ["load_paths.unload", "true or false"]),
    (MATERIAL, ["nothing to run"]),
], ids=["unknown key", "unknown section", "nu out of range", "E a string", "R missing", "unknown mesh level",
        "loads below yield", "unload not boolean", "nothing to run"])
def test_invalid_scene_is_one_line_naming_file_and_key(tmp_path, monkeypatch, capsys, body, words):
    path = write(tmp_path, body)
    with pytest.raises(ValueError) as info:
        scenes.load_scene(path)
    message = str(info.value)
    assert str(path) in message and "\n" not in message
    for word in words:
        assert word in message
    assert nfdcal(monkeypatch, "run", "--dry-run", path) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("nfdcal run: error: scene") and len(err.splitlines()) == 1


def test_missing_scene_file_exits_2(monkeypatch, capsys, tmp_path):
    assert nfdcal(monkeypatch, "run", tmp_path / "nope.toml") == 2
    assert "scene file not found" in capsys.readouterr().err


def test_not_toml(tmp_path):
    with pytest.raises(ValueError, match="not valid TOML"):
        scenes.load_scene(write(tmp_path, "[scene\nname = 1"))


def test_dry_run_prints_stages_meshes_and_estimate(monkeypatch, capsys, tmp_path):
    path = write(tmp_path, """
        [scene]
        name = "plan"
        [mesh]
        level = "coarse"
        """ + MATERIAL + """
        [hertz]
        P_max = 1500.0
        steps = 5
        [load_paths]
        P_max = [500.0, 1000.0]
        [calibration]
        [collision]
        v_in = [0.1]
        """)
    assert nfdcal(monkeypatch, "run", "--dry-run", path) == 0
    out = capsys.readouterr().out
    for word in ("hertz", "calibration", "collision", "estimated total", "loading and unloading", "elastoplastic"):
        assert word in out
    stages = scenes.plan(scenes.load_scene(path))
    assert [s.stage for s in stages] == ["hertz", "calibration", "collision"]
    assert stages[1].dofs > 1000 and stages[1].estimate_s > 0
    assert not (tmp_path / "out").exists()  # nothing ran


def test_estimated_dofs_match_the_reference_meshes():
    """Against the meshes gmsh made (results/calibration/mesh_ladder.csv: 4,464, 6,880, 12,112 and
    27,186 dofs at 1.6e-4 ... 2e-5 m)."""
    from meshes.hemisphere import HemisphereMeshSpec

    for size, dofs in ((1.6e-4, 4464), (8e-5, 6880), (4e-5, 12112), (2e-5, 27186)):
        assert estimate_dofs(HemisphereMeshSpec(contact_size=size)) == pytest.approx(dofs, rel=0.15)


def test_elastic_only_scene_never_runs_the_return_mapping_nor_unloads(tmp_path, monkeypatch):
    import calib.fe.loadpath
    import calib.fe.von_mises

    def forbidden(*args, **kwargs):
        raise AssertionError("must not be called by an elastic-only, loading-only scene")

    monkeypatch.setattr(calib.fe.von_mises, "radial_return", forbidden)
    monkeypatch.setattr(calib.fe.von_mises, "VonMisesMaterial", forbidden)
    monkeypatch.setattr(calib.fe.loadpath.LoadPathPlan, "unloading_targets", forbidden)
    path = write(tmp_path, """
        [scene]
        name = "elastic"
        [mesh]
        level = "coarse"
        """ + MATERIAL + """
        [hertz]
        P_min = 1.0
        P_max = 30.0
        steps = 3
        [load_paths]
        P_max_over_P_Y = [0.8]
        unload = false
        loading_steps = 4
        [outputs]
        histories = false
        """)
    scene = scenes.load_scene(path)
    assert not scenes.plastic_needed(scene, scene.materials[0])
    summary = scenes.run_scene(scene, tmp_path / "out")
    entry = summary["materials"][0]
    assert entry["load_paths"]["elastic"] and not entry["load_paths"]["unload"]
    assert entry["hertz"]["top_load"]["contact_radius_rel_error"] < 0.05
    written = {p.name for p in (tmp_path / "out").iterdir()}
    assert written == {"hertz.json", "load_paths.json", "scene.json"}  # no plots, no histories


def test_loading_only_calibration_and_collision(tmp_path, monkeypatch):
    """A loading-only calibration never unloads; its Ca, Kc drive the collision stage."""
    import calib.fe.loadpath

    monkeypatch.setattr(calib.fe.loadpath.LoadPathPlan, "unloading_targets",
                        lambda *a: (_ for _ in ()).throw(AssertionError("unloaded")))
    path = write(tmp_path, """
        [scene]
        name = "loadonly"
        [mesh]
        level = "coarse"
        """ + MATERIAL + """
        [load_paths]
        P_max = [700.0]
        unload = false
        loading_steps = 8
        [calibration]
        [collision]
        v_in = [0.05]
        laws = ["vz", "hertz"]
        """)
    summary = scenes.run_scene(scenes.load_scene(path), tmp_path / "out")
    cal = summary["materials"][0]["calibration"]
    assert cal["loading_only"] and 0.015 < cal["Ca_hat"] < 0.035
    params = json.loads((tmp_path / "out" / "parameters.json").read_text())
    assert params["Ca"] == pytest.approx(cal["Ca"])
    rows = (tmp_path / "out" / "collision.csv").read_text()
    assert "vz" in rows and "hertz" in rows
    assert not list((tmp_path / "out").glob("*.png"))


class Terminal(io.StringIO):
    def isatty(self):
        return True


def test_progress_is_silent_off_a_terminal_or_when_quiet(capsys):
    with progress_reporter(quiet=False, total_s=10) as progress:
        progress("load step 1/3")  # pytest's stderr is not a terminal
    with progress_reporter(quiet=True, stream=Terminal()) as progress:
        progress("load step 1/3")
    assert capsys.readouterr().err == ""


@pytest.mark.parametrize("total_s", [10.0, None], ids=["with an estimate", "without"])
def test_progress_on_a_terminal_shows_the_latest_message(total_s):
    stream = Terminal()
    with progress_reporter(quiet=False, total_s=total_s, stream=stream) as progress:
        progress("material 1/2: load step 1/3")
        progress("material 1/2: load step 2/3")
    shown = stream.getvalue()
    assert "load step 2/3" in shown and "00:00" in shown   # the message and the elapsed time
    assert ("<" in shown) == (total_s is not None)          # the time left needs an estimate


def test_run_scene_names_the_material_in_each_message(tmp_path):
    """A scene with several materials prefixes every progress message with its material."""
    path = write(tmp_path, """
        [mesh]
        level = "coarse"
        """ + MATERIAL + MATERIAL.replace('"al"', '"al2"') + """
        [collision]
        v_in = [0.05]
        laws = ["hertz"]
        """)
    messages = []
    scenes.run_scene(scenes.load_scene(path), tmp_path / "out", progress=messages.append)
    assert messages and messages[0].startswith("material 1/2 (al): ") and messages[-1].startswith("material 2/2 (al2): ")


def test_run_full_calibration_scene_end_to_end(tmp_path, monkeypatch, capsys):
    """`nfdcal run` on a scene with every FE stage: Hertz validation, load paths WITH unloading,
    calibration shipping the force fit (which needs the unloading), collisions with the
    calibrated law and plots; the parameter file reproduces the printed Ca, Kc and drives
    nfdmodel directly."""
    from nfdmodel import VZTableParams, collide, load_parameters

    path = write(tmp_path, """
        [scene]
        name = "full"
        [mesh]
        level = "coarse"
        """ + MATERIAL + """
        [hertz]
        P_max = 300.0
        steps = 3
        [load_paths]
        P_max = [300.0, 600.0]
        unload = true
        loading_steps = 8
        unloading_steps = 4
        [calibration]
        ship = "force"
        [collision]
        v_in_over_v_Y = [2.0, 20.0]
        laws = ["vz", "vz-table", "thornton"]
        [outputs]
        plots = true
        histories = true
        """)
    out = tmp_path / "out"
    assert nfdcal(monkeypatch, "run", path, "--out", out, "--quiet") == 0
    text = capsys.readouterr().out        # the readable summary: a line per stage and where it went
    for word in ("hertz: at P = ", "calibration: Ca = ", "collision vz: e = ", "collision thornton: e = ",
                 f"results in {out}"):
        assert word in text
    summary = json.loads((out / "scene.json").read_text())
    cal = summary["materials"][0]["calibration"]
    assert not cal["loading_only"] and cal["shipped_fit"] == "force"
    assert 0.015 < cal["Ca_hat"] < 0.04 and 0.004 < cal["Kc_hat"] < 0.03
    params = load_parameters(out / "parameters.json")
    assert params.Ca == pytest.approx(cal["Ca"]) and params.Kc == pytest.approx(cal["Kc"])
    paths = json.loads((out / "calibration.json").read_text())["paths"]
    assert [p["P_max"] for p in paths] == pytest.approx([300.0, 600.0])
    assert all(0.6 < p["e"] < 1.0 for p in paths)
    # the scene's collisions used the calibrated law: same e as nfdmodel with the file
    rows = [line.split(",") for line in (out / "collision.csv").read_text().splitlines()
            if not line.startswith("#")]
    header, rows = rows[0], rows[1:]
    vz_rows = [dict(zip(header, r)) for r in rows if dict(zip(header, r))["law"] == "vz"]
    direct = collide("vz", params, [float(r["v_in"]) for r in vz_rows], dt=None)
    assert [float(r["e_velocity"]) for r in vz_rows] == pytest.approx(direct.e_velocity.tolist(), rel=1e-9)
    table_rows = [dict(zip(header, r)) for r in rows if dict(zip(header, r))["law"] == "vz-table"]
    table = VZTableParams(params.pair, *(tuple(cal["table"][k]) for k in ("P_over_P_Y", "a_p_over_a_Y", "C_R")))
    direct = collide("vz-table", table, [float(r["v_in"]) for r in table_rows], dt=None)
    assert [float(r["e_velocity"]) for r in table_rows] == pytest.approx(direct.e_velocity.tolist(), rel=1e-9)
    assert list(out.glob("*.png")) and list(out.glob("*.csv"))
    assert (out / "collision.png").is_file()   # the scene asked for plots: e(v_in) of its laws


def test_the_calibration_window_from_the_scene_s_impacts(tmp_path, monkeypatch, capsys):
    """[calibration] v_max_from = "collision": the load paths reach the force of the fastest
    impact, so every vz collision of the scene runs inside the calibrated window."""
    path = write(tmp_path, """
        [scene]
        name = "window"
        [mesh]
        contact_size = 1.6e-4
        """ + MATERIAL + """
        [load_paths]
        unload = false
        loading_steps = 24
        [calibration]
        v_max_from = "collision"
        [collision]
        v_in_over_v_Y = [2.0, 6.0]
        laws = ["vz"]
        """)
    out = tmp_path / "out"
    assert nfdcal(monkeypatch, "run", path, "--out", out, "--quiet") == 0
    summary = json.loads((out / "scene.json").read_text())
    calibration = summary["materials"][0]["calibration"]
    pair = scenes.load_scene(path).materials[0].pair()
    assert calibration["v_max"] == pytest.approx(6.0 * pair.v_Y)
    rows = [line.split(",") for line in (out / "collision.csv").read_text().splitlines() if not line.startswith("#")]
    column = rows[0].index("in_calibrated_range")
    assert [r[column] for r in rows[1:]] == ["True", "True"]
    # --v-max on the command line sets it for a scene too; beyond the FE's reach: refused at --dry-run
    assert nfdcal(monkeypatch, "run", path, "--v-max", "5", "--dry-run") == 2
    assert "v_max out of range" in capsys.readouterr().err


@pytest.mark.parametrize("extra, needle", [
    ('[calibration]\nv_max = 0.1\nv_max_from = "collision"\n[collision]\nv_in = [0.1]\n', "not both"),
    ('[calibration]\nv_max_from = "collision"\n', "needs a \\[collision\\] stage"),
    ('[load_paths]\nP_max = [500.0]\n[calibration]\nv_max = 0.1\n', "do not give load_paths.P_max too"),
    ('[collision]\nv_in = [0.1]\nlaws = ["vz-table"]\n', "'vz-table' takes its tables from this scene's FE"),
    ('[load_paths]\nunload = false\n[calibration]\n[collision]\nv_in = [0.1]\nlaws = ["vz-table"]\n',
     "'vz-table' takes its tables"),
    ('[load_paths]\nunload = false\n[calibration]\nship = "table"\n', "'table' fits the unloading too"),
])
def test_v_max_keys_are_checked(tmp_path, extra, needle):
    path = write(tmp_path, '[scene]\nname = "w"\n' + MATERIAL + extra)
    with pytest.raises(scenes.SceneError, match=needle):
        scenes.load_scene(path)

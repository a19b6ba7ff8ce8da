"""The vz master table (calib.fit.vz_master_table) and fit-data's vz-table model
(calib.fit.measured.table_law), checked against FE data: the shipped table's own FE nodes
(results/tables/vz_master_grid/nodes) and the FE load-unload paths of two off-grid materials
stored in tests/data/vz_master_fe.json (the checks nu0.42_E700sy and nu0.22_E2000sy of the scene
vz_master_grid; not table nodes, never made by the law)."""
import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

from calib.cli import main
from calib.fit import vz_master_build, vz_master_join, vz_master_scene
from calib.fit.measured.data import ForceApproachData, ImpactData, Measurements
from calib.fit.measured.specimen import Specimen
from calib.fit.measured.table_law import fit
from calib.fit.vz_master_check import check_material, fe_paths, material_of
from calib.fit.vz_master_table import VZMasterTable
from nfdmodel import ContactPair, Material

ROOT = Path(__file__).resolve().parent.parent
FE_DATA = Path(__file__).resolve().parent / "data" / "vz_master_fe.json"
NODES = ROOT / "results" / "tables" / "vz_master_grid" / "nodes"
FINITE = ROOT / "results" / "tables" / "vz_master_reach"      # the finite-strain nodes it joins
# bounds of the interpolated law against the stored off-grid FE paths inside its window (the
# table's .json states the figures measured on every check material)
E_BOUND, FORCE_BOUND = 0.03, 0.06
SIGMA_Y_BOUND = 0.03            # sigma_Y recovered from the stored FE data within this


@pytest.fixture(scope="module")
def table():
    return VZMasterTable.load()


@pytest.fixture(scope="module")
def fe_rows():
    return json.loads(FE_DATA.read_text(encoding="utf-8"))["rows"]


def node_rows(folder=None):
    rows = [json.loads(p.read_text(encoding="utf-8")) for p in sorted((folder or NODES).glob("*.json"))]
    return [r for r in rows if r.get("kind") == "node" and r.get("status") == "ok"]


def test_shipped_table_covers_its_grid_and_states_its_measured_accuracy(table):
    scene = vz_master_scene.load_scene("vz_master_grid")
    assert list(table.nu) == scene["nu"] and list(table.E_over_sigma_y) == scene["E_over_sigma_y"]
    assert "off-grid" in table.accuracy and table.meta["model_form"]["sigma_y"]["drops e"] > 0
    assert table.meta["accuracy_details"]["materials"] >= 6


def test_the_table_is_exact_on_its_nodes_against_each_node_fe_calibration(table):
    """On a node the table gives the node's own FE calibration: the small-strain node's below its join
    load, the finite-strain node's (results/tables/vz_master_reach) from it on (calib.fit.vz_master_join)."""
    rows = node_rows()
    # the finite-strain nodes as their scene names them (a node's record can be a ladder's level run first)
    finite = {node[:2]: r for node, r in vz_master_join.nodes_of(
        vz_master_join.scene_records(vz_master_scene.load_scene("vz_master_reach"), FINITE)).items()}
    assert len(rows) == len(finite) == table.nu.size * table.E_over_sigma_y.size
    for row in rows[:: max(1, len(rows) // 5)]:
        beyond = finite[(row["nu"], row["E_over_sigma_y"])]
        values = table.tables(row["nu"], row["E_over_sigma_y"])
        below = values["x"] < vz_master_join.join_load(row, beyond) * (1 - 1e-9)
        for node, part in ((row, below), (beyond, ~below)):
            f, g = vz_master_build.resample(node, values["x"][part])
            assert np.allclose(values["f"][part][1:], f[1:], rtol=1e-9, atol=1e-12)     # x = 1: Hertz's, exactly
            # below the lowest path g - 1 is made proportional to f (proportional_below): within 1e-3 there
            # (measured at every node: 8.3e-4 at E/sigma_Y 30, 9e-5 at 100, 1.3e-6 elsewhere)
            measured = values["x"][part] >= values["low"]
            assert np.allclose(values["g"][part][measured], g[measured], rtol=1e-9, atol=1e-12)
            assert np.allclose(values["g"][part][1:], g[1:], rtol=0.0, atol=1e-3)
        assert values["top"] <= beyond["window"]["P_max_over_P_Y"] * (1 + 1e-9)


@pytest.mark.parametrize("nu, E_over_sigma_y", [(0.2, 300.0), (0.3, 1000.0), (0.49, 5000.0)])
def test_a_ratio_a_rounding_below_a_column_is_that_column_s(table, nu, E_over_sigma_y):
    """E/sigma_Y = 300 (1 - 2e-15) (sigma_Y through exp(log(.))) reads the E/sigma_Y 300 column, as 300 does:
    the same tables, never NaN (the columns that reach a load may end at that column)."""
    exact = table.tables(nu, E_over_sigma_y)
    for ratio in (E_over_sigma_y * (1 - 2e-15), E_over_sigma_y * (1 + 2e-15)):
        near = table.tables(nu, min(ratio, table.E_over_sigma_y[-1]))
        assert near["top"] == exact["top"]
        for key in ("f", "g", "rho", "m", "f_a"):
            assert np.all(np.isfinite(near[key])) and np.allclose(near[key], exact[key], rtol=1e-9, atol=1e-12), key


@pytest.mark.parametrize("index", [0, 1])
def test_between_nodes_the_law_follows_the_off_grid_fe(table, fe_rows, index):
    compared = [c for c in check_material(fe_rows[index], table) if c["inside"]]
    assert len(compared) >= 3
    worst_e = max(abs(c["e_error"]) for c in compared)
    worst_force = max(c["force_error"] for c in compared)
    assert worst_e <= E_BOUND, compared
    assert worst_force <= FORCE_BOUND, compared


def drop_tests(row, table):
    material, R = material_of(row)
    pair = ContactPair.sphere_flat(material, R)
    window = table.law(material, R).window
    inside = [p for p in fe_paths(row) if window.P_min_over_P_Y <= p["P_max"] / pair.P_Y <= window.P_max_over_P_Y * 1.000001]
    v_in = np.array([math.sqrt(2 * p["loading_work"] / pair.mass_star) for p in inside])
    e = np.array([math.sqrt(p["unloading_work"] / p["loading_work"]) for p in inside])
    return Specimen(material.E, material.nu, R, material.rho), material.sigma_y, v_in, e, inside


@pytest.mark.parametrize("index", [0, 1])
def test_fit_data_recovers_sigma_y_from_fe_drop_tests(table, fe_rows, index):
    specimen, sigma_y, v_in, e, _ = drop_tests(fe_rows[index], table)
    data = Measurements(impacts=ImpactData("fe_drops.csv", v_in, e, None, None, np.arange(1, e.size + 1)))
    result = fit(data, specimen, table)
    assert abs(result.sigma_y / sigma_y - 1) <= SIGMA_Y_BOUND
    assert result.interval95[0] <= sigma_y <= result.interval95[1]


def test_fit_data_recovers_sigma_y_from_an_fe_force_approach_curve(table, fe_rows):
    specimen, sigma_y, _, _, inside = drop_tests(fe_rows[0], table)
    top = max(inside, key=lambda p: p["P_max"])
    data = Measurements(forces=ForceApproachData("fe_force.csv", (("fe", top["approach"], top["force"]),)))
    result = fit(data, specimen, table)
    assert abs(result.sigma_y / sigma_y - 1) <= SIGMA_Y_BOUND
    assert result.interval95[0] <= sigma_y <= result.interval95[1]


@pytest.mark.parametrize("index", [0, 1])
def test_fit_data_s_default_law_recovers_sigma_y_from_fe_drop_tests_and_names_it(table, fe_rows, index, tmp_path,
                                                                                   capsys):
    """``nfdcal fit-data`` without --law on FE-made drop tests of the two off-grid materials: the
    vz-table law, sigma_Y within SIGMA_Y_BOUND, its 95 % interval covering the truth; the summary
    names the law (JSON and text)."""
    specimen, sigma_y, v_in, e, _ = drop_tests(fe_rows[index], table)
    impacts = tmp_path / "fe_drops.csv"
    impacts.write_text("v_in,e\n" + "".join(f"{float(v)!r},{float(r)!r}\n" for v, r in zip(v_in, e)), encoding="utf-8")
    flags = ["fit-data", "--impacts", str(impacts), "--E", repr(float(specimen.E)), "--nu", repr(float(specimen.nu)),
             "--R", repr(float(specimen.R)), "--rho", repr(float(specimen.rho))]
    assert main([*flags, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["law"] == "vz-table"
    assert abs(out["sigma_y"] / sigma_y - 1) <= SIGMA_Y_BOUND
    assert out["sigma_y_interval95"][0] <= sigma_y <= out["sigma_y_interval95"][1]
    assert main(flags) == 0
    assert capsys.readouterr().out.splitlines()[0].startswith("law: vz-table")


@pytest.mark.parametrize("index", [0, 1])
def test_fit_data_recovers_sigma_y_from_fe_drop_tests_with_contact_times(table, fe_rows, index):
    """e, P_max and the contact time of each FE loop thrown as a quasi-static impact (the FE's time,
    not the law's): sigma_Y within the bound, the interval covers it, the contact time's measured
    level judges the residual."""
    from calib.fit.vz_master_check import fe_datasets

    sets = fe_datasets(fe_rows[index], table)
    d = sets["drops"]
    data = Measurements(impacts=ImpactData("fe_drops.csv", d["v_in"], d["e"], d["P_max"], d["contact_time"],
                                           np.arange(1, d["e"].size + 1)))
    result = fit(data, sets["specimen"], table)
    assert abs(result.sigma_y / sets["sigma_y"] - 1.0) < SIGMA_Y_BOUND
    assert result.interval95[0] <= sets["sigma_y"] <= result.interval95[1]
    assert result.uncertainty["kind"] == "drops e+P+t" and result.uncertainty["law_error"]["contact_time"] > 0
    assert result.consistent and "not judged" not in result.verdict


def test_a_group_whose_level_the_table_never_measured_is_not_judged(table, fe_rows):
    """Contact times against a table that states no level for them, no noise stated: the verdict
    names them as not judged (no ratio to a zero level) and judges the other groups."""
    import dataclasses

    from calib.fit.vz_master_check import fe_datasets

    form = dict(table.meta["model_form"])
    form["residual_rms"] = {k: v for k, v in form["residual_rms"].items() if "contact_time" not in k}
    blind = dataclasses.replace(table, meta={**table.meta, "model_form": form})
    sets = fe_datasets(fe_rows[0], table)
    d = sets["drops"]
    data = Measurements(impacts=ImpactData("fe_drops.csv", d["v_in"], d["e"], d["P_max"], d["contact_time"],
                                           np.arange(1, d["e"].size + 1)))
    result = fit(data, sets["specimen"], blind)
    assert "contact_time" in result.verdict and "not judged" in result.verdict
    assert not re.search(r"\de[+]\d", result.verdict)                   # no ratio to a zero level
    assert result.consistent


def test_a_residual_far_above_the_stated_noise_is_never_called_consistent(table, fe_rows):
    specimen, sigma_y, v_in, e, _ = drop_tests(fe_rows[0], table)
    skewed = np.minimum(e * np.linspace(0.8, 1.2, e.size), 1.0)      # a trend no yield stress explains
    data = Measurements(impacts=ImpactData("skewed.csv", v_in, skewed, None, None, np.arange(1, e.size + 1)))
    result = fit(data, specimen, table, noise=0.001)
    assert not result.consistent
    assert "consistent with" not in result.verdict and "agree" not in result.verdict


def test_material_v_max_gives_the_law_and_its_window(capsys):
    assert main(["material", "--E", "70e9", "--nu", "0.3", "--sigma-y", "100e6", "--R", "0.1", "--v-max", "0.05",
                 "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["law"] == "vz-table" and out["table"]["P_over_P_Y"][0] == 1.0
    assert out["window"]["P_min_over_P_Y"] <= out["P_max_of_v_max_over_P_Y"] <= out["window"]["P_max_over_P_Y"]


@pytest.mark.parametrize("argv, text", [
    (["material", "--E", "70e9", "--nu", "0.1", "--sigma-y", "100e6", "--R", "0.1", "--v-max", "0.05"], "nu"),
    (["material", "--E", "70e9", "--nu", "0.3", "--sigma-y", "100e6", "--R", "0.1", "--v-max", "50"], "v_max"),
    (["material", "--E", "70e9", "--nu", "0.3", "--sigma-y", "1e6", "--R", "0.1", "--v-max", "0.05"], "E/sigma_Y"),
    (["material", "--E", "70e9", "--nu", "0.3", "--sigma-y", "100e6", "--R", "0.1", "--v-max", "-1"], "v-max"),
    (["fit-data", "--impacts", "IMPACTS", "--E", "70e9", "--nu", "0.3", "--R", "0.1", "--rho", "2700",
      "--law", "vz-table", "--noise", "-0.1"], "noise"),
    (["fit-data", "--impacts", "IMPACTS", "--E", "70e9", "--nu", "0.3", "--R", "0.1", "--rho", "2700",
      "--law", "vz-table", "--free"], "--free"),
    (["fit-data", "--impacts", "IMPACTS", "--E", "70e9", "--nu", "0.3", "--R", "0.1", "--rho", "2700",
      "--law", "vz", "--noise", "0.01"], "--noise"),
    (["fit-data", "--impacts", "IMPACTS", "--E", "70e9", "--nu", "0.3", "--R", "0.1", "--rho", "2700",
      "--free"], "--law vz"),
    (["fit-data", "--impacts", "IMPACTS", "--E", "70e9", "--nu", "0.1", "--R", "0.1", "--rho", "2700"], "--law vz"),
    # these drops reach 3.2e4-1.3e5 P_Y, beyond the table's 1e4: the default refuses, naming both laws
    (["fit-data", "--impacts", "FAST_IMPACTS", "--E", "70e9", "--nu", "0.3", "--R", "0.1", "--rho", "2700"],
     "--law vz-table fits them"),
])
def test_bad_input_is_one_line_and_exit_2(argv, text, tmp_path, capsys):
    impacts = tmp_path / "drops.csv"
    impacts.write_text("v_in,e\n0.05,0.6\n0.1,0.55\n0.2,0.5\n", encoding="utf-8")
    fast = tmp_path / "fast_drops.csv"
    fast.write_text("v_in,e\n0.5,0.2\n1,0.15\n3,0.1\n", encoding="utf-8")
    argv = [str(impacts) if a == "IMPACTS" else str(fast) if a == "FAST_IMPACTS" else a for a in argv]
    try:
        code = main(argv)
    except SystemExit as exc:                       # argparse's own refusals
        code = exc.code
    assert code == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and text in err and "Traceback" not in err


def test_an_incomplete_grid_is_refused_and_tasks_resume_by_key(fe_rows, tmp_path):
    scene = vz_master_scene.load_scene("vz_master_grid")
    tasks = vz_master_build.tasks_for(scene)
    nodes = {t["key"]: t for t in tasks if t["kind"] == "node"}
    # a ladder level that is a node's own graded mesh and loading runs once, as the node
    shared = [c for c in scene["refine"] if vz_master_build.task(scene, c["nu"], c["E_over_sigma_y"], "refine",
                                                                 refine=c)["key"] in nodes]
    assert {(c["nu"], c["E_over_sigma_y"]) for c in shared} == {(c["nu"], c["E_over_sigma_y"]) for c in scene["refine"]}
    assert all(c["refinement"] == scene["graded"]["refinement"] for c in shared)
    assert len({t["key"] for t in tasks}) == len(tasks) == (len(scene["nu"]) * len(scene["E_over_sigma_y"])
                                                             + len(scene["checks"]) + len(scene["refine"])
                                                             - len(shared))
    assert all(t["refinement"] == scene["graded"]["refinement"] for t in tasks if t["kind"] != "refine")
    grid = [t for t in tasks if t["kind"] != "refine"]
    assert [t["E_over_sigma_y"] for t in grid] == sorted(t["E_over_sigma_y"] for t in grid)
    assert {(t["nu"], t["E_over_sigma_y"]) for t in tasks if t["kind"] == "refine"} <= {
        (t["nu"], t["E_over_sigma_y"]) for t in grid if t["kind"] == "node"}
    with pytest.raises(ValueError, match="grid nodes"):
        vz_master_build.write_master([{**fe_rows[0], "kind": "node"}], tmp_path / "t.csv", scene, "test")
    material = Material(70e9, 0.3, 100e6, 2700.0)
    assert material.E / material.sigma_y == 700.0


@pytest.mark.parametrize("entry, text", [
    ('ladder = "sideways"\nrefinement = [0.5, 1.0]', "ladder must be one of both, mesh, steps"),
    ('ladder = "mesh"\nrefinement = [0.5, 1.0]\nloading_steps_per_decade = [16.0, 32.0]',
     "loading_steps_per_decade must be one number"),
    ('ladder = "steps"\nrefinement = [0.5, 1.0]\nloading_steps_per_decade = [16.0, 32.0]',
     "refinement must be one number"),
    ('ladder = "steps"\nloading_steps_per_decade = [0.5, 32.0]', "loading_steps_per_decade must be >= 1"),
    ('ladder = "steps"\nrefinement = 0.0\nloading_steps_per_decade = [16.0, 32.0]', "refinement must be in [0.5, 4]"),
])
def test_a_bad_refine_ladder_is_refused_naming_its_field(entry, text, tmp_path, capsys):
    source = vz_master_scene.scene_path("vz_master_grid").read_text(encoding="utf-8")
    scene = tmp_path / "grid.toml"
    scene.write_text(source + "\n[[refine]]\nnu = 0.3\nE_over_sigma_y = 300.0\nelements_per_contact_radius = 25.0\n"
                     + entry + "\n", encoding="utf-8")
    with pytest.raises(ValueError, match=re.escape(text)):
        vz_master_scene.load_scene(str(scene))
    assert main(["table", str(scene), "--dry-run"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and text in err


def test_the_law_is_admissible_everywhere_in_the_table(table):
    for nu in np.linspace(table.nu[0], table.nu[-1], 5):
        for ratio in np.geomspace(table.E_over_sigma_y[0], table.E_over_sigma_y[-1], 9):
            law = table.law(Material(ratio * 100e6, float(nu), 100e6, 2700.0), 0.1)
            table.unload_law(Material(ratio * 100e6, float(nu), 100e6, 2700.0), 0.1)    # admissible too
            assert law.window.P_min_over_P_Y < law.window.P_max_over_P_Y <= law.x[-1] * (1 + 1e-12)


@pytest.mark.parametrize("nu, ratio", [(0.22, 130.37), (0.26, 169.97), (0.46, 114.18)])
def test_no_cycle_just_above_first_yield_creates_energy_between_the_nodes(table, nu, ratio):
    """Materials whose interpolated f and g - 1 were not proportional below the nodes' lowest path (PCHIP
    end slopes g'/f' > 10/3 at P_Y): cycles to 1.001-1.3 P_Y return at most the loading work, the work
    integrated here by the trapezoid rule on the law's loading curve, not taken from the law."""
    material = Material(ratio * 100e6, nu, 100e6, 2700.0)
    for law in (table.law(material, 0.1), table.unload_law(material, 0.1)):
        pair = law.pair
        force = pair.P_Y * np.linspace(0.0, 1.3, 200001)
        approach = np.asarray(law.loading_approach(force))
        taken = np.concatenate([[0.0], np.cumsum(0.5 * (force[1:] + force[:-1]) * np.diff(approach))])
        peaks = np.searchsorted(force, pair.P_Y * np.array([1.001, 1.005, 1.02, 1.1, 1.3]) * (1 - 1e-12))
        returned = law._scaled_returned_work(force[peaks] / pair.P_Y) * pair.P_Y * pair.delta_Y
        assert np.all(returned <= taken[peaks] * (1 + 1e-7))


def test_the_interval_widens_for_few_tests_as_students_t():
    """The 95 % coverage factor: Student's t at the Welch-Satterthwaite degrees of freedom. Table
    values of t(0.975, nu): 12.706 (1), 2.5706 (5), 2.2281 (10); the normal 1.96 without an
    estimated part; with half the variance stated (infinite dof) nu = 4 dof_stat."""
    from calib.fit.measured.table_law import Z95, coverage_factor

    assert coverage_factor(1e-4, 0.0, 1) == pytest.approx(12.706, abs=5e-4)
    assert coverage_factor(1e-4, 0.0, 5) == pytest.approx(2.5706, abs=5e-5)
    assert coverage_factor(1e-4, 0.0, 10) == pytest.approx(2.2281, abs=5e-5)
    assert coverage_factor(1e-4, 1e-4, 5) == pytest.approx(coverage_factor(1e-4, 0.0, 20), rel=1e-12)
    assert coverage_factor(0.0, 1e-4, 5) == Z95 and coverage_factor(1e-4, 1e-4, 0) == Z95
    assert Z95 < coverage_factor(1e-4, 0.0, 10 ** 6) < Z95 + 1e-5


def test_a_stored_node_refitted_from_its_fe_data_equals_the_fe_calibration_s_own_fit(tmp_path):
    """refit_row, from the FE data a task row keeps, gives the tables and e that the FE calibration
    (calibrate(ship="table"): the solver's own paths and works) gave: a row holding another fit
    (fit_version 1, its tables and e altered) is brought back to them without the FE; through the
    sweep runner, the stored row is rewritten in place and no task runs."""
    from calib.sweep.runner import run_sweep

    scene = {**vz_master_scene.load_scene("vz_master_grid"), "contact_size_over_a_max": 0.1, "top_over_P_Y": 30.0}
    task = vz_master_build.task(scene, 0.3, 300.0, "node")
    fresh = vz_master_build.run_task(task)
    assert fresh["status"] == "ok" and fresh["fit_version"] == vz_master_build.FIT_VERSION
    stale = {**fresh, "fit_version": 1, "table": {**fresh["table"], "g": [1.01 * g for g in fresh["table"]["g"]]},
             "paths": [{**p, "e": 1.002 * p["e"]} for p in fresh["paths"]]}
    refitted = vz_master_build.refit_row(stale)
    for key in ("x", "f", "g"):
        assert np.allclose(refitted["table"][key], fresh["table"][key], rtol=1e-12, atol=1e-15)
    assert np.allclose([p["e"] for p in refitted["paths"]], [p["e"] for p in fresh["paths"]], rtol=1e-12)
    assert refitted["window"] == pytest.approx(fresh["window"]) and vz_master_build.refit_row(refitted) is refitted
    assert vz_master_build.refit_row({**stale, "meshes": 2}) is None     # the second mesh's FE is not kept

    folder = tmp_path / "nodes"
    folder.mkdir()
    (folder / f"{task['key']}.json").write_text(json.dumps(stale), encoding="utf-8")

    def no_fe(item):
        raise AssertionError("the FE ran")

    swept = run_sweep([task], no_fe, folder, keep=vz_master_build.is_finished, refit=vz_master_build.refit_row)
    assert (swept.computed, swept.reused, swept.refitted) == (0, 1, 1)
    stored = json.loads((folder / f"{task['key']}.json").read_text(encoding="utf-8"))
    assert stored["fit_version"] == vz_master_build.FIT_VERSION
    assert np.allclose(stored["table"]["g"], fresh["table"]["g"], rtol=1e-12)


def test_a_row_the_refit_cannot_bring_to_the_current_fit_runs_again(tmp_path):
    from calib.sweep.runner import run_sweep

    (tmp_path / "a.json").write_text(json.dumps({"key": "a", "fit": 1}), encoding="utf-8")
    (tmp_path / "b.json").write_text(json.dumps({"key": "b", "fit": 2}), encoding="utf-8")
    swept = run_sweep([{"key": "a"}, {"key": "b"}], lambda task: {"key": task["key"], "fit": 2}, tmp_path,
                      refit=lambda row: row if row["fit"] == 2 else None)
    assert (swept.computed, swept.reused, swept.refitted) == (1, 1, 0)
    assert json.loads((tmp_path / "a.json").read_text(encoding="utf-8"))["fit"] == 2


def test_the_table_meets_the_targets_against_the_reference_fe_and_ships_that_figure(table):
    """The reference ladder's finest level (the node's FE on a graded mesh, 35 elements across every
    contact radius, 45 loading steps per decade: an FE the table never saw): the shipped table's law
    along its paths inside the table's window is within the targets (2 % in e, 5 % in force), and the
    table's .json states the discretisation measured there: the table's difference from the finest
    level, that level's own (Richardson) error and their sum, the bound against the converged FE."""
    from calib.fit.calibration import E_TARGET, FORCE_TARGET
    from calib.fit.path_check import law_against_path

    rows = [json.loads(p.read_text(encoding="utf-8")) for p in sorted(NODES.glob("*.json"))]
    ladder = [r for r in rows if r.get("kind") == "refine" and r.get("status") == "ok" and r.get("refinement")]
    finest = [r for r in ladder if r["refinement"] == max(x["refinement"] for x in ladder)]
    assert {r["E_over_sigma_y"] for r in finest} >= {100.0, 5000.0}
    for row in finest:
        material, R = material_of(row)
        law = table.law(material, R)
        inside = [p for p in fe_paths(row) if law.window.P_min_over_P_Y * (1 - 1e-9) <= p["P_max"] / law.pair.P_Y
                  <= law.window.P_max_over_P_Y * (1 + 1e-9)]
        assert len(inside) >= 4
        for path in inside:
            errors = law_against_path("vz-table", law, path)
            assert abs(errors["e_error"]) <= E_TARGET and errors["force_error"] <= FORCE_TARGET, (row["name"], errors)
    measured = table.meta["discretisation"]
    assert {n["E_over_sigma_y"] for n in measured["nodes"]} >= {100.0, 5000.0}
    assert all(n["order_basis"] == "observed" and len(n["refinements"]) == 3 for n in measured["nodes"])
    worst = measured["worst"]
    assert 0 < worst["table_e_change_max"] < E_TARGET and 0 < worst["table_force_change_max"] < FORCE_TARGET
    assert worst["e_error_estimate"] == pytest.approx(max(
        abs(p["table_e_change"]) + p["finest_e_error_estimate"] for n in measured["nodes"] for p in n["by_path"]))
    assert "reference FE" in table.accuracy


def _mesh_ladder(order, sizes, scale=0.3):
    """Q_h = Q + C(x) h^p at a few points x (closed form): the signed changes between successive
    meshes of ``sizes``."""
    x = np.linspace(0.5, 2.0, 7)
    values = [1.0 + scale * (1.0 + x**2) * h**order for h in sizes]
    return [values[k] - values[k + 1] for k in range(len(sizes) - 1)]


@pytest.mark.parametrize("order", [0.7, 1.0, 2.0, 3.3])
def test_the_observed_order_is_the_order_of_a_known_error_law(order):
    """Three meshes of ratio 1.4 (the reference ladder's 17.9, 25, 35 elements) on Q_h = Q + C h^p: p comes back, and
    Richardson's estimate at it is the coarse mesh's exact error."""
    from calib.fit.vz_master_check import observed_order

    h = np.array([1 / 25, 1 / 35, 1 / 49])
    d1, d2 = _mesh_ladder(order, h)
    found = observed_order(d1, d2, 1.4)
    assert found["status"] == "observed" and found["order"] == pytest.approx(order, rel=1e-9)
    exact_error = 0.3 * (1.0 + np.linspace(0.5, 2.0, 7) ** 2) * h[0] ** order
    assert found["richardson_factor"] * d1 == pytest.approx(exact_error, rel=1e-9)


def test_the_observed_order_with_unequal_ratios_solves_the_general_relation():
    from calib.fit.vz_master_check import observed_order

    h = np.array([1 / 25, 1 / 35, 1 / 60])
    d1, d2 = _mesh_ladder(1.6, h)
    found = observed_order(d1, d2, h[0] / h[1], h[1] / h[2])
    assert found["order"] == pytest.approx(1.6, rel=1e-7)


def test_an_order_outside_the_range_is_bounded_and_oscillation_gives_the_bounding_estimate():
    from calib.fit.vz_master_check import ORDER_RANGE, observed_order

    h = np.array([1 / 25, 1 / 35, 1 / 49])
    d1, d2 = _mesh_ladder(6.0, h)
    steep = observed_order(d1, d2, 1.4)
    assert steep["status"] == "bounded" and steep["order_raw"] == pytest.approx(6.0, rel=1e-6)
    assert steep["order"] == steep["order_used"] == ORDER_RANGE[1]
    lowest = 1.4 ** ORDER_RANGE[0] / (1.4 ** ORDER_RANGE[0] - 1.0)
    flipped = observed_order(d1, -0.5 * d1, 1.4)                 # the changes alternate in sign
    assert flipped["status"] == "oscillating" and flipped["order"] is None
    assert flipped["order_used"] == ORDER_RANGE[0] and flipped["richardson_factor"] == pytest.approx(lowest)
    growing = observed_order(0.5 * d1, d1, 1.4)                  # the finer change is the larger
    assert growing["status"] == "not converging" and growing["richardson_factor"] == pytest.approx(lowest)


def test_the_reference_ladder_refines_every_size_and_the_loading_steps_by_the_same_ratio():
    """The [[refine]] levels form a systematic refinement (the condition for an observed order):
    contact element, grading, growth and far-field size divided by r, loading steps multiplied by r,
    the same unloading peaks; the graded mesh puts N elements across the lowest path's contact."""
    from calib.fit import impact_window, recipe

    scene = vz_master_scene.load_scene("vz_master_grid")
    for nu, ratio in {(c["nu"], c["E_over_sigma_y"]) for c in scene["refine"]}:
        levels = sorted((c for c in scene["refine"] if (c["nu"], c["E_over_sigma_y"]) == (nu, ratio)),
                        key=lambda c: c["refinement"])
        assert len(levels) == 3
        material = vz_master_build.task(scene, nu, ratio, "node")["material"]
        pair = ContactPair.sphere_flat(material, scene["R"])
        top = min(recipe.fe_reach(pair) * (1 - vz_master_build.REACH_MARGIN), scene["top_over_P_Y"] * pair.P_Y)
        specs = [impact_window.window_spec(material, scene["R"], top,
                                           lowest_over_P_Y=vz_master_build.TABLE_LOWEST_PEAK_OVER_P_Y,
                                           elements_per_contact_radius=c["elements_per_contact_radius"],
                                           refinement=c["refinement"],
                                           loading_steps_per_decade=c["loading_steps_per_decade"] * c["refinement"])
                 for c in levels]
        base, r_base = specs[0], levels[0]["refinement"]
        low = vz_master_build.TABLE_LOWEST_PEAK_OVER_P_Y * pair.P_Y
        for c, spec in zip(levels, specs):
            r = c["refinement"] / r_base
            assert spec.plan.peaks == base.plan.peaks and spec.plan.peaks[0] == pytest.approx(low)
            assert recipe.estimated_contact_radius(pair, low) / spec.mesh.contact_size == pytest.approx(
                c["elements_per_contact_radius"] * c["refinement"])
            for field in ("contact_size", "grading", "growth", "far_size"):
                assert getattr(spec.mesh, field) == pytest.approx(getattr(base.mesh, field) / r, rel=1e-12), field
            assert math.log(spec.plan.loading_ratio) == pytest.approx(math.log(base.plan.loading_ratio) / r)


@pytest.mark.parametrize("nu", [0.2, 0.33, 0.45, 0.49])
def test_the_soft_columns_vz_unload_law_is_admissible_and_the_rest_unchanged(table, nu):
    """Below the nodes' lowest path the polymer columns' loading is stiffer than Hertz's, and the interpolated
    unloading would return more work than the loading took at 1.1-1.3 P_Y (E/sigma_Y 30-65: 496 of 3600
    materials of a 30 nu x 120 E/sigma_Y scan refused without vz_master_table.admissible_below, 0 with it).
    Every law builds (nfdmodel's own check: no load-unload cycle from P_Y up creates energy); above
    E/sigma_Y 66 the unloading nodes are the table's, untouched (0 of the scan's 3030 there; the largest E/sigma_Y
    changed 65.04)."""
    from calib.fit.vz_master_table import admissible_below, dent_below

    for ratio in (30.0, 34.0, 42.3, 50.0, 57.0, 65.0, 80.0, 100.0, 150.0):
        material = Material(E=70e9, nu=nu, sigma_y=70e9 / ratio, rho=2700.0)
        table.unload_law(material, 0.01)        # refused (ValueError) where a cycle would create energy
        values = table.tables(nu, ratio)
        c = np.cbrt(values["x"])
        f_a, g_a = values["f_a"], values["g"] * ((c + values["f_a"]) / (c + values["f"])) ** 2
        x_unload, rho, m = dent_below(values["x"], values["rho"], values["m"], values["low"])
        kept = admissible_below(values["x"], f_a, g_a, x_unload, rho, m, values["low"])
        if ratio > 66.0:
            assert kept[0] is x_unload and kept[2] is m

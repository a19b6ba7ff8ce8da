"""The pair table (calib.fit.pair_table): a yielding sphere on an elastic counter-body without an FE run.

Checked against what the table did not produce: the two-body FE (calib.fe.two_body) of a held-out pair (an
aluminium-like sphere on a steel-like flat, nu 0.33, E/sigma_Y 250, E1'/E2' 0.335: off every node) on the table's
mesh family to 41.2 P_Y, where the law must meet 2 % in e and 5 % of P_max in force and beat the rigid-flat
substitution; the rigid-flat limit (a counter-body 1e4 times stiffer), where the mapped law must give the vz
master table's own e and D; every pair over the table's domain, admissible from P_Y; the table's interpolation,
exact at its nodes; the build's seven held-out checks (results/pairs/pair_table_checks.csv) over each whole window
the law declares. The CLI: ``nfdcal material --counter-E ... --v-max`` writes a parameter file of the pair that nfdmodel loads and ``nfdcal collide`` runs, and
refuses what the table does not cover in one line (exit 2).
"""
import json
from pathlib import Path

import numpy as np
import pytest

from calib.cli import main
from calib.fit import pair_table_build as build
from calib.fit.calibration import drive_law
from calib.fit.counter import CounterBody
from calib.fit.master_table import read_rows
from calib.fit.pair_table import CHECKED_CAPS_OVER_P_Y, TOP_SHARE, PairTable, law_curves, pair_law
from calib.fit.vz_master_table import VZMasterTable
from nfdmodel import Material, VZTableParams, load_parameters

pytestmark = pytest.mark.laws

HELD_OUT = (0.33, 250.0, "0.335")


@pytest.fixture(scope="module")
def held_out_fe():
    task = build.case_task(*HELD_OUT, peaks=(5.0, 13.7, 41.2), role="check")
    build.build_meshes([task])
    row = build.run_task(task)
    assert row["status"] == "ok", row.get("error")
    return row


def test_pair_law_meets_the_two_body_fe_of_a_held_out_pair(held_out_fe):
    m, body = build.material(*HELD_OUT[:2]), build.counter(held_out_fe)
    found = pair_law(m, build.R, body)
    pair = found["law"].pair
    assert found["law"].window.P_min_over_P_Y == 1.0
    errors = {"table": [], "substitution": []}
    for path in held_out_fe["paths"]:
        fe = np.array(path["rows"])
        alpha, force = fe[:, 0] * pair.delta_Y, np.maximum(fe[:, 1], 0.0) * pair.P_Y
        for name, law in (("table", found["law"]), ("substitution", found["substitution"])):
            law_force, e = drive_law("vz-table", law, alpha)
            errors[name].append((e / path["e"] - 1.0, np.abs(law_force - force).max() / force.max()))
    table, substitution = np.array(errors["table"]), np.array(errors["substitution"])
    assert np.abs(table[:, 0]).max() < 0.02, table
    assert table[:, 1].max() < 0.05, table
    assert abs(table[-1, 0]) < abs(substitution[-1, 0]), (table, substitution)   # the table earns its place


def test_rigid_flat_limit_is_the_master_table_law():
    m = Material(1e8, 0.33, 4e5, 1000.0)                  # E/sigma_Y 250; the counter-body 1e4 times stiffer
    found = pair_law(m, 0.002, CounterBody(m.E * 1e4, 0.33))
    law, master = found["law"], found["substitution"]
    peaks = np.geomspace(2.0, min(law.window.P_max_over_P_Y, 200.0), 6)
    _, e_pair = law_curves(law, peaks[:1], peaks)
    _, e_master = law_curves(master, peaks[:1], peaks)
    assert np.abs(e_pair / e_master - 1.0).max() < 3e-3
    D_pair, _ = law_curves(law, peaks, peaks[:1])
    D_master, _ = law_curves(master, peaks, peaks[:1])
    assert np.abs(D_pair / D_master - 1.0).max() < 5e-3


def test_interpolation_is_exact_at_the_nodes():
    table = PairTable.load()
    (nu, ratio), nodes = next(iter(table.nodes.items()))
    node = nodes[0]
    ratios = table.ratios(nu, ratio, node.s, node.top)
    for quantity in ("D", "loss"):
        xs, phis = getattr(node, quantity)
        np.testing.assert_allclose(ratios.at(quantity, xs), phis, rtol=2e-3)


def test_material_writes_the_pair_law_collide_runs(tmp_path, capsys):
    out = tmp_path / "pair.json"
    code = main(["material", "--E", "69e9", "--nu", "0.33", "--sigma-y", "276e6", "--R", "0.002", "--rho", "2700",
                 "--counter-E", "210e9", "--counter-nu", "0.3", "--v-max", "1", "--params-out", str(out), "--json"])
    assert code == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["window"]["P_min_over_P_Y"] == 1.0
    assert summary["source"] == "pair table on the vz master table"
    params = load_parameters(out)
    assert isinstance(params, VZTableParams)
    assert params.pair.E_star == pytest.approx(summary["E_star"])
    assert json.loads(out.read_text())["counter_body"]["E"] == 210e9
    assert main(["collide", "--law", "vz-table", "--params", str(out), "--v-in", "0.5"]) == 0


STEEL = ["--counter-E", "210e9", "--counter-nu", "0.3"]


@pytest.mark.parametrize("extra, names", [
    (STEEL, "--v-max"),                                                       # the pair law needs a window
    (STEEL + ["--v-max", "1", "--law", "vz-unload"], "--law"),
    (STEEL + ["--v-max", "1", "--counter-sigma-y", "200e6"], "--counter-sigma-y"),   # the counter yields first
    (["--counter-E", "10e9", "--v-max", "1"], "E1'/E2'"),                     # softer than the table's nodes
    (STEEL + ["--v-max", "1", "--nu", "0.48"], "nu"),
    (STEEL + ["--v-max", "100"], "v_max"),
])
def test_material_refuses_what_the_pair_table_does_not_cover(extra, names, capsys):
    args = ["material", "--E", "69e9", "--sigma-y", "276e6", "--R", "0.002"]
    args += ([] if "--nu" in extra else ["--nu", "0.33"]) + extra
    assert main(args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and names in err[0], err


def test_every_pair_the_table_covers_gets_an_admissible_law():
    """Across the table's whole domain (nu, E/sigma_Y, X from the rigid-flat limit to its largest node), the law
    is built (admissible: D increasing, no cycle returning more work than it took, to full contact), starts at
    P_Y and keeps 0 < e <= 1 over its window."""
    table, master = PairTable.load(), VZMasterTable.load()
    for nu in (0.2, 0.33, 0.45):
        for ratio in (200.0, 500.0, 2000.0):
            for X in (1e-3, 0.3, 1.0, 3.0):
                m = Material(1e8, nu, 1e8 / ratio, 1000.0)
                E2 = m.plane_strain_modulus / X * (1 - nu ** 2)
                found = pair_law(m, 0.002, CounterBody(E2, nu), table, master)
                law = found["law"]
                assert law.window.P_min_over_P_Y == 1.0
                peaks = np.geomspace(1.5, law.window.P_max_over_P_Y, 5)
                _, e = law_curves(law, peaks[:1], peaks)
                assert np.all((e > 0) & (e <= 1.0 + 1e-9)), (nu, ratio, X, e)


def test_calibrate_v_max_on_a_counter_body_agrees_with_the_pair_table(tmp_path, capsys):
    """``nfdcal calibrate --counter-E ... --v-max``, the FE route for the pairs the table does not cover: the
    window is sized by the pair's impact (m*, E*, R*) and covers it; where the table also covers the pair, the
    law the two-body FE calibrates (a coarse mesh, its own paths) and the table's law (other FE runs: the
    table's nodes) agree within 1 % in e at 2-5 P_Y and in the impact's e at v_max."""
    from nfdmodel import collide

    code = main(["calibrate", "--counter-E", "2e11", "--counter-nu", "0.3", "--v-max", "0.012", "--contact-size",
                 "1.6e-4", "--no-plots", "--json", "--quiet", "--out", str(tmp_path)])
    assert code == 0
    out = json.loads(capsys.readouterr().out)
    assert out["v_max"]["rounds"][-1]["covered"]
    calibrated = load_parameters(tmp_path / "parameters.json")
    assert json.loads((tmp_path / "parameters.json").read_text())["counter_body"]["E"] == 2e11
    reference = Material(70e9, 0.3, 100e6, 2700.0)           # the calibration's default sphere, R 0.1 m
    table_law = pair_law(reference, 0.1, CounterBody(2e11, 0.3))["law"]
    assert calibrated.pair.E_star == pytest.approx(table_law.pair.E_star)
    peaks = np.array([2.0, 3.0, 4.0, 5.0])
    _, e_calibrated = law_curves(calibrated, peaks, peaks)
    _, e_table = law_curves(table_law, peaks, peaks)
    assert np.abs(e_calibrated / e_table - 1.0).max() < 0.01, (e_calibrated, e_table)
    impact = collide("vz-table", calibrated, [0.012])
    assert impact.in_calibrated_range.tolist() == [True]
    assert impact.e_velocity[0] == pytest.approx(collide("vz-table", table_law, [0.012]).e_velocity[0], rel=0.01)


CHECKS_CSV = Path(__file__).resolve().parents[1] / "results" / "pairs" / "pair_table_checks.csv"


def test_held_out_checks_meet_the_targets_over_each_whole_window():
    """The build's held-out checks (results/pairs/pair_table_checks.csv: two-body FE of pairs off every node, one
    a counter-sphere): each law's window is the one pair_law declares today, its FE paths reach at least 0.9 of
    that window's top, and every path inside meets 5 % of P_max in force and 2 % in e but two, named: e +2.27 % at
    300 P_Y (nu 0.34, E/sigma_Y 560, E1'/E2' 0.49) and +2.19 % at 3000 P_Y (nu 0.29, E/sigma_Y 1200, E1'/E2' 1).
    Both appeared when the master table's finite-strain nodes went from 16 to 64 loading steps per decade (1.91 %
    and 1.65 % before): the pair table's ratios and these checks' two-body FE still run 16."""
    checks: dict = {}
    missed = []
    for row in read_rows(CHECKS_CSV):
        checks.setdefault((row["nu"], row["E_over_sigma_y"], row["x"], row["counter"]), []).append(row)
    assert len(checks) >= 6
    for (nu, ratio, x, counter), paths in checks.items():
        radius = None if counter == "flat" else float(counter.split("=")[1].split()[0])
        body = build.counter({"x": repr(x), "nu": nu, "E_over_sigma_y": ratio, "counter_R_over_R": radius})
        top = pair_law(build.material(nu, ratio), build.R, body)["law"].window.P_max_over_P_Y
        inside = [p for p in paths if p["inside_window"] == "True"]
        assert paths[0]["window_top"] == pytest.approx(top, rel=1e-9), (nu, ratio, x, counter)
        assert max(p["P_max_over_P_Y"] for p in inside) >= 0.9 * top, (nu, ratio, x, counter)
        for p in inside:
            assert abs(p["pair_table_e_error"]) < 0.025 and p["pair_table_force_error"] < 0.05, p
            if abs(p["pair_table_e_error"]) >= 0.02:
                missed.append((nu, ratio, x, round(p["P_max_over_P_Y"])))
    assert sorted(missed) == [(0.29, 1200.0, 1.0, 3000), (0.34, 560.0, 0.49, 300)]


def test_the_window_ends_at_a_share_of_the_data_or_where_the_checks_hold():
    """On a flat stiffer than the sphere the window's top is TOP_SHARE of the lowest of the pair table's, the master
    table's and the two-body FE reach's tops; on a counter-sphere and on a softer flat at most the held-out check's
    load (CHECKED_CAPS_OVER_P_Y)."""
    brass, steel = Material(100e9, 0.34, 250e6, 8500.0), Material(210e9, 0.3, 800e6, 7800.0)
    flat = pair_law(brass, 0.002, CounterBody(210e9, 0.3))
    assert flat["law"].window.P_max_over_P_Y == pytest.approx(TOP_SHARE * min(flat["tops"].values()))
    sphere = pair_law(brass, 0.002, CounterBody(210e9, 0.3, R=0.002))
    assert sphere["law"].window.P_max_over_P_Y == CHECKED_CAPS_OVER_P_Y["counter-sphere"]
    softer = pair_law(Material(210e9, 0.3, 200e6, 7800.0), 0.002, CounterBody(105e9, 0.3))   # X 2, E/sigma_Y 1050
    assert softer["law"].window.P_max_over_P_Y == CHECKED_CAPS_OVER_P_Y["softer flat"]
    assert softer["top_by"] == "softer flat check" and sphere["top_by"] == "counter-sphere check"
    like = pair_law(steel, 0.002, CounterBody(210e9, 0.3))                                     # X 1: a flat's share
    assert like["law"].window.P_max_over_P_Y == pytest.approx(TOP_SHARE * min(like["tops"].values()))


@pytest.mark.parametrize("E, nu, sigma_y, rho", [(69e9, 0.33, 276e6, 2700.0), (210e9, 0.3, 800e6, 7800.0),
                                                  (100e9, 0.34, 250e6, 8500.0), (117e9, 0.34, 280e6, 8900.0)],
                         ids=["aluminium 6061", "steel", "brass", "copper"])
@pytest.mark.parametrize("R", ["0.001", "0.005"])
def test_metals_on_a_steel_floor_answer_to_10_m_s_from_first_yield(E, nu, sigma_y, rho, R, capsys):
    """A DEM user's spheres of R 1-5 mm of these metals on a steel floor (210 GPa, nu 0.3) get the pair law to
    10 m/s without an FE run, the window from P_Y."""
    code = main(["material", "--E", str(E), "--nu", str(nu), "--sigma-y", str(sigma_y), "--rho", str(rho), "--R", R,
                 *STEEL, "--v-max", "10", "--json"])
    assert code == 0, capsys.readouterr().err
    summary = json.loads(capsys.readouterr().out)
    assert summary["window"]["P_min_over_P_Y"] == 1.0
    assert summary["P_max_of_v_max_over_P_Y"] <= summary["window"]["P_max_over_P_Y"]

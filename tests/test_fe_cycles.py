"""FE load cycles (calib.fe.cycles) on the coarse mesh of the reference sphere (R = 0.1 m, P_Y 36.6 N):
load to P_max = 500 N, unload to 0.5 and 0.2 P_max, reload each time to P_max, the last on to
1.3 P_max, unload fully. The FE's reload meets its unloading curve at the turning point; a closed
partial cycle creates no energy; the rows are continuous; the vz-table and vz-unload laws, fitted
on the same mesh's monotone load-unload paths (calib/data/fe_unloading_coarse.json, 'fit'), against
the cycles they were not fitted on; `calibrate --cycles` refusals."""
import json
from pathlib import Path

import numpy as np
import pytest

from calib.cli import main
from calib.fe.cycles import CyclePlan, branch_segments, closed_cycles, run_cycles, trapezoid_work
from calib.fe.loadpath import LoadPathPlan, run_load_paths
from calib.fit.cycle_check import CYCLE_TARGET, cycles_against_law
from calib.fit.least_squares import radius_law_data
from calib.fit.table_fit import fit_tables
from calib.fit.unload_fit import fit_unload_law

ROOT = Path(__file__).resolve().parent.parent
FIT = json.loads((ROOT / "calib" / "data" / "fe_unloading_coarse.json").read_text(encoding="utf-8"))["fit"]
P_MAX = 500.0
FRACTIONS = (0.5, 0.2)


@pytest.fixture(scope="module")
def cycles():
    from calib.fit import recipe
    from calib.fit.calibration import body_meshes, _solver

    spec = recipe.reference_spec("coarse")
    assert spec.mesh.cache_key() == FIT["mesh"]["key"]          # the mesh the laws are fitted on
    plan = LoadPathPlan(peaks=(P_MAX,), loading_step=spec.plan.loading_step, first_load=spec.plan.first_load)
    solver = _solver(spec, body_meshes(spec))
    return run_cycles(solver, plan, CyclePlan(FRACTIONS, 1.3), run_load_paths(solver, plan)), spec.pair


def test_the_reload_meets_the_unloading_curve_at_the_turning_point(cycles):
    """At every force of a partial unload the reload returns to the unloading's approach, and at
    P_max to the turning point's: measured within 2e-6 alpha_max (0.5 P_max) and 5e-12 (0.2 P_max)."""
    run, _ = cycles
    segments = branch_segments(run.rows)
    for found in closed_cycles(run):
        assert abs(found["reload_alpha_at_peak_error"]) <= 1e-5
        down = [s for c, b, s in segments if c == found["cycle"] and b == "unloading"][0]
        up = [s for c, b, s in segments if c == found["cycle"] and b == "reloading"][0]
        assert [r["P"] for r in up] == pytest.approx([r["P"] for r in down[::-1]], rel=1e-7)
        gap = np.abs(np.array([r["alpha"] for r in up]) - np.array([r["alpha"] for r in down[::-1]]))
        assert gap.max() <= 1e-5 * run.alpha_max
    assert run.rows[-1]["P"] == pytest.approx(0.0, abs=1e-6 * P_MAX)


def test_a_closed_partial_cycle_creates_no_energy_and_the_history_dissipates(cycles):
    """W_in (reload) >= W_out (unload) up to the Newton tolerance (measured W_in - W_out = -4.5e-6 W_out
    at 0.5 P_max, -1e-11 at 0.2: the coarse FE unloads elastically from 13.6 P_Y), and the whole
    history, from contact to separation, takes more work than it returns."""
    run, _ = cycles
    for found in closed_cycles(run):
        assert found["work_in"] > 0 and found["work_out"] > 0
        assert found["dissipated"] >= -1e-5 * found["work_out"]
    assert trapezoid_work([{"alpha": 0.0, "P": 0.0}] + run.rows) > 0


def test_the_cycle_rows_are_continuous(cycles):
    """Cycle indices 0, 1, 2, 3 in order, the branches as planned, every force step at most
    P_max / 16 (the plan's unloading steps) or the overload's / 16, the approach and the contact
    radius following the force (alpha rises with P on loading and reloading, falls on unloading)."""
    run, _ = cycles
    order = [(c, b) for c, b, _ in branch_segments(run.rows)]
    assert order == [(0, "loading"), (1, "unloading"), (1, "reloading"), (2, "unloading"), (2, "reloading"),
                     (2, "loading"), (3, "unloading")]
    force = np.array([r["P"] for r in run.rows])
    alpha = np.array([r["alpha"] for r in run.rows])
    assert np.abs(np.diff(force)).max() <= 1.3 * P_MAX / 16 * (1 + 1e-9)
    assert np.all(np.sign(np.diff(alpha)) == np.sign(np.diff(force)))
    assert run.rows[-1]["cycle"] == len(FRACTIONS) + 1
    for c, fraction in enumerate(FRACTIONS, 1):
        assert min(r["P"] for r in run.rows if r["cycle"] == c) == pytest.approx(fraction * P_MAX, rel=1e-7)
    assert force.max() == pytest.approx(1.3 * P_MAX, rel=1e-7)


@pytest.mark.laws
def test_the_laws_against_the_fe_cycles_they_were_not_fitted_on(cycles):
    """Measured (laws fitted on the coarse mesh's monotone paths to 80..1500 N): along the partial
    unloads and reloads vz-unload is off by 0.68 % of P_max, vz-table by 1.42 %; the final unload
    from 1.3 P_max 1.14 % and 1.67 % of 650 N; the dent after it -2.0 % (vz-unload) and -9.5 %
    (vz-table, its Hertz unloading). The 2 % target on unloading and reloading: both laws."""
    run, pair = cycles
    loading = FIT["loading"]
    force, approach, radius = (np.array(loading[k]) for k in ("P", "alpha", "contact_radius"))
    paths = FIT["paths"]
    peaks, works = [p["peak"] for p in paths], [p["unloading_work"] for p in paths]
    unload = fit_unload_law(force, approach, radius, pair, peaks, [p["alpha_max"] for p in paths],
                            [p["alpha_residual"] for p in paths], works)
    table = fit_tables(radius_law_data(force, approach, radius, R_star=pair.R_star, E_star=pair.E_star, P_Y=pair.P_Y),
                       pair, peaks, works)
    by_unload = cycles_against_law("vz-unload", unload, run.rows, run.P_max, run.alpha_residual)
    by_table = cycles_against_law("vz-table", table, run.rows, run.P_max, run.alpha_residual)
    for figures in (by_unload, by_table):
        assert figures["partial_error"] <= CYCLE_TARGET and figures["final_unloading_error"] <= CYCLE_TARGET
        assert figures["within"]
    assert by_unload["partial_error"] <= 0.01 < by_table["partial_error"]
    assert abs(by_unload["dent_error"]) <= 0.03
    assert by_table["dent_error"] < -0.07
    assert by_unload["loading_error"] <= 0.01 and by_table["loading_error"] <= 0.01


@pytest.mark.parametrize("fractions", [(), (0.5, 1.0), (0.0,), (float("nan"),)])
def test_a_cycle_plan_out_of_range_is_refused(fractions):
    with pytest.raises(ValueError, match="cycle fractions out of range"):
        CyclePlan(fractions)


def test_a_cycle_peak_not_among_the_plan_is_refused():
    with pytest.raises(ValueError, match="cycle peak out of range"):
        CyclePlan((0.5,), peak=700.0).peak_of(LoadPathPlan(peaks=(500.0, 1000.0), loading_step=50.0))
    assert CyclePlan((0.5,)).peak_of(LoadPathPlan(peaks=(80.0, 500.0, 1000.0, 1500.0), loading_step=50.0)) == 1000.0


@pytest.mark.parametrize("argv, says", [
    (["calibrate", "--cycles", "0.5,1.2"], "--cycles"),
    (["calibrate", "--cycles", "0.5,"], "--cycles"),
    (["calibrate", "--cycles", "0.5", "--ladder"], "--ladder"),
])
def test_calibrate_cycles_refusals_are_one_line(argv, says, capsys):
    assert main(argv + ["--quiet", "--dry-run"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and says in err


def test_calibrate_cycles_writes_the_rows_and_the_laws_figures(tmp_path, capsys):
    """`calibrate --cycles 0.5,0.2` on a coarse mesh: cycles.csv holds the rows (cycle, branch, alpha, P,
    contact radius), the summary the closed cycles and both laws' figures, from the middle path's peak."""
    out = tmp_path / "out"
    assert main(["calibrate", "--contact-size", "0.00016", "--cycles", "0.5,0.2", "--no-plots", "--json", "--quiet",
                 "--out", str(out)]) == 0
    summary = json.loads(capsys.readouterr().out)["cycles"]
    assert summary["fractions"] == [0.5, 0.2] and summary["P_max"] == P_MAX and summary["overload_peak"] == 650.0
    assert set(summary["laws"]) == {"vz-table", "vz-unload"} and len(summary["closed_cycles"]) == 2
    lines = [line for line in (out / "cycles.csv").read_text(encoding="utf-8").splitlines() if not line.startswith("#")]
    assert lines[0].startswith("cycle,branch,alpha,P,contact_radius") and len(lines) - 1 == summary["rows"]
    assert json.loads((out / "cycles.json").read_text(encoding="utf-8"))["rows"] == summary["rows"]

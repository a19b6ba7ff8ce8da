"""``nfdcal fit-data --law vz`` and calib.fit.measured: the two-constant vz law fitted to
measurements (the default vz-table law: tests/test_vz_master.py, against FE data).

Synthetic drop tests come from the law itself (nfdmodel.collision_reference, the exact
quasi-static restitution) with known parameters and 1-3 % multiplicative noise; the fit must
return those parameters within its own standard errors. The reference FE load-unload paths
(results/calibration/path_P*.csv) as force-approach data must return the FE calibration's FORCE
fit (see test_fe_paths_return_the_force_fit).
"""
import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest
from scipy import optimize

from calib.cli import main
from calib.fit.master_table import MasterTable
from calib.fit.measured import data as measured_data
from calib.fit.measured.domain import extended_residuals, full_contact_speed, largest_admissible_Kc_hat
from calib.fit.measured.models import fit_constrained, fit_free, fit_measurements
from calib.fit.measured.specimen import Specimen, law_parameters, predict_impacts, relative_residuals
from nfdmodel import collide, load_parameters

ROOT = Path(__file__).resolve().parent.parent
ALUMINIUM = Specimen(E=70e9, nu=0.3, R=0.1, rho=2699.0)     # the paper's sphere (README)
SPECIMEN_FLAGS = ["--E", "70e9", "--nu", "0.3", "--R", "0.1", "--rho", "2699"]


@pytest.fixture(scope="module")
def table():
    return MasterTable.load()


def drop_tests(params, v_over_v_Y, noise, seed, P_max_noise=None) -> measured_data.Measurements:
    """Drop tests of ``params`` at v_in = v_over_v_Y x v_Y with relative Gaussian noise on e
    (capped at e = 1, as a measured e > 1 is refused)."""
    rng = np.random.default_rng(seed)
    v = params.pair.v_Y * np.asarray(v_over_v_Y, dtype=float)
    exact = predict_impacts(params, v)
    e = np.minimum(exact["e"] * (1.0 + noise * rng.standard_normal(v.size)), 1.0)
    P_max = None if P_max_noise is None else exact["P_max"] * (1.0 + P_max_noise * rng.standard_normal(v.size))
    return measured_data.Measurements(impacts=measured_data.ImpactData("synthetic.csv", v, e, P_max, None,
                                                                       np.arange(1, v.size + 1)))


def write_impacts(path: Path, data: measured_data.Measurements) -> Path:
    rows = ["v_in,e"] + [f"{float(v)!r},{float(e)!r}" for v, e in zip(data.impacts.v_in, data.impacts.e)]
    path.write_text("# synthetic drop tests\n" + "\n".join(rows) + "\n")
    return path


def test_constrained_model_recovers_sigma_y(table):
    """12 drop tests at 2..100 v_Y, 2 % noise, from the law with the master table's constants at
    sigma_Y = 100 MPa: the constrained fit returns sigma_Y within 3 standard errors (and 3 %)."""
    truth = law_parameters(ALUMINIUM, {"sigma_y": 100e6}, table)
    data = drop_tests(truth, np.geomspace(2.0, 100.0, 12), noise=0.02, seed=7)
    fit = fit_constrained(data, ALUMINIUM, table)
    error = fit.values["sigma_y"] / 100e6 - 1.0
    assert abs(error) < 3 * fit.standard_errors["sigma_y"] / fit.values["sigma_y"] and abs(error) < 0.03
    assert fit.identifiability["determined"] == {"sigma_y": True}
    assert 1.0 < fit.params.window.P_min_over_P_Y < fit.params.window.P_max_over_P_Y
    assert all(np.isfinite(r).all() for r in fit.residuals.values())


def test_free_model_recovers_the_constants_and_is_preferred(table):
    """Ca_hat = 0.032, Kc_hat = 0.014 (off the master table's 0.0258, 0.0109), sigma_Y known:
    20 tests from 1.2 to 300 v_Y with 1 % noise determine both (within 3 standard errors, 5 %),
    sigma_Y stays held (e(v_in) alone does not separate it from Ca_hat, Kc_hat: the identifiability
    report says so), and AICc prefers the free model."""
    truth = law_parameters(ALUMINIUM, {"sigma_y": 100e6, "Ca_hat": 0.032, "Kc_hat": 0.014}, None)
    data = drop_tests(truth, np.geomspace(1.2, 300.0, 20), noise=0.01, seed=11)
    choice = fit_measurements(data, ALUMINIUM, table, "free", sigma_y=100e6)
    fit = choice.result
    assert choice.used == "free" and choice.preferred == "free"
    assert fit.spec.free == ("Ca_hat", "Kc_hat") and fit.standard_errors["sigma_y"] is None
    assert "sigma_Y held at 1e+08 Pa (given)" in fit.note
    for name, true in (("Ca_hat", 0.032), ("Kc_hat", 0.014)):
        error = fit.values[name] / true - 1.0
        assert abs(error) < 3 * fit.standard_errors[name] / fit.values[name] and abs(error) < 0.05, name
    assert abs(fit.correlation[0, 1]) <= 1.0 and fit.correlation[0, 0] == pytest.approx(1.0)
    assert "suggested_v_in" in fit.identifiability


def off_table_drop_tests() -> measured_data.Measurements:
    """The drop tests of test_free_model_recovers_the_constants_and_is_preferred."""
    truth = law_parameters(ALUMINIUM, {"sigma_y": 100e6, "Ca_hat": 0.032, "Kc_hat": 0.014}, None)
    return drop_tests(truth, np.geomspace(1.2, 300.0, 20), noise=0.01, seed=11)


def test_a_start_the_law_refuses_walks_back_to_the_usual_fit(table):
    """Where the law cannot be evaluated the fit's residuals continue smoothly
    (calib.fit.measured.domain), so a fit started there walks back: sigma_Y = 15 MPa puts the
    fastest test (300 v_Y of 100 MPa) beyond full contact, and Kc_hat = 0.1 lies beyond the largest
    Kc_hat the law admits at Ca_hat = 0.032 (0.0867). Both return what the usual starts give."""
    data = off_table_drop_tests()
    assert extended_residuals(ALUMINIUM, {"sigma_y": 15e6}, table, data).beyond
    assert extended_residuals(ALUMINIUM, {"sigma_y": 100e6, "Ca_hat": 0.032, "Kc_hat": 0.1}, None, data).beyond
    usual = fit_constrained(data, ALUMINIUM, table)
    walked = fit_constrained(data, ALUMINIUM, table, sigma_y_start=15e6)
    assert walked.values["sigma_y"] == pytest.approx(usual.values["sigma_y"], rel=1e-6)
    usual = fit_free(data, ALUMINIUM, 100e6, None, table, free_sigma_y=False)
    walked = fit_free(data, ALUMINIUM, 100e6, {"Ca_hat": 0.032, "Kc_hat": 0.1}, table, free_sigma_y=False)
    for name in ("Ca_hat", "Kc_hat"):
        assert walked.values[name] == pytest.approx(usual.values[name], rel=1e-6), name
        assert walked.standard_errors[name] == pytest.approx(usual.standard_errors[name], rel=1e-4), name


def test_the_fit_objective_is_smooth_across_the_law_s_boundaries(table):
    """The least-squares cost of the continued residuals is continuous and continuously
    differentiable across both boundaries of the law (calib.fit.measured.domain), and grows beyond
    them when the data lie inside: across Kc_hat*(Ca_hat = 0.032), the largest Kc_hat the law
    admits, and across the sigma_Y at which the fastest drop test reaches full contact. A
    constant residual there (no gradient, a jump of 10^2 per row) would fail every check."""
    data = off_table_drop_tests()

    def cost(log_x, values):
        extended = extended_residuals(ALUMINIUM, values(math.exp(log_x)), table, data)
        r = extended.residuals["e"]
        return float(r @ r), bool(extended.beyond)

    def accepted(Kc_hat):
        return 1.0 if not extended_residuals(ALUMINIUM, {"sigma_y": 100e6, "Ca_hat": 0.032, "Kc_hat": Kc_hat},
                                             None, data).beyond else -1.0

    along_Kc = {"sigma_y": 100e6, "Ca_hat": 0.032}
    Kc_boundary = optimize.bisect(accepted, 0.05, 0.5, rtol=1e-14)
    fastest = float(data.impacts.v_in.max())
    sigma_boundary = optimize.brentq(lambda s: full_contact_speed(law_parameters(ALUMINIUM, {"sigma_y": s}, table))
                                     - fastest, 15e6, 100e6, rtol=1e-14)
    h = 1e-4
    for values, boundary, outward in ((lambda k: {**along_Kc, "Kc_hat": k}, Kc_boundary, 1.0),
                                      (lambda s: {"sigma_y": s}, sigma_boundary, -1.0)):
        x = math.log(boundary)
        (inside, was_beyond), (outside, is_beyond) = (cost(x - outward * 1e-9, values),
                                                      cost(x + outward * 1e-9, values))
        assert not was_beyond and is_beyond
        assert outside == pytest.approx(inside, rel=1e-8, abs=1e-8)
        slope_in = (inside - cost(x - outward * (1e-9 + h), values)[0]) / h
        slope_out = (cost(x + outward * (1e-9 + h), values)[0] - outside) / h
        assert slope_out == pytest.approx(slope_in, rel=1e-3) and slope_in > 0.0
        assert outside < cost(x + outward * 1e-3, values)[0] < cost(x + outward * 1e-2, values)[0]


def test_a_best_fit_beyond_the_law_s_constants_is_one_line_naming_it(tmp_path, capsys):
    """Drop tests of constants 0.5 % inside the largest Kc_hat the law admits at Ca_hat = 0.03,
    2 % noise (seed 1): the free fit (sigma_Y given) is best beyond that Kc_hat, where the law
    creates energy; the error names Kc_hat and its bound (exit 2)."""
    largest = largest_admissible_Kc_hat(ALUMINIUM.pair(100e6), 0.03)
    truth = law_parameters(ALUMINIUM, {"sigma_y": 100e6, "Ca_hat": 0.03, "Kc_hat": 0.995 * largest}, None)
    impacts = write_impacts(tmp_path / "drops.csv", drop_tests(truth, np.geomspace(1.2, 300.0, 20), 0.02, seed=1))
    code = main(["fit-data", "--law", "vz", "--impacts", str(impacts), *SPECIMEN_FLAGS, "--free", "--sigma-y", "100e6"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "Traceback" not in err[0]
    assert "cannot be evaluated" in err[0] and "Kc_hat = " in err[0] and "the largest the vz law admits" in err[0], err


REFERENCE_PEAKS = (80, 140, 260, 500, 1000, 1500)   # the reference calibration's paths [N]


def fe_paths_csv(path: Path) -> Path:
    """The reference FE load-unload paths (results/calibration/path_P<peak>.csv: alpha [m], P [N])
    as one force-approach file, one test label per path (each a virgin sphere)."""
    rows = []
    for peak in REFERENCE_PEAKS:
        lines = (ROOT / "results" / "calibration" / f"path_P{peak}.csv").read_text().splitlines()
        for row in csv.DictReader(line for line in lines if not line.startswith("#")):
            rows.append(f"P{peak},{row['alpha']},{row['P']}")
    path.write_text("test,approach,force\n" + "\n".join(rows) + "\n")
    return path


def test_fe_paths_return_the_force_fit(tmp_path, table):
    """The FE paths as force-approach data return the FE calibration's FORCE fit (calibration.json
    "force_fit": Ca = 2.963e-7 m/N, Kc = 4.550e-4 1/N) within 2 %, not its radius fit (Ca =
    2.316e-7, Kc = 2.984e-4 on the finer mesh: 22 % and 34 % lower). Why: the radius fit is least squares
    of the FE's contact radius (a_p and C_R against P - P_Y), which force-approach data do not
    contain; the force fit minimises the law's relative force error along the same paths, with the
    same weighting (floor 0.05 x the smallest peak, 4 N) and the same P_Y (sigma_Y = 100 MPa), which
    is exactly what fit-data does with a force-approach curve. sigma_Y is held at the given
    100 MPa because the identifiability analysis finds that these paths do not determine it together
    with Ca_hat and Kc_hat (tested below); the law's Ca and Kc in SI units they do determine."""
    data = measured_data.Measurements(forces=measured_data.read_force_approach(fe_paths_csv(tmp_path / "fe.csv")))
    paths = json.loads((ROOT / "results" / "calibration" / "calibration.json").read_text())["paths"]
    assert tuple(round(p["P_max"]) for p in paths) == REFERENCE_PEAKS
    assert data.forces.n_points == sum(p["steps"] for p in paths) and data.forces.force_floor == pytest.approx(4.0)
    fit = fit_free(data, ALUMINIUM, 100e6, None, table)
    reference = json.loads((ROOT / "results" / "calibration" / "calibration.json").read_text())
    assert fit.spec.free == ("Ca_hat", "Kc_hat") and "sigma_Y held at 1e+08 Pa" in fit.note
    for name in ("Ca", "Kc"):
        assert fit.values[name] == pytest.approx(reference["force_fit"][name], rel=0.02), name
        assert abs(fit.values[name] / reference["radius_fit"][name] - 1.0) > 0.1, name
    assert fit.rms_residual == pytest.approx(reference["force_fit"]["rms_relative_force_error"], rel=0.02)
    assert all(fit.identifiability["determined"].values())


def test_two_sphere_tests_give_the_material_s_law(tmp_path, capsys, table):
    """--pair: head-on impacts of two identical spheres (R* = R/2, E* = E/(2(1 - nu^2)),
    m* = m/2, v_in the relative speed) return sigma_Y, and the parameter file is the same
    material's sphere on a rigid flat (same sigma_Y, Ca_hat, Kc_hat)."""
    pair_specimen = Specimen(E=70e9, nu=0.3, R=0.1, rho=2699.0, two_spheres=True)
    truth = law_parameters(pair_specimen, {"sigma_y": 100e6}, table)
    assert truth.pair.R_star == pytest.approx(0.05)
    impacts = write_impacts(tmp_path / "pairs.csv", drop_tests(truth, np.geomspace(2.0, 100.0, 12), 0.01, seed=5))
    params_out = tmp_path / "p.json"
    assert main(["fit-data", "--law", "vz", "--impacts", str(impacts), *SPECIMEN_FLAGS, "--pair", "--json",
                 "--params-out", str(params_out)]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["sigma_y"] == pytest.approx(100e6, rel=0.02) and summary["specimen"]["tested"] == "two identical spheres"
    params = load_parameters(params_out)
    assert params.pair.R_star == pytest.approx(0.1) and params.pair.sigma_y == pytest.approx(summary["sigma_y"])
    assert params.Ca_hat == pytest.approx(summary["Ca_hat"]) and params.Kc_hat == pytest.approx(summary["Kc_hat"])


def test_parameter_file_loads_and_drives_a_collision(tmp_path, capsys, table):
    """--params-out writes through the one writer: nfdmodel.load_parameters reads it back, and a
    collision with it gives the fitted law's e; an existing file is refused without --overwrite."""
    truth = law_parameters(ALUMINIUM, {"sigma_y": 100e6}, table)
    impacts = write_impacts(tmp_path / "drops.csv", drop_tests(truth, np.geomspace(2.0, 100.0, 12), 0.02, seed=3))
    params_out, plot = tmp_path / "p.json", tmp_path / "fit.png"
    code = main(["fit-data", "--law", "vz", "--impacts", str(impacts), *SPECIMEN_FLAGS, "--json",
                 "--params-out", str(params_out), "--plot", str(plot)])
    summary = json.loads(capsys.readouterr().out)
    assert code == 0 and plot.stat().st_size > 0
    for key in ("sigma_y", "sigma_y_se", "Ca", "Kc", "Ca_hat", "Kc_hat", "Ca_se", "Kc_se", "Ca_hat_se", "Kc_hat_se",
                "model", "aic", "correlation", "identifiability", "window", "n_points", "rms_residual"):
        assert key in summary, key
    assert summary["model"]["chosen"] == "constrained" and set(summary["aic"]) == {"constrained", "free"}
    assert "NaN" not in params_out.read_text()
    params = load_parameters(params_out)
    assert params.Ca == pytest.approx(summary["Ca"]) and params.pair.sigma_y == pytest.approx(summary["sigma_y"])
    assert json.loads(params_out.read_text())["fit"]["source"] == "measurements"
    v = np.array([0.02, 0.1])
    e = collide("vz", params, v, dt=None).e_velocity
    assert e == pytest.approx(predict_impacts(params, v)["e"], rel=2e-3)

    before = params_out.read_bytes()
    code = main(["fit-data", "--law", "vz", "--impacts", str(impacts), *SPECIMEN_FLAGS,
                 "--params-out", str(params_out)])
    err = capsys.readouterr().err.strip()
    assert code == 2 and "--overwrite" in err and len(err.splitlines()) == 1 and params_out.read_bytes() == before
    assert main(["fit-data", "--law", "vz", "--impacts", str(impacts), *SPECIMEN_FLAGS, "--params-out", str(params_out),
                 "--overwrite"]) == 0


GOOD = "v_in,e\n0.01,0.9\n0.02,0.8\n0.05,0.7\n"
BAD_IMPACTS = [
    ("e above 1", "v_in,e\n0.01,0.9\n0.02,1.2\n0.05,0.7\n", ["row 2", "'e'", "e <= 1"]),
    ("e zero", "v_in,e\n0.01,0.9\n0.02,0\n0.05,0.7\n", ["row 2", "'e'", "e > 0"]),
    ("v_in negative", "v_in,e\n0.01,0.9\n-0.02,0.8\n0.05,0.7\n", ["row 2", "'v_in'", "v_in > 0"]),
    ("v_in zero", "v_in,e\n0,0.9\n", ["row 1", "'v_in'"]),
    ("NaN", "v_in,e\n0.01,0.9\n0.02,nan\n", ["row 2", "'e'", "finite"]),
    ("text", "v_in,e\n0.01,0.9\n0.02,0.8\nfast,0.7\n", ["row 3", "'v_in'", "not a number"]),
    ("missing column", "v_in,restitution\n0.01,0.9\n", ["column", "'restitution'"]),
    ("no e column", "v_in\n0.01\n", ["missing column", "'e'"]),
    ("ragged row", "v_in,e\n0.01,0.9\n0.02\n", ["row 2", "field"]),
    ("fewer rows than parameters", "v_in,e\n0.01,0.9\n", ["1 data point", "need at least 2"]),
    ("unit slip", "v_in,e\n20000,0.9\n0.02,0.8\n", ["row 1", "'v_in'", "v_in <= 10000"]),
    ("empty", "# nothing\n", ["no header"]),
]


@pytest.mark.parametrize("case, text, named", BAD_IMPACTS, ids=[c[0] for c in BAD_IMPACTS])
def test_bad_impact_data_is_one_line_naming_file_row_column(tmp_path, capsys, case, text, named):
    path = tmp_path / "drops.csv"
    path.write_text(text)
    code = main(["fit-data", "--law", "vz", "--impacts", str(path), *SPECIMEN_FLAGS])
    captured = capsys.readouterr()
    err = captured.err.strip()
    assert code == 2 and len(err.splitlines()) == 1 and "Traceback" not in err and captured.out == ""
    assert err.startswith("nfdcal fit-data: error: ") and str(path) in err
    for word in named:
        assert word in err, (word, err)


BAD_FORCES = [
    ("text force", "approach,force\n1e-6,10\n2e-6,lots\n", ["row 2", "'force'", "not a number"]),
    ("inf approach", "approach,force\n1e-6,10\ninf,20\n", ["row 2", "'approach'", "finite"]),
    ("no force", "approach\n1e-6\n", ["missing column", "'force'"]),
    ("never loaded", "approach,force\n1e-6,0\n2e-6,0\n", ["'force'", "no positive force"]),
    ("empty label", "test,approach,force\nA,1e-6,10\n,2e-6,20\n", ["row 2", "'test'"]),
]


@pytest.mark.parametrize("case, text, named", BAD_FORCES, ids=[c[0] for c in BAD_FORCES])
def test_bad_force_data_is_one_line(tmp_path, capsys, case, text, named):
    path = tmp_path / "press.csv"
    path.write_text(text)
    code = main(["fit-data", "--force-approach", str(path), *SPECIMEN_FLAGS])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1 and str(path) in err
    for word in named:
        assert word in err, (word, err)


@pytest.mark.parametrize("argv, named", [
    (["fit-data", *SPECIMEN_FLAGS], "--impacts"),
    (["fit-data", "--impacts", "x.csv", "--E", "70e9", "--nu", "0.3"], "--R, --rho"),
    (["fit-data", "--impacts", "missing.csv", *SPECIMEN_FLAGS], "missing.csv"),
    (["fit-data", "--impacts", "x.csv", "--E", "70", "--nu", "0.3", "--R", "0.1", "--rho", "2699"], "GPa"),
    (["fit-data", "--impacts", "x.csv", *SPECIMEN_FLAGS, "--sigma-y", "nan"], "--sigma-y"),
], ids=["no data", "missing flags", "missing file", "E in GPa", "sigma_y NaN"])
def test_bad_flags_are_one_line(tmp_path, capsys, monkeypatch, argv, named):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "x.csv").write_text(GOOD)
    code = main(argv)
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1 and named in err


def test_output_that_is_a_folder_is_refused_before_work(tmp_path, capsys):
    (tmp_path / "x.csv").write_text(GOOD)
    (tmp_path / "out").mkdir()
    code = main(["fit-data", "--impacts", str(tmp_path / "x.csv"), *SPECIMEN_FLAGS, "--plot", str(tmp_path / "out")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and "folder" in err and len(err.splitlines()) == 1


def test_repeats_and_optional_columns_are_read(tmp_path):
    path = tmp_path / "drops.csv"
    path.write_text("# lab 3\nv_in,e,P_max,contact_time\n0.01,0.9,120,\n0.01,0.91,,\n0.05,0.7,800,1e-4\n")
    data = measured_data.read_impacts(path)
    assert data.v_in.tolist() == [0.01, 0.01, 0.05] and data.n_points == 3 + 2 + 1
    assert math.isnan(data.P_max[1]) and data.rows.tolist() == [1, 2, 3]

"""A counter-body's inputs (calib.fit.counter, calib.commands.common, nfdmodel.parameter_file,
nfdcal collide): the counter-sphere's density and the pair's reduced mass, against the closed form
and Hertz's impact computed here; refusals before any mesh or FE work, one line naming the flag and
the range (exit 2), for each class of input the two-body FE cannot handle; and the unit slip of the
dimensionless Ca_hat, Kc_hat typed in collide's SI flags."""
import json
import math

import pytest

from calib.cli import main
from calib.fit.counter import SOFT_COUNTER_MIN, CounterBody
from calib.report.parameter_file import write_parameter_file
from nfdmodel import Material, VZConstants, limits
from nfdmodel.hertz_contact import hertz_impact_force, hertz_impact_time

ALUMINIUM, R1 = Material(70e9, 0.3, 100e6, 2699.0), 0.01
STEEL = CounterBody(205e9, 0.29, 655e6, 0.006, 7850.0)     # a free steel sphere, R2 = 6 mm


def closed_form(counter: CounterBody) -> dict:
    """E*, R*, m* of aluminium on ``counter`` written out (Johnson 1985 eq. 4.22; m = 4/3 pi R^3 rho)."""
    m1, m2 = (4.0 / 3.0 * math.pi * R ** 3 * rho for R, rho in ((R1, ALUMINIUM.rho), (counter.R, counter.rho)))
    E_star = 1.0 / ((1 - ALUMINIUM.nu ** 2) / ALUMINIUM.E + (1 - counter.nu ** 2) / counter.E)
    return {"E_star": E_star, "R_star": R1 * counter.R / (R1 + counter.R), "m_star": m1 * m2 / (m1 + m2)}


def one_line_refusal(capsys, args, *words):
    assert main(args) == 2
    err = "\n".join(line for line in capsys.readouterr().err.strip().splitlines() if ": warning: " not in line)
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    for word in words:
        assert word in err, err
    return err


def test_the_pair_s_reduced_mass_is_the_closed_form():
    pair = STEEL.pair(ALUMINIUM, R1)
    expected = closed_form(STEEL)
    assert pair.mass_star == pytest.approx(expected["m_star"], rel=1e-12)
    assert pair.E_star == pytest.approx(expected["E_star"], rel=1e-12)
    assert pair.R_star == pytest.approx(expected["R_star"], rel=1e-12)
    # the sphere's density for the steel sphere (the silent default) gives another m*: 1.6x too small here
    assert CounterBody(STEEL.E, STEEL.nu, STEEL.sigma_y, STEEL.R).pair(ALUMINIUM, R1).mass_star < 0.7 * pair.mass_star
    flat = CounterBody(STEEL.E, STEEL.nu, rho=7850.0)          # a held block: the sphere's own mass
    assert flat.pair(ALUMINIUM, R1).mass_star == pytest.approx(4 / 3 * math.pi * R1 ** 3 * ALUMINIUM.rho, rel=1e-12)


def test_collide_params_gives_hertz_impact_of_the_pair(tmp_path, capsys):
    """The parameter file states rho2 and m*; collide --params runs the pair's m*: below first yield
    its P_max and contact time are Hertz's impact of the pair (E*, R*, m* computed here) within 1e-3."""
    pair = STEEL.pair(ALUMINIUM, R1)
    path = write_parameter_file(tmp_path / "pair.json", VZConstants(0.026, 0.0098).params(pair), R1, ALUMINIUM,
                                {}, {}, counter=STEEL.describe())
    record = json.loads(path.read_text())
    assert record["counter_body"]["rho"] == 7850.0
    expected = closed_form(STEEL)
    assert record["mass_star"] == pytest.approx(expected["m_star"], rel=1e-12)
    v = 0.5 * pair.v_Y
    assert main(["collide", "--params", str(path), "--v-in", f"{v!r}", "--json"]) == 0
    row = json.loads(capsys.readouterr().out)[0]
    k_H = 4.0 / 3.0 * expected["E_star"] * math.sqrt(expected["R_star"])
    assert row["P_max"] == pytest.approx(hertz_impact_force(expected["m_star"], k_H, v), rel=1e-3)
    assert row["contact_time"] == pytest.approx(
        hertz_impact_time(expected["m_star"], expected["R_star"], expected["E_star"], v), rel=1e-3)


def test_a_counter_sphere_file_without_its_density_is_refused(tmp_path, capsys):
    pair = STEEL.pair(ALUMINIUM, R1)
    record = {k: v for k, v in STEEL.describe().items() if k != "rho"}
    path = write_parameter_file(tmp_path / "old.json", VZConstants(0.026, 0.0098).params(pair), R1, ALUMINIUM,
                                {}, {}, counter=record)
    one_line_refusal(capsys, ["collide", "--params", str(path), "--v-in", "0.01"], "counter_body.rho", "m*")


@pytest.mark.parametrize("command", [["calibrate"], ["impact", "--no-error-estimate"]], ids=["calibrate", "impact"])
def test_a_counter_sphere_needs_its_density(command, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    one_line_refusal(capsys, [*command, "--counter-E", "2.1e11", "--counter-R", "0.05", "--dry-run"],
                     "--counter-rho", "m*")
    assert main([*command, "--counter-E", "2.1e11", "--counter-R", "0.05", "--counter-rho", "7850", "--dry-run",
                 "--json"]) == 0
    assert json.loads(capsys.readouterr().out)
    # a flat needs none (a held block has no mass in m*); hertz (a press) has no --counter-rho
    assert main([*command, "--counter-E", "2.1e11", "--dry-run", "--json"]) == 0
    capsys.readouterr()


def test_hertz_takes_no_density():
    from calib.cli import build_parser

    with pytest.raises(SystemExit):
        build_parser().parse_args(["hertz", "--counter-E", "2e11", "--counter-rho", "7850"])


# Each class of counter-body the two-body FE cannot handle, refused before any mesh, in the dry run
# as in the run (the run's refusal comes before any FE work: the same check). Bounds measured on
# coarse meshes (calib/fit/counter.py's docstring).
SOFT = ["--counter-E", "1e5"]                         # a gel: 7e5 x softer than aluminium
REFUSED = [
    (["hertz", *SOFT, "--P-max", "2"], ["--counter-E", f"{SOFT_COUNTER_MIN:g}", "need --counter-E >="]),
    (["hertz", "--counter-E", "7e6", "--P-max", "20"], ["--counter-E", "softer than the sphere"]),
    (["hertz", "--counter-E", "2e11", "--counter-R", "1e-4", "--P-max", "20"], ["--counter-R", "0.2 min(R1, R2)"]),
    (["calibrate", *SOFT], ["--counter-E", f"{limits.FE_FINITE_MAX_CONTACT_RADIUS_OVER_R:g} R",   # auto: finite
                            "need --counter-E >="]),
    (["calibrate", "--counter-E", "2e11", "--counter-sigma-y", "1e4"], ["--counter-sigma-y", "E2/sigma_Y2", "2e+07"]),
    (["calibrate", "--counter-E", "2e11", "--counter-R", "1e-4", "--counter-rho", "7850"],
     ["--counter-R", "need --counter-R >="]),
    (["impact", *SOFT], ["--counter-E", "need --counter-E >="]),
    (["impact", *SOFT, "--v-in", "0.01"], ["--counter-E", "softer than the sphere"]),
    (["impact", "--counter-E", "2e11", "--counter-sigma-y", "1e4"], ["--counter-sigma-y", "E2/sigma_Y2"]),
    (["impact", "--counter-E", "2e11", "--counter-R", "1e-4", "--counter-rho", "7850"], ["--counter-R"]),
    (["impact", "--counter-E", "2e11", "--counter-R", "1e-3", "--counter-rho", "7850"],
     ["--counter-R out of range for the default velocities", "need --counter-R >="]),
]


@pytest.mark.parametrize("args, words", REFUSED, ids=[
    "hertz gel", "hertz soft at small loads", "hertz counter-R", "calibrate gel", "calibrate sigma-y",
    "calibrate counter-R", "impact gel", "impact gel v_in", "impact sigma-y", "impact counter-R mesh",
    "impact counter-R default velocities"])
@pytest.mark.parametrize("dry", [True, False], ids=["dry run", "run"])
def test_a_counter_body_beyond_the_fe_is_refused_before_any_work(args, words, dry, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    import calib.fe.impact_pair_mesh as impact_pair_mesh
    import calib.studies.hertz as hertz
    import calib.studies.impact_pair as impact_pair
    import meshes.counter_body as counter_body

    def no_work(*_, **__):
        raise AssertionError("meshed or ran the FE before refusing")
    for module, name in ((counter_body, "pair_mesh"), (impact_pair, "impact_pair_mesh"),
                         (impact_pair_mesh, "impact_pair_mesh"), (hertz, "run_hertz")):
        monkeypatch.setattr(module, name, no_work)
    extra = ["--dry-run"] if dry else ["--out", str(tmp_path / "out")]
    one_line_refusal(capsys, [*args, *extra, *([] if args[0] == "hertz" else ["--quiet"])], *words)
    assert not (tmp_path / "results").exists() and not (tmp_path / "out").exists()


def test_the_bounds_let_a_usual_pair_through(capsys, tmp_path, monkeypatch):
    """A steel flat and a steel sphere under the reference sphere, and a counter 1000x softer at a
    contact wide enough ((E2/E1)(a/R) = 1e-3 x 0.0137 > 1e-5), are planned."""
    monkeypatch.chdir(tmp_path)
    for args in (["hertz", "--counter-E", "2e11", "--P-max", "20"], ["hertz", "--counter-E", "7e7", "--P-min", "2",
                                                                        "--P-max", "20"],
                 ["calibrate", "--counter-E", "2e11", "--counter-R", "0.05", "--counter-rho", "7850"],
                 ["impact", "--counter-E", "2.1e11", "--counter-nu", "0.28", "--v-in", "0.04"]):
        assert main([*args, "--dry-run", "--json"]) == 0, capsys.readouterr().err
        capsys.readouterr()


def test_hertz_step_not_converged_is_one_line(capsys, tmp_path, monkeypatch):
    """An FE step that does not converge after the checks passed: one line naming the loads, exit 2."""
    import calib.studies.hertz as hertz
    from calib.fe import StepNotConverged

    def stalls(*_, **__):
        raise StepNotConverged("force step 0.64: Newton stalled (relative residual 2.26e-08)")
    monkeypatch.setattr(hertz, "write_hertz_results", stalls)
    one_line_refusal(capsys, ["hertz", "--counter-E", "2e11", "--P-max", "20", "--out", str(tmp_path / "h")],
                     "--P-min, --P-max", "Newton stalled")


# --Ca, --Kc typed as the README's dimensionless numbers (Ca_hat 0.026, Kc_hat 0.0098): refused
# with the SI value; the SI values run.
P_Y_REFERENCE, A_Y_REFERENCE = 36.63733, 3.293387e-4      # the reference sphere's (nfdmodel.ContactPair.reference)


@pytest.mark.parametrize("flags, words", [
    (["--Ca", "0.026", "--Kc", "0.0098"], ["--Ca out of range", "did you give Ca_hat?", "2.337e-07 m/N"]),
    (["--Ca", "0.026"], ["--Ca out of range", "did you give Ca_hat?"]),
    (["--Ca", "5.7e-6", "--Kc", "0.0098"], ["--Kc out of range", "did you give Kc_hat?", "0.0002675 1/N"]),
    (["--Ca", "1e-4", "--Kc", "2.7e-4"], ["--Ca out of range", "Ca_hat"]),
], ids=["README numbers", "Ca alone", "Kc", "Ca far off"])
def test_dimensionless_constants_in_the_si_flags_are_refused(flags, words, capsys):
    err = one_line_refusal(capsys, ["collide", "--v-in", "0.05", *flags], *words)
    if "did you give Ca_hat?" in err:
        assert 0.026 * A_Y_REFERENCE / P_Y_REFERENCE == pytest.approx(2.337e-7, rel=1e-3)


def test_the_si_values_run(capsys):
    Ca, Kc = 0.026 * A_Y_REFERENCE / P_Y_REFERENCE, 0.0098 / P_Y_REFERENCE
    assert main(["collide", "--v-in", "0.05", "--Ca", f"{Ca:.6g}", "--Kc", f"{Kc:.6g}", "--json"]) == 0
    row = json.loads(capsys.readouterr().out)[0]
    assert 0.6 < row["e_velocity"] < 0.8            # the reference law's e at 0.05 m/s (0.034 from the slip)

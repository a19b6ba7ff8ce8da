"""Runtime model on extreme inputs: regressions for the failures the stability grid found, and the
stability report itself (calib.studies.runtime_stability, `nfdcal stability`)."""
import json
import subprocess
import sys
import warnings

import numpy as np
import pytest

import nfdmodel
from nfdmodel import ContactPair, Material, TimeStepWarning, VZParams, collide, collision_reference, get_law
from nfdmodel.vz import vz_largest_admissible_Kc

pytestmark = pytest.mark.laws      # rerun on the numpy kernels by .ci/run (tests/test_markers.py)

REF = VZParams.reference()
PAIR = REF.pair


def test_force_is_continuous_at_the_turning_point_when_the_elastic_recovery_is_tiny():
    """Ca at 1e3 x, P up to 1e6 P_Y: delta_max - delta_res ~ 1e-11 delta_max. K_u from the
    closed form made the force jump by up to 1e-5 at the turning point; K_u is now fitted to the
    stored delta_res, so holding the overlap returns P_max to round-off."""
    params = VZParams.from_dimensionless(PAIR, REF.Ca_hat * 1e3, REF.Kc_hat)
    law = get_law("vz")
    top = min(1e6, 0.99 * params.full_contact_load / PAIR.P_Y)       # the law's domain: a < R*
    delta = params.loading_approach(PAIR.P_Y * np.geomspace(1.01, top, 200))
    force, state = law.force(delta, law.initial_state(delta.size), params)
    held, _ = law.force(delta, state, params)
    np.testing.assert_allclose(held, force, rtol=1e-13)
    # the unloading stiffness still equals the paper's (4/3) E* C_Rmax^(3/2) sqrt(R*) where
    # the recovery is resolved (eq. 3.22)
    paper = PAIR.hertz_stiffness * params.curvature_factor(state.P_max) ** 1.5
    assert abs(state.unloading_stiffness[0] / paper[0] - 1) < 1e-9


@pytest.mark.parametrize("law", ["vz", "thornton", "walton-braun", "hertz"])
def test_contact_time_estimate_matches_the_simulation_over_the_velocity_range(law):
    """The estimate was 3 delta_max / v_in: 1.86 x the simulated contact time of vz at
    v_in = 1e4 v_Y (unloading is 2 % of the contact there). Now t_load (quadrature) + exact
    unloading time: within the O(dt^2) error of the simulation. (The paper's constants reach a = R*
    at 3290 v_Y: the fastest impact is 3000 v_Y, where unloading is 7 % of the contact.)"""
    v = PAIR.v_Y * np.array([0.1, 10.0, 3000.0])
    exact = collision_reference(law, REF, v)
    result = collide(law, REF, v, dt=float(exact.unloading_time_estimate.min()) / 50)
    np.testing.assert_allclose(result.contact_time, exact.contact_time_estimate, rtol=1e-3)
    assert np.all(exact.unloading_time_estimate <= 0.5 * exact.contact_time_estimate * (1 + 1e-9))


def test_warning_when_the_unloading_phase_is_under_resolved():
    """v_in = 1e4 v_Y, dt = contact / 100: 100 steps per contact (no warning before) but only
    2 in the unloading phase, with a 3 % error on e_energy. Now a TimeStepWarning (here at
    3000 v_Y, inside the domain of the paper's constants: 7 steps in the unloading phase)."""
    v = [3000 * PAIR.v_Y]
    exact = collision_reference("vz", REF, v)
    dt = float(exact.contact_time_estimate[0]) / 100
    with pytest.warns(TimeStepWarning, match=r"unloading about .* need >= 10\).*use dt <= "):
        collide("vz", REF, v, dt=dt)
    assert issubclass(TimeStepWarning, RuntimeWarning)    # existing RuntimeWarning filters still apply
    with warnings.catch_warnings():
        warnings.simplefilter("error", TimeStepWarning)   # below the limit: silent and accurate
        result = collide("vz", REF, v, dt=float(exact.unloading_time_estimate[0]) / 12)
    assert abs(result.e_energy[0] / exact.restitution[0] - 1) < 1e-2


def test_dt_beyond_the_stability_limit_or_too_small_is_refused():
    v = [100 * PAIR.v_Y]
    limit = 2 * float(collision_reference("vz", REF, v).unloading_time_estimate[0]) / np.pi
    with pytest.raises(ValueError, match=r"^dt out of range: .* stability limit"):
        collide("vz", REF, v, dt=1.01 * limit)
    with pytest.raises(ValueError, match=r"^dt out of range: .* steps"):
        collide("vz", REF, v, dt=1e-300)       # a dt below the clock's resolution must not loop for ever


def test_cli_prints_the_time_step_warning_as_one_line(tmp_path):
    proc = subprocess.run([sys.executable, "-m", "calib.cli", "collide", "--law", "vz", "--v-in", "0.02",
                           "--dt", "1e-4"], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("nfdcal collide: warning: dt = 0.0001 s is too large")


@pytest.mark.parametrize("Ca_factor", [1e-3, 1.0, 1e3])
def test_largest_admissible_Kc_is_the_boundary_and_is_stated_in_the_error(Ca_factor):
    Ca = REF.Ca * Ca_factor
    largest = vz_largest_admissible_Kc(PAIR, Ca)
    VZParams(PAIR, Ca, largest)
    with pytest.raises(ValueError, match=r"Kc out of range") as info:
        VZParams(PAIR, Ca, largest * 1.001)
    assert f"0 <= Kc <= {largest:.4g} 1/N" in str(info.value)


def test_extreme_materials_give_a_clear_error_not_an_overflow():
    with pytest.raises(ValueError, match=r"^R out of range for a particle"):
        ContactPair.sphere_flat(Material.reference(), 1e200)     # OverflowError before
    with pytest.raises(ValueError, match=r"^E out of range for a solid"):
        Material(1e-300, 0.3, 1e8, 2700)                         # ZeroDivisionError before
    with pytest.raises(ValueError, match=r"^Ca out of range"):
        VZParams(PAIR, 1e300, 0.0)            # accepted before, with NaN in its own checks
    with pytest.raises(ValueError, match=r"^delta out of range: the force overflows"):
        get_law("vz").force(np.array([1e300]), get_law("vz").initial_state(1), REF)  # inf, NaN state
    with pytest.raises(ValueError, match=r"^v_in out of range"):
        collide("vz", REF, [1e-300])          # "cannot convert float NaN to integer" before


def test_stability_report_small_grid(tmp_path, monkeypatch):
    import calib.studies.runtime_stability as study
    from calib.cli import main

    monkeypatch.setattr(study, "RADII", (1e-6, 10.0))
    monkeypatch.setattr(study, "POISSON", (0.49,))
    monkeypatch.setattr(study, "STRENGTH_RATIOS", (50.0,))
    monkeypatch.setattr(study, "FACTORS_KC", (1.0, 1e3))
    monkeypatch.setattr(study, "VELOCITY_RATIOS", (0.1, 1e4))
    monkeypatch.setattr(study, "COLLISION_VZ_FACTORS", ((1.0, 1.0), (1e3, 1e3), (1.0, 1e3)))
    monkeypatch.setattr(study, "EXTREME_MATERIALS", ((1e-6, 0.49, 5000.0),))
    monkeypatch.setattr(study, "DT_VELOCITY_RATIOS", (1e3,))
    summary = study.generate(tmp_path)
    assert summary["failures"] == []
    assert set(summary["outcomes"]) <= {"ok", "warned", "clear error"}
    assert summary["outcomes"]["clear error"] >= 2 and summary["outcomes"]["warned"] >= 1
    assert 2 <= summary["newton_max"] < 60
    data = json.loads((tmp_path / study.JSON_NAME).read_text())
    assert data["stamp"]["git_commit"] and len(data["rows"]) == summary["cases"]
    csv_lines = (tmp_path / study.CSV_NAME).read_text().splitlines()
    assert csv_lines[0].startswith("# git_commit") and any(line.startswith("backend,group,law,R") for line in csv_lines)
    # every case on every backend this install has, with the same outcomes
    assert set(summary["backends"]) == set(nfdmodel.native.available_backends())
    assert summary.get("backends_disagree", []) == []
    assert len({r["backend"] for r in data["rows"]}) == len(summary["backends"])
    if "stability" in __import__("calib.cli", fromlist=["x"]).COMMAND_MODULES:
        assert main(["stability", "--runtime", "--out", str(tmp_path)]) == 0

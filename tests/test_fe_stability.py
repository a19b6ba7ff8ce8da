"""FE stability table (calib.studies.fe_stability): extreme inputs either calibrate with an error
estimate or stop with a clear error; the sweep resumes without recomputing; bad calibration inputs
are refused before any mesh is built."""
import json

import pytest

from calib.fit import recipe
from calib.studies import fe_stability
from nfdmodel import ContactPair, Material


def test_fe_stability_small_sweep_resumes(tmp_path, monkeypatch):
    monkeypatch.setattr(fe_stability, "MESH_RATIOS", (0.15, 0.1))
    monkeypatch.setattr(fe_stability, "LOADING_STEPS", 6)
    monkeypatch.setattr(fe_stability, "UNLOADING_STEPS", 3)
    cases = (("soft", 0.49, 50.0, 1e-3, (6.0, 12.0)),
             ("too large a contact", 0.3, 50.0, 0.1, (1000.0,)),
             ("E in GPa", 0.3, 70.0 / 100e6, 0.1, (12.0,)))
    summary = fe_stability.generate(tmp_path, workers=1, cases=cases)
    assert summary["failures"] == []
    assert summary["outcomes"] == {"ok": 2, "clear error": 4}
    data = json.loads((tmp_path / fe_stability.JSON_NAME).read_text())
    rows = {(r["case"], r["mesh_ratio"]): r for r in data["rows"]}
    fine = rows[("soft", 0.1)]
    assert 0 < fine["e"] < 1 and fine["newton_max"] >= 1
    assert abs(fine["P_Y_fe_error"]) < 0.1            # first yield near P_Y(nu = 0.49)
    assert fine["alpha_mesh_change"] is not None and abs(fine["alpha_mesh_change"]) < 0.05
    assert "P_max out of range" in rows[("too large a contact", 0.1)]["outcome"]
    assert "did you give GPa?" in rows[("E in GPa", 0.1)]["outcome"]
    assert data["stamp"]["computed"] == 6
    # a rerun recomputes nothing (each finished run is a file of its own)
    fe_stability.generate(tmp_path, workers=1, cases=cases)
    assert json.loads((tmp_path / fe_stability.JSON_NAME).read_text())["stamp"]["computed"] == 4  # refusals only


@pytest.mark.parametrize("E, peaks_over_yield, match", [
    (70.0, (13.7,), "E out of range for a solid.*did you give GPa"),   # E typed in GPa
    (100e6 * 1e5, (13.7,), "E out of range for a solid"),
    (100e6 * 1.5e4, (13.7,), "E/sigma_Y out of range"),
    (100e6 * 50, (1000.0,), "P_max out of range"),
])
def test_calibration_refuses_inputs_it_cannot_represent(E, peaks_over_yield, match):
    with pytest.raises(ValueError, match=match):
        recipe.calibration_spec(Material(E, 0.3, 100e6, 2700.0), 0.1, peaks_over_yield=peaks_over_yield)


def test_mesh_covers_the_contact_at_deep_plastic_loads():
    """Beyond ~43 P_Y the plastic radius a_p = Ca (P - P_Y) outgrows 1.3 x Hertz: the refined
    zone follows it (at 100 P_Y the estimate is 7.1 a_Y against 1.3 a_H = 6.0 a_Y). E = 80 GPa:
    not the reference sphere, which keeps its own mesh family."""
    material = Material(80e9, 0.3, 100e6, 2700.0)
    pair = ContactPair.sphere_flat(material, 0.1)
    spec = recipe.calibration_spec(material, 0.1, peaks=(100 * pair.P_Y,))
    assert spec.mesh.refined_radius >= pair.hertz_radius(100 * pair.P_Y) + 0.024 * 99 * pair.a_Y
    standard = recipe.calibration_spec(material, 0.1)   # <= 41.2 P_Y: 1.3 x Hertz, as before
    assert standard.mesh.refined_radius == pytest.approx(1.1 * 1.3 * pair.hertz_radius(41.2 * pair.P_Y))
    with pytest.raises(ValueError, match="P_max <= 1000 P_Y"):
        recipe.calibration_spec(material, 0.1, peaks=(2000 * pair.P_Y,))


def test_cli_calibrate_refuses_a_modulus_in_gpa(capsys):
    from calib.cli import main

    assert main(["calibrate", "--quiet", "--E", "70", "--no-plots"]) == 2
    err = capsys.readouterr().err
    assert "did you give GPa? 70 GPa = 7e+10 Pa" in err and "Traceback" not in err and len(err.strip().splitlines()) == 1

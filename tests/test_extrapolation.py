"""Two-mesh calibrations: Richardson extrapolation and its error estimate (calib.fit.extrapolation),
against closed forms, and the calibration that ships it (both meshes, on one or two processes)."""
import dataclasses
import json

import numpy as np
import pytest

from calib.fe import LoadPathPlan
from calib.fit import calibration, extrapolation, recipe
from calib.fit.extrapolation import MeshWarning, order_sensitivity, richardson, unextrapolated
from nfdmodel import load_parameters


def converging(h, Q0=2.37e-7, C=-1.3e-4, p=1.0):
    """A quantity converging as Q0 + C h^p (Ca on the reference ladder: C < 0, it grows under refinement)."""
    return Q0 + C * h**p


def test_first_order_quantity_is_extrapolated_exactly():
    h = 4e-5
    estimate = richardson(converging(h), converging(2 * h))
    assert estimate.extrapolated and estimate.value == pytest.approx(2.37e-7, rel=1e-12)
    # error estimate: |Q_h - Q_2h| (1/(2^0.85 - 1) - 1) / Q0, the lower order's side
    change = converging(h) - converging(2 * h)
    expected = change * (1 / (2**0.85 - 1) - 1) / 2.37e-7
    assert estimate.rel_error_estimate == pytest.approx(expected, rel=1e-12)
    assert order_sensitivity() == pytest.approx(1 / (2**0.85 - 1) - 1, rel=1e-15)


@pytest.mark.parametrize("order", [0.86, 0.94, 1.0, 1.05, 1.14])
def test_error_estimate_bounds_the_true_error_for_orders_within_the_spread(order):
    """Q = Q0 + C h^p with p within ORDER +- ORDER_SPREAD: the p = 1 extrapolation misses Q0 by no
    more than its estimate (the reference ladder's observed orders are 0.94-1.11)."""
    for h in (8e-5, 4e-5, 2e-5):
        fine, coarse = converging(h, p=order, C=-1.3e-4 * 4e-5 ** (1 - order)), converging(
            2 * h, p=order, C=-1.3e-4 * 4e-5 ** (1 - order))
        estimate = richardson(fine, coarse)
        assert estimate.extrapolated
        assert abs(estimate.value / 2.37e-7 - 1) <= estimate.rel_error_estimate * (1 + 1e-9)


@pytest.mark.parametrize("fine, coarse", [(1.0, 1.2), (1.3, 1.0), (1.0, 0.0), (0.0, 0.0)])
def test_pairs_outside_the_asymptotic_range_ship_the_fine_value(fine, coarse):
    """Refinement that lowers the value, or moves it by more than 10 %, is not first-order
    convergence: the fine mesh's value ships with the change as its error estimate."""
    estimate = richardson(fine, coarse)
    assert not estimate.extrapolated and estimate.value == fine
    assert estimate.rel_error_estimate == (abs(fine - coarse) / fine if fine else np.inf)


def test_noise_level_quantities_are_not_extrapolated():
    estimate = unextrapolated(0.7387, 0.7381)
    assert estimate.value == 0.7387 and estimate.rel_error_estimate == pytest.approx(0.0006 / 0.7387)


def test_table_nodes_extrapolate_and_report_relative_to_the_largest_value():
    fine, coarse = np.array([0.0, 1.0, 2.0]), np.array([0.0, 0.9, 1.9])
    value, error = extrapolation.extrapolated_table(fine, coarse)
    assert np.allclose(value, [0.0, 1.1, 2.1])
    assert error == pytest.approx(0.1 * order_sensitivity() / 2.1)


@pytest.fixture(scope="module")
def small_spec():
    """The reference sphere on the coarse test mesh (1.6e-4 m; second mesh 3.2e-4 m), two short paths."""
    spec = recipe.reference_spec(contact_size=1.6e-4)
    return dataclasses.replace(spec, plan=LoadPathPlan(peaks=(500.0, 1000.0), loading_step=125.0,
                                                       unloading_steps=6, first_load=20.0))


@pytest.fixture(scope="module")
def one_mesh(small_spec):
    """The finer mesh's own calibration (meshes=1), on this process."""
    return calibration.calibrate(small_spec, meshes=1)


@pytest.fixture(scope="module")
def two_meshes(small_spec):
    with pytest.warns(MeshWarning, match="not in the asymptotic range for Ca"):
        return calibration.calibrate(small_spec, parallel=True)


def test_two_meshes_ship_the_extrapolation_of_both_fits(small_spec, two_meshes, one_mesh):
    """The shipped Ca, Kc are richardson() of the two meshes' radius fits (each the one-mesh
    calibration of its mesh, bit for bit, whether the second ran on another process or not); on
    these coarse meshes (1.6e-4 / 3.2e-4 m) refinement moves them by more than 10 %: not
    asymptotic, so the fine values ship with the change as the estimate, and a MeshWarning says so."""
    fine = one_mesh
    coarse = calibration.calibrate(recipe.coarse_spec(small_spec), meshes=1)
    assert two_meshes.mesh_pair["radius_fit"] == list(coarse.fitted_constants("radius"))
    s = calibration.summary(two_meshes)
    for name, k in (("Ca", 0), ("Kc", 1)):
        expected = richardson(fine.fitted_constants("radius")[k], coarse.fitted_constants("radius")[k])
        assert s[name] == pytest.approx(expected.value, rel=1e-12)
        assert s[f"{name}_rel_error_estimate"] == pytest.approx(expected.rel_error_estimate, rel=1e-12)
        assert s["discretisation"]["extrapolated"][name] == expected.extrapolated
    assert s["Ca_hat_rel_error_estimate"] == s["Ca_rel_error_estimate"]
    for path, coarse_path in zip(s["paths"], coarse.load_paths.paths):
        assert path["e_rel_error_estimate"] == pytest.approx(abs(path["e"] - coarse_path.restitution) / path["e"])
    assert s["e_rel_error_estimate"] == max(p["e_rel_error_estimate"] for p in s["paths"])
    with pytest.warns(MeshWarning):
        serial = calibration.calibrate(small_spec, parallel=False)
    assert serial.mesh_pair == {**two_meshes.mesh_pair, "wall_time_s": serial.mesh_pair["wall_time_s"]}
    assert calibration.summary(fine)["Ca_rel_error_estimate"] is None


def test_the_finer_mesh_s_rows_are_its_own_whichever_process_unloaded_its_top_path(small_spec, two_meshes, one_mesh):
    """With two meshes the second mesh's process may take the finer mesh's top unloading
    (calib.sweep.runner.Background.offer): every row of every path is the one-mesh calibration's,
    bit for bit (times aside), and so is the factorisation count."""
    fine = one_mesh
    timed = ("wall_time_s", "time_assembly_s", "time_solve_s")
    for ours, theirs in zip(two_meshes.load_paths.paths, fine.load_paths.paths, strict=True):
        assert len(ours.rows) == len(theirs.rows)
        for a, b in zip(ours.rows, theirs.rows):
            assert {k: v for k, v in a.items() if k not in timed} == {k: v for k, v in b.items() if k not in timed}
        assert ours.restitution == theirs.restitution
    assert two_meshes.load_paths.factorizations == fine.load_paths.factorizations
    # the offered task itself (a fresh solver on the same mesh, from the peak state) gives the same rows
    top = fine.load_paths.paths[-1]
    run = calibration.unloading_of({"spec": small_spec, "peak": top.peak, "peak_state": top.peak_state})
    unloading = [r for r in top.rows if r["branch"] == "unloading"]
    assert [{k: v for k, v in r.items() if k not in timed} for r in run.rows] == \
        [{k: v for k, v in r.items() if k not in timed} for r in unloading]
    assert run.alpha_residual == top.alpha_residual


def test_an_offered_task_is_computed_once_by_whichever_process_takes_it():
    """calib.sweep.runner.in_background: an offered task runs on the other process when it is idle
    (take() returns its result); when that process is still busy, take() gives it back (None) and
    the other process skips it."""
    import math
    import time

    from calib.sweep.runner import in_background

    with in_background(time.sleep, 0.0) as background:
        assert background() is None
        take = background.offer(math.sqrt, 16.0)
        time.sleep(1.0)                                # the idle process takes it at once
        assert take() == 4.0
    with in_background(time.sleep, 3.0) as background:
        take = background.offer(math.sqrt, 16.0)
        assert take() is None                          # still sleeping: the task is the caller's
        assert background() is None
    with in_background(time.sleep, 0.0, parallel=False) as background:
        assert background.offer(math.sqrt, 16.0)() is None and background() is None


def test_parameter_file_carries_the_error_estimates(two_meshes, tmp_path):
    from calib.report.calibration import write_calibration_parameters

    path = write_calibration_parameters(tmp_path / "parameters.json", two_meshes, {"git_commit": "test"})
    data = json.loads(path.read_text())
    s = calibration.summary(two_meshes)
    for key in ("Ca_rel_error_estimate", "Kc_rel_error_estimate", "e_rel_error_estimate", "alpha_rel_error_estimate"):
        assert data[key] == s[key] and data[key] > 0
    assert load_parameters(path).Ca == s["Ca"]
    data["Kc_rel_error_estimate"] = -0.01
    path.write_text(json.dumps(data))
    with pytest.raises(ValueError, match="Kc_rel_error_estimate must be a number >= 0 or null"):
        load_parameters(path)


def test_meshes_other_than_one_or_two_are_refused(small_spec):
    with pytest.raises(ValueError, match="meshes must be 1 or 2"):
        calibration.calibrate(small_spec, meshes=3)

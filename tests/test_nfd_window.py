"""The law knows its range: the calibrated window travels with the constants, the runtime counts
and warns about contacts beyond it, and an overlap where the law's contact radius reaches R* is
an error naming the overlap, never a number."""
import json
import warnings

import numpy as np
import pytest

from nfdmodel import (CalibrationWindow, ContactPair, Material, RangeWarning, VZParams, collide, get_law,
                      load_parameters, parameter_record, reference)

pytestmark = pytest.mark.laws      # rerun on the numpy kernels by .ci/run (tests/test_markers.py)

REF = VZParams.reference()
PAIR = REF.pair
LAW = get_law("vz")


def test_the_paper_constants_carry_the_window_they_were_fitted_on():
    window = REF.window
    assert window.P_max_over_P_Y == pytest.approx(1500.0 / PAIR.P_Y) and window.P_min_over_P_Y == 1.0
    assert REF.window_force == pytest.approx(1500.0)
    assert VZParams(PAIR, REF.Ca, REF.Kc).window is None        # constants typed by hand: not stated


def test_step_counts_contacts_beyond_the_window_and_warns_once_naming_the_largest():
    inside = REF.loading_approach(PAIR.P_Y * np.array([2.0, 30.0]))
    beyond = REF.loading_approach(PAIR.P_Y * np.array([100.0, 250.0]))
    with warnings.catch_warnings():
        warnings.simplefilter("error", RangeWarning)           # inside the window: silent
        _, update = LAW.step(inside, LAW.initial_state(2), REF)
    assert update.beyond_window == 0 and update.largest_load_over_P_Y == 0.0
    delta = np.concatenate([inside, beyond])
    with pytest.warns(RangeWarning, match=r"2 contact\(s\) loaded to P/P_Y up to 250 \(fitted on P/P_Y 1..40.9") as caught:
        P, update = LAW.step(delta, LAW.initial_state(4), REF)
    assert len(caught) == 1                                     # once per call
    assert update.beyond_window == 2 and update.largest_load_over_P_Y == pytest.approx(250.0, rel=1e-9)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RangeWarning)           # the kernel counts, never warns
        P_kernel, update_kernel = LAW.step_function(delta, LAW.initial_state(4), REF)
    assert np.array_equal(P, P_kernel) and update_kernel.beyond_window == 2
    # unloading a contact beyond the window moves no turning point: nothing new to count
    state = LAW.committed(LAW.initial_state(4), update)
    _, again = LAW.step_function(0.5 * delta, state, REF)
    assert again.beyond_window == 0
    # per contact, on request: the turning point lies beyond the window
    with pytest.warns(RangeWarning):
        details = LAW.contact_state(delta, LAW.initial_state(4), REF)
    assert details.beyond_window.tolist() == [False, False, True, True]


def test_collisions_report_whether_each_impact_stayed_in_the_window():
    v = np.array([0.01, 0.02, 0.2])                  # 285, 635 and 10431 N; window to 1500 N
    with pytest.warns(RangeWarning, match=r"1 of 3 impact\(s\), up to v_in = 0.2 m/s reaching P/P_Y = 28") as caught:
        result = collide("vz", REF, v)
    assert len(caught) == 1
    assert result.in_calibrated_range.tolist() == [True, True, False]
    np.testing.assert_allclose(result.P_max_over_window, result.P_max / 1500.0)
    records = result.records()
    assert [r["in_calibrated_range"] for r in records] == [True, True, False]
    hertz = collide("hertz", PAIR, v[:1]).records()[0]   # no fitted constants: no window
    assert hertz["in_calibrated_range"] is None and hertz["P_max_over_window"] is None


def test_collisions_flag_impacts_that_yield_below_the_lowest_unloading_path():
    """An impact whose peak lies between first yield and the window's lowest load unloads where the FE
    measured nothing: flagged and warned, like one above the window; an elastic impact (P_max <= P_Y,
    Hertz) is inside for any window."""
    params = VZParams(PAIR, REF.Ca, REF.Kc, CalibrationWindow(10.0, 40.0, None, "lowest path at 10 P_Y"))
    elastic = collide("hertz", PAIR, [1e-4])
    assert elastic.P_max[0] < PAIR.P_Y                       # 0.1 mm/s stays elastic for the reference pair
    loads = collide("vz", VZParams(PAIR, REF.Ca, REF.Kc), [1e-4, 0.004, 0.02]).P_max / PAIR.P_Y
    assert loads[0] < 1.0 < loads[1] < 10.0 < loads[2] < 40.0
    with pytest.warns(RangeWarning, match=r"below its calibrated window: 1 of 3 impact\(s\)") as caught:
        result = collide("vz", params, [1e-4, 0.004, 0.02])
    assert len(caught) == 1
    assert result.in_calibrated_range.tolist() == [True, False, True]


def test_parameter_files_keep_the_window_and_old_files_say_what_is_assumed(tmp_path):
    material = Material.reference()
    window = CalibrationWindow(1.07, 41.2, 0.0148, "FE mesh abc, commit 123")
    params = VZParams(PAIR, REF.Ca, REF.Kc, window)
    record = parameter_record(params, 0.1, material)
    path = tmp_path / "p.json"
    path.write_text(json.dumps(record))
    with warnings.catch_warnings():
        warnings.simplefilter("error", RangeWarning)
        assert load_parameters(path).window == window
    del record["window"]
    path.write_text(json.dumps(record))
    with pytest.warns(RangeWarning, match=r"states no calibrated window .* assuming P/P_Y 1..41.2"):
        assert load_parameters(path).window == CalibrationWindow.assumed_default()
    for bad, needle in (({"P_min_over_P_Y": 1.0}, "missing key"), ({"P_min_over_P_Y": 1.0, "P_max_over_P_Y": 0.5},
                                                                   "P_max_over_P_Y out of range"),
                        ({"P_min_over_P_Y": 1.0, "P_max_over_P_Y": 40.0, "bogus": 1}, "unknown key"),
                        ([1, 40], "must be an object")):
        path.write_text(json.dumps({**record, "window": bad}))
        with pytest.raises(ValueError, match=needle):
            load_parameters(path)


@pytest.mark.parametrize("pair", [PAIR, ContactPair.sphere_flat(Material(3e9, 0.4, 60e6, 1200), 2e-3)])
def test_an_overlap_where_the_contact_radius_reaches_R_is_an_error_in_both_kernels(pair):
    params = VZParams.from_dimensionless(pair, REF.Ca_hat, REF.Kc_hat)
    reach = params.full_contact_approach
    assert float(params.contact_radius_at(params.full_contact_load)) == pytest.approx(pair.R_star, rel=1e-9)
    inside, outside = 0.99 * reach, 1.01 * reach
    P, _ = LAW.force_function(np.array([inside]), LAW.initial_state(1), params)
    P_ref, _ = reference.vz_step(inside, reference.History(), pair.R_star, pair.E_star, pair.P_Y, pair.delta_Y,
                                 params.Ca, params.Kc)
    assert P[0] == pytest.approx(P_ref, rel=1e-9)
    with pytest.raises(ValueError, match=rf"^delta out of range: at delta = {outside:g} m .* need delta < "):
        LAW.force_function(np.array([1e-9, outside]), LAW.initial_state(2), params)
    with pytest.raises(ValueError, match=r"^delta out of range"):
        reference.vz_step(outside, reference.History(), pair.R_star, pair.E_star, pair.P_Y, pair.delta_Y,
                          params.Ca, params.Kc)


def test_an_impact_beyond_the_law_s_domain_names_the_largest_velocity():
    with pytest.raises(ValueError, match=r"^v_in out of range: at v_in = 20 m/s .* need v_in < 5.5\d* m/s"):
        collide("vz", REF, [0.1, 20.0])


@pytest.mark.parametrize("window, flagged", [
    ((1.0, 41.2, 0.0148), None), ((1.0, 1000.0, 0.2), None),
    ((1.0, 4.6e4, 0.05), "P/P_Y up to 4.6e+04 (the FE reaches 1000)"),
    ((1.0, 100.0, 0.3), "a/R* up to 0.3 (the FE reaches 0.2)"),
    ((1.0, 1e4, 0.45, "FE (finite-strain): mesh"), None),
    ((1.0, 4.6e4, 0.05, "FE (finite-strain): mesh"), "P/P_Y up to 4.6e+04 (the FE reaches 10000)"),
    ((1.0, 100.0, 0.9, "FE (finite-strain): mesh"), "a/R* up to 0.9 (the FE reaches 0.45)"),
], ids=["the reference", "at the reach", "load beyond", "radius beyond", "at the finite-strain reach",
        "load beyond finite strain", "radius beyond finite strain"])
def test_a_window_beyond_the_fes_reach_is_flagged(window, flagged):
    """Against the reach of the FE that made the window: the small strain's unless its source names
    finite strain (a finite-strain calibration's, calib.fit.calibration.fitted_window)."""
    import warnings

    from nfdmodel import CalibrationWindow, PlausibilityWarning

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        CalibrationWindow(*window[:3], source=window[3] if len(window) > 3 else "test")
    messages = [str(w.message) for w in caught if issubclass(w.category, PlausibilityWarning)]
    assert (messages == []) if flagged is None else (len(messages) == 1 and flagged in messages[0]), messages

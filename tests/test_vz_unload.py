"""The vz-unload law (the FE's dent and unloading exponent over the turning point): fitted from
one FE run's paths and checked against a separate FE run's paths it was not fitted on, beside the
vz-table law fitted on the same run: on the reference mesh (fitted on the shipped calibration's
paths, results/calibration; held out: calib/data/fe_unloading_default.json) and on the coarse mesh
(calib/data/fe_unloading_coarse.json, both runs); the scalar
transcription against the vectorised kernel; continuity, reloading, no energy created, Hertz
below first yield; refusals of inadmissible tables."""
import csv
import json
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from calib.fe.loadpath import contact_work
from calib.fit.least_squares import radius_law_data
from calib.fit.table_fit import fit_tables
from calib.fit.unload_check import unload_against_path
from calib.fit.unload_fit import fit_unload_law
from nfdmodel import ContactPair, Material, VZTableParams, VZUnloadParams, get_law, reference
from nfdmodel.hertz import hertz_kernel

pytestmark = pytest.mark.laws      # rerun on the numpy kernels by .ci/run (tests/test_markers.py)

ROOT = Path(__file__).resolve().parent.parent
DATA = json.loads((ROOT / "calib" / "data" / "fe_unloading_coarse.json").read_text(encoding="utf-8"))
DEFAULT = json.loads((ROOT / "calib" / "data" / "fe_unloading_default.json").read_text(encoding="utf-8"))
PAIR = ContactPair.sphere_flat(Material.reference(), 0.1)
LAW = get_law("vz-unload")
BENT = VZTableParams(PAIR, (1.0, 3.0, 10.0, 41.0, 200.0, 1000.0), (0.0, 0.06, 0.25, 0.9, 3.0, 10.0),
                     (1.0, 1.02, 1.1, 1.4, 2.5, 6.0))
UNLOADING = ((1.0, 2.2, 7.1, 41.0), (0.0, 0.05, 0.2, 0.45), (1.5, 1.46, 1.41, 1.36))
PARAMS = VZUnloadParams.from_table(BENT, *UNLOADING)


def fitted(run: dict):
    """(vz-unload, vz-table) fitted on one run (loading rows, paths)."""
    loading, paths = run["loading"], run["paths"]
    force, approach, radius = (np.array(loading[k]) for k in ("P", "alpha", "contact_radius"))
    peaks = [p["peak"] for p in paths]
    unload = fit_unload_law(force, approach, radius, PAIR, peaks, [p["alpha_max"] for p in paths],
                            [p["alpha_residual"] for p in paths], [p["unloading_work"] for p in paths])
    data = radius_law_data(force, approach, radius, R_star=PAIR.R_star, E_star=PAIR.E_star, P_Y=PAIR.P_Y)
    return unload, fit_tables(data, PAIR, peaks, [p["unloading_work"] for p in paths])


def csv_rows(name: str) -> list[dict]:
    with open(ROOT / "results" / "calibration" / name, encoding="utf-8") as stream:
        return list(csv.DictReader(line for line in stream if not line.startswith("#")))


def shipped_calibration_run() -> dict:
    """The shipped calibration's FE paths (reference mesh) as a run: its loading rows, and per
    path the peak, alpha_max, alpha_res and the work its unloading rows returned (calib.fe.loadpath)."""
    rows = csv_rows("loading.csv")
    loading = {k: [float(r[k]) for r in rows] for k in ("P", "alpha", "contact_radius")}
    paths = []
    for p in json.loads((ROOT / "results" / "calibration" / "calibration.json").read_text(encoding="utf-8"))["paths"]:
        unloading = [r for r in csv_rows(f"path_P{p['P_max']:g}.csv") if r["branch"] == "unloading"]
        alpha = np.array([p["alpha_max"]] + [float(r["alpha"]) for r in unloading])
        force = np.array([p["P_max"]] + [max(float(r["P"]), 0.0) for r in unloading])
        paths.append({"peak": p["P_max"], "alpha_max": p["alpha_max"], "alpha_residual": p["alpha_residual"],
                      "unloading_work": contact_work(alpha, force)})
    return {"loading": loading, "paths": paths}


def fe_paths(run: dict):
    loading = run["loading"]
    force = np.array(loading["P"])
    for p in run["paths"]:
        to_peak = force <= p["peak"] * (1 + 1e-9)
        yield {"loading_approach": np.array(loading["alpha"])[to_peak], "loading_force": np.maximum(force[to_peak], 0),
               "unloading_approach": np.array(p["unloading"]["alpha"]),
               "unloading_force": np.maximum(np.array(p["unloading"]["P"]), 0.0), "P_max": p["peak"],
               "alpha_max": p["alpha_max"], "alpha_residual": p["alpha_residual"],
               "radius_at_peak": np.array(loading["contact_radius"])[to_peak][-1], "e": p["e"]}


UNLOAD, TABLE = fitted(DATA["fit"])
HELD_OUT = {round(p["P_max"]): (unload_against_path("vz-unload", UNLOAD, p), unload_against_path("vz-table", TABLE, p))
            for p in fe_paths(DATA["held_out"])}
REFERENCE_MESH = fitted(shipped_calibration_run())
HELD_OUT_REFERENCE_MESH = {round(p["P_max"]): tuple(unload_against_path(law, params, p) for law, params in
                                                    zip(("vz-unload", "vz-table"), REFERENCE_MESH))
                           for p in fe_paths(DEFAULT["held_out"])}


@pytest.mark.parametrize("peak", sorted(HELD_OUT_REFERENCE_MESH))
def test_held_out_fe_paths_on_the_reference_mesh_meet_every_target(peak):
    """Reference mesh, every held-out peak (3..34 P_Y): dent within 3 % (or 0.5 % of alpha_max),
    contact radius at the peak within 2 %, unloading force within 2 % of P_max, e within 1 %;
    vz-table (fitted on the same paths) misses the dent by 7-29 %."""
    unload, table = HELD_OUT_REFERENCE_MESH[peak]
    assert unload["within"], unload
    assert unload["loading_error"] <= 0.01
    assert table["dent_error"] < -0.07 and not table["within"]


@pytest.mark.parametrize("peak", sorted(HELD_OUT))
def test_held_out_fe_paths_radius_unloading_and_e(peak):
    """Coarse mesh, every held-out peak (3..34 P_Y): contact radius at the peak within 2 %, the unloading force
    within 2 % of P_max at the FE's unloading points, e within 1 %; vz-table's unloading (a
    Hertz curve) misses the FE's by more."""
    unload, table = HELD_OUT[peak]
    assert abs(unload["radius_error"]) <= 0.02
    assert unload["unloading_error"] <= 0.02
    assert abs(unload["e_error"]) <= 0.01
    assert unload["loading_error"] <= 0.02
    assert unload["unloading_error"] < table["unloading_error"]


@pytest.mark.parametrize("peak", [380, 750, 1250])
def test_held_out_fe_dent_where_the_coarse_mesh_resolves_it(peak):
    """From 10 P_Y up (the coarse contact 6+ elements wide) the dent is the FE's within 3 % (or
    0.5 % of alpha_max), all targets met; vz-table's Hertz unloading leaves it 7-14 % short."""
    unload, table = HELD_OUT[peak]
    assert abs(unload["dent_error"]) <= 0.03 or abs(unload["dent_error_of_alpha_max"]) <= 0.005
    assert unload["within"]
    assert table["dent_error"] < -0.07 and not table["within"]


def test_the_fit_reproduces_its_own_paths():
    for path in fe_paths(DATA["fit"]):
        result = unload_against_path("vz-unload", UNLOAD, path)
        assert abs(result["dent_error_of_alpha_max"]) <= 0.005 and result["unloading_error"] <= 0.02, result


# ------------------------------------------------------------------------------ the law
def scalar_tables(params):
    a, u = params._arrays, params._unload
    return (tuple(list(a[k]) for k in ("x", "f", "df", "g", "dg")),
            tuple(list(u[k]) for k in ("x", "rho", "drho", "m", "dm")))


paths = st.lists(st.lists(st.floats(-2.0, 450.0, allow_nan=False), min_size=1, max_size=20), min_size=1, max_size=4)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(contact_paths=paths)
def test_vectorised_kernel_equals_the_scalar_transcription(contact_paths):
    steps = max(len(p) for p in contact_paths)
    deltas = np.array([[p[min(k, len(p) - 1)] for p in contact_paths] for k in range(steps)]) * PAIR.delta_Y
    table, unloading = scalar_tables(PARAMS)
    state = LAW.initial_state(len(contact_paths))
    histories = [reference.ExponentHistory() for _ in contact_paths]
    for row in deltas:
        P, update = LAW.step_function(row, state, PARAMS)
        LAW.commit(state, update)
        for j, delta in enumerate(row):
            P_ref, histories[j] = reference.vz_unload_step(float(delta), histories[j], PAIR.R_star, PAIR.E_star,
                                                           PAIR.P_Y, PAIR.delta_Y, PAIR.a_Y, table, unloading)
            assert P[j] == pytest.approx(P_ref, rel=1e-10, abs=1e-12 * PAIR.P_Y)
            assert state.delta_res[j] == pytest.approx(histories[j].delta_res, rel=1e-9, abs=1e-9 * PAIR.delta_Y)


def test_hertz_below_first_yield_and_the_vz_table_loading_curve_above():
    delta = PAIR.delta_Y * np.linspace(0.01, 1.0, 30)
    P, state = LAW.force_function(delta, LAW.initial_state(delta.size), PARAMS)
    np.testing.assert_allclose(P, hertz_kernel(delta, PAIR), rtol=1e-14)
    np.testing.assert_array_equal(state.delta_res, 0.0)
    np.testing.assert_allclose(LAW.force_function(0.6 * delta, state, PARAMS)[0], hertz_kernel(0.6 * delta, PAIR),
                               rtol=1e-12)
    above = PAIR.delta_Y * np.geomspace(1.5, 400.0, 20)
    table_law = get_law("vz-table")
    np.testing.assert_allclose(LAW.force_function(above, LAW.initial_state(20), PARAMS)[0],
                               table_law.force_function(above, table_law.initial_state(20), BENT)[0], rtol=1e-13)


def test_turning_points_dent_continuity_and_reloading():
    delta = PAIR.delta_Y * np.geomspace(1.5, 450.0, 40)
    P, state = LAW.force_function(delta, LAW.initial_state(delta.size), PARAMS)
    rho, m = PARAMS.unloading_tables(state.P_max / PAIR.P_Y)
    np.testing.assert_allclose(state.delta_res, rho * delta, rtol=1e-14)
    np.testing.assert_allclose(state.unloading_exponent, m, rtol=1e-14)
    np.testing.assert_allclose(LAW.force_function(delta * (1 - 1e-12), state, PARAMS)[0], P, rtol=1e-10)
    s = 0.6
    gap = state.delta_res + s * (delta - state.delta_res)
    P_half, same = LAW.force_function(gap, state, PARAMS)
    np.testing.assert_allclose(P_half, P * s**m, rtol=1e-12)            # the power curve through the peak
    assert same is state                                                # unloading and reloading keep the history
    P_beyond, moved = LAW.force_function(1.1 * delta, state, PARAMS)
    np.testing.assert_array_less(P, P_beyond)                           # loading beyond the turning point
    np.testing.assert_array_equal(LAW.force_function(0.9 * state.delta_res, state, PARAMS)[0], 0.0)


def test_a_load_unload_reload_cycle_returns_no_more_work_than_it_took():
    """Work along delta: 0 -> peak -> 0 -> 1.5 peak -> 0 (4000 steps per leg, the trapezoid rule):
    what the contact returns never exceeds what it took; below first yield (Hertz) it returns it all."""
    top = PAIR.delta_Y * np.array([0.6, 3.0, 30.0, 300.0])
    fractions = np.concatenate([np.linspace(0, 1, 4001), np.linspace(1, 0, 4001)[1:], np.linspace(0, 1.5, 6001)[1:],
                                np.linspace(1.5, 0, 6001)[1:]])
    state = LAW.initial_state(top.size)
    forces = np.empty((fractions.size, top.size))
    for k, fraction in enumerate(fractions):
        forces[k], state = LAW.force_function(fraction * top, state, PARAMS)
    work = 0.5 * (forces[1:] + forces[:-1]) * np.diff(fractions)[:, None] * top
    taken, returned = np.maximum(work, 0.0).sum(axis=0), -np.minimum(work, 0.0).sum(axis=0)
    assert np.all(returned <= taken * (1 + 1e-9))
    assert returned[0] == pytest.approx(taken[0], rel=1e-9)          # Hertz: elastic
    assert np.all(returned[1:] < 0.99 * taken[1:])


@pytest.mark.parametrize("unloading, message", [
    (((1.0, 5.0), (0.0, 1.0), (1.5, 1.4)), "table dent out of range"),
    (((1.0, 5.0), (0.0, 0.2), (1.5, 0.0)), "table exponent out of range"),
    (((1.0, 5.0), (0.1, 0.2), (1.5, 1.4)), "first unloading node is first yield"),
    (((1.0, 5.0), (0.0, 0.2), (1.4, 1.4)), "first unloading node is first yield"),
    (((1.0, 1.0), (0.0, 0.2), (1.5, 1.4)), "table x_unload out of range"),
    (((1.0, 5.0), (0.0,), (1.5, 1.4)), "need the same length"),
    (((1.0, 41.0), (0.0, 0.01), (1.5, 0.2)), "would create energy"),
])
def test_inadmissible_unloading_tables_are_refused_naming_the_table(unloading, message):
    with pytest.raises(ValueError, match=message):
        VZUnloadParams.from_table(BENT, *unloading)


def test_each_law_takes_only_its_own_parameters():
    with pytest.raises(ValueError, match="law 'vz-table' must be VZTableParams, got VZUnloadParams"):
        get_law("vz-table").force(np.array([1e-5]), get_law("vz-table").initial_state(1), PARAMS)
    with pytest.raises(ValueError, match="law 'vz-unload' must be VZUnloadParams, got VZTableParams"):
        LAW.force(np.array([1e-5]), LAW.initial_state(1), BENT)


def test_collisions_return_the_work_of_the_power_curve():
    """collide and the quasi-static energy balance (collision_reference, which uses each contact's
    own exponent m) agree on e; e equals sqrt(W_u / W_l) of the turning point."""
    from nfdmodel import collide, collision_reference
    v_in = np.array([0.005, 0.02, 0.1])
    reference_impact = collision_reference("vz-unload", PARAMS, v_in)
    np.testing.assert_allclose(collide("vz-unload", PARAMS, v_in, dt=None).e_velocity, reference_impact.restitution,
                               rtol=2e-3)
    rho, m = PARAMS.unloading_tables(reference_impact.P_max / PAIR.P_Y)
    returned = reference_impact.P_max * reference_impact.delta_max * (1 - rho) / (m + 1)
    np.testing.assert_allclose(reference_impact.restitution ** 2, returned / reference_impact.loading_work, rtol=1e-9)


def test_the_friction_models_read_the_law_s_contact_radius():
    from nfdmodel.friction import contact_radius
    delta = PAIR.delta_Y * np.array([0.5, 3.0, 30.0])
    P, state = LAW.force_function(delta, LAW.initial_state(3), PARAMS)
    expected = LAW.contact_state(delta, LAW.initial_state(3), PARAMS).a_ep
    np.testing.assert_allclose(contact_radius("vz-unload", delta, P, state, PARAMS), expected, rtol=1e-12)

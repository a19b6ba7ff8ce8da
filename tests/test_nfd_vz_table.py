"""The vz-table law (load-dependent a_p and C_R tables): the paper's law as its linear special
case, the scalar transcription against the vectorised kernel, continuity and reloading at the
turning point, no energy created, collisions, admissibility and the parameter-file form."""
import json

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st
from scipy.integrate import quad
from scipy.interpolate import PchipInterpolator

from nfdmodel import (Material, VZParams, VZTableParams, collide, collision_reference, get_law, load_parameters,
                      parameter_record, reference)
from nfdmodel.pchip import pchip_evaluate, pchip_slopes

pytestmark = pytest.mark.laws      # rerun on the numpy kernels by .ci/run (tests/test_markers.py)

REF = VZParams.reference()
PAIR = REF.pair
LAW = get_law("vz-table")
# a table whose plastic radius bends over and whose curvature factor grows (the shape the FE
# shows over wide windows: Ca_hat falls from ~0.026 to ~0.010)
BENT = VZTableParams(PAIR, (1.0, 3.0, 10.0, 41.0, 200.0, 1000.0), (0.0, 0.06, 0.25, 0.9, 3.0, 10.0),
                     (1.0, 1.02, 1.1, 1.4, 2.5, 6.0))


def scalar_table(params):
    a = params._arrays
    return tuple(list(a[k]) for k in ("x", "f", "df", "g", "dg"))


@pytest.mark.parametrize("n", [2, 3, 6, 12])
def test_pchip_equals_scipy(n):
    rng = np.random.default_rng(n)
    x = np.concatenate([[1.0], np.sort(rng.uniform(1.5, 1000.0, n - 1))])
    y = np.concatenate([[0.0], np.cumsum(rng.uniform(0.0, 1.0, n - 1))])
    slopes = pchip_slopes(x, y)
    scipy_table = PchipInterpolator(x, y)
    np.testing.assert_allclose(slopes, scipy_table.derivative()(x), rtol=1e-12, atol=1e-15)
    s = np.linspace(1.0, x[-1], 500)
    value, slope = pchip_evaluate(x, y, slopes, s, derivative=True)
    np.testing.assert_allclose(value, scipy_table(s), rtol=1e-12, atol=1e-13)
    np.testing.assert_allclose(slope, scipy_table.derivative()(s), rtol=1e-9, atol=1e-12)


def test_linear_tables_are_the_paper_law_to_round_off():
    table = VZTableParams.from_linear(PAIR, REF.Ca_hat, REF.Kc_hat, [1.0, 3.0, 10.0, 41.0])
    vz = get_law("vz")
    delta = PAIR.delta_Y * np.array([0.5, 1.0, 2.0, 5.0, 20.0, 40.0, 100.0, 300.0, 800.0])  # beyond the nodes too
    P_vz, s_vz = vz.force_function(delta, vz.initial_state(delta.size), REF)
    P_tab, s_tab = LAW.force_function(delta, LAW.initial_state(delta.size), table)
    np.testing.assert_allclose(P_tab, P_vz, rtol=1e-12)
    np.testing.assert_allclose(s_tab.delta_res, s_vz.delta_res, rtol=1e-10, atol=1e-12 * PAIR.delta_Y)
    np.testing.assert_allclose(LAW.force_function(0.7 * delta, s_tab, table)[0],
                               vz.force_function(0.7 * delta, s_vz, REF)[0], rtol=1e-11)
    np.testing.assert_allclose(LAW.loading_work(s_tab.delta_max, s_tab.P_max, table),
                               vz.loading_work(s_vz.delta_max, s_vz.P_max, REF), rtol=1e-12)
    assert table.full_contact_load == pytest.approx(REF.full_contact_load, rel=1e-9)
    np.testing.assert_allclose(collide("vz-table", table, [0.02, 0.1]).e_velocity,
                               collide("vz", REF, [0.02, 0.1]).e_velocity, rtol=1e-10)


paths = st.lists(st.lists(st.floats(-2.0, 450.0, allow_nan=False), min_size=1, max_size=20), min_size=1, max_size=4)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(contact_paths=paths)
@example(contact_paths=[[372.2757187571333, 357.34765625]])   # 1.6 N just before separation from 7.6e5 N
def test_vectorised_kernel_equals_the_scalar_transcription(contact_paths):
    steps = max(len(p) for p in contact_paths)
    deltas = np.array([[p[min(k, len(p) - 1)] for p in contact_paths] for k in range(steps)]) * PAIR.delta_Y
    table = scalar_table(BENT)
    state = LAW.initial_state(len(contact_paths))
    histories = [reference.History() for _ in contact_paths]
    for row in deltas:
        P, update = LAW.step_function(row, state, BENT)
        LAW.commit(state, update)
        for j, delta in enumerate(row):
            P_ref, histories[j] = reference.vz_table_step(float(delta), histories[j], PAIR.R_star, PAIR.E_star,
                                                          PAIR.P_Y, PAIR.delta_Y, PAIR.a_Y, table)
            # near separation P = K (delta - delta_res)^(3/2) is a difference of P_max-sized terms: round-off scale
            assert P[j] == pytest.approx(P_ref, rel=1e-10, abs=1e-12 * max(PAIR.P_Y, histories[j].P_max))
            assert state.delta_res[j] == pytest.approx(histories[j].delta_res, rel=1e-9, abs=1e-9 * PAIR.delta_Y)


def test_turning_points_are_continuous_and_reloading_retraces_unloading():
    delta = PAIR.delta_Y * np.geomspace(1.5, 450.0, 40)
    P, state = LAW.force_function(delta, LAW.initial_state(delta.size), BENT)
    held, _ = LAW.force_function(delta, state, BENT)
    np.testing.assert_allclose(held, P, rtol=1e-13)
    half, unloaded = LAW.force_function(0.95 * delta, state, BENT)
    back, _ = LAW.force_function(delta, unloaded, BENT)
    np.testing.assert_allclose(back, P, rtol=1e-12)
    assert np.all(half < P)
    # the unloading constant is the paper's (4/3) E* C_Rmax^(3/2) sqrt(R*) with C_Rmax = g(x)
    _, g = BENT.tables(state.P_max / PAIR.P_Y)
    np.testing.assert_allclose(state.unloading_stiffness, PAIR.hertz_stiffness * g**1.5, rtol=1e-8)


@pytest.mark.parametrize("peak", [2.0, 30.0, 150.0, 420.0])
def test_loading_work_and_dissipation_match_quadrature(peak):
    delta_max = peak * PAIR.delta_Y
    P_max, state = LAW.force_function(np.array([delta_max]), LAW.initial_state(1), BENT)
    force = lambda d: LAW.force_function(np.array([d]), LAW.initial_state(1), BENT)[0][0]  # noqa: E731
    W_quad = quad(force, 0, delta_max, epsabs=0, epsrel=1e-11, limit=400, points=[PAIR.delta_Y])[0]
    assert LAW.loading_work(np.array([delta_max]), P_max, BENT)[0] == pytest.approx(W_quad, rel=1e-8)
    E_el = quad(lambda d: LAW.force_function(np.array([d]), state, BENT)[0][0], state.delta_res[0], delta_max,
                epsabs=0, epsrel=1e-11, limit=200)[0]
    dissipated = LAW.dissipated_energy(state, BENT)[0]
    assert dissipated == pytest.approx(W_quad - E_el, rel=1e-7) and dissipated >= 0


def test_collisions_dissipate_and_agree_with_the_energy_balance():
    v = PAIR.v_Y * np.array([2.0, 20.0, 200.0])
    exact = collision_reference("vz-table", BENT, v)
    result = collide("vz-table", BENT, v, dt=float(exact.unloading_time_estimate.min()) / 50)
    assert np.all(result.e_velocity < 1) and np.all(np.diff(result.e_velocity) < 0)
    np.testing.assert_allclose(result.e_velocity, exact.restitution, rtol=2e-3)
    assert result.in_calibrated_range.tolist() == [True, True, True]   # BENT's nodes reach 1000 P_Y


@pytest.mark.parametrize("x, f, g, needle", [
    ((1.0, 10.0), (0.0, 1.0), (1.0, 100.0), "stops increasing"),          # curvature grows too fast
    ((1.0, 10.0), (0.0, -0.1), (1.0, 1.1), "must not decrease"),
    ((2.0, 10.0), (0.0, 0.2), (1.0, 1.1), "first node is first yield"),
    ((1.0, 10.0, 5.0), (0.0, 0.2, 0.3), (1.0, 1.1, 1.2), "increase strictly"),
    ((1.0, 10.0), (0.0, 0.2), (1.0, 0.0), "must be > 0"),
    ((1.0, 10.0), (0.0, 0.2), (1.0,), "same length"),
    ((1.0, "10"), (0.0, 0.2), (1.0, 1.1), "must be a number"),
])
def test_inadmissible_tables_are_refused_naming_the_reason(x, f, g, needle):
    with pytest.raises(ValueError, match=needle):
        VZTableParams(PAIR, x, f, g)


def test_the_parameter_file_form(tmp_path):
    record = parameter_record(BENT, 0.1, Material.reference())
    assert record["law"] == "vz-table" and "Ca" not in record
    path = tmp_path / "table.json"
    path.write_text(json.dumps(record))
    assert load_parameters(path) == BENT
    for mutate, needle in ((lambda r: r["table"].pop("C_R"), "missing key"),
                           (lambda r: r["table"].update(bogus=1), "unknown key"),
                           (lambda r: r.update(Ca=1e-7), "not Ca/Kc")):
        broken = json.loads(json.dumps(record))
        mutate(broken)
        path.write_text(json.dumps(broken))
        with pytest.raises(ValueError, match=needle):
            load_parameters(path)

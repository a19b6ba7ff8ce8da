"""nfdmodel.collision: sphere-on-flat impacts (paper section 4: restitution from velocities and from energy)."""
import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from nfdmodel import ContactPair, Material, VZParams, WaltonBraunParams, collide, collision_reference

pytestmark = pytest.mark.laws      # rerun on the numpy kernels by .ci/run (tests/test_markers.py)

REF = VZParams.reference()
PAIR = REF.pair
SWEEP = np.linspace(0.02, 0.2, 10)


def thornton_closed_form(v_in, v_Y):
    r = v_Y / np.asarray(v_in)
    return (np.sqrt(6 * np.sqrt(3) / 5) * np.sqrt(1 - r**2 / 6)
            * (r / (r + 2 * np.sqrt(6 / 5 - r**2 / 5))) ** 0.25)


@pytest.mark.parametrize("law", ["vz", "thornton", "hertz"])
def test_below_yield_restitution_is_one_and_force_is_hertz(law):
    v = PAIR.v_Y * np.array([0.2, 0.5, 0.95])
    result = collide(law, REF, v, dt=1e-6)
    np.testing.assert_allclose(result.e_velocity, 1.0, atol=1e-6)
    np.testing.assert_allclose(result.e_energy, 1.0, atol=1e-6)
    # Hertz impact: delta_max from (1/2) m v^2 = (2/5) k delta^(5/2); contact time (Johnson 11.24)
    delta_max = (0.5 * PAIR.mass_star * v**2 / (0.4 * PAIR.hertz_stiffness)) ** 0.4
    np.testing.assert_allclose(result.P_max, PAIR.hertz_stiffness * delta_max**1.5, rtol=1e-5)
    np.testing.assert_allclose(result.contact_time, 2.9432 * delta_max / v, rtol=1e-3)
    np.testing.assert_array_equal(result.delta_res, 0.0)


def test_velocity_and_energy_restitution_agree_at_paper_dt():
    result = collide("vz", REF, SWEEP, dt=1e-6)
    assert np.all(np.abs(result.e_velocity - result.e_energy) <= 2e-3 * result.e_energy)
    # and both agree with the exact energy-balance value
    exact = collision_reference("vz", REF, SWEEP).restitution
    np.testing.assert_allclose(result.e_velocity, exact, rtol=1e-4)
    assert np.all(np.diff(result.e_velocity) < 0) and np.all(result.e_velocity < 1)
    assert result.max_newton_iterations <= 10


def test_thornton_collision_reproduces_closed_form():
    v = PAIR.v_Y * np.geomspace(2.0, 200.0, 9)
    result = collide("thornton", REF, v, dt=1e-6)
    closed = thornton_closed_form(v, PAIR.v_Y)
    np.testing.assert_allclose(result.e_velocity, closed, rtol=5e-3)
    np.testing.assert_allclose(result.e_energy, closed, rtol=5e-3)
    # the energy-balance reference equals the closed form to round-off
    np.testing.assert_allclose(collision_reference("thornton", PAIR, v).restitution, closed, rtol=1e-12)


def test_walton_braun_restitution_is_sqrt_K1_over_K2():
    wb = WaltonBraunParams(PAIR, 1e8, 2e8)
    result = collide("walton-braun", wb, [0.05, 0.1], dt=1e-6)
    np.testing.assert_allclose(result.e_velocity, np.sqrt(0.5), rtol=1e-4)
    np.testing.assert_allclose(result.e_energy, np.sqrt(0.5), rtol=1e-4)


def test_second_order_convergence_in_dt():
    exact = collision_reference("vz", REF, [0.04])
    errors = [abs(collide("vz", REF, [0.04], dt=dt).e_velocity[0] / exact.restitution[0] - 1)
              for dt in (4e-6, 2e-6)]
    assert 2.5 < errors[0] / errors[1] < 6.0


def test_history_on_request_and_auto_dt():
    result = collide("vz", REF, [0.04, 0.1], dt=None, history=True)
    h = result.history
    assert h.delta.shape == h.force.shape == (result.steps + 1, 2)
    assert h.time.shape == (result.steps + 1,)
    assert np.max(h.force, axis=0) == pytest.approx(result.P_max)
    assert result.dt < 1e-6
    assert collide("vz", REF, [0.04]).history is None
    records = result.records()
    assert set(records[0]) == {"v_in", "v_out", "e_velocity", "e_energy", "P_max", "contact_time",
                               "in_calibrated_range", "P_max_over_window", "dent", "delta_max",
                               "dissipated_plastic"}
    assert [r["in_calibrated_range"] for r in records] == [True, False]   # 0.1 m/s reaches 120 P_Y


def test_large_dt_warns():
    with pytest.warns(RuntimeWarning, match="dt"):
        collide("hertz", REF, [0.1], dt=5e-5)


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(E=st.floats(1e9, 400e9), nu=st.floats(0.0, 0.49), ratio=st.floats(50.0, 5000.0),
       R=st.floats(1e-4, 1.0), rho=st.floats(1000.0, 20000.0), Ca_hat=st.floats(0.005, 0.2),
       Kc_hat=st.floats(0.0, 0.3), v_over_v_Y=st.floats(0.1, 1e3),
       law=st.sampled_from(["vz", "thornton", "walton-braun"]))
def test_no_energy_created_in_random_collisions(E, nu, ratio, R, rho, Ca_hat, Kc_hat, v_over_v_Y, law):
    pair = ContactPair.sphere_flat(Material(E, nu, E / ratio, rho), R)
    try:
        params = VZParams.from_dimensionless(pair, Ca_hat, Kc_hat)
    except ValueError:
        assume(False)
    v = pair.v_Y * v_over_v_Y
    try:
        exact = collision_reference(law, params, [v])
    except ValueError as exc:           # vz: the impact would push its contact radius beyond R*
        assert law == "vz" and str(exc).startswith("v_in out of range: at v_in")
        assume(False)
    result = collide(law, params, [v], dt=float(exact.contact_time_estimate[0]) / 1000)
    for e in (result.e_velocity, result.e_energy, exact.restitution):
        assert np.all(np.isfinite(e)) and np.all(e > 0) and np.all(e <= 1 + 1e-6)
    assert result.e_velocity[0] == pytest.approx(exact.restitution[0], rel=1e-3)


@pytest.mark.parametrize("kwargs, message", [
    (dict(v_in=[0.1], dt=0.0), r"^dt out of range"),
    (dict(v_in=[0.1], dt=-1e-6), r"^dt out of range"),
    (dict(v_in=[0.1], dt=float("nan")), r"^dt must be finite"),
    (dict(v_in=[np.nan]), r"^v_in must be finite"),
    (dict(v_in=[np.inf]), r"^v_in must be finite"),
    (dict(v_in=[0.0]), r"^v_in out of range"),
    (dict(v_in=[-0.1]), r"^v_in out of range"),
    (dict(v_in=[]), r"^v_in must hold"),
])
def test_bad_collision_input(kwargs, message):
    with pytest.raises(ValueError, match=message):
        collide("vz", REF, **kwargs)


def test_unknown_law_in_collision():
    with pytest.raises(ValueError, match=r"^law must be one of"):
        collide("elastic", REF, [0.1])

"""The energies a contact reports: nfdmodel.turning_point.elastic_energy (E_el = P <delta - delta_res> / (n + 1),
the integral of the unloading curve), the C kernel's nfd_elastic_energy, and the plastic energy of
nfdmodel.collide's records (CollisionResult.dissipated_plastic, ``nfdcal collide --json``).

Against what the formula did not produce: E_el against adaptive quadrature of the law's own force along
its unloading curve, from delta_res to delta, for every law (1e-9); the C kernel's value equal to
Python's bit for bit; a collision's dissipated_plastic against 1/2 m* (v_in^2 - v_out^2) of its own
velocities (the leap-frog's O(dt^2): 1e-6 at collide's automatic step, measured at most 7.8e-8); a
second impact below the first's turning point dissipates nothing.
"""
import json

import numpy as np
import pytest
from scipy.integrate import quad

from calib.cli import main
from nfdmodel import (ContactPair, Material, VZParams, VZTableParams, VZUnloadParams, collide, collide_repeated,
                      get_law, limits, native, reference_case)
from nfdmodel.turning_point import elastic_energy

pytestmark = pytest.mark.laws      # rerun on the numpy kernels by .ci/run (tests/test_markers.py)

REF = VZParams.reference()
PAIR = ContactPair.sphere_flat(Material.reference(), reference_case.R)
BENT = VZTableParams(PAIR, (1.0, 3.0, 10.0, 41.0, 200.0, 1000.0), (0.0, 0.06, 0.25, 0.9, 3.0, 10.0),
                     (1.0, 1.02, 1.1, 1.4, 2.5, 6.0))
UNLOAD = VZUnloadParams.from_table(BENT, (1.0, 2.2, 7.1, 41.0), (0.0, 0.05, 0.2, 0.45), (1.5, 1.46, 1.41, 1.36))
CASES = {"hertz": REF, "vz": REF, "thornton": REF, "walton-braun": REF, "vz-table": BENT, "vz-unload": UNLOAD}


def loaded(name: str, overlap: float):
    """A contact of law ``name`` loaded on its virgin curve to ``overlap`` x delta_Y: (law, history)."""
    law = get_law(name)
    _, state = law.force(np.array([overlap * REF.pair.delta_Y]), law.initial_state(1), CASES[name])
    return law, state


@pytest.mark.parametrize("name", sorted(CASES))
@pytest.mark.parametrize("overlap", [3.0, 40.0])
def test_elastic_energy_is_the_integral_of_the_unloading_curve(name, overlap):
    """At the turning point and on its unloading curve: E_el equals the quadrature of the law's force from
    delta_res to delta (1e-9); the C kernel's nfd_elastic_energy equals it bit for bit."""
    law, state = loaded(name, overlap)
    params = CASES[name]
    delta_max = overlap * REF.pair.delta_Y
    delta_res = float(getattr(state, "delta_res", np.zeros(1))[0])
    exponent = law.exponent_of(state)

    def force(delta):
        P, after = law.force(np.array([delta]), state, params)
        assert after is state           # on the unloading curve: the history does not move
        return float(P[0])

    for fraction in (1.0, 0.6, 0.2):
        delta = delta_res + fraction * (delta_max - delta_res)
        P = force(delta)
        energy = float(np.reshape(elastic_energy(np.array([P]), np.array([delta]), delta_res, exponent), -1)[0])
        integral, error = quad(force, delta_res, delta, epsabs=0.0, epsrel=1e-13, limit=200)
        assert energy == pytest.approx(integral, rel=1e-9), (fraction, error)
        code = limits.LAW_CODES.get(name)
        if code is not None and native.active():
            from nfdmodel import _native
            out = np.empty(1)
            _native.elastic_energy(code, np.array([delta]), np.array([delta_res]), np.array(exponent, float).reshape(1),
                                   np.array([P]), out)
            assert out[0] == energy


def test_the_kernel_has_an_elastic_energy_for_every_law_and_nan_for_none():
    """nfd_elastic_energy answers for every code of nfd_limits.h (a law added there needs its case) and
    NaN for a code outside the table."""
    if not native.active():
        pytest.skip("the compiled kernel is not built")
    from nfdmodel import _native
    out = np.empty(1)
    for code in limits.LAW_CODES.values():
        _native.elastic_energy(code, np.array([2.0]), np.array([1.0]), np.array([1.4]), np.array([5.0]), out)
        assert np.isfinite(out[0]) and out[0] > 0.0, code
    _native.elastic_energy(limits.LAW_COUNT, np.array([2.0]), np.array([1.0]), np.array([1.4]), np.array([5.0]), out)
    assert np.isnan(out[0])


@pytest.mark.parametrize("name", sorted(CASES))
def test_a_collision_records_the_energy_it_lost(name):
    """dissipated_plastic of collide's records against the kinetic energy its own velocities lost,
    1/2 m* (v_in^2 - v_out^2) (1e-6; an elastic Hertz impact loses none), and the dent its delta_res."""
    params = CASES[name]
    v_in = np.array([3.0, 20.0]) * PAIR.v_Y
    result = collide(name, params, v_in, dt=None)
    lost = 0.5 * PAIR.mass_star * (v_in**2 - result.v_out**2)
    for record, loss, dent in zip(result.records(), lost, result.delta_res):
        assert record["dent"] == dent
        if name == "hertz":
            energy = 0.5 * PAIR.mass_star * v_in[0] ** 2
            assert record["dissipated_plastic"] < 1e-12 * energy and abs(loss) < 1e-6 * energy
        else:
            assert record["dissipated_plastic"] == pytest.approx(loss, rel=1e-6)


@pytest.mark.parametrize("name", ["vz", "vz-table", "vz-unload"])
def test_repeated_impacts_record_each_impact_s_own_loss(name):
    """collide_repeated: each impact's dissipated_plastic is the kinetic energy it lost (1e-5); a second
    impact slower than the first's rebound stays below the turning point and loses nothing."""
    params = CASES[name]
    v_in = 10.0 * PAIR.v_Y
    results = collide_repeated(name, params, [v_in], 3)
    for result in results:
        loss = 0.5 * PAIR.mass_star * (v_in**2 - result.v_out[0] ** 2)
        assert result.records()[0]["dissipated_plastic"] == pytest.approx(loss, rel=1e-5)
    law = get_law(name)
    first, state = collide(name, params, [v_in], dt=None, start=law.initial_state(1))
    second, _ = collide(name, params, [0.9 * first.e_velocity[0] * v_in], dt=first.dt, start=state)
    assert second.records()[0]["dissipated_plastic"] == 0.0


def test_collide_json_carries_the_contact_state(capsys):
    """``nfdcal collide --json``: dent, delta_max and dissipated_plastic per impact."""
    assert main(["collide", "--law", "vz", "--v-in", "0.04", "--dt", "1e-6", "--json"]) == 0
    record = json.loads(capsys.readouterr().out)[0]
    result = collide("vz", REF, [0.04], dt=1e-6)
    assert record["dent"] == result.delta_res[0] and record["delta_max"] == result.delta_max[0]
    assert record["dissipated_plastic"] == pytest.approx(
        0.5 * REF.pair.mass_star * (0.04**2 - result.v_out[0] ** 2), rel=1e-4)

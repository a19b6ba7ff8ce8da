"""The vectorised kernels against the plain scalar transcription (nfdmodel.reference), the porting
specification: random load / unload / reload / separation / re-contact histories, every law."""
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from nfdmodel import ContactPair, Material, VZParams, WaltonBraunParams, get_law, reference, reference_case

pytestmark = pytest.mark.laws      # rerun on the numpy kernels by .ci/run (tests/test_markers.py)

PAIR = ContactPair.reference()
VZ = VZParams.reference()
WB = WaltonBraunParams.from_vz(VZ)
# the vectorised Newton stops at 1e-10 relative in P, the scalar one at 1e-13
RTOL = 1e-8


def scalar_law(name):
    R, E, P_Y, d_Y, p_Y = PAIR.R_star, PAIR.E_star, PAIR.P_Y, PAIR.delta_Y, PAIR.p_Y
    return {"hertz": lambda d, h: reference.hertz_step(d, h, R, E),
            "vz": lambda d, h: reference.vz_step(d, h, R, E, P_Y, d_Y, VZ.Ca, VZ.Kc),
            "thornton": lambda d, h: reference.thornton_step(d, h, R, E, P_Y, d_Y, p_Y),
            "walton-braun": lambda d, h: reference.walton_braun_step(d, h, WB.K1, WB.K2)}[name]


PARAMS = {"hertz": PAIR, "vz": VZ, "thornton": PAIR, "walton-braun": WB}
# approaches in units of delta_Y: negative (apart) to 300 delta_Y (~ 1e4 P_Y for vz)
paths = st.lists(st.lists(st.floats(-2.0, 300.0, allow_nan=False), min_size=1, max_size=25),
                 min_size=1, max_size=4)


@pytest.mark.parametrize("name", ["hertz", "vz", "thornton", "walton-braun"])
@settings(max_examples=60, deadline=None)
@given(contact_paths=paths)
def test_vectorised_kernel_equals_the_scalar_reference(name, contact_paths):
    steps = max(len(p) for p in contact_paths)
    # each contact holds its last approach once its own path ends
    deltas = np.array([[p[min(k, len(p) - 1)] for p in contact_paths] for k in range(steps)]) * PAIR.delta_Y
    law, step = get_law(name), scalar_law(name)
    state = law.initial_state(len(contact_paths))
    histories = [reference.History() for _ in contact_paths]
    for row in deltas:
        P, update = law.step(row, state, PARAMS[name])
        law.commit(state, update)
        for j, delta in enumerate(row):
            P_ref, histories[j] = step(float(delta), histories[j])
            assert P[j] == pytest.approx(P_ref, rel=RTOL, abs=1e-12 * PAIR.P_Y)
            if name != "hertz":
                assert state.delta_max[j] == histories[j].delta_max
                assert state.P_max[j] == pytest.approx(histories[j].P_max, rel=RTOL, abs=1e-12 * PAIR.P_Y)
                assert state.delta_res[j] == pytest.approx(histories[j].delta_res, rel=RTOL,
                                                           abs=1e-9 * PAIR.delta_Y)


def test_the_reference_case_anchor():
    """The corrected F(P) gives the paper's P = 1495 N at alpha = 1.56e-5 m with its Ca, Kc."""
    pair = ContactPair.sphere_flat(Material.reference(), reference_case.R)
    P, history = reference.vz_step(reference_case.ALPHA_MAX_AFG, reference.History(), pair.R_star,
                                   pair.E_star, pair.P_Y, pair.delta_Y, reference_case.CA, reference_case.KC)
    assert P == pytest.approx(1495.0, abs=1.0)
    # and the turning point it leaves: unloading returns through it, separation at delta_res
    assert reference.unloading_force(history.delta_max, history, 1.5) == pytest.approx(P, rel=1e-12)
    assert reference.vz_step(history.delta_res, history, pair.R_star, pair.E_star, pair.P_Y,
                             pair.delta_Y, reference_case.CA, reference_case.KC)[0] == 0.0


def test_newton_function_is_zero_on_the_explicit_loading_curve():
    """F(P) = 0 exactly where delta = (a_e + a_p)^2 / (C_R R) (paper eq. 3.4), at 2..1e4 P_Y."""
    for load in np.geomspace(2.0, 1e4, 9) * PAIR.P_Y:
        delta = float(VZ.loading_approach(load))
        F, dF = reference.vz_newton_function(load, delta, PAIR.R_star, PAIR.E_star, PAIR.P_Y, VZ.Ca, VZ.Kc)
        assert abs(F) <= 1e-9 * load and dF > 0
        assert reference.vz_loading_force(delta, PAIR.P_Y, PAIR.R_star, PAIR.E_star, PAIR.P_Y,
                                          VZ.Ca, VZ.Kc) == pytest.approx(load, rel=1e-11)
    assert math.isfinite(reference.hertz_force(-1.0, 1.0, 1.0))

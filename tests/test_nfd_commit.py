"""nfdmodel.history: sparse trial history (ContactLaw.step -> HistoryUpdate) and its commit.

``P, update = law.step(delta, state, params); law.commit(state, update)`` (in place) must give
exactly the force and history of the pure ``P, state = law.force(delta, state, params)``, for
every law and along load / partial unload / reload / separation / re-contact sequences; the pure
path never mutates its input; bad updates are refused with a ValueError naming the parameter.
"""
from dataclasses import fields

import numpy as np
import pytest

import nfdmodel.turning_point as turning_point
from nfdmodel import (HertzState, HistoryUpdate, ThorntonState, VZParams, VZState, WaltonBraunState, get_law,
                      vz_force_with_iterations)

pytestmark = pytest.mark.laws      # rerun on the numpy kernels by .ci/run (tests/test_markers.py)

REF = VZParams.reference()
PAIR = REF.pair
LAWS = ["vz", "thornton", "walton-braun", "hertz"]
# the reference and an extreme vz case (Ca, Kc at 1e3 x: recovery near the float spacing)
PARAMS = [REF, VZParams(PAIR, REF.Ca * 1e3, REF.Kc * 1e3)]


def random_sequence(rng, n: int, steps: int = 24) -> np.ndarray:
    """Approaches [m] (steps x n) for n contacts: phases of loading (elastic and plastic, small
    increments and jumps), partial unloading, reloading past the turning point, separation
    (negative approach or below delta_res) and re-contact, each contact on its own path."""
    dY = PAIR.delta_Y
    delta = np.zeros(n)
    path = []
    for step in range(steps):
        phase = rng.integers(0, 5, n)              # per contact
        jump = dY * rng.uniform(0.0, 40.0, n) * (rng.random(n) < 0.5)
        small = delta * rng.uniform(0.0, 1e-3, n) + dY * 1e-4 * rng.random(n)
        delta = np.select(
            [phase == 0, phase == 1, phase == 2, phase == 3, phase == 4],
            [delta + jump + small,                               # loading
             delta * rng.uniform(0.2, 1.0, n),                   # partial unloading
             delta * rng.uniform(1.0, 1.5, n),                   # reloading (past delta_max or not)
             np.where(rng.random(n) < 0.5, -dY * rng.random(n), 0.0),   # separation
             dY * rng.uniform(0.0, 60.0, n)])                    # re-contact anywhere
        if step % 7 == 6:
            delta = delta.copy()                    # hold: same approach twice
            path.append(delta)
        path.append(delta)
    return np.array(path)


def snapshot(state):
    if isinstance(state, HertzState):
        return {"n": state.n}
    return {f.name: getattr(state, f.name).copy() for f in fields(state)}


def assert_same_state(a, b):
    assert type(a) is type(b)
    if isinstance(a, HertzState):
        assert a.n == b.n
        return
    for f in fields(a):
        np.testing.assert_array_equal(getattr(a, f.name), getattr(b, f.name), err_msg=f.name)


def assert_unchanged(state, before):
    if isinstance(state, HertzState):
        assert state.n == before["n"]
        return
    for name, values in before.items():
        np.testing.assert_array_equal(getattr(state, name), values, err_msg=name)


@pytest.mark.parametrize("block", [None, 5])
@pytest.mark.parametrize("params", PARAMS, ids=["reference", "extreme"])
@pytest.mark.parametrize("name", LAWS)
def test_step_and_in_place_commit_equal_the_pure_force(name, params, block, monkeypatch):
    """Same force and same history (array_equal) at every step of several random sequences;
    block = 5 makes the kernel work on many small blocks (loading ones too)."""
    if block is not None:
        monkeypatch.setattr(turning_point, "BLOCK", block)
    law = get_law(name)
    p = law.params_from(params)
    rng = np.random.default_rng(2024)
    for n in (1, 7, 64):
        path = random_sequence(rng, n)
        pure = law.initial_state(n)
        owned = law.initial_state(n)
        moved = 0
        for delta in path:
            before = snapshot(pure)
            P_pure, pure_next = law.force(delta, pure, p)
            assert_unchanged(pure, before)                      # the pure force never mutates
            P_step, update = law.step(delta, owned, p)
            assert isinstance(update, HistoryUpdate) and update.n == n
            assert law.commit(owned, update) is owned
            np.testing.assert_array_equal(P_step, P_pure)
            assert_same_state(owned, pure_next)
            if update.size == 0:
                assert pure_next is pure                        # nothing moved: no copy either
            else:
                assert not any(np.shares_memory(getattr(pure_next, f.name), getattr(pure, f.name))
                               for f in fields(pure))
            moved += update.size
            pure = pure_next
        if name != "hertz":
            assert moved > n                                    # turning points moved repeatedly


@pytest.mark.parametrize("name", LAWS)
def test_blocking_does_not_change_results(name, monkeypatch):
    """The kernel works in blocks of BLOCK contacts; results are bit-identical for any block."""
    law = get_law(name)
    p = law.params_from(REF)
    path = random_sequence(np.random.default_rng(5), 300, steps=12)
    results = []
    for block in (turning_point.BLOCK, 1, 16, 97):
        monkeypatch.setattr(turning_point, "BLOCK", block)
        state = law.initial_state(path.shape[1])
        forces, iterations = [], []
        for delta in path:
            P, update = law.step(delta, state, p)
            law.commit(state, update)
            forces.append(P)
            iterations.append(update.newton_iterations)
        results.append((np.array(forces), snapshot(state), iterations))
    for forces, state, iterations in results[1:]:
        np.testing.assert_array_equal(forces, results[0][0])
        assert iterations == results[0][2]
        for key in state:
            np.testing.assert_array_equal(state[key], results[0][1][key])


def test_vz_update_carries_the_named_history_and_newton_iterations():
    law = get_law("vz")
    dY = PAIR.delta_Y
    state = law.initial_state(4)
    _, state = law.force(np.array([10 * dY, 20 * dY, 0.5 * dY, 30 * dY]), state, REF)
    before = snapshot(state)
    delta = np.array([11 * dY, 15 * dY, 0.7 * dY, 90 * dY])      # loads: 0, 2 (elastic), 3 (jump)
    P, update = law.step(delta, state, REF)
    assert_unchanged(state, before)                              # step does not mutate either
    np.testing.assert_array_equal(update.index, [0, 2, 3])
    assert update.index.dtype == np.int64 and update.size == 3
    assert isinstance(update.values, VZState) and update.values.n == 3
    np.testing.assert_array_equal(update.values.delta_max, delta[[0, 2, 3]])
    np.testing.assert_array_equal(update.values.P_max, P[[0, 2, 3]])
    assert not np.shares_memory(update.values.delta_max, delta)
    _, _, iterations = vz_force_with_iterations(delta, state, REF)
    assert update.newton_iterations == iterations > 2            # the jump needs the safe path
    # the update is a frozen record
    with pytest.raises(AttributeError):
        update.index = np.array([1])


@pytest.mark.parametrize("name", LAWS)
def test_commit_of_an_empty_update_is_a_no_op(name):
    law = get_law(name)
    p = law.params_from(REF)
    state = law.initial_state(3)
    _, state = law.force(PAIR.delta_Y * np.array([5.0, 1.0, 20.0]), state, p)
    before = snapshot(state)
    P, update = law.step(PAIR.delta_Y * np.array([4.0, 0.5, -1.0]), state, p)   # all unloading
    assert update.size == 0 and update.newton_iterations == 0
    assert law.commit(state, update) is state
    assert law.committed(state, update) is state
    assert_unchanged(state, before)
    P_pure, same = law.force(PAIR.delta_Y * np.array([4.0, 0.5, -1.0]), state, p)
    np.testing.assert_array_equal(P, P_pure)
    assert same is state


def test_hertz_step_has_an_empty_update():
    law = get_law("hertz")
    delta = PAIR.delta_Y * np.array([0.0, 2.0, 50.0, -1.0])
    P, update = law.step(delta, law.initial_state(4), PAIR)
    np.testing.assert_array_equal(P, law.force(delta, law.initial_state(4), PAIR)[0])
    assert update.size == 0 and isinstance(update.values, HertzState) and update.n == 4


def test_committed_copies_and_leaves_the_state_alone():
    law = get_law("thornton")
    state = law.initial_state(3)
    before = snapshot(state)
    _, update = law.step(PAIR.delta_Y * np.array([3.0, 0.0, 9.0]), state, PAIR)
    new = law.committed(state, update)
    assert new is not state
    assert_unchanged(state, before)
    np.testing.assert_array_equal(new.delta_max, PAIR.delta_Y * np.array([3.0, 0.0, 9.0]))


def _vz_update(n_state=3):
    law = get_law("vz")
    state = law.initial_state(n_state)
    _, update = law.step(PAIR.delta_Y * np.arange(1.0, n_state + 1.0) * 5.0, state, REF)
    return law, state, update


def test_mismatched_updates_raise_naming_the_parameter():
    law, state, update = _vz_update(3)
    before = snapshot(state)
    # another law's history class
    thornton = get_law("thornton")
    with pytest.raises(ValueError, match=r"^update does not match state: update.values is a VZState "
                                         r"but state is a ThorntonState"):
        thornton.commit(ThorntonState.virgin(3), update)
    # computed for another number of contacts
    with pytest.raises(ValueError, match=r"^update does not match state: update was computed for 3 "
                                         r"contacts but state holds 4"):
        law.commit(law.initial_state(4), update)
    # index and values of different lengths
    short = HistoryUpdate(update.index[:2], update.values, 3)
    with pytest.raises(ValueError, match=r"^update does not match state: update.index has 2 contacts "
                                         r"but update.values.delta_max has shape \(3,\)"):
        law.commit(state, short)
    # positions outside the state
    outside = HistoryUpdate(np.array([0, 1, 3]), update.values, 3)
    with pytest.raises(ValueError, match=r"^update.index out of range: contact positions must be in 0..2"):
        law.commit(state, outside)
    with pytest.raises(ValueError, match=r"^update.index out of range"):
        law.commit(state, HistoryUpdate(np.array([-1, 0, 1]), update.values, 3))
    # not an integer index
    with pytest.raises(ValueError, match=r"^update.index must be a 1-d integer array"):
        law.commit(state, HistoryUpdate(update.index.astype(float), update.values, 3))
    # not an update at all, or a state in its place
    with pytest.raises(ValueError, match=r"^update must be a HistoryUpdate"):
        law.commit(state, update.values)
    # the state of another law
    with pytest.raises(ValueError, match=r"^state for law 'vz' must be a VZState"):
        law.commit(WaltonBraunState.virgin(3), update)
    # a Hertz update with contacts in it
    with pytest.raises(ValueError, match=r"^update does not match state: a Hertz contact has no history"):
        get_law("hertz").commit(HertzState(3), HistoryUpdate(np.array([0]), HertzState(0), 3))
    # every refused commit left the state untouched (checked before anything is written)
    assert_unchanged(state, before)
    law.commit(state, update)
    assert state.delta_max[2] == 15 * PAIR.delta_Y


@pytest.mark.parametrize("name", ["vz", "thornton", "walton-braun"])
def test_bad_input_to_step_is_refused_like_force(name):
    law = get_law(name)
    p = law.params_from(REF)
    with pytest.raises(ValueError, match=r"^delta must be finite"):
        law.step(np.array([1e-6, np.nan]), law.initial_state(2), p)
    with pytest.raises(ValueError, match=r"contacts but the state holds"):
        law.step(np.array([1e-6, 2e-6]), law.initial_state(1), p)
    other = "vz" if name != "vz" else "thornton"
    with pytest.raises(ValueError, match=rf"^state for law '{name}'"):
        law.step(np.array([1e-6]), get_law(other).initial_state(1), p)


def test_step_keeps_the_shape_of_delta_and_accepts_float32():
    law = get_law("vz")
    delta = (PAIR.delta_Y * np.array([[1.0, 5.0], [30.0, 0.2]])).astype(np.float32)
    P, update = law.step(delta, law.initial_state(4), REF)
    P_pure, state = law.force(delta, law.initial_state(4), REF)
    assert P.shape == (2, 2) and P.dtype == np.float64
    np.testing.assert_array_equal(P, P_pure)
    owned = law.initial_state(4)
    law.commit(owned, update)
    assert_same_state(owned, state)

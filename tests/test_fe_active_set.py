"""The contact active set (calib.fe.active_set): the update on its own (settled, release and add,
the cycling branch, the support under force control), and inside the solver (the first
prediction is the Hertz contact; a step that cycles is reported unconverged)."""
import numpy as np
import pytest
from conftest import PAIR, R

import calib.fe.solver
from calib.fe import StepNotConverged
from calib.fe.active_set import next_active_set


@pytest.mark.parametrize("P", [50.0, 1000.0])
def test_first_prediction_is_the_hertz_contact(elastic_solver, P):
    """On the first step the prediction is the set of nodes inside the Hertz radius; on the coarse
    mesh the elastic solve confirms it in one active-set iteration (measured at 50-1500 N)."""
    state = elastic_solver.initial_state()
    predicted = elastic_solver.predict_active_set(state, "force", P)
    assert np.array_equal(predicted, elastic_solver.candidate_r <= PAIR.hertz_radius(P))
    result = elastic_solver.solve_force(state, P)
    assert result.converged and result.record.active_set_iterations == 1
    assert np.array_equal(result.state.active, predicted)


def test_a_step_that_cycles_is_reported_unconverged(elastic_solver, monkeypatch):
    """Force a cycle: every set the update proposes (the full update, then the worst-node one)
    counts as solved before. The step must end with "active set cycles", unconverged, with the
    committed state unchanged and uncommittable."""
    def cycling(active, reaction, gap, visited, **options):
        tried = set(visited)
        for _ in range(2):
            proposal = next_active_set(active, reaction, gap, set(tried), **options)
            if proposal.settled or proposal.active is None:
                break
            tried.add(proposal.active.tobytes())
        visited |= tried
        return next_active_set(active, reaction, gap, visited, **options)

    monkeypatch.setattr(calib.fe.contact_loop, "next_active_set", cycling)
    state = elastic_solver.initial_state()
    # started from the committed set (the pole alone) the set must grow: the update is needed
    result = elastic_solver.solve_step(state, "displacement", 2e-6, start=state)
    assert not result.converged and result.message == "active set cycles"
    assert result.state is state
    with pytest.raises(StepNotConverged, match="active set cycles"):
        elastic_solver.commit(result)


def test_settled_set_is_recognised():
    active = np.array([True, True, False])
    update = next_active_set(active, np.array([1.0, 2.0, 0.0]), np.array([0.0, 0.0, 1e-6]), set(),
                             force_tolerance=1e-9, gap_tolerance=1e-12, force_scale=1.0,
                             length_scale=R, force_control=True)
    assert update.settled and update.active is None


def test_tensile_nodes_are_released_and_penetrating_ones_added():
    active = np.array([True, True, False, False])
    visited = {active.tobytes()}
    update = next_active_set(active, np.array([1.0, -0.5, 0.0, 0.0]),
                             np.array([0.0, 0.0, -1e-6, 1e-6]), visited, force_tolerance=1e-9,
                             gap_tolerance=1e-12, force_scale=1.0, length_scale=R,
                             force_control=True)
    assert not update.settled
    assert update.active.tolist() == [True, False, True, False]
    assert update.active.tobytes() in visited


def test_cycling_changes_only_the_worst_node_then_gives_up():
    """The full update leads back to a set already solved: only the worst violation flips."""
    active = np.array([True, True, False, False])
    reaction = np.array([1.0, -0.5, 0.0, 0.0])             # node 1 tensile (violation 0.5)
    gap = np.array([0.0, 0.0, -1e-3 * R, 0.0])              # node 2 penetrates (violation 1e-3)
    full = np.array([True, False, True, False])
    visited = {active.tobytes(), full.tobytes()}
    kwargs = dict(force_tolerance=1e-9, gap_tolerance=1e-12, force_scale=1.0, length_scale=R,
                  force_control=True)
    update = next_active_set(active, reaction, gap, visited, **kwargs)
    assert update.active.tolist() == [True, False, False, False]  # only node 1 released
    visited.add(np.array([True, False, False, False]).tobytes())
    cycles = next_active_set(active, reaction, gap, visited, **kwargs)
    assert not cycles.settled and cycles.active is None


def test_force_control_keeps_a_support():
    active = np.array([True, False, False])
    update = next_active_set(active, np.array([-1.0, 0.0, 0.0]), np.array([3e-9, 2e-9, 1e-9]),
                             set(), force_tolerance=1e-9, gap_tolerance=1e-12, force_scale=1.0,
                             length_scale=R, force_control=True)
    assert update.active.tolist() == [False, False, True]  # the smallest gap carries the plate


def test_a_node_open_inside_the_contact_stays_open_in_displacement_control(elastic_solver):
    """The warm start of a displacement step keeps a node that separated inside the last contact open
    (the pole lifts off the flat at a/R 0.28 on contact elements R/100; closing it again stalled
    Newton at a residual of 0.04): the rest of the prediction unchanged, the contiguous set's
    prediction unchanged, and force control still adds the pole as its support."""
    import dataclasses

    state = elastic_solver.solve_displacement(elastic_solver.initial_state(), 1e-4 * R).state
    assert state.active[:3].all()
    target = 1.5 * state.alpha
    contiguous = elastic_solver.predict_active_set(state, "displacement", target)
    lifted = dataclasses.replace(state, active=state.active & (np.arange(state.active.size) != 0))
    predicted = elastic_solver.predict_active_set(lifted, "displacement", target)
    assert not predicted[0] and np.array_equal(predicted[1:], contiguous[1:]) and contiguous[0]
    assert elastic_solver.predict_active_set(lifted, "force", 1.5 * state.force)[0]

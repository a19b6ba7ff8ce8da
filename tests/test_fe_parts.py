"""The parts of the contact solver on their own: linear solvers, active-set update, rescue solve."""
import sys

import numpy as np
import pytest
import scipy.sparse as sp

from calib.fe import Material, VonMisesMaterial, run_load_path
from calib.fe.active_set import next_active_set
from calib.fe.elastic import ElasticMaterial
from calib.fe.linsolve import METHODS, factorize

from conftest import E, NU, R, SIGMA_Y



def laplacian(n):
    """The 1-D Dirichlet Laplacian: symmetric positive definite, known to every solver."""
    return sp.diags([-np.ones(n - 1), 2 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1], format="csc")


# --------------------------------------------------------------------------- linear solvers
@pytest.mark.parametrize("method", ["splu", "qdldl"])
def test_every_backend_solves_a_known_system(method):
    A = laplacian(50)
    x = np.linspace(-1.0, 2.0, 50)
    np.testing.assert_allclose(factorize(A, method).solve(A @ x), x, rtol=1e-10)


def test_a_missing_backend_falls_back_to_superlu(monkeypatch):
    monkeypatch.setitem(sys.modules, "qdldl", None)  # "not installed": import raises ImportError
    A = laplacian(30)
    factor = factorize(A, "qdldl")
    x = np.arange(1.0, 31.0)
    assert factor.method == "splu"
    np.testing.assert_allclose(factor.solve(A @ x), x, rtol=1e-10)


@pytest.mark.parametrize("method", [m for m in METHODS if m != "pardiso"])
def test_a_singular_matrix_is_a_clear_error_never_nan(method):
    A = laplacian(20).tolil()
    A[5, :] = 0.0
    A[:, 5] = 0.0  # a zero row and column: exactly singular
    with pytest.raises(np.linalg.LinAlgError, match="singular"):
        factorize(A.tocsc(), method)


def test_unknown_backend_is_refused():
    with pytest.raises(ValueError, match="method must be one of"):
        factorize(laplacian(3), "umfpack")


# --------------------------------------------------------------------------- active set
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


# --------------------------------------------------------------------------- materials, rescue
def test_both_materials_meet_the_protocol():
    assert isinstance(ElasticMaterial(E, NU), Material)
    assert isinstance(VonMisesMaterial(E, NU, SIGMA_Y), Material)


@pytest.mark.parametrize("control", ["force", "displacement"])
def test_rescue_solve_reaches_the_ordinary_solution(plastic_solver, control):
    """A plastic step both solves can take: the same equilibrium to the residual tolerance,
    and the rescue record charges every solve it tried."""
    _, state = run_load_path(plastic_solver, [50.0, 150.0], control="force")
    target = 200.0 if control == "force" else 1.2 * state.alpha
    step = plastic_solver.solve_force if control == "force" else plastic_solver.solve_displacement
    ordinary = step(state, target)
    rescued = plastic_solver.rescue_step(state, control, target)
    assert ordinary.converged and rescued.converged
    assert "rescue" in rescued.message
    assert rescued.record.alpha == pytest.approx(ordinary.record.alpha, rel=1e-6)
    assert rescued.record.P == pytest.approx(ordinary.record.P, rel=1e-6)
    assert rescued.record.newton_iterations >= 1 and len(rescued.residual_history) >= 2


def test_rescue_by_displacement_when_the_force_solve_fails(plastic_solver):
    """Stage 2 of the rescue: the force step 150 -> 400 N in one increment stalls the ordinary
    Newton (the plastic zone runs away under force control) and stage 1 too; displacement control
    reaches it. Reference: the same load in four ordinary increments (backward Euler is path
    dependent in plasticity, so the two agree to the step-size error, not to round-off)."""
    _, state = run_load_path(plastic_solver, [50.0, 150.0], control="force")
    ordinary = plastic_solver.solve_force(state, 400.0)
    assert not ordinary.converged
    rescued = plastic_solver.rescue_step(state, "force", 400.0)
    assert rescued.converged and "displacement control" in rescued.message
    assert rescued.record.P == pytest.approx(400.0, rel=1e-6)
    steps, _ = run_load_path(plastic_solver, [212.5, 275.0, 337.5, 400.0], state=state)
    assert rescued.record.alpha == pytest.approx(steps[-1].record.alpha, rel=0.01)
    assert rescued.record.newton_iterations > ordinary.record.newton_iterations

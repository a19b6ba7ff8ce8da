"""The defensive step solve (calib.fe.rescue): its stages give the
ordinary solution itself where both converge, and it takes a real step of a stiff material that
the ordinary solve cannot (E / sigma_Y = 5000), its record charging every factorisation."""
import time

import numpy as np
import pytest

from calib.fe import ContactSolver, ElasticMaterial, VonMisesMaterial, advance
from calib.fe.rescue import force_by_displacement
from meshes.hemisphere import HemisphereMeshSpec, hemisphere_mesh

E, NU, SIGMA_Y = 500e9, 0.3, 100e6  # E / sigma_Y = 5000: P_Y = 0.72 N for R = 0.1 m
# contact elements of 0.1 x the estimated contact radius at 1000 P_Y (4574 dofs)
MESH = HemisphereMeshSpec(radius=0.1, contact_size=1.6126071365214677e-4,
                          refined_radius=1.7738678501736144e-3, refined_depth=5.644124977825136e-4,
                          far_size=0.01, growth=0.2)
# the loading targets [N] of a 1000 P_Y path in 16 steps
TARGETS = (0.3590458536259873, 45.19489682517114, 90.0307477967163, 134.86659876826147)
# Both solves converge the same backward-Euler step to the residual tolerance 1e-8 (relative
# to the force scale), so their approaches agree to about that (measured: 2e-11 to 3e-11).
SAME_STEP = 1e-8


@pytest.fixture(scope="module")
def mesh(mesh_cache):
    return hemisphere_mesh(MESH, cache_dir=mesh_cache)


@pytest.fixture(scope="module")
def plastic(mesh):
    return ContactSolver(mesh, VonMisesMaterial(E, NU, SIGMA_Y), contact_radius_method="gap")


def test_rescue_from_the_committed_state_gives_the_ordinary_solution(mesh):
    solver = ContactSolver(mesh, ElasticMaterial(E, NU))
    state = solver.commit(solver.solve_force(solver.initial_state(), 20.0))
    for control, target, quantity in (("force", 200.0, "alpha"), ("displacement", 3e-6, "P")):
        ordinary = (solver.solve_force if control == "force" else solver.solve_displacement)(state, target)
        rescued = solver.rescue_step(state, control, target)
        assert ordinary.converged and rescued.converged
        assert rescued.message == "converged (rescue: from the committed state)"
        assert getattr(rescued.record, quantity) == pytest.approx(getattr(ordinary.record, quantity),
                                                                  rel=SAME_STEP)
        assert np.array_equal(rescued.state.active, ordinary.state.active)


def test_force_through_displacement_control_gives_the_ordinary_solution(plastic):
    """Stage 2 of the rescue on a plastic step the ordinary solve takes (to 63 P_Y)."""
    state = plastic.commit(plastic.solve_force(plastic.initial_state(), TARGETS[0]))
    ordinary = plastic.solve_force(state, TARGETS[1])
    assert ordinary.converged
    rescued = force_by_displacement(plastic, state, TARGETS[1], ordinary, time.perf_counter())
    assert rescued.converged and "displacement control" in rescued.message
    assert rescued.record.P == pytest.approx(TARGETS[1], rel=SAME_STEP)
    assert rescued.record.alpha == pytest.approx(ordinary.record.alpha, rel=SAME_STEP)
    assert np.array_equal(rescued.state.active, ordinary.state.active)


def test_rescue_takes_a_step_the_ordinary_solve_cannot(plastic):
    """125 P_Y -> 188 P_Y at E / sigma_Y = 5000: Newton stalls at the whole increment, at half and
    at 1/64 of it; the rescue converges (from the committed state it stalls too, displacement
    control with a secant on the approach gets there) to the target force."""
    state = plastic.initial_state()
    for target in TARGETS[:3]:
        state = advance(plastic, state, "force", target, 1 / 64, lambda result, before: None)
    target = TARGETS[3]
    for fraction in (1.0, 0.5, 1 / 64):
        count = plastic.factorization_count
        step = plastic.solve_force(state, state.force + fraction * (target - state.force))
        assert not step.converged and "stalled" in step.message
        assert step.record.factorizations == plastic.factorization_count - count
    count = plastic.factorization_count
    rescued = plastic.rescue_step(state, "force", target)
    assert rescued.converged and "displacement control" in rescued.message
    assert rescued.record.P == pytest.approx(target, rel=1e-8)
    assert rescued.record.alpha > state.alpha
    # a contact solution: no penetration, no tension (beyond the noise of reactions that are
    # known to the Newton tolerance)
    assert rescued.gap.min() >= -plastic.gap_tolerance
    assert rescued.contact_reaction.min() >= -1e-6 * target
    # the record charges every solve tried (discarded Newton runs included)
    assert rescued.record.factorizations == plastic.factorization_count - count
    assert rescued.record.newton_iterations <= len(rescued.residual_history)
    assert rescued.record.active_set_iterations > 1
    # the force step itself: the approach it found, prescribed, gives back the target force
    check = plastic.solve_displacement(state, rescued.record.alpha)
    assert check.converged and check.record.P == pytest.approx(target, rel=1e-8)

"""The exact frictionless contact of one step: the primal active set on the nodal gaps, Newton inside.

For one step of a static (calib.fe.solver) or dynamic (calib.fe.newmark) problem with the unknowns
q and contact candidates of NodeDofs (calib.fe.dofs): each trial active set A prescribes

    q_z,i = -z0_i   (gap g_i = z0_i + q_z,i = 0)        for i in A

and Newton solves the equilibrium r(q) = 0 on the other unknowns (calib.fe.newton.solve_newton).
The set is then updated: active nodes with a tensile reaction are released, open nodes that
penetrate are added (calib.fe.active_set.next_active_set), until neither exists. A set seen before
(cycling) is answered there; a Newton run that fails on a new set is retried from the step's safe
start (continuing from the previous set's solution can diverge when a node that held plastic flow
is released). Optionally the trial sets are solved to a looser tolerance only (enough to tell
tensile reactions and penetrations apart) and the set that settles again to the full one.
No penalty: the active nodes do not penetrate. Reference: Wriggers 2006, Computational Contact
Mechanics, ch. 6. Forces [N], lengths [m].
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

from calib.fe.active_set import next_active_set
from calib.fe.newton import NewtonResult, solve_newton


@dataclass
class ContactSolve:
    """The outcome of one step's active-set loop: whether it settled (``message`` says why not),
    the last Newton run (its q, residual, stress, trial state), the active set, the work done
    (Newton iterations, active sets tried, factorisations, assembly and solve times [s])."""

    converged: bool
    message: str
    newton: Optional[NewtonResult]
    active: np.ndarray
    newton_iterations: int
    active_set_iterations: int
    factorizations: int
    time_assembly: float
    time_solve: float


class _WithTolerance:
    """The solver as calib.fe.newton.solve_newton reads it, with another residual tolerance."""

    def __init__(self, solver, tolerance: float):
        self._solver, self.residual_tolerance = solver, tolerance

    def __getattr__(self, name):
        return getattr(self._solver, name)


def solve_contact(solver, q, safe_start, start, control: str, target: float, active, *, key_prefix,
                  residual_history: list, plate: int | None = None, trial_tolerance: float | None = None,
                  update_set=next_active_set) -> ContactSolve:
    """The active-set loop of one step (module docstring) from ``q`` and the warm-start set ``active``.

    ``solver``: what calib.fe.newton.solve_newton reads, with ``dofs`` (candidate_q, candidate_z0),
    gap_tolerance [m], radius [m], is_linear and max_active_set_iterations; ``safe_start``: the q a
    failed run on a new set restarts from; ``start``, ``control``, ``target``: solve_newton's;
    ``plate``: an unknown prescribed to -target with the active nodes (displacement control);
    ``key_prefix``: with the set, the key of a linear material's cached factorisation;
    ``trial_tolerance``: the looser tolerance of the trial sets (None: every set to the full one);
    ``update_set``: the set update (calib.fe.active_set.next_active_set's signature).
    """
    dofs = solver.dofs
    visited = {active.tobytes()}
    newton_total = factorizations = iterations = 0
    t_assembly = t_solve = 0.0
    message, converged, newton = "", False, None
    final = trial_tolerance is None or solver.residual_tolerance >= trial_tolerance
    while iterations < solver.max_active_set_iterations:
        iterations += 1
        constrained = dofs.candidate_q[active]
        constrained_target = -dofs.candidate_z0[active]
        if plate is not None:
            constrained = np.append(constrained, plate)
            constrained_target = np.append(constrained_target, -target)
        free = np.ones(dofs.n_q, dtype=bool)
        free[constrained] = False
        key = (key_prefix, active.tobytes()) if solver.is_linear else None
        problem = solver if final else _WithTolerance(solver, trial_tolerance)
        runs = [solve_newton(problem, q.copy(), start, control, target, constrained, constrained_target, free, key,
                             residual_history)]
        if not runs[0].ok and iterations > 1:
            runs.append(solve_newton(problem, safe_start.copy(), start, control, target, constrained,
                                     constrained_target, free, key, residual_history))
        for run in runs:  # the work of a discarded run counts too
            newton_total += run.iterations
            factorizations += run.factorizations
            t_assembly += run.time_assembly
            t_solve += run.time_solve
        newton = runs[-1]
        q = newton.q
        if not newton.ok:
            message = newton.message or (f"Newton did not reach the residual tolerance {problem.residual_tolerance:g}"
                                         f" in {solver.max_newton_iterations} iterations (relative residual"
                                         f" {newton.residual_norm:.3g})")
            break
        update = update_set(active, newton.residual[dofs.candidate_q], dofs.candidate_z0 + q[dofs.candidate_q],
                            visited, force_tolerance=10.0 * problem.residual_tolerance * newton.scale,
                            gap_tolerance=solver.gap_tolerance, force_scale=newton.scale,
                            length_scale=solver.radius, force_control=control == "force")
        if update.settled and final:
            converged = True
            break
        if update.settled:
            final = True                  # the same set again, to the full tolerance
            continue
        if update.active is None:
            message = "active set cycles"
            break
        active = update.active
    else:
        message = f"active set did not settle in {solver.max_active_set_iterations} iterations"
    return ContactSolve(converged=converged, message=message, newton=newton, active=active,
                        newton_iterations=newton_total, active_set_iterations=iterations,
                        factorizations=factorizations, time_assembly=t_assembly, time_solve=t_solve)

"""The one active-set loop of frictionless contact: every FE step (press, impact, pair press, pair
impact) solves its contact here, with Newton inside.

For one step of a static (calib.fe.quasi_static) or dynamic (calib.fe.newmark) problem and a
contact constraint (calib.fe.constraint: the rigid flat or a deformable counter-body's mortar gap),
each trial active set A prescribes a zero gap at its nodes,

    g_i(q) = 0   for i in A,

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
    the last Newton run (its residual, stress, trial state), the solver's unknowns q [m] and the
    candidates' reactions [N] of that run, the active set, the work done (Newton iterations, active
    sets tried, factorisations, assembly and solve times [s])."""

    converged: bool
    message: str
    newton: Optional[NewtonResult]
    q: Optional[np.ndarray]
    reaction: Optional[np.ndarray]
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


def solve_contact(solver, constraint, q, safe_start, start, control: str, target: float, active, *,
                  key_prefix, residual_history: list, trial_tolerance: float | None = None) -> ContactSolve:
    """The active-set loop of one step (module docstring) from ``q`` and the warm-start set ``active``.

    ``solver``: what calib.fe.newton.solve_newton reads, with gap_tolerance [m], radius [m],
    is_linear and max_active_set_iterations; ``constraint``: calib.fe.constraint's RigidFlat or
    MortarContact, which turns each set into Newton's system; ``safe_start``: the q a failed run on
    a new set restarts from; ``start``, ``control``, ``target``: solve_newton's (in displacement
    control the plate is prescribed to -target); ``key_prefix``: with the set, the key of a linear
    material's cached factorisation; ``trial_tolerance``: the looser tolerance of the trial sets
    (None: every set to the full one). The set update is calib.fe.active_set.next_active_set.
    """
    visited = {active.tobytes()}
    newton_total = factorizations = iterations = 0
    t_assembly = t_solve = 0.0
    message, converged, newton, reaction = "", False, None, None
    final = trial_tolerance is None or solver.residual_tolerance >= trial_tolerance
    while iterations < solver.max_active_set_iterations:
        iterations += 1
        key = (key_prefix, active.tobytes()) if solver.is_linear else None
        runs = []
        for q_from in ((q,) if iterations == 1 else (q, safe_start)):
            system = constraint.system(solver, active, q_from, control, target)
            problem = system.problem if final else _WithTolerance(system.problem, trial_tolerance)
            runs.append(solve_newton(problem, system.start, start, control, target, system.constrained,
                                     system.target, system.free, key, residual_history))
            if runs[-1].ok:
                break
        for run in runs:  # the work of a discarded run counts too
            newton_total += run.iterations
            factorizations += run.factorizations
            t_assembly += run.time_assembly
            t_solve += run.time_solve
        newton = runs[-1]
        q = system.to_q(newton.q)
        if not newton.ok:
            message = newton.message or (f"Newton did not reach the residual tolerance {problem.residual_tolerance:g}"
                                         f" in {solver.max_newton_iterations} iterations (relative residual"
                                         f" {newton.residual_norm:.3g})")
            break
        reaction = constraint.reactions(solver, newton)
        update = next_active_set(active, reaction, constraint.gaps(q), visited,
                                 force_tolerance=10.0 * problem.residual_tolerance * newton.scale,
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
    return ContactSolve(converged=converged, message=message, newton=newton, q=q, reaction=reaction, active=active,
                        newton_iterations=newton_total, active_set_iterations=iterations,
                        factorizations=factorizations, time_assembly=t_assembly, time_solve=t_solve)

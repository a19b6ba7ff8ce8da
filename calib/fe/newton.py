"""Newton's method for the equilibrium of one active set, with a stall test.

r(q) = T^T f_int(T q) + P e_plate (force control) = 0 on the free q, the constrained ones
prescribed; the consistent tangent of the material's return mapping gives quadratic
convergence near the solution (Simo & Taylor 1985, Comput. Methods Appl. Mech. Eng. 48, 101).
"""
from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Optional

import numpy as np


@dataclass
class NewtonResult:
    """The outcome of Newton on one active set (times [s], forces [N])."""

    ok: bool
    q: np.ndarray
    f_int: np.ndarray
    residual: np.ndarray
    stress: Optional[np.ndarray]
    trial: object
    residual_norm: float
    scale: float
    iterations: int
    factorizations: int
    time_assembly: float
    time_solve: float
    message: str


def solve_newton(solver, q, state, control, target, constrained, constrained_target, free, key,
                 residual_history) -> NewtonResult:
    """Newton on r(q) = 0 for one active set, from ``q`` (updated in place).

    ``constrained`` q entries (active nodes, and the plate in displacement control) are driven
    to ``constrained_target`` by the first increment; ``free`` the others. Each iteration solves
    K_q[free, free] dq = -r_free - K_q[free, constrained] dq_constrained with the consistent
    tangent (``solver.assemble``, ``solver.factor``; ``key`` reuses a factorisation of a linear
    material). Converged when ||r_free||_2 <= tol * max(||r_constrained||_2, base force scale)
    and the constraints are met; stops at the iteration limit, or early when it stalls.
    ``residual_history`` receives the relative residual of every iterate.
    """
    t_assembly = t_solve = 0.0
    iterations = factorizations = 0
    message = ""
    best, stalled = np.inf, 0
    # A physical force scale, never one that grows with the iterate (a diverging iterate
    # must not look converged): besides the constraint reactions, the target force, the
    # force the step starts from (near separation the reactions vanish), and E R |u| for
    # the committed and the prescribed displacements (a lifted sphere has no force at all).
    displacement_scale = max(np.abs(state.displacement).max(initial=0.0),
                             abs(target) if control == "displacement" else 0.0)
    base_scale = max(target if control == "force" else 0.0, abs(state.force),
                     1e-3 * solver.stiffness_scale * displacement_scale, solver.force_floor)
    ok, f_int, residual, stress, trial, residual_norm, scale = False, None, None, None, None, np.inf, base_scale
    for newton in range(solver.max_newton_iterations + 1):
        t0 = time.perf_counter()
        try:
            f_int, tangent, stress, trial = solver.assemble(solver.T @ q, state.material_state)
        except ArithmeticError as exc:
            # a return mapping that found no root at this iterate (calib.fe.flow_curve): the step
            # failed like a diverging Newton, and the stepper retries it smaller
            message, ok = f"material: {exc}", False
            break
        residual = solver.TT @ f_int
        if control == "force":
            residual[solver.plate] += target  # f_ext on the plate unknown is -P
        t_assembly += time.perf_counter() - t0
        dq_constrained = constrained_target - q[constrained]
        scale = max(np.linalg.norm(residual[constrained]), base_scale)
        residual_norm = np.linalg.norm(residual[free]) / scale
        residual_history.append(float(residual_norm))
        ok = residual_norm <= solver.residual_tolerance and not np.any(dq_constrained)
        if ok or newton == solver.max_newton_iterations:
            break
        # Newton with a consistent tangent at least halves the residual every iteration
        # near the solution: four iterations in a row without halving the best residual
        # mean divergence or a limit cycle, not slow progress.
        # An iterate that does not meet the constraints yet (the first of a displacement
        # step, or one with newly active nodes) is no baseline for that test.
        if np.any(dq_constrained):
            pass
        elif residual_norm < 0.5 * best:
            best, stalled = residual_norm, 0
        else:
            stalled += 1
            if stalled >= 4:
                message = f"Newton stalled (relative residual {residual_norm:.3g})"
                break
        t0 = time.perf_counter()
        K_q = tangent()
        t_assembly += time.perf_counter() - t0
        t0 = time.perf_counter()
        try:
            factor, n_new = solver.factor(K_q, free, key)
        except np.linalg.LinAlgError as exc:
            message = f"singular tangent: {exc}"
            break
        factorizations += n_new
        rhs = -residual[free]
        if dq_constrained.any():
            rhs -= K_q[free][:, constrained] @ dq_constrained
        dq_free = factor.solve(rhs)
        t_solve += time.perf_counter() - t0
        if not np.all(np.isfinite(dq_free)):
            message = "non-finite Newton increment"
            break
        q[free] += dq_free
        q[constrained] = constrained_target
        iterations += 1
    return NewtonResult(ok=bool(ok), q=q, f_int=f_int, residual=residual, stress=stress,
                         trial=trial, residual_norm=float(residual_norm), scale=float(scale),
                         iterations=iterations, factorizations=factorizations,
                         time_assembly=t_assembly, time_solve=t_solve, message=message)

"""The rescue solve: a step that failed the ordinary way, solved defensively.

calib.fe.loadpath.advance calls it only once halving the increment has failed down to its
smallest fraction, so every load path that converges the ordinary way is unchanged.
"""
from __future__ import annotations

import time

import numpy as np

from calib.fe.state import ContactState, StepResult, merged_result
from nfdmodel import check_real
from nfdmodel.materials import plane_strain_modulus


def rescue_step(solver, state: ContactState, control: str, target: float) -> StepResult:
    """The step from ``state`` to ``target`` (force [N] or approach [m]) solved defensively,
    for a step that failed the ordinary way (``solve_force`` / ``solve_displacement``).

    Slower, and not bit-identical to the ordinary solve, so calib.fe.loadpath.advance calls it
    only once halving the increment has failed down to its smallest fraction: every load path
    that converges the ordinary way is unchanged. Why ordinary steps fail at deep plastic
    loads (measured at E / sigma_Y = 5000, 60-81 P_Y, where even 1/64 of the increment
    failed): the warm-start active set (the recovered contact radius, which can lie inside
    the outermost contact node, scaled by the learnt growth exponent) drops that node; with
    one ring less the force-controlled body flows (alpha +4.7 % for a +0.16 % force step) and the
    outer nodes penetrate. Two stages (loading and unloading alike):

    1. the same step started from the committed state itself, its displacement and its active
       set (no secant predictor, no predicted set);
    2. force control only, if 1 fails: displacement control on the plate, the approach alpha
       found by a safeguarded secant on P(alpha) (every trial from ``state``, the committed
       state, so the accepted step is still one backward-Euler increment), then a
       force-controlled step started from that solution and its active set, so the result
       is the force step itself, to the same residual tolerance. A force-controlled Newton
       on a perfectly plastic body can run away along the soft plastic mode (alpha grows
       6x-85x once a node is released); a prescribed alpha bounds it.

    The record sums the iterations, factorisations and times of every solve tried.
    """
    if control not in ("force", "displacement"):
        raise ValueError(f"control must be 'force' or 'displacement', got {control!r}")
    if control == "force":
        target = check_real("force", target, unit="N")
        if not target > 0:
            raise ValueError(f"force must be > 0 [N], got {target}")
    else:
        target = check_real("alpha", target, unit="m")
    t_start = time.perf_counter()
    first = solver.solve_step(state, control, target, start=state)
    if first.converged or control == "displacement":
        return merged_result([first], first, t_start, "converged (rescue: from the committed state)"
                       if first.converged else f"rescue from the committed state: {first.message}")
    return force_by_displacement(solver, state, target, first, t_start)

def force_by_displacement(solver, state: ContactState, target: float, failed: StepResult,
                          t_start: float, max_solves: int = 20) -> StepResult:
    """Stage 2 of ``rescue_step``: the force step to ``target`` [N] through displacement
    control (safeguarded secant on alpha, then a force-controlled polish)."""
    a0, P0 = state.alpha, state.force
    direction = float(np.sign(target - P0))
    slope = None  # first guess of d alpha / d P [m/N] > 0: the last step's, or Hertz's 1 / (2 E* a)
    if state.displacement_rate is not None and direction == state.load_direction:
        slope = -float(state.displacement_rate[solver.top_z_dof])
    if not (slope is not None and np.isfinite(slope) and slope > 0):
        E_star = plane_strain_modulus(float(getattr(solver.material, "E", 1.0)),
                                      float(getattr(solver.material, "nu", 0.0)))
        slope = 1.0 / (2.0 * E_star * max(state.contact_radius, solver.candidate_r[1]))
    near = (a0, P0)  # (alpha, P) on the committed side of the target
    far = None       # (alpha, P) beyond the target, once one is found
    last = near      # the latest solution
    tried = [failed]
    best = None
    alpha = a0 + slope * (target - P0)
    for _ in range(max_solves):
        result = solver.solve_step(state, "displacement", alpha)
        tried.append(result)
        if not result.converged:
            alpha = near[0] + 0.5 * (alpha - near[0])  # closer to the committed side
            continue
        P = result.record.P
        if best is None or abs(P - target) < abs(best.record.P - target):
            best = result
        if abs(P - target) <= solver.residual_tolerance * abs(target):
            break
        previous, last = last, (alpha, P)
        if (P - target) * direction < 0:
            near = last
        else:
            far = last
        # secant through the last two solutions (the committed state counts as one)
        secant = (last[0] - previous[0]) / (last[1] - previous[1]) if last[1] != previous[1] else 0.0
        alpha = last[0] + (secant if secant > 0 else slope) * (target - P)
        if far is None:  # not bracketed yet: extrapolate forward, at most 4x the way so far
            reach = 4.0 * abs(near[0] - a0)
            alpha = near[0] + direction * min(max((alpha - near[0]) * direction, 0.0), reach)
            if alpha == near[0]:
                alpha = near[0] + slope * (target - near[1])
        elif not min(near[0], far[0]) < alpha < max(near[0], far[0]):
            alpha = 0.5 * (near[0] + far[0])  # bisection keeps the bracket
    if best is None:
        return merged_result(tried, failed, t_start, f"{failed.message}; under displacement control"
                       f" too: {tried[-1].message}")
    polish = solver.solve_step(state, "force", target, start=best.state)
    tried.append(polish)
    if polish.converged:
        return merged_result(tried, polish, t_start, f"converged (rescue: displacement control,"
                       f" {len(tried) - 2} displacement solves, after {failed.message})")
    return merged_result(tried, polish, t_start, f"{failed.message}; force step from the"
                   f" displacement-controlled solution at P = {best.record.P:.8g}:"
                   f" {polish.message}")

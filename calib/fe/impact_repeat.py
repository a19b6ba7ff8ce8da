"""Repeated impacts of the sphere on the same spot of the rigid flat: the dent and the residual
stresses carried from one impact to the next.

Impact k + 1 starts from impact k's end, with the sphere brought to rest between them: every
vibration the sphere kept after separating (its vibration energy E_vib, calib.fe.impact) is taken
to have died out elastically, so the body is in the static equilibrium of its plastic strain,
frozen, free of load (calib.fe.impact.residual_state's: K u = int B^T D eps_p dV with the pole's
u_z held, sigma = D (eps(u) - eps_p), the kinematics' residual_state). The restart state
(``rest_state``) is that displacement field u_res, moved by a rigid translation c along z so the
lowest contact candidate just touches the flat (min_i g_i = 0: first touch at t = 0), with the
committed material state of impact k (plastic strain, equivalent plastic strain: the residual
stress follows from them and u_res), every point moving at v_in toward the flat, zero
acceleration (u_res is an equilibrium), and the energy sums started so impact_run's identities
stay exact: work_internal = U_res + W_p (the strain energy and plastic work the body holds).

Per impact (``RepeatedImpact``), with the ImpactResult of calib.fe.impact:
  e = v_cm(out) / v_in of this impact [-]; P_max [N]; dent = u_z(pole) - u_cm of the residual
  state after it (cumulative: from the virgin sphere) [m]; alpha_max: the largest approach of the
  centre of mass since this impact's first touch [m]; plastic_work: W_p dissipated in this
  impact [J]; balance_residual = KE_in + U_res,0 - KE_out - dW_p - U_res - E_vib [J] (U_res,0:
  the residual-stress energy it started with).
Units: SI.
"""
from __future__ import annotations

import dataclasses
from typing import Callable

import numpy as np

from calib.fe.impact import DEFAULT_STEPS_PER_CONTACT, _result, impact_run, residual_field
from calib.fe.newmark import ImpactSolver, ImpactState

MAX_REPEAT = 100          # impacts per series


def _residual_field(solver: ImpactSolver, state: ImpactState):
    """(q [m], stress (E, Q, 4) [Pa]) of the free sphere's static equilibrium with ``state``'s plastic
    strain frozen, the pole's u_z held (module docstring); (zeros, zeros) for a sphere that never yielded."""
    field = residual_field(solver, state)
    if field is None:
        return np.zeros(solver.dofs.n_q), np.zeros((solver.n_elements, solver.n_qp, 4))
    return field


def rest_state(solver: ImpactSolver, end: ImpactState, v_in: float) -> ImpactState:
    """The first touch of the next impact at v_in [m/s] after ``end`` (an impact's last state):
    the sphere at rest in its residual state, lowest candidate on the flat, re-launched at v_in
    (module docstring)."""
    q, stress = _residual_field(solver, end)
    q = q - float(solver.constraint.gaps(q).min()) * solver.dofs.translation   # min gap 0: translation is unit u_z
    velocity = -float(v_in) * solver.dofs.translation
    zeros = np.zeros(solver.dofs.n_q)
    elastic = solver.elastic_energy(stress)
    plastic = solver.plastic_work(end.material_state)
    return ImpactState(time=0.0, q=q, velocity=velocity, acceleration=zeros.copy(),
                       material_state=end.material_state, active=np.zeros(solver.candidate_r.size, dtype=bool),
                       internal_force=solver.TT @ solver.kinematics.internal_force(stress),
                       contact_force=zeros.copy(), free_residual=zeros.copy(),
                       kinetic_energy=solver.kinetic_energy(velocity), elastic_energy=elastic, plastic_work=plastic,
                       work_internal=elastic + plastic)


@dataclasses.dataclass(frozen=True)
class RepeatedImpact:
    """One impact of a series (module docstring): its index ``repeat`` (1..N) and figures [SI]."""

    repeat: int
    v_in: float
    e: float
    P_max: float
    contact_time: float
    alpha_max: float
    dent: float
    contact_radius_max: float
    plastic_work: float
    residual_stress_energy: float
    vibration_energy: float
    balance_residual: float
    recontacts: int
    steps: int
    wall_time_s: float

    def record(self) -> dict:
        return dataclasses.asdict(self)


def repeated_impacts(solver: ImpactSolver, v_in: float, repeat: int, *,
                     steps_per_contact: int = DEFAULT_STEPS_PER_CONTACT,
                     progress: Callable[[str], None] | None = None) -> list[RepeatedImpact]:
    """``repeat`` impacts (1 .. MAX_REPEAT) at v_in [m/s] of ``solver``'s sphere on one spot (module
    docstring); run_impact's errors (ImpactNotConverged, ValueError)."""
    if isinstance(repeat, bool) or not isinstance(repeat, (int, np.integer)) or not 1 <= repeat <= MAX_REPEAT:
        raise ValueError(f"repeat out of range: need an integer in [1, {MAX_REPEAT}], got {repeat!r}")
    say = progress or (lambda message: None)
    impacts, start = [], None
    for k in range(1, int(repeat) + 1):
        run = impact_run(solver, v_in, steps_per_contact=steps_per_contact, start=start)
        result = _result(solver, run)                   # the sphere's record (calib.fe.impact)
        initial = run.initial
        held = initial.elastic_energy + initial.plastic_work        # U_res,0 + W_p,0 (zero for the first)
        alpha = result.history["alpha"]
        impacts.append(RepeatedImpact(
            repeat=k, v_in=float(v_in), e=result.e, P_max=result.P_max, contact_time=result.contact_time,
            alpha_max=result.alpha_max - float(alpha[0]), dent=result.dent,
            contact_radius_max=result.contact_radius_max, plastic_work=result.plastic_work - initial.plastic_work,
            residual_stress_energy=result.residual_stress_energy, vibration_energy=result.vibration_energy,
            balance_residual=result.balance_residual + held, recontacts=result.recontacts, steps=result.steps,
            wall_time_s=result.wall_time_s))
        say(f"v_in = {v_in:g} m/s, impact {k} of {repeat}: e = {result.e:.5f}, P_max = {result.P_max:.5g} N")
        if k < repeat:
            start = rest_state(solver, run.state, v_in)
    return impacts

"""The states and records of the contact solver: committed/trial state, step record, step result.

A load step returns a trial ``ContactState`` inside its ``StepResult``; it becomes the state to
continue from only when the caller commits it (``ContactSolver.commit``), so a failed step can
be retried from the unchanged committed state. Units: lengths [m], forces [N], pressures [Pa],
times [s].
"""
from __future__ import annotations

import time
from dataclasses import asdict, dataclass, field, replace
from typing import Optional

import numpy as np


@dataclass(frozen=True)
class ContactState:
    """A (committed or trial) state of the contact problem.

    displacement    full dof vector u [m] (scikit-fem ordering of ``solver.basis``)
    material_state  the material's state at the quadrature points
    active          bool per contact candidate node (``solver.candidate_r`` order): in contact
    alpha           approach [m] (plate moved down by alpha)
    force           plate reaction P [N]
    contact_radius  recovered contact radius [m] (warm start of the next step's active set)
    """

    displacement: np.ndarray
    material_state: object
    active: np.ndarray
    alpha: float = 0.0
    force: float = 0.0
    contact_radius: float = 0.0
    # d ln(contact_radius) / d ln(P) and / d ln(alpha) over the step that produced this state
    # (None before two loaded states exist): the warm start of the next active set
    radius_exponents: Optional[tuple] = None
    # du/dP over the step that produced this state [m/N] (force control only): the secant
    # predictor of the next force step in the same direction
    displacement_rate: Optional[np.ndarray] = field(default=None, repr=False)
    load_direction: int = 0  # sign of the force change over that step


@dataclass(frozen=True)
class StepRecord:
    """One history row (CSV-able). Lengths [m], forces [N], pressures [Pa], times [s]."""

    control: str
    target: float
    alpha: float
    P: float
    contact_force: float
    contact_radius: float
    contact_radius_gap: float
    contact_radius_pressure: float
    contact_radius_node: float
    peak_pressure: float
    n_contact_nodes: int
    newton_iterations: int
    active_set_iterations: int
    factorizations: int
    residual_norm: float
    residual_tolerance: float
    converged: bool
    time_assembly_s: float
    time_solve_s: float
    wall_time_s: float

    def as_dict(self) -> dict:
        return asdict(self)


@dataclass(frozen=True)
class StepResult:
    """What a load step produced. ``state`` is the trial state: commit it explicitly.

    pressure_r, pressure: nodal contact pressure [Pa] at the candidate nodes (sorted by r [m]);
    contact_reaction: nodal contact forces [N]; gap: nodal gaps [m]; stress (E, Q, 4) [Pa]
    (None for linear materials: ask ``solver.stress(state)``).
    """

    state: ContactState
    record: StepRecord
    converged: bool
    message: str
    pressure_r: np.ndarray = field(repr=False)
    pressure: np.ndarray = field(repr=False)
    contact_reaction: np.ndarray = field(repr=False)
    gap: np.ndarray = field(repr=False)
    stress: Optional[np.ndarray] = field(default=None, repr=False)
    residual_history: tuple = ()  # relative residual at every Newton iterate, in order


class StepNotConverged(RuntimeError):
    """A load step did not meet the residual tolerance or its active set did not settle."""


class QuadratureStates:
    """The state methods every contact solver shares (the press, the pair): it needs ``candidate_r``
    (contact candidates, the pole first), ``n_dofs``, ``material`` (initial_state, update),
    ``n_elements``, ``n_qp`` and ``kinematics`` (strain, stress)."""

    def initial_state(self) -> ContactState:
        """Undeformed, unloaded, only the pole touching."""
        active = np.zeros(self.candidate_r.size, dtype=bool)
        active[0] = True  # the pole
        return ContactState(displacement=np.zeros(self.n_dofs),
                            material_state=self.material.initial_state(self.n_elements, self.n_qp),
                            active=active)

    def commit(self, result: StepResult) -> ContactState:
        """The state to continue from after ``result``: refuses an unconverged step."""
        if not result.converged:
            raise StepNotConverged(f"cannot commit an unconverged step: {result.message}")
        return result.state

    def strain(self, displacement) -> np.ndarray:
        """Strain at the quadrature points, (E, Q, 4) [-] (calib.fe.kinematics)."""
        return self.kinematics.strain(displacement)

    def stress(self, state: ContactState) -> np.ndarray:
        """Stress of a state at the quadrature points, (E, Q, 4) [Pa] (pure; calib.fe.kinematics)."""
        return self.kinematics.stress(self.material, state.displacement, state.material_state)


def displacement_rate(before: ContactState, control: str, displacement, force: float) -> dict:
    """du/dP and the load direction over a force-controlled step (for the secant predictor)."""
    change = force - before.force
    if control != "force" or before.force <= 0 or abs(change) < 1e-9 * abs(force):
        return {}
    return {"displacement_rate": (displacement - before.displacement) / change,
            "load_direction": int(np.sign(change))}


def radius_exponents(before: ContactState, alpha: float, force: float, radius: float):
    """(d ln a / d ln P, d ln a / d ln alpha) over one step, clipped to a plausible range;
    None when the step is too small or not in contact at both ends to measure them."""
    values = (before.contact_radius, radius, before.force, force, before.alpha, alpha)
    if min(values) <= 0:
        return None
    d_radius = np.log(radius / before.contact_radius)
    d_force, d_alpha = np.log(force / before.force), np.log(alpha / before.alpha)
    if abs(d_force) < 1e-6 or abs(d_alpha) < 1e-6 or d_radius == 0:
        return None
    return (float(np.clip(d_radius / d_force, 0.1, 1.0)), float(np.clip(d_radius / d_alpha, 0.2, 2.0)))


def merged_result(tried, result: StepResult, t_start: float, message: str) -> StepResult:
    """``result`` with its record charged the cost of every solve in ``tried`` (rescue_step)."""
    record = replace(result.record,
                     newton_iterations=sum(r.record.newton_iterations for r in tried),
                     active_set_iterations=sum(r.record.active_set_iterations for r in tried),
                     factorizations=sum(r.record.factorizations for r in tried),
                     time_assembly_s=sum(r.record.time_assembly_s for r in tried),
                     time_solve_s=sum(r.record.time_solve_s for r in tried),
                     wall_time_s=time.perf_counter() - t_start)
    history = tuple(h for r in tried for h in r.residual_history)
    return replace(result, record=record, message=message, residual_history=history)

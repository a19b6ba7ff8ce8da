"""The quasi-static stepper: one load step of a contact problem under force or displacement control.

Equilibrium r(q) = T^T f_int(T q) + P e_plate = 0 (force control: the plate unknown carries P [N];
displacement control: the plate prescribed to -alpha [m]) with the contact constraint of the solver
(calib.fe.constraint: the rigid flat, or a deformable counter-body's mortar gap), solved by the one
active-set loop (calib.fe.contact_loop) with Newton inside. A step is one backward-Euler increment
of the material from the committed state; its trial state becomes the state to continue from only
when the caller commits it (``solver.commit(result)``), so a failed step can be retried from the
unchanged committed state. A step never returns silently unconverged: ``StepResult.converged`` is
False and ``commit`` refuses it. ``rescue_step`` is the slower, defensive solve of a step that
failed (calib.fe.rescue).

Warm starts: the active set from the previous contact radius scaled by a power of the load
(calib.fe.active_set.predict_active_set); under force control in the same load direction, the
displacement continued along the last step's du/dP (a secant predictor). In displacement control
the plate is NOT moved before Newton: its jump to -alpha enters the first Newton solve as a
constraint increment (an elastic predictor spread over the body); moving it alone would strain only
the top layer, which a plastic material reads as flow, and Newton can then stall (seen at
separation, E / sigma_Y = 100).

Post-processing per step: the contact reactions lambda_i (consistent nodal forces), the pressure
recovered from them (per undeformed surface area), the contact radius with sub-element accuracy
(recorded on the deformed surface under finite strain, r = R_i + u_r,i; on the undeformed one under
small strain; the state keeps the undeformed one, the warm start of the next active set) and the peak
pressure (calib.fe.recovery). References: Wriggers 2006, Computational Contact Mechanics, ch. 6; Simo &
Hughes 1998, Computational Inelasticity, ch. 3 (the step as a backward-Euler increment).
"""
from __future__ import annotations

import time

import numpy as np

from calib.fe.active_set import predict_active_set
from calib.fe.contact_loop import solve_contact
from calib.fe.recovery import contact_radius_from_gap, contact_radius_from_pressure, lumped_contact_pressure
from calib.fe.rescue import rescue_step
from calib.fe.state import (ContactState, QuadratureStates, StepRecord, StepResult, displacement_rate,
                             radius_exponents)
from nfdmodel import check_real

CONTROLS = ("force", "displacement")


class QuasiStaticSolver(QuadratureStates):
    """Load steps of a contact configuration (the sphere on the rigid flat, calib.fe.solver; on a
    deformable counter-body, calib.fe.two_body). A configuration provides: ``constraint``
    (calib.fe.constraint), ``kinematics``, ``_linear_tangent()`` (K_el in q, assembled once) and
    ``_K_full`` (K_el on every dof), ``factorizations`` (calib.fe.linsolve.FactorCache), ``factor`` (calib.fe.newton's interface), ``plate``,
    ``kept`` and ``top_z_dof`` (q from u), ``displacement(q)`` (u from q), ``full_stress(u, stress)``,
    the candidates' ``candidate_r``, the options (residual_tolerance, iteration limits,
    contact_radius_method) and the scales (radius, gap_tolerance, stiffness_scale, force_floor)."""

    def solve_displacement(self, state: ContactState, alpha: float) -> StepResult:
        """Equilibrium at approach ``alpha`` [m] (plate displacement -alpha), from ``state``."""
        return self.solve_step(state, "displacement", check_real("alpha", alpha, unit="m"))

    def solve_force(self, state: ContactState, force: float) -> StepResult:
        """Equilibrium at plate force ``force`` = P [N] > 0 (the plate is an unknown)."""
        force = check_real("force", force, unit="N")
        if not force > 0:
            raise ValueError(f"force must be > 0 [N] (P = 0 leaves the approach undetermined;"
                             f" use solve_displacement), got {force}")
        return self.solve_step(state, "force", force)

    def predict_active_set(self, state: ContactState, control: str, target: float):
        """Warm start of the step's active set (calib.fe.active_set.predict_active_set)."""
        return predict_active_set(state, control, target, self.candidate_r, self.radius, self.material)

    def rescue_step(self, state: ContactState, control: str, target: float) -> StepResult:
        """The step solved defensively after the ordinary solve failed (calib.fe.rescue)."""
        return rescue_step(self, state, control, target)

    def q_of(self, displacement) -> np.ndarray:
        """The unknowns q of a full dof vector u [m] (the plate's from one top-face u_z)."""
        q = np.empty(self.n_q)
        q[:self.plate] = displacement[self.kept]
        q[self.plate] = displacement[self.top_z_dof]
        return q

    def displacement(self, q) -> np.ndarray:
        """The full dof vector u = T q [m]."""
        return self.T @ q

    def full_stress(self, displacement, stress):
        """The stress of every element (E, Q, 4) [Pa] from Newton's (a configuration that evaluates
        part of the body in Newton fills in the rest)."""
        return stress

    def assemble(self, displacement, committed):
        """(f_int [N] on every dof, tangent() -> K_q [N/m], stress, trial state) at ``displacement``
        (calib.fe.newton's interface): the elastic part K_el u plus the flowed elements' correction
        (calib.fe.kinematics); ``tangent()`` assembles K_q on demand (the converged iterate of a step
        needs only the residual)."""
        K_q = self._linear_tangent()
        f_int = self._K_full @ displacement
        if self.is_linear:
            return f_int, lambda: K_q, None, committed
        response = self.kinematics.correction(self.material, displacement, committed)
        if response.force is None:
            return f_int, lambda: K_q, response.stress, response.trial
        return (f_int + response.force(),
                lambda: self.tangent_matrix(self.kinematics.elastic_data + response.tangent_data()),
                response.stress, response.trial)

    @property
    def factorization_count(self) -> int:
        """Factorisations computed by this solver (its FactorCache)."""
        return self.factorizations.count

    def tangent_matrix(self, data):
        """K_q [N/m] from its data on the element pattern."""
        return self.elements.matrix(data)

    @staticmethod
    def _contact_radii(r, gap, pressure, active) -> dict:
        """The contact radius [m] by each method of calib.fe.recovery on the candidates' radii ``r``."""
        return {"gap": contact_radius_from_gap(r, gap, active),
                "pressure": contact_radius_from_pressure(r, pressure, active),
                "node": float(r[active].max()) if active.any() else 0.0}

    def contact_surface_r(self, displacement) -> np.ndarray:
        """r [m] of the contact candidates the contact radius is measured on: the deformed surface,
        R_i + u_r,i, under a kinematics that measures on it (``deformed_surface``: finite strain),
        the undeformed one (small strain, u_r << a)."""
        if not getattr(self.kinematics, "deformed_surface", False):
            return self.candidate_r
        return self.candidate_r + displacement[self.r_dof[self.candidate_nodes]]

    def contact_pressure(self, reaction, active):
        """Nodal contact pressure [Pa] from the nodal reactions [N] (calib.fe.recovery)."""
        return lumped_contact_pressure(reaction, active, self.candidate_weight, self.candidate_r)

    def solve_step(self, state: ContactState, control: str, target: float,
                   start: ContactState | None = None) -> StepResult:
        """One load step from ``state`` to ``target`` (force [N] or approach [m] by ``control``),
        unchecked (``solve_force`` / ``solve_displacement`` check the target): the one active-set
        loop, Newton inside. ``start``: a state whose displacement and active set start the
        iteration instead of the predictors (the rescue solve)."""
        t_start = time.perf_counter()
        q = self.q_of(state.displacement)
        q_start = q.copy()
        if start is not None:
            q = self.q_of(start.displacement)
        elif (control == "force" and state.displacement_rate is not None
                and np.sign(target - state.force) == state.load_direction):
            # secant predictor: continue along the last step's du/dP (same load direction only:
            # at a turning point the unloading is stiffer than the plastic loading was)
            q = self.q_of(state.displacement + state.displacement_rate * (target - state.force))
        active = self.predict_active_set(state, control, target) if start is None else start.active.copy()
        history: list[float] = []
        loop = solve_contact(self, self.constraint, q, q_start, state, control, target, active,
                             key_prefix=control, residual_history=history)
        active, newton = loop.active, loop.newton
        work = (loop.newton_iterations, loop.active_set_iterations, loop.factorizations, newton.residual_norm)
        if not loop.converged:
            record = self._record(control, target, state.alpha, state.force, 0.0, (0.0,) * 4, 0.0,
                                  int(active.sum()), *work, False, loop.time_assembly, loop.time_solve,
                                  time.perf_counter() - t_start)
            empty = np.zeros(0)
            return StepResult(state=state, record=record, converged=False, message=loop.message, pressure_r=empty,
                              pressure=empty, contact_reaction=empty, gap=empty, residual_history=tuple(history))
        q = loop.q
        u = self.displacement(q)
        reaction = np.where(active, loop.reaction, 0.0)
        gap = self.constraint.gaps(q)
        alpha, P = -q[self.plate], -(self.TT @ newton.f_int)[self.plate]
        pressure = self.contact_pressure(reaction, active)
        radii = self._contact_radii(self.candidate_r, gap, pressure, active)
        # the warm start of the next step's active set is in the candidates' reference r
        warm_start = radii[self.contact_radius_method]
        if getattr(self.kinematics, "deformed_surface", False):
            radii = self._contact_radii(self.contact_surface_r(u), gap, pressure, active)
        chosen = radii[self.contact_radius_method]
        new_state = ContactState(displacement=u, material_state=newton.trial, active=active, alpha=float(alpha),
                                 force=float(P), contact_radius=warm_start,
                                 radius_exponents=radius_exponents(state, alpha, P, warm_start),
                                 **displacement_rate(state, control, u, P))
        record = self._record(control, target, alpha, P, float(reaction.sum()),
                              (chosen, radii["gap"], radii["pressure"], radii["node"]), float(pressure.max()),
                              int(active.sum()), *work, True, loop.time_assembly, loop.time_solve,
                              time.perf_counter() - t_start)
        return StepResult(state=new_state, record=record, converged=True, message="converged",
                          pressure_r=self.candidate_r.copy(), pressure=pressure, contact_reaction=reaction, gap=gap,
                          stress=self.full_stress(u, newton.stress), residual_history=tuple(history))

    def _record(self, control, target, alpha, P, contact_force, radii, peak_pressure, n_contact, newton,
                active_iterations, factorizations, residual_norm, converged, t_assembly, t_solve, wall):
        return StepRecord(control=control, target=float(target), alpha=float(alpha), P=float(P),
                          contact_force=contact_force, contact_radius=radii[0], contact_radius_gap=radii[1],
                          contact_radius_pressure=radii[2], contact_radius_node=radii[3],
                          peak_pressure=peak_pressure, n_contact_nodes=n_contact, newton_iterations=newton,
                          active_set_iterations=active_iterations, factorizations=factorizations,
                          residual_norm=float(residual_norm), residual_tolerance=self.residual_tolerance,
                          converged=converged, time_assembly_s=t_assembly, time_solve_s=t_solve, wall_time_s=wall)

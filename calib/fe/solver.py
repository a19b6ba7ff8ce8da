"""Axisymmetric FE of a sphere pressed on a rigid frictionless flat: Newton + exact contact.

Problem (Vu-Quoc & Zhang 1999, section 2). The r-z section of the hemisphere
(meshes.hemisphere) with quadratic isoparametric triangles; equilibrium in weak form

    r(u) = f_int(u) - f_ext = 0,   f_int,i = int_A sigma(eps(u)) . eps(phi_i) 2 pi r dA   [N]

(calib.fe.forms; calib.fe.axisym for eps and the 2 pi r weight), with
  * axis r = 0: u_r = 0;
  * top face z = R: a rigid plate, all its u_z tied to ONE plate unknown (u = T q, T sparse),
    u_r free. The plate displacement is -alpha (alpha = approach [m]); its reaction
    P = -(T^T f_int)_plate [N] is the contact force (compressive > 0) (calib.fe.dofs);
  * the curved surface against the rigid flat z = 0, frictionless and unilateral:
    gap g_i = z0_i + u_z,i >= 0, reaction lambda_i >= 0, g_i lambda_i = 0 at every surface node.
    Solved exactly by an active set on the nodal gaps (active nodes: u_z = -z0, i.e. g = 0),
    no penalty, so there is no penetration at the nodes.

Algorithm per load step (displacement control: alpha given; force control: P given, the plate
unknown carries the load):
  outer loop over active sets, warm-started from the previous step's set:
    Newton on r(u) = 0 with the active nodes (and, in displacement control, the plate) as
    Dirichlet constraints; stress and tangent from ``material.update`` at the quadrature points.
    Converged when ||r_free||_2 <= residual_tolerance * max(||reactions||_2, P, floor).
    Then: release active nodes with a tensile reaction, add open nodes that penetrate; stop when
    neither exists. A set seen before (cycling) is answered by changing only the single worst
    node; if that repeats too the step is reported unconverged (calib.fe.active_set,
    calib.fe.newton).
A step never returns silently unconverged: ``StepResult.converged`` is False (and
``ContactSolver.commit`` refuses it), and ``run_load_path`` raises ``StepNotConverged``.
``ContactSolver.rescue_step`` is a slower, defensive solve of a step that failed (from the
committed state without warm start, then, for a force, displacement control with a secant on
the approach; calib.fe.rescue); calib.fe.loadpath.advance uses it only where halving the
increment has failed.

Materials follow ``calib.fe.material.Material``: ``update(strain, committed)`` is pure;
the trial state is kept in ``StepResult.state`` and becomes the committed state only when the
caller commits it (``state = solver.commit(result)``), so a failed step can be retried from the
unchanged committed state. For ``material.is_linear`` the tangent is assembled once and each
factorisation is reused for as long as the active set (and control mode) does not change.

Post-processing per step: contact reactions lambda_i (consistent nodal forces), the contact
pressure recovered from them, the contact radius with sub-element accuracy and the peak
pressure (calib.fe.recovery).
References: Johnson 1985, Contact Mechanics, ch. 4 (Hertz); Vu-Quoc & Zhang 1999;
Wriggers 2006, Computational Contact Mechanics, ch. 6 (active set strategy).
"""
from __future__ import annotations

import time
from collections import OrderedDict

import numpy as np
from skfem import Basis, ElementTriP2, ElementVector, asm

from calib.fe.active_set import next_active_set, predict_active_set
from calib.fe.axisym import quadrature_radius, to_form_layout
from calib.fe.contact_loop import solve_contact
from calib.fe.dofs import contact_dofs
from calib.fe.element_arrays import ElementArrays
from calib.fe.forms import tangent_stiffness
from calib.fe.linsolve import METHODS as LINEAR_SOLVERS
from calib.fe.linsolve import factorize
from calib.fe.material import Material
from calib.fe.recovery import (CONTACT_RADIUS_METHODS, contact_radius_from_gap, contact_radius_from_pressure,
                               lumped_contact_pressure)
from calib.fe.rescue import rescue_step
from calib.fe.state import (ContactState, QuadratureStates, StepNotConverged, StepRecord, StepResult,
                             displacement_rate, radius_exponents)
from nfdmodel import check_real


class ContactSolver(QuadratureStates):
    """Sphere (hemisphere mesh) on a rigid frictionless flat, any ``calib.fe.material.Material``.

    Parameters
    ----------
    mesh : meshes.hemisphere.HemisphereMesh
    material : a ``calib.fe.material.Material``
    residual_tolerance : relative tolerance on ||r_free||_2 (see module docstring)
    max_newton_iterations, max_active_set_iterations : iteration limits per step
    linear_solver : calib.fe.linsolve method name (None: its default)
    contact_radius_method : "pressure" (default), "gap" or "node" (see the recovery functions;
        measured against Hertz in results/hertz/mesh_ladder.csv)
    quadrature_order : scikit-fem intorder (4: 6-point rule, exact for the P2 stiffness terms)
    """

    def __init__(self, mesh, material: Material, *, residual_tolerance: float = 1e-8,
                 max_newton_iterations: int = 30, max_active_set_iterations: int = 50,
                 linear_solver: str | None = None, contact_radius_method: str = "pressure",
                 quadrature_order: int = 4):
        if not (0 < residual_tolerance < 1):
            raise ValueError(f"residual_tolerance must be in (0, 1), got {residual_tolerance}")
        if contact_radius_method not in CONTACT_RADIUS_METHODS:
            raise ValueError(f"contact_radius_method must be one of {CONTACT_RADIUS_METHODS},"
                             f" got {contact_radius_method!r}")
        for name, value in (("max_newton_iterations", max_newton_iterations),
                            ("max_active_set_iterations", max_active_set_iterations)):
            if not (isinstance(value, int) and value >= 1):
                raise ValueError(f"{name} must be an integer >= 1, got {value!r}")
        # checked here, not at the first solve: a typo must not cost a mesh load and a first step
        if linear_solver is not None and linear_solver not in LINEAR_SOLVERS:
            raise ValueError(f"linear_solver must be None or one of {LINEAR_SOLVERS}, got {linear_solver!r}")
        if not (isinstance(quadrature_order, int) and not isinstance(quadrature_order, bool)
                and 2 <= quadrature_order <= 10):
            raise ValueError(f"quadrature_order must be an integer in [2, 10], got {quadrature_order!r}")
        self.hemisphere = mesh
        self.material = material
        self.residual_tolerance = float(residual_tolerance)
        self.max_newton_iterations = max_newton_iterations
        self.max_active_set_iterations = max_active_set_iterations
        self.linear_solver = linear_solver
        self.contact_radius_method = contact_radius_method
        self.is_linear = bool(getattr(material, "is_linear", False))

        self.radius = float(mesh.spec.radius if mesh.spec is not None else mesh.radius)
        self.basis = Basis(mesh.mesh, ElementVector(ElementTriP2()), intorder=quadrature_order)
        self.quadrature_order = quadrature_order
        self.r_qp = quadrature_radius(self.basis)
        self.n_elements, self.n_qp = self.r_qp.shape
        self.n_dofs = self.basis.N

        dofs = contact_dofs(mesh, self.basis, quadrature_order)
        self.dofs = dofs
        # the names the steps use most, at hand
        self.node_r, self.node_z, self.r_dof, self.z_dof = dofs.node_r, dofs.node_z, dofs.r_dof, dofs.z_dof
        self.T, self.TT, self.plate, self.n_q = dofs.T, dofs.TT, dofs.plate, dofs.n_q
        self.top_z_dof = dofs.top_z_dof
        self.elements = ElementArrays(self.basis, self.T)   # B, weights, the fixed K_q pattern
        self.candidate_nodes, self.candidate_r = dofs.candidate_nodes, dofs.candidate_r
        self.candidate_z0, self.candidate_q = dofs.candidate_z0, dofs.candidate_q
        self.candidate_weight = dofs.candidate_weight

        self.gap_tolerance = 1e-12 * self.radius  # [m]: round-off, far below any gap of interest
        self.stiffness_scale = float(getattr(material, "E", 1.0)) * self.radius  # [N/m]
        # [N]: a force far below any of interest (E R^2 is the body's natural force unit)
        self.force_floor = 1e-14 * self.stiffness_scale * self.radius
        self._K_q = None  # the elastic tangent in q-space (on self.elements' pattern)
        self._factor_cache: OrderedDict = OrderedDict()
        self._last_free, self._last_factor = None, None  # nonlinear: reuse the symbolic analysis
        self.factorization_count = 0

    # ----------------------------------------------------------------- assembly
    def assemble(self, displacement, committed):
        """(f_int [N], tangent, stress, trial state) at ``displacement``; ``tangent()`` assembles
        K_q on demand (the converged iterate of a step needs only the residual)."""
        if self.is_linear:
            K_q = self._linear_tangent()
            return self._K_full @ displacement, lambda: K_q, None, committed
        # f_int = K_el u + int B^T (sigma - D eps),  K = K_el + int B^T (C - D) B: both
        # corrections vanish wherever the material is still elastic (no plastic strain), so
        # only the elements that have flowed are assembled (the plastic zone is small).
        strain = self.strain(displacement)
        stress, tangent, trial = self.material.update(strain, committed)
        K_q = self._linear_tangent()
        elastic = self._elastic_D
        stress_correction = stress - strain @ elastic
        tangent_correction = tangent - elastic
        f_int = self._K_full @ displacement
        inelastic = (np.abs(stress_correction).max(axis=(1, 2)) > 1e-13 * self._stress_scale(stress)) | \
                    (np.abs(tangent_correction).max(axis=(1, 2, 3)) > 1e-13 * np.abs(elastic).max())
        if not inelastic.any():
            return f_int, lambda: K_q, stress, trial
        elements = np.flatnonzero(inelastic)
        f_int = f_int + self.elements.internal_force(stress_correction[elements], elements)

        def tangent():
            data = K_q.data + self.elements.stiffness_data(tangent_correction[elements], elements)
            return self.elements.matrix(data)

        return f_int, tangent, stress, trial

    @staticmethod
    def _stress_scale(stress):
        return max(float(np.abs(stress).max()), 1e-300)

    def elastic_stiffness(self):
        """Full stiffness matrix [N/m] of a linear material (scikit-fem dof ordering)."""
        if not self.is_linear:
            raise ValueError("elastic_stiffness needs a material with is_linear = True")
        self._linear_tangent()
        return self._K_full

    def _linear_tangent(self):
        if self._K_q is None:
            _, tangent, _ = self.material.update(np.zeros((self.n_elements, self.n_qp, 4)),
                                                 self.material.initial_state(self.n_elements,
                                                                             self.n_qp))
            self._elastic_D = np.array(tangent[0, 0])  # (4, 4): homogeneous material
            self._K_full = asm(tangent_stiffness, self.basis,
                               tangent=to_form_layout(tangent)).tocsr()
            self._K_q = self.elements.matrix(self.elements.stiffness_data(tangent, slice(None)))
        return self._K_q

    def factor(self, K_q, free, key):
        """Factorisation of K_q[free, free]; reused for linear materials while ``key`` repeats."""
        if key is not None and key in self._factor_cache:
            self._factor_cache.move_to_end(key)
            return self._factor_cache[key], 0
        matrix = self.elements.restricted(K_q.data, free)   # K_q[free][:, free]
        free_bytes = free.tobytes()
        if key is None and self._last_free == free_bytes and self._last_factor.update(matrix):
            # same constraints, same pattern (Newton iterations of one active set): numeric
            # refactorization only (bit-identical to a fresh one, about 40 % of its cost)
            self.factorization_count += 1
            return self._last_factor, 1
        factor = factorize(matrix, self.linear_solver)
        if key is None:
            self._last_free, self._last_factor = free_bytes, factor
        self.factorization_count += 1
        if key is not None:
            self._factor_cache[key] = factor
            while len(self._factor_cache) > 4:
                self._factor_cache.popitem(last=False)
        return factor, 1

    # ----------------------------------------------------------------- steps
    def solve_displacement(self, state: ContactState, alpha: float) -> StepResult:
        """Equilibrium at approach ``alpha`` [m] (plate displacement -alpha), from ``state``."""
        alpha = check_real("alpha", alpha, unit="m")
        return self.solve_step(state, "displacement", alpha)

    def solve_force(self, state: ContactState, force: float) -> StepResult:
        """Equilibrium at plate force ``force`` = P [N] > 0 (the plate is an unknown)."""
        force = check_real("force", force, unit="N")
        if not force > 0:
            raise ValueError(f"force must be > 0 [N] (P = 0 leaves the approach undetermined;"
                             f" use solve_displacement), got {force}")
        return self.solve_step(state, "force", force)

    def predict_active_set(self, state: ContactState, control: str, target: float):
        """Warm start of the step's active set (calib.fe.active_set.predict_active_set)."""
        return predict_active_set(state, control, target, self.candidate_r, self.radius,
                                  self.material)

    def rescue_step(self, state: ContactState, control: str, target: float) -> StepResult:
        """The step solved defensively after the ordinary solve failed (calib.fe.rescue)."""
        return rescue_step(self, state, control, target)

    def solve_step(self, state: ContactState, control: str, target: float,
                   start: ContactState | None = None) -> StepResult:
        """One load step from ``state`` to ``target`` (force [N] or approach [m] by ``control``),
        unchecked (``solve_force`` / ``solve_displacement`` check the target): the outer loop over
        active sets, Newton inside. ``start``: a state whose displacement and active set start the
        iteration instead of the predictors (the rescue solve)."""
        t_start = time.perf_counter()
        q = np.empty(self.n_q)
        q[:self.plate] = state.displacement[self.dofs.kept]
        q[self.plate] = state.displacement[self.top_z_dof]
        # In displacement control the plate is NOT moved here: its jump to -target enters the
        # first Newton solve as a constraint increment (an elastic predictor spread over the
        # body). Moving it alone would strain only the top layer, which a plastic material
        # reads as flow, and Newton can then stall (seen at separation, E / sigma_Y = 100).
        q_start = q.copy()
        if start is not None:
            q[:self.plate] = start.displacement[self.dofs.kept]
            q[self.plate] = start.displacement[self.top_z_dof]
        elif (control == "force" and state.displacement_rate is not None
                and np.sign(target - state.force) == state.load_direction):
            # secant predictor: continue along the last step's du/dP (same load direction only:
            # at a turning point the unloading is stiffer than the plastic loading was)
            u_predicted = state.displacement + state.displacement_rate * (target - state.force)
            q[:self.plate] = u_predicted[self.dofs.kept]
            q[self.plate] = u_predicted[self.top_z_dof]
        active = self.predict_active_set(state, control, target) if start is None else start.active.copy()
        residual_history: list[float] = []
        loop = solve_contact(self, q, q_start, state, control, target, active, key_prefix=control,
                             residual_history=residual_history,
                             plate=self.plate if control == "displacement" else None,
                             update_set=next_active_set)
        newton, active, converged, message = loop.newton, loop.active, loop.converged, loop.message
        newton_total, factorizations = loop.newton_iterations, loop.factorizations
        active_set_iterations, t_assembly, t_solve = loop.active_set_iterations, loop.time_assembly, loop.time_solve
        q, f_int, residual, stress = newton.q, newton.f_int, newton.residual, newton.stress
        trial, residual_norm = newton.trial, newton.residual_norm

        record_time = time.perf_counter() - t_start
        if not converged:
            record = self._record(control, target, state.alpha, state.force, 0.0,
                                  (0.0, 0.0, 0.0, 0.0), 0.0, int(active.sum()), newton_total,
                                  active_set_iterations, factorizations, residual_norm, False,
                                  t_assembly, t_solve, record_time)
            empty = np.zeros(0)
            return StepResult(state=state, record=record, converged=False, message=message,
                              pressure_r=empty, pressure=empty, contact_reaction=empty, gap=empty,
                              residual_history=tuple(residual_history))

        u = self.T @ q
        reaction = np.where(active, residual[self.candidate_q], 0.0)
        gap = self.candidate_z0 + q[self.candidate_q]
        alpha = -q[self.plate]
        P = -(self.TT @ f_int)[self.plate]
        pressure = self.contact_pressure(reaction, active)
        radii = {"gap": contact_radius_from_gap(self.candidate_r, gap, active),
                 "pressure": contact_radius_from_pressure(self.candidate_r, pressure, active),
                 "node": float(self.candidate_r[active].max()) if active.any() else 0.0}
        chosen = radii[self.contact_radius_method]
        new_state = ContactState(displacement=u, material_state=trial, active=active,
                                 alpha=float(alpha), force=float(P), contact_radius=chosen,
                                 radius_exponents=radius_exponents(state, alpha, P, chosen),
                                 **displacement_rate(state, control, u, P))
        record = self._record(control, target, alpha, P, float(reaction.sum()),
                              (chosen, radii["gap"], radii["pressure"], radii["node"]),
                              float(pressure.max()), int(active.sum()),
                              newton_total, active_set_iterations, factorizations,
                              residual_norm, True, t_assembly, t_solve,
                              time.perf_counter() - t_start)
        return StepResult(state=new_state, record=record, converged=True, message="converged",
                          pressure_r=self.candidate_r.copy(), pressure=pressure,
                          contact_reaction=reaction, gap=gap, stress=stress,
                          residual_history=tuple(residual_history))

    def contact_pressure(self, reaction, active):
        """Nodal contact pressure [Pa] from the nodal reactions [N] (calib.fe.recovery)."""
        return lumped_contact_pressure(reaction, active, self.candidate_weight, self.candidate_r)

    def _record(self, control, target, alpha, P, contact_force, radii, peak_pressure,
                n_contact, newton, active_iterations, factorizations, residual_norm, converged,
                t_assembly, t_solve, wall):
        return StepRecord(control=control, target=float(target), alpha=float(alpha), P=float(P),
                          contact_force=contact_force, contact_radius=radii[0],
                          contact_radius_gap=radii[1], contact_radius_pressure=radii[2],
                          contact_radius_node=radii[3], peak_pressure=peak_pressure,
                          n_contact_nodes=n_contact, newton_iterations=newton,
                          active_set_iterations=active_iterations,
                          factorizations=factorizations, residual_norm=float(residual_norm),
                          residual_tolerance=self.residual_tolerance, converged=converged,
                          time_assembly_s=t_assembly, time_solve_s=t_solve, wall_time_s=wall)

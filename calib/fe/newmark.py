"""One time step of a sphere's impact on a rigid frictionless flat: Newmark, Newton, exact contact.

Semi-discrete equations (q: the unknowns of calib.fe.sphere_dofs, M its mass with a massless
contact boundary, f_int the internal force of calib.fe.forms, lambda >= 0 the contact reactions
on the active candidates' u_z):

    M a + f_int(q) = f_c,    f_c = sum over active nodes of lambda_i e_z,i              [N]
    gap g_i = z0_i + q_z,i >= 0,  lambda_i >= 0,  g_i lambda_i = 0  at every candidate node

Time integration: Newmark's average acceleration (trapezoidal rule, beta = 1/4, gamma = 1/2;
Newmark 1959, J. Eng. Mech. Div. ASCE 85, 67; Hughes 2000, The Finite Element Method, ch. 9):

    q_n+1 = q_n + dt v_n + dt^2/4 (a_n + a_n+1)      v_n+1 = v_n + dt/2 (a_n + a_n+1)

solved for q_n+1 with a_n+1 = (4/dt^2)(q_n+1 - q_n - dt v_n) - a_n, so each step is the static
contact problem of calib.fe.solver with the effective tangent K_t + (4/dt^2) M: Newton with the
material's consistent tangent (calib.fe.newton.solve_newton) inside the primal active set on the
nodal gaps at t_n+1 (calib.fe.active_set.next_active_set), no penalty.

Why this integrator:
  * implicit and unconditionally stable: the step follows the contact time (about 1e2 steps per
    contact), not the wave transit of the smallest element (an explicit step on the reference
    mesh is about 3 ns, 3e5 steps per millisecond contact);
  * no numerical dissipation, second order on smooth motion: the vibration energy the sphere keeps
    after it separates, which the impact study measures, is the physics', not removed by the
    integrator as a dissipative scheme (generalized-alpha, HHT) removes the high modes' energy
    (the impact converges at about first order in dt: each node's contact starts and ends inside
    a step; calib.studies.impact_convergence measures it);
  * its discrete energy identity is exact: with dq = q_n+1 - q_n,
        KE_n+1 - KE_n = dq . (M a_n + M a_n+1) / 2      (KE = v . M v / 2)
    so  dKE + dq . avg(f_int) - dq . avg(f_c) = dq . avg(r_free),  r_free the Newton residual:
    the run's energy balance closes to the solver tolerance (ImpactState keeps the three sums);
  * the spurious high modes of P2 elements that trapezoidal contact excites come from the
    velocity jump of a node stopped by the flat within a step; the massless contact boundary
    (calib.fe.sphere_dofs) removes it, so no dissipation is needed to damp them.
For the massless dofs, v and a are not part of the dynamics (their mass is zero); they carry the
backward difference dq/dt and zero, which only serve the next step's predictor.

Units: lengths [m], time [s], forces [N], energies [J].
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
from skfem import Basis, ElementTriP2, ElementVector

from calib.fe.axisym import quadrature_radius
from calib.fe.constraint import RigidFlat
from calib.fe.contact_loop import solve_contact
from calib.fe.kinematics import DEFAULT_KINEMATICS, build_kinematics, elastic_tangent
from calib.fe.linsolve import FactorCache
from calib.fe.material import Material
from calib.fe.recovery import contact_radius_from_pressure, lumped_contact_pressure
from calib.fe.sphere_dofs import sphere_dofs
from nfdmodel import ContactPair
from nfdmodel.materials import plane_strain_modulus

ACTIVE_SET_TOLERANCE = 1e-4      # relative residual to which trial active sets are solved


@dataclass(frozen=True)
class ImpactState:
    """A committed state of the impact at ``time`` [s].

    q, velocity, acceleration: the unknowns [m], [m/s], [m/s^2]; material_state at the quadrature
    points; active: bool per contact candidate; internal_force = T^T f_int [N]; contact_force: the
    reactions lambda in q [N]; free_residual: Newton's residual on the other unknowns [N];
    force: P = sum lambda [N]; contact_radius [m] (calib.fe.recovery); contact_edge: r of the
    outermost active node [m], and its rate over the last step [m/s] (None before two states in
    contact); displacement_rate: (q_n - q_n-1) / dt over the last step [m/s]; kinetic_energy, elastic_energy [J] (the
    strain energy of the elastic strain, 1/2 int sigma . D^-1 sigma dV); plastic_work [J]
    (the material's dissipated_work: sigma_Y int eps_p,eq dV for perfect plasticity, the return mapping's
    dissipation); work_internal, work_contact,
    work_residual [J]: the trapezoidal sums of dq . avg(f_int), dq . avg(f_c), dq . avg(r_free)
    since t = 0 (module docstring).
    """

    time: float
    q: np.ndarray = field(repr=False)
    velocity: np.ndarray = field(repr=False)
    acceleration: np.ndarray = field(repr=False)
    material_state: object = field(repr=False)
    active: np.ndarray = field(repr=False)
    internal_force: np.ndarray = field(repr=False)
    contact_force: np.ndarray = field(repr=False)
    free_residual: np.ndarray = field(repr=False)
    force: float = 0.0
    contact_radius: float = 0.0
    contact_edge: float = 0.0
    contact_edge_rate: float | None = None
    displacement_rate: np.ndarray | None = field(default=None, repr=False)
    kinetic_energy: float = 0.0
    elastic_energy: float = 0.0
    plastic_work: float = 0.0
    work_internal: float = 0.0
    work_contact: float = 0.0
    work_residual: float = 0.0

    @property
    def in_contact(self) -> bool:
        return bool(self.active.any())


@dataclass(frozen=True)
class ImpactStep:
    """One solved time step: the trial ``state`` (commit by adopting it), whether it converged
    (``message`` says why not), the contact radius [m] and peak pressure [Pa], iteration counts,
    wall time [s]."""

    state: ImpactState
    converged: bool
    message: str
    contact_radius: float = 0.0
    peak_pressure: float = 0.0
    newton_iterations: int = 0
    active_set_iterations: int = 0
    wall_time_s: float = 0.0


class NewtonStart(NamedTuple):
    """What calib.fe.newton.solve_newton reads of the step's start: the displacement [m], the
    material state, and ``force``, the force scale of the step's residual test [N]."""

    displacement: np.ndarray
    material_state: object
    force: float


def sphere_flat_pair(material, rho: float, radius: float):
    """The Hertz constants of a sphere of ``material`` on the rigid flat, for the contact-time
    estimate: R [m], E* = E / (1 - nu^2) [Pa], the yield point (an elastic material, one without
    sigma_y, never yields: sigma_Y = E, beyond any elastic impact's peak pressure p_Y = A_Y E), and
    the sphere's mass (4/3) pi R^3 rho [kg] (nfdmodel.ContactPair)."""
    E_star = plane_strain_modulus(material.E, material.nu)
    sigma_y = getattr(material, "sigma_y", None)
    sigma_y = material.E if sigma_y is None else sigma_y
    return ContactPair(radius, E_star, sigma_y, material.nu, 4.0 / 3.0 * math.pi * radius ** 3 * rho)


class _FreeBlock:
    """x_free = K[free, free]^-1 b_free from a factorisation of K with the other rows and columns
    cleared but their diagonal (ImpactSolver.factor)."""

    def __init__(self, factor, free: np.ndarray):
        self.factor, self.free = factor, free

    def solve(self, b):
        x = np.zeros(self.free.size)
        x[self.free] = b
        return self.factor.solve(x)[self.free]


class NewmarkSolver:
    """Time steps of a contact configuration under Newmark's average acceleration (module
    docstring): the sphere on the rigid flat (ImpactSolver) or on a deformable counter-body
    (calib.fe.impact_pair.PairImpactSolver). A configuration provides ``constraint``
    (calib.fe.constraint), ``factor`` (calib.fe.newton's interface), T and TT (u = T q, each q one
    dof), ``elements`` (calib.fe.element_arrays), ``material``, ``mass_matrix`` and ``mass_data``, ``compliance`` (D^-1)
    (M on the element pattern), ``stiffness_data`` and ``elastic_D`` (the elastic tangent),
    ``massless`` (the dofs without mass), ``n_q``, ``candidate_r``, ``candidate_weight``, the
    options and scales (residual_tolerance, iteration limits, radius, gap_tolerance,
    stiffness_scale, force_floor), ``kinetic_energy``, ``elastic_energy`` and ``plastic_work``."""

    # ------------------------------------------------- calib.fe.newton's interface
    def assemble(self, displacement, committed):
        """(T (T^T f_int + M a), tangent(), stress, trial state) at ``displacement`` [m] for the
        step being solved: the dynamic residual and K_t + (4/dt^2) M on the element pattern, the
        tangent as the elastic part plus the flowed elements' correction (calib.fe.kinematics)."""
        base, acceleration_n, c0 = self._step
        q = self.TT @ displacement
        # a rate-dependent material (calib.fe.rate_law) reads eps_dot = delta gamma / dt; the others keep the
        # kinematics' three-argument call
        if getattr(self.material, "rate_dependent", False):
            response = self.kinematics.correction(self.material, displacement, committed, time_step=self._time_step)
        else:
            response = self.kinematics.correction(self.material, displacement, committed)
        stress = response.conjugate_stress             # small strain: sigma; finite strain: T (calib.fe.kinematics)
        f_int = self.TT @ self.kinematics.internal_force(stress, displacement)
        data = self.kinematics.elastic_data + c0 * self.mass_data
        if response.tangent_data is not None:
            data = data + response.tangent_data()
        inertia = self.mass_matrix @ (c0 * (q - base) - acceleration_n)
        return self.T @ (f_int + inertia), lambda: self.elements.matrix(data), stress, response.trial

    def elastic_energy(self, stress) -> float:
        """1/2 int sigma . D^-1 sigma dV [J] of a stress field (E, Q, 4) [Pa] (``compliance`` D^-1:
        (4, 4) for one material, (E, Q, 4, 4) per point). Under finite strain ``stress`` is the
        material's T (calib.fe.kinematics.Correction.conjugate_stress) and the integral is over the
        reference volume: the Hencky energy 1/2 int E_e : D E_e dV0, T = D E_e."""
        path = "eqi,ij,eqj->eq" if self.compliance.ndim == 2 else "eqi,eqij,eqj->eq"
        density = 0.5 * np.einsum(path, stress, self.compliance, stress)
        return float(np.sum(density * self.elements.weight))

    def plastic_work(self, material_state) -> float:
        """The work the material has dissipated [J] (calib.fe.material.Material.dissipated_work)."""
        return self.material.dissipated_work(material_state, self.elements.weight)

    def contact_surface_r(self, q) -> np.ndarray:
        """r [m] of the contact candidates the contact radius is measured on: the deformed surface,
        R_i + u_r,i, under a kinematics that measures on it (finite strain), else the undeformed one."""
        if not getattr(self.kinematics, "deformed_surface", False):
            return self.candidate_r
        return self.candidate_r + (self.T @ q)[self.dofs.r_dof[self.dofs.candidate_nodes]]

    # ------------------------------------------------------------------ a step
    def predict_active_set(self, state: ImpactState, dt: float, extrapolated) -> np.ndarray:
        """The active set's warm start: the candidates out to the outermost active node's r
        extrapolated along its last rate; before two states in contact, the candidates whose gap
        the step's velocity closes (``extrapolated`` = q_n + dt v_n). A wrong guess costs
        active-set iterations only; gaps overshoot by one to three nodes at the edge, where the
        pressure bends the surface, and so does the recovered contact radius (it lies between the
        outermost active and the first open node)."""
        if state.contact_edge_rate is not None:
            reach = state.contact_edge + state.contact_edge_rate * dt
            active = self.candidate_r <= reach + 1e-9 * self.radius
            active[0] = True
            return active
        return state.active | (self.constraint.gaps(extrapolated) < -self.gap_tolerance)

    def solve_step(self, state: ImpactState, dt: float, force_scale: float) -> ImpactStep:
        """The state at ``state.time + dt`` [s]; ``force_scale`` [N] (e.g. m v_in / contact time)
        scales the residual test. Never raises for a step that fails: ``converged`` is False."""
        started = time.perf_counter()
        c0 = 4.0 / dt ** 2
        base = state.q + dt * state.velocity
        self._step = (base, state.acceleration, c0)
        self._time_step = float(dt)
        # Newton starts from the committed displacement moved along the last step's displacement rate,
        # an increment the body has just been in equilibrium with. Starting from Newmark's predictor
        # q_n + dt v_n + dt^2/2 a_n puts the nodes next to the contact where their last deceleration
        # points, a strain a perfectly plastic material reads as flow, and Newton then stalls (seen
        # at 24 v_Y).
        q_predicted = state.q + (0.0 if state.displacement_rate is None else dt * state.displacement_rate)
        active = self.predict_active_set(state, dt, base)
        start = NewtonStart(self.T @ state.q, state.material_state, float(force_scale))
        # Trial sets are solved to ACTIVE_SET_TOLERANCE only; the set that settles is solved again to the full
        # tolerance and checked (calib.fe.contact_loop).
        loop = solve_contact(self, self.constraint, q_predicted.copy(), q_predicted, start, "dynamic", 0.0, active,
                             key_prefix=dt, residual_history=[], trial_tolerance=ACTIVE_SET_TOLERANCE)
        active, converged, message = loop.active, loop.converged, loop.message
        if converged and active.size and active[-1]:
            converged, message = False, (f"the contact reached the last candidate node (r = {self.candidate_r[-1]:.4g} m):"
                                         f" the mesh's refined zone is too small for this impact")
        wall = time.perf_counter() - started
        if not converged:
            return ImpactStep(state=state, converged=False, message=message, newton_iterations=loop.newton_iterations,
                              active_set_iterations=loop.active_set_iterations, wall_time_s=wall)
        return self._advanced(state, dt, loop, wall)

    def _advanced(self, state, dt, loop, wall) -> ImpactStep:
        """The new state from a converged step: Newmark's velocity and acceleration, forces, energies."""
        q, active, newton, massless = loop.q, loop.active, loop.newton, self.massless
        acceleration = 4.0 / dt ** 2 * (q - state.q - dt * state.velocity) - state.acceleration
        velocity = state.velocity + 0.5 * dt * (state.acceleration + acceleration)
        velocity[massless] = (q[massless] - state.q[massless]) / dt
        acceleration[massless] = 0.0
        residual = self.TT @ newton.f_int                # T^T f_int + M a: the contact on the active, r_free elsewhere
        internal = residual - self.mass_matrix @ acceleration
        reaction = np.where(active, loop.reaction, 0.0)
        contact = self.constraint.contact_force(reaction, self.n_q)
        free_residual = residual - contact
        dq = q - state.q
        pressure = lumped_contact_pressure(reaction, active, self.candidate_weight, self.candidate_r)
        radius = contact_radius_from_pressure(self.contact_surface_r(q), pressure, active)
        edge = float(self.candidate_r[active].max(initial=0.0))
        rate = (edge - state.contact_edge) / dt if state.in_contact and active.any() else None
        new = ImpactState(
            time=state.time + dt, q=q, velocity=velocity, acceleration=acceleration,
            material_state=newton.trial, active=active, internal_force=internal, contact_force=contact,
            free_residual=free_residual,
            force=float(reaction.sum()), contact_radius=radius, contact_edge=edge, contact_edge_rate=rate,
            displacement_rate=dq / dt, kinetic_energy=self.kinetic_energy(velocity),
            elastic_energy=self.elastic_energy(newton.stress), plastic_work=self.plastic_work(newton.trial),
            work_internal=state.work_internal + 0.5 * float(dq @ (state.internal_force + internal)),
            work_contact=state.work_contact + 0.5 * float(dq @ (state.contact_force + contact)),
            work_residual=state.work_residual + 0.5 * float(dq @ (state.free_residual + free_residual)))
        return ImpactStep(state=new, converged=True, message="converged", contact_radius=radius,
                          peak_pressure=float(pressure.max(initial=0.0)), newton_iterations=loop.newton_iterations,
                          active_set_iterations=loop.active_set_iterations, wall_time_s=wall)


class ImpactSolver(NewmarkSolver):
    """Time steps of a free sphere (meshes.sphere.SphereMesh) on a rigid frictionless flat.

    material: a calib.fe.material.Material; rho: density [kg/m^3]; contact_radius [m]: the
    candidates reach this far from the axis (default: the mesh's refined_radius); kinematics: a name
    of calib.fe.kinematics.KINEMATICS (finite strain: total Lagrangian, the contact radius on the
    deformed surface); the other options as calib.fe.solver.ContactSolver's.
    """

    def __init__(self, sphere, material: Material, rho: float, *, contact_radius: float | None = None,
                 residual_tolerance: float = 1e-8, max_newton_iterations: int = 30,
                 max_active_set_iterations: int = 50, linear_solver: str | None = None, quadrature_order: int = 4,
                 kinematics: str = DEFAULT_KINEMATICS):
        if not (0 < residual_tolerance < 1):
            raise ValueError(f"residual_tolerance must be in (0, 1), got {residual_tolerance}")
        if not (np.isfinite(rho) and rho > 0):
            raise ValueError(f"rho must be > 0 kg/m^3, got {rho}")
        self.sphere = sphere
        self.material = material
        self.rho = float(rho)
        self.radius = float(sphere.spec.radius if sphere.spec is not None else sphere.radius)
        self.residual_tolerance = float(residual_tolerance)
        self.max_newton_iterations = max_newton_iterations
        self.max_active_set_iterations = max_active_set_iterations
        self.linear_solver = linear_solver
        self.is_linear = bool(getattr(material, "is_linear", False))
        self.basis = Basis(sphere.mesh, ElementVector(ElementTriP2()), intorder=quadrature_order)
        self.n_elements, self.n_qp = quadrature_radius(self.basis).shape
        reach = contact_radius if contact_radius is not None else sphere.spec.refined_radius
        self.dofs, self.elements = sphere_dofs(sphere, self.basis, self.rho, quadrature_order, reach)
        self.T, self.TT, self.n_q = self.dofs.T, self.dofs.TT, self.dofs.n_q
        self.candidate_r, self.candidate_weight = self.dofs.candidate_r, self.dofs.candidate_weight
        self.constraint = RigidFlat(self.dofs.candidate_q, self.dofs.candidate_z0, self.candidate_r,
                                    self.candidate_weight)
        self.mass = self.dofs.mass
        self.mass_data = self.dofs.mass_data
        self.mass_matrix = self.elements.matrix(self.mass_data)
        self.massless = self.mass_matrix.diagonal() == 0.0
        self.elastic_D = elastic_tangent(material, self.n_elements, self.n_qp)[0, 0]   # homogeneous material
        self.compliance = np.linalg.inv(self.elastic_D)
        self.kinematics = build_kinematics(kinematics, self.elements, self.elastic_D)
        self.stiffness_data = self.kinematics.elastic_data
        self.gap_tolerance = 1e-12 * self.radius
        # calib.fe.newton reads these: no displacement-based force scale (the free flight's
        # translation carries no force); the floor as calib.fe.solver's
        self.stiffness_scale = 0.0
        self.force_floor = 1e-14 * float(material.E) * self.radius ** 2
        self._step = None                      # (q_n + dt v_n, a_n, 4 / dt^2) of the step being solved
        self.factorizations = FactorCache(linear_solver)
        pattern = self.elements.matrix(np.zeros(self.elements.nnz))
        self._pattern_rows = np.repeat(np.arange(pattern.shape[0]), np.diff(pattern.indptr))
        self._pattern_diagonal = self._pattern_rows == pattern.indices

    # ------------------------------------------------------------------ states
    def contact_pair(self):
        """The quasi-static contact of the impact (its contact-time estimate): sphere_flat_pair."""
        return sphere_flat_pair(self.material, self.rho, self.radius)

    def initial_state(self, v_in: float) -> ImpactState:
        """At first touch (t = 0): undeformed, every point moving at v_in [m/s] toward the flat."""
        zeros = np.zeros(self.dofs.n_q)
        velocity = -float(v_in) * self.dofs.translation
        return ImpactState(time=0.0, q=zeros, velocity=velocity, acceleration=zeros.copy(),
                           material_state=self.material.initial_state(self.n_elements, self.n_qp),
                           active=np.zeros(self.dofs.candidate_r.size, dtype=bool), internal_force=zeros.copy(),
                           contact_force=zeros.copy(), free_residual=zeros.copy(),
                           kinetic_energy=self.kinetic_energy(velocity))

    def kinetic_energy(self, velocity) -> float:
        """v . M v / 2 [J]."""
        return 0.5 * float(velocity @ (self.mass_matrix @ velocity))

    def momentum(self, velocity) -> float:
        """z-momentum t . M v [kg m/s]."""
        return float(self.dofs.translation @ (self.mass_matrix @ velocity))

    def approach(self, q) -> float:
        """alpha = -u_cm [m]: the approach of the centre of mass to the flat since first touch."""
        return -self.centre_of_mass_displacement(q)

    def centre_of_mass_displacement(self, q) -> float:
        """u_z of the centre of mass, t . M q / m [m]."""
        return self.momentum(q) / self.mass

    # ------------------------------------------------- calib.fe.newton's interface
    def factor(self, K_q, free, key):
        """A solver of K_q[free, free] x = b (calib.fe.newton's interface). K_q is factorised whole,
        with the rows and columns of the constrained unknowns cleared but their diagonal: every
        active set then has one sparsity pattern, and every factorisation after the run's first is
        numeric only (qdldl's update, about 60 % of a fresh one). Linear materials: cached by
        ``key`` (dt and the active set)."""
        cached = self.factorizations.cached(key)
        if cached is not None:
            return cached, 0
        data = K_q.data.copy()
        constrained = ~free
        data[(constrained[self._pattern_rows] | constrained[K_q.indices]) & ~self._pattern_diagonal] = 0.0
        # one pattern for every active set: after the run's first, numeric refactorisations only
        return self.factorizations.factor(self.elements.matrix(data), key, b"",
                                          lambda factor: _FreeBlock(factor, free)), 1

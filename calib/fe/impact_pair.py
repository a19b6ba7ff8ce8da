"""One time step of a sphere's impact on a deformable counter-body: Newmark, Newton, the mortar gap.

Two bodies in one mesh (calib.fe.impact_pair_mesh): body 1 the whole sphere (radius R1,
material 1, density rho1), body 2 a whole counter-sphere (R2; free, so the pair's momentum is
conserved) or a flat block (radius and height L, its far face z = -L held). Semi-discrete
equations, u = T q with q every dof but u_r on the axis and the held face's u_z:

    M a + f_int(q) = f_c                                                            [N]
    g_i = q_z1,i - sum_k G_ik q_z2,k + g0_i >= 0,  lambda_i >= 0,  g_i lambda_i = 0   [m], [N]

at the sphere's contact candidates i (its surface nodes with r <= the contact reach), with the
dual mortar gap of calib.fe.contact_pair (G, g0: Wohlmuth 2000; Puso & Laursen 2004); f_c is
lambda_i on body 1's u_z,i and -G_ik lambda_i on body 2's u_z,k. The active set A is solved
exactly (primal active set, Wriggers 2006 ch. 6): each active u_z1,i is eliminated as the affine
function of the master's, q = S p + d (S: identity on the other unknowns, the rows G_i for the
active slaves; d_i = -g0_i), as calib.fe.two_body does for the quasi-static pair; Newton with the
consistent tangent runs on p with K_p = S^T (K_t + (4/dt^2) M) S, r_p = S^T r_q.

Time integration: Newmark's average acceleration, the scheme of calib.fe.newmark (which states
why: implicit, unconditionally stable, non-dissipative, an exact discrete energy identity):

    q_n+1 = q_n + dt v_n + dt^2/4 (a_n + a_n+1),    v_n+1 = v_n + dt/2 (a_n + a_n+1)

Mass: the consistent axisymmetric mass of each body (M_ij = int rho_k phi_i . phi_j 2 pi r dA
[kg]) with the rows and columns of BOTH contact sides' nodes removed (the sphere's candidates and
the counter-body's surface nodes out to the last candidate's r): a massless contact boundary
(Khenous, Laborde & Renard 2008, Eur. J. Mech. A/Solids 27, 918), the rest of each body's mass
scaled so each keeps its consistent mass t_k^T M t_k (t_k its unit z-translation). For two
identical spheres the problem is then the mirror image of calib.fe.newmark's sphere on the rigid
flat (G = I on the mirrored meshes): the symmetry the tests check.

The finite block (a flat counter-body): its far face is held, so the elastic waves the impact
sends into it (longitudinal speed c_L = sqrt(E (1 - nu) / (rho (1 + nu)(1 - 2 nu))) [m/s])
reflect there and at its side, and return after 2 L / c_L [s]. A half-space radiates them away
(Hunter 1957, J. Mech. Phys. Solids 5, 162; Johnson 1985, section 11.4: a fraction of about
1.04 (v_in / c_0)^(3/5) of the kinetic energy, c_0 = sqrt(E / rho), for a sphere and a half-space
of one material; 1e-3 at 0.1 m/s in steel). When the contact time t_c >> 2 L / c_L (the 0.1 m
aluminium sphere on a steel block of L = 2 R1 at 0.04 m/s: t_c = 1.1e-3 s against 7e-5 s) the
block responds quasi-statically: its static compliance changes alpha by O(a / L) (the size study
of calib.fit.counter), and the energy it holds at separation stays in it as vibration instead of
radiating. Measured on the coarse test mesh (contact element 1.6e-4 m), 50 steps per contact,
0.04 m/s: elastic aluminium on elastic steel (of the aluminium's density), e changes by < 5e-6
and P_max, t_c by < 8e-4 from L = R1 to 4 R1; elastoplastic aluminium (24 v_Y) on elastic steel
(tests/benchmarks/bench_impact_pair.py --coarse), e changes by about 1e-4 per doubling of L
(-1.0e-4 at L = R1, +8.4e-5 at 4 R1 against 2 R1), P_max and t_c by < 5e-4.
calib.studies.impact_pair.block_size_effect runs such a study for any pair.

Units: lengths [m], time [s], forces [N], energies [J].
"""
from __future__ import annotations

import time
from collections import OrderedDict

import numpy as np
import scipy.sparse as sp
from skfem import Basis, ElementTriP2, ElementVector, asm

from calib.fe.axisym import quadrature_radius
from calib.fe.contact_pair import active_set_reduction, mortar_gap
from calib.fe.active_set import next_active_set
from calib.fe.dofs import Numbering
from calib.fe.element_arrays import ElementArrays
from calib.fe.forms import mass as mass_form
from calib.fe.linsolve import factorize
from calib.fe.newmark import ImpactState, ImpactStep
from calib.fe.recovery import contact_radius_from_pressure, lumped_contact_pressure
from calib.fe.sphere_dofs import pattern_data
from calib.fe.two_body import PairMaterial

ACTIVE_SET_TOLERANCE = 1e-4      # relative residual to which trial active sets are solved


class PairImpactSolver:
    """Time steps of the sphere on a deformable counter-body (module docstring); the interface
    calib.fe.impact's time loop reads (initial_state, solve_step, approach, ...).

    pair_mesh: calib.fe.impact_pair_mesh.ImpactPairMesh; material1, material2: calib.fe Materials
    of the sphere and the counter-body; rho1, rho2: their densities [kg/m^3]; contact_radius [m]:
    the sphere's candidates reach this far from the axis (default: its mesh's refined_radius).
    """

    def __init__(self, pair_mesh, material1, material2, rho1: float, rho2: float, *,
                 contact_radius: float | None = None, residual_tolerance: float = 1e-8,
                 max_newton_iterations: int = 30, max_active_set_iterations: int = 50,
                 linear_solver: str | None = None, quadrature_order: int = 4):
        if not (0 < residual_tolerance < 1):
            raise ValueError(f"residual_tolerance must be in (0, 1), got {residual_tolerance}")
        for name, rho in (("rho1", rho1), ("rho2", rho2)):
            if not (np.isfinite(rho) and rho > 0):
                raise ValueError(f"{name} must be > 0 kg/m^3, got {rho}")
        self.pair_mesh = pair_mesh
        mesh = pair_mesh.mesh
        self.materials = (material1, material2)
        self.material = PairMaterial(self.materials, pair_mesh.body)
        self.rho = (float(rho1), float(rho2))
        self.R1, self.R2 = pair_mesh.R1, pair_mesh.R2
        self.radius = 1.0 / (1.0 / self.R1 + 1.0 / self.R2)            # R* [m]
        self.free_counter = not pair_mesh.is_block
        self.residual_tolerance = float(residual_tolerance)
        self.max_newton_iterations = max_newton_iterations
        self.max_active_set_iterations = max_active_set_iterations
        self.linear_solver = linear_solver
        self.is_linear = self.material.is_linear

        self.basis = Basis(mesh, ElementVector(ElementTriP2()), intorder=quadrature_order)
        self.n_elements, self.n_qp = quadrature_radius(self.basis).shape
        nodes = Numbering(mesh, self.basis)
        b1, b2 = pair_mesh.boundaries
        eliminated = nodes.r_dof[np.union1d(nodes.facet_nodes(b1["axis"]), nodes.facet_nodes(b2["axis"]))]
        if pair_mesh.is_block:
            eliminated = np.union1d(eliminated, nodes.z_dof[nodes.facet_nodes(b2["held"])])
        self.T, kept, q_of_dof = nodes.reduction(eliminated)
        self.TT = self.T.T.tocsr()
        self.n_q = kept.size
        self.elements = ElementArrays(self.basis, self.T)

        reach = contact_radius if contact_radius is not None else pair_mesh.specs[0].refined_radius
        self.gap = gap = mortar_gap(mesh, b1["contact"], b2["contact"], reach)
        self.candidate_r, self.candidate_weight, self.candidate_g0 = gap.r, gap.weight, gap.g0
        self.candidate_q = q_of_dof[nodes.z_dof[gap.nodes]]
        master_q = q_of_dof[nodes.z_dof[gap.master_nodes]]
        if np.any(self.candidate_q < 0) or np.any(master_q < 0):
            raise ValueError("a contact node's u_z is held: the contact reach meets the block's far face")
        G = gap.G.tocoo()
        self.G_q = sp.csr_matrix((G.data, (G.row, master_q[G.col])), shape=(gap.nodes.size, self.n_q))

        # the bodies' translations and masses; the massless contact boundary (module docstring)
        node_body = np.zeros(nodes.node_r.size, dtype=int)
        node_body[np.unique(np.vstack([mesh.t, mesh.nvertices + mesh.t2f])[:, pair_mesh.body == 1])] = 1
        self.translation = []
        for k in (0, 1):
            t = np.zeros(self.n_q)
            z = q_of_dof[nodes.z_dof[node_body == k]]
            t[z[z >= 0]] = 1.0
            self.translation.append(t)
        M = sum(asm(mass_form, Basis(mesh, ElementVector(ElementTriP2()), intorder=quadrature_order,
                                     elements=np.flatnonzero(pair_mesh.body == k)), rho=self.rho[k]) for k in (0, 1))
        M_q = (self.TT @ M @ self.T).tocsr()
        surface2 = nodes.facet_nodes(b2["contact"])
        master_massless = surface2[nodes.node_r[surface2] <= gap.r.max() * (1 + 1e-9)]
        massless_nodes = np.concatenate([gap.nodes, master_massless])
        massless_dofs = q_of_dof[np.concatenate([nodes.r_dof[massless_nodes], nodes.z_dof[massless_nodes]])]
        massless = np.zeros(self.n_q, dtype=bool)
        massless[massless_dofs[massless_dofs >= 0]] = True
        keep = sp.diags((~massless).astype(float))
        M_kept = (keep @ M_q @ keep).tocsr()
        self.masses = tuple(float(t @ (M_q @ t)) for t in self.translation)
        scale = np.ones(self.n_q)
        q_body = np.zeros(self.n_q, dtype=int)
        q_body[q_of_dof[nodes.z_dof[node_body == 1]][q_of_dof[nodes.z_dof[node_body == 1]] >= 0]] = 1
        q_body[q_of_dof[nodes.r_dof[node_body == 1]][q_of_dof[nodes.r_dof[node_body == 1]] >= 0]] = 1
        for k in (0, 1):
            kept_mass = float(self.translation[k] @ (M_kept @ self.translation[k]))
            scale[q_body == k] = self.masses[k] / kept_mass
        M_kept = (sp.diags(scale) @ M_kept).tocsr()
        self.mass_matrix = M_kept
        self.mass_data = pattern_data(self.elements, M_kept)
        self.massless = massless
        self.q_body = q_body
        # the reduced mass m* [kg] of the relative motion (the sphere's own against a held block)
        m1, m2 = self.masses
        self.mass = m1 * m2 / (m1 + m2) if self.free_counter else m1

        self.elastic_D = self.material.elastic_tangent(self.n_qp)
        self.compliance = np.linalg.inv(self.elastic_D)
        self.stiffness_data = self.elements.stiffness_data(self.elastic_D, slice(None))
        self.gap_tolerance = 1e-12 * self.R1
        self._step = None
        self._factors: OrderedDict = OrderedDict()
        self._last_factor = None

    # ------------------------------------------------------------------ states
    def initial_velocities(self, v_in: float) -> tuple[float, float]:
        """(v1, v2) [m/s]: the sphere moves down at v1, the counter-body up at v2, v1 + v2 = v_in,
        zero total momentum for a free counter-sphere (the centre-of-mass frame); v2 = 0 for a block."""
        if not self.free_counter:
            return float(v_in), 0.0
        m1, m2 = self.masses
        return v_in * m2 / (m1 + m2), v_in * m1 / (m1 + m2)

    def initial_state(self, v_in: float) -> ImpactState:
        """At first touch (t = 0): undeformed, the bodies approaching at v_in [m/s]."""
        v1, v2 = self.initial_velocities(v_in)
        zeros = np.zeros(self.n_q)
        velocity = -v1 * self.translation[0] + v2 * self.translation[1]
        return ImpactState(time=0.0, q=zeros, velocity=velocity, acceleration=zeros.copy(),
                           material_state=self.material.initial_state(self.n_elements, self.n_qp),
                           active=np.zeros(self.candidate_r.size, dtype=bool), internal_force=zeros.copy(),
                           contact_force=zeros.copy(), free_residual=zeros.copy(),
                           kinetic_energy=self.kinetic_energy(velocity))

    def kinetic_energy(self, velocity) -> float:
        """v . M v / 2 [J] of both bodies."""
        return 0.5 * float(velocity @ (self.mass_matrix @ velocity))

    def body_velocity(self, velocity, k: int) -> float:
        """z-velocity of body k's centre of mass, t_k . M v / m_k [m/s]."""
        return float(self.translation[k] @ (self.mass_matrix @ velocity)) / self.masses[k]

    def body_displacement(self, q, k: int) -> float:
        """u_z of body k's centre of mass [m]."""
        return self.body_velocity(q, k)

    def approach(self, q) -> float:
        """alpha [m]: the approach of the two centres of mass (of the sphere's centre to the held
        face, for a block), the DEM overlap of the pair."""
        alpha = -self.body_displacement(q, 0)
        return alpha + self.body_displacement(q, 1) if self.free_counter else alpha

    def separation_velocity(self, velocity) -> float:
        """The relative normal velocity [m/s], > 0 when the bodies move apart: v_z1 - v_z2 (the
        sphere's own, v_z1, against a held block)."""
        v = self.body_velocity(velocity, 0)
        return v - self.body_velocity(velocity, 1) if self.free_counter else v

    def elastic_energy(self, stress) -> float:
        """1/2 int sigma . D^-1 sigma dV [J], each body with its own D."""
        density = 0.5 * np.einsum("eqi,eqij,eqj->eq", stress, self.compliance, stress)
        return float(np.sum(density * self.elements.weight))

    def plastic_work(self, material_state) -> float:
        """sum over the bodies of sigma_Yk int eps_p,eq dV [J] (perfect plasticity's dissipation)."""
        work = 0.0
        for material, state, elements in zip(self.materials, material_state.states, self.material.elements):
            eps = getattr(state, "equivalent_plastic_strain", None)
            if eps is not None:
                work += float(material.sigma_y * np.sum(eps * self.elements.weight[elements]))
        return work

    def gaps(self, q) -> np.ndarray:
        """g_i [m] of every candidate at the unknowns q."""
        return q[self.candidate_q] - self.G_q @ q + self.candidate_g0

    # ------------------------------------------------------------------ one step
    def _assemble(self, q, committed):
        """(r_q = T^T f_int + M a, f_int, K_q + (4/dt^2) M on demand, stress, trial) at ``q`` [m]."""
        base, acceleration_n, c0 = self._step
        stress, tangent, trial = self.material.update(self.elements.strain(self.T @ q), committed)
        f_int = self.TT @ self.elements.internal_force(stress, slice(None))
        residual = f_int + self.mass_matrix @ (c0 * (q - base) - acceleration_n)

        def matrix():
            data = self.stiffness_data + c0 * self.mass_data
            if not self.is_linear:
                correction = tangent - self.elastic_D
                plastic = np.flatnonzero(np.abs(correction).max(axis=(1, 2, 3)) > 1e-13 * np.abs(self.elastic_D).max())
                if plastic.size:
                    data = data + self.elements.stiffness_data(correction[plastic], plastic)
            return self.elements.matrix(data)

        return residual, f_int, matrix, stress, trial

    def reduction(self, active, q_from):
        """(S, d, free_q) of calib.fe.contact_pair.active_set_reduction for the active set."""
        return active_set_reduction(self.candidate_q, self.G_q, self.candidate_g0, active, q_from)

    def _newton(self, q_from, committed, active, force_scale: float, key, tolerance: float):
        """Newton on p for one active set from ``q_from``: (ok, q, r_q, f_int, stress, trial,
        iterations). Converged when ||r_p|| <= tolerance x max(force_scale, ||lambda||) with theta = 1."""
        S, d, free_q = self.reduction(active, q_from)
        ST = S.T.tocsr()
        p = np.append(q_from[free_q], 0.0)
        free = np.ones(p.size, dtype=bool)
        free[-1] = False
        slaves = self.candidate_q[active]
        best, stalled = np.inf, 0
        for iteration in range(self.max_newton_iterations + 1):
            q = S @ p + d
            residual, f_int, matrix, stress, trial = self._assemble(q, committed)
            r_p = ST @ residual
            scale = max(force_scale, float(np.linalg.norm(residual[slaves])))
            norm = float(np.linalg.norm(r_p[free]))
            if not np.isfinite(norm):
                break
            if p[-1] == 1.0 and norm <= tolerance * scale:
                return True, q, residual, f_int, stress, trial, iteration
            if iteration == self.max_newton_iterations:
                break
            # with theta at 1, Newton with the consistent tangent at least halves the residual near
            # the solution: four iterations in a row without halving the best mean divergence
            if p[-1] == 1.0 and iteration > 1:
                if norm < 0.5 * best:
                    best, stalled = norm, 0
                else:
                    stalled += 1
                    if stalled >= 4:
                        break
            K_p = (ST @ matrix() @ S).tocsr()
            rhs = -r_p[free]
            if p[-1] != 1.0:
                rhs -= (1.0 - p[-1]) * K_p[:, -1].toarray().ravel()[free]
            factor = self._factors.get(key) if key is not None else None
            if factor is None:
                matrix_free = K_p[free][:, free].tocsr()
                # a plastic body: a numeric refactorisation while the pattern repeats (qdldl's update)
                if key is None and self._last_factor is not None and self._last_factor.update(matrix_free):
                    factor = self._last_factor
                else:
                    factor = factorize(matrix_free, self.linear_solver)
                if key is not None:
                    self._factors[key] = factor
                    while len(self._factors) > 4:
                        self._factors.popitem(last=False)
                else:
                    self._last_factor = factor
            p[free] += factor.solve(rhs)
            p[-1] = 1.0
        return False, None, None, None, None, None, iteration

    def predict_active_set(self, state: ImpactState, dt: float, extrapolated) -> np.ndarray:
        """The warm start (as calib.fe.newmark.ImpactSolver.predict_active_set): the candidates out to
        the outermost active node's r extrapolated along its rate; before two states in contact,
        the candidates that ``extrapolated`` = q_n + dt v_n carries through the counter-body."""
        if state.contact_edge_rate is not None:
            active = self.candidate_r <= state.contact_edge + state.contact_edge_rate * dt + 1e-9 * self.R1
            active[0] = True
            return active
        return state.active | (self.gaps(extrapolated) < -self.gap_tolerance)

    def solve_step(self, state: ImpactState, dt: float, force_scale: float) -> ImpactStep:
        """The state at ``state.time + dt`` [s]; ``force_scale`` [N] scales the residual test.
        Never raises for a step that fails: ``converged`` is False."""
        started = time.perf_counter()
        c0 = 4.0 / dt ** 2
        base = state.q + dt * state.velocity
        self._step = (base, state.acceleration, c0)
        q = state.q + (0.0 if state.displacement_rate is None else dt * state.displacement_rate)
        q_start = q.copy()
        active = self.predict_active_set(state, dt, base)
        visited = {active.tobytes()}
        newton_total = iterations = 0
        message, converged = "", False
        # trial sets are solved to ACTIVE_SET_TOLERANCE only (enough to tell tensile reactions and
        # penetrations apart); the set that settles is solved again to the full tolerance and checked
        tolerance = max(ACTIVE_SET_TOLERANCE, self.residual_tolerance)
        while iterations < self.max_active_set_iterations:
            iterations += 1
            key = (dt, active.tobytes()) if self.is_linear else None
            # from the previous set's solution; if Newton fails there, from the step's start (a
            # node that held plastic flow and is released can make the former diverge)
            for q_from in ((q,) if iterations == 1 else (q, q_start)):
                ok, q_new, residual, f_int, stress, trial, n = self._newton(q_from, state.material_state, active,
                                                                            force_scale, key, tolerance)
                newton_total += n
                if ok:
                    break
            if not ok:
                message = f"Newton did not converge in {self.max_newton_iterations} iterations"
                break
            q = q_new
            update = next_active_set(active, residual[self.candidate_q], self.gaps(q), visited,
                                     force_tolerance=10.0 * tolerance * force_scale,
                                     gap_tolerance=self.gap_tolerance, force_scale=force_scale,
                                     length_scale=self.R1, force_control=False)
            if update.settled and tolerance == self.residual_tolerance:
                converged = True
                break
            if update.settled:
                tolerance = self.residual_tolerance
                continue
            if update.active is None:
                message = "active set cycles"
                break
            active = update.active
        else:
            message = f"active set did not settle in {self.max_active_set_iterations} iterations"
        if converged and active[-1]:
            converged, message = False, (f"the contact reached the last candidate node (r = {self.candidate_r[-1]:.4g}"
                                         f" m): the mesh's refined zone is too small for this impact")
        wall = time.perf_counter() - started
        if not converged:
            return ImpactStep(state=state, converged=False, message=message, newton_iterations=newton_total,
                              active_set_iterations=iterations, wall_time_s=wall)
        return self._advanced(state, dt, q, active, residual, f_int, stress, trial, newton_total, iterations, wall)

    def _advanced(self, state, dt, q, active, residual, f_int, stress, trial, newton_total, iterations, wall):
        """The new state from a converged step: Newmark's velocity and acceleration, forces, energies."""
        massless = self.massless
        acceleration = 4.0 / dt ** 2 * (q - state.q - dt * state.velocity) - state.acceleration
        velocity = state.velocity + 0.5 * dt * (state.acceleration + acceleration)
        velocity[massless] = (q[massless] - state.q[massless]) / dt
        acceleration[massless] = 0.0
        reaction = np.where(active, residual[self.candidate_q], 0.0)        # lambda_i [N]
        contact = np.zeros(self.n_q)
        contact[self.candidate_q] = reaction
        contact -= self.G_q.T @ reaction                                      # the master's share
        free_residual = residual - contact
        dq = q - state.q
        pressure = lumped_contact_pressure(reaction, active, self.candidate_weight, self.candidate_r)
        radius = contact_radius_from_pressure(self.candidate_r, pressure, active)
        edge = float(self.candidate_r[active].max(initial=0.0))
        rate = (edge - state.contact_edge) / dt if state.in_contact and active.any() else None
        new = ImpactState(
            time=state.time + dt, q=q, velocity=velocity, acceleration=acceleration, material_state=trial,
            active=active, internal_force=f_int, contact_force=contact, free_residual=free_residual,
            force=float(reaction.sum()), contact_radius=radius, contact_edge=edge, contact_edge_rate=rate,
            displacement_rate=dq / dt, kinetic_energy=self.kinetic_energy(velocity),
            elastic_energy=self.elastic_energy(stress), plastic_work=self.plastic_work(trial),
            work_internal=state.work_internal + 0.5 * float(dq @ (state.internal_force + f_int)),
            work_contact=state.work_contact + 0.5 * float(dq @ (state.contact_force + contact)),
            work_residual=state.work_residual + 0.5 * float(dq @ (state.free_residual + free_residual)))
        return ImpactStep(state=new, converged=True, message="converged", contact_radius=radius,
                          peak_pressure=float(pressure.max(initial=0.0)), newton_iterations=newton_total,
                          active_set_iterations=iterations, wall_time_s=wall)

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

import numpy as np
import scipy.sparse as sp
from skfem import Basis, ElementTriP2, ElementVector, asm

from calib.fe.axisym import quadrature_radius
from calib.fe.constraint import MortarContact
from calib.fe.contact_pair import mortar_gap
from calib.fe.dofs import Numbering
from calib.fe.element_arrays import ElementArrays
from calib.fe.forms import mass as mass_form
from calib.fe.kinematics import DEFAULT_KINEMATICS, build_kinematics, elastic_tangent
from calib.fe.linsolve import FactorCache
from calib.fe.newmark import ImpactState, NewmarkSolver
from calib.fe.sphere_dofs import pattern_data
from calib.fe.two_body import PairMaterial
from nfdmodel import ContactPair
from nfdmodel.materials import effective_radius, first_to_yield


class PairImpactSolver(NewmarkSolver):
    """Time steps of the sphere on a deformable counter-body (module docstring): the Newmark stepper
    (calib.fe.newmark.NewmarkSolver) with the mortar contact (calib.fe.constraint.MortarContact);
    the interface calib.fe.impact's time loop reads (initial_state, solve_step, approach, ...).

    pair_mesh: calib.fe.impact_pair_mesh.ImpactPairMesh; material1, material2: calib.fe Materials
    of the sphere and the counter-body; rho1, rho2: their densities [kg/m^3]; contact_radius [m]:
    the sphere's candidates reach this far from the axis (default: its mesh's refined_radius).
    """

    def __init__(self, pair_mesh, material1, material2, rho1: float, rho2: float, *,
                 contact_radius: float | None = None, residual_tolerance: float = 1e-8,
                 max_newton_iterations: int = 30, max_active_set_iterations: int = 50,
                 linear_solver: str | None = None, quadrature_order: int = 4, kinematics: str = DEFAULT_KINEMATICS):
        if not (0 < residual_tolerance < 1):
            raise ValueError(f"residual_tolerance must be in (0, 1), got {residual_tolerance}")
        if kinematics != DEFAULT_KINEMATICS:
            raise ValueError(f"kinematics {kinematics!r} takes the sphere on the rigid flat: the pair impact's"
                             f" two-body contact is small-strain")
        for name, rho in (("rho1", rho1), ("rho2", rho2)):
            if not (np.isfinite(rho) and rho > 0):
                raise ValueError(f"{name} must be > 0 kg/m^3, got {rho}")
        self.pair_mesh = pair_mesh
        mesh = pair_mesh.mesh
        self.materials = (material1, material2)
        self.material = PairMaterial(self.materials, pair_mesh.body)
        self.rho = (float(rho1), float(rho2))
        self.R1, self.R2 = pair_mesh.R1, pair_mesh.R2
        self.radius = effective_radius(self.R1, self.R2)            # R* [m]
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
        self.candidate_r, self.candidate_weight = gap.r, gap.weight
        self.constraint = MortarContact.in_unknowns(gap, q_of_dof, nodes.z_dof, self.n_q, "a contact node's u_z is "
                                                    "held: the contact reach meets the block's far face")
        self.candidate_q = self.constraint.candidate_q

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

        self.elastic_D = elastic_tangent(self.material, self.n_elements, self.n_qp)
        self.compliance = np.linalg.inv(self.elastic_D)
        self.kinematics = build_kinematics(kinematics, self.elements, self.elastic_D)
        self.stiffness_data = self.kinematics.elastic_data
        self.gap_tolerance = 1e-12 * self.R1
        # calib.fe.newton reads these: no displacement-based force scale (the free flight's
        # translation carries no force); the floor as calib.fe.solver's
        self.stiffness_scale = 0.0
        self.force_floor = 1e-14 * float(self.material.E) * self.R1 ** 2
        self._step = None                      # (q_n + dt v_n, a_n, 4 / dt^2) of the step being solved
        self.factorizations = FactorCache(linear_solver)

    # ------------------------------------------------------------------ states
    def contact_pair(self) -> ContactPair:
        """The quasi-static contact of the impact (its contact-time estimate): R*, E* [Pa], m* [kg] and
        the yield point of the body with the lower A_Y(nu) sigma_Y (none yields: sigma_Y = E*, beyond
        any elastic impact's peak pressure, as calib.fe.newmark.sphere_flat_pair)."""
        yielding = [(m.sigma_y, m.nu) for m in self.materials if getattr(m, "sigma_y", None) is not None]
        E_star = float(self.material.E)
        sigma_y, nu = yielding[first_to_yield(*yielding)] if yielding else (E_star, self.materials[0].nu)
        return ContactPair(self.radius, E_star, sigma_y, nu, self.mass)

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


    def factor(self, K_p, free, key, pattern=None):
        """Factorisation of K_p[free, free] and the number of new ones (calib.fe.linsolve.FactorCache.block)."""
        return self.factorizations.block(K_p, free, key, pattern)

"""Axisymmetric FE of a sphere pressed on a deformable counter-body: two meshes, exact contact.

Problem. Body 1, the sphere of radius R1 (material 1), and body 2, a sphere of radius R2 or a
flat block (material 2), meshed as one two-component section (meshes.counter_body), touch at
the origin. Each material is elastic or elastic-perfectly plastic von Mises
(calib.fe.elastic, calib.fe.von_mises: the one return mapping). Equilibrium as in
calib.fe.solver, r(u) = f_int(u) - f_ext = 0 with the axisymmetric weak form (calib.fe.forms,
calib.fe.axisym, calib.fe.element_arrays), and

  * both axes r = 0: u_r = 0;
  * body 1's equatorial face z = R1: a rigid plate, all its u_z tied to one unknown
    q_plate = -alpha; its reaction P = -(T^T f_int)_plate is the contact force [N];
  * body 2's far face (z = -R2, or the block's bottom z = -L): u_z = 0. So alpha [m] is the
    approach of the two far points, the quantity a DEM law takes (for two spheres, the sum of
    the two bodies' approaches);
  * the two surfaces in frictionless unilateral contact: the dual mortar gap g_i >= 0 of the
    sphere's surface nodes against the counter-body's surface (calib.fe.contact_pair, which
    says why mortar and not node-to-segment), reaction lambda_i >= 0, g_i lambda_i = 0,
    solved exactly by the primal active set of calib.fe.active_set: an active node's u_z is
    eliminated as the affine function u_z1,i = G_i u_z2 - g0_i of the master's, so the unknowns
    are q = S p + d (S sparse, one per active set) and Newton (calib.fe.newton, the one Newton
    with the consistent tangent) runs on p with K_p = S^T K_q S, r_p = S^T r_q; the gap closure
    enters as a constrained unknown (TwoBodySolver.reduction), like the rigid plate's prescribed
    approach in calib.fe.solver, so Newton's first solve is an elastic predictor.

The load steps, the secant predictor, the rescue solve (calib.fe.rescue) and the load paths
(calib.fe.loadpath.run_load_paths) are the rigid-flat solver's: TwoBodySolver offers the same
interface (solve_force, solve_displacement, solve_step, rescue_step, commit, initial_state).
An elastic counter-body (a wall) is condensed statically onto the u_z of its contact surface
(calib.fe.condensation, exact for a linear body without loads of its own): the unknowns are then
the sphere's and the counter-body's contact-surface u_z (6,300 instead of 12,000 on the Hertz
test mesh); its stiffness S_m enters the tangent, its interior displacement is filled in once per
converged step (``TwoBodySolver.displacement``), and Newton evaluates the sphere's material only.
A plastic counter-body keeps all its dofs: both materials' states are updated in Newton and
committed with the step (PairMaterial, PairState). Recovery (calib.fe.recovery): pressure
p_i = lambda_i / w_i, contact radius from pressure or gap, first yield in each body
(``first_yield_loads``). Small strain and a << R1, R2 throughout (as Hertz): the gap is
measured along z at the same r, the projections do not follow the tangential displacements.
Frictionless: identical bodies (no relative slip) and a flat counter-body are exact in this
respect (a tangential shift leaves a flat's z unchanged); unlike spheres slip relative to each
other by O(a^2/R), which changes the gap by O(a^3/R^2), a relative O(a/R).

References: Johnson 1985, Contact Mechanics, ch. 4 (Hertz, E*, R*); Wriggers 2006,
Computational Contact Mechanics, ch. 6 (active set); Puso & Laursen 2004 (mortar contact);
Mesarovic & Fleck 2000, Int. J. Solids Struct. 37, 7071 (dissimilar elastic-plastic spheres).
"""
from __future__ import annotations

import copy
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from skfem import Basis, ElementTriP2, ElementVector

from calib.fe.axisym import quadrature_radius
from calib.fe.condensation import CondensedBody
from calib.fe.constraint import MortarContact
from calib.fe.contact_pair import mortar_gap
from calib.fe.element_arrays import ElementArrays
from calib.fe.kinematics import DEFAULT_KINEMATICS, build_kinematics, elastic_tangent
from calib.fe.linsolve import FactorCache
from calib.fe.quasi_static import QuasiStaticSolver
from calib.fe.von_mises import von_mises_stress
from meshes.counter_body import six_node_cells
from nfdmodel.materials import contact_modulus, effective_radius, plane_strain_compliance


# candidates for contact: the sphere's surface nodes within this fraction of the smallest body
# dimension (min(R1, R2, L)); the recipe's largest contact is FE_MAX_CONTACT_RADIUS_OVER_R R below it
CONTACT_ZONE = 0.5


@dataclass(frozen=True, eq=False)
class PairState:
    """The two materials' quadrature-point states; ``equivalent_plastic_strain`` (E, Q) in the pair
    mesh's element order (zero in an elastic body), as calib.fe.loadpath.plastic_zone reads it."""

    states: tuple
    elements: tuple = field(repr=False)
    shape: tuple = ()

    @property
    def equivalent_plastic_strain(self) -> np.ndarray:
        out = np.zeros(self.shape)
        for state, elements in zip(self.states, self.elements):
            eps = getattr(state, "equivalent_plastic_strain", None)
            if eps is not None:
                out[elements] = eps
        return out


class PairMaterial:
    """Material 1 on body 1's elements, material 2 on body 2's: a calib.fe.material.Material.

    ``E`` = E* and ``nu`` = 0 so that E / (1 - nu^2) is the pair's effective modulus
    1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2 [Pa] (the force scales and Hertz warm starts use it).
    """

    def __init__(self, materials, body: np.ndarray):
        self.materials = tuple(materials)
        if any(getattr(m, "rate_dependent", False) for m in self.materials):
            raise ValueError("a rate-dependent material (calib.fe.rate_law) runs on the rigid flat only, not in a pair")
        self.elements = tuple(np.flatnonzero(body == k) for k in (0, 1))
        self.is_linear = all(getattr(m, "is_linear", False) for m in self.materials)
        self.E = contact_modulus(*(plane_strain_compliance(m.E, m.nu) for m in self.materials))
        self.nu = 0.0
        self.n_elements = int(body.size)

    def initial_state(self, n_elements: int, n_qp: int) -> PairState:
        return PairState(tuple(m.initial_state(e.size, n_qp) for m, e in zip(self.materials, self.elements)),
                         self.elements, (n_elements, n_qp))

    def update(self, strain, committed: PairState, elements: np.ndarray | None = None):
        """(stress, tangent, trial state) of the total ``strain`` (n, Q, 4) of ``elements`` (all when
        None); a body none of whose elements are given keeps its committed state."""
        strain = np.asarray(strain)
        stress = np.empty(strain.shape)
        tangent = np.empty(strain.shape + (4,))
        position = None
        if elements is not None:
            position = np.full(self.n_elements, -1)
            position[elements] = np.arange(len(elements))
        states = []
        for material, body, state in zip(self.materials, self.elements, committed.states):
            rows = body if position is None else position[body]
            if rows.size and rows.min() < 0:
                if rows.max() >= 0:
                    raise ValueError("PairMaterial.update: a body's elements are given all or none")
                states.append(state)
                continue
            s, t, trial = material.update(strain[rows], state)
            stress[rows], tangent[rows] = s, t
            states.append(trial)
        return stress, tangent, PairState(tuple(states), self.elements, committed.shape)

    def dissipated_work(self, state: PairState, weight) -> float:
        """The two bodies' dissipated work [J] (calib.fe.material.Material.dissipated_work)."""
        return sum(material.dissipated_work(body_state, weight[elements])
                   for material, body_state, elements in zip(self.materials, state.states, self.elements))


class TwoBodySolver(QuasiStaticSolver):
    """Sphere on a deformable counter-body (module docstring); the interface of ContactSolver.

    pair_mesh: meshes.counter_body.PairMesh; material1, material2: calib.fe Materials (sphere,
    counter-body). Options as ContactSolver's; ``contact_zone``: the contact candidates are the
    sphere's surface nodes within contact_zone x the smallest radius or block size [m] (1: the
    whole face, for two blocks); ``condense``: an elastic counter-body is condensed onto its contact
    surface (False: both bodies in the unknowns, for checking the condensation).
    """

    def __init__(self, pair_mesh, material1, material2, *, residual_tolerance: float = 1e-8,
                 max_newton_iterations: int = 30, max_active_set_iterations: int = 50,
                 linear_solver: str | None = None, contact_radius_method: str = "pressure",
                 quadrature_order: int = 4, contact_zone: float = CONTACT_ZONE, condense: bool = True,
                 kinematics: str = DEFAULT_KINEMATICS):
        if not (0 < residual_tolerance < 1):
            raise ValueError(f"residual_tolerance must be in (0, 1), got {residual_tolerance}")
        if contact_radius_method not in ("pressure", "gap", "node"):
            raise ValueError(f"contact_radius_method must be 'pressure', 'gap' or 'node', got {contact_radius_method!r}")
        self.pair_mesh = self.hemisphere = pair_mesh   # .hemisphere.mesh: the mesh, as ContactSolver's
        mesh = pair_mesh.mesh
        self.material = PairMaterial((material1, material2), pair_mesh.body)
        self.residual_tolerance = float(residual_tolerance)
        self.max_newton_iterations = max_newton_iterations
        self.max_active_set_iterations = max_active_set_iterations
        self.linear_solver = linear_solver
        self.contact_radius_method = contact_radius_method
        self.is_linear = self.material.is_linear
        R1, R2 = pair_mesh.R1, pair_mesh.R2
        # R* [m] (R2 = inf for a block); two blocks (the patch test): the smaller block's size
        self.radius = effective_radius(R1, R2) if min(R1, R2) < np.inf else pair_mesh.smallest_size

        self.basis = Basis(mesh, ElementVector(ElementTriP2()), intorder=quadrature_order)
        self.r_qp = quadrature_radius(self.basis)
        self.n_elements, self.n_qp = self.r_qp.shape
        self.n_dofs = self.basis.N
        self.node_r, self.node_z = mesh.doflocs
        self.r_dof = np.concatenate([self.basis.nodal_dofs[0], self.basis.facet_dofs[0]])
        self.z_dof = np.concatenate([self.basis.nodal_dofs[1], self.basis.facet_dofs[1]])

        def nodes(body, name):
            facets = pair_mesh.boundaries[body][name]
            return np.unique(np.concatenate([mesh.facets[:, facets].ravel(), mesh.nvertices + facets]))

        axis = np.union1d(nodes(0, "axis"), nodes(1, "axis"))
        top, bottom = nodes(0, "top"), nodes(1, "bottom")
        eliminated = np.union1d(np.union1d(self.r_dof[axis], self.z_dof[top]), self.z_dof[bottom])
        unknown = np.setdiff1d(np.arange(self.n_dofs), eliminated)
        gap = mortar_gap(mesh, pair_mesh.boundaries[0]["surface"], pair_mesh.boundaries[1]["surface"],
                         contact_zone * pair_mesh.smallest_size)
        self.gap = gap
        # an elastic counter-body is condensed onto the u_z of its contact surface (module docstring)
        self.condensed = bool(condense and getattr(material2, "is_linear", False))
        body2 = np.unique(six_node_cells(mesh)[:, pair_mesh.body == 1])
        body2_dofs = np.union1d(self.r_dof[body2], self.z_dof[body2])
        master_dofs = self.z_dof[gap.master_nodes]
        if self.condensed:
            kept = np.concatenate([np.setdiff1d(unknown, body2_dofs), master_dofs])
        else:
            kept = unknown
        self.kept, self.plate, self.n_q = kept, int(kept.size), int(kept.size) + 1
        q_of_dof = np.full(self.n_dofs, -1)
        q_of_dof[kept] = np.arange(kept.size)
        # the element arrays see the sphere (and an uncondensed counter-body): one unknown per dof
        direct = np.setdiff1d(kept, master_dofs) if self.condensed else kept
        rows = np.concatenate([direct, self.z_dof[top]])
        cols = np.concatenate([q_of_dof[direct], np.full(top.size, self.plate)])
        T_elements = sp.csr_matrix((np.ones(rows.size), (rows, cols)), shape=(self.n_dofs, self.n_q))
        self.elements = ElementArrays(self.basis, T_elements)
        self.material_D = elastic_tangent(self.material, self.n_elements, self.n_qp)
        if kinematics != DEFAULT_KINEMATICS and not self.condensed:
            raise ValueError(f"kinematics {kinematics!r} takes the pair press on an elastic, condensed counter-body"
                             f" (which stays small-strain); a plastic or uncondensed counter-body needs 'small-strain'")
        # the bodies whose material Newton evaluates: the sphere alone when the counter-body is condensed
        self.kinematics = build_kinematics(kinematics, self.elements, self.material_D,
                                           self.material.elements[0] if self.condensed else None)
        K_full = self.kinematics.elastic_stiffness(self.basis)
        self.counter, self._S_block = None, None
        if self.condensed:
            interior = np.setdiff1d(np.intersect1d(unknown, body2_dofs), master_dofs)
            self.counter = CondensedBody.of(K_full, interior, master_dofs, self.material.elements[1], linear_solver)
            self._S_block = self.counter.stiffness(q_of_dof[master_dofs], self.n_q)
            # Newton's iterate: the sphere's dofs and the master u_z (calib.fe.condensation: X stays out)
            self.T = (T_elements + sp.csr_matrix((np.ones(master_dofs.size), (master_dofs, q_of_dof[master_dofs])),
                                                 shape=(self.n_dofs, self.n_q))).tocsr()
            sphere = sp.diags(np.where(np.isin(np.arange(self.n_dofs), body2_dofs), 0.0, 1.0))
            K_full = (sphere @ K_full @ sphere + self.counter.stiffness(master_dofs, self.n_dofs)).tocsr()
            K_full.eliminate_zeros()
        else:
            self.T = T_elements
        self._K_full = K_full        # f_int = K_full u at Newton's iterates (elastic part)
        self.TT = self.T.T.tocsr()
        self.top_z_dof = int(self.z_dof[top[0]])

        self.candidate_nodes, self.candidate_r = gap.nodes, gap.r
        self.candidate_weight = gap.weight
        self.constraint = MortarContact.in_unknowns(gap, q_of_dof, self.z_dof, self.n_q, "a contact node's u_z is "
                                                    "constrained: the contact zone reaches a loaded face")
        self.candidate_q = self.constraint.candidate_q

        self.gap_tolerance = 1e-12 * self.radius
        self.stiffness_scale = float(self.material.E) * self.radius
        self.force_floor = 1e-14 * self.stiffness_scale * self.radius
        self._K_q = None
        self.factorizations = FactorCache(linear_solver)

    def elastic_twin(self, material1, material2) -> "TwoBodySolver":
        """This solver with the elastic materials ``material1``, ``material2`` of the same E and nu
        (the first-yield search's): the mesh, element arrays, stiffness and the counter-body's
        condensation are shared, not rebuilt; the factorisations are its own."""
        twin = copy.copy(self)
        twin.material = PairMaterial((material1, material2), self.pair_mesh.body)
        if not np.array_equal(elastic_tangent(twin.material, self.n_elements, self.n_qp), self.material_D):
            raise ValueError("elastic_twin: the elastic materials must have the solver's E and nu")
        self._linear_tangent()                  # built once, shared by both
        twin.is_linear = twin.material.is_linear
        twin.factorizations = FactorCache(self.linear_solver)
        return twin

    # ----------------------------------------------------------------- assembly
    def _with_counter(self, K_q):
        return K_q if self._S_block is None else (K_q + self._S_block).tocsr()

    def displacement(self, q) -> np.ndarray:
        """The full dof vector u [m] of the unknowns q (a condensed counter-body's interior filled)."""
        u = self.T @ q
        return u if self.counter is None else self.counter.fill(u)

    def full_stress(self, u, stress):
        """Newton's stress (E, Q, 4) [Pa] with a condensed counter-body's, D strain(u), added."""
        if stress is None or self.counter is None:
            return stress
        full = np.empty((self.n_elements, self.n_qp, 4))
        full[self.kinematics.evaluated] = stress
        elements = self.counter.elements
        full[elements] = self.kinematics.elastic_stress(self.kinematics.strain(u, elements), elements)
        return full

    def tangent_matrix(self, data):
        """K_q from its data on the element pattern, with a condensed counter-body's stiffness."""
        return self._with_counter(self.elements.matrix(data))

    def _linear_tangent(self):
        if self._K_q is None:
            self._K_q_elements = self.elements.matrix(self.kinematics.elastic_data)
            self._K_q = self._with_counter(self._K_q_elements)
        return self._K_q

    def factor(self, K_p, free, key, pattern=None):
        """Factorisation of K_p[free, free] and the number of new ones (calib.fe.linsolve.FactorCache.block)."""
        return self.factorizations.block(K_p, free, key, pattern)

    # ----------------------------------------------------------------- yield
    def yield_ratios(self, state) -> tuple:
        """Per body, max von Mises stress / sigma_Y [-] (None for an elastic body)."""
        q = von_mises_stress(self.stress(state))
        return tuple(float(q[elements].max()) / material.sigma_y if hasattr(material, "sigma_y") else None
                     for material, elements in zip(self.material.materials, self.material.elements))


def first_yield_loads(pair_mesh, material1, material2, sigma_y: tuple, guess: float,
                      solver: TwoBodySolver | None = None) -> tuple:
    """Force [N] at which each body's first quadrature point reaches its yield stress (None for a
    body without one), from the elastic two-body solution: the peak stress grows as P^(1/3)
    (Hertz, Johnson 1985 eq. 4.23), so fixed-point updates P <- P (sigma_Y / q_max)^3 from
    ``guess`` converge (as calib.fit.calibration.first_yield_load for the rigid flat).
    ``material1``, ``material2``: elastic materials of the two bodies; ``sigma_y``: their yield
    stresses [Pa] (None: elastic); ``solver``: a TwoBodySolver on ``pair_mesh`` with these E and nu,
    whose assembly and condensation are reused (TwoBodySolver.elastic_twin)."""
    solver = (TwoBodySolver(pair_mesh, material1, material2) if solver is None
              else solver.elastic_twin(material1, material2))
    loads = []
    for k, sy in enumerate(sigma_y):
        if sy is None:
            loads.append(None)
            continue
        load = guess
        for _ in range(3):
            result = solver.solve_force(solver.initial_state(), load)
            if not result.converged:
                raise RuntimeError(f"elastic first-yield solve at P = {load:g} N: {result.message}")
            q_max = float(von_mises_stress(solver.stress(result.state))[solver.material.elements[k]].max())
            load *= (sy / q_max) ** 3
        loads.append(float(load))
    return tuple(loads)

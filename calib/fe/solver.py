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

Each load step is the quasi-static stepper's (calib.fe.quasi_static: force or displacement
control, the warm starts, the rescue solve, commit) with the one active-set loop
(calib.fe.contact_loop) and the rigid flat as the contact constraint (calib.fe.constraint.RigidFlat).
This module is the configuration: the mesh, the unknowns, the assembly and the factorisations.

Materials follow ``calib.fe.material.Material``: ``update(strain, committed)`` is pure;
the trial state is kept in ``StepResult.state`` and becomes the committed state only when the
caller commits it (``state = solver.commit(result)``), so a failed step can be retried from the
unchanged committed state. For ``material.is_linear`` the tangent is assembled once and each
factorisation is reused for as long as the active set (and control mode) does not change.

References: Johnson 1985, Contact Mechanics, ch. 4 (Hertz); Vu-Quoc & Zhang 1999;
Wriggers 2006, Computational Contact Mechanics, ch. 6 (active set strategy).
"""
from __future__ import annotations

from skfem import Basis, ElementTriP2, ElementVector

from calib.fe.axisym import quadrature_radius
from calib.fe.constraint import RigidFlat
from calib.fe.dofs import contact_dofs
from calib.fe.element_arrays import ElementArrays
from calib.fe.kinematics import DEFAULT_KINEMATICS, build_kinematics, elastic_tangent
from calib.fe.linsolve import METHODS as LINEAR_SOLVERS
from calib.fe.linsolve import FactorCache
from calib.fe.material import Material
from calib.fe.quasi_static import QuasiStaticSolver
from calib.fe.recovery import CONTACT_RADIUS_METHODS

class ContactSolver(QuasiStaticSolver):
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
    kinematics : a name of calib.fe.kinematics.KINEMATICS (small strain)
    """

    def __init__(self, mesh, material: Material, *, residual_tolerance: float = 1e-8,
                 max_newton_iterations: int = 30, max_active_set_iterations: int = 50,
                 linear_solver: str | None = None, contact_radius_method: str = "pressure",
                 quadrature_order: int = 4, kinematics: str = DEFAULT_KINEMATICS):
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
        D = elastic_tangent(material, self.n_elements, self.n_qp)[0, 0]   # homogeneous material
        self.kinematics = build_kinematics(kinematics, self.elements, D)
        self.candidate_nodes, self.candidate_r = dofs.candidate_nodes, dofs.candidate_r
        self.candidate_z0, self.candidate_q = dofs.candidate_z0, dofs.candidate_q
        self.candidate_weight = dofs.candidate_weight
        self.kept = dofs.kept
        self.constraint = RigidFlat(dofs.candidate_q, dofs.candidate_z0, dofs.candidate_r, dofs.candidate_weight)

        self.gap_tolerance = 1e-12 * self.radius  # [m]: round-off, far below any gap of interest
        self.stiffness_scale = float(getattr(material, "E", 1.0)) * self.radius  # [N/m]
        # [N]: a force far below any of interest (E R^2 is the body's natural force unit)
        self.force_floor = 1e-14 * self.stiffness_scale * self.radius
        self._K_q = None  # the elastic tangent in q-space (on self.elements' pattern)
        self.factorizations = FactorCache(linear_solver)

    # ----------------------------------------------------------------- assembly
    def elastic_stiffness(self):
        """Full stiffness matrix [N/m] of a linear material (scikit-fem dof ordering)."""
        if not self.is_linear:
            raise ValueError("elastic_stiffness needs a material with is_linear = True")
        self._linear_tangent()
        return self._K_full

    def _linear_tangent(self):
        """K_el in q-space and on every dof, assembled on first use."""
        if self._K_q is None:
            self._K_full = self.kinematics.elastic_stiffness(self.basis)
            self._K_q = self.elements.matrix(self.kinematics.elastic_data)
        return self._K_q

    def factor(self, K_q, free, key):
        """Factorisation of K_q[free, free] (calib.fe.linsolve.FactorCache: kept under ``key`` for a
        linear material, numeric refactorisation while the constraints ``free`` repeat), and the
        number of new factorisations (0 or 1)."""
        cached = self.factorizations.cached(key)
        if cached is not None:
            return cached, 0
        # K_q[free][:, free] gathered on the fixed pattern
        return self.factorizations.factor(self.elements.restricted(K_q.data, free), key, free.tobytes()), 1

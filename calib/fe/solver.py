"""Axisymmetric FE of a sphere pressed on a rigid frictionless flat: Newton + exact contact.

Problem (SPEC section 6; Vu-Quoc & Zhang 1999, section 2). The r-z section of the hemisphere
(meshes.hemisphere) with quadratic isoparametric triangles; equilibrium in weak form

    r(u) = f_int(u) - f_ext = 0,   f_int,i = int_A sigma(eps(u)) . eps(phi_i) 2 pi r dA   [N]

(calib.fe.axisym for eps and the 2 pi r weight), with
  * axis r = 0: u_r = 0;
  * top face z = R: a rigid plate, all its u_z tied to ONE plate unknown (u = T q, T sparse),
    u_r free. The plate displacement is -alpha (alpha = approach [m]); its reaction
    P = -(T^T f_int)_plate [N] is the contact force (compressive > 0);
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
    node; if that repeats too the step is reported unconverged.
A step never returns silently unconverged: ``StepResult.converged`` is False (and
``ContactSolver.commit`` refuses it), and ``run_load_path`` raises ``StepNotConverged``.
``ContactSolver.rescue_step`` is a slower, defensive solve of a step that failed (from the
committed state without warm start, then, for a force, displacement control with a secant on
the approach); calib.fe.loadpath.advance uses it only where halving the increment has failed.

Materials follow the Material interface (CONTRACTS.md): ``update(strain, committed)`` is pure;
the trial state is kept in ``StepResult.state`` and becomes the committed state only when the
caller commits it (``state = solver.commit(result)``), so a failed step can be retried from the
unchanged committed state. For ``material.is_linear`` the tangent is assembled once and each
factorisation is reused for as long as the active set (and control mode) does not change.

Post-processing per step: contact reactions lambda_i (consistent nodal forces), the contact
pressure recovered from them, the contact radius with sub-element accuracy (see
``contact_radius_from_gap``) and the peak pressure.
References: Johnson 1985, Contact Mechanics, ch. 4 (Hertz); Vu-Quoc & Zhang 1999;
Wriggers 2006, Computational Contact Mechanics, ch. 6 (active set strategy).
"""
from __future__ import annotations

import time
from collections import OrderedDict
from dataclasses import asdict, dataclass, field, replace
from typing import Optional

import numpy as np
import scipy.sparse as sp
from skfem import (Basis, BilinearForm, ElementTriP2, ElementVector, FacetBasis, LinearForm,
                   asm)

from calib.fe.axisym import (quadrature_radius, quadrature_strain, radial_weight, strain,
                          to_form_layout)
from calib.fe.linsolve import METHODS as LINEAR_SOLVERS, factorize
from nfdmodel import check_real

CONTACT_RADIUS_METHODS = ("pressure", "gap", "node")


# --------------------------------------------------------------------------- weak forms
@LinearForm
def internal_force(v, w):
    """Internal nodal forces, int_A sigma . eps(v) 2 pi r dA [N]; ``stress`` shaped (4, E, Q)."""
    r = w.x[0]
    return np.sum(np.asarray(w.stress) * strain(v, r), axis=0) * radial_weight(r)


@BilinearForm
def tangent_stiffness(u, v, w):
    """Tangent stiffness, int_A eps(v) . C eps(u) 2 pi r dA [N/m]; ``tangent`` (4, 4, E, Q)."""
    r = w.x[0]
    C_eps_u = np.einsum("ij...,j...->i...", np.asarray(w.tangent), strain(u, r))
    return np.sum(strain(v, r) * C_eps_u, axis=0) * radial_weight(r)


@LinearForm
def surface_weight(v, w):
    """int_S v 2 pi r ds [m^2]: the lumped (row-sum) boundary mass of the contact surface."""
    return v * radial_weight(w.x[0])


# --------------------------------------------------------------------------- data
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


@dataclass
class _NewtonResult:
    ok: bool
    q: np.ndarray
    f_int: np.ndarray
    residual: np.ndarray
    stress: Optional[np.ndarray]
    trial: object
    residual_norm: float
    scale: float
    iterations: int
    factorizations: int
    time_assembly: float
    time_solve: float
    message: str


class StepNotConverged(RuntimeError):
    """A load step did not meet the residual tolerance or its active set did not settle."""


# --------------------------------------------------------------------------- edge recovery
def contact_radius_from_gap(r, gap, active, n_skip=1):
    """Contact edge from the gap of the open nodes next to the contact [m].

    Outside a smooth (Hertz-like) contact the gap grows like (r - a)^(3/2) (Johnson 1985,
    eq. 4.47 expanded at r = a), so g^(2/3) is linear in r near the edge: extrapolate the line
    through two open nodes to g = 0. The first ``n_skip`` open node(s) are skipped (their gap is
    distorted by the element cut at the edge); the result is clamped to [r of the outermost
    contact node - its spacing, r of the first open node]. Falls back to the outermost contact
    node when there are too few open nodes.
    """
    r, gap, active = np.asarray(r), np.asarray(gap), np.asarray(active, dtype=bool)
    idx = np.flatnonzero(active)
    if idx.size == 0:
        return 0.0
    last = idx[-1]
    i1, i2 = last + 1 + n_skip, last + 2 + n_skip
    if i2 >= r.size:
        return float(r[last])
    s1, s2 = np.maximum(gap[[i1, i2]], 0.0) ** (2.0 / 3.0)
    if not s2 > s1:
        return float(r[last])
    edge = r[i1] - s1 * (r[i2] - r[i1]) / (s2 - s1)
    lower = r[last] - (r[last] - r[idx[-2]] if idx.size > 1 else 0.0)
    return float(np.clip(edge, lower, r[last + 1]))


def contact_radius_from_pressure(r, pressure, active, n_fit=10, n_skip=3):
    """Contact edge from the pressure of the outer contact nodes [m].

    Hertz: p^2 = p0^2 (1 - r^2 / a^2) is linear in r^2 (Johnson 1985, eq. 4.23); near any
    smooth contact edge p ~ sqrt(a - r), so p^2 is locally linear in r (and in r^2) there too.
    Fit a line to (r^2, p^2) over the ``n_fit`` contact nodes that precede the outermost
    ``n_skip`` ones (whose pressure is polluted by the element cut at the edge), take its zero,
    and clamp it to [r of the outermost contact node - its spacing, r of the first open node].
    Falls back to the outermost contact node when the contact has too few nodes.
    """
    r, pressure, active = np.asarray(r), np.asarray(pressure), np.asarray(active, dtype=bool)
    idx = np.flatnonzero(active)
    if idx.size == 0:
        return 0.0
    last = idx[-1]
    fit = idx[:-n_skip][-n_fit:] if idx.size > n_skip else idx[:0]
    fit = fit[r[fit] > 0]
    if fit.size < 3:
        return float(r[last])
    slope, intercept = np.polyfit(r[fit] ** 2, pressure[fit] ** 2, 1)
    if not (slope < 0 and intercept > 0):
        return float(r[last])
    lower = r[last] - (r[last] - r[idx[-2]] if idx.size > 1 else 0.0)
    upper = r[last + 1] if last + 1 < r.size else r[last]
    return float(np.clip(np.sqrt(-intercept / slope), lower, upper))


# --------------------------------------------------------------------------- solver
class ContactSolver:
    """Sphere (hemisphere mesh) on a rigid frictionless flat, any Material (CONTRACTS.md).

    Parameters
    ----------
    mesh : meshes.hemisphere.HemisphereMesh
    material : object with initial_state/update (and optionally ``is_linear``)
    residual_tolerance : relative tolerance on ||r_free||_2 (see module docstring)
    max_newton_iterations, max_active_set_iterations : iteration limits per step
    linear_solver : calib.fe.linsolve method name (None: its default)
    contact_radius_method : "pressure" (default), "gap" or "node" (see the recovery functions;
        measured against Hertz in results/hertz/mesh_ladder.csv)
    quadrature_order : scikit-fem intorder (4: 6-point rule, exact for the P2 stiffness terms)
    """

    def __init__(self, mesh, material, *, residual_tolerance: float = 1e-8,
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

        m = mesh.mesh
        self.radius = float(mesh.spec.radius if mesh.spec is not None else mesh.radius)
        self.basis = Basis(m, ElementVector(ElementTriP2()), intorder=quadrature_order)
        self.quadrature_order = quadrature_order
        self.r_qp = quadrature_radius(self.basis)
        self.n_elements, self.n_qp = self.r_qp.shape
        self.n_dofs = self.basis.N

        # nodes = vertices then edge nodes (MeshTri2 doflocs order); their u_r and u_z dofs
        self.node_r, self.node_z = m.doflocs
        self.r_dof = np.concatenate([self.basis.nodal_dofs[0], self.basis.facet_dofs[0]])
        self.z_dof = np.concatenate([self.basis.nodal_dofs[1], self.basis.facet_dofs[1]])
        n_vertices = m.nvertices

        def facet_nodes(facets):
            return np.unique(np.concatenate([m.facets[:, facets].ravel(), n_vertices + facets]))

        axis_nodes = facet_nodes(mesh.boundaries["axis"])
        top_nodes = facet_nodes(mesh.boundaries["top"])
        surface_nodes = np.setdiff1d(facet_nodes(mesh.boundaries["surface"]), top_nodes)

        # u = T q: q = the dofs that are neither axis u_r (= 0) nor top u_z, plus the plate u_z
        eliminated = np.union1d(self.r_dof[axis_nodes], self.z_dof[top_nodes])
        kept = np.setdiff1d(np.arange(self.n_dofs), eliminated)
        self.plate = kept.size
        self.n_q = kept.size + 1
        rows = np.concatenate([kept, self.z_dof[top_nodes]])
        cols = np.concatenate([np.arange(kept.size), np.full(top_nodes.size, self.plate)])
        self.T = sp.csr_matrix((np.ones(rows.size), (rows, cols)), shape=(self.n_dofs, self.n_q))
        self.TT = self.T.T.tocsr()
        q_of_dof = np.full(self.n_dofs, -1)
        q_of_dof[kept] = np.arange(kept.size)
        self._kept = kept
        self._top_z_dof = int(self.z_dof[top_nodes[0]])

        # contact candidates: surface nodes sorted by r
        order = np.argsort(self.node_r[surface_nodes])
        self.candidate_nodes = surface_nodes[order]
        self.candidate_r = self.node_r[self.candidate_nodes]
        self.candidate_z0 = self.node_z[self.candidate_nodes]
        self.candidate_q = q_of_dof[self.z_dof[self.candidate_nodes]]
        if np.any(self.candidate_q < 0):
            raise ValueError("a contact candidate's u_z is constrained: mesh boundaries overlap")

        # boundary mass on the surface (scalar P2 = one value per node) for the pressure
        surface_basis = FacetBasis(m, ElementTriP2(), facets=mesh.boundaries["surface"],
                                   intorder=quadrature_order)
        self.candidate_weight = asm(surface_weight, surface_basis)[self.candidate_nodes]

        self.gap_tolerance = 1e-12 * self.radius  # [m]: round-off, far below any gap of interest
        self._stiffness_scale = float(getattr(material, "E", 1.0)) * self.radius  # [N/m]
        # [N]: a force far below any of interest (E R^2 is the body's natural force unit)
        self.force_floor = 1e-14 * self._stiffness_scale * self.radius
        self._K_q = None  # linear materials: the constant tangent in q-space
        self._factor_cache: OrderedDict = OrderedDict()
        self._last_free, self._last_factor = None, None  # nonlinear: reuse the symbolic analysis
        self.factorization_count = 0

    # ----------------------------------------------------------------- state
    def initial_state(self) -> ContactState:
        """Undeformed, unloaded, only the pole touching the flat."""
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
        """Strain at the quadrature points, (E, Q, 4) [-]."""
        return quadrature_strain(self.basis, displacement, self.r_qp)

    def stress(self, state: ContactState) -> np.ndarray:
        """Stress of a state at the quadrature points, (E, Q, 4) [Pa] (pure)."""
        return self.material.update(self.strain(state.displacement), state.material_state)[0]

    # ----------------------------------------------------------------- assembly
    def _assemble(self, displacement, committed):
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
        plastic_basis = Basis(self.basis.mesh, self.basis.elem, intorder=self.quadrature_order,
                              elements=elements)
        f_int = f_int + asm(internal_force, plastic_basis,
                            stress=to_form_layout(stress_correction[elements]))

        def tangent():
            K = asm(tangent_stiffness, plastic_basis,
                    tangent=to_form_layout(tangent_correction[elements]))
            return K_q + (self.TT @ K @ self.T).tocsr()

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
            self._K_q = (self.TT @ self._K_full @ self.T).tocsr()
        return self._K_q

    def _factor(self, K_q, free, key):
        """Factorisation of K_q[free, free]; reused for linear materials while ``key`` repeats."""
        if key is not None and key in self._factor_cache:
            self._factor_cache.move_to_end(key)
            return self._factor_cache[key], 0
        matrix = K_q[free][:, free]
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
        return self._solve(state, "displacement", alpha)

    def solve_force(self, state: ContactState, force: float) -> StepResult:
        """Equilibrium at plate force ``force`` = P [N] > 0 (the plate is an unknown)."""
        force = check_real("force", force, unit="N")
        if not force > 0:
            raise ValueError(f"force must be > 0 [N] (P = 0 leaves the approach undetermined;"
                             f" use solve_displacement), got {force}")
        return self._solve(state, "force", force)

    def predict_active_set(self, state: ContactState, control: str, target: float):
        """Warm start of the active set: the nodes inside a predicted contact radius.

        The previous step's radius scaled by a power of the load: the exponent measured over
        the previous step when there is one (elastoplastic contacts grow faster than Hertz's),
        else the Hertz similarity a ~ P^(1/3) (force control) or a ~ alpha^(1/2) (displacement
        control) (Johnson 1985, eq. 4.22-4.23); on the first
        step, the Hertz radius itself when the material has E and nu. A wrong guess costs only
        active-set iterations (the loop corrects it either way); it saves most of them because
        the primal active set otherwise grows by about one ring of nodes per iteration.
        """
        previous = state.force if control == "force" else state.alpha
        if state.contact_radius > 0 and previous > 0 and target > 0:
            if state.radius_exponents is not None:  # learnt from the last step (plasticity
                exponent = state.radius_exponents[0 if control == "force" else 1]  # grows a faster)
            else:
                exponent = 1.0 / 3.0 if control == "force" else 0.5
            radius = state.contact_radius * (target / previous) ** exponent
        elif target > 0 and hasattr(self.material, "E") and hasattr(self.material, "nu"):
            E_star = self.material.E / (1.0 - self.material.nu ** 2)
            radius = ((3.0 * target * self.radius / (4.0 * E_star)) ** (1.0 / 3.0)
                      if control == "force" else np.sqrt(self.radius * target))
        else:
            return state.active.copy() | (np.arange(state.active.size) == 0)
        active = self.candidate_r <= radius
        active[0] = target > 0 or state.active[0]  # the pole: force control needs a support
        return active

    def rescue_step(self, state: ContactState, control: str, target: float) -> StepResult:
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
           on a perfectly plastic body can run away along the soft plastic mode (alpha grew
           6x-85x within failing runs after a node was released); a prescribed alpha bounds it.

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
        first = self._solve(state, control, target, start=state)
        if first.converged or control == "displacement":
            return _merged([first], first, t_start, "converged (rescue: from the committed state)"
                           if first.converged else f"rescue from the committed state: {first.message}")
        return self._force_by_displacement(state, target, first, t_start)

    def _force_by_displacement(self, state: ContactState, target: float, failed: StepResult,
                               t_start: float, max_solves: int = 20) -> StepResult:
        """Stage 2 of ``rescue_step``: the force step to ``target`` [N] through displacement
        control (safeguarded secant on alpha, then a force-controlled polish)."""
        a0, P0 = state.alpha, state.force
        direction = float(np.sign(target - P0))
        slope = None  # first guess of d alpha / d P [m/N] > 0: the last step's, or Hertz's 1 / (2 E* a)
        if state.displacement_rate is not None and direction == state.load_direction:
            slope = -float(state.displacement_rate[self._top_z_dof])
        if not (slope is not None and np.isfinite(slope) and slope > 0):
            E_star = (float(getattr(self.material, "E", 1.0))
                      / (1.0 - float(getattr(self.material, "nu", 0.0)) ** 2))
            slope = 1.0 / (2.0 * E_star * max(state.contact_radius, self.candidate_r[1]))
        near = (a0, P0)  # (alpha, P) on the committed side of the target
        far = None       # (alpha, P) beyond the target, once one is found
        last = near      # the latest solution
        tried = [failed]
        best = None
        alpha = a0 + slope * (target - P0)
        for _ in range(max_solves):
            result = self._solve(state, "displacement", alpha)
            tried.append(result)
            if not result.converged:
                alpha = near[0] + 0.5 * (alpha - near[0])  # closer to the committed side
                continue
            P = result.record.P
            if best is None or abs(P - target) < abs(best.record.P - target):
                best = result
            if abs(P - target) <= self.residual_tolerance * abs(target):
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
            return _merged(tried, failed, t_start, f"{failed.message}; under displacement control"
                           f" too: {tried[-1].message}")
        polish = self._solve(state, "force", target, start=best.state)
        tried.append(polish)
        if polish.converged:
            return _merged(tried, polish, t_start, f"converged (rescue: displacement control,"
                           f" {len(tried) - 2} displacement solves, after {failed.message})")
        return _merged(tried, polish, t_start, f"{failed.message}; force step from the"
                       f" displacement-controlled solution at P = {best.record.P:.8g}:"
                       f" {polish.message}")

    def _solve(self, state: ContactState, control: str, target: float,
               start: ContactState | None = None) -> StepResult:
        t_start = time.perf_counter()
        t_assembly = t_solve = 0.0
        q = np.empty(self.n_q)
        q[:self.plate] = state.displacement[self._kept]
        q[self.plate] = state.displacement[self._top_z_dof]
        # In displacement control the plate is NOT moved here: its jump to -target enters the
        # first Newton solve as a constraint increment (an elastic predictor spread over the
        # body). Moving it alone would strain only the top layer, which a plastic material
        # reads as flow, and Newton can then stall (seen at separation, E / sigma_Y = 100).
        q_start = q.copy()
        if start is not None:
            q[:self.plate] = start.displacement[self._kept]
            q[self.plate] = start.displacement[self._top_z_dof]
        elif (control == "force" and state.displacement_rate is not None
                and np.sign(target - state.force) == state.load_direction):
            # secant predictor: continue along the last step's du/dP (same load direction only:
            # at a turning point the unloading is stiffer than the plastic loading was)
            u_predicted = state.displacement + state.displacement_rate * (target - state.force)
            q[:self.plate] = u_predicted[self._kept]
            q[self.plate] = u_predicted[self._top_z_dof]
        active = self.predict_active_set(state, control, target) if start is None else start.active.copy()
        visited = {active.tobytes()}
        residual_history: list[float] = []
        newton_total = factorizations = active_set_iterations = 0
        message = ""
        converged = False
        stress = trial = None
        residual_norm = np.inf
        tolerance = self.residual_tolerance
        while active_set_iterations < self.max_active_set_iterations:
            active_set_iterations += 1
            constrained = self.candidate_q[active]
            constrained_target = -self.candidate_z0[active]
            if control == "displacement":
                constrained = np.append(constrained, self.plate)
                constrained_target = np.append(constrained_target, -target)
            free = np.ones(self.n_q, dtype=bool)
            free[constrained] = False
            key = (control, active.tobytes()) if self.is_linear else None
            newton = self._newton(q.copy(), state, control, target, constrained,
                                  constrained_target, free, key, residual_history)
            if not newton.ok and active_set_iterations > 1:
                # Continuing from the previous set's solution can diverge when a node that
                # held plastic flow is released (its plastic tangent does not describe the
                # unloading); the committed state is a safe start for the new set.
                newton = self._newton(q_start.copy(), state, control, target, constrained,
                                      constrained_target, free, key, residual_history)
            newton_total += newton.iterations
            factorizations += newton.factorizations
            t_assembly += newton.time_assembly
            t_solve += newton.time_solve
            q, f_int, residual, stress, trial = (newton.q, newton.f_int, newton.residual,
                                                 newton.stress, newton.trial)
            residual_norm, scale = newton.residual_norm, newton.scale
            if not newton.ok:
                message = newton.message or (f"Newton did not reach the residual tolerance"
                                             f" {tolerance:g} in {self.max_newton_iterations}"
                                             f" iterations (relative residual {residual_norm:.3g})")
                break
            # active set update: release tensile reactions, add penetrating nodes
            reaction = residual[self.candidate_q]
            gap = self.candidate_z0 + q[self.candidate_q]
            # Reactions are only known to the Newton tolerance: a "tensile" reaction below it is
            # noise (e.g. the pole, whose P2 weight 2 pi r vanishes) and must not flip the set.
            force_tol = 10.0 * self.residual_tolerance * scale
            tensile = active & (reaction < -force_tol)
            penetrating = ~active & (gap < -self.gap_tolerance)
            if not (tensile.any() or penetrating.any()):
                converged = True
                break
            new_active = (active | penetrating) & ~tensile
            if new_active.tobytes() in visited:
                # cycling: change only the single worst node
                violation = np.where(tensile, -reaction / scale, 0.0)
                violation = np.maximum(violation, np.where(penetrating, -gap / self.radius, 0.0))
                worst = int(np.argmax(violation))
                new_active = active.copy()
                new_active[worst] = not active[worst]
                if new_active.tobytes() in visited:
                    message = "active set cycles"
                    break
            if control == "force" and not new_active.any():
                new_active[int(np.argmin(gap))] = True
            visited.add(new_active.tobytes())
            active = new_active
        else:
            message = f"active set did not settle in {self.max_active_set_iterations} iterations"

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
                                 radius_exponents=_radius_exponents(state, alpha, P, chosen),
                                 **_displacement_rate(state, control, u, P))
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

    def _newton(self, q, state, control, target, constrained, constrained_target, free, key,
                residual_history):
        """Newton on r(q) = 0 for one active set (constraints: active nodes, and the plate in
        displacement control), from ``q``. Stops at the residual tolerance, at the iteration
        limit, or early when it stalls (see below)."""
        t_assembly = t_solve = 0.0
        iterations = factorizations = 0
        message = ""
        best, stalled = np.inf, 0
        # A physical force scale, never one that grows with the iterate (a diverging iterate
        # must not look converged): besides the constraint reactions, the target force, the
        # force the step starts from (near separation the reactions vanish), and E R |u| for
        # the committed and the prescribed displacements (a lifted sphere has no force at all).
        displacement_scale = max(np.abs(state.displacement).max(initial=0.0),
                                 abs(target) if control == "displacement" else 0.0)
        base_scale = max(target if control == "force" else 0.0, abs(state.force),
                         1e-3 * self._stiffness_scale * displacement_scale, self.force_floor)
        for newton in range(self.max_newton_iterations + 1):
            t0 = time.perf_counter()
            f_int, tangent, stress, trial = self._assemble(self.T @ q, state.material_state)
            residual = self.TT @ f_int
            if control == "force":
                residual[self.plate] += target  # f_ext on the plate unknown is -P
            t_assembly += time.perf_counter() - t0
            dq_constrained = constrained_target - q[constrained]
            scale = max(np.linalg.norm(residual[constrained]), base_scale)
            residual_norm = np.linalg.norm(residual[free]) / scale
            residual_history.append(float(residual_norm))
            ok = residual_norm <= self.residual_tolerance and not np.any(dq_constrained)
            if ok or newton == self.max_newton_iterations:
                break
            # Newton with a consistent tangent at least halves the residual every iteration
            # near the solution: four iterations in a row without halving the best residual
            # mean divergence or a limit cycle, not slow progress.
            # An iterate that does not meet the constraints yet (the first of a displacement
            # step, or one with newly active nodes) is no baseline for that test.
            if np.any(dq_constrained):
                pass
            elif residual_norm < 0.5 * best:
                best, stalled = residual_norm, 0
            else:
                stalled += 1
                if stalled >= 4:
                    message = f"Newton stalled (relative residual {residual_norm:.3g})"
                    break
            t0 = time.perf_counter()
            K_q = tangent()
            t_assembly += time.perf_counter() - t0
            t0 = time.perf_counter()
            try:
                factor, n_new = self._factor(K_q, free, key)
            except np.linalg.LinAlgError as exc:
                message = f"singular tangent: {exc}"
                break
            factorizations += n_new
            rhs = -residual[free]
            if dq_constrained.any():
                rhs -= K_q[free][:, constrained] @ dq_constrained
            dq_free = factor.solve(rhs)
            t_solve += time.perf_counter() - t0
            if not np.all(np.isfinite(dq_free)):
                message = "non-finite Newton increment"
                break
            q[free] += dq_free
            q[constrained] = constrained_target
            iterations += 1
        return _NewtonResult(ok=bool(ok), q=q, f_int=f_int, residual=residual, stress=stress,
                             trial=trial, residual_norm=float(residual_norm), scale=float(scale),
                             iterations=iterations, factorizations=factorizations,
                             time_assembly=t_assembly, time_solve=t_solve, message=message)

    def contact_pressure(self, reaction, active):
        """Nodal contact pressure [Pa] from the nodal contact reactions [N] (lumped recovery).

        p_i = lambda_i / int_S N_i 2 pi r ds: local, no oscillation at the contact edge (the
        consistent recovery M_AA p_A = lambda_A, tried first, rings near the edge, by 5 % of p0
        on the outermost nodes). At the pole the P2 vertex weight int N_pole 2 pi r ds is zero,
        so p(0) is extrapolated from the next three nodes as p = c0 + c2 r^2 (p is even in r).
        """
        pressure = np.zeros(reaction.size)
        weight = self.candidate_weight
        usable = active & (weight > 1e-9 * weight.max())  # the pole's weight is round-off
        pressure[usable] = reaction[usable] / weight[usable]
        if active[0] and not usable[0]:
            nearest = np.flatnonzero(usable)[:3]
            if nearest.size >= 2:
                c2, c0 = np.polyfit(self.candidate_r[nearest] ** 2, pressure[nearest], 1)
                pressure[0] = c0
            elif nearest.size == 1:
                pressure[0] = pressure[nearest[0]]
        return pressure

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


def run_load_path(solver: ContactSolver, loads, control: str = "force",
                  state: ContactState | None = None):
    """Apply ``loads`` (forces [N] or approaches [m]) in order, committing each converged step.

    Returns (results, final_state). Raises StepNotConverged at the first failed step (the
    results so far are attached as ``exc.results``).
    """
    if control not in ("force", "displacement"):
        raise ValueError(f"control must be 'force' or 'displacement', got {control!r}")
    state = solver.initial_state() if state is None else state
    step = solver.solve_force if control == "force" else solver.solve_displacement
    results = []
    for load in loads:
        result = step(state, load)
        if not result.converged:
            exc = StepNotConverged(f"{control} step {load:g}: {result.message}")
            exc.results = results
            raise exc
        results.append(result)
        state = solver.commit(result)
    return results, state


def _displacement_rate(before: ContactState, control: str, displacement, force: float) -> dict:
    """du/dP and the load direction over a force-controlled step (for the secant predictor)."""
    change = force - before.force
    if control != "force" or before.force <= 0 or abs(change) < 1e-9 * abs(force):
        return {}
    return {"displacement_rate": (displacement - before.displacement) / change,
            "load_direction": int(np.sign(change))}


def _radius_exponents(before: ContactState, alpha: float, force: float, radius: float):
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


def _merged(tried, result: StepResult, t_start: float, message: str) -> StepResult:
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

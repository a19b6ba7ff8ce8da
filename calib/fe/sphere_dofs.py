"""The free sphere of an impact: its unknowns, its contact candidates and its mass matrix.

Unknowns: u = T q with q = every dof of the P2 vector basis but u_r on the axis r = 0 (zero by
symmetry); T selects (each q is one dof). No face is held: the sphere's rigid translation along
z is free (K is singular in it, K + M / (beta dt^2) is not).

Contact candidates: the surface nodes of the mesh's refined zone (r <= refined_radius, below the
centre), sorted by r, with the q index of their u_z, their initial gap z0 [m] and their boundary
weight int_S N_i 2 pi r ds [m^2] (calib.fe.dofs states the same for the hemisphere).

Mass: the consistent mass of the axisymmetric solid (calib.fe.forms.mass)

    M_ij = int_A rho phi_i . phi_j 2 pi r dA                         [kg]

with the rows and columns of the contact candidates' dofs removed: a massless contact boundary
(Khenous, Laborde & Renard 2008, Eur. J. Mech. A/Solids 27, 918; Renard 2010, J. Comput. Appl.
Math. 234, 906). With mass on them, a node stopped by the flat inside a time step leaves the
implicit scheme with a velocity jump it cannot absorb: the contact force rings and the active set
chatters. Without, the contact nodes follow the body quasi-statically, the semi-discrete problem
is well posed and its contact stresses are stable. The rest of M is scaled by m_h / m_kept so
the sphere keeps the discrete mass m_h = t^T M t of the full consistent matrix (t: the unit
translation along z); the mass moved is a surface layer of the refined zone (about 1e-7 m_h
on the reference mesh), the centre of mass moves by that fraction of R.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from skfem import ElementTriP2, FacetBasis, asm

from calib.fe.element_arrays import ElementArrays
from calib.fe.forms import mass as mass_form
from calib.fe.forms import surface_weight


@dataclass(frozen=True)
class SphereDofs:
    """The reduction u = T q, the contact candidates and the mass of one sphere mesh.

    node_r, node_z [m] of every P2 node; r_dof, z_dof per node; T (n_dofs, n_q), TT = T^T;
    candidate_nodes/_r/_z0/_q/_weight as in calib.fe.dofs.ContactDofs; translation: the unit
    rigid translation along z in q [-]; pole_q: q index of the bottom pole's u_z; mass_data: M_q
    on the ElementArrays pattern [kg]; mass: m_h [kg]; massless_fraction: the consistent mass of
    the candidates' dofs over m_h (moved to the others) [-].
    """

    node_r: np.ndarray
    node_z: np.ndarray
    r_dof: np.ndarray
    z_dof: np.ndarray
    T: sp.csr_matrix
    TT: sp.csr_matrix
    candidate_nodes: np.ndarray
    candidate_r: np.ndarray
    candidate_z0: np.ndarray
    candidate_q: np.ndarray
    candidate_weight: np.ndarray
    translation: np.ndarray
    pole_q: int
    mass_data: np.ndarray
    mass: float
    massless_fraction: float

    @property
    def n_q(self) -> int:
        return self.T.shape[1]


def sphere_dofs(sphere, basis, rho: float, quadrature_order: int,
                contact_radius: float) -> tuple[SphereDofs, ElementArrays]:
    """The unknowns, candidates (surface nodes with r <= ``contact_radius`` [m], below the centre)
    and mass (density ``rho`` [kg/m^3]) of ``sphere`` (meshes.sphere.SphereMesh) on ``basis`` (P2
    vector basis of its mesh), with the ElementArrays of the reduction u = T q."""
    m = sphere.mesh
    radius = float(sphere.spec.radius if sphere.spec is not None else sphere.radius)
    n_dofs = basis.N
    node_r, node_z = m.doflocs
    r_dof = np.concatenate([basis.nodal_dofs[0], basis.facet_dofs[0]])
    z_dof = np.concatenate([basis.nodal_dofs[1], basis.facet_dofs[1]])

    def facet_nodes(facets):
        return np.unique(np.concatenate([m.facets[:, facets].ravel(), m.nvertices + facets]))

    axis_nodes = facet_nodes(sphere.boundaries["axis"])
    kept = np.setdiff1d(np.arange(n_dofs), r_dof[axis_nodes])
    T = sp.csr_matrix((np.ones(kept.size), (kept, np.arange(kept.size))), shape=(n_dofs, kept.size))
    q_of_dof = np.full(n_dofs, -1)
    q_of_dof[kept] = np.arange(kept.size)
    elements = ElementArrays(basis, T)

    surface = facet_nodes(sphere.boundaries["surface"])
    tol = 1e-9 * radius
    lower = surface[(node_z[surface] < radius) & (node_r[surface] <= contact_radius + tol)]
    candidates = lower[np.argsort(node_r[lower])]
    candidate_q = q_of_dof[z_dof[candidates]]
    surface_basis = FacetBasis(m, ElementTriP2(), facets=sphere.boundaries["surface"], intorder=quadrature_order)
    weight = asm(surface_weight, surface_basis)[candidates]

    translation = np.zeros(kept.size)
    translation[q_of_dof[z_dof]] = 1.0
    M_q = (T.T @ asm(mass_form, basis, rho=rho) @ T).tocsr()
    full_mass = float(translation @ (M_q @ translation))
    massless = np.zeros(kept.size, dtype=bool)
    candidate_dofs = np.concatenate([q_of_dof[r_dof[candidates]], candidate_q])
    massless[candidate_dofs[candidate_dofs >= 0]] = True    # the pole's u_r is no unknown
    keep = sp.diags((~massless).astype(float))
    M_kept = (keep @ M_q @ keep).tocsr()
    kept_mass = float(translation @ (M_kept @ translation))
    M_kept = M_kept * (full_mass / kept_mass)
    pole = candidates[np.argmin(node_r[candidates])]
    dofs = SphereDofs(node_r=node_r, node_z=node_z, r_dof=r_dof, z_dof=z_dof, T=T, TT=T.T.tocsr(),
                      candidate_nodes=candidates, candidate_r=node_r[candidates], candidate_z0=node_z[candidates],
                      candidate_q=candidate_q, candidate_weight=weight, translation=translation,
                      pole_q=int(q_of_dof[z_dof[pole]]), mass_data=pattern_data(elements, M_kept),
                      mass=full_mass, massless_fraction=1.0 - kept_mass / full_mass)
    return dofs, elements


def pattern_data(elements: ElementArrays, matrix: sp.spmatrix) -> np.ndarray:
    """The entries of ``matrix`` (n_q x n_q) as a data array on the sparsity pattern of
    ``elements`` (ElementArrays.matrix); ValueError if an entry lies outside the pattern."""
    coo = sp.coo_matrix(matrix)
    numbered = elements.matrix(np.arange(1, elements.nnz + 1, dtype=float))
    position = np.asarray(numbered[coo.row, coo.col]).ravel().astype(np.int64) - 1
    if np.any(position < 0):
        raise ValueError("matrix has entries outside the element pattern")
    return np.bincount(position, coo.data, minlength=elements.nnz)

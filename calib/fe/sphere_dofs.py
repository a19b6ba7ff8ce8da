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
from skfem import asm

from calib.fe.dofs import NodeDofs, Numbering
from calib.fe.element_arrays import ElementArrays
from calib.fe.forms import mass as mass_form


@dataclass(frozen=True)
class SphereDofs(NodeDofs):
    """The reduction u = T q, the contact candidates (calib.fe.dofs.NodeDofs) and the mass of one
    sphere mesh: translation: the unit rigid translation along z in q [-]; pole_q: q index of the
    bottom pole's u_z; mass_data: M_q on the ElementArrays pattern [kg]; mass: m_h [kg];
    massless_fraction: the consistent mass of the candidates' dofs over m_h (moved to the others) [-].
    """

    translation: np.ndarray = None
    pole_q: int = 0
    mass_data: np.ndarray = None
    mass: float = 0.0
    massless_fraction: float = 0.0


def sphere_dofs(sphere, basis, rho: float, quadrature_order: int,
                contact_radius: float) -> tuple[SphereDofs, ElementArrays]:
    """The unknowns, candidates (surface nodes with r <= ``contact_radius`` [m], below the centre)
    and mass (density ``rho`` [kg/m^3]) of ``sphere`` (meshes.sphere.SphereMesh) on ``basis`` (P2
    vector basis of its mesh), with the ElementArrays of the reduction u = T q."""
    radius = float(sphere.spec.radius if sphere.spec is not None else sphere.radius)
    nodes = Numbering(sphere.mesh, basis)
    node_r, node_z = nodes.node_r, nodes.node_z
    T, kept, q_of_dof = nodes.reduction(nodes.r_dof[nodes.facet_nodes(sphere.boundaries["axis"])])
    elements = ElementArrays(basis, T)

    surface = nodes.facet_nodes(sphere.boundaries["surface"])
    tol = 1e-9 * radius
    lower = surface[(node_z[surface] < radius) & (node_r[surface] <= contact_radius + tol)]
    contact = nodes.candidates(lower, q_of_dof, sphere.boundaries["surface"], quadrature_order)
    candidates, candidate_q = contact["candidate_nodes"], contact["candidate_q"]

    translation = np.zeros(kept.size)
    translation[q_of_dof[nodes.z_dof]] = 1.0
    M_q = (T.T @ asm(mass_form, basis, rho=rho) @ T).tocsr()
    full_mass = float(translation @ (M_q @ translation))
    massless = np.zeros(kept.size, dtype=bool)
    candidate_dofs = np.concatenate([q_of_dof[nodes.r_dof[candidates]], candidate_q])
    massless[candidate_dofs[candidate_dofs >= 0]] = True    # the pole's u_r is no unknown
    keep = sp.diags((~massless).astype(float))
    M_kept = (keep @ M_q @ keep).tocsr()
    kept_mass = float(translation @ (M_kept @ translation))
    M_kept = M_kept * (full_mass / kept_mass)
    pole = candidates[np.argmin(node_r[candidates])]
    dofs = SphereDofs(**contact, T=T, TT=T.T.tocsr(), translation=translation,
                      pole_q=int(q_of_dof[nodes.z_dof[pole]]), mass_data=pattern_data(elements, M_kept),
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

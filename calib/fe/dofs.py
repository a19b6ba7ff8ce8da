"""The unknowns of the contact problem: the rigid-plate tie and the contact candidate nodes.

Displacement dofs u (scikit-fem ordering of the P2 vector basis) are reduced to unknowns q by

    u = T q,   q = (the dofs that are neither u_r on the axis r = 0 (zero by symmetry) nor u_z on
                    the top face, then ONE plate unknown that all top-face u_z are tied to)

so the top face moves as a rigid plate: its displacement is q_plate = -alpha (alpha the approach
[m]) and its reaction (T^T f_int)_plate = -P. Forces reduce with T^T, stiffnesses with
T^T K T. The contact candidates are the curved-surface nodes, sorted by r, each with the q index
of its u_z and its boundary weight int_S N_i 2 pi r ds [m^2] (the lumped surface mass that turns
nodal reactions into pressure).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from skfem import ElementTriP2, FacetBasis, asm

from calib.fe.forms import surface_weight


@dataclass(frozen=True)
class ContactDofs:
    """The reduction u = T q and the contact candidates of one hemisphere mesh.

    node_r, node_z [m]: coordinates of every P2 node (vertices, then edge nodes);
    r_dof, z_dof: the u_r and u_z dof of each node; T (n_dofs, n_q), TT = T^T (csr);
    plate: the index of the plate unknown in q (the last); kept: the dofs that are q entries;
    top_z_dof: one top-face u_z dof (all equal the plate's);
    candidate_nodes/_r/_z0/_q/_weight: the contact candidates sorted by r, their r and z [m], the
    q index of their u_z, and int_S N_i 2 pi r ds [m^2].
    """

    node_r: np.ndarray
    node_z: np.ndarray
    r_dof: np.ndarray
    z_dof: np.ndarray
    T: sp.csr_matrix
    TT: sp.csr_matrix
    plate: int
    kept: np.ndarray
    top_z_dof: int
    candidate_nodes: np.ndarray
    candidate_r: np.ndarray
    candidate_z0: np.ndarray
    candidate_q: np.ndarray
    candidate_weight: np.ndarray

    @property
    def n_q(self) -> int:
        return self.plate + 1


def contact_dofs(hemisphere, basis, quadrature_order: int) -> ContactDofs:
    """The plate tie and contact candidates of ``hemisphere`` (meshes.hemisphere.HemisphereMesh,
    boundaries "axis", "top", "surface") on ``basis`` (P2 vector basis of its mesh)."""
    m = hemisphere.mesh
    n_dofs = basis.N
    # nodes = vertices then edge nodes (MeshTri2 doflocs order); their u_r and u_z dofs
    node_r, node_z = m.doflocs
    r_dof = np.concatenate([basis.nodal_dofs[0], basis.facet_dofs[0]])
    z_dof = np.concatenate([basis.nodal_dofs[1], basis.facet_dofs[1]])

    def facet_nodes(facets):
        return np.unique(np.concatenate([m.facets[:, facets].ravel(), m.nvertices + facets]))

    axis_nodes = facet_nodes(hemisphere.boundaries["axis"])
    top_nodes = facet_nodes(hemisphere.boundaries["top"])
    surface_nodes = np.setdiff1d(facet_nodes(hemisphere.boundaries["surface"]), top_nodes)

    eliminated = np.union1d(r_dof[axis_nodes], z_dof[top_nodes])
    kept = np.setdiff1d(np.arange(n_dofs), eliminated)
    plate = kept.size
    rows = np.concatenate([kept, z_dof[top_nodes]])
    cols = np.concatenate([np.arange(kept.size), np.full(top_nodes.size, plate)])
    T = sp.csr_matrix((np.ones(rows.size), (rows, cols)), shape=(n_dofs, plate + 1))
    q_of_dof = np.full(n_dofs, -1)
    q_of_dof[kept] = np.arange(kept.size)

    candidate_nodes = surface_nodes[np.argsort(node_r[surface_nodes])]
    candidate_q = q_of_dof[z_dof[candidate_nodes]]
    if np.any(candidate_q < 0):
        raise ValueError("a contact candidate's u_z is constrained: mesh boundaries overlap")
    # boundary mass on the surface (scalar P2 = one value per node) for the pressure
    surface_basis = FacetBasis(m, ElementTriP2(), facets=hemisphere.boundaries["surface"],
                               intorder=quadrature_order)
    weight = asm(surface_weight, surface_basis)[candidate_nodes]
    return ContactDofs(node_r=node_r, node_z=node_z, r_dof=r_dof, z_dof=z_dof, T=T,
                       TT=T.T.tocsr(), plate=int(plate), kept=kept,
                       top_z_dof=int(z_dof[top_nodes[0]]), candidate_nodes=candidate_nodes,
                       candidate_r=node_r[candidate_nodes], candidate_z0=node_z[candidate_nodes],
                       candidate_q=candidate_q, candidate_weight=weight)

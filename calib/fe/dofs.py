"""The unknowns of the contact problem: the rigid-plate tie and the contact candidate nodes.

Displacement dofs u (scikit-fem ordering of the P2 vector basis) are reduced to unknowns q by

    u = T q,   q = (the dofs that are neither u_r on the axis r = 0 (zero by symmetry) nor u_z on
                    the top face, then ONE plate unknown that all top-face u_z are tied to)

so the top face moves as a rigid plate: its displacement is q_plate = -alpha (alpha the approach
[m]) and its reaction (T^T f_int)_plate = -P. Forces reduce with T^T, stiffnesses with
T^T K T. The contact candidates are the curved-surface nodes, sorted by r, each with the q index
of its u_z and its boundary weight int_S N_i 2 pi r ds [m^2] (the lumped surface mass that turns
nodal reactions into pressure).

NodeDofs (the nodes, T and the candidates) and Numbering (the P2 nodes of a mesh, their facet
nodes, a reduction u = T q, the candidates' weights) serve the hemisphere here and the free sphere
of an impact (calib.fe.sphere_dofs).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from skfem import ElementTriP2, FacetBasis, asm

from calib.fe.forms import surface_weight


@dataclass(frozen=True)
class NodeDofs:
    """The P2 nodes of a mesh and their unknowns, with the contact candidates.

    node_r, node_z [m]: coordinates of every P2 node (vertices, then edge nodes);
    r_dof, z_dof: the u_r and u_z dof of each node; T (n_dofs, n_q), TT = T^T (csr);
    candidate_nodes/_r/_z0/_q/_weight: the contact candidates sorted by r, their r and z [m], the
    q index of their u_z, and int_S N_i 2 pi r ds [m^2].
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

    @property
    def n_q(self) -> int:
        return self.T.shape[1]


@dataclass(frozen=True)
class ContactDofs(NodeDofs):
    """The reduction u = T q and the contact candidates of one hemisphere mesh (NodeDofs), with
    plate: the index of the plate unknown in q (the last); kept: the dofs that are q entries;
    top_z_dof: one top-face u_z dof (all equal the plate's).
    """

    plate: int = 0
    kept: np.ndarray = None
    top_z_dof: int = 0


class Numbering:
    """The P2 nodes of ``mesh`` on ``basis`` (P2 vector basis): node_r, node_z [m] (vertices then
    edge nodes, MeshTri2's doflocs order) and their u_r, u_z dofs."""

    def __init__(self, mesh, basis):
        self.mesh = mesh
        self.n_dofs = basis.N
        self.node_r, self.node_z = mesh.doflocs
        self.r_dof = np.concatenate([basis.nodal_dofs[0], basis.facet_dofs[0]])
        self.z_dof = np.concatenate([basis.nodal_dofs[1], basis.facet_dofs[1]])

    def facet_nodes(self, facets) -> np.ndarray:
        """The nodes (vertices and mid-side nodes) of ``facets``, sorted, unique."""
        m = self.mesh
        return np.unique(np.concatenate([m.facets[:, facets].ravel(), m.nvertices + facets]))

    def reduction(self, eliminated, tied=()) -> tuple[sp.csr_matrix, np.ndarray, np.ndarray]:
        """(T, kept, q_of_dof) of u = T q: each dof but the ``eliminated`` is one q entry, in order;
        the ``tied`` dofs (among the eliminated) all equal ONE more, last, unknown. q_of_dof: the q
        index of each dof, -1 for the eliminated."""
        kept = np.setdiff1d(np.arange(self.n_dofs), eliminated)
        tied = np.asarray(tied, dtype=int)
        rows = np.concatenate([kept, tied])
        cols = np.concatenate([np.arange(kept.size), np.full(tied.size, kept.size)])
        n_q = kept.size + (1 if tied.size else 0)
        T = sp.csr_matrix((np.ones(rows.size), (rows, cols)), shape=(self.n_dofs, n_q))
        q_of_dof = np.full(self.n_dofs, -1)
        q_of_dof[kept] = np.arange(kept.size)
        return T, kept, q_of_dof

    def candidates(self, nodes, q_of_dof, surface_facets, quadrature_order: int) -> dict:
        """The contact candidates ``nodes`` sorted by r, as NodeDofs' fields (with the numbering's
        and T's fields left to the caller); their weight int_S N_i 2 pi r ds [m^2] on ``surface_facets``
        (the boundary mass of scalar P2, one value per node, that turns reactions into pressure)."""
        candidates = nodes[np.argsort(self.node_r[nodes])]
        candidate_q = q_of_dof[self.z_dof[candidates]]
        if np.any(candidate_q < 0):
            raise ValueError("a contact candidate's u_z is constrained: mesh boundaries overlap")
        surface_basis = FacetBasis(self.mesh, ElementTriP2(), facets=surface_facets, intorder=quadrature_order)
        weight = asm(surface_weight, surface_basis)[candidates]
        return {"node_r": self.node_r, "node_z": self.node_z, "r_dof": self.r_dof, "z_dof": self.z_dof,
                "candidate_nodes": candidates, "candidate_r": self.node_r[candidates],
                "candidate_z0": self.node_z[candidates], "candidate_q": candidate_q, "candidate_weight": weight}


def contact_dofs(hemisphere, basis, quadrature_order: int) -> ContactDofs:
    """The plate tie and contact candidates of ``hemisphere`` (meshes.hemisphere.HemisphereMesh,
    boundaries "axis", "top", "surface") on ``basis`` (P2 vector basis of its mesh)."""
    nodes = Numbering(hemisphere.mesh, basis)
    axis_nodes = nodes.facet_nodes(hemisphere.boundaries["axis"])
    top_nodes = nodes.facet_nodes(hemisphere.boundaries["top"])
    surface_nodes = np.setdiff1d(nodes.facet_nodes(hemisphere.boundaries["surface"]), top_nodes)
    T, kept, q_of_dof = nodes.reduction(np.union1d(nodes.r_dof[axis_nodes], nodes.z_dof[top_nodes]),
                                        tied=nodes.z_dof[top_nodes])
    return ContactDofs(**nodes.candidates(surface_nodes, q_of_dof, hemisphere.boundaries["surface"], quadrature_order),
                       T=T, TT=T.T.tocsr(), plate=int(kept.size), kept=kept,
                       top_z_dof=int(nodes.z_dof[top_nodes[0]]))

"""The axisymmetric P2 elements as arrays: strain, internal force and tangent stiffness of any set
of elements by array contractions, scattered into one fixed sparsity pattern of K_q = T^T K T.

The integrals are those of calib.fe.forms (the strain of each basis function from
calib.fe.axisym.strain, the volume weight 2 pi r dA), with the strain-displacement matrix of
every element evaluated once, at construction:

    B[e, g, :, i] = eps(phi_i)(x_eg)                         [1/m]    (4 x 12 per point)
    w[e, g]       = 2 pi r(x_eg) |J_e| w_g                   [m^3]
    eps(u)[e, g]  = B[e, g] u_e                              [-]
    f_e           = sum_g B^T sigma w                        [N]
    K_e           = sum_g B^T C B w                          [N/m]

(Zienkiewicz & Taylor, The Finite Element Method, vol. 1, ch. 5 and 9). scikit-fem's ``asm``
evaluates the bilinear form once per pair of basis functions (144 passes over the quadrature
points per assembly, each recomputing both strains); here a tangent of the plastic elements is
two contractions and one ``bincount`` into the data array of a pattern built once, so no COO
or CSR structure is rebuilt per Newton iteration. tests/test_plasticity.py checks both against
scikit-fem's assembly of the named forms.
"""
from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from calib.fe.axisym import quadrature_radius, radial_weight, strain


class ElementArrays:
    """B and w of every element of ``basis`` (a scikit-fem P2 vector CellBasis) and the sparsity
    pattern of K_q = T^T K T for the reduction ``u = T q`` (calib.fe.dofs: each dof maps to at
    most one unknown)."""

    def __init__(self, basis, T: sp.csr_matrix):
        r = quadrature_radius(basis)
        local = [strain(basis.basis[i][0], r) for i in range(basis.Nbfun)]     # each (4, E, Q)
        self.B = np.ascontiguousarray(np.stack(local, axis=-1).transpose(1, 2, 0, 3))   # (E, Q, 4, 12)
        self.weight = np.asarray(basis.dx) * radial_weight(r)                  # (E, Q) [m^3]
        self.element_dofs = np.ascontiguousarray(basis.element_dofs.T)         # (E, 12)
        self.n_dofs = int(basis.N)
        self._basis, self._gradient, self._gradient_weighted = basis, None, None

        T = sp.csr_matrix(T)
        counts = np.diff(T.indptr)
        if counts.max(initial=0) > 1 or not np.all(T.data == 1.0):
            raise ValueError("ElementArrays needs a reduction u = T q mapping each dof to at most one unknown")
        q_of_dof = np.full(T.shape[0], -1)
        q_of_dof[counts == 1] = T.indices[T.indptr[:-1][counts == 1]]
        self.n_q = int(T.shape[1])
        q = q_of_dof[self.element_dofs]                                        # (E, 12)
        rows = np.broadcast_to(q[:, :, None], q.shape + (q.shape[1],))
        cols = np.broadcast_to(q[:, None, :], rows.shape)
        self._kept = (rows >= 0) & (cols >= 0)                                 # (E, 12, 12)
        keys = rows.astype(np.int64) * self.n_q + cols
        pattern = np.unique(keys[self._kept])
        self.indptr = np.searchsorted(pattern // self.n_q, np.arange(self.n_q + 1)).astype(np.int32)
        self.indices = (pattern % self.n_q).astype(np.int32)
        self.nnz = int(pattern.size)
        # position of each element entry in the pattern's data array (-1: an eliminated dof)
        self._position = np.where(self._kept, np.searchsorted(pattern, keys), -1)
        self._restriction_key, self._restriction = None, None

    # ------------------------------------------------------------------ fields
    def strain(self, displacement) -> np.ndarray:
        """Strain at the quadrature points, (E, Q, 4) [-], of the dof vector [m]."""
        return np.matmul(self.B, np.asarray(displacement)[self.element_dofs][:, None, :, None])[..., 0]

    @property
    def gradient(self) -> np.ndarray:
        """G (E, Q, 5, 12) [1/m]: the displacement gradient [du_r/dR, du_r/dZ, du_z/dR, du_z/dZ, u_r/R]
        of each basis function at the quadrature points (the finite-strain kinematics,
        calib.fe.log_strain), built on first use."""
        if self._gradient is None:
            r = quadrature_radius(self._basis)
            local = []
            for i in range(self._basis.Nbfun):
                phi = self._basis.basis[i][0]
                local.append(np.array([phi.grad[0, 0], phi.grad[0, 1], phi.grad[1, 0], phi.grad[1, 1], phi[0] / r]))
            self._gradient = np.ascontiguousarray(np.stack(local, axis=-1).transpose(1, 2, 0, 3))
        return self._gradient

    def internal_force(self, stress, elements, matrix=None) -> np.ndarray:
        """f_i = sum over ``elements`` of int eps(phi_i) . sigma 2 pi r dA [N] (all dofs); ``stress``
        (len(elements), Q, 4) [Pa]. ``matrix``: another operator than B (all elements), e.g.
        :attr:`gradient` with the first Piola stress (len(elements), Q, 5)."""
        stress_w = (np.asarray(stress) * self.weight[elements][:, :, None]).reshape(len(self.element_dofs[elements]), -1)
        B = (self.B if matrix is None else matrix)[elements]
        local = np.matmul(stress_w[:, None, :], B.reshape(B.shape[0], -1, B.shape[-1]))[:, 0, :]
        return np.bincount(self.element_dofs[elements].ravel(), local.ravel(), minlength=self.n_dofs)

    def stiffness_data(self, tangent, elements, matrix=None) -> np.ndarray:
        """Data array (on :meth:`matrix`'s pattern) of K_q from ``elements`` only, with the material
        tangent ``tangent`` (len(elements), Q, 4, 4) [Pa]: sum_g B^T C B w [N/m]. ``matrix``: another
        operator than B, e.g. :attr:`gradient` with dP/dF (len(elements), Q, 5, 5)."""
        B = (self.B if matrix is None else matrix)[elements]
        n, n_qp, n_strain, n_local = B.shape
        C_B = np.matmul(tangent, B).reshape(n, n_qp * n_strain, n_local)               # C B per point
        if matrix is not None and matrix is self._gradient and isinstance(elements, slice) and elements == slice(None):
            # the finite strain's every-element tangent: G^T w, formed once
            if self._gradient_weighted is None:
                self._gradient_weighted = np.ascontiguousarray(
                    (B * self.weight[:, :, None, None]).reshape(n, n_qp * n_strain, n_local).transpose(0, 2, 1))
            B_wT = self._gradient_weighted
        else:
            B_wT = (B * self.weight[elements][:, :, None, None]).reshape(n, n_qp * n_strain, n_local).transpose(0, 2, 1)
        local = np.matmul(B_wT, C_B)                            # (n, 12, 12): sum over points
        kept = self._kept[elements]
        return np.bincount(self._position[elements][kept], local[kept], minlength=self.nnz)

    def matrix(self, data) -> sp.csr_matrix:
        """K_q (n_q x n_q) with ``data`` on the fixed pattern."""
        return sp.csr_matrix((data, self.indices, self.indptr), shape=(self.n_q, self.n_q))

    def restricted(self, data, free: np.ndarray) -> sp.csr_matrix:
        """K_q[free][:, free] without slicing: the selection of the data array is computed once
        per ``free`` set and reused while it repeats (the Newton iterations of one active set)."""
        key = free.tobytes()
        if key != self._restriction_key:
            numbered = self.matrix(np.arange(1, self.nnz + 1, dtype=float))[free][:, free]
            self._restriction = (numbered.data.astype(np.int64) - 1, numbered.indices, numbered.indptr,
                                 numbered.shape)
            self._restriction_key = key
        select, indices, indptr, shape = self._restriction
        return sp.csr_matrix((np.asarray(data)[select], indices, indptr), shape=shape)

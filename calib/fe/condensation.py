"""Static condensation of an elastic body onto some of its dofs, applied outside the Newton loop.

An elastic body without loads of its own, with stiffness K [N/m] over its other dofs i and the
retained dofs m (for calib.fe.two_body: the u_z of the counter-body's contact surface), has

    u_i = -X u_m,   X = K_ii^-1 K_im              [-]
    f_m = S_m u_m,  S_m = K_mm - K_mi X           [N/m]

exactly (Guyan 1965, AIAA J. 3, 380: exact in statics for a linear body). Both are dense:
S_m is n_m x n_m, X is n_i x n_m (n_m = 211, n_i = 15,800 on the default calibration mesh of the
aluminium sphere of R = 0.1 m on a steel flat: 3.3e6 entries).

Where each enters the two-body Newton iteration, and why (that mesh, 11,900 unknowns; times
measured on a loaded machine, so their ratios matter):

* S_m stays in the tangent, a dense block of the sparse K_q, factorised with the rest. The sparse
  LDL^T (AMD ordering) eliminates the 211-node clique last: a factorisation with it costs 1.11
  times one with only its diagonal, a numeric refactorisation 1.06 times. A Woodbury form would
  need K_q without S_m to be regular in m, which it is not (the master u_z have no other
  stiffness); a Schur complement on m needs K_ss^-1 K_sm, a solve per master u_z coupled to the
  sphere (up to n_m) per factorisation, to save those 11 %.
* X stays out of Newton. The iterate carries the sphere's dofs and the master u_z only, the
  counter-body's internal force on them is S_m u_m (``stiffness``), and ``fill`` puts u_i = -X u_m
  into the displacement once per converged step: one dense product (n_i n_m multiply-adds). X in
  Newton's reduction u = T q adds two sparse products with 3.3e6 entries to every iteration
  (T q and T^T f: a fifth of the load paths' time on that mesh).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from calib.fe.linsolve import factorize


@dataclass(frozen=True, eq=False)
class CondensedBody:
    """A linear body condensed onto the dofs ``master`` (module docstring).

    interior: the body's other unknown dofs; master: the retained dofs (indices into the full dof
    vector); X (n_i, n_m) [-]; S (n_m, n_m) [N/m], symmetric; elements: the body's elements.
    """

    interior: np.ndarray
    master: np.ndarray
    X: np.ndarray = field(repr=False)
    S: np.ndarray = field(repr=False)
    elements: np.ndarray = field(repr=False)

    @classmethod
    def of(cls, K: sp.csr_matrix, interior, master, elements, linear_solver: str | None = None) -> "CondensedBody":
        """Condense the body whose stiffness rows and columns ``interior`` + ``master`` of ``K`` [N/m]
        are (its other dofs constrained or absent)."""
        K_ii = K[interior][:, interior].tocsr()
        K_im = K[interior][:, master].toarray()
        X = np.ascontiguousarray(factorize(K_ii, linear_solver).solve(K_im))
        S = K[master][:, master].toarray() - K[master][:, interior] @ X
        return cls(interior=np.asarray(interior), master=np.asarray(master), X=X, S=0.5 * (S + S.T),
                   elements=np.asarray(elements))

    def fill(self, u: np.ndarray) -> np.ndarray:
        """``u`` [m] with the body's interior dofs set from its master dofs (in place)."""
        u[self.interior] = -(self.X @ u[self.master])
        return u

    def stiffness(self, positions, n: int) -> sp.csr_matrix:
        """S_m as an n x n sparse matrix on the rows and columns ``positions`` of the master dofs."""
        rows, cols = np.meshgrid(positions, positions, indexing="ij")
        return sp.csr_matrix((self.S.ravel(), (rows.ravel(), cols.ravel())), shape=(n, n))

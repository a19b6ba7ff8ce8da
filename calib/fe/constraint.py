"""The contact constraint of one step: what an active set prescribes, for the one active-set loop.

Frictionless unilateral contact at the contact candidates i (surface nodes of body 1, sorted by r):

    g_i(q) >= 0,   lambda_i >= 0,   g_i lambda_i = 0                       [m], [N]

Two constraints share one interface (``gaps``, ``system``, ``reactions``, ``contact_force``), so
calib.fe.contact_loop.solve_contact runs one loop for every configuration:

  * ``RigidFlat``: the rigid frictionless flat z = 0, g_i = z0_i + q_z,i. An active node's u_z is
    prescribed, q_z,i = -z0_i, as a Dirichlet constraint of Newton (its first increment, an elastic
    predictor spread over the body).
  * ``MortarContact``: a deformable counter-body, the dual mortar gap g_i = q_z1,i - G_i q + g0_i of
    calib.fe.contact_pair (which says why mortar). An active node's u_z is eliminated as the affine
    function of the master's, q = S p + d (calib.fe.contact_pair.active_set_reduction); Newton runs
    on p with K_p = S^T K_q S, r_p = S^T r_q, the gap closure a constrained unknown theta = 1.

In displacement control the plate unknown is prescribed too (-alpha). Forces [N], lengths [m].
References: Wriggers 2006, Computational Contact Mechanics, ch. 6; Puso & Laursen 2004.
"""
from __future__ import annotations

from typing import Callable, NamedTuple

import numpy as np
import scipy.sparse as sp

from calib.fe.contact_pair import active_set_reduction


class ActiveSetSystem(NamedTuple):
    """Newton's problem for one active set: ``problem`` (what calib.fe.newton.solve_newton reads),
    its ``start`` unknowns, the ``constrained`` unknowns and their ``target`` values, the ``free``
    mask, and ``to_q`` (Newton's unknowns -> the solver's q)."""

    problem: object
    start: np.ndarray
    constrained: np.ndarray
    target: np.ndarray
    free: np.ndarray
    to_q: Callable[[np.ndarray], np.ndarray]


def _identity(q):
    return q


class RigidFlat:
    """The rigid frictionless flat z = 0 (module docstring). ``candidate_q``: q index of each
    candidate's u_z; ``candidate_z0`` [m]: its initial gap (its height); ``candidate_r`` [m],
    ``candidate_weight`` [m^2]: its radius and int_S N_i 2 pi r ds (pressure recovery)."""

    def __init__(self, candidate_q, candidate_z0, candidate_r, candidate_weight):
        self.candidate_q, self.candidate_z0 = candidate_q, candidate_z0
        self.candidate_r, self.candidate_weight = candidate_r, candidate_weight

    def gaps(self, q) -> np.ndarray:
        """g_i = z0_i + q_z,i [m]."""
        return self.candidate_z0 + q[self.candidate_q]

    def system(self, solver, active, q_from, control: str, target: float) -> ActiveSetSystem:
        """The active nodes' u_z (and the plate's, in displacement control) prescribed; Newton on q."""
        constrained = self.candidate_q[active]
        constrained_target = -self.candidate_z0[active]
        if control == "displacement":
            constrained = np.append(constrained, solver.plate)
            constrained_target = np.append(constrained_target, -target)
        free = np.ones(q_from.size, dtype=bool)
        free[constrained] = False
        return ActiveSetSystem(solver, q_from.copy(), constrained, constrained_target, free, _identity)

    def reactions(self, solver, newton) -> np.ndarray:
        """lambda_i [N] at every candidate: the residual on its u_z (T^T f_int + M a)."""
        return newton.residual[self.candidate_q]

    def contact_force(self, reaction, n_q: int) -> np.ndarray:
        """f_c in q [N]: lambda_i on the candidates' u_z."""
        force = np.zeros(n_q)
        force[self.candidate_q] = reaction
        return force


class _Affine:
    """u = T (S p + d): what ``problem.T @ p`` means to calib.fe.newton for one active set."""

    def __init__(self, T, S, d):
        self.T, self.S, self.d = T, S, d

    def __matmul__(self, p):
        return self.T @ (self.S @ p + self.d)


class _Chain:
    """S^T T^T f: the reduced residual of the full internal force."""

    def __init__(self, ST, TT):
        self.ST, self.TT = ST, TT

    def __matmul__(self, f):
        return self.ST @ (self.TT @ f)


class _Reduced:
    """The solver restricted to one active set's q = S p + d, as calib.fe.newton.solve_newton sees a
    solver: assembly and factorisation through S; the plate (the last q entry) is p's next to last."""

    def __init__(self, solver, S, d, pattern: bytes):
        self.solver, self.S, self.ST, self.pattern = solver, S, S.T.tocsr(), pattern
        self.T, self.TT = _Affine(solver.T, S, d), _Chain(self.ST, solver.TT)
        self.plate = S.shape[1] - 2
        for name in ("stiffness_scale", "force_floor", "max_newton_iterations", "residual_tolerance"):
            setattr(self, name, getattr(solver, name))

    def assemble(self, displacement, committed):
        f_int, tangent, stress, trial = self.solver.assemble(displacement, committed)
        return f_int, lambda: (self.ST @ tangent() @ self.S).tocsr(), stress, trial

    def factor(self, K_p, free, key):
        return self.solver.factor(K_p, free, key, self.pattern)


class MortarContact:
    """A deformable counter-body through the dual mortar gap (module docstring). ``gap``: the
    calib.fe.contact_pair.MortarGap; ``candidate_q``: q index of each slave candidate's u_z;
    ``G_q``: the rows G_i in q numbering (candidates x n_q)."""

    def __init__(self, gap, candidate_q, G_q):
        self.gap, self.candidate_q, self.G_q = gap, candidate_q, G_q
        self.candidate_r, self.candidate_weight, self.candidate_g0 = gap.r, gap.weight, gap.g0

    @classmethod
    def in_unknowns(cls, gap, q_of_dof, z_dof, n_q: int, refusal: str) -> "MortarContact":
        """The mortar gap ``gap`` in the ``n_q`` unknowns q (``q_of_dof``: the q index of each dof, -1
        for an eliminated one; ``z_dof``: each node's u_z dof); ValueError(``refusal``) when a slave
        or master u_z is not an unknown (the contact zone reaches a held or loaded face)."""
        candidate_q, master_q = q_of_dof[z_dof[gap.nodes]], q_of_dof[z_dof[gap.master_nodes]]
        if np.any(candidate_q < 0) or np.any(master_q < 0):
            raise ValueError(refusal)
        G = gap.G.tocoo()
        return cls(gap, candidate_q, sp.csr_matrix((G.data, (G.row, master_q[G.col])), shape=(gap.nodes.size, n_q)))

    def gaps(self, q) -> np.ndarray:
        """g_i = q_z1,i - G_i q + g0_i [m]."""
        return q[self.candidate_q] - self.G_q @ q + self.candidate_g0

    def system(self, solver, active, q_from, control: str, target: float) -> ActiveSetSystem:
        """Newton on p (q = S p + d, the active slaves eliminated), theta (p's last) held at 1, the
        plate (p's next to last) prescribed in displacement control."""
        S, d, free_q = active_set_reduction(self.candidate_q, self.G_q, self.candidate_g0, active, q_from)
        reduced = _Reduced(solver, S, d, str(control).encode() + active.tobytes())
        n_p = S.shape[1]
        displacement = control == "displacement"
        constrained = np.array([n_p - 1] + ([reduced.plate] if displacement else []))
        constrained_target = np.array([1.0] + ([-target] if displacement else []))
        free = np.ones(n_p, dtype=bool)
        free[constrained] = False
        return ActiveSetSystem(reduced, np.append(q_from[free_q], 0.0), constrained, constrained_target, free,
                               lambda p: S @ p + d)

    def reactions(self, solver, newton) -> np.ndarray:
        """lambda_i [N] at every candidate: the q residual (T^T f_int + M a) on its u_z."""
        return (solver.TT @ newton.f_int)[self.candidate_q]

    def contact_force(self, reaction, n_q: int) -> np.ndarray:
        """f_c in q [N]: lambda_i on the slaves' u_z, -G_ik lambda_i on the masters'."""
        force = np.zeros(n_q)
        force[self.candidate_q] = reaction
        return force - self.G_q.T @ reaction

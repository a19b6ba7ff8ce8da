"""Frictionless contact between two meshed bodies: the dual mortar gap of each slave node.

Choice: a segment-to-segment (mortar) gap with dual (biorthogonal) test functions, not a
node-to-segment projection. Body 1's surface is the slave side (its nodes carry the contact
unknowns), body 2's the master. The gap is measured along z (the contact normal of a small-strain,
a << R contact, as in Hertz's theory and in the rigid-flat solver, calib.fe.dofs), at the same r:

    g(r) = z1(r) + u_z1(r) - z2(r) - u_z2(r)                                     [m]

and tested against the dual function psi_i of each slave node on the projected surface
(weight 2 pi r dr). On each slave facet psi_a = sum_b A_ab N_b with A = D M^-1, M_ab = int N_a N_b
2 pi r dr the facet's weighted mass and D its row sums, so that int psi_a N_b 2 pi r dr =
delta_ab w_a and sum_a psi_a = 1 (Wohlmuth 2000, SIAM J. Numer. Anal. 38, 989). Then

    w_i g_i = int psi_i g 2 pi r dr,   w_i = int N_i 2 pi r dr                   [m^3], [m^2]
    g_i     = z1_i + u_z1,i - (int psi_i z2 2 pi r dr + sum_k M_ik u_z2,k) / w_i
    M_ik    = int psi_i N2_k 2 pi r dr                                           [m^2]

exactly (the slave part is diagonal by biorthogonality, no lumping). The Signorini conditions
hold node by node on g_i >= 0 and lambda_i >= 0 (lambda_i the contact force on slave node i,
-M_ik lambda_i / w_i on master node k), so the active set of calib.fe.active_set applies
unchanged, and an active node's u_z is an affine function of the master's (eliminated exactly,
no multiplier unknowns and no penalty):

    u_z1,i = sum_k G_ik u_z2,k - g0_i,   G_ik = M_ik / w_i,   g0_i = z1_i - int psi_i z2 2 pi r dr / w_i

Why this and not node-to-segment: a one-pass node-to-segment constraint transmits the forces
lambda_i to the master through the master shape functions at the slave nodes, which does not
pass the contact patch test on non-matching meshes (Taylor & Papadopoulos 1991, Int. J. Numer.
Methods Eng. 31, 1141). The mortar weights do (Puso & Laursen 2004, Comput. Methods Appl. Mech.
Eng. 193, 601): under a uniform pressure p, lambda_i = p w_i and the master receives
sum_i M_ik p = p int N2_k 2 pi r dr, its own consistent load, because the psi_i sum to one. On
matching meshes (two identical spheres) G is the identity: node-to-node, the rigid-flat
problem's own constraint. The integrals are exact up to round-off: Gauss quadrature on the
segments between the union of both sides' facet ends, where both integrands are smooth. At the
pole the P2 weight w_i vanishes (the factor r); there the gap is collocated (g at r = 0).

The measure is the projected area 2 pi r dr (z is the normal): the pressure lambda_i / w_i is
the force per projected area, which differs from the force per surface area by the factor
cos(theta) = 1 - O((a/R)^2) (below 1.3e-3 for a < 0.05 R).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

GAUSS_POINTS = 4  # per segment: N_i N2_k r is a degree-5 polynomial in r on straight facets


@dataclass(frozen=True)
class SurfaceFacets:
    """P2 boundary facets of one body along r: ``nodes`` (n, 3) = (start, end, mid-side), sorted by
    r, with ``r`` and ``z`` (n, 3) their coordinates [m]."""

    nodes: np.ndarray
    r: np.ndarray
    z: np.ndarray

    @classmethod
    def of(cls, mesh, facets) -> "SurfaceFacets":
        ends = mesh.facets[:, facets]
        r_end = mesh.doflocs[0][ends]
        swap = r_end[0] > r_end[1]
        start, end = np.where(swap, ends[1], ends[0]), np.where(swap, ends[0], ends[1])
        nodes = np.stack([start, end, mesh.nvertices + np.asarray(facets)], axis=1)
        order = np.argsort(mesh.doflocs[0][nodes[:, 0]])
        nodes = nodes[order]
        return cls(nodes=nodes, r=mesh.doflocs[0][nodes], z=mesh.doflocs[1][nodes])

    def locate(self, r) -> np.ndarray:
        """Index of the facet whose r range holds each r [m] (clipped to the first/last)."""
        return np.clip(np.searchsorted(self.r[:, 0], r, side="right") - 1, 0, len(self.nodes) - 1)

    def parameter(self, facet, r) -> np.ndarray:
        """xi in [0, 1] on ``facet`` where the isoparametric r(xi) equals r (Newton on the quadratic)."""
        r0, r1, rm = self.r[facet, 0], self.r[facet, 1], self.r[facet, 2]
        xi = np.clip((r - r0) / (r1 - r0), 0.0, 1.0)
        for _ in range(30):
            value = r0 * (1 - xi) * (1 - 2 * xi) + r1 * xi * (2 * xi - 1) + rm * 4 * xi * (1 - xi) - r
            slope = r0 * (4 * xi - 3) + r1 * (4 * xi - 1) + rm * (4 - 8 * xi)
            step = value / slope
            xi = xi - step
            if np.all(np.abs(step) < 1e-15):
                break
        return np.clip(xi, 0.0, 1.0)


def shape(xi) -> np.ndarray:
    """P2 shape functions on a facet (start, end, mid-side) at xi, shaped (3, ...)."""
    xi = np.asarray(xi)
    return np.stack([(1 - xi) * (1 - 2 * xi), xi * (2 * xi - 1), 4 * xi * (1 - xi)])


@dataclass(frozen=True)
class MortarGap:
    """The lumped mortar gap of the slave candidates (module docstring).

    nodes, r, z1: the slave candidate nodes sorted by r, their r and z [m]
    weight: w_i [m^2]; G (n_candidates x n_master, csr) [-]; g0 [m]: the initial gap
    master_nodes: the master nodes G's columns refer to
    """

    nodes: np.ndarray
    r: np.ndarray
    z1: np.ndarray
    weight: np.ndarray
    G: sp.csr_matrix
    g0: np.ndarray
    master_nodes: np.ndarray


def mortar_gap(mesh, slave_facets, master_facets, r_limit: float) -> MortarGap:
    """The lumped mortar gap of ``mesh``'s slave surface facets against the master's, for the slave
    facets within r <= ``r_limit`` [m] (which the master surface must cover)."""
    slave, master = SurfaceFacets.of(mesh, slave_facets), SurfaceFacets.of(mesh, master_facets)
    keep = slave.r[:, 1] <= r_limit * (1 + 1e-12)
    slave = SurfaceFacets(slave.nodes[keep], slave.r[keep], slave.z[keep])
    r_end = slave.r[-1, 1]
    if master.r[-1, 1] < r_end:
        raise ValueError(f"the counter-body's surface (to r = {master.r[-1, 1]:g} m) does not cover the sphere's "
                         f"contact candidates (to r = {r_end:g} m)")
    nodes = np.unique(slave.nodes)
    nodes = nodes[np.argsort(mesh.doflocs[0][nodes], kind="stable")]
    index = np.full(mesh.doflocs.shape[1], -1)
    index[nodes] = np.arange(nodes.size)
    master_nodes = np.unique(master.nodes[master.r[:, 0] <= r_end])
    master_index = np.full(mesh.doflocs.shape[1], -1)
    master_index[master_nodes] = np.arange(master_nodes.size)

    # segments between the union of both sides' facet ends, Gauss points on each
    breaks = np.unique(np.concatenate([slave.r[:, :2].ravel(), master.r[:, :2].ravel()]))
    breaks = breaks[breaks <= r_end]
    x, wx = np.polynomial.legendre.leggauss(GAUSS_POINTS)
    a, b = breaks[:-1, None], breaks[1:, None]
    r = (0.5 * (a + b) + 0.5 * (b - a) * x).ravel()
    dr = (0.5 * (b - a) * wx).ravel()
    middle = np.repeat(0.5 * (breaks[:-1] + breaks[1:]), GAUSS_POINTS)
    fs, fm = slave.locate(middle), master.locate(middle)
    Ns = shape(slave.parameter(fs, r))                       # (3, n_points)
    # the dual (biorthogonal) test functions psi_a = A_ab N_b of each slave facet, A = D M^-1
    # with M the facet's weighted mass and D its row sums: int psi_a N_b = delta_ab w_a, sum psi = 1
    facet_mass = np.zeros((len(slave.nodes), 3, 3))
    np.add.at(facet_mass, fs, np.einsum("ap,bp,p->pab", Ns, Ns, 2 * np.pi * r * dr))
    A = np.einsum("fa,fab->fab", facet_mass.sum(axis=2), np.linalg.inv(facet_mass))
    psi = np.einsum("pab,bp->ap", A[fs], Ns)
    Nm = shape(master.parameter(fm, r))
    z2 = np.sum(Nm * master.z[fm].T, axis=0)
    measure = 2 * np.pi * r * dr
    rows = index[slave.nodes[fs]].T                           # (3, n_points)
    cols = master_index[master.nodes[fm]].T
    n = nodes.size
    weight = np.bincount(rows.ravel(), (Ns * measure).ravel(), minlength=n)
    gz = np.bincount(rows.ravel(), (psi * z2 * measure).ravel(), minlength=n)
    M = sp.coo_matrix(((psi[:, None, :] * Nm[None, :, :] * measure).ravel(),
                       (np.broadcast_to(rows[:, None, :], (3, 3, r.size)).ravel(),
                        np.broadcast_to(cols[None, :, :], (3, 3, r.size)).ravel())),
                      shape=(n, master_nodes.size)).tocsr()
    node_r, node_z = mesh.doflocs[0][nodes], mesh.doflocs[1][nodes]
    lumped = weight > 1e-9 * weight.max()
    G = sp.diags(np.where(lumped, 1.0 / np.where(lumped, weight, 1.0), 0.0)) @ M
    g0 = node_z - np.where(lumped, gz / np.where(lumped, weight, 1.0), 0.0)
    # collocation where the weight vanishes (the pole): g = z1 + u_z1 - (z2 + u_z2) at r_i
    collocated = np.flatnonzero(~lumped)
    if collocated.size:
        fc = master.locate(node_r[collocated])
        Nc = shape(master.parameter(fc, node_r[collocated]))
        G = G.tolil()
        for j, i in enumerate(collocated):
            G[i, :] = 0.0
            for k in range(3):
                G[i, master_index[master.nodes[fc[j], k]]] += Nc[k, j]
        g0[collocated] = node_z[collocated] - np.sum(Nc * master.z[fc].T, axis=0)
    return MortarGap(nodes=nodes, r=node_r, z1=node_z, weight=weight, G=sp.csr_matrix(G), g0=g0,
                     master_nodes=master_nodes)


def active_set_reduction(candidate_q: np.ndarray, G_q, candidate_g0: np.ndarray, active: np.ndarray,
                         q_from: np.ndarray):
    """(S, d, free_q): q = S p + d eliminates the active slaves' u_z for one active set.

    p = (the q entries that are not active slaves' u_z, then theta). An active slave follows
    u_z1,i = G_i u_z2 + (1 - theta) o_i - theta g0_i, o_i = q_i - G_i q its offset in ``q_from``
    (``candidate_q`` the slaves' q indices, ``G_q`` the rows G_i in q numbering, ``candidate_g0``
    the g0_i [m]): theta = 0 is ``q_from`` itself and theta = 1 closes the gaps. Theta, held at 1,
    enters Newton's first solve as an increment spread over both bodies (an elastic predictor),
    never as a jump of the contact nodes alone, which a plastic body would read as flow.
    """
    n_q = q_from.size
    slave_q = candidate_q[active]
    free_q = np.ones(n_q, dtype=bool)
    free_q[slave_q] = False
    n_free = int(free_q.sum())
    p_of_q = np.full(n_q, -1)
    p_of_q[free_q] = np.arange(n_free)
    G_active = G_q[np.flatnonzero(active)]
    G = G_active.tocoo()
    offset = q_from[slave_q] - G_active @ q_from
    rows = np.concatenate([np.flatnonzero(free_q), slave_q[G.row], slave_q])
    cols = np.concatenate([np.arange(n_free), p_of_q[G.col], np.full(slave_q.size, n_free)])
    data = np.concatenate([np.ones(n_free), G.data, -candidate_g0[active] - offset])
    S = sp.csr_matrix((data, (rows, cols)), shape=(n_q, n_free + 1))
    d = np.zeros(n_q)
    d[slave_q] = offset
    return S, d, free_q

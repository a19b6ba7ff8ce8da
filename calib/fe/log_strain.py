"""Axisymmetric finite-strain kinematics in the Lagrangian logarithmic (Hencky) strain.

The deformation gradient of an axisymmetric body without torsion at a point of the reference
section (R, Z), from the displacement (u_r, u_z):

    F = [[1 + du_r/dR, du_r/dZ, 0], [du_z/dR, 1 + du_z/dZ, 0], [0, 0, 1 + u_r / R]]        [-]

stored as its five components [F_rR, F_rZ, F_zR, F_zZ, F_tt] (the displacement gradient H = F - I
likewise, calib.fe.element_arrays.ElementArrays.gradient). The right Cauchy-Green tensor C = F^T F has
the r-z block and the hoop entry F_tt^2, each an eigen-direction of its own (the hoop axis is one):
the 2x2 block is diagonalised in closed form, C = sum_i lambda_i N_i (x) N_i, and the Lagrangian
Hencky strain is

    E = 1/2 ln C = sum_i 1/2 ln(lambda_i) N_i (x) N_i                                      [-]

given to the material in the project's Voigt convention [E_RR, E_ZZ, E_tt, 2 E_RZ] (calib.fe.material).
The material's stress T = d psi / d E [Pa] (the small-strain update unchanged: its strain is E, its
plastic strain the Lagrangian plastic log strain E_p) is the stress conjugate to E, so
T : dE = S : dC / 2 gives the second Piola-Kirchhoff stress by the Daleckii-Krein derivative of the
logarithm, in the eigenbasis of C,

    S'_ij = 2 f1(lambda_i, lambda_j) T'_ij,  f1 = (1/2 ln lambda_i - 1/2 ln lambda_j) / (lambda_i - lambda_j)
            (1 / (2 lambda_i) for i = j)                                                   [Pa]

and P = F S (first Piola-Kirchhoff, the internal force int P : Grad N 2 pi R dA0), tau = F S F^T
(Kirchhoff), sigma = tau / det F (Cauchy). Equivalently P = (dE/dF)^T T, which the tests check.

This is additive plasticity in the Lagrangian log strain (Miehe, Apel & Lambrecht 2002, Comput.
Methods Appl. Mech. Eng. 191, 5383; Papadopoulos & Lu 1998): E_e = E - E_p with E_p stored in the
reference frame, so the stress is objective by construction (a rigid rotation leaves C, E and T
unchanged and rotates P). For isotropic elasticity and plastic flow whose principal axes stay those
of the stretch (proportional loading) it coincides with multiplicative J2 plasticity integrated by
the exponential map (Eterovic & Bathe 1990; Simo 1992; de Souza Neto, Peric & Owen 2008, ch. 14, the
small-strain return mapping in log strain); where the principal axes rotate during flow the two
differ at the order of that rotation times the plastic strain.
"""
from __future__ import annotations

import numpy as np

# I in the five-component layout [rR, rZ, zR, zZ, tt] of F = I + H
IDENTITY = np.array([1.0, 0.0, 0.0, 1.0, 1.0])
N_GRADIENT = 5


def _block(F) -> np.ndarray:
    """The r-z block of F (..., 2, 2)."""
    return F[..., :4].reshape(F.shape[:-1] + (2, 2))


def _log_divided_difference(mu1, mu2) -> np.ndarray:
    """f1 = (ln lam1 - ln lam2) / (2 (lam1 - lam2)) of lam_i = 1 + mu_i, 1 / (2 lam) when equal
    (lam1 >= lam2 > 0), without cancellation: log1p(d) / d with d = lam1 / lam2 - 1."""
    d = (mu1 - mu2) / (1.0 + mu2)
    ratio = np.where(d > 0.0, np.log1p(d) / np.where(d > 0.0, d, 1.0), 1.0)
    return 0.5 * ratio / (1.0 + mu2)


class Stretch:
    """The eigen-decomposition of C = F^T F at every point of the displacement gradient ``H`` = F - I
    (..., 5): the eigenvalues lam_i = 1 + mu_i of the r-z block with the rotation Q (columns N_1, N_2),
    the hoop eigenvalue C_tt. C - I = H + H^T + H^T H and ln(1 + mu) are formed from H itself, so the
    strain keeps its relative accuracy however small it is (1 + H would round it off at 1e-16
    absolute). Points whose F is not orientation preserving (det of the block or F_tt <= 0) get NaN,
    which Newton rejects."""

    def __init__(self, H):
        H = np.asarray(H, dtype=float)
        self.H = H
        self.F = H + IDENTITY
        Hb = _block(H)
        M = Hb + np.swapaxes(Hb, -1, -2) + np.swapaxes(Hb, -1, -2) @ Hb       # C - I, r-z block
        m11, m22, m12 = M[..., 0, 0], M[..., 1, 1], M[..., 0, 1]
        Fb = _block(self.F)
        J_block = Fb[..., 0, 0] * Fb[..., 1, 1] - Fb[..., 0, 1] * Fb[..., 1, 0]
        valid = (J_block > 0.0) & (self.F[..., 4] > 0.0)
        mean, radius = 0.5 * (m11 + m22), np.hypot(0.5 * (m11 - m22), m12)
        self.mu1 = np.where(valid, mean + radius, np.nan)
        self.mu2 = np.where(valid, mean - radius, np.nan)
        self.lam1, self.lam2 = 1.0 + self.mu1, 1.0 + self.mu2
        angle = 0.5 * np.arctan2(m12, 0.5 * (m11 - m22))
        c, s = np.cos(angle), np.sin(angle)
        self.Q = np.stack([np.stack([c, -s], axis=-1), np.stack([s, c], axis=-1)], axis=-2)
        self.C_tt = self.F[..., 4] ** 2
        self.J = np.where(valid, J_block * self.F[..., 4], np.nan)

    def hencky(self) -> np.ndarray:
        """E = 1/2 ln C in Voigt form [E_RR, E_ZZ, E_tt, 2 E_RZ] (..., 4) [-]."""
        e = np.stack([0.5 * np.log1p(self.mu1), 0.5 * np.log1p(self.mu2)], axis=-1)
        E = (self.Q * e[..., None, :]) @ np.swapaxes(self.Q, -1, -2)
        return np.stack([E[..., 0, 0], E[..., 1, 1], np.log1p(self.H[..., 4]), 2.0 * E[..., 0, 1]], axis=-1)

    def second_piola(self, T) -> tuple[np.ndarray, np.ndarray]:
        """(S's r-z block (..., 2, 2), S_tt) [Pa] of the stress T (..., 4) [T_RR, T_ZZ, T_tt, T_RZ]
        conjugate to the Hencky strain (module docstring)."""
        T = np.asarray(T, dtype=float)
        Tb = np.stack([np.stack([T[..., 0], T[..., 3]], axis=-1), np.stack([T[..., 3], T[..., 1]], axis=-1)], axis=-2)
        Qt = np.swapaxes(self.Q, -1, -2)
        T_eig = Qt @ Tb @ self.Q
        off = 2.0 * _log_divided_difference(self.mu1, self.mu2)
        weights = np.stack([np.stack([1.0 / self.lam1, off], axis=-1), np.stack([off, 1.0 / self.lam2], axis=-1)],
                           axis=-2)
        return self.Q @ (weights * T_eig) @ Qt, T[..., 2] / self.C_tt

    def first_piola(self, T) -> np.ndarray:
        """P = F S (..., 5) [Pa], components [P_rR, P_rZ, P_zR, P_zZ, P_tt]."""
        S_block, S_tt = self.second_piola(T)
        P_block = _block(self.F) @ S_block
        return np.concatenate([P_block.reshape(P_block.shape[:-2] + (4,)), (self.F[..., 4] * S_tt)[..., None]],
                              axis=-1)

    def cauchy(self, T) -> np.ndarray:
        """sigma = F S F^T / det F (..., 4) [Pa] in the spatial r-z-t frame, [s_rr, s_zz, s_tt, s_rz]."""
        S_block, S_tt = self.second_piola(T)
        Fb = _block(self.F)
        tau = Fb @ S_block @ np.swapaxes(Fb, -1, -2)
        return np.stack([tau[..., 0, 0], tau[..., 1, 1], self.C_tt * S_tt, tau[..., 0, 1]], axis=-1) / self.J[..., None]


def hencky_strain(H) -> np.ndarray:
    """E = 1/2 ln(F^T F) in Voigt form (..., 4) [-] of the displacement gradient H = F - I (..., 5)."""
    return Stretch(H).hencky()


# central-difference step on the components of F [-]: truncation ~ h^2, round-off ~ 1e-16 / h, both
# below 1e-9 of the tangent
GRADIENT_STEP = 1e-6


def kinematic_derivatives(H, T, step: float = GRADIENT_STEP) -> tuple[np.ndarray, np.ndarray]:
    """(dE/dF (..., 4, 5), d P/d F at fixed T (..., 5, 5)) at the displacement gradient H = F - I
    (..., 5) by central differences over its five components, the material left out (its own consistent tangent dT/dE closes the chain:
    dP/dF = dP/dF|_T + (dE/dF)^T C_alg dE/dF, since P = (dE/dF)^T T)."""
    H = np.asarray(H, dtype=float)
    # the ten perturbed gradients in one evaluation (+h e_k, then -h e_k, on a leading axis)
    shifts = step * np.concatenate([np.eye(N_GRADIENT), -np.eye(N_GRADIENT)])
    perturbed = Stretch(H + shifts.reshape((2 * N_GRADIENT,) + (1,) * (H.ndim - 1) + (N_GRADIENT,)))
    E, P = perturbed.hencky(), perturbed.first_piola(T)
    dE = np.moveaxis((E[:N_GRADIENT] - E[N_GRADIENT:]) / (2.0 * step), 0, -1)
    dP = np.moveaxis((P[:N_GRADIENT] - P[N_GRADIENT:]) / (2.0 * step), 0, -1)
    return dE, dP

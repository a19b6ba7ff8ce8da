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
        h0, h1, h2, h3 = H[..., 0], H[..., 1], H[..., 2], H[..., 3]
        # C - I = H + H^T + H^T H, r-z block, componentwise
        m11, m22 = 2.0 * h0 + h0 * h0 + h2 * h2, 2.0 * h3 + h1 * h1 + h3 * h3
        m12 = h1 + h2 + h0 * h1 + h2 * h3
        F = self.F
        J_block = F[..., 0] * F[..., 3] - F[..., 1] * F[..., 2]
        valid = (J_block > 0.0) & (F[..., 4] > 0.0)
        mean, radius = 0.5 * (m11 + m22), np.hypot(0.5 * (m11 - m22), m12)
        self.mu1 = np.where(valid, mean + radius, np.nan)
        self.mu2 = np.where(valid, mean - radius, np.nan)
        self.lam1, self.lam2 = 1.0 + self.mu1, 1.0 + self.mu2
        angle = 0.5 * np.arctan2(m12, 0.5 * (m11 - m22))
        self.c, self.s = np.cos(angle), np.sin(angle)                 # Q = [[c, -s], [s, c]]
        self.C_tt = F[..., 4] ** 2
        self.J = np.where(valid, J_block * F[..., 4], np.nan)

    @property
    def Q(self) -> np.ndarray:
        """The rotation (..., 2, 2) whose columns are the eigenvectors N_1, N_2 of the r-z block of C."""
        c, s = self.c, self.s
        return np.stack([np.stack([c, -s], axis=-1), np.stack([s, c], axis=-1)], axis=-2)

    def hencky(self) -> np.ndarray:
        """E = 1/2 ln C in Voigt form [E_RR, E_ZZ, E_tt, 2 E_RZ] (..., 4) [-]."""
        e00, e01, e11 = _from_eigenbasis(self.c, self.s, 0.5 * np.log1p(self.mu1), 0.0, 0.5 * np.log1p(self.mu2))
        return np.stack([e00, e11, np.log1p(self.H[..., 4]), 2.0 * e01], axis=-1)

    def _second_piola(self, T):
        """(S_RR, S_RZ, S_ZZ, S_tt) [Pa] of the stress T (..., 4) conjugate to E (module docstring)."""
        T = np.asarray(T, dtype=float)
        t00, t01, t11 = _to_eigenbasis(self.c, self.s, T[..., 0], T[..., 3], T[..., 1])
        off = 2.0 * _log_divided_difference(self.mu1, self.mu2)
        return _from_eigenbasis(self.c, self.s, t00 / self.lam1, off * t01, t11 / self.lam2) + (T[..., 2] / self.C_tt,)

    def second_piola(self, T) -> tuple[np.ndarray, np.ndarray]:
        """(S's r-z block (..., 2, 2), S_tt) [Pa] of the stress T (..., 4) [T_RR, T_ZZ, T_tt, T_RZ]
        conjugate to the Hencky strain (module docstring)."""
        s00, s01, s11, s_tt = self._second_piola(T)
        return np.stack([np.stack([s00, s01], axis=-1), np.stack([s01, s11], axis=-1)], axis=-2), s_tt

    def _first_piola(self, T):
        s00, s01, s11, s_tt = self._second_piola(T)
        F = self.F
        return (F[..., 0] * s00 + F[..., 1] * s01, F[..., 0] * s01 + F[..., 1] * s11,
                F[..., 2] * s00 + F[..., 3] * s01, F[..., 2] * s01 + F[..., 3] * s11, F[..., 4] * s_tt)

    def first_piola(self, T) -> np.ndarray:
        """P = F S (..., 5) [Pa], components [P_rR, P_rZ, P_zR, P_zZ, P_tt]."""
        return np.stack(self._first_piola(T), axis=-1)

    def cauchy(self, T) -> np.ndarray:
        """sigma = F S F^T / det F (..., 4) [Pa] in the spatial r-z-t frame, [s_rr, s_zz, s_tt, s_rz]."""
        p00, p01, p10, p11, _ = self._first_piola(T)
        F = self.F
        tau = (p00 * F[..., 0] + p01 * F[..., 1], p10 * F[..., 2] + p11 * F[..., 3], np.asarray(T)[..., 2],
               p00 * F[..., 2] + p01 * F[..., 3])
        return np.stack(tau, axis=-1) / self.J[..., None]


def hencky_strain(H) -> np.ndarray:
    """E = 1/2 ln(F^T F) in Voigt form (..., 4) [-] of the displacement gradient H = F - I (..., 5)."""
    return Stretch(H).hencky()


def _log_second_divided_difference(x, y) -> np.ndarray:
    """g[x, x, y] of g = 1/2 ln: (g'(x) - g[x, y]) / (x - y) = -(t - ln(1 + t)) / (2 x^2 t^2), t = y / x - 1
    (-1 / (4 x^2) at t = 0), by its series where |t| < 1e-3 (the difference cancels there)."""
    t = (y - x) / x
    small = np.abs(t) < 1e-3
    safe = np.where(small, 1.0, t)
    direct = (safe - np.log1p(safe)) / safe ** 2
    series = 0.5 + t * (-1.0 / 3.0 + t * (0.25 + t * (-0.2 + t * (1.0 / 6.0 - t / 7.0))))
    return -np.where(small, series, direct) / (2.0 * x ** 2)


# the four directions E_k = e_a e_b^T of the r-z block of F (k = rR, rZ, zR, zZ): a and b
_ROW, _COLUMN = np.array([0, 0, 1, 1]), np.array([0, 1, 0, 1])


def _to_eigenbasis(c, s, m00, m01, m11):
    """Q^T M Q of the symmetric 2x2 M, Q = [[c, -s], [s, c]] (componentwise: far faster than a batched matmul)."""
    cc, ss, cs = c * c, s * s, c * s
    return (cc * m00 + 2.0 * cs * m01 + ss * m11, cs * (m11 - m00) + (cc - ss) * m01,
            ss * m00 - 2.0 * cs * m01 + cc * m11)


def _from_eigenbasis(c, s, m00, m01, m11):
    """Q M Q^T of the symmetric 2x2 M."""
    cc, ss, cs = c * c, s * s, c * s
    return (cc * m00 - 2.0 * cs * m01 + ss * m11, cs * (m00 - m11) + (cc - ss) * m01,
            ss * m00 + 2.0 * cs * m01 + cc * m11)


def kinematic_derivatives(H, T, stretch: Stretch | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(dE/dF (..., 4, 5), dP/dF at fixed T (..., 5, 5)) at the displacement gradient H = F - I
    (..., 5) and the stress T (..., 4) conjugate to E, in closed form (the material left out: its
    consistent tangent dT/dE closes the chain, dP/dF = dP/dF|_T + (dE/dF)^T C_alg dE/dF).

    In the eigenbasis of C (Q, the r-z block; the hoop axis its own), with g = 1/2 ln and dC =
    dF^T F + F^T dF, the Daleckii-Krein formulas of the first and second derivative of a matrix
    function (Daleckii & Krein 1965; Bhatia 1997, Matrix Analysis, V.3; for the Hencky strain, Miehe
    & Lambrecht 2001, Commun. Numer. Methods Eng. 17, 337; de Souza Neto, Peric & Owen 2008, A.5):

        dE'_ij = g[l_i, l_j] dC'_ij
        S'_ij = 2 g[l_i, l_j] T'_ij,   dS'_ij = 2 sum_k g[l_i, l_k, l_j] (T'_ik dC'_kj + dC'_ik T'_kj)
        dP = dF S + F dS                                                               [Pa]

    g[x, y] the first divided difference (1 / (2x) at x = y), g[x, y, z] the second (-1 / (4 x^2) at
    x = y = z), both evaluated without cancellation when the eigenvalues meet (every point that
    barely deforms); the hoop terms dE_tt = dF_tt / F_tt, dP_tt = -T_tt / F_tt^2 dF_tt. Checked
    against central differences (kinematic_derivatives_by_differences) in tests/test_finite_strain.py.
    ``stretch``: Stretch(H), when the caller has it."""
    H, T = np.asarray(H, dtype=float), np.asarray(T, dtype=float)
    st = Stretch(H) if stretch is None else stretch
    c, s = st.c, st.s
    lam1, lam2 = st.lam1, st.lam2
    g11, g22, g12 = 0.5 / lam1, 0.5 / lam2, _log_divided_difference(st.mu1, st.mu2)
    a111, a222 = -0.25 / lam1 ** 2, -0.25 / lam2 ** 2
    a112, a122 = _log_second_divided_difference(lam1, lam2), _log_second_divided_difference(lam2, lam1)
    F = st.F
    t00, t01, t11 = _to_eigenbasis(c, s, T[..., 0], T[..., 3], T[..., 1])
    S00, S01, S11 = _from_eigenbasis(c, s, 2.0 * g11 * t00, 2.0 * g12 * t01, 2.0 * g22 * t11)
    # the four block directions on a new last axis n: dC = e_b F_a + F_a^T e_b^T (F_a: row a of F)
    x = (..., None)
    row0, row1 = F[..., 2 * _ROW], F[..., 2 * _ROW + 1]               # F_a0, F_a1 (..., 4)
    b0, b1 = (_COLUMN == 0).astype(float), (_COLUMN == 1).astype(float)
    dC00, dC01, dC11 = 2.0 * b0 * row0, b0 * row1 + b1 * row0, 2.0 * b1 * row1
    cx, sx = c[x], s[x]
    d00, d01, d11 = _to_eigenbasis(cx, sx, dC00, dC01, dC11)
    E00, E01, E11 = _from_eigenbasis(cx, sx, g11[x] * d00, g12[x] * d01, g22[x] * d11)
    t00, t01, t11 = t00[x], t01[x], t11[x]
    dS00 = 4.0 * (a111[x] * t00 * d00 + a112[x] * t01 * d01)
    dS11 = 4.0 * (a122[x] * t01 * d01 + a222[x] * t11 * d11)
    dS01 = 2.0 * (a112[x] * (t00 * d01 + d00 * t01) + a122[x] * (t01 * d11 + d01 * t11))
    dS00, dS01, dS11 = _from_eigenbasis(cx, sx, dS00, dS01, dS11)
    a0, a1 = (_ROW == 0).astype(float), (_ROW == 1).astype(float)
    S_b0 = b0 * S00[x] + b1 * S01[x]                                   # S_b0, S_b1 of each direction
    S_b1 = b0 * S01[x] + b1 * S11[x]
    F00, F01, F10, F11 = F[..., 0][x], F[..., 1][x], F[..., 2][x], F[..., 3][x]
    shape = H.shape[:-1]
    dE = np.zeros(shape + (4, N_GRADIENT))
    dE[..., 0, :4], dE[..., 1, :4], dE[..., 3, :4] = E00, E11, 2.0 * E01
    dE[..., 2, 4] = 1.0 / F[..., 4]                                          # E_tt = ln F_tt
    dP = np.zeros(shape + (N_GRADIENT, N_GRADIENT))
    dP[..., 0, :4] = a0 * S_b0 + F00 * dS00 + F01 * dS01
    dP[..., 1, :4] = a0 * S_b1 + F00 * dS01 + F01 * dS11
    dP[..., 2, :4] = a1 * S_b0 + F10 * dS00 + F11 * dS01
    dP[..., 3, :4] = a1 * S_b1 + F10 * dS01 + F11 * dS11
    dP[..., 4, 4] = -T[..., 2] / st.C_tt                                     # P_tt = T_tt / F_tt
    return dE, dP


# central-difference step on the components of F [-]: truncation ~ h^2, round-off ~ 1e-16 / h, both
# below 1e-9 of the tangent
GRADIENT_STEP = 1e-6


def kinematic_derivatives_by_differences(H, T, step: float = GRADIENT_STEP) -> tuple[np.ndarray, np.ndarray]:
    """``kinematic_derivatives`` by central differences over the five components of F (the
    reference the closed form is checked against)."""
    H = np.asarray(H, dtype=float)
    # the ten perturbed gradients in one evaluation (+h e_k, then -h e_k, on a leading axis)
    shifts = step * np.concatenate([np.eye(N_GRADIENT), -np.eye(N_GRADIENT)])
    perturbed = Stretch(H + shifts.reshape((2 * N_GRADIENT,) + (1,) * (H.ndim - 1) + (N_GRADIENT,)))
    E, P = perturbed.hencky(), perturbed.first_piola(T)
    dE = np.moveaxis((E[:N_GRADIENT] - E[N_GRADIENT:]) / (2.0 * step), 0, -1)
    dP = np.moveaxis((P[:N_GRADIENT] - P[N_GRADIENT:]) / (2.0 * step), 0, -1)
    return dE, dP

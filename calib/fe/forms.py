"""The weak forms of axisymmetric equilibrium, named after the physics (scikit-fem forms).

Equilibrium r(u) = f_int(u) - f_ext = 0 (M a + f_int - f_ext = 0 in an impact) with

    f_int,i = int_A sigma(eps(u)) . eps(phi_i) 2 pi r dA        [N]
    K_ij    = int_A eps(phi_i) . C eps(phi_j) 2 pi r dA         [N/m]
    M_ij    = int_A rho phi_i . phi_j 2 pi r dA                 [kg]

on the r-z section A; eps and the 2 pi r weight come from calib.fe.axisym (components r, z,
theta, rz with engineering shear). Quadrature-point fields enter as ``asm`` keyword arguments:
``stress`` (4, E, Q) [Pa] and ``tangent`` (4, 4, E, Q) [Pa], as calib.fe.axisym.to_form_layout
arranges them. Reference: Zienkiewicz & Taylor, The Finite Element Method, vol. 1, ch. 9
(axisymmetric solids).
"""
import numpy as np
from skfem import BilinearForm, LinearForm

from calib.fe.axisym import radial_weight, strain


@LinearForm
def internal_force(v, w):
    """Internal nodal forces, int_A sigma . eps(v) 2 pi r dA [N]; ``stress`` shaped (4, E, Q)."""
    r = w.x[0]
    return np.sum(np.asarray(w.stress) * strain(v, r), axis=0) * radial_weight(r)


@BilinearForm
def tangent_stiffness(u, v, w):
    """Tangent stiffness, int_A eps(v) . C eps(u) 2 pi r dA [N/m]; ``tangent`` (4, 4, E, Q)."""
    r = w.x[0]
    C_eps_u = np.einsum("ij...,j...->i...", np.asarray(w.tangent), strain(u, r))
    return np.sum(strain(v, r) * C_eps_u, axis=0) * radial_weight(r)


@LinearForm
def surface_weight(v, w):
    """int_S v 2 pi r ds [m^2]: the lumped (row-sum) boundary mass of the contact surface."""
    return v * radial_weight(w.x[0])


@BilinearForm
def mass(u, v, w):
    """Consistent mass, int_A rho u . v 2 pi r dA [kg]; ``rho`` [kg/m^3] a constant."""
    return w.rho * (u[0] * v[0] + u[1] * v[1]) * radial_weight(w.x[0])

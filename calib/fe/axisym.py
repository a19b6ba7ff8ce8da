"""Axisymmetric small-strain kinematics: the one place that knows about hoop strain and 2 pi r.

Coordinates x = (r, z) [m], displacement u = (u_r, u_z) [m]. Strain in the project's Voigt
convention (calib.fe.material), with ENGINEERING shear:

    eps = [eps_rr, eps_zz, eps_tt, gamma_rz]
        = [du_r/dr, du_z/dz, u_r / r, du_r/dz + du_z/dr]                         [-]

so that the work density is stress . eps with stress = [s_rr, s_zz, s_tt, s_rz] [Pa]. A volume
integral over the solid of revolution is the integral over the r-z section weighted by 2 pi r:

    int_V f dV = int_A f(r, z) 2 pi r dA.

Quadrature points of triangles are interior, so r > 0 there and u_r / r is evaluated directly
(no special case on the axis, where u_r = 0 is imposed). Reference: Zienkiewicz & Taylor,
The Finite Element Method, vol. 1, ch. 5 (axisymmetric stress analysis).
"""
from __future__ import annotations

import numpy as np

N_COMPONENTS = 4  # [rr, zz, tt, rz]


def strain(u, r):
    """Voigt strain [eps_rr, eps_zz, eps_tt, gamma_rz] of a scikit-fem vector field.

    ``u`` is a vector DiscreteField inside a form (value (2, ...), grad (2, 2, ...)), ``r`` the
    radial coordinate at the same points (w.x[0]). Returns an array (4, ...) [-].
    """
    du = u.grad
    return np.array([du[0, 0], du[1, 1], u[0] / r, du[0, 1] + du[1, 0]])


def radial_weight(r):
    """Volume weight of the axisymmetric section, 2 pi r [m]."""
    return 2.0 * np.pi * r


def quadrature_radius(basis):
    """Radial coordinate r at the quadrature points of ``basis``, (n_elements, n_qp) [m]."""
    return np.asarray(basis.global_coordinates()[0])


def quadrature_strain(basis, displacement, r=None):
    """Strain at the quadrature points of ``basis`` for the dof vector ``displacement`` [m].

    ``r`` (optional, from quadrature_radius) saves recomputing the coordinates.
    Returns (n_elements, n_quadrature_points, 4), the layout of the Material interface.
    """
    r = quadrature_radius(basis) if r is None else r
    return np.moveaxis(strain(basis.interpolate(displacement), r), 0, -1)


def to_form_layout(array):
    """(E, Q, ...) quadrature array -> (..., E, Q), the layout scikit-fem forms expect."""
    # contiguous: scikit-fem's kernels run ~2.5x faster than on a strided (moveaxis) view
    return np.ascontiguousarray(np.moveaxis(np.asarray(array), (0, 1), (-2, -1)))

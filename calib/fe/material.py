"""What the contact solver needs of a material, and the isotropic elastic constants they share.

Component convention of every quadrature-point array, shaped (n_elements, n_qp, 4) with
components [rr, zz, tt, rz] (r radial, z axial, t hoop):

* strain: Voigt with ENGINEERING shear, [eps_rr, eps_zz, eps_tt, gamma_rz], gamma_rz = 2 eps_rz [-]
  (calib.fe.axisym computes it from the displacement);
* stress: plain components [s_rr, s_zz, s_tt, s_rz] [Pa], so stress . strain is the work density;
* tangent: d stress / d strain in the same convention, shaped (n_elements, n_qp, 4, 4) [Pa].

Isotropic elasticity (Johnson 1985, Contact Mechanics, ch. 2): with Young's modulus E [Pa] and
Poisson's ratio nu [-],

    lambda = E nu / ((1 + nu)(1 - 2 nu)),  mu = E / (2 (1 + nu)),  K = E / (3 (1 - 2 nu))   [Pa]
    D[:3, :3] = lambda + 2 mu I,  D[3, 3] = mu      (engineering shear),  D[:3, 3] = D[3, :3] = 0
"""
from __future__ import annotations

from typing import Any, Protocol, runtime_checkable

import numpy as np

from nfdmodel import check_real, limits


@runtime_checkable
class Material(Protocol):
    """A constitutive model at the quadrature points, as calib.fe.solver.ContactSolver uses it.

    ``update`` is pure: it returns the trial state and never changes ``committed``; the solver
    adopts the trial state only once a load step has converged, so a failed step is retried from
    the unchanged committed state. ``is_linear`` (True: the tangent never changes, the solver
    assembles and factorises it once per active set). ``E`` [Pa] and ``nu`` [-] are the elastic
    constants, used for force scales and the Hertz warm start of the active set.
    """

    E: float
    nu: float
    is_linear: bool

    def initial_state(self, n_elements: int, n_qp: int) -> Any:
        """The virgin state (e.g. zero plastic strain) at every quadrature point."""

    def update(self, strain, committed) -> tuple[np.ndarray, np.ndarray, Any]:
        """(stress (E, Q, 4) [Pa], tangent (E, Q, 4, 4) [Pa], trial state) at the total strain
        (E, Q, 4) [-], from the committed state."""

    def dissipated_work(self, state, weight) -> float:
        """The work dissipated since the virgin state [J]: the integral of the dissipation density
        [J/m^3] at the quadrature points with the volume weights ``weight`` (E, Q) [m^3] (0 for an
        elastic material; the energy balance of the impacts, calib.fe.newmark)."""


def elastic_constants(E, nu) -> tuple[float, float]:
    """(E, nu) as floats: Young's modulus E > 0 [Pa] and Poisson's ratio 0 <= nu < 0.5, or a
    ValueError naming the parameter and its range (nfdmodel.check_real, the one validator)."""
    return (check_real("E", E, low=0.0, unit="[Pa] (Young's modulus)"),
            check_real("nu", nu, low=0.0, low_inclusive=True, high=limits.NU_MAX, unit="(Poisson's ratio)"))


def lame_constants(E: float, nu: float) -> tuple[float, float, float]:
    """(lambda, mu, K) [Pa] of an isotropic solid with Young's modulus E [Pa] > 0 and Poisson's
    ratio 0 <= nu < 0.5."""
    E, nu = elastic_constants(E, nu)
    return (E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), E / (2.0 * (1.0 + nu)),
            E / (3.0 * (1.0 - 2.0 * nu)))


def elastic_matrix(E: float, nu: float) -> np.ndarray:
    """The isotropic elastic D (4, 4) [Pa] in the component convention above."""
    lame_lambda, shear_modulus, _ = lame_constants(E, nu)
    matrix = np.zeros((4, 4))
    matrix[:3, :3] = lame_lambda
    matrix[[0, 1, 2], [0, 1, 2]] += 2.0 * shear_modulus
    matrix[3, 3] = shear_modulus
    return matrix


class IsotropicElasticity:
    """The elastic constants of a material with fields ``E`` and ``nu`` (mixin)."""

    E: float
    nu: float

    @property
    def lame_lambda(self) -> float:
        """lambda [Pa]."""
        return lame_constants(self.E, self.nu)[0]

    @property
    def shear_modulus(self) -> float:
        """mu [Pa]."""
        return lame_constants(self.E, self.nu)[1]

    @property
    def bulk_modulus(self) -> float:
        """K [Pa]."""
        return lame_constants(self.E, self.nu)[2]

    def elastic_tangent(self) -> np.ndarray:
        """D (4, 4) [Pa], the tangent of every elastic point."""
        return elastic_matrix(self.E, self.nu)

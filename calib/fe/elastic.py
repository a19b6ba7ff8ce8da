"""Isotropic linear elasticity, a ``calib.fe.material.Material`` (the Hertz-limit validation).

stress = D strain at every quadrature point, D from calib.fe.material.elastic_matrix; no history.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from calib.fe.material import IsotropicElasticity, elastic_constants


@dataclass(frozen=True)
class ElasticState:
    """Linear elasticity carries no history: the state has no fields."""


@dataclass(frozen=True)
class ElasticMaterial(IsotropicElasticity):
    """Isotropic linear elasticity, stress = D strain.

    D[:3, :3] = lambda + 2 mu I,  D[3, 3] = mu  (engineering shear), with the Lame constants
    lambda = E nu / ((1 + nu)(1 - 2 nu)),  mu = E / (2 (1 + nu))          [Pa]
    (Johnson 1985, Contact Mechanics, ch. 2). E [Pa] > 0, 0 <= nu < 0.5.
    """

    E: float
    nu: float
    is_linear: ClassVar[bool] = True  # the tangent never changes: the solver may reuse it

    def __post_init__(self):
        E, nu = elastic_constants(self.E, self.nu)
        object.__setattr__(self, "E", E)
        object.__setattr__(self, "nu", nu)

    def initial_state(self, n_elements: int, n_qp: int) -> ElasticState:
        return ElasticState()

    def update(self, strain_total, state_committed):
        """(stress, tangent, trial_state) for the total strain (E, Q, 4); pure."""
        strain_total = np.asarray(strain_total, dtype=float)
        if strain_total.ndim != 3 or strain_total.shape[-1] != 4:
            raise ValueError(f"strain_total must be shaped (n_elements, n_qp, 4), got {strain_total.shape}")
        D = self.elastic_tangent()
        stress = strain_total @ D  # D is symmetric
        tangent = np.broadcast_to(D, strain_total.shape[:2] + (4, 4))
        return stress, tangent, state_committed

    def dissipated_work(self, state, weight) -> float:
        """Elasticity dissipates nothing [J]."""
        return 0.0

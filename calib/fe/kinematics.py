"""The kinematics of the FE, and the one place where the material is evaluated.

Every configuration (the press, the pair press, the impact and the pair impact) takes its strains,
internal forces and tangents from here, so a material model plugs in through the
calib.fe.material.Material protocol alone (``update`` is called in this module only) and another
kinematics (finite strain) replaces the class below alone.

Small strain, axisymmetric (calib.fe.axisym: the r-z strain with the hoop strain u_r / r;
calib.fe.element_arrays: B and the 2 pi r weight at the quadrature points):

    eps = B u                                                             [-]
    f_int = int B^T sigma dV                                              [N]
    K_t = int B^T C B dV,  C = d sigma / d eps the material's consistent tangent   [N/m]

and, for the presses, written as the elastic part plus the inelastic correction (D: the elastic
tangent; the impacts assemble f_int = int B^T sigma dV itself, whose discrete energy identity then
closes to round-off, and the tangent the same way):

    f_int = K_el u + sum over flowed elements of int B^T (sigma - D eps) dV
    K_t   = K_el   + sum over flowed elements of int B^T (C - D) B dV

Both corrections vanish wherever the material is still elastic (sigma = D eps, C = D to 1e-13),
so only the elements that have flowed are assembled: the plastic zone of a contact is small.
K_el is assembled once (scikit-fem's form calib.fe.forms.tangent_stiffness for the full dofs, the
element arrays for the unknowns q). Reference: Zienkiewicz & Taylor, The Finite Element Method,
vol. 1, ch. 5 and 9 (small-strain axisymmetric solids); Simo & Hughes 1998, Computational
Inelasticity, ch. 3 (the consistent tangent).
"""
from __future__ import annotations

from typing import Callable, NamedTuple, Optional

import numpy as np
from skfem import asm

from calib.fe.axisym import to_form_layout
from calib.fe.element_arrays import ElementArrays
from calib.fe.forms import tangent_stiffness
from calib.fe.log_strain import Stretch, kinematic_derivatives

# the kinematics a configuration can take (its ``kinematics`` option), by name: adding one is adding
# its class here, with SmallStrain's interface
DEFAULT_KINEMATICS = "small-strain"


def build_kinematics(name: str, elements: ElementArrays, D: np.ndarray, evaluated: np.ndarray | None = None):
    """The kinematics ``name`` (one of KINEMATICS) of a mesh's ``elements``, elastic tangent ``D`` and
    ``evaluated`` elements (SmallStrain's arguments); ValueError naming the choices otherwise."""
    if name not in KINEMATICS:
        raise ValueError(f"kinematics must be one of {sorted(KINEMATICS)}, got {name!r}")
    return KINEMATICS[name](elements, D, evaluated)


# a stress or tangent correction below this fraction of the stress / the elastic modulus is
# round-off of an elastic point, not flow
INELASTIC_TOLERANCE = 1e-13


def elastic_tangent(material, n_elements: int, n_qp: int) -> np.ndarray:
    """D [Pa] at every quadrature point, (E, Q, 4, 4): the material's tangent at zero strain from
    its virgin state."""
    _, tangent, _ = material.update(np.zeros((n_elements, n_qp, 4)), material.initial_state(n_elements, n_qp))
    return np.asarray(tangent)


def _hooke(D, strain) -> np.ndarray:
    """D eps [Pa]: ``D`` (4, 4) for every point (symmetric) or (n, Q, 4, 4) per point, ``strain`` (n, Q, 4)."""
    return strain @ D if D.ndim == 2 else np.einsum("eqij,eqj->eqi", D, strain)


class Correction(NamedTuple):
    """The material's response at one iterate: ``stress`` (evaluated elements, Q, 4) [Pa] and the
    ``trial`` state; the ``flowed`` elements (indices), their internal-force correction ``force()``,
    int B^T (sigma - D eps) dV on all dofs [N], and ``tangent_data()``, int B^T (C - D) B dV as
    data on the element pattern [N/m] (both None when nothing has flowed; computed on demand);
    ``material_stress``: the stress the material returned, conjugate to the kinematics' strain
    (finite strain: T, conjugate to the Hencky strain; None: ``stress`` itself, small strain's)."""

    stress: np.ndarray
    trial: object
    flowed: np.ndarray
    force: Optional[Callable[[], np.ndarray]]
    tangent_data: Optional[Callable[[], np.ndarray]]
    material_stress: Optional[np.ndarray] = None

    @property
    def conjugate_stress(self) -> np.ndarray:
        """The stress conjugate to the kinematics' strain (E, Q, 4) [Pa]: what ``internal_force`` and
        the elastic energy 1/2 int s . D^-1 s dV (reference volume) take."""
        return self.stress if self.material_stress is None else self.material_stress


class SmallStrain:
    """Small-strain axisymmetric kinematics of one mesh (module docstring).

    ``elements``: the calib.fe.element_arrays.ElementArrays of the mesh's basis and its reduction
    u = T q; ``D``: the elastic tangent [Pa], (4, 4) for one homogeneous material or (E, Q, 4, 4)
    per point; ``evaluated``: the elements whose material Newton evaluates (None: all; a condensed
    elastic counter-body's are left out, calib.fe.two_body). ``deformed_surface``: the contact radius
    is measured on the undeformed surface (calib.fe.quasi_static)."""

    deformed_surface = False

    def __init__(self, elements: ElementArrays, D: np.ndarray, evaluated: np.ndarray | None = None):
        self.elements = elements
        self.D = np.asarray(D)
        self.homogeneous = self.D.ndim == 2
        self.evaluated = evaluated
        n_elements, n_qp = elements.weight.shape
        D_all = np.broadcast_to(self.D, (n_elements, n_qp, 4, 4)) if self.homogeneous else self.D
        self.elastic_data = elements.stiffness_data(D_all, slice(None))     # K_el on the q pattern
        self._D_all = D_all
        if evaluated is not None:
            # the B matrices, dofs and D of the evaluated elements, gathered once (not per iteration)
            self._B = np.ascontiguousarray(elements.B[evaluated])
            self._dofs = np.ascontiguousarray(elements.element_dofs[evaluated])
            self._D_evaluated = self.D if self.homogeneous else self.D[evaluated]
        self._K_full = None

    def elastic_stiffness(self, basis):
        """K_el over every dof [N/m] (scikit-fem ordering of ``basis``), assembled once."""
        if self._K_full is None:
            self._K_full = asm(tangent_stiffness, basis, tangent=to_form_layout(self._D_all)).tocsr()
        return self._K_full

    def strain(self, displacement, elements=slice(None)) -> np.ndarray:
        """eps = B u at the quadrature points of ``elements``, (n, Q, 4) [-]."""
        a = self.elements
        if isinstance(elements, slice) and elements == slice(None):
            return a.strain(displacement)
        return np.matmul(a.B[elements], np.asarray(displacement)[a.element_dofs[elements]][:, None, :, None])[..., 0]

    def elastic_stress(self, strain, elements=slice(None)) -> np.ndarray:
        """D eps [Pa] of ``elements``' strain (n, Q, 4)."""
        return _hooke(self.D if self.homogeneous else self.D[elements], strain)

    def stress(self, material, displacement, committed) -> np.ndarray:
        """sigma (E, Q, 4) [Pa] of the material at ``displacement`` from ``committed`` (pure)."""
        return material.update(self.strain(displacement), committed)[0]

    def correction(self, material, displacement, committed, time_step: float | None = None) -> Correction:
        """The material at the displacement [m] (every dof) from its ``committed`` state, and the
        inelastic corrections of the internal force and the tangent (module docstring); ``time_step``
        [s], given by the dynamic stepper to a rate-dependent material, reaches its update."""
        if self.evaluated is None:
            strain = self.strain(displacement)
            stress, tangent, trial = (material.update(strain, committed) if time_step is None
                                      else material.update(strain, committed, time_step=time_step))
            D = self.D
        else:
            strain = np.matmul(self._B, np.asarray(displacement)[self._dofs][:, None, :, None])[..., 0]
            stress, tangent, trial = material.update(strain, committed, self.evaluated)
            D = self._D_evaluated
        stress_correction = stress - _hooke(D, strain)
        tangent_correction = tangent - D
        scale = max(float(np.abs(stress).max()), 1e-300)
        inelastic = (np.abs(stress_correction).max(axis=(1, 2)) > INELASTIC_TOLERANCE * scale) | \
                    (np.abs(tangent_correction).max(axis=(1, 2, 3)) > INELASTIC_TOLERANCE * np.abs(D).max())
        if not inelastic.any():
            return Correction(stress, trial, np.zeros(0, dtype=int), None, None)
        flowed = np.flatnonzero(inelastic) if self.evaluated is None else self.evaluated[inelastic]
        stress_correction, tangent_correction = stress_correction[inelastic], tangent_correction[inelastic]
        return Correction(stress, trial, flowed, lambda: self.elements.internal_force(stress_correction, flowed),
                          lambda: self.elements.stiffness_data(tangent_correction, flowed))

    def internal_force(self, stress, displacement=None) -> np.ndarray:
        """f_int = int B^T sigma dV [N] on all dofs, from the stress (E, Q, 4) [Pa] of every element
        (the impacts: their energy identity closes to round-off with the same B as the strain);
        ``displacement`` [m]: unused here (finite strain's P = F S needs it)."""
        return self.elements.internal_force(stress, slice(None))

    def residual_state(self, plastic_strain, stiffness_solve):
        """(u [m] on every dof, sigma (E, Q, 4) [Pa]) of the body's static equilibrium with the
        plastic strain (E, Q, 4) frozen, free of load: K u = int B^T D eps_p dV, solved by
        ``stiffness_solve`` (f on every dof -> u on every dof, the body's supports applied), then
        sigma = D (eps(u) - eps_p)."""
        u = stiffness_solve(self.internal_force(self.elastic_stress(plastic_strain)))
        return u, self.elastic_stress(self.strain(u) - plastic_strain)


class FiniteStrain(SmallStrain):
    """Total Lagrangian finite-strain axisymmetric kinematics in the Lagrangian Hencky strain
    (calib.fe.log_strain: F, E = 1/2 ln C, the material's T conjugate to E, P = F S):

        F = I + G u,  f_int = int G^T P(F) 2 pi R dA0,  K_t = int G^T (dP/dF) G 2 pi R dA0

    (G: calib.fe.element_arrays.ElementArrays.gradient; the integrals over the reference section).
    The material's update is SmallStrain's, with E for eps; its plastic strain is the Lagrangian
    plastic log strain. dP/dF = dP/dF|_T + (dE/dF)^T C_alg dE/dF, C_alg the material's consistent
    tangent, the kinematic derivatives in closed form (calib.fe.log_strain.kinematic_derivatives),
    symmetrised (the exact dP/dF of this hyperelastic-plastic model is symmetric). Every element is
    reported as flowed, its correction f_int - K_el u and K_t - K_el, so the steppers stay those of
    small strain; the rigid flat's gap z0 + u_z is already the deformed surface's. The press and the
    impact on the rigid flat, and the pair press on a condensed elastic counter-body (``evaluated``:
    the sphere's elements take finite strain, the counter-body's stay linear small-strain). ``stress`` and
    Correction.stress are the Cauchy stress in the spatial r-z-t frame, Correction.material_stress
    the material's T; the impact's f_int is ``internal_force(T, u)`` = int G^T P dV0 and its elastic
    energy the Hencky one, 1/2 int E_e : D E_e dV0 = 1/2 int T : D^-1 T dV0 (E_e = E - E_p, per
    reference volume). The contact radius is measured on the deformed surface (``deformed_surface``)."""

    deformed_surface = True

    def __init__(self, elements: ElementArrays, D: np.ndarray, evaluated: np.ndarray | None = None):
        super().__init__(elements, D, evaluated)
        self._evaluated_elastic_data = None

    def displacement_gradient(self, displacement, elements=slice(None)) -> np.ndarray:
        """H = F - I = G u (n, Q, 5) [-] of ``elements``, components [H_rR, H_rZ, H_zR, H_zZ, H_tt]."""
        a = self.elements
        return np.matmul(a.gradient[elements], np.asarray(displacement)[a.element_dofs[elements]][:, None, :, None])[..., 0]

    def _linear(self, elements) -> np.ndarray:
        """Which of ``elements`` are outside ``evaluated`` (a condensed linear counter-body's), (n,) bool."""
        chosen = np.arange(self.elements.weight.shape[0])[elements]
        return np.zeros(chosen.size, dtype=bool) if self.evaluated is None else ~np.isin(chosen, self.evaluated)

    def strain(self, displacement, elements=slice(None)) -> np.ndarray:
        """The Hencky strain E = 1/2 ln C, (n, Q, 4) [-] (Voigt, engineering shear); B u in the
        elements outside ``evaluated`` (a condensed counter-body stays small-strain and linear)."""
        strain = Stretch(self.displacement_gradient(displacement, elements)).hencky()
        linear = self._linear(elements)
        if linear.any():
            strain[linear] = SmallStrain.strain(self, displacement, np.arange(self.elements.weight.shape[0])[elements][linear])
        return strain

    def stress(self, material, displacement, committed) -> np.ndarray:
        """The Cauchy stress (E, Q, 4) [Pa] of the material at ``displacement`` from ``committed``
        (outside ``evaluated``: the linear counter-body's D B u)."""
        stretch = Stretch(self.displacement_gradient(displacement))
        T = material.update(self.strain(displacement), committed)[0]
        cauchy = stretch.cauchy(T)
        linear = self._linear(slice(None))
        cauchy[linear] = T[linear]
        return cauchy

    @staticmethod
    def response(material, H, committed, stretch: Stretch | None = None, time_step: float | None = None,
                 elements: np.ndarray | None = None):
        """(P (..., 5) [Pa], dP/dF () -> (..., 5, 5) [Pa], Cauchy stress (..., 4) [Pa], trial state, T
        (..., 4) [Pa]) of the material at the displacement gradients ``H`` = F - I (E, Q, 5) from
        ``committed`` (``stretch``: Stretch(H), when the caller has it; ``time_step`` [s]: to a
        rate-dependent material's update, as SmallStrain.correction; ``elements``: the evaluated
        elements H is of, to a two-body material's update)."""
        stretch = Stretch(H) if stretch is None else stretch
        args = () if elements is None else (elements,)
        kwargs = {} if time_step is None else {"time_step": time_step}
        T, C_alg, trial = material.update(stretch.hencky(), committed, *args, **kwargs)

        def tangent():
            dE, dP = kinematic_derivatives(H, T, stretch)
            A = dP + np.swapaxes(dE, -1, -2) @ np.asarray(C_alg) @ dE
            return 0.5 * (A + np.swapaxes(A, -1, -2))

        return stretch.first_piola(T), tangent, stretch.cauchy(T), trial, T

    def correction(self, material, displacement, committed, time_step: float | None = None) -> Correction:
        """Every evaluated element's f_int - K_el u [N] and K_t - K_el (class docstring); ``time_step``
        as SmallStrain.correction's."""
        a = self.elements
        chosen = slice(None) if self.evaluated is None else self.evaluated
        flowed = np.arange(a.weight.shape[0]) if self.evaluated is None else self.evaluated
        H = self.displacement_gradient(displacement, chosen)
        stretch = Stretch(H)
        if not np.isfinite(stretch.J).all():
            # an iterate that inverts an element: a NaN residual, which Newton reports as a failed step
            nan = np.full(a.n_dofs, np.nan)
            return Correction(np.full(H.shape[:-1] + (4,), np.nan), committed, flowed,
                              lambda: nan, lambda: np.zeros(a.nnz))
        P, tangent, cauchy, trial, T = self.response(material, H, committed, stretch, time_step, self.evaluated)
        if self.evaluated is None:
            force = a.internal_force(P, chosen, a.gradient) - \
                a.internal_force(_hooke(self.D, a.strain(displacement)), chosen)
            elastic = self.elastic_data
        else:
            force = a.internal_force(P, chosen, a.gradient) - \
                a.internal_force(_hooke(self._D_evaluated, SmallStrain.strain(self, displacement, chosen)), chosen)
            if self._evaluated_elastic_data is None:
                D = np.broadcast_to(self._D_evaluated, H.shape[:-1] + (4, 4))
                self._evaluated_elastic_data = a.stiffness_data(D, chosen)
            elastic = self._evaluated_elastic_data
        return Correction(cauchy, trial, flowed, lambda: force,
                          lambda: a.stiffness_data(tangent(), chosen, a.gradient) - elastic, T)

    def internal_force(self, stress, displacement=None) -> np.ndarray:
        """f_int = int G^T P dV0 [N] on all dofs, P = F S(T) of the material's stress T (E, Q, 4) [Pa]
        (Correction.material_stress, conjugate to the Hencky strain) at ``displacement`` [m]."""
        if displacement is None:
            raise ValueError("kinematics 'finite-strain': the internal force needs the displacement")
        a = self.elements
        P = Stretch(self.displacement_gradient(displacement)).first_piola(stress)
        return a.internal_force(P, slice(None), a.gradient)

    def residual_state(self, plastic_strain, stiffness_solve):
        """(u [m] on every dof, T (E, Q, 4) [Pa]) of the body's static equilibrium with the Lagrangian
        plastic log strain E_p (E, Q, 4) frozen, free of load: int G^T P(u) dV0 = 0 with
        T = D (E(u) - E_p), hyperelastic. Modified Newton on the elastic stiffness (``stiffness_solve``
        as SmallStrain's, the supports applied): u_k+1 = u_k - K_el^-1 f_int(u_k), from u_0 = 0, whose
        first iterate is small strain's K_el^-1 int B^T D E_p dV; it contracts at about the strain's
        size, stopped when the increment is RESIDUAL_STATE_TOLERANCE of u."""
        a = self.elements
        u = np.zeros(a.n_dofs)
        for _ in range(RESIDUAL_STATE_ITERATIONS):
            stretch = Stretch(self.displacement_gradient(u))
            T = _hooke(self.D, stretch.hencky() - plastic_strain)
            step = stiffness_solve(a.internal_force(stretch.first_piola(T), slice(None), a.gradient))
            u = u - step
            if np.abs(step).max() <= RESIDUAL_STATE_TOLERANCE * np.abs(u).max():
                break
        return u, _hooke(self.D, self.strain(u) - plastic_strain)


# the finite-strain residual state's modified Newton: the increment's size relative to u at which it
# stops, and at most this many iterations (it contracts at about the largest residual strain, < 0.3)
RESIDUAL_STATE_TOLERANCE = 1e-12
RESIDUAL_STATE_ITERATIONS = 100


KINEMATICS = {DEFAULT_KINEMATICS: SmallStrain, "finite-strain": FiniteStrain}

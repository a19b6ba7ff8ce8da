"""Von Mises plasticity: the radial return with isotropic hardening and its consistent tangent.

Small-strain, rate-independent J2 plasticity, elastic-perfectly plastic (VonMisesMaterial) or with
the isotropic hardening of a flow curve sigma_y(eps_bar) (HardeningMaterial; calib.fe.flow_curve:
linear, Swift, Ludwik, tabulated), integrated by backward Euler (the radial return) at the
quadrature points of an axisymmetric finite-element mesh.
References: Simo & Hughes, *Computational Inelasticity* (1998), Box 3.1 (return mapping) and
Box 3.2 (consistent elastoplastic moduli); de Souza Neto, Peric & Owen, *Computational Methods
for Plasticity* (2008), ch. 7 (Box 7.3/7.4 and eq. 7.120).

Component convention (calib.fe.material), arrays shaped (n_elements, n_qp, 4), components
[rr, zz, tt, rz]:

* strain, plastic strain: Voigt with ENGINEERING shear, [eps_rr, eps_zz, eps_tt, gamma_rz],
  gamma_rz = 2 eps_rz  [-];
* stress: plain components [s_rr, s_zz, s_tt, s_rz]  [Pa]  (work density = stress . strain);
* tangent: d stress / d strain (Voigt, engineering shear), shaped (..., 4, 4)  [Pa].

Equations (mu shear modulus, K bulk modulus, lambda Lame's first parameter; all in Pa):

    eps_e_trial = eps - eps_p_old
    sigma_trial = D eps_e_trial,          D[:3,:3] = lambda + 2 mu I,  D[3,3] = mu
    p = (s_rr + s_zz + s_tt)_trial / 3,   s_trial = sigma_trial - p [1,1,1,0]
    |s|^2 = s_rr^2 + s_zz^2 + s_tt^2 + 2 s_rz^2      (the tensor norm: s_rz counted twice)
    q_trial = sqrt(3/2) |s_trial|                     (von Mises equivalent stress)
    f_trial = q_trial - sigma_y

    elastic (f_trial <= tol sigma_y):   sigma = sigma_trial, C = D, delta eps_p = 0
    plastic (f_trial >  tol sigma_y):
        delta gamma = f_trial / (3 mu)                (= equivalent plastic strain increment)
        theta = 1 - 3 mu delta gamma / q_trial = sigma_y / q_trial
        sigma = p [1,1,1,0] + theta s_trial           (so q(sigma) = sigma_y)
        delta eps_p (tensor) = (3/2) delta gamma s_trial / q_trial = (1 - theta) s_trial / (2 mu)
        delta eps_p (Voigt)  = that tensor with the rz entry doubled (engineering shear)

Consistent (algorithmic) tangent, perfect plasticity (Simo & Hughes Box 3.2 with
theta_bar = theta when H = 0):

    C = K 1 (x) 1 + 2 mu theta (I_dev - n (x) n),    n = s_trial / |s_trial|

and in the Voigt convention with engineering shear, where d sigma_I = C_IJ d e_J:

    1      = [1, 1, 1, 0]
    I_dev  = diag(1, 1, 1, 1/2) - (1/3) 1 (x) 1      (the 1/2: s_rz = 2 mu eps_rz = mu gamma_rz)
    n      = [n_rr, n_zz, n_tt, n_rz]  PLAIN components (no factor 2 on the shear: the tensor
             contraction n : d s = n_rr ds_rr + ... + 2 n_rz ds_rz meets the 1/2 of I_dev).

Elastic points get D itself (bit for bit); with theta = 1 and n = 0 the formula reduces to D
anyway. n (x) n removes the stiffness along the flow direction: C n_eng = 0 for the
engineering-shear form of n, so the tangent of a plastic point is singular in that direction
(as it must be for a perfectly plastic material).

Isotropic hardening (return_mapping; de Souza Neto et al. Box 7.4, eq. 7.120; Simo & Hughes
Box 3.2), eps_bar_n the committed equivalent plastic strain, H = d sigma_y / d eps_bar [Pa]:

    plastic where q_trial > sigma_y(eps_bar_n) (1 + tol)
    delta gamma: q_trial - 3 mu delta gamma - sigma_y(eps_bar_n + delta gamma) = 0
        (closed form (q_trial - sigma_y(eps_bar_n)) / (3 mu + H) for a linear curve; a scalar
        Newton iteration otherwise, calib.fe.flow_curve.FlowCurve.return_stress)
    theta = sigma_y(eps_bar_n+1) / q_trial  (= 1 - 3 mu delta gamma / q_trial)
    sigma, delta eps_p as above with this theta
    C = K 1 (x) 1 + 2 mu theta I_dev - 2 mu theta_bar n (x) n,
        theta_bar = theta - H / (3 mu + H)  (= 1 / (1 + H / (3 mu)) - (1 - theta), H at eps_bar_n+1)

With H = 0 (sigma_y = sigma_Y) this is the perfectly plastic return above, operation for operation.

Equivalent plastic strain increment: sqrt(2/3 delta eps_p : delta eps_p)
= sqrt(2/3 (d_rr^2 + d_zz^2 + d_tt^2 + d_gamma_rz^2 / 2)), equal to delta gamma.
"""
from __future__ import annotations

import math
import numbers
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from calib.fe.flow_curve import FlowCurve, LinearHardening, flow_curve_from_record
from calib.fe.rate_law import RateDependentFlow, RateLaw, rate_law_from_record
from calib.fe.material import IsotropicElasticity, elastic_constants, elastic_matrix, lame_constants
from nfdmodel import check_real

__all__ = [
    "PlasticState",
    "VonMisesMaterial",
    "HardeningMaterial",
    "RateDependentMaterial",
    "ViscoplasticState",
    "von_mises_material",
    "radial_return",
    "return_mapping",
    "von_mises_stress",
    "equivalent_plastic_strain_increment",
    "yielded_points",
    "YIELD_TOLERANCE",
]

#: A trial state counts as plastic only if q_trial > sigma_y (1 + YIELD_TOLERANCE). This keeps a
#: point that sits on the yield surface after a converged step (q_trial = sigma_y up to round-off
#: when the strain does not change) from flickering between the elastic and plastic tangents.
YIELD_TOLERANCE = 1e-12

# Voigt vectors and matrices of the convention above (engineering shear strain, plain stress).
_ONE = np.array([1.0, 1.0, 1.0, 0.0])
_ONE_OUTER_ONE = np.outer(_ONE, _ONE)
_DEVIATORIC_PROJECTOR = np.diag([1.0, 1.0, 1.0, 0.5]) - _ONE_OUTER_ONE / 3.0
# Weights of the tensor inner product for plain-component Voigt vectors (rz appears twice).
_TENSOR_NORM_WEIGHTS = np.array([1.0, 1.0, 1.0, 2.0])


# --------------------------------------------------------------------------------------------
# validation
# --------------------------------------------------------------------------------------------
def _validated_parameters(E, nu, sigma_y) -> tuple[float, float, float]:
    """(E, nu, sigma_y) as floats, or a ValueError naming the parameter and its allowed range."""
    E, nu = elastic_constants(E, nu)
    return E, nu, check_real("sigma_y", sigma_y, low=0.0, unit="[Pa] (yield stress)")


def _component_array(values, name: str) -> np.ndarray:
    """A float64, C-contiguous (n_elements, n_qp, 4) array of finite numbers, or ValueError."""
    try:
        array = np.ascontiguousarray(values, dtype=np.float64)
    except (TypeError, ValueError) as error:
        raise ValueError(f"{name} must be a numeric array shaped (n_elements, n_qp, 4)") from error
    if array.ndim != 3 or array.shape[-1] != 4:
        raise ValueError(
            f"{name} must be shaped (n_elements, n_qp, 4) with components [rr, zz, tt, rz], "
            f"got shape {array.shape}")
    if not np.isfinite(array).all():
        raise ValueError(f"{name} must contain only finite numbers (found NaN or inf)")
    return array


# --------------------------------------------------------------------------------------------
# helpers on component arrays
# --------------------------------------------------------------------------------------------
def von_mises_stress(stress) -> np.ndarray:
    """Von Mises equivalent stress q = sqrt(3/2 s:s) [Pa] of plain-component stress (..., 4).

    s = deviator of [s_rr, s_zz, s_tt, s_rz]; s:s = s_rr^2 + s_zz^2 + s_tt^2 + 2 s_rz^2 (the rz
    and zr entries of the tensor both count). Returns shape stress.shape[:-1].
    """
    stress = np.asarray(stress, dtype=np.float64)
    if stress.ndim < 1 or stress.shape[-1] != 4:
        raise ValueError(f"stress must have 4 components [rr, zz, tt, rz] on its last axis, "
                         f"got shape {stress.shape}")
    mean_stress = (stress[..., 0] + stress[..., 1] + stress[..., 2]) / 3.0
    s_rr = stress[..., 0] - mean_stress
    s_zz = stress[..., 1] - mean_stress
    s_tt = stress[..., 2] - mean_stress
    s_rz = stress[..., 3]
    return np.sqrt(1.5 * (s_rr * s_rr + s_zz * s_zz + s_tt * s_tt + 2.0 * s_rz * s_rz))


def equivalent_plastic_strain_increment(plastic_increment) -> np.ndarray:
    """Equivalent plastic strain increment sqrt(2/3 d:d) [-] of Voigt plastic strain (..., 4).

    d = [d_rr, d_zz, d_tt, d_gamma_rz] with engineering shear, so the tensor contraction is
    d:d = d_rr^2 + d_zz^2 + d_tt^2 + d_gamma_rz^2 / 2. For the radial return this equals the
    plastic multiplier delta gamma = (q_trial - sigma_y) / (3 mu). Returns shape (...,).
    """
    d = np.asarray(plastic_increment, dtype=np.float64)
    if d.ndim < 1 or d.shape[-1] != 4:
        raise ValueError(f"plastic_increment must have 4 components [rr, zz, tt, rz] on its last "
                         f"axis, got shape {d.shape}")
    contraction = d[..., 0] ** 2 + d[..., 1] ** 2 + d[..., 2] ** 2 + 0.5 * d[..., 3] ** 2
    return np.sqrt((2.0 / 3.0) * contraction)


def yielded_points(plastic_increment) -> np.ndarray:
    """Boolean (...,): True where the step produced plastic flow (plastic_increment nonzero).

    radial_return sets the increment to exactly 0 at elastic points, so no threshold is needed.
    """
    d = np.asarray(plastic_increment)
    if d.ndim < 1 or d.shape[-1] != 4:
        raise ValueError(f"plastic_increment must have 4 components [rr, zz, tt, rz] on its last "
                         f"axis, got shape {d.shape}")
    return np.any(d != 0.0, axis=-1)


# --------------------------------------------------------------------------------------------
# the return mapping
# --------------------------------------------------------------------------------------------
def radial_return(strain_total, plastic_strain_old, E, nu, sigma_y):
    """Radial return of von Mises elastic-perfectly plastic material, vectorised over points:
    return_mapping with the flow curve sigma_y = sigma_Y (H = 0).

    Parameters
    ----------
    strain_total : (n_elements, n_qp, 4) total strain [eps_rr, eps_zz, eps_tt, gamma_rz] [-]
        (engineering shear).
    plastic_strain_old : (n_elements, n_qp, 4) committed plastic strain, same convention [-].
    E : Young's modulus [Pa], > 0.  nu : Poisson's ratio [-], 0 <= nu < 0.5.
    sigma_y : yield stress in uniaxial tension [Pa], > 0.

    Returns
    -------
    stress : (n_elements, n_qp, 4) [s_rr, s_zz, s_tt, s_rz] [Pa], plain components.
    tangent : (n_elements, n_qp, 4, 4) consistent tangent d stress / d strain_total [Pa]
        (exactly the elastic D at elastic points).
    plastic_increment : (n_elements, n_qp, 4) plastic strain increment of this step, Voigt with
        engineering shear [-] (exactly 0 at elastic points). New plastic strain =
        plastic_strain_old + plastic_increment.

    Pure: the inputs are not modified; outputs are fresh C-contiguous float64 arrays. Equations
    in the module docstring (Simo & Hughes 1998, Box 3.1/3.2; de Souza Neto et al. 2008, ch. 7).
    Raises ValueError for bad parameters, shapes, or non-finite input.
    """
    E, nu, sigma_y = _validated_parameters(E, nu, sigma_y)
    plastic_strain_old = _component_array(plastic_strain_old, "plastic_strain_old")
    return return_mapping(strain_total, plastic_strain_old, np.zeros(plastic_strain_old.shape[:-1]), E, nu,
                          LinearHardening(sigma_y))


def return_mapping(strain_total, plastic_strain_old, equivalent_old, E, nu, flow_curve: FlowCurve):
    """Radial return of von Mises plasticity with the isotropic hardening of ``flow_curve``
    (calib.fe.flow_curve), vectorised over points (module docstring, "Isotropic hardening").

    strain_total, plastic_strain_old : (n_elements, n_qp, 4) [-] as radial_return's;
    equivalent_old : (n_elements, n_qp) committed equivalent plastic strain eps_bar [-];
    E [Pa], nu [-]: the elastic constants. Returns (stress [Pa], consistent tangent [Pa], plastic
    strain increment [-]) as radial_return. Pure. With sigma_y = sigma_Y (H = 0) every operation is
    the perfectly plastic one, so the result is that of elastic-perfect plasticity bit for bit.
    """
    strain_total = _component_array(strain_total, "strain_total")
    plastic_strain_old = _component_array(plastic_strain_old, "plastic_strain_old")
    if plastic_strain_old.shape != strain_total.shape:
        raise ValueError(f"plastic_strain_old must have the shape of strain_total "
                         f"{strain_total.shape}, got {plastic_strain_old.shape}")
    shear_modulus = lame_constants(E, nu)[1]
    elastic_tangent = elastic_matrix(E, nu)

    # Elastic predictor as (..., 4) @ (4, 4) products: BLAS-backed, several times faster than
    # component-wise slicing of the last axis. D and I_dev are symmetric, so eps @ D = D eps.
    elastic_strain = strain_total - plastic_strain_old
    trial_stress = elastic_strain @ elastic_tangent
    trial_deviator = elastic_strain @ (2.0 * shear_modulus * _DEVIATORIC_PROJECTOR)
    deviator_norm = np.sqrt(np.einsum("...i,i,...i->...", trial_deviator,
                                      _TENSOR_NORM_WEIGHTS, trial_deviator))
    trial_von_mises = math.sqrt(1.5) * deviator_norm

    plastic = trial_von_mises > flow_curve.yield_stress(equivalent_old) * (1.0 + YIELD_TOLERANCE)
    plastic_index = np.nonzero(plastic)
    # theta = sigma_y(eps_bar_n+1) / q_trial on plastic points, exactly 1 elsewhere (zero-stress
    # points are always elastic since sigma_y > 0); H the plastic modulus there
    theta = np.ones(trial_von_mises.shape)
    if plastic_index[0].size:
        yield_new, modulus = flow_curve.return_stress(trial_von_mises[plastic_index],
                                                      np.asarray(equivalent_old)[plastic_index],
                                                      3.0 * shear_modulus)
        theta[plastic_index] = yield_new / trial_von_mises[plastic_index]

    # Return to the yield surface: sigma = sigma_trial - (1 - theta) s_trial. At elastic points
    # (1 - theta) is exactly 0, so the elastic stress comes back unchanged.
    one_minus_theta = (1.0 - theta)[..., None]
    stress = trial_stress - one_minus_theta * trial_deviator

    # Plastic strain increment (1 - theta) s_trial / (2 mu), rz entry doubled (engineering shear).
    plastic_increment = trial_deviator * (one_minus_theta * (_TENSOR_NORM_WEIGHTS
                                                            / (2.0 * shear_modulus)))

    # C = D - 2 mu (1 - theta) I_dev - 2 mu theta_bar n (x) n on plastic points only, theta_bar =
    # theta - H / (3 mu + H): the (E,Q,4,4) array is the costly part, and in a contact problem most
    # points stay elastic (exactly D).
    tangent = np.empty(strain_total.shape + (4,), dtype=np.float64)
    tangent[...] = elastic_tangent
    if plastic_index[0].size:
        theta_p = theta[plastic_index][:, None, None]
        theta_bar = theta_p - (np.asarray(modulus) / (3.0 * shear_modulus + np.asarray(modulus)))[..., None, None]
        n_p = trial_deviator[plastic_index] / deviator_norm[plastic_index][:, None]
        tangent[plastic_index] -= 2.0 * shear_modulus * (
            (1.0 - theta_p) * _DEVIATORIC_PROJECTOR + theta_bar * (n_p[:, :, None] * n_p[:, None, :]))
    return stress, tangent, plastic_increment


# --------------------------------------------------------------------------------------------
# the calib.fe.material.Material
# --------------------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class PlasticState:
    """Quadrature-point history of the von Mises material.

    plastic_strain : (n_elements, n_qp, 4) [eps_p_rr, eps_p_zz, eps_p_tt, gamma_p_rz] [-]
        (engineering shear).
    equivalent_plastic_strain : (n_elements, n_qp) accumulated sqrt(2/3 d:d) over steps [-].
    """

    plastic_strain: np.ndarray
    equivalent_plastic_strain: np.ndarray

    def __post_init__(self):
        plastic_strain = _component_array(self.plastic_strain, "plastic_strain")
        equivalent = np.ascontiguousarray(self.equivalent_plastic_strain, dtype=np.float64)
        if equivalent.shape != plastic_strain.shape[:2]:
            raise ValueError(f"equivalent_plastic_strain must be shaped (n_elements, n_qp) = "
                             f"{plastic_strain.shape[:2]}, got {equivalent.shape}")
        if not (np.isfinite(equivalent).all() and (equivalent >= 0.0).all()):
            raise ValueError("equivalent_plastic_strain must be finite and >= 0")
        object.__setattr__(self, "plastic_strain", plastic_strain)
        object.__setattr__(self, "equivalent_plastic_strain", equivalent)

    @property
    def shape(self) -> tuple[int, int]:
        """(n_elements, n_qp)."""
        return self.equivalent_plastic_strain.shape


@dataclass(frozen=True, eq=False)
class ViscoplasticState(PlasticState):
    """PlasticState with the plastic work density accumulated over the steps, plastic_work (n_elements,
    n_qp) = sum of sigma_n+1 . delta eps_p [J/m^3] (with a rate law the work is not a function of eps_bar)."""

    plastic_work: np.ndarray

    def __post_init__(self):
        super().__post_init__()
        work = np.ascontiguousarray(self.plastic_work, dtype=np.float64)
        if work.shape != self.equivalent_plastic_strain.shape or not np.isfinite(work).all():
            raise ValueError(f"plastic_work must be finite and shaped (n_elements, n_qp) = "
                             f"{self.equivalent_plastic_strain.shape}, got {work.shape}")
        object.__setattr__(self, "plastic_work", work)


class _VonMisesPlasticity(IsotropicElasticity):
    """What the von Mises materials share: the state, the update through return_mapping with the
    material's ``flow_curve``, the plastic work."""

    def initial_state(self, n_elements: int, n_qp: int) -> PlasticState:
        """Virgin state: zero plastic strain everywhere."""
        for name, value in (("n_elements", n_elements), ("n_qp", n_qp)):
            if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < 1:
                raise ValueError(f"{name} must be an integer >= 1, got {value!r}")
        return PlasticState(plastic_strain=np.zeros((n_elements, n_qp, 4)),
                            equivalent_plastic_strain=np.zeros((n_elements, n_qp)))

    def update(self, strain_total, state: PlasticState):
        """(stress (E,Q,4) [Pa], tangent (E,Q,4,4) [Pa], trial_state) for the total strain.

        Pure: `state` (the committed state of the last converged step) is not modified; the
        solver commits `trial_state` only once the load step has converged.
        """
        if not isinstance(state, PlasticState):
            raise ValueError(f"state must be a PlasticState (from initial_state or a previous "
                             f"update), got {type(state).__name__}")
        stress, tangent, plastic_increment = return_mapping(
            strain_total, state.plastic_strain, state.equivalent_plastic_strain, self.E, self.nu, self.flow_curve)
        trial_state = PlasticState(
            plastic_strain=state.plastic_strain + plastic_increment,
            equivalent_plastic_strain=state.equivalent_plastic_strain
            + equivalent_plastic_strain_increment(plastic_increment))
        return stress, tangent, trial_state

    def dissipated_work(self, state: PlasticState, weight) -> float:
        """The plastic work int W_p(eps_bar) dV [J], W_p = int_0^eps_bar sigma_y(e) de = int sigma : d eps_p
        (on the yield surface sigma : d eps_p = sigma_y d eps_bar): sigma_Y int eps_bar dV for perfect
        plasticity. With hardening it includes the cold work stored in the lattice (about 5-15 % of it
        in metals), which the mechanical energy balance of an impact counts as lost all the same."""
        return self.flow_curve.plastic_work(state.equivalent_plastic_strain, weight)

    @staticmethod
    def yielded(state_committed: PlasticState, trial_state: PlasticState) -> np.ndarray:
        """Boolean (E, Q): points whose plastic strain changed between the two states."""
        return yielded_points(trial_state.plastic_strain - state_committed.plastic_strain)


@dataclass(frozen=True)
class VonMisesMaterial(_VonMisesPlasticity):
    """Von Mises elastic-perfectly plastic material, a ``calib.fe.material.Material``.

    E : Young's modulus [Pa] (> 0); nu : Poisson's ratio [-] (0 <= nu < 0.5);
    sigma_y : uniaxial yield stress [Pa] (> 0). update() is the radial return (the flow curve
    sigma_y = sigma_Y, H = 0; see return_mapping and the module docstring for equations and
    citations).
    """

    E: float
    nu: float
    sigma_y: float
    is_linear: ClassVar[bool] = False

    def __post_init__(self):
        E, nu, sigma_y = _validated_parameters(self.E, self.nu, self.sigma_y)
        object.__setattr__(self, "E", E)
        object.__setattr__(self, "nu", nu)
        object.__setattr__(self, "sigma_y", sigma_y)

    @property
    def flow_curve(self) -> LinearHardening:
        """sigma_y(eps_bar) = sigma_Y."""
        return LinearHardening(self.sigma_y)


@dataclass(frozen=True)
class HardeningMaterial(_VonMisesPlasticity):
    """Von Mises plasticity with isotropic hardening, a ``calib.fe.material.Material``.

    E : Young's modulus [Pa] (> 0); nu : Poisson's ratio [-] (0 <= nu < 0.5); flow_curve : a
    calib.fe.flow_curve.FlowCurve (linear, Swift, Ludwik or tabulated), the uniaxial true yield
    stress against the equivalent plastic strain; ``sigma_y`` its initial yield stress [Pa].
    update() is return_mapping (module docstring, "Isotropic hardening"); with a linear curve of
    H = 0 every figure is VonMisesMaterial's bit for bit.
    """

    E: float
    nu: float
    flow_curve: FlowCurve
    is_linear: ClassVar[bool] = False

    def __post_init__(self):
        E, nu = elastic_constants(self.E, self.nu)
        if not isinstance(self.flow_curve, FlowCurve):
            raise ValueError(f"flow_curve must be a calib.fe.flow_curve.FlowCurve, got "
                             f"{type(self.flow_curve).__name__}")
        object.__setattr__(self, "E", E)
        object.__setattr__(self, "nu", nu)

    @property
    def sigma_y(self) -> float:
        """The initial yield stress sigma_Y = sigma_y(0) [Pa]."""
        return self.flow_curve.sigma_y


@dataclass(frozen=True)
class RateDependentMaterial(_VonMisesPlasticity):
    """Von Mises viscoplasticity: the flow curve ``flow_curve`` scaled by the rate law ``rate_law``
    (calib.fe.rate_law: Johnson-Cook, Cowper-Symonds; the viscoplastic consistency model), a
    ``calib.fe.material.Material``. E [Pa], nu [-] as HardeningMaterial's.

    update(strain, state, time_step) returns with the time step dt [s] of the dynamic FE the return at
    eps_dot = dgamma / dt (calib.fe.newmark passes it to a material that is ``rate_dependent``);
    without one (the quasi-static press, elastic_tangent) the rate-independent limit R = 1. The state
    (ViscoplasticState) accumulates the plastic work sum sigma_n+1 . delta eps_p, the backward-Euler
    dissipation of the return, which ``dissipated_work`` integrates.
    """

    E: float
    nu: float
    flow_curve: FlowCurve
    rate_law: RateLaw
    is_linear: ClassVar[bool] = False
    rate_dependent: ClassVar[bool] = True

    def __post_init__(self):
        E, nu = elastic_constants(self.E, self.nu)
        if not isinstance(self.flow_curve, FlowCurve):
            raise ValueError(f"flow_curve must be a calib.fe.flow_curve.FlowCurve, got "
                             f"{type(self.flow_curve).__name__}")
        if not isinstance(self.rate_law, RateLaw):
            raise ValueError(f"rate_law must be a calib.fe.rate_law.RateLaw, got {type(self.rate_law).__name__}")
        object.__setattr__(self, "E", E)
        object.__setattr__(self, "nu", nu)

    @property
    def sigma_y(self) -> float:
        """The initial, static yield stress sigma_Y = sigma_y(0) R(0) [Pa]."""
        return self.flow_curve.sigma_y

    def initial_state(self, n_elements: int, n_qp: int) -> ViscoplasticState:
        state = super().initial_state(n_elements, n_qp)
        return ViscoplasticState(state.plastic_strain, state.equivalent_plastic_strain,
                                 np.zeros(state.equivalent_plastic_strain.shape))

    def update(self, strain_total, state: ViscoplasticState, time_step: float | None = None):
        """(stress [Pa], tangent [Pa], trial_state) at the total strain over the time step ``time_step`` [s]
        (None: the rate-independent limit). Pure, as _VonMisesPlasticity.update."""
        if not isinstance(state, ViscoplasticState):
            raise ValueError(f"state must be a ViscoplasticState (from initial_state or a previous update), got "
                             f"{type(state).__name__}")
        flow = self.flow_curve if time_step is None else RateDependentFlow(self.flow_curve, self.rate_law, time_step)
        stress, tangent, plastic_increment = return_mapping(
            strain_total, state.plastic_strain, state.equivalent_plastic_strain, self.E, self.nu, flow)
        trial_state = ViscoplasticState(
            plastic_strain=state.plastic_strain + plastic_increment,
            equivalent_plastic_strain=state.equivalent_plastic_strain
            + equivalent_plastic_strain_increment(plastic_increment),
            plastic_work=state.plastic_work + np.einsum("...i,...i->...", stress, plastic_increment))
        return stress, tangent, trial_state

    def dissipated_work(self, state: ViscoplasticState, weight) -> float:
        """int sum sigma_n+1 . delta eps_p dV [J], the work accumulated in the state."""
        return float(np.sum(state.plastic_work * weight))


def von_mises_material(E, nu, sigma_y, hardening=None, rate_law=None):
    """The von Mises material of a sphere: VonMisesMaterial (``hardening`` and ``rate_law`` None),
    HardeningMaterial with the flow curve ``hardening`` (a FlowCurve or its ``record()``, which must start
    at sigma_y), or RateDependentMaterial with ``rate_law`` (a RateLaw or its ``record()``)."""
    if hardening is None and rate_law is None:
        return VonMisesMaterial(E, nu, sigma_y)
    if hardening is None:
        curve = LinearHardening(sigma_y)
    else:
        curve = hardening if isinstance(hardening, FlowCurve) else flow_curve_from_record(hardening)
    if not math.isclose(curve.sigma_y, sigma_y, rel_tol=1e-6):
        raise ValueError(f"hardening: the flow curve starts at {curve.sigma_y:g} Pa, not at sigma_y = {sigma_y:g} Pa")
    if rate_law is None:
        return HardeningMaterial(E, nu, curve)
    law = rate_law if isinstance(rate_law, RateLaw) else rate_law_from_record(rate_law)
    return RateDependentMaterial(E, nu, curve, law)

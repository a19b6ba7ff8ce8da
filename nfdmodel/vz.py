"""The Vu-Quoc & Zhang (1999) elastoplastic NFD law as a runtime kernel (law name "vz").

Loading beyond the turning point: Hertz up to delta_Y, then the root of the corrected F(P) on
the loading curve (nfdmodel.vz_curve). Unloading and reloading below delta_max: a_p and C_R
frozen at P_max, P = (4/3) E* C_Rmax^(3/2) sqrt(R*) <delta - delta_res>^(3/2) (paper eqs.
3.19-3.22; nfdmodel.turning_point). Separation for delta <= delta_res, re-contact above it.

This module is the vz law as one unit: its parameters (:class:`VZParams`, the pair and the two
constants Ca [m/N] (a_p = Ca <P - P_Y>) and Kc [1/N] (C_R = 1 + Kc <P - P_Y>), in dimensionless form
Ca_hat = Ca P_Y / a_Y and Kc_hat = Kc P_Y; nfdmodel/README.md, The reference case and the
dimensionless constants) and their admissibility (the loading curve delta(P) increases up to 1e8 P_Y
and no load-unload cycle creates energy, e <= 1, up to 1e6 P_Y), its history (:class:`VZState`), the
numpy kernel (:func:`vz_step`, :func:`vz_force`) and ``LAW``; the loading curve's solve is
:mod:`nfdmodel.vz_curve`, the scalar specification ``nfdmodel.reference.vz_step``.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from functools import cached_property, lru_cache

import numpy as np
from scipy.optimize import brentq

from . import limits, native, reference_case
from .contact_law import ContactLaw, plastic_radii
from .hertz import hertz_kernel
from .history import TurningPointHistory, apply_update, check_delta, check_state, restore_shape, step_and_commit
from .materials import ContactPair
from .turning_point import turning_point_step
from .validation import check_real
from .vz_curve import vz_loading_work, vz_plastic_solve, vz_turning_point
from .window import CalibrationWindow, check_contact_radius_below_R

CA_HAT_RANGE = limits.CA_HAT_RANGE      # admissible Ca P_Y / a_Y (paper: 0.026), nfd_limits.h
KC_HAT_MAX = limits.KC_HAT_MAX          # admissible Kc P_Y (paper: 0.0098), nfd_limits.h
# The constants of real solids: the master table's FE calibrations span Ca_hat 0.024..0.035,
# Kc_hat 0.010..0.017 (calib/data/master_table.csv). Beyond these bands (Ca_hat > 1 puts the
# plastic radius a_p = Ca_hat a_Y (P/P_Y - 1) past the contact's; Kc_hat > 0.2 is twice the
# largest admissible Kc_hat at Ca_hat = 0.035) an SI value is a unit slip (the dimensionless
# number typed for it), not a material: check_si_constants refuses it.
CA_HAT_USUAL = (1e-3, 1.0)
KC_HAT_USUAL_MAX = 0.2


@dataclass(frozen=True)
class VZState(TurningPointHistory):
    """History of the vz law; adds a_e_max [m], the elastic contact radius at the turning point,
    a_e,max = (3 P_max R*/(4 E*))^(1/3) (paper eq. 3.19), which also starts the next Newton solve.
    C_Rmax = 1 + Kc<P_max - P_Y> and a_p,max = Ca<P_max - P_Y> are functions of P_max and are
    derived on request (:meth:`ContactLaw.contact_state`)."""

    a_e_max: np.ndarray


@dataclass(frozen=True)
class VZParams:
    """Parameters of the Vu-Quoc & Zhang (1999) NFD model.

    pair: the contact (R*, E*, yield point); Ca [m/N] > 0: plastic contact-radius rate,
    a_p = Ca <P - P_Y> (paper eq. 2.5); Kc [1/N] >= 0: curvature-factor rate,
    C_R = 1 + Kc <P - P_Y> (paper eq. 3.6).

    Validation also requires the loading curve delta(P) = a_ep^2 / (C_R R*) to increase with P
    (checked for P_Y <= P <= 1e8 P_Y); otherwise the displacement-driven force is not unique.
    Dimensionless forms (nfdmodel/README.md, The reference case and the dimensionless constants): Ca_hat = Ca P_Y / a_Y, Kc_hat = Kc P_Y.
    window: the loads the constants were fitted on (:class:`CalibrationWindow`); None when not
    stated, and then no contact is flagged as beyond it.
    """

    pair: ContactPair
    Ca: float
    Kc: float
    window: CalibrationWindow | None = None

    def __post_init__(self):
        if not isinstance(self.pair, ContactPair):
            raise ValueError(f"pair must be a ContactPair, got {type(self.pair).__name__}")
        if self.window is not None and not isinstance(self.window, CalibrationWindow):
            raise ValueError(f"window must be a CalibrationWindow or None, got {type(self.window).__name__}")
        object.__setattr__(self, "Ca", check_real("Ca", self.Ca, low=0.0, unit="m/N"))
        object.__setattr__(self, "Kc", check_real("Kc", self.Kc, low=0.0, low_inclusive=True, unit="1/N"))
        pair = self.pair
        # Beyond these the force solve works with numbers near the float limits (the paper's
        # values are Ca_hat = 0.026, Kc_hat = 0.0098); stated in SI for this pair.
        check_real("Ca", self.Ca, low=CA_HAT_RANGE[0] * pair.a_Y / pair.P_Y, low_inclusive=True,
                   high=CA_HAT_RANGE[1] * pair.a_Y / pair.P_Y, high_inclusive=True,
                   unit=f"m/N for this contact, i.e. {CA_HAT_RANGE[0]:g} <= Ca P_Y/a_Y <= {CA_HAT_RANGE[1]:g}")
        check_real("Kc", self.Kc, high=KC_HAT_MAX / pair.P_Y, high_inclusive=True,
                   unit=f"1/N for this contact, i.e. Kc P_Y <= {KC_HAT_MAX:g}")
        self._check_monotone_loading()
        self._check_dissipative()

    @classmethod
    def from_dimensionless(cls, pair: ContactPair, Ca_hat: float, Kc_hat: float,
                           window: CalibrationWindow | None = None) -> "VZParams":
        """Ca = Ca_hat a_Y / P_Y [m/N], Kc = Kc_hat / P_Y [1/N]."""
        Ca_hat = check_real("Ca_hat", Ca_hat, low=0.0)
        Kc_hat = check_real("Kc_hat", Kc_hat, low=0.0, low_inclusive=True)
        return cls(pair, Ca_hat * pair.a_Y / pair.P_Y, Kc_hat / pair.P_Y, window)

    @classmethod
    def reference(cls) -> "VZParams":
        """The paper's reference case with its Abaqus calibration Ca = 2.33e-7 m/N, Kc = 2.69e-4 1/N,
        fitted on the load paths to 500, 1000 and 1500 N (to 40.9 P_Y)."""
        pair = ContactPair.reference()
        window = CalibrationWindow(1.0, max(reference_case.PEAKS) / pair.P_Y, None,
                                   "Vu-Quoc & Zhang (1999): Abaqus load paths to 500, 1000, 1500 N")
        return cls(pair, reference_case.CA, reference_case.KC, window)

    @cached_property
    def window_force(self) -> float:
        """The largest force of the calibrated window [N] (inf when no window is stated). The law's
        contact radius grows with P, so the window's radius bound a/R* coincides with this one up
        to the fit error of the constants: the force decides (a/R* is recorded, not tested)."""
        return math.inf if self.window is None else self.window.P_max_over_P_Y * self.pair.P_Y

    def contact_radius_at(self, force):
        """a_ep = a_e + a_p [m] on the virgin loading curve at force P [N]."""
        return self.pair.hertz_radius(force) + self.plastic_radius(force)

    @cached_property
    def full_contact_load(self) -> float:
        """The force [N] at which the law's contact radius a_e + Ca (P - P_Y) reaches R*: the
        end of the law's domain (a contact law needs a << R). a_ep increases with P and is below
        R* at P_Y (a_Y << R*) and above it at P_Y + R*/Ca, so the root is bracketed."""
        pair = self.pair
        if pair.a_Y >= pair.R_star:     # the bracket's lower end is not below R*: the domain is empty
            raise ValueError(f"sigma_y out of range: at first yield the contact radius a_Y = {pair.a_Y:.4g} m already "
                             f"reaches R* = {pair.R_star:.4g} m (E/sigma_y = {pair.E_star / pair.sigma_y:.3g} is far below "
                             f"the elastic-plastic solids a contact law describes): the vz law has no domain")
        return float(brentq(lambda P: float(self.contact_radius_at(P)) - pair.R_star, pair.P_Y,
                            pair.P_Y + pair.R_star / self.Ca, xtol=1e-12 * pair.P_Y, rtol=1e-12))

    @cached_property
    def full_contact_approach(self) -> float:
        """The approach [m] at which the law's contact radius reaches R* (:attr:`full_contact_load`)."""
        return float(self.loading_approach(self.full_contact_load))

    @property
    def Ca_hat(self) -> float:
        """Ca P_Y / a_Y [-]."""
        return self.Ca * self.pair.P_Y / self.pair.a_Y

    @property
    def Kc_hat(self) -> float:
        """Kc P_Y [-]."""
        return self.Kc * self.pair.P_Y

    @cached_property
    def c1(self) -> float:
        """c1 = (3 R* / (4 E*))^(1/3) / Ca [N^(2/3)] in the corrected F(P) (nfdmodel.vz_curve)."""
        return (3.0 * self.pair.R_star / (4.0 * self.pair.E_star)) ** (1.0 / 3.0) / self.Ca

    def curvature_factor(self, force):
        """C_R = 1 + Kc <P - P_Y> [-] (paper eq. 3.6)."""
        return 1.0 + self.Kc * np.maximum(np.asarray(force, dtype=float) - self.pair.P_Y, 0.0)

    def plastic_radius(self, force):
        """a_p = Ca <P - P_Y> [m] (paper eq. 2.5)."""
        return self.Ca * np.maximum(np.asarray(force, dtype=float) - self.pair.P_Y, 0.0)

    def loading_approach(self, force):
        """Approach on the virgin loading curve at force P [N]: explicit in P [m].

        delta = (a_e + a_p)^2 / (C_R R*), a_e = (3 P R*/(4 E*))^(1/3) (paper eqs. 3.4, 3.5);
        Hertz's delta = a_e^2 / R* below P_Y.
        """
        force = np.asarray(force, dtype=float)
        a_ep = self.pair.hertz_radius(force) + self.plastic_radius(force)
        return a_ep**2 / (self.curvature_factor(force) * self.pair.R_star)

    def _energy_excess(self):
        """(largest returned/taken - 1, P_max/P_Y there) over full load-unload cycles."""
        pair = self.pair
        P_max = pair.P_Y * _DISSIPATION_LOADS
        delta_max = self.loading_approach(P_max)
        delta_res, _ = vz_turning_point(delta_max, P_max, np.cbrt(P_max), self)
        returned = P_max * (delta_max - delta_res) / 2.5
        taken = vz_loading_work(delta_max, P_max, self)
        excess = returned / taken - 1.0
        worst = int(np.argmax(excess))
        return float(excess[worst]), float(_DISSIPATION_LOADS[worst])

    def _check_dissipative(self) -> None:
        """Reject (Ca, Kc) for which a load-unload cycle returns more work than it took.

        For turning points P_max / P_Y in [1, 1e6]: the unloading work P_max (delta_max -
        delta_res) / (5/2) (paper eqs. 3.19-3.22) must not exceed the loading work on the
        virgin curve (the law's own exact integral), i.e. e <= 1 (paper 2.1). Partial cycles
        retrace the unloading curve, so full cycles are the only way to create energy. Extreme
        combinations (e.g. Kc_hat = 0.25 at Ca_hat = 0.06) violate it near P_max ~ 3 P_Y.
        """
        excess, load = self._energy_excess()
        if not excess <= _DISSIPATION_SLACK:          # NaN-safe
            raise ValueError(
                f"Ca, Kc out of range: the vz law would create energy (restitution "
                f"{math.sqrt(1.0 + excess):.4f} > 1) for a turning point at P/P_Y = {load:.3g} "
                f"(Ca_hat = {self.Ca_hat:.3g}, Kc_hat = {self.Kc_hat:.3g}); "
                f"{_admissible_Kc_text(self.pair, self.Ca)}")

    def _check_monotone_loading(self) -> None:
        worst = _monotone_violation(self.Ca_hat, self.Kc_hat)
        if worst is not None:
            raise ValueError(
                f"Kc out of range for this Ca: the vz loading curve delta(P) stops increasing near "
                f"P/P_Y = {worst:.3g} (Kc_hat = Kc P_Y = {self.Kc_hat:.3g}, Ca_hat = Ca P_Y/a_Y = "
                f"{self.Ca_hat:.3g}); {_admissible_Kc_text(self.pair, self.Ca)}")


# Loads over which VZParams checks its curve: monotone up to 1e8 P_Y, dissipative up to 1e6 P_Y.
# the checks' loads and slack: the table the C kernel's nfd_vz_admissible uses too (nfd_limits.h)
_MONOTONE_LOADS = np.geomspace(1.0, limits.MONOTONE_LOAD_MAX, limits.MONOTONE_POINTS)
_DISSIPATION_LOADS = np.geomspace(limits.DISSIPATION_LOAD_MIN, limits.DISSIPATION_LOAD_MAX, limits.DISSIPATION_POINTS)
_DISSIPATION_SLACK = limits.DISSIPATION_SLACK


def _monotone_slope_terms(Ca_hat: float):
    """d delta/dP > 0  <=>  2 a_ep' C_R - Kc a_ep > 0; dimensionless with p = P / P_Y this is
    A(p) + Kc_hat B(p) > 0 with A = (2/3) p^(-2/3) + 2 Ca_hat > 0 and
    B = Ca_hat (p - 1) - p^(1/3) (p + 2) / (3 p) (linear in Kc_hat)."""
    p = _MONOTONE_LOADS
    return (2.0 / 3.0 * p ** (-2.0 / 3.0) + 2.0 * Ca_hat,
            Ca_hat * (p - 1.0) - np.cbrt(p) * (p + 2.0) / (3.0 * p))


def _monotone_violation(Ca_hat: float, Kc_hat: float):
    """P/P_Y where the loading curve turns back most steeply, or None when it is monotone."""
    A, B = _monotone_slope_terms(Ca_hat)
    slope = A + Kc_hat * B
    return None if np.all(slope > 0.0) else float(_MONOTONE_LOADS[np.argmin(slope)])  # NaN-safe


def vz_largest_admissible_Kc(pair: ContactPair, Ca: float) -> float:
    """The largest Kc [1/N] that VZParams accepts with this pair and Ca [m/N] (bisection, 1e-6).

    Kc is admissible when the loading curve is monotone up to 1e8 P_Y (a bound known in
    closed form, the slope being linear in Kc_hat: Kc_hat < min over B < 0 of A / (-B), see
    :func:`_monotone_slope_terms`) and no load-unload cycle up to 1e6 P_Y creates energy
    (bisection below that bound; Kc = 0 always passes). It states the admissible range
    in VZParams' error messages.
    """
    return _largest_admissible_Kc(pair, check_real("Ca", Ca, low=0.0, unit="m/N"), native.backend())


@lru_cache(maxsize=256)
def _largest_admissible_Kc(pair: ContactPair, Ca: float, backend: str) -> float:
    # cached: a refused VZParams states the bound, and a fit continued beyond the law's domain asks it
    # again for the same (pair, Ca); each answer costs about 25 energy integrals (backend: the key only)
    Ca_hat = Ca * pair.P_Y / pair.a_Y
    A, B = _monotone_slope_terms(Ca_hat)
    turning = B < 0.0
    upper_hat = float(np.min(A[turning] / -B[turning])) * (1.0 - 1e-9) if turning.any() else math.inf
    if not math.isfinite(upper_hat):
        upper_hat = 1e6                  # never reached by the physical range (B >= 0 everywhere)

    def dissipative(Kc_hat: float) -> bool:
        trial = object.__new__(VZParams)          # unchecked: this IS the check
        object.__setattr__(trial, "pair", pair)
        object.__setattr__(trial, "Ca", Ca)
        object.__setattr__(trial, "Kc", Kc_hat / pair.P_Y)
        object.__setattr__(trial, "window", None)
        return trial._energy_excess()[0] <= _DISSIPATION_SLACK

    if dissipative(upper_hat):
        return upper_hat / pair.P_Y
    low, high = 0.0, upper_hat
    while high - low > 1e-6 * high:
        middle = 0.5 * (low + high)
        low, high = (middle, high) if dissipative(middle) else (low, middle)
    return low / pair.P_Y


def _admissible_Kc_text(pair: ContactPair, Ca: float) -> str:
    largest = vz_largest_admissible_Kc(pair, Ca)
    return (f"for Ca = {Ca:.4g} m/N the admissible range is 0 <= Kc <= {largest:.4g} 1/N "
            f"(Kc_hat <= {largest * pair.P_Y:.4g}; loading curve monotone up to P/P_Y = 1e8, "
            f"no energy created up to 1e6); lower Kc or raise Ca")


def check_si_constants(pair: ContactPair, Ca: float | None, Kc: float | None, names=("Ca", "Kc")) -> None:
    """ValueError naming ``names[0]`` (``names[1]``) when Ca [m/N] (Kc [1/N]) of ``pair`` has a
    dimensionless Ca_hat = Ca P_Y / a_Y outside CA_HAT_USUAL (Kc_hat = Kc P_Y above
    KC_HAT_USUAL_MAX): a unit slip, with the SI value of the typed number read as Ca_hat (Kc_hat)
    when that number is a usual one. None: not given."""
    if Ca is not None:
        Ca_hat, scale = Ca * pair.P_Y / pair.a_Y, pair.a_Y / pair.P_Y
        low, high = CA_HAT_USUAL
        if not low <= Ca_hat <= high:
            hint = (f"; did you give Ca_hat? Ca_hat = {Ca:g} is {names[0]} {Ca * scale:.4g} m/N for this contact"
                    if low <= Ca <= high else "")
            raise ValueError(f"{names[0]} out of range for a solid: need {low:g} <= Ca_hat = Ca P_Y / a_Y <= {high:g}, "
                             f"i.e. {low * scale:.4g} <= {names[0]} <= {high * scale:.4g} m/N (P_Y = {pair.P_Y:.4g} N, "
                             f"a_Y = {pair.a_Y:.4g} m), got {Ca:g} m/N (Ca_hat {Ca_hat:.4g}){hint}")
    if Kc is not None:
        Kc_hat = Kc * pair.P_Y
        if Kc_hat > KC_HAT_USUAL_MAX:
            hint = (f"; did you give Kc_hat? Kc_hat = {Kc:g} is {names[1]} {Kc / pair.P_Y:.4g} 1/N for this contact"
                    if Kc <= KC_HAT_USUAL_MAX else "")
            raise ValueError(f"{names[1]} out of range for a solid: need Kc_hat = Kc P_Y <= {KC_HAT_USUAL_MAX:g}, i.e. "
                             f"{names[1]} <= {KC_HAT_USUAL_MAX / pair.P_Y:.4g} 1/N (P_Y = {pair.P_Y:.4g} N), got {Kc:g} "
                             f"1/N (Kc_hat {Kc_hat:.4g}){hint}")


def vz_params(params) -> VZParams:
    """``params`` when it is a VZParams, else a ValueError naming params."""
    if not isinstance(params, VZParams):
        raise ValueError(f"params for law 'vz' must be VZParams, got {type(params).__name__}")
    return params


def _kernel_params(params: VZParams) -> tuple:
    return native.kernel_params(params.pair, params.Ca, params.Kc, params.window_force, c1=params.c1)


def _vz_loading_branch(params: VZParams):
    pair = params.pair
    radius_per_cube_root = params.c1 * params.Ca        # a_e = (3 R*/(4 E*))^(1/3) P^(1/3)

    def branch(delta, state, index, out=None):
        if delta.min() > pair.delta_Y:          # all plastic (the usual case; delta is finite)
            out = {} if out is None else out
            start = state.a_e_max[index]
            start /= radius_per_cube_root       # P^(1/3) at the old turning point
            P, cube_root, iterations = vz_plastic_solve(delta, start, params, start_is_cube_root=True,
                                                         out=out.get("P_max"))
            a_e_max = np.multiply(cube_root, radius_per_cube_root, out=out.get("a_e_max"))
            delta_res, stiffness = vz_turning_point(
                delta, P, cube_root, params, a_e=a_e_max,
                out=(out.get("delta_res"), out.get("unloading_stiffness")))
            return ({"P_max": P, "delta_res": delta_res, "unloading_stiffness": stiffness,
                     "a_e_max": a_e_max}, int(iterations.max()))
        # Hertz below yield: delta_res = 0, K_u = k_H, a = sqrt(R delta)
        out = {"P_max": hertz_kernel(delta, pair), "delta_res": np.zeros_like(delta),
               "unloading_stiffness": np.full_like(delta, pair.hertz_stiffness),
               "a_e_max": np.sqrt(pair.R_star * np.maximum(delta, 0.0))}
        plastic = np.flatnonzero(delta > pair.delta_Y)
        if plastic.size == 0:
            return out, 0
        delta_plastic = delta[plastic]
        start = state.a_e_max[index[plastic]] / radius_per_cube_root
        P, cube_root, iterations = vz_plastic_solve(delta_plastic, start, params, start_is_cube_root=True)
        out["P_max"][plastic] = P
        out["a_e_max"][plastic] = a_e_max = cube_root * radius_per_cube_root
        out["delta_res"][plastic], out["unloading_stiffness"][plastic] = vz_turning_point(
            delta_plastic, P, cube_root, params, a_e=a_e_max)
        return out, int(iterations.max())

    return branch


def vz_step(delta, state: VZState, params: VZParams):
    """One vz step without committing it: (P [N], :class:`HistoryUpdate`); ``state`` is not modified.

    The force is :func:`vz_force`'s; the update holds the contacts with delta > delta_max, their
    new turning point (delta_max, P_max, delta_res, K_u = (4/3) E* C_Rmax^(3/2) sqrt(R*), a_e,max;
    paper eqs. 3.19-3.22) and the largest Newton iteration count of the step.
    """
    vz_params(params)
    check_state(state, VZState, "vz")
    delta, shape = check_delta(delta, state.n)
    if native.active():
        pair = params.pair
        force, update, (_, beyond, largest_P, widest, widest_radius, _) = native.turning_point_step(
            native.law_loading("vz", _kernel_params(params)), delta, state, pair, True)
        if update.size:
            check_contact_radius_below_R(widest_radius, pair.R_star, float(update.values.delta_max[widest]), params)
            if beyond:
                update = dataclasses.replace(update, beyond_window=beyond, largest_load_over_P_Y=largest_P / pair.P_Y)
        return restore_shape(force, shape), update
    force, update = turning_point_step(delta, state, _vz_loading_branch(params), True, params.pair)
    if update.size:                  # sparse: only the contacts whose turning point moved
        update = _check_reach(update, params)
    return restore_shape(force, shape), update


def _check_reach(update, params: VZParams):
    """The contacts that loaded in this step against R* (ValueError) and the calibrated window
    (counted in the update; ContactLaw.step warns): a few passes over the loading contacts only."""
    pair = params.pair
    P_max = update.values.P_max
    radius = update.values.a_e_max + params.Ca * np.maximum(P_max - pair.P_Y, 0.0)
    largest = int(np.argmax(radius))
    check_contact_radius_below_R(float(radius[largest]), pair.R_star, float(update.values.delta_max[largest]),
                                 params)
    P_limit = params.window_force
    if not float(P_max.max()) > P_limit:
        return update
    beyond = int(np.count_nonzero(P_max > P_limit))
    return dataclasses.replace(update, beyond_window=beyond, largest_load_over_P_Y=float(P_max.max()) / pair.P_Y)


def vz_force_with_iterations(delta, state: VZState, params: VZParams):
    """:func:`vz_force` that also returns the largest number of Newton iterations of the step."""
    force, update = vz_step(delta, state, params)
    return force, apply_update(state, update, copy=True), update.newton_iterations


def vz_force(delta, state: VZState, params: VZParams):
    """Vu-Quoc & Zhang (1999) displacement-driven NFD force P(delta, history) [N].

    Loading beyond the turning point (delta > delta_max): Hertz for delta <= delta_Y, else the
    root of the corrected F(P) (:func:`vz_plastic_force`, paper eqs. 3.4-3.14). Unloading and
    reloading below delta_max (paper eqs. 3.19-3.22): a_p and C_R frozen at P_max,
    P = (4/3) E* C_Rmax^(3/2) sqrt(R*) <delta - delta_res>^(3/2), which retraces back to
    (delta_max, P_max) and then continues plastically; separation (P = 0) for delta <= delta_res,
    re-contact above it. Any (R*, E*). Pure: :func:`vz_step` + a copying commit.
    """
    return step_and_commit(vz_step, delta, state, params)


def vz_newton_iterations(delta, state: VZState, params: VZParams) -> np.ndarray:
    """Newton iterations per contact for one vz step (0 where no Newton solve is needed)."""
    delta, _ = check_delta(delta, state.n)
    counts = np.zeros(delta.shape[0], dtype=np.int64)
    plastic = np.flatnonzero((delta > state.delta_max) & (delta > params.pair.delta_Y))
    if plastic.size:
        start = state.a_e_max[plastic] / (params.c1 * params.Ca)
        _, _, counts[plastic] = vz_plastic_solve(delta[plastic], start, params, start_is_cube_root=True)
    return counts


LAW = ContactLaw("vz", "Vu-Quoc & Zhang (1999) elastoplastic NFD model", vz_force, VZState, vz_loading_work, 1.5,
                 vz_step, params_function=vz_params, radii_function=plastic_radii, fitted=True,
                 collision_params=_kernel_params)

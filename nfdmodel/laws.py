"""Normal contact force laws, displacement-driven and vectorised over contacts.

Each law is one kernel used two ways (MercuryDPM style: compute the trial state, then commit it):

* ``law.step(delta, state, params) -> (P, update)``: the force and the SPARSE trial history, a
  :class:`HistoryUpdate` holding only the contacts whose turning point moved (``update.index``)
  and their new history (``update.values``, a state of the same class over those contacts);
  ``state`` is not modified;
* ``law.commit(state, update)`` writes the update into ``state``'s arrays IN PLACE (the caller
  owns the state; nobody else may hold it), cost O(len(update.index));
* ``law.force(delta, state, params) -> (P, new_state)``: the pure function, step + a copying
  commit (``state`` is never modified; ``new_state`` is ``state`` itself when no turning point
  moved, otherwise a copy).

* ``delta``  total approach ("overlap") of each contact [m], shape (n,), any float dtype;
* ``state``  the named per-contact history (a frozen dataclass of float64 arrays of shape (n,));
* ``P``      normal force [N], float64, >= 0, shape of ``delta``.

In a DEM loop that owns its history, ``P, update = law.step(delta, state, params);
law.commit(state, update)`` avoids copying the n-contact history whenever one contact loads
plastically (the pure ``force`` copies all its arrays then).

Laws (chosen by name with :func:`get_law`):

``hertz``         Hertz (Johnson 1985 eq. 4.23): P = (4/3) E* sqrt(R*) delta^(3/2); elastic.
``vz``            Vu-Quoc & Zhang (1999) elastoplastic NFD model, SPEC section 3.
``thornton``      Thornton (1997): Hertz to yield, then linear; Hertzian unloading with an
                  enlarged curvature radius, SPEC section 5.
``walton-braun``  Walton & Braun (1986): P = K1 delta loading, P = K2 (delta - delta_res)
                  unloading, e = sqrt(K1/K2), SPEC section 5.

The three elastoplastic laws share one history (:class:`TurningPointHistory`): the turning point
(delta_max, P_max), the approach delta_res at which the unloading curve through it reaches P = 0,
and that curve's constant K_u. Unloading AND reloading below delta_max follow

    P = K_u <delta - delta_res>^n

with n = 3/2 (vz, thornton: Hertzian unloading) or n = 1 (walton-braun); K_u and delta_res are
fixed when the turning point moves so that the curve passes through (delta_max, P_max): the force
is continuous at every turning point, reloading retraces unloading, and a constant delta gives
a constant force. For vz this is the paper's eq. 3.22, K_u = (4/3) E* C_Rmax^(3/2) sqrt(R*).
Beyond delta_max the contact loads on the virgin curve and the turning point moves.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, fields
from functools import cached_property, lru_cache
from typing import Callable

import numpy as np

from . import reference_case
from .materials import ContactPair
from .validation import check_real

NEWTON_TOLERANCE = 1e-10        # relative tolerance on P of the vz plastic-loading solve
NEWTON_MAX_ITERATIONS = 200     # never reached: the bracket halves at worst every other step
CA_HAT_RANGE = (1e-8, 1e4)      # admissible Ca P_Y / a_Y (paper: 0.026)
KC_HAT_MAX = 1e4                # admissible Kc P_Y (paper: 0.0098)
_TINY = 1e-300
_BLOCK = 16384                  # contacts per block of the step kernel (temporaries stay in cache)
_GAUSS_NODES, _GAUSS_WEIGHTS = np.polynomial.legendre.leggauss(12)


# ----------------------------------------------------------------------------------- parameters
def _as_pair(params, law: str) -> ContactPair:
    if isinstance(params, ContactPair):
        return params
    pair = getattr(params, "pair", None)
    if isinstance(pair, ContactPair):
        return pair
    raise ValueError(f"params for law '{law}' must be a ContactPair or carry one as .pair, "
                     f"got {type(params).__name__}")


@dataclass(frozen=True)
class VZParams:
    """Parameters of the Vu-Quoc & Zhang (1999) NFD model.

    pair: the contact (R*, E*, yield point); Ca [m/N] > 0: plastic contact-radius rate,
    a_p = Ca <P - P_Y> (paper eq. 2.5); Kc [1/N] >= 0: curvature-factor rate,
    C_R = 1 + Kc <P - P_Y> (paper eq. 3.6).

    Validation also requires the loading curve delta(P) = a_ep^2 / (C_R R*) to increase with P
    (checked for P_Y <= P <= 1e8 P_Y); otherwise the displacement-driven force is not unique.
    Dimensionless forms (SPEC section 7): Ca_hat = Ca P_Y / a_Y, Kc_hat = Kc P_Y.
    """

    pair: ContactPair
    Ca: float
    Kc: float

    def __post_init__(self):
        if not isinstance(self.pair, ContactPair):
            raise ValueError(f"pair must be a ContactPair, got {type(self.pair).__name__}")
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
    def from_dimensionless(cls, pair: ContactPair, Ca_hat: float, Kc_hat: float) -> "VZParams":
        """Ca = Ca_hat a_Y / P_Y [m/N], Kc = Kc_hat / P_Y [1/N] (SPEC section 7)."""
        Ca_hat = check_real("Ca_hat", Ca_hat, low=0.0)
        Kc_hat = check_real("Kc_hat", Kc_hat, low=0.0, low_inclusive=True)
        return cls(pair, Ca_hat * pair.a_Y / pair.P_Y, Kc_hat / pair.P_Y)

    @classmethod
    def reference(cls) -> "VZParams":
        """The paper's reference case with its Abaqus calibration Ca = 2.33e-7 m/N, Kc = 2.69e-4 1/N."""
        return cls(ContactPair.reference(), reference_case.CA, reference_case.KC)

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
        """c1 = (3 R* / (4 E*))^(1/3) / Ca [N^(2/3)] in F(P) (SPEC section 3)."""
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
        delta_res, _ = _vz_turning_point(delta_max, P_max, np.cbrt(P_max), self)
        returned = P_max * (delta_max - delta_res) / 2.5
        taken = _vz_loading_work(delta_max, P_max, self)
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
_MONOTONE_LOADS = np.geomspace(1.0, 1e8, 2000)
_DISSIPATION_LOADS = np.geomspace(1.0 + 1e-6, 1e6, 200)
_DISSIPATION_SLACK = 1e-9


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
    (bisection below that bound; Kc = 0 always passes). Used to state the admissible range
    in VZParams' error messages.
    """
    Ca = check_real("Ca", Ca, low=0.0, unit="m/N")
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


@dataclass(frozen=True)
class WaltonBraunParams:
    """Walton & Braun (1986) stiffnesses: K1 [N/m] > 0 loading, K2 [N/m] >= K1 unloading.

    e = sqrt(K1/K2) in a collision. Defaults from a pair (:meth:`from_vz`): secants of the vz
    loading and unloading curves through a reference turning point.
    """

    pair: ContactPair
    K1: float
    K2: float

    def __post_init__(self):
        if not isinstance(self.pair, ContactPair):
            raise ValueError(f"pair must be a ContactPair, got {type(self.pair).__name__}")
        object.__setattr__(self, "K1", check_real("K1", self.K1, low=0.0, unit="N/m"))
        object.__setattr__(self, "K2", check_real("K2", self.K2, low=self.K1, low_inclusive=True,
                                                  unit="N/m (K2 >= K1, otherwise energy is created)"))

    @classmethod
    def from_vz(cls, vz_params: "VZParams", P_ref: float | None = None) -> "WaltonBraunParams":
        """Secant stiffnesses of the vz model through the turning point at P_ref [N].

        K1 = P_ref / delta_max (loading secant), K2 = P_ref / (delta_max - delta_res) (unloading
        secant), so that e = sqrt(K1/K2) equals the vz energy ratio of a triangle-shaped cycle.
        P_ref defaults to 40 P_Y (the paper's AFG load path: 1500 N ~ 41 P_Y).
        """
        pair = vz_params.pair
        P_ref = 40.0 * pair.P_Y if P_ref is None else check_real("P_ref", P_ref, low=pair.P_Y, unit="N")
        delta_max = float(vz_params.loading_approach(P_ref))
        delta_res = _vz_residual_approach(delta_max, np.asarray(P_ref), vz_params)
        return cls(pair, P_ref / delta_max, P_ref / (delta_max - float(delta_res)))

    @classmethod
    def from_pair(cls, pair: ContactPair) -> "WaltonBraunParams":
        """Defaults for a bare pair: :meth:`from_vz` with the paper's dimensionless Ca_hat, Kc_hat."""
        reference = VZParams.reference()
        return cls.from_vz(VZParams.from_dimensionless(pair, reference.Ca_hat, reference.Kc_hat))


# ---------------------------------------------------------------------------------- histories
@dataclass(frozen=True)
class HertzState:
    """Hertz contact has no history; ``n`` is the number of contacts."""

    n: int


@dataclass(frozen=True)
class TurningPointHistory:
    """Per-contact history of an elastoplastic law [SI].

    delta_max [m]: largest approach so far (turning point); P_max [N]: force there;
    delta_res [m]: approach at which the unloading curve through (delta_max, P_max) reaches 0
    (residual indentation; 0 while the contact never yielded); unloading_stiffness: the constant
    K_u of that curve, P = K_u <delta - delta_res>^n (vz: K_u = (4/3) E* C_Rmax^(3/2) sqrt(R*),
    paper eq. 3.22, [N/m^1.5]; thornton: (4/3) E* sqrt(R_p*); walton-braun: K2 [N/m]).
    """

    delta_max: np.ndarray
    P_max: np.ndarray
    delta_res: np.ndarray
    unloading_stiffness: np.ndarray

    @classmethod
    def virgin(cls, n: int):
        n = _contact_count(n)
        return cls(**{f.name: np.zeros(n) for f in fields(cls)})

    @property
    def n(self) -> int:
        return self.delta_max.shape[0]

    def updated(self, index, **values):
        """A new history with the contacts ``index`` moved to a new turning point (no mutation);
        ``values`` gives the new value of every field for those contacts."""
        out = {}
        for f in fields(self):
            array = getattr(self, f.name).copy()
            array[index] = values[f.name]
            out[f.name] = array
        return type(self)(**out)


@dataclass(frozen=True)
class VZState(TurningPointHistory):
    """History of the vz law; adds a_e_max [m], the elastic contact radius at the turning point,
    a_e,max = (3 P_max R*/(4 E*))^(1/3) (paper eq. 3.19), which also starts the next Newton solve.
    C_Rmax = 1 + Kc<P_max - P_Y> and a_p,max = Ca<P_max - P_Y> are functions of P_max and are
    derived on request (:meth:`ContactLaw.contact_state`)."""

    a_e_max: np.ndarray


class ThorntonState(TurningPointHistory):
    """History of the Thornton law (delta_res is Thornton's delta_p)."""


class WaltonBraunState(TurningPointHistory):
    """History of the Walton-Braun law (delta_res = delta_max - P_max / K2)."""


@dataclass(frozen=True)
class HistoryUpdate:
    """The trial history of one step, sparse: only the contacts whose turning point moved.

    index: the contacts (positions 0..n-1 in the state, increasing, int64) that loaded beyond
    their turning point delta_max in this step, shape (k,);
    values: their new history, a state of the SAME class as the law's state (VZState,
    ThorntonState, WaltonBraunState; named fields, [SI] as there) over those k contacts: contact
    index[i] gets values.<field>[i]; a HertzState(0) for hertz (no history);
    n: the number of contacts of the state the step was computed from;
    newton_iterations: the largest number of Newton iterations of the step (vz plastic loading,
    :func:`_vz_plastic_solve`; 0 for the other laws and when no contact loads plastically).

    Made by :meth:`ContactLaw.step`; applied by :meth:`ContactLaw.commit` (in place) or
    :meth:`ContactLaw.committed` (copy). The contacts not in ``index`` keep their history.
    """

    index: np.ndarray
    values: object
    n: int
    newton_iterations: int = 0

    @property
    def size(self) -> int:
        """Number of contacts whose turning point moved (k)."""
        return int(self.index.shape[0])


_EMPTY_VALUES: dict = {}     # history class -> (read-only empty index, empty history): shared, never written


def _empty_update(state, n: int) -> HistoryUpdate:
    cls = type(state)
    empty = _EMPTY_VALUES.get(cls)
    if empty is None:
        index = np.empty(0, dtype=np.int64)
        index.flags.writeable = False
        values = HertzState(0) if cls is HertzState else cls(**{name: index.astype(float) for name in
                                                                _field_names(cls)})
        for name in _field_names(cls):
            getattr(values, name).flags.writeable = False
        empty = _EMPTY_VALUES[cls] = (index, values)
    return HistoryUpdate(empty[0], empty[1], n, 0)


@lru_cache(maxsize=None)
def _field_names(cls) -> tuple:
    """Names of the per-contact arrays of a history class (none for HertzState)."""
    return () if cls is HertzState else tuple(f.name for f in fields(cls))


def _check_update(state, update) -> None:
    """A ValueError naming ``update`` when it does not belong to ``state`` (class, length, index)."""
    if not isinstance(update, HistoryUpdate):
        raise ValueError(f"update must be a HistoryUpdate (from ContactLaw.step), got {type(update).__name__}")
    if type(update.values) is not type(state):
        raise ValueError(f"update does not match state: update.values is a {type(update.values).__name__} "
                         f"but state is a {type(state).__name__} (commit an update to the state of the "
                         f"law that computed it)")
    n = state.n
    if update.n != n:
        raise ValueError(f"update does not match state: update was computed for {update.n} contacts "
                         f"but state holds {n}")
    index = update.index
    if not (isinstance(index, np.ndarray) and index.ndim == 1 and index.dtype.kind in "iu"):
        raise ValueError(f"update.index must be a 1-d integer array of contact positions, got "
                         f"{type(index).__name__} {getattr(index, 'dtype', '')}")
    k = index.shape[0]
    if isinstance(state, HertzState):
        if k:
            raise ValueError(f"update does not match state: a Hertz contact has no history, but "
                             f"update.index holds {k} contacts")
        return
    for name in _field_names(type(state)):
        values = getattr(update.values, name)
        if not (isinstance(values, np.ndarray) and values.shape == (k,)):
            raise ValueError(f"update does not match state: update.index has {k} contacts but "
                             f"update.values.{name} has shape {np.shape(values)}")
    if k and not (0 <= int(index.min()) and int(index.max()) < n):
        raise ValueError(f"update.index out of range: contact positions must be in 0..{n - 1} "
                         f"(state holds {n} contacts), got {int(index.min())}..{int(index.max())}")


def _apply_update(state, update: HistoryUpdate, copy: bool):
    """Write ``update`` (checked by the caller) into ``state`` (in place) or into a copy of it;
    returns the new state (``state`` itself when the update is empty)."""
    if update.index.shape[0] == 0:
        return state
    names = _field_names(type(state))
    if copy:
        state = type(state)(**{name: getattr(state, name).copy() for name in names})
    index, values = update.index, update.values
    for name in names:
        getattr(state, name)[index] = getattr(values, name)
    return state


# ---------------------------------------------------------------------------------- validation
def _contact_count(n) -> int:
    """n as a number of contacts (an integer >= 0), or a ValueError naming n."""
    value = check_real("n", n, low=0, low_inclusive=True, unit="(number of contacts)")
    if value != int(value):
        raise ValueError(f"n must be a whole number of contacts (>= 0), got {n!r}")
    return int(value)


def _check_delta(delta, n_expected: int | None):
    """delta as a flat contiguous float64 array and its original shape; ValueError naming delta
    if it is not real, not finite or has the wrong number of contacts (checked before any
    force is computed: no floating-point warnings from bad input)."""
    delta = np.asarray(delta)
    if delta.dtype.kind not in "fiu":
        raise ValueError(f"delta must be a real array of approaches [m], got dtype {delta.dtype}")
    shape = delta.shape
    delta = np.ascontiguousarray(delta, dtype=np.float64).reshape(-1)
    # One cheap reduction first; the elementwise check only when something is off.
    if not math.isfinite(float(np.add.reduce(delta))) and not np.isfinite(delta).all():
        raise ValueError("delta must be finite (no NaN or inf) approaches [m]")
    if n_expected is not None and delta.shape[0] != n_expected:
        raise ValueError(f"delta has {delta.shape[0]} contacts but the state holds {n_expected}")
    return delta, shape


def _check_force(force, delta, pair: ContactPair, total: float | None = None):
    """Overlaps so large that the force overflows (delta ~ 1e100 m) give a ValueError naming
    delta, never inf or NaN in a result. One cheap reduction (or ``total``, a sum of values
    that includes every entry of force, computed by the caller); elementwise only on failure."""
    if total is None:
        total = float(np.add.reduce(force))
    if not math.isfinite(total) and not np.isfinite(force).all():
        worst = int(np.flatnonzero(~np.isfinite(force))[0])
        raise ValueError(f"delta out of range: the force overflows at delta = {delta[worst]:g} m "
                         f"(contact {worst}, delta/R* = {delta[worst] / pair.R_star:.3g}); overlaps "
                         f"this large are far outside any contact model")
    return force


def _check_state(state, cls, law):
    if not isinstance(state, cls):
        raise ValueError(f"state for law '{law}' must be a {cls.__name__} "
                         f"(use get_law('{law}').initial_state(n)), got {type(state).__name__}")
    return state


# ------------------------------------------------------------------------------- shared kernels
def _blocks(n: int):
    """Slices of at most _BLOCK contacts covering 0..n-1 (one slice(None) when n <= _BLOCK)."""
    if n <= _BLOCK:
        return (slice(None),)
    return tuple(slice(first, min(first + _BLOCK, n)) for first in range(0, n, _BLOCK))


def _turning_point_step(delta, state, loading_branch, three_halves: bool, pair: ContactPair):
    """Force and sparse trial history of a turning-point law (module doc): (P, HistoryUpdate).

    Unloading/reloading for all contacts: P = K_u <delta - delta_res>^n (n = 3/2 if
    ``three_halves``, else 1); then, for the contacts with delta > delta_max,
    ``loading_branch(delta, state, index, out) -> (new field values, iterations)`` on the virgin
    curve (it may write the values into the arrays of the dict ``out``, or None, and return
    those arrays), which moves their turning point (P_max is the new force, delta_max the new approach).
    ``state`` is not modified; the update's arrays share no memory with ``delta`` or ``state``.

    Work is done in blocks of _BLOCK contacts (loading contacts for the loading branch) so that
    the temporaries stay in cache; every operation is elementwise, so the result does not
    depend on the blocking. ``delta`` is checked by the caller (:func:`_check_delta`); the
    overflow check of the force (:func:`_check_force`, ValueError naming delta) uses a sum
    taken block by block while the forces are in cache, instead of one more pass.
    """
    n = delta.shape[0]
    force = np.empty(n)
    loading_mask = np.empty(n, dtype=bool)
    gap_buffer = np.empty(min(n, _BLOCK))
    arrays = (delta, force, state.delta_res, state.unloading_stiffness, state.delta_max, loading_mask)
    force_sum = 0.0
    add = np.add.reduce
    for d, f, delta_res, stiffness, delta_max, mask in (
            (arrays,) if n <= _BLOCK else (tuple(a[block] for a in arrays) for block in _blocks(n))):
        gap = gap_buffer if f.shape[0] == gap_buffer.shape[0] else gap_buffer[:f.shape[0]]
        np.subtract(d, delta_res, out=gap)
        np.maximum(gap, 0.0, out=gap)
        if three_halves:
            np.sqrt(gap, out=f)
            f *= gap
            f *= stiffness
        else:
            np.multiply(gap, stiffness, out=f)
        force_sum += add(f)
        np.greater(d, delta_max, out=mask)
    loading = loading_mask.nonzero()[0]                  # (np.flatnonzero without its wrappers)
    k = loading.shape[0]
    if k == 0:
        update = _empty_update(state, n)
    elif k <= _BLOCK:
        delta_loading = delta[loading]
        new_values, iterations = loading_branch(delta_loading, state, loading)
        P = new_values["P_max"]
        force[loading] = P
        force_sum += add(P)
        update = HistoryUpdate(loading, type(state)(delta_max=delta_loading, **new_values), n, int(iterations))
    else:
        values = {name: np.empty(k) for name in _field_names(type(state))}
        iterations = 0
        for block in _blocks(k):
            index = loading[block]
            delta_loading = np.take(delta, index, out=values["delta_max"][block], mode="clip")
            out = {name: values[name][block] for name in values if name != "delta_max"}
            new_values, block_iterations = loading_branch(delta_loading, state, index, out)
            for name, array in new_values.items():
                if array is not out[name]:          # not written in place by the branch
                    values[name][block] = array
            P = new_values["P_max"]
            force[index] = P
            force_sum += add(P)
            iterations = max(iterations, int(block_iterations))
        update = HistoryUpdate(loading, type(state)(**values), n, iterations)
    # force_sum covers every entry of force (and the overwritten unloading values: a false
    # alarm there only triggers the exact elementwise test)
    _check_force(force, delta, pair, float(force_sum))
    return force, update


def _restore_shape(force, shape):
    return force.reshape(shape) if shape != force.shape else force


# ---------------------------------------------------------------------------------------- hertz
def hertz_step(delta, state: HertzState, params):
    """Hertz (Johnson 1985 eq. 4.23): P = (4/3) E* sqrt(R*) <delta>^(3/2) [N] and an empty
    :class:`HistoryUpdate` (no history). params: a ContactPair (or anything with .pair)."""
    pair = _as_pair(params, "hertz")
    _check_state(state, HertzState, "hertz")
    delta, shape = _check_delta(delta, state.n)
    force = _restore_shape(_check_force(_hertz_kernel(delta, pair), delta, pair), shape)
    return force, _empty_update(state, state.n)


def hertz_force(delta, state: HertzState, params):
    """Hertz (Johnson 1985 eq. 4.23): P = (4/3) E* sqrt(R*) <delta>^(3/2) [N]; no history.

    params: a ContactPair (or anything with .pair). Returns (P, state) (the state unchanged).
    """
    pair = _as_pair(params, "hertz")
    _check_state(state, HertzState, "hertz")
    delta, shape = _check_delta(delta, state.n)
    return _restore_shape(_check_force(_hertz_kernel(delta, pair), delta, pair), shape), state


def _hertz_kernel(delta, pair):
    d = np.maximum(delta, 0.0)
    force = np.sqrt(d)
    force *= d
    force *= pair.hertz_stiffness
    return force


# ------------------------------------------------------------------------------------------- vz
def _vz_residual_approach(delta_max, P_max, params: VZParams):
    """delta_res = delta_max - a_e,max^2 / (C_Rmax R*) [m] (paper eqs. 3.19-3.21), >= 0."""
    a_e = params.pair.hertz_radius(P_max)
    elastic_recovery = a_e**2 / (params.curvature_factor(P_max) * params.pair.R_star)
    return np.maximum(delta_max - elastic_recovery, 0.0)


def _vz_turning_point(delta_max, P_max, cube_root, params: VZParams, a_e=None, out=None):
    """delta_res [m] and K_u [N/m^1.5] of a new plastic turning point (paper eqs. 3.19-3.22);
    cube_root = P_max^(1/3) gives a_e,max = (3 R*/(4 E*))^(1/3) P_max^(1/3) without a cube root
    (or pass a_e = a_e,max [m] when already computed: cube_root * c1 * Ca); ``out``: optional
    (delta_res, K_u) arrays to write into.

    K_u = (4/3) E* C_Rmax^(3/2) sqrt(R*) equals P_max / (delta_max - delta_res)^(3/2) exactly;
    the second form is used, with the STORED (rounded) delta_res, so the unloading curve passes
    through (delta_max, P_max) to round-off. The first form is off by up to 1e-5 relative when
    the elastic recovery is tiny next to delta_max (Ca at 1e3 x the reference, P ~ 1e6 P_Y:
    delta_max - delta_res ~ 1e-11 delta_max), which made the force jump at the turning point.
    If the recovery is below the spacing of floats at delta_max, delta_res is the float just
    below delta_max (an unloading curve that drops to zero within one ulp, as the model says).
    """
    pair = params.pair
    curvature = P_max - pair.P_Y
    curvature *= params.Kc
    curvature += 1.0
    curvature *= pair.R_star                                # C_Rmax R*
    if a_e is None:
        a_e = cube_root * (params.c1 * params.Ca)
    delta_res_out, stiffness_out = (None, None) if out is None else out
    recovery = a_e * a_e
    recovery /= curvature                                   # a_e,max^2 / (C_Rmax R*)
    delta_res = np.subtract(delta_max, recovery, out=recovery if delta_res_out is None else delta_res_out)
    np.maximum(delta_res, 0.0, out=delta_res)
    # delta_res = min(delta_res, the float below delta_max); only the (rare) contacts with
    # delta_res >= delta_max change, so nextafter (slow) runs on those alone.
    at_turning_point = np.greater_equal(delta_res, delta_max)
    if at_turning_point.any():
        np.copyto(delta_res, np.nextafter(delta_max, 0.0), where=at_turning_point)
    gap = np.subtract(delta_max, delta_res, out=curvature)
    stiffness = np.sqrt(gap, out=stiffness_out)
    stiffness *= gap
    np.divide(P_max, stiffness, out=stiffness)
    return delta_res, stiffness


def _vz_residual(u, b, params: VZParams):
    """F and dF/du at P = u^3 (u = P^(1/3) [N^(1/3)]); F is SPEC section 3's corrected F(P):

        F    = (P - P_Y) + c1 u - b sqrt(1 + Kc (P - P_Y)),       b = sqrt(R* delta)/Ca
        dF/du = 3 u^2 F'(P) = 3 u^2 (1 - Kc b / (2 sqrt(C_R))) + c1
    """
    P_Y, Kc, c1 = params.pair.P_Y, params.Kc, params.c1
    u_sq = u * u
    F = u_sq * u                                            # P
    sqrt_curvature = F * Kc
    sqrt_curvature += 1.0 - Kc * P_Y
    np.sqrt(sqrt_curvature, out=sqrt_curvature)
    F -= P_Y
    term = np.multiply(u, c1)
    F += term
    F -= np.multiply(b, sqrt_curvature, out=term)
    slope = np.divide(b, sqrt_curvature, out=sqrt_curvature)
    slope *= -0.5 * Kc
    slope += 1.0
    slope *= np.multiply(u_sq, 3.0, out=u_sq)
    slope += c1
    return F, slope


def vz_plastic_force(delta, P_start, params: VZParams, tolerance: float = NEWTON_TOLERANCE):
    """Force on the plastic loading branch (see :func:`_vz_plastic_solve`): (P [N], iterations)."""
    delta = np.asarray(delta, dtype=float)
    P_start = np.broadcast_to(np.asarray(P_start, dtype=float), delta.shape)
    force, _, iterations = _vz_plastic_solve(delta, P_start, params, tolerance)
    return force, iterations


def _vz_plastic_solve(delta, P_start, params: VZParams, tolerance: float = NEWTON_TOLERANCE,
                      start_is_cube_root: bool = False, out=None):
    """Force on the plastic loading branch, delta > delta_Y [m]: the root P [N] of

        F(P)  = (P - P_Y) + c1 P^(1/3) - sqrt((1 + Kc (P - P_Y)) R* delta) / Ca = 0
        F'(P) = 1 + c1 P^(-2/3) / 3 - Kc sqrt(R* delta) / (2 Ca sqrt(1 + Kc (P - P_Y)))

    (Vu-Quoc & Zhang 1999 eq. 3.14 with the dimensional misprint fixed, SPEC section 3;
    c1 = (3 R*/(4 E*))^(1/3) / Ca). Newton runs on u = P^(1/3) (dF/du = 3 u^2 F'(P); same root,
    no cube root per iteration), vectorised, with P_start (the force at a smaller approach, e.g.
    the previous P_max) as start and lower bracket, P_lo = max(P_start, P_Y), F(P_lo) <= 0.

    1. Fast path: two Newton steps s1, s2 for all contacts. Accepted when F' > 0 at both
       iterates, |s2| <= 0.01 |s1| (quadratic regime) and the a-posteriori error of the result,
       10 |s2|^3 / s1^2, is below the tolerance, and P >= P_lo. (DEM steps: almost all.)
    2. The others: safeguarded Newton on the bracket [P_lo, P_hi], P_hi = P_Y + x_hi with
       Ca^2 x_hi^2 = R* delta (1 + Kc x_hi) (a_ep >= Ca x bounds delta(P) from below, so
       F(P_hi) >= 0). A Newton step that leaves the bracket, goes uphill or does not halve the
       previous step is replaced by bisection (geometric while P_hi/P_lo > 2); stop when the
       step or the bracket is below the tolerance. Only unconverged contacts are iterated.

    Relative tolerance ``tolerance`` on P (1e-10). Returns (P [N], u = P^(1/3), Newton iterations
    per contact); P is written into ``out`` if given.
    """
    pair = params.pair
    P_Y, Ca, Kc = pair.P_Y, params.Ca, params.Kc
    tol_u = tolerance / 3.0                                 # dP/P = 3 du/u
    R_delta = pair.R_star * delta
    b = np.sqrt(R_delta)
    b /= Ca
    # start_is_cube_root: P_start holds P^(1/3) already (from the history; a cube root costs
    # ten square roots).
    u_lo = np.maximum(P_start, P_Y ** (1.0 / 3.0)) if start_is_cube_root else np.cbrt(np.maximum(P_start, P_Y))
    u_min = u_lo * (1.0 - 1e-15)
    # Fast path (temporaries reused through out=; the operations and their rounding are those
    # of the formulas in the comments).
    F, slope = _vz_residual(u_lo, b, params)
    step_1 = np.divide(F, slope, out=F)                     # s1 = F/F'
    u = u_lo - step_1
    np.maximum(u, u_min, out=u)
    ok = slope > 0.0
    F, slope = _vz_residual(u, b, params)
    ok &= np.greater(slope, 0.0)
    step_2 = np.divide(F, slope, out=F)                     # s2
    u -= step_2
    abs_1, abs_2 = np.abs(step_1, out=step_1), np.abs(step_2, out=step_2)
    # quadratic regime with a small a-posteriori error, or a step already below round-off level:
    # ((|s2| <= 0.01 |s1|) & (10 |s2|^3 <= tol_u u s1^2)) | (|s2| <= 0.01 tol_u u)
    bound = np.multiply(abs_1, 0.01, out=slope)
    accept = abs_2 <= bound
    error = np.multiply(abs_2, 10.0)
    error *= abs_2
    error *= abs_2
    allowed = np.multiply(u, tol_u)
    allowed *= abs_1
    allowed *= abs_1
    accept &= np.less_equal(error, allowed)
    np.multiply(u, 0.01 * tol_u, out=bound)
    accept |= np.less_equal(abs_2, bound)
    ok &= accept
    ok &= np.greater_equal(u, u_min)
    iterations = np.full(delta.shape[0], 2, dtype=np.int64)
    if ok.all():
        P = np.multiply(u, u, out=out)
        P *= u
        return P, u, iterations
    # Safe path on the remaining contacts.
    rest = np.flatnonzero(~ok)
    b_r = b[rest]
    lo = u_lo[rest]
    R_delta_r = R_delta[rest]
    x_hi = (R_delta_r * Kc + np.sqrt((R_delta_r * Kc) ** 2 + 4.0 * Ca**2 * R_delta_r)) / (2.0 * Ca**2)
    hi = np.maximum(np.cbrt((P_Y + x_hi) * (1.0 + 1e-12)), lo)
    u_fast = u[rest]
    inside = (u_fast > lo) & (u_fast < hi)             # NaN-safe: restart from P_lo otherwise
    u_r = np.where(inside, u_fast, lo)
    # Working arrays hold the unconverged contacts only (``position`` in rest); a contact's
    # result is written once, when it converges, and the set is compacted then.
    previous_step = hi - lo
    count = np.zeros(rest.size, dtype=np.int64)
    position = np.arange(rest.size)
    ua, la, ha, ba = u_r, lo, hi, b_r
    for iteration in range(1, NEWTON_MAX_ITERATIONS + 1):
        F, slope = _vz_residual(ua, ba, params)
        below = F < 0.0
        la = np.where(below, ua, la)
        ha = np.where(below, ha, ua)
        with np.errstate(divide="ignore", invalid="ignore"):
            step = F / slope
        u_newton = ua - step
        abs_step = np.abs(step)
        rising = slope > 0.0                    # F' > 0: the Newton step points to the root
        newton_ok = (u_newton > la) & (u_newton < ha) & rising & (abs_step <= 0.5 * previous_step)
        bisection = np.where(ha > 1.26 * la, np.sqrt(la * ha), 0.5 * (la + ha))   # 1.26^3 ~ 2
        # A Newton step below the tolerance ends the solve even if it rounds onto the bracket end.
        tiny_step = rising & (abs_step <= tol_u * ua)
        u_new = np.where(newton_ok, u_newton, bisection)
        u_new = np.where(tiny_step, np.clip(u_newton, la, ha), u_new)
        root = F == 0.0
        u_new = np.where(root, ua, u_new)
        taken = np.abs(u_new - ua)
        converged = root | tiny_step | ((ha - la) <= tol_u * la) | (newton_ok & (taken <= tol_u * u_new))
        if converged.any():
            finished = position[converged]
            u_r[finished] = u_new[converged]
            count[finished] = iteration
            keep = ~converged
            position = position[keep]
            if position.size == 0:
                break
            ua, la, ha, ba, previous_step = u_new[keep], la[keep], ha[keep], ba[keep], taken[keep]
        else:
            ua, previous_step = u_new, taken
    else:                                       # never reached (see NEWTON_MAX_ITERATIONS)
        u_r[position] = ua
        count[position] = NEWTON_MAX_ITERATIONS
    u[rest] = u_r
    iterations[rest] += count
    P = np.multiply(u, u, out=out)
    P *= u
    return P, u, iterations


def _vz_loading_branch(params: VZParams):
    pair = params.pair
    radius_per_cube_root = params.c1 * params.Ca        # a_e = (3 R*/(4 E*))^(1/3) P^(1/3)

    def branch(delta, state, index, out=None):
        if delta.min() > pair.delta_Y:          # all plastic (the usual case; delta is finite)
            out = {} if out is None else out
            start = state.a_e_max[index]
            start /= radius_per_cube_root       # P^(1/3) at the old turning point
            P, cube_root, iterations = _vz_plastic_solve(delta, start, params, start_is_cube_root=True,
                                                         out=out.get("P_max"))
            a_e_max = np.multiply(cube_root, radius_per_cube_root, out=out.get("a_e_max"))
            delta_res, stiffness = _vz_turning_point(
                delta, P, cube_root, params, a_e=a_e_max,
                out=(out.get("delta_res"), out.get("unloading_stiffness")))
            return ({"P_max": P, "delta_res": delta_res, "unloading_stiffness": stiffness,
                     "a_e_max": a_e_max}, int(iterations.max()))
        # Hertz below yield: delta_res = 0, K_u = k_H, a = sqrt(R delta)
        out = {"P_max": _hertz_kernel(delta, pair), "delta_res": np.zeros_like(delta),
               "unloading_stiffness": np.full_like(delta, pair.hertz_stiffness),
               "a_e_max": np.sqrt(pair.R_star * np.maximum(delta, 0.0))}
        plastic = np.flatnonzero(delta > pair.delta_Y)
        if plastic.size == 0:
            return out, 0
        delta_plastic = delta[plastic]
        start = state.a_e_max[index[plastic]] / radius_per_cube_root
        P, cube_root, iterations = _vz_plastic_solve(delta_plastic, start, params, start_is_cube_root=True)
        out["P_max"][plastic] = P
        out["a_e_max"][plastic] = a_e_max = cube_root * radius_per_cube_root
        out["delta_res"][plastic], out["unloading_stiffness"][plastic] = _vz_turning_point(
            delta_plastic, P, cube_root, params, a_e=a_e_max)
        return out, int(iterations.max())

    return branch


def vz_step(delta, state: VZState, params: VZParams):
    """One vz step without committing it: (P [N], :class:`HistoryUpdate`); ``state`` is not modified.

    The force is :func:`vz_force`'s; the update holds the contacts with delta > delta_max, their
    new turning point (delta_max, P_max, delta_res, K_u = (4/3) E* C_Rmax^(3/2) sqrt(R*), a_e,max;
    paper eqs. 3.19-3.22) and the largest Newton iteration count of the step.
    """
    if not isinstance(params, VZParams):
        raise ValueError(f"params for law 'vz' must be VZParams, got {type(params).__name__}")
    _check_state(state, VZState, "vz")
    delta, shape = _check_delta(delta, state.n)
    force, update = _turning_point_step(delta, state, _vz_loading_branch(params), True, params.pair)
    return _restore_shape(force, shape), update


def vz_force_with_iterations(delta, state: VZState, params: VZParams):
    """:func:`vz_force` that also returns the largest number of Newton iterations of the step."""
    force, update = vz_step(delta, state, params)
    return force, _apply_update(state, update, copy=True), update.newton_iterations


def vz_force(delta, state: VZState, params: VZParams):
    """Vu-Quoc & Zhang (1999) displacement-driven NFD force P(delta, history) [N].

    Loading beyond the turning point (delta > delta_max): Hertz for delta <= delta_Y, else the
    root of the corrected F(P) (:func:`vz_plastic_force`, paper eqs. 3.4-3.14). Unloading and
    reloading below delta_max (paper eqs. 3.19-3.22): a_p and C_R frozen at P_max,
    P = (4/3) E* C_Rmax^(3/2) sqrt(R*) <delta - delta_res>^(3/2), which retraces back to
    (delta_max, P_max) and then continues plastically; separation (P = 0) for delta <= delta_res,
    re-contact above it. Any (R*, E*). Pure: :func:`vz_step` + a copying commit.
    """
    force, update = vz_step(delta, state, params)
    return force, _apply_update(state, update, copy=True)


def vz_newton_iterations(delta, state: VZState, params: VZParams) -> np.ndarray:
    """Newton iterations per contact for one vz step (0 where no Newton solve is needed)."""
    delta, _ = _check_delta(delta, state.n)
    counts = np.zeros(delta.shape[0], dtype=np.int64)
    plastic = np.flatnonzero((delta > state.delta_max) & (delta > params.pair.delta_Y))
    if plastic.size:
        start = state.a_e_max[plastic] / (params.c1 * params.Ca)
        _, _, counts[plastic] = _vz_plastic_solve(delta[plastic], start, params, start_is_cube_root=True)
    return counts


# ------------------------------------------------------------------------------------- thornton
def _thornton_unloading(P_max, delta_max, pair: ContactPair):
    """Thornton (1997) unloading from (P*, delta*) [SI]: a*^2 = (2 P* + P_Y)/(2 pi p_Y),
    R_p* = 4 E* a*^3 / (3 P*), delta_p = delta* - a*^2 / R_p*; returns (delta_p, (4/3) E* sqrt(R_p*))."""
    a_sq = (2.0 * P_max + pair.P_Y) / (2.0 * math.pi * pair.p_Y)
    R_p = 4.0 * pair.E_star * a_sq * np.sqrt(a_sq) / (3.0 * P_max)
    return np.maximum(delta_max - a_sq / R_p, 0.0), 4.0 / 3.0 * pair.E_star * np.sqrt(R_p)


def _thornton_loading_branch(pair: ContactPair):
    def branch(delta, _state, _index, out=None):
        plastic = delta > pair.delta_Y
        force = np.where(plastic, pair.P_Y + math.pi * pair.p_Y * pair.R_star * (delta - pair.delta_Y),
                         _hertz_kernel(delta, pair))
        delta_p, stiffness = _thornton_unloading(np.maximum(force, _TINY), delta, pair)
        return {"P_max": force, "delta_res": np.where(plastic, delta_p, 0.0),
                "unloading_stiffness": np.where(plastic, stiffness, pair.hertz_stiffness)}, 0

    return branch


def thornton_step(delta, state: ThorntonState, params):
    """One Thornton step without committing it: (P [N], :class:`HistoryUpdate`) (see
    :func:`thornton_force`); ``state`` is not modified."""
    pair = _as_pair(params, "thornton")
    _check_state(state, ThorntonState, "thornton")
    delta, shape = _check_delta(delta, state.n)
    force, update = _turning_point_step(delta, state, _thornton_loading_branch(pair), True, pair)
    return _restore_shape(force, shape), update


def thornton_force(delta, state: ThorntonState, params):
    """Thornton (1997) force [N]: Hertz up to delta_Y, then P = P_Y + pi p_Y R* (delta - delta_Y)
    (p_Y = A_Y sigma_Y); unloading from (P*, delta*) Hertzian with the enlarged radius R_p*:
    P = (4/3) E* sqrt(R_p*) (delta - delta_p)^(3/2) (SPEC section 5). params: a ContactPair.
    Pure: :func:`thornton_step` + a copying commit."""
    force, update = thornton_step(delta, state, params)
    return force, _apply_update(state, update, copy=True)


# --------------------------------------------------------------------------------- walton-braun
def _walton_braun_params(params) -> WaltonBraunParams:
    if isinstance(params, WaltonBraunParams):
        return params
    if isinstance(params, VZParams):
        return WaltonBraunParams.from_vz(params)
    return WaltonBraunParams.from_pair(_as_pair(params, "walton-braun"))


def _walton_braun_loading_branch(params: WaltonBraunParams):
    def branch(delta, _state, _index, out=None):
        force = params.K1 * delta
        return {"P_max": force, "delta_res": delta - force / params.K2,
                "unloading_stiffness": np.full_like(delta, params.K2)}, 0

    return branch


def walton_braun_force(delta, state: WaltonBraunState, params):
    """Walton & Braun (1986) force [N]: P = K1 delta on loading, P = K2 <delta - delta_res> on
    unloading/reloading with delta_res = delta_max - P_max/K2 (SPEC section 5).

    params: WaltonBraunParams; a VZParams or ContactPair gives the documented defaults
    (:meth:`WaltonBraunParams.from_vz`, secants through the turning point at 40 P_Y).
    Pure: :func:`walton_braun_step` + a copying commit.
    """
    force, update = walton_braun_step(delta, state, params)
    return force, _apply_update(state, update, copy=True)


def walton_braun_step(delta, state: WaltonBraunState, params):
    """One Walton-Braun step without committing it: (P [N], :class:`HistoryUpdate`) (see
    :func:`walton_braun_force`); ``state`` is not modified."""
    wb = _walton_braun_params(params)
    _check_state(state, WaltonBraunState, "walton-braun")
    delta, shape = _check_delta(delta, state.n)
    force, update = _turning_point_step(delta, state, _walton_braun_loading_branch(wb), False, wb.pair)
    return _restore_shape(force, shape), update


# --------------------------------------------------------------------------------- energies
def _vz_loading_work(delta_max, P_max, params: VZParams):
    """W = integral_0^delta_max P d delta on the virgin vz curve [J].

    Hertz part (2/5) P_Y delta_Y, then by parts W = P delta | - integral delta(P) dP with the
    explicit delta(P) (paper eq. 3.4). The integral uses Gauss-Legendre panels in
    t = ln(1 + (P - P_Y)/d), d = min(P_Y, 1/Kc): the integrand's singularities (P = 0 and
    C_R = 0) lie at least pi away from the real t axis, so 12-point panels of width <= 1 are
    accurate to round-off for any P_max/P_Y.
    """
    pair = params.pair
    delta_max = np.asarray(delta_max, dtype=float)
    P_max = np.asarray(P_max, dtype=float)
    elastic_part = np.minimum(delta_max, pair.delta_Y)
    work = 0.4 * pair.hertz_stiffness * elastic_part**2 * np.sqrt(elastic_part)
    plastic = np.flatnonzero((P_max > pair.P_Y) & (delta_max > pair.delta_Y))
    if plastic.size == 0:
        return work
    P = P_max[plastic]
    scale = pair.P_Y if params.Kc * pair.P_Y <= 1.0 else 1.0 / params.Kc
    t_max = np.log1p((P - pair.P_Y) / scale)
    n_panels = max(1, int(math.ceil(float(t_max.max()))))
    width = t_max / n_panels
    integral = np.zeros(plastic.size)
    for panel in range(n_panels):
        t = (panel + 0.5 * (_GAUSS_NODES + 1.0)) * width[:, None]
        excess = scale * np.expm1(t)
        integrand = params.loading_approach(pair.P_Y + excess) * (scale + excess)
        integral += 0.5 * width * (integrand @ _GAUSS_WEIGHTS)
    work[plastic] += P * delta_max[plastic] - pair.P_Y * pair.delta_Y - integral
    return work


def _thornton_loading_work(delta_max, pair: ContactPair):
    delta_max = np.asarray(delta_max, dtype=float)
    elastic_part = np.minimum(delta_max, pair.delta_Y)
    plastic_part = np.maximum(delta_max - pair.delta_Y, 0.0)
    return (0.4 * pair.hertz_stiffness * elastic_part**2 * np.sqrt(elastic_part)
            + pair.P_Y * plastic_part + 0.5 * math.pi * pair.p_Y * pair.R_star * plastic_part**2)


# ----------------------------------------------------------------------------------- registry
@dataclass(frozen=True)
class ContactDetails:
    """Per-contact quantities on request [SI]: force P [N]; elastic contact radius a_e [m] (Hertz
    radius at P); plastic radius a_p [m]; total contact radius a_ep [m] (the residual a_p,max
    after separation for vz); delta_res [m]; elastic_energy [J] recoverable at the current state;
    dissipated_energy [J] so far; state: the trial history after this step."""

    force: np.ndarray
    a_e: np.ndarray
    a_p: np.ndarray
    a_ep: np.ndarray
    delta_res: np.ndarray
    elastic_energy: np.ndarray
    dissipated_energy: np.ndarray
    state: object


@dataclass(frozen=True)
class ContactLaw:
    """A named force law plus helpers (module doc):

    ``force(delta, state, params) -> (P, new_state)``  pure (``state`` never modified);
    ``step(delta, state, params) -> (P, update)``      force and sparse trial history, not committed;
    ``commit(state, update) -> state``                 writes the update into ``state`` in place.
    """

    name: str
    description: str
    force: Callable
    state_type: type
    loading_work_function: Callable    # (delta_max, P_max, params) -> work on the virgin curve [J]
    unloading_exponent: float          # n in P = P_max s^n on unloading
    step_function: Callable            # (delta, state, params) -> (P, HistoryUpdate); the same kernel as force

    def step(self, delta, state, params):
        """Force P [N] (shape of ``delta``) and the trial history as a :class:`HistoryUpdate`
        (the contacts whose turning point moved and their new history), without committing it:
        ``state`` is not modified. ``P, update = law.step(delta, state, params)`` then
        ``law.commit(state, update)`` gives the same force and history as
        ``P, state = law.force(delta, state, params)``, bit for bit.
        """
        return self.step_function(delta, state, params)

    def commit(self, state, update: HistoryUpdate):
        """Write ``update`` (from :meth:`step` on this ``state``) into ``state``'s arrays IN PLACE
        and return ``state``; cost O(update.size), nothing is copied.

        The caller owns ``state``: every other reference to it (e.g. a state kept from an
        earlier step, or the ``new_state`` that :meth:`force` returns unchanged when no turning
        point moved) sees the change. Use :meth:`committed` for a copy. An empty update is a
        no-op. ValueError naming ``update`` if it does not belong to ``state`` (other law's
        history class, other number of contacts, positions out of range) or naming ``state``
        if that is not this law's history.
        """
        _check_state(state, self.state_type, self.name)
        _check_update(state, update)
        return _apply_update(state, update, copy=False)

    def committed(self, state, update: HistoryUpdate):
        """:meth:`commit` into a copy: the new history; ``state`` is not modified (it is returned
        itself when the update is empty). This is the commit :meth:`force` uses."""
        _check_state(state, self.state_type, self.name)
        _check_update(state, update)
        return _apply_update(state, update, copy=True)

    def initial_state(self, n: int):
        """History of n virgin contacts (never loaded)."""
        if self.state_type is HertzState:
            return HertzState(_contact_count(n))
        return self.state_type.virgin(n)

    def params_from(self, params):
        """This law's parameter object from VZParams / ContactPair / its own parameters."""
        if self.name == "vz":
            if not isinstance(params, VZParams):
                raise ValueError(f"params for law 'vz' must be VZParams, got {type(params).__name__}")
            return params
        if self.name == "walton-braun":
            return _walton_braun_params(params)
        return _as_pair(params, self.name)

    def loading_work(self, delta_max, P_max, params):
        """Work done on the virgin loading curve up to (delta_max, P_max) [J]."""
        return self.loading_work_function(np.asarray(delta_max, float), np.asarray(P_max, float),
                                          self.params_from(params))

    def dissipated_energy(self, state, params):
        """Energy dissipated per contact so far [J]: loading work to the turning point minus the
        elastic energy the unloading curve returns, W(delta_max) - P_max (delta_max - delta_res)/(n+1)."""
        if isinstance(state, HertzState):
            return np.zeros(state.n)
        work = self.loading_work(state.delta_max, state.P_max, params)
        returned = state.P_max * (state.delta_max - state.delta_res) / (self.unloading_exponent + 1.0)
        return np.maximum(work - returned, 0.0)

    def contact_state(self, delta, state, params) -> ContactDetails:
        """Force, radii, residual approach and energies per contact after this step."""
        p = self.params_from(params)
        force, new_state = self.force(delta, state, p)
        force = np.reshape(force, -1)
        pair = _as_pair(p, self.name)
        a_e = np.asarray(pair.hertz_radius(force), dtype=float).reshape(-1)
        delta_flat = np.asarray(delta, dtype=float).reshape(-1)
        if isinstance(new_state, HertzState):
            zeros = np.zeros_like(force)
            elastic = 0.4 * force * np.maximum(delta_flat, 0.0)
            return ContactDetails(force, a_e, zeros, a_e.copy(), zeros, elastic, zeros, new_state)
        elastic = force * np.maximum(delta_flat - new_state.delta_res, 0.0) / (self.unloading_exponent + 1.0)
        if self.name == "vz":
            a_p = p.plastic_radius(new_state.P_max)
            a_ep = a_e + a_p                # after separation a_e = 0: residual radius a_p,max
        elif self.name == "thornton":
            a_sq = np.where(new_state.P_max > pair.P_Y,
                            (2.0 * new_state.P_max + pair.P_Y) / (2.0 * math.pi * pair.p_Y), 0.0)
            a_star = np.sqrt(a_sq)
            s = force / np.maximum(new_state.P_max, _TINY)
            a_ep = np.where(new_state.P_max > pair.P_Y, a_star * np.cbrt(s), a_e)  # a ~ P^(1/3) at fixed R_p
            a_p = np.maximum(a_ep - a_e, 0.0)
        else:                               # walton-braun has no radius model: Hertz radius at P
            a_p = np.zeros_like(force)
            a_ep = a_e.copy()
        return ContactDetails(force, a_e, a_p, a_ep, new_state.delta_res.copy(), elastic,
                              self.dissipated_energy(new_state, p), new_state)

    def contact_radius(self, delta, state, params):
        """Total contact radius a_ep [m] per contact (see :meth:`contact_state`)."""
        return self.contact_state(delta, state, params).a_ep


def _hertz_work(delta_max, P_max, pair):
    d = np.maximum(delta_max, 0.0)
    return 0.4 * pair.hertz_stiffness * d**2 * np.sqrt(d)


LAWS: dict[str, ContactLaw] = {
    "hertz": ContactLaw("hertz", "Hertz elastic contact (Johnson 1985)", hertz_force, HertzState,
                        _hertz_work, 1.5, hertz_step),
    "vz": ContactLaw("vz", "Vu-Quoc & Zhang (1999) elastoplastic NFD model", vz_force, VZState,
                     _vz_loading_work, 1.5, vz_step),
    "thornton": ContactLaw("thornton", "Thornton (1997) elastic-perfectly plastic contact",
                           thornton_force, ThorntonState,
                           lambda d, P, pair: _thornton_loading_work(d, pair), 1.5, thornton_step),
    "walton-braun": ContactLaw("walton-braun", "Walton & Braun (1986) bilinear hysteretic spring",
                               walton_braun_force, WaltonBraunState,
                               lambda d, P, wb: 0.5 * wb.K1 * np.maximum(d, 0.0) ** 2, 1.0,
                               walton_braun_step),
}


def get_law(name: str) -> ContactLaw:
    """The force law called ``name``: one of 'hertz', 'vz', 'thornton', 'walton-braun'."""
    if not isinstance(name, str) or name.strip().lower() not in LAWS:
        raise ValueError(f"law must be one of {', '.join(LAWS)}; got {name!r}")
    return LAWS[name.strip().lower()]

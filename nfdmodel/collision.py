"""Normal impact of a sphere on a rigid flat, vectorised over incoming velocities.

Vu-Quoc & Zhang (1999) section 4: no gravity, the sphere (mass m*) hits the flat at v_in > 0;
the contact force P(delta, history) of a law from :mod:`nfdmodel.registry` decelerates it:

    m* d^2 delta / dt^2 = -P(delta, history)

integrated by leap-frog (velocities at half steps, paper eq. 4.3):

    v_(n+1/2) = v_(n-1/2) - P(delta_n) dt / m*,     delta_(n+1) = delta_n + v_(n+1/2) dt

starting at first touch (delta_0 = 0, v_(-1/2) = v_in, t = 0). The contact ends when the force
returns to 0 while the sphere moves away (delta <= delta_res); the separation instant is
interpolated linearly inside the last step (velocity is constant within a step). Outputs:

    e_velocity = -v_out / v_in                                    (paper eq. 4.6)
    e_energy   = sqrt(unloading area / loading area) of P-delta   (paper eqs. 2.1, 4.7)

with the areas integrated by the trapezoidal rule along the computed path (the last segment is
cut at delta_res). Both converge to the exact value as O(dt^2).

:func:`collision_reference` gives the exact answer by energy balance: the loading curve is
followed until (1/2) m* v_in^2 = W(delta_max) = integral_0^delta_max P d delta, and the
unloading curve returns E_el = P_max (delta_max - delta_res)/(n + 1), so
e = sqrt(E_el / W) exactly (no time stepping).

Contact duration (it sizes dt and says when dt is too large), per velocity:

    t_load   = integral_0^delta_max d delta / sqrt(v_in^2 - 2 W(delta) / m*)
             (Gauss-Legendre in s, delta = delta_max (1 - s^2), which removes the inverse
             square-root end point; Hertz: 1.4716 delta_max / v_in, linear: pi/2 delta_max / v_in)
    t_unload = I(n) (delta_max - delta_res) / v_out,   I(n) = sqrt(pi) G(1 + 1/(n+1)) / G(1/2 + 1/(n+1))
             (exact for the unloading curve P = K_u (delta - delta_res)^n; I(3/2) = 1.4716)

At high v_in / v_Y the unloading phase is short (2 % of the contact for vz at v_in = 1e4 v_Y),
so the warning also checks the number of steps in it.
"""
from __future__ import annotations

import copy
import math
import time
import warnings
from dataclasses import dataclass, field

import numpy as np

from . import limits, native
from .hertz_contact import hertz_approach_at_work
from .history import HertzState, check_state
from .materials import as_pair
from .registry import ContactLaw, get_law
from .turning_point import elastic_energy
from .validation import bound_text, check_real, check_solid
from .window import RangeWarning

STEPS_PER_CONTACT_AUTO = 2000     # dt = None: dt = shortest estimated contact time / this
STEPS_PER_CONTACT_WARN = limits.STEPS_PER_CONTACT_MIN      # warn when a contact would last fewer steps
STEPS_PER_UNLOADING_WARN = limits.STEPS_PER_UNLOADING_MIN  # ... or its unloading phase fewer (e error > ~0.2 %)
STEPS_PER_UNLOADING_AUTO = 100    # dt = None: also at most the shortest unloading time / this
# dt so small that a contact needs more steps: ValueError. 400 x the automatic resolution
# (~2500 steps per contact); about 40 s of the numpy time loop (40 us per step).
MAX_STEPS_LIMIT = 10**6
_SMALLEST_ENERGY = limits.SMALLEST_ENERGY      # J; below, (1/2) m v^2 and the overlaps underflow
_LOADING_NODES, _LOADING_WEIGHTS = np.polynomial.legendre.leggauss(24)


class TimeStepWarning(RuntimeWarning):
    """dt is too large for the contact: the collision result is inaccurate (see :func:`collide`)."""
CONTACT_TIME_SAFETY = 20.0
MAX_REPEAT = 1000                 # collide_repeated: at most this many impacts per contact        # max_steps = this * longest estimated contact time / dt


@dataclass(frozen=True)
class CollisionHistory:
    """Time series of a collision (on request): time [s] shape (steps+1,), delta [m] and
    force [N] shape (steps+1, n_velocities)."""

    time: np.ndarray
    delta: np.ndarray
    force: np.ndarray


@dataclass(frozen=True)
class CollisionReference:
    """Exact collision by energy balance (no time stepping), per velocity [SI]."""

    v_in: np.ndarray
    delta_max: np.ndarray
    P_max: np.ndarray
    delta_res: np.ndarray
    loading_work: np.ndarray
    restitution: np.ndarray
    contact_time_estimate: np.ndarray   # t_load + t_unload [s] (module doc)
    unloading_time_estimate: np.ndarray  # t_unload [s], the shorter, stiffer phase


@dataclass(frozen=True)
class CollisionResult:
    """Result of :func:`collide`, arrays per incoming velocity [SI].

    v_out [m/s] (< 0: rebound), e_velocity = -v_out/v_in, e_energy (paper 4.7), P_max [N],
    delta_max [m], delta_res [m] (residual indentation), contact_time [s]; dt [s], steps,
    wall_time_s, max_newton_iterations (vz; 0 otherwise); history on request;
    in_calibrated_range: per velocity, whether the impact stayed inside the calibrated window of
    the law's constants, and P_max_over_window: P_max / the window's largest force (both None
    when the law has no fitted constants or they state no window); dissipated_plastic [J]: the
    energy the contact dissipated, the loading work to the turning point minus the elastic energy
    its unloading returns, W(delta_max) - E_el (turning_point.elastic_energy; the law's own
    (1 - e^2) (1/2) m* v_in^2, the leap-frog's 1/2 m* (v_in^2 - v_out^2) to O(dt^2)).
    """

    law: str
    v_in: np.ndarray
    v_out: np.ndarray
    e_velocity: np.ndarray
    e_energy: np.ndarray
    P_max: np.ndarray
    delta_max: np.ndarray
    delta_res: np.ndarray
    contact_time: np.ndarray
    dt: float
    steps: int
    wall_time_s: float
    max_newton_iterations: int = 0
    history: CollisionHistory | None = field(default=None, repr=False)
    in_calibrated_range: np.ndarray | None = None
    P_max_over_window: np.ndarray | None = None
    dissipated_plastic: np.ndarray | None = None

    def records(self) -> list[dict]:
        """One dict per velocity with the CLI's JSON keys (SI units; null where not applicable):
        also the contact's state at the end, its dent (delta_res) and turning point (delta_max [m],
        P_max [N]), and dissipated_plastic [J], as the LAMMPS plugin reports a contact."""
        known = self.in_calibrated_range is not None
        lost = self.dissipated_plastic
        return [{"v_in": float(self.v_in[i]), "v_out": float(self.v_out[i]),
                 "e_velocity": float(self.e_velocity[i]), "e_energy": float(self.e_energy[i]),
                 "P_max": float(self.P_max[i]), "contact_time": float(self.contact_time[i]),
                 "in_calibrated_range": bool(self.in_calibrated_range[i]) if known else None,
                 "P_max_over_window": float(self.P_max_over_window[i]) if known else None,
                 "dent": float(self.delta_res[i]), "delta_max": float(self.delta_max[i]),
                 "dissipated_plastic": float(lost[i]) if lost is not None else None}
                for i in range(self.v_in.size)]


def _check_velocities(v_in) -> np.ndarray:
    try:
        v = np.atleast_1d(np.asarray(v_in, dtype=float)).reshape(-1)
    except (TypeError, ValueError):
        raise ValueError(f"v_in must be numbers (> 0 m/s), got {v_in!r}") from None
    if v.size == 0:
        raise ValueError("v_in must hold at least one velocity (> 0 m/s)")
    if not np.isfinite(v).all():
        raise ValueError("v_in must be finite (no NaN or inf), > 0 m/s")
    if (v <= 0).any():
        raise ValueError(f"v_in out of range: need v_in > 0 m/s (toward the flat), got {v[v <= 0][0]:g}")
    check_solid("v_in", float(v.max()))     # 1e10 m/s is a slip, not an impact: say so first
    return v


def _resolve(law_name, params):
    law = law_name if isinstance(law_name, ContactLaw) else get_law(law_name)
    law_params = law.params_from(params)
    return law, law_params, as_pair(law_params, law.name)


def _virgin_force(law: ContactLaw, delta, law_params):
    force, state = law.force_function(delta, law.initial_state(delta.size), law_params)
    return force, state


def _check_within_domain(law: ContactLaw, params, pair, v, energy) -> float:
    """The largest approach [m] the law covers (vz: where its contact radius reaches R*; inf for
    the others); a ValueError naming the largest admissible v_in when an impact goes beyond."""
    if not law.fitted:
        return math.inf
    reach = params.full_contact_approach * (1.0 - 1e-9)   # just inside: at the root a = R* exactly
    work = float(law.loading_work(np.array([reach]), np.array([params.full_contact_load]), params)[0])
    if (energy > work).any():
        v_reach = math.sqrt(2.0 * work / pair.mass_star)
        raise ValueError(f"v_in out of range: at v_in = {float(v[energy > work][0]):g} m/s the {law.name} law's contact "
                         f"radius would reach R* = {pair.R_star:g} m (beyond any contact law); need v_in < "
                         f"{v_reach:.4g} m/s ({v_reach / pair.v_Y:.4g} v_Y) for these constants")
    return reach


def collision_reference(law_name, params, v_in) -> CollisionReference:
    """Exact turning point and restitution by energy balance (see module doc), per velocity.

    Solves W(delta_max) = (1/2) m* v_in^2 by Newton with dW/d delta = P (W convex, so Newton from
    above converges monotonically), to 1e-13 relative.
    """
    law, law_params, pair = _resolve(law_name, params)
    v = _check_velocities(v_in)
    if law.reference_function is not None:          # the law's own energy balance (nfdmodel.rate_aware)
        return law.reference_function(law_params, v)
    with np.errstate(over="ignore", under="ignore"):
        energy = 0.5 * pair.mass_star * v**2
    unusable = ~(np.isfinite(energy) & (energy > _SMALLEST_ENERGY))
    if unusable.any():
        raise ValueError(f"v_in out of range: the impact energy (1/2) m* v_in^2 = {energy[unusable][0]:g} J "
                         f"at v_in = {v[unusable][0]:g} m/s (v_in/v_Y = {v[unusable][0] / pair.v_Y:.3g}) "
                         f"is outside the floating-point range ({_SMALLEST_ENERGY:g} J .. 1.8e308 J)")
    delta = hertz_approach_at_work(energy, pair.hertz_stiffness)     # Hertz: W = (2/5) k delta^(5/2)
    reach = _check_within_domain(law, law_params, pair, v, energy)
    delta = np.minimum(delta, reach)
    for _ in range(limits.REFERENCE_BRACKET_STEPS):               # bracket from above
        force, _ = _virgin_force(law, delta, law_params)
        short = law.loading_work(delta, force, law_params) < energy
        if not short.any():
            break
        delta = np.where(short, np.minimum(2.0 * delta, reach), delta)
    for _ in range(limits.REFERENCE_NEWTON_STEPS):
        force, _ = _virgin_force(law, delta, law_params)
        excess = law.loading_work(delta, force, law_params) - energy
        step = excess / np.maximum(force, 1e-300)
        delta = delta - np.clip(step, 0.0, 0.5 * delta)            # monotone from above
        if np.all(np.abs(step) <= limits.REFERENCE_TOLERANCE * delta):
            break
    force, state = _virgin_force(law, delta, law_params)
    work = law.loading_work(delta, force, law_params)
    if not (np.isfinite(work).all() and (work > 0).all()):
        raise ValueError(f"v_in out of range: the energy balance of the impact at v_in = {v[0]:g} .. "
                         f"{v[-1]:g} m/s cannot be solved in floating point")
    delta_res = np.zeros_like(delta) if isinstance(state, HertzState) else state.delta_res
    exponent = law.exponent_of(state)           # per contact where the history keeps one (vz-unload)
    returned = elastic_energy(force, delta, delta_res, exponent)
    restitution = np.sqrt(returned / work)
    loading_time = _loading_time(law, law_params, pair, v, delta)
    factor = (_unloading_time_factor(exponent) if np.ndim(exponent) == 0
              else np.array([_unloading_time_factor(float(n)) for n in exponent]))
    unloading_time = factor * (delta - delta_res) / (restitution * v)
    return CollisionReference(v, delta, force, delta_res, work, restitution,
                              loading_time + unloading_time, unloading_time)


def _unloading_time_factor(exponent: float) -> float:
    """I(n) = integral_0^1 dx / sqrt(1 - x^(n+1)) = sqrt(pi) G(1 + 1/m) / G(1/2 + 1/m), m = n + 1."""
    m = exponent + 1.0
    return math.sqrt(math.pi) * math.gamma(1.0 + 1.0 / m) / math.gamma(0.5 + 1.0 / m)


def _loading_time(law: ContactLaw, law_params, pair, v, delta_max):
    """t_load = integral_0^delta_max d delta / v(delta) [s] with v^2 = v_in^2 - 2 W(delta)/m*."""
    s = 0.5 * (_LOADING_NODES + 1.0)                           # nodes on (0, 1)
    delta = delta_max[:, None] * (1.0 - s * s)[None, :]        # (velocities, nodes)
    force, _ = _virgin_force(law, delta.reshape(-1), law_params)
    work = law.loading_work(delta.reshape(-1), force, law_params).reshape(delta.shape)
    speed_sq = v[:, None] ** 2 - 2.0 * work / pair.mass_star
    # near s = 0, v^2 ~ (2 P_max delta_max / m*) s^2: the integrand 2 delta_max s / v stays finite
    floor = 1e-300 + 1e-12 * v[:, None] ** 2
    integrand = 2.0 * delta_max[:, None] * s[None, :] / np.sqrt(np.maximum(speed_sq, floor))
    return 0.5 * integrand @ _LOADING_WEIGHTS


def coarse_time_step(reference: CollisionReference, dt: float) -> str | None:
    """What is wrong with time step dt [s] for the impacts of ``reference`` (collision_reference):
    None when every contact lasts at least STEPS_PER_CONTACT_WARN steps and its unloading at least
    STEPS_PER_UNLOADING_WARN (nfd_limits.h), else one line naming the steps and the largest dt that
    passes (collide's TimeStepWarning, nfdcal collide's oblique impacts)."""
    shortest_contact = float(reference.contact_time_estimate.min())
    shortest_unloading = float(reference.unloading_time_estimate.min())
    largest_dt = min(shortest_contact / STEPS_PER_CONTACT_WARN, shortest_unloading / STEPS_PER_UNLOADING_WARN)
    if dt <= largest_dt:
        return None
    return (f"dt = {dt:g} s is too large for this contact: the shortest contact lasts about "
            f"{shortest_contact:.3g} s ({shortest_contact / dt:.3g} steps, need "
            f">= {STEPS_PER_CONTACT_WARN}) and its unloading about {shortest_unloading:.3g} s "
            f"({shortest_unloading / dt:.3g} steps, need >= {STEPS_PER_UNLOADING_WARN}); "
            f"results are inaccurate: use dt <= {largest_dt:.3g} s")


def collide(law_name, params, v_in, dt: float | None = 1e-6, history: bool = False,
            max_steps: int | None = None, start=None):
    """Simulate sphere-on-flat impacts at all velocities ``v_in`` [m/s] at once (module doc).

    law_name: 'vz' | 'hertz' | 'thornton' | 'walton-braun' (or a ContactLaw); params: VZParams
    (any law), a ContactPair (hertz, thornton, walton-braun defaults) or WaltonBraunParams.
    dt [s]: time step (paper: 1e-6 s); None picks dt = min(shortest estimated contact time /
    2000, shortest unloading time / 100), the estimates coming from :func:`collision_reference`.
    A :class:`TimeStepWarning` (a RuntimeWarning) is issued when a contact would last fewer than
    50 steps or its unloading phase fewer than 10 (the result is then inaccurate; the message
    gives the largest dt that passes); a ValueError when dt reaches the leap-frog stability
    limit 2 t_unload / pi, or needs more than 1e6 steps per contact. max_steps: default 20 x the longest estimated contact
    time / dt; a ValueError if some velocity has not separated by then. start: the contacts' history
    (the law's state, one contact per velocity) to begin from, each at first touch delta = its
    delta_res; then the result is (CollisionResult, the history at the end) (collide_repeated).
    """
    started = time.perf_counter()
    law, law_params, pair = _resolve(law_name, params)
    v_in = _check_velocities(v_in)
    reference = collision_reference(law, law_params, v_in)
    contact_estimate = reference.contact_time_estimate
    shortest_contact = float(contact_estimate.min())
    shortest_unloading = float(reference.unloading_time_estimate.min())
    if dt is None:
        dt = min(shortest_contact / STEPS_PER_CONTACT_AUTO, shortest_unloading / STEPS_PER_UNLOADING_AUTO)
    dt = check_real("dt", dt, low=0.0, unit="s")
    # Leap-frog is stable for dt < 2/omega; the stiffest phase (unloading) is a half oscillation
    # of duration t_unload = pi/omega, so dt must stay below 2 t_unload / pi. Beyond it the
    # numbers are meaningless (restitutions such as e = 4.7), so this is an error, not a warning.
    stability_limit = 2.0 * shortest_unloading / math.pi
    if dt >= stability_limit:
        raise ValueError(f"dt out of range: dt = {dt:g} s is beyond the leap-frog stability limit "
                         f"{stability_limit:.3g} s of this contact (its unloading lasts about "
                         f"{shortest_unloading:.3g} s); need dt < {bound_text(stability_limit, '<=', 3)} s, and dt <= "
                         f"{bound_text(min(shortest_contact / STEPS_PER_CONTACT_WARN, shortest_unloading / STEPS_PER_UNLOADING_WARN), '<=', 3)} s "
                         f"for accurate results")
    longest_contact = float(contact_estimate.max())
    if longest_contact / dt > MAX_STEPS_LIMIT:
        raise ValueError(f"dt out of range: dt = {dt:g} s would need {longest_contact / dt:.3g} steps for a "
                         f"contact of {longest_contact:.3g} s; need dt >= {bound_text(longest_contact / MAX_STEPS_LIMIT, '>=', 3)} s "
                         f"(at most {MAX_STEPS_LIMIT:.0e} steps)")
    coarse = coarse_time_step(reference, dt)
    if coarse is not None:
        warnings.warn(coarse, TimeStepWarning, stacklevel=2)
    if max_steps is None:
        max_steps = int(math.ceil(CONTACT_TIME_SAFETY * contact_estimate.max() / dt)) + 10
    max_steps = int(check_real("max_steps", max_steps, low=1, low_inclusive=True))

    if native.active() and not history and start is None and law.collision_params is not None:
        path = native.collide(law.name, law.collision_params(law_params), v_in, dt, pair.mass_star, max_steps,
                              lambda delta, v: law.step_function(np.array([delta]), law.initial_state(1), law_params,
                                                                 *law._velocity(np.array([v]))))
    else:
        path = _time_loop(law, law_params, v_in, dt, pair.mass_star, max_steps, history, start)
    in_range, over_window = _window_check(law, law_params, path["P_max"], v_in)
    result = CollisionResult(law.name, v_in, path["v_out"], -path["v_out"] / v_in,
                           np.sqrt(path["unloading_area"] / np.maximum(path["loading_area"], 1e-300)),
                           path["P_max"], path["delta_max"], path["delta_res"], path["contact_time"], dt,
                           path["steps"], time.perf_counter() - started, path["max_iterations"],
                           path["history"], in_range, over_window, _dissipated(law, law_params, path, start))
    return (result, path["state"]) if start is not None else result


def _dissipated(law: ContactLaw, law_params, path: dict, start) -> np.ndarray:
    """The plastic energy [J] of each impact's contact (CollisionResult.dissipated_plastic): the
    loading work to its turning point minus the elastic energy the unloading returns
    (ContactLaw.dissipated_energy) of the history at the end, less that of the history it started
    from (``start``: a repeated impact reloads along the unloading curve before it loads further)."""
    state = path.get("state")
    if state is None:       # the compiled loop (a virgin contact): its turning point is the path's (and R)
        rate = (path["rate_factor"],) if "rate_factor" in path else ()
        lost = (law.loading_work_function(path["delta_max"], path["P_max"], law.params_from(law_params), *rate)
                - elastic_energy(path["P_max"], path["delta_max"], path["delta_res"], law.unloading_exponent))
        return np.maximum(lost, 0.0)
    lost = law.dissipated_energy(state, law_params)
    return lost if start is None else np.maximum(lost - law.dissipated_energy(start, law_params), 0.0)


def collide_repeated(law_name, params, v_in, repeat: int, dt: float | None = None) -> list[CollisionResult]:
    """``repeat`` impacts of each sphere on the same spot, one contact per velocity ``v_in`` [m/s]:
    after each separation the sphere is re-launched at the same v_in from first touch, the contact's
    history (turning point delta_max, P_max, dent delta_res, unloading curve) carried over, so each
    impact starts at delta = delta_res (force 0) and reloads along the unloading curve up to the
    turning point, then on the virgin curve (nfdmodel.turning_point). One CollisionResult per
    impact (the first is :func:`collide`'s); dt as collide's (None: from the first impact's
    estimates, which bound the later, stiffer ones' unloading too: it follows the same curves).
    e of impact k: -v_out / v_in of that impact."""
    if isinstance(repeat, bool) or not isinstance(repeat, (int, np.integer)) or not 1 <= repeat <= MAX_REPEAT:
        raise ValueError(f"repeat out of range: need an integer in [1, {MAX_REPEAT}], got {repeat!r}")
    law, law_params, _ = _resolve(law_name, params)
    state = law.initial_state(_check_velocities(v_in).size)
    results = []
    for _ in range(int(repeat)):
        result, state = collide(law, law_params, v_in, dt=dt, start=state)
        dt = result.dt                                   # one time step for the whole series
        results.append(result)
    return results


def _window_check(law, params, P_max, v_in):
    """(in_calibrated_range, P_max / window's largest force) per velocity, or (None, None) when
    the law's constants state no window. An impact is inside when it stays elastic (P_max <= P_Y:
    Hertz, exact) or peaks inside the window, P_min <= P_max <= the window's largest force; a peak
    between P_Y and P_min unloads where no FE unloading path measured the law (the vz-table law
    extrapolates its C_R there). One RangeWarning for the impacts above the window, one for those
    below it, each naming the worst."""
    window = getattr(params, "window", None)
    if not law.fitted or window is None:
        return None, None
    P_limit, P_Y = params.window_force, params.pair.P_Y
    over = P_max / P_limit
    above = P_max > P_limit
    below = (P_max > P_Y * (1.0 + 1e-9)) & (P_max < window.P_min_over_P_Y * P_Y * (1.0 - 1e-9))
    if above.any():
        worst = int(np.argmax(np.where(above, P_max, -np.inf)))
        warnings.warn(f"{law.name} law used beyond its calibrated window: {int(above.sum())} of {v_in.size} "
                      f"impact(s), up to v_in = {v_in[worst]:g} m/s reaching P/P_Y = {P_max[worst] / P_Y:.4g}"
                      f" (fitted on {window.describe()}); calibrate for these impacts (nfdcal calibrate --peaks)",
                      RangeWarning, stacklevel=3)
    if below.any():
        worst = int(np.argmin(np.where(below, P_max, np.inf)))
        warnings.warn(f"{law.name} law used below its calibrated window: {int(below.sum())} of {v_in.size} "
                      f"impact(s) yield and unload below its lowest measured unloading, down to v_in = "
                      f"{v_in[worst]:g} m/s reaching P/P_Y = {P_max[worst] / P_Y:.4g} (fitted on {window.describe()}); "
                      f"calibrate with a lower unloading path (nfdcal calibrate --peaks)", RangeWarning, stacklevel=3)
    return ~(above | below), over


def _time_loop(law, law_params, v_in, dt: float, mass: float, max_steps: int, history: bool, start=None) -> dict:
    """The leap-frog loop of :func:`collide` (module doc) for all velocities at once: per
    velocity v_out, contact_time, loading and unloading areas, P_max, delta_max, delta_res; the
    number of steps, the largest Newton iteration count, the history on request and the contacts'
    final ``state``. ``start``: the contacts' history to begin from (None: virgin), at first touch
    delta = delta_res (a copy: ``start`` is not modified)."""
    n = v_in.size
    if start is None:
        state = law.initial_state(n)
        delta = np.zeros(n)
    else:
        check_state(start, type(law.initial_state(1)), law.name)
        if start.n != n:
            raise ValueError(f"start out of range: need the history of {n} contact(s), got {start.n}")
        state = copy.deepcopy(start)
        delta = np.zeros(n) if isinstance(state, HertzState) else state.delta_res.copy()
    force = np.zeros(n)
    velocity = v_in.copy()                      # v_(-1/2)
    loading_area = np.zeros(n)
    unloading_area = np.zeros(n)
    contact_time = np.zeros(n)
    v_out = np.zeros(n)
    in_contact = np.ones(n, dtype=bool)
    P_max = np.zeros(n)                         # largest force and approach on the path
    delta_max = np.zeros(n)
    max_iterations = 0
    times, deltas, forces = ([0.0], [delta.copy()], [force.copy()]) if history else (None, None, None)
    step = 0
    while in_contact.any():
        if step >= max_steps:
            raise ValueError(f"max_steps = {max_steps} reached before separation at v_in = "
                             f"{v_in[in_contact][0]:g} m/s: increase max_steps or dt (dt = {dt:g} s)")
        velocity = velocity - force * (dt / mass)
        delta_new = delta + velocity * dt
        # The loop owns ``state`` (made above, never handed out before the end): the trial
        # history is committed in place, O(contacts whose turning point moved), no copy.
        # the kernel: no RangeWarning per step; one per collide, from _window_check
        force_new, update = law.step_function(delta_new, state, law_params, *law._velocity(velocity))
        law.commit(state, update)
        max_iterations = max(max_iterations, update.newton_iterations)
        increment = delta_new - delta
        area = 0.5 * (force + force_new) * increment
        separating = in_contact & (force_new == 0.0) & (velocity < 0.0)
        if separating.any():
            delta_res = np.zeros(n) if isinstance(state, HertzState) else state.delta_res
            # Cut the last segment at delta_res, where the force vanishes.
            fraction = np.clip((delta - delta_res) / np.where(increment < 0, -increment, 1.0), 0.0, 1.0)
            area = np.where(separating, 0.5 * force * fraction * increment, area)
            contact_time = np.where(separating, (step + fraction) * dt, contact_time)
            v_out = np.where(separating, velocity, v_out)
        loading_area += np.where(in_contact & (increment > 0), area, 0.0)
        unloading_area += np.where(in_contact & (increment < 0), -area, 0.0)
        in_contact &= ~separating
        np.maximum(P_max, force_new, out=P_max)
        np.maximum(delta_max, delta_new, out=delta_max)
        delta, force = delta_new, force_new
        step += 1
        if history:
            times.append(step * dt)
            deltas.append(delta.copy())
            forces.append(force.copy())
    return {"v_out": v_out, "contact_time": contact_time, "loading_area": loading_area,
            "unloading_area": unloading_area, "P_max": P_max, "delta_max": delta_max,
            "delta_res": np.zeros(n) if isinstance(state, HertzState) else state.delta_res,
            "steps": step, "max_iterations": max_iterations, "state": state,
            "history": CollisionHistory(np.asarray(times), np.asarray(deltas), np.asarray(forces)) if history else None}

"""The plain scalar transcription of every runtime law: one contact, Python floats, ``math`` only.

This is the specification to port from (a C kernel, a LAMMPS pair style, any DEM code): the
vectorised kernels of nfdmodel are tested against it, branch by branch. Each law is a step
``(delta, history, constants) -> (P, new_history)``: ``delta`` the approach [m] of this time
step, ``history`` the contact's turning point (a :class:`History`; the initial one is all
zeros), ``P`` the normal force [N]. The new history is returned, never written into the old
one: the caller commits it when the time step is accepted.

Every elastoplastic law follows one scheme (nfdmodel/README.md, The model: Unloading and reloading):

* loading beyond the turning point (delta > delta_max): the law's virgin curve gives P, and
  the turning point moves: (delta_max, P_max) = (delta, P), with the residual approach
  delta_res and the constant K_u of the unloading curve through it;
* otherwise unloading or reloading along that curve, P = K_u <delta - delta_res>^n, n = 3/2
  (vz, thornton) or 1 (walton-braun); delta <= delta_res is separation (P = 0) and re-contact
  above it retraces the same curve.

K_u is stored as P_max / (delta_max - delta_res)^n, so the curve passes through the turning
point to round-off (continuity of the force).

Constants [SI]: R = R* [m], E = E* [Pa], P_Y [N], delta_Y [m], p_Y = A_Y(nu) sigma_Y [Pa]
(nfdmodel/README.md, The model: First yield), the vz constants Ca [m/N], Kc [1/N], the Walton-Braun
stiffnesses K1 <= K2 [N/m].
"""
from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class History:
    """One contact's turning point [SI]: delta_max [m], P_max [N], delta_res [m], K_u (the
    unloading constant: N/m^1.5 for n = 3/2, N/m for n = 1), a_e_max [m] (vz: the Hertz radius
    at P_max, kept because it starts the next Newton solve)."""

    delta_max: float = 0.0
    P_max: float = 0.0
    delta_res: float = 0.0
    K_u: float = 0.0
    a_e_max: float = 0.0


def hertz_force(delta: float, R: float, E: float) -> float:
    """Hertz (Johnson 1985 eq. 4.23): P = (4/3) E* sqrt(R*) <delta>^(3/2) [N]."""
    d = max(delta, 0.0)
    return 4.0 / 3.0 * E * math.sqrt(R) * d * math.sqrt(d)


def hertz_step(delta: float, history: History, R: float, E: float) -> tuple[float, History]:
    """Hertz has no history: (P, history) with the history unchanged."""
    return hertz_force(delta, R, E), history


def unloading_force(delta: float, history: History, n: float) -> float:
    """P = K_u <delta - delta_res>^n on the unloading (and reloading) curve [N]."""
    gap = max(delta - history.delta_res, 0.0)
    return history.K_u * gap ** n


def turning_point(delta_max: float, P_max: float, delta_res: float, n: float, a_e_max: float = 0.0) -> History:
    """The history of a new turning point: delta_res is kept strictly below delta_max (at least
    one float below: an unloading curve that drops to zero within one ulp) so that
    K_u = P_max / (delta_max - delta_res)^n is finite."""
    delta_res = max(delta_res, 0.0)
    if delta_res >= delta_max:
        delta_res = math.nextafter(delta_max, 0.0)
    return History(delta_max, P_max, delta_res, P_max / (delta_max - delta_res) ** n, a_e_max)


# ----------------------------------------------------------------------------------- vz
def vz_newton_function(P: float, delta: float, R: float, E: float, P_Y: float, Ca: float, Kc: float):
    """The corrected Newton function of Vu-Quoc & Zhang (1999) eq. 3.14 and its derivative:

        F(P)  = (P - P_Y) + c1 P^(1/3) - sqrt((1 + Kc (P - P_Y)) R delta) / Ca,
        F'(P) = 1 + c1 P^(-2/3) / 3 - Kc sqrt(R delta) / (2 Ca sqrt(1 + Kc (P - P_Y))),
        c1 = (3 R / (4 E))^(1/3) / Ca   [N^(2/3)].

    F is the plastic contact radius a_p = Ca (P - P_Y) minus its value on the loading curve
    delta = (a_e + a_p)^2 / (C_R R), divided by Ca (nfdmodel/README.md, The model: The NFD law on loading)."""
    c1 = (3.0 * R / (4.0 * E)) ** (1.0 / 3.0) / Ca
    C_R = 1.0 + Kc * (P - P_Y)
    F = (P - P_Y) + c1 * P ** (1.0 / 3.0) - math.sqrt(C_R * R * delta) / Ca
    dF = 1.0 + c1 * P ** (-2.0 / 3.0) / 3.0 - Kc * math.sqrt(R * delta) / (2.0 * Ca * math.sqrt(C_R))
    return F, dF


def vz_loading_force(delta: float, P_start: float, R: float, E: float, P_Y: float, Ca: float,
                     Kc: float, tolerance: float = 1e-13) -> float:
    """The force [N] on the plastic loading curve at delta > delta_Y: the root P >= P_Y of F.

    F(P_Y) <= 0 and F grows without bound, so the root is bracketed by [P_lo, P_hi] with
    P_lo = max(P_start, P_Y) (P_start: the force at a smaller approach, e.g. P_max) and P_hi
    doubled until F(P_hi) > 0; Newton steps that leave the bracket are replaced by bisection."""
    low = max(P_start, P_Y)
    if vz_newton_function(low, delta, R, E, P_Y, Ca, Kc)[0] >= 0.0:
        return low
    high = 2.0 * low
    while vz_newton_function(high, delta, R, E, P_Y, Ca, Kc)[0] < 0.0:
        low, high = high, 2.0 * high
    P = low
    for _ in range(400):
        F, dF = vz_newton_function(P, delta, R, E, P_Y, Ca, Kc)
        if F < 0.0:
            low = P
        else:
            high = P
        step = F / dF if dF > 0.0 else math.inf
        candidate = P - step
        if not low < candidate < high:
            candidate = 0.5 * (low + high)
        if abs(candidate - P) <= tolerance * candidate or high - low <= tolerance * high:
            return candidate
        P = candidate
    return P


def vz_step(delta: float, history: History, R: float, E: float, P_Y: float, delta_Y: float,
            Ca: float, Kc: float) -> tuple[float, History]:
    """One time step of the vz law (Vu-Quoc & Zhang 1999, algorithm of section 3.2).

    Virgin curve: Hertz up to delta_Y (delta_res = 0, K_u = (4/3) E sqrt(R)); beyond it
    P = vz_loading_force, then C_Rmax = 1 + Kc (P_max - P_Y), a_e,max = (3 P_max R / (4 E))^(1/3)
    and delta_res = delta_max - a_e,max^2 / (C_Rmax R) (paper eqs. 3.19-3.21); unloading
    P = K_u <delta - delta_res>^(3/2), K_u = (4/3) E C_Rmax^(3/2) sqrt(R) (paper eq. 3.22).
    A ValueError where the contact radius a_e + Ca (P - P_Y) reaches R (no contact law there)."""
    if delta <= history.delta_max:
        return unloading_force(delta, history, 1.5), history
    if delta <= delta_Y:
        P = hertz_force(delta, R, E)
        return P, History(delta, P, 0.0, 4.0 / 3.0 * E * math.sqrt(R), math.sqrt(R * max(delta, 0.0)))
    P = vz_loading_force(delta, history.P_max, R, E, P_Y, Ca, Kc)
    C_R = 1.0 + Kc * (P - P_Y)
    a_e = (3.0 * P * R / (4.0 * E)) ** (1.0 / 3.0)
    if not a_e + Ca * (P - P_Y) < R:   # the law's domain ends where its contact radius reaches R*
        raise ValueError(f"delta out of range: at delta = {delta:g} m the vz contact radius reaches R* = {R:g} m")
    return P, turning_point(delta, P, delta - a_e * a_e / (C_R * R), 1.5, a_e)


# ----------------------------------------------------------------------------- vz-table
def hermite(x: float, nodes, values, slopes) -> tuple[float, float]:
    """(value, slope) of the monotone cubic table at x (nfdmodel.pchip: cubic Hermite on the
    node segment holding x, the straight line of the end slope beyond the last node)."""
    n = len(nodes)
    if x >= nodes[-1]:
        return values[-1] + slopes[-1] * (x - nodes[-1]), slopes[-1]
    k = 0
    while k < n - 2 and x >= nodes[k + 1]:
        k += 1
    h = nodes[k + 1] - nodes[k]
    t = (x - nodes[k]) / h
    y0, y1, d0, d1 = values[k], values[k + 1], slopes[k], slopes[k + 1]
    value = ((2 * t**3 - 3 * t**2 + 1) * y0 + (t**3 - 2 * t**2 + t) * h * d0 + (3 * t**2 - 2 * t**3) * y1
             + (t**3 - t**2) * h * d1)
    slope = (6 * t**2 - 6 * t) * (y0 - y1) / h + (3 * t**2 - 4 * t + 1) * d0 + (3 * t**2 - 2 * t) * d1
    return value, slope


def vz_table_approach(x: float, table) -> tuple[float, float]:
    """D(x) = (x^(1/3) + f(x))^2 / g(x) = delta/delta_Y on the loading curve, and dD/dx;
    ``table`` = (nodes, f, f slopes, g, g slopes)."""
    nodes, f_values, f_slopes, g_values, g_slopes = table
    f, df = hermite(x, nodes, f_values, f_slopes)
    g, dg = hermite(x, nodes, g_values, g_slopes)
    radius = x ** (1.0 / 3.0) + f
    D = radius * radius / g
    return D, (2.0 * radius * (x ** (-2.0 / 3.0) / 3.0 + df) - D * dg) / g


def vz_table_step(delta: float, history: History, R: float, E: float, P_Y: float, delta_Y: float,
                  a_Y: float, table) -> tuple[float, History]:
    """One time step of the vz-table law (nfdmodel.vz_table): Hertz up to delta_Y; beyond it
    x = P/P_Y solves D(x) = delta/delta_Y (bisection on a doubling bracket, then Newton kept
    inside it), C_Rmax = g(x), delta_res = delta - delta_Y x^(2/3) / C_Rmax; unloading
    P = K_u <delta - delta_res>^(3/2). A ValueError where the contact radius a_Y (x^(1/3) + f(x))
    reaches R."""
    if delta <= history.delta_max:
        return unloading_force(delta, history, 1.5), history
    if delta <= delta_Y:
        P = hertz_force(delta, R, E)
        return P, History(delta, P, 0.0, 4.0 / 3.0 * E * math.sqrt(R))
    x = vz_table_load(delta / delta_Y, table)
    nodes, f_values, f_slopes, g_values, g_slopes = table
    f = hermite(x, nodes, f_values, f_slopes)[0]
    g = hermite(x, nodes, g_values, g_slopes)[0]
    if not a_Y * (x ** (1.0 / 3.0) + f) < R:
        raise ValueError(f"delta out of range: at delta = {delta:g} m the vz-table contact radius reaches R* = {R:g} m")
    return x * P_Y, turning_point(delta, x * P_Y, delta - delta_Y * x ** (2.0 / 3.0) / g, 1.5)


def vz_table_load(d: float, table) -> float:
    """x = P/P_Y >= 1 on the vz-table loading curve at d = delta/delta_Y > 1: the root of
    D(x) = d (bisection on a doubling bracket, then Newton kept inside it)."""
    low, high = 1.0, 2.0
    while vz_table_approach(high, table)[0] < d:
        low, high = high, 2.0 * high
    x = 0.5 * (low + high)
    for _ in range(400):
        D, dD = vz_table_approach(x, table)
        if D < d:
            low = x
        else:
            high = x
        candidate = x - (D - d) / dD
        if not low < candidate < high:
            candidate = 0.5 * (low + high)
        if abs(candidate - x) <= 1e-13 * candidate or high - low <= 1e-13 * high:
            x = candidate
            break
        x = candidate
    return x


@dataclass(frozen=True)
class ExponentHistory(History):
    """A :class:`History` whose unloading curve carries its own exponent m (vz-unload)."""

    m: float = 1.5


def vz_unload_step(delta: float, history: ExponentHistory, R: float, E: float, P_Y: float, delta_Y: float,
                   a_Y: float, table, unloading) -> tuple[float, ExponentHistory]:
    """One time step of the vz-unload law (nfdmodel.vz_unload): Hertz up to delta_Y (delta_res = 0,
    m = 3/2); beyond it x = P/P_Y on the vz-table loading curve (``table`` as vz_table_step's),
    rho = delta_res/delta_max and m from ``unloading`` = (nodes, rho, rho slopes, m, m slopes) at
    x (held beyond the last node), delta_res = rho delta, K_u = P / (delta - delta_res)^m;
    unloading P = K_u <delta - delta_res>^m. A ValueError where the contact radius
    a_Y (x^(1/3) + f(x)) reaches R."""
    if delta <= history.delta_max:
        return unloading_force(delta, history, history.m), history
    if delta <= delta_Y:
        P = hertz_force(delta, R, E)
        return P, ExponentHistory(delta, P, 0.0, 4.0 / 3.0 * E * math.sqrt(R), 0.0, 1.5)
    x = vz_table_load(delta / delta_Y, table)
    nodes, f_values, f_slopes = table[:3]
    if not a_Y * (x ** (1.0 / 3.0) + hermite(x, nodes, f_values, f_slopes)[0]) < R:
        raise ValueError(f"delta out of range: at delta = {delta:g} m the vz-unload contact radius reaches R* = {R:g} m")
    u_nodes, rho_values, rho_slopes, m_values, m_slopes = unloading
    at = min(max(x, 1.0), u_nodes[-1])
    rho = hermite(at, u_nodes, rho_values, rho_slopes)[0]
    m = hermite(at, u_nodes, m_values, m_slopes)[0]
    delta_res = min(rho * delta, math.nextafter(delta, 0.0))
    P = x * P_Y
    return P, ExponentHistory(delta, P, delta_res, P / (delta - delta_res) ** m, 0.0, m)


# ----------------------------------------------------------------------------- thornton
def thornton_step(delta: float, history: History, R: float, E: float, P_Y: float, delta_Y: float,
                  p_Y: float) -> tuple[float, History]:
    """One time step of Thornton's (1997) law: Hertz up to delta_Y, then
    P = P_Y + pi p_Y R (delta - delta_Y); unloading from (P*, delta*) Hertzian with the enlarged
    radius R_p = 4 E a*^3 / (3 P*), a*^2 = (2 P* + P_Y) / (2 pi p_Y), about
    delta_p = delta* - a*^2 / R_p."""
    if delta <= history.delta_max:
        return unloading_force(delta, history, 1.5), history
    if delta <= delta_Y:
        P = hertz_force(delta, R, E)
        return P, History(delta, P, 0.0, 4.0 / 3.0 * E * math.sqrt(R))
    P = P_Y + math.pi * p_Y * R * (delta - delta_Y)
    a_sq = (2.0 * P + P_Y) / (2.0 * math.pi * p_Y)
    R_p = 4.0 * E * a_sq * math.sqrt(a_sq) / (3.0 * P)
    # Thornton's own unloading constant (4/3) E sqrt(R_p): equal to P / (delta - delta_p)^(3/2)
    return P, History(delta, P, max(delta - a_sq / R_p, 0.0), 4.0 / 3.0 * E * math.sqrt(R_p))


# ------------------------------------------------------------------------- walton-braun
def walton_braun_step(delta: float, history: History, K1: float, K2: float) -> tuple[float, History]:
    """One time step of Walton & Braun's (1986) law: P = K1 delta on loading,
    P = K2 <delta - delta_res> on unloading and reloading, delta_res = delta_max - P_max / K2."""
    if delta <= history.delta_max:
        return unloading_force(delta, history, 1.0), history
    P = K1 * delta
    return P, History(delta, P, delta - P / K2, K2)


# ---------------------------------------------------------------------------- rate-aware
def johnson_cook_factor(rate: float, C: float, reference_rate: float) -> float:
    """Johnson & Cook (1983): R = 1 + C ln(max(eps_dot / eps_dot_0, 1))."""
    return 1.0 + C * math.log(max(rate / reference_rate, 1.0))


def cowper_symonds_factor(rate: float, D: float, q: float) -> float:
    """Cowper & Symonds (1957): R = 1 + (eps_dot / D)^(1/q)."""
    return 1.0 + (rate / D) ** (1.0 / q)


@dataclass(frozen=True)
class RateHistory(History):
    """A :class:`History` with the rate factor R fixed at first contact (0: never touched)."""

    rate_factor: float = 0.0


def rate_aware_first_factor(speed: float, a_ref: float, c: float, factor) -> float:
    """R of a contact first touching at the normal speed ``speed`` [m/s]: ``factor``(eps_dot), eps_dot =
    speed / (c a_ref) [1/s], a_ref [m] the base law's contact radius at the peak of its impact at that
    speed (nfdmodel.collision_reference); eps_dot = 0 for speed <= 0."""
    return factor(speed / (c * a_ref) if speed > 0.0 else 0.0)


def rate_aware_step(delta: float, history: RateHistory, first_factor: float, base_step) -> tuple[float, RateHistory]:
    """One time step of the rate-aware law (nfdmodel.rate_aware): the base law (``base_step(delta,
    History) -> (P, History)``, e.g. vz_table_step with its constants) with p_Y scaled by R, i.e.
    P = R^3 P_0(delta / R^2), the history held in the base law's units at R = 1 (delta ~ R^2, P ~ R^3,
    a_e_max ~ R, K_u ~ 1). R is the history's, or ``first_factor`` where the contact first touches."""
    R = history.rate_factor
    if R == 0.0 and delta > 0.0:
        R = first_factor
    scale = R if R > 0.0 else 1.0
    base = History(history.delta_max / scale**2, history.P_max / scale**3, history.delta_res / scale**2,
                   history.K_u, history.a_e_max / scale)
    P, new = base_step(delta / scale**2, base)
    return P * scale**3, RateHistory(new.delta_max * scale**2, new.P_max * scale**3, new.delta_res * scale**2,
                                     new.K_u, new.a_e_max * scale, R)


def johnson_cook_rate(factor: float, C: float, reference_rate: float) -> float:
    """The inverse of johnson_cook_factor: eps_dot = eps_dot_0 exp((R - 1) / C) [1/s] (eps_dot_0 at R <= 1)."""
    excess = max(factor - 1.0, 0.0)
    if C == 0.0:
        return math.inf if excess > 0.0 else reference_rate
    return reference_rate * math.exp(excess / C) if excess / C < 709.0 else math.inf


def cowper_symonds_rate(factor: float, D: float, q: float) -> float:
    """The inverse of cowper_symonds_factor: eps_dot = D (R - 1)^q [1/s] (0 at R <= 1)."""
    excess = max(factor - 1.0, 0.0)
    return D * excess**q if excess > 0.0 else 0.0


@dataclass(frozen=True)
class RelaxingHistory(RateHistory):
    """A :class:`RateHistory` whose rate_factor s follows the strain rate (nfdmodel.rate_relaxing), with
    strain_rate_per_speed = 1 / (c a_ref) [1/m] fixed at first contact and the loading work [J]."""

    strain_rate_per_speed: float = 0.0
    loading_work: float = 0.0


def rate_relaxing_factor(factor: float, per_speed: float, increment: float, speed: float, stiffness: float,
                         rate_at) -> float:
    """Backward Euler of ds/dt = K (eps_dot - eps_dot_s(s)) over dt = increment / speed: the root s >= 1 of
    s - factor - K (per_speed increment - rate_at(s) increment / speed) = 0, by bisection (1 where the
    left side is >= 0 at s = 1)."""
    drive = factor + stiffness * per_speed * increment
    relax = stiffness * increment / speed

    def residual(s):
        return s - drive + relax * rate_at(s)

    if residual(1.0) >= 0.0:
        return 1.0
    low, high = 1.0, max(drive, 1.0)
    for _ in range(200):
        middle = 0.5 * (low + high)
        if residual(middle) < 0.0:
            low = middle
        else:
            high = middle
        if high - low <= 1e-15 * high:
            break
    return 0.5 * (low + high)


def rate_relaxing_step(delta: float, speed: float, history: RelaxingHistory, first_per_speed: float,
                       stiffness: float, rate_at, base_step) -> tuple[float, RelaxingHistory]:
    """One time step of the relaxing rate-aware law (nfdmodel.rate_relaxing): s = 1 and strain_rate_per_speed
    = ``first_per_speed`` where the contact first touches; where it loads beyond its turning point at
    ``speed`` > 0 [m/s], s moves by :func:`rate_relaxing_factor` (K = ``stiffness``, ``rate_at`` the rate law's
    inverse); then the base law at p_Y scaled by s (:func:`rate_aware_step`) and the loading work by the
    trapezoid rule."""
    s, per_speed = history.rate_factor, history.strain_rate_per_speed
    if s == 0.0 and delta > 0.0:
        s, per_speed = 1.0, first_per_speed
    loading = delta > history.delta_max and delta > 0.0
    if loading and speed > 0.0:
        s = rate_relaxing_factor(s, per_speed, delta - history.delta_max, speed, stiffness, rate_at)
    P, new = rate_aware_step(delta, RateHistory(history.delta_max, history.P_max, history.delta_res, history.K_u,
                                                history.a_e_max, s), s, base_step)
    work = history.loading_work
    if loading:
        work += 0.5 * (history.P_max + P) * (delta - history.delta_max)
    else:
        new = RateHistory(history.delta_max, history.P_max, history.delta_res, history.K_u, history.a_e_max, s)
    return P, RelaxingHistory(new.delta_max, new.P_max, new.delta_res, new.K_u, new.a_e_max, s, per_speed, work)

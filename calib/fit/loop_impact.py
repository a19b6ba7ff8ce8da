"""A load-unload loop P(alpha) thrown as a quasi-static impact: the collision of a mass m whose contact
follows the loop (Johnson 1985, section 11.4; Thornton 1997):

    m d2(alpha)/dt2 = -P(alpha),   the loading branch while d(alpha)/dt > 0, the unloading one after

so that, with W(alpha) = int_0^alpha P dalpha' on loading and the work returned on unloading,

    v_in,qs   = sqrt(2 W_load / m)                 the velocity that reaches P_max quasi-statically [m/s]
    e_qs      = sqrt(W_unload / W_load)            (the loop's restitution, calib.fe.loadpath)
    t_c,qs    = int dalpha / |v(alpha)|,  (1/2) m v^2 = (1/2) m v_in,qs^2 - W(alpha) on loading,
                                            = work returned from alpha_max to alpha on unloading
    P_qs(v_in) = P on the loading branch where W = (1/2) m v_in^2 (the dynamic impact's v_in;
                 the last segment extended linearly in W when v_in > v_in,qs)

t_c,qs in closed form per segment: on [a0, a1] with P linear, (1/2) m v^2 = c0 + c1 x + c2 x^2
(x = alpha - a0), and int dx / sqrt(quadratic) is an elementary function (arcsin / log / sqrt).
At alpha_max v = 0 and the integrand is 1/sqrt, integrable and exact in that form.
"""
from __future__ import annotations

import math

import numpy as np

HERTZ_POINTS = 32                # points on the Hertzian first load and last unloading step


def segment_time(length: float, c0: float, c1: float, c2: float) -> float:
    """int_0^length dx / sqrt(c0 + c1 x + c2 x^2) [s] for a quadratic that is >= 0 on [0, length]
    (units: x [m], the quadratic [m^2/s^2])."""
    if length <= 0.0:
        return 0.0
    scale = max(abs(c0), abs(c1) * length, abs(c2) * length ** 2)
    if abs(c2) * length ** 2 <= 1e-9 * scale:             # linear (or constant) in x
        if abs(c1) * length <= 1e-12 * scale:
            return length / math.sqrt(c0)
        return 2.0 * (math.sqrt(max(c0 + c1 * length, 0.0)) - math.sqrt(max(c0, 0.0))) / c1
    if c2 > 0.0:
        def antiderivative(x):
            return math.log(abs(2.0 * math.sqrt(c2 * max(c0 + c1 * x + c2 * x * x, 0.0)) + 2.0 * c2 * x + c1)) \
                / math.sqrt(c2)
    else:
        disc = math.sqrt(max(c1 * c1 - 4.0 * c0 * c2, 0.0))

        def antiderivative(x):
            return -math.asin(max(-1.0, min(1.0, (2.0 * c2 * x + c1) / disc))) / math.sqrt(-c2)
    return float(antiderivative(length) - antiderivative(0.0))


def branch_time(alpha, force, mass: float, energy_at_start: float, sign: float) -> float:
    """Time [s] to cross a piecewise linear branch (alpha [m], P [N], in the order the sphere moves)
    with kinetic energy ``energy_at_start`` [J] at its first point; ``sign`` -1 on loading (P
    decelerates the sphere), +1 on unloading (P accelerates it back)."""
    total, energy = 0.0, energy_at_start
    for a0, a1, p0, p1 in zip(alpha[:-1], alpha[1:], force[:-1], force[1:]):
        length = abs(a1 - a0)
        if length == 0.0:
            continue
        slope = (p1 - p0) / length
        # (1/2) m v^2 = energy + sign (p0 x + slope x^2 / 2)  ->  v^2 = 2/m (...)
        c0, c1, c2 = 2.0 * energy / mass, sign * 2.0 * p0 / mass, sign * slope / mass
        total += segment_time(length, max(c0, 0.0), c1, c2)
        energy += sign * 0.5 * (p0 + p1) * length
    return total


def hertzian(start, end, force_at_end, points: int = HERTZ_POINTS) -> tuple[np.ndarray, np.ndarray]:
    """``points`` inner points of P = force_at_end (x / x_end)^(3/2), x = |alpha - start|, from
    alpha = start (P = 0) to alpha = end (excluded both) [m], [N]."""
    s = np.linspace(0.0, 1.0, points + 2)[1:-1]
    return start + s * (end - start), force_at_end * s ** 1.5


def loop_impact(path: dict, mass: float, v_in: float) -> dict:
    """The quasi-static impact of a load-unload loop (module docstring) on a mass ``mass`` [kg] at
    ``v_in`` [m/s]: e, contact time, works; ``path`` holds loading_alpha, loading_P (from 0) and
    unloading_alpha, unloading_P (from the peak) [m], [N]."""
    a_load, p_load = np.asarray(path["loading_alpha"], float), np.asarray(path["loading_P"], float)
    a_unload, p_unload = np.asarray(path["unloading_alpha"], float), np.asarray(path["unloading_P"], float)
    # the first load (elastic) and the last unloading step (to separation) are Hertzian, P ~ x^(3/2):
    # sampled along that curve, not as one chord (a chord overstates their work by a quarter)
    a, p = hertzian(a_load[0], a_load[1], p_load[1])
    a_load, p_load = np.concatenate([a_load[:1], a, a_load[1:]]), np.concatenate([p_load[:1], p, p_load[1:]])
    a, p = hertzian(a_unload[-1], a_unload[-2], p_unload[-2])
    a_unload = np.concatenate([a_unload[:-1], a[::-1], a_unload[-1:]])
    p_unload = np.concatenate([p_unload[:-1], p[::-1], p_unload[-1:]])
    work_load = np.concatenate([[0.0], np.cumsum(0.5 * (p_load[1:] + p_load[:-1]) * np.diff(a_load))])
    w_load = float(work_load[-1])
    w_unload = float(np.sum(0.5 * (p_unload[1:] + p_unload[:-1]) * -np.diff(a_unload)))
    v_qs = math.sqrt(2.0 * w_load / mass)
    loading_time = branch_time(a_load, p_load, mass, w_load, -1.0)
    unloading_time = branch_time(a_unload, p_unload, mass, 0.0, 1.0)
    kinetic_in = 0.5 * mass * v_in ** 2
    if kinetic_in <= w_load:
        force_at_v_in = float(np.interp(kinetic_in, work_load, p_load))
    else:                                  # beyond the peak: the last segment, linear in W
        slope = (p_load[-1] - p_load[-2]) / (work_load[-1] - work_load[-2])
        force_at_v_in = float(p_load[-1] + slope * (kinetic_in - w_load))
    return {"e": math.sqrt(w_unload / w_load), "v_in_quasi_static": v_qs, "P_max": float(p_load[-1]),
            "P_max_at_v_in": force_at_v_in, "contact_time": loading_time + unloading_time,
            "loading_time": loading_time, "alpha_max": float(a_load[-1]), "dent": float(a_unload[-1]),
            "loading_work": w_load, "unloading_work": w_unload}

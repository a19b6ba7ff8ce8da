"""The vz loading curve of Vu-Quoc & Zhang (1999): its Newton solve, turning points and work.

Beyond first yield the contact radius is a_ep = a_e + a_p with the Hertz radius
a_e = (3 P R* / (4 E*))^(1/3) and the plastic radius a_p = Ca <P - P_Y> (paper eq. 2.5), the
sphere's curvature radius is C_R R* with C_R = 1 + Kc <P - P_Y> (paper eq. 3.6), and the
approach is delta = a_ep^2 / (C_R R*) (paper eqs. 3.4-3.5). Driven by displacement, the force
on the loading curve is the root P >= P_Y of the corrected Newton function (paper eq. 3.14
with its dimensional misprint fixed; nfdmodel/README.md, The NFD law on loading)

    F(P) = (P - P_Y) + c1 P^(1/3) - sqrt((1 + Kc (P - P_Y)) R* delta) / Ca = 0,
    c1 = (3 R* / (4 E*))^(1/3) / Ca  [N^(2/3)].

Unloading from a turning point (delta_max, P_max) freezes a_p and C_R (paper eqs. 3.19-3.22):
P = (4/3) E* C_Rmax^(3/2) sqrt(R*) <delta - delta_res>^(3/2) with the residual approach
delta_res = delta_max - a_e,max^2 / (C_Rmax R*). Every function takes the law's parameters
(:class:`nfdmodel.vz.VZParams`: pair, Ca [m/N], Kc [1/N], c1) and works on arrays.
"""
from __future__ import annotations

import math

import numpy as np

from . import limits

NEWTON_TOLERANCE = limits.VZ_TOLERANCE               # relative tolerance on P of the vz plastic-loading solve
NEWTON_MAX_ITERATIONS = limits.VZ_MAX_ITERATIONS     # never reached: the bracket halves at worst every other step
JUMP_NEWTON_STEPS = 4           # Newton steps from the explicit start (stage 2 of vz_plastic_solve)
# fdlibm's cube-root seed: the high 32 bits of y divided by 3 plus (1023 - 1023/3 - 0.0331) 2^20
# give y^(1/3) to 3.2 % (an exponent divided by 3 with a linear mantissa correction).
_CBRT_SEED = np.uint32(715094163)
_GAUSS_NODES, _GAUSS_WEIGHTS = np.polynomial.legendre.leggauss(12)


def vz_residual_approach(delta_max, P_max, params):
    """delta_res = delta_max - a_e,max^2 / (C_Rmax R*) [m] (paper eqs. 3.19-3.21), >= 0."""
    a_e = params.pair.hertz_radius(P_max)
    elastic_recovery = a_e**2 / (params.curvature_factor(P_max) * params.pair.R_star)
    return np.maximum(delta_max - elastic_recovery, 0.0)


def vz_turning_point(delta_max, P_max, cube_root, params, a_e=None, out=None):
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


def cube_root_estimate(y):
    """y^(1/3) to about 1e-4 relative for positive normal floats y, from +, *, / and integer
    operations only (so that the compiled kernel computes it bit for bit the same, in a loop the
    compiler vectorises; np.cbrt costs about ten square roots): fdlibm's seed, the exponent
    divided by 3 through the high 32 bits of the float (3.2 % off), then one Halley step
    t (t^3 + 2 y) / (2 t^3 + y) (cubic convergence: 3.2 % -> 2.1e-5)."""
    y = np.asarray(y, dtype=np.float64)
    high = (y.view(np.uint64) >> np.uint64(32)).astype(np.uint32)
    high //= np.uint32(3)
    high += _CBRT_SEED
    t = (high.astype(np.uint64) << np.uint64(32)).view(np.float64)
    t3 = t * t
    t3 *= t
    return t * ((t3 + 2.0 * y) / (2.0 * t3 + y))          # (the ratio first: no overflow)


def vz_explicit_start(R_delta, params):
    """An explicit approximation u_x [N^(1/3)] of the root u = P^(1/3) of the vz loading curve
    at R_delta = R* delta [m^2] (delta > delta_Y): the Newton start for approaches far from the
    last turning point.

    Divided by Ca, the loading curve a_e + a_p = sqrt(C_R R* delta) reads
    c1 u = psi(x) = b sqrt(1 + Kc x) - x with x = P - P_Y = u^3 - P_Y [N], b = sqrt(R* delta)/Ca.
    psi is concave and vanishes at the plastic asymptote x_B, the root of Ca x = sqrt(R* delta
    (1 + Kc x)) (a_e neglected; the bracket's upper end):

        x_B = (R* delta Kc + sqrt((R* delta Kc)^2 + 4 Ca^2 R* delta)) / (2 Ca^2)           [N]

    Replacing psi by its tangent there, psi(x) ~ gamma (x_B - x) with
    gamma = -psi'(x_B) = (2 + Kc x_B) / (2 (1 + Kc x_B)) in [1/2, 1], leaves a depressed cubic,
    in P_Y units (s = u / P_Y^(1/3), Ca_hat = Ca P_Y / a_Y, c1 / P_Y^(2/3) = 1 / Ca_hat):

        s^3 + p s = Q,   p = 1 / (Ca_hat gamma),   Q = 1 + x_B / P_Y,

    solved by Cardano's formula in its cancellation-free form
        w = (Q/2 + sqrt(Q^2/4 + (p/3)^3))^(1/3),   s = Q / (w^2 + p/3 + (p/(3 w))^2)
    (w from :func:`cube_root_estimate`). Exact for Kc = 0 (psi is then linear) up to the cube
    root's error (4.2e-5 in s); for Kc > 0 the tangent lies above the concave psi, so u_x is an upper bound
    of the root (to the cube root's error) that tends to it in both asymptotes, Hertz (p s >> s^3:
    s -> Q/p) and fully plastic (s^3 -> Q): 11 % above it at worst for the paper's constants
    (P ~ 66 P_Y), 4.2e-5 for Kc = 0 (tests/test_nfd_laws.py).
    """
    pair = params.pair
    Ca, Kc = params.Ca, params.Kc
    P_Y = pair.P_Y
    u_Y = P_Y ** (1.0 / 3.0)
    curvature = R_delta * Kc
    x_B = np.sqrt(curvature * curvature + (4.0 * Ca * Ca) * R_delta)
    x_B += curvature
    x_B /= 2.0 * Ca * Ca
    Kc_x = x_B * Kc
    # p/3 = 1 / (3 Ca_hat gamma) = (c1 / u_Y^2) 2 (1 + Kc x_B) / (3 (2 + Kc x_B))
    third = Kc_x + 1.0
    third *= (2.0 / 3.0) * (params.c1 / (u_Y * u_Y))
    third /= Kc_x + 2.0
    Q = x_B / P_Y
    Q += 1.0
    w = np.sqrt(Q * Q * 0.25 + third * third * third)
    w += 0.5 * Q
    w = cube_root_estimate(w)
    v = third / w
    denominator = w * w
    denominator += third
    denominator += v * v
    Q /= denominator
    Q *= u_Y
    return Q


def vz_residual(u, b, params):
    """F and dF/du at P = u^3 (u = P^(1/3) [N^(1/3)]); F is the corrected F(P):

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


def newton_converged(abs_previous, abs_step, u, tol_u):
    """The acceptance test of two successive Newton steps s_prev, s on u (C: newton_converged):
    the quadratic regime with a small a-posteriori error, or a step already at round-off level,

        ((|s| <= 0.01 |s_prev|) & (10 |s|^3 <= tol_u u s_prev^2)) | (|s| <= 0.01 tol_u u)
    """
    accept = abs_step <= abs_previous * 0.01
    error = abs_step * 10.0
    error *= abs_step
    error *= abs_step
    allowed = u * tol_u
    allowed *= abs_previous
    allowed *= abs_previous
    accept &= error <= allowed
    accept |= abs_step <= u * (0.01 * tol_u)
    return accept


def vz_plastic_force(delta, P_start, params, tolerance: float = NEWTON_TOLERANCE):
    """Force on the plastic loading branch (see :func:`vz_plastic_solve`): (P [N], iterations)."""
    delta = np.asarray(delta, dtype=float)
    P_start = np.broadcast_to(np.asarray(P_start, dtype=float), delta.shape)
    force, _, iterations = vz_plastic_solve(delta, P_start, params, tolerance)
    return force, iterations


def vz_plastic_solve(delta, P_start, params, tolerance: float = NEWTON_TOLERANCE,
                      start_is_cube_root: bool = False, out=None):
    """Force on the plastic loading branch, delta > delta_Y [m]: the root P [N] of

        F(P)  = (P - P_Y) + c1 P^(1/3) - sqrt((1 + Kc (P - P_Y)) R* delta) / Ca = 0
        F'(P) = 1 + c1 P^(-2/3) / 3 - Kc sqrt(R* delta) / (2 Ca sqrt(1 + Kc (P - P_Y)))

    (Vu-Quoc & Zhang 1999 eq. 3.14 with the dimensional misprint fixed;
    c1 = (3 R*/(4 E*))^(1/3) / Ca). Newton runs on u = P^(1/3) (dF/du = 3 u^2 F'(P); same root,
    no cube root per iteration), vectorised, with P_start (the force at a smaller approach, e.g.
    the previous P_max) as start and lower bracket, P_lo = max(P_start, P_Y), F(P_lo) <= 0.

    1. Fast path: two Newton steps s1, s2 for all contacts. Accepted when F' > 0 at both
       iterates, |s2| <= 0.01 |s1| (quadratic regime) and the a-posteriori error of the result,
       10 |s2|^3 / s1^2, is below the tolerance, and P >= P_lo. (DEM steps: almost all.)
    2. The others (approaches far beyond the start: jumps): JUMP_NEWTON_STEPS = 4 Newton steps
       from the lower of :func:`vz_explicit_start` (the loading curve's tangent approximation,
       above the root) and the fast path's last iterate if that lies above P_lo, kept >= P_lo,
       accepted after step k >= 2 by the same test on steps k-1 and k (:func:`_jump_newton`).
    3. The rest (never for the paper's constants): safeguarded Newton on the bracket
       [P_lo, P_hi] from stage 2's last iterate, P_hi = P_Y + x_hi with
       Ca^2 x_hi^2 = R* delta (1 + Kc x_hi) (a_ep >= Ca x bounds delta(P) from below, so
       F(P_hi) >= 0). A Newton step that leaves the bracket, goes uphill or does not halve the
       previous step is replaced by bisection (geometric while P_hi/P_lo > 2); stop when the
       step or the bracket is below the tolerance. Only unconverged contacts are iterated.

    Relative tolerance ``tolerance`` on P (limits.VZ_TOLERANCE). Returns (P [N], u = P^(1/3),
    Newton iterations per contact: 2, 2 + k after stage 2, 2 + 4 + the safe path's); P is written
    into ``out``.

    The stages, their acceptance tests and the operation order are nfd_kernel.c's, so the numpy
    backend returns the compiled kernel's numbers bit for bit. Both stop within the tolerance, up
    to 4e-11 from the exact root (nfdmodel.reference, solved to 1e-13); a solve converged to
    round-off (a bracketed Newton from P_lo) agrees with the reference to 5e-13 but with the
    kernel only to 1e-11 on P_max, 2e-10 on the unloading force near separation and 3e-8 on
    delta_res (ill-conditioned where the elastic recovery is tiny), beyond the 1e-12 the two
    backends are tested to (tests/test_native.py).
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
    F, slope = vz_residual(u_lo, b, params)
    step_1 = np.divide(F, slope, out=F)                     # s1 = F/F'
    u = u_lo - step_1
    np.maximum(u, u_min, out=u)
    ok = slope > 0.0
    F, slope = vz_residual(u, b, params)
    ok &= np.greater(slope, 0.0)
    step_2 = np.divide(F, slope, out=F)                     # s2
    u -= step_2
    ok &= newton_converged(np.abs(step_1, out=step_1), np.abs(step_2, out=step_2), u, tol_u)
    ok &= np.greater_equal(u, u_min)
    iterations = np.full(delta.shape[0], 2, dtype=np.int64)
    if ok.all():
        P = np.multiply(u, u, out=out)
        P *= u
        return P, u, iterations
    # Stage 2, the contacts whose start was poor (a jump far beyond the turning point): Newton
    # from the explicit start.
    rest = np.flatnonzero(~ok)
    u_start = vz_explicit_start(R_delta[rest], params)
    u_fast = u[rest]
    u_start = np.where((u_fast > u_lo[rest]) & (u_fast < u_start), u_fast, u_start)
    u_jump, steps = _jump_newton(u_start, u_lo[rest], b[rest], params, tol_u)
    done = steps > 0
    u[rest] = u_jump
    iterations[rest] += np.where(done, steps, JUMP_NEWTON_STEPS)
    if done.all():
        P = np.multiply(u, u, out=out)
        P *= u
        return P, u, iterations
    # Stage 3, the safe path on the remaining contacts (never for the paper's constants).
    rest = rest[~done]
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
        F, slope = vz_residual(ua, ba, params)
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


def _jump_newton(u_start, u_lo, b, params, tol_u):
    """Stage 2 of :func:`vz_plastic_solve`: JUMP_NEWTON_STEPS Newton steps on u from
    max(u_start, u_lo) (u_start the explicit start, u_lo <= root the lower bracket end), the
    iterates kept >= u_lo; accepted after step k >= 2 by the fast path's test on steps k-1 and k.
    Returns (u, k): the accepted iterate and k, or the last iterate and 0. The steps run on every
    contact (branch-free, as the compiled loop); an accepted value is kept."""
    u_min = u_lo * (1.0 - 1e-15)
    u = np.where(u_start > u_lo, u_start, u_lo)          # (as the C ternaries: a NaN start gives u_lo)
    result = u.copy()
    steps = np.zeros(u.shape[0], dtype=np.int64)
    abs_previous = np.zeros_like(u)
    rising_previous = np.zeros(u.shape[0], dtype=bool)
    for k in range(1, JUMP_NEWTON_STEPS + 1):
        F, slope = vz_residual(u, b, params)
        rising = slope > 0.0
        with np.errstate(divide="ignore", invalid="ignore"):
            step = np.divide(F, slope, out=F)
        u_newton = u - step
        abs_step = np.abs(step, out=step)
        if k >= 2:
            # the fast path's test, F' > 0 at both iterates, u >= u_lo
            accept = newton_converged(abs_previous, abs_step, u_newton, tol_u)
            accept &= rising & rising_previous & (u_newton >= u_min)
            accept &= steps == 0
            result[accept] = u_newton[accept]
            steps[accept] = k
        abs_previous, rising_previous = abs_step, rising
        u = np.where(u_newton < u_min, u_min, u_newton)
    return np.where(steps > 0, result, u), steps


def vz_loading_work(delta_max, P_max, params):
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

/* nfd_kernel.c: the runtime contact laws of nfdcal, one contact at a time (nfd_kernel.h describes
 * the laws and the API). The arithmetic follows nfdmodel's numpy kernels operation by operation
 * (same formulas, same order), so both give the same numbers to round-off. C99, math.h only.
 */
#include "nfd_friction.h"  /* nfd_kernel.h, and the contact models around the laws (static inline) */
#include "nfd_unload.h"    /* the vz_unload law (static inline, on the vz_table solve below) */
#include "nfd_rate.h"      /* the rate-aware law, and the Gauss-Legendre rules (static inline) */

#include <math.h>
#include <stdint.h>
#include <string.h>

#define NFD_PI 3.14159265358979323846
#ifdef __cplusplus                   /* the LAMMPS plugin compiles this source as C++ */
#define NFD_RESTRICT __restrict
#else
#define NFD_RESTRICT restrict
#endif
#if defined(__GNUC__)                /* vz_jump is large: inline it all the same, so that the */
#define NFD_ALWAYS_INLINE static inline __attribute__((always_inline))   /* loop over a block vectorises */
#else
#define NFD_ALWAYS_INLINE static inline
#endif
/* x86-64, gcc or clang: the batch loops also compiled for AVX2, chosen at load time (same numbers) */
#if defined(__x86_64__) && defined(__GNUC__) && defined(__linux__)
#define NFD_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define NFD_CLONES
#endif
#define NFD_JUMP_STEPS 4             /* Newton steps from the explicit start (vz_jump)          */
#define NFD_JUMP_BLOCK 256           /* contacts per vectorised block of vz_jump (nfd_vz_load) */
#define NFD_CBRT_SEED 715094163u     /* fdlibm: (1023 - 1023/3 - 0.03306) 2^20                  */
#define PLASTIC_LOADING 100          /* elastic_step: the law's own plastic solve must run       */

nfd_params nfd_pair(double R_star, double E_star, double p_Y)
{
    nfd_params p;
    memset(&p, 0, sizeof p);          /* the law's constants zero until set */
    p.R_star = R_star; p.E_star = E_star; p.p_Y = p_Y;
    p.P_Y = NFD_PI * NFD_PI * NFD_PI * R_star * R_star * p_Y * p_Y * p_Y / (6.0 * E_star * E_star);
    p.a_Y = nfd_hertz_radius(p.P_Y, R_star, E_star);
    p.delta_Y = p.a_Y * p.a_Y / R_star;
    p.hertz_k = 4.0 / 3.0 * E_star * sqrt(R_star);
    p.u_Y = pow(p.P_Y, 1.0 / 3.0);
    p.window_P_max = INFINITY;
    return p;
}

void nfd_vz_constants(nfd_params *p, double Ca, double Kc)
{
    p->Ca = Ca; p->Kc = Kc;
    p->c1 = pow(3.0 * p->R_star / (4.0 * p->E_star), 1.0 / 3.0) / Ca;
    p->u_Y = pow(p->P_Y, 1.0 / 3.0);
}

/* |sigma_z - sigma_r| / p0 on the axis of a Hertz contact at depth zeta = z/a (Johnson 1985
 * eq. 3.45; nfdmodel.materials.axis_stress_difference). */
static double axis_stress_difference(double zeta, double nu)
{
    double zeta_atan = zeta * atan2(1.0, zeta);      /* -> 0 at the surface, without 1/zeta */
    double sigma_z = -1.0 / (1.0 + zeta * zeta);
    double sigma_r = -(1.0 + nu) * (1.0 - zeta_atan) + 0.5 / (1.0 + zeta * zeta);
    return fabs(sigma_z - sigma_r);
}

/* The maximum over zeta in [0, 3] by golden-section search to 1e-13 in zeta (the function is
 * unimodal there), compared with the surface value |nu - 1/2|. */
double nfd_yield_factor(double nu)
{
    const double ratio = 0.5 * (sqrt(5.0) - 1.0);
    double a = 0.0, b = 3.0, c = b - ratio * (b - a), d = a + ratio * (b - a);
    double fc = axis_stress_difference(c, nu), fd = axis_stress_difference(d, nu);
    while (b - a > 1e-13) {
        if (fc > fd) {
            b = d; d = c; fd = fc; c = b - ratio * (b - a);
            fc = axis_stress_difference(c, nu);
        } else {
            a = c; c = d; fc = fd; d = a + ratio * (b - a);
            fd = axis_stress_difference(d, nu);
        }
    }
    double peak = axis_stress_difference(0.5 * (a + b), nu), surface = axis_stress_difference(0.0, nu);
    return 1.0 / (peak > surface ? peak : surface);
}

static double hertz(double delta, double k)
{
    double d = delta > 0.0 ? delta : 0.0;
    return sqrt(d) * d * k;
}

/* Unloading and reloading below the turning point (delta <= delta_max): P = K_u <delta - delta_res>^n,
 * the history unchanged. Returns 0 when the contact loads beyond its turning point instead. */
static int unloading(double delta, const nfd_history *h, int three_halves, double *force, nfd_history *out)
{
    if (delta > h->delta_max) return 0;
    double gap = delta - h->delta_res;
    if (gap < 0.0) gap = 0.0;
    *force = three_halves ? sqrt(gap) * gap * h->K_u : gap * h->K_u;
    *out = *h;
    return 1;
}

int nfd_hertz_step(double delta, const nfd_params *p, const nfd_history *h, double *force, nfd_history *out)
{
    if (!isfinite(delta)) return NFD_NOT_FINITE;
    *force = hertz(delta, p->hertz_k);
    *out = *h;
    return isfinite(*force) ? NFD_OK : NFD_NOT_FINITE;
}

/* ------------------------------------------------------------------------------------- vz */
/* F and dF/du at P = u^3 (nfdmodel.vz_curve.vz_residual), b = sqrt(R* delta) / Ca. */
static void vz_residual(double u, double b, const nfd_params *p, double c1, double one_minus,
                        double *F, double *slope)
{
    double u_sq = u * u;
    double f = u_sq * u;
    double sqrt_curvature = sqrt(f * p->Kc + one_minus);
    *F = f - p->P_Y + u * c1 - b * sqrt_curvature;
    *slope = (b / sqrt_curvature * (-0.5 * p->Kc) + 1.0) * (u_sq * 3.0) + c1;
}

/* The acceptance test of two successive Newton steps s_prev, s on u (vz_curve.newton_converged, in
 * its order): ((|s| <= 0.01 |s_prev|) & (10 |s|^3 <= tol_u u s_prev^2)) | (|s| <= 0.01 tol_u u). */
static inline int newton_converged(double abs_previous, double abs_step, double u, double tol_u)
{
    int accept = abs_step <= abs_previous * 0.01;
    accept &= abs_step * 10.0 * abs_step * abs_step <= u * tol_u * abs_previous * abs_previous;
    accept |= abs_step <= u * (0.01 * tol_u);
    return accept;
}

/* The fast path of the root u = P^(1/3) of F (nfdmodel.vz_curve.vz_plastic_solve): two Newton
 * steps from u_lo = max(u_start, u_Y), accepted in the quadratic regime. Branch-free, so that a
 * loop over many contacts vectorises (nfd_vz_load). Returns 1 when accepted (*u_out the root). */
static inline int vz_fast(double delta, double u_start, const nfd_params *p, double *u_out)
{
    const double tol_u = NFD_VZ_TOLERANCE / 3.0;
    const double one_minus = 1.0 - p->Kc * p->P_Y;
    double c1 = p->c1, b = sqrt(p->R_star * delta) / p->Ca;
    double u_lo = u_start > p->u_Y ? u_start : p->u_Y, u_min = u_lo * (1.0 - 1e-15);
    double F, slope, step_1, step_2, u;
    vz_residual(u_lo, b, p, c1, one_minus, &F, &slope);     /* two Newton steps from u_lo */
    step_1 = F / slope;
    u = u_lo - step_1 < u_min ? u_min : u_lo - step_1;
    int ok = slope > 0.0;
    vz_residual(u, b, p, c1, one_minus, &F, &slope);
    ok &= slope > 0.0;
    step_2 = F / slope;
    u -= step_2;
    ok &= newton_converged(fabs(step_1), fabs(step_2), u, tol_u) & (u >= u_min);
    *u_out = u;
    return ok;
}

/* y^(1/3) to 2.1e-5 relative for a positive normal y (nfdmodel.vz_curve.cube_root_estimate: fdlibm's
 * seed, one Halley step): integer and IEEE operations that vectorise, unlike cbrt(). */
static inline double cube_root_estimate(double y)
{
    uint64_t bits;
    double t;
    memcpy(&bits, &y, sizeof bits);
    uint32_t high = (uint32_t)(bits >> 32);
    bits = (uint64_t)(high / 3u + NFD_CBRT_SEED) << 32;
    memcpy(&t, &bits, sizeof t);
    double t3 = t * t * t;
    return t * ((t3 + 2.0 * y) / (2.0 * t3 + y));     /* the ratio first: no overflow */
}

/* The explicit start u_x [N^(1/3)] of the vz solve at R_delta = R* delta [m^2]
 * (nfdmodel.vz_curve.vz_explicit_start): the root of the depressed cubic s^3 + p s = Q in
 * s = u / u_Y, by Cardano without cancellation; exact for Kc = 0, above the root for Kc > 0. */
static inline double vz_explicit_start(double R_delta, const nfd_params *p)
{
    double Ca = p->Ca, Kc = p->Kc, u_Y = p->u_Y;
    double curvature = R_delta * Kc;
    double x_B = (sqrt(curvature * curvature + (4.0 * Ca * Ca) * R_delta) + curvature) / (2.0 * Ca * Ca);
    double Kc_x = x_B * Kc;
    /* p/3 = 2 (1 + Kc x_B) / (3 Ca_hat (2 + Kc x_B)), with c1 / u_Y^2 = 1 / Ca_hat */
    double third = (Kc_x + 1.0) * ((2.0 / 3.0) * (p->c1 / (u_Y * u_Y))) / (Kc_x + 2.0);
    double Q = x_B / p->P_Y + 1.0;
    double w = cube_root_estimate(sqrt(Q * Q * 0.25 + third * third * third) + 0.5 * Q);
    double v = third / w;
    return Q / (w * w + third + v * v) * u_Y;
}

/* One Newton step of vz_jump: from *u (kept >= u_min afterwards), with the acceptance test of the
 * fast path on this step and the previous one (*abs_previous, *rising_previous) when check;
 * an accepted iterate is kept in *result and the step number k in *steps. */
static inline void vz_jump_step(int k, int check, double b, double u_min, const nfd_params *p, double c1,
                                double one_minus, double *u, double *abs_previous, int *rising_previous,
                                double *result, int *steps)
{
    const double tol_u = NFD_VZ_TOLERANCE / 3.0;
    double F, slope;
    vz_residual(*u, b, p, c1, one_minus, &F, &slope);
    int rising = slope > 0.0;
    double step = F / slope;
    double u_newton = *u - step;
    double abs_step = fabs(step);
    if (check) {
        int accept = newton_converged(*abs_previous, abs_step, u_newton, tol_u);
        accept &= rising & *rising_previous & (u_newton >= u_min) & (*steps == 0);
        *result = accept ? u_newton : *result;
        *steps += accept * k;                   /* (accept holds at one k at most) */
    }
    *abs_previous = abs_step, *rising_previous = rising;
    *u = u_newton < u_min ? u_min : u_newton;
}

/* Stage 2 of the solve, when the fast path was not accepted (nfdmodel.vz_curve._jump_newton):
 * NFD_JUMP_STEPS Newton steps from min(u_x, u_fast) kept >= u_lo, accepted after step k >= 2 by
 * the fast path's test; branch-free, the steps written out (a loop over contacts vectorises).
 * Returns k, or 0 (then *u_out is the last iterate, the safe path's start). */
NFD_ALWAYS_INLINE int vz_jump(double delta, double u_start, double u_fast, const nfd_params *p, double *u_out)
{
    const double one_minus = 1.0 - p->Kc * p->P_Y;
    double c1 = p->c1, R_delta = p->R_star * delta;
    double b = sqrt(R_delta) / p->Ca;
    double u_lo = u_start > p->u_Y ? u_start : p->u_Y;
    double u_min = u_lo * (1.0 - 1e-15);
    double u = vz_explicit_start(R_delta, p);
    u = ((u_fast > u_lo) & (u_fast < u)) ? u_fast : u;
    u = u > u_lo ? u : u_lo;
    double result = u, abs_previous = 0.0;
    int rising_previous = 0, steps = 0;
    vz_jump_step(1, 0, b, u_min, p, c1, one_minus, &u, &abs_previous, &rising_previous, &result, &steps);
    vz_jump_step(2, 1, b, u_min, p, c1, one_minus, &u, &abs_previous, &rising_previous, &result, &steps);
    vz_jump_step(3, 1, b, u_min, p, c1, one_minus, &u, &abs_previous, &rising_previous, &result, &steps);
    vz_jump_step(4, 1, b, u_min, p, c1, one_minus, &u, &abs_previous, &rising_previous, &result, &steps);
    *u_out = steps > 0 ? result : u;
    return steps;
}

/* The safe path, when neither the fast path nor vz_jump was accepted: a safeguarded Newton on
 * the bracket [u_lo, u_hi] from vz_jump's last iterate u_fast; *iterations counts all three. */
static double vz_safe(double delta, double u_start, double u_fast, const nfd_params *p, int *iterations)
{
    const double tol_u = NFD_VZ_TOLERANCE / 3.0;
    const double one_minus = 1.0 - p->Kc * p->P_Y;
    double c1 = p->c1, R_delta = p->R_star * delta, Ca = p->Ca, Kc = p->Kc, F, slope;
    double b = sqrt(R_delta) / p->Ca;
    double x_hi = (R_delta * Kc + sqrt((R_delta * Kc) * (R_delta * Kc) + 4.0 * (Ca * Ca) * R_delta)) / (2.0 * (Ca * Ca));
    double lo = u_start > p->u_Y ? u_start : p->u_Y;
    double hi = cbrt((p->P_Y + x_hi) * (1.0 + 1e-12));
    if (hi < lo) hi = lo;
    double ua = (u_fast > lo && u_fast < hi) ? u_fast : lo;
    double previous_step = hi - lo;
    for (int iteration = 1; iteration <= NFD_VZ_MAX_ITERATIONS; ++iteration) {
        vz_residual(ua, b, p, c1, one_minus, &F, &slope);
        if (F < 0.0) lo = ua; else hi = ua;
        double step = F / slope;
        double u_newton = ua - step;
        double abs_step = fabs(step);
        int rising = slope > 0.0;
        int newton_ok = u_newton > lo && u_newton < hi && rising && abs_step <= 0.5 * previous_step;
        double bisection = hi > 1.26 * lo ? sqrt(lo * hi) : 0.5 * (lo + hi);
        int tiny_step = rising && abs_step <= tol_u * ua;
        double u_new = newton_ok ? u_newton : bisection;
        if (tiny_step) u_new = u_newton < lo ? lo : (u_newton > hi ? hi : u_newton);
        int root = F == 0.0;
        if (root) u_new = ua;
        double taken = fabs(u_new - ua);
        if (root || tiny_step || (hi - lo) <= tol_u * lo || (newton_ok && taken <= tol_u * u_new)) {
            *iterations = 2 + NFD_JUMP_STEPS + iteration;
            return u_new;
        }
        ua = u_new;
        previous_step = taken;
    }
    *iterations = 2 + NFD_JUMP_STEPS + NFD_VZ_MAX_ITERATIONS;
    return ua;
}

/* nextafter(x, 0) for a finite x > 0, as integer arithmetic on its bits (loops calling it vectorise). */
static inline double below(double x)
{
    int64_t bits;
    memcpy(&bits, &x, sizeof bits);
    --bits;
    memcpy(&x, &bits, sizeof x);
    return x;
}

/* The turning point of a plastic loading step at the root u = P^(1/3)
 * (nfdmodel.vz_curve.vz_turning_point): P_max, delta_res, K_u, a_e,max. Branch-free. */
static inline void vz_turning_point(double delta, double u, const nfd_params *p, double *P_out,
                                    double *delta_res_out, double *K_u_out, double *a_e_out)
{
    double P = u * u * u;
    double a_e = u * (p->c1 * p->Ca);
    double curvature = ((P - p->P_Y) * p->Kc + 1.0) * p->R_star;
    double delta_res = delta - a_e * a_e / curvature;
    delta_res = delta_res < 0.0 ? 0.0 : delta_res;
    /* delta_res >= delta only when the recovery underflows: keep the gap positive */
    delta_res = delta_res >= delta ? below(delta) : delta_res;
    double gap = delta - delta_res;
    *P_out = P; *delta_res_out = delta_res;
    *K_u_out = P / (sqrt(gap) * gap); *a_e_out = a_e;
}

/* Hertz loading below first yield as a turning point (delta <= delta_Y). */
static inline void vz_hertz_turning_point(double delta, const nfd_params *p, nfd_history *out)
{
    nfd_history loaded = {delta, hertz(delta, p->hertz_k), 0.0, p->hertz_k, 0.0};
    loaded.a_e_max = sqrt(p->R_star * (delta > 0.0 ? delta : 0.0));
    *out = loaded;
}

static inline int vz_status(const nfd_params *p, double P, double a_e)
{
    if (!isfinite(P)) return NFD_NOT_FINITE;
    double excess = P - p->P_Y;
    if (!(a_e + p->Ca * (excess > 0.0 ? excess : 0.0) < p->R_star)) return NFD_FULL_CONTACT;
    return P > p->window_P_max ? NFD_BEYOND_WINDOW : NFD_OK;
}

/* The branches vz and vz_table share (a non-finite approach, unloading or reloading, Hertz below
 * first yield): their status, or PLASTIC_LOADING when the law's own plastic solve must run. */
static int elastic_step(double delta, const nfd_params *p, const nfd_history *h, double *force, nfd_history *out,
                        int *iterations)
{
    if (iterations) *iterations = 0;
    if (!isfinite(delta)) return NFD_NOT_FINITE;
    if (unloading(delta, h, 1, force, out)) return NFD_OK;
    if (!(delta > p->delta_Y)) {                    /* Hertz below first yield */
        vz_hertz_turning_point(delta, p, out);
        *force = out->P_max;
        return isfinite(out->P_max) ? NFD_OK : NFD_NOT_FINITE;
    }
    return PLASTIC_LOADING;
}

int nfd_vz_step(double delta, const nfd_params *p, const nfd_history *h, double *force, nfd_history *out,
                int *iterations)
{
    int status = elastic_step(delta, p, h, force, out, iterations);
    if (status != PLASTIC_LOADING) return status;
    double start = h->a_e_max / (p->c1 * p->Ca);      /* a_e = u c1 Ca */
    double u;
    int count = 2;
    if (!vz_fast(delta, start, p, &u)) {
        int steps = vz_jump(delta, start, u, p, &u);
        if (steps > 0) count = 2 + steps;
        else u = vz_safe(delta, start, u, p, &count);
    }
    if (iterations) *iterations = count;
    out->delta_max = delta;
    vz_turning_point(delta, u, p, &out->P_max, &out->delta_res, &out->K_u, &out->a_e_max);
    *force = out->P_max;
    return vz_status(p, out->P_max, out->a_e_max);
}

/* Pass 2 of nfd_vz_load from contact `first` on (the first whose fast path failed): vz_jump on
 * blocks of such contacts (a vectorised loop), then vz_safe where vz_jump was not accepted; writes
 * u into P_max; returns the largest iteration count. Not inlined: it would slow pass 1 by 30 %. */
NFD_CLONES static int vz_jump_block(size_t n, size_t first, const nfd_params *p, const double *NFD_RESTRICT delta,
                                    double *NFD_RESTRICT P_max, const double *NFD_RESTRICT delta_res,
                                    const double *NFD_RESTRICT K_u)
{
    size_t at[NFD_JUMP_BLOCK], m = 0, i, j;
    double d[NFD_JUMP_BLOCK], start[NFD_JUMP_BLOCK], u_fast[NFD_JUMP_BLOCK], u[NFD_JUMP_BLOCK];
    int steps[NFD_JUMP_BLOCK], most = 2;
    for (i = first; i <= n; ++i) {
        if (i < n) {
            if (!(delta[i] > p->delta_Y) || K_u[i] != 0.0) continue;   /* Hertz, or the fast path held */
            at[m] = i;
            d[m] = delta[i];
            start[m] = delta_res[i];
            u_fast[m] = P_max[i];
            if (++m < NFD_JUMP_BLOCK) continue;
        }
        for (j = 0; j < m; ++j)                          /* a full block, or the last one */
            steps[j] = vz_jump(d[j], start[j], u_fast[j], p, &u[j]);
        for (j = 0; j < m; ++j) {
            int count = 2 + steps[j];
            if (steps[j] == 0) u[j] = vz_safe(d[j], start[j], u[j], p, &count);
            P_max[at[j]] = u[j];
            most = count > most ? count : most;
        }
        m = 0;
    }
    return most;
}

NFD_CLONES int nfd_vz_load(size_t n, const nfd_params *params, const double *NFD_RESTRICT delta,
                           double *NFD_RESTRICT a_e_max, double *NFD_RESTRICT P_max, double *NFD_RESTRICT delta_res,
                           double *NFD_RESTRICT K_u)
{
    const nfd_params local = *params;     /* not aliased by the outputs: the loops vectorise */
    const nfd_params *p = &local;
    const double radius_per_cube_root = p->c1 * p->Ca;
    int most = 0;
    size_t i;
    /* Four passes, the two long ones branch-free (vectorised). 1. the fast path for every contact:
     * meanwhile P_max holds u, delta_res the Newton start, K_u 1 where the fast path holds, else 0 */
    for (i = 0; i < n; ++i) {
        double start = a_e_max[i] / radius_per_cube_root;
        double u;
        int ok = vz_fast(delta[i], start, p, &u);
        P_max[i] = u;
        delta_res[i] = start;
        K_u[i] = ok ? 1.0 : 0.0;
    }
    /* 2. where the fast path did not hold (jumps far beyond the turning point): vz_jump_block */
    for (i = 0; i < n; ++i) {
        if (!(delta[i] > p->delta_Y)) continue;          /* Hertz: pass 4 */
        if (K_u[i] == 0.0) {
            int count = vz_jump_block(n, i, p, delta, P_max, delta_res, K_u);
            most = count > most ? count : most;
            break;
        }
        most = most > 2 ? most : 2;
    }
    /* 3. the turning points (vectorised) */
    for (i = 0; i < n; ++i)
        vz_turning_point(delta[i], P_max[i], p, &P_max[i], &delta_res[i], &K_u[i], &a_e_max[i]);
    /* 4. contacts still below first yield load on Hertz */
    for (i = 0; i < n; ++i) {
        if (delta[i] > p->delta_Y) continue;
        nfd_history h;
        vz_hertz_turning_point(delta[i], p, &h);
        P_max[i] = h.P_max; delta_res[i] = h.delta_res; K_u[i] = h.K_u; a_e_max[i] = h.a_e_max;
    }
    return most;
}

void nfd_vz_radii(const nfd_params *p, const nfd_history *h, double force, double *a_e, double *a_p, double *a_ep)
{
    double excess = h->P_max - p->P_Y;
    *a_e = nfd_hertz_radius(force, p->R_star, p->E_star);
    *a_p = p->Ca * (excess > 0.0 ? excess : 0.0);
    *a_ep = *a_e + *a_p;
}

/* ------------------------------------------------------------------------------ vz_table */
/* PCHIP end slope (nfdmodel.pchip._end_slope). */
static double end_slope(double h0, double h1, double s0, double s1)
{
    double d = ((2.0 * h0 + h1) * s0 - h0 * s1) / (h0 + h1);
    int sign_d = (d > 0.0) - (d < 0.0), sign_s0 = (s0 > 0.0) - (s0 < 0.0), sign_s1 = (s1 > 0.0) - (s1 < 0.0);
    if (sign_d != sign_s0) return 0.0;
    if (sign_s0 != sign_s1 && fabs(d) > fabs(3.0 * s0)) return 3.0 * s0;
    return d;
}

/* PCHIP node slopes (nfdmodel.pchip.pchip_slopes, Fritsch-Butland as scipy). */
void nfd_pchip_slopes(int n, const double *x, const double *y, double *d)
{
    if (n == 2) {
        d[0] = d[1] = (y[1] - y[0]) / (x[1] - x[0]);
        return;
    }
    for (int k = 1; k < n - 1; ++k) {
        double h0 = x[k] - x[k - 1], h1 = x[k + 1] - x[k];
        double s0 = (y[k] - y[k - 1]) / h0, s1 = (y[k + 1] - y[k]) / h1;
        double w1 = 2.0 * h1 + h0, w2 = h1 + 2.0 * h0;
        d[k] = s0 * s1 > 0.0 ? (w1 + w2) / (w1 / s0 + w2 / s1) : 0.0;
    }
    double h0 = x[1] - x[0], h1 = x[2] - x[1];
    d[0] = end_slope(h0, h1, (y[1] - y[0]) / h0, (y[2] - y[1]) / h1);
    double hl = x[n - 1] - x[n - 2], hm = x[n - 2] - x[n - 3];
    d[n - 1] = end_slope(hl, hm, (y[n - 1] - y[n - 2]) / hl, (y[n - 2] - y[n - 3]) / hm);
}

/* (value, slope) of a table at z (nfdmodel.pchip.pchip_evaluate: the cubic Hermite form, straight
 * continuations beyond the end nodes). */
void nfd_pchip_evaluate(int n, const double *x, const double *y, const double *d, double z, double *value,
                        double *slope)
{
    int lo = 0, hi = n - 1;
    if (z > x[n - 1] || z < x[0]) {
        int end = z > x[n - 1] ? n - 1 : 0;
        *value = y[end] + d[end] * (z - x[end]);
        *slope = d[end];
        return;
    }
    while (hi - lo > 1) {                 /* the segment: x[lo] <= z < x[lo+1], lo <= n - 2 */
        int mid = (lo + hi) / 2;
        if (x[mid] <= z) lo = mid; else hi = mid;
    }
    double x0 = x[lo], h = x[lo + 1] - x0;
    double s = (z - x0) / h;
    double y0 = y[lo], y1 = y[lo + 1], d0 = d[lo], d1 = d[lo + 1];
    double s2 = s * s;
    double s3 = s2 * s;
    *value = (2 * s3 - 3 * s2 + 1) * y0 + (s3 - 2 * s2 + s) * h * d0 + (3 * s2 - 2 * s3) * y1 + (s3 - s2) * h * d1;
    *slope = (6 * s2 - 6 * s) * (y0 - y1) / h + (3 * s2 - 4 * s + 1) * d0 + (3 * s2 - 2 * s) * d1;
}

/* D(z) = delta/delta_Y on the loading curve at z = P/P_Y >= 1 and dD/dz
 * (nfdmodel.vz_table.VZTableParams.scaled_approach). */
static void table_approach(const nfd_table *t, double z, double *D, double *dD)
{
    double f, df, g, dg;
    nfd_pchip_evaluate(t->n, t->x, t->f, t->df, z, &f, &df);
    nfd_pchip_evaluate(t->n, t->x, t->g, t->dg, z, &g, &dg);
    double c = cbrt(z);
    double radius = c + f;
    double value = radius * radius / g;
    *D = value;
    *dD = (2.0 * radius * (1.0 / (3.0 * c * c) + df) - value * dg) / g;
}

int nfd_table_init(nfd_table *t, int n, const double *x, const double *f, const double *g)
{
    if (n < 2 || n > NFD_TABLE_MAX_NODES || x[0] != 1.0 || f[0] != 0.0 || g[0] != 1.0) return -1;
    for (int k = 0; k < n; ++k) {
        if (!(isfinite(x[k]) && isfinite(f[k]) && isfinite(g[k]) && g[k] > 0.0)) return -1;
        if (k > 0 && !(x[k] > x[k - 1] && f[k] >= f[k - 1])) return -1;
        t->x[k] = x[k]; t->f[k] = f[k]; t->g[k] = g[k];
    }
    t->n = n; t->n_unload = 0;            /* vz_table: no unloading tables (nfd_unload_table_init) */
    nfd_pchip_slopes(n, t->x, t->f, t->df);
    nfd_pchip_slopes(n, t->x, t->g, t->dg);
    double slope;
    for (int k = 0; k < n; ++k) table_approach(t, t->x[k], &t->D[k], &slope);
    return 0;
}

/* x >= 1 with D(x) = d (> 1) (nfdmodel.vz_table.VZTableParams.solve): the segment of the node
 * approaches brackets the root, doubled beyond the table; Newton inside it from the start
 * (the last turning point), bisection where Newton strays. */
static double table_solve(const nfd_table *t, double d, double start, int *iterations)
{
    int n = t->n, k = -1, iteration;
    double D, dD;
    for (int j = 0; j < n; ++j)           /* k = searchsorted(D, d, "right") - 1 */
        if (t->D[j] <= d) k = j;
    double low = t->x[k < 0 ? 0 : (k > n - 1 ? n - 1 : k)];
    double high = k < n - 1 ? t->x[k + 1 < 0 ? 0 : k + 1] : t->x[n - 1] * 2.0;
    while (k >= n - 1 && (table_approach(t, high, &D, &dD), D < d)) {    /* beyond the table: doubled */
        low = high;
        high *= 2.0;
    }
    double z = start < low ? low : (start > high ? high : start);
    for (iteration = 1; iteration <= NFD_TABLE_MAX_ITERATIONS; ++iteration) {
        table_approach(t, z, &D, &dD);
        double residual = D - d;
        if (residual < 0.0) low = z; else high = z;
        double candidate = z - residual / dD;
        if (!(candidate > low && candidate < high)) candidate = 0.5 * (low + high);
        int done = fabs(candidate - z) <= NFD_TABLE_TOLERANCE * candidate;
        z = candidate;
        if (done || high - low <= NFD_TABLE_TOLERANCE * high) break;
    }
    table_approach(t, z, &D, &dD);        /* one more Newton step inside the bracket: the root to round-off */
    double candidate = z - (D - d) / dD;
    if ((candidate >= low && candidate <= high) || fabs(candidate - z) <= 1e-9 * z) z = candidate;
    *iterations = iteration > NFD_TABLE_MAX_ITERATIONS ? NFD_TABLE_MAX_ITERATIONS : iteration;
    return z;
}

double nfd_vz_table_radius(const nfd_params *p, const nfd_table *t, double P)
{
    double z = P / p->P_Y, f, df;
    nfd_pchip_evaluate(t->n, t->x, t->f, t->df, z, &f, &df);
    return p->a_Y * (cbrt(z) + f);
}

int nfd_vz_table_step(double delta, const nfd_params *p, const nfd_table *t, const nfd_history *h, double *force,
                      nfd_history *out, int *iterations)
{
    int status = elastic_step(delta, p, h, force, out, iterations);
    if (status != PLASTIC_LOADING) return status;
    double start = h->P_max / p->P_Y, f, df, g, dg;
    int count = 0;
    double z = table_solve(t, delta / p->delta_Y, start > 1.0 ? start : 1.0, &count);
    if (iterations) *iterations = count;
    double P = z * p->P_Y;
    nfd_pchip_evaluate(t->n, t->x, t->f, t->df, z, &f, &df);
    nfd_pchip_evaluate(t->n, t->x, t->g, t->dg, z, &g, &dg);
    double c = cbrt(z);
    double delta_res = delta - p->delta_Y * (c * c) / g;     /* a_e,max^2 / (C_Rmax R*) */
    delta_res = delta_res < 0.0 ? 0.0 : delta_res;
    delta_res = delta_res >= delta ? below(delta) : delta_res;
    double gap = delta - delta_res;
    nfd_history loaded = {delta, P, delta_res, P / (gap * sqrt(gap)), p->a_Y * c};
    *out = loaded;
    *force = P;
    if (!isfinite(P)) return NFD_NOT_FINITE;
    if (!(p->a_Y * (c + f) < p->R_star)) return NFD_FULL_CONTACT;
    return P > p->window_P_max ? NFD_BEYOND_WINDOW : NFD_OK;
}

/* ------------------------------------------------------------------------------- thornton */
int nfd_thornton_step(double delta, const nfd_params *p, const nfd_history *h, double *force, nfd_history *out)
{
    if (!isfinite(delta)) return NFD_NOT_FINITE;
    if (unloading(delta, h, 1, force, out)) return NFD_OK;
    if (!(delta > p->delta_Y)) {
        nfd_history elastic = {delta, hertz(delta, p->hertz_k), 0.0, p->hertz_k, 0.0};
        *out = elastic;
        *force = elastic.P_max;
        return isfinite(elastic.P_max) ? NFD_OK : NFD_NOT_FINITE;
    }
    /* P = P_Y + pi p_Y R* (delta - delta_Y); unloading from (P*, delta*) with
       a*^2 = (2 P* + P_Y) / (2 pi p_Y), R_p* = 4 E* a*^3 / (3 P*), delta_p = delta* - a*^2 / R_p* */
    double P = p->P_Y + NFD_PI * p->p_Y * p->R_star * (delta - p->delta_Y);
    double P_safe = P > 1e-300 ? P : 1e-300;
    double a_sq = (2.0 * P_safe + p->P_Y) / (2.0 * NFD_PI * p->p_Y);
    double R_p = 4.0 * p->E_star * a_sq * sqrt(a_sq) / (3.0 * P_safe);
    double delta_p = delta - a_sq / R_p;
    nfd_history plastic = {delta, P, delta_p > 0.0 ? delta_p : 0.0, 4.0 / 3.0 * p->E_star * sqrt(R_p), 0.0};
    *out = plastic;
    *force = P;
    return isfinite(P) ? NFD_OK : NFD_NOT_FINITE;
}

/* --------------------------------------------------------------------------- walton_braun */
int nfd_walton_braun_step(double delta, const nfd_params *p, const nfd_history *h, double *force,
                          nfd_history *out)
{
    if (!isfinite(delta)) return NFD_NOT_FINITE;
    if (unloading(delta, h, 0, force, out)) return NFD_OK;
    double P = p->K1 * delta;
    nfd_history loaded = {delta, P, delta - P / p->K2, p->K2, 0.0};
    *out = loaded;
    *force = P;
    return isfinite(P) ? NFD_OK : NFD_NOT_FINITE;
}

int nfd_step(int law, double delta, const nfd_params *p, const nfd_table *t, const nfd_history *h, double *force,
             nfd_history *out, int *iterations)
{
    if (iterations) *iterations = 0;
    switch (law) {
    case NFD_LAW_HERTZ: return nfd_hertz_step(delta, p, h, force, out);
    case NFD_LAW_VZ: return nfd_vz_step(delta, p, h, force, out, iterations);
    case NFD_LAW_THORNTON: return nfd_thornton_step(delta, p, h, force, out);
    case NFD_LAW_VZ_TABLE: return nfd_vz_table_step(delta, p, t, h, force, out, iterations);
    case NFD_LAW_WALTON_BRAUN: return nfd_walton_braun_step(delta, p, h, force, out);
    case NFD_LAW_VZ_UNLOAD: return nfd_vz_unload_step(delta, p, t, h, force, out, iterations);
    default: return NFD_UNKNOWN_LAW;
    }
}

/* ------------------------------------------------------------------------- vz admissibility */

/* The k-th of n loads geomspace(first, last, n), as numpy's (its ends exact). */
static double geomspace(double first, double last, int k, int n)
{
    if (k == 0 || k == n - 1) return k == 0 ? first : last;
    return pow(10.0, log10(first) + (log10(last) - log10(first)) * k / (n - 1));
}

/* D = delta/delta_Y on the vz loading curve at p = P/P_Y >= 1: (p^(1/3) + Ca_hat (p - 1))^2 / C_R. */
static double scaled_approach(double p, double Ca_hat, double Kc_hat)
{
    double radius = cbrt(p) + Ca_hat * (p - 1.0);
    return radius * radius / (1.0 + Kc_hat * (p - 1.0));
}

/* The largest relative excess returned/taken - 1 of a full cycle to the dissipation loads p, *load
 * its p (VZParams._energy_excess, in units of P_Y delta_Y): returned p (p^(2/3) / C_R) / (5/2),
 * taken 2/5 (Hertz) + p D(p) - 1 - integral_1^p D dq by Gauss-Legendre panels of width <= 1 in
 * t = ln(1 + (q - 1)/s), s = min(1, 1/Kc_hat) (vz_curve.vz_loading_work). A NaN stays. */
static double energy_excess(double Ca_hat, double Kc_hat, double *load)
{
    double s = Kc_hat <= 1.0 ? 1.0 : 1.0 / Kc_hat, worst = -INFINITY;
    int panels = (int)ceil(log1p((NFD_DISSIPATION_LOAD_MAX - 1.0) / s));
    for (int k = 0; k < NFD_DISSIPATION_POINTS; ++k) {
        double p = geomspace(NFD_DISSIPATION_LOAD_MIN, NFD_DISSIPATION_LOAD_MAX, k, NFD_DISSIPATION_POINTS);
        double width = log1p((p - 1.0) / s) / panels, integral = 0.0;
        for (int panel = 0; panel < panels; ++panel)
            for (int i = 0; i < 12; ++i) {
                double x, w;
                nfd_gauss_node(nfd_gauss12_x, nfd_gauss12_w, 6, i, &x, &w);      /* nfd_rate.h */
                double q = s * expm1((panel + 0.5 * (x + 1.0)) * width);      /* q - 1 */
                integral += 0.5 * width * w * scaled_approach(1.0 + q, Ca_hat, Kc_hat) * (s + q);
            }
        double taken = 0.4 + p * scaled_approach(p, Ca_hat, Kc_hat) - 1.0 - integral;
        double excess = p * (cbrt(p) * cbrt(p) / (1.0 + Kc_hat * (p - 1.0))) / 2.5 / taken - 1.0;
        if (!(excess <= worst) && worst == worst) { worst = excess; *load = p; }
    }
    return worst;
}

int nfd_vz_admissible(double Ca_hat, double Kc_hat, double *load, double *restitution)
{
    double least = INFINITY;
    *load = *restitution = NAN;
    if (!(Ca_hat >= NFD_CA_HAT_MIN && Ca_hat <= NFD_CA_HAT_MAX && Kc_hat >= 0.0 && Kc_hat <= NFD_KC_HAT_MAX))
        return NFD_VZ_OUT_OF_RANGE;
    for (int k = 0; k < NFD_MONOTONE_POINTS; ++k) {    /* VZParams._monotone_violation */
        double p = geomspace(1.0, NFD_MONOTONE_LOAD_MAX, k, NFD_MONOTONE_POINTS);
        double A = 2.0 / 3.0 * pow(p, -2.0 / 3.0) + 2.0 * Ca_hat;
        double slope = A + Kc_hat * (Ca_hat * (p - 1.0) - cbrt(p) * (p + 2.0) / (3.0 * p));
        if (slope < least) { least = slope; *load = p; }
    }
    if (!(least > 0.0)) return NFD_VZ_TURNS_BACK;
    double excess = energy_excess(Ca_hat, Kc_hat, load);
    *restitution = sqrt(1.0 + excess);
    return excess <= NFD_DISSIPATION_SLACK ? NFD_VZ_ADMISSIBLE : NFD_VZ_CREATES_ENERGY;
}

/* nfd_kernel.c: the runtime contact laws of nfdcal, one contact at a time (see nfd_kernel.h).
 *
 * The arithmetic follows nfdmodel's numpy kernels operation by operation (same formulas, same
 * order), so both give the same numbers to round-off: the vz Newton solve is the same two-step
 * fast path with the same acceptance test, then the same safeguarded bracketed iteration.
 * C99, math.h only.
 */
#include "nfd_kernel.h"

#include <math.h>

#define NFD_PI 3.14159265358979323846
#define NFD_TOLERANCE 1e-10          /* relative, on P, of the vz plastic-loading solve       */
#define NFD_MAX_ITERATIONS 200       /* never reached: the bracket halves at worst every other */

nfd_params nfd_pair(double R_star, double E_star, double p_Y)
{
    nfd_params p;
    double a_Y;
    p.R_star = R_star;
    p.E_star = E_star;
    p.p_Y = p_Y;
    p.P_Y = NFD_PI * NFD_PI * NFD_PI * R_star * R_star * p_Y * p_Y * p_Y / (6.0 * E_star * E_star);
    a_Y = cbrt(3.0 * p.P_Y * R_star / (4.0 * E_star));
    p.a_Y = a_Y;
    p.delta_Y = a_Y * a_Y / R_star;
    p.hertz_k = 4.0 / 3.0 * E_star * sqrt(R_star);
    p.Ca = 0.0;
    p.Kc = 0.0;
    p.c1 = 0.0;
    p.u_Y = pow(p.P_Y, 1.0 / 3.0);
    p.window_P_max = INFINITY;
    p.K1 = 0.0;
    p.K2 = 0.0;
    return p;
}

void nfd_vz_constants(nfd_params *p, double Ca, double Kc)
{
    p->Ca = Ca;
    p->Kc = Kc;
    p->c1 = pow(3.0 * p->R_star / (4.0 * p->E_star), 1.0 / 3.0) / Ca;
    p->u_Y = pow(p->P_Y, 1.0 / 3.0);
}

static double hertz(double delta, double k)
{
    double d = delta > 0.0 ? delta : 0.0;
    double f = sqrt(d);
    f *= d;
    return f * k;
}

/* Unloading and reloading about the turning point: P = K_u <delta - delta_res>^n. */
static double unloading(double delta, const nfd_history *h, int three_halves)
{
    double gap = delta - h->delta_res;
    if (gap < 0.0) gap = 0.0;
    if (three_halves) {
        double f = sqrt(gap);
        f *= gap;
        return f * h->K_u;
    }
    return gap * h->K_u;
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
    double sqrt_curvature = f * p->Kc;
    sqrt_curvature += one_minus;
    sqrt_curvature = sqrt(sqrt_curvature);
    f -= p->P_Y;
    f += u * c1;
    f -= b * sqrt_curvature;
    *F = f;
    double s = b / sqrt_curvature;
    s *= -0.5 * p->Kc;
    s += 1.0;
    s *= u_sq * 3.0;
    s += c1;
    *slope = s;
}

/* The root u = P^(1/3) of F (nfdmodel.vz_curve.vz_plastic_solve): two Newton steps accepted
 * in the quadratic regime, else a safeguarded Newton on the bracket [u_lo, u_hi]. */
static double vz_solve(double delta, double u_start, const nfd_params *p, double c1, int *iterations)
{
    const double tol_u = NFD_TOLERANCE / 3.0;
    const double one_minus = 1.0 - p->Kc * p->P_Y;
    double R_delta = p->R_star * delta;
    double b = sqrt(R_delta);
    b /= p->Ca;
    double u_lo = u_start > p->u_Y ? u_start : p->u_Y;
    double u_min = u_lo * (1.0 - 1e-15);
    double F, slope, step_1, step_2, u;
    int ok;

    vz_residual(u_lo, b, p, c1, one_minus, &F, &slope);
    step_1 = F / slope;
    u = u_lo - step_1;
    if (u < u_min) u = u_min;
    ok = slope > 0.0;
    vz_residual(u, b, p, c1, one_minus, &F, &slope);
    ok = ok && slope > 0.0;
    step_2 = F / slope;
    u -= step_2;
    {
        double abs_1 = fabs(step_1), abs_2 = fabs(step_2);
        int accept = abs_2 <= abs_1 * 0.01;
        double error = abs_2 * 10.0;
        error *= abs_2;
        error *= abs_2;
        double allowed = u * tol_u;
        allowed *= abs_1;
        allowed *= abs_1;
        accept = accept && error <= allowed;
        accept = accept || abs_2 <= u * (0.01 * tol_u);
        ok = ok && accept && u >= u_min;
    }
    *iterations = 2;
    if (ok) return u;

    /* the safe path */
    double Ca = p->Ca, Kc = p->Kc;
    double x_hi = (R_delta * Kc + sqrt((R_delta * Kc) * (R_delta * Kc) + 4.0 * (Ca * Ca) * R_delta)) / (2.0 * (Ca * Ca));
    double lo = u_lo;
    double hi = cbrt((p->P_Y + x_hi) * (1.0 + 1e-12));
    if (hi < lo) hi = lo;
    double ua = (u > lo && u < hi) ? u : lo;
    double previous_step = hi - lo;
    for (int iteration = 1; iteration <= NFD_MAX_ITERATIONS; ++iteration) {
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
            *iterations = 2 + iteration;
            return u_new;
        }
        ua = u_new;
        previous_step = taken;
    }
    *iterations = 2 + NFD_MAX_ITERATIONS;
    return ua;
}

int nfd_vz_step(double delta, const nfd_params *p, const nfd_history *h, double *force, nfd_history *out,
                int *iterations)
{
    if (iterations) *iterations = 0;
    if (!isfinite(delta)) return NFD_NOT_FINITE;
    if (!(delta > h->delta_max)) {                  /* unloading or reloading */
        *force = unloading(delta, h, 1);
        *out = *h;
        return NFD_OK;
    }
    if (!(delta > p->delta_Y)) {                    /* Hertz below first yield */
        double P = hertz(delta, p->hertz_k);
        out->delta_max = delta;
        out->P_max = P;
        out->delta_res = 0.0;
        out->K_u = p->hertz_k;
        out->a_e_max = sqrt(p->R_star * (delta > 0.0 ? delta : 0.0));
        *force = P;
        return isfinite(P) ? NFD_OK : NFD_NOT_FINITE;
    }
    /* c1 = (3 R* / (4 E*))^(1/3) / Ca, as VZParams.c1; a_e = u c1 Ca */
    double c1 = p->c1;
    double radius_per_cube_root = c1 * p->Ca;
    double start = h->a_e_max;
    start /= radius_per_cube_root;
    int count = 0;
    double u = vz_solve(delta, start, p, c1, &count);
    if (iterations) *iterations = count;
    double P = u * u;
    P *= u;
    double a_e = u * radius_per_cube_root;
    /* the turning point (nfdmodel.vz_curve.vz_turning_point) */
    double curvature = P - p->P_Y;
    curvature *= p->Kc;
    curvature += 1.0;
    curvature *= p->R_star;
    double recovery = a_e * a_e;
    recovery /= curvature;
    double delta_res = delta - recovery;
    if (delta_res < 0.0) delta_res = 0.0;
    if (delta_res >= delta) delta_res = nextafter(delta, 0.0);
    double gap = delta - delta_res;
    double stiffness = sqrt(gap);
    stiffness *= gap;
    out->delta_max = delta;
    out->P_max = P;
    out->delta_res = delta_res;
    out->K_u = P / stiffness;
    out->a_e_max = a_e;
    *force = P;
    if (!isfinite(P)) return NFD_NOT_FINITE;
    double excess = P - p->P_Y;
    if (!(a_e + p->Ca * (excess > 0.0 ? excess : 0.0) < p->R_star)) return NFD_FULL_CONTACT;
    return P > p->window_P_max ? NFD_BEYOND_WINDOW : NFD_OK;
}

void nfd_vz_radii(const nfd_params *p, const nfd_history *h, double force, double *a_e, double *a_p, double *a_ep)
{
    double excess = h->P_max - p->P_Y;
    *a_e = cbrt(3.0 * force * p->R_star / (4.0 * p->E_star));
    *a_p = p->Ca * (excess > 0.0 ? excess : 0.0);
    *a_ep = *a_e + *a_p;
}

/* ------------------------------------------------------------------------------- thornton */
int nfd_thornton_step(double delta, const nfd_params *p, const nfd_history *h, double *force, nfd_history *out)
{
    if (!isfinite(delta)) return NFD_NOT_FINITE;
    if (!(delta > h->delta_max)) {
        *force = unloading(delta, h, 1);
        *out = *h;
        return NFD_OK;
    }
    if (!(delta > p->delta_Y)) {
        double P = hertz(delta, p->hertz_k);
        out->delta_max = delta;
        out->P_max = P;
        out->delta_res = 0.0;
        out->K_u = p->hertz_k;
        out->a_e_max = 0.0;
        *force = P;
        return isfinite(P) ? NFD_OK : NFD_NOT_FINITE;
    }
    /* P = P_Y + pi p_Y R* (delta - delta_Y); unloading from (P*, delta*) with
       a*^2 = (2 P* + P_Y) / (2 pi p_Y), R_p* = 4 E* a*^3 / (3 P*), delta_p = delta* - a*^2 / R_p* */
    double P = p->P_Y + NFD_PI * p->p_Y * p->R_star * (delta - p->delta_Y);
    double P_safe = P > 1e-300 ? P : 1e-300;
    double a_sq = (2.0 * P_safe + p->P_Y) / (2.0 * NFD_PI * p->p_Y);
    double R_p = 4.0 * p->E_star * a_sq * sqrt(a_sq) / (3.0 * P_safe);
    double delta_p = delta - a_sq / R_p;
    out->delta_max = delta;
    out->P_max = P;
    out->delta_res = delta_p > 0.0 ? delta_p : 0.0;
    out->K_u = 4.0 / 3.0 * p->E_star * sqrt(R_p);
    out->a_e_max = 0.0;
    *force = P;
    return isfinite(P) ? NFD_OK : NFD_NOT_FINITE;
}

/* --------------------------------------------------------------------------- walton_braun */
int nfd_walton_braun_step(double delta, const nfd_params *p, const nfd_history *h, double *force,
                          nfd_history *out)
{
    if (!isfinite(delta)) return NFD_NOT_FINITE;
    if (!(delta > h->delta_max)) {
        *force = unloading(delta, h, 0);
        *out = *h;
        return NFD_OK;
    }
    double P = p->K1 * delta;
    out->delta_max = delta;
    out->P_max = P;
    out->delta_res = delta - P / p->K2;
    out->K_u = p->K2;
    out->a_e_max = 0.0;
    *force = P;
    return isfinite(P) ? NFD_OK : NFD_NOT_FINITE;
}

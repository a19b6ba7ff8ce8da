/* nfd_rate.h: the rate-aware law (nfdmodel.rate_aware; its scalar specification
 * nfdmodel.reference.rate_aware_step): a base law, vz or vz_table, whose yield stress is scaled by
 * the factor R of the contact's strain rate, fixed at first contact:
 *
 *     eps_dot = v_n0 / (c a_ref)                                               [1/s]
 *     Johnson-Cook (ln form)  R = 1 + C ln(max(eps_dot / eps_dot_0, 1))
 *     Cowper-Symonds          R = 1 + (eps_dot / D)^(1/q)
 *     P(delta; R) = R^3 P_0(delta / R^2)                                        [N]
 *
 * v_n0 [m/s] the normal approach speed at first contact (eps_dot = 0 for v_n0 <= 0), a_ref [m] the
 * base law's contact radius at the peak of a sphere-on-flat impact at v_n0 of the pair's reduced
 * mass m* (the energy balance W(delta_max) = m* v_n0^2 / 2 of nfdmodel.collision_reference: the
 * Hertz approach, doubled until W >= m* v^2 / 2, Newton from above to NFD_REFERENCE_TOLERANCE),
 * c [-] NFD_RATE_LENGTH_FACTOR by default, P_0 the base law at R = 1 (nfd_params of sigma_Y). The
 * history is the base law's nfd_history in SI (delta_max, delta_res ~ R^2, P_max ~ R^3, a_e_max ~
 * R (vz; vz_table leaves it as it is, 0), K_u ~ R^0) plus one double per contact, R (0 until the
 * contact first touches). Johnson & Cook
 * 1983 (Proc. 7th Int. Symp. Ballistics, 541-547), Cowper & Symonds 1957 (Brown Univ. Tech. Rep.
 * 28). nfd_rate_factor is the C home of nfdmodel/strain_rate.py's two formulas.
 *
 * A DEM code: nfd_rate_init once per pair of materials, then per contact and step
 *     status = nfd_rate_step(&rate, delta, v_n, m_star, &params, table, &history, &R, &force, &next, NULL);
 * with R the contact's extra history value (in: stored, out: commit it with `next`); or, with the
 * contact models of nfd_friction.h (the LAMMPS plugin), nfd_rate_contact_params, then nfd_contact_step
 * of the base law with the R-scaled nfd_params (the same law, module doc).
 *
 * Static inline C99 on nfd_kernel.h (math.h only), compiled with nfd_kernel.c. SI units.
 * License: the same as nfdcal (nfd_kernel.h).
 */
#ifndef NFD_RATE_H
#define NFD_RATE_H

#include <math.h>

#include "nfd_kernel.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Gauss-Legendre rules on [-1, 1], the positive nodes and their weights (numpy.polynomial.legendre.
 * leggauss(12) and leggauss(16) to the bit): the loading works of vz (12) and vz_table (16). */
static const double nfd_gauss12_x[6] = {0.1252334085114689, 0.3678314989981802, 0.5873179542866175,
                                        0.7699026741943047, 0.9041172563704748, 0.9815606342467192};
static const double nfd_gauss12_w[6] = {0.2491470458134027, 0.2334925365383546, 0.20316742672306573,
                                        0.16007832854334642, 0.10693932599531907, 0.04717533638651141};
static const double nfd_gauss16_x[8] = {0.09501250983763744, 0.2816035507792589, 0.45801677765722737,
                                        0.6178762444026438, 0.755404408355003, 0.8656312023878318,
                                        0.9445750230732326, 0.9894009349916499};
static const double nfd_gauss16_w[8] = {0.18945061045506864, 0.18260341504492364, 0.16915651939500265,
                                        0.1495959888165767, 0.12462897125553407, 0.0951585116824926,
                                        0.062253523938647456, 0.027152459411754176};

/* The k-th node (k = 0 .. 2h-1, increasing) and weight of a rule of 2h points from its positive half. */
static inline void nfd_gauss_node(const double *x, const double *w, int half, int k, double *node, double *weight)
{
    int j = k < half ? half - 1 - k : k - half;
    *node = k < half ? -x[j] : x[j];
    *weight = w[j];
}

/* The rate-aware law's constants: the base law (NFD_LAW_VZ or NFD_LAW_VZ_TABLE), the rate law
 * (NFD_RATE_JOHNSON_COOK: first = C >= 0, second = eps_dot_0 > 0 [1/s]; NFD_RATE_COWPER_SYMONDS:
 * first = D > 0 [1/s] (inf: R = 1), second = q > 0) and c > 0 of eps_dot = v_n0 / (c a_ref). */
typedef struct {
    int base_law, rate_law;
    double first, second, c;
    double k;               /* the relaxing form's element stiffness (nfd_rate_relaxing); 0: R fixed at first contact */
} nfd_rate;

/* Fill *r; returns 0, or -1 (r unchanged) when a code or a constant is outside the ranges above. */
static inline int nfd_rate_init(nfd_rate *r, int base_law, int rate_law, double first, double second, double c)
{
    if (base_law != NFD_LAW_VZ && base_law != NFD_LAW_VZ_TABLE) return -1;
    if (!(c > 0.0 && isfinite(c) && second > 0.0 && isfinite(second))) return -1;
    if (rate_law == NFD_RATE_JOHNSON_COOK) {
        if (!(first >= 0.0 && isfinite(first))) return -1;
    } else if (rate_law == NFD_RATE_COWPER_SYMONDS) {
        if (!(first > 0.0)) return -1;                        /* D = inf: rate-independent */
    } else {
        return -1;
    }
    r->base_law = base_law; r->rate_law = rate_law; r->first = first; r->second = second; r->c = c; r->k = 0.0;
    return 0;
}

/* R(eps_dot) [-] of the strain rate `rate` [1/s] (nfdmodel.strain_rate.johnson_cook_factor and
 * cowper_symonds_factor: the same operations). */
static inline double nfd_rate_factor(const nfd_rate *r, double rate)
{
    if (r->rate_law == NFD_RATE_JOHNSON_COOK) {
        double ratio = rate / r->second;
        return 1.0 + r->first * log(ratio > 1.0 ? ratio : 1.0);
    }
    return 1.0 + pow(rate / r->first, 1.0 / r->second);
}

/* The base law's force on its virgin curve at delta [m] (a contact never loaded before). */
static inline double nfd_rate_virgin_force(const nfd_rate *r, double delta, const nfd_params *p, const nfd_table *t)
{
    nfd_history virgin = {0.0, 0.0, 0.0, 0.0, 0.0}, out;
    double force = 0.0;
    nfd_step(r->base_law, delta, p, t, &virgin, &force, &out, NULL);
    return force;
}

/* vz's explicit loading curve delta(P) = (a_e + Ca <P - P_Y>)^2 / ((1 + Kc <P - P_Y>) R*) [m]
 * (nfdmodel.vz.VZParams.loading_approach). */
static inline double nfd_rate_vz_approach(const nfd_params *p, double P)
{
    double excess = P - p->P_Y > 0.0 ? P - p->P_Y : 0.0;
    double a_ep = nfd_hertz_radius(P, p->R_star, p->E_star) + p->Ca * excess;
    return a_ep * a_ep / ((1.0 + p->Kc * excess) * p->R_star);
}

/* vz_table's D(s) = (s^(1/3) + f(s))^2 / g(s) at s = P/P_Y (nfdmodel.vz_table.VZTableParams.scaled_approach). */
static inline double nfd_rate_table_approach(const nfd_table *t, double s)
{
    double f, g, slope;
    nfd_pchip_evaluate(t->n, t->x, t->f, t->df, s, &f, &slope);
    nfd_pchip_evaluate(t->n, t->x, t->g, t->dg, s, &g, &slope);
    double radius = cbrt(s) + f;
    return radius * radius / g;
}

/* integral_low^high D(s) ds by the 16-point rule (VZTableParams._gauss). */
static inline double nfd_rate_table_gauss(const nfd_table *t, double low, double high)
{
    double sum = 0.0, node, weight;
    for (int k = 0; k < 16; ++k) {
        nfd_gauss_node(nfd_gauss16_x, nfd_gauss16_w, 8, k, &node, &weight);
        sum += nfd_rate_table_approach(t, 0.5 * (low + high) + 0.5 * (high - low) * node) * weight;
    }
    return 0.5 * (high - low) * sum;
}

/* W = integral_0^delta P d delta [J] on the base law's virgin curve up to (delta, P)
 * (nfdmodel.vz_curve.vz_loading_work, VZTableParams.loading_work: the Hertz part, then by parts
 * P delta - integral delta(P) dP; vz: 12-point panels of width <= 1 in ln(1 + (P - P_Y)/d),
 * d = min(P_Y, 1/Kc); vz_table: x D(x) - 3/5 - integral_1^x D in units of P_Y delta_Y, 16-point
 * pieces between the table's nodes and log panels beyond the last). */
static inline double nfd_rate_loading_work(const nfd_rate *r, const nfd_params *p, const nfd_table *t, double delta,
                                           double P)
{
    double elastic = delta < p->delta_Y ? delta : p->delta_Y;
    double work = 0.4 * p->hertz_k * (elastic * elastic) * sqrt(elastic);
    if (!(P > p->P_Y && delta > p->delta_Y)) return work;
    if (r->base_law == NFD_LAW_VZ) {
        double scale = p->Kc * p->P_Y <= 1.0 ? p->P_Y : 1.0 / p->Kc;
        double t_max = log1p((P - p->P_Y) / scale), integral = 0.0, node, weight;
        int panels = (int)ceil(t_max);
        panels = panels > 1 ? panels : 1;
        double width = t_max / panels;
        for (int panel = 0; panel < panels; ++panel) {
            double sum = 0.0;
            for (int k = 0; k < 12; ++k) {
                nfd_gauss_node(nfd_gauss12_x, nfd_gauss12_w, 6, k, &node, &weight);
                double excess = scale * expm1((panel + 0.5 * (node + 1.0)) * width);
                sum += nfd_rate_vz_approach(p, p->P_Y + excess) * (scale + excess) * weight;
            }
            integral += 0.5 * width * sum;
        }
        return work + (P * delta - p->P_Y * p->delta_Y - integral);
    }
    double x = P / p->P_Y, last = t->x[t->n - 1], integral = 0.0;
    int k = 0;
    while (k < t->n - 1 && t->x[k + 1] <= x) {           /* the node integrals up to x's segment */
        integral += nfd_rate_table_gauss(t, t->x[k], t->x[k + 1]);
        ++k;
    }
    if (x <= last) {
        integral += nfd_rate_table_gauss(t, t->x[k], x);
    } else {
        double ratio = log(x / last);
        int panels = (int)ceil(ratio);
        panels = panels > 1 ? panels : 1;
        for (int panel = 0; panel < panels; ++panel)
            integral += nfd_rate_table_gauss(t, last * exp(ratio * panel / panels),
                                             last * exp(ratio * (panel + 1) / panels));
    }
    return p->P_Y * p->delta_Y * (x * nfd_rate_table_approach(t, x) - 0.6 - integral);
}

/* a_ref [m]: the base law's contact radius a_e + a_p at the peak of its impact at `speed` [m/s] > 0
 * of reduced mass m_star [kg] (module doc; nfdmodel.rate_aware.RateAwareParams.reference_radius);
 * NAN when m* v^2 / 2 is not a finite number above NFD_SMALLEST_ENERGY. */
static inline double nfd_rate_reference_radius(const nfd_rate *r, const nfd_params *p, const nfd_table *t,
                                               double m_star, double speed)
{
    double energy = 0.5 * m_star * (speed * speed);
    if (!(energy > NFD_SMALLEST_ENERGY && isfinite(energy))) return NAN;     /* the overlaps underflow */
    double delta = pow(energy / (0.4 * p->hertz_k), 0.4), P;   /* Hertz: W = (2/5) k_H delta^(5/2) */
    for (int k = 0; k < NFD_REFERENCE_BRACKET_STEPS; ++k) {    /* bracket from above */
        P = nfd_rate_virgin_force(r, delta, p, t);
        if (!(nfd_rate_loading_work(r, p, t, delta, P) < energy)) break;
        delta = 2.0 * delta;
    }
    for (int k = 0; k < NFD_REFERENCE_NEWTON_STEPS; ++k) {     /* Newton, dW/d delta = P: monotone from above */
        P = nfd_rate_virgin_force(r, delta, p, t);
        double step = (nfd_rate_loading_work(r, p, t, delta, P) - energy) / (P > 1e-300 ? P : 1e-300);
        double half = 0.5 * delta;
        delta = delta - (step < 0.0 ? 0.0 : (step > half ? half : step));
        if (fabs(step) <= NFD_REFERENCE_TOLERANCE * delta) break;
    }
    P = nfd_rate_virgin_force(r, delta, p, t);
    if (r->base_law == NFD_LAW_VZ)
        return nfd_hertz_radius(P, p->R_star, p->E_star) + p->Ca * (P - p->P_Y > 0.0 ? P - p->P_Y : 0.0);
    double x = P / p->P_Y > 0.0 ? P / p->P_Y : 0.0, f = 0.0, slope;
    if (x > 1.0) nfd_pchip_evaluate(t->n, t->x, t->f, t->df, x, &f, &slope);
    return p->a_Y * (cbrt(x) + f);
}

/* a_ref [m] of a contact first touching at `speed` [m/s] > 0 into *a_ref: NFD_OK, NFD_FULL_CONTACT (a_ref
 * reaches R*: the impact lies beyond the base law's domain) or NFD_NOT_FINITE. */
static inline int nfd_rate_first_radius(const nfd_rate *r, const nfd_params *p, const nfd_table *t, double m_star,
                                        double speed, double *a_ref)
{
    *a_ref = nfd_rate_reference_radius(r, p, t, m_star, speed);
    if (!isfinite(*a_ref)) return NFD_NOT_FINITE;
    return *a_ref < p->R_star ? NFD_OK : NFD_FULL_CONTACT;
}

/* R of a contact first touching at the normal approach speed `speed` [m/s] (eps_dot = 0 for speed
 * <= 0) into *factor: NFD_OK, NFD_FULL_CONTACT (a_ref reaches R*: the impact lies beyond the base
 * law's domain) or NFD_NOT_FINITE (a speed or a result that is not a finite number). */
static inline int nfd_rate_first_factor(const nfd_rate *r, const nfd_params *p, const nfd_table *t, double m_star,
                                        double speed, double *factor)
{
    double rate = 0.0, a_ref;
    if (!isfinite(speed)) return NFD_NOT_FINITE;
    if (speed > 0.0) {
        int status = nfd_rate_first_radius(r, p, t, m_star, speed, &a_ref);
        if (status != NFD_OK) return status;
        rate = speed / (r->c * a_ref);
    }
    *factor = nfd_rate_factor(r, rate);
    return isfinite(*factor) ? NFD_OK : NFD_NOT_FINITE;
}

/* One step of the rate-aware law: the statuses of the base law's step (nfd_step), or of
 * nfd_rate_first_factor where the contact first touches (delta > 0 with *factor == 0: R is set
 * from `speed` [m/s] and m_star [kg], else they are not read). p, t: the base law's constants at
 * R = 1 (t NULL for vz); h, out: the contact's history [SI] (out = *h, bit for bit, when the turning
 * point does not move); *factor: the contact's R, in and out. iterations may be NULL. */
static inline int nfd_rate_step(const nfd_rate *r, double delta, double speed, double m_star, const nfd_params *p,
                                const nfd_table *t, const nfd_history *h, double *factor, double *force,
                                nfd_history *out, int *iterations)
{
    double R = *factor;
    if (iterations) *iterations = 0;
    if (R == 0.0 && delta > 0.0) {
        int status = nfd_rate_first_factor(r, p, t, m_star, speed, &R);
        if (status != NFD_OK) return status;
    }
    double scale = R > 0.0 ? R : 1.0, square = pow(scale, 2.0), cube = pow(scale, 3.0);
    nfd_history base = {h->delta_max / square, h->P_max / cube, h->delta_res / square, h->K_u, h->a_e_max / scale};
    nfd_history next;
    double scaled = delta / square, P = 0.0;
    int status = nfd_step(r->base_law, scaled, p, t, &base, &P, &next, iterations);
    *force = P * cube;
    if (scaled > base.delta_max) {                   /* the turning point moved: back to SI */
        nfd_history loaded = {next.delta_max * square, next.P_max * cube, next.delta_res * square, next.K_u,
                              r->base_law == NFD_LAW_VZ ? next.a_e_max * scale : h->a_e_max};   /* vz_table: unused */
        *out = loaded;
    } else {
        *out = *h;
    }
    *factor = R;
    return status;
}

/* The base law's nfd_params at the yield stress sigma_Y R (R >= 1): P_Y R^3, delta_Y R^2, a_Y R,
 * p_Y R, vz's Ca / R^2, Kc / R^3 (Ca_hat, Kc_hat held), c1 R^2, u_Y R, the window's force R^3; R*,
 * E*, hertz_k as they are. The base law's step with them is P(delta; R) = R^3 P_0(delta / R^2) with
 * the history in SI (module doc): the same law as nfd_rate_step, and its contact radius (nfd_friction.h's
 * nfd_contact_radius) R a_0(delta / R^2), nfdmodel.rate_aware's. R = 1 gives p bit for bit. What a
 * DEM code with contact models steps (nfd_contact_step with the base law's code). */
static inline void nfd_rate_params(const nfd_params *p, double R, nfd_params *out)
{
    double square = R * R, cube = square * R;
    *out = *p;
    out->P_Y = p->P_Y * cube;
    out->delta_Y = p->delta_Y * square;
    out->a_Y = p->a_Y * R;
    out->p_Y = p->p_Y * R;
    out->Ca = p->Ca / square;
    out->Kc = p->Kc / cube;
    out->c1 = p->c1 * square;
    out->u_Y = p->u_Y * R;
    out->window_P_max = p->window_P_max * cube;
}

/* A contact's nfd_params under the rate-aware law (a DEM code's step: then nfd_step or nfd_contact_step
 * of r->base_law with *out): R fixed where the contact first touches (delta > 0 with *factor == 0,
 * nfd_rate_first_factor of the normal approach speed `speed` [m/s] and m_star [kg]; else they are not
 * read), p, t the base law's at R = 1 and the contact's R*, *out = nfd_rate_params(p, R). *factor:
 * the contact's R, in and out (0 until it touches: *out = *p). Returns NFD_OK or
 * nfd_rate_first_factor's status (*factor and *out unchanged). */
static inline int nfd_rate_contact_params(const nfd_rate *r, const nfd_params *p, const nfd_table *t, double m_star,
                                          double speed, double delta, double *factor, nfd_params *out)
{
    double R = *factor;
    if (R == 0.0 && delta > 0.0) {
        int status = nfd_rate_first_factor(r, p, t, m_star, speed, &R);
        if (status != NFD_OK) return status;
    }
    nfd_rate_params(p, R > 0.0 ? R : 1.0, out);
    *factor = R;
    return NFD_OK;
}

/* The relaxing form (nfdmodel.rate_relaxing; its scalar specification nfdmodel.reference.rate_relaxing_step):
 * the factor s of the flow stress is one viscoplastic element driven by the contact's strain rate,
 *
 *     ds/dt = k (E* / sigma_Y) (v_n / (c a_ref) - eps_dot_s(s)),   s >= 1, s = 1 at first contact
 *
 * eps_dot_s(s) the rate at which the rate law's flow stress is s sigma_Y (nfd_rate_inverse), a_ref as above (at the
 * speed of first contact), k and c NFD_RELAXATION_STIFFNESS and NFD_RELAXING_LENGTH_FACTOR by default. s moves
 * only where the contact loads beyond its turning point at v_n > 0: backward Euler over dt = (delta - delta_max)
 * / v_n (nfd_rate_relaxed_factor); P = s^3 P_0(delta / s^2) as the fixed form's. A contact keeps three doubles
 * besides the base law's history: s (0 until it touches), 1 / (c a_ref) [1/m] and the loading work W [J] along its
 * virgin path (the trapezoid rule; the dissipated energy W - the elastic energy the unloading returns). */

/* Make *r the relaxing form with element stiffness k > 0 (after nfd_rate_init, whose c is then the relaxing
 * law's, e.g. NFD_RELAXING_LENGTH_FACTOR); returns 0, or -1 (r unchanged) for k outside (0, inf). */
static inline int nfd_rate_relaxing(nfd_rate *r, double k)
{
    if (!(k > 0.0 && isfinite(k))) return -1;
    r->k = k;
    return 0;
}

/* eps_dot_s(s) [1/s]: the strain rate at which the flow stress is s sigma_Y (nfdmodel.strain_rate's rate_at):
 * Johnson-Cook eps_dot_0 exp((s - 1) / C) (eps_dot_0 at s <= 1; C = 0: inf above s = 1), Cowper-Symonds
 * D (s - 1)^q (0 at s <= 1). */
static inline double nfd_rate_inverse(const nfd_rate *r, double s)
{
    double excess = s - 1.0 > 0.0 ? s - 1.0 : 0.0;
    if (r->rate_law == NFD_RATE_JOHNSON_COOK) {
        if (r->first == 0.0) return excess > 0.0 ? INFINITY : r->second;
        return r->second * exp(excess / r->first);
    }
    return excess > 0.0 ? r->first * pow(excess, r->second) : 0.0;
}

/* d eps_dot_s / ds [1/s] above s = 1 (0 at s <= 1): Johnson-Cook eps_dot_s / C (inf for C = 0), Cowper-Symonds
 * D q (s - 1)^(q - 1) (nfdmodel.strain_rate's rate_slope). */
static inline double nfd_rate_inverse_slope(const nfd_rate *r, double s)
{
    if (!(s > 1.0)) return 0.0;
    if (r->rate_law == NFD_RATE_JOHNSON_COOK) return r->first > 0.0 ? nfd_rate_inverse(r, s) / r->first : INFINITY;
    return r->first * r->second * pow(s - 1.0, r->second - 1.0);
}

/* s after one loading increment [m] > 0 at the speed [m/s] > 0: the root s >= 1 of
 * F(s) = s - factor - K (per_speed increment - eps_dot_s(s) increment / speed) = 0, K = k E* / sigma_Y =
 * `stiffness` (nfdmodel.rate_relaxing.relaxed_factor: Newton's method from `factor` inside the bracket [1,
 * factor + K per_speed increment], bisecting where a step leaves it or F' is not finite; 1 where F(1) >= 0). */
static inline double nfd_rate_relaxed_factor(const nfd_rate *r, double factor, double per_speed, double increment,
                                             double speed, double stiffness)
{
    double drive = factor + stiffness * per_speed * increment, relax = stiffness * increment / speed;
    if (!(1.0 - drive + relax * nfd_rate_inverse(r, 1.0) < 0.0)) return 1.0;
    double low = 1.0, high = drive > 1.0 ? drive : 1.0;
    double s = factor < 1.0 ? 1.0 : (factor > high ? high : factor);
    for (int k = 0; k < NFD_RATE_FACTOR_ITERATIONS; ++k) {
        double value = s - drive + relax * nfd_rate_inverse(r, s);
        double slope = 1.0 + relax * nfd_rate_inverse_slope(r, s);
        if (value < 0.0) low = s; else high = s;
        double newton = s - value / slope;
        double step = isfinite(newton) && newton >= low && newton <= high ? newton : 0.5 * (low + high);
        int done = fabs(step - s) <= NFD_RATE_FACTOR_TOLERANCE * step;
        s = step;
        if (done) break;
    }
    return s;
}

/* 1 / (c a_ref) [1/m] of a contact first touching at `speed` [m/s] into *per_speed (0 for speed <= 0): NFD_OK,
 * NFD_FULL_CONTACT or NFD_NOT_FINITE as nfd_rate_first_factor. */
static inline int nfd_rate_per_speed(const nfd_rate *r, const nfd_params *p, const nfd_table *t, double m_star,
                                     double speed, double *per_speed)
{
    double a_ref;
    if (!isfinite(speed)) return NFD_NOT_FINITE;
    *per_speed = 0.0;
    if (speed > 0.0) {
        int status = nfd_rate_first_radius(r, p, t, m_star, speed, &a_ref);
        if (status != NFD_OK) return status;
        *per_speed = 1.0 / (r->c * a_ref);
    }
    return NFD_OK;
}

/* K = k E* / sigma_Y [-] of the element: E* [Pa] the pair's, sigma_y [Pa] the yielding body's yield stress. */
static inline double nfd_rate_element_stiffness(const nfd_rate *r, double E_star, double sigma_y)
{
    return r->k * E_star / sigma_y;
}

/* The contact's s before its base-law step (the relaxing form; stiffness: nfd_rate_element_stiffness): s = 1 and
 * *per_speed where it first touches (delta > 0 with *factor == 0; m_star [kg] read there only), then
 * nfd_rate_relaxed_factor where delta > delta_max [m] (the history's, SI) at speed > 0. Returns NFD_OK or
 * nfd_rate_per_speed's status (nothing written). */
static inline int nfd_rate_relax(const nfd_rate *r, const nfd_params *p, const nfd_table *t, double m_star,
                                 double stiffness, double speed, double delta, double delta_max, double *factor,
                                 double *per_speed)
{
    double s = *factor, rate = *per_speed;
    if (s == 0.0 && delta > 0.0) {
        int status = nfd_rate_per_speed(r, p, t, m_star, speed, &rate);
        if (status != NFD_OK) return status;
        s = 1.0;
    }
    if (delta > delta_max && delta > 0.0 && speed > 0.0)
        s = nfd_rate_relaxed_factor(r, s, rate, delta - delta_max, speed, stiffness);
    *factor = s; *per_speed = rate;
    return NFD_OK;
}

/* One step of the relaxing form (stiffness: nfd_rate_element_stiffness): nfd_rate_relax, then nfd_rate_step at
 * s (R fixed there: the same mapping), and *work += (P_max + P) (delta - delta_max) / 2 where the contact loads
 * beyond its turning point. *factor, *per_speed, *work: the contact's three doubles, in and out. */
static inline int nfd_rate_relaxing_step(const nfd_rate *r, double delta, double speed, double m_star,
                                         double stiffness, const nfd_params *p, const nfd_table *t,
                                         const nfd_history *h, double *factor, double *per_speed, double *work,
                                         double *force, nfd_history *out, int *iterations)
{
    if (iterations) *iterations = 0;
    int status = nfd_rate_relax(r, p, t, m_star, stiffness, speed, delta, h->delta_max, factor, per_speed);
    if (status != NFD_OK) return status;
    status = nfd_rate_step(r, delta, speed, m_star, p, t, h, factor, force, out, iterations);
    if (delta > h->delta_max && delta > 0.0) *work += 0.5 * (h->P_max + *force) * (delta - h->delta_max);
    return status;
}

#ifdef __cplusplus
}
#endif
#endif

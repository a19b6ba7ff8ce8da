/* nfd_unload.h: the vz_unload law (nfdmodel.vz_unload; its scalar specification
 * nfdmodel.reference.vz_unload_step): the vz_table loading curve with the FE's dent and unloading
 * exponent tabulated over the turning point x_m = P_max / P_Y,
 *
 *     loading (x = P/P_Y)   delta / delta_Y = D(x) = (x^(1/3) + f(x))^2 / g(x)   (Hertz below P_Y)
 *     dent                  delta_res = rho(x_m) delta_max      (rho(1) = 0, 0 <= rho < 1)
 *     unloading/reloading   P = K_u <delta - delta_res>^m(x_m),  K_u = P_max / (delta_max - delta_res)^m
 *                           (m(1) = 3/2, m > 0; P = 0 for delta <= delta_res)
 *
 * rho and m monotone cubic (PCHIP) interpolants of their values at the nodes x_unload (x_unload[0]
 * = 1, where the contact is Hertz's: rho = 0, m = 3/2), held at the last node's values beyond it.
 * Below first yield the law is Hertz's (delta_res = 0, m = 3/2). The force is continuous at every
 * turning point; reloading retraces the unloading curve to the turning point and loads on the
 * virgin curve beyond it. The contact radius is vz_table's, a_Y f(x_m) + the Hertz radius at P
 * (nfd_contact_radius). The history is nfd_history with the exponent m in its a_e_max slot (the
 * fifth double; 0 for a virgin contact, whose K_u = 0 gives P = 0). Etsion, Kligerman & Kadin 2005
 * (J. Appl. Mech. 72, 173) report the FE's unloading exponent of 1.3-1.5 this law carries.
 *
 * Static inline C99 on nfd_kernel.h (math.h only): any C or C++ code includes this header and
 * compiles nfd_kernel.c (which includes it: one dispatch, nfd_step). SI units.
 *
 * License: the same as nfdcal (nfd_kernel.h).
 */
#ifndef NFD_UNLOAD_H
#define NFD_UNLOAD_H

#include <math.h>

#include "nfd_kernel.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Fill the unloading tables of *t (after nfd_table_init, which clears them) from n nodes
 * (2 <= n <= NFD_TABLE_MAX_NODES): x_unload = P_max/P_Y (x_unload[0] = 1, increasing), dent =
 * delta_res/delta_max (dent[0] = 0, each in [0, 1)) and exponent = m (exponent[0] = 3/2, each > 0).
 * Returns 0, or -1 when the nodes break these rules (t unchanged). nfdmodel checks the law's
 * admissibility (no load-unload cycle returning more work than it took) when the tables are fitted
 * or read: use tables from nfdcal. */
static inline int nfd_unload_table_init(nfd_table *t, int n, const double *x_unload, const double *dent,
                                        const double *exponent)
{
    if (n < 2 || n > NFD_TABLE_MAX_NODES || x_unload[0] != 1.0 || dent[0] != 0.0 || exponent[0] != 1.5) return -1;
    for (int k = 0; k < n; ++k) {
        if (!(isfinite(x_unload[k]) && dent[k] >= 0.0 && dent[k] < 1.0 && exponent[k] > 0.0 &&
              isfinite(exponent[k])))
            return -1;
        if (k > 0 && !(x_unload[k] > x_unload[k - 1])) return -1;
    }
    for (int k = 0; k < n; ++k) {
        t->x_unload[k] = x_unload[k]; t->dent[k] = dent[k]; t->exponent[k] = exponent[k];
    }
    t->n_unload = n;
    nfd_pchip_slopes(n, t->x_unload, t->dent, t->d_dent);
    nfd_pchip_slopes(n, t->x_unload, t->exponent, t->d_exponent);
    return 0;
}

/* (rho, m) at the turning point x_m = P_max / P_Y: the tables at x_m clamped to [1, x_unload[n-1]]. */
static inline void nfd_unload_tables(const nfd_table *t, double x_max, double *rho, double *m)
{
    double last = t->x_unload[t->n_unload - 1], slope;
    double at = x_max < 1.0 ? 1.0 : (x_max > last ? last : x_max);
    nfd_pchip_evaluate(t->n_unload, t->x_unload, t->dent, t->d_dent, at, rho, &slope);
    nfd_pchip_evaluate(t->n_unload, t->x_unload, t->exponent, t->d_exponent, at, m, &slope);
}

/* One vz_unload step (the statuses of nfd_vz_table_step; t filled by nfd_table_init and
 * nfd_unload_table_init). */
static inline int nfd_vz_unload_step(double delta, const nfd_params *p, const nfd_table *t, const nfd_history *h,
                                     double *force, nfd_history *out, int *iterations)
{
    if (iterations) *iterations = 0;
    if (!isfinite(delta)) return NFD_NOT_FINITE;
    if (delta <= h->delta_max) {                /* unloading or reloading on the curve of exponent m */
        double gap = delta - h->delta_res;
        *force = h->K_u * pow(gap > 0.0 ? gap : 0.0, h->a_e_max);
        *out = *h;
        return NFD_OK;
    }
    /* the virgin curve is vz_table's: its P, statuses and, below first yield, Hertz's history */
    int status = nfd_vz_table_step(delta, p, t, h, force, out, iterations);
    if (!(delta > p->delta_Y)) {
        out->a_e_max = 1.5;                     /* Hertz: delta_res = 0, K_u = k_H, m = 3/2 */
        return status;
    }
    double rho, m, P = out->P_max;
    nfd_unload_tables(t, P / p->P_Y, &rho, &m);
    double delta_res = rho * delta, below = nextafter(delta, 0.0);
    delta_res = delta_res < below ? delta_res : below;      /* the curve drops to 0 below delta_max */
    out->delta_res = delta_res;
    out->K_u = P / pow(delta - delta_res, m);
    out->a_e_max = m;
    return status;
}

#ifdef __cplusplus
}
#endif
#endif

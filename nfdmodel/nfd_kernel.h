/* nfd_kernel: the runtime contact laws of nfdcal in dependency-free C99 (math.h only).
 *
 * One contact at a time, SI units. A law is a step function
 *
 *     status = nfd_<law>_step(delta, &params, &history, &force, &new_history);
 *
 * delta: the approach ("overlap") of the two centres [m]; history: the contact's turning point
 * (all zeros for a virgin contact); force: the normal force [N] (>= 0); new_history: the
 * trial history of this step (commit it by copying it over `history` once the step is
 * accepted). The laws are those of nfdmodel (nfdmodel/README.md, The model; nfdmodel/reference.py is the
 * plain Python transcription, branch by branch):
 *
 *   hertz          P = (4/3) E* sqrt(R*) <delta>^(3/2)                       (no history)
 *   vz             Vu-Quoc & Zhang (1999): Hertz to delta_Y, then the root of the corrected
 *                  F(P) = (P - P_Y) + c1 P^(1/3) - sqrt((1 + Kc (P - P_Y)) R* delta) / Ca,
 *                  c1 = (3 R* / (4 E*))^(1/3) / Ca, by Newton on u = P^(1/3);
 *   thornton       Thornton (1997): Hertz to delta_Y, then P = P_Y + pi p_Y R* (delta - delta_Y);
 *   walton_braun   Walton & Braun (1986): P = K1 delta on loading;
 *   vz_table       the NFD structure with load-dependent a_p = a_Y f(x) and C_R = g(x),
 *                  x = P / P_Y, monotone cubic (PCHIP) tables (nfd_table): the force solves
 *                  delta / delta_Y = D(x) = (x^(1/3) + f(x))^2 / g(x) (bracketed Newton);
 *   vz_unload      vz_table's loading curve with the dent delta_res = rho(x_m) delta_max and the
 *                  unloading exponent n = m(x_m) tabulated over the turning point (nfd_unload.h);
 *
 * and every law with memory unloads and reloads on P = K_u <delta - delta_res>^n (n = 3/2;
 * walton_braun: n = 1; vz_unload: its m) through its turning point (delta_max, P_max). Fill nfd_params with
 * nfd_pair(); then set the law's constants (Ca, Kc for vz; K1, K2 for walton_braun).
 *
 * Status: NFD_OK; NFD_BEYOND_WINDOW (the force is returned, but the turning point lies beyond
 * the load window the vz constants were fitted on: an extrapolation); NFD_FULL_CONTACT (vz: the
 * contact radius a_e + Ca (P - P_Y) reached R*, no contact law holds there: the force is not
 * computed); NFD_NOT_FINITE (delta or the force is not a finite number).
 *
 * License: the same as nfdcal. This file and nfd_kernel.c may be copied into any C or C++ code.
 */
#ifndef NFD_KERNEL_H
#define NFD_KERNEL_H

#include <math.h>
#include <stddef.h>

#include "nfd_limits.h"   /* law codes, tolerances, admissible ranges */

#ifdef __cplusplus
extern "C" {
#endif

#define NFD_OK 0
#define NFD_BEYOND_WINDOW 1
#define NFD_FULL_CONTACT (-1)
#define NFD_NOT_FINITE (-2)
#define NFD_UNKNOWN_LAW (-3)

/* Per contact pair, precomputed once (nfd_pair), then the law's constants. */
typedef struct {
    double R_star;        /* effective radius R* [m]: 1/R* = 1/R_i + 1/R_j (a wall: R* = R)   */
    double E_star;        /* effective modulus E* [Pa]: 1/E* = (1-nu_i^2)/E_i + (1-nu_j^2)/E_j */
    double P_Y;           /* first-yield force [N] = pi^3 R*^2 p_Y^3 / (6 E*^2)              */
    double delta_Y;       /* approach at first yield [m] = a_Y^2 / R*                         */
    double a_Y;           /* contact radius at first yield [m]                                 */
    double p_Y;           /* yield pressure A_Y(nu) sigma_Y [Pa] of the body that yields first */
    double hertz_k;       /* (4/3) E* sqrt(R*) [N/m^1.5]                                       */
    double Ca;            /* vz: plastic contact-radius rate [m/N]                            */
    double Kc;            /* vz: curvature-factor rate [1/N]                                   */
    double c1;            /* vz: (3 R* / (4 E*))^(1/3) / Ca [N^(2/3)] (nfd_vz_constants)       */
    double u_Y;           /* vz: P_Y^(1/3) [N^(1/3)] (nfd_vz_constants)                        */
    double window_P_max;  /* vz: the largest force [N] the constants were fitted on (inf: any) */
    double K1, K2;        /* walton_braun: loading and unloading stiffness [N/m], K1 <= K2     */
} nfd_params;

/* One contact's history (named fields; all zeros for a virgin contact). */
typedef struct {
    double delta_max;     /* largest approach so far (turning point) [m]                      */
    double P_max;         /* force there [N]                                                   */
    double delta_res;     /* approach where the unloading curve reaches 0 [m]                 */
    double K_u;           /* constant of the unloading curve P = K_u <delta - delta_res>^n    */
    double a_e_max;       /* vz: Hertz radius at P_max [m] (starts the next Newton solve);
                             vz_unload: the unloading exponent m [-] of this curve (0: virgin) */
} nfd_history;

/* The vz_table law's tables (nfdmodel.vz_table.VZTableParams): node loads x = P/P_Y (x[0] = 1,
 * increasing), a_p/a_Y = f (f[0] = 0, non-decreasing) and C_R = g (g[0] = 1, > 0) at them; the
 * PCHIP node slopes and D at the nodes are filled in by nfd_table_init. vz_unload's tables over
 * the turning point follow (n_unload nodes, 0 for vz_table; nfd_unload_table_init, nfd_unload.h).
 * A plain struct (no pointers): copy it, broadcast it, write it to a restart file. */
typedef struct {
    int n;
    double x[NFD_TABLE_MAX_NODES], f[NFD_TABLE_MAX_NODES], g[NFD_TABLE_MAX_NODES];
    double df[NFD_TABLE_MAX_NODES], dg[NFD_TABLE_MAX_NODES], D[NFD_TABLE_MAX_NODES];
    int n_unload;
    double x_unload[NFD_TABLE_MAX_NODES], dent[NFD_TABLE_MAX_NODES], exponent[NFD_TABLE_MAX_NODES];
    double d_dent[NFD_TABLE_MAX_NODES], d_exponent[NFD_TABLE_MAX_NODES];
} nfd_table;

/* nfd_params of a contact pair from R* [m], E* [Pa] and p_Y = A_Y(nu) sigma_Y [Pa]; the vz and
 * walton_braun constants are zero and the window unlimited until set. */
nfd_params nfd_pair(double R_star, double E_star, double p_Y);

/* Set the vz constants Ca [m/N], Kc [1/N] and what the solve precomputes from them. */
void nfd_vz_constants(nfd_params *p, double Ca, double Kc);

/* The nfd_params of a contact of effective radius R_star [m] from `unit`, those of the same pair of
 * materials and law constants at R* = 1 m (nfd_pair(1.0, E*, p_Y), then the law's constants with
 * Ca_hat, Kc_hat and the window P_max/P_Y, which hold for any R*): for many contacts of one pair of
 * materials and varying radii, a square root per contact in place of nfd_pair's cube root and
 * powers. Every quantity is a power of R* times its value at 1 m (Hertz, first yield at the same
 * p_Y): P_Y, window_P_max ~ R*^2; a_Y, delta_Y ~ R*; hertz_k ~ sqrt(R*); Ca ~ 1/R* (Ca = Ca_hat
 * a_Y / P_Y), Kc ~ 1/R*^2; u_Y = P_Y^(1/3) ~ R*^(2/3), c1 ~ R*^(4/3). Equal to nfd_pair's to
 * round-off (hertz_k bit for bit). with_roots: also u_Y and c1 (a cube root), which only vz's
 * plastic loading step reads, i.e. when delta > the history's delta_max; without, they are NaN
 * (a step that would need them returns NFD_NOT_FINITE, never a wrong force). */
static inline void nfd_pair_scaled(const nfd_params *unit, double R_star, int with_roots, nfd_params *p)
{
    double R_squared = R_star * R_star;
    *p = *unit;
    p->R_star = R_star;
    p->P_Y = unit->P_Y * R_squared;
    p->delta_Y = unit->delta_Y * R_star;
    p->a_Y = unit->a_Y * R_star;
    p->hertz_k = unit->hertz_k * sqrt(R_star);
    p->Ca = unit->Ca / R_star;
    p->Kc = unit->Kc / R_squared;
    p->window_P_max = unit->window_P_max * R_squared;
    if (with_roots) {
        double root = cbrt(R_star);
        p->c1 = unit->c1 * (R_star * root);
        p->u_Y = unit->u_Y * (root * root);
    } else {
        p->c1 = p->u_Y = NAN;
    }
}

int nfd_hertz_step(double delta, const nfd_params *p, const nfd_history *h, double *force, nfd_history *out);
/* vz: *iterations (if not NULL) receives the Newton iterations of a plastic loading step (else 0). */
int nfd_vz_step(double delta, const nfd_params *p, const nfd_history *h, double *force, nfd_history *out,
                int *iterations);
int nfd_thornton_step(double delta, const nfd_params *p, const nfd_history *h, double *force, nfd_history *out);
int nfd_walton_braun_step(double delta, const nfd_params *p, const nfd_history *h, double *force,
                          nfd_history *out);

/* Fill *t from n nodes (2 <= n <= NFD_TABLE_MAX_NODES); returns 0, or -1 when the nodes break
 * the rules above (nfdmodel checks the law's admissibility, D increasing and e <= 1, when the
 * table is fitted or read: use tables from nfdcal). */
int nfd_table_init(nfd_table *t, int n, const double *x, const double *f, const double *g);

/* The monotone cubic (PCHIP) interpolant of n nodes x (increasing), values y: its node slopes d
 * (nfdmodel.pchip.pchip_slopes), and its (value, slope) at z (nfdmodel.pchip.pchip_evaluate; the
 * straight lines of the end slopes beyond the end nodes). */
void nfd_pchip_slopes(int n, const double *x, const double *y, double *d);
void nfd_pchip_evaluate(int n, const double *x, const double *y, const double *d, double z, double *value,
                        double *slope);

/* vz_table: history as for vz (a_e_max unused); p as for any law (window_P_max optional). */
int nfd_vz_table_step(double delta, const nfd_params *p, const nfd_table *t, const nfd_history *h, double *force,
                      nfd_history *out, int *iterations);

/* The vz_table contact radius a_Y (x^(1/3) + f(x)) [m] on the loading curve at P [N] >= P_Y. */
double nfd_vz_table_radius(const nfd_params *p, const nfd_table *t, double P);

/* vz for many contacts at once, all of them loading beyond their turning points (delta[i] >
 * their history's delta_max; structure of arrays, the layout of a vectorised DEM code): in,
 * delta[i] [m] and a_e_max[i], their history's a_e,max [m] (the Newton start); out, the new
 * turning points (delta_max = delta[i], force = P_max[i]): P_max [N], delta_res [m], K_u and
 * a_e_max [m] (overwritten). The same numbers as nfd_vz_step contact by contact, several times
 * faster: the two-step Newton fast path runs as one branch-free loop. Returns the largest
 * Newton iteration count. Check P_max against p->window_P_max and the contact radius
 * a_e_max + Ca <P_max - P_Y> against R* yourself (nfd_vz_step's statuses). */
int nfd_vz_load(size_t n, const nfd_params *p, const double *delta, double *a_e_max, double *P_max,
                double *delta_res, double *K_u);     /* the arrays must not overlap */

/* The step of law `law` (NFD_LAW_HERTZ ... NFD_LAW_VZ_UNLOAD, nfd_limits.h): the one dispatch of
 * every caller. t: the vz_table and vz_unload laws' tables (NULL for the others); iterations may be NULL.
 * Returns the law's status, or NFD_UNKNOWN_LAW for a code outside the table. */
int nfd_step(int law, double delta, const nfd_params *p, const nfd_table *t, const nfd_history *h, double *force,
             nfd_history *out, int *iterations);

/* A_Y(nu) = 1 / max over zeta of |sigma_z - sigma_r| / p0 on the axis of a Hertz contact (Johnson
 * 1985 eq. 3.45; nfdmodel.materials.yield_factor): first yield at the peak Hertz pressure
 * p_Y = A_Y sigma_Y. 0 <= nu < NFD_NU_MAX (A_Y(0.3) = 1.61). */
double nfd_yield_factor(double nu);

/* The contact formulas of every caller (the kernel, nfd_friction.h, the LAMMPS plugin), one home each
 * (nfdmodel.materials and nfdmodel.hertz_contact in Python; Johnson 1985, Contact Mechanics, section
 * 4.2 and eqs. 4.22-4.23), SI units:
 *   nfd_plane_strain_modulus  E' = E / (1 - nu^2) [Pa]: E* of a body on a rigid flat;
 *   nfd_contact_modulus       E* = 1 / (c_i + c_j) [Pa] of two bodies' compliances c = 1/E' [1/Pa];
 *   nfd_effective_radius      R* = 1 / (1/R_i + 1/R_j) [m] of two spheres (a flat: R* = R);
 *   nfd_yield_pressure        p_Y = A_Y(nu) sigma_Y [Pa]: the peak Hertz pressure at first yield;
 *   nfd_yields_first          whether body i (yield pressure p_Y_i) yields first against body j: the
 *                             lower p_Y, body i on a tie;
 *   nfd_hertz_radius          a = (3 P R* / (4 E*))^(1/3) [m] at force P [N]. */
static inline double nfd_plane_strain_modulus(double E, double nu) { return E / (1.0 - nu * nu); }
static inline double nfd_contact_modulus(double compliance_i, double compliance_j)
{
    return 1.0 / (compliance_i + compliance_j);
}
static inline double nfd_effective_radius(double R_i, double R_j) { return 1.0 / (1.0 / R_i + 1.0 / R_j); }
static inline double nfd_yield_pressure(double sigma_y, double nu) { return nfd_yield_factor(nu) * sigma_y; }
static inline int nfd_yields_first(double p_Y_i, double p_Y_j) { return p_Y_i <= p_Y_j; }
static inline double nfd_hertz_radius(double P, double R_star, double E_star)
{
    return cbrt(3.0 * P * R_star / (4.0 * E_star));
}

/* The estimated duration [s] of a collision at normal speed v [m/s] of reduced mass m_star [kg], which
 * says whether a time step resolves it (NFD_STEPS_PER_CONTACT_MIN):
 *   nfd_hertz_impact_time   Hertz's elastic impact, NFD_HERTZ_IMPACT_TIME (m*^2 / (R* E*^2 v))^(1/5)
 *                           (Johnson 1985 eq. 11.24; nfdmodel.hertz_contact.hertz_impact_time); for the
 *                           elastoplastic laws an estimate (the softer plastic loading and the stiffer
 *                           unloading roughly balance: 2 % above nfdmodel.collision_reference's for
 *                           the reference sphere at 30 v_Y);
 *   nfd_linear_impact_time  springs K1 loading, K2 unloading [N/m] (walton_braun): the two half periods
 *                           (pi/2) (sqrt(m* / K1) + sqrt(m* / K2)), whatever v. */
static inline double nfd_hertz_impact_time(double m_star, double R_star, double E_star, double v)
{
    return NFD_HERTZ_IMPACT_TIME * pow(m_star * m_star / (R_star * E_star * E_star * v), 0.2);
}
static inline double nfd_linear_impact_time(double m_star, double k_load, double k_unload)
{
    return 0.5 * 3.14159265358979323846 * (sqrt(m_star / k_load) + sqrt(m_star / k_unload));
}

/* The admissibility of vz constants Ca_hat = Ca P_Y / a_Y, Kc_hat = Kc P_Y (dimensionless, so one answer for
 * every pair; nfdmodel.vz.VZParams decides the same): NFD_VZ_ADMISSIBLE, or NFD_VZ_OUT_OF_RANGE
 * (outside NFD_CA_HAT_MIN <= Ca_hat <= NFD_CA_HAT_MAX, 0 <= Kc_hat <= NFD_KC_HAT_MAX), NFD_VZ_TURNS_BACK
 * (the loading curve delta(P) stops increasing near P/P_Y = *load; checked up to NFD_MONOTONE_LOAD_MAX),
 * NFD_VZ_CREATES_ENERGY (a load-unload cycle to P/P_Y = *load returns more work than it took:
 * restitution *restitution > 1; checked up to NFD_DISSIPATION_LOAD_MAX). Admissible: *load and
 * *restitution (<= 1) of the cycle nearest to creating energy. About 2 ms. */
#define NFD_VZ_ADMISSIBLE 0
#define NFD_VZ_OUT_OF_RANGE 1
#define NFD_VZ_TURNS_BACK 2
#define NFD_VZ_CREATES_ENERGY 3
int nfd_vz_admissible(double Ca_hat, double Kc_hat, double *load, double *restitution);

/* The elastic energy [J] a contact of law `law` returns if it unloads from overlap delta [m] at force P [N]
 * with the step's new history h: the integral of its unloading curve P = K_u <d - delta_res>^n from
 * delta_res to delta, E_el = P <delta - delta_res> / (n + 1), n = 3/2 (hertz, vz, thornton, vz_table;
 * hertz: delta_res = 0), 1 (walton_braun) or the history's m (vz_unload); NAN for a law without a case here (nfdmodel.turning_point.
 * elastic_energy). The plastic energy dissipated so far is the normal work minus it. */
static inline double nfd_elastic_energy(int law, double delta, const nfd_history *h, double P)
{
    double gap = delta - h->delta_res, exponent;
    switch (law) {
    case NFD_LAW_HERTZ: case NFD_LAW_VZ: case NFD_LAW_THORNTON: case NFD_LAW_VZ_TABLE: exponent = 1.5; break;
    case NFD_LAW_WALTON_BRAUN: exponent = 1.0; break;
    case NFD_LAW_VZ_UNLOAD: exponent = h->a_e_max; break;    /* its exponent m (nfd_unload.h) */
    default: return NAN;
    }
    return P * (gap > 0.0 ? gap : 0.0) / (exponent + 1.0);
}

/* On request, after a step: the contact radii [m] of a history at force P [N] (vz): the Hertz
 * radius a_e, the plastic radius a_p = Ca <P_max - P_Y> and a_ep = a_e + a_p. */
void nfd_vz_radii(const nfd_params *p, const nfd_history *h, double force, double *a_e, double *a_p, double *a_ep);

#ifdef __cplusplus
}
#endif
#endif

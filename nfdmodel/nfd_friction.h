/* nfd_friction.h: the rest of a DEM contact around the normal laws of nfd_kernel.h -- normal
 * damping, tangential friction, rolling and twisting resistance -- as LAMMPS's pair_style granular
 * defines them (its damping, tangential mindlin, rolling sds, twisting marshall and sds sub-models),
 * with the contact radius of the normal law in use. Static inline C99 (math.h only), one contact at
 * a time over named history fields, so any C or C++ DEM code includes this header and compiles
 * nfd_kernel.c (which includes it too: one translation unit). SI units.
 *
 * Per step, with n the unit normal from j to i, delta the overlap, v = v_i - v_j, R* the effective
 * radius, m* the effective mass (nfdmodel/README.md, Friction, rolling and twisting, states each
 * model with its citation):
 *
 *   P        the normal law's force (nfd_step; friction never changes it)
 *   a        its contact radius (nfd_contact_radius): Hertz's sqrt(R* delta) until first yield,
 *            then the law's own (vz: a_e + a_p; vz_table, vz_unload: a_Y (x^(1/3) + f(x_max)); thornton:
 *            the Hertz radius of its enlarged curvature R_p; walton_braun: sqrt(R* delta))
 *   F_n      = P - eta v.n, eta the damping prefactor (none 0; viscoelastic c m* a;
 *            tsuji / coeff_restitution c sqrt(m* P / delta), c from nfd_damping_coefficient)
 *   F_t      Mindlin-Deresiewicz: spring xi_t (rotated into the tangent plane, + dt v_t,rel),
 *            F_t = -k_t a xi_t - x_gamma_t eta v_t,rel, capped at mu |F_n| (xi_t rescaled to the cap);
 *            LAMMPS's variants: rescale (xi_t scaled by a/a_old where a shrank), /force (xi_t the
 *            elastic force, + -k_t a dt v_t,rel): a plastic law takes mindlin_rescale/force
 *            (nfdmodel/friction.py says why)
 *   M_roll   SDS: spring xi_roll (+ dt v_roll, v_roll = R* (omega_i - omega_j) x n), force
 *            F_r = -k_roll xi_roll - gamma_roll v_roll capped at mu_roll |F_n|, torque R* n x F_r
 *   M_twist  spring theta (+ dt omega_twist, omega_twist = (omega_i - omega_j).n), torque
 *            -k theta - gamma omega_twist capped at mu |F_n|; Marshall: k = k_t a^2 / 2,
 *            gamma = x_gamma_t eta a^2 / 2, mu = 2 mu_t a / 3; SDS: the given k, gamma, mu
 *   force on i F_n n + F_t (j: the opposite); torque on i -(R_i - delta/2) n x F_t + R* n x F_r +
 *            M_twist n, on j -(R_j - delta/2) n x F_t - R* n x F_r - M_twist n (a flat wall:
 *            arm R_i, as LAMMPS's fix wall/gran)
 *
 * `update` = 0 evaluates the forces of the stored springs without advancing them (LAMMPS's set-up
 * step after a `run` or a restart file, which recomputes the forces of the current positions).
 * A spring that would exceed its cap is set back to the cap, also when update = 0, as LAMMPS does.
 * A capped force is the force of the spring as set back (the cap to round-off), so that evaluating
 * the stored spring again gives the same force bit for bit (a restart continues bit for bit); with
 * update = 0 a force beyond its cap by no more than that round-off (NFD_CAP_SLACK) is not capped again.
 *
 * License: the same as nfdcal (nfd_kernel.h). The models are LAMMPS's; no LAMMPS source is copied.
 */
#ifndef NFD_FRICTION_H
#define NFD_FRICTION_H

#include <math.h>

#include "nfd_kernel.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The contact models and constants of a pair (per pair of atom types, or a wall). */
typedef struct {
    int damping;          /* NFD_DAMPING_*                                                         */
    double damping_coeff; /* c of the prefactor (nfd_damping_coefficient)                          */
    int tangential;       /* NFD_TANGENTIAL_NONE, _MINDLIN, _MINDLIN_RESCALE, _MINDLIN_FORCE or
                             _MINDLIN_RESCALE_FORCE (LAMMPS's mindlin, mindlin_rescale, ...)       */
    double k_t;           /* Mindlin coefficient [Pa]: stiffness k_t a [N/m]; 8 G* from the materials
                             (nfd_shear_coefficient), as LAMMPS's `tangential mindlin NULL`         */
    double x_gamma_t;     /* tangential damping: x_gamma_t times the normal damping prefactor      */
    double mu;            /* Coulomb friction coefficient                                          */
    int rolling;          /* NFD_ROLLING_NONE or NFD_ROLLING_SDS                                   */
    double k_roll, gamma_roll, mu_roll;      /* [N/m], [N s/m], [-]                                */
    int twisting;         /* NFD_TWISTING_NONE, _MARSHALL (needs the tangential model) or _SDS     */
    double k_twist, gamma_twist, mu_twist;   /* SDS: [N m/rad], [N m s/rad], [m]                   */
} nfd_friction;

/* One contact's springs (all zeros for a new contact). xi_t as seen from body i: the other
 * body's view is -xi_t (the others are the same from both bodies). */
typedef struct {
    double xi_t[3];       /* tangential displacement [m] in the tangent plane (the /force variants:
                             the elastic tangential force [N])                                     */
    double xi_roll[3];    /* rolling displacement [m]                                              */
    double theta_twist;   /* twist angle [rad]                                                     */
    double a_previous;    /* the contact radius of the last step [m] (the rescale variants)        */
} nfd_friction_history;

/* One contact's geometry and motion at this step. */
typedef struct {
    double n[3];          /* unit normal from j to i                                               */
    double delta;         /* overlap [m]                                                           */
    double R_i, R_j;      /* radii [m]; R_j = 0: a flat wall                                       */
    double v[3];          /* v_i - v_j [m/s]                                                       */
    double omega_i[3], omega_j[3];           /* angular velocities [rad/s] (a wall: zero)          */
    double m_star;        /* m_i m_j / (m_i + m_j) [kg] (a wall: m_i)                              */
    double dt;            /* time step [s]                                                         */
} nfd_contact;

typedef struct {
    double force[3];      /* on i [N]; j takes -force                                              */
    double torque_i[3], torque_j[3];         /* [N m]                                              */
    double P;             /* the normal law's force [N]                                            */
    double F_n;           /* P plus normal damping [N] (may be negative at the end of a damped contact) */
    double a;             /* contact radius [m]                                                    */
    double F_t[3];        /* tangential force on i [N]                                             */
} nfd_contact_result;

static inline double nfd_dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static inline double nfd_len3(const double *a) { return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

static inline void nfd_cross3(const double *a, const double *b, double *c)
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

/* 8 G* [Pa], the Mindlin coefficient of two bodies: 1/G* = (2 - nu_i)/G_i + (2 - nu_j)/G_j with
 * G = E / (2 (1 + nu)); a rigid flat: E_j = INFINITY (G* = G_i / (2 - nu_i)). */
static inline double nfd_shear_coefficient(double E_i, double nu_i, double E_j, double nu_j)
{
    double factor_i = 2.0 * (2.0 - nu_i) * (1.0 + nu_i) / E_i, factor_j = 2.0 * (2.0 - nu_j) * (1.0 + nu_j) / E_j;
    return 8.0 * (1.0 / (factor_i + factor_j));
}

/* c of the damping prefactor from the user's value: viscoelastic, value = c [1/(m s)]; tsuji,
 * value = the restitution e, c = 1.2728 - 4.2783 e + 11.087 e^2 - 22.348 e^3 + 27.467 e^4
 * - 18.022 e^5 + 4.8218 e^6 (Marshall 2009 eq. 53, as LAMMPS 22 Jul 2025); coeff_restitution, value = e,
 * c = -sqrt(5) ln e / sqrt(pi^2 + ln^2 e) (a Hertz contact of restitution e). */
static inline double nfd_damping_coefficient(int model, double value)
{
    if (model == NFD_DAMPING_VISCOELASTIC) return value;
    if (model == NFD_DAMPING_TSUJI) {
        double e = value, e2 = e * e, e4 = e2 * e2;
        double c = 1.2728 - 4.2783 * e + 11.087 * e2;
        c += -22.348 * (e2 * e) + 27.467 * e4;
        c += -18.022 * (e4 * e) + 4.8218 * (e4 * e2);
        return c;
    }
    if (model == NFD_DAMPING_COEFF_RESTITUTION) {
        double log_e = log(value), pi = 3.14159265358979323846;
        double root_3_2 = 1.22474487139158894067, two_root_5_6 = 1.82574185835055380345;   /* sqrt(3/2), 2 sqrt(5/6) */
        return -root_3_2 * two_root_5_6 * log_e / sqrt(pi * pi + log_e * log_e);
    }
    return 0.0;
}

/* eta [N s/m]: the normal damping force is -eta v.n. */
static inline double nfd_damping_prefactor(const nfd_friction *f, double m_star, double a, double P, double delta)
{
    if (f->damping == NFD_DAMPING_VISCOELASTIC) return f->damping_coeff * m_star * a;
    if (f->damping == NFD_DAMPING_TSUJI || f->damping == NFD_DAMPING_COEFF_RESTITUTION) {
        double s = delta > 0.0 ? m_star * P / delta : 0.0;
        return f->damping_coeff * sqrt(s > 0.0 ? s : 0.0);
    }
    return 0.0;
}

/* The contact radius [m] of law `law` at overlap delta with the step's new history h and force P
 * (nfdmodel/README.md, Friction: the contact radius). */
static inline double nfd_contact_radius(int law, double delta, const nfd_params *p, const nfd_table *t,
                                        const nfd_history *h, double P)
{
    double d = delta > 0.0 ? delta : 0.0;
    int table = law == NFD_LAW_VZ_TABLE || law == NFD_LAW_VZ_UNLOAD;
    if (h->P_max > p->P_Y && (law == NFD_LAW_VZ || table || law == NFD_LAW_THORNTON)) {
        if (law == NFD_LAW_VZ) {
            double a_e, a_p, a_ep;
            nfd_vz_radii(p, h, P, &a_e, &a_p, &a_ep);
            return a_ep;
        }
        if (table)                        /* a_Y f(x_max) + the Hertz radius at P */
            return nfd_vz_table_radius(p, t, h->P_max) - p->a_Y * cbrt(h->P_max / p->P_Y) +
                   nfd_hertz_radius(P, p->R_star, p->E_star);
        double R_p = 3.0 * h->K_u / (4.0 * p->E_star);       /* thornton: K_u = (4/3) E* sqrt(R_p) */
        return nfd_hertz_radius(P, R_p * R_p, p->E_star);      /* Hertz at the enlarged radius R_p^2 */
    }
    return sqrt(d * p->R_star);
}

/* v projected into the plane normal to the unit n, its length kept (a spring follows its contact). */
static inline void nfd_rotate_rescale(double *v, const double *n)
{
    double along = nfd_dot3(v, n), length = nfd_len3(v), projected;
    v[0] -= along * n[0];
    v[1] -= along * n[1];
    v[2] -= along * n[2];
    projected = nfd_len3(v);
    double scale = projected > 0.0 ? length / projected : 0.0;
    v[0] *= scale;
    v[1] *= scale;
    v[2] *= scale;
}

/* Mindlin (variant: an NFD_TANGENTIAL_MINDLIN* code): advance the spring (update), F_t = -k a xi
 * - gamma_t v_t,rel, capped at F_cap (the spring set back, its force at most F_cap). rescale: where the contact radius a
 * shrank below the last step's, the spring is first scaled by a / a_previous; /force: the spring
 * is the elastic force, advanced by -k a dt v_t,rel (F_t = spring - gamma_t v_t,rel). */
static inline void nfd_tangential_mindlin(int variant, nfd_friction_history *s, double a, const double *n,
                                          const double *v_t, double dt, double stiffness, double gamma_t, double F_cap,
                                          int update, double *F_t)
{
    double damping[3], *xi = s->xi_t;
    int k, rescale = variant == NFD_TANGENTIAL_MINDLIN_RESCALE || variant == NFD_TANGENTIAL_MINDLIN_RESCALE_FORCE;
    int force_form = variant == NFD_TANGENTIAL_MINDLIN_FORCE || variant == NFD_TANGENTIAL_MINDLIN_RESCALE_FORCE;
    if (rescale && a < s->a_previous)
        for (k = 0; k < 3; ++k) xi[k] *= a / s->a_previous;
    if (update) {
        double along = fabs(nfd_dot3(xi, n));
        if ((force_form ? along : along * stiffness) > NFD_FRAME_EPSILON * F_cap) nfd_rotate_rescale(xi, n);
        for (k = 0; k < 3; ++k) xi[k] += force_form ? -stiffness * dt * v_t[k] : dt * v_t[k];
        if (rescale) s->a_previous = a;
    }
    for (k = 0; k < 3; ++k) {
        damping[k] = -gamma_t * v_t[k];
        F_t[k] = (force_form ? xi[k] : -stiffness * xi[k]) + damping[k];
    }
    double magnitude = nfd_len3(F_t);
    if (magnitude > (update ? F_cap : F_cap * (1.0 + NFD_CAP_SLACK))) {
        if (nfd_len3(xi) != 0.0) {
            /* the spring keeps the elastic part of the capped force, at most the cap itself: damping
             * beyond the cap stored in it would be returned as work later (nfdmodel/README.md) */
            double scale = F_cap / magnitude, back = -1.0 / stiffness, capped[3], elastic[3], size;
            for (k = 0; k < 3; ++k) {
                capped[k] = F_t[k] * scale;
                elastic[k] = capped[k] - damping[k];
            }
            size = nfd_len3(elastic);
            int limited = size > F_cap * (1.0 + NFD_CAP_SLACK);
            for (k = 0; k < 3; ++k) {
                if (limited) {          /* F_t is the capped force; the spring holds the cap */
                    xi[k] = force_form ? elastic[k] * (F_cap / size) : elastic[k] * (F_cap / size) * back;
                    F_t[k] = capped[k];
                } else {                /* F_t from the spring set back, as LAMMPS computes it */
                    xi[k] = force_form ? elastic[k] : elastic[k] * back;
                    F_t[k] = (force_form ? xi[k] : -stiffness * xi[k]) + damping[k];
                }
            }
        } else {
            F_t[0] = F_t[1] = F_t[2] = 0.0;
        }
    }
}

/* SDS rolling: advance xi (update), F_r = -k xi - gamma v_roll, capped at F_cap. */
static inline void nfd_rolling_sds(double *xi, const double *n, const double *v_roll, double dt, const nfd_friction *f,
                                   double F_cap, int update, double *F_r)
{
    double spring[3] = {xi[0], xi[1], xi[2]};
    int k;
    if (update) {
        if (fabs(nfd_dot3(spring, n)) * f->k_roll > NFD_FRAME_EPSILON * F_cap) nfd_rotate_rescale(spring, n);
        for (k = 0; k < 3; ++k) spring[k] += dt * v_roll[k];
    }
    for (k = 0; k < 3; ++k) F_r[k] = -f->k_roll * spring[k] + -f->gamma_roll * v_roll[k];
    double magnitude = nfd_len3(F_r);
    if (magnitude > (update ? F_cap : F_cap * (1.0 + NFD_CAP_SLACK))) {
        if (nfd_len3(spring) != 0.0) {
            double k_inv = 1.0 / f->k_roll, magnitude_inv = 1.0 / magnitude;
            double back = -F_cap * k_inv * magnitude_inv, drag = -f->gamma_roll * k_inv;
            for (k = 0; k < 3; ++k) {
                spring[k] = back * F_r[k] + drag * v_roll[k];
                F_r[k] = -f->k_roll * spring[k] + -f->gamma_roll * v_roll[k];
            }
        } else {
            F_r[0] = F_r[1] = F_r[2] = 0.0;
        }
    }
    if (update)
        for (k = 0; k < 3; ++k) xi[k] = spring[k];
}

/* Twisting: advance theta (update); the torque -k theta - gamma w, capped at M_cap (theta set back). */
static inline double nfd_twisting(double *theta, double w, double dt, double k, double gamma, double M_cap, int update)
{
    if (update) *theta += w * dt;
    double M = -k * *theta - gamma * w;
    double sign = (double) ((w > 0.0) - (w < 0.0));
    if (fabs(M) > M_cap) {      /* set back: the torque of the spring as set back, -M_cap sign to round-off */
        *theta = (M_cap * sign - gamma * w) / k;
        M = -k * *theta - gamma * w;
    }
    return M;
}

/* The elastic energy [J] the springs of f can return at contact radius a [m] and normal force F_n [N]:
 * each spring's force F_s (tangential k_t a |xi_t|, the /force variants |xi_t|; rolling k_roll |xi_roll|;
 * twisting k |theta|, marshall k = k_t a^2 / 2), limited by its Coulomb cap mu |F_n| (marshall's
 * 2 mu a / 3 |F_n|), as F_s^2 / (2 k): the energy of the spring unloading at this radius through the force
 * it can transmit (at a zero cap, the end of a contact, nothing). The frictional energy dissipated so far
 * is the work of the tangential force and of the rolling and twisting torques minus it
 * (nfdmodel/lammps/nfd_energy.h). */
static inline double nfd_spring_energy(const nfd_friction *f, const nfd_friction_history *s, double a, double F_n)
{
    /* squared forces throughout: no square root per contact */
    double energy = 0.0, F_crit = fabs(F_n), k, cap, squared;
    if (f->tangential != NFD_TANGENTIAL_NONE && f->k_t * a > 0.0) {
        int force_form = f->tangential == NFD_TANGENTIAL_MINDLIN_FORCE ||
                         f->tangential == NFD_TANGENTIAL_MINDLIN_RESCALE_FORCE;
        k = f->k_t * a;
        cap = f->mu * F_crit;
        squared = nfd_dot3(s->xi_t, s->xi_t);
        energy += 0.5 * fmin(force_form ? squared : k * k * squared, cap * cap) / k;
    }
    if (f->rolling == NFD_ROLLING_SDS && f->k_roll > 0.0) {
        cap = f->mu_roll * F_crit;
        energy += 0.5 * fmin(f->k_roll * f->k_roll * nfd_dot3(s->xi_roll, s->xi_roll), cap * cap) / f->k_roll;
    }
    if (f->twisting != NFD_TWISTING_NONE) {
        int marshall = f->twisting == NFD_TWISTING_MARSHALL;
        k = marshall ? 0.5 * f->k_t * a * a : f->k_twist;
        cap = (marshall ? 2.0 / 3.0 * f->mu * a : f->mu_twist) * F_crit;
        squared = k * s->theta_twist;
        if (k > 0.0) energy += 0.5 * fmin(squared * squared, cap * cap) / k;
    }
    return energy;
}

/* One contact: the normal law's step (nfd_step) and the models of f; h_out, fh_out the trial
 * histories (commit them once the step is accepted). Returns the law's status (nothing else is
 * computed for a negative one). */
static inline int nfd_contact_step(int law, const nfd_contact *c, const nfd_params *p, const nfd_table *t,
                                   const nfd_friction *f, const nfd_history *h, const nfd_friction_history *fh,
                                   int update, nfd_history *h_out, nfd_friction_history *fh_out, nfd_contact_result *r)
{
    const double *n = c->n;
    double P = 0.0, v_n, v_t[3], wr[3], spin[3], relrot[3], v_roll[3], F_r[3], turn[3];
    int k, wall = c->R_j == 0.0;
    int status = nfd_step(law, c->delta, p, t, h, &P, h_out, NULL);
    if (status < 0) return status;
    *fh_out = *fh;
    r->P = P;
    r->a = nfd_contact_radius(law, c->delta, p, t, h_out, P);
    double eta = nfd_damping_prefactor(f, c->m_star, r->a, P, c->delta);
    v_n = nfd_dot3(c->v, n);
    r->F_n = P + -eta * v_n;
    double F_crit = fabs(r->F_n);

    r->F_t[0] = r->F_t[1] = r->F_t[2] = 0.0;
    if (f->tangential != NFD_TANGENTIAL_NONE) {
        for (k = 0; k < 3; ++k) wr[k] = c->R_i * c->omega_i[k] + c->R_j * c->omega_j[k];
        nfd_cross3(wr, n, spin);
        for (k = 0; k < 3; ++k) v_t[k] = (c->v[k] - v_n * n[k]) - spin[k];
        nfd_tangential_mindlin(f->tangential, fh_out, r->a, n, v_t, c->dt, f->k_t * r->a, f->x_gamma_t * eta,
                               F_crit * f->mu, update, r->F_t);
    }
    for (k = 0; k < 3; ++k) r->force[k] = r->F_n * n[k] + r->F_t[k];
    nfd_cross3(n, r->F_t, turn);
    double arm_i = wall ? c->R_i : c->R_i - 0.5 * c->delta, arm_j = wall ? 0.0 : c->R_j - 0.5 * c->delta;
    for (k = 0; k < 3; ++k) {
        r->torque_i[k] = -turn[k] * arm_i;
        r->torque_j[k] = -turn[k] * arm_j;
        relrot[k] = c->omega_i[k] - c->omega_j[k];
    }
    if (f->rolling == NFD_ROLLING_SDS) {
        nfd_cross3(relrot, n, v_roll);
        for (k = 0; k < 3; ++k) v_roll[k] *= p->R_star;
        nfd_rolling_sds(fh_out->xi_roll, n, v_roll, c->dt, f, f->mu_roll * F_crit, update, F_r);
        nfd_cross3(n, F_r, turn);
        for (k = 0; k < 3; ++k) {
            r->torque_i[k] += p->R_star * turn[k];
            r->torque_j[k] -= p->R_star * turn[k];
        }
    }
    if (f->twisting != NFD_TWISTING_NONE) {
        int marshall = f->twisting == NFD_TWISTING_MARSHALL;
        double k_twist = marshall ? 0.5 * f->k_t * r->a * r->a : f->k_twist;
        double gamma = marshall ? 0.5 * (f->x_gamma_t * eta) * r->a * r->a : f->gamma_twist;
        double mu = marshall ? 2.0 / 3.0 * f->mu * r->a : f->mu_twist;
        double M = nfd_twisting(&fh_out->theta_twist, nfd_dot3(relrot, n), c->dt, k_twist, gamma, mu * F_crit, update);
        for (k = 0; k < 3; ++k) {
            r->torque_i[k] += M * n[k];
            r->torque_j[k] -= M * n[k];
        }
    }
    if (wall) r->torque_j[0] = r->torque_j[1] = r->torque_j[2] = 0.0;
    return status;
}

#ifdef __cplusplus
}
#endif
#endif

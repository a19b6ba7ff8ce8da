/* nfd_energy.h: what the plugin reports of a contact besides its law's history: the normal force, the
 * tangential force and the energy the contact dissipated so far, in three parts (ContactEnergy,
 * nfd_energy.cpp), kept per contact after the nfd_history and the springs by pair_style nfd/<law>
 * (compute pair/local p6-p10: in the runs that define one) and the wall fixes (their per-atom arrays).
 *
 * Each part is the work its forces and torques took from the two bodies over the contact's steps,
 * by velocity Verlet's trapezoidal rule (the rule under which LAMMPS's nve integrators change the
 * kinetic energy, Verlet's identity), less the elastic energy the part holds at this step (it returns
 * it on unloading), SI units [J]:
 *
 *   dW(F, T) = -(F_old + F_new)/2 . dr - (T_i,old + T_i,new)/2 . dtheta_i - (T_j,old + T_j,new)/2 . dtheta_j
 *   dr = dt (v_i - v_j), dtheta = dt omega, at the half step (what the integrator moved the bodies by)
 *
 *   plastic   D_p += dW(P n) - dE_el,  E_el = P <delta - delta_res>/(n + 1): the integral of the law's
 *             unloading curve from delta_res to delta (nfd_elastic_energy of the kernel; its Python home
 *             nfdmodel.turning_point.elastic_energy); the law's hysteresis
 *   viscous   D_v += dW(F_d n),  F_d = F_n - P: the normal damping force
 *   friction  D_f += dW(F_t, the torques of F_t, rolling and twisting) - dE_s,  E_s the energy the
 *             springs can return, each spring's force limited by its Coulomb cap, F_s^2 / (2 k)
 *             (nfd_spring_energy of nfd_friction.h; zero at the end of a contact, where the cap is):
 *             tangential sliding and damping, rolling and twisting resistance
 *
 * Over a contact that starts and ends at zero force, Verlet's identity (the kinetic energy change of a
 * step is dt/2 (F_old + F_new) . v_half + dt^2/(8 m) (F_new^2 - F_old^2), whose second term telescopes)
 * makes D_p + D_v + D_f the kinetic energy, translational and rotational, the two bodies lost, to
 * round-off. The set-up step of a run evaluates without adding work (the bodies did not move).
 *
 * License: GPL-2.0-or-later (see nfd_law.h).
 */
#ifndef NFD_LAMMPS_ENERGY_H
#define NFD_LAMMPS_ENERGY_H

#include "nfd_law.h"

namespace nfdcal_lammps {

/* The doubles of a contact's energy block: NENERGY for every contact, NENERGY_MODELS with contact
 * models. Vectors are stored as seen from the body of the lower atom ID (sign = +1 when atom i has
 * it), so that both copies of a contact across two ranks hold the same numbers. */
constexpr int NENERGY = 10;
constexpr int NENERGY_MODELS = 20;
enum EnergyField : int {
    ENERGY_F_N = 0,        // normal force F_n = P + damping [N] (on the lower-ID body, along n)
    ENERGY_F_T = 1,        // tangential force |F_t| [N]
    ENERGY_PLASTIC = 2,    // D_p [J]
    ENERGY_VISCOUS = 3,    // D_v [J]
    ENERGY_FRICTION = 4,   // D_f [J]
    ENERGY_P = 5,          // the law's force P [N] of this step
    ENERGY_ELASTIC = 6,    // E_el [J] of this step
    ENERGY_NORMAL = 7,     // n [3], from the higher-ID body to the lower
    ENERGY_TANGENTIAL = 10,    // F_t [3] on the lower-ID body (models)
    ENERGY_TORQUE_LOW = 13,    // the torque on the lower-ID body [3] (models)
    ENERGY_TORQUE_HIGH = 16,   // on the higher-ID body [3] (models; a wall: 0)
    ENERGY_SPRINGS = 19        // E_s [J] of this step (models)
};

/* A contact record: the nfd_history (NHIST), with models the springs (NFRICTION), then the energy
 * block, then with the rate-aware law its R (NRATE). Records of other widths (restart files of the plugin
 * without the energy block: NHIST, or NHIST + NFRICTION) are mapped part by part. */
inline int record_width(bool models) { return models ? NHIST + NFRICTION + NENERGY_MODELS : NHIST + NENERGY; }
/* A record of the rate-aware law (nfd_rate.h) holds one double more at its end, the contact's R (0 until
 * it first touches): NRATE after any of the widths above (none of which is another's plus one). With the
 * relaxing form on some type, every record holds the energy block and NRATE_RELAXING doubles at its end:
 * 1 / (c a_ref) [1/m], then s (last, where R is): record_width + 2, a width no other layout takes. */
constexpr int NRATE = 1;
constexpr int NRATE_RELAXING = 2;
inline bool record_has_relaxing(int width)
{
    return width == record_width(false) + NRATE_RELAXING || width == record_width(true) + NRATE_RELAXING;
}
inline bool record_has_rate(int width)
{
    return width == NHIST + NRATE || width == NHIST + NFRICTION + NRATE || width == record_width(false) + NRATE ||
        width == record_width(true) + NRATE || record_has_relaxing(width);
}
inline int record_rate_doubles(int width)
{
    return record_has_relaxing(width) ? NRATE_RELAXING : record_has_rate(width) ? NRATE : 0;
}
inline int record_base(int width) { return width - record_rate_doubles(width); }
inline bool record_has_springs(int width)
{
    return record_base(width) == NHIST + NFRICTION || record_base(width) == record_width(true);
}
inline int energy_offset(int width) { return record_has_springs(width) ? NHIST + NFRICTION : NHIST; }

class ContactEnergy {
 public:
    /* The record `in` of width w_in copied into `out` of width w_out (zeros where `in` has no part). */
    static void restride(const double *in, int w_in, double *out, int w_out);

    /* A contact of the law alone (force P [N] on body i along the unit n from j to i): this step's
     * entries of the energy block b, the plastic work added when advance (not the set-up step).
     * dr [m]: dt (v_i - v_j) (NaN when unknown: the energies become NaN); sign: +1 when i has the lower ID. */
    static void law_step(double *b, int law, double delta, const nfd_history &next, double P, const double *n,
                         const double *dr, double sign, bool advance);

    /* A contact with models (nfd_contact_step's result `out`, the springs after the step), body i of
     * rotation dtheta_i = dt omega_i [rad], body j dtheta_j (a wall: 0). */
    static void models_step(double *b, int law, double delta, const nfd_history &next, const nfd_contact_result &out,
                            const nfd_friction &f, const nfd_friction_history &springs, const double *n,
                            const double *dr, const double *dtheta_i, const double *dtheta_j, double sign,
                            bool advance);
};

}    // namespace nfdcal_lammps

#endif

/* nfd_energy.cpp: a contact's dissipated energies (nfd_energy.h).
 *
 * License: GPL-2.0-or-later (see nfd_law.h).
 */
#include "nfd_energy.h"

#include <algorithm>

namespace nfdcal_lammps {

void ContactEnergy::restride(const double *in, int w_in, double *out, int w_out)
{
    std::fill(out, out + w_out, 0.0);
    std::copy(in, in + std::min(NHIST, std::min(w_in, w_out)), out);
    if (record_has_springs(w_in) && record_has_springs(w_out)) std::copy(in + NHIST, in + NHIST + NFRICTION, out + NHIST);
    const int from = energy_offset(w_in), to = energy_offset(w_out);
    const int count = std::min(record_base(w_in) - from, record_base(w_out) - to);
    if (count > 0) std::copy(in + from, in + from + count, out + to);
    // the rate block from its end: R or s last, then the relaxing form's 1 / (c a_ref)
    const int rate = std::min(record_rate_doubles(w_in), record_rate_doubles(w_out));
    for (int k = 1; k <= rate; ++k) out[w_out - k] = in[w_in - k];
}

void ContactEnergy::law_step(double *b, int law, double delta, const nfd_history &next, double P, const double *n,
                             const double *dr, double sign, bool advance)
{
    double normal[3], step[3];
    for (int k = 0; k < 3; ++k) {
        normal[k] = sign * n[k];
        step[k] = sign * dr[k];
    }
    const double elastic = nfd_elastic_energy(law, delta, &next, P);
    if (advance) {
        const double *old = b + ENERGY_NORMAL;
        const double work = -0.5 * (b[ENERGY_P] * nfd_dot3(old, step) + P * nfd_dot3(normal, step));
        b[ENERGY_PLASTIC] += work - (elastic - b[ENERGY_ELASTIC]);
    }
    b[ENERGY_F_N] = P;
    b[ENERGY_F_T] = 0.0;
    b[ENERGY_P] = P;
    b[ENERGY_ELASTIC] = elastic;
    for (int k = 0; k < 3; ++k) b[ENERGY_NORMAL + k] = normal[k];
}

void ContactEnergy::models_step(double *b, int law, double delta, const nfd_history &next,
                                const nfd_contact_result &out, const nfd_friction &f,
                                const nfd_friction_history &springs, const double *n, const double *dr,
                                const double *dtheta_i, const double *dtheta_j, double sign, bool advance)
{
    double normal[3], step[3], tangential[3];
    const bool low = sign > 0.0;
    const double *torque_low = low ? out.torque_i : out.torque_j, *torque_high = low ? out.torque_j : out.torque_i;
    const double *turn_low = low ? dtheta_i : dtheta_j, *turn_high = low ? dtheta_j : dtheta_i;
    for (int k = 0; k < 3; ++k) {
        normal[k] = sign * n[k];
        step[k] = sign * dr[k];
        tangential[k] = sign * out.F_t[k];
    }
    const double elastic = nfd_elastic_energy(law, delta, &next, out.P);
    const double stored = nfd_spring_energy(&f, &springs, out.a, out.F_n);
    const double damping = out.F_n - out.P;
    if (advance) {
        const double *old = b + ENERGY_NORMAL;
        const double along_old = nfd_dot3(old, step), along = nfd_dot3(normal, step);
        const double law_work = -0.5 * (b[ENERGY_P] * along_old + out.P * along);
        const double damping_work = -0.5 * ((b[ENERGY_F_N] - b[ENERGY_P]) * along_old + damping * along);
        double friction_work = 0.0;
        for (int k = 0; k < 3; ++k)
            friction_work += (b[ENERGY_TANGENTIAL + k] + tangential[k]) * step[k] +
                (b[ENERGY_TORQUE_LOW + k] + torque_low[k]) * turn_low[k] +
                (b[ENERGY_TORQUE_HIGH + k] + torque_high[k]) * turn_high[k];
        b[ENERGY_PLASTIC] += law_work - (elastic - b[ENERGY_ELASTIC]);
        b[ENERGY_VISCOUS] += damping_work;
        b[ENERGY_FRICTION] += -0.5 * friction_work - (stored - b[ENERGY_SPRINGS]);
    }
    b[ENERGY_F_N] = out.F_n;
    b[ENERGY_F_T] = nfd_len3(out.F_t);
    b[ENERGY_P] = out.P;
    b[ENERGY_ELASTIC] = elastic;
    b[ENERGY_SPRINGS] = stored;
    for (int k = 0; k < 3; ++k) {
        b[ENERGY_NORMAL + k] = normal[k];
        b[ENERGY_TANGENTIAL + k] = tangential[k];
        b[ENERGY_TORQUE_LOW + k] = torque_low[k];
        b[ENERGY_TORQUE_HIGH + k] = torque_high[k];
    }
}

}    // namespace nfdcal_lammps

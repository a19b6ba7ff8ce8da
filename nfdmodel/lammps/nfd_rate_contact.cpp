/* nfd_rate_contact.cpp: the rate-aware law in the pair style and the wall fixes (the keyword `rate`,
 * nfd_input.h's take_rate; nfd_rate.h).
 *
 * A contact of constants with a rate law keeps one double more at the end of its record, R, 0 until it
 * first touches. At that step (overlap > 0 with R = 0) R is fixed from the normal approach speed
 * v_n0 = -(v_i - v_j).n [m/s] (n from j to i; a wall: v_j the wall's velocity at the contact) and the
 * pair's reduced mass m* (a wall: the atom's mass), nfd_rate_first_factor: eps_dot = v_n0 / (c a_ref),
 * a_ref the base law's contact radius at the peak of its impact at v_n0; v_n0 <= 0 (a contact formed
 * without approach) gives eps_dot = 0. LAMMPS's force step sees the half-step velocities, those of
 * nfdmodel.collide's leap-frog at its first contact step. The relaxing form (`rate ... relaxing K`) keeps two
 * doubles, 1 / (c a_ref) then s (last), and moves s every step the contact loads beyond its turning point
 * (nfd_rate_relax with that step's normal speed and K = k E* / sigma_y of the contact's constants). The contact then steps its base law (nfd_step,
 * nfd_contact_step with the contact models) with nfd_rate_params(p, R): P = R^3 P_0(delta / R^2), the
 * history in SI and the contact radius R a_0 (friction, rolling, twisting, damping), as
 * nfdmodel.rate_aware. The record is zeroed when the contact ends, so a new contact fixes its own R.
 *
 * License: GPL-2.0-or-later (see nfd_law.h).
 */
#include "fix_nfd_wall.h"
#include "fix_nfd_history.h"
#include "pair_nfd.h"

#include "atom.h"
#include "error.h"
#include "utils.h"

#include <cmath>

using namespace LAMMPS_NS;

namespace nfdcal_lammps {

/* The relaxing form (nfd_rate.h): s and 1 / (c a_ref), the record's last two doubles (end: one past the record),
 * moved by nfd_rate_relax (delta_max the record's history), then p = nfd_rate_params(base, s). */
static int relax_params(const NfdMaterial &c, const nfd_params &base, double m_star, double speed, double delta,
                 const double *record, double *end, nfd_params &p)
{
    const double stiffness = nfd_rate_element_stiffness(&c.rate, base.E_star, c.sigma_y);
    const int status = nfd_rate_relax(&c.rate, &base, &c.table, m_star, stiffness, speed, delta,
                                      load_history(record).delta_max, end - 1, end - 2);
    if (status != NFD_OK) return status;
    nfd_rate_params(&base, end[-1] > 0.0 ? end[-1] : 1.0, &p);
    return NFD_OK;
}

/* The error of a contact whose R could not be found (status of nfd_rate_first_factor). */
static std::string rate_failure(int status, double speed)
{
    return status == NFD_FULL_CONTACT
        ? fmt::format("the base law's contact radius at the peak of an impact at the normal speed {:.6g} m/s of its "
                      "first touch reaches R* (no rate factor: beyond the law's domain)", speed)
        : fmt::format("its rate factor at the normal speed {:.6g} m/s of its first touch is not a finite number",
                      speed);
}

void PairNfd::rate_params(int i, int j, double delx, double dely, double delz, double r, double delta,
                          const NfdMaterial &c, double *stored, nfd_params &p)
{
    double *factor = stored + history->stride() - NRATE;
    const bool relaxing = c.rate.k > 0.0;
    double speed = 0.0, m_star = 0.0;
    nfd_params base = p;
    if (*factor == 0.0 || relaxing) {      // the normal approach speed: at first touch (relaxing: every step)
        double **v = atom->v;
        speed = -((v[i][0] - v[j][0]) * delx + (v[i][1] - v[j][1]) * dely + (v[i][2] - v[j][2]) * delz) / r;
    }
    if (*factor == 0.0) {                  // the first touch: the reduced mass
        m_star = atom->rmass[i] * atom->rmass[j] / (atom->rmass[i] + atom->rmass[j]);
        // a_ref's impact loads vz beyond first yield: its cube roots (contact_params leaves them out unless
        // this step needs them)
        nfd_pair_scaled(&type_pair(atom->type[i], atom->type[j]).unit, p.R_star, 1, &base);
    }
    const int status = relaxing ? relax_params(c, base, m_star, speed, delta, stored, stored + history->stride(), p)
                                : nfd_rate_contact_params(&c.rate, &base, &c.table, m_star, speed, delta, factor, &p);
    if (status != NFD_OK)
        error->one(FLERR, fmt::format("pair_style {} rate: the contact of atoms {} and {}: {}", name(),
                                      atom->tag[i], atom->tag[j], rate_failure(status, speed)));
}

void FixNfdWall::rate_params(int i, double delta, const double *n, const double *v_wall, double *stored,
                             nfd_params &p)
{
    double *factor = stored + width - NRATE;
    const bool relaxing = material.rate.k > 0.0;
    double speed = 0.0;
    if (*factor == 0.0 || relaxing)
        for (int d = 0; d < 3; ++d) speed -= (atom->v[i][d] - v_wall[d]) * n[d];
    const nfd_params base = p;
    const int status = relaxing
        ? relax_params(material, base, atom->rmass[i], speed, delta, stored, stored + width, p)
        : nfd_rate_contact_params(&material.rate, &base, &material.table, atom->rmass[i], speed, delta, factor, &p);
    if (status != NFD_OK)
        error->one(FLERR, fmt::format("{} rate: atom {} on the wall: {}", who(), atom->tag[i],
                                      rate_failure(status, speed)));
}

}    // namespace nfdcal_lammps

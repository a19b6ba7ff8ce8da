/* pair_nfd.cpp: pair_style nfd/<law> (pair_nfd.h).
 *
 * Each contact takes its constants from the two atoms' types (NfdLaw::mix, once per pair of
 * types in init_one; the constants of pair_coeff I J calibrated for that pair in place of the
 * yielding body's, NfdLaw::with_pair) and its radii (1/R* = 1/R_i + 1/R_j, per contact), as
 * nfdmodel.ContactPair.sphere_sphere. With contact models (nfd_models.h) a contact is the
 * kernel's nfd_contact_step: the normal law's force, normal damping, friction, rolling and
 * twisting resistance, forces and torques on both atoms; the springs are advanced on every step
 * but the set-up step of a run (as LAMMPS's granular styles). A contact whose turning point moves beyond the window of
 * its constants is counted once, and one that ends after turning below the window's lowest unloading
 * (window P_min/P_Y P_max/P_Y); the counts are reported at the end of each run. A
 * contact that reaches full contact (the law's contact radius reaches R*) stops the run with an
 * error naming the two atoms.
 *
 * License: GPL-2.0-or-later (see nfd_law.h).
 */
#include "pair_nfd.h"

#include "fix_nfd_history.h"
#include "nfd_input.h"

#include "atom.h"
#include "comm.h"
#include "compute.h"
#include "error.h"
#include "force.h"
#include "memory.h"
#include "modify.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "update.h"
#include "utils.h"

#include <mpi.h>

#include <algorithm>
#include <utility>
#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;

namespace nfdcal_lammps {

/* The per-atom fix data of a restart file that read_restart keeps until the next run's init (fix
 * ID and style of each entry): Modify holds these lists as protected members and reports unused
 * entries only as a plain log line at that run, so the pair style reads them here (a pointer to
 * member formed in a derived class: read-only, standard C++; never instantiated) to say at once
 * when the file holds the contact history of another nfd law. */
struct RestartFixLists : Modify {
    static char **Modify::*ids() { return &RestartFixLists::id_restart_peratom; }
    static char **Modify::*styles() { return &RestartFixLists::style_restart_peratom; }
};

PairNfd::PairNfd(LAMMPS *lmp, const NfdLaw *law) : Pair(lmp), law(law)
{
    single_enable = 1;
    single_extra = 10;             // delta, force, delta_max, P_max, delta_res, F_n, |F_t|, D_p, D_v, D_f
    svector = new double[single_extra];
    no_virial_fdotr_compute = 1;   // ev_tally_xyz per contact (correct across periodic images)
    restartinfo = 0;               // the constants are issued again after read_restart
    finitecutflag = 1;
    writedata = 0;
}

PairNfd::~PairNfd()
{
    delete[] svector;
    if (history && modify->get_fix_by_id(law->history_id)) modify->delete_fix(law->history_id);
    if (allocated) {
        memory->destroy(setflag);
        memory->destroy(cutsq);
    }
}

void PairNfd::settings(int narg, char ** /*arg*/)
{
    require_si_units(lmp, fmt::format("pair_style {}", name()));
    if (narg != 0)
        error->all(FLERR, fmt::format("pair_style {} takes no arguments (the constants go in pair_coeff)", name()));
}

void PairNfd::coeff(int narg, char **arg)
{
    const std::string who = fmt::format("pair_coeff for {}", name());
    if (narg < 2) error->all(FLERR, fmt::format("{}: need the types I I, then the material", who));
    if (!allocated) allocate();
    int ilo, ihi, jlo, jhi;
    utils::bounds(FLERR, arg[0], 1, atom->ntypes, ilo, ihi, error);
    utils::bounds(FLERR, arg[1], 1, atom->ntypes, jlo, jhi, error);
    if (!law->per_type_pair && (ilo != jlo || ihi != jhi)) {
        calibrated_pair_coeff(who, narg, arg, ilo, ihi, jlo, jhi);
        create_history_fix();
        return;
    }
    std::vector<char *> rest(arg + 2, arg + narg);     // the constants and models, without `rate ...`
    nfd_rate rate{};
    const bool rate_given = take_rate(lmp, who, law, rest, &rate);
    const int models_at = first_model_keyword(static_cast<int>(rest.size()), rest.data());
    NfdMaterial constants = law->read(lmp, who, false, models_at, rest.data());
    constants.models = read_models(lmp, who, static_cast<int>(rest.size()) - models_at, rest.data() + models_at,
                                   !law->per_type_pair);
    constants.rate_on = rate_given;
    constants.rate = rate;
    constants.friction = contact_friction(constants.models, constants.E, constants.nu, constants.E, constants.nu);
    int count = 0;
    for (int i = ilo; i <= ihi; ++i)
        for (int j = std::max(jlo, i); j <= jhi; ++j, ++count) {
            if (i != j && !law->per_type_pair) continue;
            if (i == j) material[i] = constants;
            if (law->per_type_pair) {
                contact[i][j] = contact[j][i] = constants;
                explicit_pair[i][j] = explicit_pair[j][i] = 1;
            }
            setflag[i][j] = 1;
        }
    // LAMMPS puts two plain type numbers in order itself, not a wildcard (2* 1 sets nothing)
    if (count == 0)
        error->all(FLERR, fmt::format("{}: types {} {} out of range: need I <= J (no type pair in these ranges has "
                                      "I <= J; give the lower types first)", who, arg[0], arg[1]));
    // the history fix comes right after the first pair_coeff, before fixes that add atoms
    create_history_fix();
}

/* pair_coeff I J (I != J) of a law of materials: the constants calibrated for that pair
 * (NfdLaw::read_pair), used in place of the yielding body's; E*, first yield and the contact models
 * stay the two types' (init_one). */
void PairNfd::calibrated_pair_coeff(const std::string &who, int narg, char **arg, int ilo, int ihi, int jlo, int jhi)
{
    if (first_model_keyword(narg - 2, arg + 2) < narg - 2)
        error->all(FLERR, fmt::format("{}: types I J take the constants calibrated for the pair only; its contact "
                                      "models are its types' (pair_coeff I I ..., mixed)", who));
    for (int k = 3; k < narg; ++k)
        if (std::strcmp(arg[k], "rate") == 0 && std::strcmp(arg[k - 1], "file") != 0)
            error->all(FLERR, fmt::format("{} rate: types I J take the constants calibrated for the pair only; the "
                                          "rate law is the yielding type's (pair_coeff I I ... rate ...)", who));
    const NfdMaterial constants = law->read_pair(lmp, who, narg - 2, arg + 2);
    int count = 0;
    for (int i = ilo; i <= ihi; ++i)
        for (int j = std::max(jlo, i); j <= jhi; ++j, ++count) {
            if (i == j)
                error->all(FLERR, fmt::format("{}: types {} {} out of range: the constants of a pair need I != J in "
                                              "every pair of the ranges (a type's own go in pair_coeff I I)", who,
                                              arg[0], arg[1]));
            pair_constants[i][j] = pair_constants[j][i] = constants;
            calibrated[i][j] = calibrated[j][i] = 1;
            setflag[i][j] = 1;
        }
    if (count == 0)
        error->all(FLERR, fmt::format("{}: types {} {} out of range: need I <= J (no type pair in these ranges has "
                                      "I <= J; give the lower types first)", who, arg[0], arg[1]));
}

void PairNfd::init_style()
{
    require_si_units(lmp, fmt::format("pair_style {}", name()));
    if (!atom->radius_flag || !atom->rmass_flag)
        error->all(FLERR, fmt::format("pair_style {} needs per-atom radius and mass: use atom_style sphere", name()));
    if (force->newton_pair)
        error->all(FLERR, fmt::format("pair_style {} supports newton off only: add 'newton off' before the "
                                      "simulation box is created", name()));
    if (atom->tag_enable == 0) error->all(FLERR, fmt::format("pair_style {} needs atom IDs", name()));
    neighbor->add_request(this, NeighConst::REQ_SIZE);
    create_history_fix();
    history->pair = this;

    // contact models on any type (mixing requires the same on all) or explicit pair: the springs
    // are stored with the history, and the contacts need velocities and spins of both atoms
    models_on = false;
    for (int i = 1; i <= atom->ntypes; ++i)
        for (int j = i; j <= atom->ntypes; ++j)
            models_on = models_on || (i == j && material[i].models.any()) ||
                (explicit_pair[i][j] && contact[i][j].models.any());
    // the energy block's one reader is compute pair/local (single()): without one the bookkeeping is skipped
    energy_on = false;
    for (Compute *compute : modify->get_compute_list())
        energy_on = energy_on || std::strcmp(compute->style, "pair/local") == 0;
    // the rate-aware law on some type: each record holds the contact's R at its end (NRATE)
    rate_on = false;
    bool relaxing = false;              // the relaxing form: the energy block and two doubles (nfd_energy.h)
    for (int i = 1; i <= atom->ntypes; ++i) {
        rate_on = rate_on || material[i].rate_on;
        relaxing = relaxing || (material[i].rate_on && material[i].rate.k > 0.0);
    }
    history->set_width(relaxing ? record_width(models_on) + NRATE_RELAXING
                                : (energy_on ? record_width(models_on) : models_on ? NHIST + NFRICTION : NHIST) +
                                      (rate_on ? NRATE : 0));
    if (rate_on && !comm->ghost_velocity)
        error->all(FLERR, fmt::format("pair_style {} with the rate keyword needs the velocities of ghost atoms (the "
                                      "normal speed at first contact): add 'comm_modify vel yes'", name()));
    if (models_on && (!atom->omega_flag || !atom->torque_flag))
        error->all(FLERR, fmt::format("pair_style {} with contact models needs per-atom spins and torques: use "
                                      "atom_style sphere", name()));
    if (models_on && !comm->ghost_velocity)
        error->all(FLERR, fmt::format("pair_style {} with contact models needs the velocities of ghost atoms: add "
                                      "'comm_modify vel yes'", name()));

    // the largest radius of each type, including the particles fix pour / deposit will insert
    const int ntypes = atom->ntypes;
    std::vector<double> mine(ntypes + 1, 0.0);
    for (Fix *fix : modify->get_fix_list()) {
        if (std::strcmp(fix->style, "pour") != 0 && std::strcmp(fix->style, "deposit") != 0) continue;
        for (int t = 1; t <= ntypes; ++t) {
            int itype = t;
            auto *radius = static_cast<double *>(fix->extract("radius", itype));
            if (radius && *radius > mine[t]) mine[t] = *radius;
        }
    }
    for (int i = 0; i < atom->nlocal; ++i)
        if (atom->radius[i] > mine[atom->type[i]]) mine[atom->type[i]] = atom->radius[i];
    max_radius.assign(ntypes + 1, 0.0);
    MPI_Allreduce(mine.data(), max_radius.data(), ntypes + 1, MPI_DOUBLE, MPI_MAX, world);

    beyond_count = 0;
    beyond_largest = 0.0;
    window_of_largest = 0.0;
    below_count = 0;
    below_lowest = INFINITY;
    window_min_of_lowest = 0.0;
    time_step.begin_run();
}

/* The contact constants of a pair of types (NfdLaw::mix, the lower type first, unless set by
 * pair_coeff I J; with the constants calibrated for the pair in place of the yielding body's when
 * given) and its cutoff, the sum of the largest radii. */
double PairNfd::init_one(int i, int j)
{
    if (!explicit_pair[i][j]) {
        const NfdMaterial &a = material[i], &b = material[j];
        if (!a.models.same_kinds(b.models))
            error->all(FLERR, fmt::format("pair_style {}: the pair_coeff of atom types {} and {} give other contact "
                                          "models ({}; {}), which do not mix: give both the same models", name(), i,
                                          j, a.models.kinds(), b.models.kinds()));
        NfdMaterial mixed = law->mix(a, b);
        mixed.models = mix_models(a.models, b.models);
        mixed.friction = contact_friction(mixed.models, a.E, a.nu, b.E, b.nu);
        if (calibrated[i][j]) mixed = NfdLaw::with_pair(mixed, pair_constants[i][j]);
        contact[i][j] = contact[j][i] = mixed;
    }
    for (const auto &ij : {std::make_pair(i, j), std::make_pair(j, i)}) {
        TypePair &pair = type_pairs[ij.first * (ntypes_set + 1) + ij.second];
        pair.constants = &contact[ij.first][ij.second];
        pair.unit = law->params(1.0, *pair.constants);
        pair.models = pair.constants->models.any();
    }
    return max_radius[i] + max_radius[j];
}

/* A contact's nfd_params from its types' (nfd_pair_scaled) at R* (1/R* = 1/R_i + 1/R_j); the cube
 * root of vz's plastic solve only when the contact loads beyond its turning point and beyond first
 * yield (delta > delta_Y: the kernel's test, on the same product), the only step that reads it. */
nfd_params PairNfd::contact_params(int itype, int jtype, double R_i, double R_j, const nfd_history &h,
                                   double delta) const
{
    const nfd_params &unit = type_pair(itype, jtype).unit;
    const double R_star = nfd_effective_radius(R_i, R_j);
    nfd_params p;
    nfd_pair_scaled(&unit, R_star, delta > h.delta_max && delta > unit.delta_Y * R_star, &p);
    return p;
}

void PairNfd::compute(int eflag, int vflag)
{
    ev_init(eflag, vflag);
    if (!history->ready())
        error->one(FLERR, fmt::format("pair_style {}: the contact history is out of step with the neighbor list",
                                      name()));
    double **x = atom->x;
    double **f = atom->f;
    double *radius = atom->radius;
    int *type = atom->type;
    tagint *tag = atom->tag;
    const int nlocal = atom->nlocal;

    for (int ii = 0; ii < list->inum; ++ii) {
        const int i = list->ilist[ii];
        const int *jlist = list->firstneigh[i];
        for (int jj = 0; jj < list->numneigh[i]; ++jj) {
            const int j = jlist[jj] & NEIGHMASK;
            const double delx = x[i][0] - x[j][0];
            const double dely = x[i][1] - x[j][1];
            const double delz = x[i][2] - x[j][2];
            const double rsq = delx * delx + dely * dely + delz * delz;
            const double radsum = radius[i] + radius[j];
            double *stored = history->value(i, jj);
            if (rsq >= radsum * radsum) {         // apart: the contact (if any) is over
                if (history->touching(i, jj)) {
                    count_below_window(i, j, stored);
                    for (int n = 0; n < history->stride(); ++n) stored[n] = 0.0;
                    history->set_touching(i, jj, false);
                }
                continue;
            }
            const double r = std::sqrt(rsq);
            const double delta = radsum - r;
            const TypePair &pair = type_pair(type[i], type[j]);
            const nfd_history h = load_history(stored);
            nfd_params p = contact_params(type[i], type[j], radius[i], radius[j], h, delta);
            if (!history->touching(i, jj)) see_contact_start(i, j, delx, dely, delz, r, p);
            if (pair.constants->rate_on) rate_params(i, j, delx, dely, delz, r, delta, *pair.constants, stored, p);
            if (pair.models) {
                contact_with_models(i, j, delx, dely, delz, r, *pair.constants, p, stored);
                history->set_touching(i, jj, true);
                continue;
            }
            nfd_history next;
            double force = 0.0;
            const int status = nfd_step(law->code, delta, &p, &pair.constants->table, &h, &force, &next, nullptr);
            if (status != NFD_OK) check_status(status, i, j, delta, p, h, next);
            store_history(next, stored);
            history->set_touching(i, jj, true);
            if (energy_on) law_energy(i, j, delx, dely, delz, r, delta, next, force, stored);

            const double fpair = force / r;
            const double fx = delx * fpair, fy = dely * fpair, fz = delz * fpair;
            f[i][0] += fx;
            f[i][1] += fy;
            f[i][2] += fz;
            if (j < nlocal) {
                f[j][0] -= fx;
                f[j][1] -= fy;
                f[j][2] -= fz;
            }
            if (evflag) ev_tally_xyz(i, j, nlocal, 0, 0.0, 0.0, fx, fy, fz, delx, dely, delz);
        }
    }
}

/* A contact's first step: its duration at the normal speed of its start against the timestep. A
 * ghost atom's velocity is known only with comm_modify vel yes (else the contact is not seen here). */
void PairNfd::see_contact_start(int i, int j, double delx, double dely, double delz, double r, const nfd_params &p)
{
    if (j >= atom->nlocal && !comm->ghost_velocity) return;
    double **v = atom->v;
    const double v_n = std::fabs(((v[i][0] - v[j][0]) * delx + (v[i][1] - v[j][1]) * dely +
                                  (v[i][2] - v[j][2]) * delz) / r);
    const double m_i = atom->rmass[i], m_j = atom->rmass[j];
    time_step.see(lmp, fmt::format("pair_style {}", name()), law->contact_time(p, m_i * m_j / (m_i + m_j), v_n), v_n);
}

/* A status other than NFD_OK (the callers test it first): a negative one stops the run naming the two
 * atoms; a turning point beyond the window is counted (once per contact, when it first leaves; by one rank per contact). */
void PairNfd::check_status(int status, int i, int j, double delta, const nfd_params &p, const nfd_history &h,
                           const nfd_history &next)
{
    tagint *tag = atom->tag;
    if (status == NFD_FULL_CONTACT)
        error->one(FLERR, fmt::format("pair_style {}: the contact of atoms {} and {} reached full contact at "
                                      "overlap {:.6g} m (delta/R* = {:.4g}, P/P_Y = {:.4g}): the law's contact "
                                      "radius reaches R*, where no contact law holds", name(), tag[i], tag[j],
                                      delta, delta / p.R_star, next.P_max / p.P_Y));
    if (status == NFD_NOT_FINITE)
        error->one(FLERR, fmt::format("pair_style {}: the force of the contact of atoms {} and {} is not a "
                                      "finite number (overlap {:.6g} m)", name(), tag[i], tag[j], delta));
    if (status == NFD_BEYOND_WINDOW && (j < atom->nlocal || tag[i] < tag[j])) {
        if (h.P_max <= p.window_P_max) ++beyond_count;
        const double load = next.P_max / p.P_Y;
        if (load > beyond_largest) {
            beyond_largest = load;
            window_of_largest = p.window_P_max / p.P_Y;
        }
    }
}

/* A contact that ends (i and j apart) after it yielded and turned below the lowest unloading load of
 * its constants' window, P_Y < P_max < P_min (what nfdmodel.collide flags as outside the calibrated
 * range): counted once, by one rank; P_Y of the contact from its types' at R* = 1 m (P_Y ~ R*^2). */
void PairNfd::count_below_window(int i, int j, const double *stored)
{
    const int *type = atom->type;
    const TypePair &pair = type_pair(type[i], type[j]);
    if (!(pair.constants->window_min > 1.0) || !(j < atom->nlocal || atom->tag[i] < atom->tag[j])) return;
    const double R_star = nfd_effective_radius(atom->radius[i], atom->radius[j]);
    double P_Y = pair.unit.P_Y * R_star * R_star;
    const double P_max = load_history(stored).P_max;
    const double R = pair.constants->rate_on ? stored[history->stride() - NRATE] : 0.0;
    if (R > 0.0) P_Y *= R * R * R;                   // the rate-aware law: P_Y R^3
    if (P_max > P_Y * (1.0 + 1e-9) && P_max < pair.constants->window_min * P_Y * (1.0 - 1e-9)) {
        ++below_count;
        below_lowest = std::min(below_lowest, P_max / P_Y);
        window_min_of_lowest = below_lowest == P_max / P_Y ? pair.constants->window_min : window_min_of_lowest;
    }
}

/* The energy block (nfd_energy.h) of a contact of the law alone: the velocity of a ghost atom j is
 * known with comm_modify vel yes only (else the energies are NaN). */
void PairNfd::law_energy(int i, int j, double delx, double dely, double delz, double r, double delta,
                         const nfd_history &next, double force, double *stored)
{
    double **v = atom->v;
    const double rinv = 1.0 / r, dt = update->dt;
    const double n[3] = {delx * rinv, dely * rinv, delz * rinv};
    double dr[3];
    const bool known = j < atom->nlocal || comm->ghost_velocity;
    for (int d = 0; d < 3; ++d) dr[d] = known ? dt * (v[i][d] - v[j][d]) : NAN;
    ContactEnergy::law_step(stored + energy_offset(history->stride()), law->code, delta, next, force, n, dr,
                            atom->tag[i] < atom->tag[j] ? 1.0 : -1.0, !update->setupflag);
}

/* A contact with models (nfd_contact_step): the normal law, damping, friction, rolling and
 * twisting; the force on both atoms (j only if owned: newton off), the torques, the history and
 * springs stored in the list entry (the tangential spring as seen from the lower atom ID). */
void PairNfd::contact_with_models(int i, int j, double delx, double dely, double delz, double r,
                                  const NfdMaterial &c, const nfd_params &p, double *stored)
{
    double **v = atom->v, **omega = atom->omega, **f = atom->f, **torque = atom->torque;
    double *radius = atom->radius, *rmass = atom->rmass;
    const int nlocal = atom->nlocal;
    const double rinv = 1.0 / r, sign = atom->tag[i] < atom->tag[j] ? 1.0 : -1.0;
    nfd_contact k;
    k.n[0] = delx * rinv;
    k.n[1] = dely * rinv;
    k.n[2] = delz * rinv;
    k.delta = radius[i] + radius[j] - r;
    k.R_i = radius[i];
    k.R_j = radius[j];
    for (int d = 0; d < 3; ++d) {
        k.v[d] = v[i][d] - v[j][d];
        k.omega_i[d] = omega[i][d];
        k.omega_j[d] = omega[j][d];
    }
    k.m_star = rmass[i] * rmass[j] / (rmass[i] + rmass[j]);
    k.dt = update->dt;
    const nfd_history h = load_history(stored);
    const nfd_friction_history springs = load_friction(stored + NHIST, sign);
    nfd_history next;
    nfd_friction_history springs_next;
    nfd_contact_result out;
    const int status = nfd_contact_step(law->code, &k, &p, &c.table, &c.friction, &h, &springs,
                                        update->setupflag ? 0 : 1, &next, &springs_next, &out);
    if (status != NFD_OK) check_status(status, i, j, k.delta, p, h, next);
    store_history(next, stored);
    store_friction(springs_next, sign, stored + NHIST);
    if (energy_on) {
        double dr[3], turn_i[3], turn_j[3];
        for (int d = 0; d < 3; ++d) {
            dr[d] = k.dt * k.v[d];
            turn_i[d] = k.dt * k.omega_i[d];
            turn_j[d] = k.dt * k.omega_j[d];
        }
        ContactEnergy::models_step(stored + NHIST + NFRICTION, law->code, k.delta, next, out, c.friction,
                                   springs_next, k.n, dr, turn_i, turn_j, sign, !update->setupflag);
    }
    for (int d = 0; d < 3; ++d) {
        f[i][d] += out.force[d];
        torque[i][d] += out.torque_i[d];
    }
    if (j < nlocal)
        for (int d = 0; d < 3; ++d) {
            f[j][d] -= out.force[d];
            torque[j][d] += out.torque_j[d];
        }
    if (evflag) ev_tally_xyz(i, j, nlocal, 0, 0.0, 0.0, out.force[0], out.force[1], out.force[2], delx, dely, delz);
}

/* One contact's force from its stored history, not committed (compute pair/local); extra values:
 * p1 overlap delta [m], p2 the law's force P [N], p3 delta_max [m], p4 P_max [N], p5 delta_res [m] (the
 * dent), and this step's entries of the energy block (nfd_energy.h): p6 the normal force F_n (P plus
 * damping) [N], p7 the tangential force |F_t| [N], the energy dissipated so far [J]: p8 plastic, p9
 * viscous (normal damping), p10 frictional (tangential, rolling, twisting). */
double PairNfd::single(int i, int j, int itype, int jtype, double rsq, double /*factor_coul*/,
                       double /*factor_lj*/, double &fforce)
{
    for (int n = 0; n < single_extra; ++n) svector[n] = 0.0;
    fforce = 0.0;
    double *radius = atom->radius;
    const double radsum = radius[i] + radius[j];
    if (rsq >= radsum * radsum) return 0.0;
    const double r = std::sqrt(rsq);
    const double delta = radsum - r;
    nfd_history h = {0.0, 0.0, 0.0, 0.0, 0.0};
    const double *stored = find_stored(i, j);
    if (!stored) stored = find_stored(j, i);
    if (stored) {
        h = load_history(stored);
        const double *b = stored + energy_offset(history->stride());
        for (int n = 0; n < 5; ++n) svector[5 + n] = b[ENERGY_F_N + n];
    }
    nfd_params p = contact_params(itype, jtype, radius[i], radius[j], h, delta);
    if (contact[itype][jtype].rate_on && stored) {          // the contact's R (0: not touched yet, R = 1)
        const double R = stored[history->stride() - NRATE];
        const nfd_params base = p;
        nfd_rate_params(&base, R > 0.0 ? R : 1.0, &p);
    }
    nfd_history next;
    double force = 0.0;
    if (nfd_step(law->code, delta, &p, &contact[itype][jtype].table, &h, &force, &next, nullptr) < 0) force = 0.0;
    fforce = force / r;
    svector[0] = delta;
    svector[1] = force;
    svector[2] = next.delta_max;
    svector[3] = next.P_max;
    svector[4] = next.delta_res;
    return 0.0;
}

/* "nfd/beyond_window": the contacts of this rank counted beyond the window this run (a double,
 * for the library interface); the run's total is in the end-of-run line. */
void *PairNfd::extract(const char *str, int &dim)
{
    dim = 0;
    if (std::strcmp(str, "nfd/beyond_window") == 0) {
        beyond_as_double = (double) beyond_count;
        return &beyond_as_double;
    }
    if (std::strcmp(str, "nfd/below_window") == 0) {
        below_as_double = (double) below_count;
        return &below_as_double;
    }
    return nullptr;
}

void PairNfd::finish()
{
    time_step.end_run(lmp, fmt::format("pair_style {}", name()));
    if (!law->has_window) return;
    bigint total = 0;
    bigint mine = beyond_count;
    MPI_Allreduce(&mine, &total, 1, MPI_LMP_BIGINT, MPI_SUM, world);
    double largest[2] = {beyond_largest, window_of_largest}, all[2];
    // the window that goes with the largest excursion: reduce the pair by its first value
    MPI_Allreduce(&largest[0], &all[0], 1, MPI_DOUBLE, MPI_MAX, world);
    double window = largest[0] == all[0] ? largest[1] : 0.0;
    MPI_Allreduce(&window, &all[1], 1, MPI_DOUBLE, MPI_MAX, world);
    if (comm->me == 0) {
        if (total == 0)
            utils::logmesg(lmp, fmt::format("pair {}: 0 contacts loaded beyond the calibrated window\n", name()));
        else
            utils::logmesg(lmp, fmt::format("pair {}: {} contact(s) loaded beyond the calibrated window (up to "
                                            "P/P_Y = {:.4g}, fitted to P/P_Y <= {:.4g}): the constants are an "
                                            "extrapolation there\n", name(), total, all[0], all[1]));
    }
    report_below_window();
}

/* The contacts that ended below the window's lowest unloading, in one line, when some pair of types
 * has constants whose window states a lower end (P_min/P_Y > 1). */
void PairNfd::report_below_window()
{
    bool stated = false;
    for (int i = 1; i <= ntypes_set; ++i)
        for (int j = i; j <= ntypes_set; ++j) stated = stated || contact[i][j].window_min > 1.0;
    if (!stated) return;          // the same on every rank
    bigint total = 0, mine = below_count;
    MPI_Allreduce(&mine, &total, 1, MPI_LMP_BIGINT, MPI_SUM, world);
    double lowest[2] = {below_lowest, window_min_of_lowest}, all[2];
    MPI_Allreduce(&lowest[0], &all[0], 1, MPI_DOUBLE, MPI_MIN, world);
    double window = lowest[0] == all[0] ? lowest[1] : 0.0;
    MPI_Allreduce(&window, &all[1], 1, MPI_DOUBLE, MPI_MAX, world);
    if (comm->me != 0) return;
    if (total == 0)
        utils::logmesg(lmp, fmt::format("pair {}: 0 contacts unloaded below the calibrated window\n", name()));
    else
        utils::logmesg(lmp, fmt::format("pair {}: {} contact(s) unloaded below the calibrated window (yielded and "
                                        "turned at P/P_Y down to {:.4g}, below the lowest unloading fitted, P/P_Y = "
                                        "{:.4g}): the constants are an extrapolation there\n", name(), total, all[0],
                                        all[1]));
}

uint64_t PairNfd::coeff_fingerprint(int t) const
{
    uint64_t z = law->fingerprint(material[t]);
    for (size_t j = 1; j < explicit_pair[t].size(); ++j)
        if (explicit_pair[t][j]) {
            z = mix64(z ^ static_cast<uint64_t>(j));
            z = mix_double(mix_double(z, contact[t][j].K1), contact[t][j].K2);
        }
    // the constants calibrated for a pair (Ca_hat, Kc_hat, the tables), as the law fingerprints a type's
    for (size_t j = 1; j < calibrated[t].size(); ++j)
        if (calibrated[t][j]) z = mix64(z ^ mix64(static_cast<uint64_t>(j) + 0x70616972ULL) ^
                                        law->fingerprint(pair_constants[t][j]));
    return z;
}

void PairNfd::allocate()
{
    allocated = 1;
    const int n = atom->ntypes;
    memory->create(setflag, n + 1, n + 1, "pair:setflag");
    for (int i = 1; i <= n; ++i)
        for (int j = i; j <= n; ++j) setflag[i][j] = 0;
    memory->create(cutsq, n + 1, n + 1, "pair:cutsq");
    material.assign(n + 1, NfdMaterial());
    max_radius.assign(n + 1, 0.0);
    contact.assign(n + 1, std::vector<NfdMaterial>(n + 1));
    explicit_pair.assign(n + 1, std::vector<char>(n + 1, 0));
    pair_constants.assign(n + 1, std::vector<NfdMaterial>(n + 1));
    calibrated.assign(n + 1, std::vector<char>(n + 1, 0));
    ntypes_set = n;
    type_pairs.assign((n + 1) * (n + 1), TypePair());
}

void PairNfd::create_history_fix()
{
    if (history) return;
    warn_other_histories();
    Fix *fix = modify->get_fix_by_id(law->history_id);
    if (!fix) fix = modify->add_fix(law->history_id + " all nfd/history");
    history = dynamic_cast<FixNfdHistory *>(fix);
    if (!history) error->all(FLERR, fmt::format("fix {} is not the history of pair_style {}", law->history_id, name()));
    history->pair = this;
}

/* A restart file just read may hold the contact history of another nfd law (fix nfd/history
 * under another law's ID): this law cannot use it (other history values), so its contacts start
 * afresh at their current overlap. Said as a warning when the pair style is set up, rather than
 * only in LAMMPS' list of unused restart data at the next run. */
void PairNfd::warn_other_histories()
{
    if (comm->me != 0 || modify->nfix_restart_peratom == 0) return;
    char **ids = modify->*RestartFixLists::ids();
    char **styles = modify->*RestartFixLists::styles();
    for (int i = 0; i < modify->nfix_restart_peratom; ++i) {
        if (std::strcmp(styles[i], "nfd/history") != 0 || law->history_id == ids[i]) continue;
        const NfdLaw *other = NfdLaw::of_history_id(ids[i]);
        const std::string writer = other ? "pair_style " + other->pair_style : std::string("another pair style");
        const std::string remedy =
            other ? fmt::format(" (to continue them, use pair_style {})", other->pair_style) : "";
        error->warning(FLERR, fmt::format("pair_style {}: the restart file holds the contact history of {} (fix {}), "
                                          "which this pair style does not read: those contacts start afresh at "
                                          "their current overlap{}", name(), writer, ids[i], remedy));
    }
}

/* the stored history of the pair (i, j) when j is in owned atom i's list */
const double *PairNfd::find_stored(int i, int j)
{
    if (!history || !history->ready() || i >= atom->nlocal || !list) return nullptr;
    const int *jlist = list->firstneigh[i];
    for (int jj = 0; jj < list->numneigh[i]; ++jj)
        if ((jlist[jj] & NEIGHMASK) == j) return history->touching(i, jj) ? history->value(i, jj) : nullptr;
    return nullptr;
}

}    // namespace nfdcal_lammps

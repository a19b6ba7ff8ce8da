/* fix_nfd_wall.cpp: fix nfd/wall/<law> (fix_nfd_wall.h).
 *
 * License: GPL-2.0-or-later (see nfd_law.h).
 */
#include "fix_nfd_wall.h"

#include "nfd_energy.h"
#include "nfd_input.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "memory.h"
#include "update.h"
#include "utils.h"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

using namespace LAMMPS_NS;

namespace nfdcal_lammps {

FixNfdWall::FixNfdWall(LAMMPS *lmp, int narg, char **arg, const NfdLaw *law) : FixNfdWall(lmp, narg, arg, law, 5)
{
    const char *geometry = "FACE COORD (FACE one of xlo xhi ylo yhi zlo zhi)";
    if (narg < 5) error->all(FLERR, fmt::format("{}: need {} and the material", who(), geometry));
    const char *faces[] = {"xlo", "xhi", "ylo", "yhi", "zlo", "zhi"};
    int face = -1;
    for (int k = 0; k < 6; ++k)
        if (std::strcmp(arg[3], faces[k]) == 0) face = k;
    if (face < 0)
        error->all(FLERR, fmt::format("{}: FACE out of range: need one of xlo xhi ylo yhi zlo zhi, got '{}'", who(),
                                      arg[3]));
    dim = face / 2;
    side = face % 2 == 0 ? 1.0 : -1.0;
    coord = number_in(lmp, who(), arg[4], "COORD", -INFINITY, true, INFINITY, true, "a finite position [m]");
    read_constants(narg, arg, geometry);
    allocate(1, false);
    counts_below = true;
}

FixNfdWall::FixNfdWall(LAMMPS *lmp, int narg, char **arg, const NfdLaw *law, int first_constant) :
    Fix(lmp, narg, arg), law(law), first(first_constant)
{
    require_si_units(lmp, who());
    forget_params();
}

void FixNfdWall::read_constants(int narg, char **arg, const char *geometry)
{
    if (narg <= first) error->all(FLERR, fmt::format("{}: need {} and the material", who(), geometry));
    std::vector<char *> rest(arg + first, arg + narg);    // the constants and models, without the keywords
    nfd_rate rate{};
    const bool rate_given = take_rate(lmp, who(), law, rest, &rate);     // first: no other keyword's value
    energy = read_energy_keyword(rest);
    const NfdMaterial *pair = read_pair_constants(rest);
    const NfdMaterial *wall = read_wall_material(rest);
    if (pair && !wall)
        error->all(FLERR, fmt::format("{} pair_constants: needs wall_material E_w nu_w, the wall the constants were "
                                      "calibrated on (on a rigid flat the sphere's own constants are the pair's)",
                                      who()));
    const int count = static_cast<int>(rest.size());
    const int models_at = first_model_keyword(count, rest.data());
    material = law->read(lmp, who(), true, models_at, rest.data());
    material.models = read_models(lmp, who(), count - models_at, rest.data() + models_at, !law->per_type_pair);
    // an elastic wall: the pair style's mixing of two bodies, the wall never the one that yields
    if (wall) material = law->mix(material, *wall);
    if (pair) material = NfdLaw::with_pair(material, *pair);
    material.rate_on = rate_given;
    material.rate = rate;
    material.friction = contact_friction(material.models, material.E, material.nu, wall ? wall->E : INFINITY,
                                         wall ? wall->nu : 0.0);
    const bool models = material.models.any();
    width = material.rate_on && material.rate.k > 0.0      // the relaxing form (nfd_energy.h)
        ? record_width(models) + NRATE_RELAXING
        : (energy ? record_width(models) : models ? NHIST + NFRICTION : NHIST) +
            (material.rate_on ? NRATE : 0);    // R last (nfd_energy.h)
}

bool FixNfdWall::read_energy_keyword(std::vector<char *> &rest)
{
    bool found = false;
    for (size_t k = 0; k < rest.size();) {
        // a parameter file may be named energy: `file energy` is its path
        if (std::strcmp(rest[k], "energy") != 0 || (k > 0 && std::strcmp(rest[k - 1], "file") == 0)) {
            ++k;
            continue;
        }
        if (found) error->all(FLERR, fmt::format("{}: energy given twice", who()));
        if (k == 0) error->all(FLERR, fmt::format("{} energy: need the keyword after the law's constants", who()));
        found = true;
        rest.erase(rest.begin() + static_cast<long>(k));
    }
    return found;
}

const NfdMaterial *FixNfdWall::read_wall_material(std::vector<char *> &rest)
{
    const std::string keyword = who() + " wall_material";
    size_t at = 0;
    while (at < rest.size() && std::strcmp(rest[at], "wall_material") != 0) ++at;
    if (at == rest.size()) return nullptr;
    if (law->per_type_pair)
        error->all(FLERR, fmt::format("{}: wall_material applies to the laws of a material (E nu ...), not to the "
                                      "stiffnesses of {}", who(), law->wall_style));
    if (at == 0 || rest.size() < at + 3)
        error->all(FLERR, fmt::format("{}: need the keyword after the law's constants, followed by E_w [Pa] and "
                                      "nu_w (the wall's elastic material)", keyword));
    for (size_t k = at + 3; k < rest.size(); ++k)
        if (std::strcmp(rest[k], "wall_material") == 0)
            error->all(FLERR, fmt::format("{}: wall_material given twice", who()));
    // E_w and nu_w as the hertz law reads a material (E within the range of solids, 0 <= nu < NU_MAX)
    char *values[2] = {rest[at + 1], rest[at + 2]};
    wall = NfdLaw::of(NFD_LAW_HERTZ)->read(lmp, keyword, true, 2, values);
    wall.p_Y = INFINITY;             // elastic: first yield is the sphere's
    rest.erase(rest.begin() + static_cast<long>(at), rest.begin() + static_cast<long>(at) + 3);
    return &wall;
}

const NfdMaterial *FixNfdWall::read_pair_constants(std::vector<char *> &rest)
{
    const std::string keyword = who() + " pair_constants";
    size_t at = 0;
    while (at < rest.size() && std::strcmp(rest[at], "pair_constants") != 0) ++at;
    if (at == rest.size()) return nullptr;
    if (at == 0) error->all(FLERR, fmt::format("{}: need the keyword after the law's constants", keyword));
    // its values run up to the next keyword: wall_material or a contact model
    size_t end = at + 1;
    while (end < rest.size() && std::strcmp(rest[end], "wall_material") != 0 &&
           std::strcmp(rest[end], "pair_constants") != 0 && first_model_keyword(1, &rest[end]) == 1)
        ++end;
    for (size_t k = end; k < rest.size(); ++k)
        if (std::strcmp(rest[k], "pair_constants") == 0)
            error->all(FLERR, fmt::format("{}: pair_constants given twice", who()));
    pair = law->read_pair(lmp, keyword, static_cast<int>(end - at - 1), rest.data() + at + 1);
    // constants calibrated on a flat that yields first are relative to the flat's P_Y; this wall is
    // elastic and its contact yields in the sphere (nfdcal export lammps refuses such a file alike)
    if (pair.counter_flat && !nfd_yields_first(pair.p_Y, pair.counter_p_Y))
        error->all(FLERR, fmt::format("{}: parameter file {}: its flat counter-body yields before the sphere "
                                      "(A_Y(nu) sigma_y = {:.4g} Pa below the sphere's {:.4g} Pa), so its constants "
                                      "are relative to the flat's P_Y; the plugin's walls are elastic and their "
                                      "contacts yield in the sphere: not supported", keyword, rest[at + 2],
                                      pair.counter_p_Y, pair.p_Y));
    rest.erase(rest.begin() + static_cast<long>(at), rest.begin() + static_cast<long>(end));
    return &pair;
}

void FixNfdWall::allocate(int slots_per_atom, bool tag_slots)
{
    slots = slots_per_atom;
    tagged = tag_slots;
    stride = width + (tagged ? 1 : 0);
    row = slots * stride;
    scalar_flag = 1;
    global_freq = 1;
    extscalar = 1;
    vector_flag = 1;
    size_vector = 1;
    extvector = 1;
    peratom_flag = 1;
    size_peratom_cols = row;
    peratom_freq = 1;
    create_attribute = 1;
    maxexchange = row;
    restart_peratom = 1;
    FixNfdWall::grow_arrays(atom->nmax);
    atom->add_callback(Atom::GROW);
    atom->add_callback(Atom::RESTART);
    for (int i = 0; i < atom->nmax; ++i) FixNfdWall::set_arrays(i);
}

FixNfdWall::~FixNfdWall()
{
    if (!history) return;         // a constructor stopped before the store
    atom->delete_callback(id, Atom::GROW);
    atom->delete_callback(id, Atom::RESTART);
    memory->destroy(history);
}

int FixNfdWall::setmask() { return FixConst::POST_FORCE | FixConst::MIN_POST_FORCE | FixConst::POST_RUN; }

void FixNfdWall::init()
{
    require_si_units(lmp, who());
    if (!atom->radius_flag || !atom->rmass_flag)
        error->all(FLERR, fmt::format("{} needs per-atom radius and mass: use atom_style sphere", who()));
    if (std::strncmp(update->integrate_style, "respa", 5) == 0)
        error->all(FLERR, fmt::format("{}: run_style {} is not supported: use run_style verlet (the plugin has "
                                      "no access to the rRESPA force levels)", who(), update->integrate_style));
    if (material.models.any() && (!atom->omega_flag || !atom->torque_flag))
        error->all(FLERR, fmt::format("{} with contact models needs per-atom spins and torques: use atom_style "
                                      "sphere", who()));
    beyond_count = 0;
    beyond_largest = 0.0;
    below_count = 0;
    below_lowest = INFINITY;
    time_step.begin_run();
    forget_params();              // the constants are read again when a run starts
}

void FixNfdWall::post_force(int /*vflag*/)
{
    double **x = atom->x;
    double *radius = atom->radius;
    int *mask = atom->mask;
    const double still[3] = {0.0, 0.0, 0.0};
    double n[3] = {0.0, 0.0, 0.0};
    n[dim] = side;
    begin_forces();
    for (int i = 0; i < atom->nlocal; ++i) {
        if (!(mask[i] & groupbit)) continue;
        double *stored = history[i];
        const double delta = radius[i] - side * (x[i][dim] - coord);
        if (!(delta > 0.0)) {              // off the wall: the contact (if any) is over
            // a record stays all zeros until a contact step, which sets delta_max >= delta > 0
            if (!held[i]) continue;
            if (stored[1] > 0.0) count_below_window(stored, radius[i]);
            for (int k = 0; k < width; ++k) stored[k] = 0.0;
            held[i] = 0;
            continue;
        }
        contact(i, delta, n, radius[i], still, stored);
        note_held(i);
    }
    end_forces();
}

const nfd_params &FixNfdWall::contact_params(double R_star)
{
    uint64_t bits;
    std::memcpy(&bits, &R_star, sizeof bits);
    const size_t mask = remembered_keys.size() - 1;
    for (size_t at = mix64(bits) & mask; remembered_keys[at].index != 0; at = (at + 1) & mask)
        if (remembered_keys[at].bits == bits) return remembered_params[remembered_keys[at].index - 1];
    return remember_params(R_star, bits);
}

/* A radius contact_params has not met: its nfd_params computed and entered. The table keeps at most
 * half its slots filled (doubling), and starts afresh past 2^16 radii (a region of varying shape meets
 * new curvatures without end). */
const nfd_params &FixNfdWall::remember_params(double R_star, uint64_t bits)
{
    constexpr size_t MOST = size_t(1) << 16;
    if (remembered_params.size() >= MOST) forget_params();
    if (2 * (remembered_params.size() + 1) > remembered_keys.size()) {
        std::vector<RememberedKey> keys(2 * remembered_keys.size(), RememberedKey{0, 0});
        const size_t mask = keys.size() - 1;
        for (const RememberedKey &key : remembered_keys) {
            if (key.index == 0) continue;
            size_t at = mix64(key.bits) & mask;
            while (keys[at].index != 0) at = (at + 1) & mask;
            keys[at] = key;
        }
        remembered_keys.swap(keys);
    }
    remembered_params.push_back(law->params(R_star, material));
    const size_t mask = remembered_keys.size() - 1;
    size_t at = mix64(bits) & mask;
    while (remembered_keys[at].index != 0) at = (at + 1) & mask;
    remembered_keys[at] = RememberedKey{bits, remembered_params.size()};
    return remembered_params.back();
}

void FixNfdWall::forget_params()
{
    remembered_keys.assign(64, RememberedKey{0, 0});
    remembered_params.clear();
}

void FixNfdWall::begin_forces()
{
    total_local = 0.0;
    touching_local = 0.0;
}

void FixNfdWall::contact(int i, double delta, const double *n, double R_star, const double *v_wall, double *stored)
{
    double **f = atom->f;
    touching_local += 1.0;
    const nfd_params &remembered = contact_params(R_star);
    nfd_params scaled;                         // the rate-aware law's: the remembered ones at sigma_Y R
    if (material.rate_on) {
        scaled = remembered;
        rate_params(i, delta, n, v_wall, stored, scaled);
    }
    const nfd_params &p = material.rate_on ? scaled : remembered;
    const nfd_history h = load_history(stored);
    if (h.delta_max == 0.0) {        // the contact's first step: its duration against the timestep
        double v_n = 0.0;
        for (int d = 0; d < 3; ++d) v_n += (atom->v[i][d] - v_wall[d]) * n[d];
        time_step.see(lmp, fmt::format("fix {} ({})", id, style),
                      law->contact_time(p, atom->rmass[i], std::fabs(v_n)), std::fabs(v_n));
    }
    nfd_history next;
    double force = 0.0;
    nfd_contact_result out;
    int status;
    const bool models = material.models.any();
    if (models) {       // the sphere on a rigid wall (R_j = 0: arm R_i, no torque on the wall)
        nfd_contact c;
        for (int d = 0; d < 3; ++d) {
            c.n[d] = n[d];
            c.v[d] = atom->v[i][d] - v_wall[d];
            c.omega_i[d] = atom->omega[i][d];
            c.omega_j[d] = 0.0;
        }
        c.delta = delta;
        c.R_i = atom->radius[i];
        c.R_j = 0.0;
        c.m_star = atom->rmass[i];
        c.dt = update->dt;
        const nfd_friction_history springs = load_friction(stored + NHIST, 1.0);
        nfd_friction_history springs_next;
        status = nfd_contact_step(law->code, &c, &p, &material.table, &material.friction, &h, &springs,
                                  update->setupflag ? 0 : 1, &next, &springs_next, &out);
        if (status >= 0) store_friction(springs_next, 1.0, stored + NHIST);
        if (status >= 0 && energy) {
            double dr[3], turn[3];
            const double still[3] = {0.0, 0.0, 0.0};
            for (int d = 0; d < 3; ++d) {
                dr[d] = c.dt * c.v[d];
                turn[d] = c.dt * c.omega_i[d];
            }
            ContactEnergy::models_step(stored + NHIST + NFRICTION, law->code, delta, next, out, material.friction,
                                       springs_next, n, dr, turn, still, 1.0, !update->setupflag);
        }
        force = out.F_n;
    } else {
        status = nfd_step(law->code, delta, &p, &material.table, &h, &force, &next, nullptr);
        if (status >= 0 && energy) {
            double dr[3];
            for (int d = 0; d < 3; ++d) dr[d] = update->dt * (atom->v[i][d] - v_wall[d]);
            ContactEnergy::law_step(stored + NHIST, law->code, delta, next, force, n, dr, 1.0, !update->setupflag);
        }
    }
    if (status == NFD_FULL_CONTACT)
        error->one(FLERR, fmt::format("{}: atom {} reached full contact with the wall at overlap {:.6g} m "
                                      "(delta/R = {:.4g}): the law's contact radius reaches R", who(),
                                      atom->tag[i], delta, delta / atom->radius[i]));
    if (status == NFD_NOT_FINITE)
        error->one(FLERR, fmt::format("{}: the wall force on atom {} is not a finite number (overlap {:.6g} m)",
                                      who(), atom->tag[i], delta));
    if (status == NFD_BEYOND_WINDOW) {
        if (h.P_max <= p.window_P_max) ++beyond_count;
        beyond_largest = std::max(beyond_largest, next.P_max / p.P_Y);
    }
    store_history(next, stored);
    for (int d = 0; d < 3; ++d) f[i][d] += models ? out.force[d] : n[d] * force;
    if (models)
        for (int d = 0; d < 3; ++d) atom->torque[i][d] += out.torque_i[d];
    total_local += force;
}

double FixNfdWall::compute_scalar()
{
    if (!total_reduced) {
        MPI_Allreduce(&total_local, &total, 1, MPI_DOUBLE, MPI_SUM, world);
        total_reduced = true;
    }
    return total;
}

/* 1: the contacts with the wall, each holding a history (a plane: the atoms touching it) */
double FixNfdWall::compute_vector(int /*n*/)
{
    double all = 0.0;
    MPI_Allreduce(&touching_local, &all, 1, MPI_DOUBLE, MPI_SUM, world);
    return all;
}

/* A contact that ends (off the wall) after it yielded and turned below the lowest unloading load of
 * the window, P_Y < P_max < P_min (nfdmodel.collide's outside the calibrated range): counted. */
void FixNfdWall::count_below_window(const double *stored, double R_star)
{
    if (!law->has_window || !(material.window_min > 1.0)) return;
    double P_Y = contact_params(R_star).P_Y;
    const double P_max = load_history(stored).P_max, R = material.rate_on ? stored[width - NRATE] : 0.0;
    if (R > 0.0) P_Y *= R * R * R;                   // the rate-aware law: P_Y R^3
    if (P_max > P_Y * (1.0 + 1e-9) && P_max < material.window_min * P_Y * (1.0 - 1e-9)) {
        ++below_count;
        below_lowest = std::min(below_lowest, P_max / P_Y);
    }
}

void FixNfdWall::post_run()
{
    time_step.end_run(lmp, fmt::format("fix {} ({})", id, style));
    if (!law->has_window) return;
    bigint mine = beyond_count, all = 0;
    MPI_Allreduce(&mine, &all, 1, MPI_LMP_BIGINT, MPI_SUM, world);
    double largest = 0.0;
    MPI_Allreduce(&beyond_largest, &largest, 1, MPI_DOUBLE, MPI_MAX, world);
    if (comm->me == 0) {
        if (all == 0)
            utils::logmesg(lmp, fmt::format("fix {} ({}): 0 contacts loaded beyond the calibrated window\n", id,
                                            style));
        else
            utils::logmesg(lmp, fmt::format("fix {} ({}): {} contact(s) loaded beyond the calibrated window (up to "
                                            "P/P_Y = {:.4g}, fitted to P/P_Y <= {:.4g}): the constants are an "
                                            "extrapolation there\n", id, style, all, largest, material.window));
    }
    if (!counts_below || !(material.window_min > 1.0)) return;
    mine = below_count;
    MPI_Allreduce(&mine, &all, 1, MPI_LMP_BIGINT, MPI_SUM, world);
    double lowest = INFINITY;
    MPI_Allreduce(&below_lowest, &lowest, 1, MPI_DOUBLE, MPI_MIN, world);
    if (comm->me != 0) return;
    if (all == 0)
        utils::logmesg(lmp, fmt::format("fix {} ({}): 0 contacts unloaded below the calibrated window\n", id, style));
    else
        utils::logmesg(lmp, fmt::format("fix {} ({}): {} contact(s) unloaded below the calibrated window (yielded "
                                        "and turned at P/P_Y down to {:.4g}, below the lowest unloading fitted, P/P_Y "
                                        "= {:.4g}): the constants are an extrapolation there\n", id, style, all,
                                        lowest, material.window_min));
}

void FixNfdWall::grow_arrays(int nmax)
{
    memory->grow(history, nmax, row, "nfd/wall:history");
    array_atom = history;
    held.resize(nmax, 0);
}

void FixNfdWall::copy_arrays(int i, int j, int /*delflag*/)
{
    for (int n = 0; n < row; ++n) history[j][n] = history[i][n];
    held[j] = held[i];
}

void FixNfdWall::set_arrays(int i)
{
    for (int n = 0; n < row; ++n) history[i][n] = 0.0;
    held[i] = 0;
}

int FixNfdWall::pack_exchange(int i, double *buf)
{
    for (int n = 0; n < row; ++n) buf[n] = history[i][n];
    return row;
}

int FixNfdWall::unpack_exchange(int nlocal, double *buf)
{
    for (int n = 0; n < row; ++n) history[nlocal][n] = buf[n];
    note_held(nlocal);
    return row;
}

/* Restart files: per atom [row + 1, the row values]; read_restart keeps the values of every fix
 * in atom->extra[i] one after the other, each led by its own length. A record of another width (a
 * file written with or without contact models) gives, slot by slot, what both hold: the springs
 * of a frictionless file start at zero. */
int FixNfdWall::pack_restart(int i, double *buf)
{
    buf[0] = row + 1;
    for (int n = 0; n < row; ++n) buf[n + 1] = history[i][n];
    return row + 1;
}

void FixNfdWall::unpack_restart(int nlocal, int nth)
{
    const double *extra = atom->extra[nlocal];
    int m = 0;
    for (int k = 0; k < nth; ++k) m += static_cast<int>(extra[m]);
    const int written = static_cast<int>(extra[m]) - 1;
    const int written_stride = written % slots == 0 ? written / slots : 0;    // another layout: dropped
    const int lead = tagged ? 1 : 0;
    for (int s = 0; s < slots; ++s) {
        double *slot = history[nlocal] + s * stride;
        if (written_stride <= lead) {
            for (int n = 0; n < stride; ++n) slot[n] = 0.0;
            continue;
        }
        const double *from = &extra[m + 1 + s * written_stride];
        if (tagged) slot[0] = from[0];
        ContactEnergy::restride(from + lead, written_stride - lead, slot + lead, width);
    }
    note_held(nlocal);
}

double FixNfdWall::memory_usage() { return (double) atom->nmax * (row * sizeof(double) + 1); }

}    // namespace nfdcal_lammps

/* pair_nfd.h: pair_style nfd/<law> (nfd/hertz, nfd/vz, nfd/thornton, nfd/vz-table,
 * nfd/walton-braun): one class for every law, the law an NfdLaw (nfd_law.h).
 *
 *     pair_style nfd/vz
 *     pair_coeff I I E nu sigma_y Ca_hat Kc_hat [window P_max/P_Y] [rate ...] [damping ...] [tangential ...]
 *                [rolling ...] [twisting ...]         (rate: the rate-aware law, nfd_rate_contact.cpp)
 *     pair_coeff I J Ca_hat Kc_hat [window P_max/P_Y]    (I != J: constants calibrated for that pair)
 *
 * The normal force of each touching pair of spheres is the law's step of the C kernel
 * (nfd_step); with the contact models of nfd_models.h (LAMMPS's granular keywords) the contact
 * is nfd_contact_step, with damping, friction, rolling and twisting resistance and torques.
 * Without them: frictionless, undamped, no torque. The history lives in fix nfd/history, with each
 * contact's forces and dissipated energies (nfd_energy.h; compute pair/local p6-p10, single()) in the
 * runs that define a compute pair/local (energy_on).
 * Granular spheres (atom_style sphere), SI units, newton off (each rank computes every contact
 * of one of its atoms, so both copies of a contact across a subdomain boundary evolve alike).
 *
 * License: GPL-2.0-or-later (see nfd_law.h).
 */
#ifndef NFD_LAMMPS_PAIR_NFD_H
#define NFD_LAMMPS_PAIR_NFD_H

#include "nfd_energy.h"
#include "nfd_time_step.h"
#include "pair.h"

#include <string>
#include <vector>

namespace nfdcal_lammps {

class FixNfdHistory;

class PairNfd : public LAMMPS_NS::Pair {
 public:
    PairNfd(LAMMPS_NS::LAMMPS *lmp, const NfdLaw *law);
    ~PairNfd() override;

    void settings(int narg, char **arg) override;
    void coeff(int narg, char **arg) override;
    void init_style() override;
    double init_one(int i, int j) override;
    void compute(int eflag, int vflag) override;
    double single(int i, int j, int itype, int jtype, double rsq, double factor_coul, double factor_lj,
                  double &fforce) override;
    void *extract(const char *str, int &dim) override;
    void finish() override;

    const char *name() const { return law->pair_style.c_str(); }
    FixNfdHistory *contact_history() const { return history; }

    /* A 64-bit fingerprint of atom type t's pair_coeff (NfdLaw::fingerprint) and of each explicit
     * pair_coeff t J (J and its constants: walton-braun's stiffnesses, a calibrated pair's
     * constants): kept with the histories in restart files. */
    uint64_t coeff_fingerprint(int t) const;

 private:
    void allocate();
    void calibrated_pair_coeff(const std::string &who, int narg, char **arg, int ilo, int ihi, int jlo, int jhi);
    void check_status(int status, int i, int j, double delta, const nfd_params &p, const nfd_history &h,
                      const nfd_history &next);
    void contact_with_models(int i, int j, double delx, double dely, double delz, double r, const NfdMaterial &c,
                             const nfd_params &p, double *stored);
    void count_below_window(int i, int j, const double *stored);
    void law_energy(int i, int j, double delx, double dely, double delz, double r, double delta,
                    const nfd_history &next, double force, double *stored);
    void see_contact_start(int i, int j, double delx, double dely, double delz, double r, const nfd_params &p);
    void report_below_window();
    void create_history_fix();
    void warn_other_histories();
    const double *find_stored(int i, int j);
    nfd_params contact_params(int itype, int jtype, double R_i, double R_j, const nfd_history &h, double delta) const;
    /* The rate-aware law (nfd_rate_contact.cpp): p, the contact's base nfd_params, scaled to sigma_Y R,
     * R the record's last double, fixed at the first touch from the normal approach speed. */
    void rate_params(int i, int j, double delx, double dely, double delz, double r, double delta,
                     const NfdMaterial &c, double *stored, nfd_params &p);

    /* What a contact of two atom types takes from its types, set in init_one: the nfd_params at
     * R* = 1 m (NfdLaw::params(1.0, ...); nfd_pair_scaled gives a contact's from them) and the
     * contact constants (NfdLaw::mix or pair_coeff I J) with their models. */
    struct TypePair {
        nfd_params unit{};
        const NfdMaterial *constants = nullptr;
        bool models = false;
    };
    const TypePair &type_pair(int itype, int jtype) const { return type_pairs[itype * (ntypes_set + 1) + jtype]; }

    const NfdLaw *law;
    std::vector<NfdMaterial> material;                 // per atom type, as read
    std::vector<std::vector<NfdMaterial>> contact;     // per pair of types: NfdLaw::mix, or pair_coeff I J
    std::vector<std::vector<char>> explicit_pair;      // set by pair_coeff I J (per-type-pair laws)
    std::vector<std::vector<NfdMaterial>> pair_constants;   // pair_coeff I J of a law of materials (read_pair)
    std::vector<std::vector<char>> calibrated;         // ... set for this pair of types
    std::vector<double> max_radius;                    // per atom type, pour/deposit included
    std::vector<TypePair> type_pairs;                  // (ntypes + 1)^2, row-major (type_pair)
    int ntypes_set = 0;
    FixNfdHistory *history = nullptr;
    bool models_on = false;                            // contact models on some pair of types
    bool rate_on = false;                              // the rate keyword on some type: records end with R
    bool energy_on = true;                             // the energy block kept this run (init_style)
    LAMMPS_NS::bigint beyond_count = 0;
    double beyond_largest = 0.0, window_of_largest = 0.0, beyond_as_double = 0.0;
    LAMMPS_NS::bigint below_count = 0;                 // contacts ended below the window's lowest unloading
    double below_lowest = INFINITY, window_min_of_lowest = 0.0, below_as_double = 0.0;
    NfdTimeStep time_step;                             // the contacts' durations against the timestep
};

}    // namespace nfdcal_lammps

#endif

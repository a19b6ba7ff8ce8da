/* nfd_models.h: the contact models after a style's constants (nfd_friction.h of the kernel), in
 * the order and meaning of LAMMPS's pair_style granular keywords, each optional (default: none,
 * the normal law alone):
 *
 *     [damping viscoelastic c | damping tsuji e | damping coeff_restitution e]
 *     [tangential mindlin|mindlin_rescale|mindlin/force|mindlin_rescale/force k_t|NULL x_gamma_t mu]
 *     [rolling sds k_roll gamma_roll mu_roll]
 *     [twisting marshall | twisting sds k_twist gamma_twist mu_twist]
 *
 * c [1/(m s)], e the restitution (the damping prefactor's constant: nfd_damping_coefficient);
 * k_t [Pa] (stiffness k_t a), NULL: 8 G* of the two materials; x_gamma_t [-]; mu [-]; k_roll
 * [N/m], gamma_roll [N s/m], mu_roll [-]; k_twist [N m/rad], gamma_twist [N m s/rad], mu_twist [m].
 * Unlike types mix as LAMMPS's granular does: the same models on both, each constant the
 * geometric mean sqrt(a b); k_t NULL on either: 8 G* of the two materials, G* = 1 / ((2 - nu_i)/G_i
 * + (2 - nu_j)/G_j). (LAMMPS's granular takes 8 G of its mixed hertz/material modulus there, which
 * treats the effective modulus as a material's: for two types of one material 1 / (2 (1 - nu^2)) of
 * the like-type k_t, 0.55 at nu = 0.3. The physical G* keeps types of one material alike.)
 *
 * License: GPL-2.0-or-later (see nfd_law.h).
 */
#ifndef NFD_LAMMPS_MODELS_H
#define NFD_LAMMPS_MODELS_H

#include "../nfd_friction.h"

#include <string>

namespace LAMMPS_NS {
class LAMMPS;
}

namespace nfdcal_lammps {

struct NfdModels {
    int damping = NFD_DAMPING_NONE;
    double damping_value = 0.0;
    int tangential = NFD_TANGENTIAL_NONE;
    double k_t = -1.0;              // -1: NULL, 8 G* of the materials
    double x_gamma_t = 0.0, mu = 0.0;
    int rolling = NFD_ROLLING_NONE;
    double k_roll = 0.0, gamma_roll = 0.0, mu_roll = 0.0;
    int twisting = NFD_TWISTING_NONE;
    double k_twist = 0.0, gamma_twist = 0.0, mu_twist = 0.0;

    /* any model on: the contact needs velocities, torques and the friction history */
    bool any() const
    {
        return damping != NFD_DAMPING_NONE || tangential != NFD_TANGENTIAL_NONE || rolling != NFD_ROLLING_NONE ||
            twisting != NFD_TWISTING_NONE;
    }
    bool same_kinds(const NfdModels &o) const
    {
        return damping == o.damping && tangential == o.tangential && rolling == o.rolling && twisting == o.twisting;
    }
    /* "damping tsuji, tangential mindlin" (the kinds on), or "none": for messages */
    std::string kinds() const;
};

/* The position of the first model keyword in arg[0..narg), or narg: what comes before belongs to
 * the law's constants. */
int first_model_keyword(int narg, char **arg);

/* The models of arg[0..narg) (from a keyword on), each value checked against its range, or an
 * error naming it; who starts every message ("pair_coeff for nfd/vz"); materials: the law has E
 * and nu (else k_t NULL is refused). */
NfdModels read_models(LAMMPS_NS::LAMMPS *lmp, const std::string &who, int narg, char **arg, bool materials);

/* The models of a contact of two bodies of the same kinds (checked by the caller): the geometric
 * mean of each constant (equal constants are kept as they are). */
NfdModels mix_models(const NfdModels &a, const NfdModels &b);

/* The kernel's nfd_friction of a contact with models m between bodies (E_i, nu_i) and (E_j,
 * nu_j) [Pa, -] (a rigid flat: E_j = INFINITY), for k_t NULL: 8 G* of the two bodies
 * (nfd_shear_coefficient). */
nfd_friction contact_friction(const NfdModels &m, double E_i, double nu_i, double E_j, double nu_j);

}    // namespace nfdcal_lammps

#endif

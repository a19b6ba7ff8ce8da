/* nfd_law.h: what differs between the laws of the plugin, one class per law (nfd_law.cpp).
 *
 * A law (NfdLaw::of(NFD_LAW_VZ), ...) knows its LAMMPS names (pair_style nfd/<name>, fix
 * nfd/wall/<name>, the ID of its history fix), reads its constants from a pair_coeff or wall-fix
 * line, mixes two bodies' constants into a contact's, builds the contact's nfd_params for the C
 * kernel and fingerprints its constants for restart files. Everything else (neighbor lists,
 * history, restart, MPI) is the same for every law and lives in PairNfd, FixNfdWall and
 * FixNfdHistory, which call the kernel's one dispatch nfd_step(law->code, ...).
 *
 * License: GPL-2.0-or-later (the plugin loads into LAMMPS through its plugin interface and public
 * headers; it contains no LAMMPS source code).
 */
#ifndef NFD_LAMMPS_LAW_H
#define NFD_LAMMPS_LAW_H

#include "nfd_models.h"

#include "../nfd_rate.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>

namespace LAMMPS_NS {
class LAMMPS;
}

namespace nfdcal_lammps {

constexpr int NHIST = 5;    // the doubles of an nfd_history, as stored per contact and per atom
// with contact models: then the nfd_friction_history's (nfd_friction.h), NHIST + NFRICTION in all
constexpr int NFRICTION = NFD_FRICTION_HISTORY;

inline nfd_history load_history(const double *v) { return nfd_history{v[0], v[1], v[2], v[3], v[4]}; }

inline void store_history(const nfd_history &h, double *v)
{
    v[0] = h.delta_max;
    v[1] = h.P_max;
    v[2] = h.delta_res;
    v[3] = h.K_u;
    v[4] = h.a_e_max;
}

/* The springs stored after the normal history (v + NHIST); the tangential one as seen from the
 * atom of the lower ID (sign = +1 when atom i has it, else -1), so that both atoms of a contact,
 * on any rank and in either order of a neighbor list, hold the same numbers. */
inline nfd_friction_history load_friction(const double *v, double sign)
{
    return nfd_friction_history{{sign * v[0], sign * v[1], sign * v[2]}, {v[3], v[4], v[5]}, v[6], v[7]};
}

inline void store_friction(const nfd_friction_history &h, double sign, double *v)
{
    for (int k = 0; k < 3; ++k) {
        v[k] = sign * h.xi_t[k];
        v[3 + k] = h.xi_roll[k];
    }
    v[6] = h.theta_twist;
    v[7] = h.a_previous;
}

/* One atom type's (or a wall fix's sphere's) constants, or a contact's after NfdLaw::mix:
 * E [Pa], nu, sigma_y [Pa]; p_Y = A_Y(nu) sigma_Y [Pa] (nfd_yield_factor); E_star [Pa]: one
 * body's E / (1 - nu^2) (its E* on a rigid flat), a contact's E* after mixing; the vz constants
 * Ca_hat, Kc_hat; the vz-table tables (x = P/P_Y, a_p/a_Y, C_R: dimensionless, so they hold for
 * any pair); the window P_max/P_Y and its lower end P_min/P_Y; the Walton-Braun stiffnesses
 * K1 <= K2 [N/m]; the contact models after the constants (nfd_models.h) and, for a contact (or a
 * wall), their kernel form; the rate law (nfd_rate.h), when given. */
struct NfdMaterial {
    double E = 0, nu = 0, sigma_y = 0, p_Y = 0, E_star = 0, Ca_hat = 0, Kc_hat = 0, window = INFINITY;
    double window_min = 1.0;
    double K1 = 0, K2 = 0;
    // a parameter file's counter_body: a flat one, the yield pressure A_Y(nu) sigma_y [Pa] of its
    // counter-body (inf: elastic, or none stated)
    bool counter_flat = false;
    double counter_p_Y = INFINITY;
    nfd_table table{};
    NfdModels models;
    nfd_friction friction{};
    // `rate ...` (nfd_rate_input.cpp): the rate-aware law on this (vz or vz-table) law, sigma_Y R(eps_dot)
    // with R fixed at first contact (nfd_rate.h); a contact takes the yielding body's with its constants
    bool rate_on = false;
    nfd_rate rate{};
};

/* A 64-bit mixing step (splitmix64), for hashes that only tell equal inputs from different ones. */
inline uint64_t mix64(uint64_t z)
{
    z += 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

/* z folded with the exact bits of a double (0.0 and -0.0, or two roundings, differ). */
inline uint64_t mix_double(uint64_t z, double value)
{
    uint64_t bits;
    std::memcpy(&bits, &value, sizeof(bits));
    return mix64(z ^ bits);
}

class NfdLaw {
 public:
    virtual ~NfdLaw() = default;

    /* The law of an NFD_LAW_* code (nfd_limits.h), or of the ID of a history fix; nullptr if none. */
    static const NfdLaw *of(int code);
    static const NfdLaw *of_history_id(const char *id);

    const int code;                  // NFD_LAW_*: the kernel's nfd_step dispatches on it
    const std::string pair_style;    // "nfd/vz"
    const std::string wall_style;    // "nfd/wall/vz"
    const std::string history_id;    // "NFD_HISTORY_VZ": fixed, so that read_restart finds the history
    const std::string pair_info, wall_info;    // the plugin registry's descriptions
    const bool has_window;           // constants fitted on a load window: loads beyond it are counted
    const bool per_type_pair;        // pair_coeff I J sets a pair of types (else I I, mixed per contact,
                                     // and I J the constants calibrated for a pair: read_pair)

    /* The constants of `pair_coeff I J ...` (wall = false) or of a wall fix after its plane, up to
     * the contact models (read by read_models); who starts every error message ("pair_coeff for
     * nfd/vz", "fix nfd/wall/vz"). */
    virtual NfdMaterial read(LAMMPS_NS::LAMMPS *lmp, const std::string &who, bool wall, int narg,
                             char **arg) const = 0;

    /* The constants calibrated for one pair of unlike bodies (`pair_coeff I J ...` with I != J, a wall
     * fix's `pair_constants ...`): vz Ca_hat Kc_hat [window [P_min] P_max], vz-table file PATH, relative to
     * the pair's P_Y and a_Y (E* of the two bodies in series, R*, first yield in the body with the lower
     * p_Y). The laws without calibrated constants (hertz, thornton, walton-braun) refuse them. */
    virtual NfdMaterial read_pair(LAMMPS_NS::LAMMPS *lmp, const std::string &who, int narg, char **arg) const;

    /* A contact's constants (from mix) with the law's constants of a calibrated pair (read_pair) in
     * place of the yielding body's: Ca_hat, Kc_hat, the tables and the window; E*, p_Y and the models
     * stay the contact's. */
    static NfdMaterial with_pair(const NfdMaterial &contact, const NfdMaterial &pair);

    /* The constants of a contact of bodies a and b (a of the lower type): E* of the two in series
     * (1/E* = 1/E*_a + 1/E*_b) and the constants of the body that yields first, the lower p_Y
     * (a tie: a), as nfdmodel.ContactPair.sphere_sphere. */
    virtual NfdMaterial mix(const NfdMaterial &a, const NfdMaterial &b) const;

    /* The nfd_params of a contact of effective radius R_star [m] with constants c (from mix, or a
     * wall's sphere as read). */
    virtual nfd_params params(double R_star, const NfdMaterial &c) const = 0;

    /* The estimated duration [s] of a contact of nfd_params p and reduced mass m_star [kg] starting at
     * normal speed v [m/s] (NfdTimeStep): Hertz's elastic impact (nfd_hertz_impact_time); Walton-Braun
     * the half periods of its springs. */
    virtual double contact_time(const nfd_params &p, double m_star, double v) const
    {
        return nfd_hertz_impact_time(m_star, p.R_star, p.E_star, v);
    }

    /* The exact bits of the constants the force and the history depend on (not the window, which
     * only flags loads; the contact models when any is on), seeded with the law: equal pair_coeff
     * lines, equal fingerprints. */
    uint64_t fingerprint(const NfdMaterial &m) const;

 protected:
    NfdLaw(int code, const char *name, const char *title, bool has_window, bool per_type_pair);
    /* "types I I", "types I J" or "wall plane": what an argument list follows, for messages */
    const char *after(bool wall) const { return wall ? "wall plane" : (per_type_pair ? "types I J" : "types I I"); }
};

}    // namespace nfdcal_lammps

#endif

/* fix_nfd_wall.h: fix nfd/wall/<law> (nfd/wall/hertz, nfd/wall/vz, nfd/wall/thornton,
 * nfd/wall/vz-table, nfd/wall/walton-braun), a flat wall, rigid or of its own elastic material,
 * with the law of the pair styles.
 *
 *     fix ID group nfd/wall/vz FACE COORD E nu sigma_y Ca_hat Kc_hat [window P_max/P_Y]
 *     fix ID group nfd/wall/walton-braun FACE COORD K1 K2       (the contact's stiffnesses [N/m])
 *     fix ID group nfd/wall/vz-table FACE COORD file params.json
 *     ... [rate johnson-cook C eps_dot_0 | rate cowper-symonds D q]   (vz, vz-table: the rate-aware law,
 *         nfd_rate_contact.cpp; R the last double of each history)
 *     ... [wall_material E_w nu_w]   (the wall's elastic material; absent: a rigid flat)
 *     ... [pair_constants Ca_hat Kc_hat [window W] | pair_constants file pair.json]   (with wall_material:
 *         the constants calibrated for this sphere on this wall, in place of the sphere's)
 *     ... [damping ...] [tangential ...] [rolling ...] [twisting ...]   (nfd_models.h, optional)
 *     ... [energy]   (keep each contact's forces and dissipated energies: the energy block columns)
 *
 * FACE is xlo, xhi, ylo, yhi, zlo or zhi: the plane x = COORD (...) bounding the atoms from below
 * (lo) or above (hi). Each atom of the group is a sphere of its own radius R on a rigid flat, the
 * FE calibration's own setting (nfdmodel.ContactPair.sphere_flat): R* = R, E* = E / (1 - nu^2),
 * first yield in the sphere; overlap delta = R - (distance of the centre from the plane), the
 * force pushes the atom away from the wall along the normal. With contact models (the keywords of
 * nfd_models.h after the constants) the contact is the kernel's nfd_contact_step on a rigid flat
 * (R_j = 0: LAMMPS's fix wall/gran with the sphere's E doubled), with torques, k_t NULL = 8 G /
 * (2 - nu).
 * With wall_material (every law but walton-braun) the wall is an elastic body of E_w [Pa], nu_w:
 * the contact is the pair style's of two unlike bodies (NfdLaw::mix, the wall never yielding;
 * nfdmodel.ContactPair.sphere_wall): 1/E* = (1 - nu^2)/E + (1 - nu_w^2)/E_w, R* as above, first
 * yield in the sphere at the pair's P_Y = (pi A_Y(nu) sigma_Y)^3 R*^2 / (6 E*^2), the sphere's
 * plastic constants, k_t NULL = 8 G* with 1/G* = (2 - nu)/G + (2 - nu_w)/G_w (Johnson 1985
 * section 4.2; README of this folder, Walls of their own material); with pair_constants, the
 * constants calibrated for that sphere on that wall in place of the sphere's (NfdLaw::with_pair).
 * The per-atom history (nfd_history, then the nfd_friction_history) travels with the atom
 * between MPI ranks, goes into restart files (read back by a fix of the same ID and style
 * defined after read_restart) and is zeroed when the sphere leaves the wall.
 *
 * Outputs: the global scalar, the group's total normal force on the wall [N] (extensive); the
 * global vector [1], the atoms touching the wall; the per-atom array of the history: 1 delta_max
 * [m], 2 P_max [N], 3 delta_res [m], 4 K_u, 5 a_e_max [m] (with models also 6-8 the tangential
 * spring, 9-11 the rolling spring [m], 12 the twist angle, 13 the last contact radius [m]), then, with
 * the keyword energy, the energy block (nfd_energy.h; columns 6-10, with models 14-18): F_n [N], |F_t|
 * [N], the plastic, viscous and frictional energy dissipated so far [J], and the block's working
 * values; without it the fix skips that bookkeeping (as the pair style without a compute pair/local). Loads
 * beyond the window are counted and reported at the end of each run like the pair style's, in a
 * line naming the fix's ID and style; the plane wall also counts contacts that end after turning
 * below the window's lowest unloading (window P_min/P_Y P_max/P_Y).
 * The class is also the shared part of the region wall (FixNfdWallRegion, as LAMMPS's fix
 * wall/gran/region extends fix wall/gran): the constants, one contact's force (contact), the
 * per-atom store of `slots` histories per atom, its migration and restart, the outputs.
 * Integrators: run_style verlet and minimization (the force is added after all others,
 * post_force); run_style respa is refused (the wheel ships no respa.h: the plugin cannot reach the
 * rRESPA force levels).
 *
 * License: GPL-2.0-or-later (see nfd_law.h).
 */
#ifndef NFD_LAMMPS_FIX_NFD_WALL_H
#define NFD_LAMMPS_FIX_NFD_WALL_H

#include "fix.h"
#include "nfd_law.h"
#include "nfd_time_step.h"

#include <string>
#include <vector>

namespace nfdcal_lammps {

class FixNfdWall : public LAMMPS_NS::Fix {
 public:
    FixNfdWall(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg, const NfdLaw *law);
    ~FixNfdWall() override;

    int setmask() override;
    void init() override;
    void setup(int vflag) override { post_force(vflag); }
    void min_setup(int vflag) override { post_force(vflag); }
    void min_post_force(int vflag) override { post_force(vflag); }
    void post_force(int vflag) override;
    void post_run() override;
    double compute_scalar() override;
    double compute_vector(int n) override;

    void grow_arrays(int nmax) override;
    void copy_arrays(int i, int j, int delflag) override;
    void set_arrays(int i) override;
    int pack_exchange(int i, double *buf) override;
    int unpack_exchange(int nlocal, double *buf) override;
    int pack_restart(int i, double *buf) override;
    void unpack_restart(int nlocal, int nth) override;
    int size_restart(int /*i*/) override { return row + 1; }
    int maxsize_restart() override { return row + 1; }
    double memory_usage() override;

 protected:
    /* The part every wall fix shares (FixNfdWallRegion), whose constants start at
     * arg[first_constant]: Fix's set-up only; the derived constructor reads its geometry, then
     * calls read_constants and allocate. */
    FixNfdWall(LAMMPS_NS::LAMMPS *lmp, int narg, char **arg, const NfdLaw *law, int first_constant);

    /* "fix nfd/wall/vz", "fix nfd/wall/region/vz": what starts every message */
    std::string who() const { return std::string("fix ") + style; }
    /* The law's constants and contact models from arg[first] on; geometry: what precedes them,
     * for the message of a short line. */
    void read_constants(int narg, char **arg, const char *geometry);
    /* `wall_material E_w nu_w` taken out of rest (the arguments from the first constant on): the
     * wall's elastic material (p_Y infinite), or nullptr without the keyword (a rigid flat). */
    const NfdMaterial *read_wall_material(std::vector<char *> &rest);
    /* `pair_constants ...` taken out of rest: the law's constants calibrated for this sphere on this
     * wall (NfdLaw::read_pair), used in place of the sphere's; nullptr without the keyword. */
    const NfdMaterial *read_pair_constants(std::vector<char *> &rest);
    /* `energy` taken out of rest: the energy block is kept (per-atom columns after the history and
     * springs); without it the fix stores the history and springs alone. */
    bool read_energy_keyword(std::vector<char *> &rest);
    /* The per-atom store: `slots` contacts per atom, each [its facet's tag (tagged only), the
     * width doubles of the history]; registers the per-atom callbacks and the outputs. */
    void allocate(int slots, bool tagged);
    /* One contact of owned atom i with the wall: overlap delta [m] > 0, unit normal n from the wall
     * to the centre, effective radius R_star [m], the wall's velocity at the contact [m/s]; the
     * history (width doubles) advanced in place; force and torques added to the atom. */
    void contact(int i, double delta, const double *n, double R_star, const double *v_wall, double *stored);
    /* Before and after the loop over the atoms: the outputs' sums. */
    void begin_forces();
    /* A contact ending with its history `stored` (R_star [m]): counted when it turned below the
     * window's lowest unloading (the plane wall; a region's ended contact leaves no curvature). */
    void count_below_window(const double *stored, double R_star);
    void end_forces() { total_reduced = false; }
    /* law->params(R_star, material), remembered per R_star (a sphere keeps its radius, so its contacts
     * repeat it): the same numbers, computed once per radius rather than once per contact step. */
    const nfd_params &contact_params(double R_star);
    /* The rate-aware law (nfd_rate_contact.cpp): p, the contact's base nfd_params, scaled to sigma_Y R,
     * R the history's last double, fixed at the first touch from the normal approach speed. */
    void rate_params(int i, double delta, const double *n, const double *v_wall, double *stored, nfd_params &p);

    const NfdLaw *law;
    const int first;              // the index of the first constant in the fix's arguments
    NfdMaterial material;         // the contact's constants: the sphere's, E* with the wall's
    NfdMaterial wall;             // wall_material: E_w, nu_w, E_w / (1 - nu_w^2)
    NfdMaterial pair;             // pair_constants: the constants calibrated for the sphere on this wall
    bool energy = false;          // the energy block kept (keyword energy)
    int width = NHIST;            // doubles per history: with energy record_width(contact models on)
                                  // (nfd_energy.h), else NHIST (+ NFRICTION with models)
    int slots = 1;                // contacts kept per atom
    int stride = NHIST;           // doubles per slot: width, plus a leading tag when tagged
    int row = NHIST;              // doubles per atom: slots * stride
    bool tagged = false;
    double **history = nullptr;   // per atom: row doubles
    /* per atom: history[i][0] != 0.0 (its record holds a contact: the plane wall's delta_max, the region's
     * first facet tag), kept with every write of a record, so that the loop over the atoms reads a byte
     * per atom rather than the first cache line of each record */
    std::vector<unsigned char> held;
    void note_held(int i) { held[i] = history[i][0] != 0.0; }

 private:
    int dim = 2;                  // the wall's normal: 0 x, 1 y, 2 z
    double side = 1.0;            // +1: atoms above the plane (lo), pushed in +dim; -1: hi
    double coord = 0.0;           // the plane [m]
    double total_local = 0.0, total = 0.0, touching_local = 0.0;
    bool total_reduced = false;
    LAMMPS_NS::bigint beyond_count = 0, below_count = 0;
    double beyond_largest = 0.0, below_lowest = INFINITY;
    bool counts_below = false;    // the plane wall counts contacts ended below the window
    NfdTimeStep time_step;        // the contacts' durations against the timestep
    /* contact_params' table: open addressing (linear probing) from the hash of R_star's bits to the
     * index + 1 (0: empty) of its nfd_params in remembered_params */
    struct RememberedKey {
        uint64_t bits;
        size_t index;
    };
    std::vector<RememberedKey> remembered_keys;
    std::vector<nfd_params> remembered_params;
    const nfd_params &remember_params(double R_star, uint64_t bits);
    void forget_params();
};

}    // namespace nfdcal_lammps

#endif

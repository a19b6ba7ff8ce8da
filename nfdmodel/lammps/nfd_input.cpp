/* nfd_input.cpp: the numbers of pair_coeff and wall-fix lines and of nfdcal parameter files
 * (nfd_input.h).
 *
 * License: GPL-2.0-or-later (see nfd_law.h).
 */
#include "nfd_input.h"

#include "../nfd_unload.h"

#include "comm.h"
#include "error.h"
#include "json.h"
#include "lammps.h"
#include "update.h"
#include "utils.h"

#include <mpi.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

using namespace LAMMPS_NS;

namespace nfdcal_lammps {

void require_si_units(LAMMPS *lmp, const std::string &who)
{
    const char *units = lmp->update->unit_style;
    if (units && std::strcmp(units, "si") == 0) return;
    lmp->error->all(FLERR, fmt::format("{}: units {} is not supported: need units si (the laws' constants, their "
                                       "ranges and formulas are SI: Pa, m, kg, s)", who, units ? units : "(none)"));
}

double positive(LAMMPS *lmp, const std::string &who, const char *text, const char *what)
{
    const double value = utils::is_double(text) ? std::strtod(text, nullptr) : NAN;
    if (!(value > 0.0) || !std::isfinite(value))
        lmp->error->all(FLERR, fmt::format("{}: {} out of range: need a finite number > 0, got {}", who, what, text));
    return value;
}

double number_in(LAMMPS *lmp, const std::string &who, const char *text, const char *what, double low, bool low_open,
                 double high, bool high_open, const std::string &range)
{
    // parsed here (not by utils::numeric): text, inf, nan or 1e400 get the line naming the constant
    const double v = utils::is_double(text) ? std::strtod(text, nullptr) : NAN;
    if (!std::isfinite(v) || (low_open ? !(v > low) : !(v >= low)) || (high_open ? !(v < high) : !(v <= high)))
        lmp->error->all(FLERR, fmt::format("{}: {} out of range: need {}, got {}", who, what, range, text));
    return v;
}

double check_solid(LAMMPS *lmp, const std::string &where, const char *name, const std::string &label, double value)
{
    const bool modulus = std::strcmp(name, "E") == 0;
    const double low = modulus ? NFD_E_MIN : NFD_SIGMA_Y_MIN, high = modulus ? NFD_E_MAX : NFD_SIGMA_Y_MAX;
    if (value >= low && value <= high) return value;
    const struct { double factor; const char *unit; } slips[2] = {{modulus ? 1e9 : 1e6, modulus ? "GPa" : "MPa"},
                                                                   {modulus ? 1e6 : 1e3, modulus ? "MPa" : "kPa"}};
    std::string slip;
    for (const auto &s : slips)
        if (slip.empty() && value * s.factor >= low && value * s.factor <= high)
            slip = fmt::format("; did you give {}? {:g} {} = {:g} Pa", s.unit, value, s.unit, value * s.factor);
    lmp->error->all(FLERR, fmt::format("{} {} out of range for a solid: need {:g} <= {} <= {:g} Pa ({} of solids), "
                                       "got {:g}{}", where, label, low, name, high,
                                       modulus ? "Young's modulus" : "yield stress", value, slip));
    return value;
}

/* The largest Kc_hat that nfd_vz_admissible accepts with this Ca_hat, to 1e-6 relative (bisection,
 * as nfdmodel.vz.vz_largest_admissible_Kc; Kc_hat = 0 is admissible for any Ca_hat). */
static double largest_Kc_hat(double Ca_hat)
{
    double low = 0.0, high = NFD_KC_HAT_MAX, load, restitution;
    if (nfd_vz_admissible(Ca_hat, high, &load, &restitution) == NFD_VZ_ADMISSIBLE) return high;
    while (high - low > 1e-6 * high) {
        const double middle = 0.5 * (low + high);
        if (nfd_vz_admissible(Ca_hat, middle, &load, &restitution) == NFD_VZ_ADMISSIBLE) low = middle;
        else high = middle;
    }
    return low;
}

void check_vz_admissible(LAMMPS *lmp, const std::string &who, double Ca_hat, double Kc_hat)
{
    double load, restitution;
    const int code = nfd_vz_admissible(Ca_hat, Kc_hat, &load, &restitution);
    if (code == NFD_VZ_ADMISSIBLE) return;
    const std::string failure =
        code == NFD_VZ_TURNS_BACK
            ? fmt::format("Kc_hat out of range for this Ca_hat: the vz loading curve delta(P) stops increasing near "
                          "P/P_Y = {:.3g}", load)
            : fmt::format("Ca_hat, Kc_hat out of range: the vz law would create energy (restitution {:.4f} > 1) for a "
                          "turning point at P/P_Y = {:.3g}", restitution, load);
    // SI constants typed where the dimensionless ones go: Ca [m/N] of a DEM particle is far below any Ca_hat
    const std::string slip = Ca_hat < 1e-3 ? "; did you give Ca [m/N] and Kc [1/N]? pair_coeff takes Ca_hat = Ca "
                                             "P_Y / a_Y and Kc_hat = Kc P_Y (nfdcal export lammps prints them)" : "";
    lmp->error->all(FLERR, fmt::format("{}: {} (Ca_hat = {:.4g}, Kc_hat = {:.4g}); for Ca_hat = {:.4g} the admissible "
                                       "range is 0 <= Kc_hat <= {:.4g} (loading curve monotone up to P/P_Y = {:g}, no "
                                       "energy created up to {:g}): lower Kc_hat or raise Ca_hat{}", who, failure,
                                       Ca_hat, Kc_hat, Ca_hat, largest_Kc_hat(Ca_hat), NFD_MONOTONE_LOAD_MAX,
                                       NFD_DISSIPATION_LOAD_MAX, slip));
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
                          double high, bool high_open, const std::string &range)
{
    const bool ok = value.is_number() && std::isfinite(value.get<double>());
    const double v = ok ? value.get<double>() : 0.0;
    if (!ok || (low_open ? !(v > low) : !(v >= low)) || (high_open ? !(v < high) : !(v <= high)))
        lmp->error->all(FLERR, fmt::format("{} out of range: need {}, got {}", where, range, value.dump()));
    return v;
}

/* The columns `keys` of the file's object `name` (2..NFD_TABLE_MAX_NODES numbers each, as many in each). */
static std::vector<std::vector<double>> file_columns(LAMMPS *lmp, const std::string &in, const json &data,
                                                     const char *name, const std::vector<const char *> &keys)
{
    if (!data.contains(name) || !data[name].is_object())
        lmp->error->all(FLERR, fmt::format("{} missing '{}' object ({}, {}, {})", in, name, keys[0], keys[1], keys[2]));
    const json &table = data[name];
    std::vector<std::vector<double>> column(keys.size());
    for (size_t k = 0; k < keys.size(); ++k) {
        if (!table.contains(keys[k]) || !table[keys[k]].is_array())
            lmp->error->all(FLERR, fmt::format("{} missing {}.{} (a list of numbers)", in, name, keys[k]));
        const json &nodes = table[keys[k]];
        for (size_t n = 0; n < nodes.size(); ++n)
            column[k].push_back(file_number(lmp, fmt::format("{} {}.{}[{}]", in, name, keys[k], n), nodes[n],
                                            -INFINITY, true, INFINITY, true, "a finite number"));
    }
    const size_t n = column[0].size();
    bool same = true;
    for (const auto &c : column) same = same && c.size() == n;
    if (n < 2 || n > NFD_TABLE_MAX_NODES || !same)
        lmp->error->all(FLERR, fmt::format("{} {} out of range: need 2..{} nodes, the same number in each list, "
                                           "got {} in {}", in, name, NFD_TABLE_MAX_NODES, n, keys[0]));
    return column;
}

NfdMaterial read_parameter_file(LAMMPS *lmp, const std::string &who, const std::string &path,
                                const std::string &law_name)
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
    if (law != law_name)
        lmp->error->all(FLERR, fmt::format("{} law out of range: need '{}', got '{}' (pair_style nfd/{} takes it; a "
                                           "two-constant file: pair_style nfd/vz with the numbers of nfdcal export "
                                           "lammps)", in, law_name, law, law));
    if (!data.contains("material") || !data["material"].is_object())
        lmp->error->all(FLERR, fmt::format("{} missing 'material' object (E, nu, sigma_y)", in));
    const json &material = data["material"];
    for (const char *key : {"E", "nu", "sigma_y"})
        if (!material.contains(key)) lmp->error->all(FLERR, fmt::format("{} missing key material.{}", in, key));
    NfdMaterial mat;
    mat.E = file_number(lmp, in + " material.E [Pa]", material["E"], 0.0, true, INFINITY, true, "a number > 0");
    check_solid(lmp, in, "E", "material.E", mat.E);
    mat.nu = file_number(lmp, in + " material.nu", material["nu"], 0.0, false, NFD_NU_MAX, true,
                         fmt::format("0 <= nu < {:g}", NFD_NU_MAX));
    mat.sigma_y = file_number(lmp, in + " material.sigma_y [Pa]", material["sigma_y"], 0.0, true, INFINITY, true,
                              "a number > 0");
    check_solid(lmp, in, "sigma_y", "material.sigma_y", mat.sigma_y);
    mat.p_Y = nfd_yield_pressure(mat.sigma_y, mat.nu);
    mat.E_star = nfd_plane_strain_modulus(mat.E, mat.nu);
    const auto column = file_columns(lmp, in, data, "table", {"P_over_P_Y", "a_p_over_a_Y", "C_R"});
    const size_t n = column[0].size();
    if (nfd_table_init(&mat.table, static_cast<int>(n), column[0].data(), column[1].data(), column[2].data()) != 0)
        lmp->error->all(FLERR, fmt::format("{} table out of range: need P_over_P_Y[0] = 1 and increasing, "
                                           "a_p_over_a_Y[0] = 0 and non-decreasing, C_R[0] = 1 and > 0", in));
    if (law_name == "vz-unload") {      // the dent and unloading exponent over the turning point
        const auto u = file_columns(lmp, in, data, "unloading", {"P_max_over_P_Y", "dent", "exponent"});
        if (nfd_unload_table_init(&mat.table, static_cast<int>(u[0].size()), u[0].data(), u[1].data(),
                                  u[2].data()) != 0)
            lmp->error->all(FLERR, fmt::format("{} unloading out of range: need P_max_over_P_Y[0] = 1 and "
                                               "increasing, dent[0] = 0 and 0 <= dent < 1, exponent[0] = 1.5 and "
                                               "exponent > 0", in));
    }
    mat.window = column[0][n - 1];
    // the counter-body the file was calibrated on (nfdmodel/parameter_file.py): its shape and yield pressure
    if (data.contains("counter_body") && data["counter_body"].is_object()) {
        const json &counter = data["counter_body"];
        mat.counter_flat = counter.contains("shape") && counter["shape"].is_string() &&
            counter["shape"].get<std::string>() == "flat";
        if (counter.contains("sigma_y") && !counter["sigma_y"].is_null()) {
            const double sigma_y = file_number(lmp, in + " counter_body.sigma_y [Pa]", counter["sigma_y"], 0.0, true,
                                               INFINITY, true, "a number > 0 or null");
            const double nu = counter.contains("nu") ? file_number(lmp, in + " counter_body.nu", counter["nu"], 0.0,
                                                                   false, NFD_NU_MAX, true,
                                                                   fmt::format("0 <= nu < {:g}", NFD_NU_MAX))
                                                     : 0.0;
            mat.counter_p_Y = nfd_yield_pressure(sigma_y, nu);
        }
    }
    if (data.contains("window") && data["window"].is_object() && data["window"].contains("P_min_over_P_Y"))
        mat.window_min = file_number(lmp, in + " window.P_min_over_P_Y", data["window"]["P_min_over_P_Y"], 1.0,
                                     false, 1e8, false, "1 <= P_min/P_Y <= 1e8");
    if (data.contains("window") && data["window"].is_object() && data["window"].contains("P_max_over_P_Y"))
        mat.window = file_number(lmp, in + " window.P_max_over_P_Y", data["window"]["P_max_over_P_Y"], 1.0, false,
                                 1e8, false, "1 <= P_max/P_Y <= 1e8");
    return mat;
}

}    // namespace nfdcal_lammps

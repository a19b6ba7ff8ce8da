/* nfd_input.cpp: the numbers of pair_coeff and wall-fix lines and of nfdcal parameter files
 * (nfd_input.h).
 *
 * License: GPL-2.0-or-later (see nfd_law.h).
 */
#include "nfd_input.h"

#include "comm.h"
#include "error.h"
#include "json.h"
#include "lammps.h"
#include "utils.h"

#include <mpi.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

using namespace LAMMPS_NS;

namespace nfdcal_lammps {

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
    const double v = utils::numeric(FLERR, text, false, lmp);
    if ((low_open ? !(v > low) : !(v >= low)) || (high_open ? !(v < high) : !(v <= high)))
        lmp->error->all(FLERR, fmt::format("{}: {} out of range: need {}, got {}", who, what, range, text));
    return v;
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

NfdMaterial read_parameter_file(LAMMPS *lmp, const std::string &who, const std::string &path)
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
    NfdMaterial mat;
    mat.E = file_number(lmp, in + " material.E [Pa]", material["E"], 0.0, true, INFINITY, true, "a number > 0");
    mat.nu = file_number(lmp, in + " material.nu", material["nu"], 0.0, false, NFD_NU_MAX, true,
                         fmt::format("0 <= nu < {:g}", NFD_NU_MAX));
    mat.sigma_y = file_number(lmp, in + " material.sigma_y [Pa]", material["sigma_y"], 0.0, true, INFINITY, true,
                              "a number > 0");
    mat.p_Y = nfd_yield_factor(mat.nu) * mat.sigma_y;
    mat.E_star = mat.E / (1.0 - mat.nu * mat.nu);
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

}    // namespace nfdcal_lammps

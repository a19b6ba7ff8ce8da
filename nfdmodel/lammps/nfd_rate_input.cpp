/* nfd_rate_input.cpp: the keyword `rate` of the pair styles and wall fixes (nfd_input.h, take_rate).
 *
 * License: GPL-2.0-or-later (see nfd_law.h).
 */
#include "nfd_input.h"

#include "error.h"
#include "lammps.h"
#include "utils.h"

#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;

namespace nfdcal_lammps {

bool take_rate(LAMMPS *lmp, const std::string &who, const NfdLaw *law, std::vector<char *> &rest, nfd_rate *rate)
{
    const std::string keyword = who + " rate";
    size_t at = 1;
    while (at < rest.size() && (std::strcmp(rest[at], "rate") != 0 || std::strcmp(rest[at - 1], "file") == 0)) ++at;
    if (at >= rest.size()) {
        if (!rest.empty() && std::strcmp(rest[0], "rate") == 0)
            lmp->error->all(FLERR, fmt::format("{}: need the keyword after the law's constants", keyword));
        return false;
    }
    if (law->code != NFD_LAW_VZ && law->code != NFD_LAW_VZ_TABLE)
        lmp->error->all(FLERR, fmt::format("{}: the rate-aware law needs a law whose constants scale with sigma_Y: "
                                           "nfd/vz or nfd/vz-table, not {}", keyword, law->pair_style));
    const char *usage = "johnson-cook C eps_dot_0 [c C_LENGTH] [relaxing K] or cowper-symonds D q [c C_LENGTH] "
                        "[relaxing K]";
    if (at + 3 >= rest.size())
        lmp->error->all(FLERR, fmt::format("{}: need {} ({} value(s) after the keyword)", keyword, usage,
                                           rest.size() - at - 1));
    const char *model = rest[at + 1];
    int code;
    double first, second;
    if (std::strcmp(model, "johnson-cook") == 0) {
        code = NFD_RATE_JOHNSON_COOK;
        first = number_in(lmp, keyword + " johnson-cook", rest[at + 2], "C", 0.0, false, INFINITY, true,
                          "a finite number C >= 0 (the rate constant)");
        second = number_in(lmp, keyword + " johnson-cook", rest[at + 3], "eps_dot_0", 0.0, true, INFINITY, true,
                           "a finite number eps_dot_0 > 0 [1/s] (the reference strain rate)");
    } else if (std::strcmp(model, "cowper-symonds") == 0) {
        code = NFD_RATE_COWPER_SYMONDS;
        first = std::strcmp(rest[at + 2], "inf") == 0
            ? INFINITY
            : number_in(lmp, keyword + " cowper-symonds", rest[at + 2], "D", 0.0, true, INFINITY, true,
                        "a finite number D > 0 [1/s] (or inf: rate-independent)");
        second = number_in(lmp, keyword + " cowper-symonds", rest[at + 3], "q", 0.0, true, INFINITY, true,
                           "a finite number q > 0 (the exponent)");
    } else {
        lmp->error->all(FLERR, fmt::format("{}: rate law out of range: need johnson-cook or cowper-symonds, got '{}'",
                                           keyword, model));
        return false;
    }
    size_t end = at + 4;
    double c = NAN, k = 0.0;
    if (end < rest.size() && std::strcmp(rest[end], "c") == 0) {
        if (end + 1 >= rest.size())
            lmp->error->all(FLERR, fmt::format("{}: c needs a value (eps_dot = v_n0 / (c a_ref), default {:g}; "
                                               "relaxing: {:g})", keyword, NFD_RATE_LENGTH_FACTOR,
                                               NFD_RELAXING_LENGTH_FACTOR));
        c = number_in(lmp, keyword, rest[end + 1], "c", 0.0, true, INFINITY, true,
                      fmt::format("a finite number c > 0 (eps_dot = v_n0 / (c a_ref), default {:g}; relaxing: {:g})",
                                  NFD_RATE_LENGTH_FACTOR, NFD_RELAXING_LENGTH_FACTOR));
        end += 2;
    }
    // the relaxing form (nfd_rate.h): its element's stiffness k (in E* / sigma_Y), then c defaults to its own
    if (end < rest.size() && std::strcmp(rest[end], "relaxing") == 0) {
        if (end + 1 >= rest.size())
            lmp->error->all(FLERR, fmt::format("{}: relaxing needs a value K (the element's stiffness in E*/sigma_Y, "
                                               "default {:g})", keyword, NFD_RELAXATION_STIFFNESS));
        k = number_in(lmp, keyword, rest[end + 1], "relaxing K", 0.0, true, INFINITY, true,
                      fmt::format("a finite number K > 0 (the element's stiffness in E*/sigma_Y, default {:g})",
                                  NFD_RELAXATION_STIFFNESS));
        end += 2;
    }
    if (std::isnan(c)) c = k > 0.0 ? NFD_RELAXING_LENGTH_FACTOR : NFD_RATE_LENGTH_FACTOR;
    for (size_t k = end; k < rest.size(); ++k)
        if (std::strcmp(rest[k], "rate") == 0 && std::strcmp(rest[k - 1], "file") != 0)
            lmp->error->all(FLERR, fmt::format("{}: rate given twice", who));
    if (nfd_rate_init(rate, law->code, code, first, second, c) != 0 || (k > 0.0 && nfd_rate_relaxing(rate, k) != 0))
        lmp->error->all(FLERR, fmt::format("{}: constants out of range (nfd_rate_init)", keyword));
    rest.erase(rest.begin() + static_cast<long>(at), rest.begin() + static_cast<long>(end));
    return true;
}

}    // namespace nfdcal_lammps

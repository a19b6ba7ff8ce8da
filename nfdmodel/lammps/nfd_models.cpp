/* nfd_models.cpp: the contact models after a style's constants (nfd_models.h).
 *
 * License: GPL-2.0-or-later (see nfd_law.h).
 */
#include "nfd_models.h"

#include "nfd_input.h"

#include "error.h"
#include "lammps.h"
#include "utils.h"

#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;

namespace nfdcal_lammps {

static const char *const KEYWORDS[] = {"damping", "tangential", "rolling", "twisting"};

std::string NfdModels::kinds() const
{
    static const char *const damping_names[] = {"none", "viscoelastic", "tsuji", "coeff_restitution"};
    std::string out;
    auto add = [&out](const std::string &text) { out += (out.empty() ? "" : ", ") + text; };
    if (damping != NFD_DAMPING_NONE) add(std::string("damping ") + damping_names[damping]);
    static const char *const tangential_names[] = {"none", "mindlin", "mindlin_rescale", "mindlin/force",
                                                   "mindlin_rescale/force"};
    if (tangential != NFD_TANGENTIAL_NONE) add(std::string("tangential ") + tangential_names[tangential]);
    if (rolling == NFD_ROLLING_SDS) add("rolling sds");
    if (twisting != NFD_TWISTING_NONE) add(twisting == NFD_TWISTING_MARSHALL ? "twisting marshall" : "twisting sds");
    return out.empty() ? "none" : out;
}

int first_model_keyword(int narg, char **arg)
{
    for (int k = 0; k < narg; ++k)
        for (const char *keyword : KEYWORDS)
            if (std::strcmp(arg[k], keyword) == 0) return k;
    return narg;
}

namespace {

/* count values after arg[at] (a model name), or an error naming the keyword's usage. */
void need(LAMMPS *lmp, const std::string &who, int narg, int at, int count, const char *usage)
{
    if (at + count >= narg)
        lmp->error->all(FLERR, fmt::format("{}: need {} ({} value(s) after the model name), got {}", who, usage, count,
                                           narg - 1 - at));
}

double at_least(LAMMPS *lmp, const std::string &who, const char *text, const char *what, double low, bool open)
{
    return number_in(lmp, who, text, what, low, open, INFINITY, false,
                     fmt::format("{} {} {:g}", what, open ? ">" : ">=", low));
}

}    // namespace

NfdModels read_models(LAMMPS *lmp, const std::string &who, int narg, char **arg, bool materials)
{
    NfdModels m;
    bool seen[4] = {false, false, false, false};
    int k = 0;
    while (k < narg) {
        int which = -1;
        for (int w = 0; w < 4; ++w)
            if (std::strcmp(arg[k], KEYWORDS[w]) == 0) which = w;
        if (which < 0)
            lmp->error->all(FLERR, fmt::format("{}: unknown keyword '{}' (allowed after the constants: damping, "
                                               "tangential, rolling, twisting)", who, arg[k]));
        if (seen[which]) lmp->error->all(FLERR, fmt::format("{}: keyword {} given twice", who, KEYWORDS[which]));
        seen[which] = true;
        if (k + 1 >= narg)
            lmp->error->all(FLERR, fmt::format("{}: {} needs a model name", who, KEYWORDS[which]));
        const char *model = arg[k + 1];
        if (which == 0) {              // damping MODEL value
            if (std::strcmp(model, "viscoelastic") == 0) {
                need(lmp, who, narg, k + 1, 1, "damping viscoelastic c [1/(m s)]");
                m.damping = NFD_DAMPING_VISCOELASTIC;
                m.damping_value = at_least(lmp, who, arg[k + 2], "damping viscoelastic c", 0.0, false);
            } else if (std::strcmp(model, "tsuji") == 0 || std::strcmp(model, "coeff_restitution") == 0) {
                const bool tsuji = model[0] == 't';
                need(lmp, who, narg, k + 1, 1, tsuji ? "damping tsuji e" : "damping coeff_restitution e");
                m.damping = tsuji ? NFD_DAMPING_TSUJI : NFD_DAMPING_COEFF_RESTITUTION;
                m.damping_value = number_in(lmp, who, arg[k + 2], "the restitution e", 0.0, !tsuji, 1.0, false,
                                            tsuji ? "0 <= e <= 1" : "0 < e <= 1");
            } else {
                lmp->error->all(FLERR, fmt::format("{}: damping model '{}' out of range: need viscoelastic, tsuji or "
                                                   "coeff_restitution", who, model));
            }
            k += 3;
        } else if (which == 1) {       // tangential mindlin[_rescale][/force] k_t|NULL x_gamma_t mu
            static const char *const variants[] = {"mindlin", "mindlin_rescale", "mindlin/force",
                                                   "mindlin_rescale/force"};
            static const int codes[] = {NFD_TANGENTIAL_MINDLIN, NFD_TANGENTIAL_MINDLIN_RESCALE,
                                        NFD_TANGENTIAL_MINDLIN_FORCE, NFD_TANGENTIAL_MINDLIN_RESCALE_FORCE};
            for (int v = 0; v < 4; ++v)
                if (std::strcmp(model, variants[v]) == 0) m.tangential = codes[v];
            if (m.tangential == NFD_TANGENTIAL_NONE)
                lmp->error->all(FLERR, fmt::format("{}: tangential model '{}' out of range: need mindlin, "
                                                   "mindlin_rescale, mindlin/force or mindlin_rescale/force", who,
                                                   model));
            need(lmp, who, narg, k + 1, 3, "tangential mindlin k_t|NULL x_gamma_t mu");
            if (std::strcmp(arg[k + 2], "NULL") == 0) {
                if (!materials)
                    lmp->error->all(FLERR, fmt::format("{}: tangential mindlin k_t NULL (8 G* of the materials) needs "
                                                       "a law of materials: give k_t [Pa]", who));
                m.k_t = -1.0;
            } else {
                m.k_t = positive(lmp, who, arg[k + 2], "tangential mindlin k_t [Pa]");
            }
            m.x_gamma_t = at_least(lmp, who, arg[k + 3], "tangential mindlin x_gamma_t", 0.0, false);
            m.mu = number_in(lmp, who, arg[k + 4], "tangential mindlin mu", 0.0, false, NFD_MU_MAX, false,
                             fmt::format("0 <= mu <= {:g}", NFD_MU_MAX));
            k += 5;
        } else if (which == 2) {       // rolling sds k gamma mu
            if (std::strcmp(model, "sds") != 0)
                lmp->error->all(FLERR, fmt::format("{}: rolling model '{}' out of range: need sds", who, model));
            need(lmp, who, narg, k + 1, 3, "rolling sds k_roll gamma_roll mu_roll");
            m.rolling = NFD_ROLLING_SDS;
            m.k_roll = positive(lmp, who, arg[k + 2], "rolling sds k_roll [N/m]");
            m.gamma_roll = at_least(lmp, who, arg[k + 3], "rolling sds gamma_roll", 0.0, false);
            m.mu_roll = number_in(lmp, who, arg[k + 4], "rolling sds mu_roll", 0.0, false, NFD_MU_MAX, false,
                                  fmt::format("0 <= mu_roll <= {:g}", NFD_MU_MAX));
            k += 5;
        } else {                       // twisting marshall | sds k gamma mu
            if (std::strcmp(model, "marshall") == 0) {
                m.twisting = NFD_TWISTING_MARSHALL;
                k += 2;
            } else if (std::strcmp(model, "sds") == 0) {
                need(lmp, who, narg, k + 1, 3, "twisting sds k_twist gamma_twist mu_twist");
                m.twisting = NFD_TWISTING_SDS;
                m.k_twist = positive(lmp, who, arg[k + 2], "twisting sds k_twist [N m/rad]");
                m.gamma_twist = at_least(lmp, who, arg[k + 3], "twisting sds gamma_twist", 0.0, false);
                m.mu_twist = at_least(lmp, who, arg[k + 4], "twisting sds mu_twist [m]", 0.0, false);
                k += 5;
            } else {
                lmp->error->all(FLERR, fmt::format("{}: twisting model '{}' out of range: need marshall or sds", who,
                                                   model));
            }
        }
    }
    if (m.twisting == NFD_TWISTING_MARSHALL && m.tangential == NFD_TANGENTIAL_NONE)
        lmp->error->all(FLERR, fmt::format("{}: twisting marshall takes its stiffness and friction from the tangential "
                                           "model: add tangential mindlin", who));
    return m;
}

static double mix_geom(double a, double b) { return a == b ? a : std::sqrt(a * b); }

NfdModels mix_models(const NfdModels &a, const NfdModels &b)
{
    NfdModels m = a;
    m.damping_value = mix_geom(a.damping_value, b.damping_value);
    m.k_t = a.k_t < 0.0 || b.k_t < 0.0 ? -1.0 : mix_geom(a.k_t, b.k_t);
    m.x_gamma_t = mix_geom(a.x_gamma_t, b.x_gamma_t);
    m.mu = mix_geom(a.mu, b.mu);
    m.k_roll = mix_geom(a.k_roll, b.k_roll);
    m.gamma_roll = mix_geom(a.gamma_roll, b.gamma_roll);
    m.mu_roll = mix_geom(a.mu_roll, b.mu_roll);
    m.k_twist = mix_geom(a.k_twist, b.k_twist);
    m.gamma_twist = mix_geom(a.gamma_twist, b.gamma_twist);
    m.mu_twist = mix_geom(a.mu_twist, b.mu_twist);
    return m;
}

nfd_friction contact_friction(const NfdModels &m, double E_i, double nu_i, double E_j, double nu_j)
{
    nfd_friction f;
    f.damping = m.damping;
    f.damping_coeff = nfd_damping_coefficient(m.damping, m.damping_value);
    f.tangential = m.tangential;
    f.k_t = m.k_t < 0.0 ? nfd_shear_coefficient(E_i, nu_i, E_j, nu_j) : m.k_t;
    f.x_gamma_t = m.x_gamma_t;
    f.mu = m.mu;
    f.rolling = m.rolling;
    f.k_roll = m.k_roll;
    f.gamma_roll = m.gamma_roll;
    f.mu_roll = m.mu_roll;
    f.twisting = m.twisting;
    f.k_twist = m.k_twist;
    f.gamma_twist = m.gamma_twist;
    f.mu_twist = m.mu_twist;
    return f;
}

}    // namespace nfdcal_lammps

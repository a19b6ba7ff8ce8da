/* nfd_law.cpp: the six laws of the plugin (nfd_law.h), one class each, and their registry.
 *
 *   hertz         pair_coeff I I E nu
 *   thornton      pair_coeff I I E nu sigma_y
 *   vz            pair_coeff I I E nu sigma_y Ca_hat Kc_hat [window [P_min/P_Y] P_max/P_Y]
 *   vz-table      pair_coeff I I file params.json          (an nfdcal parameter file)
 *   vz-unload     pair_coeff I I file params.json          (an nfdcal parameter file of that law)
 *   walton-braun  pair_coeff I J K1 K2                      (stiffnesses [N/m], mixed in series)
 *
 * and, for a pair of unlike types calibrated as a pair (read_pair):
 *
 *   vz            pair_coeff I J Ca_hat Kc_hat [window [P_min/P_Y] P_max/P_Y]
 *   vz-table      pair_coeff I J file pair.json             (a counter-body parameter file)
 *   vz-unload     pair_coeff I J file pair.json             (the same, of law vz-unload)
 *
 * SI units; the dimensionless vz constants Ca_hat = Ca P_Y / a_Y, Kc_hat = Kc P_Y hold for any
 * pair of the material (README of this folder, Mixing).
 *
 * License: GPL-2.0-or-later (see nfd_law.h).
 */
#include "nfd_law.h"

#include "nfd_input.h"

#include "error.h"
#include "lammps.h"
#include "utils.h"

#include <algorithm>
#include <cctype>

using namespace LAMMPS_NS;

namespace nfdcal_lammps {

static std::string upper_id(const char *name)
{
    std::string id = name;
    for (char &c : id) c = c == '-' ? '_' : static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return "NFD_HISTORY_" + id;
}

NfdLaw::NfdLaw(int code, const char *name, const char *title, bool has_window, bool per_type_pair) :
    code(code), pair_style(std::string("nfd/") + name), wall_style(std::string("nfd/wall/") + name),
    history_id(upper_id(name)), pair_info(fmt::format("nfdcal: {} (nfd_kernel.c)", title)),
    wall_info(fmt::format("nfdcal: flat wall (rigid, or elastic with wall_material), {} (nfd_kernel.c)", title)),
    has_window(has_window),
    per_type_pair(per_type_pair)
{
}

NfdMaterial NfdLaw::mix(const NfdMaterial &a, const NfdMaterial &b) const
{
    NfdMaterial contact = nfd_yields_first(a.p_Y, b.p_Y) ? a : b;
    contact.E_star = nfd_contact_modulus(1.0 / a.E_star, 1.0 / b.E_star);
    return contact;
}

NfdMaterial NfdLaw::read_pair(LAMMPS *lmp, const std::string &who, int /*narg*/, char ** /*arg*/) const
{
    lmp->error->all(FLERR, fmt::format("{}: {} takes no constants of a pair (a contact of unlike types follows from "
                                       "the two materials): use I I", who, pair_style));
    return NfdMaterial();
}

NfdMaterial NfdLaw::with_pair(const NfdMaterial &contact, const NfdMaterial &pair)
{
    NfdMaterial calibrated = contact;
    calibrated.Ca_hat = pair.Ca_hat;
    calibrated.Kc_hat = pair.Kc_hat;
    calibrated.window = pair.window;
    calibrated.window_min = pair.window_min;
    calibrated.table = pair.table;
    return calibrated;
}

uint64_t NfdLaw::fingerprint(const NfdMaterial &m) const
{
    uint64_t z = mix64(static_cast<uint64_t>(code) + 1);
    for (double v : {m.E, m.nu, m.sigma_y, m.Ca_hat, m.Kc_hat, m.K1, m.K2}) z = mix_double(z, v);
    z = mix64(z ^ static_cast<uint64_t>(m.table.n));
    for (int n = 0; n < m.table.n; ++n)
        for (double v : {m.table.x[n], m.table.f[n], m.table.g[n]}) z = mix_double(z, v);
    if (m.table.n_unload > 0) z = mix64(z ^ static_cast<uint64_t>(m.table.n_unload));   // vz-unload's tables
    for (int n = 0; n < m.table.n_unload; ++n)
        for (double v : {m.table.x_unload[n], m.table.dent[n], m.table.exponent[n]}) z = mix_double(z, v);
    if (m.rate_on) {                     // the rate law: absent, the fingerprint of the base law alone
        z = mix64(z ^ static_cast<uint64_t>(0x72617465ULL + m.rate.rate_law));
        for (double v : {m.rate.first, m.rate.second, m.rate.c}) z = mix_double(z, v);
    }
    if (!m.models.any()) return z;       // the fingerprint of a frictionless material is the law's alone
    const NfdModels &c = m.models;
    z = mix64(z ^ static_cast<uint64_t>(c.damping + 8 * (c.tangential + 8 * (c.rolling + 8 * c.twisting))));
    for (double v : {c.damping_value, c.k_t, c.x_gamma_t, c.mu, c.k_roll, c.gamma_roll, c.mu_roll, c.k_twist,
                     c.gamma_twist, c.mu_twist})
        z = mix_double(z, v);
    return z;
}

/* The laws of a solid, E nu [sigma_y] [...]: E* and first yield from the material. */
class SolidLaw : public NfdLaw {
 protected:
    SolidLaw(int code, const char *name, const char *title, bool has_window, const char *usage, int count) :
        NfdLaw(code, name, title, has_window, false), usage(usage), count(count)
    {
    }

    /* E nu [sigma_y], the first `count` arguments (with_yield: sigma_y too), after the argument count
     * was checked against [count, count + optional]. */
    NfdMaterial read_solid(LAMMPS *lmp, const std::string &who, bool wall, int narg, char **arg, bool with_yield,
                           int optional = 0) const
    {
        if (narg != count && !(optional > 0 && narg == count + optional))
            lmp->error->all(FLERR, fmt::format("{}: need {} (SI units) after the {}, got {} arguments", who, usage,
                                               after(wall), narg));
        NfdMaterial m;
        m.E = check_solid(lmp, who + ":", "E", "E", positive(lmp, who, arg[0], "E [Pa]"));
        m.nu = number_in(lmp, who, arg[1], "nu", 0.0, false, NFD_NU_MAX, true,
                         fmt::format("0 <= nu < {:g}", NFD_NU_MAX));
        if (with_yield)
            m.sigma_y = check_solid(lmp, who + ":", "sigma_y", "sigma_y", positive(lmp, who, arg[2], "sigma_y [Pa]"));
        m.p_Y = with_yield ? nfd_yield_pressure(m.sigma_y, m.nu) : 0.0;
        m.E_star = nfd_plane_strain_modulus(m.E, m.nu);
        return m;
    }

    const char *usage;
    int count;
};

class HertzLaw : public SolidLaw {
 public:
    HertzLaw() : SolidLaw(NFD_LAW_HERTZ, "hertz", "Hertz normal contact", false, "E nu", 2) {}
    NfdMaterial read(LAMMPS *lmp, const std::string &who, bool wall, int narg, char **arg) const override
    {
        return read_solid(lmp, who, wall, narg, arg, false);
    }
    nfd_params params(double R_star, const NfdMaterial &c) const override { return nfd_pair(R_star, c.E_star, 1.0); }
};

class ThorntonLaw : public SolidLaw {
 public:
    ThorntonLaw() :
        SolidLaw(NFD_LAW_THORNTON, "thornton", "Thornton (1997) elastoplastic normal contact", false, "E nu sigma_y", 3)
    {
    }
    NfdMaterial read(LAMMPS *lmp, const std::string &who, bool wall, int narg, char **arg) const override
    {
        return read_solid(lmp, who, wall, narg, arg, true);
    }
    nfd_params params(double R_star, const NfdMaterial &c) const override { return nfd_pair(R_star, c.E_star, c.p_Y); }
};

class VzLaw : public SolidLaw {
 public:
    VzLaw() :
        SolidLaw(NFD_LAW_VZ, "vz", "Vu-Quoc & Zhang elastoplastic normal contact, FE-calibrated", true,
                 "E nu sigma_y Ca_hat Kc_hat [window [P_min/P_Y] P_max/P_Y]", 5)
    {
    }

    /* Ca = Ca_hat a_Y / P_Y, Kc = Kc_hat / P_Y, window force = window P_Y; the window defaults to
     * NFD_DEFAULT_WINDOW (nfdmodel.window), `window inf` never flags a contact; its lower end P_min/P_Y
     * (default 1: none) is the lowest unloading the constants were fitted on. */
    NfdMaterial read(LAMMPS *lmp, const std::string &who, bool wall, int narg, char **arg) const override
    {
        NfdMaterial m = read_solid(lmp, who, wall, narg == count + 3 ? count + 2 : narg, arg, true, 2);
        read_constants(lmp, who, narg - 3, arg + 3, m);
        return m;
    }

    NfdMaterial read_pair(LAMMPS *lmp, const std::string &who, int narg, char **arg) const override
    {
        // the shape first: a material's numbers (E nu sigma_y ...) given to I J get the usage, not a range
        if (narg != 2 && !((narg == 4 || narg == 5) && std::strcmp(arg[2], "window") == 0))
            lmp->error->all(FLERR, fmt::format("{}: need Ca_hat Kc_hat [window [P_min/P_Y] P_max/P_Y] (the constants "
                                               "calibrated for this pair; a type's material goes in pair_coeff I I), "
                                               "got {} arguments", who, narg));
        NfdMaterial m;
        read_constants(lmp, who, narg, arg, m);
        return m;
    }

    /* Ca_hat Kc_hat [window [P_min] P_max] of arg[0..narg) (narg 2, 4 or 5, checked by the caller), each in
     * its range */
    static void read_constants(LAMMPS *lmp, const std::string &who, int narg, char **arg, NfdMaterial &m)
    {
        m.Ca_hat = positive(lmp, who, arg[0], "Ca_hat = Ca P_Y / a_Y");
        if (m.Ca_hat < NFD_CA_HAT_MIN || m.Ca_hat > NFD_CA_HAT_MAX)
            lmp->error->all(FLERR, fmt::format("{}: Ca_hat out of range: need {:g} <= Ca_hat <= {:g} (the paper's "
                                               "0.026), got {}", who, NFD_CA_HAT_MIN, NFD_CA_HAT_MAX, arg[0]));
        m.Kc_hat = number_in(lmp, who, arg[1], "Kc_hat", 0.0, false, NFD_KC_HAT_MAX, false,
                             fmt::format("0 <= Kc_hat <= {:g} (the paper's 0.0098)", NFD_KC_HAT_MAX));
        check_vz_admissible(lmp, who, m.Ca_hat, m.Kc_hat);
        m.window = NFD_DEFAULT_WINDOW;
        if (narg >= 4) {
            if (std::strcmp(arg[2], "window") != 0)
                lmp->error->all(FLERR, fmt::format("{}: unknown keyword '{}' (allowed: window)", who, arg[2]));
            if (narg == 5)
                m.window_min = number_in(lmp, who, arg[3], "window P_min/P_Y", 1.0, false, INFINITY, true,
                                         "P_min/P_Y >= 1 (the lowest unloading of the fit)");
            const char *high = arg[narg - 1];
            m.window = std::strcmp(high, "inf") == 0
                ? INFINITY
                : number_in(lmp, who, high, "window", m.window_min, false, INFINITY, true,
                            fmt::format("P_max/P_Y >= {:g} (or inf)", m.window_min));
        }
    }

    nfd_params params(double R_star, const NfdMaterial &c) const override
    {
        nfd_params p = nfd_pair(R_star, c.E_star, c.p_Y);
        nfd_vz_constants(&p, c.Ca_hat * p.a_Y / p.P_Y, c.Kc_hat / p.P_Y);
        p.window_P_max = c.window * p.P_Y;
        return p;
    }
};

/* The law of an nfdcal parameter file's tables (vz-table; VzUnloadLaw reads its own files the same way). */
class VzTableLaw : public NfdLaw {
 public:
    VzTableLaw() : VzTableLaw(NFD_LAW_VZ_TABLE, "vz-table", "NFD law with FE tables of a_p and C_R") {}
    VzTableLaw(int code, const char *name, const char *title) : NfdLaw(code, name, title, true, false), name(name) {}

    NfdMaterial read(LAMMPS *lmp, const std::string &who, bool wall, int narg, char **arg) const override
    {
        if (narg != 2 || std::strcmp(arg[0], "file") != 0)
            lmp->error->all(FLERR, fmt::format("{}: need 'file PATH' (an nfdcal parameter file of law {}) "
                                               "after the {}, got {} arguments", who, name, after(wall), narg));
        return read_parameter_file(lmp, who, arg[1], name);
    }

    /* a counter-body parameter file's tables and window (its material is the types') */
    NfdMaterial read_pair(LAMMPS *lmp, const std::string &who, int narg, char **arg) const override
    {
        if (narg != 2 || std::strcmp(arg[0], "file") != 0)
            lmp->error->all(FLERR, fmt::format("{}: need 'file PATH' (an nfdcal parameter file of law {}, "
                                               "calibrated for this pair), got {} arguments", who, name, narg));
        return read_parameter_file(lmp, who, arg[1], name);
    }

    nfd_params params(double R_star, const NfdMaterial &c) const override
    {
        nfd_params p = nfd_pair(R_star, c.E_star, c.p_Y);
        p.window_P_max = c.window * p.P_Y;
        return p;
    }

 private:
    const char *name;
};

/* vz-table's loading tables with the dent and unloading exponent over the turning point (nfd_unload.h). */
class VzUnloadLaw : public VzTableLaw {
 public:
    VzUnloadLaw() :
        VzTableLaw(NFD_LAW_VZ_UNLOAD, "vz-unload", "NFD law with FE tables of a_p, C_R, dent and unloading exponent")
    {
    }
};

/* Walton & Braun (1986): a law of stiffnesses, not of materials: loading P = K1 delta, unloading
 * P = K2 <delta - delta_res> (e = sqrt(K1/K2) in a collision). */
class WaltonBraunLaw : public NfdLaw {
 public:
    WaltonBraunLaw() :
        NfdLaw(NFD_LAW_WALTON_BRAUN, "walton-braun", "Walton & Braun (1986) bilinear normal contact", false, true)
    {
    }

    NfdMaterial read(LAMMPS *lmp, const std::string &who, bool wall, int narg, char **arg) const override
    {
        if (narg != 2)
            lmp->error->all(FLERR, fmt::format("{}: need K1 K2 (loading and unloading stiffness [N/m], "
                                               "0 < K1 <= K2) after the {}, got {} arguments", who, after(wall),
                                               narg));
        NfdMaterial springs;
        springs.K1 = positive(lmp, who, arg[0], "K1 [N/m]");
        springs.K2 = positive(lmp, who, arg[1], "K2 [N/m]");
        if (springs.K2 < springs.K1)
            lmp->error->all(FLERR, fmt::format("{}: K2 out of range: need K2 >= K1 = {} N/m (a stiffer unloading; "
                                               "otherwise the contact creates energy), got {}", who, arg[0], arg[1]));
        return springs;
    }

    /* Unlike types without pair_coeff I J: the harmonic mean K_IJ = 2 / (1/K_II + 1/K_JJ) of K1 and
     * of K2 (each body in series with half the compliance of its own like-type contact), so a type
     * mixed with itself keeps its stiffness and K1 <= K2 still holds. */
    NfdMaterial mix(const NfdMaterial &a, const NfdMaterial &b) const override
    {
        NfdMaterial mixed;
        mixed.K1 = 2.0 / (1.0 / a.K1 + 1.0 / b.K1);
        mixed.K2 = 2.0 / (1.0 / a.K2 + 1.0 / b.K2);
        return mixed;
    }

    double contact_time(const nfd_params &p, double m_star, double /*v*/) const override
    {
        return nfd_linear_impact_time(m_star, p.K1, p.K2);
    }

    nfd_params params(double R_star, const NfdMaterial &c) const override
    {
        nfd_params p = nfd_pair(R_star, 1.0, 1.0);     // no material: the pair quantities are unused
        p.K1 = c.K1;
        p.K2 = c.K2;
        return p;
    }
};

static const NfdLaw *const *all_laws()
{
    static const HertzLaw hertz;
    static const VzLaw vz;
    static const ThorntonLaw thornton;
    static const VzTableLaw vz_table;
    static const WaltonBraunLaw walton_braun;
    static const VzUnloadLaw vz_unload;
    static const NfdLaw *const laws[] = {&hertz, &vz, &thornton, &vz_table, &walton_braun, &vz_unload, nullptr};
    return laws;
}

const NfdLaw *NfdLaw::of(int code)
{
    for (const NfdLaw *const *law = all_laws(); *law; ++law)
        if ((*law)->code == code) return *law;
    return nullptr;
}

const NfdLaw *NfdLaw::of_history_id(const char *id)
{
    for (const NfdLaw *const *law = all_laws(); *law; ++law)
        if ((*law)->history_id == id) return *law;
    return nullptr;
}

}    // namespace nfdcal_lammps

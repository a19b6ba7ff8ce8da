/* nfd_input.h: the numbers of pair_coeff and wall-fix lines and of nfdcal parameter files, each
 * checked against its range (nfd_limits.h), with one error line naming the constant and the range.
 *
 * License: GPL-2.0-or-later (see nfd_law.h).
 */
#ifndef NFD_LAMMPS_INPUT_H
#define NFD_LAMMPS_INPUT_H

#include "nfd_law.h"

#include <string>
#include <vector>

namespace nfdcal_lammps {

/* Stop with one error line unless the LAMMPS unit style is `si`: the laws' constants, their ranges and
 * the kernel's formulas are SI (Pa, m, kg, s), so under another style the same numbers mean another
 * contact. who: the style ("pair_style nfd/vz", "fix nfd/wall/vz"). */
void require_si_units(LAMMPS_NS::LAMMPS *lmp, const std::string &who);

/* A constant that must be a finite number > 0 (E, sigma_y, Ca_hat, K1, K2); what names it
 * ("E [Pa]"). Parsed here rather than by utils::numeric, so that inf, nan or 1e400 get the
 * message naming the constant and its range. */
double positive(LAMMPS_NS::LAMMPS *lmp, const std::string &who, const char *text, const char *what);

/* A finite number within [low, high] (either end open), or an error naming what and the range text
 * (text, inf, nan and 1e400 too). */
double number_in(LAMMPS_NS::LAMMPS *lmp, const std::string &who, const char *text, const char *what, double low,
                 bool low_open, double high, bool high_open, const std::string &range);

/* E or sigma_y [Pa] (name "E", "sigma_y"; a finite number > 0) within the range of real solids,
 * NFD_E_MIN..NFD_E_MAX, NFD_SIGMA_Y_MIN..NFD_SIGMA_Y_MAX (nfdmodel.validation.check_solid), or an error
 * naming the range and the likely unit slip: "did you give GPa? 70 GPa = 7e+10 Pa". where: the
 * message's start ("pair_coeff for nfd/vz:"), label: the value's name there ("E", "material.E"). */
double check_solid(LAMMPS_NS::LAMMPS *lmp, const std::string &where, const char *name, const std::string &label,
                   double value);

/* Ca_hat, Kc_hat (each within its range) admissible by nfd_vz_admissible (the loading curve
 * increases, no load-unload cycle creates energy), or an error naming the two constants, the load
 * where the law fails and the admissible range of Kc_hat for this Ca_hat (nfdmodel.VZParams' check). */
void check_vz_admissible(LAMMPS_NS::LAMMPS *lmp, const std::string &who, double Ca_hat, double Kc_hat);

/* The law `law` ("vz-table" or "vz-unload") of an nfdcal parameter file (nfdmodel/parameter_file.py):
 * material E [Pa], nu, sigma_y [Pa]; table P_over_P_Y, a_p_over_a_Y, C_R (2..NFD_TABLE_MAX_NODES
 * nodes, the rules of nfd_table_init); vz-unload also unloading P_max_over_P_Y, dent, exponent (the
 * rules of nfd_unload_table_init); window P_max_over_P_Y (absent: the table's last node, as
 * nfdmodel.VZTableParams). A file of another law is refused. Read on rank 0 and broadcast. */
NfdMaterial read_parameter_file(LAMMPS_NS::LAMMPS *lmp, const std::string &who, const std::string &path,
                                const std::string &law);

/* The keyword `rate` taken out of rest (a style's arguments after the types or the wall's plane; the
 * keyword at position 1 or later, not the PATH of `file PATH`):
 *
 *     rate johnson-cook C eps_dot_0 [c C_LENGTH]     R = 1 + C ln(max(eps_dot / eps_dot_0, 1))
 *     rate cowper-symonds D q [c C_LENGTH]           R = 1 + (eps_dot / D)^(1/q)
 *
 * the rate-aware law on the style's law (nfd_rate.h; vz and vz-table, another law refuses it), each
 * constant in nfdmodel.strain_rate's range (C >= 0, eps_dot_0 > 0 [1/s], D > 0 [1/s] or inf (R = 1),
 * q > 0; c > 0 of eps_dot = v_n0 / (c a_ref), default NFD_RATE_LENGTH_FACTOR), or an error naming the
 * keyword, the constant and its range. Returns whether the keyword was given (then *rate is set). */
bool take_rate(LAMMPS_NS::LAMMPS *lmp, const std::string &who, const NfdLaw *law, std::vector<char *> &rest,
               nfd_rate *rate);

}    // namespace nfdcal_lammps

#endif

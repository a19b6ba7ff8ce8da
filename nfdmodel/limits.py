"""The laws' codes, defaults, solver tolerances and admissible ranges, read from ``nfd_limits.h``.

``nfd_limits.h`` (beside this module) is the one table of these numbers for C (the kernel), C++
(the LAMMPS plugin) and Python: each ``#define NFD_<NAME> <number>`` there is ``limits.<NAME>``
here (an int when written as one, else a float; every entry of the table is also in ``TABLE``).
Nothing else in nfdmodel or calib writes these numbers again (tests/test_limits.py).
"""
from __future__ import annotations

import re
from pathlib import Path

HEADER = Path(__file__).with_name("nfd_limits.h")
_DEFINE = re.compile(r"^#define\s+NFD_([A-Z0-9_]+)\s+([-+0-9.eE]+)\s*(?:/\*.*)?$")


def read_table(path: Path = HEADER) -> dict[str, int | float]:
    """{NAME: value} of every ``#define NFD_NAME number`` line of the header (guards skipped)."""
    table: dict[str, int | float] = {}
    for line in path.read_text(encoding="utf-8").splitlines():
        match = _DEFINE.match(line.strip())
        if match:
            name, text = match.groups()
            table[name] = int(text) if re.fullmatch(r"[-+]?\d+", text) else float(text)
    return table


TABLE = read_table()
LAW_HERTZ, LAW_VZ, LAW_THORNTON = TABLE["LAW_HERTZ"], TABLE["LAW_VZ"], TABLE["LAW_THORNTON"]
LAW_VZ_TABLE, LAW_WALTON_BRAUN, LAW_COUNT = TABLE["LAW_VZ_TABLE"], TABLE["LAW_WALTON_BRAUN"], TABLE["LAW_COUNT"]
LAW_VZ_UNLOAD = TABLE["LAW_VZ_UNLOAD"]
DEFAULT_WINDOW = TABLE["DEFAULT_WINDOW"]
CA_HAT_MIN, CA_HAT_MAX, KC_HAT_MAX = TABLE["CA_HAT_MIN"], TABLE["CA_HAT_MAX"], TABLE["KC_HAT_MAX"]
NU_MAX = TABLE["NU_MAX"]
E_MIN, E_MAX, SIGMA_Y_MIN, SIGMA_Y_MAX = TABLE["E_MIN"], TABLE["E_MAX"], TABLE["SIGMA_Y_MIN"], TABLE["SIGMA_Y_MAX"]
RHO_MIN, RHO_MAX, V_IN_MAX = TABLE["RHO_MIN"], TABLE["RHO_MAX"], TABLE["V_IN_MAX"]
RADIUS_USUAL_MAX, RADIUS_MAX = TABLE["RADIUS_USUAL_MAX"], TABLE["RADIUS_MAX"]
VZ_TOLERANCE, VZ_MAX_ITERATIONS = TABLE["VZ_TOLERANCE"], TABLE["VZ_MAX_ITERATIONS"]
TABLE_TOLERANCE, TABLE_MAX_ITERATIONS = TABLE["TABLE_TOLERANCE"], TABLE["TABLE_MAX_ITERATIONS"]
TABLE_MAX_NODES = TABLE["TABLE_MAX_NODES"]
# the admissibility of (Ca_hat, Kc_hat): the loading curve checked at MONOTONE_POINTS loads up to
# MONOTONE_LOAD_MAX P_Y, load-unload cycles at DISSIPATION_POINTS turning points in
# [DISSIPATION_LOAD_MIN, DISSIPATION_LOAD_MAX] P_Y, returned work at most 1 + DISSIPATION_SLACK times taken
MONOTONE_LOAD_MAX, MONOTONE_POINTS = TABLE["MONOTONE_LOAD_MAX"], TABLE["MONOTONE_POINTS"]
DISSIPATION_LOAD_MIN, DISSIPATION_LOAD_MAX = TABLE["DISSIPATION_LOAD_MIN"], TABLE["DISSIPATION_LOAD_MAX"]
DISSIPATION_POINTS, DISSIPATION_SLACK = TABLE["DISSIPATION_POINTS"], TABLE["DISSIPATION_SLACK"]
# the time step of a collision: the fewest steps per contact and per unloading that pass unwarned;
# the constant of Hertz's elastic impact duration (Johnson 1985 eq. 11.24)
STEPS_PER_CONTACT_MIN, STEPS_PER_UNLOADING_MIN = TABLE["STEPS_PER_CONTACT_MIN"], TABLE["STEPS_PER_UNLOADING_MIN"]
HERTZ_IMPACT_TIME = TABLE["HERTZ_IMPACT_TIME"]
# the FE's reach: the largest load over P_Y and contact radius over R a calibration runs to
FE_MAX_LOAD_OVER_YIELD, FE_MAX_CONTACT_RADIUS_OVER_R = TABLE["FE_MAX_LOAD_OVER_YIELD"], TABLE["FE_MAX_CONTACT_RADIUS_OVER_R"]
# ... and the finite-strain FE's (the farthest any calibration runs to)
FE_FINITE_MAX_LOAD_OVER_YIELD = TABLE["FE_FINITE_MAX_LOAD_OVER_YIELD"]
FE_FINITE_MAX_CONTACT_RADIUS_OVER_R = TABLE["FE_FINITE_MAX_CONTACT_RADIUS_OVER_R"]
# the rate-aware law (nfd_rate.h): its rate laws' codes and the default c of eps_dot = v_n0 / (c a_ref); the
# energy balance of an impact (collision_reference): bracket doublings, Newton steps and tolerance
RATE_JOHNSON_COOK, RATE_COWPER_SYMONDS = TABLE["RATE_JOHNSON_COOK"], TABLE["RATE_COWPER_SYMONDS"]
RATE_LENGTH_FACTOR = TABLE["RATE_LENGTH_FACTOR"]
RELAXATION_STIFFNESS, RELAXING_LENGTH_FACTOR = TABLE["RELAXATION_STIFFNESS"], TABLE["RELAXING_LENGTH_FACTOR"]
RATE_FACTOR_ITERATIONS, RATE_FACTOR_TOLERANCE = TABLE["RATE_FACTOR_ITERATIONS"], TABLE["RATE_FACTOR_TOLERANCE"]
# the rate laws' constants a command or a scene accepts: Johnson-Cook's C and eps_dot_0, Cowper-Symonds' D and q
JC_C_MAX, JC_REFERENCE_RATE_MIN, JC_REFERENCE_RATE_MAX = (TABLE["JC_C_MAX"], TABLE["JC_REFERENCE_RATE_MIN"],
                                                          TABLE["JC_REFERENCE_RATE_MAX"])
CS_D_MIN, CS_D_MAX, CS_Q_MIN, CS_Q_MAX = TABLE["CS_D_MIN"], TABLE["CS_D_MAX"], TABLE["CS_Q_MIN"], TABLE["CS_Q_MAX"]
REFERENCE_BRACKET_STEPS, REFERENCE_NEWTON_STEPS = TABLE["REFERENCE_BRACKET_STEPS"], TABLE["REFERENCE_NEWTON_STEPS"]
REFERENCE_TOLERANCE, SMALLEST_ENERGY = TABLE["REFERENCE_TOLERANCE"], TABLE["SMALLEST_ENERGY"]
# the contact models around the normal law (nfd_friction.h, nfdmodel.friction): their codes, the
# frame tolerance of a spring, the friction history's size, the largest friction coefficient
DAMPING_NONE, DAMPING_VISCOELASTIC = TABLE["DAMPING_NONE"], TABLE["DAMPING_VISCOELASTIC"]
DAMPING_TSUJI, DAMPING_COEFF_RESTITUTION = TABLE["DAMPING_TSUJI"], TABLE["DAMPING_COEFF_RESTITUTION"]
TANGENTIAL_NONE, TANGENTIAL_MINDLIN = TABLE["TANGENTIAL_NONE"], TABLE["TANGENTIAL_MINDLIN"]
TANGENTIAL_MINDLIN_RESCALE, TANGENTIAL_MINDLIN_FORCE = (TABLE["TANGENTIAL_MINDLIN_RESCALE"],
                                                        TABLE["TANGENTIAL_MINDLIN_FORCE"])
TANGENTIAL_MINDLIN_RESCALE_FORCE = TABLE["TANGENTIAL_MINDLIN_RESCALE_FORCE"]
ROLLING_NONE, ROLLING_SDS = TABLE["ROLLING_NONE"], TABLE["ROLLING_SDS"]
TWISTING_NONE, TWISTING_MARSHALL = TABLE["TWISTING_NONE"], TABLE["TWISTING_MARSHALL"]
TWISTING_SDS = TABLE["TWISTING_SDS"]
FRAME_EPSILON, FRICTION_HISTORY, MU_MAX = TABLE["FRAME_EPSILON"], TABLE["FRICTION_HISTORY"], TABLE["MU_MAX"]
CAP_SLACK = TABLE["CAP_SLACK"]

# The names the laws go by in Python, C and LAMMPS (pair_style nfd/<name>), by code: NFD_LAW_VZ_TABLE
# is "vz-table" (every NFD_LAW_<NAME> but the count).
LAW_NAMES = {code: key[len("LAW_"):].lower().replace("_", "-") for key, code in TABLE.items()
             if key.startswith("LAW_") and key != "LAW_COUNT"}
LAW_CODES = {name: code for code, name in LAW_NAMES.items()}
CA_HAT_RANGE = (TABLE["CA_HAT_MIN"], TABLE["CA_HAT_MAX"])

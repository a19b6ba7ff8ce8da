/* nfd_limits.h: the one table of the laws' codes, defaults, solver tolerances and admissible
 * ranges, shared by every language of nfdcal:
 *
 *   C      nfd_kernel.c includes it (the kernel's tolerances, the law codes of its callers);
 *   C++    the LAMMPS plugin includes it (its argument checks use these ranges and messages);
 *   Python nfdmodel/limits.py reads this file at import (every `#define NFD_<NAME> <number>`
 *          below becomes limits.<NAME>), so nfdmodel's checks use the same numbers.
 *
 * Each number is written here once. tests/test_limits.py fails when another source file states
 * one of them again as a literal, or when a consumer disagrees with this table.
 * Format (read by a parser): one `#define NFD_<NAME> <number>` per line, a C comment after it.
 * SI units; "_hat" quantities are dimensionless (nfdmodel/README.md: the dimensionless constants).
 */
#ifndef NFD_LIMITS_H
#define NFD_LIMITS_H

/* Law codes: one number per law, in the kernel, its Python binding and the LAMMPS plugin. */
#define NFD_LAW_HERTZ 0
#define NFD_LAW_VZ 1
#define NFD_LAW_THORNTON 2
#define NFD_LAW_VZ_TABLE 3
#define NFD_LAW_WALTON_BRAUN 4
#define NFD_LAW_VZ_UNLOAD 5
#define NFD_LAW_COUNT 6

/* The rate-aware law (nfd_rate.h, nfdmodel.rate_aware): the codes of its rate laws and c, the
 * constant of eps_dot = v_n0 / (c a_ref) (fitted once to the dynamic FE: Cowper-Symonds D 40 /s, q 5,
 * 0.02 m/s, coarse mesh; nfdmodel/README.md, The rate-aware law). */
#define NFD_RATE_JOHNSON_COOK 0
#define NFD_RATE_COWPER_SYMONDS 1
#define NFD_RATE_LENGTH_FACTOR 26.0
/* the relaxing rate-aware law (nfd_rate.h, nfdmodel.rate_relaxing): its element's stiffness k (in units of
 * E* / sigma_Y) and c of eps_dot = v_n / (c a_ref), fitted to the dynamic FE; the backward-Euler solve's iterations and tolerance */
#define NFD_RELAXATION_STIFFNESS 1.15
#define NFD_RELAXING_LENGTH_FACTOR 5.7
#define NFD_RATE_FACTOR_ITERATIONS 200
#define NFD_RATE_FACTOR_TOLERANCE 1e-14
/* The rate laws' constants a command or a scene accepts (calib.commands.common, calib.scenes.schema):
 * Johnson-Cook's C in [0, JC_C_MAX] and eps_dot_0 [1/s] in [JC_REFERENCE_RATE_MIN, JC_REFERENCE_RATE_MAX];
 * Cowper-Symonds' D [1/s] in [CS_D_MIN, CS_D_MAX] and q in [CS_Q_MIN, CS_Q_MAX] (every measured metal
 * inside; D 1e12 is practically rate-independent). */
#define NFD_JC_C_MAX 1.0
#define NFD_JC_REFERENCE_RATE_MIN 1e-6
#define NFD_JC_REFERENCE_RATE_MAX 1e6
#define NFD_CS_D_MIN 1e-3
#define NFD_CS_D_MAX 1e12
#define NFD_CS_Q_MIN 0.5
#define NFD_CS_Q_MAX 20.0
/* The energy balance of an impact (nfdmodel.collision_reference, nfd_rate.h's a_ref): the Hertz
 * approach doubled at most REFERENCE_BRACKET_STEPS times until W >= m* v^2 / 2, then at most
 * REFERENCE_NEWTON_STEPS Newton steps from above, until a step is below REFERENCE_TOLERANCE delta. */
#define NFD_REFERENCE_BRACKET_STEPS 200
#define NFD_REFERENCE_NEWTON_STEPS 100
#define NFD_REFERENCE_TOLERANCE 1e-13     /* relative, on delta_max */
#define NFD_SMALLEST_ENERGY 1e-250        /* [J] m* v^2 / 2 below: the overlaps underflow, refused */

/* The calibrated window P_max/P_Y assumed for constants that do not state theirs: the largest
 * peak of the default calibration recipe (load paths to 13.7, 27.4 and 41.2 P_Y). */
#define NFD_DEFAULT_WINDOW 41.2

/* Admissible dimensionless vz constants: Ca_hat = Ca P_Y / a_Y (paper: 0.026) in
 * [CA_HAT_MIN, CA_HAT_MAX], Kc_hat = Kc P_Y (paper: 0.0098) in [0, KC_HAT_MAX]. */
#define NFD_CA_HAT_MIN 1e-8
#define NFD_CA_HAT_MAX 1e4
#define NFD_KC_HAT_MAX 1e4

/* The admissibility of vz constants (nfdmodel.vz.VZParams, nfd_vz_admissible): the loading
 * curve delta(P) increases at MONOTONE_POINTS loads geomspace(1, MONOTONE_LOAD_MAX) P_Y, and no full
 * load-unload cycle to the DISSIPATION_POINTS turning points geomspace(DISSIPATION_LOAD_MIN,
 * DISSIPATION_LOAD_MAX) P_Y returns more than (1 + DISSIPATION_SLACK) times the work it took (e <= 1). */
#define NFD_MONOTONE_LOAD_MAX 1e8        /* P/P_Y */
#define NFD_MONOTONE_POINTS 2000
#define NFD_DISSIPATION_LOAD_MIN 1.000001 /* P/P_Y: 1 + 1e-6, just past first yield */
#define NFD_DISSIPATION_LOAD_MAX 1e6     /* P/P_Y */
#define NFD_DISSIPATION_POINTS 200
#define NFD_DISSIPATION_SLACK 1e-9       /* relative excess of returned over taken work: round-off */

/* The time step of a collision: a contact resolved by fewer than STEPS_PER_CONTACT_MIN steps of its
 * estimated duration, or its unloading by fewer than STEPS_PER_UNLOADING_MIN, is warned of
 * (nfdmodel.collide, nfdcal collide, the LAMMPS plugin's pair styles and wall fixes): the leap-frog's
 * error in e is O(dt^2), about 1e-4 at 50 steps per contact and 1e-2 at 6. */
#define NFD_STEPS_PER_CONTACT_MIN 50
#define NFD_STEPS_PER_UNLOADING_MIN 10
/* Hertz's elastic impact lasts t_c = HERTZ_IMPACT_TIME (m*^2 / (R* E*^2 v))^(1/5) [s] (Johnson 1985
 * eq. 11.24; nfdmodel.hertz_contact.hertz_impact_time, nfd_hertz_impact_time). */
#define NFD_HERTZ_IMPACT_TIME 2.8683

/* Poisson's ratio: 0 <= nu < NU_MAX (A_Y(nu) and the Hertz field need a compressible solid). */
#define NFD_NU_MAX 0.5

/* The range of real solids and impacts: a value outside is a unit slip, refused with the slip named. */
#define NFD_E_MIN 1e5            /* [Pa] gels */
#define NFD_E_MAX 2e12           /* [Pa] above diamond, 1.2e12 */
#define NFD_SIGMA_Y_MIN 1e4      /* [Pa] soft foams */
#define NFD_SIGMA_Y_MAX 1e11     /* [Pa] whiskers */
#define NFD_RHO_MIN 10.0         /* [kg/m^3] aerogels */
#define NFD_RHO_MAX 3e4          /* [kg/m^3] above osmium, 22590 */
#define NFD_V_IN_MAX 1e4         /* [m/s] hypervelocity above */
#define NFD_RADIUS_USUAL_MAX 10.0   /* [m] a larger particle is unusual (a boulder): warned */
#define NFD_RADIUS_MAX 1e4       /* [m] no particle of a contact model is larger: refused */

/* The vz plastic-loading solve (Newton on u = P^(1/3), bracketed). */
#define NFD_VZ_TOLERANCE 1e-10       /* relative, on P */
#define NFD_VZ_MAX_ITERATIONS 200    /* never reached: the bracket halves at worst every other step */
/* The vz_table loading solve (bracketed Newton on x = P/P_Y). */
#define NFD_TABLE_TOLERANCE 1e-12    /* relative, on x */
#define NFD_TABLE_MAX_ITERATIONS 100 /* never reached: bisection halves the bracket when Newton strays */
#define NFD_TABLE_MAX_NODES 64       /* nodes of a vz_table table (nfd_table holds them inline) */

/* The FE's reach (calib.fit.recipe): a calibration runs to at most FE_MAX_LOAD_OVER_YIELD P_Y and
 * a contact radius of FE_MAX_CONTACT_RADIUS_OVER_R R (a small-strain, a << R contact problem: at
 * 0.2 R the contact edge has turned by 12 degrees; beyond about 0.19 R the bulged surface rolls onto
 * the flat, the contact's active set stops settling within a step, and at 0.26 R the FE's e changes
 * by 1.3 % between systematically refined meshes). A window stated beyond them is flagged. */
#define NFD_FE_MAX_LOAD_OVER_YIELD 1000.0
#define NFD_FE_MAX_CONTACT_RADIUS_OVER_R 0.2
/* The finite-strain FE's reach (calib.fit.recipe, --kinematics finite on the rigid flat): at most
 * FE_FINITE_MAX_LOAD_OVER_YIELD P_Y and a contact radius of FE_FINITE_MAX_CONTACT_RADIUS_OVER_R R,
 * whichever comes first. Its mesh ladder (tests/benchmarks/ladder_finite_strain.py, contact elements
 * R/28 to R/57) spreads 1.0 % in force and 3.4 % in contact radius at a/R 0.3, 0.25 % and 2.4 % at
 * a/R 0.45, its step error below 0.1 %; the press reaches a/R 0.48. A window stated beyond these is flagged. */
#define NFD_FE_FINITE_MAX_LOAD_OVER_YIELD 10000.0
#define NFD_FE_FINITE_MAX_CONTACT_RADIUS_OVER_R 0.45

/* The contact models around the normal law (nfd_friction.h), as LAMMPS's pair_style granular
 * names them: normal damping, tangential friction, rolling and twisting resistance. */
#define NFD_DAMPING_NONE 0
#define NFD_DAMPING_VISCOELASTIC 1
#define NFD_DAMPING_TSUJI 2
#define NFD_DAMPING_COEFF_RESTITUTION 3
#define NFD_TANGENTIAL_NONE 0
#define NFD_TANGENTIAL_MINDLIN 1
#define NFD_TANGENTIAL_MINDLIN_RESCALE 2
#define NFD_TANGENTIAL_MINDLIN_FORCE 3
#define NFD_TANGENTIAL_MINDLIN_RESCALE_FORCE 4
#define NFD_ROLLING_NONE 0
#define NFD_ROLLING_SDS 1
#define NFD_TWISTING_NONE 0
#define NFD_TWISTING_MARSHALL 1
#define NFD_TWISTING_SDS 2
/* A spring history leaving the tangent plane by more than FRAME_EPSILON times its Coulomb limit
 * is rotated back into it (LAMMPS's EPSILON of the granular sub-models). */
#define NFD_FRAME_EPSILON 1e-10
#define NFD_FRICTION_HISTORY 8       /* doubles of nfd_friction_history: xi_t[3], xi_roll[3], theta_twist, a_previous */
/* Admissible friction constants: 0 <= mu <= MU_MAX (LAMMPS's classic granular bound). */
#define NFD_MU_MAX 1e4
/* With update = 0, a stored spring's force beyond its cap by at most this fraction is the round-off of
 * a spring set back to the cap at the step that stored it: left as it is (not set back again); and a
 * spring set back is limited to the cap only beyond it by more than this fraction (nfd_friction.h). */
#define NFD_CAP_SLACK 1e-12

#endif

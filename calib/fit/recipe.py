"""The one calibration recipe: (material, R, load plan, mesh level) -> what to calibrate.

Every entry point that runs the FE calibration (``nfdcal calibrate``, scenes and tables, the
master table, the Hertz validation, the stability studies and mesh ladders) takes its
``CalibrationSpec`` from ``calibration_spec`` here, so one material gets one mesh and one load
plan whichever way it is asked for:

* load paths: to each P_max [N] (given, or the reference case's 500/1000/1500 N for the
  reference sphere, else 13.7, 27.4 and 41.2 P_Y: the reference peaks in units of P_Y), loading
  in equal force increments (16 up to the smallest P_max unless the caller says how many up
  to the largest), 16 unloading increments per path, the first load at 0.5 P_Y (20 N for the
  reference sphere, as the reference calibration has always been run);
* mesh: the element size at the contact is a fixed fraction of the largest contact radius a_max
  [m] estimated before any FE run (``sizing_radius``: the FE's radius in finite strain; 1/37 at level
  "default": the reference mesh's 4e-5 m at a_max = 1.48 mm; 1/10 "coarse", 1/74 "fine"), the refined
  zone 1.1 a_max wide and 0.35 a_max deep, so that the discretisation error is the reference one for
  any material and size; the reference sphere (the reference material, R = 0.1 m, a_max inside the
  reference fine zone) keeps the reference mesh family (``REFERENCE_CONTACT_SIZES``), whose meshes and
  results are cached and published.
"""
from __future__ import annotations

import dataclasses
import math
import os
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from calib.fe.kinematics import DEFAULT_KINEMATICS, KINEMATICS
from calib.fe.loadpath import LoadPathPlan
from calib.fit.extrapolation import REFINEMENT
from meshes.hemisphere import HemisphereMeshSpec, estimate_dofs

BASE_GROWTH = HemisphereMeshSpec.growth     # the size growth outside the refined zone, before a refinement
from nfdmodel import ContactPair, Material, limits, reference_case
from nfdmodel.reference_case import is_reference_sphere

# E / sigma_Y a calibration accepts. Below 20 the yield contact itself is wide (a_Y/R =
# (pi/2) A_Y sigma_Y / E* > 0.12, the first-yield formulas) and a small-strain, small-contact model is
# meaningless; an E typed in GPa with sigma_Y in Pa lands there. Above 1e4 the contact zone is
# below 1e-5 R wide and the mesh grading has not been tested.
E_OVER_SIGMA_Y_RANGE = (20.0, 1.0e4)
# The largest contact radius a calibration may reach, over R: beyond it the hemisphere is no
# longer a small-strain, a << R contact problem (Hertz needs a << R; at 0.2 R the contact
# edge has turned by 12 degrees; beyond it the FE's contact stops converging, nfd_limits.h).
CONTACT_RADIUS_LIMIT = limits.FE_MAX_CONTACT_RADIUS_OVER_R     # nfd_limits.h
# The largest load a calibration runs to, over P_Y (DEM users need up to ~1000). Measured
# (results/stability/fe_stability.csv): the force-driven FE loads and unloads to 1000 P_Y at
# E/sigma_Y = 700 and 5000 (ContactSolver.rescue_step takes the steps the ordinary solve cannot);
# softer materials are limited first by CONTACT_RADIUS_LIMIT. Beyond ~400 P_Y the contact is
# fully plastic (P grows with the contact area, Johnson 1985 sec. 6.3) and a_p = Ca <P - P_Y>
# (paper eq. 2.5) is an extrapolation: fit such runs knowingly. The runtime law itself takes any
# P / P_Y (nfdmodel).
MAX_LOAD_OVER_YIELD = limits.FE_MAX_LOAD_OVER_YIELD            # nfd_limits.h
# The FE's reach by kinematics (calib.fe.kinematics.KINEMATICS): (the largest P/P_Y, the largest contact
# radius / R) a calibration runs to, whichever comes first (nfd_limits.h), and the error estimate that
# vouches for it. Finite strain: its mesh and step ladder (tests/benchmarks/ladder_finite_strain.py); on an
# elastic flat too (reach_kinematics), a counter-sphere or a yielding counter keeps the small-strain reach.
REACH = {DEFAULT_KINEMATICS: (MAX_LOAD_OVER_YIELD, CONTACT_RADIUS_LIMIT),
         "finite-strain": (limits.FE_FINITE_MAX_LOAD_OVER_YIELD, limits.FE_FINITE_MAX_CONTACT_RADIUS_OVER_R)}
REACH_ERROR = {DEFAULT_KINEMATICS: "beyond it the small-strain contact stops converging (the bulged surface rolls "
                                   "onto the flat)",
               "finite-strain": "its mesh ladder spreads 1.0 % in force and 3.4 % in contact radius at a/R 0.3, "
                                "0.25 % and 2.4 % at a/R 0.45, its step error below 0.1 %"}
# Ca_hat that estimates the plastic radius for sizing a calibration's mesh (the reference's is 0.0258,
# the master table's span 0.024-0.028).
CA_HAT_ESTIMATE = 0.025


def estimated_contact_radius(pair: ContactPair, force) -> float:
    """Largest contact radius [m] expected at the force P [N] on the loading branch, before any
    FE run (sizes the refined mesh zone): Hertz's a_H below P_Y; above it
    max(1.3 a_H, a_H + Ca_hat <P/P_Y - 1> a_Y), the first the elastoplastic/Hertz radius ratio
    measured up to 41 P_Y (the reference FE: 1.47 / 1.135 mm at 1500 N), the second the
    plastic radius a_p = Ca <P - P_Y> (paper eq. 2.5) that dominates from ~43 P_Y on. Linear in P, it
    overstates the FE's radius beyond ~100 P_Y (2.4x at 2000 P_Y, where the FE's grows as sqrt(P)), so the
    small-strain refined zone it sizes covers the contact; the finite strain's reach check and meshes
    (``sizing_radius``) and ``--kinematics auto`` take the FE's radius, ``fe_contact_radius``."""
    a_hertz = float(pair.hertz_radius(force))
    if force <= pair.P_Y:
        return a_hertz
    return max(1.3 * a_hertz, a_hertz + CA_HAT_ESTIMATE * (force / pair.P_Y - 1.0) * pair.a_Y)


# The FE's contact radius on the loading branch (fe_contact_radius): the mean contact pressure p_m = P / (pi a^2)
# blends Hertz's, P / (pi a_H^2), with a fully plastic one, FE_PLATEAU sigma_Y G(a / R*), as
# p_m^-n = p_Hertz^-n + p_plastic^-n, n = FE_BLEND; G is Jackson & Green's (2005, J. Tribol. 127, 343, eq. 14)
# geometric limit of the flattened sphere's hardness, 1 - exp(-0.82 (a/R)^-0.7), which lowers the mean pressure as
# the contact widens. FE_PLATEAU and FE_BLEND are fitted to the FE's own contact radii (calib/fit/README.md, The
# plan's contact radius; tests/benchmarks/plan_radius.py).
FE_PLATEAU, FE_BLEND = 3.05, 1.9
JACKSON_GREEN_GEOMETRY = (0.82, 0.7)


def fe_contact_radius(pair: ContactPair, force: float) -> float:
    """The contact radius a [m] the FE reaches at the force P [N] on the loading branch, before any FE run (the
    reach check, ``--kinematics auto`` and the plan's a/R*): Hertz's a_H below P_Y; above it the root of

        a = sqrt(P / (pi p_m)),   p_m^-n = (P / (pi a_H^2))^-n + (FE_PLATEAU sigma_Y G(a / R*))^-n,

    n = FE_BLEND, G = 1 - exp(-0.82 (a / R*)^-0.7) (JACKSON_GREEN_GEOMETRY), sigma_Y the yielding body's. Its error
    against the FE: calib/fit/README.md, The plan's contact radius. ``estimated_contact_radius``, which sizes the
    small-strain meshes, overstates it up to 2.4x at 2000 P_Y; finite-strain meshes are sized by this one
    (``sizing_radius``)."""
    a_hertz = float(pair.hertz_radius(force))
    if force <= pair.P_Y:
        return a_hertz
    c1, c2 = JACKSON_GREEN_GEOMETRY
    p_hertz = force / (math.pi * a_hertz ** 2)

    def excess(a):
        p_plastic = FE_PLATEAU * pair.sigma_y * -math.expm1(-c1 * (a / pair.R_star) ** -c2)
        p_mean = (p_hertz ** -FE_BLEND + p_plastic ** -FE_BLEND) ** (-1.0 / FE_BLEND)
        return a - math.sqrt(force / (math.pi * p_mean))

    high = 2.0 * a_hertz                # p_m <= p_Hertz: the root lies above a_H
    while excess(high) < 0.0:
        high *= 2.0
    return float(brentq(excess, a_hertz, high, rtol=1e-10))


def largest_admissible_load(pair: ContactPair, radius_over_R: float = CONTACT_RADIUS_LIMIT,
                            estimate=fe_contact_radius) -> float:
    """The largest P_max [N] whose contact radius, as ``estimate`` (pair, P) [m] has it (default fe_contact_radius,
    the FE's), stays within ``radius_over_R`` R* (default CONTACT_RADIUS_LIMIT, the small-strain reach)."""
    limit = radius_over_R * pair.R_star
    if estimate(pair, pair.P_Y) >= limit:
        return 0.0
    hi = 2.0 * pair.P_Y
    while estimate(pair, hi) < limit:
        hi *= 2.0
    return float(brentq(lambda P: estimate(pair, P) - limit, pair.P_Y, hi, rtol=1e-6))


# The contact radius each kinematics' reach (REACH's a/R) is checked with: finite strain the FE's
# (fe_contact_radius; its ladder's a/R 0.3 and 0.45 are the FE's). Small strain keeps the estimate its 0.2 R
# was set and measured with (estimated_contact_radius, which overstates the FE's by 8 % at E/sigma_Y 100,
# where the FE has 0.185-0.189 R; fe_contact_radius understates the small-strain FE's by up to 6 % near 0.2 R),
# so the small-strain plans (and the vz master table's node windows) stay as measured.
REACH_RADIUS = {DEFAULT_KINEMATICS: estimated_contact_radius, "finite-strain": fe_contact_radius}


def sizing_radius(kinematics: str = DEFAULT_KINEMATICS, counter=None):
    """The contact radius estimate (pair, P) -> a [m] that sizes the meshes of a calibration in ``kinematics``
    (the refined zone, 1.1 a_max; a level's contact element, its ratio x a_max; a graded mesh's smallest
    contact radius): REACH_RADIUS of its reach's kinematics. Finite strain on the rigid flat takes the FE's
    (fe_contact_radius), so its refined zone and elements follow the contact the FE reaches (the
    estimate overstates it 2.3x at 2300 P_Y, calib/fit/README.md, The plan's contact radius); small strain and a
    counter-body keep estimated_contact_radius, whose meshes every small-strain figure was measured on."""
    return REACH_RADIUS[reach_kinematics(kinematics, counter)]


def contact_pair(material: Material, radius: float, counter=None) -> ContactPair:
    """The contact pair of a calibration: the sphere on the rigid flat, or on ``counter``
    (calib.fit.counter.CounterBody: E*, R*, m* of the two bodies, Johnson 1985 eq. 4.22)."""
    return ContactPair.sphere_flat(material, radius) if counter is None else counter.pair(material, radius)


def reach_kinematics(kinematics: str, counter=None) -> str:
    """The kinematics whose reach (REACH) bounds a calibration in ``kinematics``: its own on the rigid flat and on
    an elastic flat, the small strain's on a counter-sphere or a yielding counter-body.

    Why: the two-body contact (calib.fe.two_body) measures the gap along z at the sphere node's reference r. On an
    elastic flat that errs by the flat's surface slope (of order p/E2', a few %) times the node's radial displacement,
    and a finite-strain sphere on a flat 100x stiffer than itself follows the rigid flat's finite-strain FE to
    a/R 0.44 (3090 P_Y, E/sigma_Y 200): approach within 0.74 %, e within 0.36 % (tests/test_pair_reach.py at a
    coarse mesh). Unlike spheres slip by O(a^2/R) and a yielding flat dents: their gap stays small-strain."""
    if counter is None or (counter.R is None and counter.sigma_y is None):
        return kinematics
    return DEFAULT_KINEMATICS


def fe_reach(pair: ContactPair, kinematics: str = DEFAULT_KINEMATICS) -> float:
    """The largest load [N] this FE vouches for on ``pair`` in ``kinematics``: P <= REACH's P/P_Y and a
    contact radius <= REACH's a/R (nfd_limits.h: small strain 1000 P_Y, 0.2 R; finite strain 1e4 P_Y,
    0.45 R), whichever comes first, the radius as REACH_RADIUS[kinematics] estimates it."""
    max_load_over_yield, radius_over_R = REACH[kinematics]
    return min(max_load_over_yield * pair.P_Y, largest_admissible_load(pair, radius_over_R, REACH_RADIUS[kinematics]))


def reach_text(kinematics: str = DEFAULT_KINEMATICS) -> str:
    """'P <= 1000 P_Y and contact radius <= 0.2 R, small strain: beyond it ...': the reach and its
    error estimate, for refusals and plans."""
    load_over_yield, radius_over_R = REACH[kinematics]
    return (f"P <= {load_over_yield:g} P_Y and contact radius <= {radius_over_R:g} R with {kinematics} kinematics: "
            f"{REACH_ERROR[kinematics]}")


# Where the kinematics part (the reference sphere, E/sigma_Y 700, on contact elements R/20 and R/40:
# finite over small strain in force +0.3..1.5 % up to a/R 0.075, +2.7..4.1 % at a/R 0.1, +5..9 % at
# 0.11-0.14, +11..17 % at 0.22-0.25, +14..22 % at 0.3): above this contact radius / R the two differ by
# more than a calibration's E_TARGET (2 %), and finite strain is the one that meets Jackson & Green
# (calib/README.md, Large presses), so a calibration whose plan reaches it takes finite strain.
KINEMATICS_PART_OVER_R = 0.1


def chosen_kinematics(pair: ContactPair, top: float, counter=None) -> str:
    """The kinematics of a calibration to ``top`` [N] on ``pair`` when none is asked for ("auto"):
    finite strain where its contact radius (fe_contact_radius) passes KINEMATICS_PART_OVER_R R* (on the rigid
    flat or an elastic counter-body) or its load the small-strain MAX_LOAD_OVER_YIELD P_Y; small
    strain below, whose figures it keeps."""
    plastic_counter = counter is not None and counter.sigma_y is not None
    if plastic_counter or (fe_contact_radius(pair, top) <= KINEMATICS_PART_OVER_R * pair.R_star
                           and top <= MAX_LOAD_OVER_YIELD * pair.P_Y):
        return DEFAULT_KINEMATICS
    return "finite-strain"


def check_calibration_inputs(material: Material, radius: float, largest_peak: float,
                             pair: ContactPair | None = None, kinematics: str = DEFAULT_KINEMATICS) -> None:
    """ValueError naming the parameter and its allowed range when a calibration cannot be
    meaningful: E / sigma_Y outside E_OVER_SIGMA_Y_RANGE, or a largest load P_max beyond the reach of
    ``kinematics`` (REACH: its P/P_Y, or a contact radius beyond its a/R). ``pair``: the contact
    pair (default: the sphere on a rigid flat; a counter-body's, calib.fit.counter)."""
    ratio = material.E / material.sigma_y
    low, high = E_OVER_SIGMA_Y_RANGE
    if not low <= ratio <= high:
        hint = " (are E and sigma_Y both in Pa?)" if ratio < 1.0 or ratio > 1e6 else ""
        raise ValueError(f"E/sigma_Y out of range for a calibration: need {low:g} <= E/sigma_Y <= "
                         f"{high:g}, got {ratio:.3g} (E = {material.E:g} Pa, sigma_Y = "
                         f"{material.sigma_y:g} Pa){hint}")
    pair = pair or ContactPair.sphere_flat(material, radius)
    load_over_yield, radius_over_R = REACH[kinematics]
    wider = ("" if kinematics != DEFAULT_KINEMATICS or pair.R_star != radius else
             f"; --kinematics finite reaches {fe_reach(pair, 'finite-strain') / pair.P_Y:.4g} P_Y on the rigid flat")
    if largest_peak > load_over_yield * pair.P_Y:
        raise ValueError(f"P_max out of range: the largest load {largest_peak:.4g} N is "
                         f"{largest_peak / pair.P_Y:.4g} P_Y; the FE calibration ({kinematics}) runs to P_max <= "
                         f"{load_over_yield:g} P_Y = {load_over_yield * pair.P_Y:.4g} N for this "
                         f"material and R (tested to there; the NFD model's linear plastic radius is "
                         f"meant for the contained elastoplastic regime, below ~400 P_Y){wider}")
    a_max = REACH_RADIUS[kinematics](pair, largest_peak)
    if a_max > radius_over_R * radius:
        P_limit = largest_admissible_load(pair, radius_over_R, REACH_RADIUS[kinematics])
        model = ("the small-strain model needs" if kinematics == DEFAULT_KINEMATICS else
                 f"the {kinematics} FE vouches for")
        raise ValueError(f"P_max out of range: the largest load {largest_peak:.4g} N "
                         f"({largest_peak / pair.P_Y:.4g} P_Y) needs a contact radius of about "
                         f"{a_max / radius:.3g} R; {model} a_max <= "
                         f"{radius_over_R:g} R, i.e. P_max <= {P_limit:.4g} N "
                         f"({P_limit / pair.P_Y:.4g} P_Y) for this material and R{wider}")


def smallest_radius(radius: float, counter=None) -> float:
    """The radius [m] that bounds the contact (a <= CONTACT_RADIUS_LIMIT x it): the sphere's, or a
    smaller counter-sphere's."""
    return min(radius, counter.R) if counter is not None and counter.R is not None else radius


@dataclass(frozen=True)
class CalibrationSpec:
    """What to calibrate: material, sphere radius R [m], mesh, load paths, Newton tolerance, the
    counter-body (calib.fit.counter.CounterBody; None: the rigid flat), the sphere's isotropic
    hardening (a calib.fe.flow_curve.FlowCurve starting at the material's sigma_y; None: perfectly
    plastic) and the FE's kinematics (calib.fe.kinematics.KINEMATICS; finite strain of the sphere on the
    rigid flat or on an elastic, condensed counter-body, which stays small-strain)."""

    material: Material
    radius: float
    mesh: HemisphereMeshSpec
    plan: LoadPathPlan
    residual_tolerance: float = 1e-8
    contact_radius_method: str = "gap"
    counter: object = None
    hardening: object = None
    kinematics: str = DEFAULT_KINEMATICS

    def __post_init__(self):
        if self.kinematics not in KINEMATICS:
            raise ValueError(f"kinematics must be one of {sorted(KINEMATICS)}, got {self.kinematics!r}")
        if self.kinematics != DEFAULT_KINEMATICS and self.counter is not None and self.counter.sigma_y is not None:
            raise ValueError(f"kinematics {self.kinematics!r} takes the sphere on the rigid flat or on an elastic"
                             f" counter-body: a plastic counter-body needs {DEFAULT_KINEMATICS!r}")
        if not (np.isfinite(self.radius) and self.radius > 0):
            raise ValueError(f"radius R must be a finite length > 0 [m], got {self.radius}")
        if not np.isclose(self.mesh.radius, self.radius, rtol=1e-12):
            raise ValueError(f"mesh radius {self.mesh.radius} differs from the sphere radius R = {self.radius}")
        check_calibration_inputs(self.material, smallest_radius(self.radius, self.counter), self.plan.peaks[-1],
                                 self.pair, reach_kinematics(self.kinematics, self.counter))
        if self.hardening is not None and not math.isclose(self.hardening.sigma_y, self.material.sigma_y, rel_tol=1e-6):
            raise ValueError(f"hardening: the flow curve starts at {self.hardening.sigma_y:g} Pa, not at the material's "
                             f"sigma_y = {self.material.sigma_y:g} Pa")
        # the contact the mesh is sized by (sizing_radius, the reach's radius): a finite-strain plan to 1e4 P_Y reaches
        # a/R 0.39 (brass), inside the refined zone's 0.9 R, where estimated_contact_radius passes R
        a_max = sizing_radius(self.kinematics, self.counter)(self.pair, self.plan.peaks[-1])
        if self.mesh.refined_radius < 0.99 * a_max:   # a contact wider than the fine zone
            raise ValueError(f"mesh refined_radius {self.mesh.refined_radius:.4g} m is smaller than the "
                             f"estimated contact radius {a_max:.4g} m at P_max = {self.plan.peaks[-1]:.4g} N:"
                             f" need refined_radius >= {a_max:.4g} m (calib.fit.recipe.calibration_spec sizes it)")

    @property
    def pair(self) -> ContactPair:
        if self.counter is not None:
            return self.counter.pair(self.material, self.radius)
        return ContactPair.sphere_flat(self.material, self.radius)


MIN_FIT_POINTS = 2   # loading points above P_Y the radius fit needs (a slope and its error)
# The narrowest window the two-mesh radius fit recovers Ca, Kc from (reference sphere, the
# recipe's meshes, nfdcal calibrate --peaks): largest peaks of 1.4, 2.5 and 2.7 P_Y give a failed
# fit or constants that create energy (e = 1.005-1.41), 3 P_Y fits outside the asymptotic range
# of the two meshes, 5 and 8 P_Y fit (Ca_hat 0.021, 0.025; Kc_hat 0.018, 0.019).
MIN_WINDOW_OVER_P_Y = 5.0


def fit_points(plan: LoadPathPlan, P_Y: float) -> int:
    """Loading points of ``plan`` above P_Y [N]: the points the radius fit of Ca and Kc uses."""
    return sum(1 for load in plan.loading_targets() if load > P_Y)


def check_fittable(spec: CalibrationSpec) -> None:
    """ValueError before any FE work when the load plan cannot give Ca and Kc: fewer than
    MIN_FIT_POINTS loading points above P_Y, or a largest peak below MIN_WINDOW_OVER_P_Y P_Y
    (the plastic growth of the contact radius and curvature is then lost in the FE's
    discretisation error). The message names the smallest admissible largest load: the peaks
    scaled up (same increments per peak) until both hold."""
    P_Y = spec.pair.P_Y
    plan = spec.plan
    wide_enough = plan.peaks[-1] >= MIN_WINDOW_OVER_P_Y * P_Y * (1.0 - 1e-12)
    if fit_points(plan, P_Y) >= MIN_FIT_POINTS and wide_enough:
        return

    def scaled(factor):
        return dataclasses.replace(plan, peaks=tuple(p * factor for p in plan.peaks),
                                   loading_step=plan.loading_step * factor)

    low, high = 1.0, 2.0 * P_Y / plan.peaks[-1] + 2.0
    while fit_points(scaled(high), P_Y) < MIN_FIT_POINTS:
        high *= 2.0
    while high - low > 1e-4 * high:
        middle = 0.5 * (low + high)
        low, high = (middle, high) if fit_points(scaled(middle), P_Y) < MIN_FIT_POINTS else (low, middle)
    smallest = max(high * plan.peaks[-1], MIN_WINDOW_OVER_P_Y * P_Y)
    reason = (f"needs at least {MIN_FIT_POINTS} load steps above first yield P_Y = {P_Y:.4g} N, this load plan "
              f"(largest P_max = {plan.peaks[-1]:.4g} N) has {fit_points(plan, P_Y)}" if wide_enough or
              fit_points(plan, P_Y) < MIN_FIT_POINTS else
              f"needs load paths to at least {MIN_WINDOW_OVER_P_Y:g} P_Y = {MIN_WINDOW_OVER_P_Y * P_Y:.4g} N (below, "
              f"the plastic growth of the contact is lost in the FE's discretisation error), this load plan reaches "
              f"{plan.peaks[-1]:.4g} N ({plan.peaks[-1] / P_Y:.3g} P_Y)")
    raise ValueError(f"P_max out of range: the fit of Ca and Kc {reason}; the smallest admissible "
                     f"largest P_max is {smallest:.4g} N ({smallest / P_Y:.3g} P_Y)")


# ----------------------------------------------------------------------------- the recipe
MESH_LEVELS = {"coarse": 0.1, "default": 1.0 / 37.0, "fine": 1.0 / 74.0}   # contact size / a_max
REFERENCE_CONTACT_SIZES = {"coarse": 1.6e-4, "default": 4e-5, "fine": 2e-5}  # [m], R = 0.1 m
# The reference peaks in units of P_Y; the largest is the window assumed for constants that do not
# state theirs (nfd_limits.h's DEFAULT_WINDOW).
DEFAULT_PEAKS_OVER_YIELD = (13.7, 27.4, limits.DEFAULT_WINDOW)
LOADING_STEPS_TO_FIRST_PEAK = 16
UNLOADING_STEPS = 16
REFERENCE_FIRST_LOAD = 20.0                     # [N], 0.55 P_Y of the reference sphere


# Peak memory of an FE calibration against its dofs, measured (peak RSS of ``nfdcal calibrate``:
# 146 MB at 6,880 dofs, 478 MB at 27,186): about 35 MB + 16.5 kB per dof.
MEMORY_BASE_BYTES, MEMORY_BYTES_PER_DOF = 35e6, 16.5e3
MEMORY_SHARE = 0.8            # of the machine's memory one FE run may plan to use


def machine_memory() -> float:
    """Physical memory of the machine running the FE [bytes]."""
    return float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))


def check_machine(mesh: HemisphereMeshSpec) -> None:
    """ValueError before meshing when the mesh's estimated memory exceeds MEMORY_SHARE of this
    machine's, naming the estimate, the limit and the smallest admissible contact element."""
    dofs = estimate_dofs(mesh)
    limit = MEMORY_SHARE * machine_memory()
    need = MEMORY_BASE_BYTES + MEMORY_BYTES_PER_DOF * dofs
    if need <= limit:
        return
    low, high = mesh.contact_size, mesh.contact_size
    while MEMORY_BASE_BYTES + MEMORY_BYTES_PER_DOF * estimate_dofs(
            dataclasses.replace(mesh, contact_size=high)) > limit:
        low, high = high, 2.0 * high
    while high - low > 1e-3 * high:
        middle = 0.5 * (low + high)
        fits = MEMORY_BASE_BYTES + MEMORY_BYTES_PER_DOF * estimate_dofs(
            dataclasses.replace(mesh, contact_size=middle)) <= limit
        low, high = (low, middle) if fits else (middle, high)
    raise ValueError(f"contact_size out of range: a contact element of {mesh.contact_size:.3g} m gives "
                     f"about {dofs:.3g} dofs and needs about {need / 1e9:.3g} GB; one FE run may use "
                     f"{limit / 1e9:.3g} GB ({MEMORY_SHARE:.0%} of the machine's memory): need contact_size >= "
                     f"{high:.3g} m")


def mesh_for(radius: float, a_max: float, *, reference: bool = False, level: str | None = None,
             contact_size: float | None = None,
             contact_size_over_a_max: float | None = None,
             graded_from: float | None = None, elements_per_contact_radius: float | None = None,
             refinement: float = 1.0) -> HemisphereMeshSpec:
    """The hemisphere mesh [m] for a largest contact radius ``a_max`` [m] on a sphere of radius R.

    ``reference``: the reference sphere, which keeps the reference mesh family while a_max fits
    its fine zone and no ratio is asked for. Otherwise the contact element is ``contact_size``, or
    ``contact_size_over_a_max`` (or the ``level``'s ratio) x a_max; the refined zone covers
    1.1 a_max along the surface and 0.35 a_max in depth (at least two elements, at most 0.9 R);
    the far field is graded to R / 10.

    ``graded_from`` a_min [m] with ``elements_per_contact_radius`` N: a graded refined zone
    (meshes.hemisphere, grading), h = a_min / N and grading 1 / N, so every contact radius from a_min
    to a_max spans N elements (load paths over decades of load resolved alike). ``refinement`` r:
    every size divided by r (h, grading, growth and the far field; r < 1 coarsens): a systematic
    refinement, Roache 1998, for an observed order of convergence.
    """
    if not (math.isfinite(refinement) and refinement > 0.0):
        raise ValueError(f"refinement must be a finite number > 0, got {refinement!r}")
    level = level or "default"
    if level not in MESH_LEVELS:
        raise ValueError(f"mesh level must be one of {', '.join(MESH_LEVELS)}, got {level!r}")
    base = HemisphereMeshSpec()
    grading = 0.0
    if graded_from is not None:
        if not (elements_per_contact_radius is not None and elements_per_contact_radius > 1.0
                and 0.0 < graded_from <= a_max):
            raise ValueError(f"a graded mesh needs elements_per_contact_radius > 1 and graded_from in (0, a_max = "
                             f"{a_max:.4g} m], got {elements_per_contact_radius!r}, {graded_from!r}")
        grading = 1.0 / (elements_per_contact_radius * refinement)
        h = graded_from * grading
    elif reference and contact_size_over_a_max is None and a_max <= base.refined_radius and refinement == 1.0:
        mesh = HemisphereMeshSpec(contact_size=contact_size or REFERENCE_CONTACT_SIZES[level])
        check_machine(mesh)
        return mesh
    else:
        ratio = contact_size_over_a_max if contact_size_over_a_max is not None else MESH_LEVELS[level]
        h = (contact_size if contact_size is not None else a_max * ratio) / refinement
    mesh = HemisphereMeshSpec(radius=radius, contact_size=h,
                              refined_radius=min(max(1.1 * a_max, 2 * h), 0.9 * radius),
                              refined_depth=min(max(0.35 * a_max, 2 * h), 0.9 * radius),
                              far_size=max(radius / 10 / refinement, h), growth=BASE_GROWTH / refinement,
                              grading=grading)
    check_machine(mesh)                 # before meshing: a mesh beyond the machine's memory is refused
    return mesh


def calibration_spec(material: Material, radius: float, *, peaks=None, peaks_over_yield=None,
                     level: str | None = None, contact_size: float | None = None,
                     contact_size_over_a_max: float | None = None, loading_steps: int | None = None,
                     unloading_steps: int = UNLOADING_STEPS, counter=None, graded_from: float | None = None,
                     elements_per_contact_radius: float | None = None, refinement: float = 1.0,
                     kinematics: str = DEFAULT_KINEMATICS) -> CalibrationSpec:
    """The CalibrationSpec of ``material`` on a sphere of radius R [m] (see the module docstring).

    peaks [N] or peaks_over_yield [-] (not both); loading_steps: force increments up to the
    largest peak (default 16 up to the smallest); the mesh options (level, contact_size,
    contact_size_over_a_max, graded_from, elements_per_contact_radius, refinement) as in ``mesh_for``. Raises
    ValueError naming the parameter when the material or the load cannot be calibrated.
    ``counter``: calib.fit.counter.CounterBody (None: the rigid flat); the load plan is then in units
    of the pair's P_Y and the mesh sized by the pair's contact radius. ``kinematics``: the FE's
    (calib.fe.kinematics.KINEMATICS), whose reach bounds the load plan (REACH).
    """
    if peaks is not None and peaks_over_yield is not None:
        raise ValueError("give peaks [N] or peaks_over_yield [-], not both")
    pair = contact_pair(material, radius, counter)
    reference = counter is None and is_reference_sphere(material.E, material.nu, radius, material.sigma_y)
    given = peaks
    if peaks is None:
        if peaks_over_yield is None and reference:
            peaks = reference_case.PEAKS
        else:
            peaks = tuple(float(k * pair.P_Y) for k in (peaks_over_yield or DEFAULT_PEAKS_OVER_YIELD))
    peaks = tuple(sorted(float(p) for p in peaks))
    reach, largest_contact = reach_kinematics(kinematics, counter), sizing_radius(kinematics, counter)
    if counter is not None:             # what the two-body FE handles, before sizing a mesh
        def planned(p: ContactPair) -> tuple[float, float]:
            top = peaks if given is not None else [k * p.P_Y for k in (peaks_over_yield or DEFAULT_PEAKS_OVER_YIELD)]
            return (float(p.hertz_radius(min(0.5 * p.P_Y, min(top)))), largest_contact(p, max(top)))

        counter.check(material, radius, planned,
                      f"the load plan {min(0.5 * pair.P_Y, peaks[0]):.4g} .. {peaks[-1]:.4g} N",
                      REACH[reach][1])
    check_calibration_inputs(material, smallest_radius(radius, counter), peaks[-1], pair, reach)   # before a mesh
    a_max = largest_contact(pair, peaks[-1])
    mesh = mesh_for(radius, a_max, reference=reference, level=level, contact_size=contact_size,
                    contact_size_over_a_max=contact_size_over_a_max, graded_from=graded_from,
                    elements_per_contact_radius=elements_per_contact_radius, refinement=refinement)
    loading_step = (peaks[0] / LOADING_STEPS_TO_FIRST_PEAK if loading_steps is None
                    else peaks[-1] / loading_steps)
    first_load = min(REFERENCE_FIRST_LOAD if reference else 0.5 * pair.P_Y, peaks[0])
    return CalibrationSpec(material=material, radius=radius, mesh=mesh,
                           plan=LoadPathPlan(peaks=peaks, loading_step=loading_step,
                                             unloading_steps=unloading_steps, first_load=first_load),
                           counter=counter, kinematics=kinematics)


def coarse_spec(spec: CalibrationSpec, ratio: float | None = None) -> CalibrationSpec:
    """The second mesh of a calibration (calib.fit.extrapolation): the same material, load plan and
    refined zone (at least two elements wide and deep) with the contact element ``ratio`` x h
    (default REFINEMENT = 2); a graded mesh's grading ``ratio`` x too, so every contact radius spans
    1 / ratio the elements (otherwise the two meshes differ at the tip of the graded zone alone)."""
    h = spec.mesh.contact_size * (ratio or REFINEMENT)
    mesh = dataclasses.replace(spec.mesh, contact_size=h, refined_radius=max(spec.mesh.refined_radius, 2 * h),
                               refined_depth=max(spec.mesh.refined_depth, 2 * h),
                               far_size=max(spec.mesh.far_size, h),   # at least two elements, as mesh_for
                               grading=spec.mesh.grading * (ratio or REFINEMENT))
    return dataclasses.replace(spec, mesh=mesh)


def reference_spec(level: str | None = None, contact_size: float | None = None) -> CalibrationSpec:
    """The paper's case: aluminium R = 0.1 m (E = 70 GPa, nu = 0.3, sigma_Y = 100 MPa,
    rho = 2699 kg/m^3), paths ABC, ADE, AFG (P_max = 500, 1000, 1500 N)."""
    return calibration_spec(Material.reference(), reference_case.R, level=level,
                            contact_size=contact_size)


def hertz_mesh(pair: ContactPair, top_load: float, *, reference: bool = False,
               level: str | None = None, contact_size: float | None = None,
               contact_size_over_a_max: float | None = None) -> HemisphereMeshSpec:
    """The mesh of an elastic (Hertz) run to ``top_load`` [N]: ``mesh_for`` at its Hertz radius."""
    return mesh_for(pair.R_star, float(pair.hertz_radius(top_load)), reference=reference,
                    level=level, contact_size=contact_size,
                    contact_size_over_a_max=contact_size_over_a_max)

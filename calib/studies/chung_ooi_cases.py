"""The cases of the DEM benchmark of Chung & Ooi (2011, Granular Matter 13:643), tests 1-8, in the elastic
limit and with the plastic vz law, run through nfdmodel, and the closed forms they are checked against
(the study that runs them and writes results/lammps/chung_ooi.{csv,json,png}: calib.studies.chung_ooi).

The tests (as Chung & Ooi define them; their numbers as the YADE, LIGGGHTS and PySPH
reproductions of the benchmark state them; the paper itself was not at hand, so the comparisons
below are with the closed forms and theories the paper's curves are built on, and test 4 also with
the paper's curves as the PySPH authors digitised them: calib.studies.chung_ooi_paper):

    1  two identical spheres head-on, each at 10 m/s, R = 10 mm: glass (E = 48 GPa, nu = 0.20,
       rho = 2800) and limestone (20 GPa, 0.25, 2500); frictionless
    2  a sphere on a rigid flat at 0.2 m/s, R = 0.1 m: aluminium alloy (70 GPa, 0.30, 2699) and
       magnesium alloy (40 GPa, 0.35, 1800); frictionless
    3  a sphere on a rigid flat at 3.9 m/s, R = 2.5 mm, restitution e = 0.2 .. 1 by normal damping:
       aluminium oxide (380 GPa, 0.23, 4000) and cast iron (100 GPa, 0.25, 7000)
    4  oblique, sphere on flat, constant speed 3.9 m/s at 5..85 deg, R = 2.5 mm, mu = 0.092:
       aluminium oxide and aluminium alloy (70 GPa, 0.33, 2700)
    5  oblique, sphere on flat, v_n = 5 m/s, tangential speeds up to 12 mu v_n, R = 10 mm, mu = 0.3:
       steel (208 GPa, 0.30, 7850) and polyethylene (1 GPa, 0.40, 1400)
    6  sphere on flat, v_n = 0.2 m/s, spin omega R / v_n = 0.1 .. 10, no tangential speed,
       R = 0.1 m, mu = 0.4: aluminium alloy and nylon (2.5 GPa, 0.40, 1000)
    7  two identical spheres, each at 0.2 m/s, spinning at omega and -omega (their contact points
       move alike: no slip), R = 0.1 m, mu = 0.4: aluminium alloy and copper (120 GPa, 0.35, 8900)
    8  a sphere (R = 0.1 m, spin omega R / v_n = 0.1 .. 8, 0.2 m/s) on a sphere five times larger and
       of 1000 times its density at rest, mu = 0.4: aluminium alloy and nylon

The elastic limit: Hertz normal force, ``tangential mindlin NULL 0 mu`` (k_t = 8 G*), no damping
but test 3's ``damping coeff_restitution e``. Each test runs through nfdmodel.oblique_collide
(numpy), the LAMMPS plugin (nfd/hertz pair style, nfd/wall/hertz) and LAMMPS's own ``granular
hertz/material`` (``fix wall/gran`` with E doubled), every impact of a test in one LAMMPS run;
the same time step everywhere (the shortest Hertz contact time / STEPS). References:

    Hertz (tests 1, 2): delta_max = (15 m* v^2 / (16 E* sqrt(R*)))^(2/5), F_max = (4/3) E*
        sqrt(R*) delta_max^(3/2), t_c = 2.8683 (m*^2 / (R* E*^2 v))^(1/5) (Johnson 1985, 11.2;
        nfdmodel.hertz_contact)
    test 3: the restitution that coeff_restitution is built to give, e
    gross sliding (tests 4-6, 8, large angles): v_t' = v_t - mu (v_n + v_n'), omega' = omega +
        5 mu (v_n + v_n') m* / (2 m R) (the Coulomb impulse, v_n' the measured rebound; Maw, Barber
        & Fawcett 1976's limit), where the tangential impulse is mu times the normal one throughout
    no slip (small angles): the Mindlin spring without its Coulomb cap, F_t = -8 G* a x,
        x' = V, V' = F_t (1/m* + sum R^2/I), on the Hertz normal motion, integrated by scipy's
        solve_ivp (rtol 1e-10), independently of nfdmodel: the tangential restitution of the
        contact point beta_0 of Maw, Barber & Fawcett's no-slip regime, met where the impact
        slips so little that its frictional work is below STUCK of the kinetic energy (the capped
        spring always slips as the force vanishes at parting)
    test 7: no slip at all, so v_t' = 0 and omega' = omega exactly

Between no slip and gross sliding, Maw, Barber & Fawcett's theory follows Mindlin-Deresiewicz
micro-slip within the contact area, which LAMMPS's capped spring does not resolve: there the DEM
has no closed form to meet, and the study reports its curve as it is.

Plastic (tests 4-8's oblique impacts with the vz law): test 4's geometry with the paper's
aluminium (E = 70 GPa, nu = 0.3, sigma_y = 100 MPa, Ca_hat = 0.026, Kc_hat = 0.0098) at
PLASTIC_SPEEDS, ``mindlin_rescale/force`` (the Mindlin variant for a plastic law), through
nfdmodel and nfd/wall/vz. Checked against the trends Wu, Thornton & Li (2009) report for
elastoplastic oblique impacts: the normal restitution does not depend on the angle (it equals
the head-on one at the same normal speed), and e_t against Psi = tan(angle) / (mu (1 + e_n))
follows 1 - 1/Psi wherever the contact slides throughout, whatever the speed (the normalisation
that puts plastic impacts on the elastic curve). Thornton, Cummins & Cleary (2013) compare normal
models; their curves were not at hand, so no number of theirs is compared.
SI units; angles in degrees.
"""
from __future__ import annotations

import dataclasses
import math
import warnings
from dataclasses import dataclass

import numpy as np

from nfdmodel import ContactPair, Material, VZParams
from nfdmodel.friction import Friction, shear_coefficient
from nfdmodel.hertz_contact import hertz_impact_approach, hertz_impact_time
from nfdmodel.oblique import oblique_collide

STEPS = 1000                    # steps per shortest contact
STUCK = 1e-4                    # frictional work / kinetic energy of an impact that counts as not slipping
HARD = 1e11                     # Pa: a yield stress no impact here reaches (the elastic limit's sigma_y)
PLASTIC_SPEEDS = (0.02, 0.1, 0.5)   # m/s: about 12, 60, 300 v_Y of the paper's aluminium
PLASTIC_MU = 0.3
MATERIALS = {"glass": (48e9, 0.20, 2800.0), "limestone": (20e9, 0.25, 2500.0),
             "aluminium alloy": (70e9, 0.30, 2699.0), "magnesium alloy": (40e9, 0.35, 1800.0),
             "aluminium oxide": (380e9, 0.23, 4000.0), "cast iron": (100e9, 0.25, 7000.0),
             "aluminium alloy, nu 0.33": (70e9, 0.33, 2700.0), "steel": (208e9, 0.30, 7850.0),
             "polyethylene": (1e9, 0.40, 1400.0), "nylon": (2.5e9, 0.40, 1000.0),
             "copper": (120e9, 0.35, 8900.0)}


@dataclass(frozen=True)
class Case:
    """One test on one material: impacts at relative speed ``speed`` and ``angle`` [deg] with
    spins omega, omega_partner [rad/s] (arrays), a flat (partner None) or a sphere (R_j, density
    ratio), friction mu, damping restitution e (None: none), the variable the test sweeps."""

    test: int
    material: str
    R: float
    speed: np.ndarray
    angle: np.ndarray
    omega: np.ndarray
    omega_partner: np.ndarray
    mu: float
    partner: tuple[float, float] | None = None      # (R_j, rho_j / rho)
    restitution: np.ndarray | None = None
    variable: str = ""
    values: np.ndarray | None = None

    @property
    def solid(self) -> Material:
        E, nu, rho = MATERIALS[self.material]
        return Material(E, nu, HARD, rho)

    def bodies(self) -> tuple[float, float, float, float]:
        """(R_i, m_i, R_j, m_j); a flat: R_j = 0, m_j = inf."""
        m = self.solid.sphere_mass(self.R)
        if self.partner is None:
            return self.R, m, 0.0, math.inf
        R_j, ratio = self.partner
        return self.R, m, R_j, ratio * self.solid.sphere_mass(R_j)     # (a density beyond solids': test 8)

    def pair(self) -> ContactPair:
        if self.partner is None:
            return ContactPair.sphere_flat(self.solid, self.R)
        _, m_i, R_j, m_j = self.bodies()
        pair = ContactPair.sphere_sphere(self.solid, self.R, self.solid, R_j)
        return dataclasses.replace(pair, mass_star=m_i * m_j / (m_i + m_j))


def cases() -> list[Case]:
    """The eight tests on their two materials each (module doc)."""
    out = []

    def sweep(test, material, R, speed, angle, omega=0.0, omega_partner=0.0, mu=0.0, partner=None,
              restitution=None, variable="", values=None):
        arrays = np.broadcast_arrays(*(np.atleast_1d(np.asarray(a, dtype=float))
                                       for a in (speed, angle, omega, omega_partner)))
        out.append(Case(test, material, R, *arrays, mu=mu, partner=partner,
                        restitution=None if restitution is None else np.asarray(restitution, dtype=float),
                        variable=variable, values=np.asarray(values if values is not None else arrays[1])))

    for material in ("glass", "limestone"):
        sweep(1, material, 0.01, 20.0, 0.0, partner=(0.01, 1.0), variable="head-on", values=[0.0])
    for material in ("aluminium alloy", "magnesium alloy"):
        sweep(2, material, 0.1, 0.2, 0.0, variable="head-on", values=[0.0])
    e = np.array([0.2, 0.4, 0.6, 0.8, 1.0])
    for material in ("aluminium oxide", "cast iron"):
        sweep(3, material, 0.0025, 3.9, 0.0 * e, restitution=e, variable="e_in", values=e)
    angles = np.array([2.0, 5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0, 45.0, 50.0, 60.0, 70.0, 80.0, 85.0])
    for material in ("aluminium oxide", "aluminium alloy, nu 0.33"):
        sweep(4, material, 0.0025, 3.9, angles, mu=0.092, variable="angle", values=angles)
    ratio = np.array([0.05, 0.25, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0, 5.0, 6.0, 8.0, 10.0, 12.0])
    for material in ("steel", "polyethylene"):       # tan(angle) = v_t / v_n = ratio mu
        tangential = ratio * 0.3 * 5.0
        sweep(5, material, 0.01, np.hypot(5.0, tangential), np.degrees(np.arctan2(tangential, 5.0)), mu=0.3,
              variable="v_t/(mu v_n)", values=ratio)
    spin = np.array([0.1, 0.25, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 7.0, 10.0])
    for material in ("aluminium alloy, nu 0.33", "nylon"):
        sweep(6, material, 0.1, 0.2, 0.0 * spin, omega=spin * 0.2 / 0.1, mu=0.4, variable="omega R/v_n",
              values=spin)
    for material in ("aluminium alloy, nu 0.33", "copper"):
        w = np.array([0.175, 0.5, 1.0, 2.0, 5.0, 10.0, 21.0])
        sweep(7, material, 0.1, 0.4, 0.0 * w, omega=w, omega_partner=-w, mu=0.4, partner=(0.1, 1.0),
              variable="omega", values=w)
    for material in ("aluminium alloy, nu 0.33", "nylon"):
        spin8 = np.array([0.1, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0])
        sweep(8, material, 0.1, 0.2, 0.0 * spin8, omega=spin8 * 0.2 / 0.1, mu=0.4, partner=(0.5, 1000.0),
              variable="omega R/v_n", values=spin8)
    return out


def hertz_closed_form(pair: ContactPair, v: float) -> dict:
    """delta_max [m], F_max [N], t_c [s] of an elastic Hertz impact at relative speed v (module doc)."""
    delta = hertz_impact_approach(pair.mass_star, pair.hertz_stiffness, v)
    return {"delta_max": delta, "F_max": pair.hertz_stiffness * delta ** 1.5,
            "t_c": hertz_impact_time(pair.mass_star, pair.R_star, pair.E_star, v)}


def time_step(case: Case) -> float:
    """The shortest Hertz contact time of the case's impacts / STEPS."""
    v_n = case.speed * np.cos(np.radians(case.angle))
    return hertz_closed_form(case.pair(), float(v_n.max()))["t_c"] / STEPS


def friction_of(case: Case, restitution: float | None = None, variant: str = "mindlin") -> Friction:
    damping = {} if restitution is None or restitution >= 1.0 else dict(damping="coeff_restitution",
                                                                       damping_value=restitution)
    if case.mu == 0.0:
        return Friction(**damping)
    other = None if case.partner is None else case.solid
    return Friction.mindlin(case.mu, case.solid, other, variant=variant, **damping)


def run_nfdmodel(case: Case, dt: float) -> dict:
    """nfdmodel.oblique_collide of every impact of the case (elastic limit): per-impact arrays."""
    R_i, m_i, R_j, m_j = case.bodies()
    partner = None if case.partner is None else (R_j, m_j)
    if case.restitution is None:
        results = [oblique_collide("hertz", case.pair(), friction_of(case), case.speed, case.angle, case.omega,
                                   dt=dt, partner=partner, omega_partner=case.omega_partner)]
        index = [np.arange(case.speed.size)]
    else:           # one damping model per restitution
        results = [oblique_collide("hertz", case.pair(), friction_of(case, e), case.speed[k:k + 1],
                                   case.angle[k:k + 1], case.omega[k:k + 1], dt=dt, partner=partner,
                                   omega_partner=case.omega_partner[k:k + 1])
                   for k, e in enumerate(case.restitution)]
        index = [np.array([k]) for k in range(case.restitution.size)]
    fields = ("v_n_out", "v_t_out", "omega_out", "omega_partner_out", "e_n", "e_t", "beta", "P_max",
              "contact_time", "delta_max", "angle_out", "normal_turn", "velocities", "kinetic_energy_lost",
              "work_normal", "work_friction", "impulse_n", "impulse_t")
    out = {name: np.concatenate([np.atleast_1d(getattr(r, name)) for r in results]) for name in fields}
    order = np.concatenate(index)
    return {name: values[np.argsort(order)] for name, values in out.items()}


def no_slip(case: Case) -> np.ndarray:
    """beta_0 of each impact: the contact point's tangential restitution -V'/V of the uncapped
    Mindlin spring on the Hertz normal motion (module doc), by scipy's solve_ivp."""
    from scipy.integrate import solve_ivp
    pair = case.pair()
    R_i, m_i, R_j, m_j = case.bodies()
    k_t = shear_coefficient(case.solid, None if case.partner is None else case.solid)
    # dV/dt = F_t (1/m* + R_i^2/I_i + R_j^2/I_j), I = 2 m R^2 / 5
    factor = 1.0 / pair.mass_star + 2.5 / m_i + (0.0 if case.partner is None else 2.5 / m_j)
    stiffness = pair.hertz_stiffness
    out = []
    for speed, angle, w_i, w_j in zip(case.speed, case.angle, case.omega, case.omega_partner):
        v_n = speed * math.cos(math.radians(angle))
        slip = speed * math.sin(math.radians(angle)) - (R_i * w_i + R_j * w_j)
        if slip == 0.0:
            out.append(math.nan)
            continue

        def rates(t, y):
            delta, rate, x, V = y
            overlap = max(delta, 0.0)
            F_t = -k_t * math.sqrt(pair.R_star * overlap) * x
            return [rate, -stiffness * overlap ** 1.5 / pair.mass_star, V, F_t * factor]

        def parted(t, y):
            return y[0]
        parted.terminal, parted.direction = True, -1
        t_c = hertz_closed_form(pair, v_n)["t_c"]
        sol = solve_ivp(rates, (0.0, 2.0 * t_c), [0.0, v_n, 0.0, slip], rtol=1e-10, atol=1e-14 * t_c * v_n,
                        events=parted, first_step=1e-6 * t_c, max_step=t_c / 200)
        out.append(-sol.y[3, -1] / slip)
    return np.array(out)


def references(case: Case, model: dict) -> dict:
    """The closed forms of the case's impacts (module doc), per impact (nan where none applies)."""
    R_i, m_i, R_j, m_j = case.bodies()
    pair = case.pair()
    v_n = case.speed * np.cos(np.radians(case.angle))
    v_t = case.speed * np.sin(np.radians(case.angle))
    nan = np.full(case.speed.size, np.nan)
    ref = {"delta_max": nan.copy(), "F_max": nan.copy(), "t_c": nan.copy(), "e_n": nan.copy(),
           "v_t_out_sliding": nan.copy(), "omega_out_sliding": nan.copy(), "beta_no_slip": nan.copy()}
    if case.test in (1, 2):
        closed = hertz_closed_form(pair, float(v_n[0]))
        for key in ("delta_max", "F_max", "t_c"):
            ref[key][:] = closed[key]
        ref["e_n"][:] = 1.0
    if case.test == 3:
        ref["e_n"] = case.restitution.copy()
    if case.test >= 4:
        slip_in = v_t - (R_i * case.omega + R_j * case.omega_partner)
        direction = np.sign(slip_in)
        impulse = case.mu * (v_n + model["v_n_out"])        # per unit reduced mass, the rebound measured
        ref["v_t_out_sliding"] = v_t - direction * impulse
        ref["omega_out_sliding"] = case.omega + direction * 2.5 * impulse * pair.mass_star / (m_i * R_i)
        ref["beta_no_slip"] = no_slip(case)
        ref["e_n"][:] = 1.0
    if case.test == 7:
        ref["v_t_out_sliding"][:] = 0.0      # no slip: nothing changes tangentially
        ref["omega_out_sliding"] = case.omega.copy()
    # which impacts slid throughout (the Coulomb impulse), which never slid (no frictional work)
    sliding = np.isclose(np.abs(model["impulse_t"]), case.mu * model["impulse_n"], rtol=1e-9, atol=0.0)
    ref["slid_throughout"] = sliding & (case.mu > 0.0)
    kinetic = 0.5 * pair.mass_star * case.speed ** 2
    ref["stuck"] = (np.abs(model["work_friction"]) < STUCK * kinetic) & (case.mu > 0.0) & np.isfinite(
        ref["beta_no_slip"])
    return ref


def plastic_cases() -> list[Case]:
    """Test 4's geometry (R = 2.5 mm, flat) with the paper's aluminium at PLASTIC_SPEEDS."""
    angles = np.array([0.0, 5.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0, 85.0])
    return [Case(4, "aluminium alloy", 0.0025, np.full(angles.size, v), angles, np.zeros(angles.size),
                 np.zeros(angles.size), mu=PLASTIC_MU, variable="angle", values=angles) for v in PLASTIC_SPEEDS]


def plastic_params() -> tuple[VZParams, Material]:
    material = Material.reference()
    return VZParams.from_dimensionless(ContactPair.sphere_flat(material, 0.0025), 0.026, 0.0098), material


def run_plastic(case: Case, dt: float) -> dict:
    params, material = plastic_params()
    friction = Friction.mindlin(PLASTIC_MU, material, variant="mindlin_rescale/force")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")          # RangeWarning: beyond the calibrated window, said in the summary
        r = oblique_collide("vz", params, friction, case.speed, case.angle, 0.0, dt=dt)
        head_on = oblique_collide("vz", params, friction, case.speed * np.cos(np.radians(case.angle)), 0.0, 0.0,
                                  dt=dt)
    return {"e_n": r.e_n, "e_t": r.e_t, "beta": r.beta, "omega_out": r.omega_out, "angle_out": r.angle_out,
            "P_max_over_P_Y": r.P_max / params.pair.P_Y, "e_n_head_on": head_on.e_n, "velocities": r.velocities,
            "v_t_out": r.v_t_out, "v_n_out": r.v_n_out, "slid_throughout": np.isclose(
                np.abs(r.impulse_t), PLASTIC_MU * r.impulse_n, rtol=1e-9, atol=0.0) & (case.angle > 0)}

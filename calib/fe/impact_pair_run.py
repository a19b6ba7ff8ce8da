"""One impact of the sphere on a deformable counter-body, from first touch to free flight.

The time loop is calib.fe.impact's (time step dt = t_c / steps_per_contact, halving on failure,
separation located by the secant on P^(2/3), a tenth of t_c of free flight after it) on
calib.fe.impact_pair.PairImpactSolver's steps; t_c is the quasi-static estimate of the pair (PairImpactSolver.contact_pair)
(Thornton's law with the pair's R*, E*, reduced mass m* and the yield point of the body with the
lower A_Y(nu) sigma_Y; Hertz's 2.8683 (m*^2 / (R* E*^2 v_in))^(1/5) below first yield; Johnson
1985, eq. 11.24; Thornton 1997).

Outputs (PairImpactResult), v_in the relative normal velocity of approach [m/s]:
  e          = v_sep / v_in, v_sep the relative normal velocity of separation of the two centres
               of mass (each t_k . M v / m_k) after separation; against a held block, the
               sphere's own rebound velocity [-]
  alpha(t)   = the approach of the centres of mass (calib.fe.impact_pair.PairImpactSolver.approach) [m]
  P_max, alpha_max: parabola through the largest sample and its neighbours [N], [m]
  momentum_change: |p_out - p_in| / (m1 v1) of the two free bodies' total z-momentum [-] (None
               against a held block, whose far face takes momentum)
  energies [J]: kinetic in (both bodies); the rigid-body kinetic energy out sum m_k v_k^2 / 2;
               plastic work sum sigma_Yk int eps_p dV; internal energy left E_left = KE - KE_out
               + U_el (vibration of both bodies, with the residual-stress energy of a yielded
               body); balance residual KE_in - KE_out - W_p - E_left (the discrete energy
               identity of the trapezoidal rule: the integrator's internal-work error, the
               contact forces' work and the Newton residual's, each reported).
Units: SI.
"""
from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import Callable

from calib.fe.impact import DEFAULT_STEPS_PER_CONTACT, _peak, impact_run
from calib.fe.impact_pair import PairImpactSolver
from nfdmodel.hertz_contact import hertz_impact_approach, hertz_impact_time, hertz_stiffness


@dataclass(frozen=True)
class PairImpactResult:
    """One pair impact (module docstring: definitions); ``history``: per step arrays time, P,
    alpha, contact_radius, kinetic, elastic, plastic_work [SI]."""

    v_in: float
    v1_in: float
    v2_in: float
    e: float
    v_sep: float
    P_max: float
    time_P_max: float
    contact_time: float
    alpha_max: float
    contact_radius_max: float
    momentum_change: float | None
    kinetic_in: float
    kinetic_out: float
    plastic_work: float
    energy_left: float
    balance_residual: float
    internal_work_error: float
    contact_work: float
    solver_residual_work: float
    recontacts: int
    dt: float
    steps: int
    newton_iterations: int
    halvings: int
    masses: tuple
    reduced_mass: float
    E_star: float
    R_star: float
    dofs: int
    wall_time_s: float
    cpu_time_s: float
    history: dict = field(repr=False, default_factory=dict)

    def record(self) -> dict:
        """The scalars as one JSON-able dict."""
        return {k: (list(v) if isinstance(v, tuple) else v) for k, v in asdict(self).items() if k != "history"}


def hertz_pair_impact(E_star: float, R_star: float, mass: float, v_in: float) -> dict:
    """Hertz's elastic impact of a pair (Johnson 1985, section 11.4): with k = (4/3) E* sqrt(R*),
    alpha_max = (15 m* v^2 / (16 E* sqrt(R*)))^(2/5) [m], P_max = k alpha_max^(3/2) [N],
    t_c = 2.8683 (m*^2 / (R* E*^2 v))^(1/5) [s] (E* [Pa], R* [m], m* [kg], v [m/s]; nfdmodel.hertz_contact)."""
    k = hertz_stiffness(R_star, E_star)
    alpha = hertz_impact_approach(mass, k, v_in)
    return {"alpha_max": alpha, "P_max": k * alpha ** 1.5,
            "contact_time": hertz_impact_time(mass, R_star, E_star, v_in)}


def run_pair_impact(solver: PairImpactSolver, v_in: float, *, steps_per_contact: int = DEFAULT_STEPS_PER_CONTACT,
                    progress: Callable[[str], None] | None = None) -> PairImpactResult:
    """The impact at the relative velocity v_in [m/s] > 0 (module docstring); raises
    calib.fe.impact.ImpactNotConverged as run_impact does, ValueError on bad input."""
    run = impact_run(solver, v_in, steps_per_contact=steps_per_contact, progress=progress)
    history, initial, state = run.history(), run.initial, run.state
    time_P_max, P_max = _peak(history["time"], history["P"])
    _, alpha_max = _peak(history["time"], history["alpha"])
    v1, v2 = solver.initial_velocities(v_in)
    v_sep = solver.separation_velocity(state.velocity)
    free = (0, 1) if solver.free_counter else (0,)
    kinetic_out = sum(0.5 * solver.masses[k] * solver.body_velocity(state.velocity, k) ** 2 for k in free)
    momentum = [sum(solver.masses[k] * solver.body_velocity(s.velocity, k) for k in free) for s in (initial, state)]
    left = state.kinetic_energy - kinetic_out + state.elastic_energy
    return PairImpactResult(
        v_in=float(v_in), v1_in=v1, v2_in=v2, e=v_sep / v_in, v_sep=v_sep, P_max=P_max, time_P_max=time_P_max,
        contact_time=run.contacts[0], alpha_max=alpha_max, contact_radius_max=float(history["contact_radius"].max()),
        momentum_change=(abs(momentum[1] - momentum[0]) / (solver.masses[0] * v1) if solver.free_counter else None),
        kinetic_in=initial.kinetic_energy, kinetic_out=kinetic_out, plastic_work=state.plastic_work,
        energy_left=left, balance_residual=initial.kinetic_energy - kinetic_out - state.plastic_work - left,
        internal_work_error=state.work_internal - state.elastic_energy - state.plastic_work,
        contact_work=state.work_contact, solver_residual_work=state.work_residual, recontacts=len(run.contacts) - 1,
        dt=run.dt, steps=len(run.rows) - 1, newton_iterations=run.newton_iterations, halvings=run.halvings,
        masses=tuple(solver.masses), reduced_mass=solver.mass, E_star=float(solver.material.E), R_star=solver.radius,
        dofs=solver.n_q, wall_time_s=run.wall_time_s, cpu_time_s=run.cpu_time_s, history=history)

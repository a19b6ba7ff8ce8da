"""One impact of the whole sphere on the rigid frictionless flat, from first touch to free flight.

The sphere (calib.fe.newmark.ImpactSolver) flies at v_in toward the flat and touches it with its
bottom pole at t = 0: the flight before is a rigid translation, exact, so the run starts there
(contact onset exactly at t = 0). Each time step is Newmark's average acceleration with the exact
active set (calib.fe.newmark states the scheme and why).

The time loop (``impact_run``) serves every Newmark configuration: this sphere on the rigid flat
(``run_impact``, the record below) and the pair of calib.fe.impact_pair (calib.fe.impact_pair_run).
Time step: dt = t_c / steps_per_contact, t_c the contact time of the quasi-static estimate
(nfdmodel.collision_reference with Thornton's law on the configuration's contact_pair(), Hertz's 2.8683 (m^2 / (R E*^2 v_in))^(1/5)
below first yield; Thornton 1997). A step whose Newton or active set fails is cut in half and
retried from the committed state (down to dt / 64); the step then doubles back to dt. The error of dt is measured, not assumed:
calib.studies.impact runs the same impact at several dt.

Separation, inside the step: near separation the contact unloads elastically and Hertz's
P ~ (approach - residual)^(3/2) holds with the approach linear in time, so P^(2/3) is linear in t.
When a step ends out of contact, the step is re-solved from the last state in contact, to the
zero of the line through the last two (t, P^(2/3)); repeated (a secant) until the force left is
below 1e-4 P_max, then the separation time t_sep is that line's zero. The contact time is t_sep.
The run then continues for a tenth of the estimated contact time (at least 5 steps) to catch a
re-contact (vibrations of the pole); a re-contact restarts the contact phase, and is counted.

Outputs (ImpactResult), with u_cm = t . M q / m the z-displacement of the centre of mass:
  e         = v_cm(out) / v_in, v_cm = t . M v / m after separation (rigid-body velocity) [-]
  alpha(t)  = -u_cm(t): the approach of the centre of mass since first touch, the DEM overlap of
              the sphere and the flat; alpha_max its largest value [m]
  P_max     = largest contact force (a parabola through the largest sampled P and its two
              neighbours; alpha_max alike) [N]
  dent      = u_z(pole) - u_cm in the static equilibrium of the sphere with its plastic strains,
              free of load (what the dent is once the vibrations have died) [m]
  energies  [J]: kinetic in m v_in^2 / 2; out m v_cm^2 / 2; plastic work sigma_Y int eps_p dV;
              the residual-stress energy U_res of that static equilibrium; the vibration energy
              E_vib = KE - KE_out + U_el - U_res (kinetic energy about the centre of mass plus the
              strain energy above the residual state; K-orthogonality makes the split exact);
              balance residual = KE_in - KE_out - W_p - U_res - E_vib. It holds to the time
              discretisation: it equals the integrator's trapezoidal internal work less
              (U_el + W_p), less the work of the discrete contact forces (zero for the exact
              problem), plus the Newton residual's work; each is reported.
Units: SI.
"""
from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass, field
from typing import Callable

import numpy as np

from calib.fe.linsolve import factorize
from calib.fe.newmark import ImpactSolver, ImpactState, ImpactStep, sphere_flat_pair
from nfdmodel import collision_reference

DEFAULT_STEPS_PER_CONTACT = 100
SEPARATION_FORCE = 1e-4          # the separation search ends when P < this x P_max ...
SEPARATION_TIME = 1e-4           # ... or the bracket is shorter than this x dt
MAX_SEPARATION_STEPS = 12
HALVINGS = 6                     # a failed step is cut in half at most this often
AFTER_SEPARATION = 0.1           # free flight after separation, x the estimated contact time


class ImpactNotConverged(RuntimeError):
    """A time step failed even at dt / 2^HALVINGS, or the sphere did not separate in time."""


@dataclass(frozen=True)
class ImpactResult:
    """One impact (module docstring: definitions). Scalars SI (cpu_time_s: this process's CPU time,
    the run time on a shared machine); ``history``: per step arrays
    time, P, alpha, contact_radius, kinetic, elastic, plastic_work [SI]."""

    v_in: float
    e: float
    v_out: float
    P_max: float
    time_P_max: float
    contact_time: float
    alpha_max: float
    dent: float
    contact_radius_max: float
    kinetic_in: float
    kinetic_out: float
    plastic_work: float
    residual_stress_energy: float
    vibration_energy: float
    balance_residual: float
    internal_work_error: float
    contact_work: float
    solver_residual_work: float
    recontacts: int
    dt: float
    steps: int
    newton_iterations: int
    halvings: int
    mass: float
    dofs: int
    wall_time_s: float
    cpu_time_s: float
    history: dict = field(repr=False, default_factory=dict)

    def record(self) -> dict:
        """The scalars as one JSON-able dict."""
        return {k: v for k, v in asdict(self).items() if k != "history"}


def contact_time_estimate(material, rho: float, radius: float, v_in: float) -> float:
    """The quasi-static contact time [s] of the sphere's impact on the rigid flat at v_in [m/s]:
    Thornton's (Hertz's below first yield; an elastic material, one without sigma_y, never yields)."""
    pair = sphere_flat_pair(material, rho, radius)
    return float(collision_reference("thornton", pair, [v_in]).contact_time_estimate[0])


def _peak(times, values) -> tuple[float, float]:
    """(time, value) of the maximum: a parabola through the largest sample and its neighbours."""
    k = int(np.argmax(values))
    if k == 0 or k == len(values) - 1:
        return float(times[k]), float(values[k])
    t, y = np.asarray(times[k - 1:k + 2]), np.asarray(values[k - 1:k + 2])
    c2, c1, c0 = np.polyfit(t - t[1], y, 2)
    if not c2 < 0:
        return float(times[k]), float(values[k])
    s = float(np.clip(-c1 / (2 * c2), t[0] - t[1], t[2] - t[1]))
    return float(t[1] + s), float(c0 + c1 * s + c2 * s * s)


def _zero_of_line(t0, P0, t1, P1) -> float:
    """The time where the line through (t0, P0^(2/3)), (t1, P1^(2/3)) reaches zero (inf if it
    does not fall)."""
    y0, y1 = P0 ** (2.0 / 3.0), P1 ** (2.0 / 3.0)
    return t1 + y1 * (t1 - t0) / (y0 - y1) if y0 > y1 else math.inf


class _Run:
    """The time loop of one impact (``run_impact``): every committed state is one history row."""

    def __init__(self, solver: ImpactSolver, v_in: float, dt: float, force_scale: float,
                 progress: Callable[[str], None] | None):
        self.solver, self.v_in, self.dt, self.force_scale = solver, v_in, dt, force_scale
        self.say = progress or (lambda message: None)
        self.rows: list[dict] = []
        self.newton = self.halvings = 0

    def record(self, state: ImpactState, step: ImpactStep | None = None) -> None:
        self.rows.append({"time": state.time, "P": state.force,
                          "alpha": self.solver.approach(state.q),
                          "contact_radius": step.contact_radius if step else 0.0,
                          "kinetic": state.kinetic_energy, "elastic": state.elastic_energy,
                          "plastic_work": state.plastic_work})

    def solve(self, state: ImpactState, h: float) -> ImpactStep:
        """One step of h [s] from ``state`` (an unconverged step is returned as such, never raised)."""
        step = self.solver.solve_step(state, h, self.force_scale)
        self.newton += step.newton_iterations
        return step

    def failed(self, state: ImpactState, h: float, step: ImpactStep) -> float:
        """The next, halved step after a failure; ImpactNotConverged below dt / 2^HALVINGS."""
        if h <= self.dt / 2 ** HALVINGS * (1 + 1e-9):
            raise ImpactNotConverged(f"time step at t = {state.time:.6g} s failed at dt / {2 ** HALVINGS}:"
                                     f" {step.message}")
        self.halvings += 1
        return 0.5 * h

    def separate(self, inside: ImpactState, outside: ImpactStep) -> tuple[ImpactStep, float]:
        """Land on the separation found between ``inside`` (in contact, the last recorded row) and
        ``outside`` (out of contact): the out-of-contact step to continue from and t_sep [s]."""
        P_max = max(row["P"] for row in self.rows)
        before = self.rows[-2] if len(self.rows) > 1 else {"time": 0.0, "P": 0.0}
        t_before, P_before = before["time"], before["P"]
        upper = outside.state.time
        for _ in range(MAX_SEPARATION_STEPS):
            if inside.force <= SEPARATION_FORCE * P_max or upper - inside.time <= SEPARATION_TIME * self.dt:
                break
            span = upper - inside.time
            aim = _zero_of_line(t_before, P_before, inside.time, inside.force) - inside.time
            tau = float(np.clip(0.99 * aim if math.isfinite(aim) else 0.5 * span, 0.02 * span, 0.98 * span))
            trial = self.solve(inside, tau)
            while not trial.converged:
                tau = self.failed(inside, tau, trial)
                trial = self.solve(inside, tau)
            if trial.state.in_contact:
                t_before, P_before = inside.time, inside.force
                inside = trial.state
                self.record(inside, trial)
            else:
                outside, upper = trial, trial.state.time
        remainder = _zero_of_line(t_before, P_before, inside.time, inside.force) - inside.time
        t_sep = inside.time + float(np.clip(remainder, 0.0, upper - inside.time))
        return outside, t_sep


@dataclass(frozen=True)
class ImpactRun:
    """What one impact's time loop produced, for any Newmark configuration: v_in [m/s], dt [s], the
    ``initial`` and final ``state``, the separation times ``contacts`` [s], the history rows, the
    Newton iterations and step halvings, the wall and CPU times [s] of the loop."""

    v_in: float
    dt: float
    initial: ImpactState
    state: ImpactState
    contacts: list
    rows: list
    newton_iterations: int
    halvings: int
    wall_time_s: float
    cpu_time_s: float

    def history(self) -> dict:
        """The rows as per-step arrays (time, P, alpha, contact_radius, kinetic, elastic, plastic_work)."""
        return {key: np.array([row[key] for row in self.rows]) for key in self.rows[0]}


def impact_run(solver, v_in: float, *, steps_per_contact: int = DEFAULT_STEPS_PER_CONTACT,
               progress: Callable[[str], None] | None = None, start: ImpactState | None = None) -> ImpactRun:
    """The time loop (module docstring) of ``solver``'s bodies (a calib.fe.newmark.NewmarkSolver
    configuration) meeting at v_in [m/s] > 0: dt from the quasi-static contact time of
    ``solver.contact_pair()`` (Thornton's law); raises ImpactNotConverged if a step fails at dt / 64
    or the bodies have not separated after five estimated contact times, ValueError on bad input.
    ``start``: the state at first touch (None: solver.initial_state(v_in); a later impact of a
    series, calib.fe.impact_repeat.rest_state)."""
    started, cpu = time.perf_counter(), time.process_time()
    if not (isinstance(v_in, (int, float)) and math.isfinite(v_in) and v_in > 0):
        raise ValueError(f"v_in must be > 0 m/s, got {v_in!r}")
    if not (isinstance(steps_per_contact, int) and steps_per_contact >= 10):
        raise ValueError(f"steps_per_contact must be an integer >= 10, got {steps_per_contact!r}")
    t_c = float(collision_reference("thornton", solver.contact_pair(), [v_in]).contact_time_estimate[0])
    dt = t_c / steps_per_contact
    run = _Run(solver, float(v_in), dt, solver.mass * v_in / t_c, progress)
    initial = solver.initial_state(v_in) if start is None else start
    state, contacts = time_loop(run, initial, t_c)
    return ImpactRun(float(v_in), dt, initial, state, contacts, run.rows, run.newton, run.halvings,
                     time.perf_counter() - started, time.process_time() - cpu)


def run_impact(solver: ImpactSolver, v_in: float, *, steps_per_contact: int = DEFAULT_STEPS_PER_CONTACT,
               progress: Callable[[str], None] | None = None, start: ImpactState | None = None) -> ImpactResult:
    """The impact at v_in [m/s] > 0 of ``solver``'s sphere on the rigid flat (module docstring;
    impact_run's errors; ``start`` as impact_run's)."""
    return _result(solver, impact_run(solver, v_in, steps_per_contact=steps_per_contact, progress=progress,
                                      start=start))


def time_loop(run: _Run, state: ImpactState, t_c: float) -> tuple[ImpactState, list[float]]:
    """Steps from ``state`` (first touch) until a tenth of ``t_c`` [s] (at least 5 steps) after the
    last separation (module docstring): (the last state, the separation times [s]); raises
    ImpactNotConverged when a step fails at dt / 64 or the bodies are still in contact at 5 t_c."""
    dt = run.dt
    run.record(state)
    contacts: list[float] = []
    flight_until = math.inf
    h = dt                              # the step: dt, or a part of it after a failure
    while not (contacts and state.time >= flight_until and not state.in_contact):
        if state.time > 5.0 * t_c:
            raise ImpactNotConverged(f"the bodies are still in contact after {state.time:.4g} s"
                                     f" (5 estimated contact times)")
        step = run.solve(state, h)
        if not step.converged:
            h = run.failed(state, h, step)
            continue
        if state.in_contact and not step.state.in_contact:
            step, t_sep = run.separate(state, step)
            contacts.append(t_sep)
            flight_until = step.state.time + max(AFTER_SEPARATION * t_c, 5 * dt)
            run.say(f"v_in = {run.v_in:g} m/s: separated at {t_sep:.6g} s")
        state = step.state
        run.record(state, step)
        h = min(dt, 2.0 * h)
    return state, contacts


def _result(solver: ImpactSolver, run: ImpactRun) -> ImpactResult:
    history = run.history()
    state = run.state
    time_P_max, P_max = _peak(history["time"], history["P"])
    _, alpha_max = _peak(history["time"], history["alpha"])
    v_in = run.v_in
    v_out = solver.momentum(state.velocity) / solver.mass
    kinetic_in = 0.5 * solver.mass * v_in ** 2
    kinetic_out = 0.5 * solver.mass * v_out ** 2
    dent, residual_energy = residual_state(solver, state)
    vibration = state.kinetic_energy - kinetic_out + state.elastic_energy - residual_energy
    balance = kinetic_in - kinetic_out - state.plastic_work - residual_energy - vibration
    return ImpactResult(
        v_in=v_in, e=v_out / v_in, v_out=v_out, P_max=P_max, time_P_max=time_P_max, contact_time=run.contacts[0],
        alpha_max=alpha_max, dent=dent, contact_radius_max=float(history["contact_radius"].max()),
        kinetic_in=kinetic_in, kinetic_out=kinetic_out,
        plastic_work=state.plastic_work, residual_stress_energy=residual_energy, vibration_energy=vibration,
        balance_residual=balance, internal_work_error=state.work_internal - state.elastic_energy - state.plastic_work,
        contact_work=state.work_contact, solver_residual_work=state.work_residual, recontacts=len(run.contacts) - 1,
        dt=run.dt, steps=len(run.rows) - 1, newton_iterations=run.newton_iterations, halvings=run.halvings,
        mass=solver.mass, dofs=solver.basis.N, wall_time_s=run.wall_time_s, cpu_time_s=run.cpu_time_s,
        history=history)


def residual_field(solver: ImpactSolver, state: ImpactState):
    """(q [m], sigma (E, Q, 4) [Pa]) of the static equilibrium of the free sphere with the plastic
    strains of ``state`` frozen: K u = int B^T D eps_p dV with the pole's u_z held (K is singular in
    the translation, which moves no stress), sigma = D (eps(u) - eps_p); under finite strain the
    hyperelastic equilibrium with the plastic log strain frozen
    (calib.fe.kinematics.FiniteStrain.residual_state). None for a sphere that never yielded."""
    plastic = getattr(state.material_state, "plastic_strain", None)
    if plastic is None or not np.any(plastic):
        return None
    free = np.ones(solver.dofs.n_q, dtype=bool)
    free[solver.dofs.pole_q] = False
    K_free = factorize(solver.elements.restricted(solver.stiffness_data, free), solver.linear_solver)

    def pole_held(load):
        q = np.zeros(solver.dofs.n_q)
        q[free] = K_free.solve((solver.TT @ load)[free])
        return solver.T @ q

    u, stress = solver.kinematics.residual_state(plastic, pole_held)
    return solver.TT @ u, stress


def residual_state(solver: ImpactSolver, state: ImpactState) -> tuple[float, float]:
    """(dent [m], residual-stress energy [J]) of ``residual_field``: dent = u_z(pole) - u_cm and
    U_res = 1/2 int sigma . D^-1 sigma dV (its Hencky energy under finite strain); (0, 0) for a
    sphere that never yielded."""
    field = residual_field(solver, state)
    if field is None:
        return 0.0, 0.0
    q, stress = field
    dent = q[solver.dofs.pole_q] - solver.centre_of_mass_displacement(q)
    return float(dent), solver.elastic_energy(stress)

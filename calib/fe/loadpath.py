"""Force-driven load paths with unloading: the paper's ABC / ADE / AFG cycles.

Vu-Quoc & Zhang (1999), section 2: the force P on the rigid top plate rises linearly to P_max,
then returns to zero. The loading branch is common to every path, so it is computed once and each
unloading branches off the committed state at its peak.

Each accepted step appends one history row (a dict, SI units): the FE step record (alpha, P,
contact radius, Newton and active-set iterations, factorisations, wall time ...) plus ``path``,
``branch``, ``plastic_zone_depth`` / ``plastic_zone_radius`` (extent of the yielded quadrature
points [m]) and ``yielded_points``. A step whose Newton fails is cut in half and retried from
the committed state (down to ``min_step_fraction`` of the planned increment); a step that still
fails is run again with the solver's slower rescue solve (``ContactSolver.rescue_step``: from the
committed state without warm start and with a fixed Newton stall test, then displacement control
hitting the target force by a secant on the approach), and raises StepNotConverged only if that
fails too: there is never a silently unconverged row.

Separation. Force control at P = 0 leaves the approach undetermined, so unloading runs under
force control down to P_max / n, then the residual approach is found where the FE force returns
to zero. Near separation the unloading is elastic and Hertzian, P ~ (alpha - alpha_res)^(3/2)
(Johnson 1985, eq. 4.23), so P^(2/3) is linear in alpha: the line through the last two unloading
points gives alpha_res, checked by a displacement-controlled FE step there (its force is
recorded, and is zero up to the extrapolation error).

Restitution (paper 2.1 / 4.7):  e = sqrt( W_unloading / W_loading ),  W = int P d(alpha) [J],
by the trapezoid rule between the FE points, except on the two segments that end at P = 0: the
loading from zero to the first load (below first yield by the recipe, calib.fit.recipe) and the
unloading to separation are Hertzian, P ~ |alpha - alpha_0|^(3/2), whose work is exactly
(2/5) P |Delta alpha|; the trapezoid's 1/2 there overstates W_loading by 2.3 % on a path from
0.5 P_Y to 2 P_Y (e 1.7 % low).
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Callable, Sequence

import numpy as np

from calib.fe.solver import ContactSolver
from calib.fe.state import ContactState, StepNotConverged, StepResult


@dataclass(frozen=True)
class LoadPathPlan:
    """Which peaks to unload from and how finely (forces in N).

    peaks: P_max of each path, e.g. (500, 1000, 1500) for ABC, ADE, AFG.
    loading_step: force increment on the loading branch [N] (shortened to land on each peak).
    unloading_steps: force-controlled steps of each unloading (plus the separation step).
    first_load: the first (elastic) load [N]; starting elastic lets the contact set settle
        before plasticity (a first plastic step with only the pole in contact is a point load
        on a perfectly plastic body and diverges).
    """

    peaks: tuple[float, ...]
    loading_step: float
    unloading_steps: int = 16
    first_load: float | None = None
    min_step_fraction: float = 1.0 / 64.0

    def __post_init__(self):
        peaks = tuple(sorted(float(p) for p in self.peaks))
        object.__setattr__(self, "peaks", peaks)
        if not peaks or not all(np.isfinite(p) and p > 0 for p in peaks):
            raise ValueError(f"peaks (P_max) must be finite forces > 0 [N], got {self.peaks}")
        repeated = sorted({p for p in peaks if peaks.count(p) > 1})
        if repeated:            # two paths to one peak: the same FE path twice, weighted twice in the fit
            raise ValueError(f"peaks (P_max) out of range: need distinct forces, got {', '.join(f'{p:g}' for p in repeated)} "
                             f"more than once")
        if not (np.isfinite(self.loading_step) and 0 < self.loading_step <= peaks[-1]):
            raise ValueError(f"loading_step must be in (0, max peak = {peaks[-1]:g}] N, got {self.loading_step}")
        if not (isinstance(self.unloading_steps, int) and self.unloading_steps >= 2):
            raise ValueError(f"unloading_steps must be an integer >= 2, got {self.unloading_steps!r}")
        if self.first_load is not None and not (0 < self.first_load <= peaks[0]):
            raise ValueError(f"first_load must be in (0, smallest peak = {peaks[0]:g}] N, got {self.first_load}")

    def loading_targets(self) -> list[float]:
        """Loads of the loading branch: first_load, then steps of at most loading_step, hitting
        every peak exactly."""
        start = self.first_load if self.first_load is not None else min(self.loading_step, self.peaks[0])
        targets = [start]
        for peak in self.peaks:
            n = max(1, int(np.ceil((peak - targets[-1]) / self.loading_step - 1e-9)))
            targets.extend(np.linspace(targets[-1], peak, n + 1)[1:].tolist())
        return targets

    def unloading_targets(self, peak: float) -> list[float]:
        return [peak * (1.0 - k / self.unloading_steps) for k in range(1, self.unloading_steps)]


@dataclass
class PathResult:
    """One load path: its peak, history rows (loading rows shared with the other paths, then its
    unloading rows) and the derived figures."""

    peak: float
    rows: list[dict]
    alpha_max: float
    alpha_residual: float
    restitution: float
    loading_work: float
    unloading_work: float
    peak_state: ContactState = field(repr=False)


@dataclass
class LoadPathResults:
    loading_rows: list[dict]
    paths: list[PathResult]
    wall_time_s: float
    factorizations: int
    final_state: ContactState = field(repr=False)  # end of the last unloading
    pressure_profiles: dict = field(default_factory=dict, repr=False)  # peak -> (r [m], p [Pa])


def run_load_path(solver: ContactSolver, loads, control: str = "force",
                  state: ContactState | None = None):
    """Apply ``loads`` (forces [N] or approaches [m]) in order, committing each converged step.

    Returns (results, final_state). Raises StepNotConverged at the first failed step (the
    results so far are attached as ``exc.results``).
    """
    if control not in ("force", "displacement"):
        raise ValueError(f"control must be 'force' or 'displacement', got {control!r}")
    state = solver.initial_state() if state is None else state
    step = solver.solve_force if control == "force" else solver.solve_displacement
    results = []
    for load in loads:
        result = step(state, load)
        if not result.converged:
            exc = StepNotConverged(f"{control} step {load:g}: {result.message}")
            exc.results = results
            raise exc
        results.append(result)
        state = solver.commit(result)
    return results, state


def run_press(solver: ContactSolver, approaches, min_step_fraction: float = 1.0 / 64.0,
              state: ContactState | None = None):
    """The press to each approach [m] of ``approaches`` in order, under displacement control, every
    increment through ``advance`` (halved on failure, grown back after success; the rescue solve
    last). Returns (the StepResult at each approach, the sub-steps' StepResults, final state).

    Why halving: on a perfectly plastic sphere past a/R ~ 0.15 a displacement increment of
    10-20 % of the approach leaves Newton's basin (its first iterate, elastic, puts 0.14-0.2 of
    plastic strain at the contact edge in one increment; the next iterates oscillate, and with
    finite strain an element at the edge inverts), whatever the active set; half the increment
    converges (tests/test_finite_strain.py)."""
    state = solver.initial_state() if state is None else state
    at_targets, steps = [], []
    for alpha in approaches:
        state = advance(solver, state, "displacement", float(alpha), min_step_fraction,
                        lambda result, previous: steps.append(result))
        at_targets.append(steps[-1])
    return at_targets, steps, state


def plastic_zone(state: ContactState, quadrature_r: np.ndarray, quadrature_z: np.ndarray) -> dict:
    """Extent of the yielded region (equivalent plastic strain > 0): depth below the contact plane
    z = 0, |z| (the sphere lies above it, a counter-body below), and radius [m]."""
    eps_p = getattr(state.material_state, "equivalent_plastic_strain", None)
    yielded = eps_p > 0 if eps_p is not None else np.zeros(quadrature_r.shape, dtype=bool)
    if not yielded.any():
        return {"plastic_zone_depth": 0.0, "plastic_zone_radius": 0.0, "yielded_points": 0}
    return {"plastic_zone_depth": float(np.abs(quadrature_z[yielded]).max()),
            "plastic_zone_radius": float(quadrature_r[yielded].max()),
            "yielded_points": int(yielded.sum())}


def advance(solver: ContactSolver, state: ContactState, control: str, target: float,
            min_fraction: float, on_step: Callable[[StepResult, ContactState], None]) -> ContactState:
    """Reach ``target`` (force [N] or approach [m]) from ``state``, cutting the increment in half
    and retrying from the committed state when a step fails; grows back after each success.

    When a step still fails at ``min_fraction`` of the increment, the rest of the increment is
    run again (from the full remaining piece, halving the same way) with
    ``solver.rescue_step``, the slower defensive solve (see there); StepNotConverged only if
    that fails too at ``min_fraction``. The rescue starts only where the ordinary stepping has
    given up, so every path that converges without it is unchanged bit for bit.

    ``on_step(result, previous_state)`` is called for every accepted step (sub-steps included).
    """
    solve = solver.solve_force if control == "force" else solver.solve_displacement
    start = state.force if control == "force" else state.alpha
    full = target - start
    fraction = 1.0
    done = 0.0
    rescue, ordinary_failure = False, ""
    while done < 1.0:
        fraction = min(fraction, 1.0 - done)
        step_target = target if done + fraction >= 1.0 else start + (done + fraction) * full
        if rescue:
            result = solver.rescue_step(state, control, step_target)
        else:
            result = solve(state, step_target)
        if result.converged:
            on_step(result, state)
            state = solver.commit(result)
            done += fraction
            fraction *= 2.0  # Newton was fine: try a bigger piece of what is left
            continue
        fraction /= 2.0
        if fraction < min_fraction and not rescue:
            # the ordinary solve gave up: the rest of the increment with the rescue solve
            rescue, ordinary_failure, fraction = True, result.message, 1.0
            continue
        if fraction < min_fraction:
            raise StepNotConverged(f"{control} step to {target:g} failed even at {fraction * 2:g} of the"
                                   f" increment from {start:g}: {ordinary_failure}; rescue solve:"
                                   f" {result.message}")
    return state


def contact_work(alpha: np.ndarray, force: np.ndarray) -> float:
    """W = |int P d(alpha)| [J] of a loading history from P = 0 or an unloading history to
    separation (monotone in alpha): the trapezoid rule, and (2/5) P |Delta alpha| on the segment at
    the unloaded end (the end of smaller force: zero, or the FE's residual force at separation),
    where P ~ |alpha - alpha_0|^(3/2) (Hertz; module docstring), P the force at its other end."""
    alpha, force = np.asarray(alpha, dtype=float), np.asarray(force, dtype=float)
    step = np.abs(np.diff(alpha))
    segment = 0.5 * (force[:-1] + force[1:]) * step
    if force[0] <= force[-1]:           # contact begins at the first point
        segment[0] = 0.4 * force[1] * step[0]
    else:                               # ... or separates at the last
        segment[-1] = 0.4 * force[-2] * step[-1]
    return float(np.sum(segment))


PEAK_MATCH = 1e-6    # relative: the loading row of a peak holds the FE's force there, to the Newton tolerance


def loading_count_to_peak(force: Sequence[float], peak: float) -> int:
    """How many loading rows, in load order, belong to the path of ``peak`` [N]: up to and including
    the row of the peak itself. The plan hits every peak as a force target, and Newton meets it to its
    residual tolerance (relative 1e-8), so the FE's force there may lie a little above the peak: the
    peak's row is the one nearest to it, not the last at or below it. ValueError when no row lies
    within PEAK_MATCH of the peak (a history of another plan)."""
    force = np.asarray(force, dtype=float)
    nearest = int(np.argmin(np.abs(force - peak)))
    if not abs(force[nearest] - peak) <= PEAK_MATCH * peak:
        raise ValueError(f"no loading row at the peak {peak:g} N (nearest {force[nearest]:g} N)")
    return nearest + 1


def separation_approach(alpha: Sequence[float], force: Sequence[float]) -> float:
    """alpha where P returns to 0, from the last two unloading points, P^(2/3) linear in alpha."""
    (a1, a2), (p1, p2) = alpha[-2:], force[-2:]
    s1, s2 = max(p1, 0.0) ** (2 / 3), max(p2, 0.0) ** (2 / 3)
    if not s1 > s2:
        return float(a2)
    return float(a2 - s2 * (a1 - a2) / (s1 - s2))


def history_row(result: StepResult, path: str, branch: str, quadrature) -> dict:
    """One history row of an accepted step (module docstring): the step record, the path and branch,
    the plastic zone of its state; ``quadrature``: the (r, z) [m] of the solver's quadrature points."""
    return {"path": path, "branch": branch, **result.record.as_dict(), **plastic_zone(result.state, *quadrature)}


@dataclass
class UnloadingRun:
    """One path's unloading from its peak: its history rows, the residual approach alpha_res [m]
    (where the force returns to zero), the state at separation and the factorisations it took."""

    rows: list[dict]
    alpha_residual: float
    final_state: ContactState = field(repr=False)
    factorizations: int = 0


def unloading_path(solver: ContactSolver, plan: LoadPathPlan, peak: float, peak_state: ContactState) -> UnloadingRun:
    """The unloading of the path of peak ``peak`` [N] from its committed ``peak_state``: force
    control down to P_max / n, then the separation step to the residual approach (module
    docstring). A function of its arguments alone, so any process holding the same solver gives
    the same rows bit for bit."""
    factorizations_before = solver.factorization_count
    quadrature = solver.basis.mapping.F(solver.basis.X)  # (r, z) of the quadrature points, (E, Q) each [m]
    name = f"P_max={peak:g}"
    rows: list[dict] = []

    def record_unloading(result, before):
        rows.append(history_row(result, name, "unloading", quadrature))

    state = peak_state
    for target in plan.unloading_targets(peak):
        state = advance(solver, state, "force", target, plan.min_step_fraction, record_unloading)
    alpha_res = separation_approach([r["alpha"] for r in rows[-2:]], [r["P"] for r in rows[-2:]])
    result = solver.solve_displacement(state, alpha_res)
    if not result.converged:  # only then: a converging separation step stays bit-identical
        result = solver.rescue_step(state, "displacement", alpha_res)
    if result.converged:
        record_unloading(result, state)
        state = solver.commit(result)
    else:
        # One step from the last unloading load to separation can cycle in Newton (a reverse
        # yield that comes and goes, seen at 250 P_Y, E/sigma_Y 5000): cut it, every piece a row.
        try:
            state = advance(solver, state, "displacement", alpha_res, plan.min_step_fraction, record_unloading)
        except StepNotConverged as exc:
            raise StepNotConverged(f"separation step of path {name} at alpha = {alpha_res:g}: "
                                   f"{result.message}; cut: {exc}") from None
    return UnloadingRun(rows, alpha_res, state, solver.factorization_count - factorizations_before)


def run_load_paths(solver: ContactSolver, plan: LoadPathPlan,
                   progress: Callable[[str], None] | None = None, unload: bool = True,
                   offload: Callable[[float, ContactState], Callable[[], UnloadingRun | None]] | None = None
                   ) -> LoadPathResults:
    """Run the shared loading branch once, then (``unload``) each path's unloading from its peak;
    without unloading the result has the loading rows and no paths. ``offload(peak, peak_state)``
    (optional) offers the top path's unloading to another process holding the same solver: it
    returns ``take()``, which waits for that process's UnloadingRun, or gives None when the
    process has not started it, and this one computes it (the rows are the same either way)."""
    t_start = time.perf_counter()
    factorizations_before = solver.factorization_count
    say = progress or (lambda message: None)
    quadrature = solver.basis.mapping.F(solver.basis.X)  # (r, z) of the quadrature points, (E, Q) each [m]
    loading_rows: list[dict] = []
    peak_states: dict[float, ContactState] = {}
    state = solver.initial_state()

    pressure_profiles: dict[float, tuple[np.ndarray, np.ndarray]] = {}
    last_result: list[StepResult] = []

    def record_loading(result, before):
        loading_rows.append(history_row(result, "loading", "loading", quadrature))
        last_result[:] = [result]

    targets = plan.loading_targets()
    for k, target in enumerate(targets, 1):
        state = advance(solver, state, "force", target, plan.min_step_fraction, record_loading)
        say(f"loading {k}/{len(targets)}: P = {state.force:.4g} N, alpha = {state.alpha:.4g} m")
        for peak in plan.peaks:
            if np.isclose(target, peak, rtol=1e-12):
                peak_states[peak] = state
                pressure_profiles[peak] = (last_result[0].pressure_r, last_result[0].pressure)

    peaks = list(plan.peaks) if unload else []
    offered = {}
    if offload is not None and len(peaks) > 1:
        offered[peaks[-1]] = offload(peaks[-1], peak_states[peaks[-1]])
    unloadings = {}
    offloaded_factorizations = 0
    for peak in peaks:
        run = offered[peak]() if peak in offered else None
        if run is None:
            run = unloading_path(solver, plan, peak, peak_states[peak])
        else:
            offloaded_factorizations += run.factorizations
        unloadings[peak] = run
        say(f"unloading P_max={peak:g}: residual alpha = {run.alpha_residual:.4g} m")

    paths = []
    for peak in peaks:
        peak_state, run = peak_states[peak], unloadings[peak]
        name = f"P_max={peak:g}"
        loading_part = loading_rows[:loading_count_to_peak([r["P"] for r in loading_rows], peak)]
        path_loading = [{**r, "path": name} for r in loading_part]
        a_load = np.array([0.0] + [r["alpha"] for r in loading_part])
        p_load = np.array([0.0] + [r["P"] for r in loading_part])
        a_unload = np.array([peak_state.alpha] + [r["alpha"] for r in run.rows])
        p_unload = np.array([peak_state.force] + [max(r["P"], 0.0) for r in run.rows])
        w_load, w_unload = contact_work(a_load, p_load), contact_work(a_unload, p_unload)
        paths.append(PathResult(peak=peak, rows=path_loading + run.rows,
                                alpha_max=peak_state.alpha, alpha_residual=run.alpha_residual,
                                restitution=float(np.sqrt(w_unload / w_load)),
                                loading_work=w_load, unloading_work=w_unload,
                                peak_state=peak_state))
        state = run.final_state
    return LoadPathResults(loading_rows=loading_rows, paths=paths,
                           wall_time_s=time.perf_counter() - t_start,
                           factorizations=solver.factorization_count - factorizations_before + offloaded_factorizations,
                           final_state=state, pressure_profiles=pressure_profiles)

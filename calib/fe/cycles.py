"""Load cycles of the force-driven FE: load to P_max, partial unloads, reloads, past the peak, unload.

From the committed state at the peak P_max [N] of one load path (calib.fe.loadpath, the shared
loading branch), for each fraction f_i of ``CyclePlan.fractions`` (cycle i = 1..n):

    unload to f_i P_max   (branch "unloading", cycle i)
    reload to P_max       (branch "reloading", cycle i: up to the turning point; the last reload
                           goes on past it to ``overload`` x P_max, branch "loading", cycle n)

then unload fully to separation (branch "unloading", cycle n + 1: calib.fe.loadpath.unloading_path,
its residual approach where P^(2/3) extrapolates to zero). Every step under force control through
``calib.fe.loadpath.advance`` (the one quasi-static stepper: halving, then the rescue solve), in
force increments of at most P_max / ``LoadPathPlan.unloading_steps``. The rows start with the
loading branch to P_max (cycle 0), so they are the whole force history of one contact.

Work of a branch: W = int P d(alpha) [J] by the trapezoid rule between the FE points. A closed
partial cycle (unload from P_max to f P_max, reload to P_max) takes W_in (reload) and returns
W_out (unload); W_in - W_out >= 0 is the energy dissipated in the cycle (Drucker's stability
postulate for the elastic-plastic body, Lubliner 2008 sec. 3.2: no work is gained in a closed
cycle of the loads).

The cycles branch off the committed peak state and share no state with the other paths, so a
calibration's paths and figures are the same with or without them.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from calib.fe.loadpath import LoadPathPlan, LoadPathResults, advance, history_row, unloading_path
from calib.fe.solver import ContactSolver
from calib.fe.state import ContactState

CYCLES_PATH = "cycles"      # the rows' path name


@dataclass(frozen=True)
class CyclePlan:
    """The cycles of one load path.

    fractions: P / P_max of each partial unload, in order, each in (0, 1), e.g. (0.5, 0.2).
    overload: the last reload's peak over P_max, > 1 (e.g. 1.3: past the turning point).
    peak: the load path's P_max [N] the cycles start from (one of the plan's peaks); None: the
        middle one of the plan's peaks (the upper of the two middle ones), so the overload stays
        inside the peaks the laws are fitted on when there are three or more.
    """

    fractions: tuple[float, ...]
    overload: float = 1.3
    peak: float | None = None

    def __post_init__(self):
        fractions = tuple(float(f) for f in self.fractions)
        object.__setattr__(self, "fractions", fractions)
        if not fractions or not all(np.isfinite(f) and 0.0 < f < 1.0 for f in fractions):
            raise ValueError(f"cycle fractions out of range: need P/P_max in (0, 1), got "
                             f"{', '.join(f'{f:g}' for f in fractions) or 'none'}")
        if not (np.isfinite(self.overload) and self.overload > 1.0):
            raise ValueError(f"cycle overload out of range: need a reload peak / P_max > 1, got {self.overload:g}")

    def peak_of(self, plan: LoadPathPlan) -> float:
        """The P_max [N] of ``plan`` the cycles start from."""
        if self.peak is None:
            return plan.peaks[len(plan.peaks) // 2]
        matches = [p for p in plan.peaks if np.isclose(p, self.peak, rtol=1e-12)]
        if not matches:
            raise ValueError(f"cycle peak out of range: need one of the plan's peaks "
                             f"({', '.join(f'{p:g}' for p in plan.peaks)} N), got {self.peak:g} N")
        return matches[0]


@dataclass
class CycleRun:
    """The rows of the cycles (module doc; each with ``branch`` and ``cycle``), P_max [N], the
    overload peak [N], alpha_max [m] at P_max and the residual approach after the final unload [m]."""

    rows: list[dict]
    P_max: float
    overload_peak: float
    alpha_max: float
    alpha_residual: float
    final_state: ContactState = field(repr=False)


def force_targets(start: float, end: float, step: float) -> list[float]:
    """Equal force targets [N] from ``start`` (excluded) to ``end`` (included), at most ``step`` apart."""
    n = max(1, int(np.ceil(abs(end - start) / step - 1e-9)))
    return np.linspace(start, end, n + 1)[1:].tolist()


def run_cycles(solver: ContactSolver, plan: LoadPathPlan, cycles: CyclePlan, results: LoadPathResults) -> CycleRun:
    """The cycles of ``cycles`` (module doc) from the peak state of its path in ``results`` (the
    load paths of ``plan`` on ``solver``, run with unloading)."""
    peak = cycles.peak_of(plan)
    paths = [p for p in results.paths if p.peak == peak]
    if not paths:
        raise ValueError(f"no load path to {peak:g} N with its peak state: run the load paths with unloading")
    path = paths[0]
    quadrature = solver.basis.mapping.F(solver.basis.X)  # (r, z) of the quadrature points, (E, Q) each [m]
    loading = [r for r in path.rows if r["branch"] == "loading"]
    rows = [{**r, "path": CYCLES_PATH, "cycle": 0} for r in loading]
    step = peak / plan.unloading_steps
    state = path.peak_state
    count = len(cycles.fractions)
    for index, fraction in enumerate(cycles.fractions, 1):
        legs = [("unloading", fraction * peak), ("reloading", peak)]     # the reload's targets: the unload's
        if index == count:
            legs.append(("loading", peak * cycles.overload))
        for branch, end in legs:
            def record(result, before, branch=branch, index=index):
                rows.append({**history_row(result, CYCLES_PATH, branch, quadrature), "cycle": index})
            for target in force_targets(state.force, end, step):
                state = advance(solver, state, "force", target, plan.min_step_fraction, record)
    overload_peak = peak * cycles.overload
    final = unloading_path(solver, plan, overload_peak, state)
    rows.extend({**r, "path": CYCLES_PATH, "cycle": count + 1} for r in final.rows)
    return CycleRun(rows, peak, overload_peak, path.alpha_max, final.alpha_residual, final.final_state)


def branch_segments(rows: list[dict]) -> list[tuple[int, str, list[dict]]]:
    """(cycle, branch, rows) of each run of rows with one cycle and branch, in order, each run
    starting from the last row of the one before (so its works and forces start where it does)."""
    segments: list[tuple[int, str, list[dict]]] = []
    for k, row in enumerate(rows):
        key = (row["cycle"], row["branch"])
        if not segments or (segments[-1][0], segments[-1][1]) != key:
            segments.append((row["cycle"], row["branch"], [rows[k - 1]] if k else []))
        segments[-1][2].append(row)
    return segments


def trapezoid_work(rows: list[dict]) -> float:
    """int P d(alpha) [J] along ``rows`` by the trapezoid rule (signed: negative on unloading)."""
    alpha = np.array([r["alpha"] for r in rows])
    force = np.array([r["P"] for r in rows])
    return float(np.sum(0.5 * (force[1:] + force[:-1]) * np.diff(alpha)))


def closed_cycles(run: CycleRun) -> list[dict]:
    """Each closed partial cycle (every cycle but the last, whose reload goes past the peak): the
    work returned on its unload W_out [J], taken on its reload W_in [J], the dissipated
    W_in - W_out, and the reload's approach at P_max against the turning point's,
    (alpha_reload - alpha_max) / alpha_max."""
    segments = branch_segments(run.rows)
    found = []
    for cycle in range(1, max(r["cycle"] for r in run.rows)):
        down = [s for c, b, s in segments if c == cycle and b == "unloading"][0]
        up = [s for c, b, s in segments if c == cycle and b == "reloading"][0]
        w_out, w_in = -trapezoid_work(down), trapezoid_work(up)
        found.append({"cycle": cycle, "fraction": down[-1]["P"] / run.P_max, "work_out": w_out, "work_in": w_in,
                      "dissipated": w_in - w_out,
                      "reload_alpha_at_peak_error": (up[-1]["alpha"] - down[0]["alpha"]) / run.alpha_max})
    return found

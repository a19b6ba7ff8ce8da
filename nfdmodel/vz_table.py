"""The NFD law with load-dependent plastic radius and curvature factor (law name "vz-table").

The paper's two constants are slopes: a_p = Ca <P - P_Y>, C_R = 1 + Kc <P - P_Y>, fitted over
one load window. Over wide windows (to 1000 P_Y) neither is linear; this law keeps the paper's
structure and makes the two slopes two monotone tables taken from the FE, in dimensionless form
(x = P / P_Y, a_Y and delta_Y the contact radius and approach at first yield):

    a_p(P) = a_Y f(x),  f(1) = 0, f non-decreasing        (two constants: f = Ca_hat (x - 1))
    C_R(P) = g(x),      g(1) = 1, g > 0                   (two constants: g = 1 + Kc_hat (x - 1))

f and g are monotone piecewise-cubic (PCHIP) interpolants of their node values
(:mod:`nfdmodel.pchip`), continued as straight lines beyond the last node. Loading: with the
Hertz radius a_e = a_Y x^(1/3), delta = (a_e + a_p)^2 / (C_R R*), i.e.

    delta / delta_Y = D(x) = (x^(1/3) + f(x))^2 / g(x)        (x >= 1; Hertz below: x^(2/3)),

which must increase strictly with x (then the force of an approach is unique: the root of
D(x) = delta / delta_Y, bracketed by the table's nodes, found by safeguarded Newton).
Unloading and reloading as the paper (eqs. 3.19-3.22): a_p and C_R frozen at the turning
point x_m = P_max / P_Y, P = K_u <delta - delta_res>^(3/2), K_u = (4/3) E* g(x_m)^(3/2) sqrt(R*),
delta_res = delta_max - a_e,max^2 / (g(x_m) R*) (nfdmodel.turning_point). Admissible tables:
D strictly increasing up to where the contact radius reaches R*, and no load-unload cycle
returning more work than it took (e <= 1). The window of the table is its node range; the
runtime flags contacts beyond it like vz's (nfdmodel.window). With linear tables the law IS
the paper's, to round-off (tested). This module is the law as one unit (parameters, history, numpy
kernel, ``LAW``); the scalar specification is ``nfdmodel.reference.vz_table_step``.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
from scipy.optimize import brentq

from . import limits, native
from .contact_law import ContactLaw, plastic_radii
from .hertz import hertz_kernel
from .history import TurningPointHistory, check_delta, check_state, restore_shape, step_and_commit
from .materials import ContactPair
from .pchip import pchip_evaluate, pchip_slopes
from .turning_point import turning_point_step
from .validation import check_real
from .window import CalibrationWindow, check_contact_radius_below_R

NEWTON_TOLERANCE = limits.TABLE_TOLERANCE            # relative, on x = P / P_Y
NEWTON_MAX_ITERATIONS = limits.TABLE_MAX_ITERATIONS  # never reached: bisection halves the bracket when Newton strays
POLISH_STEP = 1e-9              # the final Newton step is taken when this small (relative), bracket or not
_GAUSS_NODES, _GAUSS_WEIGHTS = np.polynomial.legendre.leggauss(16)
_SAMPLES_PER_SEGMENT = 64       # admissibility checks: points per table segment
_LARGEST_LOAD = 1e8             # x beyond which nothing is checked (the law stops at a = R* first)


class VZTableState(TurningPointHistory):
    """History of the vz-table law (delta_max, P_max, delta_res, unloading_stiffness; [SI])."""


@dataclass(frozen=True)
class VZTableParams:
    """The vz-table law of a contact pair: node loads ``x`` = P/P_Y (x[0] = 1, increasing),
    plastic radius ``f`` = a_p/a_Y (f[0] = 0, non-decreasing) and curvature factor ``g`` = C_R
    (g[0] = 1, > 0) at those nodes; ``window``: what the table was fitted on (default: its node
    range, source unstated)."""

    pair: ContactPair
    x: tuple
    f: tuple
    g: tuple
    window: CalibrationWindow | None = None
    _arrays: dict = field(default=None, init=False, repr=False, compare=False)

    def __post_init__(self):
        if not isinstance(self.pair, ContactPair):
            raise ValueError(f"pair must be a ContactPair, got {type(self.pair).__name__}")
        columns = {}
        for name in ("x", "f", "g"):
            values = getattr(self, name)
            if isinstance(values, (str, bytes)) or not hasattr(values, "__len__"):
                raise ValueError(f"table {name} must be a list of numbers, got {values!r}")
            columns[name] = tuple(check_real(f"table {name}[{k}]", v) for k, v in enumerate(values))
            object.__setattr__(self, name, columns[name])
        n = len(columns["x"])
        if n < 2 or len(columns["f"]) != n or len(columns["g"]) != n:
            raise ValueError(f"table: x, f and g need the same length >= 2, got {n}, {len(columns['f'])}, "
                             f"{len(columns['g'])}")
        x, f, g = (np.array(columns[name]) for name in ("x", "f", "g"))
        if x[0] != 1.0 or f[0] != 0.0 or g[0] != 1.0:
            raise ValueError(f"table out of range: the first node is first yield: need x[0] = 1, f[0] = 0, "
                             f"g[0] = 1, got {x[0]:g}, {f[0]:g}, {g[0]:g}")
        if not np.all(np.diff(x) > 0):
            raise ValueError("table x out of range: node loads P/P_Y must increase strictly")
        if not np.all(np.diff(f) >= 0):
            k = int(np.argmin(np.diff(f)))
            raise ValueError(f"table f out of range: the plastic radius a_p/a_Y must not decrease, "
                             f"got {f[k]:g} then {f[k + 1]:g} at P/P_Y = {x[k + 1]:g}")
        if not np.all(g > 0):
            raise ValueError(f"table g out of range: the curvature factor C_R must be > 0, got {g.min():g}")
        if self.window is not None and not isinstance(self.window, CalibrationWindow):
            raise ValueError(f"window must be a CalibrationWindow or None, got {type(self.window).__name__}")
        arrays = {"x": x, "f": f, "g": g, "df": pchip_slopes(x, f), "dg": pchip_slopes(x, g)}
        object.__setattr__(self, "_arrays", arrays)
        if self.window is None:
            object.__setattr__(self, "window", CalibrationWindow(1.0, float(x[-1]), None, "the table's node range"))
        self._check_admissible()

    # ------------------------------------------------------------------ the curve
    @classmethod
    def from_linear(cls, pair: ContactPair, Ca_hat: float, Kc_hat: float, x_nodes, window=None) -> "VZTableParams":
        """The paper's law as a table: f = Ca_hat (x - 1), g = 1 + Kc_hat (x - 1) at ``x_nodes``."""
        x = np.asarray(x_nodes, dtype=float)
        return cls(pair, tuple(x), tuple(Ca_hat * (x - 1.0)), tuple(1.0 + Kc_hat * (x - 1.0)), window)

    def tables(self, x, derivative: bool = False):
        """(f, g) at x = P/P_Y, and (df/dx, dg/dx) when ``derivative``."""
        a = self._arrays
        f, df = pchip_evaluate(a["x"], a["f"], a["df"], x, derivative)
        g, dg = pchip_evaluate(a["x"], a["g"], a["dg"], x, derivative)
        return (f, g, df, dg) if derivative else (f, g)

    def scaled_approach(self, x, derivative: bool = False):
        """D(x) = delta/delta_Y on the loading curve at x = P/P_Y >= 1 (and dD/dx)."""
        x = np.asarray(x, dtype=float)
        if not derivative:
            f, g = self.tables(x)
            return (np.cbrt(x) + f) ** 2 / g
        f, g, df, dg = self.tables(x, True)
        radius = np.cbrt(x) + f
        D = radius * radius / g
        dD = (2.0 * radius * (1.0 / (3.0 * np.cbrt(x) ** 2) + df) - D * dg) / g
        return D, dD

    def loading_approach(self, force):
        """delta [m] on the virgin loading curve at the force P [N] (Hertz below P_Y)."""
        pair = self.pair
        x = np.asarray(force, dtype=float) / pair.P_Y
        return pair.delta_Y * np.where(x <= 1.0, np.cbrt(np.maximum(x, 0.0)) ** 2,
                                       self.scaled_approach(np.maximum(x, 1.0)))

    def contact_radius_at(self, force):
        """a_ep = a_Y (x^(1/3) + f(x)) [m] on the loading curve at P [N] (Hertz below P_Y)."""
        x = np.maximum(np.asarray(force, dtype=float) / self.pair.P_Y, 0.0)
        f, _ = self.tables(np.maximum(x, 1.0))
        return self.pair.a_Y * (np.cbrt(x) + np.where(x > 1.0, f, 0.0))

    def plastic_radius(self, force):
        """a_p = a_Y f(P/P_Y) [m] (0 below P_Y)."""
        x = np.asarray(force, dtype=float) / self.pair.P_Y
        return self.pair.a_Y * np.where(x > 1.0, self.tables(np.maximum(x, 1.0))[0], 0.0)

    def curvature_factor(self, force):
        """C_R = g(P/P_Y) [-] (1 below P_Y)."""
        x = np.asarray(force, dtype=float) / self.pair.P_Y
        return np.where(x > 1.0, self.tables(np.maximum(x, 1.0))[1], 1.0)

    @cached_property
    def window_force(self) -> float:
        """The largest force of the window [N]."""
        return self.window.P_max_over_P_Y * self.pair.P_Y

    @cached_property
    def full_contact_load(self) -> float:
        """The force [N] at which the contact radius reaches R* (the end of the law's domain)."""
        pair = self.pair
        ratio = pair.R_star / pair.a_Y
        top = 2.0
        while float(self.contact_radius_at(top * pair.P_Y)) / pair.a_Y < ratio:
            top *= 2.0
        return pair.P_Y * float(brentq(lambda x: float(self.contact_radius_at(x * pair.P_Y)) / pair.a_Y - ratio,
                                       1.0, top, xtol=1e-12, rtol=1e-12))

    @cached_property
    def full_contact_approach(self) -> float:
        """The approach [m] at which the contact radius reaches R*."""
        return float(self.loading_approach(self.full_contact_load))

    # ------------------------------------------------------------------ admissibility
    def _check_admissible(self) -> None:
        """D strictly increasing and e <= 1 up to the end of the domain (or 1e8 P_Y)."""
        a = self._arrays
        t = np.linspace(0.0, 1.0, _SAMPLES_PER_SEGMENT, endpoint=False)
        inside = (a["x"][:-1, None] + np.diff(a["x"])[:, None] * t).ravel()
        end = min(self.full_contact_load / self.pair.P_Y, _LARGEST_LOAD)
        beyond = np.geomspace(a["x"][-1], max(end, a["x"][-1] * (1 + 1e-9)), 200)
        samples = np.concatenate([inside, beyond])
        samples = samples[samples <= end]
        _, slope = self.scaled_approach(samples, derivative=True)
        if not np.all(slope > 0.0):
            worst = float(samples[np.argmin(slope)])
            raise ValueError(f"table out of range: the loading curve delta(P) stops increasing near P/P_Y = {worst:.4g} "
                             f"(the force of an approach would not be unique); raise g's growth or f there")
        turning = samples[samples > 1.0]
        if turning.size:
            returned = self._scaled_returned_work(turning)
            taken = self._scaled_work(turning)
            excess = returned / taken - 1.0
            if not np.all(excess <= 1e-9):
                worst = int(np.argmax(excess))
                raise ValueError(f"table out of range: a load-unload cycle to P/P_Y = {turning[worst]:.4g} would "
                                 f"create energy (restitution {math.sqrt(1.0 + excess[worst]):.4f} > 1)")

    def _scaled_returned_work(self, x):
        """W_u / (P_Y delta_Y), the work the Hertz unloading from x returns: (2/5) x^(5/3) / g(x)."""
        return x * np.cbrt(x) ** 2 / self.tables(x)[1] / 2.5

    def _scaled_work(self, x):
        """W / (P_Y delta_Y) on the virgin curve up to x >= 1: x D(x) - 3/5 - integral_1^x D."""
        x = np.asarray(x, dtype=float)
        return x * self.scaled_approach(x) - 0.6 - self._integral_of_D(x)

    @cached_property
    def _node_integrals(self) -> np.ndarray:
        """integral_1^{x_k} D(s) ds at every node (Gauss-Legendre per segment, where D is smooth)."""
        x = self._arrays["x"]
        return np.concatenate([[0.0], np.cumsum(self._gauss(x[:-1], x[1:]))])      # all segments at once

    def _gauss(self, low, high):
        low, high = np.asarray(low, dtype=float), np.asarray(high, dtype=float)
        s = 0.5 * (low + high)[..., None] + 0.5 * (high - low)[..., None] * _GAUSS_NODES
        return 0.5 * (high - low) * (self.scaled_approach(s) @ _GAUSS_WEIGHTS)

    def _integral_of_D(self, x):
        """integral_1^x D(s) ds, x >= 1: node integrals plus the last piece; beyond the last node
        in log panels of width <= 1 (D grows there like a power of s)."""
        nodes = self._arrays["x"]
        x = np.asarray(x, dtype=float)
        k = np.clip(np.searchsorted(nodes, x, side="right") - 1, 0, nodes.size - 1)
        start = nodes[k]
        total = self._node_integrals[k]
        inside = x <= nodes[-1]
        total = total + np.where(inside, self._gauss(start, np.where(inside, x, start)), 0.0)
        if not inside.all():
            last = nodes[-1]
            beyond = np.flatnonzero(~inside.ravel())        # the panels only where they are used
            ratio = np.log(x.ravel()[beyond] / last)
            panels = max(1, int(math.ceil(float(ratio.max()))))
            extra = np.zeros(beyond.size)
            for panel in range(panels):
                extra += self._gauss(last * np.exp(ratio * panel / panels), last * np.exp(ratio * (panel + 1) / panels))
            total = np.array(total, dtype=float).ravel()
            total[beyond] += extra
            total = total.reshape(x.shape)
        return total

    def loading_work(self, delta_max, P_max):
        """W = integral_0^delta_max P d delta on the virgin curve [J]."""
        pair = self.pair
        delta_max = np.asarray(delta_max, dtype=float)
        P_max = np.asarray(P_max, dtype=float)
        elastic = np.minimum(delta_max, pair.delta_Y)
        work = 0.4 * pair.hertz_stiffness * elastic**2 * np.sqrt(elastic)
        plastic = np.flatnonzero((P_max > pair.P_Y) & (delta_max > pair.delta_Y))
        if plastic.size:
            x = P_max[plastic] / pair.P_Y
            work[plastic] = pair.P_Y * pair.delta_Y * self._scaled_work(x)
        return work

    # ------------------------------------------------------------------ the solve
    def solve(self, scaled_delta, start=None):
        """x = P/P_Y >= 1 with D(x) = delta/delta_Y (> 1), per contact: the table segment
        brackets the root (D is increasing), safeguarded Newton inside it; ``start``: a lower
        bound with a good guess (the last turning point). Returns (x, largest iteration count)."""
        d = np.asarray(scaled_delta, dtype=float)
        nodes = self._arrays["x"]
        D_nodes = self._node_approaches
        k = np.searchsorted(D_nodes, d, side="right") - 1
        low = nodes[np.clip(k, 0, nodes.size - 1)].astype(float)
        high = np.where(k < nodes.size - 1, nodes[np.clip(k + 1, 0, nodes.size - 1)], nodes[-1] * 2.0)
        beyond = k >= nodes.size - 1
        while beyond.any():                                 # beyond the table: double until bracketed
            short = beyond & (self.scaled_approach(high) < d)
            if not short.any():
                break
            low = np.where(short, high, low)
            high = np.where(short, 2.0 * high, high)
        x = 0.5 * (low + high) if start is None else np.clip(start, low, high)
        iterations = 0
        for iterations in range(1, NEWTON_MAX_ITERATIONS + 1):
            D, dD = self.scaled_approach(x, derivative=True)
            residual = D - d
            low = np.where(residual < 0.0, x, low)
            high = np.where(residual >= 0.0, x, high)
            step = residual / dD
            candidate = x - step
            stray = ~((candidate > low) & (candidate < high))
            candidate = np.where(stray, 0.5 * (low + high), candidate)
            done = np.abs(candidate - x) <= NEWTON_TOLERANCE * candidate
            x = candidate
            if done.all() or np.all(high - low <= NEWTON_TOLERANCE * high):
                break
        # one more Newton step, kept inside the bracket: every contact ends at its root to round-off,
        # however many iterations the others needed (so a contact-by-contact kernel gives the same)
        D, dD = self.scaled_approach(x, derivative=True)
        candidate = x - (D - d) / dD
        polish = ((candidate >= low) & (candidate <= high)) | (np.abs(candidate - x) <= POLISH_STEP * x)
        x = np.where(polish, candidate, x)
        return x, iterations

    @cached_property
    def _node_approaches(self) -> np.ndarray:
        return self.scaled_approach(self._arrays["x"])


def _loading_branch(params: VZTableParams):
    pair = params.pair

    def branch(delta, state, index, out=None):
        P = hertz_kernel(delta, pair)
        delta_res = np.zeros_like(delta)
        stiffness = np.full_like(delta, pair.hertz_stiffness)
        plastic = np.flatnonzero(delta > pair.delta_Y)
        iterations = 0
        if plastic.size:
            start = np.maximum(state.P_max[index[plastic]] / pair.P_Y, 1.0)
            x, iterations = params.solve(delta[plastic] / pair.delta_Y, start)
            P_plastic = x * pair.P_Y
            _, g = params.tables(x)
            recovery = pair.delta_Y * np.cbrt(x) ** 2 / g          # a_e,max^2 / (C_Rmax R*)
            d_res = np.maximum(delta[plastic] - recovery, 0.0)
            d_res = np.where(d_res >= delta[plastic], np.nextafter(delta[plastic], 0.0), d_res)
            gap = delta[plastic] - d_res
            P[plastic], delta_res[plastic] = P_plastic, d_res
            stiffness[plastic] = P_plastic / (gap * np.sqrt(gap))   # through the turning point
        return {"P_max": P, "delta_res": delta_res, "unloading_stiffness": stiffness}, iterations

    return branch


def vz_table_params(params) -> VZTableParams:
    """``params`` when it is a VZTableParams, else a ValueError naming params."""
    if type(params) is not VZTableParams:     # (a subclass's tables unload otherwise: vz-unload)
        raise ValueError(f"params for law 'vz-table' must be VZTableParams, got {type(params).__name__}")
    return params


def vz_table_step(delta, state: VZTableState, params: VZTableParams):
    """One vz-table step without committing it: (P [N], HistoryUpdate) (module doc)."""
    vz_table_params(params)
    check_state(state, VZTableState, "vz-table")
    delta, shape = check_delta(delta, state.n)
    if native.active():
        force, update = compiled_table_step(delta, state, params)
        return restore_shape(force, shape), update
    force, update = turning_point_step(delta, state, _loading_branch(params), True, params.pair)
    return restore_shape(force, shape), checked_loading_update(update, params)


def compiled_table_step(delta, state, params: VZTableParams):
    """The step of the vz-table law, or of vz-unload for VZUnloadParams, in the compiled kernel
    (nfd_vz_table_step, nfd_unload.h): (P [N], HistoryUpdate), the update checked as
    :func:`checked_loading_update` does from the kernel's widest contact radius."""
    pair = params.pair
    kernel = native.kernel_params(pair, window_P_max=params.window_force)
    force, update, (_, beyond, largest_P, widest, widest_radius, _) = native.turning_point_step(
        native.table_loading(kernel, native.kernel_table(params)), delta, state, pair, True)
    if update.size:
        check_contact_radius_below_R(widest_radius, pair.R_star, float(update.values.delta_max[widest]), params)
        if beyond:
            update = dataclasses.replace(update, beyond_window=beyond, largest_load_over_P_Y=largest_P / pair.P_Y)
    return force, update


def checked_loading_update(update, params):
    """The history update of a step whose contacts loaded on the virgin curve, checked: a
    ContactRadiusError when the widest new contact radius reaches R* (nfdmodel.window), and the
    contacts beyond the calibrated window (P_max above ``params.window_force``) counted in it
    (vz-table and every law on its loading curve)."""
    if not update.size:
        return update
    pair = params.pair
    P_max = update.values.P_max
    radius = params.contact_radius_at(P_max)
    largest = int(np.argmax(radius))
    check_contact_radius_below_R(float(radius[largest]), pair.R_star, float(update.values.delta_max[largest]), params)
    if float(P_max.max()) > params.window_force:
        update = dataclasses.replace(update, beyond_window=int(np.count_nonzero(P_max > params.window_force)),
                                     largest_load_over_P_Y=float(P_max.max()) / pair.P_Y)
    return update


def vz_table_force(delta, state: VZTableState, params: VZTableParams):
    """The pure vz-table law: (P [N], new_state) (vz_table_step + a copying commit)."""
    return step_and_commit(vz_table_step, delta, state, params)


def vz_table_loading_work(delta_max, P_max, params: VZTableParams):
    """Work on the virgin vz-table curve up to (delta_max, P_max) [J]."""
    return params.loading_work(delta_max, P_max)


# The compiled collision loop takes no table (collision_params None): collide runs the numpy loop,
# whose steps use the compiled table solve when it is active.
LAW = ContactLaw("vz-table", "the NFD model with load-dependent a_p and C_R tables from the FE", vz_table_force,
                 VZTableState, vz_table_loading_work, 1.5, vz_table_step, params_function=vz_table_params,
                 radii_function=plastic_radii, fitted=True)

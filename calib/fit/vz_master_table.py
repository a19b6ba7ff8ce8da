"""The master table of the vz-table law: a_p/a_Y and C_R against P/P_Y over (nu, E / sigma_Y).

The vz-table law (nfdmodel.vz_table) loads along D(x) = (x^(1/3) + f(x))^2 / g(x) and unloads
with C_R = g(x_m) frozen (x = P/P_Y, D = alpha/delta_Y, f = a_p/a_Y, g = C_R; calib.fit.table_fit).
For a sphere on a rigid flat f and g are functions of x, nu and E / sigma_Y only, so one FE
calibration per grid node (nu, E / sigma_Y), at the FE's reach, gives them for every material
(calib.fit.vz_master_build writes calib/data/vz_master_table.{csv,json}). At a material:

    f(x_k), g(x_k) = PCHIP in nu, then PCHIP in log10(E / sigma_Y) of the node values at each
                     common load x_k (monotone cubics: exact on the nodes, no overshoot),

using at each x_k the E / sigma_Y columns that reach it (a softer material's window ends lower:
the small strain's reach, P <= 1000 P_Y and a <= 0.2 R, or, for the table joined over the finite
strain's reach (calib.fit.vz_master_join, its .json's "kinematics"), P <= 1e4 P_Y and a <= 0.45 R);
the material's window runs from P_Y (below the nodes' lowest unloading
path, 2 P_Y, the law interpolates from Hertz's f = 0, g = 1 at x = 1, checked against the FE there:
BELOW_NODES) to the largest x_k that the columns around it reach. Then

    a_p = a_Y f,   C_R = g   (nfdmodel.VZTableParams(pair, x_k, f, g, window))

The table also carries the vz-unload law's (nfdmodel.vz_unload) dent ratio rho = delta_res/delta_max
and unloading exponent m at each node and load (calib.fit.vz_master_build, from the node's FE
unloading paths), interpolated the same way on the same loads and E / sigma_Y columns:

    VZUnloadParams(pair, x_k, f_a, g_a, window, x_unload = x_k, rho, m),  rho(1) = 0, m(1) = 3/2

(below the nodes' lowest unloading path x_unload takes the loads, and rho the shape, of the FE's dent near
first yield: dent_below),

with its own contact radius a = a_Y (x^(1/3) + f_a(x)): f_a at each node from the FE's contact radius
along the node's loading branch (calib.fit.vz_master_build.resample_radius: x^(1/3) + f_a = q (x^(1/3)
+ f), q a cubic in ln x fitted to a_FE / a_Y (x^(1/3) + f); f itself is fitted to the force and the
returned work and overstates the FE's radius by 1-6 %), interpolated like f; g_a = g ((x^(1/3) +
f_a)/(x^(1/3) + f))^2 keeps the vz-table law's loading curve D(x_k) at every table load.

numpy/scipy only (``nfdcal material --v-max`` answers in a fraction of a second). Its accuracy,
against direct FE at off-grid materials (calib.fit.vz_master_check), is in the table's .json.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from calib.fit.master_table import DATA_DIR, check_axes, read_meta, read_rows
from calib.fit.table_fit import K_BELOW_LOWEST_MAX
from nfdmodel import CalibrationWindow, ContactPair, Material, VZTableParams, VZUnloadParams, limits
from nfdmodel.vz_unload import HERTZ_EXPONENT

DEFAULT_TABLE = DATA_DIR / "vz_master_table.csv"
UNLOADING_COLUMNS = ("delta_res_over_delta_max", "unloading_exponent")   # rho, m of the vz-unload law
RADIUS_COLUMN = "radius_a_p_over_a_Y"     # f_a of the vz-unload law: its contact radius a = a_Y (x^(1/3) + f_a)
# The laws between P_Y and the nodes' lowest unloading path (2 P_Y) against FE load-unload paths to 1.2, 1.5
# and 1.8 P_Y of three off-grid materials (calib.studies.below_nodes: results/tables/below_nodes.json; small
# strain, every contact radius from 1.1 P_Y spanning 25 elements): the largest |e error|, force error over
# P_max and |dent error| over alpha_max. So both laws' windows start at P_Y.
BELOW_NODES = {"checked_from_over_P_Y": 1.2,
               "vz-table": {"e_error": 0.0096, "force_error": 0.012, "dent_error_of_alpha_max": 0.027},
               "vz-unload": {"e_error": 0.0019, "force_error": 0.0057, "dent_error_of_alpha_max": 0.0003}}


# The FE's dent near first yield, S(x) = rho(x) / rho(2.371 P_Y) (to the table's first load above the nodes'
# lowest unloading path): the mean over FE load-unload paths at 12 table nodes (calib.studies.below_nodes:
# SHAPE_NODES, nu 0.2-0.49 x E/sigma_Y 100, 1000, 5000; results/tables/below_nodes.json "dent_shape"), each
# node within DENT_SHAPE_SPREAD of it.
DENT_SHAPE_BELOW = ((1.0, 1.1, 1.2, 1.333521432163324, 1.5, 1.7782794100389228, 2.0, 2.371373705661655),
                    (0.0, 0.00925, 0.04778, 0.12970, 0.25524, 0.50057, 0.69011, 1.0))
DENT_SHAPE_SPREAD = 0.018
DISSIPATION_SLOPE = 0.01        # admissible_below: the least dissipated share of a cycle to x, 0.01 (x - 1)
BELOW_SUBDIVISIONS = 4          # admissible_below's subdivision of the unloading nodes below the lowest path


def dent_below(x: np.ndarray, rho: np.ndarray, m: np.ndarray, low: float) -> tuple[np.ndarray, ...]:
    """The vz-unload law's unloading nodes (x_unload, rho, m) from the table's (x, rho, m) at its common loads,
    the FE's dent shape near first yield taken below ``low`` (the nodes' lowest unloading path): x_unload holds
    1, the loads of DENT_SHAPE_BELOW below low, low, and the table's loads above low, with

        rho(x) = rho_t(low) S(x) / S(low),   m(x) + 1 = (m_t(x) + 1) (1 - rho(x)) / (1 - rho_t(x))   (x < low)

    S = DENT_SHAPE_BELOW (PCHIP), rho_t and m_t the table's PCHIP (nfdmodel.pchip) from rho = 0, m = 3/2 at
    x = 1. The returned work P_max (delta_max - delta_res) / (m + 1) [J], hence e, stays the table's, and at low,
    the nodes' lowest FE path, rho too; below it the dent follows the FE's, which grows as (x - 1)^(1.3 to 2).
    On the held-out FE paths of calib.studies.below_nodes (1.2-1.8 P_Y) the dent is within 0.03 % of alpha_max;
    the table's rho_t overstated it by up to 0.53 % (at 1.2 P_Y, where the FE's is 0.25-0.29 %). e moves by
    1e-5 there, the force by 0.05 % of P_max; 0 of 14160 laws refused (59 nu x 120 E/sigma_Y, both laws)."""
    from nfdmodel.pchip import pchip_evaluate, pchip_slopes

    xs, shape = (np.array(v) for v in DENT_SHAPE_BELOW)
    if not 1.0 < low <= xs[-1] * (1 + 1e-9) or x[-1] <= low:
        return x, rho, m
    at = np.concatenate([xs[(xs > 1.0) & (xs < low * (1 - 1e-9))], [low]])
    S = pchip_evaluate(xs, shape, pchip_slopes(xs, shape), at)[0]
    rho_t = pchip_evaluate(x, rho, pchip_slopes(x, rho), at)[0]
    m_t = pchip_evaluate(x, m, pchip_slopes(x, m), at)[0]
    rho_new = rho_t[-1] * S / S[-1]
    m_new = (m_t + 1.0) * (1.0 - rho_new) / (1.0 - rho_t) - 1.0
    above = x > low * (1 + 1e-9)
    return (np.concatenate([[1.0], at, x[above]]), np.concatenate([[0.0], rho_new, rho[above]]),
            np.concatenate([[HERTZ_EXPONENT], m_new, m[above]]))


def admissible_below(x: np.ndarray, f: np.ndarray, g: np.ndarray, x_unload: np.ndarray, rho: np.ndarray,
                     m: np.ndarray, low: float) -> tuple[np.ndarray, ...]:
    """The vz-unload law's unloading nodes (x_unload, rho, m) below ``low`` (the nodes' lowest unloading path),
    made admissible where a cycle there would return more work than the loading took. (x, f, g): the vz-unload
    law's loading tables (f_a, g_a), D = (x^(1/3) + f)^2 / g as nfdmodel's PCHIP gives it, W = P_Y delta_Y
    (x D - 3/5 - integral_1^x D), integrated here because a VZTableParams of (f_a, g_a) refuses itself at the
    soft columns (its Hertz unloading creates energy). The nodes below low are subdivided (BELOW_SUBDIVISIONS
    per interval, rho and m the PCHIP of the given nodes); where a cycle to any of them returns more than its
    loading work W, m is raised at every one to

        m_k + 1 >= P_k delta_k (1 - rho_k) / ((1 - DISSIPATION_SLOPE (x_k - 1)) W_k)      (1 < x_k < low)

    (a dissipated share growing at least as DISSIPATION_SLOPE (x - 1) from 0 at P_Y); else the nodes are
    returned unchanged: every law above E/sigma_Y 65.1 (the table's interpolation from rho = 0, m = 3/2 at
    P_Y to the lowest FE path returns less than it took; 496 of 3600 laws of a 30 nu x 120 E/sigma_Y scan
    changed, none above 65.1, none refused). At the soft columns (E/sigma_Y 30-65), whose loading just above
    P_Y is stiffer than Hertz's (the FE's finite sphere: g - 1 = 3 f at 1.3-1.8 P_Y, E/sigma_Y 30), the
    interpolation returned up to 2 % more work than the loading took at 1.1-1.3 P_Y."""
    from nfdmodel.pchip import pchip_evaluate, pchip_slopes

    edges = x_unload[x_unload <= low * (1 + 1e-9)]
    if edges.size < 2 or not edges[-1] > 1.0:
        return x_unload, rho, m
    t = np.arange(1, BELOW_SUBDIVISIONS) / BELOW_SUBDIVISIONS
    dense = np.sort(np.concatenate([edges[1:-1], (edges[:-1, None] + np.diff(edges)[:, None] * t).ravel()]))
    rho_dense = pchip_evaluate(x_unload, rho, pchip_slopes(x_unload, rho), dense)[0]
    m_dense = pchip_evaluate(x_unload, m, pchip_slopes(x_unload, m), dense)[0]

    def approach(s):                # D(s), the scaled loading approach
        return (np.cbrt(s) + pchip_evaluate(x, f, pchip_slopes(x, f), s)[0]) ** 2 / pchip_evaluate(
            x, g, pchip_slopes(x, g), s)[0]

    path = 1.0 + (dense[:, None] - 1.0) * np.linspace(0.0, 1.0, 401)          # 1 .. x_k, 400 panels each
    values = approach(path)
    work = dense * values[:, -1] - 0.6 - np.sum(0.5 * (values[:, 1:] + values[:, :-1]) * np.diff(path), axis=1)
    share = dense * values[:, -1] * (1.0 - rho_dense) / work              # (m + 1) at e = 1
    if np.all(m_dense + 1.0 >= share * (1.0 - 1e-9)):       # the law's own tolerance (nfdmodel.vz_table)
        return x_unload, rho, m
    m_dense = np.maximum(m_dense, share / (1.0 - DISSIPATION_SLOPE * (dense - 1.0)) - 1.0)
    keep = x_unload >= low * (1 - 1e-9)
    return (np.concatenate([[1.0], dense, x_unload[keep]]), np.concatenate([[0.0], rho_dense, rho[keep]]),
            np.concatenate([[m[0]], m_dense, m[keep]]))


def proportional_below(x: np.ndarray, f: np.ndarray, g: np.ndarray, low: float) -> np.ndarray:
    """g at the loads x with g - 1 = k f on 1 < x_k < low (below the nodes' lowest unloading path), k the
    proportion at the highest such load, at most calib.fit.table_fit.K_BELOW_LOWEST_MAX.

    Each node's table is proportional there (calib.fit.table_fit), each with its own k; interpolated
    across nodes f and g - 1 are not, and where the PCHIP end slopes at x = 1 give g'/f' > 10/3 a cycle
    just above P_Y returns more work than it took (nu 0.46, E/sigma_Y 114: 1.4e-6 of it at 1.005 P_Y;
    nu 0.22, E/sigma_Y 130: f'(1) = 0): the law refused 25 of 7080 materials and laws of the shipped table
    (59 nu x 120 E/sigma_Y, vz-table and vz-unload), none with it. Proportional node values have proportional
    PCHIP slopes. It moves g and the loading approach by at most 2.6e-4 (nu 0.23, E/sigma_Y 100; 30 nu x 60
    E/sigma_Y), far inside BELOW_NODES' figures."""
    below = np.flatnonzero((x > 1.0) & (x < low * (1 - 1e-9)))
    if below.size == 0 or not f[below[-1]] > 0.0:
        return g
    k = min((g[below[-1]] - 1.0) / f[below[-1]], K_BELOW_LOWEST_MAX)
    g = g.copy()
    g[below] = 1.0 + k * f[below]
    return g


def pchip_along(axis: np.ndarray, values: np.ndarray, at: float) -> np.ndarray:
    """Monotone cubics through (axis, values[i, ...]) along axis 0, at ``at`` (lines through two points)."""
    if axis.size == 1:
        return values[0]
    if axis.size == 2:
        t = (at - axis[0]) / (axis[1] - axis[0])
        return (1.0 - t) * values[0] + t * values[1]
    if not axis[0] <= at <= axis[-1]:
        return np.full(values.shape[1:], np.nan)            # no extrapolation
    from nfdmodel.pchip import pchip_evaluate, pchip_slopes

    return pchip_evaluate(axis, values, pchip_slopes(axis, values), float(at))[0]


@dataclass(frozen=True)
class VZMasterTable:
    """f, g at the common loads x over the grid nu x E_over_sigma_y (NaN above a node's window)."""
    nu: np.ndarray
    E_over_sigma_y: np.ndarray
    x: np.ndarray
    f: np.ndarray                 # (len(nu), len(E_over_sigma_y), len(x))
    g: np.ndarray
    window_low: np.ndarray        # (len(nu), len(E_over_sigma_y)): the lowest unloading path [P_Y]
    window_top: np.ndarray
    rel_error: np.ndarray         # the nodes' estimated discretisation error (NaN: not estimated)
    rho: np.ndarray | None = None   # the vz-unload law's delta_res/delta_max and unloading exponent m at x
    m: np.ndarray | None = None     # (as f, g; None: a table without them)
    f_a: np.ndarray | None = None   # the vz-unload law's contact radius a_p/a_Y at x (None: f's)
    meta: dict = field(default_factory=dict)
    path: Path | None = None

    @classmethod
    def from_rows(cls, rows: list[dict], meta: dict | None = None, path: Path | None = None) -> "VZMasterTable":
        where = f" in {path}" if path else ""
        need = ("nu", "E_over_sigma_y", "P_over_P_Y", "a_p_over_a_Y", "C_R", "window_low", "window_top")
        if not rows or any(k not in rows[0] for k in need):
            raise ValueError(f"vz master table{where}: need the columns {', '.join(need)}")
        nu = np.unique([float(r["nu"]) for r in rows])
        ratio = np.unique([float(r["E_over_sigma_y"]) for r in rows])
        x = np.unique([float(r["P_over_P_Y"]) for r in rows])
        shape = (nu.size, ratio.size)
        f, g = np.full(shape + (x.size,), np.nan), np.full(shape + (x.size,), np.nan)
        low, top, err = np.full(shape, np.nan), np.full(shape, np.nan), np.full(shape, np.nan)
        unloading = all(k in rows[0] for k in UNLOADING_COLUMNS)
        rho, m = np.full(shape + (x.size,), np.nan), np.full(shape + (x.size,), np.nan)
        radius = RADIUS_COLUMN in rows[0]
        f_a = np.full(shape + (x.size,), np.nan)
        for r in rows:
            i, j, k = (int(np.searchsorted(a, float(r[c]))) for a, c in
                       ((nu, "nu"), (ratio, "E_over_sigma_y"), (x, "P_over_P_Y")))
            f[i, j, k], g[i, j, k] = (float(r[c]) if isinstance(r[c], float) else np.nan for c in ("a_p_over_a_Y", "C_R"))
            if unloading:
                rho[i, j, k], m[i, j, k] = (float(r[c]) if isinstance(r[c], float) else np.nan
                                            for c in UNLOADING_COLUMNS)
            if radius:
                f_a[i, j, k] = float(r[RADIUS_COLUMN]) if isinstance(r[RADIUS_COLUMN], float) else np.nan
            low[i, j], top[i, j] = float(r["window_low"]), float(r["window_top"])
            e = r.get("rel_error_estimate")
            err[i, j] = float(e) if isinstance(e, float) else np.nan
        if np.isnan(low).any():
            missing = [(float(nu[i]), float(ratio[j])) for i, j in zip(*np.nonzero(np.isnan(low)))]
            raise ValueError(f"vz master table{where}: grid nodes (nu, E/sigma_Y) without a value: {missing}")
        if nu.size < 2 or ratio.size < 2 or x[0] != 1.0:
            raise ValueError(f"vz master table{where}: need >= 2 values of nu and of E/sigma_Y and loads from P/P_Y = 1")
        return cls(nu, ratio, x, f, g, low, top, err, rho if unloading else None, m if unloading else None,
                   f_a if radius else None, meta or {}, path)

    @classmethod
    def load(cls, path: str | Path | None = None) -> "VZMasterTable":
        """The table at ``path`` (default: the shipped one) with its metadata (same name, .json)."""
        path = Path(path) if path is not None else DEFAULT_TABLE
        return cls.from_rows(read_rows(path), read_meta(path, "vz_master_table"), path)

    def check(self, nu: float, E_over_sigma_y: float) -> None:
        """ValueError naming the parameter and the table's range when (nu, E/sigma_Y) is outside it."""
        check_axes(self.nu, self.E_over_sigma_y, nu, E_over_sigma_y, "the vz master table",
                   "nfdcal calibrate --v-max")

    @staticmethod
    def _reaches(columns: np.ndarray, log_ratio: np.ndarray, lr: float) -> bool:
        """Whether the E/sigma_Y columns that reach a load bracket log10(E/sigma_Y) = lr."""
        valid = np.nonzero(columns)[0]
        return bool(valid.size and log_ratio[valid[0]] - 1e-12 <= lr <= log_ratio[valid[-1]] + 1e-12)

    def _bracket(self, axis: np.ndarray, value: float) -> slice:
        i = int(np.clip(np.searchsorted(axis, value), 1, axis.size - 1))
        return slice(i - 1, i + 1)

    def tables(self, nu: float, E_over_sigma_y: float, same_columns: bool = False) -> dict:
        """x, f, g at (nu, E/sigma_Y) on the common loads the material's window covers, the window
        [low, top] in P/P_Y and the surrounding nodes' largest estimated discretisation error. Each load
        interpolates over the E/sigma_Y columns reaching it; ``same_columns``: every load over those reaching
        the window's top (no step where a column ends inside the window: calib.fit.vz_hardening's share)."""
        self.check(nu, E_over_sigma_y)
        nu = min(max(nu, self.nu[0]), self.nu[-1])
        lr = float(np.clip(np.log10(E_over_sigma_y), *np.log10(self.E_over_sigma_y[[0, -1]])))
        log_ratio = np.log10(self.E_over_sigma_y)
        both = np.stack([self.f, self.g], axis=-1)                 # (nu, ratio, x, 2)
        finite = np.all(np.isfinite(both), axis=(0, 3))                # (ratio, x): every nu reaches x_k
        reach = np.array([self._reaches(finite[:, k], log_ratio, lr) for k in range(self.x.size)])
        stop = int(np.argmin(reach)) if not reach.all() else self.x.size   # the loads up to the first unreached one
        if same_columns and stop:
            finite = finite & finite[:, [stop - 1]]
        value = self._interpolate(both, finite, stop, nu, lr)
        xs, fs, gs = self.x[:stop], value[:, 0], value[:, 1].copy()
        if stop < 2:
            raise ValueError(f"E/sigma_Y = {E_over_sigma_y:g}: the vz master table's nodes around it reach no load above P_Y")
        f = np.maximum.accumulate(np.maximum(fs, 0.0))    # monotone, as VZTableParams needs
        f[0], gs[0] = 0.0, 1.0
        around = (self._bracket(self.nu, nu), self._bracket(self.E_over_sigma_y, 10.0 ** lr))
        errors = self.rel_error[around]
        low = float(self.window_low[around].max())
        gs = proportional_below(xs, f, gs, low)
        out = {"x": np.array(xs), "f": f, "g": gs, "low": min(low, xs[-1]), "top": xs[-1],
               "rel_error_estimate": None if np.isnan(errors).any() else float(errors.max())}
        if self.has_unloading:        # rho, m on the same loads from the same columns as f, g
            unloading = self._interpolate(np.stack([self.rho, self.m], axis=-1), finite, stop, nu, lr)
            out["rho"], out["m"] = unloading[:, 0].copy(), unloading[:, 1].copy()
            out["rho"][0], out["m"][0] = 0.0, HERTZ_EXPONENT      # first yield: Hertz's, exactly
        if self.f_a is not None:       # the vz-unload law's radius, the same way
            f_a = self._interpolate(self.f_a[..., None], finite, stop, nu, lr)[:, 0]
            out["f_a"] = np.maximum.accumulate(np.maximum(f_a, 0.0))
            out["f_a"][0] = 0.0
        return out

    def _interpolate(self, stack: np.ndarray, finite: np.ndarray, stop: int, nu: float, lr: float) -> np.ndarray:
        """The columns ``stack`` (nu, ratio, x, n) at (nu, log10 E/sigma_Y = lr) on the loads x_k, k < stop:
        PCHIP in nu, then in log10(E/sigma_Y) over the columns ``finite`` (ratio, x) that reach each x_k."""
        log_ratio = np.log10(self.E_over_sigma_y)
        at_nu = pchip_along(self.nu, np.where(np.isfinite(stack), stack, 0.0), nu)   # (ratio, x, n); unreached: unused
        value = np.empty((stop, stack.shape[-1]))
        k = 0
        while k < stop:                  # runs of loads reached by the same E/sigma_Y columns: one interpolation
            end = k + 1
            while end < stop and np.array_equal(finite[:, end], finite[:, k]):
                end += 1
            valid = np.nonzero(finite[:, k])[0]
            # lr within _reaches' 1e-12 of the columns' end (E/sigma_Y = 300 (1 - 2e-15)): at that end, not NaN
            at = min(max(lr, log_ratio[valid[0]]), log_ratio[valid[-1]])
            value[k:end] = pchip_along(log_ratio[valid], at_nu[valid, k:end], at)
            k = end
        return value

    @property
    def radius_reach(self) -> float:
        """The contact radius / R its FE vouches for: the finite strain's (FE_FINITE_MAX_CONTACT_RADIUS_OVER_R)
        for a table joined with a finite-strain scene (calib.fit.vz_master_join), else the small strain's."""
        return (limits.FE_FINITE_MAX_CONTACT_RADIUS_OVER_R if self.meta.get("kinematics") == "finite-strain"
                else limits.FE_MAX_CONTACT_RADIUS_OVER_R)

    @property
    def has_unloading(self) -> bool:
        """Whether the table carries the vz-unload law's rho and m (:func:`unload_law`)."""
        return self.rho is not None and self.m is not None

    def law(self, material: Material, R: float) -> VZTableParams:
        """The vz-table law of a sphere of ``material`` and radius R [m] on a rigid flat, declared on
        the table's window at that material."""
        return self.vz_table_of(self.tables(float(material.nu), float(material.E / material.sigma_y)),
                                ContactPair.sphere_flat(material, R))

    def vz_table_of(self, values: dict, pair: ContactPair) -> VZTableParams:
        """The vz-table law of :meth:`tables` ``values`` (or values derived from them: calib.fit.vz_hardening)
        for ``pair``, declared on their window."""
        return VZTableParams(pair, tuple(values["x"]), tuple(values["f"]), tuple(values["g"]),
                             self._window(values, pair))

    def _window(self, values: dict, pair: ContactPair, law: str = "vz-table") -> CalibrationWindow:
        """The window of :meth:`tables` ``values`` for ``pair``, from P_Y (the ``law``'s loading, unloading
        and dent checked below the nodes' lowest path against the FE: BELOW_NODES)."""
        a_top = pair.a_Y * (np.cbrt(values["top"]) + values["f"][-1]) / pair.R_star   # the law's a = a_Y (x^(1/3) + f)
        # every node ran to at most the FE's reach (vz_master_build.run_task); the law's radius can
        # overstate the estimate that reach is set by (0.201 against 0.2 R at E/sigma_Y 100, small strain;
        # the FE's own contact radius there is 0.185 R)
        name = self.path.name if self.path else "vz master table"
        nodes = (f"{name}: FE unloading paths of the surrounding nodes from {values['low']:.3g} "
                 f"to {values['top']:.4g} P_Y" + (f" ({self.meta['kinematics']} where the contact passes "
                                                  f"{self.meta['join']['join_a_over_R']:g} R)"
                                                  if self.meta.get("kinematics") else ""))
        below = BELOW_NODES[law]
        return CalibrationWindow(1.0, values["top"], float(min(a_top, self.radius_reach)),
                                 f"{nodes}; from P_Y to {values['low']:.3g} P_Y interpolated from Hertz's, checked "
                                 f"against the FE (e {below['e_error']:.2%}, force {below['force_error']:.1%}, dent "
                                 f"{below['dent_error_of_alpha_max']:.1%} of alpha_max at worst)"
                                 + values.get("source_note", ""))

    def unload_law(self, material: Material, R: float) -> VZUnloadParams:
        """The vz-unload law of that sphere: the table's rho, m interpolated at :meth:`law`'s loads
        (rho = 0, m = 3/2 at P_Y; below the nodes' lowest path the FE's dent shape, dent_below), declared from
        P_Y (below the nodes' lowest unloading path checked against the FE: BELOW_NODES). Its contact radius is the
        table's own f_a (fitted to the FE's, RADIUS_COLUMN) and its loading the vz-table law's at
        every table load: D = (x^(1/3) + f)^2 / g = (x^(1/3) + f_a)^2 / g_a, so

            g_a(x_k) = g(x_k) ((x_k^(1/3) + f_a(x_k)) / (x_k^(1/3) + f(x_k)))^2

        (a table without f_a: f_a = f, g_a = g). A ValueError when the table carries no unloading columns."""
        return self.vz_unload_of(self.tables(float(material.nu), float(material.E / material.sigma_y)),
                                 ContactPair.sphere_flat(material, R))

    def vz_unload_of(self, values: dict, pair: ContactPair) -> VZUnloadParams:
        """The vz-unload law of :meth:`tables` ``values`` (as :meth:`vz_table_of`) for ``pair``
        (:meth:`unload_law`)."""
        if not self.has_unloading:
            name = self.path.name if self.path else "vz master table"
            raise ValueError(f"{name} has no columns {', '.join(UNLOADING_COLUMNS)}: the vz-unload law needs them "
                             f"(nfdcal table vz_master_grid --master-out CSV writes them)")
        f, g = values["f"], values["g"]
        if "f_a" in values:
            c = np.cbrt(values["x"])
            f, g = values["f_a"], g * ((c + values["f_a"]) / (c + f)) ** 2
        x_unload, rho, m = dent_below(values["x"], values["rho"], values["m"], values["low"])
        window = self._window({**values, "f": f}, pair, "vz-unload")
        x_unload, rho, m = admissible_below(values["x"], f, g, x_unload, rho, m, values["low"])
        return VZUnloadParams(pair, tuple(values["x"]), tuple(f), tuple(g), window, tuple(x_unload), tuple(rho),
                              tuple(m))

    @property
    def accuracy(self) -> str:
        return self.meta.get("accuracy", "not stated")

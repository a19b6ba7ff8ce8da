"""When fit-data's vz-table fit is no fit (``nfdcal fit-data``, the default law): the residual
ceiling, an interval wider than the value, the data's window at the point estimate, and the
likely cause of data refused (calib.fit.measured.diagnosis).

**Residual ceiling.** Group g (e, P_max, contact_time, force: n_g relative residuals r_g of
calib.fit.measured.table_law) is judged against

    c_g = hypot(l_g, s_g),   refused when  chi2_g = r_g.r_g / c_g^2 > chi2.isf(1e-3, n_g)

l_g the law's measured rms residual on noise-free FE data of this data kind (the vz master table's
.json, ``model_form.residual_rms``), s_g the stated noise (--noise) or, when none is stated, the
largest plausible scatter of that kind of measurement (calib.fit.measured.scatter
PLAUSIBLE_SCATTER: e 10 %, P_max, contact time and force 20 %). Data at the ceiling are refused
once in a thousand fits (six drop tests: rms above 1.93 c_g). On the FE's drop tests
(results/impact/drop_tests.csv, sigma_Y 1e8 Pa) P_max in kN leaves 7.2e4 % on P_max, a contact
time in ms 99.9 %, --rho 7850 for 2699 77 %, --pair on sphere-on-flat data 57 %: each far above it.

**No fit.** A 95 % interval wider than the value (high - low > sigma_Y) says the data do not
determine sigma_Y: refused.

**Window.** The data's loads P/P_Y (drop tests: the law's P_max at the fit; force curves: each
test's peak) are judged at the point estimate, never widened by the fit's own interval (a bad
enough fit's interval admits any load); a load within the law's model-form uncertainty of the
edge counts as inside: P/P_Y ~ sigma_Y^-3, the factor exp(3 x 1.96 u), u the model-form standard
uncertainty in ln sigma_Y (0.45 %: 2.7 %). The default law leaves the drop tests outside out of
the fit (named in the summary) and refits, until the set is stable; fewer than ``MIN_TESTS``
inside: refused.

**Likely cause** (of residuals above the ceiling, or of data the fit refuses). Each column rescaled as calib.fit.measured.diagnosis tries it; a rescaled data
set is plausible when some sigma_Y inside the table (not on its edge) passes the ceiling: sum_g chi2_g minimized over
ln sigma_Y (a ``SCAN``-point scan over the table, each trial law built once for every rescaling,
then one parabolic step about the best point: the verdict needs the minimum's level, not its place).
"""
from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np
from scipy import stats

from calib.fit.measured import diagnosis, imprint
from calib.fit.measured.data import Measurements
from calib.fit.measured.interval import Z95
from calib.fit.measured.scatter import PLAUSIBLE_SCATTER, SIGNIFICANCE
from calib.fit.measured.specimen import Specimen
from calib.fit.measured.table_law import (TableLawFit, data_kind, fit, law_name, predict, residuals_of,
                                          sigma_y_range, table_law)
from calib.fit.vz_master_table import VZMasterTable
from nfdmodel import RangeWarning, collision_reference

MIN_TESTS = 2            # drop tests left inside the window, at least
SCAN = 25                # the diagnosis's scan of ln sigma_Y over the table
PRESCREEN = 20.0         # a scan minimum above this x the summed thresholds is not refined


def ceilings(table: VZMasterTable, kind: str, names, noise: float | None) -> dict[str, float]:
    """c_g [-] per group (module doc)."""
    level = imprint.model_form(table).get("residual_rms", {})
    return {name: math.hypot(float(level.get(f"{kind}: {name}", 0.0)),
                             PLAUSIBLE_SCATTER[name] if noise is None else noise) for name in names}


def ceiling_excess(groups: dict, ceiling: dict) -> list[str]:
    """The groups whose chi2 against the ceiling exceeds the 1e-3 quantile, in words ([] when none)."""
    out = []
    for name, r in groups.items():
        chi2 = float(r @ r) / max(ceiling[name], 1e-300) ** 2
        threshold = float(stats.chi2.isf(SIGNIFICANCE, r.size))
        if chi2 > threshold:
            out.append(f"{name} rms {100 * math.sqrt(float(r @ r) / r.size):.3g} % against a ceiling of "
                       f"{100 * ceiling[name]:.2g} % (chi-square {chi2:.3g} > {threshold:.3g}, {r.size} values)")
    return out


def refusal(result: TableLawFit, table: VZMasterTable, noise: float | None) -> str:
    """Why ``result`` is no fit (module doc: the residual ceiling), "" when it is one."""
    kind = result.uncertainty["kind"]
    excess = ceiling_excess(result.residuals, ceilings(table, kind, result.residuals, noise))
    if excess:
        said = ("the stated noise" if noise is not None else
                "the largest plausible scatter (--noise states the data's own)")
        return (f"the vz-table law does not fit these data: residuals far above the law's measured level and "
                f"{said}: {'; '.join(excess)}")
    return ""


def undetermined(result: TableLawFit) -> str:
    """Why the data do not determine sigma_Y (module doc: an interval wider than the value), "" when they do."""
    low, high = result.interval95
    if high - low > result.sigma_y:
        return (f"the data do not determine sigma_Y: its 95 % interval {low:.4g}..{high:.4g} Pa is wider than the "
                f"value {result.sigma_y:.4g} Pa; more tests over a wider range of loads (drop tests from 2 to 100 "
                f"v_Y, or a force-approach curve) would; nothing written")
    return ""


def tolerance(result: TableLawFit) -> float:
    """The window's tolerance factor exp(3 x 1.96 u) (module doc)."""
    return math.exp(3.0 * Z95 * result.uncertainty["u_ln_sigma_y"])


def drop_loads(law, v_in: np.ndarray) -> np.ndarray:
    """P/P_Y [-] of each drop test by the law."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RangeWarning)
        return np.asarray(collision_reference(law_name(law), law, v_in).P_max) / law.pair.P_Y


def outside(x: np.ndarray, window, factor: float) -> np.ndarray:
    """Loads beyond the window by more than ``factor`` (elastic ones, P/P_Y <= 1, are inside)."""
    return (x > window.P_max_over_P_Y * factor) | ((x > 1.0) & (x < window.P_min_over_P_Y / factor))


def fit_in_window(data: Measurements, specimen: Specimen, table: VZMasterTable, sigma_y: float | None,
                  noise: float | None, leave_out: bool) -> tuple[TableLawFit, Measurements, list[dict]]:
    """The fit, the data it used and the drop tests left out (module doc: ``leave_out``, the
    default law, fits the tests inside the window; fewer than MIN_TESTS inside: all kept, the
    caller's window check refuses)."""
    result = fit(data, specimen, table, sigma_y, noise)
    if not leave_out or data.impacts is None:
        return result, data, []
    kept, used = np.ones(data.impacts.e.size, bool), data
    for _ in range(4):
        inside = ~outside(drop_loads(result.law, data.impacts.v_in), result.law.window, tolerance(result))
        if (inside == kept).all() or inside.sum() < MIN_TESTS:
            break
        kept = inside
        used = dataclasses.replace(data, impacts=data.impacts.subset(kept))
        result = fit(used, specimen, table, sigma_y, noise)
    if kept.all():
        return result, data, []
    x = drop_loads(result.law, data.impacts.v_in)
    left = [{"row": int(data.impacts.rows[k]), "v_in": float(data.impacts.v_in[k]), "P_over_P_Y": float(x[k])}
            for k in np.flatnonzero(~kept)]
    return result, used, left


def likely_cause(data: Measurements, specimen: Specimen, table: VZMasterTable, noise: float | None) -> str:
    """In words, the likely cause of data the vz-table law does not fit (module doc)."""
    low, high = np.log(sigma_y_range(specimen, table))
    grid = np.linspace(low, high, SCAN)
    laws = {}

    def law_at(theta):
        if theta not in laws:
            try:
                laws[theta] = table_law(specimen, math.exp(theta), table)
            except ValueError:
                laws[theta] = None
        return laws[theta]

    predictions = {}

    def predicted(law, theta, scaled):      # the law's predictions depend on v_in and approach only
        key = (theta, None if scaled.impacts is None else scaled.impacts.v_in.tobytes(),
               None if scaled.forces is None else tuple(a.tobytes() for _, a, _ in scaled.forces.tests))
        if key not in predictions:
            predictions[key] = predict(law, scaled)
        return predictions[key]

    def plausible_fit(scaled):
        names = scaled.group_sizes()
        ceiling = ceilings(table, data_kind(scaled), names, noise)
        thresholds = {name: float(stats.chi2.isf(SIGNIFICANCE, n)) for name, n in names.items()}

        def chi2(theta):
            law = law_at(float(theta))
            if law is None:
                return None
            try:
                g = residuals_of(predicted(law, float(theta), scaled), scaled)
            except ValueError:
                return None
            return {name: float(g[name] @ g[name]) / ceiling[name] ** 2 for name in names}, g

        def cost(theta):
            c = chi2(theta)
            return math.inf if c is None or not all(map(math.isfinite, c[0].values())) else sum(c[0].values())

        costs = np.array([cost(t) for t in grid])
        i = int(np.argmin(costs))
        if not costs[i] < PRESCREEN * sum(thresholds.values()) or i in (0, SCAN - 1):
            return None                     # far off, or best on the table's edge: no fit
        theta = float(grid[i])
        if 0 < i < SCAN - 1 and np.isfinite(costs[i - 1:i + 2]).all():     # one parabolic step about the scan's best
            left, mid, right = costs[i - 1:i + 2]
            curvature = left - 2.0 * mid + right
            if curvature > 0.0:
                vertex = theta + 0.5 * (grid[1] - grid[0]) * (left - right) / curvature
                theta = float(vertex) if cost(vertex) < mid else theta
        values, g = chi2(theta)
        if any(values[name] > thresholds[name] for name in names):
            return None
        r = np.concatenate(list(g.values()))
        rms = float(np.sqrt(np.mean(r ** 2)))
        return rms, f"rms residual {100 * rms:.3g} %, sigma_Y = {math.exp(theta):.4g} Pa"

    return diagnosis.find_cause(data, specimen, plausible_fit)

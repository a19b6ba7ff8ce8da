"""Why the vz law does not fit measurements: the likely cause, named (``nfdcal fit-data``).

A fit that fails for a reason of the data (calib.fit.measured.regression.DataMismatch: best at
an edge of the model's range, nowhere the law can be evaluated, or all data below first yield)
or leaves a residual far above any plausible scatter (calib.fit.measured.scatter) is examined
for the usual causes, in this order:

    units    each numeric column rescaled by the factors of its common other units
             (``UNIT_SLIPS``: v_in in mm/s or cm/s; P_max and force in kN or mN; contact_time in
             ms or us; dent, radius and approach in mm or um), then by every other power of ten 1e-3..1e3
             (``POWERS_OF_TEN``, e included), and the law refitted (the vz law: sigma_Y with the
             master table's constants, --free: Ca_hat, Kc_hat at the given sigma_Y; the vz-table
             law: calib.fit.measured.table_refusal); a slip is named when that refit is
             plausible, the smallest rms residual among several, a common unit before a bare power
             of ten
    columns  a force-approach file with its two columns swapped, refitted the same way
    trend    above first yield the law's e falls as v_in grows; measured e that do not fall
             (Spearman's rank correlation with v_in not negative at the 5 % level, one-sided;
             at least ``TREND_TESTS`` tests) suggest that the e or the v_in column holds other values
    material otherwise, the message names the material flags to check

Each refit costs one fit of the data (about 0.1 s for 20 drop tests, 1 s for 100k rows).
"""
from __future__ import annotations

import dataclasses

import numpy as np
from scipy import stats

from calib.fit.master_table import MasterTable
from calib.fit.measured.data import ForceApproachData, ImpactData, Measurements
from calib.fit.measured.models import check_table_covers, starting_sigma_y
from calib.fit.measured.regression import FitResult, ModelSpec, fit_model
from calib.fit.measured.scatter import Scatter
from calib.fit.measured.specimen import Specimen

# column -> (factor to SI, the unit that factor converts from)
UNIT_SLIPS = {"v_in": ((1e-3, "mm/s"), (1e-2, "cm/s")),
              "P_max": ((1e3, "kN"), (1e-3, "mN")),
              "contact_time": ((1e-3, "ms"), (1e-6, "us")),
              "dent": ((1e-3, "mm"), (1e-6, "um")),
              "radius": ((1e-3, "mm"), (1e-6, "um")),
              "approach": ((1e-3, "mm"), (1e-6, "um")),
              "force": ((1e3, "kN"), (1e-3, "mN"))}
SI_UNITS = {"v_in": "m/s", "e": "-", "P_max": "N", "contact_time": "s", "dent": "m", "radius": "m", "approach": "m", "force": "N"}
POWERS_OF_TEN = (1e3, 1e-3, 1e2, 1e-2, 1e1, 1e-1)     # any column off by one of these (module doc)
TREND_TESTS = 5
TREND_SIGNIFICANCE = 0.05


def refit(data: Measurements, specimen: Specimen, table: MasterTable, model: str,
          sigma_y: float | None) -> FitResult:
    """One least-squares fit of the model used (no identifiability report): sigma_Y with the
    master table's Ca_hat, Kc_hat, or (``model`` "free" with ``sigma_y`` given) Ca_hat, Kc_hat."""
    if model == "free" and sigma_y is not None:
        try:
            start = dict(zip(("Ca_hat", "Kc_hat"), table.lookup(specimen.nu, specimen.E / sigma_y)))
        except ValueError:
            start = {"Ca_hat": 0.0258, "Kc_hat": 0.0109}
        return fit_model(data, specimen, ModelSpec("free", ("Ca_hat", "Kc_hat"), {"sigma_y": sigma_y}), start, table)
    check_table_covers(specimen, table)
    start = starting_sigma_y(data, specimen, table, sigma_y)
    return fit_model(data, specimen, ModelSpec("constrained", ("sigma_y",)), {"sigma_y": start}, table)


def rescaled(data: Measurements, column: str, factor: float) -> Measurements:
    """``data`` with one column multiplied by ``factor``."""
    if column in ("v_in", "e", "P_max", "contact_time", "dent", "radius"):
        impacts = data.impacts
        scaled = dataclasses.replace(impacts, **{column: getattr(impacts, column) * factor})
        return dataclasses.replace(data, impacts=scaled)
    index = 1 if column == "approach" else 2
    tests = tuple(tuple(x * factor if k == index else x for k, x in enumerate(test)) for test in data.forces.tests)
    return dataclasses.replace(data, forces=dataclasses.replace(data.forces, tests=tests))


def _columns(data: Measurements) -> list[str]:
    columns = []
    if data.impacts is not None:
        columns += ["v_in", "e"]
        columns += [name for name in ("P_max", "contact_time", "dent", "radius")
                    if getattr(data.impacts, name) is not None and np.isfinite(getattr(data.impacts, name)).any()]
    if data.forces is not None:
        columns += ["force", "approach"]
    return columns


def _swapped(forces: ForceApproachData) -> ForceApproachData:
    return dataclasses.replace(forces, tests=tuple((label, force, approach) for label, approach, force in forces.tests))


def _plausible_refit(data, specimen, table, model, sigma_y) -> FitResult | None:
    try:
        fit = refit(data, specimen, table, model, sigma_y)
    except ValueError:
        return None
    return fit if fit.scatter.plausible else None


def _describe(fit: FitResult) -> str:
    values = fit.values
    fitted = (f"sigma_Y = {values['sigma_y']:.4g} Pa" if "sigma_y" in fit.spec.free
              else f"Ca_hat = {values['Ca_hat']:.4g}, Kc_hat = {values['Kc_hat']:.4g}")
    return f"rms residual {100 * fit.rms_residual:.3g} %, {fitted}"


def trend_hint(impacts: ImpactData) -> str:
    """A sentence when the measured e do not fall with v_in (module doc), else ""."""
    if impacts is None or impacts.e.size < TREND_TESTS or np.ptp(impacts.v_in) == 0 or np.ptp(impacts.e) == 0:
        return ""
    result = stats.spearmanr(impacts.v_in, impacts.e, alternative="less")
    if result.pvalue < TREND_SIGNIFICANCE:
        return ""
    return (f"the measured e do not fall as v_in grows (Spearman's rank correlation {result.statistic:+.2f} over "
            f"{impacts.e.size} tests, p = {result.pvalue:.2g}), as impacts beyond first yield do: check that the "
            f"columns e and v_in hold these tests' restitution coefficients and impact speeds")


def slips(column: str) -> tuple:
    """(factor to SI, what the column then was) to try for ``column`` (module doc): its common other
    units, then every other power of ten from 1e-3 to 1e3."""
    named = UNIT_SLIPS.get(column, ())
    others = tuple((f, None) for f in POWERS_OF_TEN if not any(abs(f / g - 1) < 1e-9 for g, _ in named))
    return named + others


def _slip_words(column: str, factor: float, unit: str | None) -> tuple[str, str]:
    """(what the column looks like, how the refit converts it) in words."""
    if unit is not None:
        return f"like {unit}, not {SI_UNITS[column]}", f"multiplied by {factor:g} ({unit} to {SI_UNITS[column]})"
    size = f"{1 / factor:g} times too large" if factor < 1 else f"{factor:g} times too small"
    return size, f"multiplied by {factor:g}"


def find_cause(data: Measurements, specimen: Specimen, plausible_fit) -> str:
    """In words, the likely cause of data a law does not fit (module doc); ``plausible_fit(data)``:
    (rms residual, the fit in words) of a refit of ``data`` whose residual is plausible, else None
    (each law judges plausibility its own way)."""
    found = {}
    for column in _columns(data):
        for factor, unit in slips(column):
            fit = plausible_fit(rescaled(data, column, factor))
            if fit is not None:
                found.setdefault(column, []).append((fit[0], factor, unit, fit[1]))
    named = {column: [slip for slip in found_slips if slip[2] is not None] for column, found_slips in found.items()}
    named = {column: found_slips for column, found_slips in named.items() if found_slips}
    found = named or found          # a common unit is far likelier than a bare power of ten
    if found:
        column, found_slips = min(found.items(), key=lambda item: min(slip[0] for slip in item[1]))
        found_slips.sort(key=lambda slip: slip[0])
        words = [_slip_words(column, factor, unit) for _, factor, unit, _ in found_slips]
        fits = "; ".join(f"{how} the data fit: {fit}" for (_, how), (_, _, _, fit) in zip(words, found_slips))
        unit = SI_UNITS[column]
        units = [u for _, _, u, _ in found_slips if u is not None]
        either = " or ".join(([f"like {' or '.join(units)}, not {unit}"] if units else [])
                             + [looks for (looks, _), slip in zip(words, found_slips) if slip[2] is None])
        return (f"likely cause: the column {column} looks {either}: {fits}; give {column} "
                + (f"in {unit}" if unit != "-" else "as a ratio (0 < e <= 1)"))
    if data.forces is not None:
        fit = plausible_fit(dataclasses.replace(data, forces=_swapped(data.forces)))
        if fit is not None:
            return (f"likely cause: the columns approach and force of {data.forces.path} look swapped: swapped, the "
                    f"data fit: {fit[1]}")
    tried = "; ".join(f"{column} in {', '.join(unit for _, unit in UNIT_SLIPS[column])}" if column in UNIT_SLIPS
                      else column for column in _columns(data))
    trend = trend_hint(data.impacts)
    columns = trend or "check that each column holds what its header names"
    flags = "--E, --nu, --R, --rho" + (" and --pair" if specimen.two_spheres else " (and --pair for two spheres)")
    return (f"no unit slip explains it (tried {tried}, and each column off by a power of ten 1e-3..1e3); {columns}; "
            f"and that {flags} describe the tested specimen (a wrong material or sphere)")


def likely_cause(data: Measurements, specimen: Specimen, table: MasterTable, model: str,
                 sigma_y: float | None) -> str:
    """In words, the likely cause of data the vz law does not fit (module doc)."""
    def plausible_fit(scaled):
        fit = _plausible_refit(scaled, specimen, table, model, sigma_y)
        return None if fit is None else (fit.rms_residual, _describe(fit))

    return find_cause(data, specimen, plausible_fit)


def implausible_fit_message(scatter: Scatter, model: str, cause: str) -> str:
    """One line: the fit's residual is far above plausible scatter, the likely cause."""
    return f"the {model} model does not fit these data: {scatter.describe_implausible()}; {cause}"

"""Why the vz law does not fit measurements: the likely cause, named (``nfdcal fit-data``).

A fit that fails for a reason of the data (calib.fit.measured.regression.DataMismatch: best at
an edge of the model's range, nowhere the law can be evaluated, or all data below first yield)
or leaves a residual far above any plausible scatter (calib.fit.measured.scatter) is examined
for the usual causes, in this order:

    units    each numeric column rescaled by the factors of its common other units
             (``UNIT_SLIPS``: v_in in mm/s or cm/s; P_max and force in kN or mN; contact_time in
             ms or us; approach in mm or um) and the model refitted (sigma_Y with the master
             table's constants; --free: Ca_hat, Kc_hat at the given sigma_Y); a slip is named
             when that refit is plausible, the smallest rms residual among several
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
              "approach": ((1e-3, "mm"), (1e-6, "um")),
              "force": ((1e3, "kN"), (1e-3, "mN"))}
SI_UNITS = {"v_in": "m/s", "P_max": "N", "contact_time": "s", "approach": "m", "force": "N"}
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
    if column in ("v_in", "P_max", "contact_time"):
        impacts = data.impacts
        scaled = dataclasses.replace(impacts, **{column: getattr(impacts, column) * factor})
        return dataclasses.replace(data, impacts=scaled)
    index = 1 if column == "approach" else 2
    tests = tuple(tuple(x * factor if k == index else x for k, x in enumerate(test)) for test in data.forces.tests)
    return dataclasses.replace(data, forces=dataclasses.replace(data.forces, tests=tests))


def _columns(data: Measurements) -> list[str]:
    columns = []
    if data.impacts is not None:
        columns.append("v_in")
        columns += [name for name in ("P_max", "contact_time")
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


def likely_cause(data: Measurements, specimen: Specimen, table: MasterTable, model: str,
                 sigma_y: float | None) -> str:
    """In words, the likely cause of data the model does not fit (module doc)."""
    found = {}
    for column in _columns(data):
        for factor, unit in UNIT_SLIPS[column]:
            fit = _plausible_refit(rescaled(data, column, factor), specimen, table, model, sigma_y)
            if fit is not None:
                found.setdefault(column, []).append((fit.rms_residual, factor, unit, fit))
    if found:
        column, slips = min(found.items(), key=lambda item: min(slip[0] for slip in item[1]))
        slips.sort(key=lambda slip: slip[0])
        fits = "; ".join(f"multiplied by {factor:g} ({unit} to {SI_UNITS[column]}) the data fit: {_describe(fit)}"
                         for _, factor, unit, fit in slips)
        either = " or ".join(unit for _, _, unit, _ in slips)
        return (f"likely cause: the column {column} looks like {either}, not {SI_UNITS[column]}: {fits}; give "
                f"{column} in {SI_UNITS[column]}")
    if data.forces is not None:
        fit = _plausible_refit(dataclasses.replace(data, forces=_swapped(data.forces)), specimen, table, model, sigma_y)
        if fit is not None:
            return (f"likely cause: the columns approach and force of {data.forces.path} look swapped: swapped, the "
                    f"data fit: {_describe(fit)}")
    tried = "; ".join(f"{column} in {', '.join(unit for _, unit in UNIT_SLIPS[column])}" for column in _columns(data))
    trend = trend_hint(data.impacts)
    columns = trend or "check that each column holds what its header names"
    flags = "--E, --nu, --R, --rho" + (" and --pair" if specimen.two_spheres else " (and --pair for two spheres)")
    return (f"no common unit slip explains it (tried {tried}); {columns}; and that {flags} describe the tested "
            f"specimen (a wrong material or sphere)")


def implausible_fit_message(scatter: Scatter, model: str, cause: str) -> str:
    """One line: the fit's residual is far above plausible scatter, the likely cause."""
    return f"the {model} model does not fit these data: {scatter.describe_implausible()}; {cause}"

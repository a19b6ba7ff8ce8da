"""How far the rigid-flat substitution misses an unlike pair, from the measured map: a steer to a pair calibration.

nfdmodel mixes a sphere with an unlike counter-body by putting the pair's E* and R* and the yield point of the
body with the lower A_Y(nu) sigma_Y into the rigid-flat law with that body's constants (nfdmodel.ContactPair).
calib.studies.pairs measures what that costs against the two-body FE and ships the map
calib/data/substitution_error.csv: per counter shape (a flat, a sphere R2 = R1), yielding body (the sphere, the
counter-body, both) and E1/E2 (1/3..3, nu = 0.3), the range of the relative errors substitution / FE - 1 of the
force (equal approach), the contact radius (equal force) and e (equal P_max / P_Y) over loads 1..41.2 P_Y.

A pair is placed on the map by

    x = E1' / E2',  E' = E / (1 - nu^2)             [-]   (the grid has equal nu, E1'/E2' = E1/E2)
    q = A_Y(nu2) sigma_Y2 / (A_Y(nu1) sigma_Y1)     [-]   q < 1/BOTH_BAND: the counter-body yields first,
                                                          q > BOTH_BAND or no sigma_Y2: the sphere (column
                                                          measured with an elastic counter-body), else both

the e error range interpolated linearly in log x inside the measured E1/E2, the nearest end outside it. Where
its largest |e error| exceeds STEER_E_ERROR (2 %), ``substitution_warning`` says so in one line and names the
pair calibration (``nfdcal calibrate --counter-E ...``); ``warn_substitution`` issues it as a SubstitutionWarning
(the nfdcal commands print warnings as one line on stderr).
"""
from __future__ import annotations

import csv
import math
import warnings
from functools import lru_cache
from pathlib import Path

import numpy as np

from nfdmodel import Material
from nfdmodel.materials import plane_strain_modulus, yield_pressure

DATA_FILE = Path(__file__).resolve().parents[1] / "data" / "substitution_error.csv"
STEER_E_ERROR = 0.02        # |e error| beyond which a pair calibration is named
BOTH_BAND = 1.1             # yield pressures within 10 %: both bodies yield in the window


class SubstitutionWarning(UserWarning):
    """The measured substitution error of an unlike pair exceeds STEER_E_ERROR in e."""


@lru_cache(maxsize=4)
def measured_map(path: str | None = None) -> tuple:
    """The rows of the map (dicts: shape, yielding, E1_over_E2 and the error ranges as floats)."""
    text = Path(path or DATA_FILE).read_text(encoding="utf-8").splitlines()
    rows = csv.DictReader(line for line in text if not line.startswith("#"))
    return tuple({k: (v if k in ("shape", "yielding") else float(v)) for k, v in row.items()} for row in rows)


def placement(material: Material, counter) -> dict:
    """Where the pair of a sphere (``material``) and ``counter`` (calib.fit.counter.CounterBody) sits on the
    map: shape, yielding body, x = E1'/E2' (module docstring)."""
    x = material.plane_strain_modulus / plane_strain_modulus(counter.E, counter.nu)
    if counter.sigma_y is None:
        yielding = "sphere"
    else:
        q = yield_pressure(counter.sigma_y, counter.nu) / yield_pressure(material.sigma_y, material.nu)
        yielding = "counter" if q < 1.0 / BOTH_BAND else "sphere" if q > BOTH_BAND else "both"
    return {"shape": "flat" if counter.R is None else "sphere", "yielding": yielding, "E1_over_E2": x}


def identical(material: Material, radius: float, counter) -> bool:
    """Two identical spheres: the mid-plane is a rigid frictionless flat, the substitution exact."""
    return (counter.R is not None and math.isclose(counter.R, radius, rel_tol=1e-9)
            and (counter.E, counter.nu, counter.sigma_y) == (material.E, material.nu, material.sigma_y))


def substitution_error(material: Material, radius: float, counter, path: str | None = None) -> dict | None:
    """The measured e, force and radius error ranges [-] at the pair's place on the map (interpolated), its
    placement and whether E1/E2 lies beyond the measured range; None for identical spheres (exact)."""
    if identical(material, radius, counter):
        return None
    where = placement(material, counter)
    column = sorted((r for r in measured_map(path) if r["shape"] == where["shape"]
                     and r["yielding"] == where["yielding"]), key=lambda r: r["E1_over_E2"])
    if not column:
        return None
    xs = np.log([r["E1_over_E2"] for r in column])
    x = float(np.log(where["E1_over_E2"]))
    out = {**where, "beyond": not xs[0] - 1e-9 <= x <= xs[-1] + 1e-9,
           "measured_E1_over_E2": (column[0]["E1_over_E2"], column[-1]["E1_over_E2"])}
    for key in ("e_error", "force_error", "radius_error"):
        out[key] = tuple(float(np.interp(x, xs, [r[f"{key}_{end}"] for r in column])) for end in ("min", "max"))
    return out


def substitution_warning(material: Material, radius: float, counter, path: str | None = None) -> str | None:
    """One line when the measured |e error| of the substitution at this pair exceeds STEER_E_ERROR, naming the
    range and the pair calibration; None otherwise (and for identical spheres, where it is exact)."""
    error = substitution_error(material, radius, counter, path)
    if error is None or max(abs(v) for v in error["e_error"]) <= STEER_E_ERROR:
        return None
    low, high = error["e_error"]
    f_low, f_high = error["force_error"]
    lo, hi = error["measured_E1_over_E2"]
    where = (f"E1/E2 = {error['E1_over_E2']:.3g}" + (f", beyond the measured {lo:.3g}..{hi:.3g}: the nearest end"
                                                      if error["beyond"] else ""))
    flags = f"--counter-E {counter.E:g} --counter-nu {counter.nu:g}" + (
        "" if counter.sigma_y is None else f" --counter-sigma-y {counter.sigma_y:g}") + (
        "" if counter.R is None else f" --counter-R {counter.R:g} --counter-rho "
                                     + ("RHO" if counter.rho is None else f"{counter.rho:g}"))
    shape = "flat" if counter.R is None else "sphere"
    return (f"unlike pair ({where}, {shape} counter-body, {error['yielding']} yielding): the rigid-flat law with the "
            f"pair's E*, R* misses the two-body FE by {100 * low:+.1f}..{100 * high:+.1f} % in e and "
            f"{100 * f_low:+.1f}..{100 * f_high:+.1f} % in force (results/pairs); calibrate the pair: "
            f"nfdcal calibrate {flags}")


def warn_substitution(material: Material, radius: float, counter, path: str | None = None) -> str | None:
    """:func:`substitution_warning` issued as a SubstitutionWarning (when there is one); returns it."""
    message = substitution_warning(material, radius, counter, path)
    if message is not None:
        warnings.warn(message, SubstitutionWarning, stacklevel=2)
    return message

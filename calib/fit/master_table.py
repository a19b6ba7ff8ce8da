"""The dimensionless master table: Ca_hat, Kc_hat over (nu, E / sigma_Y), interpolated.

Scaling lengths by a_Y, approaches by delta_Y, forces by P_Y and stresses by
sigma_Y, the small-strain sphere-on-flat problem (load paths at fixed multiples of P_Y) depends
only on nu and E / sigma_Y, so

    Ca_hat = Ca P_Y / a_Y  [-],   Kc_hat = Kc P_Y  [-]

are material constants of (nu, E / sigma_Y). The table (calib/data/master_table.csv, one row per
grid node, written by ``nfdcal table`` on the built-in scene ``master_grid``) is interpolated
by monotone piecewise cubics (PCHIP) in nu and in log10(E / sigma_Y) (scipy RegularGridInterpolator,
method "pchip": no overshoot between nodes; against direct FE at five off-grid materials it halves
the error of linear interpolation, 0.48 % / 0.76 % against 1.01 % / 1.82 %), so it is exact on
the grid nodes; its metadata (calib/data/master_table.json) states the mesh, the commit and the
accuracy that was measured. A new material then needs no FE run:

    Ca = Ca_hat a_Y / P_Y  [m/N],   Kc = Kc_hat / P_Y  [1/N]   (nfdmodel VZParams.from_dimensionless)

numpy/scipy only (``nfdcal material`` answers in a fraction of a second).
"""
from __future__ import annotations

import csv
import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy.interpolate import RegularGridInterpolator

from nfdmodel import CalibrationWindow, ContactPair, Material, VZParams, limits, reference_case
from nfdmodel.reference_case import is_reference_sphere

DATA_DIR = Path(__file__).resolve().parent.parent / "data"   # calib/data: shipped with the package
DEFAULT_TABLE = DATA_DIR / "master_table.csv"
AXES = ("nu", "E_over_sigma_y")
VALUES = ("Ca_hat", "Kc_hat")
ERRORS = ("Ca_hat_rel_error_estimate", "Kc_hat_rel_error_estimate")   # per node, optional columns
INTERPOLATION = "pchip"   # scipy RegularGridInterpolator method in nu and log10(E / sigma_Y) (>= 4 nodes per axis)


def read_rows(path: str | Path) -> list[dict]:
    """The rows of a table CSV (lines starting with '#' are the stamp), numbers as floats."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"master table not found: {path}")
    lines = [line for line in path.read_text(encoding="utf-8").splitlines() if not line.startswith("#")]
    rows = []
    for raw in csv.DictReader(lines):
        row = {}
        for key, text in raw.items():
            try:
                row[key] = float(text)
            except (TypeError, ValueError):
                row[key] = text
        rows.append(row)
    return rows


def read_meta(path: Path, key: str) -> dict:
    """The metadata of a table CSV (its .json beside it; the object under ``key``), {} without one."""
    meta_path = path.with_suffix(".json")
    meta = json.loads(meta_path.read_text(encoding="utf-8")) if meta_path.is_file() else {}
    return meta.get(key, meta)


def check_axes(nu_axis, ratio_axis, nu: float, E_over_sigma_y: float, table: str, command: str) -> None:
    """ValueError naming the parameter and ``table``'s range when (nu, E/sigma_Y) lies outside its
    grid, and the FE ``command`` that calibrates such a material instead."""
    for name, value, axis in (("nu", nu, nu_axis), ("E/sigma_Y", E_over_sigma_y, ratio_axis)):
        if not (isinstance(value, (int, float)) and math.isfinite(value)):
            raise ValueError(f"{name} must be a finite number, got {value!r}")
        low, high = float(axis[0]), float(axis[-1])
        if not (low * (1 - 1e-12) <= value <= high * (1 + 1e-12) + 1e-15):
            raise ValueError(f"{name} = {value:g} is outside {table}: need {name} in [{low:g}, {high:g}] "
                             f"(calibrate this material by FE with `{command}` instead)")


@dataclass(frozen=True)
class MasterTable:
    """Ca_hat, Kc_hat on the regular grid nu x E_over_sigma_y (axes ascending)."""
    nu: np.ndarray
    E_over_sigma_y: np.ndarray
    Ca_hat: np.ndarray          # shape (len(nu), len(E_over_sigma_y))
    Kc_hat: np.ndarray
    meta: dict = field(default_factory=dict)
    path: Path | None = None
    errors: dict = field(default_factory=dict)   # ERRORS -> (len(nu), len(E_over_sigma_y)), when the table has them

    @classmethod
    def from_rows(cls, rows: list[dict], meta: dict | None = None, path: Path | None = None) -> "MasterTable":
        """Build from table rows (one per node, columns nu, E_over_sigma_y, Ca_hat, Kc_hat); every
        node of the grid must be present with finite values."""
        where = f" in {path}" if path else ""
        for key in AXES + VALUES:
            if not rows or key not in rows[0]:
                raise ValueError(f"master table{where}: missing column {key!r}")
        nu = np.unique([float(r["nu"]) for r in rows])
        ratio = np.unique([float(r["E_over_sigma_y"]) for r in rows])
        values = {k: np.full((nu.size, ratio.size), np.nan) for k in VALUES}
        for r in rows:
            i, j = np.searchsorted(nu, float(r["nu"])), np.searchsorted(ratio, float(r["E_over_sigma_y"]))
            for k in VALUES:
                v = r[k]
                values[k][i, j] = float(v) if isinstance(v, float) and math.isfinite(v) else np.nan
        missing = [(float(nu[i]), float(ratio[j])) for i, j in zip(*np.nonzero(np.isnan(values["Ca_hat"]) | np.isnan(values["Kc_hat"])))]
        if missing:
            raise ValueError(f"master table{where}: grid nodes (nu, E/sigma_Y) without a value: {missing}")
        if nu.size < 2 or ratio.size < 2:
            raise ValueError(f"master table{where}: need at least 2 values of nu and of E/sigma_Y, "
                             f"got {nu.size} x {ratio.size}")
        errors = {}
        for key in ERRORS:              # the nodes' discretisation error estimates (two-mesh tables)
            if key in rows[0]:
                grid = np.full((nu.size, ratio.size), np.nan)
                for r in rows:
                    v = r[key]
                    grid[np.searchsorted(nu, float(r["nu"])), np.searchsorted(ratio, float(r["E_over_sigma_y"]))] = \
                        float(v) if isinstance(v, float) and math.isfinite(v) and v >= 0 else np.nan
                if not np.isnan(grid).any():
                    errors[key] = grid
        return cls(nu, ratio, values["Ca_hat"], values["Kc_hat"], meta or {}, path, errors)

    @property
    def interpolation(self) -> str:
        """INTERPOLATION, or "linear" for a grid with fewer than 4 values on an axis (a cubic needs 4)."""
        return INTERPOLATION if min(self.nu.size, self.E_over_sigma_y.size) >= 4 else "linear"

    def node_error_estimates(self, nu: float, E_over_sigma_y: float) -> dict:
        """The largest estimated relative discretisation error of the (up to four) grid nodes
        around (nu, E / sigma_Y), per constant, or {} for a table without them."""
        self._check(nu, E_over_sigma_y)
        i = np.clip(np.searchsorted(self.nu, nu), 1, self.nu.size - 1)
        j = np.clip(np.searchsorted(self.E_over_sigma_y, E_over_sigma_y), 1, self.E_over_sigma_y.size - 1)
        return {key: float(grid[i - 1:i + 1, j - 1:j + 1].max()) for key, grid in self.errors.items()}

    @classmethod
    def load(cls, path: str | Path | None = None) -> "MasterTable":
        """The table at ``path`` (default: the shipped one) with its metadata (same name, .json)."""
        path = Path(path) if path is not None else DEFAULT_TABLE
        return cls.from_rows(read_rows(path), read_meta(path, "master_table"), path)

    def _check(self, nu: float, E_over_sigma_y: float) -> None:
        check_axes(self.nu, self.E_over_sigma_y, nu, E_over_sigma_y, "the master table", "nfdcal calibrate")

    def lookup(self, nu: float, E_over_sigma_y: float) -> tuple[float, float]:
        """(Ca_hat, Kc_hat) at (nu, E / sigma_Y): PCHIP in nu and log10(E / sigma_Y)."""

        self._check(nu, E_over_sigma_y)
        x = np.log10(self.E_over_sigma_y)
        point = np.array([[min(max(nu, self.nu[0]), self.nu[-1]),
                           np.clip(np.log10(E_over_sigma_y), x[0], x[-1])]])
        out = []
        for values in (self.Ca_hat, self.Kc_hat):
            out.append(float(RegularGridInterpolator((self.nu, x), values, method=self.interpolation)(point)[0]))
        return out[0], out[1]

    def window_for(self, pair: ContactPair, Ca_hat: float, Kc_hat: float) -> CalibrationWindow:
        """The window of the table's constants for ``pair``: P/P_Y of the grid's load plan (the
        table's metadata; if it does not say, nfd_limits.h's DEFAULT_WINDOW, the default recipe's
        largest peak) and the contact radius the law reaches at its top, a/R* (the nodes' FE radii
        are not stored)."""
        P_max_over_P_Y = float(self.meta.get("window_P_max_over_P_Y") or limits.DEFAULT_WINDOW)
        params = VZParams.from_dimensionless(pair, Ca_hat, Kc_hat)
        a_max = float(params.contact_radius_at(P_max_over_P_Y * pair.P_Y)) / pair.R_star
        return CalibrationWindow(1.0, P_max_over_P_Y, a_max,
                                 f"master table {self.path.name if self.path else ''}: load paths to "
                                 f"{P_max_over_P_Y:g} P_Y, a/R* of the law at the top")

    def parameters(self, E: float, nu: float, sigma_y: float, R: float, rho: float = 2700.0) -> dict:
        """Ca, Kc [SI] and the dimensionless values of a sphere (E, nu, sigma_Y, R) on a rigid flat;
        ``*_rel_error_estimate``: the surrounding nodes' largest discretisation error estimate
        (None for a table without them; the interpolation's own error is in ``accuracy``)."""

        material = Material(E, nu, sigma_y, rho)
        pair = ContactPair.sphere_flat(material, R)
        Ca_hat, Kc_hat = self.lookup(float(nu), float(E) / float(sigma_y))
        params = VZParams.from_dimensionless(pair, Ca_hat, Kc_hat, self.window_for(pair, Ca_hat, Kc_hat))
        nodes = self.node_error_estimates(float(nu), float(E) / float(sigma_y))
        return {"Ca": params.Ca, "Kc": params.Kc, "Ca_hat": Ca_hat, "Kc_hat": Kc_hat,
                "Ca_rel_error_estimate": nodes.get("Ca_hat_rel_error_estimate"),
                "Kc_rel_error_estimate": nodes.get("Kc_hat_rel_error_estimate"),
                "window": params.window.record(),
                "P_Y": pair.P_Y, "a_Y": pair.a_Y, "delta_Y": pair.delta_Y,
                "E_over_sigma_y": float(E) / float(sigma_y),
                "units": {"Ca": "m/N", "Kc": "1/N", "P_Y": "N", "a_Y": "m", "delta_Y": "m"},
                "source": "master table interpolation",
                "table": str(self.path) if self.path else None,
                "accuracy": self.meta.get("accuracy", "not stated"),
                "accuracy_details": (f"{self.path.with_suffix('.json')}: master_table.accuracy_details"
                                     if self.path and "accuracy_details" in self.meta else "none")}


def vz_constants(material: Material, radius: float) -> tuple[VZParams, str]:
    """(the vz law of a sphere given by its material alone, where its constants come from): the paper's
    calibration for the reference sphere; its dimensionless constants Ca_hat = Ca P_Y / a_Y, Kc_hat = Kc P_Y
    for the reference solid at another radius (they depend on nu and E / sigma_Y only); for another solid the
    master table's at (nu, E / sigma_Y), with its window. Outside the table: the table's ValueError."""
    pair = ContactPair.sphere_flat(material, radius)
    reference = VZParams.reference()
    if is_reference_sphere(material.E, material.nu, radius, material.sigma_y):
        return VZParams(pair, reference_case.CA, reference_case.KC, reference.window), "the paper's calibration"
    if is_reference_sphere(material.E, material.nu, reference_case.R, material.sigma_y):
        return (VZParams.from_dimensionless(pair, reference.Ca_hat, reference.Kc_hat, reference.window),
                "the paper's calibration (its dimensionless constants)")
    table = MasterTable.load()
    values = table.parameters(material.E, material.nu, material.sigma_y, radius, material.rho)
    return (VZParams.from_dimensionless(pair, values["Ca_hat"], values["Kc_hat"],
                                        CalibrationWindow.from_record(values["window"])),
            f"master table ({table.meta.get('accuracy', 'accuracy not stated')})")


# The accuracy the interpolation must reach against direct FE calibrations (Ca_hat, Kc_hat:
# 1 % and 2 %, measured by ``nfdcal table master_validation --check-master``)
CHECK_LIMITS = {"Ca_hat": 0.01, "Kc_hat": 0.02}
# The shipped table's own standard uncertainty, relative, as a systematic error of every value it
# gives (its stated accuracy, combined in quadrature): interpolation against direct FE within
# 0.48 % (Ca_hat) and 0.76 % (Kc_hat), the nodes' estimated discretisation error <= 0.64 % and 1.07 %.
RELATIVE_UNCERTAINTY = {"Ca_hat": math.hypot(0.0048, 0.0064), "Kc_hat": math.hypot(0.0076, 0.0107)}


def check_against_fe(rows: list[dict], table: "MasterTable") -> list[dict]:
    """Interpolated against directly calibrated Ca_hat, Kc_hat for each row of a parameter table
    (``nfdcal table`` rows with nu, E_over_sigma_y, Ca_hat, Kc_hat; same recipe as the master
    table): relative errors interpolated / FE - 1 and whether they are within CHECK_LIMITS."""
    out = []
    for row in rows:
        if row.get("status") != "ok":
            raise ValueError(f"master check: material {row.get('name')} has no FE result ({row.get('status')})")
        Ca_hat, Kc_hat = table.lookup(float(row["nu"]), float(row["E_over_sigma_y"]))
        errors = {"Ca_hat_error": Ca_hat / float(row["Ca_hat"]) - 1.0,
                  "Kc_hat_error": Kc_hat / float(row["Kc_hat"]) - 1.0}
        out.append({"name": row["name"], "nu": float(row["nu"]),
                    "E_over_sigma_y": float(row["E_over_sigma_y"]),
                    "Ca_hat_fe": float(row["Ca_hat"]), "Ca_hat_table": Ca_hat,
                    "Kc_hat_fe": float(row["Kc_hat"]), "Kc_hat_table": Kc_hat, **errors,
                    "within_limits": all(abs(errors[f"{k}_error"]) <= v for k, v in CHECK_LIMITS.items())})
    return out

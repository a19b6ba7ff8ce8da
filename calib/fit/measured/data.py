"""What was measured on one specimen, read from CSV and checked (SI units): drop tests and
quasi-static force-approach curves of a sphere on a rigid flat, the data ``nfdcal fit-data`` fits.

**Files** (CSV, one header line, lines starting with '#' are comments):

    impacts         v_in [m/s] > 0, e [-] in (0, 1 + E_ROUND_OFF]; optional P_max [N] > 0, contact_time [s] > 0,
                    dent [m] > 0 (the residual indentation depth, delta_res, of the test's
                    impact on a fresh spot; fitted through the vz-unload law of the vz master
                    table), radius [m] > 0 (the imprint's radius, taken as the contact radius at the
                    impact's peak: calib.fit.measured.imprint; < the sphere's R, checked by
                    fit-data) (an empty cell: not measured in that test). One row per drop test,
                    repeats at the same v_in allowed.
    force-approach  approach [m], force [N] along one or more load-unload cycles of one
                    contact, in the order measured; optional test (a label): rows with the same
                    label are one history on a fresh (virgin) specimen, in file order.

An e above 1 by at most ``E_ROUND_OFF`` (1e-3) is an FE's (or a measurement's) round-off about
an elastic impact (an FE's energy balance holds to about 1e-4: e 1.00008 at 0.5 v_Y); it is kept
as measured (no clamping: the fit compares it with the law's e <= 1, a residual of that size).
Any other column is refused; every bad cell is one ValueError naming the file, the row, its line
and the column. The residual groups of the fit (calib.fit.measured.specimen) are e, P_max,
contact_time, dent, radius and force; ``Measurements.group_sizes`` counts the values of each. The force
residuals are scaled by max(|P|, P_floor) with P_floor = 0.05 x the smallest test's peak force,
the weighting of the FE force fit (calib.fit.least_squares.fit_force_law).
"""
from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from nfdmodel.validation import check_solid, number_from_text

IMPACT_COLUMNS = {"v_in": "m/s", "e": "-"}
IMPACT_OPTIONAL = {"P_max": "N", "contact_time": "s", "dent": "m", "radius": "m"}
FORCE_COLUMNS = {"approach": "m", "force": "N"}
FORCE_OPTIONAL = {"test": "label"}
FORCE_FLOOR_FRACTION = 0.05     # P_floor = this x the smallest test's peak force (the FE force fit's)
E_ROUND_OFF = 1e-3              # e up to 1 + this is accepted (module doc: round-off about an elastic impact)


@dataclass(frozen=True)
class ImpactData:
    """Drop tests: v_in [m/s], e [-]; P_max [N], contact_time [s], dent [m] and radius [m] with NaN where
    a test did not measure them (None when the file has no such column); ``rows``: each test's data row number."""

    path: str
    v_in: np.ndarray
    e: np.ndarray
    P_max: np.ndarray | None
    contact_time: np.ndarray | None
    rows: np.ndarray
    dent: np.ndarray | None = None
    radius: np.ndarray | None = None

    def subset(self, keep: np.ndarray) -> "ImpactData":
        """The tests where ``keep`` (a boolean mask) is True, their row numbers kept."""
        return ImpactData(self.path, self.v_in[keep], self.e[keep], None if self.P_max is None else self.P_max[keep],
                          None if self.contact_time is None else self.contact_time[keep], self.rows[keep],
                          None if self.dent is None else self.dent[keep],
                          None if self.radius is None else self.radius[keep])

    @property
    def n_points(self) -> int:
        return int(self.e.size + sum(int(np.isfinite(x).sum()) for x in (self.P_max, self.contact_time, self.dent,
                                                                         self.radius) if x is not None))


@dataclass(frozen=True)
class ForceApproachData:
    """Quasi-static force-approach histories: one (label, approach [m], force [N]) per test."""

    path: str
    tests: tuple

    @property
    def n_points(self) -> int:
        return int(sum(approach.size for _, approach, _ in self.tests))

    @property
    def force_floor(self) -> float:
        """P_floor [N] = 0.05 x the smallest test's peak force (module doc)."""
        return FORCE_FLOOR_FRACTION * min(float(np.max(force)) for _, _, force in self.tests)


def _read_rows(path, what: str, required: dict, optional: dict
               ) -> tuple[list[str], dict[str, int], list[tuple[int, int, list[str]]]]:
    """(header, column index by name, [(data row number, line number, fields)]) of a CSV; ValueError
    naming the file and what is wrong (missing file, not text, no header, missing or unknown column,
    ragged row, no data rows)."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{what} file not found: {path}")
    try:
        text = path.read_text(encoding="utf-8-sig")
    except UnicodeDecodeError:
        raise ValueError(f"{what} file {path}: not a text (UTF-8) CSV file") from None
    lines = [(number, line) for number, line in enumerate(text.splitlines(), start=1)
             if line.strip() and not line.lstrip().startswith("#")]
    allowed = ", ".join([f"{k} [{u}]" for k, u in required.items()] + [f"{k} [{u}] (optional)"
                                                                        for k, u in optional.items()])
    if not lines:
        raise ValueError(f"{what} file {path}: no header line (need the columns {allowed})")
    parsed = list(csv.reader([line for _, line in lines]))
    header = [name.strip() for name in parsed[0]]
    unknown = [name for name in header if name not in required and name not in optional]
    if unknown:
        raise ValueError(f"{what} file {path}: unknown column(s) {', '.join(map(repr, unknown))} (line "
                         f"{lines[0][0]}); allowed: {allowed}")
    missing = [name for name in required if name not in header]
    if missing:
        raise ValueError(f"{what} file {path}: missing column(s) {', '.join(map(repr, missing))} (line "
                         f"{lines[0][0]}); need {allowed}")
    doubled = sorted({name for name in header if header.count(name) > 1})
    if doubled:
        raise ValueError(f"{what} file {path}: column(s) {', '.join(map(repr, doubled))} appear twice")
    rows = []
    for row, ((line, _), fields) in enumerate(zip(lines[1:], parsed[1:]), start=1):
        if len(fields) != len(header):
            raise ValueError(f"{what} file {path}: row {row} (line {line}): {len(fields)} field(s), the "
                             f"header has {len(header)}")
        rows.append((row, line, [f.strip() for f in fields]))
    if not rows:
        raise ValueError(f"{what} file {path}: no data rows")
    return header, {name: header.index(name) for name in header}, rows


def _cell(path, what, row, line, column, text, unit, low, high=None, low_inclusive=False,
          optional=False) -> float:
    """One numeric cell: a finite float in its range, NaN for an empty optional cell; else a
    ValueError naming the file, the row, the line and the column."""
    where = f"{what} file {path}: row {row} (line {line}), column {column!r}"
    if text == "" and optional:
        return math.nan
    try:
        value = number_from_text(column, text)
    except ValueError:
        hint = " (digits only, no '_': 0_05 is not 0.05)" if "_" in text else ""
        raise ValueError(f"{where}: not a number: {text!r}{hint}") from None
    bounds = (f"{column} {'>=' if low_inclusive else '>'} {low:g}" if low is not None else "") + \
             (f" and {column} <= {high:g}" if high is not None else "")
    unit = "" if unit == "-" else f" {unit}"
    if not math.isfinite(value):
        raise ValueError(f"{where}: must be a finite number ({bounds}{unit}), got {text!r}")
    if (low is not None and (value < low or (value == low and not low_inclusive))) or \
            (high is not None and value > high):
        raise ValueError(f"{where}: out of range: need {bounds}{unit}, got {value:g}")
    return value


def read_impacts(path) -> ImpactData:
    """The drop tests of ``path`` (module doc: columns v_in, e; optional P_max, contact_time, dent, radius)."""
    what = "impacts"
    header, index, rows = _read_rows(path, what, IMPACT_COLUMNS, IMPACT_OPTIONAL)
    ranges = {"v_in": ("m/s", 0.0, None), "e": ("-", 0.0, 1.0 + E_ROUND_OFF), "P_max": ("N", 0.0, None),
              "contact_time": ("s", 0.0, None), "dent": ("m", 0.0, None), "radius": ("m", 0.0, None)}
    values = {name: [] for name in header}
    for row, line, fields in rows:
        for name in header:
            unit, low, high = ranges[name]
            value = _cell(path, what, row, line, name, fields[index[name]], unit, low, high,
                          optional=name in IMPACT_OPTIONAL)
            if name == "v_in":
                try:
                    check_solid("v_in", value)
                except ValueError as exc:
                    raise ValueError(f"{what} file {path}: row {row} (line {line}), column 'v_in': {exc}") from None
            values[name].append(value)
    arrays = {name: np.asarray(v, dtype=float) for name, v in values.items()}
    return ImpactData(str(path), arrays["v_in"], arrays["e"], arrays.get("P_max"), arrays.get("contact_time"),
                      np.array([row for row, _, _ in rows]), arrays.get("dent"), arrays.get("radius"))


def read_force_approach(path) -> ForceApproachData:
    """The force-approach histories of ``path`` (module doc: columns approach, force; optional test)."""
    what = "force-approach"
    header, index, rows = _read_rows(path, what, FORCE_COLUMNS, FORCE_OPTIONAL)
    tests: dict[str, list] = {}
    for row, line, fields in rows:
        label = fields[index["test"]] if "test" in index else ""
        if "test" in index and label == "":
            raise ValueError(f"{what} file {path}: row {row} (line {line}), column 'test': empty label "
                             f"(rows with the same label are one test)")
        approach = _cell(path, what, row, line, "approach", fields[index["approach"]], "m", None)
        force = _cell(path, what, row, line, "force", fields[index["force"]], "N", None)
        tests.setdefault(label, []).append((row, approach, force))
    out = []
    for label, points in tests.items():
        approach = np.array([a for _, a, _ in points])
        force = np.array([f for _, _, f in points])
        if not force.max() > 0.0:
            raise ValueError(f"{what} file {path}: test {label or '(the only one)'} (rows {points[0][0]}.."
                             f"{points[-1][0]}), column 'force': no positive force, nothing to fit")
        out.append((label, approach, force))
    return ForceApproachData(str(path), tuple(out))


@dataclass(frozen=True)
class Measurements:
    """Everything measured on one specimen: drop tests and/or force-approach curves."""

    impacts: ImpactData | None = None
    forces: ForceApproachData | None = None

    def __post_init__(self):
        if self.impacts is None and self.forces is None:
            raise ValueError("no data: give drop tests (impacts) or force-approach curves, or both")

    @property
    def n_points(self) -> int:
        return sum(d.n_points for d in (self.impacts, self.forces) if d is not None)

    @property
    def files(self) -> list[str]:
        return [d.path for d in (self.impacts, self.forces) if d is not None]

    def group_sizes(self) -> dict[str, int]:
        """The number of measured values per residual group (e, P_max, contact_time, dent, radius, force)."""
        sizes = {}
        if self.impacts is not None:
            sizes["e"] = int(self.impacts.e.size)
            for name in ("P_max", "contact_time", "dent", "radius"):
                measured = getattr(self.impacts, name)
                if measured is not None and np.isfinite(measured).any():
                    sizes[name] = int(np.isfinite(measured).sum())
        if self.forces is not None:
            sizes["force"] = self.forces.n_points
        return sizes

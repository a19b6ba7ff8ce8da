"""Flow curves of von Mises plasticity with isotropic hardening: sigma_y(eps_bar) and H(eps_bar).

A flow curve gives the uniaxial (true) yield stress sigma_y [Pa] as a function of the equivalent
plastic strain eps_bar = int sqrt(2/3 d eps_p : d eps_p) [-] (equal to the plastic strain of a
uniaxial test), its slope, the plastic modulus H = d sigma_y / d eps_bar [Pa], and the plastic work
density W_p(eps_bar) = int_0^eps_bar sigma_y(e) de [J/m^3]:

    perfect / linear  sigma_y = sigma_Y + H eps_bar                      (H >= 0; H = 0: perfectly plastic)
    Swift             sigma_y = K (eps0 + eps_bar)^n,  eps0 = (sigma_Y / K)^(1/n)   (K > 0, 0 < n <= 1)
    Ludwik            sigma_y = sigma_Y + K eps_bar^n                  (K >= 0, 0 < n <= 1)
    tabulated         piecewise linear through (eps_bar_i, sigma_i) of a tensile test, eps_bar_0 = 0,
                      sigma_0 = sigma_Y; beyond the last point flat (H = 0) or by the last slope

The hardening coefficient K of Vu-Quoc & Zhang (1999), as in Simo & Hughes (1998, Computational
Inelasticity, sec. 2.3 and Box 3.1: the yield radius sqrt(2/3) (sigma_Y + K alpha), alpha the
equivalent plastic strain), is the linear curve's plastic modulus: H = K, the slope of the uniaxial
stress against the PLASTIC strain. A tensile test's tangent modulus E_t (the slope against the TOTAL
strain) gives H = E E_t / (E - E_t).

``return_stress`` solves the radial return's consistency condition of von Mises plasticity
(calib.fe.von_mises.return_mapping; de Souza Neto, Peric & Owen 2008, Box 7.4):

    q_trial - 3 mu dgamma - sigma_y(eps_bar_n + dgamma) = 0,   dgamma > 0

in closed form for the linear curve (dgamma = (q_trial - sigma_y(eps_bar_n)) / (3 mu + H)) and by a
scalar Newton iteration, safeguarded by bisection on [0, (q_trial - sigma_y(eps_bar_n)) / (3 mu)] (the
root lies there as sigma_y never falls), for the others.
"""
from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

from nfdmodel import check_real

__all__ = ["FlowCurve", "LinearHardening", "SwiftHardening", "LudwikHardening", "TabulatedFlowCurve",
           "read_flow_curve", "flow_curve_from_record", "solve_consistency", "bracketed_newton", "EXTRAPOLATIONS", "FLOW_CURVE_COLUMNS"]

#: the columns of a flow-curve CSV: equivalent (true) plastic strain [-], true stress [Pa]
FLOW_CURVE_COLUMNS = ("plastic_strain", "stress")
#: beyond a table's last point: the stress stays (flat) or grows by the last segment's slope (slope)
EXTRAPOLATIONS = ("flat", "slope")
# the Newton iteration stops at |residual| <= this fraction of q_trial (round-off of the stress)
_NEWTON_TOLERANCE = 1e-14
_NEWTON_MAX_ITERATIONS = 80
# Newton steps before the bracket is only bisected
_NEWTON_BEFORE_BISECTION = 20


class FlowCurve:
    """A flow curve (module docstring): ``sigma_y`` [Pa] the initial yield stress, ``yield_stress``,
    ``modulus`` and ``work_density`` of eps_bar (arrays), ``return_stress`` the radial return's
    consistency condition, ``record()`` the curve as a parameter file states it."""

    sigma_y: float

    def yield_stress(self, eps_bar) -> np.ndarray:
        raise NotImplementedError

    def modulus(self, eps_bar) -> np.ndarray:
        raise NotImplementedError

    def work_density(self, eps_bar) -> np.ndarray:
        raise NotImplementedError

    def plastic_work(self, eps_bar, weight) -> float:
        """int W_p(eps_bar) dV [J] with the volume weights ``weight`` [m^3] of the points."""
        return float(np.sum(self.work_density(eps_bar) * weight))

    def record(self) -> dict:
        raise NotImplementedError

    def return_stress(self, q_trial, eps_bar, three_mu: float):
        """(sigma_y, H) [Pa] at eps_bar + dgamma, dgamma the root of the consistency condition (module
        docstring) for the trial equivalent stress ``q_trial`` > sigma_y(eps_bar) [Pa] of plastic
        points, their committed ``eps_bar`` [-] and 3 mu [Pa]."""
        q_trial = np.asarray(q_trial, dtype=float)
        eps_bar = np.asarray(eps_bar, dtype=float)
        overstress = q_trial - self.yield_stress(eps_bar)
        dgamma = solve_consistency(q_trial, overstress, three_mu, self.modulus(eps_bar),
                                   lambda dgamma: self.yield_stress(eps_bar + dgamma),
                                   lambda dgamma: self.modulus(eps_bar + dgamma), self.record)
        eps_new = eps_bar + dgamma
        return self.yield_stress(eps_new), self.modulus(eps_new)


def solve_consistency(q_trial, overstress, three_mu: float, modulus, flow_stress, flow_modulus, record):
    """dgamma > 0 [-], the root of q_trial - 3 mu dgamma - flow_stress(dgamma) = 0 (module docstring) for
    the plastic points' ``q_trial`` [Pa] and ``overstress`` q_trial - flow_stress(0) [Pa]: Newton with the
    slope 3 mu + flow_modulus(dgamma) [Pa] from the start overstress / (3 mu + ``modulus``), safeguarded by
    bisection on [0, overstress / (3 mu)] (the root lies there as flow_stress never falls with dgamma).
    ``record()`` names the flow in the error of a return that does not converge."""
    high = overstress / three_mu
    step = np.where(np.isfinite(modulus), overstress / (three_mu + np.where(np.isfinite(modulus), modulus, 0.0)),
                    0.5 * high)
    return bracketed_newton(lambda dgamma: q_trial - three_mu * dgamma - flow_stress(dgamma),
                            lambda dgamma: three_mu + flow_modulus(dgamma), np.zeros_like(q_trial), high, step,
                            q_trial, lambda: f"flow curve {record()}")


def bracketed_newton(residual, slope, low, high, start, q_trial, name):
    """The root x of a falling ``residual`` [Pa] in [``low``, ``high``] (arrays, one root per point) by Newton
    with ``slope`` = -d residual / dx, bisecting where Newton leaves the bracket (an infinite slope, a
    table's kink) and after a few iterations (a piecewise-linear curve can make Newton cycle between two
    segments); converged at |residual| <= 1e-14 ``q_trial`` [Pa] or a bracket closed to round-off. An
    ArithmeticError naming ``name()`` (the flow) if not converged in _NEWTON_MAX_ITERATIONS: the FE's
    Newton then fails that iterate (calib.fe.newton)."""
    x = np.clip(start, low, high)
    for iteration in range(_NEWTON_MAX_ITERATIONS):
        value = residual(x)
        if np.all((np.abs(value) <= _NEWTON_TOLERANCE * q_trial) | (high - low <= 4.0 * np.spacing(high))):
            return x
        low = np.where(value > 0.0, x, low)
        high = np.where(value < 0.0, x, high)
        newton = x + value / slope(x)
        inside = (newton > low) & (newton < high) & np.isfinite(newton) & (iteration < _NEWTON_BEFORE_BISECTION)
        x = np.where(inside, newton, 0.5 * (low + high))
    raise ArithmeticError(f"{name()}: the return mapping did not converge in {_NEWTON_MAX_ITERATIONS} iterations")


class LinearHardening(FlowCurve):
    """sigma_y = sigma_Y + H eps_bar [Pa]; sigma_Y > 0, H >= 0 [Pa] (H = 0: perfectly plastic; H is the
    hardening coefficient K of Vu-Quoc & Zhang 1999, module docstring). The consistency condition has
    the closed form dgamma = (q_trial - sigma_y(eps_bar)) / (3 mu + H)."""

    def __init__(self, sigma_y, H=0.0):
        self.sigma_y = check_real("sigma_y", sigma_y, low=0.0, unit="[Pa] (yield stress)")
        self.H = check_real("hardening_modulus", H, low=0.0, low_inclusive=True, unit="[Pa] (plastic modulus H)")

    def yield_stress(self, eps_bar):
        return self.sigma_y + self.H * np.asarray(eps_bar, dtype=float)

    def modulus(self, eps_bar):
        return np.full(np.shape(eps_bar), self.H)

    def work_density(self, eps_bar):
        eps_bar = np.asarray(eps_bar, dtype=float)
        return eps_bar * (self.sigma_y + 0.5 * self.H * eps_bar)

    def plastic_work(self, eps_bar, weight) -> float:
        # sigma_Y int eps_bar dV (+ H/2 int eps_bar^2 dV): the perfectly plastic sum as it always was
        work = self.sigma_y * np.sum(eps_bar * weight)
        if self.H:
            work = work + 0.5 * self.H * np.sum(eps_bar * eps_bar * weight)
        return float(work)

    def return_stress(self, q_trial, eps_bar, three_mu: float):
        if not self.H:
            return self.sigma_y, 0.0                    # perfect plasticity: back onto sigma_Y itself
        dgamma = (q_trial - self.yield_stress(eps_bar)) / (three_mu + self.H)
        return self.yield_stress(eps_bar + dgamma), self.H

    def record(self) -> dict:
        return {"flow_curve": "linear", "sigma_y": self.sigma_y, "hardening_modulus": self.H}


def _exponent(n) -> float:
    return check_real("n", n, low=0.0, high=1.0, high_inclusive=True, unit="(hardening exponent)")


class SwiftHardening(FlowCurve):
    """Swift's power law sigma_y = K (eps0 + eps_bar)^n [Pa], eps0 = (sigma_Y / K)^(1/n) so that
    sigma_y(0) = sigma_Y; K > 0 [Pa], 0 < n <= 1. H = n K (eps0 + eps_bar)^(n - 1)."""

    def __init__(self, sigma_y, K, n):
        self.sigma_y = check_real("sigma_y", sigma_y, low=0.0, unit="[Pa] (yield stress)")
        self.K = check_real("K", K, low=0.0, unit="[Pa] (Swift strength coefficient)")
        self.n = _exponent(n)
        self.eps0 = (self.sigma_y / self.K) ** (1.0 / self.n)

    def yield_stress(self, eps_bar):
        return self.K * (self.eps0 + np.asarray(eps_bar, dtype=float)) ** self.n

    def modulus(self, eps_bar):
        return self.n * self.K * (self.eps0 + np.asarray(eps_bar, dtype=float)) ** (self.n - 1.0)

    def work_density(self, eps_bar):
        base = self.eps0 + np.asarray(eps_bar, dtype=float)
        return self.K / (self.n + 1.0) * (base ** (self.n + 1.0) - self.eps0 ** (self.n + 1.0))

    def record(self) -> dict:
        return {"flow_curve": "swift", "sigma_y": self.sigma_y, "K": self.K, "n": self.n, "eps0": self.eps0}


class LudwikHardening(FlowCurve):
    """Ludwik's power law sigma_y = sigma_Y + K eps_bar^n [Pa]; K >= 0 [Pa], 0 < n <= 1.
    H = n K eps_bar^(n - 1) (infinite at eps_bar = 0 for n < 1: the return starts by bisection)."""

    def __init__(self, sigma_y, K, n):
        self.sigma_y = check_real("sigma_y", sigma_y, low=0.0, unit="[Pa] (yield stress)")
        self.K = check_real("K", K, low=0.0, low_inclusive=True, unit="[Pa] (Ludwik strength coefficient)")
        self.n = _exponent(n)

    def yield_stress(self, eps_bar):
        return self.sigma_y + self.K * np.asarray(eps_bar, dtype=float) ** self.n

    def modulus(self, eps_bar):
        eps_bar = np.asarray(eps_bar, dtype=float)
        if not self.K:
            return np.zeros(eps_bar.shape)
        with np.errstate(divide="ignore"):
            return self.n * self.K * np.where(eps_bar > 0.0, eps_bar, 0.0) ** (self.n - 1.0)

    def work_density(self, eps_bar):
        eps_bar = np.asarray(eps_bar, dtype=float)
        return self.sigma_y * eps_bar + self.K / (self.n + 1.0) * eps_bar ** (self.n + 1.0)

    def record(self) -> dict:
        return {"flow_curve": "ludwik", "sigma_y": self.sigma_y, "K": self.K, "n": self.n}


class TabulatedFlowCurve(FlowCurve):
    """The piecewise-linear flow curve through the points (plastic_strain_i, stress_i) [-, Pa]: true
    values, plastic strain from 0 strictly increasing, stress > 0 and never falling; sigma_Y = stress_0.
    Beyond the last point ``extrapolation`` "flat" (H = 0) or "slope" (the last segment's H). H is the
    slope of the segment to the right of eps_bar (the one the plastic flow enters). ``source`` names
    the table in refusals (a file, or "table")."""

    def __init__(self, plastic_strain, stress, extrapolation: str = "flat", source: str = "table"):
        self.source = str(source)
        strain = np.asarray(plastic_strain, dtype=float)
        stress = np.asarray(stress, dtype=float)
        where = f"flow curve {self.source}"
        if strain.ndim != 1 or strain.shape != stress.shape or strain.size < 2:
            raise ValueError(f"{where}: need at least two rows of {','.join(FLOW_CURVE_COLUMNS)}")
        for column, values in zip(FLOW_CURVE_COLUMNS, (strain, stress)):
            if not np.isfinite(values).all():
                raise ValueError(f"{where}: column {column} must hold finite numbers")
        if (strain < 0.0).any():
            raise ValueError(f"{where}: column plastic_strain must be >= 0, got {strain.min():g}")
        if strain[0] != 0.0:
            raise ValueError(f"{where}: column plastic_strain must start at 0 (stress there is sigma_Y), "
                             f"got {strain[0]:g}")
        if (np.diff(strain) <= 0.0).any():
            row = int(np.flatnonzero(np.diff(strain) <= 0.0)[0]) + 2
            raise ValueError(f"{where}: column plastic_strain must increase strictly (data row {row})")
        if stress[0] <= 0.0:
            raise ValueError(f"{where}: column stress must start at sigma_Y > 0 [Pa], got {stress[0]:g}")
        if (np.diff(stress) < 0.0).any():
            row = int(np.flatnonzero(np.diff(stress) < 0.0)[0]) + 2
            raise ValueError(f"{where}: column stress must be monotone non-decreasing (falls at data row {row}; "
                             f"softening is not a flow curve of this model)")
        if extrapolation not in EXTRAPOLATIONS:
            raise ValueError(f"flow_curve_extrapolation must be one of {', '.join(EXTRAPOLATIONS)}, "
                             f"got {extrapolation!r}")
        self.strain, self.stress, self.extrapolation = strain, stress, extrapolation
        self.sigma_y = float(stress[0])
        self.slopes = np.diff(stress) / np.diff(strain)
        self.last_slope = float(self.slopes[-1]) if extrapolation == "slope" else 0.0
        # W_p at the points: the trapezoids of the segments, summed
        self.work_at_points = np.concatenate(([0.0], np.cumsum(0.5 * (stress[1:] + stress[:-1]) * np.diff(strain))))

    def _segment(self, eps_bar):
        """(index of the segment right of eps_bar, clipped to the last, and whether beyond the table)."""
        eps_bar = np.asarray(eps_bar, dtype=float)
        index = np.clip(np.searchsorted(self.strain, eps_bar, side="right") - 1, 0, self.slopes.size - 1)
        return eps_bar, index, eps_bar >= self.strain[-1]

    def yield_stress(self, eps_bar):
        eps_bar, index, beyond = self._segment(eps_bar)
        inside = self.stress[index] + self.slopes[index] * (eps_bar - self.strain[index])
        return np.where(beyond, self.stress[-1] + self.last_slope * (eps_bar - self.strain[-1]), inside)

    def modulus(self, eps_bar):
        eps_bar, index, beyond = self._segment(eps_bar)
        return np.where(beyond, self.last_slope, self.slopes[index])

    def work_density(self, eps_bar):
        eps_bar, index, beyond = self._segment(eps_bar)
        start = np.where(beyond, self.strain[-1], self.strain[index])
        work_start = np.where(beyond, self.work_at_points[-1], self.work_at_points[index])
        stress_start = np.where(beyond, self.stress[-1], self.stress[index])
        return work_start + 0.5 * (stress_start + self.yield_stress(eps_bar)) * (eps_bar - start)

    def record(self) -> dict:
        return {"flow_curve": "table", "source": self.source, "sigma_y": self.sigma_y,
                "extrapolation": self.extrapolation, "plastic_strain": self.strain.tolist(),
                "stress": self.stress.tolist()}


def flow_curve_from_record(record: dict) -> FlowCurve:
    """The flow curve a ``record()`` states (a parameter file's "hardening", a sweep task's)."""
    kind = record.get("flow_curve")
    if kind == "linear":
        return LinearHardening(record["sigma_y"], record["hardening_modulus"])
    if kind in ("swift", "ludwik"):
        return (SwiftHardening if kind == "swift" else LudwikHardening)(record["sigma_y"], record["K"], record["n"])
    if kind == "table":
        return TabulatedFlowCurve(record["plastic_strain"], record["stress"], record["extrapolation"], record["source"])
    raise ValueError(f"flow_curve must be one of linear, swift, ludwik, table, got {kind!r}")


def read_flow_curve(path, extrapolation: str = "flat", sigma_y: float | None = None) -> TabulatedFlowCurve:
    """The TabulatedFlowCurve of the CSV ``path`` with the header ``plastic_strain,stress`` (true plastic
    strain [-], true stress [Pa]); with ``sigma_y`` [Pa] given, its first stress must equal it (relative
    1e-6). A ValueError of one line naming the file (and the column) otherwise."""
    path = Path(path)
    try:
        with path.open(newline="") as handle:
            rows = [row for row in csv.reader(handle) if row and any(cell.strip() for cell in row)]
    except (OSError, UnicodeDecodeError) as error:
        raise ValueError(f"flow curve {path}: cannot read it ({error.__class__.__name__})") from None
    header = tuple(cell.strip() for cell in rows[0]) if rows else ()
    if header != FLOW_CURVE_COLUMNS:
        raise ValueError(f"flow curve {path}: the header must be {','.join(FLOW_CURVE_COLUMNS)}, got "
                         f"{','.join(header) or 'an empty file'}")
    columns = ([], [])
    for number, row in enumerate(rows[1:], start=2):
        if len(row) != 2:
            raise ValueError(f"flow curve {path}: line {number} must have 2 columns, got {len(row)}")
        for column, cell, values in zip(FLOW_CURVE_COLUMNS, row, columns):
            try:
                values.append(float(cell))
            except ValueError:
                raise ValueError(f"flow curve {path}: column {column} line {number} is not a number: "
                                 f"{cell.strip()!r}") from None
    curve = TabulatedFlowCurve(*columns, extrapolation=extrapolation, source=str(path))
    if sigma_y is not None and not math.isclose(curve.sigma_y, sigma_y, rel_tol=1e-6):
        raise ValueError(f"flow curve {path}: column stress must start at sigma_y = {sigma_y:g} Pa, got "
                         f"{curve.sigma_y:g}")
    return curve

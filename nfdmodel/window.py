"""The load window a law's constants were fitted on, and what the runtime says beyond it.

A calibration fits Ca and Kc to FE loading points with P_Y < P <= P_max. The constants describe
the contact inside that window, P_min <= P <= P_max (contact radius up to the FE's a_max, which
the law reproduces to its fit error: the force decides), and are an extrapolation beyond it: fitted to 41 P_Y, Ca_hat = Ca P_Y / a_Y is about 0.026; fitted to
1000 P_Y, about 0.010. ``CalibrationWindow`` travels with the constants (``VZParams.window``, the
parameter file, the master table); the vz kernel counts the contacts whose turning point moves
beyond it (``HistoryUpdate.beyond_window``, sparse: only the contacts loading this step) and
``ContactLaw.step`` / ``force`` issue one ``RangeWarning`` per call naming the largest excursion. Below P_Y the law is Hertz
and needs no window.

A contact radius reaching R* is outside any small-strain contact law (a << R): the vz kernel
raises a ValueError naming the overlap instead of returning a number.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

from . import limits
from .validation import PlausibilityWarning, check_real

# What a parameter file without a window was calibrated on: the largest peak of the default
# recipe of nfdcal calibrate (the fit uses the loading points above P_Y); nfd_limits.h.
DEFAULT_RECIPE_P_MAX_OVER_P_Y = limits.DEFAULT_WINDOW


# what the source of a finite-strain calibration's window names (calib.fit.calibration.fitted_window):
# its window is checked against the finite-strain FE's reach
FINITE_STRAIN = "finite-strain"


class RangeWarning(UserWarning):
    """A law used beyond the load window its constants were fitted on (an extrapolation)."""


@dataclass(frozen=True)
class CalibrationWindow:
    """The loads the constants were fitted on [dimensionless]: P/P_Y from ``P_min_over_P_Y`` to
    ``P_max_over_P_Y`` (>= 1), the largest contact radius ``a_max_over_R`` = a/R* of the fitted
    data (None: not stated, then only the force bounds the window), and ``source``: what produced
    it (FE mesh and commit, a master table, an assumption)."""

    P_min_over_P_Y: float
    P_max_over_P_Y: float
    a_max_over_R: float | None = None
    source: str = ""

    def __post_init__(self):
        low = check_real("window.P_min_over_P_Y", self.P_min_over_P_Y, low=1.0, low_inclusive=True)
        high = check_real("window.P_max_over_P_Y", self.P_max_over_P_Y, low=low, low_inclusive=True,
                          high=1e8, high_inclusive=True)
        object.__setattr__(self, "P_min_over_P_Y", low)
        object.__setattr__(self, "P_max_over_P_Y", high)
        if self.a_max_over_R is not None:
            object.__setattr__(self, "a_max_over_R", check_real("window.a_max_over_R", self.a_max_over_R,
                                                                low=0.0, high=1.0))
        if not isinstance(self.source, str):
            raise ValueError(f"window.source must be text, got {type(self.source).__name__}")
        beyond = self.beyond_fe_reach()
        if beyond:                  # no FE calibration vouches for constants there (calib.fit.recipe)
            warnings.warn(f"window beyond the FE's reach: {', '.join(beyond)}; constants stated for it are an "
                          f"extrapolation no calibration can check ({self.source or 'source not stated'})",
                          PlausibilityWarning, stacklevel=3)

    def beyond_fe_reach(self) -> list[str]:
        """How far the window reaches beyond what the FE that made it runs to (nfd_limits.h: a
        finite-strain calibration's, its source naming "finite-strain", FE_FINITE_MAX_LOAD_OVER_YIELD and
        FE_FINITE_MAX_CONTACT_RADIUS_OVER_R; any other's the small-strain FE_MAX_LOAD_OVER_YIELD and
        FE_MAX_CONTACT_RADIUS_OVER_R), as text; [] inside it."""
        beyond = []
        if FINITE_STRAIN in self.source:
            top_load, top_radius = limits.FE_FINITE_MAX_LOAD_OVER_YIELD, limits.FE_FINITE_MAX_CONTACT_RADIUS_OVER_R
        else:
            top_load, top_radius = limits.FE_MAX_LOAD_OVER_YIELD, limits.FE_MAX_CONTACT_RADIUS_OVER_R
        if self.P_max_over_P_Y > top_load * (1.0 + 1e-9):
            beyond.append(f"P/P_Y up to {self.P_max_over_P_Y:.3g} (the FE reaches {top_load:g})")
        if self.a_max_over_R is not None and self.a_max_over_R > top_radius * (1.0 + 1e-9):
            beyond.append(f"a/R* up to {self.a_max_over_R:.3g} (the FE reaches {top_radius:g})")
        return beyond

    @classmethod
    def assumed_default(cls) -> "CalibrationWindow":
        """The window of the default recipe, for constants that do not state theirs."""
        return cls(1.0, DEFAULT_RECIPE_P_MAX_OVER_P_Y, None,
                   f"assumed: the default recipe of nfdcal calibrate (load paths to 13.7, 27.4, "
                   f"{DEFAULT_RECIPE_P_MAX_OVER_P_Y:g} P_Y)")

    def describe(self) -> str:
        """'P/P_Y 1..41.2, a/R* <= 0.0148'"""
        text = f"P/P_Y {self.P_min_over_P_Y:.3g}..{self.P_max_over_P_Y:.3g}"
        return text + (f", a/R* <= {self.a_max_over_R:.3g}" if self.a_max_over_R is not None else "")

    def record(self) -> dict:
        """The JSON form (parameter files, tables)."""
        return {"P_min_over_P_Y": self.P_min_over_P_Y, "P_max_over_P_Y": self.P_max_over_P_Y,
                "a_max_over_R": self.a_max_over_R, "source": self.source}

    @classmethod
    def from_record(cls, data) -> "CalibrationWindow":
        """The window from its JSON form; a ValueError naming the key when it is malformed."""
        if not isinstance(data, dict):
            raise ValueError(f"window must be an object with P_min_over_P_Y, P_max_over_P_Y, a_max_over_R, "
                             f"source; got {type(data).__name__}")
        allowed = ("P_min_over_P_Y", "P_max_over_P_Y", "a_max_over_R", "source")
        unknown = [key for key in data if key not in allowed]
        if unknown:
            raise ValueError(f"unknown key(s) in 'window': {', '.join(map(repr, unknown))}; allowed: "
                             f"{', '.join(allowed)}")
        missing = [key for key in allowed[:2] if key not in data]
        if missing:
            raise ValueError(f"window: missing key(s) {', '.join(missing)}")
        return cls(data["P_min_over_P_Y"], data["P_max_over_P_Y"], data.get("a_max_over_R"),
                   data.get("source", ""))


def warn_beyond_window(law: str, count: int, largest_load_over_P_Y: float, window: CalibrationWindow,
                       stacklevel: int = 4) -> None:
    """One RangeWarning for ``count`` contacts loaded beyond ``window`` in one call."""
    warnings.warn(f"{law} law used beyond its calibrated window: {count} contact(s) loaded to P/P_Y up to "
                  f"{largest_load_over_P_Y:.4g} (fitted on {window.describe()}; beyond it the constants are "
                  f"an extrapolation: calibrate for these loads, e.g. nfdcal calibrate --peaks)",
                  RangeWarning, stacklevel=stacklevel)


def check_contact_radius_below_R(largest_radius: float, R_star: float, delta: float, params) -> None:
    """ValueError when the law's contact radius reaches R* (a << R fails: no contact law holds),
    naming the overlap and the largest one the law covers (``params.full_contact_approach``)."""
    if not largest_radius < R_star or not math.isfinite(largest_radius):
        raise ValueError(f"delta out of range: at delta = {delta:g} m (delta/R* = {delta / R_star:.3g}) the vz law's "
                         f"contact radius {largest_radius:.4g} m reaches R* = {R_star:g} m; need delta < "
                         f"{params.full_contact_approach:.4g} m (P < {params.full_contact_load / params.pair.P_Y:.4g} P_Y) "
                         f"for these constants: a contact law needs a contact radius well below the sphere's radius")

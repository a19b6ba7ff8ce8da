"""The strain-rate factor of the flow stress: Johnson-Cook and Cowper-Symonds (the formulas' one home).

A rate law scales the flow stress by a factor R >= 1 of the equivalent plastic strain rate eps_dot [1/s]:

    sigma_y(eps_dot) = sigma_y R(eps_dot)                                                    [Pa]
    Johnson-Cook (ln form)  R = 1 + C ln(max(eps_dot / eps_dot_0, 1))     C >= 0 [-], eps_dot_0 > 0 [1/s]
    Cowper-Symonds          R = 1 + (eps_dot / D)^(1/q)                   D > 0 [1/s], q > 0 [-]

(Johnson & Cook 1983, Proc. 7th Int. Symp. on Ballistics, 541-547: the rate term of their flow stress,
rate-independent below eps_dot_0; Cowper & Symonds 1957, Brown Univ. Tech. Rep. 28: mild steel D = 40.4 /s,
q = 5; Jones 2012, Structural Impact, ch. 8.) The dynamic FE (calib.fe.rate_law) and the rate-aware law
(nfdmodel.rate_aware) both call these functions.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .validation import check_real

__all__ = ["johnson_cook_factor", "cowper_symonds_factor", "JohnsonCook", "CowperSymonds", "rate_law_of"]


def johnson_cook_factor(rate, C: float, reference_rate: float):
    """R = 1 + C ln(max(eps_dot / eps_dot_0, 1)) [-] of the strain rate ``rate`` [1/s] (array)."""
    ratio = np.maximum(np.asarray(rate, dtype=float) / reference_rate, 1.0)
    return 1.0 + C * np.log(ratio)


def cowper_symonds_factor(rate, D: float, q: float):
    """R = 1 + (eps_dot / D)^(1/q) [-] of the strain rate ``rate`` [1/s] (array); D = inf gives 1."""
    return 1.0 + (np.asarray(rate, dtype=float) / D) ** (1.0 / q)


@dataclass(frozen=True)
class JohnsonCook:
    """Johnson-Cook's rate term: ``C`` >= 0 [-], ``reference_rate`` eps_dot_0 > 0 [1/s] (default 1 /s)."""

    C: float
    reference_rate: float = 1.0

    def __post_init__(self):
        object.__setattr__(self, "C", check_real("C", self.C, low=0.0, low_inclusive=True,
                                                 unit="(Johnson-Cook rate constant)"))
        object.__setattr__(self, "reference_rate", check_real("reference_rate", self.reference_rate, low=0.0,
                                                              unit="[1/s] (Johnson-Cook reference strain rate)"))

    def factor(self, rate):
        return johnson_cook_factor(rate, self.C, self.reference_rate)

    def rate_at(self, factor):
        """The inverse: eps_dot = eps_dot_0 exp((R - 1) / C) [1/s] at which the flow stress is R sigma_y
        (eps_dot_0 at R <= 1; C = 0: inf above R = 1, the flow stress never rises)."""
        excess = np.maximum(np.asarray(factor, dtype=float) - 1.0, 0.0)
        with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
            ratio = np.exp(excess / self.C) if self.C > 0.0 else np.where(excess > 0.0, np.inf, 1.0)
        return self.reference_rate * ratio

    def rate_slope(self, factor):
        """d eps_dot_s / dR [1/s] of :meth:`rate_at` above R = 1: eps_dot_s / C (0 at R <= 1)."""
        factor = np.asarray(factor, dtype=float)
        with np.errstate(over="ignore", invalid="ignore"):
            return np.where(factor > 1.0, self.rate_at(factor) / self.C if self.C > 0.0 else np.inf, 0.0)

    def record(self) -> dict:
        return {"rate_law": "johnson-cook", "C": self.C, "reference_rate": self.reference_rate}


@dataclass(frozen=True)
class CowperSymonds:
    """Cowper-Symonds' rate term: ``D`` > 0 [1/s], ``q`` > 0 [-]."""

    D: float
    q: float

    def __post_init__(self):
        object.__setattr__(self, "D", check_real("D", self.D, low=0.0, unit="[1/s] (Cowper-Symonds rate constant)"))
        object.__setattr__(self, "q", check_real("q", self.q, low=0.0, unit="(Cowper-Symonds exponent)"))

    def factor(self, rate):
        return cowper_symonds_factor(rate, self.D, self.q)

    def rate_at(self, factor):
        """The inverse: eps_dot = D (R - 1)^q [1/s] at which the flow stress is R sigma_y (0 at R <= 1)."""
        excess = np.maximum(np.asarray(factor, dtype=float) - 1.0, 0.0)
        with np.errstate(over="ignore", invalid="ignore"):
            return np.where(excess > 0.0, self.D * excess ** self.q, 0.0)

    def rate_slope(self, factor):
        """d eps_dot_s / dR [1/s] of :meth:`rate_at` above R = 1: D q (R - 1)^(q - 1) (0 at R <= 1)."""
        excess = np.maximum(np.asarray(factor, dtype=float) - 1.0, 0.0)
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            return np.where(excess > 0.0, self.D * self.q * excess ** (self.q - 1.0), 0.0)

    def record(self) -> dict:
        return {"rate_law": "cowper-symonds", "D": self.D, "q": self.q}


def rate_law_of(record: dict):
    """The rate law a ``record()`` (or a parameter file's "rate_law" entry) states."""
    kind = record.get("rate_law") if isinstance(record, dict) else None
    if kind == "johnson-cook":
        return JohnsonCook(record.get("C"), record.get("reference_rate", 1.0))
    if kind == "cowper-symonds":
        return CowperSymonds(record.get("D"), record.get("q"))
    raise ValueError(f"rate_law must be one of johnson-cook, cowper-symonds, got {kind!r}")

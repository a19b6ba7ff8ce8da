"""Strain-rate dependence of the flow stress: Johnson-Cook and Cowper-Symonds, and the viscoplastic return.

A rate law scales the flow curve (calib.fe.flow_curve) by a factor R >= 1 of the equivalent plastic
strain rate eps_dot [1/s], R(0) = 1 (the factor's home: nfdmodel.strain_rate):

    sigma_y(eps_bar, eps_dot) = sigma_y(eps_bar) R(eps_dot)                                  [Pa]
    Johnson-Cook (ln form)  R = 1 + C ln(max(eps_dot / eps_dot_0, 1))     C >= 0 [-], eps_dot_0 > 0 [1/s]
    Cowper-Symonds          R = 1 + (eps_dot / D)^(1/q)                   D > 0 [1/s], q > 0 [-]

(Johnson & Cook 1983, Proc. 7th Int. Symp. on Ballistics, 541-547: the rate term of their flow stress,
below eps_dot_0 rate-independent; Cowper & Symonds 1957, Brown Univ. Tech. Rep. 28: mild steel
D = 40.4 /s, q = 5; Jones 2012, Structural Impact, ch. 8.)

Viscoplastic consistency model (Wang, Sluys & de Borst 1997, Int. J. Numer. Meth. Eng. 40, 3839): the
stress stays on the rate-dependent yield surface q = sigma_y(eps_bar) R(eps_dot), elastic while q_trial <=
sigma_y(eps_bar_n) (= the surface at eps_dot = 0). Backward Euler over a step dt [s] takes eps_dot =
dgamma / dt, so the radial return's scalar equation (calib.fe.von_mises.return_mapping) becomes

    f(dgamma) = q_trial - 3 mu dgamma - sigma_y(eps_bar_n + dgamma) R(dgamma / dt) = 0

solved by the bracketed Newton of calib.fe.flow_curve.solve_consistency (f falls with dgamma: the root
lies in [0, (q_trial - sigma_y(eps_bar_n)) / (3 mu)]; Cowper-Symonds with q > 1 in y = (dgamma / (dt D))^(1/q),
where f is smooth), and the consistent tangent takes the slope of the
flow stress in dgamma,

    H_eff = d (sigma_y R) / d dgamma = H(eps_bar_n+1) R + sigma_y(eps_bar_n+1) R'(eps_dot) / dt       [Pa]

in place of H. The alternative, Perzyna's overstress model (de Souza Neto, Peric & Owen 2008, ch. 11),
lets the stress leave the yield surface; the consistency model is chosen because Johnson-Cook and
Cowper-Symonds are stated as the flow stress at a rate, which is what it integrates. Without a time step
(the quasi-static press, dt -> infinity) eps_dot = 0 and R = 1: the rate-independent limit.
"""
from __future__ import annotations

import math

import numpy as np

from calib.fe.flow_curve import FlowCurve, bracketed_newton, solve_consistency
from nfdmodel import check_real
from nfdmodel.strain_rate import cowper_symonds_factor, johnson_cook_factor

__all__ = ["RateLaw", "JohnsonCookRate", "CowperSymondsRate", "RateDependentFlow", "rate_law_from_record",
           "RATE_LAWS"]


class RateLaw:
    """A rate law (module docstring): ``factor`` R and ``slope`` dR/d eps_dot [s] of the equivalent plastic
    strain rate eps_dot >= 0 [1/s] (arrays), ``record()`` as a parameter file or a run key states it,
    ``is_unity``: R = 1 at every rate (the rate-independent material)."""

    is_unity: bool = False

    def factor(self, rate) -> np.ndarray:
        raise NotImplementedError

    def slope(self, rate) -> np.ndarray:
        raise NotImplementedError

    def record(self) -> dict:
        raise NotImplementedError


class JohnsonCookRate(RateLaw):
    """R = 1 + C ln(max(eps_dot / eps_dot_0, 1)); C >= 0 [-], ``reference_rate`` eps_dot_0 > 0 [1/s]
    (Johnson & Cook 1983). R' = C / eps_dot above eps_dot_0, 0 below. C = 0: R = 1."""

    def __init__(self, C, reference_rate=1.0):
        self.C = check_real("C", C, low=0.0, low_inclusive=True, unit="(Johnson-Cook rate constant)")
        self.reference_rate = check_real("reference_rate", reference_rate, low=0.0,
                                         unit="[1/s] (Johnson-Cook reference strain rate)")
        self.is_unity = self.C == 0.0

    def factor(self, rate):
        return johnson_cook_factor(rate, self.C, self.reference_rate)

    def slope(self, rate):
        rate = np.asarray(rate, dtype=float)
        above = rate > self.reference_rate
        return np.where(above, self.C / np.where(above, rate, 1.0), 0.0)

    def record(self) -> dict:
        return {"rate_law": "johnson-cook", "C": self.C, "reference_rate": self.reference_rate}


class CowperSymondsRate(RateLaw):
    """R = 1 + (eps_dot / D)^(1/q); D > 0 [1/s], q > 0 [-] (Cowper & Symonds 1957). R' = (eps_dot / D)^(1/q)
    / (q eps_dot), infinite at eps_dot = 0 for q > 1 (the return then starts by bisection). D = inf: R = 1."""

    def __init__(self, D, q):
        infinite = isinstance(D, (float, np.floating)) and D == math.inf      # the rate-independent limit
        self.D = math.inf if infinite else check_real("D", D, low=0.0, unit="[1/s] (Cowper-Symonds rate constant)")
        self.q = check_real("q", q, low=0.0, unit="(Cowper-Symonds exponent)")
        self.is_unity = math.isinf(self.D)

    def factor(self, rate):
        return cowper_symonds_factor(rate, self.D, self.q)

    def slope(self, rate):
        rate = np.asarray(rate, dtype=float)
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(rate > 0.0, (rate / self.D) ** (1.0 / self.q) / (self.q * np.where(rate > 0.0, rate, 1.0)),
                            0.0 if self.q < 1.0 else (1.0 / self.D if self.q == 1.0 else np.inf))

    def record(self) -> dict:
        return {"rate_law": "cowper-symonds", "D": self.D, "q": self.q}


#: the rate laws by the name a command and a record give them
RATE_LAWS = {"johnson-cook": JohnsonCookRate, "cowper-symonds": CowperSymondsRate}


def rate_law_from_record(record: dict) -> RateLaw:
    """The rate law a ``record()`` states (a run key's "rate_law")."""
    kind = record.get("rate_law")
    if kind == "johnson-cook":
        return JohnsonCookRate(record["C"], record["reference_rate"])
    if kind == "cowper-symonds":
        return CowperSymondsRate(record["D"], record["q"])
    raise ValueError(f"rate_law must be one of {', '.join(RATE_LAWS)}, got {kind!r}")


class RateDependentFlow(FlowCurve):
    """The flow curve ``curve`` scaled by ``law`` over a time step ``time_step`` [s] (module docstring): the
    static surface sigma_y(eps_bar) decides elastic or plastic (R(0) = 1); ``return_stress`` gives (sigma_y
    R, H_eff) [Pa] at the root of the viscoplastic consistency condition."""

    def __init__(self, curve: FlowCurve, law: RateLaw, time_step: float):
        self.curve, self.law = curve, law
        self.time_step = check_real("time_step", time_step, low=0.0, unit="[s]")
        self.sigma_y = curve.sigma_y

    def yield_stress(self, eps_bar):
        return self.curve.yield_stress(eps_bar)

    def modulus(self, eps_bar):
        return self.curve.modulus(eps_bar)

    def work_density(self, eps_bar):
        raise ValueError("the plastic work of a rate-dependent flow is not a function of eps_bar: accumulate "
                         "sigma : d eps_p (calib.fe.von_mises.RateDependentMaterial)")

    def record(self) -> dict:
        return {**self.curve.record(), **self.law.record(), "time_step": self.time_step}

    def flow_stress(self, eps_bar, dgamma):
        """sigma_y(eps_bar + dgamma) R(dgamma / dt) [Pa]."""
        return self.curve.yield_stress(eps_bar + dgamma) * self.law.factor(dgamma / self.time_step)

    def flow_modulus(self, eps_bar, dgamma):
        """H_eff = H R + sigma_y R' / dt [Pa] at eps_bar + dgamma and the rate dgamma / dt."""
        rate = dgamma / self.time_step
        eps_new = eps_bar + dgamma
        return (self.curve.modulus(eps_new) * self.law.factor(rate)
                + self.curve.yield_stress(eps_new) * self.law.slope(rate) / self.time_step)

    def return_stress(self, q_trial, eps_bar, three_mu: float):
        if self.law.is_unity:                       # R = 1: the rate-independent return itself
            return self.curve.return_stress(q_trial, eps_bar, three_mu)
        q_trial = np.asarray(q_trial, dtype=float)
        eps_bar = np.asarray(eps_bar, dtype=float)
        overstress = q_trial - self.curve.yield_stress(eps_bar)
        if isinstance(self.law, CowperSymondsRate) and self.law.q > 1.0:
            dgamma = self._cowper_symonds_increment(q_trial, eps_bar, overstress, three_mu)
        else:
            dgamma = solve_consistency(q_trial, overstress, three_mu, self.curve.modulus(eps_bar),
                                       lambda dgamma: self.flow_stress(eps_bar, dgamma),
                                       lambda dgamma: self.flow_modulus(eps_bar, dgamma), self.record)
        # H_eff is infinite where dgamma underflows to 0 under Cowper-Symonds (R' ~ dgamma^(1/q - 1)): capped, the
        # tangent's H_eff / (3 mu + H_eff) is then 1, its limit
        return self.flow_stress(eps_bar, dgamma), np.minimum(self.flow_modulus(eps_bar, dgamma), _MODULUS_CAP)

    def _cowper_symonds_increment(self, q_trial, eps_bar, overstress, three_mu):
        """dgamma of the consistency condition under Cowper-Symonds with q > 1, solved in y = (dgamma / (dt D))^(1/q)
        (dgamma = dt D y^q): f(y) = q_trial - (3 mu dgamma + sigma_y(eps_bar + dgamma) (1 + y)) is smooth in y where
        it is not in dgamma (R' infinite at dgamma = 0), so the bracketed Newton on [0, y(overstress / 3 mu)]
        converges for an overstress of round-off as for a large one."""
        scale, q = self.time_step * self.law.D, self.law.q

        def residual(y):
            dgamma = scale * y ** q
            return q_trial - three_mu * dgamma - self.curve.yield_stress(eps_bar + dgamma) * (1.0 + y)

        def slope(y):                                   # -df/dy
            dgamma = scale * y ** q
            ddgamma = scale * q * y ** (q - 1.0)
            return (three_mu * ddgamma + self.curve.modulus(eps_bar + dgamma) * ddgamma * (1.0 + y)
                    + self.curve.yield_stress(eps_bar + dgamma))

        high = (overstress / (three_mu * scale)) ** (1.0 / q)
        y = bracketed_newton(residual, slope, np.zeros_like(high), high,
                             np.minimum(overstress / self.curve.sigma_y, high), q_trial,
                             lambda: f"rate-dependent flow {self.record()}")
        return scale * y ** q


# above it the effective plastic modulus is infinite for the tangent (H_eff / (3 mu + H_eff) = 1 in floats)
_MODULUS_CAP = 1e300

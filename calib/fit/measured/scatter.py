"""Is a fit's residual the data's scatter? (``nfdcal fit-data``)

Three questions about the relative residuals r of a fit (calib.fit.measured.specimen), per
group k (e, P_max, contact_time, force) with n_k values:

**Plausible scatter** (a chi-square test against a ceiling). No measurement of the kind is
scattered by more than ``PLAUSIBLE_SCATTER[k]`` (relative, one standard deviation: e 10 %;
P_max, contact time and force 20 %, which include the vz law's own error against the FE, 7 % rms
on the reference force paths, calibration.json "force_fit"). If the scatter were at the ceiling,
chi2_k = sum r^2 / ceiling_k^2 would follow a chi-square law with at most n_k degrees of freedom,
so the fit is *implausible* when chi2_k > chi2.isf(``SIGNIFICANCE``, n_k) (SIGNIFICANCE 1e-3: data
at the ceiling are flagged once in a thousand fits; 12 drop tests pass up to 16.6 % rms on e,
1000 up to 10.7 %, 147 force values up to 23.7 %). Random e values between 0.3 and 0.95 leave
46..59 % rms. Measured on synthetic drop tests (tests/benchmarks/bench_fit_data.py, second
table: 20 trials per noise level, both models), the largest chi2 / threshold is 1e-28, 0.0063
and 0.073 at 0, 1 and 3 % noise on e, 0.86 at 10 % (none refused); at 20 % the test refuses
23 of 40 fits.

**Lack of fit against repeats** (drop tests repeated at the same v_in, Draper & Smith 1998,
Applied Regression Analysis, section 2.1). With m distinct v_in among n tests, the
residual sum of squares splits into pure error (repeats about their mean, n - m degrees of
freedom) and lack of fit (the rest, m - p); F = (SS_lof / (m - p)) / (SS_pe / (n - m)) above
F.isf(SIGNIFICANCE, m - p, n - m) says the law misses the data by more than the repeats scatter.
That is no refusal (the vz law is an approximation), but then no summary says the data agree
with a model.

**Noise-free data.** When every residual is below ``NOISE_FREE`` (1e-9 relative; the law's
numerical precision is about 1e-13, a measured value carries at most 6 significant digits), the
data are on the law exactly (synthetic, or identical values): their scatter cannot be estimated,
so s^2 = sum r^2 / (n - p) and the standard errors measure the law's numerical precision, not the
data's. :func:`assess` then gives the relative standard errors the same tests would give at
1 % scatter, sqrt(diag((J_u^T J_u)^-1)) x 0.01, J_u = d r / d ln theta (unweighted).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy import stats

from calib.fit.measured.data import Measurements

PLAUSIBLE_SCATTER = {"e": 0.10, "P_max": 0.20, "contact_time": 0.20, "dent": 0.20, "radius": 0.20, "force": 0.20}
SIGNIFICANCE = 1e-3
NOISE_FREE = 1e-9               # rms relative residual below which the data are on the law exactly
REFERENCE_SCATTER = 0.01        # noise-free data: the standard errors at this relative scatter


@dataclass(frozen=True)
class Scatter:
    """The verdict on a fit's residuals (module doc). ``groups``: per group its rms, chi2 against
    the ceiling and the threshold; ``implausible``: the groups beyond it; ``lack_of_fit``: the
    F test against repeats (None without repeats); ``estimable``: False for noise-free data;
    ``se_at_reference``: then the relative standard errors at 1 % scatter per fitted parameter."""

    groups: dict
    implausible: tuple = ()
    lack_of_fit: dict | None = None
    estimable: bool = True
    se_at_reference: dict = field(default_factory=dict)

    @property
    def plausible(self) -> bool:
        return not self.implausible

    @property
    def within_repeats(self) -> bool:
        return self.lack_of_fit is None or not self.lack_of_fit["significant"]

    def describe_implausible(self) -> str:
        """In words, the groups whose residual is far above plausible scatter."""
        return "; ".join(
            f"the {name} residuals have rms {100 * g['rms']:.3g} %, far above any plausible scatter of {name} "
            f"({100 * g['ceiling']:g} %: chi-square {g['chi2']:.3g} > {g['threshold']:.3g}, {g['n']} values, "
            f"significance {SIGNIFICANCE:g})" for name, g in self.groups.items() if name in self.implausible)

    def describe_lack_of_fit(self) -> str:
        f = self.lack_of_fit
        return (f"the law misses the repeated drop tests by more than they scatter (rms {100 * f['rms_lack']:.3g} % "
                f"about the law against {100 * f['rms_pure']:.3g} % between repeats at the same v_in; "
                f"F = {f['F']:.3g}, p = {f['p']:.2g})")

    def record(self) -> dict:
        return {"groups": self.groups, "plausible": self.plausible, "implausible": list(self.implausible),
                "lack_of_fit": self.lack_of_fit, "estimable": self.estimable,
                "relative_se_at_1_percent_scatter": self.se_at_reference or None}


def _lack_of_fit(data: Measurements, residual: np.ndarray, p: int) -> dict | None:
    """The F test of the e residuals against the scatter of drop tests repeated at one v_in."""
    if data.impacts is None:
        return None
    _, group, counts = np.unique(data.impacts.v_in, return_inverse=True, return_counts=True)
    n, m = residual.size, counts.size
    if n - m < 2 or m - p < 1:
        return None
    means = np.bincount(group, weights=residual) / counts
    pure = float(np.sum((residual - means[group]) ** 2))
    lack = max(float(residual @ residual) - pure, 0.0)
    if not pure > 0.0:
        return None
    F = (lack / (m - p)) / (pure / (n - m))
    p_value = float(stats.f.sf(F, m - p, n - m))
    return {"F": float(F), "p": p_value, "significant": bool(p_value < SIGNIFICANCE), "distinct_v_in": int(m),
            "tests": int(n), "rms_pure": float(np.sqrt(pure / (n - m))), "rms_lack": float(np.sqrt(lack / (m - p)))}


def assess(data: Measurements, residuals: dict, p: int, unweighted_jacobian: np.ndarray,
           names: tuple) -> Scatter:
    """The verdict on relative ``residuals`` per group of a fit of ``p`` parameters ``names``
    whose unweighted J = d r / d ln theta is ``unweighted_jacobian`` (module doc)."""
    groups, implausible = {}, []
    for name, r in residuals.items():
        n = int(r.size)
        ceiling = PLAUSIBLE_SCATTER[name]
        chi2 = float(r @ r) / ceiling**2
        threshold = float(stats.chi2.isf(SIGNIFICANCE, n))
        groups[name] = {"n": n, "rms": float(np.sqrt(r @ r / n)), "ceiling": ceiling, "chi2": chi2,
                        "threshold": threshold}
        if chi2 > threshold:
            implausible.append(name)
    everything = np.concatenate(list(residuals.values()))
    estimable = bool(np.sqrt(np.mean(everything**2)) > NOISE_FREE)
    at_reference = {}
    if not estimable:
        try:
            covariance = np.linalg.inv(unweighted_jacobian.T @ unweighted_jacobian)
            at_reference = {k: float(REFERENCE_SCATTER * np.sqrt(c)) for k, c in zip(names, np.diag(covariance))}
        except np.linalg.LinAlgError:
            at_reference = {}
    lack = _lack_of_fit(data, residuals["e"], p) if "e" in residuals else None
    return Scatter(groups, tuple(implausible), lack, estimable, at_reference)

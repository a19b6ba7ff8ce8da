"""sigma_Y and the plastic modulus H of a linearly hardening sphere fitted together, on the vz master table's law
with its hardening sheet (calib.fit.vz_hardening): ``nfdcal fit-data --fit-hardening``
(calib.commands.fit_data_hardening); ``--hardening-modulus H`` takes H as known instead.

**The model.** sigma_y(eps_p) = sigma_Y + H eps_p; theta = (ln sigma_Y, ln H), H/E from LOWEST_H_OVER_E
(1e-4) to the sheet's top (0.2). For a trial theta the law is the vz-table law (with dents or imprint
radii the vz-unload law) of the hardened master table at (nu, E/sigma_Y, H/E) (calib.fit.measured.table_law,
calib.fit.vz_hardening.HardenedMasterTable); drop tests (e, P_max, contact_time, dent, radius) and force-approach
curves as calib.fit.measured.table_law takes them. The weighted least squares, covariance and intervals:
calib.fit.measured.two_parameter. The model-form term V_model = diag(u_s^2, u_H^2): u_s the vz master table's u in
ln sigma_Y for this kind of data (calib.fit.measured.table_law.model_form_uncertainty) and U_LN_SIGMA_Y in
quadrature, u_H = U_LN_H, both the rms of ln(fitted / true) of this fit on the noise-free FE data (drops e; e +
P_max; e + P_max + contact time; e + dent; the force curve) of the sheet's four finite-strain linear checks (nu
0.23-0.42; E/sigma_Y 250-2000; H/E 0.012-0.14; off every node): sigma_Y within 2.70 %, H within 9.4 %
(tests/benchmarks/bench_hardening_fit_data.py).

**Identifiability.** Hardening changes the law little while the contact is small: in small strain (below
about a = 0.05 R) drop tests barely change along ln H; over the finite strain's reach (12.8-50 P_Y to
2039-4135 P_Y, 1 % scatter) they determine H in 100 of 160 noisy trials: 6 of 40 at H/E 0.012, all 40 at 0.14
(calib/fit/README.md, The hardening sheet). A parameter is determined
when its statistical relative standard error is at most DETERMINED_RELATIVE_SE (10 %;
calib.fit.measured.identifiability). Where H is not, the data determine the flow stress at one plastic
strain, the combination of least variance

    sigma_* = sigma_Y + H eps_*,   eps_* = -Cov(sigma_Y, H) / Var(H)   (clipped to >= 0)

(the statistical Cov in SI from Cov(theta): Cov(x) = D Cov(theta) D, D = diag(sigma_Y, H)); :func:`refusal` is
the one line naming sigma_*, eps_* and its standard error (combined).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from calib.fit.measured import two_parameter
from calib.fit.measured.data import Measurements
from calib.fit.measured.identifiability import DETERMINED_RELATIVE_SE
from calib.fit.measured.specimen import Specimen
from calib.fit.measured.table_law import (CONSISTENT, data_kind, data_window, has_dents, law_residual_levels,
                                          model_form_uncertainty, residuals, sigma_y_range, table_law)
from calib.fit.vz_hardening import HardenedMasterTable, HardeningSheet
from calib.fit.vz_master_table import VZMasterTable
from nfdmodel import VZTableParams

LOWEST_H_OVER_E = 1e-4          # the fit's lower bound of H/E: below it no drop test tells the law from H = 0
U_LN_H = 0.0469                 # model form in ln H (module doc): rms of ln(H_fit / H) on the finite checks
U_LN_SIGMA_Y = 0.0109           # model form in ln sigma_Y beyond the table's (module doc), the same fits
GRID = (9, 7)                   # the starting grid over (ln sigma_Y, ln H)


@dataclass(frozen=True)
class HardeningFit:
    """sigma_Y [Pa] and H [Pa] with standard errors (combined, statistical, model-form), 95 % intervals, their
    correlation, the residuals per group, the law at the fit, the identifiability report and the verdict."""
    values: dict
    spread: dict                # two_parameter.intervals: se, se_stat, se_model, interval95, correlation
    law: VZTableParams
    data_window: tuple
    H_over_E: float
    residuals: dict
    group_scale: dict
    verdict: str
    consistent: bool
    identifiability: dict
    uncertainty: dict

    @property
    def interval95(self) -> dict:
        return self.spread["interval95"]


def fit(data: Measurements, specimen: Specimen, master: VZMasterTable, sheet: HardeningSheet,
        noise: float | None = None) -> HardeningFit:
    """sigma_Y and H fitted together (module doc). A ValueError in one line when the best fit lies on a bound."""
    master.check(specimen.nu, float(master.E_over_sigma_y[0]))      # nu inside the table
    sizes = data.group_sizes()
    unload = has_dents(data)
    E = specimen.E
    low_sigma, high_sigma = sigma_y_range(specimen, master)
    lower = np.log([low_sigma, LOWEST_H_OVER_E * E])
    upper = np.log([high_sigma, sheet.H_over_E_range[1] * E])

    def law_at(theta):
        sigma_y, H = np.exp(theta)
        return table_law(specimen, float(sigma_y), HardenedMasterTable(master, sheet, float(H / E)), unload)

    def groups(theta):
        return residuals(law_at(theta), data)

    grid = [np.linspace(lower[0], upper[0], GRID[0]), np.linspace(lower[1], upper[1], GRID[1])]
    theta, g, scale, weighted = two_parameter.solve(groups, sizes, grid, lower, upper)
    sigma_y, H = (float(x) for x in np.exp(theta))
    files = ", ".join(data.files)
    if theta[0] <= lower[0] + 1e-6 or theta[0] >= upper[0] - 1e-6:
        side = "softer" if theta[0] <= lower[0] + 1e-6 else "harder"
        raise ValueError(f"{files}: the hardened vz-table model fits these data best at E/sigma_Y = {E / sigma_y:.4g}, "
                         f"the edge of the vz master table: the data ask for a {side} material; check the data's "
                         f"units and the material flags")
    fitted = two_parameter.covariance(weighted, theta)
    v_stat, n = fitted["v_stat"], fitted["n"]
    kind = data_kind(data)
    u = model_form_uncertainty(master, specimen.nu, E / sigma_y, kind)
    v_model = np.diag([u * u + U_LN_SIGMA_Y**2, U_LN_H**2])
    names = ("sigma_y", "hardening_modulus")
    values = {"sigma_y": sigma_y, "hardening_modulus": H}
    spread = two_parameter.intervals(names, values, v_stat, v_model, n)
    report = identifiability(values, v_stat, v_model, fitted["degenerate"])
    on_bound = "lower" if theta[1] <= lower[1] + 1e-6 else "upper" if theta[1] >= upper[1] - 1e-6 else None
    if on_bound and report["hardening_determined"]:
        raise ValueError(f"{files}: the hardened model fits these data best at H/E = {H / E:.3g}, the {on_bound} end "
                         f"of the range {LOWEST_H_OVER_E:g}..{sheet.H_over_E_range[1]:g} it is measured on: "
                         + ("the data show no hardening; fit them as a perfectly plastic sphere" if on_bound == "lower"
                            else
                            "a stiffer hardening than the sheet holds; calibrate by FE (nfdcal calibrate "
                            "--hardening-modulus)"))
    law = law_at(theta)
    rms = {group: float(np.sqrt(np.mean(g[group] ** 2))) for group in sizes}
    level = law_residual_levels(master, kind, sizes)
    expected = {group: math.hypot(level[group], noise or 0.0) for group in sizes}
    said = ", ".join(f"{group} {100 * rms[group]:.2g} % against {100 * expected[group]:.2g} %" for group in sizes)
    consistent = all(rms[group] <= CONSISTENT * expected[group] for group in sizes if expected[group] > 0)
    verdict = (f"rms residuals {'within' if consistent else 'beyond'} {CONSISTENT:g}x the vz-table law's residual on "
               f"noise-free FE data" + (f" and the stated noise {100 * noise:.2g} %" if noise else "") + f" ({said})")
    return HardeningFit(values=values, spread=spread, law=law, data_window=data_window(law, data), H_over_E=H / E,
                        residuals=g, group_scale=scale, verdict=verdict, consistent=consistent, identifiability=report,
                        uncertainty={"kind": kind, "u_ln_sigma_y_table": u, "u_ln_sigma_y_hardening": U_LN_SIGMA_Y,
                                     "u_ln_H": U_LN_H, "dof_statistical": n - 2})


def identifiability(values: dict, v_stat: np.ndarray, v_model: np.ndarray, degenerate: bool) -> dict:
    """Which of sigma_Y and H the data determine and the flow stress sigma_* at the plastic strain eps_* they
    determine best (module doc)."""
    relative = {key: float(math.sqrt(max(v_stat[j, j], 0.0))) for j, key in enumerate(values)}
    if degenerate:
        relative["hardening_modulus"] = math.inf
    determined = {key: rel <= DETERMINED_RELATIVE_SE for key, rel in relative.items()}
    sigma_y, H = values["sigma_y"], values["hardening_modulus"]
    scale = np.diag([sigma_y, H])
    total = scale @ (v_stat + v_model) @ scale              # Cov of (sigma_Y, H) [Pa^2]
    statistical = scale @ v_stat @ scale                    # the data's own: where they leave H free
    strain = max(-statistical[0, 1] / statistical[1, 1], 0.0) if statistical[1, 1] > 0 else 0.0
    weights = np.array([1.0, strain])
    flow = sigma_y + H * strain
    flow_se = float(math.sqrt(max(weights @ total @ weights, 0.0))) / flow
    flow_stat = float(math.sqrt(max(weights @ statistical @ weights, 0.0))) / flow
    said = ", ".join(f"{'sigma_Y' if key == 'sigma_y' else 'H'} to {100 * rel:.2g} %" for key, rel in relative.items())
    combination = (f"the flow stress at plastic strain {strain:.3g}, sigma_Y + H {strain:.3g} = {flow:.4g} Pa +- "
                   f"{100 * flow_se:.2g} % (statistical {100 * flow_stat:.2g} %)")
    text = f"the data determine {said} (statistical relative standard errors); {combination}"
    loose = [key for key, ok in determined.items() if not ok]
    if loose:
        text += f"; not determined (> {100 * DETERMINED_RELATIVE_SE:g} %): {', '.join(loose)}"
    return {"relative_se": relative, "determined": determined,
            "hardening_determined": all(determined.values()),
            "determined_combination": {"name": "sigma_Y + H eps_*", "plastic_strain": strain, "value": flow,
                                       "relative_se": flow_se, "relative_se_statistical": flow_stat, "unit": "Pa"},
            "summary": text}


def refusal(result: HardeningFit) -> str:
    """The one-line refusal when the data do not determine sigma_Y and H apart (module doc), else ""."""
    report = result.identifiability
    if report["hardening_determined"]:
        return ""
    flow = report["determined_combination"]
    said = ", ".join(f"{'sigma_Y' if key == 'sigma_y' else 'H'} to {100 * rel:.2g} %" if math.isfinite(rel) else
                     f"{key} not at all" for key, rel in report["relative_se"].items())
    return (f"the data do not determine sigma_Y and H apart: they would be known only to {said} (> "
            f"{100 * DETERMINED_RELATIVE_SE:g} %); they determine the flow stress at plastic strain "
            f"{flow['plastic_strain']:.3g}, sigma_Y + H {flow['plastic_strain']:.3g} = {flow['value']:.4g} Pa +- "
            f"{100 * flow['relative_se']:.2g} %; drop tests to larger loads (contact radii beyond 0.05 R) separate "
            f"them, or give H (a tensile test's) with --hardening-modulus")

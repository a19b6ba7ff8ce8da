"""fit-data's constrained model on the load-dependent law: sigma_Y from drop tests and
force-approach curves through the vz-table law of the vz master table (``nfdcal fit-data --law vz-table``).

**The model.** For a trial sigma_Y the law is the vz-table law interpolated in the vz master
table at (nu, E / sigma_Y) (calib.fit.vz_master_table: a_p/a_Y and C_R against P/P_Y, from FE
load-unload paths over the whole window), so one parameter, theta = ln sigma_Y, is fitted over the
data's whole window. Predictions, as calib.fit.measured.specimen states them for the vz law:
drop tests by the law's quasi-static impact (nfdmodel.collision_reference, law "vz-table":
e, P_max, contact time; with a dent column the table's vz-unload law, the same loading with the
FE's dent ratio and unloading exponent, its delta_res the dent; with a radius column the same law,
its contact radius at the peak the imprint's: calib.fit.measured.imprint), force-approach curves by the law driven along each measured approach
(a virgin contact per test), their force fitted on the virgin loading rows (approach at its
running maximum): the law takes the FE's loading curve and the work each unloading returns, its
unloading is a Hertz curve of that work, not the FE's unloading shape (fitted on whole cycles,
the unloading rows bias sigma_Y by -2.5 to -3.9 % at three off-grid materials whose loading rows
give -0.2 to +0.7 %). Residuals per group g (e, P_max, contact_time, force) are relative
(force: / max(|P|, P_floor)); each group is weighted by 1 / s_g, s_g its rms residual
(re-estimated), as calib.fit.measured.regression.

**Uncertainty.** Var(ln sigma_Y) = V_stat + V_model. V_stat is the statistical variance of the
fit with its groups' scales estimated from their own residuals, and its degrees of freedom
(calib.fit.measured.interval: the sandwich of the linearised fit, per group degrees of freedom,
Meier's factor for the estimated weights; one group: s^2 / J^T J, s^2 = sum r^2 / (n - 1));
V_model = u^2. u is the law's model-form standard uncertainty in ln sigma_Y for this kind of data
(drop tests on e, on e and P_max, a force-approach curve), measured against direct FE across the
table: the rms error of this very fit on the noise-free FE data of off-grid materials
(calib.fit.vz_master_check; the table's .json, ``model_form.sigma_y``), combined with the
surrounding nodes' estimated discretisation error when the table has it. The model-form error is
systematic (the same for every test of a series), so it does not shrink with more data. The 95 %
interval (calib.fit.measured.interval) takes the statistical half-widths below and above the fit
from the profile of the weighted sum of squares (sigma_Y's sensitivities change across the
interval at a few percent noise), combines each with u and scales by k, Student's t at the
Welch-Satterthwaite degrees of freedom (V_model is stated: infinite degrees of freedom; JCGM
100:2008, G.4): s^2 from six drop tests has five degrees of freedom, and 1.96 would cover the truth
in about 89 % of noisy series instead of 95 %.

**What the summary says.** The rms residual is compared with the law's model-form level and with
the scatter the residuals show (calib.fit.measured.scatter); the fit is called consistent with
the law only when the residual lies within that; otherwise it says by how much it exceeds it.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field

import numpy as np
from scipy import optimize

from calib.fit.measured import imprint
from calib.fit.measured.data import Measurements
from calib.fit.measured.interval import Z95, coverage_factor, interval95  # noqa: F401 (re-exported)
from calib.fit.measured.specimen import Specimen, impact_residuals
from calib.fit.pair_table import PairTable, pair_law
from calib.fit.vz_master_table import VZMasterTable
from nfdmodel import (ContactPair, PlausibilityWarning, RangeWarning, VZTableParams, VZUnloadParams, collision_reference,
                      get_law)

STEP = 1e-5                        # the central-difference step in ln sigma_Y
SCAN_POINTS = 13                   # the coarse scan of ln sigma_Y over the table that starts the fit
CONSISTENT = 2.0                   # residual / expected level above this: the law does not describe the data


def table_law(specimen: Specimen, sigma_y: float, table: VZMasterTable, unload: bool = False) -> VZTableParams:
    """The vz-table law of the tested pair at sigma_Y [Pa] (a_p/a_Y, C_R of the material at
    (nu, E / sigma_Y); the window the table measured there); ``unload``: the table's vz-unload law
    (the same loading, the FE's dent ratio and unloading exponent: the law dents are fitted on). On a
    specimen's counter-body: the pair law of the pair table on that law (calib.fit.pair_table.pair_law)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PlausibilityWarning)
        material = specimen.material(sigma_y)
        if specimen.counter is not None:
            return pair_law(material, specimen.R, specimen.counter, pair_table_of(specimen), table)["law"]
        flat = table.unload_law(material, specimen.R) if unload else table.law(material, specimen.R)
        if not specimen.two_spheres:
            return flat
        pair = ContactPair.sphere_sphere(material, specimen.R, material, specimen.R)
    params = VZTableParams(pair, flat.x, flat.f, flat.g, flat.window)
    return VZUnloadParams.from_table(params, flat.x_unload, flat.dent, flat.exponent) if unload else params


def pair_table_of(specimen: Specimen) -> PairTable:
    """The pair table a specimen on a counter-body is fitted with (Specimen.pair_table)."""
    given = specimen.pair_table
    return given if isinstance(given, PairTable) else PairTable.load(given)


def law_name(law: VZTableParams) -> str:
    """The nfdmodel law of ``law``: vz-unload for the table's vz-unload law, else vz-table."""
    return "vz-unload" if isinstance(law, VZUnloadParams) else "vz-table"


def has_dents(data: Measurements) -> bool:
    """Whether the drop tests measured dents or imprint radii (fitted through the vz-unload law,
    :func:`table_law`; the radius: calib.fit.measured.imprint)."""
    return bool({"dent", "radius"} & set(data.group_sizes()))


def predict(law: VZTableParams, data: Measurements) -> dict:
    """What the law predicts for each measured group (module doc)."""
    out = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RangeWarning)
        if data.impacts is not None:
            ref = collision_reference(law_name(law), law, data.impacts.v_in)
            out["impacts"] = {"e": ref.restitution, "P_max": ref.P_max, "contact_time": ref.contact_time_estimate,
                              "dent": ref.delta_res, "radius": imprint.predicted_radius(law, ref.P_max)}
        if data.forces is not None:
            driver = get_law("vz-table")
            forces = []
            for _, approach, _ in data.forces.tests:
                turning = np.maximum.accumulate(np.maximum(approach, 0.0))
                at_turning, loaded = driver.force(turning, driver.initial_state(approach.size), law)
                force, _ = driver.force(approach, loaded, law)
                forces.append(np.where(approach >= turning, at_turning, force))
            out["forces"] = forces
    return out


def residuals(law: VZTableParams, data: Measurements) -> dict[str, np.ndarray]:
    """Relative residuals per group (calib.fit.measured.specimen's definitions)."""
    return residuals_of(predict(law, data), data)


def residuals_of(predicted: dict, data: Measurements) -> dict[str, np.ndarray]:
    """Relative residuals per group of the law's predictions ``predicted`` (:func:`predict`)."""
    out = {}
    if data.impacts is not None:
        out.update(impact_residuals(data, predicted["impacts"]))
    if data.forces is not None:
        floor = data.forces.force_floor
        parts = []
        for p, (_, approach, f) in zip(predicted["forces"], data.forces.tests):
            loading = virgin_loading(approach)
            parts.append((p[loading] - f[loading]) / np.maximum(np.abs(f[loading]), floor))
        out["force"] = np.concatenate(parts)
    return out


def virgin_loading(approach: np.ndarray) -> np.ndarray:
    """The rows of a force-approach test on its virgin loading curve (approach at its running
    maximum, > 0): where the law reproduces the FE's force (module doc)."""
    return (approach > 0.0) & (approach >= np.maximum.accumulate(approach) * (1.0 - 1e-12))


def data_kind(data: Measurements) -> str:
    """Which measured model-form error applies: "force" when a force-approach curve is fitted,
    else "drops e+radius" or "drops e+dent+radius" with imprint radii (the vz-unload law,
    calib.fit.measured.imprint; P_max or contact times beside them are fitted, not judged), else "drops e+dent" with dents (the vz-unload law; with P_max or
    contact times too, their groups' levels under it are not measured and not judged), else "drops e+P+t" with contact times (with or without P_max: the contact time's error is the
    law's largest, its unloading a Hertz curve of the FE's work), "drops e+P" with P_max, else
    "drops e"."""
    if data.forces is not None:
        return "force"
    groups = data.group_sizes()
    if "radius" in groups:            # the imprint radius (calib.fit.measured.imprint), with or without dents
        return "drops e+dent+radius" if "dent" in groups else "drops e+radius"
    if "dent" in groups:
        return "drops e+dent"
    return "drops e+P+t" if "contact_time" in groups else "drops e+P" if "P_max" in groups else "drops e"


def model_form_uncertainty(table: VZMasterTable, nu: float, E_over_sigma_y: float, kind: str,
                           model_form: dict | None = None, specimen: Specimen | None = None) -> float:
    """u [-] in ln sigma_Y (module doc): ``model_form`` (kind -> u), else the table's measured one,
    combined in quadrature with the surrounding nodes' discretisation error estimate and, on a
    specimen's counter-body, the pair table's own (this fit on the two-body FE of held-out pairs: it holds the
    master law's error on those pairs too, so the sum overstates u rather than understates it)."""
    form = imprint.model_form(table).get("sigma_y", {}) if model_form is None else model_form
    node = table.tables(nu, E_over_sigma_y)["rel_error_estimate"] or 0.0
    pair = 0.0
    if specimen is not None and specimen.counter is not None and model_form is None:
        pair = float(pair_table_of(specimen).meta.get("model_form", {}).get("sigma_y", {}).get(kind, 0.0))
    return math.hypot(float(form.get(kind, 0.0)), node, pair)


def law_residual_levels(table: VZMasterTable, kind: str, groups, specimen: Specimen | None = None) -> dict:
    """The law's rms residual per data group on noise-free FE data of this ``kind`` (the table's, with a
    specimen's counter-body the pair table's in quadrature): the level a fit's residual is judged against."""
    levels = imprint.model_form(table).get("residual_rms", {})
    pair = (pair_table_of(specimen).meta.get("model_form", {}).get("residual_rms", {})
            if specimen is not None and specimen.counter is not None else {})
    return {name: math.hypot(float(levels.get(f"{kind}: {name}", 0.0)), float(pair.get(f"{kind}: {name}", 0.0)))
            for name in groups}


@dataclass(frozen=True)
class TableLawFit:
    """sigma_Y [Pa] with its standard errors (statistical, model-form, combined), the 95 % interval,
    the residuals per group, the law at the fit and the verdict in words."""
    sigma_y: float
    se_stat: float
    se_model: float
    se: float
    interval95: tuple
    residuals: dict
    group_scale: dict
    law: VZTableParams
    uncertainty: dict           # the data kind, u in ln sigma_Y, the law's measured errors per group
    verdict: str
    consistent: bool
    data_window: tuple = field(default=(float("nan"), float("nan")))

    @property
    def rms_residual(self) -> float:
        r = np.concatenate(list(self.residuals.values()))
        return float(np.sqrt(np.mean(r**2)))


def sigma_y_range(specimen: Specimen, table: VZMasterTable) -> tuple[float, float]:
    """[Pa]: E / sigma_Y inside the table (and, on a counter-body, inside the pair table's nodes)."""
    low, high = float(table.E_over_sigma_y[0]), float(table.E_over_sigma_y[-1])
    if specimen.counter is not None:
        axis = pair_table_of(specimen).ratios_axis
        low, high = max(low, float(axis[0])), min(high, float(axis[-1]))
    return specimen.E / high * (1 + 1e-9), specimen.E / low * (1 - 1e-9)


def fit(data: Measurements, specimen: Specimen, table: VZMasterTable, sigma_y_start: float | None = None,
        noise: float | None = None, model_form: dict | None = None) -> TableLawFit:
    """The constrained fit of sigma_Y on the vz-table law (module doc). ``noise``: the stated
    relative measurement noise [-] (None: not stated); ``model_form``: kind -> u in ln sigma_Y
    (default: the table's measured one). A ValueError naming the cause when the
    data cannot be fitted inside the table (nu outside it, best sigma_Y on its edge)."""
    table.check(specimen.nu, float(table.E_over_sigma_y[0]))      # nu inside the table
    low, high = np.log(sigma_y_range(specimen, table))
    sizes = data.group_sizes()
    scale = {name: 1.0 for name in sizes}

    unload = has_dents(data)
    if specimen.counter is not None:      # nu, E1'/E2' inside the pair table's nodes: refused before the data
        table_law(specimen, math.exp(0.5 * (low + high)), table)

    def groups(theta):
        return residuals(table_law(specimen, math.exp(theta), table, unload), data)

    def weighted(theta):
        g = groups(float(np.atleast_1d(theta)[0]))
        return np.concatenate([g[name] / scale[name] for name in sizes])

    def cost(theta):
        try:
            r = weighted(theta)
        except ValueError:
            return math.inf
        return float(r @ r)

    if sigma_y_start is None:                         # a coarse scan: the fit starts in the right basin
        grid = np.linspace(low, high, SCAN_POINTS)
        theta = float(grid[int(np.argmin([cost(t) for t in grid]))])
    else:
        theta = float(np.clip(math.log(sigma_y_start), low, high))
    for _ in range(3 if len(sizes) > 1 else 1):       # re-weight the groups by their scatter (one group: no need)
        span = 0.3
        best = optimize.minimize_scalar(cost, bounds=(max(low, theta - span), min(high, theta + span)),
                                        method="bounded", options={"xatol": 1e-9})
        theta = float(best.x)
        g = groups(theta)
        scale = {name: max(float(np.sqrt(np.mean(g[name] ** 2))), 1e-6) for name in sizes}
    at_fit = sum(float(g[name] @ g[name]) / scale[name] ** 2 for name in sizes)
    if theta <= low + 1e-6 or theta >= high - 1e-6:
        side = "softer" if theta <= low + 1e-6 else "harder"
        raise ValueError(f"{', '.join(data.files)}: the vz-table model fits these data best at E/sigma_Y = "
                         f"{specimen.E / math.exp(theta):.4g}, the edge of the "
                         f"{'vz master' if specimen.counter is None else 'pair'} table (E/sigma_Y "
                         f"{specimen.E / math.exp(high):.4g}..{specimen.E / math.exp(low):.4g}): the data ask for a "
                         f"{side} material; "
                         f"check the data's units and the material flags, or calibrate by FE (nfdcal calibrate --v-max)")
    plus, minus = groups(theta + STEP), groups(theta - STEP)
    slope = {name: (plus[name] - minus[name]) / (2 * STEP) for name in sizes}
    kind = data_kind(data)
    u = model_form_uncertainty(table, specimen.nu, specimen.E / math.exp(theta), kind, model_form, specimen)
    bounded = interval95(theta, g, slope, scale, cost, at_fit, u, (low, high))
    sigma_y = math.exp(theta)
    v_stat, v_model = bounded.statistical.variance, u * u
    se_stat, se_model = sigma_y * math.sqrt(v_stat), sigma_y * math.sqrt(v_model)
    v = v_stat + v_model
    interval = (math.exp(bounded.low), math.exp(bounded.high))
    law = table_law(specimen, sigma_y, table, unload)
    rms = {name: float(np.sqrt(np.mean(g[name] ** 2))) for name in sizes}
    law_error = law_residual_levels(table, kind, sizes, specimen)
    expected = {name: math.hypot(law_error[name], noise or 0.0) for name in sizes}
    # a group with no measured level (a table without it, no noise stated) cannot be judged
    judged = [name for name in sizes if expected[name] > 0] or list(sizes)
    excess = {name: rms[name] / max(expected[name], 1e-12) for name in judged}
    consistent = all(ratio <= CONSISTENT for ratio in excess.values())
    level = "the law's residual on noise-free FE data" + (f" and the stated noise {100 * noise:.2g} %" if noise else
                                                          " (no noise stated)")
    said = ", ".join(f"{name} {100 * rms[name]:.2g} % against {100 * expected[name]:.2g} %" if name in judged else
                     f"{name} {100 * rms[name]:.2g} % (the law's level not measured: not judged)" for name in sizes)
    name = "vz-unload" if unload else "vz-table"
    verdict = (f"rms residuals within {CONSISTENT:g}x {level} ({said}): consistent with the {name} law of the vz "
               f"master table" if consistent else
               f"rms residuals {max(excess.values()):.3g}x {level} ({said}): the {name} law does not describe "
               f"these data to within its measured accuracy" + ("" if noise else " unless they scatter that much")
               + "; the interval assumes it does")
    window = data_window(law, data)
    return TableLawFit(sigma_y, se_stat, se_model, sigma_y * math.sqrt(v), interval, g, scale, law,
                       {"kind": kind, "u_ln_sigma_y": u, "law_error": law_error,
                        "dof_statistical": bounded.statistical.dof, "coverage_factor": bounded.k,
                        "u_ln_sigma_y_statistical": [bounded.u_minus, bounded.u_plus]},
                       verdict, consistent, window)


def data_window(law: VZTableParams, data: Measurements) -> tuple[float, float]:
    """The loads the data reach, P/P_Y (the law's P_max of each drop test, each force test's peak:
    the window bounds the peaks whose unloading the table measured, a loading curve passes below)."""
    loads = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RangeWarning)
        if data.impacts is not None:
            loads.append(np.asarray(collision_reference(law_name(law), law, data.impacts.v_in).P_max))
    if data.forces is not None:
        loads.append(np.array([float(np.max(force)) for _, _, force in data.forces.tests]))
    x = np.concatenate(loads) / law.pair.P_Y
    return float(x[x > 1].min()) if (x > 1).any() else 1.0, float(x.max())

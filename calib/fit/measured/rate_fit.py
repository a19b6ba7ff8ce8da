"""sigma_Y and one rate constant fitted together to drop tests at several speeds, on the rate-aware
vz-table law (``nfdcal fit-data --rate-law``), or the rate constant alone with sigma_Y held
(``--hold-sigma-y``).

**The model.** theta = (ln sigma_Y, ln k), k the rate law's free constant: Cowper-Symonds' D [1/s] with
q given, or Johnson-Cook's C [-] with eps_dot_0 given (nfdmodel.strain_rate). For a trial theta the law
is the rate-aware law (nfdmodel.rate_aware) on the vz-table law of the vz master table at (nu,
E / sigma_Y) (calib.fit.measured.table_law): each test's strain rate eps_dot = v_in / (c a_ref) and its
factor R fixed at first contact, the impact that of the base law with sigma_Y R (its exact energy
balance, nfdmodel.rate_aware.rate_aware_reference: e, P_max, contact time). Residuals per group (e,
P_max, contact_time) are relative and each group is weighted by 1 / s_g, s_g its rms residual
(re-estimated), as calib.fit.measured.table_law. Least squares in theta (scipy.optimize.least_squares,
bounds D 1e-3..1e12 /s, C 1e-4..1), started at the best of a coarse grid.

**Two forms** (``form``, ``--rate-form``). fixed: the above, c = 26. relaxing (nfdmodel.rate_relaxing, c
5.7, k 1.15): the flow-stress factor s follows the contact's strain rate, the impact is the law's
continuous-time reference (nfdmodel.rate_relaxing.relaxing_reference, every test one block of one Radau
system), a test's R is s at its turning point and its strain rate the rate law's inverse at s. Its least
squares starts at the fixed form's fit (a relaxing grid would cost 81 series of impacts).

**sigma_Y held** (``hold_sigma_y``: a quasi-static yield stress, such as a tensile test's): theta = (ln k)
alone. A decade of speeds moves the flow stress by a few per cent, which the two constants trade against
each other; with sigma_Y given, that change is the rate law's alone.

**Uncertainty.** Cov(theta) = V_stat + V_model. V_stat = s^2 (J^T J)^-1, J = d r_w / d theta at the fit
(central differences), s^2 = r_w.r_w / (n - 2). V_model, systematic (the same for every test, so it does
not shrink with more tests): (i) the vz master table's model-form error u in ln sigma_Y for this kind of
data (calib.fit.measured.table_law.model_form_uncertainty), a bias common to every test that moves
sigma_Y R as a whole, hence ln sigma_Y alone (with sigma_Y held, it and the held value's own relative
uncertainty ``sigma_y_uncertainty`` move ln k by the linear response to ln sigma_Y, as (ii)); (ii) the
rate-aware law's constant c of eps_dot = v_n0 / (c a_ref), known to u_c in ln c per form and rate law
(U_LN_C; fixed: the rms of ln(c_e / c) over the dynamic FE impacts of
tests/benchmarks/bench_rate_materials.py, c_e the c whose rate-aware e equals the FE's: Cowper-Symonds
0.31 over 39 impacts, six spheres, q 1 and 5, 6-278 v_Y, 0.5-135 /s, c_e 13-42; Johnson-Cook 1.23 over
3 impacts of mild steel at 44-135 /s, c_e 57-123; relaxing: 0.30 over the 71 impacts of
tests/benchmarks/bench_rate_relaxing.py, both rate laws, c_e 4.3-14.5), propagated by the linear response
g = -(J^T J)^-1 J^T
d r_w / d ln c (for Cowper-Symonds it is exactly u_c in ln D: c and D enter as c D); (iii) c's trend
with the speed, which no constant c follows (the c matched to each impact grows or falls with v_in on every
sphere of that benchmark): each test's c_i = c (v_i / v_mean)^beta, v_mean the tests' geometric mean speed,
beta known to u_beta (U_C_TREND; fixed 0.17, the rms of d ln c_e / d ln v_in over its 14 spheres and rate
laws, -0.20..+0.33; relaxing 0.28 over 17, -0.44..+0.32), propagated by the linear response to beta as
(ii). A trend in the law's error is what two constants absorb by moving sigma_Y (Cowper-Symonds D 2 q 1
on the FE's drop tests: sigma_Y 19 % low at statistical errors below 1 %), so this term widens sigma_Y's
interval where the data leave that room. The 95 % interval per parameter: theta_j +- k_j sqrt(Cov_jj), k_j
Student's t at the Welch-Satterthwaite degrees of freedom of V_stat (n - 2, n - 1 with sigma_Y held) and
V_model (infinite) (calib.fit.measured.interval; JCGM 100:2008, G.4).

**Identifiability** (as calib.fit.measured.identifiability: relative sensitivities, singular values,
a parameter determined when its statistical relative standard error is at most
DETERMINED_RELATIVE_SE, 10 %). When the speeds span too little, R varies little across the tests and
the data determine only the flow stress at the tests' strain rates: the report names that combination,
sigma_Y R at the tests' mean strain rate (sigma_Y exp(mean ln R_i), the geometric mean of the tests'
R), its value and relative standard error, and the spread of R across the tests; fit-data then refuses
(one line, exit 2): the two are not fitted apart. Johnson-Cook with every test below eps_dot_0 (R = 1
throughout) determines sigma_Y alone, said so. The refusal adds, when the rms residuals exceed twice the
law's residual on noise-free FE data (per group, the larger of the vz-table law's and the rate-aware form's
own against the dynamic FE, RATE_LAW_LEVEL; and the stated noise), that the rate-aware law does not
describe the data to that level: then the combination's figure carries the law's error too.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np
from calib.fit.measured import two_parameter
from calib.fit.measured.data import Measurements
from calib.fit.measured.identifiability import DETERMINED_RELATIVE_SE
from calib.fit.measured.specimen import Specimen, impact_residuals
from calib.fit.measured.table_law import data_kind, model_form_uncertainty, sigma_y_range, table_law
from calib.fit.vz_master_table import VZMasterTable
from nfdmodel import RangeWarning
from nfdmodel.rate_aware import RATE_LENGTH_FACTOR, RateAwareParams, rate_aware_reference
from nfdmodel.rate_relaxing import RELAXING_LENGTH_FACTOR, RelaxingRateParams, rate_form_law, relaxing_reference
from nfdmodel.strain_rate import CowperSymonds, JohnsonCook

# the free constant of each rate law, its bounds and the fixed constant's name (module doc)
FREE = {"cowper-symonds": "D", "johnson-cook": "C"}
FIXED = {"cowper-symonds": "q", "johnson-cook": "reference_rate"}
BOUNDS = {"D": (1e-3, 1e12), "C": (1e-4, 1.0)}
UNITS = {"D": "1/s", "C": "-", "q": "-", "reference_rate": "1/s"}
# c of each form of the rate-aware law, as shipped
LENGTH_FACTOR = {"fixed": RATE_LENGTH_FACTOR, "relaxing": RELAXING_LENGTH_FACTOR}
# u of ln c per form and rate law: the rms of ln(c_e / c) over the dynamic FE impacts (module doc): fixed,
# bench_rate_materials.py; relaxing, bench_rate_relaxing.py (71 impacts, both rate laws)
U_LN_C = {"fixed": {"cowper-symonds": 0.31, "johnson-cook": 1.23},
          "relaxing": {"cowper-symonds": 0.30, "johnson-cook": 0.30}}
# u of c's trend with the speed, d ln c_e / d ln v_in: the rms over the spheres and rate laws of the same benchmarks
# (fixed 14, relaxing 17)
U_C_TREND = {"fixed": 0.17, "relaxing": 0.28}
# each form's rms error against the dynamic FE on noise-free drop tests (the 36 impacts its constants were fitted on,
# six spheres, Cowper-Symonds q 5 and 1: tests/benchmarks/bench_rate_relaxing.py): the misfit test's level (module doc)
RATE_LAW_LEVEL = {"fixed": {"e": 0.0235, "P_max": 0.0211, "contact_time": 0.0156},
                  "relaxing": {"e": 0.0085, "P_max": 0.0145, "contact_time": 0.0147}}
STEP = two_parameter.STEP
GRID = (9, 9)                 # the starting grid over (ln sigma_Y, ln k)


def rate_law(kind: str, constant: float, fixed: float):
    """The nfdmodel.strain_rate law of ``kind`` with its free ``constant`` and ``fixed`` one."""
    return CowperSymonds(constant, fixed) if kind == "cowper-symonds" else JohnsonCook(constant, fixed)


def rate_params(specimen: Specimen, table: VZMasterTable, kind: str, sigma_y: float, constant: float,
                fixed: float, c: float | None = None, form: str = "fixed") -> RateAwareParams:
    """The rate-aware law of ``form`` (fixed or relaxing; c its shipped one by default) of the tested pair on the
    vz master table's vz-table law at sigma_Y [Pa]."""
    return rate_form_law(form, "vz-table", table_law(specimen, sigma_y, table), rate_law(kind, constant, fixed), c)[1]


def form_of(params: RateAwareParams) -> str:
    """The form of the rate-aware law ``params`` state: fixed or relaxing."""
    return "relaxing" if isinstance(params, RelaxingRateParams) else "fixed"


def rates_and_factors(params: RateAwareParams, v_in) -> tuple[np.ndarray, np.ndarray]:
    """(each test's strain rate [1/s], its flow-stress factor R [-]) at ``v_in`` [m/s]: fixed, eps_dot = v_in /
    (c a_ref) and R(eps_dot); relaxing, s at the turning point and the rate at which the rate law's flow stress is
    s sigma_Y (the rate law's inverse; at most the first contact's, where s stays 1 below Johnson-Cook's eps_dot_0)."""
    factors = params.rate_factor(v_in)
    if form_of(params) == "fixed":
        return params.strain_rate(v_in), factors
    return np.minimum(params.rate_law.rate_at(factors), params.strain_rate(v_in)), factors


def predict(params: RateAwareParams, v_in) -> dict:
    """e, P_max [N], contact time [s] of the rate-aware law's impacts at ``v_in`` [m/s] (either form)."""
    reference = relaxing_reference if form_of(params) == "relaxing" else rate_aware_reference
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RangeWarning)
        ref = reference(params, v_in)
    return {"e": ref.restitution, "P_max": ref.P_max, "contact_time": ref.contact_time_estimate,
            "dent": ref.delta_res}


def check_data(data: Measurements) -> None:
    """A ValueError (one line) for data the rate fit does not take: force curves (quasi-static: no strain
    rate), dents (the rate-aware law's base is vz-table, whose dent is not the FE's), one speed."""
    if data.forces is not None:
        raise ValueError(f"--rate-law fits drop tests at several speeds: {data.forces.path} is a quasi-static "
                         f"force-approach curve, which carries no strain rate; fit it without --rate-law")
    if data.impacts is None:
        raise ValueError("--rate-law needs --impacts CSV (drop tests at several speeds)")
    if data.impacts.dent is not None:
        raise ValueError(f"{data.impacts.path}: column 'dent' is fitted on the vz-unload law, which the rate-aware "
                         f"law does not take (its base is vz or vz-table); drop the column or fit without --rate-law")
    speeds = np.unique(data.impacts.v_in)
    if speeds.size < 3:
        raise ValueError(f"{data.impacts.path}: v_in takes {speeds.size} distinct value(s): --rate-law fits sigma_Y "
                         f"and a rate constant from drop tests at three speeds or more (a decade apart or more)")


@dataclass(frozen=True)
class RateFit:
    """sigma_Y [Pa] and the rate constant with standard errors (statistical, model-form, combined, SI),
    95 % intervals, the correlation, the residuals per group, the law at the fit, each test's strain
    rate [1/s] and R, the identifiability report and the verdict in words."""
    kind: str
    name: str                   # the free constant: D or C
    fixed: float                # q or eps_dot_0
    values: dict                # sigma_y, and D or C
    se: dict
    se_stat: dict
    se_model: dict
    interval95: dict
    correlation: float
    residuals: dict
    group_scale: dict
    params: RateAwareParams
    strain_rates: np.ndarray
    rate_factors: np.ndarray
    identifiability: dict
    uncertainty: dict
    verdict: str
    consistent: bool
    data_window: tuple

    @property
    def rms_residual(self) -> float:
        r = np.concatenate(list(self.residuals.values()))
        return float(np.sqrt(np.mean(r**2)))


def fit(data: Measurements, specimen: Specimen, table: VZMasterTable, kind: str, fixed: float,
        sigma_y_start: float | None = None, constant_start: float | None = None,
        noise: float | None = None, form: str = "fixed", hold_sigma_y: bool = False,
        sigma_y_uncertainty: float = 0.0) -> RateFit:
    """sigma_Y and the rate law's free constant fitted together on the rate-aware law of ``form`` (fixed or
    relaxing), or the constant alone with sigma_Y held at ``sigma_y_start`` (``hold_sigma_y``; its relative
    standard uncertainty ``sigma_y_uncertainty``; module doc). A ValueError in one line when the data cannot be
    fitted (the checks of :func:`check_data`, the best fit on a bound)."""
    check_data(data)
    table.check(specimen.nu, float(table.E_over_sigma_y[0]))      # nu inside the table
    if hold_sigma_y and sigma_y_start is None:
        raise ValueError("sigma_y out of range: holding sigma_Y needs its value")
    name = FREE[kind]
    sizes = data.group_sizes()
    v = data.impacts.v_in
    lower = np.log([sigma_y_range(specimen, table)[0], BOUNDS[name][0]])
    upper = np.log([sigma_y_range(specimen, table)[1], BOUNDS[name][1]])
    free = [1] if hold_sigma_y else [0, 1]             # which of (ln sigma_Y, ln k) are fitted
    held = np.array([math.log(sigma_y_start) if sigma_y_start is not None else 0.0, 0.0])

    def full(theta):                                   # (ln sigma_Y, ln k) of the fitted parameters
        out = held.copy()
        out[free] = theta
        return out

    v_mean = float(np.exp(np.mean(np.log(v))))        # the tests' geometric mean speed [m/s]
    c_law = LENGTH_FACTOR[form]

    def groups_of(theta_full, c=c_law, trend=0.0, law_form=form):
        sigma_y, constant = np.exp(theta_full)
        if trend == 0.0:
            return impact_residuals(data, predict(rate_params(specimen, table, kind, sigma_y, constant, fixed, c,
                                                              law_form), v))
        # c_i = c (v_i / v_mean)^trend: c's trend with the speed (module doc, model form (iii))
        each = [predict(rate_params(specimen, table, kind, sigma_y, constant, fixed, c_i, law_form), [v_i])
                for v_i, c_i in zip(v, c * (v / v_mean) ** trend)]
        return impact_residuals(data, {key: np.concatenate([one[key] for one in each]) for key in each[0]})

    def groups(theta, **kw):
        return groups_of(full(theta), **kw)

    grid = [np.linspace(lower[0], upper[0], GRID[0]), np.linspace(lower[1], upper[1], GRID[1])]
    if sigma_y_start is not None:
        grid[0] = [float(np.clip(math.log(sigma_y_start), lower[0], upper[0]))]
    if constant_start is not None:
        grid[1] = [float(np.clip(math.log(constant_start), lower[1], upper[1]))]
    grid = [grid[j] for j in free]
    if form == "relaxing" and not hold_sigma_y:   # its least squares starts at the fixed form's fit (module doc)
        start = two_parameter.solve(lambda theta: groups(theta, c=LENGTH_FACTOR["fixed"], law_form="fixed"), sizes,
                                    grid, lower[free], upper[free])[0]
        grid = [[float(x)] for x in start]
    theta, g, scale, weighted = two_parameter.solve(groups, sizes, grid, lower[free], upper[free])
    sigma_y, constant = (float(x) for x in np.exp(full(theta)))
    sigma_y = sigma_y_start if hold_sigma_y else sigma_y       # the held value as given
    if not hold_sigma_y and (theta[0] <= lower[0] + 1e-6 or theta[0] >= upper[0] - 1e-6):
        side = "softer" if theta[0] <= lower[0] + 1e-6 else "harder"
        raise ValueError(f"{', '.join(data.files)}: the rate-aware vz-table model fits these data best at E/sigma_Y "
                         f"= {specimen.E / sigma_y:.4g}, the edge of the vz master table (E/sigma_Y "
                         f"{table.E_over_sigma_y[0]:g}..{table.E_over_sigma_y[-1]:g}): the data ask for a {side} "
                         f"material; check the data's units and the material flags")
    fitted = two_parameter.covariance(weighted, theta)
    jac, v_stat, inverse, n, degenerate = (fitted[key] for key in ("jac", "v_stat", "inverse", "n", "degenerate"))
    params = rate_params(specimen, table, kind, sigma_y, constant, fixed, form=form)
    u = model_form_uncertainty(table, specimen.nu, specimen.E / sigma_y, data_kind(data))

    def response_to(plus, minus):          # -(J^T J)^-1 J^T d r_w / d(a systematic term), central differences
        return -inverse @ jac.T @ ((plus - minus) / (2 * STEP))

    def shifted(h):                        # the weighted residuals with ln sigma_Y moved by h from the fit
        theta_full = full(theta)
        theta_full[0] += h
        moved = groups_of(theta_full)
        return np.concatenate([moved[group] / scale[group] for group in sizes])

    response = response_to(weighted(theta, c=c_law * math.exp(STEP)), weighted(theta, c=c_law * math.exp(-STEP)))
    response_trend = response_to(weighted(theta, trend=STEP), weighted(theta, trend=-STEP))
    v_model = (np.outer(response, response) * U_LN_C[form][kind] ** 2
               + np.outer(response_trend, response_trend) * U_C_TREND[form] ** 2)
    # the table's bias u in the flow stress (model form (i)): sigma_Y's own where it is fitted; where it is held,
    # it moves the constant as an error in the held sigma_Y would, and so does the held value's own uncertainty
    response_sigma_y = response_to(shifted(STEP), shifted(-STEP)) if hold_sigma_y else None
    v_model = v_model + (np.outer(response_sigma_y, response_sigma_y) * (u * u + sigma_y_uncertainty**2)
                         if hold_sigma_y else np.diag([u * u, 0.0]))
    names = ("sigma_y", name)[2 - len(free):]
    values = {"sigma_y": sigma_y, name: constant}
    spread = two_parameter.intervals(names, values, v_stat, v_model, n)
    se, se_stat, se_model, interval, correlation = (spread[key] for key in ("se", "se_stat", "se_model",
                                                                            "interval95", "correlation"))
    rates, factors = rates_and_factors(params, v)
    report = identifiability(theta, jac, v_stat, v_model, names, values, rates, factors, degenerate,
                             specimen, table, kind, fixed, data, form, full)
    on_bound = theta[-1] <= lower[1] + 1e-6 or theta[-1] >= upper[1] - 1e-6
    if on_bound and (report["rate_determined"] or hold_sigma_y):
        side = "lower" if theta[-1] <= lower[1] + 1e-6 else "upper"
        raise ValueError(f"{', '.join(data.files)}: the rate-aware model fits these data best at {name} = "
                         f"{constant:.4g} {UNITS[name]}, the {side} end of its range {BOUNDS[name][0]:g}.."
                         f"{BOUNDS[name][1]:g}: the data ask for a rate dependence this rate law does not give")
    rms = {group: float(np.sqrt(np.mean(g[group] ** 2))) for group in sizes}
    kind_of_data = data_kind(data)
    level_of = table.meta.get("model_form", {}).get("residual_rms", {})
    expected = {group: math.hypot(max(float(level_of.get(f"{kind_of_data}: {group}", 0.0)),
                                      RATE_LAW_LEVEL[form].get(group, 0.0)), noise or 0.0) for group in sizes}
    said = ", ".join(f"{group} {100 * rms[group]:.2g} % against {100 * expected[group]:.2g} %" for group in sizes)
    consistent = all(rms[group] <= 2.0 * expected[group] for group in sizes if expected[group] > 0)
    verdict = (f"rms residuals {'within' if consistent else 'beyond'} 2x the {form} rate-aware law's residual on "
               f"noise-free FE data" + (f" and the stated noise {100 * noise:.2g} %" if noise else "") + f" ({said})")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RangeWarning)
        peaks = predict(params, v)["P_max"] / (params.pair.P_Y * factors**3)   # the base law's P/P_Y
    above = peaks[peaks > 1.0]
    window = (float(above.min()) if above.size else 1.0, float(peaks.max()))
    uncertainty = {"kind": kind_of_data, "form": form, "sigma_y_held": hold_sigma_y, "u_ln_sigma_y_table": u,
                   "u_ln_sigma_y_held": sigma_y_uncertainty if hold_sigma_y else None,
                   "u_ln_c": U_LN_C[form][kind], "u_c_trend": U_C_TREND[form], "dof_statistical": n - len(free),
                   "c_response": dict(zip(names, map(float, response))),
                   "c_trend_response": dict(zip(names, map(float, response_trend)))}
    if response_sigma_y is not None:
        uncertainty["sigma_y_response"] = {name: float(response_sigma_y[0])}
    return RateFit(kind, name, fixed, values, se, se_stat, se_model, interval, correlation, g, scale, params,
                   rates, factors, report, uncertainty, verdict, consistent, window)


def identifiability(theta, jac, v_stat, v_model, names, values, rates, factors, degenerate, specimen, table,
                    kind, fixed, data, form: str = "fixed", full=None) -> dict:
    """Which of sigma_Y and the rate constant the data determine (module doc; the constant alone where sigma_Y
    is held, ``full`` mapping the fitted parameters onto (ln sigma_Y, ln k)) and, when the rate constant is not,
    the combination they do: sigma_Y R at the tests' mean strain rate."""
    full = full or (lambda t: t)
    _, singular, vt = np.linalg.svd(jac, full_matrices=False)
    relative = {key: float(math.sqrt(max(v_stat[j, j], 0.0))) for j, key in enumerate(names)}
    if degenerate:
        relative = {key: (math.inf if abs(vt[-1][j]) > 1e-3 else rel) for j, (key, rel) in
                    enumerate(relative.items())}
    determined = {key: rel <= DETERMINED_RELATIVE_SE for key, rel in relative.items()}
    weakest = dict(zip(names, map(float, vt[-1] * np.sign(vt[-1][np.argmax(np.abs(vt[-1]))]))))
    mean_ln_r = float(np.mean(np.log(factors)))
    mean_rate = float(np.exp(np.mean(np.log(np.maximum(rates, 1e-300)))))
    flow = values["sigma_y"] * math.exp(mean_ln_r)

    def log_flow(t):                                     # ln(sigma_Y exp(mean ln R_i)) at theta t
        sigma_y, constant = np.exp(full(t))
        law = rate_params(specimen, table, kind, sigma_y, constant, fixed, form=form)
        return math.log(sigma_y) + float(np.mean(np.log(law.rate_factor(data.impacts.v_in))))

    gradient = np.array([(log_flow(theta + STEP * unit) - log_flow(theta - STEP * unit)) / (2 * STEP)
                         for unit in np.eye(len(names))])
    flow_stat = float(math.sqrt(max(gradient @ v_stat @ gradient, 0.0)))
    flow_total = float(math.sqrt(max(gradient @ (v_stat + v_model) @ gradient, 0.0)))
    spread = float(factors.max() / factors.min() - 1.0)
    name = names[-1]
    said = ", ".join(f"{key} to {100 * rel:.2g} %" for key, rel in relative.items())
    text = f"the data determine {said} (statistical relative standard errors)"
    if len(names) == 1:
        text += f", sigma_Y held at {values['sigma_y']:.4g} Pa"
    combination = (f"sigma_Y R at the tests' mean strain rate {mean_rate:.3g} /s = {flow:.4g} Pa +- "
                   f"{100 * flow_total:.2g} % (statistical {100 * flow_stat:.2g} %)")
    loose = [key for key, ok in determined.items() if not ok]
    if loose:
        along = " ".join(f"{v:+.2f} ln {key}" for key, v in weakest.items())
        text += (f"; not determined (> {100 * DETERMINED_RELATIVE_SE:g} %): {', '.join(loose)}: R varies by "
                 f"{100 * spread:.2g} % across the tests (R {factors.min():.4g}..{factors.max():.4g}), the data barely "
                 f"change along {along}; they determine {combination}")
    return {"parameters": list(names), "singular_values": [float(s) for s in singular],
            "condition_number": float(singular[0] / singular[-1]) if singular[-1] > 0 else math.inf,
            "relative_se": relative, "determined": determined, "weakest_combination": weakest,
            "rate_determined": all(determined.values()),
            "rate_factor_spread": spread, "mean_strain_rate": mean_rate,
            "determined_combination": {"name": "sigma_Y R at the tests' mean strain rate", "value": flow,
                                       "strain_rate": mean_rate, "relative_se": flow_total,
                                       "relative_se_statistical": flow_stat, "unit": "Pa"},
            "summary": text}


def undetermined(result: RateFit) -> str:
    """The one-line refusal when the data do not determine sigma_Y and the rate constant apart (module doc),
    else ""."""
    report = result.identifiability
    if report["rate_determined"]:
        return ""
    flow = report["determined_combination"]
    factors = result.rate_factors
    said = ", ".join(f"{key} to {100 * rel:.2g} %" if math.isfinite(rel) else f"{key} not at all"
                     for key, rel in report["relative_se"].items())
    if factors.max() <= 1.0 + 1e-12:                 # Johnson-Cook: every test below eps_dot_0, where R = 1
        return (f"every test's strain rate ({result.strain_rates.min():.3g}..{result.strain_rates.max():.3g} /s) lies "
                f"below the reference rate eps_dot_0 = {result.fixed:g} /s, where R = 1: the data do not determine "
                f"{result.name}; they determine sigma_Y = {flow['value']:.4g} Pa +- {100 * flow['relative_se']:.2g} % "
                f"(fit it without --rate-law), or give a lower --jc-reference-rate")
    misfit = "" if result.consistent else (f"; {result.verdict}: the rate-aware law does not describe these data "
                                           f"to that level")
    if result.uncertainty["sigma_y_held"]:
        return (f"the data do not determine {result.name} with sigma_Y held at {result.values['sigma_y']:.4g} Pa: R "
                f"varies by {100 * report['rate_factor_spread']:.2g} % across the tests (R {factors.min():.4g}.."
                f"{factors.max():.4g}, eps_dot {result.strain_rates.min():.3g}..{result.strain_rates.max():.3g} "
                f"/s), so "
                f"it would be known only to {said} (> {100 * DETERMINED_RELATIVE_SE:g} %); the data determine sigma_Y "
                f"R at the tests' mean strain rate {flow['strain_rate']:.3g} /s = {flow['value']:.4g} Pa +- "
                f"{100 * flow['relative_se']:.2g} %; drop tests at higher speeds would determine it{misfit}")
    return (f"the data do not determine sigma_Y and {result.name} apart: R varies by "
            f"{100 * report['rate_factor_spread']:.2g} % across the tests (R {factors.min():.4g}..{factors.max():.4g}, "
            f"eps_dot {result.strain_rates.min():.3g}..{result.strain_rates.max():.3g} /s), so they would be known "
            f"only to {said} (> {100 * DETERMINED_RELATIVE_SE:g} %); the data determine sigma_Y R at the tests' mean "
            f"strain rate {flow['strain_rate']:.3g} /s = {flow['value']:.4g} Pa +- {100 * flow['relative_se']:.2g} %; "
            f"drop tests over a wider range of speeds would separate them, or give sigma_Y with the rate law's "
            f"constants to nfdcal material --v-max --rate-law{misfit}")


def misfit(result: RateFit) -> str:
    """The one-line refusal when the rate-aware law misses the data beyond twice its residual on noise-free FE
    data and the stated noise (``result.consistent`` false): the fitted sigma_Y and rate constant would carry
    a misfit their statistical errors do not state; else ""."""
    if result.consistent:
        return ""
    flow = result.identifiability["determined_combination"]
    return (f"the rate-aware law does not describe these data: {result.verdict}; its sigma_Y and {result.name} "
            f"would carry that misfit unstated; the data determine sigma_Y R at the tests' mean strain rate "
            f"{flow['strain_rate']:.3g} /s = {flow['value']:.4g} Pa +- {100 * flow['relative_se']:.2g} %; give --noise "
            f"when the data scatter more")


def refusal(result: RateFit) -> str:
    """Why fit-data --rate-law refuses ``result`` (:func:`undetermined`, then :func:`misfit`), "" when it does not."""
    return undetermined(result) or misfit(result)

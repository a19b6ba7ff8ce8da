"""The 95 % interval of fit-data's vz-table fit (calib.fit.measured.interval): against closed forms
and a simulation of models the law did not make (a common mean of groups with their own unknown
scatter; a mean fitted through exp(theta)), and on FE drop tests of an off-grid material
(tests/data/vz_master_fe.json, never made by the law) with noise."""
import json
import math
from pathlib import Path

import numpy as np
import pytest
from scipy import stats

from calib.fit.measured.interval import interval95
from calib.fit.measured.table_law import fit
from calib.fit.vz_master_check import fe_datasets, measurements
from calib.fit.vz_master_table import VZMasterTable

FE_DATA = Path(__file__).resolve().parent / "data" / "vz_master_fe.json"


def common_mean(samples: list[np.ndarray]):
    """Fit a common mean theta to groups y_g (residuals theta - y_g, each group weighted by its rms
    residual, re-weighted as fit-data does): theta, its interval (u = 0) and the linearised
    variance s^2 / J_w.J_w with s^2 = S / (n - 1) over all residuals."""
    scale = {g: 1.0 for g in range(len(samples))}
    for _ in range(3):
        w = {g: 1.0 / scale[g] ** 2 for g in scale}
        theta = sum(w[g] * samples[g].sum() for g in scale) / sum(w[g] * samples[g].size for g in scale)
        scale = {g: float(np.sqrt(np.mean((theta - samples[g]) ** 2))) for g in scale}
    residuals = {g: theta - samples[g] for g in scale}
    ones = {g: np.ones(samples[g].size) for g in scale}

    def weighted_sum(x):
        return sum(float(np.sum((x - samples[g]) ** 2)) / scale[g] ** 2 for g in scale)

    n = sum(y.size for y in samples)
    linear = weighted_sum(theta) / (n - 1) / sum(y.size / scale[g] ** 2 for g, y in enumerate(samples))
    return theta, interval95(theta, residuals, ones, scale, weighted_sum, weighted_sum(theta), 0.0, (-50.0, 50.0)), linear


def test_one_group_is_the_student_t_interval_of_a_mean():
    """One group: the interval of a mean is ybar -+ t(0.975, n-1) s / sqrt(n), exactly."""
    y = np.array([0.3, -1.2, 0.8, 2.1, -0.4, 0.9])
    theta, bounds, _ = common_mean([y])
    half = stats.t.ppf(0.975, y.size - 1) * y.std(ddof=1) / math.sqrt(y.size)
    assert theta == pytest.approx(y.mean(), abs=1e-14)
    assert bounds.statistical.dof == pytest.approx(y.size - 1, rel=1e-12)
    assert bounds.low == pytest.approx(y.mean() - half, rel=1e-5) and bounds.high == pytest.approx(y.mean() + half, rel=1e-5)


def test_the_profile_gives_the_exact_interval_through_a_nonlinear_parameter():
    """y_i = exp(theta) + noise: the interval of theta is ln of the t interval of the mean (the
    profile does not depend on the parametrisation; the slope at the fit would be symmetric)."""
    y = np.array([1.9, 2.6, 1.4, 2.2, 3.0, 1.7])
    theta = math.log(y.mean())
    r = {"y": math.exp(theta) - y}
    scale = {"y": float(np.sqrt(np.mean(r["y"] ** 2)))}
    slope = {"y": np.full(y.size, math.exp(theta))}

    def weighted_sum(x):
        return float(np.sum((math.exp(x) - y) ** 2)) / scale["y"] ** 2

    bounds = interval95(theta, r, slope, scale, weighted_sum, weighted_sum(theta), 0.0, (-10.0, 10.0))
    half = stats.t.ppf(0.975, y.size - 1) * y.std(ddof=1) / math.sqrt(y.size)
    assert bounds.low == pytest.approx(math.log(y.mean() - half), abs=2e-4)
    assert bounds.high == pytest.approx(math.log(y.mean() + half), abs=2e-4)
    assert theta - bounds.low > bounds.high - theta       # ln stretches the lower side


@pytest.mark.parametrize("ratio", [1.0, 4.0])
def test_two_groups_of_six_with_their_own_scatter_cover_about_95_percent(ratio):
    """The common mean of two groups of six (scatter 1 and ``ratio``, both estimated from the data,
    the Graybill-Deal problem): the interval covers the true mean in 93-96 % of 3000 simulated
    series (binomial sd 0.4 %; Meier's factor is first order in 1 / nu_g: 93.4 % at equal scatter);
    the linearised variance at n - 1 = 11 degrees of freedom covers less than 91.5 %."""
    rng = np.random.default_rng(7)
    covered, naive = 0, 0
    trials = 3000
    for _ in range(trials):
        samples = [rng.normal(0.0, 1.0, 6), rng.normal(0.0, ratio, 6)]
        theta, bounds, linear = common_mean(samples)
        covered += bounds.low <= 0.0 <= bounds.high
        naive += abs(theta) <= stats.t.ppf(0.975, 11) * math.sqrt(linear)
    assert 0.93 <= covered / trials <= 0.96
    assert naive / trials < 0.915


@pytest.fixture(scope="module")
def fe_sets():
    table = VZMasterTable.load()
    row = json.loads(FE_DATA.read_text(encoding="utf-8"))["rows"][0]
    return table, row, fe_datasets(row, table)


@pytest.mark.parametrize("seed", [1])
def test_fe_drop_tests_with_noise_on_e_and_p_max(fe_sets, seed):
    """FE drop tests of an off-grid material (e and P_max, 3 % noise): the interval holds the true
    sigma_Y, its statistical degrees of freedom lie between one group's (n_g - 1 = 5) and all
    residuals' (2 n_g - 1 = 11)."""
    table, row, sets = fe_sets
    rng = np.random.default_rng(seed)
    d = sets["drops"]
    values = {"v_in": d["v_in"], "e": d["e"] * (1 + 0.03 * rng.standard_normal(d["e"].size)),
              "P_max": d["P_max"] * (1 + 0.03 * rng.standard_normal(d["P_max"].size)),
              "approach": sets["force"][0], "force": sets["force"][1]}
    result = fit(measurements("drops e+P", values, row["name"]), sets["specimen"], table, noise=0.03)
    n = d["e"].size
    assert result.interval95[0] <= sets["sigma_y"] <= result.interval95[1]
    assert n - 1 - 1e-9 <= result.uncertainty["dof_statistical"] <= 2 * n - 1
    assert result.se_stat > 0.0 and result.uncertainty["coverage_factor"] > stats.norm.ppf(0.975)

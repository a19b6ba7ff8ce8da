"""The works of a load-unload path from its history (calib.fe.loadpath.contact_work, the rows of a
path): against the closed form of an elastic Hertzian contact, W = (2/5) K alpha^(5/2), e = 1."""
import numpy as np
import pytest

from calib.fe.loadpath import loading_count_to_peak
from calib.fit.vz_master_check import fe_paths

K = 3.0e9            # P = K alpha^(3/2) [N], alpha [m]
PEAK = 250.0         # [N]


def hertz_row(overshoot: float) -> dict:
    """A stored row (the vz master table's format) of an elastic path to PEAK, its loading branch
    stepped geometrically, the FE's force at the peak ``overshoot`` (relative) above the target as
    Newton leaves it, and a further load beyond (the next path's)."""
    P = np.r_[np.geomspace(1.0, PEAK, 40), 400.0]
    P[39] *= 1.0 + overshoot
    alpha = (P / K) ** (2 / 3)
    down_P = np.r_[np.linspace(PEAK, 0.0, 60)[1:-1], 1e-6]
    return {"loading": {"P": P.tolist(), "alpha": alpha.tolist()},
            "paths": [{"P_max": PEAK, "alpha_max": float(alpha[39]),
                       "unloading": {"P": down_P.tolist(), "alpha": ((down_P / K) ** (2 / 3)).tolist()}}]}


@pytest.mark.parametrize("overshoot", [0.0, -3e-9, 3e-9, 5e-8])
def test_the_peak_row_closes_the_loading_work_whichever_side_newton_leaves_it(overshoot):
    path = fe_paths(hertz_row(overshoot))[0]
    exact = 0.4 * K * ((PEAK / K) ** (2 / 3)) ** 2.5
    assert path["loading_points"] == 40
    assert path["loading_work"] == pytest.approx(exact, rel=2e-3)    # the trapezoid on 40 geometric steps
    assert path["unloading_work"] == pytest.approx(exact, rel=2e-3)
    assert path["e"] == pytest.approx(1.0, abs=2e-3)                 # elastic: nothing dissipated


def test_a_history_without_the_peak_is_refused():
    with pytest.raises(ValueError, match="no loading row at the peak"):
        loading_count_to_peak([1.0, 2.0, 4.0], 3.0)

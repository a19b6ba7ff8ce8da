"""The works of a load-unload path from its history (calib.fe.loadpath.contact_work, the rows of a
path): against the closed form of an elastic Hertzian contact, W = (2/5) K alpha^(5/2), e = 1."""
import dataclasses

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


def test_a_separation_step_newton_cannot_close_is_cut_and_gives_the_same_path(mesh_cache):
    """The step from the last unloading load to separation, when neither the ordinary nor the
    rescue solve converges in one piece, runs in pieces (calib.fe.loadpath.advance, each one a
    row): the same residual approach and, against the one-piece run on the same FE, e within the
    Hertzian end segment's error (the works' end segment, P ~ (alpha - alpha_res)^(3/2))."""
    from calib.fe import ContactSolver, LoadPathPlan, VonMisesMaterial, run_load_paths
    from meshes.hemisphere import HemisphereMeshSpec, hemisphere_mesh
    from nfdmodel import ContactPair, Material

    material = Material(70e9, 0.3, 100e6, 2700.0)
    pair = ContactPair.sphere_flat(material, 0.1)
    mesh = hemisphere_mesh(HemisphereMeshSpec(radius=0.1, contact_size=2e-4, refined_radius=2e-3,
                                              refined_depth=1e-3, far_size=0.01), cache_dir=mesh_cache)
    plan = LoadPathPlan(peaks=(4 * pair.P_Y,), loading_step=pair.P_Y, first_load=0.5 * pair.P_Y)

    def solver():
        return ContactSolver(mesh, VonMisesMaterial(material.E, material.nu, material.sigma_y))

    whole = run_load_paths(solver(), plan).paths[0]
    stalling = solver()
    separation = whole.alpha_residual
    refused = []

    def refuse_at_separation(solve):
        def wrapped(state, *args):
            result = solve(state, *args)
            target = args[-1]
            if np.isclose(target, separation, rtol=1e-9) and state.force > 0 and len(refused) < 3:
                refused.append(target)      # the ordinary, the rescue and the first whole piece
                return dataclasses.replace(result, converged=False, message="refused by the test")
            return result
        return wrapped

    stalling.solve_displacement = refuse_at_separation(stalling.solve_displacement)
    stalling.rescue_step = refuse_at_separation(stalling.rescue_step)
    cut = run_load_paths(stalling, plan).paths[0]
    assert len(refused) == 3
    rows = [r for r in cut.rows if r["branch"] == "unloading"]
    assert len(rows) == len([r for r in whole.rows if r["branch"] == "unloading"]) + 1   # two pieces
    assert cut.alpha_residual == whole.alpha_residual
    assert rows[-1]["alpha"] == pytest.approx(separation, rel=1e-12)
    assert cut.restitution == pytest.approx(whole.restitution, rel=2e-3)

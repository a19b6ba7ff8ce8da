"""The two-body FE's finite-strain reach on an elastic flat (calib.fit.recipe.reach_kinematics).

Checked against what the two-body FE did not produce: the rigid flat's finite-strain FE (calib.fe.solver). A
sphere (nu 0.3, E/sigma_Y 200) on an elastic flat 100 times stiffer than itself (E1'/E2' = 0.01) must press and
rebound as on the rigid flat, within the flat's own share of the approach (about 1 % here: E* is 1 % below E1')
and the mesh difference the block brings. On one coarse graded mesh (ELEMENTS across every contact radius from
300 P_Y) to 2900 P_Y, where the contact reaches a/R* 0.43: the approach D = alpha/delta_Y on each body's own
scales within 2.5 % along the loading branch from 300 P_Y (1.8 % at the top, 1.0 % to 1982 P_Y), e within
2.5 % at 300 P_Y and at the top (1.6 %). On the pair table's mesh (10 elements) the two meet within 0.74 % in
approach and 0.36 % in e at 3090 P_Y, a/R* 0.44. The plan's reach: a
calibration to there on an elastic flat is accepted in finite strain, refused in small strain and on a
counter-sphere, whose gap stays small-strain (one line naming P_max).
"""
import numpy as np
import pytest

from calib.fit import pair_table_build as build
from calib.fit import recipe
from calib.fit.calibration import body_meshes
from calib.fit.counter import CounterBody

NU, E_OVER_SIGMA_Y, TOP = 0.3, 200.0, 2900.0
ELEMENTS = 5.0     # across every contact radius from the lower peak


@pytest.fixture(scope="module")
def records():
    out = {}
    for x in ("1/100", build.RIGID):
        spec = build.spec_of(build.case_task(NU, E_OVER_SIGMA_Y, x, (300.0, TOP), "check"), ELEMENTS)
        body_meshes(spec)
        out[x] = build.load_paths_record(spec)
    return out


def test_a_stiff_flat_is_the_rigid_flat_to_the_finite_reach(records):
    pair, rigid = (np.array(records[x]["loading"]) for x in ("1/100", build.RIGID))
    assert pair[-1, 2] > 0.4                                      # a/R* at the top: the reach is exercised
    loads = np.geomspace(300.0, TOP, 7)
    D_pair, D_rigid = (np.interp(np.log(loads), np.log(r[:, 0]), r[:, 1]) for r in (pair, rigid))
    assert np.abs(D_pair / D_rigid - 1.0).max() < 0.025, D_pair / D_rigid
    e_pair, e_rigid = ([p["e"] for p in records[x]["paths"]] for x in ("1/100", build.RIGID))
    assert np.allclose(e_pair, e_rigid, rtol=0.025, atol=0.0), (e_pair, e_rigid)


def test_the_plan_reaches_0_45_R_on_an_elastic_flat_only():
    m = build.material(NU, E_OVER_SIGMA_Y)
    stiff_flat = CounterBody(m.E * 100.0, NU)
    recipe.calibration_spec(m, build.R, peaks_over_yield=(TOP,), counter=stiff_flat, kinematics="finite-strain")
    with pytest.raises(ValueError, match="P_max out of range|out of range for the FE"):
        recipe.calibration_spec(m, build.R, peaks_over_yield=(TOP,), counter=stiff_flat)
    with pytest.raises(ValueError, match="out of range for the FE"):
        recipe.calibration_spec(m, build.R, peaks_over_yield=(TOP,), kinematics="finite-strain",
                                counter=CounterBody(m.E * 100.0, NU, R=build.R, rho=7800.0))

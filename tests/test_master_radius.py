"""The vz master table's vz-unload and vz-table laws against one coarse direct FE run of a material the
table was not built on (calib.fit.master_radius_check; nu 0.25, E/sigma_Y 150, one of its off-grid
checks): the load path to 27 P_Y with the FE's contact radius at the peak, and one cycle from it
(unloads to 0.5 and 0.2 P_max, reloads, the last on to 1.3 P_max, full unload). Graded mesh of 8
elements across the contact radius at the peak, 16 loading steps per decade, 16 unloading steps
(about 6 s). The node mesh's figures at three peaks and three materials, and the FE's mesh spread:
tests/benchmarks/master_unload_radius.py."""
from __future__ import annotations

import pytest

from calib.fit.cycle_check import CYCLE_TARGET
from calib.fit.master_radius_check import compare, fe_run, laws_of
from calib.fit.unload_check import DENT_TARGET, E_TARGET, RADIUS_TARGET, UNLOADING_TARGET
from calib.fit.vz_master_table import VZMasterTable
from nfdmodel import Material

R = 0.1
MATERIAL = Material(150 * 100e6, 0.25, 100e6, 2700.0)
PEAK_OVER_P_Y = 27.0
# The laws' contact radius at the peak, a_Y (x^(1/3) + f), over the FE's (calib.fe.recovery, gap) on this
# mesh: vz-unload (f_a, fitted to the table nodes' FE radius) +1.3 %, within the 2 % target although this
# mesh's FE radius lies about 1 % below the nodes' mesh's (17.9 elements: -0.3..+0.1 %, the benchmark);
# vz-table (f, fitted to the force and the returned work) +3.5 %.
VZ_TABLE_OVERSTATES = 0.025


@pytest.fixture(scope="module")
def compared():
    run = fe_run(MATERIAL, R, (PEAK_OVER_P_Y,), 8.0, loading_steps_per_decade=16.0, unloading_steps=16)
    return run, compare(laws_of(VZMasterTable.load(), MATERIAL, R), run)


def test_the_fe_radius_is_recorded_and_vz_unload_gives_it_within_the_target(compared):
    """The FE's contact radius at the peak lies between Hertz's at P_max (the plastic contact is wider)
    and R; the vz-unload law's radius at the peak is within the 2 % target of it, the vz-table law's
    (fitted to the force, not the radius) above it by more than 2.5 %."""
    run, result = compared
    path, row = run["paths"][0], result["paths"][0]
    assert run["pair"].hertz_radius(path["P_max"]) < path["radius_at_peak"] < R
    assert abs(row["vz-unload"]["radius_error"]) <= RADIUS_TARGET
    assert row["vz-table"]["radius_error"] > VZ_TABLE_OVERSTATES


def test_vz_unload_follows_the_fe_along_unloading_and_reloading(compared):
    """vz-unload: the force along the FE's unloading, the partial unloads and reloads and the final
    unload after the reload past the peak within 2 % of P_max; the dent within 3 %; e within 1 %."""
    _, result = compared
    row, cycle = result["paths"][0]["vz-unload"], result["cycle"]["vz-unload"]
    assert row["unloading_error"] <= UNLOADING_TARGET
    assert abs(row["dent_error"]) <= DENT_TARGET
    assert abs(row["e_error"]) <= E_TARGET
    assert cycle["partial_error"] <= CYCLE_TARGET and cycle["final_unloading_error"] <= CYCLE_TARGET
    assert abs(cycle["dent_error"]) <= DENT_TARGET


def test_vz_table_misses_the_dent_that_vz_unload_gets(compared):
    """The vz-table law unloads as a Hertz curve: on the same FE path its dent is off by more than the
    3 % target (measured -6.8 %), while its e stays within 1 %."""
    _, result = compared
    row = result["paths"][0]["vz-table"]
    assert abs(row["dent_error"]) > DENT_TARGET
    assert abs(row["e_error"]) <= E_TARGET

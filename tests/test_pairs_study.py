"""The unlike-pair study (calib.studies.pairs) and its steer (calib.fit.substitution), against the two-body FE.

The study's claims, checked on a coarse mesh with one short load-unload path to 13.7 P_Y: the rigid-flat
substitution is exact for two identical spheres (the mid-plane of the symmetric two-body FE is a rigid
frictionless flat: the rigid-flat FE rescaled must match it), and for an aluminium-like sphere on an elastic
flat three times stiffer it gives a force too low at equal approach, a contact radius too large at equal force
and an e too low, by the size results/pairs measures (e about -1.4 % at 13.7 P_Y). The steer is checked on a
hand-made map: its placement of a pair, its interpolation, and the one line the CLI prints.
"""
import pytest

from calib.cli import main
from calib.fit import substitution
from calib.fit.counter import CounterBody
from calib.studies import pairs
from nfdmodel import Material

PLAN = {"peaks_over_yield": (13.7,), "steps_to_first_peak": 8, "unloading_steps": 6}


@pytest.fixture(scope="module")
def fe_rows():
    tasks = {"rigid": pairs.rigid_task("coarse", **PLAN), "identical": pairs.case_task(1.0, "both", "sphere", "coarse", **PLAN),
             "unlike": pairs.case_task(1.0 / 3.0, "sphere", "flat", "coarse", **PLAN)}
    pairs.build_meshes(list(tasks.values()))
    rows = {name: pairs.run_task(task) for name, task in tasks.items()}
    for name, row in rows.items():
        assert row["status"] == "ok", f"{name}: {row.get('error')}"
    return rows


def test_identical_spheres_are_the_rigid_flat(fe_rows):
    row = pairs.compare(fe_rows["identical"], fe_rows["rigid"])
    for key in ("force_error", "radius_error", "e_error"):
        assert abs(row[f"{key}_min"]) < 1e-3 and abs(row[f"{key}_max"]) < 1e-3, (key, row)


def test_unlike_pair_substitution_errs_as_measured(fe_rows):
    row = pairs.compare(fe_rows["unlike"], fe_rows["rigid"])
    assert -0.03 < row["e_error_min"] <= row["e_error_max"] < -0.005, row     # e too low by 0.5-3 %
    assert -0.04 < row["force_error_top"] < -0.005, row                        # force too low at equal approach
    assert 0.0 < row["radius_error_top"] < 0.04, row                           # contact too wide at equal force


MAP = """# a hand-made map
shape,yielding,E1_over_E2,force_error_min,force_error_max,radius_error_min,radius_error_max,e_error_min,e_error_max
flat,sphere,0.5,-0.03,-0.01,0.0,0.02,-0.04,-0.02
flat,sphere,2.0,-0.01,0.0,0.0,0.01,-0.01,0.0
flat,counter,0.5,0.0,0.01,0.0,0.01,0.0,0.005
sphere,both,1.0,0.0,0.0,0.0,0.0,0.0,0.0
"""


@pytest.fixture
def hand_map(tmp_path, monkeypatch):
    path = tmp_path / "map.csv"
    path.write_text(MAP)
    monkeypatch.setattr(substitution, "DATA_FILE", path)
    substitution.measured_map.cache_clear()
    yield str(path)
    substitution.measured_map.cache_clear()


SPHERE = Material(70e9, 0.3, 100e6, 2700.0)


def test_placement_and_interpolation(hand_map):
    stiff = CounterBody(140e9, 0.3)                      # E1/E2 = 0.5, elastic flat: the sphere yields
    assert substitution.placement(SPHERE, stiff) == {"shape": "flat", "yielding": "sphere", "E1_over_E2": 0.5}
    soft_yielding = CounterBody(140e9, 0.3, 50e6)
    assert substitution.placement(SPHERE, soft_yielding)["yielding"] == "counter"
    assert substitution.placement(SPHERE, CounterBody(140e9, 0.3, 105e6, 0.1))["yielding"] == "both"
    middle = substitution.substitution_error(SPHERE, 0.1, CounterBody(70e9, 0.3))    # E1/E2 = 1: log-midway
    assert middle["e_error"] == pytest.approx((-0.025, -0.01))
    assert not middle["beyond"]
    assert not substitution.substitution_error(SPHERE, 0.1, CounterBody(35e9, 0.3))["beyond"]   # E1/E2 = 2
    beyond = substitution.substitution_error(SPHERE, 0.1, CounterBody(700e9, 0.3))             # E1/E2 = 0.1
    assert beyond["beyond"] and beyond["e_error"] == pytest.approx((-0.04, -0.02))             # the nearest end


def test_warning_only_where_e_errs_beyond_two_percent(hand_map):
    line = substitution.substitution_warning(SPHERE, 0.1, CounterBody(140e9, 0.3))
    assert "-4.0..-2.0 % in e" in line and "nfdcal calibrate --counter-E 1.4e+11" in line and "\n" not in line
    assert substitution.substitution_warning(SPHERE, 0.1, CounterBody(35e9, 0.3)) is None      # 1 % at E1/E2 = 2
    assert substitution.substitution_warning(SPHERE, 0.1, CounterBody(140e9, 0.3, 50e6)) is None
    identical = CounterBody(SPHERE.E, SPHERE.nu, SPHERE.sigma_y, 0.1)
    assert substitution.substitution_error(SPHERE, 0.1, identical) is None                     # exact


def test_hertz_with_an_unlike_counter_body_prints_one_steer_line(hand_map, capsys, tmp_path):
    code = main(["hertz", "--counter-E", "140e9", "--counter-nu", "0.3", "--dry-run", "--out", str(tmp_path / "h")])
    err = capsys.readouterr().err.splitlines()
    assert code == 0
    steer = [line for line in err if "calibrate the pair" in line]
    assert len(steer) == 1 and steer[0].startswith("nfdcal hertz: warning: unlike pair"), err

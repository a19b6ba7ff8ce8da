"""The FE's reach by kinematics and the window from first yield (calib.fit.recipe, calib.fit.impact_window,
``nfdcal calibrate --v-max --kinematics``): plans only, no FE run.

- finite strain vouches for 1e4 P_Y and a/R 0.45 (nfd_limits.h), small strain for 1000 P_Y and 0.2 R;
  a brass sphere (E 100 GPa, nu 0.34, sigma_Y 250 MPa, R 5 mm, rho 8500) at 3 m/s needs about 2100 P_Y
  (a/R about 0.17 with the load paths' margin: the FE's contact radius, recipe.fe_contact_radius): planned
  with finite strain, refused with small strain in one line naming the finite strain's reach;
- ``--kinematics auto`` (the default) takes finite strain where the plan's contact radius passes
  recipe.KINEMATICS_PART_OVER_R R or its load the small-strain reach, small strain below (the reference
  calibration's spec unchanged);
- every --v-max window starts at or below 1.1 P_Y on a mesh that resolves the contact there.
"""
from __future__ import annotations

import dataclasses

import pytest

from calib.cli import main
from calib.fit import impact_window, recipe
from calib.fit.counter import CounterBody
from nfdmodel import CalibrationWindow, ContactPair, Material, limits
from nfdmodel.validation import PlausibilityWarning

BRASS = Material(100e9, 0.34, 250e6, 8500.0)
BRASS_R = 0.005
BRASS_FLAGS = ["--E", "100e9", "--nu", "0.34", "--sigma-y", "250e6", "--rho", "8500", "--R", "0.005"]


def test_the_reach_of_each_kinematics_is_the_table_s():
    pair = ContactPair.sphere_flat(BRASS, BRASS_R)
    assert recipe.REACH["small-strain"] == (limits.FE_MAX_LOAD_OVER_YIELD, limits.FE_MAX_CONTACT_RADIUS_OVER_R)
    assert recipe.REACH["finite-strain"] == (limits.FE_FINITE_MAX_LOAD_OVER_YIELD,
                                             limits.FE_FINITE_MAX_CONTACT_RADIUS_OVER_R) == (1e4, 0.45)
    for kinematics, (load, radius) in recipe.REACH.items():     # whichever comes first
        reach = recipe.fe_reach(pair, kinematics)
        a = recipe.REACH_RADIUS[kinematics](pair, reach) / BRASS_R
        assert reach <= load * pair.P_Y * (1 + 1e-12) and a <= radius * (1 + 1e-5)
        assert reach == pytest.approx(load * pair.P_Y) or a == pytest.approx(radius, rel=1e-5)
    assert recipe.fe_reach(pair) == recipe.fe_reach(pair, "small-strain")
    # a counter-sphere's or a yielding counter's contact is small-strain whatever the sphere's kinematics; an
    # elastic flat's follows the sphere's (tests/test_pair_reach.py)
    assert recipe.reach_kinematics("finite-strain", CounterBody(2e11, 0.3, R=0.01, rho=7800.0)) == "small-strain"
    assert recipe.reach_kinematics("finite-strain", CounterBody(2e11, 0.3, sigma_y=1e9)) == "small-strain"
    assert recipe.reach_kinematics("finite-strain", CounterBody(2e11, 0.3)) == "finite-strain"
    assert recipe.reach_kinematics("small-strain", CounterBody(2e11, 0.3)) == "small-strain"


def test_brass_at_3_m_s_is_planned_with_finite_strain_and_covers_its_impact():
    needed, params, _ = impact_window.check_reach(BRASS, BRASS_R, 3.0, "finite-strain")
    pair = params.pair
    assert 1900 < needed / pair.P_Y < 2300                        # "about 2100 P_Y"
    spec = impact_window.impact_spec(BRASS, BRASS_R, needed, "finite-strain",
                                     elements_per_contact_radius=impact_window.GRADED_ELEMENTS_PER_CONTACT_RADIUS)
    assert spec.kinematics == "finite-strain" and spec.plan.peaks[-1] >= needed
    # the FE's contact radius at the top: 0.157 R at 2000 P_Y (coarse graded mesh), 0.17 R estimated at 2300 P_Y
    assert 0.15 < recipe.fe_contact_radius(pair, spec.plan.peaks[-1]) / BRASS_R < 0.2
    assert spec.plan.peaks[0] <= 1.1 * pair.P_Y * (1 + 1e-12)
    with pytest.raises(ValueError, match=r"^v_max out of range: .*1000 P_Y.*--kinematics finite vouches for v_max "
                                         r"<= 7\.\d"):      # the estimating law's radius reaches R* at 5800 P_Y
        impact_window.check_reach(BRASS, BRASS_R, 3.0, "small-strain")
    with pytest.raises(ValueError, match=r"^P_max out of range: .*small-strain.*--kinematics finite reaches"):
        dataclasses.replace(spec, kinematics="small-strain")


def test_the_command_plans_brass_at_3_m_s_and_states_the_reach_and_its_error(capsys):
    assert main(["calibrate", *BRASS_FLAGS, "--v-max", "3", "--dry-run", "--quiet"]) == 0
    out = capsys.readouterr().out
    line = next(x for x in out.splitlines() if x.startswith("kinematics:"))
    assert line.startswith("kinematics: finite-strain (auto:") and "0.45 R" in line and "1.0 % in force" in line
    assert main(["calibrate", *BRASS_FLAGS, "--v-max", "3", "--kinematics", "finite", "--dry-run", "--quiet"]) == 0
    capsys.readouterr()
    assert main(["calibrate", *BRASS_FLAGS, "--v-max", "3", "--kinematics", "small", "--dry-run", "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "v_max out of range" in err[0] and "--kinematics finite vouches for" in err[0]


def test_the_plan_s_contact_radius_follows_the_fe():
    """recipe.fe_contact_radius (the finite strain's reach, --kinematics auto, the plan's a/R*) against the FE's
    contact radius: along --v-max plans' loading branches from 8 P_Y (tests/data/plan_radius_fe.csv, measured by
    tests/benchmarks/plan_radius.py: E/sigma_Y 100-5000, nu 0.22-0.45, small and finite strain, to 2000 P_Y) and the
    published reference calibration's (results/calibration/loading.csv, 8-41 P_Y); the mesh-sizing estimate
    overstates the FE's radius more than 2x at 2000 P_Y."""
    import csv
    from pathlib import Path

    root = Path(__file__).resolve().parent.parent
    rows = list(csv.DictReader(line for line in (root / "tests" / "data" / "plan_radius_fe.csv").open()
                               if not line.startswith("#")))
    errors, mesh_sizing = {}, []
    for row in rows:
        pair = ContactPair.sphere_flat(Material(float(row["E_over_sigma_y"]) * 250e6, float(row["nu"]), 250e6, 8500.0),
                                       0.005)
        load, fe = float(row["P_over_P_Y"]) * pair.P_Y, float(row["a_over_R"]) * 0.005
        errors.setdefault(row["mesh"], []).append(recipe.fe_contact_radius(pair, load) / fe - 1.0)
        if float(row["P_over_P_Y"]) > 1900:
            mesh_sizing.append(recipe.estimated_contact_radius(pair, load) / fe - 1.0)
    assert set(errors) == {"graded-6", "graded-17.9", "uniform-4e-5"} and len(rows) > 300
    finer = errors["graded-17.9"] + errors["uniform-4e-5"]
    assert -0.035 < min(finer) and max(finer) < 0.05               # measured -2.8 .. +4.6 %
    assert -0.05 < min(errors["graded-6"]) and max(errors["graded-6"]) < 0.085      # -4.4 .. +7.8 %
    assert min(mesh_sizing) > 1.0
    reference = ContactPair.sphere_flat(Material.reference(), 0.1)
    loading = [row for row in csv.DictReader(line for line in (root / "results" / "calibration" / "loading.csv").open()
                                             if not line.startswith("#")) if float(row["P"]) >= 8 * reference.P_Y]
    assert len(loading) > 30
    for row in loading:
        assert recipe.fe_contact_radius(reference, float(row["P"])) == pytest.approx(float(row["contact_radius"]),
                                                                                     rel=0.03)


def test_auto_keeps_small_strain_below_where_the_kinematics_part():
    reference = recipe.reference_spec()
    assert recipe.chosen_kinematics(reference.pair, reference.plan.peaks[-1]) == "small-strain"
    pair = ContactPair.sphere_flat(BRASS, BRASS_R)
    below = recipe.largest_admissible_load(pair, recipe.KINEMATICS_PART_OVER_R)
    assert recipe.chosen_kinematics(pair, 0.99 * below) == "small-strain"
    assert recipe.chosen_kinematics(pair, 1.01 * below) == "finite-strain"
    hard = ContactPair.sphere_flat(Material(200e9, 0.3, 40e6, 7800.0), 0.005)       # E/sigma_Y 5000
    assert recipe.fe_contact_radius(hard, 1500 * hard.P_Y) < recipe.KINEMATICS_PART_OVER_R * 0.005
    assert recipe.chosen_kinematics(hard, 1500 * hard.P_Y) == "finite-strain"      # beyond 1000 P_Y


def test_auto_leaves_the_reference_calibration_as_it_was(capsys):
    """The default command plans the small-strain recipe's reference calibration (its figures kept bit for bit)."""
    assert main(["calibrate", "--dry-run", "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "kinematics: small-strain (auto: the plan reaches about a/R* 0.01" in out


@pytest.mark.parametrize("material, radius, v_max", [(BRASS, BRASS_R, 0.3), (BRASS, BRASS_R, 3.0),
                                                     (Material(70e9, 0.3, 100e6, 2700.0), 0.1, 0.05),
                                                     (Material(210e9, 0.29, 1.2e9, 7800.0), 0.002, 2.0)],
                         ids=["brass 0.3 m/s", "brass 3 m/s", "reference 0.05 m/s", "steel 2 m/s"])
def test_every_v_max_window_starts_at_first_yield_on_a_mesh_that_resolves_it(material, radius, v_max):
    needed, params, _ = impact_window.check_reach(material, radius, v_max, "finite-strain")
    kinematics = recipe.chosen_kinematics(params.pair, impact_window.window_top(params.pair, needed, "finite-strain"))
    spec = impact_window.impact_spec(material, radius, needed, kinematics,
                                     elements_per_contact_radius=impact_window.GRADED_ELEMENTS_PER_CONTACT_RADIUS)
    pair = spec.pair
    low = spec.plan.peaks[0]
    assert low == pytest.approx(1.1 * pair.P_Y, rel=1e-9)
    assert recipe.estimated_contact_radius(pair, low) / spec.mesh.contact_size >= \
        impact_window.CONTACT_ELEMENTS_AT_LOWEST
    coarse = recipe.coarse_spec(spec)               # the second mesh: every size x 2, the grading too
    assert coarse.mesh.grading == pytest.approx(2 * spec.mesh.grading)
    assert recipe.estimated_contact_radius(pair, low) / coarse.mesh.contact_size >= \
        impact_window.CONTACT_ELEMENTS_AT_LOWEST


def test_a_finite_strain_window_is_inside_the_fe_s_reach():
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        CalibrationWindow(1.1, 2300.0, 0.41, "FE (finite-strain): mesh")       # brass at 3 m/s: not flagged
    with pytest.warns(PlausibilityWarning, match=r"a/R\* up to 0.5 \(the FE reaches 0.45\)"):
        CalibrationWindow(1.0, 100.0, 0.5, "FE (finite-strain): mesh")
    with pytest.warns(PlausibilityWarning, match=r"a/R\* up to 0.41 \(the FE reaches 0.2\)"):
        CalibrationWindow(1.1, 900.0, 0.41, "FE: mesh")                         # a small-strain FE's
    from calib.fit.calibration import kinematics_note
    assert kinematics_note("finite-strain") == " (finite-strain)" and kinematics_note("small-strain") == ""


def test_the_master_table_law_is_inside_its_window_from_first_yield():
    """The vz master table's nodes start at 2 P_Y (shipped data); its law is declared from P_Y, where it meets
    the targets against an FE path it was not built on (1.5 P_Y, the graded mesh, 12 elements across the
    contact), and an impact loading the contact to 1.5 P_Y is inside its window."""
    import warnings

    from calib.fe.loadpath import run_load_paths
    from calib.fit.calibration import E_TARGET, FORCE_TARGET, _solver
    from calib.fit.path_check import law_against_path
    from calib.fit.vz_master_table import VZMasterTable
    from calib.studies.between_nodes import fe_path, path_record
    from meshes.hemisphere import hemisphere_mesh
    from nfdmodel import RangeWarning, collide

    material = Material.reference()
    law = VZMasterTable.load().law(material, 0.1)
    assert law.window.P_min_over_P_Y == 1.0
    peak = 1.5 * law.pair.P_Y
    spec = impact_window.window_spec(material, 0.1, peak, elements_per_contact_radius=12.0)
    spec = dataclasses.replace(spec, plan=dataclasses.replace(spec.plan, peaks=(peak,), loading_step=peak))
    path = run_load_paths(_solver(spec, hemisphere_mesh(spec.mesh)), spec.plan).paths[0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RangeWarning)
        errors = law_against_path("vz-table", law, fe_path(path_record(path.peak, path.restitution, path.rows)))
    assert abs(errors["e_error"]) <= E_TARGET and errors["force_error"] <= FORCE_TARGET
    v_in = impact_window.reach_velocity(law, peak)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RangeWarning)
        assert collide("vz-table", law, [v_in]).in_calibrated_range.tolist() == [True]


def test_finite_strain_meshes_are_sized_by_the_fe_s_contact_radius():
    """A finite-strain plan's mesh (recipe.sizing_radius: fe_contact_radius) against the FE's contact radius at the
    top of each --v-max plan of tests/data/plan_radius_fe.csv (to 2000-9990 P_Y): the "coarse" level's 10 elements
    across it (9.3-9.9; estimated_contact_radius's mesh gives 2.5-9.1 there, 4.2-4.5 at 2000 P_Y)
    and a refined zone 1.0-1.2x as wide. A small-strain plan keeps estimated_contact_radius's mesh."""
    import csv
    from pathlib import Path

    root = Path(__file__).resolve().parent.parent
    tops = {}
    for row in csv.DictReader(line for line in (root / "tests" / "data" / "plan_radius_fe.csv").open()
                              if not line.startswith("#")):
        key = (float(row["E_over_sigma_y"]), float(row["nu"]), row["kinematics"])
        if row["mesh"] == "graded-6" and float(row["P_over_P_Y"]) > tops.get(key, (0.0,))[0]:
            tops[key] = (float(row["P_over_P_Y"]), float(row["a_over_R"]) * BRASS_R)
    assert len(tops) == 15
    for (ratio, nu, kinematics), (top, fe) in tops.items():
        material = Material(ratio * 250e6, nu, 250e6, 8500.0)
        pair = ContactPair.sphere_flat(material, BRASS_R)
        if kinematics == "finite-strain":
            spec = recipe.calibration_spec(material, BRASS_R, peaks=(top * pair.P_Y,), level="coarse",
                                           kinematics=kinematics)
            assert 9.2 < fe / spec.mesh.contact_size < 10.6, (ratio, nu, fe / spec.mesh.contact_size)
            assert 1.0 < spec.mesh.refined_radius / fe < 1.2, (ratio, nu, spec.mesh.refined_radius / fe)
        else:                           # within the small strain's reach
            spec = recipe.calibration_spec(material, BRASS_R, peaks=(min(top, 100.0) * pair.P_Y,), level="coarse",
                                           kinematics=kinematics)
            a_max = recipe.estimated_contact_radius(pair, min(top, 100.0) * pair.P_Y)
            assert spec.mesh == recipe.mesh_for(BRASS_R, a_max, level="coarse")


@pytest.mark.parametrize("material, contact_size", [(BRASS, 1e-4), (BRASS, 5e-5), (BRASS, None),
                                                    (Material(25e9, 0.34, 250e6, 8500.0), 1e-4)],
                         ids=["brass 1e-4 m", "brass 5e-5 m", "brass graded", "E 25 GPa 1e-4 m"])
def test_a_finite_strain_window_s_lowest_path_spans_the_threshold_s_elements(material, contact_size):
    """On a finite-strain --v-max plan at 3 m/s (mesh sized by recipe.fe_contact_radius) the FE's contact at the
    lowest path spans at least CONTACT_ELEMENTS_AT_LOWEST elements by fe_contact_radius (and
    CONTACT_ELEMENTS_NEAR_YIELD below COARSE_LOWEST_OVER_P_Y P_Y): brass on 1e-4 m elements starts at 270 P_Y
    (3.0 elements), where estimated_contact_radius would start it at 188 P_Y (2.5). A small-strain mesh of the
    same element keeps estimated_contact_radius's lowest path."""
    from calib.commands.calibrate import v_max_mesh

    needed, _, _ = impact_window.check_reach(material, BRASS_R, 3.0, "finite-strain")
    spec = impact_window.impact_spec(material, BRASS_R, needed, "finite-strain", **v_max_mesh(contact_size))
    pair, low, size = spec.pair, spec.plan.peaks[0], spec.mesh.contact_size
    assert recipe.fe_contact_radius(pair, low) / size >= impact_window.CONTACT_ELEMENTS_AT_LOWEST * (1 - 1e-6)
    if low < impact_window.COARSE_LOWEST_OVER_P_Y * pair.P_Y:
        assert recipe.fe_contact_radius(pair, low) / size >= impact_window.CONTACT_ELEMENTS_NEAR_YIELD * (1 - 1e-6)
    if contact_size == 1e-4 and material is BRASS:
        assert low / pair.P_Y == pytest.approx(270.1, abs=0.1)
        by_estimate = impact_window.lowest_peak(pair, size)
        assert by_estimate / pair.P_Y == pytest.approx(187.8, abs=0.1)
        assert recipe.fe_contact_radius(pair, by_estimate) / size < 2.6
    if contact_size is not None:            # small strain: the estimate's lowest path, as before
        top = min(spec.plan.peaks[-1], 0.9 * recipe.fe_reach(pair, "small-strain"))
        small = impact_window.window_spec(material, BRASS_R, top, contact_size=contact_size)
        assert small.plan.peaks[0] == impact_window.lowest_peak(pair, contact_size)

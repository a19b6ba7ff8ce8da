"""The vz master table's hardening sheet (calib.fit.vz_hardening) and ``nfdcal material --hardening-modulus``.

The hardened laws are checked against FE load-unload paths of hardening spheres the sheet was not built on
(the scenes' [[check]] runs, other nu, E/sigma_Y and H/E: the finite-strain checks to 1e4 P_Y, the small-strain
ones below the join), recomputed here from their stored records; the sheet is the join of its two scenes' node
records; a vanishing hardening is the master table's law; the command answers, writes a parameter file stating
the flow curve, and refuses what the sheet does not hold in one line."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from calib.fit import vz_hardening, vz_hardening_build, vz_master_build, vz_master_join, vz_master_scene
from calib.fit.master_table import read_rows
from calib.fit.vz_master_table import VZMasterTable
from nfdmodel import Material

ROOT = Path(__file__).resolve().parents[1]
FINITE_SCENE = "vz_master_reach_hardening"       # the shipped sheet's scene, joined with vz_hardening.SCENE


@pytest.fixture(scope="module")
def joined():
    """The finite-strain scene's records and its join with the small-strain sheet's (vz_master_join.joined_table)."""
    scene = vz_master_scene.load_scene(FINITE_SCENE)
    rows = vz_master_join.scene_records(scene, ROOT / "results" / "tables" / FINITE_SCENE)
    return rows, vz_master_join.joined_table(scene, rows, ROOT / "results" / "tables" / vz_hardening.SCENE)


@pytest.fixture(scope="module")
def stored(joined):
    """The sheet's node records and the FE checks it answers for: the finite-strain checks and the small-strain
    checks' paths below the join."""
    rows, join = joined
    return rows + join["check_rows"]


@pytest.fixture(scope="module")
def master():
    return VZMasterTable.load()


@pytest.fixture(scope="module")
def sheet():
    return vz_hardening.HardeningSheet.load()


def test_the_shipped_sheet_is_the_join_of_its_node_records(joined):
    rebuilt = joined[1]["rows"]
    shipped = read_rows(vz_hardening.DEFAULT_SHEET)
    assert len(rebuilt) == len(shipped)
    for new, old in zip(rebuilt, shipped):
        for key, value in new.items():
            if isinstance(value, float) and np.isfinite(value):
                assert old[key] == pytest.approx(value, rel=1e-9, abs=1e-12), key
            else:
                assert not isinstance(old[key], float) or not np.isfinite(old[key]), key


def test_hardened_laws_meet_the_fe_of_spheres_off_the_sheet(stored, master, sheet):
    """Inside each window: e within 2 %, force within 5 % of P_max (the master table's targets); the vz-unload
    law's dent within 0.5 % of alpha_max or 3 %. The perfectly plastic law on the same paths misses by more:
    the hardening is what the sheet adds."""
    linear = vz_hardening_build.check_rows([r for r in stored if not r.get("power_law")], master, sheet)
    measured = vz_hardening_build.summary(linear)
    assert measured["checks"] == 11 and measured["paths"] >= 60
    assert measured["vz-table"]["e_error"] <= 0.02
    assert measured["vz-table"]["force_error"] <= 0.05
    assert measured["vz-unload"]["e_error"] <= 0.02
    assert measured["vz-unload"]["unloading_error"] <= 0.05
    assert measured["perfectly plastic"]["e_error"] > 2 * measured["vz-table"]["e_error"]
    shipped = json.loads(vz_hardening.DEFAULT_SHEET.with_suffix(".json").read_text(encoding="utf-8"))
    stated = shipped["vz_hardening_table"]["accuracy_details"]
    assert stated["vz-table"]["e_error"] == pytest.approx(measured["vz-table"]["e_error"], rel=1e-6)


# four finite-strain power-law checks held out of the choice of the representative strain's factor: they were run
# after c was put to the test (c 0.15, the best on the other checks, against Tabor's 0.2)
HELD_OUT = ("nu0.34_E1500sy_swift4_0.4_finite", "nu0.29_E600sy_swift2.5_0.25_finite",
            "nu0.33_E350sy_ludwik1_0.5_finite", "nu0.34_E2500sy_ludwik5_0.5_finite")


def test_power_law_flow_curves_read_through_their_secant_modulus_against_their_fe(stored, master, sheet):
    """Swift and Ludwik spheres (ten: three in small and seven in finite strain), each read as the linear hardening
    of its secant modulus to 0.2 a/R: the 2 % / 5 % targets met on all 60 paths (measured e within 1.87 %, at the
    steep Ludwik sphere's (K 3 sigma_Y, n 0.5) top path, 4135 P_Y; force within 4.94 % of P_max). On the four checks
    held out of the factor's choice (25 paths to 4256 P_Y): e within 1.47 %, force 3.69 % (with the factor 0.15:
    1.98 % and 3.52 %, so 0.2 stays). The perfectly plastic law misses by 11 % and 19 %."""
    power = vz_hardening_build.check_rows([r for r in stored if r.get("power_law")], master, sheet)
    measured = vz_hardening_build.summary(power)
    assert measured["checks"] == 10 and measured["paths"] >= 55
    assert measured["vz-table"]["e_error"] <= 0.02 and measured["vz-table"]["force_error"] <= 0.05
    inside = [r for r in power["vz-table"] if r["inside"]]
    held_out = [r for r in inside if r["name"] in HELD_OUT]
    assert len({r["name"] for r in held_out}) == 4 and len(held_out) >= 20
    assert max(abs(r["e_error"]) for r in held_out) <= 0.02 and max(r["force_error"] for r in held_out) <= 0.05
    assert measured["perfectly plastic"]["e_error"] > 3 * measured["vz-table"]["e_error"]


def test_a_vanishing_hardening_is_the_master_law(master, sheet):
    material = Material(210e9, 0.29, 700e6, 7800.0)
    plain = master.law(material, 2e-3)
    hardened = vz_hardening.HardenedMasterTable(master, sheet, 1e-9).law(material, 2e-3)
    x = np.geomspace(1.0, hardened.window.P_max_over_P_Y, 40)
    f0, g0 = plain.tables(x)
    f1, g1 = hardened.tables(x)
    assert np.allclose(f1, f0, rtol=0, atol=2e-3 * f0.max()) and np.allclose(g1, g0, rtol=2e-3)


@pytest.mark.parametrize("nu", [0.2, 0.3, 0.49])
@pytest.mark.parametrize("E_over_sigma_y", [100.0, 300.0, 1000.0, 5000.0])
def test_the_hardened_law_rises_in_e_as_the_fe_at_the_sheet_s_nodes(stored, master, sheet, E_over_sigma_y, nu):
    """At the top path of each finite-strain node inside the law's window (339-1e4 P_Y; nu 0.2, 0.3, 0.49; H/E
    0.005-0.2) the FE's e rises with H/E by up to 0.31 over the perfectly plastic sphere's; the law's e rises by the
    same within 0.01 (measured 0.0046 at most, at nu 0.3, E/sigma_Y 100, H/E 0.05, 339 P_Y). The law's e itself is
    within 2 % of the node's FE (measured 0.93 %, at nu 0.49, E/sigma_Y 5000, H/E 0.005; the perfectly plastic
    master law is 1.32 % from its own node's FE at nu 0.49, E/sigma_Y 1000)."""
    from calib.fit.path_check import law_against_path
    from calib.fit.vz_master_check import fe_paths

    material = Material(E_over_sigma_y * 100e6, nu, 100e6, 2700.0)
    node = {r.get("H_over_E", 0.0): r for r in stored
            if r.get("kind") == "node" and r["E_over_sigma_y"] == E_over_sigma_y and r["nu"] == nu}
    plain_law = master.law(material, 0.1)
    top_load = plain_law.window.P_max_over_P_Y * plain_law.pair.P_Y * (1 + 1e-6)
    plain_top = [p for p in fe_paths(node[0.0]) if p["P_max"] <= top_load][-1]
    e_plain = law_against_path("vz-table", plain_law, plain_top)["e_law"]
    for H_over_E in (0.005, 0.02, 0.05, 0.1, 0.2):
        top = next(p for p in fe_paths(node[H_over_E]) if p["P_max"] == pytest.approx(plain_top["P_max"], rel=1e-6))
        compared = law_against_path("vz-table", vz_hardening.HardenedMasterTable(master, sheet, H_over_E)
                                    .law(material, 0.1), top)
        assert abs(compared["e_error"]) <= 0.02
        assert compared["e_law"] - e_plain == pytest.approx(top["e"] - plain_top["e"], abs=0.01)


def run_cli(argv, capsys):
    from calib.cli import main

    code = main(argv)
    out = capsys.readouterr()
    return code, out.out, out.err.strip()


STEEL = ["--E", "210e9", "--nu", "0.29", "--sigma-y", "700e6", "--rho", "7800", "--R", "2e-3"]


def test_material_answers_a_hardening_sphere_and_states_it(tmp_path, capsys):
    path = tmp_path / "law.json"
    code, out, err = run_cli(["material", *STEEL, "--hardening-modulus", "2.1e9", "--v-max", "1",
                              "--params-out", str(path), "--json"], capsys)
    assert code == 0, err
    summary = json.loads(out)
    assert summary["H_over_E"] == pytest.approx(0.01)
    assert summary["hardening"] == {"flow_curve": "linear", "sigma_y": 700e6, "hardening_modulus": 2.1e9}
    record = json.loads(path.read_text(encoding="utf-8"))
    assert record["hardening"]["hardening_modulus"] == 2.1e9 and "hardening" in record["fit"]["accuracy"]
    code, out, err = run_cli(["material", *STEEL, "--v-max", "1", "--json"], capsys)
    assert json.loads(out)["P_max_of_v_max"] > 0 and summary["P_max_of_v_max"] > json.loads(out)["P_max_of_v_max"]
    code, out, err = run_cli(["collide", "--params", str(path), "--v-in", "0.5", "--json"], capsys)
    assert code == 0, err


@pytest.mark.parametrize("flags, needle", [
    (["--hardening-modulus", "2.1e9"], "--hardening-modulus needs --v-max"),
    (["--hardening-modulus", "6.3e10", "--v-max", "1"], "--hardening-modulus out of range: H/E = 0.3"),
    (["--hardening-modulus", "2.1e9", "--v-max", "1", "--counter-E", "210e9", "--counter-nu", "0.3"],
     "--hardening-modulus out of range with --counter-E"),
    (["--hardening-modulus", "2.1e9", "--v-max", "1", "--rate-law", "cowper-symonds", "--cs-D", "40",
      "--cs-q", "5"], "--hardening-modulus out of range with --rate-law"),
])
def test_material_refuses_what_the_sheet_does_not_hold_in_one_line(flags, needle, capsys):
    code, out, err = run_cli(["material", *STEEL, *flags], capsys)
    assert code == 2 and "\n" not in err and needle in err, err


def test_material_answers_a_measured_flow_curve_and_refuses_one_beyond_the_sheet(tmp_path, capsys):
    """--flow-curve CSV: the law of the curve read through its secant modulus (its parameter file states the curve,
    collide runs it, and it lies between the perfectly plastic law and the law of the curve's initial slope); a
    curve whose secant modulus in the window is beyond the sheet's H/E is refused in one line naming calibrate."""
    curve = tmp_path / "curve.csv"
    curve.write_text("plastic_strain,stress\n0,700e6\n0.01,730e6\n0.05,780e6\n0.2,850e6\n", encoding="utf-8")
    path = tmp_path / "law.json"
    code, out, err = run_cli(["material", *STEEL, "--flow-curve", str(curve), "--v-max", "3", "--params-out",
                              str(path), "--json"], capsys)
    assert code == 0, err
    summary = json.loads(out)
    assert summary["hardening"]["flow_curve"] == "table" and "secant modulus" in summary["hardening_read_as"]
    record = json.loads(path.read_text(encoding="utf-8"))
    assert record["hardening"]["stress"] == [700e6, 730e6, 780e6, 850e6]
    code, out, err = run_cli(["collide", "--params", str(path), "--v-in", "2", "--json"], capsys)
    assert code == 0, err
    P_max = {}
    for flags in ([], ["--hardening-modulus", "3e9"]):      # 3e9: the curve's initial slope
        code, out, err = run_cli(["material", *STEEL, "--v-max", "3", *flags, "--json"], capsys)
        P_max[bool(flags)] = json.loads(out)["P_max_of_v_max"]
    assert P_max[False] < summary["P_max_of_v_max"] < P_max[True]
    curve.write_text("plastic_strain,stress\n0,700e6\n0.001,900e6\n", encoding="utf-8")
    code, out, err = run_cli(["material", *STEEL, "--flow-curve", str(curve), "--v-max", "1"], capsys)
    assert code == 2 and "\n" not in err and "--flow-curve out of range" in err, err
    assert "nfdcal calibrate --flow-curve" in err


def test_a_linear_curve_read_through_its_secant_modulus_is_its_h(master, sheet):
    """The secant modulus of a linear flow curve is H at every strain (to round-off), and its tables through the flow
    curve's path (the shares at the sheet's H/E nodes, PCHIP in H/E at each load) equal the H/E path's (PCHIP in
    H/E, then in E/sigma_Y) to the two interpolation orders' difference: 0.023 % in f, 0.025 % in g (measured)."""
    from calib.fe.flow_curve import LinearHardening

    curve = LinearHardening(100e6, 0.02 * 250 * 100e6)
    assert np.allclose(vz_hardening.effective_hardening(curve, 250 * 100e6, np.geomspace(1e-4, 0.2, 9)), 0.02,
                       rtol=1e-12, atol=0)
    for nu, ratio, H_over_E in [(0.3, 700.0, 0.012), (0.42, 250.0, 0.03), (0.25, 2000.0, 0.035)]:
        plain = vz_hardening.hardened_tables(master, sheet, nu, ratio, H_over_E)
        read = vz_hardening.hardened_tables(master, sheet, nu, ratio, LinearHardening(1e8, H_over_E * ratio * 1e8))
        assert np.array_equal(plain["x"], read["x"])
        for key, tolerance in (("f", 2e-3), ("g", 1e-3)):
            assert np.all(np.abs(read[key] - plain[key]) <= tolerance * np.maximum(np.abs(plain[key]), 1e-3)), key


def drops_file(row: dict, table, tmp_path) -> tuple[Path, dict]:
    """The FE's noise-free drop tests (v_in, e, P_max) of a stored check inside the law's window, as a CSV."""
    from calib.fit.vz_master_check import fe_datasets

    sets = fe_datasets(row, table)
    path = tmp_path / f"{row['name']}.csv"
    drops = sets["drops"]
    path.write_text("v_in,e,P_max\n" + "".join(f"{float(v)!r},{float(e)!r},{float(p)!r}\n" for v, e, p in
                                                  zip(drops["v_in"], drops["e"], drops["P_max"])), encoding="utf-8")
    return path, sets


@pytest.mark.parametrize("name", ["nu0.23_E400sy_H0.012E_finite", "nu0.25_E2000sy_H0.035E_finite",
                                  "nu0.42_E250sy_H0.03E_finite"])
def test_fit_data_recovers_sigma_y_of_a_hardening_sphere_from_its_fe_drops(stored, master, sheet, name, tmp_path,
                                                                            capsys):
    """fit-data --hardening-modulus H on the FE's drop tests of a hardening sphere off the sheet's nodes (finite
    strain, 13-50 P_Y to the window's top, 2039-4135 P_Y): sigma_Y within 1.5 % (measured 0.07-0.51 %), its 95 %
    interval covering the truth; fitted as perfectly plastic the same drops give sigma_Y 9.8-23 % high, outside
    that interval."""
    row = next(r for r in stored if r.get("name") == name and r.get("kind") == "check")
    path, sets = drops_file(row, vz_hardening.HardenedMasterTable(master, sheet, row["H_over_E"]), tmp_path)
    specimen = sets["specimen"]
    flags = ["fit-data", "--impacts", str(path), "--E", f"{specimen.E!r}", "--nu", f"{specimen.nu!r}",
             "--R", f"{specimen.R!r}", "--rho", f"{specimen.rho!r}", "--json"]
    H = row["H_over_E"] * specimen.E
    code, out, err = run_cli([*flags, "--hardening-modulus", f"{H!r}"], capsys)
    assert code == 0, err
    hardened = json.loads(out)
    assert hardened["sigma_y"] == pytest.approx(sets["sigma_y"], rel=0.015)
    low, high = hardened["sigma_y_interval95"]
    assert low <= sets["sigma_y"] <= high
    assert hardened["hardening"]["hardening_modulus"] == pytest.approx(H)
    code, out, err = run_cli(flags, capsys)
    assert code == 0, err
    plain = json.loads(out)
    assert plain["sigma_y"] > high and plain["sigma_y"] / sets["sigma_y"] - 1 > 0.05


@pytest.mark.parametrize("flags, needle", [
    (["--hardening-modulus", "1e9", "--law", "vz"], "--hardening-modulus out of range with --law vz"),
    (["--hardening-modulus", "1e9", "--counter-E", "210e9", "--counter-nu", "0.3"],
     "--hardening-modulus out of range with --counter-E"),
    (["--hardening-modulus", "1e12"], "--hardening-modulus out of range"),
])
def test_fit_data_refuses_what_the_sheet_does_not_hold_in_one_line(flags, needle, tmp_path, capsys):
    path = tmp_path / "drops.csv"
    path.write_text("v_in,e\n0.5,0.8\n1.0,0.75\n", encoding="utf-8")
    code, out, err = run_cli(["fit-data", "--impacts", str(path), *STEEL, *flags], capsys)
    assert code == 2 and "\n" not in err and needle in err, err


@pytest.mark.parametrize("flags, needle", [
    (["--hardening-modulus", "1e9"], "--hardening-modulus out of range with --fit-hardening"),
    (["--rate-law", "cowper-symonds", "--cs-q", "5"], "--rate-law out of range with --fit-hardening"),
    (["--counter-E", "210e9", "--counter-nu", "0.3"], "--counter-E out of range with --fit-hardening"),
    (["--law", "vz"], "--fit-hardening fits the hardened vz-table law"),
    (["--flow-curve", "curve.csv"], "nfdcal fit-data takes linear hardening only"),
])
def test_fit_hardening_refuses_what_it_does_not_fit_in_one_line(flags, needle, tmp_path, capsys):
    path = tmp_path / "drops.csv"
    path.write_text("v_in,e\n0.5,0.8\n1.0,0.75\n", encoding="utf-8")
    code, out, err = run_cli(["fit-data", "--impacts", str(path), *STEEL, "--fit-hardening", *flags], capsys)
    assert code == 2 and "\n" not in err and needle in err, err


def test_drop_tests_determine_H_over_the_finite_reach_only(stored, master, sheet):
    """Identifiability (Bates & Watts 1988, sec. 2.3): at the drop speeds of each hardening check inside the law's
    window, with 1 % scatter in e and P_max, Cov(ln sigma_Y, ln H) = s^2 (J^T J)^-1 from the hardened law's
    sensitivities (J by one-sided steps that keep E/sigma_Y on the check's side of a column). Drops spanning the
    finite strain's reach (13-50 P_Y to 2039-4135 P_Y) give sigma_Y to 1.5-2.2 % and H to 8.9-15 % (measured; 15 %
    at the lowest hardening, H/E 0.012); the small-strain checks' drops below the join (2 P_Y to 11.5-250 P_Y) give
    sigma_Y to 2.0-5.3 % and H only to 38-2480 %: the data barely change along ln H there."""
    import math

    from calib.fit.vz_master_check import fe_datasets
    from nfdmodel import collision_reference

    for row in (r for r in stored if r.get("kind") == "check" and "H_over_E" in r and r["H_over_E"] <= 0.05):
        H_over_E = row["H_over_E"]
        sets = fe_datasets(row, vz_hardening.HardenedMasterTable(master, sheet, H_over_E))
        specimen, sigma_y, v_in = sets["specimen"], sets["sigma_y"], sets["drops"]["v_in"]

        def predicted(ln_sigma_y, ln_H):
            law = vz_hardening.HardenedMasterTable(master, sheet, math.exp(ln_H)).law(
                specimen.material(math.exp(ln_sigma_y)), specimen.R)
            ref = collision_reference("vz-table", law, v_in)
            return np.log(np.r_[ref.restitution, ref.P_max])

        step = 1e-3
        at = (math.log(sigma_y), math.log(H_over_E))
        base = predicted(*at)
        J = np.c_[(base - predicted(at[0] - step, at[1])) / step, (predicted(at[0], at[1] + step) - base) / step]
        se = np.sqrt(np.diag(np.linalg.inv(J.T @ J))) * 0.01
        if row["name"].endswith("_finite"):
            assert se[0] < 0.03 and se[1] < 0.2, (row["name"], se)
        else:
            assert se[0] < 0.06 and se[1] > 0.3, (row["name"], se)


def fitted_with_hardening(stored, master, sheet, name: str, kind: str):
    """hardening_fit.fit on one check's noise-free FE data of ``kind``; the truth (sigma_Y, H)."""
    from calib.fit.measured import hardening_fit
    from calib.fit.vz_master_check import fe_datasets, measurements

    row = next(r for r in stored if r.get("name") == name and r.get("kind") == "check")
    sets = fe_datasets(row, vz_hardening.HardenedMasterTable(master, sheet, row["H_over_E"]))
    values = {**sets["drops"], "approach": sets["force"][0], "force": sets["force"][1]}
    result = hardening_fit.fit(measurements(kind, values, name), sets["specimen"], master, sheet)
    return result, {"sigma_y": sets["sigma_y"], "hardening_modulus": row["H_over_E"] * sets["specimen"].E}


@pytest.mark.parametrize("name", ["nu0.23_E400sy_H0.012E_finite", "nu0.25_E2000sy_H0.035E_finite",
                                  "nu0.42_E250sy_H0.03E_finite"])
def test_fit_hardening_recovers_sigma_y_and_H_from_finite_strain_drops(stored, master, sheet, name, tmp_path, capsys):
    """fit-data --fit-hardening on a finite-strain check's FE drops (e, P_max; off every node of the sheet in nu,
    E/sigma_Y and H/E): sigma_Y within 1.5 % and H within 7 % (measured 0.05-0.47 % and 0.65-6.5 %; targets 3 % and
    10 %), the data determine both and each 95 % interval, with the measured model-form terms, covers the truth;
    the parameter file carries the fitted flow curve and runs."""
    row = next(r for r in stored if r.get("name") == name and r.get("kind") == "check")
    path, sets = drops_file(row, vz_hardening.HardenedMasterTable(master, sheet, row["H_over_E"]), tmp_path)
    specimen = sets["specimen"]
    truth = {"sigma_y": sets["sigma_y"], "hardening_modulus": row["H_over_E"] * specimen.E}
    params = tmp_path / "law.json"
    code, out, err = run_cli(["fit-data", "--impacts", str(path), "--E", f"{specimen.E!r}", "--nu", f"{specimen.nu!r}",
                              "--R", f"{specimen.R!r}", "--rho", f"{specimen.rho!r}", "--fit-hardening", "--json",
                              "--params-out", str(params)], capsys)
    assert code == 0, err
    fitted = json.loads(out)
    assert fitted["identifiability"]["hardening_determined"]
    for key, bound in (("sigma_y", 0.015), ("hardening_modulus", 0.07)):
        assert fitted[key] == pytest.approx(truth[key], rel=bound), key
        low, high = fitted["interval95"][key]
        assert low <= truth[key] <= high, key
    record = json.loads(params.read_text(encoding="utf-8"))
    assert record["hardening"]["hardening_modulus"] == pytest.approx(fitted["hardening_modulus"])
    code, out, err = run_cli(["collide", "--params", str(params), "--v-in", f"{float(sets['drops']['v_in'][0])!r}",
                              "--json"], capsys)
    assert code == 0, err


def test_fit_hardening_refuses_small_strain_drops_naming_the_flow_stress_they_determine(stored, master, sheet,
                                                                                        tmp_path, capsys):
    """Drops below the join (nu 0.4, E/sigma_Y 150, H/E 0.003: 2-11.5 P_Y) do not separate sigma_Y and H: fit-data
    --fit-hardening refuses in one line (exit 2), naming the flow stress at the plastic strain they determine."""
    row = next(r for r in stored if r.get("name") == "nu0.4_E150sy_H0.003E" and r.get("kind") == "check")
    path, sets = drops_file(row, vz_hardening.HardenedMasterTable(master, sheet, row["H_over_E"]), tmp_path)
    specimen = sets["specimen"]
    code, out, err = run_cli(["fit-data", "--impacts", str(path), "--E", f"{specimen.E!r}", "--nu", f"{specimen.nu!r}",
                              "--R", f"{specimen.R!r}", "--rho", f"{specimen.rho!r}", "--fit-hardening"], capsys)
    assert code == 2 and "\n" not in err, err
    assert "do not determine sigma_Y and H apart" in err and "flow stress at plastic strain" in err


def test_small_strain_drops_leave_H_free_and_name_the_flow_stress_they_determine(stored, master, sheet):
    """On the small-strain check nu 0.4, E/sigma_Y 150, H/E 0.003 (drops 2-11.5 P_Y) the fit leaves H free
    (statistical relative standard error 54 %, H 9.6x the truth) and names what the data determine: the flow stress
    at a plastic strain of a few 1e-3 (0.0040), within 2 % of the true sigma_Y + H eps_* (measured 0.65 %)."""
    from calib.fit.measured import hardening_fit

    result, truth = fitted_with_hardening(stored, master, sheet, "nu0.4_E150sy_H0.003E", "drops e")
    assert not result.identifiability["hardening_determined"]
    flow = result.identifiability["determined_combination"]
    strain = flow["plastic_strain"]
    assert 1e-4 < strain < 0.05
    assert flow["value"] == pytest.approx(truth["sigma_y"] + truth["hardening_modulus"] * strain, rel=0.02)
    why = hardening_fit.refusal(result)
    assert "do not determine sigma_Y and H apart" in why and "flow stress at plastic strain" in why
    assert "\n" not in why


@pytest.mark.parametrize("sheet_scene, grid_scene", [("vz_master_hardening", "vz_master_grid"),
                                                     ("vz_master_reach_hardening", "vz_master_reach")])
def test_a_sheet_s_perfectly_plastic_nodes_are_its_grid_s_tasks(sheet_scene, grid_scene):
    """H/E 0 of a hardening sheet is its grid's own node (the same key: the same FE, run once), and every hardening
    task is keyed apart from every grid task."""
    from calib.fit import vz_master_build

    grid = {t["key"] for t in vz_master_build.tasks_for(vz_master_scene.load_scene(grid_scene))}
    tasks = vz_master_build.tasks_for(vz_master_scene.load_scene(sheet_scene))
    plain = [t for t in tasks if t["kind"] == "node" and not t.get("H_over_E")]
    hardening = [t for t in tasks if t.get("H_over_E") or t.get("power_law")]
    assert len(plain) == 18 and all(t["key"] in grid for t in plain)
    checks = [t for t in tasks if t["kind"] == "check"]
    assert len(hardening) == 90 + len(checks) and not any(t["key"] in grid for t in hardening)


def test_calibrate_v_max_sizes_a_hardening_sphere_s_window_by_the_sheet(tmp_path, capsys):
    """calibrate --v-max --hardening-modulus: the window estimated with the hardening sheet's law covers the impact
    in one FE round; the FE-calibrated hardening law and the sheet's law (other FE runs, another material's nodes)
    agree in e at v_max within 1 % (measured 0.19 %, coarse mesh)."""
    from calib.fe.flow_curve import LinearHardening
    from calib.fit import impact_window
    from nfdmodel import collide, load_parameters

    code, out, err = run_cli(["calibrate", "--v-max", "0.05", "--contact-size", "3e-4", "--hardening-modulus", "3.5e9",
                              "--no-plots", "--json", "--quiet", "--out", str(tmp_path)], capsys)
    assert code == 0, err
    summary = json.loads(out)
    rounds = summary["v_max"]["rounds"]
    assert len(rounds) == 1 and rounds[0]["covered"]
    record = json.loads((tmp_path / "parameters.json").read_text(encoding="utf-8"))
    assert record["hardening"]["hardening_modulus"] == 3.5e9
    material = Material(70e9, 0.3, 100e6, 2699.0)
    sheet_law, source = impact_window.estimating_constants(material, 0.1, None, LinearHardening(100e6, 3.5e9))
    assert source == "the vz master table's hardening sheet"
    calibrated = load_parameters(tmp_path / "parameters.json")
    e_fe = collide("vz-table", calibrated, [0.05]).e_velocity[0]
    e_sheet = collide("vz-table", sheet_law, [0.05]).e_velocity[0]
    assert e_fe == pytest.approx(e_sheet, rel=0.01)


def test_the_sheet_s_laws_are_admissible_to_its_top_and_near_yield_keep_the_plain_plastic_radius(master, sheet):
    """Scanned over 7 nu (0.2-0.49) x 12 E/sigma_Y (100-5000) x 8 H/E (0.001-0.2), and 6 Swift and Ludwik curves
    over the same materials: the sheet's vz-table and vz-unload laws are admissible everywhere (1344 linear laws;
    938 of 1008 of the curves, the other 70 beyond the sheet's top and refused as such). Near P_Y the FE's plastic
    radius f is 1e-5-1e-2 and the ratio of two such values noise (183 at nu 0.2, E/sigma_Y 100, H/E 0.2, 1.33
    P_Y): below f = 0.02 f and g take no hardening factor (vz_hardening.FACTOR_FLOOR). Taken, PCHIP in nu put f
    0.31 at nu 0.25 there, flat to 13 P_Y, and two vz-unload laws created energy near 6 P_Y. Sampled here at the
    corners."""
    for H_over_E in (0.005, 0.2):
        hardened = vz_hardening.HardenedMasterTable(master, sheet, H_over_E)
        for nu in (0.2, 0.25, 0.44, 0.49):
            for E_over_sigma_y in (100.0, 5000.0):
                material = Material(E_over_sigma_y * 1e8, nu, 1e8, 7800.0)
                hardened.law(material, 1e-3)
                hardened.unload_law(material, 1e-3)
                plain = master.tables(nu, E_over_sigma_y)
                tables = vz_hardening.hardened_tables(master, sheet, nu, E_over_sigma_y, H_over_E)
                near = (tables["x"] > 1.0) & (tables["x"] < 2.0)
                assert np.all(tables["f"][near] <= np.interp(tables["x"][near], plain["x"], plain["f"]) + 1e-12)


def test_a_hardening_sphere_below_the_sheet_s_columns_is_refused_naming_the_sheet(capsys):
    """The vz master table reaches E/sigma_Y 30 (polymers), its hardening sheet 100: a hardening sphere at E/sigma_Y
    43 is refused in one line naming the sheet and its range (the perfectly plastic one answers)."""
    from calib.cli import main

    sphere = ["--E", "3e9", "--nu", "0.38", "--sigma-y", "70e6", "--rho", "1190", "--R", "0.002", "--v-max", "1"]
    assert main(["material", *sphere, "--quiet"]) == 0
    capsys.readouterr()
    assert main(["material", *sphere, "--hardening-modulus", "1e8", "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "outside the vz master table's hardening sheet: need E/sigma_Y in [100, 5000]" in err

